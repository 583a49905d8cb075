#include "axonguide/placement.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "axonguide/core/random.hpp"
#include "axonguide/error.hpp"
#include "axonguide/sampler_nd.hpp"

namespace axg {

using core::Rng;
using core::Stream;
using core::Vec3;

double packing_fraction(const Scene::Neurons& n) {
  if (!n.populations.empty()) {  // the densest population's volume fraction
    double phi = 0.0;
    for (const Population& p : n.populations) {
      const double r = n.soma_radius / p.radius;
      phi = std::max(phi, static_cast<double>(p.count) * r * r * r);
    }
    return phi;
  }
  const double count = static_cast<double>(n.count);
  const double r = n.soma_radius, R = n.radius;
  switch (n.shape) {
    case RegionShape::kBall: return count * (r * r * r) / (R * R * R);
    case RegionShape::kBox: return count * (4.0 / 3.0 * M_PI * r * r * r) / (8.0 * R * R * R);
    case RegionShape::kSphere: return count * (r * r) / (4.0 * R * R);
  }
  return 0.0;
}

Vec3 soma_draw(const Scene& scene, std::uint64_t id, std::uint32_t attempt) {
  Rng rng(scene.seed, Stream::kPlacement, id, attempt);
  const auto& nn = scene.neurons;
  if (nn.populations.empty()) return sample_region_point(nn.shape, nn.radius, nn.sampler, rng);
  const Population& p = nn.populations[nn.population_of(id)];
  return p.center + sample_region_point(RegionShape::kBall, p.radius, nn.sampler, rng);
}

Vec3 heading_draw(const Scene& scene, std::uint64_t id) {
  Rng rng(scene.seed, Stream::kAxonDirection, id, 0);
  return sample_direction3(scene.neurons.sampler, rng);
}

namespace {

// Hashed cell lists for the sequential overlap pass: cells of edge 2 r_s, so every
// soma that can overlap a new one lies in the 27 cells around it.
class OverlapIndex {
 public:
  // Room for the n somas with ids [base, base + n); the block index is cleared and rebased
  // for every block.
  OverlapIndex(std::size_t n, double cell) : cell_(cell), next_(n, kEmpty) {
    std::size_t buckets = 1;
    while (buckets < 2 * n) buckets <<= 1;
    head_.assign(buckets, kEmpty);
    mask_ = buckets - 1;
  }
  void clear(std::uint32_t base) {
    std::fill(head_.begin(), head_.end(), kEmpty);
    base_ = base;
  }

  bool overlaps(const std::vector<Vec3>& pos, Vec3 p, double min_dist2) const {
    const std::int64_t cx = coord(p.x), cy = coord(p.y), cz = coord(p.z);
    for (std::int64_t dz = -1; dz <= 1; ++dz)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dx = -1; dx <= 1; ++dx)
          for (std::uint32_t j = head_[bucket(cx + dx, cy + dy, cz + dz)]; j != kEmpty; j = next_[j - base_])
            if (core::norm2(pos[j] - p) < min_dist2) return true;
    return false;
  }

  void insert(std::uint32_t id, Vec3 p) {
    std::size_t b = bucket(coord(p.x), coord(p.y), coord(p.z));
    next_[id - base_] = head_[b];
    head_[b] = id;
  }

 private:
  static constexpr std::uint32_t kEmpty = 0xffffffffu;
  std::int64_t coord(double v) const { return static_cast<std::int64_t>(std::floor(v / cell_)); }
  std::size_t bucket(std::int64_t x, std::int64_t y, std::int64_t z) const {
    std::uint64_t h = static_cast<std::uint64_t>(x) * 0x9E3779B97F4A7C15ull ^
                      static_cast<std::uint64_t>(y) * 0xC2B2AE3D27D4EB4Full ^
                      static_cast<std::uint64_t>(z) * 0x165667B19E3779F9ull;
    h ^= h >> 29;
    return static_cast<std::size_t>(h) & mask_;
  }

  double cell_;
  std::uint32_t base_ = 0;
  std::size_t mask_ = 0;
  std::vector<std::uint32_t> head_, next_;
};

// Random sequential addition cannot exceed these (3D close packing; hexagonal discs).
constexpr double kMaxVolumeFraction = 0.7405;
constexpr double kMaxAreaFraction = 0.9069;

}  // namespace

Placement place_neurons(const Scene& scene) {
  const auto& nn = scene.neurons;
  const std::size_t n = static_cast<std::size_t>(nn.count);
  Placement out;
  out.soma.resize(n);
  out.heading.resize(n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    out.soma[i] = soma_draw(scene, i, 0);
    out.heading[i] = heading_draw(scene, i);
  });
  if (!nn.overlap_reject || n < 2) return out;

  const double phi = packing_fraction(nn);
  if (!nn.populations.empty() && phi > 0.38)
    throw RunError(fmt::format(
        "placement impossible: a population's packing fraction is {:.4f} (somas of radius {}); random sequential "
        "addition jams near 0.38: enlarge neurons.populations[].radius or reduce its count",
        phi, nn.soma_radius));
  const double limit = nn.shape == RegionShape::kSphere ? kMaxAreaFraction : kMaxVolumeFraction;
  const char* what = nn.shape == RegionShape::kSphere ? "area" : "volume";
  if (phi > limit)
    throw RunError(fmt::format(
        "placement impossible: packing fraction {:.4f} ({} fraction of {} somas of radius {} in a "
        "{} of radius {}) exceeds the densest packing {:.4f}; reduce neurons.count or "
        "neurons.soma_radius, enlarge neurons.region.radius, or set neurons.overlap to \"allow\"",
        phi, what, nn.count, nn.soma_radius, name_of(nn.shape), nn.radius, limit));

  // Random sequential addition in id order: attempt k of soma i is rejected when it
  // overlaps any earlier soma's final position. The pass runs in blocks of ids with the
  // same result. For a block [a, b), every soma first draws, in parallel, until an attempt
  // clears the somas before a (which are final, so each rejection there is one the
  // sequential pass makes too); then, in id order, the attempt found is checked against
  // the block's earlier somas only, and only a soma that meets one draws on, against both.
  const double min_dist = 2.0 * nn.soma_radius, min_dist2 = min_dist * min_dist;
  OverlapIndex index(n, min_dist);
  constexpr std::size_t kBlock = 4096;
  OverlapIndex local(kBlock, min_dist);
  std::vector<std::uint32_t> attempts(kBlock);
  auto fail = [&](std::size_t i) {
    throw RunError(fmt::format(
        "placement failed: neuron {} still overlaps an earlier soma after {} attempts; "
        "packing fraction {:.4f} ({} fraction of {} somas of radius {} in a {} of radius {}; "
        "random sequential addition jams near {}); reduce neurons.count or "
        "neurons.soma_radius, enlarge neurons.region.radius, raise neurons.max_attempts, or "
        "set neurons.overlap to \"allow\"",
        i, nn.max_attempts, phi, what, nn.count, nn.soma_radius, name_of(nn.shape), nn.radius,
        nn.shape == RegionShape::kSphere ? "0.547" : "0.38"));
  };
  for (std::size_t a = 0; a < n; a += kBlock) {
    const std::size_t b = std::min(n, a + kBlock);
    tbb::parallel_for(a, b, [&](std::size_t i) {
      std::uint32_t attempt = 0;
      while (attempt < nn.max_attempts && index.overlaps(out.soma, out.soma[i], min_dist2))
        if (++attempt < nn.max_attempts) out.soma[i] = soma_draw(scene, i, attempt);
      attempts[i - a] = attempt;  // max_attempts: none cleared the earlier blocks
    });
    local.clear(static_cast<std::uint32_t>(a));
    for (std::size_t i = a; i < b; ++i) {
      std::uint32_t attempt = attempts[i - a];
      if (attempt >= nn.max_attempts) fail(i);
      while (local.overlaps(out.soma, out.soma[i], min_dist2) ||
             (attempt != attempts[i - a] && index.overlaps(out.soma, out.soma[i], min_dist2))) {
        if (++attempt >= nn.max_attempts) fail(i);
        out.soma[i] = soma_draw(scene, i, attempt);
      }
      out.redraws += attempt;
      local.insert(static_cast<std::uint32_t>(i), out.soma[i]);
    }
    for (std::size_t i = a; i < b; ++i) index.insert(static_cast<std::uint32_t>(i), out.soma[i]);
  }
  return out;
}

}  // namespace axg

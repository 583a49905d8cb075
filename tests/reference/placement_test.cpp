// Placement's samplers: the points `axonguide validate samplers` tests are the points
// placement places (same calls, same bits), and a box region is filled uniformly (a
// chi-square test over cells that also rejects a slightly non-uniform control); and the
// blocked overlap pass places exactly what random sequential addition in id order places.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <fmt/format.h>
#include <gsl/gsl_cdf.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "axonguide/core/random.hpp"
#include "axonguide/support/error.hpp"
#include "axonguide/placement/overlap_index.hpp"
#include "axonguide/placement/placement.hpp"
#include "axonguide/placement/sampler_nd.hpp"
#include "axonguide/scene/scene.hpp"
#include "axonguide/validate/validate.hpp"
#include "support.hpp"

namespace axg {
namespace {

using core::bits_of;
using core::Rng;
using core::Sampler;
using core::Stream;
using core::Vec3;

constexpr Sampler kSamplers[] = {Sampler::kRejection, Sampler::kNormal, Sampler::kTrig, Sampler::kCoordinate};

::testing::AssertionResult same_bits(Vec3 a, const double* b) {
  if (bits_of(a.x) == bits_of(b[0]) && bits_of(a.y) == bits_of(b[1]) && bits_of(a.z) == bits_of(b[2]))
    return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "(" << a.x << ", " << a.y << ", " << a.z << ") != (" << b[0] << ", " << b[1]
                                       << ", " << b[2] << ")";
}

TEST(placement, ValidatedSamplersAreThePlacedOnes) {
  for (const Sampler s : kSamplers) {
    Scene scene;
    scene.seed = 90210;
    scene.neurons.sampler = s;
    scene.neurons.count = 500;
    scene.neurons.overlap_reject = false;
    for (const auto& [shape, radius, ball] : {std::tuple{RegionShape::kBall, 1.0, true}, std::tuple{RegionShape::kBall, 6.5, true},
                                              std::tuple{RegionShape::kSphere, 1.0, false}}) {
      scene.neurons.shape = shape;
      scene.neurons.radius = radius;
      const std::string what = std::string(name_of(shape)) + " radius " + std::to_string(radius) + ", sampler " +
                               std::to_string(static_cast<int>(s));
      const Placement placed = place_neurons(scene);
      for (std::uint64_t id = 0; id < scene.neurons.count; ++id) {
        double p[3];
        Rng rng(scene.seed, Stream::kPlacement, id, 0);
        validate::sampler_point(s, ball, 3, ball ? radius : 1.0, rng, p);
        if (!ball) p[0] *= radius, p[1] *= radius, p[2] *= radius;
        ASSERT_TRUE(same_bits(placed.soma[id], p)) << what << ", neuron " << id;
        // A redraw (attempt 3) goes through the same function.
        Rng again(scene.seed, Stream::kPlacement, id, 3);
        validate::sampler_point(s, ball, 3, ball ? radius : 1.0, again, p);
        if (!ball) p[0] *= radius, p[1] *= radius, p[2] *= radius;
        ASSERT_TRUE(same_bits(soma_draw(scene, id, 3), p)) << what << ", neuron " << id << ", attempt 3";
        // Headings: validate's directions.
        Rng heading(scene.seed, Stream::kAxonDirection, id, 0);
        validate::sampler_point(s, false, 3, 1.0, heading, p);
        ASSERT_TRUE(same_bits(placed.heading[id], p)) << what << ", heading " << id;
      }
    }
  }
}

// validate samplers draws d = 3 through placement's functions and other d through the
// d-dimensional ones; at d = 3 those give the same bits as well.
TEST(placement, DimensionGeneralSamplersAtThreeDimensionsAreTheThreeDimensionalOnes) {
  for (const Sampler s : kSamplers)
    for (std::uint64_t id = 0; id < 2000; ++id) {
      double p[3];
      Rng a(7, Stream::kValidation, id, 1), b(7, Stream::kValidation, id, 1);
      sample_direction(s, a, 3, p);
      ASSERT_TRUE(same_bits(sample_direction3(s, b), p)) << static_cast<int>(s) << ", point " << id;
      Rng c(7, Stream::kValidation, id, 2), d(7, Stream::kValidation, id, 2);
      sample_ball(s, c, 3, 2.5, p);
      ASSERT_TRUE(same_bits(sample_region_point(RegionShape::kBall, 2.5, s, d), p)) << static_cast<int>(s) << ", point " << id;
    }
}

// Pearson's chi-square of points in the cube [-h, h]^3 over cells^3 equal cells, and its
// p-value (chi-square law with cells^3 - 1 degrees of freedom).
double box_uniformity_p(const std::vector<Vec3>& points, double h, int cells) {
  std::vector<double> count(static_cast<std::size_t>(cells * cells * cells), 0.0);
  auto cell = [&](double v) {
    const int c = static_cast<int>(std::floor((v + h) / (2.0 * h) * cells));
    return std::min(cells - 1, std::max(0, c));
  };
  for (const Vec3& p : points) count[(cell(p.z) * cells + cell(p.y)) * cells + cell(p.x)] += 1.0;
  const double expected = static_cast<double>(points.size()) / static_cast<double>(count.size());
  double chi2 = 0.0;
  for (double c : count) chi2 += (c - expected) * (c - expected) / expected;
  return gsl_cdf_chisq_Q(chi2, static_cast<double>(count.size() - 1));
}

// The criterion, fixed in advance: p > 1e-4 for the placed somas (deterministic seeds, so
// the outcome is fixed too), p < 1e-4 for a control that moves each coordinate by at most
// 1.4 % of the half-edge towards the centre.
constexpr double kThreshold = 1e-4;
constexpr int kCells = 10;  // 1000 cells, 100 points expected in each

Scene box_scene(const std::string& overlap) {
  return parse_scene(R"({"seed": 4711, "neurons": {"count": 100000, "soma_radius": 0.01, "overlap": ")" + overlap +
                         R"(", "region": {"shape": "box", "radius": 4.0}}})",
                     "box test")
      .scene;
}

TEST(placement, BoxRegionIsUniform) {
  for (const std::string overlap : {"allow", "reject"}) {
    const Scene scene = box_scene(overlap);
    ASSERT_EQ(scene.neurons.shape, RegionShape::kBox);
    const double h = scene.neurons.radius;
    const Placement placed = place_neurons(scene);
    ASSERT_EQ(placed.soma.size(), 100000u);
    // Packing fraction 8e-7: about 330 pairs of the 10^5 independent draws overlap (the
    // birthday effect), so "reject" redraws a few hundred somas; "allow" none.
    EXPECT_LT(placed.redraws, overlap == "reject" ? 1000u : 1u) << overlap;
    for (const Vec3& p : placed.soma)
      ASSERT_TRUE(std::fabs(p.x) < h && std::fabs(p.y) < h && std::fabs(p.z) < h) << overlap;
    const double p = box_uniformity_p(placed.soma, h, kCells);
    EXPECT_GT(p, kThreshold) << overlap << ": chi-square p = " << p;
    std::printf("box, overlap %s: chi-square p = %.4g over %d cells\n", overlap.c_str(), p, kCells * kCells * kCells);
  }
}

TEST(placement, BoxUniformityTestRejectsANonUniformSample) {
  const Scene scene = box_scene("allow");
  const double h = scene.neurons.radius;
  std::vector<Vec3> squeezed = place_neurons(scene).soma;
  // x -> h sign(x) (|x|/h)^1.04 in every coordinate: per axis, the two central slabs of
  // cells get 6.4 % more points and the two outer ones 3.5 % fewer.
  auto squeeze = [h, kSqueeze = 1.04](double v) { return std::copysign(h * std::pow(std::fabs(v) / h, kSqueeze), v); };
  for (Vec3& p : squeezed) p = {squeeze(p.x), squeeze(p.y), squeeze(p.z)};
  const double p = box_uniformity_p(squeezed, h, kCells);
  EXPECT_LT(p, kThreshold) << "the chi-square test cannot see a 6 % density change: p = " << p;
  std::printf("box, squeezed control: chi-square p = %.4g\n", p);
}

// Random sequential addition as its definition reads: soma i draws attempt 0, 1, ... until
// an attempt overlaps no earlier soma's final position (min distance 2 r_s), and the
// first soma that exhausts max_attempts ends the placement. A std::map of cells, one soma
// at a time: slow and plain.
struct Sequential {
  std::vector<Vec3> soma;
  std::uint64_t redraws = 0;
  std::optional<std::size_t> failed;  // the neuron that exhausted its attempts
};
Sequential place_sequentially(const Scene& scene) {
  const auto& nn = scene.neurons;
  const double d = 2.0 * nn.soma_radius;
  std::map<std::tuple<long, long, long>, std::vector<std::size_t>> cells;
  auto cell = [&](Vec3 p) {
    return std::tuple<long, long, long>(static_cast<long>(std::floor(p.x / d)), static_cast<long>(std::floor(p.y / d)),
                                        static_cast<long>(std::floor(p.z / d)));
  };
  Sequential out;
  for (std::size_t i = 0; i < nn.count; ++i) {
    for (std::uint32_t attempt = 0;; ++attempt) {
      if (attempt == nn.max_attempts) {
        out.failed = i;
        return out;
      }
      const Vec3 p = soma_draw(scene, i, attempt);
      const auto [cx, cy, cz] = cell(p);
      bool overlaps = false;
      for (long dz = -1; dz <= 1; ++dz)
        for (long dy = -1; dy <= 1; ++dy)
          for (long dx = -1; dx <= 1; ++dx)
            if (auto it = cells.find({cx + dx, cy + dy, cz + dz}); it != cells.end())
              for (std::size_t j : it->second) overlaps = overlaps || core::norm2(out.soma[j] - p) < d * d;
      if (!overlaps) {
        out.soma.push_back(p);
        cells[cell(p)].push_back(i);
        out.redraws += attempt;
        break;
      }
    }
  }
  return out;
}

// Across block boundaries (4096 ids), shapes, populations, densities up to jamming and
// attempt limits low enough to fail: the same somas, bit for bit, the same redraw count,
// and the same neuron named when it fails.
RC_GTEST_PROP(placement, BlockedOverlapPassIsRandomSequentialAddition, ()) {
  const Scene s = *test::gen_placement_scene(12000);
  const Sequential expected = place_sequentially(s);
  std::optional<Placement> got;
  std::string error;
  try {
    got = place_neurons(s);
  } catch (const RunError& e) {
    error = e.what();
  }
  if (expected.failed) {
    RC_ASSERT(!got.has_value());
    RC_ASSERT(error.find(fmt::format("neuron {} still overlaps", *expected.failed)) != std::string::npos);
    return;
  }
  if (!got) RC_FAIL("placement refused: " + error);
  RC_ASSERT(got->redraws == expected.redraws);
  RC_ASSERT(got->soma.size() == expected.soma.size());
  for (std::size_t i = 0; i < expected.soma.size(); ++i)
    RC_ASSERT(bits_of(got->soma[i].x) == bits_of(expected.soma[i].x) &&
              bits_of(got->soma[i].y) == bits_of(expected.soma[i].y) &&
              bits_of(got->soma[i].z) == bits_of(expected.soma[i].z));
}

// The batched query answers what one query at a time answers, for any batch size, chains of
// any length (a small table over many points) and points at exactly the overlap distance
// (which do not overlap: the test is strict).
RC_GTEST_PROP(placement, OverlapBatchAnswersAsSingleQueries, ()) {
  const double min_dist = *rc::gen::element(0.5, 1.0, 2.0);
  const std::size_t n = *rc::gen::inRange<std::size_t>(0, 400);
  const std::size_t expected = *rc::gen::element<std::size_t>(1, 16, 1024);
  const std::uint32_t base = *rc::gen::element<std::uint32_t>(0, 5000);
  const auto coord = [] { return static_cast<double>(*rc::gen::inRange(-4000, 4000)) / 997.0; };
  std::vector<core::Vec3> pos(base + n);
  OverlapIndex index(n, min_dist, expected);
  index.clear(base);
  for (std::size_t i = 0; i < n; ++i) {
    pos[base + i] = {coord(), coord(), coord()};
    index.insert(static_cast<std::uint32_t>(base + i), pos[base + i]);
  }
  const std::size_t count = *rc::gen::inRange<std::size_t>(1, OverlapIndex::kBatch + 1);
  std::vector<core::Vec3> p(count);
  for (core::Vec3& q : p) {
    q = {coord(), coord(), coord()};
    if (n == 0 || !*rc::gen::arbitrary<bool>()) continue;
    // Near an indexed point, in any of the 26 directions: just inside the distance, or at
    // exactly it along an axis.
    const core::Vec3 at = pos[base + *rc::gen::inRange<std::size_t>(0, n)];
    const double sx = *rc::gen::inRange(-1, 2), sy = *rc::gen::inRange(-1, 2), sz = *rc::gen::inRange(-1, 2);
    const double axes = std::abs(sx) + std::abs(sy) + std::abs(sz);
    if (axes == 0.0) continue;
    const double d = axes == 1.0 && *rc::gen::arbitrary<bool>() ? min_dist : 0.999 * min_dist / std::sqrt(axes);
    q = at + core::Vec3{sx * d, sy * d, sz * d};
  }
  bool hit[OverlapIndex::kBatch];
  index.overlaps_batch(pos, p.data(), count, min_dist * min_dist, hit);
  for (std::size_t q = 0; q < count; ++q) RC_ASSERT(hit[q] == index.overlaps(pos, p[q], min_dist * min_dist));
}

// A query answers exactly what testing every indexed point answers, at any scale of the
// coordinates (up to 10^7 times the distance, where rounding a position to float moves it by
// about the distance itself) and for points within a few ulps of the overlap distance, on
// either side: the index's float positions only rule out, never decide.
RC_GTEST_PROP(placement, OverlapQueryIsExhaustiveSearch, ()) {
  const double min_dist = *rc::gen::element(0.5, 1.0, 3.0), min_dist2 = min_dist * min_dist;
  const double scale = *rc::gen::element(1.0, 1e3, 1e5, 1e7);
  const std::size_t n = *rc::gen::inRange<std::size_t>(1, 300);
  const auto coord = [&] { return scale * static_cast<double>(*rc::gen::inRange(-4000, 4000)) / 3989.0; };
  std::vector<core::Vec3> pos(n);
  OverlapIndex index(n, min_dist, *rc::gen::element<std::size_t>(1, 64, 1024));
  for (std::size_t i = 0; i < n; ++i) {
    pos[i] = {coord(), coord(), coord()};
    index.insert(static_cast<std::uint32_t>(i), pos[i]);
  }
  for (int t = 0; t < 32; ++t) {
    core::Vec3 q{coord(), coord(), coord()};
    if (*rc::gen::arbitrary<bool>()) {  // at the distance from an indexed point, give or take a few ulps
      const core::Vec3 at = pos[*rc::gen::inRange<std::size_t>(0, n)];
      core::Vec3 u{static_cast<double>(*rc::gen::inRange(-9, 10)), static_cast<double>(*rc::gen::inRange(-9, 10)),
                   static_cast<double>(*rc::gen::inRange(-9, 10))};
      const double len = std::sqrt(core::norm2(u));
      if (len == 0.0) u = {1.0, 0.0, 0.0};
      const double r = min_dist * (1.0 + static_cast<double>(*rc::gen::inRange(-4, 5)) * 0x1p-52);
      q = at + u * (r / (len == 0.0 ? 1.0 : len));
    }
    bool brute = false;
    for (const core::Vec3& x : pos) brute = brute || core::norm2(x - q) < min_dist2;
    RC_ASSERT(index.overlaps(pos, q, min_dist2) == brute);
  }
}

}  // namespace
}  // namespace axg

#pragma once
// Hashed cell lists for placement's overlap tests (methods §2.1): cells of edge 2 r_s, so
// every soma that can overlap a new one lies in the 27 cells around it. The hash keeps
// space's neighbours near in memory: the cells are grouped in blocks of 4 x 4 x 4, a block
// is hashed to a run of 64 buckets and its cells lie in that run in Morton order, so a
// query's 27 buckets fall in a few cache lines instead of 27 (bucket()). Entries are slot
// numbers [base, base + capacity) into a position array the caller owns: neuron ids for the
// one-process placement, local slots for the decomposed one (distributed/).
#include <cmath>
#include <cstdint>
#include <vector>

#include "axonguide/core/vec3.hpp"

namespace axg {

class OverlapIndex {
 public:
  // Buckets for about `expected` entries; room for `n` slots (grown by insert past it).
  OverlapIndex(std::size_t n, double cell, std::size_t expected = 0) : cell_(cell), next_(n, kEmpty) {
    std::size_t buckets = 64;  // one block's run at least (bucket())
    while (buckets < 2 * (expected ? expected : n)) buckets <<= 1;
    head_.assign(buckets, kEmpty);
    mask_ = buckets - 1;
  }
  // Empties the index and rebases its slots at `base`.
  void clear(std::uint32_t base) {
    std::fill(head_.begin(), head_.end(), kEmpty);
    base_ = base;
  }
  // The same, for an index that holds slots [base, end) inserted at pos[slot] (every slot
  // inserted, none moved since): only their buckets are emptied, so that a large index
  // with few entries (few collisions a query) costs its entries to clear, not its size.
  void clear_inserted(const std::vector<core::Vec3>& pos, std::uint32_t end, std::uint32_t base) {
    for (std::uint32_t j = base_; j < end; ++j)
      head_[bucket(coord(pos[j].x), coord(pos[j].y), coord(pos[j].z))] = kEmpty;
    base_ = base;
  }

  // Whether any indexed slot j has |pos[j] - p|^2 < min_dist2. The 27 buckets' heads are
  // read first, without a branch between them, so that their cache misses overlap (the
  // query is bound by memory latency once the index outgrows the cache); the answer does
  // not depend on the order the chains are then walked in.
  bool overlaps(const std::vector<core::Vec3>& pos, core::Vec3 p, double min_dist2) const {
    std::size_t buckets[27];
    neighbour_buckets(p, buckets);
    std::uint32_t heads[27];
    for (int k = 0; k < 27; ++k) heads[k] = head_[buckets[k]];
    return chains_hold_near(pos, p, min_dist2, heads);
  }

  // overlaps() for `count` points at once (count <= kBatch), hit[q] its answer for p[q]. The
  // reads are issued level by level across all the points, so that their cache misses
  // overlap: first the 27 buckets of every point are prefetched, then every chain's first
  // node (its position and its link), and only then are the chains walked. One query is a
  // chain of dependent misses (head, node, position), about 1 us a query at 10^7 somas, when
  // the index and the positions are far beyond the cache; a batch of them issues those
  // misses together. The answers are overlaps()'s: whether any slot is near, not which.
  static constexpr std::size_t kBatch = 16;
  void overlaps_batch(const std::vector<core::Vec3>& pos, const core::Vec3* p, std::size_t count, double min_dist2,
                      bool* hit) const {
    std::size_t buckets[kBatch][27];
    for (std::size_t q = 0; q < count; ++q) {
      neighbour_buckets(p[q], buckets[q]);
      for (int k = 0; k < 27; ++k) __builtin_prefetch(&head_[buckets[q][k]]);
    }
    std::uint32_t heads[kBatch][27];
    for (std::size_t q = 0; q < count; ++q)
      for (int k = 0; k < 27; ++k) {
        const std::uint32_t j = heads[q][k] = head_[buckets[q][k]];
        if (j != kEmpty) {
          __builtin_prefetch(&pos[j]);
          __builtin_prefetch(&next_[j - base_]);
        }
      }
    for (std::size_t q = 0; q < count; ++q) hit[q] = chains_hold_near(pos, p[q], min_dist2, heads[q]);
  }

  // The bucket insert(p) writes to, prefetched: an insert loop calls it a few slots ahead.
  void prefetch_insert(core::Vec3 p) const { __builtin_prefetch(&head_[bucket(coord(p.x), coord(p.y), coord(p.z))]); }

  void insert(std::uint32_t slot, core::Vec3 p) {
    if (slot - base_ >= next_.size()) next_.resize(std::max<std::size_t>(2 * next_.size(), slot - base_ + 1), kEmpty);
    std::size_t b = bucket(coord(p.x), coord(p.y), coord(p.z));
    next_[slot - base_] = head_[b];
    head_[b] = slot;
  }

  std::size_t bytes() const { return (head_.capacity() + next_.capacity()) * 4; }

 private:
  static constexpr std::uint32_t kEmpty = 0xffffffffu;

  // The buckets of the 27 cells around p's.
  void neighbour_buckets(core::Vec3 p, std::size_t (&out)[27]) const {
    const std::int64_t cx = coord(p.x), cy = coord(p.y), cz = coord(p.z);
    int k = 0;
    for (std::int64_t dz = -1; dz <= 1; ++dz)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dx = -1; dx <= 1; ++dx) out[k++] = bucket(cx + dx, cy + dy, cz + dz);
  }
  // Whether a slot of the chains from `heads` lies within the distance of p.
  bool chains_hold_near(const std::vector<core::Vec3>& pos, core::Vec3 p, double min_dist2,
                        const std::uint32_t (&heads)[27]) const {
    for (int k = 0; k < 27; ++k)
      for (std::uint32_t j = heads[k]; j != kEmpty; j = next_[j - base_])
        if (core::norm2(pos[j] - p) < min_dist2) return true;
    return false;
  }
  std::int64_t coord(double v) const { return static_cast<std::int64_t>(std::floor(v / cell_)); }
  // Cell (x, y, z)'s bucket: the hash of its 4 x 4 x 4 block picks a run of 64 buckets (the
  // table has at least 64), the cell's place in the block in Morton order (x, y, z
  // interleaved, lowest bit first) its bucket in the run. Which bucket a cell gets changes
  // only memory traffic: a query walks every chain of its 27 cells' buckets and tests each
  // entry's distance, so the answer is the same for any hash.
  std::size_t bucket(std::int64_t x, std::int64_t y, std::int64_t z) const {
    const std::uint64_t ux = static_cast<std::uint64_t>(x), uy = static_cast<std::uint64_t>(y),
                        uz = static_cast<std::uint64_t>(z);
    std::uint64_t h = (ux >> 2) * 0x9E3779B97F4A7C15ull ^ (uy >> 2) * 0xC2B2AE3D27D4EB4Full ^
                      (uz >> 2) * 0x165667B19E3779F9ull;
    h ^= h >> 29;
    const std::uint64_t m = (ux & 1) | (uy & 1) << 1 | (uz & 1) << 2 | (ux & 2) << 2 | (uy & 2) << 3 | (uz & 2) << 4;
    return static_cast<std::size_t>(h << 6 | m) & mask_;
  }

  double cell_;
  std::uint32_t base_ = 0;
  std::size_t mask_ = 0;
  std::vector<std::uint32_t> head_, next_;
};

}  // namespace axg

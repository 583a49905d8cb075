// Random sequential addition in id order, decomposed over ranks (placement.hpp).
#include "axonguide/distributed/placement.hpp"

#include <algorithm>

#include <tbb/parallel_for.h>

#include "axonguide/overlap_index.hpp"
#include "axonguide/placement.hpp"

namespace axg::distributed {

using core::Vec3;

namespace {

constexpr std::uint32_t kNone = 0xffffffffu;

// What every rank knows of one soma of the current id block.
struct Soma {
  std::uint32_t clear[2] = {kNone, kNone};  // attempts found clear of the earlier blocks, ascending
  std::uint32_t known = 0;                  // how many of them
  std::uint32_t next = 0;                   // the first attempt not yet tested
  bool exhausted = false;                   // next reached max_attempts
};

// One search's state after a round, from the rank that ran it.
struct Update {
  std::uint32_t k;      // index in the id block
  std::uint32_t next;   // the first attempt not yet tested
  std::uint32_t clear;  // the clear attempt found, or kNone
  std::int32_t at;      // the rank holding attempt `next` when the search goes on; -1 when it ended
};

class Placer {
 public:
  Placer(const Scene& scene, const Decomposition& d, Comm& comm, std::size_t id_block)
      : scene_(scene),
        d_(d),
        comm_(comm),
        rank_(comm.rank()),
        n_(static_cast<std::size_t>(scene.neurons.count)),
        id_block_(id_block),
        max_attempts_(scene.neurons.max_attempts),
        min_dist2_(4.0 * scene.neurons.soma_radius * scene.neurons.soma_radius),
        earlier_(0, 2.0 * scene.neurons.soma_radius, n_ / static_cast<std::size_t>(comm.size()) + 1024),
        block_index_(id_block, 2.0 * scene.neurons.soma_radius),
        x0_(id_block),
        final_(id_block),
        somas_(id_block) {}

  DecomposedPlacement run() {
    const bool reject = scene_.neurons.overlap_reject && n_ >= 2;
    if (reject) check_packing(scene_);
    if (comm_.root()) out_.all.resize(n_);
    for (std::size_t a = 0; a < n_; a += id_block_) {
      base_ = a;
      m_ = std::min(n_, a + id_block_) - a;
      tbb::parallel_for(std::size_t{0}, m_, [&](std::size_t k) { x0_[k] = soma_draw(scene_, a + k, 0); });
      if (reject) {
        place_block();
      } else {
        std::copy(x0_.begin(), x0_.begin() + static_cast<std::ptrdiff_t>(m_), final_.begin());
      }
      keep_block();
    }
    out_.somas.pos = std::move(near_pos_);
    for (const Vec3& p : out_.somas.pos) out_.somas.owned.push_back(d_.owner(p) == rank_);
    return std::move(out_);
  }

 private:
  Vec3 position(std::size_t k, std::uint32_t attempt) const {
    return attempt == 0 ? x0_[k] : soma_draw(scene_, base_ + k, attempt);
  }

  void place_block() {
    std::fill(somas_.begin(), somas_.begin() + static_cast<std::ptrdiff_t>(m_), Soma{});
    // 1. Every soma's first attempt clear of the earlier blocks.
    std::vector<std::uint32_t> ks(m_);
    for (std::size_t k = 0; k < m_; ++k) ks[k] = static_cast<std::uint32_t>(k);
    search(ks, false);
    // 2. Those whose first clear attempt meets a lower id's: their second.
    block_index_.clear(0);
    ks.clear();
    for (std::size_t k = 0; k < m_; ++k) {
      if (somas_[k].known == 0) continue;
      const Vec3 x = position(k, somas_[k].clear[0]);
      if (block_index_.overlaps(final_, x, min_dist2_) && !somas_[k].exhausted) ks.push_back(static_cast<std::uint32_t>(k));
      final_[k] = x;
      block_index_.insert(static_cast<std::uint32_t>(k), x);
    }
    out_.second_searches += ks.size();
    search(ks, false);
    // 3. The scan in id order, against the block's lower ids.
    block_index_.clear(0);
    for (std::size_t k = 0; k < m_; ++k) {
      Soma& s = somas_[k];
      std::uint32_t taken = kNone;
      for (std::uint32_t j = 0; j < s.known && taken == kNone; ++j) {
        const Vec3 x = position(k, s.clear[j]);
        if (!block_index_.overlaps(final_, x, min_dist2_)) taken = s.clear[j], final_[k] = x;
      }
      if (taken == kNone) {
        if (!s.exhausted) {
          ++out_.scan_searches;
          const std::uint32_t from = s.next;
          search({static_cast<std::uint32_t>(k)}, true);
          if (s.known > 0 && s.clear[s.known - 1] != kNone && s.clear[s.known - 1] >= from)
            taken = s.clear[s.known - 1], final_[k] = position(k, taken);
        }
        if (taken == kNone) placement_failed(scene_, base_ + k);
      }
      out_.redraws += taken;
      block_index_.insert(static_cast<std::uint32_t>(k), final_[k]);
    }
  }

  // Rounds until each listed soma has found one more clear attempt or run out of them.
  // With `with_block`, an attempt must also clear the block's somas in block_index_ (the
  // scan's lower ids).
  void search(const std::vector<std::uint32_t>& ks, bool with_block) {
    std::vector<std::uint32_t> active;
    std::vector<std::int32_t> at(m_, -1);
    for (std::uint32_t k : ks) {
      Soma& s = somas_[k];
      if (s.next >= max_attempts_) {
        s.exhausted = true;
        continue;
      }
      // The capacity of clear[]: a third search for one soma (a scan search after the
      // second) overwrites the second clear attempt, which was already tried.
      if (s.known == 2) s.known = 1, s.clear[1] = kNone;
      at[k] = d_.owner(position(k, s.next));
      active.push_back(k);
    }
    while (!active.empty()) {
      std::vector<std::uint32_t> mine;
      for (std::uint32_t k : active)
        if (at[k] == rank_) mine.push_back(k);
      std::vector<Update> updates(mine.size());
      tbb::parallel_for(std::size_t{0}, mine.size(), [&](std::size_t j) { updates[j] = advance(mine[j], with_block); });
      Bytes bytes;
      append(bytes, updates);
      const std::vector<Bytes> all = comm_.allgather(bytes);
      ++out_.rounds;
      for (const Bytes& from : all)
        for (const Update& u : records<Update>(from)) {
          Soma& s = somas_[u.k];
          s.next = u.next;
          if (u.clear != kNone) s.clear[s.known++] = u.clear;
          if (u.at < 0 && u.clear == kNone) s.exhausted = true;
          at[u.k] = u.at;
        }
      std::vector<std::uint32_t> still;
      for (std::uint32_t k : active)
        if (at[k] >= 0) still.push_back(k);
      active.swap(still);
    }
  }

  // This rank's part of soma k's search: test its attempts while they fall in this block.
  Update advance(std::uint32_t k, bool with_block) const {
    std::uint32_t t = somas_[k].next;
    Vec3 x = position(k, t);
    for (;;) {
      if (!earlier_.overlaps(near_pos_, x, min_dist2_) && !(with_block && block_index_.overlaps(final_, x, min_dist2_)))
        return {k, t + 1, t, -1};
      if (++t >= max_attempts_) return {k, t, kNone, -1};
      x = soma_draw(scene_, base_ + k, t);
      const int owner = d_.owner(x);
      if (owner != rank_) return {k, t, kNone, owner};
    }
  }

  // The block's final somas: into this rank's halo list and overlap index, and rank 0's copy.
  void keep_block() {
    for (std::size_t k = 0; k < m_; ++k) {
      const Vec3 x = final_[k];
      if (comm_.root()) out_.all[base_ + k] = x;
      if (!d_.near(rank_, x, d_.halo)) continue;
      const auto slot = static_cast<std::uint32_t>(near_pos_.size());
      out_.somas.id.push_back(static_cast<std::uint32_t>(base_ + k));
      near_pos_.push_back(x);
      earlier_.insert(slot, x);
    }
  }

  const Scene& scene_;
  const Decomposition& d_;
  Comm& comm_;
  int rank_;
  std::size_t n_, id_block_, base_ = 0, m_ = 0;
  std::uint32_t max_attempts_;
  double min_dist2_;
  OverlapIndex earlier_;       // slots into near_pos_
  std::vector<Vec3> near_pos_;
  OverlapIndex block_index_;   // slots k of the current id block, into final_
  std::vector<Vec3> x0_, final_;
  std::vector<Soma> somas_;
  DecomposedPlacement out_;
};

}  // namespace

DecomposedPlacement place_decomposed(const Scene& scene, const Decomposition& d, Comm& comm, std::size_t id_block) {
  return Placer(scene, d, comm, std::max<std::size_t>(1, id_block)).run();
}

}  // namespace axg::distributed

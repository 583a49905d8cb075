// Random sequential addition in id order, decomposed over ranks (placement.hpp).
#include "axonguide/distributed/placement.hpp"

#include <algorithm>
#include <optional>
#include <chrono>
#include <cmath>

#include <tbb/parallel_for.h>

#include "axonguide/distributed/on_every_rank.hpp"
#include "axonguide/placement/overlap_index.hpp"
#include "axonguide/placement/placement.hpp"

namespace axg::distributed {

using core::Vec3;

namespace {

constexpr std::uint32_t kNone = 0xffffffffu;
constexpr std::uint32_t kMaxWindow = 4096;  // attempts a round draws for one soma, at most

// Adds the wall time of its scope to `total` (seconds).
class Stopwatch {
 public:
  explicit Stopwatch(double& total) : total_(total), t0_(std::chrono::steady_clock::now()) {}
  ~Stopwatch() { total_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count(); }
  Stopwatch(const Stopwatch&) = delete;
  Stopwatch& operator=(const Stopwatch&) = delete;

 private:
  double& total_;
  std::chrono::steady_clock::time_point t0_;
};

// What every rank knows of one soma of the current id block.
struct Soma {
  std::vector<std::uint32_t> clear;  // every attempt below `next` that clears the earlier blocks, ascending
  std::vector<Vec3> at_clear;        // their positions
  std::uint32_t next = 0;            // the first attempt not yet tested
  std::uint32_t asks = 0;            // searches after the first: each asks for twice the clear attempts
  bool exhausted = false;            // next reached max_attempts
};

// A clear attempt found in a round, by the rank whose block holds its position.
struct Found {
  Vec3 pos;
  std::uint32_t k;        // index in the id block
  std::uint32_t attempt;
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
        final_(id_block),
        taken_(id_block),
        somas_(id_block) {}

  DecomposedPlacement run() {
    const bool reject = scene_.neurons.overlap_reject && n_ >= 2;
    if (reject) on_every_rank([&] { check_packing(scene_); });
    if (comm_.root()) out_.all.resize(n_);
    for (std::size_t a = 0; a < n_; a += id_block_) {
      base_ = a;
      m_ = std::min(n_, a + id_block_) - a;
      if (reject) {
        place_block();
      } else {
        tbb::parallel_for(std::size_t{0}, m_, [&](std::size_t k) { final_[k] = soma_draw(scene_, a + k, 0); });
      }
      keep_block();
    }
    out_.somas.pos = std::move(near_pos_);
    for (const Vec3& p : out_.somas.pos) out_.somas.owned.push_back(d_.owner(p) == rank_);
    return std::move(out_);
  }

 private:
  void place_block() {
    for (std::size_t k = 0; k < m_; ++k) somas_[k] = Soma{};
    settled_ = 0;
    std::vector<std::uint32_t> ks(m_);
    for (std::size_t k = 0; k < m_; ++k) ks[k] = static_cast<std::uint32_t>(k);
    search(ks);
    while (!scan(ks)) {
      out_.stats.extra_searches += ks.size();
      search(ks);
    }
  }

  // The block in id order, from the first soma the last scan left pending: soma k takes its
  // first known clear attempt that no lower id's position overlaps. A soma whose known clear
  // attempts are all overlapped is pending, and so is every position after it: they stand
  // only if the pending ones do not move into them. Returns true when no soma is pending
  // (every position is final and is random sequential addition's); otherwise `requests`
  // lists the pending somas that can search on, and the first of them always can (or it
  // fails, as RSA does).
  bool scan(std::vector<std::uint32_t>& requests) {
    Stopwatch w(out_.stats.replicated_seconds);
    ++out_.stats.scan_passes;
    requests.clear();
    block_index_.clear(0);
    for (std::size_t k = 0; k < settled_; ++k) block_index_.insert(static_cast<std::uint32_t>(k), final_[k]);
    bool pending = false;
    for (std::size_t k = settled_; k < m_; ++k) {
      const Soma& s = somas_[k];
      std::uint32_t taken = kNone;
      for (std::size_t j = 0; j < s.clear.size() && taken == kNone; ++j)
        if (!block_index_.overlaps(final_, s.at_clear[j], min_dist2_)) taken = s.clear[j], final_[k] = s.at_clear[j];
      if (taken != kNone) {
        taken_[k] = taken;
        block_index_.insert(static_cast<std::uint32_t>(k), final_[k]);
        if (!pending) settled_ = k + 1;  // final: every lower id is
        continue;
      }
      if (!pending && s.exhausted) on_every_rank([&] { placement_failed(scene_, base_ + k); });
      pending = true;
      if (!s.exhausted) requests.push_back(static_cast<std::uint32_t>(k));
    }
    if (pending) return false;
    for (std::size_t k = 0; k < m_; ++k) out_.redraws += taken_[k];
    return true;
  }

  // Rounds until each listed soma has found `want` more attempts clear of the earlier
  // blocks, or run out of attempts. A round tests a window of each soma's next attempts:
  // every rank draws the window (a cheap, replicated draw) and tests the positions in its
  // own block; the all-gather of what they found tells every rank every clear attempt in
  // the window. A window that finds too few doubles for the next round, so that a soma
  // near jamming takes rounds in the logarithm of its attempts.
  void search(const std::vector<std::uint32_t>& ks) {
    std::vector<std::uint32_t> active, want(m_, 0), window(m_, 1);
    for (std::uint32_t k : ks) {
      Soma& s = somas_[k];
      if (s.next >= max_attempts_) {
        s.exhausted = true;
        continue;
      }
      want[k] = 1u << std::min<std::uint32_t>(s.asks, 10);
      if (s.asks > 0) window[k] = std::min(want[k], kMaxWindow);
      ++s.asks;
      active.push_back(k);
    }
    std::vector<Found> found;
    std::vector<std::size_t> offset;
    while (!active.empty()) {
      std::optional<Stopwatch> clock(std::in_place, out_.stats.window_seconds);
      // Slots for every attempt of every window (most windows are one attempt).
      offset.assign(active.size() + 1, 0);
      for (std::size_t j = 0; j < active.size(); ++j) offset[j + 1] = offset[j] + window[active[j]];
      found.assign(offset.back(), Found{{}, kNone, kNone});
      tbb::parallel_for(std::size_t{0}, active.size(), [&](std::size_t j) {
        const std::uint32_t k = active[j];
        const std::uint32_t end = std::min(max_attempts_, somas_[k].next + window[k]);
        Found* slot = found.data() + offset[j];
        for (std::uint32_t t = somas_[k].next; t < end; ++t) {
          const Vec3 x = soma_draw(scene_, base_ + k, t);
          if (d_.owner(x) == rank_ && !earlier_.overlaps(near_pos_, x, min_dist2_)) *slot++ = {x, k, t};
        }
      });
      found.erase(std::remove_if(found.begin(), found.end(), [](const Found& f) { return f.k == kNone; }),
                  found.end());
      Bytes bytes;
      append(bytes, found);
      clock.emplace(out_.stats.gather_seconds);
      const std::vector<Bytes> all = comm_.allgather(bytes);
      clock.emplace(out_.stats.replicated_seconds);
      ++out_.stats.rounds;
      // Each window's clear attempts, ascending, from whichever ranks found them.
      std::vector<Found> round;
      for (const Bytes& from : all) {
        const std::vector<Found> part = records<Found>(from);
        round.insert(round.end(), part.begin(), part.end());
      }
      std::sort(round.begin(), round.end(),
                [](const Found& a, const Found& b) { return a.k != b.k ? a.k < b.k : a.attempt < b.attempt; });
      for (const Found& f : round) {
        Soma& s = somas_[f.k];
        s.clear.push_back(f.attempt);
        s.at_clear.push_back(f.pos);
        want[f.k] = want[f.k] > 0 ? want[f.k] - 1 : 0;
      }
      std::vector<std::uint32_t> still;
      for (std::uint32_t k : active) {
        Soma& s = somas_[k];
        s.next = std::min(max_attempts_, s.next + window[k]);
        if (s.next >= max_attempts_) {
          s.exhausted = true;
          continue;
        }
        if (want[k] == 0) continue;
        window[k] = std::min<std::uint32_t>(2 * window[k], kMaxWindow);
        still.push_back(k);
      }
      active.swap(still);
    }
  }

  // The block's final somas: into this rank's halo list and overlap index, and rank 0's copy.
  void keep_block() {
    Stopwatch w(out_.stats.replicated_seconds);
    const Decomposition::Bounds mine = d_.bounds(rank_);
    for (std::size_t k = 0; k < m_; ++k) {
      const Vec3 x = final_[k];
      if (comm_.root()) out_.all[base_ + k] = x;
      if (!mine.near(x, d_.halo)) continue;
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
  std::vector<Vec3> final_;
  std::vector<std::uint32_t> taken_;  // the attempt each soma of the block takes
  std::size_t settled_ = 0;           // the block's leading somas whose positions are final
  std::vector<Soma> somas_;
  DecomposedPlacement out_;
};

}  // namespace

std::size_t placement_id_block(const Scene& scene) {
  // About one overlap in ten at the end of a block (soma volume fraction phi: a block of B
  // somas overlaps a new one with probability about 8 phi B / N) keeps the scan's passes few;
  // blocks of at most 16384 keep its replicated work small.
  const double phi = std::max(packing_fraction(scene.neurons), 1e-9);
  const double b = static_cast<double>(scene.neurons.count) * 0.1 / (8.0 * phi);
  return static_cast<std::size_t>(std::clamp(b, 256.0, 16384.0));
}

DecomposedPlacement place_decomposed(const Scene& scene, const Decomposition& d, Comm& comm, std::size_t id_block) {
  return Placer(scene, d, comm, std::max<std::size_t>(1, id_block ? id_block : placement_id_block(scene))).run();
}

}  // namespace axg::distributed

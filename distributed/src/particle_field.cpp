// The particle field over ranks (fields.hpp; docs/scaling.md §2.4). Each step runs the
// one-process stages on this rank's particles, in the one-process order, with the core
// functions of reference/src/fields/particle_field.cpp:
//   emit (the ranks near the source) -> move -> compact and migrate
//   -> halo and hashed grid (when gathers need them) -> collisions -> migrate, halo, grid
//   -> estimate deposits, summed over the ranks, and their fold.
// Why the bits are the one-process bits: every particle's motion and death is a function of
// (seed, id, step, its state); ids are the one-process ids (every rank counts every
// emission); a gather at a point of this block adds the particles within its radius,
// all of which are here (owned or in the halo, which is at least that radius wide), in
// (bucket, id) order, because this rank's arrays are in id order and the hashed grid has
// the one-process geometry: a bucket here holds a subset of the one-process bucket, in the
// same order, and what it lacks lies beyond the radius, which the one-process loop skips.
#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

#include <tbb/parallel_for.h>

#include "axonguide/core/particles.hpp"
#include "axonguide/engine/state.hpp"
#include "axonguide/model/cues.hpp"
#include "axonguide/model/estimate.hpp"
#include "axonguide/model/particles.hpp"
#include "axonguide/model/sensing.hpp"
#include "axonguide/distributed/fields.hpp"
#include "axonguide/distributed/on_every_rank.hpp"
#include "axonguide/support/error.hpp"
#include "axonguide/fields/particle_stages.hpp"

namespace axg::distributed {

using core::Vec3;

namespace {

// A particle that changes owner (and a checkpoint's record).
struct Migrant {
  Vec3 pos, vel;
  std::uint64_t id;
  std::uint16_t cue;
};

// A particle another rank keeps in its halo (and an output frame's record).
struct HaloParticle {
  Vec3 pos;
  std::uint64_t id;
  std::uint16_t cue;
};

// Records received as runs, each in id order (a rank sends its particles in id order):
// merged into one run in id order, O(n log runs).
template <class T>
void merge_runs(std::vector<T>& v, const std::vector<std::size_t>& ends) {
  auto by_id = [](const T& a, const T& b) { return a.id < b.id; };
  for (std::size_t k = 1; k < ends.size(); ++k)
    std::inplace_merge(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(ends[k - 1]),
                       v.begin() + static_cast<std::ptrdiff_t>(ends[k]), by_id);
}

class DecomposedParticleField final : public ParticleFieldStages {
 public:
  DecomposedParticleField(const Scene& scene, const std::vector<core::CueParams>& cues, const Decomposition& d,
                          Comm& comm, FieldReport& report)
      : ParticleFieldStages(scene, cues),
        gathers_(sense_.sensing != core::ParticleSensing::kEstimate),
        d_(d),
        comm_(comm),
        rank_(comm.rank()),
        neighbours_(d.neighbours(rank_)),
        peer_of_(static_cast<std::size_t>(d.ranks), -1),
        width_(d.particle_halo),
        inner_margin_(d.inner_margin()),
        rounding_margin_(d.rounding_margin()),
        report_(report) {
    for (std::size_t k = 0; k < neighbours_.size(); ++k) peer_of_[neighbours_[k]] = static_cast<int>(k);
    for (int r = 0; r < d.ranks; ++r) adjacent_.push_back(d.neighbours(r)), bounds_.push_back(d.bounds(r));
    for (const core::CueParams& cue : cues_) {  // the source's owner among them (its block is near)
      makers_.emplace_back();
      for (int r = 0; r < d.ranks; ++r)
        if (bounds_[static_cast<std::size_t>(r)].near(cue.position, d.halo)) makers_.back().push_back(r);
    }
  }

  // Collective: every particle, in id order, on rank 0.
  void snapshot(std::vector<Vec3>& pos, std::vector<std::uint16_t>& cue) const override {
    Bytes mine;
    mine.reserve(pos_.size() * sizeof(HaloParticle));
    for (std::size_t i = 0; i < pos_.size(); ++i) {
      const HaloParticle h{pos_[i], id_[i], source_[i]};
      append(mine, &h, 1);
    }
    std::vector<HaloParticle> all;
    std::vector<std::size_t> ends;
    for (const Bytes& from : comm_.gather(std::move(mine))) {
      for_each_record<HaloParticle>(from, [&](const HaloParticle& h) { all.push_back(h); });
      ends.push_back(all.size());
    }
    merge_runs(all, ends);
    pos.resize(all.size());
    cue.resize(all.size());
    for (std::size_t i = 0; i < all.size(); ++i) pos[i] = all[i].pos, cue[i] = all[i].cue;
  }

  // Collective: rank 0 receives the one-process state (particles in id order, the
  // estimate, which every rank holds whole).
  void save(EngineState& out) const override {
    Bytes mine;
    mine.reserve(pos_.size() * sizeof(Migrant));
    for (std::size_t i = 0; i < pos_.size(); ++i) {
      const Migrant m{pos_[i], ballistic_ ? vel_[i] : Vec3{0, 0, 0}, id_[i], source_[i]};
      append(mine, &m, 1);
    }
    std::vector<Migrant> all;
    std::vector<std::size_t> ends;
    for (const Bytes& from : comm_.gather(std::move(mine))) {
      for_each_record<Migrant>(from, [&](const Migrant& m) { all.push_back(m); });
      ends.push_back(all.size());
    }
    if (!comm_.root()) return;
    merge_runs(all, ends);
    out.next_particle_id = next_id_;
    out.particle_pos.resize(all.size());
    out.particle_vel.resize(ballistic_ ? all.size() : 0);
    out.particle_id.resize(all.size());
    out.particle_cue.resize(all.size());
    for (std::size_t i = 0; i < all.size(); ++i) {
      out.particle_pos[i] = all[i].pos;
      if (ballistic_) out.particle_vel[i] = all[i].vel;
      out.particle_id[i] = all[i].id;
      out.particle_cue[i] = all[i].cue;
    }
    out.grid = estimate_;
  }

  // Every rank reads the whole checkpoint and keeps the particles in its block. A state that
  // does not fit the scene is found alike on every rank (they read the same checkpoint): the
  // ranks end together, rank 0 saying why. (Copying it, one rank may run out of memory
  // alone: that error ends the job.)
  void load(const EngineState& in) override {
    on_every_rank([&] {
      check_checkpoint_particles(in, cues_.size(), ballistic_);
      if (use_estimate_ && in.grid.size() != estimate_.size())
        throw RunError("checkpoint: the particle estimate has " + std::to_string(in.grid.size()) +
                       " values, the scene needs " + std::to_string(estimate_.size()));
    });
    next_id_ = in.next_particle_id;
    pos_.clear(), vel_.clear(), id_.clear(), source_.clear();
    for (std::size_t i = 0; i < in.particle_pos.size(); ++i) {
      if (d_.owner(in.particle_pos[i]) != rank_) continue;
      pos_.push_back(in.particle_pos[i]);
      if (ballistic_) vel_.push_back(in.particle_vel[i]);
      id_.push_back(in.particle_id[i]);
      source_.push_back(in.particle_cue[i]);
    }
    if (use_estimate_) estimate_ = in.grid;
  }

  std::size_t bytes() const override {
    return state_bytes() + local_pos_.capacity() * 24 + local_source_.capacity() * 2 + local_slot_.capacity() * 4 +
           buffers_bytes();
  }

 private:
  std::size_t buffers_bytes() const {
    std::size_t n = arrivals_.capacity() * sizeof(Migrant) + halo_.capacity() * sizeof(HaloParticle);
    for (const auto* buffers : {&out_, &in_})
      for (const Bytes& b : *buffers) n += b.capacity();
    for (const auto& v : moving_) n += v.capacity() * sizeof(Migrant);
    for (const auto& v : near_) n += v.capacity() * sizeof(HaloParticle);
    n += self_halo_.capacity() * sizeof(HaloParticle);
    return n;
  }

  // Every rank counts every emission (the ids). The ranks whose blocks lie within the halo
  // of a source share its new particles by id (particle id goes to makers[id mod m]): a
  // particle's motion is a function of (seed, id, step, state), so any rank may make and
  // move it, and the migration that follows gives it to its owner. A source on a cut (the
  // centre of a domain cut in halves) would otherwise load its owner alone with every new
  // particle's first move.
  bool makes(std::uint64_t id, std::size_t cue) const override {
    const std::vector<int>& makers = makers_[cue];
    return makers[id % makers.size()] == rank_;
  }

  const char* settle_phase() const override { return "particles.migrate"; }  // the dead dropped in the same pass
  void settle() override { redistribute(use_grid_, &keep_); }

  void build_grid() override {
    build_local();
    grid_.build(geometry_, local_pos_, local_source_);
  }

  // The one-process grid after the collisions is read only by gathers.
  void collide() override {
    push_apart();
    redistribute(gathers_);
    if (gathers_) build_grid();
  }

  void reduce_deposits() override {
    if (comm_.size() > 1) comm_.allreduce(deposit_, Reduce::kSum);  // exact integer sums
  }

  void stepped() override { report_.owned_particles += pos_.size(); }

  // After a move or a collision push, in one neighbour exchange: the particles that left
  // this block go to their new owner and, when gathers read particles (with_halo), every
  // rank receives the particles within the halo width of its block that other ranks own.
  // A rank sends each neighbour the particles it gives that neighbour, then those it keeps
  // or gives to a third rank that lie near that neighbour (the sender knows every
  // position), so that halo and migration cost one round, not two. A particle whose new
  // owner, or a rank near it, is not adjacent to this block (a Brownian step has no bound)
  // goes to every rank by an all-gather, empty but for such rare jumps, and each rank
  // takes it as its own or as halo. Arrivals are merged into this rank's arrays by id; the
  // halo is kept for build_local(). After a move, `alive` is the move's survival flags: the
  // same pass drops the dead (the one-process compaction), so the arrays are read once.
  void redistribute(bool with_halo, const std::vector<std::uint8_t>* alive = nullptr) {
    const std::size_t peers = neighbours_.size();
    moving_.resize(peers), near_.resize(peers), out_.resize(peers);
    for (auto& v : moving_) v.clear();
    for (auto& v : near_) v.clear();
    Bytes far;
    self_halo_.clear();
    std::size_t w = 0;
    const Decomposition::Bounds& mine = bounds_[static_cast<std::size_t>(rank_)];
    for (std::size_t i = 0; i < pos_.size(); ++i) {
      if (alive && !(*alive)[i]) continue;
      const Vec3 x = pos_[i];
      // Most particles lie well inside the block: kept, near no other block.
      const bool inner = inner_margin_ > 0.0 && mine.inner(x, inner_margin_);
      const int owner = inner || mine.inner(x, rounding_margin_) ? rank_ : d_.owner(x);
      const HaloParticle h{x, id_[i], source_[i]};
      if (owner == rank_) {
        if (w != i) {
          pos_[w] = x, id_[w] = id_[i], source_[w] = source_[i];
          if (ballistic_) vel_[w] = vel_[i];
        }
        ++w;
        if (with_halo && !inner && mine.near_boundary(x, width_))
          for (std::size_t k = 0; k < peers; ++k)
            if (bounds_[static_cast<std::size_t>(neighbours_[k])].near(x, width_)) near_[k].push_back(h);
        continue;
      }
      const Migrant m{x, ballistic_ ? vel_[i] : Vec3{0, 0, 0}, id_[i], source_[i]};
      ++report_.migrated;
      // The ranks other than the owner that keep it in their halo, all adjacent to the
      // owner (the halo is narrower than a block); none when it is far from the owner's faces.
      near_ranks_.clear();
      if (with_halo && bounds_[static_cast<std::size_t>(owner)].near_boundary(x, width_))
        for (int r : adjacent_[static_cast<std::size_t>(owner)])
          if (bounds_[static_cast<std::size_t>(r)].near(x, width_)) near_ranks_.push_back(r);
      bool adjacent = peer_of_[static_cast<std::size_t>(owner)] >= 0;
      for (int r : near_ranks_) adjacent = adjacent && (r == rank_ || peer_of_[static_cast<std::size_t>(r)] >= 0);
      if (!adjacent) {
        append(far, &m, 1);
        ++report_.far_migrated;
        continue;
      }
      moving_[static_cast<std::size_t>(peer_of_[static_cast<std::size_t>(owner)])].push_back(m);
      for (int r : near_ranks_) {
        if (r == rank_)
          self_halo_.push_back(h);
        else
          near_[static_cast<std::size_t>(peer_of_[static_cast<std::size_t>(r)])].push_back(h);
      }
    }
    pos_.resize(w), id_.resize(w), source_.resize(w);
    if (ballistic_) vel_.resize(w);

    // To each neighbour: the migrants' count, the migrants, the halo particles.
    for (std::size_t k = 0; k < peers; ++k) {
      const std::uint64_t moving = moving_[k].size();
      out_[k].clear();
      append(out_[k], &moving, 1);
      append(out_[k], moving_[k]);
      append(out_[k], near_[k]);
      const std::size_t halo_bytes = near_[k].size() * sizeof(HaloParticle);
      if (halo_bytes) ++report_.halo.messages, report_.halo.message_bytes += halo_bytes;
    }
    comm_.exchange_into(out_, in_);

    std::vector<Migrant>& arrivals = arrivals_;
    std::vector<HaloParticle>& halo = halo_;
    arrivals.clear(), halo.clear(), arrival_ends_.clear(), halo_ends_.clear();
    for (const Bytes& from : in_) {
      std::uint64_t moving = 0;
      std::memcpy(&moving, from.data(), sizeof moving);
      const std::size_t split = sizeof moving + moving * sizeof(Migrant);
      append_records(from, sizeof moving, split, arrivals);
      append_records(from, split, from.size(), halo);
      arrival_ends_.push_back(arrivals.size()), halo_ends_.push_back(halo.size());
    }
    halo.insert(halo.end(), self_halo_.begin(), self_halo_.end());
    halo_ends_.push_back(halo.size());
    for (const Bytes& from : comm_.allgather(far)) {
      for_each_record<Migrant>(from, [&](const Migrant& m) {
        if (d_.owner(m.pos) == rank_)
          arrivals.push_back(m);
        else if (with_halo && mine.near(m.pos, width_))
          halo.push_back({m.pos, m.id, m.cue});
      });
      arrival_ends_.push_back(arrivals.size()), halo_ends_.push_back(halo.size());
    }
    if (!arrivals.empty()) {
      merge_runs(arrivals, arrival_ends_);
      merge_arrivals(arrivals);
    }
    if (with_halo) {
      merge_runs(halo, halo_ends_);
      report_.halo_particles += halo.size();
    }
  }

  // Records of type T in bytes [from, to) of a message, appended to v.
  template <class T>
  static void append_records(const Bytes& in, std::size_t from, std::size_t to, std::vector<T>& v) {
    const std::size_t at = v.size(), n = (to - from) / sizeof(T);
    v.resize(at + n);
    if (n) std::memcpy(static_cast<void*>(v.data() + at), in.data() + from, n * sizeof(T));
  }

  void merge_arrivals(const std::vector<Migrant>& in) {
    const std::size_t n = pos_.size() + in.size();
    pos_scratch_.resize(n), id_scratch_.resize(n), source_scratch_.resize(n);
    if (ballistic_) vel_scratch_.resize(n);
    std::size_t a = 0, b = 0;
    for (std::size_t o = 0; o < n; ++o) {
      if (b == in.size() || (a < pos_.size() && id_[a] < in[b].id)) {
        pos_scratch_[o] = pos_[a], id_scratch_[o] = id_[a], source_scratch_[o] = source_[a];
        if (ballistic_) vel_scratch_[o] = vel_[a];
        ++a;
      } else {
        pos_scratch_[o] = in[b].pos, id_scratch_[o] = in[b].id, source_scratch_[o] = in[b].cue;
        if (ballistic_) vel_scratch_[o] = in[b].vel;
        ++b;
      }
    }
    pos_.swap(pos_scratch_), id_.swap(id_scratch_), source_.swap(source_scratch_);
    if (ballistic_) vel_.swap(vel_scratch_);
  }

  // This rank's particles and the halo merged by id into the arrays the hashed grid is built
  // over; local_slot_[i] is particle i's slot there.
  void build_local() {
    const std::vector<HaloParticle>& halo = halo_;
    const std::size_t n = pos_.size() + halo.size();
    local_pos_.resize(n), local_source_.resize(n), local_slot_.resize(pos_.size());
    std::size_t a = 0, b = 0;
    for (std::size_t o = 0; o < n; ++o) {
      if (b == halo.size() || (a < pos_.size() && id_[a] < halo[b].id)) {
        local_pos_[o] = pos_[a], local_source_[o] = source_[a];
        local_slot_[a] = static_cast<std::uint32_t>(o);
        ++a;
      } else {
        local_pos_[o] = halo[b].pos, local_source_[o] = halo[b].cue;
        ++b;
      }
    }
  }

  // Jacobi, as in one process: every particle of this block reads the positions before the
  // collisions (its own and the halo's) and writes its own.
  void push_apart() {
    const core::HashGridView g = grid_.view(geometry_);
    tbb::parallel_for(std::size_t{0}, pos_.size(), [&](std::size_t i) {
      const std::uint32_t slot = local_slot_[i];
      const Vec3 x = local_pos_[slot];
      const Vec3 push = core::collision_push(slot, x, g, params_);
      pos_[i] = x + push;
      if (ballistic_) vel_[i] = vel_[i] + push / params_.dt;
    });
  }

  bool gathers_;  // growth cones gather the particles within r (not the estimate)
  const Decomposition& d_;
  Comm& comm_;
  int rank_;
  std::vector<int> neighbours_;
  std::vector<int> peer_of_;  // rank -> index in neighbours_, -1 when not adjacent
  double width_;              // LU: the halo's width
  double inner_margin_;       // LU: Bounds::inner's margin (the decomposition's halo, at least width_)
  double rounding_margin_;    // LU: within the block by more than this, a particle is this rank's
  FieldReport& report_;
  std::vector<Vec3> pos_scratch_, vel_scratch_;
  std::vector<std::uint64_t> id_scratch_;
  std::vector<std::uint16_t> source_scratch_;
  // This rank's and the halo's particles, in id order, which the hashed grid is built over.
  std::vector<Vec3> local_pos_;
  std::vector<std::uint16_t> local_source_;
  std::vector<std::uint32_t> local_slot_;
  // The exchanges' buffers, kept from step to step (their capacity is memory already
  // touched; fresh buffers each step made page faults the halo's largest cost).
  std::vector<std::vector<Migrant>> moving_;  // per neighbour: the migrants,
  std::vector<std::vector<HaloParticle>> near_;  // the halo particles,
  std::vector<Bytes> out_, in_;                  // the message; what it sent
  std::vector<Migrant> arrivals_;
  std::vector<HaloParticle> halo_, self_halo_;  // the halo; the particles this rank sent away but keeps near
  std::vector<std::size_t> arrival_ends_, halo_ends_;
  std::vector<int> near_ranks_;
  std::vector<std::vector<int>> adjacent_;  // every rank's neighbours
  std::vector<Decomposition::Bounds> bounds_;  // every rank's block
  std::vector<std::vector<int>> makers_;       // per cue: the ranks that make its particles, ascending
};

}  // namespace

std::unique_ptr<CueField> make_decomposed_grid_field(const Scene& scene, const std::vector<core::CueParams>& cues,
                                                     const Decomposition& d, Comm& comm, FieldReport& report);

std::unique_ptr<CueField> make_decomposed_field(const Scene& scene, const std::vector<core::CueParams>& cues,
                                                const Decomposition& d, Comm& comm, FieldReport& report) {
  if (!scene.uses_cues()) return nullptr;
  if (scene.cues.field == FieldKind::kParticles) {
    check_cue_fields(scene, cues);
    return std::make_unique<DecomposedParticleField>(scene, cues, d, comm, report);
  }
  if (scene.cues.field == FieldKind::kGrid) {
    check_cue_fields(scene, cues);
    return make_decomposed_grid_field(scene, cues, d, comm, report);
  }
  return make_reference_field(scene, cues);
}

}  // namespace axg::distributed

// The particle field over ranks (fields.hpp; docs/scaling.md §2.4). Each step runs the
// one-process stages on this rank's particles, in the one-process order, with the core
// functions of reference/src/fields/particle_field.cpp:
//   emit (the source's owner) -> move -> compact -> migrate
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
#include <stdexcept>
#include <string>

#include <tbb/parallel_for.h>

#include "axonguide/compact.hpp"
#include "axonguide/core/particles.hpp"
#include "axonguide/cue_setup.hpp"
#include "axonguide/distributed/fields.hpp"
#include "axonguide/error.hpp"
#include "axonguide/particle_stages.hpp"

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

class DecomposedParticleField final : public CueField {
 public:
  DecomposedParticleField(const Scene& scene, const std::vector<core::CueParams>& cues, const Decomposition& d,
                          Comm& comm, FieldReport& report)
      : seed_(scene.seed),
        cues_(cues),
        sense_(sense_params(scene)),
        params_(particle_params(scene)),
        geometry_(particle_hash_geometry(scene)),
        ballistic_(scene.cues.particles.motion == Motion::kBallistic),
        use_grid_(particle_grid_used(scene)),
        gathers_(sense_params(scene).sensing != core::ParticleSensing::kEstimate),
        use_estimate_(particle_estimate_used(scene)),
        mesh_(estimate_geometry(scene)),
        estimate_params_(estimate_params(scene)),
        d_(d),
        comm_(comm),
        rank_(comm.rank()),
        neighbours_(d.neighbours(rank_)),
        peer_of_(static_cast<std::size_t>(d.ranks), -1),
        width_(d.particle_halo),
        report_(report) {
    for (std::size_t k = 0; k < neighbours_.size(); ++k) peer_of_[neighbours_[k]] = static_cast<int>(k);
    grid_.reserve_starts(geometry_, use_grid_);
    if (use_estimate_) {
      estimate_.assign(2 * cues_.size() * mesh_.nodes, 0.0);
      deposit_.assign(estimate_.size(), 0);
    }
  }

  void advance(std::uint32_t step, PhaseTimes& times) override {
    {
      ScopedPhase p(times, step, "particles.emit");
      emit(step);
    }
    {
      ScopedPhase p(times, step, "particles.move");
      move_particles(seed_, step, cues_, params_, ballistic_, pos_, vel_, id_, source_, keep_);
    }
    {
      ScopedPhase p(times, step, "particles.compact");
      compact();
    }
    {
      ScopedPhase p(times, step, "particles.migrate");
      migrate();
    }
    if (use_grid_) {
      ScopedPhase p(times, step, "particles.grid");
      refresh_halo();
      grid_.build(geometry_, local_pos_, local_source_);
    }
    if (params_.collisions) {
      ScopedPhase p(times, step, "particles.collide");
      collide();
      migrate();
      if (gathers_) {  // the one-process grid after the collisions is read only by gathers
        refresh_halo();
        grid_.build(geometry_, local_pos_, local_source_);
      }
    }
    if (use_estimate_) {
      ScopedPhase p(times, step, "particles.estimate");
      deposit_particles(mesh_, cues_.size(), pos_, id_, source_, deposit_);  // this rank's particles
      if (comm_.size() > 1) comm_.allreduce(deposit_, Reduce::kSum);          // exact integer sums
      fold_estimate(step, estimate_params_, estimate_, deposit_);
    }
    report_.owned_particles += pos_.size();
  }

  void sample(Vec3 x, core::CueSample* samples, Vec3* pull) const override {
    core::sample_particle_field(x, grid_.view(geometry_), estimate_set(), cues_.data(), static_cast<int>(cues_.size()), sense_,
                                samples, pull);
  }

  // This rank's particles (the engine sums them over the ranks).
  std::uint64_t particles() const override { return pos_.size(); }

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

  // Every rank reads the whole checkpoint and keeps the particles in its block.
  void load(const EngineState& in) override {
    next_id_ = in.next_particle_id;
    pos_.clear(), vel_.clear(), id_.clear(), source_.clear();
    const bool with_vel = ballistic_ && in.particle_vel.size() == in.particle_pos.size();
    if (ballistic_ && !with_vel)
      throw std::runtime_error("checkpoint: the ballistic particles have no velocities");
    for (std::size_t i = 0; i < in.particle_pos.size(); ++i) {
      if (d_.owner(in.particle_pos[i]) != rank_) continue;
      pos_.push_back(in.particle_pos[i]);
      if (ballistic_) vel_.push_back(in.particle_vel[i]);
      id_.push_back(in.particle_id[i]);
      source_.push_back(in.particle_cue[i]);
    }
    if (use_estimate_) {
      if (in.grid.size() != estimate_.size())
        throw std::runtime_error("checkpoint: the particle estimate has " + std::to_string(in.grid.size()) +
                                 " values, the scene needs " + std::to_string(estimate_.size()));
      estimate_ = in.grid;
    }
  }

  std::size_t bytes() const override {
    return pos_.capacity() * 24 + vel_.capacity() * 24 + id_.capacity() * 8 + source_.capacity() * 2 +
           keep_.capacity() + local_pos_.capacity() * 24 + local_source_.capacity() * 2 + local_slot_.capacity() * 4 +
           grid_.bytes() + estimate_.capacity() * 8 + deposit_.capacity() * 8 + buffers_bytes();
  }

 private:
  std::size_t buffers_bytes() const {
    std::size_t n = arrivals_.capacity() * sizeof(Migrant) + halo_.capacity() * sizeof(HaloParticle);
    for (const Bytes& b : out_) n += b.capacity();
    for (const Bytes& b : in_) n += b.capacity();
    return n;
  }

  core::EstimateSet estimate_set() const {
    core::EstimateSet e = mesh_;
    e.c = estimate_.data();
    return e;
  }

  // Every rank counts every emission (the ids); the source's owner makes the particles.
  void emit(std::uint32_t step) {
    for (std::size_t k = 0; k < cues_.size(); ++k) {
      const std::uint32_t count = core::emitted_at(cues_[k].emission, step);
      const bool mine = d_.owner(cues_[k].position) == rank_;
      for (std::uint32_t j = 0; j < count; ++j) {
        const std::uint64_t id = next_id_++;
        if (!mine) continue;
        pos_.push_back(cues_[k].position);
        id_.push_back(id);
        source_.push_back(static_cast<std::uint16_t>(k));
        if (ballistic_) vel_.push_back(core::birth_velocity(seed_, id, step, params_));
      }
    }
  }

  void compact() {
    StableCompaction c;
    if (c.plan(keep_) == pos_.size()) return;
    c.apply(pos_, pos_scratch_);
    c.apply(id_, id_scratch_);
    c.apply(source_, source_scratch_);
    if (ballistic_) c.apply(vel_, vel_scratch_);
  }

  // Particles whose position left the block go to its owner: a neighbour by the neighbour
  // exchange, any other rank (a Brownian step has no bound) by an all-gather that is empty
  // but for such rare jumps. Arrivals are merged in by id.
  void migrate() {
    std::vector<Bytes>& out = out_;
    out.resize(neighbours_.size());
    for (Bytes& b : out) b.clear();
    Bytes far;
    std::size_t w = 0;
    for (std::size_t i = 0; i < pos_.size(); ++i) {
      const int owner = d_.owner(pos_[i]);
      if (owner == rank_) {
        if (w != i) {
          pos_[w] = pos_[i], id_[w] = id_[i], source_[w] = source_[i];
          if (ballistic_) vel_[w] = vel_[i];
        }
        ++w;
        continue;
      }
      const Migrant m{pos_[i], ballistic_ ? vel_[i] : Vec3{0, 0, 0}, id_[i], source_[i]};
      const int peer = peer_of_[static_cast<std::size_t>(owner)];
      append(peer >= 0 ? out[static_cast<std::size_t>(peer)] : far, &m, 1);
      ++report_.migrated;
    }
    pos_.resize(w), id_.resize(w), source_.resize(w);
    if (ballistic_) vel_.resize(w);
    std::vector<Migrant>& in = arrivals_;
    std::vector<std::size_t>& ends = ends_;
    in.clear(), ends.clear();
    comm_.exchange_into(out, in_);
    for (const Bytes& from : in_) {
      for_each_record<Migrant>(from, [&](const Migrant& m) { in.push_back(m); });
      ends.push_back(in.size());
    }
    for (const Bytes& from : comm_.allgather(far)) {
      for_each_record<Migrant>(from, [&](const Migrant& m) {
        if (d_.owner(m.pos) == rank_) in.push_back(m);
      });
      ends.push_back(in.size());
    }
    if (in.empty()) return;
    merge_runs(in, ends);
    merge_arrivals(in);
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

  // The neighbours' particles within the halo width of this block, merged with this rank's
  // by id into the arrays the hashed grid is built over; local_slot_[i] is particle i's
  // slot there.
  void refresh_halo() {
    const Traffic before = comm_.traffic();
    std::vector<Bytes>& out = out_;
    out.resize(neighbours_.size());
    for (Bytes& b : out) b.clear();
    for (std::size_t i = 0; i < pos_.size(); ++i) {
      if (!d_.near_boundary(rank_, pos_[i], width_)) continue;
      const HaloParticle h{pos_[i], id_[i], source_[i]};
      for (std::size_t k = 0; k < neighbours_.size(); ++k)
        if (d_.near(neighbours_[k], pos_[i], width_)) append(out[k], &h, 1);
    }
    std::vector<HaloParticle>& halo = halo_;
    std::vector<std::size_t>& ends = ends_;
    halo.clear(), ends.clear();
    comm_.exchange_into(out, in_);
    for (const Bytes& from : in_) {
      for_each_record<HaloParticle>(from, [&](const HaloParticle& h) { halo.push_back(h); });
      ends.push_back(halo.size());
    }
    merge_runs(halo, ends);
    report_.halo_particles += halo.size();
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
    const Traffic spent = comm_.traffic() - before;
    report_.halo.messages += spent.messages, report_.halo.message_bytes += spent.message_bytes;
    report_.halo.collectives += spent.collectives, report_.halo.collective_bytes += spent.collective_bytes;
  }

  // Jacobi, as in one process: every particle of this block reads the positions before the
  // collisions (its own and the halo's) and writes its own.
  void collide() {
    const core::HashGridView g = grid_.view(geometry_);
    tbb::parallel_for(std::size_t{0}, pos_.size(), [&](std::size_t i) {
      const std::uint32_t slot = local_slot_[i];
      const Vec3 x = local_pos_[slot];
      const Vec3 push = core::collision_push(slot, x, g, params_);
      pos_[i] = x + push;
      if (ballistic_) vel_[i] = vel_[i] + push / params_.dt;
    });
  }

  std::uint64_t seed_;
  std::vector<core::CueParams> cues_;
  core::SenseParams sense_;
  core::ParticleParams params_;
  HashGeometry geometry_;
  bool ballistic_;
  bool use_grid_;      // the hashed grid: collisions and gathers
  bool gathers_;       // growth cones gather the particles within r (not the estimate)
  bool use_estimate_;  // the estimate meshes
  core::EstimateSet mesh_;
  EstimateParams estimate_params_;
  const Decomposition& d_;
  Comm& comm_;
  int rank_;
  std::vector<int> neighbours_;
  std::vector<int> peer_of_;  // rank -> index in neighbours_, -1 when not adjacent
  double width_;              // LU: the halo's width
  FieldReport& report_;
  std::uint64_t next_id_ = 0;
  // This rank's particles, in id order.
  std::vector<Vec3> pos_, vel_;
  std::vector<std::uint64_t> id_;
  std::vector<std::uint16_t> source_;
  std::vector<std::uint8_t> keep_;
  std::vector<Vec3> pos_scratch_, vel_scratch_;
  std::vector<std::uint64_t> id_scratch_;
  std::vector<std::uint16_t> source_scratch_;
  // This rank's and the halo's particles, in id order, and the hashed grid over them.
  std::vector<Vec3> local_pos_;
  std::vector<std::uint16_t> local_source_;
  std::vector<std::uint32_t> local_slot_;
  ParticleHashGrid grid_;
  // The exchanges' buffers, kept from step to step (their capacity is memory already
  // touched; fresh buffers each step made page faults the halo's largest cost).
  std::vector<Bytes> out_, in_;
  std::vector<Migrant> arrivals_;
  std::vector<HaloParticle> halo_;
  std::vector<std::size_t> ends_;
  // The whole estimate (2 K meshes), the same on every rank.
  std::vector<double> estimate_;
  std::vector<std::uint64_t> deposit_;
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

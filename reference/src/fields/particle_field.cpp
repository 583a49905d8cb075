// The particle field on the CPU: emission, motion and death per particle, stable
// compaction, the estimate of C and grad C that growth cones read (core/estimate.hpp:
// fixed-point cloud-in-cell deposits and their moving average), and, where it is used,
// the hashed grid rebuilt by a stable radix sort on (bucket, id) for the soft-sphere
// collisions and the gathers of the particles within r. Particles are kept in id order
// (emission appends increasing ids; compaction is stable), so sorting by bucket alone
// sorts by (bucket, id).
#include <stdexcept>
#include <string>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "axonguide/support/compact.hpp"
#include "axonguide/core/particles.hpp"
#include "axonguide/model/estimate.hpp"
#include "axonguide/model/particles.hpp"
#include "axonguide/model/sensing.hpp"
#include "axonguide/fields/fields.hpp"
#include "axonguide/fields/particle_stages.hpp"

namespace axg {

namespace {

class ParticleField final : public CueField {
 public:
  ParticleField(const Scene& scene, const std::vector<core::CueParams>& cues)
      : seed_(scene.seed),
        cues_(cues),
        sense_(sense_params(scene)),
        params_(particle_params(scene)),
        geometry_(particle_hash_geometry(scene)),
        ballistic_(scene.cues.particles.motion == Motion::kBallistic),
        use_grid_(particle_grid_used(scene)),
        use_estimate_(particle_estimate_used(scene)),
        mesh_(estimate_geometry(scene)),
        estimate_params_(estimate_params(scene)) {
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
    if (use_grid_) {
      ScopedPhase p(times, step, "particles.grid");
      grid_.build(geometry_, pos_, source_);
    }
    if (params_.collisions) {
      ScopedPhase p(times, step, "particles.collide");
      collide();
      grid_.build(geometry_, pos_, source_);
    }
    if (use_estimate_) {
      ScopedPhase p(times, step, "particles.estimate");
      deposit_particles(mesh_, cues_.size(), pos_, id_, source_, deposit_);
      fold_estimate(step, estimate_params_, estimate_, deposit_);
    }
  }

  void sample(core::Vec3 x, core::CueSample* samples, core::Vec3* pull) const override {
    core::sample_particle_field(x, grid_.view(geometry_), estimate_set(), cues_.data(), static_cast<int>(cues_.size()), sense_, samples,
                                pull);
  }

  std::uint64_t particles() const override { return pos_.size(); }

  void snapshot(std::vector<core::Vec3>& pos, std::vector<std::uint16_t>& cue) const override {
    pos = pos_;
    cue = source_;
  }

  void save(EngineState& out) const override {
    out.next_particle_id = next_id_;
    out.particle_pos = pos_;
    out.particle_vel = vel_;
    out.particle_id = id_;
    out.particle_cue = source_;
    out.grid = estimate_;
  }

  // The hashed grid is rebuilt by the next step's advance, before anything reads it; the
  // estimate continues from its saved average (the deposits are per-step scratch).
  void load(const EngineState& in) override {
    check_checkpoint_particles(in, cues_.size(), ballistic_);
    next_id_ = in.next_particle_id;
    pos_ = in.particle_pos;
    vel_ = in.particle_vel;
    id_ = in.particle_id;
    source_ = in.particle_cue;
    if (use_estimate_) {
      if (in.grid.size() != estimate_.size())
        throw std::runtime_error("checkpoint: the particle estimate has " + std::to_string(in.grid.size()) +
                                 " values, the scene needs " + std::to_string(estimate_.size()));
      estimate_ = in.grid;
    }
  }

  std::size_t bytes() const override {
    return pos_.capacity() * 24 + vel_.capacity() * 24 + id_.capacity() * 8 + source_.capacity() * 2 +
           keep_.capacity() + grid_.bytes() + estimate_.capacity() * 8 + deposit_.capacity() * 8;
  }

 private:
  core::EstimateSet estimate_set() const {
    core::EstimateSet e = mesh_;
    e.c = estimate_.data();
    return e;
  }

  // Each cue emits floor(step Q) - floor((step-1) Q) particles at its position; ids are
  // consecutive in (cue, emission) order.
  void emit(std::uint32_t step) {
    for (std::size_t k = 0; k < cues_.size(); ++k) {
      const std::uint32_t count = core::emitted_at(cues_[k].emission, step);
      for (std::uint32_t j = 0; j < count; ++j) {
        const std::uint64_t id = next_id_++;
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

  // Jacobi: every particle reads the sorted positions and writes its own new position.
  void collide() {
    const core::HashGridView g = grid_.view(geometry_);
    tbb::parallel_for(std::size_t{0}, pos_.size(), [&](std::size_t k) {
      const std::uint32_t i = grid_.index[k];
      const core::Vec3 push = core::collision_push(i, grid_.sorted_pos[k], g, params_);
      pos_[i] = grid_.sorted_pos[k] + push;
      if (ballistic_) vel_[i] = vel_[i] + push / params_.dt;
    });
  }

  std::uint64_t seed_;
  std::vector<core::CueParams> cues_;
  core::SenseParams sense_;
  core::ParticleParams params_;
  HashGeometry geometry_;
  bool ballistic_;
  bool use_grid_;      // the hashed grid: collisions and the gathers of the particles within r
  bool use_estimate_;  // the estimate meshes
  core::EstimateSet mesh_;  // geometry (c unused)
  EstimateParams estimate_params_;
  std::uint64_t next_id_ = 0;
  // State, in id order.
  std::vector<core::Vec3> pos_, vel_;
  std::vector<std::uint64_t> id_;
  std::vector<std::uint16_t> source_;
  std::vector<std::uint8_t> keep_;
  // Scratch kept between steps, so that no step allocates.
  std::vector<core::Vec3> pos_scratch_, vel_scratch_;
  std::vector<std::uint64_t> id_scratch_;
  std::vector<std::uint16_t> source_scratch_;
  ParticleHashGrid grid_;
  // Estimate: 2 K meshes (cue-major, even half first) of averages and of this step's deposits.
  std::vector<double> estimate_;
  std::vector<std::uint64_t> deposit_;
};

}  // namespace

std::unique_ptr<CueField> make_particle_field(const Scene& scene, const std::vector<core::CueParams>& cues) {
  return std::make_unique<ParticleField>(scene, cues);
}

}  // namespace axg

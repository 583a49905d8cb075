// The particle field on the CPU: emission, motion and death per particle, stable
// compaction, the estimate of C and grad C that growth cones read (core/estimate.hpp:
// fixed-point cloud-in-cell deposits and their moving average), and, where it is used,
// the hashed grid rebuilt by a stable radix sort on (bucket, id) for the soft-sphere
// collisions and the gathers of the particles within r. Particles are kept in id order
// (emission appends increasing ids; compaction is stable), so sorting by bucket alone
// sorts by (bucket, id). The step's sequence is ParticleFieldStages' (particle_stages.hpp),
// which the field over ranks shares.
#include <stdexcept>
#include <string>

#include <tbb/parallel_for.h>

#include "axonguide/core/particles.hpp"
#include "axonguide/engine/state.hpp"
#include "axonguide/fields/fields.hpp"
#include "axonguide/fields/particle_stages.hpp"
#include "axonguide/support/compact.hpp"

namespace axg {

namespace {

class ParticleField final : public ParticleFieldStages {
 public:
  ParticleField(const Scene& scene, const std::vector<core::CueParams>& cues) : ParticleFieldStages(scene, cues) {}

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

  std::size_t bytes() const override { return state_bytes(); }

 private:
  const char* settle_phase() const override { return "particles.compact"; }

  void settle() override {
    StableCompaction c;
    if (c.plan(keep_) == pos_.size()) return;
    c.apply(pos_, pos_scratch_);
    c.apply(id_, id_scratch_);
    c.apply(source_, source_scratch_);
    if (ballistic_) c.apply(vel_, vel_scratch_);
  }

  void build_grid() override { grid_.build(geometry_, pos_, source_); }

  // Jacobi: every particle reads the sorted positions and writes its own new position; the
  // grid is rebuilt over the new positions.
  void collide() override {
    const core::HashGridView g = grid_.view(geometry_);
    tbb::parallel_for(std::size_t{0}, pos_.size(), [&](std::size_t k) {
      const std::uint32_t i = grid_.index[k];
      const core::Vec3 push = core::collision_push(i, grid_.sorted_pos[k], g, params_);
      pos_[i] = grid_.sorted_pos[k] + push;
      if (ballistic_) vel_[i] = vel_[i] + push / params_.dt;
    });
    grid_.build(geometry_, pos_, source_);
  }

  // Scratch kept between steps, so that no step allocates.
  std::vector<core::Vec3> pos_scratch_, vel_scratch_;
  std::vector<std::uint64_t> id_scratch_;
  std::vector<std::uint16_t> source_scratch_;
};

}  // namespace

std::unique_ptr<CueField> make_particle_field(const Scene& scene, const std::vector<core::CueParams>& cues) {
  return std::make_unique<ParticleField>(scene, cues);
}

}  // namespace axg

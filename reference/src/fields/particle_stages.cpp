#include "axonguide/fields/particle_stages.hpp"

#include <stdexcept>
#include <string>

#include <tbb/parallel_for.h>

#include "axonguide/engine/state.hpp"
#include "axonguide/scene/scene.hpp"

namespace axg {

void check_checkpoint_particles(const EngineState& in, std::size_t cues, bool ballistic) {
  if (ballistic && in.particle_vel.size() != in.particle_pos.size())
    throw std::runtime_error("checkpoint: the ballistic particles have no velocities");
  for (const std::uint16_t cue : in.particle_cue)
    if (cue >= cues)
      throw std::runtime_error("checkpoint: a particle of cue " + std::to_string(cue) + ", the scene has " +
                               std::to_string(cues));
}

void move_particles(std::uint64_t seed, std::uint32_t step, const std::vector<core::CueParams>& cues,
                    const core::ParticleParams& params, bool ballistic, std::vector<core::Vec3>& pos,
                    std::vector<core::Vec3>& vel, const std::vector<std::uint64_t>& id,
                    const std::vector<std::uint16_t>& source, std::vector<std::uint8_t>& keep) {
  keep.resize(pos.size());
  const core::Vec3 unused{0, 0, 0};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pos.size(), 4096), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      core::Vec3 v = ballistic ? vel[i] : unused;
      keep[i] = core::particle_step(seed, id[i], step, pos[i], v, cues[source[i]], params);
      if (ballistic) vel[i] = v;
    }
  });
}

void ParticleHashGrid::build(const HashGeometry& g, const std::vector<core::Vec3>& pos,
                             const std::vector<std::uint16_t>& source) {
  const std::size_t n = pos.size();
  const core::HashGridView geometry{g.origin, g.cell, g.dim, nullptr, nullptr, nullptr, nullptr};
  keys.resize(n);
  index.resize(n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    keys[i] = core::hash_of(pos[i], geometry);
    index[i] = static_cast<std::uint32_t>(i);
  });
  const auto buckets = static_cast<std::uint32_t>(g.buckets());
  stable_sort_by_key(keys, index, buckets - 1, scratch);
  cell_starts(keys, buckets, cell_start);
  sorted_pos.resize(n);
  sorted_source.resize(n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t k) {
    sorted_pos[k] = pos[index[k]];
    sorted_source[k] = source[index[k]];
  });
}

void deposit_particles(const core::EstimateSet& mesh, std::size_t cue_count, const std::vector<core::Vec3>& pos,
                       const std::vector<std::uint64_t>& id, const std::vector<std::uint16_t>& source,
                       std::vector<std::uint64_t>& deposit) {
  const std::size_t nodes = mesh.nodes;
  const auto meshes = static_cast<int>(2 * cue_count);
  tbb::parallel_for(0, meshes, [&](int m) {
    const auto cue = static_cast<std::uint16_t>(m / 2);
    const int half = m % 2;
    std::uint64_t* q = deposit.data() + static_cast<std::size_t>(m) * nodes;
    for (std::size_t i = 0; i < pos.size(); ++i) {
      if (source[i] != cue || core::estimate_half_of(id[i]) != half) continue;
      if (!core::cic_inside(pos[i], mesh.origin[cue], mesh.h, mesh.n)) continue;
      const core::CicDeposit d = core::cic_deposit(pos[i], mesh.origin[cue], mesh.h, mesh.n);
      for (int c = 0; c < 8; ++c) q[d.index[c]] += d.weight[c];
    }
  });
}

void fold_estimate(std::uint32_t step, const EstimateParams& params, std::vector<double>& estimate,
                   std::vector<std::uint64_t>& deposit) {
  const core::EstimateFold f = core::estimate_fold(step, params.beta, params.scale);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, estimate.size(), 16384),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i != r.end(); ++i) {
                        estimate[i] = core::fold_node(estimate[i], deposit[i], f);
                        deposit[i] = 0;
                      }
                    });
}

ParticleFieldStages::ParticleFieldStages(const Scene& scene, const std::vector<core::CueParams>& cues)
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

void ParticleFieldStages::advance(std::uint32_t step, PhaseTimes& times) {
  {
    ScopedPhase p(times, step, "particles.emit");
    emit(step);
  }
  {
    ScopedPhase p(times, step, "particles.move");
    move_particles(seed_, step, cues_, params_, ballistic_, pos_, vel_, id_, source_, keep_);
  }
  {
    ScopedPhase p(times, step, settle_phase());
    settle();
  }
  if (use_grid_) {
    ScopedPhase p(times, step, "particles.grid");
    build_grid();
  }
  if (params_.collisions) {
    ScopedPhase p(times, step, "particles.collide");
    collide();
  }
  if (use_estimate_) {
    ScopedPhase p(times, step, "particles.estimate");
    deposit_particles(mesh_, cues_.size(), pos_, id_, source_, deposit_);
    reduce_deposits();
    fold_estimate(step, estimate_params_, estimate_, deposit_);
  }
  stepped();
}

void ParticleFieldStages::sample(core::Vec3 x, core::CueSample* samples, core::Vec3* pull) const {
  core::sample_particle_field(x, grid_.view(geometry_), estimate_set(), cues_.data(), static_cast<int>(cues_.size()),
                              sense_, samples, pull);
}

void ParticleFieldStages::emit(std::uint32_t step) {
  for (std::size_t k = 0; k < cues_.size(); ++k) {
    const std::uint32_t count = core::emitted_at(cues_[k].emission, step);
    for (std::uint32_t j = 0; j < count; ++j) {
      const std::uint64_t id = next_id_++;
      if (!makes(id, k)) continue;
      pos_.push_back(cues_[k].position);
      id_.push_back(id);
      source_.push_back(static_cast<std::uint16_t>(k));
      if (ballistic_) vel_.push_back(core::birth_velocity(seed_, id, step, params_));
    }
  }
}

}  // namespace axg

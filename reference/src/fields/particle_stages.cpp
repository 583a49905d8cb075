#include "axonguide/fields/particle_stages.hpp"

#include <stdexcept>
#include <string>

#include <tbb/parallel_for.h>

#include "axonguide/engine/state.hpp"

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

}  // namespace axg

// The particle-field kernels: emission, motion and death, hashing, sorted copies,
// soft-sphere collisions, and the estimate's deposit and moving average.
// Part of the pipeline (../pipeline.inl); compiled once per build of it.
#pragma once

namespace axg::accel::AXG_ACCEL_NS {

struct EmitParticles {
  std::uint64_t first_id;
  std::size_t first_slot;
  const std::uint32_t* d_offsets;  // per cue: first new particle of the cue, then the total
  int cue_count;
  const core::CueParams* d_cues;
  bool ballistic;
  core::ParticleParams params;
  std::uint64_t seed;
  std::uint32_t step;
  Vec3* d_pos;
  Vec3* d_vel;
  std::uint64_t* d_id;
  std::uint16_t* d_source;
  AXG_HD void operator()(std::size_t e) const {
    int k = 0;
    while (k + 1 < cue_count && d_offsets[k + 1] <= e) ++k;
    const std::uint64_t id = first_id + e;
    const std::size_t i = first_slot + e;
    d_pos[i] = d_cues[k].position;
    d_id[i] = id;
    d_source[i] = static_cast<std::uint16_t>(k);
    if (ballistic) d_vel[i] = core::birth_velocity(seed, id, step, params);
  }
};

struct MoveParticles {
  const std::uint64_t* d_id;
  const std::uint16_t* d_source;
  const core::CueParams* d_cues;
  core::ParticleParams params;
  bool ballistic;
  std::uint64_t seed;
  std::uint32_t step;
  Vec3* d_pos;
  Vec3* d_vel;
  std::uint8_t* d_keep;
  AXG_HD void operator()(std::size_t i) const {
    Vec3 v = ballistic ? d_vel[i] : Vec3{0.0, 0.0, 0.0};
    d_keep[i] = core::particle_step(seed, d_id[i], step, d_pos[i], v, d_cues[d_source[i]], params) ? 1 : 0;
    if (ballistic) d_vel[i] = v;
  }
};

struct ParticleKeys {
  const Vec3* d_pos;
  core::HashGridView geometry;
  std::uint32_t* d_keys;
  std::uint32_t* d_index;
  AXG_HD void operator()(std::size_t i) const {
    d_keys[i] = core::hash_of(d_pos[i], geometry);
    d_index[i] = static_cast<std::uint32_t>(i);
  }
};

struct GatherParticles {
  const Vec3* d_pos;
  const std::uint16_t* d_source;
  const std::uint32_t* d_index;
  Vec3* d_sorted_pos;
  std::uint16_t* d_sorted_source;
  AXG_HD void operator()(std::size_t k) const {
    d_sorted_pos[k] = d_pos[d_index[k]];
    d_sorted_source[k] = d_source[d_index[k]];
  }
};

struct Collide {
  core::HashGridView grid;
  core::ParticleParams params;
  bool ballistic;
  Vec3* d_pos;
  Vec3* d_vel;
  AXG_HD void operator()(std::size_t k) const {
    const std::uint32_t i = grid.index[k];
    const Vec3 push = core::collision_push(i, grid.pos[k], grid, params);
    d_pos[i] = grid.pos[k] + push;
    if (ballistic) d_vel[i] = d_vel[i] + push / params.dt;
  }
};

struct IsKept {
  AXG_HD bool operator()(std::uint8_t k) const { return k != 0; }
};

// One particle's fixed-point cloud-in-cell weights into the deposit of its cue and half
// (integer atomics: the sums do not depend on the order).
struct DepositParticles {
  const Vec3* d_pos;
  const std::uint64_t* d_id;
  const std::uint16_t* d_source;
  core::EstimateSet mesh;  // geometry only
  std::uint64_t* d_deposit;
  AXG_HD void operator()(std::size_t i) const {
    const Vec3 origin = mesh.origin[d_source[i]];
    if (!core::cic_inside(d_pos[i], origin, mesh.h, mesh.n)) return;
    const core::CicDeposit d = core::cic_deposit(d_pos[i], origin, mesh.h, mesh.n);
    std::uint64_t* q = d_deposit + (2 * static_cast<std::size_t>(d_source[i]) +
                                    static_cast<std::size_t>(core::estimate_half_of(d_id[i]))) * mesh.nodes;
    for (int c = 0; c < 8; ++c) atomic_add(q + d.index[c], d.weight[c]);
  }
};

struct FoldEstimate {
  core::EstimateFold fold;
  double* d_estimate;
  std::uint64_t* d_deposit;
  AXG_HD void operator()(std::size_t i) const {
    d_estimate[i] = core::fold_node(d_estimate[i], d_deposit[i], fold);
    d_deposit[i] = 0;
  }
};

}  // namespace axg::accel::AXG_ACCEL_NS

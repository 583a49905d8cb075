#pragma once
// The particle field (SPEC §3.3, the report's method): per-particle motion, death, the
// hashed uniform grid, the soft-sphere collision gather and the sensing gather. Each is
// a pure function of (state, parameters, step, particle id) writing only its own slot.
#include <cstdint>

#include "cues.hpp"
#include "estimate.hpp"
#include "hd.hpp"
#include "random.hpp"
#include "sampler.hpp"
#include "sensing.hpp"
#include "types.hpp"
#include "vec3.hpp"

namespace axg::core {

struct ParticleParams {
  Motion motion;
  double dt;              // time per step
  double damping;         // ballistic: fraction of velocity lost per step
  double speed;           // ballistic: speed at birth, LU per time unit
  double bounds_radius;   // LU: particles leaving the domain die
  bool bounds_box;
  bool collisions;
  double contact2;        // (2 particle radius)^2, LU^2
  double contact;         // 2 particle radius, LU
  double stiffness;       // fraction of the overlap removed per step
};

// A hashed uniform grid: cell coordinates wrap modulo `dim` (a power of two), so distant
// cells may share a bucket; every gather checks real distances, so wrapping costs time,
// never correctness. Cells are at least as wide as every gather radius, so the 27
// buckets around a point hold every particle within that radius.
struct HashGridView {
  Vec3 origin;   // LU; (x - origin) >= 0 for every point inside the domain
  double cell;   // LU
  int dim;       // buckets per axis, a power of two >= 4
  const std::uint32_t* cell_start;  // dim^3 + 1
  const std::uint32_t* index;       // particle slots sorted by (bucket, id)
  const Vec3* pos;                  // positions in that order
  const std::uint16_t* source;      // cue index in that order
};

// floor((v - origin) / cell), clamped to +-2^30 so that the conversion and the +-1 of the
// neighbour loops stay within int (a domain that large only ever shares buckets).
AXG_HDI int hash_coord(double v, double origin, double cell) {
  double t = (v - origin) / cell;
  if (!(t > -1073741824.0)) t = -1073741824.0;
  if (t > 1073741824.0) t = 1073741824.0;
  int i = static_cast<int>(t);
  if (static_cast<double>(i) > t) --i;
  return i;
}

AXG_HDI std::uint32_t hash_bucket(int x, int y, int z, int dim) {
  const auto m = static_cast<std::uint32_t>(dim - 1);
  const auto d = static_cast<std::uint32_t>(dim);
  return ((static_cast<std::uint32_t>(z) & m) * d + (static_cast<std::uint32_t>(y) & m)) * d +
         (static_cast<std::uint32_t>(x) & m);
}

AXG_HDI std::uint32_t hash_of(Vec3 p, const HashGridView& g) {
  return hash_bucket(hash_coord(p.x, g.origin.x, g.cell), hash_coord(p.y, g.origin.y, g.cell),
                     hash_coord(p.z, g.origin.z, g.cell), g.dim);
}

// Number of particles cue `cue` emits at `step` (1-based): floor(step Q) - floor((step-1) Q),
// so a fractional emission rate is honoured exactly on average.
AXG_HDI std::uint32_t emitted_at(double emission, std::uint32_t step) {
  const double a = emission * static_cast<double>(step);
  const double b = emission * static_cast<double>(step - 1);
  return static_cast<std::uint32_t>(static_cast<std::uint64_t>(a) - static_cast<std::uint64_t>(b));
}

// Velocity at birth (ballistic motion): a uniform direction times the speed.
AXG_HDI Vec3 birth_velocity(std::uint64_t seed, std::uint64_t id, std::uint32_t step,
                            const ParticleParams& p) {
  Rng rng(seed, Stream::kParticleEmission, id, step);
  return p.speed * direction_trig(rng);
}

AXG_HDI bool outside_domain(Vec3 x, double radius, bool box) {
  if (box) return x.x > radius || x.x < -radius || x.y > radius || x.y < -radius || x.z > radius || x.z < -radius;
  return norm2(x) > radius * radius;
}

// One step of one particle, all from one stream (kParticleMotion, id, step): move
// (Brownian x += sigma xi with xi ~ N(0, I) from two polar pairs, or ballistic
// x += v dt, v *= 1 - damping), then the survival draw: death by decay when the next
// uniform is not below e^(-k dt), or by leaving the domain. Returns whether it lives.
AXG_HDI bool particle_step(std::uint64_t seed, std::uint64_t id, std::uint32_t step, Vec3& x, Vec3& v,
                           const CueParams& cue, const ParticleParams& p) {
  Rng rng(seed, Stream::kParticleMotion, id, step);
  if (p.motion == Motion::kBrownian) {
    double z0, z1, z2, unused;
    normal_pair(rng, &z0, &z1);
    normal_pair(rng, &z2, &unused);
    x = x + cue.sigma * Vec3{z0, z1, z2};
  } else {
    x = x + p.dt * v;
    v = (1.0 - p.damping) * v;
  }
  if (!(rng.uniform() < cue.survival)) return false;
  return !outside_domain(x, p.bounds_radius, p.bounds_box);
}

// Soft-sphere response: the displacement that removes `stiffness` of every overlap with
// the particles within 2 radii, summed over the 27 buckets in a fixed order (bucket z, y,
// x, then id). Only the particle's own slot is written by the caller (a gather).
AXG_HDI Vec3 collision_push(std::uint32_t self, Vec3 x, const HashGridView& g, const ParticleParams& p) {
  const int cx = hash_coord(x.x, g.origin.x, g.cell), cy = hash_coord(x.y, g.origin.y, g.cell),
            cz = hash_coord(x.z, g.origin.z, g.cell);
  Vec3 push{0.0, 0.0, 0.0};
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const std::uint32_t b = hash_bucket(cx + dx, cy + dy, cz + dz, g.dim);
        for (std::uint32_t k = g.cell_start[b]; k < g.cell_start[b + 1]; ++k) {
          if (g.index[k] == self) continue;
          const Vec3 d = x - g.pos[k];
          const double d2 = norm2(d);
          if (d2 >= p.contact2 || d2 == 0.0) continue;
          const double dist = std::sqrt(d2);
          push += (p.stiffness * 0.5 * (p.contact - dist) / dist) * d;
        }
      }
  return push;
}

// The particles within r of x, for molecule-resolved count sensing and the report's
// source_vector_sum (SPEC §3.4, docs/methods.md §2.6): for every cue, over its n particles
// within r, C = a n / V and the count dipole sum_j (x_j - x) / r (grad = grad_check); the
// pull sums unit vectors from each particle toward its source (the report's rule, which
// needs knowledge no growth cone has). Order: buckets z, y, x, then particle id, identical
// on every backend.
AXG_HDI void particle_gather(Vec3 x, const HashGridView& g, const CueParams* cues, int cue_count,
                             const SenseParams& p, CueSample* samples, Vec3* pull) {
  double count[kMaxCues];
  Vec3 dipole[kMaxCues];
  for (int k = 0; k < cue_count; ++k) {
    count[k] = 0.0;
    dipole[k] = {0.0, 0.0, 0.0};
    pull[k] = {0.0, 0.0, 0.0};
  }
  const bool source_pulls = p.sensing == ParticleSensing::kGather;
  const int cx = hash_coord(x.x, g.origin.x, g.cell), cy = hash_coord(x.y, g.origin.y, g.cell),
            cz = hash_coord(x.z, g.origin.z, g.cell);
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const std::uint32_t b = hash_bucket(cx + dx, cy + dy, cz + dz, g.dim);
        for (std::uint32_t k = g.cell_start[b]; k < g.cell_start[b + 1]; ++k) {
          const Vec3 d = g.pos[k] - x;
          const double d2 = norm2(d);
          if (d2 > p.radius2) continue;
          const int c = g.source[k];
          count[c] += 1.0;
          dipole[c] += d;
          if (source_pulls) {
            const Vec3 to_source = cues[c].position - g.pos[k];
            const double n = norm(to_source);
            if (n > 0.0) pull[c] += to_source / n;
          }
        }
      }
  for (int k = 0; k < cue_count; ++k) {
    const Vec3 dip = p.inv_radius * dipole[k];
    samples[k] = {p.c_per_particle * count[k], dip, dip};
    pull[k] = cues[k].sign * pull[k];
  }
}

// Every cue's sample and signed pull from the particle field: the estimate (its vector_sum
// pull is the signed unit vector of the estimated gradient, as for the exact fields), or
// the particles within r (molecule-resolved counts, source_vector_sum).
AXG_HDI void sample_particle_field(Vec3 x, const HashGridView& g, const EstimateSet& e, const CueParams* cues,
                                   int cue_count, const SenseParams& p, CueSample* samples, Vec3* pull) {
  if (p.sensing != ParticleSensing::kEstimate) {
    particle_gather(x, g, cues, cue_count, p, samples, pull);
    return;
  }
  for (int k = 0; k < cue_count; ++k) {
    samples[k] = p.ball ? estimate_ball_sample(x, e, k, p.radius) : estimate_sample(x, e, k);
    const CueSample both{samples[k].c, samples[k].grad + samples[k].grad_check, samples[k].grad};
    pull[k] = signed_unit_gradient(both, cues[k].sign);
  }
}

}  // namespace axg::core

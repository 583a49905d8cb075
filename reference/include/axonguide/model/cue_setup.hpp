#pragma once
// Scene-derived parameters of the cue stages, shared by every backend so that all of
// them hand identical numbers to the core/ functions. Source positions that the scene
// leaves to sampling are drawn here (host code, like placement).
#include <cstdint>
#include <string>
#include <vector>

#include "axonguide/core/cues.hpp"
#include "axonguide/core/estimate.hpp"
#include "axonguide/core/particles.hpp"
#include "axonguide/core/stencil.hpp"
#include "axonguide/scene/scene.hpp"

namespace axg {

// Every cue in index order: the scene's sources (in their canonical order), then the
// random ones. Throws InputError for an imposed linear profile that would go negative
// inside the domain.
std::vector<core::CueParams> make_cues(const Scene& scene);
void check_imposed_field(const Scene& scene, const std::vector<core::CueParams>& cues);

core::SenseParams sense_params(const Scene& scene);
core::SteerParams steer_params(const Scene& scene);
core::ParticleParams particle_params(const Scene& scene);

struct HashGeometry {
  core::Vec3 origin;
  double cell;
  int dim;
  std::size_t buckets() const { return static_cast<std::size_t>(dim) * dim * dim; }
};
// Buckets at least as wide as the sensing radius (and the collision diameter), at most
// 128 per axis (wrapping beyond), covering the domain without wrap when they can.
HashGeometry particle_hash_geometry(const Scene& scene);

struct GridGeometry3 {
  core::Vec3 origin;
  double h;
  int n;
  std::size_t nodes() const { return static_cast<std::size_t>(n) * n * n; }
};
// Nodes spanning the domain's cube [-R_b, R_b]^3 at the scene's spacing.
GridGeometry3 grid_field_geometry(const Scene& scene);

// Explicit sub-steps needed by cue k: ceil(dt (6 D / h^2 + k)) (at most kMaxSubsteps:
// check_cue_fields refuses scenes that need more).
inline constexpr double kMaxSubsteps = 1e6;
std::uint32_t explicit_substeps(const core::CueParams& cue, double h, double dt);
// Sub-steps per step of cue k's grid: cues.grid.substeps, or 1 (implicit) or the explicit
// stability limit when it is not given (check_cue_fields refuses fewer than the limit).
std::uint32_t grid_substeps(const Scene& scene, const core::CueParams& cue);

// The particle estimate's meshes (core/estimate.hpp): every cue's nodes at
// estimate_spacing() over the domain's cube or a cube about its source, and the weights of
// its moving average: beta = 1 - e^(-dt/tau) per
// step (1 for tau = 0), scale 2a / (h^3 2^32) per fixed-point unit of one half.
inline constexpr double kEstimateReach = 8.0;   // decay lengths about a source
core::EstimateSet estimate_geometry(const Scene& scene);  // c = nullptr
struct EstimateParams {
  double beta;
  double scale;
};
EstimateParams estimate_params(const Scene& scene);
// Whether the particle field keeps the estimate, and whether it needs the hashed grid of
// the particles within r (collisions, molecule-resolved counts, source_vector_sum).
bool particle_estimate_used(const Scene& scene);
bool particle_grid_used(const Scene& scene);

// Scene errors of a grid field or of the particle estimate's meshes, checked before
// anything is allocated and for every backend: more than kMaxGridNodes nodes per axis, a
// memory estimate above the machine's, an explicit scheme that needs sub-steps the scene
// forbids, more than kMaxSubsteps, or more than cues.grid.substeps gives. Throws
// InputError (exit 2) naming the key.
inline constexpr double kMaxGridNodes = 4096;
void check_cue_fields(const Scene& scene, const std::vector<core::CueParams>& cues);
core::StencilParams stencil_params(const GridGeometry3& g, const core::CueParams& cue, double dt, bool reflecting);

// The summary line of a grid field ("explicit grid, 109^3 nodes, h = 0.1, sub-steps per
// step: 14"); empty for other fields.
std::string grid_field_note(const Scene& scene, const std::vector<core::CueParams>& cues);

// Bytes the cue fields of this scene need (0 for direct guidance); checked against the
// machine before allocation (the grid field refuses with exit 2, as a scene error).
std::uint64_t estimate_cue_bytes(const Scene& scene);
// Typical steady particle count (for estimates and messages).
double expected_particles(const Scene& scene);

}  // namespace axg

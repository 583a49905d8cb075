#pragma once
// The grid field (SPEC §3.3; docs/methods.md §2.5): the keys cues.grid.{spacing, scheme,
// boundary, allow_substeps, substeps}, their reading, canonical form and defaults, the
// grid's geometry and sub-steps, and the parameters that core/stencil.hpp's explicit and
// implicit schemes get.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "axonguide/core/cues.hpp"
#include "axonguide/core/stencil.hpp"
#include "axonguide/core/types.hpp"
#include "axonguide/core/vec3.hpp"

namespace axg {

struct Scene;
class ObjectReader;

struct GridKeys {
  // Node spacing, length units; nullopt: grid_spacing()'s rule.
  std::optional<double> spacing;
  core::GridScheme scheme = core::GridScheme::kImplicit;
  core::GridBoundary boundary = core::GridBoundary::kAbsorbing;
  bool allow_substeps = true;  // explicit: sub-step to the stability limit, or refuse
  // Sub-steps per step; nullopt: 1 (implicit) or the explicit scheme's stability limit.
  std::optional<std::uint32_t> substeps;
};

void read_grid_keys(ObjectReader& cues, GridKeys& keys);
void write_grid_keys(const GridKeys& keys, nlohmann::json& cues);

// The node spacing: cues.grid.spacing, or min(r, lambda_min / 6, R_b / 4) with lambda_min the
// shortest decay length sqrt(D / k) of the cues (docs/methods.md §11.7: the cheapest spacing
// whose guidance is within 10 % and evidence error within 10 %).
inline constexpr double kGridPointsPerLambda = 6.0;
double grid_spacing(const Scene& scene);
// The spacing must leave the grid cells inside the domain.
void check_grid_spacing(const Scene& scene);
// Nodes per axis, memory, and the explicit scheme's sub-steps (check_cue_fields).
void check_grid(const Scene& scene, const std::vector<core::CueParams>& cues);

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
core::StencilParams stencil_params(const GridGeometry3& g, const core::CueParams& cue, double dt, bool reflecting);

// The ghost planes each side of a slab of a grid decomposed over ranks: what sensing at a
// tip of the slab reads beyond it. A point sample reads its cell and the centred differences,
// two planes, and a third covers rounding at a face; the count form's sensing ball reads
// r + h/2 about the tip (mesh_ball_sample), one plane more for rounding.
int grid_ghost_planes(const Scene& scene);

// The summary line of a grid field ("explicit grid, 109^3 nodes, h = 0.1, sub-steps per
// step: 14"); empty for other fields.
std::string grid_field_note(const Scene& scene, const std::vector<core::CueParams>& cues);

}  // namespace axg

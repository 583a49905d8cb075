#include "axonguide/model/stencil.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "axonguide/model/cues.hpp"
#include "axonguide/model/growth.hpp"
#include "axonguide/model/sensing.hpp"
#include "axonguide/scene/reader.hpp"
#include "axonguide/scene/scene.hpp"
#include "axonguide/support/error.hpp"

namespace axg {

void read_grid_keys(ObjectReader& r, GridKeys& q) {
  const nlohmann::json* g = r.take("grid");
  if (!g) return;
  ObjectReader rr(*g, "cues.grid");
  rr.optional_number("spacing", q.spacing, positive());
  rr.choice("scheme", q.scheme, {{"explicit", GridScheme::kExplicit}, {"implicit", GridScheme::kImplicit}});
  rr.choice("boundary", q.boundary, {{"absorbing", GridBoundary::kAbsorbing}, {"reflecting", GridBoundary::kReflecting}});
  rr.boolean("allow_substeps", q.allow_substeps);
  if (const nlohmann::json* m = rr.take("substeps")) {
    if (m->is_null()) q.substeps.reset();
    else q.substeps = static_cast<std::uint32_t>(ObjectReader::read_integer(*m, rr.path("substeps"), 1, 1000000));
  }
  rr.finish();
}

void write_grid_keys(const GridKeys& q, nlohmann::json& j) {
  nlohmann::json& g = j["grid"];
  g["spacing"] = q.spacing ? nlohmann::json(*q.spacing) : nlohmann::json(nullptr);
  g["scheme"] = name_of(q.scheme);
  g["boundary"] = name_of(q.boundary);
  g["allow_substeps"] = q.allow_substeps;
  if (q.substeps) g["substeps"] = *q.substeps;  // only when given
}

double grid_spacing(const Scene& s) {
  const auto& cues = s.cues;
  if (cues.grid.spacing) return *cues.grid.spacing;
  double lambda = HUGE_VAL;
  for (const Source& src : cues.sources)
    if (src.decay > 0) lambda = std::min(lambda, std::sqrt(src.diffusion / src.decay));
  if (cues.random_sources.count > 0 && cues.random_sources.decay > 0)
    lambda = std::min(lambda, std::sqrt(cues.random_sources.diffusion / cues.random_sources.decay));
  return std::min({s.guidance.sensing_radius, lambda / kGridPointsPerLambda, 0.25 * s.bounds_radius()});
}

void check_grid_spacing(const Scene& s) {
  const double rb = s.bounds_radius();
  if (s.cues.field == FieldKind::kGrid && grid_spacing(s) >= rb)
    throw InputError(fmt::format(
        "scene: cues.grid.spacing = {}: must be below the domain radius {} (the grid needs cells)", grid_spacing(s), rb));
}

void check_grid(const Scene& scene, const std::vector<core::CueParams>& cues) {
  const double half = scene.bounds_radius(), h = grid_spacing(scene);
  const double n = std::ceil(2.0 * half / h) + 1.0;
  if (n > kMaxGridNodes)
    throw InputError(fmt::format(
        "scene: cues.grid.spacing = {}: {:.3g} nodes per axis over the domain of half-width {}; at most {} are allowed",
        h, n, half, kMaxGridNodes));
  const std::uint64_t bytes = estimate_cue_bytes(scene);
  const std::uint64_t have = physical_memory_bytes();
  if (have != 0 && bytes > have)
    throw InputError(fmt::format(
        "scene: cues.grid.spacing = {}: {} cue grids of {}^3 nodes need an estimated {}, above this machine's {}; "
        "use a coarser spacing or fewer sources",
        h, cues.size(), static_cast<int>(n), human_bytes(static_cast<double>(bytes)), human_bytes(static_cast<double>(have))));
  if (scene.cues.grid.scheme != GridScheme::kExplicit) return;
  for (std::size_t k = 0; k < cues.size(); ++k) {
    const double need = scene.dt * (6.0 * cues[k].diffusion / (h * h) + cues[k].decay);
    if (need > kMaxSubsteps)
      throw InputError(fmt::format(
          "scene: cues.grid.scheme = \"explicit\": cue {} needs {:.3g} sub-steps per step (dt (6 D / h^2 + k) = {:.3g}), "
          "more than {:.0g}; use the \"implicit\" scheme or a coarser cues.grid.spacing",
          k, std::ceil(need), need, kMaxSubsteps));
    if (scene.cues.grid.substeps && *scene.cues.grid.substeps < explicit_substeps(cues[k], h, scene.dt))
      throw InputError(fmt::format(
          "scene: cues.grid.substeps = {}: the explicit scheme needs at least {} sub-steps per step for cue {} "
          "(dt (6 D / h^2 + k) = {:.4g}, the stability limit); give at least that, null, or the \"implicit\" scheme",
          *scene.cues.grid.substeps, explicit_substeps(cues[k], h, scene.dt), k, need));
    if (need > 1.0 && !scene.cues.grid.allow_substeps)
      throw InputError(fmt::format(
          "scene: cues.grid.allow_substeps = false, but the explicit scheme needs {} sub-steps per step for cue {}: "
          "dt (6 D / h^2 + k) = {:.4g} exceeds the stability limit 1 (h = {}, dt = {}); allow sub-steps, use a coarser "
          "cues.grid.spacing, or the \"implicit\" scheme",
          explicit_substeps(cues[k], h, scene.dt), k, need, h, scene.dt));
  }
}

GridGeometry3 grid_field_geometry(const Scene& scene) {
  GridGeometry3 g;
  g.h = grid_spacing(scene);
  const double half = scene.bounds_radius();
  // Clamped for the conversion; check_cue_fields refuses grids this large.
  g.n = static_cast<int>(std::min(std::ceil(2.0 * half / g.h) + 1.0, kMaxGridNodes + 1.0));
  const double o = -0.5 * (g.n - 1) * g.h;
  g.origin = {o, o, o};
  return g;
}

std::uint32_t explicit_substeps(const core::CueParams& cue, double h, double dt) {
  const double need = dt * (6.0 * cue.diffusion / (h * h) + cue.decay);
  return static_cast<std::uint32_t>(std::clamp(std::ceil(need), 1.0, kMaxSubsteps));
}

std::uint32_t grid_substeps(const Scene& scene, const core::CueParams& cue) {
  if (scene.cues.grid.substeps) return *scene.cues.grid.substeps;
  if (scene.cues.grid.scheme == GridScheme::kImplicit) return 1;
  return explicit_substeps(cue, grid_spacing(scene), scene.dt);
}

core::StencilParams stencil_params(const GridGeometry3& g, const core::CueParams& cue, double dt, bool reflecting) {
  core::StencilParams s{};
  s.n = g.n;
  s.lambda = cue.diffusion * dt / (g.h * g.h);
  s.decay_dt = cue.decay * dt;
  s.reflecting = reflecting;
  return s;
}

int grid_ghost_planes(const Scene& scene) {
  if (!sense_params(scene).ball) return 3;
  // The sample point lies up to half a step ahead of the tip (core/guide.hpp, sample_point),
  // the ball's points r beyond it, and their cells one plane further.
  const double h = grid_spacing(scene);
  const double reach = scene.guidance.sensing_radius + 0.5 * max_step_length(scene);
  return std::max(3, static_cast<int>(std::ceil(reach / h)) + 1);
}

std::string grid_field_note(const Scene& scene, const std::vector<core::CueParams>& cues) {
  if (!scene.uses_cues() || scene.cues.field != FieldKind::kGrid) return {};
  const GridGeometry3 g = grid_field_geometry(scene);
  std::uint32_t worst = 1;
  for (const auto& c : cues) worst = std::max(worst, grid_substeps(scene, c));
  if (scene.cues.grid.scheme == GridScheme::kImplicit)
    return worst == 1 ? fmt::format("implicit LOD grid, {}^3 nodes, h = {}", g.n, g.h)
                      : fmt::format("implicit LOD grid, {}^3 nodes, h = {}, sub-steps per step: {}", g.n, g.h, worst);
  return fmt::format("explicit grid, {}^3 nodes, h = {}, sub-steps per step: {}", g.n, g.h, worst);
}

}  // namespace axg

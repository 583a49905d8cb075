#include "axonguide/model/estimate.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "axonguide/core/pmath.hpp"
#include "axonguide/model/cues.hpp"
#include "axonguide/model/sensing.hpp"
#include "axonguide/model/steering.hpp"
#include "axonguide/scene/reader.hpp"
#include "axonguide/scene/scene.hpp"
#include "axonguide/support/error.hpp"

namespace axg {

void read_estimate_keys(ObjectReader& rr, EstimateKeys& q) {
  const nlohmann::json* e = rr.take("estimate");
  if (!e) return;
  ObjectReader er(*e, "cues.particles.estimate");
  er.optional_number("spacing", q.spacing, positive());
  er.optional_number("time", q.time, non_negative());
  er.finish();
}

void write_estimate_keys(const EstimateKeys& q, nlohmann::json& j) {
  // Only when given, so that older scenes keep their canonical form.
  if (q.spacing) j["estimate"]["spacing"] = *q.spacing;
  if (q.time) j["estimate"]["time"] = *q.time;
}

double estimate_spacing(const Scene& s) {
  return s.cues.particles.estimate.spacing.value_or(std::min(s.guidance.sensing_radius, 0.25 * s.bounds_radius()));
}

double estimate_time(const Scene& s) {
  if (s.cues.particles.estimate.time) return *s.cues.particles.estimate.time;
  const DecisionClock clock = decision_clock(s);
  return kEstimateIntervals * (clock.per_step ? s.dt : clock.time);
}

void check_estimate(const Scene& s) {
  const double rb = s.bounds_radius();
  if (s.cues.field == FieldKind::kParticles && estimate_spacing(s) >= rb)
    throw InputError(fmt::format(
        "scene: cues.particles.estimate.spacing = {}: must be below the domain radius {} (the estimate's mesh needs "
        "cells)",
        estimate_spacing(s), rb));
  if (!s.uses_cues() || s.cues.field != FieldKind::kParticles) return;
  const core::SenseParams p = sense_params(s);
  const double r = s.guidance.sensing_radius;
  if (p.sensing == core::ParticleSensing::kEstimate && estimate_spacing(s) > r)
    throw InputError(fmt::format("scene: cues.particles.estimate.spacing = {}: the estimate's mesh cannot resolve the "
                                 "sensing ball of radius r = {} (guidance.sensing_radius); the largest spacing "
                                 "allowed is r = {}",
                                 estimate_spacing(s), r, r),
                     "cues.particles.estimate.spacing", fmt::format("{}", estimate_spacing(s)),
                     fmt::format("at most {}", r));
  if (p.sensing == core::ParticleSensing::kMolecules && !decision_clock(s).per_step &&
      s.cues.particles.motion == Motion::kBrownian) {
    double fastest = 0.0;
    for (const Source& src : s.cues.sources) fastest = std::max(fastest, src.diffusion);
    const double crossing = r * r / (6.0 * fastest);
    if (fastest > 0.0 && s.dt > crossing)
      throw InputError(fmt::format("scene: dt = {}: a molecule-resolved count samples the sensing ball once per step, "
                                   "and a molecule of diffusion {} crosses a ball of radius {} in r^2 / (6 D) = {:.6g}: "
                                   "the sampling cannot resolve the ball; the largest dt allowed is {:.6g}",
                                   s.dt, fastest, r, crossing, crossing),
                       "dt", fmt::format("{}", s.dt), fmt::format("at most {:.6g}", crossing));
  }
}

void check_estimate_mesh(const Scene& scene, const std::vector<core::CueParams>& cues) {
  const core::EstimateSet g = estimate_geometry(scene);
  const double h = g.h;
  const double n = static_cast<double>(g.n);
  if (n > kMaxGridNodes)
    throw InputError(fmt::format(
        "scene: cues.particles.estimate.spacing = {}: more than {} nodes per axis over the estimate's cube of "
        "half-width {:.4g} (the domain's, or {} decay lengths about a source); use a coarser spacing",
        h, kMaxGridNodes, 0.5 * (n - 1) * h, kEstimateReach));
  const std::uint64_t bytes = estimate_cue_bytes(scene);
  const std::uint64_t have = physical_memory_bytes();
  if (have != 0 && bytes > have)
    throw InputError(fmt::format(
        "scene: cues.particles.estimate.spacing = {}: the particles and {} estimate meshes of {}^3 nodes need an "
        "estimated {}, above this machine's {}; use a coarser spacing",
        h, 2 * cues.size(), static_cast<int>(n), human_bytes(static_cast<double>(bytes)),
        human_bytes(static_cast<double>(have))));
}

core::EstimateSet estimate_geometry(const Scene& scene) {
  core::EstimateSet g{};
  g.h = estimate_spacing(scene);
  // Each cue's meshes span the domain's cube, or, when that is larger, a cube centred on
  // the cue's source kEstimateReach decay lengths wide (a steady profile falls as
  // e^(-r/lambda)/r, so beyond 8 lambda it is below 10^-4 of its value at lambda): a wide
  // domain does not cost meshes of its size. A cue without decay, and ballistic motion,
  // reach the whole domain. Every cue has the same n (the largest), its own origin.
  const double domain = scene.bounds_radius();
  const std::vector<core::CueParams> cues = scene.uses_cues() ? make_cues(scene) : std::vector<core::CueParams>{};
  std::vector<double> half(cues.size(), domain);
  double widest = cues.empty() ? domain : 0.0;
  for (std::size_t k = 0; k < cues.size(); ++k) {
    const bool bounded = cues[k].decay > 0 && scene.cues.particles.motion != Motion::kBallistic;
    if (bounded) half[k] = std::min(domain, kEstimateReach * std::sqrt(cues[k].diffusion / cues[k].decay) + 2.0 * g.h);
    widest = std::max(widest, half[k]);
  }
  // Clamped for the conversion; check_cue_fields refuses meshes this large.
  g.n = static_cast<int>(std::min(std::ceil(2.0 * widest / g.h) + 1.0, kMaxGridNodes + 1.0));
  g.nodes = static_cast<std::size_t>(g.n) * static_cast<std::size_t>(g.n) * static_cast<std::size_t>(g.n);
  const double o = -0.5 * (g.n - 1) * g.h;
  for (std::size_t k = 0; k < cues.size(); ++k) {
    const core::Vec3 centre = half[k] < domain ? cues[k].position : core::Vec3{0.0, 0.0, 0.0};
    g.origin[k] = {centre.x + o, centre.y + o, centre.z + o};
  }
  return g;
}

EstimateParams estimate_params(const Scene& scene) {
  const double tau = estimate_time(scene);
  const double h = estimate_spacing(scene);
  EstimateParams p;
  p.beta = tau > 0.0 ? 1.0 - core::pm::exp(-scene.dt / tau) : 1.0;
  if (!(p.beta > 0.0)) p.beta = 1.0 / 4294967296.0;  // tau beyond any run: the weights stay positive
  p.scale = 2.0 * scene.cues.particles.amount / (h * h * h * core::kDepositUnit);
  return p;
}

bool particle_estimate_used(const Scene& scene) {
  return scene.uses_cues() && scene.cues.field == FieldKind::kParticles &&
         sense_params(scene).sensing == core::ParticleSensing::kEstimate;
}

}  // namespace axg

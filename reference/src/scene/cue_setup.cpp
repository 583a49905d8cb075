#include "axonguide/model/cue_setup.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "axonguide/core/pmath.hpp"
#include "axonguide/core/random.hpp"
#include "axonguide/support/error.hpp"
#include "axonguide/placement/sampler_nd.hpp"

namespace axg {

namespace {

core::CueParams cue_from(const Source& s, core::Vec3 position, const Scene& scene) {
  core::CueParams c{};
  const double dt = scene.dt;
  c.position = position;
  c.sign = s.kind == CueKind::kAttractant ? 1.0 : -1.0;
  c.emission = s.emission;
  c.diffusion = s.diffusion;
  c.decay = s.decay;
  c.kd = s.kd;
  c.min_c = s.min_concentration;
  c.max_c = s.max_concentration;
  c.survival = core::pm::exp(-s.decay * dt);
  c.sigma = std::sqrt(2.0 * s.diffusion * dt);
  c.inv_lambda = std::sqrt(s.decay / s.diffusion);
  c.analytic_scale = scene.cues.particles.amount * s.emission / (dt * 4.0 * 3.141592653589793 * s.diffusion);
  return c;
}

// A source position inside the region (a sphere region's sources fill its ball).
core::Vec3 sample_source_position(const Scene& scene, std::uint64_t index) {
  core::Rng rng(scene.seed, core::Stream::kSourcePosition, index, 0);
  const auto shape = scene.neurons.shape == RegionShape::kSphere ? RegionShape::kBall : scene.neurons.shape;
  return sample_region_point(shape, scene.neurons.radius, scene.neurons.sampler, rng);
}

}  // namespace

std::vector<core::CueParams> make_cues(const Scene& scene) {
  std::vector<core::CueParams> cues;
  if (!scene.uses_cues()) return cues;
  std::uint64_t index = 0;
  for (const Source& s : canonical_sources(scene.cues.sources)) {
    cues.push_back(cue_from(s, s.position ? *s.position : sample_source_position(scene, index), scene));
    ++index;
  }
  const RandomSources& r = scene.cues.random_sources;
  for (std::uint32_t j = 0; j < r.count; ++j, ++index) {
    Source s;
    core::Rng kind(scene.seed, core::Stream::kSourceKind, index, 0);
    s.kind = kind.uniform() < r.attractant_fraction ? CueKind::kAttractant : CueKind::kRepellent;
    s.emission = r.emission;
    s.diffusion = r.diffusion;
    s.decay = r.decay;
    s.kd = r.kd;
    cues.push_back(cue_from(s, sample_source_position(scene, index), scene));
  }
  if (scene.cues.field == FieldKind::kImposed) check_imposed_field(scene, cues);
  return cues;
}

void check_imposed_field(const Scene& scene, const std::vector<core::CueParams>& cues) {
  const auto& q = scene.cues.imposed;
  if (q.profile != ImposedProfile::kLinear) return;
  // The profile exactly as the growth cones will sense it.
  const core::ImposedParams p = sense_params(scene).imposed;
  const double rate = p.rate;
  const double rb = scene.bounds_radius();
  const core::Vec3 d = p.direction;
  // The lowest value of (x - p).d over the domain: -R_b |d|_1 - p.d (box) or -R_b - p.d (ball).
  const double reach = scene.neurons.shape == RegionShape::kBox ? rb * (std::fabs(d.x) + std::fabs(d.y) + std::fabs(d.z)) : rb;
  for (std::size_t k = 0; k < cues.size(); ++k) {
    const double t_min = -reach - core::dot(cues[k].position, d);
    const double c_min = 1.0 + rate * t_min;
    if (c_min < 0.0)
      throw InputError(fmt::format(
          "scene: cues.imposed.steepness = {}: the linear profile of cue {} (C = {} at [{}, {}, {}]) falls to {:.4g} x "
          "that value {} length units down the gradient, inside the domain; a concentration cannot be negative: use a "
          "smaller steepness, a longer cues.imposed.reference_length, or the \"exponential\" profile",
          q.steepness, k, q.concentration, cues[k].position.x, cues[k].position.y, cues[k].position.z, c_min, -t_min));
  }
}

core::SenseParams sense_params(const Scene& scene) {
  core::SenseParams p{};
  const double r = scene.guidance.sensing_radius;
  const double volume = 4.0 / 3.0 * 3.141592653589793 * r * r * r;
  const double m = scene.molecule_amount();
  p.field = scene.cues.field;
  if (scene.guidance.model == GuidanceModel::kSourceVectorSum) p.sensing = core::ParticleSensing::kGather;
  else if (scene.cues.particles.molecules && scene.guidance.model == GuidanceModel::kSnr &&
           scene.guidance.noise == NoiseForm::kCount)
    p.sensing = core::ParticleSensing::kMolecules;
  else p.sensing = core::ParticleSensing::kEstimate;
  p.radius = r;
  p.radius2 = r * r;
  p.inv_radius = 1.0 / r;
  p.molecule = m;
  p.c_per_particle = scene.cues.particles.amount / volume;
  p.count_mean_scale = volume * r / (5.0 * m);
  p.count_var_scale = volume / (5.0 * m);
  p.cone_width = scene.guidance.growth_cone_width;
  p.analytic_rmin = 1e-3;
  const auto& q = scene.cues.imposed;
  p.imposed.profile = q.profile;
  p.imposed.direction = core::normalized(q.direction);
  p.imposed.c0 = q.concentration;
  const double s = q.steepness / 100.0;
  p.imposed.rate = q.profile == ImposedProfile::kLinear ? s / q.reference_length : core::pm::log(1.0 + s) / q.reference_length;
  return p;
}

core::SteerParams steer_params(const Scene& scene) {
  core::SteerParams p{};
  p.model = scene.guidance.model;
  double s, c;
  core::pm::sincos(scene.guidance.turn_angle, &s, &c);
  p.cos_turn = c;
  p.sin_turn = s;
  p.gain = scene.guidance.gain;
  p.vector_weight = scene.guidance.vector_weight;
  p.noise = scene.guidance.noise;
  p.modulation = scene.axons.growth_modulation;
  return p;
}

core::ParticleParams particle_params(const Scene& scene) {
  core::ParticleParams p{};
  const auto& q = scene.cues.particles;
  p.motion = q.motion;
  p.dt = scene.dt;
  p.damping = q.damping;
  p.bounds_radius = scene.bounds_radius();
  p.bounds_box = scene.neurons.shape == RegionShape::kBox;
  p.collisions = q.collisions;
  p.contact = 2.0 * q.radius;
  p.contact2 = p.contact * p.contact;
  p.stiffness = q.stiffness;
  // Default ballistic speed: the RMS displacement of Brownian motion in one step,
  // sqrt(6 D dt) / dt, for the smallest diffusion of the scene.
  double d_min = HUGE_VAL;
  for (const auto& c : make_cues(scene)) d_min = std::min(d_min, c.diffusion);
  p.speed = q.speed > 0 ? q.speed : (d_min < HUGE_VAL ? std::sqrt(6.0 * d_min * scene.dt) / scene.dt : 0.0);
  return p;
}

HashGeometry particle_hash_geometry(const Scene& scene) {
  HashGeometry g;
  g.cell = scene.guidance.sensing_radius;
  if (scene.cues.particles.collisions) g.cell = std::max(g.cell, 2.0 * scene.cues.particles.radius);
  const double half = scene.bounds_radius();
  const double span = 2.0 * half / g.cell + 2.0;
  g.dim = 4;
  while (g.dim < span && g.dim < 128) g.dim *= 2;
  g.origin = {-half - g.cell, -half - g.cell, -half - g.cell};
  return g;
}

GridGeometry3 grid_field_geometry(const Scene& scene) {
  GridGeometry3 g;
  g.h = scene.grid_spacing();
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
  return explicit_substeps(cue, scene.grid_spacing(), scene.dt);
}

core::EstimateSet estimate_geometry(const Scene& scene) {
  core::EstimateSet g{};
  g.h = scene.estimate_spacing();
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
  const double tau = scene.estimate_time();
  const double h = scene.estimate_spacing();
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

bool particle_grid_used(const Scene& scene) {
  return scene.uses_cues() && scene.cues.field == FieldKind::kParticles &&
         (scene.cues.particles.collisions || sense_params(scene).sensing != core::ParticleSensing::kEstimate);
}

void check_cue_fields(const Scene& scene, const std::vector<core::CueParams>& cues) {
  if (particle_estimate_used(scene)) {
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
  if (!scene.uses_cues() || scene.cues.field != FieldKind::kGrid) return;
  const double half = scene.bounds_radius(), h = scene.grid_spacing();
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

core::StencilParams stencil_params(const GridGeometry3& g, const core::CueParams& cue, double dt, bool reflecting) {
  core::StencilParams s{};
  s.n = g.n;
  s.lambda = cue.diffusion * dt / (g.h * g.h);
  s.decay_dt = cue.decay * dt;
  s.reflecting = reflecting;
  return s;
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

double expected_particles(const Scene& scene) {
  double total = 0;
  for (const auto& c : make_cues(scene)) {
    const double horizon = static_cast<double>(scene.steps) + static_cast<double>(scene.cues.warmup_steps);
    const double lifetime = c.survival < 1.0 ? 1.0 / (1.0 - c.survival) : horizon;
    total += c.emission * std::min(lifetime, horizon);
  }
  return total;
}

std::uint64_t estimate_cue_bytes(const Scene& scene) {
  if (!scene.uses_cues()) return 0;
  const double cues = static_cast<double>(scene.source_count());
  switch (scene.cues.field) {
    case FieldKind::kAnalytic:
    case FieldKind::kImposed: return 0;
    case FieldKind::kGrid: {
      const GridGeometry3 g = grid_field_geometry(scene);
      const double buffers = scene.cues.grid.scheme == GridScheme::kExplicit ? 2.0 : 1.0;
      const double b = cues * buffers * static_cast<double>(g.nodes()) * 8.0;
      return b >= 1.8e19 ? UINT64_MAX : static_cast<std::uint64_t>(b);
    }
    case FieldKind::kParticles: {
      // state (position, velocity, id, source, flags) and grid (keys, index, sorted copies)
      const double per = 24 + 24 + 8 + 2 + 4 + 4 * 4 + 24 + 2;
      const HashGeometry h = particle_hash_geometry(scene);
      // The estimate: per cue two halves of n^3 nodes, a double and a 64-bit deposit each.
      const double mesh = particle_estimate_used(scene) ? cues * 2.0 * static_cast<double>(estimate_geometry(scene).nodes) * 16.0 : 0.0;
      const double b = expected_particles(scene) * per * 2 + static_cast<double>(h.buckets()) * 4.0 + mesh;
      return b >= 1.8e19 ? UINT64_MAX : static_cast<std::uint64_t>(b);
    }
  }
  return 0;
}

}  // namespace axg

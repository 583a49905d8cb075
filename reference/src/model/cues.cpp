#include "axonguide/model/cues.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>

#include <fmt/format.h>

#include "axonguide/core/pmath.hpp"
#include "axonguide/core/random.hpp"
#include "axonguide/model/estimate.hpp"
#include "axonguide/model/particles.hpp"
#include "axonguide/model/stencil.hpp"
#include "axonguide/model/steering.hpp"
#include "axonguide/placement/sampler_nd.hpp"
#include "axonguide/scene/reader.hpp"
#include "axonguide/scene/scene.hpp"
#include "axonguide/support/error.hpp"

namespace axg {

using nlohmann::json;

namespace {

void read_source_common(ObjectReader& r, double& emission, double& diffusion, double& decay, double& kd) {
  // Particles per step; 2^31 keeps every per-step count and particle id exact.
  r.number("emission", emission, closed(0, 2147483648.0));
  r.number("diffusion", diffusion, positive());
  r.number("decay", decay, non_negative());
  r.number("kd", kd, positive());
}

Source read_source(const json& j, const std::string& path) {
  Source s;
  ObjectReader r(j, path);
  r.choice("kind", s.kind, {{"attractant", CueKind::kAttractant}, {"repellent", CueKind::kRepellent}});
  if (const json* p = r.take("position")) {
    if (p->is_null()) s.position.reset();
    else s.position = read_position(*p, r.path("position"));
  }
  read_source_common(r, s.emission, s.diffusion, s.decay, s.kd);
  r.number("min_concentration", s.min_concentration, non_negative());
  r.number("max_concentration", s.max_concentration, positive());
  r.finish();
  if (s.min_concentration > s.max_concentration)
    throw InputError(fmt::format(
        "scene: {}.min_concentration = {} is above {}.max_concentration = {}: min must be <= max",
        path, s.min_concentration, path, s.max_concentration));
  return s;
}

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
  c.dipole_variance = count_dipole_variance(scene, s.diffusion);
  return c;
}

// A source position inside the region (a sphere region's sources fill its ball).
core::Vec3 sample_source_position(const Scene& scene, std::uint64_t index) {
  core::Rng rng(scene.seed, core::Stream::kSourcePosition, index, 0);
  const auto shape = scene.neurons.shape == RegionShape::kSphere ? RegionShape::kBall : scene.neurons.shape;
  return sample_region_point(shape, scene.neurons.radius, scene.neurons.sampler, rng);
}

}  // namespace

void read_cue_keys(ObjectReader& r, CueKeys& c) {
  r.choice("field", c.field, {{"particles", FieldKind::kParticles}, {"grid", FieldKind::kGrid},
                              {"analytic", FieldKind::kAnalytic}, {"imposed", FieldKind::kImposed}});
  r.integer("warmup_steps", c.warmup_steps, 0, 1000000);
  if (const json* src = r.take("sources")) {
    if (!src->is_array()) fail_key("cues.sources", *src, "must be an array of source objects");
    c.sources.clear();
    for (std::size_t k = 0; k < src->size(); ++k)
      c.sources.push_back(read_source((*src)[k], fmt::format("cues.sources[{}]", k)));
  }
  if (const json* rs = r.take("random_sources")) {
    ObjectReader rr(*rs, "cues.random_sources");
    auto& q = c.random_sources;
    rr.integer("count", q.count, 0, 1000000);
    rr.number("attractant_fraction", q.attractant_fraction, closed(0, 1));
    read_source_common(rr, q.emission, q.diffusion, q.decay, q.kd);
    rr.finish();
  }
}

void read_imposed_keys(ObjectReader& r, ImposedKeys& q) {
  const json* g = r.take("imposed");
  if (!g) return;
  ObjectReader rr(*g, "cues.imposed");
  rr.choice("profile", q.profile, {{"linear", ImposedProfile::kLinear}, {"exponential", ImposedProfile::kExponential}});
  if (const json* d = rr.take("direction")) {
    const core::Vec3 v = read_position(*d, "cues.imposed.direction");
    const double n = core::norm(v);
    if (!(n > 0.0) || !(n < HUGE_VAL)) fail_key("cues.imposed.direction", *d, "must be a non-zero finite vector [x, y, z]");
    q.direction = v;  // as written (the canonical form reads back unchanged); normalised where used
  }
  // Up to +100 % per reference length for a linear profile, and far more for an
  // exponential one; 0 is the no-gradient control.
  rr.number("steepness", q.steepness, closed(0, 1e6));
  rr.number("reference_length", q.reference_length, positive());
  rr.number("concentration", q.concentration, positive());
  rr.finish();
}

void write_cue_keys(const CueKeys& c, json& j) {
  auto source_json = [](const Source& src) {
    json s;
    s["kind"] = name_of(src.kind);
    s["position"] = src.position ? json::array({src.position->x, src.position->y, src.position->z}) : json(nullptr);
    s["emission"] = src.emission;
    s["diffusion"] = src.diffusion;
    s["decay"] = src.decay;
    s["kd"] = src.kd;
    s["min_concentration"] = src.min_concentration;
    s["max_concentration"] = src.max_concentration;
    return s;
  };
  json sources = json::array();
  for (const auto& src : canonical_sources(c.sources)) sources.push_back(source_json(src));
  const auto& rs = c.random_sources;
  j["field"] = name_of(c.field);
  j["warmup_steps"] = c.warmup_steps;
  j["sources"] = sources;
  j["random_sources"] = {{"count", rs.count}, {"attractant_fraction", rs.attractant_fraction},
                         {"emission", rs.emission}, {"diffusion", rs.diffusion},
                         {"decay", rs.decay}, {"kd", rs.kd}};
  const auto& q = c.imposed;
  j["imposed"] = {{"profile", name_of(q.profile)},
                  {"direction", json::array({q.direction.x, q.direction.y, q.direction.z})},
                  {"steepness", q.steepness}, {"reference_length", q.reference_length},
                  {"concentration", q.concentration}};
}

void check_cues(const Scene& s) {
  const auto& n = s.neurons;
  if (s.source_count() > static_cast<std::size_t>(core::kMaxCues))
    throw InputError(fmt::format(
        "scene: cues.sources has {} and cues.random_sources.count {}: at most {} cue sources in all",
        s.cues.sources.size(), s.cues.random_sources.count, core::kMaxCues));
  const double rb = s.bounds_radius();
  for (std::size_t k = 0; k < s.cues.sources.size(); ++k) {
    const auto& p = s.cues.sources[k].position;
    if (!p) continue;
    const bool inside = n.shape == RegionShape::kBox
                            ? std::fabs(p->x) <= rb && std::fabs(p->y) <= rb && std::fabs(p->z) <= rb
                            : core::norm(*p) <= rb;
    if (!inside)
      throw InputError(fmt::format(
          "scene: cues.sources[{}].position = [{}, {}, {}]: must lie inside the domain ({} of {} {})",
          k, p->x, p->y, p->z, n.shape == RegionShape::kBox ? "box" : "ball",
          n.shape == RegionShape::kBox ? "half-edge" : "radius", rb));
  }
}

std::vector<Source> canonical_sources(std::vector<Source> sources) {
  auto key = [](const Source& s) {
    const core::Vec3 p = s.position.value_or(core::Vec3{0.0, 0.0, 0.0});
    return std::make_tuple(static_cast<int>(s.kind), s.position.has_value(), p.x, p.y, p.z, s.emission, s.diffusion,
                           s.decay, s.kd, s.min_concentration, s.max_concentration);
  };
  std::stable_sort(sources.begin(), sources.end(), [&](const Source& a, const Source& b) { return key(a) < key(b); });
  return sources;
}

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

core::ImposedParams imposed_params(const Scene& scene) {
  core::ImposedParams p{};
  const auto& q = scene.cues.imposed;
  p.profile = q.profile;
  p.direction = core::normalized(q.direction);
  p.c0 = q.concentration;
  const double s = q.steepness / 100.0;
  p.rate = q.profile == ImposedProfile::kLinear ? s / q.reference_length : core::pm::log(1.0 + s) / q.reference_length;
  return p;
}

void check_imposed_field(const Scene& scene, const std::vector<core::CueParams>& cues) {
  const auto& q = scene.cues.imposed;
  if (q.profile != ImposedProfile::kLinear) return;
  // The profile exactly as the growth cones will sense it.
  const core::ImposedParams p = imposed_params(scene);
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

void check_cue_fields(const Scene& scene, const std::vector<core::CueParams>& cues) {
  if (particle_estimate_used(scene)) check_estimate_mesh(scene, cues);
  if (!scene.uses_cues() || scene.cues.field != FieldKind::kGrid) return;
  check_grid(scene, cues);
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
      const double mesh =
          particle_estimate_used(scene) ? cues * 2.0 * static_cast<double>(estimate_geometry(scene).nodes) * 16.0 : 0.0;
      const double b = expected_particles(scene) * per * 2 + static_cast<double>(h.buckets()) * 4.0 + mesh;
      return b >= 1.8e19 ? UINT64_MAX : static_cast<std::uint64_t>(b);
    }
  }
  return 0;
}

}  // namespace axg

#include "axonguide/model/particles.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "axonguide/model/cues.hpp"
#include "axonguide/model/sensing.hpp"
#include "axonguide/scene/reader.hpp"
#include "axonguide/scene/scene.hpp"
#include "axonguide/support/error.hpp"

namespace axg {

bool read_particle_keys(ObjectReader& rr, ParticleKeys& q) {
  const bool amount_given = rr.take("amount") != nullptr;
  rr.number("amount", q.amount, positive());
  rr.boolean("molecules", q.molecules);
  read_estimate_keys(rr, q.estimate);
  rr.choice("motion", q.motion, {{"brownian", Motion::kBrownian}, {"ballistic", Motion::kBallistic}});
  rr.boolean("collisions", q.collisions);
  rr.number("speed", q.speed, non_negative());
  rr.number("damping", q.damping, closed(0, 1));
  rr.number("radius", q.radius, positive());
  rr.number("stiffness", q.stiffness, closed(0, 1));
  return amount_given;
}

void write_particle_keys(const ParticleKeys& q, nlohmann::json& j) {
  j["amount"] = q.amount;
  j["motion"] = name_of(q.motion);
  j["collisions"] = q.collisions;
  j["speed"] = q.speed;
  j["damping"] = q.damping;
  j["radius"] = q.radius;
  j["stiffness"] = q.stiffness;
  if (q.molecules) j["molecules"] = true;  // only when given
  write_estimate_keys(q.estimate, j);
}

void resolve_molecules(Scene& s, bool amount_given) {
  auto& q = s.cues.particles;
  if (!q.molecules) return;
  const double m = s.molecule_amount();
  if (amount_given && q.amount != m)
    throw InputError(fmt::format(
        "scene: cues.particles.amount = {} with cues.particles.molecules = true: a molecule-resolved particle is "
        "one molecule, {:.6g} (concentration x length^3 in this scene's units); remove the amount or make it equal",
        q.amount, m));
  q.amount = m;
}

void check_particles(const Scene& s, std::vector<std::string>& warnings) {
  if (s.cues.particles.molecules && s.cues.field != FieldKind::kParticles)
    warnings.push_back(fmt::format("cues.particles.molecules is true but cues.field is \"{}\": it applies to the "
                                   "particle field only and is ignored",
                                   name_of(s.cues.field)));
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

bool particle_grid_used(const Scene& scene) {
  return scene.uses_cues() && scene.cues.field == FieldKind::kParticles &&
         (scene.cues.particles.collisions || sense_params(scene).sensing != core::ParticleSensing::kEstimate);
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

}  // namespace axg

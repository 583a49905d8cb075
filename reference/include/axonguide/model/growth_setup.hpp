#pragma once
// Scene-derived parameters of the growth stage, shared by every backend so that both
// hand identical numbers to core::grow_axon.
#include "axonguide/engine/cell_grid.hpp"
#include <cmath>

#include "axonguide/core/growth.hpp"
#include "axonguide/core/pmath.hpp"
#include "axonguide/core/wander.hpp"
#include "axonguide/scene/scene.hpp"
#include "axonguide/model/signalling_setup.hpp"

namespace axg {

inline core::GrowthParams growth_params(const Scene& s) {
  core::GrowthParams g{};
  g.step_length = s.axons.step_length;
  g.contact_radius = s.neurons.soma_radius + s.axons.contact_distance;
  g.contact_radius2 = g.contact_radius * g.contact_radius;
  g.bounds_radius = s.bounds_radius();
  g.bounds_box = s.neurons.shape == RegionShape::kBox;
  g.rule = s.axons.contact;
  return g;
}

inline core::WanderParams wander_params(const Scene& s) {
  core::WanderParams w{};
  w.on = s.axons.persistence_length.has_value();
  if (!w.on) return w;
  w.inv_persistence = 1.0 / *s.axons.persistence_length;
  w.cos_step = core::pm::exp(-s.axons.step_length * w.inv_persistence);
  w.sin_step = std::sqrt(1.0 - w.cos_step * w.cos_step);
  return w;
}

// Growth-rate modulation gives every axon its own step length (stored per axon).
inline bool modulates_growth(const Scene& s) { return s.axons.growth_modulation > 0.0 && s.uses_cues(); }

// The longest step any axon can take, LU: l0, or l0 (1 + m) with modulation (the bound of
// core::modulated_step); what a step's contact search can reach beyond its tip.
inline double max_step_length(const Scene& s) {
  if (s.signalling()) return signalling_max_step(s);
  return modulates_growth(s) ? s.axons.step_length * (1.0 + s.axons.growth_modulation) : s.axons.step_length;
}

inline core::Vec3 axon_start(core::Vec3 soma, core::Vec3 heading, const Scene& s) {
  return core::axon_start(soma, heading, s.neurons.soma_radius);
}

// The soma grid covers the region; cells are at least one contact diameter wide and
// about one per neuron, so a step visits a handful of cells.
inline GridGeometry soma_grid_geometry(const Scene& s) {
  const double contact = s.neurons.soma_radius + s.axons.contact_distance;
  return cube_geometry(s.neurons.radius + contact, 2.0 * contact,
                       static_cast<double>(s.neurons.count));
}

}  // namespace axg

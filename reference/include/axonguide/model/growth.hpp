#pragma once
// Growth (SPEC §3.2; docs/methods.md §2.2): the keys axons.{step_length, growth_speed,
// contact_distance, contact, bounds_radius}, their reading and canonical form, and the
// parameters that core/growth.hpp's step gets (the move, contact and bounds).
#include <optional>

#include <nlohmann/json.hpp>

#include "axonguide/core/growth.hpp"
#include "axonguide/core/types.hpp"

namespace axg {

struct Scene;
class ObjectReader;

struct GrowthKeys {
  double step_length = 0.35;           // length units per step (growth_speed dt when that is given)
  std::optional<double> growth_speed;  // length units per time unit; nullopt: step_length rules
  double contact_distance = 0.05;
  core::ContactRule contact = core::ContactRule::kSwept;
  std::optional<double> bounds_radius;  // nullopt: the region's radius
};

// axons.{step_length, growth_speed} (the step length is growth_speed x dt when that is
// given), contact_distance, contact, bounds_radius.
void read_growth_keys(ObjectReader& axons, GrowthKeys& keys, double dt);
void write_growth_keys(const GrowthKeys& keys, nlohmann::json& axons);

core::GrowthParams growth_params(const Scene& s);

// The longest step any axon can take, LU: l0, or l0 (1 + m) with modulation (the bound of
// core::modulated_step), or the signalling model's bound; what a step's contact search can
// reach beyond its tip.
double max_step_length(const Scene& s);

core::Vec3 axon_start(core::Vec3 soma, core::Vec3 heading, const Scene& s);

}  // namespace axg

#include "axonguide/model/growth.hpp"

#include <cmath>

#include <fmt/format.h>

#include "axonguide/model/signalling.hpp"
#include "axonguide/model/steering.hpp"
#include "axonguide/scene/reader.hpp"
#include "axonguide/scene/scene.hpp"
#include "axonguide/support/error.hpp"

namespace axg {

void read_growth_keys(ObjectReader& r, GrowthKeys& a, double dt) {
  std::optional<double> step_length = a.step_length;
  const bool step_length_given = r.take("step_length") != nullptr;
  r.optional_number("step_length", step_length, positive());
  r.optional_number("growth_speed", a.growth_speed, positive());
  if (a.growth_speed) {
    if (step_length_given && step_length)
      throw InputError(fmt::format(
          "scene: axons.step_length = {} and axons.growth_speed = {} are both given: give one (the step length is "
          "growth_speed x dt)",
          *step_length, *a.growth_speed));
    a.step_length = *a.growth_speed * dt;
    if (!(a.step_length > 0.0) || !std::isfinite(a.step_length))
      fail_key("axons.growth_speed", *a.growth_speed,
               fmt::format("growth_speed x dt = {} must be a positive finite step length", a.step_length));
  } else if (!step_length) {
    fail_key("axons.step_length", nullptr, "must be a positive number (null only when axons.growth_speed is given)");
  } else {
    a.step_length = *step_length;
  }
  r.number("contact_distance", a.contact_distance, non_negative());
  r.choice("contact", a.contact, {{"swept", ContactRule::kSwept}, {"endpoint", ContactRule::kEndpoint}});
  r.optional_number("bounds_radius", a.bounds_radius, positive());
}

void write_growth_keys(const GrowthKeys& a, nlohmann::json& j) {
  using nlohmann::json;
  j["step_length"] = a.growth_speed ? json(nullptr) : json(a.step_length);
  j["growth_speed"] = a.growth_speed ? json(*a.growth_speed) : json(nullptr);
  j["contact_distance"] = a.contact_distance;
  j["contact"] = name_of(a.contact);
  j["bounds_radius"] = a.bounds_radius ? json(*a.bounds_radius) : json(nullptr);
}

core::GrowthParams growth_params(const Scene& s) {
  core::GrowthParams g{};
  g.step_length = s.axons.step_length;
  g.contact_radius = s.neurons.soma_radius + s.axons.contact_distance;
  g.contact_radius2 = g.contact_radius * g.contact_radius;
  g.bounds_radius = s.bounds_radius();
  g.bounds_box = s.neurons.shape == RegionShape::kBox;
  g.rule = s.axons.contact;
  return g;
}

double max_step_length(const Scene& s) {
  if (s.signalling()) return signalling_max_step(s);
  return modulates_growth(s) ? s.axons.step_length * (1.0 + s.axons.growth_modulation) : s.axons.step_length;
}

core::Vec3 axon_start(core::Vec3 soma, core::Vec3 heading, const Scene& s) {
  return core::axon_start(soma, heading, s.neurons.soma_radius);
}

}  // namespace axg

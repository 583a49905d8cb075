#include "axonguide/model/wander.hpp"

#include <cmath>

#include "axonguide/core/pmath.hpp"
#include "axonguide/scene/reader.hpp"
#include "axonguide/scene/scene.hpp"

namespace axg {

void read_wander_keys(ObjectReader& r, WanderKeys& a) {
  r.optional_number("persistence_length", a.persistence_length, positive());
}

void write_wander_keys(const WanderKeys& a, nlohmann::json& j) {
  j["persistence_length"] = a.persistence_length ? nlohmann::json(*a.persistence_length) : nlohmann::json(nullptr);
}

core::WanderParams wander_params(const Scene& s) {
  core::WanderParams w{};
  w.on = s.axons.persistence_length.has_value();
  if (!w.on) return w;
  w.inv_persistence = 1.0 / *s.axons.persistence_length;
  w.cos_step = core::pm::exp(-s.axons.step_length * w.inv_persistence);
  w.sin_step = std::sqrt(1.0 - w.cos_step * w.cos_step);
  return w;
}

}  // namespace axg

#pragma once
// Wandering (SPEC §3.5; docs/methods.md §2.9): the heading's persistent random walk, its
// key axons.persistence_length, its default, and the parameters core/wander.hpp gets.
#include <optional>

#include <nlohmann/json.hpp>

#include "axonguide/core/wander.hpp"
#include "axonguide/scene/units.hpp"

namespace axg {

struct Scene;
class ObjectReader;

// Katz 1985 (J Neurosci 5:589): axons in culture hold a nearly constant orientation over
// hundreds of micrometres. Default persistence length in um, and in LU with the report's
// soma radius 0.25 LU read as 10 um (kMicrometresPerLu).
inline constexpr double kDefaultPersistenceUm = 250.0;

struct WanderKeys {
  // L_p of the heading's random walk, length units; nullopt: no wandering. The default
  // follows the length unit (default_persistence_length).
  std::optional<double> persistence_length = kDefaultPersistenceUm / kMicrometresPerLu;
};

inline double default_persistence_length(const Units& units) { return kDefaultPersistenceUm / units.micrometres(); }

void read_wander_keys(ObjectReader& axons, WanderKeys& keys);
void write_wander_keys(const WanderKeys& keys, nlohmann::json& axons);

core::WanderParams wander_params(const Scene& s);

}  // namespace axg

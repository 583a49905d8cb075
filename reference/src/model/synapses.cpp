#include "axonguide/model/synapses.hpp"

#include <fmt/format.h>

#include "axonguide/scene/reader.hpp"
#include "axonguide/scene/scene.hpp"
#include "axonguide/support/error.hpp"

namespace axg {

using nlohmann::json;

void read_synapse_keys(const json& j, std::optional<SynapseKeys>& out) {
  if (j.is_null()) {
    out.reset();
    return;
  }
  SynapseKeys k;
  ObjectReader r(j, "synapses");
  r.number("distance", k.distance, positive());
  r.number("probability", k.probability, closed(0.0, 1.0));
  if (const json* v = r.take("max_per_connection")) {
    if (v->is_null()) k.max_per_connection.reset();
    else k.max_per_connection = static_cast<std::uint32_t>(
             ObjectReader::read_integer(*v, r.path("max_per_connection"), 0, 0xfffffffeu));
  }
  r.boolean("autapses", k.autapses);
  r.finish();
  out = k;
}

json write_synapse_keys(const SynapseKeys& k) {
  return {{"distance", k.distance},
          {"probability", k.probability},
          {"max_per_connection", k.max_per_connection ? json(*k.max_per_connection) : json(nullptr)},
          {"autapses", k.autapses}};
}

DistanceRange synapse_distance_range(const Scene& s) {
  const double diameter = 2.0 * s.bounds_radius();
  return {diameter / static_cast<double>(1u << 21), diameter / 16.0};
}

void check_synapses(const Scene& s) {
  if (!s.synapses) return;
  if (!s.arbours)
    fail_key("synapses", write_synapse_keys(*s.synapses),
             "synapses form where axons pass dendrites: they need an arbour scene (an `arbours` section)");
  const double um = s.units.micrometres();
  const DistanceRange r = synapse_distance_range(s);
  const double d = s.synapses->distance / um;
  if (!(d >= r.lo && d <= r.hi))
    fail_key("synapses.distance", s.synapses->distance,
             fmt::format("must lie in [{:.6g}, {:.6g}] um, the range the detection's spatial hash supports for "
                         "bounds of radius {:.6g} um (cells of at least 2d, from 8 to 2^20 across the bounds)",
                         r.lo * um, r.hi * um, s.bounds_radius() * um));
}

SynapseParams synapse_params(const Scene& s) {
  SynapseParams p;
  if (!s.synapses) return p;
  p.distance = s.synapses->distance / s.units.micrometres();
  p.probability = s.synapses->probability;
  p.cap = s.synapses->max_per_connection.value_or(0xffffffffu);
  p.autapses = s.synapses->autapses;
  p.seed = s.seed;
  return p;
}

}  // namespace axg

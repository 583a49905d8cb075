#pragma once
// Synapses (SPEC §3.9; docs/methods.md §2.13): the scene section `synapses`, its reading,
// canonical form and checks, and the parameters that network/appositions.hpp detects
// appositions with. `distance` is physical (micrometres, whatever the scene's length
// unit); `probability` realises each apposition by its own draw; `max_per_connection`
// caps a connection's realised synapses (null: no cap); `autapses` lets an axon synapse
// on its own neuron's dendrites and soma.
#include <cstdint>
#include <optional>

#include <nlohmann/json.hpp>

namespace axg {

struct Scene;

struct SynapseKeys {
  double distance = 2.0;  // micrometres, > 0
  double probability = 1.0;
  std::optional<std::uint32_t> max_per_connection;
  bool autapses = false;
};

// Reads `synapses` (an object; null: no synapse detection).
void read_synapse_keys(const nlohmann::json& j, std::optional<SynapseKeys>& out);
nlohmann::json write_synapse_keys(const SynapseKeys& keys);
// Checks against the rest of the scene: synapses need arbours, and the distance must lie in
// the range the detection's spatial hash supports (synapse_distance_range).
void check_synapses(const Scene& s);

// The distances the spatial hash supports, in the scene's length units: cells of at least
// 2d, at most 2^20 of them across the bounds' diameter (21-bit cell coordinates with room
// for the neurites that end just outside), and at least 8 across it (above that, the hash
// is one cell and detection is the brute-force search).
struct DistanceRange {
  double lo, hi;
};
DistanceRange synapse_distance_range(const Scene& s);

struct SynapseParams {
  double distance = 0.0;  // length units
  double probability = 1.0;
  std::uint32_t cap = 0xffffffffu;  // realised synapses per connection at most
  bool autapses = false;
  std::uint64_t seed = 0;
};
SynapseParams synapse_params(const Scene& s);

}  // namespace axg

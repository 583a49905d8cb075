#pragma once
// Reading a run's neurons.csv back (view, assay): the one reader, which refuses anything a
// run does not write.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "axonguide/core/types.hpp"
#include "axonguide/core/vec3.hpp"

namespace axg {

// One row per neuron, in id order.
struct NeuronRows {
  std::vector<core::Vec3> soma, tip;
  std::vector<double> soma_radius, length;
  std::vector<core::AxonStatus> status;
  std::vector<std::uint32_t> steps;
  std::vector<std::uint32_t> target;  // core::kNoNeuron where the file says -1
  std::size_t size() const { return soma.size(); }
};

// Parses neurons.csv (its header line first). A run writes 12 fields a row: id (0, 1, 2, ...
// in order), soma x y z, soma radius (> 0), status (growing, connected, exited, max_steps),
// tip x y z, length (>= 0), steps (an integer below 2^32), target (a neuron id, or -1), every
// number finite. Anything else throws InputError "WHERE: line N: why: not a run's data";
// so does a row count other than `expected` when it is given.
NeuronRows read_neurons_csv(const std::string& text, const std::string& where,
                            std::optional<std::size_t> expected = std::nullopt);

}  // namespace axg

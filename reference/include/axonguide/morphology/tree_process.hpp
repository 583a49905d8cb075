#pragma once
// The topology of one growth-cone tree under the branching and elongation rules of
// core/branching.hpp, without geometry: the process whose exact results (van Pelt's
// recursion for the number of terminal segments, the Yule process, the elongation model)
// `validate branching` tests, with the same per-step rule, cone keys and draws an arbour
// engine uses. Cones are visited in index order; a branching cone ends its segment at a
// branch point and its two daughters (order + 1) take the next indices, in the order of
// their parents' indices.
#include <cstdint>
#include <vector>

#include "axonguide/core/branching.hpp"

namespace axg::morphology {

struct TreeProcess {
  core::BranchingParams branching;
  core::ElongationParams elongation;
  double dt = 1;
  std::uint32_t steps = 1;
  std::uint64_t seed = 1;
};

struct TreeOutcome {
  int terminals = 0;               // cones at the end
  int branch_points = 0;
  double total_length = 0;
  double terminal_length = 0;      // summed over terminal segments
  double intermediate_length = 0;  // summed over intermediate segments
  double cone_steps = 0;           // the cones grown, summed over the steps (an arbour's points)
};

// Grows tree `tree` (its neuron id in the cone keys) from one cone at t = 0: each step every
// cone elongates, then draws whether it branches.
TreeOutcome grow_tree(const TreeProcess& p, std::uint32_t tree);

// grow_tree for trees 0 .. count - 1, in parallel; the outcomes in tree order.
std::vector<TreeOutcome> grow_trees(const TreeProcess& p, std::uint32_t count);

}  // namespace axg::morphology

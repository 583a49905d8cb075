#pragma once
// The connection graph (SPEC §3.6): CSR built by a stable counting sort by source,
// level-synchronous BFS from given sources, and connected components of the undirected
// view. Outputs are deterministic by definition: level (-1 unreached), parent = lowest id
// at the previous level (-1 for sources and unreached), component = lowest vertex id.
#include <cstdint>
#include <vector>

#include "axonguide/core/random.hpp"

namespace axg {

struct Csr {
  std::vector<std::uint32_t> offsets;  // vertices + 1
  std::vector<std::uint32_t> targets;  // neighbours, ascending within a vertex
  std::uint32_t max_degree = 0;
  std::size_t vertices() const { return offsets.empty() ? 0 : offsets.size() - 1; }
  std::size_t edges() const { return targets.size(); }
};

// CSR of the edges (source[k] -> target[k]) by a stable counting sort on the source:
// neighbours keep the input order, so sort edges by target first for ascending lists.
Csr csr_from_edges(std::size_t vertices, const std::vector<std::uint32_t>& source,
                   const std::vector<std::uint32_t>& target);
// The same edges reversed (in-neighbours, ascending).
Csr transpose(const Csr& g);
// Both directions, each list ascending, duplicates removed.
Csr undirected(const Csr& g);

inline constexpr std::uint32_t kNoParent = 0xffffffffu;

struct BfsResult {
  std::vector<std::int32_t> level;   // -1 unreached
  std::vector<std::uint32_t> parent;  // kNoParent for sources and unreached (written as -1)
  std::int32_t max_level = -1;
  std::size_t reached = 0;
  // How many levels the reference expanded bottom-up (a statistic for tests and benchmarks,
  // not part of the result: levels and parents are the same either way; 0 elsewhere).
  std::int32_t bottom_up_levels = 0;
};

// Level-synchronous BFS over the out-edges of g from every source at once (level 0).
// `in` is transpose(g), read only by the levels expanded bottom-up.
BfsResult bfs(const Csr& g, const Csr& in, const std::vector<std::uint32_t>& sources);
// The same search, building transpose(g) only if a level is expanded bottom-up (a sparse
// axon network never is, and at 10^7 neurons the transpose cost more than the search).
BfsResult bfs(const Csr& g, const std::vector<std::uint32_t>& sources);

// A random digraph for tests, validation and benchmarks: `edges` endpoints pairs drawn
// uniformly from Philox stream (seed, stream, pair index, step), duplicates removed,
// neighbour lists ascending.
Csr random_digraph(std::size_t vertices, std::size_t edges, std::uint64_t seed, core::Stream stream,
                   std::uint32_t step);

// Component label of every vertex of the undirected graph: its lowest vertex id.
std::vector<std::uint32_t> components(const Csr& undirected_graph);
// The same labels from a directed graph's edges taken both ways, by union-find (no
// undirected copy: one array of labels is all it holds).
std::vector<std::uint32_t> edge_components(const Csr& g);

}  // namespace axg

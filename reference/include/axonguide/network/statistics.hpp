#pragma once
// The statistics a network builder checks first (issue 42; docs/methods.md §2.13): degree
// distributions, synapses per connection, connection probability against intersomatic
// distance, reciprocity, clustering and path length. Each is defined as networkx defines it,
// so that networkx on the same graph gives the same numbers (tests/python/test_network.py).
#include <cstdint>
#include <vector>

#include "axonguide/core/vec3.hpp"

namespace axg::network {

struct Edge {
  std::uint32_t source, target, synapses;
};

struct DistanceBin {
  double lo, hi;
  std::uint64_t pairs = 0, connected = 0;  // ordered pairs (i != j) at that distance, and those connected i -> j
};

struct NetworkStats {
  std::size_t neurons = 0, connections = 0;
  std::uint64_t synapses = 0;
  std::vector<std::uint64_t> out_degree, in_degree;  // neurons per degree (connections, a self-loop once each way)
  std::vector<std::uint64_t> synapses_per_connection;  // connections per synapse count
  std::vector<DistanceBin> distance;
  // networkx reciprocity(G): the fraction of edges whose reverse is an edge (a self-loop never).
  double reciprocity = 0.0;
  // networkx average_clustering(G.to_undirected()): the mean over every neuron of its local
  // clustering in the undirected simple graph (self-loops ignored; fewer than 2 neighbours: 0).
  double clustering = 0.0;
  // Directed shortest paths (unweighted) from `path_sources` sources: the mean length over
  // ordered pairs (u, v), u != v, v reachable from u, and the fraction of such pairs reachable.
  double mean_path_length = 0.0, reachable = 0.0;
  std::size_t path_sources = 0;
};

// Up to this many neurons every neuron is a path source; above, this many evenly spaced ids
// (floor(k n / kPathSources)).
inline constexpr std::size_t kPathSources = 2000;

// edges: sorted by (source, target), no duplicates. bin: the distance histogram's width.
NetworkStats network_stats(const std::vector<core::Vec3>& soma, const std::vector<Edge>& edges, double bin);

}  // namespace axg::network

#include "axonguide/graph/graph.hpp"

#include <algorithm>
#include <atomic>
#include <optional>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

namespace axg {

Csr csr_from_edges(std::size_t vertices, const std::vector<std::uint32_t>& source,
                   const std::vector<std::uint32_t>& target) {
  Csr g;
  g.offsets.assign(vertices + 1, 0);
  for (std::uint32_t s : source) ++g.offsets[s + 1];
  for (std::size_t v = 0; v < vertices; ++v) {
    g.max_degree = std::max(g.max_degree, g.offsets[v + 1]);
    g.offsets[v + 1] += g.offsets[v];
  }
  g.targets.resize(source.size());
  std::vector<std::uint32_t> next(g.offsets.begin(), g.offsets.end() - 1);
  for (std::size_t k = 0; k < source.size(); ++k) g.targets[next[source[k]]++] = target[k];
  return g;
}

Csr random_digraph(std::size_t vertices, std::size_t edges, std::uint64_t seed, core::Stream stream,
                   std::uint32_t step) {
  std::vector<std::uint64_t> key(edges);
  const auto n = static_cast<std::uint32_t>(vertices);
  tbb::parallel_for(std::size_t{0}, edges, [&](std::size_t k) {
    core::Rng rng(seed, stream, k, step);
    const std::uint32_t a = rng.word32() % n, b = rng.word32() % n;
    key[k] = (std::uint64_t{a} << 32) | b;
  });
  std::sort(key.begin(), key.end());
  key.erase(std::unique(key.begin(), key.end()), key.end());
  std::vector<std::uint32_t> src(key.size()), dst(key.size());
  for (std::size_t k = 0; k < key.size(); ++k) src[k] = static_cast<std::uint32_t>(key[k] >> 32), dst[k] = static_cast<std::uint32_t>(key[k]);
  return csr_from_edges(vertices, src, dst);
}

Csr transpose(const Csr& g) {
  const std::size_t n = g.vertices();
  std::vector<std::uint32_t> src, dst;
  src.reserve(g.edges());
  dst.reserve(g.edges());
  // Edges in source order, so the stable sort by (new) source keeps lists ascending.
  for (std::size_t u = 0; u < n; ++u)
    for (std::uint32_t k = g.offsets[u]; k < g.offsets[u + 1]; ++k) {
      src.push_back(g.targets[k]);
      dst.push_back(static_cast<std::uint32_t>(u));
    }
  return csr_from_edges(n, src, dst);
}

Csr undirected(const Csr& g) {
  const Csr in = transpose(g);
  const std::size_t n = g.vertices();
  Csr u;
  u.offsets.assign(n + 1, 0);
  u.targets.reserve(2 * g.edges());
  std::vector<std::uint32_t> merged;
  for (std::size_t v = 0; v < n; ++v) {
    merged.clear();
    // Out-lists may be in any order; in-lists are ascending. Sort the union.
    merged.insert(merged.end(), g.targets.begin() + g.offsets[v], g.targets.begin() + g.offsets[v + 1]);
    merged.insert(merged.end(), in.targets.begin() + in.offsets[v], in.targets.begin() + in.offsets[v + 1]);
    std::sort(merged.begin(), merged.end());
    merged.erase(std::unique(merged.begin(), merged.end()), merged.end());
    u.targets.insert(u.targets.end(), merged.begin(), merged.end());
    u.offsets[v + 1] = static_cast<std::uint32_t>(u.targets.size());
    u.max_degree = std::max(u.max_degree, static_cast<std::uint32_t>(merged.size()));
  }
  return u;
}

// Level-synchronous and direction-optimizing (Beamer et al. 2012): a level is expanded
// top-down from the frontier's out-edges (one thread: on sparse levels the random writes
// of a parallel expansion cost more than they save, measured), or bottom-up in parallel
// (every unvisited vertex scans its in-edges for a frontier vertex) when it is dense.
// Levels are unique whichever way a level is expanded. Parents follow the lowest-id rule:
// bottom-up scans ascending in-lists and stops at the first frontier vertex, which is the
// lowest; top-down keeps the minimum over every frontier vertex that reaches a vertex in
// this level (an integer minimum, so the order of the visits does not matter).
namespace {

// in_edges() gives transpose(g); it is called only when a level is expanded bottom-up.
template <class InEdges>
BfsResult bfs_with(const Csr& g, InEdges in_edges, const std::vector<std::uint32_t>& sources) {
  const std::size_t n = g.vertices();
  BfsResult r;
  r.level.assign(n, -1);
  r.parent.assign(n, kNoParent);
  auto degree = [&g](std::uint32_t u) { return static_cast<double>(g.offsets[u + 1] - g.offsets[u]); };

  const double max_degree = g.max_degree;

  // The frontier of the current level and the out-edges leaving it (counted only when
  // the bound frontier size x max degree leaves the choice of expansion open).
  std::vector<std::uint32_t> frontier, next;
  frontier.reserve(sources.size());
  for (std::uint32_t s : sources)
    if (r.level[s] == -1) {
      r.level[s] = 0;
      frontier.push_back(s);
    }
  double frontier_edges = 0;
  bool counted = false;
  struct alignas(64) Found {  // one cache line per thread: no false sharing
    std::vector<std::uint32_t> vertices;
    double edges = 0;
  };
  tbb::enumerable_thread_specific<Found> local;
  auto gather = [&] {
    for (auto& l : local) {
      next.insert(next.end(), l.vertices.begin(), l.vertices.end());
      l.vertices.clear();
      frontier_edges += l.edges;
      l.edges = 0;
    }
  };
  // Graphs below this size are searched top-down on one thread only.
  constexpr double kBottomUpMinVertices = 1 << 17;
  constexpr double kBottomUpFactor = 4.0;
  std::int32_t level = 0;
  std::size_t reached = frontier.size();
  double unexplored = static_cast<double>(g.edges());
  while (!frontier.empty()) {
    const double bound = static_cast<double>(frontier.size()) * max_degree;
    if (!counted) {
      frontier_edges = bound;
      if (bound * kBottomUpFactor > static_cast<double>(n)) {
        frontier_edges = 0;
        for (std::uint32_t u : frontier) frontier_edges += degree(u);
      }
    }
    unexplored -= frontier_edges;
    // Cost model per level: top-down touches the frontier's out-edges; bottom-up scans
    // every vertex and the in-edges of the unvisited ones (stopping early, hence the
    // factor). Bottom-up wins only on dense levels, never on sparse axon networks.
    const bool bottom_up = static_cast<double>(n) > kBottomUpMinVertices &&
                           frontier_edges * kBottomUpFactor > static_cast<double>(n) + unexplored;
    next.clear();
    next.reserve(static_cast<std::size_t>(std::min(bound, static_cast<double>(n - reached))));
    frontier_edges = 0;
    counted = bottom_up;  // the bottom-up expansion counts as it goes
    if (bottom_up) {
      ++r.bottom_up_levels;
      const Csr& in = in_edges();
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& b) {
        Found& out = local.local();
        // Relaxed atomic accesses: other threads read levels this pass writes (a written
        // level is level + 1, never `level`, so what they read does not change the result).
        auto load = [&](std::uint32_t u) { return std::atomic_ref<std::int32_t>(r.level[u]).load(std::memory_order_relaxed); };
        for (std::size_t v = b.begin(); v != b.end(); ++v) {
          if (load(static_cast<std::uint32_t>(v)) != -1) continue;
          for (std::uint32_t k = in.offsets[v]; k < in.offsets[v + 1]; ++k)
            if (load(in.targets[k]) == level) {
              std::atomic_ref<std::int32_t>(r.level[v]).store(level + 1, std::memory_order_relaxed);
              r.parent[v] = in.targets[k];
              out.vertices.push_back(static_cast<std::uint32_t>(v));
              out.edges += degree(static_cast<std::uint32_t>(v));
              break;
            }
        }
      });
      gather();
    } else {
      for (std::uint32_t u : frontier)
        for (std::uint32_t k = g.offsets[u]; k < g.offsets[u + 1]; ++k) {
          const std::uint32_t v = g.targets[k];
          if (r.level[v] == -1) {
            r.level[v] = level + 1;
            r.parent[v] = u;
            next.push_back(v);
          } else if (r.level[v] == level + 1 && u < r.parent[v]) {
            r.parent[v] = u;
          }
        }
    }
    reached += next.size();
    if (!next.empty()) ++level;
    frontier.swap(next);
  }
  r.max_level = reached == 0 ? -1 : level;
  r.reached = reached;
  return r;
}

}  // namespace

BfsResult bfs(const Csr& g, const Csr& in, const std::vector<std::uint32_t>& sources) {
  return bfs_with(g, [&in]() -> const Csr& { return in; }, sources);
}

BfsResult bfs(const Csr& g, const std::vector<std::uint32_t>& sources) {
  std::optional<Csr> in;
  return bfs_with(
      g,
      [&]() -> const Csr& {
        if (!in) in = transpose(g);
        return *in;
      },
      sources);
}

std::vector<std::uint32_t> components(const Csr& u) {
  const std::size_t n = u.vertices();
  constexpr std::uint32_t kUnset = 0xffffffffu;
  std::vector<std::uint32_t> comp(n, kUnset);
  std::vector<std::uint32_t> queue;
  // Visiting roots in ascending order makes each label its component's lowest id.
  for (std::size_t root = 0; root < n; ++root) {
    if (comp[root] != kUnset) continue;
    const auto label = static_cast<std::uint32_t>(root);
    comp[root] = label;
    queue.assign(1, label);
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const std::uint32_t x = queue[head];
      for (std::uint32_t k = u.offsets[x]; k < u.offsets[x + 1]; ++k) {
        const std::uint32_t y = u.targets[k];
        if (comp[y] == kUnset) {
          comp[y] = label;
          queue.push_back(y);
        }
      }
    }
  }
  return comp;
}

// Union by lowest root: every parent link points to a lower id (path halving keeps that),
// so a root is its set's lowest id and one ascending pass resolves every label.
std::vector<std::uint32_t> edge_components(const Csr& g) {
  const std::size_t n = g.vertices();
  std::vector<std::uint32_t> parent(n);
  for (std::size_t v = 0; v < n; ++v) parent[v] = static_cast<std::uint32_t>(v);
  auto find = [&](std::uint32_t x) {
    while (parent[x] != x) {
      parent[x] = parent[parent[x]];
      x = parent[x];
    }
    return x;
  };
  // The targets are random ids: their parents, and those of the sources' parents, are
  // prefetched kAhead edges and vertices early so that the cache misses overlap (at 10^7
  // vertices the parents are 40 MB, beyond the last-level cache).
  constexpr std::size_t kAhead = 16;
  const std::size_t edges = g.targets.size();
  for (std::size_t u = 0; u < n; ++u) {
    if (u + kAhead < n) __builtin_prefetch(&parent[parent[u + kAhead]]);
    for (std::uint32_t k = g.offsets[u]; k < g.offsets[u + 1]; ++k) {
      if (k + kAhead < edges) __builtin_prefetch(&parent[g.targets[k + kAhead]]);
      const std::uint32_t a = find(static_cast<std::uint32_t>(u)), b = find(g.targets[k]);
      if (a < b) parent[b] = a;
      else if (b < a) parent[a] = b;
    }
  }
  for (std::size_t v = 0; v < n; ++v) parent[v] = parent[parent[v]];
  return parent;
}

}  // namespace axg

#include "axonguide/graph.hpp"

#include <algorithm>
#include <atomic>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

namespace axg {

Csr csr_from_edges(std::size_t vertices, const std::vector<std::uint32_t>& source,
                   const std::vector<std::uint32_t>& target) {
  Csr g;
  g.offsets.assign(vertices + 1, 0);
  for (std::uint32_t s : source) ++g.offsets[s + 1];
  for (std::size_t v = 0; v < vertices; ++v) g.offsets[v + 1] += g.offsets[v];
  g.targets.resize(source.size());
  std::vector<std::uint32_t> next(g.offsets.begin(), g.offsets.end() - 1);
  for (std::size_t k = 0; k < source.size(); ++k) g.targets[next[source[k]]++] = target[k];
  return g;
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
  }
  return u;
}

BfsResult bfs(const Csr& g, const Csr& in, const std::vector<std::uint32_t>& sources) {
  const std::size_t n = g.vertices();
  BfsResult r;
  r.level.assign(n, -1);
  r.parent.assign(n, -1);
  std::vector<std::uint32_t> frontier;
  for (std::uint32_t s : sources)
    if (r.level[s] == -1) {
      r.level[s] = 0;
      frontier.push_back(s);
    }
  std::int32_t level = 0;
  std::size_t reached = frontier.size();
  // Levels are unique whatever order a level's frontier is expanded in; a vertex is
  // claimed by whichever expansion reaches it first (integer compare-and-swap), and
  // parents are fixed afterwards by the lowest-id rule.
  tbb::enumerable_thread_specific<std::vector<std::uint32_t>> local;
  constexpr std::size_t kParallelFrontier = 1u << 14;
  while (!frontier.empty()) {
    std::vector<std::uint32_t> next;
    if (frontier.size() < kParallelFrontier) {
      for (std::uint32_t u : frontier)
        for (std::uint32_t k = g.offsets[u]; k < g.offsets[u + 1]; ++k) {
          const std::uint32_t v = g.targets[k];
          if (r.level[v] == -1) {
            r.level[v] = level + 1;
            next.push_back(v);
          }
        }
    } else {
      for (auto& l : local) l.clear();
      tbb::parallel_for(std::size_t{0}, frontier.size(), [&](std::size_t f) {
        const std::uint32_t u = frontier[f];
        auto& out = local.local();
        for (std::uint32_t k = g.offsets[u]; k < g.offsets[u + 1]; ++k) {
          const std::uint32_t v = g.targets[k];
          std::atomic_ref<std::int32_t> lv(r.level[v]);
          std::int32_t expected = -1;
          if (lv.load(std::memory_order_relaxed) == -1 &&
              lv.compare_exchange_strong(expected, level + 1, std::memory_order_relaxed))
            out.push_back(v);
        }
      });
      for (auto& l : local) next.insert(next.end(), l.begin(), l.end());
    }
    reached += next.size();
    if (!next.empty()) ++level;
    frontier.swap(next);
  }
  r.max_level = reached == 0 ? -1 : level;
  r.reached = reached;
  // Parent: the lowest in-neighbour one level up (in-lists are ascending).
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t v) {
    const std::int32_t lv = r.level[v];
    if (lv <= 0) return;
    for (std::uint32_t k = in.offsets[v]; k < in.offsets[v + 1]; ++k)
      if (r.level[in.targets[k]] == lv - 1) {
        r.parent[v] = in.targets[k];
        return;
      }
  });
  return r;
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

}  // namespace axg

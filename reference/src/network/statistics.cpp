// The network's statistics, as networkx defines them (docs/methods.md §2.13).
#include "axonguide/network/statistics.hpp"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

namespace axg::network {

namespace {

// A histogram's entry k, growing it as needed.
void count(std::vector<std::uint64_t>& h, std::size_t k) {
  if (h.size() <= k) h.resize(k + 1, 0);
  ++h[k];
}

}  // namespace

NetworkStats network_stats(const std::vector<core::Vec3>& soma, const std::vector<Edge>& edges, double bin) {
  NetworkStats s;
  const std::size_t n = soma.size();
  s.neurons = n;
  s.connections = edges.size();
  std::vector<std::vector<std::uint32_t>> out(n), in(n), both(n);
  for (const Edge& e : edges) {
    s.synapses += e.synapses;
    count(s.synapses_per_connection, e.synapses);
    out[e.source].push_back(e.target);
    in[e.target].push_back(e.source);
    if (e.source != e.target) {
      both[e.source].push_back(e.target);
      both[e.target].push_back(e.source);
    }
  }
  for (std::size_t v = 0; v < n; ++v) {
    count(s.out_degree, out[v].size());
    count(s.in_degree, in[v].size());
    std::sort(both[v].begin(), both[v].end());
    both[v].erase(std::unique(both[v].begin(), both[v].end()), both[v].end());
  }
  // Reciprocity: out lists are ascending (edges sorted by source, then target).
  std::uint64_t reciprocated = 0;
  for (const Edge& e : edges)
    if (e.source != e.target && std::binary_search(out[e.target].begin(), out[e.target].end(), e.source))
      ++reciprocated;
  s.reciprocity = edges.empty() ? 0.0 : static_cast<double>(reciprocated) / static_cast<double>(edges.size());
  // Clustering, in vertex order (a fixed sum).
  std::vector<double> local(n, 0.0);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t v) {
    const auto& nb = both[v];
    const std::size_t k = nb.size();
    if (k < 2) return;
    std::uint64_t links = 0;
    for (std::size_t a = 0; a < k; ++a)
      for (std::size_t b = a + 1; b < k; ++b)
        links += std::binary_search(both[nb[a]].begin(), both[nb[a]].end(), nb[b]);
    local[v] = 2.0 * static_cast<double>(links) / (static_cast<double>(k) * static_cast<double>(k - 1));
  });
  double sum = 0.0;
  for (const double c : local) sum += c;
  s.clustering = n == 0 ? 0.0 : sum / static_cast<double>(n);
  // Paths: BFS from each source; per-source integer sums, added in source order.
  std::vector<std::uint32_t> sources;
  if (n <= kPathSources)
    for (std::size_t v = 0; v < n; ++v) sources.push_back(static_cast<std::uint32_t>(v));
  else
    for (std::size_t k = 0; k < kPathSources; ++k) sources.push_back(static_cast<std::uint32_t>(k * n / kPathSources));
  s.path_sources = sources.size();
  std::vector<std::uint64_t> reached(sources.size(), 0), total(sources.size(), 0);
  tbb::parallel_for(std::size_t{0}, sources.size(), [&](std::size_t q) {
    std::vector<std::int32_t> level(n, -1);
    std::vector<std::uint32_t> frontier{sources[q]}, next;
    level[sources[q]] = 0;
    for (std::int32_t d = 1; !frontier.empty(); ++d) {
      next.clear();
      for (const std::uint32_t u : frontier)
        for (const std::uint32_t w : out[u])
          if (level[w] < 0) {
            level[w] = d;
            next.push_back(w);
            ++reached[q];
            total[q] += static_cast<std::uint64_t>(d);
          }
      frontier.swap(next);
    }
  });
  std::uint64_t pairs = 0, length = 0;
  for (std::size_t q = 0; q < sources.size(); ++q) pairs += reached[q], length += total[q];
  s.mean_path_length = pairs == 0 ? 0.0 : static_cast<double>(length) / static_cast<double>(pairs);
  s.reachable = n < 2 ? 0.0 : static_cast<double>(pairs) / (static_cast<double>(sources.size()) * static_cast<double>(n - 1));
  // Connection probability against distance: every ordered pair, by bin.
  // Bins up to the bounding box's diagonal, which no pair exceeds.
  core::Vec3 lo = n ? soma[0] : core::Vec3{0, 0, 0}, hi = lo;
  for (const core::Vec3& p : soma) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  const double far = core::norm(hi - lo);
  const std::size_t bins = n < 2 ? 0 : static_cast<std::size_t>(far / bin) + 1;
  std::vector<std::uint64_t> pair_count(bins, 0), hit_count(bins, 0);
  {
    std::vector<std::vector<std::uint64_t>> rows(n);
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
      rows[i].assign(bins, 0);
      for (std::size_t j = 0; j < n; ++j)
        if (j != i) ++rows[i][static_cast<std::size_t>(core::norm(soma[i] - soma[j]) / bin)];
    });
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t b = 0; b < bins; ++b) pair_count[b] += rows[i][b];
  }
  for (const Edge& e : edges)
    if (e.source != e.target) ++hit_count[static_cast<std::size_t>(core::norm(soma[e.source] - soma[e.target]) / bin)];
  for (std::size_t b = 0; b < bins; ++b)
    s.distance.push_back({bin * static_cast<double>(b), bin * static_cast<double>(b + 1), pair_count[b], hit_count[b]});
  return s;
}

}  // namespace axg::network

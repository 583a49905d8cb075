// The graph kernels: edges from the axon slots, level-synchronous and queue BFS,
// connected components.
// Part of the pipeline (../pipeline.inl); compiled once per build of it.
#pragma once

namespace axg::accel::AXG_ACCEL_NS {

struct EdgeFlags {
  const std::uint32_t* d_target;  // by neuron id
  AXG_HD bool operator()(std::uint32_t i) const { return d_target[i] != core::kNoNeuron; }
};

struct EdgeTargets {
  const std::uint32_t* d_source;
  const std::uint32_t* d_target_by_id;
  std::uint32_t* d_target;
  AXG_HD void operator()(std::size_t e) const { d_target[e] = d_target_by_id[d_source[e]]; }
};

// The report's kernel (Fig. 5): one thread per vertex; a vertex of the current level
// labels its unvisited neighbours (every writer writes the same value).
struct LevelSyncExpand {
  const std::uint32_t* d_offsets;
  const std::uint32_t* d_targets;
  int* d_level;
  int level;
  std::uint32_t* d_changed;
  AXG_HD void operator()(std::size_t u) const {
    if (d_level[u] != level) return;
    for (std::uint32_t k = d_offsets[u]; k < d_offsets[u + 1]; ++k) {
      const std::uint32_t v = d_targets[k];
      if (atomic_cas(&d_level[v], -1, level + 1) == -1) *d_changed = 1;
    }
  }
};

// Parents: every vertex of level L offers itself to its neighbours of level L+1; the
// minimum wins (lowest id at the previous level).
struct OfferParent {
  const std::uint32_t* d_offsets;
  const std::uint32_t* d_targets;
  const int* d_level;
  int level;
  std::uint32_t* d_parent;
  AXG_HD void operator()(std::size_t u) const {
    if (d_level[u] != level) return;
    for (std::uint32_t k = d_offsets[u]; k < d_offsets[u + 1]; ++k) {
      const std::uint32_t v = d_targets[k];
      if (d_level[v] == level + 1) atomic_min(&d_parent[v], static_cast<std::uint32_t>(u));
    }
  }
};

// Work-efficient BFS: one thread per frontier vertex; claimed vertices are appended to
// the next frontier (in any order: the frontier is a set, and its order changes nothing).
struct QueueExpand {
  const std::uint32_t* d_offsets;
  const std::uint32_t* d_targets;
  const std::uint32_t* d_frontier;
  int* d_level;
  int level;
  std::uint32_t* d_next;
  std::uint32_t* d_next_count;
  AXG_HD void operator()(std::size_t f) const {
    const std::uint32_t u = d_frontier[f];
    for (std::uint32_t k = d_offsets[u]; k < d_offsets[u + 1]; ++k) {
      const std::uint32_t v = d_targets[k];
      if (atomic_cas(&d_level[v], -1, level + 1) == -1) d_next[atomic_add(d_next_count, 1)] = v;
    }
  }
};

struct QueueParents {
  const std::uint32_t* d_offsets;
  const std::uint32_t* d_targets;
  const std::uint32_t* d_frontier;
  const int* d_level;
  int level;
  std::uint32_t* d_parent;
  AXG_HD void operator()(std::size_t f) const {
    const std::uint32_t u = d_frontier[f];
    for (std::uint32_t k = d_offsets[u]; k < d_offsets[u + 1]; ++k) {
      const std::uint32_t v = d_targets[k];
      if (d_level[v] == level + 1) atomic_min(&d_parent[v], u);
    }
  }
};

// Components: min-label propagation over the edges as undirected, then pointer jumping;
// labels only decrease and stay ids of the vertex's component, so the fixpoint is the
// component's lowest id.
struct HookEdges {
  const std::uint32_t* d_source;
  const std::uint32_t* d_target;
  std::uint32_t* d_label;
  std::uint32_t* d_changed;
  AXG_HD void operator()(std::size_t e) const {
    const std::uint32_t a = d_source[e], b = d_target[e];
    const std::uint32_t la = d_label[a], lb = d_label[b];
    if (la == lb) return;
    const std::uint32_t m = la < lb ? la : lb;
    atomic_min(&d_label[a], m);
    atomic_min(&d_label[b], m);
    atomic_min(&d_label[la], m);
    atomic_min(&d_label[lb], m);
    *d_changed = 1;
  }
};

struct Jump {
  std::uint32_t* d_label;
  AXG_HD void operator()(std::size_t v) const {
    std::uint32_t l = d_label[v];
    while (d_label[l] < l) l = d_label[l];
    d_label[v] = l;
  }
};

inline std::uint32_t read_flag(dvec<std::uint32_t>& flag) {
  const std::uint32_t v = flag[0];
  flag[0] = 0;
  return v;
}

// CSR on the device from a host CSR.
struct DeviceCsr {
  dvec<std::uint32_t> offsets, targets;
  explicit DeviceCsr(const Csr& g) : offsets(g.offsets.begin(), g.offsets.end()), targets(g.targets.begin(), g.targets.end()) {}
  DeviceCsr(dvec<std::uint32_t>&& o, dvec<std::uint32_t>&& t) : offsets(std::move(o)), targets(std::move(t)) {}
  std::size_t vertices() const { return offsets.size() - 1; }
};

inline BfsResult download_bfs(dvec<int>& level, dvec<std::uint32_t>& parent, int max_level) {
  BfsResult r;
  r.level.resize(level.size());
  r.parent.resize(parent.size());
  thrust::copy(level.begin(), level.end(), r.level.begin());
  thrust::copy(parent.begin(), parent.end(), r.parent.begin());
  r.reached = static_cast<std::size_t>(std::count_if(r.level.begin(), r.level.end(), [](int l) { return l >= 0; }));
  r.max_level = r.reached == 0 ? -1 : max_level;
  return r;
}

inline void init_bfs(const DeviceCsr& g, const std::vector<std::uint32_t>& sources, dvec<int>& level,
                     dvec<std::uint32_t>& parent) {
  const std::size_t n = g.vertices();
  level.assign(n, -1);
  parent.assign(n, kNoParent);
  thrust::host_vector<int> h_level(n, -1);
  for (std::uint32_t s : sources) h_level[s] = 0;
  thrust::copy(h_level.begin(), h_level.end(), level.begin());
}

inline BfsResult bfs_level_sync_device(const DeviceCsr& g, const std::vector<std::uint32_t>& sources) {
  dvec<int> level;
  dvec<std::uint32_t> parent, changed(1, 0);
  init_bfs(g, sources, level, parent);
  const std::size_t n = g.vertices();
  int l = 0;
  for (;; ++l) {
    launch(n, LevelSyncExpand{raw(g.offsets), raw(g.targets), raw(level), l, raw(changed)});
    if (!read_flag(changed)) break;
    launch(n, OfferParent{raw(g.offsets), raw(g.targets), raw(level), l, raw(parent)});
  }
  return download_bfs(level, parent, l);
}

inline BfsResult bfs_queue_device(const DeviceCsr& g, const std::vector<std::uint32_t>& sources) {
  dvec<int> level;
  dvec<std::uint32_t> parent;
  init_bfs(g, sources, level, parent);
  std::vector<std::uint32_t> unique_sources;
  {
    std::vector<char> seen(g.vertices(), 0);
    for (std::uint32_t s : sources)
      if (!seen[s]) seen[s] = 1, unique_sources.push_back(s);
  }
  dvec<std::uint32_t> frontier(unique_sources.begin(), unique_sources.end()), next(g.vertices() + 1),
      count(1, 0);
  int l = 0;
  while (!frontier.empty()) {
    count[0] = 0;
    launch(frontier.size(), QueueExpand{raw(g.offsets), raw(g.targets), raw(frontier), raw(level), l, raw(next), raw(count)});
    launch(frontier.size(), QueueParents{raw(g.offsets), raw(g.targets), raw(frontier), raw(level), l, raw(parent)});
    const std::uint32_t found = count[0];
    frontier.resize(found);
    thrust::copy_n(next.begin(), found, frontier.begin());
    if (found) ++l;
  }
  return download_bfs(level, parent, l);
}

inline std::vector<std::uint32_t> components_device(const dvec<std::uint32_t>& source, const dvec<std::uint32_t>& target,
                                                    std::size_t n) {
  dvec<std::uint32_t> label(n), changed(1, 0);
  thrust::sequence(label.begin(), label.end());
  for (;;) {
    launch(source.size(), HookEdges{raw(source), raw(target), raw(label), raw(changed)});
    launch(n, Jump{raw(label)});
    if (!read_flag(changed)) break;
  }
  std::vector<std::uint32_t> out(n);
  thrust::copy(label.begin(), label.end(), out.begin());
  return out;
}

// Edge list (source, target) of a host CSR, on the device.
inline void device_edges(const Csr& g, dvec<std::uint32_t>& source, dvec<std::uint32_t>& target) {
  std::vector<std::uint32_t> s;
  s.reserve(g.edges());
  for (std::size_t u = 0; u < g.vertices(); ++u)
    for (std::uint32_t k = g.offsets[u]; k < g.offsets[u + 1]; ++k) s.push_back(static_cast<std::uint32_t>(u));
  source.assign(s.begin(), s.end());
  target.assign(g.targets.begin(), g.targets.end());
}

}  // namespace axg::accel::AXG_ACCEL_NS

// The accelerator's pipeline, included by engine_cuda.cu (namespace gpu, Thrust's CUDA
// system) and engine_emulated.cpp (namespace emu, Thrust's sequential CPP system).
// Every kernel is a functor whose operator() handles one entity and calls core/
// functions; `launch` runs it once per index. Grids are built by a stable radix sort of
// (cell, id) (CUB's, through Thrust, on the GPU), compactions are stable (copy_if), and
// every floating-point sum is the one the core function performs, so the results equal
// the reference's bit for bit.
#include <thrust/copy.h>
#include <thrust/count.h>
#include <thrust/device_vector.h>
#include <thrust/execution_policy.h>
#include <thrust/fill.h>
#include <thrust/for_each.h>
#include <thrust/host_vector.h>
#include <thrust/iterator/counting_iterator.h>
#include <thrust/iterator/zip_iterator.h>
#include <thrust/sequence.h>
#include <thrust/sort.h>
#include <thrust/tuple.h>

#include <algorithm>
#include <memory>
#include <vector>

#include "axonguide/cell_grid.hpp"
#include "axonguide/core/cellgrid.hpp"
#include "axonguide/core/growth.hpp"
#include "axonguide/core/particles.hpp"
#include "axonguide/core/steering.hpp"
#include "axonguide/core/stencil.hpp"
#include "axonguide/cue_setup.hpp"
#include "axonguide/engine.hpp"
#include "axonguide/growth_setup.hpp"

namespace axg::accel::AXG_ACCEL_NS {

using core::Vec3;
template <class T>
using dvec = thrust::device_vector<T>;

template <class T>
T* raw(dvec<T>& v) {
  return thrust::raw_pointer_cast(v.data());
}
template <class T>
const T* raw(const dvec<T>& v) {
  return thrust::raw_pointer_cast(v.data());
}

// One call of f(i) for every i in [0, n): a grid of threads on the GPU, a loop on the CPU.
template <class F>
void launch(std::size_t n, const F& f) {
  if (n == 0) return;
  thrust::for_each_n(thrust::device, thrust::counting_iterator<std::size_t>(0), n, f);
}

// ---- Integer atomics (the only atomics: their results do not depend on order). ----

AXG_HDI int atomic_cas(int* p, int expected, int desired) {
#if defined(__CUDA_ARCH__)
  return atomicCAS(p, expected, desired);
#else
  const int old = *p;
  if (old == expected) *p = desired;
  return old;
#endif
}

AXG_HDI void atomic_min(std::uint32_t* p, std::uint32_t v) {
#if defined(__CUDA_ARCH__)
  atomicMin(reinterpret_cast<unsigned int*>(p), static_cast<unsigned int>(v));
#else
  if (v < *p) *p = v;
#endif
}

AXG_HDI std::uint32_t atomic_add(std::uint32_t* p, std::uint32_t v) {
#if defined(__CUDA_ARCH__)
  return atomicAdd(reinterpret_cast<unsigned int*>(p), static_cast<unsigned int>(v));
#else
  const std::uint32_t old = *p;
  *p = old + v;
  return old;
#endif
}

// ---- Grids: hash, stable sort by key, cell starts, sorted copies. ----

struct FillCellStarts {
  const std::uint32_t* d_keys;
  std::size_t n;
  std::uint32_t cells;
  std::uint32_t* d_start;
  AXG_HD void operator()(std::size_t k) const { core::fill_cell_starts(k, d_keys, n, cells, d_start); }
};

struct SomaKeys {
  const Vec3* d_pos;
  core::CellGridView geometry;
  std::uint32_t* d_keys;
  std::uint32_t* d_ids;
  AXG_HD void operator()(std::size_t i) const {
    d_keys[i] = core::cell_of(d_pos[i], geometry);
    d_ids[i] = static_cast<std::uint32_t>(i);
  }
};

template <class T>
struct GatherBy {
  const T* d_in;
  const std::uint32_t* d_index;
  T* d_out;
  AXG_HD void operator()(std::size_t k) const { d_out[k] = d_in[d_index[k]]; }
};

template <class T>
struct ScatterBy {
  const T* d_in;
  const std::uint32_t* d_index;
  T* d_out;
  AXG_HD void operator()(std::size_t k) const { d_out[d_index[k]] = d_in[k]; }
};

// keys are sorted stably (values carried), then cell starts are found.
inline void sort_and_find_starts(dvec<std::uint32_t>& keys, dvec<std::uint32_t>& values, std::uint32_t cells,
                                 dvec<std::uint32_t>& start) {
  thrust::stable_sort_by_key(thrust::device, keys.begin(), keys.end(), values.begin());
  start.resize(static_cast<std::size_t>(cells) + 1);
  launch(keys.size() + 1, FillCellStarts{raw(keys), keys.size(), cells, raw(start)});
}

// ---- Axons. ----

struct InitAxons {
  const Vec3* d_soma;
  const Vec3* d_heading_by_id;
  const std::uint32_t* d_ids;  // slot -> neuron
  double soma_radius;
  Vec3* d_tip;
  Vec3* d_heading;
  AXG_HD void operator()(std::size_t k) const {
    const std::uint32_t i = d_ids[k];
    d_heading[k] = d_heading_by_id[i];
    d_tip[k] = core::axon_start(d_soma[i], d_heading_by_id[i], soma_radius);
  }
};

struct CueFields {
  core::FieldKind kind;
  const core::CueParams* d_cues;
  int cue_count;
  core::SenseParams sense;
  core::HashGridView particles;
  core::GridFieldSet grids;
};

struct Steer {
  const std::uint32_t* d_active;
  const std::uint32_t* d_ids;
  const Vec3* d_tip;
  Vec3* d_heading;
  CueFields fields;
  core::SteerParams params;
  std::uint64_t seed;
  std::uint32_t step;
  AXG_HD void operator()(std::size_t a) const {
    const std::uint32_t k = d_active[a];
    core::CueSample samples[core::kMaxCues];
    Vec3 pull[core::kMaxCues];
    const Vec3 x = d_tip[k];
    switch (fields.kind) {
      case core::FieldKind::kParticles:
        core::sample_particle_field(x, fields.particles, fields.d_cues, fields.cue_count, fields.sense, samples, pull);
        break;
      case core::FieldKind::kGrid:
        core::sample_grid_field(x, fields.grids, fields.d_cues, fields.cue_count, samples, pull);
        break;
      case core::FieldKind::kAnalytic:
        core::sample_analytic_field(x, fields.d_cues, fields.cue_count, fields.sense, samples, pull);
        break;
    }
    d_heading[k] = core::steer_axon(d_heading[k], samples, pull, fields.d_cues, fields.cue_count, fields.sense, params,
                                    seed, d_ids[k], step);
  }
};

struct Grow {
  const std::uint32_t* d_active;
  const std::uint32_t* d_ids;
  core::GrowthParams params;
  core::CellGridView somas;
  std::uint32_t step;
  Vec3* d_tip;
  const Vec3* d_heading;
  double* d_length;
  core::AxonStatus* d_status;
  std::uint32_t* d_steps;
  std::uint32_t* d_target;
  AXG_HD void operator()(std::size_t a) const {
    const std::uint32_t k = d_active[a];
    const core::AxonStep s = core::grow_axon(d_ids[k], d_tip[k], d_heading[k], params, somas);
    d_tip[k] = s.tip;
    d_length[k] = d_length[k] + s.advanced;
    d_steps[k] = step;
    d_status[k] = s.status;
    d_target[k] = s.target;
  }
};

struct StatusIs {
  const core::AxonStatus* d_status;
  core::AxonStatus want;
  AXG_HD bool operator()(std::uint32_t k) const { return d_status[k] == want; }
};

struct MarkMaxSteps {
  const std::uint32_t* d_active;
  core::AxonStatus* d_status;
  AXG_HD void operator()(std::size_t a) const { d_status[d_active[a]] = core::AxonStatus::kMaxSteps; }
};

// ---- Particles. ----

struct EmitParticles {
  std::uint64_t first_id;
  std::size_t first_slot;
  const std::uint32_t* d_offsets;  // per cue: first new particle of the cue, then the total
  int cue_count;
  const core::CueParams* d_cues;
  bool ballistic;
  core::ParticleParams params;
  std::uint64_t seed;
  std::uint32_t step;
  Vec3* d_pos;
  Vec3* d_vel;
  std::uint64_t* d_id;
  std::uint16_t* d_source;
  AXG_HD void operator()(std::size_t e) const {
    int k = 0;
    while (k + 1 < cue_count && d_offsets[k + 1] <= e) ++k;
    const std::uint64_t id = first_id + e;
    const std::size_t i = first_slot + e;
    d_pos[i] = d_cues[k].position;
    d_id[i] = id;
    d_source[i] = static_cast<std::uint16_t>(k);
    if (ballistic) d_vel[i] = core::birth_velocity(seed, id, step, params);
  }
};

struct MoveParticles {
  const std::uint64_t* d_id;
  const std::uint16_t* d_source;
  const core::CueParams* d_cues;
  core::ParticleParams params;
  bool ballistic;
  std::uint64_t seed;
  std::uint32_t step;
  Vec3* d_pos;
  Vec3* d_vel;
  std::uint8_t* d_keep;
  AXG_HD void operator()(std::size_t i) const {
    Vec3 v = ballistic ? d_vel[i] : Vec3{0.0, 0.0, 0.0};
    d_keep[i] = core::particle_step(seed, d_id[i], step, d_pos[i], v, d_cues[d_source[i]], params) ? 1 : 0;
    if (ballistic) d_vel[i] = v;
  }
};

struct ParticleKeys {
  const Vec3* d_pos;
  core::HashGridView geometry;
  std::uint32_t* d_keys;
  std::uint32_t* d_index;
  AXG_HD void operator()(std::size_t i) const {
    d_keys[i] = core::hash_of(d_pos[i], geometry);
    d_index[i] = static_cast<std::uint32_t>(i);
  }
};

struct GatherParticles {
  const Vec3* d_pos;
  const std::uint16_t* d_source;
  const std::uint32_t* d_index;
  Vec3* d_sorted_pos;
  std::uint16_t* d_sorted_source;
  AXG_HD void operator()(std::size_t k) const {
    d_sorted_pos[k] = d_pos[d_index[k]];
    d_sorted_source[k] = d_source[d_index[k]];
  }
};

struct Collide {
  core::HashGridView grid;
  core::ParticleParams params;
  bool ballistic;
  Vec3* d_pos;
  Vec3* d_vel;
  AXG_HD void operator()(std::size_t k) const {
    const std::uint32_t i = grid.index[k];
    const Vec3 push = core::collision_push(i, grid.pos[k], grid, params);
    d_pos[i] = grid.pos[k] + push;
    if (ballistic) d_vel[i] = d_vel[i] + push / params.dt;
  }
};

struct IsKept {
  AXG_HD bool operator()(std::uint8_t k) const { return k != 0; }
};

// ---- Grid fields. ----

struct Deposit {
  double* d_c;
  core::SourceDeposit d;
  AXG_HD void operator()(std::size_t) const {
    for (int m = 0; m < 8; ++m) d_c[d.index[m]] += d.value[m];
  }
};

struct Ftcs {
  const double* d_in;
  double* d_out;
  core::StencilParams s;
  AXG_HD void operator()(std::size_t idx) const {
    const std::size_t n = static_cast<std::size_t>(s.n);
    const int i = static_cast<int>(idx % n), j = static_cast<int>((idx / n) % n), k = static_cast<int>(idx / (n * n));
    d_out[idx] = core::ftcs_node(d_in, i, j, k, s);
  }
};

// One thread per line of one axis (the reference's lines: x lines contiguous; y lines of
// plane z = p, column x = q; z lines of row y = p, column x = q).
struct LodLines {
  double* d_c;
  double* d_cp;
  double* d_dp;
  int n;
  int axis;
  double lambda;
  bool reflecting;
  AXG_HD void operator()(std::size_t line) const {
    const std::size_t nn = static_cast<std::size_t>(n);
    const std::size_t p = line / nn, q = line % nn;
    std::size_t first, stride;
    if (axis == 0) first = line * nn, stride = 1;
    else if (axis == 1) first = p * nn * nn + q, stride = nn;
    else first = p * nn + q, stride = nn * nn;
    core::lod_line_solve(d_c, first, stride, n, lambda, reflecting, d_cp + line * nn, d_dp + line * nn);
  }
};

struct Scale {
  double* d_c;
  double factor;
  AXG_HD void operator()(std::size_t i) const { d_c[i] = d_c[i] * factor; }
};

// ---- Graph. ----

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

// ---- The engine. ----

class AccelEngine final : public Engine {
 public:
  AccelEngine(const Scene& scene, const Placement& placement)
      : scene_(scene),
        growth_(growth_params(scene)),
        cues_host_(make_cues(scene)),
        sense_(sense_params(scene)),
        steer_(steer_params(scene)),
        particle_params_(particle_params(scene)),
        hash_(particle_hash_geometry(scene)),
        grid_geometry_(grid_field_geometry(scene)) {
    build_somas(placement);
    const std::size_t n = placement.soma.size();
    tip_.resize(n);
    heading_.resize(n);
    length_.assign(n, 0.0);
    status_.assign(n, core::AxonStatus::kGrowing);
    steps_.assign(n, 0);
    target_.assign(n, core::kNoNeuron);
    {
      const dvec<Vec3> soma(placement.soma.begin(), placement.soma.end());
      const dvec<Vec3> heading(placement.heading.begin(), placement.heading.end());
      launch(n, InitAxons{raw(soma), raw(heading), raw(ids_), scene.neurons.soma_radius, raw(tip_), raw(heading_)});
    }
    active_.resize(n);
    thrust::sequence(active_.begin(), active_.end());
    active_next_.resize(n);
    if (scene.uses_cues()) init_field();
  }

  StepStats step(std::uint32_t step, PhaseTimes& times) override {
    if (scene_.uses_cues()) {
      advance_field(step, times);
      ScopedPhase p(times, step, "steer");
      launch(active_.size(), Steer{raw(active_), raw(ids_), raw(tip_), raw(heading_), fields(), steer_, scene_.seed, step});
    }
    {
      ScopedPhase p(times, step, "grow");
      launch(active_.size(), Grow{raw(active_), raw(ids_), growth_, somas_view(), step, raw(tip_), raw(heading_),
                                  raw(length_), raw(status_), raw(steps_), raw(target_)});
    }
    {
      ScopedPhase p(times, step, "compact");
      stats_.connected += static_cast<std::uint64_t>(thrust::count_if(
          thrust::device, active_.begin(), active_.end(), StatusIs{raw(status_), core::AxonStatus::kConnected}));
      stats_.exited += static_cast<std::uint64_t>(thrust::count_if(
          thrust::device, active_.begin(), active_.end(), StatusIs{raw(status_), core::AxonStatus::kExited}));
      const auto end = thrust::copy_if(thrust::device, active_.begin(), active_.end(), active_next_.begin(),
                                       StatusIs{raw(status_), core::AxonStatus::kGrowing});
      active_next_.resize(static_cast<std::size_t>(end - active_next_.begin()));
      active_.swap(active_next_);
      active_next_.resize(active_.capacity());
    }
    stats_.step = step;
    stats_.growing = active_.size();
    stats_.particles = pos_.size();
    return stats_;
  }

  void particles(std::vector<Vec3>& pos, std::vector<std::uint16_t>& cue) override {
    pos.resize(pos_.size());
    cue.resize(source_.size());
    thrust::copy(pos_.begin(), pos_.end(), pos.begin());
    thrust::copy(source_.begin(), source_.end(), cue.begin());
  }

  void tips(std::vector<Vec3>& out) override {
    dvec<Vec3> by_id(tip_.size());
    launch(tip_.size(), ScatterBy<Vec3>{raw(tip_), raw(ids_), raw(by_id)});
    out.resize(tip_.size());
    thrust::copy(by_id.begin(), by_id.end(), out.begin());
  }

  void finish(NeuronState& out) override {
    launch(active_.size(), MarkMaxSteps{raw(active_), raw(status_)});
    const std::size_t n = tip_.size();
    out.resize(n);
    download_by_id(tip_, out.tip);
    download_by_id(length_, out.length);
    download_by_id(status_, out.status);
    download_by_id(steps_, out.steps);
    target_by_id_.resize(n);
    launch(n, ScatterBy<std::uint32_t>{raw(target_), raw(ids_), raw(target_by_id_)});
    thrust::copy(target_by_id_.begin(), target_by_id_.end(), out.target.begin());
  }

  // Edges from the per-axon slots: compacted (ascending source id), then CSR offsets as
  // the cell starts of the sorted sources; BFS and components on the device.
  bool analyze(const Scene& scene, GraphAnalysis& a) override {
    const std::size_t n = tip_.size();
    dvec<std::uint32_t> source(n);
    const auto end = thrust::copy_if(thrust::device, thrust::counting_iterator<std::uint32_t>(0),
                                     thrust::counting_iterator<std::uint32_t>(static_cast<std::uint32_t>(n)),
                                     source.begin(), EdgeFlags{raw(target_by_id_)});
    source.resize(static_cast<std::size_t>(end - source.begin()));
    dvec<std::uint32_t> target(source.size()), offsets;
    launch(source.size(), EdgeTargets{raw(source), raw(target_by_id_), raw(target)});
    // Sources are already ascending (out-degree <= 1); the stable sort keeps the general
    // construction (and costs one pass on sorted keys).
    dvec<std::uint32_t> sorted_source = source;
    thrust::stable_sort_by_key(thrust::device, sorted_source.begin(), sorted_source.end(), target.begin());
    offsets.resize(n + 1);
    launch(sorted_source.size() + 1,
           FillCellStarts{raw(sorted_source), sorted_source.size(), static_cast<std::uint32_t>(n), raw(offsets)});
    a.out.offsets.resize(n + 1);
    a.out.targets.resize(target.size());
    thrust::copy(offsets.begin(), offsets.end(), a.out.offsets.begin());
    thrust::copy(target.begin(), target.end(), a.out.targets.begin());
    for (std::size_t v = 0; v < n; ++v)
      a.out.max_degree = std::max(a.out.max_degree, a.out.offsets[v + 1] - a.out.offsets[v]);
    if (!scene.analysis.bfs_sources.empty()) {
      const std::vector<std::uint32_t> sources(scene.analysis.bfs_sources.begin(), scene.analysis.bfs_sources.end());
      DeviceCsr g(std::move(offsets), dvec<std::uint32_t>(target));
      a.bfs = bfs_queue_device(g, sources);
    }
    if (scene.analysis.components) {
      a.component = components_device(sorted_source, target, n);
      summarize_components(a);
    }
    return true;
  }

  std::size_t bytes() const override {
    const std::size_t n = tip_.size();
    return n * (4 + 24 + 24 + 24 + 8 + 1 + 4 + 4 + 4 + 4) + soma_start_.size() * 4 +
           pos_.capacity() * (24 + 8 + 2 + 1) + vel_.capacity() * 24 + grid_[0].size() * 8 + grid_[1].size() * 8;
  }

  std::string note() const override { return grid_field_note(scene_, cues_host_); }

 private:
  template <class T>
  void download_by_id(dvec<T>& by_slot, std::vector<T>& out) {
    dvec<T> by_id(by_slot.size());
    launch(by_slot.size(), ScatterBy<T>{raw(by_slot), raw(ids_), raw(by_id)});
    thrust::copy(by_id.begin(), by_id.end(), out.begin());
  }

  void build_somas(const Placement& placement) {
    const GridGeometry g = soma_grid_geometry(scene_);
    soma_geometry_ = g;
    const std::size_t n = placement.soma.size();
    const dvec<Vec3> pos(placement.soma.begin(), placement.soma.end());
    dvec<std::uint32_t> keys(n);
    ids_.resize(n);
    const core::CellGridView geometry{g.origin, g.cell, g.nx, g.ny, g.nz, nullptr, nullptr, nullptr};
    launch(n, SomaKeys{raw(pos), geometry, raw(keys), raw(ids_)});
    sort_and_find_starts(keys, ids_, g.cells(), soma_start_);
    soma_pos_.resize(n);
    launch(n, GatherBy<Vec3>{raw(pos), raw(ids_), raw(soma_pos_)});
  }

  core::CellGridView somas_view() const {
    const GridGeometry& g = soma_geometry_;
    return {g.origin, g.cell, g.nx, g.ny, g.nz, raw(soma_start_), raw(ids_), raw(soma_pos_)};
  }

  void init_field() {
    check_grid_field(scene_, cues_host_);
    cues_.assign(cues_host_.begin(), cues_host_.end());
    if (scene_.cues.field == FieldKind::kParticles) {
      particle_start_.assign(hash_.buckets() + 1, 0);
    } else if (scene_.cues.field == FieldKind::kGrid) {
      const std::size_t nodes = grid_geometry_.nodes();
      grid_[0].assign(cues_host_.size() * nodes, 0.0);
      cur_.assign(cues_host_.size(), 0);
      if (scene_.cues.grid.scheme == GridScheme::kExplicit) {
        grid_[1].assign(cues_host_.size() * nodes, 0.0);
        for (const auto& cue : cues_host_) substeps_.push_back(explicit_substeps(cue, grid_geometry_.h, scene_.dt));
      } else {
        lod_cp_.resize(nodes);
        lod_dp_.resize(nodes);
      }
    }
  }

  CueFields fields() {
    CueFields f{};
    f.kind = scene_.cues.field;
    f.d_cues = raw(cues_);
    f.cue_count = static_cast<int>(cues_host_.size());
    f.sense = sense_;
    f.particles = particle_view();
    f.grids = grid_set();
    return f;
  }

  core::HashGridView particle_view() {
    return {hash_.origin, hash_.cell, hash_.dim, raw(particle_start_), raw(particle_index_), raw(sorted_pos_),
            raw(sorted_source_)};
  }

  core::GridFieldSet grid_set() {
    core::GridFieldSet set{grid_geometry_.origin, grid_geometry_.h, grid_geometry_.n, {}};
    for (std::size_t k = 0; k < cur_.size(); ++k) set.c[k] = raw(grid_[cur_[k]]) + k * grid_geometry_.nodes();
    return set;
  }

  void advance_field(std::uint32_t step, PhaseTimes& times) {
    switch (scene_.cues.field) {
      case FieldKind::kParticles: advance_particles(step, times); break;
      case FieldKind::kGrid: {
        ScopedPhase p(times, step,
                      scene_.cues.grid.scheme == GridScheme::kExplicit ? "grid.explicit" : "grid.implicit");
        for (std::size_t k = 0; k < cues_host_.size(); ++k) {
          if (scene_.cues.grid.scheme == GridScheme::kExplicit) explicit_step(k, step);
          else implicit_step(k, step);
        }
        break;
      }
      case FieldKind::kAnalytic: break;
    }
  }

  void advance_particles(std::uint32_t step, PhaseTimes& times) {
    const bool ballistic = scene_.cues.particles.motion == Motion::kBallistic;
    {
      ScopedPhase p(times, step, "particles.emit");
      std::vector<std::uint32_t> offsets(cues_host_.size() + 1, 0);
      for (std::size_t k = 0; k < cues_host_.size(); ++k)
        offsets[k + 1] = offsets[k] + core::emitted_at(cues_host_[k].emission, step);
      const std::uint32_t emitted = offsets.back();
      if (emitted > 0) {
        const std::size_t first = pos_.size();
        pos_.resize(first + emitted);
        id_.resize(first + emitted);
        source_.resize(first + emitted);
        if (ballistic) vel_.resize(first + emitted);
        const dvec<std::uint32_t> d_offsets(offsets.begin(), offsets.end());
        launch(emitted, EmitParticles{next_id_, first, raw(d_offsets), static_cast<int>(cues_host_.size()), raw(cues_),
                                      ballistic, particle_params_, scene_.seed, step, raw(pos_), raw(vel_), raw(id_),
                                      raw(source_)});
        next_id_ += emitted;
      }
    }
    {
      ScopedPhase p(times, step, "particles.move");
      keep_.resize(pos_.size());
      launch(pos_.size(), MoveParticles{raw(id_), raw(source_), raw(cues_), particle_params_, ballistic, scene_.seed,
                                        step, raw(pos_), raw(vel_), raw(keep_)});
    }
    {
      ScopedPhase p(times, step, "particles.compact");
      compact_particles(ballistic);
    }
    {
      ScopedPhase p(times, step, "particles.grid");
      build_particle_grid();
    }
    if (particle_params_.collisions) {
      ScopedPhase p(times, step, "particles.collide");
      launch(pos_.size(), Collide{particle_view(), particle_params_, ballistic, raw(pos_), raw(vel_)});
      build_particle_grid();
    }
  }

  void compact_particles(bool ballistic) {
    const std::size_t n = pos_.size();
    const std::size_t kept = static_cast<std::size_t>(thrust::count_if(thrust::device, keep_.begin(), keep_.end(), IsKept{}));
    if (kept == n) return;
    auto compact = [&](auto& v, auto& scratch) {
      scratch.resize(kept);
      thrust::copy_if(thrust::device, v.begin(), v.end(), keep_.begin(), scratch.begin(), IsKept{});
      v.swap(scratch);
    };
    compact(pos_, pos_scratch_);
    compact(id_, id_scratch_);
    compact(source_, source_scratch_);
    if (ballistic) compact(vel_, vel_scratch_);
  }

  void build_particle_grid() {
    const std::size_t n = pos_.size();
    particle_keys_.resize(n);
    particle_index_.resize(n);
    const core::HashGridView geometry{hash_.origin, hash_.cell, hash_.dim, nullptr, nullptr, nullptr, nullptr};
    launch(n, ParticleKeys{raw(pos_), geometry, raw(particle_keys_), raw(particle_index_)});
    sort_and_find_starts(particle_keys_, particle_index_, static_cast<std::uint32_t>(hash_.buckets()), particle_start_);
    sorted_pos_.resize(n);
    sorted_source_.resize(n);
    launch(n, GatherParticles{raw(pos_), raw(source_), raw(particle_index_), raw(sorted_pos_), raw(sorted_source_)});
  }

  double* grid_values(std::size_t k, int buffer) { return raw(grid_[buffer]) + k * grid_geometry_.nodes(); }

  void deposit(std::size_t k, std::uint32_t step, double fraction) {
    const double total = scene_.cues.particles.amount * core::emitted_at(cues_host_[k].emission, step) * fraction;
    if (total == 0.0) return;
    launch(1, Deposit{grid_values(k, cur_[k]),
                      core::source_deposit(cues_host_[k].position, total, grid_geometry_.origin, grid_geometry_.h,
                                           grid_geometry_.n)});
  }

  void explicit_step(std::size_t k, std::uint32_t step) {
    const std::uint32_t m = substeps_[k];
    const core::StencilParams s =
        stencil_params(grid_geometry_, cues_host_[k], scene_.dt / m, scene_.cues.grid.boundary == GridBoundary::kReflecting);
    for (std::uint32_t sub = 0; sub < m; ++sub) {
      deposit(k, step, 1.0 / m);
      launch(grid_geometry_.nodes(), Ftcs{grid_values(k, cur_[k]), grid_values(k, 1 - cur_[k]), s});
      cur_[k] = 1 - cur_[k];
    }
  }

  void implicit_step(std::size_t k, std::uint32_t step) {
    deposit(k, step, 1.0);
    const bool reflecting = scene_.cues.grid.boundary == GridBoundary::kReflecting;
    const core::StencilParams s = stencil_params(grid_geometry_, cues_host_[k], scene_.dt, reflecting);
    const std::size_t lines = static_cast<std::size_t>(grid_geometry_.n) * grid_geometry_.n;
    for (int axis = 0; axis < 3; ++axis)
      launch(lines, LodLines{grid_values(k, 0), raw(lod_cp_), raw(lod_dp_), grid_geometry_.n, axis, s.lambda, reflecting});
    launch(grid_geometry_.nodes(), Scale{grid_values(k, 0), 1.0 / (1.0 + s.decay_dt)});
  }

  const Scene& scene_;
  core::GrowthParams growth_;
  std::vector<core::CueParams> cues_host_;
  core::SenseParams sense_;
  core::SteerParams steer_;
  core::ParticleParams particle_params_;
  HashGeometry hash_;
  GridGeometry3 grid_geometry_;
  GridGeometry soma_geometry_;
  // Somas (sorted grid) and axons in slot order (slot k = neuron ids_[k]).
  dvec<std::uint32_t> ids_, soma_start_;
  dvec<Vec3> soma_pos_, tip_, heading_;
  dvec<double> length_;
  dvec<core::AxonStatus> status_;
  dvec<std::uint32_t> steps_, target_, target_by_id_, active_, active_next_;
  StepStats stats_;
  // Cues.
  dvec<core::CueParams> cues_;
  std::uint64_t next_id_ = 0;
  dvec<Vec3> pos_, vel_, sorted_pos_, pos_scratch_, vel_scratch_;
  dvec<std::uint64_t> id_, id_scratch_;
  dvec<std::uint16_t> source_, sorted_source_, source_scratch_;
  dvec<std::uint8_t> keep_;
  dvec<std::uint32_t> particle_keys_, particle_index_, particle_start_;
  dvec<double> grid_[2], lod_cp_, lod_dp_;
  std::vector<int> cur_;
  std::vector<std::uint32_t> substeps_;
};

std::unique_ptr<Engine> make_engine(const Scene& scene, const Placement& placement) {
  return std::make_unique<AccelEngine>(scene, placement);
}

BfsResult bfs_level_sync(const Csr& g, const std::vector<std::uint32_t>& sources) {
  return bfs_level_sync_device(DeviceCsr(g), sources);
}

BfsResult bfs_queue(const Csr& g, const std::vector<std::uint32_t>& sources) {
  return bfs_queue_device(DeviceCsr(g), sources);
}

std::vector<std::uint32_t> components(const Csr& g) {
  dvec<std::uint32_t> source, target;
  device_edges(g, source, target);
  return components_device(source, target, g.vertices());
}

}  // namespace axg::accel::AXG_ACCEL_NS

// Arbours on the accelerator (docs/scaling.md §2.6b): one thread per neuron runs
// morphology/arbour_step.hpp, the reference's own step, on the neuron's fixed pools of
// points, cones and trees. A phase that would not fit its pools stops before it starts and
// says how much it needs; the host grows the pools (every neuron's to at least twice what
// it holds) and runs that neuron on from the same phase. No phase is undone and none
// depends on the pools' sizes, so the bytes are the reference's.
// Part of the pipeline (../pipeline.inl); compiled once per build of it.
#pragma once

namespace axg::accel::AXG_ACCEL_NS {

using morphology::ArbourFail;
using morphology::ArbourRoom;
using morphology::Cone;

// A tree as the kernels keep it: morphology::Tree without its per-order counts, which the
// kernels count from the growing cones when S != 0 (DeviceArbour::mean_weight).
struct DeviceTree {
  std::uint8_t type = morphology::kAxonType;
  std::uint32_t born = 0;
  int growing = 0;
  int n = 0;
  double mean_weight = 1.0, grow = 0.0, branching = 0.0, probability = 0.0;
};

// One neuron's pools: where they start in the shared arrays, their capacities and what they
// hold; the phase its step has reached (3: done) and why it failed.
struct NeuronPool {
  std::uint64_t point_at = 0, cone_at = 0, tree_at = 0;
  std::uint32_t point_cap = 0, cone_cap = 0, tree_cap = 0;
  std::uint32_t points = 0, cones = 0, trees = 0, growing = 0;
  ArbourRoom need{};  // what the phase it stopped before needs beyond what it holds
  std::uint8_t phase = 3;
  ArbourFail fail = ArbourFail::kNone;
};

// The shared arrays (device pointers).
struct PoolArrays {
  NeuronPool* pool;
  Vec3* point;
  std::uint32_t* cone_of;
  std::uint32_t* step_of;
  std::uint32_t* parent;
  Cone* cone;
  std::uint32_t* last;
  std::uint32_t* growing;
  double* sums;  // sums_per_cone per cone slot (null without sums)
  std::uint32_t sums_per_cone;
  DeviceTree* tree;
};

// morphology/arbour_step.hpp's storage on one neuron's pools (their room checked first).
class DeviceArbour {
 public:
  AXG_HD DeviceArbour(const PoolArrays& a, NeuronPool& p) : a_(a), p_(p) {}
  AXG_HD bool fits(ArbourRoom r) const {
    return p_.points + r.points <= p_.point_cap && p_.cones + r.cones <= p_.cone_cap &&
           p_.trees + r.trees <= p_.tree_cap;
  }
  AXG_HD std::uint32_t point_count() const { return p_.points; }
  AXG_HD Vec3 point(std::uint32_t i) const { return a_.point[p_.point_at + i]; }
  AXG_HD std::uint32_t cone_of(std::uint32_t i) const { return a_.cone_of[p_.point_at + i]; }
  AXG_HD std::uint32_t parent_of(std::uint32_t i) const { return a_.parent[p_.point_at + i]; }
  AXG_HD std::uint32_t push_point(Vec3 at, std::uint32_t cone, std::uint32_t step, std::uint32_t parent) {
    const std::uint32_t i = p_.points++;
    const std::uint64_t k = p_.point_at + i;
    a_.point[k] = at;
    a_.cone_of[k] = cone;
    a_.step_of[k] = step;
    a_.parent[k] = parent;
    a_.last[p_.cone_at + cone] = i;
    return i;
  }
  AXG_HD std::uint32_t cone_count() const { return p_.cones; }
  AXG_HD Cone& cone(std::uint32_t c) { return a_.cone[p_.cone_at + c]; }
  AXG_HD const Cone& cone(std::uint32_t c) const { return a_.cone[p_.cone_at + c]; }
  AXG_HD std::uint32_t last_of(std::uint32_t c) const { return a_.last[p_.cone_at + c]; }
  AXG_HD void push_cone(const Cone& c) {
    const std::uint32_t i = p_.cones++;
    a_.cone[p_.cone_at + i] = c;
    a_.last[p_.cone_at + i] = morphology::kNoPoint;
    if (a_.sums_per_cone)
      for (std::uint32_t k = 0; k < a_.sums_per_cone; ++k) sums(i)[k] = 0.0;
  }
  AXG_HD double* sums(std::uint32_t c) {
    return a_.sums_per_cone ? a_.sums + (p_.cone_at + c) * a_.sums_per_cone : nullptr;
  }
  AXG_HD std::uint32_t sums_per_cone() const { return a_.sums_per_cone; }
  AXG_HD std::uint32_t tree_count() const { return p_.trees; }
  AXG_HD DeviceTree& tree(std::uint32_t t) { return a_.tree[p_.tree_at + t]; }
  AXG_HD void push_tree(std::uint8_t type, std::uint32_t born) {
    DeviceTree t;
    t.type = type;
    t.born = born;
    t.growing = 1;
    a_.tree[p_.tree_at + p_.trees++] = t;
  }
  AXG_HD void count_order(std::uint32_t, std::uint8_t, int) {}
  // C over tree t's growing cones: their counts per order, summed as core::mean_order_weight
  // sums the reference's running counts (the same integers, so the same sum).
  AXG_HD double mean_weight(std::uint32_t t, double s, int n) const {
    int counts[256];
    for (int g = 0; g < 256; ++g) counts[g] = 0;
    for (std::uint32_t g = 0; g < p_.growing; ++g) {
      const Cone& c = cone(growing(g));
      if (c.tree == t) ++counts[c.order];
    }
    return core::mean_order_weight(s, counts, 256, n);
  }
  AXG_HD std::uint32_t growing_count() const { return p_.growing; }
  AXG_HD std::uint32_t growing(std::uint32_t g) const { return a_.growing[p_.cone_at + g]; }
  AXG_HD void set_growing(std::uint32_t g, std::uint32_t cone) {
    a_.growing[p_.cone_at + g] = cone;
    if (g == p_.growing) ++p_.growing;
  }
  AXG_HD void resize_growing(std::uint32_t n) { p_.growing = n; }

 private:
  const PoolArrays& a_;
  NeuronPool& p_;
};

// The cue field's sample at x (core::FieldKind's sampler, as the axons' Steer).
struct FieldSampler {
  CueFields fields;
  AXG_HD void operator()(Vec3 x, core::CueSample* samples, Vec3* pull) const {
    sample_fields(x, fields, samples, pull);
  }
};

// Before a step: every neuron that may grow starts at phase 0 (a neuron without growing
// cones grows again only where stems or lateral branches start at a rate).
struct BeginArbourStep {
  NeuronPool* d_pool;
  std::uint32_t* d_stopped;  // 2 per neuron: cones stopped at a soma, at the bounds
  bool restarts;
  AXG_HD void operator()(std::size_t i) const {
    NeuronPool& p = d_pool[i];
    p.phase = p.growing == 0 && !restarts ? 3 : 0;
    p.need = ArbourRoom{};
    d_stopped[2 * i] = d_stopped[2 * i + 1] = 0;
  }
};

// The step of neuron d_todo[k], from the phase it reached, until it ends or a phase does
// not fit its pools.
struct StepArbours {
  const std::uint32_t* d_todo;
  PoolArrays arrays;
  morphology::ArbourStepContext ctx;  // ctx.guide is set from `guide` on the device
  core::GuideParams guide;
  bool steers;
  FieldSampler field;
  const Vec3* d_soma;  // by id
  std::uint32_t step;
  std::uint32_t* d_stopped;
  AXG_HD void operator()(std::size_t k) const {
    const std::uint32_t i = d_todo[k];
    NeuronPool& p = arrays.pool[i];
    DeviceArbour a(arrays, p);
    morphology::ArbourStepContext c = ctx;
    c.guide = steers ? &guide : nullptr;
    while (p.phase < 3) {
      ArbourRoom room;
      int events[2] = {0, 0};
      if (p.phase == 0) {
        room = morphology::cone_room(a);
      } else if (p.phase == 1) {
        morphology::lateral_events(c, i, step, a, events);
        room = morphology::lateral_room(events);
      } else {
        morphology::stem_events(c, i, step, events);
        room = morphology::stem_room(events);
      }
      if (!a.fits(room)) {
        p.need = room;
        return;
      }
      bool ok = true;
      if (p.phase == 0) {
        std::uint32_t stopped[2] = {0, 0};
        ok = morphology::grow_cones(c, field, i, step, a, stopped, &p.fail);
        d_stopped[2 * i] = stopped[0];
        d_stopped[2 * i + 1] = stopped[1];
      } else if (p.phase == 1) {
        ok = morphology::lateral_branches(c, i, step, events, a, &p.fail);
      } else {
        ok = morphology::new_stems(c, i, d_soma[i], step, events, a, &p.fail);
      }
      p.phase = ok ? static_cast<std::uint8_t>(p.phase + 1) : 3;
    }
  }
};

struct PoolPending {
  const NeuronPool* d_pool;
  AXG_HD bool operator()(std::uint32_t i) const {
    return d_pool[i].phase < 3 && d_pool[i].fail == ArbourFail::kNone;
  }
};
struct PoolFailed {
  const NeuronPool* d_pool;
  AXG_HD bool operator()(std::uint32_t i) const { return d_pool[i].fail != ArbourFail::kNone; }
};
struct GrowingNeuron {
  const NeuronPool* d_pool;
  bool restarts;
  AXG_HD bool operator()(std::uint32_t i) const { return d_pool[i].growing > 0 || restarts; }
};

// A neuron's contents from its old room (from.pool) to its new (d_new), which never overlap.
struct MovePools {
  const std::uint32_t* d_ids;  // the neurons to move (null: all, by index)
  PoolArrays from;
  PoolArrays to;
  const NeuronPool* d_new;
  AXG_HD void operator()(std::size_t k) const {
    const std::size_t i = d_ids ? d_ids[k] : k;
    const NeuronPool& o = from.pool[i];
    const NeuronPool& n = d_new[i];
    for (std::uint32_t k = 0; k < o.points; ++k) {
      to.point[n.point_at + k] = from.point[o.point_at + k];
      to.cone_of[n.point_at + k] = from.cone_of[o.point_at + k];
      to.step_of[n.point_at + k] = from.step_of[o.point_at + k];
      to.parent[n.point_at + k] = from.parent[o.point_at + k];
    }
    for (std::uint32_t k = 0; k < o.cones; ++k) {
      to.cone[n.cone_at + k] = from.cone[o.cone_at + k];
      to.last[n.cone_at + k] = from.last[o.cone_at + k];
    }
    for (std::uint32_t k = 0; k < o.growing; ++k) to.growing[n.cone_at + k] = from.growing[o.cone_at + k];
    const std::uint64_t m = from.sums_per_cone;
    for (std::uint64_t k = 0; k < o.cones * m; ++k) to.sums[n.cone_at * m + k] = from.sums[o.cone_at * m + k];
    for (std::uint32_t k = 0; k < o.trees; ++k) to.tree[n.tree_at + k] = from.tree[o.tree_at + k];
  }
};

// Every neuron's arbour in fixed pools on the device.
class ArbourPools {
 public:
  explicit ArbourPools(std::uint32_t sums_per_cone) : m_(sums_per_cone) {}

  // The arbours from the host (at the start and from a checkpoint), each neuron's pools
  // twice what it holds plus a little.
  void upload(const std::vector<morphology::Arbour>& arbours) {
    const std::size_t n = arbours.size();
    std::vector<NeuronPool> pool(n);
    for (std::size_t i = 0; i < n; ++i) {
      const morphology::Arbour& a = arbours[i];
      NeuronPool& p = pool[i];
      p.points = static_cast<std::uint32_t>(a.point.size());
      p.cones = static_cast<std::uint32_t>(a.cones.size());
      p.trees = static_cast<std::uint32_t>(a.trees.size());
      p.growing = static_cast<std::uint32_t>(a.growing.size());
    }
    const std::vector<NeuronPool> layout = lay_out(pool);
    resize(ends_);
    // Host copies in the new layout, then one upload per array.
    std::vector<Vec3> point(point_.size());
    std::vector<std::uint32_t> cone_of(point.size()), step_of(point.size()), parent(point.size());
    std::vector<Cone> cone(cone_.size());
    std::vector<std::uint32_t> last(cone.size()), growing(cone.size());
    std::vector<double> sums(sums_.size());
    std::vector<DeviceTree> tree(tree_.size());
    std::vector<std::uint32_t> parents;
    for (std::size_t i = 0; i < n; ++i) {
      const morphology::Arbour& a = arbours[i];
      const NeuronPool& p = layout[i];
      morphology::point_parents(a, parents);
      std::copy(a.point.begin(), a.point.end(), point.begin() + static_cast<std::ptrdiff_t>(p.point_at));
      std::copy(a.cone_of.begin(), a.cone_of.end(), cone_of.begin() + static_cast<std::ptrdiff_t>(p.point_at));
      std::copy(a.step_of.begin(), a.step_of.end(), step_of.begin() + static_cast<std::ptrdiff_t>(p.point_at));
      std::copy(parents.begin(), parents.end(), parent.begin() + static_cast<std::ptrdiff_t>(p.point_at));
      std::copy(a.cones.begin(), a.cones.end(), cone.begin() + static_cast<std::ptrdiff_t>(p.cone_at));
      std::copy(a.last.begin(), a.last.end(), last.begin() + static_cast<std::ptrdiff_t>(p.cone_at));
      std::copy(a.growing.begin(), a.growing.end(), growing.begin() + static_cast<std::ptrdiff_t>(p.cone_at));
      std::copy(a.sums.begin(), a.sums.end(), sums.begin() + static_cast<std::ptrdiff_t>(p.cone_at * m_));
      for (std::size_t t = 0; t < a.trees.size(); ++t) {
        DeviceTree& d = tree[p.tree_at + t];
        d.type = a.trees[t].type;
        d.born = a.trees[t].born;
        d.growing = a.trees[t].growing;
      }
    }
    pool_.assign(layout.begin(), layout.end());
    thrust::copy(point.begin(), point.end(), point_.begin());
    thrust::copy(cone_of.begin(), cone_of.end(), cone_of_.begin());
    thrust::copy(step_of.begin(), step_of.end(), step_of_.begin());
    thrust::copy(parent.begin(), parent.end(), parent_.begin());
    thrust::copy(cone.begin(), cone.end(), cone_.begin());
    thrust::copy(last.begin(), last.end(), last_.begin());
    thrust::copy(growing.begin(), growing.end(), growing_.begin());
    thrust::copy(sums.begin(), sums.end(), sums_.begin());
    thrust::copy(tree.begin(), tree.end(), tree_.begin());
  }

  // The arbours as the reference holds them; a tree's per-order counts are its growing
  // cones' (what the reference's running counts hold).
  void download(std::vector<morphology::Arbour>& out, bool growth_state) const {
    const std::vector<NeuronPool> pool = host(pool_);
    const std::vector<Vec3> point = host(point_);
    const std::vector<std::uint32_t> cone_of = host(cone_of_), step_of = host(step_of_);
    const std::vector<Cone> cone = host(cone_);
    const std::vector<std::uint32_t> last = host(last_), growing = host(growing_);
    const std::vector<double> sums = host(sums_);
    const std::vector<DeviceTree> tree = host(tree_);
    out.resize(pool.size());
    for (std::size_t i = 0; i < pool.size(); ++i) {
      const NeuronPool& p = pool[i];
      morphology::Arbour& a = out[i];
      const auto pts = [&](const auto& v) {
        return std::vector<typename std::decay_t<decltype(v)>::value_type>(
            v.begin() + static_cast<std::ptrdiff_t>(p.point_at),
            v.begin() + static_cast<std::ptrdiff_t>(p.point_at + p.points));
      };
      a.point = pts(point);
      a.cone_of = pts(cone_of);
      a.step_of = pts(step_of);
      a.cones.assign(cone.begin() + static_cast<std::ptrdiff_t>(p.cone_at),
                     cone.begin() + static_cast<std::ptrdiff_t>(p.cone_at + p.cones));
      a.trees.resize(p.trees);
      for (std::uint32_t t = 0; t < p.trees; ++t) {
        const DeviceTree& d = tree[p.tree_at + t];
        a.trees[t].type = d.type;
        a.trees[t].born = d.born;
        a.trees[t].growing = d.growing;
        a.trees[t].by_order.clear();
      }
      if (!growth_state) continue;
      a.last.assign(last.begin() + static_cast<std::ptrdiff_t>(p.cone_at),
                    last.begin() + static_cast<std::ptrdiff_t>(p.cone_at + p.cones));
      a.growing.assign(growing.begin() + static_cast<std::ptrdiff_t>(p.cone_at),
                       growing.begin() + static_cast<std::ptrdiff_t>(p.cone_at + p.growing));
      a.sums.assign(sums.begin() + static_cast<std::ptrdiff_t>(p.cone_at * m_),
                    sums.begin() + static_cast<std::ptrdiff_t>((p.cone_at + p.cones) * m_));
      for (const std::uint32_t g : a.growing) {
        const Cone& c = a.cones[g];
        std::vector<int>& b = a.trees[c.tree].by_order;
        if (b.size() <= c.order) b.resize(c.order + 1u, 0);
        ++b[c.order];
      }
    }
  }

  // One step of every neuron; the pools grow as the phases ask. Returns the cones stopped
  // at a soma and at the bounds, and the neurons still growing.
  struct StepCounts {
    std::uint64_t soma = 0, exited = 0, growing_neurons = 0;
  };
  StepCounts step(const morphology::ArbourStepContext& ctx, const core::GuideParams& guide, bool steers,
                  const FieldSampler& field, const dvec<Vec3>& soma, std::uint32_t step, bool restarts) {
    const std::size_t n = pool_.size();
    stopped_.resize(2 * n);
    launch(n, BeginArbourStep{raw(pool_), raw(stopped_), restarts});
    todo_.resize(n);
    thrust::sequence(todo_.begin(), todo_.end());
    for (;;) {
      launch(todo_.size(), StepArbours{raw(todo_), arrays(), ctx, guide, steers, field, raw(soma), step, raw(stopped_)});
      fail_check();
      dvec<std::uint32_t> pending(todo_.size());
      const auto end = thrust::copy_if(thrust::device, todo_.begin(), todo_.end(), pending.begin(), PoolPending{raw(pool_)});
      pending.resize(static_cast<std::size_t>(end - pending.begin()));
      if (pending.empty()) break;
      grow_pools(pending);
      todo_.swap(pending);
    }
    StepCounts c;
    const std::vector<std::uint32_t> stopped = host(stopped_);
    for (std::size_t i = 0; i < n; ++i) {  // integers: any order
      c.soma += stopped[2 * i];
      c.exited += stopped[2 * i + 1];
    }
    c.growing_neurons = static_cast<std::uint64_t>(
        thrust::count_if(thrust::device, thrust::counting_iterator<std::uint32_t>(0),
                         thrust::counting_iterator<std::uint32_t>(static_cast<std::uint32_t>(n)),
                         GrowingNeuron{raw(pool_), restarts}));
    return c;
  }

  std::size_t bytes() const {
    return pool_.size() * sizeof(NeuronPool) + point_.capacity() * (sizeof(Vec3) + 12) +
           cone_.capacity() * (sizeof(Cone) + 8) + sums_.capacity() * 8 + tree_.capacity() * sizeof(DeviceTree) +
           todo_.capacity() * 4 + stopped_.size() * 4;
  }

 private:
  template <class T>
  static std::vector<T> host(const dvec<T>& v) {
    std::vector<T> out(v.size());
    thrust::copy(v.begin(), v.end(), out.begin());
    return out;
  }

  PoolArrays arrays() {
    return {raw(pool_), raw(point_), raw(cone_of_), raw(step_of_), raw(parent_), raw(cone_), raw(last_), raw(growing_),
            m_ ? raw(sums_) : nullptr, m_, raw(tree_)};
  }

  static std::uint32_t grown(std::uint32_t cap, std::uint32_t held, std::uint32_t need, std::uint32_t start) {
    const std::uint64_t want = 2ull * (static_cast<std::uint64_t>(held) + need) + start;
    if (want > 0xffffffffull) throw RunError("arbours: a neuron's pool on the accelerator passed 2^32 entries");
    return std::max(cap, static_cast<std::uint32_t>(want));
  }
  // A neuron's capacities: twice what it holds and what its waiting phase needs (plus a
  // start of 64 points, 16 cones and 4 trees).
  static void grow(NeuronPool& p) {
    p.point_cap = grown(p.point_cap, p.points, p.need.points, 64);
    p.cone_cap = grown(p.cone_cap, p.cones, p.need.cones, 16);
    p.tree_cap = grown(p.tree_cap, p.trees, p.need.trees, 4);
    p.need = ArbourRoom{};
  }

  // Every neuron's pools grown and packed in neuron order.
  std::vector<NeuronPool> lay_out(std::vector<NeuronPool> out) {
    std::uint64_t points = 0, cones = 0, trees = 0;
    for (NeuronPool& p : out) {
      grow(p);
      p.point_at = points;
      p.cone_at = cones;
      p.tree_at = trees;
      points += p.point_cap;
      cones += p.cone_cap;
      trees += p.tree_cap;
    }
    ends_ = {points, cones, trees};
    holes_ = 0;
    return out;
  }

  // The pools of the neurons that wait, grown. Each moves to new room at the arrays' ends
  // (which grow geometrically), leaving a hole; when the holes pass what the arrays hold
  // live, every neuron is grown and packed again. Either way a neuron's contents are only
  // moved, never changed.
  void grow_pools(const dvec<std::uint32_t>& pending) {
    std::vector<NeuronPool> now = host(pool_);
    const std::vector<std::uint32_t> ids = host(pending);
    std::uint64_t freed = 0;
    for (const std::uint32_t i : ids)
      freed += now[i].point_cap * (sizeof(Vec3) + 12) + now[i].cone_cap * (sizeof(Cone) + 12 + 8 * m_);
    const std::uint64_t live = ends_.points * (sizeof(Vec3) + 12) + ends_.cones * (sizeof(Cone) + 12 + 8 * m_);
    if (holes_ + freed > live - holes_ - freed) {
      relayout(lay_out(now));
      return;
    }
    holes_ += freed;
    for (const std::uint32_t i : ids) {
      NeuronPool& p = now[i];
      grow(p);
      p.point_at = ends_.points;
      p.cone_at = ends_.cones;
      p.tree_at = ends_.trees;
      ends_.points += p.point_cap;
      ends_.cones += p.cone_cap;
      ends_.trees += p.tree_cap;
    }
    resize(ends_);
    const dvec<NeuronPool> moved(now.begin(), now.end());
    launch(ids.size(), MovePools{raw(pending), arrays(), arrays(), raw(moved)});
    pool_ = moved;
  }

  struct Ends {
    std::uint64_t points = 0, cones = 0, trees = 0;
  };
  // The arrays at the given ends, their capacity doubled when they pass it.
  template <class T>
  static void resize_to(dvec<T>& v, std::uint64_t n) {
    if (n > v.capacity()) v.reserve(std::max<std::uint64_t>(n, 2 * v.capacity()));
    v.resize(n);
  }
  void resize(Ends e) {
    resize_to(point_, e.points);
    resize_to(cone_of_, e.points);
    resize_to(step_of_, e.points);
    resize_to(parent_, e.points);
    resize_to(cone_, e.cones);
    resize_to(last_, e.cones);
    resize_to(growing_, e.cones);
    resize_to(sums_, e.cones * m_);
    resize_to(tree_, e.trees);
  }

  void relayout(const std::vector<NeuronPool>& layout) {
    ArbourPools next(m_);
    next.resize(ends_);
    next.pool_.assign(layout.begin(), layout.end());
    launch(layout.size(), MovePools{nullptr, arrays(), next.arrays(), raw(next.pool_)});
    pool_.swap(next.pool_);
    point_.swap(next.point_);
    cone_of_.swap(next.cone_of_);
    step_of_.swap(next.step_of_);
    parent_.swap(next.parent_);
    cone_.swap(next.cone_);
    last_.swap(next.last_);
    growing_.swap(next.growing_);
    sums_.swap(next.sums_);
    tree_.swap(next.tree_);
  }

  // A failed step: the lowest failing neuron's error, as the reference reports it.
  void fail_check() {
    if (thrust::count_if(thrust::device, thrust::counting_iterator<std::uint32_t>(0),
                         thrust::counting_iterator<std::uint32_t>(static_cast<std::uint32_t>(pool_.size())),
                         PoolFailed{raw(pool_)}) == 0)
      return;
    const std::vector<NeuronPool> pool = host(pool_);
    for (std::size_t i = 0; i < pool.size(); ++i)
      if (pool[i].fail != ArbourFail::kNone) arbour_fail(pool[i].fail, static_cast<std::uint32_t>(i));
  }

  std::uint32_t m_;
  Ends ends_;                  // where the arrays' used room ends
  std::uint64_t holes_ = 0;    // bytes of room left behind by grown neurons
  dvec<NeuronPool> pool_;
  dvec<Vec3> point_;
  dvec<std::uint32_t> cone_of_, step_of_, parent_;
  dvec<Cone> cone_;
  dvec<std::uint32_t> last_, growing_;
  dvec<double> sums_;
  dvec<DeviceTree> tree_;
  dvec<std::uint32_t> todo_, stopped_;
};

}  // namespace axg::accel::AXG_ACCEL_NS

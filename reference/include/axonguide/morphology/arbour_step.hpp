#pragma once
// One step of one neuron's arbour (SPEC §3.8; docs/methods.md §2.12), written once for
// both engines: the reference's arbour engine runs it on std::vector storage
// (engine/arbour_engine.cpp), the accelerator's kernels on fixed per-neuron pools
// (accel/src/pipeline/arbours.inl). The storage is a template parameter `A` with:
//   points: point_count(), point(i), cone_of(i), parent_of(i), push_point(at, cone, step, parent)
//   cones:  cone_count(), cone(c), last_of(c), push_cone(cone) (its sums zero), sums(c), sums_per_cone()
//   trees:  tree_count(), tree(t) (.type .born .growing, and the step's .n .mean_weight .grow
//           .branching .probability), push_tree(type, born),
//           count_order(t, order, delta), mean_weight(t, s, n) (core::mean_order_weight over the
//           tree's growing cones by order)
//   growing cones: growing_count(), growing(g), set_growing(g, cone) (g <= count), resize_growing(n)
// A step is three phases (cones; lateral branches; new stems), each of which first says how
// many points, cones and trees it adds at most, so that a fixed pool can be grown before
// the phase runs and no phase is ever undone (room()). Every draw is keyed on (neuron,
// cone index) or the neuron, and the cones go in index order, so the bytes are the same for
// any schedule and either engine.
#include <cstdint>

#include "axonguide/core/arbour.hpp"
#include "axonguide/core/branching.hpp"
#include "axonguide/core/cellgrid.hpp"
#include "axonguide/core/guide.hpp"
#include "axonguide/core/growth.hpp"
#include "axonguide/core/hd.hpp"
#include "axonguide/core/pmath.hpp"
#include "axonguide/core/random.hpp"
#include "axonguide/morphology/arbour.hpp"
#include "axonguide/morphology/arbour_rules.hpp"

namespace axg::morphology {

// Why a step could not go on (the host reports it as a run error).
enum class ArbourFail : std::uint8_t {
  kNone = 0,
  kCones = 1,  // a neuron has grown core::kConesPerNeuron cones (the most its cone ids hold)
  kTrees = 2,  // a neuron has started 65535 stems (the most its tree ids hold)
};

// What every neuron's step shares.
struct ArbourStepContext {
  ArbourRules rules;
  core::GrowthParams growth;     // contact radius, bounds and rule
  core::CellGridView somas;
  std::uint64_t seed = 0;
  double dt = 0.0;
  double soma_radius = 0.0;
  std::uint32_t last_step = 0;   // the scene's steps: every cone makes a point at its end
  // Cue steering (core/guide.hpp, the axons' body); guide null: no cues.
  const core::GuideParams* guide = nullptr;
  core::Decision decision{};     // this step's place in its decision interval
  bool sums = false;             // the cones keep decision-interval sums (Arbour::sums)
};

// At most this many points, cones and trees a phase adds.
struct ArbourRoom {
  std::uint32_t points = 0, cones = 0, trees = 0;
};

// Poisson(m) by inversion of one uniform in (0, 1) (m is small: events per step).
AXG_HDI int poisson(double m, double u) {
  double p = core::pm::exp(-m), f = p;
  int k = 0;
  while (u > f && k < 1000) {
    ++k;
    p = p * m / static_cast<double>(k);
    f += p;
  }
  return k;
}

// A point at the end of cone c's path so far; it hangs on the cone's last point, or, for
// its first, on its branch point (a lateral branch's attach point, or its parent's last
// point), or on nothing (a stem's first point).
template <class A>
AXG_HDI std::uint32_t add_point(A& a, std::uint32_t c, core::Vec3 at, std::uint32_t step) {
  const Cone& k = a.cone(c);
  std::uint32_t b = a.last_of(c);
  if (b == kNoPoint && k.parent != kNoCone) b = k.attach != kNoPoint ? k.attach : a.last_of(k.parent);
  a.cone(c).unsampled = 0.0;
  return a.push_point(at, c, step, b);
}

template <class A>
AXG_HDI bool cone_index(A& a, std::uint32_t* index, ArbourFail* fail) {
  if (a.cone_count() >= core::kConesPerNeuron) {
    *fail = ArbourFail::kCones;
    return false;
  }
  *index = a.cone_count();
  return true;
}

// A new stem of `type` at the end of step `born`: its own tree, its start on the soma's
// surface (raised to its height in a culture's growth layer), its heading and rate factor
// drawn on (seed, kConeBirth, cone, 0).
template <class A>
AXG_HDI bool new_stem(const ArbourStepContext& ctx, std::uint32_t neuron, core::Vec3 soma, std::uint8_t type,
                      std::uint32_t born, A& a, ArbourFail* fail) {
  std::uint32_t index = 0;
  if (!cone_index(a, &index, fail)) return false;
  if (a.tree_count() >= 0xffffu) {
    *fail = ArbourFail::kTrees;
    return false;
  }
  const ConeRules& p = ctx.rules.of(type);
  core::Rng rng(ctx.seed, core::Stream::kConeBirth, core::cone_key(neuron, index), 0);
  Cone c;
  c.heading = core::stem_heading(ctx.rules.planar, rng);
  c.rate = core::rate_factor(p.geometry.rate_sigma, rng);
  const double height = ctx.rules.planar ? ctx.rules.slab * rng.uniform_co() : 0.0;
  c.tip = soma + ctx.soma_radius * c.heading + core::Vec3{0.0, 0.0, height};
  c.born = c.ended = born;
  c.type = type;
  c.tree = static_cast<std::uint16_t>(a.tree_count());
  a.push_tree(type, born);
  a.push_cone(c);
  a.push_point(c.tip, index, born, kNoPoint);
  a.set_growing(a.growing_count(), index);
  return true;
}

// The cue stage of one growing cone (core::guide_axon, the axons' body): its sample, and
// its decision at the interval's end (kept in the plane in a culture). A cone steers on an
// interval's sums only when it held them from the interval's start (Cone::evidence).
template <class A, class Field>
AXG_HDI void steer_cone(const ArbourStepContext& ctx, const Field& field, std::uint64_t key, core::Vec3 at,
                        std::uint32_t c, A& a) {
  Cone& cone = a.cone(c);
  if (ctx.sums) {
    if (ctx.decision.open) cone.evidence = true;
    if (!cone.evidence) return;
  }
  core::CueSample samples[core::kMaxCues];
  core::Vec3 pull[core::kMaxCues];
  field(at, samples, pull);
  const core::GuidedAxon g{&cone.heading, nullptr, nullptr, 0.0, ctx.sums ? a.sums(c) : nullptr};
  core::guide_axon(*ctx.guide, samples, pull, g, key, ctx.decision);
  if (ctx.rules.planar) cone.heading = core::in_plane(cone.heading);
}

// ---- Phase 1: the growing cones. ----

// Each growing cone adds at most one point (it moves, stops or branches) and two cones.
template <class A>
AXG_HDI ArbourRoom cone_room(const A& a) {
  return {a.growing_count(), 2u * a.growing_count(), 0u};
}

// Every growing cone in `growing` order: it steers by the cues (the per-step rule: before it
// moves), elongates by v0 n^-F dt times its rate factor, moves, meets a soma or the bounds,
// takes its heading's random walk and steers (the continuum rule: on its path, after it
// moves); then it may branch into two daughters (the next indices). The cones still growing
// keep their order, and the daughters follow. `stopped[0]` and `[1]` count the cones that
// stopped at a soma and at the bounds.
template <class A, class Field>
AXG_HDI bool grow_cones(const ArbourStepContext& ctx, const Field& field, std::uint32_t neuron, std::uint32_t step,
                        A& a, std::uint32_t stopped[2], ArbourFail* fail) {
  const ArbourRules& P = ctx.rules;
  const double dt = ctx.dt;
  const double t0 = static_cast<double>(step - 1) * dt;
  const bool steers = ctx.guide != nullptr;
  const bool after = steers && ctx.guide->after_move;
  const std::uint32_t n_growing = a.growing_count();
  const std::uint32_t first_daughter = a.cone_count();
  // What a tree's cones share over the step, from n and C at its start (the rule holds
  // them over the step): the elongation v0 n^-F dt, the branching exponent's tree part, C,
  // and (S = 0: no order dependence) the branching probability itself.
  for (std::uint32_t t = 0; t < a.tree_count(); ++t) {
    auto& tree = a.tree(t);
    tree.n = tree.growing;
    if (tree.n == 0) continue;
    const ConeRules& p = P.of(tree.type);
    const double s = p.branching.s;
    tree.mean_weight = s == 0.0 ? 1.0 : a.mean_weight(t, s, tree.n);
    tree.grow = core::elongation(p.elongation, tree.n, dt);
    tree.branching = core::tree_branching(p.branching, t0 - static_cast<double>(tree.born) * dt, dt, tree.n);
    tree.probability = core::cone_branch_probability(tree.branching, s, 0, tree.mean_weight);  // S = 0: every cone's
  }
  std::uint32_t kept = 0;
  for (std::uint32_t g = 0; g < n_growing; ++g) {
    const std::uint32_t idx = a.growing(g);
    const std::uint64_t key = core::cone_key(neuron, idx);
    if (steers && !after) steer_cone(ctx, field, key, a.cone(idx).tip, idx, a);
    const Cone c0 = a.cone(idx);
    const ConeRules& p = P.of(c0.type);
    const auto& tree = a.tree(c0.tree);
    const double l = tree.grow * c0.rate;
    // Move, then contact and bounds (core/growth.hpp's step; contact only when cones stop at somas).
    core::AxonStep st;
    if (P.stop_at_soma) {
      st = core::grow_axon(neuron, c0.tip, c0.heading, l, ctx.growth, ctx.somas);
    } else {
      const core::Vec3 to = c0.tip + l * c0.heading;
      st = {to, l, core::outside_bounds(to, ctx.growth) ? core::AxonStatus::kExited : core::AxonStatus::kGrowing,
            core::kNoNeuron};
    }
    {
      Cone& c = a.cone(idx);
      c.tip = st.tip;
      c.length += st.advanced;
      c.unsampled += st.advanced;
      c.ended = step;
    }
    if (st.status != core::AxonStatus::kGrowing) {
      Cone& c = a.cone(idx);
      c.status = st.status == core::AxonStatus::kConnected ? ConeStatus::kSoma : ConeStatus::kExited;
      ++stopped[st.status == core::AxonStatus::kConnected ? 0 : 1];
      --a.tree(c.tree).growing;
      a.count_order(c.tree, c.order, -1);
      add_point(a, idx, c.tip, step);
      continue;
    }
    {
      Cone& c = a.cone(idx);
      c.heading = core::cone_wander(c.heading, l, p.geometry, ctx.seed, key, step);
    }
    if (after) {
      double moved = l;
      steer_cone(ctx, field, key, core::sample_point(*ctx.guide, a.cone(idx).tip, a.cone(idx).heading, &moved), idx,
                 a);
    }
    const Cone& c = a.cone(idx);
    const double q = p.branching.s == 0.0
                         ? tree.probability
                         : core::cone_branch_probability(tree.branching, p.branching.s, c.order, tree.mean_weight);
    if (!(q > 0.0) || !core::branches(q, ctx.seed, key, step)) {
      if (c.unsampled >= P.sample_length || step == ctx.last_step) add_point(a, idx, c.tip, step);
      a.set_growing(kept++, idx);
      continue;
    }
    // Two daughters take the next indices; the parent's segment ends at the branch point.
    add_point(a, idx, c.tip, step);
    const Cone parent = a.cone(idx);  // a reference dangles once the daughters are pushed
    core::Vec3 h[2];
    core::daughter_headings(parent.heading, p.geometry, ctx.seed, key, step, &h[0], &h[1]);
    a.cone(idx).status = ConeStatus::kBranched;
    const std::uint8_t order = parent.order == 255 ? 255 : static_cast<std::uint8_t>(parent.order + 1);
    a.count_order(parent.tree, parent.order, -1);
    a.count_order(parent.tree, order, 2);
    ++a.tree(parent.tree).growing;
    for (int d = 0; d < 2; ++d) {
      std::uint32_t index = 0;
      if (!cone_index(a, &index, fail)) return false;
      core::Rng rng(ctx.seed, core::Stream::kConeBirth, core::cone_key(neuron, index), 0);
      Cone child;
      child.tip = parent.tip;
      child.heading = h[d];
      child.rate = core::rate_factor(p.geometry.rate_sigma, rng);
      child.parent = idx;
      child.born = child.ended = step;
      child.tree = parent.tree;
      child.type = parent.type;
      child.order = order;
      child.evidence = parent.evidence;  // and its parent's sums
      a.push_cone(child);
      if (ctx.sums) {
        const double* from = a.sums(idx);
        double* to = a.sums(index);
        for (std::uint32_t k = 0; k < a.sums_per_cone(); ++k) to[k] = from[k];
      }
    }
  }
  // The daughters, in index order, after the cones that go on growing.
  for (std::uint32_t d = first_daughter; d < a.cone_count(); ++d) a.set_growing(kept++, d);
  a.resize_growing(kept);
  return true;
}

// ---- Phase 2: lateral (interstitial) branches. ----

// Per neurite type, Poisson(lateral_rate x L x dt) events, L the type's path length grown
// so far, drawn on (seed, kLateral, neuron, step); each adds at most one point and one cone.
template <class A>
AXG_HDI void lateral_events(const ArbourStepContext& ctx, std::uint32_t neuron, std::uint32_t step, const A& a,
                            int events[2]) {
  events[0] = events[1] = 0;
  const ArbourRules& P = ctx.rules;
  if (!(P.axon.lateral_rate > 0.0) && !(P.dendrites.lateral_rate > 0.0)) return;
  double length[2] = {0.0, 0.0};  // axon, dendrites: the path grown
  for (std::uint32_t k = 0; k < a.cone_count(); ++k) {
    const Cone& c = a.cone(k);
    length[c.type == kAxonType ? 0 : 1] += c.length;
  }
  const double mean[2] = {P.axon.lateral_rate * length[0] * ctx.dt, P.dendrites.lateral_rate * length[1] * ctx.dt};
  if (!(mean[0] > 0.0) && !(mean[1] > 0.0)) return;
  core::Rng rng(ctx.seed, core::Stream::kLateral, neuron, step);
  events[0] = poisson(mean[0], rng.uniform());
  events[1] = poisson(mean[1], rng.uniform());
}

AXG_HDI ArbourRoom lateral_room(const int events[2]) {
  const auto n = static_cast<std::uint32_t>(events[0] + events[1]);
  return {n, n, 0u};
}

// Where a cone's stretch since its last point starts: that point, or, before it made one,
// the point it started from (its branch point); kNoPoint for a stem without points.
template <class A>
AXG_HDI std::uint32_t stretch_start(const A& a, std::uint32_t c) {
  const Cone& cone = a.cone(c);
  const std::uint32_t last = a.last_of(c);
  if (last != kNoPoint || cone.parent == kNoCone) return last;
  return cone.attach != kNoPoint ? cone.attach : a.last_of(cone.parent);
}

// The events of lateral_events(): each new cone starts where a uniform draw along the
// type's sampled path falls: at the point that ends the segment it falls in, or, when it
// falls in a growing cone's stretch since its last point, at that cone's tip, which then
// makes a point (a numerical choice: sample_length sets how far from the drawn place a
// branch starts). The type's sampled path: each point's segment from the point it hangs
// on (none for a stem's first point), in the order growth made them, then each growing
// cone's stretch from its last point to its tip. Each new cone's rate factor and heading
// are drawn on (seed, kConeBirth, cone, 0).
template <class A>
AXG_HDI bool lateral_branches(const ArbourStepContext& ctx, std::uint32_t neuron, std::uint32_t step,
                              const int events[2], A& a, ArbourFail* fail) {
  if (events[0] == 0 && events[1] == 0) return true;
  const ArbourRules& P = ctx.rules;
  core::Rng rng(ctx.seed, core::Stream::kLateral, neuron, step);
  rng.uniform();  // the two counts' draws (lateral_events)
  rng.uniform();
  for (int t = 0; t < 2; ++t) {
    const ConeRules& p = t == 0 ? P.axon : P.dendrites;
    const std::uint8_t type = t == 0 ? kAxonType : kDendriteType;
    for (int e = 0; e < events[t]; ++e) {
      auto tail = [&](std::uint32_t c) {
        const Cone& cone = a.cone(c);
        const std::uint32_t from = stretch_start(a, c);
        return cone.type == type && cone.unsampled > 0.0 && from != kNoPoint ? core::norm(cone.tip - a.point(from))
                                                                              : 0.0;
      };
      double total = 0.0;
      for (std::uint32_t i = 0; i < a.point_count(); ++i)
        if (a.cone(a.cone_of(i)).type == type && a.parent_of(i) != kNoPoint)
          total += core::norm(a.point(i) - a.point(a.parent_of(i)));
      for (std::uint32_t g = 0; g < a.growing_count(); ++g) total += tail(a.growing(g));
      if (!(total > 0.0)) break;
      const double at = total * rng.uniform_co();
      std::uint32_t where = kNoPoint;
      double walked = 0.0;
      for (std::uint32_t i = 0; i < a.point_count() && where == kNoPoint; ++i)
        if (a.cone(a.cone_of(i)).type == type && a.parent_of(i) != kNoPoint &&
            (walked += core::norm(a.point(i) - a.point(a.parent_of(i)))) > at)
          where = i;
      for (std::uint32_t g = 0; g < a.growing_count() && where == kNoPoint; ++g) {
        const std::uint32_t c = a.growing(g);
        const double l = tail(c);
        if (l > 0.0 && (walked += l) > at)  // the cone's tip makes a point to branch from
          where = add_point(a, c, a.cone(c).tip, step);
      }
      if (where == kNoPoint) continue;  // rounding at the path's end
      const std::uint32_t owner = a.cone_of(where);
      std::uint32_t index = 0;
      if (!cone_index(a, &index, fail)) return false;
      core::Rng birth(ctx.seed, core::Stream::kConeBirth, core::cone_key(neuron, index), 0);
      const Cone o = a.cone(owner);
      Cone child;
      child.rate = core::rate_factor(p.geometry.rate_sigma, birth);
      child.heading =
          core::lateral_heading(core::normalized(a.point(where) - a.point(a.parent_of(where))), p.geometry, birth);
      child.tip = a.point(where);
      child.parent = owner;
      child.attach = where;
      child.born = child.ended = step;
      child.tree = o.tree;
      child.type = type;
      child.order = o.order == 255 ? 255 : static_cast<std::uint8_t>(o.order + 1);
      a.count_order(child.tree, child.order, 1);
      ++a.tree(child.tree).growing;
      a.push_cone(child);
      a.set_growing(a.growing_count(), index);
    }
  }
  return true;
}

// ---- Phase 3: new stems. ----

// Poisson with mean (stem rate) dt, axons then dendrites, drawn on (seed, kStems, neuron, step).
AXG_HDI void stem_events(const ArbourStepContext& ctx, std::uint32_t neuron, std::uint32_t step, int events[2]) {
  events[0] = events[1] = 0;
  const ArbourRules& P = ctx.rules;
  if (!(P.axon.stem_rate > 0.0) && !(P.dendrites.stem_rate > 0.0)) return;
  core::Rng rng(ctx.seed, core::Stream::kStems, neuron, step);
  events[0] = poisson(P.axon.stem_rate * ctx.dt, rng.uniform());
  events[1] = poisson(P.dendrites.stem_rate * ctx.dt, rng.uniform());
}

AXG_HDI ArbourRoom stem_room(const int events[2]) {
  const auto n = static_cast<std::uint32_t>(events[0] + events[1]);
  return {n, n, n};
}

template <class A>
AXG_HDI bool new_stems(const ArbourStepContext& ctx, std::uint32_t neuron, core::Vec3 soma, std::uint32_t step,
                       const int events[2], A& a, ArbourFail* fail) {
  for (int k = 0; k < events[0]; ++k)
    if (!new_stem(ctx, neuron, soma, kAxonType, step, a, fail)) return false;
  for (int k = 0; k < events[1]; ++k)
    if (!new_stem(ctx, neuron, soma, kDendriteType, step, a, fail)) return false;
  return true;
}

}  // namespace axg::morphology

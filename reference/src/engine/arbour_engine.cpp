// The arbour engine (docs/methods.md §2.12): neurons in parallel, each neuron's cones in
// index order, every draw keyed on (neuron, cone index) or the neuron.
#include "axonguide/engine/arbour_engine.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "axonguide/core/arbour.hpp"
#include "axonguide/core/branching.hpp"
#include "axonguide/core/growth.hpp"
#include "axonguide/engine/cell_grid.hpp"
#include "axonguide/fields/fields.hpp"
#include "axonguide/model/cues.hpp"
#include "axonguide/model/growth.hpp"
#include "axonguide/model/steering.hpp"
#include "axonguide/morphology/tree_process.hpp"
#include "axonguide/support/error.hpp"

namespace axg {

using morphology::Arbour;
using morphology::Cone;
using morphology::ConeStatus;
using morphology::kAxonType;
using morphology::kDendriteType;
using morphology::kNoCone;
using morphology::kNoPoint;
using morphology::Tree;

namespace {

const NeuriteParams& neurite(const ArbourParams& p, std::uint8_t type) {
  return type == kAxonType ? p.axon : p.dendrites;
}

std::uint32_t next_index(std::uint32_t neuron, const Arbour& a) {
  if (a.cones.size() >= core::kConesPerNeuron)
    throw RunError(fmt::format("arbours: neuron {} has grown 2^24 growth cones (the most a neuron's cone ids hold); "
                               "lower the branching rates or the steps",
                               neuron));
  return static_cast<std::uint32_t>(a.cones.size());
}

// A new stem of `type` at the end of step `born`: its own tree, its start on the soma's
// surface (raised to its height in a culture's growth layer), its heading and rate factor
// drawn on (seed, kConeBirth, cone, 0).
void new_stem(const ArbourContext& ctx, std::uint32_t neuron, core::Vec3 soma, std::uint8_t type, std::uint32_t born,
              Arbour& a) {
  const std::uint32_t index = next_index(neuron, a);
  const NeuriteParams& p = neurite(*ctx.params, type);
  core::Rng rng(ctx.seed, core::Stream::kConeBirth, core::cone_key(neuron, index), 0);
  Cone c;
  c.heading = core::stem_heading(ctx.params->planar, rng);
  c.rate = core::rate_factor(p.geometry.rate_sigma, rng);
  const double height = ctx.params->planar ? ctx.params->slab * rng.uniform_co() : 0.0;
  c.tip = soma + ctx.soma_radius * c.heading + core::Vec3{0.0, 0.0, height};
  c.born = c.ended = born;
  c.type = type;
  c.tree = static_cast<std::uint16_t>(a.trees.size());
  if (a.trees.size() >= 0xffff)
    throw RunError(fmt::format("arbours: neuron {} has started 65535 stems (the most a neuron's tree ids hold); lower "
                               "arbours.*.stem_rate",
                               neuron));
  Tree t;
  t.type = type;
  t.born = born;
  t.growing = 1;
  t.by_order = {1};
  a.trees.push_back(std::move(t));
  a.cones.push_back(c);
  a.point.push_back(c.tip);
  a.cone_of.push_back(index);
  a.step_of.push_back(born);
  a.growing.push_back(index);
}

// Poisson(m) by inversion of one uniform in (0, 1) (m is small: stems per step).
int poisson(double m, double u) {
  double p = core::pm::exp(-m), f = p;
  int k = 0;
  while (u > f && k < 1000) {
    ++k;
    p = p * m / static_cast<double>(k);
    f += p;
  }
  return k;
}

// The cue stage of one growing cone (core::guide_axon, the axons' body): its sample, and its
// decision at the interval's end (kept in the plane in a culture). A cone steers on an
// interval's sums only when it held them from the interval's start (Cone::evidence).
void steer_cone(const ArbourSteering& st, bool planar, std::uint64_t key, core::Vec3 at, Cone& c, double* sums) {
  core::CueSample samples[core::kMaxCues];
  core::Vec3 pull[core::kMaxCues];
  const core::Decision& d = st.decision;
  if (st.sums_per_cone) {
    if (d.open) c.evidence = true;
    if (!c.evidence) return;
  }
  st.field->sample(at, samples, pull);
  const core::GuidedAxon cone{&c.heading, nullptr, nullptr, 0.0, st.sums_per_cone ? sums : nullptr};
  core::guide_axon(*st.guide, samples, pull, cone, key, d);
  if (planar) c.heading = core::in_plane(c.heading);
}

// Lateral (interstitial) branches of one neuron at the end of a step: per neurite type,
// Poisson(lateral_rate x L x dt) new cones, L the type's path length grown so far, each
// starting where a uniform draw along the type's sampled path falls: at the point that ends
// the segment it falls in, or, when it falls in a growing cone's stretch since its last
// point, at that cone's tip, which then makes a point (a numerical choice: sample_length
// sets how far from the drawn place a branch starts). Draws on (seed, kLateral, neuron,
// step); each new cone's rate factor and heading on (seed, kConeBirth, cone, 0).
void lateral_branches(const ArbourContext& ctx, std::uint32_t neuron, std::uint32_t step, Arbour& a) {
  const ArbourParams& P = *ctx.params;
  double length[2] = {0.0, 0.0};  // axon, dendrites: the path grown
  for (const Cone& c : a.cones) length[c.type == kAxonType ? 0 : 1] += c.length;
  const double mean[2] = {P.axon.lateral_rate * length[0] * ctx.dt, P.dendrites.lateral_rate * length[1] * ctx.dt};
  if (!(mean[0] > 0.0) && !(mean[1] > 0.0)) return;
  core::Rng rng(ctx.seed, core::Stream::kLateral, neuron, step);
  const int events[2] = {poisson(mean[0], rng.uniform()), poisson(mean[1], rng.uniform())};
  if (events[0] == 0 && events[1] == 0) return;
  thread_local std::vector<std::uint32_t> last, before;
  for (int t = 0; t < 2; ++t) {
    const NeuriteParams& p = t == 0 ? P.axon : P.dendrites;
    const std::uint8_t type = t == 0 ? kAxonType : kDendriteType;
    for (int e = 0; e < events[t]; ++e) {
      // The type's sampled path: each point's segment from the point before it (its cone's
      // previous point, or its branch point; none for a stem's first point), in the order
      // growth made them, then each growing cone's stretch from its last point to its tip.
      morphology::point_parents(a, before);
      last.assign(a.cones.size(), kNoPoint);
      double total = 0.0;
      for (std::size_t i = 0; i < a.point.size(); ++i) {
        last[a.cone_of[i]] = static_cast<std::uint32_t>(i);
        if (a.cones[a.cone_of[i]].type == type && before[i] != kNoPoint)
          total += core::norm(a.point[i] - a.point[before[i]]);
      }
      // Where a cone's stretch since its last point starts: that point, or, before it made
      // one, the point it started from (its branch point).
      auto start_of = [&](std::uint32_t c) {
        const Cone& cone = a.cones[c];
        if (last[c] != kNoPoint || cone.parent == kNoCone) return last[c];
        return cone.attach != kNoPoint ? cone.attach : last[cone.parent];
      };
      auto tail = [&](std::uint32_t c) {
        const Cone& cone = a.cones[c];
        return cone.type == type && cone.unsampled > 0.0 && start_of(c) != kNoPoint
                   ? core::norm(cone.tip - a.point[start_of(c)])
                   : 0.0;
      };
      for (const std::uint32_t c : a.growing) total += tail(c);
      if (!(total > 0.0)) break;
      const double at = total * rng.uniform_co();
      std::uint32_t where = kNoPoint;
      double walked = 0.0;
      for (std::size_t i = 0; i < a.point.size() && where == kNoPoint; ++i)
        if (a.cones[a.cone_of[i]].type == type && before[i] != kNoPoint &&
            (walked += core::norm(a.point[i] - a.point[before[i]])) > at)
          where = static_cast<std::uint32_t>(i);
      for (std::size_t g = 0; g < a.growing.size() && where == kNoPoint; ++g) {
        const std::uint32_t c = a.growing[g];
        const double l = tail(c);
        if (l > 0.0 && (walked += l) > at) {  // the cone's tip makes a point to branch from
          a.point.push_back(a.cones[c].tip);
          a.cone_of.push_back(c);
          a.step_of.push_back(step);
          a.cones[c].unsampled = 0.0;
          before.push_back(start_of(c));
          where = static_cast<std::uint32_t>(a.point.size() - 1);
        }
      }
      if (where == kNoPoint) continue;  // rounding at the path's end
      const std::uint32_t owner = a.cone_of[where];
      const std::uint32_t index = next_index(neuron, a);
      core::Rng birth(ctx.seed, core::Stream::kConeBirth, core::cone_key(neuron, index), 0);
      Cone child;
      child.rate = core::rate_factor(p.geometry.rate_sigma, birth);
      child.heading =
          core::lateral_heading(core::normalized(a.point[where] - a.point[before[where]]), p.geometry, birth);
      child.tip = a.point[where];
      child.parent = owner;
      child.attach = where;
      child.born = child.ended = step;
      child.tree = a.cones[owner].tree;
      child.type = type;
      child.order = a.cones[owner].order == 255 ? 255 : static_cast<std::uint8_t>(a.cones[owner].order + 1);
      Tree& tree = a.trees[child.tree];
      if (tree.by_order.size() <= child.order) tree.by_order.resize(child.order + 1u, 0);
      ++tree.by_order[child.order];
      ++tree.growing;
      a.cones.push_back(child);
      a.growing.push_back(index);
    }
  }
}

}  // namespace

void start_arbour(const ArbourContext& ctx, std::uint32_t neuron, core::Vec3 soma, Arbour& a) {
  core::Rng rng(ctx.seed, core::Stream::kStems, neuron, 0);
  const int axons = draw_count(ctx.params->axon.stems_cdf, rng.uniform());
  const int dendrites = draw_count(ctx.params->dendrites.stems_cdf, rng.uniform());
  for (int k = 0; k < axons; ++k) new_stem(ctx, neuron, soma, kAxonType, 0, a);
  for (int k = 0; k < dendrites; ++k) new_stem(ctx, neuron, soma, kDendriteType, 0, a);
}

void step_arbour(const ArbourContext& ctx, std::uint32_t neuron, core::Vec3 soma, std::uint32_t step, Arbour& a) {
  const ArbourParams& P = *ctx.params;
  const double dt = ctx.dt;
  const double t0 = static_cast<double>(step - 1) * dt;
  // What a tree's cones share over the step, from n and C at its start (the rule holds them
  // over the step): the elongation v0 n^-F dt, the branching exponent's tree part, C, and
  // (S = 0: no order dependence) the branching probability itself.
  struct TreeStep {
    double grow, branching, mean_weight, probability;
    int n;
  };
  thread_local std::vector<TreeStep> trees;
  thread_local std::vector<std::uint32_t> next, daughters;
  trees.resize(a.trees.size());
  for (std::size_t t = 0; t < a.trees.size(); ++t) {
    const Tree& tree = a.trees[t];
    TreeStep& ts = trees[t];
    ts.n = tree.growing;
    if (ts.n == 0) continue;
    const NeuriteParams& p = neurite(P, tree.type);
    ts.grow = core::elongation(p.elongation, ts.n, dt);
    ts.branching = core::tree_branching(p.branching, t0 - static_cast<double>(tree.born) * dt, dt, ts.n);
    ts.mean_weight = p.branching.s == 0.0 ? 1.0
                                           : core::mean_order_weight(p.branching.s, tree.by_order.data(),
                                                                     static_cast<int>(tree.by_order.size()), ts.n);
    ts.probability = core::cone_branch_probability(ts.branching, p.branching.s, 0, ts.mean_weight);
  }
  const ArbourSteering& steering = ctx.steering;
  const bool steers = steering.field != nullptr;
  const bool after = steers && steering.guide->after_move;
  const std::size_t m = steering.sums_per_cone;
  thread_local std::vector<double> next_sums, daughter_sums;
  next_sums.clear();
  daughter_sums.clear();
  // The stems started at birth (at the end of `growing`) hold no evidence yet.
  if (m) a.sums.resize(a.growing.size() * m, 0.0);
  auto add_point = [&](std::uint32_t idx, core::Vec3 at) {
    a.point.push_back(at);
    a.cone_of.push_back(idx);
    a.step_of.push_back(step);
    a.cones[idx].unsampled = 0.0;
  };
  next.clear();
  daughters.clear();
  for (std::size_t g = 0; g < a.growing.size(); ++g) {
    const std::uint32_t idx = a.growing[g];
    const std::uint64_t key = core::cone_key(neuron, idx);
    double* sums = m ? a.sums.data() + g * m : nullptr;
    if (steers && !after) steer_cone(steering, P.planar, key, a.cones[idx].tip, a.cones[idx], sums);
    const Cone c0 = a.cones[idx];
    const NeuriteParams& p = neurite(P, c0.type);
    const TreeStep& ts = trees[c0.tree];
    const double l = ts.grow * c0.rate;
    // Move, then contact and bounds (core/growth.hpp's step; contact only when cones stop at somas).
    core::AxonStep st;
    if (P.stop_at_soma) {
      st = core::grow_axon(neuron, c0.tip, c0.heading, l, *ctx.growth, *ctx.somas);
    } else {
      const core::Vec3 to = c0.tip + l * c0.heading;
      st = {to, l, core::outside_bounds(to, *ctx.growth) ? core::AxonStatus::kExited : core::AxonStatus::kGrowing,
            core::kNoNeuron};
    }
    Cone& c = a.cones[idx];
    c.tip = st.tip;
    c.length += st.advanced;
    c.unsampled += st.advanced;
    c.ended = step;
    Tree& tree = a.trees[c.tree];
    if (st.status != core::AxonStatus::kGrowing) {
      c.status = st.status == core::AxonStatus::kConnected ? ConeStatus::kSoma : ConeStatus::kExited;
      --tree.growing;
      --tree.by_order[c.order];
      add_point(idx, c.tip);
      continue;
    }
    c.heading = core::cone_wander(c.heading, l, p.geometry, ctx.seed, key, step);
    if (after) steer_cone(steering, P.planar, key, core::sample_point(*steering.guide, c.tip, c.heading, &l), c, sums);
    const double q = p.branching.s == 0.0 ? ts.probability
                                          : core::cone_branch_probability(ts.branching, p.branching.s, c.order,
                                                                          ts.mean_weight);
    if (!(q > 0.0) || !core::branches(q, ctx.seed, key, step)) {
      if (c.unsampled >= P.sample_length || step == ctx.last_step) add_point(idx, c.tip);
      next.push_back(idx);
      if (m) next_sums.insert(next_sums.end(), sums, sums + m);
      continue;
    }
    // Two daughters take the next indices; the parent's segment ends at the branch point.
    add_point(idx, c.tip);
    Cone& b = a.cones[idx];
    core::Vec3 h[2];
    core::daughter_headings(b.heading, p.geometry, ctx.seed, key, step, &h[0], &h[1]);
    b.status = ConeStatus::kBranched;
    const std::uint8_t order = b.order == 255 ? 255 : static_cast<std::uint8_t>(b.order + 1);
    --tree.by_order[b.order];
    if (tree.by_order.size() <= order) tree.by_order.resize(order + 1u, 0);
    tree.by_order[order] += 2;
    ++tree.growing;
    const Cone parent = b;  // `b` dangles once the daughters are pushed
    for (int d = 0; d < 2; ++d) {
      const std::uint32_t index = next_index(neuron, a);
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
      a.cones.push_back(child);
      daughters.push_back(index);
      if (m) daughter_sums.insert(daughter_sums.end(), sums, sums + m);
    }
  }
  next.insert(next.end(), daughters.begin(), daughters.end());
  a.growing.swap(next);
  if (m) {
    next_sums.insert(next_sums.end(), daughter_sums.begin(), daughter_sums.end());
    a.sums.swap(next_sums);
  }
  // Lateral branches, then new stems, at the end of the step.
  if (P.axon.lateral_rate > 0.0 || P.dendrites.lateral_rate > 0.0) lateral_branches(ctx, neuron, step, a);
  // New stems: Poisson with mean (stem rate) dt, axons then dendrites.
  if (P.axon.stem_rate > 0.0 || P.dendrites.stem_rate > 0.0) {
    core::Rng rng(ctx.seed, core::Stream::kStems, neuron, step);
    const int axons = poisson(P.axon.stem_rate * dt, rng.uniform());
    const int dendrites = poisson(P.dendrites.stem_rate * dt, rng.uniform());
    for (int k = 0; k < axons; ++k) new_stem(ctx, neuron, soma, kAxonType, step, a);
    for (int k = 0; k < dendrites; ++k) new_stem(ctx, neuron, soma, kDendriteType, step, a);
  }
  if (m) a.sums.resize(a.growing.size() * m, 0.0);  // the new stems' (empty) sums
}

double expected_arbour_points(const Scene& scene) {
  if (!scene.arbours) return 0.0;
  const ArbourParams p = arbour_params(scene);
  double points = 0.0;
  for (const NeuriteParams* q : {&p.axon, &p.dendrites}) {
    // Stems: the birth distribution's mean, and the rate's over the run (each a full run's).
    double stems = 0.0, previous = 0.0;
    for (std::size_t k = 0; k < q->stems_cdf.size(); ++k) {
      stems += static_cast<double>(k) * (q->stems_cdf[k] - previous);
      previous = q->stems_cdf[k];
    }
    stems += q->stem_rate * static_cast<double>(scene.steps) * scene.dt;
    if (stems == 0.0) continue;
    // A tree's points: a pilot of the topology-only process. Every cone-step makes a point
    // (sample length 0), or one per sample length of path plus one at every branching and
    // at every end, whichever is fewer.
    morphology::TreeProcess tp;
    tp.branching = q->branching;
    tp.elongation = q->elongation;
    tp.dt = scene.dt;
    tp.steps = scene.steps;
    tp.seed = scene.seed;
    const std::uint32_t trees = 64;
    double tree_points = 0.0;
    for (const morphology::TreeOutcome& o : morphology::grow_trees(tp, trees)) {
      const double sampled = p.sample_length > 0.0 ? o.total_length / p.sample_length + 2.0 * o.branch_points + o.terminals
                                                   : o.cone_steps;
      tree_points += std::min(o.cone_steps, sampled);
    }
    // Lateral branches (not in the pilot): a tree whose cones elongate at v0 and branch
    // laterally at rate lambda per length has cosh(sqrt(lambda v0) t) cones at t (n'' =
    // lambda v0 n), an upper bound with competition (F > 0); its points grow as its cones.
    const double x = std::sqrt(q->lateral_rate * q->elongation.v0) * static_cast<double>(scene.steps) * scene.dt;
    const double lateral = x > 0.0 ? 0.5 * (core::pm::exp(x) + core::pm::exp(-x)) : 1.0;
    points += stems * (1.0 + lateral * tree_points / trees);
  }
  return points;
}

std::size_t arbour_bytes_per_neuron() {
  // soma (grid copy, id order), grid id, cell start, the Arbour's vectors, one stem each.
  return 3 * sizeof(core::Vec3) + 8 + sizeof(Arbour) + 2 * sizeof(Cone) + 2 * sizeof(Tree) + 64;
}

namespace {

struct ConeCounts {
  std::uint64_t growing_neurons = 0, soma = 0, exited = 0;
};

class ArbourEngine final : public Engine {
 public:
  ArbourEngine(const Scene& scene, Placement&& placement)
      : scene_(scene),
        params_(arbour_params(scene)),
        growth_(growth_params(scene)),
        cues_(make_cues(scene)),
        guide_(guide_params(scene, cues_.data(), static_cast<int>(cues_.size()))),
        clock_(decision_clock(scene)),
        field_(make_reference_field(scene, cues_)),
        sums_per_cone_(field_ && clock_.sums() ? cues_.size() * core::kSumsPerCue : 0) {
    soma_ = std::move(placement.soma);
    placement = Placement{};
    grid_ = build_cell_grid(soma_grid_geometry(scene), soma_);
    view_ = grid_.view();
    arbours_.resize(soma_.size());
    // Stems start at a rate, or lateral branches along the grown path: a neuron without
    // growing cones may grow again.
    restarts_ = params_.axon.stem_rate > 0.0 || params_.dendrites.stem_rate > 0.0 || params_.axon.lateral_rate > 0.0 ||
                params_.dendrites.lateral_rate > 0.0;
    const ArbourContext ctx = context();
    tbb::parallel_for(std::size_t{0}, soma_.size(), [&](std::size_t i) {
      start_arbour(ctx, static_cast<std::uint32_t>(i), soma_[i], arbours_[i]);
    });
  }

  void warm_up() override {
    if (!field_) return;
    PhaseTimes warmup;  // before the step loop: not part of any step's timings
    for (std::uint32_t s = 1; s <= scene_.cues.warmup_steps; ++s) field_->advance(s, warmup);
  }

  void save(EngineState& out) override {
    const std::size_t n = soma_.size();
    out.axons.resize(n);
    out.heading.assign(n, core::Vec3{0, 0, 0});
    out.connected = stats_.connected;
    out.exited = stats_.exited;
    out.arbour.clear();
    morphology::append_arbours(arbours_, out.arbour);
    if (field_) field_->save(out);
  }

  void load(const EngineState& in) override {
    try {
      arbours_ = morphology::read_arbours(in.arbour);
    } catch (const std::runtime_error& e) {
      throw RunError(e.what());
    }
    if (arbours_.size() != soma_.size())
      throw RunError("checkpoint: its arbours are not the scene's neurons");
    for (const Arbour& a : arbours_)
      if (!a.sums.empty() && a.sums.size() != a.growing.size() * sums_per_cone_)
        throw RunError("checkpoint: its growth cones' decision sums are not the scene's");
    if (field_) field_->load(in);
    stats_.connected = in.connected;
    stats_.exited = in.exited;
  }

  StepStats step(std::uint32_t step, PhaseTimes& times) override {
    if (field_) field_->advance(scene_.cues.warmup_steps + step, times);
    ScopedPhase phase(times, step, "grow");
    ArbourContext ctx = context();
    if (field_) ctx.steering = {field_.get(), &guide_, clock_.at(step), sums_per_cone_};
    const ConeCounts c = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, soma_.size()), ConeCounts{},
        [&](const tbb::blocked_range<std::size_t>& r, ConeCounts acc) {
          for (std::size_t i = r.begin(); i != r.end(); ++i) {
            Arbour& a = arbours_[i];
            if (a.growing.empty() && !restarts_) continue;
            const std::size_t first = a.point.size();
            step_arbour(ctx, static_cast<std::uint32_t>(i), soma_[i], step, a);
            for (std::size_t k = first; k < a.point.size(); ++k) {  // the cones that stopped this step
              const ConeStatus s = a.cones[a.cone_of[k]].status;
              if (a.cones[a.cone_of[k]].ended != step) continue;
              acc.soma += s == ConeStatus::kSoma;
              acc.exited += s == ConeStatus::kExited;
            }
            acc.growing_neurons += !a.growing.empty() || restarts_;
          }
          return acc;
        },
        [](ConeCounts x, ConeCounts y) {
          return ConeCounts{x.growing_neurons + y.growing_neurons, x.soma + y.soma, x.exited + y.exited};
        });
    stats_.step = step;
    stats_.growing = c.growing_neurons;
    stats_.connected += c.soma;
    stats_.exited += c.exited;
    stats_.particles = field_ ? field_->particles() : 0;
    return stats_;
  }

  void particles(std::vector<core::Vec3>& pos, std::vector<std::uint16_t>& cue) override {
    if (field_) field_->snapshot(pos, cue);
  }

  std::string note() const override { return field_ ? field_->note() : std::string(); }

  void tips(std::vector<core::Vec3>& out) override {
    out.resize(soma_.size());
    for (std::size_t i = 0; i < soma_.size(); ++i) out[i] = morphology::summarize(arbours_[i], soma_[i]).farthest;
  }

  void finish(NeuronState& out) override {
    const std::size_t n = soma_.size();
    out.resize(n);
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
      const morphology::ArbourSummary s = morphology::summarize(arbours_[i], soma_[i]);
      out.tip[i] = s.farthest;
      out.length[i] = s.axon_length;
      out.status[i] = s.growing ? core::AxonStatus::kMaxSteps : core::AxonStatus::kExited;
      out.steps[i] = s.last_step;
    });
  }

  void somas(std::vector<core::Vec3>& out) override { out = soma_; }

  // Moved out at their size (growth doubles the point arrays' capacity as it goes).
  void arbours(std::vector<Arbour>& out) override {
    tbb::parallel_for(std::size_t{0}, arbours_.size(), [&](std::size_t i) {
      Arbour& a = arbours_[i];
      a.point.shrink_to_fit();
      a.cone_of.shrink_to_fit();
      a.step_of.shrink_to_fit();
      std::vector<std::uint32_t>().swap(a.growing);
      std::vector<double>().swap(a.sums);
    });
    out = std::move(arbours_);
  }

  std::size_t bytes() const override {
    std::size_t b = (field_ ? field_->bytes() : 0) + grid_.bytes() + soma_.capacity() * sizeof(core::Vec3) +
                    arbours_.capacity() * sizeof(Arbour);
    for (const Arbour& a : arbours_) b += a.bytes();
    return b;
  }

 private:
  ArbourContext context() const {
    return {&params_, &growth_, &view_, scene_.seed, scene_.dt, scene_.neurons.soma_radius, scene_.steps};
  }

  const Scene& scene_;
  ArbourParams params_;
  core::GrowthParams growth_;
  std::vector<core::CueParams> cues_;
  core::GuideParams guide_;
  DecisionClock clock_;
  std::unique_ptr<CueField> field_;  // null for direct guidance
  std::size_t sums_per_cone_;
  std::vector<core::Vec3> soma_;  // by id
  CellGrid grid_;
  core::CellGridView view_{};
  std::vector<Arbour> arbours_;
  bool restarts_ = false;  // stems or lateral branches start at a rate: a neuron without growing cones may grow again
  StepStats stats_;
};

}  // namespace

std::unique_ptr<Engine> make_arbour_engine(const Scene& scene, Placement&& placement) {
  return std::make_unique<ArbourEngine>(scene, std::move(placement));
}

}  // namespace axg

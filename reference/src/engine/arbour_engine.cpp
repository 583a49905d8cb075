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

// The reference's storage for morphology/arbour_step.hpp: the arbour's own vectors,
// which grow as the step needs (room is never short). The points' parents are not stored
// (32 bytes a point): the first lateral event of a step lists them (point_parents()) into
// a scratch list that the step's new points then extend.
class VectorArbour {
 public:
  VectorArbour(Arbour& a, std::size_t sums_per_cone)
      : a_(a), m_(static_cast<std::uint32_t>(sums_per_cone)) {}
  std::uint32_t point_count() const { return static_cast<std::uint32_t>(a_.point.size()); }
  core::Vec3 point(std::uint32_t i) const { return a_.point[i]; }
  std::uint32_t cone_of(std::uint32_t i) const { return a_.cone_of[i]; }
  std::uint32_t parent_of(std::uint32_t i) {
    if (!listed_) {
      morphology::point_parents(a_, parents_);
      listed_ = true;
    }
    return parents_[i];
  }
  std::uint32_t push_point(core::Vec3 at, std::uint32_t cone, std::uint32_t step, std::uint32_t parent) {
    const auto i = static_cast<std::uint32_t>(a_.point.size());
    a_.point.push_back(at);
    a_.cone_of.push_back(cone);
    a_.step_of.push_back(step);
    if (listed_) parents_.push_back(parent);
    a_.last[cone] = i;
    return i;
  }
  std::uint32_t cone_count() const { return static_cast<std::uint32_t>(a_.cones.size()); }
  Cone& cone(std::uint32_t c) { return a_.cones[c]; }
  const Cone& cone(std::uint32_t c) const { return a_.cones[c]; }
  std::uint32_t last_of(std::uint32_t c) const { return a_.last[c]; }
  void push_cone(const Cone& c) {
    a_.cones.push_back(c);
    a_.last.push_back(kNoPoint);
    a_.sums.resize(a_.cones.size() * m_, 0.0);
  }
  double* sums(std::uint32_t c) { return m_ ? a_.sums.data() + static_cast<std::size_t>(c) * m_ : nullptr; }
  std::uint32_t sums_per_cone() const { return m_; }
  std::uint32_t tree_count() const { return static_cast<std::uint32_t>(a_.trees.size()); }
  Tree& tree(std::uint32_t t) { return a_.trees[t]; }
  void push_tree(std::uint8_t type, std::uint32_t born) {
    Tree t;
    t.type = type;
    t.born = born;
    t.growing = 1;
    t.by_order = {1};
    a_.trees.push_back(std::move(t));
  }
  void count_order(std::uint32_t t, std::uint8_t order, int delta) {
    std::vector<int>& b = a_.trees[t].by_order;
    if (b.size() <= order) b.resize(order + 1u, 0);
    b[order] += delta;
  }
  double mean_weight(std::uint32_t t, double s, int n) const {
    const std::vector<int>& b = a_.trees[t].by_order;
    return core::mean_order_weight(s, b.data(), static_cast<int>(b.size()), n);
  }
  std::uint32_t growing_count() const { return static_cast<std::uint32_t>(a_.growing.size()); }
  std::uint32_t growing(std::uint32_t g) const { return a_.growing[g]; }
  void set_growing(std::uint32_t g, std::uint32_t cone) {
    if (g == a_.growing.size()) a_.growing.push_back(cone);
    else a_.growing[g] = cone;
  }
  void resize_growing(std::uint32_t n) { a_.growing.resize(n); }

 private:
  Arbour& a_;
  std::uint32_t m_;
  bool listed_ = false;
  static thread_local std::vector<std::uint32_t> parents_;
};
thread_local std::vector<std::uint32_t> VectorArbour::parents_;

}  // namespace

void arbour_fail(morphology::ArbourFail fail, std::uint32_t neuron) {
  switch (fail) {
    case morphology::ArbourFail::kNone:
      return;
    case morphology::ArbourFail::kCones:
      throw RunError(fmt::format("arbours: neuron {} has grown 2^24 growth cones (the most a neuron's cone ids hold); "
                                 "lower the branching rates or the steps",
                                 neuron));
    case morphology::ArbourFail::kTrees:
      throw RunError(fmt::format("arbours: neuron {} has started 65535 stems (the most a neuron's tree ids hold); lower "
                                 "arbours.*.stem_rate",
                                 neuron));
  }
}

ArbourContext arbour_context(const Scene& scene, const ArbourParams& params, const core::GrowthParams& growth,
                             const core::CellGridView& somas, const CueField* field, std::size_t sums_per_cone) {
  ArbourContext c{&params, {}, field, sums_per_cone};
  c.step.rules = params.rules();
  c.step.growth = growth;
  c.step.somas = somas;
  c.step.seed = scene.seed;
  c.step.dt = scene.dt;
  c.step.soma_radius = scene.neurons.soma_radius;
  c.step.last_step = scene.steps;
  c.step.sums = sums_per_cone > 0;
  return c;
}

bool arbours_restart(const ArbourParams& p) {
  return p.axon.stem_rate > 0.0 || p.dendrites.stem_rate > 0.0 || p.axon.lateral_rate > 0.0 ||
         p.dendrites.lateral_rate > 0.0;
}

void start_arbour(const ArbourContext& ctx, std::uint32_t neuron, core::Vec3 soma, Arbour& a) {
  core::Rng rng(ctx.step.seed, core::Stream::kStems, neuron, 0);
  const int axons = draw_count(ctx.params->axon.stems_cdf, rng.uniform());
  const int dendrites = draw_count(ctx.params->dendrites.stems_cdf, rng.uniform());
  VectorArbour store(a, ctx.sums_per_cone);
  morphology::ArbourFail fail = morphology::ArbourFail::kNone;
  morphology::ArbourStepContext sc = ctx.step;
  for (int k = 0; k < axons && fail == morphology::ArbourFail::kNone; ++k)
    morphology::new_stem(sc, neuron, soma, kAxonType, 0, store, &fail);
  for (int k = 0; k < dendrites && fail == morphology::ArbourFail::kNone; ++k)
    morphology::new_stem(sc, neuron, soma, kDendriteType, 0, store, &fail);
  arbour_fail(fail, neuron);
}

void step_arbour(const ArbourContext& ctx, std::uint32_t neuron, core::Vec3 soma, std::uint32_t step, Arbour& a,
                 std::uint32_t stopped[2]) {
  VectorArbour store(a, ctx.sums_per_cone);
  morphology::ArbourFail fail = morphology::ArbourFail::kNone;
  const morphology::ArbourStepContext& sc = ctx.step;
  const CueField* field = ctx.field;
  const auto sample = [field](core::Vec3 at, core::CueSample* samples, core::Vec3* pull) {
    field->sample(at, samples, pull);
  };
  int events[2];
  if (morphology::grow_cones(sc, sample, neuron, step, store, stopped, &fail)) {
    morphology::lateral_events(sc, neuron, step, store, events);
    if (morphology::lateral_branches(sc, neuron, step, events, store, &fail)) {
      morphology::stem_events(sc, neuron, step, events);
      morphology::new_stems(sc, neuron, soma, step, events, store, &fail);
    }
  }
  arbour_fail(fail, neuron);
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
    restarts_ = arbours_restart(params_);
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
      if (a.sums.size() != a.cones.size() * sums_per_cone_)
        throw RunError("checkpoint: its growth cones' decision sums are not the scene's");
    if (field_) field_->load(in);
    stats_.connected = in.connected;
    stats_.exited = in.exited;
  }

  StepStats step(std::uint32_t step, PhaseTimes& times) override {
    if (field_) field_->advance(scene_.cues.warmup_steps + step, times);
    ScopedPhase phase(times, step, "grow");
    ArbourContext ctx = context();
    if (field_) ctx.step.decision = clock_.at(step);
    const ConeCounts c = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, soma_.size()), ConeCounts{},
        [&](const tbb::blocked_range<std::size_t>& r, ConeCounts acc) {
          for (std::size_t i = r.begin(); i != r.end(); ++i) {
            Arbour& a = arbours_[i];
            if (a.growing.empty() && !restarts_) continue;
            std::uint32_t stopped[2] = {0, 0};
            step_arbour(ctx, static_cast<std::uint32_t>(i), soma_[i], step, a, stopped);
            acc.soma += stopped[0];
            acc.exited += stopped[1];
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
      std::vector<std::uint32_t>().swap(a.last);
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
    ArbourContext c = arbour_context(scene_, params_, growth_, view_, field_.get(), sums_per_cone_);
    c.step.guide = field_ ? &guide_ : nullptr;
    return c;
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

#include "axonguide/engine/axon_stages.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>

#include <fmt/format.h>

#include "axonguide/model/cues.hpp"
#include "axonguide/model/growth.hpp"
#include "axonguide/model/sensing.hpp"
#include "axonguide/model/signalling.hpp"
#include "axonguide/model/steering.hpp"
#include "axonguide/model/wander.hpp"
#include "axonguide/support/error.hpp"
#include "axonguide/fields/fields.hpp"

namespace axg {

AxonStages::AxonStages(const Scene& scene)
    : seed_(scene.seed),
      params_(growth_params(scene)),
      wander_(wander_params(scene)),
      modulated_(modulates_growth(scene)),
      signalling_(scene.signalling()),
      cues_(make_cues(scene)),
      guide_(guide_params(scene, cues_.data(), static_cast<int>(cues_.size()))),
      clock_(decision_clock(scene)),
      sums_per_axon_(clock_.sums() && scene.uses_cues() ? cues_.size() * core::kSumsPerCue : 0) {
  if (signalling_) {
    population_inhibition_ = scene.axons.signalling.population;
    populations_ = scene.neurons.populations;
  }
}

namespace {

SignallingFailure first_failure(SignallingFailure x, SignallingFailure y) { return y.neuron < x.neuron ? y : x; }

}  // namespace

SignallingFailure AxonStages::steer(const CueField& field, const std::vector<std::uint32_t>& slots, AxonArrays a,
                                    std::uint32_t step) const {
  const core::Decision d = clock_.at(step);
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, slots.size()), SignallingFailure{},
      [&](const tbb::blocked_range<std::size_t>& r, SignallingFailure failed) {
        core::CueSample samples[core::kMaxCues];
        core::Vec3 pull[core::kMaxCues];
        for (std::size_t s = r.begin(); s != r.end(); ++s) {
          const std::uint32_t k = slots[s];
          field.sample(core::sample_point(guide_, a.tip[k], a.heading[k], a.step_length ? &a.step_length[k] : nullptr),
                       samples, pull);
          const core::GuidedAxon axon{&a.heading[k], a.step_length ? &a.step_length[k] : nullptr,
                                      a.signal ? a.signal + static_cast<std::size_t>(k) * core::kSignalSpecies : nullptr,
                                      a.inhibition ? a.inhibition[a.id[k]] : 0.0,
                                      a.sums ? a.sums + static_cast<std::size_t>(k) * sums_per_axon_ : nullptr};
          const core::SignallingStep g = core::guide_axon(guide_, samples, pull, axon, a.id[k], d);
          if (g.status != core::StiffStatus::kOk && a.id[k] < failed.neuron) failed = {a.id[k], g.species, g.status};
        }
        return failed;
      },
      first_failure);
}

void AxonStages::soma_signals(const CueField& field, const std::vector<core::Vec3>& soma, double* receptors,
                              double* inhibition, bool start) const {
  const core::SignallingParams& q = guide_.signal;
  tbb::parallel_for(std::size_t{0}, soma.size(), [&](std::size_t i) {
    core::CueSample samples[core::kMaxCues];
    core::Vec3 pull[core::kMaxCues];
    field.sample(soma[i], samples, pull);
    const double c = samples[guide_.signal_cue].c;
    receptors[i] = start ? core::bound_receptors(q.It, q.kpI, q.kmI, c) : core::soma_receptor_step(q, receptors[i], c, guide_.dt);
  });
  inhibition_from(receptors, inhibition, soma.size());
}

void AxonStages::inhibition_from(const double* receptors, double* inhibition, std::size_t n) const {
  // Each population's mean over its cell bodies, in id order (the populations take
  // consecutive ids; without populations every neuron is the explant), or each neuron's own.
  if (!population_inhibition_) {
    std::copy(receptors, receptors + n, inhibition);
    return;
  }
  std::vector<std::size_t> ends;
  for (const Population& p : populations_) ends.push_back((ends.empty() ? 0 : ends.back()) + p.count);
  if (ends.empty()) ends.push_back(n);
  std::size_t first = 0;
  for (const std::size_t end : ends) {
    core::population_inhibition(receptors, first, end, inhibition);
    first = end;
  }
}

void throw_signalling_failure(const Scene& scene, const SignallingFailure& f, std::uint32_t step) {
  static const char* names[core::kSignalSpecies] = {"A", "Ac", "Ic", "X", "Y", "Zx", "Zy", "F", "G", "Gs", "R"};
  const char* what = f.status == core::StiffStatus::kSingular    ? "the implicit system was singular"
                     : f.status == core::StiffStatus::kNotFinite ? "a species was not finite"
                                                                 : "a species left its range (below 0, A above A_t or F above F_t)";
  throw RunError(fmt::format(
      "signalling: the stiff step of axon {} failed at step {} ({}{}{}), with axons.signalling.substeps = {} ROS2 steps "
      "of {} {} per growth step, each halved up to {} times; give more sub-steps",
      f.neuron, step, what, f.species >= 0 ? ": species " : "", f.species >= 0 ? names[f.species] : "",
      scene.axons.signalling.substeps, scene.dt / scene.axons.signalling.substeps, scene.units.time,
      scene.axons.signalling.halvings));
}

void AxonStages::start_signals(const CueField& field, const std::vector<core::Vec3>& soma,
                               const std::vector<std::uint32_t>& slots, AxonArrays a) const {
  tbb::parallel_for(std::size_t{0}, slots.size(), [&](std::size_t s) {
    const std::uint32_t k = slots[s], id = a.id[k];
    core::CueSample samples[core::kMaxCues];
    core::Vec3 pull[core::kMaxCues];
    field.sample(soma[id], samples, pull);
    core::signalling_steady_state(guide_.signal, samples[guide_.signal_cue].c, a.inhibition[id],
                                  a.signal + static_cast<std::size_t>(k) * core::kSignalSpecies);
  });
}

GrowthCounts AxonStages::grow(const core::CellGridView& somas, Slots slots, AxonArrays a,
                              std::uint32_t step) const {
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, slots.size()), GrowthCounts{},
      [&](const tbb::blocked_range<std::size_t>& r, GrowthCounts acc) {
        for (std::size_t s = r.begin(); s != r.end(); ++s) {
          const std::uint32_t k = slots[s];
          if (a.status[k] != core::AxonStatus::kGrowing) continue;  // every slot, not a list
          const std::uint32_t id = a.id[k];
          const bool own = modulated_ || signalling_;
          const double l = own ? a.step_length[k] : params_.step_length;
          const core::Vec3 h = a.heading[k];
          const core::AxonStep st = core::grow_axon(id, a.tip[k], h, l, params_, somas);
          // The heading's random walk for the next step (independent of the move, so the
          // two overlap in the pipeline).
          a.heading[k] = core::wander(h, l, !own, wander_, seed_, id, step);
          a.tip[k] = st.tip;
          a.length[k] += st.advanced;
          a.steps[k] = step;
          a.status[k] = st.status;
          a.target[k] = st.target;
          acc.connected += st.status == core::AxonStatus::kConnected;
          acc.exited += st.status == core::AxonStatus::kExited;
        }
        return acc;
      },
      [](GrowthCounts x, GrowthCounts y) { return GrowthCounts{x.connected + y.connected, x.exited + y.exited}; });
}

}  // namespace axg

#pragma once
// Stages 2-5 of a step (SPEC §3.2) over a list of axon slots: sense and steer, then move,
// contact, bounds and the heading's random walk. One home for the per-axon loop bodies of
// every CPU engine: the reference engine (all axons, slot order of the soma grid) and the
// decomposed engine (distributed/: the axons whose tips lie in this rank's block). Each
// slot's update is a pure function of its own state, the soma grid and (seed, id, step).
#include <cstdint>
#include <vector>

#include "axonguide/core/cellgrid.hpp"
#include "axonguide/core/cues.hpp"
#include "axonguide/core/growth.hpp"
#include "axonguide/core/guide.hpp"
#include "axonguide/core/signalling.hpp"
#include "axonguide/core/steering.hpp"
#include "axonguide/core/wander.hpp"
#include "axonguide/model/steering.hpp"
#include "axonguide/scene/scene.hpp"

namespace axg {

class CueField;

// The axons' arrays, indexed by slot. step_length is null unless axons have their own
// step lengths (growth-rate modulation, the signalling model); signal and inhibition are
// null without the signalling model.
struct AxonArrays {
  const std::uint32_t* id;      // neuron id of each slot
  core::Vec3* tip;              // LU
  core::Vec3* heading;          // unit
  double* length;               // LU grown
  double* step_length;          // LU, per axon (modulation, signalling)
  core::AxonStatus* status;
  std::uint32_t* steps;         // the last step grown
  std::uint32_t* target;        // kNoNeuron unless connected
  double* signal = nullptr;            // kSignalSpecies per slot: the axon's network
  const double* inhibition = nullptr;  // by neuron id: the inhibitory signal its network reads
  double* sums = nullptr;              // sums_per_axon() per slot: the open decision interval's sums
};

// The first axon (lowest neuron id) whose signalling step failed in a stage, or none.
struct SignallingFailure {
  std::uint32_t neuron = core::kNoNeuron;
  int species = -1;
  core::StiffStatus status = core::StiffStatus::kOk;
};

// The slots a stage visits, in slot order: a list, or (list null) every slot below count.
// A run without cue fields starts with every slot and builds its list once seven in eight
// have stopped, so that a large network never holds a list of all its axons.
struct Slots {
  const std::uint32_t* list = nullptr;
  std::size_t count = 0;
  Slots(const std::vector<std::uint32_t>& v) : list(v.data()), count(v.size()) {}  // NOLINT: a list is a Slots
  static Slots all(std::size_t n) {
    Slots s;
    s.count = n;
    return s;
  }
  std::uint32_t operator[](std::size_t s) const { return list ? list[s] : static_cast<std::uint32_t>(s); }
  std::size_t size() const { return count; }

 private:
  Slots() = default;
};

struct GrowthCounts {
  std::uint64_t connected = 0, exited = 0;
};

// Exit 3 for a signalling step that failed (RunError): which axon, step and species.
[[noreturn]] void throw_signalling_failure(const Scene& scene, const SignallingFailure& f, std::uint32_t step);

class AxonStages {
 public:
  explicit AxonStages(const Scene& scene);
  AxonStages(const AxonStages&) = delete;  // guide_ points into cues_
  AxonStages& operator=(const AxonStages&) = delete;

  // Stage 2: every listed axon samples every cue at its tip and adds the samples to its
  // decision interval's sums; the step that closes the interval turns the heading on their
  // mean (and, with growth-rate modulation, sets the step length); with the signalling
  // model, every step integrates the axon's network, which sets its step length
  // (core/guide.hpp). Returns the first signalling failure (lowest neuron id), if any.
  SignallingFailure steer(const CueField& field, const std::vector<std::uint32_t>& slots, AxonArrays a,
                          std::uint32_t step) const;

  // The signalling model's cell bodies (every neuron, by id): the receptors at each soma
  // driven by the concentration of the model's cue there over one step (exactly), then the
  // inhibitory signal each network reads: its population's mean in id order, or its own.
  // `start` sets the receptors to their steady state instead (before the first step).
  void soma_signals(const CueField& field, const std::vector<core::Vec3>& soma, double* receptors, double* inhibition,
                    bool start) const;
  // Every listed axon's network at its steady state with the tip at its soma (the initial
  // condition, after soma_signals(start)).
  void start_signals(const CueField& field, const std::vector<core::Vec3>& soma, const std::vector<std::uint32_t>& slots,
                     AxonArrays a) const;
  // The inhibitory signal from the receptors (soma_signals' second half; also on resume).
  void inhibition_from(const double* receptors, double* inhibition, std::size_t n) const;
  bool signalling() const { return signalling_; }
  // Doubles of decision-interval sums each axon keeps (0 when every interval is one step).
  std::size_t sums_per_axon() const { return sums_per_axon_; }
  // Whether axons carry their own step length (modulation or signalling).
  bool own_step_lengths() const { return modulated_ || signalling_; }
  // The continuum rule moves first, then steers (core/guide.hpp, sample_point).
  bool steers_after_move() const { return guide_.after_move; }
  // Stages 3-5: every listed axon still growing moves, tests contact against `somas` and
  // the bounds, and its heading takes the random walk of the next step. Returns how many
  // connected and exited (integer sums: exact in any order).
  GrowthCounts grow(const core::CellGridView& somas, Slots slots, AxonArrays a,
                    std::uint32_t step) const;

  const core::GrowthParams& params() const { return params_; }
  bool modulated() const { return modulated_; }
  const std::vector<core::CueParams>& cues() const { return cues_; }

 private:
  std::uint64_t seed_;
  core::GrowthParams params_;
  core::WanderParams wander_;
  bool modulated_;
  bool signalling_;
  bool population_inhibition_ = true;
  std::vector<Population> populations_;
  std::vector<core::CueParams> cues_;
  core::GuideParams guide_;  // its cue pointer is cues_' data
  DecisionClock clock_;
  std::size_t sums_per_axon_ = 0;
};

}  // namespace axg

#pragma once
// Stage 2 of a step for one axon (SPEC §3.2, §3.5, §3.7), written once for every engine:
// from the field's samples at the tip, the decision of steering.hpp turns the heading, and
// the step length follows from it (growth-rate modulation) or from the signalling network,
// integrated over the step with the concentration at the tip (signalling.hpp). The
// reference engine calls it in a TBB loop, the accelerator in a kernel; each call writes
// only its own axon's state.
#include <cstdint>

#include "cues.hpp"
#include "hd.hpp"
#include "signalling.hpp"
#include "steering.hpp"
#include "vec3.hpp"

namespace axg::core {

// Every parameter of the stage (host-computed, passed by value).
struct GuideParams {
  SteerParams steer;
  SenseParams sense;
  const CueParams* cues;  // cue_count cues, in the engine's memory
  int cue_count;
  double step_length;     // l0, length units per step
  bool modulated;         // growth-rate modulation sets each axon's step length
  bool signalling;        // the signalling network sets it instead
  SignallingParams signal;
  int signal_cue, signal_substeps, signal_halvings;
  double dt;              // time units per step
  std::uint64_t seed;
};

// One axon's state that the stage writes: its heading, and (with modulation or the
// signalling model) its step length and its network's species.
struct GuidedAxon {
  Vec3* heading;
  double* step_length;  // null unless axons have their own step lengths
  double* signal;       // kSignalSpecies values; null without the signalling model
  double inhibition;    // the inhibitory signal its network reads (signalling model)
};

// The stage for axon `neuron` at `step`; returns the signalling step's status (kOk without
// the model), which the engine reports for the lowest failing neuron id.
AXG_HDI SignallingStep guide_axon(const GuideParams& p, const CueSample* samples, const Vec3* pull, GuidedAxon a,
                                  std::uint32_t neuron, std::uint32_t step) {
  const Steered st = steer_axon(*a.heading, samples, pull, p.cues, p.cue_count, p.sense, p.steer, p.seed, neuron, step);
  *a.heading = st.heading;
  if (p.modulated) *a.step_length = modulated_step(p.step_length, st.along, p.steer);
  if (!p.signalling) return {StiffStatus::kOk, -1, 0.0};
  const SignallingStep g = signalling_step(p.signal, a.signal, samples[p.signal_cue].c, a.inhibition, p.dt,
                                           p.signal_substeps, p.signal_halvings);
  *a.step_length = g.grown;
  return g;
}

}  // namespace axg::core

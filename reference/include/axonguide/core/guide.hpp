#pragma once
// Stage 2 of a step for one axon (SPEC §3.2, §3.5, §3.7), written once for every engine.
// The growth cone decides once per integration interval T (guidance.integration_time), a
// physical time: the interval's steps (dt <= T) add the field's samples at the tip along its
// path, and the step that closes the interval turns the heading by the decision of
// steering.hpp on their mean (the non-linear parts of the decision act on the integrated
// evidence only). The step length follows from the decision (growth-rate modulation, held
// until the next one) or from the signalling network, integrated over every step with the
// concentration at the tip (signalling.hpp). The report's rule (guidance.decision
// "per_step") is one step per interval. The reference engine calls guide_axon in a TBB loop,
// the accelerator in a kernel; each call writes only its own axon's state.
#include <cstddef>
#include <cstdint>

#include "cues.hpp"
#include "hd.hpp"
#include "signalling.hpp"
#include "steering.hpp"
#include "vec3.hpp"

namespace axg::core {

// Where a step stands in its decision interval: the same for every axon (all start at growth
// step 1), computed on the host for each step (model/steering.cpp, decision_at).
struct Decision {
  bool open;              // this step's samples start the interval's sums
  bool decide;            // this step closes the interval: the decision acts on the mean
  std::uint32_t samples;  // samples in the interval, this step's included
  std::uint32_t index;    // the interval's number from 1: the decision's random counter
};

// The sums an axon keeps over an interval, per cue: C, grad, grad_check, pull.
inline constexpr int kSumsPerCue = 10;

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
  bool after_move;        // the continuum rule: the engines steer after the step's move
};

// The continuum rule's order within a step (every engine): move, then sample and steer. An
// interval's samples are taken along the path it grew, each at the midpoint of the step just
// taken, tip - (l/2) h (l the axon's step length: its own under modulation, else l0; h the
// heading after the move's wandering, which differs from the move's by O(sqrt(l / L_p))), a
// midpoint rule for the time average of C and grad C along the path; and the interval's
// decision turns the heading for the moves after it, as in the limit dt -> 0, where it acts
// once the interval is over. Sampling the tip before the move and turning at once, the
// report's order, is first order in dt and guides 10 % more at dt = T (docs/methods.md
// §11.10). The report's per-step rule and the signalling model (whose network integrates its
// own input in time) keep that order: steer at the tip, then move.
AXG_HDI Vec3 sample_point(const GuideParams& p, Vec3 tip, Vec3 heading, const double* step_length) {
  if (!p.after_move) return tip;
  const double l = step_length ? *step_length : p.step_length;
  return tip - (0.5 * l) * heading;
}

// One axon's state that the stage writes: its heading, and (with modulation or the
// signalling model) its step length and its network's species.
struct GuidedAxon {
  Vec3* heading;
  double* step_length;  // null unless axons have their own step lengths
  double* signal;       // kSignalSpecies values; null without the signalling model
  double inhibition;    // the inhibitory signal its network reads (signalling model)
  double* sums;         // kSumsPerCue per cue; null when every interval is one step
};

// Adds this step's samples to the interval's sums (or starts them).
AXG_HDI void add_samples(double* sums, const CueSample* samples, const Vec3* pull, int cue_count, bool open) {
  for (int k = 0; k < cue_count; ++k) {
    double* q = sums + static_cast<std::size_t>(k) * kSumsPerCue;
    const CueSample& s = samples[k];
    const double v[kSumsPerCue] = {s.c,      s.grad.x,  s.grad.y,  s.grad.z,  s.grad_check.x,
                                   s.grad_check.y, s.grad_check.z, pull[k].x, pull[k].y, pull[k].z};
    for (int j = 0; j < kSumsPerCue; ++j) q[j] = open ? v[j] : q[j] + v[j];
  }
}

// The interval's mean samples from its sums.
AXG_HDI void mean_samples(const double* sums, std::uint32_t count, int cue_count, CueSample* samples, Vec3* pull) {
  const double n = static_cast<double>(count);
  for (int k = 0; k < cue_count; ++k) {
    const double* q = sums + static_cast<std::size_t>(k) * kSumsPerCue;
    samples[k] = {q[0] / n, {q[1] / n, q[2] / n, q[3] / n}, {q[4] / n, q[5] / n, q[6] / n}};
    pull[k] = {q[7] / n, q[8] / n, q[9] / n};
  }
}

// The stage for axon `neuron` at a step standing at `d` in its interval; returns the
// signalling step's status (kOk without the model), which the engine reports for the lowest
// failing neuron id. An arbour's growth cone passes its core::cone_key as `neuron`.
AXG_HDI SignallingStep guide_axon(const GuideParams& p, const CueSample* samples, const Vec3* pull, GuidedAxon a,
                                  std::uint64_t neuron, const Decision& d) {
  if (a.sums) add_samples(a.sums, samples, pull, p.cue_count, d.open);
  if (d.decide) {
    Steered st;
    if (a.sums) {
      CueSample mean[kMaxCues];
      Vec3 mean_pull[kMaxCues];
      mean_samples(a.sums, d.samples, p.cue_count, mean, mean_pull);
      st = steer_axon(*a.heading, mean, mean_pull, p.cues, p.cue_count, p.sense, p.steer, p.seed, neuron, d.index);
    } else {
      st = steer_axon(*a.heading, samples, pull, p.cues, p.cue_count, p.sense, p.steer, p.seed, neuron, d.index);
    }
    *a.heading = st.heading;
    if (p.modulated) *a.step_length = modulated_step(p.step_length, st.along, p.steer);
  }
  if (!p.signalling) return {StiffStatus::kOk, -1, 0.0};
  const SignallingStep g = signalling_step(p.signal, a.signal, samples[p.signal_cue].c, a.inhibition, p.dt,
                                           p.signal_substeps, p.signal_halvings);
  *a.step_length = g.grown;
  return g;
}

}  // namespace axg::core

#pragma once
// The axon step of SPEC §3.2, written once for every engine: the reference
// (engine/reference_engine.cpp), the ranks (distributed/src/engine.cpp) and the accelerator
// (accel/src/pipeline/engine.inl) each call axon_step with their own operations.
//   (1) the cue fields advance, and, with the signalling model, the somas read their signal;
//   (2) the growing axons steer: before they move, or under the continuum rule after they
//       have moved and met their contacts and bounds (core/guide.hpp, sample_point);
//   (3) they grow (move, contact, bounds);
//   (4) the engine settles: compacts its growing axons, or migrates them between ranks.
// Each stage is timed under its phase name in timings.csv.
#include <cstdint>

#include "axonguide/support/phase_times.hpp"

namespace axg {

struct AxonStepPlan {
  bool field = false;             // the scene has cue fields (steps 1 and 2)
  bool soma_signals = false;      // the signalling model reads each soma's signal after (1)
  bool steer_after_move = false;  // the continuum rule: (2) after (3)
  std::uint32_t warmup = 0;       // the field's warm-up steps before step 0
  const char* settle = "compact"; // the phase name of (4)
};

// advance(field_step, times), soma(), steer(step), grow(step), settle(step): the engine's
// operations for the stages above.
template <class Advance, class Soma, class Steer, class Grow, class Settle>
void axon_step(std::uint32_t step, PhaseTimes& times, const AxonStepPlan& plan, Advance&& advance, Soma&& soma,
               Steer&& steer, Grow&& grow, Settle&& settle) {
  const auto steer_stage = [&] {
    ScopedPhase p(times, step, "steer");
    steer(step);
  };
  if (plan.field) {
    advance(plan.warmup + step, times);
    if (plan.soma_signals) {
      ScopedPhase p(times, step, "signalling.somas");
      soma();
    }
    if (!plan.steer_after_move) steer_stage();
  }
  {
    ScopedPhase p(times, step, "grow");
    grow(step);
  }
  if (plan.field && plan.steer_after_move) steer_stage();
  {
    ScopedPhase p(times, step, plan.settle);
    settle(step);
  }
}

}  // namespace axg

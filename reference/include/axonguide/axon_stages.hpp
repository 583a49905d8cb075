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
#include "axonguide/core/steering.hpp"
#include "axonguide/core/wander.hpp"
#include "axonguide/scene.hpp"

namespace axg {

class CueField;

// The axons' arrays, indexed by slot. step_length is null without growth-rate modulation.
struct AxonArrays {
  const std::uint32_t* id;      // neuron id of each slot
  core::Vec3* tip;              // LU
  core::Vec3* heading;          // unit
  double* length;               // LU grown
  double* step_length;          // LU, per axon (modulation only)
  core::AxonStatus* status;
  std::uint32_t* steps;         // the last step grown
  std::uint32_t* target;        // kNoNeuron unless connected
};

struct GrowthCounts {
  std::uint64_t connected = 0, exited = 0;
};

class AxonStages {
 public:
  explicit AxonStages(const Scene& scene);

  // Stage 2: every listed axon samples every cue at its tip and makes its one turn (and,
  // with growth-rate modulation, sets its step length).
  void steer(const CueField& field, const std::vector<std::uint32_t>& slots, AxonArrays a, std::uint32_t step) const;
  // Stages 3-5: every listed axon moves, tests contact against `somas` and the bounds, and
  // its heading takes the random walk of the next step. Returns how many connected and
  // exited (integer sums: exact in any order).
  GrowthCounts grow(const core::CellGridView& somas, const std::vector<std::uint32_t>& slots, AxonArrays a,
                    std::uint32_t step) const;

  const core::GrowthParams& params() const { return params_; }
  bool modulated() const { return modulated_; }
  const std::vector<core::CueParams>& cues() const { return cues_; }

 private:
  std::uint64_t seed_;
  core::GrowthParams params_;
  core::WanderParams wander_;
  bool modulated_;
  std::vector<core::CueParams> cues_;
  core::SenseParams sense_;
  core::SteerParams steer_;
};

}  // namespace axg

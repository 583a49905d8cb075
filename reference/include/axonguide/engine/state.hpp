#pragma once
// What a run produces, independent of the backend that produced it.
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "axonguide/core/types.hpp"
#include "axonguide/core/vec3.hpp"

namespace axg {

// Counts after a step (SPEC §4 stats.csv).
struct StepStats {
  std::uint32_t step = 0;
  std::uint64_t growing = 0;
  std::uint64_t connected = 0;
  std::uint64_t exited = 0;
  std::uint64_t particles = 0;
};

// Per-neuron results, host side, structure of arrays indexed by neuron id.
struct NeuronState {
  std::vector<core::Vec3> tip;          // LU
  std::vector<double> length;           // LU grown
  std::vector<core::AxonStatus> status;
  std::vector<std::uint32_t> steps;     // steps grown (the step of contact or exit)
  std::vector<std::uint32_t> target;    // kNoNeuron unless connected

  void resize(std::size_t n) {
    tip.resize(n);
    length.assign(n, 0.0);
    status.assign(n, core::AxonStatus::kGrowing);
    steps.assign(n, 0);
    target.assign(n, core::kNoNeuron);
  }
  std::size_t size() const { return tip.size(); }
};

// An engine's state between two steps: what a checkpoint holds (SPEC §4). It is in neuron
// id (and particle id) order and independent of the backend, so any backend resumes
// from any backend's checkpoint. Scratch and derived data (the growing list, the soma and
// particle grids, sorted copies) are rebuilt from it.
struct EngineState {
  NeuronState axons;                 // tip, length, status, steps and target, by id
  std::vector<core::Vec3> heading;   // by id
  std::vector<double> step_length;   // by id; empty without growth-rate modulation
  std::uint64_t connected = 0, exited = 0;
  // Particle field: the particles alive, in id order, and the next id to emit.
  std::uint64_t next_particle_id = 0;
  std::vector<core::Vec3> particle_pos, particle_vel;  // velocity: ballistic motion only
  std::vector<std::uint64_t> particle_id;
  std::vector<std::uint16_t> particle_cue;
  // Grid field: every cue's current values, cue after cue (K n^3 values); particle field:
  // the estimate's meshes.
  std::vector<double> grid;
  // The signalling model: each axon's network (core::kSignalSpecies per neuron, by id) and
  // the cell-body receptors of each neuron.
  std::vector<double> signal, receptors;
  // The sums of the open decision interval (core::kSumsPerCue per cue per neuron, by id);
  // empty when every interval is one step.
  std::vector<double> guidance;
  // Arbour scenes: every neuron's arbour (morphology::append_arbours).
  std::vector<std::uint8_t> arbour;
};

// Wall-clock time per (step, phase): the only output allowed to vary between runs.
class PhaseTimes {
 public:
  struct Row {
    std::uint32_t step;  // 0 for work outside the step loop
    std::string phase;
    double seconds;
  };
  void add(std::uint32_t step, const char* phase, double seconds) {
    rows_.push_back({step, phase, seconds});
  }
  const std::vector<Row>& rows() const { return rows_; }
  std::vector<Row>& rows() { return rows_; }
  double total(const std::string& phase) const {
    double t = 0;
    for (const auto& r : rows_)
      if (r.phase == phase) t += r.seconds;
    return t;
  }

 private:
  std::vector<Row> rows_;
};

class ScopedPhase {
 public:
  ScopedPhase(PhaseTimes& times, std::uint32_t step, const char* phase)
      : times_(times), step_(step), phase_(phase), start_(std::chrono::steady_clock::now()) {}
  ~ScopedPhase() {
    times_.add(step_, phase_,
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count());
  }
  ScopedPhase(const ScopedPhase&) = delete;
  ScopedPhase& operator=(const ScopedPhase&) = delete;

 private:
  PhaseTimes& times_;
  std::uint32_t step_;
  const char* phase_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace axg

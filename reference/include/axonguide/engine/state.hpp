#pragma once
// What a run produces, independent of the backend that produced it.
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "axonguide/support/phase_times.hpp"
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

}  // namespace axg

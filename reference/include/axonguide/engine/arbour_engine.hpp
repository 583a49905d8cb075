#pragma once
// The arbour engine (SPEC §3.8; docs/methods.md §2.12): every neuron grows an axon arbour
// and dendrites whose growth cones elongate, steer, wander, branch (BESTL) and stop. Neurons
// are independent within a step (a cone reads only the somas and the cue field, which
// advances before the cones move), so each neuron's cones are
// stepped in index order by one task and the neurons in parallel: the bytes are the same
// for any thread count.
#include <cstdint>
#include <memory>

#include "axonguide/core/guide.hpp"
#include "axonguide/engine/engine.hpp"
#include "axonguide/model/arbours.hpp"
#include "axonguide/morphology/arbour.hpp"

namespace axg {

class CueField;

// One step (1-based) of one neuron's arbour: new stems (at birth, step 0, from the stem
// distributions), then every growing cone in index order steers by the cues (the per-step
// rule: before it moves), elongates by v0 n^-F dt times its rate factor, moves, meets a
// soma or the bounds, takes its heading's random walk and steers (the continuum rule: on
// its path, after it moves), as an axon does (core/guide.hpp, the one body); then it may
// branch into two daughters (the next indices), and new stems start at the stem rates.
struct ArbourSteering {
  const CueField* field = nullptr;  // null: no cues (guidance "direct")
  const core::GuideParams* guide = nullptr;
  core::Decision decision{};        // this step's place in its decision interval
  std::size_t sums_per_cone = 0;    // 0: every interval is one step (no sums kept)
};
struct ArbourContext {
  const ArbourParams* params;
  const core::GrowthParams* growth;  // contact radius, bounds and rule
  const core::CellGridView* somas;
  std::uint64_t seed;
  double dt;
  double soma_radius;
  std::uint32_t last_step;  // the scene's steps: every cone makes a point at its end
  ArbourSteering steering{};
};
void start_arbour(const ArbourContext& ctx, std::uint32_t neuron, core::Vec3 soma, morphology::Arbour& a);
void step_arbour(const ArbourContext& ctx, std::uint32_t neuron, core::Vec3 soma, std::uint32_t step,
                 morphology::Arbour& a);

// The expected points per neuron (a pilot of 64 topology-only trees per neurite type,
// morphology/tree_process.hpp, times the expected stems): the memory estimate's.
double expected_arbour_points(const Scene& scene);

// Bytes the arbour engine needs before growth (per neuron), and per stored point.
std::size_t arbour_bytes_per_neuron();
inline constexpr std::size_t kArbourBytesPerPoint = sizeof(core::Vec3) + 8;

std::unique_ptr<Engine> make_arbour_engine(const Scene& scene, Placement&& placement);

}  // namespace axg

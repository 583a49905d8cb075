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
#include "axonguide/morphology/arbour_step.hpp"

namespace axg {

class CueField;

// One step (1-based) of one neuron's arbour: morphology/arbour_step.hpp's three phases
// (the growing cones; lateral branches; new stems), on the arbour's own vectors. New stems
// at birth (step 0) are drawn from the stem-count distributions (start_arbour).
struct ArbourContext {
  const ArbourParams* params;
  morphology::ArbourStepContext step;  // its guide and decision set when the cones steer
  const CueField* field = nullptr;     // null: no cues (guidance "direct")
  std::size_t sums_per_cone = 0;       // 0: every decision interval is one step (no sums kept)
};
// The context of a scene's arbours, shared by both engines (the guide is set by the
// engine that steers: the reference's host copy, or the kernels' own).
ArbourContext arbour_context(const Scene& scene, const ArbourParams& params, const core::GrowthParams& growth,
                             const core::CellGridView& somas, const CueField* field, std::size_t sums_per_cone);
// Stems or lateral branches start at a rate: a neuron without growing cones may grow again.
bool arbours_restart(const ArbourParams& p);
void start_arbour(const ArbourContext& ctx, std::uint32_t neuron, core::Vec3 soma, morphology::Arbour& a);
// `stopped[0]` and `[1]` gain the cones that stopped at a soma and at the bounds.
void step_arbour(const ArbourContext& ctx, std::uint32_t neuron, core::Vec3 soma, std::uint32_t step,
                 morphology::Arbour& a, std::uint32_t stopped[2]);
// Throws the run error of a failed step (morphology::ArbourFail) of `neuron`; nothing for kNone.
void arbour_fail(morphology::ArbourFail fail, std::uint32_t neuron);

// The expected points per neuron (a pilot of 64 topology-only trees per neurite type,
// morphology/tree_process.hpp, times the expected stems): the memory estimate's.
double expected_arbour_points(const Scene& scene);

// Bytes the arbour engine needs before growth (per neuron), and per stored point.
std::size_t arbour_bytes_per_neuron();
inline constexpr std::size_t kArbourBytesPerPoint = sizeof(core::Vec3) + 8;

std::unique_ptr<Engine> make_arbour_engine(const Scene& scene, Placement&& placement);

}  // namespace axg

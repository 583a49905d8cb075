#pragma once
// A backend's simulation state and its per-step pipeline. The run (run.hpp) places the
// neurons with shared host code, hands them to an Engine, calls step() until no axon
// grows or the steps run out, then reads the results back. The reference and the CUDA
// accelerator implement this interface with the same core/ functions.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "axonguide/graph/graph.hpp"
#include "axonguide/morphology/arbour.hpp"
#include "axonguide/placement/placement.hpp"
#include "axonguide/scene/scene.hpp"
#include "axonguide/engine/state.hpp"

namespace axg {

struct GraphAnalysis {
  Csr out;                                // connections by source
  std::optional<BfsResult> bfs;           // when analysis.bfs_sources is non-empty
  std::vector<std::uint32_t> component;   // when analysis.components
  std::size_t component_count = 0;
  std::size_t largest_component = 0;
};

// Fills component_count and largest_component from `component`.
void summarize_components(GraphAnalysis& a);

class Engine {
 public:
  virtual ~Engine() = default;
  // The cue fields' warm-up before step 1 (cues.warmup_steps). A resumed engine is
  // loaded instead.
  virtual void warm_up() = 0;
  // The state after the last step (save) and its restoration into an engine freshly
  // built for the same scene and placement (load): checkpoints and resume.
  virtual void save(EngineState& out) = 0;
  virtual void load(const EngineState& in) = 0;
  // Runs every stage of step `step` (1-based) and returns the counts after it.
  virtual StepStats step(std::uint32_t step, PhaseTimes& times) = 0;
  // Current tips of all axons (for output.paths); only called when paths are recorded.
  virtual void tips(std::vector<core::Vec3>& out) = 0;
  // Positions and cue indices of the particles now, in id order (output frames).
  virtual void particles(std::vector<core::Vec3>& pos, std::vector<std::uint16_t>& cue) {
    pos.clear();
    cue.clear();
  }
  // Final per-neuron state; axons still growing are reported as max_steps.
  virtual void finish(NeuronState& out) = 0;
  // After finish(): the arbours by neuron id, moved out (arbour scenes; empty otherwise).
  virtual void arbours(std::vector<morphology::Arbour>& out) { out.clear(); }
  // The somas in id order, from an engine that took the placement's (the reference
  // engine built by make_reference_engine(scene, Placement&&)): a copy before finish(),
  // the engine's own after it. The run calls it only for such an engine.
  virtual void somas(std::vector<core::Vec3>& out) { out.clear(); }
  // Bytes of memory this engine holds (host or device), for the summary.
  virtual std::size_t bytes() const = 0;
  // A line about the cue field for the summary and the manifest (may be empty).
  virtual std::string note() const { return {}; }
  // The graph analysis of SPEC §3.6 on this backend, after finish(); false means "use
  // the host's" (the reference engine). The accelerator builds the CSR and runs BFS and
  // components on the device.
  virtual bool analyze(const Scene& scene, GraphAnalysis& out) {
    (void)scene;
    (void)out;
    return false;
  }
};

// Bytes per neuron the reference engine needs (for memory estimates before allocation).
std::size_t reference_bytes_per_neuron();

// The reference engine. Given the placement to keep, it takes the arrays (the placement is
// left empty) and holds one copy of the somas, which somas() gives back; given a const
// placement, it copies it first.
// An arbour scene (scene.arbours) gets the arbour engine (engine/arbour_engine.hpp).
std::unique_ptr<Engine> make_reference_engine(const Scene& scene, Placement&& placement);
std::unique_ptr<Engine> make_reference_engine(const Scene& scene, const Placement& placement);

}  // namespace axg

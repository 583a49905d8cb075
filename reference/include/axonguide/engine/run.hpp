#pragma once
// One run: placement (shared host code), the engine's step loop, the graph analysis and
// the output files. The CLI's `run`, the golden checks, the benchmarks and the tests all
// go through here.
#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "axonguide/core/cues.hpp"
#include "axonguide/engine/engine.hpp"
#include "axonguide/graph/graph.hpp"
#include "axonguide/network/appositions.hpp"
#include "axonguide/scene/scene.hpp"
#include "axonguide/engine/state.hpp"

namespace axg {

using EngineFactory =
    std::function<std::unique_ptr<Engine>(const Scene&, const Placement&)>;

struct RunResult;
struct RunCheckpoint;

struct RunOptions {
  // Builds the backend's engine; empty means the reference engine.
  EngineFactory make_engine;
  // Places the neurons; empty means place_neurons. A run decomposed over ranks
  // (distributed/) places them together: every rank gets an empty soma list but rank 0,
  // which gets them all (it writes the outputs), and make_engine builds the rank's share.
  std::function<Placement(const Scene&)> place;
  // Combines a flag word over the processes of a decomposed run (bitwise OR), so that all
  // of them take a checkpoint or stop at the same step; empty: one process.
  std::function<unsigned(unsigned)> agree;
  // Called after each step (for progress lines); may be empty.
  std::function<void(const StepStats&, std::uint32_t steps)> on_step;
  // Resume: start after this checkpoint's step, from its state (no placement, no
  // warm-up). Its scene hash must be the scene's. Its contents are moved into the run.
  RunCheckpoint* resume = nullptr;
  // Receives the run so far and the engine's state after step `step` (0: after setup)
  // when output.checkpoint_every divides the step, when output.checkpoint_seconds have
  // passed since the last checkpoint, and when stop_requested() is true. Never after
  // the last step. Empty: no checkpoints.
  std::function<void(const RunResult& progress, std::uint32_t step, const EngineState& engine)> on_checkpoint;
  // Polled after setup and after every step but the last; true ends the run there (after
  // the checkpoint) by throwing Interrupted.
  std::function<bool()> stop_requested;
};

// Thrown by run_scene when stop_requested() ended the run between two steps.
struct Interrupted : std::runtime_error {
  explicit Interrupted(std::uint32_t s) : std::runtime_error("interrupted"), step(s) {}
  std::uint32_t step;  // steps run
};

// Particles at one step (output.paths or output.vtk; every output.frames_every steps).
// Frames above kMaxFrameParticles keep every k-th particle by id, k = ceil(count / max).
inline constexpr std::size_t kMaxFrameParticles = 1000000;
struct ParticleFrame {
  std::uint32_t step = 0;
  std::uint64_t count = 0;   // particles in the field
  std::uint32_t stride = 1;  // every stride-th particle kept
  std::vector<core::Vec3> pos;
  std::vector<std::uint16_t> cue;
};

struct RunResult {
  Scene scene;  // as run (seed overrides applied)
  std::vector<core::Vec3> soma;
  std::uint64_t placement_redraws = 0;
  NeuronState neurons;
  std::vector<morphology::Arbour> arbours;  // arbour scenes: by neuron id
  // Scenes with synapses: the appositions on the final arbours, their connections (by
  // source, then target) and how many contacts the runs gathered.
  network::Appositions synapses;
  std::vector<network::Connection> synapse_connections;
  std::uint64_t contacts = 0;
  std::vector<StepStats> stats;           // step 0 and every step run
  std::vector<std::vector<core::Vec3>> paths;  // tips after each step (output.paths)
  std::vector<core::CueParams> cues;           // the sources, positions resolved
  std::vector<ParticleFrame> frames;
  GraphAnalysis graph;
  PhaseTimes times;
  std::uint32_t steps_run = 0;
  std::size_t engine_bytes = 0;
  std::string field_note;  // e.g. the explicit grid's sub-steps
  // A run decomposed over ranks: its blocks, placement rounds and traffic (run facts for
  // the manifest, like the thread count: they depend on the rank count). Null otherwise.
  nlohmann::json decomposition;
};

// Memory needed for the scene, estimated before anything is allocated.
std::uint64_t estimate_run_bytes(const Scene& scene);

// What refuses a scene before anything runs, in the order run_scene checks it: the neuron
// count (32-bit ids), the cue grids and meshes (nodes per axis, memory), and a packing that
// placement cannot reach. The command calls it before it touches the run folder, so that a
// refused scene never costs a previous run's files (--force). Throws InputError / RunError.
void check_scene_runs(const Scene& scene);

// Appositions, realised synapses and connections on the final arbours (scenes with
// synapses; run_scene calls it after the last step).
void detect_synapses(RunResult& r);

// Runs the scene. Throws InputError / RunError.
RunResult run_scene(const Scene& scene, const RunOptions& options);

GraphAnalysis analyze_graph(const Scene& scene, const NeuronState& neurons);
// The same analysis of a graph given by its edges (source[k] -> target[k], sorted by
// source then target): a synapse scene's connections.
GraphAnalysis analyze_graph(const Scene& scene, std::size_t neurons, const std::vector<std::uint32_t>& source,
                            const std::vector<std::uint32_t>& target);

// Writes every output file of SPEC §4 into dir, manifest.json last.
struct OutputInfo {
  std::vector<std::pair<std::string, std::string>> files;  // name, sha256
};
OutputInfo write_outputs(const RunResult& result, const std::filesystem::path& dir,
                         const std::string& backend_name, int threads,
                         const std::vector<std::string>& warnings);

// The files write_outputs writes for this scene, relative to the folder ("vtk/*.vtp" for
// the VTK frames); a cue scene without sources has no sources.csv. A running manifest
// lists them, so that --force can remove what a killed run left.
std::vector<std::string> planned_outputs(const Scene& scene);

// The bytes of connections.csv (sweeps hash them without writing the file).
std::string connections_csv(const RunResult& result);

// Whether stats.csv prints result.stats[k]: every output.stats_every steps, and the last.
bool stats_row_printed(const RunResult& result, std::size_t k);

// The manifest's "summary" (neurons, steps run, the final counts, redraws, components).
nlohmann::json run_summary(const RunResult& result);

}  // namespace axg

#include "axonguide/engine/run.hpp"

#include <algorithm>
#include <chrono>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <fmt/format.h>

#include "axonguide/engine/arbour_engine.hpp"
#include "axonguide/engine/checkpoint.hpp"
#include "axonguide/model/cues.hpp"
#include "axonguide/model/particles.hpp"
#include "axonguide/support/error.hpp"
#include "axonguide/support/fault.hpp"
#include "axonguide/placement/placement.hpp"

namespace axg {

std::uint64_t estimate_run_bytes(const Scene& scene) {
  const double n = static_cast<double>(scene.neurons.count);
  // Placement: soma, heading, overlap index (12 B). Engine: reference_bytes_per_neuron.
  // Results and graph: copy of the state, CSR out/in/undirected, level, parent, component.
  const double per_neuron = 2 * 24 + 12 + static_cast<double>(reference_bytes_per_neuron()) + 64;
  double bytes = n * per_neuron;
  if (scene.output.paths) bytes += n * 24.0 * (scene.steps + 1.0);
  // Per-step bookkeeping, whatever the neuron count: a stats row (40 B) and the timing
  // rows (48 B and a name on the heap; grow and compact, steer and the field's stages
  // with cues, a checkpoint), each doubled for vector growth.
  double rows = 2;
  if (scene.uses_cues()) {
    rows += 1;
    if (scene.cues.field == FieldKind::kParticles) rows += scene.cues.particles.collisions ? 5 : 4;
    if (scene.cues.field == FieldKind::kGrid) rows += 1;
  }
  if (scene.output.checkpoint_every != 0) rows += 1;
  bytes += (scene.steps + 1.0) * 2.0 * (40.0 + rows * 80.0);
  // Particle frames (paths or VTK with particles): up to kMaxFrameParticles each.
  if ((scene.output.paths || scene.output.vtk) && scene.uses_cues() && scene.cues.field == FieldKind::kParticles) {
    const double frames = scene.steps / static_cast<double>(scene.output.frames_every) + 1.0;
    bytes += frames * std::min(expected_particles(scene), static_cast<double>(kMaxFrameParticles)) * 26.0;
  }
  // Arbours: their expected points (32 B each, doubled for vector growth, and 16 B of
  // cone state a point as a margin) and the per-neuron records.
  if (scene.arbours) bytes += n * (expected_arbour_points(scene) * (2.0 * kArbourBytesPerPoint + 16.0) +
                                   static_cast<double>(arbour_bytes_per_neuron()));
  // The output writers' row buffers (32 chunks of 8192 formatted rows).
  bytes += 48.0 * 1024 * 1024;
  // Particles; a grid field is checked when it is created (a scene error, exit 2).
  if (scene.uses_cues() && scene.cues.field == FieldKind::kParticles)
    bytes += static_cast<double>(estimate_cue_bytes(scene));
  return bytes >= 1.8e19 ? UINT64_MAX : static_cast<std::uint64_t>(bytes);
}

GraphAnalysis analyze_graph(const Scene& scene, const NeuronState& neurons) {
  const std::size_t n = neurons.size();
  std::vector<std::uint32_t> src, dst;  // the edge lists at their size
  const std::size_t edges = static_cast<std::size_t>(
      std::count_if(neurons.target.begin(), neurons.target.end(), [](std::uint32_t t) { return t != core::kNoNeuron; }));
  src.reserve(edges);
  dst.reserve(edges);
  for (std::size_t i = 0; i < n; ++i)
    if (neurons.target[i] != core::kNoNeuron) {
      src.push_back(static_cast<std::uint32_t>(i));
      dst.push_back(neurons.target[i]);
    }
  return analyze_graph(scene, n, src, dst);
}

GraphAnalysis analyze_graph(const Scene& scene, std::size_t n, const std::vector<std::uint32_t>& source,
                            const std::vector<std::uint32_t>& target) {
  GraphAnalysis a;
  a.out = csr_from_edges(n, source, target);
  if (!scene.analysis.bfs_sources.empty()) {
    std::vector<std::uint32_t> sources(scene.analysis.bfs_sources.begin(), scene.analysis.bfs_sources.end());
    a.bfs = bfs(a.out, sources);
  }
  if (scene.analysis.components) {
    a.component = edge_components(a.out);
    summarize_components(a);
  }
  return a;
}

void summarize_components(GraphAnalysis& a) {
  std::vector<std::uint32_t> size(a.component.size(), 0);
  for (std::uint32_t c : a.component) ++size[c];
  a.component_count = 0;
  a.largest_component = 0;
  for (std::size_t v = 0; v < size.size(); ++v)
    if (size[v] != 0) {
      ++a.component_count;
      a.largest_component = std::max<std::size_t>(a.largest_component, size[v]);
    }
}

void check_scene_runs(const Scene& scene) {
  if (scene.neurons.count >= core::kNoNeuron)
    throw InputError(fmt::format("scene: neurons.count = {}: must be below {} (32-bit neuron ids)",
                                 scene.neurons.count, core::kNoNeuron));
  check_cue_fields(scene, make_cues(scene));  // every backend refuses the same grids
  if (scene.neurons.overlap_reject && scene.neurons.count >= 2) check_packing(scene);
}

void detect_synapses(RunResult& r) {
  ScopedPhase p(r.times, 0, "synapses");
#if defined(__GLIBC__)
  // Growth freed its vectors' old buffers (a cone's points grow by doubling) into the
  // allocator's arenas; hand them back to the system before detection's arrays are made,
  // so that the two do not add up in the peak. Only memory moves, never a value.
  malloc_trim(0);
#endif
  const network::Segments g = network::segments_of(r.arbours, r.soma, r.scene.neurons.soma_radius);
  const SynapseParams sp = synapse_params(r.scene);
  r.synapses = network::find_appositions(g, sp, &r.contacts);
  r.synapse_connections = network::connections_of(r.synapses);
}

RunResult run_scene(const Scene& scene, const RunOptions& options) {
  check_memory_estimate(estimate_run_bytes(scene),
                        fmt::format("a run of {} neurons", scene.neurons.count));
  check_scene_runs(scene);
  RunCheckpoint* resume = options.resume;
  if (resume && resume->scene_hash != scene_hash(scene))
    throw InputError("--resume: the checkpoint was written for another scene");
  RunResult r;
  Placement placement;
  if (resume) {
    r = std::move(resume->progress);  // somas, stats, paths, frames and timings so far
    placement.soma = std::move(r.soma);
    placement.heading = resume->engine.heading;
  } else {
    ScopedPhase p(r.times, 0, "placement");
    placement = options.place ? options.place(scene) : place_neurons(scene);
    fault_point("placement");
  }
  r.scene = scene;
  if (!resume) r.placement_redraws = placement.redraws;
  std::unique_ptr<Engine> engine;
  // The reference engine takes the placement's arrays and keeps the only copy of the
  // somas until finish() (a large network's memory peak is the engine's construction);
  // r.soma holds them only for a checkpoint and from readback on.
  const bool engine_has_somas = !options.make_engine;
  {
    ScopedPhase p(r.times, 0, resume ? "resume" : "setup");
    engine = options.make_engine ? options.make_engine(scene, placement)
                                 : make_reference_engine(scene, std::move(placement));
    if (resume) {
      engine->load(resume->engine);
      resume->engine = EngineState{};
    } else {
      engine->warm_up();
    }
  }
  if (!engine_has_somas) r.soma = std::move(placement.soma);
  placement = Placement{};

  r.cues = make_cues(scene);
  const bool frames = (scene.output.paths || scene.output.vtk) && scene.uses_cues() &&
                      scene.cues.field == FieldKind::kParticles;
  auto record_frame = [&](std::uint32_t step) {
    ParticleFrame f;
    f.step = step;
    engine->particles(f.pos, f.cue);
    f.count = f.pos.size();
    if (f.count > kMaxFrameParticles) {
      f.stride = static_cast<std::uint32_t>((f.count + kMaxFrameParticles - 1) / kMaxFrameParticles);
      std::size_t kept = 0;
      for (std::size_t i = 0; i < f.count; i += f.stride, ++kept) {
        f.pos[kept] = f.pos[i];
        f.cue[kept] = f.cue[i];
      }
      f.pos.resize(kept);
      f.cue.resize(kept);
    }
    r.frames.push_back(std::move(f));
  };
  // Checkpoints between steps: by step count, by wall clock, and before stopping.
  using clock = std::chrono::steady_clock;
  auto last_checkpoint = clock::now();
  const double interval = scene.output.checkpoint_interval();
  // The wall clock and the signals are each process's own: a decomposed run agrees on them.
  enum : unsigned { kStop = 1, kClockDue = 2 };
  auto between_steps = [&](std::uint32_t step) {
    unsigned flags = 0;
    if (options.stop_requested && options.stop_requested()) flags |= kStop;
    if (options.on_checkpoint && interval > 0 &&
        std::chrono::duration<double>(clock::now() - last_checkpoint).count() >= interval)
      flags |= kClockDue;
    if (options.agree) flags = options.agree(flags);
    const bool stop = (flags & kStop) != 0;
    if (options.on_checkpoint) {
      const bool due = (scene.output.checkpoint_every != 0 && step != 0 && step % scene.output.checkpoint_every == 0) ||
                       (flags & kClockDue) != 0;
      if (due || stop) {
        ScopedPhase p(r.times, step, "checkpoint");
        EngineState state;
        engine->save(state);
        r.steps_run = step;
        if (engine_has_somas) engine->somas(r.soma);
        options.on_checkpoint(r, step, state);
        if (engine_has_somas) std::vector<core::Vec3>().swap(r.soma);
        last_checkpoint = clock::now();
      }
    }
    if (stop) throw Interrupted(step);
  };
  const std::uint32_t first = resume ? resume->step + 1 : 1;
  // Arbour scenes write their cones' paths from the arbours (io/writers.cpp, write_arbour_paths).
  const bool record_paths = scene.output.paths && !scene.arbours;
  if (!resume) {
    StepStats s0;
    s0.growing = scene.neurons.count;
    r.stats.push_back(s0);
    if (record_paths) {
      r.paths.emplace_back();
      engine->tips(r.paths.back());
    }
    fault_point("setup");
    if (scene.steps > 0) between_steps(0);
  }
  for (std::uint32_t step = first; step <= scene.steps; ++step) {
    const StepStats s = engine->step(step, r.times);
    r.stats.push_back(s);
    r.steps_run = step;
    if (record_paths) {
      r.paths.emplace_back();
      engine->tips(r.paths.back());
    }
    if (options.on_step) options.on_step(s, scene.steps);
    const bool last = s.growing == 0 || step == scene.steps;
    if (frames && (step % scene.output.frames_every == 0 || last)) record_frame(step);
    fault_point(fmt::format("step {}", step));
    if (last) break;  // nothing left to grow or guide, or no steps left
    between_steps(step);
  }
  r.engine_bytes = engine->bytes();
  r.field_note = engine->note();
  {
    ScopedPhase p(r.times, 0, "readback");
    engine->finish(r.neurons);
    engine->arbours(r.arbours);
    if (engine_has_somas) engine->somas(r.soma);
  }
  if (scene.synapses) {
    engine.reset();
    detect_synapses(r);
    ScopedPhase p(r.times, 0, "graph");
    std::vector<std::uint32_t> src, dst;
    for (const network::Connection& c : r.synapse_connections) {
      src.push_back(c.source);
      dst.push_back(c.target);
    }
    r.graph = analyze_graph(scene, r.neurons.size(), src, dst);
  } else {
    ScopedPhase p(r.times, 0, "graph");
    if (!engine->analyze(scene, r.graph)) {
      engine.reset();
      r.graph = analyze_graph(scene, r.neurons);
    }
  }
  engine.reset();
  return r;
}

}  // namespace axg

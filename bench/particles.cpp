// Cue fields: particle-steps per second (emission, motion, death, compaction, grid
// rebuild and sensing together) and grid voxel-updates per second (explicit and
// implicit at 128^3), plus the report's 1000-neuron cue scene end to end.
#include <fmt/format.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>

#include <cmath>

#include "axonguide/core/random.hpp"
#include "axonguide/core/sampler.hpp"
#include "axonguide/model/cues.hpp"
#include "axonguide/model/stencil.hpp"
#include "axonguide/support/error.hpp"
#include "axonguide/fields/fields.hpp"
#include "axonguide/placement/placement.hpp"
#include "axonguide/support/threads.hpp"
#include "bench.hpp"

namespace axg::bench {

namespace {

// 10^4 growth cones that keep growing (tiny somas, unbounded domain) among four sources
// whose steady state holds about `particles` particles (lifetime 20 steps; nothing leaves
// the domain, so the count is emission x 20).
Scene particle_scene(double particles) {
  Scene s;
  s.steps = 100000;
  s.neurons.count = 10000;
  s.neurons.radius = 20;
  s.neurons.soma_radius = 0.01;
  s.neurons.overlap_reject = false;
  s.axons.contact_distance = 0;
  s.axons.bounds_radius = 1e6;
  s.guidance.model = GuidanceModel::kSnr;
  s.cues.field = FieldKind::kParticles;
  s.cues.random_sources.count = 4;
  s.cues.random_sources.decay = -std::log(1.0 - 1.0 / 20.0);
  s.cues.random_sources.emission = particles / (4 * 20);
  s.cues.random_sources.diffusion = 0.05;
  s.analysis.bfs_sources.clear();
  return s;
}

struct Measured {
  double particle_steps = 0, seconds = 0, particles = 0;
};

// Warms the field up to steady state, then times `measured` whole engine steps.
Measured measure_particles(const Scene& s, const EngineFactory& make, int measured) {
  const Placement p = place_neurons(s);
  std::unique_ptr<Engine> engine = make ? make(s, p) : make_reference_engine(s, p);
  engine->warm_up();  // as a run does (cues.warmup_steps; none in the benchmark scenes)
  PhaseTimes times;
  std::uint32_t step = 0;
  const double target = 0.97 * 20 * 4 * s.cues.random_sources.emission;
  while (step < 300 && static_cast<double>(engine->step(++step, times).particles) < target) {
  }
  Measured m;
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < measured; ++k) m.particle_steps += static_cast<double>(engine->step(++step, times).particles);
  m.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  m.particles = m.particle_steps / measured;
  return m;
}

}  // namespace

std::vector<Row> particles(const Options& o) {
  std::vector<Row> rows;
  auto emit = [&](Row r) {
    if (o.on_row) o.on_row(r);
    rows.push_back(std::move(r));
  };
  const int threads = resolve_threads(o.max_threads);
  const bool gpu = o.backend == "cuda";
  std::vector<double> sizes = gpu ? std::vector<double>{1e5, 1e6, 1e7, 1e8} : std::vector<double>{1e4, 1e5, 1e6};
  if (o.quick) sizes.pop_back();
  double reference_rate = 0;
  for (double target : sizes) {
    const Scene s = particle_scene(target);
    const int steps = o.quick ? 5 : 10;
    Measured m;
    try {
      m = with_threads(threads, [&] { return measure_particles(s, o.make_engine, steps); });
    } catch (const RunError& e) {
      emit(failed_row("particles", "engine step, 10^4 growth cones sensing", "axonguide " + o.backend, threads, target,
                      "particle-steps/s", e.what()));
      continue;
    }
    double speedup = 0;
    std::string note = fmt::format("{} steps at {:.3g} particles", steps, m.particles);
    if (gpu && target <= 1e6) {
      // The 2-core reference at the same size, in the same run.
      const Measured r = with_threads(2, [&] { return measure_particles(s, {}, steps); });
      reference_rate = r.particle_steps / r.seconds;
    }
    if (gpu && reference_rate > 0) {
      speedup = (m.particle_steps / m.seconds) / reference_rate;
      note += target <= 1e6 ? "; vs the 2-thread reference at this size" : "; vs the 2-thread reference at 10^6";
    }
    emit({"particles", "engine step, 10^4 growth cones sensing", "axonguide " + o.backend, threads, m.particles,
          m.seconds, m.particle_steps / m.seconds, "particle-steps/s", speedup, gpu ? "reference (2 threads)" : "",
          note});
  }
  {
    const Scene scene = paper_cue_scene(1000);
    const ChildRun c = run_child(scene, threads, o.backend);
    const std::string name = "paper-cue-1000 (report Table 5: 300.5 s)";
    if (c.status != 0)  // no time for a run that did not finish
      emit(failed_row("end-to-end", name, "axonguide " + o.backend, threads, 1000, "neurons/s",
                      fmt::format("axonguide run exited {}", c.status)));
    else
      emit({"end-to-end", name, "axonguide " + o.backend, threads, 1000, c.seconds, 1000 / c.seconds, "neurons/s",
            300.5 / c.seconds, "report Table 5", fmt::format("exit 0, peak {:.0f} MiB", c.peak_bytes / 1048576.0)});
  }
  return rows;
}

std::vector<Row> grid(const Options& o) {
  std::vector<Row> rows;
  auto emit = [&](Row r) {
    if (o.on_row) o.on_row(r);
    rows.push_back(std::move(r));
  };
  const int threads = resolve_threads(o.max_threads);
  const int n = o.quick ? 64 : 128;
  for (GridScheme scheme : {GridScheme::kExplicit, GridScheme::kImplicit}) {
    Scene s;
    s.neurons.radius = 5;
    s.guidance.model = GuidanceModel::kSnr;
    s.cues.field = FieldKind::kGrid;
    s.cues.grid.scheme = scheme;
    s.cues.grid.spacing = 10.0 / (n - 1) + 1e-12;
    s.cues.random_sources.count = 1;
    s.cues.random_sources.diffusion = 0.002;  // one explicit sub-step per step at this spacing
    const auto cues = make_cues(s);
    const GridGeometry3 g = grid_field_geometry(s);
    with_threads(threads, [&] {
      auto field = make_reference_field(s, cues);
      PhaseTimes times;
      field->advance(1, times);
      const std::uint32_t substeps = scheme == GridScheme::kExplicit ? explicit_substeps(cues[0], g.h, s.dt) : 1;
      const int measured = o.quick ? 3 : 10;
      const auto t0 = std::chrono::steady_clock::now();
      for (int k = 0; k < measured; ++k) field->advance(static_cast<std::uint32_t>(k + 2), times);
      const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const double updates = static_cast<double>(g.nodes()) * substeps * measured;
      // The reference field whatever --backend says (the accelerator's is timed inside its
      // engine step), so the row names the reference.
      emit({"grid", fmt::format("{} {}^3 nodes, 1 cue", name_of(scheme), g.n), "axonguide reference", threads,
            static_cast<double>(g.nodes()), t / measured, updates / t, "voxel-updates/s", 0, "",
            fmt::format("{} sub-step(s) per step; s per step", substeps)});
    });
  }
  return rows;
}

}  // namespace axg::bench

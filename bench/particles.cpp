// Cue fields: particle-steps per second (emission, motion, death, compaction, grid
// rebuild and sensing together) and grid voxel-updates per second (explicit and
// implicit at 128^3), plus the report's 1000-neuron cue scene end to end.
#include <fmt/format.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>

#include <cmath>

#include "axonguide/core/random.hpp"
#include "axonguide/core/sampler.hpp"
#include "axonguide/cue_setup.hpp"
#include "axonguide/fields.hpp"
#include "axonguide/threads.hpp"
#include "bench.hpp"

namespace axg::bench {

namespace {

// Four sources whose steady state holds about `particles` particles (lifetime 20 steps).
Scene particle_scene(double particles) {
  Scene s;
  s.neurons.radius = 20;  // sources far from the absorbing boundary: few particles leave
  s.guidance.model = GuidanceModel::kSnr;
  s.cues.field = FieldKind::kParticles;
  s.cues.random_sources.count = 4;
  s.cues.random_sources.decay = -std::log(1.0 - 1.0 / 20.0);
  s.cues.random_sources.emission = 1.15 * particles / (4 * 20);  // ~13 % leave the domain
  s.cues.random_sources.diffusion = 0.05;
  return s;
}

}  // namespace

std::vector<Row> particles(const Options& o) {
  std::vector<Row> rows;
  auto emit = [&](Row r) {
    if (o.on_row) o.on_row(r);
    rows.push_back(std::move(r));
  };
  const int threads = resolve_threads(o.max_threads);
  std::vector<double> sizes{1e4, 1e5, 1e6};
  if (o.quick) sizes.pop_back();
  const std::size_t probes = 10000;  // growth cones sensing every step
  for (double target : sizes) {
    const Scene s = particle_scene(target);
    const auto cues = make_cues(s);
    with_threads(threads, [&] {
      auto field = make_reference_field(s, cues);
      std::vector<core::Vec3> tips(probes);
      for (std::size_t i = 0; i < probes; ++i) {
        core::Rng rng(4, core::Stream::kBenchmark, i, 0);
        tips[i] = 8.0 * core::unit_ball_rejection(rng);
      }
      PhaseTimes times;
      std::uint32_t step = 0;
      while (static_cast<double>(field->particles()) < 0.95 * target && step < 300) field->advance(++step, times);
      const int measured = o.quick ? 5 : 10;
      double particle_steps = 0;
      std::vector<double> sink(probes);
      const auto t0 = std::chrono::steady_clock::now();
      for (int k = 0; k < measured; ++k) {
        field->advance(++step, times);
        particle_steps += static_cast<double>(field->particles());
        tbb::parallel_for(std::size_t{0}, probes, [&](std::size_t i) {
          core::CueSample samples[core::kMaxCues];
          core::Vec3 pull[core::kMaxCues];
          field->sample(tips[i], samples, pull);
          sink[i] = samples[0].c;
        });
      }
      const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      emit({"particles", "particle field step + 10^4 sensing growth cones", "axonguide " + o.backend, threads,
            particle_steps / measured, t, particle_steps / t, "particle-steps/s", 0, "",
            fmt::format("{} steps at {:.3g} particles", measured, particle_steps / measured)});
    });
  }
  {
    const Scene scene = paper_cue_scene(1000);
    const ChildRun c = run_child(scene, threads, o.backend);
    emit({"end-to-end", "paper-cue-1000 (report Table 5: 300.5 s)", "axonguide " + o.backend, threads, 1000,
          c.seconds, 1000 / c.seconds, "neurons/s", 300.5 / c.seconds, "report Table 5",
          fmt::format("exit {}, peak {:.0f} MiB", c.status, c.peak_bytes / 1048576.0)});
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
      emit({"grid", fmt::format("{} {}^3 nodes, 1 cue", name_of(scheme), g.n), "axonguide " + o.backend, threads,
            static_cast<double>(g.nodes()), t / measured, updates / t, "voxel-updates/s", 0, "",
            fmt::format("{} sub-step(s) per step; s per step", substeps)});
    });
  }
  return rows;
}

}  // namespace axg::bench

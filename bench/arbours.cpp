// Arbours (issue 41): 10^4 neurons of scenes/culture.json with arbours about twice the
// data's 5-day size (~50 axon terminal segments, ~2.5 mm of axon, ~12 dendrites per
// neuron), grown end to end (placement, growth, readback; no output), then their SWC
// written separately. Rates: growth-cone steps, um of neurite grown (path length of every
// cone, axons and dendrites), bytes per stored point. NETMORPH's published figure (640,000
// axon segments for 992 neurons in 21.9 s on one thread; Koene et al. 2009) is quoted, not
// run: it gives segments per second, whose length this machine cannot measure without
// NETMORPH (docs/methods.md §12.7 says what that leaves open).
#include <chrono>

#include <fmt/format.h>

#include "axonguide/engine/arbour_engine.hpp"
#include "axonguide/support/files.hpp"
#include "axonguide/io/swc.hpp"
#include "axonguide/scene/scene.hpp"
#include "axonguide/support/resources.hpp"
#include "axonguide/support/threads.hpp"
#include "bench.hpp"

namespace axg::bench {

Scene arbour_benchmark_scene(std::uint64_t neurons) {
  Scene s = load_scene_file((data_dir() / "scenes" / "culture.json").string()).scene;
  // The culture's density (300 neurons in a disc of radius 1000 um), and arbours twice the
  // data's 5-day size: the fitted axon B 6.863 -> 8.6 and v0 1.373 -> 3.0 um/h (on 300
  // neurons: terminal segments 31 -> 47, axon 0.98 -> 2.7 mm, 13.8 dendrites).
  s.neurons.count = neurons;
  s.neurons.shape = RegionShape::kDisc;
  s.neurons.radius = 1000.0 * std::sqrt(static_cast<double>(neurons) / 300.0);
  s.arbours->axon.b = 8.6;
  s.arbours->axon.v0 = 3.0;
  s.output.swc = true;
  return s;
}

namespace {

struct ArbourRun {
  double seconds = 0, swc_seconds = 0;
  double cone_steps = 0, micrometres = 0, points = 0, point_bytes = 0;
  double terminals = 0, axon_um = 0, dendrites = 0;
};

ArbourRun time_arbours(const Scene& scene, bool write) {
  ArbourRun a;
  RunOptions options;
  const auto t0 = std::chrono::steady_clock::now();
  RunResult r = run_scene(scene, options);
  a.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double um = scene.units.micrometres();
  for (const morphology::Arbour& arb : r.arbours) {
    for (const morphology::Cone& c : arb.cones) {
      a.micrometres += c.length * um;
      a.cone_steps += static_cast<double>(c.ended - c.born);
      if (c.type == morphology::kAxonType) {
        a.axon_um += c.length * um;
        a.terminals += c.status != morphology::ConeStatus::kBranched;
      }
    }
    for (const morphology::Tree& t : arb.trees) a.dendrites += t.type == morphology::kDendriteType;
    a.points += static_cast<double>(arb.point.size());
    a.point_bytes += static_cast<double>(arb.point.capacity() * sizeof(core::Vec3) + arb.cone_of.capacity() * 4 +
                                         arb.step_of.capacity() * 4);
  }
  if (write) {
    const ScratchDir scratch("axonguide-bench-swc");
    OutputInfo info;
    const auto t1 = std::chrono::steady_clock::now();
    write_swc(r, scratch.path(), info);
    a.swc_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  }
  return a;
}

}  // namespace

std::vector<Row> arbours(const Options& o) {
  std::vector<Row> rows;
  auto emit = [&](Row r) {
    if (o.on_row) o.on_row(r);
    rows.push_back(std::move(r));
  };
  const int max_threads = resolve_threads(o.max_threads);
  const std::uint64_t n = o.quick ? 1000 : 10000;
  const Scene scene = arbour_benchmark_scene(n);
  const std::string name = fmt::format("arbours, culture x2 size ({} neurons, 5 days, dt 0.5 h)", n);
  std::vector<int> thread_counts{max_threads};
  if (max_threads > 1) thread_counts.insert(thread_counts.begin(), 1);
  // NETMORPH (Koene et al. 2009): 640,000 axon segments for 992 neurons in 21.9 s, one thread.
  constexpr double kNetmorphSegmentsPerSecond = 640000.0 / 21.9;
  double direct_seconds = 0;
  for (const int threads : thread_counts) {
    ArbourRun a;
    try {
      a = with_threads(threads, [&] { return time_arbours(scene, threads == max_threads); });
    } catch (const std::exception& e) {
      emit(failed_row("arbours", name, "axonguide reference", threads, double(n), "um/s", e.what()));
      continue;
    }
    const double per_neuron = 1.0 / static_cast<double>(n);
    emit({"arbours", name + ": end to end, no output", "axonguide reference", threads, double(n), a.seconds,
          a.micrometres / a.seconds, "um/s", 0, "",
          fmt::format("{:.1f} axon terminal segments, {:.0f} um of axon, {:.1f} dendrites per neuron; {:.3g} um/s per "
                      "thread: 100x NETMORPH's published 29,224 axon segments/s per core if its segments average "
                      "<= {:.2f} um, 1x if <= {:.0f} um",
                      a.terminals * per_neuron, a.axon_um * per_neuron, a.dendrites * per_neuron,
                      a.micrometres / a.seconds / threads,
                      a.micrometres / a.seconds / threads / kNetmorphSegmentsPerSecond / 100.0,
                      a.micrometres / a.seconds / threads / kNetmorphSegmentsPerSecond)});
    emit({"arbours", name + ": growth-cone steps", "axonguide reference", threads, double(n), a.seconds,
          a.cone_steps / a.seconds, "cone-steps/s", 0, "", ""});
    if (threads == max_threads) {
      direct_seconds = a.seconds;
      emit({"arbours", name + ": stored points", "axonguide reference", threads, a.points, a.seconds,
            a.point_bytes / a.points, "bytes/point", 0, "",
            fmt::format("{:.0f} points of 32 bytes ({} B position, cone, step), vector capacity included",
                        a.points, sizeof(core::Vec3))});
      emit({"arbours", name + ": SWC writing (morphologies/*.swc)", "axonguide reference", threads, double(n),
            a.swc_seconds, double(n) / a.swc_seconds, "files/s", 0, "", ""});
    }
  }
  // The same arbours with every cone steered by the cues (validate branching §E's gradient:
  // an imposed exponential gradient of 1 % per 10 um, SNR, snapshot noise, T = 1 h), beside
  // the direct run above on the same machine: the cost of steering.
  Scene steered = scene;
  steered.output.swc = false;
  steered.guidance.model = GuidanceModel::kSnr;
  steered.guidance.noise = core::NoiseForm::kSnapshot;
  steered.guidance.gain = 40;
  steered.guidance.integration_time = 1.0;
  steered.guidance.growth_cone_width = 10;
  steered.guidance.sensing_radius = 10;
  steered.cues.field = FieldKind::kImposed;
  steered.cues.imposed.direction = {1, 0, 0};
  steered.cues.imposed.steepness = 1.0;
  Source attractant;
  attractant.position = core::Vec3{0, 0, 0};
  steered.cues.sources = {attractant};
  try {
    const ArbourRun a = with_threads(max_threads, [&] { return time_arbours(steered, false); });
    emit({"arbours", name + ": every cone steered (imposed gradient, SNR, T = 1 h)", "axonguide reference",
          max_threads, double(n), a.seconds, a.micrometres / a.seconds, "um/s", 0, "",
          fmt::format("{:.2f}x the direct run's time ({:.2f} s) on the same threads", a.seconds / direct_seconds,
                      direct_seconds)});
  } catch (const std::exception& e) {
    emit(failed_row("arbours", name + ": every cone steered", "axonguide reference", max_threads, double(n), "um/s",
                    e.what()));
  }
  return rows;
}

}  // namespace axg::bench

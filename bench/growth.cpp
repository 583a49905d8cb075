// Growth throughput at the report's constant density, 10^3 to 10^6 neurons, and the
// end-to-end times of the paper scene and of a million-neuron run (in a child process,
// so that its peak memory can be read with wait4).
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>

#include <fmt/format.h>
#include <tbb/info.h>

#include "axonguide/support/error.hpp"
#include "axonguide/support/files.hpp"
#include "axonguide/placement/placement.hpp"
#include "axonguide/support/threads.hpp"
#include "bench.hpp"

extern char** environ;

namespace axg::bench {

namespace fs = std::filesystem;

namespace {

struct GrowthRun {
  double seconds = 0;
  double axon_steps = 0;
};

GrowthRun time_steps(const Scene& scene, const Placement& p, const EngineFactory& make) {
  std::unique_ptr<Engine> engine = make ? make(scene, p) : make_reference_engine(scene, p);
  engine->warm_up();  // as a run does (cues.warmup_steps; none in the benchmark scenes)
  PhaseTimes times;
  GrowthRun r;
  double growing = static_cast<double>(scene.neurons.count);
  const auto t0 = std::chrono::steady_clock::now();
  for (std::uint32_t step = 1; step <= scene.steps && growing > 0; ++step) {
    r.axon_steps += growing;
    growing = static_cast<double>(engine->step(step, times).growing);
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace

// Runs `axonguide run SCENE --out DIR -q --threads T` as a child and reads its peak RSS.
ChildRun run_child(const Scene& scene, int threads, const std::string& backend) {
  const ScratchDir scratch("axonguide-bench");
  const fs::path& dir = scratch.path();
  const fs::path scene_file = dir / "scene.json";
  std::ofstream(scene_file) << scene_to_json(scene).dump();
  std::vector<std::string> args{"axonguide", "run", scene_file.string(), "--out", (dir / "out").string(), "-q",
                                "--threads", std::to_string(threads), "--backend", backend};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  ChildRun r;
  pid_t pid;
  const auto t0 = std::chrono::steady_clock::now();
  if (posix_spawn(&pid, "/proc/self/exe", nullptr, nullptr, argv.data(), environ) != 0) return r;
  int status = 0;
  struct rusage ru {};
  wait4(pid, &status, 0, &ru);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  // The child's own VmHWM, from its manifest (wait4's ru_maxrss would also count the
  // pages it shared with this process before exec).
  try {
    const auto m = nlohmann::json::parse(std::ifstream(dir / "out" / "manifest.json"));
    r.manifest = m;
    r.peak_bytes = m.at("peak_memory_bytes").get<double>();
    r.output_seconds = m.at("timings_seconds").at("output").get<double>();
  } catch (const std::exception&) {
    r.peak_bytes = static_cast<double>(ru.ru_maxrss) * 1024.0;
  }
  return r;
}


std::vector<Row> growth(const Options& o) {
  std::vector<Row> rows;
  auto emit = [&](Row r) {
    if (o.on_row) o.on_row(r);
    rows.push_back(std::move(r));
  };
  const int max_threads = resolve_threads(o.max_threads);
  const bool gpu = o.backend == "cuda";
  std::vector<std::uint64_t> sizes = gpu ? std::vector<std::uint64_t>{100000, 1000000, 10000000, 100000000}
                                         : std::vector<std::uint64_t>{1000, 10000, 100000, 1000000};
  if (o.quick) sizes.pop_back();
  double first_cost = 0, reference_rate = 0;
  for (std::uint64_t n : sizes) {
    Scene scene = paper_direct_scene(n);
    // Growth as a scene gets it by default: the heading's random walk every step.
    scene.axons.persistence_length = Scene{}.axons.persistence_length;
    // Beyond 10^6 neurons the sequential overlap pass of placement would dominate the
    // benchmark's own run time; the growth it measures does not depend on it.
    if (n > 1000000) scene.neurons.overlap_reject = false;
    Placement p;
    try {
      check_memory_estimate(estimate_run_bytes(scene), fmt::format("bench growth at {} neurons", n));
      p = place_neurons(scene);
    } catch (const RunError& e) {
      emit({"growth", "direct growth with wandering, constant density", "axonguide " + o.backend, max_threads, double(n), 0, 0,
            "axon-steps/s", 0, "", std::string("skipped: ") + e.what()});
      continue;
    }
    std::vector<int> thread_counts{max_threads};
    if (!gpu && max_threads > 1) thread_counts.insert(thread_counts.begin(), 1);
    for (int threads : thread_counts) {
      const int repeats = n >= 1000000 ? 3 : 5;
      std::vector<double> secs;
      GrowthRun g;
      try {
        for (int k = 0; k < repeats; ++k) {
          g = with_threads(threads, [&] { return time_steps(scene, p, o.make_engine); });
          secs.push_back(g.seconds);
        }
      } catch (const RunError& e) {
        emit(failed_row("growth", "direct growth with wandering, constant density", "axonguide " + o.backend, threads,
                        double(n), "axon-steps/s", e.what()));
        continue;
      }
      std::sort(secs.begin(), secs.end());
      const double seconds = secs[secs.size() / 2];
      const double rate = g.axon_steps / seconds;
      const double ns = 1e9 / rate * threads;
      std::string baseline, note = fmt::format("{:.0f} axon-steps, {:.1f} ns x threads per axon-step", g.axon_steps, ns);
      double ratio = 0;
      if (gpu) {
        if (n <= 1000000) {
          const GrowthRun r = with_threads(2, [&] { return time_steps(scene, p, {}); });
          reference_rate = r.axon_steps / r.seconds;
        }
        if (reference_rate > 0) {
          ratio = rate / reference_rate;
          baseline = n <= 1000000 ? "reference (2 threads), same size" : "reference (2 threads) at 10^6";
        }
      } else if (threads == max_threads) {
        if (first_cost == 0) first_cost = ns;
        ratio = ns / first_cost;
        baseline = "cost per axon-step vs 10^3 neurons";
      }
      emit({"growth", "direct growth with wandering, constant density", "axonguide " + o.backend, threads, double(n), seconds, rate,
            "axon-steps/s", ratio, baseline, note});
    }
  }
  // End to end (placement, steps, graph, every output file), as a user runs it. A run
  // that did not exit 0 has no time to report.
  {
    const Scene scene = paper_direct_scene(5000);
    const ChildRun c = run_child(scene, max_threads, o.backend);
    const std::string name = "paper-direct-5000 (report Table 4: 285.43 s)";
    if (c.status != 0)
      emit(failed_row("end-to-end", name, "axonguide " + o.backend, max_threads, 5000, "neurons/s",
                      fmt::format("axonguide run exited {}", c.status)));
    else
      emit({"end-to-end", name, "axonguide " + o.backend, max_threads, 5000, c.seconds, 5000 / c.seconds, "neurons/s",
            285.43 / c.seconds, "report Table 4", fmt::format("exit 0, peak {:.0f} MiB", c.peak_bytes / 1048576.0)});
  }
  // The large run with its default outputs (no GraphML above 10^5 neurons), then with
  // SONATA added, then with GraphML forced on: what each format costs.
  const std::uint64_t n = o.quick ? 100000 : 1000000;
  struct Variant {
    const char* name;
    bool sonata;
    std::optional<bool> graphml;
  };
  for (const Variant& v : {Variant{"default outputs", false, std::nullopt}, Variant{"+ SONATA", true, std::nullopt},
                           Variant{"+ GraphML", false, true}}) {
    Scene scene = paper_direct_scene(n);
    scene.output.sonata = v.sonata;
    scene.output.graphml = v.graphml;
    const ChildRun c = run_child(scene, max_threads, o.backend);
    const std::string name = fmt::format("{} neurons, {}", n, v.name);
    if (c.status != 0)
      emit(failed_row("end-to-end", name, "axonguide " + o.backend, max_threads, double(n), "neurons/s",
                      fmt::format("axonguide run exited {}", c.status)));
    else
      emit({"end-to-end", name, "axonguide " + o.backend, max_threads, double(n), c.seconds, n / c.seconds, "neurons/s",
            0, "",
            fmt::format("exit 0, outputs {:.2f} s, peak {:.0f} MiB = {:.0f} bytes per neuron", c.output_seconds,
                        c.peak_bytes / 1048576.0, c.peak_bytes / n)});
  }
  return rows;
}

}  // namespace axg::bench

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

#include <fmt/format.h>
#include <tbb/info.h>

#include "axonguide/error.hpp"
#include "axonguide/placement.hpp"
#include "axonguide/threads.hpp"
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
  const fs::path dir = fs::temp_directory_path() / fmt::format("axonguide-bench-{}", ::getpid());
  fs::create_directories(dir);
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
    r.peak_bytes = m.at("peak_memory_bytes").get<double>();
  } catch (const std::exception&) {
    r.peak_bytes = static_cast<double>(ru.ru_maxrss) * 1024.0;
  }
  std::error_code ec;
  fs::remove_all(dir, ec);
  return r;
}


std::vector<Row> growth(const Options& o) {
  std::vector<Row> rows;
  auto emit = [&](Row r) {
    if (o.on_row) o.on_row(r);
    rows.push_back(std::move(r));
  };
  const int max_threads = o.max_threads > 0 ? o.max_threads : static_cast<int>(tbb::info::default_concurrency());
  std::vector<std::uint64_t> sizes{1000, 10000, 100000, 1000000};
  if (o.quick) sizes.pop_back();
  double first_cost = 0;
  for (std::uint64_t n : sizes) {
    const Scene scene = paper_direct_scene(n);
    check_memory_estimate(estimate_run_bytes(scene), fmt::format("bench growth at {} neurons", n));
    const Placement p = place_neurons(scene);
    std::vector<int> thread_counts{1};
    if (max_threads > 1) thread_counts.push_back(max_threads);
    for (int threads : thread_counts) {
      GrowthRun best;
      const int repeats = n >= 1000000 ? 3 : 5;
      std::vector<double> secs;
      for (int k = 0; k < repeats; ++k) {
        GrowthRun g = with_threads(threads, [&] { return time_steps(scene, p, o.make_engine); });
        secs.push_back(g.seconds);
        best.axon_steps = g.axon_steps;
      }
      std::sort(secs.begin(), secs.end());
      best.seconds = secs[secs.size() / 2];
      const double rate = best.axon_steps / best.seconds;
      const double ns = 1e9 / rate * threads;
      if (threads == max_threads && first_cost == 0) first_cost = ns;
      emit({"growth", "direct growth, constant density", "axonguide " + o.backend, threads, double(n), best.seconds,
            rate, "axon-steps/s", threads == max_threads ? ns / first_cost : 0.0,
            threads == max_threads ? "cost per axon-step vs 10^3 neurons" : "",
            fmt::format("{:.0f} axon-steps, {:.1f} ns x threads per axon-step", best.axon_steps, ns)});
    }
  }
  // End to end (placement, steps, graph, every output file), as a user runs it.
  {
    const Scene scene = paper_direct_scene(5000);
    const ChildRun c = run_child(scene, max_threads, o.backend);
    emit({"end-to-end", "paper-direct-5000 (report Table 4: 285.43 s)", "axonguide " + o.backend, max_threads, 5000,
          c.seconds, 5000 / c.seconds, "neurons/s", 285.43 / c.seconds, "report Table 4",
          fmt::format("exit {}, peak {:.0f} MiB", c.status, c.peak_bytes / 1048576.0)});
  }
  {
    const std::uint64_t n = o.quick ? 100000 : 1000000;
    const Scene scene = paper_direct_scene(n);
    const ChildRun c = run_child(scene, max_threads, o.backend);
    emit({"end-to-end", fmt::format("{} neurons, all outputs", n), "axonguide " + o.backend, max_threads, double(n),
          c.seconds, n / c.seconds, "neurons/s", 0, "",
          fmt::format("exit {}, peak {:.0f} MiB = {:.0f} bytes per neuron", c.status, c.peak_bytes / 1048576.0,
                      c.peak_bytes / n)});
  }
  return rows;
}

}  // namespace axg::bench

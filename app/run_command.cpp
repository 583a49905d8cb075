#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <thread>

#include <fmt/format.h>

#include "axonguide/cue_setup.hpp"
#include "axonguide/error.hpp"
#include "axonguide/output.hpp"
#include "axonguide/placement.hpp"
#include "axonguide/run.hpp"
#include "axonguide/threads.hpp"
#include "axonguide/version.hpp"
#include "backend.hpp"
#include "commands.hpp"

namespace axg::app {

namespace {

std::uint64_t parse_seed(const std::string& text) {
  std::size_t used = 0;
  unsigned long long v = 0;
  try {
    if (text.empty() || text[0] == '-' || text[0] == '+') throw std::invalid_argument("sign");
    v = std::stoull(text, &used, 10);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty())
    throw InputError(fmt::format("--seed {}: must be an unsigned 64-bit integer (0 to 18446744073709551615)", text));
  return v;
}

// A progress line on stderr, only when stderr is a terminal and the run has taken more
// than a couple of seconds; rate-limited to a few updates per second.
class Progress {
 public:
  Progress() : tty_(::isatty(STDERR_FILENO) == 1), start_(clock::now()), last_(start_) {}
  ~Progress() {
    if (shown_) std::fprintf(stderr, "\r\033[K");
  }
  void update(const StepStats& s, std::uint32_t steps) {
    if (!tty_) return;
    const auto now = clock::now();
    if (now - start_ < std::chrono::seconds(2) || now - last_ < std::chrono::milliseconds(200)) return;
    last_ = now;
    shown_ = true;
    std::fprintf(stderr, "\r\033[Kstep %u/%u  growing %llu  connected %llu  exited %llu  particles %llu", s.step,
                 steps, static_cast<unsigned long long>(s.growing), static_cast<unsigned long long>(s.connected),
                 static_cast<unsigned long long>(s.exited), static_cast<unsigned long long>(s.particles));
    std::fflush(stderr);
  }

 private:
  using clock = std::chrono::steady_clock;
  bool tty_;
  bool shown_ = false;
  clock::time_point start_, last_;
};

std::string scene_line(const Scene& s) {
  std::string guidance = name_of(s.guidance.model);
  if (s.uses_cues())
    guidance += fmt::format(" ({} field, {} sources)", name_of(s.cues.field), s.source_count());
  return fmt::format("{} neurons in a {} of radius {}, {} sampler, {} guidance, {} contact, {} steps",
                     s.neurons.count, name_of(s.neurons.shape), s.neurons.radius, name_of(s.neurons.sampler),
                     guidance, name_of(s.axons.contact), s.steps);
}

void print_summary(const RunResult& r, const RunArgs& args, int threads, const std::string& origin,
                   double wall) {
  const Scene& s = r.scene;
  const StepStats& last = r.stats.back();
  const double n = static_cast<double>(r.neurons.size());
  fmt::print("axonguide {} ({}) — {} backend, {} thread{}\n", kVersion, kCommit, args.backend, threads,
             threads == 1 ? "" : "s");
  fmt::print("scene     {} (seed {})\n          {}\n", origin, s.seed, scene_line(s));
  fmt::print("units     {}{}\n", s.units.describe(), s.units.declared() ? "" : " (none declared: the report's units)");
  fmt::print("axons     step {} {}{}, {}{}\n", s.axons.step_length, s.units.length,
             s.axons.growth_speed ? fmt::format(" (growth speed {} {}/{} x dt {})", *s.axons.growth_speed, s.units.length,
                                                s.units.time, s.dt)
                                  : std::string(),
             s.axons.persistence_length
                 ? fmt::format("wandering with persistence length {} {}", *s.axons.persistence_length, s.units.length)
                 : std::string("no wandering (straight between turns)"),
             s.axons.growth_modulation > 0 ? fmt::format(", growth-rate modulation m = {}", s.axons.growth_modulation)
                                           : std::string());
  fmt::print("placement {} neurons, {} redraws, packing fraction {:.4f}\n", r.neurons.size(), r.placement_redraws,
             packing_fraction(s.neurons));
  if (s.uses_cues()) {
    std::string sources;
    for (const auto& c : make_cues(s))
      sources += fmt::format("{}{} at ({:.2f}, {:.2f}, {:.2f})", sources.empty() ? "" : ", ",
                             c.sign > 0 ? "attractant" : "repellent", c.position.x, c.position.y, c.position.z);
    fmt::print("cues      {} field, {} steering: {}\n", name_of(s.cues.field), name_of(s.guidance.model), sources);
    if (s.cues.warmup_steps > 0)
      fmt::print("          {} warm-up steps of the fields before growth\n", s.cues.warmup_steps);
    if (!r.field_note.empty()) fmt::print("          {}\n", r.field_note);
    if (s.cues.field == FieldKind::kParticles) fmt::print("          {} particles at the end\n", last.particles);
  }
  fmt::print("growth    {} of {} steps{}\n", r.steps_run, s.steps,
             r.steps_run < s.steps ? " (stopped early: no axon left growing)" : "");
  fmt::print("          connected {} ({:.1f}%), exited {} ({:.1f}%), max_steps {}\n", last.connected,
             100.0 * static_cast<double>(last.connected) / n, last.exited,
             100.0 * static_cast<double>(last.exited) / n, last.growing);
  std::string graph = fmt::format("{} edges", r.graph.out.edges());
  if (r.graph.component_count)
    graph += fmt::format(", {} components (largest {})", r.graph.component_count, r.graph.largest_component);
  if (r.graph.bfs)
    graph += fmt::format(", BFS from {} source{} reached {} (max level {})", s.analysis.bfs_sources.size(),
                         s.analysis.bfs_sources.size() == 1 ? "" : "s", r.graph.bfs->reached, r.graph.bfs->max_level);
  fmt::print("graph     {}\n", graph);
  double steps_time = 0, grow_time = 0;
  for (const auto& row : r.times.rows())
    if (row.step > 0) {
      steps_time += row.seconds;
      if (row.phase == "grow" || row.phase == "compact") grow_time += row.seconds;
    }
  const double axon_steps = [&] {
    double a = 0;
    for (std::size_t k = 0; k + 1 < r.stats.size(); ++k) a += static_cast<double>(r.stats[k].growing);
    return a;
  }();
  fmt::print("time      {:.3f} s total: placement {:.3f}, steps {:.3f} (growth {:.3g} axon-steps/s{}), graph {:.3f}\n",
             wall, r.times.total("placement"), steps_time, grow_time > 0 ? axon_steps / grow_time : 0.0,
             s.uses_cues() ? fmt::format("; cue fields and steering {:.3f} s", steps_time - grow_time) : "",
             r.times.total("graph"));
}

}  // namespace

int cmd_run(const RunArgs& args) {
  const auto t0 = std::chrono::steady_clock::now();
  ParseResult parsed;
  std::string origin;
  if (args.scene_path.empty()) {
    parsed.scene = Scene::builtin_default();
    origin = "built-in default";
  } else {
    parsed = load_scene_file(args.scene_path);
    origin = args.scene_path;
  }
  Scene scene = parsed.scene;
  if (!args.seed.empty()) scene.seed = parse_seed(args.seed);
  if (args.vtk) {
    scene.output.vtk = true;
    resolve_output_dependencies(scene, parsed.warnings);
  }
  for (const auto& w : parsed.warnings) std::fprintf(stderr, "axonguide: warning: %s\n", w.c_str());

  RunOptions options;
  options.make_engine = engine_factory(args.backend);
  const int threads = resolve_threads(args.threads);
  prepare_output_dir(args.out_dir);

  Progress progress;
  options.on_step = [&](const StepStats& s, std::uint32_t steps) { progress.update(s, steps); };
  RunResult result = with_threads(threads, [&] {
    RunResult r = run_scene(scene, options);
    write_outputs(r, args.out_dir, args.backend, threads, parsed.warnings);
    return r;
  });
  for (const ParticleFrame& fr : result.frames)
    if (fr.stride > 1)
      std::fprintf(stderr,
                   "axonguide: note: the particle frame at step %u has %llu particles; every %uth (by id) is kept in "
                   "particles.csv and the VTK frames\n",
                   fr.step, static_cast<unsigned long long>(fr.count), fr.stride);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!args.quiet) {
    print_summary(result, args, threads, origin, wall);
    fmt::print("outputs   {}/ (manifest.json lists every file with its SHA-256)\n", args.out_dir);
  }
  return kExitOk;
}

int cmd_scene_default() {
  fmt::print("{}\n", scene_to_json(Scene::builtin_default()).dump(2));
  return kExitOk;
}

int cmd_scene_check(const std::string& path) {
  ParseResult parsed = load_scene_file(path);
  for (const auto& w : parsed.warnings) std::fprintf(stderr, "axonguide: warning: %s\n", w.c_str());
  fmt::print("{}\n", scene_to_json(parsed.scene).dump(2));
  return kExitOk;
}

}  // namespace axg::app

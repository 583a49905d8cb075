#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <csignal>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <thread>

#include <fmt/format.h>

#include "axonguide/engine/checkpoint.hpp"
#include "axonguide/model/cues.hpp"
#include "axonguide/distributed/decomposed_run.hpp"
#include "axonguide/distributed/launch.hpp"
#include "axonguide/distributed/mpi_comm.hpp"
#include "axonguide/support/error.hpp"
#include "axonguide/scene/json_input.hpp"
#include "axonguide/support/files.hpp"
#include "axonguide/placement/placement.hpp"
#include "axonguide/engine/run.hpp"
#include "axonguide/io/run_folder.hpp"
#include "axonguide/support/threads.hpp"
#include "axonguide/version.hpp"
#include "backend.hpp"
#include "commands.hpp"

namespace axg::app {

namespace fs = std::filesystem;
using nlohmann::json;

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
  fmt::print("axonguide {} ({}) — {} backend, {} thread{}{}\n", kVersion, kCommit, args.backend, threads,
             threads == 1 ? "" : "s",
             r.decomposition.is_null() ? std::string()
                                       : r.decomposition["ranks"].get<int>() == 1
                                             ? std::string(" on 1 rank")
                                             : fmt::format(" on each of {} ranks", r.decomposition["ranks"].get<int>()));
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
  if (s.arbours)  // an arbour run's counts are growth cones (stats.csv), not neurons
    fmt::print("          growth cones stopped at a soma {}, left the bounds {}; {} neurons still growing\n",
               last.connected, last.exited, last.growing);
  else
    fmt::print("          connected {} ({:.1f}%), exited {} ({:.1f}%), max_steps {}\n", last.connected,
               100.0 * static_cast<double>(last.connected) / n, last.exited,
               100.0 * static_cast<double>(last.exited) / n, last.growing);
  std::string graph = fmt::format("{} edges", r.graph.out.edges());
  if (r.graph.component_count)
    graph += fmt::format(", {} components (largest {})", r.graph.component_count, r.graph.largest_component);
  if (r.graph.bfs)
    graph += fmt::format(", BFS from {} source{} reached {} (max level {})", s.analysis.bfs_sources.size(),
                         s.analysis.bfs_sources.size() == 1 ? "" : "s", r.graph.bfs->reached, r.graph.bfs->max_level);
  if (s.synapses) {
    std::size_t realised = 0;
    for (const std::uint8_t x : r.synapses.realised) realised += x;
    const double t = r.times.total("synapses");
    fmt::print("synapses  {} contacts in {} appositions (d = {:.4g} um), {} realised on {} connections; detection "
               "{:.3f} s ({:.3g} contacts/s)\n",
               r.contacts, r.synapses.size(), s.synapses->distance, realised, r.synapse_connections.size(), t,
               t > 0 ? static_cast<double>(r.contacts) / t : 0.0);
  }
  fmt::print("graph     {}\n", graph);
  const json& d = r.decomposition;
  if (!d.is_null())
    fmt::print("ranks     {} ({} x {} x {} blocks, halo {:.4g} LU; {} to {} somas a rank): placement {} rounds; per step "
               "{:.1f} axons migrate in {:.1f} messages ({:.0f} bytes) and {:.0f} collectives a rank\n",
               d["ranks"].get<int>(), d["blocks"][0].get<int>(), d["blocks"][1].get<int>(), d["blocks"][2].get<int>(),
               d["halo_lu"].get<double>(), d["somas_per_rank"]["min"].get<std::uint64_t>(),
               d["somas_per_rank"]["max"].get<std::uint64_t>(), d["placement"]["rounds"].get<std::uint64_t>(),
               d["per_step"]["migrated_axons"].get<double>(), d["per_step"]["messages"].get<double>(),
               d["per_step"]["message_bytes"].get<double>(), d["per_step"]["collectives_per_rank"].get<double>());
  if (!d.is_null() && s.uses_cues() && s.cues.field == FieldKind::kParticles)
    fmt::print("          per step {:.0f} particles migrate and {:.0f} are received into halos\n",
               d["per_step"]["migrated_particles"].get<double>(), d["per_step"]["halo_particles"].get<double>());
  if (!d.is_null() && s.uses_cues() && s.cues.field == FieldKind::kGrid)
    fmt::print("          per step {:.0f} grid values are received into ghost planes; the implicit sweeps' "
               "pipeline takes {:.0f} exchanges\n",
               d["per_step"]["ghost_values"].get<double>(), d["per_step"]["pipeline_stages"].get<double>());
  double steps_time = 0, grow_time = 0;
  for (const auto& row : r.times.rows())
    if (row.step > 0) {
      steps_time += row.seconds;
      if (row.phase == "grow" || row.phase == "compact" || row.phase == "migrate") grow_time += row.seconds;
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

// SIGINT and SIGTERM set a flag; the run stops at the end of the current step. The handler
// may run on any thread (a TBB worker, a file's writer thread) while the main thread reads
// the flag: a lock-free atomic, which a signal handler may use, not a volatile.
std::atomic<int> g_signal{0};
static_assert(std::atomic<int>::is_always_lock_free);

// Ranks other than 0 of a decomposed run stop as quietly as they run.
std::atomic<int> g_quiet{0};

extern "C" void on_stop_signal(int sig) {
  if (g_signal == 0 && g_quiet == 0) {
    static const char msg[] = "\naxonguide: stopping at the end of the current step (checkpoint, then exit)\n";
    [[maybe_unused]] const ssize_t w = ::write(STDERR_FILENO, msg, sizeof msg - 1);
  }
  g_signal = sig;
}

class StopSignals {
 public:
  StopSignals() {
    g_signal = 0;
    struct sigaction sa {};
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    ::sigaction(SIGINT, &sa, &old_int_);
    ::sigaction(SIGTERM, &sa, &old_term_);
  }
  ~StopSignals() {
    ::sigaction(SIGINT, &old_int_, nullptr);
    ::sigaction(SIGTERM, &old_term_, nullptr);
  }
  static int received() { return g_signal; }
  static int exit_code() { return 128 + g_signal; }  // 130 for SIGINT, 143 for SIGTERM
  static const char* name() { return name_of(g_signal); }
  static const char* name_of(int sig) { return sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "a signal"; }

 private:
  struct sigaction old_int_ {}, old_term_ {};
};

struct Job {
  Scene scene;
  std::vector<std::string> warnings;
  std::string origin;
  std::optional<RunCheckpoint> checkpoint;
  json manifest;  // a resume's: the unfinished run's manifest
};

// `run --resume DIR`: the scene, warnings and checkpoint of the unfinished run in DIR.
Job resume_job(const RunArgs& args, const fs::path& dir) {
  Job job;
  job.manifest = read_manifest(dir);
  const json& m = job.manifest;
  const std::string status = m.value("status", std::string("complete"));
  job.origin = fmt::format("resumed from {}", dir.string());
  const json& by = m.contains("axonguide") ? m["axonguide"] : json::object();
  if (by.value("version", std::string()) != kVersion || by.value("commit", std::string()) != kCommit)
    throw InputError(fmt::format("--resume {}: the run was started by axonguide {} ({}); this is {} ({}); a resume "
                                 "must use the same build, or give --force to start over",
                                 dir.string(), by.value("version", std::string("?")), by.value("commit", std::string("?")),
                                 kVersion, kCommit));
  if (!m.contains("scene")) throw InputError(fmt::format("--resume {}: the manifest holds no scene", dir.string()));
  ParseResult parsed = parse_scene(m["scene"].dump(), (dir / kManifestName).string());
  job.scene = parsed.scene;
  if (m.contains("warnings") && m["warnings"].is_array())
    for (const auto& w : m["warnings"])
      if (w.is_string()) job.warnings.push_back(w.get<std::string>());
  if (!args.scene_path.empty()) {
    Scene given = load_scene_file(args.scene_path).scene;
    if (scene_hash(given) != scene_hash(job.scene))
      throw InputError(fmt::format("--resume {}: {} is not the scene of this run (its canonical form differs); "
                                   "resume without a scene, or start a new run",
                                   dir.string(), args.scene_path));
  }
  if (status == "complete") return job;  // the caller verifies and reports it
  if (status != "running" && status != "interrupted")
    throw InputError(fmt::format("--resume {}: manifest status \"{}\" is not a run's", dir.string(), printable(status)));
  // An interrupted run's manifest records the checkpoint it stopped with: that file, and
  // no other (a killed run's manifest records none; it resumes from what it finds).
  std::string recorded;
  if (status == "interrupted" && m.contains("checkpoint") && m["checkpoint"].is_object() &&
      m["checkpoint"].contains("sha256") && m["checkpoint"]["sha256"].is_string())
    recorded = m["checkpoint"]["sha256"].get<std::string>();
  const fs::path path = dir / kCheckpointName;
  std::error_code ec;
  if (!fs::exists(path, ec)) {
    if (!recorded.empty())
      throw InputError(fmt::format("--resume {}: the run stopped with a checkpoint (after step {}), but {} is missing; "
                                   "put it back, or start over with `axonguide run SCENE --out {} --force`",
                                   dir.string(), m["checkpoint"].value("step", json(0)).dump(), path.string(),
                                   dir.string()));
    return job;
  }
  RunCheckpoint c = read_checkpoint(path);  // damaged: exit 3
  if (c.version != kVersion || c.commit != kCommit)
    throw InputError(fmt::format("--resume {}: the checkpoint was written by axonguide {} ({}); this is {} ({})",
                                 dir.string(), c.version, c.commit, kVersion, kCommit));
  if (c.scene_hash != scene_hash(job.scene))
    throw InputError(fmt::format("--resume {}: the checkpoint was written for another scene than the manifest's",
                                 dir.string()));
  if (!recorded.empty()) {
    const std::string got = sha256_file(path);
    if (got != recorded)
      throw InputError(fmt::format("--resume {}: {} is whole, but not the checkpoint this run stopped with (its SHA-256 "
                                   "is {}…, the manifest records {}…); put that one back, or start over with --force",
                                   dir.string(), path.string(), got.substr(0, 16), recorded.substr(0, 16)));
  }
  job.checkpoint = std::move(c);
  return job;
}

// The ranks of a run decomposed over mpirun's ranks (docs/scaling.md): rank 0 does all that
// a one-process run does (the folder, checkpoints, outputs, messages); every rank places,
// steps and gathers with it, and all end with one exit code. Errors that every rank meets
// alike (bad input, a decomposition that cannot proceed, placement too dense) end them
// together, with rank 0's message; an error one rank meets alone ends the job (MPI_Abort),
// since the others would wait for it in a collective forever.
struct Ranks {
  distributed::Comm& comm;
  std::unique_ptr<distributed::DecomposedRun> run;
  std::string pml;  // Open MPI's messaging layer, as the session chose it (the run facts)
  bool root() const { return comm.root(); }
  std::uint64_t most(std::uint64_t v) {
    std::vector<std::uint64_t> x{v};
    comm.allreduce(x, distributed::Reduce::kMax);
    return x[0];
  }
};

// A rank other than 0 ends with the run's exit code and says nothing: rank 0 speaks.
struct QuietExit {
  int code;
};

int exit_code_of(const std::exception_ptr& e) {
  try {
    std::rethrow_exception(e);
  } catch (const InputError&) {
    return kExitBadInput;
  } catch (...) {
    return kExitCannotRun;
  }
}

// Runs fn on every rank (one process: just runs it); when it failed on any, every rank
// stops: rank 0 with its error, the others quietly.
template <class Fn>
void together(Ranks* ranks, Fn&& fn) {
  if (!ranks) return fn();
  std::exception_ptr error;
  try {
    fn();
  } catch (...) {
    error = std::current_exception();
  }
  const int code = static_cast<int>(ranks->most(error ? static_cast<std::uint64_t>(exit_code_of(error)) : 0));
  if (code == kExitOk) return;
  if (!ranks->root()) throw QuietExit{code};
  // Rank 0 says why (its own error, or that another rank had one), and every rank ends
  // with the same code: the worst any rank met.
  if (!error) {
    const std::string what =
        fmt::format("another rank could not start the run (exit {}); every rank must see the same files", code);
    error = code == kExitBadInput ? std::make_exception_ptr(InputError(what)) : std::make_exception_ptr(RunError(what));
  }
  if (exit_code_of(error) == code) std::rethrow_exception(error);
  report_error(error);
  std::fprintf(stderr, "axonguide: error: another rank could not start the run either (exit %d)\n", code);
  throw QuietExit{code};
}

// fn on rank 0 alone (the folder); the others wait for its outcome.
template <class Fn>
void on_root(Ranks* ranks, Fn&& fn) {
  together(ranks, [&] {
    if (!ranks || ranks->root()) fn();
  });
}

Job fresh_job(const RunArgs& args) {
  Job job;
  ParseResult parsed;
  if (args.scene_path.empty()) {
    parsed.scene = Scene::builtin_default();
    job.origin = "built-in default";
  } else {
    parsed = load_scene_file(args.scene_path);
    job.origin = args.scene_path;
  }
  job.scene = parsed.scene;
  job.warnings = parsed.warnings;
  if (args.seed_given) job.scene.seed = parse_seed(args.seed);
  if (args.vtk) {
    job.scene.output.vtk = true;
    resolve_output_dependencies(job.scene, job.warnings);
  }
  return job;
}

// The memory a run needs where it runs: the whole run in one process; under mpirun, on
// each node, rank 0's whole result (assumed on this node) and the node's ranks' shares, at
// twice the one-process bytes a neuron (the decomposed engine's records and halo).
void check_run_memory(const Scene& scene, Ranks* ranks) {
  const double whole = static_cast<double>(estimate_run_bytes(scene));
  const int on_node = distributed::detect_launch().local_size;
  const double need = ranks ? whole + 2.0 * whole * on_node / ranks->comm.size() : whole;
  check_memory_estimate(need >= 1.8e19 ? UINT64_MAX : static_cast<std::uint64_t>(need),
                        fmt::format("a run of {} neurons{}", scene.neurons.count,
                                    ranks ? fmt::format(" ({} of {} ranks on this node)", on_node, ranks->comm.size())
                                          : std::string()));
}

// A checkpoint's step and scene in 64 bits, for the ranks to compare.
std::uint64_t checkpoint_digest(const RunCheckpoint& c) {
  return (std::hash<std::string>{}(c.scene_hash) ^ (static_cast<std::uint64_t>(c.step) * 0x9E3779B97F4A7C15ull)) | 1u;
}

int run_job(const RunArgs& args, Ranks* ranks, int threads) {
  const auto t0 = std::chrono::steady_clock::now();
  const bool root = !ranks || ranks->root();
  const bool resuming = !args.resume.empty();
  const fs::path dir = resuming ? fs::path(args.resume) : fs::path(args.out_dir);
  Job job;
  RunOptions options;
  // Everything that can refuse the run does so before the folder is created or touched.
  together(ranks, [&] {
    if (resuming) {
      if (args.out_given && fs::path(args.out_dir) != dir)
        throw InputError("--resume DIR writes into DIR: give no --out (or the same folder)");
      if (args.seed_given) throw InputError("--seed with --resume: the seed is the one the run started with");
      if (args.force) throw InputError("--force with --resume: give one (--force starts over, --resume continues)");
      if (args.vtk) throw InputError("--vtk with --resume: the outputs are the ones the run started with");
      if (!fs::is_directory(dir)) throw InputError(fmt::format("--resume {}: not a directory", dir.string()));
    } else {
      job = fresh_job(args);
    }
    require_backend(args.backend);
    if (ranks && args.backend != "reference")
      throw RunError(fmt::format(
          "--backend {} under mpirun: a decomposed run steps each rank's block on the reference engine; one block per "
          "GPU is designed (docs/scaling.md §2.6) but not built",
          args.backend));
    options.make_engine = engine_factory(args.backend);
    if (!resuming) {
      check_run_memory(job.scene, ranks);
      check_scene_runs(job.scene);  // grids, count, packing: before --force removes anything
      if (ranks) ranks->run = std::make_unique<distributed::DecomposedRun>(job.scene, ranks->comm);
    }
  });
  // A fresh run that fails before it has anything to resume (placement too dense, out of
  // memory) takes its running manifest back, and the folder when it made it.
  struct RemoveIfEmpty {
    fs::path dir;
    bool armed = false;
    ~RemoveIfEmpty() {
      std::error_code ec;
      if (armed && fs::is_empty(dir, ec)) fs::remove(dir, ec);
    }
  } cleanup{dir, false};
  const bool made_dir = root && !fs::exists(dir);
  std::optional<FolderLock> lock;
  json running;
  bool mark_running = false;  // a resume: write `running` after its first step
  bool already_complete = false;
  on_root(ranks, [&] {
    prepare_output_dir(dir);
    lock.emplace(dir);
    FolderClaim claim;
    if (resuming) {
      job = resume_job(args, dir);
      const FolderCheck check = verify_run_folder(dir);
      if (check.status == "complete") {
        if (!check.whole)
          throw InputError(fmt::format("--resume {}: holds a complete run that does not verify (see `axonguide "
                                       "verify {}`); give --force to replace it",
                                       dir.string(), dir.string()));
        discard_replaced_run(dir);  // left by a run killed once it was whole
        already_complete = true;
        return;
      }
      if (ranks) ranks->run = std::make_unique<distributed::DecomposedRun>(job.scene, ranks->comm);
      if (!job.checkpoint && !args.quiet)
        std::fprintf(stderr, "axonguide: note: %s has no checkpoint yet; the run starts again from step 0\n",
                     dir.c_str());
    } else {
      claim = claim_run_folder(dir, args.force);
      refuse_foreign_in_the_way(dir, claim, job.scene);
    }
    for (const auto& name : claim.foreign)
      if (is_run_output(name) || name == "view.html" || name.rfind("assay", 0) == 0 || name.rfind("plot", 0) == 0)
        std::fprintf(stderr, "axonguide: warning: %s/%s is not this run's (its manifest will not list it)\n",
                     dir.c_str(), name.c_str());
    for (const auto& w : job.warnings) std::fprintf(stderr, "axonguide: warning: %s\n", w.c_str());
    if (resuming) {
      // What the killed run was replacing, if it was killed before it had moved or removed
      // it all: into .replaced/ when it keeps the complete run it replaces.
      running = job.manifest;
      std::vector<std::string> left;
      if (running.contains("replacing") && running["replacing"].is_array())
        for (const auto& name : running["replacing"])
          if (name.is_string() && name.get<std::string>() != kCheckpointName) left.push_back(name.get<std::string>());
      if (!left.empty()) {
        if (keeps_replaced_run(running)) keep_replaced_files(dir, left);
        else remove_run_files(dir, left);
        sync_filesystem(dir);  // the moves, before the manifest stops naming the files
        running["replacing"] = json::array();
        write_manifest(dir, running);
      }
      remove_stale_temporaries(dir);  // a killed writer's
      // Running again, once the first step after the checkpoint is done (so that a resume
      // refused on the way, a checkpoint that does not fit say, leaves the folder as it
      // was): an interrupted run's manifest would go on naming a checkpoint that the next
      // one replaces, and `verify` would call a running folder stopped.
      mark_running = running.value("status", std::string()) != "running";
      running["status"] = "running";
      running.erase("interrupted");
      running.erase("checkpoint");
    } else {
      // The running manifest first: from here on a kill leaves a folder whose manifest
      // names every file in it (shared with the Python module's Result.write).
      running = start_fresh_run(dir, claim, job.scene, args.backend, threads, job.warnings);
    }
  });
  if (ranks && ranks->most(already_complete ? 1 : 0)) already_complete = true;
  if (already_complete) {
    if (root && !args.quiet) fmt::print("{} already holds a complete run that verifies; nothing to resume\n", dir.string());
    return kExitOk;
  }
  // The other ranks of a resumed run read its scene and checkpoint once rank 0 has
  // checked the folder.
  if (ranks && resuming) {
    together(ranks, [&] {
      if (!ranks->root()) {
        job = resume_job(args, dir);
        ranks->run = std::make_unique<distributed::DecomposedRun>(job.scene, ranks->comm);
      }
      check_run_memory(job.scene, ranks);
    });
    // Every rank must resume the same checkpoint (a shared file system): else they would
    // not even make the same collective calls.
    const std::uint64_t seen = job.checkpoint ? checkpoint_digest(*job.checkpoint) : 0;
    together(ranks, [&] {
      if (ranks->most(seen) != seen || ~ranks->most(~seen) != seen)
        throw RunError(fmt::format("--resume {}: the ranks read different checkpoints (or some none); a run over "
                                   "ranks resumes from a folder every rank sees alike (a shared file system)",
                                   dir.string()));
    });
  }
  const Scene& scene = job.scene;

  g_quiet = root ? 0 : 1;
  StopSignals signals;
  Progress progress;
  if (root)
    options.on_step = [&](const StepStats& s, std::uint32_t steps) {
      if (mark_running) {
        write_manifest(dir, running);
        mark_running = false;
      }
      progress.update(s, steps);
    };
  options.resume = job.checkpoint ? &*job.checkpoint : nullptr;
  options.on_checkpoint = [&](const RunResult& r, std::uint32_t step, const EngineState& e) {
    if (root) write_checkpoint(dir, r, step, e);  // the others took part in gathering it
  };
  options.stop_requested = [] { return StopSignals::received() != 0; };
  if (ranks) ranks->run->attach(options);
  RunResult result;
  int code = kExitOk;
  bool writing = false;  // rank 0 writes the outputs after the last collective work
  try {
    result = with_threads(threads, [&] {
      RunResult r = run_scene(scene, options);
      if (ranks) r.decomposition = ranks->run->facts(), r.decomposition["mpi_pml"] = ranks->pml;
      writing = true;
      if (root) write_outputs(r, dir, args.backend, threads, job.warnings);
      return r;
    });
  } catch (const Interrupted& stop) {
    // Every rank stopped after this step, for a signal that reached one of them or more.
    const int sig = ranks ? static_cast<int>(ranks->most(static_cast<std::uint64_t>(StopSignals::received())))
                          : StopSignals::received();
    const char* name = StopSignals::name_of(sig);
    if (root) {
      json m = running;
      m["status"] = "interrupted";
      m["interrupted"] = {{"signal", name}, {"after_step", stop.step}};
      m["checkpoint"] = {{"file", kCheckpointName}, {"step", stop.step}, {"sha256", sha256_file(dir / kCheckpointName)}};
      write_manifest(dir, m);
      std::fprintf(stderr,
                   "axonguide: interrupted by %s after step %u of %u; the checkpoint is in %s/%s. Continue with: "
                   "%saxonguide run --resume %s\n",
                   name, stop.step, scene.steps, dir.c_str(), kCheckpointName, ranks ? "mpirun ... " : "",
                   dir.c_str());
    }
    return 128 + sig;  // 130 for SIGINT, 143 for SIGTERM
  } catch (...) {
    std::exception_ptr error = std::current_exception();
    bool every_rank = !ranks || writing;  // the others wait only for rank 0's exit code
    if (ranks) {
      try {
        std::rethrow_exception(error);
      } catch (const distributed::OnEveryRank& e) {
        error = e.error;
        every_rank = true;
      } catch (...) {
      }
    }
    if (!every_rank) {
      // Met by this rank alone, perhaps in the middle of collective work: end the job.
      std::fprintf(stderr, "axonguide: rank %d of %d: ", ranks->comm.rank(), ranks->comm.size());
      distributed::abort_job(report_error(error));
    }
    if (root) {
      std::error_code ec;
      // A run with nothing to resume is taken back, and the run it replaced put back: a
      // fresh one, or a resumed replacement that had not reached its first checkpoint.
      if (!fs::exists(dir / kCheckpointName, ec) && (!resuming || keeps_replaced_run(running))) {
        abandon_fresh_run(dir, scene);
        cleanup.armed = made_dir;
      } else if (fs::exists(dir / kReplacedName / kManifestName, ec)) {
        std::fprintf(stderr, "axonguide: note: the run this one replaces is kept in %s/%s until this one completes\n",
                     dir.c_str(), kReplacedName);
      }
      if (!ranks) std::rethrow_exception(error);
      code = report_error(error);
    }
    throw QuietExit{ranks ? static_cast<int>(ranks->most(static_cast<std::uint64_t>(code))) : code};
  }
  if (ranks && !root) return static_cast<int>(ranks->most(0));  // rank 0's code, once it has written the outputs
  if (StopSignals::received()) code = StopSignals::exit_code();  // after the last step: the outputs are whole
  if (ranks) ranks->most(static_cast<std::uint64_t>(code));     // the other ranks end with this code
  std::error_code ec;
  fs::remove(dir / kCheckpointName, ec);  // the run is whole: the checkpoint is not needed
  discard_replaced_run(dir);              // and the run it replaced is given up
  for (const ParticleFrame& fr : result.frames)
    if (fr.stride > 1)
      std::fprintf(stderr,
                   "axonguide: note: the particle frame at step %u has %llu particles; every %uth (by id) is kept in "
                   "particles.csv and the VTK frames\n",
                   fr.step, static_cast<unsigned long long>(fr.count), fr.stride);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!args.quiet) {
    print_summary(result, args, threads, job.checkpoint ? fmt::format("{} (checkpoint at step {})", job.origin,
                                                                       job.checkpoint->step)
                                                         : job.origin,
                  wall);
    fmt::print("outputs   {}/ (manifest.json lists every file with its SHA-256)\n", dir.string());
  }
  if (StopSignals::received())
    std::fprintf(stderr, "axonguide: %s arrived after the last step; the outputs were finished first, and %s is a "
                         "whole run\n", StopSignals::name(), dir.c_str());
  return code;
}

}  // namespace

int cmd_run(const RunArgs& args) {
  const distributed::Launch launch = distributed::detect_launch();
  if (!launch.launched) return run_job(args, nullptr, resolve_threads(args.threads));
  // Started by mpirun: one network over its ranks, each with its share of the node's cores.
#ifdef AXG_HAVE_MPI
  const int threads =
      args.threads > 0 ? args.threads : std::max(1, resolve_threads(0) / std::max(1, launch.local_size));
  distributed::MpiSession session;
  const std::unique_ptr<distributed::Comm> comm = distributed::make_mpi_comm();
  if (comm->size() == 1 && launch.size > 1) {
    // Another MPI's launcher (its variables say K ranks; this library sees itself alone):
    // K copies would each run the whole network into the same folder. (A launcher that
    // does not say its size, such as srun with PMIx, is taken at MPI's word.)
    if (launch.rank == 0)
      std::fprintf(stderr,
                   "axonguide: error: the launcher started %d ranks, but this build's MPI (%s) sees %d: the job's "
                   "launcher is not this MPI's; start it with the mpirun (or srun) of %s, or run without a "
                   "launcher\n",
                   launch.size, distributed::mpi_library().c_str(), comm->size(), distributed::mpi_library().c_str());
    return kExitCannotRun;
  }
  Ranks ranks{*comm, nullptr, session.pml};
  try {
    session.exit_code = run_job(args, &ranks, threads);
  } catch (const QuietExit& e) {
    session.exit_code = e.code;
  } catch (...) {
    // Rank 0's error before the ranks began working together: every rank agreed to stop.
    session.exit_code = report_error(std::current_exception());
  }
  return session.exit_code;
#else
  // K copies of a build without MPI: rank 0 runs the network alone, the others must not
  // touch its folder.
  if (launch.rank != 0) return kExitOk;
  if (launch.size > 1)
    std::fprintf(stderr,
                 "axonguide: note: started as rank 0 of %d by mpirun, but this build has no MPI (install "
                 "libopenmpi-dev and rebuild): the run goes on in this one process; ranks 1-%d exit\n",
                 launch.size, launch.size - 1);
  return run_job(args, nullptr, resolve_threads(args.threads));
#endif
}

int cmd_verify(const std::string& dir) {
  const FolderCheck c = verify_run_folder(dir);
  for (const auto& n : c.notes) fmt::print("note: {}\n", n);
  if (c.whole) {
    const std::size_t files = c.manifest["files"].size();
    fmt::print("{}: a whole run: status complete, {} file{} with the SHA-256 their manifest lists\n", dir, files,
               files == 1 ? "" : "s");
    return kExitOk;
  }
  fmt::print("{}: not a whole run:\n", dir);
  for (const auto& p : c.problems) fmt::print("  - {}\n", p);
  return kExitCheckFailed;
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

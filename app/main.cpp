// axonguide: axon growth and guidance through diffusing cues, deterministic on any
// thread count and on both backends. See README.md and docs/methods.md.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cstdio>
#include <exception>
#include <new>

#include "axonguide/error.hpp"
#include "axonguide/version.hpp"
#include "commands.hpp"

namespace {

int dispatch(int argc, char** argv) {
  using namespace axg::app;
  CLI::App app{"axonguide: deterministic simulation of axon growth and guidance through diffusing cues"};
  app.require_subcommand(1);
  app.set_version_flag("--version", fmt::format("axonguide {} ({})", axg::kVersion, axg::kCommit));

  RunArgs run;
  auto* run_cmd = app.add_subcommand("run", "Run a scene (the built-in default when SCENE is omitted)");
  run_cmd->add_option("scene", run.scene_path, "Scene JSON file");
  run_cmd->add_option("--out", run.out_dir, "Output directory")->capture_default_str();
  run_cmd->add_option("--threads", run.threads, "Worker threads (0: all cores)")
      ->check(CLI::Range(0, 4096));
  run_cmd->add_option("--backend", run.backend, "reference or cuda")
      ->check(CLI::IsMember({"reference", "cuda"}))->capture_default_str();
  run_cmd->add_option("--seed", run.seed, "Override the scene's seed (unsigned 64-bit)");
  run_cmd->add_flag("--quiet,-q", run.quiet, "No summary on stdout");

  auto* scene_cmd = app.add_subcommand("scene", "Scene utilities");
  scene_cmd->require_subcommand(1);
  auto* scene_default = scene_cmd->add_subcommand("default", "Print the built-in scene");
  std::string check_path;
  auto* scene_check = scene_cmd->add_subcommand("check", "Validate a scene and print its canonical form");
  scene_check->add_option("scene", check_path, "Scene JSON file")->required();

  BenchArgs bench;
  auto* bench_cmd = app.add_subcommand("bench", "Benchmarks, with installed peers measured in the same run");
  bench_cmd->add_option("what", bench.what, "samplers|growth|particles|grid|bfs|all")
      ->check(CLI::IsMember({"samplers", "growth", "particles", "grid", "bfs", "all"}))
      ->capture_default_str();
  bench_cmd->add_option("--backend", bench.backend, "reference or cuda")
      ->check(CLI::IsMember({"reference", "cuda"}))->capture_default_str();
  bench_cmd->add_flag("--json", bench.json, "Machine-readable output");
  bench_cmd->add_flag("--quick", bench.quick, "Smaller sizes (for CI)");
  bench_cmd->add_option("--threads", bench.threads, "Largest thread count to measure (0: all cores)")
      ->check(CLI::Range(0, 4096));

  if (argc > 1 && argv[1][0] != '-') {
    std::string names;
    bool known = false;
    for (const auto* sub : app.get_subcommands({})) {
      names += (names.empty() ? "" : ", ") + sub->get_name();
      known = known || sub->get_name() == argv[1];
    }
    if (!known) {
      std::fprintf(stderr, "axonguide: unknown command '%s' (commands: %s; see --help)\n", argv[1], names.c_str());
      return axg::kExitBadInput;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return axg::kExitBadInput;
  }

  if (run_cmd->parsed()) return cmd_run(run);
  if (scene_default->parsed()) return cmd_scene_default();
  if (scene_check->parsed()) return cmd_scene_check(check_path);
  if (bench_cmd->parsed()) return cmd_bench(bench);
  return axg::kExitBadInput;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return dispatch(argc, argv);
  } catch (const axg::InputError& e) {
    std::fprintf(stderr, "axonguide: error: %s\n", e.what());
    return axg::kExitBadInput;
  } catch (const axg::RunError& e) {
    std::fprintf(stderr, "axonguide: cannot run: %s\n", e.what());
    return axg::kExitCannotRun;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "axonguide: cannot run: out of memory\n");
    return axg::kExitCannotRun;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "axonguide: cannot run: %s\n", e.what());
    return axg::kExitCannotRun;
  }
}

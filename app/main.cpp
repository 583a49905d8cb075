// axonguide: axon growth and guidance through diffusing cues, deterministic on any
// thread count and on both backends. See README.md and docs/methods.md.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cmath>
#include <csignal>
#include <cstdio>
#include <exception>
#include <new>
#include <optional>
#include <string>

#include "axonguide/io/csv.hpp"
#include "axonguide/support/error.hpp"
#include "axonguide/support/resources.hpp"
#include "axonguide/version.hpp"
#include "commands.hpp"

namespace {

int dispatch(int argc, char** argv) {
  using namespace axg::app;
  // CLI11's number checks compare, and every comparison with NaN is false: NaN would pass
  // them all. A real-valued option is a finite number first.
  const CLI::Validator finite(
      [](std::string& text) {
        const std::optional<double> v = axg::parse_number(text);
        return v && std::isfinite(*v) ? std::string() : std::string("must be a finite number");
      },
      "FINITE");
  CLI::App app{"axonguide: deterministic simulation of axon growth and guidance through diffusing cues"};
  app.require_subcommand(1);
  // The data folder is where the bundled scenes and golden networks are read from: the
  // installed share/axonguide, or the source tree (axonguide/support/resources.hpp).
  app.set_version_flag("--version", fmt::format("axonguide {} ({})\ndata: {}", axg::kVersion, axg::kCommit,
                                                axg::data_dir().string()));

  RunArgs run;
  auto* run_cmd = app.add_subcommand("run", "Run a scene (the built-in default when SCENE is omitted)");
  run_cmd->add_option("scene", run.scene_path, "Scene JSON file");
  auto* run_out = run_cmd->add_option("--out", run.out_dir, "Output directory (a run owns it)")->capture_default_str();
  run_cmd->add_option("--threads", run.threads, "Worker threads (0: all cores)")
      ->check(CLI::Range(0, 4096));
  run_cmd->add_option("--backend", run.backend, "reference, cuda, or emulated (the accelerator's pipeline on the CPU)")
      ->check(CLI::IsMember({"reference", "cuda", "emulated"}))->capture_default_str();
  auto* run_seed = run_cmd->add_option("--seed", run.seed, "Override the scene's seed (unsigned 64-bit)");
  run_cmd->add_flag("--force", run.force,
                    "Replace the run that --out holds (exactly the files its manifest lists; a complete run is put back if "
                    "the new one fails before its first checkpoint)");
  run_cmd->add_option("--resume", run.resume, "Continue the killed or interrupted run in this folder, from its checkpoint");
  run_cmd->add_flag("--quiet,-q", run.quiet, "No summary on stdout");
  run_cmd->add_flag("--vtk", run.vtk, "Also write ParaView files (vtk/*.vtp, growth.pvd); implies output.paths");

  auto* scene_cmd = app.add_subcommand("scene", "Scene utilities");
  scene_cmd->require_subcommand(1);
  auto* scene_default = scene_cmd->add_subcommand("default", "Print the built-in scene");
  std::string check_path;
  auto* scene_check = scene_cmd->add_subcommand("check", "Validate a scene and print its canonical form");
  scene_check->add_option("scene", check_path, "Scene JSON file")->required();

  BenchArgs bench;
  auto* bench_cmd = app.add_subcommand("bench", "Benchmarks, with installed peers measured in the same run");
  bench_cmd->add_option("what", bench.what, "samplers|growth|particles|grid|bfs|arbours|synapses|all")
      ->check(CLI::IsMember({"samplers", "growth", "particles", "grid", "bfs", "arbours", "synapses", "all"}))
      ->capture_default_str();
  bench_cmd->add_option("--backend", bench.backend, "reference or cuda")
      ->check(CLI::IsMember({"reference", "cuda"}))->capture_default_str();
  bench_cmd->add_flag("--json", bench.json, "Machine-readable output");
  bench_cmd->add_flag("--quick", bench.quick, "Smaller sizes (for CI)");
  bench_cmd->add_option("--threads", bench.threads, "Largest thread count to measure (0: all cores)")
      ->check(CLI::Range(0, 4096));

  ValidateArgs val;
  auto* val_cmd = app.add_subcommand("validate", "Validation studies; writes a report (Markdown, CSV, PNG)");
  val_cmd->add_option("what", val.what, "samplers|field|stiff|turning|guidance|assay|gpu|bfs|all")
      ->check(CLI::IsMember({"samplers", "field", "stiff", "turning", "guidance", "continuum", "assay", "calibration", "branching", "synapses", "gpu", "bfs", "all"}))
      ->capture_default_str();
  val_cmd->add_option("--report", val.report, "Report directory")->capture_default_str();
  val_cmd->add_flag("--quick", val.quick, "Smaller sizes (the CI run)");
  val_cmd->add_option("--threads", val.threads, "Worker threads (0: all cores)")->check(CLI::Range(0, 4096));
  val_cmd->add_option("--points", val.points, "samplers: test this CSV point set (one point per row, d columns)");
  auto* val_radius = val_cmd->add_option("--radius", val.radius,
                                         "samplers --points: ball radius for points that are not unit vectors")
      ->check(finite)->check(CLI::PositiveNumber);
  val_cmd->add_flag("--allow-skip", val.allow_skip,
                    "Exit 0 when a check is skipped (it could not run here, e.g. gpu without a GPU); without it, 3");

  GoldenArgs gold;
  auto* gold_cmd = app.add_subcommand("golden", "Golden networks: check them exactly, or regenerate them");
  gold_cmd->add_option("action", gold.action, "check or bless")->required()->check(CLI::IsMember({"check", "bless"}));
  auto* gold_reason = gold_cmd->add_option("--reason", gold.reason, "bless: why (appended to data/golden/CHANGELOG.md)");
  gold_cmd->add_option("--dir", gold.dir, "Golden directory (default: data/golden)");
  auto* gold_only = gold_cmd->add_option("--only", gold.only, "bless: only this network");
  auto* gold_backend = gold_cmd->add_option("--backend", gold.backend, "check: reference or cuda")
      ->check(CLI::IsMember({"reference", "cuda"}))->capture_default_str();
  gold_cmd->add_option("--threads", gold.threads, "Worker threads (0: all cores)")->check(CLI::Range(0, 4096));

  std::string verify_dir;
  auto* verify_cmd = app.add_subcommand("verify", "Check a run's folder against its manifest: exit 0 if whole, 1 if not");
  verify_cmd->add_option("dir", verify_dir, "Output directory of a run")->required();

  std::string view_dir, plot_dir;
  auto* view_cmd = app.add_subcommand("view", "Write DIR/view.html, a self-contained 3D viewer of a run");
  view_cmd->add_option("dir", view_dir, "Output directory of a run")->required();
  auto* plot_cmd = app.add_subcommand("plot", "Write PNG plots of a run into DIR (matplotlib)");
  plot_cmd->add_option("dir", plot_dir, "Output directory of a run")->required();

  std::string assay_dir;
  auto* assay_cmd = app.add_subcommand("assay", "Measure an explant or target assay of a run: DIR/assay.csv and plots");
  assay_cmd->add_option("dir", assay_dir, "Output directory of a run")->required();

  MorphometryArgs morph;
  auto* morph_cmd = app.add_subcommand(
      "morphometry", "Morphometric statistics of SWC morphologies: DIR/morphometry.csv, sholl.csv and a plot");
  morph_cmd->add_option("dir", morph.dir, "A run's folder (its morphologies/) or a folder of .swc files")->required();
  morph_cmd->add_option("--out", morph.out, "Output folder (default: DIR)");
  morph_cmd->add_option("--projection", morph.projection, "none or xy: measure in the xy plane (2-D culture images)")
      ->capture_default_str();
  morph_cmd->add_option("--sholl-step", morph.sholl_step, "Sholl radius step (µm)")->capture_default_str();

  NetworkArgs network;
  auto* network_cmd = app.add_subcommand(
      "network", "A run's network statistics: degrees, synapses per connection, connection probability against "
                 "distance, reciprocity, clustering, path length (DIR/network.csv and a plot)");
  network_cmd->add_option("dir", network.dir, "A run's folder")->required();
  network_cmd->add_option("--out", network.out, "Output folder (default: DIR)");
  network_cmd->add_option("--bin", network.bin, "Distance bin of the connection probability (µm)")->capture_default_str();

  SweepArgs sweep;
  auto* sweep_cmd = app.add_subcommand("sweep", "Run a parameter sweep: sweep.csv, summary.csv (mean and 95% CI)");
  sweep_cmd->add_option("sweep", sweep.spec_path, "Sweep JSON file")->required();
  sweep_cmd->add_option("--out", sweep.out_dir, "Output directory")->required();
  sweep_cmd->add_option("--threads", sweep.threads, "Worker threads (0: all cores)")->check(CLI::Range(0, 4096));
  sweep_cmd->add_option("--backend", sweep.backend, "reference or cuda")
      ->check(CLI::IsMember({"reference", "cuda"}))->capture_default_str();
  sweep_cmd->add_flag("--quiet,-q", sweep.quiet, "No summary or progress");

  FitArgs fit;
  auto* fit_cmd = app.add_subcommand("fit", "Fit a model's parameters to measured bias and/or outgrowth");
  fit_cmd->add_option("data", fit.data_path,
                      "CSV: concentration, steepness, count, bias and/or outgrowth, se (or bias_se, outgrowth_se)")
      ->required();
  fit_cmd->add_option("--scene", fit.scene_path, "Base scene: an explant in an imposed gradient")->required();
  fit_cmd->add_option("--out", fit.out_dir, "Output directory")->required();
  fit_cmd->add_option("--max-chi2", fit.max_chi2, "Exit 1 when chi2/dof is above this")->capture_default_str()
      ->check(finite)->check(CLI::PositiveNumber);
  fit_cmd->add_flag("--scale", fit.scale, "Also fit a scale on the nominal concentrations");
  fit_cmd->add_option("--seeds", fit.seeds, "Seeds per model point of the grid search (more are added at its best for --target-se)")
      ->capture_default_str()->check(CLI::Range(1, 1000));
  fit_cmd->add_option("--max-seeds", fit.max_seeds, "The most seeds --target-se may take")->capture_default_str()
      ->check(CLI::Range(1, 1000));
  fit_cmd->add_option("--polish", fit.polish, "Gauss-Newton steps from the grid's best (0: none)")
      ->capture_default_str()->check(CLI::Range(0, 20));
  fit_cmd->add_option("--target-se", fit.target_se, "Model SE / data SE to reach at every point (0: off)")
      ->capture_default_str()->check(finite)->check(CLI::Range(0.0, 10.0));
  fit_cmd->add_flag("!--no-mirror", fit.mirror, "Do not also run every seed with the gradient mirrored");
  fit_cmd->add_flag("!--no-antithetic", fit.antithetic,
                    "Run the mirror images with the first runs' decision draws, not their negatives");
  fit_cmd->add_flag("--profile", fit.profile, "Morphometric data: profile intervals (slow) instead of the curvature's");
  fit_cmd->add_option("--param", fit.params,
                      "NAME or NAME=LO:HI, repeatable: a parameter to fit (gain, kd, scale, or a signalling parameter) "
                      "and its coarse range");
  fit_cmd->add_option("--correct", fit.corrections,
                      "STEEPNESS=FACTOR, repeatable: model that steepness's rows at concentration x FACTOR");
  fit_cmd->add_option("--bias-metric", fit.bias_metric, "The assay metric a bias column is compared with")
      ->check(CLI::IsMember({"bias", "outgrowth_bias", "guidance_ratio"}));
  fit_cmd->add_option("--gain-min", fit.gain_lo, "Coarse grid: smallest gain")->capture_default_str()
      ->check(finite)->check(CLI::PositiveNumber);
  fit_cmd->add_option("--gain-max", fit.gain_hi, "Coarse grid: largest gain")->capture_default_str()
      ->check(finite)->check(CLI::PositiveNumber);
  fit_cmd->add_option("--grid", fit.coarse, "Coarse grid points per parameter")->capture_default_str()
      ->check(CLI::Range(2, 50));
  fit_cmd->add_option("--refine", fit.refine, "Refinement rounds (5 points per parameter each)")->capture_default_str()
      ->check(CLI::Range(0, 10));
  fit_cmd->add_option("--threads", fit.threads, "Worker threads (0: all cores)")->check(CLI::Range(0, 4096));
  fit_cmd->add_option("--backend", fit.backend, "reference or cuda")
      ->check(CLI::IsMember({"reference", "cuda"}))->capture_default_str();

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

  if (run_cmd->parsed()) {
    run.seed_given = run_seed->count() > 0;
    run.out_given = run_out->count() > 0;
    return cmd_run(run);
  }
  if (verify_cmd->parsed()) return cmd_verify(verify_dir);
  if (scene_default->parsed()) return cmd_scene_default();
  if (scene_check->parsed()) return cmd_scene_check(check_path);
  if (bench_cmd->parsed()) return cmd_bench(bench);
  if (val_cmd->parsed()) {
    if (val_radius->count() && val.points.empty())
      throw axg::InputError("--radius: only with --points (the radius of the ball the points fill)");
    return cmd_validate(val);
  }
  if (view_cmd->parsed()) return cmd_view(view_dir);
  if (assay_cmd->parsed()) return cmd_assay(assay_dir);
  if (morph_cmd->parsed()) return cmd_morphometry(morph);
  if (network_cmd->parsed()) return cmd_network(network);
  if (sweep_cmd->parsed()) return cmd_sweep(sweep);
  if (fit_cmd->parsed()) {
    if (!(fit.gain_lo < fit.gain_hi)) throw axg::InputError("fit: --gain-min must be below --gain-max");
    return cmd_fit(fit);
  }
  if (plot_cmd->parsed()) return cmd_plot(plot_dir);
  if (gold_cmd->parsed()) {
    if (gold.action == "bless" && gold.reason.empty())
      throw axg::InputError("golden bless: --reason TEXT is required (it is appended to data/golden/CHANGELOG.md)");
    // An option the action does not take is refused, not ignored.
    if (gold.action == "bless" && gold_backend->count())
      throw axg::InputError("golden bless --backend: blessing renders on the reference engine; check takes --backend");
    if (gold.action == "check" && (gold_reason->count() || gold_only->count()))
      throw axg::InputError("golden check: --reason and --only are bless's options");
    return cmd_golden(gold);
  }
  return axg::kExitBadInput;
}

}  // namespace

namespace axg::app {

int report_error(std::exception_ptr error) {
  try {
    std::rethrow_exception(error);
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

}  // namespace axg::app

int main(int argc, char** argv) {
  // A write past the file-size limit (ulimit -f) fails with EFBIG, which every writer reports
  // as a RunError naming the file (exit 3, nothing half-written), instead of the default
  // SIGXFSZ, which kills the process before it can say anything or clean up.
  std::signal(SIGXFSZ, SIG_IGN);
  try {
    return dispatch(argc, argv);
  } catch (...) {
    return axg::app::report_error(std::current_exception());
  }
}

// axonguide assay DIR, axonguide sweep SWEEP.json --out DIR (docs/methods.md §12).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "axonguide/study/assay.hpp"
#include "axonguide/io/csv.hpp"
#include "axonguide/scene/json_input.hpp"
#include "axonguide/io/neurons_csv.hpp"
#include "axonguide/distributed/launch.hpp"
#include "axonguide/distributed/mpi_comm.hpp"
#ifdef AXG_HAVE_MPI
#include "axonguide/distributed/mpi_sweep.hpp"
#endif
#include "axonguide/support/error.hpp"
#include "axonguide/study/fit.hpp"
#include "axonguide/study/morphometry_fit.hpp"
#include "axonguide/core/pmath.hpp"
#include "axonguide/support/files.hpp"
#include "axonguide/io/run_folder.hpp"
#include "axonguide/study/sweep.hpp"
#include "axonguide/support/threads.hpp"
#include "axonguide/validate/report.hpp"
#include "backend.hpp"
#include "commands.hpp"

namespace axg::app {

namespace fs = std::filesystem;
using nlohmann::json;

std::string read_file(const fs::path& p, const char* what) {
  std::ifstream in(p, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot read {}", what, p.string()));
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

int cmd_assay(const std::string& dir_name) {
  const fs::path dir(dir_name);
  if (!fs::is_directory(dir)) throw InputError(fmt::format("assay: {} is not a directory", dir_name));
  const json manifest = require_whole_run(dir, "assay");  // every listed file has its hash
  if (!manifest["files"].contains("neurons.csv"))
    throw InputError(fmt::format("assay: {}/manifest.json does not list neurons.csv", dir_name));
  const std::string neurons_text = read_file(dir / "neurons.csv", "assay");
  if (!manifest.contains("scene"))
    throw InputError(fmt::format("assay: {}/manifest.json holds no scene: not a run's manifest", dir_name));
  const Scene scene = parse_scene(manifest["scene"].dump(), dir_name + "/manifest.json scene").scene;
  const NeuronRows rows =
      read_neurons_csv(neurons_text, fmt::format("assay: {}", (dir / "neurons.csv").string()), scene.neurons.count);
  const std::vector<core::Vec3>& soma = rows.soma;
  NeuronState n;
  n.resize(scene.neurons.count);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    n.status[i] = rows.status[i];
    n.tip[i] = rows.tip[i];
    n.length[i] = rows.length[i];
    n.steps[i] = rows.steps[i];
    n.target[i] = rows.target[i];
  }
  const auto cues = assay::reference_cues(scene);
  const assay::Metrics m = assay::measure(scene, soma, n, cues);

  std::string text = "metric,value,ci_low,ci_high\n";
  auto num = [](double v) { return std::isfinite(v) ? fmt::format("{}", v) : std::string(); };
  const double z = 1.959963984540054;
  for (const auto& [name, value] : assay::scalar_metrics(m)) {
    double lo = NAN, hi = NAN;
    if (name == "bias") lo = value - z * m.bias_se, hi = value + z * m.bias_se;
    if (name == "guidance_ratio") lo = value - z * m.guidance_ratio_se, hi = value + z * m.guidance_ratio_se;
    if (name == "mean_turning_deg") lo = value - z * m.turning_se_deg, hi = value + z * m.turning_se_deg;
    const double explant = static_cast<double>(scene.neurons.populations.empty() ? scene.neurons.count
                                                                                 : scene.neurons.populations[0].count);
    if ((name == "connected_fraction" || name == "exited_fraction" || name == "target_fraction") &&
        std::isfinite(value))
      std::tie(lo, hi) = assay::wilson_interval(std::round(value * explant), explant);
    if (name == "crossing_fraction" && std::isfinite(value))
      std::tie(lo, hi) = assay::wilson_interval(std::round(value * m.crossing_axons), m.crossing_axons);
    text += fmt::format("{},{},{},{}\n", name, num(value), num(lo), num(hi));
  }
  write_file_atomically(dir, "assay.csv", text);
  std::string prof = "theta_deg,outgrowth,axons\n";
  for (int j = 0; j < assay::kAngleBins; ++j)
    prof += fmt::format("{},{},{}\n", (j + 0.5) * 360.0 / assay::kAngleBins, m.profile[j], m.profile_axons[j]);
  write_file_atomically(dir, "assay_profile.csv", prof);
  std::string turn = "from_deg,to_deg,axons\n";
  for (int k = 0; k < assay::kTurningBins; ++k)
    turn += fmt::format("{},{},{}\n", -180 + k * 360 / assay::kTurningBins, -180 + (k + 1) * 360 / assay::kTurningBins,
                        m.turning[k]);
  write_file_atomically(dir, "assay_turning.csv", turn);

  const core::Vec3 up = assay::explant_geometry(scene, cues).up;
  fmt::print("assay     {} explant axons that grew; gradient axis up = ({:.3f}, {:.3f}, {:.3f})\n", m.axons, up.x,
             up.y, up.z);
  fmt::print("          directional bias {:.4f} ± {:.4f} (95% CI), guidance ratio {:.4f} ± {:.4f}\n", m.bias,
             z * m.bias_se, m.guidance_ratio, z * m.guidance_ratio_se);
  fmt::print("          mean turning angle {:.2f}° ± {:.2f}°, mean outgrowth {:.4g} {}\n", m.mean_turning_deg,
             z * m.turning_se_deg, m.mean_outgrowth, scene.units.length);
  if (std::isfinite(m.target_fraction))
    fmt::print("          reached the target population {:.4f}, crossed the midplane {:.4f}\n", m.target_fraction,
               m.crossing_fraction);
  if (std::isfinite(m.near_attractant_fraction) || std::isfinite(m.near_repellent_fraction))
    fmt::print("          tips within 3 sensing radii of an attractant {:.4f}, of a repellent {:.4f} (all neurons)\n",
               m.near_attractant_fraction, m.near_repellent_fraction);
  const bool drawn = validate::draw_folder_plot(dir, "assay_run.py", "assay.png", "assay");
  fmt::print("outputs   {}/assay.csv, assay_profile.csv, assay_turning.csv{}\n", dir_name,
             drawn ? ", assay.png" : "");
  return kExitOk;
}

int cmd_sweep(const SweepArgs& args) {
  const auto t0 = std::chrono::steady_clock::now();
  const distributed::Launch launch = distributed::detect_launch();
  const bool over_ranks = launch.under_mpirun() && distributed::have_mpi();
  if (launch.under_mpirun() && !over_ranks) {
    // K copies of a build without MPI: one runs the sweep, the others must not write it.
    if (launch.rank != 0) return kExitOk;
    std::fprintf(stderr,
                 "axonguide: note: started as rank 0 of %d by mpirun, but this build has no MPI (install "
                 "libopenmpi-dev and rebuild): the sweep runs in this one process; ranks 1-%d exit\n",
                 launch.size, launch.size - 1);
  }
  sweep::Options options;
  // Under mpirun the ranks on a node share its cores: each runs its member on its share.
  const int cores = resolve_threads(0);
  options.threads =
      args.threads > 0 ? args.threads : over_ranks ? std::max(1, cores / std::max(1, launch.local_size)) : cores;
  options.run.make_engine = engine_factory(args.backend);
  options.backend = args.backend;
  const bool tty = ::isatty(STDERR_FILENO) == 1 && !args.quiet;
  auto last = std::chrono::steady_clock::now() - std::chrono::seconds(1);
  options.on_member = [&](std::size_t done, std::size_t total, std::size_t failed, std::size_t skipped) {
    if (!tty) return;
    const auto now = std::chrono::steady_clock::now();
    if (done != total && now - last < std::chrono::milliseconds(200)) return;
    last = now;
    const double el = std::chrono::duration<double>(now - t0).count();
    std::fprintf(stderr, "\r\033[Ksweep %zu/%zu members  failed %zu  reused %zu  %.1f s", done, total, failed, skipped,
                 el);
    if (done == total) std::fprintf(stderr, "\n");
    std::fflush(stderr);
  };
  sweep::Outcome out;
  std::optional<sweep::Spec> spec;
  std::optional<distributed::MpiSession> session;
  if (over_ranks) {
#ifdef AXG_HAVE_MPI
    session.emplace();
    int code = kExitOk;
    distributed::SweepOverRanks r;
    try {
      r = distributed::run_sweep_over_ranks(args.spec_path, args.out_dir, options, &code);
    } catch (...) {
      // Rank 0's message goes out before MPI_Finalize lets the other ranks exit (mpirun
      // would end the job, rank 0 with it, at the first non-zero exit).
      session->exit_code = report_error(std::current_exception());
      return session->exit_code;
    }
    session->rank_died = r.dead_ranks > 0;
    if (!r.is_root) return session->exit_code = code;
    out = std::move(r.outcome);
    spec = std::move(r.spec);
#endif
  } else {
    spec = sweep::load_spec(args.spec_path);
    out = sweep::run(*spec, args.out_dir, options);
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!args.quiet) {
    const std::string where = over_ranks ? fmt::format("{} ranks ({} running members, {} threads each)", launch.size,
                                                       launch.size - 1, options.threads)
                                         : fmt::format("{} threads", options.threads);
    fmt::print("sweep     {}: {} points x {} seeds = {} members on {}\n", args.spec_path,
               sweep::point_count(*spec), spec->seeds.size(), out.members.size(), where);
    fmt::print("          ran {}, reused {} verified records, failed {}; {:.2f} s\n",
               out.members.size() - out.skipped, out.skipped, out.failed, wall);
    for (const auto& r : out.members)
      if (!r.ok)
        fmt::print("          member {} failed (exit {}): {}\n", r.member, r.exit_code, r.message);
    fmt::print("outputs   {}/sweep.csv, summary.csv, sweep.json, members/\n", args.out_dir);
  }
  const int code = out.failed > 0 ? kExitCheckFailed : kExitOk;
  if (session) session->exit_code = code;
  return code;
}

}  // namespace axg::app

namespace axg::app {

namespace {

// "NAME" or "NAME=LO:HI".
fit::Parameter parse_param(const std::string& text) {
  fit::Parameter p;
  const std::size_t eq = text.find('=');
  p.name = text.substr(0, eq);
  if (eq == std::string::npos) return p;
  const std::string range = text.substr(eq + 1);
  const std::size_t colon = range.find(':');
  auto finite = [&](const std::string& v) {
    const std::optional<double> x = parse_number(v);
    if (!x || !std::isfinite(*x))
      throw InputError(fmt::format("fit: --param {}: \"{}\" is not a finite number (NAME=LO:HI)", text, v));
    return *x;
  };
  if (colon == std::string::npos) throw InputError(fmt::format("fit: --param {}: must be NAME or NAME=LO:HI", text));
  p.lo = finite(range.substr(0, colon));
  p.hi = finite(range.substr(colon + 1));
  if (!(p.lo > 0) || !(p.hi > p.lo))
    throw InputError(fmt::format("fit: --param {}: LO and HI must be > 0 with LO below HI", text));
  return p;
}

std::pair<double, double> parse_correction(const std::string& text) {
  const std::size_t eq = text.find('=');
  double s = -1, f = -1;
  if (eq != std::string::npos) {
    const std::optional<double> a = parse_number(text.substr(0, eq)), b = parse_number(text.substr(eq + 1));
    if (a && b) s = *a, f = *b;
  }
  if (!(s >= 0) || !(f > 0) || !std::isfinite(s) || !std::isfinite(f))
    throw InputError(fmt::format("fit: --correct {}: must be STEEPNESS=FACTOR with STEEPNESS >= 0 and FACTOR > 0", text));
  return {s, f};
}

}  // namespace

namespace {

// `axonguide fit` on morphometric data (study/morphometry_fit.hpp): an arbour scene's
// branching and elongation parameters against statistics by age.
int fit_morphometry(const FitArgs& args) {
  const std::vector<morphofit::DataRow> data = morphofit::load_data(args.data_path);
  const Scene scene = load_scene_file(args.scene_path).scene;
  morphofit::Options o;
  o.seeds.clear();
  for (int k = 1; k <= args.seeds; ++k) o.seeds.push_back(static_cast<std::uint64_t>(k));
  o.iterations = std::max(1, 3 * args.polish);
  o.profile = args.profile;
  for (const std::string& p : args.params) {
    morphofit::Parameter q;
    const auto eq = p.find('=');
    q.name = p.substr(0, eq);
    if (eq != std::string::npos) {
      const auto colon = p.find(':', eq);
      try {
        if (colon == std::string::npos) throw std::invalid_argument(p);
        q.lo = std::stod(p.substr(eq + 1, colon - eq - 1));
        q.hi = std::stod(p.substr(colon + 1));
      } catch (const std::exception&) {
        throw InputError(fmt::format("--param {}: give NAME or NAME=LO:HI", p));
      }
      if (!(q.lo > 0) || !(q.hi > q.lo)) throw InputError(fmt::format("--param {}: need 0 < LO < HI", p));
    }
    (void)morphofit::get_parameter(scene, q.name);  // names a fittable parameter
    o.parameters.push_back(q);
  }
  o.on_progress = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
  const morphofit::Result r = with_threads(resolve_threads(args.threads), [&] { return morphofit::fit(scene, data, o); });
  prepare_output_dir(args.out_dir);
  morphofit::write_result(r, args.out_dir);
  fmt::print("fit       {} statistics at {} ages, {} parameters, {} seeds; {} evaluations in {:.1f} s\n", data.size(),
             [&] {
               std::vector<double> a;
               for (const auto& d : data)
                 if (std::find(a.begin(), a.end(), d.age_days) == a.end()) a.push_back(d.age_days);
               return a.size();
             }(),
             r.parameters.size(), o.seeds.size(), r.evaluations, r.seconds);
  fmt::print("chi2      {:.2f} / {} dof = {:.2f} (correlated; {:.2f} ignoring correlations)\n", r.chi2, r.dof,
             r.chi2 / std::max(1, r.dof), r.chi2_diagonal);
  for (const auto& p : r.parameters)
    fmt::print("          {:<20} {:.4g} [{:.4g}, {:.4g}] ({}; start {:.4g})\n", p.name, p.best, p.lo, p.hi, p.method, p.start);
  if (r.refused_draws > 0)
    fmt::print("predict   {} of {} drawn parameter sets left out: their arbours would not fit in memory\n",
               r.refused_draws, o.predict_draws);
  fmt::print("outputs   {}/ (fit.json, residuals.csv, predictions.csv, scene.json)\n", args.out_dir);
  return r.chi2 / std::max(1, r.dof) > args.max_chi2 ? 1 : 0;
}

}  // namespace

int cmd_fit(const FitArgs& args) {
  {
    std::error_code ec;  // before the fit's runs, not after them
    if (fs::exists(args.out_dir, ec) && !fs::is_directory(args.out_dir, ec))
      throw InputError(fmt::format("--out {}: exists and is not a directory", args.out_dir));
  }
  if (morphofit::is_morphometric_data(args.data_path)) return fit_morphometry(args);
  const fit::Data data = fit::load_data(args.data_path);
  const std::string scene_text = read_input_file(args.scene_path, "scene file");  // read once: checked, then the base
  const ParseResult parsed = parse_scene(scene_text, args.scene_path);
  const json base = parse_json_strict(scene_text, args.scene_path);
  fit::Options o;
  o.threads = resolve_threads(args.threads);
  o.fit_scale = args.scale;
  o.seeds.clear();
  for (int k = 1; k <= args.seeds; ++k) o.seeds.push_back(static_cast<std::uint64_t>(k));
  o.max_seeds = static_cast<std::size_t>(args.max_seeds);
  o.polish_iterations = args.polish;
  o.target_se_ratio = args.target_se;
  o.mirror = args.mirror;
  o.antithetic = args.antithetic;
  for (const auto& p : args.params) o.parameters.push_back(parse_param(p));
  for (const auto& c : args.corrections) o.corrections.push_back(parse_correction(c));
  o.bias_metric = args.bias_metric;
  o.gain_lo = args.gain_lo;
  o.gain_hi = args.gain_hi;
  o.coarse = args.coarse;
  o.refine_rounds = args.refine;
  o.run.make_engine = engine_factory(args.backend);
  const auto t0 = std::chrono::steady_clock::now();
  if (::isatty(STDERR_FILENO) == 1)  // a progress line on a terminal, as run and sweep show
    o.on_evaluation = [t0](std::size_t evaluations, double best) {
      const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (std::isfinite(best))
        std::fprintf(stderr, "\r\033[Kfit %zu evaluations  best chi2 %.6g  %.1f s", evaluations, best, el);
      else
        std::fprintf(stderr, "\r\033[Kfit %zu evaluations  %.1f s", evaluations, el);
      std::fflush(stderr);
    };
  const fit::Result r = fit::fit(base, args.scene_path, data, o);
  if (o.on_evaluation) std::fprintf(stderr, "\n");
  const double fit_wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  // The fitted curve: a dense concentration grid for each steepness of the data (model
  // concentrations, corrected as the points are).
  std::vector<double> steep;
  double cmin = HUGE_VAL, cmax = 0;
  auto factor = [&](double s) { return fit::correction_factor(o, s); };
  for (const auto& d : data.points) {
    if (std::find(steep.begin(), steep.end(), d.steepness) == steep.end()) steep.push_back(d.steepness);
    cmin = std::min(cmin, d.concentration * factor(d.steepness));
    cmax = std::max(cmax, d.concentration * factor(d.steepness));
  }
  std::vector<std::pair<double, double>> curve_pts;
  const int nc = 13;
  for (double s : steep)
    for (int k = 0; k < nc; ++k)
      curve_pts.emplace_back(core::pm::exp(core::pm::log(cmin / 3) + (core::pm::log(cmax * 3) - core::pm::log(cmin / 3)) * k / (nc - 1)), s);
  std::vector<double> cm[fit::kMeasures], cs[fit::kMeasures];
  fit::Options po = o;
  po.seeds = r.seeds;
  fit::predict(base, curve_pts, r.parameters, r.best, po, cm, cs);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  prepare_output_dir(args.out_dir);
  const fs::path dir(args.out_dir);
  auto num = [](double v) { return std::isfinite(v) ? fmt::format("{}", v) : std::string(); };
  auto value_of = [&](const char* name, double otherwise) {
    for (std::size_t k = 0; k < r.parameters.size(); ++k)
      if (r.parameters[k].name == name) return r.best[k];
    return otherwise;
  };
  std::string grid = "evaluation";
  for (const auto& p : r.parameters) grid += "," + p.name;
  grid += ",chi2\n";
  for (std::size_t e = 0; e < r.evaluations.size(); ++e) {
    grid += fmt::format("{}", e);
    for (double v : r.evaluations[e].p) grid += fmt::format(",{}", v);
    grid += fmt::format(",{}\n", num(r.evaluations[e].chi2));
  }
  std::string pts =
      "line,concentration,steepness,measure,value,se,count,model,model_se,residual,model_min,model_max,reachable,"
      "model_concentration\n";
  std::size_t unreachable = 0;
  json unreach = json::array();
  for (std::size_t q = 0; q < r.residuals.size(); ++q) {
    const auto [i, m] = r.residuals[q];
    const auto& d = data.points[i];
    const double v = d.value[m], se = d.se[m];
    pts += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", d.line, d.concentration, d.steepness,
                       fit::measure_name(m), v, se, d.count, num(r.model[q]), num(r.model_se[q]),
                       num((v - r.model[q]) / se), num(r.model_min[q]), num(r.model_max[q]),
                       r.reachable[q] ? "yes" : "no", d.concentration * factor(d.steepness));
    if (!r.reachable[q]) {
      ++unreachable;
      unreach.push_back({{"line", d.line}, {"concentration", d.concentration}, {"steepness", d.steepness},
                         {"measure", fit::measure_name(m)}, {fit::measure_name(m), v}, {"se", se},
                         {"model_min", r.model_min[q]}, {"model_max", r.model_max[q]}});
    }
  }
  std::string curve = "concentration,steepness,measure,model,model_se\n";
  for (int m = 0; m < fit::kMeasures; ++m)
    for (std::size_t k = 0; k < curve_pts.size(); ++k)
      curve += fmt::format("{},{},{},{},{}\n", curve_pts[k].first, curve_pts[k].second, fit::measure_name(m),
                           num(cm[m][k]), num(cs[m][k]));
  json params = json::object();
  for (std::size_t k = 0; k < r.parameters.size(); ++k) {
    const auto& iv = r.intervals[k];
    params[r.parameters[k].name] = {{"best", r.best[k]},          {"interval_low", iv.lo},
                                    {"interval_high", iv.hi},     {"open_low", iv.open_low},
                                    {"open_high", iv.open_high},  {"coarse_range", {r.parameters[k].lo, r.parameters[k].hi}},
                                    {"profiled", iv.profiled}};
  }
  json measured = json::array();
  for (int m = 0; m < fit::kMeasures; ++m)
    if (data.measured[m]) measured.push_back(fit::measure_name(m));
  json corrections = json::array();
  for (const auto& [s, f] : o.corrections) corrections.push_back({s, f});
  json summary = {{"data", args.data_path},
                  {"scene", args.scene_path},
                  {"measured", measured},
                  {"bias_metric", r.bias_metric},
                  {"parameters", params},
                  {"interval", fmt::format("profile likelihood, chi2 <= min + {:.4g} (3.84 x max(1, chi2/dof)), "
                                           "each end found on the profile (the other parameters re-fitted there)",
                                           r.interval_delta)},
                  {"polished", r.polished},
                  {"gain", value_of("gain", parsed.scene.guidance.gain)},
                  {"kd", value_of("kd", parsed.scene.cues.sources.empty() ? 0.0 : parsed.scene.cues.sources[0].kd)},
                  {"concentration_scale", value_of("scale", 1.0)},
                  {"scale_fitted", args.scale},
                  {"corrections", corrections},
                  {"chi2", r.chi2},
                  {"dof", r.dof},
                  {"chi2_per_dof", r.chi2_per_dof},
                  {"max_chi2_per_dof", args.max_chi2},
                  {"seeds", r.seeds.size()},
                  {"mirror", o.mirror},
                  {"antithetic", o.mirror && o.antithetic},
                  {"target_se_ratio", o.target_se_ratio},
                  {"model_se_ratio_max", r.se_ratio_max},
                  {"evaluations", r.evaluations.size()},
                  {"runs", r.runs},
                  {"fit_seconds", fit_wall},
                  {"runs_per_second", fit_wall > 0 ? static_cast<double>(r.runs) / fit_wall : 0.0},
                  {"unreachable", unreach},
                  {"units", parsed.scene.units.describe()}};
  for (const auto& [name, text] : std::vector<std::pair<std::string, std::string>>{
           {"fit_grid.csv", grid}, {"fit_points.csv", pts}, {"fit_curve.csv", curve}, {"fit.json", summary.dump(2) + "\n"}})
    write_file_atomically(dir, name, text);
  const bool drawn = validate::draw_folder_plot(dir, "fit_curve.py", "fit.png", "fit", /*quiet_without_python=*/true);
  std::string what;
  for (int m = 0; m < fit::kMeasures; ++m)
    if (data.measured[m]) what += (what.empty() ? "" : " and ") + std::string(fit::measure_name(m));
  fmt::print("fit       {} data points ({}) from {}; base scene {}\n", data.points.size(), what, args.data_path,
             args.scene_path);
  for (std::size_t k = 0; k < r.parameters.size(); ++k) {
    const auto& iv = r.intervals[k];
    fmt::print("          {} = {:.4g}, 95% profile interval {}{:.4g} to {:.4g}{}\n", r.parameters[k].name, r.best[k],
               iv.open_low ? "<=" : "", iv.lo, iv.hi, iv.open_high ? " (open: the searched range's edge)" : "");
  }
  fmt::print("          chi2 {:.3f} on {} degrees of freedom: chi2/dof = {:.3f} (threshold {})\n", r.chi2, r.dof,
             r.chi2_per_dof, args.max_chi2);
  fmt::print("          {} seeds{}; model SE / data SE at most {:.3f} (target {:.3f})\n", r.seeds.size(),
             o.mirror ? (o.antithetic ? ", each with its antithetic mirror image" : ", each with its mirror image") : "",
             r.se_ratio_max, o.target_se_ratio);
  fmt::print("          {} parameter sets, {} runs, {:.1f} s ({:.1f} runs/s); {} value{} the model cannot reach\n",
             r.evaluations.size(), r.runs, wall, fit_wall > 0 ? r.runs / fit_wall : 0.0, unreachable,
             unreachable == 1 ? "" : "s");
  for (const auto& u : unreach) {
    const std::string m = u["measure"].get<std::string>();
    fmt::print("          line {}: {} {} ± {} at {} {}, steepness {}: the model gives {:.4g} to {:.4g}\n",
               u["line"].get<std::size_t>(), m, u[m].get<double>(), u["se"].get<double>(),
               u["concentration"].get<double>(), parsed.scene.units.concentration, u["steepness"].get<double>(),
               u["model_min"].get<double>(), u["model_max"].get<double>());
  }
  if (o.target_se_ratio > 0 && r.se_ratio_max > o.target_se_ratio)
    fmt::print("          warning: the model SE is above {:.3f} x the data SE at some point: raise --max-seeds\n",
               o.target_se_ratio);
  fmt::print("outputs   {}/fit.json, fit_points.csv, fit_grid.csv, fit_curve.csv{}\n", args.out_dir,
             drawn ? ", fit.png" : "");
  if (r.chi2_per_dof > args.max_chi2) {
    std::fprintf(stderr, "axonguide: fit: chi2/dof = %.3f is above the threshold %g (--max-chi2)\n", r.chi2_per_dof,
                 args.max_chi2);
    return kExitCheckFailed;
  }
  return kExitOk;
}

}  // namespace axg::app

#include "axonguide/study/fit.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string_view>

#include <fmt/format.h>

#include "axonguide/study/assay.hpp"
#include "axonguide/io/csv.hpp"
#include "axonguide/core/pmath.hpp"
#include "axonguide/core/rosenbrock.hpp"
#include "axonguide/support/error.hpp"
#include "axonguide/scene/json_input.hpp"
#include "axonguide/model/signalling.hpp"
#include "axonguide/study/sweep.hpp"

namespace axg::fit {

using nlohmann::json;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double log_of(double x) { return core::pm::log(x); }
double exp_of(double x) { return core::pm::exp(x); }

}  // namespace

const char* measure_name(int m) { return m == kBias ? "bias" : "outgrowth"; }

Data load_data(const std::string& path) { return parse_data(read_input_file(path, "fit: data"), path); }

Data parse_data(const std::string& text, const std::string& path) {
  std::istringstream in(text);
  std::string line;
  std::size_t n = 0;
  std::map<std::string, std::size_t> col;
  Data out;
  // Column indices: concentration, steepness, count, then value and se per measure.
  std::vector<std::pair<std::string, int>> read;  // (column, slot)
  static const char* kKnown = "concentration, steepness, count, bias, outgrowth, se, bias_se, outgrowth_se";
  while (std::getline(in, line)) {
    ++n;
    const std::string t = trim_cell(line);
    if (t.empty() || t[0] == '#') continue;
    const auto f = split_csv_line(t);
    if (col.empty()) {
      for (std::size_t k = 0; k < f.size(); ++k) {
        static const std::vector<std::string> known{"concentration", "steepness", "count", "bias",
                                                    "outgrowth",     "se",        "bias_se", "outgrowth_se"};
        if (std::find(known.begin(), known.end(), f[k]) == known.end())
          throw InputError(fmt::format("fit: {} line {}: unknown column \"{}\" (the columns are {})", path, n, f[k],
                                       kKnown));
        if (col.count(f[k])) throw InputError(fmt::format("fit: {} line {}: column \"{}\" twice", path, n, f[k]));
        col[f[k]] = k;
      }
      for (const char* name : {"concentration", "steepness", "count"})
        if (!col.count(name))
          throw InputError(fmt::format(
              "fit: {} line {}: the header must name the columns concentration, steepness, count, a measured column "
              "(bias and/or outgrowth) and its se (missing \"{}\")",
              path, n, name));
      out.measured[kBias] = col.count("bias") > 0;
      out.measured[kOutgrowth] = col.count("outgrowth") > 0;
      if (out.measure_count() == 0)
        throw InputError(fmt::format(
            "fit: {} line {}: no measured column: the header must name bias (directional bias) and/or outgrowth "
            "(radial outgrowth, length units)",
            path, n));
      read = {{"concentration", 0}, {"steepness", 1}, {"count", 2}};
      if (out.measure_count() == 1) {
        const int m = out.measured[kBias] ? kBias : kOutgrowth;
        for (const char* other : {"bias_se", "outgrowth_se"})
          if (col.count(other))
            throw InputError(fmt::format("fit: {} line {}: column \"{}\" with one measured column: its SE is \"se\"",
                                         path, n, other));
        if (!col.count("se"))
          throw InputError(fmt::format("fit: {} line {}: the header must name the column se (the standard error of {}; "
                                       "missing \"se\")",
                                       path, n, measure_name(m)));
        read.push_back({measure_name(m), 3 + 2 * m});
        read.push_back({"se", 4 + 2 * m});
      } else {
        if (col.count("se"))
          throw InputError(fmt::format(
              "fit: {} line {}: column \"se\" is ambiguous with both bias and outgrowth: name bias_se and outgrowth_se",
              path, n));
        for (int m = 0; m < kMeasures; ++m) {
          const std::string se = std::string(measure_name(m)) + "_se";
          if (!col.count(se))
            throw InputError(fmt::format("fit: {} line {}: the header must name the column {} (missing \"{}\")", path,
                                         n, se, se));
          read.push_back({measure_name(m), 3 + 2 * m});
          read.push_back({se, 4 + 2 * m});
        }
      }
      continue;
    }
    if (f.size() != col.size())
      throw InputError(fmt::format("fit: {} line {}: {} fields, the header has {}", path, n, f.size(), col.size()));
    double v[7] = {kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN};
    for (const auto& [name, slot] : read) {
      const std::string& s = f[col[name]];
      std::size_t used = 0;
      try {
        v[slot] = std::stod(s, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != s.size() || s.empty() || !std::isfinite(v[slot]))
        throw InputError(fmt::format("fit: {} line {}: {} = \"{}\" is not a finite number", path, n, name, s));
    }
    if (!(v[0] > 0)) throw InputError(fmt::format("fit: {} line {}: concentration = {} must be > 0", path, n, v[0]));
    if (v[1] < 0) throw InputError(fmt::format("fit: {} line {}: steepness = {} must be >= 0", path, n, v[1]));
    if (v[2] < 1 || v[2] > 1e9 || v[2] != std::floor(v[2]))  // 1e30 was cast to an integer: undefined
      throw InputError(fmt::format("fit: {} line {}: count = {} must be an integer in [1, 10^9]", path, n, v[2]));
    DataPoint p{v[0], v[1], {v[3], v[5]}, {v[4], v[6]}, static_cast<std::uint64_t>(v[2]), n};
    for (int m = 0; m < kMeasures; ++m)
      if (out.measured[m] && !(p.se[m] > 0))
        throw InputError(fmt::format("fit: {} line {}: {} = {} must be > 0", path, n,
                                     out.measure_count() == 1 ? std::string("se") : std::string(measure_name(m)) + "_se",
                                     p.se[m]));
    out.points.push_back(p);
  }
  if (col.empty()) throw InputError(fmt::format("fit: {}: empty (a header and data rows are needed)", path));
  if (out.points.size() < 3)
    throw InputError(fmt::format("fit: {}: {} data rows; at least 3 are needed", path, out.points.size()));
  return out;
}

namespace {

bool signalling_scene(const Scene& s) { return s.signalling(); }

const SignalParameter* signal_parameter(const std::string& name) {
  for (const auto& p : kSignalTable)
    if (name == p.name) return &p;
  return nullptr;
}

// Writes parameter `name` = v into a copy of the base scene.
void apply(json& scene, const Parameter& par, double v) {
  if (par.name == "gain") {
    scene["guidance"]["gain"] = v;
  } else if (par.name == "kd") {
    for (auto& src : scene["cues"]["sources"]) src["kd"] = v;
  } else if (par.name == "scale") {
    // Applied to the points' concentrations (spec_for).
  } else {
    scene["axons"]["signalling"][par.name] = signal_value_json(v, *signal_parameter(par.name));
  }
}

double scale_of(const std::vector<Parameter>& ps, const Params& p) {
  for (std::size_t k = 0; k < ps.size(); ++k)
    if (ps[k].name == "scale") return p[k];
  return 1.0;
}

// The sweeps of one parameter set: the points zipped, one spec per mirror image; the mirror
// image's decisions antithetic where asked.
std::vector<sweep::Spec> specs_for(const json& base, const std::vector<std::pair<double, double>>& pts,
                                   const std::vector<Parameter>& ps, const Params& p,
                                   const std::vector<std::uint64_t>& seeds, bool mirror, bool antithetic) {
  std::vector<sweep::Spec> out;
  for (int side = 0; side < (mirror ? 2 : 1); ++side) {
    sweep::Spec s;
    s.base = base;
    for (std::size_t k = 0; k < ps.size(); ++k) apply(s.base, ps[k], p[k]);
    if (side == 1) {
      json& d = s.base["cues"]["imposed"]["direction"];
      if (d.is_null()) d = json::array({1.0, 0.0, 0.0});
      for (auto& x : d) x = -x.get<double>();
      if (antithetic) s.base["guidance"]["antithetic"] = true;
    }
    s.base_origin = "fit";
    s.zip = true;
    sweep::Parameter c{"concentration", {"cues.imposed.concentration"}, {}, {}};
    sweep::Parameter st{"steepness", {"cues.imposed.steepness"}, {}, {}};
    const double scale = scale_of(ps, p);
    for (const auto& [conc, steep] : pts) {
      c.values.push_back(conc * scale);
      st.values.push_back(steep);
    }
    s.parameters = {c, st};
    s.seeds = seeds;
    out.push_back(std::move(s));
  }
  return out;
}

struct Evaluated {
  // [set][measure][point]
  std::vector<std::array<std::vector<double>, kMeasures>> mean, se;
};

std::string describe(const std::vector<Parameter>& ps, const Params& p) {
  std::string s;
  for (std::size_t k = 0; k < ps.size(); ++k) s += fmt::format("{}{} {}", k ? ", " : "", ps[k].name, p[k]);
  return s;
}

// Runs every (parameter set, mirror, point, seed) in one parallel loop; returns each
// measure's mean and SE over seeds per set and point. Per seed, a mirrored pair gives the
// mean of its two values, each measured along its own run's gradient axis: the explant's
// random asymmetry (the same in both, since the seed is) adds +a to one bias and -a to the
// other, and cancels. With antithetic decisions in the mirror image (Options::antithetic)
// the two axons of a neuron turn the same way in space at every decision the evidence does
// not settle, so the decisions' noise cancels too (docs/methods.md §12.3).
Evaluated evaluate(const json& base, const std::vector<std::pair<double, double>>& pts,
                   const std::vector<Parameter>& ps, const std::vector<Params>& sets, const Options& o,
                   const std::vector<std::uint64_t>& seeds, const std::string& bias_metric, std::size_t& runs) {
  std::vector<sweep::Spec> specs;
  for (const Params& p : sets)
    for (auto& s : specs_for(base, pts, ps, p, seeds, o.mirror, o.antithetic)) specs.push_back(std::move(s));
  const std::size_t S = seeds.size(), sides = o.mirror ? 2 : 1, per_side = pts.size() * S;
  const std::size_t per = per_side * sides;
  const std::vector<sweep::MemberResult> results = sweep::run_in_memory(specs, o.threads, o.run);
  for (std::size_t k = 0; k < results.size(); ++k)
    if (!results[k].ok) {
      const std::string what = fmt::format("fit: the model run at {} (concentration {}, steepness {}) failed: {}",
                                           describe(ps, sets[k / per]), pts[k % per_side / S].first,
                                           pts[k % per_side / S].second, results[k].message);
      if (results[k].exit_code == 2) throw InputError(what);  // the scene the data made is not valid
      throw RunError(what);
    }
  runs += results.size();
  Evaluated ev;
  ev.mean.resize(sets.size());
  ev.se.resize(sets.size());
  const std::string names[kMeasures] = {bias_metric, "outgrowth"};
  for (std::size_t e = 0; e < sets.size(); ++e)
    for (int m = 0; m < kMeasures; ++m) {
      ev.mean[e][m].assign(pts.size(), kNaN);
      ev.se[e][m].assign(pts.size(), kNaN);
      for (std::size_t i = 0; i < pts.size(); ++i) {
        std::vector<double> x(S);
        for (std::size_t j = 0; j < S; ++j) {
          const double a = sweep::metric(results[e * per + i * S + j], names[m]);
          if (sides == 1) {
            x[j] = a;
          } else {
            const double b = sweep::metric(results[e * per + per_side + i * S + j], names[m]);
            x[j] = 0.5 * (a + b);
          }
        }
        const sweep::MeanSe s = sweep::mean_se(x);
        // An undefined value (no axon grew) makes the point, and so the set, undefined.
        ev.mean[e][m][i] = s.n == S ? s.mean : kNaN;
        ev.se[e][m][i] = S > 1 ? s.se : 0.0;
      }
    }
  return ev;
}

// The profile of parameter k over the evaluations: per distinct value, the lowest chi2;
// the parabola through the lowest and its neighbours (in log value) cut at min + delta.
Interval profile_interval(const std::vector<Evaluation>& evs, std::size_t k, double best, double delta) {
  std::map<double, double> prof;  // log value -> lowest chi2
  for (const auto& e : evs) {
    if (!std::isfinite(e.chi2)) continue;
    const double x = log_of(e.p[k]);
    auto it = prof.find(x);
    if (it == prof.end() || e.chi2 < it->second) prof[x] = e.chi2;
  }
  Interval r;
  r.best = best;
  r.lo = r.hi = best;
  if (prof.empty()) return r;
  std::vector<std::pair<double, double>> v(prof.begin(), prof.end());
  std::size_t m = 0;
  for (std::size_t i = 1; i < v.size(); ++i)
    if (v[i].second < v[m].second) m = i;
  const double cmin = v[m].second, cut = cmin + delta;
  // Each side: the parabola through (m-1, m, m+1) where both neighbours exist; at an end of
  // the searched values the interval is open on that side.
  double a = 0, x0 = v[m].first;
  if (m > 0 && m + 1 < v.size()) {
    const double x1 = v[m - 1].first, y1 = v[m - 1].second, x2 = v[m].first, y2 = v[m].second, x3 = v[m + 1].first,
                 y3 = v[m + 1].second;
    const double d = (x1 - x2) * (x1 - x3) * (x2 - x3);
    a = (x3 * (y2 - y1) + x2 * (y1 - y3) + x1 * (y3 - y2)) / d;
    const double b = (x3 * x3 * (y1 - y2) + x2 * x2 * (y3 - y1) + x1 * x1 * (y2 - y3)) / d;
    if (a > 0) x0 = -b / (2 * a);
  }
  // Without a parabola (the lowest value at an end, or a flat profile), the profile's own
  // crossings of the cut, linearly interpolated; open where it never rises past it.
  double lo = v.front().first, hi = v.back().first;
  r.open_low = r.open_high = true;
  for (std::size_t i = m; i-- > 0;)
    if (v[i].second > cut) {
      lo = v[i].first + (v[i + 1].first - v[i].first) * (cut - v[i + 1].second) / (v[i].second - v[i + 1].second);
      r.open_low = false;
      break;
    }
  for (std::size_t i = m + 1; i < v.size(); ++i)
    if (v[i].second > cut) {
      hi = v[i - 1].first + (v[i].first - v[i - 1].first) * (cut - v[i - 1].second) / (v[i].second - v[i - 1].second);
      r.open_high = false;
      break;
    }
  if (a > 0) {
    const double vertex = cmin - a * (x0 - v[m].first) * (x0 - v[m].first);
    const double h = std::sqrt(std::max(0.0, cut - vertex) / a);
    lo = std::min(x0 - h, log_of(best));
    hi = std::max(x0 + h, log_of(best));
    // Open where the parabola reaches past every searched value and the profile never rose.
    r.open_low = r.open_low && lo < v.front().first;
    r.open_high = r.open_high && hi > v.back().first;
  }
  r.lo = exp_of(lo);
  r.hi = exp_of(hi);
  return r;
}

// Solves a x = b (n x n, row-major; a copied) by the core's LU with partial pivoting;
// false when singular.
bool solve(std::vector<double> a, std::vector<double>& b, std::size_t n) {
  std::vector<int> piv(n);
  if (!core::lu_factor(a.data(), static_cast<int>(n), piv.data())) return false;
  core::lu_solve(a.data(), static_cast<int>(n), piv.data(), b.data());
  return true;
}

}  // namespace

std::vector<Parameter> resolve_parameters(const json& base, const std::string& origin, const Data& data,
                                          const Options& o) {
  const Scene scene = parse_scene(base.dump(), origin).scene;
  double cmin = HUGE_VAL, cmax = 0;
  for (const auto& d : data.points) cmin = std::min(cmin, d.concentration), cmax = std::max(cmax, d.concentration);
  std::vector<Parameter> ps = o.parameters;
  if (ps.empty()) {
    if (signalling_scene(scene))
      ps = {{"r0", 0, 0}, {"kext", 0, 0}, {"a1b", 0, 0}};
    else
      ps = {{"gain", 0, 0}, {"kd", 0, 0}};
    if (o.fit_scale) ps.push_back({"scale", 0, 0});
  }
  for (auto& p : ps) {
    const SignalParameter* sp = signal_parameter(p.name);
    if (p.name == "gain" || p.name == "kd") {
      if (signalling_scene(scene) && scene.guidance.model != GuidanceModel::kSnr)
        throw InputError(fmt::format("fit: parameter {}: the base scene does not steer by the SNR model", p.name));
    } else if (p.name != "scale" && !sp) {
      std::string names = "gain, kd, scale";
      for (const auto& q : kSignalTable) names += std::string(", ") + q.name;
      throw InputError(fmt::format("fit: unknown parameter \"{}\" (the parameters are {})", p.name, names));
    } else if (sp && !signalling_scene(scene)) {
      throw InputError(fmt::format("fit: parameter {}: the base scene's axons.growth_model is not \"signalling\"",
                                   p.name));
    }
    if (p.lo == 0 && p.hi == 0) {
      if (p.name == "gain") p.lo = o.gain_lo, p.hi = o.gain_hi;
      else if (p.name == "kd") p.lo = o.kd_lo > 0 ? o.kd_lo : cmin / 10, p.hi = o.kd_hi > 0 ? o.kd_hi : cmax * 10;
      else if (p.name == "scale") p.lo = 0.1, p.hi = 10;
      else {
        const double v = sp->value > 0 ? sp->value : (p.name == "a1b" ? 0.01 : 1.0);
        p.lo = v / 10, p.hi = v * 10;
      }
    }
    if (!(p.lo > 0) || !(p.hi > p.lo) || !std::isfinite(p.hi))
      throw InputError(fmt::format("fit: parameter {}: range {} to {}: both must be > 0 and finite, the first below "
                                   "the second",
                                   p.name, p.lo, p.hi));
  }
  for (std::size_t a = 0; a < ps.size(); ++a)
    for (std::size_t b = 0; b < a; ++b)
      if (ps[a].name == ps[b].name) throw InputError(fmt::format("fit: parameter {} given twice", ps[a].name));
  return ps;
}

void predict(const json& base, const std::vector<std::pair<double, double>>& pts, const std::vector<Parameter>& ps,
             const Params& p, const Options& o, std::vector<double> (&mean)[kMeasures],
             std::vector<double> (&se)[kMeasures]) {
  std::size_t runs = 0;
  const Scene scene = parse_scene(base.dump(), "fit").scene;
  const std::string bias_metric =
      !o.bias_metric.empty() ? o.bias_metric : (scene.signalling() ? "outgrowth_bias" : "bias");
  const Evaluated ev = evaluate(base, pts, ps, {p}, o, o.seeds, bias_metric, runs);
  for (int m = 0; m < kMeasures; ++m) mean[m] = ev.mean[0][m], se[m] = ev.se[0][m];
}

double correction_factor(const Options& o, double steepness) {
  double f = 1.0;  // the last correction given for this steepness
  for (const auto& [s, factor] : o.corrections)
    if (std::fabs(steepness - s) <= 1e-9 * std::max(1.0, std::fabs(s))) f = factor;
  return f;
}

namespace {

// The options' ranges, for every caller (the command line's checks, and the Python module's
// arguments, which reach here unchecked).
void check_options(const Options& o) {
  auto bad = [](const std::string& what) { throw InputError("fit: " + what); };
  if (o.coarse < 2 || o.coarse > 50) bad(fmt::format("grid = {}: must be 2 to 50 points per parameter", o.coarse));
  if (o.refine_rounds < 0 || o.refine_rounds > 10) bad(fmt::format("refine = {}: must be 0 to 10", o.refine_rounds));
  if (o.polish_iterations < 0 || o.polish_iterations > 20) bad(fmt::format("polish = {}: must be 0 to 20", o.polish_iterations));
  if (!(o.target_se_ratio >= 0 && o.target_se_ratio <= 10))
    bad(fmt::format("target_se = {}: must be a number from 0 (off) to 10", o.target_se_ratio));
  if (o.max_seeds < 1 || o.max_seeds > 1000) bad(fmt::format("max_seeds = {}: must be 1 to 1000", o.max_seeds));
  if (o.seeds.size() > 1000) bad(fmt::format("{} seeds: at most 1000", o.seeds.size()));
  std::vector<std::uint64_t> sorted = o.seeds;
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t k = 1; k < sorted.size(); ++k)
    if (sorted[k] == sorted[k - 1])
      bad(fmt::format("seed {} is given twice (a repeated seed repeats its runs, and narrows the intervals)", sorted[k]));
  if (sorted.back() > std::numeric_limits<std::uint64_t>::max() - o.max_seeds)
    bad(fmt::format("seed {}: too large to add seeds after it (at most 2^64 - 1 - max_seeds)", sorted.back()));
  if (!(o.gain_lo > 0 && o.gain_hi >= o.gain_lo && std::isfinite(o.gain_hi)))
    bad(fmt::format("gain range {} to {}: both finite, > 0, the first not above the second", o.gain_lo, o.gain_hi));
  if (!(o.kd_lo >= 0 && o.kd_hi >= 0 && std::isfinite(o.kd_lo) && std::isfinite(o.kd_hi)) ||
      (o.kd_lo > 0 && o.kd_hi > 0 && !(o.kd_lo < o.kd_hi)))
    bad(fmt::format("kd range {} to {}: finite and > 0, the first below the second (0: from the data)", o.kd_lo,
                    o.kd_hi));
  for (const auto& [steepness, factor] : o.corrections)
    if (!(steepness >= 0 && std::isfinite(steepness) && factor > 0 && std::isfinite(factor)))
      bad(fmt::format("correction {} = {}: the steepness must be finite and >= 0, the factor finite and > 0", steepness,
                      factor));
}

}  // namespace

Result fit(const json& base, const std::string& origin, const Data& data, const Options& o) {
  const Scene scene = parse_scene(base.dump(), origin).scene;
  const bool steers = scene.guidance.model == GuidanceModel::kSnr;
  if (!(steers || scene.signalling()) || scene.cues.field != FieldKind::kImposed || scene.cues.sources.empty())
    throw InputError(fmt::format(
        "fit: {}: the base scene must be an explant in an imposed gradient (guidance.model \"snr\" or "
        "axons.growth_model \"signalling\", cues.field \"imposed\", at least one source in cues.sources)",
        origin));
  if (o.seeds.empty()) throw InputError("fit: at least one seed is needed");
  check_options(o);
  Result r;
  r.parameters = resolve_parameters(base, origin, data, o);
  r.bias_metric = !o.bias_metric.empty() ? o.bias_metric : (scene.signalling() ? "outgrowth_bias" : "bias");
  {
    const auto& names = assay::scalar_metric_names();
    if (std::find(names.begin(), names.end(), r.bias_metric) == names.end())
      throw InputError(fmt::format("fit: bias metric \"{}\" is not an assay metric", r.bias_metric));
  }
  // The modelled points: concentrations corrected per steepness.
  std::vector<std::pair<double, double>> pts;
  for (const auto& d : data.points) pts.emplace_back(d.concentration * correction_factor(o, d.steepness), d.steepness);
  for (std::size_t i = 0; i < data.points.size(); ++i)
    for (int m = 0; m < kMeasures; ++m)
      if (data.measured[m]) r.residuals.push_back({i, m});
  const std::size_t k = r.parameters.size();
  r.dof = static_cast<int>(r.residuals.size()) - static_cast<int>(k);
  if (r.dof < 1)
    throw InputError(fmt::format("fit: {} measured values for {} parameters: at least {} are needed",
                                 r.residuals.size(), k, k + 1));
  // The grids' sizes, n^k parameter sets a round, bounded before anything runs.
  constexpr std::size_t kMaxSets = 1000000;
  for (const int n : {o.coarse, o.refine_rounds > 0 ? 5 : 1}) {
    std::size_t sets = 1;
    for (std::size_t j = 0; j < k && sets <= kMaxSets; ++j)
      sets = sets > kMaxSets / static_cast<std::size_t>(n) ? kMaxSets + 1 : sets * static_cast<std::size_t>(n);
    if (sets > kMaxSets)
      throw InputError(fmt::format("fit: a grid of {}^{} parameter sets is more than {} (fewer parameters, or a "
                                   "smaller --grid)",
                                   n, k, kMaxSets));
  }
  std::vector<double> lo(k), hi(k);
  for (std::size_t j = 0; j < k; ++j) lo[j] = log_of(r.parameters[j].lo), hi[j] = log_of(r.parameters[j].hi);
  // Every data point must make a valid scene at both ends of the parameters' ranges: a bad
  // row is refused now, naming its line, not after the first batch of runs.
  {
    Params low(k), high(k);
    for (std::size_t j = 0; j < k; ++j) low[j] = r.parameters[j].lo, high[j] = r.parameters[j].hi;
    for (const Params& p : {low, high})
      for (const sweep::Spec& s : specs_for(base, pts, r.parameters, p, {1}, o.mirror, o.antithetic))
        for (std::size_t i = 0; i < pts.size(); ++i) {
          try {
            parse_scene(sweep::member_scene_json(s, i).dump(), origin);
          } catch (const InputError& e) {
            throw InputError(fmt::format("fit: data line {} (concentration {}, steepness {}) makes no valid model scene "
                                         "at {}: {}",
                                         data.points[i].line, data.points[i].concentration, data.points[i].steepness,
                                         describe(r.parameters, p), e.what()));
          }
        }
  }

  // The seeds. The grid and its refinements, which only locate the best, run on the first
  // two given seeds (the fewest an SE needs). At the grid's best the model is run on all the
  // given seeds (a measurement of the spread, not an evaluation), and the spread sets how
  // many seeds make its SE at most target x data SE at every point; the polish and the
  // intervals use those. `se_of(q)` is the model's SE of residual q on `n` seeds; the seeds
  // it asks for are at least 2 and at most max_seeds, the given seeds first.
  auto seeds_for = [&](auto se_of, std::size_t n) {
    double need = 2.0;
    for (std::size_t q = 0; q < r.residuals.size(); ++q) {
      const double se = se_of(q);
      if (!std::isfinite(se)) continue;
      const auto [i, m] = r.residuals[q];
      const double want = se * std::sqrt(static_cast<double>(n)) / (o.target_se_ratio * data.points[i].se[m]);
      need = std::max(need, std::ceil(want * want));
    }
    const std::size_t want = std::max<std::size_t>(2, std::min(static_cast<std::size_t>(std::min(need, 1e6)), o.max_seeds));
    std::vector<std::uint64_t> seeds = o.seeds;
    if (want < seeds.size()) seeds.resize(want);
    std::uint64_t next = *std::max_element(o.seeds.begin(), o.seeds.end()) + 1;
    while (seeds.size() < want) seeds.push_back(next++);
    return seeds;
  };
  const bool targeted = o.seeds.size() >= 2 && o.target_se_ratio > 0;
  r.seeds = o.seeds;
  if (targeted) r.seeds.resize(2);

  r.model_min.assign(r.residuals.size(), HUGE_VAL);
  r.model_max.assign(r.residuals.size(), -HUGE_VAL);
  r.chi2 = HUGE_VAL;
  // Evaluates parameter sets; appends each to r.evaluations (its chi2, model and model SE)
  // and returns the index of the first.
  auto score = [&](const std::vector<Params>& sets) {
    const Evaluated ev = evaluate(base, pts, r.parameters, sets, o, r.seeds, r.bias_metric, r.runs);
    const std::size_t first = r.evaluations.size();
    for (std::size_t e = 0; e < sets.size(); ++e) {
      double chi2 = 0;
      std::vector<double> model, model_se;
      for (std::size_t q = 0; q < r.residuals.size(); ++q) {
        const auto [i, m] = r.residuals[q];
        const double mu = ev.mean[e][m][i], s = ev.se[e][m][i], sd = data.points[i].se[m];
        const double d = data.points[i].value[m] - mu;
        chi2 += d * d / (sd * sd + s * s);
        model.push_back(mu);
        model_se.push_back(s);
        r.model_min[q] = std::min(r.model_min[q], mu);
        r.model_max[q] = std::max(r.model_max[q], mu);
      }
      if (!std::isfinite(chi2)) chi2 = kNaN;
      r.evaluations.push_back({sets[e], chi2, model, model_se});
    }
    if (o.on_evaluation) {
      double best = r.chi2;
      for (std::size_t e = first; e < r.evaluations.size(); ++e)
        if (r.evaluations[e].chi2 < best) best = r.evaluations[e].chi2;
      o.on_evaluation(r.evaluations.size(), best);
    }
    return first;
  };
  // Takes evaluation e as the best where it is lower (ties: the first evaluated).
  auto consider = [&](std::size_t e) {
    if (r.evaluations[e].chi2 < r.chi2) {
      r.chi2 = r.evaluations[e].chi2;
      r.best = r.evaluations[e].p;
      r.model = r.evaluations[e].model;
      r.model_se = r.evaluations[e].model_se;
    }
  };
  for (int round = 0; round <= o.refine_rounds; ++round) {
    const int n = round == 0 ? o.coarse : 5;
    std::vector<Params> sets;
    std::size_t total = 1;
    for (std::size_t j = 0; j < k; ++j) total *= static_cast<std::size_t>(n);
    for (std::size_t idx = 0; idx < total; ++idx) {
      Params p(k);
      std::size_t rest = idx;
      for (std::size_t j = k; j-- > 0;) {  // the first parameter slowest
        const int i = static_cast<int>(rest % static_cast<std::size_t>(n));
        rest /= static_cast<std::size_t>(n);
        p[j] = exp_of(n == 1 ? 0.5 * (lo[j] + hi[j]) : lo[j] + (hi[j] - lo[j]) * i / (n - 1));
      }
      sets.push_back(std::move(p));
    }
    const std::size_t first = score(sets);
    for (std::size_t e = first; e < r.evaluations.size(); ++e) consider(e);
    if (r.best.empty()) throw RunError("fit: no parameter set gave a defined model at every data point");
    // The next grid spans one step of this one on either side of the best point.
    for (std::size_t j = 0; j < k; ++j) {
      const double step = n > 1 ? (hi[j] - lo[j]) / (n - 1) : 0.0;
      const double c = log_of(r.best[j]);
      lo[j] = c - step;
      hi[j] = c + step;
    }
  }
  // The seeds at the grid's best: the model's spread over all the given seeds there sets the
  // seeds. Where they are more than the grid's, the best is evaluated again on them, and the
  // polish and the intervals go on from it using only evaluations on these seeds (a chi2 on
  // other seeds is not comparable); otherwise the grid's seeds stay.
  std::size_t same_seeds = 0;  // the first evaluation on the final seeds
  auto restart_on = [&](std::vector<std::uint64_t> seeds) {
    r.seeds = std::move(seeds);
    same_seeds = r.evaluations.size();
    const Params best = r.best;
    r.chi2 = HUGE_VAL;
    r.best.clear();
    consider(score({best}));
    if (r.best.empty())
      throw RunError(fmt::format("fit: the grid's best gave no defined model on {} seeds", r.seeds.size()));
  };
  if (targeted) {
    // With two seeds given, the grid's own evaluation of the best is the measurement.
    std::vector<std::uint64_t> need;
    if (o.seeds.size() > r.seeds.size()) {
      const Evaluated spread = evaluate(base, pts, r.parameters, {r.best}, o, o.seeds, r.bias_metric, r.runs);
      need = seeds_for([&](std::size_t q) { return spread.se[0][r.residuals[q].measure][r.residuals[q].point]; },
                       o.seeds.size());
    } else {
      need = seeds_for([&](std::size_t q) { return r.model_se[q]; }, r.seeds.size());
    }
    if (need.size() > r.seeds.size()) restart_on(std::move(need));
  }
  // The polish: Gauss-Newton in log parameters from the grid's best. Each iteration takes
  // the model's Jacobian J by forward differences (common seeds make them smooth), solves
  // (J'WJ) z = J'W (data - model), W = 1 / (se^2 + model se^2), limits z to the last
  // window, and keeps the step (or its half) only if chi2 falls; it stops when chi2 falls by
  // less than 0.1 %. J'WJ at the last point where J was taken (the best, or one step before
  // it when the last step converged) is the curvature A of chi2 ~ min + z'Az, which widens
  // the intervals below.
  std::vector<double> curvature;  // A^-1, k x k; empty where it could not be formed
  for (int it = 0; it <= o.polish_iterations && o.polish_iterations > 0; ++it) {
    const double delta = 0.02;
    std::vector<Params> probes;
    for (std::size_t j = 0; j < k; ++j) {
      Params p = r.best;
      p[j] = exp_of(log_of(p[j]) + delta);
      probes.push_back(p);
    }
    const std::size_t first = score(probes);
    std::vector<double> jac(r.residuals.size() * k), w(r.residuals.size());
    bool finite = true;
    for (std::size_t q = 0; q < r.residuals.size(); ++q) {
      const auto [i, m] = r.residuals[q];
      w[q] = 1.0 / (data.points[i].se[m] * data.points[i].se[m] + r.model_se[q] * r.model_se[q]);
      for (std::size_t j = 0; j < k; ++j) {
        jac[q * k + j] = (r.evaluations[first + j].model[q] - r.model[q]) / delta;
        finite = finite && std::isfinite(jac[q * k + j]);
      }
    }
    if (!finite) break;
    std::vector<double> a(k * k, 0.0), g(k, 0.0);
    for (std::size_t q = 0; q < r.residuals.size(); ++q) {
      const auto [i, m] = r.residuals[q];
      const double res = data.points[i].value[m] - r.model[q];
      for (std::size_t j = 0; j < k; ++j) {
        g[j] += jac[q * k + j] * w[q] * res;
        for (std::size_t l = 0; l < k; ++l) a[j * k + l] += jac[q * k + j] * w[q] * jac[q * k + l];
      }
    }
    curvature.assign(k * k, 0.0);
    for (std::size_t col = 0; col < k && !curvature.empty(); ++col) {
      std::vector<double> e(k, 0.0);
      e[col] = 1.0;
      if (!solve(a, e, k)) curvature.clear();
      else for (std::size_t j = 0; j < k; ++j) curvature[j * k + col] = e[j];
    }
    if (curvature.empty() || it == o.polish_iterations) break;
    std::vector<double> z = g;
    if (!solve(a, z, k)) break;
    double shrink = 1.0;  // within the last window (|z_j| <= its half width) and the searched range
    for (std::size_t j = 0; j < k; ++j) {
      const double half = 0.5 * (hi[j] - lo[j]);
      if (std::fabs(z[j]) > half && half > 0) shrink = std::min(shrink, half / std::fabs(z[j]));
      const double room = z[j] > 0 ? log_of(r.parameters[j].hi) - log_of(r.best[j])
                                   : log_of(r.best[j]) - log_of(r.parameters[j].lo);
      if (std::fabs(z[j]) > room) shrink = std::min(shrink, std::max(0.0, room) / std::fabs(z[j]));
    }
    if (!(shrink > 0)) break;
    const double chi2_before = r.chi2;
    for (double f : {shrink, 0.5 * shrink}) {
      Params p(k);
      for (std::size_t j = 0; j < k; ++j) p[j] = exp_of(log_of(r.best[j]) + f * z[j]);
      consider(score({p}));
      if (r.chi2 < chi2_before) break;
    }
    r.polished = r.polished || r.chi2 < chi2_before;
    if (!(r.chi2 < chi2_before - 1e-3 * std::max(1.0, chi2_before))) break;  // converged
  }
  r.chi2_per_dof = r.chi2 / r.dof;
  r.interval_delta = 3.84 * std::max(1.0, r.chi2_per_dof);
  // The profile of parameter j at log value x: the lowest chi2 over the others, from the
  // linearised conditional minimum (z_o = C_oj / C_jj dz_j, C = (J'WJ)^-1) and one
  // Gauss-Newton step of the others from there.
  auto profile_at = [&](std::size_t j, double x) {
    const double dz = x - log_of(r.best[j]);
    Params p0 = r.best;
    for (std::size_t l = 0; l < k; ++l)
      p0[l] = exp_of(l == j ? x : log_of(r.best[l]) + curvature[l * k + j] / curvature[j * k + j] * dz);
    const std::size_t e0 = score({p0});
    double lowest = r.evaluations[e0].chi2;
    if (k == 1 || !std::isfinite(lowest)) return lowest;
    const double delta = 0.02;
    std::vector<Params> probes;
    std::vector<std::size_t> others;
    for (std::size_t l = 0; l < k; ++l)
      if (l != j) {
        Params p = p0;
        p[l] = exp_of(log_of(p[l]) + delta);
        probes.push_back(p);
        others.push_back(l);
      }
    const std::size_t first = score(probes);
    const std::size_t ko = others.size();
    std::vector<double> a(ko * ko, 0.0), g(ko, 0.0);
    const Evaluation& at = r.evaluations[e0];
    for (std::size_t q = 0; q < r.residuals.size(); ++q) {
      const auto [i, m] = r.residuals[q];
      const double w = 1.0 / (data.points[i].se[m] * data.points[i].se[m] + at.model_se[q] * at.model_se[q]);
      const double res = data.points[i].value[m] - at.model[q];
      for (std::size_t u = 0; u < ko; ++u) {
        const double ju = (r.evaluations[first + u].model[q] - at.model[q]) / delta;
        g[u] += ju * w * res;
        for (std::size_t v = 0; v < ko; ++v)
          a[u * ko + v] += ju * w * (r.evaluations[first + v].model[q] - at.model[q]) / delta;
      }
    }
    for (std::size_t u = 0; u < ko; ++u) lowest = std::min(lowest, r.evaluations[first + u].chi2);
    if (!solve(a, g, ko)) return lowest;
    Params p1 = p0;
    for (std::size_t u = 0; u < ko; ++u) {
      const std::size_t l = others[u];
      const double z = std::max(log_of(r.parameters[l].lo), std::min(log_of(r.parameters[l].hi), log_of(p0[l]) + g[u]));
      p1[l] = exp_of(z);
    }
    const double c1 = r.evaluations[score({p1})].chi2;
    return std::min(lowest, c1);
  };
  for (std::size_t j = 0; j < k; ++j) {
    // The grid's profile over the evaluations on the final seeds, the earlier parameters'
    // profile trials included.
    const std::vector<Evaluation> comparable(r.evaluations.begin() + static_cast<std::ptrdiff_t>(same_seeds),
                                             r.evaluations.end());
    Interval iv = profile_interval(comparable, j, r.best[j], r.interval_delta);
    // Each side's crossing of min + Delta on the profile itself: from the linearised
    // half-width h = sqrt(Delta (J'WJ)^-1_jj), a step t -> t sqrt(Delta / dchi2(t)) (exact for
    // a parabola) until it moves by < 5 %, at most 4 profile points; a crossing beyond the
    // searched range leaves that side open at the edge. The grid's profile, which can only
    // be too narrow, is kept where it is wider.
    if (o.profile && !curvature.empty() && curvature[j * k + j] > 0) {
      const double zc = log_of(r.best[j]), h = std::sqrt(r.interval_delta * curvature[j * k + j]);
      for (int side : {-1, 1}) {
        const double edge = side < 0 ? log_of(r.parameters[j].lo) : log_of(r.parameters[j].hi);
        double t = side * h;
        bool open = false;
        for (int step = 0; step < 4; ++step) {
          if (side * (zc + t - edge) > 0) t = edge - zc;  // at most the edge
          const double d = profile_at(j, zc + t) - r.chi2;
          const bool at_edge = std::fabs(zc + t - edge) < 1e-12;
          if (!(d > 0)) {  // flat (or lower) here: look twice as far
            if (at_edge) { open = true; break; }
            t *= 2;
            continue;
          }
          double next = t * std::sqrt(r.interval_delta / d);
          if (std::fabs(next) > 4 * std::fabs(t)) next = 4 * t;
          if (at_edge && d < r.interval_delta) { open = true; break; }
          const bool done = std::fabs(next - t) < 0.05 * std::fabs(t);
          t = next;
          if (done) break;
        }
        if (side * (zc + t - edge) >= 0) t = edge - zc, open = true;
        if (side < 0) {
          iv.lo = std::min(iv.lo, exp_of(zc + t));
          iv.open_low = open;
        } else {
          iv.hi = std::max(iv.hi, exp_of(zc + t));
          iv.open_high = open;
        }
      }
      iv.profiled = true;
    }
    iv.best = r.best[j];
    // An open side ends at the searched range's edge (the data do not bound it there).
    if (iv.open_low) iv.lo = r.parameters[j].lo;
    if (iv.open_high) iv.hi = r.parameters[j].hi;
    iv.lo = std::min(iv.lo, iv.best);
    iv.hi = std::max(iv.hi, iv.best);
    r.intervals.push_back(iv);
  }
  for (std::size_t q = 0; q < r.residuals.size(); ++q) {
    const auto [i, m] = r.residuals[q];
    const double v = data.points[i].value[m], s = data.points[i].se[m];
    r.reachable.push_back(v + 2 * s >= r.model_min[q] && v - 2 * s <= r.model_max[q]);
    r.se_ratio_max = std::max(r.se_ratio_max, r.model_se[q] / s);
  }
  return r;
}

}  // namespace axg::fit

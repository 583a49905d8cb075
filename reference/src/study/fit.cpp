#include "axonguide/fit.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include <fmt/format.h>

#include "axonguide/assay.hpp"
#include "axonguide/csv.hpp"
#include "axonguide/core/pmath.hpp"
#include "axonguide/error.hpp"
#include "axonguide/sweep.hpp"

namespace axg::fit {

using nlohmann::json;

namespace {

double log_of(double x) { return core::pm::log(x); }
double exp_of(double x) { return core::pm::exp(x); }

}  // namespace

std::vector<DataPoint> load_data(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("fit: cannot read {}", path));
  std::stringstream text;
  text << in.rdbuf();
  return parse_data(text.str(), path);
}

std::vector<DataPoint> parse_data(const std::string& text, const std::string& path) {
  std::istringstream in(text);
  std::string line;
  std::size_t n = 0;
  std::map<std::string, std::size_t> col;
  std::vector<DataPoint> out;
  const char* names[] = {"concentration", "steepness", "bias", "se", "count"};
  while (std::getline(in, line)) {
    ++n;
    const std::string t = trim_cell(line);
    if (t.empty() || t[0] == '#') continue;
    const auto f = split_csv_line(t);
    if (col.empty()) {
      for (std::size_t k = 0; k < f.size(); ++k) col[f[k]] = k;
      for (const char* name : names)
        if (!col.count(name))
          throw InputError(fmt::format(
              "fit: {} line {}: the header must name the columns concentration, steepness, bias, se, count "
              "(missing \"{}\")",
              path, n, name));
      continue;
    }
    if (f.size() != col.size())
      throw InputError(fmt::format("fit: {} line {}: {} fields, the header has {}", path, n, f.size(), col.size()));
    double v[5];
    for (int k = 0; k < 5; ++k) {
      const std::string& s = f[col[names[k]]];
      std::size_t used = 0;
      try {
        v[k] = std::stod(s, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != s.size() || s.empty() || !std::isfinite(v[k]))
        throw InputError(fmt::format("fit: {} line {}: {} = \"{}\" is not a finite number", path, n, names[k], s));
    }
    if (!(v[0] > 0)) throw InputError(fmt::format("fit: {} line {}: concentration = {} must be > 0", path, n, v[0]));
    if (v[1] < 0) throw InputError(fmt::format("fit: {} line {}: steepness = {} must be >= 0", path, n, v[1]));
    if (!(v[3] > 0)) throw InputError(fmt::format("fit: {} line {}: se = {} must be > 0", path, n, v[3]));
    if (v[4] < 1 || v[4] != std::floor(v[4]))
      throw InputError(fmt::format("fit: {} line {}: count = {} must be an integer >= 1", path, n, v[4]));
    out.push_back({v[0], v[1], v[2], v[3], static_cast<std::uint64_t>(v[4]), n});
  }
  if (col.empty()) throw InputError(fmt::format("fit: {}: empty (a header and data rows are needed)", path));
  if (out.size() < 3) throw InputError(fmt::format("fit: {}: {} data rows; at least 3 are needed", path, out.size()));
  return out;
}

namespace {

sweep::Spec spec_for(const json& base, const std::vector<std::pair<double, double>>& pts, const Params& p,
                     const Options& o) {
  sweep::Spec s;
  s.base = base;
  s.base["guidance"]["gain"] = p.gain;
  for (auto& src : s.base["cues"]["sources"]) src["kd"] = p.kd;
  s.base_origin = "fit";
  s.zip = true;
  sweep::Parameter c{"concentration", {"cues.imposed.concentration"}, {}, {}};
  sweep::Parameter st{"steepness", {"cues.imposed.steepness"}, {}, {}};
  for (const auto& [conc, steep] : pts) {
    c.values.push_back(conc * p.scale);
    st.values.push_back(steep);
  }
  s.parameters = {c, st};
  s.seeds = o.seeds;
  return s;
}

// Runs every (parameter set, point, seed) of a round in one parallel loop; returns the
// mean and SE over seeds per parameter set and point.
void evaluate(const json& base, const std::vector<std::pair<double, double>>& pts, const std::vector<Params>& ps,
              const Options& o, std::vector<std::vector<double>>& mean, std::vector<std::vector<double>>& se,
              std::size_t& runs) {
  std::vector<sweep::Spec> specs;
  for (const Params& p : ps) specs.push_back(spec_for(base, pts, p, o));
  const std::size_t per = pts.size() * o.seeds.size();
  const std::vector<sweep::MemberResult> results = sweep::run_in_memory(specs, o.threads, o.run);
  for (std::size_t k = 0; k < results.size(); ++k)
    if (!results[k].ok)
      throw RunError(fmt::format("fit: the model run at gain {}, K_d {}, scale {} failed: {}", ps[k / per].gain,
                                 ps[k / per].kd, ps[k / per].scale, results[k].message));
  runs += results.size();
  const std::size_t S = o.seeds.size();
  mean.assign(ps.size(), std::vector<double>(pts.size()));
  se.assign(ps.size(), std::vector<double>(pts.size()));
  for (std::size_t e = 0; e < ps.size(); ++e)
    for (std::size_t i = 0; i < pts.size(); ++i) {
      std::vector<double> bias(S);
      for (std::size_t j = 0; j < S; ++j) bias[j] = sweep::metric(results[e * per + i * S + j], "bias");
      const sweep::MeanSe m = sweep::mean_se(bias);
      // An undefined bias (no axon grew) makes the point, and so the parameter set, undefined.
      mean[e][i] = m.n == S ? m.mean : std::numeric_limits<double>::quiet_NaN();
      se[e][i] = S > 1 ? m.se : 0.0;
    }
}

}  // namespace

void predict(const json& base, const std::vector<std::pair<double, double>>& pts, const Params& p, const Options& o,
             std::vector<double>& mean, std::vector<double>& se) {
  std::vector<std::vector<double>> m, s;
  std::size_t runs = 0;
  evaluate(base, pts, {p}, o, m, s, runs);
  mean = m[0];
  se = s[0];
}

Result fit(const json& base, const std::string& origin, const std::vector<DataPoint>& data, const Options& o) {
  const Scene scene = parse_scene(base.dump(), origin).scene;
  if (scene.guidance.model != GuidanceModel::kSnr || scene.cues.field != FieldKind::kImposed ||
      scene.cues.sources.empty())
    throw InputError(fmt::format(
        "fit: {}: the base scene must be an explant in an imposed gradient (guidance.model \"snr\", cues.field "
        "\"imposed\", at least one source in cues.sources)",
        origin));
  std::vector<std::pair<double, double>> pts;
  double cmin = HUGE_VAL, cmax = 0;
  for (const auto& d : data) {
    pts.emplace_back(d.concentration, d.steepness);
    cmin = std::min(cmin, d.concentration);
    cmax = std::max(cmax, d.concentration);
  }
  Result r;
  const int k = o.fit_scale ? 3 : 2;
  r.dof = static_cast<int>(data.size()) - k;
  if (r.dof < 1)
    throw InputError(fmt::format("fit: {} data rows for {} parameters: at least {} are needed", data.size(), k, k + 1));
  double lg[2] = {log_of(o.gain_lo), log_of(o.gain_hi)};
  double lk[2] = {log_of(o.kd_lo > 0 ? o.kd_lo : cmin / 10), log_of(o.kd_hi > 0 ? o.kd_hi : cmax * 10)};
  double ls[2] = {log_of(0.1), log_of(10.0)};
  r.model_min.assign(data.size(), HUGE_VAL);
  r.model_max.assign(data.size(), -HUGE_VAL);
  r.chi2 = HUGE_VAL;
  for (int round = 0; round <= o.refine_rounds; ++round) {
    const int n = round == 0 ? o.coarse : 5;
    const int ns = o.fit_scale ? n : 1;
    std::vector<Params> ps;
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b)
        for (int c = 0; c < ns; ++c) {
          auto at = [&](const double* l, int i, int m) { return m == 1 ? 0.5 * (l[0] + l[1]) : l[0] + (l[1] - l[0]) * i / (m - 1); };
          ps.push_back({exp_of(at(lg, a, n)), exp_of(at(lk, b, n)), o.fit_scale ? exp_of(at(ls, c, ns)) : 1.0});
        }
    std::vector<std::vector<double>> mean, se;
    evaluate(base, pts, ps, o, mean, se, r.runs);
    std::size_t best = 0;
    double best_chi2 = HUGE_VAL;
    for (std::size_t e = 0; e < ps.size(); ++e) {
      double chi2 = 0;
      for (std::size_t i = 0; i < data.size(); ++i) {
        const double d = data[i].bias - mean[e][i];
        chi2 += d * d / (data[i].se * data[i].se + se[e][i] * se[e][i]);
        r.model_min[i] = std::min(r.model_min[i], mean[e][i]);
        r.model_max[i] = std::max(r.model_max[i], mean[e][i]);
      }
      r.evaluations.push_back({ps[e], chi2, mean[e], se[e]});
      if (chi2 < best_chi2) {  // ties: the first evaluated
        best_chi2 = chi2;
        best = e;
      }
    }
    if (best_chi2 < r.chi2) {
      r.chi2 = best_chi2;
      r.best = ps[best];
      r.model = mean[best];
      r.model_se = se[best];
    }
    // The next grid spans one step of this one on either side of the best point.
    const auto narrow = [&](double* l, double centre, int m) {
      const double step = m > 1 ? (l[1] - l[0]) / (m - 1) : 0.0;
      l[0] = centre - step;
      l[1] = centre + step;
    };
    narrow(lg, log_of(r.best.gain), n);
    narrow(lk, log_of(r.best.kd), n);
    if (o.fit_scale) narrow(ls, log_of(r.best.scale), ns);
  }
  r.chi2_per_dof = r.chi2 / r.dof;
  for (std::size_t i = 0; i < data.size(); ++i)
    r.reachable.push_back(data[i].bias + 2 * data[i].se >= r.model_min[i] &&
                          data[i].bias - 2 * data[i].se <= r.model_max[i]);
  return r;
}

}  // namespace axg::fit

// `validate assay`: the explant assay of scenes/assay-explant.json (docs/methods.md §12.5)
// against what the literature and the model's own noise form require.
//  A. No-gradient control: steepness 0 at three concentrations; the bias must be within
//     its error of zero (t test per point, family-wise alpha).
//  B. Steepness (Yuan et al. 2013, Neural Comput 25:3055): at C = K_d the bias rises
//     linearly in shallow gradients (a line through the shallow points fits, lack-of-fit
//     chi2) and saturates in steep ones (between the two steepest points the bias rises
//     by less than a tenth of the shallow slope).
//  C. Peak concentration: for three steepnesses, the concentration of peak bias (a
//     parabola in log C through the three highest means, with a leave-one-seed-out
//     jackknife SE) must not move with the steepness and must lie where the scene's noise
//     form puts the peak of f(gamma) (snapshot: C = K_d; and, on a finer grid at one
//     steepness, binding: C = K_d / 2).
//  D. What the model cannot do: Bicknell et al. 2018 report a bias that falls to zero and
//     below at 10-100 nM. Under the SNR model the bias is never significantly negative at
//     high concentration; this is measured and reported, not hidden.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <gsl/gsl_cdf.h>

#include "axonguide/support/error.hpp"
#include "axonguide/support/resources.hpp"
#include "axonguide/study/sweep.hpp"
#include "axonguide/validate/validate.hpp"

namespace axg::validate {

namespace {

using nlohmann::json;
constexpr double kAlpha = 0.01;

struct Series {
  std::vector<double> x;                  // the swept value per point
  std::vector<std::vector<double>> bias;  // [point][seed]
};

double mean_of(const std::vector<double>& v) { return sweep::mean_se(v).mean; }
double se_of(const std::vector<double>& v) { return sweep::mean_se(v).se; }

// Runs the base scene at every (value of key, seed) and returns the bias per member.
Series run_series(const json& base, const std::vector<std::pair<std::string, json>>& fixed, const std::string& key,
                  const std::vector<double>& values, std::size_t seeds, int threads) {
  sweep::Spec spec;
  spec.base = base;
  for (const auto& [k, v] : fixed) {
    sweep::Parameter p{k, {k}, {v}, {}};
    spec.parameters.push_back(p);
  }
  sweep::Parameter p{key, {key}, {}, {}};
  for (double v : values) p.values.push_back(v);
  spec.parameters.push_back(p);
  for (std::size_t s = 1; s <= seeds; ++s) spec.seeds.push_back(s);
  const std::vector<sweep::MemberResult> results = sweep::run_in_memory({spec}, threads, {});
  std::vector<double> bias(results.size());
  for (std::size_t m = 0; m < results.size(); ++m) {
    if (!results[m].ok) throw RunError("validate assay: a run failed: " + results[m].message);
    bias[m] = sweep::metric(results[m], "bias");
  }
  Series s;
  s.x = values;
  for (std::size_t i = 0; i < values.size(); ++i)
    s.bias.emplace_back(bias.begin() + i * seeds, bias.begin() + (i + 1) * seeds);
  return s;
}

// log10 of the peak: a parabola in log10 x through the highest mean and its neighbours.
double peak_log10(const std::vector<double>& x, const std::vector<double>& m) {
  std::size_t k = 0;
  for (std::size_t i = 1; i < m.size(); ++i)
    if (m[i] > m[k]) k = i;
  k = std::clamp<std::size_t>(k, 1, m.size() - 2);
  const double x0 = std::log10(x[k - 1]), x1 = std::log10(x[k]), x2 = std::log10(x[k + 1]);
  const double y0 = m[k - 1], y1 = m[k], y2 = m[k + 1];
  const double den = (x0 - x1) * (x0 - x2) * (x1 - x2);
  const double a = (x2 * (y1 - y0) + x1 * (y0 - y2) + x0 * (y2 - y1)) / den;
  const double b = (x2 * x2 * (y0 - y1) + x1 * x1 * (y2 - y0) + x0 * x0 * (y1 - y2)) / den;
  if (!(a < 0)) return x1;
  return std::clamp(-b / (2 * a), x0, x2);
}

struct Peak {
  double log10c, se;
};
Peak peak_with_jackknife(const Series& s) {
  const std::size_t S = s.bias[0].size();
  std::vector<double> m(s.x.size());
  for (std::size_t i = 0; i < s.x.size(); ++i) m[i] = mean_of(s.bias[i]);
  Peak p{peak_log10(s.x, m), 0};
  std::vector<double> jk;
  for (std::size_t leave = 0; leave < S; ++leave) {
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      double t = 0;
      for (std::size_t j = 0; j < S; ++j)
        if (j != leave) t += s.bias[i][j];
      m[i] = t / static_cast<double>(S - 1);
    }
    jk.push_back(peak_log10(s.x, m));
  }
  const double jm = mean_of(jk);
  double ss = 0;
  for (double v : jk) ss += (v - jm) * (v - jm);
  p.se = std::sqrt(ss * static_cast<double>(S - 1) / static_cast<double>(S));
  return p;
}

}  // namespace

void validate_assay(const Options& o, Report& r) {
  const auto path = data_dir() / "scenes" / "assay-explant.json";
  std::ifstream in(path);
  if (!in) throw RunError(fmt::format("validate assay: cannot read {}", path.string()));
  std::stringstream ss;
  ss << in.rdbuf();
  json base = json::parse(ss.str());
  const std::uint64_t neurons = o.quick ? 500 : 1000;
  const std::size_t seeds = o.quick ? 8 : 20;
  base["neurons"]["populations"][0]["count"] = neurons;
  const Scene scene = parse_scene(base.dump(), path.string()).scene;
  const double kd = scene.cues.sources.at(0).kd;
  const bool snapshot = scene.guidance.noise == NoiseForm::kSnapshot;
  const double predicted_peak = snapshot ? kd : kd / 2;
  const int threads = o.threads;
  r.text(fmt::format(
      "The explant assay of `scenes/assay-explant.json` ({} neurons per explant, {} seeds per point; noise form "
      "`{}`, K_d = {} {}; directional bias = first sine Fourier coefficient of R(θ) / mean R, docs/methods.md §12.1). "
      "Every point is the mean over seeds with a Student-t 95 % CI; checks use family-wise α = {}.",
      neurons, seeds, name_of(scene.guidance.noise), kd, scene.units.concentration, kAlpha));

  // A. No gradient.
  r.heading("A. No-gradient control");
  const std::vector<double> control_c{0.01 * kd, kd, 100 * kd};
  const Series ctrl = run_series(base, {{"cues.imposed.steepness", 0.0}}, "cues.imposed.concentration", control_c,
                                 seeds, threads);
  std::vector<std::vector<std::string>> rows;
  bool control_ok = true;
  double worst_t = 0;
  const double t_bound = gsl_cdf_tdist_Pinv(1 - kAlpha / (2.0 * control_c.size()), static_cast<double>(seeds - 1));
  for (std::size_t i = 0; i < control_c.size(); ++i) {
    const double m = mean_of(ctrl.bias[i]), se = se_of(ctrl.bias[i]);
    const double t = m / se;
    worst_t = std::max(worst_t, std::fabs(t));
    control_ok = control_ok && std::fabs(t) <= t_bound;
    const double half = gsl_cdf_tdist_Pinv(0.975, static_cast<double>(seeds - 1)) * se;
    rows.push_back({num(control_c[i]), num(m), num(m - half), num(m + half), num(t, 3)});
  }
  r.table({"concentration", "bias", "CI low", "CI high", "t"}, rows, "assay_control.csv");
  r.check({"no gradient: bias within its error of zero at every concentration", control_ok,
           fmt::format("largest |t| = {:.2f}", worst_t), fmt::format("|t| <= {:.2f} (family-wise alpha {})", t_bound, kAlpha),
           fmt::format("{:.2f}", t_bound - worst_t)});

  // B. Steepness.
  r.heading("B. Bias against steepness at C = K_d (Yuan et al. 2013)");
  const std::vector<double> shallow{0.05, 0.1, 0.2, 0.3}, steep{1, 3, 10, 30};
  std::vector<double> all = shallow;
  all.insert(all.end(), steep.begin(), steep.end());
  const Series st = run_series(base, {{"cues.imposed.concentration", kd}}, "cues.imposed.steepness", all, seeds, threads);
  std::vector<double> xs, ys;
  for (std::size_t i = 0; i < shallow.size(); ++i) {
    xs.push_back(shallow[i]);
    ys.push_back(mean_of(st.bias[i]));
  }
  const Fit line = fit_line(xs, ys);
  double chi2 = 0;
  for (std::size_t i = 0; i < shallow.size(); ++i) {
    const double d = (ys[i] - (line.intercept + line.slope * xs[i])) / se_of(st.bias[i]);
    chi2 += d * d;
  }
  const double dof = static_cast<double>(shallow.size()) - 2;
  const double p_lof = gsl_cdf_chisq_Q(chi2, dof);
  rows.clear();
  for (std::size_t i = 0; i < all.size(); ++i) {
    const double m = mean_of(st.bias[i]), se = se_of(st.bias[i]);
    const double half = gsl_cdf_tdist_Pinv(0.975, static_cast<double>(seeds - 1)) * se;
    rows.push_back({num(all[i]), num(m), num(m - half), num(m + half), num(line.intercept + line.slope * all[i])});
  }
  r.table({"steepness (%/10 um)", "bias", "CI low", "CI high", "shallow line"}, rows, "assay_steepness.csv");
  r.check({"shallow gradients: bias linear in steepness (lack-of-fit chi2 of the line)", p_lof >= kAlpha && line.slope > 0,
           fmt::format("slope {:.4g} ± {:.2g} per %, chi2 {:.2f} on {} dof, p = {:.3f}", line.slope, line.slope_se, chi2,
                       dof, p_lof),
           fmt::format("p >= {} and slope > 0", kAlpha), fmt::format("p - alpha = {:.3f}", p_lof - kAlpha)});
  // Saturation: the slope between the two steepest points against the shallow slope.
  const std::size_t last = all.size() - 1;
  const double b_hi = mean_of(st.bias[last]), b_lo = mean_of(st.bias[last - 1]);
  const double se_d = std::sqrt(se_of(st.bias[last]) * se_of(st.bias[last]) + se_of(st.bias[last - 1]) * se_of(st.bias[last - 1]));
  const double steep_slope = (b_hi - b_lo) / (all[last] - all[last - 1]);
  const double steep_slope_hi = (b_hi - b_lo + 3 * se_d) / (all[last] - all[last - 1]);
  r.check({"steep gradients: bias saturates (slope between the two steepest points < 1/10 of the shallow slope)",
           steep_slope_hi < 0.1 * line.slope,
           fmt::format("bias {:.4f} at {} % and {:.4f} at {} %: slope {:.3g} per % (+3 SE: {:.3g}); shallow slope {:.3g}",
                       b_lo, all[last - 1], b_hi, all[last], steep_slope, steep_slope_hi, line.slope),
           "slope + 3 SE < 0.1 x shallow slope", fmt::format("{:.3g}", 0.1 * line.slope - steep_slope_hi)});
  r.plot("assay_steepness.py", {"assay_steepness.csv"}, "assay_steepness.png",
         "Directional bias against gradient steepness at C = K_d, with the line fitted to the shallow points.");

  // C. Peak concentration.
  r.heading("C. Concentration of peak bias against steepness");
  std::vector<double> conc;
  for (int k = -8; k <= 8; ++k) conc.push_back(kd * std::pow(10.0, k / 4.0));
  rows.clear();
  std::vector<std::vector<std::string>> curve;
  std::vector<Peak> peaks;
  const std::vector<double> steeps{0.1, 0.2, 0.3};
  for (double s : steeps) {
    const Series cs = run_series(base, {{"cues.imposed.steepness", s}}, "cues.imposed.concentration", conc, seeds, threads);
    const Peak p = peak_with_jackknife(cs);
    peaks.push_back(p);
    rows.push_back({num(s), num(std::pow(10.0, p.log10c)), num(p.log10c), num(p.se, 3),
                    num(p.log10c - std::log10(predicted_peak), 3)});
    for (std::size_t i = 0; i < conc.size(); ++i) {
      const double m = mean_of(cs.bias[i]), se = se_of(cs.bias[i]);
      const double half = gsl_cdf_tdist_Pinv(0.975, static_cast<double>(seeds - 1)) * se;
      curve.push_back({num(s), num(conc[i]), num(m), num(m - half), num(m + half)});
    }
  }
  r.table({"steepness", "peak C", "log10 peak", "jackknife SE", "minus log10 prediction"}, rows, "assay_peak.csv");
  r.csv("assay_concentration.csv", {"steepness", "concentration", "bias", "ci_low", "ci_high"}, curve);
  const double z = -gsl_cdf_ugaussian_Pinv(kAlpha / (2.0 * 3));
  bool where_ok = true, fixed_ok = true;
  double worst_where = 0, worst_move = 0;
  for (const Peak& p : peaks) {
    const double zz = std::fabs(p.log10c - std::log10(predicted_peak)) / std::max(p.se, 0.02);
    worst_where = std::max(worst_where, zz);
    where_ok = where_ok && zz <= z;
  }
  for (std::size_t i = 1; i < peaks.size(); ++i) {
    const double zz = std::fabs(peaks[i].log10c - peaks[0].log10c) /
                      std::max(std::sqrt(peaks[i].se * peaks[i].se + peaks[0].se * peaks[0].se), 0.02);
    worst_move = std::max(worst_move, zz);
    fixed_ok = fixed_ok && zz <= z;
  }
  r.check({fmt::format("peak at the noise form's optimum ({}: C = {} {})", name_of(scene.guidance.noise),
                       predicted_peak, scene.units.concentration),
           where_ok, fmt::format("largest |z| = {:.2f}", worst_where), fmt::format("|z| <= {:.2f} (SE floor 0.02 decade)", z),
           fmt::format("{:.2f}", z - worst_where)});
  r.check({"peak concentration does not move with steepness (0.1 vs 0.2 and 0.3 %)", fixed_ok,
           fmt::format("largest |z| = {:.2f}", worst_move), fmt::format("|z| <= {:.2f}", z),
           fmt::format("{:.2f}", z - worst_move)});
  // The other SNR form: binding noise peaks at C = K_d / 2. Its f is asymmetric in log C,
  // so the grid is finer (1/8 decade) to keep the three-point parabola's bias small.
  {
    json bbase = base;
    bbase["guidance"]["noise"] = "binding";
    std::vector<double> bconc;
    for (int k = -8; k <= 8; ++k) bconc.push_back(0.5 * kd * std::pow(10.0, k / 8.0));
    const Series bs = run_series(bbase, {{"cues.imposed.steepness", 0.2}}, "cues.imposed.concentration", bconc, seeds,
                                 threads);
    const Peak p = peak_with_jackknife(bs);
    const double zz = std::fabs(p.log10c - std::log10(0.5 * kd)) / std::max(p.se, 0.02);
    r.table({"noise", "steepness", "peak C", "log10 peak", "jackknife SE", "minus log10(K_d/2)"},
            {{"binding", "0.2", num(std::pow(10.0, p.log10c)), num(p.log10c), num(p.se, 3),
              num(p.log10c - std::log10(0.5 * kd), 3)}},
            "assay_peak_binding.csv");
    r.check({fmt::format("binding noise: peak at C = K_d / 2 = {} {} (0.2 %)", 0.5 * kd, scene.units.concentration),
             zz <= z, fmt::format("|z| = {:.2f} (peak {:.4g})", zz, std::pow(10.0, p.log10c)),
             fmt::format("|z| <= {:.2f} (SE floor 0.02 decade)", z), fmt::format("{:.2f}", z - zz)});
  }
  r.plot("assay_concentration.py", {"assay_concentration.csv"}, "assay_concentration.png",
         "Directional bias against concentration for three steepnesses.");

  // D. High concentration: no sign reversal under SNR.
  r.heading("D. High concentration (Bicknell et al. 2018)");
  double lowest_t = HUGE_VAL;
  for (std::size_t k = 0; k < steeps.size(); ++k) {
    const double m = std::stod(curve[k * conc.size() + conc.size() - 1][2]);
    const double lo = std::stod(curve[k * conc.size() + conc.size() - 1][3]);
    const double half = m - lo;
    lowest_t = std::min(lowest_t, m / (half / gsl_cdf_tdist_Pinv(0.975, static_cast<double>(seeds - 1))));
  }
  r.text(fmt::format(
      "Bicknell et al. 2018 (PLoS Comput Biol 14:e1006218, Fig 2C, from the data of Mortimer et al. 2009) report a "
      "bias that falls to zero and below at 10-100 nM. At {} x K_d the SNR model's bias is never significantly "
      "negative (smallest t = {:.2f}): it falls toward zero, as f(γ) does, but cannot change sign. A reversal needs a "
      "mechanism the SNR model lacks, such as Bicknell et al.'s inhibitory cell-body signal.",
      conc.back() / kd, lowest_t));
  r.check({"model limitation recorded: no significant sign reversal at 100 K_d (the SNR bias is >= 0 in expectation)",
           lowest_t > -t_bound, fmt::format("smallest t = {:.2f}", lowest_t), fmt::format("t > -{:.2f}", t_bound),
           fmt::format("{:.2f}", lowest_t + t_bound)});
}

}  // namespace axg::validate

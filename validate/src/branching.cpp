// `validate branching`: the branching and elongation rules of core/branching.hpp (the BESTL
// model; docs/methods.md §2.11) against the model's exact results, through the tree process
// of morphology/tree_process.hpp (the per-step rule, cone keys and draws an arbour engine uses).
//  A. The number of terminal segments of the BE model (S = 0, infinite tau) after N time
//     bins, against van Pelt et al.'s recursion (1997) evaluated at the same bins with the
//     same per-bin probability: a chi-square goodness-of-fit test on >= 10^4 trees for three
//     (B, E). Beside it, the recursion with van Pelt's own per-bin probability B n^(-E) / N,
//     and both against the limit of many bins.
//  B. Convergence in dt: the recursion's exact mean at N = 5 ... 160 bins against its limit
//     (first order), and the simulated mean at each N within its CI of the recursion's.
//  C. E = 0: the Yule process. Constant rate: n(T) is geometric with p = e^(-B); with a
//     finite tau, p = e^(-B (1 - e^(-T/tau))). Chi-square goodness of fit at fine bins.
//  D. Elongation (E = F = 0, constant rate lambda = B/T, speed v): the pooled mean terminal
//     segment length v (1 - e^(-2 lambda T)) / (2 lambda) and the mean total length
//     v (e^(lambda T) - 1) / lambda, against their values at N = 20 ... 2000 bins.
//  E. Cue-steered arbours (the arbour engine): scenes/culture.json in the explant assay's
//     imposed gradient, its cones steered by the continuum rule (T = 1 h). The axon
//     terminals' guidance cosine, their count and the axon length as dt is refined from
//     1 h to 1/8 h, beside the same culture under direct guidance (the control).
//  F. Lateral (interstitial) branching alone (B = 0, F = 0): the mean cone count against
//     the linear process's exact discrete recursion at the same dt, and the recursion
//     against its limit cosh(sqrt(lambda v0) T) as dt is refined (first order).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <numeric>

#include <fmt/format.h>
#include <gsl/gsl_cdf.h>

#include "axonguide/engine/run.hpp"
#include "axonguide/morphology/tree_process.hpp"
#include "axonguide/scene/scene.hpp"
#include "axonguide/support/resources.hpp"
#include "axonguide/study/sweep.hpp"
#include "axonguide/validate/validate.hpp"

namespace axg::validate {

namespace {

constexpr double kAlpha = 0.01;

// van Pelt's recursion: P(n) after N bins from one segment, each of the n terminal segments
// branching independently with probability q(n) per bin. Truncated at nmax (the rest of the
// mass is returned in the last entry).
std::vector<double> recursion(int bins, int nmax, const std::function<double(int)>& q) {
  std::vector<double> p(nmax + 1, 0.0), next(nmax + 1);
  p[1] = 1.0;
  std::vector<double> lf(2 * nmax + 2);
  for (std::size_t k = 1; k < lf.size(); ++k) lf[k] = lf[k - 1] + std::log(double(k));
  for (int i = 0; i < bins; ++i) {
    std::fill(next.begin(), next.end(), 0.0);
    for (int m = 1; m <= nmax; ++m) {
      if (p[m] == 0.0) continue;
      if (m == nmax) {
        next[nmax] += p[m];
        continue;
      }
      const double qm = q(m);
      for (int j = 0; j <= m; ++j) {
        const double lb = lf[m] - lf[j] - lf[m - j] + (j ? j * std::log(qm) : 0.0) +
                          (m - j ? (m - j) * std::log1p(-qm) : 0.0);
        next[std::min(m + j, nmax)] += p[m] * std::exp(lb);
      }
    }
    p.swap(next);
  }
  return p;
}

double mean_of(const std::vector<double>& p) {
  double m = 0;
  for (std::size_t n = 1; n < p.size(); ++n) m += double(n) * p[n];
  return m;
}

struct Gof {
  double chi2;
  int dof;
  double p;
};

// Pearson's chi-square of observed counts of n = 1, 2, ... against probabilities p(n),
// bins pooled from the top until every expected count is >= 5.
Gof goodness_of_fit(const std::vector<int>& values, const std::vector<double>& p) {
  const double total = static_cast<double>(values.size());
  std::vector<double> expected, observed;
  std::vector<double> obs(p.size(), 0.0);
  for (int v : values) obs[std::min<std::size_t>(v, p.size() - 1)] += 1;
  double e_acc = 0, o_acc = 0;
  for (std::size_t n = 1; n < p.size(); ++n) {
    e_acc += total * p[n];
    o_acc += obs[n];
    if (e_acc >= 5 && total * (1.0 - std::accumulate(p.begin(), p.begin() + n + 1, 0.0)) >= 5) {
      expected.push_back(e_acc), observed.push_back(o_acc);
      e_acc = o_acc = 0;
    }
  }
  // The tail, with whatever is left.
  e_acc = total - std::accumulate(expected.begin(), expected.end(), 0.0);
  o_acc = total - std::accumulate(observed.begin(), observed.end(), 0.0);
  expected.push_back(e_acc), observed.push_back(o_acc);
  double chi2 = 0;
  for (std::size_t k = 0; k < expected.size(); ++k)
    chi2 += (observed[k] - expected[k]) * (observed[k] - expected[k]) / expected[k];
  const int dof = static_cast<int>(expected.size()) - 1;
  return {chi2, dof, gsl_cdf_chisq_Q(chi2, dof)};
}

std::vector<int> terminals(const std::vector<morphology::TreeOutcome>& o) {
  std::vector<int> v;
  for (const auto& t : o) v.push_back(t.terminals);
  return v;
}

sweep::MeanSe mean_se_of(const std::vector<int>& v) {
  std::vector<double> d(v.begin(), v.end());
  return sweep::mean_se(d);
}

morphology::TreeProcess be_process(double b, double e, int bins, std::uint64_t seed) {
  morphology::TreeProcess p;
  p.branching.b_inf = b;
  p.branching.e = e;
  p.branching.period = 1.0;
  p.dt = 1.0 / bins;
  p.steps = static_cast<std::uint32_t>(bins);
  p.seed = seed;
  return p;
}

}  // namespace

void validate_branching(const Options& o, Report& r) {
  const std::uint32_t trees = o.quick ? 4000 : 20000;
  const int nmax = o.quick ? 200 : 400;
  const int limit_bins = o.quick ? 2000 : 4000;  // the limit of many bins
  r.text(fmt::format(
      "The branching rule of `core/branching.hpp` (BESTL: van Pelt, Dityatev & Uylings 1997, J Comp Neurol 387:325; "
      "van Pelt & Uylings 2002, Network 13:261) grown by the tree process of `morphology/tree_process.hpp`, {} trees "
      "per case{}. Per step a cone branches with probability 1 − exp(−x), x = ∫D dt · n^(−E) 2^(−Sγ) / C; checks "
      "at family-wise α = {}.",
      trees, o.quick ? " (--quick)" : "", kAlpha));

  // A and B. The BE model against van Pelt's recursion.
  struct Case {
    double b, e;
  };
  const std::vector<Case> cases{{2.5, 0.5}, {4.0, 0.3}, {1.0, 0.8}};
  const int bins = 10;
  r.heading("A. Terminal segments of the BE model against van Pelt's recursion, at the same 10 bins");
  std::vector<std::vector<std::string>> rows;
  std::vector<std::vector<std::string>> dist;
  const double per_test = kAlpha / (cases.size() + 2);
  bool all_fit = true;
  double worst_p = 1;
  for (std::size_t c = 0; c < cases.size(); ++c) {
    const auto [b, e] = cases[c];
    const auto ours = [&](double bb, double ee, int nb) {
      return [=](int n) { return 1.0 - std::exp(-bb / nb * std::pow(double(n), -ee)); };
    };
    const auto vanpelt = [&](int nb) { return [=](int n) { return std::min(1.0, b / nb * std::pow(double(n), -e)); }; };
    const std::vector<double> exact = recursion(bins, nmax, ours(b, e, bins));
    const std::vector<double> original = recursion(bins, nmax, vanpelt(bins));
    const std::vector<double> limit = recursion(limit_bins, nmax, ours(b, e, limit_bins));
    const auto sim = terminals(morphology::grow_trees(be_process(b, e, bins, 100 + c), trees));
    const Gof g = goodness_of_fit(sim, exact);
    const auto ms = mean_se_of(sim);
    all_fit = all_fit && g.p >= per_test;
    worst_p = std::min(worst_p, g.p);
    rows.push_back({fmt::format("{}", b), fmt::format("{}", e), fmt::format("{:.4f} ± {:.4f}", ms.mean, ms.se),
                    fmt::format("{:.4f}", mean_of(exact)), fmt::format("{:.4f}", mean_of(original)),
                    fmt::format("{:.4f}", mean_of(limit)), fmt::format("{:.1f} on {}", g.chi2, g.dof),
                    fmt::format("{:.3f}", g.p)});
    std::vector<int> counts(nmax + 1, 0);
    for (int v : sim) ++counts[std::min(v, nmax)];
    for (int n = 1; n <= 40; ++n)
      dist.push_back({fmt::format("{}", b), fmt::format("{}", e), std::to_string(n),
                      fmt::format("{:.6g}", double(counts[n]) / trees), fmt::format("{:.6g}", exact[n]),
                      fmt::format("{:.6g}", limit[n])});
  }
  r.table({"B", "E", "simulated mean n", "recursion, same bins", "recursion, van Pelt's B n^(-E)/N", fmt::format("limit ({} bins)", limit_bins),
           "χ² (same bins)", "p"},
          rows, "branching_recursion.csv");
  r.csv("branching_distribution.csv", {"B", "E", "n", "simulated", "recursion", "limit"}, dist);
  r.check({"the BE model's terminal-segment distribution is van Pelt's recursion at the same bins (3 cases)", all_fit,
           fmt::format("smallest p = {:.4f}", worst_p), fmt::format("every p ≥ {:.4f}", per_test),
           fmt::format("{:+.4f}", worst_p - per_test)});

  r.heading("B. Convergence in dt: the mean number of terminal segments against the number of bins");
  {
    const auto [b, e] = cases[0];
    const auto ours = [&](int nb) { return [=](int n) { return 1.0 - std::exp(-b / nb * std::pow(double(n), -e)); }; };
    const double limit = mean_of(recursion(limit_bins, nmax, ours(limit_bins)));
    std::vector<std::vector<std::string>> t;
    std::vector<double> errs;
    bool within = true;
    double worst_z = 0;
    for (int nb : {5, 10, 20, 40, 80, 160}) {
      const double exact = mean_of(recursion(nb, nmax, ours(nb)));
      const auto ms = mean_se_of(terminals(morphology::grow_trees(be_process(b, e, nb, 200 + nb), trees)));
      const double z = (ms.mean - exact) / ms.se;
      worst_z = std::max(worst_z, std::fabs(z));
      within = within && std::fabs(z) <= 3.14;
      errs.push_back(exact - limit);
      t.push_back({std::to_string(nb), fmt::format("{:.5f}", exact), fmt::format("{:+.5f}", exact - limit),
                   fmt::format("{:.4f} ± {:.4f}", ms.mean, ms.se), fmt::format("{:+.2f}", z)});
    }
    r.table({"bins N", "recursion mean", "minus the limit", "simulated mean", "z (simulated − recursion)"}, t,
            "branching_convergence.csv");
    // Observed order between the two finest: log2 of the error ratio.
    const double order = std::log2(errs[errs.size() - 2] / errs.back());
    r.text(fmt::format("B = {}, E = {}; limit ({} bins) {:.5f}. The error halves with the bin width: observed order "
                       "{:.2f} between 80 and 160 bins.",
                       b, e, limit_bins, limit, order));
    r.check({"refining dt converges at first order (the recursion's exact error, 80 → 160 bins)",
             order > 0.8 && order < 1.2, fmt::format("order {:.3f}", order), "0.8 < order < 1.2",
             fmt::format("{:.3f}", std::min(order - 0.8, 1.2 - order))});
    r.check({"at every N the simulated mean is the recursion's (6 bin counts)", within,
             fmt::format("largest |z| = {:.2f}", worst_z), "|z| ≤ 3.14 (Bonferroni over 6 at α = 0.01)", fmt::format("{:.2f}", 3.14 - worst_z)});
  }

  // C. Yule.
  r.heading("C. E = 0: the Yule process");
  {
    const int fine = o.quick ? 1000 : 4000;
    std::vector<std::vector<std::string>> t;
    bool ok = true;
    double worst = 1;
    for (int finite = 0; finite < 2; ++finite) {
      morphology::TreeProcess p = be_process(2.0, 0.0, fine, 300 + finite);
      double lambda_t = 2.0;
      if (finite) {
        p.branching.b_inf = 3.0;
        p.branching.tau = 0.5;
        lambda_t = 3.0 * (1.0 - std::exp(-1.0 / 0.5));
      }
      const auto sim = terminals(morphology::grow_trees(p, trees));
      std::vector<double> geo(nmax + 1, 0.0);
      const double q = std::exp(-lambda_t);
      for (int n = 1; n <= nmax; ++n) geo[n] = q * std::pow(1 - q, n - 1);
      const Gof g = goodness_of_fit(sim, geo);
      const auto ms = mean_se_of(sim);
      ok = ok && g.p >= per_test;
      worst = std::min(worst, g.p);
      t.push_back({finite ? "B∞ = 3, τ = T/2" : "B = 2, τ infinite", fmt::format("{:.4f}", lambda_t),
                   fmt::format("{:.4f} ± {:.4f}", ms.mean, ms.se), fmt::format("{:.4f}", std::exp(lambda_t)),
                   fmt::format("{:.1f} on {}", g.chi2, g.dof), fmt::format("{:.3f}", g.p)});
    }
    r.table({"case", "Λ(T)", "simulated mean n", "e^Λ", "χ² against the geometric", "p"}, t, "branching_yule.csv");
    r.text(fmt::format("{} bins. With E = 0 each cone branches at D(t) alone, so n(T) is geometric with p = e^(−Λ), "
                       "Λ = ∫D dt.",
                       fine));
    r.check({"E = 0 gives the Yule process's geometric distribution (constant and decaying rate)", ok,
             fmt::format("smallest p = {:.4f}", worst), fmt::format("every p ≥ {:.4f}", per_test),
             fmt::format("{:+.4f}", worst - per_test)});
  }

  // D. Elongation.
  r.heading("D. Elongation: terminal segment length and total length (E = F = 0, B = 2, v = 1, T = 1)");
  {
    const double lambda = 2.0, v = 1.0;
    const double want_term = v * (1 - std::exp(-2 * lambda)) / (2 * lambda);
    const double want_total = v * (std::exp(lambda) - 1) / lambda;
    std::vector<std::vector<std::string>> t;
    double last_z = 0;
    std::vector<int> levels{20, 100, 500, 2000};
    if (o.quick) levels = {20, 100, 500};
    for (int nb : levels) {
      morphology::TreeProcess p = be_process(2.0, 0.0, nb, 400 + nb);
      p.elongation.v0 = v;
      const auto out = morphology::grow_trees(p, trees);
      // The pooled ratio sum(terminal length) / sum(terminals), its SE by the delta method.
      double sl = 0, sn = 0;
      std::vector<double> total;
      for (const auto& x : out) sl += x.terminal_length, sn += x.terminals, total.push_back(x.total_length);
      const double ratio = sl / sn, m = static_cast<double>(out.size());
      double var = 0;
      for (const auto& x : out) {
        const double d = x.terminal_length - ratio * x.terminals;
        var += d * d;
      }
      const double ratio_se = std::sqrt(var / (m - 1) / m) / (sn / m);
      const auto tot = sweep::mean_se(total);
      last_z = std::max(std::fabs(ratio - want_term) / ratio_se, std::fabs(tot.mean - want_total) / tot.se);
      t.push_back({std::to_string(nb), fmt::format("{:.5f} ± {:.5f}", ratio, ratio_se),
                   fmt::format("{:+.5f}", ratio - want_term), fmt::format("{:.4f} ± {:.4f}", tot.mean, tot.se),
                   fmt::format("{:+.4f}", tot.mean - want_total)});
    }
    r.table({"bins N", "mean terminal segment length", "minus the model's", "mean total length", "minus the model's"}, t,
            "branching_elongation.csv");
    r.text(fmt::format("The model: terminal {:.5f} = v (1 − e^(−2λT))/(2λ) (pooled over trees), total {:.4f} = v "
                       "(e^(λT) − 1)/λ. A cone elongates, then may branch, in each step: the lengths' first-order "
                       "error shrinks with the bins.",
                       want_term, want_total));
    r.check({"at the finest bins the elongation model's lengths are reproduced", last_z <= 3.0,
             fmt::format("largest |z| = {:.2f} at {} bins", last_z, levels.back()), "|z| ≤ 3",
             fmt::format("{:.2f}", 3.0 - last_z)});
  }
  // E. Cue-steered arbours.
  r.heading("E. Cue-steered arbours: guidance, terminals and length as dt is refined");
  {
    Scene base = load_scene_file((data_dir() / "scenes" / "culture.json").string()).scene;
    base.guidance.model = GuidanceModel::kSnr;
    base.guidance.noise = core::NoiseForm::kSnapshot;
    base.guidance.gain = 40;
    base.guidance.integration_time = 1.0;  // h
    base.guidance.growth_cone_width = 10;
    base.guidance.sensing_radius = 10;
    base.cues.field = FieldKind::kImposed;
    base.cues.imposed.direction = {1, 0, 0};
    base.cues.imposed.steepness = 1.0;  // % per 10 um: the steep end of Rosoff et al.'s (2004) assay
    Source attractant;
    attractant.position = core::Vec3{0, 0, 0};
    base.cues.sources = {attractant};
    const std::vector<double> dts = o.quick ? std::vector<double>{1.0, 0.5, 0.25} : std::vector<double>{1.0, 0.5, 0.25, 0.125};
    const int seeds = o.quick ? 3 : 8;
    struct Level {
      sweep::MeanSe cosine, control, terminals, length;
      double seconds;
    };
    // Every axon terminal's cosine between its displacement from the soma and the gradient
    // (+x), its neuron's axon terminals and axon length, pooled over the seeds.
    auto measure = [&](double dt, GuidanceModel model) {
      std::vector<double> cosine, terminals, length;
      double seconds = 0;
      for (int seed = 1; seed <= seeds; ++seed) {
        Scene s = base;
        s.seed = static_cast<std::uint64_t>(seed);
        s.dt = dt;
        s.steps = static_cast<std::uint32_t>(std::lround(120.0 / dt));  // 5 days
        s.guidance.model = model;
        RunOptions ro;
        const auto t0 = std::chrono::steady_clock::now();
        const RunResult res = run_scene(s, ro);
        seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        for (std::size_t i = 0; i < res.arbours.size(); ++i) {
          const morphology::Arbour& a = res.arbours[i];
          int n = 0, counted = 0;
          double sum = 0;
          for (const morphology::Cone& c : a.cones) {
            if (c.type != morphology::kAxonType || c.status == morphology::ConeStatus::kBranched) continue;
            ++n;
            const core::Vec3 d = c.tip - res.soma[i];
            const double len = std::sqrt(d.x * d.x + d.y * d.y);
            if (len > 1.0) sum += d.x / len, ++counted;
          }
          // A neuron's terminals share their tree: the neuron (its terminals' mean) is the unit.
          if (counted > 0) cosine.push_back(sum / counted);
          if (n > 0) terminals.push_back(static_cast<double>(n)), length.push_back(res.neurons.length[i]);
        }
      }
      return Level{sweep::mean_se(cosine), {}, sweep::mean_se(terminals), sweep::mean_se(length), seconds};
    };
    std::vector<Level> levels;
    std::vector<std::vector<std::string>> t;
    for (const double dt : dts) {
      Level l = measure(dt, GuidanceModel::kSnr);
      l.control = measure(dt, GuidanceModel::kDirect).cosine;
      t.push_back({fmt::format("{}", dt), fmt::format("{:.4f} ± {:.4f}", l.cosine.mean, l.cosine.se),
                   fmt::format("{:.4f} ± {:.4f}", l.control.mean, l.control.se),
                   fmt::format("{:.3f} ± {:.3f}", l.terminals.mean, l.terminals.se),
                   fmt::format("{:.1f} ± {:.1f}", l.length.mean, l.length.se), fmt::format("{:.2f}", l.seconds)});
      levels.push_back(l);
    }
    r.table({"dt (h)", "guidance cosine", "control (direct)", "axon terminals", "axon length (µm)", "run time (s)"}, t,
            "branching_guided_arbours.csv");
    const Level& a = levels[levels.size() - 2];
    const Level& b = levels.back();
    const double z_step = std::fabs(b.cosine.mean - a.cosine.mean) / std::hypot(a.cosine.se, b.cosine.se);
    const double z_cue = (b.cosine.mean - b.control.mean) / std::hypot(b.cosine.se, b.control.se);
    r.text(fmt::format(
        "`scenes/culture.json` ({} neurons, 5 days, {} seeds per level) in the explant assay's exponential gradient "
        "(1 % per 10 µm along +x; SNR model, snapshot noise, gain 40, T = 1 h, growth cone width and sensing radius "
        "10 µm): every cone steers by the axons' continuum rule. The cosine is each neuron's mean over its axon "
        "terminals farther than 1 µm from the soma (in the plane), averaged over neurons (a neuron's terminals share "
        "their tree, so the neuron is the unit of the SE); the control is the same culture under direct guidance (no cue). dt is numerical: between "
        "the two finest levels the cosine moves by z = {:.2f}; the cue's effect at the finest is z = {:.1f}. The "
        "terminal count keeps the BESTL rule's first-order dt error (§2.11).",
        base.neurons.count, seeds, z_step, z_cue));
    r.check({"the cones' guidance converges as dt is refined (the two finest levels agree)", z_step <= 3.0,
             fmt::format("|z| = {:.2f} between dt = {} and {} h", z_step, dts[dts.size() - 2], dts.back()), "|z| ≤ 3",
             fmt::format("{:.2f}", 3.0 - z_step)});
    r.check({"the steered cones grow up the gradient, against the control", z_cue >= 4.0,
             fmt::format("z = {:.1f} at dt = {} h", z_cue, dts.back()), "z ≥ 4", fmt::format("{:.1f}", z_cue - 4.0)});
  }
  // F. Lateral branching.
  r.heading("F. Lateral (interstitial) branching: the linear process");
  {
    const double lambda = 0.25, v0 = 1.0, horizon = 4.0;
    const double limit = std::cosh(std::sqrt(lambda * v0) * horizon);
    const std::uint32_t count = o.quick ? 1500 : 6000;
    std::vector<std::uint32_t> levels{10, 20, 40, 80};
    if (o.quick) levels = {10, 20, 40};
    std::vector<std::vector<std::string>> t;
    double worst_z = 0;
    std::vector<double> errs;
    std::size_t stopped = 0;
    for (const std::uint32_t steps : levels) {
      const double dt = horizon / steps;
      Scene s;
      s.seed = 900 + steps;
      s.steps = steps;
      s.dt = dt;
      s.neurons.count = count;
      s.neurons.radius = 80.0;  // the bounds, far from every cone: none stops (checked)
      s.neurons.populations = {Population{count, {0.0, 0.0, 0.0}, 40.0}};
      s.neurons.soma_radius = 0.01;
      s.guidance.model = GuidanceModel::kDirect;
      s.analysis.bfs_sources.clear();
      ArbourKeys a;
      a.stop_at_soma = false;
      a.sample_length = 0.3;
      a.axon.b = 0.0;
      a.axon.v0 = v0;
      a.axon.stems = {0.0, 1.0};
      a.axon.lateral_rate = lambda;
      s.arbours = a;
      RunOptions ro;
      const RunResult res = run_scene(s, ro);
      std::vector<double> cones;
      for (const morphology::Arbour& x : res.arbours) {
        cones.push_back(static_cast<double>(x.cones.size()));
        for (const morphology::Cone& c : x.cones) stopped += c.status != morphology::ConeStatus::kGrowing;
      }
      const sweep::MeanSe ms = sweep::mean_se(cones);
      double n = 1, length = 0;
      for (std::uint32_t k = 1; k <= steps; ++k) {
        length += v0 * dt * n;
        n += lambda * dt * length;
      }
      const double z = (ms.mean - n) / ms.se;
      worst_z = std::max(worst_z, std::fabs(z));
      errs.push_back(limit - n);
      t.push_back({std::to_string(steps), fmt::format("{}", dt), fmt::format("{:.4f} ± {:.4f}", ms.mean, ms.se),
                   fmt::format("{:.4f}", n), fmt::format("{:+.2f}", z), fmt::format("{:+.4f}", n - limit)});
    }
    r.table({"steps", "dt", "simulated mean cones", "exact discrete mean", "z", "discrete minus limit"}, t,
            "branching_lateral.csv");
    const double order = std::log2(errs[errs.size() - 2] / errs.back());
    r.text(fmt::format(
        "{} neurons of one straight axon stem each (B = 0, v0 = {}, no competition, rate factors 1), lateral branches "
        "at λ = {} per length per time, T = {}: the cone count n and the path length L obey n' = λL, L' = v0 n, so "
        "E n(T) = cosh(√(λ v0) T) = {:.4f}. In a step every cone moves, then Poisson(λ L dt) branches start along the "
        "path, which gives the exact discrete recursion n_k = n_(k−1) + λ dt L_k, L_k = L_(k−1) + v0 dt n_(k−1) for "
        "the mean. The recursion approaches the limit at observed order {:.2f}.",
        count, v0, lambda, horizon, limit, order));
    r.check({"the process stays linear: no cone stopped (bounds far away)", stopped == 0,
             fmt::format("{} cones stopped", stopped), "0", fmt::format("{}", stopped)});
    r.check({"the simulated mean cone count is the exact discrete recursion's at every dt", worst_z <= 3.0,
             fmt::format("largest |z| = {:.2f}", worst_z), "|z| ≤ 3", fmt::format("{:.2f}", 3.0 - worst_z)});
    r.check({"refining dt converges to cosh(√(λ v0) T) at first order", order > 0.8 && order < 1.2,
             fmt::format("order {:.3f}", order), "0.8 < order < 1.2",
             fmt::format("{:.3f}", std::min(order - 0.8, 1.2 - order))});
  }
  r.plot("branching_arbours.py", {"branching_guided_arbours.csv", "branching_lateral.csv"}, "branching_arbours.png",
         "Left (§E): the axon terminals' cosine to the gradient of cue-steered cultures against dt, beside the same "
         "culture under direct guidance. Right (§F): lateral branching's mean cone count against dt, simulated, the "
         "exact discrete recursion, and its limit.");
  r.plot("branching.py", {"branching_distribution.csv", "branching_convergence.csv"}, "branching.png",
         "Left: the distribution of terminal segments after 10 bins, simulated (points) against van Pelt's recursion at "
         "the same bins (lines) and its limit (dashed). Right: the recursion's mean against the number of bins, minus "
         "its limit (first order).");
}

}  // namespace axg::validate

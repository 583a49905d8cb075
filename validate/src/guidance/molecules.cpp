// `validate guidance` D: molecule-resolved counts; D2: the count dipole against the molecules.
#include "shared.hpp"

namespace axg::validate::guidance {

// ---- D. molecule-resolved counts ----------------------------------------------------------

void molecules(const Options& o, Report& r, AnalyticCache&) {
  r.heading("D. Molecule-resolved counts: the limit the estimate agrees with");
  const double m = 1e-3;
  const int seeds = o.quick ? 3 : 8;
  const double fine = o.quick ? 4 : 8;  // the estimate's amount is m / fine
  r.text(fmt::format(
      "The explant of C under the count form, with the scene saying what one molecule is: cues.molecule_amount = {} "
      "(so that a molecule-resolved run is affordable: about 12 molecules in a sensing ball at the explant). Three "
      "runs per seed (1..{}): the analytic field, whose count decision is the molecules' dipole in its Gaussian limit; "
      "molecule-resolved particles (cues.particles.molecules: one particle is one molecule, a = m, and the decision "
      "reads the particles within r with nothing added: their Poisson noise is the physical noise, exactly); and the "
      "particle estimate at a = m/{} with the physical noise of m drawn from it. Every run decides once per step "
      "(guidance.decision \"per_step\"): this compares what the growth cone senses at one instant; the noise of a "
      "decision integrated over T is checked against the molecules themselves below (D2). Criteria, fixed in advance: "
      "each paired gap within {:.2f} SE of zero (alpha = {} over the two comparisons).",
      m, seeds, fine, z_bound(2), kAlpha));
  auto scene_of = [&](std::uint64_t seed, int kind) {
    Resolution res;
    if (kind > 0) {
      res.field = FieldKind::kParticles;
      res.amount = kind == 1 ? m : m / fine;
    }
    Scene s = explant_scene(seed, core::NoiseForm::kCount, res);
    s.cues.molecule_amount = m;
    s.guidance.decision = DecisionRule::kPerStep;
    if (kind == 1) s.cues.particles.molecules = true;
    return s;
  };
  std::vector<std::vector<double>> idx[3], gap_mol_an, gap_est_mol;
  double secs[3] = {0, 0, 0};
  for (int sd = 1; sd <= seeds; ++sd) {
    std::vector<double> v[3];
    for (int kind = 0; kind < 3; ++kind) {
      const Timed t = timed_run(scene_of(static_cast<std::uint64_t>(sd), kind));
      v[kind] = explant_cosines(t.result);
      secs[kind] += t.seconds / seeds;
      idx[kind].push_back(v[kind]);
    }
    std::vector<double> a(v[0].size()), b(v[0].size());
    for (std::size_t i = 0; i < a.size(); ++i) a[i] = v[1][i] - v[0][i], b[i] = v[2][i] - v[1][i];
    gap_mol_an.push_back(a);
    gap_est_mol.push_back(b);
  }
  const std::string names[3] = {"analytic (Gaussian limit of the molecules)", "molecule-resolved particles (a = m)",
                                fmt::format("particle estimate (a = m/{})", fine)};
  std::vector<std::vector<std::string>> rows;
  for (int k = 0; k < 3; ++k) {
    const MeanSe i = clustered(idx[k]);
    rows.push_back({names[k], num(i.mean, 4), num(i.se, 2), num(secs[k], 3)});
  }
  r.table({"field", "index", "SE", "seconds per run"}, rows, "guidance_molecules.csv");
  const double zc = z_bound(2);
  const MeanSe g1 = clustered(gap_mol_an), g2 = clustered(gap_est_mol);
  r.check({"molecule-resolved particles = the analytic field's Gaussian limit (count)", std::fabs(g1.mean / g1.se) < zc,
           fmt::format("gap {:.4f} +- {:.4f} (z = {:.2f})", g1.mean, g1.se, g1.mean / g1.se), fmt::format("|z| < {:.2f}", zc),
           fmt::format("{:.2f} below the bound", zc - std::fabs(g1.mean / g1.se))});
  r.check({fmt::format("the particle estimate (a = m/{}) = molecule-resolved particles (count)", fine), std::fabs(g2.mean / g2.se) < zc,
           fmt::format("gap {:.4f} +- {:.4f} (z = {:.2f})", g2.mean, g2.se, g2.mean / g2.se), fmt::format("|z| < {:.2f}", zc),
           fmt::format("{:.2f} below the bound", zc - std::fabs(g2.mean / g2.se))});
}


namespace {

// ---- D2. the count dipole averaged over T, against the molecules -----------------------------

// The variance of the count dipole's mean over T (core::CueParams::dipole_variance, from the
// dipole's spectrum in dipole_mean_variance) against the molecules themselves: Poisson
// molecules are independent, so the dipole's autocorrelation is rho(s) = E[f(x) f(x + B_s)] /
// E[f^2] over x uniform in the ball, f(y) = y_z / r inside it and 0 outside, B_s a Brownian
// displacement of variance 2 D s per axis; Monte Carlo of rho on a grid of s, then
// v(T) = (2 / T) int_0^T (1 - s / T) rho(s) ds by the trapezoid rule.

}  // namespace

void dipole_correlation(const Options& o, Report& r) {
  r.heading("D2. The count dipole averaged over the integration time: the derivation against the molecules");
  const int samples = o.quick ? 20000 : 200000, grid = o.quick ? 48 : 96;
  r.text(fmt::format(
      "A counting growth cone's decision reads the dipole of the molecules in its ball averaged over T; its variance "
      "is the instantaneous C V / (5 m) times v(theta), theta = D T / r^2, which the model computes from the dipole's "
      "spectrum (dipole_mean_variance; 2 tau_d / T for T >> tau_d = 2 r^2 / (21 D)). Independent check: the dipole's "
      "autocorrelation rho(s) by Monte Carlo of single molecules ({} per lag, {} lags up to T, the lags denser at "
      "short times where rho falls fastest), and v = (2/T) int (1 - s/T) rho(s) ds. Criterion, fixed in advance: "
      "|v_MC - v| within 4 SE of the Monte Carlo (the quadrature's own error is below 1e-3 of v).",
      samples, grid));
  std::vector<std::vector<std::string>> rows;
  for (double theta : {0.02, 0.1, 0.5, 2.0}) {
    // Lags s_j = T (j / grid)^2 (denser near 0); rho at each by Monte Carlo.
    std::vector<double> lag(grid + 1), rho(grid + 1), var(grid + 1);
    for (int j = 0; j <= grid; ++j) {
      const double u = static_cast<double>(j) / grid;
      lag[j] = u * u;  // in units of T
      const double sigma = std::sqrt(2.0 * theta * lag[j]);  // per axis, in units of r
      double sum = 0, sum2 = 0;
      for (int i = 0; i < samples; ++i) {
        core::Rng rng(97, core::Stream::kValidation, static_cast<std::uint64_t>(i) + 1000000ull * j,
                      static_cast<std::uint32_t>(theta * 1000));
        Vec3 x;
        do {  // uniform in the unit ball
          x = {2 * rng.uniform() - 1, 2 * rng.uniform() - 1, 2 * rng.uniform() - 1};
        } while (core::norm2(x) > 1.0);
        double z0, z1, z2, unused;
        core::normal_pair(rng, &z0, &z1);
        core::normal_pair(rng, &z2, &unused);
        const Vec3 y = x + sigma * Vec3{z0, z1, z2};
        const double v = x.z * (core::norm2(y) <= 1.0 ? y.z : 0.0);
        sum += v, sum2 += v * v;
      }
      const double mean = sum / samples;
      rho[j] = mean / 0.2;  // E[f^2] = 1/5 over the ball
      var[j] = (sum2 / samples - mean * mean) / samples / 0.04;
    }
    double v = 0, v_var = 0;
    for (int j = 1; j <= grid; ++j) {  // trapezoid on s in [0, 1] (units of T)
      const double ds = lag[j] - lag[j - 1];
      const double a = 2 * (1 - lag[j - 1]) * 0.5 * ds, b = 2 * (1 - lag[j]) * 0.5 * ds;
      v += a * rho[j - 1] + b * rho[j];
    }
    // Its SE: the lags' Monte Carlo errors are independent (separate streams).
    for (int j = 0; j <= grid; ++j) {
      const double w = 2 * (1 - lag[j]) * 0.5 * ((j > 0 ? lag[j] - lag[j - 1] : 0) + (j < grid ? lag[j + 1] - lag[j] : 0));
      v_var += w * w * var[j];
    }
    const double se = std::sqrt(v_var), model = dipole_mean_variance(theta);
    const double z = (v - model) / se;
    rows.push_back({num(theta, 3), num(model, 5), num(v, 5), num(se, 2), num(z, 2)});
    r.check({fmt::format("dipole variance over T at theta = {}", theta), std::fabs(z) < 4.0,
             fmt::format("Monte Carlo {:.5f} +- {:.5f}, model {:.5f} (z = {:.2f})", v, se, model, z), "|z| < 4",
             fmt::format("{:.2f} below the bound", 4.0 - std::fabs(z))});
  }
  r.table({"theta = D T / r^2", "v (model)", "v (Monte Carlo)", "SE", "z"}, rows, "guidance_dipole_variance.csv");
}


}  // namespace axg::validate::guidance

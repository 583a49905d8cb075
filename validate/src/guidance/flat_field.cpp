// `validate guidance` A: the flat field (docs/methods.md §11.7).
#include "shared.hpp"

namespace axg::validate::guidance {

namespace {

// ---- A. flat field ----------------------------------------------------------------------

struct FlatDecision {
  bool turned[4];
  Vec3 side[4];
  bool has_own[4];
  bool toward_own[4];
};


}  // namespace

void flat_field(const Options& o, Report& r) {
  r.heading("A. Flat field: no direction, no information");
  const std::vector<double> per_cell{1, 4, 16, 64};
  const int n_dec = o.quick ? 4000 : 20000;
  const double gain = 250, h = 0.5, molecules = 100;
  const char* names[4] = {"estimate, binding", "estimate, count", "naive plug-in, binding", "naive plug-in, count"};
  const double rayleigh_tests = static_cast<double>(per_cell.size()) * 4;
  const double p_min = kAlpha / rayleigh_tests, zc = z_bound(2.0 * static_cast<double>(per_cell.size()));
  r.text(fmt::format(
      "Uniform Poisson particles (amount a = 1) around a tip placed uniformly in the central cell of a local mesh of "
      "spacing h = {} (the default estimate spacing, the sensing radius), deposited by core::cic_deposit into the two "
      "half meshes by id parity (one frame); heading h = z; nu particles per mesh cell in {{1, 4, 16, 64}}, K_d = 2 C "
      "(gamma = 1/2, the peak of the binding f), gain {}; for count a molecule amount that puts {} molecules in the "
      "sensing ball. {} independent decisions per nu: core::estimate_sample, then core::snr_steer. The naive plug-in "
      "takes direction and magnitude from the same estimate (the mean of both halves as grad and grad_check): the "
      "first version's error, here the negative control. The side vector is the new heading's part perpendicular to "
      "h, normalised; the estimated direction is the perpendicular part of the sample's grad.\n\nCriteria, fixed in "
      "advance: (i) Rayleigh p-value (2D, on the side vectors) above {:.2e} for every (nu, estimator), Bonferroni for "
      "alpha = {} over {} tests; (ii) the estimate, under binding and count: |z| = |P(toward own estimate) - 1/2| / "
      "sqrt(1/(4N)) below {:.3f} at every nu (alpha = {} over {} tests); (iii) the naive control must break (ii) at "
      "every nu.",
      h, gain, molecules, n_dec, p_min, kAlpha, rayleigh_tests, zc, kAlpha, 2 * per_cell.size()));
  std::vector<std::vector<std::string>> rows;
  bool rayleigh_ok = true, estimate_ok = true, naive_caught = true;
  double worst_p = 1, worst_est = 0, least_naive = HUGE_VAL;
  for (std::size_t ci = 0; ci < per_cell.size(); ++ci) {
    const double nu = per_cell[ci], a = 1.0;
    const double c0 = nu * a / (h * h * h);
    const core::CueParams cue = cue_with(2.0 * c0);
    const core::SenseParams sp = sense_with(c0 * kVolume / molecules);
    core::SteerParams pb = default_snr_params(core::NoiseForm::kBinding);
    pb.gain = gain;
    core::SteerParams pc = pb;
    pc.noise = core::NoiseForm::kCount;
    std::vector<FlatDecision> dec(static_cast<std::size_t>(n_dec));
    tbb::parallel_for(tbb::blocked_range<int>(0, n_dec), [&](const tbb::blocked_range<int>& br) {
      HalfMeshes m;
      m.h = h;
      for (int i = br.begin(); i != br.end(); ++i) {
        const Vec3 tip = draw_estimate(c0, a, 0.0, static_cast<std::uint64_t>(i), 100 + static_cast<std::uint32_t>(ci), m);
        const Vec3 hd{0, 0, 1};
        FlatDecision& d = dec[static_cast<std::size_t>(i)];
        const core::CueSample est = core::estimate_sample(tip, m.view, 0);
        const Vec3 both = 0.5 * (est.grad + est.grad_check);
        const core::CueSample naive{est.c, both, both};
        const core::CueSample* samples[4] = {&est, &est, &naive, &naive};
        const core::SteerParams* params[4] = {&pb, &pc, &pb, &pc};
        for (int e = 0; e < 4; ++e) {
          const auto step = static_cast<std::uint32_t>(4 * ci + static_cast<std::size_t>(e));
          const core::Steered st = core::snr_steer(hd, samples[e], &cue, 1, sp, *params[e], 5, static_cast<std::uint32_t>(i), step);
          const Vec3 side = perp_unit(st.heading, hd);
          d.turned[e] = core::norm2(side) > 0.5;
          d.side[e] = side;
          const Vec3 own = perp_unit(samples[e]->grad, hd);
          d.has_own[e] = core::norm2(own) > 0.5;
          d.toward_own[e] = core::dot(side, own) > 0.0;
        }
      }
    });
    for (int e = 0; e < 4; ++e) {
      std::vector<double> xy;
      int toward = 0, with_own = 0;
      for (const FlatDecision& d : dec)
        if (d.turned[e]) {
          xy.push_back(d.side[e].x);
          xy.push_back(d.side[e].y);
          if (d.has_own[e]) ++with_own, toward += d.toward_own[e];
        }
      const std::size_t m = xy.size() / 2;
      const auto mo = static_cast<double>(with_own);
      const TestResult ray = rayleigh(xy.data(), m, 2);
      double mx = 0, my = 0;
      for (std::size_t k = 0; k < m; ++k) mx += xy[2 * k], my += xy[2 * k + 1];
      const double rbar = m ? std::hypot(mx, my) / static_cast<double>(m) : 0.0;
      const double p = mo > 0 ? toward / mo : 0.0;
      const double se = mo > 0 ? std::sqrt(p * (1 - p) / mo) : 0.0;
      const double z = mo > 0 ? (p - 0.5) / std::sqrt(0.25 / mo) : 0.0;
      if (ray.p_value < p_min) rayleigh_ok = false;
      worst_p = std::min(worst_p, ray.p_value);
      if (e < 2) {
        if (std::fabs(z) >= zc) estimate_ok = false;
        worst_est = std::max(worst_est, std::fabs(z));
      } else {
        if (std::fabs(z) < zc) naive_caught = false;
        least_naive = std::min(least_naive, std::fabs(z));
      }
      rows.push_back({num(nu), names[e], num(c0, 4), std::to_string(m), num(rbar, 3), num(ray.statistic, 4),
                      num(ray.p_value, 3), num(p, 5), num(p - 1.96 * se, 5), num(p + 1.96 * se, 5), num(z, 3)});
    }
  }
  r.table({"nu", "estimator", "C", "turned", "R", "Rayleigh 2nR^2", "Rayleigh p", "P(toward own)", "CI low", "CI high",
           "z vs 1/2"},
          rows, "guidance_flat.csv");
  r.check({"flat field: no preferred turn direction (every nu, every estimator)", rayleigh_ok,
           fmt::format("smallest Rayleigh p = {:.3g}", worst_p), fmt::format("p > {:.2e}", p_min),
           fmt::format("{:.3g}x the bound", worst_p / p_min)});
  r.check({"flat field, the estimate (binding and count): P(turn toward own estimate) = 1/2 (zero information)",
           estimate_ok, fmt::format("max |z| = {:.3f}", worst_est), fmt::format("|z| < {:.3f}", zc),
           fmt::format("{:.2f} below the bound", zc - worst_est)});
  r.check({"flat field, naive plug-in control is caught: P(toward own estimate) != 1/2 at every nu", naive_caught,
           fmt::format("smallest |z| = {:.3g}", least_naive), fmt::format("|z| >= {:.3f}", zc),
           fmt::format("{:.3g}x the bound", least_naive / zc)});
  r.plot("guidance_flat.py", {"guidance_flat.csv"}, "guidance_flat.png",
         "Flat field: P(turn toward the growth cone's own estimated direction) against the particles per mesh cell, "
         "with 95 % CIs (left), and the Rayleigh p-value of the turn sides (right, dotted: the Bonferroni bound).");
}


}  // namespace axg::validate::guidance

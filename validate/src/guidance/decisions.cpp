// `validate guidance` B: decisions in a linear gradient.
#include "shared.hpp"

namespace axg::validate::guidance {

namespace {

// ---- B. decisions in a linear gradient ---------------------------------------------------

struct Cell {
  std::string form;
  double snr = 0, nu = 0, b = 0;
  int decisions = 0;
  double expect = 0, p_rb = 0, se_rb = 0, p_emp = 0, consistency_z = 0;
};

// The probability, given the sample, that the decision ends toward +x (h = z): binding turns
// along +u (u the unit of grad's perpendicular part) with probability Phi(e), e = weight
// (grad_check . u); count turns toward the perpendicular part of D = s g + sigma z, whose x
// component is positive with probability Phi(s g_x / sigma).
double toward_probability(const core::CueSample& s, const core::CueParams& cue, const core::SenseParams& sp,
                          const core::SteerParams& p, Vec3 h) {
  if (!core::detected(s, cue)) return 0.0;
  if (p.noise == core::NoiseForm::kCount) {
    const Vec3 g = core::decision_gradient(s);
    const double sigma = std::sqrt(sp.count_var_scale * s.c);
    return phi(cue.sign * sp.count_mean_scale * g.x / sigma);
  }
  const Vec3 u = perp_unit(s.grad, h);
  const double weight = cue.sign * p.gain * sp.cone_width / s.c * core::receptor_noise(s.c / cue.kd, p.noise);
  const double e = weight * core::dot(s.grad_check, u);
  if (!(std::fabs(e) >= core::kParallelSin) || core::norm2(u) == 0.0) return 0.5;
  return u.x > 0 ? phi(e) : 1.0 - phi(e);
}


}  // namespace

void decision_convergence(const Options& o, Report& r) {
  r.heading("B. Decisions in a linear gradient: convergence to the exact field's decision");
  const std::vector<double> snrs{0.5, 1.0};
  std::vector<double> per_cell{16, 64, 256, 1024};
  if (o.quick) per_cell.pop_back();
  // (y - tip).x reaches +-4h in the particles' cube, so b 4h < 1 keeps the intensity
  // positive: gain 100 and 100 molecules put b below 0.45 at SNR 1.
  const double gain_b = 100, gamma = 0.5, h = 0.5, molecules = 100;
  const double f = core::snr_occupancy(gamma);
  const int base = o.quick ? 500 : 2000;
  r.text(fmt::format(
      "Particles of a linear gradient C(y) = C0 (1 + b (y - tip).x) (gamma = C0 / K_d = 1/2) deposited into the half "
      "meshes (h = {}) as in A, nu particles per mesh cell; heading h = z, gradient along x (sin psi = 1). binding: "
      "gain {}, b = SNR / (alpha w f(1/2)) so that the exact field's SNR = alpha mu f sin psi is 0.5 and 1. count: "
      "molecule amount m with {} molecules in the sensing ball, b set so that core::snr_count is 0.5 and 1 (b 4h < 1: "
      "the intensity stays positive over the particles' cube). P(toward "
      "+x) is the conditional probability of the real decision given each estimate (Rao-Blackwell: the same mean, less "
      "variance); the real core::snr_steer decision is drawn alongside (`consistency z`). The exact field gives "
      "Phi(SNR); the estimate's noise, whose variance falls as 1/nu, weakens the decision, so |P - Phi| should fall "
      "as 1/nu once that noise is below the decision's own (the order is fitted over nu >= 64). {} decisions per cell.",
      h, gain_b, molecules, base));
  std::vector<Cell> cells;
  std::uint32_t test = 200;
  for (const char* form : {"binding", "count"})
    for (double snr : snrs)
      for (double nu : per_cell) {
        const bool count = std::string(form) == "count";
        const double a = 1.0, c0 = nu * a / (h * h * h);
        const double m_amount = c0 * kVolume / molecules;
        const core::SenseParams sp = sense_with(m_amount);
        // snr_count(C0, C0 b, m, r) = b r sqrt(C0 V / (5 m)) = b r sqrt(molecules / 5)
        const double b = count ? snr / (kRadius * std::sqrt(molecules / 5.0)) : snr / (gain_b * kWidth * f);
        const core::CueParams cue = cue_with(c0 / gamma);
        core::SteerParams p = default_snr_params(count ? core::NoiseForm::kCount : core::NoiseForm::kBinding);
        p.gain = gain_b;
        const int n = base;
        std::vector<double> prob(static_cast<std::size_t>(n));
        std::vector<std::uint8_t> emp(static_cast<std::size_t>(n));
        const std::uint32_t t = test++;
        tbb::parallel_for(tbb::blocked_range<int>(0, n), [&](const tbb::blocked_range<int>& br) {
          HalfMeshes m;
          m.h = h;
          for (int i = br.begin(); i != br.end(); ++i) {
            const Vec3 tip = draw_estimate(c0, a, b, static_cast<std::uint64_t>(i), t, m);
            const Vec3 hd{0, 0, 1};
            const core::CueSample s = core::estimate_sample(tip, m.view, 0);
            const core::Steered st = core::snr_steer(hd, &s, &cue, 1, sp, p, 9, static_cast<std::uint32_t>(i), t);
            emp[static_cast<std::size_t>(i)] = st.heading.x > 0.0;
            prob[static_cast<std::size_t>(i)] = toward_probability(s, cue, sp, p, hd);
          }
        });
        Cell c;
        c.form = form, c.snr = snr, c.nu = nu, c.b = b, c.decisions = n;
        double sum = 0, sum2 = 0, var = 0;
        int k = 0;
        for (int i = 0; i < n; ++i) {
          const double q = prob[static_cast<std::size_t>(i)];
          sum += q, sum2 += q * q, var += q * (1 - q), k += emp[static_cast<std::size_t>(i)];
        }
        c.p_emp = static_cast<double>(k) / n;
        c.p_rb = sum / n;
        c.se_rb = std::sqrt(std::max(0.0, sum2 / n - c.p_rb * c.p_rb) / (n - 1));
        c.consistency_z = var > 0 ? (k - sum) / std::sqrt(var) : 0.0;
        c.expect = phi(snr);
        cells.push_back(c);
      }
  std::vector<std::vector<std::string>> rows;
  for (const Cell& c : cells)
    rows.push_back({c.form, num(c.snr), num(c.nu), num(c.b, 4), std::to_string(c.decisions), num(c.expect, 5),
                    num(c.p_rb, 5), num(c.se_rb, 2), num(c.p_rb - c.expect, 3), num((c.p_rb - c.expect) / c.se_rb, 3),
                    num(c.p_emp, 5), num(c.consistency_z, 3)});
  r.table({"form", "SNR", "nu", "b", "decisions", "Phi(SNR)", "P(toward)", "SE", "P - Phi", "z vs Phi", "P empirical",
           "consistency z"},
          rows, "guidance_decisions.csv");
  double worst_cons = 0;
  for (const Cell& c : cells) worst_cons = std::max(worst_cons, std::fabs(c.consistency_z));
  const double zc_cons = z_bound(static_cast<double>(cells.size()));
  r.check({"decisions: core::snr_steer turns toward +x with the conditional probability used here", worst_cons < zc_cons,
           fmt::format("max |z| = {:.3f} over {} cells", worst_cons, cells.size()), fmt::format("|z| < {:.3f}", zc_cons),
           fmt::format("{:.2f} below the bound", zc_cons - worst_cons)});
  std::vector<std::vector<std::string>> orders;
  const double big = per_cell.back(), small = per_cell.front();
  for (const char* form : {"binding", "count"})
    for (double snr : snrs) {
      std::vector<double> x, y;
      double d_small = 0, d_big = 0, se_big = 0, se_small = 0;
      for (const Cell& c : cells) {
        if (c.form != form || c.snr != snr) continue;
        const double d = c.p_rb - c.expect;
        if (c.nu == small) d_small = d, se_small = c.se_rb;
        if (c.nu == big) d_big = d, se_big = c.se_rb;
        if (c.nu >= 64 && std::fabs(d) > 3 * c.se_rb) x.push_back(std::log(c.nu)), y.push_back(std::log(std::fabs(d)));
      }
      const Fit fit = x.size() >= 2 ? fit_line(x, y) : Fit{NAN, NAN, NAN};
      orders.push_back({form, num(snr), num(d_small, 3), num(d_big, 3), num(se_big, 2), std::to_string(x.size()),
                        num(fit.slope, 3), num(fit.slope_se, 2), "-1"});
      const double zs = (std::fabs(d_small) - std::fabs(d_big)) / std::hypot(se_small, se_big);
      r.check({fmt::format("{}, SNR {}: |P - Phi(SNR)| shrinks ({} -> {} particles per cell)", form, snr, small, big),
               zs > 3, fmt::format("{:.4f} -> {:.4f}", d_small, d_big), "decrease of |P - Phi| above 3 combined SE",
               fmt::format("{:.1f} SE", zs)});
      if (x.size() >= 2)
        r.check({fmt::format("{}, SNR {}: order of |P - Phi(SNR)| in nu ({} cells of nu >= 64 above 3 SE)", form, snr, x.size()),
                 fit.slope > -1.5 && fit.slope < -0.5, fmt::format("{:.3f} +- {:.2f}", fit.slope, fit.slope_se),
                 "slope in [-1.5, -0.5] (theory -1)", fmt::format("{:+.3f} from -1", fit.slope + 1)});
      else
        r.skip(fmt::format("{}, SNR {}: order of |P - Phi(SNR)| in nu", form, snr),
               fmt::format("{} cell(s) of nu >= 64 with |P - Phi| above 3 SE: no fit", x.size()));
    }
  r.table({"form", "SNR", "P - Phi (smallest nu)", "P - Phi (largest nu)", "SE (largest nu)", "points fitted", "slope",
           "slope SE", "theory"},
          orders, "guidance_orders.csv");
  r.plot("guidance_decisions.py", {"guidance_decisions.csv"}, "guidance_decisions.png",
         "Linear gradient: P(turn toward the gradient) against particles per mesh cell (left: binding, middle: count, "
         "dashed: the exact field's Phi(SNR)); right: |P - Phi| (log-log) with a 1/nu guide.");
}


}  // namespace axg::validate::guidance

// `validate turning`: the SNR turning model against its definition. For a grid of
// occupancies gamma and fractional gradients mu, the empirical probability of turning
// toward the gradient over many independent decisions must equal Phi(SNR) within its
// binomial error, and the response must peak at gamma = 1/2 (C = K_d / 2).
#include <cmath>

#include <fmt/format.h>
#include <gsl/gsl_cdf.h>

#include "axonguide/core/steering.hpp"
#include "axonguide/validate/validate.hpp"

namespace axg::validate {

void validate_turning(const Options& o, Report& r) {
  core::SteerParams p{};
  p.model = core::GuidanceModel::kSnr;
  p.cos_turn = std::cos(0.10471975511965977);
  p.sin_turn = std::sin(0.10471975511965977);
  p.gain = 250;
  const core::Vec3 h{0, 0, 1};
  const core::Vec3 g = core::normalized({1, 0, 1});  // sin psi = 1/sqrt(2)
  const double sin_psi = std::sqrt(0.5);
  const std::vector<double> gammas{0.01, 0.05, 0.1, 0.25, 0.5, 1, 2, 4, 10, 100};
  const std::vector<double> mus{0.002, 0.005, 0.01, 0.02, 0.04};
  // The peak is checked where the response around it differs by several binomial errors.
  const double peak_mu_min = 0.01;
  const int n = o.quick ? 20000 : 100000;
  const std::size_t tests = gammas.size() * mus.size();
  const double alpha = 0.01, z_crit = -gsl_cdf_ugaussian_Pinv(alpha / (2.0 * tests));
  r.text(fmt::format(
      "Heading h = z, signed unit gradient g at 45 degrees (sin psi = 1/sqrt 2), gain alpha = 250. For each (gamma, "
      "mu), {} neurons (ids 0..{}) make one decision each; P(toward) is the fraction that turned toward g. "
      "Criterion, fixed in advance: |z| = |P - Phi(SNR)| / sqrt(Phi(1-Phi)/n) below {:.3f}, the two-sided "
      "Bonferroni bound for family-wise alpha = {} over {} cells.",
      n, n - 1, z_crit, alpha, tests));
  std::vector<std::vector<std::string>> rows;
  double worst = 0;
  std::string worst_cell;
  int cell = 0;
  for (double mu : mus)
    for (double gamma : gammas) {
      const core::Detection d{true, gamma, mu, g};
      int toward = 0;
      for (int i = 0; i < n; ++i)
        toward += core::snr_turn(h, d, p, 31, static_cast<std::uint32_t>(i), 0, static_cast<std::uint32_t>(cell)).x > 0;
      ++cell;
      const double snr = p.gain * mu * core::snr_occupancy(gamma) * sin_psi;
      const double expect = gsl_cdf_ugaussian_P(snr);
      const double got = static_cast<double>(toward) / n;
      const double sd = std::sqrt(expect * (1 - expect) / n);
      const double z = sd > 0 ? (got - expect) / sd : 0.0;
      if (std::fabs(z) > worst) worst = std::fabs(z), worst_cell = fmt::format("gamma {} mu {}", gamma, mu);
      rows.push_back({num(gamma), num(mu), num(snr), num(expect, 6), num(got, 6), num(z, 3)});
    }
  r.table({"gamma", "mu", "SNR", "Phi(SNR)", "P(toward)", "z"}, rows, "turning.csv");
  r.check({"P(turn toward) = Phi(SNR) in every cell", worst < z_crit, fmt::format("max |z| = {:.3f} ({})", worst, worst_cell),
           fmt::format("max |z| < {:.3f}", z_crit), fmt::format("{:.2f} below the bound", z_crit - worst)});
  // The peak: for each mu, the gamma of the largest empirical P(toward) among the grid is
  // 1/2, and a parabola through the three points around it puts the maximum near ln 1/2.
  for (std::size_t m = 0; m < mus.size(); ++m) {
    if (mus[m] < peak_mu_min) continue;
    std::size_t best = 0;
    for (std::size_t k = 0; k < gammas.size(); ++k)
      if (std::stod(rows[m * gammas.size() + k][4]) > std::stod(rows[m * gammas.size() + best][4])) best = k;
    double peak = gammas[best];
    if (best > 0 && best + 1 < gammas.size()) {
      const double x0 = std::log(gammas[best - 1]), x1 = std::log(gammas[best]), x2 = std::log(gammas[best + 1]);
      const double y0 = std::stod(rows[m * gammas.size() + best - 1][4]), y1 = std::stod(rows[m * gammas.size() + best][4]),
                   y2 = std::stod(rows[m * gammas.size() + best + 1][4]);
      const double denom = (x0 - x1) * (x0 - x2) * (x1 - x2);
      const double a = (x2 * (y1 - y0) + x1 * (y0 - y2) + x0 * (y2 - y1)) / denom;
      const double b = (x2 * x2 * (y0 - y1) + x1 * x1 * (y2 - y0) + x0 * x0 * (y1 - y2)) / denom;
      if (a < 0) peak = std::exp(-b / (2 * a));
    }
    r.check({fmt::format("response peaks at gamma = 1/2 (mu = {})", mus[m]),
             gammas[best] == 0.5 && peak > 0.25 && peak < 1.0,
             fmt::format("largest P at gamma = {}, fitted peak {:.3f}", gammas[best], peak),
             "largest at 0.5 on the grid, fitted peak in (0.25, 1)", fmt::format("fitted peak / 0.5 = {:.2f}", peak / 0.5)});
  }
  r.plot("turning.py", {"turning.csv"}, "turning.png",
         "P(turn toward the gradient) against gamma = C/K_d for four mu: empirical (points) and Phi(SNR) (lines).");
}

}  // namespace axg::validate

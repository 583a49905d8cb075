// `validate turning`: the SNR turning model against its definition, for both receptor-
// noise forms. For a grid of occupancies gamma and fractional gradients mu, the empirical
// probability of turning toward the gradient over many independent decisions must equal
// Phi(SNR) within its binomial error, and the response must peak where the noise form
// says: gamma = 1/2 (binding) or gamma = 1 (snapshot).
#include <cmath>

#include <fmt/format.h>
#include <gsl/gsl_cdf.h>

#include "axonguide/core/steering.hpp"
#include "axonguide/model/steering.hpp"
#include "axonguide/validate/validate.hpp"

namespace axg::validate {

core::SteerParams default_snr_params(core::NoiseForm noise) {
  core::SteerParams p{};
  p.model = core::GuidanceModel::kSnr;
  p.noise = noise;
  const double turn = SteeringKeys{}.turn_angle;  // the scene's default (model/steering.hpp)
  p.cos_turn = std::cos(turn);
  p.sin_turn = std::sin(turn);
  p.gain = 250;
  return p;
}

core::Steered one_cue_decision(core::Vec3 h, double gamma, double mu, core::Vec3 g, const core::SteerParams& p,
                               std::uint64_t seed, std::uint32_t neuron, std::uint32_t step) {
  core::SenseParams sp{};
  sp.cone_width = 0.1;
  core::CueParams cue{};
  cue.sign = 1.0;
  cue.kd = 1.0;
  cue.max_c = HUGE_VAL;
  const double c = gamma;
  const core::Vec3 grad = (mu * c / sp.cone_width) * g;
  const core::CueSample s = core::exact_sample(c, grad);
  return core::snr_steer(h, &s, &cue, 1, sp, p, seed, neuron, step);
}

namespace {

void turning_for(core::NoiseForm noise, const Options& o, Report& r) {
  const core::SteerParams p = default_snr_params(noise);
  const bool binding = noise == core::NoiseForm::kBinding;
  const char* name = binding ? "binding" : "snapshot";
  const double gamma_peak = binding ? 0.5 : 1.0;
  r.text(fmt::format("### Noise form `{}`: f(gamma) = {}, peak at gamma = {}", name,
                     binding ? "sqrt(gamma / (1 + gamma)^3)" : "sqrt(gamma) / (1 + gamma)", gamma_peak));
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
      int toward = 0;
      for (int i = 0; i < n; ++i)
        toward += one_cue_decision(h, gamma, mu, g, p, 31, static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(cell))
                      .heading.x > 0;
      ++cell;
      const double snr = p.gain * mu * core::receptor_noise(gamma, noise) * sin_psi;
      const double expect = gsl_cdf_ugaussian_P(snr);
      const double got = static_cast<double>(toward) / n;
      const double sd = std::sqrt(expect * (1 - expect) / n);
      const double z = sd > 0 ? (got - expect) / sd : 0.0;
      if (std::fabs(z) > worst) worst = std::fabs(z), worst_cell = fmt::format("gamma {} mu {}", gamma, mu);
      rows.push_back({num(gamma), num(mu), num(snr), num(expect, 6), num(got, 6), num(z, 3)});
    }
  const std::string csv = fmt::format("turning-{}.csv", name);
  r.table({"gamma", "mu", "SNR", "Phi(SNR)", "P(toward)", "z"}, rows, csv);
  r.check({fmt::format("{}: P(turn toward) = Phi(SNR) in every cell", name), worst < z_crit, fmt::format("max |z| = {:.3f} ({})", worst, worst_cell),
           fmt::format("max |z| < {:.3f}", z_crit), fmt::format("{:.2f} below the bound", z_crit - worst)});
  // The peak: for each mu, the gamma of the largest empirical P(toward) among the grid is
  // the noise form's, and a parabola through the three points around it puts the maximum
  // within a factor 2 of it.
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
    r.check({fmt::format("{}: response peaks at gamma = {} (mu = {})", name, gamma_peak, mus[m]),
             gammas[best] == gamma_peak && peak > gamma_peak / 2 && peak < gamma_peak * 2,
             fmt::format("largest P at gamma = {}, fitted peak {:.3f}", gammas[best], peak),
             fmt::format("largest at {} on the grid, fitted peak in ({}, {})", gamma_peak, gamma_peak / 2, gamma_peak * 2),
             fmt::format("fitted peak / {} = {:.2f}", gamma_peak, peak / gamma_peak)});
  }
  r.plot("turning.py", {csv}, fmt::format("turning-{}.png", name),
         fmt::format("P(turn toward the gradient) against gamma = C/K_d for four mu, noise form {}: empirical (points) "
                     "and Phi(SNR) (lines).",
                     name));
}

}  // namespace

void validate_turning(const Options& o, Report& r) {
  turning_for(core::NoiseForm::kBinding, o, r);
  turning_for(core::NoiseForm::kSnapshot, o, r);
}

}  // namespace axg::validate

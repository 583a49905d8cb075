// Tests of the uniformity tests on S^(d-1) (validate/stats): the Kolmogorov distribution, the
// Funk-Hecke quadrature, Gine's statistic and its limit law (checked against Monte Carlo),
// Imhof's inversion against exact cases, p-values under H0, and power against alternatives.
// All random numbers come from GSL's mt19937 with fixed seeds.
#include "axonguide/validate/stats.hpp"

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <numbers>
#include <numeric>
#include <vector>

namespace {

using namespace axg::validate;
constexpr double kPi = std::numbers::pi;

struct Rng {
  std::unique_ptr<gsl_rng, void (*)(gsl_rng*)> r{gsl_rng_alloc(gsl_rng_mt19937), gsl_rng_free};
  explicit Rng(unsigned long seed) { gsl_rng_set(r.get(), seed); }
  gsl_rng* get() { return r.get(); }
};

void normalise(double* v, int d) {
  double s = 0.0;
  for (int k = 0; k < d; ++k) s += v[k] * v[k];
  s = std::sqrt(s);
  for (int k = 0; k < d; ++k) v[k] /= s;
}

// n uniform points on S^(d-1): normalised Gaussian vectors.
std::vector<double> uniform_sphere(std::size_t n, int d, Rng& rng) {
  std::vector<double> x(n * d);
  for (std::size_t i = 0; i < n; ++i) {
    for (int k = 0; k < d; ++k) x[i * d + k] = gsl_ran_gaussian_ziggurat(rng.get(), 1.0);
    normalise(&x[i * d], d);
  }
  return x;
}

double mean_of(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0) / v.size(); }
double var_of(const std::vector<double>& v) {
  const double m = mean_of(v);
  double s = 0.0;
  for (double x : v) s += (x - m) * (x - m);
  return s / (v.size() - 1.0);
}

// ---------------------------------------------------------------------------------------
// Kolmogorov-Smirnov

TEST(StatsKolmogorov, KnownValues) {
  EXPECT_EQ(kolmogorov_q(0.0), 1.0);
  EXPECT_EQ(kolmogorov_q(-1.0), 1.0);
  EXPECT_NEAR(kolmogorov_q(1.36), 0.0494, 5e-4);
  EXPECT_NEAR(kolmogorov_q(1.63), 0.00977, 1e-4);
  EXPECT_NEAR(kolmogorov_q(1.0), 0.26999967, 1e-7);  // 1 - K(1) = 0.2699996716735...
  EXPECT_NEAR(kolmogorov_q(0.5), 0.96394524, 1e-7);  // K(0.5) = 0.0360547563...
  // The two series meet at 1.18 without a visible step, and Q decreases.
  EXPECT_NEAR(kolmogorov_q(1.18 - 1e-12), kolmogorov_q(1.18), 1e-11);
  double prev = 1.0;
  for (double l = 0.05; l < 4.0; l += 0.05) {
    const double q = kolmogorov_q(l);
    EXPECT_LE(q, prev) << l;
    prev = q;
  }
  EXPECT_LT(kolmogorov_q(4.0), 1e-13);
}

TEST(StatsKolmogorov, ExactFiniteN) {
  // The example of Marsaglia, Tsang and Wang (2003).
  EXPECT_NEAR(kolmogorov_cdf_exact(10, 0.274), 0.6284796154565043, 1e-12);
  // n = 1: P(D_1 < d) = 2d - 1 for 1/2 <= d <= 1.
  EXPECT_NEAR(kolmogorov_cdf_exact(1, 0.7), 0.4, 1e-12);
  // Large n approaches the limit law.
  const double n = 1000;
  for (double l : {0.6, 1.0, 1.36}) EXPECT_NEAR(1.0 - kolmogorov_cdf_exact(1000, l / std::sqrt(n)), kolmogorov_q(l), 0.01);
}

TEST(StatsKolmogorovSmirnov, GridPassesSquaresFail) {
  for (std::size_t n : {10u, 300u, 5000u}) {  // 5000: the asymptotic (Stephens) path
    std::vector<double> u(n);
    for (std::size_t i = 0; i < n; ++i) u[i] = (i + 0.5) / n;
    const TestResult r = ks_uniform(u);
    EXPECT_NEAR(r.statistic, 0.5 / n, 1e-15);
    EXPECT_GT(r.p_value, 0.999) << n << " " << r.note;
  }
  Rng rng(11);
  for (std::size_t n : {300u, 5000u}) {
    std::vector<double> u(n), u2(n);
    for (std::size_t i = 0; i < n; ++i) {
      u[i] = gsl_rng_uniform(rng.get());
      u2[i] = u[i] * u[i];
    }
    EXPECT_GT(ks_uniform(u).p_value, 0.01);
    EXPECT_LT(ks_uniform(u2).p_value, 1e-6) << n;
  }
  // ks_cdf = ks_uniform of the transformed values.
  std::vector<double> z(200);
  for (double& v : z) v = gsl_ran_gaussian_ziggurat(rng.get(), 1.0);
  const TestResult a = ks_cdf(z, [](double t) { return gsl_cdf_ugaussian_P(t); });
  std::vector<double> uz(z.size());
  for (std::size_t i = 0; i < z.size(); ++i) uz[i] = gsl_cdf_ugaussian_P(z[i]);
  EXPECT_EQ(a.statistic, ks_uniform(uz).statistic);
  EXPECT_GT(a.p_value, 0.01);
  EXPECT_LT(ks_cdf(z, [](double t) { return gsl_cdf_ugaussian_P(t / 1.5); }).p_value, 0.01);
  EXPECT_THROW(ks_uniform({}), std::invalid_argument);
}

RC_GTEST_PROP(StatsKolmogorovSmirnov, StatisticAndPValueInRange, ()) {
  const auto u = *rc::gen::nonEmpty(rc::gen::container<std::vector<double>>(
      rc::gen::map(rc::gen::inRange(0, 1000001), [](int k) { return k / 1e6; })));
  const TestResult r = ks_uniform(u);
  RC_ASSERT(r.statistic >= 0.5 / u.size() - 1e-15);
  RC_ASSERT(r.statistic <= 1.0);
  RC_ASSERT(r.p_value >= 0.0);
  RC_ASSERT(r.p_value <= 1.0);
}

// ---------------------------------------------------------------------------------------
// Gegenbauer polynomials, harmonic dimensions, Funk-Hecke quadrature

TEST(StatsFunkHecke, PolynomialsAndDimensions) {
  const auto p3 = gegenbauer(3, 3, 0.5);  // Legendre
  EXPECT_NEAR(p3[2], -0.125, 1e-15);
  EXPECT_NEAR(p3[3], (5 * 0.125 - 3 * 0.5) / 2, 1e-15);
  const auto p2 = gegenbauer(2, 7, std::cos(0.3));  // Chebyshev
  for (int k = 0; k <= 7; ++k) EXPECT_NEAR(p2[k], std::cos(k * 0.3), 1e-14);
  for (int d : {2, 3, 5, 100}) EXPECT_NEAR(gegenbauer(d, 12, 1.0)[12], 1.0, 1e-12);
  for (int k = 0; k < 20; ++k) {
    EXPECT_EQ(harmonic_dimension(k, 2), k == 0 ? 1.0 : 2.0);
    EXPECT_EQ(harmonic_dimension(k, 3), 2.0 * k + 1);
    EXPECT_EQ(harmonic_dimension(k, 4), (k + 1.0) * (k + 1.0));
  }
  EXPECT_EQ(harmonic_dimension(2, 1000), 999.0 * 1002.0 / 2.0);  // = Bingham's df
  EXPECT_NEAR(std::exp(log_harmonic_dimension(7, 50)), harmonic_dimension(7, 50), 1e-9 * harmonic_dimension(7, 50));
}

TEST(StatsFunkHecke, KnownLegendreCoefficients) {
  // d = 3, K(t) = t^2 = 1/3 P_0 + 2/3 P_2: lambda_0 = 1/3, lambda_2 = (2/3)/dim_2 = 2/15.
  const auto lam = funk_hecke([](double t) { return t * t; }, 3, 8);
  for (int k = 0; k <= 8; ++k) EXPECT_NEAR(lam[k], k == 0 ? 1.0 / 3 : k == 2 ? 2.0 / 15 : 0.0, 1e-10) << k;
  // Orthogonality, also for large d where the weight sin^(d-2) is sharply peaked:
  // K = P_j gives lambda_k = delta_jk / dim_k.
  for (int d : {2, 3, 5, 10, 200, 1000}) {
    for (int j : {2, 3, 5}) {
      const auto l = funk_hecke([&](double t) { return gegenbauer(d, j, t)[j]; }, d, 8);
      for (int k = 0; k <= 8; ++k) {
        const double normed = l[k] * std::sqrt(harmonic_dimension(k, d) * harmonic_dimension(j, d));
        EXPECT_NEAR(normed, k == j ? 1.0 : 0.0, 1e-10) << "d=" << d << " j=" << j << " k=" << k;
      }
    }
  }
}

TEST(StatsFunkHecke, GineKernelKnownCoefficients) {
  // d = 2: -|sin theta| = -2/pi + (4/pi) sum_m cos(2 m theta)/(4m^2-1): lambda_2m = 2/(pi(4m^2-1)).
  const GineLimit& g2 = gine_limit(2);
  EXPECT_NEAR(g2.lambda[0], -2.0 / kPi, 1e-14);
  for (int m = 1; 2 * m <= g2.kmax; ++m) {
    EXPECT_NEAR(g2.lambda[2 * m], 2.0 / (kPi * (4.0 * m * m - 1.0)), 1e-13) << m;
    EXPECT_NEAR(g2.lambda[2 * m - 1], 0.0, 1e-13);
  }
  // d = 3: lambda_2 = pi/32, lambda_2m / lambda_2m-2 = (2m-3)(2m-1)/((2m)(2m+2)).
  const GineLimit& g3 = gine_limit(3);
  double expect = kPi / 32;
  for (int m = 1; 2 * m <= g3.kmax; ++m) {
    if (m > 1) expect *= (2.0 * m - 3) * (2.0 * m - 1) / ((2.0 * m) * (2.0 * m + 2));
    EXPECT_NEAR(g3.lambda[2 * m], expect, 1e-13) << m;
  }
  // The node count is enough: doubling it changes nothing that matters.
  for (int d : {2, 3, 10, 1000}) {
    const auto a = funk_hecke_angle([](double th) { return -std::sin(th); }, d, 60);
    const auto b = funk_hecke_angle([](double th) { return -std::sin(th); }, d, 60, 4 * (48 + 60 + d));
    for (int k = 0; k <= 60; k += 2) EXPECT_NEAR(a[k], b[k], 1e-14 + 1e-9 * std::fabs(b[k])) << d << " " << k;
  }
}

// ---------------------------------------------------------------------------------------
// Gine's statistic and its limit law

TEST(StatsGine, ConstantAndAffineMapToVStatistic) {
  EXPECT_NEAR(gine_constant(2), kPi / 2, 1e-15);
  EXPECT_NEAR(gine_constant(3), 4 / kPi, 1e-15);
  // c_d = 1/E[sin psi] = -1/lambda_0 (quadrature), also for large d.
  for (int d : {2, 3, 4, 7, 10, 50, 200, 999, 1000}) {
    const auto lam = funk_hecke_angle([](double th) { return -std::sin(th); }, d, 0);
    EXPECT_NEAR(gine_constant(d) * lam[0], -1.0, 1e-14) << d;
  }
  // G_n = (c/2) (V_n - n lambda_0), V_n = (1/n) sum_{i,j} K(x_i.x_j) with K(t) = -sqrt(1-t^2).
  Rng rng(5);
  for (int d : {2, 3, 7, 9, 50}) {
    const std::size_t n = 60;
    const auto x = uniform_sphere(n, d, rng);
    // (The diagonal is K(1) = 0 exactly: evaluating it from x_i.x_i = 1 +- 1e-16 would give
    // sqrt(2e-16) ~ 1.5e-8 per term.)
    double V = 0.0;
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = 0; j < n; ++j) {
        if (i == j) continue;
        double t = 0.0;
        for (int k = 0; k < d; ++k) t += x[i * d + k] * x[j * d + k];
        t = std::clamp(t, -1.0, 1.0);
        V += -std::sqrt(1.0 - t * t);
      }
    V /= n;
    const double lambda0 = funk_hecke([](double t) { return -std::sqrt(std::max(0.0, 1.0 - t * t)); }, d, 0)[0];
    const double G = gine_statistic(x.data(), n, d);
    EXPECT_NEAR(G, gine_constant(d) / 2 * (V - n * lambda0), 1e-12) << d;
    // and the definition, uncentred
    double s = 0.0;
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = i + 1; j < n; ++j) {
        double t = 0.0;
        for (int k = 0; k < d; ++k) t += x[i * d + k] * x[j * d + k];
        s += std::sqrt(std::max(0.0, 1.0 - t * t));
      }
    EXPECT_NEAR(G, n / 2.0 - gine_constant(d) / n * s, 1e-12) << d;
  }
}

TEST(StatsGine, LimitLawMomentsAndTruncation) {
  const GineLimit& g3 = gine_limit(3);
  // d = 3: weights (c/2) lambda_k = 1/16, 1/128, 5/2048 with dof 5, 9, 13.
  ASSERT_GE(g3.law.weight.size(), 3u);
  EXPECT_NEAR(g3.law.weight[0], 1.0 / 16, 1e-14);
  EXPECT_NEAR(g3.law.weight[1], 1.0 / 128, 1e-14);
  EXPECT_NEAR(g3.law.weight[2], 5.0 / 2048, 1e-14);
  EXPECT_EQ(g3.law.dof[0], 5.0);
  EXPECT_EQ(g3.law.dof[1], 9.0);
  EXPECT_EQ(g3.law.dof[2], 13.0);
  EXPECT_NEAR(gine_limit(2).variance, (kPi * kPi - 8) / 16, 1e-14);
  for (int d : {2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 15, 20, 30, 50, 100, 200, 333, 500, 999, 1000}) {
    const GineLimit& g = gine_limit(d);
    const double c = gine_constant(d);
    // The mean is exactly 1/2, the variance (c^2/2)(1 - 1/d) - 1/2; the law has them both
    // (its tail mean as a constant) up to the neglected tail variance.
    EXPECT_NEAR(g.law.mean(), 0.5, 1e-12) << d;
    EXPECT_NEAR(g.variance, c * c / 2 * (1 - 1.0 / d) - 0.5, 1e-12 * g.variance + 1e-15) << d;
    EXPECT_NEAR(g.law.variance() + g.tail_variance, g.variance, 1e-8 * g.variance) << d;
    EXPECT_LE(g.tail_variance, 1.01e-6 * g.variance) << d;
    EXPECT_LE(g.kmax, 128) << d;
    for (std::size_t j = 0; j < g.law.weight.size(); ++j) EXPECT_GT(g.law.weight[j], 0.0);
  }
  // The truncation (tail as its mean) moves p-values by < 1e-6: compare with 400 terms (d = 3)
  // and 300 terms (d = 2).
  for (int d : {2, 3}) {
    const GineLimit& g = gine_limit(d);
    const int K = 600;
    const auto lam = funk_hecke_angle([](double th) { return -std::sin(th); }, d, K);
    WeightedChiSquare big;
    double P1 = 0.0;
    for (int k = 2; k <= K; k += 2) {
      big.weight.push_back(g.c / 2 * lam[k]);
      big.dof.push_back(harmonic_dimension(k, d));
      P1 += big.weight.back() * big.dof.back();
    }
    big.shift = 0.5 - P1;
    for (double x : {0.2, 0.5, 1.0, 1.5}) EXPECT_NEAR(weighted_chisq_sf(g.law, x), weighted_chisq_sf(big, x), 1e-6) << d;
  }
}

TEST(StatsImhof, ExactCases) {
  // A single weighted chi-square.
  for (auto [w, h] : std::vector<std::pair<double, double>>{{0.1, 5}, {2, 10}, {0.01, 40}, {1e-6, 5e5}}) {
    WeightedChiSquare q{{w}, {h}, 0.0};
    for (double z : {0.1, 0.5, 1.0, 2.0, 3.0}) {
      const double x = w * h * z;
      EXPECT_NEAR(weighted_chisq_sf(q, x), gsl_cdf_chisq_Q(x / w, h), 1e-12) << w << " " << h << " " << z;
    }
  }
  // Two exponentials (chi2_2 = 2 Exp): (a e^{-x/a} - b e^{-x/b})/(a-b), a = 2 w_1, b = 2 w_2; and a shift.
  WeightedChiSquare q{{0.3, 0.1}, {2, 2}, 0.25};
  for (double x : {0.1, 0.5, 1.0, 3.0}) {
    const double a = 0.6, b = 0.2, y = x - 0.25;
    const double e = y <= 0 ? 1.0 : (a * std::exp(-y / a) - b * std::exp(-y / b)) / (a - b);
    EXPECT_NEAR(weighted_chisq_sf(q, x), e, 1e-12) << x;
  }
  // Equal weights: 20 x 0.05 chi2_2 = 0.05 chi2_40.
  WeightedChiSquare q20;
  for (int j = 0; j < 20; ++j) {
    q20.weight.push_back(0.05);
    q20.dof.push_back(2);
  }
  for (double x : {0.5, 1.0, 2.0, 3.0}) EXPECT_NEAR(weighted_chisq_sf(q20, x), gsl_cdf_chisq_Q(x / 0.05, 40), 1e-12);
}

RC_GTEST_PROP(StatsImhof, MonotoneAndInRange, ()) {
  const int m = *rc::gen::inRange(3, 9);
  WeightedChiSquare q;
  for (int j = 0; j < m; ++j) {
    q.weight.push_back(*rc::gen::inRange(1, 101) / 100.0);
    q.dof.push_back(*rc::gen::inRange(2, 12));
  }
  const double sd = std::sqrt(q.variance());
  double prev = 1.0;
  for (double z = -2.0; z <= 6.0; z += 1.0) {
    const double p = weighted_chisq_sf(q, q.mean() + z * sd);
    RC_ASSERT(p >= 0.0);
    RC_ASSERT(p <= 1.0);
    RC_ASSERT(p <= prev + 1e-10);
    prev = p;
  }
}

TEST(StatsGine, LimitLawAgainstMonteCarloOfItself) {
  // Draws of the (truncated) limit law itself, GSL mt19937 + gsl_ran_chisq, against Imhof.
  for (int d : {2, 3, 10}) {
    const GineLimit& g = gine_limit(d);
    Rng rng(100 + d);
    const int N = 100000;
    std::vector<double> s(N);
    for (double& v : s) {
      v = g.law.shift;
      for (std::size_t j = 0; j < g.law.weight.size(); ++j) v += g.law.weight[j] * gsl_ran_chisq(rng.get(), g.law.dof[j]);
    }
    const double sd = std::sqrt(g.variance);
    for (double z : {-1.0, 0.0, 1.0, 2.0, 3.0}) {
      const double x = 0.5 + z * sd;
      const double p_mc = std::count_if(s.begin(), s.end(), [&](double v) { return v >= x; }) / double(N);
      const double p = weighted_chisq_sf(g.law, x);
      EXPECT_NEAR(p, p_mc, 4.5 * std::sqrt(p * (1 - p) / N) + 1e-5) << "d=" << d << " x=" << x;
    }
  }
}

TEST(StatsGine, FiniteNNullMomentsMatchTheLimitLaw) {
  // Monte Carlo of G_n itself on uniform points (n = 200, 500 replicates). Under H0 the mean is
  // exactly 1/2 for every n and the variance (n-1)/n times the limit's (the pairs are
  // uncorrelated: E[sin psi_ij | x_i] is constant).
  for (int d : {2, 3, 10}) {
    Rng rng(200 + d);
    const std::size_t n = 200;
    const int R = 500;
    std::vector<double> G(R);
    for (double& v : G) {
      const auto x = uniform_sphere(n, d, rng);
      v = gine_statistic(x.data(), n, d);
    }
    const GineLimit& g = gine_limit(d);
    const double var_n = g.variance * (n - 1.0) / n;
    // sd of the sample variance from the law's 4th cumulant (48 sum h w^4).
    double k4 = 0.0;
    for (std::size_t j = 0; j < g.law.weight.size(); ++j) k4 += 48 * g.law.dof[j] * std::pow(g.law.weight[j], 4);
    const double sd_var = std::sqrt(2 * var_n * var_n / (R - 1.0) + k4 / R);
    EXPECT_NEAR(mean_of(G), 0.5, 4 * std::sqrt(var_n / R)) << d;
    EXPECT_NEAR(var_of(G), var_n, 4 * sd_var) << d;
    // The whole null distribution: KS of G_n against the limit law.
    const TestResult ks = ks_cdf(G, [&](double t) { return 1.0 - weighted_chisq_sf(g.law, t); });
    EXPECT_GT(ks.p_value, 1e-3) << d << " D=" << ks.statistic;
  }
}

// ---------------------------------------------------------------------------------------
// Gine for large n: the sorted circle statistic and the block statistic

TEST(StatsGineLarge, CircleStatisticEqualsThePairSum) {
  // Unit vectors in every quadrant, on the axes (y = 0 with x < 0 folds to x > 0), repeated
  // points, antipodes and a zero vector: the O(n log n) sum is the O(n^2) one.
  Rng rng(900);
  for (std::size_t n : {2u, 3u, 50u, 3000u}) {
    auto x = uniform_sphere(n, 2, rng);
    if (n >= 50) {
      x[0] = -1, x[1] = 0;    // on the negative x axis
      x[2] = 1, x[3] = 0;     // its antipode
      x[4] = 0, x[5] = -1;
      x[6] = x[8], x[7] = x[9];  // a repeated point
      x[10] = -x[12], x[11] = -x[13];
      x[14] = 0, x[15] = 0;   // a zero vector: sin psi = 1 with every point in the pair sum
    }
    const double pairs = gine_statistic(x.data(), n, 2), sorted = gine_statistic_circle(x.data(), n);
    EXPECT_NEAR(sorted, pairs, 1e-11 * std::max(1.0, std::fabs(pairs))) << n;
  }
  // Above kGineExactMax gine() takes the sorted route for d = 2: the statistic of all pairs still.
  const std::size_t n = kGineExactMax + 5000;
  const auto x = uniform_sphere(n, 2, rng);
  const TestResult g = gine(x.data(), n, 2);
  EXPECT_NEAR(g.statistic, gine_statistic(x.data(), n, 2), 1e-10);
  EXPECT_NE(g.note.find("sorting"), std::string::npos) << g.note;
  EXPECT_GT(g.p_value, 1e-4);
}

TEST(StatsGineLarge, BlockStatistic) {
  Rng rng(901);
  // One block is G_n of the same points in another order.
  {
    const std::size_t n = 400;
    const auto x = uniform_sphere(n, 3, rng);
    EXPECT_NEAR(gine_block_statistic(x.data(), n, 3, 1), gine_statistic(x.data(), n, 3), 1e-12);
  }
  EXPECT_EQ(gine_block_count(kGineExactMax), 1u);
  EXPECT_EQ(gine_block_count(kGineExactMax + 1), 2u);
  EXPECT_EQ(gine_block_count(200000), 98u);      // B = 2048
  EXPECT_EQ(gine_block_count(10000000), 4883u);  // B = 2048
  // Under H0 the sum of m blocks has mean m/2 and m times the variance of one block of its size
  // ((b-1)/b times the limit's): Monte Carlo, 300 replicates of 8 blocks of 100 points.
  {
    const std::size_t n = 800, m = 8;
    const int R = 300;
    std::vector<double> T(R), p(R);
    const GineLimit& g = gine_limit(3);
    WeightedChiSquare sum = g.law;
    for (double& h : sum.dof) h *= m;
    sum.shift *= m;
    for (int r = 0; r < R; ++r) {
      const auto x = uniform_sphere(n, 3, rng);
      T[r] = gine_block_statistic(x.data(), n, 3, m);
      p[r] = weighted_chisq_sf(sum, T[r]);
    }
    const double var = m * g.variance * 99.0 / 100.0;
    EXPECT_NEAR(mean_of(T), m / 2.0, 4 * std::sqrt(var / R));
    EXPECT_NEAR(var_of(T), var, 0.25 * var);
    EXPECT_GT(ks_uniform(p).p_value, 1e-3);
  }
  // Above kGineExactMax for d = 3: 3 blocks of 10^4. A uniform set passes, also when its rows
  // are sorted (the blocks are pseudo-random subsets, not runs of rows); the naive (theta, phi)
  // sampler fails.
  const std::size_t n = 30000;
  auto x = uniform_sphere(n, 3, rng);
  const TestResult u = gine(x.data(), n, 3);
  EXPECT_NE(u.note.find("sum of G over 3 blocks"), std::string::npos) << u.note;
  EXPECT_GT(u.p_value, 1e-4);
  std::vector<std::size_t> idx(n);
  std::iota(idx.begin(), idx.end(), 0);
  std::sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return x[3 * a + 2] < x[3 * b + 2]; });
  std::vector<double> sorted(3 * n);
  for (std::size_t i = 0; i < n; ++i) std::copy_n(&x[3 * idx[i]], 3, &sorted[3 * i]);
  EXPECT_GT(gine(sorted.data(), n, 3).p_value, 1e-4);
  for (std::size_t i = 0; i < n; ++i) {
    const double th = kPi * gsl_rng_uniform(rng.get()), ph = 2 * kPi * gsl_rng_uniform(rng.get());
    x[3 * i] = std::sin(th) * std::cos(ph), x[3 * i + 1] = std::sin(th) * std::sin(ph), x[3 * i + 2] = std::cos(th);
  }
  EXPECT_LT(gine(x.data(), n, 3).p_value, 1e-6);
}

// ---------------------------------------------------------------------------------------
// The three sphere tests under H0 and against alternatives

TEST(StatsSphereTests, PValuesUniformUnderH0) {
  for (int d : {2, 3, 5, 10, 200}) {
    Rng rng(300 + d);
    const std::size_t n = 300;
    const int R = 200;
    std::vector<double> pr, pb, pg;
    for (int r = 0; r < R; ++r) {
      const auto x = uniform_sphere(n, d, rng);
      pr.push_back(rayleigh(x.data(), n, d).p_value);
      pb.push_back(bingham(x.data(), n, d).p_value);
      pg.push_back(gine(x.data(), n, d).p_value);
    }
    for (const auto* p : {&pr, &pb, &pg}) {
      const char* name = p == &pr ? "Rayleigh" : p == &pb ? "Bingham" : "Gine";
      for (double v : *p) {
        ASSERT_GE(v, 0.0);
        ASSERT_LE(v, 1.0);
      }
      // Binomial(200, 0.05): mean 10, P(<= 2) = 0.002, P(>= 22) = 0.0005.
      const auto below = std::count_if(p->begin(), p->end(), [](double v) { return v < 0.05; });
      EXPECT_GE(below, 3) << name << " d=" << d;
      EXPECT_LE(below, 21) << name << " d=" << d;
      EXPECT_GT(ks_uniform(*p).p_value, 1e-3) << name << " d=" << d;
    }
  }
}

TEST(StatsSphereTests, ShiftedSample) {
  // von Mises-Fisher-like: uniform points plus a common vector a e_1, renormalised. Rayleigh
  // rejects a small shift; Gine sees only the even harmonics (sin psi is blind to the sign of
  // each point), so it needs a larger one in d = 3.
  for (int d : {3, 10}) {
    for (auto [a, n] : std::vector<std::pair<double, std::size_t>>{{0.3, 500}, {d == 3 ? 1.0 : 0.6, 300}}) {
      Rng rng(400 + d);
      auto x = uniform_sphere(n, d, rng);
      for (std::size_t i = 0; i < n; ++i) {
        x[i * d] += a;
        normalise(&x[i * d], d);
      }
      EXPECT_LT(rayleigh(x.data(), n, d).p_value, 1e-6) << d << " " << a;
      if (a >= 0.6) {
        EXPECT_LT(gine(x.data(), n, d).p_value, 1e-6) << d << " " << a;
      }
    }
  }
}

TEST(StatsSphereTests, AxialSample) {
  // Points concentrated near +-e_1 (angular central Gaussian, first axis 3x), each with its
  // antipode: Rayleigh sees nothing (the resultant is 0), Bingham and Gine reject.
  for (int d : {3, 10, 200}) {
    Rng rng(500 + d);
    const std::size_t half = 150, n = 2 * half;
    std::vector<double> x(n * d);
    for (std::size_t i = 0; i < half; ++i) {
      double* a = &x[i * d];
      for (int k = 0; k < d; ++k) a[k] = gsl_ran_gaussian_ziggurat(rng.get(), k == 0 ? 3.0 : 1.0);
      normalise(a, d);
      for (int k = 0; k < d; ++k) x[(half + i) * d + k] = -a[k];
    }
    EXPECT_GT(rayleigh(x.data(), n, d).p_value, 0.5) << d;
    EXPECT_LT(bingham(x.data(), n, d).p_value, 1e-6) << d;
    EXPECT_LT(gine(x.data(), n, d).p_value, 1e-6) << d;
  }
}

TEST(StatsSphereTests, NaiveSphericalCoordinatesRejected) {
  // theta and phi uniform: too many points near the poles; z = cos theta is not U(-1, 1).
  Rng rng(600);
  const std::size_t n = 1000;
  std::vector<double> x(3 * n), z(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double th = kPi * gsl_rng_uniform(rng.get()), ph = 2 * kPi * gsl_rng_uniform(rng.get());
    x[3 * i] = std::sin(th) * std::cos(ph);
    x[3 * i + 1] = std::sin(th) * std::sin(ph);
    x[3 * i + 2] = z[i] = std::cos(th);
  }
  EXPECT_LT(bingham(x.data(), n, 3).p_value, 1e-6);
  EXPECT_LT(ks_cdf(z, [](double t) { return (t + 1) / 2; }).p_value, 1e-6);
  EXPECT_LT(gine(x.data(), n, 3).p_value, 1e-6);
  // The correct sampler passes the same KS test (z uniform on [-1, 1], Archimedes).
  const auto u = uniform_sphere(n, 3, rng);
  std::vector<double> zu(n);
  for (std::size_t i = 0; i < n; ++i) zu[i] = u[3 * i + 2];
  EXPECT_GT(ks_cdf(zu, [](double t) { return (t + 1) / 2; }).p_value, 1e-3);
}

// ---------------------------------------------------------------------------------------
// Exactness, routes, sizes

TEST(StatsSphereTests, BinghamRoutesAgree) {
  // Scatter-matrix route (d <= n) and Gram route (d > n) give the same statistic.
  Rng rng(700);
  for (int d : {3, 12, 40}) {
    const std::size_t n = 30;
    const auto x = uniform_sphere(n, d, rng);
    const TestResult b = bingham(x.data(), n, d);
    double s = 0.0;
    for (std::size_t a = 0; a < n; ++a)
      for (std::size_t c = 0; c < n; ++c) {
        double t = 0.0;
        for (int k = 0; k < d; ++k) t += x[a * d + k] * x[c * d + k];
        s += t * t;
      }
    const double B = n * d * (d + 2.0) / 2 * (s / (double(n) * n) - 1.0 / d);
    EXPECT_NEAR(b.statistic, B, 1e-9 * std::max(1.0, std::fabs(B))) << d << " " << b.note;
  }
}

TEST(StatsSphereTests, RejectsBadInput) {
  std::vector<double> x(6, 0.5);
  EXPECT_THROW(rayleigh(x.data(), 3, 1), std::invalid_argument);
  EXPECT_THROW(bingham(x.data(), 0, 2), std::invalid_argument);
  EXPECT_THROW(gine(x.data(), 1, 2), std::invalid_argument);
  EXPECT_THROW(gine_limit(1), std::invalid_argument);
}

RC_GTEST_PROP(StatsSphereTests, SignFlipsAndRange, ()) {
  // Bingham and Gine are axial: flipping any point's sign changes nothing, bit for bit (both
  // the direct loops, d <= 8, and the Gram route above). p-values lie in [0, 1].
  const int d = *rc::gen::inRange(2, 14);
  const std::size_t n = *rc::gen::inRange(2, 40);
  Rng rng(*rc::gen::inRange(1, 1000000));
  auto x = uniform_sphere(n, d, rng);
  const TestResult g = gine(x.data(), n, d), b = bingham(x.data(), n, d), r = rayleigh(x.data(), n, d);
  for (const TestResult* t : {&g, &b, &r}) {
    RC_ASSERT(t->p_value >= 0.0);
    RC_ASSERT(t->p_value <= 1.0);
  }
  for (std::size_t i = 0; i < n; ++i)
    if (gsl_rng_uniform(rng.get()) < 0.5)
      for (int k = 0; k < d; ++k) x[i * d + k] = -x[i * d + k];
  RC_ASSERT(gine_statistic(x.data(), n, d) == g.statistic);
  RC_ASSERT(bingham(x.data(), n, d).statistic == b.statistic);
}

TEST(StatsSphereTests, DeterministicAndSized) {
  // d = 3, n = 10^4 and d = 1000, n = 2000: run, repeat bit for bit, record the time.
  for (auto [n, d] : std::vector<std::pair<std::size_t, int>>{{10000, 3}, {2000, 1000}}) {
    Rng rng(800 + d);
    const auto x = uniform_sphere(n, d, rng);
    const auto t0 = std::chrono::steady_clock::now();
    const TestResult g = gine(x.data(), n, d);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const TestResult b = bingham(x.data(), n, d);
    RecordProperty("gine_ms_d" + std::to_string(d), std::to_string(ms));
    EXPECT_EQ(gine(x.data(), n, d).statistic, g.statistic);
    EXPECT_EQ(gine(x.data(), n, d).p_value, g.p_value);
    EXPECT_GT(g.p_value, 1e-4) << d;
    EXPECT_GT(b.p_value, 1e-4) << d;
  }
  EXPECT_EQ(&gine_limit(7), &gine_limit(7));
}

}  // namespace

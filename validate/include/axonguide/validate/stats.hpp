#pragma once
// Statistical tests of uniformity on the sphere S^(d-1) (Rayleigh, Bingham, Gine) and
// one-sample Kolmogorov-Smirnov tests, with the pieces they are built from (Funk-Hecke
// coefficients of zonal kernels, the asymptotic law of Gine's statistic, the survival
// function of a weighted sum of chi-squares).
//
// Points are n rows of d doubles, row-major (x[i*d + k]); the sphere tests assume unit
// vectors. Everything is deterministic: the only random numbers, the order of Gine's blocks for
// large n, are Philox words of the point index.
//
// Gine's G_n (1975) as a degenerate V-statistic (derived in stats.cpp, checked by the tests):
//   G_n = n/2 - (d-1)/(2n) (Gamma((d-1)/2)/Gamma(d/2))^2 sum_{i<j} sin psi_ij
//       = (c_d/2) (V_n - n lambda_0),   c_d = (d-1)/2 (Gamma((d-1)/2)/Gamma(d/2))^2 = 1/E[sin psi],
// with V_n = (1/n) sum_{i,j} K(x_i.x_j) (diagonal included, K(1) = 0), K(t) = -sqrt(1-t^2) and
// lambda_0 = E K = -1/c_d. Under H0, G_n -> sum_{k>=1} (c_d/2) lambda_k chi2_{dim_k} (only even
// k have lambda_k != 0, and those are > 0); mean exactly 1/2, variance (c_d^2/2)(1-1/d) - 1/2.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace axg::validate {

struct TestResult {
  std::string name;  // "Rayleigh", "Bingham", "Gine", "KS uniform", "KS cdf"
  double statistic;
  double p_value;    // P(statistic >= observed | H0), in [0,1]
  std::string note;  // the reference law and how the p-value was computed
};

// R = d n |mean|^2 ~ chi2_d.
TestResult rayleigh(const double* x, std::size_t n, int d);
// B = n d (d+2)/2 (tr(T^2) - 1/d), T the scatter matrix (1/n) sum x x^T, ~ chi2 with
// (d-1)(d+2)/2 df. tr(T^2) through T (Eigen, O(n d^2)) when d <= n, otherwise through the Gram
// matrix, (1/n^2) sum_{a,b} (x_a.x_b)^2 (O(n^2 d)).
TestResult bingham(const double* x, std::size_t n, int d);
// Gine's test; p-value from the asymptotic law (gine_limit) by Imhof's inversion. The cost stays
// O(n log n) in n: up to kGineExactMax points, G_n over all pairs (gine_statistic); above, for
// d = 2, the same G_n by sorting (gine_statistic_circle); for d >= 3, the sum of G over
// gine_block_count(n) disjoint blocks (gine_block_statistic), referred to the convolution of
// that many copies of the limit law. The note says which.
TestResult gine(const double* x, std::size_t n, int d);
inline constexpr std::size_t kGineExactMax = 20000;
// G_n alone (no p-value): 1/2 - (c_d/n) sum_{i<j} (sin psi_ij - 1/c_d), the centred form of the
// definition. O(n^2 d): direct loops for d <= 8, blocked Eigen Gram products above.
double gine_statistic(const double* x, std::size_t n, int d);
// G_n of d = 2 points in O(n log n), exact: the points are normalised (and a zero vector
// counted as gine_statistic counts it), folded onto the upper half circle, sorted by angle,
// and sin psi_ij = u_j x u_i summed through prefix sums (long double). Equals gine_statistic
// to ~1e-12 for unit vectors (tested).
double gine_statistic_circle(const double* x, std::size_t n);
// The blocks for n points: 1 up to kGineExactMax, else ceil(n / B) with
// B = max(kGineBlockMin, kGinePairBudget / n) points a block, so that the pair count stays at
// about kGinePairBudget / 2 up to n = 2*10^5 and grows as kGineBlockMin n / 2 above.
inline constexpr std::size_t kGineBlockMin = 2048;
inline constexpr std::size_t kGinePairBudget = 400000000;
std::size_t gine_block_count(std::size_t n);
// sum_b G(block b): the points in the order of a Philox word of their index (seed
// kGineOrderSeed, stream kValidation, step kGineOrderStep), cut into `blocks` consecutive
// runs of floor or ceil n/blocks points. Blocks run in parallel; the sum is in block order.
inline constexpr std::uint64_t kGineOrderSeed = 2014;
inline constexpr std::uint32_t kGineOrderStep = 0x6196u;
double gine_block_statistic(const double* x, std::size_t n, int d, std::size_t blocks);
// One-sample KS against U(0,1): D_n = sup |F_n - F|. p-value exact (Marsaglia-Tsang-Wang 2003)
// for n <= 1000, otherwise kolmogorov_q((sqrt(n) + 0.12 + 0.11/sqrt(n)) D_n) (Stephens 1970).
TestResult ks_uniform(std::vector<double> u);
// KS of v against a continuous cdf: ks_uniform of cdf(v_i).
TestResult ks_cdf(std::vector<double> v, const std::function<double(double)>& cdf);
// P(K > lambda) for the Kolmogorov distribution: 2 sum_{j>=1} (-1)^(j-1) exp(-2 j^2 lambda^2) for
// lambda >= 1.18, 1 - sqrt(2 pi)/lambda sum_{j>=1} exp(-(2j-1)^2 pi^2/(8 lambda^2)) below (both
// series summed to double precision); 1 for lambda <= 0.
double kolmogorov_q(double lambda);
// P(D_n < d) for the two-sided one-sample KS statistic of n points: Marsaglia, Tsang and Wang,
// "Evaluating Kolmogorov's distribution", J. Stat. Softw. 8(18), 2003 (with their quick
// approximation for d^2 n > 7.24, or > 3.76 when n > 99). Cost O(n d)^3 log n: for moderate n.
double kolmogorov_cdf_exact(std::size_t n, double d);

// ---- Funk-Hecke coefficients of zonal kernels on S^(d-1) ----
// Gegenbauer polynomials of dimension d normalised to P_k(1) = 1 (d = 2: Chebyshev T_k):
// P_0..P_kmax at t.
std::vector<double> gegenbauer(int d, int kmax, double t);
// Dimension of the degree-k spherical harmonics in R^d: (2k+d-2)/(k+d-2) binom(k+d-2, k)
// (1 for k = 0; 2 for d = 2, k >= 1). May be +inf for huge k and d; log form alongside.
double harmonic_dimension(int k, int d);
double log_harmonic_dimension(int k, int d);
// lambda_k = int_0^pi K(theta) P_k(cos theta) sin^(d-2) theta dtheta / int_0^pi sin^(d-2) theta dtheta,
// k = 0..kmax, for a kernel given as a function of the angle theta (K(theta) = kernel(cos theta)).
// Gauss-Legendre in theta (nodes by Newton's method to full precision: GSL's glfixed rule is off
// by ~5e-11 for untabulated sizes) on [pi/2 - delta, pi/2 + delta], where sin^(d-2) drops below
// e^-80 of its peak outside (the whole [0, pi] for d <= 20 or so), the weight taken as
// exp((d-2) log sin theta), same rule for numerator and denominator; nodes = 0 picks
// 48 + (kmax + d) delta nodes, enough for trigonometric polynomials of degree kmax + d with a
// factor of 2 to spare. Accuracy ~1e-15 absolute (tested: K = t^2, K = P_j up to d = 1000, the
// Gine kernel's closed forms for d = 2, 3).
std::vector<double> funk_hecke_angle(const std::function<double(double)>& kernel_of_angle, int d, int kmax,
                                     int nodes = 0);
// The same for a kernel given as a function of t = cos theta.
std::vector<double> funk_hecke(const std::function<double(double)>& kernel, int d, int kmax, int nodes = 0);

// ---- weighted sums of chi-squares ----
// Q = shift + sum_j weight[j] chi2_{dof[j]} (independent), weights > 0.
struct WeightedChiSquare {
  std::vector<double> weight;
  std::vector<double> dof;
  double shift = 0.0;
  double mean() const;
  double variance() const;
};
// P(Q > x) by Imhof's (1961) inversion: 1/2 + (1/pi) int_0^inf sin(theta(u)) / (u rho(u)) du,
// theta(u) = 1/2 sum h_j atan(w_j u) - (x - shift) u/2, rho(u) = prod (1 + w_j^2 u^2)^(h_j/4).
// The integral is cut at U where the bound 1/(pi rho(U) s(U)) on the rest (s = u rho'/rho) is
// below 1e-12, and [0, U] is covered by 16-point Gauss-Legendre panels over which the phase
// turns by at most 3 rad, 2^18 panels at most. Absolute error below 1e-12 against exact cases
// with 5 or more degrees of freedom in all (a lone chi2_1, where the panel cap binds: 4e-9).
// Cost O(panels * 16 * terms): ~1-10 ms for the Gine laws (d = 2 the slowest).
double weighted_chisq_sf(const WeightedChiSquare& q, double x);

// ---- the limit law of Gine's G_n ----
struct GineLimit {
  int d = 0;
  double c = 0.0;                  // c_d = 1/E[sin psi]
  std::vector<double> lambda;      // Funk-Hecke coefficients of K(t) = -sqrt(1-t^2), k = 0..kmax
  std::vector<double> dim;         // dim_k, k = 0..kmax (+inf where it overflows)
  int kmax = 0;                    // last degree kept
  WeightedChiSquare law;           // weights (c/2) lambda_k, dof dim_k, even k in 2..kmax; shift = tail mean
  double mean = 0.5;               // exact mean of the full limit law
  double variance = 0.0;           // exact variance of the full limit law, (c^2/2)(1-1/d) - 1/2
  double tail_mean = 0.0;          // mean of the terms k > kmax (added to law as a constant)
  double tail_variance = 0.0;      // their variance (neglected): below 1e-6 variance, or kmax hit the cap
};
// Computed once per d and cached (thread-safe); the law does not depend on n. Terms are added
// (in batches) until the neglected variance is below 1e-6 of the total (and k >= 6), kmax at most
// 4096; in practice kmax = 112 for d = 2, 46 for d = 3, 10 for d = 10, 6 for d >= 19. (A cut on the
// neglected *mean* would not do: for large d about a third of the mean sits in degrees too high
// to enumerate, with no variance; it is exact here as the constant shift.)
const GineLimit& gine_limit(int d);
// c_d = (d-1)/2 (Gamma((d-1)/2)/Gamma(d/2))^2.
double gine_constant(int d);

}  // namespace axg::validate

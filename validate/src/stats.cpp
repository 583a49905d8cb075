#include "axonguide/validate/stats.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <numbers>
#include <stdexcept>

#include <Eigen/Dense>
#include <fmt/format.h>
#include <gsl/gsl_cdf.h>
#include <tbb/parallel_for.h>

#include "axonguide/core/random.hpp"

namespace axg::validate {

namespace {

constexpr double kPi = std::numbers::pi;
using RowMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

void check_points(const double* x, std::size_t n, int d, const char* who, std::size_t min_n) {
  if (d < 2) throw std::invalid_argument(fmt::format("{}: dimension d = {} (need d >= 2)", who, d));
  if (n < min_n) throw std::invalid_argument(fmt::format("{}: {} points (need at least {})", who, n, min_n));
  if (x == nullptr) throw std::invalid_argument(fmt::format("{}: no data", who));
}

// ---- sum_{i<j} f(x_i . x_j) ----
// Every pair is visited once, each row's terms summed in a row accumulator (in increasing j)
// that is then added to the total, so the result depends on n, d and the data only.

template <int D, class F>
double pair_sum_fixed(const double* x, std::size_t n, F f) {
  double total = 0.0;
  for (std::size_t i = 0; i + 1 < n; ++i) {
    double xi[D];
    for (int k = 0; k < D; ++k) xi[k] = x[i * D + k];
    double acc = 0.0;
    const double* xj = x + (i + 1) * D;
    for (std::size_t j = i + 1; j < n; ++j, xj += D) {
      double t = xi[0] * xj[0];
      for (int k = 1; k < D; ++k) t += xi[k] * xj[k];
      acc += f(t);
    }
    total += acc;
  }
  return total;
}

template <class F>
double pair_sum_gemm(const double* x, std::size_t n, int d, F f) {
  Eigen::Map<const RowMat> X(x, static_cast<Eigen::Index>(n), d);
  // Blocks of B rows against all later rows: at most ~2^21 doubles (16 MiB) of Gram matrix.
  const std::size_t B = std::clamp<std::size_t>((std::size_t{1} << 21) / n, 16, 512);
  std::vector<double> buf(std::min(B, n) * n);
  double total = 0.0;
  for (std::size_t i0 = 0; i0 < n; i0 += B) {
    const std::size_t b = std::min(B, n - i0), m = n - i0;
    Eigen::Map<RowMat> G(buf.data(), static_cast<Eigen::Index>(b), static_cast<Eigen::Index>(m));
    G.noalias() = X.middleRows(static_cast<Eigen::Index>(i0), static_cast<Eigen::Index>(b)) *
                  X.middleRows(static_cast<Eigen::Index>(i0), static_cast<Eigen::Index>(m)).transpose();
    for (std::size_t r = 0; r < b; ++r) {
      const double* g = buf.data() + r * m;
      double acc = 0.0;
      for (std::size_t c = r + 1; c < m; ++c) acc += f(g[c]);
      total += acc;
    }
  }
  return total;
}

template <class F>
double pair_sum(const double* x, std::size_t n, int d, F f) {
  switch (d) {
    case 2: return pair_sum_fixed<2>(x, n, f);
    case 3: return pair_sum_fixed<3>(x, n, f);
    case 4: return pair_sum_fixed<4>(x, n, f);
    case 5: return pair_sum_fixed<5>(x, n, f);
    case 6: return pair_sum_fixed<6>(x, n, f);
    case 7: return pair_sum_fixed<7>(x, n, f);
    case 8: return pair_sum_fixed<8>(x, n, f);
    default: return pair_sum_gemm(x, n, d, f);
  }
}

}  // namespace

// =====================================================================================
// Rayleigh and Bingham

TestResult rayleigh(const double* x, std::size_t n, int d) {
  check_points(x, n, d, "rayleigh", 1);
  std::vector<double> s(static_cast<std::size_t>(d), 0.0);
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < d; ++k) s[k] += x[i * d + k];
  double s2 = 0.0;
  for (double v : s) s2 += v * v;
  const double R = d * s2 / static_cast<double>(n);
  return {"Rayleigh", R, gsl_cdf_chisq_Q(R, d), fmt::format("chi2, {} df", d)};
}

TestResult bingham(const double* x, std::size_t n, int d) {
  check_points(x, n, d, "bingham", 1);
  const double nn = static_cast<double>(n);
  double sum_sq;  // n^2 tr(T^2) = sum_{a,b} (x_a.x_b)^2 = ||X^T X||_F^2
  std::string route;
  if (static_cast<std::size_t>(d) <= n) {
    Eigen::Map<const RowMat> X(x, static_cast<Eigen::Index>(n), d);
    Eigen::MatrixXd S = Eigen::MatrixXd::Zero(d, d);
    S.selfadjointView<Eigen::Lower>().rankUpdate(X.transpose());
    double diag = 0.0, off = 0.0;
    for (int j = 0; j < d; ++j) {
      diag += S(j, j) * S(j, j);
      for (int i = j + 1; i < d; ++i) off += S(i, j) * S(i, j);
    }
    sum_sq = diag + 2.0 * off;
    route = "scatter matrix";
  } else {
    double diag = 0.0;
    for (std::size_t a = 0; a < n; ++a) {
      double q = 0.0;
      for (int k = 0; k < d; ++k) q += x[a * d + k] * x[a * d + k];
      diag += q * q;
    }
    sum_sq = diag + 2.0 * pair_sum(x, n, d, [](double t) { return t * t; });
    route = "Gram matrix";
  }
  const double trT2 = sum_sq / (nn * nn);
  const double B = nn * d * (d + 2.0) / 2.0 * (trT2 - 1.0 / d);
  const double df = (d - 1.0) * (d + 2.0) / 2.0;
  return {"Bingham", B, gsl_cdf_chisq_Q(B, df), fmt::format("chi2, {} df (tr T^2 via the {})", df, route)};
}

// =====================================================================================
// Funk-Hecke coefficients

std::vector<double> gegenbauer(int d, int kmax, double t) {
  if (d < 2 || kmax < 0) throw std::invalid_argument("gegenbauer: need d >= 2, kmax >= 0");
  std::vector<double> p(static_cast<std::size_t>(kmax) + 1);
  p[0] = 1.0;
  if (kmax >= 1) p[1] = t;
  for (int k = 1; k < kmax; ++k)
    p[k + 1] = ((2.0 * k + d - 2.0) * t * p[k] - k * p[k - 1]) / (k + d - 2.0);
  return p;
}

double log_harmonic_dimension(int k, int d) {
  if (k == 0) return 0.0;
  if (d == 2) return std::log(2.0);
  return std::log(2.0 * k + d - 2.0) - std::log(k + d - 2.0) + std::lgamma(k + d - 1.0) - std::lgamma(k + 1.0) -
         std::lgamma(d - 1.0);
}

double harmonic_dimension(int k, int d) {
  if (d < 2 || k < 0) throw std::invalid_argument("harmonic_dimension: need d >= 2, k >= 0");
  if (k == 0) return 1.0;
  if (d == 2) return 2.0;
  // binom(k+d-2, k) by the exact integer recurrence while it fits in 53 bits.
  double c = 1.0;
  for (int i = 1; i <= k; ++i) {
    if (c * (d - 2.0 + i) > 9.0e15) return std::exp(log_harmonic_dimension(k, d));
    c = c * (d - 2.0 + i) / i;
  }
  // (2k+d-2)/(k+d-2) binom(k+d-2,k) = binom(k+d-2,k) + binom(k+d-3,k-1).
  const double c1 = c * k / (k + d - 2.0);
  return std::round(c + c1);
}

namespace {

// Gauss-Legendre nodes and weights on [-1, 1] by Newton's method on the three-term recurrence,
// to full double precision. (GSL's gsl_integration_glfixed_table_alloc is exact only for its
// tabulated sizes; for others, e.g. n = 252, its rule is off by ~5e-11.)
void gauss_legendre(int n, std::vector<double>& x, std::vector<double>& w) {
  x.assign(static_cast<std::size_t>(n), 0.0);
  w.assign(static_cast<std::size_t>(n), 0.0);
  auto eval = [n](double z, double* dp) {  // P_n(z), P_n'(z)
    double p1 = 1.0, p2 = 0.0;
    for (int j = 1; j <= n; ++j) {
      const double p3 = p2;
      p2 = p1;
      p1 = ((2.0 * j - 1.0) * z * p2 - (j - 1.0) * p3) / j;
    }
    *dp = n * (p2 - z * p1) / ((1.0 - z) * (1.0 + z));
    return p1;
  };
  for (int i = 0; i < (n + 1) / 2; ++i) {
    double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 0.0;
    for (int it = 0; it < 100; ++it) {
      const double dz = eval(z, &dp) / dp;
      z -= dz;
      if (std::fabs(dz) <= 1e-16) break;
    }
    eval(z, &dp);
    const double wt = 2.0 / ((1.0 - z) * (1.0 + z) * dp * dp);
    x[i] = z;
    x[n - 1 - i] = -z;
    w[i] = w[n - 1 - i] = wt;
  }
  if (n % 2 == 1) x[n / 2] = 0.0;
}

}  // namespace

std::vector<double> funk_hecke_angle(const std::function<double(double)>& kernel_of_angle, int d, int kmax,
                                     int nodes) {
  if (d < 2 || kmax < 0) throw std::invalid_argument("funk_hecke: need d >= 2, kmax >= 0");
  // sin^(d-2) theta = exp((d-2) log sin theta) <= e^-80 for |theta - pi/2| >= delta.
  double delta = kPi / 2;
  if (d > 2) delta = std::min(kPi / 2, std::acos(std::exp(-80.0 / (d - 2.0))));
  const int N = nodes > 0 ? nodes : 48 + static_cast<int>(std::ceil((kmax + d) * delta));
  std::vector<double> gx, gw;
  gauss_legendre(N, gx, gw);
  std::vector<double> num(static_cast<std::size_t>(kmax) + 1, 0.0);
  double den = 0.0;
  for (int i = 0; i < N; ++i) {
    const double th = kPi / 2 + delta * gx[i], wt = delta * gw[i];
    const double w = d == 2 ? wt : wt * std::exp((d - 2.0) * std::log(std::sin(th)));
    den += w;
    const double kw = kernel_of_angle(th) * w;
    const double t = std::cos(th);
    double pm = 1.0, p = t;  // P_{k-1}, P_k
    num[0] += kw;
    if (kmax >= 1) num[1] += kw * t;
    for (int k = 1; k < kmax; ++k) {
      const double pn = ((2.0 * k + d - 2.0) * t * p - k * pm) / (k + d - 2.0);
      pm = p;
      p = pn;
      num[k + 1] += kw * p;
    }
  }
  for (double& v : num) v /= den;
  return num;
}

std::vector<double> funk_hecke(const std::function<double(double)>& kernel, int d, int kmax, int nodes) {
  return funk_hecke_angle([&](double th) { return kernel(std::cos(th)); }, d, kmax, nodes);
}

// =====================================================================================
// Weighted sums of chi-squares (Imhof)

double WeightedChiSquare::mean() const {
  double m = shift;
  for (std::size_t j = 0; j < weight.size(); ++j) m += weight[j] * dof[j];
  return m;
}

double WeightedChiSquare::variance() const {
  double v = 0.0;
  for (std::size_t j = 0; j < weight.size(); ++j) v += 2.0 * weight[j] * weight[j] * dof[j];
  return v;
}

double weighted_chisq_sf(const WeightedChiSquare& q, double x) {
  if (q.weight.size() != q.dof.size()) throw std::invalid_argument("weighted_chisq_sf: weight/dof sizes differ");
  for (std::size_t j = 0; j < q.weight.size(); ++j)
    if (!(q.weight[j] > 0.0) || !(q.dof[j] > 0.0) || !std::isfinite(q.dof[j]))
      throw std::invalid_argument("weighted_chisq_sf: weights and dof must be positive and finite");
  if (std::isnan(x)) return std::nan("");
  const double y = x - q.shift;
  if (!(y > 0.0)) return 1.0;  // Q >= shift
  if (q.weight.empty()) return 0.0;
  const std::size_t m = q.weight.size();
  double sum_hw = 0.0, sum_hw2 = 0.0;
  for (std::size_t j = 0; j < m; ++j) {
    sum_hw += q.dof[j] * q.weight[j];
    sum_hw2 += q.dof[j] * q.weight[j] * q.weight[j];
  }
  // log rho(u) and s(u) = u d log rho / du = 1/2 sum h a^2/(1+a^2), a = w u.
  auto log_rho = [&](double u, double* s) {
    double lr = 0.0, ss = 0.0;
    for (std::size_t j = 0; j < m; ++j) {
      const double a = q.weight[j] * u, a2 = a * a;
      lr += q.dof[j] * std::log1p(a2);
      ss += q.dof[j] * a2 / (1.0 + a2);
    }
    *s = 0.5 * ss;
    return 0.25 * lr;
  };
  // Upper limit: the rest of the integral is at most 1/(pi rho(U) s(U)) (s is increasing).
  constexpr double kTail = 1e-12;
  double U = 1.0 / std::sqrt(sum_hw2);
  for (int it = 0; it < 4000; ++it) {
    double s;
    const double lr = log_rho(U, &s);
    if (s > 0.0 && lr + std::log(kPi * s) > -std::log(kTail)) break;
    U *= 1.1;
  }
  // |theta'(u)| <= omega; panels over which the phase turns by <= 3 rad (and log rho, whose
  // derivative is <= sum h w / 4 <= omega, changes by <= 3).
  const double omega = 0.5 * (sum_hw + y);
  // At most 2^18 panels: a law with very few degrees of freedom in all (rho growing like a small
  // power of u) gets a shorter range and a larger error (documented in the header).
  constexpr double kMaxPanels = 262144.0;
  U = std::min(U, kMaxPanels * 3.0 / omega);
  const std::size_t panels = std::max<std::size_t>(8, static_cast<std::size_t>(std::ceil(U * omega / 3.0)));
  const double h = U / static_cast<double>(panels);
  // 16-point Gauss-Legendre on [-1, 1] (nodes > 0; the rule is symmetric).
  static const double gx[8] = {0.0950125098376374401853193, 0.2816035507792589132304605,
                               0.4580167776572273863424194, 0.6178762444026437484466718,
                               0.7554044083550030338951012, 0.8656312023878317438804679,
                               0.9445750230732325760779884, 0.9894009349916499325961542};
  static const double gw[8] = {0.1894506104550684962853967, 0.1826034150449235888667637,
                               0.1691565193950025381893121, 0.1495959888165767320815017,
                               0.1246289712555338720524763, 0.0951585116824927848099251,
                               0.0622535239386478928628438, 0.0271524594117540948517806};
  auto integrand = [&](double u) {
    double th = 0.0, lr = 0.0;
    for (std::size_t j = 0; j < m; ++j) {
      const double a = q.weight[j] * u;
      th += q.dof[j] * std::atan(a);
      lr += q.dof[j] * std::log1p(a * a);
    }
    const double theta = 0.5 * th - 0.5 * y * u;
    return std::sin(theta) / (u * std::exp(0.25 * lr));
  };
  double integral = 0.0;
  for (std::size_t p = 0; p < panels; ++p) {
    const double c = (static_cast<double>(p) + 0.5) * h, r = 0.5 * h;
    double acc = 0.0;
    for (int k = 0; k < 8; ++k) acc += gw[k] * (integrand(c - r * gx[k]) + integrand(c + r * gx[k]));
    integral += acc * r;
  }
  return std::clamp(0.5 + integral / kPi, 0.0, 1.0);
}

// =====================================================================================
// Gine

namespace {

// E[sin psi] = Gamma(d/2)^2 / ((d-1)/2 Gamma((d-1)/2)^2) = W_{d-1}/W_{d-2}, W_m = int_0^pi sin^m, by the
// Wallis recursion r_m = (m-1)/(m r_{m-1}) (r_1 = 2/pi, r_2 = pi/4) in long double. (gsl_sf_poch and
// lgamma differences are off by ~3e-13 at d = 1000, which is enough to spoil the exact variance
// 1 - 1/d - E[sin psi]^2 ~ 1/(2 d^2) used to truncate the limit law.)
long double mean_sin_psi(int d) {
  const long double pi = 3.141592653589793238462643383279502884L;
  long double r = 2.0L / pi;  // m = 1 (d = 2)
  for (int m = 2; m <= d - 1; ++m) r = static_cast<long double>(m - 1) / (static_cast<long double>(m) * r);
  return r;
}

}  // namespace

double gine_constant(int d) {
  if (d < 2) throw std::invalid_argument("gine_constant: need d >= 2");
  return static_cast<double>(1.0L / mean_sin_psi(d));
}

namespace {

std::unique_ptr<GineLimit> make_gine_limit(int d) {
  auto g = std::make_unique<GineLimit>();
  g->d = d;
  g->c = gine_constant(d);
  const double c = g->c;
  // Exact totals over k >= 1: sum dim lambda = K(1) - lambda_0 = 1/c;
  // sum dim lambda^2 = E[K(T)^2] - lambda_0^2 = (1 - E T^2) - 1/c^2 = 1 - 1/d - 1/c^2.
  const long double mu = mean_sin_psi(d);
  const double S1 = static_cast<double>(mu);
  const double S2 = static_cast<double>((1.0L - 1.0L / d) - mu * mu);
  constexpr double kVarFraction = 1e-6;
  constexpr int kCap = 4096;
  int kmax = 32;
  constexpr int kMinK = 6;  // at least the terms k = 2, 4, 6 (cheap, and the fit of the shape)
  for (;;) {
    g->lambda = funk_hecke_angle([](double th) { return -std::sin(th); }, d, kmax);
    double P2 = 0.0;
    int kcut = -1;
    for (int k = 2; k <= kmax; k += 2) {
      const double lam = g->lambda[k];
      if (lam > 0.0) P2 += std::exp(log_harmonic_dimension(k, d) + 2.0 * std::log(lam));
      if (k >= kMinK && S2 - P2 <= kVarFraction * S2) {
        kcut = k;
        break;
      }
    }
    if (kcut >= 0 || kmax >= kCap) {
      g->kmax = kcut >= 0 ? kcut : kmax;
      break;
    }
    kmax *= 2;
  }
  g->lambda.resize(static_cast<std::size_t>(g->kmax) + 1);
  g->dim.resize(g->lambda.size());
  double P1 = 0.0, P2 = 0.0;
  for (int k = 0; k <= g->kmax; ++k) {
    g->dim[k] = harmonic_dimension(k, d);
    if (k == 0 || k % 2 == 1) continue;  // odd k: lambda_k = 0 exactly (K is even)
    const double lam = g->lambda[k];
    if (!(lam > 0.0)) continue;  // only underflowed / rounding-level coefficients
    const double ldim = log_harmonic_dimension(k, d);
    P1 += std::exp(ldim + std::log(lam));
    P2 += std::exp(ldim + 2.0 * std::log(lam));
    g->law.weight.push_back(c / 2.0 * lam);
    g->law.dof.push_back(g->dim[k]);
  }
  g->mean = 0.5;
  g->variance = c * c / 2.0 * S2;
  g->tail_mean = c / 2.0 * (S1 - P1);
  g->tail_variance = c * c / 2.0 * std::max(0.0, S2 - P2);
  g->law.shift = g->tail_mean;
  return g;
}

}  // namespace

const GineLimit& gine_limit(int d) {
  if (d < 2) throw std::invalid_argument("gine_limit: need d >= 2");
  static std::mutex mutex;
  static std::map<int, std::unique_ptr<GineLimit>> cache;
  std::lock_guard<std::mutex> lock(mutex);
  auto& slot = cache[d];
  if (!slot) slot = make_gine_limit(d);
  return *slot;
}

double gine_statistic(const double* x, std::size_t n, int d) {
  check_points(x, n, d, "gine", 2);
  const double c = gine_constant(d), mu = 1.0 / c;  // mu = E[sin psi] under H0
  // G_n = n/2 - (c/n) sum_{i<j} sin psi_ij = 1/2 - (c/n) sum_{i<j} (sin psi_ij - mu): the centred
  // sum keeps the O(n) cancellation out of floating point.
  const double S = pair_sum(x, n, d, [mu](double t) { return std::sqrt(std::max(0.0, 1.0 - t * t)) - mu; });
  return 0.5 - c / static_cast<double>(n) * S;
}

double gine_statistic_circle(const double* x, std::size_t n) {
  check_points(x, n, 2, "gine", 2);
  // Each direction folded onto the upper half circle (sin psi is the same for u and -u), keyed
  // by a pseudo-angle 1 - u_x / (|u_x| + u_y) in [0, 2), increasing with the angle.
  struct Folded {
    double key, ux, uy;
  };
  std::vector<Folded> u;
  u.reserve(n);
  std::size_t zeros = 0;
  for (std::size_t i = 0; i < n; ++i) {
    double a = x[2 * i], b = x[2 * i + 1];
    const double r = std::sqrt(a * a + b * b);
    if (r == 0.0) {
      ++zeros;
      continue;
    }
    a /= r, b /= r;
    if (b < 0.0 || (b == 0.0 && a < 0.0)) a = -a, b = -b;
    u.push_back({1.0 - a / (std::fabs(a) + b), a, b});
  }
  std::stable_sort(u.begin(), u.end(), [](const Folded& p, const Folded& q) { return p.key < q.key; });
  // For j before i, the angle from u_j to u_i is in [0, pi): sin psi_ij = u_j x u_i, so
  // sum_{j<i} sin psi_ij = u_i.y sum_{j<i} u_j.x - u_i.x sum_{j<i} u_j.y.
  long double sx = 0.0L, sy = 0.0L, sum = 0.0L;
  for (const Folded& f : u) {
    sum += f.uy * sx - f.ux * sy;
    sx += f.ux;
    sy += f.uy;
  }
  // A zero vector has x_i.x_j = 0 with every point, which the pair sum counts as sin psi = 1.
  const long double nz = static_cast<long double>(u.size()), z = static_cast<long double>(zeros);
  sum += z * nz + z * (z - 1.0L) / 2.0L;
  const long double nn = static_cast<long double>(n), c = gine_constant(2);
  return static_cast<double>(0.5L - c / nn * (sum - nn * (nn - 1.0L) / 2.0L / c));
}

std::size_t gine_block_count(std::size_t n) {
  if (n <= kGineExactMax) return 1;
  const std::size_t b = std::max<std::size_t>(kGineBlockMin, kGinePairBudget / n);
  return (n + b - 1) / b;
}

double gine_block_statistic(const double* x, std::size_t n, int d, std::size_t blocks) {
  check_points(x, n, d, "gine", 2 * std::max<std::size_t>(blocks, 1));
  // The order: points sorted by a 64-bit Philox word of their index, so that the blocks are
  // random subsets whatever the order of the rows (a file sorted by z would otherwise give
  // blocks that are far from uniform).
  std::vector<std::pair<std::uint64_t, std::size_t>> order(n);
  for (std::size_t i = 0; i < n; ++i) {
    core::Rng rng(kGineOrderSeed, core::Stream::kValidation, i, kGineOrderStep);
    const std::uint32_t hi = rng.word32();
    order[i] = {core::join64(hi, rng.word32()), i};
  }
  std::sort(order.begin(), order.end());
  std::vector<double> g(blocks);
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
    const std::size_t lo = b * n / blocks, hi = (b + 1) * n / blocks;
    std::vector<double> part((hi - lo) * static_cast<std::size_t>(d));
    for (std::size_t i = lo; i < hi; ++i)
      std::copy_n(x + order[i].second * d, d, part.begin() + (i - lo) * d);
    g[b] = gine_statistic(part.data(), hi - lo, d);
  });
  double total = 0.0;  // in block order: the same for any thread count
  for (double v : g) total += v;
  return total;
}

TestResult gine(const double* x, std::size_t n, int d) {
  check_points(x, n, d, "gine", 2);
  const GineLimit& lim = gine_limit(d);
  const std::string law = fmt::format(
      "(Funk-Hecke, {} terms, k <= {}, tail mean {:.3g} as a constant, neglected tail variance {:.2g}), Imhof "
      "inversion, abs. error < 1e-10",
      lim.law.weight.size(), lim.kmax, lim.tail_mean, lim.tail_variance);
  if (n <= kGineExactMax || d == 2) {
    const double G = n <= kGineExactMax ? gine_statistic(x, n, d) : gine_statistic_circle(x, n);
    return {"Gine", G, weighted_chisq_sf(lim.law, G),
            fmt::format("{}asymptotic weighted chi-square {}",
                        n <= kGineExactMax ? "" : "G_n by sorting the angles (O(n log n)); ", law)};
  }
  // Above kGineExactMax: the sum of G over m disjoint blocks. Each block's G has the limit law
  // under H0 and the blocks are independent, so the sum has the m-fold convolution: the same
  // weights with m times the degrees of freedom and m times the shift.
  const std::size_t m = gine_block_count(n);
  const double T = gine_block_statistic(x, n, d, m);
  WeightedChiSquare sum = lim.law;
  for (double& h : sum.dof) h *= static_cast<double>(m);
  sum.shift *= static_cast<double>(m);
  return {"Gine", T, weighted_chisq_sf(sum, T),
          fmt::format("sum of G over {} blocks of {} to {} points in a fixed pseudo-random order; mean {}; law: {}-fold "
                      "convolution of the asymptotic weighted chi-square {}",
                      m, n / m, (n + m - 1) / m, 0.5 * static_cast<double>(m), m, law)};
}

// =====================================================================================
// Kolmogorov-Smirnov

double kolmogorov_q(double lambda) {
  if (std::isnan(lambda)) return lambda;
  if (lambda <= 0.0) return 1.0;
  if (lambda < 1.18) {
    const double a = -kPi * kPi / (8.0 * lambda * lambda);
    double s = 0.0;
    for (int j = 1; j < 100; ++j) {
      const double term = std::exp(a * (2.0 * j - 1.0) * (2.0 * j - 1.0));
      s += term;
      if (term < 1e-17 * s || term == 0.0) break;
    }
    return std::clamp(1.0 - std::sqrt(2.0 * kPi) / lambda * s, 0.0, 1.0);
  }
  double s = 0.0;
  for (int j = 1; j < 100; ++j) {
    const double term = std::exp(-2.0 * j * j * lambda * lambda);
    s += (j % 2 ? 1.0 : -1.0) * term;
    if (term < 1e-17 * s || term == 0.0) break;
  }
  return std::clamp(2.0 * s, 0.0, 1.0);
}

namespace {

// Marsaglia-Tsang-Wang: matrix power with a decimal exponent kept aside.
void mtw_multiply(const std::vector<double>& A, const std::vector<double>& B, std::vector<double>& C, int m) {
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) {
      double s = 0.0;
      for (int k = 0; k < m; ++k) s += A[i * m + k] * B[k * m + j];
      C[i * m + j] = s;
    }
}

void mtw_power(const std::vector<double>& A, int eA, std::vector<double>& V, int* eV, int m, std::size_t n) {
  if (n == 1) {
    V = A;
    *eV = eA;
    return;
  }
  mtw_power(A, eA, V, eV, m, n / 2);
  std::vector<double> B(static_cast<std::size_t>(m) * m);
  mtw_multiply(V, V, B, m);
  const int eB = 2 * (*eV);
  if (n % 2 == 0) {
    V = B;
    *eV = eB;
  } else {
    mtw_multiply(A, B, V, m);
    *eV = eA + eB;
  }
  if (V[(m / 2) * m + (m / 2)] > 1e140) {
    for (double& v : V) v *= 1e-140;
    *eV += 140;
  }
}

}  // namespace

double kolmogorov_cdf_exact(std::size_t n, double d) {
  if (n == 0) throw std::invalid_argument("kolmogorov_cdf_exact: n = 0");
  if (!(d > 0.0)) return 0.0;
  if (d >= 1.0) return 1.0;
  const double nd = static_cast<double>(n);
  const double s = d * d * nd;
  if (s > 7.24 || (s > 3.76 && n > 99)) return 1.0 - 2.0 * std::exp(-(2.000071 + .331 / std::sqrt(nd) + 1.409 / nd) * s);
  const int k = static_cast<int>(nd * d) + 1;
  const int m = 2 * k - 1;
  const double h = k - nd * d;
  std::vector<double> H(static_cast<std::size_t>(m) * m), Q(static_cast<std::size_t>(m) * m);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) H[i * m + j] = (i - j + 1 < 0) ? 0.0 : 1.0;
  for (int i = 0; i < m; ++i) {
    H[i * m] -= std::pow(h, i + 1);
    H[(m - 1) * m + i] -= std::pow(h, m - i);
  }
  H[(m - 1) * m] += (2 * h - 1 > 0 ? std::pow(2 * h - 1, m) : 0.0);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j)
      if (i - j + 1 > 0)
        for (int g = 1; g <= i - j + 1; ++g) H[i * m + j] /= g;
  int eQ = 0;
  mtw_power(H, 0, Q, &eQ, m, n);
  double v = Q[(k - 1) * m + k - 1];
  for (std::size_t i = 1; i <= n; ++i) {
    v = v * static_cast<double>(i) / nd;
    if (v < 1e-140) {
      v *= 1e140;
      eQ -= 140;
    }
  }
  v *= std::pow(10.0, eQ);
  return std::clamp(v, 0.0, 1.0);
}

TestResult ks_uniform(std::vector<double> u) {
  if (u.empty()) throw std::invalid_argument("ks_uniform: no values");
  for (double& v : u) {
    if (std::isnan(v)) throw std::invalid_argument("ks_uniform: NaN value");
    v = std::clamp(v, 0.0, 1.0);
  }
  std::sort(u.begin(), u.end());
  const std::size_t n = u.size();
  const double nd = static_cast<double>(n);
  double D = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    D = std::max(D, static_cast<double>(i + 1) / nd - u[i]);
    D = std::max(D, u[i] - static_cast<double>(i) / nd);
  }
  double p;
  std::string note;
  if (n <= 1000) {
    p = 1.0 - kolmogorov_cdf_exact(n, D);
    note = fmt::format("exact Kolmogorov distribution (Marsaglia-Tsang-Wang), n = {}", n);
  } else {
    const double sn = std::sqrt(nd);
    p = kolmogorov_q((sn + 0.12 + 0.11 / sn) * D);
    note = fmt::format("asymptotic Kolmogorov with Stephens' correction, n = {}", n);
  }
  return {"KS uniform", D, std::clamp(p, 0.0, 1.0), note};
}

TestResult ks_cdf(std::vector<double> v, const std::function<double(double)>& cdf) {
  for (double& x : v) x = cdf(x);
  TestResult r = ks_uniform(std::move(v));
  r.name = "KS cdf";
  return r;
}

}  // namespace axg::validate

#include "axonguide/placement/coordinate_marginal.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>
#include <gsl/gsl_cdf.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_sf_gamma.h>
#include <gsl/gsl_sf_result.h>

#include "axonguide/core/pmath.hpp"

namespace axg {
namespace {

// The portable log, log1p and exp (core/pmath.hpp), not libm's: the sampler's own
// arithmetic is the same on every CPU; only GSL's incomplete beta, log-beta and normal
// quantile remain library code.
namespace pm = core::pm;

constexpr int kMaxIterations = 200;
// A bisection is forced when the bracket has not halved for this many evaluations
// (a guard against Newton creeping along a noisy F).
constexpr int kMaxStepsWithoutHalving = 12;

// GSL's default error handler aborts, and the _e functions still call it (underflow of
// a tiny tail mass is reported as GSL_EUNDRFLW through it). Turn it off once; a
// function-local static is initialized exactly once even under concurrent first calls.
void quiet_gsl() {
  static const bool done = [] {
    gsl_set_error_handler_off();
    return true;
  }();
  (void)done;
}

void check_dimension(int d) {
  if (d < 2) {
    throw std::invalid_argument(
        fmt::format("coordinate_marginal: dimension d = {} must be >= 2", d));
  }
}

// I_x(a, b) from GSL; an underflowed (|I| < DBL_MIN) result counts as 0.
double beta_inc(double a, double b, double x) {
  gsl_sf_result r;
  const int status = gsl_sf_beta_inc_e(a, b, x, &r);
  if (status == GSL_SUCCESS) return r.val;
  if (status == GSL_EUNDRFLW) return 0.0;
  throw std::runtime_error(fmt::format(
      "coordinate_marginal: gsl_sf_beta_inc_e({}, {}, {}) failed: {}", a, b, x,
      gsl_strerror(status)));
}

// The law of one coordinate for dimension d.
struct Law {
  int d = 0;
  double b = 0.0;        // (d - 1) / 2, the second beta parameter
  double split = 0.0;    // GSL uses its continued fraction directly for I_s(1/2, b) iff
                         // s < (a + 1) / (a + b + 2), a = 1/2; beyond it, I_y(b, 1/2)
                         // with y = 1 - s is the direct one
  double ln_beta = 0.0;  // ln B(1/2, b), the log of the density's normalizer
};

Law make_law(int d) {
  Law law;
  law.d = d;
  law.b = 0.5 * (static_cast<double>(d) - 1.0);
  law.split = (0.5 + 1.0) / (0.5 + law.b + 2.0);
  gsl_sf_result r;
  const int status = gsl_sf_lnbeta_e(0.5, law.b, &r);
  if (status != GSL_SUCCESS) {
    throw std::runtime_error(fmt::format("coordinate_marginal: gsl_sf_lnbeta_e(1/2, {}) failed: {}",
                                         law.b, gsl_strerror(status)));
  }
  law.ln_beta = r.val;
  return law;
}

// 1 - t^2 for t in [0, 1], to a few ulps and non-increasing in t (so that the masses
// below do not wobble at the ulp level): for t >= 1/2, 1 - t is exact and the rounded
// product (1 - t) * fl(1 + t) cannot increase with t (the exact factor falls by more
// than the rounded one can rise, since t > 1/3); below 1/2, 1 - fl(t * t) is a chain
// of monotone roundings with no cancellation (t^2 <= 1/4).
double one_minus_square(double t) {
  return t >= 0.5 ? (1.0 - t) * (1.0 + t) : 1.0 - t * t;
}

// For t in [0, 1]: the tail mass P(|x| > t) = I_{1-t^2}(b, 1/2) when `tail`, otherwise
// the central mass P(|x| <= t) = I_{t^2}(1/2, b). GSL is always called in the
// orientation where its continued fraction is applied directly, with both t^2 and
// 1 - t^2 formed here to full relative accuracy; the small one of the
// two masses therefore keeps its relative accuracy, the other is its complement.
double mass(const Law& law, double t, bool tail) {
  if (law.d == 3) return tail ? 1.0 - t : t;  // I_{t^2}(1/2, 1) = t exactly
  const double s = t * t;
  if (s < law.split) {
    const double a = beta_inc(0.5, law.b, s);
    return tail ? 1.0 - a : a;
  }
  const double y = one_minus_square(t);
  const double bt = beta_inc(law.b, 0.5, y);
  return tail ? bt : 1.0 - bt;
}

// f_d(t) for t in [0, 1].
double density(const Law& law, double t) {
  if (law.d == 3) return 0.5;
  const double s = t * t;
  const double ln_y = s < 0.5 ? pm::log1p(-s) : pm::log(one_minus_square(t));
  return pm::exp(0.5 * (static_cast<double>(law.d) - 3.0) * ln_y - law.ln_beta);
}

// Starting point for |x| given the lower-tail probability p in (0, 1/2).
double start_point(const Law& law, double p, bool tail_mode, double target) {
  double t0 = -1.0;
  if (tail_mode) {
    // Leading term of the tail: I_y(b, 1/2) ~ y^b / (b B(b, 1/2)) for small y.
    const double ln_y = (pm::log(target) + pm::log(law.b) + law.ln_beta) / law.b;
    if (ln_y < -1.3862943611198906) {  // y < 1/4, where the leading term is adequate
      t0 = std::sqrt(1.0 - pm::exp(ln_y));
    }
  }
  if (t0 < 0.0) {
    // x = T / sqrt(T^2 + nu) exactly, T ~ Student-t with nu = d - 1 degrees of freedom;
    // T from the normal quantile by the Cornish-Fisher expansion in 1/nu.
    const double nu = static_cast<double>(law.d) - 1.0;
    const double w = -gsl_cdf_ugaussian_Pinv(p);  // >= 0
    const double w2 = w * w;
    const double tq = w + w * (w2 + 1.0) / (4.0 * nu) +
                      w * ((5.0 * w2 + 16.0) * w2 + 3.0) / (96.0 * nu * nu) +
                      w * (((3.0 * w2 + 19.0) * w2 + 17.0) * w2 - 15.0) / (384.0 * nu * nu * nu);
    t0 = tq / std::sqrt(tq * tq + nu);
  }
  // Strictly inside the initial bracket (0, 1).
  constexpr double kBelowOne = 1.0 - 0x1p-53;
  if (!(t0 > std::numeric_limits<double>::min())) t0 = std::numeric_limits<double>::min();
  if (!(t0 < kBelowOne)) t0 = kBelowOne;
  return t0;
}

CoordinateMarginalSolve solve(double u, int d) {
  if (!(u > 0.0 && u < 1.0)) {
    throw std::invalid_argument(
        fmt::format("coordinate_marginal_inverse: u = {} must lie in (0, 1)", u));
  }
  check_dimension(d);
  quiet_gsl();
  const Law law = make_law(d);

  // Symmetry: solve for t = |x| from the lower-tail probability p = min(u, 1 - u)
  // (1 - u is exact for u >= 1/2), then attach the sign.
  const bool upper = u >= 0.5;
  const double p = upper ? 1.0 - u : u;
  if (p == 0.5) return {0.0, 0};
  // Two formulations, both with an exact target and a residual r(t) increasing in t
  // with dr/dt = 2 f_d(t):
  //   tail    (p <= 1/4): r = 2p - P(|x| > t)         (relative accuracy down to p ~ 1e-300)
  //   central (p >  1/4): r = P(|x| <= t) - (1 - 2p)  (1 - 2p exact; relative accuracy near 0)
  const bool tail_mode = p <= 0.25;
  const double target = tail_mode ? 2.0 * p : 1.0 - 2.0 * p;
  const double ln_target = pm::log(target);
  const bool log_newton = tail_mode && d != 3;  // for d = 3 the tail is linear in t

  double lo = 0.0, hi = 1.0;
  double r_lo = tail_mode ? target - 1.0 : -target;  // r(0)
  double r_hi = tail_mode ? target : 1.0 - target;   // r(1)
  double t = start_point(law, p, tail_mode, target);
  double step_old = hi - lo, step = hi - lo;  // the last two steps taken
  double width_at_halving = hi - lo;
  int since_halving = 0;  // evaluations since the bracket last halved
  int close_run = 0;      // consecutive end-game steps that did not cross the root
  bool last_negative = true;

  const auto finish = [&](double tt, int iterations) {
    return CoordinateMarginalSolve{upper ? tt : -tt, iterations};
  };

  for (int it = 1; it <= kMaxIterations; ++it) {
    const double m = mass(law, t, tail_mode);
    const double r = tail_mode ? target - m : m - target;
    if (r == 0.0) return finish(t, it);
    const bool negative = r < 0.0;
    if (negative) {
      lo = t;
      r_lo = r;
    } else {
      hi = t;
      r_hi = r;
    }
    // Adjacent doubles bracket the root: take the one with the smaller residual.
    if (std::nextafter(lo, 2.0) >= hi) {
      return finish(std::fabs(r_hi) < std::fabs(r_lo) ? hi : lo, it);
    }
    if (negative != last_negative) close_run = 0;
    last_negative = negative;
    if (hi - lo <= 0.5 * width_at_halving) {
      width_at_halving = hi - lo;
      since_halving = 0;
    } else {
      ++since_halving;
    }

    const double ulp = std::nextafter(t, 2.0) - t;
    const double mid = lo + 0.5 * (hi - lo);
    double tn = mid;
    if (hi - lo <= 8.0 * ulp) {
      // End game inside a few ulps: bisect to adjacency (at most three more steps).
    } else {
      // Newton correction t_new = t - dn. In the tail (d != 3), Newton on
      // h(t) = ln(2p) - ln P(|x| > t) (h' = 2 f / P): the tail is close to a power of
      // 1 - t^2, so its logarithm is nearly linear and Newton converges from far out.
      const double f2 = 2.0 * density(law, t);
      const double dn = log_newton ? (ln_target - pm::log(m)) * m / f2 : r / f2;
      const double newton = t - dn;
      const bool inside = std::isfinite(newton) && newton > lo && newton < hi;
      if (std::isfinite(dn) && std::fabs(dn) <= 0x1p-20 * t) {
        // Close to the root (quadratic convergence leaves an error far below |dn|), so
        // aim a few ulps past it: the next evaluation lands on the other side and the
        // bracket collapses instead of being approached from one side only. The
        // overshoot doubles while it fails to cross (noise in F at the ulp level).
        // Once the far end is within a few overshoots, the bracket is a handful of ulps
        // wide and F is flat at that scale: bisect.
        const double over = std::ldexp(2.0 * ulp, std::min(close_run, 60));
        const double far = negative ? hi - newton : newton - lo;
        const double aimed = newton + (negative ? over : -over);
        ++close_run;
        if (far > 4.0 * over && aimed > lo && aimed < hi) tn = aimed;
      } else if (inside && std::fabs(2.0 * dn) <= std::fabs(step_old) &&
                 since_halving < kMaxStepsWithoutHalving) {
        tn = newton;
      }
      // Otherwise (Newton leaves the bracket, or did not at least halve the step before
      // last, or the bracket stopped shrinking): bisect.
    }
    if (tn == mid && since_halving >= kMaxStepsWithoutHalving) since_halving = 0;
    step_old = step;
    step = tn - t;
    t = tn;
  }
  throw std::runtime_error(fmt::format(
      "coordinate_marginal_inverse: no convergence in {} iterations for u = {}, d = {}",
      kMaxIterations, u, d));
}

}  // namespace

double coordinate_marginal_cdf(double x, int d) {
  check_dimension(d);
  if (std::isnan(x)) return x;
  if (x <= -1.0) return 0.0;
  if (x >= 1.0) return 1.0;
  quiet_gsl();
  const Law law = make_law(d);
  const double t = std::fabs(x);
  if (x < 0.0) return 0.5 * mass(law, t, /*tail=*/true);
  // x >= 0: one rounding on top of whichever mass GSL gives directly.
  if (law.d == 3 || t * t < law.split) return 0.5 + 0.5 * mass(law, t, /*tail=*/false);
  return 1.0 - 0.5 * mass(law, t, /*tail=*/true);
}

double coordinate_marginal_pdf(double x, int d) {
  check_dimension(d);
  if (std::isnan(x)) return x;
  if (x < -1.0 || x > 1.0) return 0.0;
  quiet_gsl();
  return density(make_law(d), std::fabs(x));
}

CoordinateMarginalSolve coordinate_marginal_inverse_detail(double u, int d) {
  return solve(u, d);
}

double coordinate_marginal_inverse(double u, int d) { return solve(u, d).x; }

}  // namespace axg

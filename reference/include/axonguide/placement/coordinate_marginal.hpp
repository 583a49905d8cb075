#pragma once
// One coordinate of a uniform point on the unit sphere S^(d-1) in R^d (d >= 2).
//
// For X uniform on S^(d-1), a single coordinate x = X_i has density and CDF
//
//   f_d(x) = (1 - x^2)^((d-3)/2) / B(1/2, (d-1)/2)                      on [-1, 1],
//   F_d(x) = 1/2 + sign(x) * I_{x^2}(1/2, (d-1)/2) / 2,
//
// with I the regularized incomplete beta function (GSL's gsl_sf_beta_inc_e; the one
// documented library exception of the determinism contract, host-only placement code).
// Special cases: d = 2 is the arcsine law (f infinite at +-1, x = -cos(pi u)); d = 3 is
// the uniform law (F linear, x = 2u - 1). Equivalently x = T / sqrt(T^2 + d - 1) with T
// Student-t with d - 1 degrees of freedom, which is used for the starting point.
//
// Accuracy. Both tails are computed from the tail mass P(|x| > t) = I_{1-t^2}((d-1)/2, 1/2)
// and the centre from P(|x| <= t) = I_{t^2}(1/2, (d-1)/2), each evaluated in the
// orientation where GSL applies its continued fraction directly, with 1 - t^2 formed
// accurately and monotonically in t ((1 - t)(1 + t) for t >= 1/2, 1 - t*t below); so
// F_d(x) for x < 0 carries a relative (not absolute) error, down to F ~ 1e-300 (below
// DBL_MIN GSL reports underflow and the mass counts as 0). For d = 3 the masses are the exact linear forms (GSL's beta_inc at
// (1/2, 1) is off by up to ~250 ulp for small t, which would spoil x = 2u - 1).
// The computed F carries a relative noise of about (d/2) eps (GSL's prefactor
// exp(b ln y + ...) turns one rounding into b ulps), so adjacent doubles can be out of
// order by that much; measured against 60-digit roots the inverse is within 2.2e-15
// relative (tails: within an ulp), and consecutive u can come out reordered by up to
// ~6e-15 relative.
//
// All functions are pure: same inputs, same output bits on the same GSL build, whatever the
// CPU's libm (their own log, log1p and exp are core/pmath.hpp's), no state (apart from
// turning GSL's abort-on-error handler off, once, thread-safely).
// Throws std::invalid_argument for d < 2 (and, for the inverse, u outside (0, 1) or NaN).
namespace axg {

// F_d(x); 0 for x <= -1, 1 for x >= 1, NaN for NaN.
double coordinate_marginal_cdf(double x, int d);

// f_d(x), normalized on [-1, 1]; 0 outside, +inf at x = +-1 for d = 2.
double coordinate_marginal_pdf(double x, int d);

// The x in [-1, 1] with F_d(x) = u, u in (0, 1), any d >= 2 (tested up to d = 1000;
// larger d works as long as GSL's beta_inc converges). Odd symmetry is exact by
// construction: the solver works on |x| with p = min(u, 1 - u), so whenever 1 - u is
// exact (always for u >= 1/2), x(1 - u) == -x(u) bit for bit. u = 1/2 gives +0.
// The result is the double t* (with sign attached) among the two neighbours of the root
// of the computed F that has the smaller residual; for u below DBL_MIN (subnormal u)
// the tail mass underflows in GSL and the result is only as good as that allows.
// Method: safeguarded Newton on |x| in the bracket [0, 1] (Newton on the log of the tail
// mass in the tails; bisection when a step leaves the bracket or fails to halve), started
// from the Student-t / Cornish-Fisher approximation or the leading tail term, with a few
// deliberate ulp overshoots at the end so that the bracket closes to adjacent doubles.
// About 6 F evaluations on average (at most 17 seen for d <= 1000), ~2-3 us per call.
// Throws std::runtime_error if it does not converge within 200 evaluations (it is not
// expected to).
double coordinate_marginal_inverse(double u, int d);

// Same as coordinate_marginal_inverse, also reporting the number of F evaluations
// (iterations) used; for tests and benchmarks.
struct CoordinateMarginalSolve {
  double x = 0.0;
  int iterations = 0;
};
CoordinateMarginalSolve coordinate_marginal_inverse_detail(double u, int d);

}  // namespace axg

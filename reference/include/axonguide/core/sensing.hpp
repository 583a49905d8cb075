#pragma once
// Sensing at the growth cone (SPEC §3.4): concentration C and gradient from each field,
// then gamma = C/K_d and mu = |grad C| w / C. The particle estimators are in
// particles.hpp (particle_gather); the exact fields are here.
#include <cmath>

#include "cues.hpp"
#include "hd.hpp"
#include "pmath.hpp"
#include "vec3.hpp"

namespace axg::core {

// An exact sample: the gradient is its own check.
AXG_HDI CueSample exact_sample(double c, Vec3 grad) { return {c, grad, grad}; }

// ---- The sensing ball (the count form's target) ------------------------------------------
//
// A counting growth cone reads the molecules in its ball of radius r about x: their mean
// concentration cbar = (1/V) int_ball C and their dipole int_ball C(x + y) y / r dy / m. A
// sample carries the dipole as an effective gradient g = (5 / (V r^2)) int_ball C(x + y) y dy,
// so that the count decision's mean dipole g V r / (5 m) is exact (g = grad C for a linear
// field). The fields that solve (laplacian - kappa^2) C = 0 in the ball (the analytic field
// away from its source, an exponential imposed profile) have the mean-value properties
//   cbar = C(x) M0(kappa r),  g = grad C(x) M1(kappa r),
//   M0(z) = 3 (z cosh z - sinh z) / z^3 = 3 i1(z) / z,   M1(z) = 15 i2(z) / z^2,
// with i1, i2 the modified spherical Bessel functions (the l = 0 and l = 1 parts of C about x).
// ball_factors returns M0 e^(-s) and M1 e^(-s) for a shift s >= z (so that nothing overflows
// when the caller's C carries e^(-s)); small z by their series.
struct BallFactors {
  double mean, dipole;
};
AXG_HDI BallFactors ball_factors(double z, double shift) {
  if (z < 0.02) {  // M0 = 1 + z^2/10 + z^4/280, M1 = 1 + z^2/14 + z^4/504: error below 1e-14
    const double z2 = z * z, e = pm::exp(-shift);
    return {(1.0 + z2 / 10.0 + z2 * z2 / 280.0) * e, (1.0 + z2 / 14.0 + z2 * z2 / 504.0) * e};
  }
  const double up = pm::exp(z - shift), down = pm::exp(-z - shift);  // e^z e^(-s), e^(-z) e^(-s)
  const double z2 = z * z, z3 = z2 * z;
  // z cosh z - sinh z = ((z - 1) e^z + (z + 1) e^(-z)) / 2
  const double m0 = 1.5 * ((z - 1.0) * up + (z + 1.0) * down) / z3;
  // (z^2 + 3) sinh z - 3 z cosh z = ((z^2 - 3z + 3) e^z - (z^2 + 3z + 3) e^(-z)) / 2
  const double m1 = 7.5 * ((z2 - 3.0 * z + 3.0) * up - (z2 + 3.0 * z + 3.0) * down) / (z3 * z2);
  return {m0, m1};
}

// The ball about x of the analytic field of one source: the mean-value formulas when the
// source lies outside the ball (d >= r), and when it lies inside, the integrals of the
// expansion e^(-kappa R) / R = kappa sum_l (2l + 1) i_l(kappa rho<) k_l(kappa rho>) P_l over
// shells: the l = 0 part gives the mean, the l = 1 part the dipole (toward the source), with
// int z^3 i1 = z^3 i2 and int z^3 k1 = -z^3 k2 (docs/methods.md §2.6).
AXG_HDI CueSample analytic_ball_sample(Vec3 x, const CueParams& cue, const SenseParams& p);

// Steady state of a point source with decay: c(r) = S e^(-r/lambda) / r with
// S = a Q / (dt 4 pi D), evaluated at max(r, rmin) so that it stays finite as r -> 0;
// the gradient points along (x - s) and is zero at r = 0.
AXG_HDI CueSample analytic_sample(Vec3 x, const CueParams& cue, const SenseParams& p) {
  const Vec3 d = x - cue.position;
  const double r = norm(d);
  const Vec3 zero{0.0, 0.0, 0.0};
  if (!(r < HUGE_VAL)) return exact_sample(0.0, zero);  // |d|^2 overflowed: c has long reached 0
  const double re = r > p.analytic_rmin ? r : p.analytic_rmin;
  const double c = cue.analytic_scale * pm::exp(-re * cue.inv_lambda) / re;
  if (r == 0.0) return exact_sample(c, zero);
  // dc/dr = -c (1/r + 1/lambda); along the unit vector d/r.
  const double dcdr = -c * (1.0 / re + cue.inv_lambda);
  return exact_sample(c, (dcdr / r) * d);
}

namespace detail {

// Functions of the ball integrals, stable at small z (their series below 0.5) and at large z
// (a shift s multiplies what grows like e^z by e^(-s)).
// z^3 i1(z) = z (z cosh z - sinh z), times e^(-s)
AXG_HDI double i1z3(double z, double shift) {
  if (z < 0.5) {  // z^4/3 + z^6/30 + z^8/840 + z^10/45360 + z^12/3991680
    const double z2 = z * z, z4 = z2 * z2;
    return z4 * (1.0 / 3.0 + z2 * (1.0 / 30.0 + z2 * (1.0 / 840.0 + z2 * (1.0 / 45360.0 + z2 / 3991680.0)))) *
           pm::exp(-shift);
  }
  return 0.5 * z * ((z - 1.0) * pm::exp(z - shift) + (z + 1.0) * pm::exp(-z - shift));
}
// z^3 i2(z) = (z^2 + 3) sinh z - 3 z cosh z, times e^(-s)
AXG_HDI double i2z3(double z, double shift) {
  if (z < 0.5) {  // z^5/15 + z^7/210 + z^9/7560 + z^11/498960 + z^13/51891840
    const double z2 = z * z, z5 = z2 * z2 * z;
    return z5 * (1.0 / 15.0 + z2 * (1.0 / 210.0 + z2 * (1.0 / 7560.0 + z2 * (1.0 / 498960.0 + z2 / 51891840.0)))) *
           pm::exp(-shift);
  }
  return 0.5 * ((z * z - 3.0 * z + 3.0) * pm::exp(z - shift) - (z * z + 3.0 * z + 3.0) * pm::exp(-z - shift));
}
// sum_{n=2}^{16} (-1)^n c_n z^n / n! with c_n = n - 1 (form 0) or (n - 1)(n - 3) (form 1);
// for z < 0.5 the next term is below 1e-16 of the first.
AXG_HDI double alternating_series(double z, int form) {
  double term = z, sum = 0.0;  // z^n / n!
  for (int n = 2; n <= 16; ++n) {
    term = term * z / static_cast<double>(n);
    const double coef = form == 0 ? static_cast<double>(n - 1) : static_cast<double>((n - 1) * (n - 3));
    sum += ((n % 2) ? -1.0 : 1.0) * coef * term;
  }
  return sum;
}
// 1 - e^(-z) (1 + z) = sum_{n>=2} (-1)^n (n - 1) z^n / n!
AXG_HDI double g1(double z) {
  if (z < 0.5) return alternating_series(z, 0);
  return 1.0 - pm::exp(-z) * (1.0 + z);
}
// 3 - e^(-z) (z^2 + 3 z + 3) = -sum_{n>=2} (-1)^n (n - 1)(n - 3) z^n / n!
AXG_HDI double h2(double z) {
  if (z < 0.5) return -alternating_series(z, 1);
  return 3.0 - pm::exp(-z) * (z * z + 3.0 * z + 3.0);
}
// sinh(z) / z
AXG_HDI double sinhc(double z) {
  if (z < 0.5) {
    const double z2 = z * z;
    return 1.0 + z2 * (1.0 / 6.0 + z2 * (1.0 / 120.0 + z2 * (1.0 / 5040.0 + z2 * (1.0 / 362880.0 + z2 / 39916800.0))));
  }
  return 0.5 * (pm::exp(z) - pm::exp(-z)) / z;
}

}  // namespace detail

AXG_HDI CueSample analytic_ball_sample(Vec3 x, const CueParams& cue, const SenseParams& p) {
  const Vec3 a = cue.position - x;  // toward the source
  const double d = norm(a);
  const double r = p.radius, kappa = cue.inv_lambda, s = cue.analytic_scale;
  const Vec3 zero{0.0, 0.0, 0.0};
  if (!(d < HUGE_VAL)) return exact_sample(0.0, zero);
  if (d >= r) {  // outside the ball: the mean-value formulas on the field at x
    const BallFactors f = ball_factors(kappa * r, kappa * d);  // C and grad C carry e^(-kappa d)
    const double c = s / d;                                   // C e^(kappa d)
    const double slope = c * (1.0 / d + kappa);               // |grad C| e^(kappa d), toward the source
    return exact_sample(c * f.mean, (slope * f.dipole / d) * a);
  }
  // The source inside the ball: with rho< = min(rho, d), rho> = max(rho, d),
  //   mean   = 3 S (T1 + T2) / r^3,  T1 = int_0^d rho sinh(k rho) drho e^(-k d) / (k d),
  //                                  T2 = sinh(k d) / (k d) int_d^r rho e^(-k rho) drho;
  //   g      = 15 S k J / r^5 toward the source, k J = k (A + B),
  //            A = k1(k d) int_0^d rho^3 i1(k rho), B = i1(k d) int_d^r rho^3 k1(k rho);
  // kappa = 0: the Coulomb expansion, T1 + T2 = d^2/3 + (r^2 - d^2)/2, k J = d^3/15 + d (r^2 - d^2)/6.
  double t12, kj;
  if (kappa == 0.0) {
    t12 = d * d / 3.0 + (r * r - d * d) / 2.0;
    kj = d * d * d / 15.0 + d * (r * r - d * d) / 6.0;
  } else {
    const double zd = kappa * d, zr = kappa * r, k2 = kappa * kappa, k3 = k2 * kappa, k4 = k3 * kappa;
    const double t1 = d > 0.0 ? detail::i1z3(zd, zd) / (zd * k3 * d) : 0.0;
    // T2 and B hold sinh(zd) and i1(zd), which grow as e^zd, times differences of terms in
    // e^-zd and e^-zr: below zd = 0.5 by the differences' series, above with the growth
    // folded into each term (no overflow at any kappa).
    double t2, b = 0.0;
    if (zd < 0.5) {
      t2 = detail::sinhc(zd) * (detail::g1(zr) - detail::g1(zd)) / k2;
      if (d > 0.0) b = detail::i1z3(zd, 0.0) / (zd * zd * zd) * (detail::h2(zr) - detail::h2(zd)) / k4;
    } else {
      const double up = pm::exp(-2.0 * zd), across = pm::exp(zd - zr), both = pm::exp(-zd - zr);
      t2 = ((1.0 - up) * (1.0 + zd) - (across - both) * (1.0 + zr)) / (2.0 * zd) / k2;
      b = (detail::i1z3(zd, zd) * (zd * zd + 3.0 * zd + 3.0) - detail::i1z3(zd, zr) * (zr * zr + 3.0 * zr + 3.0)) /
          (zd * zd * zd) / k4;
    }
    t12 = t1 + t2;
    kj = d > 0.0 ? kappa * ((1.0 + zd) / (zd * zd) * detail::i2z3(zd, zd) / k4 + b) : 0.0;
  }
  const double r2 = r * r;
  const double mean = 3.0 * s * t12 / (r2 * r);
  if (!(d > 0.0)) return exact_sample(mean, zero);
  return exact_sample(mean, (15.0 * s * kj / (r2 * r2 * r) / d) * a);
}

// An imposed gradient (cues.hpp, ImposedParams). A linear profile is clamped at 0 (the
// scene check refuses profiles that would go negative inside the domain, so the clamp
// only acts outside it); an exponential one that overflows gives C = inf, which no
// detection window admits.
AXG_HDI CueSample imposed_sample(Vec3 x, const CueParams& cue, const ImposedParams& q) {
  const double t = dot(x - cue.position, q.direction);
  if (q.profile == ImposedProfile::kLinear) {
    const double c = q.c0 * (1.0 + q.rate * t);
    if (!(c > 0.0)) return exact_sample(0.0, {0.0, 0.0, 0.0});
    return exact_sample(c, (q.c0 * q.rate) * q.direction);
  }
  const double c = q.c0 * pm::exp(q.rate * t);
  return exact_sample(c, (q.rate * c) * q.direction);
}

// The sensing ball of an imposed gradient: exact for a linear profile (its mean is C(x), its
// effective gradient grad C), the mean-value formulas for an exponential one (C solves
// laplacian C = rate^2 C).
AXG_HDI CueSample imposed_ball_sample(Vec3 x, const CueParams& cue, const ImposedParams& q, double r) {
  const CueSample c = imposed_sample(x, cue, q);
  if (q.profile == ImposedProfile::kLinear) return c;
  const double rate = q.rate < 0.0 ? -q.rate : q.rate;
  const BallFactors f = ball_factors(rate * r, 0.0);
  return exact_sample(c.c * f.mean, f.dipole * c.grad);
}

// The signed unit gradient of a sample (a vector model's pull), or zero.
AXG_HDI Vec3 signed_unit_gradient(const CueSample& s, double sign) {
  const double n = norm(s.grad);
  return n > 0.0 && n < HUGE_VAL ? (sign / n) * s.grad : Vec3{0.0, 0.0, 0.0};
}

// Every cue's value and signed unit gradient (its vector_sum pull), analytically.
AXG_HDI void sample_analytic_field(Vec3 x, const CueParams* cues, int cue_count, const SenseParams& p,
                                   CueSample* samples, Vec3* pull) {
  for (int k = 0; k < cue_count; ++k) {
    samples[k] = p.ball ? analytic_ball_sample(x, cues[k], p) : analytic_sample(x, cues[k], p);
    pull[k] = signed_unit_gradient(samples[k], cues[k].sign);
  }
}

AXG_HDI void sample_imposed_field(Vec3 x, const CueParams* cues, int cue_count, const SenseParams& p,
                                  CueSample* samples, Vec3* pull) {
  for (int k = 0; k < cue_count; ++k) {
    samples[k] = p.ball ? imposed_ball_sample(x, cues[k], p.imposed, p.radius) : imposed_sample(x, cues[k], p.imposed);
    pull[k] = signed_unit_gradient(samples[k], cues[k].sign);
  }
}

// A cue is detected when 0 < C, C lies in [C_min, C_max] and its gradient estimate is
// non-zero and finite (either half of a split sample counts: a cue whose particles all
// fall in one half is still sensed).
AXG_HDI bool detected(const CueSample& s, const CueParams& cue) {
  if (!(s.c > 0.0) || s.c < cue.min_c || s.c > cue.max_c) return false;
  const double gn = norm2(s.grad) + norm2(s.grad_check);
  return gn > 0.0 && gn < HUGE_VAL;
}

}  // namespace axg::core

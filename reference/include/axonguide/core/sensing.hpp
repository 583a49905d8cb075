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

// The signed unit gradient of a sample (a vector model's pull), or zero.
AXG_HDI Vec3 signed_unit_gradient(const CueSample& s, double sign) {
  const double n = norm(s.grad);
  return n > 0.0 && n < HUGE_VAL ? (sign / n) * s.grad : Vec3{0.0, 0.0, 0.0};
}

// Every cue's value and signed unit gradient (its vector_sum pull), analytically.
AXG_HDI void sample_analytic_field(Vec3 x, const CueParams* cues, int cue_count, const SenseParams& p,
                                   CueSample* samples, Vec3* pull) {
  for (int k = 0; k < cue_count; ++k) {
    samples[k] = analytic_sample(x, cues[k], p);
    pull[k] = signed_unit_gradient(samples[k], cues[k].sign);
  }
}

AXG_HDI void sample_imposed_field(Vec3 x, const CueParams* cues, int cue_count, const SenseParams& p,
                                  CueSample* samples, Vec3* pull) {
  for (int k = 0; k < cue_count; ++k) {
    samples[k] = imposed_sample(x, cues[k], p.imposed);
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

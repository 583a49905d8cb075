#pragma once
// Sensing at the growth cone (SPEC §3.4): concentration C and gradient from each field,
// then gamma = C/K_d and mu = |grad C| w / C. The particle estimator counts the n
// particles within r of the tip: C = a n / V and grad C = 5 a sum(x_j - x) / (V r^2)
// (for a linear field, the mean of y over a ball of radius r weighted by g.y is g r^2/5).
#include <cmath>

#include "cues.hpp"
#include "hd.hpp"
#include "pmath.hpp"
#include "vec3.hpp"

namespace axg::core {

AXG_HDI CueSample particle_sample(double count, Vec3 sum_offsets, const SenseParams& p) {
  return {p.c_per_particle * count, p.grad_scale * sum_offsets};
}

// Steady state of a point source with decay: c(r) = S e^(-r/lambda) / r with
// S = a Q / (dt 4 pi D), evaluated at max(r, rmin) so that it stays finite as r -> 0;
// the gradient points along (x - s) and is zero at r = 0.
AXG_HDI CueSample analytic_sample(Vec3 x, const CueParams& cue, const SenseParams& p) {
  const Vec3 d = x - cue.position;
  const double r = norm(d);
  if (!(r < HUGE_VAL)) return {0.0, {0.0, 0.0, 0.0}};  // |d|^2 overflowed: c has long reached 0
  const double re = r > p.analytic_rmin ? r : p.analytic_rmin;
  const double c = cue.analytic_scale * pm::exp(-re * cue.inv_lambda) / re;
  if (r == 0.0) return {c, {0.0, 0.0, 0.0}};
  // dc/dr = -c (1/r + 1/lambda); along the unit vector d/r.
  const double dcdr = -c * (1.0 / re + cue.inv_lambda);
  return {c, (dcdr / r) * d};
}

// Every cue's value and signed unit gradient (its vector_sum pull), analytically.
AXG_HDI void sample_analytic_field(Vec3 x, const CueParams* cues, int cue_count, const SenseParams& p,
                                   CueSample* samples, Vec3* pull) {
  for (int k = 0; k < cue_count; ++k) {
    samples[k] = analytic_sample(x, cues[k], p);
    const double n = norm(samples[k].grad);
    pull[k] = n > 0.0 ? (cues[k].sign / n) * samples[k].grad : Vec3{0.0, 0.0, 0.0};
  }
}

struct Detection {
  bool detected;
  double gamma;  // C / K_d
  double mu;     // |grad C| w / C: fractional change across the growth cone
  Vec3 g;        // unit gradient, signed toward the preferred direction (- for repellents)
};

// A cue is detected when 0 < C, C lies in [C_min, C_max] and the gradient is non-zero.
AXG_HDI Detection detect(const CueSample& s, const CueParams& cue, const SenseParams& p) {
  Detection d{false, 0.0, 0.0, {0.0, 0.0, 0.0}};
  if (!(s.c > 0.0) || s.c < cue.min_c || s.c > cue.max_c) return d;
  const double gn = norm(s.grad);
  if (!(gn > 0.0) || !(gn < HUGE_VAL)) return d;
  d.detected = true;
  d.gamma = s.c / cue.kd;
  d.mu = gn * p.cone_width / s.c;
  d.g = (cue.sign / gn) * s.grad;
  return d;
}

}  // namespace axg::core

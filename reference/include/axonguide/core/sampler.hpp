#pragma once
// Uniform directions on S^(d-1) and uniform points in regions (SPEC §3.1), as pure
// functions of one Rng stream. Each sampler consumes a fixed, documented sequence of
// draws, so a point is a pure function of (seed, tag, id, step).
//
// The coordinate sampler needs the incomplete beta function (GSL) and lives in the
// host-only placement code (axonguide/placement/sampler_nd.hpp); the rest are here.
#include <cmath>

#include "hd.hpp"
#include "pmath.hpp"
#include "random.hpp"
#include "types.hpp"
#include "vec3.hpp"

namespace axg::core {

// Two independent N(0,1) deviates by Marsaglia's polar method: (a, b) uniform in the
// square (-1,1)^2, rejected outside the unit disc or at its centre.
template <class R>
AXG_HDFI void normal_pair(R& rng, double* z0, double* z1) {
  for (;;) {
    const double a = rng.symmetric();
    const double b = rng.symmetric();
    const double s = a * a + b * b;
    if (s < 1.0 && s > 0.0) {
      const double f = std::sqrt(-2.0 * pm::log(s) / s);
      *z0 = a * f;
      *z1 = b * f;
      return;
    }
  }
}

template <class R>
AXG_HDI double normal(R& rng) {
  double z0, z1;
  normal_pair(rng, &z0, &z1);
  return z0;
}

// Rejection: X uniform in (-1,1)^3, rejected unless 0 < |X|^2 <= 1. Returns the point in
// the unit ball (not normalised); the caller projects it for a direction.
template <class R>
AXG_HDI Vec3 unit_ball_rejection(R& rng) {
  for (;;) {
    const Vec3 v{rng.symmetric(), rng.symmetric(), rng.symmetric()};
    const double s = norm2(v);
    if (s <= 1.0 && s > 0.0) return v;
  }
}

// Normal deviates: (z0, z1, z2) / |z|, from two polar pairs (the fourth deviate is unused).
template <class R>
AXG_HDI Vec3 direction_normal(R& rng) {
  for (;;) {
    double a, b, c, unused;
    normal_pair(rng, &a, &b);
    normal_pair(rng, &c, &unused);
    const Vec3 v{a, b, c};
    const double s = norm2(v);
    if (s > 0.0) return v / std::sqrt(s);
  }
}

// Trig (Archimedes): z uniform in (-1,1), t uniform in [0, 1) turns.
template <class R>
AXG_HDI Vec3 direction_trig(R& rng) {
  const double z = rng.symmetric();
  const double t = rng.uniform_co();
  double s, c;
  pm::sincos_turns(t, &s, &c);
  const double r = std::sqrt((1.0 - z) * (1.0 + z));
  return {r * c, r * s, z};
}

template <class R>
AXG_HDI Vec3 direction_rejection(R& rng) {
  const Vec3 v = unit_ball_rejection(rng);
  return v / norm(v);
}

// A direction from one of the samplers that core implements (not kCoordinate).
template <class R>
AXG_HDI Vec3 direction3(Sampler sampler, R& rng) {
  switch (sampler) {
    case Sampler::kNormal: return direction_normal(rng);
    case Sampler::kTrig: return direction_trig(rng);
    default: return direction_rejection(rng);
  }
}

// Radius of a uniform point in the ball of radius R in d dimensions: R * U^(1/d),
// computed as R * exp(log(U) / d) with the portable math.
template <class R>
AXG_HDI double ball_radius(R& rng, double radius, int d) {
  const double u = rng.uniform();
  return radius * pm::exp(pm::log(u) / static_cast<double>(d));
}

// A uniform point in the cube [-h, h]^3.
template <class R>
AXG_HDI Vec3 box_point(R& rng, double half_edge) {
  const double x = rng.symmetric();
  const double y = rng.symmetric();
  const double z = rng.symmetric();
  return {half_edge * x, half_edge * y, half_edge * z};
}

// ---- Any dimension (validation and the samplers' own tests). out has d entries. ----

// Rejection in d dimensions; gives up after max_tries (its acceptance rate is
// V_d / 2^d, which collapses with d) and returns false.
template <class R>
AXG_HDI bool ball_rejection_nd(R& rng, int d, double* out, long max_tries) {
  for (long t = 0; t < max_tries; ++t) {
    double s = 0.0;
    for (int k = 0; k < d; ++k) {
      out[k] = rng.symmetric();
      s += out[k] * out[k];
    }
    if (s <= 1.0 && s > 0.0) return true;
  }
  return false;
}

template <class R>
AXG_HDI void direction_normal_nd(R& rng, int d, double* out) {
  for (;;) {
    double s = 0.0;
    for (int k = 0; k < d; k += 2) {
      double z1;
      normal_pair(rng, &out[k], &z1);
      if (k + 1 < d) out[k + 1] = z1;
    }
    for (int k = 0; k < d; ++k) s += out[k] * out[k];
    if (s > 0.0) {
      const double inv = std::sqrt(s);
      for (int k = 0; k < d; ++k) out[k] = out[k] / inv;
      return;
    }
  }
}

// A uniform point of the open unit disc, as (x, y) with s = x^2 + y^2 in (0, 1): two 32-bit
// words per try, (2k + 1) / 2^32 - 1 for word k (exact, symmetric about 0), rejected
// outside the disc or at its centre (the acceptance is pi/4).
template <class R>
AXG_HDI void unit_disc(R& rng, double* x, double* y, double* s) {
  for (;;) {
    *x = static_cast<double>(rng.word32()) * 0x1p-31 + (0x1p-32 - 1.0);
    *y = static_cast<double>(rng.word32()) * 0x1p-31 + (0x1p-32 - 1.0);
    *s = *x * *x + *y * *y;
    if (*s < 1.0 && *s > 0.0) return;
  }
}

// c h + sn u for a uniform unit vector u perpendicular to the unit vector h: the turn of a
// unit heading by the angle whose cosine and sine are (c, sn) about a uniformly random
// axis perpendicular to it. u = (x e1 + y e2) / sqrt(s) for a uniform point (x, y) of the
// unit disc, so its azimuth about h is uniform; (e1, e2) is the branch-free orthonormal
// basis of Duff et al. 2017 ("Building an orthonormal basis, revisited", JCGT 6(1)),
// written as E1 / d and E2 / d with d = sign(h_z) + h_z so that the whole turn takes one
// square root and one division.
template <class R>
AXG_HDI Vec3 random_turn(Vec3 h, double c, double sn, R& rng) {
  const double sign = h.z >= 0.0 ? 1.0 : -1.0;
  const double d = sign + h.z;  // |d| >= 1
  const double xy = h.x * h.y;
  const Vec3 e1{d - sign * h.x * h.x, -sign * xy, -sign * h.x * d};
  const Vec3 e2{-xy, sign * d - h.y * h.y, -h.y * d};
  double x, y, s;
  unit_disc(rng, &x, &y, &s);
  const double q = sn / (d * std::sqrt(s));
  return c * h + (q * x) * e1 + (q * y) * e2;
}

// A uniform unit vector perpendicular to the unit vector h (random_turn by a right angle).
template <class R>
AXG_HDI Vec3 perpendicular_direction(Vec3 h, R& rng) {
  return random_turn(h, 0.0, 1.0, rng);
}

}  // namespace axg::core

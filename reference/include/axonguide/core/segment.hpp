#pragma once
// The closest points of two segments (SPEC §3.9; docs/methods.md §2.13), after Ericson,
// Real-Time Collision Detection (2005) §5.1.9, robust for zero-length and parallel
// segments: + - * / only, in the order written. For parallel segments (and for a
// zero-length axon segment) the closest points are taken at the smallest parameter along
// the first segment, so the answer is a function of the segments alone.
#include "hd.hpp"
#include "vec3.hpp"

namespace axg::core {

struct SegmentPair {
  double s = 0.0, t = 0.0;  // parameters in [0, 1] along the first and the second segment
  double dist2 = 0.0;       // the squared distance between the two points
};

AXG_HDI double clamp01(double x) { return x < 0.0 ? 0.0 : (x > 1.0 ? 1.0 : x); }

// Nearly parallel segments (the denominator below a relative 1e-12 of |d1|^2 |d2|^2) are
// treated as parallel: the distance along their overlap is flat, so s = 0 then the clamps
// give the overlap's smallest s.
inline constexpr double kParallelTolerance = 1e-12;

// Closest points of [p0, p1] and [q0, q1].
AXG_HDI SegmentPair closest_points(Vec3 p0, Vec3 p1, Vec3 q0, Vec3 q1) {
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = dot(d1, d1), e = dot(d2, d2), f = dot(d2, r);
  SegmentPair out;
  if (a == 0.0 && e == 0.0) {
    out.s = 0.0;
    out.t = 0.0;
  } else if (a == 0.0) {
    out.s = 0.0;
    out.t = clamp01(f / e);
  } else {
    const double c = dot(d1, r);
    if (e == 0.0) {
      out.t = 0.0;
      out.s = clamp01(-c / a);
    } else {
      const double b = dot(d1, d2);
      const double denom = a * e - b * b;
      out.s = denom > kParallelTolerance * (a * e) ? clamp01((b * f - c * e) / denom) : 0.0;
      out.t = (b * out.s + f) / e;
      if (out.t < 0.0) {
        out.t = 0.0;
        out.s = clamp01(-c / a);
      } else if (out.t > 1.0) {
        out.t = 1.0;
        out.s = clamp01((b - c) / a);
      }
    }
  }
  out.dist2 = norm2((p0 + out.s * d1) - (q0 + out.t * d2));
  return out;
}

// The closest point of [p0, p1] to q: its parameter in [0, 1] (0 for a zero-length segment).
AXG_HDI double closest_parameter(Vec3 p0, Vec3 p1, Vec3 q) {
  const Vec3 d = p1 - p0;
  const double a = dot(d, d);
  return a == 0.0 ? 0.0 : clamp01(dot(q - p0, d) / a);
}

}  // namespace axg::core

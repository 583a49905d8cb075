#pragma once
// The geometry of growth cones in an arbour (SPEC §3.8; docs/methods.md §2.12): a stem's
// heading, a cone's heading random walk, the headings of two daughters, and a cone's own
// elongation-rate factor. Branching and elongation rates are core/branching.hpp. Every draw
// is keyed on the cone (core::cone_key) or the neuron, never on the thread schedule.
//
// A monolayer culture (region "disc") keeps headings in the plane: a stem's heading is a
// uniform angle, the random walk turns by theta (cos theta = e^(-l / L_p)) to a random side,
// which gives the 2D worm-like chain <h(s).h(0)> = e^(-s / L_p) exactly at every sum of
// steps, and daughters part by +-phi/2 in the plane. In 3D the walk is core/wander.hpp's
// and daughters part by +-phi/2 about a uniformly random axis perpendicular to the heading.
#include <cmath>
#include <cstdint>

#include "hd.hpp"
#include "pmath.hpp"
#include "random.hpp"
#include "sampler.hpp"
#include "vec3.hpp"

namespace axg::core {

struct ConeGeometry {
  bool planar = false;          // a culture's cones turn in the plane z = const
  bool wander = false;          // false: straight between branchings
  double inv_persistence = 0;   // 1 / L_p, per length unit
  double angle_mean = 1.0;      // phi between two daughters, radians, in (0, pi)
  double angle_sd = 0.0;        // radians; phi ~ N(mean, sd) redrawn outside (0, pi)
  double rate_sigma = 0.0;      // the log-normal rate factor's sigma (0: every cone at v0)
};

inline constexpr double kPi = 3.14159265358979323846;

// (c, s) turn of h in the plane, to the left (+) or right (-).
AXG_HDI Vec3 planar_turn(Vec3 h, double c, double s, bool left) {
  const double sn = left ? s : -s;
  return {c * h.x - sn * h.y, sn * h.x + c * h.y, 0.0};
}

// A culture's cone steers in the substrate's plane: its steered heading's projection on the
// plane, renormalised (a turn of less than pi/2 from a heading in the plane never leaves it
// vertical; a vertical one is returned as it is).
AXG_HDI Vec3 in_plane(Vec3 h) {
  const double n = std::sqrt(h.x * h.x + h.y * h.y);
  if (!(n > 0.0)) return h;
  return {h.x / n, h.y / n, 0.0};
}

// A stem's heading: a uniform angle in the plane, or a uniform direction.
AXG_HDI Vec3 stem_heading(bool planar, Rng& rng) {
  if (planar) {
    const double a = 2.0 * kPi * rng.uniform();
    return {pm::cos(a), pm::sin(a), 0.0};
  }
  return direction_normal(rng);
}

// The heading's random walk over a move of length l.
AXG_HDI Vec3 cone_wander(Vec3 h, double l, const ConeGeometry& g, std::uint64_t seed, std::uint64_t key,
                         std::uint32_t step) {
  if (!g.wander || !(l > 0.0)) return h;
  const double c = pm::exp(-l * g.inv_persistence);
  const double s = std::sqrt(1.0 - c * c);
  Rng rng(seed, Stream::kConeWander, key, step);
  if (g.planar) return planar_turn(h, c, s, (rng.word32() & 1u) != 0);
  return random_turn(h, c, s, rng);
}

// The angle between two daughters: N(mean, sd) redrawn until it falls in (0, pi); after 64
// draws (a distribution almost all outside) the mean.
AXG_HDI double daughter_angle(const ConeGeometry& g, Rng& rng) {
  if (g.angle_sd == 0.0) return g.angle_mean;
  for (int k = 0; k < 64; ++k) {
    const double a = g.angle_mean + g.angle_sd * normal(rng);
    if (a > 0.0 && a < kPi) return a;
  }
  return g.angle_mean;
}

// The daughters of a cone with heading h, drawn on (seed, kConeSplit, key, step).
AXG_HDI void daughter_headings(Vec3 h, const ConeGeometry& g, std::uint64_t seed, std::uint64_t key,
                               std::uint32_t step, Vec3* first, Vec3* second) {
  Rng rng(seed, Stream::kConeSplit, key, step);
  const double half = 0.5 * daughter_angle(g, rng);
  const double c = pm::cos(half), s = pm::sin(half);
  if (g.planar) {
    *first = planar_turn(h, c, s, true);
    *second = planar_turn(h, c, s, false);
    return;
  }
  const Vec3 u = perpendicular_direction(h, rng);
  *first = c * h + s * u;
  *second = c * h - s * u;
}

// A lateral (interstitial) branch's heading: the neurite's direction d where it starts,
// turned by an angle drawn as daughter_angle (the scene's branching angle) to a random side
// in the plane, or about a random axis perpendicular to d.
AXG_HDI Vec3 lateral_heading(Vec3 d, const ConeGeometry& g, Rng& rng) {
  const double a = daughter_angle(g, rng);
  const double c = pm::cos(a), s = pm::sin(a);
  if (g.planar) return planar_turn(d, c, s, (rng.word32() & 1u) != 0);
  return normalized(c * d + s * perpendicular_direction(d, rng));
}

// A cone's elongation-rate factor, log-normal with mean 1 and coefficient of variation cv
// (sigma^2 = ln(1 + cv^2)): exp(sigma z - sigma^2 / 2). Exactly 1 for cv = 0.
AXG_HDI double rate_factor(double sigma, Rng& rng) {
  if (sigma == 0.0) return 1.0;
  return pm::exp(sigma * normal(rng) - 0.5 * sigma * sigma);
}

}  // namespace axg::core

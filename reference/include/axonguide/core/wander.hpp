#pragma once
// Intrinsic wandering (SPEC §3.5; Katz 1985): every step, cue or no cue, the heading
// turns by an angle theta with cos(theta) = e^(-l / L_p) about a uniformly random axis
// perpendicular to it (l: the step's length, L_p: the persistence length). Given h_n the
// new heading has mean cos(theta) h_n (the perpendicular part averages out), so the
// heading autocorrelation is <h(s).h(0)> = e^(-s / L_p) exactly at every path length s
// that is a sum of steps: the 3D persistent random walk (worm-like chain) of L_p.
#include <cmath>
#include <cstdint>

#include "hd.hpp"
#include "pmath.hpp"
#include "random.hpp"
#include "sampler.hpp"
#include "vec3.hpp"

namespace axg::core {

struct WanderParams {
  bool on;                  // false: no wandering (straight axons, the report's model)
  double inv_persistence;   // 1 / L_p, per length unit
  double cos_step, sin_step;  // of theta for the scene's fixed step length (host-computed)
};

// One wander of heading h for a step of length l; `fixed` says that l is the scene's
// step length, whose angle was computed on the host (otherwise it is computed here with
// the portable exp).
AXG_HDI Vec3 wander(Vec3 h, double l, bool fixed, const WanderParams& w, std::uint64_t seed, std::uint32_t neuron,
                    std::uint32_t step) {
  if (!w.on) return h;
  double c = w.cos_step, s = w.sin_step;
  if (!fixed) {
    c = pm::exp(-l * w.inv_persistence);
    s = std::sqrt(1.0 - c * c);
  }
  Rng rng(seed, Stream::kWander, neuron, step);
  // |c h + s u| = 1 up to rounding; no renormalisation (the drift is a random walk of
  // one rounding error per step).
  return random_turn(h, c, s, rng);
}

}  // namespace axg::core

#pragma once
// Cue sources and field parameters as the per-step functions see them (SPEC §3.3-§3.5).
// Everything derived from the scene (survival probabilities, Brownian scales, analytic
// prefactors, cos and sin of the turn angle) is computed once on the host and passed in.
#include <cstdint>

#include "hd.hpp"
#include "types.hpp"
#include "vec3.hpp"

namespace axg::core {

// Sources a scene may have: the particle gather keeps one accumulator per cue.
inline constexpr int kMaxCues = 64;

struct CueParams {
  Vec3 position;          // LU
  double sign;            // +1 attractant, -1 repellent
  double emission;        // particles per step
  double diffusion;       // D, LU^2 per time unit
  double decay;           // k, per time unit
  double kd;              // K_d, concentration units
  double min_c, max_c;    // detection window, concentration units
  double survival;        // e^(-k dt): probability that a particle survives one step
  double sigma;           // sqrt(2 D dt): Brownian displacement scale per axis, LU
  double inv_lambda;      // 1/lambda = sqrt(k/D), 1/LU (0 when k = 0)
  double analytic_scale;  // a Q / (dt 4 pi D): steady-state prefactor, concentration x LU
};

// Concentration and gradient of one cue at one point.
struct CueSample {
  double c;   // concentration units
  Vec3 grad;  // concentration units per LU
};

struct SenseParams {
  FieldKind field;
  double amount;          // a: concentration x LU^3 carried by one particle
  double radius;          // r: sensing radius, LU
  double radius2;         // r^2
  double c_per_particle;  // a / V, V = 4 pi r^3 / 3
  double grad_scale;      // 5 a / (V r^2)
  double cone_width;      // w: growth-cone width, LU
  double analytic_rmin;   // LU: the analytic field is evaluated at max(r, rmin)
};

struct SteerParams {
  GuidanceModel model;
  double cos_turn, sin_turn;  // of the turn angle, computed on the host
  double gain;                // alpha
  double vector_weight;       // beta
};

}  // namespace axg::core

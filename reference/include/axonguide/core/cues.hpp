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
  // The variance of this cue's count dipole averaged over the decision's integration time,
  // per unit of its instantaneous variance: 1 for an instantaneous decision (the report's
  // per-step rule), less as T grows past the molecules' correlation time (model/steering.cpp,
  // dipole_mean_variance).
  double dipole_variance = 1.0;
};

// What the growth cone derives from one cue at one point: the field's estimate of C and
// grad C. For grid, analytic and imposed fields grad and grad_check are both the field's
// gradient. For the particle field's estimate (estimate.hpp) they come from two
// independent halves of the particles: steering takes the direction from grad and the
// magnitude along it from grad_check. Molecule-resolved count sensing (particles.hpp):
// c = a n / V of the n particles within r, grad = grad_check = their count dipole
// sum_j (x_j - x) / r (particles, not concentration units).
struct CueSample {
  double c;         // concentration units
  Vec3 grad;        // concentration units per length unit (molecule-resolved count: particles)
  Vec3 grad_check;  // concentration units per length unit
};

// An imposed gradient (SPEC §3.3): along the unit vector `direction` from each cue's
// position p, with t = (x - p).direction,
//   linear:      C = c0 (1 + rate t),      grad C = c0 rate direction,
//   exponential: C = c0 e^(rate t),         grad C = rate C direction,
// where rate = s / L (linear) or ln(1 + s) / L (exponential) for a steepness of s (a
// fraction) per reference length L, computed on the host.
struct ImposedParams {
  ImposedProfile profile;
  Vec3 direction;  // unit
  double c0;       // concentration units at the cue's position
  double rate;     // per length unit
};

struct SenseParams {
  FieldKind field;
  ParticleSensing sensing;
  double radius;          // r: sensing radius, length units
  double radius2;         // r^2
  double inv_radius;      // 1/r
  double molecule;        // m: concentration x length^3 of one molecule (physical)
  double c_per_particle;  // a / V, V = 4 pi r^3 / 3 (molecule-resolved sensing: a = m)
  double count_mean_scale;// V r / (5 m): mean count dipole of the molecules per unit gradient
  double count_var_scale; // V / (5 m): its variance per axis per unit concentration
  double cone_width;      // w: growth-cone width, length units
  double analytic_rmin;   // length units: the analytic field is evaluated at max(r, rmin)
  ImposedParams imposed;
  // The count form reads the sensing ball: the molecules' mean concentration in it and their
  // dipole (a sample's c and an effective gradient g, whose count dipole is g V r / (5 m);
  // sensing.hpp, ball_sample). The SNR forms read C and grad C at the tip.
  bool ball;
};

struct SteerParams {
  GuidanceModel model;
  NoiseForm noise;
  double cos_turn, sin_turn;  // of the turn angle, computed on the host
  // alpha: the SNR forms' gain for a decision over the integration time T (the scene's gain
  // at one time unit times the growth of the SNR with T; model/steering.cpp).
  double gain;
  double vector_weight;       // beta
  double modulation;          // m in [0, 1): growth-rate modulation (0: off)
  // +1, or -1 for the antithetic image of a run (guidance.antithetic): every normal deviate
  // of a decision and every random side is negated, an equally likely sample of the model.
  double decision_sign = 1.0;
};

}  // namespace axg::core

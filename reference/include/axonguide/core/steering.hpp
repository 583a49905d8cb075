#pragma once
// Steering (SPEC §3.5). `snr` (Mortimer et al. 2010): for each detected cue in index
// order, with g the signed unit gradient and g_perp = g - (h.g) h, sin psi = |g_perp|,
//   SNR = alpha mu sqrt(gamma / (1 + gamma)^3) sin psi,   X ~ N(SNR, 1),
// and the heading turns by delta-theta toward g_perp when X > 0, away otherwise:
//   h <- cos(dtheta) h +- sin(dtheta) g_perp / |g_perp|, renormalised.
// `vector_sum`: h <- normalise(h + beta sum_j +-u_j).
#include <cmath>

#include "cues.hpp"
#include "hd.hpp"
#include "random.hpp"
#include "sampler.hpp"
#include "sensing.hpp"
#include "vec3.hpp"

namespace axg::core {

// sqrt(gamma / (1 + gamma)^3) for any gamma >= 0 without overflow: with t = 1/(1+gamma),
// gamma/(1+gamma)^3 = t^2 (gamma t), and gamma t = gamma/(1+gamma) lies in [0, 1).
// Peaks at gamma = 1/2.
AXG_HDI double snr_occupancy(double gamma) {
  const double t = 1.0 / (1.0 + gamma);
  return t * std::sqrt(gamma * t);
}

// Below this |g_perp| the gradient is taken as parallel to the heading.
inline constexpr double kParallelSin = 1e-12;

// The stream of cue `cue` of neuron `neuron`: id = (cue << 32) | neuron.
AXG_HDI std::uint64_t steer_stream_id(std::uint32_t neuron, int cue) {
  return (static_cast<std::uint64_t>(cue) << 32) | neuron;
}

// One SNR turn of heading h for one detected cue.
AXG_HDI Vec3 snr_turn(Vec3 h, const Detection& d, const SteerParams& p, std::uint64_t seed,
                      std::uint32_t neuron, int cue, std::uint32_t step) {
  Vec3 perp = d.g - dot(h, d.g) * h;
  const double sin_psi = norm(perp);
  const double snr = p.gain * d.mu * snr_occupancy(d.gamma) * sin_psi;
  Rng decision(seed, Stream::kSteerDecision, steer_stream_id(neuron, cue), step);
  const double x = snr + normal(decision);
  if (sin_psi < kParallelSin) {
    // No preferred side: a random direction perpendicular to h.
    Rng side(seed, Stream::kSteerPerpendicular, steer_stream_id(neuron, cue), step);
    for (;;) {
      const Vec3 v = direction_trig(side);
      perp = v - dot(h, v) * h;
      if (norm2(perp) > 1e-6) break;
    }
  }
  const Vec3 u = perp / norm(perp);
  const double s = x > 0.0 ? p.sin_turn : -p.sin_turn;
  return normalized(p.cos_turn * h + s * u);
}

// vector_sum: pull is sum_j +-u_j over the detected cues; a zero or non-finite result
// leaves the heading unchanged.
AXG_HDI Vec3 vector_sum_turn(Vec3 h, Vec3 pull, const SteerParams& p) {
  const Vec3 v = h + p.vector_weight * pull;
  const double n = norm(v);
  if (!(n > 0.0) || !(n < HUGE_VAL)) return h;
  return v / n;
}

}  // namespace axg::core

namespace axg::core {

// Steers one axon by every cue in index order; samples and pulls come from the field
// (for the particle field, pull[k] is the signed sum of unit vectors toward the source of
// cue k's particles within r; for grid and analytic fields, the signed unit gradient).
// Cues outside their detection window are ignored.
AXG_HDI Vec3 steer_axon(Vec3 h, const CueSample* samples, const Vec3* pull, const CueParams* cues, int cue_count,
                        const SenseParams& sp, const SteerParams& p, std::uint64_t seed, std::uint32_t neuron,
                        std::uint32_t step) {
  if (p.model == GuidanceModel::kSnr) {
    for (int k = 0; k < cue_count; ++k) {
      const Detection d = detect(samples[k], cues[k], sp);
      if (d.detected) h = snr_turn(h, d, p, seed, neuron, k, step);
    }
    return h;
  }
  if (p.model == GuidanceModel::kVectorSum) {
    Vec3 total{0.0, 0.0, 0.0};
    for (int k = 0; k < cue_count; ++k)
      if (detect(samples[k], cues[k], sp).detected) total += pull[k];
    return vector_sum_turn(h, total, p);
  }
  return h;
}

}  // namespace axg::core

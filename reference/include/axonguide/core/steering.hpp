#pragma once
// Steering (SPEC §3.5): one decision per integration interval, whatever the number of cues.
// The decision reads the mean of the interval's samples of C and grad C along the tip's path
// (guide.hpp); only then do the non-linear parts act (1/C, f(gamma), the detection window,
// the draw). `decision` below is the interval's number, the counter of its random draws, so
// that refinements of dt share their noise. The report's rule (guidance.decision "per_step")
// is the case of one step per interval with an instantaneous SNR.
//
// `snr` (Mortimer et al. 2009-2011). Every detected cue k contributes the evidence vector
//   e_k = sign_k alpha (w m_k / C_k) f(gamma_k) u_k,
// where u_k is the unit component of its gradient perpendicular to the heading h, m_k the
// gradient's component along u_k (|grad_perp| for an exact field; from the other half of
// the particle estimate, estimate.hpp), and f the receptor-noise form. For one
// cue |e_k| = alpha mu f(gamma) sin psi, the report's SNR. The evidence combines as
// E = sum_k e_k (in the canonical cue order): with von Mises likelihoods for the
// direction, the log-likelihoods of independent cues add, so the combined posterior
// points along E with concentration |E| (Mortimer, Dayan, Burrage & Goodhill 2011). One
// draw X ~ N(|E|, 1) decides: the heading turns by delta-theta toward E when X > 0 and
// away otherwise; h <- cos(dtheta) h +- sin(dtheta) E/|E|. A step with no detected cue
// makes no cue turn; with |E| ~ 0 the side is a random perpendicular.
//
// `snr` with the count noise form: the heading turns toward the perpendicular part of
// the signed count dipole of the molecules within r (count_steer), whose Poisson noise is
// the only noise.
//
// `vector_sum` / `source_vector_sum`: h <- normalise(h + beta sum_k pull_k).
//
// Antithetic runs (guidance.antithetic; SteerParams::decision_sign = -1): every normal
// deviate of a decision (X = |E| - Z; the count dipole's noise -z) and every random side
// (-u) is negated. Z and -Z, u and -u have the same law, so such a run is an equally likely
// sample of the model. `fit` gives it to the mirror image of each run: where the mirror
// run's evidence is the negative of the first's, the two then turn the same way in space
// whatever Z is, except where the evidence decides, and their noise cancels in the pair's
// mean bias (docs/methods.md §12.3).
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
  if (!(gamma < HUGE_VAL)) return 0.0;
  const double t = 1.0 / (1.0 + gamma);
  return t * std::sqrt(gamma * t);
}

// sqrt(gamma) / (1 + gamma) = 1 / (s + 1/s), s = sqrt(gamma): 0 at gamma = 0 and at
// gamma = inf, no overflow. Peaks at gamma = 1.
AXG_HDI double snapshot_occupancy(double gamma) {
  const double s = std::sqrt(gamma);
  return 1.0 / (s + 1.0 / s);
}

// f(gamma) of an SNR noise form (the count decision has none: 0).
AXG_HDI double receptor_noise(double gamma, NoiseForm form) {
  if (form == NoiseForm::kBinding) return snr_occupancy(gamma);
  return form == NoiseForm::kSnapshot ? snapshot_occupancy(gamma) : 0.0;
}

// Below this |E| the evidence has no side: a random perpendicular is used.
inline constexpr double kParallelSin = 1e-12;

// The SNR of a counting growth cone: the dipole component D.u = sum_j (x_j - x).u / r of
// Poisson molecules of intensity C/m in the ball of radius r has mean |grad_perp| V r / (5 m)
// and variance C V / (5 m), so
//   SNR_count = |grad_perp| r sqrt(V / (5 m C)),
// with m the amount of one molecule: a physical quantity, not the simulation's particle
// amount. The validation compares the count decision with Phi(SNR_count).
AXG_HDI double snr_count(double c, double grad_perp, double molecule, double radius) {
  const double volume = 4.0 / 3.0 * 3.141592653589793 * radius * radius * radius;
  return grad_perp * radius * std::sqrt(volume / (5.0 * molecule * c));
}

// The gradient a decision takes from a sample: the component of grad_check along the
// direction of grad, (grad_check . u) u with u = grad / |grad|. For exact fields it is the
// gradient; for the particle estimate its magnitude comes from the half that did not choose
// the direction, so in a flat field it is symmetric about zero and adds no direction.
AXG_HDI Vec3 decision_gradient(const CueSample& s) {
  const double n = norm(s.grad);
  if (!(n > 0.0 && n < HUGE_VAL)) return {0.0, 0.0, 0.0};
  const Vec3 u = s.grad / n;
  return dot(s.grad_check, u) * u;
}

struct Steered {
  Vec3 heading;
  double along;  // evidence along the old heading (SNR units; count: a z-score), for growth-rate modulation
};

// The turn of delta-theta toward (x > 0) or away from the unit vector u perpendicular to h.
AXG_HDI Vec3 turn(Vec3 h, Vec3 u, bool toward, const SteerParams& p) {
  const double s = toward ? p.sin_turn : -p.sin_turn;
  return normalized(p.cos_turn * h + s * u);
}

// The count decision (noise form kCount). The growth cone counts every detected cue's
// molecules within r and turns toward the perpendicular part of the signed dipole
// D = sum_k sign_k sum_j (x_j - x) / r; nothing is added to the molecules' noise.
// Molecule-resolved particle sensing: the particles are the molecules and D is their
// dipole. Otherwise (every field, the particle estimate included) D is drawn in its
// Gaussian limit from the field's estimate: mean sum_k sign_k g_k V r / (5m), g_k the
// decision gradient, variance sum_k C_k V / (5m) per axis (three normal deviates from the
// decision stream). `along` is the z-score of D along h.
AXG_HDI Steered count_steer(Vec3 h, const CueSample* samples, const CueParams* cues, int cue_count, const SenseParams& sp,
                            const SteerParams& p, std::uint64_t seed, std::uint64_t neuron, std::uint32_t decision) {
  Vec3 d{0.0, 0.0, 0.0};
  double variance = 0.0;  // of D per axis
  bool any = false;
  const bool molecules = sp.field == FieldKind::kParticles && sp.sensing == ParticleSensing::kMolecules;
  for (int k = 0; k < cue_count; ++k) {
    const CueSample& s = samples[k];
    if (!detected(s, cues[k])) continue;
    any = true;
    if (molecules) {
      d += cues[k].sign * s.grad;
      variance += s.c / sp.c_per_particle / 5.0 * cues[k].dipole_variance;  // n_k / 5, over T
    } else {
      d += (cues[k].sign * sp.count_mean_scale) * decision_gradient(s);
      variance += sp.count_var_scale * s.c * cues[k].dipole_variance;
    }
  }
  if (!any) return {h, 0.0};
  const double sd = std::sqrt(variance);
  if (!molecules) {
    Rng noise(seed, Stream::kSteerDecision, neuron, decision);
    double z0, z1, z2, unused;
    normal_pair(noise, &z0, &z1);
    normal_pair(noise, &z2, &unused);
    d += sd * (p.decision_sign * Vec3{z0, z1, z2});
  }
  const double along = sd > 0.0 ? dot(d, h) / sd : 0.0;
  const Vec3 perp = d - dot(d, h) * h;
  const double pn = norm(perp);
  if (!(pn >= kParallelSin * (sd > 1.0 ? sd : 1.0) && pn < HUGE_VAL)) {
    Rng side(seed, Stream::kSteerPerpendicular, neuron, decision);
    return {turn(h, p.decision_sign * perpendicular_direction(h, side), true, p), along};
  }
  return {turn(h, perp / pn, true, p), along};
}

// The combined evidence of every detected cue (see the top of this file).
AXG_HDI Steered snr_steer(Vec3 h, const CueSample* samples, const CueParams* cues, int cue_count, const SenseParams& sp,
                          const SteerParams& p, std::uint64_t seed, std::uint64_t neuron, std::uint32_t decision) {
  if (p.noise == NoiseForm::kCount) return count_steer(h, samples, cues, cue_count, sp, p, seed, neuron, decision);
  Vec3 e{0.0, 0.0, 0.0};
  double along = 0.0;
  bool any = false;
  for (int k = 0; k < cue_count; ++k) {
    const CueSample& s = samples[k];
    if (!detected(s, cues[k])) continue;
    any = true;
    const double weight = cues[k].sign * p.gain * sp.cone_width / s.c * receptor_noise(s.c / cues[k].kd, p.noise);
    const Vec3 perp = s.grad - dot(h, s.grad) * h;
    const double pn = norm(perp);
    if (pn > 0.0) {
      const Vec3 u = perp / pn;
      e += (weight * dot(s.grad_check, u)) * u;
    }
    along += weight * dot(s.grad_check, h);
  }
  if (!any) return {h, 0.0};
  const double strength = norm(e);
  Rng draw(seed, Stream::kSteerDecision, neuron, decision);
  const bool toward = strength + p.decision_sign * normal(draw) > 0.0;
  if (!(strength >= kParallelSin && strength < HUGE_VAL)) {
    Rng side(seed, Stream::kSteerPerpendicular, neuron, decision);
    return {turn(h, p.decision_sign * perpendicular_direction(h, side), toward, p), along};
  }
  return {turn(h, e / strength, toward, p), along};
}

// vector_sum: pull is the sum of the detected cues' pulls; a zero or non-finite result
// leaves the heading unchanged.
AXG_HDI Vec3 vector_sum_turn(Vec3 h, Vec3 pull, const SteerParams& p) {
  const Vec3 v = h + p.vector_weight * pull;
  const double n = norm(v);
  if (!(n > 0.0) || !(n < HUGE_VAL)) return h;
  return v / n;
}

// Steers one axon; samples and pulls come from the field (particles.hpp, sensing.hpp,
// stencil.hpp). Cues outside their detection window are ignored. `neuron` keys the
// decision's draws: an axon's neuron id, or a growth cone's core::cone_key (arbours).
AXG_HDI Steered steer_axon(Vec3 h, const CueSample* samples, const Vec3* pull, const CueParams* cues, int cue_count,
                           const SenseParams& sp, const SteerParams& p, std::uint64_t seed, std::uint64_t neuron,
                           std::uint32_t decision) {
  if (p.model == GuidanceModel::kSnr) return snr_steer(h, samples, cues, cue_count, sp, p, seed, neuron, decision);
  if (p.model == GuidanceModel::kVectorSum || p.model == GuidanceModel::kSourceVectorSum) {
    Vec3 total{0.0, 0.0, 0.0};
    for (int k = 0; k < cue_count; ++k)
      if (detected(samples[k], cues[k])) total += pull[k];
    return {vector_sum_turn(h, total, p), 0.0};
  }
  return {h, 0.0};
}

// Growth-rate modulation (Mortimer et al. 2010): the step grows with the evidence along
// the heading, l = l0 (1 + m z / (1 + |z|)), within l0 (1 -+ m).
AXG_HDI double modulated_step(double l0, double along, const SteerParams& p) {
  const double a = along < 0.0 ? -along : along;
  double z = along / (1.0 + a);
  if (!(a < HUGE_VAL)) z = along > 0.0 ? 1.0 : (along < 0.0 ? -1.0 : 0.0);  // +-inf, or NaN as no evidence
  return l0 * (1.0 + p.modulation * z);
}

}  // namespace axg::core

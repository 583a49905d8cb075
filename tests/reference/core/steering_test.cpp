// Steering: the SNR turning model and vector_sum, at the level of single decisions.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <gsl/gsl_cdf.h>

#include <cfloat>
#include <cmath>

#include "axonguide/core/steering.hpp"

namespace axg::core {
namespace {

SteerParams snr_params(double turn = 0.10471975511965977) {
  SteerParams p{};
  p.model = GuidanceModel::kSnr;
  p.cos_turn = std::cos(turn);
  p.sin_turn = std::sin(turn);
  p.gain = 250;
  p.vector_weight = 0.1;
  return p;
}

bool finite(Vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

TEST(steering, OccupancyIsFiniteForAnyGammaAndPeaksAtOneHalf) {
  for (double g : {0.0, 1e-300, 1e-10, 0.5, 1.0, 1e10, 1e300, DBL_MAX}) {
    const double f = snr_occupancy(g);
    EXPECT_TRUE(std::isfinite(f)) << g;
    EXPECT_GE(f, 0.0) << g;
    EXPECT_LE(f, snr_occupancy(0.5)) << g;
  }
  EXPECT_EQ(snr_occupancy(0.0), 0.0);
  EXPECT_NEAR(snr_occupancy(1e-300), 1e-150, 1e-164);
  EXPECT_NEAR(snr_occupancy(1e300), 1e-300, 1e-314);
  EXPECT_NEAR(snr_occupancy(0.5), std::sqrt(0.5 / 3.375), 1e-16);
}

RC_GTEST_PROP(steering, OccupancyPeaksAtOneHalf, ()) {
  const double g = *rc::gen::inRange(0, 1000000) / 1000.0;
  RC_ASSERT(snr_occupancy(g) <= snr_occupancy(0.5));
}

TEST(steering, SnapshotOccupancyIsFiniteAndPeaksAtKd) {
  for (double g : {0.0, 1e-300, 1e-10, 0.5, 1.0, 1e10, 1e300, DBL_MAX, HUGE_VAL}) {
    const double f = snapshot_occupancy(g);
    EXPECT_TRUE(std::isfinite(f)) << g;
    EXPECT_GE(f, 0.0) << g;
    EXPECT_LE(f, snapshot_occupancy(1.0)) << g;
  }
  EXPECT_EQ(snapshot_occupancy(0.0), 0.0);
  EXPECT_EQ(snapshot_occupancy(HUGE_VAL), 0.0);
  EXPECT_DOUBLE_EQ(snapshot_occupancy(1.0), 0.5);
  EXPECT_DOUBLE_EQ(snapshot_occupancy(4.0), 2.0 / 5.0);
}

RC_GTEST_PROP(steering, SnapshotOccupancyPeaksAtOne, ()) {
  const double g = *rc::gen::inRange(0, 1000000) / 1000.0;
  RC_ASSERT(snapshot_occupancy(g) <= snapshot_occupancy(1.0));
}

// One exact cue of occupancy gamma (K_d = 1) and fractional gradient mu along g.
CueSample exact_cue(Vec3 g, double gamma, double mu, double width = 0.1) {
  return exact_sample(gamma, (mu * gamma / width) * (g / norm(g)));
}

CueParams cue_of(double sign) {
  CueParams c{};
  c.sign = sign;
  c.kd = 1.0;
  c.max_c = 1e300;
  return c;
}

SenseParams sense() {
  SenseParams sp{};
  sp.cone_width = 0.1;
  return sp;
}

Vec3 decide(Vec3 h, const CueSample* s, const CueParams* c, int k, const SteerParams& p, std::uint32_t n,
            std::uint32_t step) {
  return snr_steer(h, s, c, k, sense(), p, 1, n, step).heading;
}

TEST(steering, DegenerateGeometriesNeverGiveNaN) {
  const SteerParams p = snr_params();
  const Vec3 h{0, 0, 1};
  const CueParams cue = cue_of(1);
  // Parallel and antiparallel headings: a random perpendicular, a turn of exactly dtheta.
  for (Vec3 g : {Vec3{0, 0, 1}, Vec3{0, 0, -1}}) {
    for (std::uint32_t n = 0; n < 100; ++n) {
      const CueSample s = exact_cue(g, 0.5, 0.01);
      const Vec3 out = decide(h, &s, &cue, 1, p, n, 3);
      ASSERT_TRUE(finite(out));
      EXPECT_NEAR(norm(out), 1.0, 1e-15);
      EXPECT_NEAR(dot(out, h), p.cos_turn, 1e-12);
    }
  }
  for (double gamma : {1e-300, 1.0, 1e300}) {
    const CueSample s = exact_cue({1, 0, 0}, gamma, 1.0);
    EXPECT_TRUE(finite(decide(h, &s, &cue, 1, p, 7, 1))) << gamma;
  }
  // Zero gradient and zero concentration are not detected, and an undetected cue makes
  // no turn at all.
  EXPECT_FALSE(detected(exact_sample(1.0, {0, 0, 0}), cue));
  EXPECT_FALSE(detected(exact_sample(0.0, {1, 0, 0}), cue));
  EXPECT_TRUE(detected(exact_sample(1.0, {1, 0, 0}), cue));
  const CueSample none = exact_sample(0.0, {1, 0, 0});
  EXPECT_EQ(decide(h, &none, &cue, 1, p, 7, 1), h);
  // Outside the detection window.
  CueParams narrow = cue;
  narrow.min_c = 2;
  EXPECT_FALSE(detected(exact_sample(1.0, {1, 0, 0}), narrow));
}

// The turning model: X ~ N(SNR, 1) and the turn goes toward g_perp when X > 0, so over
// many independent neurons P(toward) = Phi(SNR), within the binomial error.
TEST(steering, TurnTowardProbabilityIsPhiOfSnr) {
  const SteerParams p = snr_params();
  const Vec3 h{0, 0, 1};
  const double sin_psi = std::sqrt(0.5);
  const CueParams cue = cue_of(1);
  const int n = 40000;
  // (SNR 0 is a zero gradient: not detected, no turn; see DegenerateGeometriesNeverGiveNaN.)
  for (double target : {-1.0, 1e-9, 0.25, 0.5, 1.0, 2.0}) {
    // SNR = gain mu occupancy(gamma) sin psi with gamma = 1/2.
    const double mu = std::fabs(target) / (p.gain * snr_occupancy(0.5) * sin_psi);
    const Vec3 gg = target < 0 ? Vec3{-1, 0, 1} : Vec3{1, 0, 1};  // a negative SNR is a cue on the other side
    const CueSample s = exact_cue(gg, 0.5, mu);
    int toward = 0;
    for (int i = 0; i < n; ++i) toward += (decide(h, &s, &cue, 1, p, static_cast<std::uint32_t>(i), 5).x > 0) == (gg.x > 0);
    const double expect = gsl_cdf_ugaussian_P(std::fabs(target));
    const double sigma = std::sqrt(expect * (1 - expect) / n);
    EXPECT_NEAR(static_cast<double>(toward) / n, expect, 4 * sigma + 1e-12) << "SNR " << target;
  }
}

// Antithetic decisions (SteerParams::decision_sign = -1, guidance.antithetic): P(toward) is
// still Phi(SNR); a cue and its mirror image (the gradient negated), decided on the same
// draws with the mirror's antithetic, give the same heading in space unless -SNR < Z < SNR,
// a fraction 2 Phi(SNR) - 1 of the neurons; and where there is no evidence the drawn side
// is negated with the draw, so the two turn the same way.
TEST(steering, AntitheticDecisionsKeepPhiAndTurnTheMirrorImageTheSameWay) {
  const SteerParams p = snr_params();
  SteerParams anti = p;
  anti.decision_sign = -1.0;
  const Vec3 h{0, 0, 1};
  const CueParams cue = cue_of(1);
  const int n = 40000;
  for (double target : {0.25, 1.0}) {
    const double mu = target / (p.gain * snr_occupancy(0.5) * std::sqrt(0.5));
    const CueSample s = exact_cue({1, 0, 1}, 0.5, mu), mirror = exact_cue({-1, 0, -1}, 0.5, mu);
    int toward = 0, differ = 0;
    for (int i = 0; i < n; ++i) {
      const std::uint32_t id = static_cast<std::uint32_t>(i);
      toward += snr_steer(h, &s, &cue, 1, sense(), anti, 1, id, 5).heading.x > 0;
      const Vec3 plain = snr_steer(h, &s, &cue, 1, sense(), p, 1, id, 5).heading;
      const Vec3 image = snr_steer(h, &mirror, &cue, 1, sense(), anti, 1, id, 5).heading;
      differ += !(plain == image);
    }
    const double expect = gsl_cdf_ugaussian_P(target), split = 2 * expect - 1;
    EXPECT_NEAR(static_cast<double>(toward) / n, expect, 4 * std::sqrt(expect * (1 - expect) / n)) << target;
    EXPECT_NEAR(static_cast<double>(differ) / n, split, 4 * std::sqrt(split * (1 - split) / n)) << target;
  }
  const CueSample parallel = exact_cue({0, 0, 1}, 0.5, 0.01);
  int sides = 0;
  for (std::uint32_t i = 0; i < 100; ++i) {
    const Vec3 plain = snr_steer(h, &parallel, &cue, 1, sense(), p, 1, i, 5).heading;
    EXPECT_EQ(plain, snr_steer(h, &parallel, &cue, 1, sense(), anti, 1, i, 5).heading) << i;
    sides += plain.x > 0;
  }
  EXPECT_GT(sides, 20);  // the side is random
  EXPECT_LT(sides, 80);
}

double p_toward(double gamma, NoiseForm noise, double mu = 0.004) {
  SteerParams p = snr_params();
  p.noise = noise;
  const CueParams cue = cue_of(1);
  const CueSample s = exact_cue({1, 0, 0}, gamma, mu);
  const int n = 20000;
  int toward = 0;
  for (int i = 0; i < n; ++i) toward += decide({0, 0, 1}, &s, &cue, 1, p, static_cast<std::uint32_t>(i), 1).x > 0;
  return static_cast<double>(toward) / n;
}

TEST(steering, BindingResponsePeaksAtHalfKd) {
  const double at_half = p_toward(0.5, NoiseForm::kBinding);
  EXPECT_GT(at_half, p_toward(0.1, NoiseForm::kBinding) + 0.02);
  EXPECT_GT(at_half, p_toward(2.0, NoiseForm::kBinding) + 0.02);
  EXPECT_NEAR(at_half, gsl_cdf_ugaussian_P(250 * 0.004 * snr_occupancy(0.5)), 0.015);
}

TEST(steering, SnapshotResponsePeaksAtKd) {
  const double at_one = p_toward(1.0, NoiseForm::kSnapshot, 0.003);
  EXPECT_GT(at_one, p_toward(0.2, NoiseForm::kSnapshot, 0.003) + 0.02);
  EXPECT_GT(at_one, p_toward(5.0, NoiseForm::kSnapshot, 0.003) + 0.02);
  EXPECT_NEAR(at_one, gsl_cdf_ugaussian_P(250 * 0.003 * 0.5), 0.015);
}

// One decision per step: two cues make one turn of exactly dtheta; a cue that carries no
// information (mu = 0: zero evidence) changes nothing; two equal and opposite cues cancel
// to a coin flip about a random side, still one turn.
TEST(steering, CuesCombineIntoOneDecision) {
  const SteerParams p = snr_params();
  const Vec3 h{0, 0, 1};
  const CueParams cues[2] = {cue_of(1), cue_of(1)};
  for (std::uint32_t n = 0; n < 200; ++n) {
    const CueSample two[2] = {exact_cue({1, 0, 0}, 0.5, 0.02), exact_cue({0, 1, 0}, 0.5, 0.01)};
    const Vec3 out = decide(h, two, cues, 2, p, n, 9);
    EXPECT_NEAR(dot(out, h), p.cos_turn, 1e-12);
    // The side is the evidence vector (2, 1, 0) / sqrt 5, or its opposite.
    const Vec3 side = normalized(out - dot(out, h) * h);
    EXPECT_NEAR(std::fabs(dot(side, normalized({2, 1, 0}))), 1.0, 1e-12);
    const CueSample with_blank[2] = {exact_cue({1, 0, 0}, 0.5, 0.02), exact_sample(0.5, {0, 0, 1e-3})};
    const CueSample alone = exact_cue({1, 0, 0}, 0.5, 0.02);
    EXPECT_EQ(decide(h, with_blank, cues, 2, p, n, 9), decide(h, &alone, cues, 1, p, n, 9));
  }
}

// A repellent is an attractant with the opposite sign: same decision, opposite side.
TEST(steering, RepellentMirrorsAttractant) {
  const SteerParams p = snr_params();
  const Vec3 h{0, 0, 1};
  const CueParams a = cue_of(1), r = cue_of(-1);
  for (std::uint32_t n = 0; n < 100; ++n) {
    const CueSample s = exact_cue({1, 0, 1}, 0.5, 0.01);
    const Vec3 ta = decide(h, &s, &a, 1, p, n, 2), tr = decide(h, &s, &r, 1, p, n, 2);
    EXPECT_NEAR(ta.x, -tr.x, 1e-15);
    EXPECT_NEAR(ta.z, tr.z, 1e-15);
  }
}

// Molecule-resolved: the count decision turns toward the perpendicular count dipole of the
// particles (the molecules), with no noise added.
TEST(steering, CountDecisionTurnsTowardTheDipole) {
  SteerParams p = snr_params();
  p.noise = NoiseForm::kCount;
  SenseParams sp = sense();
  sp.field = FieldKind::kParticles;
  sp.sensing = ParticleSensing::kMolecules;
  sp.c_per_particle = 0.01;
  const CueParams cue = cue_of(1);
  const CueSample s{0.5, {3, 0, 7}, {3, 0, 7}};
  for (std::uint32_t n = 0; n < 50; ++n) {
    const Steered out = snr_steer({0, 0, 1}, &s, &cue, 1, sp, p, 1, n, 4);
    EXPECT_GT(out.heading.x, 0.0);
    EXPECT_NEAR(out.heading.y, 0.0, 1e-15);
    EXPECT_NEAR(dot(out.heading, {0, 0, 1}), p.cos_turn, 1e-12);
    EXPECT_NEAR(out.along, 7 / std::sqrt(50.0 / 5.0), 1e-12);  // n = 0.5 / 0.01 = 50 particles
  }
}

// The count form on an exact field draws the molecules' count dipole in its Gaussian
// limit, so the turn goes to the +x side with probability Phi(SNR_count) exactly, with the
// molecule amount m.
TEST(steering, ExactFieldCountDecisionIsPhiOfSnrCount) {
  SteerParams p = snr_params();
  p.noise = NoiseForm::kCount;
  SenseParams sp = sense();
  sp.field = FieldKind::kAnalytic;
  const double a = 0.001, r = 0.5, volume = 4.0 / 3.0 * 3.141592653589793 * r * r * r;
  sp.molecule = a;
  sp.radius = r;
  sp.count_mean_scale = volume * r / (5.0 * a);
  sp.count_var_scale = volume / (5.0 * a);
  const CueParams cue = cue_of(1);
  const int n = 40000;
  for (double g : {0.002, 0.01, 0.03}) {
    const CueSample s = exact_sample(0.05, {g, 0.0, 0.0});
    int toward = 0;
    for (int i = 0; i < n; ++i)
      toward += snr_steer({0, 0, 1}, &s, &cue, 1, sp, p, 17, static_cast<std::uint32_t>(i), 3).heading.x > 0;
    const double expect = gsl_cdf_ugaussian_P(snr_count(0.05, g, a, r));
    const double sigma = std::sqrt(expect * (1 - expect) / n);
    EXPECT_NEAR(static_cast<double>(toward) / n, expect, 4 * sigma + 1e-12) << g;
  }
}

RC_GTEST_PROP(steering, ModulatedStepStaysWithinItsBounds, ()) {
  SteerParams p = snr_params();
  p.modulation = *rc::gen::inRange(0, 999) / 1000.0;
  const double z = *rc::gen::inRange(-1000000, 1000000) / 100.0;
  const double l = modulated_step(0.35, z, p);
  RC_ASSERT(l >= 0.35 * (1 - p.modulation) - 1e-15);
  RC_ASSERT(l <= 0.35 * (1 + p.modulation) + 1e-15);
  RC_ASSERT((z > 0) == (l > 0.35) || z == 0 || p.modulation == 0);
}

TEST(steering, VectorSumTurnsTowardThePull) {
  SteerParams p = snr_params();
  p.model = GuidanceModel::kVectorSum;
  const Vec3 h{0, 0, 1};
  const Vec3 out = vector_sum_turn(h, {5, 0, 0}, p);
  EXPECT_NEAR(norm(out), 1.0, 1e-15);
  EXPECT_NEAR(out.x / out.z, 0.5, 1e-15);
  EXPECT_EQ(vector_sum_turn(h, {0, 0, -10}, p), h);  // would cancel: heading kept
}

}  // namespace
}  // namespace axg::core

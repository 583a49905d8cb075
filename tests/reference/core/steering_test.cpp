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

Detection detection(Vec3 g, double gamma, double mu) { return {true, gamma, mu, g / norm(g)}; }

TEST(steering, DegenerateGeometriesNeverGiveNaN) {
  const SteerParams p = snr_params();
  const Vec3 h{0, 0, 1};
  // Parallel and antiparallel headings: a random perpendicular, a turn of exactly dtheta.
  for (Vec3 g : {Vec3{0, 0, 1}, Vec3{0, 0, -1}}) {
    for (std::uint32_t n = 0; n < 100; ++n) {
      const Vec3 out = snr_turn(h, detection(g, 0.5, 0.01), p, 1, n, 0, 3);
      ASSERT_TRUE(finite(out));
      EXPECT_NEAR(norm(out), 1.0, 1e-15);
      EXPECT_NEAR(dot(out, h), p.cos_turn, 1e-12);
    }
  }
  for (double gamma : {0.0, 1e-300, 1.0, 1e300}) {
    const Vec3 out = snr_turn(h, detection({1, 0, 0}, gamma, 1.0), p, 1, 7, 0, 1);
    EXPECT_TRUE(finite(out)) << gamma;
  }
  // Zero gradient and zero concentration are not detected.
  const CueParams cue{{0, 0, 0}, 1, 1, 1, 1, 1, 0, 1e300, 1, 1, 1, 1};
  SenseParams sp{};
  sp.cone_width = 0.1;
  EXPECT_FALSE(detect({1.0, {0, 0, 0}}, cue, sp).detected);
  EXPECT_FALSE(detect({0.0, {1, 0, 0}}, cue, sp).detected);
  EXPECT_TRUE(detect({1.0, {1, 0, 0}}, cue, sp).detected);
  // Outside the detection window.
  CueParams narrow = cue;
  narrow.min_c = 2;
  EXPECT_FALSE(detect({1.0, {1, 0, 0}}, narrow, sp).detected);
}

// The turning model: X ~ N(SNR, 1) and the turn goes toward g_perp when X > 0, so over
// many independent neurons P(toward) = Phi(SNR), within the binomial error.
TEST(steering, TurnTowardProbabilityIsPhiOfSnr) {
  const SteerParams p = snr_params();
  const Vec3 h{0, 0, 1};
  const Vec3 g{1, 0, 1};  // sin psi = 1/sqrt(2)
  const double sin_psi = std::sqrt(0.5);
  const int n = 40000;
  for (double target : {-1.0, 0.0, 0.25, 0.5, 1.0, 2.0}) {
    // SNR = gain mu occupancy(gamma) sin psi with gamma = 1/2.
    const double mu = std::fabs(target) / (p.gain * snr_occupancy(0.5) * sin_psi);
    const Vec3 gg = target < 0 ? Vec3{-1, 0, 1} : g;  // a negative SNR is a cue on the other side
    int toward = 0;
    for (int i = 0; i < n; ++i) {
      const Vec3 out = snr_turn(h, detection(gg, 0.5, mu), p, 99, static_cast<std::uint32_t>(i), 0, 5);
      toward += (out.x > 0) == (gg.x > 0);
    }
    const double expect = gsl_cdf_ugaussian_P(std::fabs(target));
    const double sigma = std::sqrt(expect * (1 - expect) / n);
    EXPECT_NEAR(static_cast<double>(toward) / n, expect, 4 * sigma + 1e-12) << "SNR " << target;
  }
}

TEST(steering, ResponsePeaksAtHalfKd) {
  const SteerParams p = snr_params();
  const Vec3 h{0, 0, 1}, g{1, 0, 0};
  const int n = 20000;
  auto p_toward = [&](double gamma) {
    int toward = 0;
    for (int i = 0; i < n; ++i)
      toward += snr_turn(h, detection(g, gamma, 0.004), p, 3, static_cast<std::uint32_t>(i), 0, 1).x > 0;
    return static_cast<double>(toward) / n;
  };
  const double at_half = p_toward(0.5);
  EXPECT_GT(at_half, p_toward(0.1) + 0.02);
  EXPECT_GT(at_half, p_toward(2.0) + 0.02);
  EXPECT_NEAR(at_half, gsl_cdf_ugaussian_P(250 * 0.004 * snr_occupancy(0.5)), 0.015);
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

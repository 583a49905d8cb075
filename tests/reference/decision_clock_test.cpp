// The continuum decision's clock and the growth of its evidence with the integration time
// (model/steering.hpp): every step belongs to one interval, each interval closes once, its
// decision falls on the step whose end reaches j T, and the variance factors have their
// limits.
#include <cmath>

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include "axonguide/model/steering.hpp"
#include "axonguide/scene/scene.hpp"

namespace axg {
namespace {

DecisionClock clock_of(double dt, double t) {
  Scene s;
  s.dt = dt;
  s.guidance.integration_time = t;
  return decision_clock(s);
}

// For any T and dt <= T: intervals partition the steps in order, a decision closes each one
// on the step whose end first reaches j T, and its sample count is the interval's length.
RC_GTEST_PROP(decision_clock, IntervalsPartitionTheStepsAndCloseAtTheirEnd, ()) {
  const double dt = *rc::gen::inRange(1, 1000) / 250.0;
  const bool whole = *rc::gen::arbitrary<bool>();
  const double q = whole ? static_cast<double>(*rc::gen::inRange(1, 9)) : 1.0 + *rc::gen::inRange(1, 7000) / 1000.0;
  const double t = q * dt;
  const DecisionClock c = clock_of(dt, t);
  RC_ASSERT(!c.per_step);
  RC_ASSERT((c.every != 0) == (whole || std::fabs(q - std::round(q)) < 1e-9));
  std::uint32_t decided = 0, in_interval = 0;
  for (std::uint32_t step = 1; step <= 200; ++step) {
    const core::Decision d = c.at(step);
    RC_ASSERT(d.open == (in_interval == 0));
    ++in_interval;
    RC_ASSERT(d.samples == in_interval);
    RC_ASSERT(d.index == decided + 1);
    if (d.decide) {
      ++decided;
      // Its end reaches the interval's end; the step before did not.
      RC_ASSERT(step * dt >= decided * t * (1.0 - 1e-9));
      RC_ASSERT((step - 1) * dt < decided * t * (1.0 - 1e-12) + 1e-12);
      RC_ASSERT(in_interval >= static_cast<std::uint32_t>(std::floor(q - 1e-9)));
      RC_ASSERT(in_interval <= static_cast<std::uint32_t>(std::ceil(q + 1e-9)));
      in_interval = 0;
    }
    RC_ASSERT(c.completed(step) == decided);
  }
}

TEST(decision_clock, PerStepDecidesEveryStepOnItsOwnSample) {
  Scene s;
  s.guidance.decision = DecisionRule::kPerStep;
  s.dt = 0.3;
  const DecisionClock c = decision_clock(s);
  EXPECT_FALSE(c.sums());
  for (std::uint32_t step = 1; step < 50; ++step) {
    const core::Decision d = c.at(step);
    EXPECT_TRUE(d.open && d.decide);
    EXPECT_EQ(d.samples, 1u);
    EXPECT_EQ(d.index, step);  // the report's draw: keyed on the step
  }
}

TEST(decision_clock, OneStepAnIntervalKeepsNoSums) {
  EXPECT_FALSE(clock_of(1.0, 1.0).sums());
  EXPECT_FALSE(clock_of(0.25, 0.25).sums());
  EXPECT_TRUE(clock_of(0.5, 1.0).sums());
  EXPECT_TRUE(clock_of(0.4, 1.0).sums());
  // 0.1 x 10 is not 1 in binary: still ten steps an interval, exactly.
  const DecisionClock c = clock_of(0.1, 1.0);
  EXPECT_EQ(c.every, 10u);
  EXPECT_TRUE(c.at(10).decide);
  EXPECT_FALSE(c.at(9).decide);
  EXPECT_EQ(c.at(30).index, 3u);
}

TEST(decision_clock, IntegrationTimeDefaultsToOneUnitOrThreeMinutes) {
  Scene s;
  EXPECT_EQ(integration_time(s), 1.0);
  s.units.time = "min";
  EXPECT_EQ(integration_time(s), 3.0);
  s.units.time = "h";
  EXPECT_EQ(integration_time(s), 0.05);
  s.units.time = "s";
  EXPECT_EQ(integration_time(s), 180.0);
  s.guidance.integration_time = 7.0;
  EXPECT_EQ(integration_time(s), 7.0);
}

// The mean of a unit-variance process with autocorrelation e^(-s/tau) over T = x tau.
TEST(evidence_over_time, ExponentialCorrelationHasItsLimits) {
  EXPECT_EQ(mean_variance_exponential(0.0), 1.0);
  EXPECT_NEAR(mean_variance_exponential(1e-3 * (1 - 1e-9)), mean_variance_exponential(1e-3 * (1 + 1e-9)), 1e-12);
  EXPECT_NEAR(mean_variance_exponential(1.0), 2.0 * (1.0 - 1.0 + std::exp(-1.0)), 1e-15);
  EXPECT_NEAR(mean_variance_exponential(1e4) * 1e4 / 2.0, 1.0, 1e-3);  // 2 tau / T
}

// The count dipole's factor: 1 at T = 0, falling, and 2 tau_d / T = 4 / (21 theta) for T >>
// tau_d = 2 r^2 / (21 D).
TEST(evidence_over_time, CountDipoleVarianceFallsToItsCorrelationTime) {
  EXPECT_EQ(dipole_mean_variance(0.0), 1.0);
  EXPECT_NEAR(dipole_mean_variance(1e-7), 1.0, 1e-3);
  double before = 1.0;
  for (double theta : {0.001, 0.01, 0.1, 0.5, 1.0, 2.0, 5.0, 20.0}) {
    const double v = dipole_mean_variance(theta);
    EXPECT_LT(v, before) << theta;
    EXPECT_GT(v, 0.0) << theta;
    before = v;
  }
  EXPECT_NEAR(dipole_mean_variance(200.0) / (4.0 / (21.0 * 200.0)), 1.0, 0.01);
}

}  // namespace
}  // namespace axg

// The branching rule (core/branching.hpp) and the tree process (morphology/tree_process.hpp):
// the order weights leave a tree's total rate alone, the per-step probability integrates D
// exactly, and the trees are the same bytes for any thread count.
#include <cmath>

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>
#include <tbb/global_control.h>

#include "axonguide/core/branching.hpp"
#include "axonguide/morphology/tree_process.hpp"

namespace axg {
namespace {

// For any orders and S: sum_i 2^(-S gamma_i) / C = n, with C from the order histogram, so
// the tree's total rate is n D n^(-E) whatever S is (the normalisation C of the BESTL model).
RC_GTEST_PROP(branching, OrderWeightsLeaveTheTreesTotalRate, ()) {
  const int n = *rc::gen::inRange(1, 60);
  const double s = *rc::gen::inRange(-200, 200) / 100.0;
  std::vector<int> orders(n);
  for (int& o : orders) o = *rc::gen::inRange(0, 12);
  std::vector<int> counts(13, 0);
  for (int o : orders) ++counts[o];
  const double c = core::mean_order_weight(s, counts.data(), 13, n);
  double total = 0;
  for (int o : orders) total += core::order_weight(s, o) / c;
  RC_ASSERT(std::fabs(total - n) <= 1e-12 * n);
}

TEST(branching, TheStepProbabilityIntegratesTheBaselineExactly) {
  core::BranchingParams p;
  p.b_inf = 3.0;
  p.tau = 2.0;
  // Over any partition of [0, T] the step integrals add up to B_inf (1 - e^(-T/tau)).
  double sum = 0;
  for (int k = 0; k < 37; ++k) sum += core::baseline_integral(p, k * 0.1, (k + 1) * 0.1);
  EXPECT_NEAR(sum, 3.0 * (1 - std::exp(-3.7 / 2.0)), 1e-13);
  // A lone cone (n = 1, C = its own weight): 1 - exp(-integral), whatever its order.
  EXPECT_NEAR(core::branch_probability(p, 0.0, 0.5, 1, 4, core::order_weight(0.0, 4)),
              1 - std::exp(-3.0 * (1 - std::exp(-0.25))), 1e-13);
  // An infinite tau: B_inf spread evenly over the period.
  p.tau = 0;
  p.period = 10;
  EXPECT_DOUBLE_EQ(core::baseline_integral(p, 2.0, 3.0), 0.3);
  EXPECT_EQ(core::competition(0.7, 1), 1.0);
  EXPECT_EQ(core::order_weight(0.0, 9), 1.0);
}

TEST(tree_process, TheSameTreesForAnyThreadCount) {
  morphology::TreeProcess p;
  p.branching.b_inf = 3;
  p.branching.e = 0.4;
  p.branching.s = 0.5;
  p.branching.tau = 0.7;
  p.elongation.v0 = 10;
  p.elongation.f = 0.3;
  p.dt = 0.01;
  p.steps = 100;
  std::vector<morphology::TreeOutcome> one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = morphology::grow_trees(p, 300);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two = morphology::grow_trees(p, 300);
  }
  ASSERT_EQ(one.size(), two.size());
  int branched = 0;
  for (std::size_t t = 0; t < one.size(); ++t) {
    EXPECT_EQ(one[t].terminals, two[t].terminals);
    EXPECT_EQ(one[t].total_length, two[t].total_length);
    EXPECT_EQ(one[t].terminal_length, two[t].terminal_length);
    EXPECT_EQ(one[t].intermediate_length, two[t].intermediate_length);
    EXPECT_EQ(one[t].terminals - one[t].branch_points, 1);  // binary from one stem
    branched += one[t].branch_points > 0;
  }
  EXPECT_GT(branched, 100);
  // The lengths add up: every step each cone grows v0 n^(-F) dt.
  for (const auto& t : one)
    EXPECT_NEAR(t.total_length, t.terminal_length + t.intermediate_length, 1e-9 * t.total_length);
}

}  // namespace
}  // namespace axg

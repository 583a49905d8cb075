// The particle estimate (core/estimate.hpp) and the mesh interpolation every mesh-based
// estimate goes through (core/mesh.hpp).
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "axonguide/core/estimate.hpp"
#include "axonguide/core/mesh.hpp"
#include "axonguide/core/steering.hpp"

namespace axg::core {
namespace {

double coordinate(int lo, int hi, int scale) { return *rc::gen::inRange(lo, hi) / static_cast<double>(scale); }

// Every particle deposits exactly 2^32 in fixed point, over 8 distinct nodes of the mesh,
// wherever it is (outside the mesh it is clamped to the nearest cell).
RC_GTEST_PROP(estimate, CloudInCellDepositsExactlyOneParticle, ()) {
  const int n = *rc::gen::inRange(2, 40);
  const double h = coordinate(1, 1000, 100);
  const Vec3 origin{coordinate(-5000, 5000, 100), coordinate(-5000, 5000, 100), coordinate(-5000, 5000, 100)};
  const double span = h * (n - 1);
  const Vec3 x{origin.x + coordinate(-200, 1200, 1000) * span, origin.y + coordinate(-200, 1200, 1000) * span,
               origin.z + coordinate(-200, 1200, 1000) * span};
  const CicDeposit d = cic_deposit(x, origin, h, n);
  std::uint64_t total = 0;
  std::vector<std::size_t> idx;
  for (int m = 0; m < 8; ++m) {
    total += d.weight[m];
    RC_ASSERT(d.index[m] < static_cast<std::size_t>(n) * n * n);
    idx.push_back(d.index[m]);
  }
  RC_ASSERT(total == kDepositUnitInt);
  std::sort(idx.begin(), idx.end());
  RC_ASSERT(std::adjacent_find(idx.begin(), idx.end()) == idx.end());
}

// The deposit is linear in position: for a particle inside the mesh, sum_m w_m node_m = x
// (to the fixed point's resolution), so a uniform density deposits a uniform field.
RC_GTEST_PROP(estimate, DepositCentroidIsTheParticle, ()) {
  const int n = 6;
  const double h = 0.5;
  const Vec3 origin{-1.25, -1.25, -1.25};
  const Vec3 x{coordinate(-1249, 1249, 1000), coordinate(-1249, 1249, 1000), coordinate(-1249, 1249, 1000)};
  const CicDeposit d = cic_deposit(x, origin, h, n);
  Vec3 c{0, 0, 0};
  for (int m = 0; m < 8; ++m) {
    const std::size_t i = d.index[m] % n, j = (d.index[m] / n) % n, k = d.index[m] / (n * n);
    const Vec3 node{origin.x + h * i, origin.y + h * j, origin.z + h * k};
    c += (static_cast<double>(d.weight[m]) / kDepositUnit) * node;
  }
  RC_ASSERT(std::fabs(c.x - x.x) < 1e-8 && std::fabs(c.y - x.y) < 1e-8 && std::fabs(c.z - x.z) < 1e-8);
}

// The bias-corrected moving average estimates a steady deposit without lag from step 1,
// for any beta, and beta = 1 keeps only the current step.
RC_GTEST_PROP(estimate, MovingAverageOfASteadyDepositIsTheDeposit, ()) {
  const double beta = *rc::gen::inRange(1, 1001) / 1000.0;
  const auto q = static_cast<std::uint64_t>(*rc::gen::inRange(0, 1 << 30)) << 20;
  const double scale = 1e-12;
  double m = 0.0;
  for (std::uint32_t t = 1; t <= 300; ++t) {
    m = fold_node(m, q, estimate_fold(t, beta, scale));
    RC_ASSERT(std::fabs(m - scale * static_cast<double>(q)) <= 1e-12 * scale * static_cast<double>(q) + 1e-300);
  }
  const EstimateFold only = estimate_fold(17, 1.0, scale);
  RC_ASSERT(only.keep == 0.0);
  RC_ASSERT(only.take == 1.0);
}

// The moving average's weights: M_t = sum_s w_s q_s with w_s = beta (1 - beta)^(t - s) / W_t.
TEST(estimate, MovingAverageWeightsAreGeometric) {
  const double beta = 0.3, scale = 1.0;
  const std::uint64_t q[4] = {4, 0, 0, 0};
  double m = 0.0;
  for (std::uint32_t t = 1; t <= 4; ++t) m = fold_node(m, q[t - 1], estimate_fold(t, beta, scale));
  const double w4 = 1.0 - std::pow(0.7, 4);
  EXPECT_NEAR(m, 4.0 * beta * std::pow(0.7, 3) / w4, 1e-14);
  EXPECT_EQ(power_of(0.5, 10), std::ldexp(1.0, -10));
  EXPECT_EQ(power_of(3.0, 0), 1.0);
}

std::vector<double> mesh_of(int n, double h, Vec3 origin, double (*f)(Vec3, const double*), const double* coef) {
  std::vector<double> c(static_cast<std::size_t>(n) * n * n);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) c[node_index(i, j, k, n)] = f({origin.x + h * i, origin.y + h * j, origin.z + h * k}, coef);
  return c;
}

double linear(Vec3 x, const double* a) { return a[0] + a[1] * x.x + a[2] * x.y + a[3] * x.z; }
double quadratic(Vec3 x, const double* a) {
  return linear(x, a) + a[4] * x.x * x.x + a[5] * x.y * x.y + a[6] * x.z * x.z + a[7] * x.x * x.y + a[8] * x.y * x.z +
         a[9] * x.x * x.z;
}

// Value and gradient are exact for linear fields anywhere inside the mesh, and the gradient
// is exact for quadratic fields in the cells whose nodes are all interior (centred
// differences are exact for quadratics, and trilinear interpolation reproduces the linear
// gradient): the interpolation's errors are O(h^2).
RC_GTEST_PROP(mesh, SampleIsExactForLinearAndItsGradientForQuadraticFields, ()) {
  double a[10];
  for (double& v : a) v = coordinate(-1000, 1000, 100);
  const int n = 7;
  const double h = coordinate(10, 200, 100);
  const Vec3 origin{-3 * h, -3 * h, -3 * h};
  const GridFieldView lin{origin, h, n, nullptr, 0};
  const std::vector<double> cl = mesh_of(n, h, origin, linear, a), cq = mesh_of(n, h, origin, quadratic, a);
  // A point in the cells [1, 5] of every axis (their nodes and neighbours are interior).
  const Vec3 x{h * coordinate(-1999, 1999, 1000), h * coordinate(-1999, 1999, 1000), h * coordinate(-1999, 1999, 1000)};
  GridFieldView g = lin;
  g.c = cl.data();
  const MeshSample sl = mesh_sample(x, g);
  const double tol = 1e-9 * (1 + std::fabs(a[0]) + h * (std::fabs(a[1]) + std::fabs(a[2]) + std::fabs(a[3])));
  RC_ASSERT(std::fabs(sl.value - linear(x, a)) < tol);
  RC_ASSERT(std::fabs(sl.grad.x - a[1]) < 1e-9 * (1 + std::fabs(a[1])) * 10);
  RC_ASSERT(std::fabs(sl.grad.y - a[2]) < 1e-9 * (1 + std::fabs(a[2])) * 10);
  RC_ASSERT(std::fabs(sl.grad.z - a[3]) < 1e-9 * (1 + std::fabs(a[3])) * 10);
  g.c = cq.data();
  const MeshSample sq = mesh_sample(x, g);
  const Vec3 exact{a[1] + 2 * a[4] * x.x + a[7] * x.y + a[9] * x.z, a[2] + 2 * a[5] * x.y + a[7] * x.x + a[8] * x.z,
                   a[3] + 2 * a[6] * x.z + a[8] * x.y + a[9] * x.x};
  double scale = 1;
  for (double v : a) scale += std::fabs(v);
  RC_ASSERT(std::fabs(sq.grad.x - exact.x) < 1e-8 * scale);
  RC_ASSERT(std::fabs(sq.grad.y - exact.y) < 1e-8 * scale);
  RC_ASSERT(std::fabs(sq.grad.z - exact.z) < 1e-8 * scale);
}

// A sample's halves: C is their mean, grad the even half's gradient, grad_check the odd's.
TEST(estimate, SampleTakesTheDirectionFromOneHalfAndTheMagnitudeFromTheOther) {
  const int n = 4;
  const std::size_t nodes = 64;
  std::vector<double> c(2 * nodes);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        c[node_index(i, j, k, n)] = 1.0 + 0.5 * i;           // even half: grad (0.5 / h, 0, 0)
        c[nodes + node_index(i, j, k, n)] = 3.0 + 0.25 * j;  // odd half: grad (0, 0.25 / h, 0)
      }
  EstimateSet set{};
  set.h = 1.0, set.n = n, set.nodes = nodes, set.c = c.data();
  const CueSample s = estimate_sample({1.5, 1.5, 1.5}, set, 0);
  EXPECT_DOUBLE_EQ(s.c, 0.5 * ((1.0 + 0.75) + (3.0 + 0.375)));
  EXPECT_NEAR(s.grad.x, 0.5, 1e-15);
  EXPECT_NEAR(s.grad.y, 0.0, 1e-15);
  EXPECT_NEAR(s.grad_check.y, 0.25, 1e-15);
  // The decision takes grad_check's component along grad: here orthogonal, so no gradient.
  const Vec3 g = decision_gradient(s);
  EXPECT_EQ(norm(g), 0.0);
  EXPECT_EQ(estimate_half_of(6), 0);
  EXPECT_EQ(estimate_half_of(7), 1);
}

// For an exact sample the decision gradient is the gradient, and a zero gradient gives zero.
RC_GTEST_PROP(steering, DecisionGradientOfAnExactSampleIsItsGradient, ()) {
  const Vec3 g{coordinate(-1000, 1000, 10), coordinate(-1000, 1000, 10), coordinate(-1000, 1000, 10)};
  const CueSample s{1.0, g, g};
  const Vec3 d = decision_gradient(s);
  RC_ASSERT(norm(d - g) <= 1e-12 * (1 + norm(g)));
}

}  // namespace
}  // namespace axg::core

// The count form's target: the molecules in the sensing ball, as a mean concentration and an
// effective gradient g = (5 / (V r^2)) int_ball C(x + y) y dy (core/sensing.hpp, core/mesh.hpp).
// The closed forms against Monte Carlo integration over the ball, their continuity where the
// source enters the ball and at kappa = 0, and the mesh's node sums converging at O(h^2).
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "axonguide/core/mesh.hpp"
#include "axonguide/core/random.hpp"
#include "axonguide/core/sensing.hpp"

namespace axg::core {
namespace {

constexpr double kPi = 3.141592653589793;

CueParams source(Vec3 at, double lambda) {
  CueParams c{};
  c.position = at;
  c.sign = 1.0;
  c.inv_lambda = lambda > 0 ? 1.0 / lambda : 0.0;
  c.analytic_scale = 2.0;
  return c;
}

SenseParams ball(double r) {
  SenseParams p{};
  p.radius = r;
  p.analytic_rmin = 0.0;
  p.ball = true;
  return p;
}

// Monte Carlo over the ball: the mean of C and of C y (5 / r^2), with their standard errors.
struct Integral {
  double mean, mean_se;
  Vec3 g, g_se;
};
template <class F>
Integral monte_carlo(Vec3 x, double r, F&& c, int n) {
  double s = 0, s2 = 0;
  Vec3 gs{0, 0, 0}, gs2{0, 0, 0};
  for (int i = 0; i < n; ++i) {
    Rng rng(5, Stream::kValidation, static_cast<std::uint64_t>(i), 17);
    Vec3 y;
    do {
      y = {2 * rng.uniform() - 1, 2 * rng.uniform() - 1, 2 * rng.uniform() - 1};
    } while (norm2(y) > 1.0);
    y = r * y;
    const double v = c(x + y);
    s += v, s2 += v * v;
    const Vec3 w = (5.0 / (r * r) * v) * y;
    gs += w;
    gs2 += Vec3{w.x * w.x, w.y * w.y, w.z * w.z};
  }
  const double m = s / n;
  const Vec3 g = gs / n;
  auto se = [&](double sum2, double mean) { return std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n); };
  return {m, se(s2, m), g, {se(gs2.x, g.x), se(gs2.y, g.y), se(gs2.z, g.z)}};
}

double analytic_c(Vec3 y, const CueParams& s) {
  const double d = norm(y - s.position);
  return s.analytic_scale * std::exp(-d * s.inv_lambda) / d;
}

TEST(ball, AnalyticSourceOutsideAndInsideTheBallMatchesMonteCarlo) {
  const double r = 0.5;
  for (double lambda : {0.0, 0.3, 1.0, 3.2}) {
    for (double d : {0.0, 0.1, 0.3, 0.49, 0.5, 0.7, 1.5, 4.0}) {
      const CueParams s = source({d, 0, 0}, lambda);
      const Vec3 x{0, 0, 0};
      const CueSample got = analytic_ball_sample(x, s, ball(r));
      const Integral mc = monte_carlo(x, r, [&](Vec3 y) { return analytic_c(y, s); }, 400000);
      EXPECT_NEAR(got.c, mc.mean, 5 * mc.mean_se + 1e-12) << "lambda " << lambda << " d " << d;
      EXPECT_NEAR(got.grad.x, mc.g.x, 5 * mc.g_se.x + 1e-12) << "lambda " << lambda << " d " << d;
      EXPECT_EQ(got.grad.y, 0.0);
      EXPECT_EQ(got.grad.z, 0.0);
      EXPECT_EQ(got.grad_check.x, got.grad.x);
    }
  }
}

// Where the source crosses the ball's surface the two forms meet; kappa -> 0 is the Coulomb
// form; far from the source the ball's factors tend to 1 times the field at x.
TEST(ball, AnalyticFormsAreContinuous) {
  const double r = 0.5;
  for (double lambda : {0.0, 1e-6, 0.05, 0.7, 3.2, 1e6}) {
    const double step = 1e-12 * r;  // the field itself changes by (1/d + kappa) step over it
    const CueSample in = analytic_ball_sample({0, 0, 0}, source({r - step, 0, 0}, lambda), ball(r));
    const CueSample on = analytic_ball_sample({0, 0, 0}, source({r, 0, 0}, lambda), ball(r));
    const double tol = 1e-9 + 2.0 * (1.0 / r + (lambda > 0 ? 1.0 / lambda : 0.0)) * step;
    EXPECT_NEAR(in.c / on.c, 1.0, tol) << lambda;
    EXPECT_NEAR(in.grad.x / on.grad.x, 1.0, tol) << lambda;
  }
  for (double d : {0.0, 0.2, 0.45}) {
    const CueSample coulomb = analytic_ball_sample({0, 0, 0}, source({d, 0, 0}, 0.0), ball(r));
    const CueSample near = analytic_ball_sample({0, 0, 0}, source({d, 0, 0}, 1e7), ball(r));
    EXPECT_NEAR(near.c / coulomb.c, 1.0, 1e-6) << d;
    if (d > 0) {
      EXPECT_NEAR(near.grad.x / coulomb.grad.x, 1.0, 1e-6) << d;
    }
  }
  // A small ball: the point values.
  const CueParams s = source({2.0, 0, 0}, 1.0);
  const CueSample point = analytic_sample({0, 0, 0}, s, ball(1e-4));
  const CueSample tiny = analytic_ball_sample({0, 0, 0}, s, ball(1e-4));
  EXPECT_NEAR(tiny.c / point.c, 1.0, 1e-8);
  EXPECT_NEAR(tiny.grad.x / point.grad.x, 1.0, 1e-8);
}

TEST(ball, ExponentialImposedProfileMatchesMonteCarlo) {
  ImposedParams q{};
  q.profile = ImposedProfile::kExponential;
  q.direction = normalized(Vec3{1, 2, -1});
  q.c0 = 0.7;
  CueParams cue{};
  for (double rate : {0.0, 0.01, 0.5, 3.0}) {
    q.rate = rate;
    const double r = 0.8;
    const Vec3 x{0.3, -0.2, 0.1};
    const CueSample got = imposed_ball_sample(x, cue, q, r);
    const Integral mc = monte_carlo(x, r, [&](Vec3 y) { return q.c0 * std::exp(q.rate * dot(y, q.direction)); }, 400000);
    EXPECT_NEAR(got.c, mc.mean, 5 * mc.mean_se + 1e-10) << rate;
    EXPECT_NEAR(got.grad.x, mc.g.x, 5 * mc.g_se.x + 1e-10) << rate;
    EXPECT_NEAR(got.grad.y, mc.g.y, 5 * mc.g_se.y + 1e-10) << rate;
    EXPECT_NEAR(got.grad.z, mc.g.z, 5 * mc.g_se.z + 1e-10) << rate;
  }
}

// The mesh's ball rule (degree 5 over the trilinear interpolant): exact for a linear field
// wherever the tip sits, and converging on the analytic field's exact ball at second order in
// h, down to the rule's own error (O((r/d)^6), about 1e-4 here).
TEST(ball, MeshRuleIsExactForLinearFields) {
  const double h = 0.37, r = 0.5;
  const int n = 12;
  const Vec3 origin{-2.0, -2.0, -2.0}, g0{0.3, -1.1, 0.7};
  std::vector<double> c(static_cast<std::size_t>(n) * n * n);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) c[node_index(i, j, k, n)] = 2.0 + dot(g0, origin + h * Vec3{double(i), double(j), double(k)});
  const GridFieldView g{origin, h, n, c.data(), 0};
  for (int t = 0; t < 50; ++t) {
    const Vec3 x{-0.5 + 0.021 * t, 0.37 - 0.013 * t, 0.011 * t};
    const MeshSample m = mesh_ball_sample(x, g, r);
    EXPECT_NEAR(m.value, 2.0 + dot(g0, x), 1e-12);
    EXPECT_NEAR(norm(m.grad - g0), 0.0, 1e-12);
  }
}

TEST(ball, MeshRuleConvergesToTheBallAtSecondOrder) {
  const double r = 0.5;
  const CueParams s = source({2.0, 0.3, -0.1}, 1.0);
  const Vec3 x{0.113, 0.071, -0.029};
  const CueSample exact = analytic_ball_sample(x, s, ball(r));
  const MeshSample rule = ball_rule(x, r, [&](Vec3 p) { return analytic_c(p, s); });
  // The rule on the exact field: within 2e-3 of the ball's integrals at d = 3.9 r.
  EXPECT_NEAR(rule.value / exact.c, 1.0, 2e-4);
  EXPECT_LT(norm(rule.grad - exact.grad) / norm(exact.grad), 2e-3);
  std::vector<double> err;
  for (double h : {0.5, 0.25, 0.125, 0.0625}) {
    const int n = static_cast<int>(std::lround(3.0 / h)) + 1;
    const Vec3 origin{-1.5, -1.5, -1.5};
    std::vector<double> c(static_cast<std::size_t>(n) * n * n);
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
          c[node_index(i, j, k, n)] = analytic_c(origin + h * Vec3{double(i), double(j), double(k)}, s);
    const GridFieldView g{origin, h, n, c.data(), 0};
    const MeshSample m = mesh_ball_sample(x, g, r);
    err.push_back(std::fabs(m.value / rule.value - 1.0) + norm(m.grad - rule.grad) / norm(rule.grad));
  }
  // Second order in h towards the rule on the exact field (the trilinear interpolant's error,
  // uneven at the coarsest levels, where the points' places in their cells change).
  EXPECT_GT(std::log2(err.front() / err.back()) / 3.0, 1.8) << err.front() << " -> " << err.back();
  for (std::size_t i = 1; i < err.size(); ++i)
    EXPECT_GT(std::log2(err[i - 1] / err[i]), 0.8) << "h level " << i << ": errors " << err[i - 1] << " -> " << err[i];
  EXPECT_LT(err.back(), 1e-3);
}

}  // namespace
}  // namespace axg::core

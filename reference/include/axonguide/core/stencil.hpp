#pragma once
// The grid field (SPEC §3.3, the report's Eulerian alternative):
//   dc/dt = D lap(c) - k c + sources
// on a uniform grid of n^3 nodes, node (i, j, k) at origin + h (i, j, k), index
// (k n + j) n + i. Boundaries: `absorbing` (c = 0 on the faces) or `reflecting` (zero
// flux: the ghost node mirrors the first interior one). Two schemes:
// - explicit FTCS, 7-point Laplacian: stable and non-negative while
//   dt (6 D / h^2 + k) <= 1; the driver sub-steps to that limit or refuses;
// - implicit, locally one-dimensional backward Euler: (1 - dt D d_xx), then d_yy, then
//   d_zz, each a tridiagonal solve per line (Thomas), then the decay c / (1 + k dt).
//   Every matrix is an M-matrix and Thomas only adds non-negative terms, so the result is
//   non-negative for any dt, even in floating point.
#include <cstddef>
#include <cstdint>

#include "cues.hpp"
#include "hd.hpp"
#include "mesh.hpp"
#include "sensing.hpp"
#include "vec3.hpp"

namespace axg::core {

// The grid's value and gradient at x (mesh.hpp: trilinear value, interpolated centred
// differences for the gradient); a grid is exact, so the gradient is its own check.
AXG_HDI CueSample grid_sample(Vec3 x, const GridFieldView& g) {
  const MeshSample m = mesh_sample(x, g);
  return {m.value, m.grad, m.grad};
}

// The grids of all cues (cue k's n^3 values at c[k]).
struct GridFieldSet {
  Vec3 origin;  // LU, node (0,0,0)
  double h;     // LU
  int n;        // nodes per axis
  const double* c[kMaxCues];
  int k0 = 0;   // the first plane stored (a slab of a decomposed grid)
};

AXG_HDI GridFieldView cue_view(const GridFieldSet& s, int k) { return {s.origin, s.h, s.n, s.c[k], s.k0}; }

// The sensing ball of radius r over a grid (mesh.hpp, mesh_ball_sample): the count form's
// mean concentration and effective gradient.
AXG_HDI CueSample grid_ball_sample(Vec3 x, const GridFieldView& g, double r) {
  const MeshSample m = mesh_ball_sample(x, g, r);
  return {m.value, m.grad, m.grad};
}

// Every cue's sample (at the tip, or over the sensing ball for the count form) and signed unit
// gradient (its vector_sum pull) from the grids.
AXG_HDI void sample_grid_field(Vec3 x, const GridFieldSet& set, const CueParams* cues, int cue_count,
                               const SenseParams& p, CueSample* samples, Vec3* pull) {
  for (int k = 0; k < cue_count; ++k) {
    samples[k] = p.ball ? grid_ball_sample(x, cue_view(set, k), p.radius) : grid_sample(x, cue_view(set, k));
    pull[k] = signed_unit_gradient(samples[k], cues[k].sign);
  }
}

// A source adds `total` (concentration x LU^3) per step, spread trilinearly over the 8
// nodes around its position and divided by the node volume h^3. Applied in index order.
struct SourceDeposit {
  std::size_t index[8];
  double value[8];
};

AXG_HDI SourceDeposit source_deposit(Vec3 p, double total, Vec3 origin, double h, int n) {
  int i, j, l;
  double fx, fy, fz;
  mesh_locate(p.x, origin.x, h, n, &i, &fx);
  mesh_locate(p.y, origin.y, h, n, &j, &fy);
  mesh_locate(p.z, origin.z, h, n, &l, &fz);
  const double per_volume = total / (h * h * h);
  SourceDeposit d{};
  int m = 0;
  for (int dz = 0; dz <= 1; ++dz)
    for (int dy = 0; dy <= 1; ++dy)
      for (int dx = 0; dx <= 1; ++dx, ++m) {
        const double w = (dx ? fx : 1.0 - fx) * (dy ? fy : 1.0 - fy) * (dz ? fz : 1.0 - fz);
        d.index[m] = node_index(i + dx, j + dy, l + dz, n);
        d.value[m] = w * per_volume;
      }
  return d;
}

struct StencilParams {
  int n;            // nodes per axis
  double lambda;    // D dt / h^2 for one (sub-)step
  double decay_dt;  // k dt for one (sub-)step
  bool reflecting;
  int k0;           // the first plane stored at c (0, or a decomposed grid's slab)
};

// Explicit FTCS update of node (i, j, k): reads `c`, the caller writes its own slot.
AXG_HDI double ftcs_node(const double* c, int i, int j, int k, const StencilParams& s) {
  const int n = s.n;
  const bool face = i == 0 || j == 0 || k == 0 || i == n - 1 || j == n - 1 || k == n - 1;
  if (face && !s.reflecting) return 0.0;
  auto at = [&](int a, int b, int d) {
    // Mirror ghost nodes for the reflecting boundary.
    if (a < 0) a = 1;
    if (a > n - 1) a = n - 2;
    if (b < 0) b = 1;
    if (b > n - 1) b = n - 2;
    if (d < 0) d = 1;
    if (d > n - 1) d = n - 2;
    return c[node_index(a, b, d - s.k0, n)];
  };
  const double here = c[node_index(i, j, k - s.k0, n)];
  const double sum = ((((at(i - 1, j, k) + at(i + 1, j, k)) + at(i, j - 1, k)) + at(i, j + 1, k)) + at(i, j, k - 1)) +
                     at(i, j, k + 1);
  return here + s.lambda * (sum - 6.0 * here) - s.decay_dt * here;
}

// Backward Euler along one line of n values c[first + m stride], m = 0..n-1:
//   (1 + 2 lambda) x_m - lambda (x_{m-1} + x_{m+1}) = c_m,
// with x = 0 at both ends (absorbing) or mirrored ghosts (reflecting), solved in place by
// the Thomas algorithm: every term it adds is >= 0. The forward and backward steps of one
// row are functions of their own, so that a batched sweep (many lines advanced row by
// row, for cache locality on the CPU) performs exactly the same operations per line as
// one GPU thread solving one line.
struct LodLine {
  int lo, hi;       // first and last unknown row
  double lambda;
  double diag;      // 1 + 2 lambda
  bool reflecting;
};

AXG_HDI LodLine lod_line(int n, double lambda, bool reflecting) {
  return {reflecting ? 0 : 1, reflecting ? n - 1 : n - 2, lambda, 1.0 + 2.0 * lambda, reflecting};
}

// Forward elimination of row m: from (cp, dp) of row m-1 (ignored when m == lo) and the
// right-hand side, the (cp, dp) of row m. Coefficient magnitudes: sub-diagonal a,
// super-diagonal b; a mirrored ghost doubles the coupling of a reflecting end row.
AXG_HDI void lod_forward(const LodLine& l, int m, double rhs, double cp_prev, double dp_prev, double* cp,
                         double* dp) {
  double a = m == l.lo ? 0.0 : l.lambda;
  double b = m == l.hi ? 0.0 : l.lambda;
  if (l.reflecting && m == l.lo && l.lo != l.hi) b = 2.0 * l.lambda;
  if (l.reflecting && m == l.hi && l.lo != l.hi) a = 2.0 * l.lambda;
  const double denom = m == l.lo ? l.diag : l.diag - a * cp_prev;
  *cp = b / denom;
  *dp = m == l.lo ? rhs / denom : (rhs + a * dp_prev) / denom;
}

// Back substitution of row m given the solution of row m+1.
AXG_HDI double lod_backward(double cp, double dp, double next) { return dp + cp * next; }

AXG_HDI void lod_line_solve(double* c, std::size_t first, std::size_t stride, int n, double lambda, bool reflecting,
                            double* cp, double* dp) {
  const LodLine l = lod_line(n, lambda, reflecting);
  if (!reflecting) {
    c[first] = 0.0;
    c[first + static_cast<std::size_t>(n - 1) * stride] = 0.0;
  }
  if (l.hi < l.lo) return;
  for (int m = l.lo; m <= l.hi; ++m)
    lod_forward(l, m, c[first + static_cast<std::size_t>(m) * stride], m == l.lo ? 0.0 : cp[m - 1],
                m == l.lo ? 0.0 : dp[m - 1], &cp[m], &dp[m]);
  double next = dp[l.hi];
  c[first + static_cast<std::size_t>(l.hi) * stride] = next;
  for (int m = l.hi - 1; m >= l.lo; --m) {
    next = lod_backward(cp[m], dp[m], next);
    c[first + static_cast<std::size_t>(m) * stride] = next;
  }
}

}  // namespace axg::core

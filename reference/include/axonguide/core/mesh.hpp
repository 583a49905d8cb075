#pragma once
// A uniform mesh of n^3 nodes, node (i, j, k) at origin + h (i, j, k), index (k n + j) n + i,
// and the one interpolation that every mesh-based estimate of C and grad C goes through:
// the grid field (stencil.hpp) and the particle field's estimate (estimate.hpp).
//
//   value: trilinear interpolation of the nodes of the cell containing x;
//   grad:  trilinear interpolation, with the same weights, of the nodal gradients, which
//          are centred differences (c[i+1] - c[i-1]) / 2h (one-sided at the mesh's faces).
//
// Both are exact for linear fields, and the gradient is exact for quadratic ones inside the
// mesh, so value and gradient have errors O(h^2) and the gradient is continuous across
// cells (the gradient of the trilinear interpolant itself is O(h) and jumps at faces).
// Points outside the mesh use the nearest cell.
#include <cmath>
#include <cstddef>

#include "hd.hpp"
#include "vec3.hpp"

namespace axg::core {

struct GridFieldView {
  Vec3 origin;      // LU, node (0,0,0)
  double h;         // LU, node spacing
  int n;            // nodes per axis, >= 2
  const double* c;  // values (concentration units) of planes k0.. (all n^3 from k0 = 0)
  int k0;           // the first plane (z index) stored at c: a slab of a decomposed grid
};

AXG_HDI std::size_t node_index(int i, int j, int k, int n) {
  return (static_cast<std::size_t>(k) * static_cast<std::size_t>(n) + static_cast<std::size_t>(j)) *
             static_cast<std::size_t>(n) +
         static_cast<std::size_t>(i);
}

// The cell of coordinate v along one axis (clamped to [0, n - 2]) and the fraction of the
// way across it (in [0, 1]; 0 or 1 outside the mesh).
AXG_HDI void mesh_locate(double v, double origin, double h, int n, int* cell, double* frac) {
  double t = (v - origin) / h;
  const double hi = static_cast<double>(n - 1);
  if (!(t > 0.0)) t = 0.0;
  if (t > hi) t = hi;
  int c = static_cast<int>(t);
  if (c > n - 2) c = n - 2;
  *cell = c;
  *frac = t - static_cast<double>(c);
}

struct MeshSample {
  double value;  // concentration units
  Vec3 grad;     // concentration units per LU
};

// d c / d axis at node (i, j, k), the axis given as a unit step (di, dj, dk): centred
// inside, one-sided on the faces.
AXG_HDI double nodal_derivative(const GridFieldView& g, int i, int j, int k, int di, int dj, int dk) {
  const int at = di ? i : (dj ? j : k);
  const int down = at > 0 ? 1 : 0, up = at < g.n - 1 ? 1 : 0;
  const double hi = g.c[node_index(i + up * di, j + up * dj, k + up * dk - g.k0, g.n)];
  const double lo = g.c[node_index(i - down * di, j - down * dj, k - down * dk - g.k0, g.n)];
  return (hi - lo) / (static_cast<double>(up + down) * g.h);
}

// x's cell: its lowest node (i, j, k) and the trilinear weights of its two nodes per axis.
struct MeshCell {
  int i, j, k;
  double wx[2], wy[2], wz[2];
};

AXG_HDI MeshCell mesh_cell(Vec3 x, const GridFieldView& g) {
  MeshCell m;
  double fx, fy, fz;
  mesh_locate(x.x, g.origin.x, g.h, g.n, &m.i, &fx);
  mesh_locate(x.y, g.origin.y, g.h, g.n, &m.j, &fy);
  mesh_locate(x.z, g.origin.z, g.h, g.n, &m.k, &fz);
  m.wx[0] = 1.0 - fx, m.wx[1] = fx;
  m.wy[0] = 1.0 - fy, m.wy[1] = fy;
  m.wz[0] = 1.0 - fz, m.wz[1] = fz;
  return m;
}

AXG_HDI MeshSample mesh_sample(Vec3 x, const GridFieldView& g) {
  const MeshCell m = mesh_cell(x, g);
  // Corners in (z, y, x) order; each weight is (wx wy) wz, the same for value and gradient.
  double value = 0.0;
  Vec3 grad{0.0, 0.0, 0.0};
  for (int c = 0; c < 2; ++c)
    for (int b = 0; b < 2; ++b)
      for (int a = 0; a < 2; ++a) {
        const double w = (m.wx[a] * m.wy[b]) * m.wz[c];
        value += w * g.c[node_index(m.i + a, m.j + b, m.k + c - g.k0, g.n)];
        grad += w * Vec3{nodal_derivative(g, m.i + a, m.j + b, m.k + c, 1, 0, 0),
                         nodal_derivative(g, m.i + a, m.j + b, m.k + c, 0, 1, 0),
                         nodal_derivative(g, m.i + a, m.j + b, m.k + c, 0, 0, 1)};
      }
  return {value, grad};
}

// The value alone: trilinear interpolation of the nodes of x's cell.
AXG_HDI double mesh_value(Vec3 x, const GridFieldView& g) {
  const MeshCell m = mesh_cell(x, g);
  double value = 0.0;
  for (int c = 0; c < 2; ++c)
    for (int b = 0; b < 2; ++b)
      for (int a = 0; a < 2; ++a)
        value += ((m.wx[a] * m.wy[b]) * m.wz[c]) * g.c[node_index(m.i + a, m.j + b, m.k + c - g.k0, g.n)];
  return value;
}

// The mean over a ball of radius r about x of a value and of the value times the offset, by
// a product rule exact for polynomials of degree 5: radii r t_i with weights w_i, the 3-point
// Gauss rule of the radial measure 3 t^2 dt on [0, 1] (exact to t^5), times the 14 directions
// of Lebedev's degree-5 rule on the sphere (the 6 axes, weight 1/15 each; the 8 diagonals
// (+-1, +-1, +-1)/sqrt 3, weight 3/40 each). Returns the mean and the effective gradient
// g = (5 / r^2) mean(C(x + y) y) (sensing.hpp: the count form's dipole is g V r / (5 m)).
// `value` is any callable of a point. 42 points in a fixed order: the same sums on every
// backend. (The constants live in the function: device code reads no host arrays.)
template <class Value>
AXG_HDI MeshSample ball_rule(Vec3 x, double r, const Value& value_at) {
  const double radius[3] = {0.2949977901115015, 0.6529962339616476, 0.9270059759268507};
  const double weight[3] = {0.08985210902574209, 0.4387388077795984, 0.47140908319465963};
  const double inv_sqrt3 = 0.57735026918962576;
  double value = 0.0;
  Vec3 first{0.0, 0.0, 0.0};
  for (int i = 0; i < 3; ++i) {
    const double rho = r * radius[i];
    const double axis = weight[i] / 15.0, diagonal = weight[i] * (3.0 / 40.0);
    for (int d = 0; d < 3; ++d)
      for (int s = -1; s <= 1; s += 2) {
        Vec3 y{0.0, 0.0, 0.0};
        (d == 0 ? y.x : d == 1 ? y.y : y.z) = static_cast<double>(s) * rho;
        const double c = value_at(x + y);
        value += axis * c;
        first += (axis * c) * y;
      }
    const double q = rho * inv_sqrt3;
    for (int sz = -1; sz <= 1; sz += 2)
      for (int sy = -1; sy <= 1; sy += 2)
        for (int sx = -1; sx <= 1; sx += 2) {
          const Vec3 y{static_cast<double>(sx) * q, static_cast<double>(sy) * q, static_cast<double>(sz) * q};
          const double c = value_at(x + y);
          value += diagonal * c;
          first += (diagonal * c) * y;
        }
  }
  return {value, (5.0 / (r * r)) * first};
}

struct MeshValue {
  const GridFieldView* g;
  AXG_HDI double operator()(Vec3 p) const { return mesh_value(p, *g); }
};

// The sensing ball over the mesh: ball_rule on the trilinear interpolant. For a linear field
// both the mean and the gradient are exact. Otherwise the interpolation's error is O(h^2), so
// refining the mesh converges to the rule on the exact field, whose own error is O((r/d)^6)
// at a distance d from a source (1e-3 of the gradient at d = 4r; ball_test).
AXG_HDI MeshSample mesh_ball_sample(Vec3 x, const GridFieldView& g, double r) { return ball_rule(x, r, MeshValue{&g}); }

}  // namespace axg::core

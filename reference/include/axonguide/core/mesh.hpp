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

AXG_HDI MeshSample mesh_sample(Vec3 x, const GridFieldView& g) {
  int i, j, k;
  double fx, fy, fz;
  mesh_locate(x.x, g.origin.x, g.h, g.n, &i, &fx);
  mesh_locate(x.y, g.origin.y, g.h, g.n, &j, &fy);
  mesh_locate(x.z, g.origin.z, g.h, g.n, &k, &fz);
  const double wx[2] = {1.0 - fx, fx}, wy[2] = {1.0 - fy, fy}, wz[2] = {1.0 - fz, fz};
  // Corners in (z, y, x) order; each weight is (wx wy) wz, the same for value and gradient.
  double value = 0.0;
  Vec3 grad{0.0, 0.0, 0.0};
  for (int c = 0; c < 2; ++c)
    for (int b = 0; b < 2; ++b)
      for (int a = 0; a < 2; ++a) {
        const double w = (wx[a] * wy[b]) * wz[c];
        value += w * g.c[node_index(i + a, j + b, k + c - g.k0, g.n)];
        grad += w * Vec3{nodal_derivative(g, i + a, j + b, k + c, 1, 0, 0),
                         nodal_derivative(g, i + a, j + b, k + c, 0, 1, 0),
                         nodal_derivative(g, i + a, j + b, k + c, 0, 0, 1)};
      }
  return {value, grad};
}

}  // namespace axg::core

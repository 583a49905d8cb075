#pragma once
// Contact between a growing tip and other somas (SPEC §3.2). A tip contacts neuron j when
// it comes within r = r_s + r_c of p_j. `swept` tests the whole segment of the step and
// takes its first entry into any contact sphere; `endpoint` tests the new tip only (the
// report's rule: a fast tip can tunnel through a soma). Ties: smallest segment parameter
// t, then lowest id, so the answer does not depend on the order candidates are visited.
#include <cstdint>

#include "cellgrid.hpp"
#include "hd.hpp"
#include "types.hpp"
#include "vec3.hpp"

namespace axg::core {

struct Contact {
  double t;              // segment parameter in [0, 1] of the first contact
  std::uint32_t target;  // kNoNeuron when there is none
};

// Smallest t in [0, 1] with |a + t s - c|^2 <= r2, if any. Detection uses the closest
// point of the segment, so a segment through the sphere is always caught; the entry
// parameter is the smaller root of the quadratic, clamped to [0, t_closest].
AXG_HDI bool segment_sphere_entry(Vec3 a, Vec3 s, Vec3 c, double r2, double* t_out) {
  const Vec3 d = a - c;
  const double cc = norm2(d) - r2;
  if (cc <= 0.0) {
    *t_out = 0.0;
    return true;
  }
  const double b = dot(d, s);
  if (b >= 0.0) return false;  // starts outside and moves away
  const double aa = norm2(s);
  double tc = -b / aa;
  if (tc > 1.0) tc = 1.0;
  if (norm2(d + tc * s) > r2) return false;
  const double disc = b * b - aa * cc;
  const double root = (-b - std::sqrt(disc > 0.0 ? disc : 0.0)) / aa;
  *t_out = root < 0.0 ? 0.0 : (root > tc ? tc : root);
  return true;
}

AXG_HDI bool endpoint_in_sphere(Vec3 b, Vec3 c, double r2) { return norm2(b - c) <= r2; }

AXG_HDI double min3(double a, double b) { return a < b ? a : b; }
AXG_HDI double max3(double a, double b) { return a > b ? a : b; }

// The first contact of the step a -> a + s by neuron `self` with any other soma in the
// grid, for contact radius r (r2 = r*r).
AXG_HDI Contact find_contact(std::uint32_t self, Vec3 a, Vec3 s, double r, double r2,
                             ContactRule rule, const CellGridView& g) {
  const Vec3 b = a + s;
  // The cells of the segment's box widened by r, and by a margin over rounding, so that a
  // soma in reach is visited whatever the grid's cells: the answer depends on the somas
  // only (a decomposed run's grids are not the one-process grid).
  const double rc = r * (1.0 + 1e-9);
  const int x0 = cell_coord(min3(a.x, b.x) - rc, g.origin.x, g.cell, g.nx);
  const int x1 = cell_coord(max3(a.x, b.x) + rc, g.origin.x, g.cell, g.nx);
  const int y0 = cell_coord(min3(a.y, b.y) - rc, g.origin.y, g.cell, g.ny);
  const int y1 = cell_coord(max3(a.y, b.y) + rc, g.origin.y, g.cell, g.ny);
  const int z0 = cell_coord(min3(a.z, b.z) - rc, g.origin.z, g.cell, g.nz);
  const int z1 = cell_coord(max3(a.z, b.z) + rc, g.origin.z, g.cell, g.nz);
  Contact best{2.0, kNoNeuron};
  // A soma farther than |s| + r from the start cannot be reached: most candidates are
  // rejected with one distance. (Exact: if |a - c| > |s| + r then every point of the
  // segment is farther than r; the margin covers rounding.)
  const double reach = norm(s) + r;
  const double reach2 = reach * reach * (1.0 + 1e-12);
  for (int z = z0; z <= z1; ++z) {
    for (int y = y0; y <= y1; ++y) {
      const std::uint32_t row = cell_index(x0, y, z, g.nx, g.ny, g.nz);
      const std::uint32_t begin = g.cell_start[row];
      const std::uint32_t end = g.cell_start[row + static_cast<std::uint32_t>(x1 - x0) + 1];
      for (std::uint32_t k = begin; k < end; ++k) {
        const std::uint32_t j = g.ids[k];
        if (j == self || norm2(g.pos[k] - a) > reach2) continue;
        double t;
        bool hit;
        if (rule == ContactRule::kSwept) {
          hit = segment_sphere_entry(a, s, g.pos[k], r2, &t);
        } else {
          hit = endpoint_in_sphere(b, g.pos[k], r2);
          t = 1.0;
        }
        if (hit && (t < best.t || (t == best.t && j < best.target))) best = Contact{t, j};
      }
    }
  }
  return best;
}

}  // namespace axg::core

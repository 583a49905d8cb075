#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <vector>

#include "axonguide/engine/cell_grid.hpp"
#include "axonguide/core/contact.hpp"
#include "axonguide/core/growth.hpp"

namespace axg::core {
namespace {

rc::Gen<double> coord(double lo, double hi) {
  return rc::gen::map(rc::gen::inRange(0, 1 << 20),
                      [lo, hi](int k) { return lo + (hi - lo) * (k / double(1 << 20)); });
}

rc::Gen<Vec3> point(double lo, double hi) {
  return rc::gen::construct<Vec3>(coord(lo, hi), coord(lo, hi), coord(lo, hi));
}

// A segment through a point strictly inside the sphere is always caught, whatever the
// segment's length and direction, and the entry parameter reaches the sphere.
RC_GTEST_PROP(contact, SweptCatchesEverySegmentThroughTheSphere, ()) {
  const Vec3 c = *point(-10, 10);
  const double r = *coord(0.01, 2.0);
  const Vec3 dir = *point(-1, 1);
  RC_PRE(norm(dir) > 1e-3);
  const Vec3 inside = c + (*coord(0, 0.999) * r) * normalized(dir);
  const Vec3 s = *point(-5, 5);
  RC_PRE(norm(s) > 1e-6);
  const double t0 = *coord(0, 1);
  const Vec3 a = inside - t0 * s;  // the segment a -> a + s passes through `inside` at t0
  double t;
  RC_ASSERT(segment_sphere_entry(a, s, c, r * r, &t));
  RC_ASSERT(t >= 0.0 && t <= t0 + 1e-12);
  RC_ASSERT(norm(a + t * s - c) <= r * (1 + 1e-9));
}

RC_GTEST_PROP(contact, SweptMissesSegmentsThatStayOutside, ()) {
  const Vec3 c = *point(-10, 10);
  const double r = *coord(0.01, 2.0);
  const Vec3 a = *point(-10, 10);
  const Vec3 s = *point(-3, 3);
  // Distance from c to the segment, by dense sampling (an upper bound of the minimum).
  double dmin = 1e300;
  for (int k = 0; k <= 2000; ++k) dmin = std::fmin(dmin, norm(a + (k / 2000.0) * s - c));
  RC_PRE(dmin > r * 1.01);
  double t;
  RC_ASSERT(!segment_sphere_entry(a, s, c, r * r, &t));
}

RC_GTEST_PROP(contact, EndpointIsTheReportsRule, ()) {
  const Vec3 c = *point(-5, 5);
  const double r = *coord(0.05, 1.0);
  const Vec3 b = *point(-5, 5);
  RC_ASSERT(endpoint_in_sphere(b, c, r * r) == (norm2(b - c) <= r * r));
}

TEST(contact, EndpointTunnelsWhereSweptDoesNot) {
  // A long step straight through a soma: the endpoint rule misses it.
  const Vec3 c{1, 0, 0}, a{0, 0, 0}, s{2, 0, 0};
  double t;
  EXPECT_TRUE(segment_sphere_entry(a, s, c, 0.3 * 0.3, &t));
  EXPECT_DOUBLE_EQ(t, 0.35);
  EXPECT_FALSE(endpoint_in_sphere(a + s, c, 0.3 * 0.3));
}

// find_contact over a grid gives the same answer as a brute-force scan with the tie rule
// (smallest t, then lowest id), for both rules.
RC_GTEST_PROP(contact, GridSearchEqualsBruteForce, ()) {
  const int n = *rc::gen::inRange(1, 300);
  std::vector<Vec3> somas;
  for (int i = 0; i < n; ++i) somas.push_back(*point(-4, 4));
  const double r = *coord(0.05, 0.8);
  const GridGeometry geo = cube_geometry(4.0 + r, *coord(0.1, 2.0), n);
  const CellGrid grid = build_cell_grid(geo, somas);
  const auto self = static_cast<std::uint32_t>(*rc::gen::inRange(0, n));
  const Vec3 a = *point(-6, 6);
  const Vec3 s = *point(-1.5, 1.5);
  for (ContactRule rule : {ContactRule::kSwept, ContactRule::kEndpoint}) {
    Contact best{2.0, kNoNeuron};
    for (std::uint32_t j = 0; j < static_cast<std::uint32_t>(n); ++j) {
      if (j == self) continue;
      double t = 1.0;
      const bool hit = rule == ContactRule::kSwept ? segment_sphere_entry(a, s, somas[j], r * r, &t)
                                                   : endpoint_in_sphere(a + s, somas[j], r * r);
      if (hit && (t < best.t || (t == best.t && j < best.target))) best = {t, j};
    }
    const Contact got = find_contact(self, a, s, r, r * r, rule, grid.view());
    RC_ASSERT(got.target == best.target);
    if (best.target != kNoNeuron) RC_ASSERT(got.t == best.t);
  }
}

// The cells' index (pencils of kCellTile x kCellTile rows) numbers every cell of any grid
// once, within [0, nx ny nz), and keeps each row's cells consecutive along x, which the
// contact search's runs [x0, x1] rely on; grids smaller and larger than a tile, with partial
// tiles along y and z.
RC_GTEST_PROP(cellgrid, CellIndexIsABijectionWithConsecutiveRows, ()) {
  const int nx = *rc::gen::inRange(1, 20), ny = *rc::gen::inRange(1, 30), nz = *rc::gen::inRange(1, 30);
  const std::size_t cells = static_cast<std::size_t>(nx) * ny * nz;
  std::vector<int> seen(cells, 0);
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y) {
      const std::uint32_t row = cell_index(0, y, z, nx, ny, nz);
      for (int x = 0; x < nx; ++x) {
        const std::uint32_t c = cell_index(x, y, z, nx, ny, nz);
        RC_ASSERT(c == row + static_cast<std::uint32_t>(x));
        RC_ASSERT(c < cells);
        ++seen[c];
      }
    }
  for (int v : seen) RC_ASSERT(v == 1);
}

TEST(growth, StatusesOfOneStep) {
  const std::vector<Vec3> somas{{0, 0, 0}, {1, 0, 0}};
  const CellGrid grid = build_cell_grid(cube_geometry(3, 0.5, 2), somas);
  GrowthParams g{0.35, 0.3, 0.09, 2.0, false, ContactRule::kSwept};
  // Toward neuron 1 from neuron 0's surface: no contact on the first step (0.25 -> 0.6),
  // contact on the second where the segment enters r = 0.3 around x = 1.
  AxonStep s = grow_axon(0, {0.25, 0, 0}, {1, 0, 0}, g.step_length, g, grid.view());
  EXPECT_EQ(s.status, AxonStatus::kGrowing);
  s = grow_axon(0, s.tip, {1, 0, 0}, g.step_length, g, grid.view());
  EXPECT_EQ(s.status, AxonStatus::kConnected);
  EXPECT_EQ(s.target, 1u);
  EXPECT_NEAR(s.tip.x, 0.7, 1e-12);
  EXPECT_NEAR(s.advanced, 0.1, 1e-12);
  // Away from it: leaves a ball of radius 2 after enough steps.
  s = grow_axon(0, {-1.9, 0, 0}, {-1, 0, 0}, g.step_length, g, grid.view());
  EXPECT_EQ(s.status, AxonStatus::kExited);
  s = grow_axon(0, {-1.0, 0, 0}, {-1, 0, 0}, g.step_length, g, grid.view());
  EXPECT_EQ(s.status, AxonStatus::kGrowing);
  EXPECT_DOUBLE_EQ(s.advanced, 0.35);
  // Box bounds: a corner inside the cube is not outside.
  g.bounds_box = true;
  s = grow_axon(0, {1.5, 1.5, 1.5}, {0, 0, 1}, g.step_length, g, grid.view());
  EXPECT_EQ(s.status, AxonStatus::kGrowing);
}

}  // namespace
}  // namespace axg::core

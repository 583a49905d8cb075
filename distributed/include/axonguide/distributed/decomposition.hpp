#pragma once
// Space cut into blocks, one per rank (docs/scaling.md §2.1). The domain is the cube
// [-D, D]^3 around the somas (the region or its populations, plus a soma radius); it is
// cut into P_x x P_y x P_z equal blocks, the most cubic factorisation of the rank count. A point belongs to the block its coordinates fall in,
// clamped into the grid, so every point has exactly one owner, inside the cube or not.
// Every rank computes the same decomposition from (scene, rank count): no message.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "axonguide/core/vec3.hpp"
#include "axonguide/scene/scene.hpp"

namespace axg::distributed {

struct Decomposition {
  int ranks = 1;
  std::array<int, 3> blocks{1, 1, 1};  // P_x, P_y, P_z
  double half = 1.0;                   // D, LU
  std::array<double, 3> edge{2, 2, 2}; // block edges, LU
  // Somas a rank keeps beyond its block: those within `halo` of it (LU). It covers one
  // step's contact search (the longest step plus the contact radius r_s + r_c) and the
  // placement's overlap test (2 r_s), with a margin for rounding.
  double halo = 0.0;
  double max_step = 0.0;  // LU: the longest step an axon can take
  // Particles a rank keeps beyond its block (the particle field's gathers: the sensing
  // radius, the collision diameter), LU; 0 when no gather reads particles. Within `halo`.
  double particle_halo = 0.0;
  // A grid scene is cut in slabs along z (blocks 1 x 1 x K) over the grid's cube, so that
  // the x and y sweeps of the implicit solve are local; its ghost planes are three nodes wide.
  bool slabs = false;

  // Inline: the particle field asks these of every particle every step.
  std::array<int, 3> block_of(core::Vec3 p) const {
    const double c[3] = {p.x, p.y, p.z};
    std::array<int, 3> b{};
    for (int a = 0; a < 3; ++a) {
      if (blocks[a] == 1) continue;  // uncut: every value (NaN too) clamps to block 0
      const double t = (c[a] + half) / edge[a];
      b[a] = !(t >= 0.0) ? 0 : t >= blocks[a] ? blocks[a] - 1 : static_cast<int>(t);
    }
    return b;
  }
  int rank_of(const std::array<int, 3>& b) const { return (b[2] * blocks[1] + b[1]) * blocks[0] + b[0]; }
  int owner(core::Vec3 p) const { return rank_of(block_of(p)); }
  std::array<int, 3> block(int rank) const {
    return {rank % blocks[0], (rank / blocks[0]) % blocks[1], rank / (blocks[0] * blocks[1])};
  }
  // A block's faces, computed once, for the tests a rank makes of every particle each step.
  struct Bounds {
    std::array<double, 3> lo, hi;
    std::array<bool, 3> lower_shared, upper_shared;  // a face shared with another block
    // Whether p lies within `width` of the block (the outer blocks reach to infinity, as
    // their points are clamped into them).
    bool near(core::Vec3 p, double width) const {
      const double c[3] = {p.x, p.y, p.z};
      double d2 = 0.0;
      for (int a = 0; a < 3; ++a) {
        double d = 0.0;
        if (lower_shared[a] && c[a] < lo[a]) d = lo[a] - c[a];
        if (upper_shared[a] && c[a] > hi[a]) d = c[a] - hi[a];
        d2 += d * d;
      }
      return d2 <= width * width;
    }
    // Whether p, a point of the block, lies within `width` of a face it shares with another
    // block (so that it may be within `width` of that block).
    bool near_boundary(core::Vec3 p, double width) const {
      const double c[3] = {p.x, p.y, p.z};
      for (int a = 0; a < 3; ++a) {
        if (lower_shared[a] && c[a] - lo[a] <= width) return true;
        if (upper_shared[a] && hi[a] - c[a] <= width) return true;
      }
      return false;
    }
    // Whether p lies inside the block, farther than `margin` from every face it shares: then
    // the block owns p (block_of's rounding is far below any margin the decomposition uses,
    // which inner_margin() checks) and near_boundary(p, w) is false for every w <= margin.
    bool inner(core::Vec3 p, double margin) const {
      const double c[3] = {p.x, p.y, p.z};
      for (int a = 0; a < 3; ++a) {
        if (lower_shared[a] ? !(c[a] - lo[a] > margin) : false) return false;
        if (upper_shared[a] ? !(hi[a] - c[a] > margin) : false) return false;
      }
      return true;
    }
  };
  Bounds bounds(int rank) const {
    const std::array<int, 3> b = block(rank);
    Bounds out;
    for (int a = 0; a < 3; ++a) {
      out.lo[a] = -half + b[a] * edge[a];
      out.hi[a] = out.lo[a] + edge[a];
      out.lower_shared[a] = b[a] > 0;
      out.upper_shared[a] = b[a] < blocks[a] - 1;
    }
    return out;
  }
  // A margin a million times block_of's rounding (a few ulps of the domain's size): a point
  // Bounds::inner puts this far inside a block is that block's.
  double rounding_margin() const { return 1e-9 * (half + 1.0); }
  // The margin for Bounds::inner that also rules out the halo: the halo, when it exceeds
  // the rounding margin; 0 (no fast path) otherwise.
  double inner_margin() const { return halo > rounding_margin() ? halo : 0.0; }
  bool near(int rank, core::Vec3 p, double width) const { return bounds(rank).near(p, width); }
  bool near_boundary(int rank, core::Vec3 p, double width) const { return bounds(rank).near_boundary(p, width); }
  // The ranks of the blocks adjacent to rank's (faces, edges and corners), ascending.
  std::vector<int> neighbours(int rank) const;
  // "2 x 2 x 1 blocks of 5.4 x 5.4 x 10.8 LU, halo 0.65 LU"
  std::string describe() const;
};

// The decomposition of the scene over `ranks` ranks. Throws InputError (exit 2) when the
// ranks cannot all be given a block at least a halo wide (a halo wider than a block would
// need a second ring of neighbours; a tip would cross more than one block in a step), and
// RunError (exit 3) for a scene the decomposed engine does not take (signalling growth).
// The halo covers one step's contact search, the placement's overlap test, the particle
// field's gathers and the grid's ghost planes.
Decomposition decompose(const Scene& scene, int ranks);

}  // namespace axg::distributed

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
#include "axonguide/scene.hpp"

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

  std::array<int, 3> block_of(core::Vec3 p) const;
  int rank_of(const std::array<int, 3>& b) const { return (b[2] * blocks[1] + b[1]) * blocks[0] + b[0]; }
  int owner(core::Vec3 p) const { return rank_of(block_of(p)); }
  std::array<int, 3> block(int rank) const;
  // Whether p lies within `width` of rank's block (the outer blocks reach to infinity, as
  // their points are clamped into them).
  bool near(int rank, core::Vec3 p, double width) const;
  // Whether p, a point of rank's block, lies within `width` of a face that rank's block
  // shares with another block (so that it may be within `width` of that block).
  bool near_boundary(int rank, core::Vec3 p, double width) const;
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

#pragma once
// Placement decomposed over ranks (docs/scaling.md §2.3): the same somas, bit for bit, as
// place_neurons (random sequential addition in id order, methods §2.1) for any rank count.
//
// Ids are taken in blocks, in order, as in the one-process blocked pass. For a block:
//  1. Search (rounds): each soma's attempts are drawn in order, and the rank whose block
//     holds an attempt's position tests it against the earlier blocks' somas, which that
//     rank holds within the halo of its block; it goes on drawing while the next attempt
//     stays in its block, and hands the search to the position's owner otherwise. Each
//     round ends with an all-gather of the searches' states (24 bytes each). A rejection
//     there is one the sequential pass makes too, since earlier blocks are final.
//  2. Every rank then knows every soma's first clear attempt. Where two of them, in the
//     same block, overlap, the higher id may be rejected by the lower: those somas search
//     on for their second clear attempt (more rounds).
//  3. Scan (every rank, the same, no message): in id order, a soma takes its first clear
//     attempt that no lower id of the block overlaps. A soma that runs out of known clear
//     attempts searches on from there, testing the earlier blocks (its owner) and the
//     block's lower ids (every rank knows them) together: rounds for that soma alone.
// Each rank keeps the somas within the halo of its block, and rank 0 every soma (it writes
// the outputs). Every rank draws each soma's first attempt, to learn who owns it: a cheap,
// replicated O(N) scan; the overlap tests, the costly part, are split by space.
#include <cstdint>
#include <vector>

#include "axonguide/core/vec3.hpp"
#include "axonguide/distributed/comm.hpp"
#include "axonguide/distributed/decomposition.hpp"
#include "axonguide/scene.hpp"

namespace axg::distributed {

struct RankSomas {
  std::vector<std::uint32_t> id;  // ascending
  std::vector<core::Vec3> pos;    // LU
  std::vector<bool> owned;        // in this rank's block (else within its halo)
};

struct DecomposedPlacement {
  RankSomas somas;               // this rank's block and halo
  std::vector<core::Vec3> all;   // rank 0: every soma by id; empty on the other ranks
  std::uint64_t redraws = 0;     // attempts beyond the first, summed over all neurons
  std::uint64_t rounds = 0;      // all-gathers the searches took
  std::uint64_t second_searches = 0, scan_searches = 0;  // somas that searched in steps 2 and 3
};

inline constexpr std::size_t kPlacementIdBlock = 16384;

// Collective over comm. Throws what place_neurons throws, on every rank alike (the checks
// and the failing neuron are decided from data every rank holds).
DecomposedPlacement place_decomposed(const Scene& scene, const Decomposition& d, Comm& comm,
                                     std::size_t id_block = kPlacementIdBlock);

}  // namespace axg::distributed

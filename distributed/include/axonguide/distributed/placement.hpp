#pragma once
// Placement decomposed over ranks (docs/scaling.md §2.3): the same somas, bit for bit, as
// place_neurons (random sequential addition in id order, methods §2.1) for any rank count.
//
// Ids are taken in blocks, in order, as in the one-process blocked pass. For a block:
//  1. Search (rounds): a window of each soma's next attempts is drawn by every rank (a
//     cheap draw), and the rank whose block holds an attempt's position tests it against
//     the earlier blocks' somas, which it holds within the halo of its block. An
//     all-gather of the clear attempts found (32 bytes each) ends the round; a window that
//     found none doubles for the next. A rejection there is one the sequential pass makes
//     too, since earlier blocks are final.
//  2. Scan (every rank, the same, no message): in id order, a soma takes its first known
//     clear attempt that no lower id of the block overlaps. A soma whose known ones are all
//     overlapped is pending, and so is everything after it; the pending somas search on,
//     together, for more clear attempts each (twice as many each time a soma is pending
//     again), and the scan runs again. When a scan
//     leaves none pending, every soma holds random sequential addition's position.
// Each rank keeps the somas within the halo of its block, and rank 0 every soma (it writes
// the outputs). Every rank draws the windows and runs the scans, cheap replicated O(N) work
// (about 2 draws per soma at the report's density); the overlap tests against everything
// placed, the costly part, are split by space.
#include <cstdint>
#include <vector>

#include "axonguide/core/vec3.hpp"
#include "axonguide/distributed/comm.hpp"
#include "axonguide/distributed/decomposition.hpp"
#include "axonguide/scene/scene.hpp"

namespace axg::distributed {

struct RankSomas {
  std::vector<std::uint32_t> id;  // ascending
  std::vector<core::Vec3> pos;    // LU
  std::vector<bool> owned;        // in this rank's block (else within its halo)
};

// How the placement went on this rank (the run facts).
struct PlacementStats {
  std::uint64_t rounds = 0;          // all-gathers the searches took
  std::uint64_t scan_passes = 0;     // scans of id blocks
  std::uint64_t extra_searches = 0;  // searches for pending somas
  // Wall time (s) in the searches' windows (draws and this rank's overlap tests), in their
  // all-gathers (waiting included), and in the replicated work (applying the rounds, the
  // scans, keeping the block's somas).
  double window_seconds = 0, gather_seconds = 0, replicated_seconds = 0;
};

struct DecomposedPlacement {
  RankSomas somas;               // this rank's block and halo
  std::vector<core::Vec3> all;   // rank 0: every soma by id; empty on the other ranks
  std::uint64_t redraws = 0;     // attempts beyond the first, summed over all neurons
  PlacementStats stats;
};

// The id block for a scene: about one overlap in ten at a block's end, within [256, 16384].
// It changes the rounds and the replicated work, never the result.
std::size_t placement_id_block(const Scene& scene);

// Collective over comm. Throws what place_neurons throws, on every rank alike (the checks
// and the failing neuron are decided from data every rank holds).
DecomposedPlacement place_decomposed(const Scene& scene, const Decomposition& d, Comm& comm,
                                     std::size_t id_block = 0);  // 0: placement_id_block

}  // namespace axg::distributed

#pragma once
// The cue fields of a run decomposed over ranks (docs/scaling.md §2.4). Each is a CueField
// whose advance() is collective: every rank calls it for the same steps.
//  - particles: a rank owns the particles in its block; the emission of a source is made by
//    the ranks whose blocks lie within the halo of it (shared by id), with the ids one
//    process gives it; particles that leave the block
//    migrate after every move (and after the collisions), and every rank keeps a halo of
//    the particles within the gather radius (the sensing radius r, twice the particle
//    radius for collisions) of its block, so that a growth cone's gather and a particle's
//    collision push add the same particles, in the same (bucket, id) order, as one
//    process. The estimate's fixed-point deposits are summed over the ranks (integer sums,
//    exact in any order) and every rank folds the whole estimate.
//  - grid: a rank owns the slab of grid planes in its block (the decomposition is in slabs
//    along z for a grid scene), with three ghost planes each side: one for the explicit
//    stencil, two for the sensing interpolation's centred differences, one more for a tip
//    within rounding of a slab face. The implicit LOD
//    solve's x and y sweeps are local; the z sweep is the serial Thomas algorithm
//    pipelined across the ranks: its forward elimination passes each line's (c', d') up,
//    its back substitution passes each line's solution down, in batches of planes, so
//    every rank works on one batch while its neighbours work on others.
// Every value is the one-process value, bit for bit; checkpoints hold the one-process
// state (gathered to rank 0 in id or node order) and load on any rank count.
#include <cstdint>
#include <memory>
#include <vector>

#include "axonguide/core/cues.hpp"
#include "axonguide/distributed/comm.hpp"
#include "axonguide/distributed/decomposition.hpp"
#include "axonguide/fields/fields.hpp"

namespace axg::distributed {

// This rank's field counts, summed over its steps (the run facts).
struct FieldReport {
  std::uint64_t migrated = 0;        // particles sent to another block
  std::uint64_t far_migrated = 0;    // of those, sent by the all-gather (a jump past the neighbours)
  std::uint64_t halo_particles = 0;  // particles received into the halo
  std::uint64_t owned_particles = 0; // particles owned after each advance
  std::uint64_t ghost_values = 0;    // grid values received into ghost planes
  std::uint64_t pipeline_stages = 0; // exchanges of the pipelined Thomas sweeps
  Traffic halo;                      // the halo and ghost exchanges' share of the traffic
};

// The rank's field: the decomposed particle or grid field, or the one-process exact field
// (analytic, imposed), or null for direct guidance. Throws what make_reference_field throws.
std::unique_ptr<CueField> make_decomposed_field(const Scene& scene, const std::vector<core::CueParams>& cues,
                                                const Decomposition& d, Comm& comm, FieldReport& report);

}  // namespace axg::distributed

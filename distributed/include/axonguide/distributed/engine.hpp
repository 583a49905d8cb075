#pragma once
// The engine of a run decomposed over ranks (docs/scaling.md §2.2). A rank steps the axons
// whose tips lie in its block, with the reference engine's loop bodies (AxonStages), and
// its soma grid holds its block's somas and those within the halo: every soma a step's
// contact search can reach. After a step an axon whose tip left the block moves to the
// owner of its new position, a neighbouring block (a step is shorter than a block's edge);
// the counts are integer sums over the ranks. Each axon's step is the one-process step,
// bit for bit: a pure function of its state, the somas within reach and (seed, id, step).
// Rank 0 gathers what the outputs need (tips for paths, the final state, checkpoints).
#include <memory>

#include "axonguide/distributed/comm.hpp"
#include "axonguide/distributed/decomposition.hpp"
#include "axonguide/distributed/fields.hpp"
#include "axonguide/distributed/placement.hpp"
#include "axonguide/engine/engine.hpp"

namespace axg::distributed {

// This rank's counts for the run facts (DecomposedRun::facts sums them over the ranks).
struct RankReport {
  std::uint64_t owned_somas = 0, halo_somas = 0;
  PlacementStats placing;
  Traffic placement, steps, gathers;
  std::uint64_t steps_run = 0;
  std::uint64_t migrated = 0;  // axons sent to a neighbouring block
  FieldReport field;           // the particle or grid field's migration, halo and pipeline
};

// Collective. `somas`: this rank's block and halo. `report` outlives the engine.
std::unique_ptr<Engine> make_decomposed_engine(const Scene& scene, const Decomposition& d, Comm& comm,
                                               RankSomas somas, RankReport& report);

// This rank's share of a whole placement (a resumed run's, read from its checkpoint).
RankSomas rank_somas(const std::vector<core::Vec3>& all, const Decomposition& d, int rank);

}  // namespace axg::distributed

#pragma once
// One network over the ranks of a communicator (docs/scaling.md §2): run_scene's hooks for
// the decomposed placement, the decomposed engine and the agreement on checkpoints and
// stops. Every rank calls run_scene with them; rank 0's result is the one-process result,
// byte for byte, and the other ranks' results hold no neurons.
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "axonguide/distributed/comm.hpp"
#include "axonguide/distributed/decomposition.hpp"
#include "axonguide/distributed/engine.hpp"
#include "axonguide/distributed/on_every_rank.hpp"
#include "axonguide/engine/run.hpp"

namespace axg::distributed {

class DecomposedRun {
 public:
  // Decomposes the scene over comm's ranks (no message). Throws what decompose() throws.
  DecomposedRun(const Scene& scene, Comm& comm);

  // Sets options.place, make_engine and agree. The object must outlive the run.
  void attach(RunOptions& options);

  const Decomposition& decomposition() const { return d_; }
  Comm& comm() { return comm_; }

  // Collective, after the run: the run facts for rank 0's manifest (blocks, load, placement
  // rounds, bytes and messages per step, summed over the ranks).
  nlohmann::json facts();

 private:
  Comm& comm_;
  Decomposition d_;
  std::optional<RankSomas> placed_;
  RankReport report_;
};

}  // namespace axg::distributed

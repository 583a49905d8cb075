#pragma once
// K ranks as K threads of this process (tests, and builds without MPI): the same
// collectives as MPI, through shared memory and a barrier.
#include <functional>

#include "axonguide/distributed/comm.hpp"

namespace axg::distributed {

// Runs fn(comm) once per rank, rank r on its own thread with `threads` TBB threads (its
// own arena), and returns when all have. When a rank throws, the ranks waiting in a
// collective are released (they throw too) and the exception of the lowest rank that
// threw first-hand is rethrown.
void run_local_group(int ranks, int threads, const std::function<void(Comm&)>& fn);

}  // namespace axg::distributed

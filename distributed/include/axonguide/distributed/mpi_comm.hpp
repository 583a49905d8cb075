#pragma once
// The decomposed run's messages over MPI_COMM_WORLD (Open MPI): all-gathers and reductions
// as MPI collectives, the neighbour exchange as MPI_Neighbor_alltoall(v) over a distributed
// graph of the adjacent blocks, and the gather to rank 0 as point-to-point messages of at
// most 1 GiB (so a result over 2^31 bytes still arrives). Every MPI error becomes a
// RunError naming the call. Built only with MPI (AXG_HAVE_MPI).
#include <memory>

#include "axonguide/distributed/comm.hpp"

namespace axg::distributed {

std::unique_ptr<Comm> make_mpi_comm();

}  // namespace axg::distributed

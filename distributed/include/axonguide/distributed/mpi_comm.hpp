#pragma once
// The decomposed run's messages over MPI_COMM_WORLD (Open MPI): all-gathers and reductions
// as MPI collectives, the neighbour exchange as one message to and one from each adjacent
// block (MPI_Isend, and MPI_Mprobe/MPI_Mrecv in peer order, so a message carries its own
// size), and the gather to rank 0 as point-to-point messages of at
// most 1 GiB (so a result over 2^31 bytes still arrives). Every MPI error becomes a
// RunError naming the call. Defined only in builds with MPI (AXG_HAVE_MPI).
#include <memory>
#include <string>

#include "axonguide/distributed/comm.hpp"

namespace axg::distributed {

// The MPI library this build runs on, as it names itself ("Open MPI v4.1.4").
std::string mpi_library();

// A communicator over MPI_COMM_WORLD (a duplicate, with errors returned, not fatal).
std::unique_ptr<Comm> make_mpi_comm();

// MPI_Init and MPI_Finalize around a command, on every rank. An MPI_Init that fails and
// returns ends the process with exit 3 and a message naming the library; Open MPI 4.1 ends
// the process itself from inside MPI_Init, through PMIx_Abort, which the command defines
// so that the job exits 3 with that message too (mpi_comm.cpp). When a rank died, the
// destructor does not call MPI_Finalize (Open MPI 4.1 would wait for the dead rank
// forever): it ends the process with exit_code.
// When Open MPI's launcher put every rank on this node and the user chose no messaging
// layer (no --mca pml, no OMPI_MCA_pml), the session asks for Open MPI's shared-memory
// path (pml ob1 over the vader transport) before MPI_Init: the default, UCX, probes the
// network first, which cost 0.22 s of every run's start on the 2-core VM and carries
// nothing faster between ranks of one node. Every rank sees the same launcher variables,
// so every rank makes the same choice. `pml` says what was chosen (the run facts).
#ifdef AXG_HAVE_MPI
struct MpiSession {
  MpiSession();
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  bool rank_died = false;
  int exit_code = 0;
  std::string pml;  // "ob1 (every rank on one node)", "<layer> (OMPI_MCA_pml or --mca pml)", or "the library's choice"
};
#else
struct MpiSession {  // a build without MPI: nothing to start or end
  bool rank_died = false;
  int exit_code = 0;
  std::string pml;
};
#endif

// Ends every rank of the job (MPI_Abort) with `code`: for an error one rank met alone, in
// the middle of collective work the others would wait in forever.
[[noreturn]] void abort_job(int code);

}  // namespace axg::distributed

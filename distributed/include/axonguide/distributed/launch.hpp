#pragma once
// How this process was started: alone, or as one of K ranks by mpirun (Open MPI's, or any
// launcher that sets PMI/PMIx variables). Read from the environment, so that a build
// without MPI can still tell that it was started under mpirun and say what it does.
namespace axg::distributed {

struct Launch {
  int rank = 0;
  int size = 1;        // ranks in the job
  int local_size = 1;  // ranks on this node
  bool launched = false;  // started by a launcher (mpirun -np 1 included)
  bool under_mpirun() const { return size > 1; }
};

Launch detect_launch();

// True when this build can run work over ranks (MPI was found at build time).
bool have_mpi();

// Sets TCP_NODELAY on every TCP socket of this process whose peer is on the loopback
// (127.0.0.0/8, ::1, or ::ffff:127.x); returns how many it set. MpiSession calls it before
// MPI_Finalize: Open MPI 4.1's PMIx client talks to the node's PMIx server (mpirun or the
// node's daemon) over such a socket, opened without TCP_NODELAY, and MPI_Finalize sends
// the server small messages back to back, so that Nagle's algorithm holds each behind the
// acknowledgement of the one before, which the server delays (40 ms on Linux): 44 ms of
// every rank's MPI_Finalize, 3 ms with the option (docs/scaling.md §4.2). The option only
// changes when segments leave, never what they carry.
int no_delay_on_loopback_sockets();

}  // namespace axg::distributed

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

}  // namespace axg::distributed

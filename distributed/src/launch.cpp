#include "axonguide/distributed/launch.hpp"
#include "axonguide/distributed/mpi_comm.hpp"

#include <cstdio>
#include <cstdlib>
#include <initializer_list>

namespace axg::distributed {

namespace {
int env_int(std::initializer_list<const char*> names, int fallback) {
  for (const char* n : names)
    if (const char* v = std::getenv(n); v && *v) return std::atoi(v);
  return fallback;
}
}  // namespace

Launch detect_launch() {
  Launch l;
  l.size = env_int({"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}, 1);
  l.rank = env_int({"OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK"}, 0);
  l.local_size = env_int({"OMPI_COMM_WORLD_LOCAL_SIZE", "MPI_LOCALNRANKS"}, 1);
  for (const char* n : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (const char* v = std::getenv(n); v && *v) l.launched = true;
  if (l.size < 1) l.size = 1;
  if (l.local_size < 1) l.local_size = 1;
  return l;
}

#ifndef AXG_HAVE_MPI
// A build without MPI has no job to end but this process.
void abort_job(int code) {
  std::fflush(stdout);
  std::fflush(stderr);
  std::_Exit(code);
}
#endif

bool have_mpi() {
#ifdef AXG_HAVE_MPI
  return true;
#else
  return false;
#endif
}

}  // namespace axg::distributed

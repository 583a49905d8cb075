#include "axonguide/support/fault.hpp"

#include <signal.h>

#include <cstdlib>

namespace axg {

void fault_point(std::string_view name) {
  static const char* const at = std::getenv("AXG_FAULT_KILL_AT");
  if (at == nullptr || name != at) return;
  // AXG_FAULT_RANK: only that rank of an MPI job (Open MPI's or PMIx's rank variable).
  static const char* const only = std::getenv("AXG_FAULT_RANK");
  if (only != nullptr && *only != '\0') {
    const char* rank = std::getenv("OMPI_COMM_WORLD_RANK");
    if (rank == nullptr) rank = std::getenv("PMIX_RANK");
    if (rank == nullptr || std::string_view(rank) != only) return;
  }
  static const char* const sig = std::getenv("AXG_FAULT_SIGNAL");
  const std::string_view which = sig ? sig : "KILL";
  ::raise(which == "INT" ? SIGINT : which == "TERM" ? SIGTERM : which == "STOP" ? SIGSTOP : SIGKILL);
}

}  // namespace axg

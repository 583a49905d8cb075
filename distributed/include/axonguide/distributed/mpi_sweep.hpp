#pragma once
// A sweep over MPI ranks (docs/guide.md §3.1). Rank 0 reads the verified records, hands
// the members still to run to the other ranks one at a time (dynamic scheduling: a rank
// gets the next member when it returns its last), records each result as it arrives and
// writes sweep.csv, summary.csv and sweep.json: the same bytes as the one-process sweep,
// for any rank count, because every file is written in member order from results that are
// pure functions of (sweep, member). Ranks 1..K-1 run members; each sends a heartbeat
// while it works. A rank that goes silent for `dead_after_seconds` with a member in flight
// is reported dead: that member is recorded as failed (a re-run runs it) and the others
// go on. Only with `mpirun --enable-recovery` does Open MPI 4.1 let the job outlive a rank;
// without it mpirun ends the job, and the re-run runs the members not yet recorded.
#include <string>

#include "axonguide/study/sweep.hpp"

namespace axg::distributed {

struct SweepOverRanks {
  sweep::Spec spec;        // as every rank read it
  sweep::Outcome outcome;  // rank 0's; empty on the other ranks
  int dead_ranks = 0;
  bool is_root = false;
};

// Called by every rank with the same arguments. Throws on rank 0 (InputError, RunError)
// when the sweep cannot proceed; the other ranks are told to stop first, and return with
// exit_code set (they print nothing). `threads` is per rank.
SweepOverRanks run_sweep_over_ranks(const std::string& spec_path, const std::string& out_dir,
                                    const sweep::Options& options, int* exit_code);

}  // namespace axg::distributed

// Sweeps over MPI ranks: rank 0 schedules and records, the others run members
// (docs/guide.md §3.1). Messages are JSON text (a member index, a record); a record
// carries its result exactly (sweep::record_json / result_from_record).
#include "axonguide/distributed/mpi_sweep.hpp"

#include <mpi.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <future>
#include <optional>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "axonguide/support/error.hpp"
#include "axonguide/support/threads.hpp"

namespace axg::distributed {

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

namespace {

// Worker to rank 0: kReady (first message), kResult (a record), kHeartbeat (still working).
// Rank 0 to a worker: kWork (a member index), kStop (an exit code; 0 when all is done).
enum Tag : int { kReady = 1, kResult = 2, kHeartbeat = 3, kWork = 4, kStop = 5 };

void send_text(int to, Tag tag, const std::string& text) {
  MPI_Send(text.data(), static_cast<int>(text.size()), MPI_CHAR, to, tag, MPI_COMM_WORLD);
}

std::string receive_text(const MPI_Status& st) {
  int count = 0;
  MPI_Get_count(&st, MPI_CHAR, &count);
  std::string text(static_cast<std::size_t>(count), '\0');
  MPI_Recv(text.data(), count, MPI_CHAR, st.MPI_SOURCE, st.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return text;
}

double dead_after_seconds() {
  if (const char* v = std::getenv("AXG_MPI_DEAD_AFTER"); v && *v) return std::atof(v);
  return 30.0;
}

// Rank 0: hands out `pending` one member at a time and records what comes back.
struct Scheduler {
  Scheduler(int ranks, double after) : size(ranks), dead_after(after), gone(ranks, false), idle(ranks, false) {
    gone[0] = true;
  }
  int size;
  double dead_after;
  int dead = 0;
  std::vector<bool> gone;  // stopped or dead
  std::vector<bool> idle;  // waiting: nothing was left to hand out

  // Tells every live rank to stop, with the exit code and whether a rank died: then none
  // may wait in MPI_Finalize, which Open MPI 4.1 would never let return. The idle ranks
  // wait for this until the sweep is over, so that they learn of a death after theirs.
  void stop_all(int code) {
    for (int r = 1; r < size; ++r)
      if (!gone[r]) send_text(r, kStop, fmt::format("{} {}", code, dead)), gone[r] = true;
  }

  void run(const std::vector<std::size_t>& pending, const sweep::Record& record) {
    std::vector<std::optional<std::size_t>> in_flight(size);
    std::vector<Clock::time_point> heard(size, Clock::now());
    std::size_t next = 0, recorded = 0;
    int active = size - 1;
    auto hand_out = [&](int rank) {
      if (next < pending.size()) {
        in_flight[rank] = pending[next++];
        send_text(rank, kWork, std::to_string(*in_flight[rank]));
      } else {
        idle[rank] = true;
        --active;
      }
    };
    while (active > 0) {
      int flag = 0;
      MPI_Status st;
      MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &st);
      if (flag) {
        const int from = st.MPI_SOURCE;
        const std::string text = receive_text(st);
        heard[from] = Clock::now();
        if (gone[from] || idle[from]) continue;  // a late heartbeat
        if (st.MPI_TAG == kResult) {
          record(sweep::result_from_record(json::parse(text)));
          in_flight[from].reset();
          ++recorded;
        }
        if (st.MPI_TAG == kResult || st.MPI_TAG == kReady) hand_out(from);
        continue;
      }
      const auto now = Clock::now();
      for (int r = 1; r < size; ++r) {
        if (gone[r] || idle[r] || std::chrono::duration<double>(now - heard[r]).count() < dead_after) continue;
        gone[r] = true;
        --active;
        ++dead;
        if (in_flight[r]) {
          sweep::MemberResult lost;
          lost.member = *in_flight[r];
          lost.exit_code = kExitCannotRun;
          lost.message = fmt::format("rank {} died while running it (silent for {:g} s); a re-run runs it", r,
                                     dead_after);
          record(std::move(lost));
          ++recorded;
        }
      }
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    // Every worker died: what was never handed out is left for the re-run, recorded as
    // not run.
    for (; next < pending.size(); ++next) {
      sweep::MemberResult lost;
      lost.member = pending[next];
      lost.exit_code = kExitCannotRun;
      lost.message = "not run: no rank was left to run it; a re-run runs it";
      record(std::move(lost));
    }
  }
};

// Ranks 1..K-1: run members until told to stop; returns the exit code rank 0 sent, and
// sets `dead` to the ranks it reported dead.
int work(const sweep::Spec& spec, const fs::path& dir, const sweep::Options& options, int* dead) {
  send_text(0, kReady, "");
  for (;;) {
    MPI_Status st;
    MPI_Probe(0, MPI_ANY_TAG, MPI_COMM_WORLD, &st);
    const std::string text = receive_text(st);
    if (st.MPI_TAG == kStop) {
      int code = 0;
      std::sscanf(text.c_str(), "%d %d", &code, dead);
      return code;
    }
    const std::size_t m = std::stoull(text);
    const fs::path run_dir = spec.write_runs ? dir / "members" / fmt::format("m{:07d}", m) : fs::path();
    auto result = std::async(std::launch::async, [&] {
      return with_threads(options.threads, [&] { return sweep::run_member(spec, m, options.run, run_dir, options.backend); });
    });
    while (result.wait_for(std::chrono::milliseconds(250)) != std::future_status::ready) send_text(0, kHeartbeat, "");
    const sweep::MemberResult r = result.get();
    send_text(0, kResult, sweep::record_json(r, spec.seeds[m % spec.seeds.size()]).dump());
  }
}

}  // namespace

SweepOverRanks run_sweep_over_ranks(const std::string& spec_path, const std::string& out_dir,
                                    const sweep::Options& options, int* exit_code) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  SweepOverRanks out;
  out.is_root = rank == 0;
  *exit_code = kExitOk;
  // Every rank reads the sweep; rank 0 reports an error, and every rank stops with it.
  std::optional<sweep::Spec> spec;
  std::exception_ptr error;
  int code = kExitOk;
  try {
    spec = sweep::load_spec(spec_path);
  } catch (const InputError&) {
    error = std::current_exception(), code = kExitBadInput;
  } catch (const std::exception&) {
    error = std::current_exception(), code = kExitCannotRun;
  }
  int worst = code;
  MPI_Allreduce(&code, &worst, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  if (worst != kExitOk) {
    *exit_code = worst;
    if (rank != 0) return out;
    if (error) std::rethrow_exception(error);
    throw RunError(fmt::format("sweep: another rank could not read {} (exit {}); every rank must see the same file",
                               spec_path, worst));
  }
  out.spec = *spec;
  if (rank != 0) {
    *exit_code = work(out.spec, fs::path(out_dir), options, &out.dead_ranks);
    return out;
  }
  Scheduler scheduler(size, dead_after_seconds());
  sweep::Options root = options;
  root.execute = [&](const std::vector<std::size_t>& pending, const sweep::Record& record) {
    scheduler.run(pending, record);
  };
  try {
    out.outcome = sweep::run(out.spec, out_dir, root);
    scheduler.stop_all(out.outcome.failed > 0 ? kExitCheckFailed : kExitOk);
  } catch (const InputError&) {
    scheduler.stop_all(kExitBadInput);
    throw;
  } catch (...) {
    scheduler.stop_all(kExitCannotRun);
    throw;
  }
  out.dead_ranks = scheduler.dead;
  return out;
}

}  // namespace axg::distributed

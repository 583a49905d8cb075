#include "axonguide/distributed/mpi_comm.hpp"

#include <dlfcn.h>
#include <mpi.h>

#include <algorithm>
#include <atomic>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include <fmt/format.h>

#include "axonguide/distributed/launch.hpp"
#include "axonguide/support/error.hpp"

namespace axg::distributed {

namespace {

void check(int rc, const char* call) {
  if (rc == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int len = 0;
  MPI_Error_string(rc, text, &len);
  throw RunError(fmt::format("{} failed: {}", call, std::string(text, static_cast<std::size_t>(len))));
}

int as_int(std::size_t n, const char* what) {
  if (n > static_cast<std::size_t>(INT_MAX))
    throw RunError(fmt::format("{}: {} bytes exceed one MPI message", what, n));
  return static_cast<int>(n);
}

// Messages go as pieces of at most 1 GiB (an int counts at most 2^31 - 1 bytes).
// AXG_TEST_MPI_CHUNK=N makes this rank ask for pieces of N bytes, so that the tests take the
// pieced path with small runs (tests/distributed/check_mpi_run.sh); the ranks agree on the
// smallest asked for (MpiComm's constructor), since both ends of a message must cut alike.
std::uint64_t chunk_asked() {
  const std::uint64_t most = std::uint64_t{1} << 30;
  const char* e = std::getenv("AXG_TEST_MPI_CHUNK");
  if (!e || !*e) return most;
  const long long v = std::atoll(e);
  return v >= 1 && static_cast<std::uint64_t>(v) <= most ? static_cast<std::uint64_t>(v) : most;
}
constexpr int kGatherTag = 71;
constexpr int kExchangeTag = 72;

class MpiComm final : public Comm {
 public:
  MpiComm() {
    check(MPI_Comm_dup(MPI_COMM_WORLD, &comm_), "MPI_Comm_dup");
    MPI_Comm_set_errhandler(comm_, MPI_ERRORS_RETURN);
    MPI_Comm_rank(comm_, &rank_);
    MPI_Comm_size(comm_, &size_);
    std::uint64_t chunk = chunk_asked();
    check(MPI_Allreduce(MPI_IN_PLACE, &chunk, 1, MPI_UINT64_T, MPI_MIN, comm_), "MPI_Allreduce");
    chunk_ = static_cast<std::size_t>(chunk);
  }
  ~MpiComm() override {
    MPI_Comm_free(&comm_);
  }
  int rank() const override { return rank_; }
  int size() const override { return size_; }

  std::vector<Bytes> allgather(const Bytes& mine) override {
    count_collective(mine.size());
    std::vector<std::uint64_t> sizes(static_cast<std::size_t>(size_));
    std::uint64_t n = mine.size();
    check(MPI_Allgather(&n, 1, MPI_UINT64_T, sizes.data(), 1, MPI_UINT64_T, comm_), "MPI_Allgather");
    std::vector<int> counts(size_), displs(size_);
    std::size_t total = 0;
    for (int r = 0; r < size_; ++r) {
      counts[r] = as_int(sizes[r], "all-gather");
      displs[r] = as_int(total, "all-gather");
      total += sizes[r];
    }
    as_int(total, "all-gather");
    if (total == 0) return std::vector<Bytes>(static_cast<std::size_t>(size_));  // the usual case of rare traffic
    Bytes all(total);
    check(MPI_Allgatherv(mine.data(), counts[rank_], MPI_BYTE, all.data(), counts.data(), displs.data(), MPI_BYTE,
                         comm_),
          "MPI_Allgatherv");
    std::vector<Bytes> out(size_);
    for (int r = 0; r < size_; ++r) out[r].assign(all.begin() + displs[r], all.begin() + displs[r] + counts[r]);
    return out;
  }

  void allreduce(std::vector<std::uint64_t>& v, Reduce op) override {
    count_collective(v.size() * 8);
    const MPI_Op mop = op == Reduce::kSum ? MPI_SUM : op == Reduce::kMax ? MPI_MAX : MPI_BOR;
    check(MPI_Allreduce(MPI_IN_PLACE, v.data(), as_int(v.size(), "all-reduce"), MPI_UINT64_T, mop, comm_),
          "MPI_Allreduce");
  }

  void set_neighbours(const std::vector<int>& peers) override { peers_ = peers; }

  // One message to each peer and one from each, sizes carried by the messages themselves
  // (matched probes), received straight into `in`: a round trip, not the two collectives
  // (counts, then payloads) and the staging copies of a neighbourhood all-to-all. A message
  // of a piece's size or more (chunk_) goes as pieces, the last one shorter (empty when
  // the size is a multiple): MPI keeps the order of messages between two ranks on one tag,
  // and a piece shorter than a whole one ends the message.
  void exchange_into(const std::vector<Bytes>& out, std::vector<Bytes>& in) override {
    const std::size_t n = peers_.size(), chunk = chunk_;
    requests_.clear();
    for (std::size_t k = 0; k < n; ++k) {
      std::size_t at = 0;
      do {
        const std::size_t len = std::min(chunk, out[k].size() - at);
        requests_.emplace_back();
        check(MPI_Isend(out[k].data() + at, static_cast<int>(len), MPI_BYTE, peers_[k], kExchangeTag, comm_,
                        &requests_.back()),
              "MPI_Isend");
        ++traffic_.messages, traffic_.message_bytes += len;
        at += len;
        if (len < chunk) break;
      } while (true);
    }
    in.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
      in[k].clear();
      int count = 0;
      do {
        MPI_Message message;
        MPI_Status status;
        check(MPI_Mprobe(peers_[k], kExchangeTag, comm_, &message, &status), "MPI_Mprobe");
        check(MPI_Get_count(&status, MPI_BYTE, &count), "MPI_Get_count");
        const std::size_t at = in[k].size();
        in[k].resize(at + static_cast<std::size_t>(count));
        check(MPI_Mrecv(in[k].data() + at, count, MPI_BYTE, &message, MPI_STATUS_IGNORE), "MPI_Mrecv");
      } while (static_cast<std::size_t>(count) == chunk);
    }
    check(MPI_Waitall(static_cast<int>(requests_.size()), requests_.data(), MPI_STATUSES_IGNORE), "MPI_Waitall");
  }

  std::vector<Bytes> gather(Bytes mine) override {
    const std::size_t chunk = chunk_;
    std::vector<Bytes> all;
    if (rank_ != 0) {
      std::uint64_t n = mine.size();
      check(MPI_Send(&n, 1, MPI_UINT64_T, 0, kGatherTag, comm_), "MPI_Send");
      for (std::size_t at = 0; at < mine.size(); at += chunk) {
        const std::size_t len = std::min(chunk, mine.size() - at);
        check(MPI_Send(mine.data() + at, static_cast<int>(len), MPI_BYTE, 0, kGatherTag, comm_), "MPI_Send");
        ++traffic_.messages;
        traffic_.message_bytes += len;
      }
      return all;
    }
    all.resize(static_cast<std::size_t>(size_));
    all[0] = std::move(mine);
    for (int r = 1; r < size_; ++r) {
      std::uint64_t n = 0;
      check(MPI_Recv(&n, 1, MPI_UINT64_T, r, kGatherTag, comm_, MPI_STATUS_IGNORE), "MPI_Recv");
      all[r].resize(n);
      for (std::size_t at = 0; at < n; at += chunk) {
        const std::size_t len = std::min<std::size_t>(chunk, n - at);
        check(MPI_Recv(all[r].data() + at, static_cast<int>(len), MPI_BYTE, r, kGatherTag, comm_, MPI_STATUS_IGNORE),
              "MPI_Recv");
      }
    }
    return all;
  }

 private:
  void count_collective(std::size_t bytes) {
    ++traffic_.collectives;
    traffic_.collective_bytes += bytes;
  }
  MPI_Comm comm_ = MPI_COMM_NULL;
  int rank_ = 0, size_ = 1;
  std::vector<int> peers_;
  std::vector<MPI_Request> requests_;  // the exchange's sends, kept from call to call
  std::size_t chunk_ = std::size_t{1} << 30;  // the pieces' size, agreed by every rank
};

}  // namespace

std::unique_ptr<Comm> make_mpi_comm() { return std::make_unique<MpiComm>(); }

// The MPI library, as it names itself (callable before MPI_Init): "Open MPI v4.1.4".
std::string mpi_library() {
  char text[MPI_MAX_LIBRARY_VERSION_STRING];
  int len = 0;
  if (MPI_Get_library_version(text, &len) != MPI_SUCCESS) return "an unknown MPI library";
  std::string v(text, static_cast<std::size_t>(len));
  if (const auto eol = v.find_first_of(",\n"); eol != std::string::npos) v.resize(eol);
  return v;
}

namespace {

std::atomic<bool> g_starting{false};  // inside MPI_Init_thread

void say_mpi_could_not_start() {
  std::fprintf(stderr,
               "axonguide: error: MPI could not start (%s, MPI_Init_thread; its own message is above): check the "
               "launcher (mpirun or srun of the same MPI as this build) and its MCA settings, or run without "
               "mpirun\n",
               mpi_library().c_str());
  std::fflush(stderr);
}

// A library that ends the process with exit() when MPI_Init fails (its errors are fatal
// before there is a communicator to set a handler on): this says which library failed and
// makes it exit 3, a run that could not proceed. Open MPI 4.1 takes the path of PMIx_Abort
// below instead.
void init_failed_at_exit() {
  if (!g_starting) return;
  say_mpi_could_not_start();
  std::_Exit(3);
}

}  // namespace

MpiSession::MpiSession() {
  const char* size = std::getenv("OMPI_COMM_WORLD_SIZE");
  const char* local = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
  if (const char* chosen = std::getenv("OMPI_MCA_pml"); chosen && *chosen) {
    pml = std::string(chosen) + " (OMPI_MCA_pml or --mca pml)";
  } else if (size && local && std::strcmp(size, local) == 0) {
    setenv("OMPI_MCA_pml", "ob1", 0);
    pml = "ob1 (every rank on one node)";
  } else {
    pml = "the library's choice";
  }
  int provided = 0;
  g_starting = true;
  std::atexit(init_failed_at_exit);
  const int rc = MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  if (rc != MPI_SUCCESS) init_failed_at_exit();
  g_starting = false;
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
}

MpiSession::~MpiSession() {
  if (rank_died) {
    // Open MPI 4.1 (no ULFM) waits in MPI_Finalize for a rank that died; the outputs are
    // written, so the job ends here, with the command's exit code.
    std::fflush(stdout);
    std::fflush(stderr);
    std::_Exit(exit_code);
  }
  no_delay_on_loopback_sockets();  // launch.hpp: PMIx's messages in MPI_Finalize, without 40 ms stalls
  MPI_Finalize();
}

void abort_job(int code) {
  std::fflush(stdout);
  std::fflush(stderr);
  MPI_Abort(MPI_COMM_WORLD, code);
  std::_Exit(code);
}

}  // namespace axg::distributed

// Open MPI 4.1 ends a process whose MPI_Init fails inside it (a messaging component that
// does not exist or cannot be selected, say) by reporting an abort with status 1 to its
// launcher through PMIx, whose exit status follows that report, and then calling _exit(1):
// no exit handler runs (docs/scaling.md §2.8). The command defines PMIx_Abort and exports it
// from the executable (app/CMakeLists.txt), so the library's call, made through the
// dynamic symbol table, reaches this one first. Inside MPI_Init it names the library and
// reports status 3, a run that could not proceed; at any other time (MPI_Abort, with the
// command's own codes) it passes the call on unchanged. An MPI that never calls PMIx_Abort
// is not affected. The arguments are PMIx's (pmix_status_t is a 32-bit int, procs an array
// of pmix_proc_t), passed through as they came.
extern "C" int PMIx_Abort(int status, const char msg[], void* procs, std::size_t nprocs) {
  using Abort = int (*)(int, const char[], void*, std::size_t);
  static const auto next = reinterpret_cast<Abort>(dlsym(RTLD_NEXT, "PMIx_Abort"));
  if (axg::distributed::g_starting) {
    axg::distributed::say_mpi_could_not_start();
    status = 3;
  }
  if (!next) std::_Exit(status);  // no PMIx library behind it: end the process as the abort would
  return next(status, msg, procs, nprocs);
}

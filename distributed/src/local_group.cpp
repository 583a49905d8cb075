#include "axonguide/distributed/local_group.hpp"

#include <algorithm>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "axonguide/support/threads.hpp"

namespace axg::distributed {

namespace {

// Thrown in the ranks that wait in a collective when another rank has failed.
struct GroupBroken : std::runtime_error {
  GroupBroken() : std::runtime_error("another rank of the local group failed") {}
};

// The collectives, so that a rank calling another one than the others is caught (MPI would
// hang or mismatch).
enum class Call { kAllgather, kAllreduce, kExchange, kGather };

struct Shared {
  explicit Shared(int k) : size(k), slot(k), matrix(k, std::vector<Bytes>(k)), values(k), peers(k), call(k) {}
  int size;
  std::mutex m;
  std::condition_variable cv;
  int arrived = 0;
  std::uint64_t generation = 0;
  bool broken = false;
  std::vector<Bytes> slot;                 // one contribution per rank
  std::vector<std::vector<Bytes>> matrix;  // [from][to] for exchanges
  std::vector<std::vector<std::uint64_t>> values;
  std::vector<std::vector<int>> peers;
  std::vector<Call> call;

  void sync() {
    std::unique_lock lk(m);
    if (broken) throw GroupBroken();
    const std::uint64_t gen = generation;
    if (++arrived == size) {
      arrived = 0;
      ++generation;
      cv.notify_all();
      return;
    }
    cv.wait(lk, [&] { return generation != gen || broken; });
    if (broken) throw GroupBroken();
  }
  // The first barrier of every collective: all ranks must be making the same call.
  void enter(int rank, Call c) {
    call[rank] = c;
    sync();
    for (Call other : call)
      if (other != c) throw std::logic_error("ranks of a local group called different collectives at once");
  }
  void brake() {
    std::lock_guard lk(m);
    broken = true;
    cv.notify_all();
  }
};

class LocalComm final : public Comm {
 public:
  LocalComm(Shared& s, int rank) : s_(s), rank_(rank) {}
  int rank() const override { return rank_; }
  int size() const override { return s_.size; }

  std::vector<Bytes> allgather(const Bytes& mine) override {
    count_collective(mine.size());
    s_.enter(rank_, Call::kAllgather);
    s_.slot[rank_] = mine;
    s_.sync();
    std::vector<Bytes> all = s_.slot;
    s_.sync();
    return all;
  }

  void allreduce(std::vector<std::uint64_t>& v, Reduce op) override {
    count_collective(v.size() * 8);
    s_.enter(rank_, Call::kAllreduce);
    s_.values[rank_] = v;
    s_.sync();
    for (int r = 0; r < s_.size; ++r) {
      if (r == rank_) continue;
      const auto& o = s_.values[r];
      for (std::size_t i = 0; i < v.size(); ++i)
        v[i] = op == Reduce::kSum ? v[i] + o[i] : op == Reduce::kMax ? std::max(v[i], o[i]) : (v[i] | o[i]);
    }
    s_.sync();
  }

  void set_neighbours(const std::vector<int>& peers) override { s_.peers[rank_] = peers; }

  void exchange_into(const std::vector<Bytes>& out, std::vector<Bytes>& in) override {
    const std::vector<int>& peers = s_.peers[rank_];
    s_.enter(rank_, Call::kExchange);
    for (std::size_t k = 0; k < peers.size(); ++k) {
      s_.matrix[rank_][peers[k]] = out[k];
      ++traffic_.messages, traffic_.message_bytes += out[k].size();  // one message a peer, empty or not, as MPI sends
    }
    s_.sync();
    in.resize(peers.size());
    for (std::size_t k = 0; k < peers.size(); ++k) in[k].swap(s_.matrix[peers[k]][rank_]);
    s_.sync();
  }

  std::vector<Bytes> gather(Bytes mine) override {
    if (rank_ != 0) ++traffic_.messages, traffic_.message_bytes += mine.size();
    s_.enter(rank_, Call::kGather);
    s_.slot[rank_] = std::move(mine);
    s_.sync();
    std::vector<Bytes> all;
    if (rank_ == 0) all = std::move(s_.slot), s_.slot.assign(static_cast<std::size_t>(s_.size), Bytes());
    s_.sync();
    return all;
  }

 private:
  void count_collective(std::size_t bytes) {
    ++traffic_.collectives;
    traffic_.collective_bytes += bytes;
  }
  Shared& s_;
  int rank_;
};

}  // namespace

void run_local_group(int ranks, int threads, const std::function<void(Comm&)>& fn) {
  if (ranks < 1) throw std::invalid_argument("run_local_group: at least one rank");
  Shared shared(ranks);
  std::vector<std::exception_ptr> errors(ranks);
  std::vector<bool> first_hand(ranks, false);
  std::vector<std::thread> pool;
  for (int r = 0; r < ranks; ++r)
    pool.emplace_back([&, r] {
      LocalComm comm(shared, r);
      try {
        with_threads(threads, [&] { fn(comm); });
      } catch (const GroupBroken&) {
        errors[r] = std::current_exception();
        shared.brake();
      } catch (...) {
        errors[r] = std::current_exception();
        first_hand[r] = true;
        shared.brake();
      }
    });
  for (auto& t : pool) t.join();
  for (int r = 0; r < ranks; ++r)
    if (first_hand[r]) std::rethrow_exception(errors[r]);
}

}  // namespace axg::distributed

#pragma once
// The messages of a run decomposed over ranks (docs/scaling.md §2), behind one interface
// with two transports: MPI (mpi_comm.hpp, Open MPI from Debian) and a group of threads in
// this process (local_group.hpp), so that the decomposed placement and engine are tested
// byte for byte against the one-process run on machines and in builds without MPI.
//
// Every call is collective: every rank of the group makes the same calls in the same
// order. Payloads are raw bytes of trivially copyable records: all ranks run the same
// build on the same architecture.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

namespace axg::distributed {

using Bytes = std::vector<std::byte>;

// What this rank sent: point-to-point messages (the neighbour exchanges send one to each
// peer, empty or not; the gather to rank 0) and collective calls (reductions, all-gathers),
// with their bytes.
struct Traffic {
  std::uint64_t messages = 0, message_bytes = 0;
  std::uint64_t collectives = 0, collective_bytes = 0;
  Traffic operator-(const Traffic& o) const {
    return {messages - o.messages, message_bytes - o.message_bytes, collectives - o.collectives,
            collective_bytes - o.collective_bytes};
  }
};

enum class Reduce { kSum, kMax, kOr };

class Comm {
 public:
  virtual ~Comm() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  bool root() const { return rank() == 0; }

  // Every rank's bytes, in rank order, on every rank.
  virtual std::vector<Bytes> allgather(const Bytes& mine) = 0;
  // Element by element over the ranks, the result on every rank.
  virtual void allreduce(std::vector<std::uint64_t>& values, Reduce op) = 0;
  // The peers of exchange(): a symmetric list (a is b's peer when b is a's), ascending.
  virtual void set_neighbours(const std::vector<int>& peers) = 0;
  // Sends out[k] to peer k; in[k] becomes what peer k sent. `in` keeps its buffers'
  // capacity from call to call, so that a step's exchanges reuse memory the previous step
  // touched (a fresh megabyte a step faults on every page, which a virtual machine makes
  // the halo's largest cost).
  virtual void exchange_into(const std::vector<Bytes>& out, std::vector<Bytes>& in) = 0;
  // The same, into fresh buffers: what each peer sent, in peer order.
  std::vector<Bytes> exchange(const std::vector<Bytes>& out) {
    std::vector<Bytes> in;
    exchange_into(out, in);
    return in;
  }
  // Every rank's bytes on rank 0, in rank order; empty on the other ranks. Takes the
  // buffer, so that rank 0 keeps its own without a copy.
  virtual std::vector<Bytes> gather(Bytes mine) = 0;

  const Traffic& traffic() const { return traffic_; }

 protected:
  Traffic traffic_;
};

// Records in and out of byte buffers.
template <class T>
void append(Bytes& out, const T* data, std::size_t count) {
  static_assert(std::is_trivially_copyable_v<T>);
  const std::byte* from = reinterpret_cast<const std::byte*>(data);
  out.insert(out.end(), from, from + count * sizeof(T));
}
template <class T>
void append(Bytes& out, const std::vector<T>& v) {
  append(out, v.data(), v.size());
}
// Calls visit(record) for every record in `in`, in order.
template <class T, class Visit>
void for_each_record(const Bytes& in, Visit&& visit) {
  static_assert(std::is_trivially_copyable_v<T>);
  for (std::size_t at = 0; at + sizeof(T) <= in.size(); at += sizeof(T)) {
    T r;
    std::memcpy(static_cast<void*>(&r), in.data() + at, sizeof(T));
    visit(r);
  }
}
template <class T>
std::vector<T> records(const Bytes& in) {
  static_assert(std::is_trivially_copyable_v<T>);
  std::vector<T> v(in.size() / sizeof(T));
  if (!v.empty()) std::memcpy(v.data(), in.data(), v.size() * sizeof(T));
  return v;
}

}  // namespace axg::distributed

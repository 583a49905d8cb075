// The grid field over ranks (fields.hpp; docs/scaling.md §2.4), the hooks of GridFieldStages
// (fields/grid_stages.hpp, which writes the step once): a rank owns the z-planes of
// its slab, [z0, z1), and stores [z0 - 3, z1 + 3) clamped to the grid. Every owned node is
// computed by the one-process expression from the same values:
//  - sources: the core deposit's eight nodes, each added by its plane's owner;
//  - explicit FTCS: core::ftcs_node on the slab (one ghost plane each side, exchanged
//    before every sub-step);
//  - implicit LOD: the x and y sweeps of the owned planes are local (whole lines); the z
//    sweep is the serial Thomas algorithm along lines that cross the slabs, pipelined:
//    the lines are cut in batches of y, and at stage t rank r eliminates batch t - r
//    forward from the (c', d') that rank r - 1 passed up for that batch, then in the back
//    substitution batch t - (K - 1 - r) from the solution rank r + 1 passed down. Each
//    row's lod_forward / lod_backward call is the one-process call with the same inputs.
//  - sensing: core::sample_grid_field on the slab, whose ghost planes each side are
//    exchanged after the step: a tip of the slab reads the planes of its cell and one more
//    each way (the centred differences), two beyond the slab; a third covers a tip within
//    rounding of a slab face that lies on a plane (mesh_locate's (z - origin) / h may then
//    land on the next cell).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include <tbb/parallel_for.h>

#include "axonguide/core/stencil.hpp"
#include "axonguide/engine/state.hpp"
#include "axonguide/model/stencil.hpp"
#include "axonguide/distributed/fields.hpp"
#include "axonguide/distributed/on_every_rank.hpp"
#include "axonguide/support/error.hpp"
#include "axonguide/fields/grid_stages.hpp"
#include "axonguide/fields/lod.hpp"

namespace axg::distributed {

namespace {

// The planes rank r owns: those whose z coordinate falls in its slab (monotone in the
// plane: slabs are ranges); rank r owns [first[r], first[r + 1]).
std::vector<int> slab_starts(const Scene& scene, const Decomposition& d, int ranks) {
  const GridGeometry3 g = grid_field_geometry(scene);
  const int n = g.n;
  std::vector<int> first(static_cast<std::size_t>(ranks) + 1, n);
  for (int r = 0; r < ranks; ++r) {
    int lo = n;
    for (int k = 0; k < n; ++k)
      if (d.owner({0.0, 0.0, g.origin.z + g.h * k}) >= r) {
        lo = k;
        break;
      }
    first[static_cast<std::size_t>(r)] = lo;
  }
  first[static_cast<std::size_t>(ranks)] = n;
  return first;
}

GridFieldStages::Slab rank_slab(const std::vector<int>& first, int rank, int n, int ghosts) {
  const int z0 = first[static_cast<std::size_t>(rank)], z1 = first[static_cast<std::size_t>(rank) + 1];
  return {z0, z1, std::max(0, z0 - ghosts), std::min(n, z1 + ghosts)};
}

class DecomposedGridField final : public GridFieldStages {
 public:
  DecomposedGridField(const Scene& scene, const std::vector<core::CueParams>& cues, const Decomposition& d,
                      Comm& comm, FieldReport& report, std::vector<int> first)
      : GridFieldStages(scene, cues,
                        rank_slab(first, comm.rank(), grid_field_geometry(scene).n, grid_ghost_planes(scene))),
        ghosts_(grid_ghost_planes(scene)),
        comm_(comm),
        rank_(comm.rank()),
        ranks_(comm.size()),
        report_(report),
        first_(std::move(first)),
        z0_(slab_.z0),
        z1_(slab_.z1) {
    if (!d.slabs) throw RunError("decomposed grid field: the decomposition is not in slabs along z");
    for (int r = 0; r < ranks_; ++r)
      if (first_[static_cast<std::size_t>(r) + 1] - first_[static_cast<std::size_t>(r)] < ghosts_ && ranks_ > 1)
        throw RunError("decomposed grid field: a slab holds fewer planes than its ghost layers (the halo rule "
                       "keeps slabs as thick as the ghosts; this is a bug)");
    if (rank_ > 0) peers_.push_back(rank_ - 1);
    if (rank_ + 1 < ranks_) peers_.push_back(rank_ + 1);
    if (peers_ != d.neighbours(rank_)) throw RunError("decomposed grid field: slab neighbours are not r - 1, r + 1");
    // Batches of y for the pipelined z sweep: four a rank, so that the pipeline idles for
    // (K - 1) / (4K + K - 1) of its stages.
    batches_ = ranks_ == 1 ? 1 : std::min(geometry_.n, 4 * ranks_);
  }

  std::size_t bytes() const override {
    std::size_t ghosts = 0;
    for (const Bytes& b : ghost_out_) ghosts += b.capacity();
    for (const Bytes& b : ghost_in_) ghosts += b.capacity();
    return buffer_bytes() + (cp_.size() + dp_.size()) * sizeof(double) + ghosts;
  }

  // Collective: rank 0 receives every cue's current values, node order.
  void save(EngineState& out) const override {
    Bytes mine;
    for (std::size_t k = 0; k < cues_.size(); ++k)
      append(mine, buffer_[cur_[k]].data() + k * slab_values_ + local(z0_), static_cast<std::size_t>(z1_ - z0_) * plane_);
    std::vector<Bytes> all = comm_.gather(std::move(mine));
    if (!comm_.root()) return;
    const std::size_t nodes = geometry_.nodes();
    out.grid.assign(cues_.size() * nodes, 0.0);
    for (int r = 0; r < ranks_; ++r) {
      const std::vector<double> v = records<double>(all[static_cast<std::size_t>(r)]);
      const int a = first_[static_cast<std::size_t>(r)], b = first_[static_cast<std::size_t>(r) + 1];
      const std::size_t count = static_cast<std::size_t>(b - a) * plane_;
      for (std::size_t k = 0; k < cues_.size(); ++k)
        std::copy_n(v.data() + k * count, count, out.grid.data() + k * nodes + static_cast<std::size_t>(a) * plane_);
    }
  }

  // Every rank reads the whole checkpoint and keeps its slab (ghost planes included). A grid
  // of another size is found alike on every rank: the ranks end together.
  void load(const EngineState& in) override {
    const std::size_t nodes = geometry_.nodes();
    on_every_rank([&] {
      if (in.grid.size() != cues_.size() * nodes)
        throw RunError("checkpoint: the grid has " + std::to_string(in.grid.size()) + " values, the scene needs " +
                       std::to_string(cues_.size() * nodes));
    });
    for (std::size_t k = 0; k < cues_.size(); ++k)
      std::copy_n(in.grid.data() + k * nodes + static_cast<std::size_t>(slab_.g0) * plane_, slab_values_,
                  buffer_[0].data() + k * slab_values_);
    cur_.assign(cues_.size(), 0);
  }

 private:
  // The ghost planes sensing reads: a tip of the slab reads the planes of its cell and one
  // more each way (the centred differences), two beyond the slab; a third covers a tip within
  // rounding of a slab face that lies on a plane.
  void stepped(std::uint32_t step, PhaseTimes& times) override {
    ScopedPhase p(times, step, "grid.ghosts");
    for (std::size_t k = 0; k < cues_.size(); ++k) exchange_ghosts(values(k, cur_[k]), ghosts_);
  }

  // `width` planes each side from the neighbours' owned planes.
  void exchange_ghosts(double* c, int width) override {
    if (ranks_ == 1) return;
    const Traffic before = comm_.traffic();
    std::vector<Bytes>& out = ghost_out_;
    out.resize(peers_.size());
    for (Bytes& b : out) b.clear();
    std::size_t p = 0;
    const std::size_t w = static_cast<std::size_t>(width);
    if (rank_ > 0) append(out[p++], c + local(z0_), w * plane_);
    if (rank_ + 1 < ranks_) append(out[p++], c + local(z1_ - width), w * plane_);
    std::vector<Bytes>& in = ghost_in_;
    comm_.exchange_into(out, in);
    p = 0;
    if (rank_ > 0) receive(in[p++], c + local(z0_ - width), w);
    if (rank_ + 1 < ranks_) receive(in[p++], c + local(z1_), w);
    const Traffic spent = comm_.traffic() - before;
    report_.halo.messages += spent.messages, report_.halo.message_bytes += spent.message_bytes;
    report_.halo.collectives += spent.collectives, report_.halo.collective_bytes += spent.collective_bytes;
  }

  void receive(const Bytes& from, double* to, std::size_t planes) {
    if (from.size() != planes * plane_ * sizeof(double))
      throw RunError("decomposed grid field: a neighbour sent " + std::to_string(from.size()) + " bytes of ghost planes");
    std::memcpy(to, from.data(), from.size());
    report_.ghost_values += planes * plane_;
  }

  // The z sweep of lines crossing the slabs: rows [a, b] of this rank's unknown rows, the
  // lines in batches of y.
  void sweep_z(double* c, double lambda) override {
    const int n = geometry_.n;
    const std::size_t nn = static_cast<std::size_t>(n);
    const core::LodLine l = core::lod_line(n, lambda, reflecting_);
    if (!reflecting_) {  // the serial sweep's absorbing end planes
      if (z0_ == 0) std::fill_n(c + local(0), plane_, 0.0);
      if (z1_ == n) std::fill_n(c + local(n - 1), plane_, 0.0);
    }
    if (l.hi < l.lo) return;
    const int a = std::max(z0_, l.lo), b = std::min(z1_ - 1, l.hi);  // may be empty (a > b)
    const std::size_t rows = static_cast<std::size_t>(std::max(0, b - a + 1));
    cp_.resize(rows * plane_);
    dp_.resize(rows * plane_);
    auto batch_of = [&](int t) { return std::pair{t * n / batches_, (t + 1) * n / batches_}; };  // y range
    auto row_at = [&](int m) { return c + local(m); };
    // Forward: carry_ holds (c', d') of row a - 1 for the batch's lines, from rank - 1.
    std::vector<double> carry;
    const bool up = rank_ + 1 < ranks_, down = rank_ > 0;
    const int stages = batches_ + ranks_ - 1;
    for (int t = 0; t < stages; ++t) {
      const int batch = t - rank_;
      Bytes send_up;
      if (batch >= 0 && batch < batches_ && rows > 0) {
        const auto [y0, y1] = batch_of(batch);
        tbb::parallel_for(y0, y1, [&](int y) {
          for (int m = a; m <= b; ++m) {
            const std::size_t r = static_cast<std::size_t>(m - a);
            const double* rhs = row_at(m) + static_cast<std::size_t>(y) * nn;
            double* cpm = cp_.data() + r * plane_ + static_cast<std::size_t>(y) * nn;
            double* dpm = dp_.data() + r * plane_ + static_cast<std::size_t>(y) * nn;
            const bool first = m == l.lo;
            if (first) {
              for (std::size_t x = 0; x < nn; ++x) core::lod_forward(l, m, rhs[x], 0.0, 0.0, &cpm[x], &dpm[x]);
              continue;
            }
            // Row m - 1: this rank's, or the carry rank - 1 passed up (c' then d' of each line).
            const double* cprev = m == a ? carry.data() + static_cast<std::size_t>(y - y0) * 2 * nn : cpm - plane_;
            const double* dprev = m == a ? cprev + nn : dpm - plane_;
            for (std::size_t x = 0; x < nn; ++x) core::lod_forward(l, m, rhs[x], cprev[x], dprev[x], &cpm[x], &dpm[x]);
          }
        });
        if (up && b < l.hi) {
          const std::size_t r = static_cast<std::size_t>(b - a);
          for (int y = y0; y < y1; ++y) {
            append(send_up, cp_.data() + r * plane_ + static_cast<std::size_t>(y) * nn, nn);
            append(send_up, dp_.data() + r * plane_ + static_cast<std::size_t>(y) * nn, nn);
          }
        }
      }
      if (ranks_ == 1) continue;
      std::vector<Bytes> out(peers_.size());
      if (up) out.back() = std::move(send_up);
      const std::vector<Bytes> in = comm_.exchange(out);
      ++report_.pipeline_stages;
      if (down) carry = records<double>(in.front());
    }
    // Backward: next_ holds the solution of row b + 1 for the batch's lines, from rank + 1.
    std::vector<double> next;
    for (int t = 0; t < stages; ++t) {
      const int batch = t - (ranks_ - 1 - rank_);
      Bytes send_down;
      if (batch >= 0 && batch < batches_ && rows > 0) {
        const auto [y0, y1] = batch_of(batch);
        tbb::parallel_for(y0, y1, [&](int y) {
          const std::size_t yo = static_cast<std::size_t>(y) * nn;
          for (int m = b; m >= a; --m) {
            const std::size_t r = static_cast<std::size_t>(m - a);
            double* out = row_at(m) + yo;
            const double* cpm = cp_.data() + r * plane_ + yo;
            const double* dpm = dp_.data() + r * plane_ + yo;
            if (m == l.hi) {
              std::copy_n(dpm, nn, out);
              continue;
            }
            const double* above = m == b ? next.data() + static_cast<std::size_t>(y - y0) * nn : row_at(m + 1) + yo;
            for (std::size_t x = 0; x < nn; ++x) out[x] = core::lod_backward(cpm[x], dpm[x], above[x]);
          }
        });
        if (down && a > l.lo)
          for (int y = y0; y < y1; ++y) append(send_down, row_at(a) + static_cast<std::size_t>(y) * nn, nn);
      }
      if (ranks_ == 1) continue;
      std::vector<Bytes> out(peers_.size());
      if (down) out.front() = std::move(send_down);
      const std::vector<Bytes> in = comm_.exchange(out);
      ++report_.pipeline_stages;
      if (up) next = records<double>(in.back());
    }
  }

  int ghosts_;  // planes each side: grid_ghost_planes
  Comm& comm_;
  int rank_, ranks_;
  FieldReport& report_;
  std::vector<int> first_;  // rank r owns planes [first_[r], first_[r + 1])
  int z0_ = 0, z1_ = 0;     // this rank's planes
  std::vector<int> peers_;  // rank - 1, rank + 1 where they exist
  int batches_ = 1;
  std::vector<double> cp_, dp_;  // the z sweep's (c', d') of this rank's rows
  std::vector<Bytes> ghost_out_, ghost_in_;  // the ghost exchange's buffers, kept from step to step
};

}  // namespace

std::unique_ptr<CueField> make_decomposed_grid_field(const Scene& scene, const std::vector<core::CueParams>& cues,
                                                     const Decomposition& d, Comm& comm, FieldReport& report) {
  return std::make_unique<DecomposedGridField>(scene, cues, d, comm, report, slab_starts(scene, d, comm.size()));
}

}  // namespace axg::distributed

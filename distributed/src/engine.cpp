#include "axonguide/distributed/engine.hpp"
#include "axonguide/engine/state.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <tbb/parallel_for.h>

#include "axonguide/engine/axon_stages.hpp"
#include "axonguide/engine/axon_step.hpp"
#include "axonguide/engine/cell_grid.hpp"
#include "axonguide/support/error.hpp"
#include "axonguide/distributed/fields.hpp"
#include "axonguide/model/growth.hpp"
#include "axonguide/placement/placement.hpp"

namespace axg::distributed {

using core::AxonStatus;
using core::Vec3;

namespace {

// One axon's whole state: what migrates, and what rank 0 gathers.
struct AxonRecord {
  Vec3 tip, heading;
  double length, step_length;
  std::uint32_t id, steps, target;
  AxonStatus status;
};

struct TipRecord {
  Vec3 tip;
  std::uint32_t id;
};

// An axon's record followed by its decision interval's sums (m doubles; none when every
// interval is one step), as axons travel between ranks.
void append_axon(Bytes& out, const AxonRecord& r, const double* sums, std::size_t m) {
  append(out, &r, 1);
  if (m) append(out, sums, m);
}

// visit(record, sums) for every axon of a message (sums null when m is 0).
template <class Visit>
void for_each_axon(const Bytes& in, std::size_t m, Visit&& visit) {
  const std::size_t size = sizeof(AxonRecord) + m * sizeof(double);
  std::vector<double> sums(m);
  for (std::size_t at = 0; at + size <= in.size(); at += size) {
    AxonRecord r;
    std::memcpy(static_cast<void*>(&r), in.data() + at, sizeof r);
    if (m) std::memcpy(sums.data(), in.data() + at + sizeof r, m * sizeof(double));
    visit(static_cast<const AxonRecord&>(r), m ? static_cast<const double*>(sums.data()) : nullptr);
  }
}

// The grid over this rank's somas: cells of the one-process soma grid's size over the box
// of its somas (its block and halo at most), coarsened while there are more than about two
// cells a soma. Which cells a search visits changes nothing: find_contact's answer is the
// best (t, id) over the somas within reach, and all of them are in this grid, whose cells
// clamp every point (the tips beyond the box included) monotonically.
// `order` receives the somas' local indices in the grid's order (by cell, then id).
CellGrid local_soma_grid(const Scene& scene, const RankSomas& somas, std::vector<std::uint32_t>& order) {
  Vec3 lo{0, 0, 0}, hi{0, 0, 0};
  for (std::size_t s = 0; s < somas.pos.size(); ++s) {
    const Vec3 p = somas.pos[s];
    lo = s == 0 ? p : Vec3{std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = s == 0 ? p : Vec3{std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  const GridGeometry g = box_geometry(lo, hi, soma_grid_geometry(scene).cell,
                                      2.0 * static_cast<double>(somas.pos.size()) + 64.0);
  CellGrid grid = build_cell_grid(g, somas.pos);
  order = grid.ids;
  for (std::uint32_t& k : grid.ids) k = somas.id[k];  // local index -> neuron id (both ascending)
  return grid;
}

class DecomposedEngine final : public Engine {
 public:
  DecomposedEngine(const Scene& scene, const Decomposition& d, Comm& comm, RankSomas somas, RankReport& report)
      : scene_(scene),
        d_(d),
        comm_(comm),
        rank_(comm.rank()),
        n_(static_cast<std::size_t>(scene.neurons.count)),
        stages_(scene),
        modulated_(stages_.modulated()),
        m_(stages_.sums_per_axon()),
        zeros_(m_, 0.0),
        field_(make_decomposed_field(scene, stages_.cues(), d, comm, report.field)),
        report_(report),
        neighbours_(d.neighbours(rank_)),
        peer_of_(static_cast<std::size_t>(d.ranks), -1) {
    for (std::size_t k = 0; k < neighbours_.size(); ++k) peer_of_[neighbours_[k]] = static_cast<int>(k);
    comm_.set_neighbours(neighbours_);
    // The axons start in the grid's order, so that neighbouring slots search neighbouring
    // cells (the reference engine's slot order; it changes memory traffic only).
    std::vector<std::uint32_t> order;
    grid_ = local_soma_grid(scene, somas, order);
    std::vector<Bytes> out(neighbours_.size());
    for (std::uint32_t s : order) {
      if (!somas.owned[s]) {
        ++report_.halo_somas;
        continue;
      }
      ++report_.owned_somas;
      const std::uint32_t id = somas.id[s];
      const Vec3 h = initial_heading(scene, id, somas.pos[s]);
      route({axon_start(somas.pos[s], h, scene), h, 0.0, stages_.params().step_length, id, 0, core::kNoNeuron,
             AxonStatus::kGrowing},
            zeros_.data(), out);
    }
    receive(comm_.exchange(out));  // a tip starts on its soma's surface, perhaps in the next block
  }

  void warm_up() override {
    if (!field_) return;
    PhaseTimes warmup;
    const FieldReport before = report_.field;  // the run facts count the growth steps
    for (std::uint32_t s = 1; s <= scene_.cues.warmup_steps; ++s) field_->advance(s, warmup);
    report_.field = before;
  }

  void save(EngineState& out) override {
    if (comm_.root()) {
      out.axons.resize(n_);
      out.heading.resize(n_);
      out.step_length.resize(modulated_ ? n_ : 0);
    }
    if (comm_.root()) out.guidance.assign(n_ * m_, 0.0);
    gather_records(false, m_, [&](const AxonRecord& r, const double* sums) {
      out.axons.tip[r.id] = r.tip;
      out.axons.length[r.id] = r.length;
      out.axons.status[r.id] = r.status;
      out.axons.steps[r.id] = r.steps;
      out.axons.target[r.id] = r.target;
      out.heading[r.id] = r.heading;
      if (modulated_) out.step_length[r.id] = r.step_length;
      if (m_ && r.status == AxonStatus::kGrowing)  // a stopped axon's sums are zero, as in one process
        std::copy_n(sums, m_, out.guidance.data() + static_cast<std::size_t>(r.id) * m_);
    });
    out.connected = stats_.connected;
    out.exited = stats_.exited;
    if (field_) field_->save(out);  // collective: the particles or the grid, on rank 0
  }

  // Every rank holds the whole checkpoint; each keeps the axons whose tips lie in its block.
  void load(const EngineState& in) override {
    grow_ = Growing(m_);
    done_.clear();
    if (in.guidance.size() != in.axons.size() * m_)
      throw RunError("checkpoint: the decision sums do not match the scene's neurons and cues");
    for (std::size_t i = 0; i < in.axons.size(); ++i) {
      if (d_.owner(in.axons.tip[i]) != rank_) continue;
      const AxonRecord r{in.axons.tip[i], in.heading[i], in.axons.length[i],
                         modulated_ ? in.step_length[i] : stages_.params().step_length, static_cast<std::uint32_t>(i),
                         in.axons.steps[i], in.axons.target[i], in.axons.status[i]};
      if (r.status == AxonStatus::kGrowing)
        grow_.push(r, m_ ? in.guidance.data() + i * m_ : nullptr);
      else
        done_.push_back(r);
    }
    stats_.connected = in.connected;
    stats_.exited = in.exited;
    if (field_) field_->load(in);
  }

  StepStats step(std::uint32_t step, PhaseTimes& times) override {
    const Traffic before = comm_.traffic();
    // The pipeline of SPEC §3.2, as every engine runs it (engine/axon_step.hpp); the
    // signalling model is not decomposed (refused before a decomposed run starts).
    const AxonStepPlan plan{field_ != nullptr, false, stages_.steers_after_move(), scene_.cues.warmup_steps,
                            "migrate"};
    GrowthCounts c;
    axon_step(
        step, times, plan, [&](std::uint32_t field_step, PhaseTimes& t) { field_->advance(field_step, t); }, [] {},
        [&](std::uint32_t s) { stages_.steer(*field_, grow_.slots, grow_.arrays(), s); },
        [&](std::uint32_t s) { c = stages_.grow(grid_.view(), grow_.slots, grow_.arrays(), s); },
        [&](std::uint32_t) {
          migrate();
          std::vector<std::uint64_t> counts{c.connected, c.exited, grow_.size(), field_ ? field_->particles() : 0};
          comm_.allreduce(counts, Reduce::kSum);
          stats_.connected += counts[0];
          stats_.exited += counts[1];
          stats_.growing = counts[2];
          stats_.particles = counts[3];
        });
    stats_.step = step;
    ++report_.steps_run;
    const Traffic spent = comm_.traffic() - before;
    report_.steps.messages += spent.messages;
    report_.steps.message_bytes += spent.message_bytes;
    report_.steps.collectives += spent.collectives;
    report_.steps.collective_bytes += spent.collective_bytes;
    return stats_;
  }

  void tips(std::vector<Vec3>& out) override {
    out.clear();
    if (comm_.root()) out.resize(n_);
    gather<TipRecord>(
        [&](Bytes& b) {
          b.reserve((grow_.size() + done_.size()) * sizeof(TipRecord));
          for (std::size_t k = 0; k < grow_.size(); ++k) {
            const TipRecord t{grow_.tip[k], grow_.id[k]};
            append(b, &t, 1);
          }
          for (const AxonRecord& r : done_) {
            const TipRecord t{r.tip, r.id};
            append(b, &t, 1);
          }
        },
        [&](const TipRecord& t) { out[t.id] = t.tip; });
  }

  // Collective: every particle, in id order, on rank 0 (output frames).
  void particles(std::vector<Vec3>& pos, std::vector<std::uint16_t>& cue) override {
    pos.clear();
    cue.clear();
    if (field_) field_->snapshot(pos, cue);
  }

  // The engine's state goes into the gather as it is packed (the run's memory peak).
  void finish(NeuronState& out) override {
    std::fill(grow_.status.begin(), grow_.status.end(), AxonStatus::kMaxSteps);
    bool sized = false;  // rank 0 sizes the result once the engine's own arrays are freed
    gather_records(true, 0, [&](const AxonRecord& r, const double*) {
      if (!sized) out.resize(n_), sized = true;
      out.tip[r.id] = r.tip;
      out.length[r.id] = r.length;
      out.status[r.id] = r.status;
      out.steps[r.id] = r.steps;
      out.target[r.id] = r.target;
    });
  }

  // Rank 0 runs the host's graph analysis on the gathered result; the others hold none.
  bool analyze(const Scene&, GraphAnalysis&) override { return !comm_.root(); }

  std::size_t bytes() const override {
    return (field_ ? field_->bytes() : 0) + grid_.bytes() + grow_.bytes() + done_.capacity() * sizeof(AxonRecord);
  }
  std::string note() const override { return field_ ? field_->note() : std::string(); }

 private:
  // The growing axons of this block, by slot (structure of arrays, for AxonStages), with
  // their decision interval's sums (m per axon).
  struct Growing {
    explicit Growing(std::size_t m = 0) : m(m) {}
    std::size_t m;
    std::vector<std::uint32_t> id, steps, target, slots;
    std::vector<Vec3> tip, heading;
    std::vector<double> length, step_length, sums;
    std::vector<AxonStatus> status;
    std::size_t size() const { return id.size(); }
    std::size_t bytes() const { return id.capacity() * (4 * 4 + 2 * sizeof(Vec3) + 2 * 8 + 1) + sums.capacity() * 8; }
    void push(const AxonRecord& r, const double* s) {
      slots.push_back(static_cast<std::uint32_t>(id.size()));
      id.push_back(r.id), steps.push_back(r.steps), target.push_back(r.target);
      tip.push_back(r.tip), heading.push_back(r.heading);
      length.push_back(r.length), step_length.push_back(r.step_length);
      status.push_back(r.status);
      if (m) sums.insert(sums.end(), s, s + m);
    }
    void move(std::size_t to, std::size_t from) {
      id[to] = id[from], steps[to] = steps[from], target[to] = target[from];
      tip[to] = tip[from], heading[to] = heading[from];
      length[to] = length[from], step_length[to] = step_length[from];
      status[to] = status[from];
      if (m) std::copy_n(sums.data() + from * m, m, sums.data() + to * m);
    }
    void shrink() {
      for (auto* v : {&id, &steps, &target, &slots}) v->shrink_to_fit();
      tip.shrink_to_fit(), heading.shrink_to_fit(), length.shrink_to_fit(), step_length.shrink_to_fit();
      sums.shrink_to_fit(), status.shrink_to_fit();
    }
    void resize(std::size_t n) {  // slots stay 0..n-1
      for (auto* v : {&id, &steps, &target, &slots}) v->resize(n);
      tip.resize(n), heading.resize(n), length.resize(n), step_length.resize(n), status.resize(n);
      sums.resize(n * m);
    }
    AxonRecord record(std::size_t k) const {
      return {tip[k], heading[k], length[k], step_length[k], id[k], steps[k], target[k], status[k]};
    }
    const double* sums_of(std::size_t k) const { return m ? sums.data() + k * m : nullptr; }
    AxonArrays arrays() {
      AxonArrays a{id.data(), tip.data(), heading.data(), length.data(), step_length.data(), status.data(), steps.data(),
                   target.data()};
      a.sums = m ? sums.data() : nullptr;
      return a;
    }
  };

  // An axon whose tip lies here stays; the others go to their block's rank.
  void route(const AxonRecord& r, const double* sums, std::vector<Bytes>& out) {
    const int owner = d_.owner(r.tip);
    if (owner == rank_)
      grow_.push(r, sums);
    else
      send_to(owner, r, sums, out);
  }

  // After a step: finished axons are kept as records, migrants sent, the rest compacted
  // in place, in slot order.
  void migrate() {
    std::vector<Bytes> out(neighbours_.size());
    std::size_t w = 0;
    for (std::size_t k = 0; k < grow_.size(); ++k) {
      if (grow_.status[k] != AxonStatus::kGrowing) {
        done_.push_back(grow_.record(k));
        continue;
      }
      const int owner = d_.owner(grow_.tip[k]);
      if (owner != rank_) {
        send_to(owner, grow_.record(k), grow_.sums_of(k), out);
        continue;
      }
      if (w != k) grow_.move(w, k);
      ++w;
    }
    grow_.resize(w);
    if (grow_.id.capacity() > 1024 && 4 * w < grow_.id.capacity()) grow_.shrink();  // most have stopped growing
    receive(comm_.exchange(out));
  }

  void send_to(int owner, const AxonRecord& r, const double* sums, std::vector<Bytes>& out) {
    const int peer = peer_of_[static_cast<std::size_t>(owner)];
    if (peer < 0)  // cannot happen: a step is shorter than a block (decompose checks it)
      throw RunError("decomposed run: an axon moved past the neighbouring blocks in one step");
    append_axon(out[static_cast<std::size_t>(peer)], r, sums, m_);
    ++report_.migrated;
  }

  void receive(const std::vector<Bytes>& in) {
    for (const Bytes& from : in)
      for_each_axon(from, m_, [&](const AxonRecord& r, const double* sums) { grow_.push(r, sums); });
  }

  // Every rank's records, visited on rank 0 in rank order: `fill` packs this rank's.
  template <class T, class Fill, class Visit>
  void gather(Fill&& fill, Visit&& visit) {
    const Traffic before = comm_.traffic();
    Bytes bytes;
    fill(bytes);
    for (Bytes& from : comm_.gather(std::move(bytes))) {
      for_each_record<T>(from, visit);
      from = Bytes();
    }
    const Traffic spent = comm_.traffic() - before;
    report_.gathers.messages += spent.messages;
    report_.gathers.message_bytes += spent.message_bytes;
  }

  // Every axon's record and (m doubles) its sums, visited on rank 0 in rank order as
  // visit(record, sums); a stopped axon's sums are zero. `release`: the axons are freed as
  // they are packed (finish).
  template <class Visit>
  void gather_records(bool release, std::size_t m, Visit&& visit) {
    const Traffic before = comm_.traffic();
    Bytes b;
    b.reserve((grow_.size() + done_.size()) * (sizeof(AxonRecord) + m * sizeof(double)));
    for (const AxonRecord& r : done_) append_axon(b, r, zeros_.data(), m);
    if (release) done_ = {};
    for (std::size_t k = 0; k < grow_.size(); ++k) append_axon(b, grow_.record(k), grow_.sums_of(k), m);
    if (release) grow_ = Growing(m_);
    for (Bytes& from : comm_.gather(std::move(b))) {
      for_each_axon(from, m, visit);
      from = Bytes();
    }
    const Traffic spent = comm_.traffic() - before;
    report_.gathers.messages += spent.messages;
    report_.gathers.message_bytes += spent.message_bytes;
  }

  const Scene& scene_;
  const Decomposition& d_;
  Comm& comm_;
  int rank_;
  std::size_t n_;
  AxonStages stages_;
  bool modulated_;
  std::size_t m_;               // decision sums per axon
  std::vector<double> zeros_;   // m_ zeros: a new or stopped axon's sums
  std::unique_ptr<CueField> field_;  // null for direct guidance; decomposed particles and grid
  RankReport& report_;
  std::vector<int> neighbours_;
  std::vector<int> peer_of_;  // rank -> index in neighbours_, -1 when not adjacent
  CellGrid grid_;
  Growing grow_{m_};
  std::vector<AxonRecord> done_;  // connected or exited here
  StepStats stats_;
};

}  // namespace

std::unique_ptr<Engine> make_decomposed_engine(const Scene& scene, const Decomposition& d, Comm& comm,
                                               RankSomas somas, RankReport& report) {
  return std::make_unique<DecomposedEngine>(scene, d, comm, std::move(somas), report);
}

RankSomas rank_somas(const std::vector<Vec3>& all, const Decomposition& d, int rank) {
  RankSomas s;
  const Decomposition::Bounds block = d.bounds(rank);
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (!block.near(all[i], d.halo)) continue;
    s.id.push_back(static_cast<std::uint32_t>(i));
    s.pos.push_back(all[i]);
    s.owned.push_back(d.owner(all[i]) == rank);
  }
  return s;
}

}  // namespace axg::distributed

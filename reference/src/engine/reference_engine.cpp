// The reference engine: the per-step pipeline of SPEC §3.2 as TBB loops over core/
// functions. Each loop body writes only its own slot; counts are integer reductions.
#include <algorithm>
#include <stdexcept>

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "axonguide/engine/arbour_engine.hpp"
#include "axonguide/engine/axon_stages.hpp"
#include "axonguide/engine/axon_step.hpp"
#include "axonguide/engine/cell_grid.hpp"
#include "axonguide/engine/engine.hpp"
#include "axonguide/fields/fields.hpp"
#include "axonguide/model/growth.hpp"

namespace axg {

namespace {

using core::AxonStatus;

template <class T>
void release(std::vector<T>& v) {
  std::vector<T>().swap(v);
}

// out[ids[k]] = in[k]; frees `in`.
template <class T>
void scatter(const std::vector<std::uint32_t>& ids, std::vector<T>& in, std::vector<T>& out) {
  out.resize(in.size());
  tbb::parallel_for(std::size_t{0}, in.size(), [&](std::size_t k) { out[ids[k]] = in[k]; });
  release(in);
}

// Axon state is kept in "slot" order: slot k holds neuron somas_.ids[k], the order of the
// soma grid. Growing axons are visited in that order, so neighbouring slots look up
// neighbouring cells and the state arrays are read sequentially. Slot order changes
// only memory traffic: every axon computes the same pure function of its own state.
class ReferenceEngine final : public Engine {
 public:
  // Takes the placement's arrays: the somas become the soma grid's sorted copy and the
  // headings the slot-ordered ones, each released as soon as it is copied, so that a large
  // network holds one copy of each (the run's memory peak; docs/scaling.md §5). somas()
  // gives the id-ordered somas back.
  ReferenceEngine(const Scene& scene, Placement&& placement)
      : scene_(scene),
        stages_(scene),
        modulated_(stages_.own_step_lengths()),
        field_(make_reference_field(scene, stages_.cues())) {
    const std::size_t n = placement.soma.size();
    if (stages_.signalling()) soma_ = placement.soma;
    somas_ = build_cell_grid(soma_grid_geometry(scene), placement.soma);
    release(placement.soma);
    heading_.resize(n);
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t k) { heading_[k] = placement.heading[somas_.ids[k]]; });
    release(placement.heading);
    state_.resize(n);
    tbb::parallel_for(std::size_t{0}, n,
                      [&](std::size_t k) { state_.tip[k] = axon_start(somas_.pos[k], heading_[k], scene); });
    // Without cue fields no stage needs the list until seven in eight axons have stopped.
    every_slot_ = !field_;
    if (!every_slot_) {
      active_.resize(n);
      for (std::size_t k = 0; k < n; ++k) active_[k] = static_cast<std::uint32_t>(k);
    }
    if (modulated_) step_length_.assign(n, stages_.params().step_length);
    sums_.assign(n * stages_.sums_per_axon(), 0.0);
    if (stages_.signalling()) {
      signal_.assign(n * core::kSignalSpecies, 0.0);
      receptors_.assign(n, 0.0);
      inhibition_.assign(n, 0.0);
    }
  }

  // The fields' warm-up, then the signalling model's start: the cell bodies' receptors at
  // their steady state and every network at its steady state with the tip at its soma.
  void warm_up() override {
    if (!field_) return;
    PhaseTimes warmup;  // before the step loop: not part of any step's timings
    for (std::uint32_t s = 1; s <= scene_.cues.warmup_steps; ++s) field_->advance(s, warmup);
    if (stages_.signalling()) {
      stages_.soma_signals(*field_, soma_, receptors_.data(), inhibition_.data(), true);
      stages_.start_signals(*field_, soma_, active_, arrays());
    }
  }

  void save(EngineState& out) override {
    const std::vector<std::uint32_t>& ids = somas_.ids;
    const std::size_t n = ids.size();
    out.axons.resize(n);
    out.heading.resize(n);
    out.step_length.resize(modulated_ ? n : 0);
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t k) {
      const std::uint32_t i = ids[k];
      out.axons.tip[i] = state_.tip[k];
      out.axons.length[i] = state_.length[k];
      out.axons.status[i] = state_.status[k];
      out.axons.steps[i] = state_.steps[k];
      out.axons.target[i] = state_.target[k];
      out.heading[i] = heading_[k];
      if (modulated_) out.step_length[i] = step_length_[k];
    });
    out.signal.resize(signal_.size());
    tbb::parallel_for(std::size_t{0}, signal_.size() / core::kSignalSpecies, [&](std::size_t k) {
      std::copy_n(signal_.data() + k * core::kSignalSpecies, core::kSignalSpecies,
                  out.signal.data() + static_cast<std::size_t>(ids[k]) * core::kSignalSpecies);
    });
    out.receptors = receptors_;
    // The growing axons' sums (a stopped axon's are zero: every engine writes the same).
    const std::size_t m = stages_.sums_per_axon();
    out.guidance.assign(sums_.size(), 0.0);
    tbb::parallel_for(std::size_t{0}, m ? n : 0, [&](std::size_t k) {
      if (state_.status[k] == AxonStatus::kGrowing)
        std::copy_n(sums_.data() + k * m, m, out.guidance.data() + static_cast<std::size_t>(ids[k]) * m);
    });
    out.connected = stats_.connected;
    out.exited = stats_.exited;
    if (field_) field_->save(out);
  }

  // The growing list is every growing slot in slot order: what compaction leaves.
  void load(const EngineState& in) override {
    const std::vector<std::uint32_t>& ids = somas_.ids;
    tbb::parallel_for(std::size_t{0}, ids.size(), [&](std::size_t k) {
      const std::uint32_t i = ids[k];
      state_.tip[k] = in.axons.tip[i];
      state_.length[k] = in.axons.length[i];
      state_.status[k] = in.axons.status[i];
      state_.steps[k] = in.axons.steps[i];
      state_.target[k] = in.axons.target[i];
      heading_[k] = in.heading[i];
      if (modulated_) step_length_[k] = in.step_length[i];
    });
    if (stages_.signalling()) {
      if (in.signal.size() != signal_.size() || in.receptors.size() != receptors_.size())
        throw std::runtime_error("checkpoint: the signalling state does not match the scene's neurons");
      tbb::parallel_for(std::size_t{0}, ids.size(), [&](std::size_t k) {
        std::copy_n(in.signal.data() + static_cast<std::size_t>(ids[k]) * core::kSignalSpecies, core::kSignalSpecies,
                    signal_.data() + k * core::kSignalSpecies);
      });
      receptors_ = in.receptors;
      stages_.inhibition_from(receptors_.data(), inhibition_.data(), receptors_.size());
    }
    const std::size_t m = stages_.sums_per_axon();
    if (in.guidance.size() != sums_.size())
      throw std::runtime_error("checkpoint: the decision sums do not match the scene's neurons and cues");
    tbb::parallel_for(std::size_t{0}, m ? ids.size() : 0, [&](std::size_t k) {
      std::copy_n(in.guidance.data() + static_cast<std::size_t>(ids[k]) * m, m, sums_.data() + k * m);
    });
    active_.clear();
    every_slot_ = false;
    for (std::size_t k = 0; k < ids.size(); ++k)
      if (state_.status[k] == AxonStatus::kGrowing) active_.push_back(static_cast<std::uint32_t>(k));
    stats_.connected = in.connected;
    stats_.exited = in.exited;
    if (field_) field_->load(in);
  }

  // The pipeline of SPEC §3.2, as every engine runs it (engine/axon_step.hpp).
  StepStats step(std::uint32_t step, PhaseTimes& times) override {
    const AxonStepPlan plan{field_ != nullptr, stages_.signalling(), stages_.steers_after_move(),
                            scene_.cues.warmup_steps, "compact"};
    axon_step(
        step, times, plan, [&](std::uint32_t field_step, PhaseTimes& t) { field_->advance(field_step, t); },
        [&] { stages_.soma_signals(*field_, soma_, receptors_.data(), inhibition_.data(), false); },
        [&](std::uint32_t s) {
          const SignallingFailure failed = stages_.steer(*field_, active_, arrays(), s);
          if (failed.neuron != core::kNoNeuron) throw_signalling_failure(scene_, failed, s);
        },
        [&](std::uint32_t s) {
          const GrowthCounts c = stages_.grow(somas_.view(), slots(), arrays(), s);
          stats_.connected += c.connected;
          stats_.exited += c.exited;
        },
        [&](std::uint32_t) { compact_active(); });
    stats_.step = step;
    stats_.growing = growing_;
    stats_.particles = field_ ? field_->particles() : 0;
    return stats_;
  }

  void particles(std::vector<core::Vec3>& pos, std::vector<std::uint16_t>& cue) override {
    if (field_) field_->snapshot(pos, cue);
  }

  void tips(std::vector<core::Vec3>& out) override {
    out.resize(state_.size());
    tbb::parallel_for(std::size_t{0}, state_.size(), [&](std::size_t k) { out[somas_.ids[k]] = state_.tip[k]; });
  }

  // Scatters slot order back to id order one array at a time, releasing each engine
  // array as soon as it is copied (this is the run's memory peak); the somas first.
  void finish(NeuronState& out) override {
    if (every_slot_) {
      tbb::parallel_for(std::size_t{0}, state_.size(), [&](std::size_t k) {
        if (state_.status[k] == AxonStatus::kGrowing) state_.status[k] = AxonStatus::kMaxSteps;
      });
    } else {
      for (std::uint32_t k : active_) state_.status[k] = AxonStatus::kMaxSteps;
    }
    release(active_);
    release(heading_);
    release(step_length_);
    release(signal_);
    release(receptors_);
    release(inhibition_);
    release(sums_);
    release(soma_);
    const std::vector<std::uint32_t>& ids = somas_.ids;
    release(somas_.cell_start);
    scatter(ids, somas_.pos, finished_soma_);
    scatter(ids, state_.tip, out.tip);
    scatter(ids, state_.length, out.length);
    scatter(ids, state_.status, out.status);
    scatter(ids, state_.steps, out.steps);
    scatter(ids, state_.target, out.target);
    finished_ = true;
  }

  // The somas by id: a copy while the engine runs (checkpoints), its own after finish().
  void somas(std::vector<core::Vec3>& out) override {
    if (finished_) {
      out = std::move(finished_soma_);
      return;
    }
    out.resize(somas_.pos.size());
    tbb::parallel_for(std::size_t{0}, out.size(), [&](std::size_t k) { out[somas_.ids[k]] = somas_.pos[k]; });
  }

  std::string note() const override { return field_ ? field_->note() : std::string(); }

  std::size_t bytes() const override {
    return (field_ ? field_->bytes() : 0) + somas_.bytes() + active_.capacity() * 4 + heading_.capacity() * sizeof(core::Vec3) + step_length_.capacity() * 8 +
           (signal_.capacity() + receptors_.capacity() + inhibition_.capacity() + sums_.capacity()) * 8 +
           soma_.capacity() * sizeof(core::Vec3) +
           state_.size() * (sizeof(core::Vec3) + 8 + 1 + 4 + 4);
  }

 private:
  AxonArrays arrays() {
    return {somas_.ids.data(), state_.tip.data(), heading_.data(), state_.length.data(),
            modulated_ ? step_length_.data() : nullptr, state_.status.data(), state_.steps.data(),
            state_.target.data(), signal_.empty() ? nullptr : signal_.data(),
            inhibition_.empty() ? nullptr : inhibition_.data(), sums_.empty() ? nullptr : sums_.data()};
  }

  Slots slots() const { return every_slot_ ? Slots::all(state_.size()) : Slots(active_); }

  // Keeps the growing axons, in slot order; in every-slot mode, counts them and builds the
  // list once at most one in eight is left (the scan of every slot's status costs less
  // than the list's memory at the run's peak).
  void compact_active() {
    if (every_slot_) {
      growing_ = tbb::parallel_reduce(
          tbb::blocked_range<std::size_t>(0, state_.size()), std::size_t{0},
          [&](const tbb::blocked_range<std::size_t>& r, std::size_t c) {
            for (std::size_t k = r.begin(); k != r.end(); ++k) c += state_.status[k] == AxonStatus::kGrowing;
            return c;
          },
          [](std::size_t x, std::size_t y) { return x + y; });
      if (8 * growing_ > state_.size()) return;
      every_slot_ = false;
      active_.reserve(growing_);
      for (std::size_t k = 0; k < state_.size(); ++k)
        if (state_.status[k] == AxonStatus::kGrowing) active_.push_back(static_cast<std::uint32_t>(k));
      return;
    }
    active_.erase(std::remove_if(active_.begin(), active_.end(),
                                 [&](std::uint32_t k) { return state_.status[k] != AxonStatus::kGrowing; }),
                  active_.end());
    growing_ = active_.size();
  }

  const Scene& scene_;
  AxonStages stages_;
  bool modulated_;
  std::unique_ptr<CueField> field_;  // null for direct guidance: no cue work at all
  CellGrid somas_;
  NeuronState state_;  // in slot order
  std::vector<core::Vec3> heading_;
  std::vector<double> step_length_;  // per slot, with growth-rate modulation or signalling
  // The signalling model: each slot's network, the somas by id, their receptors and the
  // inhibitory signal the networks read (by id).
  std::vector<double> signal_, receptors_, inhibition_;
  std::vector<double> sums_;  // per slot: the open decision interval's sums (stages_.sums_per_axon())
  std::vector<core::Vec3> soma_;
  std::vector<std::uint32_t> active_;  // the growing slots, unless every_slot_
  bool every_slot_ = false;
  std::size_t growing_ = 0;
  std::vector<core::Vec3> finished_soma_;  // by id, from finish() until somas()
  bool finished_ = false;
  StepStats stats_;
};

}  // namespace

std::size_t reference_bytes_per_neuron() {
  // tip, heading, length, status, steps, target, active slot, sorted grid id + position,
  // about one cell start.
  return sizeof(core::Vec3) * 2 + 8 + 1 + 4 + 4 + 4 + 4 + sizeof(core::Vec3) + 4;
}

std::unique_ptr<Engine> make_reference_engine(const Scene& scene, Placement&& placement) {
  if (scene.arbours) return make_arbour_engine(scene, std::move(placement));
  return std::make_unique<ReferenceEngine>(scene, std::move(placement));
}

std::unique_ptr<Engine> make_reference_engine(const Scene& scene, const Placement& placement) {
  return make_reference_engine(scene, Placement(placement));
}

}  // namespace axg

// The reference engine: the per-step pipeline of SPEC §3.2 as TBB loops over core/
// functions. Each loop body writes only its own slot; counts are integer reductions.
#include <algorithm>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "axonguide/cell_grid.hpp"
#include "axonguide/core/growth.hpp"
#include "axonguide/engine.hpp"
#include "axonguide/growth_setup.hpp"

namespace axg {

namespace {

using core::AxonStatus;

class ReferenceEngine final : public Engine {
 public:
  ReferenceEngine(const Scene& scene, const Placement& placement)
      : scene_(scene), params_(growth_params(scene)) {
    const std::size_t n = placement.soma.size();
    somas_ = build_cell_grid(soma_grid_geometry(scene), placement.soma);
    state_.resize(n);
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
      state_.heading[i] = placement.heading[i];
      state_.tip[i] = axon_start(placement.soma[i], placement.heading[i], scene);
    });
    active_.resize(n);
    for (std::size_t i = 0; i < n; ++i) active_[i] = static_cast<std::uint32_t>(i);
  }

  StepStats step(std::uint32_t step, PhaseTimes& times) override {
    {
      ScopedPhase p(times, step, "grow");
      grow(step);
    }
    {
      ScopedPhase p(times, step, "compact");
      compact_active();
    }
    stats_.step = step;
    stats_.growing = active_.size();
    return stats_;
  }

  void tips(std::vector<core::Vec3>& out) override { out = state_.tip; }

  void finish(NeuronState& out) override {
    for (std::uint32_t i : active_) state_.status[i] = AxonStatus::kMaxSteps;
    out = state_;
  }

  std::size_t bytes() const override {
    return somas_.bytes() + active_.capacity() * 4 + state_.size() * reference_bytes_per_neuron();
  }

 private:
  // Stages 3-4: move every growing tip and test contact and bounds.
  void grow(std::uint32_t step) {
    const core::CellGridView somas = somas_.view();
    struct Counts {
      std::uint64_t connected = 0, exited = 0;
    };
    const Counts c = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, active_.size()), Counts{},
        [&](const tbb::blocked_range<std::size_t>& r, Counts acc) {
          for (std::size_t k = r.begin(); k != r.end(); ++k) {
            const std::uint32_t i = active_[k];
            const core::AxonStep s = core::grow_axon(i, state_.tip[i], state_.heading[i], params_, somas);
            state_.tip[i] = s.tip;
            state_.length[i] += s.advanced;
            state_.steps[i] = step;
            state_.status[i] = s.status;
            state_.target[i] = s.target;
            acc.connected += s.status == AxonStatus::kConnected;
            acc.exited += s.status == AxonStatus::kExited;
          }
          return acc;
        },
        [](Counts a, Counts b) { return Counts{a.connected + b.connected, a.exited + b.exited}; });
    stats_.connected += c.connected;
    stats_.exited += c.exited;
  }

  // Keeps the growing axons, in id order.
  void compact_active() {
    auto still = [&](std::uint32_t i) { return state_.status[i] == AxonStatus::kGrowing; };
    active_.erase(std::remove_if(active_.begin(), active_.end(), [&](std::uint32_t i) { return !still(i); }),
                  active_.end());
  }

  const Scene& scene_;
  core::GrowthParams params_;
  CellGrid somas_;
  NeuronState state_;
  std::vector<std::uint32_t> active_;
  StepStats stats_;
};

}  // namespace

std::size_t reference_bytes_per_neuron() {
  // tip, heading, length, status, steps, target, active slot, sorted grid id + position,
  // about one cell start.
  return sizeof(core::Vec3) * 2 + 8 + 1 + 4 + 4 + 4 + 4 + sizeof(core::Vec3) + 4;
}

std::unique_ptr<Engine> make_reference_engine(const Scene& scene, const Placement& placement) {
  return std::make_unique<ReferenceEngine>(scene, placement);
}

}  // namespace axg

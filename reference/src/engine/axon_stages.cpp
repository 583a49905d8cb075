#include "axonguide/axon_stages.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "axonguide/cue_setup.hpp"
#include "axonguide/fields.hpp"
#include "axonguide/growth_setup.hpp"

namespace axg {

AxonStages::AxonStages(const Scene& scene)
    : seed_(scene.seed),
      params_(growth_params(scene)),
      wander_(wander_params(scene)),
      modulated_(modulates_growth(scene)),
      cues_(make_cues(scene)),
      sense_(sense_params(scene)),
      steer_(steer_params(scene)) {}

void AxonStages::steer(const CueField& field, const std::vector<std::uint32_t>& slots, AxonArrays a,
                       std::uint32_t step) const {
  const int cue_count = static_cast<int>(cues_.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, slots.size()), [&](const tbb::blocked_range<std::size_t>& r) {
    core::CueSample samples[core::kMaxCues];
    core::Vec3 pull[core::kMaxCues];
    for (std::size_t s = r.begin(); s != r.end(); ++s) {
      const std::uint32_t k = slots[s];
      field.sample(a.tip[k], samples, pull);
      const core::Steered st =
          core::steer_axon(a.heading[k], samples, pull, cues_.data(), cue_count, sense_, steer_, seed_, a.id[k], step);
      a.heading[k] = st.heading;
      if (modulated_) a.step_length[k] = core::modulated_step(params_.step_length, st.along, steer_);
    }
  });
}

GrowthCounts AxonStages::grow(const core::CellGridView& somas, const std::vector<std::uint32_t>& slots, AxonArrays a,
                              std::uint32_t step) const {
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, slots.size()), GrowthCounts{},
      [&](const tbb::blocked_range<std::size_t>& r, GrowthCounts acc) {
        for (std::size_t s = r.begin(); s != r.end(); ++s) {
          const std::uint32_t k = slots[s];
          const std::uint32_t id = a.id[k];
          const double l = modulated_ ? a.step_length[k] : params_.step_length;
          const core::Vec3 h = a.heading[k];
          const core::AxonStep st = core::grow_axon(id, a.tip[k], h, l, params_, somas);
          // The heading's random walk for the next step (independent of the move, so the
          // two overlap in the pipeline).
          a.heading[k] = core::wander(h, l, !modulated_, wander_, seed_, id, step);
          a.tip[k] = st.tip;
          a.length[k] += st.advanced;
          a.steps[k] = step;
          a.status[k] = st.status;
          a.target[k] = st.target;
          acc.connected += st.status == core::AxonStatus::kConnected;
          acc.exited += st.status == core::AxonStatus::kExited;
        }
        return acc;
      },
      [](GrowthCounts x, GrowthCounts y) { return GrowthCounts{x.connected + y.connected, x.exited + y.exited}; });
}

}  // namespace axg

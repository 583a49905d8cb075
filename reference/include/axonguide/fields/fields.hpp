#pragma once
// The reference cue fields: particles, grid (explicit or implicit) and analytic. A
// scene pays only for what it uses: direct guidance creates no field at all, and the
// analytic field holds no particles and no grid.
#include <memory>
#include <string>
#include <vector>

#include "axonguide/core/cues.hpp"
#include "axonguide/scene/scene.hpp"
#include "axonguide/support/phase_times.hpp"

namespace axg {

struct EngineState;  // engine/state.hpp: what a checkpoint holds

class CueField {
 public:
  virtual ~CueField() = default;
  // Stage 1 of a step: emission, motion, death, grid rebuild (particles) or the
  // diffusion-decay solve (grid). Times its sub-stages into `times`.
  virtual void advance(std::uint32_t step, PhaseTimes& times) = 0;
  // Every cue's sample at x and, for vector_sum, its pull (sum of +-unit vectors toward
  // the source for particles; the unit gradient for grid and analytic fields).
  virtual void sample(core::Vec3 x, core::CueSample* samples, core::Vec3* pull) const = 0;
  virtual std::uint64_t particles() const { return 0; }
  // Positions and cue indices of the particles, in id order (empty for other fields).
  virtual void snapshot(std::vector<core::Vec3>& pos, std::vector<std::uint16_t>& cue) const {
    pos.clear();
    cue.clear();
  }
  virtual std::size_t bytes() const = 0;
  // The field's state for a checkpoint (EngineState's particle or grid part), and its
  // restoration; the exact fields hold none.
  virtual void save(EngineState&) const {}
  virtual void load(const EngineState&) {}
  // A line for the summary and the manifest (e.g. explicit sub-steps), or empty.
  virtual std::string note() const { return {}; }
};

// Throws InputError for a grid the scene forbids (explicit without sub-steps) or one
// over the machine's memory.
std::unique_ptr<CueField> make_reference_field(const Scene& scene, const std::vector<core::CueParams>& cues);

}  // namespace axg

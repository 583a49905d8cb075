#pragma once
// The particle field's stages over arrays in id order, shared by the one-process field
// (reference/src/fields/particle_field.cpp) and the field decomposed over ranks
// (distributed/src/particle_field.cpp), so that both run the same loops over the same
// core/ functions.
#include <cstdint>
#include <vector>

#include "axonguide/core/estimate.hpp"
#include "axonguide/core/particles.hpp"
#include "axonguide/model/estimate.hpp"
#include "axonguide/model/particles.hpp"
#include "axonguide/support/radix_sort.hpp"

namespace axg {

struct EngineState;

// A checkpoint's particles before a field takes them: every particle's source among the
// scene's `cues`, and a velocity for each when the motion is ballistic (read_checkpoint has
// checked that the arrays are of one length). std::runtime_error: the checkpoint does not fit.
void check_checkpoint_particles(const EngineState& in, std::size_t cues, bool ballistic);

// Motion and death of every particle (core::particle_step); keep[i] says whether i lives.
void move_particles(std::uint64_t seed, std::uint32_t step, const std::vector<core::CueParams>& cues,
                    const core::ParticleParams& params, bool ballistic, std::vector<core::Vec3>& pos,
                    std::vector<core::Vec3>& vel, const std::vector<std::uint64_t>& id,
                    const std::vector<std::uint16_t>& source, std::vector<std::uint8_t>& keep);

// The hashed grid over particles in id order: hash, stable sort by bucket (so by bucket,
// then id), bucket starts and the sorted copies the gathers read.
struct ParticleHashGrid {
  std::vector<std::uint32_t> keys, index, cell_start;
  std::vector<core::Vec3> sorted_pos;
  std::vector<std::uint16_t> sorted_source;
  SortScratch scratch;

  // cell_start sized for the view: the buckets when the grid is used, else one entry.
  void reserve_starts(const HashGeometry& g, bool used) { cell_start.assign(used ? g.buckets() + 1 : 1, 0); }
  void build(const HashGeometry& g, const std::vector<core::Vec3>& pos, const std::vector<std::uint16_t>& source);
  core::HashGridView view(const HashGeometry& g) const {
    return {g.origin, g.cell, g.dim, cell_start.data(), index.data(), sorted_pos.data(), sorted_source.data()};
  }
  std::size_t bytes() const {
    return keys.capacity() * 4 + index.capacity() * 4 + sorted_pos.capacity() * 24 + sorted_source.capacity() * 2 +
           cell_start.capacity() * 4;
  }
};

// Every particle's cloud-in-cell weights into the deposit of its cue and half: one task
// per (cue, half), each over the particles in id order (integer sums: any order gives
// the same bytes).
void deposit_particles(const core::EstimateSet& mesh, std::size_t cue_count, const std::vector<core::Vec3>& pos,
                       const std::vector<std::uint64_t>& id, const std::vector<std::uint16_t>& source,
                       std::vector<std::uint64_t>& deposit);

// The moving average of field step `step` (1-based, warm-up included); clears the deposits.
void fold_estimate(std::uint32_t step, const EstimateParams& params, std::vector<double>& estimate,
                   std::vector<std::uint64_t>& deposit);

}  // namespace axg

#pragma once
// The particle field's stages over arrays in id order, shared by the one-process field
// (reference/src/fields/particle_field.cpp) and the field decomposed over ranks
// (distributed/src/particle_field.cpp), so that both run the same loops over the same
// core/ functions, in the sequence that ParticleFieldStages::advance writes once.
#include <cstdint>
#include <vector>

#include "axonguide/fields/fields.hpp"
#include "axonguide/model/sensing.hpp"

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

// A step of the particle field (SPEC §3.3), written once for one process and for ranks:
//   emit -> move -> settle (compact the dead; over ranks: migrate, halo) -> hashed grid
//   (when gathers or collisions need it) -> collisions -> estimate deposits, their sum over
//   the ranks, and their fold.
// The state is this process's (or rank's) particles in id order; the hooks say what differs.
class ParticleFieldStages : public CueField {
 public:
  ParticleFieldStages(const Scene& scene, const std::vector<core::CueParams>& cues);
  void advance(std::uint32_t step, PhaseTimes& times) final;
  void sample(core::Vec3 x, core::CueSample* samples, core::Vec3* pull) const final;
  // This process's (or rank's) particles.
  std::uint64_t particles() const final { return pos_.size(); }

 protected:
  // Whether this process makes particle `id` (every process counts every emission, so ids
  // are the one-process ids; over ranks, the ranks near a source share its new particles).
  virtual bool makes(std::uint64_t /*id*/, std::size_t /*cue*/) const { return true; }
  // After the move: drop the dead (keep_) and, over ranks, hand the particles that left this
  // block to their owner and gather the halo when the grid needs it.
  virtual const char* settle_phase() const = 0;
  virtual void settle() = 0;
  // The hashed grid over the particles the gathers and collisions read.
  virtual void build_grid() = 0;
  // The soft-sphere response (a Jacobi step), then whatever must follow before the gathers.
  virtual void collide() = 0;
  // The estimate's deposits summed over the ranks (one process: nothing to do).
  virtual void reduce_deposits() {}
  // After every stage of the step.
  virtual void stepped() {}

  core::EstimateSet estimate_set() const {
    core::EstimateSet e = mesh_;
    e.c = estimate_.data();
    return e;
  }
  std::size_t state_bytes() const {
    return pos_.capacity() * 24 + vel_.capacity() * 24 + id_.capacity() * 8 + source_.capacity() * 2 +
           keep_.capacity() + grid_.bytes() + estimate_.capacity() * 8 + deposit_.capacity() * 8;
  }

  std::uint64_t seed_;
  std::vector<core::CueParams> cues_;
  core::SenseParams sense_;
  core::ParticleParams params_;
  HashGeometry geometry_;
  bool ballistic_;
  bool use_grid_;      // the hashed grid: collisions and the gathers of the particles within r
  bool use_estimate_;  // the estimate meshes
  core::EstimateSet mesh_;  // geometry (c unused)
  EstimateParams estimate_params_;
  std::uint64_t next_id_ = 0;
  // State, in id order.
  std::vector<core::Vec3> pos_, vel_;
  std::vector<std::uint64_t> id_;
  std::vector<std::uint16_t> source_;
  std::vector<std::uint8_t> keep_;
  ParticleHashGrid grid_;  // over what the gathers read
  // Estimate: 2 K meshes (cue-major, even half first) of averages and of this step's
  // deposits, whole on every rank.
  std::vector<double> estimate_;
  std::vector<std::uint64_t> deposit_;

 private:
  // Each cue emits floor(step Q) - floor((step-1) Q) particles at its position; ids are
  // consecutive in (cue, emission) order.
  void emit(std::uint32_t step);
};

}  // namespace axg

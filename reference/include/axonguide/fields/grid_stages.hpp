#pragma once
// A step of the grid field (SPEC §3.3; docs/methods.md §2.5), written once for one process
// and for ranks: per cue, explicit FTCS sub-steps to the stability limit (the source's share
// of the step, the ghost planes, the stencil) or implicit LOD sub-steps (the source's share,
// the x, y and z sweeps, the decay); then the ghost planes that sensing reads. A process
// owns the z-planes [z0, z1) of the n^3 grid and stores [g0, g1), ghosts included: one
// process owns them all and has no ghosts. Over ranks (distributed/src/grid_field.cpp) the
// hooks exchange the ghost planes and pipeline the z sweep along lines that cross the slabs;
// every owned node is computed by the one-process expression from the same values.
#include <cstdint>
#include <string>
#include <vector>

#include "axonguide/core/cues.hpp"
#include "axonguide/core/stencil.hpp"
#include "axonguide/fields/fields.hpp"
#include "axonguide/model/sensing.hpp"
#include "axonguide/model/stencil.hpp"

namespace axg {

class GridFieldStages : public CueField {
 public:
  // The planes this process owns and stores.
  struct Slab {
    int z0, z1;  // owned: [z0, z1)
    int g0, g1;  // stored: [g0, g1)
  };
  GridFieldStages(const Scene& scene, const std::vector<core::CueParams>& cues, Slab slab);

  void advance(std::uint32_t step, PhaseTimes& times) final;
  void sample(core::Vec3 x, core::CueSample* samples, core::Vec3* pull) const final;
  std::string note() const final { return note_; }

 protected:
  // `width` planes each side from the neighbours' owned planes (one process: none).
  virtual void exchange_ghosts(double* /*c*/, int /*width*/) {}
  // The z sweep of the implicit scheme over the slab's values c (one process: every line).
  virtual void sweep_z(double* c, double lambda);
  // After every cue's step: the ghost planes sensing reads (one process: none).
  virtual void stepped(std::uint32_t /*step*/, PhaseTimes& /*times*/) {}

  std::size_t local(int plane) const { return static_cast<std::size_t>(plane - slab_.g0) * plane_; }
  double* values(std::size_t k, int buffer) { return buffer_[buffer].data() + k * slab_values_; }
  std::size_t buffer_bytes() const { return (buffer_[0].size() + buffer_[1].size()) * sizeof(double); }

  std::vector<core::CueParams> cues_;
  core::SenseParams sense_;
  GridGeometry3 geometry_;
  GridScheme scheme_;
  bool reflecting_;
  double dt_, amount_;
  std::string note_;
  Slab slab_;
  std::size_t plane_, slab_values_;  // values per plane, per cue's slab
  // Two buffers of K slabs; cue k's current values are in buffer cur_[k] (the explicit
  // scheme alternates buffers per sub-step, and cues may need different numbers of
  // sub-steps). The implicit scheme works in place in buffer 0.
  std::vector<double> buffer_[2];
  std::vector<int> cur_;
  std::vector<std::uint32_t> substeps_;

 private:
  // a Q per step (the emission of this step) deposited around the source, by the owners of
  // its nodes' planes; `fraction` splits it across sub-steps.
  void add_source(std::size_t k, std::uint32_t step, double fraction);
  void explicit_step(std::size_t k, std::uint32_t step);
  void implicit_step(std::size_t k, std::uint32_t step);
};

}  // namespace axg

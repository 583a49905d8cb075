// The grid field on the CPU: one grid per cue; explicit FTCS sub-stepped to its stability
// limit, or implicit LOD with one Thomas solve per line. Parallel over nodes (explicit)
// or lines (implicit); each task writes only its own nodes.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <fmt/format.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "axonguide/core/stencil.hpp"
#include "axonguide/model/cues.hpp"
#include "axonguide/model/sensing.hpp"
#include "axonguide/model/stencil.hpp"
#include "axonguide/support/error.hpp"
#include "axonguide/fields/fields.hpp"
#include "axonguide/fields/lod.hpp"

namespace axg {

namespace {

// Storage: two buffers of K n^3 values; cue k's current values are in buffer cur_[k]
// (the explicit scheme alternates buffers per sub-step, and cues may need different
// numbers of sub-steps). The implicit scheme works in place in buffer 0.
class GridField final : public CueField {
 public:
  GridField(const Scene& scene, const std::vector<core::CueParams>& cues)
      : cues_(cues),
        geometry_(grid_field_geometry(scene)),
        scheme_(scene.cues.grid.scheme),
        reflecting_(scene.cues.grid.boundary == GridBoundary::kReflecting),
        dt_(scene.dt),
        amount_(scene.cues.particles.amount),
        note_(grid_field_note(scene, cues)) {
    const std::size_t nodes = geometry_.nodes();
    buffer_[0].assign(cues_.size() * nodes, 0.0);
    cur_.assign(cues_.size(), 0);
    if (scheme_ == GridScheme::kExplicit) buffer_[1].assign(cues_.size() * nodes, 0.0);
    for (const auto& cue : cues_) substeps_.push_back(grid_substeps(scene, cue));
  }

  void advance(std::uint32_t step, PhaseTimes& times) override {
    ScopedPhase p(times, step, scheme_ == GridScheme::kExplicit ? "grid.explicit" : "grid.implicit");
    for (std::size_t k = 0; k < cues_.size(); ++k) {
      if (scheme_ == GridScheme::kExplicit) explicit_step(k, step);
      else implicit_step(k, step);
    }
  }

  void sample(core::Vec3 x, core::CueSample* samples, core::Vec3* pull) const override {
    core::sample_grid_field(x, field_set(), cues_.data(), static_cast<int>(cues_.size()), samples, pull);
  }

  std::size_t bytes() const override { return (buffer_[0].size() + buffer_[1].size()) * sizeof(double); }

  std::string note() const override { return note_; }

  // Every cue's current values. The explicit scheme's other buffer is scratch: each
  // sub-step writes every node of it.
  void save(EngineState& out) const override {
    const std::size_t nodes = geometry_.nodes();
    out.grid.resize(cues_.size() * nodes);
    for (std::size_t k = 0; k < cues_.size(); ++k)
      std::copy_n(buffer_[cur_[k]].data() + k * nodes, nodes, out.grid.data() + k * nodes);
  }

  void load(const EngineState& in) override {
    const std::size_t values = cues_.size() * geometry_.nodes();
    if (in.grid.size() != values)
      throw std::runtime_error("checkpoint: the grid has " + std::to_string(in.grid.size()) +
                               " values, the scene needs " + std::to_string(values));
    std::copy(in.grid.begin(), in.grid.end(), buffer_[0].begin());
    cur_.assign(cues_.size(), 0);
  }

 private:
  double* values(std::size_t k, int buffer) { return buffer_[buffer].data() + k * geometry_.nodes(); }

  core::GridFieldSet field_set() const {
    core::GridFieldSet set{geometry_.origin, geometry_.h, geometry_.n, {}};
    for (std::size_t k = 0; k < cues_.size(); ++k)
      set.c[k] = buffer_[cur_[k]].data() + k * geometry_.nodes();
    return set;
  }

  // a Q per step (the emission of this step) deposited around the source; `fraction`
  // splits it across sub-steps.
  void add_source(std::size_t k, std::uint32_t step, double fraction) {
    const double total = amount_ * core::emitted_at(cues_[k].emission, step) * fraction;
    if (total == 0.0) return;
    const core::SourceDeposit d =
        core::source_deposit(cues_[k].position, total, geometry_.origin, geometry_.h, geometry_.n);
    double* c = values(k, cur_[k]);
    for (int m = 0; m < 8; ++m) c[d.index[m]] += d.value[m];
  }

  void explicit_step(std::size_t k, std::uint32_t step) {
    const std::uint32_t m = substeps_[k];
    const core::StencilParams s = stencil_params(geometry_, cues_[k], dt_ / m, reflecting_);
    const int n = geometry_.n;
    for (std::uint32_t sub = 0; sub < m; ++sub) {
      add_source(k, step, 1.0 / m);
      const double* in = values(k, cur_[k]);
      double* out = values(k, 1 - cur_[k]);
      tbb::parallel_for(tbb::blocked_range<int>(0, n * n), [&](const tbb::blocked_range<int>& r) {
        for (int row = r.begin(); row != r.end(); ++row) {
          const int zk = row / n, yj = row % n;
          for (int xi = 0; xi < n; ++xi) out[core::node_index(xi, yj, zk, n)] = core::ftcs_node(in, xi, yj, zk, s);
        }
      });
      cur_[k] = 1 - cur_[k];
    }
  }

  // Per sub-step of dt / m: its share of the source, the three LOD sweeps, then the
  // implicit decay c / (1 + k dt / m).
  void implicit_step(std::size_t k, std::uint32_t step) {
    const std::uint32_t m = substeps_[k];
    const core::StencilParams s = stencil_params(geometry_, cues_[k], dt_ / m, reflecting_);
    const double keep = 1.0 / (1.0 + s.decay_dt);
    double* c = values(k, 0);
    for (std::uint32_t sub = 0; sub < m; ++sub) {
      add_source(k, step, 1.0 / m);
      lod_sweeps(c, geometry_.n, s.lambda, reflecting_);
      tbb::parallel_for(std::size_t{0}, geometry_.nodes(), [&](std::size_t i) { c[i] = c[i] * keep; });
    }
  }

  std::vector<core::CueParams> cues_;
  GridGeometry3 geometry_;
  GridScheme scheme_;
  bool reflecting_;
  double dt_, amount_;
  std::string note_;
  std::vector<double> buffer_[2];
  std::vector<int> cur_;
  std::vector<std::uint32_t> substeps_;
};

// The analytic steady state and the imposed gradients: exact values, no state.
template <auto SampleField>
class ExactField final : public CueField {
 public:
  ExactField(const Scene& scene, const std::vector<core::CueParams>& cues) : cues_(cues), sense_(sense_params(scene)) {}
  void advance(std::uint32_t, PhaseTimes&) override {}
  void sample(core::Vec3 x, core::CueSample* samples, core::Vec3* pull) const override {
    SampleField(x, cues_.data(), static_cast<int>(cues_.size()), sense_, samples, pull);
  }
  std::size_t bytes() const override { return 0; }

 private:
  std::vector<core::CueParams> cues_;
  core::SenseParams sense_;
};

}  // namespace

std::unique_ptr<CueField> make_particle_field(const Scene& scene, const std::vector<core::CueParams>& cues);

std::unique_ptr<CueField> make_reference_field(const Scene& scene, const std::vector<core::CueParams>& cues) {
  if (!scene.uses_cues()) return nullptr;
  switch (scene.cues.field) {
    case FieldKind::kParticles:
      check_cue_fields(scene, cues);
      return make_particle_field(scene, cues);
    case FieldKind::kAnalytic: return std::make_unique<ExactField<core::sample_analytic_field>>(scene, cues);
    case FieldKind::kImposed: return std::make_unique<ExactField<core::sample_imposed_field>>(scene, cues);
    case FieldKind::kGrid:
      check_cue_fields(scene, cues);
      return std::make_unique<GridField>(scene, cues);
  }
  return nullptr;
}

}  // namespace axg

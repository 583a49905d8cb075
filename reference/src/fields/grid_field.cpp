// The grid field on the CPU: one grid per cue; explicit FTCS sub-stepped to its stability
// limit, or implicit LOD with one Thomas solve per line. Parallel over nodes (explicit)
// or lines (implicit); each task writes only its own nodes. The step's sequence is
// GridFieldStages' (grid_stages.hpp), which the field over ranks shares.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <fmt/format.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "axonguide/core/stencil.hpp"
#include "axonguide/engine/state.hpp"
#include "axonguide/model/cues.hpp"
#include "axonguide/model/sensing.hpp"
#include "axonguide/model/stencil.hpp"
#include "axonguide/support/error.hpp"
#include "axonguide/fields/fields.hpp"
#include "axonguide/fields/grid_stages.hpp"
#include "axonguide/fields/lod.hpp"

namespace axg {

GridFieldStages::GridFieldStages(const Scene& scene, const std::vector<core::CueParams>& cues, Slab slab)
    : cues_(cues),
      sense_(sense_params(scene)),
      geometry_(grid_field_geometry(scene)),
      scheme_(scene.cues.grid.scheme),
      reflecting_(scene.cues.grid.boundary == GridBoundary::kReflecting),
      dt_(scene.dt),
      amount_(scene.cues.particles.amount),
      note_(grid_field_note(scene, cues)),
      slab_(slab),
      plane_(static_cast<std::size_t>(geometry_.n) * static_cast<std::size_t>(geometry_.n)),
      slab_values_(static_cast<std::size_t>(slab.g1 - slab.g0) * plane_) {
  buffer_[0].assign(cues_.size() * slab_values_, 0.0);
  cur_.assign(cues_.size(), 0);
  if (scheme_ == GridScheme::kExplicit) buffer_[1].assign(cues_.size() * slab_values_, 0.0);
  for (const auto& cue : cues_) substeps_.push_back(grid_substeps(scene, cue));
}

void GridFieldStages::advance(std::uint32_t step, PhaseTimes& times) {
  {
    ScopedPhase p(times, step, scheme_ == GridScheme::kExplicit ? "grid.explicit" : "grid.implicit");
    for (std::size_t k = 0; k < cues_.size(); ++k) {
      if (scheme_ == GridScheme::kExplicit) explicit_step(k, step);
      else implicit_step(k, step);
    }
  }
  stepped(step, times);
}

void GridFieldStages::sample(core::Vec3 x, core::CueSample* samples, core::Vec3* pull) const {
  core::GridFieldSet set{geometry_.origin, geometry_.h, geometry_.n, {}, slab_.g0};
  for (std::size_t k = 0; k < cues_.size(); ++k) set.c[k] = buffer_[cur_[k]].data() + k * slab_values_;
  core::sample_grid_field(x, set, cues_.data(), static_cast<int>(cues_.size()), sense_, samples, pull);
}

void GridFieldStages::sweep_z(double* c, double lambda) { lod_sweep_z(c, geometry_.n, lambda, reflecting_); }

void GridFieldStages::add_source(std::size_t k, std::uint32_t step, double fraction) {
  const double total = amount_ * core::emitted_at(cues_[k].emission, step) * fraction;
  if (total == 0.0) return;
  const core::SourceDeposit d = core::source_deposit(cues_[k].position, total, geometry_.origin, geometry_.h, geometry_.n);
  double* c = values(k, cur_[k]);
  for (int m = 0; m < 8; ++m) {
    const int plane = static_cast<int>(d.index[m] / plane_);
    if (plane >= slab_.z0 && plane < slab_.z1) c[d.index[m] - static_cast<std::size_t>(slab_.g0) * plane_] += d.value[m];
  }
}

// Parallel over the slab's rows; each task writes only its own nodes.
void GridFieldStages::explicit_step(std::size_t k, std::uint32_t step) {
  const std::uint32_t m = substeps_[k];
  core::StencilParams s = stencil_params(geometry_, cues_[k], dt_ / m, reflecting_);
  s.k0 = slab_.g0;
  const int n = geometry_.n;
  for (std::uint32_t sub = 0; sub < m; ++sub) {
    add_source(k, step, 1.0 / m);
    exchange_ghosts(values(k, cur_[k]), 1);
    const double* in = values(k, cur_[k]);
    double* out = values(k, 1 - cur_[k]);
    const int rows = (slab_.z1 - slab_.z0) * n;
    tbb::parallel_for(tbb::blocked_range<int>(0, rows), [&](const tbb::blocked_range<int>& r) {
      for (int row = r.begin(); row != r.end(); ++row) {
        const int zk = slab_.z0 + row / n, yj = row % n;
        double* o = out + local(zk) + static_cast<std::size_t>(yj) * static_cast<std::size_t>(n);
        for (int xi = 0; xi < n; ++xi) o[xi] = core::ftcs_node(in, xi, yj, zk, s);
      }
    });
    cur_[k] = 1 - cur_[k];
  }
}

// Per sub-step of dt / m: its share of the source, the three LOD sweeps, then the implicit
// decay c / (1 + k dt / m). The x and y sweeps of the owned planes are local (whole lines).
void GridFieldStages::implicit_step(std::size_t k, std::uint32_t step) {
  const std::uint32_t m = substeps_[k];
  const core::StencilParams s = stencil_params(geometry_, cues_[k], dt_ / m, reflecting_);
  const double keep = 1.0 / (1.0 + s.decay_dt);
  double* c = values(k, 0);
  double* mine = c + local(slab_.z0);
  const int planes = slab_.z1 - slab_.z0;
  const std::size_t owned = static_cast<std::size_t>(planes) * plane_;
  for (std::uint32_t sub = 0; sub < m; ++sub) {
    add_source(k, step, 1.0 / m);
    lod_sweep_x(mine, geometry_.n, planes, s.lambda, reflecting_);
    lod_sweep_y(mine, geometry_.n, planes, s.lambda, reflecting_);
    sweep_z(c, s.lambda);
    tbb::parallel_for(std::size_t{0}, owned, [&](std::size_t i) { mine[i] = mine[i] * keep; });
  }
}

namespace {

// The grid field in one process: every plane.
class GridField final : public GridFieldStages {
 public:
  GridField(const Scene& scene, const std::vector<core::CueParams>& cues)
      : GridFieldStages(scene, cues, whole(scene)) {}

  std::size_t bytes() const override { return buffer_bytes(); }

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
  static Slab whole(const Scene& scene) {
    const int n = grid_field_geometry(scene).n;
    return {0, n, 0, n};
  }
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

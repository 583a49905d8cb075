// The growth kernels: axon start, sense-and-steer, move-and-contact, status tests.
// Part of the pipeline (../pipeline.inl); compiled once per build of it.
#pragma once

namespace axg::accel::AXG_ACCEL_NS {

struct InitAxons {
  const Vec3* d_soma;
  const Vec3* d_heading_by_id;
  const std::uint32_t* d_ids;  // slot -> neuron
  double soma_radius;
  Vec3* d_tip;
  Vec3* d_heading;
  AXG_HD void operator()(std::size_t k) const {
    const std::uint32_t i = d_ids[k];
    d_heading[k] = d_heading_by_id[i];
    d_tip[k] = core::axon_start(d_soma[i], d_heading_by_id[i], soma_radius);
  }
};

struct CueFields {
  core::FieldKind kind;
  const core::CueParams* d_cues;
  int cue_count;
  core::SenseParams sense;
  core::HashGridView particles;
  core::EstimateSet estimate;
  core::GridFieldSet grids;
};

struct Steer {
  const std::uint32_t* d_active;
  const std::uint32_t* d_ids;
  const Vec3* d_tip;
  Vec3* d_heading;
  double* d_step_length;  // null unless growth-rate modulation is on
  double step_length;     // l0
  CueFields fields;
  core::SteerParams params;
  std::uint64_t seed;
  std::uint32_t step;
  AXG_HD void operator()(std::size_t a) const {
    const std::uint32_t k = d_active[a];
    core::CueSample samples[core::kMaxCues];
    Vec3 pull[core::kMaxCues];
    const Vec3 x = d_tip[k];
    switch (fields.kind) {
      case core::FieldKind::kParticles:
        core::sample_particle_field(x, fields.particles, fields.estimate, fields.d_cues, fields.cue_count, fields.sense,
                                    samples, pull);
        break;
      case core::FieldKind::kGrid:
        core::sample_grid_field(x, fields.grids, fields.d_cues, fields.cue_count, samples, pull);
        break;
      case core::FieldKind::kAnalytic:
        core::sample_analytic_field(x, fields.d_cues, fields.cue_count, fields.sense, samples, pull);
        break;
      case core::FieldKind::kImposed:
        core::sample_imposed_field(x, fields.d_cues, fields.cue_count, fields.sense, samples, pull);
        break;
    }
    const core::Steered s = core::steer_axon(d_heading[k], samples, pull, fields.d_cues, fields.cue_count, fields.sense,
                                             params, seed, d_ids[k], step);
    d_heading[k] = s.heading;
    if (d_step_length) d_step_length[k] = core::modulated_step(step_length, s.along, params);
  }
};

struct Grow {
  const std::uint32_t* d_active;
  const std::uint32_t* d_ids;
  core::GrowthParams params;
  core::WanderParams wander;
  const double* d_step_length;  // null unless growth-rate modulation is on
  std::uint64_t seed;
  core::CellGridView somas;
  std::uint32_t step;
  Vec3* d_tip;
  Vec3* d_heading;
  double* d_length;
  core::AxonStatus* d_status;
  std::uint32_t* d_steps;
  std::uint32_t* d_target;
  AXG_HD void operator()(std::size_t a) const {
    const std::uint32_t k = d_active[a];
    const std::uint32_t id = d_ids[k];
    const double l = d_step_length ? d_step_length[k] : params.step_length;
    const Vec3 h = d_heading[k];
    const core::AxonStep s = core::grow_axon(id, d_tip[k], h, l, params, somas);
    d_heading[k] = core::wander(h, l, d_step_length == nullptr, wander, seed, id, step);
    d_tip[k] = s.tip;
    d_length[k] = d_length[k] + s.advanced;
    d_steps[k] = step;
    d_status[k] = s.status;
    d_target[k] = s.target;
  }
};

struct StatusIs {
  const core::AxonStatus* d_status;
  core::AxonStatus want;
  AXG_HD bool operator()(std::uint32_t k) const { return d_status[k] == want; }
};

struct MarkMaxSteps {
  const std::uint32_t* d_active;
  core::AxonStatus* d_status;
  AXG_HD void operator()(std::size_t a) const { d_status[d_active[a]] = core::AxonStatus::kMaxSteps; }
};

}  // namespace axg::accel::AXG_ACCEL_NS

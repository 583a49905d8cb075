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

// Every cue's sample and pull at x, from whichever field the scene has.
AXG_HDI void sample_fields(Vec3 x, const CueFields& fields, core::CueSample* samples, Vec3* pull) {
  switch (fields.kind) {
    case core::FieldKind::kParticles:
      core::sample_particle_field(x, fields.particles, fields.estimate, fields.d_cues, fields.cue_count, fields.sense,
                                  samples, pull);
      break;
    case core::FieldKind::kGrid:
      core::sample_grid_field(x, fields.grids, fields.d_cues, fields.cue_count, fields.sense, samples, pull);
      break;
    case core::FieldKind::kAnalytic:
      core::sample_analytic_field(x, fields.d_cues, fields.cue_count, fields.sense, samples, pull);
      break;
    case core::FieldKind::kImposed:
      core::sample_imposed_field(x, fields.d_cues, fields.cue_count, fields.sense, samples, pull);
      break;
  }
}

// The signalling model's inputs for the kernels (null pointers: not used).
struct SignalArrays {
  core::SignallingParams params;
  double* d_signal;            // kSignalSpecies per slot
  const double* d_inhibition;  // by neuron id
  double* d_receptors;         // by neuron id
  const Vec3* d_soma;          // by neuron id
  int cue;
  int substeps;
  int halvings;
  double dt;
  std::uint32_t* d_fail_id;    // the lowest failing neuron id (integer atomic minimum)
  std::uint16_t* d_fail_code;  // per slot: status << 8 | (species + 1) of a failed step
};

struct Steer {
  const std::uint32_t* d_active;
  const std::uint32_t* d_ids;
  const Vec3* d_tip;
  Vec3* d_heading;
  double* d_step_length;  // null unless axons have their own step lengths
  double* d_sums;         // sums_per_axon per slot: the decision interval's sums; null when intervals are one step
  std::size_t sums_per_axon;
  CueFields fields;
  core::GuideParams guide;  // its cues are fields.d_cues
  SignalArrays signal;      // d_signal null without the signalling model
  core::Decision decision;  // where this step stands in its interval
  AXG_HD void operator()(std::size_t a) const {
    const std::uint32_t k = d_active[a];
    core::CueSample samples[core::kMaxCues];
    Vec3 pull[core::kMaxCues];
    sample_fields(core::sample_point(guide, d_tip[k], d_heading[k], d_step_length ? d_step_length + k : nullptr), fields,
                  samples, pull);
    const core::GuidedAxon axon{d_heading + k, d_step_length ? d_step_length + k : nullptr,
                                signal.d_signal ? signal.d_signal + static_cast<std::size_t>(k) * core::kSignalSpecies : nullptr,
                                signal.d_signal ? signal.d_inhibition[d_ids[k]] : 0.0,
                                d_sums ? d_sums + k * sums_per_axon : nullptr};
    const core::SignallingStep g = core::guide_axon(guide, samples, pull, axon, d_ids[k], decision);
    if (g.status != core::StiffStatus::kOk) {
      signal.d_fail_code[k] = static_cast<std::uint16_t>((static_cast<int>(g.status) << 8) | (g.species + 1));
      atomic_min(signal.d_fail_id, d_ids[k]);
    }
  }
};

// The cell-body receptors of neuron i over a step (or at their steady state at the start).
struct SomaReceptors {
  CueFields fields;
  SignalArrays signal;
  bool start;
  AXG_HD void operator()(std::size_t i) const {
    core::CueSample samples[core::kMaxCues];
    Vec3 pull[core::kMaxCues];
    sample_fields(signal.d_soma[i], fields, samples, pull);
    const double c = samples[signal.cue].c;
    const core::SignallingParams& q = signal.params;
    signal.d_receptors[i] = start ? core::bound_receptors(q.It, q.kpI, q.kmI, c)
                                  : core::soma_receptor_step(q, signal.d_receptors[i], c, signal.dt);
  }
};

// One thread per population: its mean receptors over its ids in order, to each of them.
struct PopulationInhibition {
  const std::uint64_t* d_first;  // per population, then the end
  const double* d_receptors;
  double* d_inhibition;
  AXG_HD void operator()(std::size_t p) const {
    core::population_inhibition(d_receptors, d_first[p], d_first[p + 1], d_inhibition);
  }
};

// Every network at its steady state with the tip at its soma.
struct StartSignals {
  const std::uint32_t* d_ids;
  CueFields fields;
  SignalArrays signal;
  AXG_HD void operator()(std::size_t k) const {
    const std::uint32_t id = d_ids[k];
    core::CueSample samples[core::kMaxCues];
    Vec3 pull[core::kMaxCues];
    sample_fields(signal.d_soma[id], fields, samples, pull);
    core::signalling_steady_state(signal.params, samples[signal.cue].c, signal.d_inhibition[id],
                                  signal.d_signal + static_cast<std::size_t>(k) * core::kSignalSpecies);
  }
};

struct Grow {
  const std::uint32_t* d_active;
  const std::uint32_t* d_ids;
  core::GrowthParams params;
  core::WanderParams wander;
  const double* d_step_length;  // null unless axons have their own step lengths
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

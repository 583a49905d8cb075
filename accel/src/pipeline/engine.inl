// The accelerator's engine: the per-step pipeline of SPEC §3.2 as launches of the kernels
// of growth.inl, particles.inl and grid_field.inl, and the graph analysis of graph.inl.
// Part of the pipeline (../pipeline.inl); compiled once per build of it.
#pragma once

namespace axg::accel::AXG_ACCEL_NS {

class AccelEngine final : public Engine {
 public:
  AccelEngine(const Scene& scene, const Placement& placement)
      : scene_(scene),
        growth_(growth_params(scene)),
        wander_(wander_params(scene)),
        cues_host_(make_cues(scene)),
        sense_(sense_params(scene)),
        particle_params_(particle_params(scene)),
        hash_(particle_hash_geometry(scene)),
        grid_geometry_(grid_field_geometry(scene)),
        mesh_(estimate_geometry(scene)),
        estimate_params_(estimate_params(scene)),
        use_grid_(particle_grid_used(scene)),
        use_estimate_(particle_estimate_used(scene)) {
    build_somas(placement);
    if (scene.arbours) {
      start_arbours(placement);
      return;
    }
    const std::size_t n = placement.soma.size();
    tip_.resize(n);
    heading_.resize(n);
    length_.assign(n, 0.0);
    status_.assign(n, core::AxonStatus::kGrowing);
    steps_.assign(n, 0);
    target_.assign(n, core::kNoNeuron);
    {
      const dvec<Vec3> soma(placement.soma.begin(), placement.soma.end());
      const dvec<Vec3> heading(placement.heading.begin(), placement.heading.end());
      launch(n, InitAxons{raw(soma), raw(heading), raw(ids_), scene.neurons.soma_radius, raw(tip_), raw(heading_)});
    }
    active_.resize(n);
    thrust::sequence(active_.begin(), active_.end());
    active_next_.resize(n);
    modulated_ = modulates_growth(scene);
    if (modulated_ || scene.signalling()) step_length_.assign(n, growth_.step_length);
    if (scene.uses_cues()) init_field();
    guide_ = guide_params(scene, raw(cues_), static_cast<int>(cues_host_.size()));
    clock_ = decision_clock(scene);
    sums_per_axon_ = clock_.sums() && scene.uses_cues() ? cues_host_.size() * core::kSumsPerCue : 0;
    sums_.assign(n * sums_per_axon_, 0.0);
    if (scene.signalling()) {
      soma_by_id_.assign(placement.soma.begin(), placement.soma.end());
      signal_.assign(n * core::kSignalSpecies, 0.0);
      receptors_.assign(n, 0.0);
      inhibition_.assign(n, 0.0);
      fail_id_.assign(1, core::kNoNeuron);
      fail_code_.assign(n, 0);
      std::vector<std::uint64_t> first{0};
      if (scene.axons.signalling.population) {  // without populations, every neuron is the explant
        for (const Population& p : scene.neurons.populations) first.push_back(first.back() + p.count);
        if (scene.neurons.populations.empty()) first.push_back(n);
      }
      population_first_.assign(first.begin(), first.end());
    }
  }

  // The fields' warm-up, then the signalling model's start (as the reference engine).
  void warm_up() override {
    if (!scene_.uses_cues()) return;
    PhaseTimes warmup;  // before the step loop: not part of any step's timings
    for (std::uint32_t s = 1; s <= scene_.cues.warmup_steps; ++s) advance_field(s, warmup);
    if (scene_.signalling()) {
      soma_signals(true);
      launch(active_.size(), StartSignals{raw(ids_), fields(), signal_arrays()});
    }
  }

  void save(EngineState& out) override {
    if (arbours_) {
      const std::size_t n = soma_host_.size();
      out.axons.resize(n);
      out.heading.assign(n, Vec3{0, 0, 0});
      out.step_length.clear();
      out.connected = stats_.connected;
      out.exited = stats_.exited;
      out.guidance.clear();
      out.signal.clear();
      out.receptors.clear();
      std::vector<morphology::Arbour> a;
      arbours_->download(a, true);
      out.arbour.clear();
      morphology::append_arbours(a, out.arbour);
      save_field(out);
      return;
    }
    const std::size_t n = tip_.size();
    out.axons.resize(n);
    out.heading.resize(n);
    download_by_id(tip_, out.axons.tip);
    download_by_id(length_, out.axons.length);
    download_by_id(status_, out.axons.status);
    download_by_id(steps_, out.axons.steps);
    download_by_id(target_, out.axons.target);
    download_by_id(heading_, out.heading);
    out.step_length.resize(step_length_.size());
    if (!step_length_.empty()) download_by_id(step_length_, out.step_length);
    out.connected = stats_.connected;
    out.exited = stats_.exited;
    out.signal.clear();
    out.receptors.clear();
    if (scene_.signalling()) {
      // slot-major networks to id order
      std::vector<double> by_slot(signal_.size());
      thrust::copy(signal_.begin(), signal_.end(), by_slot.begin());
      std::vector<std::uint32_t> ids(ids_.size());
      thrust::copy(ids_.begin(), ids_.end(), ids.begin());
      out.signal.resize(by_slot.size());
      for (std::size_t k = 0; k < ids.size(); ++k)
        std::copy_n(by_slot.data() + k * core::kSignalSpecies, core::kSignalSpecies,
                    out.signal.data() + static_cast<std::size_t>(ids[k]) * core::kSignalSpecies);
      copy_out(receptors_, out.receptors);
    }
    // The growing axons' decision sums, slot-major to id order (a stopped axon's are zero).
    const std::size_t m = sums_per_axon_;
    out.guidance.assign(n * m, 0.0);
    if (m) {
      std::vector<double> by_slot(sums_.size());
      thrust::copy(sums_.begin(), sums_.end(), by_slot.begin());
      std::vector<std::uint32_t> ids(ids_.size());
      thrust::copy(ids_.begin(), ids_.end(), ids.begin());
      std::vector<core::AxonStatus> status(status_.size());
      thrust::copy(status_.begin(), status_.end(), status.begin());
      for (std::size_t k = 0; k < ids.size(); ++k)
        if (status[k] == core::AxonStatus::kGrowing)
          std::copy_n(by_slot.data() + k * m, m, out.guidance.data() + static_cast<std::size_t>(ids[k]) * m);
    }
    save_field(out);
  }

  // The cue field's state (particles, the estimate, the grid).
  void save_field(EngineState& out) {
    out.next_particle_id = next_id_;
    copy_out(pos_, out.particle_pos);
    copy_out(vel_, out.particle_vel);
    copy_out(id_, out.particle_id);
    copy_out(source_, out.particle_cue);
    out.grid.clear();
    if (use_estimate_) copy_out(estimate_, out.grid);
    if (scene_.uses_cues() && scene_.cues.field == FieldKind::kGrid) {
      const std::size_t nodes = grid_geometry_.nodes();
      out.grid.resize(cues_host_.size() * nodes);
      for (std::size_t k = 0; k < cues_host_.size(); ++k)
        thrust::copy(grid_[cur_[k]].begin() + static_cast<std::ptrdiff_t>(k * nodes),
                     grid_[cur_[k]].begin() + static_cast<std::ptrdiff_t>((k + 1) * nodes),
                     out.grid.begin() + static_cast<std::ptrdiff_t>(k * nodes));
    }
  }

  // The growing list is every growing slot in slot order (what compaction leaves); the
  // particle grid is rebuilt by the next step's advance before anything reads it.
  void load(const EngineState& in) override {
    if (arbours_) {
      std::vector<morphology::Arbour> a;
      try {
        a = morphology::read_arbours(in.arbour);
      } catch (const std::runtime_error& e) {
        throw RunError(e.what());
      }
      if (a.size() != soma_host_.size()) throw RunError("checkpoint: its arbours are not the scene's neurons");
      for (const morphology::Arbour& x : a)
        if (x.sums.size() != x.cones.size() * sums_per_cone_)
          throw RunError("checkpoint: its growth cones' decision sums are not the scene's");
      arbours_->upload(a);
      stats_.connected = in.connected;
      stats_.exited = in.exited;
      load_field(in);
      return;
    }
    upload_by_id(in.axons.tip, tip_);
    upload_by_id(in.axons.length, length_);
    upload_by_id(in.axons.status, status_);
    upload_by_id(in.axons.steps, steps_);
    upload_by_id(in.axons.target, target_);
    upload_by_id(in.heading, heading_);
    if (!step_length_.empty()) upload_by_id(in.step_length, step_length_);
    const std::size_t n = tip_.size();
    active_.resize(n);
    const auto end = thrust::copy_if(thrust::device, thrust::counting_iterator<std::uint32_t>(0),
                                     thrust::counting_iterator<std::uint32_t>(static_cast<std::uint32_t>(n)),
                                     active_.begin(), StatusIs{raw(status_), core::AxonStatus::kGrowing});
    active_.resize(static_cast<std::size_t>(end - active_.begin()));
    active_next_.resize(active_.capacity());
    stats_.connected = in.connected;
    stats_.exited = in.exited;
    if (in.guidance.size() != sums_.size())
      throw std::runtime_error("checkpoint: the decision sums do not match the scene's neurons and cues");
    if (sums_per_axon_) {
      const std::size_t m = sums_per_axon_;
      std::vector<std::uint32_t> ids(ids_.size());
      thrust::copy(ids_.begin(), ids_.end(), ids.begin());
      std::vector<double> by_slot(in.guidance.size());
      for (std::size_t k = 0; k < ids.size(); ++k)
        std::copy_n(in.guidance.data() + static_cast<std::size_t>(ids[k]) * m, m, by_slot.data() + k * m);
      sums_.assign(by_slot.begin(), by_slot.end());
    }
    if (scene_.signalling()) {
      if (in.signal.size() != signal_.size() || in.receptors.size() != receptors_.size())
        throw std::runtime_error("checkpoint: the signalling state does not match the scene's neurons");
      std::vector<std::uint32_t> ids(ids_.size());
      thrust::copy(ids_.begin(), ids_.end(), ids.begin());
      std::vector<double> by_slot(in.signal.size());
      for (std::size_t k = 0; k < ids.size(); ++k)
        std::copy_n(in.signal.data() + static_cast<std::size_t>(ids[k]) * core::kSignalSpecies, core::kSignalSpecies,
                    by_slot.data() + k * core::kSignalSpecies);
      signal_.assign(by_slot.begin(), by_slot.end());
      receptors_.assign(in.receptors.begin(), in.receptors.end());
      inhibition_from_receptors();
    }
    load_field(in);
  }

  // The particle grid is rebuilt by the next step's advance before anything reads it.
  void load_field(const EngineState& in) {
    next_id_ = in.next_particle_id;
    pos_.assign(in.particle_pos.begin(), in.particle_pos.end());
    vel_.assign(in.particle_vel.begin(), in.particle_vel.end());
    id_.assign(in.particle_id.begin(), in.particle_id.end());
    source_.assign(in.particle_cue.begin(), in.particle_cue.end());
    if (use_estimate_) {
      if (in.grid.size() != estimate_.size())
        throw std::runtime_error("checkpoint: the particle estimate has " + std::to_string(in.grid.size()) +
                                 " values, the scene needs " + std::to_string(estimate_.size()));
      thrust::copy(in.grid.begin(), in.grid.end(), estimate_.begin());
    } else if (!in.grid.empty()) {
      thrust::copy(in.grid.begin(), in.grid.end(), grid_[0].begin());
      cur_.assign(cues_host_.size(), 0);
    }
  }

  void steer(std::uint32_t step) {
    launch(active_.size(), Steer{raw(active_), raw(ids_), raw(tip_), raw(heading_), step_lengths(),
                                 sums_.empty() ? nullptr : raw(sums_), sums_per_axon_, fields(), guide_,
                                 signal_arrays(), clock_.at(step)});
    if (scene_.signalling()) check_signalling(step);
  }

  // The pipeline of SPEC §3.2, as every engine runs it (engine/axon_step.hpp).
  StepStats step(std::uint32_t step, PhaseTimes& times) override {
    if (arbours_) return step_arbours(step, times);
    const AxonStepPlan plan{scene_.uses_cues(), scene_.signalling(), guide_.after_move, scene_.cues.warmup_steps,
                            "compact"};
    axon_step(
        step, times, plan, [&](std::uint32_t field_step, PhaseTimes& t) { advance_field(field_step, t); },
        [&] { soma_signals(false); }, [&](std::uint32_t s) { this->steer(s); },
        [&](std::uint32_t s) {
          launch(active_.size(), Grow{raw(active_), raw(ids_), growth_, wander_, step_lengths(), scene_.seed,
                                      somas_view(), s, raw(tip_), raw(heading_), raw(length_), raw(status_),
                                      raw(steps_), raw(target_)});
        },
        [&](std::uint32_t) {
          stats_.connected += static_cast<std::uint64_t>(thrust::count_if(
              thrust::device, active_.begin(), active_.end(), StatusIs{raw(status_), core::AxonStatus::kConnected}));
          stats_.exited += static_cast<std::uint64_t>(thrust::count_if(
              thrust::device, active_.begin(), active_.end(), StatusIs{raw(status_), core::AxonStatus::kExited}));
          const auto end = thrust::copy_if(thrust::device, active_.begin(), active_.end(), active_next_.begin(),
                                           StatusIs{raw(status_), core::AxonStatus::kGrowing});
          active_next_.resize(static_cast<std::size_t>(end - active_next_.begin()));
          active_.swap(active_next_);
          active_next_.resize(active_.capacity());
        });
    stats_.step = step;
    stats_.growing = active_.size();
    stats_.particles = pos_.size();
    return stats_;
  }

  void particles(std::vector<Vec3>& pos, std::vector<std::uint16_t>& cue) override {
    pos.resize(pos_.size());
    cue.resize(source_.size());
    thrust::copy(pos_.begin(), pos_.end(), pos.begin());
    thrust::copy(source_.begin(), source_.end(), cue.begin());
  }

  void tips(std::vector<Vec3>& out) override {
    if (arbours_) {
      std::vector<morphology::Arbour> a;
      arbours_->download(a, false);
      out.resize(a.size());
      for (std::size_t i = 0; i < a.size(); ++i) out[i] = morphology::summarize(a[i], soma_host_[i]).farthest;
      return;
    }
    dvec<Vec3> by_id(tip_.size());
    launch(tip_.size(), ScatterBy<Vec3>{raw(tip_), raw(ids_), raw(by_id)});
    out.resize(tip_.size());
    thrust::copy(by_id.begin(), by_id.end(), out.begin());
  }

  void finish(NeuronState& out) override {
    if (arbours_) {
      std::vector<morphology::Arbour> a;
      arbours_->download(a, false);
      out.resize(a.size());
      for (std::size_t i = 0; i < a.size(); ++i) {
        const morphology::ArbourSummary s = morphology::summarize(a[i], soma_host_[i]);
        out.tip[i] = s.farthest;
        out.length[i] = s.axon_length;
        out.status[i] = s.growing ? core::AxonStatus::kMaxSteps : core::AxonStatus::kExited;
        out.steps[i] = s.last_step;
      }
      return;
    }
    launch(active_.size(), MarkMaxSteps{raw(active_), raw(status_)});
    const std::size_t n = tip_.size();
    out.resize(n);
    download_by_id(tip_, out.tip);
    download_by_id(length_, out.length);
    download_by_id(status_, out.status);
    download_by_id(steps_, out.steps);
    target_by_id_.resize(n);
    launch(n, ScatterBy<std::uint32_t>{raw(target_), raw(ids_), raw(target_by_id_)});
    thrust::copy(target_by_id_.begin(), target_by_id_.end(), out.target.begin());
  }

  // Edges from the per-axon slots: compacted (ascending source id), then CSR offsets as
  // the cell starts of the sorted sources; BFS and components on the device.
  bool analyze(const Scene& scene, GraphAnalysis& a) override {
    if (arbours_) return false;  // the connections are the synapses', found on the host
    const std::size_t n = tip_.size();
    dvec<std::uint32_t> source(n);
    const auto end = thrust::copy_if(thrust::device, thrust::counting_iterator<std::uint32_t>(0),
                                     thrust::counting_iterator<std::uint32_t>(static_cast<std::uint32_t>(n)),
                                     source.begin(), EdgeFlags{raw(target_by_id_)});
    source.resize(static_cast<std::size_t>(end - source.begin()));
    dvec<std::uint32_t> target(source.size()), offsets;
    launch(source.size(), EdgeTargets{raw(source), raw(target_by_id_), raw(target)});
    // Sources are already ascending (out-degree <= 1); the stable sort keeps the general
    // construction (and costs one pass on sorted keys).
    dvec<std::uint32_t> sorted_source = source;
    thrust::stable_sort_by_key(thrust::device, sorted_source.begin(), sorted_source.end(), target.begin());
    offsets.resize(n + 1);
    launch(sorted_source.size() + 1,
           FillCellStarts{raw(sorted_source), sorted_source.size(), static_cast<std::uint32_t>(n), raw(offsets)});
    a.out.offsets.resize(n + 1);
    a.out.targets.resize(target.size());
    thrust::copy(offsets.begin(), offsets.end(), a.out.offsets.begin());
    thrust::copy(target.begin(), target.end(), a.out.targets.begin());
    for (std::size_t v = 0; v < n; ++v)
      a.out.max_degree = std::max(a.out.max_degree, a.out.offsets[v + 1] - a.out.offsets[v]);
    if (!scene.analysis.bfs_sources.empty()) {
      const std::vector<std::uint32_t> sources(scene.analysis.bfs_sources.begin(), scene.analysis.bfs_sources.end());
      DeviceCsr g(std::move(offsets), dvec<std::uint32_t>(target));
      a.bfs = bfs_queue_device(g, sources);
    }
    if (scene.analysis.components) {
      a.component = components_device(sorted_source, target, n);
      summarize_components(a);
    }
    return true;
  }

  void arbours(std::vector<morphology::Arbour>& out) override {
    if (!arbours_) return Engine::arbours(out);
    arbours_->download(out, false);
  }

  void somas(std::vector<Vec3>& out) override {
    if (!arbours_) return Engine::somas(out);
    out = soma_host_;
  }

  std::size_t bytes() const override {
    if (arbours_) return arbours_->bytes() + soma_start_.size() * 4 + soma_pos_.size() * 24 + ids_.size() * 4 +
                         pos_.capacity() * (24 + 8 + 2 + 1) + vel_.capacity() * 24 + grid_[0].size() * 8 +
                         grid_[1].size() * 8;
    const std::size_t n = tip_.size();
    return n * (4 + 24 + 24 + 24 + 8 + 1 + 4 + 4 + 4 + 4) + step_length_.size() * 8 + soma_start_.size() * 4 +
           pos_.capacity() * (24 + 8 + 2 + 1) + vel_.capacity() * 24 + grid_[0].size() * 8 + grid_[1].size() * 8;
  }

  std::string note() const override { return grid_field_note(scene_, cues_host_); }

 private:
  // Arbours: the stems at birth drawn on the host (the reference's start_arbour), then the
  // pools on the device.
  void start_arbours(const Placement& placement) {
    arbour_params_ = arbour_params(scene_);
    soma_host_.assign(placement.soma.begin(), placement.soma.end());
    soma_by_id_.assign(placement.soma.begin(), placement.soma.end());
    restarts_ = arbours_restart(arbour_params_);
    if (scene_.uses_cues()) init_field();
    guide_ = guide_params(scene_, raw(cues_), static_cast<int>(cues_host_.size()));
    clock_ = decision_clock(scene_);
    sums_per_cone_ = clock_.sums() && scene_.uses_cues() ? cues_host_.size() * core::kSumsPerCue : 0;
    const ArbourContext ctx = arbour_context();
    std::vector<morphology::Arbour> a(soma_host_.size());
    for (std::size_t i = 0; i < a.size(); ++i) start_arbour(ctx, static_cast<std::uint32_t>(i), soma_host_[i], a[i]);
    arbours_ = std::make_unique<ArbourPools>(static_cast<std::uint32_t>(sums_per_cone_));
    arbours_->upload(a);
  }

  // The kernels set the guide themselves (StepArbours).
  ArbourContext arbour_context() const {
    return axg::arbour_context(scene_, arbour_params_, growth_, somas_view(), nullptr, sums_per_cone_);
  }

  StepStats step_arbours(std::uint32_t step, PhaseTimes& times) {
    const bool steers = scene_.uses_cues();
    if (steers) advance_field(scene_.cues.warmup_steps + step, times);
    ScopedPhase phase(times, step, "grow");
    morphology::ArbourStepContext ctx = arbour_context().step;
    if (steers) ctx.decision = clock_.at(step);
    const ArbourPools::StepCounts c =
        arbours_->step(ctx, guide_, steers, FieldSampler{steers ? fields() : CueFields{}}, soma_by_id_, step, restarts_);
    stats_.step = step;
    stats_.growing = c.growing_neurons;
    stats_.connected += c.soma;
    stats_.exited += c.exited;
    stats_.particles = pos_.size();
    return stats_;
  }

  template <class T>
  void download_by_id(dvec<T>& by_slot, std::vector<T>& out) {
    dvec<T> by_id(by_slot.size());
    launch(by_slot.size(), ScatterBy<T>{raw(by_slot), raw(ids_), raw(by_id)});
    thrust::copy(by_id.begin(), by_id.end(), out.begin());
  }

  template <class T>
  void upload_by_id(const std::vector<T>& by_id, dvec<T>& by_slot) {
    const dvec<T> d_in(by_id.begin(), by_id.end());
    launch(by_slot.size(), GatherBy<T>{raw(d_in), raw(ids_), raw(by_slot)});
  }

  template <class T>
  static void copy_out(const dvec<T>& in, std::vector<T>& out) {
    out.resize(in.size());
    thrust::copy(in.begin(), in.end(), out.begin());
  }

  void build_somas(const Placement& placement) {
    const GridGeometry g = soma_grid_geometry(scene_);
    soma_geometry_ = g;
    const std::size_t n = placement.soma.size();
    const dvec<Vec3> pos(placement.soma.begin(), placement.soma.end());
    dvec<std::uint32_t> keys(n);
    ids_.resize(n);
    const core::CellGridView geometry{g.origin, g.cell, g.nx, g.ny, g.nz, nullptr, nullptr, nullptr};
    launch(n, SomaKeys{raw(pos), geometry, raw(keys), raw(ids_)});
    sort_and_find_starts(keys, ids_, g.cells(), soma_start_);
    soma_pos_.resize(n);
    launch(n, GatherBy<Vec3>{raw(pos), raw(ids_), raw(soma_pos_)});
  }

  double* step_lengths() { return step_length_.empty() ? nullptr : raw(step_length_); }

  SignalArrays signal_arrays() {
    SignalArrays a{};
    if (!scene_.signalling()) return a;
    a.params = guide_.signal;
    a.d_signal = raw(signal_);
    a.d_inhibition = raw(inhibition_);
    a.d_receptors = raw(receptors_);
    a.d_soma = raw(soma_by_id_);
    a.cue = static_cast<int>(scene_.axons.signalling.cue);
    a.substeps = static_cast<int>(scene_.axons.signalling.substeps);
    a.halvings = static_cast<int>(scene_.axons.signalling.halvings);
    a.dt = scene_.dt;
    a.d_fail_id = raw(fail_id_);
    a.d_fail_code = raw(fail_code_);
    return a;
  }

  // The inhibitory signal from the receptors: each population's mean, or each neuron's own.
  void inhibition_from_receptors() {
    if (population_first_.size() > 1)
      launch(population_first_.size() - 1, PopulationInhibition{raw(population_first_), raw(receptors_), raw(inhibition_)});
    else
      thrust::copy(receptors_.begin(), receptors_.end(), inhibition_.begin());
  }

  void soma_signals(bool start) {
    launch(receptors_.size(), SomaReceptors{fields(), signal_arrays(), start});
    inhibition_from_receptors();
  }

  // A failed signalling step: the lowest failing neuron id, then its slot's code.
  void check_signalling(std::uint32_t step) {
    const std::uint32_t id = fail_id_[0];
    if (id == core::kNoNeuron) return;
    std::vector<std::uint32_t> ids(ids_.size());
    thrust::copy(ids_.begin(), ids_.end(), ids.begin());
    const std::size_t k = static_cast<std::size_t>(std::find(ids.begin(), ids.end(), id) - ids.begin());
    const std::uint16_t code = fail_code_[k];
    SignallingFailure f;
    f.neuron = id;
    f.status = static_cast<core::StiffStatus>(code >> 8);
    f.species = (code & 0xff) - 1;
    throw_signalling_failure(scene_, f, step);
  }

  core::CellGridView somas_view() const {
    const GridGeometry& g = soma_geometry_;
    return {g.origin, g.cell, g.nx, g.ny, g.nz, raw(soma_start_), raw(ids_), raw(soma_pos_)};
  }

  void init_field() {
    check_cue_fields(scene_, cues_host_);
    cues_.assign(cues_host_.begin(), cues_host_.end());
    if (scene_.cues.field == FieldKind::kParticles) {
      particle_start_.assign(use_grid_ ? hash_.buckets() + 1 : 1, 0);
      if (use_estimate_) {
        estimate_.assign(2 * cues_host_.size() * mesh_.nodes, 0.0);
        deposit_.assign(estimate_.size(), 0);
      }
    } else if (scene_.cues.field == FieldKind::kGrid) {
      const std::size_t nodes = grid_geometry_.nodes();
      grid_[0].assign(cues_host_.size() * nodes, 0.0);
      cur_.assign(cues_host_.size(), 0);
      for (const auto& cue : cues_host_) substeps_.push_back(grid_substeps(scene_, cue));
      if (scene_.cues.grid.scheme == GridScheme::kExplicit) {
        grid_[1].assign(cues_host_.size() * nodes, 0.0);
      } else {
        lod_cp_.resize(nodes);
        lod_dp_.resize(nodes);
      }
    }
  }

  CueFields fields() {
    CueFields f{};
    f.kind = scene_.cues.field;
    f.d_cues = raw(cues_);
    f.cue_count = static_cast<int>(cues_host_.size());
    f.sense = sense_;
    f.particles = particle_view();
    f.estimate = mesh_;
    f.estimate.c = raw(estimate_);
    f.grids = grid_set();
    return f;
  }

  core::HashGridView particle_view() {
    return {hash_.origin, hash_.cell, hash_.dim, raw(particle_start_), raw(particle_index_), raw(sorted_pos_),
            raw(sorted_source_)};
  }

  core::GridFieldSet grid_set() {
    core::GridFieldSet set{grid_geometry_.origin, grid_geometry_.h, grid_geometry_.n, {}};
    for (std::size_t k = 0; k < cur_.size(); ++k) set.c[k] = raw(grid_[cur_[k]]) + k * grid_geometry_.nodes();
    return set;
  }

  void advance_field(std::uint32_t step, PhaseTimes& times) {
    switch (scene_.cues.field) {
      case FieldKind::kParticles: advance_particles(step, times); break;
      case FieldKind::kGrid: {
        ScopedPhase p(times, step,
                      scene_.cues.grid.scheme == GridScheme::kExplicit ? "grid.explicit" : "grid.implicit");
        for (std::size_t k = 0; k < cues_host_.size(); ++k) {
          if (scene_.cues.grid.scheme == GridScheme::kExplicit) explicit_step(k, step);
          else implicit_step(k, step);
        }
        break;
      }
      case FieldKind::kAnalytic:
      case FieldKind::kImposed: break;
    }
  }

  void advance_particles(std::uint32_t step, PhaseTimes& times) {
    const bool ballistic = scene_.cues.particles.motion == Motion::kBallistic;
    {
      ScopedPhase p(times, step, "particles.emit");
      std::vector<std::uint32_t> offsets(cues_host_.size() + 1, 0);
      for (std::size_t k = 0; k < cues_host_.size(); ++k)
        offsets[k + 1] = offsets[k] + core::emitted_at(cues_host_[k].emission, step);
      const std::uint32_t emitted = offsets.back();
      if (emitted > 0) {
        const std::size_t first = pos_.size();
        pos_.resize(first + emitted);
        id_.resize(first + emitted);
        source_.resize(first + emitted);
        if (ballistic) vel_.resize(first + emitted);
        const dvec<std::uint32_t> d_offsets(offsets.begin(), offsets.end());
        launch(emitted, EmitParticles{next_id_, first, raw(d_offsets), static_cast<int>(cues_host_.size()), raw(cues_),
                                      ballistic, particle_params_, scene_.seed, step, raw(pos_), raw(vel_), raw(id_),
                                      raw(source_)});
        next_id_ += emitted;
      }
    }
    {
      ScopedPhase p(times, step, "particles.move");
      keep_.resize(pos_.size());
      launch(pos_.size(), MoveParticles{raw(id_), raw(source_), raw(cues_), particle_params_, ballistic, scene_.seed,
                                        step, raw(pos_), raw(vel_), raw(keep_)});
    }
    {
      ScopedPhase p(times, step, "particles.compact");
      compact_particles(ballistic);
    }
    if (use_grid_) {
      ScopedPhase p(times, step, "particles.grid");
      build_particle_grid();
    }
    if (particle_params_.collisions) {
      ScopedPhase p(times, step, "particles.collide");
      launch(pos_.size(), Collide{particle_view(), particle_params_, ballistic, raw(pos_), raw(vel_)});
      build_particle_grid();
    }
    if (use_estimate_) {
      ScopedPhase p(times, step, "particles.estimate");
      launch(pos_.size(), DepositParticles{raw(pos_), raw(id_), raw(source_), mesh_, raw(deposit_)});
      launch(estimate_.size(),
             FoldEstimate{core::estimate_fold(step, estimate_params_.beta, estimate_params_.scale), raw(estimate_),
                          raw(deposit_)});
    }
  }

  void compact_particles(bool ballistic) {
    const std::size_t n = pos_.size();
    const std::size_t kept = static_cast<std::size_t>(thrust::count_if(thrust::device, keep_.begin(), keep_.end(), IsKept{}));
    if (kept == n) return;
    auto compact = [&](auto& v, auto& scratch) {
      scratch.resize(kept);
      thrust::copy_if(thrust::device, v.begin(), v.end(), keep_.begin(), scratch.begin(), IsKept{});
      v.swap(scratch);
    };
    compact(pos_, pos_scratch_);
    compact(id_, id_scratch_);
    compact(source_, source_scratch_);
    if (ballistic) compact(vel_, vel_scratch_);
  }

  void build_particle_grid() {
    const std::size_t n = pos_.size();
    particle_keys_.resize(n);
    particle_index_.resize(n);
    const core::HashGridView geometry{hash_.origin, hash_.cell, hash_.dim, nullptr, nullptr, nullptr, nullptr};
    launch(n, ParticleKeys{raw(pos_), geometry, raw(particle_keys_), raw(particle_index_)});
    sort_and_find_starts(particle_keys_, particle_index_, static_cast<std::uint32_t>(hash_.buckets()), particle_start_);
    sorted_pos_.resize(n);
    sorted_source_.resize(n);
    launch(n, GatherParticles{raw(pos_), raw(source_), raw(particle_index_), raw(sorted_pos_), raw(sorted_source_)});
  }

  double* grid_values(std::size_t k, int buffer) { return raw(grid_[buffer]) + k * grid_geometry_.nodes(); }

  void deposit(std::size_t k, std::uint32_t step, double fraction) {
    const double total = scene_.cues.particles.amount * core::emitted_at(cues_host_[k].emission, step) * fraction;
    if (total == 0.0) return;
    launch(1, Deposit{grid_values(k, cur_[k]),
                      core::source_deposit(cues_host_[k].position, total, grid_geometry_.origin, grid_geometry_.h,
                                           grid_geometry_.n)});
  }

  void explicit_step(std::size_t k, std::uint32_t step) {
    const std::uint32_t m = substeps_[k];
    const core::StencilParams s =
        stencil_params(grid_geometry_, cues_host_[k], scene_.dt / m, scene_.cues.grid.boundary == GridBoundary::kReflecting);
    for (std::uint32_t sub = 0; sub < m; ++sub) {
      deposit(k, step, 1.0 / m);
      launch(grid_geometry_.nodes(), Ftcs{grid_values(k, cur_[k]), grid_values(k, 1 - cur_[k]), s});
      cur_[k] = 1 - cur_[k];
    }
  }

  void implicit_step(std::size_t k, std::uint32_t step) {
    const std::uint32_t m = substeps_[k];
    const bool reflecting = scene_.cues.grid.boundary == GridBoundary::kReflecting;
    const core::StencilParams s = stencil_params(grid_geometry_, cues_host_[k], scene_.dt / m, reflecting);
    const std::size_t lines = static_cast<std::size_t>(grid_geometry_.n) * grid_geometry_.n;
    for (std::uint32_t sub = 0; sub < m; ++sub) {
      deposit(k, step, 1.0 / m);
      for (int axis = 0; axis < 3; ++axis)
        launch(lines, LodLines{grid_values(k, 0), raw(lod_cp_), raw(lod_dp_), grid_geometry_.n, axis, s.lambda, reflecting});
      launch(grid_geometry_.nodes(), Scale{grid_values(k, 0), 1.0 / (1.0 + s.decay_dt)});
    }
  }

  const Scene& scene_;
  core::GrowthParams growth_;
  core::WanderParams wander_;
  std::vector<core::CueParams> cues_host_;
  core::SenseParams sense_;
  core::ParticleParams particle_params_;
  HashGeometry hash_;
  GridGeometry3 grid_geometry_;
  core::EstimateSet mesh_;  // the particle estimate's mesh geometry (c unused)
  EstimateParams estimate_params_;
  bool use_grid_, use_estimate_;
  GridGeometry soma_geometry_;
  // Somas (sorted grid) and axons in slot order (slot k = neuron ids_[k]).
  dvec<std::uint32_t> ids_, soma_start_;
  dvec<Vec3> soma_pos_, tip_, heading_;
  dvec<double> length_, step_length_;
  dvec<core::AxonStatus> status_;
  dvec<std::uint32_t> steps_, target_, target_by_id_, active_, active_next_;
  StepStats stats_;
  // Cues.
  dvec<core::CueParams> cues_;
  std::uint64_t next_id_ = 0;
  dvec<Vec3> pos_, vel_, sorted_pos_, pos_scratch_, vel_scratch_;
  dvec<std::uint64_t> id_, id_scratch_;
  dvec<std::uint16_t> source_, sorted_source_, source_scratch_;
  dvec<std::uint8_t> keep_;
  dvec<std::uint32_t> particle_keys_, particle_index_, particle_start_;
  dvec<double> grid_[2], lod_cp_, lod_dp_;
  dvec<double> estimate_;              // 2 K meshes, cue-major, even half first
  dvec<std::uint64_t> deposit_;        // this step's fixed-point deposits
  std::vector<int> cur_;
  std::vector<std::uint32_t> substeps_;
  // The signalling model.
  bool modulated_ = false;
  core::GuideParams guide_{};  // stage 2's parameters; its cues are cues_
  DecisionClock clock_;
  std::size_t sums_per_axon_ = 0;
  dvec<double> sums_;         // per slot: the open decision interval's sums
  dvec<Vec3> soma_by_id_;
  dvec<double> signal_, receptors_, inhibition_;
  dvec<std::uint32_t> fail_id_;
  dvec<std::uint16_t> fail_code_;
  dvec<std::uint64_t> population_first_;
  // Arbours (null: the scene grows axons).
  std::unique_ptr<ArbourPools> arbours_;
  ArbourParams arbour_params_;
  std::vector<Vec3> soma_host_;  // by id
  bool restarts_ = false;        // stems or lateral branches start at a rate
  std::size_t sums_per_cone_ = 0;
};

std::unique_ptr<Engine> make_engine(const Scene& scene, const Placement& placement) {
  return std::make_unique<AccelEngine>(scene, placement);
}

BfsResult bfs_level_sync(const Csr& g, const std::vector<std::uint32_t>& sources) {
  return bfs_level_sync_device(DeviceCsr(g), sources);
}

BfsResult bfs_queue(const Csr& g, const std::vector<std::uint32_t>& sources) {
  return bfs_queue_device(DeviceCsr(g), sources);
}

std::vector<std::uint32_t> components(const Csr& g) {
  dvec<std::uint32_t> source, target;
  device_edges(g, source, target);
  return components_device(source, target, g.vertices());
}

}  // namespace axg::accel::AXG_ACCEL_NS

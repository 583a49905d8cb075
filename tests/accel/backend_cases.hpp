#pragma once
// One test body for every backend (STYLE §8): the scenes a backend must reproduce byte
// for byte, and the check itself. Used by the CPU-emulated pipeline (label accel) and by
// the GPU (label gpu).
#include <filesystem>
#include <string>
#include <vector>

#include "axonguide/core/random.hpp"
#include "axonguide/graph/graph.hpp"
#include "support.hpp"

namespace axg::test {

struct NamedScene {
  std::string name;
  Scene scene;
};
inline void PrintTo(const NamedScene& s, std::ostream* os) { *os << s.name; }

// Test-name suffix of a scene: its name with every non-alphanumeric character as '_'.
struct SceneName {
  template <class Info>
  std::string operator()(const Info& info) const {
    std::string n = info.param.name;
    for (char& c : n)
      if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return n;
  }
};

inline Source with_position(Source s, core::Vec3 p) {
  s.position = p;
  return s;
}
inline Source repellent(Source s) {
  s.kind = CueKind::kRepellent;
  return s;
}

// Every bundled scene, every golden scene, the default, and one small variant per field,
// motion, scheme, boundary, steering model, sampler and contact rule, and arbours. `small` shrinks the
// bundled scenes (the CPU emulation runs its kernels on one thread).
inline std::vector<NamedScene> backend_scenes(bool small) {
  std::vector<NamedScene> out;
  auto shrink = [&](Scene s) {
    if (small && s.arbours && s.neurons.count > 150) {
      // Arbours: at most 150 neurons at the same density, and at most 5 days of growth.
      const double f = 150.0 / static_cast<double>(s.neurons.count);
      s.neurons.count = 150;
      s.neurons.radius *= s.neurons.shape == RegionShape::kDisc ? std::sqrt(f) : std::cbrt(f);
      s.steps = std::min<std::uint32_t>(s.steps, static_cast<std::uint32_t>(120.0 / s.dt));
    } else if (small && !s.neurons.populations.empty()) {
      // Populations: at most 300 neurons each, in their own balls (the region unchanged);
      // the particle field's emission at most 1000 per step.
      std::uint64_t total = 0;
      for (auto& p : s.neurons.populations) total += (p.count = std::min<std::uint64_t>(p.count, 300));
      s.neurons.count = total;
      for (auto& src : s.cues.sources) src.emission = std::min(src.emission, 1000.0);
      s.cues.warmup_steps = std::min<std::uint32_t>(s.cues.warmup_steps, 20);
    } else if (small && s.neurons.count > 600) {
      const double f = 600.0 / static_cast<double>(s.neurons.count);
      s.neurons.count = 600;
      s.neurons.radius *= std::cbrt(f);
      s.axons.bounds_radius.reset();
    }
    return s;
  };
  const std::filesystem::path root(source_dir());
  for (const char* dir : {"scenes", "data/golden"}) {
    if (!std::filesystem::exists(root / dir)) continue;
    std::vector<std::filesystem::path> files;
    for (const auto& e : std::filesystem::recursive_directory_iterator(root / dir))
      if (e.path().extension() == ".json" && e.path().filename() == "scene.json") files.push_back(e.path());
      else if (e.path().extension() == ".json" && std::string(dir) == "scenes" && !test::is_sweep_file(e.path()))
        files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
      Scene s = load_scene_file(f.string()).scene;
      out.push_back({std::filesystem::relative(f, root).string(), shrink(std::move(s))});
    }
  }
  out.push_back({"builtin-default", Scene::builtin_default()});
  struct Variant {
    const char* name;
    void (*tweak)(Scene&);
  };
  const Variant variants[] = {
      {"direct-endpoint-trig-box", [](Scene& s) {
         s.guidance.model = GuidanceModel::kDirect;
         s.axons.contact = ContactRule::kEndpoint;
         s.neurons.sampler = Sampler::kTrig;
         s.neurons.shape = RegionShape::kBox;
       }},
      {"direct-sphere-coordinate", [](Scene& s) {
         s.guidance.model = GuidanceModel::kDirect;
         s.neurons.shape = RegionShape::kSphere;
         s.neurons.sampler = Sampler::kCoordinate;
         s.axons.bounds_radius = s.neurons.radius * 1.6;
       }},
      {"particles-vector-sum", [](Scene& s) { s.guidance.model = GuidanceModel::kVectorSum; }},
      {"particles-ballistic-collisions", [](Scene& s) {
         s.cues.particles.motion = Motion::kBallistic;
         s.cues.particles.collisions = true;
         s.cues.particles.radius = 0.05;
       }},
      {"grid-implicit-absorbing", [](Scene& s) { s.cues.field = FieldKind::kGrid; }},
      {"grid-implicit-reflecting-vector-sum", [](Scene& s) {
         s.cues.field = FieldKind::kGrid;
         s.cues.grid.boundary = GridBoundary::kReflecting;
         s.guidance.model = GuidanceModel::kVectorSum;
       }},
      {"grid-explicit-absorbing", [](Scene& s) {
         s.cues.field = FieldKind::kGrid;
         s.cues.grid.scheme = GridScheme::kExplicit;
       }},
      {"grid-explicit-reflecting", [](Scene& s) {
         s.cues.field = FieldKind::kGrid;
         s.cues.grid.scheme = GridScheme::kExplicit;
         s.cues.grid.boundary = GridBoundary::kReflecting;
       }},
      {"analytic-snr", [](Scene& s) { s.cues.field = FieldKind::kAnalytic; }},
      {"analytic-vector-sum-normal", [](Scene& s) {
         s.cues.field = FieldKind::kAnalytic;
         s.guidance.model = GuidanceModel::kVectorSum;
         s.neurons.sampler = Sampler::kNormal;
       }},
      // The guidance-model options (SPEC §3.3-§3.5): one variant each.
      {"particles-snr-noise-binding", [](Scene& s) { s.guidance.noise = NoiseForm::kBinding; }},
      {"particles-snr-noise-snapshot", [](Scene& s) { s.guidance.noise = NoiseForm::kSnapshot; }},
      {"particles-snr-sensing-count", [](Scene& s) { use_count_sensing(s); }},
      // Antithetic decisions (guidance.antithetic): the snapshot SNR and the count dipole.
      {"particles-snr-snapshot-antithetic", [](Scene& s) {
         s.guidance.noise = NoiseForm::kSnapshot;
         s.guidance.antithetic = true;
       }},
      {"particles-snr-count-antithetic", [](Scene& s) { s.guidance.antithetic = true; }},
      {"imposed-linear-snr", [](Scene& s) {
         s.cues.field = FieldKind::kImposed;
         s.cues.imposed.profile = ImposedProfile::kLinear;
         s.cues.imposed.direction = core::normalized(core::Vec3{1.0, 0.5, -0.25});
         s.cues.imposed.steepness = 5.0;  // 5 % per LU: stays > 0 over the radius ~4 ball
         s.cues.imposed.reference_length = 1.0;
         s.cues.imposed.concentration = 0.5;
         s.cues.sources = {with_position(Source{}, {0.5, 0.0, 0.0}),
                           with_position(repellent(Source{}), {-1.0, 0.5, 0.25})};
       }},
      {"imposed-exponential-snr-snapshot", [](Scene& s) {
         s.cues.field = FieldKind::kImposed;
         s.cues.imposed.profile = ImposedProfile::kExponential;
         s.cues.imposed.direction = {0.0, 0.0, -1.0};
         s.cues.imposed.steepness = 40.0;
         s.cues.imposed.reference_length = 1.0;
         s.cues.imposed.concentration = 2.0;
         s.guidance.noise = NoiseForm::kSnapshot;
         s.cues.sources = {with_position(Source{}, {0.0, 1.0, 0.0}),
                           with_position(repellent(Source{}), {1.0, -1.0, 0.5})};
       }},
      {"imposed-exponential-vector-sum", [](Scene& s) {
         s.cues.field = FieldKind::kImposed;
         s.guidance.model = GuidanceModel::kVectorSum;
         s.cues.imposed.steepness = 20.0;
         s.cues.imposed.reference_length = 1.0;
         s.cues.sources = {with_position(Source{}, {0.0, 0.0, 0.0})};
       }},
      {"particles-vector-sum-sensed", [](Scene& s) {
         s.guidance.model = GuidanceModel::kVectorSum;
         s.guidance.vector_weight = 0.5;
       }},
      {"particles-source-vector-sum", [](Scene& s) { s.guidance.model = GuidanceModel::kSourceVectorSum; }},
      {"analytic-source-vector-sum", [](Scene& s) {
         s.cues.field = FieldKind::kAnalytic;
         s.guidance.model = GuidanceModel::kSourceVectorSum;
       }},
      {"particles-snr-binding-growth-modulation", [](Scene& s) {
         s.axons.growth_modulation = 0.5;
         s.guidance.noise = NoiseForm::kBinding;  // the split estimate
       }},
      {"analytic-snr-binding", [](Scene& s) {
         s.cues.field = FieldKind::kAnalytic;
         s.guidance.noise = NoiseForm::kBinding;
       }},
      {"grid-snr-snapshot", [](Scene& s) {
         s.cues.field = FieldKind::kGrid;
         s.guidance.noise = NoiseForm::kSnapshot;
       }},
      {"particles-count-warmup", [](Scene& s) { s.cues.warmup_steps = 15; }},
      {"grid-implicit-warmup", [](Scene& s) {
         s.cues.field = FieldKind::kGrid;
         s.cues.warmup_steps = 10;
       }},
      {"particles-count-growth-modulation", [](Scene& s) {
         s.axons.growth_modulation = 0.5;
         use_count_sensing(s);
       }},
      {"analytic-snr-growth-modulation", [](Scene& s) {
         s.cues.field = FieldKind::kAnalytic;
         s.axons.growth_modulation = 0.5;
       }},
      {"grid-snr-growth-modulation-short-persistence", [](Scene& s) {
         s.cues.field = FieldKind::kGrid;
         s.axons.growth_modulation = 0.5;
         s.axons.persistence_length = 0.5;
       }},
      {"particles-snr-persistence-off", [](Scene& s) { s.axons.persistence_length.reset(); }},
      {"particles-snr-persistence-short", [](Scene& s) { s.axons.persistence_length = 0.5; }},
      {"direct-persistence-short", [](Scene& s) {
         s.guidance.model = GuidanceModel::kDirect;
         s.axons.persistence_length = 0.5;
       }},
      {"units-um-min-nM-growth-speed", [](Scene& s) {
         // 1 LU read as 40 um: the region, somas and cues scaled so the run is the same size.
         s.units.length = "um";
         s.units.time = "min";
         s.units.concentration = "nM";
         s.dt = 0.5;
         s.neurons.radius *= 40.0;
         s.neurons.soma_radius *= 40.0;
         s.axons.contact_distance *= 40.0;
         s.axons.growth_speed = 28.0;  // um/min: step length 14 um = 0.35 LU
         s.axons.step_length = *s.axons.growth_speed * s.dt;
         s.axons.persistence_length = 250.0;
         s.guidance.sensing_radius *= 40.0;
         s.guidance.growth_cone_width *= 40.0;
         s.cues.field = FieldKind::kAnalytic;
         s.cues.particles.amount *= 64000.0;  // per um^3: the same concentrations
         for (Source& src : s.cues.sources) src.diffusion *= 1600.0 / s.dt;
       }},
      {"particles-count-integrated", [](Scene& s) {
         // Decisions over four steps of half a time unit: the sums per axon and cue.
         s.dt = 0.5;
         s.axons.step_length = 0.175;
         s.guidance.integration_time = 2.0;
       }},
      {"grid-binding-integrated-unwhole", [](Scene& s) {
         // T = 2.5 steps: intervals of 2 and 3 steps, a vector pull and growth modulation.
         s.cues.field = FieldKind::kGrid;
         s.guidance.noise = NoiseForm::kBinding;
         s.guidance.integration_time = 2.5;
         s.axons.growth_modulation = 0.4;
       }},
      {"particles-source-vector-sum-integrated", [](Scene& s) {
         s.guidance.model = GuidanceModel::kSourceVectorSum;
         s.guidance.integration_time = 3.0;
       }},
      {"particles-mixed-sources", [](Scene& s) {
         Source a = with_position(Source{}, {1.0, 0.0, 0.0});
         Source b = with_position(repellent(Source{}), {-1.0, 1.0, 0.0});
         b.emission = 60;
         b.diffusion = 0.08;
         Source c;  // sampled position
         c.kd = 0.5;
         c.decay = 0.1;
         Source d = repellent(Source{});  // sampled position
         d.min_concentration = 0.01;
         d.max_concentration = 50.0;
         Source e = with_position(Source{}, {0.0, -1.5, 1.0});
         e.emission = 150;
         s.cues.sources = {e, d, c, b, a};
         s.cues.random_sources.count = 2;
         s.cues.random_sources.emission = 80;
       }},
      {"particles-molecule-resolved-count", [](Scene& s) {
         // One particle, one molecule: count decisions from the particles within r.
         use_count_sensing(s);
         s.cues.molecule_amount = 0.002;
         s.cues.particles.molecules = true;
         s.cues.particles.amount = 0.002;
         for (Source& src : s.cues.sources) src.emission = 500;
       }},
      {"particles-estimate-coarse-mesh-no-average", [](Scene& s) {
         s.cues.particles.estimate.spacing = 0.7;
         s.cues.particles.estimate.time = 0.0;
         s.guidance.model = GuidanceModel::kVectorSum;
       }},
      {"grid-implicit-substeps-reflecting", [](Scene& s) {
         s.cues.field = FieldKind::kGrid;
         s.cues.grid.substeps = 3;
         s.cues.grid.boundary = GridBoundary::kReflecting;
       }},
      {"analytic-mixed-sources-count-modulation", [](Scene& s) {
         s.cues.field = FieldKind::kAnalytic;
         s.axons.growth_modulation = 0.3;
         Source a = with_position(Source{}, {1.0, 0.0, 0.0});
         Source b = with_position(repellent(Source{}), {-1.0, 1.0, 0.0});
         b.kd = 3.0;
         Source c;
         c.decay = 0.02;
         s.cues.sources = {c, b, a};
         s.cues.random_sources.count = 1;
       }},
  };
  for (const Variant& v : variants) {
    Scene s = Scene::builtin_default();
    s.neurons.count = 400;
    s.neurons.radius = 2.5 * std::cbrt(4.0);
    s.steps = 50;
    s.cues.grid.spacing = 0.25;
    s.analysis.bfs_sources = {0, 1, 2, 3};
    s.output.paths = true;
    v.tweak(s);
    out.push_back({v.name, s});
  }
  // Arbours (morphology/arbour_step.hpp) in length units: branching with an order
  // dependence (S), lateral branches and stems at a rate, every field kind, decision sums,
  // cones that stop at somas or pass them, points every step or every 0.2 LU. Every neuron's
  // pools start small and grow many times.
  struct ArbourVariant {
    const char* name;
    const char* field;
    double integration_time;  // 1: every step
    const char* soma_contact;
    double sample_length;
    const char* shape;
  };
  const ArbourVariant arbour_variants[] = {
      {"arbours-particles-order-lateral-stems", "particles", 1.0, "stop", 0.2, "ball"},
      {"arbours-particles-integrated", "particles", 3.0, "stop", 0.2, "ball"},
      {"arbours-grid-pass-every-step", "grid", 1.0, "pass", 0.0, "ball"},
      {"arbours-analytic-integrated-culture", "analytic", 2.5, "pass", 0.2, "disc"},
      {"arbours-direct-stop", "direct", 1.0, "stop", 0.2, "ball"},
  };
  for (const ArbourVariant& v : arbour_variants) {
    nlohmann::json j = scene_to_json(Scene::builtin_default());
    j["neurons"]["count"] = 150;
    j["neurons"]["region"]["shape"] = v.shape;
    j["steps"] = 40;
    j["output"]["paths"] = true;
    j["output"]["swc"] = true;
    j["guidance"]["integration_time"] = v.integration_time;
    if (std::string(v.field) == "direct") j["guidance"]["model"] = "direct";
    else j["cues"]["field"] = v.field;
    j["arbours"] = {{"sample_length", v.sample_length},
                    {"soma_contact", v.soma_contact},
                    {"axon", {{"B", 4}, {"E", 0.3}, {"S", 0.5}, {"tau", 30}, {"v0", 0.1}, {"F", 0.3},
                              {"rate_cv", 0.4}, {"angle", 1.0}, {"angle_sd", 0.3}, {"persistence_length", 5},
                              {"stems", {0, 0.7, 0.3}}, {"stem_rate", 0.02}, {"lateral_rate", 0.05}}},
                    {"dendrites", {{"B", 1}, {"E", 0.5}, {"S", 0.3}, {"tau", 20}, {"v0", 0.03}, {"F", 0.3},
                                   {"rate_cv", 0.4}, {"angle", 1.0}, {"stems", {0, 0.2, 0.5, 0.3}},
                                   {"stem_rate", 0.05}, {"lateral_rate", 0.1}}}};
    out.push_back({v.name, parse_scene(j.dump(), v.name).scene});
  }
  // The signalling growth model (core/signalling.hpp) on every field kind, from the units
  // variant (um, min, nM): rates set so that 50 steps of 30 min grow ~100-700 um.
  Scene units;
  for (const auto& n : out)
    if (n.name == "units-um-min-nM-growth-speed") units = n.scene;
  struct SignallingVariant {
    const char* name;
    const char* field;
    const char* steering;
    const char* inhibition;
    bool populations;
  };
  const SignallingVariant signalling[] = {
      {"signalling-particles-snr-population", "particles", "snr", "population", false},
      {"signalling-analytic-direct-soma", "analytic", "direct", "soma", false},
      {"signalling-grid-vector-sum-populations", "grid", "vector_sum", "population", true},
      {"signalling-imposed-direct-populations", "imposed", "direct", "population", true},
  };
  for (const SignallingVariant& v : signalling) {
    nlohmann::json j = scene_to_json(units);
    j["dt"] = 30.0;
    j["axons"]["growth_speed"] = nullptr;
    j["axons"]["step_length"] = 10.0;
    j["axons"]["growth_model"] = "signalling";
    j["axons"]["signalling"] = {{"cue", 0},        {"inhibition", v.inhibition}, {"substeps", 2},
                                {"r0", "0.2 um/min"}, {"kext", "0.1 um/min"},       {"kr", "0.02 /min"},
                                {"ka", "0.02 /min"}, {"a1b", "0.001 /min"}};
    j["guidance"]["model"] = v.steering;
    j["guidance"]["integration_time"] = 30.0;  // one decision per step of 30 min
    j["cues"]["field"] = v.field;
    if (std::string(v.field) == "grid") j["cues"]["grid"]["spacing"] = 40.0;
    if (std::string(v.field) == "imposed")
      j["cues"]["imposed"] = {{"profile", "exponential"}, {"direction", {0, 1, 0}}, {"steepness", 0.5},
                              {"reference_length", 10}, {"concentration", 0.3}};
    if (v.populations) {
      const double r = j["neurons"]["region"]["radius"].get<double>();
      j["neurons"]["populations"] = {{{"count", 200}, {"center", {-0.4 * r, 0, 0}}, {"radius", 0.4 * r}},
                                     {{"count", 200}, {"center", {0.4 * r, 0, 0}}, {"radius", 0.4 * r}}};
    }
    out.push_back({v.name, parse_scene(j.dump(), v.name).scene});
  }
  return out;
}

// Random cue scenes for the RapidCheck comparison.
inline rc::Gen<Scene> gen_cue_scene() {
  return rc::gen::exec([] {
    Scene s = *gen_direct_scene();
    s.neurons.count = std::min<std::uint64_t>(s.neurons.count, 200);
    s.steps = std::min<std::uint32_t>(s.steps, 30);
    s.guidance.model = *rc::gen::element(GuidanceModel::kDirect, GuidanceModel::kSnr, GuidanceModel::kVectorSum,
                                         GuidanceModel::kSourceVectorSum);
    s.cues.field = *rc::gen::element(FieldKind::kParticles, FieldKind::kGrid, FieldKind::kAnalytic, FieldKind::kImposed);
    s.guidance.noise = *rc::gen::element(NoiseForm::kBinding, NoiseForm::kSnapshot);
    if (*rc::gen::arbitrary<bool>()) use_count_sensing(s);
    if (*rc::gen::arbitrary<bool>()) s.axons.persistence_length.reset();
    else s.axons.persistence_length = *rc::gen::inRange(1, 200) / 10.0;
    if (s.guidance.model == GuidanceModel::kSnr && *rc::gen::arbitrary<bool>())
      s.axons.growth_modulation = *rc::gen::inRange(1, 100) / 100.0;
    // Decisions over 1 to 4 steps, whole or not (each axon's sums on the device).
    if (*rc::gen::arbitrary<bool>()) s.guidance.integration_time = s.dt * *rc::gen::inRange(2, 9) / 2.0;
    // Linear only at 1 % per length unit: non-negative over any generated domain (R_b <= 12).
    s.cues.imposed.profile = *rc::gen::element(ImposedProfile::kLinear, ImposedProfile::kExponential);
    s.cues.imposed.steepness = s.cues.imposed.profile == ImposedProfile::kLinear ? 1.0 : *rc::gen::inRange(0, 200);
    s.cues.imposed.reference_length = 1.0;
    s.cues.random_sources.count = *rc::gen::inRange<std::uint32_t>(1, 5);
    s.cues.random_sources.emission = *rc::gen::inRange(0, 300) / 2.0;
    s.cues.particles.motion = *rc::gen::element(Motion::kBrownian, Motion::kBallistic);
    s.cues.particles.collisions = *rc::gen::arbitrary<bool>();
    s.cues.grid.spacing = std::max(0.2, s.bounds_radius() / 12);
    s.cues.grid.scheme = *rc::gen::element(GridScheme::kExplicit, GridScheme::kImplicit);
    if (s.cues.grid.scheme == GridScheme::kImplicit && *rc::gen::arbitrary<bool>())
      s.cues.grid.substeps = *rc::gen::inRange<std::uint32_t>(1, 4);
    // The particle estimate's mesh and moving average, or molecule-resolved particles.
    s.cues.particles.estimate.spacing = *rc::gen::inRange(2, 9) / 10.0 * std::min(1.0, s.bounds_radius() / 2);
    s.cues.particles.estimate.time = *rc::gen::inRange(0, 30) / 2.0;
    if (*rc::gen::arbitrary<bool>()) {
      s.cues.molecule_amount = s.cues.particles.amount;
      s.cues.particles.molecules = *rc::gen::arbitrary<bool>();
    }
    s.cues.grid.boundary = *rc::gen::element(GridBoundary::kAbsorbing, GridBoundary::kReflecting);
    s.analysis.bfs_sources = {0};
    return s;
  });
}

// Random arbour scenes (length units): branching, elongation, lateral branches and stems
// drawn, on a random field and contact rule, with or without decision sums and synapses.
inline rc::Gen<Scene> gen_arbour_scene() {
  return rc::gen::exec([] {
    nlohmann::json j = scene_to_json(Scene::builtin_default());
    j["seed"] = *rc::gen::inRange<std::uint64_t>(0, 1u << 20);
    j["neurons"]["count"] = *rc::gen::inRange(1, 40);
    j["neurons"]["region"]["shape"] = *rc::gen::element<std::string>("ball", "disc", "box");
    j["steps"] = *rc::gen::inRange(1, 25);
    const std::string field = *rc::gen::element<std::string>("direct", "particles", "grid", "analytic", "imposed");
    if (field == "direct") j["guidance"]["model"] = "direct";
    else j["cues"]["field"] = field;
    if (field == "imposed") j["cues"]["imposed"] = {{"direction", {1, 0, 0}}, {"steepness", 20}};
    j["guidance"]["integration_time"] = *rc::gen::inRange(2, 9) / 2.0;
    auto neurite = [](double v0) {
      nlohmann::json n = {{"B", *rc::gen::inRange(0, 60) / 10.0},
                          {"E", *rc::gen::inRange(0, 10) / 10.0},
                          {"S", *rc::gen::inRange(0, 10) / 10.0},
                          {"v0", v0 * *rc::gen::inRange(1, 20) / 10.0},
                          {"F", *rc::gen::inRange(0, 10) / 10.0},
                          {"rate_cv", *rc::gen::inRange(0, 10) / 10.0},
                          {"angle", *rc::gen::inRange(1, 30) / 10.0},
                          {"angle_sd", *rc::gen::inRange(0, 5) / 10.0},
                          {"stems", {0.2, 0.5, 0.3}},
                          {"stem_rate", *rc::gen::inRange(0, 10) / 100.0},
                          {"lateral_rate", *rc::gen::inRange(0, 10) / 50.0}};
      if (*rc::gen::arbitrary<bool>()) n["tau"] = *rc::gen::inRange(1, 50);
      if (*rc::gen::arbitrary<bool>()) n["persistence_length"] = *rc::gen::inRange(1, 50) / 5.0;
      return n;
    };
    j["arbours"] = {{"sample_length", *rc::gen::inRange(0, 5) / 10.0},
                    {"soma_contact", *rc::gen::element<std::string>("stop", "pass")},
                    {"axon", neurite(0.1)},
                    {"dendrites", neurite(0.03)}};
    if (*rc::gen::arbitrary<bool>()) j["synapses"] = {{"distance", 0.05}, {"probability", 0.5}};
    return parse_scene(j.dump(), "random-arbours").scene;
  });
}

// The outputs of `make` equal the reference's, byte for byte.
inline void expect_same_as_reference(const Scene& scene, const EngineFactory& make, const std::string& name) {
  const auto reference = run_hashes(scene, 2);
  const auto backend = run_hashes(scene, 2, make);
  EXPECT_EQ(backend, reference) << name;
}

}  // namespace axg::test

// The guidance-model options of SPEC §3.3-§3.5 (noise form, particle sensing, imposed
// gradients, sensed and source vector sums, growth-rate modulation, wandering, units and
// growth speed) under the determinism contract: identical bytes for 1 and 2 threads, the
// same bytes whatever order the cue sources are listed in, and finite outputs at the
// extremes of every accepted value.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "support.hpp"

namespace axg {
namespace {

Source source(CueKind kind, std::optional<core::Vec3> position, double emission, double diffusion, double decay,
              double kd) {
  Source s;
  s.kind = kind;
  s.position = position;
  s.emission = emission;
  s.diffusion = diffusion;
  s.decay = decay;
  s.kd = kd;
  return s;
}

// A small cue scene: 150 neurons in a ball of radius 2.5, 30 steps, two sources.
Scene small_cue_scene() {
  Scene s;
  s.neurons.count = 150;
  s.neurons.radius = 2.5;
  s.steps = 30;
  s.guidance.model = GuidanceModel::kSnr;
  s.guidance.noise = NoiseForm::kSnapshot;  // not the default: "noise binding" and "sensing count" change it
  s.cues.field = FieldKind::kParticles;
  s.cues.grid.spacing = 0.25;
  s.cues.sources = {source(CueKind::kAttractant, core::Vec3{0.5, 0.0, 0.0}, 100, 0.05, 0.05, 1.0),
                    source(CueKind::kRepellent, std::nullopt, 80, 0.05, 0.05, 1.0)};
  s.analysis.bfs_sources = {0, 1};
  return s;
}

// The new options, one per entry; each changes the scene it is given.
struct Option {
  const char* name;
  void (*apply)(Scene&);
};

const std::vector<Option>& options() {
  static const std::vector<Option> list = {
      {"sensing count", [](Scene& s) { test::use_count_sensing(s); }},
      {"noise binding", [](Scene& s) { s.guidance.noise = NoiseForm::kBinding; }},
      {"imposed linear", [](Scene& s) {
         s.cues.field = FieldKind::kImposed;
         s.cues.imposed.profile = ImposedProfile::kLinear;
         s.cues.imposed.steepness = 10;
         s.cues.imposed.reference_length = 1;
         s.cues.sources[1].position = core::Vec3{-0.5, 0.5, 0.0};
       }},
      {"imposed exponential", [](Scene& s) {
         s.cues.field = FieldKind::kImposed;
         s.cues.imposed.steepness = 50;
         s.cues.imposed.reference_length = 1;
         s.cues.imposed.direction = core::normalized(core::Vec3{0.0, 1.0, 1.0});
       }},
      {"vector_sum on particles", [](Scene& s) { s.guidance.model = GuidanceModel::kVectorSum; }},
      {"vector_sum on imposed", [](Scene& s) {
         s.guidance.model = GuidanceModel::kVectorSum;
         s.cues.field = FieldKind::kImposed;
       }},
      {"source_vector_sum on particles", [](Scene& s) { s.guidance.model = GuidanceModel::kSourceVectorSum; }},
      {"source_vector_sum on grid", [](Scene& s) {
         s.guidance.model = GuidanceModel::kSourceVectorSum;
         s.cues.field = FieldKind::kGrid;
       }},
      {"growth_modulation 0.5 on particles", [](Scene& s) { s.axons.growth_modulation = 0.5; }},
      {"growth_modulation 0.5 on analytic", [](Scene& s) {
         s.axons.growth_modulation = 0.5;
         s.cues.field = FieldKind::kAnalytic;
       }},
      {"growth_modulation 0.5, count sensing", [](Scene& s) {
         s.axons.growth_modulation = 0.5;
         test::use_count_sensing(s);
       }},
      {"count noise on analytic (Gaussian limit)", [](Scene& s) {
         test::use_count_sensing(s);
         s.cues.field = FieldKind::kAnalytic;
       }},
      {"warmup 12 steps, particles", [](Scene& s) { s.cues.warmup_steps = 12; }},
      {"warmup 12 steps, explicit grid", [](Scene& s) {
         s.cues.warmup_steps = 12;
         s.cues.field = FieldKind::kGrid;
         s.cues.grid.scheme = GridScheme::kExplicit;
       }},
      {"two populations", [](Scene& s) {
         const double R = s.neurons.radius;
         const std::uint64_t half = s.neurons.count / 2;
         s.neurons.soma_radius = 0.08;
         s.neurons.populations = {{half, {-0.45 * R, 0.0, 0.0}, 0.5 * R},
                                  {s.neurons.count - half, {0.45 * R, 0.0, 0.0}, 0.5 * R}};
       }},
      {"antithetic decisions (count)", [](Scene& s) { s.guidance.antithetic = true; }},
      {"antithetic decisions (snapshot)", [](Scene& s) {
         s.guidance.antithetic = true;
         s.guidance.noise = NoiseForm::kSnapshot;
       }},
      {"persistence off", [](Scene& s) { s.axons.persistence_length.reset(); }},
      {"persistence 0.5", [](Scene& s) { s.axons.persistence_length = 0.5; }},
      {"persistence 0.5, direct", [](Scene& s) {
         s.axons.persistence_length = 0.5;
         s.guidance.model = GuidanceModel::kDirect;
       }},
      {"units um/min/nM, growth speed", [](Scene& s) {
         s.units = {"um", "min", "nM"};
         s.dt = 0.5;
         s.axons.growth_speed = 0.7;
         s.axons.step_length = 0.35;
       }},
      {"signalling growth, population inhibition, SNR steering", [](Scene& s) {
         s.units = {"um", "min", "nM"};
         s.dt = 5.0;
         s.axons.growth_model = GrowthModel::kSignalling;
         s.axons.signalling.substeps = 2;
         s.cues.field = FieldKind::kImposed;  // 0.3 nM, 5 % per um
         s.cues.imposed.concentration = 0.3;
         s.cues.imposed.steepness = 5.0;
         s.cues.imposed.reference_length = 1.0;
       }},
      {"signalling growth on the particle field, SNR steering", [](Scene& s) {
         s.units = {"um", "min", "nM"};
         s.dt = 5.0;
         s.axons.growth_model = GrowthModel::kSignalling;
       }},
      {"signalling growth, soma inhibition, radial headings, direct", [](Scene& s) {
         s.units = {"um", "min", "nM"};
         s.dt = 5.0;
         s.axons.growth_model = GrowthModel::kSignalling;
         s.axons.signalling.population = false;
         s.neurons.radial_heading = true;
         s.guidance.model = GuidanceModel::kDirect;
         s.cues.field = FieldKind::kAnalytic;
       }},
      {"five mixed sources", [](Scene& s) {
         s.cues.sources.push_back(source(CueKind::kAttractant, std::nullopt, 50, 0.1, 0.02, 0.5));
         s.cues.sources.push_back(source(CueKind::kRepellent, core::Vec3{0.0, -1.0, 0.5}, 120, 0.04, 0.08, 2.0));
         s.cues.sources.push_back(source(CueKind::kAttractant, core::Vec3{-1.0, 0.0, 0.0}, 100, 0.05, 0.05, 1.0));
         s.cues.random_sources.count = 1;
       }},
  };
  return list;
}

// Uniform in [0, n) whatever the test's size (RapidCheck scales inRange by size).
std::size_t pick(std::size_t n) { return *rc::gen::resize(rc::kNominalSize, rc::gen::inRange<std::size_t>(0, n)); }

RC_GTEST_PROP(model_options, EveryNewOptionIsThreadCountInvariant, ()) {
  const std::size_t k = pick(options().size());
  Scene s = small_cue_scene();
  s.seed = *rc::gen::arbitrary<std::uint64_t>();
  s.neurons.count = *rc::gen::inRange<std::uint64_t>(20, 200);
  s.steps = *rc::gen::inRange<std::uint32_t>(5, 30);
  options()[k].apply(s);
  RC_TAG(options()[k].name);
  RC_ASSERT(test::run_hashes(s, 1) == test::run_hashes(s, 2));
}

// The same for every option in turn, with a fixed seed (so a failure names the option).
TEST(model_options, EachNewOptionOnOneAndTwoThreads) {
  for (const Option& o : options()) {
    Scene s = small_cue_scene();
    s.neurons.count = 300;
    s.neurons.radius = 2.5 * std::cbrt(3.0);
    o.apply(s);
    const auto one = test::run_hashes(s, 1);
    EXPECT_EQ(test::run_hashes(s, 2), one) << o.name;
    EXPECT_TRUE(one.count("neurons.csv") && one.count("connections.csv")) << o.name;
  }
}

// Each option changes the network of the base scene (so the checks above cover code that
// runs, not a scene that ignores it).
TEST(model_options, EachNewOptionChangesTheNetwork) {
  Scene base = small_cue_scene();
  base.neurons.count = 300;
  base.neurons.radius = 2.5 * std::cbrt(3.0);
  const auto reference = test::run_hashes(base, 2);
  for (const Option& o : options()) {
    Scene s = base;
    o.apply(s);
    EXPECT_NE(test::run_hashes(s, 2).at("neurons.csv"), reference.at("neurons.csv")) << o.name;
  }
}

// ---------------------------------------------------------------------------------------
// Canonical cue order: the sources' listing order is not part of the scene.

// Five sources: explicit and sampled positions, attractants and repellents, different
// parameters and detection windows.
std::vector<Source> five_sources() {
  Source e = source(CueKind::kAttractant, std::nullopt, 60, 0.08, 0.03, 0.7);
  e.min_concentration = 0.001;
  e.max_concentration = 40;
  return {source(CueKind::kAttractant, core::Vec3{1.0, 0.0, 0.0}, 100, 0.05, 0.05, 1.0),
          source(CueKind::kRepellent, core::Vec3{-1.0, 0.5, 0.0}, 70, 0.06, 0.04, 1.5),
          source(CueKind::kAttractant, std::nullopt, 120, 0.05, 0.05, 1.0),
          source(CueKind::kRepellent, std::nullopt, 90, 0.04, 0.06, 0.8),
          e,
          // Same position as the first, different emission: the order must still be fixed.
          source(CueKind::kAttractant, core::Vec3{1.0, 0.0, 0.0}, 40, 0.05, 0.05, 1.0)};
}

Scene permutation_scene(FieldKind field, GuidanceModel model) {
  Scene s = small_cue_scene();
  s.neurons.count = 120;
  s.steps = 20;
  s.cues.field = field;
  s.guidance.model = model;
  s.cues.sources = five_sources();
  s.cues.random_sources.count = 1;
  s.output.paths = true;
  return s;
}

// Every output file and the canonical scene.
std::map<std::string, std::string> fingerprint(const Scene& s) {
  auto h = test::run_hashes(s, 2);
  h["(canonical scene)"] = scene_to_json(s).dump();
  return h;
}

rc::Gen<std::vector<std::size_t>> gen_permutation(std::size_t n) {
  return rc::gen::exec([n] {
    std::vector<std::size_t> p(n);
    std::iota(p.begin(), p.end(), 0);
    for (std::size_t i = n; i > 1; --i) std::swap(p[i - 1], p[pick(i)]);
    return p;
  });
}

rc::Gen<std::pair<FieldKind, GuidanceModel>> gen_cue_model() {
  return rc::gen::exec([] {
    const FieldKind f =
        *rc::gen::element(FieldKind::kParticles, FieldKind::kGrid, FieldKind::kAnalytic, FieldKind::kImposed);
    const GuidanceModel m =
        *rc::gen::element(GuidanceModel::kSnr, GuidanceModel::kVectorSum, GuidanceModel::kSourceVectorSum);
    return std::make_pair(f, m);
  });
}

RC_GTEST_PROP(cue_order, PermutedSourcesGiveTheSameBytes, ()) {
  const auto [field, model] = *gen_cue_model();
  Scene a = permutation_scene(field, model);
  a.seed = *rc::gen::arbitrary<std::uint64_t>();
  if (*rc::gen::arbitrary<bool>()) test::use_count_sensing(a);
  if (model == GuidanceModel::kSnr && *rc::gen::arbitrary<bool>()) a.axons.growth_modulation = 0.4;
  const auto perm = *gen_permutation(a.cues.sources.size());
  Scene b = a;
  for (std::size_t i = 0; i < perm.size(); ++i) b.cues.sources[i] = a.cues.sources[perm[i]];
  RC_TAG(name_of(field), name_of(model));
  RC_ASSERT(fingerprint(b) == fingerprint(a));
}

// As JSON text through the parser: the permuted file is the same scene.
RC_GTEST_PROP(cue_order, PermutedSourcesInJsonGiveTheSameBytes, ()) {
  const auto [field, model] = *gen_cue_model();
  Scene s = permutation_scene(field, model);
  s.seed = *rc::gen::arbitrary<std::uint64_t>();
  nlohmann::json j = scene_to_json(s);
  const nlohmann::json sources = j["cues"]["sources"];
  const auto perm = *gen_permutation(sources.size());
  nlohmann::json permuted = nlohmann::json::array();
  for (std::size_t i : perm) permuted.push_back(sources[i]);
  nlohmann::json jp = j;
  jp["cues"]["sources"] = permuted;
  const Scene a = parse_scene(j.dump(2), "a.json").scene;
  const Scene b = parse_scene(jp.dump(), "b.json").scene;
  RC_ASSERT(scene_to_json(b).dump() == scene_to_json(a).dump());
  RC_ASSERT(scene_to_json(a).dump() == j.dump());
  RC_ASSERT(fingerprint(b) == fingerprint(a));
  // And the programmatic scene it came from.
  RC_ASSERT(fingerprint(a) == fingerprint(s));
}

// The sources matter: dropping one, or swapping a kind, changes the network (so the
// permutation checks compare runs that depend on every source).
TEST(cue_order, EverySourceMatters) {
  for (FieldKind field : {FieldKind::kParticles, FieldKind::kAnalytic, FieldKind::kImposed}) {
    const Scene a = permutation_scene(field, GuidanceModel::kSnr);
    const std::string base = test::run_hashes(a, 2).at("neurons.csv");
    for (std::size_t k = 0; k < a.cues.sources.size(); ++k) {
      Scene b = a;
      b.cues.sources[k].kind =
          b.cues.sources[k].kind == CueKind::kAttractant ? CueKind::kRepellent : CueKind::kAttractant;
      EXPECT_NE(test::run_hashes(b, 2).at("neurons.csv"), base) << name_of(field) << " source " << k;
    }
  }
}

TEST(cue_order, ReversedListIsTheSameCanonicalScene) {
  Scene a = permutation_scene(FieldKind::kParticles, GuidanceModel::kSnr);
  Scene b = a;
  std::reverse(b.cues.sources.begin(), b.cues.sources.end());
  EXPECT_EQ(scene_to_json(a).dump(), scene_to_json(b).dump());
  EXPECT_EQ(fingerprint(a), fingerprint(b));
  // The run resolves the cues in canonical order too.
  const RunResult ra = run_scene(a, {}), rb = run_scene(b, {});
  ASSERT_EQ(ra.cues.size(), rb.cues.size());
  for (std::size_t k = 0; k < ra.cues.size(); ++k) {
    EXPECT_EQ(ra.cues[k].position.x, rb.cues[k].position.x) << k;
    EXPECT_EQ(ra.cues[k].position.y, rb.cues[k].position.y) << k;
    EXPECT_EQ(ra.cues[k].position.z, rb.cues[k].position.z) << k;
    EXPECT_EQ(ra.cues[k].emission, rb.cues[k].emission) << k;
    EXPECT_EQ(ra.cues[k].sign, rb.cues[k].sign) << k;
  }
}

// ---------------------------------------------------------------------------------------
// Extremes: every accepted value runs to the end with finite outputs.

void expect_finite_run(const Scene& s, const std::string& what) {
  RunResult r;
  ASSERT_NO_THROW(r = run_scene(s, {})) << what;
  ASSERT_EQ(r.neurons.size(), s.neurons.count) << what;
  EXPECT_GT(r.steps_run, 0u) << what;
  EXPECT_LE(r.steps_run, s.steps) << what;
  std::size_t moved = 0;
  for (std::size_t i = 0; i < r.neurons.size(); ++i) {
    const core::Vec3 t = r.neurons.tip[i];
    ASSERT_TRUE(std::isfinite(t.x) && std::isfinite(t.y) && std::isfinite(t.z)) << what << ": neuron " << i;
    ASSERT_TRUE(std::isfinite(r.neurons.length[i]) && r.neurons.length[i] >= 0.0) << what << ": neuron " << i;
    moved += r.neurons.length[i] > 0.0;
  }
  EXPECT_GT(moved, 0u) << what;
  for (const auto& path : r.paths)
    for (const core::Vec3& p : path) ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) << what;
  // The files say so too: no nan or inf anywhere in the text outputs.
  test::TempDir dir;
  write_outputs(r, dir.path(), "test", 1, {});
  for (const char* name : {"neurons.csv", "connections.csv", "stats.csv", "graph.graphml"}) {
    std::string text = test::read_file(dir.path() / name);
    ASSERT_FALSE(text.empty()) << what << ": " << name;
    std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
    EXPECT_EQ(text.find("nan"), std::string::npos) << what << ": " << name;
    EXPECT_EQ(text.find("inf"), std::string::npos) << what << ": " << name;
  }
  // neurons.csv: every numeric field parses to a finite number.
  std::istringstream in(test::read_file(dir.path() / "neurons.csv"));
  std::string line;
  std::getline(in, line);  // header
  std::size_t rows = 0;
  while (std::getline(in, line)) {
    ++rows;
    std::istringstream fields(line);
    std::string f;
    while (std::getline(fields, f, ',')) {
      if (f.empty() || !(std::isdigit(static_cast<unsigned char>(f[0])) || f[0] == '-' || f[0] == '.')) continue;
      const double v = std::strtod(f.c_str(), nullptr);
      EXPECT_TRUE(std::isfinite(v)) << what << ": " << line;
    }
  }
  EXPECT_EQ(rows, s.neurons.count) << what;
}

Scene extreme_base() {
  Scene s = small_cue_scene();
  s.neurons.count = 100;
  s.steps = 25;
  s.output.paths = true;
  return s;
}

TEST(extremes, PersistenceLengthTinyAndHuge) {
  for (double lp : {1e-300, 1e-6, 1e300}) {
    for (GuidanceModel m : {GuidanceModel::kDirect, GuidanceModel::kSnr, GuidanceModel::kVectorSum}) {
      Scene s = extreme_base();
      s.axons.persistence_length = lp;
      s.guidance.model = m;
      expect_finite_run(s, fmt::format("persistence_length {} {}", lp, name_of(m)));
    }
    Scene s = extreme_base();  // with modulation the wander angle is computed per axon
    s.axons.persistence_length = lp;
    s.axons.growth_modulation = 0.9;
    expect_finite_run(s, fmt::format("persistence_length {} with growth_modulation", lp));
  }
}

// The smallest persistence length the parser accepts: 1 / L_p overflows to infinity.
TEST(extremes, PersistenceLengthSubnormal) {
  const Scene parsed = parse_scene(R"({"axons": {"persistence_length": 5e-324}})", "t").scene;
  Scene s = extreme_base();
  s.axons.persistence_length = parsed.axons.persistence_length;
  expect_finite_run(s, "persistence_length 5e-324");
  s.axons.growth_modulation = 0.5;
  expect_finite_run(s, "persistence_length 5e-324 with growth_modulation");
}

TEST(extremes, GrowthModulationNearOne) {
  for (FieldKind f : {FieldKind::kParticles, FieldKind::kAnalytic, FieldKind::kGrid, FieldKind::kImposed}) {
    for (bool count : {false, true}) {
      Scene s = extreme_base();
      s.cues.field = f;
      if (count) test::use_count_sensing(s);
      s.axons.growth_modulation = 0.999999;
      expect_finite_run(s, fmt::format("growth_modulation 0.999999 {}{}", name_of(f), count ? " count" : ""));
    }
  }
}

TEST(extremes, ImposedSteepAndHugeAndTiny) {
  struct Case {
    ImposedProfile profile;
    double steepness, concentration;
  };
  for (const Case c : {Case{ImposedProfile::kExponential, 1e6, 1.0}, Case{ImposedProfile::kExponential, 1e6, 1e300},
                       Case{ImposedProfile::kExponential, 1e6, 1e-300}, Case{ImposedProfile::kExponential, 0.2, 1e300},
                       Case{ImposedProfile::kExponential, 0.2, 1e-300}, Case{ImposedProfile::kLinear, 1.0, 1e300},
                       Case{ImposedProfile::kLinear, 1.0, 1e-300}, Case{ImposedProfile::kExponential, 0.0, 1.0}}) {
    for (GuidanceModel m : {GuidanceModel::kSnr, GuidanceModel::kVectorSum, GuidanceModel::kSourceVectorSum}) {
      for (NoiseForm noise : {NoiseForm::kBinding, NoiseForm::kSnapshot}) {
        Scene s = extreme_base();
        s.cues.field = FieldKind::kImposed;
        s.cues.imposed.profile = c.profile;
        s.cues.imposed.steepness = c.steepness;
        s.cues.imposed.reference_length = 1.0;
        s.cues.imposed.concentration = c.concentration;
        s.guidance.model = m;
        s.guidance.noise = noise;
        if (m == GuidanceModel::kSnr) s.axons.growth_modulation = 0.5;
        expect_finite_run(s, fmt::format("imposed {} steepness {} concentration {} {} {}", name_of(c.profile),
                                         c.steepness, c.concentration, name_of(m), name_of(noise)));
      }
    }
  }
}

// The CLI runs an extreme scene to the end (exit 0) with finite outputs.
TEST(extremes, CommandRunsAnExtremeScene) {
  test::TempDir tmp;
  const auto scene = tmp.path() / "extreme.json";
  std::ofstream(scene) << R"({"neurons": {"count": 100, "region": {"radius": 2.5}}, "steps": 25,
      "axons": {"persistence_length": 1e-300, "growth_modulation": 0.999999},
      "cues": {"field": "imposed", "sources": [{"position": [0, 0, 0]}, {"kind": "repellent"}],
               "imposed": {"steepness": 1000000, "reference_length": 1, "concentration": 1e300}}})";
  const std::string cmd = fmt::format("{} run {} -q --out {} >{} 2>&1", test::binary(), scene.string(),
                                      (tmp.path() / "o").string(), (tmp.path() / "log.txt").string());
  ASSERT_EQ(std::system(cmd.c_str()), 0) << test::read_file(tmp.path() / "log.txt");
  std::string text = test::read_file(tmp.path() / "o" / "neurons.csv");
  ASSERT_FALSE(text.empty());
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  EXPECT_EQ(text.find("nan"), std::string::npos);
  EXPECT_EQ(text.find("inf"), std::string::npos);
}

// ---------------------------------------------------------------------------------------
// Units and growth speed.

TEST(units, GrowthSpeedTimesDtIsTheStepLength) {
  const ParseResult r = parse_scene(R"({"dt": 0.5, "axons": {"step_length": null, "growth_speed": 2}})", "t");
  EXPECT_EQ(r.scene.axons.step_length, 1.0);
  const nlohmann::json j = scene_to_json(r.scene);
  EXPECT_TRUE(j["axons"]["step_length"].is_null()) << j["axons"];
  EXPECT_EQ(j["axons"]["growth_speed"], 2.0);
  // The canonical form reads back to the same scene.
  const Scene back = parse_scene(j.dump(), "canonical").scene;
  EXPECT_EQ(back.axons.step_length, 1.0);
  EXPECT_EQ(scene_to_json(back), j);
  // Without step_length at all, and with a different dt.
  EXPECT_EQ(parse_scene(R"({"dt": 2, "axons": {"growth_speed": 0.25}, "guidance": {"integration_time": 2}})", "t").scene.axons.step_length, 0.5);
}

// A growth-speed scene runs exactly as the step-length scene it describes.
TEST(units, GrowthSpeedSceneRunsAsItsStepLength) {
  const Scene a = parse_scene(R"({"dt": 0.5, "neurons": {"count": 150, "region": {"radius": 2.5}}, "steps": 20,
      "axons": {"step_length": null, "growth_speed": 0.7}, "cues": {"sources": [{}, {"kind": "repellent"}]}})",
                              "a")
                      .scene;
  const Scene b = parse_scene(R"({"dt": 0.5, "neurons": {"count": 150, "region": {"radius": 2.5}}, "steps": 20,
      "axons": {"step_length": 0.35}, "cues": {"sources": [{}, {"kind": "repellent"}]}})",
                              "b")
                      .scene;
  EXPECT_EQ(a.axons.step_length, 0.35);
  EXPECT_EQ(test::run_hashes(a, 2), test::run_hashes(b, 2));
}

TEST(units, DefaultPersistenceLengthFollowsTheLengthUnit) {
  EXPECT_EQ(parse_scene(R"({"units": {"length": "um"}})", "t").scene.axons.persistence_length, 250.0);
  EXPECT_EQ(parse_scene(R"({"units": {"length": "um", "time": "min", "concentration": "nM"}})", "t")
                .scene.axons.persistence_length,
            250.0);
  EXPECT_EQ(parse_scene("{}", "t").scene.axons.persistence_length, 6.25);
  EXPECT_EQ(parse_scene(R"({"units": {"length": "LU"}})", "t").scene.axons.persistence_length, 6.25);
  EXPECT_EQ(parse_scene(R"({"units": {"time": "min", "concentration": "nM"}})", "t").scene.axons.persistence_length,
            6.25);
  EXPECT_EQ(Scene{}.axons.persistence_length, 6.25);
  // An explicit value wins, and null turns wandering off, in either unit.
  EXPECT_EQ(parse_scene(R"({"units": {"length": "um"}, "axons": {"persistence_length": 10}})", "t")
                .scene.axons.persistence_length,
            10.0);
  EXPECT_FALSE(parse_scene(R"({"units": {"length": "um"}, "axons": {"persistence_length": null}})", "t")
                   .scene.axons.persistence_length.has_value());
  EXPECT_FALSE(parse_scene(R"({"axons": {"persistence_length": null}})", "t").scene.axons.persistence_length);
  // The canonical form keeps the unit and the value.
  const nlohmann::json j = scene_to_json(parse_scene(R"({"units": {"length": "um"}})", "t").scene);
  EXPECT_EQ(j["units"]["length"], "um");
  EXPECT_EQ(j["axons"]["persistence_length"], 250.0);
  EXPECT_TRUE(scene_to_json(parse_scene(R"({"axons": {"persistence_length": null}})", "t").scene)["axons"]
                  ["persistence_length"]
                      .is_null());
}

}  // namespace
}  // namespace axg

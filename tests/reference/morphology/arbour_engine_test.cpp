// The arbour engine (issue 41; docs/methods.md §2.12): identical bytes for any thread
// count, SWC trees that are trees, checkpoints that carry the arbours, the scene's checks.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <fstream>
#include <set>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "axonguide/engine/arbour_engine.hpp"
#include "axonguide/engine/checkpoint.hpp"
#include "axonguide/io/swc.hpp"
#include "axonguide/morphology/morphometry.hpp"
#include "support.hpp"

namespace axg {
namespace {

namespace fs = std::filesystem;

Scene culture() { return load_scene_file(test::source_dir() + "/scenes/culture.json").scene; }

// Small random arbour scenes: a disc culture or a ball/box, both soma-contact rules, every
// parameter of both neurite types.
rc::Gen<Scene> gen_arbour_scene() {
  return rc::gen::exec([] {
    Scene s;
    s.seed = *rc::gen::arbitrary<std::uint64_t>();
    s.steps = *rc::gen::inRange<std::uint32_t>(1, 40);
    s.dt = *rc::gen::inRange(1, 20) / 10.0;
    s.neurons.count = *rc::gen::inRange<std::uint64_t>(1, 60);
    s.neurons.shape = *rc::gen::element(RegionShape::kDisc, RegionShape::kBall, RegionShape::kBox);
    s.neurons.radius = 20.0;
    s.neurons.soma_radius = 0.5;
    s.neurons.overlap_reject = false;
    s.guidance.model = GuidanceModel::kDirect;
    s.analysis.bfs_sources.clear();
    ArbourKeys a;
    a.slab = s.neurons.shape == RegionShape::kDisc ? *rc::gen::inRange(0, 5) / 2.0 : 0.0;
    a.stop_at_soma = *rc::gen::arbitrary<bool>();
    for (NeuriteKeys* n : {&a.axon, &a.dendrites}) {
      n->b = *rc::gen::inRange(0, 60) / 10.0;
      n->e = *rc::gen::inRange(0, 10) / 10.0;
      n->s = *rc::gen::inRange(-5, 10) / 10.0;
      if (*rc::gen::arbitrary<bool>()) n->tau = *rc::gen::inRange(1, 100) / 2.0;
      n->v0 = *rc::gen::inRange(0, 30) / 10.0;
      n->f = *rc::gen::inRange(0, 10) / 10.0;
      n->rate_cv = *rc::gen::inRange(0, 10) / 10.0;
      n->angle = *rc::gen::inRange(1, 31) / 10.0;
      n->angle_sd = *rc::gen::inRange(0, 10) / 10.0;
      if (*rc::gen::arbitrary<bool>()) n->persistence_length = *rc::gen::inRange(1, 100);
      n->stems = {0.25, 0.5, 0.25};
      n->stem_rate = *rc::gen::inRange(0, 5) / 10.0;
      // Lateral branching grows a tree as cosh(sqrt(lambda v0) T): lambda v0 T^2 of 0, 1 or 4.
      const double horizon = s.steps * s.dt, k = *rc::gen::element(0.0, 0.0, 1.0, 4.0);
      n->lateral_rate = n->v0 > 0.0 ? k / (n->v0 * horizon * horizon) : 0.1 * k;
    }
    s.arbours = a;
    s.output.swc = true;
    s.output.paths = true;
    s.output.vtk = *rc::gen::arbitrary<bool>();
    s.output.sonata = *rc::gen::arbitrary<bool>();
    return s;
  });
}

RC_GTEST_PROP(arbours, ThreadCountNeverChangesAByte, ()) {
  const Scene scene = *gen_arbour_scene();
  const auto one = test::run_hashes(scene, 1);
  RC_ASSERT(one.count("morphologies/0.swc") == 1u);
  RC_ASSERT(one.count("paths.csv") == 1u);
  RC_ASSERT(test::run_hashes(scene, 2) == one);
  RC_ASSERT(test::run_hashes(scene, 7) == one);
}

TEST(arbours, TheCultureOnOneTwoAndSevenThreads) {
  Scene scene = culture();
  scene.output.paths = true;
  const auto one = test::run_hashes(scene, 1);
  EXPECT_EQ(test::run_hashes(scene, 2), one);
  EXPECT_EQ(test::run_hashes(scene, 7), one);
  Scene other = scene;
  other.seed = 2;
  EXPECT_NE(test::run_hashes(other, 2).at("morphologies/0.swc"), one.at("morphologies/0.swc"));
}

// Every SWC is a tree: ids 1..n in order, every parent an earlier sample, the soma the only
// root; a stem starts at the soma; types are 2 and 3; morphometry reads it back.
RC_GTEST_PROP(arbours, EverySwcIsATreeWithParentsFirst, ()) {
  const Scene scene = *gen_arbour_scene();
  RunOptions o;
  const RunResult r = run_scene(scene, o);
  for (std::size_t i = 0; i < r.arbours.size(); ++i) {
    const std::vector<morphology::ArbourSample> s = morphology::arbour_samples(r.arbours[i]);
    RC_ASSERT(s.size() == r.arbours[i].point.size());
    for (std::size_t j = 0; j < s.size(); ++j) {
      RC_ASSERT(s[j].parent >= 1u && s[j].parent < j + 2);
      RC_ASSERT(s[j].type == morphology::kAxonType || s[j].type == morphology::kDendriteType);
      const morphology::Cone& c = r.arbours[i].cones[s[j].cone];
      if (c.parent == morphology::kNoCone && (j == 0 || s[j - 1].cone != s[j].cone)) RC_ASSERT(s[j].parent == 1u);
      if (s[j].parent > 1) RC_ASSERT(s[s[j].parent - 2].type == s[j].type);  // a neurite never changes type
      RC_ASSERT(s[j].step <= scene.steps);
    }
    // The cones are numbered by the tree: a daughter after its parent, born when it branched;
    // a lateral branch after the cone whose point it starts from, made before it was born.
    const morphology::Arbour& a = r.arbours[i];
    for (std::size_t c = 0; c < a.cones.size(); ++c) {
      const morphology::Cone& k = a.cones[c];
      if (k.parent == morphology::kNoCone) continue;
      RC_ASSERT(k.parent < c);
      if (k.attach == morphology::kNoPoint) {
        RC_ASSERT(a.cones[k.parent].status == morphology::ConeStatus::kBranched);
        RC_ASSERT(a.cones[k.parent].ended == k.born);
      } else {
        RC_ASSERT(a.cone_of[k.attach] == k.parent);
        RC_ASSERT(a.step_of[k.attach] <= k.born);
      }
      RC_ASSERT(k.order == std::min(255, a.cones[k.parent].order + 1));
    }
    const morphology::Morphology m = morphology::parse_swc(swc_text(r, i), "neuron.swc");
    RC_ASSERT(m.samples.size() == s.size() + 1);
  }
}

// A cone's length is its points' path length when every step makes a point (the axon
// length in neurons.csv is their sum), and the chords of a sampled path are at most 1 %
// shorter with the culture's sample length (4 um against a persistence length of 250 um).
TEST(arbours, NeuronLengthIsTheAxonsPathLength) {
  for (const double sample : {0.0, 4.0}) {
  Scene scene = culture();
  scene.neurons.count = 40;
  scene.arbours->sample_length = sample;
  RunOptions o;
  const RunResult r = run_scene(scene, o);
  for (std::size_t i = 0; i < r.arbours.size(); ++i) {
    const morphology::Arbour& a = r.arbours[i];
    const std::vector<morphology::ArbourSample> s = morphology::arbour_samples(a);
    double path = 0.0;
    for (std::size_t j = 0; j < s.size(); ++j)
      if (s[j].type == morphology::kAxonType && s[j].parent > 1 &&
          !(a.cones[s[j].cone].parent == morphology::kNoCone && s[s[j].parent - 2].cone != s[j].cone))
        path += core::norm(s[j].pos - s[s[j].parent - 2].pos);
    if (sample == 0.0) {
      EXPECT_NEAR(r.neurons.length[i], path, 1e-9 * (1.0 + path)) << "neuron " << i;
    } else {
      EXPECT_LE(path, r.neurons.length[i] * (1 + 1e-12)) << "neuron " << i;
      EXPECT_GE(path, 0.99 * r.neurons.length[i]) << "neuron " << i;
    }
  }
  }
}

// A run interrupted right after it wrote its checkpoint of step `at` into `dir` (an
// Interrupted thrown, as the command's stop would), and that checkpoint read back.
RunCheckpoint interrupted_at(const Scene& scene, std::uint32_t at, const fs::path& dir) {
  RunOptions first;
  first.on_checkpoint = [&](const RunResult& progress, std::uint32_t step, const EngineState& e) {
    if (step == at) write_checkpoint(dir, progress, step, e);
  };
  first.stop_requested = [&] { return fs::exists(dir / kCheckpointName); };
  EXPECT_THROW(run_scene(scene, first), Interrupted);
  return read_checkpoint(dir / kCheckpointName);
}

// The output hashes of the run resumed from `c` (written on 2 threads).
std::map<std::string, std::string> resumed_hashes(const Scene& scene, RunCheckpoint& c) {
  RunOptions resumed;
  resumed.resume = &c;
  const RunResult r = run_scene(scene, resumed);
  test::TempDir out;
  write_outputs(r, out.path(), "test", 2, {});
  return test::output_hashes(out.path());
}

// A checkpoint after step 37 resumes to the uninterrupted bytes.
TEST(arbours, ACheckpointCarriesTheArbours) {
  Scene scene = culture();
  scene.neurons.count = 60;
  scene.arbours->axon.lateral_rate = 0.0005;  // per um per h: lateral branches too
  scene.output.paths = true;
  scene.output.checkpoint_every = 37;
  const auto want = test::run_hashes(scene, 2);
  test::TempDir dir;
  RunCheckpoint c = interrupted_at(scene, 37, dir.path());
  ASSERT_EQ(c.step, 37u);
  EXPECT_FALSE(c.engine.arbour.empty());
  EXPECT_EQ(resumed_hashes(scene, c), want);
}

// Cue-steered arbours (the axons' continuum steering, core/guide.hpp, for every cone): a
// small arbour scene in a ball with one attractant, for each field and both decision rules.
Scene steered_scene(const char* field, const char* decision, std::uint64_t seed) {
  return parse_scene(fmt::format(R"({{"seed": {}, "steps": 30, "dt": 0.5,
      "neurons": {{"count": 40, "soma_radius": 0.25, "region": {{"radius": 8}}}},
      "guidance": {{"model": "snr", "decision": "{}", "integration_time": 2}},
      "cues": {{"field": "{}", "sources": [{{"kind": "attractant", "position": [6, 0, 0]}}]}},
      "arbours": {{"axon": {{"B": 2, "v0": 0.3, "tau": 10, "persistence_length": 20}},
                   "dendrites": {{"B": 1, "v0": 0.1, "stem_rate": 0.2}}}},
      "output": {{"paths": true, "swc": true, "frames_every": 10}}}})",
                                 seed, decision, field),
                     "steered.json")
      .scene;
}

TEST(arbours, CueSteeredConesOnOneTwoAndSevenThreads) {
  for (const char* field : {"analytic", "grid", "particles"})
    for (const char* decision : {"per_interval", "per_step"}) {
      const Scene scene = steered_scene(field, decision, 3);
      const auto one = test::run_hashes(scene, 1);
      EXPECT_EQ(test::run_hashes(scene, 2), one) << field << " " << decision;
      EXPECT_EQ(test::run_hashes(scene, 7), one) << field << " " << decision;
    }
}

// A checkpoint in the middle of a decision interval (T = 4 steps, saved after step 37)
// carries the cones' sums and the field: the resumed run gives the uninterrupted bytes.
TEST(arbours, ACheckpointCarriesTheConesDecisionSums) {
  for (const char* field : {"analytic", "particles"}) {
    Scene scene = steered_scene(field, "per_interval", 5);
    scene.steps = 60;
    scene.output.checkpoint_every = 37;
    const auto want = test::run_hashes(scene, 2);
    test::TempDir dir;
    RunCheckpoint c = interrupted_at(scene, 37, dir.path());
    ASSERT_EQ(c.step, 37u);
    EXPECT_EQ(resumed_hashes(scene, c), want) << field;
  }
}

// Earlier checkpoint formats (3: arbours without the cones' sums; 4: the sums by growing
// cone) are refused by name.
TEST(arbours, AnEarlierCheckpointFormatIsRefusedByName) {
  for (const char* format : {"3", "4"}) {
    test::TempDir dir;
    std::ofstream(dir.path() / kCheckpointName, std::ios::binary)
        << "AXGCKPT" << format << std::string(4096, '\0');
    try {
      read_checkpoint(dir.path() / kCheckpointName);
      FAIL() << "a format-" << format << " checkpoint was read";
    } catch (const RunError& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("checkpoint format ") + format), std::string::npos) << e.what();
    }
  }
}

// The cones climb the gradient: the cosine between an axon terminal's displacement from its
// soma and the direction from the soma to the attractant exceeds the same scene's under direct guidance (the
// control: the same seeds, no cue) by more than 4 standard errors of the difference. (The
// control's own cosine is not 0: the bounds stop the cones that grow outward early.)
TEST(arbours, CueSteeredAxonsGrowTowardTheAttractant) {
  const core::Vec3 source{6, 0, 0};
  auto toward = [&](const Scene& scene) {
    RunOptions o;
    const RunResult r = run_scene(scene, o);
    std::vector<double> v;
    for (std::size_t i = 0; i < r.arbours.size(); ++i) {
      const morphology::Arbour& a = r.arbours[i];
      for (std::size_t c = 0; c < a.cones.size(); ++c) {
        const morphology::Cone& k = a.cones[c];
        if (k.type != morphology::kAxonType || k.status == morphology::ConeStatus::kBranched) continue;
        const core::Vec3 d = k.tip - r.soma[i], to = source - r.soma[i];
        const double n = core::norm(d);
        if (n > 0.5) v.push_back(core::dot(d, to) / (n * core::norm(to)));
      }
    }
    return v;
  };
  auto mean_se = [](const std::vector<double>& v) {
    double m = 0, q = 0;
    for (double x : v) m += x;
    m /= static_cast<double>(v.size());
    for (double x : v) q += (x - m) * (x - m);
    return std::pair{m, std::sqrt(q / static_cast<double>(v.size() - 1) / static_cast<double>(v.size()))};
  };
  Scene cue = steered_scene("analytic", "per_interval", 11);
  cue.neurons.count = 200;
  cue.steps = 60;
  Scene control = cue;
  control.guidance.model = GuidanceModel::kDirect;
  const auto [m1, s1] = mean_se(toward(cue));
  const auto [m0, s0] = mean_se(toward(control));
  RecordProperty("cue", std::to_string(m1));
  RecordProperty("control", std::to_string(m0));
  EXPECT_GT(m1 - m0, 4.0 * std::sqrt(s1 * s1 + s0 * s0)) << "cue " << m1 << " +- " << s1 << ", control " << m0 << " +- " << s0;
}

// A culture steered by an imposed gradient in its plane (the explant assay's guidance, on
// every cone): the cones stay in the growth layer, and the same bytes on 1 and 2 threads.
TEST(arbours, ACueSteeredCultureStaysInItsGrowthLayer) {
  auto j = nlohmann::json::parse(test::read_file(fs::path(test::source_dir()) / "scenes" / "culture.json"));
  j["neurons"]["count"] = 40;
  j["steps"] = 60;
  j["guidance"] = {{"model", "snr"}, {"noise", "snapshot"}, {"gain", 40}, {"integration_time", 1.0},
                   {"growth_cone_width", 10}, {"sensing_radius", 10}};
  j["cues"] = {{"field", "imposed"},
               {"imposed", {{"profile", "exponential"}, {"direction", {1, 0, 0}}, {"steepness", 0.2}}},
               {"sources", {{{"kind", "attractant"}, {"position", {0, 0, 0}}, {"kd", 1}}}}};
  j["output"] = {{"paths", true}};
  const Scene scene = parse_scene(j.dump(), "steered-culture.json").scene;
  RunOptions o;
  const RunResult r = run_scene(scene, o);
  std::size_t points = 0;
  for (const morphology::Arbour& a : r.arbours)
    for (const core::Vec3& p : a.point) {
      ASSERT_GE(p.z, 0.0);
      ASSERT_LE(p.z, scene.arbours->slab);
      ++points;
    }
  EXPECT_GT(points, 1000u);
  EXPECT_EQ(test::run_hashes(scene, 1), test::run_hashes(scene, 2));
}

// Lateral (interstitial) branching alone (B = 0, F = 0, straight cones, no bounds reached):
// the cones' mean count follows the linear process's exact discrete recursion, n_k =
// n_(k-1) + lambda dt L_k with L_k = L_(k-1) + v0 dt n_(k-1) (each step every cone moves,
// then Poisson(lambda L dt) branches start along the path), whose limit is
// cosh(sqrt(lambda v0) T). Every lateral cone's first SWC sample hangs on its branch point.
TEST(arbours, LateralBranchingFollowsTheLinearProcess) {
  const double lambda = 0.25, v0 = 1.0, dt = 0.1;
  const std::uint32_t steps = 40;
  const Scene scene = parse_scene(fmt::format(R"({{"seed": 8, "steps": {}, "dt": {},
      "neurons": {{"soma_radius": 0.01, "region": {{"radius": 60}},
                  "populations": [{{"count": 3000, "center": [0, 0, 0], "radius": 20}}]}},
      "guidance": {{"model": "direct"}},
      "arbours": {{"soma_contact": "pass", "sample_length": 0.3,
                   "axon": {{"B": 0, "v0": {}, "stems": [0, 1], "lateral_rate": {}}}}}}})",
                                              steps, dt, v0, lambda),
                                  "lateral.json")
                          .scene;
  RunOptions o;
  const RunResult r = run_scene(scene, o);
  double sum = 0, sq = 0;
  std::size_t laterals = 0;
  for (const morphology::Arbour& a : r.arbours) {
    const double n = static_cast<double>(a.cones.size());
    sum += n, sq += n * n;
    const std::vector<morphology::ArbourSample> s = morphology::arbour_samples(a);
    for (std::size_t j = 0; j < s.size(); ++j) {
      const morphology::Cone& c = a.cones[s[j].cone];
      ASSERT_EQ(c.status, morphology::ConeStatus::kGrowing);  // none stopped: the process is linear
      if (c.attach == morphology::kNoPoint || (j > 0 && s[j - 1].cone == s[j].cone)) continue;
      ++laterals;  // its first sample: it hangs on the branch point's sample
      ASSERT_EQ(s[s[j].parent - 2].pos, a.point[c.attach]);
    }
  }
  const double m = static_cast<double>(r.arbours.size());
  const double mean = sum / m, se = std::sqrt((sq / m - mean * mean) / (m - 1));
  double n = 1, length = 0;
  for (std::uint32_t k = 1; k <= steps; ++k) {
    length += v0 * dt * n;
    n += lambda * dt * length;
  }
  const double limit = std::cosh(std::sqrt(lambda * v0) * dt * steps);
  RecordProperty("mean", std::to_string(mean));
  EXPECT_LT(std::fabs(mean - n) / se, 4.0) << "simulated " << mean << " +- " << se << ", recursion " << n;
  EXPECT_NEAR(n, limit, 0.1 * limit) << "the recursion at dt = 0.1 is within 10 % of its limit";
  EXPECT_GT(laterals, 3000u);
}

// VTK: the last frame holds one polyline per cone that made a point, each from its parent's
// branch point (a stem from its own first point): points = samples + daughters drawn.
TEST(arbours, VtkHasOnePolylinePerCone) {
  Scene scene = culture();
  scene.neurons.count = 30;
  scene.output.vtk = true;
  scene.output.frames_every = 100;
  RunOptions o;
  const RunResult r = run_scene(scene, o);
  test::TempDir dir;
  write_outputs(r, dir.path(), "test", 2, {});
  std::size_t lines = 0, points = 0;
  for (const morphology::Arbour& a : r.arbours) {
    const std::vector<morphology::ArbourSample> s = morphology::arbour_samples(a);
    points += s.size();
    for (std::size_t j = 0; j < s.size(); ++j)
      if (j == 0 || s[j].cone != s[j - 1].cone) {
        ++lines;
        if (s[j].parent > 1 && s[s[j].parent - 2].cone != s[j].cone) ++points;
      }
  }
  const std::string vtp = test::read_file(dir.path() / "vtk" / fmt::format("axons_{:06d}.vtp", r.steps_run));
  EXPECT_NE(vtp.find(fmt::format("NumberOfPoints=\"{}\"", points)), std::string::npos);
  EXPECT_NE(vtp.find(fmt::format("NumberOfLines=\"{}\"", lines)), std::string::npos);
  EXPECT_NE(vtp.find("Name=\"order\""), std::string::npos);
  EXPECT_TRUE(fs::exists(dir.path() / "growth.pvd"));
}

// Bad input: exit 2 naming the key, the value and the allowed range.
TEST(arbours, BadParametersAreRefusedWithTheirKeyAndRange) {
  struct Case {
    const char* text;
    const char* key;
    const char* allowed;
  };
  const Case cases[] = {
      {R"({"arbours": {"axon": {"B": -1}}})", "arbours.axon.B", ">= 0"},
      {R"({"arbours": {"axon": {"v0": -0.5}}})", "arbours.axon.v0", ">= 0"},
      {R"({"arbours": {"dendrites": {"stem_rate": -2}}})", "arbours.dendrites.stem_rate", ">= 0"},
      {R"({"arbours": {"axon": {"lateral_rate": -0.01}}})", "arbours.axon.lateral_rate", ">= 0"},
      {R"({"arbours": {"axon": {"E": -0.1}}})", "arbours.axon.E", ">= 0"},
      {R"({"arbours": {"dendrites": {"tau": 0}}})", "arbours.dendrites.tau", "> 0"},
      {R"({"arbours": {"axon": {"tau": -3}}})", "arbours.axon.tau", "> 0"},
      {R"({"arbours": {"dendrites": {"stems": [0.5, 0.6]}}})", "arbours.dendrites.stems", "sum to 1"},
      {R"({"arbours": {"dendrites": {"stems": [1.5, -0.5]}}})", "arbours.dendrites.stems[1]", "non-negative"},
      {R"({"arbours": {"dendrites": {"stems": []}}})", "arbours.dendrites.stems", "distribution"},
      {R"({"arbours": {"dendrites": {"stems": "six"}}})", "arbours.dendrites.stems", "distribution"},
      {R"({"arbours": {"axon": {"angle": 0}}})", "arbours.axon.angle", "(0, 3.14"},
      {R"({"arbours": {"axon": {"angle": 3.2}}})", "arbours.axon.angle", "(0, 3.14"},
      {R"({"arbours": {"axon": {"taper": 1.5}}})", "arbours.axon.taper", "(0, 1]"},
      {R"({"arbours": {"axon": {"branching": 1}}})", "arbours.axon.branching", "allowed"},
  };
  for (const Case& c : cases) {
    try {
      parse_scene(c.text, "scene.json");
      ADD_FAILURE() << c.text << " was accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.key(), c.key) << c.text;
      EXPECT_NE(std::string(e.what()).find(c.allowed), std::string::npos) << c.text << ": " << e.what();
    }
  }
  // Through the command: exit 2, and the message names the key.
  test::TempDir dir;
  const fs::path scene = dir.path() / "bad.json";
  {
    std::ofstream f(scene);
    f << R"({"arbours": {"axon": {"E": -1}}})";
  }
  const auto [code, out] = test::run_command(fmt::format("run {} --out {}", scene.string(), (dir.path() / "o").string()));
  EXPECT_EQ(code, 2) << out;
  EXPECT_NE(out.find("arbours.axon.E"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir.path() / "o"));
}

TEST(arbours, WhatIsNotBuiltIsRefusedBeforeAnythingRuns) {
  EXPECT_THROW(parse_scene(R"({"units": {"length": "um", "time": "min", "concentration": "nM"},
      "axons": {"growth_model": "signalling"}, "cues": {"field": "analytic"}, "arbours": {}})", "s.json"), InputError);
  EXPECT_THROW(parse_scene(R"({"guidance": {"model": "snr"}, "axons": {"growth_modulation": 0.5},
      "cues": {"sources": [{"position": [0, 0, 0]}]}, "arbours": {}})", "s.json"), InputError);
  EXPECT_THROW(parse_scene(R"({"arbours": {"slab": 2}})", "s.json"), InputError);  // a layer needs a disc
}

// Scenes without arbours keep their canonical form: the section is written only when given.
TEST(arbours, ScenesWithoutArboursKeepTheirCanonicalForm) {
  EXPECT_FALSE(scene_to_json(Scene{}).contains("arbours"));
  const Scene c = culture();
  ASSERT_TRUE(c.arbours.has_value());
  const nlohmann::json j = scene_to_json(c);
  EXPECT_EQ(scene_to_json(parse_scene(j.dump(), "canonical").scene), j);
}

// The memory estimate counts the arbours: a scene that cannot fit exits 3 before it runs.
TEST(arbours, TheMemoryEstimateGrowsWithTheArbours) {
  Scene small = culture();
  Scene big = small;
  big.arbours->axon.b = 12.0;
  big.arbours->axon.e = 0.0;
  EXPECT_GT(expected_arbour_points(big), 2.0 * expected_arbour_points(small));
  EXPECT_GT(estimate_run_bytes(big), estimate_run_bytes(small));
  big.neurons.count = 1u << 30;
  big.neurons.radius = 1e6;
  EXPECT_THROW(run_scene(big, RunOptions{}), RunError);
}

}  // namespace
}  // namespace axg

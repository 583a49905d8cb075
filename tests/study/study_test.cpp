// Assay metrics, sweeps and the fit's data reader (docs/methods.md §12).
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <fstream>

#include "axonguide/assay.hpp"
#include "axonguide/error.hpp"
#include "axonguide/fit.hpp"
#include "axonguide/placement.hpp"
#include "axonguide/sweep.hpp"
#include "support.hpp"

namespace axg {
namespace {

using core::Vec3;
using nlohmann::json;

// An explant scene (imposed gradient along +x) and a state with every tip set by hand.
Scene explant_scene(std::uint64_t n) {
  Scene s;
  s.neurons.count = n;
  s.neurons.radius = 50;
  s.neurons.populations = {{n, {0.0, 0.0, 0.0}, 5.0}};
  s.cues.field = FieldKind::kImposed;
  s.cues.sources = {Source{}};
  s.cues.sources[0].position = Vec3{0.0, 0.0, 0.0};
  return s;
}

NeuronState state_with_tips(const std::vector<Vec3>& tips) {
  NeuronState st;
  st.resize(tips.size());
  for (std::size_t i = 0; i < tips.size(); ++i) {
    st.tip[i] = tips[i];
    st.length[i] = 1.0;
    st.status[i] = core::AxonStatus::kMaxSteps;
  }
  return st;
}

TEST(assay, AllTipsUpGradientGiveTheLargestBiasAndRatioOne) {
  const Scene s = explant_scene(10);
  std::vector<Vec3> tips(10, Vec3{20.0, 0.0, 0.0});
  const std::vector<Vec3> soma(10, Vec3{0.0, 0.0, 0.0});
  const auto m = assay::measure(s, soma, state_with_tips(tips), {});
  // The tips lie at θ = 90°, in the sector centred at 85°.
  EXPECT_NEAR(m.bias, 2.0 * std::sin(85.0 * M_PI / 180.0), 1e-12);
  EXPECT_DOUBLE_EQ(m.guidance_ratio, 1.0);
  EXPECT_DOUBLE_EQ(m.mean_outgrowth, 20.0);
  std::vector<Vec3> down(10, Vec3{-20.0, 0.0, 0.0});
  const auto d = assay::measure(s, soma, state_with_tips(down), {});
  EXPECT_NEAR(d.bias, -m.bias, 1e-12);
  EXPECT_DOUBLE_EQ(d.guidance_ratio, -1.0);
}

TEST(assay, FourfoldSymmetricOutgrowthHasNoBias) {
  const Scene s = explant_scene(4);
  // The imaging plane holds the gradient (x) and the across axis (y); z is the view axis.
  const std::vector<Vec3> tips{{10.0, 0.0, 0.0}, {-10.0, 0.0, 0.0}, {0.0, 10.0, 0.0}, {0.0, -10.0, 0.0}};
  const auto m = assay::measure(s, std::vector<Vec3>(4), state_with_tips(tips), {});
  EXPECT_NEAR(m.bias, 0.0, 1e-12);
  EXPECT_NEAR(m.guidance_ratio, 0.0, 1e-12);
}

// Mirroring every tip through the plane perpendicular to the gradient negates the bias and
// the guidance ratio; mirroring through the gradient axis (across -> -across) keeps them.
RC_GTEST_PROP(assay, MirrorsNegateOrKeepTheBias, ()) {
  const auto n = *rc::gen::inRange<std::size_t>(3, 40);
  const Scene s = explant_scene(n);
  std::vector<Vec3> tips, up_down, left_right;
  for (std::size_t i = 0; i < n; ++i) {
    // Tips off the sector edges (odd multiples of 1/64 of a turn never hit a 10° edge at 0 or 180).
    const double x = *rc::gen::inRange(-1000, 1000) / 37.0 + 0.013, y = *rc::gen::inRange(-1000, 1000) / 41.0 + 0.017;
    const double z = *rc::gen::inRange(-100, 100) / 10.0;
    tips.push_back({x, y, z});
    up_down.push_back({-x, y, z});
    left_right.push_back({x, -y, z});
  }
  const std::vector<Vec3> soma(n);
  const auto a = assay::measure(s, soma, state_with_tips(tips), {});
  const auto b = assay::measure(s, soma, state_with_tips(up_down), {});
  const auto c = assay::measure(s, soma, state_with_tips(left_right), {});
  RC_ASSERT(std::fabs(a.bias + b.bias) < 1e-9);
  RC_ASSERT(std::fabs(a.guidance_ratio + b.guidance_ratio) < 1e-12);
  RC_ASSERT(std::fabs(a.bias - c.bias) < 1e-9);
  RC_ASSERT(std::fabs(a.mean_outgrowth - c.mean_outgrowth) < 1e-9);
}

TEST(assay, TargetAndCrossingFractionsCountThePopulations) {
  Scene s;
  s.neurons.radius = 20;
  s.neurons.populations = {{2, {-5.0, 0.0, 0.0}, 1.0}, {2, {5.0, 0.0, 0.0}, 1.0}};
  s.neurons.count = 4;
  NeuronState st = state_with_tips({{6.0, 0.0, 0.0}, {-4.0, 0.0, 0.0}, {-6.0, 0.0, 0.0}, {4.0, 0.0, 0.0}});
  st.status[0] = core::AxonStatus::kConnected;
  st.target[0] = 3;  // population 1
  const auto m = assay::measure(s, std::vector<Vec3>(4), st, {});
  EXPECT_DOUBLE_EQ(m.target_fraction, 0.5);
  EXPECT_DOUBLE_EQ(m.crossing_fraction, 0.5);  // neuron 0 (to +x) and neuron 2 (to -x) crossed
  EXPECT_EQ(m.crossing_axons, 4u);
}

TEST(assay, PopulationsPlaceEachNeuronInItsBall) {
  Scene s;
  s.neurons.radius = 20;
  s.neurons.soma_radius = 0.1;
  s.neurons.populations = {{50, {-8.0, 0.0, 0.0}, 2.0}, {30, {8.0, 3.0, 0.0}, 1.5}};
  s.neurons.count = 80;
  const Placement p = place_neurons(s);
  for (std::size_t i = 0; i < 80; ++i) {
    const Population& pop = s.neurons.populations[i < 50 ? 0 : 1];
    EXPECT_LE(std::sqrt(core::norm2(p.soma[i] - pop.center)), pop.radius) << i;
  }
}

// A small sweep over the midline barrier: 3 emissions x 2 seeds.
json midline_sweep() {
  return json::parse(R"({
    "scene": "midline.json",
    "parameters": [{"name": "emission", "key": "cues.sources.*.emission", "values": [0, 100, 1000]}],
    "seeds": 2})");
}

std::string slurp(const std::filesystem::path& p) { return test::read_file(p); }

TEST(sweep, BytesAreThreadInvariantAndARerunReusesVerifiedRecords) {
  const sweep::Spec spec = sweep::parse_spec(midline_sweep(), "test", std::filesystem::path(AXG_SOURCE_DIR) / "scenes");
  ASSERT_EQ(sweep::member_count(spec), 6u);
  test::TempDir a, b;
  sweep::Options o1, o2;
  o1.threads = 1;
  o2.threads = 2;
  const auto ra = sweep::run(spec, a.path(), o1);
  sweep::run(spec, b.path(), o2);
  EXPECT_EQ(ra.failed, 0u);
  for (const char* f : {"sweep.csv", "summary.csv", "sweep.json"})
    EXPECT_EQ(slurp(a.path() / f), slurp(b.path() / f)) << f;
  // The barrier works: the crossing fraction falls with the emission.
  EXPECT_GT(ra.members[0].metrics[11].second, ra.members[4].metrics[11].second);

  const auto again = sweep::run(spec, a.path(), o2);
  EXPECT_EQ(again.skipped, 6u);
  EXPECT_EQ(slurp(a.path() / "sweep.csv"), slurp(b.path() / "sweep.csv"));
  // A tampered record is not verified: that member runs again and gives the same bytes.
  {
    const auto rec = sweep::record_path(a.path(), 3);
    std::string text = slurp(rec);
    text.replace(text.find("\"seed\""), 6, "\"seeD\"");
    std::ofstream(rec) << text;
  }
  const auto third = sweep::run(spec, a.path(), o1);
  EXPECT_EQ(third.skipped, 5u);
  EXPECT_EQ(slurp(a.path() / "sweep.csv"), slurp(b.path() / "sweep.csv"));
}

TEST(sweep, AFailedMemberIsRecordedAndTheOthersRun) {
  // 20 neurons fit in a population of radius 2 LU; 20000 do not (RunError, exit 3).
  json j = json::parse(R"({
    "scene": {"steps": 5, "neurons": {"soma_radius": 0.1, "region": {"radius": 5},
              "populations": [{"count": 20, "center": [0, 0, 0], "radius": 2}]}, "guidance": {"model": "direct"}},
    "parameters": [{"key": "neurons.populations.0.count", "values": [20, 20000]}],
    "seeds": 2})");
  const sweep::Spec spec = sweep::parse_spec(j, "test", ".");
  test::TempDir d;
  const auto r = sweep::run(spec, d.path(), {});
  EXPECT_EQ(r.failed, 2u);
  EXPECT_TRUE(r.members[0].ok);
  EXPECT_FALSE(r.members[2].ok);
  EXPECT_EQ(r.members[2].exit_code, kExitCannotRun);
  EXPECT_NE(r.members[2].message.find("packing"), std::string::npos);
  const std::string csv = slurp(d.path() / "sweep.csv");
  EXPECT_NE(csv.find(",failed,3,"), std::string::npos);
  const std::string summary = slurp(d.path() / "summary.csv");
  EXPECT_NE(summary.find("\n1,20000,2,0,2,"), std::string::npos) << summary;
}

TEST(sweep, BadSpecsNameTheKey) {
  const auto dir = std::filesystem::path(AXG_SOURCE_DIR) / "scenes";
  auto expect_error = [&](const std::string& text, const std::string& needle) {
    try {
      sweep::parse_spec(json::parse(text), "s.json", dir);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expect_error(R"({"parameters": []})", "needs \"scene\"");
  expect_error(R"({"scene": "midline.json", "bogus": 1})", "unknown key bogus");
  expect_error(R"({"scene": "midline.json", "parameters": [{"key": "guidance.gain", "values": [-1]}]})",
               "guidance.gain");
  expect_error(R"({"scene": "midline.json", "parameters": [{"key": "cues.sources.9.kd", "values": [1]}]})",
               "must index");
  expect_error(R"({"scene": "midline.json", "seeds": 0})", "seeds");
  expect_error(R"({"scene": "midline.json", "parameters": [{"key": "guidance.gain", "log": {"from": 0, "to": 1, "count": 3}}]})",
               "from and to must be > 0");
}

// A sweep file and the scene file it names are read as strictly as a scene.
TEST(sweep, DuplicateKeysAndTrailingBytesAreRefused) {
  test::TempDir d;
  const auto scenes = std::filesystem::path(AXG_SOURCE_DIR) / "scenes";
  auto expect_error = [&](const std::string& name, const std::string& text, const std::string& needle) {
    const auto p = d.path() / name;
    std::ofstream(p, std::ios::binary) << text;
    try {
      sweep::load_spec(p.string());
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  const std::string scene = (scenes / "midline.json").string();
  expect_error("a.sweep.json", fmt::format(R"({{"scene": "{}", "seeds": 2, "seeds": 3}})", scene),
               "duplicate key seeds:");
  expect_error("b.sweep.json",
               fmt::format(R"({{"scene": "{}", "parameters": [{{"key": "guidance.gain", "values": [1], "key": "dt"}}]}})",
                           scene),
               "duplicate key parameters[0].key:");
  expect_error("c.sweep.json", fmt::format("{{\"scene\": \"{}\"}}", scene) + std::string("\0", 1), "NUL byte");
  std::ofstream(d.path() / "dup.json") << R"({"neurons": {"count": 10}, "neurons": {"count": 20}})";
  expect_error("d.sweep.json", R"({"scene": "dup.json"})", "scene " + (d.path() / "dup.json").string() +
                                                               ": duplicate key neurons:");
  expect_error("e.sweep.json", fmt::format(R"({{"scene": "{}", "bogus\u001b[2J": 1}})", scene),
               R"(unknown key bogus\u001b[2J ()");
}

TEST(sweep, LogGridsHitTheirEndsExactly) {
  const sweep::Spec spec = sweep::parse_spec(
      json::parse(R"({"scene": "assay-explant.json",
                      "parameters": [{"key": "cues.imposed.concentration", "log": {"from": 0.001, "to": 100, "count": 6}}]})"),
      "s", std::filesystem::path(AXG_SOURCE_DIR) / "scenes");
  const auto& v = spec.parameters[0].values;
  ASSERT_EQ(v.size(), 6u);
  EXPECT_EQ(v.front().get<double>(), 0.001);
  EXPECT_EQ(v.back().get<double>(), 100.0);
  EXPECT_NEAR(v[2].get<double>(), 0.1, 1e-15);
}

TEST(fit, MalformedDataNamesTheLine) {
  test::TempDir d;
  auto expect_error = [&](const std::string& text, const std::string& needle) {
    const auto p = d.path() / "data.csv";
    std::ofstream(p) << text;
    try {
      fit::load_data(p.string());
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  const std::string header = "concentration,steepness,bias,se,count\n";
  expect_error("conc,steepness,bias,se,count\n1,0.2,0.1,0.01,3\n", "missing \"concentration\"");
  expect_error(header + "1,0.2,0.1,0.01,3\n# a comment\n2,0.2,abc,0.01,3\n", "line 4: bias = \"abc\"");
  expect_error(header + "1,0.2,0.1,0.01,3\n2,0.2,0.1,0,3\n3,0.2,0.1,0.1,3\n", "line 3: se = 0");
  expect_error(header + "1,0.2,0.1,0.01\n", "line 2: 4 fields");
  expect_error(header + "-1,0.2,0.1,0.01,3\n", "line 2: concentration");
  expect_error(header + "1,0.2,0.1,0.01,2.5\n", "line 2: count");
  expect_error(header + "1,0.2,0.1,0.01,3\n", "at least 3");
}

int run_binary(const std::string& args) {
  const int status = std::system(fmt::format("{} {} >/dev/null 2>&1", test::binary(), args).c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
}

TEST(fit, ExitCodesFollowTheThresholdAndTheData) {
  test::TempDir d;
  const std::string data = (std::filesystem::path(AXG_SOURCE_DIR) / "data/assay/bicknell2018-summary.csv").string();
  json scene = json::parse(test::read_file(std::filesystem::path(AXG_SOURCE_DIR) / "scenes/assay-explant.json"));
  scene["neurons"]["populations"][0]["count"] = 100;
  scene["steps"] = 40;
  const auto base = d.path() / "base.json";
  std::ofstream(base) << scene.dump();
  const std::string common = fmt::format("--scene {} --seeds 2 --grid 2 --refine 0", base.string());
  EXPECT_EQ(run_binary(fmt::format("fit {} {} --out {}/a --max-chi2 1e6", data, common, d.path().string())), 0);
  EXPECT_TRUE(std::filesystem::exists(d.path() / "a/fit.json"));
  EXPECT_EQ(run_binary(fmt::format("fit {} {} --out {}/b --max-chi2 1e-9", data, common, d.path().string())), 1);
  std::ofstream(d.path() / "bad.csv") << "concentration,steepness,bias,se,count\n1,x,0,1,1\n";
  EXPECT_EQ(run_binary(fmt::format("fit {}/bad.csv {} --out {}/c", d.path().string(), common, d.path().string())), 2);
}

TEST(assay, CommandRefusesAFolderWhoseNeuronsDoNotMatchTheManifest) {
  test::TempDir d;
  const std::string scene = (std::filesystem::path(AXG_SOURCE_DIR) / "scenes/midline-control.json").string();
  ASSERT_EQ(run_binary(fmt::format("run {} --out {}/r -q", scene, d.path().string())), 0);
  EXPECT_EQ(run_binary(fmt::format("assay {}/r", d.path().string())), 0);
  EXPECT_TRUE(std::filesystem::exists(d.path() / "r/assay.csv"));
  std::ofstream(d.path() / "r/neurons.csv", std::ios::app) << "\n";
  EXPECT_EQ(run_binary(fmt::format("assay {}/r", d.path().string())), 2);
}

}  // namespace
}  // namespace axg

namespace axg {
namespace {

TEST(scene, BadPopulationsAreRefusedNamingTheKey) {
  auto expect_error = [](const std::string& text, const std::string& needle) {
    try {
      parse_scene(text, "t.json");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expect_error(R"({"neurons": {"region": {"radius": 5}, "populations": [{"count": 5, "center": [4, 0, 0], "radius": 2}]}})",
               "neurons.populations[0]");
  expect_error(R"({"neurons": {"count": 7, "populations": [{"count": 5, "radius": 2}]}})", "sum to 5");
  expect_error(R"({"neurons": {"region": {"shape": "sphere"}, "populations": [{"count": 5, "radius": 2}]}})", "sphere");
  expect_error(R"({"neurons": {"populations": []}})", "neurons.populations");
  expect_error(R"({"neurons": {"populations": [{"count": 5, "radius": 2, "colour": 1}]}})", "neurons.populations[0].colour");
  expect_error(R"({"neurons": {"populations": [{"count": 5, "radius": 0.1}]}})", "not above neurons.soma_radius");
  const Scene s = parse_scene(R"({"neurons": {"populations": [{"count": 5, "radius": 2}, {"count": 3, "center": [1, 1, 1], "radius": 1}]}})", "t").scene;
  EXPECT_EQ(s.neurons.count, 8u);
  EXPECT_EQ(s.neurons.population_of(4), 0u);
  EXPECT_EQ(s.neurons.population_of(5), 1u);
  // The canonical form round-trips, and a scene without populations keeps its old form.
  EXPECT_EQ(scene_to_json(parse_scene(scene_to_json(s).dump(), "c").scene), scene_to_json(s));
  EXPECT_FALSE(scene_to_json(Scene{})["neurons"].contains("populations"));
}

}  // namespace
}  // namespace axg

namespace axg {
namespace {

TEST(sweep, CommandExitCodes) {
  test::TempDir d;
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(d.path() / name) << text;
    return (d.path() / name).string();
  };
  const std::string scene = (std::filesystem::path(AXG_SOURCE_DIR) / "scenes/midline-control.json").string();
  const std::string ok = write("ok.json", fmt::format(R"({{"scene": "{}", "seeds": 2,
      "parameters": [{{"key": "steps", "values": [5, 10]}}]}})", scene));
  EXPECT_EQ(run_binary(fmt::format("sweep {} --out {}/a", ok, d.path().string())), 0);
  EXPECT_TRUE(std::filesystem::exists(d.path() / "a/summary.csv"));
  const std::string bad = write("bad.json", fmt::format(R"({{"scene": "{}", "parameters": [{{"key": "steps", "values": [-1]}}]}})", scene));
  EXPECT_EQ(run_binary(fmt::format("sweep {} --out {}/b", bad, d.path().string())), 2);
  EXPECT_FALSE(std::filesystem::exists(d.path() / "b/sweep.csv"));  // nothing ran
  const std::string failing = write("fail.json", R"({"scene": {"steps": 3, "neurons": {"soma_radius": 0.1, "region": {"radius": 5},
      "populations": [{"count": 10, "radius": 2}]}, "guidance": {"model": "direct"}},
      "parameters": [{"key": "neurons.populations.0.count", "values": [10, 100000]}]})");
  EXPECT_EQ(run_binary(fmt::format("sweep {} --out {}/c", failing, d.path().string())), 1);
  EXPECT_NE(test::read_file(d.path() / "c/sweep.csv").find(",ok,0,"), std::string::npos);
}

}  // namespace
}  // namespace axg

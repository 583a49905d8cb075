// Assay metrics, sweeps and the fit's data reader (docs/methods.md §12).
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <tuple>

#include "axonguide/study/assay.hpp"
#include "axonguide/support/error.hpp"
#include "axonguide/study/fit.hpp"
#include "axonguide/support/files.hpp"
#include "axonguide/placement/placement.hpp"
#include "axonguide/study/sweep.hpp"
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
  // A parameter's keys and sources: every key known, of its type, one source of values.
  expect_error(R"({"scene": "midline.json", "parameters": [{"keys": ["steps", 5], "values": [3]}]})",
               "parameters[0].keys[1] must be a string");
  expect_error(R"({"scene": "midline.json", "parameters": [{"key": 5, "values": [3]}]})", "parameters[0].key must be");
  expect_error(R"({"scene": "midline.json", "parameters": [{"key": "steps", "valeus": [3]}]})", "unknown key valeus");
  expect_error(R"({"scene": "midline.json", "parameters": [{"key": "steps", "name": 7, "values": [3]}]})",
               "parameters[0].name must be a string");
  expect_error(R"({"scene": "midline.json", "parameters": [{"key": "steps", "values": [3], "linear": {"from": 1, "to": 2, "count": 2}}]})",
               "give one of");
  expect_error(R"({"scene": "midline.json", "parameters": [{"name": "c", "key": "steps", "cases": {"a": {"steps": 3}}}]})",
               "name their keys inside each case");
  expect_error(R"({"scene": "midline.json", "parameters": [{"name": "c", "cases": {"a": {"seed": 3}}}]})",
               "parameters[0].cases.a: the seed is swept");
  // What would run one value under two labels, or one run twice.
  expect_error(R"({"scene": "midline.json", "parameters": [{"key": "steps", "values": [3]}, {"key": "steps", "name": "b", "values": [4]}]})",
               "key steps of parameter steps and key steps of parameter b set the same part of the scene");
  expect_error(R"({"scene": "midline.json", "parameters": [{"name": "e", "key": "cues.sources.*.emission", "values": [1]},
                   {"name": "f", "key": "cues.sources.0.emission", "values": [2]}]})",
               "key cues.sources.*.emission of parameter e and key cues.sources.0.emission of parameter f");
  expect_error(R"({"scene": "midline.json", "parameters": [{"name": "c", "cases": {"a": {"cues.sources.0": {"kind": "repellent"}}}},
                   {"name": "k", "key": "cues.sources.0.kind", "values": ["attractant"]}]})",
               "set the same part of the scene");
  expect_error(R"({"scene": "midline.json", "parameters": [{"key": "steps", "name": "a", "values": [3]}, {"key": "dt", "name": "a", "values": [0.5]}]})",
               "two parameters are named a");
  expect_error(R"({"scene": "midline.json", "seeds": [4, 1, 4]})", "seeds: 4 is given twice");
  expect_error(R"({"scene": "midline.json\u0000.evil"})", "a NUL byte in a path");
  // 65536^4 members wrap a 64-bit count to 0; the product is bounded as it is taken.
  expect_error(R"({"scene": "midline.json", "parameters": [
                   {"key": "steps", "linear": {"from": 1, "to": 2, "count": 65536}},
                   {"key": "dt", "linear": {"from": 1, "to": 2, "count": 65536}},
                   {"key": "guidance.gain", "linear": {"from": 1, "to": 2, "count": 65536}},
                   {"key": "neurons.count", "linear": {"from": 1, "to": 2, "count": 65536}}]})",
               "more than 10^7 members");
  expect_error(R"({"scene": "midline.json", "parameters": [{"key": "dt", "linear": {"from": -1e308, "to": 1e308, "count": 3}}]})",
               "is not a finite number");
  // A point's bad value names the point and its values.
  expect_error(R"({"scene": "midline.json", "parameters": [{"key": "steps", "values": [3, "abc"]}]})",
               "point 1 (steps=abc)");
}

// A grid of one value is its `from`, linear or log.
TEST(sweep, AOneValueGridIsItsFrom) {
  for (const char* kind : {"linear", "log"}) {
    const sweep::Spec spec = sweep::parse_spec(
        json::parse(fmt::format(R"({{"scene": "midline.json",
                                    "parameters": [{{"key": "guidance.gain", "{}": {{"from": 3, "to": 7, "count": 1}}}}]}})",
                                kind)),
        "s", std::filesystem::path(AXG_SOURCE_DIR) / "scenes");
    ASSERT_EQ(spec.parameters[0].values.size(), 1u) << kind;
    EXPECT_EQ(spec.parameters[0].values[0].get<double>(), 3.0) << kind;
  }
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
  // Nesting deep enough to exhaust the parser's stack (it crashed, at 100,000 levels), in the
  // sweep file and in the scene file it names; and inputs that are not regular files.
  const std::string deep = std::string(100000, '[') + std::string(100000, ']');
  expect_error("f.sweep.json", fmt::format(R"({{"scene": "{}", "parameters": [{{"key": "steps", "values": {}}}]}})",
                                           scene, deep),
               "JSON nested deeper than 64 levels");
  std::ofstream(d.path() / "deep.json") << R"({"neurons": )" << deep << "}";
  expect_error("g.sweep.json", R"({"scene": "deep.json"})", "nested deeper than");
  expect_error("h.sweep.json", R"({"scene": "/dev/zero"})", "not a regular file");
  std::filesystem::create_directories(d.path() / "adir");
  try {
    sweep::load_spec((d.path() / "adir").string());
    ADD_FAILURE() << "a folder was read as a sweep";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("is a directory"), std::string::npos) << e.what();
  }
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
  expect_error("conc,steepness,bias,se,count\n1,0.2,0.1,0.01,3\n", "line 1: unknown column \"conc\"");
  expect_error("steepness,bias,se,count\n0.2,0.1,0.01,3\n", "missing \"concentration\"");
  expect_error("concentration,steepness,se,count\n1,0.2,0.01,3\n", "no measured column");
  expect_error("concentration,steepness,bias,count\n1,0.2,0.1,3\n", "missing \"se\"");
  expect_error("concentration,steepness,bias,bias,se,count\n1,0.2,0.1,0.1,0.01,3\n", "column \"bias\" twice");
  expect_error("concentration,steepness,bias,outgrowth,se,count\n1,0.2,0.1,300,0.01,3\n", "\"se\" is ambiguous");
  expect_error("concentration,steepness,bias,outgrowth,bias_se,count\n1,0.2,0.1,300,0.01,3\n",
               "missing \"outgrowth_se\"");
  expect_error("concentration,steepness,outgrowth,outgrowth_se,count\n1,0.2,300,10,3\n",
               "one measured column: its SE is \"se\"");
  expect_error(header + "1,0.2,0.1,0.01,3\n# a comment\n2,0.2,abc,0.01,3\n", "line 4: bias = \"abc\"");
  expect_error(header + "1,0.2,0.1,0.01,1e30\n", "line 2: count = 1e+30 must be an integer in [1, 10^9]");
  expect_error(header + "1,0.2,0.1,0.01,3\n2,0.2,0.1,0,3\n3,0.2,0.1,0.1,3\n", "line 3: se = 0");
  expect_error(header + "1,0.2,0.1,0.01\n", "line 2: 4 fields");
  expect_error(header + "-1,0.2,0.1,0.01,3\n", "line 2: concentration");
  expect_error(header + "1,0.2,0.1,0.01,2.5\n", "line 2: count");
  expect_error(header + "1,0.2,0.1,0.01,3\n", "at least 3");
  expect_error(header + "1,0.2,nan,0.01,3\n", "line 2: bias = \"nan\" is not a finite number");
}

TEST(fit, DataReadsEitherMeasureOrBothInAnyColumnOrder) {
  const auto one = fit::parse_data("count,outgrowth,steepness,se,concentration\n3,300,0.1,10,0.5\n4,310,0.1,12,1\n"
                                   "# comment\n5,320,0,11,2\n", "o.csv");
  EXPECT_FALSE(one.measured[fit::kBias]);
  EXPECT_TRUE(one.measured[fit::kOutgrowth]);
  ASSERT_EQ(one.points.size(), 3u);
  EXPECT_EQ(one.points[1].concentration, 1.0);
  EXPECT_EQ(one.points[1].value[fit::kOutgrowth], 310.0);
  EXPECT_EQ(one.points[1].se[fit::kOutgrowth], 12.0);
  EXPECT_EQ(one.points[2].count, 5u);
  EXPECT_EQ(one.points[2].line, 5u);
  EXPECT_TRUE(std::isnan(one.points[0].value[fit::kBias]));
  const auto both = fit::parse_data("concentration,steepness,bias,bias_se,outgrowth,outgrowth_se,count\n"
                                    "1,0.2,0.1,0.01,300,10,3\n2,0.2,0.05,0.01,280,9,3\n3,0.2,0.0,0.02,260,8,3\n",
                                    "b.csv");
  EXPECT_EQ(both.measure_count(), 2);
  EXPECT_EQ(both.points[2].value[fit::kBias], 0.0);
  EXPECT_EQ(both.points[2].se[fit::kBias], 0.02);
  EXPECT_EQ(both.points[2].value[fit::kOutgrowth], 260.0);
  EXPECT_EQ(both.points[2].se[fit::kOutgrowth], 8.0);
}

TEST(fit, TheSharedDataSetsParse) {
  // data/bicknell2018/: byte-for-byte copies of the workplace's shared data (provenance in the headers).
  const std::filesystem::path dir = std::filesystem::path(AXG_SOURCE_DIR) / "data/bicknell2018";
  const auto g = fit::load_data((dir / "outgrowth-gradient.csv").string());
  EXPECT_TRUE(g.measured[fit::kOutgrowth]);
  EXPECT_EQ(g.points.size(), 40u);
  const auto u = fit::load_data((dir / "outgrowth-uniform.csv").string());
  EXPECT_EQ(u.points.size(), 8u);
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
  const std::string common = fmt::format("--scene {} --seeds 2 --max-seeds 2 --grid 2 --refine 0", base.string());
  EXPECT_EQ(run_binary(fmt::format("fit {} {} --out {}/a --max-chi2 1e6", data, common, d.path().string())), 0);
  EXPECT_TRUE(std::filesystem::exists(d.path() / "a/fit.json"));
  EXPECT_EQ(run_binary(fmt::format("fit {} {} --out {}/b --max-chi2 1e-9", data, common, d.path().string())), 1);
  std::ofstream(d.path() / "bad.csv") << "concentration,steepness,bias,se,count\n1,x,0,1,1\n";
  EXPECT_EQ(run_binary(fmt::format("fit {}/bad.csv {} --out {}/c", d.path().string(), common, d.path().string())), 2);
  // NaN passes every comparison CLI11 makes: it would turn the chi2 gate and the seed pilot off.
  EXPECT_EQ(run_binary(fmt::format("fit {} {} --out {}/e --max-chi2 nan", data, common, d.path().string())), 2);
  EXPECT_EQ(run_binary(fmt::format("fit {} {} --out {}/e --target-se nan", data, common, d.path().string())), 2);
  EXPECT_EQ(run_binary(fmt::format("fit /dev/zero {} --out {}/e", common, d.path().string())), 2);
  EXPECT_FALSE(std::filesystem::exists(d.path() / "e"));
}

// A data row that makes no valid model scene is refused before any run, naming its line;
// so is an --out that is a file.
TEST(fit, DataOutsideTheScenesLimitsAndHugeGridsAreRefusedBeforeAnyRun) {
  test::TempDir d;
  json scene = json::parse(test::read_file(std::filesystem::path(AXG_SOURCE_DIR) / "scenes/assay-explant.json"));
  scene["neurons"]["populations"][0]["count"] = 20;
  scene["steps"] = 5;
  const auto base = d.path() / "base.json";
  std::ofstream(base) << scene.dump();
  std::ofstream(d.path() / "data.csv") << "concentration,steepness,count,bias,se\n1,0.5,3,0.1,0.02\n2,0.5,3,0.15,0.02\n"
                                          "2,1e300,3,0.1,0.02\n";
  auto message = [&](const std::string& args) { return test::run_command("fit " + args); };
  const std::string common = fmt::format("--scene {} --seeds 1 --grid 2 --refine 0 --polish 0", base.string());
  auto [rc, out] = message(fmt::format("{}/data.csv {} --out {}/o", d.path().string(), common, d.path().string()));
  EXPECT_EQ(rc, 2) << out;
  EXPECT_NE(out.find("data line 4 (concentration 2, steepness 1e+300) makes no valid model scene"), std::string::npos)
      << out;
  std::ofstream(d.path() / "good.csv") << "concentration,steepness,count,bias,se\n1,0.5,3,0.1,0.02\n"
                                          "2,0.5,3,0.15,0.02\n2,1,3,0.1,0.02\n3,1,3,0.1,0.02\n";
  std::ofstream(d.path() / "afile") << "x";
  std::tie(rc, out) = message(fmt::format("{}/good.csv {} --out {}/afile", d.path().string(), common, d.path().string()));
  EXPECT_EQ(rc, 2) << out;
  EXPECT_NE(out.find("exists and is not a directory"), std::string::npos) << out;
  EXPECT_EQ(out.find("fit "), std::string::npos) << "refused before the fit ran: " << out;
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

// The folder's name reaches the plotting helper as one argument, never through a shell: a
// name with quotes and $(...) is a name (it ran the command inside it, before).
TEST(assay, AFolderNameIsNeverShellSyntax) {
  if (std::system("/usr/bin/python3 -c 'import matplotlib' >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "python3-matplotlib is not installed: the helper is not started";
  test::TempDir d;
  const std::string scene = (std::filesystem::path(AXG_SOURCE_DIR) / "scenes/midline-control.json").string();
  const std::filesystem::path run = d.path() / "r'$(touch PWNED)'", marker = d.path() / "PWNED";
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    if (::chdir(d.path().c_str()) != 0) ::_exit(126);
    ::execl(test::binary().c_str(), "axonguide", "run", scene.c_str(), "--out", run.c_str(), "-q",
            static_cast<char*>(nullptr));
    ::_exit(127);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  const pid_t assay = ::fork();
  ASSERT_GE(assay, 0);
  if (assay == 0) {
    if (::chdir(d.path().c_str()) != 0) ::_exit(126);
    const int devnull = ::open("/dev/null", O_WRONLY);
    ::dup2(devnull, 1);
    ::execl(test::binary().c_str(), "axonguide", "assay", run.filename().c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ASSERT_EQ(::waitpid(assay, &status, 0), assay);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  EXPECT_TRUE(std::filesystem::exists(run / "assay.png"));
  EXPECT_FALSE(std::filesystem::exists(marker)) << "the folder's name ran as a command";
}

// neurons.csv is read back as strictly as view reads it: rows a run does not write are
// refused, exit 2, naming the line (the manifest re-hashed, so only the data is wrong).
TEST(assay, RowsNoRunWritesAreRefused) {
  test::TempDir d;
  const std::string scene = (std::filesystem::path(AXG_SOURCE_DIR) / "scenes/midline-control.json").string();
  ASSERT_EQ(run_binary(fmt::format("run {} --out {}/r -q", scene, d.path().string())), 0);
  const auto dir = d.path() / "r";
  const std::string original = test::read_file(dir / "neurons.csv");
  const json manifest = json::parse(test::read_file(dir / "manifest.json"));
  const std::size_t header = original.find('\n') + 1, second = original.find('\n', header) + 1;
  for (const auto& [row, why] : {std::pair{"0,0,0,0,0.25,growing,0,0,0,0,nan,-1", "not finite"},
                                 std::pair{"0,0,0,0,0.25,flying,0,0,0,0,0,-1", "status \"flying\""},
                                 std::pair{"0,0,0,0,0.25,growing,0,0,0,-1,0,-1", "the length is negative"},
                                 std::pair{"0,0,0,0,0.25,growing,0,0,0,0,2.5,-1", "steps 2.5 is not an integer"},
                                 std::pair{"-1,0,0,0,0.25,growing,0,0,0,0,0,-1", "id -1 where 0 belongs"},
                                 std::pair{"0,0,0,0,0.25,growing,0,0,0,0,0,-7", "target -7 is not a neuron id"}}) {
    std::ofstream(dir / "neurons.csv", std::ios::binary) << original.substr(0, header) << row << "\n"
                                                         << original.substr(second);
    json m = manifest;
    m["files"]["neurons.csv"]["sha256"] = sha256_file(dir / "neurons.csv");
    std::ofstream(dir / "manifest.json") << m.dump(2);
    const auto [rc, out] = test::run_command("assay " + dir.string());
    EXPECT_EQ(rc, 2) << row << ": " << out;
    EXPECT_NE(out.find(why), std::string::npos) << row << ": " << out;
    EXPECT_NE(out.find("line 2"), std::string::npos) << row << ": " << out;
  }
  // Fewer rows than the scene's neurons (each row fine); then a manifest without its scene.
  std::ofstream(dir / "neurons.csv", std::ios::binary) << original.substr(0, second);
  json m = manifest;
  m["files"]["neurons.csv"]["sha256"] = sha256_file(dir / "neurons.csv");
  std::ofstream(dir / "manifest.json") << m.dump(2);
  const auto [rc, out] = test::run_command("assay " + dir.string());
  EXPECT_EQ(rc, 2) << out;
  EXPECT_NE(out.find("1 neurons, where the run's scene has"), std::string::npos) << out;
  m.erase("scene");
  std::ofstream(dir / "manifest.json") << m.dump(2);
  EXPECT_EQ(run_binary(fmt::format("assay {}", dir.string())), 2) << "a manifest without its scene";
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

namespace axg {
namespace {

// A small explant of the signalling model in uniform NGF: 40 neurons for 48 h.
json small_signalling_explant() {
  json scene = json::parse(test::read_file(std::filesystem::path(AXG_SOURCE_DIR) / "scenes/assay-bicknell.json"));
  scene["neurons"]["count"] = 40;
  scene["steps"] = 30;
  scene["dt"] = 1.6;
  return scene;
}

// The fit recovers known parameters from data the model made with other seeds: the truth
// (off every grid point) lies inside each profile-likelihood interval, and the intervals
// are closed and narrower than the searched range.
TEST(fit, RecoversKnownSignallingParametersWithinTheirIntervals) {
  const json base = small_signalling_explant();
  const std::vector<fit::Parameter> ps{{"r0", 0.02, 0.2}, {"kext", 0.005, 0.08}};
  const fit::Params truth{0.07, 0.03};
  const std::vector<double> conc{0.001, 0.01, 0.1, 0.3, 1, 10, 100};
  std::vector<std::pair<double, double>> pts;
  for (double c : conc) pts.emplace_back(c, 0.0);
  fit::Options o;
  o.seeds = {101, 102, 103, 104};
  std::vector<double> mean[fit::kMeasures], se[fit::kMeasures];
  fit::predict(base, pts, ps, truth, o, mean, se);
  fit::Data data;
  data.measured[fit::kOutgrowth] = true;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    ASSERT_TRUE(std::isfinite(mean[fit::kOutgrowth][i]));
    // A data SE of 3 % of the value, as for a well-sampled group of explants.
    const double nan = std::nan("");
    data.points.push_back({pts[i].first, 0.0, {nan, mean[fit::kOutgrowth][i]}, {nan, 0.03 * mean[fit::kOutgrowth][i]},
                           20, i + 2});
  }
  o.seeds = {1, 2};
  o.max_seeds = 8;
  o.parameters = ps;
  o.coarse = 5;
  o.refine_rounds = 1;
  const fit::Result r = fit::fit(base, "synthetic", data, o);
  ASSERT_EQ(r.intervals.size(), 2u);
  EXPECT_LE(r.se_ratio_max, 1.0 / 3.0 + 1e-12);
  EXPECT_TRUE(r.polished);
  EXPECT_LT(r.chi2_per_dof, 3.0) << r.chi2 << " at r0 " << r.best[0] << ", kext " << r.best[1];
  for (std::size_t j = 0; j < 2; ++j) {
    const auto& iv = r.intervals[j];
    EXPECT_LE(iv.lo, truth[j]) << ps[j].name;
    EXPECT_GE(iv.hi, truth[j]) << ps[j].name;
    EXPECT_LE(iv.lo, iv.best);
    EXPECT_GE(iv.hi, iv.best);
    EXPECT_FALSE(iv.open_low) << ps[j].name;
    EXPECT_FALSE(iv.open_high) << ps[j].name;
    EXPECT_LT(iv.hi / iv.lo, ps[j].hi / ps[j].lo) << ps[j].name;
    // Gauss-Newton from the grid: within 5 % of the truth (the grid's last step is 33 %).
    EXPECT_NEAR(r.best[j] / truth[j], 1.0, 0.05) << ps[j].name << " [" << iv.lo << ", " << iv.hi << "]";
  }
}

TEST(fit, BadParametersAndCorrectionsExitTwoNamingThem) {
  test::TempDir d;
  const std::string data = (std::filesystem::path(AXG_SOURCE_DIR) / "data/bicknell2018/outgrowth-uniform.csv").string();
  const auto base = d.path() / "base.json";
  std::ofstream(base) << small_signalling_explant().dump();
  auto message = [&](const std::string& args) {
    return test::run_command(fmt::format("fit {} --scene {} --out {}/o {}", data, base.string(), d.path().string(), args));
  };
  for (const auto& [args, needle] : std::vector<std::pair<std::string, std::string>>{
           {"--param nonsense", "unknown parameter \"nonsense\""},
           {"--param r0=0.1:0.01", "--param r0=0.1:0.01: LO and HI"},
           {"--param r0=-1:2", "--param r0=-1:2: LO and HI"},
           {"--param r0=a:2", "is not a finite number"},
           {"--param r0 --param r0", "parameter r0 given twice"},
           {"--param gain", "does not steer by the SNR model"},
           {"--correct 0.12", "--correct"},
           {"--correct 0.12=-1", "--correct"},
           {"--bias-metric nothing", "--bias-metric: nothing not in"},
           {"--param r0 --param kext --param a0 --param aF --grid 50",
            "a grid of 50^4 parameter sets is more than 1000000"}}) {
    const auto [rc, out] = message(args);
    EXPECT_EQ(rc, 2) << args << ": " << out;
    EXPECT_NE(out.find(needle), std::string::npos) << args << ": " << out;
    EXPECT_FALSE(std::filesystem::exists(d.path() / "o/fit.json")) << args;
  }
}

}  // namespace
}  // namespace axg

namespace axg {
namespace {

// The mirrored pair measures each run's bias along its own gradient: the mirrored model's
// bias is the plain model's (within their SEs), clearly above zero up a guiding gradient,
// and its SE over seeds is no larger (the explant's asymmetry cancels).
TEST(fit, MirroringKeepsTheBiasAndCancelsTheExplantsAsymmetry) {
  json base = json::parse(test::read_file(std::filesystem::path(AXG_SOURCE_DIR) / "scenes/assay-bicknell.json"));
  base["steps"] = 30;
  base["dt"] = 1.6;
  const std::vector<fit::Parameter> ps{{"r0", 0.01, 1}};
  const std::vector<std::pair<double, double>> pts{{0.3, 0.3}, {0.3, 0.0}};
  fit::Options o;
  o.seeds = {1, 2, 3, 4, 5, 6, 7, 8};
  std::vector<double> mm[fit::kMeasures], ms[fit::kMeasures], pm[fit::kMeasures], pse[fit::kMeasures];
  fit::predict(base, pts, ps, {0.05}, o, mm, ms);
  o.mirror = false;
  fit::predict(base, pts, ps, {0.05}, o, pm, pse);
  const double b = mm[fit::kBias][0], se = ms[fit::kBias][0];
  EXPECT_GT(b, 5 * se) << "mirrored bias " << b << " +- " << se;
  EXPECT_LT(std::fabs(b - pm[fit::kBias][0]), 3 * std::hypot(se, pse[fit::kBias][0]))
      << b << " against " << pm[fit::kBias][0];
  EXPECT_LE(se, pse[fit::kBias][0]);
  // Without a gradient the mirrored bias is zero to rounding (the pair's two runs are mirror
  // images of the same explant).
  EXPECT_LT(std::fabs(mm[fit::kBias][1]), 1e-12);
}

// Antithetic mirror images (guidance.antithetic in the mirror run) on the SNR explant: the
// pair's mean bias is the plain mirrored pair's (within their SEs; both are means of
// equally likely samples of the model) and its SE over seeds is well below it, since the
// decisions' noise cancels too; without a gradient the pair's bias is still zero to
// rounding (the two runs make the same turns in space, the sides drawn where there is no
// evidence included).
TEST(fit, AntitheticMirrorsKeepTheSnrBiasAndCancelTheDecisionsNoise) {
  json base = json::parse(test::read_file(std::filesystem::path(AXG_SOURCE_DIR) / "scenes/assay-explant.json"));
  base["neurons"]["populations"][0]["count"] = 250;
  base["steps"] = 60;
  const std::vector<fit::Parameter> ps{{"gain", 1, 1000}};
  const std::vector<std::pair<double, double>> pts{{1.0, 0.3}, {0.01, 0.2}, {1.0, 0.0}};
  fit::Options o;
  o.seeds = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
  std::vector<double> am[fit::kMeasures], as[fit::kMeasures], mm[fit::kMeasures], ms[fit::kMeasures];
  fit::predict(base, pts, ps, {40}, o, am, as);
  o.antithetic = false;
  fit::predict(base, pts, ps, {40}, o, mm, ms);
  for (std::size_t i = 0; i < 2; ++i) {
    const double a = am[fit::kBias][i], m = mm[fit::kBias][i];
    EXPECT_LT(std::fabs(a - m), 3 * std::hypot(as[fit::kBias][i], ms[fit::kBias][i])) << i << ": " << a << " against " << m;
    EXPECT_LT(as[fit::kBias][i], 0.5 * ms[fit::kBias][i]) << i << ": SE " << as[fit::kBias][i] << " against "
                                                          << ms[fit::kBias][i];
  }
  EXPECT_GT(am[fit::kBias][0], 5 * as[fit::kBias][0]);
  EXPECT_LT(std::fabs(am[fit::kBias][2]), 1e-12);
}

}  // namespace
}  // namespace axg

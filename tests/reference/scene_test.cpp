// Scenes: defaults, the canonical form, and a table of bad scenes, each rejected with a
// message that names the key path, the value and what is allowed.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <sys/wait.h>

#include <fstream>

#include <fmt/format.h>

#include "axonguide/support/error.hpp"
#include "axonguide/scene/json_input.hpp"
#include "axonguide/scene/scene.hpp"
#include "support.hpp"

namespace axg {
namespace {

TEST(scene, EmptyObjectIsAllDefaults) {
  const ParseResult r = parse_scene("{}", "test");
  EXPECT_EQ(scene_to_json(r.scene), scene_to_json(Scene{}));
  EXPECT_TRUE(r.warnings.empty());
}

TEST(scene, CanonicalFormRoundTrips) {
  const Scene d = Scene::builtin_default();
  const std::string text = scene_to_json(d).dump();
  EXPECT_EQ(scene_to_json(parse_scene(text, "test").scene).dump(), text);
}

TEST(scene, SeedIsExactTo64Bits) {
  const ParseResult r = parse_scene(R"({"seed": 18446744073709551615})", "test");
  EXPECT_EQ(r.scene.seed, 18446744073709551615ull);
}

TEST(scene, IntegralFloatsAreIntegers) {
  EXPECT_EQ(parse_scene(R"({"neurons": {"count": 1e3}})", "t").scene.neurons.count, 1000u);
}

TEST(scene, DirectGuidanceWarnsThatCuesAreIgnored) {
  const ParseResult r = parse_scene(R"({"guidance": {"model": "direct"}, "cues": {"field": "grid"}})", "t");
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("ignored"), std::string::npos);
}

struct Bad {
  const char* text;
  const char* expect;  // a substring of the message
};

void PrintTo(const Bad& b, std::ostream* os) { *os << b.expect; }

class BadScene : public ::testing::TestWithParam<Bad> {};

TEST_P(BadScene, IsRejectedWithAClearMessage) {
  try {
    parse_scene(GetParam().text, "scene.json");
    FAIL() << "accepted: " << GetParam().text;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(GetParam().expect), std::string::npos)
        << "message: " << e.what() << "\nexpected to contain: " << GetParam().expect;
  }
}

// A valid signalling scene's prefix, its axons.signalling object left open.
#define SIG                                                                                      \
  R"({"units": {"length": "um", "time": "min", "concentration": "nM"}, "cues": {"field": "analytic", )" \
  R"("sources": [{"position": [0, 0, 0]}]}, "axons": {"growth_model": "signalling", "signalling": {)"

INSTANTIATE_TEST_SUITE_P(
    scene, BadScene,
    ::testing::Values(
        Bad{"", "not valid JSON"}, Bad{"{", "not valid JSON"}, Bad{"[1,2]", "must be a JSON object"},
        Bad{"\x01\x02\xff garbage", "not valid JSON"}, Bad{"NaN", "not valid JSON"},
        Bad{R"({"dt": 1e999})", "number overflow"},
        Bad{R"({"stepz": 3})", "unknown key stepz (allowed here: seed, steps, dt"},
        Bad{R"({"neurons": {"cont": 3}})", "unknown key neurons.cont"},
        Bad{R"({"neurons": {"count": 0}})", "neurons.count = 0: must be an integer in [1, "},
        Bad{R"({"neurons": {"count": -5}})", "neurons.count = -5: must be an integer"},
        Bad{R"({"neurons": {"count": 2.5}})", "neurons.count = 2.5: must be an integer"},
        Bad{R"({"neurons": {"count": "10"}})", R"(neurons.count = "10": must be an integer)"},
        Bad{R"({"neurons": {"soma_radius": 0}})", "neurons.soma_radius = 0: must be > 0"},
        Bad{R"({"neurons": {"soma_radius": -1}})", "neurons.soma_radius = -1: must be > 0"},
        Bad{R"({"neurons": {"region": {"radius": -2}}})", "neurons.region.radius = -2: must be > 0"},
        Bad{R"({"neurons": {"region": {"shape": "cube"}}})",
            R"(neurons.region.shape = "cube": must be one of "ball", "sphere", "box")"},
        Bad{R"({"neurons": {"sampler": "uniform"}})", R"(must be one of "rejection", "normal", "trig", "coordinate")"},
        Bad{R"({"neurons": {"overlap": true}})", R"(neurons.overlap = true: must be one of "reject", "allow")"},
        Bad{R"({"neurons": {"max_attempts": 0}})", "neurons.max_attempts = 0"},
        Bad{R"({"neurons": {"soma_radius": 3, "region": {"radius": 2}}})", "somas must fit in the region"},
        Bad{R"({"axons": {"step_length": 0}})", "axons.step_length = 0: must be > 0"},
        Bad{R"({"axons": {"step_length": -0.1}})", "axons.step_length = -0.1: must be > 0"},
        Bad{R"({"axons": {"contact_distance": -0.01}})", "axons.contact_distance = -0.01: must be >= 0"},
        Bad{R"({"axons": {"contact": "tip"}})", R"(axons.contact = "tip": must be one of "swept", "endpoint")"},
        Bad{R"({"axons": {"bounds_radius": 0}})", "axons.bounds_radius = 0: must be > 0"},
        Bad{R"({"steps": -1})", "steps = -1: must be an integer"},
        Bad{R"({"dt": 0})", "dt = 0: must be > 0"},
        Bad{R"({"seed": 18446744073709551616})", "seed = 1.8446744073709552e+19"},
        Bad{R"({"guidance": {"model": "magic"}})", R"(guidance.model = "magic")"},
        Bad{R"({"guidance": {"turn_angle": 4}})", "guidance.turn_angle = 4: must be in [0, 3.14159"},
        Bad{R"({"cues": {"sources": [{"diffusion": -1}]}})", "cues.sources[0].diffusion = -1: must be > 0"},
        Bad{R"({"cues": {"sources": [{"decay": -0.1}]}})", "cues.sources[0].decay = -0.1: must be >= 0"},
        Bad{R"({"cues": {"sources": [{"kd": -1}]}})", "cues.sources[0].kd = -1: must be > 0"},
        Bad{R"({"cues": {"sources": [{"min_concentration": 2, "max_concentration": 1}]}})",
            "min must be <= max"},
        Bad{R"({"cues": {"sources": [{"position": [0, 0, 99]}]}})",
            "cues.sources[0].position = [0, 0, 99]: must lie inside the domain"},
        Bad{R"({"cues": {"sources": [{"position": [0, 0]}]}})", "must be [x, y, z] or null"},
        Bad{R"({"cues": {"sources": {"kind": "attractant"}}})", "cues.sources"},
        Bad{R"({"cues": {"random_sources": {"attractant_fraction": 1.5}}})",
            "cues.random_sources.attractant_fraction = 1.5: must be in [0, 1]"},
        Bad{R"({"cues": {"grid": {"scheme": "crank"}}})", R"(cues.grid.scheme = "crank")"},
        Bad{R"({"cues": {"grid": {"spacing": 0}}})", "cues.grid.spacing = 0: must be > 0"},
        Bad{R"({"analysis": {"bfs_sources": [5000]}})", "analysis.bfs_sources[0] = 5000: must be a neuron id below"},
        Bad{R"({"output": {"stats_every": 0}})", "output.stats_every = 0"},
        Bad{R"({"output": {"paths": "yes"}})", R"(output.paths = "yes": must be true or false)"},
        Bad{"[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]",
            "nested deeper than 32 levels"},
        // The guidance-model options (SPEC §3.3-§3.5).
        Bad{R"({"axons": {"persistence_length": -1}})", "axons.persistence_length = -1: must be > 0"},
        Bad{R"({"axons": {"persistence_length": 0}})", "axons.persistence_length = 0: must be > 0"},
        Bad{R"({"axons": {"persistence_length": "long"}})", R"(axons.persistence_length = "long": must be a number)"},
        Bad{R"({"guidance": {"noise": "poisson"}})",
            R"(guidance.noise = "poisson": must be one of "binding", "snapshot")"},
        Bad{R"({"cues": {"particles": {"sensing": "mean"}}})",
            "cues.particles.sensing"},
        Bad{R"({"cues": {"field": "imposed", "imposed": {"profile": "sigmoid"}}})",
            R"(cues.imposed.profile = "sigmoid": must be one of "linear", "exponential")"},
        Bad{R"({"cues": {"field": "fixed"}})", R"(cues.field = "fixed")"},
        // Physical noise and the particle estimate (issue 21).
        Bad{R"({"cues": {"molecule_amount": 0}})", "cues.molecule_amount = 0: must be > 0"},
        Bad{R"({"cues": {"molecule_amount": -1e-5}})", "cues.molecule_amount = -1e-05: must be > 0"},
        Bad{R"({"units": {"length": "um", "concentration": "nM"}, "cues": {"molecule_amount": 1}})",
            "the scene declares physical units (length um, time step, concentration nM), which fix one molecule at 1.66054 nM um^3"},
        Bad{R"({"cues": {"particles": {"molecules": true, "amount": 0.001}}})",
            "cues.particles.amount = 0.001 with cues.particles.molecules = true: a molecule-resolved particle is one molecule"},
        Bad{R"({"cues": {"particles": {"molecules": "yes"}}})", R"(cues.particles.molecules = "yes": must be true or false)"},
        Bad{R"({"cues": {"particles": {"estimate": {"spacing": 0}}}})", "cues.particles.estimate.spacing = 0: must be > 0"},
        Bad{R"({"cues": {"particles": {"estimate": {"time": -1}}}})", "cues.particles.estimate.time = -1: must be >= 0"},
        Bad{R"({"cues": {"particles": {"estimate": {"width": 1}}}})", "unknown key cues.particles.estimate.width"},
        Bad{R"({"cues": {"particles": {"estimate": {"spacing": 9}}}})",
            "cues.particles.estimate.spacing = 9: must be below the domain radius 5"},
        Bad{R"({"cues": {"grid": {"substeps": 0}}})", "cues.grid.substeps = 0: must be an integer in [1, 1000000]"},
        Bad{R"({"cues": {"grid": {"substeps": 1.5}}})", "cues.grid.substeps = 1.5: must be an integer"},
        Bad{R"({"cues": {"field": "imposed", "imposed": {"direction": [0, 0, 0]}}})",
            "cues.imposed.direction = [0,0,0]: must be a non-zero finite vector"},
        Bad{R"({"cues": {"field": "imposed", "imposed": {"direction": [1, 0]}}})", "cues.imposed.direction"},
        Bad{R"({"cues": {"field": "imposed", "imposed": {"steepness": -1}}})",
            "cues.imposed.steepness = -1: must be in [0, 1000000]"},
        Bad{R"({"cues": {"field": "imposed", "imposed": {"reference_length": 0}}})",
            "cues.imposed.reference_length = 0: must be > 0"},
        Bad{R"({"cues": {"field": "imposed", "imposed": {"concentration": 0}}})",
            "cues.imposed.concentration = 0: must be > 0"},
        Bad{R"({"cues": {"field": "imposed", "imposed": {"slope": 1}}})", "unknown key cues.imposed.slope"},
        // 50 % per length unit falls below zero 2 length units down the gradient; the ball has radius 5.
        Bad{R"({"neurons": {"count": 100, "region": {"radius": 5}},
               "cues": {"field": "imposed", "sources": [{"position": [0, 0, 0]}],
                        "imposed": {"profile": "linear", "steepness": 50, "reference_length": 1}}})",
            "cues.imposed.steepness = 50: the linear profile"},
        // The same with a sampled source position.
        Bad{R"({"neurons": {"count": 100, "region": {"radius": 5}},
               "cues": {"field": "imposed", "sources": [{}],
                        "imposed": {"profile": "linear", "steepness": 50, "reference_length": 1}}})",
            "cues.imposed.steepness = 50"},
        // And in a box, whose corners reach further down the gradient than its half-edge.
        Bad{R"({"neurons": {"count": 100, "region": {"shape": "box", "radius": 5}},
               "cues": {"field": "imposed", "sources": [{"position": [0, 0, 0]}],
                        "imposed": {"profile": "linear", "direction": [1, 1, 1], "steepness": 15, "reference_length": 1}}})",
            "cues.imposed.steepness = 15"},
        Bad{R"({"axons": {"growth_modulation": 1}})", "axons.growth_modulation = 1: must be in [0, 1)"},
        Bad{R"({"axons": {"growth_modulation": -0.1}})", "axons.growth_modulation = -0.1: must be in [0, 1)"},
        Bad{R"({"axons": {"growth_modulation": 0.5}, "guidance": {"model": "vector_sum"}})",
            "axons.growth_modulation = 0.5"},
        Bad{R"({"axons": {"growth_modulation": 0.5}, "guidance": {"model": "source_vector_sum"}})",
            "axons.growth_modulation = 0.5"},
        Bad{R"({"axons": {"growth_modulation": 0.5}, "guidance": {"model": "direct"}})",
            "axons.growth_modulation = 0.5"},
        Bad{R"({"axons": {"step_length": 0.35, "growth_speed": 0.35}})", "axons.step_length = 0.35 and axons.growth_speed"},
        Bad{R"({"axons": {"step_length": null}})", "axons.step_length"},
        Bad{R"({"axons": {"growth_speed": 0}})", "axons.growth_speed = 0: must be > 0"},
        Bad{R"({"axons": {"growth_speed": -2}})", "axons.growth_speed = -2: must be > 0"},
        Bad{R"({"dt": 1e-300, "axons": {"growth_speed": 1e-300}})", "axons.growth_speed"},
        Bad{R"({"units": {"length": "mm"}})", R"(units.length = "mm": must be one of "LU", "um")"},
        Bad{R"({"units": {"time": "day"}})", R"(units.time = "day")"},
        Bad{R"({"units": {"concentration": "mM"}})", R"(units.concentration = "mM")"},
        Bad{R"({"units": {"mass": "kg"}})", "unknown key units.mass"},
        Bad{R"({"units": "um"})", "units"},
        Bad{R"({"output": {"graphml": "yes"}})", R"(output.graphml = "yes": must be true, false or null)"},
        Bad{R"({"output": {"conduction_speed": 0}})", "output.conduction_speed = 0: must be > 0"},
        Bad{R"({"output": {"swc": 1}})", "output.swc = 1: must be true or false"},
        Bad{R"({"output": {"sonata": null}})", "output.sonata = null: must be true or false"},
        // The signalling growth model: physical units, rates with their units, >= 0.
        Bad{R"({"axons": {"growth_model": "signalling"}, "cues": {"field": "analytic"}})", "needs physical units"},
        Bad{SIG R"("kr": "-0.1 /min"}}})", "axons.signalling.kr = \"-0.1 /min\": must not be negative"},
        Bad{SIG R"("kr": 0.1}}})", "axons.signalling.kr = 0.1: needs its unit"},
        Bad{SIG R"("kr": "0.1 min"}}})", "unit \"min\" is not one of /s, /min or /h"},
        Bad{SIG R"("kpA": "1 /min"}}})", "axons.signalling.kpA"},
        Bad{SIG R"("r0": "0.05 um"}}})", "axons.signalling.r0"},
        Bad{SIG R"("kr": "1e999 /min"}}})", "is not a finite number"},
        Bad{SIG R"("kr": "0.1  /min"}}})", "axons.signalling.kr"},
        Bad{SIG R"("At": "1000 molecules"}}})", "axons.signalling.At"},
        Bad{SIG R"("At": 0}}})", "axons.signalling.At = 0: must be > 0"},
        Bad{SIG R"("speed": "1 um/min"}}})", "unknown key axons.signalling.speed"},
        Bad{SIG R"("cue": 3}}})", "axons.signalling.cue = 3"},
        Bad{SIG R"("inhibition": "none"}}})", "axons.signalling.inhibition"},
        Bad{SIG R"("substeps": 0}}})", "axons.signalling.substeps"}),
    [](const auto& info) { return std::to_string(info.index); });

// The output keys added with SWC and SONATA: read, and in the canonical form only when set,
// so that every scene written before them keeps its canonical form (and its hash).
TEST(scene, FormatKeysAppearInTheCanonicalFormOnlyWhenSet) {
  const nlohmann::json plain = scene_to_json(parse_scene("{}", "scene.json").scene);
  for (const char* key : {"swc", "sonata", "graphml", "conduction_speed"}) EXPECT_FALSE(plain["output"].contains(key));
  const ParseResult set = parse_scene(
      R"({"output": {"swc": true, "sonata": true, "graphml": false, "conduction_speed": 2}})", "scene.json");
  const Scene& s = set.scene;
  EXPECT_TRUE(s.output.swc && s.output.sonata && s.output.paths);  // swc turns paths on
  EXPECT_FALSE(s.writes_graphml());
  EXPECT_EQ(s.output.conduction_m_per_s(), 2.0);
  const nlohmann::json canonical = scene_to_json(s);
  EXPECT_EQ(canonical["output"]["graphml"], false);
  EXPECT_EQ(scene_to_json(parse_scene(canonical.dump(), "again").scene), canonical);
  ASSERT_EQ(set.warnings.size(), 1u);
  EXPECT_NE(set.warnings[0].find("output.swc"), std::string::npos);
  // null: GraphML up to the limit, not above it.
  Scene big;
  big.neurons.count = Scene::kGraphmlAutoLimit;
  EXPECT_TRUE(big.writes_graphml());
  big.neurons.count += 1;
  EXPECT_FALSE(big.writes_graphml());
  big.output.graphml = true;
  EXPECT_TRUE(big.writes_graphml());
}

// A scene error names its parts for the Python module's SceneError.
TEST(scene, InputErrorCarriesKeyValueAndAllowed) {
  try {
    parse_scene(R"({"neurons": {"count": -1}})", "scene.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "neurons.count");
    EXPECT_EQ(e.value(), "-1");
    EXPECT_NE(e.allowed().find("integer"), std::string::npos);
  }
  try {
    parse_scene(R"({"output": {"colour": 1}})", "scene.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "output.colour");
    EXPECT_NE(e.allowed().find("sonata"), std::string::npos);
  }
}

// The message of the InputError that parse_scene throws for `text` ("" when it accepts it).
std::string refusal(const std::string& text) {
  try {
    parse_scene(text, "scene.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// nlohmann::json keeps the last of two equal keys; a scene names each key once, at any depth.
TEST(scene, DuplicateKeysAreRefusedWithTheirPath) {
  const std::pair<const char*, const char*> cases[] = {
      {R"({"seed": 1, "seed": 2})", "scene.json: duplicate key seed:"},
      {R"({"neurons": {"region": {"shape": "ball", "radius": 3, "shape": "box"}}})",
       "duplicate key neurons.region.shape:"},
      {R"({"cues": {"sources": [{"kind": "attractant"}, {"kind": "attractant", "kind": "repellent"}]}})",
       "duplicate key cues.sources[1].kind:"},
      {R"({"analysis": {"bfs_sources": [[1], 2, {"a": 1, "a": 2}]}})", "duplicate key analysis.bfs_sources[2].a:"},
      {R"({"output": {}, "stepz": {"x": [0, {"y": 1, "y": 1}]}})", "duplicate key stepz.x[1].y:"},
      {R"({"neurons": {}, "axons": {}, "neurons": {}})", "duplicate key neurons:"},
  };
  for (const auto& [text, expect] : cases) {
    const std::string what = refusal(text);
    EXPECT_NE(what.find(expect), std::string::npos) << text << "\nmessage: " << what;
  }
  // The same key in different objects is no duplicate.
  EXPECT_EQ(refusal(R"({"neurons": {"count": 5, "region": {"radius": 5}}, "cues": {"random_sources": {"count": 1}},
                        "analysis": {"bfs_sources": [0, 0]}})"),
            "");
}

// nlohmann's lexer takes a NUL byte for the end of the text; nothing may follow the object
// but whitespace.
TEST(scene, TrailingBytesAreRefused) {
  EXPECT_NE(refusal(std::string("{}\0", 3)).find("not valid JSON: a NUL byte at line 1, column 3 (byte 2)"),
            std::string::npos)
      << refusal(std::string("{}\0", 3));
  EXPECT_NE(refusal(std::string("{}\0{\"seed\": 1}", 14)).find("NUL byte"), std::string::npos);
  EXPECT_NE(refusal(std::string("{\"seed\":\n\0 1}", 13)).find("NUL byte at line 2, column 1"), std::string::npos);
  EXPECT_NE(refusal("{} x").find("not valid JSON"), std::string::npos);
  EXPECT_NE(refusal("{}{}").find("not valid JSON"), std::string::npos);
  EXPECT_NE(refusal("{}\f").find("not valid JSON"), std::string::npos);
  EXPECT_EQ(refusal("{} \t\r\n "), "");
}

// A message quotes keys and values from the file: no byte of it may reach the terminal as
// a control character.
TEST(scene, MessagesEscapeControlCharacters) {
  const std::pair<std::string, std::string> cases[] = {
      {R"({"\u001b[2J": 1})", R"(unknown key \u001b[2J (allowed here:)"},
      {"{\"neurons\": {\"a\\u0001\x7f\": 1}}", R"(unknown key neurons.a\u0001\u007f ()"},
      {"{\"a\xc2\x85\xe2\x80\xae\": 1}", R"(unknown key a\u0085\u202e ()"},
      {R"({"seed": 1, "seed\u0001": 2, "seed\u0001": 3})", R"(duplicate key seed\u0001:)"},
      {R"({"units": {"length": "\u001b]0;owned\u0007"}})", R"(units.length = "\u001b]0;owned\u0007": must be)"},
      {"{\"\xff\": 1}", R"(\xff)"},
      {"{\"caf\xc3\xa9\": 1}", "unknown key caf\xc3\xa9 ("},  // well-formed UTF-8 stays as it is
  };
  for (const auto& [text, expect] : cases) {
    const std::string what = refusal(text);
    EXPECT_NE(what.find(expect), std::string::npos) << "message: " << what << "\nexpected: " << expect;
    for (unsigned char c : what) EXPECT_TRUE(c >= 0x20 && c != 0x7f) << "raw byte " << int(c) << " in " << what;
  }
  EXPECT_EQ(printable("a\tb\nc\\d\xf0\x9f\x98\x80"), "a\\u0009b\\u000ac\\d\xf0\x9f\x98\x80");
  EXPECT_EQ(printable("\xc0\xaf\xed\xa0\x80\xe2\x82"), "\\xc0\\xaf\\xed\\xa0\\x80\\xe2\\x82");  // overlong, surrogate, cut
}

// Through the command: exit 2, the key path on stderr, no control byte.
TEST(scene, DuplicateKeyIsExit2FromTheCommand) {
  test::TempDir tmp;
  const auto scene = tmp.path() / "dup.json", err = tmp.path() / "err.txt";
  std::ofstream(scene, std::ios::binary) << R"({"neurons": {"count": 10, "count\u001b[31m": 20, "count": 30}})";
  const int status =
      std::system(fmt::format("{} scene check {} > /dev/null 2> {}", test::binary(), scene.string(), err.string()).c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 2);
  const std::string text = test::read_file(err);
  EXPECT_NE(text.find("duplicate key neurons.count:"), std::string::npos) << text;
  for (unsigned char c : text) EXPECT_TRUE(c >= 0x20 || c == '\n') << "raw byte " << int(c) << " in " << text;
  std::ofstream(scene, std::ios::binary) << std::string("{}\0", 3);
  EXPECT_EQ(WEXITSTATUS(std::system(
                fmt::format("{} scene check {} > /dev/null 2> {}", test::binary(), scene.string(), err.string()).c_str())),
            2);
  EXPECT_NE(test::read_file(err).find("NUL byte"), std::string::npos) << test::read_file(err);
}

// Any value the parser accepts must survive the canonical form unchanged.
RC_GTEST_PROP(scene, AcceptedValuesRoundTrip, ()) {
  Scene s;
  s.seed = *rc::gen::arbitrary<std::uint64_t>();
  s.steps = *rc::gen::inRange<std::uint32_t>(0, 1000000);
  s.neurons.count = *rc::gen::inRange<std::uint64_t>(1, 1000000);
  s.neurons.radius = *rc::gen::inRange(1, 100000) / 7.0;
  s.neurons.soma_radius = s.neurons.radius / *rc::gen::inRange(2, 1000);
  s.axons.step_length = *rc::gen::inRange(1, 100000) / 3.0;
  // The report's per-step rule takes any step; a continuum decision needs dt <= T and steps
  // at most the sensing diameter.
  if (*rc::gen::arbitrary<bool>()) s.guidance.decision = DecisionRule::kPerStep;
  else s.guidance.sensing_radius = s.axons.step_length;
  if (*rc::gen::arbitrary<bool>()) s.guidance.integration_time = s.dt * *rc::gen::inRange(1, 100) / 7.0 + s.dt;
  const std::string text = scene_to_json(s).dump();
  RC_ASSERT(scene_to_json(parse_scene(text, "t").scene).dump() == text);
}

// The canonical form of a scene with an oblique imposed gradient reads back as the same
// scene: the direction printed must not change when it is read (and normalised) again.
TEST(scene, ImposedDirectionCanonicalFormIsAFixedPoint) {
  for (const char* dir : {"[1, 1, 1]", "[-8.5, 1, -2]", "[0.3, -0.2, 0.7]", "[3, 4, 0]"}) {
    const std::string text = fmt::format(R"({{"cues": {{"field": "imposed", "imposed": {{"direction": {}}}}}}})", dir);
    const std::string once = scene_to_json(parse_scene(text, "t").scene).dump();
    const std::string twice = scene_to_json(parse_scene(once, "canonical").scene).dump();
    EXPECT_EQ(twice, once) << dir;
  }
}

// The same for the guidance-model options, units and growth speed.
RC_GTEST_PROP(scene, AcceptedModelOptionsRoundTrip, ()) {
  Scene s = Scene::builtin_default();
  s.dt = *rc::gen::inRange(1, 1000) / 8.0;
  s.units.length = *rc::gen::element(std::string("LU"), std::string("um"));
  s.units.time = *rc::gen::element(std::string("step"), std::string("s"), std::string("min"), std::string("h"));
  s.units.concentration = *rc::gen::element(std::string("CU"), std::string("pM"), std::string("nM"), std::string("uM"));
  if (*rc::gen::arbitrary<bool>()) {
    s.axons.growth_speed = *rc::gen::inRange(1, 100000) / 7.0;
    s.axons.step_length = *s.axons.growth_speed * s.dt;
  }
  if (*rc::gen::arbitrary<bool>()) s.axons.persistence_length.reset();
  else s.axons.persistence_length = *rc::gen::inRange(1, 1000000) / 3.0;
  s.guidance.model = *rc::gen::element(GuidanceModel::kSnr, GuidanceModel::kVectorSum, GuidanceModel::kSourceVectorSum);
  if (s.guidance.model == GuidanceModel::kSnr) s.axons.growth_modulation = *rc::gen::inRange(0, 1000) / 1000.0;
  s.guidance.noise = *rc::gen::element(NoiseForm::kBinding, NoiseForm::kSnapshot);
  s.cues.field = *rc::gen::element(FieldKind::kParticles, FieldKind::kGrid, FieldKind::kAnalytic, FieldKind::kImposed);
  if (*rc::gen::arbitrary<bool>()) test::use_count_sensing(s);
  s.cues.imposed.profile = ImposedProfile::kExponential;
  // Exact unit vectors (any other direction: see ImposedDirectionCanonicalFormIsAFixedPoint).
  s.cues.imposed.direction = *rc::gen::element(core::Vec3{1, 0, 0}, core::Vec3{0, -1, 0}, core::Vec3{0, 0, 1});
  s.cues.imposed.steepness = *rc::gen::inRange(0, 1000000);
  s.cues.imposed.reference_length = *rc::gen::inRange(1, 1000) / 3.0;
  s.cues.imposed.concentration = *rc::gen::inRange(1, 1000) / 9.0;
  // Physical noise and the numerical keys of issue 21, each given or not.
  if (*rc::gen::arbitrary<bool>() && !(s.units.length == "um" && s.units.concentration != "CU"))
    s.cues.molecule_amount = *rc::gen::inRange(1, 100000) / 1e7;
  if (*rc::gen::arbitrary<bool>()) {
    s.cues.particles.molecules = true;
    s.cues.particles.amount = s.molecule_amount();
  }
  if (*rc::gen::arbitrary<bool>()) s.cues.particles.estimate.spacing = *rc::gen::inRange(1, 100) / 50.0;
  if (*rc::gen::arbitrary<bool>()) s.cues.particles.estimate.time = *rc::gen::inRange(0, 100) / 4.0;
  if (*rc::gen::arbitrary<bool>()) s.cues.grid.spacing = *rc::gen::inRange(1, 100) / 100.0;
  if (*rc::gen::arbitrary<bool>()) s.cues.grid.substeps = *rc::gen::inRange<std::uint32_t>(1, 50);
  // The decision: the report's per step, or per integration interval T >= dt with steps at
  // most the sensing diameter; the receptors' correlation time given or not.
  if (*rc::gen::arbitrary<bool>()) {
    s.guidance.decision = DecisionRule::kPerStep;
  } else {
    s.guidance.integration_time = s.dt * (1.0 + *rc::gen::inRange(0, 64) / 8.0);
    s.guidance.sensing_radius = std::max(s.guidance.sensing_radius, s.axons.step_length * (1.0 + s.axons.growth_modulation));
    // A molecule-resolved count samples the ball faster than a molecule crosses it.
    double fastest = 0.0;
    for (const Source& src : s.cues.sources) fastest = std::max(fastest, src.diffusion);
    if (s.cues.particles.molecules)
      s.guidance.sensing_radius = std::max(s.guidance.sensing_radius, std::sqrt(6.0 * fastest * s.dt) * 1.001);
  }
  // The estimate's mesh resolves the sensing ball.
  if (s.cues.particles.estimate.spacing)
    s.cues.particles.estimate.spacing = std::min(*s.cues.particles.estimate.spacing, s.guidance.sensing_radius);
  if (*rc::gen::arbitrary<bool>()) s.guidance.receptor_time = *rc::gen::inRange(0, 1000) / 16.0;
  s.guidance.antithetic = *rc::gen::arbitrary<bool>();
  const std::string text = scene_to_json(s).dump();
  const Scene back = parse_scene(text, "t").scene;
  RC_ASSERT(scene_to_json(back).dump() == text);
  RC_ASSERT(back.guidance.antithetic == s.guidance.antithetic);
  RC_ASSERT(back.axons.step_length == s.axons.step_length);
  RC_ASSERT(back.axons.persistence_length == s.axons.persistence_length);
  RC_ASSERT(back.molecule_amount() == s.molecule_amount());
  RC_ASSERT(back.cues.particles.amount == s.cues.particles.amount);
  RC_ASSERT(grid_spacing(back) == grid_spacing(s));
}

// One molecule in each system of units: 1 nM is 0.602214076 molecules per um^3, LU read as
// 40 um and CU as nM where they are not declared; the key only where units do not fix it.
TEST(scene, MoleculeAmountFollowsTheUnits) {
  auto m = [](const char* units) { return parse_scene(units, "t").scene.molecule_amount(); };
  EXPECT_NEAR(m(R"({"units": {"length": "um", "concentration": "nM"}})"), 1.0 / 0.602214076, 1e-12);
  EXPECT_NEAR(m(R"({"units": {"length": "um", "concentration": "pM"}})"), 1000.0 / 0.602214076, 1e-9);
  EXPECT_NEAR(m(R"({"units": {"length": "um", "concentration": "uM"}})"), 0.001 / 0.602214076, 1e-15);
  EXPECT_NEAR(m("{}"), 1.0 / 0.602214076 / 64000.0, 1e-18);
  EXPECT_NEAR(m(R"({"units": {"length": "um"}})"), 1.0 / 0.602214076, 1e-12);
  EXPECT_EQ(m(R"({"cues": {"molecule_amount": 0.002}})"), 0.002);
  EXPECT_EQ(m(R"({"units": {"concentration": "nM"}, "cues": {"molecule_amount": 0.002}})"), 0.002);
  // Molecule-resolved particles carry exactly one molecule.
  const Scene s = parse_scene(R"({"cues": {"molecule_amount": 0.002, "particles": {"molecules": true}}})", "t").scene;
  EXPECT_EQ(s.cues.particles.amount, 0.002);
}

// The grid's default spacing follows the cues' shortest decay length and the sensing radius.
TEST(scene, GridSpacingDefaultFollowsTheDecayLength) {
  EXPECT_NEAR(grid_spacing(Scene::builtin_default()), 1.0 / 6.0, 1e-15);  // lambda = 1 LU
  const Scene s = parse_scene(R"({"cues": {"sources": [{"diffusion": 0.5, "decay": 0.05}]}})", "t").scene;
  EXPECT_NEAR(grid_spacing(s), std::min(0.5, std::sqrt(10.0) / 6.0), 1e-15);
  const Scene t = parse_scene(R"({"cues": {"sources": [{"decay": 0}]}})", "t").scene;
  EXPECT_EQ(grid_spacing(t), 0.5);  // no decay: the sensing radius
  const Scene u = parse_scene(R"({"cues": {"grid": {"spacing": 0.3}}})", "t").scene;
  EXPECT_EQ(grid_spacing(u), 0.3);
}

}  // namespace
}  // namespace axg

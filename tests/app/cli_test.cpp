// The command as a user meets it: exit codes, messages, files.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <fstream>

#include <nlohmann/json.hpp>

#include "axonguide/accel/engines.hpp"
#include "support.hpp"

namespace axg {
namespace {

struct Result {
  int code;
  std::string out, err;
};

// Runs the built binary with arguments; stdout and stderr captured through files.
Result run(const std::string& args, const test::TempDir& tmp) {
  const auto out = tmp.path() / "stdout.txt", err = tmp.path() / "stderr.txt";
  const std::string cmd = fmt::format("{} {} >{} 2>{}", test::binary(), args, out.string(), err.string());
  const int status = std::system(cmd.c_str());
  Result r{WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status), test::read_file(out),
           test::read_file(err)};
  return r;
}

std::string write(const test::TempDir& tmp, const std::string& name, const std::string& content) {
  const auto p = tmp.path() / name;
  std::ofstream(p, std::ios::binary) << content;
  return p.string();
}

TEST(cli, DefaultRunWritesEveryFileAtomically) {
  test::TempDir tmp;
  const Result r = run(fmt::format("run --out {}/o --threads 2", tmp.path().string()), tmp);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("connected"), std::string::npos);
  for (const char* f : {"neurons.csv", "connections.csv", "stats.csv", "bfs.csv", "graph.graphml", "timings.csv",
                        "manifest.json"})
    EXPECT_TRUE(std::filesystem::exists(tmp.path() / "o" / f)) << f;
  for (const auto& e : std::filesystem::directory_iterator(tmp.path() / "o"))
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
  // The manifest's hashes are the files' hashes.
  const auto m = nlohmann::json::parse(test::read_file(tmp.path() / "o" / "manifest.json"));
  for (auto& [name, v] : m["files"].items())
    EXPECT_EQ(v["sha256"].get<std::string>(), sha256_file(tmp.path() / "o" / name)) << name;
  EXPECT_EQ(m["backend"], "reference");
  EXPECT_EQ(m["threads"], 2);
  EXPECT_EQ(m["scene"], scene_to_json(Scene::builtin_default()));
}

// A cue scene without any source is valid: it grows straight, on every field.
TEST(cli, CueGuidanceWithoutSourcesRuns) {
  test::TempDir tmp;
  for (const char* field : {"particles", "grid", "analytic"}) {
    const std::string scene = write(tmp, std::string(field) + ".json",
                                    fmt::format(R"({{"neurons": {{"count": 100, "region": {{"radius": 2.5}}}},
        "cues": {{"field": "{}", "grid": {{"scheme": "explicit", "spacing": 0.5}}}}}})",
                                                field));
    const Result r = run(fmt::format("run {} -q --out {}/{}", scene, tmp.path().string(), field), tmp);
    EXPECT_EQ(r.code, 0) << field << ": " << r.err;
  }
}

TEST(cli, SceneDefaultPrintsAValidScene) {
  test::TempDir tmp;
  const Result r = run("scene default", tmp);
  ASSERT_EQ(r.code, 0);
  EXPECT_EQ(scene_to_json(parse_scene(r.out, "stdout").scene), scene_to_json(Scene::builtin_default()));
}

TEST(cli, SeedFlagOverridesTheScene) {
  test::TempDir tmp;
  ASSERT_EQ(run(fmt::format("run -q --out {}/a --seed 42", tmp.path().string()), tmp).code, 0);
  const auto m = nlohmann::json::parse(test::read_file(tmp.path() / "a" / "manifest.json"));
  EXPECT_EQ(m["seed"], 42);
  EXPECT_EQ(m["scene"]["seed"], 42);
}

struct BadRun {
  std::string args;  // {tmp} is replaced by the temp dir
  int code;
  std::string expect;
};

void PrintTo(const BadRun& b, std::ostream* os) { *os << b.args; }

class CliBadInput : public ::testing::TestWithParam<BadRun> {};

TEST_P(CliBadInput, ExitsWithCodeAndMessage) {
  test::TempDir tmp;
  write(tmp, "garbage.json", std::string("\x7f" "ELF\x02\x01\x01\0\0\0binary", 16));
  write(tmp, "nested.json", std::string(100000, '[') + std::string(100000, ']'));
  write(tmp, "huge.json", R"({"neurons": {"count": 1e15, "region": {"radius": 1e6}}})");
  write(tmp, "negradius.json", R"({"neurons": {"soma_radius": -0.25}})");
  write(tmp, "zerostep.json", R"({"axons": {"step_length": 0}})");
  write(tmp, "dense.json",
        R"({"neurons": {"count": 5000, "soma_radius": 0.5, "region": {"radius": 5}, "max_attempts": 50}})");
  write(tmp, "impossible.json", R"({"neurons": {"count": 5000, "soma_radius": 0.9, "region": {"radius": 5}}})");
  write(tmp, "file.txt", "x");
  write(tmp, "hugegrid.json", R"({"cues": {"field": "grid", "grid": {"spacing": 0.001}}, "cues2": 0})");
  write(tmp, "hugegrid2.json", R"({"cues": {"field": "grid", "random_sources": {"count": 2}, "grid": {"spacing": 0.001}}})");
  write(tmp, "nosubsteps.json",
        R"({"cues": {"field": "grid", "random_sources": {"count": 1}, "grid": {"spacing": 0.05, "scheme": "explicit", "allow_substeps": false}}})");
  write(tmp, "toomanycues.json", R"({"cues": {"random_sources": {"count": 65}}})");
  write(tmp, "hugeemission.json", R"({"cues": {"sources": [{"emission": 5e9}]}})");
  write(tmp, "endless.json",
        R"({"cues": {"field": "grid", "sources": [{"diffusion": 1e6}], "grid": {"spacing": 0.1, "scheme": "explicit"}}})");
  write(tmp, "gridnodes.json", R"({"cues": {"field": "grid", "grid": {"spacing": 0.002}}})");
  write(tmp, "negpersist.json", R"({"axons": {"persistence_length": -1}})");
  write(tmp, "steepimposed.json", R"({"neurons": {"count": 100, "region": {"radius": 5}},
      "cues": {"field": "imposed", "sources": [{"position": [0, 0, 0]}],
               "imposed": {"profile": "linear", "steepness": 50, "reference_length": 1}}})");
  write(tmp, "modvector.json", R"({"axons": {"growth_modulation": 0.5}, "guidance": {"model": "vector_sum"}})");
  write(tmp, "bothlengths.json", R"({"axons": {"step_length": 0.35, "growth_speed": 1}})");
  write(tmp, "endlesssteps.json", R"({"steps": 1000000000, "guidance": {"model": "direct"}})");
  {
    std::string unit;  // 400 directions on the circle: a points file that passes
    for (int k = 0; k < 400; ++k) unit += fmt::format("{},{}\n", std::cos(0.0157 * k), std::sin(0.0157 * k));
    write(tmp, "circle.csv", unit);
    std::filesystem::create_directories(tmp.path() / "blocked" / "samplers" / "report.md");  // a folder in its place
  }
  std::string args = GetParam().args;
  for (std::size_t p; (p = args.find("{tmp}")) != std::string::npos;) args.replace(p, 5, tmp.path().string());
  const Result r = run(args, tmp);
  EXPECT_EQ(r.code, GetParam().code) << r.err;
  EXPECT_NE(r.err.find(GetParam().expect), std::string::npos) << "stderr: " << r.err;
}

INSTANTIATE_TEST_SUITE_P(
    cli, CliBadInput,
    ::testing::Values(
        BadRun{"run {tmp}/missing.json --out {tmp}/o", 2, "missing.json: cannot open: No such file"},
        BadRun{"run {tmp} --out {tmp}/o", 2, "is a directory"},
        BadRun{"run {tmp}/garbage.json --out {tmp}/o", 2, "not valid JSON"},
        BadRun{"run {tmp}/nested.json --out {tmp}/o", 2, "nested deeper"},
        BadRun{"run {tmp}/huge.json --out {tmp}/o", 3, "needs an estimated"},
        BadRun{"run {tmp}/negradius.json --out {tmp}/o", 2, "neurons.soma_radius = -0.25: must be > 0"},
        BadRun{"run {tmp}/zerostep.json --out {tmp}/o", 2, "axons.step_length = 0: must be > 0"},
        BadRun{"run {tmp}/dense.json --out {tmp}/o", 3, "packing fraction"},
        BadRun{"run {tmp}/impossible.json --out {tmp}/o", 3, "exceeds the densest packing"},
        BadRun{"run --out {tmp}/file.txt", 2, "exists and is not a directory"},
        BadRun{"run {tmp}/hugegrid.json --out {tmp}/o", 2, "unknown key cues2"},
        BadRun{"run {tmp}/hugegrid2.json --out {tmp}/o", 2, "cues.grid.spacing = 0.001"},
        BadRun{"run {tmp}/nosubsteps.json --out {tmp}/o", 2, "cues.grid.allow_substeps = false"},
        BadRun{"run {tmp}/toomanycues.json --out {tmp}/o", 2, "at most 64 cue sources"},
        BadRun{"run {tmp}/hugeemission.json --out {tmp}/o", 2, "cues.sources[0].emission = 5000000000.0: must be in [0, 2147483648]"},
        BadRun{"run {tmp}/endless.json --out {tmp}/o", 2, "sub-steps per step"},
        BadRun{"run {tmp}/gridnodes.json --out {tmp}/o", 2, "nodes per axis"},
        BadRun{"run {tmp}/negpersist.json --out {tmp}/o", 2, "axons.persistence_length = -1: must be > 0"},
        BadRun{"scene check {tmp}/negpersist.json", 2, "axons.persistence_length = -1"},
        BadRun{"run {tmp}/steepimposed.json --out {tmp}/o", 2, "cues.imposed.steepness = 50"},
        BadRun{"run {tmp}/modvector.json --out {tmp}/o", 2, "axons.growth_modulation = 0.5"},
        BadRun{"run {tmp}/bothlengths.json --out {tmp}/o", 2, "axons.step_length = 0.35 and axons.growth_speed = 1"},
        BadRun{"run --seed -3 --out {tmp}/o", 2, "--seed -3: must be an unsigned 64-bit integer"},
        BadRun{"run --seed 99999999999999999999 --out {tmp}/o", 2, "must be an unsigned 64-bit integer"},
        BadRun{"run {tmp}/endlesssteps.json --out {tmp}/o", 3, "a run of 1000 neurons needs an estimated"},
        BadRun{"run --seed '' --out {tmp}/o", 2, "--seed : must be an unsigned 64-bit integer"},
        BadRun{"run --threads -1 --out {tmp}/o", 2, "--threads"},
        BadRun{"run --backend opencl --out {tmp}/o", 2, "--backend"},
        BadRun{"frobnicate", 2, "unknown command 'frobnicate'"},
        // Options an action does not take are refused, not ignored.
        BadRun{"golden check --only analytic-snr", 2, "--reason and --only are bless's options"},
        BadRun{"golden bless --reason x --backend cuda --dir {tmp}", 2, "blessing renders on the reference engine"},
        BadRun{"validate samplers --radius 2 --report {tmp}/r", 2, "--radius: only with --points"},
        // A report that could not be written is not a PASS (it printed PASS and exited 0).
        BadRun{"validate samplers --points {tmp}/circle.csv --report {tmp}/blocked", 3, "report.md"}),
    [](const auto& info) { return std::to_string(info.index); });

// The memory estimate respects an address-space limit (ulimit -v), and refuses before
// the output folder exists.
TEST(cli, AddressSpaceLimitIsRespected) {
  test::TempDir tmp;
  write(tmp, "big.json", R"({"neurons": {"count": 2000000, "region": {"radius": 300}}, "guidance": {"model": "direct"}, "steps": 5})");
  const auto out = tmp.path() / "o";
  const std::string cmd = fmt::format("sh -c 'ulimit -v 300000; exec {} run {} --out {} -q' 2>{}", test::binary(),
                                      (tmp.path() / "big.json").string(), out.string(), (tmp.path() / "err").string());
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 3);
  const std::string err = test::read_file(tmp.path() / "err");
  EXPECT_NE(err.find("the address-space limit (ulimit -v 300000 KiB) leaves this process"), std::string::npos) << err;
  EXPECT_FALSE(std::filesystem::exists(out));
}

// The order in which a scene lists its sources is not part of the scene: `scene check`
// prints the same canonical form, and `run` writes the same files, for a permutation.
TEST(cli, PermutedSourcesAreTheSameScene) {
  test::TempDir tmp;
  const char* sources[] = {
      R"({"kind": "attractant", "position": [1, 0, 0], "emission": 100})",
      R"({"kind": "repellent", "position": [-1, 0.5, 0], "emission": 70, "kd": 1.5})",
      R"({"kind": "attractant", "position": null, "emission": 120, "decay": 0.02})",
      R"({"kind": "repellent", "emission": 90, "diffusion": 0.04})",
      R"({"kind": "attractant", "position": [0, -1, 0.5], "emission": 60, "max_concentration": 40})"};
  auto scene = [&](std::initializer_list<int> order) {
    std::string list;
    for (int k : order) list += fmt::format("{}{}", list.empty() ? "" : ", ", sources[k]);
    return fmt::format(R"({{"neurons": {{"count": 150, "region": {{"radius": 2.5}}}}, "steps": 25,
        "cues": {{"sources": [{}]}}}})",
                       list);
  };
  const std::string a = write(tmp, "a.json", scene({0, 1, 2, 3, 4}));
  const std::string b = write(tmp, "b.json", scene({3, 0, 4, 2, 1}));
  const std::string c = write(tmp, "c.json", scene({4, 3, 2, 1, 0}));
  const Result ca = run(fmt::format("scene check {}", a), tmp);
  ASSERT_EQ(ca.code, 0) << ca.err;
  EXPECT_FALSE(ca.out.empty());
  for (const std::string& other : {b, c}) {
    const Result r = run(fmt::format("scene check {}", other), tmp);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.out, ca.out) << other;
  }
  ASSERT_EQ(run(fmt::format("run {} -q --out {}/a", a, tmp.path().string()), tmp).code, 0);
  ASSERT_EQ(run(fmt::format("run {} -q --out {}/b", b, tmp.path().string()), tmp).code, 0);
  const auto ha = test::output_hashes(tmp.path() / "a"), hb = test::output_hashes(tmp.path() / "b");
  EXPECT_EQ(ha, hb);
  EXPECT_TRUE(ha.count("neurons.csv"));
  const auto ma = nlohmann::json::parse(test::read_file(tmp.path() / "a" / "manifest.json"));
  const auto mb = nlohmann::json::parse(test::read_file(tmp.path() / "b" / "manifest.json"));
  EXPECT_EQ(ma["scene"], mb["scene"]);
  auto files_a = ma["files"], files_b = mb["files"];
  files_a.erase("timings.csv");
  files_b.erase("timings.csv");
  EXPECT_EQ(files_a, files_b);
  EXPECT_TRUE(files_a.contains("neurons.csv"));
}

// Not built: exit 2 "not built". Built without a usable GPU: exit 3 with the CUDA error
// text. With a GPU: a normal run.
TEST(cli, CudaBackendSaysWhyItCannotRun) {
  test::TempDir tmp;
  const Result r = run(fmt::format("run --backend cuda --out {}/o", tmp.path().string()), tmp);
  if (!accel::cuda_built()) {
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("not built"), std::string::npos) << r.err;
  } else if (r.code != 0) {
    EXPECT_EQ(r.code, 3) << r.err;
    EXPECT_NE(r.err.find("GPU"), std::string::npos) << r.err;
  }
}

}  // namespace
}  // namespace axg

namespace axg {
namespace {

// The formats of issue 12 (SWC, SONATA, GraphML forced on, a conduction speed) are
// outputs like the others: the same bytes on 1 and 2 threads and from the accelerator's
// pipeline compiled for the CPU (--backend emulated). A cue scene, so that the engines
// differ in every stage they have.
TEST(cli, NetworkFormatsAreTheSameOnAnyThreadCountAndBackend) {
  test::TempDir tmp;
  const std::string scene = write(tmp, "formats.json", R"({"neurons": {"count": 120}, "steps": 30, "cues":
      {"warmup_steps": 5}, "output": {"swc": true, "sonata": true, "graphml": true, "conduction_speed": 1.5}})");
  std::vector<nlohmann::json> files;
  for (const char* how : {"--threads 1", "--threads 2", "--threads 2 --backend emulated"}) {
    const std::string out = fmt::format("{}/o{}", tmp.path().string(), files.size());
    const Result r = run(fmt::format("run {} --out {} -q {}", scene, out, how), tmp);
    ASSERT_EQ(r.code, 0) << how << ": " << r.err;
    nlohmann::json m = nlohmann::json::parse(test::read_file(std::filesystem::path(out) / "manifest.json"))["files"];
    m.erase("timings.csv");
    EXPECT_TRUE(m.contains("morphologies/119.swc") && m.contains("network/edges.h5") && m.contains("graph.graphml"))
        << how;
    files.push_back(m);
  }
  EXPECT_EQ(files[0], files[1]) << "1 and 2 threads";
  EXPECT_EQ(files[0], files[2]) << "reference and emulated";
}

}  // namespace
}  // namespace axg

// A run is a whole (docs/methods.md §4.2): a run killed with SIGKILL at any point of any
// stage, then resumed, writes the bytes of an uninterrupted run; SIGINT and SIGTERM stop
// it with a checkpoint; a folder holds one run; `verify` tells whole from not.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <functional>
#include <map>
#include <random>
#include <thread>

#include <nlohmann/json.hpp>

#include "axonguide/engine/checkpoint.hpp"
#include "axonguide/io/run_folder.hpp"
#include "support.hpp"

namespace axg {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

struct Result {
  int code;
  std::string err;
};

// The command through the shell; `env` is prefixed (e.g. AXG_FAULT_KILL_AT='step 3').
Result axonguide(const std::string& args, const fs::path& tmp, const std::string& env = "") {
  const fs::path err = tmp / "stderr.txt";
  const std::string cmd = fmt::format("{} {} {} >/dev/null 2>{}", env, test::binary(), args, err.string());
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status), test::read_file(err)};
}

// Every file of a run (the VTK frames included) but the two that may vary.
std::map<std::string, std::string> outputs(const fs::path& dir) {
  std::map<std::string, std::string> h;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file()) continue;
    const std::string name = fs::relative(e.path(), dir).generic_string();
    if (name == "timings.csv" || name == "manifest.json") continue;
    h[name] = sha256_file(e.path());
  }
  return h;
}

// Small scenes of every field type, with a checkpoint every 4 steps.
json base_scene() {
  json s = scene_to_json(Scene::builtin_default());
  s["neurons"]["count"] = 300;
  s["steps"] = 24;
  s["cues"]["warmup_steps"] = 6;
  s["output"]["checkpoint_every"] = 4;
  s["output"]["paths"] = true;
  return s;
}

// The scenes of the --force tests: one with VTK frames in a subfolder, one without paths,
// and one whose placement jams below the packing bound (fraction 0.4), so that it fails
// inside the run, where only the run can find it, with no checkpoint.
json cue_with_vtk() {
  json s = base_scene();
  s["output"]["vtk"] = true;
  return s;
}
json direct_without_paths() {
  json s = base_scene();
  s["guidance"]["model"] = "direct";
  s["output"]["paths"] = false;
  return s;
}
json jamming() {
  json s = base_scene();
  s["neurons"] = {{"count", 400}, {"soma_radius", 0.5}, {"region", {{"radius", 5}}}};
  s["output"]["checkpoint_every"] = 0;
  return s;
}

std::vector<std::pair<std::string, json>> field_scenes() {
  std::vector<std::pair<std::string, json>> out;
  json s = base_scene();
  s["guidance"]["model"] = "direct";
  out.emplace_back("direct", s);
  out.emplace_back("particles", base_scene());
  s = base_scene();
  s["cues"]["particles"]["motion"] = "ballistic";
  s["cues"]["particles"]["collisions"] = true;
  s["output"]["vtk"] = true;
  out.emplace_back("particles-ballistic-collisions-vtk", s);
  s = base_scene();
  s["cues"]["field"] = "grid";
  s["cues"]["grid"]["spacing"] = 0.5;
  s["cues"]["grid"]["scheme"] = "implicit";
  out.emplace_back("grid-implicit", s);
  s["cues"]["grid"]["scheme"] = "explicit";
  s["cues"]["grid"]["boundary"] = "reflecting";
  out.emplace_back("grid-explicit-reflecting", s);
  s = base_scene();
  s["cues"]["field"] = "analytic";
  s["axons"]["growth_modulation"] = 0.3;
  out.emplace_back("analytic-modulated", s);
  s = base_scene();
  s["cues"]["field"] = "imposed";
  out.emplace_back("imposed", s);
  // The signalling growth model (its 11 species per axon are state): the Bicknell explant,
  // inhibition from the population's mean, SNR steering.
  s = json::parse(test::read_file(fs::path(AXG_SOURCE_DIR) / "scenes/assay-bicknell.json"));
  s["neurons"]["count"] = 300;
  s["steps"] = 24;
  s["dt"] = 2.0;
  s["cues"]["warmup_steps"] = 6;
  s["axons"]["signalling"]["inhibition"] = "population";
  s["guidance"] = {{"model", "snr"}, {"noise", "binding"}, {"integration_time", 2.0}};
  s["output"] = {{"checkpoint_every", 4}, {"paths", true}};
  out.emplace_back("signalling-imposed", s);
  // Decisions over several steps (their sums are state, and a checkpoint falls inside an
  // interval): three steps an interval, and a T of 2.5 steps (intervals of 2 and 3).
  s = base_scene();
  s["cues"]["field"] = "analytic";
  s["dt"] = 0.5;
  s["axons"]["step_length"] = 0.175;
  s["axons"]["growth_modulation"] = 0.3;
  s["guidance"]["integration_time"] = 1.5;
  out.emplace_back("analytic-integrated-modulated", s);
  s = base_scene();
  s["guidance"]["integration_time"] = 2.5;
  s["guidance"]["noise"] = "binding";
  out.emplace_back("particles-integrated", s);
  return out;
}

// The kill points, every stage: placement, setup (warm-up), steps, a checkpoint being
// written, each output file being written, the final manifest.
const std::vector<std::string> kKillPoints = {
    "placement",          "setup",           "step 3",         "checkpoint 8",          "step 13",
    "output neurons.csv", "output stats.csv", "checkpoint 4",  "output graph.graphml", "manifest",
    "step 22",            "output paths.csv", "checkpoint 20", "output connections.csv"};

class Trial {
 public:
  Trial(const std::string& name, const json& scene) : name_(name) {
    scene_ = tmp_.path() / "scene.json";
    std::ofstream(scene_) << scene.dump();
  }
  const fs::path& dir() const { return tmp_.path(); }
  fs::path scene() const { return scene_; }
  // The uninterrupted run's outputs, once per backend.
  const std::map<std::string, std::string>& expected(const std::string& backend) {
    auto& e = expected_[backend];
    if (e.empty()) {
      const fs::path out = tmp_.path() / ("ref-" + backend);
      const Result r = axonguide(fmt::format("run {} --out {} -q --backend {}", scene_.string(), out.string(), backend), tmp_.path());
      EXPECT_EQ(r.code, 0) << r.err;
      e = outputs(out);
    }
    return e;
  }
  // Kills a run at `point`, resumes it, and compares.
  void kill_and_resume(const std::string& point, const std::string& backend, const std::string& resume_backend) {
    SCOPED_TRACE(fmt::format("{}: killed at \"{}\" ({}), resumed on {}", name_, point, backend, resume_backend));
    const fs::path out = tmp_.path() / fmt::format("k{}", trials_++);
    const Result killed = axonguide(fmt::format("run {} --out {} -q --backend {}", scene_.string(), out.string(), backend),
                                    tmp_.path(), fmt::format("AXG_FAULT_KILL_AT='{}'", point));
    ASSERT_EQ(killed.code, 128 + SIGKILL) << killed.err;
    EXPECT_EQ(axonguide("verify " + out.string(), tmp_.path()).code, 1);  // not whole
    // Every other resume on one thread (the killed run had all cores): the thread count
    // is not part of the state.
    const Result resumed = axonguide(fmt::format("run --resume {} -q --backend {} --threads {}", out.string(),
                                                 resume_backend, trials_ % 2 == 0 ? 1 : 2),
                                     tmp_.path());
    ASSERT_EQ(resumed.code, 0) << resumed.err;
    EXPECT_EQ(axonguide("verify " + out.string(), tmp_.path()).code, 0);
    EXPECT_EQ(outputs(out), expected(backend));
    EXPECT_FALSE(fs::exists(out / kCheckpointName));
    EXPECT_FALSE(fs::exists(out / kLockName));
  }

 private:
  test::TempDir tmp_;
  std::string name_;
  fs::path scene_;
  std::map<std::string, std::map<std::string, std::string>> expected_;
  int trials_ = 0;
};

// 8 scenes (7 field types and the signalling model) x 4 kill points = 32 trials on the reference engine, each point in turn.
TEST(resume, KilledAnywhereResumesToTheSameBytesForEveryFieldType) {
  std::size_t next = 0;
  for (const auto& [name, scene] : field_scenes()) {
    Trial t(name, scene);
    for (int k = 0; k < 4; ++k) t.kill_and_resume(kKillPoints[next++ % kKillPoints.size()], "reference", "reference");
  }
}

// The accelerator's engine (its CPU build): killed and resumed on itself, and a
// checkpoint of either engine resumed on the other (the state is backend-independent).
TEST(resume, TheAcceleratorsEngineResumesToTheSameBytes) {
  const auto scenes = field_scenes();
  std::size_t next = 3;
  for (std::size_t s : {1u, 3u, 5u, 7u, 8u, 9u}) {
    Trial t(scenes[s].first, scenes[s].second);
    for (int k = 0; k < 2; ++k) t.kill_and_resume(kKillPoints[next++ % kKillPoints.size()], "emulated", "emulated");
    t.kill_and_resume("step 13", "emulated", "reference");
    t.kill_and_resume("checkpoint 8", "reference", "emulated");
  }
}

// Arbours (issue 41) with synapses (issue 42): a culture whose cones steer by an imposed gradient with decisions over 3
// steps (checkpoints fall inside an interval: the cones' sums are state), with lateral
// branches, SWC and paths; killed with SIGKILL at every stage and resumed by the command
// (arbour_engine_test resumes a particle field's state with the cones' sums in process).
TEST(resume, AKilledArbourRunResumesToTheSameBytes) {
  json s = json::parse(test::read_file(fs::path(test::source_dir()) / "scenes" / "culture.json"));
  s["neurons"]["count"] = 40;
  s["neurons"]["region"]["radius"] = 300;
  s["steps"] = 24;
  s["guidance"] = {{"model", "snr"}, {"noise", "snapshot"}, {"gain", 40}, {"integration_time", 1.5},
                   {"growth_cone_width", 10}, {"sensing_radius", 10}};
  s["cues"] = {{"field", "imposed"},
               {"imposed", {{"profile", "exponential"}, {"direction", {1, 0, 0}}, {"steepness", 1.0}}},
               {"sources", {{{"kind", "attractant"}, {"position", {0, 0, 0}}}}}};
  s["arbours"]["axon"]["lateral_rate"] = 0.002;
  s["synapses"] = {{"distance", 3}, {"probability", 0.7}};  // issue 42: detected on the final arbours
  s["output"] = {{"checkpoint_every", 4}, {"paths", true}, {"swc", true}};
  Trial t("culture-steered-lateral", s);
  for (const char* point : {"placement", "setup", "step 3", "checkpoint 8", "step 13", "output neurons.csv",
                            "output synapses.csv", "output paths.csv", "checkpoint 20", "manifest"})
    t.kill_and_resume(point, "reference", "reference");
  // The accelerator's arbours (its CPU build): killed and resumed on itself, and a
  // checkpoint of either engine resumed on the other.
  for (const char* point : {"step 13", "checkpoint 20"}) t.kill_and_resume(point, "emulated", "emulated");
  t.kill_and_resume("step 13", "emulated", "reference");
  t.kill_and_resume("checkpoint 8", "reference", "emulated");
}

// kill -9 at random times once the run has claimed its folder (its running manifest is
// there; the run's own pace decides the stage it is in). A kill before that, while the
// command starts, leaves nothing to resume: --resume says the folder is not a run's, and
// a plain run into it gives the uninterrupted bytes.
TEST(resume, KilledAtRandomTimesResumesToTheSameBytes) {
  json s = base_scene();
  s["neurons"]["count"] = 3000;
  s["steps"] = 60;
  s["output"]["checkpoint_every"] = 5;
  Trial t("random times", s);
  const auto& want = t.expected("reference");
  std::mt19937 rng(20261202);
  int killed = 0;
  for (int trial = 0; trial < 8; ++trial) {
    const fs::path out = t.dir() / fmt::format("r{}", trial);
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      ::execl(test::binary().c_str(), "axonguide", "run", t.scene().c_str(), "--out", out.c_str(), "-q",
              static_cast<char*>(nullptr));
      ::_exit(127);
    }
    // The wait for the claim is bounded by the run itself: it exits (and the kill is
    // then of a finished process) if it never writes one.
    const auto started = std::chrono::steady_clock::now();
    while (!fs::exists(out / kManifestName) && std::chrono::steady_clock::now() - started < std::chrono::seconds(20))
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    std::this_thread::sleep_for(std::chrono::milliseconds(std::uniform_int_distribution<int>(20, 600)(rng)));
    ::kill(pid, SIGKILL);
    int status = 0;
    ::waitpid(pid, &status, 0);
    killed += WIFSIGNALED(status);
    const Result resumed = axonguide(fmt::format("run --resume {} -q", out.string()), t.dir());
    ASSERT_EQ(resumed.code, 0) << resumed.err;
    EXPECT_EQ(outputs(out), want) << "trial " << trial;
  }
  EXPECT_GT(killed, 0);  // at least some of them died mid-run

  // Killed after it made its folder and took the lock, before the running manifest: the
  // folder holds the lock file alone (the kernel released the lock with the process).
  const fs::path early = t.dir() / "early";
  fs::create_directories(early);
  std::ofstream(early / kLockName).flush();
  const Result refused = axonguide(fmt::format("run --resume {} -q", early.string()), t.dir());
  EXPECT_EQ(refused.code, 2) << refused.err;
  EXPECT_NE(refused.err.find("not a run's folder"), std::string::npos) << refused.err;
  const Result fresh = axonguide(fmt::format("run {} --out {} -q", t.scene().string(), early.string()), t.dir());
  ASSERT_EQ(fresh.code, 0) << fresh.err;
  EXPECT_EQ(outputs(early), want);
}

// SIGINT and SIGTERM: the step ends, a checkpoint and an "interrupted" manifest are
// written, the exit is 130 or 143 with a message, no temporary file is left, and the
// resume gives the uninterrupted bytes.
TEST(resume, SigintAndSigtermStopWithACheckpoint) {
  Trial t("signals", field_scenes()[1].second);
  for (const auto& [sig, code] : {std::pair{"INT", 130}, std::pair{"TERM", 143}}) {
    const fs::path out = t.dir() / fmt::format("sig{}", sig);
    const Result r = axonguide(fmt::format("run {} --out {} -q", t.scene().string(), out.string()), t.dir(),
                               fmt::format("AXG_FAULT_KILL_AT='step 10' AXG_FAULT_SIGNAL={}", sig));
    EXPECT_EQ(r.code, code) << r.err;
    EXPECT_NE(r.err.find(fmt::format("interrupted by SIG{} after step 10 of 24", sig)), std::string::npos) << r.err;
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(out)) names.insert(e.path().filename().string());
    EXPECT_EQ(names, (std::set<std::string>{"manifest.json", kCheckpointName})) << "no temporary files, no outputs";
    const json m = json::parse(test::read_file(out / "manifest.json"));
    EXPECT_EQ(m["status"], "interrupted");
    EXPECT_EQ(m["checkpoint"]["step"], 10);
    EXPECT_EQ(m["checkpoint"]["sha256"], sha256_file(out / kCheckpointName));
    EXPECT_EQ(read_checkpoint(out / kCheckpointName).step, 10u);
    const Result v = axonguide("verify " + out.string(), t.dir());
    EXPECT_EQ(v.code, 1);
    const Result resumed = axonguide(fmt::format("run --resume {} -q", out.string()), t.dir());
    ASSERT_EQ(resumed.code, 0) << resumed.err;
    EXPECT_EQ(outputs(out), t.expected("reference"));
  }
}

// A resumed run is running again once its first step is done: its manifest no longer says
// "interrupted" nor names the checkpoint it started from (the next checkpoint replaces that
// file). Killed then, the folder says "running", and a second resume finishes it with the
// same bytes.
TEST(resume, AResumedRunIsRunningAgain) {
  Trial t("resumed-running", field_scenes()[1].second);
  const fs::path out = t.dir() / "o";
  ASSERT_EQ(axonguide(fmt::format("run {} --out {} -q", t.scene().string(), out.string()), t.dir(),
                      "AXG_FAULT_KILL_AT='step 10' AXG_FAULT_SIGNAL=INT")
                .code,
            130);
  ASSERT_EQ(json::parse(test::read_file(out / "manifest.json"))["status"], "interrupted");
  const Result killed = axonguide(fmt::format("run --resume {} -q", out.string()), t.dir(),
                                  "AXG_FAULT_KILL_AT='step 18'");
  ASSERT_EQ(killed.code, 128 + SIGKILL) << killed.err;
  const json m = json::parse(test::read_file(out / "manifest.json"));
  EXPECT_EQ(m["status"], "running");
  EXPECT_FALSE(m.contains("interrupted"));
  EXPECT_FALSE(m.contains("checkpoint"));
  EXPECT_EQ(read_checkpoint(out / kCheckpointName).step, 16u);  // checkpoint_every 4
  const Result v = axonguide("verify " + out.string(), t.dir());
  EXPECT_EQ(v.code, 1);
  const Result resumed = axonguide(fmt::format("run --resume {} -q", out.string()), t.dir());
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  EXPECT_EQ(outputs(out), t.expected("reference"));
}

// An interrupted run's manifest records the checkpoint it stopped with (its SHA-256). A
// resume refuses, with exit 2 and the folder unchanged, when that file is missing (it does
// not start again from step 0) or when another whole checkpoint of the same scene stands in
// its place; with the file put back it finishes with the same bytes.
TEST(resume, AnInterruptedRunResumesOnlyFromTheCheckpointItStoppedWith) {
  Trial t("own-checkpoint", field_scenes()[1].second);
  const fs::path out = t.dir() / "o", earlier = t.dir() / "earlier";
  for (const auto& [dir, step] : {std::pair{out, 10}, std::pair{earlier, 6}})
    ASSERT_EQ(axonguide(fmt::format("run {} --out {} -q", t.scene().string(), dir.string()), t.dir(),
                        fmt::format("AXG_FAULT_KILL_AT='step {}' AXG_FAULT_SIGNAL=INT", step))
                  .code,
              130);
  const std::string manifest = test::read_file(out / "manifest.json");
  const fs::path own = t.dir() / "own.bin";
  fs::rename(out / kCheckpointName, own);
  Result r = axonguide(fmt::format("run --resume {} -q", out.string()), t.dir());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("the run stopped with a checkpoint (after step 10), but"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("is missing"), std::string::npos) << r.err;
  EXPECT_EQ(test::read_file(out / "manifest.json"), manifest);
  EXPECT_FALSE(fs::exists(out / kCheckpointName));
  fs::copy_file(earlier / kCheckpointName, out / kCheckpointName);  // whole, the same scene, step 6
  r = axonguide(fmt::format("run --resume {} -q", out.string()), t.dir());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("is whole, but not the checkpoint this run stopped with"), std::string::npos) << r.err;
  EXPECT_EQ(test::read_file(out / "manifest.json"), manifest);
  fs::rename(own, out / kCheckpointName);
  r = axonguide(fmt::format("run --resume {} -q", out.string()), t.dir());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(outputs(out), t.expected("reference"));
}

TEST(resume, RefusesAnotherSceneAnotherBuildAndADamagedCheckpoint) {
  Trial t("refusals", field_scenes()[0].second);
  const fs::path out = t.dir() / "k";
  ASSERT_EQ(axonguide(fmt::format("run {} --out {} -q", t.scene().string(), out.string()), t.dir(),
                      "AXG_FAULT_KILL_AT='step 9'")
                .code,
            128 + SIGKILL);
  // Another scene.
  json other = field_scenes()[0].second;
  other["seed"] = 99;
  const fs::path other_path = t.dir() / "other.json";
  std::ofstream(other_path) << other.dump();
  Result r = axonguide(fmt::format("run {} --resume {} -q", other_path.string(), out.string()), t.dir());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("is not the scene of this run"), std::string::npos) << r.err;
  // The same scene, named: accepted below. A damaged checkpoint: exit 3.
  const std::string saved = test::read_file(out / kCheckpointName);
  std::string damaged = saved;
  damaged[damaged.size() / 2] ^= 1;
  std::ofstream(out / kCheckpointName, std::ios::binary) << damaged;
  r = axonguide(fmt::format("run --resume {} -q", out.string()), t.dir());
  EXPECT_EQ(r.code, 3);
  EXPECT_NE(r.err.find("its SHA-256 does not match"), std::string::npos) << r.err;
  std::ofstream(out / kCheckpointName, std::ios::binary) << saved.substr(0, saved.size() - 100);
  r = axonguide(fmt::format("run --resume {} -q", out.string()), t.dir());
  EXPECT_EQ(r.code, 3);
  EXPECT_NE(r.err.find("is damaged"), std::string::npos) << r.err;
  std::ofstream(out / kCheckpointName, std::ios::binary) << saved;
  // Another version in the manifest.
  json m = json::parse(test::read_file(out / "manifest.json"));
  const json good = m;
  m["axonguide"]["version"] = "0.0.1";
  std::ofstream(out / "manifest.json") << m.dump();
  r = axonguide(fmt::format("run --resume {} -q", out.string()), t.dir());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("must use the same build"), std::string::npos) << r.err;
  std::ofstream(out / "manifest.json") << good.dump();
  r = axonguide(fmt::format("run {} --resume {} -q", t.scene().string(), out.string()), t.dir());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(outputs(out), t.expected("reference"));
  // Nothing left to resume.
  r = axonguide(fmt::format("run --resume {}", out.string()), t.dir());
  EXPECT_EQ(r.code, 0);
  // Options that contradict a resume.
  EXPECT_EQ(axonguide(fmt::format("run --resume {} --seed 3", out.string()), t.dir()).code, 2);
  EXPECT_EQ(axonguide(fmt::format("run --resume {} --force", out.string()), t.dir()).code, 2);
  EXPECT_EQ(axonguide(fmt::format("run --resume {}/nowhere", t.dir().string()), t.dir()).code, 2);
}

// A checkpoint that is whole (its hash recomputed) but whose field state does not fit the
// scene: a grid of another size, a particle of a cue the scene lacks, particle arrays of
// different lengths. Each is refused with exit 3 and a message, never read past its end.
TEST(resume, ACheckpointWhoseFieldStateDoesNotFitIsRefused) {
  std::map<std::string, json> scenes;
  for (const auto& [name, j] : field_scenes()) scenes[name] = j;
  struct Edit {
    const char* scene;
    const char* what;
    std::function<void(EngineState&)> edit;
    const char* message;
  };
  const std::vector<Edit> edits = {
      {"grid-implicit", "a grid one value short", [](EngineState& e) { e.grid.pop_back(); }, "the grid has"},
      {"particles", "a particle of cue 7", [](EngineState& e) { e.particle_cue.back() = 7; }, "a particle of cue 7"},
      {"particles", "an id short", [](EngineState& e) { e.particle_id.pop_back(); },
       "per-particle arrays of different lengths"},
      {"particles-ballistic-collisions-vtk", "no velocities", [](EngineState& e) { e.particle_vel.clear(); },
       "no velocities"},
      {"particles-integrated", "decision sums one value short", [](EngineState& e) { e.guidance.pop_back(); },
       "the decision sums do not match"},
  };
  for (const Edit& x : edits) {
    Trial t(std::string("misfit-") + x.scene, scenes.at(x.scene));
    const fs::path out = t.dir() / "k";
    ASSERT_EQ(axonguide(fmt::format("run {} --out {} -q", t.scene().string(), out.string()), t.dir(),
                        "AXG_FAULT_KILL_AT='step 9'")
                  .code,
              128 + SIGKILL);
    RunCheckpoint c = read_checkpoint(out / kCheckpointName);
    ASSERT_FALSE(c.engine.particle_pos.empty() && c.engine.grid.empty()) << x.scene << ": no field state";
    x.edit(c.engine);
    json m = json::parse(test::read_file(out / "manifest.json"));
    c.progress.scene = parse_scene(m["scene"].dump(), "manifest").scene;  // the hash the checkpoint carries
    ASSERT_EQ(scene_hash(c.progress.scene), c.scene_hash);
    write_checkpoint(out, c.progress, c.step, c.engine);
    if (m.contains("checkpoint")) m["checkpoint"]["sha256"] = sha256_file(out / kCheckpointName);
    std::ofstream(out / "manifest.json") << m.dump();
    const std::string manifest = test::read_file(out / "manifest.json");
    const Result r = axonguide(fmt::format("run --resume {} -q", out.string()), t.dir());
    EXPECT_EQ(r.code, 3) << x.what << ": " << r.err;
    EXPECT_NE(r.err.find(x.message), std::string::npos) << x.what << ": " << r.err;
    EXPECT_EQ(test::read_file(out / "manifest.json"), manifest) << x.what << ": a refused resume changed the manifest";
  }
}

// The wall-clock interval: with checkpoint_seconds below a step's time every step is
// checkpointed; with neither setting there is none, and a resume starts from step 0.
TEST(resume, WallClockCheckpointsAndNone) {
  json s = base_scene();
  s["output"].erase("checkpoint_every");
  s["output"]["checkpoint_seconds"] = 1e-9;
  Trial t("wall clock", s);
  const fs::path out = t.dir() / "w";
  ASSERT_EQ(axonguide(fmt::format("run {} --out {} -q", t.scene().string(), out.string()), t.dir(),
                      "AXG_FAULT_KILL_AT='step 11'")
                .code,
            128 + SIGKILL);
  EXPECT_EQ(read_checkpoint(out / kCheckpointName).step, 10u);
  Result r = axonguide(fmt::format("run --resume {} -q", out.string()), t.dir());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(outputs(out), t.expected("reference"));

  s["output"]["checkpoint_seconds"] = 0;
  Trial none("no checkpoints", s);
  const fs::path out2 = none.dir() / "n";
  ASSERT_EQ(axonguide(fmt::format("run {} --out {}", none.scene().string(), out2.string()), none.dir(),
                      "AXG_FAULT_KILL_AT='step 20'")
                .code,
            128 + SIGKILL);
  EXPECT_FALSE(fs::exists(out2 / kCheckpointName));
  r = axonguide(fmt::format("run --resume {}", out2.string()), none.dir());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("has no checkpoint yet; the run starts again from step 0"), std::string::npos) << r.err;
  EXPECT_EQ(outputs(out2), none.expected("reference"));
}

// The canonical scene of a manifest reads back as the same scene (resume depends on it).
TEST(resume, EveryBundledSceneRoundTripsThroughItsCanonicalForm) {
  for (const auto& e : fs::directory_iterator(fs::path(test::source_dir()) / "scenes")) {
    if (test::is_sweep_file(e.path())) continue;
    const Scene s = load_scene_file(e.path().string()).scene;
    const Scene back = parse_scene(scene_to_json(s).dump(), "canonical").scene;
    EXPECT_EQ(scene_hash(back), scene_hash(s)) << e.path();
  }
  for (const auto& [name, j] : field_scenes()) {
    const Scene s = parse_scene(j.dump(), name).scene;
    EXPECT_EQ(scene_hash(parse_scene(scene_to_json(s).dump(), "canonical").scene), scene_hash(s)) << name;
  }
}

// One run per folder.
TEST(run_folder, RefusesAnotherRunsFolderAndForceRemovesExactlyItsFiles) {
  test::TempDir tmp;
  const fs::path cue_path = tmp.path() / "cue.json", direct_path = tmp.path() / "direct.json";
  std::ofstream(cue_path) << cue_with_vtk().dump();
  std::ofstream(direct_path) << direct_without_paths().dump();
  const fs::path out = tmp.path() / "o";
  ASSERT_EQ(axonguide(fmt::format("run {} --out {} -q", cue_path.string(), out.string()), tmp.path()).code, 0);
  ASSERT_TRUE(fs::exists(out / "paths.csv") && fs::exists(out / "vtk") && fs::exists(out / "growth.pvd"));
  std::ofstream(out / "notes.txt") << "mine";
  std::ofstream(out / "vtk" / "my-view.pvsm") << "mine too";
  Result r = axonguide(fmt::format("run {} --out {} -q", direct_path.string(), out.string()), tmp.path());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("holds another run"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(out / "paths.csv"));  // refused: nothing touched
  r = axonguide(fmt::format("run {} --out {} -q --force", direct_path.string(), out.string()), tmp.path());
  ASSERT_EQ(r.code, 0) << r.err;
  std::set<std::string> names;
  for (const auto& e : fs::recursive_directory_iterator(out)) names.insert(fs::relative(e.path(), out).generic_string());
  EXPECT_EQ(names, (std::set<std::string>{"bfs.csv", "connections.csv", "graph.graphml", "manifest.json", "neurons.csv",
                                          "stats.csv", "timings.csv", "notes.txt", "vtk", "vtk/my-view.pvsm"}));
  EXPECT_EQ(axonguide("verify " + out.string(), tmp.path()).code, 0);
  // Outputs without a manifest: refused even with --force.
  const fs::path bare = tmp.path() / "bare";
  fs::create_directories(bare);
  std::ofstream(bare / "neurons.csv") << "id\n";
  r = axonguide(fmt::format("run {} --out {} -q --force", direct_path.string(), bare.string()), tmp.path());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("no manifest.json"), std::string::npos) << r.err;
}

// A scene that the run itself would refuse (a cue grid of too many nodes, packing beyond
// what placement reaches) is refused before --force touches the folder: the complete run in
// it stays whole. (The grid check was once made only inside the run, after --force had
// removed the old run's files.)
TEST(run_folder, ForceWithARefusedSceneKeepsThePreviousRun) {
  test::TempDir tmp;
  const fs::path good = tmp.path() / "good.json", out = tmp.path() / "o";
  std::ofstream(good) << base_scene().dump();
  ASSERT_EQ(axonguide(fmt::format("run {} --out {} -q", good.string(), out.string()), tmp.path()).code, 0);
  const std::map<std::string, std::string> before = outputs(out);
  json fine_grid = base_scene();
  fine_grid["cues"]["field"] = "grid";
  fine_grid["cues"]["grid"]["spacing"] = 1e-4;  // far more nodes per axis than allowed
  json dense = base_scene();
  dense["neurons"]["count"] = 200000;  // a packing fraction (1.28) above the densest packing (0.74)
  for (const auto& [name, scene, code] : {std::tuple{"fine-grid", fine_grid, 2}, std::tuple{"dense", dense, 3}}) {
    const fs::path path = tmp.path() / (std::string(name) + ".json");
    std::ofstream(path) << scene.dump();
    const Result r = axonguide(fmt::format("run {} --out {} -q --force", path.string(), out.string()), tmp.path());
    EXPECT_EQ(r.code, code) << name << ": " << r.err;
    EXPECT_EQ(outputs(out), before) << name << ": the previous run's files changed: " << r.err;
    EXPECT_EQ(axonguide("verify " + out.string(), tmp.path()).code, 0) << name;
  }
}

// A file under a run output's name that the old manifest does not list is not the old run's
// to replace: when the new run would write it (or remove it, failing), --force refuses and
// leaves the folder as it was.
TEST(run_folder, ForceRefusesToWriteOverAFileTheOldManifestDoesNotList) {
  test::TempDir tmp;
  const fs::path direct_path = tmp.path() / "direct.json", cue_path = tmp.path() / "cue.json", out = tmp.path() / "o";
  std::ofstream(direct_path) << direct_without_paths().dump();
  std::ofstream(cue_path) << cue_with_vtk().dump();
  ASSERT_EQ(axonguide(fmt::format("run {} --out {} -q", direct_path.string(), out.string()), tmp.path()).code, 0);
  std::ofstream(out / "paths.csv") << "mine\n";  // the direct run writes no paths.csv
  fs::create_directories(out / "vtk");
  std::ofstream(out / "vtk" / "mine.vtp") << "mine too\n";
  const std::map<std::string, std::string> before = outputs(out);
  const Result r = axonguide(fmt::format("run {} --out {} -q --force", cue_path.string(), out.string()), tmp.path());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("paths.csv, vtk/mine.vtp: not listed by the old run's manifest"), std::string::npos) << r.err;
  EXPECT_EQ(outputs(out), before);
  EXPECT_EQ(test::read_file(out / "paths.csv"), "mine\n");
  // Moved away, the same --force replaces the old run.
  fs::remove(out / "paths.csv");
  fs::remove_all(out / "vtk");
  EXPECT_EQ(axonguide(fmt::format("run {} --out {} -q --force", cue_path.string(), out.string()), tmp.path()).code, 0);
  EXPECT_EQ(axonguide("verify " + out.string(), tmp.path()).code, 0);
}

// A manifest whose keys have another type than a run writes (a hand edit, a damaged
// file) is bad input, exit 2, named, for every command that reads it.
TEST(run_folder, AManifestKeyOfAnotherTypeIsBadInput) {
  test::TempDir tmp;
  const fs::path scene = tmp.path() / "s.json", out = tmp.path() / "o";
  std::ofstream(scene) << base_scene().dump();
  ASSERT_EQ(axonguide(fmt::format("run {} --out {} -q", scene.string(), out.string()), tmp.path()).code, 0);
  const json good = json::parse(test::read_file(out / "manifest.json"));
  for (const auto& [pointer, value, message] :
       {std::tuple{"/status", json(5), "\"status\" is not a string"},
        std::tuple{"/created", json::array(), "\"created\" is not a string"},
        std::tuple{"/axonguide", json("x"), "\"axonguide\" is not an object"},
        std::tuple{"/axonguide/version", json(1.5), "\"axonguide\".\"version\" is not a string"}}) {
    json m = good;
    m[json::json_pointer(pointer)] = value;
    std::ofstream(out / "manifest.json") << m.dump();
    for (const std::string& command : {fmt::format("run {} --out {} -q", scene.string(), out.string()),
                                      fmt::format("run --resume {} -q", out.string())}) {
      const Result r = axonguide(command, tmp.path());
      EXPECT_EQ(r.code, 2) << pointer << ", " << command << ": " << r.err;
      EXPECT_NE(r.err.find(message), std::string::npos) << pointer << ", " << command << ": " << r.err;
    }
  }
  std::ofstream(out / "manifest.json") << good.dump();
}

// A kill while a --force run replaces an older one leaves a folder whose manifest names
// every file in it: --resume finishes it, with nothing of the old run left.
TEST(run_folder, AKilledReplacementIsStillOneRun) {
  test::TempDir tmp;
  const fs::path cue_path = tmp.path() / "cue.json", direct_path = tmp.path() / "direct.json";
  std::ofstream(cue_path) << cue_with_vtk().dump();
  std::ofstream(direct_path) << direct_without_paths().dump();
  const fs::path want = tmp.path() / "want";
  ASSERT_EQ(axonguide(fmt::format("run {} --out {} -q", direct_path.string(), want.string()), tmp.path()).code, 0);
  for (const std::string point : {"step 5", "output neurons.csv", "manifest"}) {
    const fs::path out = tmp.path() / "o";
    fs::remove_all(out);
    ASSERT_EQ(axonguide(fmt::format("run {} --out {} -q", cue_path.string(), out.string()), tmp.path()).code, 0);
    const Result k = axonguide(fmt::format("run {} --out {} -q --force", direct_path.string(), out.string()), tmp.path(),
                               fmt::format("AXG_FAULT_KILL_AT='{}'", point));
    ASSERT_EQ(k.code, 128 + SIGKILL) << point;
    EXPECT_EQ(axonguide("verify " + out.string(), tmp.path()).code, 1) << point;
    EXPECT_EQ(axonguide("view " + out.string(), tmp.path()).code, 2) << point;
    ASSERT_EQ(axonguide(fmt::format("run --resume {} -q", out.string()), tmp.path()).code, 0) << point;
    EXPECT_EQ(outputs(out), outputs(want)) << point;
  }
}

// Every file of a folder, hidden ones included, with its bytes' hash: the manifest too.
std::map<std::string, std::string> every_file(const fs::path& dir) {
  std::map<std::string, std::string> h;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) h[fs::relative(e.path(), dir).generic_string()] = sha256_file(e.path());
  return h;
}

// A --force run that fails where only the run can find it (a placement that jams below the
// packing bound; a file-size limit, as a full disk, while it writes) puts the complete run
// it replaced back: every file, the manifest included, byte for byte, and .replaced/ is
// gone. The same --force that succeeds leaves no .replaced/ either.
TEST(run_folder, AForceRunThatFailsPutsThePreviousRunBack) {
  test::TempDir tmp;
  json cue = cue_with_vtk();
  cue["output"]["checkpoint_every"] = 0;  // no checkpoint: a failure leaves nothing to resume
  const json jam = jamming();
  json big = base_scene();
  big["neurons"]["count"] = 3000;
  big["guidance"]["model"] = "direct";
  big["output"]["checkpoint_every"] = 0;
  const fs::path cue_path = tmp.path() / "cue.json", jam_path = tmp.path() / "jam.json",
                 big_path = tmp.path() / "big.json", out = tmp.path() / "o";
  std::ofstream(cue_path) << cue.dump();
  std::ofstream(jam_path) << jam.dump();
  std::ofstream(big_path) << big.dump();
  ASSERT_EQ(axonguide(fmt::format("run {} --out {} -q", cue_path.string(), out.string()), tmp.path()).code, 0);
  std::ofstream(out / "notes.txt") << "mine";
  const std::map<std::string, std::string> before = every_file(out);
  ASSERT_EQ(before.count("vtk/axons_000010.vtp"), 1u) << "the run has VTK frames, in a subfolder";
  for (const auto& [name, path, env, message] :
       {std::tuple{"jam", jam_path, std::string(), std::string("placement failed")},
        std::tuple{"full", big_path, std::string("ulimit -f 64;"), std::string("File too large")}}) {
    const Result r = axonguide(fmt::format("run {} --out {} -q --force", path.string(), out.string()), tmp.path(), env);
    EXPECT_EQ(r.code, 3) << name << ": " << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << name << ": " << r.err;
    EXPECT_EQ(every_file(out), before) << name << ": " << r.err;
    EXPECT_EQ(axonguide("verify " + out.string(), tmp.path()).code, 0) << name;
  }
  ASSERT_EQ(axonguide(fmt::format("run {} --out {} -q --force", big_path.string(), out.string()), tmp.path()).code, 0);
  EXPECT_FALSE(fs::exists(out / kReplacedName));
  EXPECT_TRUE(fs::exists(out / "notes.txt"));
  EXPECT_EQ(axonguide("verify " + out.string(), tmp.path()).code, 0);
}

// A --force run killed while it moves the complete run it replaces into .replaced/, later
// while it runs, or while a failure moves that run back, leaves a folder that ends as one
// run either way: --resume finishes the new run and removes .replaced/ (or, when the new run
// fails before its first checkpoint, puts the first run back), and another --force that
// fails puts the first run back whole. A .replaced/ left beside a complete run is removed by
// the --resume that finds nothing to do.
TEST(run_folder, AKilledReplacementKeepsThePreviousRunUntilItIsWhole) {
  test::TempDir tmp;
  const fs::path cue_path = tmp.path() / "cue.json", direct_path = tmp.path() / "direct.json",
                 jam_path = tmp.path() / "jam.json";
  std::ofstream(cue_path) << cue_with_vtk().dump();
  std::ofstream(direct_path) << direct_without_paths().dump();
  std::ofstream(jam_path) << jamming().dump();
  const fs::path want = tmp.path() / "want";
  ASSERT_EQ(axonguide(fmt::format("run {} --out {} -q", direct_path.string(), want.string()), tmp.path()).code, 0);
  const std::string jam_force = fmt::format("run {} --out {{}} -q --force", jam_path.string());
  struct Case {
    std::string point;    // where the --force run is killed
    fs::path scene;       // the scene of that run
    std::string then;     // "resume", or "jam": another --force, which fails
  };
  const std::vector<Case> cases{
      {"keep connections.csv", direct_path, "resume"}, {"keep vtk/axons_000010.vtp", direct_path, "resume"},
      {"step 5", direct_path, "resume"},               {"keep connections.csv", direct_path, "jam"},
      {"keep vtk/axons_000010.vtp", direct_path, "jam"}, {"step 5", direct_path, "jam"},
      {"keep connections.csv", jam_path, "resume"},    {"restore connections.csv", jam_path, "resume"},
      {"restore vtk/axons_000010.vtp", jam_path, "jam"}};
  for (const Case& c : cases) {
    const std::string what = c.point + ", " + c.scene.filename().string() + ", then " + c.then;
    const fs::path out = tmp.path() / "o";
    fs::remove_all(out);
    ASSERT_EQ(axonguide(fmt::format("run {} --out {} -q", cue_path.string(), out.string()), tmp.path()).code, 0);
    const std::map<std::string, std::string> first = every_file(out);
    const Result k = axonguide(fmt::format("run {} --out {} -q --force", c.scene.string(), out.string()), tmp.path(),
                               fmt::format("AXG_FAULT_KILL_AT='{}'", c.point));
    ASSERT_EQ(k.code, 128 + SIGKILL) << what << ": " << k.err;
    EXPECT_EQ(sha256_file(out / kReplacedName / "manifest.json"), first.at("manifest.json")) << what;
    EXPECT_EQ(axonguide("verify " + out.string(), tmp.path()).code, 1) << what;
    const bool finishes = c.then == "resume" && c.scene == direct_path;
    const Result r = axonguide(c.then == "resume" ? fmt::format("run --resume {} -q", out.string())
                                                  : fmt::format(fmt::runtime(jam_force), out.string()),
                               tmp.path());
    EXPECT_EQ(r.code, finishes ? 0 : 3) << what << ": " << r.err;
    if (finishes) {
      EXPECT_EQ(outputs(out), outputs(want)) << what;
      EXPECT_FALSE(fs::exists(out / kReplacedName)) << what;
    } else {
      EXPECT_EQ(every_file(out), first) << what << ": " << r.err;
    }
    EXPECT_EQ(axonguide("verify " + out.string(), tmp.path()).code, 0) << what;
  }
  const fs::path out = tmp.path() / "o";
  fs::create_directories(out / kReplacedName);
  std::ofstream(out / kReplacedName / "neurons.csv") << "left by a run killed once it was whole\n";
  EXPECT_EQ(axonguide(fmt::format("run --resume {} -q", out.string()), tmp.path()).code, 0);
  EXPECT_FALSE(fs::exists(out / kReplacedName));
}

// A second run into a folder that a run holds is refused (the lock), and the first one
// finishes whole.
TEST(run_folder, ASecondRunIntoTheSameFolderIsRefused) {
  test::TempDir tmp;
  const fs::path scene = tmp.path() / "s.json", out = tmp.path() / "o";
  std::ofstream(scene) << base_scene().dump();
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    ::setenv("AXG_FAULT_KILL_AT", "step 5", 1);
    ::setenv("AXG_FAULT_SIGNAL", "STOP", 1);
    ::execl(test::binary().c_str(), "axonguide", "run", scene.c_str(), "--out", out.c_str(), "-q",
            static_cast<char*>(nullptr));
    ::_exit(127);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, WUNTRACED), pid);  // stopped at step 5, holding the lock
  ASSERT_TRUE(WIFSTOPPED(status));
  const Result second = axonguide(fmt::format("run {} --out {} -q", scene.string(), out.string()), tmp.path());
  EXPECT_EQ(second.code, 3);
  EXPECT_NE(second.err.find(fmt::format("another axonguide run (pid {})", pid)), std::string::npos) << second.err;
  const Result forced = axonguide(fmt::format("run {} --out {} -q --force", scene.string(), out.string()), tmp.path());
  EXPECT_EQ(forced.code, 3);
  const Result resumed = axonguide(fmt::format("run --resume {} -q", out.string()), tmp.path());
  EXPECT_EQ(resumed.code, 3);
  ::kill(pid, SIGCONT);
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  EXPECT_EQ(axonguide("verify " + out.string(), tmp.path()).code, 0);
  EXPECT_FALSE(fs::exists(out / kLockName));
}

// Two runs started together into one folder: one writes it, the other is refused (the
// lock while the first runs, the first's manifest after), and the folder is one run.
TEST(run_folder, TwoRunsStartedTogetherNeverMix) {
  test::TempDir tmp;
  const fs::path a = tmp.path() / "a.json", b = tmp.path() / "b.json";
  json s = base_scene();
  s["neurons"]["count"] = 1000;
  std::ofstream(a) << s.dump();
  s["seed"] = 7;
  std::ofstream(b) << s.dump();
  for (int trial = 0; trial < 10; ++trial) {
    const fs::path out = tmp.path() / fmt::format("o{}", trial);
    pid_t pids[2];
    for (int k = 0; k < 2; ++k) {
      pids[k] = ::fork();
      ASSERT_GE(pids[k], 0);
      if (pids[k] == 0) {
        const int devnull = ::open("/dev/null", O_WRONLY);
        ::dup2(devnull, 2);
        ::execl(test::binary().c_str(), "axonguide", "run", (k ? b : a).c_str(), "--out", out.c_str(), "-q",
                static_cast<char*>(nullptr));
        ::_exit(127);
      }
    }
    int codes[2];
    for (int k = 0; k < 2; ++k) {
      int status = 0;
      ::waitpid(pids[k], &status, 0);
      codes[k] = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    EXPECT_EQ((codes[0] == 0) + (codes[1] == 0), 1) << "trial " << trial << ": exits " << codes[0] << ", " << codes[1];
    for (int code : codes) EXPECT_TRUE(code == 0 || code == 2 || code == 3) << code;
    const FolderCheck c = verify_run_folder(out);
    EXPECT_TRUE(c.whole) << "trial " << trial;
    EXPECT_EQ(c.manifest["seed"], codes[0] == 0 ? 1 : 7) << "the manifest is the winner's";
  }
}

// A run that fails before it has anything to resume leaves nothing behind: no running
// manifest, and no folder when it made the folder.
TEST(run_folder, AFailedRunTakesItsFilesBack) {
  test::TempDir tmp;
  const fs::path dense = tmp.path() / "dense.json", out = tmp.path() / "o";
  std::ofstream(dense) << R"({"neurons": {"count": 5000, "soma_radius": 0.5, "region": {"radius": 5}}})";
  Result r = axonguide(fmt::format("run {} --out {} -q", dense.string(), out.string()), tmp.path());
  EXPECT_EQ(r.code, 3) << r.err;
  EXPECT_FALSE(fs::exists(out));
  fs::create_directories(out);
  std::ofstream(out / "notes.txt") << "mine";
  r = axonguide(fmt::format("run {} --out {} -q", dense.string(), out.string()), tmp.path());
  EXPECT_EQ(r.code, 3) << r.err;
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(out)) names.insert(e.path().filename().string());
  EXPECT_EQ(names, std::set<std::string>{"notes.txt"});
}

TEST(run_folder, VerifySaysWhyAFolderIsNotWhole) {
  test::TempDir tmp;
  const fs::path out = tmp.path() / "o";
  ASSERT_EQ(axonguide(fmt::format("run --out {} -q", out.string()), tmp.path()).code, 0);
  EXPECT_TRUE(verify_run_folder(out).whole);
  std::ofstream(out / "stats.csv", std::ios::app) << "9,9,9,9,9\n";
  fs::remove(out / "bfs.csv");
  FolderCheck c = verify_run_folder(out);
  EXPECT_FALSE(c.whole);
  ASSERT_EQ(c.problems.size(), 2u);
  EXPECT_NE(c.problems[0].find("bfs.csv: missing"), std::string::npos) << c.problems[0];
  EXPECT_NE(c.problems[1].find("stats.csv: SHA-256"), std::string::npos) << c.problems[1];
  const Result r = axonguide("verify " + out.string(), tmp.path());
  EXPECT_EQ(r.code, 1);
  fs::remove(out / "manifest.json");
  c = verify_run_folder(out);
  EXPECT_FALSE(c.whole);
  EXPECT_NE(c.problems[0].find("no manifest.json"), std::string::npos);
  EXPECT_EQ(axonguide("verify " + tmp.path().string() + "/nowhere", tmp.path()).code, 1);
  for (const char* reader : {"view", "plot", "assay"}) {
    const Result refused = axonguide(fmt::format("{} {}", reader, out.string()), tmp.path());
    EXPECT_EQ(refused.code, 2) << reader;
    EXPECT_NE(refused.err.find("is not a whole run"), std::string::npos) << reader << ": " << refused.err;
  }
  // A listed name may not leave the folder.
  std::ofstream(out / "manifest.json") << R"({"status": "complete", "files": {"../x": {"sha256": "00"}}})";
  c = verify_run_folder(out);
  EXPECT_FALSE(c.whole);
  EXPECT_NE(c.problems[0].find("a name outside the folder"), std::string::npos);
}

}  // namespace
}  // namespace axg

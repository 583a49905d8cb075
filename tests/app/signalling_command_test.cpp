// The signalling growth model at the command line: a stiff step that leaves a species'
// range stops the run with exit 3 naming the axon, the step and the species, on both
// engines alike, and leaves no outputs (docs/methods.md §2.10).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "support.hpp"

namespace axg {
namespace {

using nlohmann::json;

using test::run_command;

TEST(signalling_command, AFailedStiffStepIsExitThreeNamingWhereOnBothEngines) {
  test::TempDir d;
  json s = json::parse(test::read_file(std::filesystem::path(AXG_SOURCE_DIR) / "scenes/assay-bicknell.json"));
  // A 10 h growth step of ~600 um up a 5 %/10 um gradient, one ROS2 step, transport 4 x 10^5
  // times Table 1's, and no halving of a failed sub-step: the step leaves a species' range.
  s["steps"] = 4;
  s["dt"] = 10;
  s["neurons"]["count"] = 20;
  s["cues"]["imposed"]["steepness"] = 5;
  s["axons"]["signalling"].update(json{{"kr", "1e3 /min"}, {"ka", "1e3 /min"}, {"r0", "1 um/min"}, {"halvings", 0}});
  const auto scene = d.path() / "scene.json";
  std::ofstream(scene) << s.dump();
  std::string first;
  for (const char* backend : {"reference", "emulated"}) {
    const auto out = d.path() / backend;
    const auto [rc, text] = run_command(fmt::format("run {} --out {} -q --backend {}", scene.string(), out.string(), backend));
    EXPECT_EQ(rc, 3) << backend << ": " << text;
    EXPECT_NE(text.find("the stiff step of axon 1 failed at step 2"), std::string::npos) << text;
    EXPECT_NE(text.find("species F"), std::string::npos) << text;
    EXPECT_NE(text.find("ROS2 steps of 10 h per growth step, each halved up to 0 times"), std::string::npos) << text;
    EXPECT_FALSE(std::filesystem::exists(out / "neurons.csv")) << backend;
    if (first.empty()) first = text;
    else EXPECT_EQ(text, first);  // the same failure, the same words
  }
  // Eight sub-steps integrate it; so does the default halving of the failed sub-step, on
  // both engines and any thread count alike.
  s["axons"]["signalling"]["substeps"] = 8;
  std::ofstream(scene) << s.dump();
  const auto [rc, text] = run_command(fmt::format("run {} --out {}/ok -q", scene.string(), d.path().string()));
  EXPECT_EQ(rc, 0) << text;
  s["axons"]["signalling"]["substeps"] = 1;
  s["axons"]["signalling"].erase("halvings");
  std::ofstream(scene) << s.dump();
  for (const char* backend : {"reference", "emulated"}) {
    const auto [hrc, htext] = run_command(
        fmt::format("run {} --out {}/halved-{} -q --backend {}", scene.string(), d.path().string(), backend, backend));
    EXPECT_EQ(hrc, 0) << backend << ": " << htext;
  }
  // And on one thread as on two.
  const auto [trc, ttext] = run_command(
      fmt::format("run {} --out {}/halved-1-thread -q --threads 1", scene.string(), d.path().string()));
  EXPECT_EQ(trc, 0) << ttext;
  for (const char* file : {"neurons.csv", "connections.csv", "stats.csv"}) {
    const std::string ref = test::read_file(d.path() / "halved-reference" / file);
    EXPECT_FALSE(ref.empty()) << file;
    EXPECT_EQ(ref, test::read_file(d.path() / "halved-emulated" / file)) << file;
    EXPECT_EQ(ref, test::read_file(d.path() / "halved-1-thread" / file)) << file;
  }
}

}  // namespace
}  // namespace axg

// The bundled paper scenes are the scenes the benchmarks construct (no drift).
#include <gtest/gtest.h>

#include "axonguide/scene.hpp"
#include "bench.hpp"
#include "support.hpp"

namespace axg {
namespace {

std::string scene_path(const std::string& name) { return test::source_dir() + "/scenes/" + name + ".json"; }

TEST(scenes, PaperDirectScenesMatchTheBenchmarks) {
  for (std::uint64_t n : {100, 500, 1000, 2500, 5000})
    EXPECT_EQ(scene_to_json(load_scene_file(scene_path("paper-direct-" + std::to_string(n))).scene),
              scene_to_json(bench::paper_direct_scene(n)))
        << n;
}

TEST(scenes, PaperCueScenesMatchTheBenchmarks) {
  for (std::uint64_t n : {100, 500, 1000})
    EXPECT_EQ(scene_to_json(load_scene_file(scene_path("paper-cue-" + std::to_string(n))).scene),
              scene_to_json(bench::paper_cue_scene(n)))
        << n;
}

TEST(scenes, EveryBundledSceneParses) {
  for (const auto& e : std::filesystem::directory_iterator(test::source_dir() + "/scenes"))
    EXPECT_NO_THROW(load_scene_file(e.path().string())) << e.path();
}

}  // namespace
}  // namespace axg

// The bundled paper scenes are the scenes the benchmarks construct (no drift).
#include <gtest/gtest.h>

#include "axonguide/scene/scene.hpp"
#include "bench.hpp"
#include "axonguide/study/sweep.hpp"
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

TEST(scenes, EveryBundledSceneAndSweepParses) {
  std::size_t sweeps = 0;
  for (const auto& e : std::filesystem::directory_iterator(test::source_dir() + "/scenes")) {
    if (test::is_sweep_file(e.path())) {
      EXPECT_NO_THROW(sweep::load_spec(e.path().string())) << e.path();
      ++sweeps;
    } else {
      EXPECT_NO_THROW(load_scene_file(e.path().string())) << e.path();
    }
  }
  EXPECT_EQ(sweeps, 4u);
}

TEST(scenes, DefaultJsonIsTheBuiltInScene) {
  EXPECT_EQ(scene_to_json(load_scene_file(scene_path("default")).scene), scene_to_json(Scene::builtin_default()));
}

// The assay sweep meets the shape: 40 points x 10 seeds of 1000-neuron explants over
// 100 steps, concentration 10^-3 to 10^2 x K_d, steepness 0.1 to 0.3 % per 10 um.
TEST(scenes, AssayExplantSweepCoversTheAssayRange) {
  const sweep::Spec s = sweep::load_spec(test::source_dir() + "/scenes/assay-explant.sweep.json");
  EXPECT_EQ(sweep::point_count(s), 40u);
  EXPECT_EQ(s.seeds.size(), 10u);
  const Scene base = parse_scene(s.base.dump(), "base").scene;
  EXPECT_EQ(base.neurons.count, 1000u);
  EXPECT_EQ(base.steps, 100u);
  const double kd = base.cues.sources.at(0).kd;
  EXPECT_EQ(s.parameters[1].values.front().get<double>(), 1e-3 * kd);
  EXPECT_EQ(s.parameters[1].values.back().get<double>(), 1e2 * kd);
  EXPECT_EQ(s.parameters[0].values.front().get<double>(), 0.1);
  EXPECT_EQ(s.parameters[0].values.back().get<double>(), 0.3);
  EXPECT_EQ(base.cues.imposed.reference_length, 10.0);
  EXPECT_EQ(base.units.length, "um");
  EXPECT_EQ(base.units.concentration, "nM");
}

}  // namespace
}  // namespace axg

// The determinism contract: every output except timings is identical, byte for byte,
// for any thread count.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include "support.hpp"

namespace axg {
namespace {

RC_GTEST_PROP(determinism, ThreadCountNeverChangesAByte, ()) {
  const Scene scene = *test::gen_direct_scene();
  std::map<std::string, std::string> one;
  try {
    one = test::run_hashes(scene, 1);
  } catch (const RunError&) {
    RC_DISCARD("placement too dense for this random scene");
  }
  RC_ASSERT(test::run_hashes(scene, 2) == one);
  RC_ASSERT(test::run_hashes(scene, 7) == one);
}

TEST(determinism, DefaultSceneOnOneTwoAndSevenThreads) {
  const Scene scene = Scene::builtin_default();
  const auto one = test::run_hashes(scene, 1);
  EXPECT_EQ(test::run_hashes(scene, 2), one);
  EXPECT_EQ(test::run_hashes(scene, 7), one);
  EXPECT_TRUE(one.count("neurons.csv") && one.count("connections.csv") && one.count("graph.graphml"));
}

TEST(determinism, LargeEnoughToSplitAcrossThreads) {
  // 20000 neurons: many TBB chunks, parallel BFS frontier, several radix sort chunks.
  Scene scene = Scene::builtin_default();
  scene.neurons.count = 20000;
  scene.neurons.radius = 2.5 * std::cbrt(200.0);
  scene.analysis.bfs_sources = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9};
  const auto one = test::run_hashes(scene, 1);
  EXPECT_EQ(test::run_hashes(scene, 2), one);
  EXPECT_EQ(test::run_hashes(scene, 7), one);
}

TEST(determinism, SeedChangesTheNetwork) {
  Scene a = Scene::builtin_default();
  Scene b = a;
  b.seed = 2;
  EXPECT_NE(test::run_hashes(a, 2).at("neurons.csv"), test::run_hashes(b, 2).at("neurons.csv"));
}

}  // namespace
}  // namespace axg

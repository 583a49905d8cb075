// A pinned regression: the SHA-256 of every output of one small scene. Any change to
// placement, the samplers, the portable math, growth, contact, the graph or the output
// format changes a hash. If the change is intended, update the hashes here in the same
// commit and say why in its message (the golden networks of data/golden/ do the same
// with a changelog).
#include <gtest/gtest.h>

#include "support.hpp"

namespace axg {
namespace {

Scene pinned_scene() {
  Scene s;
  s.seed = 20141405;  // the report's date
  s.steps = 60;
  s.neurons.count = 400;
  s.neurons.radius = 4.0;
  s.neurons.sampler = Sampler::kTrig;
  s.guidance.model = GuidanceModel::kDirect;
  s.analysis.bfs_sources = {0, 7};
  s.output.paths = true;
  return s;
}

TEST(regression, PinnedSceneHashes) {
  const auto h = test::run_hashes(pinned_scene(), 2);
  // Printed so that an intended change can be pinned by copying these lines.
  for (const auto& [name, hash] : h) std::printf("      {\"%s\", \"%s\"},\n", name.c_str(), hash.c_str());
  const std::map<std::string, std::string> expected{
    {"bfs.csv", "e60bc41c3f81aae41a435e94326f4fca3260a150d7f57c10ef257add903dea51"},
    {"connections.csv", "c325556b8a3d33b4bcbbbd779b7a180317e2fc74bc2d8623d0ec7850a47abf85"},
    {"graph.graphml", "f9f2729976b74434a6e6e4cdebc63a8a81c6ff375ba987322df91bec749685a9"},
    {"neurons.csv", "1c9176a9d7d913f95298fa6d1c4d5ab9130322cbe8a024a366d55111470e31f3"},
    {"paths.csv", "50f1a6d7117ea0663c5eea70808739ce6ea629777a1f4d9082d9dd5f09bcc300"},
    {"stats.csv", "e069e759166f1577ac3aca9c44e5c272cb2b30c86e39638dd3fb98ccfabf236a"},
  };
  EXPECT_EQ(h, expected);
}

}  // namespace
}  // namespace axg

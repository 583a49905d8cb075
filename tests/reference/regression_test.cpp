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
    {"bfs.csv", "646976c0ecc287f7f7de0e4f098bbe6b6cd6d777af4a7a19ab3a0eac54a9580f"},
    {"connections.csv", "6a0665fabb14479ad7dc158f5033eb20ac2e2496bfc9d7af0bb850a513ae8f4e"},
    {"graph.graphml", "e1083cc7ffaf31d5f1df8d9e4e19c5e6bad1e0564864e1a0290136c33d3beb21"},
    {"neurons.csv", "f426596da840900645a88ee1d1072ef3ea517a88c0533e4242a85e3103bd216d"},
    {"paths.csv", "a1af64c07218495d1fac30700daec5e90e75865777516a7f20fde0a6eeeb20b7"},
    {"stats.csv", "e045cc27ab43097ce8c027e72ce26a7e2b5d55580ddd7010cf6fa322d9378e33"},
  };
  EXPECT_EQ(h, expected);
}

}  // namespace
}  // namespace axg

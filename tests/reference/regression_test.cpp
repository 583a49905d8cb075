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
    {"bfs.csv", "a60a6a7d7f971e1098d4a88254af21753e21251eed38ecb31f599c114148a65d"},
    {"connections.csv", "b846390ab7063364e8618a9b91c42aecfe6f91bd059e7290483b6bed0bd1625a"},
    {"graph.graphml", "a63df5751b761ce009b579f690fc224fc5a6297fd61361a689538596b21a5c15"},
    {"neurons.csv", "4c2293818316bad8881c370a56db4a0ccea9ba6abbffa89e09ca32e21e211c64"},
    {"paths.csv", "05b2abf8bc24a7843e22ee8de248ad20d5f97ce1b89ce0cfd8130c6f89cdd992"},
    {"stats.csv", "d2dcc21500b14718cf48e35c25f6ab3cd539c76dec1e681b47a8180e94f1065b"},
  };
  EXPECT_EQ(h, expected);
}

}  // namespace
}  // namespace axg

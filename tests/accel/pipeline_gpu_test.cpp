// The accelerator on the GPU against the reference, byte for byte (label gpu). Without a
// GPU (or without the CUDA build) every test reports SKIPPED with the reason.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include "accel/backend_cases.hpp"
#include "axonguide/accel/engines.hpp"

namespace axg {
namespace {

const EngineFactory kCuda = [](const Scene& s, const Placement& p) { return accel::make_cuda_engine(s, p); };

#define SKIP_WITHOUT_GPU()                                     \
  do {                                                         \
    static const std::string reason = accel::cuda_unavailable_reason();            \
    if (!reason.empty()) GTEST_SKIP() << "no GPU: " << reason; \
  } while (0)

class GpuScene : public ::testing::TestWithParam<test::NamedScene> {};

TEST_P(GpuScene, EqualsTheReferenceByteForByte) {
  SKIP_WITHOUT_GPU();
  test::expect_same_as_reference(GetParam().scene, kCuda, GetParam().name);
}

INSTANTIATE_TEST_SUITE_P(gpu, GpuScene, ::testing::ValuesIn(test::backend_scenes(false)), test::SceneName{});

TEST(gpu, RandomScenesEqualTheReference) {
  SKIP_WITHOUT_GPU();
  const bool ok = rc::check("random scenes: cuda == reference", [] {
    const Scene s = *test::gen_cue_scene();
    std::map<std::string, std::string> reference;
    try {
      reference = test::run_hashes(s, 2);
    } catch (const RunError&) {
      RC_DISCARD("placement too dense");
    }
    RC_ASSERT(test::run_hashes(s, 2, kCuda) == reference);
  });
  EXPECT_TRUE(ok);
}

TEST(gpu, GraphKernelsEqualTheReference) {
  SKIP_WITHOUT_GPU();
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const std::size_t n = 1000 * seed;
    const Csr g = random_digraph(n, 3 * n, seed, core::Stream::kValidation, 8);
    const BfsResult ref = bfs(g, transpose(g), {0, 1});
    for (const BfsResult& r : {accel::bfs_level_sync(g, {0, 1}, true), accel::bfs_queue(g, {0, 1}, true)}) {
      EXPECT_EQ(r.level, ref.level) << seed;
      EXPECT_EQ(r.parent, ref.parent) << seed;
    }
    EXPECT_EQ(accel::components(g, true), components(undirected(g))) << seed;
  }
}

}  // namespace
}  // namespace axg

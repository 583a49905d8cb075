// The accelerator's pipeline, emulated on the CPU (Thrust's sequential host system runs
// the same kernel functors the GPU runs), against the reference, byte for byte.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <filesystem>

#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/breadth_first_search.hpp>

#include "accel/backend_cases.hpp"
#include "axonguide/accel/engines.hpp"
#include "axonguide/engine/engine.hpp"
#include "axonguide/morphology/arbour.hpp"
#include "axonguide/placement/placement.hpp"

namespace axg {
namespace {

const EngineFactory kEmulated = [](const Scene& s, const Placement& p) { return accel::make_emulated_engine(s, p); };

class EmulatedScene : public ::testing::TestWithParam<test::NamedScene> {};

TEST_P(EmulatedScene, EqualsTheReferenceByteForByte) {
  test::expect_same_as_reference(GetParam().scene, kEmulated, GetParam().name);
}

INSTANTIATE_TEST_SUITE_P(accel, EmulatedScene, ::testing::ValuesIn(test::backend_scenes(true)), test::SceneName{});

// A random scene's outputs on the emulated accelerator equal the reference's.
void check_random_scene(const Scene& s) {
  std::map<std::string, std::string> reference;
  try {
    reference = test::run_hashes(s, 2);
  } catch (const RunError&) {
    RC_DISCARD("placement too dense");
  }
  RC_ASSERT(test::run_hashes(s, 2, kEmulated) == reference);
}

RC_GTEST_PROP(accel, RandomScenesEqualTheReference, ()) { check_random_scene(*test::gen_cue_scene()); }

RC_GTEST_PROP(accel, RandomArbourScenesEqualTheReference, ()) { check_random_scene(*test::gen_arbour_scene()); }

// A checkpoint of arbours moves between the engines: saved by one after k steps, loaded by
// the other, the run goes on to the reference's arbours, point for point.
TEST(accel, ArbourCheckpointsMoveBetweenTheEngines) {
  // Cue-steered arbours with lateral branches, decisions over 3 steps (their sums carried).
  const std::filesystem::path file =
      std::filesystem::path(test::source_dir()) / "data" / "golden" / "arbours-synapses-steered-ball" / "scene.json";
  Scene s = load_scene_file(file.string()).scene;
  s.guidance.integration_time = 3.0 * s.dt;
  const Placement p = place_neurons(s);
  auto run = [&](std::unique_ptr<Engine> first, std::unique_ptr<Engine> second) {
    first->warm_up();
    PhaseTimes t;
    for (std::uint32_t step = 1; step <= 25; ++step) first->step(step, t);
    EngineState state;
    first->save(state);
    second->load(state);
    for (std::uint32_t step = 26; step <= s.steps; ++step) second->step(step, t);
    std::vector<morphology::Arbour> a;
    second->arbours(a);
    std::vector<std::vector<morphology::ArbourSample>> out;
    for (const auto& x : a) out.push_back(morphology::arbour_samples(x));
    return out;
  };
  const auto reference = run(make_reference_engine(s, Placement(p)), make_reference_engine(s, Placement(p)));
  const auto to_ref = run(accel::make_emulated_engine(s, p), make_reference_engine(s, Placement(p)));
  const auto from_ref = run(make_reference_engine(s, Placement(p)), accel::make_emulated_engine(s, p));
  ASSERT_EQ(reference.size(), to_ref.size());
  std::size_t samples = 0;
  for (std::size_t i = 0; i < reference.size(); ++i) {
    samples += reference[i].size();
    ASSERT_EQ(reference[i].size(), to_ref[i].size()) << i;
    ASSERT_EQ(reference[i].size(), from_ref[i].size()) << i;
    for (std::size_t k = 0; k < reference[i].size(); ++k) {
      for (const auto* other : {&to_ref[i][k], &from_ref[i][k]}) {
        EXPECT_EQ(core::bits_of(reference[i][k].pos.x), core::bits_of(other->pos.x));
        EXPECT_EQ(core::bits_of(reference[i][k].pos.y), core::bits_of(other->pos.y));
        EXPECT_EQ(core::bits_of(reference[i][k].pos.z), core::bits_of(other->pos.z));
        EXPECT_EQ(reference[i][k].parent, other->parent);
        EXPECT_EQ(reference[i][k].cone, other->cone);
        EXPECT_EQ(reference[i][k].step, other->step);
      }
    }
  }
  EXPECT_GT(samples, 40u * 20u);  // the arbours grew
}

RC_GTEST_PROP(accel, GraphKernelsEqualTheReference, ()) {
  const std::size_t n = *rc::gen::inRange<std::size_t>(1, 400);
  const std::size_t m = *rc::gen::inRange<std::size_t>(0, 4 * n);
  const Csr g = random_digraph(n, m, *rc::gen::arbitrary<std::uint64_t>(), core::Stream::kValidation, 7);
  std::vector<std::uint32_t> sources{*rc::gen::inRange<std::uint32_t>(0, static_cast<std::uint32_t>(n))};
  if (*rc::gen::arbitrary<bool>()) sources.push_back(static_cast<std::uint32_t>(n - 1));
  const BfsResult ref = bfs(g, transpose(g), sources);
  for (const BfsResult& r : {accel::bfs_level_sync(g, sources, false), accel::bfs_queue(g, sources, false)}) {
    RC_ASSERT(r.level == ref.level);
    RC_ASSERT(r.parent == ref.parent);
    RC_ASSERT(r.max_level == ref.max_level);
    RC_ASSERT(r.reached == ref.reached);
  }
  RC_ASSERT(accel::components(g, false) == components(undirected(g)));
}

TEST(accel, TheEmulatedEngineRunsItsOwnGraphKernels) {
  Scene s = Scene::builtin_default();
  s.neurons.count = 300;
  const Placement p = place_neurons(s);
  auto engine = accel::make_emulated_engine(s, p);
  engine->warm_up();
  PhaseTimes t;
  for (std::uint32_t step = 1; step <= 20; ++step) engine->step(step, t);
  NeuronState state;
  engine->finish(state);
  GraphAnalysis a;
  ASSERT_TRUE(engine->analyze(s, a));  // the reference engine returns false
  const GraphAnalysis host = analyze_graph(s, state);
  EXPECT_EQ(a.out.offsets, host.out.offsets);
  EXPECT_EQ(a.out.targets, host.out.targets);
  EXPECT_EQ(a.bfs->level, host.bfs->level);
  EXPECT_EQ(a.bfs->parent, host.bfs->parent);
  EXPECT_EQ(a.component, host.component);
}

TEST(accel, CudaBackendIsReportedHonestly) {
  if (accel::cuda_built()) {
    EXPECT_FALSE(accel::cuda_device_description().empty());
  } else {
    EXPECT_NE(accel::cuda_device_description().find("not built"), std::string::npos);
    EXPECT_THROW(accel::make_cuda_engine(Scene{}, Placement{}), InputError);
  }
}

}  // namespace
}  // namespace axg

// One network decomposed over ranks (docs/scaling.md §2), with the ranks as threads of
// this process (run_local_group): the same collectives as MPI, so these properties hold
// for the MPI transport too, which tests/distributed/check_mpi_run.sh compares end to end.
//  - the decomposed placement is place_neurons' placement, bit for bit, for any rank count
//    and id block, the failing neuron included; each rank keeps exactly its block's somas
//    and those within its halo;
//  - a decomposed run writes the one-process files, byte for byte, for any rank count,
//    with direct guidance, the analytic and imposed fields, and the particle and grid
//    fields (migration, halos, ghost planes, the pipelined z sweep), growth-rate
//    modulation, both contact rules and paths;
//  - a checkpoint taken by K ranks resumes on K' ranks (or one process) to the same bytes;
//  - decompositions that cannot proceed are refused with the message of the issue.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <ifaddrs.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <rapidcheck/gtest.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cstdio>
#include <optional>
#include <string>

#include "axonguide/engine/checkpoint.hpp"
#include "axonguide/model/cues.hpp"
#include "axonguide/model/particles.hpp"
#include "axonguide/core/random.hpp"
#include "axonguide/distributed/decomposed_run.hpp"
#include "axonguide/distributed/launch.hpp"
#include "axonguide/distributed/local_group.hpp"
#include "axonguide/distributed/placement.hpp"
#include "axonguide/scene/json_input.hpp"
#include "axonguide/placement/placement.hpp"
#include "support.hpp"

namespace axg {
namespace {

using core::bits_of;
using core::Vec3;
using distributed::Comm;
using distributed::DecomposedRun;

bool same_bits(Vec3 a, Vec3 b) {
  return bits_of(a.x) == bits_of(b.x) && bits_of(a.y) == bits_of(b.y) && bits_of(a.z) == bits_of(b.z);
}

Scene golden_scene(const std::string& name) {
  return load_scene_file(test::source_dir() + "/data/golden/" + name + "/scene.json").scene;
}

// Runs the scene over `ranks` in-process ranks and writes rank 0's result into dir.
// `resume`: continue from this checkpoint. Returns the run facts.
nlohmann::json run_decomposed(const Scene& scene, int ranks, const test::fs::path& dir,
                              const RunCheckpoint* resume = nullptr,
                              std::optional<RunCheckpoint>* checkpoint_at = nullptr, std::uint32_t at_step = 0) {
  nlohmann::json facts;
  distributed::run_local_group(ranks, 1, [&](Comm& comm) {
    DecomposedRun run(scene, comm);
    RunOptions options;
    run.attach(options);
    std::optional<RunCheckpoint> mine;
    if (resume) mine = *resume;  // each rank reads its own copy of the file
    options.resume = mine ? &*mine : nullptr;
    if (checkpoint_at)
      options.on_checkpoint = [&](const RunResult& r, std::uint32_t step, const EngineState& e) {
        if (!comm.root() || step != at_step) return;
        RunCheckpoint c;
        c.step = step;
        c.scene_hash = scene_hash(scene);
        c.progress = r;
        c.engine = e;
        *checkpoint_at = std::move(c);
      };
    RunResult r = run_scene(scene, options);
    const nlohmann::json f = run.facts();
    if (comm.root()) {
      write_outputs(r, dir, "test", 1, {});
      facts = f;
    }
  });
  return facts;
}

std::map<std::string, std::string> one_process(const Scene& scene) { return test::run_hashes(scene, 2); }

// --- placement -------------------------------------------------------------------------

RC_GTEST_PROP(decomposed, PlacementIsTheOneProcessPlacement, ()) {
  Scene s = *test::gen_placement_scene(5000);
  s.guidance.model = GuidanceModel::kDirect;
  s.neurons.soma_radius = std::min(s.neurons.soma_radius, 1.5);  // a halo that 8 blocks can hold
  s.neurons.overlap_reject = *rc::gen::element(true, true, true, false);
  const int ranks = *rc::gen::inRange(1, 9);
  const std::size_t id_block = *rc::gen::element<std::size_t>(0, s.neurons.count / 3 + 1, 97, 4096);
  RC_TAG(ranks);

  std::optional<Placement> expected;
  std::string expected_error;
  try {
    expected = place_neurons(s);
  } catch (const RunError& e) {
    expected_error = e.what();
  }
  // A rank count whose blocks are narrower than the halo (7 ranks cut a domain 7 x 1 x 1) is
  // refused before placement, with a message that says so: the refusal is the behaviour.
  std::optional<distributed::Decomposition> decomposition;
  try {
    decomposition = distributed::decompose(s, ranks);
  } catch (const InputError& e) {
    RC_ASSERT(std::string(e.what()).find("narrower than the halo") != std::string::npos);
    RC_SUCCEED("too many ranks for this scene: refused");
  }
  const distributed::Decomposition& d = *decomposition;
  std::vector<distributed::RankSomas> kept(static_cast<std::size_t>(ranks));
  std::vector<Vec3> all;
  std::uint64_t redraws = 0;
  std::string error;
  try {
    distributed::run_local_group(ranks, 1, [&](Comm& comm) {
      distributed::DecomposedPlacement p = distributed::place_decomposed(s, d, comm, id_block);
      kept[static_cast<std::size_t>(comm.rank())] = std::move(p.somas);
      if (comm.root()) all = std::move(p.all), redraws = p.redraws;
    });
  } catch (const distributed::OnEveryRank& e) {  // thrown by every rank alike
    error = e.what();
  }
  RC_ASSERT(error == expected_error);
  if (!expected) return;
  RC_ASSERT(redraws == expected->redraws);
  RC_ASSERT(all.size() == expected->soma.size());
  for (std::size_t i = 0; i < all.size(); ++i) RC_ASSERT(same_bits(all[i], expected->soma[i]));
  for (int r = 0; r < ranks; ++r) {
    const distributed::RankSomas& k = kept[static_cast<std::size_t>(r)];
    std::size_t j = 0;
    for (std::size_t i = 0; i < all.size(); ++i) {
      if (!d.near(r, all[i], d.halo)) continue;
      RC_ASSERT(j < k.id.size());
      RC_ASSERT(k.id[j] == i);
      RC_ASSERT(same_bits(k.pos[j], all[i]));
      RC_ASSERT(k.owned[j] == (d.owner(all[i]) == r));
      ++j;
    }
    RC_ASSERT(j == k.id.size());
  }
}

// --- runs --------------------------------------------------------------------------------

// Direct guidance, and the analytic and imposed fields of the golden scenes, with random
// seeds, rank counts, step lengths, modulation and paths.
rc::Gen<Scene> gen_decomposable_scene() {
  return rc::gen::exec([] {
    Scene s = *test::gen_direct_scene();
    const int kind = *rc::gen::inRange(0, 4);
    if (kind > 0) {
      const char* names[] = {"", "analytic-snr", "analytic-vector-sum-box", "imposed-explant-units"};
      Scene g = golden_scene(names[kind]);
      g.seed = s.seed;
      g.steps = *rc::gen::inRange<std::uint32_t>(1, 40);
      g.neurons.count = *rc::gen::inRange<std::uint64_t>(1, 600);
      g.output.paths = s.output.paths;
      if (*rc::gen::arbitrary<bool>()) g.axons.growth_modulation = *rc::gen::inRange(1, 9) / 10.0;
      // Decisions over 1 to 4 steps, whole or not (the sums travel with migrating axons).
      if (*rc::gen::arbitrary<bool>()) g.guidance.integration_time = g.dt * *rc::gen::inRange(2, 9) / 2.0;
      s = g;
    }
    s.output.graphml = true;
    return s;
  });
}

RC_GTEST_PROP(decomposed, RunWritesTheOneProcessBytes, ()) {
  const Scene s = *gen_decomposable_scene();
  const int ranks = *rc::gen::inRange(1, 9);
  RC_TAG(ranks, name_of(s.guidance.model));
  try {
    distributed::decompose(s, ranks);
  } catch (const InputError& e) {
    RC_ASSERT(std::string(e.what()).find("narrower than the halo") != std::string::npos);
    RC_SUCCEED("too many ranks for this scene: refused");
  }
  // A dense random scene may not place: then the same error, on every rank.
  std::optional<std::map<std::string, std::string>> expected;
  std::string expected_error, error;
  try {
    expected = one_process(s);
  } catch (const RunError& e) {
    expected_error = e.what();
  }
  test::TempDir dir;
  nlohmann::json facts;
  try {
    facts = run_decomposed(s, ranks, dir.path());
  } catch (const distributed::OnEveryRank& e) {
    error = e.what();
  } catch (const RunError& e) {  // refused before placement (check_scene_runs: packing), the same on every rank
    error = e.what();
  }
  RC_ASSERT(error == expected_error);
  if (!expected) return;
  RC_ASSERT(test::output_hashes(dir.path()) == *expected);
  RC_ASSERT(facts["ranks"] == ranks);
  RC_ASSERT(facts["somas_per_rank"]["max"].get<std::uint64_t>() <= s.neurons.count);
}

// The particle and grid fields of the golden scenes over ranks, with random seeds, sizes,
// steps, rank counts and variants (motion, collisions, gathers; explicit or implicit,
// absorbing or reflecting): every output file, particle frames in the paths included, is
// the one-process file.
rc::Gen<Scene> gen_cue_field_scene() {
  return rc::gen::exec([] {
    const char* names[] = {"particles-brownian-snr", "particles-ballistic-collisions-vector-sum",
                           "particles-count-modulation", "particles-source-vector-sum",
                           "grid-explicit-reflecting-vector-sum", "grid-implicit-absorbing-snr"};
    Scene s = golden_scene(*rc::gen::elementOf(std::vector<std::string>(std::begin(names), std::end(names))));
    s.seed = *rc::gen::inRange<std::uint64_t>(0, 1u << 30);
    s.steps = *rc::gen::inRange<std::uint32_t>(1, 25);
    s.neurons.count = *rc::gen::inRange<std::uint64_t>(1, 300);
    s.output.paths = *rc::gen::arbitrary<bool>();
    s.cues.warmup_steps = *rc::gen::inRange<std::uint32_t>(0, 4);
    if (s.cues.field == FieldKind::kParticles) {
      if (*rc::gen::arbitrary<bool>()) s.cues.particles.collisions = !s.cues.particles.collisions;
      if (*rc::gen::arbitrary<bool>())
        s.cues.particles.motion = s.cues.particles.motion == Motion::kBrownian ? Motion::kBallistic : Motion::kBrownian;
      s.cues.particles.radius = *rc::gen::inRange(1, 30) / 100.0;
    } else {
      if (*rc::gen::arbitrary<bool>())
        s.cues.grid.scheme = s.cues.grid.scheme == GridScheme::kExplicit ? GridScheme::kImplicit : GridScheme::kExplicit;
      if (*rc::gen::arbitrary<bool>())
        s.cues.grid.boundary =
            s.cues.grid.boundary == GridBoundary::kAbsorbing ? GridBoundary::kReflecting : GridBoundary::kAbsorbing;
      s.cues.grid.spacing = *rc::gen::element(0.2, 0.3, 0.45);
      if (s.cues.grid.scheme == GridScheme::kImplicit) s.cues.grid.substeps = *rc::gen::inRange<std::uint32_t>(1, 3);
    }
    if (*rc::gen::arbitrary<bool>()) s.guidance.integration_time = s.dt * *rc::gen::inRange(2, 9) / 2.0;
    return s;
  });
}

RC_GTEST_PROP(decomposed, CueFieldRunsWriteTheOneProcessBytes, ()) {
  const Scene s = *gen_cue_field_scene();
  const int ranks = *rc::gen::element(1, 2, 3, 4, 5, 6, 7, 8);
  RC_TAG(ranks, name_of(s.cues.field));
  try {
    distributed::decompose(s, ranks);
  } catch (const InputError& e) {
    RC_ASSERT(std::string(e.what()).find("narrower than the halo") != std::string::npos);
    RC_SUCCEED("too many ranks for this scene: refused");
  }
  const auto expected = one_process(s);
  test::TempDir dir;
  const nlohmann::json facts = run_decomposed(s, ranks, dir.path());
  RC_ASSERT(test::output_hashes(dir.path()) == expected);
  RC_ASSERT(facts["ranks"] == ranks);
}

// Fixed cases of the same, at 1, 2, 4 and 8 ranks, with the exchanges seen to happen:
// particles migrating and in halos, grid ghost planes and the pipelined z sweep.
TEST(decomposed, ParticleAndGridScenesOnOneTwoFourAndEightRanks) {
  for (const char* name : {"particles-source-vector-sum", "particles-ballistic-collisions-vector-sum",
                           "particles-brownian-snr", "grid-implicit-absorbing-snr",
                           "grid-explicit-reflecting-vector-sum"}) {
    Scene s = golden_scene(name);
    s.steps = 20;
    s.neurons.count = 200;
    const auto expected = one_process(s);
    // A grid is cut in slabs at least as thick as their ghost planes (the sensing ball and
    // half a step: 5 planes of 0.2 LU here), so its cube of 7.4 LU takes at most 7 ranks.
    const int most = s.cues.field == FieldKind::kGrid ? 6 : 8;
    for (int ranks : {1, 2, 4, most}) {
      test::TempDir dir;
      const nlohmann::json facts = run_decomposed(s, ranks, dir.path());
      EXPECT_EQ(test::output_hashes(dir.path()), expected) << name << ", " << ranks << " ranks";
      if (ranks == 1) continue;
      const nlohmann::json& f = facts["per_step"];
      if (s.cues.field == FieldKind::kParticles) {
        EXPECT_GT(f["migrated_particles"].get<double>(), 0.0) << name << facts.dump();
        if (particle_grid_used(s)) {
          EXPECT_GT(f["halo_particles"].get<double>(), 0.0) << name << facts.dump();
        }
      } else {
        EXPECT_GT(f["ghost_values"].get<double>(), 0.0) << name << facts.dump();
        if (s.cues.grid.scheme == GridScheme::kImplicit) {
          EXPECT_EQ(f["pipeline_stages"].get<double>(),  // forward and back, per cue
                    2.0 * (4 * ranks + ranks - 1) * static_cast<double>(make_cues(s).size()))
              << name << facts.dump();
        }
      }
    }
  }
}

// Brownian jumps longer than a block (a diffusion coefficient that moves a particle about a
// block's edge a step), over 3 and 6 ranks, whose outer blocks are not adjacent: the
// particles that jump past the neighbours, or land near a rank that is not the sender's
// neighbour, go by the all-gather, and each rank takes them as its own or into its halo.
// Every file is the one-process file, with gathers and with collisions.
TEST(decomposed, ParticlesJumpingPastTheNeighboursReachOwnerAndHalo) {
  for (const bool collisions : {false, true}) {
    Scene s = golden_scene("particles-source-vector-sum");
    s.steps = 12;
    s.neurons.count = 150;
    s.cues.particles.collisions = collisions;
    for (Source& src : s.cues.sources) src.diffusion = 2.0;
    const auto expected = one_process(s);
    for (int ranks : {3, 6}) {
      test::TempDir dir;
      const nlohmann::json facts = run_decomposed(s, ranks, dir.path());
      EXPECT_EQ(test::output_hashes(dir.path()), expected) << ranks << " ranks, collisions " << collisions;
      const nlohmann::json& f = facts["per_step"];
      EXPECT_GT(f["far_particles"].get<double>(), 0.0) << facts.dump();
      EXPECT_LT(f["far_particles"].get<double>(), f["migrated_particles"].get<double>()) << facts.dump();
      EXPECT_GT(f["halo_particles"].get<double>(), 0.0) << facts.dump();
    }
  }
}

// A bigger run, with a fixed rank count per case: every file, and migration really
// happening (the facts count the axons sent to neighbours).
TEST(decomposed, DefaultSizedDirectRunOnOneTwoFourAndEightRanks) {
  Scene s = load_scene_file(test::source_dir() + "/scenes/paper-direct-5000.json").scene;
  s.output.paths = true;
  const auto expected = one_process(s);
  for (int ranks : {1, 2, 4, 8}) {
    test::TempDir dir;
    const nlohmann::json facts = run_decomposed(s, ranks, dir.path());
    EXPECT_EQ(test::output_hashes(dir.path()), expected) << ranks << " ranks";
    if (ranks > 1) {
      EXPECT_GT(facts["per_step"]["migrated_axons"].get<double>(), 0.0) << facts.dump();
    }
  }
}

// Bounds far beyond the somas: the blocks share the somas (not the empty space), the rank's
// soma grid stays small, and the tips that grow far out belong to the outer blocks.
TEST(decomposed, WideBoundsKeepTheBlocksOnTheSomas) {
  Scene s = golden_scene("direct-rejection-ball-swept");
  s.neurons.count = 300;
  s.neurons.radius = 4.0;
  s.axons.bounds_radius = 1000.0;
  s.steps = 80;
  const auto expected = one_process(s);
  for (int ranks : {2, 4, 8}) {
    test::TempDir dir;
    const nlohmann::json facts = run_decomposed(s, ranks, dir.path());
    EXPECT_EQ(test::output_hashes(dir.path()), expected) << ranks << " ranks";
    EXPECT_LT(facts["block_edge_lu"][0].get<double>(), 10.0) << facts.dump();
    EXPECT_LT(facts["somas_per_rank"]["max"].get<std::uint64_t>(), 300u) << facts.dump();
  }
}

// A rank that calls another collective than the others is an error in the local group (MPI
// would hang), so that the properties above would catch such a path.
TEST(decomposed, LocalGroupCatchesMismatchedCollectives) {
  EXPECT_THROW(distributed::run_local_group(2, 1,
                                            [](Comm& comm) {
                                              if (comm.root()) {
                                                comm.allgather({});
                                              } else {
                                                std::vector<std::uint64_t> v{1};
                                                comm.allreduce(v, distributed::Reduce::kSum);
                                              }
                                            }),
               std::logic_error);
}

TEST(decomposed, CheckpointFromSomeRanksResumesOnOthers) {
  Scene s = golden_scene("analytic-snr");
  s.neurons.count = 800;
  s.neurons.radius = 7.0;
  s.steps = 30;
  s.axons.growth_modulation = 0.5;
  s.guidance.integration_time = 3.0;  // the checkpoint at step 20 falls inside a decision interval
  s.output.paths = true;
  s.output.checkpoint_every = 10;
  const auto expected = one_process(s);
  for (const auto& [from, to] : {std::pair{3, 2}, std::pair{2, 4}, std::pair{4, 1}}) {
    std::optional<RunCheckpoint> c;
    test::TempDir first;
    run_decomposed(s, from, first.path(), nullptr, &c, 20);
    ASSERT_TRUE(c.has_value());
    EXPECT_EQ(c->step, 20u);
    test::TempDir dir;
    run_decomposed(s, to, dir.path(), &*c);
    EXPECT_EQ(test::output_hashes(dir.path()), expected) << from << " ranks, resumed on " << to;
    // One process resumes the same checkpoint.
    RunOptions options;
    RunCheckpoint copy = *c;
    options.resume = &copy;
    test::TempDir single;
    write_outputs(with_threads(2, [&] { return run_scene(s, options); }), single.path(), "test", 2, {});
    EXPECT_EQ(test::output_hashes(single.path()), expected);
  }
}

// The particle (ballistic, with collisions: velocities and the estimate in the checkpoint)
// and grid state taken by K ranks resumes on K' ranks and in one process to the same bytes.
TEST(decomposed, CueFieldCheckpointsResumeOnOtherRankCounts) {
  for (const char* name : {"particles-ballistic-collisions-vector-sum", "particles-source-vector-sum",
                           "grid-implicit-absorbing-snr", "grid-explicit-reflecting-vector-sum"}) {
    Scene s = golden_scene(name);
    s.steps = 24;
    s.neurons.count = 150;
    s.output.checkpoint_every = 8;
    const auto expected = one_process(s);
    for (const auto& [from, to] : {std::pair{3, 2}, std::pair{2, 4}}) {
      std::optional<RunCheckpoint> c;
      test::TempDir first;
      run_decomposed(s, from, first.path(), nullptr, &c, 16);
      ASSERT_TRUE(c.has_value()) << name;
      if (s.cues.field == FieldKind::kParticles) {
        EXPECT_FALSE(c->engine.particle_id.empty()) << name;
        EXPECT_TRUE(std::is_sorted(c->engine.particle_id.begin(), c->engine.particle_id.end())) << name;
      } else {
        EXPECT_FALSE(c->engine.grid.empty()) << name;
      }
      test::TempDir dir;
      run_decomposed(s, to, dir.path(), &*c);
      EXPECT_EQ(test::output_hashes(dir.path()), expected) << name << ": " << from << " ranks, resumed on " << to;
      RunOptions options;
      RunCheckpoint copy = *c;
      options.resume = &copy;
      test::TempDir single;
      write_outputs(with_threads(2, [&] { return run_scene(s, options); }), single.path(), "test", 2, {});
      EXPECT_EQ(test::output_hashes(single.path()), expected) << name << ": resumed in one process";
    }
  }
}

TEST(decomposed, PlacementTooDenseFailsOnEveryRankWithTheOneProcessMessage) {
  Scene s;
  s.guidance.model = GuidanceModel::kDirect;
  s.neurons.count = 3000;
  s.neurons.radius = 5.0;
  s.neurons.soma_radius = 0.3;  // packing 0.65: random sequential addition jams before
  s.neurons.max_attempts = 50;
  std::string jam_one, jam_many;
  std::atomic<int> errors{0};
  try {
    place_neurons(s);
  } catch (const RunError& e) {
    jam_one = e.what();
  }
  ASSERT_NE(jam_one.find("still overlaps"), std::string::npos) << jam_one;
  try {
    distributed::run_local_group(4, 1, [&](Comm& comm) {
      DecomposedRun run(s, comm);
      RunOptions options;
      run.attach(options);
      try {
        run_scene(s, options);
      } catch (const distributed::OnEveryRank& e) {
        try {
          std::rethrow_exception(e.error);
        } catch (const RunError& inner) {
          if (comm.root()) jam_many = inner.what();
        }
        ++errors;
      }
    });
  } catch (const std::exception& e) {
    FAIL() << "a rank failed alone: " << e.what();
  }
  EXPECT_EQ(errors.load(), 4);
  EXPECT_EQ(jam_many, jam_one);
}

TEST(decomposed, RefusesWhatItCannotDecompose) {
  Scene s;
  s.guidance.model = GuidanceModel::kDirect;
  s.neurons.radius = 2.0;
  try {
    distributed::decompose(s, 343);
    FAIL() << "343 ranks for a region of radius 2";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("343 ranks: the domain (a cube of edge 4.5 LU) cut 7 x 7 x 7 gives blocks 0.6429 LU wide, "
                     "narrower than the halo of 0.6506 LU"),
              std::string::npos)
        << m;
    EXPECT_NE(m.find("at most 6 blocks along an axis (at most 216 ranks)"), std::string::npos) << m;
  }
  EXPECT_EQ(distributed::decompose(s, 216).blocks, (std::array<int, 3>{6, 6, 6}));
  EXPECT_THROW(distributed::decompose(s, 7), InputError);  // 7 x 1 x 1: 0.64 LU blocks
  // The particle field's gathers set the halo when they reach further than a step's
  // contact search: the message names them, and the largest rank count that works.
  Scene gathers = golden_scene("particles-source-vector-sum");
  gathers.guidance.sensing_radius = 2.0;
  try {
    distributed::decompose(gathers, 64);
    FAIL() << "64 ranks with a sensing radius of 2";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("narrower than the halo of 2.177 LU (the particles within the sensing radius)"), std::string::npos)
        << m;
    EXPECT_NE(m.find("(at most 27 ranks)"), std::string::npos) << m;
  }
  EXPECT_EQ(distributed::decompose(gathers, 27).blocks, (std::array<int, 3>{3, 3, 3}));
  // A grid scene is cut in slabs along z over the grid's cube.
  Scene grid = golden_scene("grid-implicit-absorbing-snr");
  const distributed::Decomposition slabs = distributed::decompose(grid, 4);
  EXPECT_TRUE(slabs.slabs);
  EXPECT_EQ(slabs.blocks, (std::array<int, 3>{1, 1, 4}));
  try {
    distributed::decompose(grid, 200);
    FAIL() << "200 slabs";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("at most"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("slabs along z"), std::string::npos) << e.what();
  }
  Scene signalling;
  signalling.axons.growth_model = GrowthModel::kSignalling;
  EXPECT_THROW(distributed::decompose(signalling, 2), RunError);
}

TEST(decomposed, BlocksAreTheMostCubicFactorisation) {
  Scene s;
  s.guidance.model = GuidanceModel::kDirect;
  s.neurons.radius = 20.0;
  const std::pair<int, std::array<int, 3>> cases[] = {
      {1, {1, 1, 1}}, {2, {2, 1, 1}}, {3, {3, 1, 1}}, {4, {2, 2, 1}}, {6, {3, 2, 1}}, {8, {2, 2, 2}}, {12, {3, 2, 2}}};
  for (const auto& [k, blocks] : cases) {
    const distributed::Decomposition d = distributed::decompose(s, k);
    EXPECT_EQ(d.blocks, blocks) << k;
    // Every rank's neighbours are symmetric, and every point has one owner.
    for (int r = 0; r < k; ++r)
      for (int q : d.neighbours(r)) {
        const auto back = d.neighbours(q);
        EXPECT_TRUE(std::find(back.begin(), back.end(), r) != back.end());
      }
    EXPECT_EQ(d.owner({-1e9, -1e9, -1e9}), 0);
    EXPECT_EQ(d.owner({1e9, 1e9, 1e9}), k - 1);
    EXPECT_TRUE(d.near(0, {-1e9, 0, 0}, 0.0));
  }
}

// MpiSession's remedy for PMIx's stalls in MPI_Finalize: TCP_NODELAY on the sockets to a
// loopback peer (both ends of a connection here), and on no other socket: not a listener,
// an unconnected socket or a UNIX socket pair, and, where this machine has an IPv4 address
// besides the loopback, not a connection through that address.
TEST(decomposed, NoDelayIsSetOnLoopbackSocketsOnly) {
  auto no_delay = [](int fd) {
    int v = -1;
    socklen_t len = sizeof v;
    return getsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &v, &len) == 0 ? v : -1;
  };
  // A connection to `address` (network order): {listener, client, server}.
  auto connection = [](std::uint32_t address) {
    std::array<int, 3> fds{-1, -1, -1};
    fds[0] = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in at{};
    at.sin_family = AF_INET;
    at.sin_addr.s_addr = address;
    socklen_t len = sizeof at;
    if (bind(fds[0], reinterpret_cast<sockaddr*>(&at), sizeof at) != 0 || listen(fds[0], 1) != 0 ||
        getsockname(fds[0], reinterpret_cast<sockaddr*>(&at), &len) != 0)
      return fds;
    fds[1] = socket(AF_INET, SOCK_STREAM, 0);
    if (connect(fds[1], reinterpret_cast<sockaddr*>(&at), sizeof at) != 0) return fds;
    fds[2] = accept(fds[0], nullptr, nullptr);
    return fds;
  };
  const auto [listener, client, server] = connection(htonl(INADDR_LOOPBACK));
  ASSERT_GE(server, 0);
  // This machine's first IPv4 address that is not the loopback, if it has one.
  std::uint32_t outside = 0;
  ifaddrs* interfaces = nullptr;
  ASSERT_EQ(getifaddrs(&interfaces), 0);
  for (const ifaddrs* i = interfaces; i && !outside; i = i->ifa_next)
    if (i->ifa_addr && i->ifa_addr->sa_family == AF_INET) {
      const std::uint32_t a = reinterpret_cast<const sockaddr_in*>(i->ifa_addr)->sin_addr.s_addr;
      if ((ntohl(a) >> 24) != 127) outside = a;
    }
  freeifaddrs(interfaces);
  const std::array<int, 3> through = outside ? connection(outside) : std::array<int, 3>{-1, -1, -1};
  if (outside) {
    ASSERT_GE(through[2], 0);
  }
  const int unconnected = socket(AF_INET, SOCK_STREAM, 0);
  int pair[2];
  ASSERT_EQ(socketpair(AF_UNIX, SOCK_STREAM, 0, pair), 0);
  EXPECT_EQ(no_delay(client), 0);
  EXPECT_EQ(no_delay(server), 0);

  EXPECT_GE(distributed::no_delay_on_loopback_sockets(), 2);  // and any the process inherited
  EXPECT_EQ(no_delay(client), 1);
  EXPECT_EQ(no_delay(server), 1);
  EXPECT_EQ(no_delay(unconnected), 0);
  EXPECT_EQ(no_delay(listener), 0);
  if (outside) {
    EXPECT_EQ(no_delay(through[1]), 0);
    EXPECT_EQ(no_delay(through[2]), 0);
  }
  std::printf("a connection through a non-loopback address: %s\n", outside ? "checked" : "none on this machine");
  for (int fd : {listener, client, server, unconnected, pair[0], pair[1], through[0], through[1], through[2]})
    if (fd >= 0) close(fd);
}

// The particle field's fast path: a point that Bounds::inner puts inside a block, farther
// than the margin from its shared faces, is owned by that block (block_of's divisions agree)
// and near none of its shared faces at any width up to the margin (the test that decides
// which particles go to the halo), at every scale of the domain and for points within a few
// ulps of the margin, either side.
RC_GTEST_PROP(decomposed, InnerPointsAreOwnedAndNearNoOtherBlock, ()) {
  distributed::Decomposition d;
  d.blocks = {*rc::gen::inRange(1, 5), *rc::gen::inRange(1, 5), *rc::gen::inRange(1, 5)};
  d.ranks = d.blocks[0] * d.blocks[1] * d.blocks[2];
  d.half = *rc::gen::element(0.7, 3.0, 1e3, 1e6) * (1.0 + *rc::gen::inRange(0, 1000) / 997.0);
  for (int a = 0; a < 3; ++a) d.edge[a] = 2.0 * d.half / d.blocks[a];
  const double shortest = *std::min_element(d.edge.begin(), d.edge.end());
  d.halo = shortest * *rc::gen::element(1e-7, 1e-3, 0.1, 0.5, 1.0);
  RC_ASSERT(d.inner_margin() == d.halo);
  // The halo's margin (owned, and in no other rank's halo), or the rounding margin (owned).
  const double margin = *rc::gen::arbitrary<bool>() ? d.inner_margin() : d.rounding_margin();
  const int rank = *rc::gen::inRange(0, d.ranks);
  const distributed::Decomposition::Bounds b = d.bounds(rank);
  for (int t = 0; t < 64; ++t) {
    double c[3];
    for (int a = 0; a < 3; ++a) {
      const int kind = *rc::gen::inRange(0, 4);
      const double ulps = static_cast<double>(*rc::gen::inRange(-6, 7));
      if (kind == 0)  // anywhere in and around the block
        c[a] = b.lo[a] - d.edge[a] + 3.0 * d.edge[a] * *rc::gen::inRange(0, 10001) / 10000.0;
      else if (kind == 1)  // at the margin from the lower face
        c[a] = (b.lo[a] + margin) * (1.0 + ulps * 0x1p-52);
      else if (kind == 2)  // at the margin from the upper face
        c[a] = (b.hi[a] - margin) * (1.0 + ulps * 0x1p-52);
      else  // on a face
        c[a] = (*rc::gen::arbitrary<bool>() ? b.lo[a] : b.hi[a]) * (1.0 + ulps * 0x1p-52);
    }
    const Vec3 p{c[0], c[1], c[2]};
    if (!b.inner(p, margin)) continue;
    RC_ASSERT(d.owner(p) == rank);
    RC_ASSERT(!b.near_boundary(p, margin));
    RC_ASSERT(!d.near_boundary(rank, p, margin * *rc::gen::element(0.0, 0.5, 1.0)));
    // A neighbour's face is computed from its own index, so it may lie an ulp from ours: no
    // neighbour is within the margin less 0.1 % (the halos' own allowance, 1.001 x the gather
    // radius, is what covers that ulp).
    for (int q : d.neighbours(rank)) RC_ASSERT(!d.near(q, p, 0.999 * margin));
  }
}

}  // namespace
}  // namespace axg

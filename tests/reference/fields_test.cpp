// Cue fields and cue guidance: thread invariance for every field and steering model,
// the direction of attraction and repulsion, stability and positivity of the grid
// schemes, and the particle field against the analytic steady state.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <cstring>

#include "axonguide/core/steering.hpp"
#include "axonguide/model/cues.hpp"
#include "axonguide/model/sensing.hpp"
#include "axonguide/model/steering.hpp"
#include "axonguide/fields/fields.hpp"
#include "axonguide/fields/lod.hpp"
#include "support.hpp"

namespace axg {
namespace {

Scene cue_scene(FieldKind field, GuidanceModel model) {
  Scene s = Scene::builtin_default();
  s.neurons.count = 300;
  s.neurons.radius = 2.5 * std::cbrt(3.0);
  s.steps = 40;
  s.guidance.model = model;
  s.cues.field = field;
  s.cues.grid.spacing = 0.25;
  return s;
}

struct Variant {
  const char* name;
  FieldKind field;
  GuidanceModel model;
  void (*tweak)(Scene&);
};

const Variant kVariants[] = {
    {"particles_snr", FieldKind::kParticles, GuidanceModel::kSnr, [](Scene&) {}},
    {"particles_vector_sum", FieldKind::kParticles, GuidanceModel::kVectorSum, [](Scene&) {}},
    {"particles_ballistic", FieldKind::kParticles, GuidanceModel::kSnr,
     [](Scene& s) { s.cues.particles.motion = Motion::kBallistic; }},
    {"particles_collisions", FieldKind::kParticles, GuidanceModel::kSnr,
     [](Scene& s) {
       s.cues.particles.collisions = true;
       s.cues.particles.radius = 0.05;
     }},
    {"grid_implicit_absorbing", FieldKind::kGrid, GuidanceModel::kSnr, [](Scene&) {}},
    {"grid_implicit_reflecting", FieldKind::kGrid, GuidanceModel::kVectorSum,
     [](Scene& s) { s.cues.grid.boundary = GridBoundary::kReflecting; }},
    {"grid_explicit_absorbing", FieldKind::kGrid, GuidanceModel::kSnr,
     [](Scene& s) { s.cues.grid.scheme = GridScheme::kExplicit; }},
    {"grid_explicit_reflecting", FieldKind::kGrid, GuidanceModel::kSnr,
     [](Scene& s) {
       s.cues.grid.scheme = GridScheme::kExplicit;
       s.cues.grid.boundary = GridBoundary::kReflecting;
     }},
    {"analytic_snr", FieldKind::kAnalytic, GuidanceModel::kSnr, [](Scene&) {}},
    {"analytic_vector_sum", FieldKind::kAnalytic, GuidanceModel::kVectorSum, [](Scene&) {}},
};

void PrintTo(const Variant& v, std::ostream* os) { *os << v.name; }

class FieldVariant : public ::testing::TestWithParam<Variant> {};

TEST_P(FieldVariant, ThreadCountNeverChangesAByte) {
  Scene s = cue_scene(GetParam().field, GetParam().model);
  GetParam().tweak(s);
  const auto one = test::run_hashes(s, 1);
  EXPECT_EQ(test::run_hashes(s, 2), one);
  EXPECT_EQ(test::run_hashes(s, 7), one);
}

INSTANTIATE_TEST_SUITE_P(fields, FieldVariant, ::testing::ValuesIn(kVariants),
                         [](const auto& info) { return std::string(info.param.name); });

// Random cue scenes: any field, model, motion, boundary; 1, 2 and 7 threads agree.
RC_GTEST_PROP(fields, RandomCueScenesAreThreadInvariant, ()) {
  Scene s = *test::gen_direct_scene();
  s.neurons.count = std::min<std::uint64_t>(s.neurons.count, 150);
  s.steps = std::min<std::uint32_t>(s.steps, 25);
  s.guidance.model = *rc::gen::element(GuidanceModel::kSnr, GuidanceModel::kVectorSum);
  s.cues.field = *rc::gen::element(FieldKind::kParticles, FieldKind::kGrid, FieldKind::kAnalytic);
  s.cues.random_sources.count = *rc::gen::inRange<std::uint32_t>(1, 5);
  s.cues.random_sources.emission = *rc::gen::inRange(0, 300) / 2.0;
  s.cues.particles.motion = *rc::gen::element(Motion::kBrownian, Motion::kBallistic);
  s.cues.particles.collisions = *rc::gen::arbitrary<bool>();
  s.cues.grid.spacing = std::max(0.2, s.bounds_radius() / 12);
  s.cues.grid.scheme = *rc::gen::element(GridScheme::kExplicit, GridScheme::kImplicit);
  s.cues.grid.boundary = *rc::gen::element(GridBoundary::kAbsorbing, GridBoundary::kReflecting);
  s.guidance.noise = *rc::gen::element(NoiseForm::kCount, NoiseForm::kBinding, NoiseForm::kSnapshot);
  if (*rc::gen::arbitrary<bool>()) s.guidance.integration_time = s.dt * *rc::gen::inRange(2, 9) / 2.0;
  std::map<std::string, std::string> one;
  try {
    one = test::run_hashes(s, 1);
  } catch (const RunError&) {
    RC_DISCARD("placement too dense");
  }
  RC_ASSERT(test::run_hashes(s, 2) == one);
  RC_ASSERT(test::run_hashes(s, 7) == one);
}

// One cue at the origin; tips scattered around it with random headings. After one
// steering decision, the mean change of h.u (u: unit vector toward the source) is
// positive for an attractant and negative for a repellent.
double mean_turn_toward(FieldKind field, CueKind kind, GuidanceModel model) {
  Scene s = cue_scene(field, model);
  s.cues.sources.assign(1, Source{});
  s.cues.sources[0].kind = kind;
  s.cues.sources[0].position = core::Vec3{0, 0, 0};
  s.cues.grid.spacing = 0.1;
  const auto cues = make_cues(s);
  auto f = make_reference_field(s, cues);
  PhaseTimes times;
  for (std::uint32_t step = 1; step <= 60; ++step) f->advance(step, times);
  const auto sp = sense_params(s);
  const auto st = steer_params(s);
  double total = 0;
  const int n = 4000;
  for (int i = 0; i < n; ++i) {
    core::Rng rng(5, core::Stream::kValidation, static_cast<std::uint64_t>(i), 0);
    const core::Vec3 tip = (0.6 + 1.4 * rng.uniform()) * core::direction_trig(rng);
    const core::Vec3 h = core::direction_trig(rng);
    core::CueSample samples[core::kMaxCues];
    core::Vec3 pull[core::kMaxCues];
    f->sample(tip, samples, pull);
    const core::Vec3 out = core::steer_axon(h, samples, pull, cues.data(), 1, sp, st, s.seed, static_cast<std::uint32_t>(i), 61).heading;
    const core::Vec3 u = core::normalized(-1.0 * tip);
    total += core::dot(out, u) - core::dot(h, u);
  }
  return total / n;
}

TEST(fields, AttractantsPullAndRepellentsPush) {
  for (FieldKind field : {FieldKind::kParticles, FieldKind::kGrid, FieldKind::kAnalytic})
    for (GuidanceModel model : {GuidanceModel::kSnr, GuidanceModel::kVectorSum}) {
      const double a = mean_turn_toward(field, CueKind::kAttractant, model);
      const double r = mean_turn_toward(field, CueKind::kRepellent, model);
      EXPECT_GT(a, 0.005) << name_of(field) << " " << name_of(model);
      EXPECT_LT(r, -0.005) << name_of(field) << " " << name_of(model);
    }
}

TEST(fields, DirectSceneDoesNoCueWorkAndAnalyticHoldsNoParticlesOrGrid) {
  Scene direct = cue_scene(FieldKind::kParticles, GuidanceModel::kDirect);
  const RunResult r = run_scene(direct, RunOptions{});
  for (const auto& row : r.times.rows()) {
    EXPECT_EQ(row.phase.find("particles"), std::string::npos) << row.phase;
    EXPECT_EQ(row.phase.find("grid"), std::string::npos) << row.phase;
    EXPECT_NE(row.phase, "steer");
  }
  EXPECT_EQ(r.stats.back().particles, 0u);
  EXPECT_EQ(estimate_cue_bytes(direct), 0u);

  Scene analytic = cue_scene(FieldKind::kAnalytic, GuidanceModel::kSnr);
  const auto cues = make_cues(analytic);
  EXPECT_EQ(make_reference_field(analytic, cues)->bytes(), 0u);
  const RunResult a = run_scene(analytic, RunOptions{});
  bool steered = false;
  for (const auto& row : a.times.rows()) {
    EXPECT_EQ(row.phase.find("particles"), std::string::npos) << row.phase;
    EXPECT_EQ(row.phase.find("grid"), std::string::npos) << row.phase;
    steered = steered || row.phase == "steer";
  }
  EXPECT_TRUE(steered);
  EXPECT_EQ(a.stats.back().particles, 0u);
}

// Concentration of cue 0 at x from a field.
double concentration(const CueField& f, core::Vec3 x) {
  core::CueSample s[core::kMaxCues];
  core::Vec3 pull[core::kMaxCues];
  f.sample(x, s, pull);
  return s[0].c;
}

Scene grid_scene(GridScheme scheme, double spacing) {
  Scene s = cue_scene(FieldKind::kGrid, GuidanceModel::kSnr);
  s.neurons.radius = 3;
  s.cues.sources.assign(1, Source{});
  s.cues.sources[0].position = core::Vec3{0.013, -0.021, 0.007};
  s.cues.grid.spacing = spacing;
  s.cues.grid.scheme = scheme;
  return s;
}

TEST(fields, ExplicitSubstepsKeepExplicitAndImplicitClose) {
  // dt = 0.25: D dt / h^2 = 0.56, so explicit needs 4 sub-steps per step. Implicit LOD
  // has a splitting error that grows with D dt / h^2: 4-5 % here, 8.6 % at dt = 0.5 and
  // 16 % at dt = 1, one LU from the source (`axonguide validate field` measures it).
  Scene e = grid_scene(GridScheme::kExplicit, 0.15), i = grid_scene(GridScheme::kImplicit, 0.15);
  e.dt = i.dt = 0.25;
  auto fe = make_reference_field(e, make_cues(e));
  auto fi = make_reference_field(i, make_cues(i));
  EXPECT_NE(fe->note().find("sub-steps per step: 4"), std::string::npos) << fe->note();
  PhaseTimes t;
  for (std::uint32_t step = 1; step <= 600; ++step) {
    fe->advance(step, t);
    fi->advance(step, t);
  }
  for (double r : {0.5, 1.0, 1.5, 2.0}) {
    const double ce = concentration(*fe, {r, 0.1, -0.05}), ci = concentration(*fi, {r, 0.1, -0.05});
    EXPECT_GT(ce, 0);
    EXPECT_NEAR(ci / ce, 1.0, 0.06) << "r = " << r << " explicit " << ce << " implicit " << ci;
  }
}

TEST(fields, ExplicitRefusesWhenSubstepsAreForbidden) {
  Scene e = grid_scene(GridScheme::kExplicit, 0.15);
  e.cues.grid.allow_substeps = false;
  try {
    make_reference_field(e, make_cues(e));
    FAIL();
  } catch (const InputError& err) {
    EXPECT_NE(std::string(err.what()).find("cues.grid.allow_substeps"), std::string::npos) << err.what();
  }
}

TEST(fields, ImplicitStaysNonNegativeAndBoundedWhenStiff) {
  for (GridBoundary b : {GridBoundary::kAbsorbing, GridBoundary::kReflecting}) {
    Scene s = grid_scene(GridScheme::kImplicit, 0.1);
    s.cues.grid.boundary = b;
    s.cues.sources[0].decay = 1e6;       // k dt = 1e6
    s.cues.sources[0].diffusion = 100;   // D dt / h^2 = 1e4
    const auto cues = make_cues(s);
    auto f = make_reference_field(s, cues);
    PhaseTimes t;
    for (std::uint32_t step = 1; step <= 5; ++step) f->advance(step, t);
    const double deposit = s.cues.particles.amount * s.cues.sources[0].emission / (0.1 * 0.1 * 0.1);
    for (double x = -2.9; x < 2.9; x += 0.37)
      for (double y = -2.9; y < 2.9; y += 0.41) {
        const double c = concentration(*f, {x, y, 0.03});
        ASSERT_TRUE(std::isfinite(c));
        ASSERT_GE(c, 0.0);
        ASSERT_LE(c, deposit);
      }
  }
}

// The particle field's time-averaged concentration on a shell around the source against
// the analytic steady state averaged over the same sensing ball.
TEST(fields, ParticleFieldConvergesToTheAnalyticSteadyState) {
  Scene s = cue_scene(FieldKind::kParticles, GuidanceModel::kSnr);
  s.neurons.radius = 12;  // boundary 12 lambda away: absorption there is negligible
  s.guidance.sensing_radius = 0.3;
  s.cues.sources.assign(1, Source{});
  s.cues.sources[0].position = core::Vec3{0, 0, 0};
  s.cues.sources[0].emission = 200;
  const auto cues = make_cues(s);
  auto f = make_reference_field(s, cues);
  const Scene as = [&] {
    Scene a = s;
    a.cues.field = FieldKind::kAnalytic;
    return a;
  }();
  auto analytic = make_reference_field(as, make_cues(as));
  PhaseTimes t;
  for (std::uint32_t step = 1; step <= 150; ++step) f->advance(step, t);  // reach steady state
  const double r0 = 1.5;
  std::vector<core::Vec3> probes;
  for (int i = 0; i < 64; ++i) {
    core::Rng rng(2, core::Stream::kValidation, static_cast<std::uint64_t>(i), 0);
    probes.push_back(r0 * core::direction_trig(rng));
  }
  // Expected: the analytic c averaged over the sensing ball (Monte Carlo, 4000 points).
  double expect = 0;
  for (int j = 0; j < 4000; ++j) {
    core::Rng rng(3, core::Stream::kValidation, static_cast<std::uint64_t>(j), 0);
    const double rr = 0.3 * std::cbrt(rng.uniform());
    expect += concentration(*analytic, probes[0] + rr * core::direction_trig(rng)) / 4000;
  }
  // Batch means over 10 batches of 30 steps, 64 probes each.
  std::vector<double> batch;
  std::uint32_t step = 150;
  for (int b = 0; b < 10; ++b) {
    double sum = 0;
    for (int k = 0; k < 30; ++k) {
      f->advance(++step, t);
      for (const auto& p : probes) sum += concentration(*f, p);
    }
    batch.push_back(sum / (30 * 64));
  }
  double mean = 0, var = 0;
  for (double x : batch) mean += x / batch.size();
  for (double x : batch) var += (x - mean) * (x - mean) / (batch.size() - 1);
  const double se = std::sqrt(var / batch.size());
  RecordProperty("particle_mean", std::to_string(mean));
  RecordProperty("analytic_ball_mean", std::to_string(expect));
  RecordProperty("standard_error", std::to_string(se));
  // Within 4 standard errors of the batch means (the time discretisation of the particle
  // process, one Brownian step of sqrt(2 D dt) = 0.32 LU against lambda = 1 LU, is below
  // that resolution here).
  EXPECT_NEAR(mean, expect, 4 * se) << "particles " << mean << " +- " << se << ", analytic " << expect;
}

TEST(fields, EmissionCountsHonourFractionalRates) {
  std::uint64_t total = 0;
  for (std::uint32_t step = 1; step <= 1000; ++step) total += core::emitted_at(2.5, step);
  EXPECT_EQ(total, 2500u);
  EXPECT_EQ(core::emitted_at(0.0, 7), 0u);
  EXPECT_EQ(core::emitted_at(100.0, 1), 100u);
}

}  // namespace
}  // namespace axg

namespace axg {
namespace {

// The batched CPU sweeps equal one core::lod_line_solve per line (the accelerator's one
// thread per line), bit for bit, for both boundaries and any lambda.
RC_GTEST_PROP(fields, BatchedLodSweepsEqualLineByLine, ()) {
  const int n = *rc::gen::inRange(2, 24);
  const double lambda = *rc::gen::element(0.0, 0.01, 0.5, 2.2, 1e4);
  const bool reflecting = *rc::gen::arbitrary<bool>();
  const std::size_t nn = static_cast<std::size_t>(n);
  std::vector<double> a(nn * nn * nn);
  for (std::size_t i = 0; i < a.size(); ++i) {
    core::Rng rng(9, core::Stream::kValidation, i, static_cast<std::uint32_t>(n));
    a[i] = rng.uniform();
  }
  std::vector<double> b = a;
  lod_sweeps(a.data(), n, lambda, reflecting);
  std::vector<double> cp(nn), dp(nn);
  for (std::size_t line = 0; line < nn * nn; ++line)
    core::lod_line_solve(b.data(), line * nn, 1, n, lambda, reflecting, cp.data(), dp.data());
  for (std::size_t p = 0; p < nn; ++p)
    for (std::size_t q = 0; q < nn; ++q)
      core::lod_line_solve(b.data(), p * nn * nn + q, nn, n, lambda, reflecting, cp.data(), dp.data());
  for (std::size_t p = 0; p < nn; ++p)
    for (std::size_t q = 0; q < nn; ++q)
      core::lod_line_solve(b.data(), p * nn + q, nn * nn, n, lambda, reflecting, cp.data(), dp.data());
  RC_ASSERT(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
  for (double v : a) RC_ASSERT(v >= 0.0);
}

}  // namespace
}  // namespace axg

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <vector>

#include "axonguide/core/sampler.hpp"
#include "axonguide/support/error.hpp"
#include "axonguide/placement/sampler_nd.hpp"

namespace axg {
namespace {

using core::Rng;
using core::Sampler;
using core::Stream;
using core::RegionShape;

const auto kSamplers = {Sampler::kRejection, Sampler::kNormal, Sampler::kTrig, Sampler::kCoordinate};

rc::Gen<Sampler> gen_sampler() {
  return rc::gen::element(Sampler::kRejection, Sampler::kNormal, Sampler::kTrig, Sampler::kCoordinate);
}

RC_GTEST_PROP(sampler, DirectionsHaveUnitNorm, (std::uint64_t seed, std::uint32_t id)) {
  const Sampler s = *gen_sampler();
  Rng rng(seed, Stream::kValidation, id, 0);
  const core::Vec3 v = sample_direction3(s, rng);
  RC_ASSERT(std::fabs(core::norm(v) - 1.0) <= 4e-16);
}

RC_GTEST_PROP(sampler, RegionPointsLieInTheRegion, (std::uint64_t seed, std::uint32_t id)) {
  const Sampler s = *gen_sampler();
  const auto shape = *rc::gen::element(RegionShape::kBall, RegionShape::kSphere, RegionShape::kBox, RegionShape::kDisc);
  const double R = *rc::gen::inRange(1, 1000) / 10.0;
  Rng rng(seed, Stream::kPlacement, id, 0);
  const core::Vec3 p = sample_region_point(shape, R, s, rng);
  const double r = core::norm(p);
  switch (shape) {
    case RegionShape::kBall: RC_ASSERT(r <= R * (1 + 1e-15)); break;
    case RegionShape::kSphere: RC_ASSERT(std::fabs(r - R) <= R * 1e-15); break;
    case RegionShape::kBox:
      RC_ASSERT(std::fabs(p.x) < R && std::fabs(p.y) < R && std::fabs(p.z) < R);
      break;
    case RegionShape::kDisc: RC_ASSERT(p.z == 0.0 && r < R); break;
  }
}

RC_GTEST_PROP(sampler, AnyDimensionUnitNormAndBall, (std::uint64_t seed)) {
  const Sampler s = *rc::gen::element(Sampler::kRejection, Sampler::kNormal, Sampler::kCoordinate);
  const int d = s == Sampler::kRejection ? *rc::gen::inRange(1, kRejectionMaxDimension + 1)
                                         : *rc::gen::inRange(2, 60);
  std::vector<double> x(static_cast<std::size_t>(d));
  Rng rng(seed, Stream::kValidation, static_cast<std::uint64_t>(d), 1);
  sample_direction(s, rng, d, x.data());
  double n2 = 0;
  for (double v : x) n2 += v * v;
  RC_ASSERT(std::fabs(std::sqrt(n2) - 1.0) <= 1e-14);
  sample_ball(s, rng, d, 2.0, x.data());
  n2 = 0;
  for (double v : x) n2 += v * v;
  RC_ASSERT(std::sqrt(n2) <= 2.0 * (1 + 1e-14));
}

TEST(sampler, HighDimensionsWhereEachMethodReaches) {
  std::vector<double> x(1000);
  for (Sampler s : {Sampler::kNormal, Sampler::kCoordinate}) {
    Rng rng(3, Stream::kValidation, 0, 0);
    sample_direction(s, rng, 1000, x.data());
    double n2 = 0;
    for (double v : x) n2 += v * v;
    EXPECT_NEAR(std::sqrt(n2), 1.0, 1e-13);
  }
}

TEST(sampler, RefusesDimensionsItCannotServe) {
  std::vector<double> x(20);
  Rng rng(1, Stream::kValidation, 0, 0);
  EXPECT_THROW(sample_direction(Sampler::kTrig, rng, 4, x.data()), InputError);
  try {
    sample_direction(Sampler::kRejection, rng, 14, x.data());
    FAIL() << "rejection accepted d = 14";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("acceptance rate"), std::string::npos) << e.what();
  }
  EXPECT_NEAR(rejection_acceptance(3), M_PI / 6, 1e-12);
}

TEST(sampler, MeansAreNearZero) {
  // A coarse guard; the uniformity tests are `axonguide validate samplers`.
  for (Sampler s : kSamplers) {
    core::Vec3 sum{0, 0, 0};
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
      Rng rng(11, Stream::kValidation, static_cast<std::uint64_t>(i), 0);
      sum += sample_direction3(s, rng);
    }
    // Each coordinate has variance 1/3: 5 sigma of the mean.
    const double tol = 5.0 * std::sqrt(1.0 / 3.0 / n);
    EXPECT_LT(std::fabs(sum.x / n), tol) << static_cast<int>(s);
    EXPECT_LT(std::fabs(sum.y / n), tol) << static_cast<int>(s);
    EXPECT_LT(std::fabs(sum.z / n), tol) << static_cast<int>(s);
  }
}

TEST(sampler, NormalPairMoments) {
  double s1 = 0, s2 = 0;
  const int n = 100000;
  for (int i = 0; i < n; ++i) {
    Rng rng(5, Stream::kValidation, static_cast<std::uint64_t>(i), 2);
    double a, b;
    core::normal_pair(rng, &a, &b);
    s1 += a + b;
    s2 += a * a + b * b;
  }
  EXPECT_NEAR(s1 / (2 * n), 0.0, 5 * std::sqrt(1.0 / (2 * n)));
  EXPECT_NEAR(s2 / (2 * n), 1.0, 5 * std::sqrt(2.0 / (2 * n)));
}

}  // namespace
}  // namespace axg

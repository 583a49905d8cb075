#include "axonguide/placement/sampler_nd.hpp"

#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "axonguide/placement/coordinate_marginal.hpp"
#include "axonguide/core/sampler.hpp"
#include "axonguide/support/error.hpp"

namespace axg {

using core::Sampler;

double rejection_acceptance(int d) {
  // V_d = pi^(d/2) / Gamma(d/2 + 1); here only as a rate for messages and limits.
  return std::exp(0.5 * d * std::log(M_PI) - std::lgamma(0.5 * d + 1.0) - d * std::log(2.0));
}

namespace {

// Coordinate method: x_1 from the marginal of S^(m-1) (m = d, d-1, ..., 2), each later
// coordinate scaled by the remaining radius sqrt(1 - x^2); the last one is +-scale.
void direction_coordinate(core::Rng& rng, int d, double* out) {
  double scale = 1.0;
  for (int k = 0; k + 1 < d; ++k) {
    const int m = d - k;
    const double x = coordinate_marginal_inverse(rng.uniform(), m);
    out[k] = scale * x;
    scale = scale * std::sqrt((1.0 - x) * (1.0 + x));
  }
  out[d - 1] = (rng.word32() & 1u) ? scale : -scale;
}

void check_dimension(Sampler sampler, int d) {
  if (d < 1) throw InputError(fmt::format("dimension d = {}: must be >= 1", d));
  if (sampler == Sampler::kTrig && d != 3)
    throw InputError(fmt::format("the trig sampler is defined for d = 3 only (asked d = {})", d));
  if (sampler == Sampler::kRejection && d > kRejectionMaxDimension)
    throw InputError(fmt::format(
        "the rejection sampler refuses d = {}: its acceptance rate V_d/2^d = {:.3g} would need "
        "~{:.3g} tries per point (limit d <= {})",
        d, rejection_acceptance(d), 1.0 / rejection_acceptance(d), kRejectionMaxDimension));
}

}  // namespace

void sample_direction(Sampler sampler, core::Rng& rng, int d, double* out) {
  check_dimension(sampler, d);
  switch (sampler) {
    case Sampler::kRejection: {
      core::ball_rejection_nd(rng, d, out, 1L << 40);
      double s = 0.0;
      for (int k = 0; k < d; ++k) s += out[k] * out[k];
      const double r = std::sqrt(s);
      for (int k = 0; k < d; ++k) out[k] = out[k] / r;
      return;
    }
    case Sampler::kNormal: core::direction_normal_nd(rng, d, out); return;
    case Sampler::kTrig: {
      const core::Vec3 v = core::direction_trig(rng);
      out[0] = v.x, out[1] = v.y, out[2] = v.z;
      return;
    }
    case Sampler::kCoordinate: direction_coordinate(rng, d, out); return;
  }
}

void sample_ball(Sampler sampler, core::Rng& rng, int d, double radius, double* out) {
  check_dimension(sampler, d);
  if (sampler == Sampler::kRejection) {
    core::ball_rejection_nd(rng, d, out, 1L << 40);
    for (int k = 0; k < d; ++k) out[k] = radius * out[k];
    return;
  }
  sample_direction(sampler, rng, d, out);
  const double r = core::ball_radius(rng, radius, d);
  for (int k = 0; k < d; ++k) out[k] = r * out[k];
}

core::Vec3 sample_direction3(Sampler sampler, core::Rng& rng) {
  if (sampler != Sampler::kCoordinate) return core::direction3(sampler, rng);
  double v[3];
  direction_coordinate(rng, 3, v);
  return {v[0], v[1], v[2]};
}

core::Vec3 sample_region_point(core::RegionShape shape, double radius, Sampler sampler,
                               core::Rng& rng) {
  switch (shape) {
    case core::RegionShape::kBox: return core::box_point(rng, radius);
    case core::RegionShape::kDisc: {  // the unit disc by rejection (the scene refuses other samplers)
      double x, y, s;
      core::unit_disc(rng, &x, &y, &s);
      return {radius * x, radius * y, 0.0};
    }
    case core::RegionShape::kSphere: return radius * sample_direction3(sampler, rng);
    case core::RegionShape::kBall:
      if (sampler == Sampler::kRejection) return radius * core::unit_ball_rejection(rng);
      {
        const core::Vec3 h = sample_direction3(sampler, rng);
        return core::ball_radius(rng, radius, 3) * h;
      }
  }
  return {0, 0, 0};
}

}  // namespace axg

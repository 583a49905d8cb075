#pragma once
// Host-side sampler dispatch for any dimension, including the coordinate method (which
// needs GSL's incomplete beta and so is not part of the portable core).
#include "axonguide/core/random.hpp"
#include "axonguide/core/types.hpp"
#include "axonguide/core/vec3.hpp"

namespace axg {

// Largest d for which the rejection sampler is offered: its acceptance rate V_d / 2^d
// falls below 1e-4 beyond it (d = 13: 1.1e-4 points accepted per try).
inline constexpr int kRejectionMaxDimension = 13;
// Acceptance rate of the rejection sampler in d dimensions, V_d / 2^d.
double rejection_acceptance(int d);

// A uniform direction on S^(d-1), written to out[0..d). Throws InputError when the
// sampler cannot serve d (trig: d != 3; rejection: d > kRejectionMaxDimension).
void sample_direction(core::Sampler sampler, core::Rng& rng, int d, double* out);
// A uniform point in the ball of radius `radius` in d dimensions.
void sample_ball(core::Sampler sampler, core::Rng& rng, int d, double radius, double* out);

core::Vec3 sample_direction3(core::Sampler sampler, core::Rng& rng);
// A uniform point in the region (ball, sphere surface, or box of half-edge `radius`).
core::Vec3 sample_region_point(core::RegionShape shape, double radius, core::Sampler sampler,
                               core::Rng& rng);

}  // namespace axg

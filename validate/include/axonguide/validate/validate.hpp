#pragma once
// `axonguide validate ...` (SPEC §6-§7). Each study adds its checks, tables and plots to
// a Report; `all` runs every study into DIR/<study>/ and writes an index.
#include <string>

#include "axonguide/core/random.hpp"
#include "axonguide/core/steering.hpp"
#include "axonguide/core/types.hpp"
#include "axonguide/validate/report.hpp"

namespace axg {
struct Scene;
}

namespace axg::validate {

struct Options {
  bool quick = false;        // smaller sizes (the CI run, under 3 minutes in all)
  int threads = 0;           // 0: all cores
  std::string points_file;   // samplers: test an external point set instead
  double radius = 1.0;       // samplers --points: ball radius when the points are not unit vectors
  bool allow_skip = false;   // a skipped check (no GPU, too few data) exits 0 instead of 3
};

void validate_samplers(const Options& o, Report& r);
// One point as `validate samplers` draws it: a direction on S^(d-1), or with `ball` a point
// of the ball of the given radius. For d = 3 these are placement's own calls
// (sample_region_point, sample_direction3), so the validated samplers are the placed ones.
void sampler_point(core::Sampler sampler, bool ball, int d, double radius, core::Rng& rng, double* out);
void validate_points_file(const Options& o, Report& r);
void validate_field(const Options& o, Report& r);
void validate_stiff(const Options& o, Report& r);
void validate_turning(const Options& o, Report& r);
void validate_guidance(const Options& o, Report& r);
void validate_continuum(const Options& o, Report& r);
// The explant of `validate guidance` (and of `validate continuum`): 400 neurons in a ball of
// radius 1, one attractant 4 LU away (D = 0.5, k = 0.05, K_d = 0.5), no wandering, 30 steps of
// 0.2 LU, bounds 12 LU; the field, its resolution and the emission are the caller's.
Scene explant_base(std::uint64_t seed, core::NoiseForm noise);
void validate_assay(const Options& o, Report& r);
// Every chi2 the calibration quotes, regenerated: the signalling model's fits to the shared
// explant outgrowth, with parameter counts and a between-explant variance (validate/src/calibration.cpp).
void validate_calibration(const Options& o, Report& r);
// The branching rule (BESTL) against van Pelt's recursion, the Yule process and the
// elongation model, through the tree process (validate/src/branching.cpp).
void validate_branching(const Options& o, Report& r);
// Apposition detection against Steiner's formula, the crossing term and brute force, and its
// convergence on grown arbours (validate/src/synapses.cpp).
void validate_synapses(const Options& o, Report& r);
void validate_bfs(const Options& o, Report& r);
void validate_gpu(const Options& o, Report& r);

// Runs one study (or "all") into `dir`; returns the exit code: 0 pass, 1 a check failed,
// 3 a check was skipped (it could not run here) and allow_skip is not set.
int run_validation(const std::string& what, const std::string& dir, const Options& o);

// One SNR decision of the real steering function for one exact cue with occupancy gamma
// (K_d = 1), fractional gradient mu along the unit vector g, heading h.
core::Steered one_cue_decision(core::Vec3 h, double gamma, double mu, core::Vec3 g, const core::SteerParams& p,
                               std::uint64_t seed, std::uint32_t neuron, std::uint32_t step);
core::SteerParams default_snr_params(core::NoiseForm noise);

// Least-squares slope and intercept of y on x (Eigen), with the slope's standard error.
struct Fit {
  double slope, intercept, slope_se;
};
Fit fit_line(const std::vector<double>& x, const std::vector<double>& y);

}  // namespace axg::validate

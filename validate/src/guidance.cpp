// `validate guidance`: guidance that does not depend on the numerics (SPEC §3.4-§3.5).
//  A. Flat field: synthetic Poisson particles of uniform density deposited into the two
//     half meshes of the particle estimate around a tip; the real decisions (core::snr_steer
//     under binding and count) must show no preferred direction (Rayleigh) and turn toward
//     their own estimated direction with probability 1/2. A naive plug-in (direction and
//     magnitude from the same estimate) is the negative control and must be caught.
//  B. Decisions in a linear gradient: P(turn toward) against the exact field's Phi(SNR) as
//     the particles per mesh cell grow, with the measured order.
//  C. The explant of `validate guidance` (one attractant 4 LU away) under every noise form:
//     the guidance index of the particle field (amount ladder) and of the grid field
//     (explicit and implicit, spacing ladders) against the analytic field's, paired by seed,
//     with the orders of the gap and of the grids' evidence error; the defaults within 10 %.
//  D. Molecule-resolved counts: one particle one molecule, against the estimate and the
//     analytic field under the same physical molecule amount.
//  E. The default scene at the default resolution and at 16 times the particles.
//  F. Error against run time for guidance: the explant's index error and the default
//     scene's connection-set difference against wall time, every field at 4+ resolutions.
//  G. Persistence length: direct guidance, the heading autocorrelation of recorded paths
//     against e^(-s l / L_p), and L_p fitted with a jackknife CI.
//
// One file a study in guidance/ (their shared helpers: guidance/shared.hpp).
#include "guidance/shared.hpp"

namespace axg::validate {

using guidance::kExplantSource;

Scene explant_base(std::uint64_t seed, core::NoiseForm noise) {
  Scene s;
  s.seed = seed;
  s.steps = 30;
  s.neurons.count = 400;
  s.neurons.radius = 1.0;
  s.neurons.soma_radius = 0.005;
  s.axons.step_length = 0.2;
  s.axons.bounds_radius = 12.0;
  s.axons.persistence_length = std::nullopt;
  s.guidance.model = GuidanceModel::kSnr;
  s.guidance.noise = noise;
  Source src;
  src.position = kExplantSource;
  src.diffusion = 0.5;
  src.decay = 0.05;
  src.kd = 0.5;
  s.cues.sources = {src};
  s.analysis.bfs_sources.clear();
  s.analysis.components = false;
  return s;
}

void validate_guidance(const Options& o, Report& r) {
  using namespace guidance;
  with_threads(o.threads, [&] {
    flat_field(o, r);
    decision_convergence(o, r);
    AnalyticCache analytic;
    ExplantStudy explant_st;
    explant(o, r, analytic, explant_st);
    molecules(o, r, analytic);
    dipole_correlation(o, r);
    default_scene(o, r);
    work_precision(o, r, explant_st);
    persistence(o, r);
  });
}

}  // namespace axg::validate

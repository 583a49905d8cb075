#pragma once
// Assay metrics (docs/methods.md §12.1): what an explant or a target experiment measures,
// computed from the final network of a run. Host-only analysis of the run's outputs; it
// does not feed back into the model.
//
// The explant is population 0 (or every neuron, in a scene without populations), centred
// on its population's centre (or the origin). Its gradient axis g is the imposed
// direction, or the direction from the explant to the first attractant source (the first
// repellent when there is none), or +x under direct guidance. Tips are projected onto the
// imaging plane spanned by g and the across axis e (docs §12.1), as a microscope sees a
// gel; θ is measured from e, so that θ = 90° points up the gradient.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "axonguide/core/cues.hpp"
#include "axonguide/core/vec3.hpp"
#include "axonguide/scene/scene.hpp"
#include "axonguide/engine/state.hpp"

namespace axg::assay {

inline constexpr int kAngleBins = 36;    // R(θ): 10° sectors, centred at 5°, 15°, ...
inline constexpr int kTurningBins = 36;  // turning angles: 10° bins from -180° to 180°

struct Geometry {
  core::Vec3 center;  // of the explant
  core::Vec3 axis;    // unit gradient axis (3D)
  core::Vec3 up;      // unit gradient axis in the imaging plane (θ = 90°)
  core::Vec3 across;  // unit, θ = 0°
  std::uint64_t first = 0, end = 0;  // explant neuron ids [first, end)
  bool has_target = false;           // a second population exists
  core::Vec3 target_center;          // population 1's centre
};

// The scene's cue sources, positions resolved, also under direct guidance (a control is
// measured against the same axis and sources as its treatment).
std::vector<core::CueParams> reference_cues(const Scene& scene);

Geometry explant_geometry(const Scene& scene, const std::vector<core::CueParams>& cues);

struct Metrics {
  std::uint64_t axons = 0;  // explant axons that grew (length > 0)
  // R(θ_j) = (kAngleBins / N) Σ_{i in sector j} ρ_i: the projected outgrowth per unit angle,
  // normalised so that isotropic growth gives R(θ) = mean ρ.
  std::array<double, kAngleBins> profile{};
  std::array<std::uint64_t, kAngleBins> profile_axons{};
  double mean_outgrowth = 0;  // mean R(θ) = mean projected radius ρ, length units
  double bias = 0;            // first sine Fourier coefficient of R(θ) / mean R(θ)
  double bias_se = 0;         // delta-method standard error over axons
  double guidance_ratio = 0;  // (H - L) / (H + L), extent up (H) and down (L) the gradient
  double guidance_ratio_se = 0;
  std::array<std::uint64_t, kTurningBins> turning{};  // counts per 10° bin
  double mean_turning_deg = 0;  // positive: toward the gradient
  double turning_se_deg = 0;
  double connected_fraction = 0;  // explant axons connected to any soma
  double exited_fraction = 0;
  // With a second population (NaN without): explant axons connected to a soma of another
  // population, and axons of populations 0 and 1 whose tip ended past the midplane between
  // their centres (each counted toward the other side).
  double target_fraction = 0;
  double crossing_fraction = 0;
  std::uint64_t crossing_axons = 0;  // the denominator of crossing_fraction
  // Over every neuron: tips that ended within 3 sensing radii of an attractant / repellent
  // source (NaN without such a source): where the network's axons went.
  double near_attractant_fraction = 0;
  double near_repellent_fraction = 0;
  // Radial outgrowth beyond the cell body, in 3D (Bicknell et al. 2018's measure, for an
  // explant whose somas sit on its boundary): o_i = |tip_i - c| - |soma_i - c| - r_s for every
  // explant axon that grew, and u_i = g . (tip_i - c) / |tip_i - c| the cosine of its
  // direction to the gradient axis. The least-squares line o = R0 + R1 u gives
  // outgrowth = R0 (the mean over directions, with the explant's random asymmetry,
  // mean u != 0, removed) and outgrowth_bias = R1 / R0: for R = R0 (1 + b cos) it is b, as
  // the first sine coefficient over the mean is for a disc, R(θ) = R0 (1 + b sin θ).
  // SEs from the regression's residuals (delta method for the ratio). NaN below 3 axons.
  double outgrowth = 0, outgrowth_se = 0;
  double outgrowth_bias = 0, outgrowth_bias_se = 0;
};

// soma comes from the placement (the initial heading is heading_draw's); cues from
// reference_cues.
Metrics measure(const Scene& scene, const std::vector<core::Vec3>& soma, const NeuronState& neurons,
                const std::vector<core::CueParams>& cues);

// The scalar metrics by name, in a fixed order (sweep.csv columns, assay.csv rows).
std::vector<std::pair<std::string, double>> scalar_metrics(const Metrics& m);
const std::vector<std::string>& scalar_metric_names();

// The 95 % Wilson score interval of k successes in n.
std::pair<double, double> wilson_interval(double k, double n);

}  // namespace axg::assay

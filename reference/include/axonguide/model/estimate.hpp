#pragma once
// The particle field's estimate of C and grad C (SPEC §3.4; docs/methods.md §2.6): the keys
// cues.particles.estimate.{spacing, time}, their reading, canonical form and defaults, and
// the geometry and moving-average weights that core/estimate.hpp gets.
#include <cstdint>
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "axonguide/core/cues.hpp"
#include "axonguide/core/estimate.hpp"

namespace axg {

struct Scene;
class ObjectReader;

// Mesh spacing (length units) and the time constant of the moving average (time units; 0:
// this step only); nullopt: the defaults of estimate_spacing() and estimate_time().
struct EstimateKeys {
  std::optional<double> spacing;
  std::optional<double> time;
};

// cues.particles.estimate (from the cues.particles object).
void read_estimate_keys(ObjectReader& particles, EstimateKeys& keys);
void write_estimate_keys(const EstimateKeys& keys, nlohmann::json& particles);

// Defaults, from the scene's physical scales (docs/methods.md §2.6): the spacing is the
// sensing radius r (at most a quarter of the domain radius), and the moving average's time
// constant kEstimateIntervals decision intervals (T under the continuum rule, dt under the
// report's per-step rule), so that refining dt at a fixed T leaves the estimate's window.
inline constexpr double kEstimateIntervals = 10.0;
double estimate_spacing(const Scene& scene);
double estimate_time(const Scene& scene);

// The spacing must leave the mesh cells inside the domain and resolve the sensing ball
// (h <= r); a molecule-resolved count must sample the ball faster than a molecule crosses it
// (dt <= r^2 / (6 D), the mean time to leave the ball from its centre).
void check_estimate(const Scene& scene);
// The meshes' node count and memory, before anything is allocated (check_cue_fields).
void check_estimate_mesh(const Scene& scene, const std::vector<core::CueParams>& cues);

// The particle estimate's meshes: every cue's nodes at estimate_spacing() over the
// domain's cube or a cube about its source, and the weights of its moving average:
// beta = 1 - e^(-dt/tau) per step (1 for tau = 0), scale 2a / (h^3 2^32) per fixed-point
// unit of one half.
inline constexpr double kEstimateReach = 8.0;  // decay lengths about a source
core::EstimateSet estimate_geometry(const Scene& scene);  // c = nullptr
struct EstimateParams {
  double beta;
  double scale;
};
EstimateParams estimate_params(const Scene& scene);
// Whether the particle field keeps the estimate.
bool particle_estimate_used(const Scene& scene);

}  // namespace axg

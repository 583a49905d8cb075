#pragma once
// Steering (SPEC §3.5; docs/methods.md §2.7, §2.8): the keys that choose and tune the
// growth cone's decision (guidance.model, noise, turn_angle, gain, vector_weight, decision,
// integration_time, receptor_time, antithetic) and its growth-rate modulation (axons.growth_modulation),
// their reading and canonical form, the decision's clock, and the parameters that
// core/steering.hpp's and core/guide.hpp's formulas get.
#include <cstdint>
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "axonguide/core/guide.hpp"
#include "axonguide/core/steering.hpp"
#include "axonguide/core/types.hpp"

namespace axg {

struct Scene;
struct Units;
class ObjectReader;

// When the growth cone decides: once per integration interval T, on the evidence integrated
// along its path (the continuum model: results converge as dt and the step are refined), or
// once per step on that step's samples (the report's rule, kept for its scenes: the turning
// per unit time grows with the number of steps).
enum class DecisionRule : std::uint8_t { kPerInterval, kPerStep };
const char* name_of(DecisionRule v);

struct SteeringKeys {
  core::GuidanceModel model = core::GuidanceModel::kSnr;
  core::NoiseForm noise = core::NoiseForm::kCount;
  double turn_angle = 0.10471975511965977;  // pi/30, radians per decision
  // alpha: the SNR forms' gain of a decision that integrates for one time unit (the SNR of a
  // decision over T follows from the receptor's correlation time: receptor_time).
  double gain = 250;
  double vector_weight = 0.1;  // beta, per decision
  DecisionRule decision = DecisionRule::kPerInterval;
  // T, time units; nullopt: 1 time unit without declared units (the report's step), or
  // kIntegrationMinutes in physical time units.
  std::optional<double> integration_time;
  // The correlation time of the receptors' readout, time units; nullopt: the noise form's
  // limit (binding: 0, binding events are Poisson and the SNR grows as sqrt(T); snapshot:
  // infinite, one reading of the occupancy whose SNR does not grow with T).
  std::optional<double> receptor_time;
  // The antithetic image of the run: every decision's normal deviates and random sides
  // negated (core/steering.hpp); an equally likely sample of the model. `fit` runs each
  // mirror image of a point this way (docs/methods.md §12.3).
  bool antithetic = false;
};

struct ModulationKeys {
  double growth_modulation = 0.0;  // m in [0, 1): speed v0 (1 + m z / (1 + |z|)); 0: off
};

// guidance.{model, noise, turn_angle, gain, vector_weight, decision, integration_time,
// receptor_time, antithetic}, and axons.growth_modulation.
void read_steering_keys(ObjectReader& guidance, SteeringKeys& keys);
void read_modulation_keys(ObjectReader& axons, ModulationKeys& keys);
void write_steering_keys(const SteeringKeys& keys, nlohmann::json& guidance);
void write_modulation_keys(const ModulationKeys& keys, nlohmann::json& axons);
// Growth-rate modulation responds to the SNR evidence: it needs guidance.model "snr". A
// continuum decision needs dt <= T (the largest allowed dt is T) and steps no longer than
// the sensing diameter (the sensing balls of consecutive steps overlap: the path's samples
// leave no gap).
void check_steering(const Scene& scene);

// Xu, Rosoff, Urbach & Goodhill (2005, Development 132:4545): the growth cone's temporal
// averaging that reproduces the measured gradient sensitivity has a time scale of about
// 3 minutes.
inline constexpr double kIntegrationMinutes = 3.0;
// T in the scene's time units.
double integration_time(const Scene& scene);
// Whether the scene steers by cues (any model but direct).
bool steers(const Scene& scene);

// The decision clock: where each growth step stands in its interval. An interval holds the
// steps whose ends fall in ((j - 1) T, j T], so dt = T is one step each and a T that is n dt
// is n steps; the decision is made at the interval's last step.
struct DecisionClock {
  bool per_step = true;
  std::uint32_t every = 1;  // steps per interval when T is a whole number of steps; 0 otherwise
  double dt = 1.0, time = 1.0;
  core::Decision at(std::uint32_t step) const;
  // Whether an interval can hold more than one step: then every axon keeps sums over it.
  bool sums() const { return !per_step && every != 1; }
  std::uint32_t completed(std::uint32_t step) const;  // intervals completed by the end of step
};
DecisionClock decision_clock(const Scene& scene);

// The variance of the mean over T of a process with unit variance whose autocorrelation is
// e^(-|s| / tau): 2 (x - 1 + e^(-x)) / x^2 with x = T / tau (1 at x = 0).
double mean_variance_exponential(double x);
// The same for the count dipole of freely diffusing molecules (diffusion D) in a sensing
// ball of radius r, averaged over T: exactly, from the dipole's spectrum, as a function of
// theta = D T / r^2 (1 at theta = 0, 2 tau_d / T for T >> tau_d = 2 r^2 / (21 D)).
double dipole_mean_variance(double theta);
// A cue's count dipole variance over the scene's decision interval (core::CueParams::
// dipole_variance): 1 for the per-step rule and for the receptor forms.
double count_dipole_variance(const Scene& scene, double diffusion);

core::SteerParams steer_params(const Scene& scene);
// Growth-rate modulation gives every axon its own step length (stored per axon).
bool modulates_growth(const Scene& scene);
// Every parameter of stage 2 (core/guide.hpp) for the scene's `cue_count` cues at `cues`
// (in the engine's memory).
core::GuideParams guide_params(const Scene& scene, const core::CueParams* cues, int cue_count);

}  // namespace axg

#pragma once
// Steering (SPEC §3.5; docs/methods.md §2.7, §2.8): the keys that choose and tune the
// growth cone's decision (guidance.model, noise, turn_angle, gain, vector_weight) and its
// growth-rate modulation (axons.growth_modulation), their reading and canonical form, and
// the parameters that core/steering.hpp's formulas get.
#include <vector>

#include <nlohmann/json.hpp>

#include "axonguide/core/guide.hpp"
#include "axonguide/core/steering.hpp"
#include "axonguide/core/types.hpp"

namespace axg {

struct Scene;
class ObjectReader;

struct SteeringKeys {
  core::GuidanceModel model = core::GuidanceModel::kSnr;
  core::NoiseForm noise = core::NoiseForm::kCount;
  double turn_angle = 0.10471975511965977;  // pi/30, radians per decision
  double gain = 250;                         // alpha
  double vector_weight = 0.1;                // beta
};

struct ModulationKeys {
  double growth_modulation = 0.0;  // m in [0, 1): step length l0 (1 + m z / (1 + |z|)); 0: off
};

// guidance.{model, noise, turn_angle, gain, vector_weight}, and axons.growth_modulation.
void read_steering_keys(ObjectReader& guidance, SteeringKeys& keys);
void read_modulation_keys(ObjectReader& axons, ModulationKeys& keys);
void write_steering_keys(const SteeringKeys& keys, nlohmann::json& guidance);
void write_modulation_keys(const ModulationKeys& keys, nlohmann::json& axons);
// Growth-rate modulation responds to the SNR evidence: it needs guidance.model "snr".
void check_steering(const Scene& scene);

core::SteerParams steer_params(const Scene& scene);
// Growth-rate modulation gives every axon its own step length (stored per axon).
bool modulates_growth(const Scene& scene);
// Every parameter of stage 2 (core/guide.hpp) for the scene's `cue_count` cues at `cues`
// (in the engine's memory).
core::GuideParams guide_params(const Scene& scene, const core::CueParams* cues, int cue_count);

}  // namespace axg

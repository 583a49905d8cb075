#include "axonguide/model/steering.hpp"

#include <fmt/format.h>

#include "axonguide/core/pmath.hpp"
#include "axonguide/model/sensing.hpp"
#include "axonguide/model/signalling.hpp"
#include "axonguide/scene/reader.hpp"
#include "axonguide/scene/scene.hpp"
#include "axonguide/support/error.hpp"

namespace axg {

void read_steering_keys(ObjectReader& r, SteeringKeys& g) {
  r.choice("model", g.model, {{"direct", GuidanceModel::kDirect}, {"snr", GuidanceModel::kSnr},
                              {"vector_sum", GuidanceModel::kVectorSum},
                              {"source_vector_sum", GuidanceModel::kSourceVectorSum}});
  r.choice("noise", g.noise, {{"binding", NoiseForm::kBinding}, {"snapshot", NoiseForm::kSnapshot},
                              {"count", NoiseForm::kCount}});
  r.number("turn_angle", g.turn_angle, {0, 3.141592653589793, false, false});
  r.number("gain", g.gain, non_negative());
  r.number("vector_weight", g.vector_weight, non_negative());
}

void read_modulation_keys(ObjectReader& r, ModulationKeys& a) {
  r.number("growth_modulation", a.growth_modulation, {0, 1, false, true});
}

void write_steering_keys(const SteeringKeys& g, nlohmann::json& j) {
  j["model"] = name_of(g.model);
  j["noise"] = name_of(g.noise);
  j["turn_angle"] = g.turn_angle;
  j["gain"] = g.gain;
  j["vector_weight"] = g.vector_weight;
}

void write_modulation_keys(const ModulationKeys& a, nlohmann::json& j) { j["growth_modulation"] = a.growth_modulation; }

void check_steering(const Scene& s) {
  if (s.axons.growth_modulation > 0.0 && s.guidance.model != GuidanceModel::kSnr)
    throw InputError(fmt::format(
        "scene: axons.growth_modulation = {}: growth-rate modulation responds to the SNR evidence and needs "
        "guidance.model = \"snr\" (it is \"{}\")",
        s.axons.growth_modulation, name_of(s.guidance.model)));
}

core::SteerParams steer_params(const Scene& scene) {
  core::SteerParams p{};
  p.model = scene.guidance.model;
  double s, c;
  core::pm::sincos(scene.guidance.turn_angle, &s, &c);
  p.cos_turn = c;
  p.sin_turn = s;
  p.gain = scene.guidance.gain;
  p.vector_weight = scene.guidance.vector_weight;
  p.noise = scene.guidance.noise;
  p.modulation = scene.axons.growth_modulation;
  return p;
}

bool modulates_growth(const Scene& s) { return s.axons.growth_modulation > 0.0 && s.uses_cues(); }

core::GuideParams guide_params(const Scene& scene, const core::CueParams* cues, int cue_count) {
  core::GuideParams p{};
  p.steer = steer_params(scene);
  p.sense = sense_params(scene);
  p.cues = cues;
  p.cue_count = cue_count;
  p.step_length = scene.axons.step_length;
  p.modulated = modulates_growth(scene);
  p.signalling = scene.signalling();
  if (p.signalling) {
    p.signal = signalling_params(scene);
    p.signal_cue = static_cast<int>(scene.axons.signalling.cue);
    p.signal_substeps = static_cast<int>(scene.axons.signalling.substeps);
    p.signal_halvings = static_cast<int>(scene.axons.signalling.halvings);
  }
  p.dt = scene.dt;
  p.seed = scene.seed;
  return p;
}

}  // namespace axg

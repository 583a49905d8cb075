#include "axonguide/model/steering.hpp"

#include <cmath>
#include <map>
#include <mutex>

#include <fmt/format.h>

#include "axonguide/core/pmath.hpp"
#include "axonguide/model/cues.hpp"
#include "axonguide/model/growth.hpp"
#include "axonguide/model/sensing.hpp"
#include "axonguide/model/signalling.hpp"
#include "axonguide/scene/reader.hpp"
#include "axonguide/scene/scene.hpp"
#include "axonguide/support/error.hpp"

namespace axg {

const char* name_of(DecisionRule v) { return v == DecisionRule::kPerStep ? "per_step" : "per_interval"; }

void read_steering_keys(ObjectReader& r, SteeringKeys& g) {
  r.choice("model", g.model, {{"direct", GuidanceModel::kDirect}, {"snr", GuidanceModel::kSnr},
                              {"vector_sum", GuidanceModel::kVectorSum},
                              {"source_vector_sum", GuidanceModel::kSourceVectorSum}});
  r.choice("noise", g.noise, {{"binding", NoiseForm::kBinding}, {"snapshot", NoiseForm::kSnapshot},
                              {"count", NoiseForm::kCount}});
  r.number("turn_angle", g.turn_angle, {0, 3.141592653589793, false, false});
  r.number("gain", g.gain, non_negative());
  r.number("vector_weight", g.vector_weight, non_negative());
  r.choice("decision", g.decision, {{"per_interval", DecisionRule::kPerInterval}, {"per_step", DecisionRule::kPerStep}});
  r.optional_number("integration_time", g.integration_time, positive());
  r.optional_number("receptor_time", g.receptor_time, non_negative());
  r.boolean("antithetic", g.antithetic);
}

void read_modulation_keys(ObjectReader& r, ModulationKeys& a) {
  r.number("growth_modulation", a.growth_modulation, {0, 1, false, true});
}

void write_steering_keys(const SteeringKeys& g, nlohmann::json& j) {
  using nlohmann::json;
  j["model"] = name_of(g.model);
  j["noise"] = name_of(g.noise);
  j["turn_angle"] = g.turn_angle;
  j["gain"] = g.gain;
  j["vector_weight"] = g.vector_weight;
  j["decision"] = name_of(g.decision);
  j["integration_time"] = g.integration_time ? json(*g.integration_time) : json(nullptr);
  j["receptor_time"] = g.receptor_time ? json(*g.receptor_time) : json(nullptr);
  // Written only when set: a run without it keeps its canonical scene, and so its hash
  // (checkpoints, golden provenance), byte for byte.
  if (g.antithetic) j["antithetic"] = true;
}

void write_modulation_keys(const ModulationKeys& a, nlohmann::json& j) { j["growth_modulation"] = a.growth_modulation; }

bool steers(const Scene& s) { return s.guidance.model != GuidanceModel::kDirect; }

double integration_time(const Scene& s) {
  if (s.guidance.integration_time) return *s.guidance.integration_time;
  const std::string& t = s.units.time;
  if (t == "s") return kIntegrationMinutes * 60.0;
  if (t == "min") return kIntegrationMinutes;
  if (t == "h") return kIntegrationMinutes / 60.0;
  return 1.0;  // one time unit: the report's step
}

void check_steering(const Scene& s) {
  if (s.axons.growth_modulation > 0.0 && s.guidance.model != GuidanceModel::kSnr)
    throw InputError(fmt::format(
        "scene: axons.growth_modulation = {}: growth-rate modulation responds to the SNR evidence and needs "
        "guidance.model = \"snr\" (it is \"{}\")",
        s.axons.growth_modulation, name_of(s.guidance.model)));
  if (!steers(s) || s.guidance.decision == DecisionRule::kPerStep) return;
  const double t = integration_time(s);
  if (s.dt > t)
    throw InputError(fmt::format(
        "scene: dt = {}: the growth cone decides once per guidance.integration_time T = {} {}, and the steps of an "
        "interval integrate its evidence, so dt must be at most T; the largest dt allowed is {}",
        s.dt, t, s.units.time, t),
        "dt", fmt::format("{}", s.dt), fmt::format("at most {}", t));
  // The samples along the path must leave no gap: consecutive sensing balls overlap, a step
  // of at most 2 r. (The signalling model's extension is an output of its network, whose
  // bound, signalling_max_step, is far above what it grows: not checked here.)
  if (s.signalling()) return;
  const double r = 2.0 * s.guidance.sensing_radius;
  const double longest = max_step_length(s);
  if (longest > r) {
    const double factor = longest / s.axons.step_length;  // modulation's or the signalling model's bound
    if (s.axons.growth_speed)
      throw InputError(fmt::format(
          "scene: axons.growth_speed = {}: with dt = {} an axon's step reaches {:.6g} {}, longer than the sensing "
          "diameter 2 r = {}; the sensing balls of consecutive steps must overlap, so the largest growth_speed allowed "
          "with this dt is {:.6g} (or make dt smaller)",
          *s.axons.growth_speed, s.dt, longest, s.units.length, r, r / factor / s.dt),
          "axons.growth_speed", fmt::format("{}", *s.axons.growth_speed),
          fmt::format("at most {:.6g}", r / factor / s.dt));
    throw InputError(fmt::format(
        "scene: axons.step_length = {}: an axon's step reaches {:.6g} {}, longer than the sensing diameter 2 r = {}; "
        "the sensing balls of consecutive steps must overlap, so the largest step_length allowed is {:.6g}",
        s.axons.step_length, longest, s.units.length, r, r / factor),
        "axons.step_length", fmt::format("{}", s.axons.step_length), fmt::format("at most {:.6g}", r / factor));
  }
}

DecisionClock decision_clock(const Scene& s) {
  DecisionClock c;
  c.dt = s.dt;
  c.time = integration_time(s);
  c.per_step = !steers(s) || s.guidance.decision == DecisionRule::kPerStep;
  const double q = c.time / c.dt;
  const double n = std::round(q);
  c.every = n >= 1.0 && std::fabs(q - n) <= 1e-9 * q && n < 4294967295.0 ? static_cast<std::uint32_t>(n) : 0;
  return c;
}

std::uint32_t DecisionClock::completed(std::uint32_t step) const {
  if (per_step) return step;
  if (every != 0) return step / every;
  // Interval j ends at j T; a step ends at step dt. The tolerance keeps a step whose end
  // falls on a boundary within rounding (30 x 0.1 = 3.0000000000000004) in that interval.
  return static_cast<std::uint32_t>(std::floor(static_cast<double>(step) * dt / time * (1.0 + 1e-12)));
}

core::Decision DecisionClock::at(std::uint32_t step) const {
  if (per_step) return {true, true, 1, step};
  if (every != 0) {
    const std::uint32_t within = (step - 1) % every;  // steps before this one in its interval
    return {within == 0, within + 1 == every, within + 1, (step - 1) / every + 1};
  }
  const std::uint32_t before = completed(step - 1);
  std::uint32_t first = step;  // the interval's first step: the one after the last decision
  while (first > 1 && completed(first - 1) == completed(first - 2)) --first;
  return {first == step, completed(step) > before, step - first + 1, before + 1};
}

double mean_variance_exponential(double x) {
  if (x < 0.1) {  // the series 2 sum_n (-x)^n / (n + 2)!: no cancellation (closed form: 1e-14 at 0.1)
    double term = 2.0 / 2.0, sum = 0.0;  // n = 0: 2 / 2!
    for (int n = 0; n <= 10; ++n) {
      sum += term;
      term = -term * x / static_cast<double>(n + 3);
    }
    return sum;
  }
  return 2.0 * (x - 1.0 + core::pm::exp(-x)) / (x * x);
}

namespace {

// b'(z) for b(z) = (sin z - z cos z) / z^3, the ball's transform in units of its volume x 3 /
// (4 pi): the dipole's spectrum is z^2 b'(z)^2 at wave number z / r.
double ball_transform_slope(double z) {
  if (z < 0.1) return -z / 15.0 + z * z * z / 210.0;
  double s, c;
  core::pm::sincos(z, &s, &c);
  const double z2 = z * z;
  return (z2 * s - 3.0 * s + 3.0 * z * c) / (z2 * z2);
}

template <class F>
double simpson(F&& f, double a, double b, int intervals) {
  const double h = (b - a) / intervals;
  double sum = f(a) + f(b);
  for (int i = 1; i < intervals; ++i) sum += (i % 2 ? 4.0 : 2.0) * f(a + i * h);
  return sum * h / 3.0;
}

}  // namespace

double count_dipole_variance(const Scene& scene, double diffusion) {
  const DecisionClock clock = decision_clock(scene);
  if (clock.per_step || scene.guidance.noise != NoiseForm::kCount) return 1.0;
  const double r = scene.guidance.sensing_radius;
  return dipole_mean_variance(diffusion * clock.time / (r * r));
}

double dipole_mean_variance(double theta) {
  if (!(theta > 0.0)) return 1.0;
  // Cached: make_cues asks for every cue, and often.
  static std::mutex lock;
  static std::map<double, double> known;
  {
    const std::lock_guard<std::mutex> hold(lock);
    const auto it = known.find(theta);
    if (it != known.end()) return it->second;
  }
  // The dipole sum_j (x_j - x).u / r of Poisson molecules has the spectrum w(z) = z^2 b'(z)^2
  // (z = k r), each mode decaying at the rate D k^2; its mean over T keeps the fraction
  // mean_variance_exponential(z^2 theta) of each mode's variance. The integrals run to
  // z = 400 by Simpson's rule (25 points per period), beyond that on w's mean 1 / (2 z^2).
  constexpr double kZ = 400.0;
  constexpr int kIntervals = 16000, kTail = 400;
  auto w = [](double z) {
    const double b = ball_transform_slope(z);
    return z * z * b * b;
  };
  const double total = simpson(w, 0.0, kZ, kIntervals) + 0.5 / kZ;  // pi / 10 to 5e-6
  const double kept = simpson([&](double z) { return w(z) * mean_variance_exponential(z * z * theta); }, 0.0, kZ,
                              kIntervals) +
                      simpson([&](double u) { return u > 0.0 ? 0.5 * mean_variance_exponential(theta / (u * u)) : 0.0; },
                              0.0, 1.0 / kZ, kTail);
  const std::lock_guard<std::mutex> hold(lock);
  return known.emplace(theta, kept / total).first->second;
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
  p.decision_sign = scene.guidance.antithetic ? -1.0 : 1.0;
  const DecisionClock clock = decision_clock(scene);
  if (clock.per_step) return p;  // the report's instantaneous SNR
  const double t = clock.time;
  // The receptor forms: alpha is the gain of a decision over one time unit; over T the
  // readout's mean has the variance mean_variance_exponential(T / tau_r) of one reading.
  if (p.noise != NoiseForm::kCount) {
    const double tau = scene.guidance.receptor_time.value_or(p.noise == NoiseForm::kBinding ? 0.0 : HUGE_VAL);
    if (tau == 0.0) p.gain = p.gain * std::sqrt(t);  // Poisson events: the SNR grows as sqrt(T)
    else if (tau < HUGE_VAL)
      p.gain = p.gain * std::sqrt(mean_variance_exponential(1.0 / tau) / mean_variance_exponential(t / tau));
  }
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
  p.after_move = !decision_clock(scene).per_step && !p.signalling;
  return p;
}

}  // namespace axg

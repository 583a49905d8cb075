#pragma once
// The growth-cone signalling model (SPEC §3.7, docs/methods.md §2.10): the keys
// axons.growth_model and axons.signalling, the parameters' names, units and defaults
// (Bicknell, Pujic, Dayan & Goodhill 2018, Table 1), reading a value with its unit, and the
// conversion to the scene's units that core/signalling.hpp gets. Shared by every backend.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "axonguide/core/signalling.hpp"
#include "axonguide/core/types.hpp"

namespace axg {

struct Scene;
class ObjectReader;

// What a parameter is measured in. Counts are plain numbers; everything else is a string
// "<number> <unit>" with a unit of its dimension.
enum class SignalDim : std::uint8_t {
  kCount,        // molecules (receptor totals, the switch's total and constants)
  kRate,         // per time: "/s", "/min", "/h"
  kRatePerConc,  // per concentration per time: "/nM/min", "/pM/s", "/uM/h", ...
  kSpeed,        // length per time: "um/s", "um/min", "um/h"
};

struct SignalParameter {
  const char* name;     // the symbol of Table 1 (and of the authors' code)
  SignalDim dim;
  double value;         // Table 1, in the canonical unit of its dimension (/min, /nM/min, um/min)
  bool derived;         // null by default: derived from the others as in the paper
  bool may_be_zero;     // otherwise it must be > 0
  const char* meaning;
};

inline constexpr std::size_t kSignalParameters = 33;
extern const std::array<SignalParameter, kSignalParameters> kSignalTable;

// axons.growth_model, and axons.signalling: the model's cue, inhibition, sub-steps and the
// values given in the scene.
struct SignallingKeys {
  // A constant step length, or the growth-cone signalling network of Bicknell et al. 2018
  // (core/signalling.hpp), whose output sets each axon's extension.
  core::GrowthModel growth_model = core::GrowthModel::kConstant;
  struct Signalling {
    std::uint32_t cue = 0;       // the cue whose concentration drives the receptors
    bool population = true;      // inhibition: the population's mean (true) or the soma's own
    std::uint32_t substeps = 1;  // ROS2 steps per growth step
    std::uint32_t halvings = 10; // a failed sub-step is halved up to this often (core::kSignalHalvings)
    // Values given in the scene, in Table 1's units (per minute, per nM per minute, um per
    // minute, counts), by kSignalTable's index; nullopt: Table 1's (or derived).
    std::array<std::optional<double>, kSignalParameters> given{};
  } signalling;
};

void read_signalling_keys(ObjectReader& axons, SignallingKeys& keys);
// Written only for the signalling model (older scenes keep their canonical form).
void write_signalling_keys(const SignallingKeys& keys, nlohmann::json& axons);
// Physical units, a cue, no growth-rate modulation.
void check_signalling(const Scene& scene);

// The canonical unit of a dimension ("/min", "/nM/min", "um/min"; "" for counts).
const char* canonical_unit(SignalDim d);

// Reads one parameter's value as the scene gives it, in the canonical unit: a number for a
// count, "<number> <unit>" otherwise. Throws InputError naming `path` for a bare number
// where a unit is needed, a unit of another dimension, an unknown unit, a negative value, or
// zero where the parameter must be positive.
double read_signal_value(const nlohmann::json& v, const std::string& path, const SignalParameter& p);

// The canonical form of a value: a number for a count, "<value> <canonical unit>" otherwise.
nlohmann::json signal_value_json(double value, const SignalParameter& p);

// The model's parameters in the scene's units (time per units.time, concentration per
// units.concentration, lengths in um), given values or Table 1's, derived ones as in the
// paper: a4 = a2 / I_t, a5 = a3 / A_t kdegA / kr, b3 = b2 (K_A / K_I) a5 / a4.
core::SignallingParams signalling_params(const Scene& scene);

// The longest step any axon of the model can take in one step, length units: (r0 + kext
// (a0 + aF F_t) / b0) dt, since Gs <= G + Gs <= (a0 + aF F_t) / b0.
double signalling_max_step(const Scene& scene);

}  // namespace axg

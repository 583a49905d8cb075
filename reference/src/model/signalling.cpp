#include "axonguide/model/signalling.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string_view>

#include <fmt/format.h>

#include "axonguide/core/cues.hpp"
#include "axonguide/scene/reader.hpp"
#include "axonguide/scene/scene.hpp"
#include "axonguide/support/error.hpp"

namespace axg {

using nlohmann::json;

// Bicknell, Pujic, Dayan & Goodhill 2018, Table 1 (and the authors' Fig5AB.m), in minutes,
// nM and um. The order is the order of the canonical form.
const std::array<SignalParameter, kSignalParameters> kSignalTable{{
    {"At", SignalDim::kCount, 1000, false, false, "growth-cone receptors (A's total)"},
    {"It", SignalDim::kCount, 1000, false, false, "cell-body receptors (I's total)"},
    {"kpA", SignalDim::kRatePerConc, 1, false, false, "binding rate of the growth-cone receptors"},
    {"kmA", SignalDim::kRate, 0.1, false, false, "their unbinding rate (K_A = kmA / kpA = 0.1 nM)"},
    {"kpI", SignalDim::kRatePerConc, 0.01, false, false, "binding rate of the cell-body receptors"},
    {"kmI", SignalDim::kRate, 0.1, false, false, "their unbinding rate (K_I = kmI / kpI = 10 nM)"},
    {"kr", SignalDim::kRate, 0.0025, false, false, "transport of A's signal to the cell body"},
    {"kdegA", SignalDim::kRate, 0.005, false, false, "decay of A's transported signal Ac"},
    {"ka", SignalDim::kRate, 0.0025, false, false, "transport of I's signal to the growth cone"},
    {"kdegI", SignalDim::kRate, 0.005, false, false, "decay of I's transported signal Ic"},
    {"a2", SignalDim::kRate, 0.01, false, false, "production of X from Ac"},
    {"b2", SignalDim::kRate, 1, false, false, "removal of X"},
    {"a3", SignalDim::kRate, 0.01, false, false, "production of Y from I"},
    {"b3", SignalDim::kRate, 0.02, true, false, "removal of Y (derived: b2 (K_A / K_I) a5 / a4)"},
    {"a4", SignalDim::kRate, 1e-5, true, false, "production of Zx from Ac I, per molecule (derived: a2 / It)"},
    {"b4", SignalDim::kRate, 1e-5, false, false, "removal of Zx"},
    {"a5", SignalDim::kRate, 2e-5, true, false, "production of Zy from Ac I, per molecule (derived: a3 / At kdegA / kr)"},
    {"b5", SignalDim::kRate, 1e-5, false, false, "removal of Zy"},
    {"g1", SignalDim::kRate, 0.01, false, false, "annihilation of Zx with X, per molecule"},
    {"g2", SignalDim::kRate, 0.01, false, false, "annihilation of Zy with Y, per molecule"},
    {"Ft", SignalDim::kCount, 10, false, false, "the switch's total"},
    {"a6", SignalDim::kRate, 1, false, false, "the switch's activation by X"},
    {"b6", SignalDim::kRate, 1, false, false, "the switch's deactivation by Y"},
    {"kX", SignalDim::kCount, 1, false, false, "Michaelis constant of the activation"},
    {"kY", SignalDim::kCount, 1, false, false, "Michaelis constant of the deactivation"},
    {"a0", SignalDim::kRate, 0.1, false, true, "basal production of the growth state G (molecules per minute)"},
    {"aF", SignalDim::kRate, 0.06, false, true, "production of G per molecule of the switch's output F"},
    {"a1", SignalDim::kRate, 5e-6, false, true, "activation of G to Gs by A, per molecule"},
    {"b1", SignalDim::kRate, 2.5e-4, false, true, "deactivation of Gs by Ic, per molecule"},
    {"b0", SignalDim::kRate, 0.01, false, false, "decay of G and Gs"},
    {"a1b", SignalDim::kRate, 0, false, true,
     "NGF-independent activation of G to Gs (not in the paper: 0 is its model; docs/methods.md §2.10)"},
    {"r0", SignalDim::kSpeed, 0.05, false, true, "basal extension rate"},
    {"kext", SignalDim::kSpeed, 0.02, false, true, "extension rate per molecule of Gs"},
}};

namespace {

// Minutes per unit of time, and nM per unit of concentration.
double minutes_per(std::string_view t) {
  if (t == "s") return 1.0 / 60.0;
  if (t == "min") return 1.0;
  if (t == "h") return 60.0;
  return 0.0;
}
double nanomolar_per(std::string_view c) {
  if (c == "pM") return 1e-3;
  if (c == "nM") return 1.0;
  if (c == "uM") return 1e3;
  return 0.0;
}

[[noreturn]] void bad(const std::string& path, const json& v, const std::string& allowed) {
  std::string shown = v.dump();
  if (shown.size() > 60) shown = shown.substr(0, 57) + "...";
  throw InputError(fmt::format("scene: {} = {}: {}", path, shown, allowed), path, shown, allowed);
}

std::string example(const SignalParameter& p) {
  return fmt::format("\"{} {}\"", p.value, canonical_unit(p.dim));
}

}  // namespace

const char* canonical_unit(SignalDim d) {
  switch (d) {
    case SignalDim::kCount: return "";
    case SignalDim::kRate: return "/min";
    case SignalDim::kRatePerConc: return "/nM/min";
    case SignalDim::kSpeed: return "um/min";
  }
  return "";
}

double read_signal_value(const json& v, const std::string& path, const SignalParameter& p) {
  double value = 0;
  double factor = 1;  // to the canonical unit
  if (p.dim == SignalDim::kCount) {
    if (!v.is_number()) bad(path, v, "must be a number (a count of molecules, no unit)");
    value = v.get<double>();
  } else {
    if (v.is_number())
      bad(path, v, fmt::format("needs its unit: a string \"<number> <unit>\", e.g. {}", example(p)));
    if (!v.is_string()) bad(path, v, fmt::format("must be a string \"<number> <unit>\", e.g. {}", example(p)));
    const std::string text = v.get<std::string>();
    const std::size_t space = text.find(' ');
    if (space == std::string::npos || space == 0)
      bad(path, v, fmt::format("must be \"<number> <unit>\" with one space, e.g. {}", example(p)));
    const std::string number = text.substr(0, space), unit = text.substr(space + 1);
    char* end = nullptr;
    errno = 0;
    value = std::strtod(number.c_str(), &end);
    if (end != number.c_str() + number.size() || errno == ERANGE || !std::isfinite(value))
      bad(path, v, fmt::format("\"{}\" is not a finite number", number));
    // Units of this dimension: /T, /C/T, um/T for T in s, min, h and C in pM, nM, uM.
    std::string_view u = unit, t;
    double per_conc = 1;
    bool ok = false;
    switch (p.dim) {
      case SignalDim::kRate:
        if (u.size() > 1 && u[0] == '/') t = u.substr(1), ok = minutes_per(t) > 0;
        if (ok) factor = 1.0 / minutes_per(t);
        break;
      case SignalDim::kRatePerConc:
        if (u.size() > 4 && u[0] == '/' && u[3] == '/') {
          const std::string_view c = u.substr(1, 2);
          t = u.substr(4);
          ok = nanomolar_per(c) > 0 && minutes_per(t) > 0;
          if (ok) per_conc = 1.0 / nanomolar_per(c), factor = per_conc / minutes_per(t);
        }
        break;
      case SignalDim::kSpeed:
        if (u.size() > 3 && u.substr(0, 3) == "um/") t = u.substr(3), ok = minutes_per(t) > 0;
        if (ok) factor = 1.0 / minutes_per(t);
        break;
      case SignalDim::kCount: break;
    }
    if (!ok) {
      const char* allowed = p.dim == SignalDim::kRate          ? "/s, /min or /h (per time)"
                            : p.dim == SignalDim::kRatePerConc ? "/pM, /nM or /uM, then /s, /min or /h (per "
                                                                 "concentration per time), e.g. /nM/min"
                                                               : "um/s, um/min or um/h (length per time)";
      bad(path, v, fmt::format("unit \"{}\" is not one of {}", unit, allowed));
    }
    value = value * factor;
  }
  if (value < 0.0) bad(path, v, "must not be negative (a rate constant, total or Michaelis constant)");
  if (value == 0.0 && !p.may_be_zero) bad(path, v, "must be > 0");
  if (!std::isfinite(value)) bad(path, v, "must be finite in " + std::string(canonical_unit(p.dim)));
  return value;
}

json signal_value_json(double value, const SignalParameter& p) {
  if (p.dim == SignalDim::kCount) return value;
  return fmt::format("{} {}", value, canonical_unit(p.dim));
}

void read_signalling_keys(ObjectReader& r, SignallingKeys& a) {
  r.choice("growth_model", a.growth_model, {{"constant", GrowthModel::kConstant}, {"signalling", GrowthModel::kSignalling}});
  const json* sg = r.take("signalling");
  if (!sg) return;
  ObjectReader rr(*sg, "axons.signalling");
  auto& q = a.signalling;
  rr.integer("cue", q.cue, 0, static_cast<std::uint64_t>(core::kMaxCues - 1));
  rr.choice("inhibition", q.population, {{"population", true}, {"soma", false}});
  rr.integer("substeps", q.substeps, 1, 100000);
  rr.integer("halvings", q.halvings, 0, 20);
  for (std::size_t k = 0; k < kSignalParameters; ++k) {
    const SignalParameter& p = kSignalTable[k];
    if (const json* v = rr.take(p.name)) {
      if (v->is_null() && p.derived) q.given[k].reset();
      else q.given[k] = read_signal_value(*v, rr.path(p.name), p);
    }
  }
  rr.finish();
}

void write_signalling_keys(const SignallingKeys& a, json& j) {
  if (a.growth_model != GrowthModel::kSignalling) return;
  const auto& q = a.signalling;
  j["growth_model"] = name_of(a.growth_model);
  json sg = {{"cue", q.cue}, {"inhibition", q.population ? "population" : "soma"}, {"substeps", q.substeps}};
  if (q.halvings != static_cast<std::uint32_t>(core::kSignalHalvings)) sg["halvings"] = q.halvings;
  for (std::size_t k = 0; k < kSignalParameters; ++k) {
    const SignalParameter& p = kSignalTable[k];
    if (q.given[k]) sg[p.name] = signal_value_json(*q.given[k], p);
    else sg[p.name] = p.derived ? json(nullptr) : signal_value_json(p.value, p);
  }
  j["signalling"] = sg;
}

void check_signalling(const Scene& s) {
  if (!s.signalling()) return;
  const auto& u = s.units;
  if (u.length != "um" || u.time == "step" || u.concentration == "CU")
    throw InputError(fmt::format(
        "scene: axons.growth_model = \"signalling\" needs physical units (units.length \"um\", units.time \"s\", "
        "\"min\" or \"h\", units.concentration \"pM\", \"nM\" or \"uM\"): its rate constants are per time and per "
        "concentration; the scene has {}",
        u.describe()));
  if (s.axons.growth_modulation > 0.0)
    throw InputError(fmt::format(
        "scene: axons.growth_modulation = {} with axons.growth_model = \"signalling\": both would set the step length; "
        "the signalling model sets it, so growth_modulation must be 0",
        s.axons.growth_modulation));
  if (s.source_count() == 0)
    throw InputError("scene: axons.growth_model = \"signalling\" needs a cue source (cues.sources or "
                     "cues.random_sources): its receptors read the concentration of cue axons.signalling.cue");
  if (s.axons.signalling.cue >= s.source_count())
    throw InputError(fmt::format("scene: axons.signalling.cue = {}: the scene has {} cue source(s), numbered 0 to {} in "
                                 "the canonical order",
                                 s.axons.signalling.cue, s.source_count(), s.source_count() - 1));
}

core::SignallingParams signalling_params(const Scene& scene) {
  const auto& given = scene.axons.signalling.given;
  auto get = [&](const char* name) {
    for (std::size_t k = 0; k < kSignalParameters; ++k)
      if (std::string_view(kSignalTable[k].name) == name) return given[k] ? *given[k] : kSignalTable[k].value;
    throw std::logic_error(std::string("signalling parameter ") + name);
  };
  auto is_given = [&](const char* name) {
    for (std::size_t k = 0; k < kSignalParameters; ++k)
      if (std::string_view(kSignalTable[k].name) == name) return given[k].has_value();
    return false;
  };
  core::SignallingParams q{};
  q.At = get("At"), q.It = get("It");
  q.kpA = get("kpA"), q.kmA = get("kmA"), q.kpI = get("kpI"), q.kmI = get("kmI");
  q.kr = get("kr"), q.kdegA = get("kdegA"), q.ka = get("ka"), q.kdegI = get("kdegI");
  q.a2 = get("a2"), q.b2 = get("b2"), q.a3 = get("a3"), q.b4 = get("b4"), q.b5 = get("b5");
  q.g1 = get("g1"), q.g2 = get("g2");
  q.a4 = is_given("a4") ? get("a4") : q.a2 / q.It;
  q.a5 = is_given("a5") ? get("a5") : q.a3 / q.At * q.kdegA / q.kr;
  q.b3 = is_given("b3") ? get("b3") : q.b2 * ((q.kmA / q.kpA) / (q.kmI / q.kpI)) * q.a5 / q.a4;
  q.Ft = get("Ft"), q.a6 = get("a6"), q.b6 = get("b6"), q.kX = get("kX"), q.kY = get("kY");
  q.a0 = get("a0"), q.aF = get("aF"), q.a1 = get("a1"), q.b1 = get("b1"), q.b0 = get("b0"), q.a1b = get("a1b");
  q.r0 = get("r0"), q.kext = get("kext");
  // To the scene's units: per minute -> per time unit, per nM -> per concentration unit.
  const double t = minutes_per(scene.units.time), c = nanomolar_per(scene.units.concentration);
  for (double* r : {&q.kmA, &q.kmI, &q.kr, &q.kdegA, &q.ka, &q.kdegI, &q.a2, &q.b2, &q.a3, &q.b3, &q.a4, &q.b4,
                    &q.a5, &q.b5, &q.g1, &q.g2, &q.a6, &q.b6, &q.a0, &q.aF, &q.a1, &q.b1, &q.b0, &q.a1b, &q.r0, &q.kext})
    *r = *r * t;
  q.kpA = q.kpA * c * t;
  q.kpI = q.kpI * c * t;
  return q;
}

double signalling_max_step(const Scene& scene) {
  const core::SignallingParams q = signalling_params(scene);
  return (q.r0 + q.kext * (q.a0 + q.aF * q.Ft) / q.b0) * scene.dt;
}

}  // namespace axg

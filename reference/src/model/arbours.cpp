#include "axonguide/model/arbours.hpp"
#include "axonguide/model/steering.hpp"

#include <cmath>

#include <fmt/format.h>

#include "axonguide/core/pmath.hpp"
#include "axonguide/scene/reader.hpp"
#include "axonguide/scene/scene.hpp"
#include "axonguide/support/error.hpp"

namespace axg {

using nlohmann::json;

ArbourKeys::ArbourKeys() {
  dendrites.stems = {1.0};  // no dendrites unless asked for
  dendrites.diameter = 2.0;
}

const std::vector<NeuriteKey>& neurite_key_table() {
  static const std::vector<NeuriteKey> table{
      {"B", &NeuriteKeys::b, nullptr, non_negative(), "1", true},
      {"E", &NeuriteKeys::e, nullptr, non_negative(), "1", true},
      {"S", &NeuriteKeys::s, nullptr, {}, "1", true},
      {"tau", nullptr, &NeuriteKeys::tau, positive(), "time units; null: infinite", true},
      {"period", nullptr, &NeuriteKeys::period, positive(), "time units; null: steps x dt", false},
      {"v0", &NeuriteKeys::v0, nullptr, non_negative(), "length units per time unit", true},
      {"F", &NeuriteKeys::f, nullptr, non_negative(), "1", true},
      {"rate_cv", &NeuriteKeys::rate_cv, nullptr, non_negative(), "1", true},
      {"angle", &NeuriteKeys::angle, nullptr, {0.0, core::kPi, true, true}, "rad", false},
      {"angle_sd", &NeuriteKeys::angle_sd, nullptr, non_negative(), "rad", false},
      {"persistence_length", nullptr, &NeuriteKeys::persistence_length, positive(), "length units; null: straight",
       false},
      {"diameter", &NeuriteKeys::diameter, nullptr, positive(), "um", false},
      {"taper", &NeuriteKeys::taper, nullptr, {0.0, 1.0, true, false}, "1", false},
      {"stems", nullptr, nullptr, {}, "P(k stems at birth), k = 0, 1, ...", false},
      {"stem_rate", &NeuriteKeys::stem_rate, nullptr, non_negative(), "per time unit", true},
      {"lateral_rate", &NeuriteKeys::lateral_rate, nullptr, non_negative(), "per length unit per time unit", false}};
  return table;
}

namespace {

constexpr std::size_t kMaxStemCount = 64;

void read_stems(ObjectReader& r, std::vector<double>& out) {
  const json* v = r.take("stems");
  if (!v) return;
  const std::string path = r.path("stems");
  const char* what = "must be a distribution of the stem count at birth: [P(0), P(1), ...], 1 to 64 non-negative "
                     "numbers that sum to 1";
  if (!v->is_array() || v->empty() || v->size() > kMaxStemCount) fail_key(path, *v, what);
  out.clear();
  double sum = 0.0;
  for (std::size_t k = 0; k < v->size(); ++k) {
    const json& x = (*v)[k];
    if (!x.is_number() || !std::isfinite(x.get<double>()) || x.get<double>() < 0.0)
      fail_key(fmt::format("{}[{}]", path, k), x, what);
    out.push_back(x.get<double>());
    sum += x.get<double>();
  }
  if (!(std::fabs(sum - 1.0) <= 1e-9)) fail_key(path, *v, fmt::format("{} (these sum to {})", what, sum));
}

void read_neurite(const json& j, const std::string& path, NeuriteKeys& n) {
  ObjectReader r(j, path);
  for (const NeuriteKey& k : neurite_key_table()) {
    if (k.number) {
      r.number(k.name, n.*k.number, k.range);
    } else if (k.optional) {
      if (const json* t = r.take(k.name)) {
        if (!t->is_null()) n.*k.optional = ObjectReader::read_number(*t, r.path(k.name), k.range);
        else (n.*k.optional).reset();
      }
    } else {
      read_stems(r, n.stems);
    }
  }
  r.finish();
}

json write_neurite(const NeuriteKeys& n) {
  json j = json::object();
  for (const NeuriteKey& k : neurite_key_table()) {
    if (k.number) j[k.name] = n.*k.number;
    else if (k.optional) j[k.name] = n.*k.optional ? json(*(n.*k.optional)) : json(nullptr);
    else j[k.name] = n.stems;
  }
  return j;
}

NeuriteParams neurite_params(const NeuriteKeys& k, const Scene& s, bool planar) {
  NeuriteParams p;
  p.branching.b_inf = k.b;
  p.branching.e = k.e;
  p.branching.s = k.s;
  p.branching.tau = k.tau.value_or(0.0);
  p.branching.period = k.period.value_or(static_cast<double>(s.steps) * s.dt);
  p.elongation.v0 = k.v0;
  p.elongation.f = k.f;
  p.geometry.planar = planar;
  p.geometry.wander = k.persistence_length.has_value();
  p.geometry.inv_persistence = k.persistence_length ? 1.0 / *k.persistence_length : 0.0;
  p.geometry.angle_mean = k.angle;
  p.geometry.angle_sd = k.angle_sd;
  p.geometry.rate_sigma = k.rate_cv == 0.0 ? 0.0 : std::sqrt(core::pm::log1p(k.rate_cv * k.rate_cv));
  double c = 0.0;
  for (const double q : k.stems) p.stems_cdf.push_back(c += q);
  p.stem_rate = k.stem_rate;
  p.lateral_rate = k.lateral_rate;
  p.diameter = k.diameter;
  p.taper = k.taper;
  return p;
}

}  // namespace

void read_arbour_keys(const json& j, std::optional<ArbourKeys>& out) {
  if (j.is_null()) {
    out.reset();
    return;
  }
  ArbourKeys a;
  ObjectReader r(j, "arbours");
  r.number("sample_length", a.sample_length, non_negative());
  r.number("slab", a.slab, non_negative());
  r.choice("soma_contact", a.stop_at_soma, {{"stop", true}, {"pass", false}});
  if (const json* x = r.take("axon")) read_neurite(*x, "arbours.axon", a.axon);
  if (const json* x = r.take("dendrites")) read_neurite(*x, "arbours.dendrites", a.dendrites);
  r.finish();
  out = a;
}

json write_arbour_keys(const ArbourKeys& a) {
  return {{"sample_length", a.sample_length},
          {"slab", a.slab},
          {"soma_contact", a.stop_at_soma ? "stop" : "pass"},
          {"axon", write_neurite(a.axon)},
          {"dendrites", write_neurite(a.dendrites)}};
}

void check_arbours(const Scene& s) {
  if (!s.arbours) return;
  if (s.signalling())
    throw InputError(
        "scene: arbours with the signalling growth model: an arbour's cones elongate by the BESTL rule "
        "(arbours.*.v0, F), and the signalling cone's own growth rate is not built for them (docs/methods.md §2.12); "
        "use the constant growth model");
  if (modulates_growth(s))
    fail_key("axons.growth_modulation", s.axons.growth_modulation,
             "0 in an arbour scene: an arbour's cones elongate by the BESTL rule (arbours.*.v0, F), which growth-rate "
             "modulation is not built for");
  if (s.arbours->slab > 0.0 && s.neurons.shape != RegionShape::kDisc)
    fail_key("arbours.slab", s.arbours->slab,
             "a growth layer belongs to a culture: neurons.region.shape \"disc\" (or slab 0)");
}

ArbourParams arbour_params(const Scene& s) {
  ArbourParams p;
  if (!s.arbours) return p;
  p.planar = s.neurons.shape == RegionShape::kDisc;
  p.slab = s.arbours->slab;
  p.sample_length = s.arbours->sample_length;
  p.stop_at_soma = s.arbours->stop_at_soma;
  p.axon = neurite_params(s.arbours->axon, s, p.planar);
  p.dendrites = neurite_params(s.arbours->dendrites, s, p.planar);
  return p;
}

int draw_count(const std::vector<double>& cdf, double u) {
  for (std::size_t k = 0; k < cdf.size(); ++k)
    if (u < cdf[k]) return static_cast<int>(k);
  return static_cast<int>(cdf.size()) - 1;
}

}  // namespace axg

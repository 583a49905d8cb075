#include "axonguide/scene/scene.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <initializer_list>
#include <set>
#include <tuple>
#include <utility>

#include <fmt/format.h>

#include "axonguide/core/cues.hpp"
#include "axonguide/model/cue_setup.hpp"
#include "axonguide/support/error.hpp"
#include "axonguide/scene/json_input.hpp"
#include "axonguide/model/signalling_setup.hpp"

namespace axg {

using nlohmann::json;

namespace {

constexpr std::size_t kMaxSceneBytes = 16u << 20;  // a scene is a few KiB; 16 MiB is abuse
constexpr int kMaxNesting = 32;                     // the format needs 5 levels

std::string show(const json& v) {
  std::string s = v.dump();
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  return s;
}

std::string join_path(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

[[noreturn]] void fail(const std::string& path, const json& value, const std::string& allowed) {
  throw InputError(fmt::format("scene: {} = {}: {}", path, show(value), allowed), path, show(value), allowed);
}

// An allowed numeric interval, printed the way a user reads it.
struct Range {
  double lo = -HUGE_VAL, hi = HUGE_VAL;
  bool lo_open = false, hi_open = false;
  std::string text() const {
    const bool has_lo = lo != -HUGE_VAL, has_hi = hi != HUGE_VAL;
    if (has_lo && has_hi)
      return fmt::format("must be in {}{}, {}{}", lo_open ? '(' : '[', lo, hi, hi_open ? ')' : ']');
    if (has_lo) return fmt::format("must be {} {}", lo_open ? ">" : ">=", lo);
    if (has_hi) return fmt::format("must be {} {}", hi_open ? "<" : "<=", hi);
    return "must be a finite number";
  }
  bool contains(double v) const {
    if (lo_open ? !(v > lo) : !(v >= lo)) return false;
    if (hi_open ? !(v < hi) : !(v <= hi)) return false;
    return true;
  }
};
Range positive() { return {0, HUGE_VAL, true, false}; }
Range non_negative() { return {0, HUGE_VAL, false, false}; }
Range closed(double lo, double hi) { return {lo, hi, false, false}; }

// Reads one JSON object, remembering which keys were consumed so that unknown keys
// can be reported with the list of allowed ones.
class ObjectReader {
 public:
  ObjectReader(const json& j, std::string path) : j_(j), path_(std::move(path)) {
    if (!j_.is_object()) fail(path_.empty() ? "(scene)" : path_, j_, "must be a JSON object");
  }

  const json* take(const char* key) {
    bool seen = false;
    for (const char* k : allowed_) seen = seen || std::strcmp(k, key) == 0;
    if (!seen) allowed_.push_back(key);
    auto it = j_.find(key);
    return it == j_.end() ? nullptr : &*it;
  }
  std::string path(const char* key) const { return join_path(path_, key); }

  void number(const char* key, double& out, Range range) {
    if (const json* v = take(key)) out = read_number(*v, path(key), range);
  }
  void optional_number(const char* key, std::optional<double>& out, Range range) {
    if (const json* v = take(key)) {
      if (v->is_null()) out.reset();
      else out = read_number(*v, path(key), range);
    }
  }
  template <class Int>
  void integer(const char* key, Int& out, std::uint64_t lo, std::uint64_t hi) {
    if (const json* v = take(key)) out = static_cast<Int>(read_integer(*v, path(key), lo, hi));
  }
  void boolean(const char* key, bool& out) {
    if (const json* v = take(key)) {
      if (!v->is_boolean()) fail(path(key), *v, "must be true or false");
      out = v->get<bool>();
    }
  }
  template <class E>
  void choice(const char* key, E& out, std::initializer_list<std::pair<const char*, E>> names) {
    const json* v = take(key);
    if (!v) return;
    std::string allowed;
    for (auto& [name, value] : names) {
      if (v->is_string() && v->get<std::string>() == name) {
        out = value;
        return;
      }
      allowed += fmt::format("{}\"{}\"", allowed.empty() ? "" : ", ", name);
    }
    fail(path(key), *v, "must be one of " + allowed);
  }

  // Reports the first key that was never taken.
  void finish() const {
    for (auto it = j_.begin(); it != j_.end(); ++it) {
      bool known = false;
      for (const char* k : allowed_) known = known || it.key() == k;
      if (!known) {
        std::string list;
        for (const char* k : allowed_) list += fmt::format("{}{}", list.empty() ? "" : ", ", k);
        throw InputError(fmt::format("scene: unknown key {} (allowed here: {})", join_path(path_, it.key()), list),
                         join_path(path_, it.key()), show(it.value()), "one of the keys " + list);
      }
    }
  }

  static double read_number(const json& v, const std::string& path, Range range) {
    if (!v.is_number()) fail(path, v, "must be a number; " + range.text());
    double x = v.get<double>();
    if (!std::isfinite(x)) fail(path, v, "must be finite; " + range.text());
    if (!range.contains(x)) fail(path, v, range.text());
    return x;
  }
  // Integers are compared exactly (a 64-bit seed does not fit a double); a float is
  // accepted when it is integral, so that 1e6 means 1000000.
  static std::uint64_t read_integer(const json& v, const std::string& path, std::uint64_t lo,
                                    std::uint64_t hi) {
    const std::string allowed = fmt::format("must be an integer in [{}, {}]", lo, hi);
    if (v.is_number_unsigned()) {
      std::uint64_t x = v.get<std::uint64_t>();
      if (x < lo || x > hi) fail(path, v, allowed);
      return x;
    }
    if (v.is_number_integer()) {  // negative (non-negative ones are number_unsigned)
      fail(path, v, allowed);
    }
    if (!v.is_number_float()) fail(path, v, allowed);
    double x = v.get<double>();
    if (!std::isfinite(x) || x != std::floor(x) || x < static_cast<double>(lo) ||
        x > static_cast<double>(hi) || x >= 18446744073709551616.0)
      fail(path, v, allowed);
    return static_cast<std::uint64_t>(x);
  }

 private:
  const json& j_;
  std::string path_;
  std::vector<const char*> allowed_;
};

core::Vec3 read_position(const json& v, const std::string& path) {
  if (!v.is_array() || v.size() != 3) fail(path, v, "must be [x, y, z] or null");
  double c[3];
  // + 0.0 turns -0 into +0: one position, one canonical form and one sort key.
  for (int k = 0; k < 3; ++k)
    c[k] = ObjectReader::read_number(v[k], fmt::format("{}[{}]", path, k), Range{}) + 0.0;
  return {c[0], c[1], c[2]};
}

void read_source_common(ObjectReader& r, double& emission, double& diffusion, double& decay,
                        double& kd) {
  // Particles per step; 2^31 keeps every per-step count and particle id exact.
  r.number("emission", emission, closed(0, 2147483648.0));
  r.number("diffusion", diffusion, positive());
  r.number("decay", decay, non_negative());
  r.number("kd", kd, positive());
}

Source read_source(const json& j, const std::string& path) {
  Source s;
  ObjectReader r(j, path);
  r.choice("kind", s.kind, {{"attractant", CueKind::kAttractant}, {"repellent", CueKind::kRepellent}});
  if (const json* p = r.take("position")) {
    if (p->is_null()) s.position.reset();
    else s.position = read_position(*p, r.path("position"));
  }
  read_source_common(r, s.emission, s.diffusion, s.decay, s.kd);
  r.number("min_concentration", s.min_concentration, non_negative());
  r.number("max_concentration", s.max_concentration, positive());
  r.finish();
  if (s.min_concentration > s.max_concentration)
    throw InputError(fmt::format(
        "scene: {}.min_concentration = {} is above {}.max_concentration = {}: min must be <= max",
        path, s.min_concentration, path, s.max_concentration));
  return s;
}

void read_scene(const json& root, Scene& s) {
  ObjectReader top(root, "");
  top.integer("seed", s.seed, 0, UINT64_MAX);
  top.integer("steps", s.steps, 0, 1000000000);
  top.number("dt", s.dt, positive());
  if (const json* j = top.take("units")) {
    ObjectReader r(*j, "units");
    r.choice("length", s.units.length, {{"LU", std::string("LU")}, {"um", std::string("um")}});
    r.choice("time", s.units.time, {{"step", std::string("step")}, {"s", std::string("s")},
                                    {"min", std::string("min")}, {"h", std::string("h")}});
    r.choice("concentration", s.units.concentration,
             {{"CU", std::string("CU")}, {"pM", std::string("pM")}, {"nM", std::string("nM")}, {"uM", std::string("uM")}});
    r.finish();
  }
  // The default persistence length follows the declared length unit.
  s.axons.persistence_length = kDefaultPersistenceUm / s.units.micrometres();

  if (const json* j = top.take("neurons")) {
    ObjectReader r(*j, "neurons");
    auto& n = s.neurons;
    r.integer("count", n.count, 1, std::uint64_t{1} << 53);
    r.number("soma_radius", n.soma_radius, positive());
    if (const json* g = r.take("region")) {
      ObjectReader rr(*g, "neurons.region");
      rr.choice("shape", n.shape, {{"ball", RegionShape::kBall}, {"sphere", RegionShape::kSphere},
                                   {"box", RegionShape::kBox}});
      rr.number("radius", n.radius, positive());
      rr.finish();
    }
    r.choice("sampler", n.sampler, {{"rejection", Sampler::kRejection}, {"normal", Sampler::kNormal},
                                    {"trig", Sampler::kTrig}, {"coordinate", Sampler::kCoordinate}});
    r.choice("overlap", n.overlap_reject, {{"reject", true}, {"allow", false}});
    r.integer("max_attempts", n.max_attempts, 1, 1000000000);
    r.choice("heading", n.radial_heading, {{"random", false}, {"radial", true}});
    if (const json* pops = r.take("populations")) {
      if (!pops->is_array() || pops->empty() || pops->size() > 64)
        fail("neurons.populations", *pops, "must be an array of 1 to 64 objects {count, center, radius}");
      std::uint64_t total = 0;
      for (std::size_t k = 0; k < pops->size(); ++k) {
        const std::string path = fmt::format("neurons.populations[{}]", k);
        ObjectReader pr((*pops)[k], path);
        Population p;
        pr.integer("count", p.count, 1, std::uint64_t{1} << 53);
        if (const json* c = pr.take("center")) p.center = read_position(*c, pr.path("center"));
        pr.number("radius", p.radius, positive());
        pr.finish();
        total += p.count;
        n.populations.push_back(p);
      }
      if (total > (std::uint64_t{1} << 53))
        fail("neurons.populations", *pops, "the counts must sum to at most 2^53");
      if (r.take("count") && n.count != total)
        throw InputError(fmt::format(
            "scene: neurons.count = {} but neurons.populations sum to {}: give one, or make them agree", n.count,
            total));
      n.count = total;
    }
    r.finish();
  }

  if (const json* j = top.take("axons")) {
    ObjectReader r(*j, "axons");
    auto& a = s.axons;
    std::optional<double> step_length = a.step_length;
    const bool step_length_given = r.take("step_length") != nullptr;
    r.optional_number("step_length", step_length, positive());
    r.optional_number("growth_speed", a.growth_speed, positive());
    if (a.growth_speed) {
      if (step_length_given && step_length)
        throw InputError(fmt::format(
            "scene: axons.step_length = {} and axons.growth_speed = {} are both given: give one (the step length is "
            "growth_speed x dt)",
            *step_length, *a.growth_speed));
      a.step_length = *a.growth_speed * s.dt;
      if (!(a.step_length > 0.0) || !std::isfinite(a.step_length))
        fail("axons.growth_speed", *a.growth_speed, fmt::format("growth_speed x dt = {} must be a positive finite step length", a.step_length));
    } else if (!step_length) {
      fail("axons.step_length", nullptr, "must be a positive number (null only when axons.growth_speed is given)");
    } else {
      a.step_length = *step_length;
    }
    r.number("contact_distance", a.contact_distance, non_negative());
    r.choice("contact", a.contact, {{"swept", ContactRule::kSwept}, {"endpoint", ContactRule::kEndpoint}});
    r.optional_number("bounds_radius", a.bounds_radius, positive());
    r.optional_number("persistence_length", a.persistence_length, positive());
    r.number("growth_modulation", a.growth_modulation, {0, 1, false, true});
    r.choice("growth_model", a.growth_model, {{"constant", GrowthModel::kConstant}, {"signalling", GrowthModel::kSignalling}});
    if (const json* sg = r.take("signalling")) {
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
    r.finish();
  }

  if (const json* j = top.take("guidance")) {
    ObjectReader r(*j, "guidance");
    auto& g = s.guidance;
    r.choice("model", g.model, {{"direct", GuidanceModel::kDirect}, {"snr", GuidanceModel::kSnr},
                                {"vector_sum", GuidanceModel::kVectorSum},
                                {"source_vector_sum", GuidanceModel::kSourceVectorSum}});
    r.choice("noise", g.noise, {{"binding", NoiseForm::kBinding}, {"snapshot", NoiseForm::kSnapshot},
                                {"count", NoiseForm::kCount}});
    r.number("turn_angle", g.turn_angle, {0, 3.141592653589793, false, false});
    r.number("gain", g.gain, non_negative());
    r.number("vector_weight", g.vector_weight, non_negative());
    r.number("growth_cone_width", g.growth_cone_width, positive());
    r.number("sensing_radius", g.sensing_radius, positive());
    r.finish();
  }

  if (const json* j = top.take("cues")) {
    ObjectReader r(*j, "cues");
    auto& c = s.cues;
    bool amount_given = false;
    r.choice("field", c.field, {{"particles", FieldKind::kParticles}, {"grid", FieldKind::kGrid},
                                {"analytic", FieldKind::kAnalytic}, {"imposed", FieldKind::kImposed}});
    r.integer("warmup_steps", c.warmup_steps, 0, 1000000);
    if (const json* src = r.take("sources")) {
      if (!src->is_array()) fail("cues.sources", *src, "must be an array of source objects");
      c.sources.clear();
      for (std::size_t k = 0; k < src->size(); ++k)
        c.sources.push_back(read_source((*src)[k], fmt::format("cues.sources[{}]", k)));
    }
    if (const json* rs = r.take("random_sources")) {
      ObjectReader rr(*rs, "cues.random_sources");
      auto& q = c.random_sources;
      rr.integer("count", q.count, 0, 1000000);
      rr.number("attractant_fraction", q.attractant_fraction, closed(0, 1));
      read_source_common(rr, q.emission, q.diffusion, q.decay, q.kd);
      rr.finish();
    }
    r.optional_number("molecule_amount", c.molecule_amount, positive());
    if (const json* p = r.take("particles")) {
      ObjectReader rr(*p, "cues.particles");
      auto& q = c.particles;
      amount_given = rr.take("amount") != nullptr;
      rr.number("amount", q.amount, positive());
      rr.boolean("molecules", q.molecules);
      if (const json* e = rr.take("estimate")) {
        ObjectReader er(*e, "cues.particles.estimate");
        er.optional_number("spacing", q.estimate.spacing, positive());
        er.optional_number("time", q.estimate.time, non_negative());
        er.finish();
      }
      rr.choice("motion", q.motion, {{"brownian", Motion::kBrownian}, {"ballistic", Motion::kBallistic}});
      rr.boolean("collisions", q.collisions);
      rr.number("speed", q.speed, non_negative());
      rr.number("damping", q.damping, closed(0, 1));
      rr.number("radius", q.radius, positive());
      rr.number("stiffness", q.stiffness, closed(0, 1));
      rr.finish();
    }
    if (const json* g = r.take("grid")) {
      ObjectReader rr(*g, "cues.grid");
      auto& q = c.grid;
      rr.optional_number("spacing", q.spacing, positive());
      rr.choice("scheme", q.scheme, {{"explicit", GridScheme::kExplicit}, {"implicit", GridScheme::kImplicit}});
      rr.choice("boundary", q.boundary, {{"absorbing", GridBoundary::kAbsorbing},
                                         {"reflecting", GridBoundary::kReflecting}});
      rr.boolean("allow_substeps", q.allow_substeps);
      if (const json* m = rr.take("substeps")) {
        if (m->is_null()) q.substeps.reset();
        else q.substeps = static_cast<std::uint32_t>(ObjectReader::read_integer(*m, rr.path("substeps"), 1, 1000000));
      }
      rr.finish();
    }
    if (c.molecule_amount && s.units.length == "um" && s.units.concentration != "CU")
      throw InputError(fmt::format(
          "scene: cues.molecule_amount = {}: the scene declares physical units ({}), which fix one molecule at {:.6g} "
          "{} um^3; remove the key (it is for scenes without physical length or concentration units)",
          *c.molecule_amount, s.units.describe(), s.molecule_amount_from_units(), s.units.concentration));
    if (c.particles.molecules) {
      const double m = s.molecule_amount();
      if (amount_given && c.particles.amount != m)
        throw InputError(fmt::format(
            "scene: cues.particles.amount = {} with cues.particles.molecules = true: a molecule-resolved particle is "
            "one molecule, {:.6g} (concentration x length^3 in this scene's units); remove the amount or make it equal",
            c.particles.amount, m));
      c.particles.amount = m;
    }
    if (const json* g = r.take("imposed")) {
      ObjectReader rr(*g, "cues.imposed");
      auto& q = c.imposed;
      rr.choice("profile", q.profile, {{"linear", ImposedProfile::kLinear}, {"exponential", ImposedProfile::kExponential}});
      if (const json* d = rr.take("direction")) {
        const core::Vec3 v = read_position(*d, "cues.imposed.direction");
        const double n = core::norm(v);
        if (!(n > 0.0) || !(n < HUGE_VAL)) fail("cues.imposed.direction", *d, "must be a non-zero finite vector [x, y, z]");
        q.direction = v;  // as written (the canonical form reads back unchanged); normalised where used
      }
      // Up to +100 % per reference length for a linear profile, and far more for an
      // exponential one; 0 is the no-gradient control.
      rr.number("steepness", q.steepness, closed(0, 1e6));
      rr.number("reference_length", q.reference_length, positive());
      rr.number("concentration", q.concentration, positive());
      rr.finish();
    }
    r.finish();
  }

  if (const json* j = top.take("analysis")) {
    ObjectReader r(*j, "analysis");
    if (const json* b = r.take("bfs_sources")) {
      if (!b->is_array()) fail("analysis.bfs_sources", *b, "must be an array of neuron ids");
      s.analysis.bfs_sources.clear();
      for (std::size_t k = 0; k < b->size(); ++k)
        s.analysis.bfs_sources.push_back(static_cast<std::uint64_t>(ObjectReader::read_integer(
            (*b)[k], fmt::format("analysis.bfs_sources[{}]", k), 0, std::uint64_t{1} << 53)));
    }
    r.boolean("components", s.analysis.components);
    r.finish();
  }

  if (const json* j = top.take("output")) {
    ObjectReader r(*j, "output");
    r.boolean("paths", s.output.paths);
    r.integer("stats_every", s.output.stats_every, 1, 1000000000);
    r.boolean("vtk", s.output.vtk);
    r.integer("frames_every", s.output.frames_every, 1, 1000000000);
    r.integer("checkpoint_every", s.output.checkpoint_every, 0, 1000000000);
    r.optional_number("checkpoint_seconds", s.output.checkpoint_seconds, non_negative());
    r.boolean("swc", s.output.swc);
    r.boolean("sonata", s.output.sonata);
    r.boolean("csv", s.output.csv);
    if (const json* v = r.take("graphml")) {
      if (v->is_null()) s.output.graphml.reset();
      else if (v->is_boolean()) s.output.graphml = v->get<bool>();
      else fail(r.path("graphml"), *v, fmt::format("must be true, false or null (null: written up to {} neurons)",
                                                    Scene::kGraphmlAutoLimit));
    }
    r.optional_number("conduction_speed", s.output.conduction_speed, positive());
    r.finish();
    if (!s.output.csv && !s.output.sonata)
      throw InputError("scene: output.csv = false: no file would hold the neurons and connections; set "
                       "output.sonata = true (SONATA's nodes.h5 and edges.h5 then hold them), or keep the CSV");
  }
  top.finish();
}

// Checks that involve more than one key.
void check_consistency(const Scene& s, std::vector<std::string>& warnings, bool cues_given) {
  const auto& n = s.neurons;
  if (n.soma_radius >= n.radius)
    throw InputError(fmt::format(
        "scene: neurons.soma_radius = {} is not below neurons.region.radius = {}: somas must fit in the region",
        n.soma_radius, n.radius));
  if (!n.populations.empty() && n.shape == RegionShape::kSphere)
    throw InputError("scene: neurons.populations need neurons.region.shape \"ball\" or \"box\" (populations are balls "
                     "inside the region; it is \"sphere\")");
  for (std::size_t k = 0; k < n.populations.size(); ++k) {
    const Population& p = n.populations[k];
    const core::Vec3 c = p.center;
    const double reach = n.shape == RegionShape::kBox
                             ? std::max({std::fabs(c.x), std::fabs(c.y), std::fabs(c.z)}) + p.radius
                             : std::sqrt(core::norm2(c)) + p.radius;
    if (reach > n.radius)
      throw InputError(fmt::format(
          "scene: neurons.populations[{}]: the ball of radius {} at [{}, {}, {}] reaches {} from the origin, outside "
          "neurons.region.radius = {}: populations must lie inside the region",
          k, p.radius, c.x, c.y, c.z, reach, n.radius));
    if (n.soma_radius >= p.radius)
      throw InputError(fmt::format(
          "scene: neurons.populations[{}].radius = {} is not above neurons.soma_radius = {}", k, p.radius,
          n.soma_radius));
  }
  for (std::size_t k = 0; k < s.analysis.bfs_sources.size(); ++k)
    if (s.analysis.bfs_sources[k] >= n.count)
      throw InputError(fmt::format(
          "scene: analysis.bfs_sources[{}] = {}: must be a neuron id below neurons.count = {}", k,
          s.analysis.bfs_sources[k], n.count));
  if (s.axons.growth_modulation > 0.0 && s.guidance.model != GuidanceModel::kSnr)
    throw InputError(fmt::format(
        "scene: axons.growth_modulation = {}: growth-rate modulation responds to the SNR evidence and needs "
        "guidance.model = \"snr\" (it is \"{}\")",
        s.axons.growth_modulation, name_of(s.guidance.model)));
  if (s.signalling()) {
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
  if (s.guidance.model == GuidanceModel::kDirect && !s.signalling()) {
    if (cues_given) warnings.push_back("guidance.model is \"direct\": the cues section is ignored");
    return;
  }
  if (s.source_count() > static_cast<std::size_t>(core::kMaxCues))
    throw InputError(fmt::format(
        "scene: cues.sources has {} and cues.random_sources.count {}: at most {} cue sources in all",
        s.cues.sources.size(), s.cues.random_sources.count, core::kMaxCues));
  const double rb = s.bounds_radius();
  for (std::size_t k = 0; k < s.cues.sources.size(); ++k) {
    const auto& p = s.cues.sources[k].position;
    if (!p) continue;
    const bool inside = n.shape == RegionShape::kBox
                            ? std::fabs(p->x) <= rb && std::fabs(p->y) <= rb && std::fabs(p->z) <= rb
                            : core::norm(*p) <= rb;
    if (!inside)
      throw InputError(fmt::format(
          "scene: cues.sources[{}].position = [{}, {}, {}]: must lie inside the domain ({} of {} {})",
          k, p->x, p->y, p->z, n.shape == RegionShape::kBox ? "box" : "ball",
          n.shape == RegionShape::kBox ? "half-edge" : "radius", rb));
  }
  if (s.cues.field == FieldKind::kParticles && s.estimate_spacing() >= rb)
    throw InputError(fmt::format(
        "scene: cues.particles.estimate.spacing = {}: must be below the domain radius {} (the estimate's mesh needs "
        "cells)",
        s.estimate_spacing(), rb));
  if (s.cues.particles.molecules && s.cues.field != FieldKind::kParticles)
    warnings.push_back(fmt::format("cues.particles.molecules is true but cues.field is \"{}\": it applies to the "
                                   "particle field only and is ignored",
                                   name_of(s.cues.field)));
  if (s.cues.field == FieldKind::kGrid && s.grid_spacing() >= rb)
    throw InputError(fmt::format(
        "scene: cues.grid.spacing = {}: must be below the domain radius {} (the grid needs cells)",
        s.grid_spacing(), rb));
}

}  // namespace

std::vector<Source> canonical_sources(std::vector<Source> sources) {
  auto key = [](const Source& s) {
    const core::Vec3 p = s.position.value_or(core::Vec3{0.0, 0.0, 0.0});
    return std::make_tuple(static_cast<int>(s.kind), s.position.has_value(), p.x, p.y, p.z, s.emission, s.diffusion,
                           s.decay, s.kd, s.min_concentration, s.max_concentration);
  };
  std::stable_sort(sources.begin(), sources.end(), [&](const Source& a, const Source& b) { return key(a) < key(b); });
  return sources;
}

namespace {

ParseResult parse_scene_unescaped(const std::string& text, const std::string& origin) {
  const json root = parse_json_strict(text, origin, kMaxNesting);
  ParseResult result;
  read_scene(root, result.scene);
  // Warn about ignored cues only when the user set some (the canonical form always has them).
  const bool cues_set = root.is_object() && root.contains("cues") &&
                        scene_to_json(result.scene)["cues"] != scene_to_json(Scene{})["cues"];
  check_consistency(result.scene, result.warnings, cues_set);  // messages name the file's source indices
  result.scene.cues.sources = canonical_sources(result.scene.cues.sources);
  // Resolving the cues checks what needs their positions (an imposed linear profile must
  // stay non-negative over the domain).
  if (result.scene.uses_cues() && result.scene.cues.field == FieldKind::kImposed) (void)make_cues(result.scene);
  resolve_output_dependencies(result.scene, result.warnings);
  return result;
}

}  // namespace

// Messages quote keys and values from the file: they are escaped once, here.
ParseResult parse_scene(const std::string& text, const std::string& origin) {
  try {
    return parse_scene_unescaped(text, origin);
  } catch (const InputError& e) {
    throw InputError(printable(e.what()), printable(e.key()), printable(e.value()), printable(e.allowed()));
  }
}

void resolve_output_dependencies(Scene& scene, std::vector<std::string>& warnings) {
  if (scene.output.vtk && !scene.output.paths) {
    scene.output.paths = true;
    warnings.push_back("output.vtk draws the axons' paths: output.paths is enabled");
  }
  if (scene.output.swc && !scene.output.paths) {
    scene.output.paths = true;
    warnings.push_back("output.swc writes the axons' paths: output.paths is enabled");
  }
}

ParseResult load_scene_file(const std::string& path) {
  return parse_scene(read_input_file(path, "scene file", kMaxSceneBytes), path);
}

const char* name_of(RegionShape v) {
  switch (v) {
    case RegionShape::kBall: return "ball";
    case RegionShape::kSphere: return "sphere";
    case RegionShape::kBox: return "box";
  }
  return "?";
}
const char* name_of(Sampler v) {
  switch (v) {
    case Sampler::kRejection: return "rejection";
    case Sampler::kNormal: return "normal";
    case Sampler::kTrig: return "trig";
    case Sampler::kCoordinate: return "coordinate";
  }
  return "?";
}
const char* name_of(ContactRule v) { return v == ContactRule::kSwept ? "swept" : "endpoint"; }
const char* name_of(GuidanceModel v) {
  switch (v) {
    case GuidanceModel::kDirect: return "direct";
    case GuidanceModel::kSnr: return "snr";
    case GuidanceModel::kVectorSum: return "vector_sum";
    case GuidanceModel::kSourceVectorSum: return "source_vector_sum";
  }
  return "?";
}
const char* name_of(FieldKind v) {
  switch (v) {
    case FieldKind::kParticles: return "particles";
    case FieldKind::kGrid: return "grid";
    case FieldKind::kAnalytic: return "analytic";
    case FieldKind::kImposed: return "imposed";
  }
  return "?";
}
const char* name_of(NoiseForm v) {
  switch (v) {
    case NoiseForm::kBinding: return "binding";
    case NoiseForm::kSnapshot: return "snapshot";
    case NoiseForm::kCount: return "count";
  }
  return "?";
}
const char* name_of(ImposedProfile v) { return v == ImposedProfile::kLinear ? "linear" : "exponential"; }
const char* name_of(GrowthModel v) { return v == GrowthModel::kConstant ? "constant" : "signalling"; }

double Scene::grid_spacing() const {
  if (cues.grid.spacing) return *cues.grid.spacing;
  double lambda = HUGE_VAL;
  for (const Source& src : cues.sources)
    if (src.decay > 0) lambda = std::min(lambda, std::sqrt(src.diffusion / src.decay));
  if (cues.random_sources.count > 0 && cues.random_sources.decay > 0)
    lambda = std::min(lambda, std::sqrt(cues.random_sources.diffusion / cues.random_sources.decay));
  return std::min({guidance.sensing_radius, lambda / kGridPointsPerLambda, 0.25 * bounds_radius()});
}

double Scene::molecule_amount() const { return cues.molecule_amount ? *cues.molecule_amount : molecule_amount_from_units(); }

double Scene::molecule_amount_from_units() const {
  // One molecule is 1 / 0.602214076 nM um^3 (1 nM = 6.02214076e14 per litre, a litre
  // 10^15 um^3); in the scene's units, with CU read as nM and LU as kMicrometresPerLu um.
  const double nm_per_unit = units.concentration == "pM" ? 1e-3 : (units.concentration == "uM" ? 1e3 : 1.0);
  const double um = units.micrometres();
  return 1.0 / 0.602214076 / nm_per_unit / (um * um * um);
}

std::string Units::describe() const {
  return fmt::format("length {}, time {}, concentration {}", length, time, concentration);
}
const char* name_of(CueKind v) { return v == CueKind::kAttractant ? "attractant" : "repellent"; }
const char* name_of(Motion v) { return v == Motion::kBrownian ? "brownian" : "ballistic"; }
const char* name_of(GridScheme v) { return v == GridScheme::kExplicit ? "explicit" : "implicit"; }
const char* name_of(GridBoundary v) { return v == GridBoundary::kAbsorbing ? "absorbing" : "reflecting"; }
const char* name_of(core::AxonStatus v) {
  switch (v) {
    case core::AxonStatus::kGrowing: return "growing";
    case core::AxonStatus::kConnected: return "connected";
    case core::AxonStatus::kExited: return "exited";
    case core::AxonStatus::kMaxSteps: return "max_steps";
  }
  return "?";
}

json scene_to_json(const Scene& s) {
  auto source_json = [](const Source& src) {
    json j;
    j["kind"] = name_of(src.kind);
    j["position"] = src.position ? json::array({src.position->x, src.position->y, src.position->z})
                                 : json(nullptr);
    j["emission"] = src.emission;
    j["diffusion"] = src.diffusion;
    j["decay"] = src.decay;
    j["kd"] = src.kd;
    j["min_concentration"] = src.min_concentration;
    j["max_concentration"] = src.max_concentration;
    return j;
  };
  json j;
  j["seed"] = s.seed;
  j["steps"] = s.steps;
  j["dt"] = s.dt;
  j["units"] = {{"length", s.units.length}, {"time", s.units.time}, {"concentration", s.units.concentration}};
  const auto& n = s.neurons;
  j["neurons"] = {{"count", n.count},
                  {"soma_radius", n.soma_radius},
                  {"region", {{"shape", name_of(n.shape)}, {"radius", n.radius}}},
                  {"sampler", name_of(n.sampler)},
                  {"overlap", n.overlap_reject ? "reject" : "allow"},
                  {"max_attempts", n.max_attempts}};
  if (n.radial_heading) j["neurons"]["heading"] = "radial";  // only when given (older scenes keep their bytes)
  if (!n.populations.empty()) {  // written only when given, so that older scenes keep their bytes
    json pops = json::array();
    for (const Population& p : n.populations)
      pops.push_back({{"count", p.count}, {"center", json::array({p.center.x, p.center.y, p.center.z})},
                      {"radius", p.radius}});
    j["neurons"]["populations"] = pops;
  }
  const auto& a = s.axons;
  j["axons"] = {{"step_length", a.growth_speed ? json(nullptr) : json(a.step_length)},
                {"growth_speed", a.growth_speed ? json(*a.growth_speed) : json(nullptr)},
                {"persistence_length", a.persistence_length ? json(*a.persistence_length) : json(nullptr)},
                {"growth_modulation", a.growth_modulation},
                {"contact_distance", a.contact_distance},
                {"contact", name_of(a.contact)},
                {"bounds_radius", a.bounds_radius ? json(*a.bounds_radius) : json(nullptr)}};
  const auto& g = s.guidance;
  j["guidance"] = {{"model", name_of(g.model)},          {"noise", name_of(g.noise)},
                   {"turn_angle", g.turn_angle},
                   {"gain", g.gain},                      {"vector_weight", g.vector_weight},
                   {"growth_cone_width", g.growth_cone_width}, {"sensing_radius", g.sensing_radius}};
  const auto& c = s.cues;
  json sources = json::array();
  for (const auto& src : canonical_sources(c.sources)) sources.push_back(source_json(src));
  const auto& rs = c.random_sources;
  j["cues"] = {{"field", name_of(c.field)},
               {"warmup_steps", c.warmup_steps},
               {"sources", sources},
               {"random_sources", {{"count", rs.count}, {"attractant_fraction", rs.attractant_fraction},
                                   {"emission", rs.emission}, {"diffusion", rs.diffusion},
                                   {"decay", rs.decay}, {"kd", rs.kd}}},
               {"particles", {{"amount", c.particles.amount},
                              {"motion", name_of(c.particles.motion)},
                              {"collisions", c.particles.collisions}, {"speed", c.particles.speed},
                              {"damping", c.particles.damping}, {"radius", c.particles.radius},
                              {"stiffness", c.particles.stiffness}}},
               {"grid", {{"spacing", c.grid.spacing ? json(*c.grid.spacing) : json(nullptr)}, {"scheme", name_of(c.grid.scheme)},
                         {"boundary", name_of(c.grid.boundary)},
                         {"allow_substeps", c.grid.allow_substeps}}},
               {"imposed", {{"profile", name_of(c.imposed.profile)},
                            {"direction", json::array({c.imposed.direction.x, c.imposed.direction.y, c.imposed.direction.z})},
                            {"steepness", c.imposed.steepness}, {"reference_length", c.imposed.reference_length},
                            {"concentration", c.imposed.concentration}}}};
  j["analysis"] = {{"bfs_sources", s.analysis.bfs_sources}, {"components", s.analysis.components}};
  j["output"] = {{"paths", s.output.paths}, {"stats_every", s.output.stats_every},
                 {"vtk", s.output.vtk}, {"frames_every", s.output.frames_every}};
  // Written only when given, so the bytes of older scenes (and their hashes) stay.
  if (s.output.checkpoint_every != 0) j["output"]["checkpoint_every"] = s.output.checkpoint_every;
  if (s.output.checkpoint_seconds) j["output"]["checkpoint_seconds"] = *s.output.checkpoint_seconds;
  // Keys added after the golden networks were blessed appear only when set, so that a
  // scene that does not use them keeps its canonical form (and hash).
  if (s.output.swc) j["output"]["swc"] = true;
  if (s.output.sonata) j["output"]["sonata"] = true;
  if (!s.output.csv) j["output"]["csv"] = false;
  if (s.output.graphml) j["output"]["graphml"] = *s.output.graphml;
  if (s.output.conduction_speed) j["output"]["conduction_speed"] = *s.output.conduction_speed;
  if (c.molecule_amount) j["cues"]["molecule_amount"] = *c.molecule_amount;
  if (c.particles.molecules) j["cues"]["particles"]["molecules"] = true;
  if (c.particles.estimate.spacing) j["cues"]["particles"]["estimate"]["spacing"] = *c.particles.estimate.spacing;
  if (c.particles.estimate.time) j["cues"]["particles"]["estimate"]["time"] = *c.particles.estimate.time;
  if (c.grid.substeps) j["cues"]["grid"]["substeps"] = *c.grid.substeps;
  if (s.signalling()) {
    const auto& q = s.axons.signalling;
    j["axons"]["growth_model"] = name_of(s.axons.growth_model);
    json sg = {{"cue", q.cue}, {"inhibition", q.population ? "population" : "soma"}, {"substeps", q.substeps}};
    if (q.halvings != static_cast<std::uint32_t>(core::kSignalHalvings)) sg["halvings"] = q.halvings;
    for (std::size_t k = 0; k < kSignalParameters; ++k) {
      const SignalParameter& p = kSignalTable[k];
      if (q.given[k]) sg[p.name] = signal_value_json(*q.given[k], p);
      else sg[p.name] = p.derived ? json(nullptr) : signal_value_json(p.value, p);
    }
    j["axons"]["signalling"] = sg;
  }
  return j;
}

Scene Scene::builtin_default() {
  // The main job: 1000 neurons in a ball of radius 5.386 LU, two attractant and two
  // repellent sources at sampled positions, the particle field and SNR steering. Somas of
  // radius 0.1 LU (packing fraction 0.0064) let axons travel about 9 LU before they meet
  // a soma, and 50 warm-up steps establish the fields first, so that guidance shapes the
  // network: docs/methods.md §12.6 gives the margin against `model: direct`.
  Scene s;
  s.neurons.count = 1000;
  s.neurons.radius = 5.3860;  // 2.5 * 10^(1/3)
  s.neurons.soma_radius = 0.1;
  s.guidance.model = GuidanceModel::kSnr;
  s.cues.field = FieldKind::kParticles;
  s.cues.warmup_steps = 50;
  for (CueKind kind : {CueKind::kAttractant, CueKind::kRepellent, CueKind::kAttractant, CueKind::kRepellent}) {
    Source src;
    src.kind = kind;
    s.cues.sources.push_back(src);
  }
  return s;
}

}  // namespace axg

#include "axonguide/scene/scene.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <initializer_list>
#include <set>
#include <tuple>
#include <utility>

#include <fmt/format.h>

#include "axonguide/scene/json_input.hpp"
#include "axonguide/scene/reader.hpp"
#include "axonguide/support/error.hpp"

namespace axg {

using nlohmann::json;

namespace {

constexpr std::size_t kMaxSceneBytes = 16u << 20;  // a scene is a few KiB; 16 MiB is abuse
constexpr int kMaxNesting = 32;                     // the format needs 5 levels

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
  s.axons.persistence_length = default_persistence_length(s.units);

  if (const json* j = top.take("neurons")) {
    ObjectReader r(*j, "neurons");
    auto& n = s.neurons;
    r.integer("count", n.count, 1, std::uint64_t{1} << 53);
    r.number("soma_radius", n.soma_radius, positive());
    if (const json* g = r.take("region")) {
      ObjectReader rr(*g, "neurons.region");
      rr.choice("shape", n.shape, {{"ball", RegionShape::kBall}, {"sphere", RegionShape::kSphere},
                                   {"box", RegionShape::kBox}, {"disc", RegionShape::kDisc}});
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
        fail_key("neurons.populations", *pops, "must be an array of 1 to 64 objects {count, center, radius}");
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
        fail_key("neurons.populations", *pops, "the counts must sum to at most 2^53");
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
    read_growth_keys(r, s.axons, s.dt);
    read_wander_keys(r, s.axons);
    read_modulation_keys(r, s.axons);
    read_signalling_keys(r, s.axons);
    r.finish();
  }

  if (const json* j = top.take("guidance")) {
    ObjectReader r(*j, "guidance");
    read_steering_keys(r, s.guidance);
    read_sensing_keys(r, s.guidance);
    r.finish();
  }

  if (const json* j = top.take("cues")) {
    ObjectReader r(*j, "cues");
    read_cue_keys(r, s.cues);
    read_molecule_keys(r, s.cues);
    bool amount_given = false;
    if (const json* p = r.take("particles")) {
      ObjectReader rr(*p, "cues.particles");
      amount_given = read_particle_keys(rr, s.cues.particles);
      rr.finish();
    }
    read_grid_keys(r, s.cues.grid);
    check_molecule_amount(s);
    resolve_molecules(s, amount_given);
    read_imposed_keys(r, s.cues.imposed);
    r.finish();
  }

  if (const json* j = top.take("arbours")) read_arbour_keys(*j, s.arbours);
  if (const json* j = top.take("synapses")) read_synapse_keys(*j, s.synapses);

  if (const json* j = top.take("analysis")) {
    ObjectReader r(*j, "analysis");
    if (const json* b = r.take("bfs_sources")) {
      if (!b->is_array()) fail_key("analysis.bfs_sources", *b, "must be an array of neuron ids");
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
      else fail_key(r.path("graphml"), *v, fmt::format("must be true, false or null (null: written up to {} neurons)",
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
  if (n.shape == RegionShape::kDisc && n.sampler != Sampler::kRejection)
    throw InputError(fmt::format("scene: neurons.sampler = \"{}\": a disc is sampled by rejection only",
                                 name_of(n.sampler)));
  if (n.shape == RegionShape::kDisc && !n.populations.empty())
    throw InputError("scene: neurons.populations need neurons.region.shape \"ball\" or \"box\" (it is \"disc\")");
  check_arbours(s);
  check_synapses(s);
  check_steering(s);
  check_signalling(s);
  if (s.guidance.model == GuidanceModel::kDirect && !s.signalling()) {
    if (cues_given) warnings.push_back("guidance.model is \"direct\": the cues section is ignored");
    return;
  }
  check_cues(s);
  check_estimate(s);
  check_particles(s, warnings);
  check_grid_spacing(s);
}

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
  if (scene.output.vtk && !scene.output.paths && !scene.arbours) {
    scene.output.paths = true;
    warnings.push_back("output.vtk draws the axons' paths: output.paths is enabled");
  }
  if (scene.output.swc && !scene.output.paths && !scene.arbours) {
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
    case RegionShape::kDisc: return "disc";
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
  // Each component writes its keys into the section that holds them. Keys added after the
  // golden networks were blessed appear only when set, so that a scene that does not use
  // them keeps its canonical form (and hash).
  json& axons = j["axons"];
  write_growth_keys(s.axons, axons);
  write_wander_keys(s.axons, axons);
  write_modulation_keys(s.axons, axons);
  write_signalling_keys(s.axons, axons);
  json& guidance = j["guidance"];
  write_steering_keys(s.guidance, guidance);
  write_sensing_keys(s.guidance, guidance);
  json& cues = j["cues"];
  write_cue_keys(s.cues, cues);
  write_molecule_keys(s.cues, cues);
  write_particle_keys(s.cues.particles, cues["particles"]);
  write_grid_keys(s.cues.grid, cues);
  if (s.arbours) j["arbours"] = write_arbour_keys(*s.arbours);  // only when given: older scenes keep their bytes
  if (s.synapses) j["synapses"] = write_synapse_keys(*s.synapses);
  j["analysis"] = {{"bfs_sources", s.analysis.bfs_sources}, {"components", s.analysis.components}};
  j["output"] = {{"paths", s.output.paths}, {"stats_every", s.output.stats_every},
                 {"vtk", s.output.vtk}, {"frames_every", s.output.frames_every}};
  // Written only when given, so the bytes of older scenes (and their hashes) stay.
  if (s.output.checkpoint_every != 0) j["output"]["checkpoint_every"] = s.output.checkpoint_every;
  if (s.output.checkpoint_seconds) j["output"]["checkpoint_seconds"] = *s.output.checkpoint_seconds;
  if (s.output.swc) j["output"]["swc"] = true;
  if (s.output.sonata) j["output"]["sonata"] = true;
  if (!s.output.csv) j["output"]["csv"] = false;
  if (s.output.graphml) j["output"]["graphml"] = *s.output.graphml;
  if (s.output.conduction_speed) j["output"]["conduction_speed"] = *s.output.conduction_speed;
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

#pragma once
// The scene: every input of a run (SPEC §5). Parsed strictly from JSON: every key is
// optional and has a default, unknown keys are errors, values are range-checked, and a
// bad scene raises InputError naming the key path, the value and what is allowed. Each
// model component's keys, their reading, canonical form and translation into the core
// functions' parameters live in that component's room (model/*.hpp; docs/methods.md §1);
// the scene composes them in the JSON sections that hold them (axons, guidance, cues).
#include <array>
#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "axonguide/core/types.hpp"
#include "axonguide/core/vec3.hpp"
#include "axonguide/model/arbours.hpp"
#include "axonguide/model/synapses.hpp"
#include "axonguide/model/cues.hpp"
#include "axonguide/model/estimate.hpp"
#include "axonguide/model/growth.hpp"
#include "axonguide/model/particles.hpp"
#include "axonguide/model/sensing.hpp"
#include "axonguide/model/signalling.hpp"
#include "axonguide/model/stencil.hpp"
#include "axonguide/model/steering.hpp"
#include "axonguide/model/wander.hpp"
#include "axonguide/scene/units.hpp"

namespace axg {

using core::ContactRule;
using core::CueKind;
using core::FieldKind;
using core::GridBoundary;
using core::GridScheme;
using core::GuidanceModel;
using core::ImposedProfile;
using core::Motion;
using core::NoiseForm;
using core::ParticleSensing;
using core::GrowthModel;
using core::RegionShape;
using core::Sampler;

// A ball of somas inside the region (an explant, a target tissue); populations take
// consecutive neuron ids in the order listed (SPEC §3.1).
struct Population {
  std::uint64_t count = 1;
  core::Vec3 center{0.0, 0.0, 0.0};
  double radius = 1.0;
};

struct Scene {
  std::uint64_t seed = 1;
  std::uint32_t steps = 100;
  double dt = 1.0;  // time units per step
  Units units;

  struct Neurons {
    std::uint64_t count = 1000;
    double soma_radius = 0.25;
    RegionShape shape = RegionShape::kBall;
    double radius = 5.0;  // ball/sphere radius, or the half-edge of a box
    Sampler sampler = Sampler::kRejection;
    bool overlap_reject = true;
    std::uint32_t max_attempts = 1000;
    // Initial axon headings: drawn by the sampler (false), or radial, away from the
    // population's centre through the soma (true; an explant's outgrowth).
    bool radial_heading = false;
    // Empty: one population filling the region. Otherwise count is their sum and each
    // neuron is drawn in its population's ball (the region still bounds the axons).
    std::vector<Population> populations;
    // The population of neuron `id` (0 without populations).
    std::size_t population_of(std::uint64_t id) const {
      std::uint64_t end = 0;
      for (std::size_t p = 0; p < populations.size(); ++p)
        if (id < (end += populations[p].count)) return p;
      return 0;
    }
  } neurons;

  // axons: the growth step, wandering, growth-rate modulation and the signalling model.
  struct Axons : GrowthKeys, WanderKeys, ModulationKeys, SignallingKeys {
  } axons;

  // guidance: the decision (steering) and what the growth cone senses.
  struct Guidance : SteeringKeys, SensingKeys {
  } guidance;

  // cues: the sources and their field; the particle field (and its estimate) and the grid.
  struct Cues : CueKeys, MoleculeKeys {
    ParticleKeys particles;
    GridKeys grid;
  } cues;

  // arbours (SPEC §3.8): branching axons and dendrites; nullopt: one unbranched axon per
  // neuron (the report's model).
  std::optional<ArbourKeys> arbours;
  // synapses (SPEC §3.9): appositions where axons pass dendrites, on the final arbours;
  // nullopt: none (an arbour scene's connections are then its axons' soma contacts).
  std::optional<SynapseKeys> synapses;

  struct Analysis {
    std::vector<std::uint64_t> bfs_sources{0};
    bool components = true;
  } analysis;

  struct Output {
    bool paths = false;
    std::uint32_t stats_every = 1;
    bool vtk = false;
    std::uint32_t frames_every = 10;
    // Checkpoints of `axonguide run` (SPEC §4): after every checkpoint_every-th step (0:
    // none), and after any step that ends checkpoint_seconds of wall-clock time since the
    // last one (0: none; 600 s when not given).
    std::uint32_t checkpoint_every = 0;
    std::optional<double> checkpoint_seconds;
    double checkpoint_interval() const { return checkpoint_seconds.value_or(600.0); }
    bool swc = false;     // morphologies/<id>.swc: the soma and the axon's path (needs paths)
    bool sonata = false;  // network/: SONATA nodes.h5, edges.h5, type tables, circuit_config.json
    // neurons.csv and connections.csv; false (with sonata) leaves the network to SONATA
    // alone, the format for large networks (2.2 GB of CSV at 10^7 neurons).
    bool csv = true;
    // graph.graphml: true, false, or nullopt = written up to kGraphmlAutoLimit neurons.
    std::optional<bool> graphml;
    // Axonal conduction speed for the SONATA edges' delays, m/s (= mm/ms); nullopt: 0.5.
    std::optional<double> conduction_speed;
    double conduction_m_per_s() const { return conduction_speed.value_or(kDefaultConductionSpeed); }
  } output;

  // Above this many neurons graph.graphml (about 390 bytes of XML per neuron) is written
  // only when output.graphml is true; SONATA is the format for large networks.
  static constexpr std::uint64_t kGraphmlAutoLimit = 100000;
  static constexpr double kDefaultConductionSpeed = 0.5;
  bool writes_graphml() const { return output.graphml.value_or(neurons.count <= kGraphmlAutoLimit); }

  // Derived quantities.
  double bounds_radius() const { return axons.bounds_radius.value_or(neurons.radius); }
  // m, concentration units x length^3 per molecule (cues.molecule_amount or the units;
  // model/sensing.cpp).
  double molecule_amount() const;
  bool signalling() const { return axons.growth_model == GrowthModel::kSignalling; }
  // Cue fields exist for steering, or for the signalling model's receptors.
  bool uses_cues() const { return guidance.model != GuidanceModel::kDirect || signalling(); }
  std::size_t source_count() const {
    return uses_cues() ? cues.sources.size() + cues.random_sources.count : 0;
  }

  // The built-in scene `axonguide run` uses without a scene file.
  static Scene builtin_default();
};

// Warnings collected while parsing (e.g. cues ignored under direct guidance).
struct ParseResult {
  Scene scene;
  std::vector<std::string> warnings;
};

// Parses scene text; throws InputError. `origin` names the source in messages.
ParseResult parse_scene(const std::string& text, const std::string& origin);
// Reads and parses a scene file; throws InputError for missing, unreadable, directory,
// oversized or malformed files.
ParseResult load_scene_file(const std::string& path);
// output.vtk draws axon paths, so it turns output.paths on (with a warning).
void resolve_output_dependencies(Scene& scene, std::vector<std::string>& warnings);

// The canonical form: every key, defaults filled in, keys sorted, sources in canonical order.
nlohmann::json scene_to_json(const Scene& scene);

// Names of enumerations as written in scenes.
const char* name_of(RegionShape v);
const char* name_of(Sampler v);
const char* name_of(ContactRule v);
const char* name_of(GuidanceModel v);
const char* name_of(FieldKind v);
const char* name_of(CueKind v);
const char* name_of(Motion v);
const char* name_of(GridScheme v);
const char* name_of(GridBoundary v);
const char* name_of(NoiseForm v);
const char* name_of(ImposedProfile v);
const char* name_of(GrowthModel v);
const char* name_of(core::AxonStatus v);

}  // namespace axg

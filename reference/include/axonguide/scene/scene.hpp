#pragma once
// The scene: every input of a run (SPEC §5). Parsed strictly from JSON: every key is
// optional and has a default, unknown keys are errors, values are range-checked, and a
// bad scene raises InputError naming the key path, the value and what is allowed.
#include <array>
#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "axonguide/core/types.hpp"
#include "axonguide/core/vec3.hpp"

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

// Physical units a scene may declare (SPEC §3.3). They name what the numbers mean; the
// model is the same in any consistent set. Without them: length units (LU), steps, and
// concentration units (CU: amount per LU^3).
// The report's length unit read as micrometres: its soma radius 0.25 LU as 10 um.
inline constexpr double kMicrometresPerLu = 40.0;

struct Units {
  std::string length = "LU";         // "LU" or "um"
  std::string time = "step";         // "step", "s", "min" or "h"
  std::string concentration = "CU";  // "CU", "pM", "nM" or "uM"
  bool declared() const { return length != "LU" || time != "step" || concentration != "CU"; }
  // "length um, time min, concentration nM"
  std::string describe() const;
  // Micrometres per length unit, for the formats that fix micrometres (SWC, SONATA).
  double micrometres() const { return length == "um" ? 1.0 : kMicrometresPerLu; }
};

// Katz 1985 (J Neurosci 5:589): axons in culture hold a nearly constant orientation over
// hundreds of micrometres. Default persistence length in um, and in LU with the report's
// soma radius 0.25 LU read as 10 um (kMicrometresPerLu).
inline constexpr double kDefaultPersistenceUm = 250.0;

struct Source {
  CueKind kind = CueKind::kAttractant;
  std::optional<core::Vec3> position;  // nullopt: sampled inside the region
  double emission = 1000;              // particles per step (a x emission: concentration x volume per step)
  double diffusion = 0.05;             // D, length^2 per time unit
  double decay = 0.05;                 // k, per time unit
  double kd = 1.0;                     // K_d, concentration units
  double min_concentration = 0.0;
  double max_concentration = 1e300;
};

struct RandomSources {
  std::uint32_t count = 0;
  double attractant_fraction = 0.5;
  double emission = 1000;
  double diffusion = 0.05;
  double decay = 0.05;
  double kd = 1.0;
};

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

  struct Axons {
    double step_length = 0.35;           // length units per step (growth_speed dt when that is given)
    std::optional<double> growth_speed;  // length units per time unit; nullopt: step_length rules
    double contact_distance = 0.05;
    ContactRule contact = ContactRule::kSwept;
    std::optional<double> bounds_radius;  // nullopt: the region's radius
    // L_p of the heading's random walk, length units; nullopt: no wandering.
    std::optional<double> persistence_length = kDefaultPersistenceUm / kMicrometresPerLu;
    double growth_modulation = 0.0;  // m in [0, 1): step length l0 (1 + m z / (1 + |z|)); 0: off
    // The growth model: a constant step length, or the growth-cone signalling network of
    // Bicknell et al. 2018 (core/signalling.hpp), whose output sets each axon's extension.
    GrowthModel growth_model = GrowthModel::kConstant;
    struct Signalling {
      std::uint32_t cue = 0;       // the cue whose concentration drives the receptors
      bool population = true;      // inhibition: the population's mean (true) or the soma's own
      std::uint32_t substeps = 1;  // ROS2 steps per growth step
      std::uint32_t halvings = 10; // a failed sub-step is halved up to this often (core::kSignalHalvings)
      // Values given in the scene, in Table 1's units (per minute, per nM per minute, um
      // per minute, counts), by kSignalTable's index; nullopt: Table 1's (or derived).
      std::array<std::optional<double>, 33> given{};
    } signalling;
  } axons;

  struct Guidance {
    GuidanceModel model = GuidanceModel::kSnr;
    NoiseForm noise = NoiseForm::kCount;
    double turn_angle = 0.10471975511965977;  // pi/30
    double gain = 250;                         // alpha
    double vector_weight = 0.1;                // beta
    double growth_cone_width = 0.1;            // w, LU
    double sensing_radius = 0.5;               // r, LU
  } guidance;

  struct Cues {
    FieldKind field = FieldKind::kParticles;
    // Steps the cue fields advance before growth starts (a pre-established gradient, as
    // in an assay); growth step s is field step warmup_steps + s.
    std::uint32_t warmup_steps = 0;
    std::vector<Source> sources;
    RandomSources random_sources;
    // m: concentration units x length^3 of one molecule, a physical quantity (the count
    // noise form counts molecules, and molecule-resolved particles are molecules).
    // nullopt: derived from the units, 1 nM = 0.6022 molecules per um^3, reading LU as
    // 40 um and CU as nM where they are not declared (molecule_amount()).
    std::optional<double> molecule_amount;
    struct Particles {
      // Concentration units x length^3 carried by one particle: a numerical parameter
      // (a source's strength is emission x amount; refining the particles means a
      // smaller amount and a larger emission).
      double amount = 0.001;
      // Molecule-resolved: one particle is one molecule (amount = the molecule amount),
      // and count decisions read the particles within r themselves.
      bool molecules = false;
      // The estimate of C and grad C that growth cones read (core/estimate.hpp):
      // mesh spacing (length units) and the time constant of its moving average (time
      // units; 0: this step only). nullopt: the defaults of estimate_spacing/time().
      struct Estimate {
        std::optional<double> spacing;
        std::optional<double> time;
      } estimate;
      Motion motion = Motion::kBrownian;
      bool collisions = false;
      double speed = 0.0;      // ballistic: initial speed, LU/step (0: sqrt(6 D / dt))
      double damping = 0.1;    // ballistic: fraction of velocity lost per step
      double radius = 0.02;    // collisions: particle radius, LU
      double stiffness = 0.5;  // collisions: soft-sphere response, per step
    } particles;
    struct Grid {
      // Node spacing, length units; nullopt: grid_spacing()'s rule.
      std::optional<double> spacing;
      GridScheme scheme = GridScheme::kImplicit;
      GridBoundary boundary = GridBoundary::kAbsorbing;
      bool allow_substeps = true;  // explicit: sub-step to the stability limit, or refuse
      // Sub-steps per step; nullopt: 1 (implicit) or the explicit scheme's stability limit.
      std::optional<std::uint32_t> substeps;
    } grid;
    struct Imposed {
      ImposedProfile profile = ImposedProfile::kExponential;
      core::Vec3 direction{1.0, 0.0, 0.0};  // up the gradient, as written (normalised where used)
      double steepness = 0.2;                // percent change per reference_length
      double reference_length = 10.0;        // length units
      double concentration = 1.0;            // at each source's position, concentration units
    } imposed;
  } cues;

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
  // m, concentration units x length^3 per molecule (cues.molecule_amount or the units).
  double molecule_amount() const;
  double molecule_amount_from_units() const;
  // The particle estimate's mesh spacing (length units; default: the sensing radius, at
  // most a quarter of the domain radius) and moving-average time constant (time units;
  // default: kEstimateSteps dt).
  static constexpr double kEstimateSteps = 10.0;
  double estimate_spacing() const {
    return cues.particles.estimate.spacing.value_or(std::min(guidance.sensing_radius, 0.25 * bounds_radius()));
  }
  double estimate_time() const { return cues.particles.estimate.time.value_or(kEstimateSteps * dt); }
  // The grid field's node spacing: cues.grid.spacing, or min(r, lambda_min / 6, R_b / 4) with
  // lambda_min the shortest decay length sqrt(D / k) of the cues (docs/methods.md §11.7: the
  // cheapest spacing whose guidance is within 10 % and evidence error within 10 %).
  static constexpr double kGridPointsPerLambda = 6.0;
  double grid_spacing() const;
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

// The canonical cue order (SPEC §3.5): sources sorted by (kind, position given, x, y, z,
// emission, diffusion, decay, K_d, window), so that a scene listing the same sources in
// another order is the same scene, byte for byte (particle ids, random streams and the
// evidence sum all follow the cue index). The parser, the canonical form and make_cues
// all use it.
std::vector<Source> canonical_sources(std::vector<Source> sources);

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

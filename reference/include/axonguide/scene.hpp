#pragma once
// The scene: every input of a run (SPEC §5). Parsed strictly from JSON: every key is
// optional and has a default, unknown keys are errors, values are range-checked, and a
// bad scene raises InputError naming the key path, the value and what is allowed.
#include <array>
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
using core::Motion;
using core::RegionShape;
using core::Sampler;

struct Source {
  CueKind kind = CueKind::kAttractant;
  std::optional<core::Vec3> position;  // nullopt: sampled inside the region
  double emission = 100;               // particles (amount units) per step
  double diffusion = 0.05;             // D, LU^2 per step
  double decay = 0.05;                 // k, per step
  double kd = 1.0;                     // K_d, concentration units
  double min_concentration = 0.0;
  double max_concentration = 1e300;
};

struct RandomSources {
  std::uint32_t count = 0;
  double attractant_fraction = 0.5;
  double emission = 100;
  double diffusion = 0.05;
  double decay = 0.05;
  double kd = 1.0;
};

struct Scene {
  std::uint64_t seed = 1;
  std::uint32_t steps = 100;
  double dt = 1.0;

  struct Neurons {
    std::uint64_t count = 1000;
    double soma_radius = 0.25;
    RegionShape shape = RegionShape::kBall;
    double radius = 5.0;  // ball/sphere radius, or the half-edge of a box
    Sampler sampler = Sampler::kRejection;
    bool overlap_reject = true;
    std::uint32_t max_attempts = 1000;
  } neurons;

  struct Axons {
    double step_length = 0.35;
    double contact_distance = 0.05;
    ContactRule contact = ContactRule::kSwept;
    std::optional<double> bounds_radius;  // nullopt: the region's radius
  } axons;

  struct Guidance {
    GuidanceModel model = GuidanceModel::kSnr;
    double turn_angle = 0.10471975511965977;  // pi/30
    double gain = 250;                         // alpha
    double vector_weight = 0.1;                // beta
    double growth_cone_width = 0.1;            // w, LU
    double sensing_radius = 0.5;               // r, LU
  } guidance;

  struct Cues {
    FieldKind field = FieldKind::kParticles;
    std::vector<Source> sources;
    RandomSources random_sources;
    struct Particles {
      double amount = 0.01;  // concentration units x LU^3 carried by one particle
      Motion motion = Motion::kBrownian;
      bool collisions = false;
      double speed = 0.0;      // ballistic: initial speed, LU/step (0: sqrt(6 D / dt))
      double damping = 0.1;    // ballistic: fraction of velocity lost per step
      double radius = 0.02;    // collisions: particle radius, LU
      double stiffness = 0.5;  // collisions: soft-sphere response, per step
    } particles;
    struct Grid {
      double spacing = 0.1;
      GridScheme scheme = GridScheme::kImplicit;
      GridBoundary boundary = GridBoundary::kAbsorbing;
      bool allow_substeps = true;  // explicit: sub-step to the stability limit, or refuse
    } grid;
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
  } output;

  // Derived quantities.
  double bounds_radius() const { return axons.bounds_radius.value_or(neurons.radius); }
  bool uses_cues() const { return guidance.model != GuidanceModel::kDirect; }
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

// The canonical form: every key, defaults filled in, keys sorted.
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
const char* name_of(core::AxonStatus v);

}  // namespace axg

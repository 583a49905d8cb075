#pragma once
// Cue sources and the field that carries them (SPEC §3.3; docs/methods.md §2.4, §2.5): the
// keys cues.{field, warmup_steps, sources, random_sources, imposed}, their reading and
// canonical form, the canonical cue order, and every cue's parameters for core/cues.hpp
// (source positions that the scene leaves to sampling are drawn here: host code, like
// placement). What every cue field shares: the node limit of its meshes, the check of its
// resolution before anything is allocated, and its memory estimate.
#include <cstdint>
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "axonguide/core/cues.hpp"
#include "axonguide/core/types.hpp"
#include "axonguide/core/vec3.hpp"

namespace axg {

struct Scene;
class ObjectReader;

struct Source {
  core::CueKind kind = core::CueKind::kAttractant;
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

// An imposed gradient (cues.field "imposed"): a profile along a direction, its steepness in
// percent per reference length, as in explant assays.
struct ImposedKeys {
  core::ImposedProfile profile = core::ImposedProfile::kExponential;
  core::Vec3 direction{1.0, 0.0, 0.0};  // up the gradient, as written (normalised where used)
  double steepness = 0.2;                // percent change per reference_length
  double reference_length = 10.0;        // length units
  double concentration = 1.0;            // at each source's position, concentration units
};

struct CueKeys {
  core::FieldKind field = core::FieldKind::kParticles;
  // Steps the cue fields advance before growth starts (a pre-established gradient, as in an
  // assay); growth step s is field step warmup_steps + s.
  std::uint32_t warmup_steps = 0;
  std::vector<Source> sources;
  RandomSources random_sources;
  ImposedKeys imposed;
};

// cues.{field, warmup_steps, sources, random_sources}, and cues.imposed (read last: the
// scene's order of keys in messages).
void read_cue_keys(ObjectReader& cues, CueKeys& keys);
void read_imposed_keys(ObjectReader& cues, ImposedKeys& keys);
void write_cue_keys(const CueKeys& keys, nlohmann::json& cues);
// At most core::kMaxCues sources; given positions inside the domain.
void check_cues(const Scene& scene);

// The canonical cue order (SPEC §3.5): sources sorted by (kind, position given, x, y, z,
// emission, diffusion, decay, K_d, window), so that a scene listing the same sources in
// another order is the same scene, byte for byte (particle ids, random streams and the
// evidence sum all follow the cue index). The parser, the canonical form and make_cues
// all use it.
std::vector<Source> canonical_sources(std::vector<Source> sources);

// Every cue in index order: the scene's sources (in their canonical order), then the
// random ones. Throws InputError for an imposed linear profile that would go negative
// inside the domain.
std::vector<core::CueParams> make_cues(const Scene& scene);
void check_imposed_field(const Scene& scene, const std::vector<core::CueParams>& cues);
core::ImposedParams imposed_params(const Scene& scene);

// Scene errors of a grid field or of the particle estimate's meshes, checked before
// anything is allocated and for every backend: more than kMaxGridNodes nodes per axis, a
// memory estimate above the machine's, an explicit scheme that needs sub-steps the scene
// forbids, more than kMaxSubsteps, or more than cues.grid.substeps gives. Throws
// InputError (exit 2) naming the key.
inline constexpr double kMaxGridNodes = 4096;
void check_cue_fields(const Scene& scene, const std::vector<core::CueParams>& cues);

// Bytes the cue fields of this scene need (0 for direct guidance); checked against the
// machine before allocation (the grid field refuses with exit 2, as a scene error).
std::uint64_t estimate_cue_bytes(const Scene& scene);

}  // namespace axg

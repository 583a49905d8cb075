#pragma once
// The particle field (SPEC §3.3; docs/methods.md §2.5): the keys cues.particles.{amount,
// molecules, motion, collisions, speed, damping, radius, stiffness} (its estimate's keys are
// model/estimate.hpp's), their reading and canonical form, and the parameters that
// core/particles.hpp's steps get: motion, death, the hashed grid of the gathers.
#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "axonguide/core/particles.hpp"
#include "axonguide/core/types.hpp"
#include "axonguide/model/estimate.hpp"

namespace axg {

struct Scene;
class ObjectReader;

struct ParticleKeys {
  // Concentration units x length^3 carried by one particle: a numerical parameter (a
  // source's strength is emission x amount; refining the particles means a smaller amount
  // and a larger emission).
  double amount = 0.001;
  // Molecule-resolved: one particle is one molecule (amount = the molecule amount), and
  // count decisions read the particles within r themselves.
  bool molecules = false;
  EstimateKeys estimate;
  core::Motion motion = core::Motion::kBrownian;
  bool collisions = false;
  double speed = 0.0;      // ballistic: initial speed, LU/step (0: sqrt(6 D / dt))
  double damping = 0.1;    // ballistic: fraction of velocity lost per step
  double radius = 0.02;    // collisions: particle radius, LU
  double stiffness = 0.5;  // collisions: soft-sphere response, per step
};

// cues.particles (and its estimate); returns whether `amount` was given.
bool read_particle_keys(ObjectReader& particles, ParticleKeys& keys);
void write_particle_keys(const ParticleKeys& keys, nlohmann::json& particles);
// A molecule-resolved particle is one molecule: its amount is the scene's molecule amount
// (an amount given that differs is refused).
void resolve_molecules(Scene& scene, bool amount_given);
// cues.particles.molecules applies to the particle field only: a warning for other fields.
void check_particles(const Scene& scene, std::vector<std::string>& warnings);

core::ParticleParams particle_params(const Scene& scene);

struct HashGeometry {
  core::Vec3 origin;
  double cell;
  int dim;
  std::size_t buckets() const { return static_cast<std::size_t>(dim) * dim * dim; }
};
// Buckets at least as wide as the sensing radius (and the collision diameter), at most
// 128 per axis (wrapping beyond), covering the domain without wrap when they can.
HashGeometry particle_hash_geometry(const Scene& scene);
// Whether the particle field needs the hashed grid of the particles within r (collisions,
// molecule-resolved counts, source_vector_sum).
bool particle_grid_used(const Scene& scene);
// Typical steady particle count (for estimates and messages).
double expected_particles(const Scene& scene);

}  // namespace axg

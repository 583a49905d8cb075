#pragma once
// Neuron placement (SPEC §3.1): host code shared by both backends.
#include <cstdint>
#include <vector>

#include "axonguide/core/vec3.hpp"
#include "axonguide/scene/scene.hpp"

namespace axg {

struct Placement {
  std::vector<core::Vec3> soma;     // LU
  std::vector<core::Vec3> heading;  // unit initial axon directions
  std::uint64_t redraws = 0;        // attempts beyond the first, summed over neurons
};

// Nominal packing fraction of the somas: volume fraction for a ball or box, area
// fraction (of discs of radius r_s) for a sphere surface.
double packing_fraction(const Scene::Neurons& n);

// Places neurons in id order. With overlap "reject", neuron i is redrawn (attempt a in
// the RNG counter) while it overlaps an earlier soma; after max_attempts it throws
// RunError naming the packing fraction. Parallel where it can be (first draws and
// headings); the result does not depend on the thread count.
Placement place_neurons(const Scene& scene);

// Throws RunError when the scene's packing fraction is beyond what random sequential
// addition can reach (checked before any overlap test).
void check_packing(const Scene& scene);
// Throws the RunError of neuron `id` exhausting neurons.max_attempts.
[[noreturn]] void placement_failed(const Scene& scene, std::uint64_t id);

// The position of neuron `id` at `attempt`, and its initial heading.
core::Vec3 soma_draw(const Scene& scene, std::uint64_t id, std::uint32_t attempt);
core::Vec3 heading_draw(const Scene& scene, std::uint64_t id);
// Neuron `id`'s initial heading with its soma at `soma`: heading_draw's, or under
// neurons.heading "radial" the unit vector from its population's centre (the origin
// without populations) through the soma (heading_draw's where the two coincide).
core::Vec3 initial_heading(const Scene& scene, std::uint64_t id, core::Vec3 soma);

}  // namespace axg

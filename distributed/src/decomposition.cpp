#include "axonguide/distributed/decomposition.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "axonguide/core/types.hpp"
#include "axonguide/model/growth.hpp"
#include "axonguide/model/particles.hpp"
#include "axonguide/model/sensing.hpp"
#include "axonguide/model/stencil.hpp"
#include "axonguide/support/error.hpp"

namespace axg::distributed {

std::vector<int> Decomposition::neighbours(int rank) const {
  const std::array<int, 3> b = block(rank);
  std::vector<int> out;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const std::array<int, 3> n{b[0] + dx, b[1] + dy, b[2] + dz};
        bool inside = !(dx == 0 && dy == 0 && dz == 0);
        for (int a = 0; a < 3; ++a) inside = inside && n[a] >= 0 && n[a] < blocks[a];
        if (inside) out.push_back(rank_of(n));
      }
  std::sort(out.begin(), out.end());
  return out;
}

std::string Decomposition::describe() const {
  return fmt::format("{} x {} x {} blocks of {:.4g} x {:.4g} x {:.4g} LU, halo {:.4g} LU", blocks[0], blocks[1],
                     blocks[2], edge[0], edge[1], edge[2], halo);
}

Decomposition decompose(const Scene& scene, int ranks) {
  if (scene.signalling())
    throw RunError("a run decomposed over ranks does not take axons.growth_model = \"signalling\" (its explant "
                   "inhibition is a mean over a population that may span ranks): run it without mpirun, or sweep "
                   "its members over ranks with `axonguide sweep`");
  const auto& nn = scene.neurons;
  if (nn.count >= core::kNoNeuron)
    throw InputError(fmt::format("scene: neurons.count = {}: must be below {} (32-bit neuron ids)", nn.count,
                                 core::kNoNeuron));
  Decomposition d;
  d.ranks = ranks;
  // The somas' extent: blocks share the somas, and so the work. Tips beyond it (up to the
  // bounds) belong to the outer blocks, whose points are clamped into them.
  double extent = nn.populations.empty() ? nn.radius : 0.0;
  for (const Population& p : nn.populations)
    extent = std::max({extent, std::abs(p.center.x) + p.radius, std::abs(p.center.y) + p.radius,
                       std::abs(p.center.z) + p.radius});
  d.half = extent + nn.soma_radius;
  d.max_step = max_step_length(scene);
  const double reach = d.max_step + nn.soma_radius + scene.axons.contact_distance;
  d.halo = std::max(reach, 2.0 * nn.soma_radius) * 1.001;
  std::string set_by = fmt::format("one step's contact search: step {:.4g} + soma radius + contact distance", d.max_step);
  if (scene.uses_cues() && scene.cues.field == FieldKind::kParticles && particle_grid_used(scene)) {
    const bool gathers = sense_params(scene).sensing != core::ParticleSensing::kEstimate;
    // A gather reads the particles within r of the sample point, half a step ahead of the tip.
    const double gather = std::max(gathers ? scene.guidance.sensing_radius + 0.5 * d.max_step : 0.0,
                                   scene.cues.particles.collisions ? 2.0 * scene.cues.particles.radius : 0.0);
    d.particle_halo = gather * 1.001;
    if (d.particle_halo > d.halo) {
      d.halo = d.particle_halo;
      set_by = gathers ? "the particles within the sensing radius" : "the particles' collision diameter";
    }
  }
  if (scene.uses_cues() && scene.cues.field == FieldKind::kGrid) {
    // Slabs over the grid's cube (the field's work; somas beyond it belong to the outer
    // slabs), each at least as thick as the ghost planes its neighbours keep.
    const GridGeometry3 g = grid_field_geometry(scene);
    const int ghosts = grid_ghost_planes(scene);
    d.slabs = true;
    d.half = 0.5 * (g.n - 1) * g.h + 0.5 * g.h;
    if (ghosts * g.h * 1.001 > d.halo) {
      d.halo = ghosts * g.h * 1.001;
      set_by = fmt::format("{} grid planes of ghost nodes", ghosts);
    }
  }

  // The most cubic factorisation: the least P_x + P_y + P_z, then the most cuts along x, y.
  int best = -1;
  if (d.slabs) d.blocks = {1, 1, ranks};
  for (int px = 1; px <= ranks && !d.slabs; ++px) {
    if (ranks % px) continue;
    for (int py = 1; py <= ranks / px; ++py) {
      if ((ranks / px) % py) continue;
      const int pz = ranks / px / py;
      const int score = px + py + pz;
      if (best < 0 || score < best || (score == best && std::array{px, py} > std::array{d.blocks[0], d.blocks[1]})) {
        best = score;
        d.blocks = {px, py, pz};
      }
    }
  }
  for (int a = 0; a < 3; ++a) d.edge[a] = 2.0 * d.half / d.blocks[a];
  const double shortest = *std::min_element(d.edge.begin(), d.edge.end());
  if (shortest < d.halo) {
    const int per_axis = static_cast<int>(std::floor(2.0 * d.half / d.halo));
    const long long most = d.slabs ? per_axis : static_cast<long long>(per_axis) * per_axis * per_axis;
    throw InputError(fmt::format(
        "{} ranks: the domain (a cube of edge {:.4g} LU) cut {} x {} x {} gives blocks {:.4g} LU wide, narrower than "
        "the halo of {:.4g} LU ({}); use {} (at most {} rank{}), or run without mpirun",
        ranks, 2.0 * d.half, d.blocks[0], d.blocks[1], d.blocks[2], shortest, d.halo, set_by,
        d.slabs ? fmt::format("at most {} slabs along z (a grid scene is cut in slabs)", per_axis)
                : fmt::format("a rank count whose most cubic factorisation has at most {} blocks along an axis", per_axis),
        most, most == 1 ? "" : "s"));
  }
  return d;
}

}  // namespace axg::distributed

#include "axonguide/engine/cell_grid.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <tbb/parallel_for.h>

#include "axonguide/scene/scene.hpp"
#include "axonguide/support/radix_sort.hpp"

namespace axg {

GridGeometry soma_grid_geometry(const Scene& s) {
  const double contact = s.neurons.soma_radius + s.axons.contact_distance;
  if (s.neurons.shape == RegionShape::kDisc) {
    // A culture: one layer of square cells over the disc, about one soma a cell.
    GridGeometry g = cube_geometry(s.neurons.radius + contact, 2.0 * contact,
                                   std::pow(static_cast<double>(s.neurons.count), 1.5));
    g.nz = 1;
    g.origin.z = -0.5 * g.cell;
    return g;
  }
  return cube_geometry(s.neurons.radius + contact, 2.0 * contact, static_cast<double>(s.neurons.count));
}

GridGeometry cube_geometry(double half, double min_cell, double max_cells) {
  GridGeometry g;
  double cell = std::max(min_cell, 2.0 * half / std::cbrt(std::max(1.0, max_cells)));
  int n = std::max(1, static_cast<int>(std::ceil(2.0 * half / cell)));
  g.cell = cell;
  g.nx = g.ny = g.nz = n;
  // Centre the cells on the cube; the clamped edge cells absorb anything outside.
  const double o = -0.5 * n * cell;
  g.origin = {o, o, o};
  return g;
}

CellGrid build_cell_grid(const GridGeometry& geometry, const std::vector<core::Vec3>& points) {
  CellGrid grid;
  grid.geometry = geometry;
  const std::size_t n = points.size();
  core::CellGridView view{geometry.origin, geometry.cell, geometry.nx, geometry.ny, geometry.nz,
                          nullptr, nullptr, nullptr};
  std::vector<std::uint32_t> keys(n);
  grid.ids.resize(n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    keys[i] = core::cell_of(points[i], view);
    grid.ids[i] = static_cast<std::uint32_t>(i);
  });
  const std::uint32_t cells = geometry.cells();
  stable_sort_by_key(keys, grid.ids, cells - 1);
  cell_starts(keys, cells, grid.cell_start);
  grid.pos.resize(n);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t k) { grid.pos[k] = points[grid.ids[k]]; });
  return grid;
}

}  // namespace axg

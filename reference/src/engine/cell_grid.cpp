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
  if (s.neurons.populations.empty())
    return cube_geometry(s.neurons.radius + contact, 2.0 * contact, static_cast<double>(s.neurons.count));
  // Populations: the somas fill their balls, not the region (an explant of radius 200 in a
  // region of 800 filled 27 of 1000 cells, some 40 somas each). The cells cover the balls'
  // box and are sized for about one soma a cell in the densest population, coarsened while
  // there are more than 8 cells a soma. Which cells exist changes no answer: the grid clamps
  // every point monotonically, so find_contact visits every soma in reach.
  core::Vec3 lo{0, 0, 0}, hi{0, 0, 0};
  double cell = HUGE_VAL;
  bool any = false;
  for (const Population& p : s.neurons.populations) {
    if (p.count == 0) continue;
    const double reach = p.radius + contact;
    const core::Vec3 a = p.center - core::Vec3{reach, reach, reach}, b = p.center + core::Vec3{reach, reach, reach};
    lo = any ? core::Vec3{std::min(lo.x, a.x), std::min(lo.y, a.y), std::min(lo.z, a.z)} : a;
    hi = any ? core::Vec3{std::max(hi.x, b.x), std::max(hi.y, b.y), std::max(hi.z, b.z)} : b;
    any = true;
    cell = std::min(cell, std::cbrt(4.0 / 3.0 * 3.141592653589793 * p.radius * p.radius * p.radius /
                                    static_cast<double>(p.count)));
  }
  if (!any) return cube_geometry(s.neurons.radius + contact, 2.0 * contact, static_cast<double>(s.neurons.count));
  return box_geometry(lo, hi, std::max(cell, 2.0 * contact), 8.0 * static_cast<double>(s.neurons.count) + 64.0);
}

GridGeometry box_geometry(core::Vec3 lo, core::Vec3 hi, double cell, double max_cells) {
  auto count = [&](double a, double b) { return std::max(1.0, std::ceil((b - a) / cell + 1e-9)); };
  while (count(lo.x, hi.x) * count(lo.y, hi.y) * count(lo.z, hi.z) > max_cells) cell *= 1.25;
  GridGeometry g;
  g.origin = lo;
  g.cell = cell;
  g.nx = static_cast<int>(count(lo.x, hi.x));
  g.ny = static_cast<int>(count(lo.y, hi.y));
  g.nz = static_cast<int>(count(lo.z, hi.z));
  return g;
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

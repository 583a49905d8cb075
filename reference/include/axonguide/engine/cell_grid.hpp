#pragma once
// Host-side construction of a sorted uniform grid (core::CellGridView) over points.
#include <cstdint>
#include <vector>

#include "axonguide/core/cellgrid.hpp"
#include "axonguide/core/vec3.hpp"

namespace axg {

struct GridGeometry {
  core::Vec3 origin{0, 0, 0};
  double cell = 1.0;
  int nx = 1, ny = 1, nz = 1;
  std::uint32_t cells() const {
    return static_cast<std::uint32_t>(nx) * static_cast<std::uint32_t>(ny) *
           static_cast<std::uint32_t>(nz);
  }
};

// A cube [-half, half]^3 divided into cells of edge >= min_cell, with at most about
// max_cells cells (the edge grows to respect it).
GridGeometry cube_geometry(double half, double min_cell, double max_cells);
// The box [lo, hi] from its lower corner in cells of edge `cell`, the edge grown by 1.25 at
// a time while there are more than max_cells.
GridGeometry box_geometry(core::Vec3 lo, core::Vec3 hi, double cell, double max_cells);

struct Scene;
// The soma grid covers the region (or, with populations, their balls); cells are at least
// one contact diameter wide and about one per neuron (in the densest population), so a
// step visits a handful of cells.
GridGeometry soma_grid_geometry(const Scene& s);

struct CellGrid {
  GridGeometry geometry;
  std::vector<std::uint32_t> cell_start;  // cells + 1
  std::vector<std::uint32_t> ids;         // sorted by (cell, id)
  std::vector<core::Vec3> pos;            // same order

  core::CellGridView view() const {
    return {geometry.origin, geometry.cell, geometry.nx, geometry.ny, geometry.nz,
            cell_start.data(), ids.data(), pos.data()};
  }
  std::size_t bytes() const {
    return cell_start.capacity() * 4 + ids.capacity() * 4 + pos.capacity() * sizeof(core::Vec3);
  }
};

// Hash every point to its cell, stable-sort by cell (ids ascending within a cell), then
// find cell starts.
CellGrid build_cell_grid(const GridGeometry& geometry, const std::vector<core::Vec3>& points);

}  // namespace axg

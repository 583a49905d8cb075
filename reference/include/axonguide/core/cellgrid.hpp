#pragma once
// A uniform grid over sorted entities: entity k of cell c sits at positions
// [cell_start[c], cell_start[c+1]) of `ids`/`pos`, sorted by (cell, id). Built by hashing
// and a stable sort (never by atomic insertion), so its content is deterministic.
#include <cstddef>
#include <cstdint>

#include "hd.hpp"
#include "vec3.hpp"

namespace axg::core {

struct CellGridView {
  Vec3 origin;   // LU, lower corner of cell (0,0,0)
  double cell;   // LU, cell edge
  int nx, ny, nz;
  const std::uint32_t* cell_start;  // nx*ny*nz + 1 offsets
  const std::uint32_t* ids;         // entity ids sorted by (cell, id)
  const Vec3* pos;                  // their positions, in the same order
};

// Cell coordinate of v along one axis, clamped into [0, n). Truncation of a
// non-negative quotient is floor; NaN clamps to 0.
AXG_HDI int cell_coord(double v, double origin, double cell, int n) {
  const double t = (v - origin) / cell;
  if (!(t >= 0.0)) return 0;
  if (t >= static_cast<double>(n)) return n - 1;
  return static_cast<int>(t);
}

AXG_HDI std::uint32_t cell_index(int x, int y, int z, int nx, int ny) {
  return (static_cast<std::uint32_t>(z) * static_cast<std::uint32_t>(ny) +
          static_cast<std::uint32_t>(y)) * static_cast<std::uint32_t>(nx) +
         static_cast<std::uint32_t>(x);
}

AXG_HDI std::uint32_t cell_of(Vec3 p, const CellGridView& g) {
  return cell_index(cell_coord(p.x, g.origin.x, g.cell, g.nx),
                    cell_coord(p.y, g.origin.y, g.cell, g.ny),
                    cell_coord(p.z, g.origin.z, g.cell, g.nz), g.nx, g.ny);
}

// Cell starts from keys sorted ascending: task k (0..n) handles the boundary before
// element k and writes start[c] = k for every cell c in (key[k-1], key[k]] (cells 0..key[0]
// for k = 0, the cells after the last key for k = n). Boundaries never write the same cell.
AXG_HDI void fill_cell_starts(std::size_t k, const std::uint32_t* sorted_keys, std::size_t n,
                              std::uint32_t num_cells, std::uint32_t* start) {
  if (k != 0 && k != n && sorted_keys[k - 1] == sorted_keys[k]) return;
  const std::uint32_t first = k == 0 ? 0 : sorted_keys[k - 1] + 1;
  const std::uint32_t last = k == n ? num_cells : sorted_keys[k];
  for (std::uint32_t c = first; c <= last; ++c) start[c] = static_cast<std::uint32_t>(k);
}

}  // namespace axg::core

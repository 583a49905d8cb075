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
  const std::uint32_t* cell_start;  // nx*ny*nz + 1 offsets, by cell_index
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

// Cells are stored in pencils: tiles of up to kCellTile x kCellTile rows (y, z), each row
// every x in order; the rows of a tile in (z, y) order, the tiles in (z, y) order (the last
// tile along y or z holds the rows left over, so the index space is exactly nx ny nz). A
// row's cells stay consecutive (a contact search reads runs along x), and the entities,
// sorted by cell, are swept a tile at a time: a search reads the rows around its tip's, all
// but a tile's edge rows within the tile, whose data fit a core's L2 cache at 10^7 somas
// (row-major, the three planes of rows a sweep keeps in use do not). Which index a cell gets
// changes only memory traffic: every search visits the same somas and breaks ties by (t, id).
inline constexpr std::uint32_t kCellTile = 8;

AXG_HDI std::uint32_t cell_index(int x, int y, int z, int nx, int ny, int nz) {
  const std::uint32_t uy = static_cast<std::uint32_t>(y), uz = static_cast<std::uint32_t>(z);
  const std::uint32_t uny = static_cast<std::uint32_t>(ny), unz = static_cast<std::uint32_t>(nz);
  const std::uint32_t z0 = uz / kCellTile * kCellTile, y0 = uy / kCellTile * kCellTile;
  const std::uint32_t tile_z = unz - z0 < kCellTile ? unz - z0 : kCellTile;  // the tile's rows along z
  const std::uint32_t tile_y = uny - y0 < kCellTile ? uny - y0 : kCellTile;  // and along y
  const std::uint32_t row = z0 * uny + tile_z * y0 + (uz - z0) * tile_y + (uy - y0);
  return row * static_cast<std::uint32_t>(nx) + static_cast<std::uint32_t>(x);
}

AXG_HDI std::uint32_t cell_of(Vec3 p, const CellGridView& g) {
  return cell_index(cell_coord(p.x, g.origin.x, g.cell, g.nx),
                    cell_coord(p.y, g.origin.y, g.cell, g.ny),
                    cell_coord(p.z, g.origin.z, g.cell, g.nz), g.nx, g.ny, g.nz);
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

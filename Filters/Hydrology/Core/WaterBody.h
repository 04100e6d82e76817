/**
 * @file WaterBody.h
 * @brief Statistics of one water body, shared by the flood-fill cores (FloodFill.h,
 *        DepressionWaterBodies.h).
 *
 * Plain C++ (no VTK, no GL). A water body is a set of cells under one flat water surface at
 * `level` metres; the depth of a cell is `level - z` (metres). The area of a cell in row j is
 * `DxAt(j) * DyAt(j)` (GridView.h), so geographic grids with per-row spacing are measured
 * correctly. Sums are taken in double precision in a fixed cell order, so the statistics are
 * deterministic.
 */
#ifndef terroir_hydrology_WaterBody_h
#define terroir_hydrology_WaterBody_h

#include "GridView.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

namespace terroir
{
namespace hydrology
{

/// Level, size and volume of one water body.
struct WaterBodyStats
{
  double level = 0.0;     ///< water surface, metres (same datum as the elevations)
  std::int64_t cells = 0; ///< number of wet cells
  double area = 0.0;      ///< sum of the wet cells' areas dx * dy, m^2
  double volume = 0.0;    ///< sum of depth * cell area over the wet cells, m^3
  double maxDepth = 0.0;  ///< largest depth (level - z) of a wet cell, metres; 0 when empty

  /// Adds one wet cell of area `cellArea` (m^2) and depth `depth` (m).
  void AddCell(double cellArea, double depth)
  {
    ++this->cells;
    this->area += cellArea;
    this->volume += depth * cellArea;
    if (depth > this->maxDepth)
    {
      this->maxDepth = depth;
    }
  }
};

/// True when cell k holds data: no mask or mask 1, and an elevation that is not NaN (the
/// no-data rule of every hydrology core).
inline bool HasData(const GridView<float>& view, std::size_t k)
{
  return (!view.valid || view.valid[k] != 0) && !std::isnan(view.data[k]);
}

namespace detail
{

/// The cores keep cell indices in 32-bit queues: refuse grids with more cells than that.
inline void CheckCellCount(const GridView<float>& view, const char* function)
{
  if (view.nx < 1 || view.ny < 1 || !view.data)
  {
    throw std::invalid_argument(std::string(function) + ": empty grid");
  }
  if (view.Size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
  {
    throw std::length_error(std::string(function) + ": more than 2^31 - 1 cells");
  }
}

/// Column offsets, then row offsets, of the 8 neighbours (west, east, then the row below and
/// the row above, west to east).
constexpr int kNeighbourDi[8] = { -1, 1, -1, 0, 1, -1, 0, 1 };
constexpr int kNeighbourDj[8] = { 0, 0, -1, -1, -1, 1, 1, 1 };
} // namespace detail

} // namespace hydrology
} // namespace terroir

#endif

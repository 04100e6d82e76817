/**
 * @file DepressionWaterBodies.h
 * @brief Water bodies of a DEM: the filled depressions and the flat water surfaces of a
 *        depression-filled surface.
 *
 * Plain C++ (no VTK, no GL): the second half of vtkTerroirFloodFill's FillDepressions mode
 * (the first half is PriorityFloodBarnes2014, PriorityFlood.h).
 *
 * Method. A flat of the filled surface W is a set of cells with data, connected through
 * 8-neighbours whose W is exactly equal (W is a copy of input floats, so equality is exact).
 * A flat is a water body when its area (sum of dx * dy) is at least `minimumArea` m^2 and
 * - it holds at least one filled cell (W > z): a depression that water fills up to its spill
 *   level; or
 * - `includeFlatSurfaces` is on and it has at least two cells: a flat water surface already in
 *   the DEM.
 * The depth of a water cell is W - z (0 on its unfilled cells), its level W.
 *
 * Why flat surfaces count. USGS NED / 3DEP DEMs are hydro-flattened: lakes and reservoirs are
 * replaced by a flat surface at the water level (which is the level of the outlet), not by the
 * bed. Such a lake is not a closed depression, so depression filling finds at most a few cells
 * along its shore. On the bundled Sagehen Creek DEM (786 x 720 cells of 10 m), Independence
 * Lake in the north-west is a flat of 23,531 cells at exactly 2117.804 m (float
 * 2117.803955078125); Priority-Flood raises only the 67 shore cells around it (by at most
 * 0.06 m). The flat rule finds the whole lake, 23,598 cells with those shore cells
 * (Testing/Pipeline/TestTerroirFloodFill.cxx). Depths on such a lake are 0 (a few centimetres
 * at the shore): the DEM records the water surface, not the bed.
 *
 * Caveat. On a DEM quantised to whole metres (or coarser), equal-height plateaus are common
 * and would be reported as water surfaces when they are at least `minimumArea` large: raise
 * `minimumArea`, or turn `includeFlatSurfaces` off to keep only filled depressions.
 *
 * Numbering: water bodies get ids 1, 2, ... in the order of their first cell in row-major
 * order (j = 0 first). Linear time (each cell is visited once with an explicit queue of 32-bit
 * cell indices); sequential and deterministic.
 *
 * @par Correctness
 * Testing/Unit/TestFloodFill.cxx, suite DepressionWaterBodies (a closed pit; a flat at the
 * outlet's level found only with includeFlatSurfaces and a large enough area; minimumArea
 * dropping small bodies; ids in row-major order; depths, areas, volumes by hand), and
 * Testing/Pipeline/TestTerroirFloodFill.cxx (Independence Lake).
 */
#ifndef terroir_hydrology_DepressionWaterBodies_h
#define terroir_hydrology_DepressionWaterBodies_h

#include "GridView.h"
#include "WaterBody.h"

#include <cstdint>
#include <functional>
#include <vector>

namespace terroir
{
namespace hydrology
{

/// Options of DepressionWaterBodies.
struct DepressionWaterBodyOptions
{
  double minimumArea = 10000.0;    ///< smallest water body kept, m^2 (default 1 ha)
  bool includeFlatSurfaces = true; ///< also report flats without filled cells
};

/**
 * @brief Labels the water bodies of a depression-filled surface (see the file comment).
 * @param[in] view     elevations z (metres), validity mask, per-row spacing (for areas)
 * @param[in] filled   nx*ny values of the filled surface W >= z (PriorityFloodBarnes2014)
 * @param[in] options  minimum area and whether flats without filled cells count
 * @param[out] bodyId  nx*ny values: water body id 1.. or 0 (dry or no data)
 * @param[out] depth   nx*ny values: W - z on water cells, 0 on dry cells, NaN on no-data cells
 * @param[in] progress optional, called with the fraction of cells visited (0..1)
 * @return one WaterBodyStats per water body, index id - 1 (level = W of the flat)
 * @pre filled comes from PriorityFloodBarnes2014 on the same view (any surface works, but
 *      then "filled" cells are simply those with W > z); nx*ny < 2^31
 * @correctness Testing/Unit/TestFloodFill.cxx, suite DepressionWaterBodies
 */
std::vector<WaterBodyStats> DepressionWaterBodies(const GridView<float>& view,
  const float* filled,
  const DepressionWaterBodyOptions& options,
  std::int32_t* bodyId,
  float* depth,
  const std::function<void(double)>& progress = {});

} // namespace hydrology
} // namespace terroir

#endif

/**
 * @file FloodFill.h
 * @brief Seed flood fill: the water body a point source fills up to a given level.
 *
 * Plain C++ (no VTK, no GL): the core of vtkTerroirFloodFill's Seeds mode.
 *
 * Method. From each seed cell, every cell that is 8-connected to it through cells whose
 * elevation z satisfies z <= level (inclusive) becomes water. The fill stops at the grid
 * edge (there is nothing beyond it); no-data cells (mask 0 or NaN elevation) are never water
 * and block the fill. The depth of a wet cell is level - z, computed in double and stored as
 * float. This is the "bucket fill" of an image editor applied to heights, the way a reservoir
 * or a flooded valley behind a point is drawn: the water surface is flat and the fill does not
 * ask whether the water could spill elsewhere (for that, see PriorityFlood.h and
 * DepressionWaterBodies.h).
 *
 * Several seeds. Seeds are handled from the highest level down (seeds with equal levels in
 * their given order). Body ids are the seed index + 1. A seed whose cell is already wet (it
 * lies inside the body of a seed with a level at least as high) joins that body: its own body
 * stays empty (0 cells). A seed whose level is below the terrain at its cell fills nothing.
 * Because seeds are handled from the highest level down, a later (lower) seed can never reach
 * an earlier body's cells (they would be connected below the earlier level), so the result does
 * not depend on how ties between bodies are broken.
 *
 * Cost: linear in the number of wet cells (each is pushed once on an explicit stack of 32-bit
 * cell indices; no recursion), plus O(n) to initialise the outputs and O(s log s) to sort s
 * seeds. Sequential and deterministic.
 *
 * @par Correctness
 * Testing/Unit/TestFloodFill.cxx (FloodFill.*: a bowl around an island next to a separate pit
 * with depths, areas and volumes worked out by hand on a grid with dx != dy; inclusive levels;
 * edges; no data; several seeds), Testing/Pipeline/TestTerroirFloodFill.cxx (Independence Lake
 * on the bundled Sagehen DEM).
 */
#ifndef terroir_hydrology_FloodFill_h
#define terroir_hydrology_FloodFill_h

#include "GridView.h"
#include "WaterBody.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

namespace terroir
{
namespace hydrology
{

/// One seed of FloodFillSeeds.
struct FloodSeed
{
  std::size_t cell = 0; ///< cell index j * nx + i
  /// Water surface, metres; NaN (the default) means the terrain height at the seed cell.
  double level = std::numeric_limits<double>::quiet_NaN();
};

/**
 * @brief Fills, from each seed, the 8-connected cells at or below the seed's level.
 * @param[in] view   elevations (metres) with optional validity mask and per-row spacing
 * @param[in] seeds  seed cells and levels (see FloodSeed); may be empty
 * @param[out] bodyId  nx*ny values: seed index + 1 on the cells that seed wets, 0 on dry and
 *                     no-data cells
 * @param[out] depth   nx*ny values: level - z on wet cells (metres), 0 on dry cells, NaN on
 *                     no-data cells
 * @param[in] progress optional, called with the fraction of seeds done (0..1)
 * @return one WaterBodyStats per seed, in the seeds' order: `level` is the level used (the
 *         terrain height for a NaN level; NaN when the seed cell holds no data), the others
 *         describe the cells that seed wet (all 0 for an empty body)
 * @pre every seed cell < nx*ny (else std::out_of_range); nx*ny < 2^31 (else
 *      std::length_error); levels are NaN or finite (+inf would flood the whole component)
 * @post a seed on a no-data cell, or with its level below the terrain at its cell, or on a
 *       cell already wet fills nothing
 * @correctness Testing/Unit/TestFloodFill.cxx, suite FloodFill
 */
std::vector<WaterBodyStats> FloodFillSeeds(const GridView<float>& view,
  const std::vector<FloodSeed>& seeds,
  std::int32_t* bodyId,
  float* depth,
  const std::function<void(double)>& progress = {});

} // namespace hydrology
} // namespace terroir

#endif

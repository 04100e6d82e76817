/**
 * @file PriorityFlood.h
 * @brief Depression filling by the improved Priority-Flood of Barnes, Lehman & Mulla (2014).
 *
 * Plain C++ (no VTK, no GL): the depression filling of vtkTerroirFloodFill's FillDepressions
 * mode, and the conditioning step that D8 flow accumulation will share.
 *
 * Method. The filled surface W is the lowest surface at or above the terrain from which water
 * can run to an outlet without climbing: W(c) = max(z(c), min over the 8 neighbours n of
 * W(n)), with W = z on the outlets. Outlets are the cells on the grid edge and the cells next
 * to a no-data cell (water leaves the known terrain there). Priority-Flood grows the region
 * that drains to the outlets from its lowest cell: the outlets are seeded into a priority
 * queue; the lowest open cell c is taken out and each unvisited neighbour n is visited once:
 * when z(n) <= W(c) it lies in a depression (or a flat) drained through c, so W(n) = W(c) and
 * n goes on a plain FIFO "pit" queue, which is emptied before the priority queue is used
 * again; otherwise W(n) = z(n) and n goes on the priority queue. The FIFO is the "improved"
 * variant (Algorithm 2 of the paper): cells inside depressions cost O(1) instead of
 * O(log n). Ties in the priority queue are broken by cell index, so the visiting order (not
 * only the result) is deterministic; the result W does not depend on the order.
 *
 * W is exactly one of the input floats (max and copies only, no arithmetic), so equality tests
 * on the filled surface (flats, DepressionWaterBodies.h) are exact.
 *
 * Cost: O(n log n) for the cells that go through the priority queue, O(1) for those that go
 * through the pit queue. Memory besides W: 1 byte per cell (visited flags), the priority
 * queue (8 bytes per queued cell) and the pit queue (4 bytes per queued cell).
 *
 * @par Correctness
 * Testing/Unit/TestFloodFill.cxx, suite PriorityFlood: equal, cell for cell, to a brute-force
 * fixed point of W(c) = max(z(c), min W(n)) on 50 random terrains (fixed mt19937_64 seed, some
 * no-data cells), plus hand-made pits, flats and no-data walls.
 *
 * @par Reference
 * Barnes, R., Lehman, C., Mulla, D. (2014). Priority-Flood: An optimal depression-filling and
 * watershed-labeling algorithm for digital elevation models. Computers & Geosciences 62:117-127.
 * doi:10.1016/j.cageo.2013.04.024
 */
#ifndef terroir_hydrology_PriorityFlood_h
#define terroir_hydrology_PriorityFlood_h

#include "GridView.h"

#include <cstddef>
#include <functional>

namespace terroir
{
namespace hydrology
{

/// Full citation of PriorityFloodBarnes2014, for logs.
extern const char* const kPriorityFloodBarnes2014Citation;

/**
 * @brief Fills every depression of `view` to its spill level (improved Priority-Flood).
 * @param[in] view    elevations (metres), optional validity mask; spacing is not used
 * @param[out] filled nx*ny values: max(z, spill level) on cells with data, NaN on no-data
 *                    cells (mask 0 or NaN elevation); may not alias view.data
 * @param[in] progress optional, called with the fraction of cells visited (0..1)
 * @return the number of cells raised (filled > z)
 * @pre nx*ny < 2^31 (else std::length_error)
 * @post filled >= z on every cell with data; from every such cell a path of 8-neighbours with
 *       non-increasing filled height leads to an outlet (an edge cell or a cell next to no
 *       data); filled is the lowest surface with that property
 * @correctness Testing/Unit/TestFloodFill.cxx, suite PriorityFlood
 */
std::size_t PriorityFloodBarnes2014(const GridView<float>& view,
  float* filled,
  const std::function<void(double)>& progress = {});

} // namespace hydrology
} // namespace terroir

#endif

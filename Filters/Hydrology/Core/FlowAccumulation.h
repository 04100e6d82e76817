/**
 * @file FlowAccumulation.h
 * @brief D8 flow directions over a depression-filled surface (O'Callaghan & Mark 1984), flats
 *        routed by breadth-first distance to their outlets (the "towards lower terrain"
 *        gradient of Garbrecht & Martz 1997, as computed by Barnes, Lehman & Mulla 2014), and
 *        D8 flow accumulation.
 *
 * Plain C++ (no VTK, no GL): the core of vtkTerroirFlowAccumulation, the classic stream
 * extraction that the water-flow simulation is compared with. The surface is first filled by
 * PriorityFloodBarnes2014 (PriorityFlood.h); this file does the rest.
 *
 * Direction codes (std::int8_t per cell), counter-clockwise from east, row j = 0 in the south
 * (north = j + 1, GridView.h):
 *
 *     3 NW   2 N   1 NE
 *     4 W     .    0 E
 *     5 SW   6 S   7 SE
 *
 * -1 (kD8Outlet): the cell drains off the known terrain: an outlet (a cell on the grid edge or
 * next to a no-data cell) with no strictly lower neighbour inside. -2 (kD8NoData): no data.
 *
 * Directions. A cell with a strictly lower neighbour (on the filled surface W) drains to the
 * neighbour of steepest descent (W(c) - W(n)) / L, L = DxAt(j) east-west, DyAt(j) north-south,
 * sqrt(DxAt(j)^2 + DyAt(j)^2) diagonally, with the spacing of the cell's own row j (as the
 * slope filter does; exact for projected grids, and per-row spacing of geographic grids changes
 * which neighbour is steepest). Drops and lengths are computed in double. Ties go to the lowest
 * code (E, NE, N, NW, W, SW, S, SE). An edge cell or a cell next to no data drains inside when
 * it has a strictly lower neighbour there, else off the terrain (-1). Only 8-neighbours inside
 * the grid with data count.
 *
 * Flats. The remaining cells have no strictly lower neighbour and are not outlets: they lie on
 * flats of W (hydro-flattened lakes, and the flats Priority-Flood makes in depressions). The
 * draining cells of the flats (cells that already have a direction, -1 included, next to a flat
 * cell of exactly the same W) are seeded, in index order, into a breadth-first search that
 * spreads through 8-neighbours of equal W: a flat cell's distance d is the number of D8 steps
 * inside the flat to its nearest draining cell. The cell then drains to the neighbour of equal
 * W at distance d - 1 that is nearest (smallest L: with square cells, a cardinal neighbour
 * before a diagonal one), ties to the lowest code. This is the gradient "towards lower terrain"
 * of Garbrecht & Martz (1997) in the breadth-first form of Barnes, Lehman & Mulla (2014);
 * their second gradient ("away from higher terrain", which makes flow converge on a flat) is
 * not applied, so flow crosses a flat in parallel lines along the shortest way out. W is a copy
 * of input floats (PriorityFlood.h), so "equal" is exact float equality.
 *
 * No cycles: along a direction, either W strictly decreases, or W stays equal and the flat
 * distance decreases by one; so (W, d) strictly decreases and every path ends at a -1 cell.
 * When `filled` is not depression-free (not the output of Priority-Flood), cells that cannot
 * reach a draining cell (pits and closed flats) get -1 too, as sinks; D8FlowDirections returns
 * their number in `D8Summary::sinks`.
 *
 * Accumulation. accumulation(c) = sum of w(u) over c and every cell u upstream of c (whose
 * path of directions passes through c). Computed in O(n) without recursion or a queue: the
 * in-degree of every cell is counted (1 byte per cell), then, in index order, every cell with
 * no unfinished upstream cell pushes its total one step downstream and walks on while the
 * receiving cell has none left either. Sums are in double in a fixed order: deterministic.
 *
 * Cost: directions O(n) plus the flats' breadth-first search (4 bytes per cell for the
 * distances, 4 bytes per flat cell for the queue); accumulation O(n), 1 byte per cell.
 * Sequential.
 *
 * @par Correctness
 * Testing/Unit/TestFlowAccumulation.cxx: hand-computed grids (tilted plane, V valley, a pit
 * filled and drained through a flat, a flat with one outlet, a no-data hole, per-row spacing),
 * and 40 random terrains (fixed mt19937_64 seed, quantised heights so that flats abound, no-data
 * cells): every direction re-derived by brute force, every valid cell reaching an outlet, and
 * accumulations equal to counting by walking every path; the outlets' accumulations sum to the
 * number of valid cells. Testing/Python/TestFlowAccumulationGrass.py compares the directions
 * with GRASS r.watershed -s on the bundled DEM.
 *
 * @par References
 * O'Callaghan, J.F., Mark, D.M. (1984). The extraction of drainage networks from digital
 * elevation data. Computer Vision, Graphics, and Image Processing 28(3):323-344.
 * doi:10.1016/S0734-189X(84)80011-0
 * Garbrecht, J., Martz, L.W. (1997). The assignment of drainage direction over flat surfaces in
 * raster digital elevation models. Journal of Hydrology 193:204-213.
 * doi:10.1016/S0022-1694(96)03138-1
 * Barnes, R., Lehman, C., Mulla, D. (2014). An efficient assignment of drainage direction over
 * flat surfaces in raster digital elevation models. Computers & Geosciences 62:128-135.
 * doi:10.1016/j.cageo.2013.01.009
 */
#ifndef terroir_hydrology_FlowAccumulation_h
#define terroir_hydrology_FlowAccumulation_h

#include "GridView.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>

namespace terroir
{
namespace hydrology
{

/// Full citations of D8FlowDirections (D8 and the flat routing), for logs.
extern const char* const kD8OCallaghanMark1984Citation;
extern const char* const kFlatsBarnes2014Citation;

/// Direction code of a cell that drains off the known terrain (an outlet).
constexpr std::int8_t kD8Outlet = -1;
/// Direction code of a no-data cell.
constexpr std::int8_t kD8NoData = -2;
/// Column offsets of the direction codes 0..7 (E, NE, N, NW, W, SW, S, SE).
constexpr int kD8Di[8] = { 1, 1, 0, -1, -1, -1, 0, 1 };
/// Row offsets of the direction codes 0..7 (north = +1).
constexpr int kD8Dj[8] = { 0, 1, 1, 1, 0, -1, -1, -1 };

/// What D8FlowDirections found.
struct D8Summary
{
  std::size_t outlets = 0;   ///< cells coded -1 (sinks included)
  std::size_t flatCells = 0; ///< cells routed by the flat rule
  std::size_t sinks = 0;     ///< cells coded -1 that are not outlets (0 on a filled surface)
};

/**
 * @brief D8 flow directions over a depression-filled surface (see the file comment).
 * @param[in] view      validity mask and spacing (DxAt, DyAt); view.data marks no data (NaN)
 * @param[in] filled    nx*ny values of the filled surface W (PriorityFloodBarnes2014 on view)
 * @param[out] direction nx*ny codes: 0..7, -1 (drains off the terrain), -2 (no data)
 * @param[in] progress  optional, called with the fraction done (0..1)
 * @return counts of outlets, flat cells and sinks
 * @pre nx*ny < 2^31 (else std::length_error); a cell has data when view says so and W is not NaN
 * @post following the directions from any cell with data ends, after at most nx*ny steps, on a
 *       cell coded -1; a code 0..7 points to a cell with data inside the grid
 * @correctness Testing/Unit/TestFlowAccumulation.cxx
 */
D8Summary D8FlowDirections(const GridView<float>& view,
  const float* filled,
  std::int8_t* direction,
  const std::function<void(double)>& progress = {});

/// How D8FlowAccumulation weighs a cell: w(u) = weight(u) * scale * (cell area if timesCellArea).
struct AccumulationOptions
{
  double scale = 1.0;         ///< factor on every weight (e.g. 1e-3 for mm -> m)
  bool timesCellArea = false; ///< multiply by the cell's area DxAt(j) * DyAt(j), m^2
  /// Optional, nx*ny amounts added as they are (not scaled) to the weights of the cells with
  /// data: flow entering from outside the grid (a tile of a distributed run receives its
  /// neighbours' flow this way).
  const double* inflow = nullptr;
  /// MultipleFlowAccumulation and DInfinityAccumulation: optional box of view cells (columns
  /// active[0]..active[1], rows active[2]..active[3]). Only its cells start with their weight
  /// (and inflow) and pass their flow on; a cell with data outside keeps what the box's cells
  /// send it (0 when none): a tile of a distributed run, its ring's cells the other tiles'.
  const int* active = nullptr;
  /// MultipleFlowAccumulation and DInfinityAccumulation: `accumulation` holds an earlier
  /// result and `inflow` (required) the change of the flow entering each cell; only the cells
  /// downstream of a non-zero change are updated (the sums being linear in the inflow): a tile
  /// of a distributed run, when the inflow from the other tiles changed at a few cells. The
  /// weights are not read; the angle is not computed.
  bool incremental = false;
  std::function<void(double)> progress; ///< optional, fraction done (0..1)
};

namespace detail
{
/// D8FlowDirections' working code: a cell with data and no direction yet.
constexpr std::int8_t kD8Unset = -3;

/// D8FlowDirections' first step: every cell with data (code kD8Unset on entry; kD8NoData
/// marks no data) drains to its neighbour of steepest descent; an outlet (on the grid edge or
/// next to no data) without a lower neighbour inside gets kD8Outlet (counted in `outlets`); the
/// rest (flat cells) stay kD8Unset. Returns the number of flat cells.
std::size_t D8SteepestDescent(const GridView<float>& view,
  const float* filled,
  std::int8_t* direction,
  const std::function<void(double)>& progress,
  std::size_t& outlets);

/// The flat rule of D8FlowDirections for flat cell (i, j) at breadth-first distance
/// distance[k] > 0: the code of its nearest neighbour of equal W at distance - 1 (smallest step
/// length, ties to the lowest code), or -1 when there is none.
int D8FlatStep(const GridView<float>& view,
  const float* filled,
  const std::int32_t* distance,
  int i,
  int j);

/// An accumulation's first pass at cell k = (i, j) with direction code d: the cell's own weight
/// into accumulation[k] (NaN for no data, 0 for a NaN weight, else weight x factor). True when
/// the cell drains (d in 0..7); false for no data and outlets; throws std::invalid_argument
/// naming `function` for any other code.
inline bool StartCell(int d,
  const float* weight,
  std::size_t k,
  double factor,
  double* accumulation,
  int i,
  int j,
  const char* function)
{
  if (d == kD8NoData)
  {
    accumulation[k] = std::numeric_limits<double>::quiet_NaN();
    return false;
  }
  const double w = weight ? static_cast<double>(weight[k]) : 1.0;
  accumulation[k] = std::isnan(w) ? 0.0 : w * factor;
  if (d == kD8Outlet)
  {
    return false;
  }
  if (d < 0 || d > 7)
  {
    throw std::invalid_argument(std::string(function) + ": invalid direction code " +
      std::to_string(d) + " at cell (" + std::to_string(i) + ", " + std::to_string(j) + ")");
  }
  return true;
}

/// Counts cell (i, j)'s downstream neighbour e (0..7) in `inDegree`; throws
/// std::invalid_argument naming `function` when it lies off the grid or has no data.
inline void CountDownstream(const GridView<float>& view,
  const std::int8_t* direction,
  int i,
  int j,
  int e,
  const char* function,
  std::uint8_t* inDegree)
{
  const int ii = i + kD8Di[e];
  const int jj = j + kD8Dj[e];
  if (ii < 0 || ii >= view.nx || jj < 0 || jj >= view.ny ||
    direction[view.Index(ii, jj)] == kD8NoData)
  {
    throw std::invalid_argument(std::string(function) + ": cell (" + std::to_string(i) + ", " +
      std::to_string(j) + ") drains off the grid or into no data");
  }
  ++inDegree[view.Index(ii, jj)];
}
} // namespace detail

/**
 * @brief D8 flow accumulation: the sum of the weights of a cell and of every cell upstream.
 * @param[in] view         grid size and spacing (for timesCellArea); data and mask unused
 * @param[in] direction    nx*ny codes from D8FlowDirections
 * @param[in] weight       nx*ny weights, or null for 1 per cell; a NaN weight counts as 0
 * @param[out] accumulation nx*ny sums (double); NaN on no-data cells (code -2)
 * @param[in] options      scale, area weighting, progress
 * @throw std::invalid_argument when a code 0..7 points off the grid or to a no-data cell, or
 *        when the directions hold a cycle
 * @post with weight null and scale 1, accumulation >= 1 on every cell with data, and the sum
 *       of accumulation over the cells coded -1 equals the number of cells with data
 * @correctness Testing/Unit/TestFlowAccumulation.cxx
 */
void D8FlowAccumulation(const GridView<float>& view,
  const std::int8_t* direction,
  const float* weight,
  double* accumulation,
  const AccumulationOptions& options = {});

} // namespace hydrology
} // namespace terroir

#endif

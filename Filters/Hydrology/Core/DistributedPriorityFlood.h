/**
 * @file DistributedPriorityFlood.h
 * @brief Depression filling and water bodies of a DEM split into tiles, one per process: the
 *        parallel Priority-Flood of Barnes (2016), with the water bodies merged across tiles.
 *
 * Plain C++ (no VTK, no MPI): vtkTerroirFloodFill's FillDepressions mode when ParaView runs it
 * in pieces. Every process calls FillDepressionsDistributed with its tile; the processes talk
 * only through a TileExchange (gather to rank 0, scatter from rank 0), which the VTK layer
 * implements with a vtkMultiProcessController and the tests with threads. Nothing but tile
 * perimeters and per-label summaries travels; no process ever holds the whole grid.
 *
 * Method (Barnes 2016, its "one-pass" variant on tiles that each fit one process):
 * 1. Each tile runs the improved Priority-Flood (PriorityFlood.h) on its own cells, seeded with
 *    the global outlets it holds (cells on the grid edge or next to no data: label 0, the
 *    "ocean") and with every other perimeter cell (a cell with a neighbour in another tile),
 *    each under a label of its own. The flood carries the label of the cell it came from, so
 *    every cell ends in the watershed of one seed; where two labels meet, the lowest level at
 *    which water passes between them, max(W(c), W(n)), is kept as a spill edge.
 * 2. Rank 0 gathers the spill edges and the perimeter cells (global index, label, height),
 *    joins neighbouring perimeter cells of different tiles by an edge of weight max(z, z'),
 *    and floods this graph from the ocean (minimax Dijkstra): S(label) is the level water must
 *    reach at that seed to get out of the grid.
 * 3. Each tile's filled surface is W(c) = max(W_tile(c), S(label(c))). This equals the serial
 *    PriorityFloodBarnes2014 bit for bit (max and copies only; the filled surface is unique).
 * 4. Water bodies (DepressionWaterBodies.h's rules): each tile labels the flats of W on its
 *    cells; rank 0 joins flats that meet across a tile edge at the same level (union-find),
 *    adds their statistics, keeps the water bodies (a filled cell, or a flat of two or more
 *    cells when flats count; at least the minimum area) and numbers them by their first cell
 *    in the whole grid's row-major order, as the serial code does. Rank 0 also returns the
 *    results of the cells around a tile that the caller needs (its output's ghost cells).
 *
 * Equal to the serial DepressionWaterBodies except for the order in which a body's areas and
 * volumes are added (tile by tile instead of breadth first): those two agree to about 1e-15
 * relative; levels, cell counts, depths, ids and the filled surface are bit-identical.
 *
 * Traffic: per tile, its perimeter (16 B per cell), its spill edges (12 B each, a few per
 * perimeter cell), a band of `reach` cells along its inner edges (16 B each) and the
 * statistics (56 B each) of the flats in that band and of the water bodies wholly inside it
 * (a dry flat inside a tile is dry whatever the others hold: not sent). Measured: about 100 B
 * per perimeter cell (TestDistributedPriorityFlood.SendsPerimetersNotTiles). Rank 0 holds
 * every tile's perimeter at once (its memory grows with the number of tiles times the
 * perimeter, not with the grid).
 *
 * @par Correctness
 * Testing/Unit/TestDistributedPriorityFlood.cxx: tiles run on threads; on random terrains
 * with no-data holes, split 1 to 12 ways in uneven blocks, the filled surface equals
 * PriorityFloodBarnes2014 and the water bodies equal DepressionWaterBodies; a lake and a
 * river valley crossing every tile edge; errors of a bad partition.
 * ParaView/Testing (label mpi): mpirun -np 1, 2, 4 pvbatch against the serial filter.
 *
 * @par Reference
 * Barnes, R. (2016). Parallel priority-flood depression filling for trillion cell digital
 * elevation models on desktops or clusters. Computers & Geosciences 96:56-68.
 * doi:10.1016/j.cageo.2016.07.001
 */
#ifndef terroir_hydrology_DistributedPriorityFlood_h
#define terroir_hydrology_DistributedPriorityFlood_h

#include "DepressionWaterBodies.h"
#include "GridView.h"
#include "WaterBody.h"

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace terroir
{
namespace hydrology
{

/// Full citation of FillDepressionsDistributed, for logs.
extern const char* const kPriorityFloodBarnes2016Citation;

/// A block of cells in the whole grid's indices, bounds included.
struct TileBox
{
  int i0 = 0;
  int i1 = -1;
  int j0 = 0;
  int j1 = -1;
  bool Contains(int i, int j) const { return i >= i0 && i <= i1 && j >= j0 && j <= j1; }
  long long Cells() const
  {
    return i1 < i0 || j1 < j0 ? 0 : static_cast<long long>(i1 - i0 + 1) * (j1 - j0 + 1);
  }
};

/// How the tiles of FillDepressionsDistributed talk. Every process calls each method in the
/// same order (a collective call); rank 0 is the root.
class TileExchange
{
public:
  virtual ~TileExchange() = default;
  virtual int Rank() const = 0;
  virtual int Size() const = 0;
  /// Rank 0 gets every rank's bytes in rank order; the others get an empty vector.
  virtual std::vector<std::vector<char>> Gather(const std::vector<char>& mine) = 0;
  /// Rank 0 passes one buffer per rank (the others pass nothing); each rank gets its own.
  virtual std::vector<char> Scatter(const std::vector<std::vector<char>>& parts) = 0;
};

/// One process's tile.
struct DistributedFillInput
{
  /// The elevations this process holds: its own cells and at least the `max(1, reach)` rings
  /// around them that lie in the grid (validity mask and per-row spacing as GridView says).
  GridView<float> view;
  int gi0 = 0; ///< whole-grid column of view cell (0, 0)
  int gj0 = 0; ///< whole-grid row of view cell (0, 0)
  /// The cells this process owns; the tiles of all processes must partition the grid.
  TileBox owned;
  int wholeNx = 0; ///< columns of the whole grid
  int wholeNy = 0; ///< rows of the whole grid
  /// Width of the ring around `owned` whose results the caller wants too (ghost cells).
  int reach = 1;
};

/// What FillDepressionsDistributed gives one process: arrays of the view's size, the results
/// on the owned cells and the ring of `reach` around them; elsewhere NaN / 0 / NaN.
struct DistributedFillResult
{
  std::vector<float> filled;          ///< the filled surface W, NaN on no-data cells
  std::vector<std::int32_t> bodyId;   ///< water body id 1.. (the serial ids), 0 dry
  std::vector<float> depth;           ///< W - z on water cells, 0 dry, NaN no data
  std::vector<WaterBodyStats> bodies; ///< every water body of the grid (same on every rank)
};

/**
 * @brief Fills the depressions and finds the water bodies of a grid split into tiles.
 * @param[in] input    this process's tile (see DistributedFillInput)
 * @param[in] options  as DepressionWaterBodies
 * @param[in] exchange the processes' collective gather and scatter
 * @return this tile's results (see DistributedFillResult)
 * @throws std::invalid_argument when the tile lacks its ring, or (on every rank alike) when the
 *         tiles do not partition the grid; std::runtime_error on a malformed message
 * @correctness Testing/Unit/TestDistributedPriorityFlood.cxx
 */
DistributedFillResult FillDepressionsDistributed(const DistributedFillInput& input,
  const DepressionWaterBodyOptions& options,
  TileExchange& exchange);

/// A seed of FloodFillSeedsDistributed: a cell of the whole grid and its level.
struct DistributedSeed
{
  std::int64_t cell = 0; ///< whole-grid row-major index j * wholeNx + i
  /// Water surface, metres; NaN (the default) means the terrain height at the seed cell.
  double level = std::numeric_limits<double>::quiet_NaN();
};

/**
 * @brief FloodFillSeeds (FloodFill.h) on a grid split into tiles: the same bodies, ids, depths
 *        and table (areas and volumes to the order of their sums).
 *
 * Every seed's body is the connected part of {cells with data, z <= its level} that holds its
 * cell (seeds taken from the highest level down, a seed already wet joining that body, as the
 * serial code; a lower seed can never reach a higher one's cells). Rank 0 first resolves the
 * levels from the tiles that hold the seed cells; each tile then labels, per seed level, the
 * components of that set on its cells and sends those that reach its band or hold a seed cell;
 * rank 0 joins them across tiles (union-find over the bands, as the water bodies of
 * FillDepressionsDistributed) and picks each seed's component. Cost: one labelling of the tile
 * per seed (O(seeds x cells)), two gathers and two replies. `filled` stays NaN.
 * @throws as FillDepressionsDistributed; also when a seed cell lies outside the grid
 * @correctness Testing/Unit/TestDistributedPriorityFlood.cxx, SeedsEqualSerialOnRandomTerrains
 */
DistributedFillResult FloodFillSeedsDistributed(const DistributedFillInput& input,
  const std::vector<DistributedSeed>& seeds,
  TileExchange& exchange);

} // namespace hydrology
} // namespace terroir

#endif

/**
 * @file DistributedWaterFlowWarmStart.h
 * @brief The coarse-to-fine warm start of the river-forming water flow (WaterFlowWarmStart.h)
 *        on a grid split into tiles, one per process: the serial warm start's initial water
 *        without any process holding the whole grid or a whole coarse level.
 *
 * Plain C++ (no VTK, no MPI): vtkTerroirWaterFlow's Rivers mode with WarmStart when ParaView
 * runs it in pieces. The processes talk only through a TileExchange (DistributedPriorityFlood.h).
 *
 * Method. Level 0 is the grid, tiled by the processes' owned boxes (they partition it). Level
 * l + 1 is WaterFlowCoarsen's 2 x 2 average of level l; coarse cell (i, j) belongs to the
 * process that owns fine cell (2i, 2j), so the owned boxes of level l + 1 are those of level l
 * halved ([ceil(a / 2), floor(b / 2)] per axis) and again partition the level. On each level a
 * process holds its owned box grown by reach + 1 (clipped to the level), where reach >= 2 is
 * wide enough that the refinement of the finer level reads only cells within reach (the
 * iterations refresh those from their owners): the fine cells within r of the owned box
 * [a, b] read coarse cells floor((a - r) / 2) .. floor((b + r) / 2), at most floor(r / 2) + 1
 * outside the coarse owned box (a odd), so reach(l + 1) = max(2, floor(reach(l) / 2) + 1)
 * (checked on every level before its run). Per level:
 * 1. the coarse heights, validity, spacing per row and rain of the owned cells from the finer
 *    level's cells (the same arithmetic as WaterFlowCoarsen), the ring's from their owners;
 * 2. the still water: FillDepressionsDistributed (Barnes 2016) on the level's tiles;
 * 3. the coarser levels first (recursion), then the level's own run: WaterFlowSimulation on the
 *    held box with the whole level's smallest spacing, SetCountWindow on the owned cells (and
 *    the level's border on the sides the owned box touches), the whole level's rain totals
 *    (SetRainTotals), and an iteration hook that refreshes the ring within reach from the
 *    owners and sums the iteration's window sums over the processes in rank order, so that
 *    every process stops at the same iteration as the serial run;
 * 4. refinement of the finer level's held cells (fine still water + 2 x coarse flowing water).
 * The exchanges go through TileExchange's Gather and Scatter (rank 0 routes them): per level,
 * the band of coarse cells once (heights, validity, rain, row spacing: 48 B a cell with its
 * index), the distributed fill's perimeters, and per iteration the band of water (16 B a
 * cell) and three sums.
 * Every rank calls every collective in the same order; a failure on one rank (a bad tile, a
 * negative rain found while a level is set up) becomes the same std::invalid_argument on all.
 * The runner must not fail on one rank alone once a level runs (the others would wait in the
 * iteration hook's exchange).
 *
 * Equal to WaterFlowWarmStart on the whole grid: the water of every held cell within its
 * reach of the owned ones bit for bit, the levels (sizes, iterations, reasons) exactly.
 *
 * @par Correctness
 * Testing/Unit/TestDistributedWaterFlowWarmStart.cxx (threads as processes).
 */
#ifndef terroir_hydrology_DistributedWaterFlowWarmStart_h
#define terroir_hydrology_DistributedWaterFlowWarmStart_h

#include "DistributedPriorityFlood.h"
#include "WaterFlowWarmStart.h"

#include <vector>

namespace terroir
{
namespace hydrology
{

/// One process's part of the fine grid (level 0) for WaterFlowWarmStartDistributed.
struct WaterFlowWarmStartTile
{
  /// The cells this process holds: its owned box grown by at least reach + 1 (clipped to the
  /// grid), elevations, validity and spacing per row as GridView says.
  GridView<float> view;
  int gi0 = 0; ///< whole-grid column of view cell (0, 0)
  int gj0 = 0; ///< whole-grid row of view cell (0, 0)
  /// Every process's owned box, by rank (the same on every process); they partition the grid.
  std::vector<TileBox> owned;
  /// Every process's reach (>= 2), by rank: the held cells within reach of the owned box must
  /// come out as the serial run's.
  std::vector<int> reach;
  int wholeNx = 0; ///< columns of the whole grid
  int wholeNy = 0; ///< rows of the whole grid
};

/**
 * @brief True when every coarse level the warm start would add (WaterFlowWarmStartOptions::
 *        coarsestSide) keeps at least one owned cell on every process (else a process would
 *        hold an empty tile: the caller then runs the serial warm start on the whole grid).
 * @param owned every process's owned box of the fine grid, by rank
 * @return true also when no coarse level fits (the warm start then leaves the water alone)
 * @throws std::invalid_argument when options.coarsestSide < 2
 */
bool WaterFlowWarmStartFitsTiles(const std::vector<TileBox>& owned,
  int wholeNx,
  int wholeNy,
  const WaterFlowWarmStartOptions& options);

/**
 * @brief WaterFlowWarmStart on a grid split into tiles (see the file comment); every process
 *        calls it (a collective call).
 * @param tile this process's part of the fine grid
 * @param[in,out] water view-sized: in, the still water (the Priority-Flood fill's depth) on the
 *                held cells within reach; out, the initial water of the caller's run there
 * @param rain uniform rain per iteration, metres (used when rainField is null)
 * @param rainField optional view-sized rain per iteration, metres (the same on every process:
 *        all give one or none)
 * @param run the runner of each level (nullptr: WaterFlowSimulation::Run); the simulation it
 *        gets already has its count window, rain totals and exchange hook
 * @return the coarse levels, coarsest first (empty: none), the same on every process
 * @throws std::invalid_argument as WaterFlowWarmStart, or when the tiles do not partition the
 *         grid, a tile lacks its ring or a level would leave a tile empty (on every rank alike);
 *         std::runtime_error on a malformed message
 */
std::vector<WaterFlowWarmStartLevel> WaterFlowWarmStartDistributed(
  const WaterFlowWarmStartTile& tile,
  double* water,
  double rain,
  const double* rainField,
  const WaterFlowWarmStartOptions& options,
  TileExchange& exchange,
  const WaterFlowLevelRun& run = nullptr);

} // namespace hydrology
} // namespace terroir

#endif

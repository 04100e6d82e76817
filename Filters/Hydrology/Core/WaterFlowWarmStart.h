/**
 * @file WaterFlowWarmStart.h
 * @brief Coarse-to-fine start of the river-forming water flow: the steady state of a grid twice
 *        as coarse, refined, is the initial water of the finer grid (nested iteration).
 *
 * Plain C++ (no VTK, no GL). Why: with rain on every cell, the water flow (WaterFlow.h) reaches
 * its steady state only when the water of the farthest cell has reached an outlet, and water
 * moves at most one cell per iteration (through lakes it spreads, slower still), so a cold
 * start costs at least the longest flow path in cells: thousands of iterations at 2048². On a
 * grid twice as coarse the path has half the cells and each iteration a quarter of the cost.
 *
 * Method. Level 0 is the grid; level l + 1 averages 2 x 2 cells of level l (the mean of the
 * cells with data; a coarse cell has data when one of its cells has; the last row or column
 * stands alone when the size is odd; spacing doubles, per row where rows differ); levels are
 * added while the coarser grid keeps at least `coarsestSide` cells on its shorter side. On
 * every level the still water is that level's Priority-Flood fill (as the river-forming mode's
 * own start). The coarsest level starts from its still water, the others from the refinement of
 * the level below, and each runs under `rule` until the outflow balances the rain, the finer
 * ones for at least `settleIterations` (WaterFlowStopRule::balanceAfter) so that their channels,
 * narrower than the coarse ones, gather their water first. Refinement: fine depth = fine still
 * water + 2 x the coarse cell's flowing water (its depth above the coarse still water). The
 * factor 2: at steady state water moves one cell per iteration on the slopes (the giver empties,
 * WaterFlow.h's "all" case), so a cell holds the flux through it per iteration; halving the
 * cells doubles the cells along every path, and the water on the way (the flux times the travel
 * time) doubles with it: a hillslope cell holds flux per unit width times its width over its
 * area, twice the coarse depth; a channel's 2 x 2 block holds two channel cells' flux instead of
 * one coarse cell's. Rain per iteration: the same depth (uniform), or the mean over the 2 x 2
 * cells (a rain field).
 *
 * The result is the initial water of the caller's run (itself under `rule`, settling first);
 * the steady state it converges to is the model's own: the coarse levels only shorten the way
 * there. Where the coarse levels miss a channel (narrower than two cells) the fine level forms
 * it from its own rain while it settles.
 *
 * Cost: each coarser level a quarter of the cells and half the path: at most 1/3 more cells than
 * the grid's in memory for the levels (built one at a time), and about 1/8 of the finer level's
 * cold-start work per level.
 *
 * @par Correctness
 * Testing/Unit/TestWaterFlowWarmStart.cxx: the coarse grid's heights, validity and spacing by
 * hand; a tilted plane (steady state known: each cell holds the water that passes it in one
 * iteration) refined to within one cell's rain of the fine steady state, and exactly there once
 * the extra has left; warm and cold runs of a V valley end at the same thalweg discharge
 * (within 1 %), the warm one sooner; a rain field, no-data cells, small grids, bad options.
 * Testing/GPU/TestWaterFlowGPU.cxx: the levels on the GPU path give the same bits.
 *
 * @par Reference
 * Nested iteration (the first leg of full multigrid): Brandt, A. (1977). Multi-level adaptive
 * solutions to boundary-value problems. Mathematics of Computation 31(138):333-390.
 */
#ifndef terroir_hydrology_WaterFlowWarmStart_h
#define terroir_hydrology_WaterFlowWarmStart_h

#include "GridView.h"
#include "WaterFlow.h"

#include <functional>
#include <vector>

namespace terroir
{
namespace hydrology
{

/// Runs a level's simulation under a rule (the caller's CPU or GPU path); returns why it stopped.
using WaterFlowLevelRun =
  std::function<WaterFlowStopReason(WaterFlowSimulation& sim, const WaterFlowStopRule& rule)>;

struct WaterFlowWarmStartOptions
{
  /// Add a coarser level while its shorter side has at least this many cells (>= 2); a grid
  /// whose shorter side is under twice this gets no warm start.
  int coarsestSide = 128;
  /// Iterations each refined level (and the caller's run) settles before the balance may stop
  /// it (WaterFlowStopRule::balanceAfter).
  long long settleIterations = 100;
  /// Rule of every level's run: the balance (tolerance > 0 required) and an iteration limit.
  WaterFlowStopRule rule;
};

/// What one coarse level did.
struct WaterFlowWarmStartLevel
{
  int nx = 0;
  int ny = 0;
  long long iterations = 0;
  WaterFlowStopReason reason = WaterFlowStopReason::MaximumIterations;
};

/// Averages 2 x 2 cells (the method above): `coarse` gets the heights, validity and spacing,
/// backed by the vectors given (valid and rows may stay empty when the fine grid has none).
void WaterFlowCoarsen(const GridView<float>& fine,
  std::vector<float>& heights,
  std::vector<std::uint8_t>& valid,
  std::vector<double>& rowDx,
  std::vector<double>& rowDy,
  GridView<float>& coarse);

/**
 * @brief The warm start (the method above).
 * @param terrain the grid (metres; validity, spacing)
 * @param[in,out] water nx*ny: in, the still water (the Priority-Flood fill's depth); out, the
 *                initial water of the caller's run (unchanged when no coarse level fits)
 * @param rain uniform rain per iteration, metres (used when rainField is null)
 * @param rainField optional nx*ny rain per iteration, metres
 * @param run the runner of each level (nullptr: WaterFlowSimulation::Run on the CPU)
 * @return the coarse levels, coarsest first (empty: none)
 * @throws std::invalid_argument as WaterFlowSimulation, or on options out of range
 */
std::vector<WaterFlowWarmStartLevel> WaterFlowWarmStart(const GridView<float>& terrain,
  double* water,
  double rain,
  const double* rainField,
  const WaterFlowWarmStartOptions& options,
  const WaterFlowLevelRun& run = nullptr);

} // namespace hydrology
} // namespace terroir

#endif

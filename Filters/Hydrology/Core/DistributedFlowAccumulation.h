/**
 * @file DistributedFlowAccumulation.h
 * @brief D8 flow directions and accumulation of a DEM split into tiles, one per process: the
 *        serial FlowAccumulation.h answer without any process holding the whole grid.
 *
 * Plain C++ (no VTK, no MPI): vtkTerroirFlowAccumulation's D8 method when ParaView runs it in
 * pieces. The processes talk only through a TileExchange (DistributedPriorityFlood.h).
 *
 * Method:
 * 1. The filled surface W: FillDepressionsDistributed (Barnes 2016), on the tile and a ring of
 *    reach + 1 cells (bit-identical to the serial PriorityFloodBarnes2014).
 * 2. Directions by steepest descent on the tile (D8FlowDirections' first step; every owned cell
 *    sees its 8 neighbours, the ring included).
 * 3. Flats: the breadth-first distance of a flat cell to its flat's nearest draining cell is a
 *    graph distance, whatever the order of the search, so the tiles compute it together by
 *    relaxation: each tile searches its own flat cells from its draining cells and from the
 *    distances its ring held at the last exchange, then the tiles exchange the distances of
 *    their perimeters (through rank 0), until no perimeter changes (the OR of every tile's
 *    flag). Distances only decrease towards the true ones; a flat crossed k times by tile
 *    edges on its shortest ways out needs about k + 1 exchanges. The flat rule then picks the
 *    serial direction (same distances, same ties).
 * 4. Accumulation, the perimeter graph of Barnes (2017) for D8: each tile accumulates its own
 *    cells as if flow leaving it vanished, and sends rank 0, for each perimeter cell (an owned
 *    cell next to another tile), its local sums and the next perimeter cell (of this tile or,
 *    across the edge, of another) on its way down, or none (an outlet inside). Rank 0 solves
 *    this forest in topological order: the flow a perimeter cell receives from outside its tile
 *    is carried down the same tile to the next perimeter cell, and across an edge the whole
 *    sum passes. Each tile gets the flow entering it at each cell and accumulates again with
 *    those inflows (FlowAccumulation.h's AccumulationOptions::inflow).
 * 5. The results of the ring of `reach` cells (the caller's ghost cells) come from their owners.
 *
 * Equal to the serial D8FlowDirections + D8FlowAccumulation: W and the directions bit for bit;
 * cell counts exactly (integers in double); areas and weighted sums to the order of their
 * additions (a cell downstream of a tile edge adds the inflow before its own upstream cells):
 * about 1e-15 relative.
 *
 * Traffic: the fill's (about 100 B per perimeter cell), 12 B per perimeter cell and exchange
 * for the flats, 16 + 8 m B per perimeter cell for the accumulation (m = 2 or 3 sums), and the
 * ring's results (9 + 8 m B per band cell). Rank 0 holds the perimeters of all tiles at once.
 *
 * @par Correctness
 * Testing/Unit/TestDistributedFlowAccumulation.cxx (threads as processes): random terrains with
 * flats and no data, 1 to 16 uneven tiles, equal to the serial code on every owned and ring
 * cell; a flat lake crossing tile edges; a river zig-zagging across an edge; bad tiles.
 * ParaView/Testing (label mpi): mpirun -np 1, 2, 4 pvbatch against the serial filter.
 *
 * @par Reference
 * Barnes, R. (2017). Parallel non-divergent flow accumulation for trillion cell digital
 * elevation models on desktops or clusters. Environmental Modelling & Software 92:202-212.
 * doi:10.1016/j.envsoft.2017.02.022
 */
#ifndef terroir_hydrology_DistributedFlowAccumulation_h
#define terroir_hydrology_DistributedFlowAccumulation_h

#include "DistributedPriorityFlood.h"
#include "FlowAccumulation.h"
#include "MultipleFlow.h"

#include <cstdint>
#include <vector>

namespace terroir
{
namespace hydrology
{

/// Full citation of D8FlowAccumulationDistributed's accumulation, for logs.
extern const char* const kFlowAccumulationBarnes2017Citation;

/// What D8FlowAccumulationDistributed weighs, besides the cell count and the area.
struct DistributedFlowOptions
{
  /// Optional, view-sized weights (view indices of DistributedFillInput), NaN counting 0.
  const float* weight = nullptr;
  double weightScale = 1.0; ///< factor on every weight (1e-3 for mm -> m)
};

/// What D8FlowAccumulationDistributed gives one process: view-sized arrays (the indices of
/// DistributedFillInput::view), the results on the owned cells and the ring of `reach` around
/// them; elsewhere NaN (W also on the ring of reach + 1), kD8NoData and NaN.
struct DistributedFlowResult
{
  std::vector<float> filled;          ///< the filled surface W, metres
  std::vector<std::int8_t> direction; ///< D8 codes as D8FlowDirections
  std::vector<double> cells;          ///< accumulation, cells (the cell itself included)
  std::vector<double> area;           ///< contributing area, m^2
  std::vector<double> weighted;       ///< weighted accumulation; empty without weights
  D8Summary summary;                  ///< the whole grid's counts (same on every rank)
  int flatExchanges = 0;              ///< exchanges the flats' distances took
  /// DispersiveFlowAccumulationDistributed: D-infinity's flow angle (radians, as
  /// DInfinityAccumulation's), empty otherwise; and the rounds its sums took.
  std::vector<float> angle;
  int accumulationRounds = 0;
};

/**
 * @brief D8 flow directions, cell counts, contributing areas and (optionally) weighted sums of
 *        a grid split into tiles (see the file comment).
 * @param[in] input    this process's tile; its view must hold the ring of reach + 1 cells
 * @param[in] options  optional weights
 * @param[in] exchange the processes' collective gather and scatter
 * @return this tile's results (see DistributedFlowResult)
 * @throws std::invalid_argument (on every rank alike) when a tile lacks its ring or the tiles do
 *         not partition the grid; std::runtime_error on a malformed message
 * @correctness Testing/Unit/TestDistributedFlowAccumulation.cxx
 */
DistributedFlowResult D8FlowAccumulationDistributed(const DistributedFillInput& input,
  const DistributedFlowOptions& options,
  TileExchange& exchange);

/// Which method DispersiveFlowAccumulationDistributed runs.
struct DispersiveFlowMethod
{
  bool dInfinity = false; ///< D-infinity (Tarboton 1997); else MFD with `mfd`
  MFDOptions mfd;         ///< MultipleFlow.h's options
};

/**
 * @brief MFD or D-infinity accumulation (MultipleFlow.h) of a grid split into tiles: steps 1-3
 *        and 5 as D8FlowAccumulationDistributed (W, the D8 codes that route the flats, the
 *        ring's results from their owners); the sums in rounds instead of the perimeter graph
 *        (a dispersive cell sends its flow to several cells, so there is no single path):
 *        each tile accumulates its own cells (AccumulationOptions::active) with the flow
 *        entering them, and sends the flow it gives the cells of other tiles (its ring of 1)
 *        to rank 0, which adds it per cell in rank order and returns it as the receivers'
 *        inflow; until no inflow changes. A flow path that crosses tile edges k times needs
 *        k + 1 rounds: the first a local accumulation, the next ones only push the change of
 *        the inflow down from the cells where it changed (AccumulationOptions::incremental;
 *        the sums are linear in the inflow). MFD spreads flow back and forth across a shared
 *        edge: 59 rounds on Sagehen in 4 pieces, D-infinity 12. Equal to the serial
 *        MultipleFlowAccumulation / DInfinityAccumulation to the order of the additions (a
 *        cell's inflow is added as one sum, and its changes after it): measured 3e-15
 *        relative; W, the directions and the angles bit for bit.
 * @param method MFD (with its options) or D-infinity
 * Other parameters, result and errors as D8FlowAccumulationDistributed.
 * @correctness Testing/Unit/TestDistributedFlowAccumulation.cxx (Dispersive* cases)
 */
DistributedFlowResult DispersiveFlowAccumulationDistributed(const DistributedFillInput& input,
  const DispersiveFlowMethod& method,
  const DistributedFlowOptions& options,
  TileExchange& exchange);

} // namespace hydrology
} // namespace terroir

#endif

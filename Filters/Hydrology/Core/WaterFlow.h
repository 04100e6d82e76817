/**
 * @file WaterFlow.h
 * @brief The hydrostatic water-flow simulation (Long (2016), section 3.3) in its 8-neighbour form.
 *
 * Plain C++ (no VTK, no GL): the CPU path of vtkTerroirWaterFlow, and the reference its GPU
 * kernel (Shaders/WaterFlow.comp) is tested against.
 *
 * State. Terrain height T (metres) and water depth W >= 0 (metres) per cell; the absolute
 * height of a cell is H = T + W. The grid is surrounded by Long (2016)'s one-cell border whose
 * heights continue the slope (2 T(edge) - T(next inward), T(edge) when the grid is one cell
 * thick); no-data cells get the lowest terrain height among their valid neighbours. Border and
 * no-data cells are outlets: they hold no water, and what flows onto them is counted as
 * outflow, never stored.
 *
 * One iteration (Jacobi: every cell reads only the previous state, so the result does not depend
 * on the order of the cells or on the number of threads). A cell i with water gives to each
 * neighbour k (8-neighbourhood) the amount
 *
 *     f_ik = s_i * c_ik * max(0, L_i - H_k)
 *
 * where c_ik = d_min / d_ik is the neighbour's closeness (d_ik the distance between cell
 * centres, d_min the smallest spacing of the grid: 1 for the nearest neighbours of a square
 * grid, 1/sqrt(2) for its diagonals), and the giver's new level L_i and scale s_i are Long (2016)'s
 * three cases of water evacuation capacity (its table 3.3), generalised from 1-D to 8
 * neighbours:
 * - none: no neighbour is lower (H_k >= H_i for all k) or W_i = 0: nothing moves;
 * - all: A_i = sum_k c_ik max(0, T_i - H_k) >= W_i: all the water leaves, split in proportion to
 *   c_ik (T_i - H_k); L_i = T_i, s_i = W_i / A_i. No receiver rises above T_i, the giver's new
 *   level;
 * - part: otherwise the giver and its lower neighbours level out: L_i is the root of
 *   sum_k c_ik max(0, L - H_k) = H_i - L (water lost = water received) on (T_i, H_i), s_i = 1.
 *   A receiver rises to H_k + c_ik (L_i - H_k) <= L_i: never above the giver's new level.
 * Restricted to 1-D with one lower neighbour (c = 1) these are Long (2016)'s equations: all the
 * water when H_k + W_i <= T_i, half the difference (H_i - H_k) / 2 otherwise, nothing when the
 * neighbour is not lower. Water only moves down (to H_k < L_i <= H_i), in proportion to the
 * drop to the giver's new level weighted by closeness.
 *
 * The new depth is W_i' = W_i - sum_k f_ik + sum_k f_ki (a gather: each cell sums what its
 * neighbours send it, each f_ki evaluated once, by the giver, with the same expression as the
 * GPU kernel's gather), so volume is conserved up to float rounding apart from what reaches an
 * outlet.
 * `Discharge` accumulates, per cell, the water that left it (depth times cell area, m^3, in
 * double). The cell area of row j is DxAt(j) * DyAt(j); between rows j and j + 1 the spacing is
 * the mean of the two rows' spacings, so a giver and its receiver always use the same c_ik.
 *
 * Stopping (WaterFlowStopRule): Long (2016)'s rule stops after the first iteration whose moved
 * volume is below `autoStopRatio` (1/1000) of the volume moved in all iterations so far; also
 * when nothing moved, or after `maximumIterations`.
 *
 * Cost: O(n) per iteration, rows in parallel through the ParallelFor callback (each block of
 * rows computes what its givers lose and send, f_ik for the 8 neighbours, for its rows plus one
 * halo row on each side, in a ring of three row buffers kept between iterations, then gathers:
 * 36 bytes of memory traffic per cell and iteration: terrain 4, water 8 + 8, discharge 8 + 8).
 * Each row is a few straight loops that the compiler vectorises, built for SSE2, AVX2 and
 * AVX-512 and chosen at run time (TERROIR_WATERFLOW_ISA = base, avx2 or avx512 narrows the
 * choice): absolute heights once per row; the "none" and "all" cases with their flows; the
 * "part" cases gathered into a structure of arrays and solved together in passes (a neighbour
 * still receives while it is below the cell and every earlier level); the gather, which adds
 * the eight flows towards each cell; the row's sums in eight fixed lanes. The same operations in
 * the same order on every path (no FMA contraction), so the same bits as WaterFlowEvacuation and
 * the GPU kernel.
 *
 * @par Correctness
 * Testing/Unit/TestWaterFlow.cxx: Long (2016)'s three 1-D cases on worked examples; conservation on
 * closed and open terrains (1e-6 relative, double sums); a tilted plane drains completely; a
 * closed bowl fills to one flat level; symmetric terrain gives a symmetric result; water never
 * moves uphill; the auto-stop rule; thread count independence; the same bits on every
 * instruction set. Testing/GPU/TestWaterFlowGPU.cxx:
 * the GPU kernel against this code.
 *
 * @par Reference
 * Long, H. (2016). Using procedural methods to generate realistic virtual rural worlds. MSc
 * minor dissertation (Computer Science), supervised by J. Gain and M.-P. Cani, section 3.3,
 * hydrostatic water flow, table 3.3 and equations 3.8-3.12 (the 1-D form generalised here).
 */
#ifndef terroir_hydrology_WaterFlow_h
#define terroir_hydrology_WaterFlow_h

#include "GridView.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

namespace terroir
{
namespace hydrology
{

/// Neighbour order used everywhere (kernel, GPU, tests): E, NE, N, NW, W, SW, S, SE
/// (north = row j + 1).
constexpr int kWaterFlowNeighbours = 8;

/**
 * Long (2016)'s water evacuation capacity in its literal form (its eq. 3.8, 2 T_n - H_(n-1) -
 * H_(n+1) in 1-D): WEC = sum_k c_ik (T_i - H_k) over all 8 neighbours, higher ones included
 * (they count negatively). Long (2016) moves no water when WEC < 0, even towards a lower
 * neighbour; with `longCapacity` (WaterFlowSimulation::SetLongCapacityRule) the model does the
 * same. Summed in neighbour order, no FMA (the kernels' order).
 */
inline double WaterFlowLongCapacity(double terrain,
  const double height[kWaterFlowNeighbours],
  const double closeness[kWaterFlowNeighbours])
{
  double wec = closeness[0] * (terrain - height[0]);
  for (int k = 1; k < kWaterFlowNeighbours; ++k)
  {
    wec += closeness[k] * (terrain - height[k]);
  }
  return wec;
}

/// What a giver cell does in one iteration: f_ik = scale * c_ik * max(0, level - H_k).
struct WaterFlowGiver
{
  double level = 0.0; ///< the giver's new absolute height L, metres
  double scale = 0.0; ///< s: 0 (none), W / A (all), 1 (part)
  double out = 0.0;   ///< water the cell gives, metres of depth (sum of f_ik)
};

/**
 * @brief One giver's evacuation (the three cases above) from its own terrain and water and its
 *        neighbours' absolute heights and closenesses.
 * @param terrain T_i, metres; @param water W_i >= 0, metres
 * @param height H_k of the 8 neighbours (order E, NE, N, NW, W, SW, S, SE), metres
 * @param closeness c_ik in (0, 1]
 */
inline WaterFlowGiver WaterFlowEvacuation(double terrain,
  double water,
  const double height[kWaterFlowNeighbours],
  const double closeness[kWaterFlowNeighbours],
  bool longCapacity = false)
{
  WaterFlowGiver g;
  g.level = terrain + water;
  if (!(water > 0.0))
  {
    return g;
  }
  if (longCapacity && WaterFlowLongCapacity(terrain, height, closeness) < 0.0)
  {
    return g; // Long (2016)'s literal rule: no water moves when WEC < 0
  }
  const double h = terrain + water;
  double all = 0.0;
  for (int k = 0; k < kWaterFlowNeighbours; ++k)
  {
    all += closeness[k] * std::max(0.0, terrain - height[k]);
  }
  if (all >= water)
  {
    g.level = terrain;
    g.scale = water / all;
  }
  else
  {
    // Part: L = (H_i + sum_R c_k H_k) / (1 + sum_R c_k) over the receivers R = {H_k < L}.
    // Start with every lower neighbour; dropping one with H_k >= L lowers L, so the set only
    // shrinks and the loop ends after at most 8 passes at the unique root.
    double num = h;
    double den = 1.0;
    unsigned receivers = 0;
    for (int k = 0; k < kWaterFlowNeighbours; ++k)
    {
      if (height[k] < h)
      {
        num += closeness[k] * height[k];
        den += closeness[k];
        receivers |= 1u << k;
      }
    }
    if (receivers == 0)
    {
      return g;
    }
    double level = num / den;
    for (bool changed = true; changed;)
    {
      changed = false;
      for (int k = 0; k < kWaterFlowNeighbours; ++k)
      {
        if ((receivers >> k & 1u) && height[k] >= level)
        {
          num -= closeness[k] * height[k];
          den -= closeness[k];
          receivers &= ~(1u << k);
          changed = true;
        }
      }
      if (changed)
      {
        level = num / den;
      }
    }
    g.level = level;
    g.scale = 1.0;
  }
  if (g.scale < 1.0)
  {
    // All: the giver is emptied exactly (its receivers' shares add up to W within rounding).
    g.out = water;
    return g;
  }
  double out = 0.0;
  for (int k = 0; k < kWaterFlowNeighbours; ++k)
  {
    out += closeness[k] * std::max(0.0, g.level - height[k]);
  }
  g.out = out;
  return g;
}

/// When a run stops.
struct WaterFlowStopRule
{
  /// Stop after an iteration that moved less than this fraction of all the water moved so far
  /// (Long (2016)'s 1/1000); 0 disables the rule.
  double autoStopRatio = 1e-3;
  /// Stop after this many iterations in all (counting earlier runs); must be >= 0.
  long long maximumIterations = 10000;
  /// With rain (WaterFlowSimulation::SetRain): stop after the first iteration whose outflow
  /// reached (1 - balanceTolerance) of the rain of one iteration (the river-forming mode's
  /// steady state); 0 disables the rule. Must be in [0, 1).
  double balanceTolerance = 0.0;
  /// The balance rule fires only after an iteration numbered at least this (counting from 1):
  /// a warm-started run (WaterFlowWarmStart.h) first settles its finer channels. Must be >= 0.
  long long balanceAfter = 0;
  /// Long (2016)'s own measure of flow for the auto-stop: the number of cells an iteration
  /// emptied completely (its section 3.3.4), instead of the volume moved. CPU only.
  bool countEmptiedCells = false;
};

/// Why a run stopped.
enum class WaterFlowStopReason
{
  AutoStop,          ///< the moved volume fell below autoStopRatio of the total moved
  NoMovement,        ///< an iteration moved nothing
  MaximumIterations, ///< the iteration limit was reached
  Balanced,          ///< the outflow balanced the rain (balanceTolerance)
};

/// Name of a stop reason ("AutoStop", "NoMovement", "MaximumIterations", "Balanced").
const char* WaterFlowStopReasonName(WaterFlowStopReason reason);

/// True when an iteration that moved `moved` after `movedBefore` in all earlier iterations ends
/// the run under Long (2016)'s rule (ratio > 0).
inline bool WaterFlowAutoStop(double moved, double movedBefore, double ratio)
{
  return ratio > 0.0 && moved < ratio * (movedBefore + moved);
}

/// True when an iteration whose outflow was `outflow` ends a run with rain `rainVolume` per
/// iteration under the balance rule (tolerance > 0, rain > 0).
inline bool WaterFlowBalanced(double outflow, double rainVolume, double tolerance)
{
  return tolerance > 0.0 && rainVolume > 0.0 && outflow >= (1.0 - tolerance) * rainVolume;
}

/**
 * @brief River centre lines of a discharge field: where water runs in a band several cells wide,
 *        the cells beside the band's crest are damped.
 *
 * For every cell with a dominant outflow direction d (0..7, neighbour order), the two neighbours
 * across the flow (directions d + 2 and d + 6, modulo 8) are compared with it: when either
 * carries more, the cell's value is multiplied by `factor`; else it is kept. This is the
 * non-maximum suppression of Canny (1986) across the flow direction, softened by the factor
 * (0: removed, 1: nothing changes). Cells without a direction (d = -1) and NaN keep their value.
 *
 * @param discharge nx*ny values (view's grid; data and validity), e.g. DischargeRate
 * @param dominant  nx*ny directions from WaterFlowSimulation::GetNetDischarge
 * @param factor    in [0, 1] (else std::invalid_argument)
 * @param thinned   nx*ny output; may not alias discharge
 */
void ThinAcrossFlow(const GridView<double>& discharge,
  const std::int8_t* dominant,
  double factor,
  double* thinned);

/// Volumes of one iteration (m^3).
struct WaterFlowIteration
{
  double moved = 0.0;   ///< water that left cells (sum of out times cell area)
  double outflow = 0.0; ///< water that reached an outlet (border or no-data cell)
  double emptied = 0.0; ///< cells that gave all their water (a count; CPU path, when counted)
};

/**
 * @brief The simulation state and its CPU iteration.
 *
 * Holds padded (nx + 2) x (ny + 2) arrays: terrain (with the border and no-data heights),
 * water depth, and the per-cell discharge.
 */
class WaterFlowSimulation
{
public:
  /// Runs body(begin, end) over disjoint row ranges covering [begin, end); may run them in
  /// parallel. The default runs body(begin, end) once.
  using ParallelFor =
    std::function<void(int begin, int end, const std::function<void(int, int)>& body)>;

  /**
   * @param terrain elevations (metres), optional validity mask, spacing (rowDx/rowDy honoured)
   * @param waterMetres nx*ny initial depths, metres (ignored on no-data cells)
   * @param smallestSpacing d_min of the closenesses, metres; 0 (default): the grid's own
   *        (SmallestSpacing). A piece of a larger grid passes the whole grid's, so that its
   *        closenesses are the whole grid's.
   * @throws std::invalid_argument on a negative or non-finite depth on a valid cell, a
   *         non-finite or non-positive spacing, or an empty grid
   */
  WaterFlowSimulation(const GridView<float>& terrain,
    const double* waterMetres,
    double smallestSpacing = 0.0);

  /// The smallest east-west or north-south spacing of the grid's rows, metres (d_min).
  static double SmallestSpacing(const GridView<float>& terrain);
  ~WaterFlowSimulation();
  WaterFlowSimulation(WaterFlowSimulation&&) noexcept;
  WaterFlowSimulation& operator=(WaterFlowSimulation&&) noexcept;

  void SetParallelFor(ParallelFor parallelFor) { this->Parallel = std::move(parallelFor); }

  /**
   * The river-forming source: `metres` of water added to every cell after the flows of each
   * iteration (W' = max(0, W - out + in) + rain), so that channels keep carrying water. Must be
   * finite and >= 0 (else std::invalid_argument); default 0 (Long (2016)'s single pulse).
   */
  void SetRain(double metres);
  /**
   * Rain per cell instead (nx*ny depths per iteration, metres; no-data cells ignored), e.g. a
   * month's standing water spread over the month. Throws std::invalid_argument on a negative or
   * non-finite depth on a cell with data.
   */
  void SetRainField(const double* metres);
  /// The rain of SetRain, or the largest of SetRainField (0: no rain), metres per iteration.
  double GetRain() const { return this->Rain; }
  /// Rain volume of one iteration, m^3 (rain times the area of the cells, summed).
  double RainVolume() const { return this->RainVolumeTotal; }
  /// Area of the cells with data, m^2.
  double TotalCellArea() const { return this->CellAreaTotal; }
  /// Rain per padded cell (SetRainField), or empty for uniform rain (GetRain()).
  const std::vector<double>& PaddedRain() const { return this->RainField; }

  /**
   * Also accumulate the net flux through every edge between two cells over the iterations
   * (what went one way less what came back, per neighbour pair; 4 doubles per padded cell).
   * In one iteration water never goes both ways across an edge (a giver sends only to lower
   * neighbours), but over iterations a lake's water goes back and forth; the net flux counts
   * only what passed. Turning it on starts the sums at zero; off frees them.
   */
  void SetNetFlux(bool on);

  /// Long (2016)'s literal capacity rule (WaterFlowLongCapacity): no water moves from a cell whose
  /// WEC is negative. Default off (the 8-neighbour generalisation above).
  void SetLongCapacityRule(bool on) { this->LongCapacity = on; }
  bool GetLongCapacityRule() const { return this->LongCapacity; }

  /// Count the cells each iteration empties (WaterFlowIteration::emptied, Long (2016)'s stop
  /// measure); off by default (the count is 0), on after a Run with rule.countEmptiedCells.
  void SetCountEmptiedCells(bool on) { this->CountEmptied = on; }
  bool GetCountEmptiedCells() const { return this->CountEmptied; }
  bool GetNetFlux() const { return !this->Edges.empty(); }
  /**
   * Net discharge (m^3, nx*ny; NaN on no-data cells): per cell, the sum over its 8 edges of the
   * net volume that left through the edge (0 for an edge water entered by). At steady state
   * this is what flows through the cell, and water exchanged within a lake does not count.
   * `dominant` (optional, nx*ny): the edge most water left by, in neighbour order (0 E, 1 NE,
   * 2 N, 3 NW, 4 W, 5 SW, 6 S, 7 SE; ties to the first), -1 where none did or on no data.
   * @pre GetNetFlux()
   */
  void GetNetDischarge(double* discharge, std::int8_t* dominant = nullptr) const;
  /// The edge sums, 4 planes of the padded grid (E, NE, N, NW of each cell; depth of the cell,
  /// positive out of it); empty when net flux is off. For the GPU path and checkpoints.
  std::vector<double>& PaddedEdges() { return this->Edges; }

  /// Rows per parallel block for `threads` threads over `rows` rows: at least 16, about four
  /// blocks per thread (each block recomputes the giver rows on its edges, and at 16 rows that
  /// and setting up its row buffers cost a tenth of the work).
  static int BlockRows(int rows, int threads)
  {
    return std::max(16, rows / (4 * std::max(1, threads)));
  }

  /**
   * Distributed runs: the cells whose volumes count, a window of the padded grid (columns
   * [column0, column1), rows [row0, row1), padded indices: 0 is the border). Step's sums
   * (moved, outflow, emptied) and StoredVolume() then add only the cells in the window: a
   * piece computed with a halo counts the cells it owns (and the grid's own border on the
   * sides where its piece touches it), so that the pieces' sums add up to the whole grid's.
   * The default (ClearCountWindow) counts every cell, with the same arithmetic as before.
   * @throws std::invalid_argument when the window is not inside the padded grid
   */
  void SetCountWindow(int column0, int column1, int row0, int row1);
  void ClearCountWindow() { this->Window[0] = this->Window[2] = -1; }
  bool HasCountWindow() const { return this->Window[0] >= 0; }

  /**
   * Rain volume of one iteration (m^3, SetRain or SetRainField) and cell area (m^2) of the
   * count window's cells (every cell without a window), added in row order: a distributed run
   * adds the pieces' and gives the whole grid's to SetRainTotals.
   */
  void WindowRainTotals(double& volume, double& area) const;
  /// Replaces RainVolume() and TotalCellArea() (a distributed run: the whole grid's sums, on
  /// which the balance rule and the rivers' least discharge rate then rest). Call after the
  /// rain is set.
  void SetRainTotals(double volume, double area);

  /**
   * Called by Step after every iteration, once the new state is in place and before the
   * iteration is recorded (histories, totals, stop rules): a distributed run refreshes the
   * halo cells of PaddedWater() from the neighbouring pieces there and replaces the
   * iteration's window sums (SetCountWindow) by their sums over every piece, so that every
   * piece records the same iteration and stops at the same one. Empty by default.
   */
  using IterationHook = std::function<void(WaterFlowSimulation& sim, WaterFlowIteration& it)>;
  void SetIterationHook(IterationHook hook) { this->Hook = std::move(hook); }

  /// One iteration on the CPU.
  WaterFlowIteration Step();

  /// Iterates until a stop rule fires; returns why.
  WaterFlowStopReason Run(const WaterFlowStopRule& rule);

  /// Records an iteration computed elsewhere (the GPU path), for the totals and stop rules.
  void RecordIteration(const WaterFlowIteration& it);

  int Nx() const { return this->NX; }
  int Ny() const { return this->NY; }
  long long Iterations() const { return this->IterationCount; }
  double TotalMoved() const { return this->MovedTotal; }     ///< m^3
  double TotalOutflow() const { return this->OutflowTotal; } ///< m^3
  double TotalEmptied() const { return this->EmptiedTotal; } ///< cells emptied, all iterations
  double InitialVolume() const { return this->Initial; }     ///< m^3
  /// Water stored on the terrain now, m^3 (double sum in row order; the window's cells only
  /// when SetCountWindow set one).
  double StoredVolume() const;

  /// Water heights above the terrain (metres, nx*ny, the WaterHeight output; NaN on no data).
  void GetWaterHeight(float* height) const;
  /// Discharge (m^3, nx*ny; NaN on no-data cells).
  void GetDischarge(double* discharge) const;

  ///@{
  /// The padded state, row-major (nx + 2) columns, row 0 = the southern border; for the GPU
  /// path and checkpoints. Discharge is kept in metres of depth (times the row's cell area on
  /// output).
  int Stride() const { return this->NX + 2; }
  const std::vector<float>& PaddedTerrain() const { return this->Terrain; }
  const std::vector<std::uint8_t>& PaddedIsCell() const { return this->IsCell; }
  std::vector<double>& PaddedWater() { return this->Water; }
  std::vector<double>& PaddedDischarge() { return this->DischargeDepth; }
  /// Closeness between a cell of padded row r and its E/W, N/S (rows r, r + 1) and diagonal
  /// (rows r, r + 1) neighbours; cell area of padded row r (m^2).
  const std::vector<double>& ClosenessEW() const { return this->CloseEW; }
  const std::vector<double>& ClosenessNS() const { return this->CloseNS; }
  const std::vector<double>& ClosenessDiagonal() const { return this->CloseDiag; }
  const std::vector<double>& CellArea() const { return this->Area; }
  ///@}

  /// Unique per simulation constructed in this process (a moved simulation keeps it): a cache
  /// key for its terrain, closenesses and areas, which never change.
  std::uint64_t Id() const { return this->Identity; }

  ///@{
  /// Volume moved and outflow of every iteration so far (m^3), in order.
  const std::vector<double>& MovedHistory() const { return this->Moved; }
  const std::vector<double>& OutflowHistory() const { return this->Outflow; }
  ///@}

  /**
   * Forgets the iterations after `iterations` (histories and totals), after the caller put the
   * padded water and discharge of that iteration back (checkpoints).
   * @pre 0 <= iterations <= Iterations()
   */
  void TruncateHistory(long long iterations);

  /**
   * The iteration after which a run under `rule` from iteration 0 stopped, and why, read from
   * the histories; false when the histories end before any rule fired.
   */
  bool FindStop(const WaterFlowStopRule& rule,
    long long& iteration,
    WaterFlowStopReason& reason) const;

  /**
   * The stop rules after one iteration `it`, the `iteration`-th (counting from 1; movedBefore:
   * the volume moved by the iterations before it): no movement, Long (2016)'s auto-stop, the
   * balance of outflow and rain, in that order; true with the reason when one fires (with
   * rule.countEmptiedCells the auto-stop compares it.emptied with emptiedBefore, the cells emptied
   * by the earlier iterations). Every path (Run, FindStop, the filter's loop, the GPU path) asks
   * this one function.
   */
  bool StopsAfter(const WaterFlowIteration& it,
    long long iteration,
    double movedBefore,
    const WaterFlowStopRule& rule,
    WaterFlowStopReason& reason,
    double emptiedBefore = 0.0) const;

private:
  struct ScratchPool;
  struct RowPass;
  /// One iteration over the rows [begin, end) (a RowPass on a scratch from the pool).
  void RowBlock(int begin, int end);

  int NX = 0;
  int NY = 0;
  std::uint64_t Identity = 0;
  std::vector<float> Terrain;
  std::vector<std::uint8_t> IsCell;
  std::vector<double> Water;
  std::vector<double> NextWater;
  std::vector<double> DischargeDepth;
  std::vector<double> CloseEW;
  std::vector<double> CloseNS;
  std::vector<double> CloseDiag;
  std::vector<double> Area;
  std::vector<double> RowMoved;
  std::vector<double> RowOutflow;
  std::vector<double> Moved;
  std::vector<double> Outflow;
  ParallelFor Parallel;
  /// Row buffers of finished blocks, for the next blocks (RowBlock).
  std::unique_ptr<ScratchPool> Scratch;
  long long IterationCount = 0;
  double MovedTotal = 0.0;
  double OutflowTotal = 0.0;
  double Initial = 0.0;
  double Rain = 0.0;
  double RainVolumeTotal = 0.0;
  std::vector<double> RainField;   ///< per padded cell, or empty (uniform)
  std::vector<double> RainRowData; ///< one padded row of the uniform rain
  double CellAreaTotal = 0.0;
  bool LongCapacity = false;
  bool CountEmptied = false;
  double EmptiedTotal = 0.0;
  std::vector<double> Emptied;
  std::vector<double> RowEmptied;
  std::vector<double> Edges;
  int Window[4] = { -1, 0, -1, 0 }; ///< SetCountWindow: columns, rows (padded); -1: none
  IterationHook Hook;
};

} // namespace hydrology
} // namespace terroir

#endif

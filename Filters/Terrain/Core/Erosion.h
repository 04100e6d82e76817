/**
 * @file Erosion.h
 * @brief Hydraulic erosion on the virtual-pipe water model and thermal erosion (soil slip),
 * after Mei, Decaudin & Hu (2007) as written up by Weiss (2015, section VI) and Dunn (2015,
 * sections 2.1-3.3). Plain C++ (no VTK, no GL): the CPU reference of the erosion filter.
 *
 * Grid. Row-major `nx` x `ny` cells, row j = 0 in the south (GridView's layout); row j has
 * east-west spacing lx_j = DxAt(j) and north-south spacing ly_j = DyAt(j), cell area
 * a_j = lx_j ly_j. A north-south pipe between rows j and j + 1 has the mean of their spacings.
 * Fluxes are volume rates (m^3/s) and belong to the giving cell, so each pipe's volume leaves
 * one cell and enters the other exactly: water and sediment are conserved up to float rounding.
 *
 * Hydraulic step (ErosionHydraulicStep), each pass reading only the previous pass's arrays
 * (Jacobi, ping-pong; the order of the cells does not matter, so it can become compute shaders):
 * 1. Rain (Weiss eq. 10): d1 = d + dt r.
 * 2. Outflow flux through the four pipes (Weiss eq. 11-12, Dunn eq. 2.1):
 *    f_k = max(0, f_k + dt A g dh_k / l_k), dh_k = (b + d1) - (b_k + d1_k). With the soft
 *    outflow threshold (Dunn eq. 3.1, optional) each pipe is then capped at
 *    O_min + s_O |dh_k|. Then all four are scaled by K = min(1, d1 a / (dt sum f)) (Weiss
 *    eq. 13, Dunn eq. 2.2) so that no cell gives more water than it has.
 * 3. Water height (Weiss eq. 14-15): d2 = d1 + dt (sum f_in - sum f_out) / a; velocity
 *    (Weiss eq. 16, Mei et al.): u = dWx / (ly d_mean), v = dWy / (lx d_mean) with
 *    dWx = (f_E[i-1] - f_W[i] + f_E[i] - f_W[i+1]) / 2 and d_mean = (d1 + d2) / 2; zero where
 *    d_mean < dryDepth.
 * 4. Erosion and deposition (Weiss eq. 17-20, Dunn eq. 2.3-2.5): the tilt sin(alpha) with
 *    tan(alpha) = max_k |b - b_k| / l_k over the four pipes (Weiss eq. 17 over the pipe length),
 *    clamped to [minTilt, maxTilt]; capacity C = K_c sin(alpha) |(u, v)| (times
 *    min(1, d2 / capacityDepth) when capacityDepth > 0: ours, damps thin fast films); if C > s
 *    the bed gives K_s (C - s) to the suspended sediment, else K_d (s - C) settles on the bed
 *    (K_s, K_d act per step, as in both sources). With a soil layer (ours, after Weiss section
 *    VI-B2: soil erodes more easily than rock), soil goes first at K_s; once it is used up,
 *    the rest of the deficit is taken from rock at K_s,rock; deposits become soil. Options
 *    from Weiss section VI-B2: K_s and K_d varying with the depth eroded since the start
 *    (his eq. 24) and a bound on the bed's total change.
 * 5. Sediment transport (Weiss eq. 21): s = s'(i - u dt / lx, j - v dt / ly), bilinear,
 *    positions clamped to the grid; then Dunn's (section 3.3) mass rescaling: the transported
 *    field is multiplied by k = m1 / m2, the area-weighted totals before and after transport
 *    (summed in double, row by row in a fixed order), so total suspended sediment is kept.
 * 6. Evaporation (Weiss eq. 22-23): d = d2 (1 - K_e dt T) with T = 1 or a per-cell factor
 *    (Weiss's temperature from 0 = cold to 1 = hot). Cells left with d < dryDepth drop their
 *    sediment on the bed (Dunn section 3.3).
 *
 * Boundaries. Closed: no pipe leaves the grid, no-data cells are walls. Sea: the grid is
 * surrounded by sea at `seaLevel`; valid cells with b <= seaLevel and no-data cells are sea.
 * Sea cells hold no water and give none; their surface is seaLevel for their neighbours'
 * pipes (so coasts and edges drain into the sea); the water that reaches them, or leaves
 * through the edge, is removed and reported (ErosionStepStats::waterToSea). They do not erode;
 * sediment carried into a valid sea cell settles there (Weiss section VI-B3). Their velocity is
 * that of the inflow over the sea depth max(seaLevel - b, dryDepth), with the back-traced
 * position kept within one cell (ours, so that sediment is carried into the sea). No-data cells
 * hold no sediment and take no part in its transport, so sediment never leaves the grid.
 *
 * Thermal step (ErosionThermalStep; soil slip after Mei et al. 2007 and Dunn section 3.2.1):
 * over the eight neighbours, a cell whose height exceeds a lower neighbour's by more than
 * tan(talus) times their distance gives it q = rate (excess) / 16 (height of the giver; the
 * 1/16 keeps the Jacobi update monotone on the eight-neighbour stencil, whose Laplacian's
 * eigenvalues are at most 12); the talus is the soil's where the giver has soil (or there is
 * one material), else the rock's. A soil giver never gives more than its soil (its pipes are
 * scaled down together); what moves becomes soil at the receiver. Volume is conserved.
 *
 * Arithmetic: float state and float operations (no fused multiply-add, the library is built
 * with -ffp-contract=off), totals in double. The bed and the water carry their rounding error
 * in a second float (TwoSum compensation): a float bed of 1000 m has a 61 micrometre spacing,
 * larger than many steps' erosion, and a full cell's slow leak to its neighbour is below half
 * its spacing; plain float would lose both, compensated they add up. Every cell and every
 * reduction in a fixed order, so the same bits on every run and for any ParallelFor split.
 *
 * @par Correctness
 * Testing/Unit/TestErosion.cxx (suite TerroirErosionCore): a hand-worked 3x3 flux step; dam
 * break volume on a closed domain; a still lake stays still; a tilted plane drains into the
 * sea with its mass balance; erosion/deposition balance in a uniform flow, with soil over rock;
 * dry and sea cells settle; evaporation factor and rain; sediment and water conservation over
 * 1000 steps; no negative water or sediment on random terrains; thermal erosion relaxes a
 * spike and a cliff to the talus angle, conserving material, soil before rock; the same bits
 * for any row split. Documentation/Erosion.md has the measured numbers.
 *
 * @par References
 * X. Mei, P. Decaudin, B.-G. Hu, "Fast hydraulic erosion simulation and visualization on GPU",
 * Pacific Graphics 2007. S. Weiss, "Procedural Terrain", CS6491 final project, Georgia Tech,
 * 2015, section VI. J. Dunn, "Building Dynamic & Interactive Natural Game Worlds", MSc
 * dissertation, Trinity College Dublin, 2015, sections 2.1-3.3.
 */
#ifndef terroir_terrain_Erosion_h
#define terroir_terrain_Erosion_h

#include "GridView.h"

#include <cstdint>
#include <functional>
#include <vector>

namespace terroir
{
namespace terrain
{

/// What happens at the grid's edge and at no-data cells.
enum class ErosionBoundary
{
  Closed = 0, ///< no flux leaves the grid; no-data cells are walls
  Sea = 1     ///< outside and no-data cells, and valid cells with b <= seaLevel, are sea
};

/**
 * Parameters of the hydraulic step. Defaults are Weiss (2015)'s (section VI-A): g = 10,
 * dt = 0.01, K_c = 0.5, K_s = K_d = 0.1, K_e = 0.005, tilt clamped to [0.005, 0.1].
 */
struct ErosionParams
{
  double timeStep = 0.01;      ///< dt, seconds (> 0)
  double gravity = 10.0;       ///< g, m/s^2 (> 0)
  double pipeArea = 0.0;       ///< A, m^2 (>= 0); 0: each pipe's length squared (Weiss: 1 cell)
  double capacity = 0.5;       ///< K_c, sediment capacity constant (>= 0)
  double dissolving = 0.1;     ///< K_s of soil (or of the single material), per step, [0, 1]
  double dissolvingRock = 0.1; ///< K_s of rock under the soil layer, per step, [0, 1]
  double deposition = 0.1;     ///< K_d, per step, [0, 1]
  double evaporation = 0.005;  ///< K_e, 1/s (>= 0, K_e dt <= 1)
  double capacityDepth = 0.0;  ///< m (>= 0): C is scaled by min(1, d / capacityDepth); 0: off
  double minTilt = 0.005;      ///< lower clamp of sin(alpha), [0, 1]
  double maxTilt = 0.1;        ///< upper clamp of sin(alpha), [minTilt, 1]
  /// Weiss's eq. 24: K_s 2^(-db / f_s) and K_d 2^(db / f_d), db = original - b (m eroded
  /// since the start), each clamped to 1; f_s, f_d in m (>= 0), 0: constant (the default).
  double halvingDepthErosion = 0.0;
  double halvingDepthDeposition = 0.0;
  /// Weiss's bound on the total change of the bed by erosion and deposition, |b - original|
  /// <= maxBedChange, m (>= 0); 0: none. Dry and sea cells still settle all their sediment.
  double maxBedChange = 0.0;
  double dryDepth = 1e-5;        ///< m (>= 0): below it no velocity, and sediment settles
  bool softOutflow = false;      ///< cap each pipe at O_min + s_O |dh| (Dunn eq. 3.1)
  double softOutflowMin = 0.0;   ///< O_min, m^3/s (>= 0)
  double softOutflowScale = 1.0; ///< s_O, m^2/s (>= 0)
  ErosionBoundary boundary = ErosionBoundary::Closed;
  double seaLevel = 0.0; ///< m, for ErosionBoundary::Sea (finite)
};

/// Parameters of the thermal step (soil slip).
struct ThermalParams
{
  double talusSoilDeg = 33.0; ///< talus angle of soil (or the single material), degrees (0, 90)
  double talusRockDeg = 60.0; ///< talus angle of rock under the soil layer, degrees (0, 90)
  double rate = 1.0;          ///< fraction of the excess moved per step, (0, 1]
};

/**
 * The simulation state: the grid and the per-cell arrays (float, nx*ny each, row j = 0 in
 * the south). Make it with MakeErosionState; the arrays may be edited between steps (a brush).
 */
struct ErosionState
{
  int nx = 0;
  int ny = 0;
  std::vector<double> rowDx;       ///< ny east-west spacings, metres
  std::vector<double> rowDy;       ///< ny north-south spacings, metres
  std::vector<std::uint8_t> valid; ///< nx*ny, 1 valid, 0 no data (empty: all valid)
  std::vector<float> terrain;      ///< b: bed height (rock + soil), m
  std::vector<float> original;     ///< the bed at the start (Weiss eq. 24 and his cap), m
  /// Rounding residues: the bed is terrain + terrainResidue and the water water + waterResidue
  /// (about 1e-7 of the value; kept so that small changes add up, see the file comment).
  /// ErosionMeasure includes them; zero them after editing terrain or water by hand.
  std::vector<float> terrainResidue, waterResidue;
  std::vector<float> soil; ///< soil thickness over rock, m (empty: one material)
  /// Optional per-cell multipliers (>= 0; empty: 1), e.g. from vegetation (Vegetation.h:
  /// VegetationResistance): on K_s and K_s,rock (erosion) and on the tangent of the talus angle
  /// (soil slip; the giver's factor, so both sides of a pipe agree).
  std::vector<float> erosionFactor, talusFactor;
  std::vector<float> water;              ///< d: water depth, m
  std::vector<float> sediment;           ///< s: suspended sediment, m (height of bed it would make)
  std::vector<float> fluxW, fluxE;       ///< outflow to the west (Weiss f^L) and east (f^R), m^3/s
  std::vector<float> fluxS, fluxN;       ///< outflow to the south (f^B) and north (f^T), m^3/s
  std::vector<float> velocityU;          ///< u, east, m/s
  std::vector<float> velocityV;          ///< v, north, m/s
  std::vector<float> scratch[6];         ///< ping-pong buffers of the passes (contents undefined)
  std::vector<std::uint8_t> scratchKind; ///< per-cell kind during a step (contents undefined)

  std::size_t Size() const { return static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny); }
  bool IsValid(std::size_t c) const { return valid.empty() || valid[c] != 0; }
  double CellArea(int j) const { return rowDx[j] * rowDy[j]; }
};

/**
 * @brief A state with the terrain, spacing and mask of `terrain`, no water, no sediment and
 *        zero fluxes.
 * @param terrain bed heights (m), spacing (rowDx/rowDy honoured), optional validity mask
 * @param soil    nx*ny soil thicknesses over rock (m, >= 0), or nullptr for one material
 * @throws std::invalid_argument for an empty grid, a non-positive or non-finite spacing, a
 *         non-finite height on a valid cell, or a negative soil thickness
 */
ErosionState MakeErosionState(const GridView<float>& terrain, const float* soil = nullptr);

/// What one step moved, volumes in m^3 (double sums in a fixed order).
struct ErosionStepStats
{
  double rain = 0.0;          ///< water added by rain (sea cells included)
  double evaporated = 0.0;    ///< water removed by evaporation
  double waterToSea = 0.0;    ///< water removed by the sea boundary
  double waterClamped = 0.0;  ///< negative rounding residue set to zero (about 1 ulp a cell)
  double eroded = 0.0;        ///< bed volume taken into suspension
  double deposited = 0.0;     ///< suspended volume settled (deposition, dry and sea cells)
  double sedimentScale = 1.0; ///< Dunn's k = m1 / m2 of this step (1 when nothing moved)
};

/// Area-weighted totals of a state, m^3 (double sums, row by row).
struct ErosionTotals
{
  double terrain = 0.0;  ///< sum of b a over valid cells
  double soil = 0.0;     ///< sum of soil a
  double water = 0.0;    ///< sum of d a
  double sediment = 0.0; ///< sum of s a
};

/// Runs body(begin, end) over disjoint row ranges covering [begin, end), maybe in parallel.
using ErosionParallelFor =
  std::function<void(int begin, int end, const std::function<void(int, int)>& body)>;

/**
 * @brief One hydraulic-erosion step (passes 1-6 of the file comment).
 * @param[in,out] state   the simulation state
 * @param[in] params      constants; checked (std::invalid_argument names the bad one)
 * @param[in] rain        nx*ny rain rates r (m/s, >= 0), or nullptr for none
 * @param[in] evaporationFactor nx*ny factors T (>= 0; Weiss's temperature, 0 cold to 1 hot)
 *                        multiplying K_e, or nullptr for 1
 * @param[in] parallelFor row scheduler, or empty to run the rows in order
 * @return the volumes moved (for mass balances)
 * @throws std::invalid_argument for a parameter out of range or a state whose arrays do not
 *         have nx*ny entries
 * @post water, sediment and soil >= 0
 */
ErosionStepStats ErosionHydraulicStep(ErosionState& state,
  const ErosionParams& params,
  const float* rain = nullptr,
  const float* evaporationFactor = nullptr,
  const ErosionParallelFor& parallelFor = {});

/// What one thermal step found and moved.
struct ThermalStepStats
{
  double moved = 0.0;     ///< volume moved, m^3
  double maxExcess = 0.0; ///< largest height above the talus, over all pipes before the step, m
};

/**
 * @brief One thermal-erosion (soil slip) step (see the file comment).
 * @param[in,out] state  terrain (and soil, if any) are updated; water and sediment untouched
 * @param[in] params     talus angles and rate; checked (std::invalid_argument)
 * @param[in] parallelFor row scheduler, or empty
 * @throws std::invalid_argument as ErosionHydraulicStep
 * @post every valid cell's bed changes by what its neighbours give minus what it gives; no-data
 *       cells take no part; soil >= 0
 */
ThermalStepStats ErosionThermalStep(ErosionState& state,
  const ThermalParams& params,
  const ErosionParallelFor& parallelFor = {});

/// Area-weighted totals of `state` (valid cells only).
ErosionTotals ErosionMeasure(const ErosionState& state);

/// Throws std::invalid_argument naming the first parameter out of its range.
void CheckErosionParams(const ErosionParams& params);
/// Throws std::invalid_argument naming the first parameter out of its range.
void CheckThermalParams(const ThermalParams& params);

} // namespace terrain
} // namespace terroir

#endif

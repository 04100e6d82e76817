/**
 * @file Atmosphere.h
 * @brief Dunn's (2015) atmosphere: wind on the virtual-pipe model as a pressure field, vapour
 * carried by the wind, rain where the vapour exceeds the air's capacity. Plain C++ (no VTK, no
 * GL): the CPU reference that a filter couples with the erosion and vegetation cores on one
 * time step.
 *
 * Grid: Erosion.h's (row-major nx x ny, row j = 0 in the south, row spacings rowDx/rowDy, cell
 * area a_j, pipes between rows with the mean spacing, optional validity mask). Vapour is a depth
 * of water over the cell (m, Dunn's vapour matrix, section 3.5.1); volumes are depth times area.
 *
 * AtmosphereStep (Dunn sections 2.3, 3.5.2, 3.5.3; his Table 4.2: AddPrevailingWind,
 * ComputeOutflow, ComputeAirPressure, ComputeVelocities, ComputeVapourTransport). Each pass
 * reads only the previous pass's arrays (Jacobi), so the order of the cells does not matter:
 * 1. Prevailing wind (AtmospherePrevailingWind; Dunn: pressure is added on one side and removed
 *    on the other). The wind blows FROM `windDirectionDeg` (meteorological: degrees clockwise
 *    from north, 270 = from the west, blowing east), i.e. towards d = (-sin t, -cos t) (east,
 *    north). Each valid edge cell gets w = sum over its grid edges of -(n . d) (n the edge's
 *    outward normal; a corner has two) and its air height changes by S dt w: up on the upwind
 *    edges, down on the downwind ones (never below zero). The larger of the two totals is
 *    scaled to the smaller, so the total air mass is unchanged (up to float rounding). Vapour is
 *    neither created nor removed there.
 * 2. Outflow (ComputeOutflow; Weiss eq. 11-13 with the air height h as the surface, Dunn:
 *    heights in the fluid simulation are air pressure; the terrain only shapes the pipes):
 *    f_k = max(0, f_k + dt g A_k (h - h_k) / l_k), then scaled by K = min(1, h a / (dt sum f)).
 *    Pipe cross-section (Dunn 3.5.2: smaller uphill, larger on flats and downhill; the law is
 *    ours): A_k = A0 clamp(1 - c max(0, (b_k - b) / l_k), A_min / A0, 1), A0 = pipeArea or l^2.
 * 3. Air height and velocity (ComputeAirPressure, ComputeVelocities; Weiss eq. 14-16):
 *    h2 = h + dt (sum f_in - sum f_out) / a; u = dWx / (ly h_mean), v = dWy / (lx h_mean),
 *    h_mean = (h + h2) / 2; zero where h_mean < minAirHeight.
 * 4. Vapour transport (ComputeVapourTransport; Dunn sections 2.3 and 3.5.2: "the same method of
 *    transport and mass conservation" as the sediment): q' = q(i - u dt / lx, j - v dt / ly),
 *    bilinear, clamped to the grid, then multiplied by Dunn's k = m1 / m2 (area-weighted totals
 *    before and after, double, row order), so total vapour is kept.
 * 5. Rain (Dunn 2.3, 3.5.3: rain where the humidity ratio exceeds the capacity, which varies
 *    with temperature and pressure; the pressure from the wind model, the temperature from the
 *    height): x = q rho_w / M (M: the air column's mass per area, ours), x_s = Magnus
 *    (SaturationHumidityRatio) at T and p = p0 clamp(h / h_ref, 1/2, 2), T = the given
 *    temperature or T0 - Gamma b; where x > x_s a fraction r_c dt of the excess condenses:
 *    rain = r_c dt (x - x_s) M / rho_w (m), and the vapour loses the same depth.
 *
 * Boundary: closed. No air or vapour leaves the grid; no-data cells are walls that hold neither.
 * The prevailing wind's edge source and sink (pass 1) move air only.
 *
 * Coupling (one time step of a filter): ErosionHydraulicStep (its own evaporation K_e off, rain =
 * last step's rain / dt) -> AtmosphereEvaporationFields -> EvaporationDunn2015Step (vapour +=
 * evaporated) -> AtmosphereStep (rain out). Surface water + vapour + rain in flight is then
 * conserved up to float rounding on a closed grid.
 *
 * Arithmetic: float state and operations (built with -ffp-contract=off), totals in double summed
 * row by row in order: the same bits for any ParallelFor split. The air height carries its
 * rounding error in a second float (TwoSum, as the water in Erosion.h): the edge source and sink
 * change the same cells by the same amounts every step, and plain float would round them the
 * same way every time, a drift of total air.
 *
 * @par Correctness
 * Testing/Unit/TestAtmosphere.cxx (suite TerroirAtmosphereCore): still air stays still; a
 * hand-worked 3x3 flux step, with an uphill pipe and the K scaling; vapour transport by hand;
 * an air dam break conserves air; a prevailing wind from the west blows east with v = 0, and
 * rotated by 90 degrees on the transposed grid gives the transposed wind; the wind's source and
 * sink by hand; wind is slower up a ridge than on the flat; vapour conserved over 1000 steps,
 * never negative; rain by hand, none below capacity; a plume carried up a slope rains on the
 * slope; the coupled water cycle with EvaporationDunn2015Step conserves water; any row split;
 * parameter errors. Documentation/Atmosphere.md has the numbers.
 *
 * Stability (as the water model; not checked): roughly dt^2 g A0 / (l a) <= 1/4, i.e.
 * dt <= sqrt(l / g) / 2 with A0 = l^2; a physical face A0 = l h_ref allows larger steps.
 *
 * @par References
 * J. Dunn, "Building Dynamic & Interactive Natural Game Worlds", MSc dissertation, Trinity
 * College Dublin, 2015, sections 2.3, 3.5, 4.2 (Table 4.2), 5.2.1 (Figure 5.3). S. Weiss,
 * "Procedural Terrain", Georgia Tech, 2015, section VI (the pipe model's equations).
 */
#ifndef terroir_terrain_Atmosphere_h
#define terroir_terrain_Atmosphere_h

#include "Erosion.h"
#include "GridView.h"

#include <cstdint>
#include <vector>

namespace terroir
{
namespace terrain
{

/**
 * Parameters of the atmosphere. Dunn gives the mechanisms but no numbers: g, dt and A0 follow
 * the water model (Weiss section VI-A); T0, Gamma, p0 are the standard atmosphere's; the rest is
 * ours (Documentation/Atmosphere.md gives the reasons).
 */
struct AtmosphereParams
{
  double timeStep = 0.01;          ///< dt, s (> 0)
  double gravity = 10.0;           ///< g of the pipe model, m/s^2 (> 0)
  double pipeArea = 0.0;           ///< A0, m^2 (>= 0); 0: each pipe's length squared (as Erosion.h)
  double uphillDamping = 2.0;      ///< c: A shrinks by c per unit uphill tangent (>= 0), ours
  double minAreaFraction = 0.1;    ///< A_min / A0, (0, 1], ours
  double windDirectionDeg = 270.0; ///< where the prevailing wind blows FROM, degrees from north
  double windStrength = 0.0;       ///< S, m/s of air height added at a square upwind edge (>= 0)
  double minAirHeight = 1e-5;      ///< m (>= 0): below it the velocity is zero
  double seaLevelTemperature = 15.0; ///< T0, C at b = 0 when no temperature is given
  double lapseRate = 6.5;            ///< Gamma, C per km (finite)
  double surfacePressure = 101325.0; ///< p0, Pa at air height h_ref (> 0)
  double airColumnMass = 1000.0;     ///< M, kg/m^2 of air holding the vapour (> 0), ours
  double condensationRate = 1.0;     ///< r_c, 1/s (>= 0, r_c dt <= 1), ours
  double waterDensity = 1000.0;      ///< rho_w, kg/m^3 (> 0)
};

/**
 * The atmosphere's state (float, nx*ny each; Dunn section 4.2.1: air pressure, vapour, four
 * outflows, two velocities). Make it with MakeAtmosphereState; air and vapour may be edited
 * between steps.
 */
struct AtmosphereState
{
  int nx = 0;
  int ny = 0;
  std::vector<double> rowDx;       ///< ny east-west spacings, m
  std::vector<double> rowDy;       ///< ny north-south spacings, m
  std::vector<std::uint8_t> valid; ///< nx*ny, 1 valid, 0 no data (empty: all valid)
  double referenceHeight = 0.0;    ///< h_ref, m: the air height at which p = p0
  std::vector<float> air;          ///< h: air column height (pressure), m
  /// Rounding residue of h (TwoSum): the air is air + airResidue; AtmosphereMeasure includes it.
  /// Zero it after editing air by hand.
  std::vector<float> airResidue;
  std::vector<float> vapour;       ///< q: water vapour as a depth of water, m
  std::vector<float> fluxW, fluxE; ///< air outflow to the west and east, m^3/s
  std::vector<float> fluxS, fluxN; ///< air outflow to the south and north, m^3/s
  std::vector<float> velocityU;    ///< u, east, m/s
  std::vector<float> velocityV;    ///< v, north, m/s
  std::vector<float> scratch[6];   ///< ping-pong buffers (contents undefined)

  std::size_t Size() const { return static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny); }
  bool IsValid(std::size_t c) const { return valid.empty() || valid[c] != 0; }
  double CellArea(int j) const { return rowDx[j] * rowDy[j]; }
};

/**
 * @brief A still atmosphere on the grid of `grid` (its spacings and mask; its data is not read).
 * @param airHeight h on every valid cell, m (> 0); also h_ref (p = p0 there)
 * @param vapour    nx*ny vapour depths (m, >= 0), or nullptr for dry air
 * @throws std::invalid_argument for an empty grid, a bad spacing, or a value out of range
 */
AtmosphereState MakeAtmosphereState(const GridView<float>& grid,
  double airHeight,
  const float* vapour = nullptr);

/// What one AtmosphereStep moved: volumes in m^3 (double sums in a fixed order).
struct AtmosphereStepStats
{
  double windAir = 0.0;     ///< air added on the upwind edge (= removed on the downwind one)
  double rain = 0.0;        ///< vapour condensed into rain
  double vapourScale = 1.0; ///< Dunn's k = m1 / m2 of the vapour transport
};

/**
 * @brief One atmosphere step (passes 1-5 of the file comment).
 * @param[in,out] state     the atmosphere
 * @param[in] params        checked (std::invalid_argument names the bad one)
 * @param[in] terrain       nx*ny bed (or water surface) heights b, m: pipe areas, temperature
 * @param[in] temperature   nx*ny air temperatures, C (finite on valid cells), or nullptr for
 *                          T0 - Gamma b / 1000
 * @param[in,out] rain      nx*ny: += rain of this step, m of water; or nullptr
 * @param[in] parallelFor   row scheduler, or empty to run the rows in order
 * @post air and vapour >= 0; total air and total vapour + rain unchanged up to float rounding
 */
AtmosphereStepStats AtmosphereStep(AtmosphereState& state,
  const AtmosphereParams& params,
  const float* terrain,
  const float* temperature = nullptr,
  float* rain = nullptr,
  const ErosionParallelFor& parallelFor = {});

/**
 * @brief Pass 1 alone (Dunn's AddPrevailingWind): the edge source and sink of air.
 * @return the air volume added on the upwind edge, m^3 (the same is removed downwind)
 */
double AtmospherePrevailingWind(AtmosphereState& state, const AtmosphereParams& params);

/**
 * @brief The pipe cross-section of pass 2: A0 clamp(1 - c max(0, rise / length), A_min/A0, 1).
 * @param length pipe length l, m; @param rise b_k - b, m (the neighbour's height minus ours)
 * @return A, m^2, with A0 = pipeArea or length^2
 */
float AtmospherePipeArea(const AtmosphereParams& params, float length, float rise);

/**
 * @brief The atmosphere as Dunn's eq. 2.6 sees it (EvaporationFields of Vegetation.h): per cell
 * the capacity x_s and humidity ratio x of pass 5 and the wind speed |(u, v)|.
 * @param[out] saturationRatio, humidityRatio, windSpeed nx*ny each (kg/kg, kg/kg, m/s), or null;
 *             no-data cells get x_s = x = 0, wind 0
 */
void AtmosphereEvaporationFields(const AtmosphereState& state,
  const AtmosphereParams& params,
  const float* terrain,
  const float* temperature,
  float* saturationRatio,
  float* humidityRatio,
  float* windSpeed,
  const ErosionParallelFor& parallelFor = {});

/// Area-weighted totals of a state (valid cells, double sums row by row), m^3.
struct AtmosphereTotals
{
  double air = 0.0;    ///< sum of h a
  double vapour = 0.0; ///< sum of q a
};
/// Area-weighted totals of `state` (valid cells only).
AtmosphereTotals AtmosphereMeasure(const AtmosphereState& state);

/// Throws std::invalid_argument naming the first parameter out of its range.
void CheckAtmosphereParams(const AtmosphereParams& params);

} // namespace terrain
} // namespace terroir

#endif

/**
 * @file Vegetation.h
 * @brief Dunn's (2015) vegetation cellular automaton and his evaporation from open water and
 * from the canopy, as plain C++ (no VTK, no GL): the CPU reference that a filter couples with
 * ErosionHydraulicStep / ErosionThermalStep on one time step.
 *
 * Grid: Erosion.h's (row-major nx x ny, row j = 0 in the south, row spacings rowDx/rowDy, cell
 * area a_j = rowDx[j] rowDy[j], optional validity mask). Water amounts are depths of water over
 * the cell (m); volumes are depth times area (m^3).
 *
 * State (Dunn section 4.2.1: two matrices, vegetation density and the water it holds):
 * density v in [0, 1] (section 3.4) and stored water w (m). A cell with v = 0 is empty.
 *
 * VegetationStep (Dunn section 3.4, functions ComputeVegetationWaterAbsorption and
 * ComputeGrowthAndSpread of his Table 4.3). Passes that each read only the previous pass's
 * arrays (Jacobi, ping-pong), so the order of the cells does not matter:
 * 1. Absorption: vegetation takes water out of the surface water d (and then, where given, out
 *    of a soil-water layer) into its store: up to U = r_a v dt (m), at most S - w (ours: Dunn
 *    gives no rate; uptake in proportion to density, store capped at S).
 * 2. Sharing, spreading, growth and death, all decided on the values after pass 1 (pass 2a
 *    picks each empty cell's seeding parent, pass 2b applies the rules):
 *    - sharing: a vegetated cell with w above T_share passes q = (k_s dt / 4) max(0,
 *      min(w - T_share, w - w_n)) to each vegetated 4-neighbour n (Dunn: a cell with
 *      enough water passes part of it to its neighbours; the linear law is ours);
 *    - spreading: a cell with v >= v_seed and w >= w_seed, not drowned, may seed each empty,
 *      not drowned 4-neighbour; the neighbour then gets v = g dt (Dunn: its density rises by
 *      one time step's growth) and a fraction phi of the parent's stored water (Dunn: the
 *      parent hands over part of its water). Ours: each parent-child pair seeds with probability
 *      p = 1 - exp(-r_s dt) drawn from a counter-based hash of (seed, step, child, direction),
 *      and a child with several parents takes the first that succeeds in the order E, N, W, S,
 *      so the result does not depend on how the rows are split;
 *    - drowning: surface water d > d_drown: v decreases by r_drown dt (Dunn: vegetation is
 *      suffocated once the surface water exceeds a height);
 *    - drought: else, w <= w_drought: v decreases by r_drought dt (Dunn: density decreases
 *      once the stored water reaches zero; w_drought = 0 by default);
 *    - growth: else, w >= w_grow and v > 0: v increases by g dt, up to 1 (Dunn: a fixed growth
 *      rate, with absorbed water above a user threshold).
 *    The parent gives at most (k_s dt + 4 phi) w <= w (checked), so no store goes negative.
 *
 * EvaporationDunn2015Step (Dunn section 3.5.1):
 * - open water, his eq. 2.6 (from the Engineering Toolbox): g_s = Theta A (x_s - x) / 3600
 *   (kg/s), Theta = 25 + 19 v_air (kg/(m^2 h)), x_s and x the saturation and actual humidity
 *   ratios (kg water / kg dry air); as a depth, e_w = Theta (x_s - x) / (3600 rho_w) (m/s).
 *   Ours: no evaporation where x >= x_s (condensation is the rain model's business);
 * - canopy: Table 2.1's rates (0.15 to 0.45 mm/h), one vegetation type (Dunn), a rate set by
 *   the water the vegetation holds and a minimum threshold (Dunn section 3.5.1). Ours: e_c = v
 * (E_min + (E_c - E_min) min(1, w / S)), linear in the store as in Rutter's interception model (his
 * reference [11]), with a floor E_min so that a store does run dry and the drought rule can fire.
 * Each is limited by the water there; what evaporates is added to an optional vapour array.
 *
 * Coupling with erosion (Dunn section 3.4): vegetation multiplies the soil's dissolving rate K_s
 * by f_e(v) = 1 - (1 - f_e1) v (linearly reduced) and the talus (soil-slip gradient threshold)
 * tangent by f_t(v) = 1 + (f_t1 - 1) v (linearly increased); soil slip destroys vegetation in
 * proportion to the bed change it causes, v -= |db| / d_slip (ours).
 *
 * Arithmetic: float state and operations (no fused multiply-add), totals in double summed row
 * by row in order: the same bits for any ParallelFor split. Surface water may carry its float
 * rounding residue (ErosionState::waterResidue) so that what is absorbed or evaporated is
 * accounted exactly.
 *
 * @par Correctness
 * Testing/Unit/TestVegetation.cxx (suite TerroirVegetationCore): hand-worked 3x3 and 5x5 grids
 * (growth, spreading and the parent order, sharing, drought, drowning), the spread probability,
 * water conservation, a coupled run with the erosion core, eq. 2.6 and Table 2.1 by hand,
 * resistance factors, slip damage, any row split, parameter errors.
 * Documentation/Vegetation.md has the measured numbers.
 *
 * @par References
 * J. Dunn, "Building Dynamic & Interactive Natural Game Worlds", MSc dissertation, Trinity
 * College Dublin, 2015, sections 2.3, 2.4, 3.4, 3.5.1, 4.2, eq. 2.6, Table 2.1.
 */
#ifndef terroir_terrain_Vegetation_h
#define terroir_terrain_Vegetation_h

#include "Erosion.h"
#include "GridView.h"

#include <cstdint>
#include <vector>

namespace terroir
{
namespace terrain
{

/// The canopies of Dunn's Table 2.1 (after his reference [11]).
enum class CanopyType
{
  ScotsPine = 0,
  MontereyPine,
  SitkaSpruce,
  DouglasFir,
  CommonBeech,
  SouthernBeeches
};

/// Average canopy evaporation of Dunn's Table 2.1, mm/h: Scots pine 0.19, Monterey pine 0.21,
/// Sitka spruce 0.18, Douglas fir 0.15, common beech 0.45, southern beeches 0.37.
/// @throws std::invalid_argument for a value outside the enum
double CanopyEvaporationDunn2015(CanopyType type);

/**
 * Parameters of the automaton. Dunn (section 3.4) names the mechanisms but gives no numbers:
 * every default here is ours (Documentation/Vegetation.md), in seconds of simulated time.
 */
struct VegetationParams
{
  double absorptionRate = 0.01;    ///< r_a, m/s of uptake at density 1 (>= 0)
  double storage = 0.05;           ///< S, m: the most water a cell's vegetation stores (> 0)
  double shareThreshold = 0.02;    ///< T_share, m: water above it is shared (>= 0)
  double shareRate = 0.5;          ///< k_s, 1/s (>= 0)
  double seedDensity = 0.5;        ///< v_seed: density needed to seed, (0, 1]
  double seedWater = 0.01;         ///< w_seed, m: stored water needed to seed (>= 0)
  double seedWaterFraction = 0.1;  ///< phi: fraction of the parent's store per child, [0, 0.25]
  double spreadRate = 0.5;         ///< r_s, 1/s: p = 1 - exp(-r_s dt) per pair and step (>= 0)
  double growthRate = 0.05;        ///< g, 1/s: density gained per second (>= 0)
  double growthWater = 0.005;      ///< w_grow, m: stored water needed to grow (>= 0)
  double droughtWater = 0.0;       ///< w_drought, m: at or below it vegetation dries (>= 0)
  double droughtRate = 0.02;       ///< r_drought, 1/s (>= 0)
  double drownDepth = 0.1;         ///< d_drown, m of surface water above which it drowns (>= 0)
  double drownRate = 0.5;          ///< r_drown, 1/s (>= 0)
  double slipKillDepth = 0.1;      ///< d_slip, m of bed change by soil slip that kills v = 1 (> 0)
  double erosionFactorFull = 0.25; ///< f_e1: K_s multiplier at v = 1, [0, 1] (1 at v = 0)
  double talusFactorFull = 1.5;    ///< f_t1: talus tangent multiplier at v = 1, >= 1
  std::uint32_t seed = 0;          ///< seed of the spreading draws
};

/// Parameters of the evaporation (Dunn eq. 2.6 and Table 2.1). Rates are physical; `scale`
/// speeds both up (Dunn section 5.2.1 raised his for effect).
struct EvaporationParams
{
  double canopyRate = 0.19;        ///< E_c, mm/h at a full store (Table 2.1, Scots pine) (>= 0)
  double canopyMinRate = 0.019;    ///< E_min, mm/h at an empty store (ours), [0, canopyRate]
  double saturationRatio = 0.0147; ///< x_s, kg/kg (20 C, 101325 Pa) unless given per cell
  double humidityRatio = 0.0073;   ///< x, kg/kg (50 % relative humidity at 20 C) unless per cell
  double windSpeed = 0.0;          ///< v_air, m/s, unless given per cell (>= 0)
  double waterDensity = 1000.0;    ///< rho_w, kg/m^3 (> 0)
  double scale = 1.0;              ///< multiplies both evaporations (>= 0)
};

/// The water a step reads and changes (nx*ny each, depths in m).
struct VegetationWater
{
  float* surface = nullptr;        ///< d, surface water (ErosionState::water); required
  float* surfaceResidue = nullptr; ///< d's rounding residue (ErosionState::waterResidue), or null
  float* soil = nullptr;           ///< soil water vegetation may also draw on, or null (none)
};

/// Optional per-cell atmosphere fields of the evaporation (nx*ny each, null: the parameter).
/// A negative or NaN wind counts as still air; NaN or x >= x_s as no evaporation.
struct EvaporationFields
{
  const float* saturationRatio = nullptr; ///< x_s, kg/kg
  const float* humidityRatio = nullptr;   ///< x, kg/kg
  const float* windSpeed = nullptr;       ///< v_air, m/s
  float* vapour = nullptr;                ///< out: += evaporated depth, m (Dunn's vapour matrix)
};

/// The automaton's state (float, nx*ny each). Make it with MakeVegetationState; density and
/// stored water may be edited between steps (a brush).
struct VegetationState
{
  int nx = 0;
  int ny = 0;
  std::vector<double> rowDx;              ///< ny east-west spacings, m
  std::vector<double> rowDy;              ///< ny north-south spacings, m
  std::vector<std::uint8_t> valid;        ///< nx*ny, 1 valid, 0 no data or sea (empty: all valid)
  std::vector<float> density;             ///< v in [0, 1]
  std::vector<float> stored;              ///< w, m of water held by the vegetation
  std::uint64_t step = 0;                 ///< steps taken: the counter of the spreading draws
  std::vector<float> scratch[2];          ///< ping-pong buffers (contents undefined)
  std::vector<std::int8_t> scratchChosen; ///< per-cell seeding parent during a step (undefined)

  std::size_t Size() const { return static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny); }
  bool IsValid(std::size_t c) const { return valid.empty() || valid[c] != 0; }
  double CellArea(int j) const { return rowDx[j] * rowDy[j]; }
};

/**
 * @brief A state on the grid of `density` (spacings and mask honoured).
 * @param density initial densities in `data` (in [0, 1]), or data = nullptr for none
 * @param stored  nx*ny initial stored water (m, >= 0), or nullptr for none
 * @throws std::invalid_argument for an empty grid, a bad spacing, or a value out of range
 */
VegetationState MakeVegetationState(const GridView<float>& density, const float* stored = nullptr);

/// What one VegetationStep did: volumes in m^3, areas in m^2 (double sums in a fixed order).
struct VegetationStepStats
{
  double absorbedSurface = 0.0; ///< taken from the surface water
  double absorbedSoil = 0.0;    ///< taken from the soil water
  double shared = 0.0;          ///< passed between vegetated neighbours
  double seedWater = 0.0;       ///< given to seeded cells
  double cover = 0.0;           ///< sum of v a after the step
  long long seeded = 0;         ///< cells seeded
  long long grown = 0;          ///< cells that grew
  long long drought = 0;        ///< cells that lost density to drought
  long long drowned = 0;        ///< cells that lost density to drowning
};

/**
 * @brief One step of Dunn's vegetation automaton (passes 1-2 of the file comment).
 * @param[in,out] state density and stored water; state.step is incremented
 * @param[in,out] water surface water (and optionally soil water) that vegetation absorbs
 * @param[in] dt        time step, s (> 0)
 * @param[in] params    checked (std::invalid_argument names the bad one), with
 *                      shareRate dt + 4 seedWaterFraction <= 1
 * @param[in] parallelFor row scheduler, or empty to run the rows in order
 * @post density in [0, 1]; stored, surface and soil water >= 0; water volume conserved:
 *       sum (d + soil + w) a is unchanged up to float rounding
 */
VegetationStepStats VegetationStep(VegetationState& state,
  const VegetationWater& water,
  double dt,
  const VegetationParams& params,
  const ErosionParallelFor& parallelFor = {});

/// What one evaporation step removed, m^3.
struct EvaporationStats
{
  double fromWater = 0.0;  ///< open (surface) water, eq. 2.6
  double fromCanopy = 0.0; ///< vegetation stores, Table 2.1
};

/**
 * @brief Evaporation from open water (Dunn eq. 2.6) and from the canopy (Table 2.1 rates).
 * @param[in,out] state   stored water decreases by the canopy evaporation
 * @param[in,out] water   surface water (and its residue) decreases by eq. 2.6; soil untouched
 * @param[in] dt          s (> 0)
 * @param[in] vegetation  storage S (the canopy's full store)
 * @param[in] params      checked (std::invalid_argument)
 * @param[in,out] fields  optional per-cell x_s, x, wind; vapour += evaporated depth (m)
 * @param[in] parallelFor row scheduler, or empty
 */
EvaporationStats EvaporationDunn2015Step(VegetationState& state,
  const VegetationWater& water,
  double dt,
  const VegetationParams& vegetation,
  const EvaporationParams& params,
  const EvaporationFields& fields = {},
  const ErosionParallelFor& parallelFor = {});

/// Dunn eq. 2.6's evaporation coefficient Theta = 25 + 19 v, kg/(m^2 h), wind speed v in m/s.
double EvaporationCoefficientDunn2015(double windSpeed);
/// Dunn eq. 2.6: g_s = Theta A (x_s - x) / 3600, kg/s, area A in m^2, humidity ratios kg/kg.
double OpenWaterEvaporationDunn2015(double area,
  double windSpeed,
  double saturationRatio,
  double humidityRatio);
/**
 * Saturation humidity ratio x_s = 0.622 e_s / (p - e_s), kg/kg, with the Magnus formula
 * e_s = 610.94 exp(17.625 T / (T + 243.04)) Pa (Alduchov & Eskridge 1996); ours, for feeding
 * eq. 2.6 from a temperature (Dunn takes x_s from his atmosphere model).
 * @param temperatureC air temperature, C (-80, 60); @param pressure air pressure, Pa (> e_s)
 */
double SaturationHumidityRatio(double temperatureC, double pressure = 101325.0);

/// f_e(v) = 1 - (1 - f_e1) v: the multiplier of K_s (soil dissolving) at density v (clamped).
float VegetationErosionFactor(float density, const VegetationParams& params);
/// f_t(v) = 1 + (f_t1 - 1) v: the multiplier of tan(talus) at density v (clamped to [0, 1]).
float VegetationTalusFactor(float density, const VegetationParams& params);

/**
 * @brief Per-cell resistance factors for the erosion steps (Dunn section 3.4).
 * @param[out] erosionFactor nx*ny multipliers of K_s in [f_e1, 1], or nullptr
 * @param[out] talusFactor   nx*ny multipliers of tan(talus) in [1, f_t1], or nullptr
 * No-data cells get 1.
 */
void VegetationResistance(const VegetationState& state,
  const VegetationParams& params,
  float* erosionFactor,
  float* talusFactor);

/**
 * @brief Soil slip destroys vegetation (Dunn sections 3.4, 5.2.1): v -= |b1 - b0| / d_slip.
 * @param bedBefore, bedAfter nx*ny bed heights (m) before and after ErosionThermalStep
 * @return the cover lost, sum of dv a (m^2)
 */
double VegetationSlipDamage(VegetationState& state,
  const float* bedBefore,
  const float* bedAfter,
  const VegetationParams& params,
  const ErosionParallelFor& parallelFor = {});

/// Area-weighted totals of a state (valid cells, double sums row by row).
struct VegetationTotals
{
  double cover = 0.0;  ///< sum of v a, m^2
  double stored = 0.0; ///< sum of w a, m^3
};
/// Area-weighted totals of `state` (valid cells only); throws as VegetationStep for a bad state.
VegetationTotals VegetationMeasure(const VegetationState& state);

/// Throws std::invalid_argument naming the first parameter out of its range.
void CheckVegetationParams(const VegetationParams& params);
/// Throws std::invalid_argument naming the first parameter out of its range.
void CheckEvaporationParams(const EvaporationParams& params);

} // namespace terrain
} // namespace terroir

#endif

/**
 * @file ErosionSimulation.h
 * @brief One coupled time step of erosion and vegetation, and brushes that edit the state
 * between steps: what vtkTerroirErosion runs for its time steps and what `terroir view` runs
 * live. Plain C++ (no VTK, no GL).
 *
 * A step (Dunn 2015, section 4.2: the terrain, vegetation and weather updates on one time step):
 * 1. with vegetation, its resistance factors on K_s and the talus (VegetationResistance);
 * 2. the hydraulic step (ErosionHydraulicStep) with the rain and evaporation factors;
 * 3. with vegetation, the automaton (VegetationStep) on the surface water;
 * 4. every thermalInterval steps the thermal step (ErosionThermalStep), and with vegetation the
 *    damage soil slip does to it (VegetationSlipDamage);
 * 5. with weather (Dunn section 3.5, Atmosphere.h): the erosion step's own evaporation K_e is
 *    off and its rain is the rain rate plus what the atmosphere rained on the step before;
 *    after the step, Dunn's eq. 2.6 evaporation from the water and the canopy
 *    (EvaporationDunn2015Step, fed by AtmosphereEvaporationFields) goes into the vapour, and
 *    AtmosphereStep carries the vapour on the wind and rains where it exceeds the capacity.
 *    Surface water + vegetation stores + vapour + rain in flight is conserved.
 *
 * Brushes (Dunn section 4.3: the user paints soil, water and vegetation onto the world): a dab
 * at a cell position (i east, j north, fractional) with a radius R in cells changes each valid
 * cell at distance r < R from it by amount w(r), w(r) = (1 + cos(pi r / R)) / 2 (a smooth dab,
 * 1 at the centre, 0 at the rim; ours):
 * - Soil: the bed rises by amount w (m; a negative amount digs); the volume is counted in
 *   ErosionVolumes::brushBed;
 * - Water: the depth rises by amount w (m; negative removes, never below 0); counted in
 *   brushWater;
 * - Vegetation: the density moves toward `amount` (in [0, 1]) by the weight, v += (amount - v) w;
 *   the first vegetation dab on a simulation without vegetation starts the automaton (density 0
 *   elsewhere).
 * Bed and water keep their rounding residues exactly (value + residue is changed in double and
 * split again), so the brush volumes add up in the mass balance.
 *
 * @par Correctness
 * Testing/Unit/TestErosionSimulation.cxx (suite TerroirErosionSimulationCore): a step equals the
 * core functions called in the documented order; the dab's weights and volumes by hand; water and
 * material balances including the brushes; vegetation started by a dab.
 */
#ifndef terroir_terrain_ErosionSimulation_h
#define terroir_terrain_ErosionSimulation_h

#include "Atmosphere.h"
#include "Erosion.h"
#include "GridView.h"
#include "Vegetation.h"

#include <vector>

namespace terroir
{
namespace terrain
{

/// Everything a coupled step reads besides the state.
struct ErosionSimulationParams
{
  ErosionParams hydraulic;
  ThermalParams thermal;
  int thermalInterval = 1; ///< a thermal step after every this many steps (>= 0; 0: none)
  VegetationParams vegetation;
  double rainRate = 0.0; ///< rain on every valid cell, m/s (>= 0, finite)
  /// Dunn's weather (item 5 of the file comment): off by default.
  bool weather = false;
  AtmosphereParams atmosphere;   ///< its timeStep is the hydraulic one's
  EvaporationParams evaporation; ///< eq. 2.6 and Table 2.1 (scale: Dunn raised his for effect)
  double airHeight = 10.0;       ///< the atmosphere's air column at the start, m (ours)
};

/// Volumes summed over the steps and the brushes, m^3.
struct ErosionVolumes
{
  double eroded = 0.0;           ///< bed taken into suspension
  double deposited = 0.0;        ///< suspended sediment settled
  double rain = 0.0;             ///< water added by rain
  double evaporated = 0.0;       ///< water removed by evaporation
  double toSea = 0.0;            ///< water removed by the sea boundary
  double brushWater = 0.0;       ///< water added by brushes (negative: removed)
  double brushBed = 0.0;         ///< bed added by brushes (negative: dug)
  double canopyEvaporated = 0.0; ///< weather: water evaporated from the vegetation's stores
  double weatherRain = 0.0;      ///< weather: vapour condensed into rain (falls on the next step)
};

/// What a brush dab paints.
enum class ErosionBrush
{
  Soil = 0,
  Water = 1,
  Vegetation = 2
};

/// The coupled simulation: the erosion state, the optional vegetation, and their volumes.
class ErosionSimulation
{
public:
  /**
   * @param terrain    bed heights (m) with spacing and mask (cells without data: mask 0)
   * @param initialWater depth on every valid cell at the start, m (>= 0, finite)
   * @param evaporationFactor nx*ny factors T of Weiss's evaporation (>= 0), or empty for 1
   * @param vegetation nx*ny starting densities in [0, 1] (clamped; NaN: 0), or nullptr for none
   * @param soil       nx*ny soil thicknesses over rock (m, >= 0; Erosion.h's layered
   *                   constants), or nullptr for one material
   * @throws std::invalid_argument as MakeErosionState, or for a bad initialWater or a factor
   *         array of another size
   */
  ErosionSimulation(const GridView<float>& terrain,
    double initialWater,
    std::vector<float> evaporationFactor = {},
    const float* vegetation = nullptr,
    const float* soil = nullptr);

  /// One coupled step (see the file comment); throws std::invalid_argument for bad parameters.
  void Step(const ErosionSimulationParams& params, const ErosionParallelFor& parallelFor = {});

  /**
   * @brief A brush dab (see the file comment).
   * @param i, j   centre, in cells (i east, j north from the first cell)
   * @param radius R in cells (> 0, finite)
   * @param amount metres (Soil, Water) or the target density (Vegetation, clamped to [0, 1])
   * @return the cells the dab reached (valid cells with r < R)
   * @throws std::invalid_argument for a non-finite position or amount or a bad radius
   */
  long long Paint(ErosionBrush brush, double i, double j, double radius, double amount);

  long long Steps() const { return this->StepCount; }
  const ErosionVolumes& Volumes() const { return this->Sums; }
  ErosionState& State() { return this->Erosion; }
  const ErosionState& State() const { return this->Erosion; }
  bool HasVegetation() const { return this->Plants; }
  const VegetationState& Vegetation() const { return this->PlantState; }
  /// Weather: the atmosphere (vapour, wind; made on the first step with weather) and the rain
  /// it condensed on the last step, falling on the next (m per cell).
  bool HasWeather() const { return this->Weather; }
  const AtmosphereState& Atmosphere() const { return this->Air; }
  const std::vector<float>& RainInFlight() const { return this->Falling; }
  /// Air temperatures for the weather, degC per cell (nx*ny; empty: from the height with the
  /// atmosphere's lapse rate).
  void SetTemperature(std::vector<float> temperature);
  /// Rain per cell, m/s (nx*ny values >= 0; empty: none), added to the parameters' rainRate on
  /// every step (e.g. a precipitation map); throws std::invalid_argument for a bad field.
  void SetRainRates(std::vector<float> rates);
  /// The rain field of a step: `rate` m/s on every cell plus SetRainRates' (nullptr for none),
  /// and the evaporation factors (nullptr for 1): what the GPU path takes.
  const float* RainField(double rate);
  const float* EvaporationFactor() const
  {
    return this->Factor.empty() ? nullptr : this->Factor.data();
  }
  /**
   * @brief Counts `steps` hydraulic (and thermal) steps that ran outside Step on State() (the
   * GPU path) with the volumes `sums` of their hydraulic steps; only without vegetation and
   * weather (std::logic_error otherwise).
   */
  void AddSteps(long long steps, const ErosionStepStats& sums);

private:
  void StartVegetation(const float* density);
  void StartWeather(const ErosionSimulationParams& params);
  GridView<float> View(const float* data) const;
  void WeatherStep(const ErosionSimulationParams& params, const ErosionParallelFor& rows);

  ErosionState Erosion;
  VegetationState PlantState;
  bool Plants = false;
  std::vector<float> Factor;
  std::vector<float> Rain, RainMap;
  double RainRate = -1.0;
  std::vector<float> BedBefore;
  bool Weather = false;
  AtmosphereState Air;
  VegetationState Bare; ///< a canopy of density 0 for the evaporation without vegetation
  std::vector<float> Falling, RainRates, Temperature, Xs, X, Wind;
  long long StepCount = 0;
  ErosionVolumes Sums;
};

} // namespace terrain
} // namespace terroir

#endif

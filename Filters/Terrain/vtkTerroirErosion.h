/**
 * @class   vtkTerroirErosion
 * @brief   Hydraulic erosion on the virtual-pipe water model, with thermal erosion (soil slip)
 *          and evaporation that follows the temperature: the terrain after N time steps.
 *
 * Input: a Terroir terrain (2-D vtkImageData, `Elevation` in metres, optional
 * `vtkValidPointMask`), optionally `Temperature` (degC, 1 or 12 components, e.g. from
 * vtkTerroirTemperature): its mean sets each cell's evaporation factor T = (mean - 0 degC) /
 * (30 degC - 0 degC), clamped to [0, 1] (Weiss's temperature from cold to hot; without the
 * array T = 1), and optionally `RainRate` (mm/h per point, >= 0: a rain map, e.g. a month's
 * precipitation intensity where it rains; added to the RainRate property). Output: the input's
 * arrays plus
 * - `ErodedElevation` (float, m): the bed after the steps;
 * - `ErosionDepth` (float, m): ErodedElevation - Elevation (< 0 where material left);
 * - `ErosionWaterDepth` (float, m) and `SuspendedSediment` (float, m of bed);
 * - field data `ErosionSteps` (steps computed), `ErosionVolumes` (m^3: eroded, deposited,
 *   rain, evaporated, water to the sea, over all steps) and `ErosionTotals` (m^3: bed, water,
 *   suspended sediment now, area-weighted over the valid cells).
 * - with Vegetation on, `VegetationDensity` (float, 0..1);
 * - with a `SoilThickness` input (m of soil over rock: layered constants, K_s and TalusAngle
 *   for the soil, RockDissolving and RockTalusAngle for the rock), `SoilThickness` left (m);
 * - with Weather on, `Vapour` (float, m of water in the air) and field data `WeatherVolumes`
 *   (m^3: evaporated from the water, from the canopy, rained by the atmosphere).
 * No-data cells: NaN.
 *
 * Algorithm (terroir::terrain, Filters/Terrain/Core/Erosion.h; Mei, Decaudin & Hu 2007 as
 * written by Weiss 2015 section VI and Dunn 2015): InitialWater metres on every cell, then
 * Steps hydraulic steps (rain RainRate mm/h, outflow through four pipes scaled so no cell
 * gives more than it has, velocities, capacity C = K_c sin(alpha) |v|, dissolution K_s and
 * deposition K_d, semi-Lagrangian sediment transport with Dunn's mass rescaling, evaporation
 * K_e T), each followed by a thermal step (talus TalusAngle) every ThermalInterval steps.
 * Defaults are Weiss's: TimeStep 0.01 s, Capacity 0.5, Dissolving 0.1, Deposition 0.1,
 * Evaporation 0.005 1/s, CapacityDepth 0 (off: ours, C scaled by min(1, d / CapacityDepth) so
 * that thin films carry little); InitialWater 0.05 m, RainRate 0, Steps 100, TalusAngle 33 deg,
 * ThermalInterval 1, Boundary Closed (nothing leaves the grid; no-data cells are walls) or Sea
 * (cells at or below SeaLevel, default 0 m, the grid's edge and no-data cells take the water
 * that reaches them). Water and material are conserved on a closed domain (the state carries
 * its float rounding residue: 1e-8 relative per 1000 steps measured). Rows run in parallel
 * (vtkSMPTools) with the same bits on any thread count. Weather (Dunn 2015 section 3.5,
 * Atmosphere.h; default off): Weiss's K_e gives way to Dunn's eq. 2.6 evaporation (times
 * EvaporationScale, default 1) into the vapour, a prevailing wind from WindDirection (degrees
 * clockwise from north it blows from, default 270) of WindStrength (m/s, default 1) carries it
 * on the pipe model, and it rains where it exceeds the air's capacity (the input's mean
 * `Temperature`, or 15 degC at sea level less 6.5 degC/km).
 * GPU path (Backend GPU; Shaders/Erosion.comp, vtkTerroirErosionGPU.h): the hydraulic and
 * thermal steps on the device, the CPU's bits on llvmpipe; without Vegetation and Weather only
 * (which couple on the CPU every step: a GPU request with them is an error).
 *
 * VTK time: the output announces TIME_STEPS 0, TimeStepStride, ... up to Steps; a request for
 * time t gives the state after round(t) steps. The last state is cached: a later time
 * continues from it, an earlier one starts again. Whole extent (a global filter); a
 * distributed run computes the whole grid on every process.
 *
 * Errors (one line, empty output): a parameter out of its range (TimeStep <= 0, a constant
 * outside its range, a talus angle outside (0, 90), InitialWater or RainRate < 0 or not
 * finite).
 *
 * @par Correctness
 * Testing/Unit/TestErosion.cxx (the core: hand-worked flux step, dam break, still lake, tilted
 * plane, uniform flow balance, conservation, talus), Testing/Unit/TestErosionSimulation.cxx
 * (the coupled step, brushes, weather's water cycle, rain map), Testing/Pipeline/
 * TestTerroirErosion.cxx (conservation through the filter, evaporation against
 * (1 - K_e dt T)^n for hot and cold cells, talus reached, time steps equal fresh runs,
 * vegetation, weather, the rain map, the soft outflow's cap, a soil layer over rock, errors),
 * Testing/GPU/TestErosionGPU.cxx (CPU and GPU bit for bit, the two backends across the cache),
 * Testing/Pipeline/TestDeterminism.cxx.
 *
 * @par References
 * Mei, X., Decaudin, P., Hu, B.-G. (2007). Fast hydraulic erosion simulation and visualization
 * on GPU. Pacific Graphics. Weiss, S. (2015). Procedural Terrain, section VI. Dunn, J. (2015).
 * Building Dynamic & Interactive Natural Game Worlds, sections 2-3.
 *
 * @sa vtkTerroirWaterFlow Documentation/Erosion.md
 */
#ifndef vtkTerroirErosion_h
#define vtkTerroirErosion_h

#include "vtkTerroirFiltersTerrainModule.h" // For export macro
#include "vtkTerroirImageAlgorithm.h"

namespace terroir
{
namespace terrain
{
struct ErosionSimulationParams;
}
}

class VTKTERROIRFILTERSTERRAIN_EXPORT vtkTerroirErosion : public vtkTerroirImageAlgorithm
{
public:
  static vtkTerroirErosion* New();
  vtkTypeMacro(vtkTerroirErosion, vtkTerroirImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum BoundaryType
  {
    Closed = 0,
    Sea = 1
  };

  ///@{
  /// Hydraulic steps (default 100, >= 0).
  vtkSetClampMacro(Steps, int, 0, VTK_INT_MAX);
  vtkGetMacro(Steps, int);
  ///@}
  ///@{
  /// Water on every cell at the start, metres (default 0.05, >= 0).
  vtkSetMacro(InitialWater, double);
  vtkGetMacro(InitialWater, double);
  ///@}
  ///@{
  /// Rain on every cell, mm per hour of simulated time (default 0, >= 0).
  vtkSetMacro(RainRate, double);
  vtkGetMacro(RainRate, double);
  ///@}
  ///@{
  /// Weiss's constants: dt (s, > 0), K_c (>= 0), K_s and K_d (per step, [0, 1]), K_e (1/s).
  vtkSetMacro(TimeStep, double);
  vtkGetMacro(TimeStep, double);
  vtkSetMacro(Capacity, double);
  vtkGetMacro(Capacity, double);
  vtkSetMacro(Dissolving, double);
  vtkGetMacro(Dissolving, double);
  vtkSetMacro(Deposition, double);
  vtkGetMacro(Deposition, double);
  vtkSetMacro(Evaporation, double);
  vtkGetMacro(Evaporation, double);
  ///@}
  ///@{
  /// Water depth below which the sediment capacity is scaled down, C x min(1, d /
  /// CapacityDepth), metres (default 0: off, as Weiss; ours: on real DEMs Weiss's capacity,
  /// which does not depend on the depth, lets a film of water carve metres: try 0.1-1 m).
  vtkSetMacro(CapacityDepth, double);
  vtkGetMacro(CapacityDepth, double);
  ///@}
  ///@{
  /// Dunn's soft outflow threshold against oscillation (his eq. 3.1; default off): each pipe's
  /// flux is capped at SoftOutflowMinimum (m^3/s, default 0) + SoftOutflowScale (m^2/s,
  /// default 1) x |height difference|.
  vtkSetMacro(SoftOutflow, vtkTypeBool);
  vtkGetMacro(SoftOutflow, vtkTypeBool);
  vtkBooleanMacro(SoftOutflow, vtkTypeBool);
  vtkSetMacro(SoftOutflowMinimum, double);
  vtkGetMacro(SoftOutflowMinimum, double);
  vtkSetMacro(SoftOutflowScale, double);
  vtkGetMacro(SoftOutflowScale, double);
  ///@}
  ///@{
  /// Talus angle of thermal erosion, degrees in (0, 90) (default 33): of the soil when the input
  /// has a `SoilThickness` layer, else of the one material.
  vtkSetMacro(TalusAngle, double);
  vtkGetMacro(TalusAngle, double);
  ///@}
  ///@{
  /// Rock under a soil layer (the input's `SoilThickness` point array, m; Weiss section VI-B2:
  /// soil erodes more easily than rock): its dissolving constant K_s,rock (per step, [0, 1],
  /// default 0.1) and talus angle (degrees in (0, 90), default 60). Unused without the layer.
  vtkSetMacro(RockDissolving, double);
  vtkGetMacro(RockDissolving, double);
  vtkSetMacro(RockTalusAngle, double);
  vtkGetMacro(RockTalusAngle, double);
  ///@}
  ///@{
  /// A thermal step after every this many hydraulic steps (default 1; 0: none).
  vtkSetClampMacro(ThermalInterval, int, 0, VTK_INT_MAX);
  vtkGetMacro(ThermalInterval, int);
  ///@}
  ///@{
  /// Closed (0, default) or Sea (1), and the sea's level in metres (default 0).
  vtkSetClampMacro(Boundary, int, Closed, Sea);
  vtkGetMacro(Boundary, int);
  vtkSetMacro(SeaLevel, double);
  vtkGetMacro(SeaLevel, double);
  ///@}
  ///@{
  /// Vegetation (Dunn 2015, Vegetation.h) coupled on every step (default off): it absorbs and
  /// shares water, spreads, grows, dies of drought or drowning or when soil slip buries it, and
  /// holds the soil (K_s x (1 - 0.75 v), talus tangent x (1 + 0.5 v) at density v). Its start:
  /// the input's `VegetationDensity` point array (0..1) when there is one, else
  /// InitialVegetation (default 0.5, in [0, 1]) on every cell. Output `VegetationDensity`.
  vtkSetMacro(Vegetation, vtkTypeBool);
  vtkGetMacro(Vegetation, vtkTypeBool);
  vtkBooleanMacro(Vegetation, vtkTypeBool);
  vtkSetClampMacro(InitialVegetation, double, 0.0, 1.0);
  vtkGetMacro(InitialVegetation, double);
  ///@}
  ///@{
  /// Dunn's weather (default off): wind, vapour and rain coupled on every step; see above.
  vtkSetMacro(Weather, vtkTypeBool);
  vtkGetMacro(Weather, vtkTypeBool);
  vtkBooleanMacro(Weather, vtkTypeBool);
  vtkSetMacro(WindDirection, double);
  vtkGetMacro(WindDirection, double);
  vtkSetMacro(WindStrength, double);
  vtkGetMacro(WindStrength, double);
  vtkSetMacro(EvaporationScale, double);
  vtkGetMacro(EvaporationScale, double);
  ///@}

  ///@{
  /// Steps between the announced VTK time steps (default 10, >= 1).
  vtkSetClampMacro(TimeStepStride, int, 1, VTK_INT_MAX);
  vtkGetMacro(TimeStepStride, int);
  ///@}

  /// Output array names.
  static const char* ErodedElevationName() { return "ErodedElevation"; }
  static const char* ErosionDepthName() { return "ErosionDepth"; }
  static const char* WaterDepthName() { return "ErosionWaterDepth"; }
  static const char* SedimentName() { return "SuspendedSediment"; }
  static const char* VegetationName() { return "VegetationDensity"; }
  static const char* VapourName() { return "Vapour"; }
  /// Optional input point array: rain per cell, mm/h, added to RainRate.
  static const char* RainRateName() { return "RainRate"; }
  /// Optional input point array (soil over rock, m) and, with it, the output's soil left (m).
  static const char* SoilThicknessName() { return "SoilThickness"; }

protected:
  vtkTerroirErosion();
  ~vtkTerroirErosion() override;

  int GetHaloWidth() override { return -1; }
  bool HasGPUPath() override { return !this->Vegetation && !this->Weather; }
  double EstimateMemory(double nx, double ny) override;
  std::string CheckParameters() override;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
#ifndef __VTK_WRAP__
  int RequestTerrainData(vtkImageData* input,
    const terroir::TerrainInput& terrain,
    vtkImageData* output) override;
#endif

  int Steps = 100;
  double InitialWater = 0.05;
  double RainRate = 0.0;
  double TimeStep = 0.01;
  double Capacity = 0.5;
  double Dissolving = 0.1;
  double Deposition = 0.1;
  double Evaporation = 0.005;
  double CapacityDepth = 0.0;
  double TalusAngle = 33.0;
  vtkTypeBool SoftOutflow = 0;
  double SoftOutflowMinimum = 0.0;
  double SoftOutflowScale = 1.0;
  double RockDissolving = 0.1;
  double RockTalusAngle = 60.0;
  int ThermalInterval = 1;
  int Boundary = Closed;
  double SeaLevel = 0.0;
  int TimeStepStride = 10;
  vtkTypeBool Vegetation = 0;
  double InitialVegetation = 0.5;
  vtkTypeBool Weather = 0;
  double WindDirection = 270.0;
  double WindStrength = 1.0;
  double EvaporationScale = 1.0;

private:
  vtkTerroirErosion(const vtkTerroirErosion&) = delete;
  void operator=(const vtkTerroirErosion&) = delete;

  struct Cache;
  Cache* State;
  /// The core's parameters from the properties.
  void MakeParams(terroir::terrain::ErosionSimulationParams& params) const;
};

#endif

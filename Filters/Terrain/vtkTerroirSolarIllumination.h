/**
 * @class   vtkTerroirSolarIllumination
 * @brief   Computes where the sun shines on a terrain: cast shadows at an instant, hours of
 *          direct sun per day or per month, and clear-sky direct-beam insolation.
 *
 * Input: a Terroir terrain (2-D vtkImageData, point array `Elevation` in metres, optional
 * `vtkValidPointMask`, georeference in field data). Output: the input's arrays plus, by Mode:
 * - Instant: `Illuminated` (float32, 1 lit / 0 in shadow) and `SunIncidence` (float32, cosine
 *   of the angle between the sun and the surface normal, 0 in shadow or facing away);
 * - Daily: `IlluminationHours` (1 component, hours, "h") and `Insolation` (1 component,
 *   Wh/m^2 per day, "Wh/m2");
 * - Monthly: `IlluminationHours` and `Insolation` with 12 components (Jan ... Dec), each for
 *   the representative day MonthlyDay of that month of Year.
 * No-data cells get NaN. Optionally (OutputHorizonMap) `HorizonAngle`: HorizonSectors
 * components, degrees above the horizontal, component k looking toward grid azimuth
 * k * 360 / HorizonSectors. Field data: `SunPositions` (one tuple per time step: Month, Day,
 * UTCHours, Azimuth and Elevation in degrees, azimuth clockwise from true north, and
 * GridAzimuth) so the sun path can be plotted, and `SolarFrame` (Latitude, Longitude,
 * GridNorthBearing, degrees).
 *
 * Sun: NREL's SPA (terroir::terrain::SolarPositionNREL2004) at Latitude/Longitude (default:
 * the terrain's centre, `TerroirCenterLatLon`), for the terrain's mean elevation, with
 * refraction for Pressure (default: from the mean elevation, 1013.25 exp(-z/8200) mbar) and
 * AirTemperature. Its azimuth is turned into grid azimuth with the bearing of grid north:
 * Orientation when set, else the meridian convergence (`TerroirMeridianConvergence`), else 0.
 * A terrain without georeference needs Latitude and Longitude. Instant: Year/Month/Day and
 * Time (local clock hours) with UTCOffset (hours; 0 = Time is UTC), or a fixed SunDirection.
 * Daily/Monthly: the 24 hours centred on mean solar noon, in TimeStep-minute steps evaluated
 * at their midpoints (terroir::terrain::DaySunSteps).
 *
 * Shadows (terroir/ShadowHorizon.h): a cell is lit when the sun is above the horizontal plane
 * and above its horizon in the sun's direction, the highest elevation angle of the terrain
 * along that direction (linear
 * interpolation across grid lines; optionally lowered by the Earth's curvature). ShadowMethod
 * RayMarching marches every cell toward the sun (the exact reference); HorizonMap (default)
 * builds a map of HorizonSectors horizon tangents per cell with convex-hull sweeps (after
 * Dozier & Frew 1990) once per terrain (cached while the input, the sectors and the curvature
 * setting stay the same; CacheHorizonMap) and interpolates between the two sectors around the sun.
 * Insolation: clear-sky direct beam S0/R^2 tau^m (Campbell & Norman 1998, eq. 11.11) with the
 * Kasten & Young (1989) air mass, times cos(incidence), over the lit steps (see
 * terroir/SolarIllumination.h); diffuse and reflected light are not included.
 *
 * Whole extent (global filter), except in a distributed run (a global controller of N > 1
 * processes, N pieces asked): each piece then computes on itself and DistributedHalo cells
 * around it, as if the terrain ended there; the grid's mean and highest elevation (the sun's
 * refraction, the march's cut-off) are all-reduced, and the share of decisions that terrain
 * beyond the halo could change is measured (GetLastHaloUncertainShare, field data
 * `SunHaloUncertainShare`, a warning when not 0): where it is 0 the shadows are the serial ones.
 * Backends: CPU (vtkSMPTools over sectors and cells, float32;
 * results do not depend on the thread count) and GPU (Shaders/ShadowSweep.comp,
 * ShadowGather.comp, SolarIllumination.comp).
 *
 * @par Correctness
 * Testing/Unit/TestSolarPosition.cxx, TestShadowHorizon.cxx, TestSolarIllumination.cxx;
 * Testing/Pipeline/TestTerroirSolarIllumination.cxx (horizon map vs ray marching on the
 * bundled DEM, day length on flat terrain, frames and errors); Testing/GPU/
 * TestSolarIlluminationGPU.cxx; Testing/Python/TestGrassPeer.py (GRASS r.sunmask, r.horizon).
 *
 * @par References
 * Reda & Andreas (2004), Solar Energy 76(5):577-589, doi:10.1016/j.solener.2003.12.003.
 * Dozier & Frew (1990), IEEE TGRS 28(5):963-969, doi:10.1109/36.58986.
 * Campbell & Norman (1998), An Introduction to Environmental Biophysics, ch. 11.
 * Kasten & Young (1989), Applied Optics 28(22):4735-4738, doi:10.1364/AO.28.004735.
 *
 * @sa vtkTerroirImageAlgorithm vtkTerroirSlope
 */
#ifndef vtkTerroirSolarIllumination_h
#define vtkTerroirSolarIllumination_h

#include "vtkTerroirFiltersTerrainModule.h" // For export macro
#include "vtkTerroirImageAlgorithm.h"

#include <memory> // For std::unique_ptr
#include <vector> // For std::vector

namespace terroir
{
template<typename T>
struct GridView;
namespace terrain
{
struct SunFrame;
struct SunStep;
template<typename T>
struct ShadowSource;
}
}

class VTKTERROIRFILTERSTERRAIN_EXPORT vtkTerroirSolarIllumination : public vtkTerroirImageAlgorithm
{
public:
  static vtkTerroirSolarIllumination* New();
  vtkTypeMacro(vtkTerroirSolarIllumination, vtkTerroirImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Output array names.
  static const char* IlluminatedName() { return "Illuminated"; }
  static const char* SunIncidenceName() { return "SunIncidence"; }
  static const char* IlluminationHoursName() { return "IlluminationHours"; }
  static const char* InsolationName() { return "Insolation"; }
  static const char* HorizonAngleName() { return "HorizonAngle"; }
  static const char* SunPositionsName() { return "SunPositions"; }
  static const char* SolarFrameName() { return "SolarFrame"; }
  ///@}

  enum ModeType
  {
    Instant = 0,
    Daily = 1,
    Monthly = 2
  };
  enum ShadowMethodType
  {
    RayMarching = 0,
    HorizonMap = 1
  };

  ///@{
  /// Instant (0), Daily (1) or Monthly (2, default).
  vtkSetClampMacro(Mode, int, Instant, Monthly);
  vtkGetMacro(Mode, int);
  void SetModeToInstant() { this->SetMode(Instant); }
  void SetModeToDaily() { this->SetMode(Daily); }
  void SetModeToMonthly() { this->SetMode(Monthly); }
  ///@}

  ///@{
  /// Date (Gregorian). Year is used by every mode; Month and Day by Instant and Daily.
  /// Defaults 2025-06-21. A date that does not exist is an error.
  vtkSetMacro(Year, int);
  vtkGetMacro(Year, int);
  vtkSetMacro(Month, int);
  vtkGetMacro(Month, int);
  vtkSetMacro(Day, int);
  vtkGetMacro(Day, int);
  ///@}

  ///@{
  /// Instant: clock time, hours in [0, 24] (default 12), and its offset from UTC in hours,
  /// [-14, 14] (default 0: Time is UTC). UTC = Time - UTCOffset.
  vtkSetMacro(Time, double);
  vtkGetMacro(Time, double);
  vtkSetMacro(UTCOffset, double);
  vtkGetMacro(UTCOffset, double);
  ///@}

  ///@{
  /// Instant: use SunDirection (azimuth clockwise from true north, elevation; degrees) instead
  /// of the date and time. Default off.
  vtkSetMacro(UseSunDirection, bool);
  vtkGetMacro(UseSunDirection, bool);
  vtkBooleanMacro(UseSunDirection, bool);
  vtkSetVector2Macro(SunDirection, double);
  vtkGetVector2Macro(SunDirection, double);
  ///@}

  ///@{
  /// Monthly: the day of every month used (default 15); 29..31 mean the month's last day when
  /// the month is shorter. Must lie in [1, 31].
  vtkSetMacro(MonthlyDay, int);
  vtkGetMacro(MonthlyDay, int);
  ///@}

  ///@{
  /// Daily and Monthly: time step in minutes, in (0, 1440]. Default 10.
  vtkSetMacro(TimeStep, double);
  vtkGetMacro(TimeStep, double);
  ///@}

  ///@{
  /// Observer latitude / longitude, degrees (north / east positive). NaN (default): the
  /// terrain's centre from its georeference (an error when it has none).
  vtkSetMacro(Latitude, double);
  vtkGetMacro(Latitude, double);
  vtkSetMacro(Longitude, double);
  vtkGetMacro(Longitude, double);
  ///@}

  ///@{
  /// Bearing of the grid's north (its +y axis) clockwise from true north, degrees, like the
  /// compass of Long (2016). NaN (default): the meridian convergence of the georeference, or 0.
  vtkSetMacro(Orientation, double);
  vtkGetMacro(Orientation, double);
  ///@}

  ///@{
  /// RayMarching (0, exact) or HorizonMap (1, default).
  vtkSetClampMacro(ShadowMethod, int, RayMarching, HorizonMap);
  vtkGetMacro(ShadowMethod, int);
  void SetShadowMethodToRayMarching() { this->SetShadowMethod(RayMarching); }
  void SetShadowMethodToHorizonMap() { this->SetShadowMethod(HorizonMap); }
  ///@}

  ///@{
  /// Azimuth sectors of the horizon map, [4, 1024]. Default 64.
  vtkSetMacro(HorizonSectors, int);
  vtkGetMacro(HorizonSectors, int);
  ///@}

  ///@{
  /// Lower distant terrain by the Earth's curvature, d^2 / (2R). Default off.
  vtkSetMacro(EarthCurvature, bool);
  vtkGetMacro(EarthCurvature, bool);
  vtkBooleanMacro(EarthCurvature, bool);
  ///@}

  ///@{
  /// Add the `HorizonAngle` array (HorizonSectors components, degrees). Default off.
  vtkSetMacro(OutputHorizonMap, bool);
  vtkGetMacro(OutputHorizonMap, bool);
  vtkBooleanMacro(OutputHorizonMap, bool);
  ///@}

  ///@{
  /// Atmospheric refraction of the sun's elevation (SPA eq. 42). Default on.
  vtkSetMacro(Refraction, bool);
  vtkGetMacro(Refraction, bool);
  vtkBooleanMacro(Refraction, bool);
  ///@}

  ///@{
  /// Refraction: mean air pressure (mbar; NaN, default: 1013.25 exp(-z/8200) at the mean
  /// elevation z) and temperature (degrees C, default 15).
  vtkSetMacro(Pressure, double);
  vtkGetMacro(Pressure, double);
  vtkSetMacro(AirTemperature, double);
  vtkGetMacro(AirTemperature, double);
  ///@}

  ///@{
  /// Clear-sky atmospheric transmittance tau, (0, 1]. Default 0.7.
  vtkSetMacro(Transmittance, double);
  vtkGetMacro(Transmittance, double);
  ///@}

  ///@{
  /// TT - UT1 in seconds for the ephemeris. Default 69.2 (2024).
  vtkSetMacro(DeltaT, double);
  vtkGetMacro(DeltaT, double);
  ///@}

  ///@{
  /**
   * Keep the horizon map between updates (HorizonSectors floats per cell: 256 B per cell by
   * default), so that a new sun time or mode on the same terrain skips the sweeps. Default
   * on; off frees it at the end of each update (batch chains, large grids).
   */
  vtkSetMacro(CacheHorizonMap, bool);
  vtkGetMacro(CacheHorizonMap, bool);
  vtkBooleanMacro(CacheHorizonMap, bool);
  ///@}

  /// Seconds the last run spent building the horizon map (0 when it came from the cache or
  /// was not needed).
  vtkGetMacro(LastHorizonMapSeconds, double);

  ///@{
  /**
   * Distributed runs only (pvbatch under mpirun, one piece per process): each piece computes
   * its shadows on itself and this many cells around it (ghost levels), as if the terrain
   * ended there. Default 256 cells, 1..100000.
   */
  vtkSetClampMacro(DistributedHalo, int, 1, 100000);
  vtkGetMacro(DistributedHalo, int);
  ///@}

  /**
   * Distributed runs: the share of (cell, sun step) pairs with the sun above the horizontal
   * whose lit/shadowed decision terrain beyond the halo could change (tan(sun elevation) <=
   * (highest cell of the whole grid - cell) / distance to the cut edge of its halo), over the
   * whole grid (all-reduced); 0 means the pieces give the serial shadows. -1 in a serial run.
   * Also field data `SunHaloUncertainShare`.
   */
  vtkGetMacro(LastHaloUncertainShare, double);

protected:
  vtkTerroirSolarIllumination();
  ~vtkTerroirSolarIllumination() override;

  int GetHaloWidth() override { return this->DistributedRequest ? this->DistributedHalo : -1; }
  int GetMinimumGridSize() override { return 2; }
  bool HasGPUPath() override { return true; }
  double EstimateMemory(double nx, double ny) override;
  std::string CheckParameters() override;
#ifndef __VTK_WRAP__
  int RequestTerrainData(vtkImageData* input,
    const terroir::TerrainInput& terrain,
    vtkImageData* output) override;
#endif

  int Mode = Monthly;
  int Year = 2025;
  int Month = 6;
  int Day = 21;
  double Time = 12.0;
  double UTCOffset = 0.0;
  bool UseSunDirection = false;
  double SunDirection[2] = { 180.0, 45.0 };
  int MonthlyDay = 15;
  double TimeStep = 10.0;
  double Latitude;
  double Longitude;
  double Orientation;
  int ShadowMethod = HorizonMap;
  int HorizonSectors = 64;
  bool EarthCurvature = false;
  bool OutputHorizonMap = false;
  bool CacheHorizonMap = true;
  bool Refraction = true;
  double Pressure;
  double AirTemperature = 15.0;
  double Transmittance = 0.7;
  double DeltaT = 69.2;
  double LastHorizonMapSeconds = 0.0;
  int DistributedHalo = 256;
  double LastHaloUncertainShare = -1.0;

private:
  vtkTerroirSolarIllumination(const vtkTerroirSolarIllumination&) = delete;
  void operator=(const vtkTerroirSolarIllumination&) = delete;

  struct Internals;
  std::unique_ptr<Internals> Impl;

#ifndef __VTK_WRAP__
  // RequestTerrainData in steps.
  /// Whether the run needs the terrain's place (all but an instant from SunDirection).
  bool NeedsPlace() const
  {
    return !(this->Mode == Instant && this->UseSunDirection);
  }
  /// The sun's frame (place, grid north, mean elevation, refraction) and the highest cell.
  bool MakeFrame(vtkImageData* input,
    const terroir::GridView<float>& v,
    terroir::terrain::SunFrame& frame,
    float& zMax);
  /// Distributed: LastHaloUncertainShare, its field data and warning (see its comment).
  bool MeasureHaloUncertainty(vtkImageData* input,
    const terroir::GridView<float>& v,
    const std::vector<terroir::terrain::SunStep>& steps,
    float zMax,
    vtkImageData* output);
  /// The sun steps of the Mode and the number of output slots (12 months, or 1).
  std::vector<terroir::terrain::SunStep> SunSteps(const terroir::terrain::SunFrame& frame,
    int& slots);
  /// The horizon map in the cache, computed again unless it is fresh (CPU or GPU).
  bool UpdateHorizonMap(vtkImageData* input,
    const terroir::TerrainInput& terrain,
    float curvature,
    int& backend);
  /// Hours and energy of every slot, on the GPU (falling back to the CPU) or the CPU.
  bool Accumulate(const terroir::TerrainInput& terrain,
    const terroir::terrain::ShadowSource<float>& source,
    const std::vector<float>& normals,
    const std::vector<terroir::terrain::SunStep>& steps,
    int slots,
    int& backend,
    float* hours,
    float* energy);
#endif
};

#endif

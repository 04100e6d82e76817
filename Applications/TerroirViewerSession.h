/**
 * @file TerroirViewerSession.h
 * @brief The model of `terroir view`, without any window: the terrain, the parameters, the
 * current overlay, the water state with its undo stack, the infiltration map, and a worker
 * thread that runs the filters off the render thread.
 *
 * A ViewerSession holds
 * - the terrain (a vtkImageData from our readers, `Elevation` in metres; shared read-only with
 *   the worker thread and the window);
 * - the parameters (ViewerParameters: latitude, longitude, month 1..12, hour of day, grid
 *   orientation, clusters K, lake depth, brush);
 * - the water state: a float array `WaterHeight` (metres, one value per point, 0 dry), changed
 *   by flood fills and by the water flow;
 * - the infiltration map `InfiltrationRate` (mm/h), vtkTerroirInfiltration's default recipe
 *   (15 mm/h, 0 above 30°) until changed with the brush (strokes), the fill or the slope rule;
 * - one undo stack for both: each change records the cells it changed with their previous
 *   values (or the whole previous array when it changed most cells), and Undo() restores the
 *   last change exactly (the same bytes), as many steps as there are.
 *
 * Overlays (ViewerOverlay) come from our filters: Slope (vtkTerroirSlope), Illumination
 * (vtkTerroirSolarIllumination, Instant at the hour on the 15th of the month, `Illuminated`),
 * SunHours (Daily on the 15th, `IlluminationHours`), Temperature (vtkTerroirTemperature, the
 * month's component), Humidity (vtkTerroirInfiltration's map into vtkTerroirSoilHumidity, the
 * month's `SoilHumidity`), Water (the water state itself) and Clusters (vtkTerroirSlope,
 * vtkTerroirTemperature, vtkTerroirSolarIllumination Monthly and vtkTerroirSoilHumidity's
 * `WeightedSoilHumidity` of the infiltration map into vtkTerroirKMeans, K clusters, the
 * features weighted by ClusterWeights). ComputeOverlay() runs one synchronously; RequestOverlay()
 * runs it on the worker thread on a copy of the inputs (the terrain shallow, the water and
 * infiltration arrays deep), so that the window keeps drawing; Pump() (called from the window's
 * timer) collects finished work and starts the next request; Wait() blocks until nothing is left to
 * do (scripts). Only the latest request of a kind is kept while the worker is busy.
 *
 * Everything but the worker's filter runs is meant for one (the window's) thread.
 */
#ifndef TerroirViewerSession_h
#define TerroirViewerSession_h

#include "TerroirViewerScript.h" // For ViewerOverlay
#include "vtkSmartPointer.h"     // For vtkSmartPointer
#include "vtkTable.h"            // For vtkSmartPointer<vtkTable> copies

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

class vtkDataArray;
class vtkFloatArray;
class vtkImageData;

namespace terroir
{
namespace viewer
{

static_assert(kViewerClusterFeatureCount == 4, "ViewerParameters::ClusterWeights lists 4");

/// The parameters the sliders, keys and script set.
struct ViewerParameters
{
  double Latitude = 45.0; ///< degrees north, [-90, 90]
  double Longitude = 0.0; ///< degrees east, [-180, 180]; sets the clock (local mean time)
  int Month = 6;          ///< 1..12 (the 15th of the month is used)
  double Hour = 10.0;     ///< local mean solar time, hours [0, 24]
  /// Bearing of grid north clockwise from true north, degrees (the compass); NaN: the
  /// terrain's meridian convergence, else 0.
  double Orientation = std::numeric_limits<double>::quiet_NaN();
  int Clusters = 5; ///< K of the clusters overlay, 1..64
  /// Weights of the clusters' features, one per kViewerClusterFeatures row (slope,
  /// temperature, sun hours, weighted soil humidity); 0 leaves a feature out.
  std::array<double, kViewerClusterFeatureCount> ClusterWeights = {
    kViewerClusterFeatures[0].DefaultWeight,
    kViewerClusterFeatures[1].DefaultWeight,
    kViewerClusterFeatures[2].DefaultWeight,
    kViewerClusterFeatures[3].DefaultWeight
  };
  /// A click's lake level above the clicked cell (at most the spill level), m.
  double LakeDepth = 5.0;
  double BrushRadius = 5.0;     ///< cells
  double BrushRate = 0.0;       ///< mm/h painted by the brush (and set everywhere by the fill)
  double SlopeThreshold = 30.0; ///< degrees: the slope rule sets 0 mm/h on steeper cells
  int FlowIterations = 500;     ///< most iterations of one water-flow run
  /// Water-flow mode: Long (2016)'s pulse (the water once, then the stop rule) or the
  /// river-forming mode (depressions filled, rain each iteration until the outflow balances
  /// it), vtkTerroirWaterFlow's Pulse and Rivers.
  bool FlowRivers = false;
  /// Pulse: mm of water put on every cell with data (plus the lakes); NaN: the month's rain
  /// that the soil does not take (`StandingWater`).
  double FlowWater = std::numeric_limits<double>::quiet_NaN();
  /// Rivers: rain, mm/h on every cell; NaN: the month's `StandingWater` spread over its hours.
  double FlowRainRate = std::numeric_limits<double>::quiet_NaN();
  double FlowStopRatio = 0.001; ///< pulse: Long (2016)'s stop rule (AutoStopRatio), 0 off
  double FlowBalance = 0.02;    ///< rivers: stop when the outflow is 1 - this of the rain
  /// The climate (Long 2016, eq. 3.4 and 3.5), January first: monthly precipitation R_q (mm)
  /// and intensity R_i (mm/h); the sea-level temperatures of the coldest and warmest months
  /// (°C), or the 12 of MonthlyTemperatures when UseMonthlyTemperatures (a climate file's
  /// `temperature_c`); the lapse rate (°C per km). ViewerSession's constructor sets the
  /// defaults of vtkTerroirSoilHumidity and vtkTerroirTemperature.
  std::array<double, 12> Precipitation{};
  std::array<double, 12> PrecipitationIntensity{};
  double Coldest = 0.0;
  double Warmest = 0.0;
  double LapseRate = 0.0;
  bool UseMonthlyTemperatures = false;
  std::array<double, 12> MonthlyTemperatures{};
  int FlowFrameInterval = 10; ///< iterations between the frames of a running water flow
  /// Live erosion (StartErosion): what the Brush tool paints while it runs (0 soil, 1 water,
  /// 2 vegetation: terroir::terrain::ErosionBrush), the dab's amount at its centre (m of soil
  /// or water, negative digs or dries; the target density for vegetation), rain (mm/h on every
  /// cell), water on every cell at the start (m; 0: dry, the water comes from the brush and the
  /// rain), vegetation coupled from the start (else from the first vegetation dab), and steps
  /// between two frames.
  int ErosionBrush = 1;
  double ErosionAmount = 0.5;
  double ErosionRain = 0.0;
  double ErosionInitialWater = 0.0;
  bool ErosionVegetation = false;
  int ErosionFrameInterval = 5;
};

/// One row of the cluster table: a cluster's colour, size and mean resources.
struct ClusterTableRow
{
  int Id = 0;
  std::string Color; ///< "#rrggbb", the Clusters overlay colour
  long long Cells = 0;
  double Share = 0.0;        ///< fraction of the cells that take part
  std::vector<double> Means; ///< one per ClusterTable::Columns
};

/// The table of vtkTerroirKMeans (its output port 1) reduced to what fits a window: the
/// one-component features and the given month's component of the monthly ones.
struct ClusterTable
{
  std::vector<std::string> Columns; ///< short titles with units, e.g. "Slope (deg)"
  std::vector<ClusterTableRow> Rows;
  /// From vtkTerroirKMeans's table; columns `X` and `X_<Mon>` of `month` (1..12). Known
  /// features get short titles (Slope, Temperature, IlluminationHours, WeightedSoilHumidity).
  /// `month` 0: every column, the monthly ones for every month ("Temp Jan (°C)", ...).
  static ClusterTable FromKMeans(vtkTable* table, int month);
  /// The table as CSV: a header `Cluster,Color,Cells,Share,<Columns>` and one line per row
  /// (numbers with 9 significant digits). False with "PATH: problem" when it cannot be written.
  bool WriteCsv(const std::string& path, std::string& error) const;
};

/// One overlay, ready to colour the terrain.
struct OverlayResult
{
  ViewerOverlay Overlay = ViewerOverlay::None;
  std::string ArrayName;                ///< e.g. "Slope"; empty for None
  int Component = 0;                    ///< component shown (the month's for monthly arrays)
  std::string Preset;                   ///< vtkTerroirColorPresets name
  vtkSmartPointer<vtkImageData> Output; ///< the filters' output (for legends: cluster shares)
  vtkSmartPointer<vtkTable> Table;      ///< Clusters: vtkTerroirKMeans's cluster table
  vtkDataArray* GetValues() const;      ///< the array in Output, or nullptr
  std::string Error;                    ///< non-empty when the filters failed
  unsigned long Generation = 0;         ///< request it answers
};

/// The overlays the session has a recipe for (TerroirViewerSessionOverlays.cxx: one function
/// per overlay runs its filters); every ViewerOverlay must have one (TestViewerSession).
std::vector<ViewerOverlay> ComputableOverlays();

class ViewerSession
{
public:
  ViewerSession();
  ~ViewerSession(); ///< waits for the worker thread
  ViewerSession(const ViewerSession&) = delete;
  ViewerSession& operator=(const ViewerSession&) = delete;

  /// Takes the terrain (shallow copy), resets the water (all dry, empty undo stack) and the
  /// infiltration map (default recipe), and takes latitude, longitude from its georeference
  /// when it has one. False with `error` when it has no one-component `Elevation` or is not a
  /// 2-D image of at least 2 × 2 points.
  bool SetTerrain(vtkImageData* terrain, std::string& error);
  vtkImageData* GetTerrain() const;
  /// True when the terrain came with a georeference (CRS or centre latitude/longitude).
  bool IsGeoreferenced() const;

  ///@{
  /// The climate file (CSV or JSON, vtkTerroirClimateReader): LoadClimate takes the series the
  /// file has (its `temperature_c` as the 12 sea-level temperatures); false with the reader's
  /// one-line "FILE: problem" and no change. SaveClimate writes a CSV the reader takes back:
  /// every month's precipitation, intensity and sea-level temperature (from the coldest and
  /// warmest months when no monthly ones are in use); false with "FILE: problem".
  bool LoadClimate(const std::string& path, std::string& error);
  bool SaveClimate(const std::string& path, std::string& error) const;
  ///@}

  ViewerParameters& Parameters();
  const ViewerParameters& Parameters() const;

  ///@{
  /// The overlay the window shows (bookkeeping only: RequestOverlay computes).
  void SetCurrentOverlay(ViewerOverlay overlay);
  ViewerOverlay GetCurrentOverlay() const;
  ///@}

  /// Runs the filters of `overlay` with `parameters` now, on the calling thread.
  OverlayResult ComputeOverlay(ViewerOverlay overlay, const ViewerParameters& parameters) const;

  /// The sun's grid azimuth (degrees clockwise from grid north) and elevation (degrees) at the
  /// parameters' date and hour, as the instant illumination overlay uses them.
  void SunDirection(const ViewerParameters& parameters,
    double& gridAzimuth,
    double& elevation) const;

  ///@{
  /// Asynchronous work. RequestOverlay computes the current overlay with the current
  /// parameters on the worker thread. Pump() collects finished work (a water-flow result
  /// replaces the water state, pushing the previous one) and starts what is queued; it returns
  /// true when something finished. TakeOverlay() hands out the newest finished overlay once.
  void RequestOverlay();
  /// The water flow with the parameters' mode, water or rain, stop rule and iterations,
  /// starting from the month's standing water (or FlowWater) plus the lakes.
  void RequestWaterFlow();
  bool Pump();
  bool TakeOverlay(OverlayResult& result);
  bool IsIdle() const;
  /// Blocks until the worker is idle and nothing is queued (Pump() included).
  void Wait();
  /// Progress of the running job in [0, 1] and its label ("Computing illumination").
  double GetProgress() const;
  std::string GetProgressLabel() const;
  /// The last error of a job (then cleared).
  std::string TakeError();
  ///@}

  ///@{
  /// Water. FloodFillAt fills the lake of cell (i, j) (i east, j north, from the first cell):
  /// the depression that holds the cell (vtkTerroirFloodFill, FillDepressions) up to
  /// level = min(the cell's elevation + LakeDepth, the depression's spill level). At the spill
  /// level the lake is the whole filled depression; below it, the cells connected to the click
  /// at or below the level (Seeds mode, which cannot leave the depression there). The new
  /// state is the larger depth of the old state and the lake on each cell. It pushes the
  /// previous state first. False with `error` (and no change) for a cell outside the terrain,
  /// without data, or not in a depression (water poured on a slope runs off).
  bool FloodFillAt(int i, int j, std::string& error);
  /// The sea of Long (2016)'s Fig. 3.33: every cell connected (8-connectivity, through cells
  /// at or below `level`) to an edge cell at or below `level` takes water up to `level`
  /// (vtkTerroirFloodFill, Seeds mode, one seed per such edge cell); the new state is the
  /// larger depth on each cell, one undo step. Returns the cells under water (depth > 0), or
  /// -1 with `error` (and no change) when no edge cell lies that low.
  long long FloodSea(double level, std::string& error);
  /// Restores the water or infiltration map as it was before the last change (ending a
  /// brush stroke first); false (and no change) when there is none.
  bool Undo();
  std::size_t GetUndoDepth() const;
  /// Counts the changes of the water state (fills, undos, water-flow results), so that a
  /// window can tell that it must redraw the water.
  unsigned long GetWaterVersion() const;
  /// The current water state (`WaterHeight`, metres). Changes in place; do not keep it
  /// across a change if you need the old values.
  vtkFloatArray* GetWater() const;
  /// What to draw: the live erosion's water frame while there is one (StartErosion, until
  /// KeepErosion or a new terrain), else while a water flow runs its latest frame (the state
  /// after GetFlowFrameIteration() iterations, every FlowFrameInterval), else GetWater().
  vtkFloatArray* GetDisplayedWater() const;
  /// Changes whenever GetDisplayedWater() does (water changes and flow frames).
  unsigned long GetDisplayedWaterVersion() const;
  /// Iterations of the frame on display; 0 when no flow frame is shown.
  long long GetFlowFrameIteration() const;
  /// Frames the worker published during the last (or running) water flow; for tests.
  long long GetFlowFramesPublished() const;
  /// The last finished water flow: its iterations and stop reason (vtkTerroirWaterFlow's
  /// `WaterFlowIterations`, `WaterFlowStopReason`); -1 and "" before any.
  long long GetLastFlowIterations() const;
  std::string GetLastFlowStopReason() const;
  ///@}

  ///@{
  /// Infiltration (`InfiltrationRate`, mm/h), changed by Long (2016)'s three tools.
  /// Paint: BrushRate on every cell with data within BrushRadius cells of (i, j), or of the
  /// segment from (i0, j0) to (i1, j1) (a drag); returns the number of cells within reach.
  /// Between BeginStroke() and EndStroke() the dabs make one undo step; a dab outside a
  /// stroke is a stroke of its own. EndStroke() returns the cells the stroke changed.
  /// FillInfiltration sets BrushRate on every cell with data; ApplySlopeRule sets 0 mm/h
  /// where the slope exceeds SlopeThreshold (vtkTerroirInfiltration's slope rule, Horn's
  /// slope); both return the cells they changed (one undo step when any), ApplySlopeRule -1
  /// with `error` when the filter fails.
  vtkFloatArray* GetInfiltration() const;
  unsigned long GetInfiltrationVersion() const;
  void BeginStroke();
  int PaintInfiltration(int i, int j);
  int PaintInfiltrationAlong(double i0, double j0, double i1, double j1);
  long long EndStroke();
  long long FillInfiltration();
  long long ApplySlopeRule(std::string& error);
  ///@}

  ///@{
  /// Live erosion (Dunn 2015's sandbox; terroir::terrain::ErosionSimulation with
  /// vtkTerroirErosion's defaults: Weiss's constants, a soil-slip step after every hydraulic
  /// step, a closed domain; ErosionInitialWater, ErosionRain, ErosionVegetation) on a thread
  /// of its own, with the terrain as it is now. Dabs painted while it runs (PaintErosion, the
  /// Brush tool) are applied between two steps. Every ErosionFrameInterval steps it publishes
  /// a frame: the bed (m), the water depth (m), the suspended sediment and, with vegetation,
  /// the density.
  /// StartErosion is false with `error` when one runs already or the terrain cannot be used.
  /// StopErosion ends the run (the last frame stays); KeepErosion ends it and makes the bed
  /// the terrain's `Elevation` (as SetTerrain: water, infiltration and undo start again).
  bool StartErosion(std::string& error);
  void StopErosion();
  bool KeepErosion(std::string& error);
  bool IsEroding() const;
  /// Queues a dab of the parameters' brush, amount and BrushRadius at cell (i, j); false when
  /// no erosion runs.
  bool PaintErosion(double i, double j);
  /// Blocks until the run has done at least `steps` steps (or stopped, or `timeout` seconds
  /// passed); false when it did not get there.
  bool WaitErosionSteps(long long steps, double timeout);
  long long GetErosionSteps() const;
  /// Steps per second of the run (wall clock, frames included), 0 before the first frame.
  double GetErosionStepsPerSecond() const;
  /// Changes with every frame; the frame's arrays (null before the first; the vegetation null
  /// without vegetation): bed (m), water depth (m), suspended sediment (m of bed), density.
  /// Valid until the next call that changes the version.
  unsigned long GetErosionFrameVersion() const;
  vtkFloatArray* GetErosionBed() const;
  vtkFloatArray* GetErosionWater() const;
  vtkFloatArray* GetErosionSediment() const;
  vtkFloatArray* GetErosionVegetation() const;
  ///@}

private:
  struct Internals;
  std::unique_ptr<Internals> Impl;
};

} // namespace viewer
} // namespace terroir

#endif

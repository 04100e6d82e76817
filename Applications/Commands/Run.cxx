// `terroir run`: every filter on one DEM with defaults; .vti, GeoTIFFs, PNG overlays,
// report.md/json
#include "RunState.h"
#include "TerroirCommands.h"

#include "TerroirApp.h"
#include "TerroirClusterSupport.h"
#include "TerroirCommandSupport.h"
#include "TerroirFlowSupport.h"
#include "TerroirWaterSupport.h"

#include "RiverValidation.h"
#include "SoilWater.h"

#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationStringKey.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkUnsignedCharArray.h"

#include "vtkTerroirComputeContext.h"
#include "vtkTerroirFloodFill.h"
#include "vtkTerroirFractalTerrainSource.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirInfiltration.h"
#include "vtkTerroirKMeans.h"
#include "vtkTerroirSlope.h"
#include "vtkTerroirSoilHumidity.h"
#include "vtkTerroirSolarIllumination.h"
#include "vtkTerroirTemperature.h"
#include "vtkTerroirWaterFlow.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace terroir
{
namespace app
{
namespace
{

// ---- slope ------------------------------------------------------------------------------------
void SlopeFiles(const RunState& r, RunFiles& f)
{
  f.Rasters.insert(f.Rasters.end(), { r.File("slope.tif"), r.File("aspect.tif") });
  f.Pictures.push_back(r.File("slope.png"));
}
void SlopeCompute(RunState& r)
{
  vtkNew<vtkTerroirSlope> slope;
  slope->SetBackend(r.Backend);
  r.Result = RunStage(slope.Get(), r.Result, "slope", r.Stages);
}
void SlopeWrite(RunState& r)
{
  WriteGeoTIFF(r.Result, "Slope", r.File("slope.tif"), r.Overwrite());
  WriteGeoTIFF(r.Result, "Aspect", r.File("aspect.tif"), r.Overwrite());
  if (r.Png)
  {
    WriteOverlay(r.Result, "Slope", 0, "Slope", "Slope (°)", r.File("slope.png"), r.Overwrite());
  }
}

// ---- temperature ------------------------------------------------------------------------------
void TemperatureFiles(const RunState& r, RunFiles& f)
{
  f.Rasters.push_back(r.File("temperature.tif"));
  f.Pictures.insert(
    f.Pictures.end(), { r.File("temperature_jan.png"), r.File("temperature_jul.png") });
}
void TemperatureCompute(RunState& r)
{
  vtkNew<vtkTerroirTemperature> temperature;
  temperature->SetBackend(r.Backend);
  ApplyTemperature(r.Line.Temperature, temperature);
  r.Result = RunStage(temperature.Get(), r.Result, "temperature", r.Stages);
}
void TemperatureWrite(RunState& r)
{
  WriteGeoTIFF(r.Result, "Temperature", r.File("temperature.tif"), r.Overwrite());
  if (r.Png)
  {
    WriteOverlay(r.Result,
      "Temperature",
      0,
      "Temperature",
      "Temperature, January (°C)",
      r.File("temperature_jan.png"),
      r.Overwrite());
    WriteOverlay(r.Result,
      "Temperature",
      6,
      "Temperature",
      "Temperature, July (°C)",
      r.File("temperature_jul.png"),
      r.Overwrite());
  }
}

// ---- illumination: monthly, at the solstices December (longest shadows) and June -------------
void IlluminationFiles(const RunState& r, RunFiles& f)
{
  f.Rasters.insert(f.Rasters.end(), { r.File("illumination.tif"), r.File("insolation.tif") });
  f.Pictures.insert(f.Pictures.end(),
    { r.File("illumination_dec.png"),
      r.File("illumination_jun.png"),
      r.File("insolation_dec.png"),
      r.File("insolation_jun.png") });
}
void IlluminationCompute(RunState& r)
{
  // The filter's defaults (the 15th of each month of 2025, 10-minute steps, horizon map of 64
  // sectors). Without a georeference there is no sun to place unless --lat and --lon say
  // where: the stage is then skipped, with a warning, and its outputs with it.
  const IlluminationSettings& s = r.Line.Illumination;
  r.Illuminate = r.Located || (std::isfinite(s.Latitude) && std::isfinite(s.Longitude));
  if (!r.Illuminate)
  {
    const std::string why = "the DEM has no georeference; pass --lat and --lon";
    std::cerr << "terroir: warning: " << r.Dem << ": illumination skipped (" << why << ")\n";
    r.Stages["illumination"] = json{ { "skipped", why } };
    RunFiles skipped;
    IlluminationFiles(r, skipped);
    for (const auto* list : { &skipped.Rasters, &skipped.Pictures })
    {
      for (const std::string& file : *list)
      {
        r.Outputs.erase(std::remove(r.Outputs.begin(), r.Outputs.end(), file), r.Outputs.end());
      }
    }
    return;
  }
  vtkNew<vtkTerroirSolarIllumination> illumination;
  illumination->SetBackend(r.Backend);
  illumination->SetLatitude(s.Latitude);
  illumination->SetLongitude(s.Longitude);
  r.Result = RunStage(illumination.Get(), r.Result, "illumination", r.Stages);
  r.HorizonMapSeconds = illumination->GetLastHorizonMapSeconds();
  json& st = r.Stages["illumination"];
  st["horizon_map_seconds"] = r.HorizonMapSeconds;
  st["horizon_sectors"] = illumination->GetHorizonSectors();
  st["year"] = illumination->GetYear();
  st["monthly_day"] = illumination->GetMonthlyDay();
  st["time_step_min"] = illumination->GetTimeStep();
}
void IlluminationWrite(RunState& r)
{
  if (!r.Illuminate)
  {
    return;
  }
  WriteGeoTIFF(r.Result, "IlluminationHours", r.File("illumination.tif"), r.Overwrite());
  WriteGeoTIFF(r.Result, "Insolation", r.File("insolation.tif"), r.Overwrite());
  if (!r.Png)
  {
    return;
  }
  struct Picture
  {
    const char* Array;
    int Month;
    const char* Preset;
    const char* Title;
    const char* File;
  };
  for (const Picture& p :
    { Picture{ "IlluminationHours",
        11,
        "Illumination",
        "Direct sun, December 15 (h/day)",
        "illumination_dec.png" },
      Picture{ "IlluminationHours",
        5,
        "Illumination",
        "Direct sun, June 15 (h/day)",
        "illumination_jun.png" },
      Picture{ "Insolation",
        11,
        "Insolation",
        "Insolation, December 15 (Wh/m²/day)",
        "insolation_dec.png" },
      Picture{
        "Insolation", 5, "Insolation", "Insolation, June 15 (Wh/m²/day)", "insolation_jun.png" } })
  {
    WriteOverlay(r.Result, p.Array, p.Month, p.Preset, p.Title, r.File(p.File), r.Overwrite());
  }
}

// ---- soil water: the default infiltration recipe (fill 15 mm/h, none on slopes over 30 deg)
// and the climate of --precip/--intensity, --climate or the defaults ---------------------------
void SoilWaterFiles(const RunState& r, RunFiles& f)
{
  f.Rasters.insert(f.Rasters.end(),
    { r.File("infiltration.tif"),
      r.File("humidity.tif"),
      r.File("weighted_humidity.tif"),
      r.File("standing_water.tif") });
  f.Pictures.insert(f.Pictures.end(), { r.File("humidity_jan.png"), r.File("humidity_jul.png") });
}
void SoilWaterCompute(RunState& r)
{
  vtkNew<vtkTerroirInfiltration> infiltration;
  r.Result = RunStage(infiltration.Get(), r.Result, "infiltration", r.Stages);
  vtkNew<vtkTerroirSoilHumidity> humidity;
  humidity->SetBackend(r.Backend);
  ApplyClimate(r.Line.SoilWater, humidity);
  r.Result = RunStage(humidity.Get(), r.Result, "humidity", r.Stages);
}
void SoilWaterWrite(RunState& r)
{
  WriteGeoTIFF(r.Result,
    vtkTerroirInfiltration::InfiltrationRateName(),
    r.File("infiltration.tif"),
    r.Overwrite());
  WriteGeoTIFF(
    r.Result, vtkTerroirSoilHumidity::SoilHumidityName(), r.File("humidity.tif"), r.Overwrite());
  WriteGeoTIFF(r.Result,
    vtkTerroirSoilHumidity::WeightedSoilHumidityName(),
    r.File("weighted_humidity.tif"),
    r.Overwrite());
  WriteGeoTIFF(r.Result,
    vtkTerroirSoilHumidity::StandingWaterName(),
    r.File("standing_water.tif"),
    r.Overwrite());
  if (r.Png)
  {
    WriteOverlay(r.Result,
      vtkTerroirSoilHumidity::WeightedSoilHumidityName(),
      0,
      "Humidity",
      "Weighted soil humidity, January (mm)",
      r.File("humidity_jan.png"),
      r.Overwrite());
    WriteOverlay(r.Result,
      vtkTerroirSoilHumidity::WeightedSoilHumidityName(),
      6,
      "Humidity",
      "Weighted soil humidity, July (mm)",
      r.File("humidity_jul.png"),
      r.Overwrite());
  }
}

// ---- lakes: every closed depression and hydro-flattened water surface of at least 1 ha --------
void LakesFiles(const RunState& r, RunFiles& f)
{
  f.Rasters.push_back(r.File("lakes.tif"));
  f.Pictures.push_back(r.File("lakes.png"));
}
void LakesCompute(RunState& r)
{
  vtkNew<vtkTerroirFloodFill> lakes;
  lakes->SetModeToFillDepressions();
  r.Result = RunStage(lakes.Get(), r.Result, "lakes", r.Stages);
  vtkDataArray* levels =
    r.Result->GetFieldData()->GetArray(vtkTerroirFloodFill::WaterBodyLevelName());
  r.Stages["lakes"]["water_bodies"] = levels ? levels->GetNumberOfTuples() : 0;
}
void LakesWrite(RunState& r)
{
  WriteGeoTIFF(r.Result, vtkTerroirFloodFill::WaterDepthName(), r.File("lakes.tif"), r.Overwrite());
  if (r.Png)
  {
    WriteOverlay(r.Result,
      vtkTerroirFloodFill::WaterDepthName(),
      0,
      "WaterBodies",
      "Lakes and closed depressions (depth, m)",
      r.File("lakes.png"),
      r.Overwrite());
  }
}

// ---- rivers: the water flow's river-forming mode (steady rain until the outflow balances it),
// the river network (rivers, and the lakes above) and, on the bundled DEM, its scores -----------
void RiversFiles(const RunState& r, RunFiles& f)
{
  f.Rasters.insert(f.Rasters.end(), { r.File("rivers.tif"), r.File("discharge.tif") });
  f.Pictures.insert(f.Pictures.end(), { r.File("rivers.png"), r.File("rivers_relief.png") });
  if (r.Bundled)
  {
    f.Pictures.push_back(r.File("validation.png"));
  }
}
/// The River and lake cells as one array (1 river, 2 lake), and the network in the report.
void ReportRiverNetwork(RunState& r, vtkTerroirWaterFlow* flow)
{
  vtkPointData* rpd = r.Result->GetPointData();
  vtkDataArray* river = rpd->GetArray(vtkTerroirWaterFlow::RiverName());
  vtkDataArray* lake = rpd->GetArray(vtkTerroirFloodFill::WaterBodyName());
  vtkNew<vtkUnsignedCharArray> network;
  network->SetName("RiverNetwork");
  network->SetNumberOfTuples(river->GetNumberOfTuples());
  long long riverCells = 0;
  for (vtkIdType k = 0; k < river->GetNumberOfTuples(); ++k)
  {
    const bool isRiver = river->GetComponent(k, 0) != 0.0;
    const bool isLake = lake && lake->GetComponent(k, 0) != 0.0;
    network->SetValue(k, isRiver ? 1 : (isLake ? 2 : 0));
    riverCells += isRiver ? 1 : 0;
  }
  rpd->AddArray(network);
  const double cell = std::sqrt(std::fabs(r.Spacing[0] * r.Spacing[1]));
  vtkFieldData* fd = r.Result->GetFieldData();
  json& rs = r.Stages["rivers"];
  rs["iterations"] = fd->GetArray(vtkTerroirWaterFlow::IterationsName())->GetComponent(0, 0);
  rs["stop_reason"] =
    vtkStringArray::SafeDownCast(fd->GetAbstractArray(vtkTerroirWaterFlow::StopReasonName()))
      ->GetValue(0);
  rs["rain_mm_per_h"] = flow->GetRainRate();
  if (vtkDataArray* levels =
        vtkDataArray::SafeDownCast(fd->GetAbstractArray("WaterFlowWarmStartIterations")))
  {
    // The coarse-to-fine start: iterations and size of each level, coarsest first.
    json warm = json::array();
    for (vtkIdType l = 0; l < levels->GetNumberOfTuples(); ++l)
    {
      warm.push_back({ { "iterations", levels->GetComponent(l, 0) },
        { "nx", levels->GetComponent(l, 1) },
        { "ny", levels->GetComponent(l, 2) } });
    }
    rs["warm_start_levels"] = warm;
  }
  rs["river_area_m2"] = flow->GetRiverArea();
  rs["river_cells"] = riverCells;
  rs["river_length_km"] = riverCells * cell / 1000.0; // cells x cell size: approximate
  json lakeList = json::array();
  vtkDataArray* areas = fd->GetArray(vtkTerroirFloodFill::WaterBodyAreaName());
  double lakeArea = 0.0;
  for (vtkIdType k = 0; areas && k < areas->GetNumberOfTuples(); ++k)
  {
    lakeList.push_back(areas->GetComponent(k, 0));
    lakeArea += areas->GetComponent(k, 0);
  }
  rs["lakes"] = lakeList.size();
  rs["lake_area_m2"] = lakeArea;
  rs["lake_areas_m2"] = lakeList;
}
/// The bundled DEM's rivers against its NHD flowlines in its watershed (scores, and the picture
/// of the comparison when PNGs are written).
void ValidateBundledRivers(RunState& r)
{
  const std::string dataDir = r.Dem.substr(0, r.Dem.find_last_of('/') + 1);
  const std::string referenceLines = dataDir + "sagehen_nhd_flowlines_utm11n.geojson";
  const std::string referenceArea = dataDir + "sagehen_watershed_utm11n.geojson";
  const double tv = Now();
  RiverReference reference(r.Result, r.Dem, referenceLines, referenceArea, r.Line.AllowNetwork);
  std::vector<std::uint8_t> simulated;
  const MethodScores scores = ScoreRiverMeasure("rivers",
    "RiverStrength (m3/s)",
    PointArrayValues(r.Result, vtkTerroirWaterFlow::RiverStrengthName()),
    std::nan(""),
    reference,
    simulated);
  json v = MethodScoresJson(scores);
  v["reference"] = referenceLines;
  v["area"] = referenceArea;
  v["reference_cells"] = reference.Cells;
  v["seconds"] = Now() - tv;
  r.Stages["rivers"]["validation"] = v;
  if (r.Png)
  {
    const std::size_t n = simulated.size();
    std::vector<std::uint8_t> category(n, 0);
    terroir::hydrology::RiverComparisonCategories(
      reference.View, simulated.data(), reference.Area.data(), 60.0, category.data());
    r.ValidationPicture = vtkSmartPointer<vtkImageData>::New();
    r.ValidationPicture->ShallowCopy(r.Result);
    vtkNew<vtkUnsignedCharArray> cat;
    cat->SetName("RiverComparison");
    cat->SetNumberOfTuples(static_cast<vtkIdType>(n));
    std::copy(category.begin(), category.end(), cat->GetPointer(0));
    r.ValidationPicture->GetPointData()->AddArray(cat);
  }
}
void RiversCompute(RunState& r)
{
  vtkNew<vtkTerroirWaterFlow> flow;
  flow->SetBackend(r.Backend);
  flow->SetModeToRivers();
  r.Result = RunStage(flow.Get(), r.Result, "rivers", r.Stages);
  ReportRiverNetwork(r, flow);
  if (r.Bundled)
  {
    ValidateBundledRivers(r);
  }
}
void RiversWrite(RunState& r)
{
  WriteGeoTIFF(r.Result, vtkTerroirWaterFlow::RiverName(), r.File("rivers.tif"), r.Overwrite());
  WriteGeoTIFF(
    r.Result, vtkTerroirWaterFlow::DischargeRateName(), r.File("discharge.tif"), r.Overwrite());
  if (!r.Png)
  {
    return;
  }
  WriteOverlay(r.Result,
    "RiverNetwork",
    0,
    "Rivers",
    "Rivers and lakes (map)",
    r.File("rivers.png"),
    r.Overwrite(),
    true);
  WriteOverlay(r.Result,
    "RiverNetwork",
    0,
    "Rivers",
    "Rivers and lakes",
    r.File("rivers_relief.png"),
    r.Overwrite());
  if (r.ValidationPicture)
  {
    WriteOverlay(r.ValidationPicture,
      "RiverComparison",
      0,
      "RiverComparison",
      "Rivers against NHD within 60 m (map)",
      r.File("validation.png"),
      r.Overwrite(),
      true);
  }
}

// ---- ecological zones: k-means of the resources with Long (2016)'s features and weights ------
void ClustersFiles(const RunState& r, RunFiles& f)
{
  if (r.Clusters() > 0)
  {
    f.Tables.insert(
      f.Tables.end(), { r.File("clusters.tif"), r.File("clusters.csv"), r.File("clusters.json") });
    f.Pictures.push_back(r.File("clusters.png"));
  }
}
void ClustersCompute(RunState& r)
{
  if (r.Clusters() <= 0)
  {
    r.Stages["clusters"] = json{ { "skipped", "--clusters 0" } };
    return;
  }
  vtkNew<vtkTerroirKMeans> kmeans;
  KMeansSettings settings;
  settings.Clusters = r.Clusters();
  ApplyKMeans(settings, r.Line.Backend, kmeans);
  r.Result = RunStage(kmeans.Get(), r.Result, "clusters", r.Stages);
  r.ClusterTable->DeepCopy(kmeans->GetClusterTable());
  r.ClusterSummary = ClusterTableJSON(r.ClusterTable, r.Result);
  json& st = r.Stages["clusters"];
  st["k"] = r.Clusters();
  st["iterations"] = r.ClusterSummary["iterations"];
  st["stop_reason"] = r.ClusterSummary["stop_reason"];
}
void ClustersWrite(RunState& r)
{
  if (r.Clusters() <= 0)
  {
    return;
  }
  WriteGeoTIFF(r.Result, vtkTerroirKMeans::ClusterIdName(), r.File("clusters.tif"), r.Overwrite());
  WriteTextFile(r.File("clusters.csv"), ClusterTableCSV(r.ClusterTable), r.Overwrite());
  WriteTextFile(r.File("clusters.json"), r.ClusterSummary.dump(2) + "\n", r.Overwrite());
  if (r.Png)
  {
    WriteOverlay(r.Result,
      vtkTerroirKMeans::ClusterIdName(),
      0,
      "Clusters",
      "Ecological zones (k-means, K = " + std::to_string(r.Clusters()) + ")",
      r.File("clusters.png"),
      r.Overwrite());
  }
}

/// The stages, in the order they run (and their files are listed).
const std::vector<RunStep>& RunSteps()
{
  static const std::vector<RunStep> steps = {
    { "slope", SlopeFiles, SlopeCompute, SlopeWrite },
    { "temperature", TemperatureFiles, TemperatureCompute, TemperatureWrite },
    { "illumination", IlluminationFiles, IlluminationCompute, IlluminationWrite },
    { "soil water", SoilWaterFiles, SoilWaterCompute, SoilWaterWrite },
    { "lakes", LakesFiles, LakesCompute, LakesWrite },
    { "rivers", RiversFiles, RiversCompute, RiversWrite },
    { "clusters", ClustersFiles, ClustersCompute, ClustersWrite },
  };
  return steps;
}

// ---- reading and the reports --------------------------------------------------------------------
void ReadTerrainStage(RunState& r)
{
  const double t0 = Now();
  r.Result = ReadTerrain(r.Dem, r.Line.AllowNetwork, r.Line.ZUnit);
  r.Stages["read"] = json{ { "seconds", Now() - t0 } };
  r.Result->GetDimensions(r.Dims);
  r.Result->GetSpacing(r.Spacing);
  r.Located = vtkTerroirGeoreference::GetCenterLatLon(r.Result, r.LatLon);
  r.Report["grid"] = json{ { "nx", r.Dims[0] },
    { "ny", r.Dims[1] },
    { "dx_m", r.Spacing[0] },
    { "dy_m", r.Spacing[1] },
    { "geographic", vtkTerroirGeoreference::GetRowSpacing(r.Result) != nullptr } };
  r.Report["georeference"] = json{ { "has_crs", !vtkTerroirGeoreference::GetCRS(r.Result).empty() },
    { "center_lat", r.Located ? json(r.LatLon[0]) : json(nullptr) },
    { "center_lon", r.Located ? json(r.LatLon[1]) : json(nullptr) },
    { "meridian_convergence_deg", vtkTerroirGeoreference::GetMeridianConvergence(r.Result) } };
}

/// The write stage's time and where it went: each file written since the run began (name,
/// kind, seconds) and the seconds per kind (vti, geotiff, png, text).
json WriteBreakdown(double seconds)
{
  json files = json::array();
  json byKind = json::object();
  for (const WrittenFile& f : TakeWrittenFiles())
  {
    files.push_back(json{ { "file", fs::path(f.Path).filename().string() },
      { "kind", f.Kind },
      { "seconds", f.Seconds } });
    byKind[f.Kind] = byKind.value(f.Kind, 0.0) + f.Seconds;
  }
  return json{ { "seconds", seconds }, { "files", files }, { "seconds_by_kind", byKind } };
}

int RunEveryStage(const CommandLine& c)
{
  RunState r(c);
  r.Dem = c.Input.empty() ? DefaultDEM() : c.Input;
  r.Bundled = c.Input.empty();
  r.Backend = ParseBackend(c.Backend);
  r.Png = !c.NoPng;
  std::error_code ec;
  fs::create_directories(c.Output, ec);
  if (ec || !fs::is_directory(c.Output))
  {
    throw Failure(c.Output + ": cannot create the output folder" + (ec ? ": " + ec.message() : ""));
  }
  r.Out = fs::path(c.Output);

  // Every file, checked before any work, so that a refused run leaves nothing behind.
  RunFiles files;
  for (const RunStep& step : RunSteps())
  {
    step.Files(r, files);
  }
  r.Outputs = { r.File("terrain.vti") };
  r.Outputs.insert(r.Outputs.end(), files.Rasters.begin(), files.Rasters.end());
  r.Outputs.insert(r.Outputs.end(), { r.File("report.md"), r.File("report.json") });
  r.Outputs.insert(r.Outputs.end(), files.Tables.begin(), files.Tables.end());
  if (r.Png)
  {
    if (!HaveDisplay())
    {
      throw Failure("PNG overlays need an X display (VTK 9.1 renders through X): run under "
                    "'xvfb-run -a', or pass --no-png");
    }
    r.Outputs.insert(r.Outputs.end(), files.Pictures.begin(), files.Pictures.end());
  }
  CheckWritable(r.Outputs, c.Overwrite);

  r.Report["input"] = r.Dem;
  TakeWrittenFiles(); // only this run's files in its breakdown
  ReadTerrainStage(r);
  for (const RunStep& step : RunSteps())
  {
    step.Compute(r);
  }
  const double tw = Now();
  WriteVTI(r.Result, r.File("terrain.vti"), c.Overwrite);
  for (const RunStep& step : RunSteps())
  {
    step.Write(r);
  }
  r.Stages["write"] = WriteBreakdown(Now() - tw);
  r.Report["stages"] = r.Stages;
  json arrays = ArraysReport(r.Result);
  r.Report["arrays"] = arrays;
  if (r.Clusters() > 0)
  {
    r.Report["clusters"] = json::parse(r.ClusterSummary.dump());
  }
  r.Report["outputs"] = r.Outputs;
  WriteReports(r, arrays);
  PrintSummary(r);
  return 0;
}
} // namespace

int CommandRun(const CommandLine& c)
{
  return RunEveryStage(c);
}

} // namespace app
} // namespace terroir

// `terroir run`: every filter on one DEM with defaults; .vti, GeoTIFFs, PNG overlays,
// report.md/json
#include "RunState.h"
#include "TerroirCommands.h"

#include "TerroirApp.h"
#include "TerroirClusterSupport.h"
#include "TerroirCommandSupport.h"
#include "TerroirFlowSupport.h"
#include "TerroirWaterSupport.h"

#include "RunWriter.h"
#include "TerroirSafeOutput.h"

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
#include "vtkTerroirGeoTIFFWriter.h"
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
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace terroir
{
namespace app
{
namespace
{

// ---- writing one file, when --outputs selects it (on the writer thread) ----------------------
void Tif(const RunState& r, vtkImageData* image, const char* array, const char* name)
{
  const std::string path = r.File(name);
  if (r.Wants(path))
  {
    WriteGeoTIFF(image, array, path, r.Overwrite(), r.Tiff);
  }
}
void Png(const RunState& r,
  vtkImageData* image,
  const char* array,
  int month,
  const char* preset,
  const std::string& title,
  const char* name,
  bool map = false)
{
  const std::string path = r.File(name);
  if (r.Png && r.Wants(path))
  {
    WriteOverlay(image, array, month, preset, title, path, r.Overwrite(), map);
  }
}
void Text(const RunState& r, const char* name, const std::string& text)
{
  const std::string path = r.File(name);
  if (r.Wants(path))
  {
    WriteTextFile(path, text, r.Overwrite());
  }
}

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
void SlopeWrite(const RunState& r, vtkImageData* image)
{
  Tif(r, image, "Slope", "slope.tif");
  Tif(r, image, "Aspect", "aspect.tif");
  Png(r, image, "Slope", 0, "Slope", "Slope (°)", "slope.png");
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
void TemperatureWrite(const RunState& r, vtkImageData* image)
{
  Tif(r, image, "Temperature", "temperature.tif");
  Png(
    r, image, "Temperature", 0, "Temperature", "Temperature, January (°C)", "temperature_jan.png");
  Png(r, image, "Temperature", 6, "Temperature", "Temperature, July (°C)", "temperature_jul.png");
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
void IlluminationWrite(const RunState& r, vtkImageData* image)
{
  if (!r.Illuminate)
  {
    return;
  }
  Tif(r, image, "IlluminationHours", "illumination.tif");
  Tif(r, image, "Insolation", "insolation.tif");
  const char* hours = "IlluminationHours";
  Png(
    r, image, hours, 11, "Illumination", "Direct sun, December 15 (h/day)", "illumination_dec.png");
  Png(r, image, hours, 5, "Illumination", "Direct sun, June 15 (h/day)", "illumination_jun.png");
  const char* energy = "Insolation";
  const char* preset = "Insolation";
  Png(r, image, energy, 11, preset, "Insolation, December 15 (Wh/m²/day)", "insolation_dec.png");
  Png(r, image, energy, 5, preset, "Insolation, June 15 (Wh/m²/day)", "insolation_jun.png");
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
void SoilWaterWrite(const RunState& r, vtkImageData* image)
{
  Tif(r, image, vtkTerroirInfiltration::InfiltrationRateName(), "infiltration.tif");
  Tif(r, image, vtkTerroirSoilHumidity::SoilHumidityName(), "humidity.tif");
  const char* weighted = vtkTerroirSoilHumidity::WeightedSoilHumidityName();
  Tif(r, image, weighted, "weighted_humidity.tif");
  Tif(r, image, vtkTerroirSoilHumidity::StandingWaterName(), "standing_water.tif");
  Png(
    r, image, weighted, 0, "Humidity", "Weighted soil humidity, January (mm)", "humidity_jan.png");
  Png(r, image, weighted, 6, "Humidity", "Weighted soil humidity, July (mm)", "humidity_jul.png");
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
void LakesWrite(const RunState& r, vtkImageData* image)
{
  Tif(r, image, vtkTerroirFloodFill::WaterDepthName(), "lakes.tif");
  Png(r,
    image,
    vtkTerroirFloodFill::WaterDepthName(),
    0,
    "WaterBodies",
    "Lakes and closed depressions (depth, m)",
    "lakes.png");
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
  if (r.Png && r.Wants(r.File("validation.png")))
  {
    const std::size_t n = simulated.size();
    std::vector<std::uint8_t> category(n, 0);
    terroir::hydrology::RiverComparisonCategories(
      reference.View, simulated.data(), reference.Area.data(), 60.0, category.data());
    r.RiverComparison = vtkSmartPointer<vtkUnsignedCharArray>::New();
    r.RiverComparison->SetName("RiverComparison");
    r.RiverComparison->SetNumberOfTuples(static_cast<vtkIdType>(n));
    std::copy(category.begin(), category.end(), r.RiverComparison->GetPointer(0));
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
void RiversWrite(const RunState& r, vtkImageData* image)
{
  Tif(r, image, vtkTerroirWaterFlow::RiverName(), "rivers.tif");
  Tif(r, image, vtkTerroirWaterFlow::DischargeRateName(), "discharge.tif");
  Png(r, image, "RiverNetwork", 0, "Rivers", "Rivers and lakes (map)", "rivers.png", true);
  Png(r, image, "RiverNetwork", 0, "Rivers", "Rivers and lakes", "rivers_relief.png");
  if (r.RiverComparison)
  {
    // The comparison with NHD: its own picture, not an array of terrain.vti.
    vtkNew<vtkImageData> picture;
    picture->ShallowCopy(image);
    picture->GetPointData()->AddArray(r.RiverComparison);
    Png(r,
      picture,
      "RiverComparison",
      0,
      "RiverComparison",
      "Rivers against NHD within 60 m (map)",
      "validation.png",
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
  r.ClusterCSV = ClusterTableCSV(kmeans->GetClusterTable());
  r.ClusterSummary = ClusterTableJSON(kmeans->GetClusterTable(), r.Result);
  json& st = r.Stages["clusters"];
  st["k"] = r.Clusters();
  st["iterations"] = r.ClusterSummary["iterations"];
  st["stop_reason"] = r.ClusterSummary["stop_reason"];
}
void ClustersWrite(const RunState& r, vtkImageData* image)
{
  if (r.Clusters() <= 0)
  {
    return;
  }
  Tif(r, image, vtkTerroirKMeans::ClusterIdName(), "clusters.tif");
  Text(r, "clusters.csv", r.ClusterCSV);
  Text(r, "clusters.json", r.ClusterSummary.dump(2) + "\n");
  Png(r,
    image,
    vtkTerroirKMeans::ClusterIdName(),
    0,
    "Clusters",
    "Ecological zones (k-means, K = " + std::to_string(r.Clusters()) + ")",
    "clusters.png");
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

/// Where writing went: each file written since the run began (name, kind, seconds, on
/// whichever thread wrote it), the seconds per kind and in all (`busy_seconds`), and what the
/// run waited for them after its computation (`seconds`).
json WriteBreakdown(double secondsAfterCompute)
{
  json files = json::array();
  json byKind = json::object();
  double busy = 0.0;
  for (const WrittenFile& f : TakeWrittenFiles())
  {
    files.push_back(json{ { "file", fs::path(f.Path).filename().string() },
      { "kind", f.Kind },
      { "seconds", f.Seconds } });
    byKind[f.Kind] = byKind.value(f.Kind, 0.0) + f.Seconds;
    busy += f.Seconds;
  }
  return json{ { "seconds", secondsAfterCompute },
    { "busy_seconds", busy },
    { "files", files },
    { "seconds_by_kind", byKind } };
}

/// The name --outputs knows a stage by ("soil water" is soil-water).
std::string StageOption(const char* name)
{
  std::string option = name;
  std::replace(option.begin(), option.end(), ' ', '-');
  return option;
}

/// Every file of a stage.
std::vector<std::string> AllFiles(const RunFiles& f)
{
  std::vector<std::string> all = f.Rasters;
  all.insert(all.end(), f.Tables.begin(), f.Tables.end());
  all.insert(all.end(), f.Pictures.begin(), f.Pictures.end());
  return all;
}

/// The kinds of file --outputs knows, each with its extensions.
const std::vector<std::pair<std::string, std::vector<const char*>>>& OutputKinds()
{
  static const std::vector<std::pair<std::string, std::vector<const char*>>> kinds = {
    { "vti", { ".vti" } },
    { "tif", { ".tif" } },
    { "png", { ".png" } },
    { "tables", { ".csv", ".json" } },
  };
  return kinds;
}

/// The files an item of --outputs names among `all` (each stage's files, terrain.vti first):
/// a stage's files, a kind's or one file. Throws when it names none of them.
void SelectItem(const std::string& item,
  const std::vector<RunFiles>& stages,
  const std::vector<std::string>& all,
  std::set<std::string>& selected)
{
  bool known = false;
  for (std::size_t s = 0; s < RunSteps().size(); ++s)
  {
    if (item == StageOption(RunSteps()[s].Name))
    {
      known = true;
      const std::vector<std::string> files = AllFiles(stages[s]);
      selected.insert(files.begin(), files.end());
    }
  }
  for (const auto& kind : OutputKinds())
  {
    if (item == kind.first)
    {
      known = true;
      for (const std::string& path : all)
      {
        for (const char* ext : kind.second)
        {
          if (HasExtension(path, ext))
          {
            selected.insert(path);
          }
        }
      }
    }
  }
  for (const std::string& path : all)
  {
    if (fs::path(path).filename() == item)
    {
      known = true;
      selected.insert(path);
    }
  }
  if (!known)
  {
    std::string stageNames;
    for (const RunStep& step : RunSteps())
    {
      stageNames += (stageNames.empty() ? "" : ", ") + StageOption(step.Name);
    }
    throw Failure("--outputs: '" + item + "' is not a file, stage or kind of this run (stages: " +
      stageNames + "; kinds: vti, tif, png, tables; files: as listed in report.json)");
  }
}

/// The files --outputs selects (every file without it), less terrain.vti with --no-vti.
std::set<std::string> SelectOutputs(const RunState& r, const std::vector<RunFiles>& stages)
{
  std::vector<std::string> all = { r.File("terrain.vti") };
  for (const RunFiles& f : stages)
  {
    const std::vector<std::string> files = AllFiles(f);
    all.insert(all.end(), files.begin(), files.end());
  }
  const RunOutputSettings& o = r.Line.RunOutputs;
  std::set<std::string> selected;
  for (const std::string& item : o.Only)
  {
    SelectItem(item, stages, all, selected);
  }
  if (o.Only.empty())
  {
    selected.insert(all.begin(), all.end());
  }
  if (o.NoVti)
  {
    selected.erase(r.File("terrain.vti"));
  }
  return selected;
}

/// The files the run writes, checked before any work, so that a refused run leaves nothing
/// behind: the reports and what --outputs selects.
void ListOutputs(RunState& r)
{
  std::vector<RunFiles> stages;
  for (const RunStep& step : RunSteps())
  {
    stages.emplace_back();
    step.Files(r, stages.back());
    if (!r.Png)
    {
      stages.back().Pictures.clear();
    }
  }
  r.Selected = SelectOutputs(r, stages);
  // In the report's order: terrain.vti, the rasters, the reports, the tables, the pictures.
  r.Outputs.clear();
  auto add = [&r](const std::vector<std::string>& files)
  {
    for (const std::string& f : files)
    {
      if (r.Wants(f))
      {
        r.Outputs.push_back(f);
      }
    }
  };
  add({ r.File("terrain.vti") });
  for (const RunFiles& f : stages)
  {
    add(f.Rasters);
  }
  r.Outputs.insert(r.Outputs.end(), { r.File("report.md"), r.File("report.json") });
  for (const RunFiles& f : stages)
  {
    add(f.Tables);
  }
  bool pictures = false;
  for (const RunFiles& f : stages)
  {
    add(f.Pictures);
    for (const std::string& p : f.Pictures)
    {
      pictures = pictures || r.Wants(p);
    }
  }
  if (pictures && !HaveDisplay())
  {
    throw Failure("PNG overlays need an X display (VTK 9.1 renders through X): run under "
                  "'xvfb-run -a', or pass --no-png");
  }
  CheckWritable(r.Outputs, r.Overwrite());
}

/// True when --outputs selects one of the stage's files (else nothing is copied for it).
bool WritesAnything(const RunState& r, const RunStep& step)
{
  RunFiles f;
  step.Files(r, f);
  const std::vector<std::string> files = AllFiles(f);
  return std::any_of(
    files.begin(), files.end(), [&r](const std::string& file) { return r.Wants(file); });
}

/// Every stage, each one's files written by the writer thread while the next ones compute;
/// then terrain.vti (here, while the writer finishes) and the reports.
void ComputeAndWrite(RunState& r)
{
  const double t0 = Now();
  // Queued copies for the writer: at most 1 GiB (or one stage's arrays when they are more).
  RunWriter writer(std::size_t(1) << 30);
  RunSnapshot snapshots;
  ReadTerrainStage(r);
  for (const RunStep& step : RunSteps())
  {
    step.Compute(r);
    if (!WritesAnything(r, step))
    {
      continue;
    }
    std::size_t bytes = 0;
    vtkSmartPointer<vtkImageData> image = snapshots.Take(r.Result, bytes);
    writer.Post(bytes, [&r, &step, image] { step.Write(r, image); });
  }
  const double tw = Now();
  if (r.Wants(r.File("terrain.vti")))
  {
    WriteVTI(r.Result, r.File("terrain.vti"), r.Overwrite(), r.Line.RunOutputs.VtiCompression);
  }
  json arrays = ArraysReport(r.Result);
  writer.Finish();
  r.Stages["write"] = WriteBreakdown(Now() - tw);
  r.Report["stages"] = r.Stages;
  r.Report["arrays"] = arrays;
  if (r.Clusters() > 0)
  {
    r.Report["clusters"] = json::parse(r.ClusterSummary.dump());
  }
  r.Report["outputs"] = r.Outputs;
  r.Report["wall_seconds"] = Now() - t0;
  WriteReports(r, arrays);
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
  const RunOutputSettings& o = c.RunOutputs;
  r.Tiff.Compression = vtkTerroirGeoTIFFWriter::GetCompressionFromName(o.TiffCompression.c_str());
  r.Tiff.Tiled = o.TiffLayout == "tiles";
  r.Tiff.Threads = o.TiffThreads;
  r.Tiff.Overviews = o.TiffOverviews;
  ListOutputs(r);

  r.Report["input"] = r.Dem;
  TakeWrittenFiles(); // only this run's files in its breakdown
  // Every file goes into place at the end, or none: a failure or an interruption midway leaves
  // the folder as it was (the temporaries are removed).
  HoldCommits();
  try
  {
    ComputeAndWrite(r);
  }
  catch (...)
  {
    DiscardHeldCommits();
    throw;
  }
  std::string error;
  if (!ReleaseHeldCommits(error))
  {
    throw Failure(error);
  }
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

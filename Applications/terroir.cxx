// terroir: the Terroir command-line program.
//
//   terroir run [DEM] [--out DIR]       every filter with defaults; .vti, GeoTIFFs, PNGs, report
//   terroir slope IN OUT                Horn slope (gdaldem style), GeoTIFF or .vti
//   terroir temperature IN OUT          monthly temperature (12 bands)
//   terroir illumination IN OUT         shadows, hours of sun, insolation (instant/daily/monthly)
//   terroir infiltration IN OUT         infiltration rates (fill, slope rule, paint, soil types)
//   terroir humidity IN OUT             monthly soil humidity, weighted, standing water
//   terroir floodfill IN OUT            lakes from seeds, or every closed depression
//   terroir waterflow IN OUT            the hydrostatic water-flow simulation (rivers, lakes)
//   terroir flowacc IN OUT              D8 flow accumulation after priority-flood filling
//   terroir validate [DEM]              simulated rivers scored against mapped ones
//   terroir kmeans IN OUT -k K          ecological zones: k-means of the resources, zone table
//   terroir bench [--size N]            time per stage and backend, per million cells
//   terroir info IN                     grid and georeference of a DEM
//   terroir fractal OUT --size N        a seeded synthetic DEM (GeoTIFF or .vti)
//   terroir view [DEM] [--script F]     the interactive window (Documentation/Viewer.md)
//
// Errors are one line on stderr ("terroir: error: ...") and exit code 1 (2 for a bad command
// line, found before any work: TerroirCommandLine.h); outputs are written
// under a temporary name and renamed, and existing files are kept unless --overwrite.
#include "TerroirApp.h"
#include "TerroirBench.h"
#include "TerroirClusterCommands.h"
#include "TerroirCommandLine.h"
#include "TerroirFlowCommands.h"
#include "TerroirOverlayPlugin.h"
#include "TerroirViewerPlugin.h"
#include "TerroirViewerScript.h"
#include "TerroirWaterCommands.h"

#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationStringKey.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkStringArray.h"
#include "vtkTable.h"

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
#include "vtkUnsignedCharArray.h"

#include "ClimateTable.h"
#include "RiverValidation.h"
#include "SoilWater.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <dlfcn.h>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <vector>

namespace fs = std::filesystem;
using terroir::app::Failure;
using terroir::app::ParseBackend;
using terroir::app::WriteStageResult;
using json = nlohmann::json;

namespace
{
/// Reads the climate table of --climate (before any other work) into the 12 monthly sea-level
/// temperatures.
void LoadClimate(terroir::app::TemperatureSettings& t, terroir::app::SoilWaterSettings* soil)
{
  if (t.ClimateFile.empty())
  {
    return;
  }
  terroir::io::ClimateTable table;
  std::string error;
  if (!terroir::io::ReadClimateTableFile(t.ClimateFile, table, error))
  {
    throw Failure(error);
  }
  if (!table.hasTemperature)
  {
    throw Failure(t.ClimateFile + ": no temperature_c values (needed by the temperature model)");
  }
  t.Monthly.assign(table.temperatureC.begin(), table.temperatureC.end());
  // `run`: the same file's rain, when it has both series, feeds the soil-water model (unless
  // --precip or --intensity say otherwise).
  if (soil && table.hasPrecipitation && table.hasIntensity && soil->Precipitation.empty() &&
    soil->Intensity.empty())
  {
    soil->Precipitation.assign(table.precipitationMm.begin(), table.precipitationMm.end());
    soil->Intensity.assign(table.intensityMmPerHour.begin(), table.intensityMmPerHour.end());
  }
}

/// Sets the temperature filter from the command line's temperature settings.
void ApplyTemperature(const terroir::app::TemperatureSettings& t, vtkTerroirTemperature* filter)
{
  filter->SetSeaLevelTemperatureColdest(t.Coldest);
  filter->SetSeaLevelTemperatureWarmest(t.Warmest);
  if (t.ColdestMonth > 0)
  {
    filter->SetColdestMonth(t.ColdestMonth);
  }
  if (t.WarmestMonth > 0)
  {
    filter->SetWarmestMonth(t.WarmestMonth);
  }
  filter->SetLapseRate(t.LapseRate);
  filter->SetHemisphere(t.Hemisphere == "north" ? vtkTerroirTemperature::North
      : t.Hemisphere == "south"                 ? vtkTerroirTemperature::South
                                                : vtkTerroirTemperature::AutoHemisphere);
  if (!t.Monthly.empty())
  {
    filter->SetMonthlySeaLevelTemperatures(t.Monthly.data());
    filter->SetUseMonthlyTemperatures(true);
  }
}

/// Sets the illumination filter from the command line's illumination settings.
void ApplyIllumination(const terroir::app::IlluminationSettings& s,
  vtkTerroirSolarIllumination* filter)
{
  filter->SetMode(s.Mode == "instant" ? vtkTerroirSolarIllumination::Instant
      : s.Mode == "daily"             ? vtkTerroirSolarIllumination::Daily
                                      : vtkTerroirSolarIllumination::Monthly);
  filter->SetYear(s.Year);
  filter->SetMonth(s.Month);
  filter->SetDay(s.Day);
  filter->SetTime(s.Time);
  filter->SetUTCOffset(s.UTCOffset);
  filter->SetUseSunDirection(s.UseSun);
  filter->SetSunDirection(s.SunAzimuth, s.SunElevation);
  filter->SetMonthlyDay(s.MonthlyDay);
  filter->SetTimeStep(s.TimeStep);
  filter->SetLatitude(s.Latitude);
  filter->SetLongitude(s.Longitude);
  filter->SetOrientation(s.Orientation);
  filter->SetShadowMethod(s.Method == "raymarch" ? vtkTerroirSolarIllumination::RayMarching
                                                 : vtkTerroirSolarIllumination::HorizonMap);
  filter->SetHorizonSectors(s.Sectors);
  filter->SetEarthCurvature(s.Curvature);
  filter->SetTransmittance(s.Transmittance);
}

struct Statistics
{
  double Min = 0, Max = 0, Mean = 0;
  long long Valid = 0;
};

Statistics ArrayStatistics(vtkDataArray* array, int component)
{
  Statistics s;
  double sum = 0;
  s.Min = INFINITY;
  s.Max = -INFINITY;
  for (vtkIdType i = 0; i < array->GetNumberOfTuples(); ++i)
  {
    const double v = array->GetComponent(i, component);
    if (std::isnan(v))
    {
      continue;
    }
    s.Min = std::min(s.Min, v);
    s.Max = std::max(s.Max, v);
    sum += v;
    ++s.Valid;
  }
  s.Mean = s.Valid ? sum / static_cast<double>(s.Valid) : NAN;
  if (!s.Valid)
  {
    s.Min = s.Max = NAN;
  }
  return s;
}

json StatisticsJSON(const Statistics& s)
{
  auto num = [](double v) { return std::isfinite(v) ? json(v) : json(nullptr); };
  return json{ { "min", num(s.Min) },
    { "max", num(s.Max) },
    { "mean", num(s.Mean) },
    { "valid_cells", s.Valid } };
}

/// Runs a filter on `input` with progress and timing; returns the output (shallow copy).
template<typename Filter>
vtkSmartPointer<vtkImageData> RunStage(Filter* filter,
  vtkImageData* input,
  const std::string& label,
  json& stages)
{
  filter->SetInputData(input);
  terroir::app::WatchProgress(filter, label);
  const double t0 = terroir::app::Now();
  terroir::app::UpdateOrThrow(filter, label);
  const double seconds = terroir::app::Now() - t0;
  stages[label] = json{ { "seconds", seconds },
    { "backend", vtkTerroirComputeContext::GetBackendName(filter->GetLastBackend()) },
    { "reason", filter->GetLastBackendReason() ? filter->GetLastBackendReason() : "" } };
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->ShallowCopy(filter->GetOutput());
  return out;
}

bool HaveDisplay()
{
  const char* d = std::getenv("DISPLAY");
  return d && *d;
}

/// Loads `symbol` of the module `name` (beside the program's libraries, or
/// TERROIR_<envName>_PLUGIN); throws naming `what` when it cannot.
void* LoadPluginSymbol(const char* name, const char* symbol, const char* envName, const char* what)
{
  std::vector<std::string> candidates;
  if (const char* env = std::getenv(envName))
  {
    candidates.emplace_back(env);
  }
  std::error_code ec;
  const fs::path exeDir = fs::read_symlink("/proc/self/exe", ec).parent_path();
  if (!ec)
  {
    for (const char* rel : { "../lib", "../" TERROIR_INSTALL_LIBDIR })
    {
      candidates.push_back((exeDir / rel / name).string());
    }
  }
  std::string failures;
  for (const auto& path : candidates)
  {
    if (void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL))
    {
      if (void* found = ::dlsym(handle, symbol))
      {
        return found;
      }
    }
    const char* why = ::dlerror();
    failures += (failures.empty() ? "" : "; ") + (why ? std::string(why) : path);
  }
  throw Failure(std::string(what) + " unavailable: cannot load " + name + " (" + failures + ")");
}

/// Loads the overlay module (see TerroirOverlayPlugin.cxx) once; throws when it is missing.
TerroirWriteOverlayFunction OverlayWriter()
{
  static TerroirWriteOverlayFunction writer = nullptr;
  if (!writer)
  {
    writer =
      reinterpret_cast<TerroirWriteOverlayFunction>(LoadPluginSymbol(TERROIR_OVERLAY_PLUGIN_NAME,
        TERROIR_OVERLAY_PLUGIN_SYMBOL,
        "TERROIR_OVERLAY_PLUGIN",
        "PNG overlays"));
  }
  return writer;
}

void WriteOverlay(vtkImageData* image,
  const std::string& array,
  int component,
  const std::string& preset,
  const std::string& title,
  const std::string& path,
  bool overwrite,
  bool map = false)
{
  terroir::app::CheckWritable({ path }, overwrite);
  if (const char* error = OverlayWriter()(
        image, array.c_str(), component, preset.c_str(), title.c_str(), path.c_str(), map ? 1 : 0))
  {
    throw Failure(path + ": " + error);
  }
}

// ---------------------------------------------------------------------------------------------
int CommandRun(const std::string& demArg,
  const std::string& outDir,
  bool overwrite,
  const std::string& backendName,
  bool png,
  bool allowNetwork,
  const std::string& zUnit,
  const terroir::app::TemperatureSettings& tempOpts,
  const terroir::app::IlluminationSettings& illumOpts,
  const terroir::app::SoilWaterSettings& soilOpts,
  int clusters)
{
  const std::string dem = demArg.empty() ? terroir::app::DefaultDEM() : demArg;
  const int backend = ParseBackend(backendName);
  std::error_code ec;
  fs::create_directories(outDir, ec);
  if (ec || !fs::is_directory(outDir))
  {
    throw Failure(outDir + ": cannot create the output folder" + (ec ? ": " + ec.message() : ""));
  }
  const fs::path out(outDir);
  const std::string vti = (out / "terrain.vti").string();
  const std::string slopeTif = (out / "slope.tif").string();
  const std::string aspectTif = (out / "aspect.tif").string();
  const std::string temperatureTif = (out / "temperature.tif").string();
  const std::string illuminationTif = (out / "illumination.tif").string();
  const std::string insolationTif = (out / "insolation.tif").string();
  const std::string slopePng = (out / "slope.png").string();
  const std::string temperatureJanPng = (out / "temperature_jan.png").string();
  const std::string temperatureJulPng = (out / "temperature_jul.png").string();
  // Illumination at the solstices: December (longest shadows) and June.
  const std::string illuminationDecPng = (out / "illumination_dec.png").string();
  const std::string illuminationJunPng = (out / "illumination_jun.png").string();
  const std::string insolationDecPng = (out / "insolation_dec.png").string();
  const std::string insolationJunPng = (out / "insolation_jun.png").string();
  const std::string infiltrationTif = (out / "infiltration.tif").string();
  const std::string humidityTif = (out / "humidity.tif").string();
  const std::string weightedTif = (out / "weighted_humidity.tif").string();
  const std::string standingTif = (out / "standing_water.tif").string();
  const std::string lakesTif = (out / "lakes.tif").string();
  const std::string humidityJanPng = (out / "humidity_jan.png").string();
  const std::string humidityJulPng = (out / "humidity_jul.png").string();
  const std::string lakesPng = (out / "lakes.png").string();
  const std::string riversTif = (out / "rivers.tif").string();
  const std::string dischargeTif = (out / "discharge.tif").string();
  const std::string riversPng = (out / "rivers.png").string();
  const std::string riversReliefPng = (out / "rivers_relief.png").string();
  const std::string validationPng = (out / "validation.png").string();
  // The bundled DEM's mapped rivers and watershed: its rivers are scored against them.
  const bool bundled = demArg.empty();
  const std::string dataDir = dem.substr(0, dem.find_last_of('/') + 1);
  const std::string referenceLines = dataDir + "sagehen_nhd_flowlines_utm11n.geojson";
  const std::string referenceArea = dataDir + "sagehen_watershed_utm11n.geojson";
  const std::string clustersTif = (out / "clusters.tif").string();
  const std::string clustersCsv = (out / "clusters.csv").string();
  const std::string clustersJson = (out / "clusters.json").string();
  const std::string clustersPng = (out / "clusters.png").string();
  const std::string reportMd = (out / "report.md").string();
  const std::string reportJson = (out / "report.json").string();
  std::vector<std::string> outputs = { vti,
    slopeTif,
    aspectTif,
    temperatureTif,
    illuminationTif,
    insolationTif,
    infiltrationTif,
    humidityTif,
    weightedTif,
    standingTif,
    lakesTif,
    riversTif,
    dischargeTif,
    reportMd,
    reportJson };
  if (clusters > 0)
  {
    outputs.insert(outputs.end(), { clustersTif, clustersCsv, clustersJson });
  }
  if (png)
  {
    if (!HaveDisplay())
    {
      throw Failure("PNG overlays need an X display (VTK 9.1 renders through X): run under "
                    "'xvfb-run -a', or pass --no-png");
    }
    outputs.insert(outputs.end(),
      { slopePng,
        temperatureJanPng,
        temperatureJulPng,
        illuminationDecPng,
        illuminationJunPng,
        insolationDecPng,
        insolationJunPng,
        humidityJanPng,
        humidityJulPng,
        lakesPng,
        riversPng,
        riversReliefPng });
    if (bundled)
    {
      outputs.push_back(validationPng);
    }
    if (clusters > 0)
    {
      outputs.push_back(clustersPng);
    }
  }
  // Refuse before any work, so a refused run leaves nothing behind.
  terroir::app::CheckWritable(outputs, overwrite);

  json report;
  report["input"] = dem;
  json stages;
  const double t0 = terroir::app::Now();
  vtkSmartPointer<vtkImageData> terrain = terroir::app::ReadTerrain(dem, allowNetwork, zUnit);
  stages["read"] = json{ { "seconds", terroir::app::Now() - t0 } };

  int dims[3];
  double spacing[3];
  terrain->GetDimensions(dims);
  terrain->GetSpacing(spacing);
  double latLon[2] = { NAN, NAN };
  const bool located = vtkTerroirGeoreference::GetCenterLatLon(terrain, latLon);
  report["grid"] = json{ { "nx", dims[0] },
    { "ny", dims[1] },
    { "dx_m", spacing[0] },
    { "dy_m", spacing[1] },
    { "geographic", vtkTerroirGeoreference::GetRowSpacing(terrain) != nullptr } };
  report["georeference"] = json{ { "has_crs", !vtkTerroirGeoreference::GetCRS(terrain).empty() },
    { "center_lat", located ? json(latLon[0]) : json(nullptr) },
    { "center_lon", located ? json(latLon[1]) : json(nullptr) },
    { "meridian_convergence_deg", vtkTerroirGeoreference::GetMeridianConvergence(terrain) } };

  vtkNew<vtkTerroirSlope> slope;
  slope->SetBackend(backend);
  vtkSmartPointer<vtkImageData> withSlope = RunStage(slope.Get(), terrain, "slope", stages);

  vtkNew<vtkTerroirTemperature> temperature;
  temperature->SetBackend(backend);
  ApplyTemperature(tempOpts, temperature);
  vtkSmartPointer<vtkImageData> result =
    RunStage(temperature.Get(), withSlope, "temperature", stages);

  // Monthly illumination with the filter's defaults (the 15th of each month of 2025, 10-minute
  // steps, horizon map of 64 sectors). Without a georeference there is no sun to place unless
  // --lat and --lon say where: the stage is then skipped, with a warning, and its outputs with it.
  const bool illuminate =
    located || (std::isfinite(illumOpts.Latitude) && std::isfinite(illumOpts.Longitude));
  double horizonMapSeconds = 0.0;
  if (illuminate)
  {
    vtkNew<vtkTerroirSolarIllumination> illumination;
    illumination->SetBackend(backend);
    illumination->SetLatitude(illumOpts.Latitude);
    illumination->SetLongitude(illumOpts.Longitude);
    result = RunStage(illumination.Get(), result, "illumination", stages);
    horizonMapSeconds = illumination->GetLastHorizonMapSeconds();
    stages["illumination"]["horizon_map_seconds"] = horizonMapSeconds;
    stages["illumination"]["horizon_sectors"] = illumination->GetHorizonSectors();
    stages["illumination"]["year"] = illumination->GetYear();
    stages["illumination"]["monthly_day"] = illumination->GetMonthlyDay();
    stages["illumination"]["time_step_min"] = illumination->GetTimeStep();
  }
  else
  {
    const std::string why = "the DEM has no georeference; pass --lat and --lon";
    std::cerr << "terroir: warning: " << dem << ": illumination skipped (" << why << ")\n";
    stages["illumination"] = json{ { "skipped", why } };
    for (const std::string& skipped : { illuminationTif,
           insolationTif,
           illuminationDecPng,
           illuminationJunPng,
           insolationDecPng,
           insolationJunPng })
    {
      outputs.erase(std::remove(outputs.begin(), outputs.end(), skipped), outputs.end());
    }
  }

  // Soil water with the default infiltration recipe (fill 15 mm/h, no infiltration on slopes
  // over 30 degrees) and the climate of --precip/--intensity, --climate or the defaults; then
  // the lakes: every closed depression and hydro-flattened water surface of at least 1 ha.
  vtkNew<vtkTerroirInfiltration> infiltration;
  result = RunStage(infiltration.Get(), result, "infiltration", stages);
  vtkNew<vtkTerroirSoilHumidity> humidity;
  humidity->SetBackend(backend);
  terroir::app::ApplyClimate(soilOpts, humidity);
  result = RunStage(humidity.Get(), result, "humidity", stages);
  vtkNew<vtkTerroirFloodFill> lakes;
  lakes->SetModeToFillDepressions();
  result = RunStage(lakes.Get(), result, "lakes", stages);
  vtkDataArray* lakeLevels =
    result->GetFieldData()->GetArray(vtkTerroirFloodFill::WaterBodyLevelName());
  stages["lakes"]["water_bodies"] = lakeLevels ? lakeLevels->GetNumberOfTuples() : 0;

  // Rivers: the water flow's river-forming mode (steady rain until the outflow balances it),
  // then the river network (rivers, and the lakes above) and, on the bundled DEM, its scores
  // against the mapped rivers.
  vtkNew<vtkTerroirWaterFlow> flow;
  flow->SetBackend(backend);
  flow->SetModeToRivers();
  result = RunStage(flow.Get(), result, "rivers", stages);
  {
    vtkPointData* rpd = result->GetPointData();
    vtkDataArray* river = rpd->GetArray(vtkTerroirWaterFlow::RiverName());
    vtkDataArray* lake = rpd->GetArray(vtkTerroirFloodFill::WaterBodyName());
    vtkNew<vtkUnsignedCharArray> network;
    network->SetName("RiverNetwork");
    network->SetNumberOfTuples(river->GetNumberOfTuples());
    long long riverCells = 0;
    for (vtkIdType k = 0; k < river->GetNumberOfTuples(); ++k)
    {
      const bool r = river->GetComponent(k, 0) != 0.0;
      const bool l = lake && lake->GetComponent(k, 0) != 0.0;
      network->SetValue(k, r ? 1 : (l ? 2 : 0));
      riverCells += r ? 1 : 0;
    }
    rpd->AddArray(network);
    const double cell = std::sqrt(std::fabs(spacing[0] * spacing[1]));
    json& rs = stages["rivers"];
    rs["iterations"] =
      result->GetFieldData()->GetArray(vtkTerroirWaterFlow::IterationsName())->GetComponent(0, 0);
    rs["stop_reason"] = vtkStringArray::SafeDownCast(
      result->GetFieldData()->GetAbstractArray(vtkTerroirWaterFlow::StopReasonName()))
                          ->GetValue(0);
    rs["rain_mm_per_h"] = flow->GetRainRate();
    if (vtkDataArray* levels = vtkDataArray::SafeDownCast(
          result->GetFieldData()->GetAbstractArray("WaterFlowWarmStartIterations")))
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
    vtkDataArray* areas =
      result->GetFieldData()->GetArray(vtkTerroirFloodFill::WaterBodyAreaName());
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
  vtkSmartPointer<vtkImageData> validationPicture;
  if (bundled)
  {
    const double tv = terroir::app::Now();
    terroir::app::RiverReference reference(
      result, dem, referenceLines, referenceArea, allowNetwork);
    std::vector<std::uint8_t> simulated;
    const terroir::app::MethodScores scores = terroir::app::ScoreRiverMeasure("rivers",
      "RiverStrength (m3/s)",
      terroir::app::PointArrayValues(result, vtkTerroirWaterFlow::RiverStrengthName()),
      std::nan(""),
      reference,
      simulated);
    json v = terroir::app::MethodScoresJson(scores);
    v["reference"] = referenceLines;
    v["area"] = referenceArea;
    v["reference_cells"] = reference.Cells;
    v["seconds"] = terroir::app::Now() - tv;
    stages["rivers"]["validation"] = v;
    if (png)
    {
      const std::size_t n = simulated.size();
      std::vector<std::uint8_t> category(n, 0);
      terroir::hydrology::RiverComparisonCategories(
        reference.View, simulated.data(), reference.Area.data(), 60.0, category.data());
      validationPicture = vtkSmartPointer<vtkImageData>::New();
      validationPicture->ShallowCopy(result);
      vtkNew<vtkUnsignedCharArray> cat;
      cat->SetName("RiverComparison");
      cat->SetNumberOfTuples(static_cast<vtkIdType>(n));
      std::copy(category.begin(), category.end(), cat->GetPointer(0));
      validationPicture->GetPointData()->AddArray(cat);
    }
  }

  // Ecological zones: k-means of the resources with Long (2016)'s features and weights.
  vtkNew<vtkTable> clusterTable;
  nlohmann::ordered_json clusterSummary;
  if (clusters > 0)
  {
    vtkNew<vtkTerroirKMeans> kmeans;
    terroir::app::KMeansSettings kmeansOpts;
    kmeansOpts.Clusters = clusters;
    terroir::app::ApplyKMeans(kmeansOpts, backendName, kmeans);
    result = RunStage(kmeans.Get(), result, "clusters", stages);
    clusterTable->DeepCopy(kmeans->GetClusterTable());
    clusterSummary = terroir::app::ClusterTableJSON(clusterTable, result);
    stages["clusters"]["k"] = clusters;
    stages["clusters"]["iterations"] = clusterSummary["iterations"];
    stages["clusters"]["stop_reason"] = clusterSummary["stop_reason"];
  }
  else
  {
    stages["clusters"] = json{ { "skipped", "--clusters 0" } };
  }

  const double tw = terroir::app::Now();
  terroir::app::WriteVTI(result, vti, overwrite);
  terroir::app::WriteGeoTIFF(result, "Slope", slopeTif, overwrite);
  terroir::app::WriteGeoTIFF(result, "Aspect", aspectTif, overwrite);
  terroir::app::WriteGeoTIFF(result, "Temperature", temperatureTif, overwrite);
  if (illuminate)
  {
    terroir::app::WriteGeoTIFF(result, "IlluminationHours", illuminationTif, overwrite);
    terroir::app::WriteGeoTIFF(result, "Insolation", insolationTif, overwrite);
  }
  terroir::app::WriteGeoTIFF(
    result, vtkTerroirInfiltration::InfiltrationRateName(), infiltrationTif, overwrite);
  terroir::app::WriteGeoTIFF(
    result, vtkTerroirSoilHumidity::SoilHumidityName(), humidityTif, overwrite);
  terroir::app::WriteGeoTIFF(
    result, vtkTerroirSoilHumidity::WeightedSoilHumidityName(), weightedTif, overwrite);
  terroir::app::WriteGeoTIFF(
    result, vtkTerroirSoilHumidity::StandingWaterName(), standingTif, overwrite);
  terroir::app::WriteGeoTIFF(result, vtkTerroirFloodFill::WaterDepthName(), lakesTif, overwrite);
  terroir::app::WriteGeoTIFF(result, vtkTerroirWaterFlow::RiverName(), riversTif, overwrite);
  terroir::app::WriteGeoTIFF(
    result, vtkTerroirWaterFlow::DischargeRateName(), dischargeTif, overwrite);
  if (clusters > 0)
  {
    terroir::app::WriteGeoTIFF(result, vtkTerroirKMeans::ClusterIdName(), clustersTif, overwrite);
    terroir::app::WriteTextFile(
      clustersCsv, terroir::app::ClusterTableCSV(clusterTable), overwrite);
    terroir::app::WriteTextFile(clustersJson, clusterSummary.dump(2) + "\n", overwrite);
  }
  if (png)
  {
    WriteOverlay(result,
      vtkTerroirSoilHumidity::WeightedSoilHumidityName(),
      0,
      "Humidity",
      "Weighted soil humidity, January (mm)",
      humidityJanPng,
      overwrite);
    WriteOverlay(result,
      vtkTerroirSoilHumidity::WeightedSoilHumidityName(),
      6,
      "Humidity",
      "Weighted soil humidity, July (mm)",
      humidityJulPng,
      overwrite);
    WriteOverlay(result,
      vtkTerroirFloodFill::WaterDepthName(),
      0,
      "WaterBodies",
      "Lakes and closed depressions (depth, m)",
      lakesPng,
      overwrite);
    WriteOverlay(
      result, "RiverNetwork", 0, "Rivers", "Rivers and lakes (map)", riversPng, overwrite, true);
    WriteOverlay(
      result, "RiverNetwork", 0, "Rivers", "Rivers and lakes", riversReliefPng, overwrite);
    if (validationPicture)
    {
      WriteOverlay(validationPicture,
        "RiverComparison",
        0,
        "RiverComparison",
        "Rivers against NHD within 60 m (map)",
        validationPng,
        overwrite,
        true);
    }
    if (clusters > 0)
    {
      WriteOverlay(result,
        vtkTerroirKMeans::ClusterIdName(),
        0,
        "Clusters",
        "Ecological zones (k-means, K = " + std::to_string(clusters) + ")",
        clustersPng,
        overwrite);
    }
    WriteOverlay(result, "Slope", 0, "Slope", "Slope (°)", slopePng, overwrite);
    WriteOverlay(result,
      "Temperature",
      0,
      "Temperature",
      "Temperature, January (°C)",
      temperatureJanPng,
      overwrite);
    WriteOverlay(result,
      "Temperature",
      6,
      "Temperature",
      "Temperature, July (°C)",
      temperatureJulPng,
      overwrite);
    if (illuminate)
    {
      WriteOverlay(result,
        "IlluminationHours",
        11,
        "Illumination",
        "Direct sun, December 15 (h/day)",
        illuminationDecPng,
        overwrite);
      WriteOverlay(result,
        "IlluminationHours",
        5,
        "Illumination",
        "Direct sun, June 15 (h/day)",
        illuminationJunPng,
        overwrite);
      WriteOverlay(result,
        "Insolation",
        11,
        "Insolation",
        "Insolation, December 15 (Wh/m²/day)",
        insolationDecPng,
        overwrite);
      WriteOverlay(result,
        "Insolation",
        5,
        "Insolation",
        "Insolation, June 15 (Wh/m²/day)",
        insolationJunPng,
        overwrite);
    }
  }
  stages["write"] = json{ { "seconds", terroir::app::Now() - tw } };
  report["stages"] = stages;

  json arrays;
  vtkPointData* pd = result->GetPointData();
  for (int a = 0; a < pd->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* arr = pd->GetArray(a);
    if (!arr || !arr->GetName() || std::string(arr->GetName()) == "vtkValidPointMask")
    {
      continue;
    }
    json entry;
    const char* units = arr->GetInformation()->Has(vtkDataArray::UNITS_LABEL())
      ? arr->GetInformation()->Get(vtkDataArray::UNITS_LABEL())
      : "";
    entry["units"] = units;
    if (arr->GetNumberOfComponents() == 12)
    {
      for (int c = 0; c < 12; ++c)
      {
        entry[vtkTerroirTemperature::GetMonthName(c)] = StatisticsJSON(ArrayStatistics(arr, c));
      }
    }
    else if (arr->GetNumberOfComponents() == 1)
    {
      entry["all"] = StatisticsJSON(ArrayStatistics(arr, 0));
    }
    arrays[arr->GetName()] = entry;
  }
  report["arrays"] = arrays;
  if (clusters > 0)
  {
    report["clusters"] = json::parse(clusterSummary.dump());
  }
  report["outputs"] = outputs;

  // Report: JSON for scripts, Markdown for people; both temp + rename.
  terroir::app::WriteTextFile(reportJson, report.dump(2) + "\n", overwrite);
  std::ostringstream md;
  md << std::fixed << std::setprecision(2);
  md << "# Terroir run\n\n";
  md << "- input: `" << dem << "`\n";
  md << "- grid: " << dims[0] << " x " << dims[1] << " cells, " << spacing[0] << " x " << spacing[1]
     << " m\n";
  if (located)
  {
    md << std::setprecision(5) << "- centre: " << latLon[0] << ", " << latLon[1] << " (lat, lon)\n"
       << std::setprecision(2);
  }
  md << "\n| stage | seconds | backend |\n|---|---|---|\n";
  for (const char* s : { "read",
         "slope",
         "temperature",
         "illumination",
         "infiltration",
         "humidity",
         "lakes",
         "rivers",
         "clusters",
         "write" })
  {
    if (!stages[s].contains("seconds"))
    {
      md << "| " << s << " | skipped: " << stages[s]["skipped"].get<std::string>() << " | |\n";
      continue;
    }
    md << "| " << s << " | " << std::setprecision(3) << stages[s]["seconds"].get<double>() << " | "
       << (stages[s].contains("backend") ? stages[s]["backend"].get<std::string>() : "") << " |\n";
  }
  // Why each stage ran where it did: under Auto the GPU only where its path is verified correct
  // and faster on this hardware (Documentation/Compute.md, "Verified GPU paths").
  md << "\nBackends (`--backend auto` runs a stage on the GPU only where its GPU path is verified "
        "correct and faster on this hardware; Documentation/Compute.md):\n\n";
  for (const auto& item : stages.items())
  {
    if (item.value().is_object() && item.value().contains("reason") &&
      !item.value()["reason"].get<std::string>().empty())
    {
      md << "- " << item.key() << ": " << item.value()["reason"].get<std::string>() << "\n";
    }
  }
  if (illuminate)
  {
    md << "\nIllumination: monthly, the 15th of each month of "
       << stages["illumination"]["year"].get<int>() << ", " << std::defaultfloat
       << stages["illumination"]["time_step_min"].get<double>() << std::fixed
       << "-minute steps; horizon map of " << stages["illumination"]["horizon_sectors"].get<int>()
       << " sectors built in " << std::setprecision(3) << horizonMapSeconds << " s of the stage's "
       << stages["illumination"]["seconds"].get<double>() << " s.\n";
  }
  md << std::setprecision(2) << "\n| array | units | min | mean | max |\n|---|---|---|---|---|\n";
  for (auto& [name, entry] : arrays.items())
  {
    const json& st = entry.contains("all") ? entry["all"]
      : entry.contains("Jul")              ? entry["Jul"]
                                           : json();
    if (st.is_null() || st["min"].is_null())
    {
      continue;
    }
    md << "| " << name << (entry.contains("Jul") ? " (Jul)" : "") << " | "
       << entry["units"].get<std::string>() << " | " << st["min"].get<double>() << " | "
       << st["mean"].get<double>() << " | " << st["max"].get<double>() << " |\n";
  }
  {
    const json& rs = stages["rivers"];
    md << "\nRivers (water flow, river-forming mode: " << std::defaultfloat
       << rs["rain_mm_per_h"].get<double>() << " mm/h until the outflow balances the rain; "
       << rs["iterations"].get<double>() << " iterations, " << rs["stop_reason"].get<std::string>()
       << "): " << rs["river_cells"].get<long long>()
       << " river cells (upstream area >= " << rs["river_area_m2"].get<double>() << " m2), about "
       << std::fixed << std::setprecision(1) << rs["river_length_km"].get<double>() << " km; "
       << rs["lakes"].get<std::size_t>() << " lakes, " << std::setprecision(3)
       << rs["lake_area_m2"].get<double>() / 1e6 << " km2.\n";
    if (rs.contains("validation"))
    {
      const json& v = rs["validation"];
      md << "\nAgainst the bundled NHD flowlines (" << v["reference_cells"].get<std::size_t>()
         << " cells in the watershed, length-matched, channel cells): precision "
         << v["scores"][1]["precision"].get<double>() << ", recall "
         << v["scores"][1]["recall"].get<double>() << ", F1 " << v["scores"][1]["f1"].get<double>()
         << " within 60 m (F1 " << v["scores"][0]["f1"].get<double>()
         << " within 30 m); `terroir validate` compares the classic methods.\n";
    }
    md << std::setprecision(2);
  }
  if (clusters > 0)
  {
    // The zones at a glance; clusters.csv has the mean of every feature and month.
    md << "\nEcological zones (k-means, K = " << clusters << ", "
       << clusterSummary["iterations"].get<int>() << " iterations, "
       << clusterSummary["stop_reason"].get<std::string>()
       << "):\n\n| zone | colour | cells | share | slope (°) | temperature Jul (°C) |\n"
       << "|---|---|---|---|---|---|\n";
    for (const auto& row : clusterSummary["clusters"])
    {
      auto mean = [&row](const char* column)
      {
        std::ostringstream os;
        os << std::fixed << std::setprecision(1);
        if (row.contains(column) && row[column].is_number())
        {
          os << row[column].get<double>();
        }
        else
        {
          os << "-";
        }
        return os.str();
      };
      md << "| " << row["ClusterId"].get<long long>() << " | " << row["Color"].get<std::string>()
         << " | " << row["Cells"].get<long long>() << " | " << std::setprecision(1)
         << 100.0 * row["Share"].get<double>() << " % | " << mean("Slope") << " | "
         << mean("Temperature_Jul") << " |\n";
    }
  }
  md << "\nOutputs:\n\n";
  for (const auto& o : outputs)
  {
    md << "- `" << fs::path(o).filename().string() << "`\n";
  }
  terroir::app::WriteTextFile(reportMd, md.str(), overwrite);

  std::cout << "terroir run: " << dims[0] << "x" << dims[1] << " cells from " << dem << "\n";
  for (const char* s : { "slope",
         "temperature",
         "illumination",
         "infiltration",
         "humidity",
         "lakes",
         "rivers",
         "clusters" })
  {
    if (!stages[s].contains("seconds"))
    {
      std::cout << "  " << std::left << std::setw(14) << s << std::right << "skipped\n";
      continue;
    }
    std::cout << "  " << std::left << std::setw(14) << s << std::right << std::fixed
              << std::setprecision(3) << stages[s]["seconds"].get<double>() << " s  "
              << stages[s]["backend"].get<std::string>();
    if (std::string(s) == "illumination")
    {
      std::cout << " (horizon map " << horizonMapSeconds << " s)";
    }
    std::cout << "\n";
  }
  std::cout << "  outputs in " << outDir << " (report.md)\n";
  return 0;
}

// ---------------------------------------------------------------------------------------------
/// Writes a single-stage result: GeoTIFF of `array` for .tif/.tiff, every array for .vti.
int CommandSlope(const std::string& in,
  const std::string& outPath,
  bool overwrite,
  const std::string& backendName,
  double zFactor,
  bool percent,
  const std::string& aspectPath,
  bool allowNetwork,
  const std::string& zUnit)
{
  const int backend = ParseBackend(backendName);
  std::vector<std::string> outs = { outPath };
  if (!aspectPath.empty())
  {
    outs.push_back(aspectPath);
  }
  terroir::app::CheckWritable(outs, overwrite);
  vtkSmartPointer<vtkImageData> terrain = terroir::app::ReadTerrain(in, allowNetwork, zUnit);
  vtkNew<vtkTerroirSlope> slope;
  slope->SetBackend(backend);
  slope->SetZFactor(zFactor);
  // Only what is written: a .tif gets Slope (and Aspect when asked); a .vti gets everything.
  const bool everything = terroir::app::HasExtension(outPath, ".vti");
  slope->SetComputeAspect(everything || !aspectPath.empty());
  slope->SetComputeNormals(everything);
  if (percent)
  {
    slope->SetSlopeUnitsToPercent();
  }
  json stages;
  vtkSmartPointer<vtkImageData> result = RunStage(slope.Get(), terrain, "slope", stages);
  WriteStageResult(result, "Slope", outPath, overwrite);
  if (!aspectPath.empty())
  {
    WriteStageResult(result, "Aspect", aspectPath, overwrite);
  }
  return 0;
}

int CommandTemperature(const std::string& in,
  const std::string& outPath,
  bool overwrite,
  const std::string& backendName,
  bool allowNetwork,
  const std::string& zUnit,
  const terroir::app::TemperatureSettings& opts)
{
  const int backend = ParseBackend(backendName);
  terroir::app::CheckWritable({ outPath }, overwrite);
  vtkSmartPointer<vtkImageData> terrain = terroir::app::ReadTerrain(in, allowNetwork, zUnit);
  vtkNew<vtkTerroirTemperature> temperature;
  temperature->SetBackend(backend);
  ApplyTemperature(opts, temperature);
  json stages;
  vtkSmartPointer<vtkImageData> result =
    RunStage(temperature.Get(), terrain, "temperature", stages);
  WriteStageResult(result, "Temperature", outPath, overwrite);
  return 0;
}

int CommandIllumination(const std::string& in,
  const std::string& outPath,
  bool overwrite,
  const std::string& backendName,
  bool allowNetwork,
  const std::string& zUnit,
  const terroir::app::IlluminationSettings& opts)
{
  const int backend = ParseBackend(backendName);
  std::vector<std::string> outs = { outPath };
  for (const std::string* extra : { &opts.InsolationOutput, &opts.IncidenceOutput })
  {
    if (!extra->empty())
    {
      outs.push_back(*extra);
    }
  }
  terroir::app::CheckWritable(outs, overwrite);
  vtkSmartPointer<vtkImageData> terrain = terroir::app::ReadTerrain(in, allowNetwork, zUnit);
  vtkNew<vtkTerroirSolarIllumination> illumination;
  illumination->SetBackend(backend);
  ApplyIllumination(opts, illumination);
  json stages;
  vtkSmartPointer<vtkImageData> result =
    RunStage(illumination.Get(), terrain, "illumination", stages);
  // A .tif gets the lit/shadow mask (instant) or the hours of sun (1 or 12 bands); .vti all.
  const bool instant = opts.Mode == "instant";
  WriteStageResult(result,
    instant ? vtkTerroirSolarIllumination::IlluminatedName()
            : vtkTerroirSolarIllumination::IlluminationHoursName(),
    outPath,
    overwrite);
  if (!opts.InsolationOutput.empty())
  {
    WriteStageResult(
      result, vtkTerroirSolarIllumination::InsolationName(), opts.InsolationOutput, overwrite);
  }
  if (!opts.IncidenceOutput.empty())
  {
    WriteStageResult(
      result, vtkTerroirSolarIllumination::SunIncidenceName(), opts.IncidenceOutput, overwrite);
  }
  return 0;
}

int CommandInfo(const std::string& in, bool allowNetwork, const std::string& zUnit)
{
  vtkSmartPointer<vtkImageData> terrain = terroir::app::ReadTerrain(in, allowNetwork, zUnit);
  int dims[3];
  double spacing[3], origin[3];
  terrain->GetDimensions(dims);
  terrain->GetSpacing(spacing);
  terrain->GetOrigin(origin);
  std::cout << std::setprecision(10) << "file: " << in << "\n"
            << "cells: " << dims[0] << " x " << dims[1] << "\n"
            << "spacing (m): " << spacing[0] << " x " << spacing[1] << "\n"
            << "origin: " << origin[0] << ", " << origin[1] << "\n";
  double ll[2];
  if (vtkTerroirGeoreference::GetCenterLatLon(terrain, ll))
  {
    std::cout << "centre (lat, lon): " << ll[0] << ", " << ll[1] << "\n";
  }
  std::cout << "meridian convergence (deg): "
            << vtkTerroirGeoreference::GetMeridianConvergence(terrain) << "\n";
  std::cout << "geographic grid: "
            << (vtkTerroirGeoreference::GetRowSpacing(terrain) ? "yes" : "no") << "\n";
  if (vtkDataArray* z = terrain->GetPointData()->GetArray("Elevation"))
  {
    const Statistics s = ArrayStatistics(z, 0);
    std::cout << "elevation (m): min " << s.Min << ", mean " << s.Mean << ", max " << s.Max
              << ", valid cells " << s.Valid << "\n";
  }
  return 0;
}

int CommandFractal(const std::string& outPath, int size, int seed, double spacing, bool overwrite)
{
  terroir::app::CheckWritable({ outPath }, overwrite);
  vtkNew<vtkTerroirFractalTerrainSource> source;
  source->SetDimensions(size, size);
  source->SetSeed(seed);
  source->SetSpacing(spacing);
  terroir::app::WatchProgress(source, "fractal");
  terroir::app::UpdateOrThrow(source, "fractal terrain");
  WriteStageResult(source->GetOutput(), "Elevation", outPath, overwrite);
  return 0;
}
/// `terroir view`: checks the script (one line naming FILE:LINE and the problem) before any
/// other work, reads the DEM, and hands both to the window module (TerroirViewerWindow.cxx).
int CommandView(const terroir::app::CommandLine& c)
{
  std::vector<terroir::viewer::ViewerAction> actions;
  if (!c.View.Script.empty())
  {
    std::string error;
    if (!terroir::viewer::ReadViewerScript(
          c.View.Script, c.View.Width, c.View.Height, actions, error))
    {
      throw Failure(error);
    }
  }
  std::error_code ec;
  if (!c.View.ScreenshotDir.empty() && !fs::is_directory(c.View.ScreenshotDir, ec))
  {
    throw Failure(c.View.ScreenshotDir + ": screenshot folder does not exist");
  }
  if (!HaveDisplay())
  {
    throw Failure("terroir view needs an X display (DISPLAY unset); run under 'xvfb-run -a'");
  }
  const std::string dem = c.Input.empty() ? terroir::app::DefaultDEM() : c.Input;
  if (c.Input.empty())
  {
    std::cerr << "terroir view: no DEM given; opening the bundled Sagehen Creek DEM (" << dem
              << ")\n";
  }
  vtkSmartPointer<vtkImageData> terrain = terroir::app::ReadTerrain(dem, c.AllowNetwork, c.ZUnit);
  auto run = reinterpret_cast<TerroirRunViewerFunction>(LoadPluginSymbol(TERROIR_VIEWER_PLUGIN_NAME,
    TERROIR_VIEWER_PLUGIN_SYMBOL,
    "TERROIR_VIEWER_PLUGIN",
    "terroir view"));
  TerroirViewerRequest request;
  request.Terrain = terrain;
  request.TerrainName = dem;
  request.Line = &c;
  request.Actions = c.View.Script.empty() ? nullptr : &actions;
  if (run(&request) != 0)
  {
    throw Failure(request.Error.empty() ? "terroir view failed" : request.Error);
  }
  return 0;
}
} // namespace

int main(int argc, char** argv)
{
  terroir::app::CommandLine c;
  const int exitCode = terroir::app::StartCommandLine(argc, argv, c, "terroir");
  if (exitCode >= 0)
  {
    return exitCode;
  }
  try
  {
    LoadClimate(c.Temperature, c.Command == "run" ? &c.SoilWater : nullptr);
    if (c.Command == "run")
    {
      return CommandRun(c.Input,
        c.Output,
        c.Overwrite,
        c.Backend,
        !c.NoPng,
        c.AllowNetwork,
        c.ZUnit,
        c.Temperature,
        c.Illumination,
        c.SoilWater,
        c.KMeans.Clusters);
    }
    if (c.Command == "slope")
    {
      return CommandSlope(c.Input,
        c.Output,
        c.Overwrite,
        c.Backend,
        c.ZFactor,
        c.Percent,
        c.AspectOutput,
        c.AllowNetwork,
        c.ZUnit);
    }
    if (c.Command == "temperature")
    {
      return CommandTemperature(
        c.Input, c.Output, c.Overwrite, c.Backend, c.AllowNetwork, c.ZUnit, c.Temperature);
    }
    if (c.Command == "illumination")
    {
      return CommandIllumination(
        c.Input, c.Output, c.Overwrite, c.Backend, c.AllowNetwork, c.ZUnit, c.Illumination);
    }
    if (c.Command == "infiltration")
    {
      return terroir::app::CommandInfiltration(c);
    }
    if (c.Command == "humidity")
    {
      return terroir::app::CommandHumidity(c);
    }
    if (c.Command == "floodfill")
    {
      return terroir::app::CommandFloodFill(c);
    }
    if (c.Command == "waterflow")
    {
      return terroir::app::CommandWaterFlow(c);
    }
    if (c.Command == "flowacc")
    {
      return terroir::app::CommandFlowAccumulation(c);
    }
    const auto overlayWriter = [&c](vtkImageData* image,
                                 const std::string& array,
                                 const std::string& preset,
                                 const std::string& title,
                                 const std::string& path,
                                 bool map)
    {
      if (!HaveDisplay())
      {
        throw Failure(path + ": PNG overlays need an X display: run under 'xvfb-run -a'");
      }
      WriteOverlay(image, array, 0, preset, title, path, c.Overwrite, map);
    };
    if (c.Command == "validate")
    {
      return terroir::app::CommandValidate(c, overlayWriter);
    }
    if (c.Command == "kmeans")
    {
      return terroir::app::CommandKMeans(c, overlayWriter);
    }
    if (c.Command == "bench")
    {
      return terroir::app::CommandBench(c);
    }
    if (c.Command == "info")
    {
      return CommandInfo(c.Input, c.AllowNetwork, c.ZUnit);
    }
    if (c.Command == "view")
    {
      return CommandView(c);
    }
    if (c.Command == "fractal")
    {
      return CommandFractal(c.Output, c.FractalSize, c.FractalSeed, c.FractalSpacing, c.Overwrite);
    }
  }
  catch (const std::exception& e)
  {
    std::cerr << "terroir: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

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
#include "TerroirClusterCommands.h"
#include "TerroirCommandLine.h"
#include "TerroirFlowCommands.h"
#include "TerroirOverlayPlugin.h"
#include "TerroirSafeOutput.h"
#include "TerroirViewerPlugin.h"
#include "TerroirViewerScript.h"
#include "TerroirWaterCommands.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationStringKey.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkSMPTools.h"
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
#include "vtkTerroirWaterFlowGPU.h" // UseSMPTools

#include "ClimateTable.h"
#include "GridView.h"
#include "MemoryBudget.h"
#include "SlopeHorn1981.h"
#include "SoilWater.h"
#include "WaterFlow.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <dlfcn.h>
#include <filesystem>
#include <functional>
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
  bool overwrite)
{
  terroir::app::CheckWritable({ path }, overwrite);
  if (const char* error = OverlayWriter()(
        image, array.c_str(), component, preset.c_str(), title.c_str(), path.c_str()))
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
        lakesPng });
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

  // Ecological zones: k-means of the resources with the seed's features and weights.
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
  for (const char* s :
    { "slope", "temperature", "illumination", "infiltration", "humidity", "lakes", "clusters" })
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

// ---------------------------------------------------------------------------------------------
/// Sustained memory bandwidth of this machine, bytes/s: a parallel copy of two 256 MiB arrays
/// (STREAM "copy": 8 bytes moved per float), best of `repeat`.
double MeasureCopyBandwidth(int repeat)
{
  const std::size_t n = std::size_t(64) << 20; // 64 Mi floats = 256 MiB
  std::vector<float> a(n, 1.0f), b(n, 0.0f);
  double best = 0;
  for (int r = 0; r < repeat; ++r)
  {
    const double t0 = terroir::app::Now();
    vtkSMPTools::For(0,
      static_cast<vtkIdType>(n),
      1 << 20,
      [&](vtkIdType i0, vtkIdType i1) { std::copy(a.data() + i0, a.data() + i1, b.data() + i0); });
    const double dt = terroir::app::Now() - t0;
    best = std::max(best, 2.0 * sizeof(float) * static_cast<double>(n) / dt);
  }
  if (b[n / 2] != 1.0f)
  {
    throw Failure("bandwidth probe: copy failed");
  }
  return best;
}

/// The synthetic DEM's float Elevation as a core grid view (uniform spacing).
terroir::GridView<float> ElevationView(vtkImageData* terrain)
{
  int dims[3];
  terrain->GetDimensions(dims);
  auto* z = vtkFloatArray::SafeDownCast(terrain->GetPointData()->GetArray("Elevation"));
  if (!z)
  {
    throw Failure("bench: the synthetic DEM has no float Elevation array");
  }
  terroir::GridView<float> view;
  view.data = z->GetPointer(0);
  view.nx = dims[0];
  view.ny = dims[1];
  double spacing[3];
  terrain->GetSpacing(spacing);
  view.dx = spacing[0];
  view.dy = spacing[1];
  return view;
}

/// Best time of the slope kernel alone (core SlopeHorn1981Rows over row blocks with
/// vtkSMPTools, outputs allocated and touched beforehand), seconds.
double TimeSlopeKernel(vtkImageData* terrain, bool allOutputs, int repeat)
{
  const terroir::GridView<float> view = ElevationView(terrain);
  const std::size_t n = view.Size();
  std::vector<float> slope(n, 0.0f), aspect(allOutputs ? n : 0, 0.0f),
    normals(allOutputs ? 3 * n : 0, 0.0f);
  const terroir::terrain::SlopeParams params;
  double best = 1e300;
  for (int r = 0; r < repeat + 1; ++r) // the first run warms caches and page tables
  {
    const double t0 = terroir::app::Now();
    vtkSMPTools::For(0,
      view.ny,
      16,
      [&](vtkIdType j0, vtkIdType j1)
      {
        terroir::terrain::SlopeHorn1981Rows(view,
          params,
          slope.data(),
          allOutputs ? aspect.data() : nullptr,
          allOutputs ? normals.data() : nullptr,
          static_cast<int>(j0),
          static_cast<int>(j1));
      });
    const double dt = terroir::app::Now() - t0;
    if (r > 0)
    {
      best = std::min(best, dt);
    }
  }
  return best;
}

/// Seconds per iteration of the water-flow CPU kernel alone (core WaterFlowSimulation, rows in
/// parallel as the filter runs them): the seed's benchmark, 100 mm on every cell run to the
/// automatic stop, timed without setting up the state; the best of `repeat` runs.
double TimeWaterFlowKernel(vtkImageData* terrain, int repeat)
{
  const terroir::GridView<float> view = ElevationView(terrain);
  const std::vector<double> water(view.Size(), 0.1);
  double best = 1e300;
  for (int r = 0; r < repeat; ++r)
  {
    terroir::hydrology::WaterFlowSimulation sim(view, water.data());
    terroir::hydrology::UseSMPTools(sim);
    const double t0 = terroir::app::Now();
    sim.Run(terroir::hydrology::WaterFlowStopRule{});
    const double dt = terroir::app::Now() - t0;
    if (sim.Iterations() > 0)
    {
      best = std::min(best, dt / static_cast<double>(sim.Iterations()));
    }
  }
  return best;
}

/// Best time of the soil-humidity kernel alone (core SoilHumidityLong2016 over blocks of cells
/// with vtkSMPTools, outputs allocated and touched beforehand, the default climate), seconds.
double TimeHumidityKernel(vtkImageData* withRates, bool allOutputs, int repeat)
{
  auto* rate = vtkFloatArray::SafeDownCast(
    withRates->GetPointData()->GetArray(vtkTerroirInfiltration::InfiltrationRateName()));
  if (!rate)
  {
    throw Failure("bench: no float InfiltrationRate array");
  }
  const std::size_t n = static_cast<std::size_t>(rate->GetNumberOfTuples());
  vtkNew<vtkTerroirSoilHumidity> defaults;
  terroir::terrain::MonthlyRain rain{};
  for (int m = 0; m < 12; ++m)
  {
    rain.quantityMm[m] = static_cast<float>(defaults->GetPrecipitation()[m]);
    rain.intensityMmPerHour[m] = static_cast<float>(defaults->GetPrecipitationIntensity()[m]);
  }
  std::vector<float> h(12 * n, 0.0f), w(allOutputs ? 12 * n : 0, 0.0f),
    st(allOutputs ? 12 * n : 0, 0.0f);
  const float* r = rate->GetPointer(0);
  double best = 1e300;
  for (int k = 0; k < repeat + 1; ++k) // the first run warms caches and page tables
  {
    const double t0 = terroir::app::Now();
    vtkSMPTools::For(0,
      static_cast<vtkIdType>(n),
      4096,
      [&](vtkIdType c0, vtkIdType c1)
      {
        terroir::terrain::SoilHumidityLong2016(r,
          nullptr,
          rain,
          h.data(),
          allOutputs ? w.data() : nullptr,
          allOutputs ? st.data() : nullptr,
          static_cast<std::size_t>(c0),
          static_cast<std::size_t>(c1));
      });
    const double dt = terroir::app::Now() - t0;
    if (k > 0)
    {
      best = std::min(best, dt);
    }
  }
  return best;
}

/// The bench terrain with 37 feature components for the k-means stage: Slope, Temperature
/// (12), and two 12-month fields that vary across the terrain and between months (stand-ins
/// for IlluminationHours and WeightedSoilHumidity, which take long to compute).
vtkSmartPointer<vtkImageData> BenchKMeansFeatures(vtkImageData* terrain)
{
  vtkNew<vtkTerroirSlope> slope;
  slope->SetInputData(terrain);
  vtkNew<vtkTerroirTemperature> temperature;
  temperature->SetInputConnection(slope->GetOutputPort());
  terroir::app::UpdateOrThrow(temperature, "kmeans features");
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->ShallowCopy(temperature->GetOutput());
  int dims[3];
  out->GetDimensions(dims);
  const vtkIdType n = static_cast<vtkIdType>(dims[0]) * dims[1];
  vtkDataArray* z = out->GetPointData()->GetArray("Elevation");
  vtkDataArray* s = out->GetPointData()->GetArray("Slope");
  for (const char* name : { "IlluminationHours", "WeightedSoilHumidity" })
  {
    vtkNew<vtkFloatArray> a;
    a->SetName(name);
    a->SetNumberOfComponents(12);
    a->SetNumberOfTuples(n);
    const bool sun = name[0] == 'I';
    vtkSMPTools::For(0,
      n,
      [&](vtkIdType b, vtkIdType e)
      {
        for (vtkIdType c = b; c < e; ++c)
        {
          const double x = static_cast<double>(c % dims[0]) / dims[0];
          for (int m = 0; m < 12; ++m)
          {
            const double season = std::cos(2.0 * M_PI * (m - 5.5) / 12.0);
            const double v = sun ? 10.0 + 3.0 * season - 0.05 * s->GetComponent(c, 0) + x
                                 : 80.0 - 40.0 * season + 0.02 * z->GetComponent(c, 0) - 20.0 * x;
            a->SetComponent(c, m, v);
          }
        }
      });
    out->GetPointData()->AddArray(a);
  }
  return out;
}

int CommandBench(int size,
  int repeat,
  const std::string& backends,
  const std::vector<std::string>& stages,
  bool bandwidth,
  const std::string& jsonPath)
{
  // Measured first, while the process holds no other large arrays.
  const double bw = bandwidth ? MeasureCopyBandwidth(std::max(5, repeat)) : 0.0;
  vtkNew<vtkTerroirFractalTerrainSource> source;
  source->SetDimensions(size, size);
  source->SetSeed(1);
  const double tg = terroir::app::Now();
  terroir::app::UpdateOrThrow(source, "fractal terrain");
  const double genSeconds = terroir::app::Now() - tg;
  vtkSmartPointer<vtkImageData> terrain = vtkSmartPointer<vtkImageData>::New();
  terrain->ShallowCopy(source->GetOutput());
  const double mcells = static_cast<double>(size) * size / 1e6;

  std::vector<int> backendList;
  std::stringstream ss(backends);
  std::string item;
  while (std::getline(ss, item, ','))
  {
    const int b = ParseBackend(item);
    if (b == vtkTerroirComputeContext::GPU && !vtkTerroirComputeContext::IsAvailable())
    {
      std::cerr << "terroir bench: GPU skipped: "
                << vtkTerroirComputeContext::GetUnavailableReason() << "\n";
      continue;
    }
    backendList.push_back(b);
  }

  json results = json::array();
  std::cout << "terroir bench: " << size << " x " << size << " synthetic DEM (" << std::fixed
            << std::setprecision(2) << mcells << " Mcells), best of " << repeat << ", "
            << vtkSMPTools::GetEstimatedNumberOfThreads() << " threads ("
            << vtkSMPTools::GetBackend() << ")\n";
  if (vtkTerroirComputeContext::IsAvailable())
  {
    std::cout << "GPU: " << vtkTerroirComputeContext::GetRenderer() << "\n";
  }
  std::cout << std::left << std::setw(18) << "stage" << std::setw(8) << "backend" << std::right
            << std::setw(12) << "ms" << std::setw(14) << "ms/Mcell" << std::setw(14) << "Mcells/s"
            << "\n";
  std::cout << std::left << std::setw(18) << "fractal" << std::setw(8) << "CPU" << std::right
            << std::setw(12) << genSeconds * 1e3 << std::setw(14) << genSeconds * 1e3 / mcells
            << std::setw(14) << mcells / genSeconds << "\n";

  double slopeCpuSeconds = 0;
  vtkSmartPointer<vtkImageData> humidityInput; // terrain + InfiltrationRate, for --bandwidth
  vtkSmartPointer<vtkImageData> kmeansInput;   // terrain + 37 feature components
  auto report = [&](const std::string& stage, const char* bname, double best, json extra)
  {
    std::cout << std::left << std::setw(18) << stage << std::setw(8) << bname << std::right
              << std::setw(12) << best * 1e3 << std::setw(14) << best * 1e3 / mcells
              << std::setw(14) << mcells / best << "\n";
    json row{ { "stage", stage },
      { "backend", bname },
      { "seconds", best },
      { "mcells", mcells },
      { "ms_per_mcell", best * 1e3 / mcells } };
    row.update(extra);
    results.push_back(row);
  };
  // Best of `repeat` timed calls of `once` (which returns its own seconds), after one untimed
  // warm-up call (shader compile, first touch of memory).
  auto bestOf = [&](const std::function<double()>& once)
  {
    once();
    double best = 1e300;
    for (int r = 0; r < repeat; ++r)
    {
      best = std::min(best, once());
    }
    return best;
  };
  // The illumination stages: the synthetic DEM has no georeference, so the sun is placed at
  // Sagehen Creek (39.43 N, 120.24 W) with grid north = true north; the instants are
  // 2025-06-21 15:00 local time (UTC-8), the sun at azimuth 260 deg, elevation 49 deg.
  auto illumination = [&](int b, int mode)
  {
    auto f = vtkSmartPointer<vtkTerroirSolarIllumination>::New();
    f->SetBackend(b);
    f->SetInputData(terrain);
    f->SetLatitude(39.43);
    f->SetLongitude(-120.24);
    f->SetOrientation(0.0);
    f->SetMode(mode);
    f->SetYear(2025);
    f->SetMonth(6);
    f->SetDay(21);
    f->SetTime(15.0);
    f->SetUTCOffset(-8.0);
    return f;
  };
  auto timedUpdate = [](vtkAlgorithm* f, const std::string& stage)
  {
    f->Modified();
    const double t0 = terroir::app::Now();
    terroir::app::UpdateOrThrow(f, stage);
    return terroir::app::Now() - t0;
  };
  for (const std::string& stage : stages)
  {
    for (int b : backendList)
    {
      const char* bname = vtkTerroirComputeContext::GetBackendName(b);
      try
      {
        if (stage == "slope" || stage == "temperature")
        {
          vtkSmartPointer<vtkTerroirImageAlgorithm> filter;
          if (stage == "slope")
          {
            filter = vtkSmartPointer<vtkTerroirSlope>::New();
          }
          else
          {
            filter = vtkSmartPointer<vtkTerroirTemperature>::New();
          }
          filter->SetBackend(b);
          filter->SetInputData(terrain);
          const double best = bestOf([&] { return timedUpdate(filter, stage); });
          report(stage, bname, best, json::object());
          if (stage == "slope" && b == vtkTerroirComputeContext::CPU)
          {
            slopeCpuSeconds = best;
          }
        }
        else if (stage == "horizon")
        {
          // The horizon map alone, as the filter times it, built by a fresh filter each time.
          int sectors = 0;
          const double best = bestOf(
            [&]
            {
              auto f = illumination(b, vtkTerroirSolarIllumination::Instant);
              terroir::app::UpdateOrThrow(f, stage);
              sectors = f->GetHorizonSectors();
              return f->GetLastHorizonMapSeconds();
            });
          report(stage, bname, best, json{ { "sectors", sectors } });
        }
        else if (stage == "instant")
        {
          // One instant with the horizon map already built (the warm-up builds it, later runs
          // find it in the filter's cache), then the same instant by ray marching.
          auto f = illumination(b, vtkTerroirSolarIllumination::Instant);
          double mapSeconds = 0.0;
          const double best = bestOf(
            [&]
            {
              const double t = timedUpdate(f, stage);
              mapSeconds = f->GetLastHorizonMapSeconds();
              return t;
            });
          report(stage,
            bname,
            best,
            json{ { "method", "horizon" }, { "horizon_map_seconds", mapSeconds } });
          auto g = illumination(b, vtkTerroirSolarIllumination::Instant);
          g->SetShadowMethodToRayMarching();
          const double march = bestOf([&] { return timedUpdate(g, stage); });
          report("instant-raymarch", bname, march, json{ { "method", "raymarch" } });
        }
        else if (stage == "infiltration")
        {
          // The default recipe: fill, then the slope rule on a slope computed inside (CPU only).
          if (b != vtkTerroirComputeContext::CPU)
          {
            continue;
          }
          vtkNew<vtkTerroirInfiltration> f;
          f->SetInputData(terrain);
          report(stage, bname, bestOf([&] { return timedUpdate(f, stage); }), json::object());
        }
        else if (stage == "humidity")
        {
          // Soil humidity alone (the seed's first kernel) and with the weighted average and
          // standing water (its second), from rates of the default infiltration recipe.
          vtkNew<vtkTerroirInfiltration> rates;
          rates->SetInputData(terrain);
          terroir::app::UpdateOrThrow(rates, "infiltration");
          vtkNew<vtkTerroirSoilHumidity> f;
          f->SetBackend(b);
          f->SetInputConnection(rates->GetOutputPort());
          f->ComputeWeightedSoilHumidityOff();
          f->ComputeStandingWaterOff();
          report("humidity",
            bname,
            bestOf([&] { return timedUpdate(f, stage); }),
            json{ { "outputs", "SoilHumidity" } });
          f->ComputeWeightedSoilHumidityOn();
          f->ComputeStandingWaterOn();
          report("humidity-all",
            bname,
            bestOf([&] { return timedUpdate(f, stage); }),
            json{ { "outputs", "SoilHumidity, WeightedSoilHumidity, StandingWater" } });
          if (b == vtkTerroirComputeContext::CPU)
          {
            humidityInput = vtkSmartPointer<vtkImageData>::New();
            humidityInput->ShallowCopy(rates->GetOutput());
          }
        }
        else if (stage == "floodfill" || stage == "depressions")
        {
          // Seeds: one seed in the lowest cell, level at the median height (about half the
          // terrain connected to it floods); depressions: priority-flood and lakes.
          if (b != vtkTerroirComputeContext::CPU)
          {
            continue;
          }
          vtkNew<vtkTerroirFloodFill> f;
          f->SetInputData(terrain);
          json extra = json::object();
          if (stage == "floodfill")
          {
            vtkDataArray* z = terrain->GetPointData()->GetArray("Elevation");
            std::vector<float> sorted(static_cast<std::size_t>(z->GetNumberOfTuples()));
            vtkIdType lowest = 0;
            for (vtkIdType k = 0; k < z->GetNumberOfTuples(); ++k)
            {
              sorted[static_cast<std::size_t>(k)] = static_cast<float>(z->GetComponent(k, 0));
              if (z->GetComponent(k, 0) < z->GetComponent(lowest, 0))
              {
                lowest = k;
              }
            }
            std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
            const double median = sorted[sorted.size() / 2];
            f->AddSeedCell(
              static_cast<int>(lowest % size), static_cast<int>(lowest / size), median);
            extra["level_m"] = median;
          }
          else
          {
            f->SetModeToFillDepressions();
          }
          const double best = bestOf([&] { return timedUpdate(f, stage); });
          vtkDataArray* cells =
            f->GetOutput()->GetFieldData()->GetArray(vtkTerroirFloodFill::WaterBodyCellsName());
          double wet = 0.0;
          for (vtkIdType k = 0; cells && k < cells->GetNumberOfTuples(); ++k)
          {
            wet += cells->GetComponent(k, 0);
          }
          extra["water_bodies"] = cells ? cells->GetNumberOfTuples() : 0;
          extra["wet_cells"] = wet;
          report(stage, bname, best, extra);
        }
        else if (stage == "waterflow")
        {
          // The seed's benchmark: 100 mm on every cell, run to the automatic stop; a fresh
          // filter each time (the filter caches its state).
          long long iterations = 0;
          const double best = bestOf(
            [&]
            {
              vtkNew<vtkTerroirWaterFlow> f;
              f->SetBackend(b);
              f->SetInputData(terrain);
              const double t = timedUpdate(f, stage);
              vtkDataArray* it =
                f->GetOutput()->GetFieldData()->GetArray(vtkTerroirWaterFlow::IterationsName());
              iterations = it ? static_cast<long long>(it->GetComponent(0, 0)) : 0;
              return t;
            });
          const double cells = static_cast<double>(size) * size;
          report(stage,
            bname,
            best,
            json{ { "iterations", iterations },
              { "ms_per_iteration", iterations > 0 ? 1e3 * best / iterations : 0.0 },
              { "mcells_iterations_per_s",
                iterations > 0 ? cells * iterations / best / 1e6 : 0.0 } });
        }
        else if (stage == "kmeans")
        {
          // Lloyd iterations on 37 features (Slope, Temperature x 12 with the storage trick
          // off, and two synthetic 12-month fields), K = 5 and 10, the seed's diagonal seeds.
          // Time per iteration = (time of 11 iterations - time of 1) / 10: the set-up (packing,
          // seeding, the table) cancels out. The stage's seconds: 11 iterations at K = 5.
          if (!kmeansInput)
          {
            kmeansInput = BenchKMeansFeatures(terrain);
          }
          json perK;
          double best5 = 0.0;
          for (int k : { 5, 10 })
          {
            auto once = [&](int iterations)
            {
              return bestOf(
                [&]
                {
                  vtkNew<vtkTerroirKMeans> f;
                  f->SetBackend(b);
                  f->SetNumberOfClusters(k);
                  f->SetCollapseConstantOffsets(false);
                  f->SetTolerance(0.0);
                  f->SetMaximumIterations(iterations);
                  f->SetInputData(kmeansInput);
                  return timedUpdate(f, stage);
                });
            };
            const double t1 = once(1);
            const double t11 = once(11);
            const double perIteration = std::max(0.0, (t11 - t1) / 10.0);
            perK[std::to_string(k)] = json{ { "ms_per_iteration", 1e3 * perIteration },
              { "seconds_1_iteration", t1 },
              { "seconds_11_iterations", t11 } };
            if (k == 5)
            {
              best5 = t11;
            }
            std::cout << "  kmeans K=" << k << " " << bname << ": " << std::setprecision(2)
                      << 1e3 * perIteration << " ms per iteration (37 features)\n";
          }
          report(stage, bname, best5, json{ { "features", 37 }, { "per_k", perK } });
        }
        else if (stage == "monthly")
        {
          // Monthly mode with its defaults (the 15th of each month, 10-minute steps), a fresh
          // filter each time: the horizon map is included.
          double mapSeconds = 0.0, bestSeconds = 1e300;
          int steps = 0;
          const double best = bestOf(
            [&]
            {
              auto f = illumination(b, vtkTerroirSolarIllumination::Monthly);
              const double t = timedUpdate(f, stage);
              if (t < bestSeconds)
              {
                bestSeconds = t;
                mapSeconds = f->GetLastHorizonMapSeconds();
              }
              vtkDataArray* sun = f->GetOutput()->GetFieldData()->GetArray(
                vtkTerroirSolarIllumination::SunPositionsName());
              steps = sun ? static_cast<int>(sun->GetNumberOfTuples()) : 0;
              return t;
            });
          report(stage,
            bname,
            best,
            json{ { "horizon_map_seconds", mapSeconds }, { "sun_steps", steps } });
        }
      }
      catch (const Failure& e)
      {
        // One stage failing on one backend (e.g. a grid too large for the GPU) does not
        // stop the others.
        std::cout << std::left << std::setw(18) << stage << std::setw(8) << bname
                  << "failed: " << e.what() << "\n";
        results.push_back(json{ { "stage", stage }, { "backend", bname }, { "error", e.what() } });
      }
    }
  }
  json doc{ { "size", size },
    { "repeat", repeat },
    { "mcells", mcells },
    { "stages", stages },
    { "results", results } };
  if (bandwidth)
  {
    // The slope filter reads one float and writes Slope, Aspect and 3 Normals components.
    const double bytesPerCell = 4.0 + 4.0 * (1 + 1 + 3);
    std::cout << "memory bandwidth (parallel copy, 256 MiB, "
              << vtkSMPTools::GetEstimatedNumberOfThreads() << " threads): " << bw / 1e9
              << " GB/s\n";
    doc["copy_bandwidth_GBps"] = bw / 1e9;
    // The kernel alone, without allocation or pipeline work: bytes = 4 read + 4 per output.
    for (bool all : { false, true })
    {
      const double sec = TimeSlopeKernel(terrain, all, std::max(3, repeat));
      const double bytes = (all ? bytesPerCell : 8.0) * mcells * 1e6;
      const char* what = all ? "slope kernel (Slope+Aspect+Normals)" : "slope kernel (Slope only)";
      std::cout << what << ": " << std::setprecision(2) << sec * 1e3 / mcells << " ms/Mcell, "
                << bytes / sec / 1e9 << " GB/s = " << std::setprecision(0)
                << 100.0 * bytes / sec / bw << " % of copy bandwidth\n"
                << std::setprecision(2);
      doc[all ? "slope_kernel_all_GBps" : "slope_kernel_slope_only_GBps"] = bytes / sec / 1e9;
    }
    if (humidityInput)
    {
      // Soil humidity: 4 B read (the rate) and 48 B written per output (12 months).
      for (bool all : { false, true })
      {
        const double sec = TimeHumidityKernel(humidityInput, all, std::max(3, repeat));
        const double bytes = (all ? 4.0 + 3 * 48.0 : 4.0 + 48.0) * mcells * 1e6;
        const char* what =
          all ? "humidity kernel (all three outputs)" : "humidity kernel (SoilHumidity)";
        std::cout << what << ": " << std::setprecision(2) << sec * 1e3 << " ms, "
                  << sec * 1e3 / mcells << " ms/Mcell, " << bytes / sec / 1e9
                  << " GB/s = " << std::setprecision(0) << 100.0 * bytes / sec / bw
                  << " % of copy bandwidth\n"
                  << std::setprecision(2);
        doc[all ? "humidity_kernel_all_seconds" : "humidity_kernel_seconds"] = sec;
        doc[all ? "humidity_kernel_all_fraction_of_bandwidth"
                : "humidity_kernel_fraction_of_bandwidth"] = bytes / sec / bw;
      }
    }
    if (std::find(stages.begin(), stages.end(), "waterflow") != stages.end())
    {
      // Water flow, per iteration: terrain 4 B and water 8 B read, new water 8 B written,
      // discharge 8 B read and written (WaterFlow.h).
      const double sec = TimeWaterFlowKernel(terrain, std::max(3, repeat));
      const double bytes = 36.0 * mcells * 1e6;
      std::cout << "water-flow kernel (per iteration, run to the automatic stop): "
                << std::setprecision(3) << sec * 1e3 << " ms, " << std::setprecision(0)
                << mcells / sec << " Mcells/s, " << std::setprecision(2) << bytes / sec / 1e9
                << " GB/s = " << std::setprecision(0) << 100.0 * bytes / sec / bw
                << " % of copy bandwidth\n"
                << std::setprecision(2);
      doc["waterflow_kernel_ms_per_iteration"] = sec * 1e3;
      doc["waterflow_kernel_fraction_of_bandwidth"] = bytes / sec / bw;
    }
    if (slopeCpuSeconds > 0)
    {
      const double eff = bytesPerCell * mcells * 1e6 / slopeCpuSeconds;
      std::cout << "slope CPU filter effective bandwidth: " << eff / 1e9
                << " GB/s = " << std::setprecision(0) << 100.0 * eff / bw
                << " % of copy bandwidth\n";
      doc["slope_cpu_effective_GBps"] = eff / 1e9;
      doc["slope_cpu_fraction_of_bandwidth"] = eff / bw;
    }
  }
  if (!jsonPath.empty())
  {
    terroir::app::WriteTextFile(jsonPath, doc.dump(2) + "\n", true);
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
  const terroir::app::ParseOutcome parsed = terroir::app::ParseCommandLine(argc, argv, c);
  if (!parsed.Run)
  {
    std::cout << parsed.Stdout;
    if (!parsed.Error.empty())
    {
      std::cerr << "terroir: error: " << parsed.Error << "\n";
    }
    return parsed.ExitCode;
  }

  // A malformed TERROIR_MEMORY_LIMIT is the user's error, not the first reader's.
  terroir::MemoryAvailability memory;
  std::string memoryError;
  if (!terroir::AvailableMemory(memory, memoryError))
  {
    std::cerr << "terroir: error: " << memoryError << "\n";
    return 2;
  }
  terroir::app::InstallQuietOutput(c.Verbose);
  // Interrupted or over `ulimit -f`: remove the temporaries, leave earlier results as they were.
  terroir::InstallSignalCleanup();
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
                                 const std::string& path)
    {
      if (!HaveDisplay())
      {
        throw Failure(path + ": PNG overlays need an X display: run under 'xvfb-run -a'");
      }
      WriteOverlay(image, array, 0, preset, title, path, c.Overwrite);
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
      std::string backends;
      for (const std::string& b : c.BenchBackends)
      {
        backends += (backends.empty() ? "" : ",") + b;
      }
      return CommandBench(c.BenchSize,
        c.BenchRepeat,
        backends,
        c.BenchStages.empty() ? terroir::app::BenchStageNames() : c.BenchStages,
        c.BenchBandwidth,
        c.BenchJson);
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

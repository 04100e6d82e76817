// `terroir run`: every filter on one DEM with defaults; .vti, GeoTIFFs, PNG overlays,
// report.md/json
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
int RunEveryStage(const std::string& demArg,
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
} // namespace

int CommandRun(const CommandLine& c)
{
  return RunEveryStage(c.Input,
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

} // namespace app
} // namespace terroir

// The model of `terroir view` (TerroirViewerSessionPrivate.h): the overlays' filters, run on a
// snapshot (synchronously or by the worker), the sun's direction, and the cluster table.
#include "TerroirViewerSessionPrivate.h"

#include "vtkDataArray.h"
#include "vtkInformation.h"
#include "vtkStringArray.h"
#include "vtkTable.h"

#include "vtkTerroirGeoreference.h"
#include "vtkTerroirKMeans.h"
#include "vtkTerroirSlope.h"
#include "vtkTerroirSoilHumidity.h"
#include "vtkTerroirSolarIllumination.h"
#include "vtkTerroirTemperature.h"
#include "vtkTerroirWaterFlow.h"

#include "SolarPosition.h"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>

namespace terroir
{
namespace viewer
{
namespace
{

/// Sets the place and time of a solar filter from the parameters (clock = local mean time).
void ConfigureSun(vtkTerroirSolarIllumination* sun, const ViewerParameters& p)
{
  sun->SetLatitude(p.Latitude);
  sun->SetLongitude(p.Longitude);
  sun->SetOrientation(p.Orientation);
  sun->SetYear(2025);
  sun->SetMonth(p.Month);
  sun->SetDay(15);
  sun->SetMonthlyDay(15);
  sun->SetTime(p.Hour);
  sun->SetUTCOffset(std::max(-14.0, std::min(14.0, p.Longitude / 15.0)));
}
} // namespace

void ConfigureClimate(vtkTerroirTemperature* temperature, const ViewerParameters& p)
{
  temperature->SetHemisphere(
    p.Latitude < 0.0 ? vtkTerroirTemperature::South : vtkTerroirTemperature::North);
  temperature->SetSeaLevelTemperatureColdest(p.Coldest);
  temperature->SetSeaLevelTemperatureWarmest(p.Warmest);
  temperature->SetLapseRate(p.LapseRate);
  temperature->SetUseMonthlyTemperatures(p.UseMonthlyTemperatures);
  temperature->SetMonthlySeaLevelTemperatures(p.MonthlyTemperatures.data());
}

void ConfigureClimate(vtkTerroirSoilHumidity* humidity, const ViewerParameters& p)
{
  humidity->SetPrecipitation(p.Precipitation.data());
  humidity->SetPrecipitationIntensity(p.PrecipitationIntensity.data());
}

vtkDataArray* OverlayResult::GetValues() const
{
  return this->Output && !this->ArrayName.empty()
    ? this->Output->GetPointData()->GetArray(this->ArrayName.c_str())
    : nullptr;
}

//------------------------------------------------------------------------------
// The overlays' recipes: each runs its filters on the snapshot and names the array, the
// component and the colour preset to show.
namespace
{
int MonthOf(const ViewerParameters& p)
{
  return std::max(1, std::min(12, p.Month));
}

void ShowTerrain(vtkImageData* input, const ViewerParameters&, JobMonitor&, OverlayResult& r)
{
  r.Output = input;
}

void ShowWater(vtkImageData* input, const ViewerParameters&, JobMonitor&, OverlayResult& r)
{
  r.ArrayName = vtkTerroirWaterFlow::WaterHeightName();
  r.Preset = "Water";
  r.Output = input;
}

void ComputeSlope(vtkImageData* input,
  const ViewerParameters&,
  JobMonitor& monitor,
  OverlayResult& r)
{
  vtkNew<vtkTerroirSlope> slope;
  slope->SetInputData(input);
  if (RunFilter(slope, monitor, 0.0, 1.0))
  {
    r.Output = slope->GetOutput();
  }
  r.ArrayName = vtkTerroirSlope::SlopeName();
  r.Preset = "Slope";
}

/// Illumination (instant: lit or shadow at the hour) and SunHours (daily hours of sun).
void ComputeSun(vtkImageData* input,
  const ViewerParameters& p,
  JobMonitor& monitor,
  OverlayResult& r)
{
  vtkNew<vtkTerroirSolarIllumination> sun;
  sun->SetInputData(input);
  ConfigureSun(sun, p);
  const bool instant = r.Overlay == ViewerOverlay::Illumination;
  if (instant)
  {
    sun->SetModeToInstant();
  }
  else
  {
    sun->SetModeToDaily();
  }
  if (RunFilter(sun, monitor, 0.0, 1.0))
  {
    r.Output = sun->GetOutput();
  }
  r.ArrayName = instant ? vtkTerroirSolarIllumination::IlluminatedName()
                        : vtkTerroirSolarIllumination::IlluminationHoursName();
  r.Preset = instant ? "Sunlit" : "Illumination";
}

void ComputeTemperature(vtkImageData* input,
  const ViewerParameters& p,
  JobMonitor& monitor,
  OverlayResult& r)
{
  vtkNew<vtkTerroirTemperature> temperature;
  temperature->SetInputData(input);
  ConfigureClimate(temperature, p);
  if (RunFilter(temperature, monitor, 0.0, 1.0))
  {
    r.Output = temperature->GetOutput();
  }
  r.ArrayName = vtkTerroirTemperature::TemperatureName();
  r.Component = MonthOf(p) - 1;
  r.Preset = "Temperature";
}

void ComputeHumidity(vtkImageData* input,
  const ViewerParameters& p,
  JobMonitor& monitor,
  OverlayResult& r)
{
  // Humidity: the month's SoilHumidity; WeightedHumidity: its moving weighted average.
  const bool weighted = r.Overlay == ViewerOverlay::WeightedHumidity;
  vtkNew<vtkTerroirSoilHumidity> humidity;
  humidity->SetInputData(input);
  humidity->SetComputeWeightedSoilHumidity(weighted);
  humidity->ComputeStandingWaterOff();
  ConfigureClimate(humidity, p);
  if (RunFilter(humidity, monitor, 0.0, 1.0))
  {
    r.Output = humidity->GetOutput();
  }
  r.ArrayName = weighted ? vtkTerroirSoilHumidity::WeightedSoilHumidityName()
                         : vtkTerroirSoilHumidity::SoilHumidityName();
  r.Component = MonthOf(p) - 1;
  r.Preset = "Humidity";
}

/// Slope, temperature, monthly hours of sun and the weighted soil humidity of the
/// infiltration map, then k-means with the session's K and feature weights.
void ComputeClusters(vtkImageData* input,
  const ViewerParameters& p,
  JobMonitor& monitor,
  OverlayResult& r)
{
  vtkNew<vtkTerroirSlope> slope;
  slope->SetInputData(input);
  vtkNew<vtkTerroirTemperature> temperature;
  temperature->SetInputConnection(slope->GetOutputPort());
  ConfigureClimate(temperature, p);
  vtkNew<vtkTerroirSolarIllumination> sun;
  sun->SetInputConnection(temperature->GetOutputPort());
  ConfigureSun(sun, p);
  sun->SetModeToMonthly();
  vtkNew<vtkTerroirSoilHumidity> humidity;
  humidity->SetInputConnection(sun->GetOutputPort());
  humidity->ComputeWeightedSoilHumidityOn();
  humidity->ComputeStandingWaterOff();
  ConfigureClimate(humidity, p);
  vtkNew<vtkTerroirKMeans> kmeans;
  kmeans->SetInputConnection(humidity->GetOutputPort());
  kmeans->SetNumberOfClusters(std::max(1, std::min(64, p.Clusters)));
  for (std::size_t f = 0; f < kViewerClusterFeatureCount; ++f)
  {
    if (p.ClusterWeights[f] > 0.0)
    {
      kmeans->AddFeature(kViewerClusterFeatures[f].ArrayName, p.ClusterWeights[f]);
    }
  }
  if (kmeans->GetNumberOfFeatures() == 0)
  {
    monitor.Error = "the clusters need a feature with a weight above 0";
  }
  else if (RunFilter(slope, monitor, 0.0, 0.05) && RunFilter(temperature, monitor, 0.05, 0.05) &&
    RunFilter(sun, monitor, 0.1, 0.75) && RunFilter(humidity, monitor, 0.85, 0.05) &&
    RunFilter(kmeans, monitor, 0.9, 0.1))
  {
    r.Output = kmeans->GetOutput();
    r.Table = kmeans->GetClusterTable();
  }
  r.ArrayName = vtkTerroirKMeans::ClusterIdName();
  r.Preset = "Clusters";
}

using OverlayRecipe = void (*)(vtkImageData*, const ViewerParameters&, JobMonitor&, OverlayResult&);

/// Every overlay's recipe, in the order of ViewerOverlay (TerroirViewerScript.h).
const std::map<ViewerOverlay, OverlayRecipe>& OverlayRecipes()
{
  static const std::map<ViewerOverlay, OverlayRecipe> recipes = {
    { ViewerOverlay::None, ShowTerrain },
    { ViewerOverlay::Slope, ComputeSlope },
    { ViewerOverlay::Illumination, ComputeSun },
    { ViewerOverlay::SunHours, ComputeSun },
    { ViewerOverlay::Temperature, ComputeTemperature },
    { ViewerOverlay::Humidity, ComputeHumidity },
    { ViewerOverlay::Water, ShowWater },
    { ViewerOverlay::Clusters, ComputeClusters },
    { ViewerOverlay::WeightedHumidity, ComputeHumidity },
  };
  return recipes;
}
} // namespace

std::vector<ViewerOverlay> ComputableOverlays()
{
  std::vector<ViewerOverlay> overlays;
  for (const auto& entry : OverlayRecipes())
  {
    overlays.push_back(entry.first);
  }
  return overlays;
}

//------------------------------------------------------------------------------
/// The overlay's filters on `input` (a snapshot: terrain, WaterHeight, InfiltrationRate).
OverlayResult ComputeOverlayOn(vtkImageData* input,
  ViewerOverlay overlay,
  const ViewerParameters& p,
  std::atomic<double>& progress)
{
  OverlayResult r;
  r.Overlay = overlay;
  const auto recipe = OverlayRecipes().find(overlay);
  if (recipe == OverlayRecipes().end())
  {
    r.Error = std::string("no recipe for the overlay '") + OverlayName(overlay) + "'";
    return r;
  }
  JobMonitor monitor;
  monitor.Progress = &progress;
  recipe->second(input, p, monitor, r);
  if (overlay == ViewerOverlay::None || overlay == ViewerOverlay::Water)
  {
    return r; // the terrain itself (and its water), nothing computed
  }
  r.Error = monitor.Error;
  if (r.Error.empty() && !r.GetValues())
  {
    r.Error = std::string("the ") + OverlayName(overlay) + " overlay produced no '" + r.ArrayName +
      "' array";
  }
  return r;
}

OverlayResult ViewerSession::ComputeOverlay(ViewerOverlay overlay, const ViewerParameters& p) const
{
  if (!this->Impl->Terrain)
  {
    OverlayResult r;
    r.Overlay = overlay;
    r.Error = "no terrain";
    return r;
  }
  std::atomic<double> progress{ 0.0 };
  return ComputeOverlayOn(this->Impl->Snapshot(), overlay, p, progress);
}

//------------------------------------------------------------------------------
void ViewerSession::SunDirection(const ViewerParameters& p,
  double& gridAzimuth,
  double& elevation) const
{
  terroir::terrain::UTCInstant when;
  when.year = 2025;
  when.month = std::max(1, std::min(12, p.Month));
  when.day = 15;
  when.hours = p.Hour - std::max(-14.0, std::min(14.0, p.Longitude / 15.0));
  terroir::terrain::Observer where;
  where.latitudeDeg = p.Latitude;
  where.longitudeDeg = p.Longitude;
  const terroir::terrain::SolarPosition sun = terroir::terrain::SolarPositionNREL2004(when, where);
  double gridNorth = p.Orientation;
  if (!std::isfinite(gridNorth))
  {
    gridNorth =
      this->Impl->Terrain && vtkTerroirGeoreference::HasMeridianConvergence(this->Impl->Terrain)
      ? vtkTerroirGeoreference::GetMeridianConvergence(this->Impl->Terrain)
      : 0.0;
  }
  // True azimuth = grid azimuth + bearing of grid north.
  gridAzimuth = std::fmod(sun.azimuthDeg - gridNorth + 720.0, 360.0);
  elevation = sun.elevationDeg;
}

//------------------------------------------------------------------------------
namespace
{
/// The title of a column of vtkTerroirKMeans's table: its array's short name, the month of a
/// monthly component, the units; empty when the column is another month's (`month` 1..12) or
/// no feature.
std::string ColumnTitle(vtkTable* table, vtkIdType c, int month)
{
  auto* column = vtkDataArray::SafeDownCast(table->GetColumn(c));
  const std::string name = table->GetColumnName(c) ? table->GetColumnName(c) : "";
  if (!column || name == "ClusterId" || name == "Cells" || name == "Share")
  {
    return "";
  }
  std::string base = name;
  std::string when;
  for (int m = 1; m <= 12; ++m)
  {
    const std::string suffix = std::string("_") + vtkTerroirTemperature::GetMonthName(m - 1);
    if (name.size() > suffix.size() &&
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
    {
      if (month != 0 && m != month)
      {
        return ""; // another month's component
      }
      base = name.substr(0, name.size() - suffix.size());
      when = " " + suffix.substr(1);
    }
  }
  if (when.empty() && name.find('_') != std::string::npos)
  {
    return ""; // a component that is no month
  }
  const std::map<std::string, std::string> shortNames = { { "Slope", "Slope" },
    { "Temperature", "Temp" },
    { "IlluminationHours", "Sun" },
    { "WeightedSoilHumidity", "Humidity" } };
  auto known = shortNames.find(base);
  std::string title = (known != shortNames.end() ? known->second : base) + when;
  vtkInformation* info = column->GetInformation();
  if (info->Has(vtkDataArray::UNITS_LABEL()))
  {
    const std::string units = info->Get(vtkDataArray::UNITS_LABEL());
    // Degrees as the sign, as in the legends: "deg" and "degC" become ° and °C.
    const bool degrees = units == "deg" || units == "degC";
    const std::string sign = degrees ? "\xc2\xb0" + units.substr(3) : units;
    title += " (" + sign + ")";
  }
  return title;
}
} // namespace

ClusterTable ClusterTable::FromKMeans(vtkTable* table, int month)
{
  ClusterTable t;
  if (!table)
  {
    return t;
  }
  month = month == 0 ? 0 : std::max(1, std::min(12, month));
  std::vector<vtkDataArray*> columns;
  for (vtkIdType c = 0; c < table->GetNumberOfColumns(); ++c)
  {
    const std::string title = ColumnTitle(table, c, month);
    if (!title.empty())
    {
      t.Columns.push_back(title);
      columns.push_back(vtkDataArray::SafeDownCast(table->GetColumn(c)));
    }
  }
  auto* ids = vtkDataArray::SafeDownCast(table->GetColumnByName("ClusterId"));
  auto* colors = vtkStringArray::SafeDownCast(table->GetColumnByName("Color"));
  auto* cells = vtkDataArray::SafeDownCast(table->GetColumnByName("Cells"));
  auto* shares = vtkDataArray::SafeDownCast(table->GetColumnByName("Share"));
  for (vtkIdType r = 0; r < table->GetNumberOfRows(); ++r)
  {
    ClusterTableRow row;
    row.Id = ids ? static_cast<int>(ids->GetComponent(r, 0)) : static_cast<int>(r);
    row.Color = colors ? colors->GetValue(r) : std::string("#808080");
    row.Cells = cells ? static_cast<long long>(cells->GetComponent(r, 0)) : 0;
    row.Share = shares ? shares->GetComponent(r, 0) : 0.0;
    for (vtkDataArray* column : columns)
    {
      row.Means.push_back(column->GetComponent(r, 0));
    }
    t.Rows.push_back(std::move(row));
  }
  return t;
}

bool ClusterTable::WriteCsv(const std::string& path, std::string& error) const
{
  std::ostringstream out;
  out << "Cluster,Color,Cells,Share";
  for (const std::string& title : this->Columns)
  {
    out << ",\"" << title << "\"";
  }
  out << "\n" << std::setprecision(9);
  for (const ClusterTableRow& row : this->Rows)
  {
    out << row.Id << "," << row.Color << "," << row.Cells << "," << row.Share;
    for (double mean : row.Means)
    {
      out << "," << mean;
    }
    out << "\n";
  }
  std::ofstream file(path, std::ios::binary);
  file << out.str();
  file.close();
  if (!file)
  {
    error = path + ": cannot be written";
    return false;
  }
  return true;
}

} // namespace viewer
} // namespace terroir

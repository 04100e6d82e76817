#include "TerroirCommandSupport.h"

#include "TerroirApp.h"
#include "TerroirOverlayPlugin.h"

#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"
#include "vtkTerroirSolarIllumination.h"
#include "vtkTerroirTemperature.h"
#include "vtkXMLPolyDataWriter.h"

#include "ClimateTable.h"
#include "TerroirSafeOutput.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <dlfcn.h>
#include <filesystem>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace terroir
{
namespace app
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

/// Sets the temperature filter from the command line's temperature settings. The default
/// climate is an illustrative temperate year, not the site's (on Sagehen Creek it gives July
/// about 6 °C where the station at 1,930 m records about 16 °C): a run on it says so on stderr.
void ApplyTemperature(const terroir::app::TemperatureSettings& t, vtkTerroirTemperature* filter)
{
  const terroir::app::TemperatureSettings defaults;
  if (t.Monthly.empty() && t.ClimateFile.empty() && t.Coldest == defaults.Coldest &&
    t.Warmest == defaults.Warmest && t.LapseRate == defaults.LapseRate)
  {
    char note[320];
    std::snprintf(note,
      sizeof(note),
      "the temperatures come from a placeholder climate (sea level %.3g \xc2\xb0"
      "C in the coldest month, %.3g \xc2\xb0"
      "C in the warmest, %.3g \xc2\xb0"
      "C/km), not this site's: give --coldest/--warmest, --monthly or --climate FILE",
      t.Coldest,
      t.Warmest,
      t.LapseRate);
    AddNote(note);
  }
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

double FieldNumber(vtkImageData* image, const char* name)
{
  vtkDataArray* a = vtkDataArray::SafeDownCast(image->GetFieldData()->GetAbstractArray(name));
  return a && a->GetNumberOfTuples() > 0 ? a->GetComponent(0, 0) : std::nan("");
}

std::string FieldText(vtkImageData* image, const char* name)
{
  auto* a = vtkStringArray::SafeDownCast(image->GetFieldData()->GetAbstractArray(name));
  return a && a->GetNumberOfValues() > 0 ? a->GetValue(0) : std::string();
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

namespace
{
/// Overlay batches open on this thread (OverlayBatch).
thread_local int OverlayBatchDepth = 0;
/// This thread's view holds a window (an overlay was written in the open batch).
thread_local bool OverlayViewHeld = false;

/// A symbol of the overlay module (TerroirOverlayPlugin.cxx); throws when it is missing.
void* OverlaySymbol(const char* symbol)
{
  return LoadPluginSymbol(
    TERROIR_OVERLAY_PLUGIN_NAME, symbol, "TERROIR_OVERLAY_PLUGIN", "PNG overlays");
}

void ReleaseOverlayView()
{
  static const auto release =
    reinterpret_cast<TerroirReleaseOverlaysFunction>(OverlaySymbol(TERROIR_OVERLAY_RELEASE_SYMBOL));
  release();
  OverlayViewHeld = false;
}
} // namespace

/// Loads the overlay module once; throws when it is missing.
TerroirWriteOverlayFunction OverlayWriter()
{
  static const auto writer =
    reinterpret_cast<TerroirWriteOverlayFunction>(OverlaySymbol(TERROIR_OVERLAY_PLUGIN_SYMBOL));
  return writer;
}

OverlayBatch::OverlayBatch()
{
  ++OverlayBatchDepth;
}

OverlayBatch::~OverlayBatch()
{
  if (--OverlayBatchDepth == 0 && OverlayViewHeld)
  {
    ReleaseOverlayView();
  }
}

void WriteOverlay(vtkImageData* image,
  const std::string& array,
  int component,
  const std::string& preset,
  const std::string& title,
  const std::string& path,
  bool overwrite,
  bool map)
{
  const double t0 = Now();
  terroir::app::CheckWritable({ path }, overwrite);
  const char* error = OverlayWriter()(
    image, array.c_str(), component, preset.c_str(), title.c_str(), path.c_str(), map ? 1 : 0);
  // Outside a batch the view goes with its window; in one, the batch releases it.
  OverlayViewHeld = true;
  if (OverlayBatchDepth == 0)
  {
    ReleaseOverlayView();
  }
  if (error)
  {
    throw Failure(path + ": " + error);
  }
  // The first overlay of a batch also loads the overlay module, opens the X display and
  // builds the surface; the others reuse them.
  RecordWrittenFile(path, "png", Now() - t0);
}

OverlayWriterFunction CommandOverlayWriter(const CommandLine& c)
{
  const bool overwrite = c.Overwrite;
  return [overwrite](vtkImageData* image,
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
    WriteOverlay(image, array, 0, preset, title, path, overwrite, map);
  };
}

void WriteVTP(vtkPolyData* data, const std::string& path)
{
  const std::string temporary = TemporaryNameFor(path);
  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetInputData(data);
  writer->SetFileName(temporary.c_str());
  writer->SetDataModeToAppended();
  if (writer->Write() != 1)
  {
    DiscardTemporary(temporary);
    throw Failure(path + ": cannot be written");
  }
  std::string error;
  if (!CommitTemporary(temporary, path, error))
  {
    throw Failure(path + ": " + error);
  }
}

} // namespace app
} // namespace terroir

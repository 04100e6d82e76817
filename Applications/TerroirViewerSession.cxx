// The model of `terroir view` (TerroirViewerSession.h, inside in TerroirViewerSessionPrivate.h):
// running one filter with progress and errors observed, the session's life and accessors, and
// taking a terrain.
#include "TerroirViewerSessionPrivate.h"

#include "vtkAlgorithm.h"
#include "vtkCallbackCommand.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"

#include "vtkTerroirClimateReader.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirWaterFlow.h"

#include "TemperatureLapseRate.h"

#include <cmath>
#include <fstream>
#include <iomanip>

namespace terroir
{
namespace viewer
{
namespace
{
/// Progress observer of a filter: the job's progress from the filter's.
void OnFilterProgress(vtkObject*, unsigned long, void* clientData, void* callData)
{
  auto* monitor = static_cast<JobMonitor*>(clientData);
  const double p = callData ? *static_cast<double*>(callData) : 0.0;
  if (monitor->Progress)
  {
    monitor->Progress->store(monitor->Start + monitor->Share * std::max(0.0, std::min(1.0, p)));
  }
}

/// Error observer of a filter: keeps the first message.
void OnFilterError(vtkObject*, unsigned long, void* clientData, void* callData)
{
  auto* monitor = static_cast<JobMonitor*>(clientData);
  if (monitor->Error.empty() && callData)
  {
    monitor->Error = static_cast<const char*>(callData);
  }
}
} // namespace

bool RunFilter(vtkAlgorithm* filter, JobMonitor& monitor, double start, double share)
{
  monitor.Start = start;
  monitor.Share = share;
  vtkNew<vtkCallbackCommand> progress;
  progress->SetCallback(OnFilterProgress);
  progress->SetClientData(&monitor);
  vtkNew<vtkCallbackCommand> error;
  error->SetCallback(OnFilterError);
  error->SetClientData(&monitor);
  const unsigned long p = filter->AddObserver(vtkCommand::ProgressEvent, progress);
  const unsigned long e = filter->AddObserver(vtkCommand::ErrorEvent, error);
  filter->Update();
  filter->RemoveObserver(p);
  filter->RemoveObserver(e);
  if (monitor.Error.empty() && filter->GetErrorCode() != 0)
  {
    monitor.Error = std::string(filter->GetClassName()) + " failed";
  }
  return monitor.Error.empty();
}

//------------------------------------------------------------------------------
ViewerSession::ViewerSession()
  : Impl(new Internals)
{
  // The filters' default climate.
  ViewerParameters& p = this->Impl->Params;
  vtkNew<vtkTerroirSoilHumidity> humidity;
  std::copy_n(humidity->GetPrecipitation(), 12, p.Precipitation.begin());
  std::copy_n(humidity->GetPrecipitationIntensity(), 12, p.PrecipitationIntensity.begin());
  vtkNew<vtkTerroirTemperature> temperature;
  p.Coldest = temperature->GetSeaLevelTemperatureColdest();
  p.Warmest = temperature->GetSeaLevelTemperatureWarmest();
  p.LapseRate = temperature->GetLapseRate();
  std::copy_n(temperature->GetMonthlySeaLevelTemperatures(), 12, p.MonthlyTemperatures.begin());
}

bool ViewerSession::LoadClimate(const std::string& path, std::string& error)
{
  vtkNew<vtkTerroirClimateReader> reader;
  reader->SetFileName(path.c_str());
  reader->GlobalWarningDisplayOff(); // the message goes to the window, once
  if (!reader->Read())
  {
    error = reader->GetErrorMessage();
    return false;
  }
  ViewerParameters& p = this->Impl->Params;
  if (reader->HasPrecipitation())
  {
    std::copy_n(reader->GetPrecipitation(), 12, p.Precipitation.begin());
  }
  if (reader->HasPrecipitationIntensity())
  {
    std::copy_n(reader->GetPrecipitationIntensity(), 12, p.PrecipitationIntensity.begin());
  }
  if (reader->HasTemperature())
  {
    std::copy_n(reader->GetTemperature(), 12, p.MonthlyTemperatures.begin());
    p.UseMonthlyTemperatures = true;
  }
  return true;
}

bool ViewerSession::SaveClimate(const std::string& path, std::string& error) const
{
  const ViewerParameters& p = this->Impl->Params;
  double temperature[12];
  std::copy(p.MonthlyTemperatures.begin(), p.MonthlyTemperatures.end(), temperature);
  const bool north = p.Latitude >= 0.0;
  if (!p.UseMonthlyTemperatures)
  {
    terroir::terrain::SeaLevelTemperaturesFromExtremes(
      p.Coldest, p.Warmest, north ? 1 : 7, north ? 7 : 1, temperature);
  }
  std::ofstream out(path, std::ios::binary);
  out << "# terroir view climate (lapse rate " << p.LapseRate << " C/km)\n"
      << "month,precipitation_mm,intensity_mm_per_h,temperature_c\n"
      << std::setprecision(9);
  for (int m = 0; m < 12; ++m)
  {
    out << vtkTerroirTemperature::GetMonthName(m) << "," << p.Precipitation[m] << ","
        << p.PrecipitationIntensity[m] << "," << temperature[m] << "\n";
  }
  out.close();
  if (!out)
  {
    error = path + ": cannot be written";
    return false;
  }
  return true;
}

ViewerSession::~ViewerSession()
{
  if (this->Impl->Running)
  {
    this->Impl->Worker.join();
  }
}

ViewerParameters& ViewerSession::Parameters()
{
  return this->Impl->Params;
}

const ViewerParameters& ViewerSession::Parameters() const
{
  return this->Impl->Params;
}

vtkImageData* ViewerSession::GetTerrain() const
{
  return this->Impl->Terrain;
}

bool ViewerSession::IsGeoreferenced() const
{
  return this->Impl->Georeferenced;
}

void ViewerSession::SetCurrentOverlay(ViewerOverlay overlay)
{
  this->Impl->Current = overlay;
}

ViewerOverlay ViewerSession::GetCurrentOverlay() const
{
  return this->Impl->Current;
}

vtkFloatArray* ViewerSession::GetWater() const
{
  return this->Impl->Water;
}

vtkFloatArray* ViewerSession::GetInfiltration() const
{
  return this->Impl->Infiltration;
}

std::size_t ViewerSession::GetUndoDepth() const
{
  return this->Impl->UndoStack.size();
}

unsigned long ViewerSession::GetWaterVersion() const
{
  return this->Impl->WaterVersion;
}

vtkFloatArray* ViewerSession::GetDisplayedWater() const
{
  const Internals& in = *this->Impl;
  if (in.Erosion && in.ErosionWater)
  {
    return in.ErosionWater; // a live erosion's water (until kept or the terrain changes)
  }
  return in.HavePreview ? in.Preview.Get() : in.Water.Get();
}

unsigned long ViewerSession::GetDisplayedWaterVersion() const
{
  return this->Impl->WaterVersion + this->Impl->FrameVersion + this->Impl->ErosionFrameVersion;
}

long long ViewerSession::GetFlowFrameIteration() const
{
  return this->Impl->HavePreview ? this->Impl->PreviewIteration : 0;
}

long long ViewerSession::GetFlowFramesPublished() const
{
  return this->Impl->FramesPublished.load();
}

long long ViewerSession::GetLastFlowIterations() const
{
  return this->Impl->LastFlowIterations;
}

std::string ViewerSession::GetLastFlowStopReason() const
{
  return this->Impl->LastFlowStopReason;
}

unsigned long ViewerSession::GetInfiltrationVersion() const
{
  return this->Impl->InfiltrationVersion;
}

//------------------------------------------------------------------------------
bool ViewerSession::SetTerrain(vtkImageData* terrain, std::string& error)
{
  Internals& in = *this->Impl;
  this->Wait();
  int dims[3] = { 0, 0, 0 };
  if (terrain)
  {
    terrain->GetDimensions(dims);
  }
  if (!terrain || dims[2] != 1 || dims[0] < 2 || dims[1] < 2)
  {
    error = "the terrain must be a 2-D image of at least 2x2 points";
    return false;
  }
  vtkDataArray* elevation =
    terrain->GetPointData()->GetArray(vtkTerroirGeoreference::ElevationName());
  if (!elevation || elevation->GetNumberOfComponents() != 1)
  {
    error = "the terrain has no one-component 'Elevation' point array";
    return false;
  }
  in.Erosion.reset(); // a live erosion of the old terrain ends
  in.ErosionBed = in.ErosionWater = in.ErosionSediment = in.ErosionVegetation = nullptr;
  ++in.ErosionFrameVersion;
  in.Terrain = vtkSmartPointer<vtkImageData>::New();
  in.Terrain->ShallowCopy(terrain);
  // Our own arrays replace any of the same name the file had.
  in.Terrain->GetPointData()->RemoveArray(vtkTerroirWaterFlow::WaterHeightName());
  in.Terrain->GetPointData()->RemoveArray(vtkTerroirInfiltration::InfiltrationRateName());
  double latLon[2];
  in.Georeferenced = vtkTerroirGeoreference::GetCenterLatLon(in.Terrain, latLon);
  if (in.Georeferenced)
  {
    in.Params.Latitude = latLon[0];
    in.Params.Longitude = latLon[1];
  }
  const vtkIdType n = in.Terrain->GetNumberOfPoints();
  vtkDataArray* mask =
    in.Terrain->GetPointData()->GetArray(vtkTerroirGeoreference::ValidMaskName());
  in.DataCells.assign(static_cast<std::size_t>(n), 0);
  for (vtkIdType k = 0; k < n; ++k)
  {
    in.DataCells[static_cast<std::size_t>(k)] =
      std::isfinite(elevation->GetComponent(k, 0)) && !(mask && mask->GetComponent(k, 0) == 0.0);
  }
  in.Water = vtkSmartPointer<vtkFloatArray>::New();
  in.Water->SetName(vtkTerroirWaterFlow::WaterHeightName());
  in.Water->SetNumberOfValues(n);
  in.Water->FillValue(0.0f);
  in.UndoStack.clear();
  in.InStroke = false;
  in.HavePreview = false;

  vtkNew<vtkTerroirInfiltration> recipe; // no operation: the default recipe
  recipe->SetInputData(in.Terrain);
  JobMonitor monitor;
  if (!RunFilter(recipe, monitor, 0.0, 1.0))
  {
    error = monitor.Error;
    return false;
  }
  in.Infiltration = vtkSmartPointer<vtkFloatArray>::New();
  in.Infiltration->DeepCopy(
    recipe->GetOutput()->GetPointData()->GetArray(vtkTerroirInfiltration::InfiltrationRateName()));
  in.Infiltration->SetName(vtkTerroirInfiltration::InfiltrationRateName());
  return true;
}

} // namespace viewer
} // namespace terroir

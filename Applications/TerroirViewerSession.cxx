#include "TerroirViewerSession.h"

#include "vtkAlgorithm.h"
#include "vtkCallbackCommand.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkStringArray.h"
#include "vtkTable.h"

#include "vtkTerroirFloodFill.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirInfiltration.h"
#include "vtkTerroirKMeans.h"
#include "vtkTerroirSlope.h"
#include "vtkTerroirSoilHumidity.h"
#include "vtkTerroirSolarIllumination.h"
#include "vtkTerroirTemperature.h"
#include "vtkTerroirWaterFlow.h"

#include "SolarPosition.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <thread>

namespace terroir
{
namespace viewer
{
namespace
{
/// Progress and errors of the filters of one job.
struct JobMonitor
{
  std::atomic<double>* Progress = nullptr;
  double Start = 0.0; ///< share of the job done before this filter
  double Share = 1.0; ///< share of the job this filter takes
  std::string Error;
};

void OnFilterProgress(vtkObject*, unsigned long, void* clientData, void* callData)
{
  auto* monitor = static_cast<JobMonitor*>(clientData);
  const double p = callData ? *static_cast<double*>(callData) : 0.0;
  if (monitor->Progress)
  {
    monitor->Progress->store(monitor->Start + monitor->Share * std::max(0.0, std::min(1.0, p)));
  }
}

void OnFilterError(vtkObject*, unsigned long, void* clientData, void* callData)
{
  auto* monitor = static_cast<JobMonitor*>(clientData);
  if (monitor->Error.empty() && callData)
  {
    monitor->Error = static_cast<const char*>(callData);
  }
}

/// Updates `filter` while reporting progress in [start, start + share] of the job and keeping
/// its first error (observed, so that it is not printed from the worker thread). Returns false
/// on failure, with `monitor.Error` set.
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

/// Hemisphere of the temperature model from a latitude.
int HemisphereOf(double latitude)
{
  return latitude < 0.0 ? vtkTerroirTemperature::South : vtkTerroirTemperature::North;
}

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

vtkDataArray* OverlayResult::GetValues() const
{
  return this->Output && !this->ArrayName.empty()
    ? this->Output->GetPointData()->GetArray(this->ArrayName.c_str())
    : nullptr;
}

//------------------------------------------------------------------------------
struct ViewerSession::Internals
{
  vtkSmartPointer<vtkImageData> Terrain;
  bool Georeferenced = false;
  ViewerParameters Params;
  ViewerOverlay Current = ViewerOverlay::None;
  vtkSmartPointer<vtkFloatArray> Water;
  unsigned long WaterVersion = 0;
  vtkSmartPointer<vtkFloatArray> Infiltration;
  unsigned long InfiltrationVersion = 0;

  /// One undoable change of the water or the infiltration map: the changed cells and their
  /// previous values, or (Whole) the whole previous array.
  struct Change
  {
    bool IsWater = true;
    bool Whole = false;
    std::vector<vtkIdType> Cells;
    std::vector<float> Values;
  };
  std::vector<Change> UndoStack;
  bool InStroke = false;
  std::vector<float> StrokeBefore;

  // ---- water-flow frames (written by the worker, taken by Pump) ---------------------------
  std::mutex FrameMutex;
  vtkSmartPointer<vtkFloatArray> Frame; ///< the worker's latest frame
  long long FrameIteration = 0;
  long long FrameSerial = 0; ///< frames written (under FrameMutex)
  long long FrameTaken = 0;  ///< frames Pump has shown
  std::atomic<long long> FramesPublished{ 0 };
  vtkSmartPointer<vtkFloatArray> Preview; ///< the frame on display while a flow runs
  bool HavePreview = false;
  long long PreviewIteration = 0;
  unsigned long FrameVersion = 0;

  // ---- worker ----------------------------------------------------------------------------
  /// A job's result, handed from the worker to the window's thread.
  struct JobResult
  {
    bool IsWaterFlow = false;
    OverlayResult Overlay;
    vtkSmartPointer<vtkFloatArray> Water; ///< water flow: the new state
    std::string Error;
  };
  using Job = std::function<JobResult(std::atomic<double>&)>;
  struct QueuedJob
  {
    Job Work;
    std::string Label;
  };
  std::thread Worker;
  bool Running = false;                ///< a Worker thread exists (joined by Pump)
  std::atomic<bool> Finished{ false }; ///< the worker's job returned
  std::mutex Mutex;
  std::condition_variable Done;
  JobResult Result; ///< written by the worker before Finished
  std::atomic<double> Progress{ 0.0 };
  std::string Label;
  std::unique_ptr<QueuedJob> PendingOverlay;
  std::unique_ptr<QueuedJob> PendingFlow;
  unsigned long Generation = 0; ///< of the latest overlay request
  bool HaveOverlay = false;
  OverlayResult Latest;
  std::string LastError;

  void Start(std::unique_ptr<QueuedJob> job)
  {
    this->Running = true;
    this->Finished = false;
    this->Progress = 0.0;
    this->Label = job->Label;
    this->Worker = std::thread(
      [this, work = std::move(job->Work)]()
      {
        JobResult r = work(this->Progress);
        {
          std::lock_guard<std::mutex> lock(this->Mutex);
          this->Result = std::move(r);
          this->Finished = true;
        }
        this->Done.notify_all();
      });
  }

  /// Starts `job` now, or keeps it in `slot` (replacing an older one) while the worker runs.
  void Enqueue(std::unique_ptr<QueuedJob> job, std::unique_ptr<QueuedJob>& slot)
  {
    if (this->Running)
    {
      slot = std::move(job);
    }
    else
    {
      this->Start(std::move(job));
    }
  }

  /// An input for a job: the terrain's arrays shared (never written), the water and
  /// infiltration arrays copied (the window's thread changes them in place).
  vtkSmartPointer<vtkImageData> Snapshot() const
  {
    auto copy = vtkSmartPointer<vtkImageData>::New();
    copy->ShallowCopy(this->Terrain);
    for (vtkFloatArray* a : { this->Water.Get(), this->Infiltration.Get() })
    {
      vtkNew<vtkFloatArray> own;
      own->DeepCopy(a);
      copy->GetPointData()->AddArray(own);
    }
    return copy;
  }

  static std::vector<float> CopyOf(vtkFloatArray* a)
  {
    return std::vector<float>(a->GetPointer(0), a->GetPointer(0) + a->GetNumberOfValues());
  }

  /// Pushes the change of the water (or the infiltration map) from `before` to its current
  /// values on the undo stack, and counts the version; returns the number of changed cells
  /// (0: nothing pushed). Values compare by their bits, so that Undo gives the same bytes.
  long long Record(bool water, std::vector<float>&& before)
  {
    vtkFloatArray* a = water ? this->Water.Get() : this->Infiltration.Get();
    const float* now = a->GetPointer(0);
    const std::size_t n = before.size();
    Change c;
    c.IsWater = water;
    for (std::size_t k = 0; k < n; ++k)
    {
      if (std::memcmp(now + k, before.data() + k, sizeof(float)) != 0)
      {
        c.Cells.push_back(static_cast<vtkIdType>(k));
        c.Values.push_back(before[k]);
      }
    }
    const long long changed = static_cast<long long>(c.Cells.size());
    if (changed == 0)
    {
      return 0;
    }
    if (3 * c.Cells.size() > n) // a list of most cells takes more than the whole array
    {
      c.Whole = true;
      c.Cells.clear();
      c.Values = std::move(before);
    }
    this->UndoStack.push_back(std::move(c));
    a->Modified();
    ++(water ? this->WaterVersion : this->InfiltrationVersion);
    return changed;
  }

  /// The brush rate, clamped to what vtkTerroirInfiltration accepts (mm/h).
  float BrushRate() const
  {
    return static_cast<float>(
      std::max(0.0, std::min(vtkTerroirInfiltration::GetMaximumRate(), this->Params.BrushRate)));
  }

  /// 1 where the cell has data (finite elevation, valid mask); set by SetTerrain.
  std::vector<unsigned char> DataCells;
  bool HasData(vtkIdType k) const { return this->DataCells[static_cast<std::size_t>(k)] != 0; }
};

ViewerSession::ViewerSession()
  : Impl(new Internals)
{
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
  return this->Impl->HavePreview ? this->Impl->Preview.Get() : this->Impl->Water.Get();
}

unsigned long ViewerSession::GetDisplayedWaterVersion() const
{
  return this->Impl->WaterVersion + this->Impl->FrameVersion;
}

long long ViewerSession::GetFlowFrameIteration() const
{
  return this->Impl->HavePreview ? this->Impl->PreviewIteration : 0;
}

long long ViewerSession::GetFlowFramesPublished() const
{
  return this->Impl->FramesPublished.load();
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

//------------------------------------------------------------------------------
namespace
{
/// The overlay's filters on `input` (a snapshot: terrain, WaterHeight, InfiltrationRate).
OverlayResult ComputeOverlayOn(vtkImageData* input,
  ViewerOverlay overlay,
  const ViewerParameters& p,
  std::atomic<double>& progress)
{
  OverlayResult r;
  r.Overlay = overlay;
  JobMonitor monitor;
  monitor.Progress = &progress;
  const int month = std::max(1, std::min(12, p.Month));
  switch (overlay)
  {
    case ViewerOverlay::None:
      r.Output = input;
      return r;
    case ViewerOverlay::Water:
      r.ArrayName = vtkTerroirWaterFlow::WaterHeightName();
      r.Preset = "Water";
      r.Output = input;
      return r;
    case ViewerOverlay::Slope:
    {
      vtkNew<vtkTerroirSlope> slope;
      slope->SetInputData(input);
      if (RunFilter(slope, monitor, 0.0, 1.0))
      {
        r.Output = slope->GetOutput();
      }
      r.ArrayName = vtkTerroirSlope::SlopeName();
      r.Preset = "Slope";
      break;
    }
    case ViewerOverlay::Illumination:
    case ViewerOverlay::SunHours:
    {
      vtkNew<vtkTerroirSolarIllumination> sun;
      sun->SetInputData(input);
      ConfigureSun(sun, p);
      const bool instant = overlay == ViewerOverlay::Illumination;
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
      break;
    }
    case ViewerOverlay::Temperature:
    {
      vtkNew<vtkTerroirTemperature> temperature;
      temperature->SetInputData(input);
      temperature->SetHemisphere(HemisphereOf(p.Latitude));
      if (RunFilter(temperature, monitor, 0.0, 1.0))
      {
        r.Output = temperature->GetOutput();
      }
      r.ArrayName = vtkTerroirTemperature::TemperatureName();
      r.Component = month - 1;
      r.Preset = "Temperature";
      break;
    }
    case ViewerOverlay::Humidity:
    {
      vtkNew<vtkTerroirSoilHumidity> humidity;
      humidity->SetInputData(input);
      humidity->ComputeWeightedSoilHumidityOff();
      humidity->ComputeStandingWaterOff();
      if (RunFilter(humidity, monitor, 0.0, 1.0))
      {
        r.Output = humidity->GetOutput();
      }
      r.ArrayName = vtkTerroirSoilHumidity::SoilHumidityName();
      r.Component = month - 1;
      r.Preset = "Humidity";
      break;
    }
    case ViewerOverlay::Clusters:
    {
      vtkNew<vtkTerroirSlope> slope;
      slope->SetInputData(input);
      vtkNew<vtkTerroirTemperature> temperature;
      temperature->SetInputConnection(slope->GetOutputPort());
      temperature->SetHemisphere(HemisphereOf(p.Latitude));
      vtkNew<vtkTerroirSolarIllumination> sun;
      sun->SetInputConnection(temperature->GetOutputPort());
      ConfigureSun(sun, p);
      sun->SetModeToMonthly();
      vtkNew<vtkTerroirKMeans> kmeans;
      kmeans->SetInputConnection(sun->GetOutputPort());
      kmeans->SetNumberOfClusters(std::max(1, std::min(64, p.Clusters)));
      if (RunFilter(slope, monitor, 0.0, 0.05) && RunFilter(temperature, monitor, 0.05, 0.05) &&
        RunFilter(sun, monitor, 0.1, 0.8) && RunFilter(kmeans, monitor, 0.9, 0.1))
      {
        r.Output = kmeans->GetOutput();
        r.Table = kmeans->GetClusterTable();
      }
      r.ArrayName = vtkTerroirKMeans::ClusterIdName();
      r.Preset = "Clusters";
      break;
    }
    case ViewerOverlay::Count:
      break;
  }
  r.Error = monitor.Error;
  if (r.Error.empty() && !r.GetValues())
  {
    r.Error = std::string("the ") + OverlayName(overlay) + " overlay produced no '" + r.ArrayName +
      "' array";
  }
  return r;
}
} // namespace

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
void ViewerSession::RequestOverlay()
{
  Internals& in = *this->Impl;
  const ViewerOverlay overlay = in.Current;
  const ViewerParameters params = in.Params;
  const unsigned long generation = ++in.Generation;
  auto job = std::make_unique<Internals::QueuedJob>();
  job->Label = std::string("Computing ") + OverlayTitle(overlay);
  std::transform(job->Label.begin() + 10,
    job->Label.end(),
    job->Label.begin() + 10,
    [](char c) { return static_cast<char>(std::tolower(static_cast<unsigned char>(c))); });
  if (overlay == ViewerOverlay::None || overlay == ViewerOverlay::Water)
  {
    // Nothing to compute: answer at once, on this thread.
    in.PendingOverlay.reset();
    in.Latest = this->ComputeOverlay(overlay, params);
    in.Latest.Generation = generation;
    in.HaveOverlay = true;
    return;
  }
  // The filters read a snapshot taken now, not the state when the job starts.
  vtkSmartPointer<vtkImageData> input = in.Snapshot();
  job->Work = [overlay, params, generation, input](std::atomic<double>& progress)
  {
    Internals::JobResult result;
    result.Overlay = ComputeOverlayOn(input, overlay, params, progress);
    result.Overlay.Generation = generation;
    result.Error = result.Overlay.Error;
    return result;
  };
  in.Enqueue(std::move(job), in.PendingOverlay);
}

void ViewerSession::RequestWaterFlow()
{
  Internals& in = *this->Impl;
  vtkSmartPointer<vtkImageData> input = in.Snapshot();
  const ViewerParameters params = in.Params;
  auto job = std::make_unique<Internals::QueuedJob>();
  job->Label = "Computing water flow";
  Internals* self = &in;
  job->Work = [input, params, self](std::atomic<double>& progress)
  {
    Internals::JobResult result;
    result.IsWaterFlow = true;
    self->FramesPublished = 0;
    JobMonitor monitor;
    monitor.Progress = &progress;
    const int month = std::max(1, std::min(12, params.Month));
    vtkNew<vtkTerroirSoilHumidity> humidity;
    humidity->SetInputData(input);
    humidity->ComputeWeightedSoilHumidityOff();
    if (!RunFilter(humidity, monitor, 0.0, 0.1))
    {
      result.Error = monitor.Error;
      return result;
    }
    // The month's rain that the soil did not take, plus the lakes already there (m -> mm).
    auto start = vtkSmartPointer<vtkImageData>::New();
    start->ShallowCopy(humidity->GetOutput());
    vtkDataArray* standing =
      start->GetPointData()->GetArray(vtkTerroirSoilHumidity::StandingWaterName());
    vtkDataArray* lakes = input->GetPointData()->GetArray(vtkTerroirWaterFlow::WaterHeightName());
    vtkNew<vtkFloatArray> water;
    water->DeepCopy(standing);
    water->SetName(vtkTerroirSoilHumidity::StandingWaterName());
    for (vtkIdType k = 0; k < water->GetNumberOfTuples(); ++k)
    {
      const double v = water->GetComponent(k, month - 1);
      if (std::isfinite(v))
      {
        water->SetComponent(k, month - 1, v + 1000.0 * lakes->GetComponent(k, 0));
      }
    }
    start->GetPointData()->AddArray(water);
    vtkNew<vtkTerroirWaterFlow> flow;
    flow->SetInputData(start);
    flow->SetWaterSourceToStandingWaterMonth();
    flow->SetMonth(month);
    flow->SetMaximumIterations(std::max(1, params.FlowIterations));
    // Frames for the window while the run goes on: the state every FlowFrameInterval
    // iterations, no-data cells dry.
    struct FrameSink
    {
      Internals* Self;
      vtkTerroirWaterFlow* Flow;
    } sink{ self, flow };
    vtkNew<vtkCallbackCommand> watch;
    watch->SetClientData(&sink);
    watch->SetCallback(
      [](vtkObject*, unsigned long, void* clientData, void* callData)
      {
        auto* f = static_cast<FrameSink*>(clientData);
        auto frame = vtkSmartPointer<vtkFloatArray>::New();
        if (!callData || !f->Flow->GetCurrentWaterHeight(frame))
        {
          return;
        }
        float* v = frame->GetPointer(0);
        for (vtkIdType k = 0; k < frame->GetNumberOfValues(); ++k)
        {
          v[k] = std::isfinite(v[k]) ? v[k] : 0.0f;
        }
        std::lock_guard<std::mutex> lock(f->Self->FrameMutex);
        f->Self->Frame = frame;
        f->Self->FrameIteration = *static_cast<vtkIdType*>(callData);
        ++f->Self->FrameSerial;
        ++f->Self->FramesPublished;
      });
    if (params.FlowFrameInterval > 0)
    {
      flow->SetIterationEventInterval(params.FlowFrameInterval);
      flow->AddObserver(vtkTerroirWaterFlow::IterationEvent, watch);
    }
    if (!RunFilter(flow, monitor, 0.1, 0.9))
    {
      result.Error = monitor.Error;
      return result;
    }
    result.Water = vtkSmartPointer<vtkFloatArray>::New();
    result.Water->DeepCopy(
      flow->GetOutput()->GetPointData()->GetArray(vtkTerroirWaterFlow::WaterHeightName()));
    // No-data cells hold no water.
    for (vtkIdType k = 0; k < result.Water->GetNumberOfValues(); ++k)
    {
      if (!std::isfinite(result.Water->GetValue(k)))
      {
        result.Water->SetValue(k, 0.0f);
      }
    }
    result.Water->SetName(vtkTerroirWaterFlow::WaterHeightName());
    return result;
  };
  in.Enqueue(std::move(job), in.PendingFlow);
}

bool ViewerSession::Pump()
{
  Internals& in = *this->Impl;
  bool changed = false;
  {
    // The running flow's newest frame goes on display.
    std::lock_guard<std::mutex> lock(in.FrameMutex);
    if (in.FrameSerial != in.FrameTaken && in.Frame)
    {
      if (!in.Preview)
      {
        in.Preview = vtkSmartPointer<vtkFloatArray>::New();
      }
      in.Preview->DeepCopy(in.Frame);
      in.Preview->SetName(vtkTerroirWaterFlow::WaterHeightName());
      in.PreviewIteration = in.FrameIteration;
      in.FrameTaken = in.FrameSerial;
      in.HavePreview = true;
      ++in.FrameVersion;
      changed = true;
    }
  }
  if (in.Running && in.Finished)
  {
    in.Worker.join();
    in.Running = false;
    Internals::JobResult result;
    {
      std::lock_guard<std::mutex> lock(in.Mutex);
      result = std::move(in.Result);
    }
    if (!result.Error.empty())
    {
      in.LastError = result.Error;
    }
    if (result.IsWaterFlow)
    {
      if (result.Water && result.Water->GetNumberOfValues() == in.Water->GetNumberOfValues())
      {
        std::vector<float> before = Internals::CopyOf(in.Water);
        std::memcpy(
          in.Water->GetPointer(0), result.Water->GetPointer(0), before.size() * sizeof(float));
        in.Record(true, std::move(before));
      }
      // The frames end with the run: its result (or, on error, the state) is on display.
      in.HavePreview = false;
      ++in.FrameVersion;
      changed = true;
    }
    else if (result.Overlay.Generation == in.Generation)
    {
      // Older requests are superseded by a newer one that is queued or answered.
      in.Latest = std::move(result.Overlay);
      in.HaveOverlay = true;
      changed = true;
    }
  }
  if (!in.Running)
  {
    // Water first: an overlay asked after it should see its result... but the overlay's
    // snapshot is already taken, so order them as they were asked: flow jobs are rarer and
    // the overlay of the new water is asked again by the window when the flow lands.
    if (in.PendingOverlay)
    {
      in.Start(std::move(in.PendingOverlay));
    }
    else if (in.PendingFlow)
    {
      in.Start(std::move(in.PendingFlow));
    }
  }
  return changed;
}

bool ViewerSession::TakeOverlay(OverlayResult& result)
{
  Internals& in = *this->Impl;
  if (!in.HaveOverlay)
  {
    return false;
  }
  result = in.Latest;
  in.HaveOverlay = false;
  return true;
}

bool ViewerSession::IsIdle() const
{
  const Internals& in = *this->Impl;
  return !in.Running && !in.PendingOverlay && !in.PendingFlow;
}

void ViewerSession::Wait()
{
  Internals& in = *this->Impl;
  while (!this->IsIdle())
  {
    if (in.Running)
    {
      std::unique_lock<std::mutex> lock(in.Mutex);
      in.Done.wait(lock, [&in]() { return in.Finished.load(); });
    }
    this->Pump();
  }
}

double ViewerSession::GetProgress() const
{
  return this->Impl->Running ? this->Impl->Progress.load() : 1.0;
}

std::string ViewerSession::GetProgressLabel() const
{
  return this->Impl->Running ? this->Impl->Label : std::string();
}

std::string ViewerSession::TakeError()
{
  std::string e;
  e.swap(this->Impl->LastError);
  return e;
}

//------------------------------------------------------------------------------
bool ViewerSession::FloodFillAt(int i, int j, std::string& error)
{
  Internals& in = *this->Impl;
  if (!in.Terrain)
  {
    error = "no terrain";
    return false;
  }
  int dims[3];
  in.Terrain->GetDimensions(dims);
  if (i < 0 || j < 0 || i >= dims[0] || j >= dims[1])
  {
    error = "cell (" + std::to_string(i) + ", " + std::to_string(j) + ") lies outside the terrain";
    return false;
  }
  const vtkIdType k = static_cast<vtkIdType>(j) * dims[0] + i;
  vtkPointData* pd = in.Terrain->GetPointData();
  const double z = pd->GetArray(vtkTerroirGeoreference::ElevationName())->GetComponent(k, 0);
  vtkDataArray* mask = pd->GetArray(vtkTerroirGeoreference::ValidMaskName());
  if (!std::isfinite(z) || (mask && mask->GetComponent(k, 0) == 0.0))
  {
    error = "cell (" + std::to_string(i) + ", " + std::to_string(j) + ") has no data";
    return false;
  }
  auto input = vtkSmartPointer<vtkImageData>::New();
  input->ShallowCopy(in.Terrain);
  // The depression that holds the cell, filled to its spill level: water poured in rises no
  // higher (above it, it runs out over the pass), and none on a slope stays.
  vtkNew<vtkTerroirFloodFill> depressions;
  depressions->SetInputData(input);
  depressions->SetModeToFillDepressions();
  depressions->SetIncludeFlatSurfaces(false);
  depressions->SetMinimumArea(0.0);
  JobMonitor monitor;
  if (!RunFilter(depressions, monitor, 0.0, 0.5))
  {
    error = monitor.Error;
    return false;
  }
  vtkImageData* filled = depressions->GetOutput();
  vtkDataArray* body = filled->GetPointData()->GetArray(vtkTerroirFloodFill::WaterBodyName());
  vtkDataArray* levels =
    filled->GetFieldData()->GetArray(vtkTerroirFloodFill::WaterBodyLevelName());
  const int id = body ? static_cast<int>(body->GetComponent(k, 0)) : 0;
  if (id <= 0 || !levels || id > levels->GetNumberOfTuples())
  {
    error = "cell (" + std::to_string(i) + ", " + std::to_string(j) +
      ") is not in a depression: water poured there runs off";
    return false;
  }
  const double spill = levels->GetComponent(id - 1, 0);
  const double level = std::min(z + in.Params.LakeDepth, spill);
  vtkSmartPointer<vtkDataArray> depth;
  if (level >= spill)
  {
    // The whole depression, as FillDepressions filled it.
    vtkDataArray* full = filled->GetPointData()->GetArray(vtkTerroirFloodFill::WaterDepthName());
    depth.TakeReference(vtkFloatArray::New());
    depth->SetNumberOfTuples(body->GetNumberOfTuples());
    for (vtkIdType m = 0; m < body->GetNumberOfTuples(); ++m)
    {
      depth->SetComponent(
        m, 0, static_cast<int>(body->GetComponent(m, 0)) == id ? full->GetComponent(m, 0) : 0.0);
    }
  }
  else
  {
    // Below the spill level every path out of the depression climbs above the level, so the
    // seed's fill (cells connected to the click at or below the level) stays inside it.
    vtkNew<vtkTerroirFloodFill> flood;
    flood->SetInputData(input);
    flood->SetModeToSeeds();
    flood->AddSeedCell(i, j, level);
    if (!RunFilter(flood, monitor, 0.5, 0.5))
    {
      error = monitor.Error;
      return false;
    }
    depth = flood->GetOutput()->GetPointData()->GetArray(vtkTerroirFloodFill::WaterDepthName());
  }
  if (!depth || depth->GetNumberOfTuples() != in.Water->GetNumberOfTuples())
  {
    error = "the flood fill gave no WaterDepth";
    return false;
  }
  std::vector<float> before = Internals::CopyOf(in.Water);
  float* w = in.Water->GetPointer(0);
  for (vtkIdType m = 0; m < in.Water->GetNumberOfValues(); ++m)
  {
    const double d = depth->GetComponent(m, 0);
    if (std::isfinite(d) && d > w[m])
    {
      w[m] = static_cast<float>(d);
    }
  }
  in.Record(true, std::move(before));
  return true;
}

bool ViewerSession::Undo()
{
  Internals& in = *this->Impl;
  if (in.InStroke)
  {
    this->EndStroke();
  }
  if (in.UndoStack.empty())
  {
    return false;
  }
  const Internals::Change& c = in.UndoStack.back();
  vtkFloatArray* a = c.IsWater ? in.Water.Get() : in.Infiltration.Get();
  float* values = a->GetPointer(0);
  if (c.Whole)
  {
    std::memcpy(values, c.Values.data(), c.Values.size() * sizeof(float));
  }
  else
  {
    for (std::size_t k = 0; k < c.Cells.size(); ++k)
    {
      values[c.Cells[k]] = c.Values[k];
    }
  }
  a->Modified();
  ++(c.IsWater ? in.WaterVersion : in.InfiltrationVersion);
  in.UndoStack.pop_back();
  return true;
}

void ViewerSession::BeginStroke()
{
  Internals& in = *this->Impl;
  if (in.InStroke)
  {
    this->EndStroke();
  }
  if (in.Infiltration)
  {
    in.StrokeBefore = Internals::CopyOf(in.Infiltration);
    in.InStroke = true;
  }
}

long long ViewerSession::EndStroke()
{
  Internals& in = *this->Impl;
  if (!in.InStroke)
  {
    return 0;
  }
  in.InStroke = false;
  return in.Record(false, std::move(in.StrokeBefore));
}

int ViewerSession::PaintInfiltration(int i, int j)
{
  return this->PaintInfiltrationAlong(i, j, i, j);
}

int ViewerSession::PaintInfiltrationAlong(double i0, double j0, double i1, double j1)
{
  Internals& in = *this->Impl;
  if (!in.Terrain || !std::isfinite(i0) || !std::isfinite(j0) || !std::isfinite(i1) ||
    !std::isfinite(j1))
  {
    return 0;
  }
  const bool alone = !in.InStroke;
  if (alone)
  {
    this->BeginStroke();
  }
  int dims[3];
  in.Terrain->GetDimensions(dims);
  const double r = std::max(0.0, std::min(1000.0, in.Params.BrushRadius));
  const float rate = in.BrushRate();
  // Every cell within r of the segment (a capsule), clipped to the grid.
  const double di = i1 - i0, dj = j1 - j0;
  const double length2 = di * di + dj * dj;
  const double lo[2] = { std::max(0.0, std::ceil(std::min(i0, i1) - r)),
    std::max(0.0, std::ceil(std::min(j0, j1) - r)) };
  const double hi[2] = { std::min(dims[0] - 1.0, std::floor(std::max(i0, i1) + r)),
    std::min(dims[1] - 1.0, std::floor(std::max(j0, j1) + r)) };
  int painted = 0;
  float* values = in.Infiltration->GetPointer(0);
  for (double jj = lo[1]; jj <= hi[1]; ++jj)
  {
    for (double ii = lo[0]; ii <= hi[0]; ++ii)
    {
      double t = length2 > 0.0 ? ((ii - i0) * di + (jj - j0) * dj) / length2 : 0.0;
      t = std::max(0.0, std::min(1.0, t));
      const double ei = ii - (i0 + t * di), ej = jj - (j0 + t * dj);
      const vtkIdType k = static_cast<vtkIdType>(jj) * dims[0] + static_cast<vtkIdType>(ii);
      if (ei * ei + ej * ej <= r * r && in.HasData(k))
      {
        values[k] = rate;
        ++painted;
      }
    }
  }
  in.Infiltration->Modified();
  if (alone)
  {
    this->EndStroke();
  }
  return painted;
}

long long ViewerSession::FillInfiltration()
{
  Internals& in = *this->Impl;
  if (!in.Terrain)
  {
    return 0;
  }
  if (in.InStroke)
  {
    this->EndStroke();
  }
  std::vector<float> before = Internals::CopyOf(in.Infiltration);
  const float rate = in.BrushRate();
  float* values = in.Infiltration->GetPointer(0);
  for (vtkIdType k = 0; k < in.Infiltration->GetNumberOfValues(); ++k)
  {
    if (in.HasData(k))
    {
      values[k] = rate;
    }
  }
  return in.Record(false, std::move(before));
}

long long ViewerSession::ApplySlopeRule(std::string& error)
{
  Internals& in = *this->Impl;
  if (!in.Terrain)
  {
    error = "no terrain";
    return -1;
  }
  if (in.InStroke)
  {
    this->EndStroke();
  }
  // vtkTerroirInfiltration's rule on a map of ones: 0 marks the cells it applies to.
  auto input = vtkSmartPointer<vtkImageData>::New();
  input->ShallowCopy(in.Terrain);
  vtkNew<vtkTerroirInfiltration> rule;
  rule->SetInputData(input);
  rule->AddFill(1.0);
  rule->AddSlopeRule(std::max(0.0, std::min(90.0, in.Params.SlopeThreshold)));
  JobMonitor monitor;
  if (!RunFilter(rule, monitor, 0.0, 1.0))
  {
    error = monitor.Error;
    return -1;
  }
  vtkDataArray* steep =
    rule->GetOutput()->GetPointData()->GetArray(vtkTerroirInfiltration::InfiltrationRateName());
  if (!steep || steep->GetNumberOfTuples() != in.Infiltration->GetNumberOfTuples())
  {
    error = "the slope rule gave no InfiltrationRate";
    return -1;
  }
  std::vector<float> before = Internals::CopyOf(in.Infiltration);
  float* values = in.Infiltration->GetPointer(0);
  for (vtkIdType k = 0; k < steep->GetNumberOfTuples(); ++k)
  {
    if (steep->GetComponent(k, 0) == 0.0)
    {
      values[k] = 0.0f;
    }
  }
  return in.Record(false, std::move(before));
}

//------------------------------------------------------------------------------
ClusterTable ClusterTable::FromKMeans(vtkTable* table, int month)
{
  ClusterTable t;
  if (!table)
  {
    return t;
  }
  const char* monthName = vtkTerroirTemperature::GetMonthName(std::max(1, std::min(12, month)) - 1);
  const std::string suffix = std::string("_") + (monthName ? monthName : "");
  const std::map<std::string, std::string> shortNames = { { "Slope", "Slope" },
    { "Temperature", "Temp" },
    { "IlluminationHours", "Sun" },
    { "WeightedSoilHumidity", "Humidity" } };
  std::vector<vtkDataArray*> columns;
  for (vtkIdType c = 0; c < table->GetNumberOfColumns(); ++c)
  {
    auto* column = vtkDataArray::SafeDownCast(table->GetColumn(c));
    const std::string name = table->GetColumnName(c) ? table->GetColumnName(c) : "";
    if (!column || name == "ClusterId" || name == "Cells" || name == "Share")
    {
      continue;
    }
    std::string base = name;
    std::string when;
    if (name.size() > suffix.size() &&
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
    {
      base = name.substr(0, name.size() - suffix.size());
      when = std::string(" ") + (monthName ? monthName : "");
    }
    else if (name.find('_') != std::string::npos)
    {
      continue; // another month's component
    }
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
    t.Columns.push_back(title);
    columns.push_back(column);
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

} // namespace viewer
} // namespace terroir

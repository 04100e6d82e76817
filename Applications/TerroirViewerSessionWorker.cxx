// The model of `terroir view` (TerroirViewerSessionPrivate.h): the worker thread's jobs (an
// overlay request, a water flow with its frames), collecting their results, waiting, progress.
#include "TerroirViewerSessionPrivate.h"

#include "vtkCallbackCommand.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkStringArray.h"

#include "vtkTerroirSoilHumidity.h"
#include "vtkTerroirWaterFlow.h"

#include <cctype>
#include <cmath>

namespace terroir
{
namespace viewer
{

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

namespace
{
/// The water-flow input: the terrain with the month's `StandingWater` (or FlowWater mm on
/// every cell with data) plus the lakes already there (m -> mm) in the month's component; in
/// the river-forming mode without the lakes (it fills the depressions itself). Null with the
/// error in `monitor` when the soil filter fails.
vtkSmartPointer<vtkImageData> FlowStart(vtkImageData* input,
  const ViewerParameters& params,
  JobMonitor& monitor)
{
  const int month = std::max(1, std::min(12, params.Month));
  vtkNew<vtkTerroirSoilHumidity> humidity;
  humidity->SetInputData(input);
  humidity->ComputeWeightedSoilHumidityOff();
  ConfigureClimate(humidity, params);
  if (!RunFilter(humidity, monitor, 0.0, 0.1))
  {
    return nullptr;
  }
  auto start = vtkSmartPointer<vtkImageData>::New();
  start->ShallowCopy(humidity->GetOutput());
  vtkDataArray* standing =
    start->GetPointData()->GetArray(vtkTerroirSoilHumidity::StandingWaterName());
  vtkDataArray* lakes = input->GetPointData()->GetArray(vtkTerroirWaterFlow::WaterHeightName());
  vtkNew<vtkFloatArray> water;
  water->DeepCopy(standing);
  water->SetName(vtkTerroirSoilHumidity::StandingWaterName());
  const bool given = !params.FlowRivers && std::isfinite(params.FlowWater);
  for (vtkIdType k = 0; k < water->GetNumberOfTuples(); ++k)
  {
    const double v = water->GetComponent(k, month - 1);
    if (std::isfinite(v))
    {
      const double lake = params.FlowRivers ? 0.0 : 1000.0 * lakes->GetComponent(k, 0);
      water->SetComponent(k, month - 1, (given ? params.FlowWater : v) + lake);
    }
  }
  start->GetPointData()->AddArray(water);
  return start;
}

/// Mode, source, stop rules and iterations of the parameters.
void ConfigureFlow(vtkTerroirWaterFlow* flow, const ViewerParameters& params)
{
  flow->SetMonth(std::max(1, std::min(12, params.Month)));
  flow->SetMaximumIterations(std::max(1, params.FlowIterations));
  flow->SetWaterSourceToStandingWaterMonth();
  flow->SetAutoStopRatio(std::max(0.0, params.FlowStopRatio));
  if (params.FlowRivers)
  {
    flow->SetModeToRivers();
    flow->SetBalanceTolerance(std::max(1e-6, std::min(0.999, params.FlowBalance)));
    if (std::isfinite(params.FlowRainRate))
    {
      flow->SetWaterSourceToConstant(); // RainRate on every cell, no water at the start
      flow->SetInitialWater(0.0);
      flow->SetRainRate(params.FlowRainRate);
    }
  }
}

/// The flow's output water, no-data cells dry, with its iterations and stop reason.
void TakeFlowResult(vtkTerroirWaterFlow* flow,
  vtkSmartPointer<vtkFloatArray>& water,
  long long& iterationsRun,
  std::string& stopReason)
{
  vtkImageData* out = flow->GetOutput();
  water = vtkSmartPointer<vtkFloatArray>::New();
  water->DeepCopy(out->GetPointData()->GetArray(vtkTerroirWaterFlow::WaterHeightName()));
  for (vtkIdType k = 0; k < water->GetNumberOfValues(); ++k)
  {
    if (!std::isfinite(water->GetValue(k)))
    {
      water->SetValue(k, 0.0f);
    }
  }
  water->SetName(vtkTerroirWaterFlow::WaterHeightName());
  vtkFieldData* fd = out->GetFieldData();
  auto* iterations =
    vtkDataArray::SafeDownCast(fd->GetAbstractArray(vtkTerroirWaterFlow::IterationsName()));
  auto* reason =
    vtkStringArray::SafeDownCast(fd->GetAbstractArray(vtkTerroirWaterFlow::StopReasonName()));
  iterationsRun = iterations && iterations->GetNumberOfTuples() > 0
    ? static_cast<long long>(iterations->GetComponent(0, 0))
    : -1;
  stopReason = reason && reason->GetNumberOfValues() > 0 ? reason->GetValue(0) : std::string();
}
} // namespace

void ViewerSession::RequestWaterFlow()
{
  Internals& in = *this->Impl;
  vtkSmartPointer<vtkImageData> input = in.Snapshot();
  const ViewerParameters params = in.Params;
  auto job = std::make_unique<Internals::QueuedJob>();
  job->Label = params.FlowRivers ? "Computing rivers" : "Computing water flow";
  Internals* self = &in;
  job->Work = [input, params, self](std::atomic<double>& progress)
  {
    Internals::JobResult result;
    result.IsWaterFlow = true;
    self->FramesPublished = 0;
    JobMonitor monitor;
    monitor.Progress = &progress;
    vtkSmartPointer<vtkImageData> start = FlowStart(input, params, monitor);
    if (!start)
    {
      result.Error = monitor.Error;
      return result;
    }
    vtkNew<vtkTerroirWaterFlow> flow;
    flow->SetInputData(start);
    ConfigureFlow(flow, params);
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
    TakeFlowResult(flow, result.Water, result.FlowIterations, result.FlowStopReason);
    return result;
  };
  in.Enqueue(std::move(job), in.PendingFlow);
}

bool ViewerSession::Pump()
{
  Internals& in = *this->Impl;
  bool changed = in.TakeErosionFrame();
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
      in.LastFlowIterations = result.FlowIterations;
      in.LastFlowStopReason = result.FlowStopReason;
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

} // namespace viewer
} // namespace terroir

// The model of `terroir view` (TerroirViewerSessionPrivate.h): the worker thread's jobs (an
// overlay request, a water flow with its frames), collecting their results, waiting, progress.
#include "TerroirViewerSessionPrivate.h"

#include "vtkCallbackCommand.h"
#include "vtkDataArray.h"

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

} // namespace viewer
} // namespace terroir

/**
 * @file TerroirViewerSessionPrivate.h
 * @brief The inside of ViewerSession (TerroirViewerSession.h), shared by its source files:
 * TerroirViewerSession.cxx (the terrain, the accessors, running one filter),
 * TerroirViewerSessionOverlays.cxx (the overlays' filters, the sun, the cluster table),
 * TerroirViewerSessionWorker.cxx (the worker thread: overlay and water-flow jobs) and
 * TerroirViewerSessionEdits.cxx (lakes, the infiltration tools and the undo stack).
 */
#ifndef TerroirViewerSessionPrivate_h
#define TerroirViewerSessionPrivate_h

#include "TerroirViewerSession.h"

#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkTerroirInfiltration.h"
#include "vtkTerroirSoilHumidity.h"
#include "vtkTerroirTemperature.h"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstring>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

class vtkAlgorithm;

namespace terroir
{
namespace viewer
{

/// Progress and errors of the filters of one job.
struct JobMonitor
{
  std::atomic<double>* Progress = nullptr;
  double Start = 0.0; ///< share of the job done before this filter
  double Share = 1.0; ///< share of the job this filter takes
  std::string Error;
};

/// Updates `filter` while reporting progress in [start, start + share] of the job and keeping
/// its first error (observed, so that it is not printed from the worker thread). Returns false
/// on failure, with `monitor.Error` set.
bool RunFilter(vtkAlgorithm* filter, JobMonitor& monitor, double start, double share);

/// The parameters' climate and hemisphere on the filters that take it.
void ConfigureClimate(vtkTerroirTemperature* temperature, const ViewerParameters& p);
void ConfigureClimate(vtkTerroirSoilHumidity* humidity, const ViewerParameters& p);

/// The overlay's filters on `input` (a snapshot: terrain, WaterHeight, InfiltrationRate),
/// with the job's progress (TerroirViewerSessionOverlays.cxx).
OverlayResult ComputeOverlayOn(vtkImageData* input,
  ViewerOverlay overlay,
  const ViewerParameters& p,
  std::atomic<double>& progress);

/// The state of a ViewerSession: the terrain, the parameters, the water and infiltration maps
/// with their undo stack, the water-flow frames, and the worker thread and its queue.
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
  /// The larger of the water state and `depth` on each cell, one undo step; false with the
  /// error when `depth` is missing or of another size.
  bool MergeWater(vtkDataArray* depth, std::string& error);
  long long LastFlowIterations = -1; ///< the last finished water flow's (window thread)
  std::string LastFlowStopReason;
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
    long long FlowIterations = -1;        ///< water flow: iterations run
    std::string FlowStopReason;           ///< water flow: why it stopped
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

  // ---- live erosion (TerroirViewerSessionErosion.cxx) -----------------------------------
  struct ErosionRunner; ///< the simulation and its thread
  std::shared_ptr<ErosionRunner> Erosion;
  vtkSmartPointer<vtkFloatArray> ErosionBed, ErosionWater, ErosionSediment, ErosionVegetation;
  unsigned long ErosionFrameVersion = 0;
  /// Pump's part: the runner's newest frame into the arrays above; true when there was one.
  bool TakeErosionFrame();

  /// 1 where the cell has data (finite elevation, valid mask); set by SetTerrain.
  std::vector<unsigned char> DataCells;
  bool HasData(vtkIdType k) const { return this->DataCells[static_cast<std::size_t>(k)] != 0; }
};

} // namespace viewer
} // namespace terroir

#endif

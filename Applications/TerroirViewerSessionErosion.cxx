// The model of `terroir view` (TerroirViewerSessionPrivate.h): live erosion, Dunn (2015)'s
// sandbox. A terroir::terrain::ErosionSimulation runs on a thread of its own; dabs queued by the
// window's thread are applied between two steps; frames go back under a mutex.
#include "TerroirViewerSessionPrivate.h"

#include "vtkSMPTools.h"
#include "vtkTerroirErosion.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirTerrainInput.h"

#include "ErosionSimulation.h"

#include <chrono>
#include <cmath>
#include <stdexcept>

namespace terroir
{
namespace viewer
{
namespace te = terroir::terrain;

/// The simulation, its thread, the queued dabs and the newest frame.
struct ViewerSession::Internals::ErosionRunner
{
  struct Dab
  {
    te::ErosionBrush Brush;
    double I, J, Radius, Amount;
  };

  std::unique_ptr<te::ErosionSimulation> Simulation;
  te::ErosionSimulationParams Params;
  int FrameInterval = 5;
  std::thread Thread;
  std::atomic<bool> Stop{ false };
  std::atomic<bool> Stopped{ false };
  std::atomic<long long> Steps{ 0 };
  std::atomic<double> Rate{ 0.0 };
  mutable std::mutex Mutex;
  std::condition_variable Stepped;
  std::vector<Dab> Dabs;                          // under Mutex
  std::vector<float> Bed, Water, Sediment, Plant; // the newest frame, under Mutex
  unsigned long Serial = 0;                       // frames written, under Mutex
  unsigned long Taken = 0;                        // frames the window's thread took
  std::string Error;                              // under Mutex

  ~ErosionRunner() { this->Join(); }

  void Join()
  {
    this->Stop = true;
    if (this->Thread.joinable())
    {
      this->Thread.join();
    }
  }

  /// The frame from the state (value + residue), written under Mutex.
  void Publish()
  {
    const te::ErosionState& s = this->Simulation->State();
    const std::size_t n = s.Size();
    std::lock_guard<std::mutex> lock(this->Mutex);
    this->Bed.resize(n);
    this->Water.resize(n);
    this->Sediment = s.sediment;
    for (std::size_t k = 0; k < n; ++k)
    {
      this->Bed[k] = static_cast<float>(
        static_cast<double>(s.terrain[k]) + static_cast<double>(s.terrainResidue[k]));
      this->Water[k] = static_cast<float>(
        static_cast<double>(s.water[k]) + static_cast<double>(s.waterResidue[k]));
    }
    if (this->Simulation->HasVegetation())
    {
      this->Plant = this->Simulation->Vegetation().density;
    }
    ++this->Serial;
  }

  void Loop()
  {
    const te::ErosionParallelFor rows =
      [](int begin, int end, const std::function<void(int, int)>& body)
    {
      vtkSMPTools::For(begin,
        end,
        8,
        [&](vtkIdType b, vtkIdType e) { body(static_cast<int>(b), static_cast<int>(e)); });
    };
    const auto start = std::chrono::steady_clock::now();
    try
    {
      this->Publish();
      while (!this->Stop)
      {
        std::vector<Dab> dabs;
        {
          std::lock_guard<std::mutex> lock(this->Mutex);
          dabs.swap(this->Dabs);
        }
        for (const Dab& d : dabs)
        {
          this->Simulation->Paint(d.Brush, d.I, d.J, d.Radius, d.Amount);
        }
        this->Simulation->Step(this->Params, rows);
        const long long done = ++this->Steps;
        if (done % this->FrameInterval == 0)
        {
          this->Publish();
          const std::chrono::duration<double> t = std::chrono::steady_clock::now() - start;
          this->Rate = static_cast<double>(done) / std::max(1e-9, t.count());
        }
        this->Notify();
      }
    }
    catch (const std::exception& x)
    {
      std::lock_guard<std::mutex> lock(this->Mutex);
      this->Error = x.what();
    }
    this->Publish();
    this->Stopped = true;
    this->Notify();
  }

  /// Wakes WaitErosionSteps (the lock orders the wake-up after its test of the counters).
  void Notify()
  {
    {
      std::lock_guard<std::mutex> lock(this->Mutex);
    }
    this->Stepped.notify_all();
  }
};

//------------------------------------------------------------------------------
bool ViewerSession::Internals::TakeErosionFrame()
{
  ErosionRunner* r = this->Erosion.get();
  if (!r)
  {
    return false;
  }
  std::lock_guard<std::mutex> lock(r->Mutex);
  if (!r->Error.empty())
  {
    this->LastError = "erosion: " + r->Error;
    r->Error.clear();
  }
  if (r->Serial == r->Taken)
  {
    return false;
  }
  auto fill = [](vtkSmartPointer<vtkFloatArray>& a, const std::vector<float>& v, const char* name)
  {
    if (v.empty())
    {
      a = nullptr;
      return;
    }
    if (!a)
    {
      a = vtkSmartPointer<vtkFloatArray>::New();
      a->SetName(name);
    }
    a->SetNumberOfValues(static_cast<vtkIdType>(v.size()));
    std::copy(v.begin(), v.end(), a->GetPointer(0));
    a->Modified();
  };
  fill(this->ErosionBed, r->Bed, vtkTerroirErosion::ErodedElevationName());
  fill(this->ErosionWater, r->Water, vtkTerroirErosion::WaterDepthName());
  fill(this->ErosionSediment, r->Sediment, vtkTerroirErosion::SedimentName());
  fill(this->ErosionVegetation, r->Plant, vtkTerroirErosion::VegetationName());
  r->Taken = r->Serial;
  ++this->ErosionFrameVersion;
  return true;
}

//------------------------------------------------------------------------------
bool ViewerSession::StartErosion(std::string& error)
{
  Internals& in = *this->Impl;
  if (this->IsEroding())
  {
    error = "an erosion run is under way (stop it first)";
    return false;
  }
  if (!in.Terrain)
  {
    error = "no terrain";
    return false;
  }
  terroir::TerrainInput terrain;
  vtkDataArray* elevation =
    in.Terrain->GetPointData()->GetArray(vtkTerroirGeoreference::ElevationName());
  if (!terroir::ExtractTerrain(in.Terrain, elevation, terrain, error, 2))
  {
    return false;
  }
  const ViewerParameters& p = in.Params;
  auto runner = std::make_shared<Internals::ErosionRunner>();
  try
  {
    const std::size_t n = terrain.view.Size();
    const std::vector<float> plants(p.ErosionVegetation ? n : 0, 0.5f);
    runner->Simulation.reset(new te::ErosionSimulation(terrain.view,
      std::max(0.0, p.ErosionInitialWater),
      {},
      p.ErosionVegetation ? plants.data() : nullptr));
  }
  catch (const std::invalid_argument& x)
  {
    error = x.what();
    return false;
  }
  runner->Params.rainRate = std::max(0.0, p.ErosionRain) / 1000.0 / 3600.0;
  runner->FrameInterval = std::max(1, p.ErosionFrameInterval);
  in.Erosion = runner;
  runner->Thread = std::thread([r = runner.get()]() { r->Loop(); });
  return true;
}

//------------------------------------------------------------------------------
void ViewerSession::StopErosion()
{
  Internals& in = *this->Impl;
  if (in.Erosion)
  {
    in.Erosion->Join();
    in.TakeErosionFrame();
  }
}

//------------------------------------------------------------------------------
bool ViewerSession::KeepErosion(std::string& error)
{
  Internals& in = *this->Impl;
  this->StopErosion();
  if (!in.ErosionBed || in.ErosionBed->GetNumberOfValues() != in.Terrain->GetNumberOfPoints())
  {
    error = "no erosion to keep (start one first)";
    return false;
  }
  // The bed on the cells with data; the others keep their values (no data stays no data).
  vtkDataArray* old = in.Terrain->GetPointData()->GetArray(vtkTerroirGeoreference::ElevationName());
  vtkNew<vtkFloatArray> bed;
  bed->SetName(vtkTerroirGeoreference::ElevationName());
  bed->SetNumberOfValues(old->GetNumberOfTuples());
  for (vtkIdType k = 0; k < old->GetNumberOfTuples(); ++k)
  {
    bed->SetValue(
      k, in.HasData(k) ? in.ErosionBed->GetValue(k) : static_cast<float>(old->GetComponent(k, 0)));
  }
  auto terrain = vtkSmartPointer<vtkImageData>::New();
  terrain->ShallowCopy(in.Terrain);
  terrain->GetPointData()->RemoveArray(vtkTerroirGeoreference::ElevationName());
  terrain->GetPointData()->AddArray(bed);
  in.Erosion.reset();
  return this->SetTerrain(terrain, error);
}

//------------------------------------------------------------------------------
bool ViewerSession::IsEroding() const
{
  const Internals& in = *this->Impl;
  return in.Erosion && !in.Erosion->Stop && !in.Erosion->Stopped;
}

//------------------------------------------------------------------------------
bool ViewerSession::PaintErosion(double i, double j)
{
  Internals& in = *this->Impl;
  if (!this->IsEroding())
  {
    return false;
  }
  const ViewerParameters& p = in.Params;
  const int kind = std::max(0, std::min(2, p.ErosionBrush));
  Internals::ErosionRunner::Dab dab{
    static_cast<te::ErosionBrush>(kind), i, j, std::max(0.5, p.BrushRadius), p.ErosionAmount
  };
  std::lock_guard<std::mutex> lock(in.Erosion->Mutex);
  in.Erosion->Dabs.push_back(dab);
  return true;
}

//------------------------------------------------------------------------------
bool ViewerSession::WaitErosionSteps(long long steps, double timeout)
{
  Internals& in = *this->Impl;
  Internals::ErosionRunner* r = in.Erosion.get();
  if (!r)
  {
    return false;
  }
  std::unique_lock<std::mutex> lock(r->Mutex);
  const bool reached = r->Stepped.wait_for(lock,
    std::chrono::duration<double>(timeout),
    [&]() { return r->Steps >= steps || r->Stopped; });
  lock.unlock();
  in.TakeErosionFrame();
  return reached && r->Steps >= steps;
}

//------------------------------------------------------------------------------
long long ViewerSession::GetErosionSteps() const
{
  const Internals& in = *this->Impl;
  return in.Erosion ? in.Erosion->Steps.load() : 0;
}

double ViewerSession::GetErosionStepsPerSecond() const
{
  const Internals& in = *this->Impl;
  return in.Erosion ? in.Erosion->Rate.load() : 0.0;
}

unsigned long ViewerSession::GetErosionFrameVersion() const
{
  return this->Impl->ErosionFrameVersion;
}

vtkFloatArray* ViewerSession::GetErosionBed() const
{
  return this->Impl->ErosionBed;
}

vtkFloatArray* ViewerSession::GetErosionWater() const
{
  return this->Impl->ErosionWater;
}

vtkFloatArray* ViewerSession::GetErosionSediment() const
{
  return this->Impl->ErosionSediment;
}

vtkFloatArray* ViewerSession::GetErosionVegetation() const
{
  return this->Impl->ErosionVegetation;
}

} // namespace viewer
} // namespace terroir

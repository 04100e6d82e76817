// The stages of `terroir bench` (TerroirBenchPrivate.h): each times our filters' Update() on the
// synthetic terrain for the run's backend and reports its rows.
#include "TerroirBenchPrivate.h"

#include "TerroirApp.h"

#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"

#include "vtkTerroirComputeContext.h"
#include "vtkTerroirFloodFill.h"
#include "vtkTerroirFlowAccumulation.h"
#include "vtkTerroirInfiltration.h"
#include "vtkTerroirKMeans.h"
#include "vtkTerroirMorphometry.h"
#include "vtkTerroirSlope.h"
#include "vtkTerroirSoilHumidity.h"
#include "vtkTerroirSolarIllumination.h"
#include "vtkTerroirTemperature.h"
#include "vtkTerroirWaterFlow.h"
// new-filter.sh: includes

#include <algorithm>
#include <iomanip>
#include <iostream>
#include <string>
#include <vector>

namespace terroir
{
namespace app
{
namespace
{
using json = nlohmann::json;

/// One pointwise or stencil filter with its defaults on the terrain.
void BenchFilter(BenchRun& run, vtkTerroirImageAlgorithm* filter, const std::string& stage)
{
  filter->SetBackend(run.Backend);
  filter->SetInputData(run.Terrain);
  const double best = run.BestOf([&] { return BenchRun::TimedUpdate(filter, stage); });
  run.Report(stage, best, json::object());
  if (stage == "slope" && run.Backend == vtkTerroirComputeContext::CPU)
  {
    run.SlopeCPUSeconds = best;
  }
}

void BenchSlope(BenchRun& run)
{
  BenchFilter(run, vtkSmartPointer<vtkTerroirSlope>::New(), "slope");
}

void BenchTemperature(BenchRun& run)
{
  BenchFilter(run, vtkSmartPointer<vtkTerroirTemperature>::New(), "temperature");
}

/// The horizon map alone, as the filter times it, built by a fresh filter each time.
void BenchHorizon(BenchRun& run)
{
  int sectors = 0;
  const double best = run.BestOf(
    [&]
    {
      auto f = run.Illumination(vtkTerroirSolarIllumination::Instant);
      UpdateOrThrow(f, "horizon");
      sectors = f->GetHorizonSectors();
      return f->GetLastHorizonMapSeconds();
    });
  run.Report("horizon", best, json{ { "sectors", sectors } });
}

/// One instant with the horizon map already built (the warm-up builds it, later runs find it in
/// the filter's cache), then the same instant by ray marching.
void BenchInstant(BenchRun& run)
{
  auto f = run.Illumination(vtkTerroirSolarIllumination::Instant);
  double mapSeconds = 0.0;
  const double best = run.BestOf(
    [&]
    {
      const double t = BenchRun::TimedUpdate(f, "instant");
      mapSeconds = f->GetLastHorizonMapSeconds();
      return t;
    });
  run.Report(
    "instant", best, json{ { "method", "horizon" }, { "horizon_map_seconds", mapSeconds } });
  auto g = run.Illumination(vtkTerroirSolarIllumination::Instant);
  g->SetShadowMethodToRayMarching();
  const double march = run.BestOf([&] { return BenchRun::TimedUpdate(g, "instant"); });
  run.Report("instant-raymarch", march, json{ { "method", "raymarch" } });
}

/// Monthly mode with its defaults (the 15th of each month, 10-minute steps), a fresh filter each
/// time: the horizon map is included.
void BenchMonthly(BenchRun& run)
{
  double mapSeconds = 0.0, bestSeconds = 1e300;
  int steps = 0;
  const double best = run.BestOf(
    [&]
    {
      auto f = run.Illumination(vtkTerroirSolarIllumination::Monthly);
      const double t = BenchRun::TimedUpdate(f, "monthly");
      if (t < bestSeconds)
      {
        bestSeconds = t;
        mapSeconds = f->GetLastHorizonMapSeconds();
      }
      vtkDataArray* sun =
        f->GetOutput()->GetFieldData()->GetArray(vtkTerroirSolarIllumination::SunPositionsName());
      steps = sun ? static_cast<int>(sun->GetNumberOfTuples()) : 0;
      return t;
    });
  run.Report(
    "monthly", best, json{ { "horizon_map_seconds", mapSeconds }, { "sun_steps", steps } });
}

/// The default recipe: fill, then the slope rule on a slope computed inside (CPU only).
void BenchInfiltration(BenchRun& run)
{
  vtkNew<vtkTerroirInfiltration> f;
  f->SetInputData(run.Terrain);
  run.Report("infiltration",
    run.BestOf([&] { return BenchRun::TimedUpdate(f, "infiltration"); }),
    json::object());
}

/// Soil humidity alone (Long (2016)'s first kernel) and with the weighted average and standing
/// water (its second), from rates of the default infiltration recipe.
void BenchHumidity(BenchRun& run)
{
  vtkNew<vtkTerroirInfiltration> rates;
  rates->SetInputData(run.Terrain);
  UpdateOrThrow(rates, "infiltration");
  vtkNew<vtkTerroirSoilHumidity> f;
  f->SetBackend(run.Backend);
  f->SetInputConnection(rates->GetOutputPort());
  f->ComputeWeightedSoilHumidityOff();
  f->ComputeStandingWaterOff();
  run.Report("humidity",
    run.BestOf([&] { return BenchRun::TimedUpdate(f, "humidity"); }),
    json{ { "outputs", "SoilHumidity" } });
  f->ComputeWeightedSoilHumidityOn();
  f->ComputeStandingWaterOn();
  run.Report("humidity-all",
    run.BestOf([&] { return BenchRun::TimedUpdate(f, "humidity"); }),
    json{ { "outputs", "SoilHumidity, WeightedSoilHumidity, StandingWater" } });
  if (run.Backend == vtkTerroirComputeContext::CPU)
  {
    run.HumidityInput = vtkSmartPointer<vtkImageData>::New();
    run.HumidityInput->ShallowCopy(rates->GetOutput());
  }
}

/// Times `f` and reports its water bodies and wet cells.
void BenchWaterBodies(BenchRun& run, vtkTerroirFloodFill* f, const std::string& stage, json extra)
{
  const double best = run.BestOf([&] { return BenchRun::TimedUpdate(f, stage); });
  vtkDataArray* cells =
    f->GetOutput()->GetFieldData()->GetArray(vtkTerroirFloodFill::WaterBodyCellsName());
  double wet = 0.0;
  for (vtkIdType k = 0; cells && k < cells->GetNumberOfTuples(); ++k)
  {
    wet += cells->GetComponent(k, 0);
  }
  extra["water_bodies"] = cells ? cells->GetNumberOfTuples() : 0;
  extra["wet_cells"] = wet;
  run.Report(stage, best, extra);
}

/// One seed in the lowest cell, level at the median height (about half the terrain connected to
/// it floods). CPU only.
void BenchFloodFill(BenchRun& run)
{
  vtkNew<vtkTerroirFloodFill> f;
  f->SetInputData(run.Terrain);
  vtkDataArray* z = run.Terrain->GetPointData()->GetArray("Elevation");
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
  f->AddSeedCell(static_cast<int>(lowest % run.Size), static_cast<int>(lowest / run.Size), median);
  BenchWaterBodies(run, f, "floodfill", json{ { "level_m", median } });
}

/// Every closed depression: priority-flood and lakes. CPU only.
void BenchDepressions(BenchRun& run)
{
  vtkNew<vtkTerroirFloodFill> f;
  f->SetInputData(run.Terrain);
  f->SetModeToFillDepressions();
  BenchWaterBodies(run, f, "depressions", json::object());
}

/// D8 flow accumulation (Priority-Flood, flats, D8 directions, accumulation). CPU only.
void BenchFlowAccumulation(BenchRun& run)
{
  vtkNew<vtkTerroirFlowAccumulation> f;
  f->SetInputData(run.Terrain);
  const double best = run.BestOf([&] { return BenchRun::TimedUpdate(f, "flowacc"); });
  vtkDataArray* dir =
    f->GetOutput()->GetPointData()->GetArray(vtkTerroirFlowAccumulation::FlowDirectionName());
  vtkIdType outlets = 0;
  for (vtkIdType k = 0; dir && k < dir->GetNumberOfTuples(); ++k)
  {
    outlets += dir->GetComponent(k, 0) == -1.0 ? 1 : 0;
  }
  run.Report("flowacc", best, json{ { "outlet_cells", outlets } });
}

/// Long (2016)'s benchmark: 100 mm on every cell, run to the automatic stop; a fresh filter
/// each time (the filter caches its state).
void BenchWaterFlow(BenchRun& run)
{
  long long iterations = 0;
  const double best = run.BestOf(
    [&]
    {
      vtkNew<vtkTerroirWaterFlow> f;
      f->SetBackend(run.Backend);
      f->SetInputData(run.Terrain);
      const double t = BenchRun::TimedUpdate(f, "waterflow");
      vtkDataArray* it =
        f->GetOutput()->GetFieldData()->GetArray(vtkTerroirWaterFlow::IterationsName());
      iterations = it ? static_cast<long long>(it->GetComponent(0, 0)) : 0;
      return t;
    });
  const double cells = static_cast<double>(run.Size) * run.Size;
  run.Report("waterflow",
    best,
    json{ { "iterations", iterations },
      { "ms_per_iteration", iterations > 0 ? 1e3 * best / iterations : 0.0 },
      { "mcells_iterations_per_s", iterations > 0 ? cells * iterations / best / 1e6 : 0.0 } });
}

/// Lloyd iterations on 37 features (Slope, Temperature x 12 with the storage trick off, and two
/// synthetic 12-month fields), K = 5 and 10, Long (2016)'s diagonal seeds. Time per iteration =
/// (time of 11 iterations - time of 1) / 10: the set-up (packing, seeding, the table) cancels
/// out. The stage's seconds: 11 iterations at K = 5.
void BenchKMeans(BenchRun& run)
{
  if (!run.KMeansInput)
  {
    run.KMeansInput = BenchKMeansFeatures(run.Terrain);
  }
  json perK;
  double best5 = 0.0;
  for (int k : { 5, 10 })
  {
    auto once = [&](int iterations)
    {
      return run.BestOf(
        [&]
        {
          vtkNew<vtkTerroirKMeans> f;
          f->SetBackend(run.Backend);
          f->SetNumberOfClusters(k);
          f->SetCollapseConstantOffsets(false);
          f->SetTolerance(0.0);
          f->SetMaximumIterations(iterations);
          f->SetInputData(run.KMeansInput);
          return BenchRun::TimedUpdate(f, "kmeans");
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
    std::cout << "  kmeans K=" << k << " " << run.BackendName << ": " << std::setprecision(2)
              << 1e3 * perIteration << " ms per iteration (37 features)\n";
  }
  run.Report("kmeans", best5, json{ { "features", 37 }, { "per_k", perK } });
}

} // namespace

//------------------------------------------------------------------------------
const std::vector<BenchStage>& BenchStages()
{
  static const std::vector<BenchStage> stages = {
    { "slope", false, BenchSlope },
    { "temperature", false, BenchTemperature },
    { "horizon", false, BenchHorizon },
    { "instant", false, BenchInstant },
    { "monthly", false, BenchMonthly },
    { "infiltration", true, BenchInfiltration },
    { "humidity", false, BenchHumidity },
    { "floodfill", true, BenchFloodFill },
    { "depressions", true, BenchDepressions },
    { "flowacc", true, BenchFlowAccumulation },
    { "waterflow", false, BenchWaterFlow },
    { "kmeans", false, BenchKMeans },
    { "morphometry",
      true,
      [](BenchRun& run)
      { BenchFilter(run, vtkSmartPointer<vtkTerroirMorphometry>::New(), "morphometry"); } },
    // new-filter.sh: stages
  };
  return stages;
}

} // namespace app
} // namespace terroir

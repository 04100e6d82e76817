// Pipeline tests of vtkTerroirWaterFlow: arrays, units, field data and defaults; the filter
// equals the core (WaterFlowSimulation) run by hand; the three water sources; VTK time steps
// equal fresh runs of that many iterations and reuse the cache (forward) or a checkpoint
// (backward); bad inputs; conservation on the bundled Sagehen DEM.
#include "TerroirFilterTestUtilities.h"

#include "vtkCallbackCommand.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkPointData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirWaterFlow.h"

#include "WaterFlow.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

namespace
{
using terroir_test::MakeTerrain;
namespace hy = terroir::hydrology;

/// A valley: z = 0.2 |x - 15| + 0.1 y (metres) on 31 x 21 cells of 10 m, with a dimple.
vtkSmartPointer<vtkImageData> Valley()
{
  return MakeTerrain(31,
    21,
    10.0,
    10.0,
    [](int i, int j)
    { return 100.0 + 2.0 * std::abs(i - 15) + 1.0 * j - (i == 15 && j == 10 ? 3.0 : 0.0); });
}

vtkSmartPointer<vtkImageData> RunFlow(vtkTerroirWaterFlow* f, vtkImageData* in)
{
  f->SetInputData(in);
  f->Update();
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->DeepCopy(f->GetOutput());
  return out;
}

double Field(vtkImageData* out, const char* name)
{
  vtkDataArray* a = vtkDataArray::SafeDownCast(out->GetFieldData()->GetAbstractArray(name));
  return a ? a->GetComponent(0, 0) : std::nan("");
}

std::string Reason(vtkImageData* out)
{
  auto* a = vtkStringArray::SafeDownCast(
    out->GetFieldData()->GetAbstractArray(vtkTerroirWaterFlow::StopReasonName()));
  return a && a->GetNumberOfValues() == 1 ? a->GetValue(0) : std::string("?");
}

/// The first component of `a` (empty for no array).
std::vector<double> Values(vtkDataArray* a)
{
  std::vector<double> v;
  for (vtkIdType k = 0; a && k < a->GetNumberOfTuples(); ++k)
  {
    v.push_back(a->GetComponent(k, 0));
  }
  return v;
}

std::vector<double> Values(vtkImageData* out, const char* name)
{
  return Values(out->GetPointData()->GetArray(name));
}

TEST(TerroirWaterFlow, ArraysUnitsDefaults)
{
  vtkNew<vtkTerroirWaterFlow> f;
  EXPECT_EQ(f->GetWaterSource(), vtkTerroirWaterFlow::Constant);
  EXPECT_EQ(f->GetInitialWater(), 100.0);
  EXPECT_EQ(f->GetAutoStopRatio(), 1e-3);
  EXPECT_EQ(f->GetMaximumIterations(), 10000);
  EXPECT_EQ(f->GetRiverThreshold(), 10000.0);
  EXPECT_EQ(f->GetIterationDuration(), 10.0);
  const vtkMTimeType t0 = f->GetMTime();
  f->SetInitialWater(50.0);
  EXPECT_GT(f->GetMTime(), t0);
  f->SetInitialWater(100.0);
  f->SetBackendToCPU();
  auto out = RunFlow(f, Valley());
  vtkFloatArray* h = vtkFloatArray::SafeDownCast(
    out->GetPointData()->GetArray(vtkTerroirWaterFlow::WaterHeightName()));
  vtkDoubleArray* q = vtkDoubleArray::SafeDownCast(
    out->GetPointData()->GetArray(vtkTerroirWaterFlow::DischargeName()));
  vtkDataArray* r = out->GetPointData()->GetArray(vtkTerroirWaterFlow::RiverName());
  ASSERT_TRUE(h && q && r);
  EXPECT_STREQ(h->GetInformation()->Get(vtkDataArray::UNITS_LABEL()), "m");
  EXPECT_STREQ(q->GetInformation()->Get(vtkDataArray::UNITS_LABEL()), "m3");
  EXPECT_EQ(r->GetDataType(), VTK_UNSIGNED_CHAR);
  EXPECT_TRUE(out->GetPointData()->GetArray("Elevation")); // input arrays kept
  // 0.1 m on 651 cells of 100 m^2.
  EXPECT_NEAR(Field(out, "WaterFlowInitialVolume"), 0.1 * 651 * 100, 1e-9);
  EXPECT_NEAR(Field(out, "WaterFlowStoredVolume") + Field(out, "WaterFlowOutflowVolume"),
    Field(out, "WaterFlowInitialVolume"),
    1e-6 * Field(out, "WaterFlowInitialVolume"));
  EXPECT_EQ(Reason(out), "AutoStop");
  const double iterations = Field(out, vtkTerroirWaterFlow::IterationsName());
  EXPECT_GT(iterations, 1);
  EXPECT_DOUBLE_EQ(Field(out, "WaterFlowSimulatedTime"), 10.0 * iterations);
  // River = Discharge >= threshold, and the valley's floor (i = 15) carries the most water.
  for (vtkIdType k = 0; k < q->GetNumberOfTuples(); ++k)
  {
    EXPECT_EQ(r->GetComponent(k, 0), q->GetValue(k) >= 10000.0 ? 1.0 : 0.0);
  }
  EXPECT_GT(q->GetValue(10 * 31 + 15), q->GetValue(10 * 31 + 10));
}

// The river-forming mode: the dimple (3 m deep, one cell) holds still water from the start; rain
// of 36 mm/h (1e-4 m per 10 s iteration) runs until the outflow balances it; every array is
// there with its units; the valley floor carries the rain of the cells above it. (GPU = CPU bit
// for bit: Testing/GPU/TestWaterFlowGPU.cxx and TestDeterminismGPU.cxx.)
TEST(TerroirWaterFlow, RiversModeBalancesTheRain)
{
  vtkNew<vtkTerroirWaterFlow> f;
  EXPECT_EQ(f->GetMode(), vtkTerroirWaterFlow::Pulse);
  EXPECT_EQ(f->GetRainRate(), 0.3);
  EXPECT_EQ(f->GetBalanceTolerance(), 0.02);
  f->SetModeToRivers();
  f->SetRainRate(36.0);
  f->SetBalanceTolerance(1e-6);
  f->SetRiverArea(5000.0);
  f->SetLakeArea(100.0); // one cell
  f->SetBackendToCPU();
  auto out = RunFlow(f, Valley());
  EXPECT_EQ(Reason(out), "Balanced");
  vtkDoubleArray* rate = vtkDoubleArray::SafeDownCast(
    out->GetPointData()->GetArray(vtkTerroirWaterFlow::DischargeRateName()));
  vtkDataArray* lake = out->GetPointData()->GetArray(vtkTerroirWaterFlow::LakeMaskName());
  vtkDataArray* river = out->GetPointData()->GetArray(vtkTerroirWaterFlow::RiverName());
  ASSERT_TRUE(rate && lake && river);
  EXPECT_STREQ(rate->GetInformation()->Get(vtkDataArray::UNITS_LABEL()), "m3/s");
  // The one lake: the dimple (15, 10), filled to its spill level 109 m, and the cell it spills
  // over, (15, 9) at 109 m, one flat of the filled surface (DepressionWaterBodies).
  for (vtkIdType k = 0; k < lake->GetNumberOfTuples(); ++k)
  {
    EXPECT_EQ(lake->GetComponent(k, 0), k == 10 * 31 + 15 || k == 9 * 31 + 15 ? 1.0 : 0.0) << k;
  }
  // The floor carries the most water of its row, more and more downstream, and never more
  // than the rain of the rows above (16 x 31 cells of 100 m^2 at 1e-5 m/s for row 5); the
  // side slopes (0.2) are not much steeper than the floor (0.1), so part of the water runs
  // beside the floor for a while (the multiple-direction split of Long (2016)'s rule).
  const double perCell = 100.0 * 36.0e-3 / 3600.0;
  for (int j = 1; j < 20; ++j)
  {
    const double floor = rate->GetValue(j * 31 + 15);
    EXPECT_LT(floor, rate->GetValue((j - 1) * 31 + 15)) << "row " << j;
    EXPECT_LE(floor, (21 - j) * 31 * perCell * (1.0 + 1e-9)) << "row " << j;
    for (int i = 0; i < 31; ++i)
    {
      EXPECT_LE(rate->GetValue(j * 31 + i), floor) << i << ", " << j;
    }
  }
  EXPECT_GT(rate->GetValue(5 * 31 + 15), 0.5 * 15 * 31 * perCell);
  // Balanced: the last iteration's outflow is the rain on the 651 cells, within 1e-6.
  const double rained = 651 * 100.0 * 1e-4 * Field(out, vtkTerroirWaterFlow::IterationsName());
  EXPECT_NEAR(Field(out, "WaterFlowStoredVolume") + Field(out, "WaterFlowOutflowVolume"),
    Field(out, "WaterFlowInitialVolume") + rained,
    1e-9 * rained);
  // River: the floor (a crest of the discharge) from where it carries 5000 m^2 of rain.
  EXPECT_EQ(river->GetComponent(5 * 31 + 15, 0), 1.0);
  EXPECT_EQ(river->GetComponent(5 * 31 + 10, 0), 0.0);
}

// Rivers mode's coarse-to-fine start: the levels it ran are reported, and it ends where a cold
// start ends (the discharge along the floor within 1 %, once the refinement's extra water has
// drained: 60 settling iterations, about twice the way down the valley), after fewer
// iterations on the grid.
TEST(TerroirWaterFlow, RiversModeWarmStartEndsWhereAColdStartEnds)
{
  vtkSmartPointer<vtkImageData> rates[2];
  double iterations[2];
  for (int warm = 0; warm < 2; ++warm)
  {
    vtkNew<vtkTerroirWaterFlow> f;
    EXPECT_EQ(f->GetWarmStart(), 1);
    EXPECT_EQ(f->GetWarmStartSide(), 128);
    EXPECT_EQ(f->GetSettleIterations(), 100);
    f->SetModeToRivers();
    f->SetRainRate(36.0);
    f->SetBalanceTolerance(1e-6);
    f->SetWarmStart(warm);
    f->SetWarmStartSide(5); // 31 x 21: levels of 16 x 11 and 8 x 6
    f->SetSettleIterations(60);
    f->SetBackendToCPU();
    rates[warm] = RunFlow(f, Valley());
    EXPECT_EQ(Reason(rates[warm]), "Balanced");
    iterations[warm] = Field(rates[warm], vtkTerroirWaterFlow::IterationsName());
    vtkDataArray* levels = vtkDataArray::SafeDownCast(
      rates[warm]->GetFieldData()->GetAbstractArray("WaterFlowWarmStartIterations"));
    ASSERT_NE(levels, nullptr);
    ASSERT_EQ(levels->GetNumberOfComponents(), 3);
    ASSERT_EQ(levels->GetNumberOfTuples(), warm ? 2 : 0);
    if (warm)
    {
      EXPECT_EQ(levels->GetComponent(0, 1), 8.0); // coarsest first: nx, ny
      EXPECT_EQ(levels->GetComponent(0, 2), 6.0);
      EXPECT_EQ(levels->GetComponent(1, 1), 16.0);
      EXPECT_EQ(levels->GetComponent(1, 2), 11.0);
      EXPECT_GE(levels->GetComponent(1, 0), 60.0); // settled, then balanced
    }
  }
  EXPECT_LT(iterations[1], iterations[0]);
  const std::vector<double> cold = Values(rates[0], vtkTerroirWaterFlow::DischargeRateName());
  const std::vector<double> warm = Values(rates[1], vtkTerroirWaterFlow::DischargeRateName());
  for (int j = 0; j < 20; ++j)
  {
    EXPECT_NEAR(warm[j * 31 + 15], cold[j * 31 + 15], 0.01 * cold[j * 31 + 15]) << "row " << j;
  }
}

// Rivers mode with a month's standing water: spread over the month's hours as rain per cell.
// 744 mm in January (31 days = 744 h) is 1 mm/h: the same run as RainRate 1; and where the
// standing water is doubled on the western half, more water runs there.
TEST(TerroirWaterFlow, RiversModeSpreadsTheMonthsStandingWater)
{
  auto uniform = Valley();
  vtkNew<vtkFloatArray> standing;
  standing->SetName("StandingWater");
  standing->SetNumberOfComponents(12);
  standing->SetNumberOfTuples(uniform->GetNumberOfPoints());
  standing->Fill(744.0);
  uniform->GetPointData()->AddArray(standing);
  vtkNew<vtkTerroirWaterFlow> byRate;
  byRate->SetModeToRivers();
  byRate->SetRainRate(1.0);
  byRate->SetBackendToCPU();
  auto a = RunFlow(byRate, uniform);
  vtkNew<vtkTerroirWaterFlow> byMonth;
  byMonth->SetModeToRivers();
  byMonth->SetWaterSourceToStandingWaterMonth();
  byMonth->SetMonth(1);
  byMonth->SetBackendToCPU();
  auto b = RunFlow(byMonth, uniform);
  EXPECT_EQ(Field(a, vtkTerroirWaterFlow::IterationsName()),
    Field(b, vtkTerroirWaterFlow::IterationsName()));
  const std::vector<double> qa = Values(a, vtkTerroirWaterFlow::DischargeRateName());
  const std::vector<double> qb = Values(b, vtkTerroirWaterFlow::DischargeRateName());
  ASSERT_EQ(qa.size(), qb.size());
  for (std::size_t k = 0; k < qa.size(); ++k)
  {
    EXPECT_NEAR(qb[k], qa[k], 1e-12 * std::max(1e-12, qa[k])) << k;
  }
  EXPECT_NEAR(Field(b, "WaterFlowRainVolume"),
    Field(a, "WaterFlowRainVolume"),
    1e-9 * Field(a, "WaterFlowRainVolume"));
  // Twice the standing water west of the floor (i < 15): the western side cells carry about
  // twice as much as their mirror images in the east.
  auto wet = Valley();
  vtkNew<vtkFloatArray> halves;
  halves->DeepCopy(standing);
  for (vtkIdType k = 0; k < halves->GetNumberOfTuples(); ++k)
  {
    halves->SetComponent(k, 0, k % 31 < 15 ? 1488.0 : 744.0);
  }
  wet->GetPointData()->AddArray(halves);
  vtkNew<vtkTerroirWaterFlow> uneven;
  uneven->SetModeToRivers();
  uneven->SetWaterSourceToStandingWaterMonth();
  uneven->SetBackendToCPU();
  auto c = RunFlow(uneven, wet);
  const std::vector<double> qc = Values(c, vtkTerroirWaterFlow::DischargeRateName());
  const double west = qc[15 * 31 + 10];
  const double east = qc[15 * 31 + 20];
  EXPECT_NEAR(west / east, 2.0, 0.1);
}

// The filter is the core: same water and discharge as WaterFlowSimulation run by hand.
TEST(TerroirWaterFlow, EqualsCore)
{
  auto in = Valley();
  vtkNew<vtkTerroirWaterFlow> f;
  f->SetBackendToCPU();
  f->SetAutoStopRatio(0.0);
  f->SetMaximumIterations(37);
  auto out = RunFlow(f, in);
  EXPECT_EQ(Reason(out), "MaximumIterations");
  std::vector<float> z(31 * 21);
  vtkDataArray* e = in->GetPointData()->GetArray("Elevation");
  for (vtkIdType k = 0; k < e->GetNumberOfTuples(); ++k)
  {
    z[k] = static_cast<float>(e->GetComponent(k, 0));
  }
  terroir::GridView<float> v;
  v.data = z.data();
  v.nx = 31;
  v.ny = 21;
  v.dx = v.dy = 10.0;
  std::vector<double> w(z.size(), 0.1);
  hy::WaterFlowSimulation sim(v, w.data());
  for (int k = 0; k < 37; ++k)
  {
    sim.Step();
  }
  std::vector<float> depth(z.size());
  std::vector<double> discharge(z.size());
  sim.GetWaterHeight(depth.data());
  sim.GetDischarge(discharge.data());
  const auto h = Values(out, "WaterHeight");
  const auto q = Values(out, "Discharge");
  for (std::size_t c = 0; c < z.size(); ++c)
  {
    ASSERT_EQ(static_cast<float>(h[c]), depth[c]) << c;
    ASSERT_EQ(q[c], discharge[c]) << c;
  }
}

TEST(TerroirWaterFlow, StandingWaterSources)
{
  auto in = Valley();
  const vtkIdType n = in->GetNumberOfPoints();
  vtkNew<vtkFloatArray> standing;
  standing->SetName("StandingWater");
  standing->SetNumberOfComponents(12);
  standing->SetNumberOfTuples(n);
  for (vtkIdType k = 0; k < n; ++k)
  {
    for (int m = 0; m < 12; ++m)
    {
      standing->SetComponent(k, m, m + 1.0 + (k % 3)); // mm
    }
  }
  in->GetPointData()->AddArray(standing);
  // Month 4 (April): 4 + (k % 3) mm; annual: 78 + 12 (k % 3) mm.
  double april = 0.0;
  double annual = 0.0;
  for (vtkIdType k = 0; k < n; ++k)
  {
    april += (4.0 + k % 3) / 1000.0 * 100.0;
    annual += (78.0 + 12.0 * (k % 3)) / 1000.0 * 100.0;
  }
  vtkNew<vtkTerroirWaterFlow> f;
  f->SetBackendToCPU();
  f->SetMaximumIterations(1);
  f->SetWaterSourceToStandingWaterMonth();
  f->SetMonth(4);
  EXPECT_NEAR(Field(RunFlow(f, in), "WaterFlowInitialVolume"), april, 1e-6 * april);
  f->SetWaterSourceToStandingWaterAnnual();
  EXPECT_NEAR(Field(RunFlow(f, in), "WaterFlowInitialVolume"), annual, 1e-6 * annual);
}

TEST(TerroirWaterFlow, TimeStepsContinueFromCache)
{
  auto in = Valley();
  vtkNew<vtkTerroirWaterFlow> f;
  f->SetBackendToCPU();
  f->SetMaximumIterations(60);
  f->SetCheckpointInterval(10);
  f->SetInputData(in);
  f->UpdateInformation();
  vtkInformation* info = f->GetOutputInformation(0);
  ASSERT_TRUE(info->Has(vtkStreamingDemandDrivenPipeline::TIME_STEPS()));
  EXPECT_EQ(info->Length(vtkStreamingDemandDrivenPipeline::TIME_STEPS()), 7); // 0, 10, ..., 60
  EXPECT_EQ(info->Get(vtkStreamingDemandDrivenPipeline::TIME_STEPS())[6], 60.0);

  auto fresh = [&](int iterations)
  {
    vtkNew<vtkTerroirWaterFlow> g;
    g->SetBackendToCPU();
    g->SetAutoStopRatio(0.0);
    g->SetMaximumIterations(iterations);
    return Values(RunFlow(g, in), "WaterHeight");
  };
  f->UpdateTimeStep(30.0);
  EXPECT_EQ(f->GetLastComputedIterations(), 30);
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->DeepCopy(f->GetOutput());
  EXPECT_EQ(Reason(out), "RequestedTime");
  EXPECT_EQ(Field(out, vtkTerroirWaterFlow::IterationsName()), 30.0);
  EXPECT_EQ(Values(out, "WaterHeight"), fresh(30));
  EXPECT_DOUBLE_EQ(out->GetInformation()->Get(vtkDataObject::DATA_TIME_STEP()), 30.0);
  // Forward: 20 more iterations from the cache, not 50 from zero.
  f->UpdateTimeStep(50.0);
  EXPECT_EQ(f->GetLastComputedIterations(), 20);
  out->DeepCopy(f->GetOutput());
  EXPECT_EQ(Values(out, "WaterHeight"), fresh(50));
  // Backward to 25: restart from the checkpoint at 20 (5 iterations).
  f->UpdateTimeStep(25.0);
  EXPECT_EQ(f->GetLastComputedIterations(), 5);
  out->DeepCopy(f->GetOutput());
  EXPECT_EQ(Values(out, "WaterHeight"), fresh(25));
  // Without a time request the stop rules apply; a later request for the stop's iteration
  // is then served from the cache.
  vtkNew<vtkTerroirWaterFlow> plain;
  plain->SetBackendToCPU();
  auto ruled = RunFlow(plain, in);
  const double stop = Field(ruled, vtkTerroirWaterFlow::IterationsName());
  EXPECT_EQ(Reason(ruled), "AutoStop");
  plain->UpdateTimeStep(stop);
  EXPECT_EQ(plain->GetLastComputedIterations(), 0);
  EXPECT_EQ(Values(plain->GetOutput(), "WaterHeight"), Values(ruled, "WaterHeight"));
  plain->UpdateTimeStep(stop + 3.0);
  EXPECT_EQ(plain->GetLastComputedIterations(), 3);
}

/// Records every IterationEvent: the iteration count and the state read during the event.
struct Watcher
{
  vtkTerroirWaterFlow* Filter = nullptr;
  std::vector<vtkIdType> Iterations;
  std::vector<std::vector<double>> States;
  static void Callback(vtkObject*, unsigned long, void* clientData, void* callData)
  {
    auto* self = static_cast<Watcher*>(clientData);
    self->Iterations.push_back(*static_cast<vtkIdType*>(callData));
    vtkNew<vtkFloatArray> state;
    EXPECT_TRUE(self->Filter->GetCurrentWaterHeight(state));
    self->States.push_back(Values(state));
  }
};

TEST(TerroirWaterFlow, IterationEventsShowTheStateAsTheRunGoesOn)
{
  auto in = Valley();
  // The run under the stop rules without watching: where it stops and its result.
  vtkNew<vtkTerroirWaterFlow> plain;
  plain->SetBackendToCPU();
  auto unwatched = RunFlow(plain, in);
  const double stop = Field(unwatched, vtkTerroirWaterFlow::IterationsName());
  ASSERT_GT(stop, 14.0);

  vtkNew<vtkTerroirWaterFlow> f;
  f->SetBackendToCPU();
  f->SetIterationEventInterval(7);
  Watcher watcher;
  watcher.Filter = f;
  vtkNew<vtkCallbackCommand> observer;
  observer->SetCallback(Watcher::Callback);
  observer->SetClientData(&watcher);
  f->AddObserver(vtkTerroirWaterFlow::IterationEvent, observer);
  vtkNew<vtkFloatArray> none;
  EXPECT_FALSE(f->GetCurrentWaterHeight(none)); // no simulation yet
  auto watched = RunFlow(f, in);

  // One event after every 7th iteration up to the stop, each showing the state of a fresh
  // run of that many iterations (stop rules off); the result is the unwatched one.
  const std::size_t expected = static_cast<std::size_t>(stop) / 7;
  ASSERT_EQ(watcher.Iterations.size(), expected);
  for (std::size_t k = 0; k < expected; ++k)
  {
    const int iterations = static_cast<int>(7 * (k + 1));
    EXPECT_EQ(watcher.Iterations[k], iterations);
    vtkNew<vtkTerroirWaterFlow> g;
    g->SetBackendToCPU();
    g->SetAutoStopRatio(0.0);
    g->SetMaximumIterations(iterations);
    EXPECT_EQ(watcher.States[k], Values(RunFlow(g, in), "WaterHeight")) << iterations;
  }
  EXPECT_EQ(Field(watched, vtkTerroirWaterFlow::IterationsName()), stop);
  EXPECT_EQ(Values(watched, "WaterHeight"), Values(unwatched, "WaterHeight"));
  EXPECT_EQ(Values(watched, "Discharge"), Values(unwatched, "Discharge"));
  // After the update the current state is the output.
  vtkNew<vtkFloatArray> now;
  ASSERT_TRUE(f->GetCurrentWaterHeight(now));
  EXPECT_EQ(Values(now), Values(watched, "WaterHeight"));
  // Setting the interval keeps the cache (it does not change the result): the stop's
  // iteration is served from it, no iteration is computed again.
  f->SetIterationEventInterval(0);
  f->UpdateTimeStep(stop);
  EXPECT_EQ(f->GetLastComputedIterations(), 0);
}

TEST(TerroirWaterFlow, SimulatedTimeLimit)
{
  vtkNew<vtkTerroirWaterFlow> f;
  f->SetBackendToCPU();
  f->SetAutoStopRatio(0.0);
  f->SetIterationDuration(30.0);
  f->SetMaximumSimulatedTime(600.0); // 20 iterations
  auto out = RunFlow(f, Valley());
  EXPECT_EQ(Reason(out), "SimulatedTime");
  EXPECT_EQ(Field(out, vtkTerroirWaterFlow::IterationsName()), 20.0);
  EXPECT_EQ(Field(out, "WaterFlowSimulatedTime"), 600.0);
}

TEST(TerroirWaterFlow, BadInputsAreOneErrorAndAnEmptyOutput)
{
  auto in = Valley();
  vtkTerroirGeoreference::SetSourceFile(in, "dem.tif");
  auto negative = Valley();
  vtkTerroirGeoreference::SetSourceFile(negative, "dem.tif");
  vtkNew<vtkFloatArray> standing;
  standing->SetName("StandingWater");
  standing->SetNumberOfComponents(12);
  standing->SetNumberOfTuples(negative->GetNumberOfPoints());
  standing->Fill(1.0);
  standing->SetComponent(33, 0, -2.0); // cell (2, 1), January
  negative->GetPointData()->AddArray(standing);
  struct Case
  {
    vtkImageData* input;
    std::function<void(vtkTerroirWaterFlow*)> set;
    std::string message;
  };
  const std::vector<Case> cases = {
    { in,
      [](vtkTerroirWaterFlow* f) { f->SetInitialWater(-5.0); },
      "dem.tif: InitialWater -5 mm must be a finite number >= 0" },
    { in,
      [](vtkTerroirWaterFlow* f) { f->SetInitialWater(std::nan("")); },
      "dem.tif: InitialWater nan mm must be a finite number >= 0" },
    { in,
      [](vtkTerroirWaterFlow* f) { f->SetMonth(13); },
      "dem.tif: Month 13 must be 1 (January) to 12 (December)" },
    { in,
      [](vtkTerroirWaterFlow* f) { f->SetIterationDuration(0.0); },
      "dem.tif: IterationDuration 0 s must be a finite number > 0" },
    { in,
      [](vtkTerroirWaterFlow* f) { f->SetWaterSourceToStandingWaterAnnual(); },
      "dem.tif: the StandingWater sources need a point array `StandingWater` with 12 components" },
    { in,
      [](vtkTerroirWaterFlow* f) { f->SetWarmStartSide(1); },
      "dem.tif: WarmStartSide 1 must be >= 2 and SettleIterations 100 >= 0" },
    { in, // Rivers mode asks the warm start's levels before the parameters are checked
      [](vtkTerroirWaterFlow* f)
      {
        f->SetModeToRivers();
        f->SetWarmStartSide(1);
      },
      "dem.tif: WarmStartSide 1 must be >= 2 and SettleIterations 100 >= 0" },
    { in,
      [](vtkTerroirWaterFlow* f) { f->SetSettleIterations(-3); },
      "dem.tif: WarmStartSide 128 must be >= 2 and SettleIterations -3 >= 0" },
    { negative,
      [](vtkTerroirWaterFlow* f) { f->SetWaterSourceToStandingWaterMonth(); },
      "dem.tif: water -2 mm at cell (2, 1) is negative or not a number" },
  };
  for (const Case& c : cases)
  {
    vtkNew<vtkTerroirWaterFlow> f;
    f->SetBackendToCPU();
    vtkNew<terroir_test::ErrorObserver> errors;
    f->AddObserver(vtkCommand::ErrorEvent, errors);
    vtkNew<terroir_test::ErrorObserver> pipeline;
    f->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, pipeline);
    c.set(f);
    auto out = RunFlow(f, c.input);
    EXPECT_EQ(errors->ErrorCount, 1) << c.message << ": " << errors->Errors;
    EXPECT_NE(errors->Errors.find(c.message), std::string::npos) << errors->Errors;
    EXPECT_EQ(out->GetNumberOfPoints(), 0) << c.message;
  }
}

// The bundled DEM with 100 mm everywhere, run to Long (2016)'s stop: volume is conserved, the
// rivers are where the most water passed, and the time is printed for the filter's page.
TEST(TerroirWaterFlow, SagehenConservation)
{
  vtkSmartPointer<vtkImageData> dem =
    terroir_test::ReadDEM(terroir_test::DataFile("sagehen_creek_ca/sagehen_dem_utm11n_10m.tif"));
  ASSERT_TRUE(dem);
  vtkNew<vtkTerroirWaterFlow> f;
  f->SetBackendToCPU();
  const auto t0 = std::chrono::steady_clock::now();
  auto out = RunFlow(f, dem);
  const double seconds =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double initial = Field(out, "WaterFlowInitialVolume");
  EXPECT_NEAR(initial, 0.1 * 786 * 720 * 100.0, 1e-6 * initial);
  EXPECT_NEAR(Field(out, "WaterFlowStoredVolume") + Field(out, "WaterFlowOutflowVolume"),
    initial,
    1e-6 * initial);
  EXPECT_EQ(Reason(out), "AutoStop");
  const auto river = Values(out, "River");
  double rivers = 0.0;
  for (double r : river)
  {
    rivers += r;
  }
  EXPECT_GT(rivers, 100.0);
  EXPECT_LT(rivers, 0.2 * river.size());
  std::cout << "[ timing ] Sagehen 786 x 720, 100 mm, CPU: "
            << Field(out, vtkTerroirWaterFlow::IterationsName()) << " iterations in " << seconds
            << " s, " << rivers << " river cells\n";
}

} // namespace

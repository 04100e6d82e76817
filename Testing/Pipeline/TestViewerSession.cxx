// The window-free model of `terroir view` (Applications/TerroirViewerSession.h): the water
// state and its undo stack (restored byte for byte), the overlays against the filters run
// directly, and the worker thread against the synchronous path.
#include "TerroirFilterTestUtilities.h"
#include "TerroirViewerSession.h"

#include "ErosionSimulation.h"

#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkTable.h"
#include "vtkTerroirFloodFill.h"
#include "vtkTerroirInfiltration.h"
#include "vtkTerroirSlope.h"
#include "vtkTerroirSoilHumidity.h"
#include "vtkTerroirSolarIllumination.h"
#include "vtkTerroirTemperature.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <vector>

using terroir::viewer::OverlayResult;
using terroir::viewer::ViewerOverlay;
using terroir::viewer::ViewerSession;

namespace
{
/// Two bowls (centres (12, 12) and (36, 20), 8 m deep) on a plane tilted up to the north-east,
/// a ridge between them, and one no-data cell; 48 x 32 cells of 10 m.
vtkSmartPointer<vtkImageData> TwoBowls()
{
  return terroir_test::MakeTerrain(48,
    32,
    10.0,
    10.0,
    [](int i, int j) -> double
    {
      if (i == 47 && j == 31)
      {
        return std::nan("");
      }
      const double a = std::hypot(i - 12.0, j - 12.0);
      const double b = std::hypot(i - 36.0, j - 20.0);
      return 100.0 + 0.5 * i + 0.3 * j - 8.0 * std::exp(-a * a / 40.0) -
        8.0 * std::exp(-b * b / 40.0);
    });
}

std::vector<float> Copy(vtkFloatArray* a)
{
  return std::vector<float>(a->GetPointer(0), a->GetPointer(0) + a->GetNumberOfValues());
}

bool SameBytes(vtkFloatArray* a, const std::vector<float>& b)
{
  return static_cast<std::size_t>(a->GetNumberOfValues()) == b.size() &&
    std::memcmp(a->GetPointer(0), b.data(), b.size() * sizeof(float)) == 0;
}

/// Every value of component `c` of the two arrays is the same (NaN equals NaN).
void ExpectSameComponent(vtkDataArray* got, vtkDataArray* want, int c)
{
  ASSERT_NE(got, nullptr);
  ASSERT_NE(want, nullptr);
  ASSERT_EQ(got->GetNumberOfTuples(), want->GetNumberOfTuples());
  int differ = 0;
  for (vtkIdType k = 0; k < got->GetNumberOfTuples(); ++k)
  {
    const double g = got->GetComponent(k, c);
    const double w = want->GetComponent(k, c);
    if (!(g == w || (std::isnan(g) && std::isnan(w))))
    {
      ++differ;
    }
  }
  EXPECT_EQ(differ, 0);
}

ViewerSession& Session(ViewerSession& s)
{
  std::string error;
  EXPECT_TRUE(s.SetTerrain(TwoBowls(), error)) << error;
  s.Parameters().Latitude = 45.0;
  s.Parameters().Longitude = 6.0;
  return s;
}
} // namespace

TEST(TerroirViewerSession, EveryOverlayOfTheScriptHasARecipe)
{
  // The overlay list (TerroirViewerScript.h) and the session's recipes are one registry: an
  // overlay a script or the window can choose must compute, and no recipe is unreachable.
  std::vector<ViewerOverlay> all;
  for (int k = 0; k < static_cast<int>(ViewerOverlay::Count); ++k)
  {
    all.push_back(static_cast<ViewerOverlay>(k));
  }
  EXPECT_EQ(terroir::viewer::ComputableOverlays(), all);
}

TEST(TerroirViewerSession, StartsDryWithAnEmptyUndoStack)
{
  ViewerSession s;
  Session(s);
  double range[2];
  s.GetWater()->GetRange(range, 0);
  EXPECT_EQ(range[0], 0.0);
  EXPECT_EQ(range[1], 0.0);
  EXPECT_EQ(s.GetUndoDepth(), 0u);
}

/// The cells reached from cell (ci, cj) of `terrain` through 8-connected cells below `level`
/// (at or below when `inclusive`), the start cell included.
std::vector<char> Reached(vtkImageData* terrain, int ci, int cj, double level, bool inclusive)
{
  int dims[3];
  terrain->GetDimensions(dims);
  vtkDataArray* z = terrain->GetPointData()->GetArray("Elevation");
  const int nx = dims[0];
  const int ny = dims[1];
  std::vector<char> seen(static_cast<std::size_t>(nx) * ny, 0);
  auto under = [&](int k)
  {
    const double h = z->GetComponent(k, 0);
    return std::isfinite(h) && (inclusive ? h <= level : h < level);
  };
  std::vector<int> queue{ cj * nx + ci };
  seen[queue[0]] = 1;
  for (std::size_t q = 0; q < queue.size(); ++q)
  {
    const int k = queue[q];
    for (int dj = -1; dj <= 1; ++dj)
    {
      for (int di = -1; di <= 1; ++di)
      {
        const int i = k % nx + di;
        const int j = k / nx + dj;
        if (i >= 0 && j >= 0 && i < nx && j < ny && !seen[j * nx + i] && under(j * nx + i))
        {
          seen[j * nx + i] = 1;
          queue.push_back(j * nx + i);
        }
      }
    }
  }
  return seen;
}

/// The lake a click at cell (ci, cj) makes at `level`, worked out without the flood-fill
/// filter: depth level - z on the cells Reached, 0 elsewhere.
std::vector<double> LakeByBreadthFirst(vtkImageData* terrain,
  int ci,
  int cj,
  double level,
  bool inclusive)
{
  vtkDataArray* z = terrain->GetPointData()->GetArray("Elevation");
  const std::vector<char> seen = Reached(terrain, ci, cj, level, inclusive);
  std::vector<double> depth(seen.size(), 0.0);
  for (std::size_t k = 0; k < seen.size(); ++k)
  {
    depth[k] = seen[k] ? level - z->GetComponent(static_cast<vtkIdType>(k), 0) : 0.0;
  }
  return depth;
}

/// The spill level of the depression holding cell (ci, cj): the lowest level at which the
/// cells reached from it through cells at or below the level include an outlet (an edge cell or
/// a cell next to no data), found by trying every terrain height in increasing order.
double SpillLevel(vtkImageData* terrain, int ci, int cj)
{
  int dims[3];
  terrain->GetDimensions(dims);
  vtkDataArray* z = terrain->GetPointData()->GetArray("Elevation");
  std::vector<double> heights;
  for (vtkIdType k = 0; k < z->GetNumberOfTuples(); ++k)
  {
    if (std::isfinite(z->GetComponent(k, 0)))
    {
      heights.push_back(z->GetComponent(k, 0));
    }
  }
  std::sort(heights.begin(), heights.end());
  auto outlet = [&](int i, int j)
  {
    if (i == 0 || j == 0 || i == dims[0] - 1 || j == dims[1] - 1)
    {
      return true;
    }
    for (int dj = -1; dj <= 1; ++dj)
    {
      for (int di = -1; di <= 1; ++di)
      {
        if (!std::isfinite(z->GetComponent((j + dj) * dims[0] + i + di, 0)))
        {
          return true;
        }
      }
    }
    return false;
  };
  const double start = z->GetComponent(cj * dims[0] + ci, 0);
  for (double level : heights)
  {
    if (level < start)
    {
      continue;
    }
    const std::vector<char> seen = Reached(terrain, ci, cj, level, true);
    for (int k = 0; k < static_cast<int>(seen.size()); ++k)
    {
      if (seen[k] && outlet(k % dims[0], k / dims[0]))
      {
        return level;
      }
    }
  }
  return heights.back();
}

TEST(TerroirViewerSession, FloodFillStopsAtTheSpillLevelAndUndoRestoresTheExactState)
{
  ViewerSession s;
  Session(s);
  vtkImageData* terrain = s.GetTerrain();
  const double z = terrain->GetPointData()->GetArray("Elevation")->GetComponent(12 * 48 + 12, 0);
  const double spill = SpillLevel(terrain, 12, 12);
  // The bowl around (12, 12) is 8 m deep but the plane tilts 0.5 m per cell: it spills over
  // its low (west) rim well below the 5 m of the default LakeDepth.
  ASSERT_LT(spill, z + s.Parameters().LakeDepth);
  ASSERT_GT(spill, z + 1.0);
  const std::vector<float> before = Copy(s.GetWater());
  std::string error;

  // Default LakeDepth: the level stops at the spill level and the lake fills the depression.
  ASSERT_TRUE(s.FloodFillAt(12, 12, error)) << error;
  EXPECT_EQ(s.GetUndoDepth(), 1u);
  const std::vector<double> full = LakeByBreadthFirst(terrain, 12, 12, spill, false);
  int wet = 0;
  for (std::size_t k = 0; k < full.size(); ++k)
  {
    EXPECT_NEAR(s.GetWater()->GetValue(k), full[k], 1e-5) << "cell " << k;
    wet += s.GetWater()->GetValue(k) > 0.0f ? 1 : 0;
  }
  EXPECT_GT(wet, 10);
  EXPECT_LT(wet, 48 * 32 / 4); // the lake stays in its bowl
  EXPECT_FALSE(SameBytes(s.GetWater(), before));
  ASSERT_TRUE(s.Undo());
  EXPECT_TRUE(SameBytes(s.GetWater(), before));
  EXPECT_EQ(s.GetUndoDepth(), 0u);

  // 1 m: below the spill level, the cells reached at or below the cell's height + 1 m.
  s.Parameters().LakeDepth = 1.0;
  ASSERT_TRUE(s.FloodFillAt(12, 12, error)) << error;
  const std::vector<double> shallow = LakeByBreadthFirst(terrain, 12, 12, z + 1.0, true);
  for (std::size_t k = 0; k < shallow.size(); ++k)
  {
    EXPECT_NEAR(s.GetWater()->GetValue(k), shallow[k], 1e-5) << "cell " << k;
  }
  EXPECT_NEAR(s.GetWater()->GetValue(12 * 48 + 12), 1.0, 1e-5);

  // On the plane, far from both bowls, poured water runs off: no lake, no undo step.
  const std::vector<float> state = Copy(s.GetWater());
  EXPECT_FALSE(s.FloodFillAt(24, 28, error));
  EXPECT_EQ(error, "cell (24, 28) is not in a depression: water poured there runs off");
  EXPECT_TRUE(SameBytes(s.GetWater(), state));
  EXPECT_EQ(s.GetUndoDepth(), 1u);
}

TEST(TerroirViewerSession, SeveralUndoStepsRestoreEachEarlierStateInTurn)
{
  ViewerSession s;
  Session(s);
  std::vector<std::vector<float>> states{ Copy(s.GetWater()) };
  std::string error;
  // Each fill changes the state: 1 m in the first bowl (below its spill level), then that bowl
  // to its spill level, then the second bowl.
  const int cells[3][2] = { { 12, 12 }, { 14, 11 }, { 36, 20 } };
  const double depths[3] = { 1.0, 6.0, 3.5 };
  for (int k = 0; k < 3; ++k)
  {
    s.Parameters().LakeDepth = depths[k];
    ASSERT_TRUE(s.FloodFillAt(cells[k][0], cells[k][1], error)) << error;
    states.push_back(Copy(s.GetWater()));
    EXPECT_FALSE(SameBytes(s.GetWater(), states[states.size() - 2])) << "fill " << k;
  }
  EXPECT_EQ(s.GetUndoDepth(), 3u);
  for (int k = 2; k >= 0; --k)
  {
    ASSERT_TRUE(s.Undo());
    EXPECT_TRUE(SameBytes(s.GetWater(), states[k])) << "after undoing fill " << k;
    EXPECT_EQ(s.GetUndoDepth(), static_cast<std::size_t>(k));
  }
}

TEST(TerroirViewerSession, UndoWithAnEmptyStackChangesNothing)
{
  ViewerSession s;
  Session(s);
  std::string error;
  ASSERT_TRUE(s.FloodFillAt(36, 20, error)) << error;
  ASSERT_TRUE(s.Undo());
  const std::vector<float> state = Copy(s.GetWater());
  EXPECT_FALSE(s.Undo());
  EXPECT_FALSE(s.Undo());
  EXPECT_TRUE(SameBytes(s.GetWater(), state));
  EXPECT_EQ(s.GetUndoDepth(), 0u);
}

TEST(TerroirViewerSession, FloodFillOutsideTheTerrainOrOnNoDataChangesNothing)
{
  ViewerSession s;
  Session(s);
  std::string error;
  EXPECT_FALSE(s.FloodFillAt(48, 0, error));
  EXPECT_EQ(error, "cell (48, 0) lies outside the terrain");
  EXPECT_FALSE(s.FloodFillAt(47, 31, error));
  EXPECT_EQ(error, "cell (47, 31) has no data");
  EXPECT_EQ(s.GetUndoDepth(), 0u);
}

TEST(TerroirViewerSession, OverlaysEqualTheFiltersRunDirectly)
{
  ViewerSession s;
  Session(s);
  auto& p = s.Parameters();
  p.Month = 7;
  p.Hour = 15.5;

  OverlayResult slope = s.ComputeOverlay(ViewerOverlay::Slope, p);
  ASSERT_EQ(slope.Error, "");
  EXPECT_EQ(slope.Preset, "Slope");
  vtkNew<vtkTerroirSlope> slopeFilter;
  slopeFilter->SetInputData(s.GetTerrain());
  slopeFilter->Update();
  ExpectSameComponent(
    slope.GetValues(), slopeFilter->GetOutput()->GetPointData()->GetArray("Slope"), 0);

  OverlayResult temperature = s.ComputeOverlay(ViewerOverlay::Temperature, p);
  ASSERT_EQ(temperature.Error, "");
  EXPECT_EQ(temperature.Component, 6); // July
  vtkNew<vtkTerroirTemperature> temperatureFilter;
  temperatureFilter->SetInputData(s.GetTerrain());
  temperatureFilter->SetHemisphereToNorth();
  temperatureFilter->Update();
  ExpectSameComponent(temperature.GetValues(),
    temperatureFilter->GetOutput()->GetPointData()->GetArray("Temperature"),
    6);

  OverlayResult sun = s.ComputeOverlay(ViewerOverlay::Illumination, p);
  ASSERT_EQ(sun.Error, "");
  EXPECT_EQ(sun.Preset, "Sunlit");
  vtkNew<vtkTerroirSolarIllumination> sunFilter;
  sunFilter->SetInputData(s.GetTerrain());
  sunFilter->SetModeToInstant();
  sunFilter->SetLatitude(45.0);
  sunFilter->SetLongitude(6.0);
  sunFilter->SetYear(2025);
  sunFilter->SetMonth(7);
  sunFilter->SetDay(15);
  sunFilter->SetTime(15.5);
  sunFilter->SetUTCOffset(6.0 / 15.0);
  sunFilter->Update();
  ExpectSameComponent(
    sun.GetValues(), sunFilter->GetOutput()->GetPointData()->GetArray("Illuminated"), 0);

  OverlayResult hours = s.ComputeOverlay(ViewerOverlay::SunHours, p);
  ASSERT_EQ(hours.Error, "");
  sunFilter->SetModeToDaily();
  sunFilter->Update();
  ExpectSameComponent(
    hours.GetValues(), sunFilter->GetOutput()->GetPointData()->GetArray("IlluminationHours"), 0);

  OverlayResult humidity = s.ComputeOverlay(ViewerOverlay::Humidity, p);
  ASSERT_EQ(humidity.Error, "");
  vtkNew<vtkTerroirInfiltration> infiltration; // the default recipe
  infiltration->SetInputData(s.GetTerrain());
  vtkNew<vtkTerroirSoilHumidity> humidityFilter;
  humidityFilter->SetInputConnection(infiltration->GetOutputPort());
  humidityFilter->Update();
  ExpectSameComponent(
    humidity.GetValues(), humidityFilter->GetOutput()->GetPointData()->GetArray("SoilHumidity"), 6);
  OverlayResult weighted = s.ComputeOverlay(ViewerOverlay::WeightedHumidity, p);
  ASSERT_EQ(weighted.Error, "");
  EXPECT_EQ(weighted.Component, 6);
  ExpectSameComponent(weighted.GetValues(),
    humidityFilter->GetOutput()->GetPointData()->GetArray("WeightedSoilHumidity"),
    6);

  // The water overlay is the water state itself.
  std::string error;
  ASSERT_TRUE(s.FloodFillAt(12, 12, error)) << error;
  OverlayResult water = s.ComputeOverlay(ViewerOverlay::Water, p);
  ExpectSameComponent(water.GetValues(), s.GetWater(), 0);
}

TEST(TerroirViewerSession, PaintedInfiltrationReachesTheHumidityOverlay)
{
  ViewerSession s;
  Session(s);
  auto& p = s.Parameters();
  const OverlayResult before = s.ComputeOverlay(ViewerOverlay::Humidity, p);
  p.BrushRadius = 2.0;
  p.BrushRate = 0.0;
  EXPECT_EQ(s.PaintInfiltration(20, 16), 13); // the cells within 2 cells of the centre
  EXPECT_EQ(s.GetInfiltration()->GetValue(16 * 48 + 20), 0.0f);
  const OverlayResult after = s.ComputeOverlay(ViewerOverlay::Humidity, p);
  const vtkIdType k = 16 * 48 + 20;
  EXPECT_LT(after.GetValues()->GetComponent(k, 5), before.GetValues()->GetComponent(k, 5));
}

TEST(TerroirViewerSession, WorkerThreadGivesTheSynchronousResultAndKeepsOnlyTheLatestRequest)
{
  ViewerSession s;
  Session(s);
  s.SetCurrentOverlay(ViewerOverlay::Illumination);
  s.Parameters().Hour = 8.0;
  s.RequestOverlay();
  s.Parameters().Hour = 17.0; // asked while the first one may still run
  s.RequestOverlay();
  EXPECT_FALSE(s.IsIdle());
  s.Wait();
  EXPECT_TRUE(s.IsIdle());
  OverlayResult got;
  ASSERT_TRUE(s.TakeOverlay(got));
  EXPECT_FALSE(s.TakeOverlay(got)) << "a result is handed out once";
  ASSERT_EQ(got.Error, "");
  const OverlayResult want = s.ComputeOverlay(ViewerOverlay::Illumination, s.Parameters());
  ExpectSameComponent(got.GetValues(), want.GetValues(), 0);
  // 8:00 and 17:00 shadows differ, so the result is the later request's.
  auto& p = s.Parameters();
  p.Hour = 8.0;
  const OverlayResult morning = s.ComputeOverlay(ViewerOverlay::Illumination, p);
  int differ = 0;
  for (vtkIdType k = 0; k < got.GetValues()->GetNumberOfTuples(); ++k)
  {
    differ += got.GetValues()->GetComponent(k, 0) != morning.GetValues()->GetComponent(k, 0);
  }
  EXPECT_GT(differ, 0);
}

TEST(TerroirViewerSession, WaterFlowReplacesTheWaterStateAndCanBeUndone)
{
  ViewerSession s;
  Session(s);
  s.Parameters().FlowIterations = 50;
  // Soil that takes no rain: the whole month's rain runs off.
  s.Parameters().BrushRadius = 100.0;
  s.Parameters().BrushRate = 0.0;
  const std::vector<float> soil = Copy(s.GetInfiltration());
  EXPECT_EQ(s.PaintInfiltration(24, 16), 48 * 32 - 1);
  const std::vector<float> dry = Copy(s.GetWater());
  s.RequestWaterFlow();
  s.Wait();
  EXPECT_EQ(s.TakeError(), "");
  EXPECT_EQ(s.GetUndoDepth(), 2u); // the paint, the flow
  double range[2];
  s.GetWater()->GetRange(range, 0);
  EXPECT_GT(range[1], 0.0);
  EXPECT_EQ(s.GetDisplayedWater(), s.GetWater()) << "no frame on display after the run";
  EXPECT_EQ(s.GetFlowFrameIteration(), 0);
  ASSERT_TRUE(s.Undo());
  EXPECT_TRUE(SameBytes(s.GetWater(), dry));
  ASSERT_TRUE(s.Undo());
  EXPECT_TRUE(SameBytes(s.GetInfiltration(), soil));
}

TEST(TerroirViewerSession, WaterFlowFramesAreTheStateAfterTheirIterations)
{
  // A larger terrain, so that the run lasts long enough for the frames to be seen.
  ViewerSession s;
  std::string error;
  ASSERT_TRUE(s.SetTerrain(terroir_test::MakeTerrain(240,
                             160,
                             10.0,
                             10.0,
                             [](int i, int j)
                             {
                               const double a = std::hypot(i - 60.0, j - 80.0);
                               return 100.0 + 0.2 * i + 0.1 * std::abs(j - 80) -
                                 6.0 * std::exp(-a * a / 200.0);
                             }),
    error))
    << error;
  auto& p = s.Parameters();
  p.Latitude = 45.0;
  p.Month = 1;
  p.FlowIterations = 400;
  p.FlowFrameInterval = 4;
  p.BrushRadius = 1000.0;
  p.BrushRate = 0.0; // the soil takes no rain
  s.FillInfiltration();
  s.RequestWaterFlow();
  std::vector<long long> iterations;
  std::vector<std::vector<float>> frames;
  while (!s.IsIdle())
  {
    s.Pump();
    const long long k = s.GetFlowFrameIteration();
    if (k > 0 && (iterations.empty() || iterations.back() != k))
    {
      iterations.push_back(k);
      frames.push_back(Copy(s.GetDisplayedWater()));
    }
  }
  EXPECT_EQ(s.TakeError(), "");
  ASSERT_GE(iterations.size(), 1u) << "no frame was seen";
  EXPECT_GE(s.GetFlowFramesPublished(), static_cast<long long>(iterations.size()));
  const std::vector<float> final = Copy(s.GetWater());
  for (std::size_t k = 0; k < iterations.size(); ++k)
  {
    EXPECT_EQ(iterations[k] % 4, 0) << iterations[k];
    EXPECT_TRUE(k == 0 || iterations[k] > iterations[k - 1]);
  }
  // The first and the last frame seen equal runs that stop after their iterations.
  for (std::size_t k : { std::size_t(0), iterations.size() - 1 })
  {
    ViewerSession t;
    ASSERT_TRUE(t.SetTerrain(s.GetTerrain(), error));
    t.Parameters() = p;
    t.Parameters().FlowIterations = static_cast<int>(iterations[k]);
    t.Parameters().FlowFrameInterval = 0;
    t.FillInfiltration();
    t.RequestWaterFlow();
    t.Wait();
    EXPECT_EQ(t.GetFlowFramesPublished(), 0);
    EXPECT_TRUE(SameBytes(t.GetWater(), frames[k])) << "frame of iteration " << iterations[k];
  }
  EXPECT_EQ(s.GetDisplayedWater(), s.GetWater());
  EXPECT_TRUE(SameBytes(s.GetWater(), final));
}

TEST(TerroirViewerSession, ABrushStrokeIsOneUndoStepAndCoversTheCapsuleAroundItsPath)
{
  ViewerSession s;
  Session(s);
  auto& p = s.Parameters();
  p.BrushRadius = 3.0;
  p.BrushRate = 42.0;
  const std::vector<float> before = Copy(s.GetInfiltration());
  const unsigned long version = s.GetInfiltrationVersion();
  s.BeginStroke();
  // A drag from (10, 20) to (30, 20): 21 columns of 7 cells, and at each end the cells of the
  // half disc of radius 3 beyond the column (di = 1: 5 cells, 2: 5, 3: 1), 169 in all.
  EXPECT_EQ(s.PaintInfiltrationAlong(10, 20, 30, 20), 169);
  EXPECT_EQ(s.PaintInfiltrationAlong(30, 20, 30, 26), 7 * 7 + 2 * 11); // on to (30, 26)
  EXPECT_EQ(s.GetUndoDepth(), 0u) << "the stroke is not over";
  EXPECT_GT(s.EndStroke(), 169);
  EXPECT_EQ(s.GetUndoDepth(), 1u);
  EXPECT_NE(s.GetInfiltrationVersion(), version);
  const float* rate = s.GetInfiltration()->GetPointer(0);
  EXPECT_EQ(rate[20 * 48 + 7], 42.0f);  // the tip of the first end
  EXPECT_NE(rate[21 * 48 + 7], 42.0f);  // just outside it (distance sqrt(10))
  EXPECT_EQ(rate[23 * 48 + 20], 42.0f); // 3 cells north of the path
  EXPECT_NE(rate[24 * 48 + 20], 42.0f);
  EXPECT_EQ(rate[29 * 48 + 30], 42.0f); // 3 cells beyond the second segment's end
  // A dab outside a stroke is a step of its own; undo takes the steps back in turn.
  const std::vector<float> afterStroke = Copy(s.GetInfiltration());
  p.BrushRate = 1.0;
  EXPECT_EQ(s.PaintInfiltration(40, 5), 29); // radius 3: 29 cells
  EXPECT_EQ(s.GetUndoDepth(), 2u);
  ASSERT_TRUE(s.Undo());
  EXPECT_TRUE(SameBytes(s.GetInfiltration(), afterStroke));
  ASSERT_TRUE(s.Undo());
  EXPECT_TRUE(SameBytes(s.GetInfiltration(), before));
  // A stroke that changes nothing leaves no step.
  p.BrushRate = 15.0;
  s.BeginStroke();
  s.PaintInfiltration(24, 2); // default recipe: 15 mm/h on these gentle slopes
  EXPECT_EQ(s.EndStroke(), 0);
  EXPECT_EQ(s.GetUndoDepth(), 0u);
}

TEST(TerroirViewerSession, FillAndSlopeRuleChangeTheInfiltrationMapAndAreUndone)
{
  ViewerSession s;
  Session(s);
  auto& p = s.Parameters();
  const std::vector<float> recipe = Copy(s.GetInfiltration());
  p.BrushRate = 7.0;
  const long long filled = s.FillInfiltration();
  int nan = 0, seven = 0;
  for (vtkIdType k = 0; k < s.GetInfiltration()->GetNumberOfValues(); ++k)
  {
    const float v = s.GetInfiltration()->GetValue(k);
    nan += std::isnan(v);
    seven += v == 7.0f;
  }
  EXPECT_EQ(nan, 1) << "the no-data cell keeps no rate";
  EXPECT_EQ(seven, 48 * 32 - 1);
  EXPECT_EQ(filled, 48 * 32 - 1); // every cell had 15 mm/h (no slope over 30 degrees)
  // The slope rule at 4 degrees: 0 exactly where Horn's slope (vtkTerroirSlope) is steeper.
  p.SlopeThreshold = 4.0;
  vtkNew<vtkTerroirSlope> slope;
  slope->SetInputData(s.GetTerrain());
  slope->Update();
  vtkDataArray* degrees = slope->GetOutput()->GetPointData()->GetArray("Slope");
  int steep = 0;
  for (vtkIdType k = 0; k < degrees->GetNumberOfTuples(); ++k)
  {
    steep += degrees->GetComponent(k, 0) > 4.0;
  }
  ASSERT_GT(steep, 20);
  ASSERT_LT(steep, 48 * 32 / 2);
  std::string error;
  EXPECT_EQ(s.ApplySlopeRule(error), steep) << error;
  for (vtkIdType k = 0; k < degrees->GetNumberOfTuples(); ++k)
  {
    const float v = s.GetInfiltration()->GetValue(k);
    if (degrees->GetComponent(k, 0) > 4.0)
    {
      EXPECT_EQ(v, 0.0f) << k;
    }
    else if (!std::isnan(v))
    {
      EXPECT_EQ(v, 7.0f) << k;
    }
  }
  EXPECT_EQ(s.ApplySlopeRule(error), 0) << "a second time changes nothing";
  EXPECT_EQ(s.GetUndoDepth(), 2u);
  ASSERT_TRUE(s.Undo());
  ASSERT_TRUE(s.Undo());
  EXPECT_TRUE(SameBytes(s.GetInfiltration(), recipe));
}

TEST(TerroirViewerSession, ClusterTableHoldsTheMonthsMeansOfEachCluster)
{
  ViewerSession s;
  Session(s);
  auto& p = s.Parameters();
  p.Clusters = 3;
  p.Month = 7;
  const OverlayResult r = s.ComputeOverlay(ViewerOverlay::Clusters, p);
  ASSERT_EQ(r.Error, "");
  ASSERT_NE(r.Table, nullptr);
  const terroir::viewer::ClusterTable table = terroir::viewer::ClusterTable::FromKMeans(r.Table, 7);
  ASSERT_EQ(table.Rows.size(), 3u);
  const std::vector<std::string> columns = { "Slope (\xc2\xb0)",
    "Temp Jul (\xc2\xb0"
    "C)",
    "Sun Jul (h)",
    "Humidity Jul (mm)" };
  ASSERT_EQ(table.Columns.size(), columns.size());
  for (std::size_t c = 0; c < columns.size(); ++c)
  {
    EXPECT_EQ(table.Columns[c], columns[c]);
  }
  // Means recomputed from the overlay's arrays: the cells of each ClusterId.
  vtkPointData* pd = r.Output->GetPointData();
  vtkDataArray* id = pd->GetArray("ClusterId");
  vtkDataArray* features[4] = { pd->GetArray("Slope"),
    pd->GetArray("Temperature"),
    pd->GetArray("IlluminationHours"),
    pd->GetArray("WeightedSoilHumidity") };
  const int component[4] = { 0, 6, 6, 6 };
  double share = 0.0;
  long long cells = 0;
  for (const auto& row : table.Rows)
  {
    double sum[4] = { 0.0, 0.0, 0.0, 0.0 };
    long long n = 0;
    for (vtkIdType k = 0; k < id->GetNumberOfTuples(); ++k)
    {
      if (static_cast<int>(id->GetComponent(k, 0)) == row.Id)
      {
        ++n;
        for (int f = 0; f < 4; ++f)
        {
          sum[f] += features[f]->GetComponent(k, component[f]);
        }
      }
    }
    EXPECT_EQ(row.Cells, n);
    EXPECT_EQ(row.Color.size(), 7u);
    ASSERT_EQ(row.Means.size(), 4u);
    for (int f = 0; f < 4; ++f)
    {
      EXPECT_NEAR(row.Means[f], sum[f] / n, 1e-9 * std::max(1.0, std::fabs(sum[f] / n)));
    }
    share += row.Share;
    cells += row.Cells;
  }
  EXPECT_NEAR(share, 1.0, 1e-12);
  EXPECT_EQ(cells, 48 * 32 - 1);
}

TEST(TerroirViewerSession, ClustersSplitAFlatTerrainWherePaintingChangedTheSoilHumidity)
{
  // A flat terrain has one slope, temperature and sun everywhere: only the soil humidity of
  // the infiltration map can tell cells apart. West of i = 10 the soil takes no water (0 mm/h
  // painted), east of it the default 15 mm/h, more than any month's intensity, so the soil
  // there absorbs every month's rain: July's weighted humidity is
  // R_q(Jul)/2 + R_q(Jun)/3 + R_q(May)/6 (with min(15/R_i, 1) = 1), and 0 in the west.
  ViewerSession s;
  std::string error;
  ASSERT_TRUE(s.SetTerrain(
    terroir_test::MakeTerrain(20, 10, 10.0, 10.0, [](int, int) { return 100.0; }), error))
    << error;
  vtkFloatArray* rate = s.GetInfiltration();
  for (int j = 0; j < 10; ++j)
  {
    for (int i = 0; i < 20; ++i)
    {
      ASSERT_EQ(rate->GetValue(j * 20 + i), 15.0f);
      rate->SetValue(j * 20 + i, i < 10 ? 0.0f : 15.0f);
    }
  }
  auto& p = s.Parameters();
  p.Clusters = 2;
  p.Month = 7;
  const OverlayResult r = s.ComputeOverlay(ViewerOverlay::Clusters, p);
  ASSERT_EQ(r.Error, "");
  vtkDataArray* id = r.Output->GetPointData()->GetArray("ClusterId");
  const int west = static_cast<int>(id->GetComponent(0, 0));
  const int east = static_cast<int>(id->GetComponent(19, 0));
  EXPECT_NE(west, east);
  for (int j = 0; j < 10; ++j)
  {
    for (int i = 0; i < 20; ++i)
    {
      EXPECT_EQ(static_cast<int>(id->GetComponent(j * 20 + i, 0)), i < 10 ? west : east)
        << "cell " << i << ", " << j;
    }
  }
  vtkNew<vtkTerroirSoilHumidity> climate; // its default climate, which the session uses
  const double* rq = climate->GetPrecipitation();
  const double* ri = climate->GetPrecipitationIntensity();
  auto absorbed = [&](int m) { return std::min(15.0 / ri[m], 1.0) * rq[m]; };
  const double wet = absorbed(6) / 2.0 + absorbed(5) / 3.0 + absorbed(4) / 6.0;
  const terroir::viewer::ClusterTable table = terroir::viewer::ClusterTable::FromKMeans(r.Table, 7);
  ASSERT_EQ(table.Columns.size(), 4u);
  EXPECT_EQ(table.Columns[3], "Humidity Jul (mm)");
  ASSERT_EQ(table.Rows.size(), 2u);
  for (const auto& row : table.Rows)
  {
    EXPECT_EQ(row.Cells, 100);
    EXPECT_NEAR(row.Means[3], row.Id == east ? wet : 0.0, 1e-4);
  }

  // The whole table, every month, as CSV: the header names 1 + 3 x 12 feature columns.
  const terroir::viewer::ClusterTable all = terroir::viewer::ClusterTable::FromKMeans(r.Table, 0);
  ASSERT_EQ(all.Columns.size(), 37u);
  EXPECT_EQ(all.Columns[1],
    "Temp Jan (\xc2\xb0"
    "C)");
  EXPECT_EQ(all.Columns[36], "Humidity Dec (mm)");
  const std::string csv = testing::TempDir() + "viewer_clusters.csv";
  ASSERT_TRUE(all.WriteCsv(csv, error)) << error;
  std::ifstream in(csv);
  std::string header, line;
  std::getline(in, header);
  EXPECT_EQ(std::count(header.begin(), header.end(), ','), 4 + 37 - 1);
  EXPECT_EQ(header.rfind("Cluster,Color,Cells,Share,\"Slope (", 0), 0u);
  int rows = 0;
  while (std::getline(in, line))
  {
    ++rows;
    EXPECT_EQ(std::count(line.begin(), line.end(), ','), 4 + 37 - 1);
  }
  EXPECT_EQ(rows, 2);
  EXPECT_FALSE(all.WriteCsv(testing::TempDir() + "no/such/folder/t.csv", error));
  EXPECT_NE(error.find("no/such/folder/t.csv: cannot be written"), std::string::npos);
}

TEST(TerroirViewerSession, ClusterWeightsChooseTheFeatures)
{
  ViewerSession s;
  Session(s);
  auto& p = s.Parameters();
  p.Clusters = 3;
  p.ClusterWeights = { 1.0, 0.0, 0.0, 0.0 }; // slope only
  const OverlayResult r = s.ComputeOverlay(ViewerOverlay::Clusters, p);
  ASSERT_EQ(r.Error, "");
  const terroir::viewer::ClusterTable table = terroir::viewer::ClusterTable::FromKMeans(r.Table, 7);
  ASSERT_EQ(table.Columns.size(), 1u);
  EXPECT_EQ(table.Columns[0], "Slope (\xc2\xb0)");
  // One feature: the clusters are intervals of slope, so sorted by mean they do not overlap.
  vtkPointData* pd = r.Output->GetPointData();
  vtkDataArray* id = pd->GetArray("ClusterId");
  vtkDataArray* slope = pd->GetArray("Slope");
  std::vector<double> lo(3, 1e30), hi(3, -1e30);
  for (vtkIdType k = 0; k < id->GetNumberOfTuples(); ++k)
  {
    const int c = static_cast<int>(id->GetComponent(k, 0));
    if (c >= 0)
    {
      lo[c] = std::min(lo[c], slope->GetComponent(k, 0));
      hi[c] = std::max(hi[c], slope->GetComponent(k, 0));
    }
  }
  std::vector<int> order = { 0, 1, 2 };
  std::sort(order.begin(), order.end(), [&](int a, int b) { return lo[a] < lo[b]; });
  EXPECT_LT(hi[order[0]], lo[order[1]]);
  EXPECT_LT(hi[order[1]], lo[order[2]]);

  p.ClusterWeights = { 0.0, 0.0, 0.0, 0.0 };
  EXPECT_EQ(s.ComputeOverlay(ViewerOverlay::Clusters, p).Error,
    "the clusters need a feature with a weight above 0");
}

TEST(TerroirViewerSession, WaterFlowControlsSetTheWaterTheStopRuleAndTheIterations)
{
  // A closed box: a flat floor at 100 m inside a one-cell rim at 110 m. The border continues
  // the rim's slope upwards, so no water leaves: 50 mm on each of the 20 x 10 cells is
  // 0.05 x 200 = 10 m of depths summed at every iteration. The month's standing water is 0
  // there once 15 mm/h is filled in everywhere, the rim too (it takes every month's rain), so
  // the sum tells the two sources apart.
  ViewerSession s;
  std::string error;
  ASSERT_TRUE(s.SetTerrain(
    terroir_test::MakeTerrain(20,
      10,
      10.0,
      10.0,
      [](int i, int j) { return i == 0 || j == 0 || i == 19 || j == 9 ? 110.0 : 100.0; }),
    error))
    << error;
  auto sum = [](vtkFloatArray* a)
  {
    double total = 0.0;
    for (vtkIdType k = 0; k < a->GetNumberOfValues(); ++k)
    {
      total += a->GetValue(k);
    }
    return total;
  };
  auto& p = s.Parameters();
  p.BrushRate = 15.0;
  s.FillInfiltration();
  p.Month = 7;
  p.FlowIterations = 200;
  s.RequestWaterFlow();
  s.Wait();
  EXPECT_EQ(s.TakeError(), "");
  EXPECT_EQ(sum(s.GetWater()), 0.0);
  p.FlowWater = 50.0;
  s.RequestWaterFlow();
  s.Wait();
  EXPECT_EQ(s.TakeError(), "");
  EXPECT_NEAR(sum(s.GetWater()), 10.0, 1e-4);
  EXPECT_FALSE(s.GetLastFlowStopReason().empty());
  EXPECT_LE(s.GetLastFlowIterations(), 200);

  // The stop rule off and 7 iterations: the run ends after exactly 7, for that reason.
  ViewerSession t;
  Session(t);
  t.Parameters().FlowWater = 50.0;
  t.Parameters().FlowStopRatio = 0.0;
  t.Parameters().FlowIterations = 7;
  t.RequestWaterFlow();
  t.Wait();
  EXPECT_EQ(t.TakeError(), "");
  EXPECT_EQ(t.GetLastFlowIterations(), 7);
  EXPECT_EQ(t.GetLastFlowStopReason(), "MaximumIterations");
}

TEST(TerroirViewerSession, RiverFormingModeFillsTheBowlsToTheirSpillLevelAndBalancesTheRain)
{
  // The river-forming mode fills each depression to its spill level before the rain (found
  // here independently by SpillLevel's search), then rains until the outflow balances it.
  ViewerSession s;
  Session(s);
  auto& p = s.Parameters();
  p.FlowRivers = true;
  p.FlowRainRate = 5.0;
  p.FlowIterations = 100000;
  s.RequestWaterFlow();
  s.Wait();
  ASSERT_EQ(s.TakeError(), "");
  EXPECT_EQ(s.GetLastFlowStopReason(), "Balanced");
  vtkDataArray* z = s.GetTerrain()->GetPointData()->GetArray("Elevation");
  const int bowls[2][2] = { { 12, 12 }, { 36, 20 } };
  for (const auto& c : bowls)
  {
    const vtkIdType k = c[1] * 48 + c[0];
    const double still = SpillLevel(s.GetTerrain(), c[0], c[1]) - z->GetComponent(k, 0);
    EXPECT_GT(still, 1.0);
    EXPECT_GE(s.GetWater()->GetValue(k), still - 1e-3) << "bowl at " << c[0] << ", " << c[1];
  }
}

TEST(TerroirViewerSession, TheSeaFloodsFromTheEdgeUpToItsLevelAndIsUndone)
{
  // A coast rising 1 m per cell to the east (z = i), with a pit of 2 m at (15, 5) far inland.
  // A sea at 5.5 m covers the six western columns with 5.5 - i m of water (60 cells, all
  // connected to the western edge) and leaves the pit dry: it is below the level but walled
  // off by higher ground. Undo gives the dry state back byte for byte.
  ViewerSession s;
  std::string error;
  ASSERT_TRUE(s.SetTerrain(
    terroir_test::MakeTerrain(
      20, 10, 10.0, 10.0, [](int i, int j) { return i == 15 && j == 5 ? 2.0 : double(i); }),
    error))
    << error;
  const std::vector<float> dry = Copy(s.GetWater());
  EXPECT_EQ(s.FloodSea(5.5, error), 60) << error;
  for (int j = 0; j < 10; ++j)
  {
    for (int i = 0; i < 20; ++i)
    {
      EXPECT_FLOAT_EQ(s.GetWater()->GetValue(j * 20 + i), i <= 5 ? 5.5f - i : 0.0f)
        << "cell " << i << ", " << j;
    }
  }
  EXPECT_EQ(s.GetUndoDepth(), 1u);
  ASSERT_TRUE(s.Undo());
  EXPECT_TRUE(SameBytes(s.GetWater(), dry));

  // Below every edge cell: nothing changes, and the message says why.
  EXPECT_EQ(s.FloodSea(-1.0, error), -1);
  EXPECT_EQ(error,
    "no edge cell lies at or below -1.00 m (the lowest is 0.00 m): the sea stays off the map");
  EXPECT_EQ(s.GetUndoDepth(), 0u);
  EXPECT_TRUE(SameBytes(s.GetWater(), dry));
}

TEST(TerroirViewerSession, TheClimateReachesTheOverlaysAndSurvivesItsFile)
{
  // A flat terrain at 1000 m soaking 15 mm/h. July: 100 mm falling at 4 mm/h, all absorbed
  // (15 >= 4), so July's soil humidity is 100 mm. Temperatures from a coldest January at
  // -5 °C and a warmest July at 25 °C, 5 °C/km: at 1000 m January -10, July 20, and April
  // (3 of the 6 months of warming) -5 + 30 x 3/6 - 5 = 5 °C.
  ViewerSession s;
  std::string error;
  ASSERT_TRUE(s.SetTerrain(
    terroir_test::MakeTerrain(8, 6, 10.0, 10.0, [](int, int) { return 1000.0; }), error))
    << error;
  auto& p = s.Parameters();
  p.Precipitation[6] = 100.0;
  p.PrecipitationIntensity[6] = 4.0;
  p.Coldest = -5.0;
  p.Warmest = 25.0;
  p.LapseRate = 5.0;
  p.Month = 7;
  const OverlayResult humidity = s.ComputeOverlay(ViewerOverlay::Humidity, p);
  ASSERT_EQ(humidity.Error, "");
  EXPECT_NEAR(humidity.GetValues()->GetComponent(20, 6), 100.0, 1e-4);
  const OverlayResult temperature = s.ComputeOverlay(ViewerOverlay::Temperature, p);
  ASSERT_EQ(temperature.Error, "");
  vtkDataArray* t = temperature.GetValues();
  EXPECT_NEAR(t->GetComponent(20, 0), -10.0, 1e-4);
  EXPECT_NEAR(t->GetComponent(20, 3), 5.0, 1e-4);
  EXPECT_NEAR(t->GetComponent(20, 6), 20.0, 1e-4);

  // Saved and loaded into another session: the same monthly values, now as 12 sea-level
  // temperatures (January -5, April 10, July 25), so the same overlays.
  const std::string path = testing::TempDir() + "viewer_climate.csv";
  ASSERT_TRUE(s.SaveClimate(path, error)) << error;
  ViewerSession u;
  ASSERT_TRUE(u.SetTerrain(s.GetTerrain(), error)) << error;
  ASSERT_TRUE(u.LoadClimate(path, error)) << error;
  const auto& q = u.Parameters();
  EXPECT_TRUE(q.UseMonthlyTemperatures);
  EXPECT_DOUBLE_EQ(q.MonthlyTemperatures[0], -5.0);
  EXPECT_DOUBLE_EQ(q.MonthlyTemperatures[3], 10.0);
  EXPECT_DOUBLE_EQ(q.MonthlyTemperatures[6], 25.0);
  EXPECT_DOUBLE_EQ(q.Precipitation[6], 100.0);
  EXPECT_DOUBLE_EQ(q.PrecipitationIntensity[6], 4.0);
  u.Parameters().LapseRate = 5.0; // not part of the file
  const OverlayResult again = u.ComputeOverlay(ViewerOverlay::Temperature, u.Parameters());
  ASSERT_EQ(again.Error, "");
  EXPECT_NEAR(again.GetValues()->GetComponent(20, 3), 5.0, 1e-4);

  // A file that is not a climate table: one line naming it, nothing changed.
  const std::string bad = testing::TempDir() + "viewer_bad_climate.csv";
  std::ofstream(bad) << "month,rain\nJan,3\n";
  EXPECT_FALSE(u.LoadClimate(bad, error));
  EXPECT_EQ(error.rfind(bad + ":", 0), 0u) << error;
  EXPECT_EQ(error.find('\n'), std::string::npos);
  EXPECT_DOUBLE_EQ(u.Parameters().Precipitation[6], 100.0);
}

TEST(TerroirViewerSession, RefusesATerrainWithoutElevation)
{
  ViewerSession s;
  vtkNew<vtkImageData> image;
  image->SetDimensions(4, 4, 1);
  std::string error;
  EXPECT_FALSE(s.SetTerrain(image, error));
  EXPECT_EQ(error, "the terrain has no one-component 'Elevation' point array");
}

namespace
{
/// The bed and water of a live erosion as the core computes them after `steps` steps from the
/// session's defaults (Weiss's constants, soil slip every step, closed) with 0.05 m of water.
void ExpectTheCoreAfter(vtkImageData* terrain,
  long long steps,
  vtkFloatArray* bed,
  vtkFloatArray* water)
{
  const vtkIdType n = terrain->GetNumberOfPoints();
  std::vector<float> z(n);
  std::vector<std::uint8_t> valid(n);
  vtkDataArray* e = terrain->GetPointData()->GetArray("Elevation");
  for (vtkIdType k = 0; k < n; ++k)
  {
    z[k] = static_cast<float>(e->GetComponent(k, 0));
    valid[k] = std::isfinite(z[k]) ? 1 : 0;
  }
  terroir::GridView<float> view;
  view.data = z.data();
  view.nx = 48;
  view.ny = 32;
  view.dx = view.dy = 10.0;
  view.valid = valid.data();
  terroir::terrain::ErosionSimulation sim(view, 0.05);
  while (sim.Steps() < steps)
  {
    sim.Step(terroir::terrain::ErosionSimulationParams());
  }
  const terroir::terrain::ErosionState& s = sim.State();
  int differ = 0;
  for (vtkIdType k = 0; k < n; ++k)
  {
    const float b = static_cast<float>(double(s.terrain[k]) + double(s.terrainResidue[k]));
    const float w = static_cast<float>(double(s.water[k]) + double(s.waterResidue[k]));
    differ += (b != bed->GetValue(k) || w != water->GetValue(k)) ? 1 : 0;
  }
  EXPECT_EQ(differ, 0) << "of " << n << " cells after " << steps << " steps";
}

/// Sum of the bed (or water) over the cells with data, times the cell area 100 m^2.
double Volume(vtkFloatArray* a, vtkImageData* terrain)
{
  vtkDataArray* e = terrain->GetPointData()->GetArray("Elevation");
  double v = 0.0;
  for (vtkIdType k = 0; k < a->GetNumberOfValues(); ++k)
  {
    v += std::isfinite(e->GetComponent(k, 0)) ? 100.0 * a->GetValue(k) : 0.0;
  }
  return v;
}
} // namespace

TEST(TerroirViewerSession, LiveErosionIsTheCoreSimulationStepForStep)
{
  ViewerSession s;
  std::string error;
  vtkSmartPointer<vtkImageData> terrain = TwoBowls();
  ASSERT_TRUE(s.SetTerrain(terrain, error)) << error;
  s.Parameters().ErosionInitialWater = 0.05;
  EXPECT_FALSE(s.PaintErosion(5, 5)); // nothing runs yet
  ASSERT_TRUE(s.StartErosion(error)) << error;
  EXPECT_TRUE(s.IsEroding());
  EXPECT_FALSE(s.StartErosion(error));
  EXPECT_EQ(error, "an erosion run is under way (stop it first)");
  ASSERT_TRUE(s.WaitErosionSteps(12, 120.0));
  s.StopErosion();
  EXPECT_FALSE(s.IsEroding());
  const long long steps = s.GetErosionSteps();
  EXPECT_GE(steps, 12);
  ASSERT_NE(s.GetErosionBed(), nullptr);
  ASSERT_NE(s.GetErosionWater(), nullptr);
  EXPECT_EQ(s.GetErosionVegetation(), nullptr);
  EXPECT_EQ(s.GetDisplayedWater(), s.GetErosionWater());
  ExpectTheCoreAfter(terrain, steps, s.GetErosionBed(), s.GetErosionWater());
}

TEST(TerroirViewerSession, ErosionBrushesPaintSoilAndWaterAndKeepingMakesTheBedTheTerrain)
{
  ViewerSession s;
  std::string error;
  vtkSmartPointer<vtkImageData> terrain = TwoBowls();
  ASSERT_TRUE(s.SetTerrain(terrain, error)) << error;
  auto& p = s.Parameters();
  p.BrushRadius = 4.0;
  p.ErosionInitialWater = 0.05;
  ASSERT_TRUE(s.StartErosion(error)) << error;
  ASSERT_TRUE(s.WaitErosionSteps(2, 120.0));
  // At the start: 0.05 m of water on each of the 1535 cells with data, and the terrain.
  vtkNew<vtkFloatArray> start;
  start->DeepCopy(terrain->GetPointData()->GetArray("Elevation"));
  const double water0 = 1535 * 100.0 * static_cast<double>(0.05f);
  const double bed0 = Volume(start, terrain);
  p.ErosionBrush = 0; // soil: a 3 m mound at (24, 16), on the ridge between the bowls
  p.ErosionAmount = 3.0;
  ASSERT_TRUE(s.PaintErosion(24.0, 16.0));
  p.ErosionBrush = 1; // water: 0.4 m around (12, 12), the west bowl
  p.ErosionAmount = 0.4;
  ASSERT_TRUE(s.PaintErosion(12.0, 12.0));
  ASSERT_TRUE(s.WaitErosionSteps(s.GetErosionSteps() + 3, 120.0));
  s.StopErosion();
  // A dab of radius 4 puts amount x sum of (1 + cos(pi r / 4)) / 2 over the cells with r < 4.
  double weights = 0.0;
  for (int dj = -3; dj <= 3; ++dj)
  {
    for (int di = -3; di <= 3; ++di)
    {
      const double r = std::hypot(di, dj);
      weights += r < 4.0 ? 0.5 * (1.0 + std::cos(3.14159265358979 * r / 4.0)) : 0.0;
    }
  }
  // The water: evaporation takes the fraction K_e dt = 5e-5 of every cell's water a step, so
  // after N steps, with the dab D at an unknown step, (W0 + D) f^N <= W <= W0 f^N + D,
  // f = 1 - 5e-5.
  const double dab = 0.4 * 100.0 * weights;
  const double f = std::pow(1.0 - 5e-5, static_cast<double>(s.GetErosionSteps()));
  const double water = Volume(s.GetErosionWater(), terrain);
  EXPECT_GE(water, (water0 + dab) * f * (1.0 - 1e-6));
  EXPECT_LE(water, (water0 * f + dab) * (1.0 + 1e-6));
  EXPECT_GT(dab, 0.1 * water0 * (1.0 - f)); // the test can tell the dab from evaporation
  // The material: bed and suspended sediment change by the mound alone (closed domain).
  const double mound = 3.0 * 100.0 * weights;
  const double material =
    Volume(s.GetErosionBed(), terrain) + Volume(s.GetErosionSediment(), terrain);
  EXPECT_NEAR(material, bed0 + mound, 1e-6 * bed0);
  EXPECT_GT(mound, 10.0 * 1e-6 * bed0); // the test can tell the mound from rounding
  vtkFloatArray* bed = s.GetErosionBed();
  const std::vector<float> last = Copy(bed);

  ASSERT_TRUE(s.KeepErosion(error)) << error;
  EXPECT_FALSE(s.IsEroding());
  EXPECT_EQ(s.GetErosionBed(), nullptr);
  vtkDataArray* kept = s.GetTerrain()->GetPointData()->GetArray("Elevation");
  int differ = 0;
  for (vtkIdType k = 0; k + 1 < kept->GetNumberOfTuples(); ++k) // the last cell has no data
  {
    differ += kept->GetComponent(k, 0) == last[k] ? 0 : 1;
  }
  EXPECT_EQ(differ, 0);
  EXPECT_TRUE(std::isnan(kept->GetComponent(47 + 31 * 48, 0)));
  EXPECT_EQ(s.GetDisplayedWater(), s.GetWater()); // dry again: the water starts over
  EXPECT_FALSE(s.KeepErosion(error));
  EXPECT_EQ(error, "no erosion to keep (start one first)");
}

// The window-free model of `terroir view` (Applications/TerroirViewerSession.h): the water
// state and its undo stack (restored byte for byte), the overlays against the filters run
// directly, and the worker thread against the synchronous path.
#include "TerroirFilterTestUtilities.h"
#include "TerroirViewerSession.h"

#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkTerroirFloodFill.h"
#include "vtkTerroirInfiltration.h"
#include "vtkTerroirSlope.h"
#include "vtkTerroirSoilHumidity.h"
#include "vtkTerroirSolarIllumination.h"
#include "vtkTerroirTemperature.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
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

TEST(TerroirViewerSession, FloodFillMakesTheFiltersLakeAndUndoRestoresTheExactState)
{
  ViewerSession s;
  Session(s);
  const std::vector<float> before = Copy(s.GetWater());
  std::string error;
  ASSERT_TRUE(s.FloodFillAt(12, 12, error)) << error;
  EXPECT_EQ(s.GetUndoDepth(), 1u);
  // The lake is vtkTerroirFloodFill's, seeded at the cell with level = elevation + LakeDepth.
  vtkNew<vtkTerroirFloodFill> flood;
  flood->SetInputData(s.GetTerrain());
  const double z =
    s.GetTerrain()->GetPointData()->GetArray("Elevation")->GetComponent(12 * 48 + 12, 0);
  flood->AddSeedCell(12, 12, z + s.Parameters().LakeDepth);
  flood->Update();
  vtkDataArray* depth = flood->GetOutput()->GetPointData()->GetArray("WaterDepth");
  int wet = 0;
  for (vtkIdType k = 0; k < depth->GetNumberOfTuples(); ++k)
  {
    const double d = depth->GetComponent(k, 0);
    EXPECT_EQ(s.GetWater()->GetValue(k), static_cast<float>(std::isfinite(d) ? d : 0.0));
    wet += s.GetWater()->GetValue(k) > 0.0f ? 1 : 0;
  }
  EXPECT_GT(wet, 10);
  EXPECT_FALSE(SameBytes(s.GetWater(), before));
  ASSERT_TRUE(s.Undo());
  EXPECT_TRUE(SameBytes(s.GetWater(), before));
  EXPECT_EQ(s.GetUndoDepth(), 0u);
}

TEST(TerroirViewerSession, SeveralUndoStepsRestoreEachEarlierStateInTurn)
{
  ViewerSession s;
  Session(s);
  std::vector<std::vector<float>> states{ Copy(s.GetWater()) };
  std::string error;
  // Each fill reaches higher than the one before, so each changes the state.
  const int cells[3][2] = { { 12, 12 }, { 14, 11 }, { 36, 20 } };
  const double depths[3] = { 2.0, 6.0, 3.5 };
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
  EXPECT_EQ(s.PaintInfiltration(24, 16), 48 * 32 - 1);
  const std::vector<float> dry = Copy(s.GetWater());
  s.RequestWaterFlow();
  s.Wait();
  EXPECT_EQ(s.TakeError(), "");
  EXPECT_EQ(s.GetUndoDepth(), 1u);
  double range[2];
  s.GetWater()->GetRange(range, 0);
  EXPECT_GT(range[1], 0.0);
  ASSERT_TRUE(s.Undo());
  EXPECT_TRUE(SameBytes(s.GetWater(), dry));
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

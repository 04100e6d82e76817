// Image regression tests of the terrain generators' overlays (issue 26; label rendering, run
// under xvfb-run -a): Weiss's polygon-map island, Jensen's RiverLand and Weiss's feature
// curves, each at a small size, rendered at 400 x 400 and compared with
// Testing/Baselines/TerroirGeneratorImages_<Test>.png (TerroirImageCompare.h). Each test also
// checks a number of the generated terrain that does not depend on the rendering.
#include "TerroirFeatureCurveScenes.h"
#include "TerroirRenderingTestHelpers.h"

#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkTerroirFeatureCurveTerrain.h"
#include "vtkTerroirOverlayView.h"
#include "vtkTerroirPolygonIslandSource.h"
#include "vtkTerroirRiverLandSource.h"
#include "vtkUnsignedCharArray.h"

#include <gtest/gtest.h>

using terroir::testing::CompareWithBaseline;

// The island (seed 3, 192 x 192 cells of 30 m): its biomes as a flat map (vertical exaggeration
// 0: the island's rough relief leaves no smooth patch for CompareWithBaseline's shading probes),
// one colour per biome code (the Clusters preset), uniform over whole Voronoi regions. Land is a
// share of the map between the sea around it and the whole (WaterClass 0), as the island rule makes
// it.
TEST(TerroirGeneratorImages, IslandBiomesMap)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  vtkNew<vtkTerroirPolygonIslandSource> island;
  island->SetDimensions(192, 192);
  island->SetSeed(3);
  island->SetRegions(400);
  island->Update();
  vtkImageData* out = island->GetOutput();
  vtkDataArray* water = out->GetPointData()->GetArray("WaterClass");
  ASSERT_NE(water, nullptr);
  long long land = 0;
  for (vtkIdType k = 0; k < water->GetNumberOfTuples(); ++k)
  {
    land += water->GetComponent(k, 0) == 0.0 ? 1 : 0;
  }
  const double share = static_cast<double>(land) / static_cast<double>(water->GetNumberOfTuples());
  EXPECT_GT(share, 0.15);
  EXPECT_LT(share, 0.85);
  vtkNew<vtkTerroirOverlayView> view;
  view->SetInputData(out);
  view->SetArrayName("Biome");
  view->SetPreset("Clusters");
  view->SetModeToMap();
  view->SetVerticalExaggeration(0.0);
  view->ShowLegendOff();
  CompareWithBaseline(view);
}

// RiverLand (seed 1, 192 x 192 cells of 30 m): its rivers, top-down with the Rivers preset.
// Rivers are lines: a few per cent of the cells.
TEST(TerroirGeneratorImages, RiverLandRiversMap)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  vtkNew<vtkTerroirRiverLandSource> source;
  source->SetDimensions(192, 192);
  source->SetSeed(1);
  source->Update();
  vtkImageData* out = source->GetOutput();
  vtkDataArray* river = out->GetPointData()->GetArray("River");
  ASSERT_NE(river, nullptr);
  vtkNew<vtkUnsignedCharArray> network;
  network->SetName("RiverNetwork");
  network->SetNumberOfTuples(river->GetNumberOfTuples());
  long long cells = 0;
  for (vtkIdType k = 0; k < river->GetNumberOfTuples(); ++k)
  {
    const bool r = river->GetComponent(k, 0) != 0.0;
    network->SetValue(k, r ? 1 : 0);
    cells += r ? 1 : 0;
  }
  EXPECT_GT(cells, 192 * 2);
  EXPECT_LT(cells, 192 * 192 / 5);
  auto picture = vtkSmartPointer<vtkImageData>::New();
  picture->ShallowCopy(out);
  picture->GetPointData()->AddArray(network);
  vtkNew<vtkTerroirOverlayView> view;
  view->SetInputData(picture);
  view->SetArrayName("RiverNetwork");
  view->SetPreset("Rivers");
  view->SetModeToMap();
  view->ShowLegendOff();
  CompareWithBaseline(view);
}

// Feature curves (the tests' ridge and valley, 131 x 101 cells of 10 m, CPU): the terrain in
// relief. The ridge's plateau holds its control points' heights: the cell at the middle
// control point (500, 700) m is at its 450 m (within 5 cm: the solve stops when a V-cycle
// changes no height by more than 1 mm, measured 1 cm short).
TEST(TerroirGeneratorImages, FeatureCurvesRelief)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  vtkNew<vtkTerroirFeatureCurveTerrain> terrain;
  terrain->SetInputData(terroir_test::RidgeAndValley());
  terrain->SetDimensions(131, 101);
  terrain->SetSpacing(10.0);
  terrain->SetBackend(1); // CPU
  terrain->Update();
  vtkDataArray* z = terrain->GetOutput()->GetPointData()->GetArray("Elevation");
  ASSERT_NE(z, nullptr);
  int ijk[3] = { 50, 70, 0 };
  EXPECT_NEAR(z->GetComponent(terrain->GetOutput()->ComputePointId(ijk), 0), 450.0, 0.05);
  vtkNew<vtkTerroirOverlayView> view;
  view->SetInputData(terrain->GetOutput());
  view->SetArrayName("Elevation");
  view->SetModeToRelief();
  view->ShowLegendOff();
  CompareWithBaseline(view);
}

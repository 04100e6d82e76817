// Image regression tests of the erosion and vegetation overlays (issue 27; label rendering, run
// under xvfb-run -a): vtkTerroirErosion's ErosionDepth on a hill with the Erosion preset and its
// VegetationDensity in a bowl with the Vegetation preset, rendered at 400 x 400 and compared
// with Testing/Baselines/TerroirErosionImages_<Test>.png (TerroirImageCompare.h). The tests also
// check numbers that do not depend on the rendering.
#include "TerroirRenderingTestHelpers.h"
#include "TerroirSyntheticTerrain.h"

#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkTerroirErosion.h"
#include "vtkTerroirOverlayView.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using terroir::testing::CompareWithBaseline;

namespace
{
/// 96 x 96 points 5 m apart on a plain at 100 m with a Gaussian of `height` m (negative: a
/// bowl) and `sigma` cells at the centre (47.5, 47.5).
vtkSmartPointer<vtkImageData> Gaussian(double height, double sigma)
{
  return terroir::testing::MakeTerrain(96,
    96,
    5.0,
    [=](double x, double y)
    {
      const double i = x / 5.0, j = y / 5.0;
      const double r2 = (i - 47.5) * (i - 47.5) + (j - 47.5) * (j - 47.5);
      return 100.0 + height * std::exp(-r2 / (2.0 * sigma * sigma));
    });
}
} // namespace

// A round island (Gaussian, 30 m high, 5 m cells, 96 x 96) in a sea 1 cm above the plain
// (100 m), 0.3 m of water and 60 steps of 0.5 s with soil slip. Water runs off the island: its
// flanks lose material (brown), its shore gains what the sea lets settle (blue-green), the sea
// floor beyond stays as it was (white: the uniform patches the shading probes need).
TEST(TerroirErosionImages, IslandErosionRelief)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  vtkSmartPointer<vtkImageData> terrain = Gaussian(30.0, 12.0);
  vtkNew<vtkTerroirErosion> erosion;
  erosion->SetInputData(terrain);
  erosion->SetSteps(60);
  erosion->SetTimeStep(0.5);
  erosion->SetInitialWater(0.3);
  erosion->SetBoundary(vtkTerroirErosion::Sea);
  erosion->SetSeaLevel(100.01);
  erosion->Update();
  vtkImageData* out = erosion->GetOutput();
  vtkDataArray* change = out->GetPointData()->GetArray("ErosionDepth");
  ASSERT_NE(change, nullptr);
  // The island's flank (12 cells from the top, where the Gaussian is steepest) loses decimetres;
  // the sea floor's corner does not change.
  const double flank = change->GetComponent(47 * 96 + 47 + 12, 0);
  EXPECT_LT(flank, -0.1);
  EXPECT_EQ(change->GetComponent(2 * 96 + 2, 0), 0.0);
  vtkNew<vtkTerroirOverlayView> view;
  view->SetInputData(out);
  view->SetArrayName("ErosionDepth");
  view->SetPreset("Erosion");
  view->SetModeToRelief();
  view->ShowLegendOff();
  CompareWithBaseline(view);
}

// Dunn's vegetation after erosion on a closed bowl (96 x 96 cells of 5 m, 20 m deep, sides
// rising to the rim), 0.05 m of water everywhere (below the drowning depth, 0.1 m) and half cover
// at the start, 40 steps of 0.5 s: the water runs down into the bottom of the bowl, where it
// gathers deeper than 0.1 m and the plants drown (density falls by r_drown dt = 0.25 a step),
// while on the sides they drink the water that passes and grow (g dt = 0.025 a step). The
// Vegetation preset shows a bare sand patch at the bottom and green sides.
TEST(TerroirErosionImages, VegetationInABowlRelief)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  vtkSmartPointer<vtkImageData> terrain = Gaussian(-20.0, 18.0);
  vtkNew<vtkTerroirErosion> erosion;
  erosion->SetInputData(terrain);
  erosion->SetSteps(40);
  erosion->SetTimeStep(0.5);
  erosion->SetInitialWater(0.05);
  erosion->VegetationOn();
  erosion->SetInitialVegetation(0.5);
  const vtkIdType bottom = 47 * 96 + 47, side = 47 * 96 + 47 + 24;
  // After 10 steps the water has gathered at the bottom, deeper than the drowning depth.
  erosion->UpdateTimeStep(10.0);
  EXPECT_GT(
    erosion->GetOutput()->GetPointData()->GetArray("ErosionWaterDepth")->GetComponent(bottom, 0),
    0.1);
  erosion->UpdateTimeStep(40.0);
  vtkImageData* out = erosion->GetOutput();
  vtkDataArray* plants = out->GetPointData()->GetArray("VegetationDensity");
  ASSERT_NE(plants, nullptr);
  double lo = 1.0, hi = 0.0;
  for (vtkIdType k = 0; k < plants->GetNumberOfTuples(); ++k)
  {
    lo = std::min(lo, plants->GetComponent(k, 0));
    hi = std::max(hi, plants->GetComponent(k, 0));
  }
  EXPECT_GE(lo, 0.0);
  EXPECT_LE(hi, 1.0);
  // The bottom of the bowl lost its plants; a cell on the side (24 cells out) has more than at
  // the start.
  EXPECT_LT(plants->GetComponent(bottom, 0), 0.05);
  EXPECT_GT(plants->GetComponent(side, 0), 0.5);
  vtkNew<vtkTerroirOverlayView> view;
  view->SetInputData(out);
  view->SetArrayName("VegetationDensity");
  view->SetPreset("Vegetation");
  view->SetModeToRelief();
  view->ShowLegendOff();
  CompareWithBaseline(view);
}

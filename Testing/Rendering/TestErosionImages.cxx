// Image regression test of the erosion overlay (issue 27; label rendering, run under
// xvfb-run -a): vtkTerroirErosion's ErosionDepth on a hill with the Erosion preset, rendered at
// 400 x 400 and compared with Testing/Baselines/TerroirErosionImages_<Test>.png
// (TerroirImageCompare.h). The test also checks numbers that do not depend on the rendering.
#include "TerroirRenderingTestHelpers.h"

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

#include <cmath>

using terroir::testing::CompareWithBaseline;

// A round island (Gaussian, 30 m high, 5 m cells, 96 x 96) in a sea 1 cm above the plain
// (100 m), 0.3 m of water and 60 steps of 0.5 s with soil slip. Water runs off the island: its
// flanks lose material (brown), its shore gains what the sea lets settle (blue-green), the sea
// floor beyond stays as it was (white: the uniform patches the shading probes need).
TEST(TerroirErosionImages, IslandErosionRelief)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  auto terrain = vtkSmartPointer<vtkImageData>::New();
  terrain->SetDimensions(96, 96, 1);
  terrain->SetSpacing(5.0, 5.0, 1.0);
  auto z = vtkSmartPointer<vtkFloatArray>::New();
  z->SetName("Elevation");
  for (int j = 0; j < 96; ++j)
  {
    for (int i = 0; i < 96; ++i)
    {
      const double r2 = (i - 47.5) * (i - 47.5) + (j - 47.5) * (j - 47.5);
      z->InsertNextValue(static_cast<float>(100.0 + 30.0 * std::exp(-r2 / (2.0 * 12.0 * 12.0))));
    }
  }
  terrain->GetPointData()->AddArray(z);
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

// Image regression test of plants over their zones (issue 27; label rendering, run under
// xvfb-run -a): vtkTerroirPlantPlacement's points drawn as cone glyphs by
// vtkTerroirOverlayView (SetPlantsData) over the zones' Clusters overlay, at 400 x 400, against
// Testing/Baselines/TerroirPlantImages_<Test>.png (TerroirImageCompare.h).
#include "TerroirRenderingTestHelpers.h"

#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkTerroirOverlayView.h"
#include "vtkTerroirPlantPlacement.h"

#include <gtest/gtest.h>

using terroir::testing::CompareWithBaseline;

// A plane rising 0.2 m per metre to the north (96 x 96 cells of 5 m), zone 0 in the west half
// and zone 1 in the east, plants at 0.0015 per m^2 no closer than 12 m (a hard-core pattern,
// seed 4): green cones stand in both halves and not on the strip of no zone along the south
// edge. In relief, where the cones show their height.
TEST(TerroirPlantImages, PlantsOverZonesRelief)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  auto zones = vtkSmartPointer<vtkImageData>::New();
  zones->SetDimensions(96, 96, 1);
  zones->SetSpacing(5.0, 5.0, 1.0);
  auto z = vtkSmartPointer<vtkFloatArray>::New();
  z->SetName("Elevation");
  auto id = vtkSmartPointer<vtkIntArray>::New();
  id->SetName("ClusterId");
  for (int j = 0; j < 96; ++j)
  {
    for (int i = 0; i < 96; ++i)
    {
      z->InsertNextValue(static_cast<float>(100.0 + 0.2 * 5.0 * j));
      id->InsertNextValue(j < 8 ? -1 : (i < 48 ? 0 : 1));
    }
  }
  zones->GetPointData()->AddArray(z);
  zones->GetPointData()->AddArray(id);
  vtkNew<vtkTerroirPlantPlacement> plants;
  plants->SetInputData(zones);
  plants->SetDensity(0.0015);
  plants->SetMinimumDistance(12.0);
  plants->SetSeed(4);
  plants->Update();
  vtkPolyData* out = plants->GetOutput();
  // Zones of 88 x 48 cells of 25 m^2 each: about 0.0015 x 105,600 m^2 = 158 plants apiece.
  EXPECT_GT(out->GetNumberOfPoints(), 200);
  EXPECT_LT(out->GetNumberOfPoints(), 400);
  vtkNew<vtkTerroirOverlayView> view;
  view->SetInputData(zones);
  view->SetArrayName("ClusterId");
  view->SetPreset("Clusters");
  view->SetPlantsData(out);
  view->SetPlantSize(15.0);
  view->SetModeToRelief();
  view->ShowLegendOff();
  CompareWithBaseline(view);
}

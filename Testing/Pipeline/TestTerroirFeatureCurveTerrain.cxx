// vtkTerroirFeatureCurveTerrain: the VTK contract (arrays, units, grid, base composition,
// errors) and the answers of known scenes through the pipeline.
#include "TerroirFeatureCurveScenes.h"

#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkPointData.h"
#include "vtkTerroirFeatureCurveTerrain.h"

#include <gtest/gtest.h>

#include <cmath>

using terroir_test::CurvePoint;
using terroir_test::FeatureCurvesPolyData;

namespace
{
double At(vtkImageData* image, const char* name, int i, int j)
{
  const int nx = image->GetDimensions()[0];
  return image->GetPointData()->GetArray(name)->GetComponent(static_cast<vtkIdType>(j) * nx + i, 0);
}
} // namespace

TEST(TerroirFeatureCurveTerrain, RidgeAndValleyGrid)
{
  vtkNew<vtkTerroirFeatureCurveTerrain> f;
  f->SetBackend(1);
  f->SetCurvesData(terroir_test::RidgeAndValley());
  f->SetDimensions(131, 101);
  f->SetSpacing(10.0);
  f->SetOrigin(0.0, 0.0);
  f->Update();
  vtkImageData* out = f->GetOutput();
  ASSERT_STREQ(f->GetErrorMessage(), "");
  int dims[3];
  out->GetDimensions(dims);
  EXPECT_EQ(dims[0], 131);
  EXPECT_EQ(dims[1], 101);
  EXPECT_EQ(out->GetSpacing()[0], 10.0);
  vtkDataArray* e = out->GetPointData()->GetArray("Elevation");
  ASSERT_NE(e, nullptr);
  EXPECT_TRUE(vtkFloatArray::SafeDownCast(e) != nullptr);
  EXPECT_STREQ(e->GetInformation()->Get(vtkDataArray::UNITS_LABEL()), "m");
  EXPECT_EQ(out->GetPointData()->GetScalars(), e);
  ASSERT_NE(out->GetPointData()->GetArray("FeatureKind"), nullptr);
  EXPECT_TRUE(f->GetLastConverged());
  EXPECT_EQ(f->GetLastBackend(), 1);
  EXPECT_LE(f->GetLastChange(), 1e-3);
  EXPECT_GT(f->GetLastLevels(), 3);
  // The control points lie on plateaus held at their elevation (alpha = 0.9 lets the plateau
  // sag by a fraction of a metre where slopes pull at it).
  EXPECT_EQ(At(out, "FeatureKind", 50, 70), 1.0);
  EXPECT_NEAR(At(out, "Elevation", 50, 70), 450.0, 1.0);
  EXPECT_NEAR(At(out, "Elevation", 10, 20), 300.0, 1.0);
  EXPECT_NEAR(At(out, "Elevation", 15, 90), 80.0, 1.0);
  // The ridge falls away on both sides and the valley rises from its floor.
  EXPECT_LT(At(out, "Elevation", 50, 55), At(out, "Elevation", 50, 70) - 50.0);
  EXPECT_GT(At(out, "Elevation", 60, 80), 80.0);
}

// A straight ridge with a hard plateau (PlateauWeight 1) across a 10 m grid: 100 m on the
// plateau, then 45 degrees (10 m per cell) down the slope (see TestFeatureCurves.cxx).
TEST(TerroirFeatureCurveTerrain, StraightRidgeProfile)
{
  vtkNew<vtkTerroirFeatureCurveTerrain> f;
  f->SetBackend(1);
  f->SetCurvesData(FeatureCurvesPolyData(
    { { { 320, -10000, 100, 100, 45, 200, -1 }, { 320, 10000, 100, 100, 45, 200, -1 } } }));
  f->SetDimensions(65, 9);
  f->SetSpacing(10.0);
  f->SetPlateauWeight(1.0);
  f->SetTolerance(1e-6);
  f->Update();
  vtkImageData* out = f->GetOutput();
  for (int i = 27; i <= 37; ++i)
  {
    EXPECT_FLOAT_EQ(At(out, "Elevation", i, 4), 100.0) << i;
  }
  for (int d = 6; d <= 16; ++d)
  {
    EXPECT_NEAR(At(out, "Elevation", 32 + d - 1, 4) - At(out, "Elevation", 32 + d, 4), 10.0, 1e-3);
    EXPECT_NEAR(At(out, "Elevation", 32 - d + 1, 4) - At(out, "Elevation", 32 - d, 4), 10.0, 1e-3);
  }
}

// Over a base terrain the output takes the base's grid and arrays, and cells outside the
// curve's envelope keep the base's heights exactly (Weiss's bounded smoothing, eq. 9).
TEST(TerroirFeatureCurveTerrain, BaseOutsideTheEnvelopeIsKept)
{
  vtkNew<vtkImageData> base;
  base->SetDimensions(80, 60, 1);
  base->SetSpacing(5.0, 5.0, 1.0);
  base->SetOrigin(1000.0, 2000.0, 0.0);
  vtkNew<vtkFloatArray> e;
  e->SetName("Elevation");
  e->SetNumberOfTuples(80 * 60);
  vtkNew<vtkFloatArray> other;
  other->SetName("Other");
  other->SetNumberOfTuples(80 * 60);
  for (int k = 0; k < 80 * 60; ++k)
  {
    e->SetValue(k, static_cast<float>(50.0 + 0.5 * (k % 80) + 0.25 * (k / 80)));
    other->SetValue(k, static_cast<float>(k));
  }
  base->GetPointData()->SetScalars(e);
  base->GetPointData()->AddArray(other);
  vtkNew<vtkTerroirFeatureCurveTerrain> f;
  f->SetBackend(1);
  f->SetCurvesData(FeatureCurvesPolyData(
    { { { 1100, 2050, 120, 10, 30, 25, 20 }, { 1300, 2200, 140, 10, 30, 25, 20 } } }));
  f->SetBaseData(base);
  f->SetTolerance(1e-5);
  f->Update();
  vtkImageData* out = f->GetOutput();
  ASSERT_STREQ(f->GetErrorMessage(), "");
  EXPECT_EQ(out->GetDimensions()[0], 80);
  EXPECT_EQ(out->GetOrigin()[0], 1000.0);
  ASSERT_NE(out->GetPointData()->GetArray("Other"), nullptr);
  // Reach of the curve: plateau 5 + slope 25 + envelope 20 = 50 m from the segment.
  const double ax = 1100, ay = 2050, bx = 1300, by = 2200;
  int kept = 0, changed = 0;
  for (int j = 0; j < 60; ++j)
  {
    for (int i = 0; i < 80; ++i)
    {
      const double x = 1000.0 + 5.0 * i, y = 2000.0 + 5.0 * j;
      const double ex = bx - ax, ey = by - ay;
      double u = ((x - ax) * ex + (y - ay) * ey) / (ex * ex + ey * ey);
      u = std::min(1.0, std::max(0.0, u));
      const double d = std::hypot(x - ax - u * ex, y - ay - u * ey);
      const double b = e->GetValue(j * 80 + i), o = At(out, "Elevation", i, j);
      if (d > 50.5)
      {
        EXPECT_EQ(o, b) << i << ", " << j;
        ++kept;
      }
      else if (std::abs(o - b) > 1.0)
      {
        ++changed;
      }
    }
  }
  EXPECT_GT(kept, 1000);
  EXPECT_GT(changed, 200);
  EXPECT_NEAR(At(out, "Elevation", 20, 10), 120.0, 1.0); // the first control point
}

TEST(TerroirFeatureCurveTerrain, BadCurvesAreAnError)
{
  vtkNew<vtkTerroirFeatureCurveTerrain> f;
  f->SetBackend(1);
  f->SetCurvesData(FeatureCurvesPolyData({ { { 10, 10, 5, 0, 0, 0, -1 } } }));
  f->SetDimensions(16, 16);
  f->Update();
  EXPECT_NE(std::string(f->GetErrorMessage()).find("fewer than two"), std::string::npos);
  EXPECT_EQ(f->GetOutput()->GetNumberOfPoints(), 0);
  vtkNew<vtkTerroirFeatureCurveTerrain> g;
  g->SetBackend(1);
  g->SetCurvesData(
    FeatureCurvesPolyData({ { { 0, 0, 5, 0, 95, 5, -1 }, { 50, 0, 5, 0, 95, 5, -1 } } }));
  g->SetDimensions(16, 16);
  g->Update();
  EXPECT_NE(std::string(g->GetErrorMessage()).find("angles"), std::string::npos);
}

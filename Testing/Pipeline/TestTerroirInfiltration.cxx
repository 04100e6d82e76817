// Pipeline tests of vtkTerroirInfiltration: the default recipe, the slope rule on planes of
// known slope, operation order, masks (image, array, stencil), soil types through the FAO
// table, no data, MTime of operands, errors.
#include "TerroirFilterTestUtilities.h"

#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageStencilData.h"
#include "vtkInformation.h"
#include "vtkPointData.h"
#include "vtkTerroirInfiltration.h"
#include "vtkTerroirSlope.h"
#include "vtkUnsignedCharArray.h"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

namespace
{
using terroir_test::MakeTerrain;

const double kPi = 3.14159265358979323846;

vtkSmartPointer<vtkImageData> RunInfiltration(vtkImageData* in, vtkTerroirInfiltration* f)
{
  f->SetInputData(in);
  f->Update();
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->ShallowCopy(f->GetOutput());
  return out;
}

double Rate(vtkImageData* out, int i, int j)
{
  int dims[3];
  out->GetDimensions(dims);
  return out->GetPointData()->GetArray("InfiltrationRate")->GetComponent(j * dims[0] + i, 0);
}

/// Horn's slope at the four corner cells of a grid spans one cell east-west but is divided by
/// two (gdaldem -compute_edges, reproduced by vtkTerroirSlope): half the plane's gradient there.
bool IsCorner(int i, int j, int nx, int ny)
{
  return (i == 0 || i == nx - 1) && (j == 0 || j == ny - 1);
}

/// A plane rising eastwards at `degrees` (10 m cells).
vtkSmartPointer<vtkImageData> Plane(double degrees, int nx = 6, int ny = 5)
{
  const double g = std::tan(degrees * kPi / 180.0);
  return MakeTerrain(nx, ny, 10.0, 10.0, [g](int i, int) { return 100.0 + 10.0 * g * i; });
}

TEST(TerroirInfiltration, DefaultRecipeFillsLoamAndDriesCliffs)
{
  auto f = vtkSmartPointer<vtkTerroirInfiltration>::New();
  EXPECT_EQ(f->GetNumberOfOperations(), 0);
  auto gentle = RunInfiltration(Plane(20.0), f);
  vtkDataArray* r = gentle->GetPointData()->GetArray("InfiltrationRate");
  ASSERT_NE(r, nullptr);
  EXPECT_EQ(r->GetDataType(), VTK_FLOAT);
  EXPECT_STREQ(r->GetInformation()->Get(vtkDataArray::UNITS_LABEL()), "mm/h");
  EXPECT_NE(gentle->GetPointData()->GetArray("Elevation"), nullptr);
  for (vtkIdType k = 0; k < r->GetNumberOfTuples(); ++k)
  {
    EXPECT_EQ(r->GetComponent(k, 0), 15.0) << "a 20 degree plane keeps the loam rate";
  }
  auto steep = RunInfiltration(Plane(40.0), f);
  for (int j = 0; j < 5; ++j)
  {
    for (int i = 0; i < 6; ++i)
    {
      if (!IsCorner(i, j, 6, 5))
      {
        EXPECT_EQ(Rate(steep, i, j), 0.0) << "a 40 degree plane is a cliff for the 30 degree rule";
      }
    }
  }
}

TEST(TerroirInfiltration, SlopeRuleOnPlanesOfKnownSlopeComputedOrFromSlopeArray)
{
  // Planes of 29 and 31 degrees around a 30 degree threshold; the slope comes either from
  // Horn's method inside the filter or from vtkTerroirSlope upstream, in degrees or percent.
  for (double degrees : { 29.0, 31.0 })
  {
    for (int source = 0; source < 3; ++source)
    {
      vtkSmartPointer<vtkImageData> in = Plane(degrees);
      if (source > 0)
      {
        auto slope = vtkSmartPointer<vtkTerroirSlope>::New();
        slope->SetBackendToCPU();
        if (source == 2)
        {
          slope->SetSlopeUnitsToPercent();
        }
        slope->SetInputData(in);
        slope->Update();
        in = vtkSmartPointer<vtkImageData>::New();
        in->ShallowCopy(slope->GetOutput());
      }
      auto f = vtkSmartPointer<vtkTerroirInfiltration>::New();
      f->AddFill(12.0);
      f->AddSlopeRule(30.0);
      auto out = RunInfiltration(in, f);
      const double expected = degrees > 30.0 ? 0.0 : 12.0;
      for (int j = 0; j < 5; ++j)
      {
        for (int i = 0; i < 6; ++i)
        {
          if (IsCorner(i, j, 6, 5))
          {
            continue;
          }
          EXPECT_EQ(Rate(out, i, j), expected)
            << degrees << " deg, slope source " << source << ", cell " << i << "," << j;
        }
      }
    }
  }
}

TEST(TerroirInfiltration, OperationsApplyInOrder)
{
  auto in = Plane(40.0, 4, 3);
  // The mask (an array of the input, as vtkTerroirVectorRasterizer makes) covers column 0.
  auto mask = vtkSmartPointer<vtkUnsignedCharArray>::New();
  mask->SetName("Rocks");
  mask->SetNumberOfValues(12);
  for (int k = 0; k < 12; ++k)
  {
    mask->SetValue(k, k % 4 == 0 ? 1 : 0);
  }
  in->GetPointData()->AddArray(mask);

  // Slope rule first, paint after: the painted cells keep their paint on the cliff.
  auto f = vtkSmartPointer<vtkTerroirInfiltration>::New();
  f->AddFill(20.0);
  f->AddSlopeRule(30.0);
  f->AddPaintMaskArray("Rocks", 2.0);
  auto out = RunInfiltration(in, f);
  EXPECT_EQ(Rate(out, 0, 1), 2.0);
  EXPECT_EQ(Rate(out, 1, 1), 0.0);
  // Paint first, slope rule after: the cliff wins everywhere.
  f->RemoveAllOperations();
  f->AddFill(20.0);
  f->AddPaintMaskArray("Rocks", 2.0);
  f->AddSlopeRule(30.0);
  out = RunInfiltration(in, f);
  EXPECT_EQ(Rate(out, 0, 1), 0.0);
  EXPECT_EQ(Rate(out, 2, 2), 0.0);
  // No fill: unpainted cells start at 0.
  f->RemoveAllOperations();
  f->AddPaintMaskArray("Rocks", 2.0);
  out = RunInfiltration(in, f);
  EXPECT_EQ(Rate(out, 0, 2), 2.0);
  EXPECT_EQ(Rate(out, 2, 2), 0.0);
}

TEST(TerroirInfiltration, FillAndSlopeRuleReplacesTheOperations)
{
  // ParaView's FillAndSlopeRule property: the default recipe with other numbers, replacing
  // whatever was added before (here a paint that would otherwise stay).
  auto in = Plane(25.0, 4, 3);
  auto f = vtkSmartPointer<vtkTerroirInfiltration>::New();
  f->AddFill(3.0);
  const vtkMTimeType before = f->GetMTime();
  f->SetFillAndSlopeRule(8.0, 20.0);
  EXPECT_GT(f->GetMTime(), before);
  EXPECT_EQ(f->GetNumberOfOperations(), 2);
  auto out = RunInfiltration(in, f);
  EXPECT_EQ(Rate(out, 1, 1), 0.0) << "25 degrees is above the 20 degree rule";
  f->SetFillAndSlopeRule(8.0, 30.0);
  out = RunInfiltration(in, f);
  EXPECT_EQ(Rate(out, 1, 1), 8.0) << "25 degrees keeps the fill under a 30 degree rule";
  // (15, 30) is the default recipe: the same rates as a filter with no operation.
  f->SetFillAndSlopeRule(15.0, 30.0);
  auto steep = Plane(40.0);
  auto given = RunInfiltration(steep, f);
  auto g = vtkSmartPointer<vtkTerroirInfiltration>::New();
  auto defaults = RunInfiltration(steep, g);
  for (int j = 0; j < 5; ++j)
  {
    for (int i = 0; i < 6; ++i)
    {
      EXPECT_EQ(Rate(given, i, j), Rate(defaults, i, j)) << i << "," << j;
    }
  }
}

TEST(TerroirInfiltration, PaintMaskImageStencilAndSoilTypes)
{
  auto in = Plane(5.0, 5, 4);
  // A separate mask image on the same grid: non-zero and non-NaN cells are painted.
  auto maskImage = MakeTerrain(5, 4, 10.0, 10.0, [](int i, int j) { return i == j ? 3.0 : 0.0; });
  // A stencil covering columns 1..2 of row 3 (the northern row), in index space.
  auto stencil = vtkSmartPointer<vtkImageStencilData>::New();
  stencil->SetExtent(0, 4, 0, 3, 0, 0);
  stencil->AllocateExtents();
  stencil->InsertNextExtent(1, 2, 3, 0);
  // Soil types: row 0 = 1..5 (sand .. clay), other rows 0 (unpainted) or 7 (unknown code).
  auto soil =
    MakeTerrain(5, 4, 10.0, 10.0, [](int i, int j) { return j == 0 ? i + 1.0 : 7.0 * (j % 2); });

  auto f = vtkSmartPointer<vtkTerroirInfiltration>::New();
  f->AddFill(10.0);
  f->AddPaintMask(maskImage, 4.0);
  f->AddPaintStencil(stencil, 50.0);
  f->AddSoilTypes(soil);
  f->SetSoilTypeRate(5, 1.0); // a user's clay
  auto out = RunInfiltration(in, f);
  // Row 0 is all soil types: FAO sand 30, sandy loam 25, loam 15, clay loam 7.5, user clay 1.
  const double fao[5] = { 30.0, 25.0, 15.0, 7.5, 1.0 };
  for (int i = 0; i < 5; ++i)
  {
    EXPECT_EQ(Rate(out, i, 0), fao[i]) << "soil type " << i + 1;
  }
  EXPECT_EQ(Rate(out, 1, 1), 4.0) << "mask diagonal";
  EXPECT_EQ(Rate(out, 2, 2), 4.0) << "mask diagonal";
  EXPECT_EQ(Rate(out, 0, 1), 10.0) << "fill";
  EXPECT_EQ(Rate(out, 1, 3), 50.0) << "stencil";
  EXPECT_EQ(Rate(out, 2, 3), 50.0) << "stencil";
  EXPECT_EQ(Rate(out, 3, 3), 4.0) << "mask diagonal outside the stencil";
  EXPECT_EQ(Rate(out, 0, 3), 10.0);
  EXPECT_EQ(Rate(out, 4, 3), 10.0);

  // Changing an operand re-executes the filter.
  const vtkMTimeType before = f->GetMTime();
  maskImage->Modified();
  EXPECT_GT(f->GetMTime(), before);
}

TEST(TerroirInfiltration, NoDataCellsGetNaN)
{
  auto in = MakeTerrain(
    4, 4, 10.0, 10.0, [](int i, int j) { return i == 2 && j == 1 ? std::nan("") : 5.0 * i; });
  auto f = vtkSmartPointer<vtkTerroirInfiltration>::New();
  auto out = RunInfiltration(in, f);
  EXPECT_TRUE(std::isnan(Rate(out, 2, 1)));
  EXPECT_EQ(Rate(out, 0, 0), 15.0);
}

TEST(TerroirInfiltration, BadOperationsGiveOneErrorAndNoOutput)
{
  auto in = Plane(10.0);
  auto wrongSize = MakeTerrain(3, 3, 10.0, 10.0, [](int, int) { return 1.0; });
  struct Case
  {
    std::function<void(vtkTerroirInfiltration*)> Setup;
    std::string Expected;
  };
  const std::vector<Case> cases = {
    { [](vtkTerroirInfiltration* f) { f->AddFill(-1.0); }, "outside [0, 1000]" },
    { [](vtkTerroirInfiltration* f) { f->AddFill(std::nan("")); }, "outside [0, 1000]" },
    { [](vtkTerroirInfiltration* f) { f->AddSlopeRule(95.0); }, "outside [0, 90]" },
    { [](vtkTerroirInfiltration* f) { f->AddPaintMaskArray("Nope", 3.0); },
      "no point array 'Nope'" },
    { [&](vtkTerroirInfiltration* f) { f->AddPaintMask(wrongSize, 3.0); },
      "resample it onto the terrain's grid" },
    { [](vtkTerroirInfiltration* f) { f->AddPaintMask(nullptr, 3.0); }, "no image given" },
    { [](vtkTerroirInfiltration* f) { f->AddPaintStencil(nullptr, 3.0); }, "no stencil given" },
  };
  for (const Case& c : cases)
  {
    auto f = vtkSmartPointer<vtkTerroirInfiltration>::New();
    auto obs = vtkSmartPointer<terroir_test::ErrorObserver>::New();
    f->AddObserver(vtkCommand::ErrorEvent, obs);
    c.Setup(f);
    f->SetInputData(in);
    f->Update();
    EXPECT_EQ(obs->ErrorCount, 1) << obs->Errors;
    EXPECT_NE(obs->Errors.find(c.Expected), std::string::npos) << obs->Errors;
    EXPECT_EQ(f->GetOutput()->GetNumberOfPoints(), 0);
  }
  auto f = vtkSmartPointer<vtkTerroirInfiltration>::New();
  auto obs = vtkSmartPointer<terroir_test::ErrorObserver>::New();
  f->AddObserver(vtkCommand::ErrorEvent, obs);
  f->SetSoilTypeRate(6, 3.0);
  EXPECT_EQ(obs->ErrorCount, 1);
  EXPECT_TRUE(std::isnan(f->GetSoilTypeRate(0)));
}

TEST(TerroirInfiltration, ModifiedAndPrintSelf)
{
  auto f = vtkSmartPointer<vtkTerroirInfiltration>::New();
  vtkMTimeType t = f->GetMTime();
  f->AddFill(3.0);
  EXPECT_GT(f->GetMTime(), t);
  t = f->GetMTime();
  f->SetSoilTypeRate(3, 12.0);
  EXPECT_GT(f->GetMTime(), t);
  EXPECT_EQ(f->GetSoilTypeRate(3), 12.0);
  f->AddSlopeRule(25.0);
  std::ostringstream os;
  f->Print(os);
  EXPECT_NE(os.str().find("Fill 3"), std::string::npos) << os.str();
  EXPECT_NE(os.str().find("SlopeRule 25"), std::string::npos) << os.str();
  EXPECT_NE(os.str().find("SoilTypeRates: 30 25 12 7.5 3"), std::string::npos) << os.str();
  EXPECT_EQ(f->GetNumberOfOperations(), 2);
}

} // namespace

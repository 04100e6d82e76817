// Pipeline tests of vtkTerroirSlope: the VTK contract (arrays, units, defaults, Modified,
// PrintSelf, update extents, no data, input types, bad input, TERROIR_BACKEND).
#include "TerroirFilterTestUtilities.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkExtentTranslator.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkShortArray.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"
#include "vtkTerroirComputeContext.h"
#include "vtkTerroirDEMReader.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirInfiltration.h"
#include "vtkTerroirSlope.h"
#include "vtkTerroirTemperature.h"
#include "vtkTrivialProducer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sstream>

namespace
{
using terroir_test::MakeTerrain;

constexpr double kDeg = 57.29577951308232;

vtkSmartPointer<vtkImageData> RunSlope(vtkImageData* in, vtkTerroirSlope* slope = nullptr)
{
  vtkSmartPointer<vtkTerroirSlope> local;
  if (!slope)
  {
    local = vtkSmartPointer<vtkTerroirSlope>::New();
    local->SetBackendToCPU();
    slope = local;
  }
  slope->SetInputData(in);
  slope->Update();
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->ShallowCopy(slope->GetOutput());
  return out;
}

TEST(TerroirSlope, AddsSlopeAspectNormalsWithUnitsAndPassesInputThrough)
{
  auto in = MakeTerrain(8, 6, 10.0, 10.0, [](int i, int) { return 0.1 * 10.0 * i; });
  vtkTerroirGeoreference::SetSourceFile(in, "plane.tif");
  auto out = RunSlope(in);
  vtkDataArray* slope = out->GetPointData()->GetArray("Slope");
  vtkDataArray* aspect = out->GetPointData()->GetArray("Aspect");
  vtkDataArray* normals = out->GetPointData()->GetArray("Normals");
  ASSERT_NE(slope, nullptr);
  ASSERT_NE(aspect, nullptr);
  ASSERT_NE(normals, nullptr);
  EXPECT_EQ(slope->GetDataType(), VTK_FLOAT);
  EXPECT_EQ(aspect->GetDataType(), VTK_FLOAT);
  EXPECT_EQ(normals->GetNumberOfComponents(), 3);
  EXPECT_STREQ(normals->GetComponentName(2), "Z");
  EXPECT_STREQ(slope->GetInformation()->Get(vtkDataArray::UNITS_LABEL()), "deg");
  EXPECT_STREQ(aspect->GetInformation()->Get(vtkDataArray::UNITS_LABEL()), "deg");
  EXPECT_NE(out->GetPointData()->GetArray("Elevation"), nullptr);
  EXPECT_EQ(out->GetPointData()->GetNormals(), nullptr); // not made the active normals
  EXPECT_EQ(vtkTerroirGeoreference::GetSourceFile(out), "plane.tif");
  EXPECT_NEAR(slope->GetComponent(3 * 8 + 3, 0), std::atan(0.1) * kDeg, 1e-4);
  EXPECT_NEAR(aspect->GetComponent(3 * 8 + 3, 0), 270.0, 1e-4);
  EXPECT_EQ(in->GetPointData()->GetArray("Slope"), nullptr); // input untouched

  auto percent = vtkSmartPointer<vtkTerroirSlope>::New();
  percent->SetBackendToCPU();
  percent->SetSlopeUnitsToPercent();
  percent->ComputeAspectOff();
  percent->ComputeNormalsOff();
  auto out2 = RunSlope(in, percent);
  EXPECT_STREQ(
    out2->GetPointData()->GetArray("Slope")->GetInformation()->Get(vtkDataArray::UNITS_LABEL()),
    "%");
  EXPECT_NEAR(out2->GetPointData()->GetArray("Slope")->GetComponent(20, 0), 10.0, 1e-4);
  EXPECT_EQ(out2->GetPointData()->GetArray("Aspect"), nullptr);
  EXPECT_EQ(out2->GetPointData()->GetArray("Normals"), nullptr);
}

TEST(TerroirSlope, DefaultsModifiedAndPrintSelf)
{
  auto f = vtkSmartPointer<vtkTerroirSlope>::New();
  EXPECT_EQ(f->GetZFactor(), 1.0);
  EXPECT_EQ(f->GetSlopeUnits(), vtkTerroirSlope::Degrees);
  EXPECT_EQ(f->GetBackend(), vtkTerroirComputeContext::Auto);
  EXPECT_EQ(f->GetLastBackend(), -1);
  EXPECT_TRUE(f->GetComputeAspect());
  EXPECT_TRUE(f->GetComputeNormals());
  vtkInformation* arrayInfo = f->GetInputArrayInformation(0);
  EXPECT_STREQ(arrayInfo->Get(vtkDataObject::FIELD_NAME()), "Elevation");
  EXPECT_EQ(
    arrayInfo->Get(vtkDataObject::FIELD_ASSOCIATION()), vtkDataObject::FIELD_ASSOCIATION_POINTS);

  vtkMTimeType t = f->GetMTime();
  f->SetZFactor(2.0);
  EXPECT_GT(f->GetMTime(), t);
  t = f->GetMTime();
  f->SetZFactor(2.0); // same value: no change
  EXPECT_EQ(f->GetMTime(), t);
  f->SetSlopeUnitsToPercent();
  EXPECT_GT(f->GetMTime(), t);
  t = f->GetMTime();
  f->SetBackendToCPU();
  EXPECT_GT(f->GetMTime(), t);
  t = f->GetMTime();
  f->SetComputeNormals(false);
  EXPECT_GT(f->GetMTime(), t);
  f->SetSlopeUnits(7); // clamped
  EXPECT_EQ(f->GetSlopeUnits(), vtkTerroirSlope::Percent);
  f->SetBackend(9);
  EXPECT_EQ(f->GetBackend(), vtkTerroirComputeContext::GPU);

  std::ostringstream os;
  f->Print(os);
  for (const char* word : { "ZFactor: 2",
         "SlopeUnits: Percent",
         "ComputeAspect",
         "ComputeNormals",
         "Backend: GPU",
         "LastBackend" })
  {
    EXPECT_NE(os.str().find(word), std::string::npos) << word;
  }
}

TEST(TerroirSlope, UpdateExtentGrowsByOneAndClamps)
{
  auto in = MakeTerrain(10, 10, 1.0, 1.0, [](int i, int j) { return i + 2.0 * j; });
  auto producer = vtkSmartPointer<vtkTrivialProducer>::New();
  producer->SetOutput(in);
  auto f = vtkSmartPointer<vtkTerroirSlope>::New();
  f->SetBackendToCPU();
  f->SetInputConnection(producer->GetOutputPort());
  f->UpdateInformation();
  int request[6] = { 2, 5, 3, 6, 0, 0 };
  f->UpdateExtent(request);
  int got[6];
  f->GetInputInformation(0, 0)->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), got);
  const int expected[6] = { 1, 6, 2, 7, 0, 0 };
  for (int a = 0; a < 6; ++a)
  {
    EXPECT_EQ(got[a], expected[a]) << a;
  }
  // A fresh filter (the first one's output already covers the next request).
  auto g = vtkSmartPointer<vtkTerroirSlope>::New();
  g->SetBackendToCPU();
  g->SetInputConnection(producer->GetOutputPort());
  g->UpdateInformation();
  int edge[6] = { 0, 9, 0, 3, 0, 0 };
  g->UpdateExtent(edge);
  g->GetInputInformation(0, 0)->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), got);
  const int clamped[6] = { 0, 9, 0, 4, 0, 0 };
  for (int a = 0; a < 6; ++a)
  {
    EXPECT_EQ(got[a], clamped[a]) << a;
  }
}

TEST(TerroirSlope, NoDataCellsAreNaNAndNeighboursFollowGdaldem)
{
  // A rough random surface with holes, also on the border and the corners; the same grid goes
  // through `gdaldem slope -compute_edges` and every cell must agree within 0.01 degrees.
  TERROIR_REQUIRE_PEER_OR_SKIP(terroir_test::HaveGdaldem(), "/usr/bin/gdaldem not installed");
  std::uint64_t state = 42;
  auto next = [&state]()
  {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) / 9007199254740992.0;
  };
  const int nx = 23, ny = 17;
  std::vector<double> z(nx * ny);
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      const bool hole = next() < 0.12 || (i == 0 && j == 5) || (i == nx - 1 && j == 0) ||
        (i == 1 && j == ny - 1) || (i == 0 && j == 1);
      z[j * nx + i] = hole ? NAN : 100.0 + 30.0 * next() + 2.0 * i;
    }
  }
  auto in = MakeTerrain(nx, ny, 10.0, 10.0, [&](int i, int j) { return z[j * nx + i]; });
  const std::string src = terroir_test::TempFile("slope_nodata.asc");
  const std::string ref = terroir_test::TempFile("slope_nodata_gdaldem.asc");
  ASSERT_TRUE(terroir_test::WriteAsciiGrid(src, in));
  ASSERT_EQ(terroir_test::RunCommand(
              "/usr/bin/gdaldem slope -q -compute_edges -of AAIGrid '" + src + "' '" + ref + "'"),
    0);
  terroir_test::AsciiGrid expected;
  ASSERT_TRUE(terroir_test::ReadAsciiGrid(ref, expected));
  ASSERT_EQ(expected.nx, nx);
  ASSERT_EQ(expected.ny, ny);
  auto out = RunSlope(in);
  vtkDataArray* slope = out->GetPointData()->GetArray("Slope");
  vtkDataArray* aspect = out->GetPointData()->GetArray("Aspect");
  vtkDataArray* normals = out->GetPointData()->GetArray("Normals");
  int holes = 0;
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      const vtkIdType k = static_cast<vtkIdType>(j) * nx + i;
      const double e = expected.At(i, j);
      if (std::isnan(z[k]))
      {
        ++holes;
        EXPECT_TRUE(std::isnan(e));
        EXPECT_TRUE(std::isnan(slope->GetComponent(k, 0)));
        EXPECT_TRUE(std::isnan(aspect->GetComponent(k, 0)));
        EXPECT_TRUE(std::isnan(normals->GetComponent(k, 0)));
      }
      else
      {
        EXPECT_NEAR(slope->GetComponent(k, 0), e, 0.01) << "cell " << i << "," << j;
      }
    }
  }
  EXPECT_GT(holes, 20);
  // The mask passes through, so no-data cells stay masked downstream.
  EXPECT_NE(out->GetPointData()->GetArray("vtkValidPointMask"), nullptr);
}

TEST(TerroirSlope, DoubleAndShortInputsGiveTheFloatResult)
{
  auto ref =
    MakeTerrain(9, 7, 5.0, 5.0, [](int i, int j) { return 3.0 * i - 2.0 * j + (i * j % 5); });
  auto expected = RunSlope(ref);
  for (int type : { VTK_DOUBLE, VTK_SHORT })
  {
    auto in = vtkSmartPointer<vtkImageData>::New();
    in->CopyStructure(ref);
    vtkSmartPointer<vtkDataArray> a;
    a.TakeReference(vtkDataArray::CreateDataArray(type));
    a->SetName("Elevation");
    a->SetNumberOfTuples(ref->GetNumberOfPoints());
    for (vtkIdType k = 0; k < ref->GetNumberOfPoints(); ++k)
    {
      a->SetComponent(k, 0, ref->GetPointData()->GetArray("Elevation")->GetComponent(k, 0));
    }
    in->GetPointData()->AddArray(a);
    auto out = RunSlope(in);
    vtkDataArray* s = out->GetPointData()->GetArray("Slope");
    ASSERT_NE(s, nullptr) << type;
    EXPECT_EQ(s->GetDataType(), VTK_FLOAT);
    EXPECT_EQ(out->GetPointData()->GetArray("Elevation")->GetDataType(), type); // passed through
    for (vtkIdType k = 0; k < ref->GetNumberOfPoints(); ++k)
    {
      EXPECT_EQ(
        s->GetComponent(k, 0), expected->GetPointData()->GetArray("Slope")->GetComponent(k, 0));
    }
  }
}

struct BadCase
{
  const char* what;
  vtkSmartPointer<vtkImageData> image;
  const char* message;
};

TEST(TerroirSlope, BadInputIsOneClearErrorAndAnEmptyOutput)
{
  std::vector<BadCase> cases;
  {
    auto img = MakeTerrain(5, 5, 1.0, 1.0, [](int i, int) { return i; });
    img->GetPointData()->GetArray("Elevation")->SetName("Height");
    vtkTerroirGeoreference::SetSourceFile(img, "/data/dem.tif");
    cases.push_back({ "no Elevation", img, "/data/dem.tif: no elevation array" });
  }
  {
    auto img = vtkSmartPointer<vtkImageData>::New();
    img->SetDimensions(4, 4, 3);
    auto a = vtkSmartPointer<vtkFloatArray>::New();
    a->SetName("Elevation");
    a->SetNumberOfTuples(48);
    a->FillValue(1.0f);
    img->GetPointData()->AddArray(a);
    cases.push_back({ "3-D", img, "2-D image" });
  }
  {
    auto img = vtkSmartPointer<vtkImageData>::New();
    img->SetDimensions(4, 4, 1);
    auto a = vtkSmartPointer<vtkFloatArray>::New();
    a->SetName("Elevation");
    a->SetNumberOfComponents(2);
    a->SetNumberOfTuples(16);
    a->FillValue(1.0f);
    img->GetPointData()->AddArray(a);
    cases.push_back({ "2 components", img, "2 components, expected 1" });
  }
  {
    auto img = MakeTerrain(1, 6, 1.0, 1.0, [](int, int j) { return j; });
    cases.push_back({ "one column", img, "at least 2 x 2" });
  }
  for (auto& c : cases)
  {
    auto f = vtkSmartPointer<vtkTerroirSlope>::New();
    f->SetBackendToCPU();
    auto obs = vtkSmartPointer<terroir_test::ErrorObserver>::New();
    f->AddObserver(vtkCommand::ErrorEvent, obs);
    f->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, obs);
    f->SetInputData(c.image);
    f->Update();
    EXPECT_GE(obs->ErrorCount, 1) << c.what;
    EXPECT_NE(obs->Errors.find(c.message), std::string::npos) << c.what << ": " << obs->Errors;
    EXPECT_EQ(f->GetOutput()->GetPointData()->GetArray("Slope"), nullptr) << c.what;
    EXPECT_EQ(f->GetOutput()->GetNumberOfPoints(), 0) << c.what;
  }
}

TEST(TerroirSlope, TerroirBackendEnvironmentOverridesAuto)
{
  auto in = MakeTerrain(6, 6, 1.0, 1.0, [](int i, int j) { return i + j; });
  const char* old = std::getenv("TERROIR_BACKEND");
  const std::string saved = old ? old : "";
  setenv("TERROIR_BACKEND", "cpu", 1);
  auto f = vtkSmartPointer<vtkTerroirSlope>::New(); // Auto
  RunSlope(in, f);
  EXPECT_EQ(f->GetLastBackend(), vtkTerroirComputeContext::CPU);
  EXPECT_FALSE(std::string(f->GetLastBackendReason()).empty());

  setenv("TERROIR_BACKEND", "quantum", 1);
  auto g = vtkSmartPointer<vtkTerroirSlope>::New();
  auto obs = vtkSmartPointer<terroir_test::ErrorObserver>::New();
  g->AddObserver(vtkCommand::ErrorEvent, obs);
  g->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, obs);
  RunSlope(in, g);
  EXPECT_GE(obs->ErrorCount, 1);
  EXPECT_EQ(g->GetLastBackend(), -1);
  EXPECT_EQ(g->GetOutput()->GetPointData()->GetArray("Slope"), nullptr);
  if (old)
  {
    setenv("TERROIR_BACKEND", saved.c_str(), 1);
  }
  else
  {
    unsetenv("TERROIR_BACKEND");
  }
}

TEST(TerroirSlope, AspectAddsMeridianConvergenceAndRowSpacingIsUsed)
{
  // A plane facing north; grid north is 2 degrees east of true north (gamma = +2, true = grid
  // + gamma), so the true aspect is 2 degrees.
  auto in = MakeTerrain(6, 6, 10.0, 10.0, [](int, int j) { return -1.0 * j; });
  vtkTerroirGeoreference::SetMeridianConvergence(in, 2.0);
  auto out = RunSlope(in);
  EXPECT_NEAR(out->GetPointData()->GetArray("Aspect")->GetComponent(14, 0), 2.0, 1e-4);

  // Per-row spacing from TerroirRowSpacing (geographic grids): z = g (i - 3) dx_j.
  const int nx = 7, ny = 6;
  std::vector<double> dxs = { 20, 21, 22, 23, 24, 25 };
  auto geo =
    MakeTerrain(nx, ny, 1000.0, 30.0, [&](int i, int j) { return 0.5 * (i - 3) * dxs[j]; });
  auto rows = vtkSmartPointer<vtkDoubleArray>::New();
  rows->SetNumberOfComponents(2);
  rows->SetNumberOfTuples(ny);
  for (int j = 0; j < ny; ++j)
  {
    rows->SetTuple2(j, dxs[j], 30.0);
  }
  vtkTerroirGeoreference::SetRowSpacing(geo, rows);
  auto out2 = RunSlope(geo);
  for (int j = 1; j < ny - 1; ++j)
  {
    EXPECT_NEAR(out2->GetPointData()->GetArray("Slope")->GetComponent(j * nx + 3, 0),
      std::atan(0.5) * kDeg,
      1e-4);
  }
}

} // namespace

TEST(TerroirSlope, ZFactorMustBeFiniteAndPositive)
{
  auto in = MakeTerrain(4, 4, 10.0, 10.0, [](int i, int) { return 1.0 * i; });
  vtkTerroirGeoreference::SetSourceFile(in, "plane.tif");
  for (double z : { 0.0, -2.0, std::nan(""), static_cast<double>(INFINITY) })
  {
    auto slope = vtkSmartPointer<vtkTerroirSlope>::New();
    slope->SetBackendToCPU();
    slope->SetZFactor(z);
    slope->SetInputData(in);
    auto obs = vtkSmartPointer<terroir_test::ErrorObserver>::New();
    slope->AddObserver(vtkCommand::ErrorEvent, obs);
    slope->Update();
    EXPECT_NE(obs->Errors.find("plane.tif: ZFactor "), std::string::npos) << obs->Errors;
    EXPECT_NE(obs->Errors.find(" must be finite and positive"), std::string::npos) << obs->Errors;
    EXPECT_EQ(slope->GetOutput()->GetPointData()->GetArray("Slope"), nullptr);
  }
}

// Pieces (issue 25): slope (one ghost layer), temperature (pointwise) and infiltration (one more
// ghost layer) on each of 4 pieces of the bundled DEM give back exactly the piece the pipeline
// asked for, and every added array equals the whole run's at the piece's cells bit for bit
// (the piece's border cells see their real neighbours through the ghost layers); the reader
// read the piece grown by the two ghost layers. An explicit update extent is given back cropped
// the same way.
TEST(TerroirSlope, PiecesEqualTheWholeRunBitForBit)
{
  const std::string dem =
    std::string(TERROIR_DATA_DIR) + "/sagehen_creek_ca/sagehen_dem_utm11n_10m.tif";
  auto chain = [&dem](vtkSmartPointer<vtkTerroirDEMReader>& reader)
  {
    reader = vtkSmartPointer<vtkTerroirDEMReader>::New();
    reader->SetFileName(dem.c_str());
    auto slope = vtkSmartPointer<vtkTerroirSlope>::New();
    slope->SetBackendToCPU();
    slope->SetInputConnection(reader->GetOutputPort());
    auto temperature = vtkSmartPointer<vtkTerroirTemperature>::New();
    temperature->SetBackendToCPU();
    temperature->SetInputConnection(slope->GetOutputPort());
    auto infiltration = vtkSmartPointer<vtkTerroirInfiltration>::New();
    infiltration->SetInputConnection(temperature->GetOutputPort());
    return infiltration;
  };
  vtkSmartPointer<vtkTerroirDEMReader> wholeReader;
  auto whole = chain(wholeReader);
  whole->Update();
  vtkImageData* all = whole->GetOutput();
  int wholeExtent[6];
  all->GetExtent(wholeExtent);
  const char* names[] = { "Slope", "Aspect", "Temperature", "InfiltrationRate" };

  auto compare = [&](vtkImageData* img, const int* expected)
  {
    int ext[6];
    img->GetExtent(ext);
    for (int a = 0; a < 6; ++a)
    {
      EXPECT_EQ(ext[a], expected[a]) << a;
    }
    for (const char* name : names)
    {
      vtkDataArray* x = img->GetPointData()->GetArray(name);
      vtkDataArray* y = all->GetPointData()->GetArray(name);
      ASSERT_NE(x, nullptr) << name;
      const int nc = x->GetNumberOfComponents();
      int mismatches = 0;
      for (int j = expected[2]; j <= expected[3]; ++j)
      {
        for (int i = expected[0]; i <= expected[1]; ++i)
        {
          int index[3] = { i, j, 0 };
          const vtkIdType a = img->ComputePointId(index);
          const vtkIdType b = all->ComputePointId(index);
          for (int c = 0; c < nc; ++c)
          {
            const float u = static_cast<float>(x->GetComponent(a, c));
            const float v = static_cast<float>(y->GetComponent(b, c));
            mismatches += std::memcmp(&u, &v, sizeof(float)) != 0 ? 1 : 0;
          }
        }
      }
      EXPECT_EQ(mismatches, 0) << name;
    }
  };

  vtkNew<vtkExtentTranslator> translator;
  for (int piece = 0; piece < 4; ++piece)
  {
    vtkSmartPointer<vtkTerroirDEMReader> reader;
    auto last = chain(reader);
    last->UpdateInformation();
    last->UpdatePiece(piece, 4, 0);
    int expected[6], read[6];
    translator->PieceToExtentThreadSafe(
      piece, 4, 0, wholeExtent, expected, vtkExtentTranslator::BLOCK_MODE, 0);
    translator->PieceToExtentThreadSafe(
      piece, 4, 2, wholeExtent, read, vtkExtentTranslator::BLOCK_MODE, 0);
    compare(last->GetOutput(), expected);
    for (int a = 0; a < 6; ++a)
    {
      EXPECT_EQ(reader->GetReadExtent()[a], read[a]) << "piece " << piece << " axis " << a;
    }
  }
  vtkSmartPointer<vtkTerroirDEMReader> reader;
  auto last = chain(reader);
  last->UpdateInformation();
  const int sub[6] = { 0, 200, 333, 719, 0, 0 };
  last->UpdateExtent(sub);
  compare(last->GetOutput(), sub);
  const int read[6] = { 0, 202, 331, 719, 0, 0 };
  for (int a = 0; a < 6; ++a)
  {
    EXPECT_EQ(reader->GetReadExtent()[a], read[a]) << a;
  }
}

// Tests of the filter base class vtkTerroirImageAlgorithm through a minimal subclass:
// backend setters and choice, whole-extent halo, the default input array, progress, and the
// ExtractTerrain helper (float data viewed in place, masks, row spacing).
#include "TerroirFilterTestUtilities.h"
#include "TerroirScopedEnvironment.h"

#include "vtkCallbackCommand.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkTerroirComputeContext.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirImageAlgorithm.h"
#include "vtkTerroirSlope.h"
#include "vtkTerroirTerrainInput.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>

namespace
{
/// A global filter (halo -1) without a GPU path that records what it was given.
class GlobalTestFilter : public vtkTerroirImageAlgorithm
{
public:
  static GlobalTestFilter* New();
  vtkTypeMacro(GlobalTestFilter, vtkTerroirImageAlgorithm);
  int Seen = 0;
  const float* SeenData = nullptr;

  double BytesPerCell = 8.0;

protected:
  int GetHaloWidth() override { return -1; }
  double EstimateMemory(double nx, double ny) override { return nx * ny * this->BytesPerCell; }
  int RequestTerrainData(vtkImageData*, const terroir::TerrainInput& t, vtkImageData*) override
  {
    if (this->SelectBackend(this->HasGPUPath()) < 0)
    {
      return 0;
    }
    this->Seen = t.view.nx * t.view.ny;
    this->SeenData = t.view.data;
    return 1;
  }
};
vtkStandardNewMacro(GlobalTestFilter);

TEST(TerroirImageAlgorithm, BackendSettersAndClamp)
{
  auto f = vtkSmartPointer<GlobalTestFilter>::New();
  EXPECT_EQ(f->GetBackend(), vtkTerroirComputeContext::Auto);
  f->SetBackendToGPU();
  EXPECT_EQ(f->GetBackend(), vtkTerroirComputeContext::GPU);
  f->SetBackendToCPU();
  EXPECT_EQ(f->GetBackend(), vtkTerroirComputeContext::CPU);
  f->SetBackendToAuto();
  EXPECT_EQ(f->GetBackend(), vtkTerroirComputeContext::Auto);
  f->SetBackend(-3);
  EXPECT_EQ(f->GetBackend(), 0);
  EXPECT_EQ(f->GetLastBackend(), -1);
  EXPECT_STREQ(f->GetLastBackendReason(), "");
}

TEST(TerroirImageAlgorithm, FilterWithoutGPUPathRunsOnCPUUnderAutoAndFailsUnderGPU)
{
  auto in = terroir_test::MakeTerrain(4, 4, 1.0, 1.0, [](int i, int) { return i; });
  unsetenv("TERROIR_BACKEND");
  auto f = vtkSmartPointer<GlobalTestFilter>::New();
  f->SetInputData(in);
  f->Update();
  EXPECT_EQ(f->GetLastBackend(), vtkTerroirComputeContext::CPU);
  EXPECT_NE(std::string(f->GetLastBackendReason()).find("no GPU path"), std::string::npos);
  // The float32 elevations are viewed in place, not copied.
  EXPECT_EQ(
    f->SeenData, static_cast<float*>(in->GetPointData()->GetArray("Elevation")->GetVoidPointer(0)));

  auto g = vtkSmartPointer<GlobalTestFilter>::New();
  auto obs = vtkSmartPointer<terroir_test::ErrorObserver>::New();
  g->AddObserver(vtkCommand::ErrorEvent, obs);
  g->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, obs);
  g->SetBackendToGPU();
  g->SetInputData(in);
  g->Update();
  EXPECT_EQ(g->GetLastBackend(), -1);
  EXPECT_NE(obs->Errors.find("requested backend"), std::string::npos) << obs->Errors;
}

TEST(TerroirImageAlgorithm, GPURequestMatchesContextAvailability)
{
  auto in = terroir_test::MakeTerrain(5, 5, 1.0, 1.0, [](int i, int j) { return i * j; });
  auto f = vtkSmartPointer<vtkTerroirSlope>::New();
  auto obs = vtkSmartPointer<terroir_test::ErrorObserver>::New();
  f->AddObserver(vtkCommand::ErrorEvent, obs);
  f->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, obs);
  f->SetBackendToGPU();
  f->SetInputData(in);
  f->Update();
  if (vtkTerroirComputeContext::IsAvailable())
  {
    EXPECT_EQ(f->GetLastBackend(), vtkTerroirComputeContext::GPU);
    EXPECT_NE(f->GetOutput()->GetPointData()->GetArray("Slope"), nullptr);
  }
  else
  {
    EXPECT_EQ(f->GetLastBackend(), -1);
    EXPECT_GE(obs->ErrorCount, 1);
    EXPECT_EQ(f->GetOutput()->GetPointData()->GetArray("Slope"), nullptr);
  }
}

TEST(TerroirImageAlgorithm, WholeExtentHaloAsksForEverything)
{
  auto in = terroir_test::MakeTerrain(12, 9, 1.0, 1.0, [](int i, int) { return i; });
  auto f = vtkSmartPointer<GlobalTestFilter>::New();
  f->SetBackendToCPU();
  const std::array<int, 6> whole = { 0, 11, 0, 8, 0, 0 };
  EXPECT_EQ(terroir_test::RequestedInputExtent(f, in, { 3, 4, 3, 4, 0, 0 }), whole);
  EXPECT_EQ(f->Seen, 12 * 9);
}

// A piece asked of a whole-extent filter (issue 25) comes back as exactly that extent: every
// array equals the same cells of the whole image (vtkImageData::Crop of a copy of the input,
// the filter adding nothing here), bit for bit and in the same order, with the units label and
// the active-scalars role kept.
TEST(TerroirImageAlgorithm, PieceOfAWholeExtentFilterIsItsCells)
{
  auto in = terroir_test::MakeTerrain(12, 9, 1.0, 1.0, [](int i, int j) { return 3 * i + j; });
  vtkNew<vtkDoubleArray> wind;
  wind->SetName("Wind");
  wind->SetNumberOfComponents(3);
  wind->SetNumberOfTuples(in->GetNumberOfPoints());
  for (vtkIdType k = 0; k < in->GetNumberOfPoints(); ++k)
  {
    wind->SetTuple3(k, 0.5 * k, -1.0 * k, 1e6 + k);
  }
  wind->GetInformation()->Set(vtkDataArray::UNITS_LABEL(), "m/s");
  in->GetPointData()->AddArray(wind);
  in->GetPointData()->SetActiveScalars("Elevation");
  auto f = vtkSmartPointer<GlobalTestFilter>::New();
  f->SetBackendToCPU();
  f->SetInputData(in);
  const int piece[6] = { 3, 8, 2, 6, 0, 0 };
  ASSERT_EQ(f->UpdateExtent(piece), 1);
  vtkImageData* got = f->GetOutput();
  vtkNew<vtkImageData> expected;
  expected->DeepCopy(in);
  expected->Crop(piece);
  int ext[6];
  got->GetExtent(ext);
  for (int a = 0; a < 6; ++a)
  {
    EXPECT_EQ(ext[a], piece[a]) << a;
  }
  ASSERT_EQ(
    got->GetPointData()->GetNumberOfArrays(), expected->GetPointData()->GetNumberOfArrays());
  for (int a = 0; a < expected->GetPointData()->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* x = got->GetPointData()->GetArray(a);
    vtkDataArray* y = expected->GetPointData()->GetArray(a);
    ASSERT_STREQ(x->GetName(), y->GetName());
    ASSERT_EQ(x->GetDataType(), y->GetDataType()) << y->GetName();
    ASSERT_EQ(x->GetNumberOfTuples(), 6 * 5) << y->GetName();
    ASSERT_EQ(x->GetNumberOfComponents(), y->GetNumberOfComponents()) << y->GetName();
    EXPECT_EQ(std::memcmp(x->GetVoidPointer(0),
                y->GetVoidPointer(0),
                static_cast<std::size_t>(x->GetNumberOfValues() * x->GetDataTypeSize())),
      0)
      << y->GetName();
  }
  vtkDataArray* units = got->GetPointData()->GetArray("Wind");
  ASSERT_TRUE(units->HasInformation());
  EXPECT_STREQ(units->GetInformation()->Get(vtkDataArray::UNITS_LABEL()), "m/s");
  ASSERT_NE(got->GetPointData()->GetScalars(), nullptr);
  EXPECT_STREQ(got->GetPointData()->GetScalars()->GetName(), "Elevation");
}

TEST(TerroirImageAlgorithm, ProgressIsReported)
{
  auto in = terroir_test::MakeTerrain(64, 64, 1.0, 1.0, [](int i, int j) { return i * j; });
  auto f = vtkSmartPointer<vtkTerroirSlope>::New();
  f->SetBackendToCPU();
  int events = 0;
  double last = -1.0;
  auto cb = vtkSmartPointer<vtkCallbackCommand>::New();
  struct State
  {
    int* events;
    double* last;
  } state{ &events, &last };
  cb->SetClientData(&state);
  cb->SetCallback(
    [](vtkObject*, unsigned long, void* client, void* data)
    {
      auto* s = static_cast<State*>(client);
      ++*s->events;
      *s->last = *static_cast<double*>(data);
    });
  f->AddObserver(vtkCommand::ProgressEvent, cb);
  f->SetInputData(in);
  f->Update();
  EXPECT_GE(events, 3);
  EXPECT_EQ(last, 1.0);
}

TEST(TerroirImageAlgorithm, ExtractTerrainMasksAndRowSpacing)
{
  auto in = terroir_test::MakeTerrain(
    4, 3, 7.0, 9.0, [](int i, int j) { return (i == 2 && j == 1) ? NAN : i + 10.0 * j; });
  auto rows = vtkSmartPointer<vtkDoubleArray>::New();
  rows->SetNumberOfComponents(2);
  rows->SetNumberOfTuples(3);
  rows->SetTuple2(0, 5.0, 9.5);
  rows->SetTuple2(1, 4.0, 9.5);
  rows->SetTuple2(2, 3.0, 9.5);
  vtkTerroirGeoreference::SetRowSpacing(in, rows);
  terroir::TerrainInput t;
  std::string error;
  ASSERT_TRUE(terroir::ExtractTerrain(in, in->GetPointData()->GetArray("Elevation"), t, error, 2))
    << error;
  EXPECT_EQ(t.view.nx, 4);
  EXPECT_EQ(t.view.ny, 3);
  EXPECT_EQ(t.view.dx, 7.0);
  EXPECT_EQ(t.view.dy, 9.0);
  EXPECT_TRUE(t.hasNoData);
  EXPECT_FALSE(t.view.IsValid(2, 1));
  EXPECT_TRUE(t.view.IsValid(1, 1));
  EXPECT_EQ(t.view.DxAt(2), 3.0);
  EXPECT_EQ(t.view.DyAt(0), 9.5);
  EXPECT_EQ(t.view.At(3, 2), 23.0f);

  // A wrong-sized row spacing is an error, not a crash.
  auto bad = vtkSmartPointer<vtkDoubleArray>::New();
  bad->SetNumberOfComponents(2);
  bad->SetNumberOfTuples(2);
  vtkTerroirGeoreference::SetRowSpacing(in, bad);
  EXPECT_FALSE(terroir::ExtractTerrain(in, in->GetPointData()->GetArray("Elevation"), t, error));
  EXPECT_NE(error.find("TerroirRowSpacing"), std::string::npos) << error;

  vtkFloatArray* out = terroir::NewOutputArray("X", 2, 5, "m");
  EXPECT_EQ(out->GetNumberOfTuples(), 5);
  EXPECT_STREQ(out->GetInformation()->Get(vtkDataArray::UNITS_LABEL()), "m");
  out->Delete();
}

} // namespace

TEST(TerroirImageAlgorithm, RefusesBeforeAllocatingWhenMemoryIsShort)
{
  // 300 x 300 cells at 8 B each (the test filter's estimate) + 1 B for a possible mask:
  // 810,000 B = 791 KiB needed. A limit of 500 KiB must refuse, naming both figures and the
  // source file.
  auto in = terroir_test::MakeTerrain(300, 300, 1.0, 1.0, [](int i, int) { return i; });
  vtkTerroirGeoreference::SetSourceFile(in, "big.tif");
  terroir_test::ScopedEnvironment limit("TERROIR_MEMORY_LIMIT", "500K");
  auto f = vtkSmartPointer<GlobalTestFilter>::New();
  f->SetInputData(in);
  auto obs = vtkSmartPointer<terroir_test::ErrorObserver>::New();
  f->AddObserver(vtkCommand::ErrorEvent, obs);
  f->Update();
  EXPECT_EQ(f->Seen, 0); // RequestTerrainData never ran
  EXPECT_EQ(f->GetOutput()->GetNumberOfPoints(), 0);
  EXPECT_NE(obs->Errors.find("big.tif: not enough memory for GlobalTestFilter: needs 791 KiB, "
                             "500 KiB available (TERROIR_MEMORY_LIMIT)"),
    std::string::npos)
    << obs->Errors;
  // Enough memory: it runs.
  limit.Set("1M");
  f->Modified();
  f->Update();
  EXPECT_EQ(f->Seen, 300 * 300);
}

TEST(TerroirImageAlgorithm, RejectsZeroOrNonFiniteSpacing)
{
  for (double dx : { 0.0, std::nan(""), static_cast<double>(INFINITY) })
  {
    auto in = terroir_test::MakeTerrain(4, 4, 1.0, 1.0, [](int i, int) { return i; });
    in->SetSpacing(dx, 1.0, 1.0);
    auto f = vtkSmartPointer<GlobalTestFilter>::New();
    f->SetInputData(in);
    auto obs = vtkSmartPointer<terroir_test::ErrorObserver>::New();
    f->AddObserver(vtkCommand::ErrorEvent, obs);
    f->Update();
    EXPECT_EQ(f->Seen, 0);
    EXPECT_NE(obs->Errors.find("must be positive and finite"), std::string::npos) << obs->Errors;
  }
}

// Determinism of the GPU paths: every filter with a GPU path (found in the module headers, so a
// new one cannot be missed) gives bit-identical outputs when run twice on the GPU, and agrees
// with its CPU path within STYLE.md's tolerances, |gpu - cpu| <= atol + 1e-5 |cpu|, with NaN
// (no-data) in exactly the same cells.
#include "TerroirFilterTestUtilities.h"

#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkPointData.h"
#include "vtkTerroirComputeContext.h"
#include "vtkTerroirKMeans.h"
#include "vtkTerroirSlope.h"
#include "vtkTerroirSoilHumidity.h"
#include "vtkTerroirSolarIllumination.h"
#include "vtkTerroirTemperature.h"
#include "vtkTerroirWaterFlow.h"
// new-filter.sh: includes

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace
{
struct GPUCase
{
  std::function<vtkSmartPointer<vtkTerroirImageAlgorithm>()> make;
  std::vector<std::pair<std::string, double>> arrays; ///< array name, atol
};

const std::map<std::string, GPUCase>& Cases()
{
  static const std::map<std::string, GPUCase> cases = {
    { "vtkTerroirKMeans",
      { []
        {
          // Elevation and the infiltration rates, standardised (the DEM has none of the
          // default resource arrays); labels are compared exactly (atol 0).
          auto f = vtkSmartPointer<vtkTerroirKMeans>::New();
          f->AddFeature("Elevation", 1.0);
          f->AddFeature("InfiltrationRate", 0.5);
          f->SetStandardize(true);
          f->SetMaximumIterations(30);
          return f;
        },
        { { "ClusterId", 0.0 } } } },
    { "vtkTerroirSlope",
      { [] { return vtkSmartPointer<vtkTerroirSlope>::New(); },
        { { "Slope", 1e-3 }, { "Normals", 1e-5 } } } },
    { "vtkTerroirSolarIllumination",
      { []
        {
          // A day of hourly steps on a 16-sector map (lit hours are compared, with threshold
          // flips allowed, in TestSolarIlluminationGPU.cxx).
          auto f = vtkSmartPointer<vtkTerroirSolarIllumination>::New();
          f->SetModeToDaily();
          f->SetTimeStep(60.0);
          f->SetHorizonSectors(16);
          f->SetOutputHorizonMap(true);
          return f;
        },
        { { "HorizonAngle", 1e-4 } } } },
    { "vtkTerroirTemperature",
      { [] { return vtkSmartPointer<vtkTerroirTemperature>::New(); },
        { { "Temperature", 1e-3 } } } },
    { "vtkTerroirSoilHumidity",
      { [] { return vtkSmartPointer<vtkTerroirSoilHumidity>::New(); },
        { { "SoilHumidity", 1e-4 },
          { "WeightedSoilHumidity", 1e-4 },
          { "StandingWater", 1e-4 } } } },
    { "vtkTerroirWaterFlow",
      { []
        {
          auto f = vtkSmartPointer<vtkTerroirWaterFlow>::New();
          f->SetMaximumIterations(40);
          return f;
        },
        { { "WaterHeight", 1e-9 }, { "Discharge", 1e-9 } } } },
    { "vtkTerroirWaterFlow (rivers mode)",
      { []
        {
          // Rain, net-flux sums and, after the run, the rate iterations (on the CPU).
          auto f = vtkSmartPointer<vtkTerroirWaterFlow>::New();
          f->SetModeToRivers();
          f->SetMaximumIterations(40);
          return f;
        },
        { { "WaterHeight", 0.0 },
          { "Discharge", 0.0 },
          { "DischargeRate", 0.0 },
          { "RiverStrength", 0.0 } } } },
    // new-filter.sh: cases
  };
  return cases;
}

vtkSmartPointer<vtkImageData> Terrain()
{
  // The bundled DEM with a hole of no-data cells.
  auto t =
    terroir_test::ReadDEM(terroir_test::DataFile("sagehen_creek_ca/sagehen_dem_utm11n_10m.tif"));
  vtkDataArray* z = t->GetPointData()->GetArray("Elevation");
  for (vtkIdType k = 200 * 786; k < 200 * 786 + 5000; ++k)
  {
    z->SetComponent(k, 0, std::nan(""));
  }
  // Infiltration rates of 0 .. 12 mm/h, on both sides of the rain intensities, for
  // vtkTerroirSoilHumidity (other filters ignore the array).
  auto rate = vtkSmartPointer<vtkFloatArray>::New();
  rate->SetName("InfiltrationRate");
  rate->SetNumberOfValues(z->GetNumberOfTuples());
  for (vtkIdType k = 0; k < z->GetNumberOfTuples(); ++k)
  {
    rate->SetValue(k, static_cast<float>(k % 97) * 0.125f);
  }
  t->GetPointData()->AddArray(rate);
  return t;
}

vtkSmartPointer<vtkImageData> RunCase(const GPUCase& c, vtkImageData* in, int backend)
{
  auto f = c.make();
  f->SetBackend(backend);
  f->SetInputData(in);
  f->Update();
  EXPECT_EQ(f->GetLastBackend(), backend);
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->ShallowCopy(f->GetOutput());
  return out;
}
} // namespace

TEST(TerroirDeterminismGPU, EveryFilterWithAGPUPathIsCovered)
{
  // The GPU check bundle (terroir-gpu-check, Scripts/gpu-check.sh) may run without the sources.
  const std::filesystem::path filters = std::filesystem::path(TERROIR_SOURCE_DIR) / "Filters";
  if (!std::filesystem::is_directory(filters))
  {
    GTEST_SKIP() << "no source tree to scan: " << filters << " is not a folder";
  }
  int withGPU = 0;
  for (const auto& c : terroir_test::ProjectAlgorithmClasses())
  {
    if (c.HasGPUPath)
    {
      ++withGPU;
      EXPECT_EQ(Cases().count(c.Name), 1u)
        << c.Name << " has a GPU path but no case in TestDeterminismGPU.cxx";
    }
  }
  // Every case is a class's (a second mode of a class is named "Class (mode)").
  int classes = 0;
  for (const auto& c : Cases())
  {
    classes += c.first.find(' ') == std::string::npos ? 1 : 0;
  }
  EXPECT_EQ(withGPU, classes);
}

TEST(TerroirDeterminismGPU, RepeatedGPURunsAreBitIdenticalAndAgreeWithTheCPU)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  auto in = Terrain();
  for (const auto& [name, c] : Cases())
  {
    auto gpu1 = RunCase(c, in, vtkTerroirComputeContext::GPU);
    auto gpu2 = RunCase(c, in, vtkTerroirComputeContext::GPU);
    auto cpu = RunCase(c, in, vtkTerroirComputeContext::CPU);
    for (const auto& [array, atol] : c.arrays)
    {
      vtkDataArray* a = gpu1->GetPointData()->GetArray(array.c_str());
      vtkDataArray* b = gpu2->GetPointData()->GetArray(array.c_str());
      vtkDataArray* r = cpu->GetPointData()->GetArray(array.c_str());
      ASSERT_TRUE(a && b && r) << name << " " << array;
      const std::size_t bytes = static_cast<std::size_t>(a->GetNumberOfValues()) * 4;
      ASSERT_EQ(a->GetNumberOfValues(), b->GetNumberOfValues());
      EXPECT_EQ(std::memcmp(a->GetVoidPointer(0), b->GetVoidPointer(0), bytes), 0)
        << name << " " << array << ": two GPU runs differ";
      vtkIdType outside = 0, nanMismatch = 0;
      double worst = 0.0;
      for (vtkIdType k = 0; k < r->GetNumberOfValues(); ++k)
      {
        const double g = a->GetVariantValue(k).ToDouble();
        const double c0 = r->GetVariantValue(k).ToDouble();
        if (std::isnan(g) || std::isnan(c0))
        {
          nanMismatch += std::isnan(g) != std::isnan(c0) ? 1 : 0;
          continue;
        }
        worst = std::max(worst, std::fabs(g - c0));
        outside += std::fabs(g - c0) > atol + 1e-5 * std::fabs(c0) ? 1 : 0;
      }
      EXPECT_EQ(nanMismatch, 0) << name << " " << array;
      EXPECT_EQ(outside, 0) << name << " " << array << ": worst |gpu - cpu| = " << worst;
    }
  }
}

// vtkTerroirFeatureCurveTerrain: the GPU path (Shaders/FeatureCurveMultigrid.comp) against the
// CPU path. The kernels do the core's operations in the same order in float64 with `precise`,
// so the answers are expected to be bit-identical; prints the timings.
#include "TerroirFeatureCurveScenes.h"

#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkPointData.h"
#include "vtkTerroirComputeContext.h"
#include "vtkTerroirFeatureCurveTerrain.h"
#include "vtkTimerLog.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <iostream>

namespace
{
vtkSmartPointer<vtkImageData> RunFeatureCurves(int backend,
  int nx,
  int ny,
  double spacing,
  int* cycles,
  double* seconds)
{
  vtkNew<vtkTerroirFeatureCurveTerrain> f;
  f->SetBackend(backend);
  f->SetCurvesData(terroir_test::RidgeAndValley());
  f->SetDimensions(nx, ny);
  f->SetSpacing(spacing);
  f->SetTolerance(1e-4);
  vtkNew<vtkTimerLog> timer;
  timer->StartTimer();
  f->Update();
  timer->StopTimer();
  EXPECT_STREQ(f->GetErrorMessage(), "");
  EXPECT_EQ(f->GetLastBackend(), backend);
  EXPECT_TRUE(f->GetLastConverged());
  *cycles = f->GetLastCycles();
  *seconds = timer->GetElapsedTime();
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->ShallowCopy(f->GetOutput());
  return out;
}
} // namespace

TEST(FeatureCurveTerrainGPU, SameBitsAsTheCPU)
{
  if (!vtkTerroirComputeContext::IsAvailable())
  {
    if (std::getenv("TERROIR_REQUIRE_GPU"))
    {
      FAIL() << "no compute context: " << vtkTerroirComputeContext::GetUnavailableReason();
    }
    GTEST_SKIP() << vtkTerroirComputeContext::GetUnavailableReason();
  }
  // Odd and even sizes (the coarse grids' last points differ).
  const int sizes[2][2] = { { 131, 101 }, { 256, 200 } };
  for (const auto& size : sizes)
  {
    const double spacing = 1300.0 / (size[0] - 1);
    int cpuCycles = 0, gpuCycles = 0;
    double cpuSeconds = 0, gpuSeconds = 0;
    auto cpu = RunFeatureCurves(1, size[0], size[1], spacing, &cpuCycles, &cpuSeconds);
    auto gpu = RunFeatureCurves(2, size[0], size[1], spacing, &gpuCycles, &gpuSeconds);
    EXPECT_EQ(cpuCycles, gpuCycles);
    vtkDataArray* a = cpu->GetPointData()->GetArray("Elevation");
    vtkDataArray* b = gpu->GetPointData()->GetArray("Elevation");
    ASSERT_NE(b, nullptr);
    double largest = 0.0;
    vtkIdType different = 0;
    for (vtkIdType k = 0; k < a->GetNumberOfTuples(); ++k)
    {
      const double d = std::abs(a->GetComponent(k, 0) - b->GetComponent(k, 0));
      largest = std::max(largest, d);
      different += d != 0.0;
    }
    std::cout << size[0] << " x " << size[1] << ": " << cpuCycles << " cycles, CPU " << cpuSeconds
              << " s, GPU " << gpuSeconds << " s (" << vtkTerroirComputeContext::GetRenderer()
              << "), largest difference " << largest << " m in " << different << " cells\n";
    EXPECT_EQ(different, 0) << "largest difference " << largest << " m";
    EXPECT_LE(largest, 1e-3);
  }
}

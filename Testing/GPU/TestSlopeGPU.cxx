// vtkTerroirSlope: GPU path (Shaders/Slope.comp) against the CPU path (float) on the bundled
// DEM and on a synthetic grid with no-data holes and per-row spacing. Also prints timings.
#include "TerroirFilterTestUtilities.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkPointData.h"
#include "vtkTerroirComputeContext.h"
#include "vtkTerroirGPU.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirSlope.h"
#include "vtkTimerLog.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <iostream>

namespace
{

vtkSmartPointer<vtkImageData> RunSlope(vtkImageData* in, int backend, double* seconds = nullptr)
{
  auto f = vtkSmartPointer<vtkTerroirSlope>::New();
  f->SetBackend(backend);
  f->SetInputData(in);
  auto timer = vtkSmartPointer<vtkTimerLog>::New();
  timer->StartTimer();
  f->Update();
  timer->StopTimer();
  if (seconds)
  {
    *seconds = timer->GetElapsedTime();
  }
  EXPECT_EQ(f->GetLastBackend(), backend);
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->ShallowCopy(f->GetOutput());
  return out;
}

// Compares the GPU and CPU outputs: |gpu - cpu| <= atol + 1e-5 |cpu|, NaN where NaN.
void Compare(vtkImageData* cpu, vtkImageData* gpu, const char* label)
{
  vtkDataArray* sc = cpu->GetPointData()->GetArray("Slope");
  vtkDataArray* sg = gpu->GetPointData()->GetArray("Slope");
  vtkDataArray* ac = cpu->GetPointData()->GetArray("Aspect");
  vtkDataArray* ag = gpu->GetPointData()->GetArray("Aspect");
  vtkDataArray* nc = cpu->GetPointData()->GetArray("Normals");
  vtkDataArray* ng = gpu->GetPointData()->GetArray("Normals");
  ASSERT_NE(sg, nullptr);
  ASSERT_NE(ag, nullptr);
  ASSERT_NE(ng, nullptr);
  double maxSlope = 0.0, maxAspect = 0.0, maxNormal = 0.0;
  int bad = 0;
  for (vtkIdType k = 0; k < sc->GetNumberOfTuples(); ++k)
  {
    const double c = sc->GetComponent(k, 0), g = sg->GetComponent(k, 0);
    if (std::isnan(c) || std::isnan(g))
    {
      if (std::isnan(c) != std::isnan(g) && bad++ < 10)
      {
        ADD_FAILURE() << label << ": NaN mismatch at " << k;
      }
      continue;
    }
    maxSlope = std::max(maxSlope, std::fabs(g - c));
    if (std::fabs(g - c) > 1e-3 + 1e-5 * std::fabs(c) && bad++ < 10)
    {
      ADD_FAILURE() << label << ": slope " << g << " vs " << c << " at " << k;
    }
    for (int a = 0; a < 3; ++a)
    {
      const double d = std::fabs(ng->GetComponent(k, a) - nc->GetComponent(k, a));
      maxNormal = std::max(maxNormal, d);
      if (d > 1e-5 && bad++ < 10)
      {
        ADD_FAILURE() << label << ": normal component " << a << " at " << k;
      }
    }
    // The aspect of a nearly flat cell is the direction of a rounding error: compare it where
    // the slope is at least 0.05 degrees.
    if (c >= 0.05)
    {
      const double d =
        std::fabs(std::remainder(ag->GetComponent(k, 0) - ac->GetComponent(k, 0), 360.0));
      maxAspect = std::max(maxAspect, d);
      if (!(d <= 1e-3 + 1e-5 * std::fabs(ac->GetComponent(k, 0))) && bad++ < 10)
      {
        ADD_FAILURE() << label << ": aspect " << ag->GetComponent(k, 0) << " vs "
                      << ac->GetComponent(k, 0) << " at " << k;
      }
    }
  }
  std::cout << label << ": max |gpu-cpu| slope " << maxSlope << " deg, aspect " << maxAspect
            << " deg, normals " << maxNormal << std::endl;
  EXPECT_EQ(bad, 0);
}

vtkSmartPointer<vtkImageData> Synthetic(int nx, int ny, bool holes)
{
  std::uint64_t state = 2024;
  return terroir_test::MakeTerrain(nx,
    ny,
    10.0,
    10.0,
    [&](int i, int j)
    {
      state = state * 6364136223846793005ULL + 1442695040888963407ULL;
      const double noise = static_cast<double>(state >> 11) / 9007199254740992.0;
      if (holes && (noise < 0.02 || (i > nx / 3 && i < nx / 3 + 7 && j > ny / 2 && j < ny / 2 + 5)))
      {
        return std::nan("");
      }
      return 1500.0 + 200.0 * std::sin(i * 0.037) * std::cos(j * 0.023) +
        40.0 * std::sin(i * 0.21 + j * 0.17) + 3.0 * noise;
    });
}

TEST(SlopeGPU, MatchesCPUOnBundledDEM)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  auto in =
    terroir_test::ReadDEM(terroir_test::DataFile("sagehen_creek_ca/sagehen_dem_utm11n_10m.tif"));
  ASSERT_NE(in, nullptr);
  RunSlope(in, vtkTerroirComputeContext::GPU); // warm-up: context and program
  double tc = 0.0, tg = 0.0;
  auto cpu = RunSlope(in, vtkTerroirComputeContext::CPU, &tc);
  auto gpu = RunSlope(in, vtkTerroirComputeContext::GPU, &tg);
  const double mcells = in->GetNumberOfPoints() / 1e6;
  std::cout << "bundled DEM " << in->GetNumberOfPoints() << " cells: CPU " << tc / mcells
            << " s/Mcell, GPU (" << vtkTerroirComputeContext::GetRenderer() << ") " << tg / mcells
            << " s/Mcell" << std::endl;
  Compare(cpu, gpu, "bundled DEM");
}

TEST(SlopeGPU, MatchesCPUOnSyntheticGridWithNoDataAndRowSpacing)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  const int nx = 301, ny = 257;
  auto in = Synthetic(nx, ny, true);
  auto rows = vtkSmartPointer<vtkDoubleArray>::New();
  rows->SetNumberOfComponents(2);
  rows->SetNumberOfTuples(ny);
  for (int j = 0; j < ny; ++j)
  {
    rows->SetTuple2(j, 10.0 * std::cos((39.0 + j * 0.001) / 57.29577951308232), 9.26);
  }
  vtkTerroirGeoreference::SetRowSpacing(in, rows);
  vtkTerroirGeoreference::SetMeridianConvergence(in, -2.5);
  auto cpu = RunSlope(in, vtkTerroirComputeContext::CPU);
  auto gpu = RunSlope(in, vtkTerroirComputeContext::GPU);
  Compare(cpu, gpu, "synthetic with holes");
}

// Outputs larger than one storage buffer are computed band by band: the band edges must not
// show (each band reads its halo rows from the whole-grid elevation buffer). The storage-block
// limit is capped at 320 KiB (Context::SetStorageBlockLimit): the elevation of 301 x 257 cells
// (4 B per cell) still fits one buffer, the normals (12 B per cell) take bands of 80 rows
// (four bands) on any device.
TEST(SlopeGPU, MatchesCPUWhenOutputsExceedOneStorageBuffer)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  terroir::gpu::Context& context = terroir::gpu::Context::Global();
  const long long device = context.GetLimits().MaxShaderStorageBlockSize;
  const long long cap = 320 << 10;
  ASSERT_GT(device, cap);
  context.SetStorageBlockLimit(cap);
  EXPECT_EQ(context.GetLimits().MaxShaderStorageBlockSize, cap);
  const int nx = 301, ny = 257;
  ASSERT_LE(4LL * nx * ny, cap);      // the elevation in one buffer
  ASSERT_GT(12LL * nx * ny, 2 * cap); // the normals in three bands or more
  auto in = Synthetic(nx, ny, true);
  auto cpu = RunSlope(in, vtkTerroirComputeContext::CPU);
  auto gpu = RunSlope(in, vtkTerroirComputeContext::GPU);
  context.SetStorageBlockLimit(0);
  EXPECT_EQ(context.GetLimits().MaxShaderStorageBlockSize, device);
  Compare(cpu, gpu, "banded");
}

TEST(SlopeGPU, Timing2048)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  auto in = Synthetic(2048, 2048, false);
  RunSlope(in, vtkTerroirComputeContext::GPU);
  double tc = 0.0, tg = 0.0;
  auto cpu = RunSlope(in, vtkTerroirComputeContext::CPU, &tc);
  auto gpu = RunSlope(in, vtkTerroirComputeContext::GPU, &tg);
  const double mcells = in->GetNumberOfPoints() / 1e6;
  // Kernel traffic: read 4 B elevation, write 4 + 4 + 12 B (slope, aspect, normals).
  const double bytes = in->GetNumberOfPoints() * 24.0;
  std::cout << "2048^2: CPU " << tc / mcells << " s/Mcell (" << bytes / tc / 1e9
            << " GB/s effective), GPU " << tg / mcells << " s/Mcell (" << bytes / tg / 1e9
            << " GB/s effective, with transfers)" << std::endl;
  Compare(cpu, gpu, "2048^2");
}

} // namespace

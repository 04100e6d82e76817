// vtkTerroirTemperature: GPU path (Shaders/Temperature.comp) against the CPU path (float).
#include "TerroirFilterTestUtilities.h"

#include "vtkDataArray.h"
#include "vtkPointData.h"
#include "vtkTerroirComputeContext.h"
#include "vtkTerroirTemperature.h"
#include "vtkTimerLog.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <iostream>

namespace
{

vtkSmartPointer<vtkImageData> RunTemperature(vtkImageData* in,
  int backend,
  bool south,
  double* seconds = nullptr)
{
  auto f = vtkSmartPointer<vtkTerroirTemperature>::New();
  f->SetBackend(backend);
  if (south)
  {
    f->SetHemisphereToSouth();
    f->SetLapseRate(5.5);
  }
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

void Compare(vtkImageData* cpu, vtkImageData* gpu)
{
  vtkDataArray* c = cpu->GetPointData()->GetArray("Temperature");
  vtkDataArray* g = gpu->GetPointData()->GetArray("Temperature");
  ASSERT_NE(g, nullptr);
  ASSERT_EQ(g->GetNumberOfTuples(), c->GetNumberOfTuples());
  double maxDiff = 0.0;
  int bad = 0;
  for (vtkIdType k = 0; k < c->GetNumberOfTuples(); ++k)
  {
    for (int m = 0; m < 12; ++m)
    {
      const double a = c->GetComponent(k, m), b = g->GetComponent(k, m);
      if (std::isnan(a) || std::isnan(b))
      {
        if (std::isnan(a) != std::isnan(b) && bad++ < 10)
        {
          ADD_FAILURE() << "NaN mismatch at cell " << k << " month " << m + 1;
        }
        continue;
      }
      maxDiff = std::max(maxDiff, std::fabs(a - b));
      if (std::fabs(a - b) > 1e-3 + 1e-5 * std::fabs(a) && bad++ < 10)
      {
        ADD_FAILURE() << "cell " << k << " month " << m + 1 << ": " << b << " vs " << a;
      }
    }
  }
  std::cout << "temperature: max |gpu-cpu| " << maxDiff << " degC" << std::endl;
  EXPECT_EQ(bad, 0);
}

TEST(TemperatureGPU, MatchesCPUOnBundledDEMAndSyntheticGridWithNoData)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  auto dem =
    terroir_test::ReadDEM(terroir_test::DataFile("sagehen_creek_ca/sagehen_dem_utm11n_10m.tif"));
  ASSERT_NE(dem, nullptr);
  RunTemperature(dem, vtkTerroirComputeContext::GPU, false); // warm-up
  double tc = 0.0, tg = 0.0;
  auto cpu = RunTemperature(dem, vtkTerroirComputeContext::CPU, false, &tc);
  auto gpu = RunTemperature(dem, vtkTerroirComputeContext::GPU, false, &tg);
  const double mcells = dem->GetNumberOfPoints() / 1e6;
  std::cout << "temperature bundled DEM: CPU " << tc / mcells << " s/Mcell, GPU " << tg / mcells
            << " s/Mcell" << std::endl;
  Compare(cpu, gpu);

  std::uint64_t state = 7;
  auto synthetic = terroir_test::MakeTerrain(513,
    389,
    5.0,
    5.0,
    [&](int i, int j)
    {
      state = state * 6364136223846793005ULL + 1442695040888963407ULL;
      const double u = static_cast<double>(state >> 11) / 9007199254740992.0;
      return u < 0.05 ? std::nan("") : -50.0 + 4000.0 * u * std::fabs(std::sin(0.01 * i * j));
    });
  Compare(RunTemperature(synthetic, vtkTerroirComputeContext::CPU, true),
    RunTemperature(synthetic, vtkTerroirComputeContext::GPU, true));

  auto big = terroir_test::MakeTerrain(2048,
    2048,
    10.0,
    10.0,
    [](int i, int j) { return 1000.0 + 500.0 * std::sin(i * 0.01 + j * 0.02); });
  RunTemperature(big, vtkTerroirComputeContext::CPU, false, &tc);
  RunTemperature(big, vtkTerroirComputeContext::GPU, false, &tg);
  std::cout << "temperature 2048^2: CPU " << tc / 4.194304 << " s/Mcell, GPU " << tg / 4.194304
            << " s/Mcell" << std::endl;
}

} // namespace

// vtkTerroirSoilHumidity: GPU path (Shaders/SoilHumidity.comp) against the CPU path (float),
// on the bundled DEM through the infiltration filter and on a synthetic grid of random rates
// with no-data cells, over more cells than one GPU slice.
#include "TerroirFilterTestUtilities.h"

#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkPointData.h"
#include "vtkTerroirComputeContext.h"
#include "vtkTerroirInfiltration.h"
#include "vtkTerroirSoilHumidity.h"
#include "vtkTimerLog.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <iostream>

namespace
{

vtkSmartPointer<vtkImageData> RunHumidity(vtkImageData* in, int backend, double* seconds = nullptr)
{
  auto f = vtkSmartPointer<vtkTerroirSoilHumidity>::New();
  f->SetBackend(backend);
  // A wet month with a zero intensity allowed only because its quantity is 0 (August).
  const double q[12] = { 150, 140, 110, 60, 35, 15, 5, 0, 15, 50, 110, 145 };
  const double i[12] = { 2.5, 2.5, 2, 1.5, 3, 6, 10, 0, 5, 2, 2, 2.5 };
  f->SetPrecipitation(q);
  f->SetPrecipitationIntensity(i);
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
  for (const char* name : { "SoilHumidity", "WeightedSoilHumidity", "StandingWater" })
  {
    vtkDataArray* c = cpu->GetPointData()->GetArray(name);
    vtkDataArray* g = gpu->GetPointData()->GetArray(name);
    ASSERT_NE(c, nullptr) << name;
    ASSERT_NE(g, nullptr) << name;
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
            ADD_FAILURE() << name << ": NaN mismatch at cell " << k << " month " << m + 1;
          }
          continue;
        }
        maxDiff = std::max(maxDiff, std::fabs(a - b));
        // STYLE.md tolerance, atol 1e-4 mm.
        if (std::fabs(a - b) > 1e-4 + 1e-5 * std::fabs(a) && bad++ < 10)
        {
          ADD_FAILURE() << name << " cell " << k << " month " << m + 1 << ": " << b << " vs " << a;
        }
      }
    }
    std::cout << name << ": max |gpu-cpu| " << maxDiff << " mm" << std::endl;
    EXPECT_EQ(bad, 0) << name;
  }
}

TEST(SoilHumidityGPU, MatchesCPUOnBundledDEMAndRandomRatesWithNoData)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  auto dem =
    terroir_test::ReadDEM(terroir_test::DataFile("sagehen_creek_ca/sagehen_dem_utm11n_10m.tif"));
  ASSERT_NE(dem, nullptr);
  auto rates = vtkSmartPointer<vtkTerroirInfiltration>::New();
  rates->SetInputData(dem);
  rates->Update();
  vtkImageData* withRates = rates->GetOutput();
  RunHumidity(withRates, vtkTerroirComputeContext::GPU); // warm-up
  double tc = 0.0, tg = 0.0;
  auto cpu = RunHumidity(withRates, vtkTerroirComputeContext::CPU, &tc);
  auto gpu = RunHumidity(withRates, vtkTerroirComputeContext::GPU, &tg);
  const double mcells = dem->GetNumberOfPoints() / 1e6;
  std::cout << "soil humidity bundled DEM: CPU " << tc / mcells << " s/Mcell, GPU " << tg / mcells
            << " s/Mcell" << std::endl;
  Compare(cpu, gpu);

  // 1100 x 1000 cells (more than one 2^20-cell GPU slice), random rates 0 .. 20 mm/h that
  // straddle every month's intensity, 5 % no-data elevations and 1 % NaN rates.
  std::uint64_t state = 11;
  auto next = [&state]
  {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) / 9007199254740992.0;
  };
  auto synthetic = terroir_test::MakeTerrain(
    1100, 1000, 5.0, 5.0, [&](int, int) { return next() < 0.05 ? std::nan("") : 100.0; });
  auto rate = vtkSmartPointer<vtkFloatArray>::New();
  rate->SetName("InfiltrationRate");
  rate->SetNumberOfValues(synthetic->GetNumberOfPoints());
  for (vtkIdType k = 0; k < synthetic->GetNumberOfPoints(); ++k)
  {
    const double u = next();
    rate->SetValue(k, u < 0.01 ? std::nanf("") : static_cast<float>(20.0 * next()));
  }
  synthetic->GetPointData()->AddArray(rate);
  Compare(RunHumidity(synthetic, vtkTerroirComputeContext::CPU),
    RunHumidity(synthetic, vtkTerroirComputeContext::GPU));
}

} // namespace

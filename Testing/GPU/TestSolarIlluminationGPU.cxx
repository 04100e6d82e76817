// vtkTerroirSolarIllumination: GPU path (Shaders/ShadowSweep.comp, ShadowGather.comp,
// SolarIllumination.comp) against the CPU path (float), every mode and shadow method, on a
// crop of the bundled DEM with a hole of no data.
//
// Tolerances (STYLE.md): horizon angles 1e-4 deg; hours 1e-4 h and energy 1e-3 Wh/m^2 (plus
// 1e-5 relative). A lit/shadow answer may flip only where the sun is within rounding of a
// cell's horizon: such a cell differs by whole time steps; at most 0.1 % of the cells may,
// and they are reported (count and the first 10 cells).
#include "TerroirFilterTestUtilities.h"

#include "vtkDataArray.h"
#include "vtkExtractVOI.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkTerroirComputeContext.h"
#include "vtkTerroirSolarIllumination.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <sstream>

namespace
{
vtkSmartPointer<vtkImageData> Crop()
{
  auto dem =
    terroir_test::ReadDEM(terroir_test::DataFile("sagehen_creek_ca/sagehen_dem_utm11n_10m.tif"));
  vtkNew<vtkExtractVOI> voi;
  voi->SetInputData(dem);
  voi->SetVOI(400, 519, 300, 419, 0, 0);
  voi->Update();
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->DeepCopy(voi->GetOutput());
  out->SetExtent(0, 119, 0, 119, 0, 0);
  out->GetFieldData()->ShallowCopy(dem->GetFieldData());
  vtkDataArray* z = out->GetPointData()->GetArray("Elevation");
  for (int k = 60 * 120 + 10; k < 60 * 120 + 40; ++k)
  {
    z->SetComponent(k, 0, std::nan(""));
  }
  return out;
}

vtkSmartPointer<vtkImageData> RunIllumination(vtkImageData* in, int backend, int mode, int method)
{
  vtkNew<vtkTerroirSolarIllumination> f;
  f->SetBackend(backend);
  f->SetMode(mode);
  f->SetShadowMethod(method);
  f->SetOutputHorizonMap(true);
  f->SetYear(2025);
  f->SetMonth(12);
  f->SetDay(21);
  f->SetTime(15.5);
  f->SetUTCOffset(-8.0);
  f->SetTimeStep(mode == vtkTerroirSolarIllumination::Monthly ? 60.0 : 10.0);
  f->SetInputData(in);
  f->Update();
  EXPECT_EQ(f->GetLastBackend(), backend);
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->ShallowCopy(f->GetOutput());
  return out;
}

/// Compares one array; `step` > 0: a difference of whole steps counts as a threshold flip.
void Compare(vtkImageData* cpu,
  vtkImageData* gpu,
  const char* name,
  double atol,
  double step,
  const std::string& what)
{
  vtkDataArray* c = cpu->GetPointData()->GetArray(name);
  vtkDataArray* g = gpu->GetPointData()->GetArray(name);
  ASSERT_TRUE(c && g) << what << " " << name;
  ASSERT_EQ(c->GetNumberOfValues(), g->GetNumberOfValues());
  const int nc = c->GetNumberOfComponents();
  vtkIdType bad = 0;
  vtkIdType flips = 0;
  double worst = 0.0;
  std::ostringstream first;
  for (vtkIdType k = 0; k < c->GetNumberOfTuples(); ++k)
  {
    bool flipped = false;
    for (int m = 0; m < nc; ++m)
    {
      const double a = c->GetComponent(k, m);
      const double b = g->GetComponent(k, m);
      if (std::isnan(a) || std::isnan(b))
      {
        bad += std::isnan(a) != std::isnan(b) ? 1 : 0;
        continue;
      }
      const double d = std::fabs(a - b);
      if (d <= atol + 1e-5 * std::fabs(a))
      {
        continue;
      }
      const double steps = d / step;
      if (step > 0.0 && std::fabs(steps - std::round(steps)) < 1e-3)
      {
        flipped = true;
        continue;
      }
      worst = std::max(worst, d);
      ++bad;
    }
    if (flipped && flips++ < 10)
    {
      first << " (" << k % 120 << "," << k / 120 << ")";
    }
  }
  std::cout << what << " " << name << ": " << flips << " threshold flips" << first.str()
            << std::endl;
  EXPECT_EQ(bad, 0) << what << " " << name << ": worst |gpu - cpu| " << worst;
  EXPECT_LE(flips, c->GetNumberOfTuples() / 1000) << what << " " << name;
}
/// Compares `name` where the lit hours (or the 0/1 mask) `gate` agree: a flipped step moves
/// the energy by that step's beam, which is no whole multiple of anything.
void CompareWhereGateAgrees(vtkImageData* cpu,
  vtkImageData* gpu,
  const char* name,
  const char* gate,
  double atol,
  const std::string& what)
{
  vtkDataArray* hc = cpu->GetPointData()->GetArray(gate);
  vtkDataArray* hg = gpu->GetPointData()->GetArray(gate);
  vtkDataArray* ec = cpu->GetPointData()->GetArray(name);
  vtkDataArray* eg = gpu->GetPointData()->GetArray(name);
  ASSERT_TRUE(hc && hg && ec && eg) << what << " " << name;
  vtkIdType bad = 0;
  double worst = 0.0;
  for (vtkIdType k = 0; k < hc->GetNumberOfValues(); ++k)
  {
    const double a = ec->GetVariantValue(k).ToDouble();
    const double b = eg->GetVariantValue(k).ToDouble();
    if (std::isnan(a) || std::isnan(b))
    {
      bad += std::isnan(a) != std::isnan(b) ? 1 : 0;
      continue;
    }
    if (hc->GetVariantValue(k).ToDouble() != hg->GetVariantValue(k).ToDouble())
    {
      continue;
    }
    worst = std::max(worst, std::fabs(a - b));
    bad += std::fabs(a - b) > atol + 1e-5 * std::fabs(a) ? 1 : 0;
  }
  EXPECT_EQ(bad, 0) << what << " " << name << ": worst |gpu - cpu| " << worst;
}
} // namespace

TEST(SolarIlluminationGPU, MatchesCPUInEveryModeAndMethod)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  auto in = Crop();
  const int cpu = vtkTerroirComputeContext::CPU;
  const int gpu = vtkTerroirComputeContext::GPU;
  for (int method :
    { vtkTerroirSolarIllumination::HorizonMap, vtkTerroirSolarIllumination::RayMarching })
  {
    for (int mode : { vtkTerroirSolarIllumination::Instant,
           vtkTerroirSolarIllumination::Daily,
           vtkTerroirSolarIllumination::Monthly })
    {
      const std::string what =
        std::string(method ? "map" : "ray") + " mode " + std::to_string(mode);
      auto c = RunIllumination(in, cpu, mode, method);
      auto g = RunIllumination(in, gpu, mode, method);
      Compare(c, g, "HorizonAngle", 1e-4, 0.0, what);
      if (mode == vtkTerroirSolarIllumination::Instant)
      {
        Compare(c, g, "Illuminated", 0.0, 1.0, what);
        CompareWhereGateAgrees(c, g, "SunIncidence", "Illuminated", 1e-5, what);
      }
      else
      {
        const double step = mode == vtkTerroirSolarIllumination::Monthly ? 1.0 : 1.0 / 6.0;
        Compare(c, g, "IlluminationHours", 1e-4, step, what);
        CompareWhereGateAgrees(c, g, "Insolation", "IlluminationHours", 1e-3, what);
      }
    }
  }
}

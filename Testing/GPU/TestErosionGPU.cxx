// The GPU path of hydraulic and thermal erosion (RunErosionGPU, Shaders/Erosion.comp) against
// the CPU core (terroir::terrain::ErosionHydraulicStep, ErosionThermalStep): every array of the
// state after 50-200 steps on small random terrains (Closed and Sea boundaries, no-data cells,
// a soil layer, per-cell erosion and talus factors, rain and evaporation fields, a thermal step
// every step or every third), the summed volumes, conservation on a closed domain over 1000
// steps, and no negative water, sediment or soil.
//
// Tolerance: none. The kernels do the core's float operations in the same order (`precise`,
// no fused multiply-add), divide and take square roots correctly rounded (terroirDiv,
// SqrtFloat), and sum the volumes row by row in cell order and then over the rows, in double,
// as the core does; so every array and every volume is compared bit for bit
// (CompareStates counts the entries whose bits differ and prints the largest difference in
// units in the last place). The only exception is Weiss's eq. 24 (halving depths), where the
// kernel's exp2 is the driver's: that case allows 1e-4 relative on the bed after 50 steps.
#include "TerroirFilterTestUtilities.h"

#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkTerroirComputeContext.h"
#include "vtkTerroirErosion.h"
#include "vtkTerroirErosionGPU.h"
#include "vtkTerroirGPU.h"

#include "Erosion.h"
#include "GridView.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <ctime>
#include <functional>
#include <iostream>
#include <random>
#include <string>
#include <vector>

namespace
{
namespace tr = terroir::terrain;

/// What a scene adds to the state and the step arguments.
struct SceneOptions
{
  int nx = 37;
  int ny = 29;
  unsigned seed = 1;
  bool mask = false;        ///< about 5 % no-data cells
  bool soil = false;        ///< a soil layer 0-0.3 m
  bool factors = false;     ///< per-cell erosion and talus factors in [0.3, 1.3]
  bool rainField = false;   ///< rain rates per cell
  bool evaporation = false; ///< evaporation factors per cell
  bool geographic = false;  ///< east-west spacing changing from row to row
  double base = 0.0;        ///< height of the terrain's base, m
  float water = 0.05f;      ///< initial water, m (plus up to 0.05 m at random)
};

/// A scene: the state and the rain and evaporation fields.
struct Scene
{
  tr::ErosionState state;
  std::vector<float> rain;
  std::vector<float> evaporation;
  const float* Rain() const { return rain.empty() ? nullptr : rain.data(); }
  const float* Evaporation() const { return evaporation.empty() ? nullptr : evaporation.data(); }
};

Scene MakeScene(const SceneOptions& o)
{
  std::mt19937 rng(o.seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const std::size_t n = static_cast<std::size_t>(o.nx) * o.ny;
  std::vector<float> z(n);
  std::vector<std::uint8_t> valid(n, 1);
  std::vector<double> rowDx(o.ny);
  for (int j = 0; j < o.ny; ++j)
  {
    rowDx[j] = o.geographic ? 10.0 * std::cos((40.0 + 0.3 * j) * 3.14159265358979 / 180.0) : 10.0;
    for (int i = 0; i < o.nx; ++i)
    {
      const std::size_t c = static_cast<std::size_t>(j) * o.nx + i;
      z[c] = static_cast<float>(o.base + 4.0 + 2.0 * std::sin(0.31 * i) * std::cos(0.27 * j) +
        0.05 * i - 0.04 * j + 0.8 * uniform(rng));
      if (o.mask && uniform(rng) < 0.05)
      {
        valid[c] = 0;
      }
    }
  }
  terroir::GridView<float> view;
  view.nx = o.nx;
  view.ny = o.ny;
  view.dx = 10.0;
  view.dy = 8.0;
  view.data = z.data();
  view.valid = o.mask ? valid.data() : nullptr;
  view.rowDx = rowDx.data();
  std::vector<float> soil(n);
  for (float& s : soil)
  {
    s = static_cast<float>(0.3 * uniform(rng));
  }
  Scene scene;
  scene.state = tr::MakeErosionState(view, o.soil ? soil.data() : nullptr);
  tr::ErosionState& st = scene.state;
  for (std::size_t c = 0; c < n; ++c)
  {
    st.water[c] = st.IsValid(c) ? o.water + static_cast<float>(0.05 * uniform(rng)) : 0.0f;
  }
  if (o.factors)
  {
    st.erosionFactor.resize(n);
    st.talusFactor.resize(n);
    for (std::size_t c = 0; c < n; ++c)
    {
      st.erosionFactor[c] = static_cast<float>(0.3 + uniform(rng));
      st.talusFactor[c] = static_cast<float>(0.3 + uniform(rng));
    }
  }
  if (o.rainField)
  {
    scene.rain.resize(n);
    for (float& r : scene.rain)
    {
      r = static_cast<float>(0.2 * uniform(rng));
    }
  }
  if (o.evaporation)
  {
    scene.evaporation.resize(n);
    for (float& e : scene.evaporation)
    {
      e = static_cast<float>(1.5 * uniform(rng) - 0.1);
    }
  }
  return scene;
}

/// The CPU reference: what RunErosionGPU promises to compute.
tr::ErosionGPUTotals RunCPU(Scene& scene,
  const tr::ErosionParams& p,
  const tr::ThermalParams& th,
  int interval,
  int steps)
{
  tr::ErosionGPUTotals t;
  for (int s = 1; s <= steps; ++s)
  {
    const tr::ErosionStepStats h =
      tr::ErosionHydraulicStep(scene.state, p, scene.Rain(), scene.Evaporation());
    t.hydraulic.rain += h.rain;
    t.hydraulic.evaporated += h.evaporated;
    t.hydraulic.waterToSea += h.waterToSea;
    t.hydraulic.waterClamped += h.waterClamped;
    t.hydraulic.eroded += h.eroded;
    t.hydraulic.deposited += h.deposited;
    t.hydraulic.sedimentScale = h.sedimentScale;
    if (interval > 0 && s % interval == 0)
    {
      const tr::ThermalStepStats m = tr::ErosionThermalStep(scene.state, th);
      t.thermal.moved += m.moved;
      t.thermal.maxExcess = m.maxExcess;
    }
  }
  return t;
}

/// Distance in units in the last place between two floats of the same sign (large otherwise).
double Ulps(float a, float b)
{
  std::int32_t ia, ib;
  std::memcpy(&ia, &a, 4);
  std::memcpy(&ib, &b, 4);
  if ((ia < 0) != (ib < 0))
  {
    return a == b ? 0.0 : 1e9;
  }
  return std::fabs(static_cast<double>(ia) - static_cast<double>(ib));
}

/// Entries whose bits differ between cpu and gpu, and the largest difference in ulp.
struct Difference
{
  std::size_t differing = 0;
  double maxUlps = 0.0;
  double maxRelative = 0.0;
};

Difference CompareArray(const std::vector<float>& cpu, const std::vector<float>& gpu)
{
  Difference d;
  EXPECT_EQ(cpu.size(), gpu.size());
  for (std::size_t c = 0; c < std::min(cpu.size(), gpu.size()); ++c)
  {
    if (std::memcmp(&cpu[c], &gpu[c], sizeof(float)) != 0)
    {
      ++d.differing;
      d.maxUlps = std::max(d.maxUlps, Ulps(cpu[c], gpu[c]));
      d.maxRelative = std::max(d.maxRelative,
        std::fabs(static_cast<double>(gpu[c]) - cpu[c]) / std::max(1e-30, std::fabs(1.0 * cpu[c])));
    }
  }
  return d;
}

/// Compares every array of the two states; bit-identical unless `relative` > 0, where the
/// difference of each entry may be up to relative |cpu| + relative (for exp2's rounding).
void CompareStates(const tr::ErosionState& cpu,
  const tr::ErosionState& gpu,
  const std::string& label,
  double relative = 0.0)
{
  const std::pair<const char*, const std::vector<float> tr::ErosionState::*> arrays[] = {
    { "terrain", &tr::ErosionState::terrain },
    { "terrainResidue", &tr::ErosionState::terrainResidue },
    { "soil", &tr::ErosionState::soil },
    { "water", &tr::ErosionState::water },
    { "waterResidue", &tr::ErosionState::waterResidue },
    { "sediment", &tr::ErosionState::sediment },
    { "fluxW", &tr::ErosionState::fluxW },
    { "fluxE", &tr::ErosionState::fluxE },
    { "fluxS", &tr::ErosionState::fluxS },
    { "fluxN", &tr::ErosionState::fluxN },
    { "velocityU", &tr::ErosionState::velocityU },
    { "velocityV", &tr::ErosionState::velocityV }
  };
  for (const auto& a : arrays)
  {
    const std::vector<float>& c = cpu.*(a.second);
    const std::vector<float>& g = gpu.*(a.second);
    const Difference d = CompareArray(c, g);
    if (relative == 0.0)
    {
      EXPECT_EQ(d.differing, 0u) << label << ": " << a.first << " differs in " << d.differing
                                 << " of " << c.size() << " cells, by up to " << d.maxUlps
                                 << " ulp";
    }
    else if (std::string(a.first) == "terrain" || std::string(a.first) == "soil")
    {
      EXPECT_LE(d.maxRelative, relative) << label << ": " << a.first;
    }
    if (d.differing > 0)
    {
      std::cout << label << ": " << a.first << " " << d.differing << " cells differ, max "
                << d.maxUlps << " ulp, " << d.maxRelative << " relative" << std::endl;
    }
  }
}

void ExpectSameVolumes(const tr::ErosionGPUTotals& cpu,
  const tr::ErosionGPUTotals& gpu,
  const std::string& label)
{
  EXPECT_EQ(gpu.hydraulic.rain, cpu.hydraulic.rain) << label;
  EXPECT_EQ(gpu.hydraulic.evaporated, cpu.hydraulic.evaporated) << label;
  EXPECT_EQ(gpu.hydraulic.waterToSea, cpu.hydraulic.waterToSea) << label;
  EXPECT_EQ(gpu.hydraulic.waterClamped, cpu.hydraulic.waterClamped) << label;
  EXPECT_EQ(gpu.hydraulic.eroded, cpu.hydraulic.eroded) << label;
  EXPECT_EQ(gpu.hydraulic.deposited, cpu.hydraulic.deposited) << label;
  EXPECT_EQ(gpu.hydraulic.sedimentScale, cpu.hydraulic.sedimentScale) << label;
  EXPECT_EQ(gpu.thermal.moved, cpu.thermal.moved) << label;
  EXPECT_EQ(gpu.thermal.maxExcess, cpu.thermal.maxExcess) << label;
}

/// Water, sediment and soil are never negative.
void ExpectNonNegative(const tr::ErosionState& st, const std::string& label)
{
  for (const std::vector<float>* a : { &st.water, &st.sediment, &st.soil })
  {
    for (float x : *a)
    {
      ASSERT_GE(x, 0.0f) << label;
    }
  }
}

/// Runs a scene on both paths and compares everything.
void RunBoth(const SceneOptions& o,
  const tr::ErosionParams& p,
  const tr::ThermalParams& th,
  int interval,
  int steps,
  const std::string& label,
  double relative = 0.0)
{
  Scene cpu = MakeScene(o);
  Scene gpu = MakeScene(o);
  const tr::ErosionGPUTotals expected = RunCPU(cpu, p, th, interval, steps);
  tr::ErosionGPUTotals got;
  tr::RunErosionGPU(gpu.state, p, th, interval, gpu.Rain(), gpu.Evaporation(), steps, &got);
  CompareStates(cpu.state, gpu.state, label, relative);
  if (relative == 0.0)
  {
    ExpectSameVolumes(expected, got, label);
  }
  ExpectNonNegative(gpu.state, label);
  // The test proves something only if material moved.
  EXPECT_GT(got.hydraulic.eroded, 0.0) << label;
  std::cout << label << ": eroded " << got.hydraulic.eroded << " m3 (cpu "
            << expected.hydraulic.eroded << "), deposited " << got.hydraulic.deposited
            << ", to sea " << got.hydraulic.waterToSea << ", thermal moved " << got.thermal.moved
            << " m3 (cpu " << expected.thermal.moved << ")" << std::endl;
}

tr::ThermalParams Slippery()
{
  tr::ThermalParams th;
  th.talusSoilDeg = 5.0; // the test terrain's slopes exceed it, so the thermal step moves soil
  th.talusRockDeg = 8.0;
  th.rate = 0.5;
  return th;
}
} // namespace

TEST(TerroirErosionGPU, ClosedSoilFactorsRainEvaporationThermalEveryStep)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  SceneOptions o;
  o.mask = true;
  o.soil = true;
  o.factors = true;
  o.rainField = true;
  o.evaporation = true;
  o.geographic = true;
  tr::ErosionParams p;
  p.dissolvingRock = 0.03;
  p.evaporation = 0.5;
  RunBoth(o, p, Slippery(), 1, 120, "closed, soil, factors, thermal 1");
}

TEST(TerroirErosionGPU, SeaWithNoDataThermalEveryThirdStep)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  SceneOptions o;
  o.seed = 7;
  o.mask = true;
  o.rainField = true;
  tr::ErosionParams p;
  p.boundary = tr::ErosionBoundary::Sea;
  p.seaLevel = 3.0;
  RunBoth(o, p, Slippery(), 3, 150, "sea, one material, thermal 3");
  o.soil = true;
  o.factors = true;
  o.evaporation = true;
  o.seed = 8;
  RunBoth(o, p, Slippery(), 3, 60, "sea, soil, factors, thermal 3");
}

TEST(TerroirErosionGPU, OptionsOfWeissAndDunn)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  SceneOptions o;
  o.seed = 3;
  o.soil = true;
  o.base = 1000.0; // where the bed's residue carries most of the erosion
  tr::ErosionParams p;
  p.softOutflow = true;
  p.softOutflowMin = 0.01;
  p.softOutflowScale = 0.5;
  p.capacityDepth = 0.03;
  p.maxBedChange = 0.002;
  p.pipeArea = 20.0;
  RunBoth(o, p, Slippery(), 0, 200, "soft outflow, capacity depth, bed bound, pipe area");
  // Weiss's eq. 24: the kernel's exp2 is the driver's, so a small tolerance.
  p.halvingDepthErosion = 0.01;
  p.halvingDepthDeposition = 0.02;
  RunBoth(o, p, Slippery(), 2, 50, "halving depths (exp2)", 1e-4);
}

TEST(TerroirErosionGPU, ThinGrids)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  // One row, one column, 2 x 2: the edge tests of every kernel (pipes, tilt, bilinear sample,
  // eight neighbours) with the grid's edge on both sides.
  const int sizes[][2] = { { 1, 23 }, { 23, 1 }, { 2, 2 } };
  for (const auto& size : sizes)
  {
    for (int sea = 0; sea < 2; ++sea)
    {
      SceneOptions o;
      o.nx = size[0];
      o.ny = size[1];
      o.soil = true;
      o.rainField = true;
      tr::ErosionParams p;
      p.boundary = sea ? tr::ErosionBoundary::Sea : tr::ErosionBoundary::Closed;
      p.seaLevel = 2.0;
      RunBoth(o,
        p,
        Slippery(),
        2,
        60,
        std::to_string(o.nx) + " x " + std::to_string(o.ny) + (sea ? ", sea" : ", closed"));
    }
  }
}

TEST(TerroirErosionGPU, TwoRunsEqualOne)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  // The state read back (residues, fluxes, velocities included) is the whole state: a run of
  // 2 x 45 steps gives the bits of 90 steps on the CPU (45 is a multiple of the thermal
  // interval, so the thermal steps fall on the same steps).
  SceneOptions o;
  o.seed = 5;
  o.mask = true;
  o.soil = true;
  o.factors = true;
  tr::ErosionParams p;
  Scene cpu = MakeScene(o);
  Scene gpu = MakeScene(o);
  RunCPU(cpu, p, Slippery(), 3, 90);
  for (int run = 0; run < 2; ++run)
  {
    tr::RunErosionGPU(gpu.state, p, Slippery(), 3, nullptr, nullptr, 45);
  }
  CompareStates(cpu.state, gpu.state, "2 x 45 steps");
}

TEST(TerroirErosionGPU, ClosedDomainConservesWaterAndMaterialOverAThousandSteps)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  for (int layered = 0; layered < 2; ++layered)
  {
    SceneOptions o;
    o.nx = 32;
    o.ny = 24;
    o.seed = 11 + layered;
    o.soil = layered == 1;
    o.base = 1000.0;
    o.water = 0.2f;
    Scene scene = MakeScene(o);
    tr::ErosionParams p;
    p.evaporation = 0.0;
    p.dissolvingRock = 0.02;
    const tr::ErosionTotals t0 = tr::ErosionMeasure(scene.state);
    tr::ErosionGPUTotals got;
    tr::RunErosionGPU(scene.state, p, Slippery(), 10, nullptr, nullptr, 1000, &got);
    const tr::ErosionTotals t1 = tr::ErosionMeasure(scene.state);
    EXPECT_NEAR(t1.water, t0.water, 1e-6 * t0.water) << "layered " << layered;
    const double material0 = t0.terrain + t0.sediment;
    const double material1 = t1.terrain + t1.sediment;
    EXPECT_NEAR(material1, material0, 1e-6 * material0) << "layered " << layered;
    EXPECT_GT(got.hydraulic.eroded, 1.0) << "little erosion: the test would prove little";
    EXPECT_NEAR((t1.terrain - t0.terrain) + t1.sediment, 0.0, 1e-7 * got.hydraulic.eroded);
    EXPECT_GT(got.thermal.moved, 0.0);
    EXPECT_EQ(got.hydraulic.rain, 0.0);
    EXPECT_EQ(got.hydraulic.waterToSea, 0.0);
    ExpectNonNegative(scene.state, "conservation");
  }
}

TEST(TerroirErosionGPU, BadArguments)
{
  SceneOptions o;
  Scene scene = MakeScene(o);
  tr::ErosionParams p;
  tr::ThermalParams th;
  EXPECT_THROW(
    tr::RunErosionGPU(scene.state, p, th, 0, nullptr, nullptr, -1), std::invalid_argument);
  EXPECT_THROW(
    tr::RunErosionGPU(scene.state, p, th, -2, nullptr, nullptr, 1), std::invalid_argument);
  p.timeStep = 0.0;
  EXPECT_THROW(
    tr::RunErosionGPU(scene.state, p, th, 0, nullptr, nullptr, 1), std::invalid_argument);
  p = tr::ErosionParams();
  th.rate = 2.0;
  EXPECT_THROW(
    tr::RunErosionGPU(scene.state, p, th, 1, nullptr, nullptr, 1), std::invalid_argument);
  scene.state.sediment.pop_back();
  EXPECT_THROW(tr::RunErosionGPU(scene.state, p, tr::ThermalParams(), 0, nullptr, nullptr, 1),
    std::invalid_argument);
}

// Steps per second of the CPU core (one thread) and of the GPU path at 256^2 and 1024^2, soil
// layer, the thermal step every 4th step. The GPU's rate per step is (T(steps) - T(1)) /
// (steps - 1), leaving out the upload and read-back that every run pays once (printed apart).
// Wall times, and in brackets the process CPU time (llvmpipe's threads included; steadier on a
// shared machine). Results are also compared (bit for bit) so the timed runs are the right ones.
// TerroirGPUTests --gtest_also_run_disabled_tests --gtest_filter='TerroirErosionGPU.DISABLED_*'
TEST(TerroirErosionGPU, DISABLED_Timings)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  using Clock = std::chrono::steady_clock;
  struct Time
  {
    double wall, cpu;
  };
  auto timed = [](const std::function<void()>& f)
  {
    const auto t0 = Clock::now();
    const std::clock_t c0 = std::clock();
    f();
    return Time{ std::chrono::duration<double>(Clock::now() - t0).count(),
      static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC };
  };
  for (int n : { 256, 1024 })
  {
    SceneOptions o;
    o.nx = n;
    o.ny = n;
    o.soil = true;
    const int steps = n == 256 ? 41 : 11;
    const tr::ErosionParams p;
    Scene cpu = MakeScene(o);
    const Time c = timed([&] { RunCPU(cpu, p, Slippery(), 4, steps); });
    Scene warm = MakeScene(o);
    tr::RunErosionGPU(warm.state, p, Slippery(), 4, nullptr, nullptr, 1); // compile the kernels
    Scene one = MakeScene(o);
    const Time g1 =
      timed([&] { tr::RunErosionGPU(one.state, p, Slippery(), 4, nullptr, nullptr, 1); });
    Scene gpu = MakeScene(o);
    const Time g =
      timed([&] { tr::RunErosionGPU(gpu.state, p, Slippery(), 4, nullptr, nullptr, steps); });
    CompareStates(cpu.state, gpu.state, "timing " + std::to_string(n));
    const double per = (g.wall - g1.wall) / (steps - 1);
    const double perCpu = (g.cpu - g1.cpu) / (steps - 1);
    std::cout << n << "^2, " << steps << " steps: CPU core " << steps / c.wall << " steps/s ("
              << c.wall / steps * 1e3 << " ms/step, cpu " << c.cpu / steps * 1e3 << "); GPU "
              << 1.0 / per << " steps/s (" << per * 1e3 << " ms/step, cpu " << perCpu * 1e3
              << "), plus " << (g1.wall - per) * 1e3
              << " ms upload and read-back; GPU/CPU time per step " << per / (c.wall / steps)
              << " (" << terroir::gpu::Context::Global().GetLimits().Renderer << ")" << std::endl;
  }
}

namespace
{
/// vtkTerroirErosion on `in` to `steps` steps (an UpdateTimeStep on the same filter object
/// continues from its cache), the output's ErodedElevation, water and sediment.
std::vector<float> FilterArrays(vtkTerroirErosion* f, double steps)
{
  f->UpdateTimeStep(steps);
  std::vector<float> out;
  for (const char* name : { vtkTerroirErosion::ErodedElevationName(),
         vtkTerroirErosion::WaterDepthName(),
         vtkTerroirErosion::SedimentName() })
  {
    vtkDataArray* a = f->GetOutput()->GetPointData()->GetArray(name);
    for (vtkIdType k = 0; a && k < a->GetNumberOfTuples(); ++k)
    {
      out.push_back(static_cast<float>(a->GetComponent(k, 0)));
    }
  }
  return out;
}
} // namespace

// The filter's GPU backend gives the CPU backend's bits, also when a later time continues the
// cached state from a step between two soil-slip steps (7 then 20 steps, a slip every third
// step: the GPU run first goes to step 9 with its slip, then on); the volumes agree to 1e-12. With
// Vegetation or Weather a GPU request is one error and no output.
TEST(TerroirErosionGPU, TheFilterBackendsAgreeAcrossTheCache)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  vtkSmartPointer<vtkImageData> in = terroir_test::MakeTerrain(40,
    30,
    5.0,
    5.0,
    [](int i, int j) { return 100.0 + 3.0 * std::sin(0.3 * i) * std::cos(0.25 * j) + 0.2 * i; });
  vtkNew<vtkTerroirErosion> cpu, gpu;
  for (vtkTerroirErosion* f : { cpu.Get(), gpu.Get() })
  {
    f->SetInputData(in);
    f->SetSteps(20);
    f->SetThermalInterval(3);
    f->SetTalusAngle(10.0);
    f->SetRainRate(200.0);
  }
  cpu->SetBackend(vtkTerroirComputeContext::CPU);
  gpu->SetBackend(vtkTerroirComputeContext::GPU);
  for (double t : { 7.0, 20.0 })
  {
    const std::vector<float> a = FilterArrays(cpu, t), b = FilterArrays(gpu, t);
    ASSERT_EQ(a.size(), b.size());
    ASSERT_FALSE(a.empty());
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0) << "t " << t;
    vtkDataArray* va = cpu->GetOutput()->GetFieldData()->GetArray("ErosionVolumes");
    vtkDataArray* vb = gpu->GetOutput()->GetFieldData()->GetArray("ErosionVolumes");
    for (int c = 0; c < 5; ++c)
    {
      // A GPU run sums its steps' volumes before they join the running total: the same terms,
      // another order of the additions.
      EXPECT_NEAR(
        va->GetComponent(0, c), vb->GetComponent(0, c), 1e-12 * std::fabs(va->GetComponent(0, c)))
        << "t " << t << " volume " << c;
    }
  }
  EXPECT_EQ(gpu->GetLastBackend(), vtkTerroirComputeContext::GPU);
  vtkNew<terroir_test::ErrorObserver> observer;
  gpu->AddObserver(vtkCommand::ErrorEvent, observer);
  gpu->WeatherOn();
  gpu->Update();
  EXPECT_NE(observer->Errors.find("turn Vegetation and Weather off"), std::string::npos)
    << observer->Errors;
  EXPECT_EQ(gpu->GetOutput()->GetNumberOfPoints(), 0);
}

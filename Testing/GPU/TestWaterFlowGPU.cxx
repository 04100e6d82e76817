// The GPU path of the hydrostatic water flow (RunWaterFlowGPU, Shaders/WaterFlow.comp) against
// the CPU core (terroir::hydrology::WaterFlowSimulation): same iteration count and stop reason,
// the same padded water and discharge, the same totals, conservation; the snapshot restore when
// a stop rule fires inside a read-back block; independence from the read-back period.
//
// Tolerance: |gpu - cpu| <= 1e-12 m + 1e-9 |cpu| for water depth and discharge (metres of
// depth), 1e-9 relative for the moved and outflow totals. Both sides compute in double with the
// same operations in the same order (the kernel marks its sums `precise`, so no fused
// multiply-add), so per cell they agree to the last bit on llvmpipe (the test prints the largest
// difference); the tolerance leaves room for drivers whose double division is not correctly
// rounded (GLSL only promises single-precision accuracy for double operations) and for the
// volumes, which the GPU sums per work group instead of per row (a different
// summation order: relative differences of a few 1e-16 per iteration).
#include "TerroirFilterTestUtilities.h"

#include "vtkSMPTools.h"
#include "vtkTerroirWaterFlowGPU.h"

#include "FractalNoise.h"
#include "WaterFlow.h"
#include "WaterFlowWarmStart.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <iostream>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{
namespace hy = terroir::hydrology;

constexpr double kDepthAtol = 1e-12; ///< metres
constexpr double kRelative = 1e-9;

/// A terrain, its mask, row spacings and initial water (metres).
struct Scene
{
  int nx;
  int ny;
  std::vector<float> z;
  std::vector<double> water;
  std::vector<std::uint8_t> valid;
  std::vector<double> rowDx;
  terroir::GridView<float> view;

  Scene(int nx_, int ny_, double spacing)
    : nx(nx_)
    , ny(ny_)
    , z(static_cast<std::size_t>(nx_) * ny_, 0.0f)
    , water(z.size(), 0.0f)
  {
    view.nx = nx;
    view.ny = ny;
    view.dx = spacing;
    view.dy = spacing;
  }
  std::size_t At(int i, int j) const { return static_cast<std::size_t>(j) * nx + i; }
  /// The view, pointing at the current vectors.
  const terroir::GridView<float>& View()
  {
    view.data = z.data();
    view.valid = valid.empty() ? nullptr : valid.data();
    view.rowDx = rowDx.empty() ? nullptr : rowDx.data();
    return view;
  }
  hy::WaterFlowSimulation Make() { return hy::WaterFlowSimulation(this->View(), water.data()); }
};

/// (a) Random heights in [0, 10) m inside a wall 50 m high, random water in [0, 0.5) m.
Scene RandomWalled(int nx, int ny, unsigned seed)
{
  Scene s(nx, ny, 10.0);
  std::mt19937 rng(seed);
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      const bool wall = i == 0 || j == 0 || i == nx - 1 || j == ny - 1;
      s.z[s.At(i, j)] = wall ? 50.0f : static_cast<float>(rng() % 10000) * 1e-3f;
      s.water[s.At(i, j)] = wall ? 0.0f : static_cast<float>(rng() % 5000) * 1e-4f;
    }
  }
  return s;
}

/// (b) An open tilted plane with 0-1 m of random relief, about 5 % no-data cells (mask and a
/// NaN height), east-west spacing changing from row to row (a geographic grid), 0.2 m of water.
Scene TiltedWithNoData(int nx, int ny, unsigned seed)
{
  Scene s(nx, ny, 30.0);
  std::mt19937 rng(seed);
  s.valid.assign(s.z.size(), 1);
  s.rowDx.resize(ny);
  for (int j = 0; j < ny; ++j)
  {
    s.rowDx[j] = 30.0 * std::cos((40.0 + 0.05 * j) * 3.14159265358979 / 180.0);
    for (int i = 0; i < nx; ++i)
    {
      const std::size_t c = s.At(i, j);
      s.z[c] = static_cast<float>(100.0 + 0.8 * i + 0.3 * j + (rng() % 1000) * 1e-3);
      s.water[c] = 0.2f;
      if (rng() % 20 == 0)
      {
        s.valid[c] = 0;
      }
    }
  }
  s.z[s.At(nx / 2, ny / 2)] = std::numeric_limits<float>::quiet_NaN();
  return s;
}

/// (c) Fractal terrain (the fractal source's defaults), 30 m cells, 0.1 m of water.
Scene Fractal(int n)
{
  Scene s(n, n, 30.0);
  terroir::io::FractalNoiseParameters p;
  terroir::io::FractalNoisePerlin2002Rows(p, n, 0, n, s.z.data());
  std::fill(s.water.begin(), s.water.end(), 0.1f);
  return s;
}

/// Largest |gpu - cpu| and the number of entries over the tolerance.
struct Difference
{
  double max = 0.0;
  int bad = 0;
};

Difference CompareArray(const std::vector<double>& cpu,
  const std::vector<double>& gpu,
  const char* what)
{
  Difference d;
  EXPECT_EQ(cpu.size(), gpu.size()) << what;
  for (std::size_t k = 0; k < std::min(cpu.size(), gpu.size()); ++k)
  {
    const double e = std::fabs(gpu[k] - cpu[k]);
    d.max = std::max(d.max, e);
    if (!(e <= kDepthAtol + kRelative * std::fabs(cpu[k])) && d.bad++ < 10)
    {
      ADD_FAILURE() << what << " at padded cell " << k << ": gpu " << gpu[k] << " cpu " << cpu[k];
    }
  }
  return d;
}

void ExpectRelative(double cpu, double gpu, const char* what)
{
  EXPECT_LE(std::fabs(gpu - cpu), kRelative * std::fabs(cpu))
    << what << ": gpu " << gpu << " cpu " << cpu;
}

/// The GPU simulation against the CPU one: iterations, state, totals, conservation.
void CompareSimulations(hy::WaterFlowSimulation& cpu,
  hy::WaterFlowSimulation& gpu,
  const char* label)
{
  EXPECT_EQ(gpu.Iterations(), cpu.Iterations()) << label;
  const Difference w = CompareArray(cpu.PaddedWater(), gpu.PaddedWater(), "water");
  const Difference q = CompareArray(cpu.PaddedDischarge(), gpu.PaddedDischarge(), "discharge");
  EXPECT_EQ(w.bad, 0) << label;
  EXPECT_EQ(q.bad, 0) << label;
  ExpectRelative(cpu.TotalMoved(), gpu.TotalMoved(), "total moved");
  ExpectRelative(cpu.TotalOutflow(), gpu.TotalOutflow(), "total outflow");
  // Conservation: what was there is stored or flowed out.
  const double initial = gpu.InitialVolume();
  const double balance = gpu.StoredVolume() + gpu.TotalOutflow() - initial;
  EXPECT_LE(std::fabs(balance), kRelative * initial) << label;
  std::cout << label << ": " << gpu.Iterations() << " iterations, max |gpu-cpu| water " << w.max
            << " m, discharge " << q.max << " m; moved " << gpu.TotalMoved() << " m3 (cpu "
            << cpu.TotalMoved() << "), outflow " << gpu.TotalOutflow() << " m3 (cpu "
            << cpu.TotalOutflow() << "), balance " << balance << " m3 of " << initial << std::endl;
}

/// Runs both to the stop rules (ratio, maximum) and compares them.
void RunBothToStop(Scene& scene,
  double ratio,
  long long maximum,
  int checkEvery,
  const char* label,
  long long preSteps = 0)
{
  hy::WaterFlowSimulation cpu = scene.Make();
  hy::WaterFlowSimulation gpu = scene.Make();
  for (long long k = 0; k < preSteps; ++k)
  {
    cpu.Step();
    gpu.Step();
  }
  hy::WaterFlowStopRule rule;
  rule.autoStopRatio = ratio;
  rule.maximumIterations = maximum;
  const hy::WaterFlowStopReason reason = cpu.Run(rule);
  const hy::WaterFlowGPUResult r = hy::RunWaterFlowGPU(gpu, maximum, true, ratio, checkEvery);
  EXPECT_EQ(r.stopped, reason != hy::WaterFlowStopReason::MaximumIterations) << label;
  EXPECT_EQ(hy::WaterFlowStopReasonName(r.reason), std::string(hy::WaterFlowStopReasonName(reason)))
    << label;
  CompareSimulations(cpu, gpu, label);
}

} // namespace

//------------------------------------------------------------------------------
TEST(TerroirWaterFlowGPU, RandomWalledTerrainFixedIterations)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  Scene scene = RandomWalled(48, 40, 7);
  hy::WaterFlowSimulation cpu = scene.Make();
  hy::WaterFlowSimulation gpu = scene.Make();
  for (int k = 0; k < 37; ++k)
  {
    cpu.Step();
  }
  const hy::WaterFlowGPUResult r = hy::RunWaterFlowGPU(gpu, 37, false, 1e-3, 16);
  EXPECT_FALSE(r.stopped);
  EXPECT_EQ(r.reason, hy::WaterFlowStopReason::MaximumIterations);
  CompareSimulations(cpu, gpu, "walled, 37 iterations");
  EXPECT_EQ(gpu.TotalOutflow(), 0.0); // the wall keeps all the water in
}

TEST(TerroirWaterFlowGPU, RandomWalledTerrainToAutoStop)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  Scene scene = RandomWalled(48, 40, 11);
  RunBothToStop(scene, 1e-3, 5000, 16, "walled, auto stop");
}

TEST(TerroirWaterFlowGPU, TiltedTerrainWithNoDataToAutoStop)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  Scene scene = TiltedWithNoData(64, 48, 3);
  RunBothToStop(scene, 1e-3, 5000, 16, "tilted with no data, auto stop");
}

TEST(TerroirWaterFlowGPU, TiltedPlaneDrainsToNoMovement)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  Scene scene(20, 14, 10.0);
  for (int j = 0; j < scene.ny; ++j)
  {
    for (int i = 0; i < scene.nx; ++i)
    {
      scene.z[scene.At(i, j)] = static_cast<float>(0.5 * i + 0.3 * j);
      scene.water[scene.At(i, j)] = 0.01f;
    }
  }
  hy::WaterFlowSimulation cpu = scene.Make();
  hy::WaterFlowStopRule rule;
  rule.autoStopRatio = 0.0;
  ASSERT_EQ(cpu.Run(rule), hy::WaterFlowStopReason::NoMovement);
  RunBothToStop(scene, 0.0, 10000, 16, "tilted plane, no movement");
}

TEST(TerroirWaterFlowGPU, Fractal256ToAutoStop)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  Scene scene = Fractal(256);
  RunBothToStop(scene, 1e-3, 10000, 16, "fractal 256^2, 0.1 m, auto stop");
}

// The river-forming mode on the GPU: rain every iteration, the net-flux edge sums, the balance
// stop, with a checking period that makes the stop fall inside a block (replayed from the
// snapshot, edges included): the same stop, the same bits as the CPU.
TEST(TerroirWaterFlowGPU, RainAndNetFluxToBalance)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  Scene scene = TiltedWithNoData(64, 48, 5);
  for (double& w : scene.water)
  {
    w = 0.0;
  }
  for (int every : { 16, 7 })
  {
    hy::WaterFlowSimulation cpu = scene.Make();
    hy::WaterFlowSimulation gpu = scene.Make();
    for (auto* sim : { &cpu, &gpu })
    {
      sim->SetRain(2e-4);
      sim->SetNetFlux(true);
    }
    hy::WaterFlowStopRule rule;
    rule.autoStopRatio = 0.0;
    rule.balanceTolerance = 0.01;
    rule.maximumIterations = 5000;
    const hy::WaterFlowStopReason reason = cpu.Run(rule);
    ASSERT_EQ(reason, hy::WaterFlowStopReason::Balanced);
    const hy::WaterFlowGPUResult r = hy::RunWaterFlowGPU(gpu, 5000, true, rule, every);
    EXPECT_TRUE(r.stopped);
    EXPECT_EQ(r.reason, hy::WaterFlowStopReason::Balanced);
    EXPECT_EQ(gpu.Iterations(), cpu.Iterations());
    const Difference w = CompareArray(cpu.PaddedWater(), gpu.PaddedWater(), "water");
    const Difference e = CompareArray(cpu.PaddedEdges(), gpu.PaddedEdges(), "edges");
    EXPECT_EQ(w.bad, 0);
    EXPECT_EQ(e.bad, 0);
    std::vector<double> qc(static_cast<std::size_t>(scene.nx) * scene.ny), qg(qc.size());
    cpu.GetNetDischarge(qc.data());
    gpu.GetNetDischarge(qg.data());
    for (std::size_t k = 0; k < qc.size(); ++k)
    {
      if (!(std::isnan(qc[k]) && std::isnan(qg[k])))
      {
        ASSERT_EQ(qc[k], qg[k]) << k;
      }
    }
    std::cout << "rain, balance (check every " << every << "): " << gpu.Iterations()
              << " iterations, max |gpu-cpu| water " << w.max << ", edges " << e.max << std::endl;
  }
}

// The coarse-to-fine start (WaterFlowWarmStart.h) with its levels on the GPU path: the same
// levels, iterations and initial water as with the levels on the CPU (the refinement is shared
// code, the levels' runs give the same bits).
TEST(TerroirWaterFlowGPU, WarmStartLevelsOnTheGPU)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  Scene scene = TiltedWithNoData(96, 80, 11);
  for (double& w : scene.water)
  {
    w = 0.0;
  }
  hy::WaterFlowWarmStartOptions options;
  options.coarsestSide = 10; // 48 x 40, 24 x 20, 12 x 10
  options.settleIterations = 20;
  options.rule.autoStopRatio = 0.0;
  options.rule.balanceTolerance = 0.02;
  options.rule.maximumIterations = 5000;
  std::vector<double> cpu = scene.water, gpu = scene.water;
  const auto cpuLevels = hy::WaterFlowWarmStart(scene.View(), cpu.data(), 2e-4, nullptr, options);
  int gpuRuns = 0;
  const auto gpuLevels = hy::WaterFlowWarmStart(scene.View(),
    gpu.data(),
    2e-4,
    nullptr,
    options,
    [&](hy::WaterFlowSimulation& sim, const hy::WaterFlowStopRule& rule)
    {
      ++gpuRuns;
      const hy::WaterFlowGPUResult r =
        hy::RunWaterFlowGPU(sim, rule.maximumIterations, true, rule, 16);
      return r.stopped ? r.reason : hy::WaterFlowStopReason::MaximumIterations;
    });
  ASSERT_EQ(cpuLevels.size(), 3u);
  ASSERT_EQ(gpuLevels.size(), 3u);
  EXPECT_EQ(gpuRuns, 3);
  for (std::size_t l = 0; l < cpuLevels.size(); ++l)
  {
    EXPECT_EQ(gpuLevels[l].iterations, cpuLevels[l].iterations) << "level " << l;
    EXPECT_EQ(gpuLevels[l].reason, hy::WaterFlowStopReason::Balanced) << "level " << l;
    EXPECT_EQ(cpuLevels[l].reason, hy::WaterFlowStopReason::Balanced) << "level " << l;
  }
  for (std::size_t c = 0; c < cpu.size(); ++c)
  {
    ASSERT_EQ(cpu[c], gpu[c]) << c;
  }
  std::cout << "warm start: levels of " << cpuLevels[0].iterations << ", "
            << cpuLevels[1].iterations << ", " << cpuLevels[2].iterations << " iterations"
            << std::endl;
}

// Long (2016)'s literal capacity rule (no flow where the signed WEC is negative): the same gate on
// both paths, so the same stop and bits. The emptied-cell stop count is refused on the GPU.
TEST(TerroirWaterFlowGPU, LongCapacityRule)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  Scene scene = RandomWalled(48, 40, 13);
  hy::WaterFlowSimulation cpu = scene.Make();
  hy::WaterFlowSimulation gpu = scene.Make();
  cpu.SetLongCapacityRule(true);
  gpu.SetLongCapacityRule(true);
  hy::WaterFlowStopRule rule;
  rule.maximumIterations = 3000;
  const hy::WaterFlowStopReason reason = cpu.Run(rule);
  const hy::WaterFlowGPUResult r = hy::RunWaterFlowGPU(gpu, 3000, true, rule, 16);
  EXPECT_EQ(
    hy::WaterFlowStopReasonName(r.reason), std::string(hy::WaterFlowStopReasonName(reason)));
  CompareSimulations(cpu, gpu, "walled, Long (2016)'s capacity rule");
  // The gate changes the result (it is not a no-op on this terrain).
  hy::WaterFlowSimulation general = scene.Make();
  general.Run(rule);
  EXPECT_NE(general.TotalMoved(), cpu.TotalMoved());
  rule.countEmptiedCells = true;
  hy::WaterFlowSimulation other = scene.Make();
  EXPECT_THROW(hy::RunWaterFlowGPU(other, 10, true, rule, 16), std::invalid_argument);
}

// A stop inside a read-back block: the GPU restores the block's snapshot and runs it again up
// to the stopping iteration. Starting both after a few CPU steps shifts the GPU's blocks so
// that the stop is not at a block end (and checks that a GPU run continues a CPU one).
TEST(TerroirWaterFlowGPU, StopInsideCheckBlockRestoresSnapshot)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  Scene scene = TiltedWithNoData(40, 36, 5);
  hy::WaterFlowSimulation probe = scene.Make();
  hy::WaterFlowStopRule rule;
  rule.autoStopRatio = 1e-3;
  ASSERT_EQ(probe.Run(rule), hy::WaterFlowStopReason::AutoStop);
  const long long stop = probe.Iterations();
  long long pre = 0;
  while ((stop - pre) % 16 == 0 || (stop - pre) % 16 < 3)
  {
    ++pre;
  }
  ASSERT_GT(stop - pre, 16) << "the stop must fall in a later block than the first";
  std::cout << "stop at iteration " << stop << ", GPU starts at " << pre << ": stop at "
            << (stop - pre) % 16 << " of a 16-iteration block" << std::endl;
  RunBothToStop(scene, 1e-3, 5000, 16, "stop inside a block", pre);
}

// The read-back period changes the speed only: 1, 7 and 16 give bit-identical results.
TEST(TerroirWaterFlowGPU, CheckPeriodDoesNotChangeTheResult)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  Scene scene = TiltedWithNoData(33, 29, 9);
  std::vector<hy::WaterFlowSimulation> runs;
  for (int every : { 1, 7, 16 })
  {
    runs.push_back(scene.Make());
    const hy::WaterFlowGPUResult r = hy::RunWaterFlowGPU(runs.back(), 5000, true, 1e-3, every);
    EXPECT_TRUE(r.stopped);
  }
  for (std::size_t k = 1; k < runs.size(); ++k)
  {
    EXPECT_EQ(runs[k].Iterations(), runs[0].Iterations());
    EXPECT_EQ(runs[k].TotalMoved(), runs[0].TotalMoved());
    EXPECT_EQ(runs[k].TotalOutflow(), runs[0].TotalOutflow());
    EXPECT_TRUE(runs[k].PaddedWater() == runs[0].PaddedWater());
    EXPECT_TRUE(runs[k].PaddedDischarge() == runs[0].PaddedDischarge());
  }
}

// A GPU run can be continued by a second one (and by the CPU): the state round-trips.
TEST(TerroirWaterFlowGPU, RunsContinueEachOther)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  Scene scene = RandomWalled(30, 30, 21);
  hy::WaterFlowSimulation cpu = scene.Make();
  hy::WaterFlowSimulation gpu = scene.Make();
  for (int k = 0; k < 50; ++k)
  {
    cpu.Step();
  }
  hy::RunWaterFlowGPU(gpu, 20, false, 0.0, 16);
  for (int k = 0; k < 10; ++k)
  {
    gpu.Step();
  }
  hy::RunWaterFlowGPU(gpu, 50, false, 0.0, 3);
  CompareSimulations(cpu, gpu, "GPU 20, CPU 10, GPU 20");
  // Nothing to do: the target is already reached.
  const hy::WaterFlowGPUResult r = hy::RunWaterFlowGPU(gpu, 50, true, 1e-3);
  EXPECT_FALSE(r.stopped);
  EXPECT_EQ(gpu.Iterations(), 50);
}

TEST(TerroirWaterFlowGPU, InvalidArguments)
{
  Scene scene = RandomWalled(8, 8, 1);
  hy::WaterFlowSimulation sim = scene.Make();
  EXPECT_THROW(hy::RunWaterFlowGPU(sim, 10, true, 1e-3, 0), std::invalid_argument);
  EXPECT_THROW(hy::RunWaterFlowGPU(sim, 10, true, -1.0), std::invalid_argument);
  EXPECT_EQ(sim.Iterations(), 0);
}

// Timings for Documentation/Shaders.md (not asserted, not run by default):
//   TerroirGPUTests --gtest_also_run_disabled_tests --gtest_filter='*Timings*'
TEST(TerroirWaterFlowGPU, DISABLED_Timings)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  using Clock = std::chrono::steady_clock;
  auto seconds = [](Clock::time_point a, Clock::time_point b)
  { return std::chrono::duration<double>(b - a).count(); };
  for (int n : { 512, 1024 })
  {
    Scene scene = Fractal(n);
    hy::WaterFlowStopRule rule;
    rule.autoStopRatio = 1e-3;
    rule.maximumIterations = 100000;
    hy::WaterFlowSimulation one = scene.Make();
    auto t0 = Clock::now();
    const hy::WaterFlowStopReason reason = one.Run(rule);
    auto t1 = Clock::now();
    hy::WaterFlowSimulation smp = scene.Make();
    hy::UseSMPTools(smp);
    auto t2 = Clock::now();
    smp.Run(rule);
    auto t3 = Clock::now();
    hy::WaterFlowSimulation gpu = scene.Make();
    auto t4 = Clock::now();
    const hy::WaterFlowGPUResult r =
      hy::RunWaterFlowGPU(gpu, rule.maximumIterations, true, rule.autoStopRatio, 16);
    auto t5 = Clock::now();
    EXPECT_EQ(gpu.Iterations(), one.Iterations());
    EXPECT_EQ(r.reason, reason);
    const double it = static_cast<double>(one.Iterations());
    std::cout << n << "^2: " << one.Iterations() << " iterations ("
              << hy::WaterFlowStopReasonName(reason) << "); CPU 1 thread " << seconds(t0, t1)
              << " s (" << 1e3 * seconds(t0, t1) / it << " ms/it), CPU "
              << vtkSMPTools::GetEstimatedNumberOfThreads() << " threads " << seconds(t2, t3)
              << " s (" << 1e3 * seconds(t2, t3) / it << " ms/it), GPU " << seconds(t4, t5)
              << " s (" << 1e3 * seconds(t4, t5) / it << " ms/it)" << std::endl;
  }
}

// Diagnosis on a new GPU (not run by default: --gtest_also_run_disabled_tests): after 1, 2 and 3
// iterations, how many padded cells differ from the CPU bit for bit (none may), printing the
// first of them.
TEST(TerroirWaterFlowGPU, DISABLED_FirstDifferences)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  Scene scene = RandomWalled(48, 40, 7);
  for (int iterations = 1; iterations <= 3; ++iterations)
  {
    hy::WaterFlowSimulation cpu = scene.Make();
    hy::WaterFlowSimulation gpu = scene.Make();
    for (int k = 0; k < iterations; ++k)
    {
      cpu.Step();
    }
    hy::RunWaterFlowGPU(gpu, iterations, false, 1e-3, 16);
    int differ = 0;
    for (std::size_t c = 0; c < cpu.PaddedWater().size(); ++c)
    {
      const double a = cpu.PaddedWater()[c], b = gpu.PaddedWater()[c];
      if (std::memcmp(&a, &b, sizeof a) != 0 && differ++ < 3)
      {
        std::printf("[ first    ] after %d: cell %zu water cpu %.17g gpu %.17g (terrain %.9g, "
                    "initial %.17g); discharge cpu %.17g gpu %.17g\n",
          iterations,
          c,
          a,
          b,
          static_cast<double>(cpu.PaddedTerrain()[c]),
          scene.Make().PaddedWater()[c],
          cpu.PaddedDischarge()[c],
          gpu.PaddedDischarge()[c]);
      }
    }
    std::printf("[ first    ] after %d: %d of %zu padded cells differ\n",
      iterations,
      differ,
      cpu.PaddedWater().size());
    EXPECT_EQ(differ, 0) << "after " << iterations << " iterations";
  }
}

// The coarse-to-fine start of the river-forming water flow (WaterFlowWarmStart.h): the coarse
// grid by hand, the refinement of a tilted plane against the plane's steady state, and warm and
// cold runs of a V valley that end at the same discharge.
#include "WaterFlowWarmStart.h"

#include "TerroirWaterFlowScenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

namespace
{
using terroir::GridView;
namespace hy = terroir::hydrology;

using Grid = terroir_test::WaterFlowGrid;

hy::WaterFlowStopRule Balance(double tolerance, long long maximum)
{
  hy::WaterFlowStopRule rule;
  rule.autoStopRatio = 0.0;
  rule.balanceTolerance = tolerance;
  rule.maximumIterations = maximum;
  return rule;
}

/// Padded depth of cell (i, j).
double Depth(hy::WaterFlowSimulation& sim, int i, int j)
{
  return sim.PaddedWater()[static_cast<std::size_t>(j + 1) * sim.Stride() + i + 1];
}
} // namespace

TEST(WaterFlowWarmStart, CoarsenAveragesTwoByTwo)
{
  // 5 x 3 cells, dx 2 m, dy 3 m; cell (1, 0) has no data, so does the whole block of (4, 2).
  Grid g(5, 3);
  g.view.dx = 2.0;
  g.view.dy = 3.0;
  for (int j = 0; j < 3; ++j)
  {
    for (int i = 0; i < 5; ++i)
    {
      g.Z(i, j) = static_cast<float>(10 * j + i);
    }
  }
  g.Z(1, 0) = 999.0f;
  g.Z(4, 2) = std::numeric_limits<float>::quiet_NaN();
  std::vector<std::uint8_t> valid(15, 1);
  valid[1] = 0;
  g.view.valid = valid.data();
  std::vector<float> h;
  std::vector<std::uint8_t> ok;
  std::vector<double> rowDx, rowDy;
  GridView<float> c;
  hy::WaterFlowCoarsen(g.view, h, ok, rowDx, rowDy, c);
  ASSERT_EQ(c.nx, 3);
  ASSERT_EQ(c.ny, 2);
  EXPECT_DOUBLE_EQ(c.dx, 4.0);
  EXPECT_DOUBLE_EQ(c.dy, 6.0);
  EXPECT_EQ(c.rowDx, nullptr);
  // Block (0, 0): cells (0,0) = 0, (0,1) = 10, (1,1) = 11; (1,0) has no data.
  EXPECT_FLOAT_EQ(h[0], 7.0f);
  EXPECT_FLOAT_EQ(h[1], (2.0f + 3 + 12 + 13) / 4); // block (1, 0)
  EXPECT_FLOAT_EQ(h[2], (4.0f + 14) / 2);          // the last column stands alone
  EXPECT_FLOAT_EQ(h[3], (20.0f + 21) / 2);         // the last row stands alone
  EXPECT_FLOAT_EQ(h[4], (22.0f + 23) / 2);
  EXPECT_EQ(ok[5], 0); // (4, 2) alone and without data
  EXPECT_EQ(ok[0] + ok[1] + ok[2] + ok[3] + ok[4], 5);

  // Per-row spacing: a coarse row is two rows tall, its cells two columns of the rows' mean.
  const double dxRows[3] = { 1.0, 2.0, 4.0 };
  const double dyRows[3] = { 3.0, 5.0, 7.0 };
  g.view.rowDx = dxRows;
  g.view.rowDy = dyRows;
  hy::WaterFlowCoarsen(g.view, h, ok, rowDx, rowDy, c);
  ASSERT_NE(c.rowDx, nullptr);
  ASSERT_NE(c.rowDy, nullptr);
  EXPECT_DOUBLE_EQ(c.DxAt(0), 3.0);
  EXPECT_DOUBLE_EQ(c.DxAt(1), 8.0);
  EXPECT_DOUBLE_EQ(c.DyAt(0), 8.0);
  EXPECT_DOUBLE_EQ(c.DyAt(1), 14.0);
}

TEST(WaterFlowWarmStart, TiltedPlaneRefinesNearItsSteadyState)
{
  // A plane falling 1 m per cell to the east, 64 x 132 cells, rain r = 1e-4 m per iteration:
  // every cell passes on all it holds each iteration, so at steady state a cell in column i
  // (from the west, 0-based) holds the rain of the i + 1 cells west of it and itself: (i + 1) r,
  // away from the northern and southern edges (the edge rows also lose water diagonally to the
  // border; the loss spreads at most one row per column, so the middle row never sees it). The
  // coarse level (32 x 66, 2 m cells falling 2 m) holds (I + 1) r in coarse column I; refined,
  // fine column i gets 2 (i / 2 + 1) r: the steady state, or one cell's rain more (even i).
  const int ny = 132, middle = 66;
  Grid g(64, ny);
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < 64; ++i)
    {
      g.Z(i, j) = static_cast<float>(200 - i);
    }
  }
  const double r = 1e-4;
  std::vector<double> water(g.z.size(), 0.0);
  hy::WaterFlowWarmStartOptions options;
  options.coarsestSide = 17; // 32 x 66, not 16 x 33
  options.settleIterations = 10;
  options.rule = Balance(1e-9, 1000);
  const std::vector<hy::WaterFlowWarmStartLevel> levels =
    hy::WaterFlowWarmStart(g.view, water.data(), r, nullptr, options);
  ASSERT_EQ(levels.size(), 1u);
  EXPECT_EQ(levels[0].nx, 32);
  EXPECT_EQ(levels[0].ny, 66);
  EXPECT_EQ(levels[0].reason, hy::WaterFlowStopReason::Balanced);
  EXPECT_LE(levels[0].iterations, 40); // 32 columns to cross
  for (int i = 0; i < 64; ++i)
  {
    const double expected = 2.0 * (i / 2 + 1) * r;
    EXPECT_NEAR(water[static_cast<std::size_t>(middle) * 64 + i], expected, 1e-9) << "column " << i;
    EXPECT_NEAR(water[static_cast<std::size_t>(middle) * 64 + i], (i + 1) * r, r + 1e-9);
  }

  // From there the fine run balances at once; from dry ground it needs the 64 columns.
  hy::WaterFlowSimulation warm(g.view, water.data());
  warm.SetRain(r);
  hy::WaterFlowStopRule rule = Balance(1e-9, 1000);
  rule.balanceAfter = options.settleIterations;
  ASSERT_EQ(warm.Run(rule), hy::WaterFlowStopReason::Balanced);
  EXPECT_EQ(warm.Iterations(), options.settleIterations);
  std::vector<double> dry(g.z.size(), 0.0);
  hy::WaterFlowSimulation cold(g.view, dry.data());
  cold.SetRain(r);
  ASSERT_EQ(cold.Run(Balance(1e-9, 1000)), hy::WaterFlowStopReason::Balanced);
  EXPECT_GE(cold.Iterations(), 64);
  // The cold run is at the plane's steady state in the middle row; the warm one within one
  // cell's rain of it (the even columns' extra rain moves east, one column per iteration), and
  // exactly there once that has left.
  for (int i = 0; i < 64; ++i)
  {
    EXPECT_NEAR(Depth(cold, i, middle), (i + 1) * r, 1e-9) << "column " << i;
    EXPECT_NEAR(Depth(warm, i, middle), (i + 1) * r, r + 1e-9) << "column " << i;
  }
  for (int k = 0; k < 64; ++k)
  {
    warm.Step();
  }
  for (int i = 0; i < 64; ++i)
  {
    EXPECT_NEAR(Depth(warm, i, middle), (i + 1) * r, 1e-9) << "column " << i;
  }
}

TEST(WaterFlowWarmStart, WarmAndColdRunsOfAValleyEndAtTheSameDischarge)
{
  // The V valley of TestWaterFlow (side slopes 1 m per cell, floor falling 0.01 m per cell to
  // the south), 22 x 160 cells: two coarse levels (11 x 80, 6 x 40). At steady state the
  // thalweg carries the rain of its upstream area: both runs must get there (within 1 %: the
  // warm run stops while the extra water of its refinement still drains).
  const int nx = 22, ny = 160, c = 10;
  Grid g(nx, ny);
  terroir_test::DrawVValley(g.z.data(), nx, ny, c);
  const double r = 1e-7;
  std::vector<double> water(g.z.size(), 0.0);
  hy::WaterFlowWarmStartOptions options;
  options.coarsestSide = 5;
  options.settleIterations = 50;
  options.rule = Balance(1e-6, 5000);
  const auto levels = hy::WaterFlowWarmStart(g.view, water.data(), r, nullptr, options);
  ASSERT_EQ(levels.size(), 2u);
  EXPECT_EQ(levels[0].nx, 6);
  EXPECT_EQ(levels[1].nx, 11);
  EXPECT_EQ(levels[1].ny, 80);
  std::vector<double> dry(g.z.size(), 0.0);
  hy::WaterFlowSimulation warm(g.view, water.data());
  hy::WaterFlowSimulation cold(g.view, dry.data());
  hy::WaterFlowStopRule rule = options.rule;
  rule.balanceAfter = options.settleIterations;
  std::vector<double> rates[2];
  long long iterations[2];
  int k = 0;
  for (hy::WaterFlowSimulation* sim : { &warm, &cold })
  {
    sim->SetRain(r);
    ASSERT_EQ(sim->Run(k == 0 ? rule : options.rule), hy::WaterFlowStopReason::Balanced);
    iterations[k] = sim->Iterations();
    rates[k] = terroir_test::DischargePerIteration(*sim, 20);
    ++k;
  }
  EXPECT_LT(iterations[0], iterations[1]) << "warm " << iterations[0] << " cold " << iterations[1];
  for (int j = 10; j + 100 <= ny; ++j)
  {
    const std::size_t t = static_cast<std::size_t>(j) * nx + c;
    const double upstream = nx * (ny - 1 - j) * r;
    EXPECT_NEAR(rates[0][t], upstream, 0.01 * upstream) << "row " << j;
    EXPECT_NEAR(rates[0][t], rates[1][t], 0.01 * rates[1][t]) << "row " << j;
  }
}

TEST(WaterFlowWarmStart, RainFieldNoDataAndSmallGrids)
{
  // A rain field equal to the uniform rain gives the same bits (the coarse rain is the mean of
  // the cells with data); no-data cells keep their water; a grid too small is left as it is.
  Grid g(40, 36, 10.0);
  std::vector<std::uint8_t> valid(g.z.size(), 1);
  for (int j = 0; j < 36; ++j)
  {
    for (int i = 0; i < 40; ++i)
    {
      g.Z(i, j) =
        static_cast<float>(0.5 * i + 0.2 * j + 3.0 * std::sin(0.3 * i) * std::cos(0.2 * j));
      if (i >= 10 && i < 13 && j >= 5 && j < 20)
      {
        valid[static_cast<std::size_t>(j) * 40 + i] = 0;
      }
    }
  }
  g.view.valid = valid.data();
  const double r = 2e-5;
  hy::WaterFlowWarmStartOptions options;
  options.coarsestSide = 8;
  options.rule = Balance(0.02, 3000);
  std::vector<double> a(g.z.size(), 0.0), b(g.z.size(), 0.0);
  a[static_cast<std::size_t>(6) * 40 + 11] = 7.0; // a no-data cell's value is kept
  b[static_cast<std::size_t>(6) * 40 + 11] = 7.0;
  std::vector<double> field(g.z.size(), r);
  const auto la = hy::WaterFlowWarmStart(g.view, a.data(), r, nullptr, options);
  const auto lb = hy::WaterFlowWarmStart(g.view, b.data(), 0.0, field.data(), options);
  ASSERT_EQ(la.size(), 2u); // 20 x 18, 10 x 9
  ASSERT_EQ(lb.size(), 2u);
  for (std::size_t l = 0; l < la.size(); ++l)
  {
    EXPECT_EQ(la[l].iterations, lb[l].iterations);
  }
  double total = 0.0;
  for (std::size_t t = 0; t < a.size(); ++t)
  {
    ASSERT_EQ(a[t], b[t]) << t;
    total += valid[t] ? a[t] : 0.0;
  }
  EXPECT_GT(total, 0.0);
  EXPECT_EQ(a[static_cast<std::size_t>(6) * 40 + 11], 7.0);

  Grid small(13, 300);
  std::vector<double> w(small.z.size(), 0.25);
  options.coarsestSide = 8; // 7 x 150 would have a side under 8
  EXPECT_TRUE(hy::WaterFlowWarmStart(small.view, w.data(), r, nullptr, options).empty());
  for (double x : w)
  {
    ASSERT_EQ(x, 0.25);
  }
}

TEST(WaterFlowWarmStart, RejectsBadOptions)
{
  Grid g(8, 8);
  std::vector<double> w(g.z.size(), 0.0);
  hy::WaterFlowWarmStartOptions options;
  options.rule = Balance(0.02, 100);
  options.coarsestSide = 1;
  EXPECT_THROW(
    hy::WaterFlowWarmStart(g.view, w.data(), 1e-4, nullptr, options), std::invalid_argument);
  options.coarsestSide = 2;
  options.settleIterations = -1;
  EXPECT_THROW(
    hy::WaterFlowWarmStart(g.view, w.data(), 1e-4, nullptr, options), std::invalid_argument);
  options.settleIterations = 0;
  options.rule.balanceTolerance = 0.0; // no balance: a level would never stop
  EXPECT_THROW(
    hy::WaterFlowWarmStart(g.view, w.data(), 1e-4, nullptr, options), std::invalid_argument);
  options.rule.balanceTolerance = 0.02;
  EXPECT_THROW(hy::WaterFlowWarmStart(g.view, w.data(), -1.0, nullptr, options),
    std::invalid_argument); // negative rain, from the level's simulation
  // The settling count: the balance never fires before it.
  hy::WaterFlowSimulation sim(g.view, w.data());
  hy::WaterFlowStopRule rule = Balance(0.5, 100);
  rule.balanceAfter = -1;
  EXPECT_THROW(sim.Run(rule), std::invalid_argument);
}

#include "WaterFlowWarmStart.h"

#include "PriorityFlood.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace terroir
{
namespace hydrology
{

namespace
{

bool CellHasData(const GridView<float>& g, std::size_t c)
{
  return (!g.valid || g.valid[c]) && std::isfinite(g.data[c]);
}

/// Mean of `values` over the cells with data of coarse cell (i, j)'s 2 x 2 block of `fine`;
/// false (and 0) when none has data.
template<typename T>
bool BlockMean(const GridView<float>& fine, const T* values, int i, int j, double& mean)
{
  double sum = 0.0;
  int count = 0;
  for (int fj = 2 * j; fj < std::min(2 * j + 2, fine.ny); ++fj)
  {
    for (int fi = 2 * i; fi < std::min(2 * i + 2, fine.nx); ++fi)
    {
      const std::size_t c = fine.Index(fi, fj);
      if (CellHasData(fine, c))
      {
        sum += values[c];
        ++count;
      }
    }
  }
  mean = count > 0 ? sum / count : 0.0;
  return count > 0;
}

/// The still water of `g` (Priority-Flood depth; 0 on no data), metres.
std::vector<double> StillWater(const GridView<float>& g)
{
  std::vector<float> filled(g.Size());
  PriorityFloodBarnes2014(g, filled.data());
  std::vector<double> still(g.Size(), 0.0);
  for (std::size_t c = 0; c < g.Size(); ++c)
  {
    if (CellHasData(g, c))
    {
      still[c] = std::max(0.0, static_cast<double>(filled[c]) - static_cast<double>(g.data[c]));
    }
  }
  return still;
}

} // namespace

//------------------------------------------------------------------------------
void WaterFlowCoarsen(const GridView<float>& fine,
  std::vector<float>& heights,
  std::vector<std::uint8_t>& valid,
  std::vector<double>& rowDx,
  std::vector<double>& rowDy,
  GridView<float>& coarse)
{
  const int nx = (fine.nx + 1) / 2;
  const int ny = (fine.ny + 1) / 2;
  heights.assign(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny), 0.0f);
  valid.assign(heights.size(), 0);
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      double mean = 0.0;
      const bool any = BlockMean(fine, fine.data, i, j, mean);
      const std::size_t c =
        static_cast<std::size_t>(j) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(i);
      heights[c] = static_cast<float>(mean);
      valid[c] = any ? 1 : 0;
    }
  }
  coarse = GridView<float>();
  coarse.data = heights.data();
  coarse.valid = valid.data();
  coarse.nx = nx;
  coarse.ny = ny;
  coarse.dx = 2.0 * fine.dx;
  coarse.dy = 2.0 * fine.dy;
  rowDx.clear();
  rowDy.clear();
  if (fine.rowDx || fine.rowDy)
  {
    rowDx.resize(static_cast<std::size_t>(ny));
    rowDy.resize(static_cast<std::size_t>(ny));
    for (int j = 0; j < ny; ++j)
    {
      const int a = 2 * j;
      const int b = std::min(2 * j + 1, fine.ny - 1);
      rowDx[j] = fine.DxAt(a) + fine.DxAt(b); // two columns at the rows' mean width
      rowDy[j] = fine.DyAt(a) + fine.DyAt(b);
    }
    coarse.rowDx = fine.rowDx ? rowDx.data() : nullptr;
    coarse.rowDy = fine.rowDy ? rowDy.data() : nullptr;
  }
}

//------------------------------------------------------------------------------
std::vector<WaterFlowWarmStartLevel> WaterFlowWarmStart(const GridView<float>& terrain,
  double* water,
  double rain,
  const double* rainField,
  const WaterFlowWarmStartOptions& options,
  const WaterFlowLevelRun& run)
{
  if (options.coarsestSide < 2 || options.settleIterations < 0 ||
    !(options.rule.balanceTolerance > 0.0 && options.rule.balanceTolerance < 1.0) ||
    options.rule.maximumIterations < 0)
  {
    throw std::invalid_argument("water flow warm start: the coarsest side must be >= 2, the "
                                "settling count >= 0, the balance tolerance in (0, 1)");
  }
  std::vector<WaterFlowWarmStartLevel> levels;
  if (std::min((terrain.nx + 1) / 2, (terrain.ny + 1) / 2) < options.coarsestSide)
  {
    return levels;
  }
  std::vector<float> heights;
  std::vector<std::uint8_t> valid;
  std::vector<double> rowDx, rowDy;
  GridView<float> coarse;
  WaterFlowCoarsen(terrain, heights, valid, rowDx, rowDy, coarse);
  const std::size_t n = coarse.Size();

  std::vector<double> coarseRain;
  if (rainField)
  {
    coarseRain.assign(n, 0.0);
    for (int j = 0; j < coarse.ny; ++j)
    {
      for (int i = 0; i < coarse.nx; ++i)
      {
        BlockMean(terrain, rainField, i, j, coarseRain[coarse.Index(i, j)]);
      }
    }
  }

  const std::vector<double> still = StillWater(coarse);
  std::vector<double> initial = still;
  levels = WaterFlowWarmStart(
    coarse, initial.data(), rain, rainField ? coarseRain.data() : nullptr, options, run);

  WaterFlowSimulation sim(coarse, initial.data());
  if (rainField)
  {
    sim.SetRainField(coarseRain.data());
  }
  else
  {
    sim.SetRain(rain);
  }
  WaterFlowStopRule rule = options.rule;
  rule.balanceAfter = levels.empty() ? 0 : options.settleIterations;
  WaterFlowWarmStartLevel level;
  level.nx = coarse.nx;
  level.ny = coarse.ny;
  level.reason = run ? run(sim, rule) : sim.Run(rule);
  level.iterations = sim.Iterations();
  levels.push_back(level);

  // Refine: the fine still water plus twice the coarse flowing water.
  const std::vector<double>& w = sim.PaddedWater();
  const std::size_t stride = static_cast<std::size_t>(sim.Stride());
  for (int fj = 0; fj < terrain.ny; ++fj)
  {
    for (int fi = 0; fi < terrain.nx; ++fi)
    {
      const std::size_t c = terrain.Index(fi, fj);
      if (!CellHasData(terrain, c))
      {
        continue;
      }
      const std::size_t cc = coarse.Index(fi / 2, fj / 2);
      const double depth = w[(static_cast<std::size_t>(fj / 2) + 1) * stride + fi / 2 + 1];
      water[c] += 2.0 * std::max(0.0, depth - still[cc]);
    }
  }
  return levels;
}

} // namespace hydrology
} // namespace terroir

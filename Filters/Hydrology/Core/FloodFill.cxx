#include "FloodFill.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

namespace terroir
{
namespace hydrology
{

std::vector<WaterBodyStats> FloodFillSeeds(const GridView<float>& view,
  const std::vector<FloodSeed>& seeds,
  std::int32_t* bodyId,
  float* depth,
  const std::function<void(double)>& progress)
{
  detail::CheckCellCount(view, "FloodFillSeeds");
  const std::size_t n = view.Size();
  for (std::size_t s = 0; s < seeds.size(); ++s)
  {
    if (seeds[s].cell >= n)
    {
      throw std::out_of_range("FloodFillSeeds: seed " + std::to_string(s) + " cell " +
        std::to_string(seeds[s].cell) + " is outside the grid of " + std::to_string(n) + " cells");
    }
  }
  for (std::size_t k = 0; k < n; ++k)
  {
    bodyId[k] = 0;
    depth[k] = HasData(view, k) ? 0.0f : std::numeric_limits<float>::quiet_NaN();
  }

  // Resolved levels, and the order: highest level first, ties in seed order. Seeds without a
  // usable level (no data under a NaN level) go last; they fill nothing.
  std::vector<WaterBodyStats> stats(seeds.size());
  for (std::size_t s = 0; s < seeds.size(); ++s)
  {
    const std::size_t c = seeds[s].cell;
    double level = seeds[s].level;
    if (std::isnan(level))
    {
      level = HasData(view, c) ? static_cast<double>(view.data[c])
                               : std::numeric_limits<double>::quiet_NaN();
    }
    stats[s].level = level;
  }
  std::vector<std::size_t> order(seeds.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  auto key = [&](std::size_t s) {
    return std::isnan(stats[s].level) ? -std::numeric_limits<double>::infinity() : stats[s].level;
  };
  std::stable_sort(
    order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return key(a) > key(b); });

  const int nx = view.nx;
  const int ny = view.ny;
  std::vector<std::int32_t> stack;
  for (std::size_t done = 0; done < order.size(); ++done)
  {
    const std::size_t s = order[done];
    const double level = stats[s].level;
    const std::size_t c = seeds[s].cell;
    if (progress)
    {
      progress(static_cast<double>(done) / static_cast<double>(order.size()));
    }
    if (std::isnan(level) || !HasData(view, c) || bodyId[c] != 0 ||
      !(static_cast<double>(view.data[c]) <= level))
    {
      continue; // no data, already wet (joins that body), or the terrain is above the level
    }
    const std::int32_t id = static_cast<std::int32_t>(s + 1);
    bodyId[c] = id;
    stack.assign(1, static_cast<std::int32_t>(c));
    WaterBodyStats& body = stats[s];
    while (!stack.empty())
    {
      const std::int32_t k = stack.back();
      stack.pop_back();
      const int i = k % nx;
      const int j = k / nx;
      const double d = level - static_cast<double>(view.data[k]);
      depth[k] = static_cast<float>(d);
      body.AddCell(view.DxAt(j) * view.DyAt(j), d);
      for (int e = 0; e < 8; ++e)
      {
        const int ii = i + detail::kNeighbourDi[e];
        const int jj = j + detail::kNeighbourDj[e];
        if (ii < 0 || ii >= nx || jj < 0 || jj >= ny)
        {
          continue;
        }
        const std::size_t kk = view.Index(ii, jj);
        // NaN elevations fail the comparison, so only the mask needs its own test.
        if (bodyId[kk] == 0 && (!view.valid || view.valid[kk] != 0) &&
          static_cast<double>(view.data[kk]) <= level)
        {
          bodyId[kk] = id;
          stack.push_back(static_cast<std::int32_t>(kk));
        }
      }
    }
  }
  if (progress)
  {
    progress(1.0);
  }
  return stats;
}

} // namespace hydrology
} // namespace terroir

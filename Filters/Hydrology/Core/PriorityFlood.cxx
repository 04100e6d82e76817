#include "PriorityFlood.h"

#include "WaterBody.h"

#include <cstdint>
#include <deque>
#include <limits>
#include <queue>
#include <vector>

namespace terroir
{
namespace hydrology
{

const char* const kPriorityFloodBarnes2014Citation =
  "Barnes, R., Lehman, C., Mulla, D. (2014). Priority-Flood: An optimal depression-filling and "
  "watershed-labeling algorithm for digital elevation models. Computers & Geosciences "
  "62:117-127. doi:10.1016/j.cageo.2013.04.024";

namespace
{
struct OpenCell
{
  float height;
  std::int32_t cell;
};

/// Orders the priority queue lowest height first, then lowest cell index.
struct HigherFirst
{
  bool operator()(const OpenCell& a, const OpenCell& b) const
  {
    return a.height > b.height || (a.height == b.height && a.cell > b.cell);
  }
};
} // namespace

std::size_t PriorityFloodBarnes2014(const GridView<float>& view,
  float* filled,
  const std::function<void(double)>& progress)
{
  detail::CheckCellCount(view, "PriorityFloodBarnes2014");
  const int nx = view.nx;
  const int ny = view.ny;
  const std::size_t n = view.Size();
  std::vector<std::uint8_t> closed(n, 0);
  for (std::size_t k = 0; k < n; ++k)
  {
    if (HasData(view, k))
    {
      filled[k] = view.data[k];
    }
    else
    {
      filled[k] = std::numeric_limits<float>::quiet_NaN();
      closed[k] = 1; // never entered
    }
  }

  std::priority_queue<OpenCell, std::vector<OpenCell>, HigherFirst> open;
  std::deque<std::int32_t> pit;
  std::size_t visited = 0;
  // Outlets: edge cells and cells next to no data, in index order.
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      const std::size_t k = view.Index(i, j);
      if (closed[k])
      {
        continue;
      }
      bool outlet = i == 0 || j == 0 || i == nx - 1 || j == ny - 1;
      for (int e = 0; e < 8 && !outlet; ++e)
      {
        outlet =
          !HasData(view, view.Index(i + detail::kNeighbourDi[e], j + detail::kNeighbourDj[e]));
      }
      if (outlet)
      {
        closed[k] = 1;
        open.push(OpenCell{ filled[k], static_cast<std::int32_t>(k) });
        ++visited;
      }
    }
  }

  std::size_t raised = 0;
  std::size_t processed = 0;
  const std::size_t progressStep = std::size_t(1) << 20;
  while (!open.empty() || !pit.empty())
  {
    std::int32_t c;
    if (!pit.empty())
    {
      c = pit.front();
      pit.pop_front();
    }
    else
    {
      c = open.top().cell;
      open.pop();
    }
    const float h = filled[c];
    const int i = c % nx;
    const int j = c / nx;
    for (int e = 0; e < 8; ++e)
    {
      const int ii = i + detail::kNeighbourDi[e];
      const int jj = j + detail::kNeighbourDj[e];
      if (ii < 0 || ii >= nx || jj < 0 || jj >= ny)
      {
        continue;
      }
      const std::size_t k = view.Index(ii, jj);
      if (closed[k])
      {
        continue;
      }
      closed[k] = 1;
      ++visited;
      if (filled[k] <= h)
      {
        raised += filled[k] < h ? 1 : 0;
        filled[k] = h;
        pit.push_back(static_cast<std::int32_t>(k));
      }
      else
      {
        open.push(OpenCell{ filled[k], static_cast<std::int32_t>(k) });
      }
    }
    if (progress && ++processed % progressStep == 0)
    {
      progress(static_cast<double>(visited) / static_cast<double>(n));
    }
  }
  if (progress)
  {
    progress(1.0);
  }
  return raised;
}

} // namespace hydrology
} // namespace terroir

#include "DepressionWaterBodies.h"

#include <cmath>
#include <cstddef>
#include <limits>

namespace terroir
{
namespace hydrology
{

std::vector<WaterBodyStats> DepressionWaterBodies(const GridView<float>& view,
  const float* filled,
  const DepressionWaterBodyOptions& options,
  std::int32_t* bodyId,
  float* depth,
  const std::function<void(double)>& progress)
{
  detail::CheckCellCount(view, "DepressionWaterBodies");
  const int nx = view.nx;
  const int ny = view.ny;
  const std::size_t n = view.Size();
  std::vector<std::uint8_t> seen(n, 0);
  for (std::size_t k = 0; k < n; ++k)
  {
    bodyId[k] = 0;
    const bool data = HasData(view, k) && !std::isnan(filled[k]);
    depth[k] = data ? 0.0f : std::numeric_limits<float>::quiet_NaN();
    seen[k] = data ? 0 : 1;
  }

  std::vector<WaterBodyStats> bodies;
  std::vector<std::int32_t> flat; // the current flat's cells; also its breadth-first queue
  const std::size_t progressStep = std::size_t(1) << 20;
  for (std::size_t first = 0; first < n; ++first)
  {
    if (progress && first % progressStep == 0)
    {
      progress(static_cast<double>(first) / static_cast<double>(n));
    }
    if (seen[first])
    {
      continue;
    }
    const float level = filled[first];
    WaterBodyStats body;
    body.level = level;
    bool anyFilled = false;
    seen[first] = 1;
    flat.assign(1, static_cast<std::int32_t>(first));
    for (std::size_t head = 0; head < flat.size(); ++head)
    {
      const std::int32_t c = flat[head];
      const int i = c % nx;
      const int j = c / nx;
      const double d = static_cast<double>(level) - static_cast<double>(view.data[c]);
      anyFilled = anyFilled || d > 0.0;
      body.AddCell(view.DxAt(j) * view.DyAt(j), d);
      for (int e = 0; e < 8; ++e)
      {
        const int ii = i + detail::kNeighbourDi[e];
        const int jj = j + detail::kNeighbourDj[e];
        if (ii < 0 || ii >= nx || jj < 0 || jj >= ny)
        {
          continue;
        }
        const std::size_t k = view.Index(ii, jj);
        if (!seen[k] && filled[k] == level)
        {
          seen[k] = 1;
          flat.push_back(static_cast<std::int32_t>(k));
        }
      }
    }
    const bool water = anyFilled || (options.includeFlatSurfaces && body.cells >= 2);
    if (!water || !(body.area >= options.minimumArea))
    {
      continue;
    }
    bodies.push_back(body);
    const std::int32_t id = static_cast<std::int32_t>(bodies.size());
    for (const std::int32_t c : flat)
    {
      bodyId[c] = id;
      depth[c] = static_cast<float>(static_cast<double>(level) - static_cast<double>(view.data[c]));
    }
  }
  if (progress)
  {
    progress(1.0);
  }
  return bodies;
}

} // namespace hydrology
} // namespace terroir

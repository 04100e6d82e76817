#include "FlowAccumulation.h"

#include "WaterBody.h"

#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace terroir
{
namespace hydrology
{

const char* const kD8OCallaghanMark1984Citation =
  "O'Callaghan, J.F., Mark, D.M. (1984). The extraction of drainage networks from digital "
  "elevation data. Computer Vision, Graphics, and Image Processing 28(3):323-344. "
  "doi:10.1016/S0734-189X(84)80011-0";

const char* const kFlatsBarnes2014Citation =
  "Barnes, R., Lehman, C., Mulla, D. (2014). An efficient assignment of drainage direction over "
  "flat surfaces in raster digital elevation models. Computers & Geosciences 62:128-135. "
  "doi:10.1016/j.cageo.2013.01.009";

namespace
{
constexpr std::int8_t kUnset = detail::kD8Unset;
constexpr std::size_t kProgressStep = std::size_t(1) << 20;

/// Lengths of the 8 D8 steps from a cell of row j, metres.
void StepLengths(const GridView<float>& view, int j, double length[8])
{
  const double dx = view.DxAt(j);
  const double dy = view.DyAt(j);
  const double diagonal = std::sqrt(dx * dx + dy * dy);
  for (int e = 0; e < 8; ++e)
  {
    length[e] = kD8Di[e] == 0 ? dy : (kD8Dj[e] == 0 ? dx : diagonal);
  }
}

/// Counts of the flat routing (DrainFlats), added to the D8Summary.
struct FlatCounts
{
  std::size_t outlets = 0;
  std::size_t flatCells = 0;
  std::size_t sinks = 0;
};

/// The draining cells of the flats (a direction, -1 included, and an unset neighbour of exactly
/// the same W), in index order, at distance 0: the seeds of FlatDistances.
void SeedFlatOutlets(const GridView<float>& view,
  const float* filled,
  const std::int8_t* direction,
  std::vector<std::int32_t>& distance,
  std::vector<std::int32_t>& queue)
{
  const int nx = view.nx;
  const int ny = view.ny;
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      const std::size_t k = view.Index(i, j);
      if (direction[k] < kD8Outlet)
      {
        continue; // no data, or a flat cell itself
      }
      for (int e = 0; e < 8; ++e)
      {
        const int ii = i + kD8Di[e];
        const int jj = j + kD8Dj[e];
        if (ii < 0 || ii >= nx || jj < 0 || jj >= ny)
        {
          continue;
        }
        const std::size_t kk = view.Index(ii, jj);
        if (direction[kk] == kUnset && filled[kk] == filled[k])
        {
          distance[k] = 0;
          queue.push_back(static_cast<std::int32_t>(k));
          break;
        }
      }
    }
  }
}

/// Breadth-first distances from the seeds in `queue` through unset cells of equal W.
void FlatDistances(const GridView<float>& view,
  const float* filled,
  const std::int8_t* direction,
  std::vector<std::int32_t>& distance,
  std::vector<std::int32_t>& queue,
  const std::function<void(double)>& progress)
{
  const int nx = view.nx;
  const int ny = view.ny;
  for (std::size_t q = 0; q < queue.size(); ++q)
  {
    const std::size_t k = static_cast<std::size_t>(queue[q]);
    const int i = static_cast<int>(k % static_cast<std::size_t>(nx));
    const int j = static_cast<int>(k / static_cast<std::size_t>(nx));
    for (int e = 0; e < 8; ++e)
    {
      const int ii = i + kD8Di[e];
      const int jj = j + kD8Dj[e];
      if (ii < 0 || ii >= nx || jj < 0 || jj >= ny)
      {
        continue;
      }
      const std::size_t kk = view.Index(ii, jj);
      if (direction[kk] == kUnset && distance[kk] < 0 && filled[kk] == filled[k])
      {
        distance[kk] = distance[k] + 1;
        queue.push_back(static_cast<std::int32_t>(kk));
      }
    }
    if (progress && q % kProgressStep == kProgressStep - 1)
    {
      progress(0.5 + 0.4 * static_cast<double>(q) / static_cast<double>(queue.size()));
    }
  }
}

/// Each reached flat cell drains to its nearest equal neighbour one step closer; an unreached
/// one (a pit or a closed flat) becomes an outlet and a sink.
FlatCounts DrainFlats(const GridView<float>& view,
  const float* filled,
  std::int8_t* direction,
  const std::vector<std::int32_t>& distance)
{
  const int nx = view.nx;
  const int ny = view.ny;
  FlatCounts counts;
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      const std::size_t k = view.Index(i, j);
      if (direction[k] != kUnset)
      {
        continue;
      }
      if (distance[k] < 0)
      {
        direction[k] = kD8Outlet; // a pit or closed flat: W was not depression-free
        ++counts.outlets;
        ++counts.sinks;
        continue;
      }
      // A breadth-first distance d > 0 always has a neighbour at d - 1 in the same flat.
      direction[k] =
        static_cast<std::int8_t>(detail::D8FlatStep(view, filled, distance.data(), i, j));
      ++counts.flatCells;
    }
  }
  return counts;
}
} // namespace

std::size_t detail::D8SteepestDescent(const GridView<float>& view,
  const float* filled,
  std::int8_t* direction,
  const std::function<void(double)>& progress,
  std::size_t& outlets)
{
  const int nx = view.nx;
  const int ny = view.ny;
  std::size_t unresolved = 0;
  std::size_t outletCount = 0;
  double length[8];
  for (int j = 0; j < ny; ++j)
  {
    StepLengths(view, j, length);
    for (int i = 0; i < nx; ++i)
    {
      const std::size_t k = view.Index(i, j);
      if (direction[k] == kD8NoData)
      {
        continue;
      }
      const double h = filled[k];
      bool outlet = false;
      int best = -1;
      double bestSlope = 0.0;
      for (int e = 0; e < 8; ++e)
      {
        const int ii = i + kD8Di[e];
        const int jj = j + kD8Dj[e];
        if (ii < 0 || ii >= nx || jj < 0 || jj >= ny)
        {
          outlet = true;
          continue;
        }
        const std::size_t kk = view.Index(ii, jj);
        if (direction[kk] == kD8NoData)
        {
          outlet = true;
          continue;
        }
        const double drop = h - static_cast<double>(filled[kk]);
        if (drop > 0.0)
        {
          const double slope = drop / length[e];
          if (best < 0 || slope > bestSlope)
          {
            best = e;
            bestSlope = slope;
          }
        }
      }
      if (best >= 0)
      {
        direction[k] = static_cast<std::int8_t>(best);
      }
      else if (outlet)
      {
        direction[k] = kD8Outlet;
        ++outletCount;
      }
      else
      {
        ++unresolved;
      }
    }
    if (progress && j % 256 == 255)
    {
      progress(0.5 * (j + 1) / ny);
    }
  }
  outlets = outletCount;
  return unresolved;
}

int detail::D8FlatStep(const GridView<float>& view,
  const float* filled,
  const std::int32_t* distance,
  int i,
  int j)
{
  double length[8];
  StepLengths(view, j, length);
  const std::size_t k = view.Index(i, j);
  int best = -1;
  for (int e = 0; e < 8; ++e)
  {
    const int ii = i + kD8Di[e];
    const int jj = j + kD8Dj[e];
    if (ii < 0 || ii >= view.nx || jj < 0 || jj >= view.ny)
    {
      continue;
    }
    const std::size_t kk = view.Index(ii, jj);
    if (distance[kk] == distance[k] - 1 && filled[kk] == filled[k] &&
      (best < 0 || length[e] < length[best]))
    {
      best = e;
    }
  }
  return best;
}

D8Summary D8FlowDirections(const GridView<float>& view,
  const float* filled,
  std::int8_t* direction,
  const std::function<void(double)>& progress)
{
  detail::CheckCellCount(view, "D8FlowDirections");
  const std::size_t n = view.Size();
  auto hasData = [&](std::size_t k) { return HasData(view, k) && !std::isnan(filled[k]); };
  for (std::size_t k = 0; k < n; ++k)
  {
    direction[k] = hasData(k) ? kUnset : kD8NoData;
  }

  // 1. Steepest descent; outlets without a lower neighbour inside get -1; the rest stay unset.
  D8Summary summary;
  const std::size_t unresolved =
    detail::D8SteepestDescent(view, filled, direction, progress, summary.outlets);

  // 2. Flats: breadth-first distance from their draining cells, through cells of equal W.
  if (unresolved > 0)
  {
    std::vector<std::int32_t> distance(n, -1);
    std::vector<std::int32_t> queue;
    queue.reserve(unresolved);
    SeedFlatOutlets(view, filled, direction, distance, queue);
    FlatDistances(view, filled, direction, distance, queue, progress);
    const FlatCounts flats = DrainFlats(view, filled, direction, distance);
    summary.outlets += flats.outlets;
    summary.flatCells += flats.flatCells;
    summary.sinks += flats.sinks;
  }
  if (progress)
  {
    progress(1.0);
  }
  return summary;
}

void D8FlowAccumulation(const GridView<float>& view,
  const std::int8_t* direction,
  const float* weight,
  double* accumulation,
  const AccumulationOptions& options)
{
  if (view.nx < 1 || view.ny < 1 || !direction)
  {
    throw std::invalid_argument("D8FlowAccumulation: empty grid");
  }
  if (view.Size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
  {
    throw std::length_error("D8FlowAccumulation: more than 2^31 - 1 cells");
  }
  const int nx = view.nx;
  const int ny = view.ny;
  const std::size_t n = view.Size();

  // Own weights and in-degrees; every code 0..7 must point to a cell with data.
  std::vector<std::uint8_t> inDegree(n, 0);
  for (int j = 0; j < ny; ++j)
  {
    const double area = options.timesCellArea ? view.DxAt(j) * view.DyAt(j) : 1.0;
    const double factor = options.scale * area;
    for (int i = 0; i < nx; ++i)
    {
      const std::size_t k = view.Index(i, j);
      const int d = direction[k];
      const bool drains =
        detail::StartCell(d, weight, k, factor, accumulation, i, j, "D8FlowAccumulation");
      if (options.inflow && d != kD8NoData)
      {
        accumulation[k] += options.inflow[k];
      }
      if (drains)
      {
        detail::CountDownstream(view, direction, i, j, d, "D8FlowAccumulation", inDegree.data());
      }
    }
  }

  // Topological sweep: a cell whose upstream cells are all done passes its total downstream.
  std::ptrdiff_t offset[8];
  for (int e = 0; e < 8; ++e)
  {
    offset[e] = static_cast<std::ptrdiff_t>(kD8Dj[e]) * nx + kD8Di[e];
  }
  std::size_t done = 0;
  for (std::size_t start = 0; start < n; ++start)
  {
    if (direction[start] == kD8NoData || inDegree[start] != 0)
    {
      continue;
    }
    std::size_t k = start;
    inDegree[k] = 0xff; // done
    while (true)
    {
      ++done;
      if (options.progress && done % kProgressStep == 0)
      {
        options.progress(static_cast<double>(done) / static_cast<double>(n));
      }
      const int d = direction[k];
      if (d == kD8Outlet)
      {
        break;
      }
      const std::size_t t = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(k) + offset[d]);
      accumulation[t] += accumulation[k];
      if (--inDegree[t] != 0)
      {
        break; // t still waits for other upstream cells
      }
      inDegree[t] = 0xff;
      k = t;
    }
  }
  for (std::size_t k = 0; k < n; ++k)
  {
    if (direction[k] != kD8NoData && inDegree[k] != 0xff)
    {
      throw std::invalid_argument("D8FlowAccumulation: the directions hold a cycle through cell (" +
        std::to_string(k % static_cast<std::size_t>(nx)) + ", " +
        std::to_string(k / static_cast<std::size_t>(nx)) + ")");
    }
  }
  if (options.progress)
  {
    options.progress(1.0);
  }
}

} // namespace hydrology
} // namespace terroir

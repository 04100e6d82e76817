#include "MultipleFlow.h"

#include "WaterBody.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

namespace terroir
{
namespace hydrology
{

const char* const kMFDFreeman1991Citation =
  "Freeman, T.G. (1991). Calculating catchment area with divergent flow based on a regular grid. "
  "Computers & Geosciences 17(3):413-422. doi:10.1016/0098-3004(91)90048-I";

const char* const kDInfinityTarboton1997Citation =
  "Tarboton, D.G. (1997). A new method for the determination of flow directions and upslope "
  "areas in grid digital elevation models. Water Resources Research 33(2):309-319. "
  "doi:10.1029/96WR03137";

const char* const kSlopeAreaMontgomery1988Citation =
  "Montgomery, D.R., Dietrich, W.E. (1988). Where do channels begin? Nature 336:232-234. "
  "doi:10.1038/336232a0";

namespace
{
constexpr double kPi = 3.14159265358979323846;

/// The topological sweep shared by the methods. `partition(i, j, fraction)` fills the 8
/// fractions (neighbour order E, NE, N, NW, W, SW, S, SE) of a cell with a code 0..7.
template<typename Partition>
void Accumulate(const GridView<float>& view,
  const std::int8_t* direction,
  const float* weight,
  double* accumulation,
  const AccumulationOptions& options,
  const char* function,
  Partition partition)
{
  if (view.nx < 1 || view.ny < 1 || !direction)
  {
    throw std::invalid_argument(std::string(function) + ": empty grid");
  }
  detail::CheckCellCount(view, function);
  const int nx = view.nx;
  const int ny = view.ny;
  const std::size_t n = view.Size();
  const int* box = options.active;
  const auto active = [box](int i, int j)
  { return !box || (i >= box[0] && i <= box[1] && j >= box[2] && j <= box[3]); };
  std::vector<std::uint8_t> inDegree(n, 0);
  double fraction[8];
  for (int j = 0; j < ny; ++j)
  {
    const double area = options.timesCellArea ? view.DxAt(j) * view.DyAt(j) : 1.0;
    const double factor = options.scale * area;
    for (int i = 0; i < nx; ++i)
    {
      const std::size_t k = view.Index(i, j);
      if (!active(i, j))
      {
        accumulation[k] =
          direction[k] == kD8NoData ? std::numeric_limits<double>::quiet_NaN() : 0.0;
        continue;
      }
      const bool drains =
        detail::StartCell(direction[k], weight, k, factor, accumulation, i, j, function);
      if (options.inflow && direction[k] != kD8NoData)
      {
        accumulation[k] += options.inflow[k];
      }
      if (!drains)
      {
        continue;
      }
      partition(i, j, fraction);
      for (int e = 0; e < 8; ++e)
      {
        if (fraction[e] > 0.0)
        {
          detail::CountDownstream(view, direction, i, j, e, function, inDegree.data());
        }
      }
    }
  }
  std::vector<std::size_t> ready;
  for (std::size_t k = n; k-- > 0;)
  {
    if (direction[k] != kD8NoData && inDegree[k] == 0)
    {
      ready.push_back(k); // popped in index order
    }
  }
  std::size_t done = 0;
  while (!ready.empty())
  {
    const std::size_t k = ready.back();
    ready.pop_back();
    inDegree[k] = 0xff;
    ++done;
    const int i = static_cast<int>(k % static_cast<std::size_t>(nx));
    const int j = static_cast<int>(k / static_cast<std::size_t>(nx));
    if (direction[k] == kD8Outlet || !active(i, j))
    {
      continue;
    }
    partition(i, j, fraction);
    for (int e = 0; e < 8; ++e)
    {
      if (fraction[e] > 0.0)
      {
        const std::size_t t = view.Index(i + kD8Di[e], j + kD8Dj[e]);
        accumulation[t] += fraction[e] * accumulation[k];
        if (--inDegree[t] == 0)
        {
          ready.push_back(t);
        }
      }
    }
    if (options.progress && done % (std::size_t(1) << 20) == 0)
    {
      options.progress(static_cast<double>(done) / static_cast<double>(n));
    }
  }
  for (std::size_t k = 0; k < n; ++k)
  {
    if (direction[k] != kD8NoData && inDegree[k] != 0xff)
    {
      throw std::invalid_argument(std::string(function) +
        ": the flow graph holds a cycle through cell (" +
        std::to_string(k % static_cast<std::size_t>(nx)) + ", " +
        std::to_string(k / static_cast<std::size_t>(nx)) + ")");
    }
  }
  if (options.progress)
  {
    options.progress(1.0);
  }
}

/// Accumulate's incremental form (AccumulationOptions::incremental): the changes in
/// options.inflow pushed down from the active cells where they are non-zero, through the cells
/// downstream of them only, in topological order (a stack started in index order).
template<typename Partition>
void PropagateChange(const GridView<float>& view,
  const std::int8_t* direction,
  double* accumulation,
  const AccumulationOptions& options,
  const char* function,
  Partition partition)
{
  if (!options.inflow)
  {
    throw std::invalid_argument(std::string(function) + ": an incremental run needs the inflow");
  }
  const int nx = view.nx;
  const std::size_t n = view.Size();
  const int* box = options.active;
  const auto active = [box](int i, int j)
  { return !box || (i >= box[0] && i <= box[1] && j >= box[2] && j <= box[3]); };
  // f(t, fraction) for each receiver t of cell k (an active cell that drains).
  double fraction[8];
  const auto forReceivers = [&](std::size_t k, auto f)
  {
    const int i = static_cast<int>(k % static_cast<std::size_t>(nx));
    const int j = static_cast<int>(k / static_cast<std::size_t>(nx));
    if (direction[k] < 0 || direction[k] > 7 || !active(i, j))
    {
      return;
    }
    partition(i, j, fraction);
    for (int e = 0; e < 8; ++e)
    {
      if (fraction[e] > 0.0)
      {
        f(view.Index(i + kD8Di[e], j + kD8Dj[e]), fraction[e]);
      }
    }
  };
  // The cells downstream of a change, and their in-degrees within that set.
  std::unordered_map<std::size_t, std::uint8_t> inDegree;
  std::unordered_map<std::size_t, double> change;
  std::vector<std::size_t> stack;
  for (std::size_t k = n; k-- > 0;)
  {
    const int i = static_cast<int>(k % static_cast<std::size_t>(nx));
    const int j = static_cast<int>(k / static_cast<std::size_t>(nx));
    if (options.inflow[k] != 0.0 && direction[k] != kD8NoData && active(i, j))
    {
      change[k] = options.inflow[k];
      if (inDegree.emplace(k, 0).second)
      {
        stack.push_back(k);
      }
    }
  }
  std::vector<std::size_t> seeds(stack.rbegin(), stack.rend()); // index order
  while (!stack.empty())
  {
    const std::size_t k = stack.back();
    stack.pop_back();
    forReceivers(k,
      [&](std::size_t t, double)
      {
        const auto added = inDegree.emplace(t, 0);
        ++added.first->second;
        if (added.second)
        {
          stack.push_back(t);
        }
      });
  }
  std::vector<std::size_t> ready;
  for (auto s = seeds.rbegin(); s != seeds.rend(); ++s)
  {
    if (inDegree[*s] == 0)
    {
      ready.push_back(*s); // popped in index order
    }
  }
  while (!ready.empty())
  {
    const std::size_t k = ready.back();
    ready.pop_back();
    const double d = change[k];
    accumulation[k] += d;
    forReceivers(k,
      [&](std::size_t t, double f)
      {
        change[t] += f * d;
        if (--inDegree[t] == 0)
        {
          ready.push_back(t);
        }
      });
  }
}

/// True when neighbour (i + di, j + dj) is inside the grid and has data (code != -2).
bool Inside(const GridView<float>& view, const std::int8_t* direction, int i, int j)
{
  return i >= 0 && j >= 0 && i < view.nx && j < view.ny && direction[view.Index(i, j)] != kD8NoData;
}

/// The cell's D8 code as fractions (flats, and cells without a usable facet).
void FollowD8(int d, double fraction[8])
{
  for (int e = 0; e < 8; ++e)
  {
    fraction[e] = e == d ? 1.0 : 0.0;
  }
}
} // namespace

//------------------------------------------------------------------------------
void MultipleFlowAccumulation(const GridView<float>& view,
  const float* filled,
  const std::int8_t* direction,
  const MFDOptions& mfd,
  const float* weight,
  double* accumulation,
  const AccumulationOptions& options)
{
  if (!(std::isfinite(mfd.exponent) && mfd.exponent > 0.0))
  {
    throw std::invalid_argument("MultipleFlowAccumulation: the exponent must be a number > 0");
  }
  auto partition = [&](int i, int j, double fraction[8])
  {
    const double dx = view.DxAt(j);
    const double dy = view.DyAt(j);
    const double diagonal = std::sqrt(dx * dx + dy * dy);
    const double w = filled[view.Index(i, j)];
    double p = mfd.exponent;
    if (mfd.adaptive)
    {
      double steepest = 0.0;
      for (int e = 0; e < 8; ++e)
      {
        const int ii = i + kD8Di[e];
        const int jj = j + kD8Dj[e];
        if (Inside(view, direction, ii, jj))
        {
          const double length = kD8Di[e] == 0 ? dy : (kD8Dj[e] == 0 ? dx : diagonal);
          steepest = std::max(steepest, (w - filled[view.Index(ii, jj)]) / length);
        }
      }
      p =
        mfd.adaptiveMinimum + (mfd.adaptiveMaximum - mfd.adaptiveMinimum) * std::min(steepest, 1.0);
    }
    double sum = 0.0;
    for (int e = 0; e < 8; ++e)
    {
      fraction[e] = 0.0;
      const int ii = i + kD8Di[e];
      const int jj = j + kD8Dj[e];
      if (!Inside(view, direction, ii, jj))
      {
        continue;
      }
      const double drop = w - static_cast<double>(filled[view.Index(ii, jj)]);
      if (drop > 0.0)
      {
        const bool cardinal = kD8Di[e] == 0 || kD8Dj[e] == 0;
        const double length = kD8Di[e] == 0 ? dy : (kD8Dj[e] == 0 ? dx : diagonal);
        double share = std::pow(drop / length, p);
        if (mfd.contourLength)
        {
          share *= cardinal ? 0.5 * (kD8Di[e] == 0 ? dx : dy) : 0.25 * diagonal;
        }
        fraction[e] = share;
        sum += share;
      }
    }
    if (!(sum > 0.0))
    {
      FollowD8(direction[view.Index(i, j)], fraction);
      return;
    }
    for (int e = 0; e < 8; ++e)
    {
      fraction[e] /= sum;
    }
  };
  if (options.incremental)
  {
    PropagateChange(view, direction, accumulation, options, "MultipleFlowAccumulation", partition);
    return;
  }
  Accumulate(view, direction, weight, accumulation, options, "MultipleFlowAccumulation", partition);
}

namespace
{
/// Tarboton's facets: the cardinal neighbour's code and the diagonal's, in his order.
constexpr int kFacetCardinal[8] = { 0, 2, 2, 4, 4, 6, 6, 0 };
constexpr int kFacetDiagonal[8] = { 1, 1, 3, 3, 5, 5, 7, 7 };

/// D-infinity of cell (i, j): the winning facet, the angle r within it and its opening a;
/// false when no facet descends.
bool DInfinityFacet(const GridView<float>& view,
  const float* filled,
  const std::int8_t* direction,
  int i,
  int j,
  int& facet,
  double& r,
  double& a)
{
  const double dx = view.DxAt(j);
  const double dy = view.DyAt(j);
  const double e0 = filled[view.Index(i, j)];
  double best = 0.0;
  facet = -1;
  for (int f = 0; f < 8; ++f)
  {
    const int c = kFacetCardinal[f];
    const int g = kFacetDiagonal[f];
    if (!Inside(view, direction, i + kD8Di[c], j + kD8Dj[c]) ||
      !Inside(view, direction, i + kD8Di[g], j + kD8Dj[g]))
    {
      continue;
    }
    const double e1 = filled[view.Index(i + kD8Di[c], j + kD8Dj[c])];
    const double e2 = filled[view.Index(i + kD8Di[g], j + kD8Dj[g])];
    // d1 along the cardinal's axis, d2 along the other one.
    const double d1 = kD8Di[c] == 0 ? dy : dx;
    const double d2 = kD8Di[c] == 0 ? dx : dy;
    const double s1 = (e0 - e1) / d1;
    const double s2 = (e1 - e2) / d2;
    const double opening = std::atan2(d2, d1);
    double rf = std::atan2(s2, s1);
    double s = std::sqrt(s1 * s1 + s2 * s2);
    if (rf < 0.0)
    {
      rf = 0.0;
      s = s1;
    }
    else if (rf > opening)
    {
      rf = opening;
      s = (e0 - e2) / std::sqrt(d1 * d1 + d2 * d2);
    }
    if (s > best)
    {
      best = s;
      facet = f;
      r = rf;
      a = opening;
    }
  }
  return facet >= 0;
}

/// Angle counter-clockwise from east of a D8 code on a grid with spacing dx, dy.
double CodeAngle(int d, double dx, double dy)
{
  const double x = kD8Di[d] * dx;
  const double y = kD8Dj[d] * dy;
  const double t = std::atan2(y, x);
  return t < 0.0 ? t + 2.0 * kPi : t;
}
} // namespace

//------------------------------------------------------------------------------
void DInfinityAccumulation(const GridView<float>& view,
  const float* filled,
  const std::int8_t* direction,
  const float* weight,
  double* accumulation,
  float* angle,
  const AccumulationOptions& options)
{
  auto partition = [&](int i, int j, double fraction[8])
  {
    int facet = -1;
    double r = 0.0;
    double a = 0.0;
    if (!DInfinityFacet(view, filled, direction, i, j, facet, r, a))
    {
      FollowD8(direction[view.Index(i, j)], fraction);
      return;
    }
    for (int e = 0; e < 8; ++e)
    {
      fraction[e] = 0.0;
    }
    fraction[kFacetCardinal[facet]] = (a - r) / a;
    fraction[kFacetDiagonal[facet]] += r / a;
  };
  if (options.incremental)
  {
    PropagateChange(view, direction, accumulation, options, "DInfinityAccumulation", partition);
    return;
  }
  Accumulate(view, direction, weight, accumulation, options, "DInfinityAccumulation", partition);
  if (!angle)
  {
    return;
  }
  for (int j = 0; j < view.ny; ++j)
  {
    const double dx = view.DxAt(j);
    const double dy = view.DyAt(j);
    for (int i = 0; i < view.nx; ++i)
    {
      const std::size_t k = view.Index(i, j);
      const int d = direction[k];
      if (d < 0)
      {
        angle[k] = std::numeric_limits<float>::quiet_NaN();
        continue;
      }
      int facet = -1;
      double r = 0.0;
      double a = 0.0;
      if (!DInfinityFacet(view, filled, direction, i, j, facet, r, a))
      {
        angle[k] = static_cast<float>(CodeAngle(d, dx, dy));
        continue;
      }
      // Counter-clockwise from the cardinal towards the diagonal, or clockwise.
      const double base = CodeAngle(kFacetCardinal[facet], dx, dy);
      const double towards = CodeAngle(kFacetDiagonal[facet], dx, dy);
      double delta = towards - base;
      if (delta > kPi)
      {
        delta -= 2.0 * kPi;
      }
      if (delta < -kPi)
      {
        delta += 2.0 * kPi;
      }
      double t = base + (delta > 0.0 ? r : -r);
      if (t < 0.0)
      {
        t += 2.0 * kPi;
      }
      angle[k] = static_cast<float>(t);
    }
  }
}

//------------------------------------------------------------------------------
void ChannelInitiationScore(const GridView<float>& view,
  const double* accumulation,
  double theta,
  double minimumSlope,
  double* score)
{
  if (!(std::isfinite(theta) && theta >= 0.0 && std::isfinite(minimumSlope) && minimumSlope >= 0.0))
  {
    throw std::invalid_argument(
      "ChannelInitiationScore: theta and the minimum slope must be numbers >= 0");
  }
  for (int j = 0; j < view.ny; ++j)
  {
    const double dx = view.DxAt(j);
    const double dy = view.DyAt(j);
    const double diagonal = std::sqrt(dx * dx + dy * dy);
    for (int i = 0; i < view.nx; ++i)
    {
      const std::size_t k = view.Index(i, j);
      const double a = accumulation[k];
      if (!HasData(view, k) || std::isnan(a))
      {
        score[k] = std::numeric_limits<double>::quiet_NaN();
        continue;
      }
      const double z = view.data[k];
      double steepest = 0.0;
      for (int e = 0; e < 8; ++e)
      {
        const int ii = i + kD8Di[e];
        const int jj = j + kD8Dj[e];
        if (ii < 0 || jj < 0 || ii >= view.nx || jj >= view.ny ||
          !HasData(view, view.Index(ii, jj)))
        {
          continue;
        }
        const double length = kD8Di[e] == 0 ? dy : (kD8Dj[e] == 0 ? dx : diagonal);
        steepest = std::max(steepest, (z - view.data[view.Index(ii, jj)]) / length);
      }
      score[k] = a * std::pow(std::max(steepest, minimumSlope), theta);
    }
  }
}

} // namespace hydrology
} // namespace terroir

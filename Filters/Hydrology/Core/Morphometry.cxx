#include "Morphometry.h"

#include "FlowAccumulation.h"
#include "PriorityFlood.h"
#include "SlopeHorn1981.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace terroir
{
namespace hydrology
{

const char* const kMorphometryCitations =
  "Strahler, A.N. (1952). Hypsometric (area-altitude) analysis of erosional topography. GSA "
  "Bulletin 63(11):1117-1142. Horton, R.E. (1945). Erosional development of streams and their "
  "drainage basins. GSA Bulletin 56(3):275-370. Strahler, A.N. (1957). Quantitative analysis "
  "of watershed geomorphology. Trans. AGU 38(6):913-920. Hack, J.T. (1957). Studies of "
  "longitudinal stream profiles in Virginia and Maryland. USGS Prof. Paper 294-B.";

namespace
{
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool CellValid(const GridView<float>& view, std::size_t k)
{
  return (!view.valid || view.valid[k] != 0) && std::isfinite(view.data[k]);
}

/// Length of the D8 step with code e from a cell of row j (D8FlowDirections' distances).
double StepLength(const GridView<float>& view, int j, int e)
{
  const double dx = view.DxAt(j);
  const double dy = view.DyAt(j);
  if (kD8Dj[e] == 0)
  {
    return dx;
  }
  if (kD8Di[e] == 0)
  {
    return dy;
  }
  return std::sqrt(dx * dx + dy * dy);
}

/// Linear-interpolation percentile (numpy's default) of the values, reordered in place.
double Percentile(std::vector<float>& v, double p)
{
  if (v.empty())
  {
    return kNaN;
  }
  const double pos = p * static_cast<double>(v.size() - 1);
  const std::size_t lo = static_cast<std::size_t>(std::floor(pos));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(lo), v.end());
  const double a = v[lo];
  if (lo + 1 >= v.size())
  {
    return a;
  }
  const double b = *std::min_element(v.begin() + static_cast<std::ptrdiff_t>(lo) + 1, v.end());
  return a + (pos - static_cast<double>(lo)) * (b - a);
}
} // namespace

//------------------------------------------------------------------------------
LineFit FitLine(const std::vector<double>& x, const std::vector<double>& y)
{
  LineFit fit;
  fit.points = x.size();
  fit.slope = kNaN;
  fit.intercept = kNaN;
  if (x.size() < 2 || x.size() != y.size())
  {
    return fit;
  }
  double mx = 0.0, my = 0.0;
  for (std::size_t k = 0; k < x.size(); ++k)
  {
    mx += x[k];
    my += y[k];
  }
  mx /= static_cast<double>(x.size());
  my /= static_cast<double>(x.size());
  double sxx = 0.0, sxy = 0.0;
  for (std::size_t k = 0; k < x.size(); ++k)
  {
    sxx += (x[k] - mx) * (x[k] - mx);
    sxy += (x[k] - mx) * (y[k] - my);
  }
  if (!(sxx > 0.0))
  {
    return fit;
  }
  fit.slope = sxy / sxx;
  fit.intercept = my - fit.slope * mx;
  return fit;
}

//------------------------------------------------------------------------------
void HortonRatios(MorphometryReport& report)
{
  report.bifurcationRatio = kNaN;
  report.lengthRatio = kNaN;
  report.hortonFirstOrder = 0;
  report.hortonLastOrder = 0;
  const int omega = static_cast<int>(report.orders.size());
  const int last = omega - 1; // the highest order is left out (cut by the map edge)
  if (last < 2)
  {
    return;
  }
  std::vector<double> w, logN, logL;
  for (int k = 0; k < last; ++k)
  {
    const HortonOrderRow& row = report.orders[static_cast<std::size_t>(k)];
    w.push_back(row.order);
    logN.push_back(std::log10(static_cast<double>(row.streams)));
    logL.push_back(std::log10(row.meanLength));
  }
  report.hortonFirstOrder = 1;
  report.hortonLastOrder = last;
  report.bifurcationRatio = std::pow(10.0, -FitLine(w, logN).slope);
  report.lengthRatio = std::pow(10.0, FitLine(w, logL).slope);
}

//------------------------------------------------------------------------------
void ChannelNetworkStrahler1957(const GridView<float>& view,
  const std::int8_t* direction,
  const double* area,
  double channelArea,
  MorphometryReport& report,
  std::uint8_t* order,
  float* flowLength)
{
  const int nx = view.nx;
  const int ny = view.ny;
  const std::size_t n = view.Size();
  auto isChannel = [&](std::size_t k)
  { return direction[k] != kD8NoData && area[k] >= channelArea; };

  // In-degree over all cells with data (for the longest flow paths), and the downstream step.
  std::vector<std::uint8_t> inDegree(n, 0);
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      const int d = direction[view.Index(i, j)];
      if (d >= 0)
      {
        detail::CountDownstream(
          view, direction, i, j, d, "ChannelNetworkStrahler1957", inDegree.data());
      }
    }
  }
  std::vector<double> longest(n, 0.0);      // longest flow path ending at the cell, m
  std::vector<std::uint8_t> maxIn(n, 0);    // largest order among the channel inflows
  std::vector<std::uint8_t> countMax(n, 0); // how many channel inflows have that order
  std::vector<long long> streams;
  std::vector<double> lengths;
  std::vector<double> hackX, hackY;
  std::size_t channelCells = 0;
  double channelLength = 0.0;

  for (std::size_t start = 0; start < n; ++start)
  {
    if (direction[start] == kD8NoData || inDegree[start] != 0)
    {
      continue;
    }
    std::size_t k = start;
    for (;;)
    {
      inDegree[k] = 0xff; // done
      const int j = static_cast<int>(k / static_cast<std::size_t>(nx));
      const int i = static_cast<int>(k % static_cast<std::size_t>(nx));
      const int d = direction[k];
      const double step = d >= 0 ? StepLength(view, j, d) : 0.0;
      int w = 0;
      if (isChannel(k))
      {
        ++channelCells;
        const bool startsStream = maxIn[k] == 0 || countMax[k] >= 2;
        w = maxIn[k] == 0 ? 1 : (countMax[k] >= 2 ? maxIn[k] + 1 : maxIn[k]);
        if (w > 255)
        {
          throw std::length_error("ChannelNetworkStrahler1957: order above 255");
        }
        if (static_cast<std::size_t>(w) > streams.size())
        {
          streams.resize(static_cast<std::size_t>(w), 0);
          lengths.resize(static_cast<std::size_t>(w), 0.0);
        }
        streams[static_cast<std::size_t>(w - 1)] += startsStream ? 1 : 0;
        lengths[static_cast<std::size_t>(w - 1)] += step;
        channelLength += step;
        if (longest[k] > 0.0)
        {
          hackX.push_back(std::log10(area[k] * 1e-6));
          hackY.push_back(std::log10(longest[k] * 1e-3));
        }
      }
      if (order)
      {
        order[k] = static_cast<std::uint8_t>(w);
      }
      if (d < 0)
      {
        break;
      }
      const std::size_t t = view.Index(i + kD8Di[d], j + kD8Dj[d]);
      longest[t] = std::max(longest[t], longest[k] + step);
      if (w > 0)
      {
        if (w > maxIn[t])
        {
          maxIn[t] = static_cast<std::uint8_t>(w);
          countMax[t] = 1;
        }
        else if (w == maxIn[t])
        {
          countMax[t] = static_cast<std::uint8_t>(std::min(countMax[t] + 1, 8));
        }
      }
      if (--inDegree[t] != 0)
      {
        break;
      }
      k = t;
    }
  }
  for (std::size_t k = 0; k < n; ++k)
  {
    if (direction[k] != kD8NoData && inDegree[k] != 0xff)
    {
      throw std::invalid_argument("ChannelNetworkStrahler1957: the flow directions hold a cycle");
    }
    if (flowLength)
    {
      flowLength[k] = direction[k] == kD8NoData ? std::numeric_limits<float>::quiet_NaN()
                                                : static_cast<float>(longest[k]);
    }
    if (order && direction[k] == kD8NoData)
    {
      order[k] = 0;
    }
  }

  report.channelArea = channelArea;
  report.channelCells = channelCells;
  report.channelLength = channelLength;
  report.orders.clear();
  for (std::size_t w = 0; w < streams.size(); ++w)
  {
    HortonOrderRow row;
    row.order = static_cast<int>(w + 1);
    row.streams = streams[w];
    row.totalLength = lengths[w];
    row.meanLength = streams[w] > 0 ? lengths[w] / static_cast<double>(streams[w]) : kNaN;
    report.orders.push_back(row);
  }
  HortonRatios(report);
  const LineFit hack = FitLine(hackX, hackY);
  report.hackExponent = hack.slope;
  report.hackCoefficient = std::pow(10.0, hack.intercept);
  report.hackPoints = hack.points;
}

//------------------------------------------------------------------------------
MorphometryReport Morphometry(const GridView<float>& view,
  const MorphometryParams& params,
  const MorphometryCells& cells,
  const std::function<void(double)>& progress)
{
  if (view.nx < 2 || view.ny < 2)
  {
    throw std::invalid_argument("Morphometry: the grid must be at least 2 x 2 cells");
  }
  const std::size_t n = view.Size();
  auto report_progress = [&](double f)
  {
    if (progress)
    {
      progress(f);
    }
  };
  MorphometryReport r;

  // Hypsometry and valid area.
  double zMin = std::numeric_limits<double>::infinity();
  double zMax = -zMin, zSum = 0.0;
  for (int j = 0; j < view.ny; ++j)
  {
    const double cellArea = view.DxAt(j) * view.DyAt(j);
    for (int i = 0; i < view.nx; ++i)
    {
      const std::size_t k = view.Index(i, j);
      if (!CellValid(view, k))
      {
        continue;
      }
      const double z = view.data[k];
      zMin = std::min(zMin, z);
      zMax = std::max(zMax, z);
      zSum += z;
      ++r.validCells;
      r.validArea += cellArea;
    }
  }
  if (r.validCells == 0)
  {
    throw std::invalid_argument("Morphometry: the DEM has no cell with data");
  }
  r.minElevation = zMin;
  r.maxElevation = zMax;
  r.meanElevation = zSum / static_cast<double>(r.validCells);
  r.hypsometricIntegral = zMax > zMin ? (r.meanElevation - zMin) / (zMax - zMin) : kNaN;

  // Slope distribution.
  std::vector<float> ownSlope;
  const float* slope = cells.slope;
  if (!slope)
  {
    ownSlope.resize(n);
    terrain::SlopeHorn1981<float>(view, terrain::SlopeParams{}, ownSlope.data(), nullptr, nullptr);
    slope = ownSlope.data();
  }
  r.slopeBinWidth = params.slopeBinWidth;
  const std::size_t bins = static_cast<std::size_t>(std::ceil(90.0 / params.slopeBinWidth - 1e-9));
  r.slopeHistogram.assign(bins, 0);
  std::vector<float> slopes;
  slopes.reserve(r.validCells);
  double slopeSum = 0.0;
  for (std::size_t k = 0; k < n; ++k)
  {
    if (!CellValid(view, k) || !std::isfinite(slope[k]))
    {
      continue;
    }
    slopes.push_back(slope[k]);
    slopeSum += slope[k];
    const std::size_t b =
      std::min(bins - 1, static_cast<std::size_t>(std::max(0.0, slope[k] / params.slopeBinWidth)));
    ++r.slopeHistogram[b];
  }
  ownSlope.clear();
  ownSlope.shrink_to_fit();
  r.slopeMean = slopes.empty() ? kNaN : slopeSum / static_cast<double>(slopes.size());
  r.slopeP10 = Percentile(slopes, 0.10);
  r.slopeMedian = Percentile(slopes, 0.50);
  r.slopeP90 = Percentile(slopes, 0.90);
  slopes.clear();
  slopes.shrink_to_fit();
  report_progress(0.15);

  // Depressions.
  std::vector<float> filled(n);
  PriorityFloodBarnes2014(view, filled.data());
  report_progress(0.45);
  for (int j = 0; j < view.ny; ++j)
  {
    const double cellArea = view.DxAt(j) * view.DyAt(j);
    for (int i = 0; i < view.nx; ++i)
    {
      const std::size_t k = view.Index(i, j);
      const bool ok = CellValid(view, k);
      const double depth = ok ? static_cast<double>(filled[k]) - view.data[k] : kNaN;
      if (cells.depressionDepth)
      {
        cells.depressionDepth[k] = static_cast<float>(depth);
      }
      if (ok)
      {
        r.depressionVolume += depth * cellArea;
        r.depressionCells += depth > params.depressionDepth ? 1 : 0;
      }
    }
  }
  r.depressionShare = static_cast<double>(r.depressionCells) / static_cast<double>(r.validCells);

  // Streams.
  std::vector<std::int8_t> direction(n);
  D8FlowDirections(view, filled.data(), direction.data());
  filled.clear();
  filled.shrink_to_fit();
  report_progress(0.65);
  std::vector<double> ownArea;
  double* area = cells.contributingArea;
  if (!area)
  {
    ownArea.resize(n);
    area = ownArea.data();
  }
  AccumulationOptions acc;
  acc.timesCellArea = true;
  D8FlowAccumulation(view, direction.data(), nullptr, area, acc);
  report_progress(0.8);
  ChannelNetworkStrahler1957(
    view, direction.data(), area, params.channelArea, r, cells.strahlerOrder, cells.flowLength);
  r.drainageDensity = (r.channelLength * 1e-3) / (r.validArea * 1e-6);
  report_progress(1.0);
  return r;
}

} // namespace hydrology
} // namespace terroir

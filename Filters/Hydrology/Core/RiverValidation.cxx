#include "RiverValidation.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace terroir
{
namespace hydrology
{
namespace
{

/// Relative allowance on the squared tolerance: a distance equal to the tolerance up to
/// rounding (3 x 10 m against 30 m, sums of per-row steps) is within it.
constexpr double kToleranceSlack = 2e-9;

void CheckGrid(const GridView<std::uint8_t>& grid, const std::uint8_t* simulated, double tolerance)
{
  if (grid.nx < 0 || grid.ny < 0)
  {
    throw std::invalid_argument("river validation: negative grid size");
  }
  if (grid.Size() > 0 && (!grid.data || !simulated))
  {
    throw std::invalid_argument("river validation: null reference or simulated raster");
  }
  if (!std::isfinite(tolerance) || tolerance < 0.0)
  {
    throw std::invalid_argument(
      "river validation: the tolerance must be finite and >= 0 metres, got " +
      std::to_string(tolerance));
  }
  for (int j = 0; j < grid.ny; ++j)
  {
    const double dx = grid.DxAt(j);
    const double dy = grid.DyAt(j);
    if (!(std::isfinite(dx) && dx > 0.0 && std::isfinite(dy) && dy > 0.0))
    {
      throw std::invalid_argument(
        "river validation: cell spacing must be finite and > 0 (row " + std::to_string(j) + ")");
    }
    if (!grid.rowDx && !grid.rowDy)
    {
      break; // one spacing for every row: checked once
    }
  }
}

/// Distances between cell centres on the grid (see RiverValidation.h).
class GridMetric
{
public:
  explicit GridMetric(const GridView<std::uint8_t>& grid)
    : Grid(grid)
  {
    if (grid.rowDy)
    {
      this->Northing.resize(static_cast<std::size_t>(grid.ny));
      double y = 0.0;
      for (int j = 0; j < grid.ny; ++j)
      {
        if (j > 0)
        {
          y += 0.5 * (grid.rowDy[j - 1] + grid.rowDy[j]);
        }
        this->Northing[static_cast<std::size_t>(j)] = y;
      }
    }
  }

  /// North-south distance between the centres of rows j and k, metres.
  double RowDistance(int j, int k) const
  {
    if (this->Northing.empty())
    {
      return std::abs(j - k) * this->Grid.dy;
    }
    return std::abs(
      this->Northing[static_cast<std::size_t>(j)] - this->Northing[static_cast<std::size_t>(k)]);
  }

  /// East-west distance of one column step between rows j and k: the mean of their spacings.
  double ColumnStep(int j, int k) const
  {
    return this->Grid.rowDx ? 0.5 * (this->Grid.rowDx[j] + this->Grid.rowDx[k]) : this->Grid.dx;
  }

private:
  const GridView<std::uint8_t>& Grid;
  std::vector<double> Northing;
};

/// For one partner mask: per cell, the column distance to the nearest partner cell in the same
/// row, saturated at Far (meaning "none in this row"). Cells outside the area are no partners.
template<typename Distance>
class NearestInRow
{
public:
  static constexpr Distance Far = std::numeric_limits<Distance>::max();

  NearestInRow(const GridView<std::uint8_t>& grid,
    const std::uint8_t* partner,
    const std::vector<std::uint8_t>& inside)
    : Nx(grid.nx)
    , Column(grid.Size())
  {
    const std::size_t nx = static_cast<std::size_t>(grid.nx);
    for (int j = 0; j < grid.ny; ++j)
    {
      const std::size_t row = static_cast<std::size_t>(j) * nx;
      const std::uint8_t* p = partner + row;
      const std::uint8_t* in = inside.data() + row;
      Distance* d = this->Column.data() + row;
      // Left to right: distance to the nearest partner at or west of i.
      Distance run = Far;
      for (std::size_t i = 0; i < nx; ++i)
      {
        if (p[i] && in[i])
        {
          run = 0;
        }
        else if (run != Far)
        {
          ++run;
        }
        d[i] = run;
      }
      // Right to left: the nearest partner at or east of i, if nearer.
      run = Far;
      for (std::size_t i = nx; i-- > 0;)
      {
        if (p[i] && in[i])
        {
          run = 0;
        }
        else if (run != Far)
        {
          ++run;
        }
        d[i] = std::min(d[i], run);
      }
    }
  }

  Distance At(int i, int j) const
  {
    return this->Column[static_cast<std::size_t>(j) * static_cast<std::size_t>(this->Nx) +
      static_cast<std::size_t>(i)];
  }

private:
  int Nx;
  std::vector<Distance> Column;
};

/// Marks (in `hit`) the query cells inside the area that have a partner cell within the
/// tolerance. Returns the number of query cells inside the area.
template<typename Distance>
std::size_t MarkHits(const GridView<std::uint8_t>& grid,
  const GridMetric& metric,
  const std::uint8_t* query,
  const std::uint8_t* partner,
  const std::vector<std::uint8_t>& inside,
  double tolerance,
  std::vector<std::uint8_t>& hit)
{
  const NearestInRow<Distance> nearest(grid, partner, inside);
  const double limit = tolerance * tolerance * (1.0 + kToleranceSlack);
  std::size_t count = 0;
  hit.assign(grid.Size(), 0);
  for (int j = 0; j < grid.ny; ++j)
  {
    for (int i = 0; i < grid.nx; ++i)
    {
      const std::size_t c = grid.Index(i, j);
      if (!query[c] || !inside[c])
      {
        continue;
      }
      ++count;
      // Rows j, j-1, j+1, j-2, ... while the north-south distance alone is within tolerance.
      bool found = false;
      for (int step = 0; !found; ++step)
      {
        bool anyRow = false;
        for (int side = 0; side < (step == 0 ? 1 : 2) && !found; ++side)
        {
          const int k = side == 0 ? j - step : j + step;
          if (k < 0 || k >= grid.ny)
          {
            continue;
          }
          const double dyk = metric.RowDistance(j, k);
          const double dy2 = dyk * dyk;
          if (dy2 > limit)
          {
            continue;
          }
          anyRow = true;
          const Distance di = nearest.At(i, k);
          if (di == NearestInRow<Distance>::Far)
          {
            continue;
          }
          const double dxk = static_cast<double>(di) * metric.ColumnStep(j, k);
          found = dxk * dxk + dy2 <= limit;
        }
        if (!anyRow)
        {
          break; // rows further away are further still (spacings are > 0)
        }
      }
      hit[c] = found ? 1 : 0;
    }
  }
  return count;
}

/// Inside = area (or everywhere) and the reference view's valid mask.
std::vector<std::uint8_t> InsideMask(const GridView<std::uint8_t>& grid, const std::uint8_t* area)
{
  std::vector<std::uint8_t> inside(grid.Size(), 1);
  for (std::size_t c = 0; c < inside.size(); ++c)
  {
    inside[c] = ((!area || area[c]) && (!grid.valid || grid.valid[c])) ? 1 : 0;
  }
  return inside;
}

/// Both directions: which simulated cells have a reference partner and which reference cells
/// have a simulated partner.
struct Matches
{
  std::vector<std::uint8_t> inside;
  std::vector<std::uint8_t> simulatedHit;
  std::vector<std::uint8_t> referenceHit;
  std::size_t simulatedCells = 0;
  std::size_t referenceCells = 0;
};

Matches Match(const GridView<std::uint8_t>& reference,
  const std::uint8_t* simulated,
  const std::uint8_t* area,
  double tolerance)
{
  CheckGrid(reference, simulated, tolerance);
  Matches m;
  if (reference.Size() == 0)
  {
    return m;
  }
  m.inside = InsideMask(reference, area);
  const GridMetric metric(reference);
  // Column distances fit 16 bits (with the "none" value) when a row has at most 65535 cells.
  if (reference.nx <= 65535)
  {
    m.simulatedCells = MarkHits<std::uint16_t>(
      reference, metric, simulated, reference.data, m.inside, tolerance, m.simulatedHit);
    m.referenceCells = MarkHits<std::uint16_t>(
      reference, metric, reference.data, simulated, m.inside, tolerance, m.referenceHit);
  }
  else
  {
    m.simulatedCells = MarkHits<std::uint32_t>(
      reference, metric, simulated, reference.data, m.inside, tolerance, m.simulatedHit);
    m.referenceCells = MarkHits<std::uint32_t>(
      reference, metric, reference.data, simulated, m.inside, tolerance, m.referenceHit);
  }
  return m;
}

template<typename T>
double LengthMatchingThresholdT(const GridView<T>& value,
  const std::uint8_t* reference,
  const std::uint8_t* area,
  std::size_t* simulatedCellsOut)
{
  constexpr double inf = std::numeric_limits<double>::infinity();
  if (simulatedCellsOut)
  {
    *simulatedCellsOut = 0;
  }
  if (value.nx < 0 || value.ny < 0)
  {
    throw std::invalid_argument("LengthMatchingThreshold: negative grid size");
  }
  const std::size_t n = value.Size();
  if (n == 0)
  {
    return inf;
  }
  if (!value.data || !reference)
  {
    throw std::invalid_argument("LengthMatchingThreshold: null value or reference raster");
  }
  std::size_t k = 0;
  std::vector<T> candidates;
  for (std::size_t c = 0; c < n; ++c)
  {
    if ((area && !area[c]) || (value.valid && !value.valid[c]))
    {
      continue;
    }
    if (reference[c])
    {
      ++k;
    }
    if (std::isfinite(value.data[c]))
    {
      candidates.push_back(value.data[c]);
    }
  }
  if (k == 0 || candidates.empty())
  {
    return inf;
  }
  const std::size_t m = candidates.size();
  if (k >= m)
  {
    // Fewer values than reference cells: every finite value counts.
    if (simulatedCellsOut)
    {
      *simulatedCellsOut = m;
    }
    return static_cast<double>(*std::min_element(candidates.begin(), candidates.end()));
  }
  // v = the k-th largest value: position k - 1 in descending order.
  auto kth = candidates.begin() + static_cast<std::ptrdiff_t>(k - 1);
  std::nth_element(candidates.begin(), kth, candidates.end(), std::greater<T>());
  const T v = *kth;
  std::size_t atLeast = 0; // count(value >= v) >= k
  std::size_t above = 0;   // count(value > v) < k
  T next = v;              // smallest value > v, if any
  bool hasNext = false;
  for (const T x : candidates)
  {
    if (x >= v)
    {
      ++atLeast;
    }
    if (x > v)
    {
      ++above;
      if (!hasNext || x < next)
      {
        next = x;
        hasNext = true;
      }
    }
  }
  // The larger threshold (fewer cells) wins ties; with no value above v, that threshold is the
  // smallest value above all of them, i.e. no cell: +inf.
  const std::size_t overshoot = atLeast - k;
  const std::size_t undershoot = k - above;
  if (undershoot <= overshoot)
  {
    if (simulatedCellsOut)
    {
      *simulatedCellsOut = above;
    }
    return hasNext ? static_cast<double>(next) : inf;
  }
  if (simulatedCellsOut)
  {
    *simulatedCellsOut = atLeast;
  }
  return static_cast<double>(v);
}

} // namespace

//------------------------------------------------------------------------------
RiverScores ScoreRivers(const GridView<std::uint8_t>& reference,
  const std::uint8_t* simulated,
  const std::uint8_t* area,
  double toleranceMetres)
{
  const Matches m = Match(reference, simulated, area, toleranceMetres);
  RiverScores s;
  s.toleranceMetres = toleranceMetres;
  s.simulatedCells = m.simulatedCells;
  s.referenceCells = m.referenceCells;
  s.simulatedHits = static_cast<std::size_t>(
    std::count(m.simulatedHit.begin(), m.simulatedHit.end(), std::uint8_t(1)));
  s.referenceHits = static_cast<std::size_t>(
    std::count(m.referenceHit.begin(), m.referenceHit.end(), std::uint8_t(1)));
  s.precision = s.simulatedCells ? static_cast<double>(s.simulatedHits) / s.simulatedCells : 0.0;
  s.recall = s.referenceCells ? static_cast<double>(s.referenceHits) / s.referenceCells : 0.0;
  s.f1 =
    (s.precision + s.recall) > 0.0 ? 2.0 * s.precision * s.recall / (s.precision + s.recall) : 0.0;
  return s;
}

double LengthMatchingThreshold(const GridView<double>& value,
  const std::uint8_t* reference,
  const std::uint8_t* area,
  std::size_t* simulatedCellsOut)
{
  return LengthMatchingThresholdT(value, reference, area, simulatedCellsOut);
}

double LengthMatchingThreshold(const GridView<float>& value,
  const std::uint8_t* reference,
  const std::uint8_t* area,
  std::size_t* simulatedCellsOut)
{
  return LengthMatchingThresholdT(value, reference, area, simulatedCellsOut);
}

void RiverComparisonCategories(const GridView<std::uint8_t>& reference,
  const std::uint8_t* simulated,
  const std::uint8_t* area,
  double toleranceMetres,
  std::uint8_t* category)
{
  if (reference.Size() > 0 && !category)
  {
    throw std::invalid_argument("RiverComparisonCategories: null category output");
  }
  const Matches m = Match(reference, simulated, area, toleranceMetres);
  for (std::size_t c = 0; c < reference.Size(); ++c)
  {
    std::uint8_t out = RiverComparisonNone;
    if (m.inside[c])
    {
      const bool isReference = reference.data[c] != 0;
      const bool isSimulated = simulated[c] != 0;
      if ((isReference && m.referenceHit[c]) || (isSimulated && m.simulatedHit[c]))
      {
        out = RiverComparisonBoth;
      }
      else if (isReference)
      {
        out = RiverComparisonMappedOnly;
      }
      else if (isSimulated)
      {
        out = RiverComparisonSimulatedOnly;
      }
    }
    category[c] = out;
  }
}

//------------------------------------------------------------------------------
void ChannelCells(const GridView<double>& value, std::uint8_t* channel)
{
  const int nx = value.nx;
  const int ny = value.ny;
  const double none = std::numeric_limits<double>::quiet_NaN();
  auto at = [&](int i, int j) -> double
  {
    return i < 0 || j < 0 || i >= nx || j >= ny ? none
                                                : value.data[static_cast<std::size_t>(j) * nx + i];
  };
  static const int axis[4][2] = { { 1, 0 }, { 0, 1 }, { 1, 1 }, { 1, -1 } };
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      const double v = value.data[static_cast<std::size_t>(j) * nx + i];
      bool crest = false;
      for (int a = 0; a < 4 && std::isfinite(v) && !crest; ++a)
      {
        // An axis counts only when both of its neighbours hold values (NaN compares false).
        crest = v >= at(i + axis[a][0], j + axis[a][1]) && v >= at(i - axis[a][0], j - axis[a][1]);
      }
      channel[static_cast<std::size_t>(j) * nx + i] = crest ? 1 : 0;
    }
  }
}

} // namespace hydrology
} // namespace terroir

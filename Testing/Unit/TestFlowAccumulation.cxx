// Unit tests of the D8 cores (no VTK, no GL): terroir::hydrology::D8FlowDirections and
// D8FlowAccumulation, after PriorityFloodBarnes2014. Grids are drawn north row first in the
// source (as on a map) and stored with j = 0 in the south. Expected directions and
// accumulations are worked out by hand in the comments; the random terrains are checked
// against brute-force re-derivations (every neighbour's slope recomputed, every path walked).
#include "FlowAccumulation.h"
#include "PriorityFlood.h"

#include "TerroirDrawnGrid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

namespace
{
using terroir::GridView;
namespace hy = terroir::hydrology;

const float kNoData = std::numeric_limits<float>::quiet_NaN();

// Direction codes, as in FlowAccumulation.h.
constexpr int E = 0, NE = 1, N = 2, NW = 3, W = 4, SW = 5, S = 6, SE = 7, OUT = -1, ND = -2;

/// A grid drawn north row first, with its storage (Testing/Common/TerroirDrawnGrid.h).
using Grid = terroir_test::DrawnGrid;

/// Priority-Flood, then D8 directions and accumulation (1 per cell).
struct Routed
{
  std::vector<float> filled;
  std::vector<std::int8_t> dir;
  std::vector<double> acc;
  hy::D8Summary summary;
};

Routed Route(const Grid& g)
{
  Routed r;
  r.filled.assign(g.z.size(), -7.0f);
  r.dir.assign(g.z.size(), 99);
  r.acc.assign(g.z.size(), -7.0);
  hy::PriorityFloodBarnes2014(g.view, r.filled.data());
  r.summary = hy::D8FlowDirections(g.view, r.filled.data(), r.dir.data());
  hy::D8FlowAccumulation(g.view, r.dir.data(), nullptr, r.acc.data());
  return r;
}

/// Expects the directions (drawn north row first) cell for cell.
void ExpectDirections(const Grid& g,
  const std::vector<std::int8_t>& dir,
  const std::vector<std::vector<int>>& expected)
{
  for (int j = 0; j < g.view.ny; ++j)
  {
    for (int i = 0; i < g.view.nx; ++i)
    {
      EXPECT_EQ(dir[g.Cell(i, j)], expected[g.view.ny - 1 - j][i])
        << "cell (" << i << ", " << j << ")";
    }
  }
}

void ExpectAccumulation(const Grid& g,
  const std::vector<double>& acc,
  const std::vector<std::vector<double>>& expected)
{
  for (int j = 0; j < g.view.ny; ++j)
  {
    for (int i = 0; i < g.view.nx; ++i)
    {
      const double e = expected[g.view.ny - 1 - j][i];
      if (std::isnan(e))
      {
        EXPECT_TRUE(std::isnan(acc[g.Cell(i, j)])) << "cell (" << i << ", " << j << ")";
      }
      else
      {
        EXPECT_EQ(acc[g.Cell(i, j)], e) << "cell (" << i << ", " << j << ")";
      }
    }
  }
}

/// Walks the directions from every cell with data: each walk must end on a -1 cell within
/// nx*ny steps, through cells with data. Returns, per cell, how many walks passed through it
/// (the accumulation counted the slow way), NaN on no data.
std::vector<double> WalkEveryPath(const GridView<float>& v, const std::vector<std::int8_t>& dir)
{
  std::vector<double> count(v.Size(), 0.0);
  for (int j = 0; j < v.ny; ++j)
  {
    for (int i = 0; i < v.nx; ++i)
    {
      if (dir[v.Index(i, j)] == ND)
      {
        count[v.Index(i, j)] = std::nan("");
        continue;
      }
      int ci = i, cj = j;
      std::size_t steps = 0;
      while (true)
      {
        const std::size_t k = v.Index(ci, cj);
        count[k] += 1.0;
        const int d = dir[k];
        if (d == OUT)
        {
          break;
        }
        EXPECT_TRUE(d >= 0 && d < 8) << "code " << d << " at (" << ci << ", " << cj << ")";
        if (!(d >= 0 && d < 8))
        {
          return count;
        }
        ci += hy::kD8Di[d];
        cj += hy::kD8Dj[d];
        EXPECT_TRUE(ci >= 0 && ci < v.nx && cj >= 0 && cj < v.ny && dir[v.Index(ci, cj)] != ND)
          << "the path from (" << i << ", " << j << ") leaves the terrain";
        if (!(ci >= 0 && ci < v.nx && cj >= 0 && cj < v.ny && dir[v.Index(ci, cj)] != ND))
        {
          return count;
        }
        EXPECT_LE(++steps, v.Size()) << "cycle on the path from (" << i << ", " << j << ")";
        if (steps > v.Size())
        {
          return count;
        }
      }
    }
  }
  return count;
}

} // namespace

// A plane rising 1 m per 10 m cell to the east (z = i). Every cell east of the west column
// drains W (drop 1 over 10 m = 0.1; NW/SW: 1 over 14.14 m); the west column is the edge with
// no lower neighbour: -1. Accumulation = position along the slope = nx - i.
TEST(D8FlowDirections, TiltedPlaneDrainsDownTheSlope)
{
  Grid g(5,
    4,
    10.0,
    10.0,
    {
      { 0, 1, 2, 3, 4 },
      { 0, 1, 2, 3, 4 },
      { 0, 1, 2, 3, 4 },
      { 0, 1, 2, 3, 4 },
    });
  Routed r = Route(g);
  ExpectDirections(g,
    r.dir,
    {
      { OUT, W, W, W, W },
      { OUT, W, W, W, W },
      { OUT, W, W, W, W },
      { OUT, W, W, W, W },
    });
  ExpectAccumulation(g,
    r.acc,
    {
      { 5, 4, 3, 2, 1 },
      { 5, 4, 3, 2, 1 },
      { 5, 4, 3, 2, 1 },
      { 5, 4, 3, 2, 1 },
    });
  EXPECT_EQ(r.summary.outlets, 4u);
  EXPECT_EQ(r.summary.flatCells, 0u);
  EXPECT_EQ(r.summary.sinks, 0u);
}

// A plane falling to the north-east by 1 m per cell in both directions (z = -(i + j)) with
// square cells: the diagonal drop 2 over 1.414 beats the cardinal 1 over 1, so the interior
// drains NE; the north row and east column (edges) with a lower neighbour inside drain E or N
// along the edge, and the north-east corner is the only outlet.
TEST(D8FlowDirections, DiagonalPlaneDrainsNorthEast)
{
  Grid g(4,
    3,
    1.0,
    1.0,
    {
      { -2, -3, -4, -5 },
      { -1, -2, -3, -4 },
      { 0, -1, -2, -3 },
    });
  Routed r = Route(g);
  ExpectDirections(g,
    r.dir,
    {
      { E, E, E, OUT },
      { NE, NE, NE, N },
      { NE, NE, NE, N },
    });
  // Walk: (0,0) -> (1,1) -> (2,2) -> (3,2); (1,0) -> (2,1) -> (3,2); (2,0) -> (3,1) -> (3,2).
  ExpectAccumulation(g,
    r.acc,
    {
      { 1, 3, 6, 12 },
      { 1, 2, 2, 3 },
      { 1, 1, 1, 1 },
    });
}

// A V valley: z = 10 |i - 2| + j, square cells of 1 m. The floor (i = 2) drains S (drop 1);
// the sides drain sideways into the floor (E or W: drop 10 over 1, against 11 over 1.414 =
// 7.8 diagonally downstream); the floor's south end (2, 0) is the outlet. Floor accumulation:
// 5 cells per row at or north of it; each side cell next to the floor collects 2.
TEST(D8FlowDirections, VValleyCollectsBothSides)
{
  Grid g(5,
    6,
    1.0,
    1.0,
    {
      { 25, 15, 5, 15, 25 },
      { 24, 14, 4, 14, 24 },
      { 23, 13, 3, 13, 23 },
      { 22, 12, 2, 12, 22 },
      { 21, 11, 1, 11, 21 },
      { 20, 10, 0, 10, 20 },
    });
  Routed r = Route(g);
  ExpectDirections(g,
    r.dir,
    {
      { E, E, S, W, W },
      { E, E, S, W, W },
      { E, E, S, W, W },
      { E, E, S, W, W },
      { E, E, S, W, W },
      { E, E, OUT, W, W },
    });
  ExpectAccumulation(g,
    r.acc,
    {
      { 1, 2, 5, 2, 1 },
      { 1, 2, 10, 2, 1 },
      { 1, 2, 15, 2, 1 },
      { 1, 2, 20, 2, 1 },
      { 1, 2, 25, 2, 1 },
      { 1, 2, 30, 2, 1 },
    });
  EXPECT_EQ(r.summary.outlets, 1u);
}

// A pit (1) inside a ring of 5 inside a rim of 9, spilling over (2, 0) = 4 on the south edge.
// Priority-Flood raises the pit to 5: the interior is a 3 x 3 flat at 5. Its draining cells
// are the south row of the flat ((1,1) SE, (2,1) S, (3,1) SW into the spill cell); the rows
// above are flat cells at breadth-first distance 1 and 2, and each drains S (the nearest
// neighbour one step closer). The rim drains inwards (steepest drop into the flat or the
// spill cell); (2, 0) has no lower neighbour and lies on the edge: the only outlet.
// Accumulations counted by hand from these directions; all 25 cells reach the outlet.
TEST(D8FlowDirections, FilledPitDrainsThroughItsSpillCell)
{
  Grid g(5,
    5,
    1.0,
    1.0,
    {
      { 9, 9, 9, 9, 9 },
      { 9, 5, 5, 5, 9 },
      { 9, 5, 1, 5, 9 },
      { 9, 5, 5, 5, 9 },
      { 9, 9, 4, 9, 9 },
    });
  Routed r = Route(g);
  EXPECT_EQ(r.filled[g.Cell(2, 2)], 5.0f);
  ExpectDirections(g,
    r.dir,
    {
      { SE, S, S, S, SW },
      { E, S, S, S, W },
      { E, S, S, S, W },
      { E, SE, S, SW, W },
      { NE, E, OUT, W, NW },
    });
  ExpectAccumulation(g,
    r.acc,
    {
      { 1, 1, 1, 1, 1 },
      { 1, 4, 2, 4, 1 },
      { 1, 6, 3, 6, 1 },
      { 1, 9, 4, 9, 1 },
      { 1, 1, 25, 1, 1 },
    });
  EXPECT_EQ(r.summary.outlets, 1u);
  EXPECT_EQ(r.summary.flatCells, 6u);
  EXPECT_EQ(r.summary.sinks, 0u);
}

// A 4 x 4 flat at 5 inside a rim of 9, open to the west edge through (0, 1) = 4. Draining
// cells: (1, 1) W and (1, 2) SW into the spill cell. Breadth-first distance d of a flat cell
// (i, j) = max(i - 1, distance of row j to rows {1, 2}); drawn north row first:
//   j = 4:  2 2 2 3
//   j = 3:  1 1 2 3
//   j = 2:  0 1 2 3
//   j = 1:  0 1 2 3
// Each cell drains to the nearest neighbour at d - 1 (cardinal before diagonal, then code
// order): (1,3) S; (2,3) SW (its only d = 0 neighbour is (1,2)); (3,4) SW (W and S are at
// d = 2 too); (1,4), (2,4) S; the rest W.
TEST(D8FlowDirections, FlatDrainsBreadthFirstToItsOutlet)
{
  Grid g(6,
    6,
    1.0,
    1.0,
    {
      { 9, 9, 9, 9, 9, 9 },
      { 9, 5, 5, 5, 5, 9 },
      { 9, 5, 5, 5, 5, 9 },
      { 9, 5, 5, 5, 5, 9 },
      { 4, 5, 5, 5, 5, 9 },
      { 9, 9, 9, 9, 9, 9 },
    });
  Routed r = Route(g);
  for (std::size_t k = 0; k < g.z.size(); ++k)
  {
    EXPECT_EQ(r.filled[k], g.z[k]); // nothing to fill
  }
  // Flat interior as derived above; the rim drains to its steepest neighbour ((0, 0) and
  // (0, 2) into the spill cell: drop 5 over 1 beats 4 over 1 or 1.414 into the flat).
  ExpectDirections(g,
    r.dir,
    {
      { SE, S, S, S, S, SW },
      { E, S, S, SW, W, W },
      { E, S, SW, W, W, W },
      { S, SW, W, W, W, W },
      { OUT, W, W, W, W, W },
      { N, N, N, N, N, NW },
    });
  EXPECT_EQ(r.summary.flatCells, 14u);
  EXPECT_EQ(r.acc[g.Cell(0, 1)], 36.0);
  const std::vector<double> walked = WalkEveryPath(g.view, r.dir);
  for (std::size_t k = 0; k < g.z.size(); ++k)
  {
    EXPECT_EQ(r.acc[k], walked[k]) << "cell " << k;
  }
}

// A cone pointing down into a no-data cell: z = |i - 2| + |j - 2|, (2, 2) masked out. The
// four cells next to the hole at z = 1 have no lower neighbour with data: outlets (-1). The
// diagonal neighbours of the hole (z = 2) drain to a cardinal one at z = 1 (drop 1 over 1;
// tie E/N/W/S by code order); the other cells go down the cone (diagonal when off-axis: drop
// 2 over 1.414). The hole itself: -2, accumulation NaN; the four outlets collect all 24 cells.
TEST(D8FlowDirections, NoDataHoleDrainsItsNeighbours)
{
  Grid g(5,
    5,
    1.0,
    1.0,
    {
      { 4, 3, 2, 3, 4 },
      { 3, 2, 1, 2, 3 },
      { 2, 1, 0, 1, 2 },
      { 3, 2, 1, 2, 3 },
      { 4, 3, 2, 3, 4 },
    });
  g.MaskOut(2, 2);
  Routed r = Route(g);
  ExpectDirections(g,
    r.dir,
    {
      { SE, SE, S, SW, SW },
      { SE, E, OUT, W, SW },
      { E, OUT, ND, OUT, W },
      { NE, E, OUT, N, NW },
      { NE, NE, N, NW, NW },
    });
  // (2,1) collects (1,1), (1,0), (2,0), (3,0) and (0,0) through (1,1): 6. (1,2) collects
  // (0,2), (0,1), (0,3): 4. (3,2) collects (3,1), (4,1), (4,2), (4,3), (4,0) through (3,1):
  // 6. (2,3) collects (1,3), (3,3), (2,4), (1,4), (3,4), (0,4) through (1,3), (4,4) through
  // (3,3): 8. Total 24.
  ExpectAccumulation(g,
    r.acc,
    {
      { 1, 1, 1, 1, 1 },
      { 1, 2, 8, 2, 1 },
      { 1, 4, std::nan(""), 6, 1 },
      { 1, 2, 6, 2, 1 },
      { 1, 1, 1, 1, 1 },
    });
  EXPECT_EQ(r.summary.outlets, 4u);
}

// Per-row spacing decides the steepest neighbour. Cell (1, 1) at 10 m has E at 9 (drop 1) and
// N at 8.5 (drop 1.5), everything else higher. Square 1 m cells: N (1.5 > 1). Row 1 twice as
// long north-south (rowDy[1] = 2): N gives 0.75 < 1, so E. Row 1 half as wide east-west
// (rowDx[1] = 0.5, rowDy 1): E gives 2 > 1.5, so E. Only the cell's own row's spacing counts:
// changing rows 0 and 2 changes nothing.
TEST(D8FlowDirections, PerRowSpacingChangesTheSteepestNeighbour)
{
  Grid g(3,
    3,
    1.0,
    1.0,
    {
      { 20, 8.5, 20 },
      { 20, 10, 9 },
      { 20, 20, 20 },
    });
  EXPECT_EQ(Route(g).dir[g.Cell(1, 1)], N);
  auto spacing = [&g](std::vector<double> rowDx, std::vector<double> rowDy)
  {
    g.rowDx = std::move(rowDx);
    g.rowDy = std::move(rowDy);
    g.view.rowDx = g.rowDx.data();
    g.view.rowDy = g.rowDy.data();
  };
  spacing({ 1.0, 1.0, 1.0 }, { 1.0, 2.0, 1.0 });
  EXPECT_EQ(Route(g).dir[g.Cell(1, 1)], E);
  spacing({ 1.0, 0.5, 1.0 }, { 1.0, 1.0, 1.0 });
  EXPECT_EQ(Route(g).dir[g.Cell(1, 1)], E);
  spacing({ 0.1, 1.0, 0.1 }, { 5.0, 1.0, 5.0 });
  EXPECT_EQ(Route(g).dir[g.Cell(1, 1)], N);
}

// Ties between equally steep neighbours go to the lowest code (E, NE, N, NW, W, SW, S, SE).
TEST(D8FlowDirections, TiesGoToTheLowestCode)
{
  // The centre (5) sees W, S and N at 4: N (code 2) wins over W (4) and S (6).
  Grid g(3,
    3,
    1.0,
    1.0,
    {
      { 9, 4, 9 },
      { 4, 5, 9 },
      { 9, 4, 9 },
    });
  EXPECT_EQ(Route(g).dir[g.Cell(1, 1)], N);
  // SW and SE at the same drop: SW (5) before SE (7).
  Grid h(3,
    3,
    1.0,
    1.0,
    {
      { 9, 9, 9 },
      { 9, 5, 9 },
      { 3, 9, 3 },
    });
  EXPECT_EQ(Route(h).dir[h.Cell(1, 1)], SW);
}

// Weights: the weighted accumulation is the sum of the weights upstream, times scale and cell
// area when asked; NaN weights count as 0. On the V valley with 2 m x 3 m cells: the outlet
// collects 30 cells of 6 m^2 = 180 m^2; with weight 10 mm per cell and scale 1e-3, 30 * 0.01
// * 6 = 1.8 m^3.
TEST(D8FlowAccumulation, WeightsScaleAndCellArea)
{
  std::vector<std::vector<float>> rows;
  for (int j = 5; j >= 0; --j)
  {
    rows.push_back({ 20.0f + j, 10.0f + j, 0.0f + j, 10.0f + j, 20.0f + j });
  }
  Grid g(5, 6, 2.0, 3.0, rows);
  Routed r = Route(g);
  std::vector<double> area(g.z.size());
  hy::AccumulationOptions byArea;
  byArea.timesCellArea = true;
  hy::D8FlowAccumulation(g.view, r.dir.data(), nullptr, area.data(), byArea);
  EXPECT_DOUBLE_EQ(area[g.Cell(2, 0)], 180.0);
  EXPECT_DOUBLE_EQ(area[g.Cell(1, 3)], 12.0);

  std::vector<float> mm(g.z.size(), 10.0f);
  mm[g.Cell(0, 5)] = kNoData; // counts as 0
  std::vector<double> volume(g.z.size());
  hy::AccumulationOptions options;
  options.timesCellArea = true;
  options.scale = 1e-3;
  hy::D8FlowAccumulation(g.view, r.dir.data(), mm.data(), volume.data(), options);
  EXPECT_NEAR(volume[g.Cell(2, 0)], 29 * 0.01 * 6.0, 1e-12);
  EXPECT_NEAR(volume[g.Cell(1, 5)], 0.06, 1e-12);
  EXPECT_EQ(volume[g.Cell(0, 5)], 0.0);

  // Per-row areas: rows 0..5 with dx = 1..6 and dy = 1: the outlet collects
  // 5 * (1 + 2 + ... + 6) = 105 m^2.
  std::vector<double> rowDx = { 1, 2, 3, 4, 5, 6 }, rowDy(6, 1.0);
  GridView<float> v = g.view;
  v.rowDx = rowDx.data();
  v.rowDy = rowDy.data();
  hy::D8FlowAccumulation(v, r.dir.data(), nullptr, area.data(), byArea);
  EXPECT_DOUBLE_EQ(area[g.Cell(2, 0)], 105.0);
}

// Directions that cannot come from D8FlowDirections are refused: a cycle, a step off the grid,
// a step into no data, an unknown code.
TEST(D8FlowAccumulation, RefusesBrokenDirections)
{
  Grid g(2, 2, 1.0, 1.0, { { 1, 1 }, { 1, 1 } });
  std::vector<double> acc(4);
  // (0,0) E -> (1,0) N -> (1,1) W -> (0,1) S -> (0,0): a cycle.
  std::vector<std::int8_t> cycle = { E, N, S, W };
  EXPECT_THROW(
    hy::D8FlowAccumulation(g.view, cycle.data(), nullptr, acc.data()), std::invalid_argument);
  std::vector<std::int8_t> offGrid = { W, OUT, OUT, OUT };
  EXPECT_THROW(
    hy::D8FlowAccumulation(g.view, offGrid.data(), nullptr, acc.data()), std::invalid_argument);
  std::vector<std::int8_t> intoNoData = { E, ND, OUT, OUT };
  EXPECT_THROW(
    hy::D8FlowAccumulation(g.view, intoNoData.data(), nullptr, acc.data()), std::invalid_argument);
  std::vector<std::int8_t> unknown = { 8, OUT, OUT, OUT };
  EXPECT_THROW(
    hy::D8FlowAccumulation(g.view, unknown.data(), nullptr, acc.data()), std::invalid_argument);
  std::vector<std::int8_t> fine = { E, OUT, SE, S };
  hy::D8FlowAccumulation(g.view, fine.data(), nullptr, acc.data());
  EXPECT_EQ(acc[1], 4.0);
}

// A surface that was not filled: the pit has no way down and becomes a sink (-1), counted.
TEST(D8FlowDirections, UnfilledPitBecomesACountedSink)
{
  Grid g(3, 3, 1.0, 1.0, { { 9, 9, 9 }, { 9, 1, 9 }, { 9, 9, 9 } });
  std::vector<std::int8_t> dir(9);
  const hy::D8Summary s = hy::D8FlowDirections(g.view, g.z.data(), dir.data());
  EXPECT_EQ(dir[g.Cell(1, 1)], OUT);
  EXPECT_EQ(s.sinks, 1u);
  EXPECT_EQ(s.outlets, 1u); // the rim cells all drain into the pit
}

// Random terrains (fixed mt19937_64 seed, heights quantised to whole metres so that flats are
// common, ~5 % no-data cells, some grids with per-row spacing): every direction is re-derived
// by brute force; every walk ends on an outlet (no cycles); accumulations equal the walk
// counts; outlet accumulations sum to the number of valid cells, contributing areas to the
// total area.
TEST(D8FlowDirections, RandomTerrainsDrainWithoutCycles)
{
  std::mt19937_64 rng(20240611);
  // Our own mapping of raw draws (std:: distributions differ between standard libraries).
  auto uniform = [&rng]() { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };
  std::size_t flatCellsSeen = 0;
  for (int t = 0; t < 40; ++t)
  {
    const int nx = 8 + static_cast<int>(uniform() * 40);
    const int ny = 8 + static_cast<int>(uniform() * 40);
    std::vector<std::vector<float>> rows(ny, std::vector<float>(nx));
    for (auto& row : rows)
    {
      for (float& z : row)
      {
        z = static_cast<float>(std::floor(uniform() * 12.0));
      }
    }
    Grid g(nx, ny, 1.0 + uniform() * 20.0, 1.0 + uniform() * 20.0, rows);
    for (std::size_t k = 0; k < g.z.size(); ++k)
    {
      if (uniform() < 0.05)
      {
        if (uniform() < 0.5)
        {
          g.z[k] = kNoData;
        }
        else
        {
          g.MaskOut(static_cast<int>(k % nx), static_cast<int>(k / nx));
        }
      }
    }
    if (t % 3 == 0)
    {
      for (int j = 0; j < ny; ++j)
      {
        g.rowDx.push_back(5.0 + 10.0 * uniform());
        g.rowDy.push_back(5.0 + 10.0 * uniform());
      }
      g.view.rowDx = g.rowDx.data();
      g.view.rowDy = g.rowDy.data();
    }
    const GridView<float>& v = g.view;
    Routed r = Route(g);
    flatCellsSeen += r.summary.flatCells;
    EXPECT_EQ(r.summary.sinks, 0u) << "terrain " << t;

    std::size_t validCells = 0, outlets = 0;
    double outletSum = 0.0, totalArea = 0.0;
    for (int j = 0; j < ny; ++j)
    {
      for (int i = 0; i < nx; ++i)
      {
        const std::size_t k = v.Index(i, j);
        const bool hasData = (v.valid == nullptr || v.valid[k]) && !std::isnan(v.data[k]);
        if (!hasData)
        {
          EXPECT_EQ(r.dir[k], ND);
          EXPECT_TRUE(std::isnan(r.acc[k]));
          continue;
        }
        ++validCells;
        totalArea += v.DxAt(j) * v.DyAt(j);
        // Brute force: steepest strictly lower neighbour with data, lowest code on ties;
        // whether the cell is an outlet (edge or next to no data).
        const double dx = v.DxAt(j), dy = v.DyAt(j);
        const double diag = std::sqrt(dx * dx + dy * dy);
        const double len[8] = { dx, diag, dy, diag, dx, diag, dy, diag };
        int best = -1;
        double bestSlope = 0.0;
        bool outlet = false;
        for (int e = 0; e < 8; ++e)
        {
          const int ii = i + hy::kD8Di[e], jj = j + hy::kD8Dj[e];
          if (ii < 0 || ii >= nx || jj < 0 || jj >= ny || r.dir[v.Index(ii, jj)] == ND)
          {
            outlet = true;
            continue;
          }
          const double drop = double(r.filled[k]) - double(r.filled[v.Index(ii, jj)]);
          if (drop > 0.0 && (best < 0 || drop / len[e] > bestSlope))
          {
            best = e;
            bestSlope = drop / len[e];
          }
        }
        if (best >= 0)
        {
          EXPECT_EQ(r.dir[k], best) << "terrain " << t << " cell (" << i << ", " << j << ")";
        }
        else if (outlet)
        {
          EXPECT_EQ(r.dir[k], OUT) << "terrain " << t << " cell (" << i << ", " << j << ")";
        }
        else
        {
          // A flat cell: it drains to a neighbour of exactly the same filled height.
          ASSERT_GE(r.dir[k], 0) << "terrain " << t << " cell (" << i << ", " << j << ")";
          const int d = r.dir[k];
          EXPECT_EQ(r.filled[v.Index(i + hy::kD8Di[d], j + hy::kD8Dj[d])], r.filled[k]);
        }
        if (r.dir[k] == OUT)
        {
          ++outlets;
          outletSum += r.acc[k];
        }
      }
    }
    EXPECT_EQ(outlets, r.summary.outlets);
    EXPECT_EQ(outletSum, static_cast<double>(validCells)) << "terrain " << t;
    const std::vector<double> walked = WalkEveryPath(v, r.dir);
    for (std::size_t k = 0; k < g.z.size(); ++k)
    {
      if (!std::isnan(walked[k]))
      {
        ASSERT_EQ(r.acc[k], walked[k]) << "terrain " << t << " cell " << k;
      }
    }
    std::vector<double> area(g.z.size());
    hy::AccumulationOptions byArea;
    byArea.timesCellArea = true;
    hy::D8FlowAccumulation(v, r.dir.data(), nullptr, area.data(), byArea);
    double outletArea = 0.0;
    for (std::size_t k = 0; k < g.z.size(); ++k)
    {
      outletArea += r.dir[k] == OUT ? area[k] : 0.0;
    }
    EXPECT_NEAR(outletArea, totalArea, 1e-9 * totalArea) << "terrain " << t;
  }
  EXPECT_GT(flatCellsSeen, 1000u) << "the random terrains should exercise the flat rule";
}

// Degenerate grids: a single cell is an outlet; an all-no-data grid has no outlet.
TEST(D8FlowDirections, SingleCellAndAllNoData)
{
  Grid one(1, 1, 1.0, 1.0, { { 3 } });
  Routed r = Route(one);
  EXPECT_EQ(r.dir[0], OUT);
  EXPECT_EQ(r.acc[0], 1.0);
  Grid none(2, 1, 1.0, 1.0, { { kNoData, kNoData } });
  Routed s = Route(none);
  EXPECT_EQ(s.dir[0], ND);
  EXPECT_EQ(s.dir[1], ND);
  EXPECT_TRUE(std::isnan(s.acc[0]));
}

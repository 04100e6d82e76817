// Unit tests of the hydrology cores (no VTK, no GL): terroir::hydrology::FloodFillSeeds,
// PriorityFloodBarnes2014 and DepressionWaterBodies. Grids are drawn north row first in the
// source (as on a map) and stored with j = 0 in the south. Every expected value is worked out
// by hand in the comments, or comes from an independent brute-force fixed point.
#include "DepressionWaterBodies.h"
#include "FloodFill.h"
#include "PriorityFlood.h"

#include "TerroirDrawnGrid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

namespace
{
using terroir::GridView;
namespace hy = terroir::hydrology;

const float kNoData = std::numeric_limits<float>::quiet_NaN();

/// A grid drawn north row first, with its storage (Testing/Common/TerroirDrawnGrid.h).
using Grid = terroir_test::DrawnGrid;

struct SeedResult
{
  std::vector<std::int32_t> id;
  std::vector<float> depth;
  std::vector<hy::WaterBodyStats> bodies;
};

SeedResult Fill(const Grid& g, const std::vector<hy::FloodSeed>& seeds)
{
  SeedResult r;
  r.id.assign(g.z.size(), -7);
  r.depth.assign(g.z.size(), -7.0f);
  r.bodies = hy::FloodFillSeeds(g.view, seeds, r.id.data(), r.depth.data());
  return r;
}

hy::FloodSeed Seed(const Grid& g, int i, int j, double level = std::nan(""))
{
  hy::FloodSeed s;
  s.cell = g.Cell(i, j);
  s.level = level;
  return s;
}

// A bowl (rim 9) whose floor surrounds an island (8), and east of it, behind the rim, a
// separate pit (0). Cells are 2 m (east-west) by 3 m (north-south): 6 m^2 each.
Grid Bowl()
{
  return Grid(7,
    5,
    2.0,
    3.0,
    {
      { 9, 9, 9, 9, 9, 9, 9 }, // j = 4
      { 9, 1, 2, 1, 9, 0, 9 }, // j = 3
      { 9, 2, 8, 3, 9, 9, 9 }, // j = 2
      { 9, 1, 2, 1, 9, 9, 9 }, // j = 1
      { 9, 9, 9, 9, 9, 9, 9 }, // j = 0
    });
}

/// Expects `id` to be `expected` (drawn north row first) cell for cell.
void ExpectIds(const Grid& g,
  const std::vector<std::int32_t>& id,
  const std::vector<std::vector<int>>& expected)
{
  for (int j = 0; j < g.view.ny; ++j)
  {
    for (int i = 0; i < g.view.nx; ++i)
    {
      EXPECT_EQ(id[g.Cell(i, j)], expected[g.view.ny - 1 - j][i])
        << "cell (" << i << ", " << j << ")";
    }
  }
}

} // namespace

// Level 5 from (1, 1): the eight floor cells (1, 2, 1 / 2, _, 3 / 1, 2, 1) are wet, the island
// (8) and the rim (9) are not, and neither is the pit (0 <= 5, but not connected).
// Depths 5 - z: 4 3 4 / 3 _ 2 / 4 3 4, sum 27; area 8 * 6 = 48 m^2, volume 27 * 6 = 162 m^3.
TEST(TerroirFloodFillSeeds, BowlFloodsAroundTheIslandButNotTheSeparatePit)
{
  const Grid g = Bowl();
  const SeedResult r = Fill(g, { Seed(g, 1, 1, 5.0) });
  ExpectIds(g,
    r.id,
    {
      { 0, 0, 0, 0, 0, 0, 0 },
      { 0, 1, 1, 1, 0, 0, 0 },
      { 0, 1, 0, 1, 0, 0, 0 },
      { 0, 1, 1, 1, 0, 0, 0 },
      { 0, 0, 0, 0, 0, 0, 0 },
    });
  const float expectedDepth[5][7] = {
    { 0, 0, 0, 0, 0, 0, 0 },
    { 0, 4, 3, 4, 0, 0, 0 },
    { 0, 3, 0, 2, 0, 0, 0 },
    { 0, 4, 3, 4, 0, 0, 0 },
    { 0, 0, 0, 0, 0, 0, 0 },
  };
  for (int j = 0; j < 5; ++j)
  {
    for (int i = 0; i < 7; ++i)
    {
      EXPECT_EQ(r.depth[g.Cell(i, j)], expectedDepth[4 - j][i]) << i << ", " << j;
    }
  }
  ASSERT_EQ(r.bodies.size(), 1u);
  EXPECT_EQ(r.bodies[0].level, 5.0);
  EXPECT_EQ(r.bodies[0].cells, 8);
  EXPECT_DOUBLE_EQ(r.bodies[0].area, 48.0);
  EXPECT_DOUBLE_EQ(r.bodies[0].volume, 162.0);
  EXPECT_DOUBLE_EQ(r.bodies[0].maxDepth, 4.0);
}

// The level is inclusive: at 8 the island (z = 8) is wet with depth 0. Depths 8 - z:
// 7 6 7 / 6 0 5 / 7 6 7, sum 51; 9 cells, 54 m^2, 306 m^3. Just below 8 it stays dry.
TEST(TerroirFloodFillSeeds, LevelIsInclusive)
{
  const Grid g = Bowl();
  const SeedResult r = Fill(g, { Seed(g, 1, 1, 8.0) });
  EXPECT_EQ(r.id[g.Cell(2, 2)], 1);
  EXPECT_EQ(r.depth[g.Cell(2, 2)], 0.0f);
  EXPECT_EQ(r.id[g.Cell(4, 2)], 0); // rim 9
  EXPECT_EQ(r.bodies[0].cells, 9);
  EXPECT_DOUBLE_EQ(r.bodies[0].area, 54.0);
  EXPECT_DOUBLE_EQ(r.bodies[0].volume, 306.0);
  EXPECT_DOUBLE_EQ(r.bodies[0].maxDepth, 7.0);

  const SeedResult below = Fill(g, { Seed(g, 1, 1, std::nextafter(8.0, 0.0)) });
  EXPECT_EQ(below.id[g.Cell(2, 2)], 0);
  EXPECT_EQ(below.bodies[0].cells, 8);
}

// With no level the water stands at the terrain height of the seed cell.
// From (3, 2) (z = 3): all eight floor cells (<= 3); depths 3 - z: 2 1 2 / 1 _ 0 / 2 1 2,
// sum 11, volume 66 m^3. From (2, 1) (z = 2): the seven floor cells <= 2 (not (3, 2) = 3),
// depths 1 0 1 / 0 _ _ / 1 0 1, sum 4, volume 24 m^3.
TEST(TerroirFloodFillSeeds, DefaultLevelIsTheTerrainAtTheSeed)
{
  const Grid g = Bowl();
  const SeedResult a = Fill(g, { Seed(g, 3, 2) });
  EXPECT_EQ(a.bodies[0].level, 3.0);
  EXPECT_EQ(a.bodies[0].cells, 8);
  EXPECT_DOUBLE_EQ(a.bodies[0].volume, 66.0);
  EXPECT_EQ(a.depth[g.Cell(3, 2)], 0.0f);

  const SeedResult b = Fill(g, { Seed(g, 2, 1) });
  EXPECT_EQ(b.bodies[0].level, 2.0);
  EXPECT_EQ(b.bodies[0].cells, 7);
  EXPECT_DOUBLE_EQ(b.bodies[0].area, 42.0);
  EXPECT_DOUBLE_EQ(b.bodies[0].volume, 24.0);
  EXPECT_DOUBLE_EQ(b.bodies[0].maxDepth, 1.0);
  EXPECT_EQ(b.id[g.Cell(3, 2)], 0);
}

// Low cells on both edges: the fill stops at the edge and does not wrap around to the other
// side of the grid (cell (0, 1) has index 4, cell (3, 0) index 3 and cell (3, 1) index 7).
TEST(TerroirFloodFillSeeds, StopsAtTheEdgesWithoutWrappingAround)
{
  const Grid g(4,
    3,
    1.0,
    1.0,
    {
      { 5, 5, 5, 5 },
      { 0, 5, 5, 0 },
      { 5, 5, 5, 0 },
    });
  const SeedResult west = Fill(g, { Seed(g, 0, 1, 1.0) });
  ExpectIds(g,
    west.id,
    {
      { 0, 0, 0, 0 },
      { 1, 0, 0, 0 },
      { 0, 0, 0, 0 },
    });
  const SeedResult east = Fill(g, { Seed(g, 3, 1, 1.0) });
  ExpectIds(g,
    east.id,
    {
      { 0, 0, 0, 0 },
      { 0, 0, 0, 1 },
      { 0, 0, 0, 1 },
    });
  // Level 5 reaches every cell, and nothing beyond the grid.
  const SeedResult all = Fill(g, { Seed(g, 0, 1, 5.0) });
  EXPECT_EQ(all.bodies[0].cells, 12);
}

// Seeds, in order: A (1, 1) at 2; B (3, 3) at 5; C in the pit (5, 3), terrain level 0;
// D on the island (2, 2) at 7 (below its 8 m); E in the pit again at 0.
// Handled highest first: B (5) fills the bowl floor (8 cells, 162 m^3 as above); A (2) is
// already wet: it joins B, its own body is empty; C and E (0, equal: C first) - C fills the
// pit (1 cell, depth 0), E joins it; D fills nothing (the island stays dry).
TEST(TerroirFloodFillSeeds, SeveralSeedsFromTheHighestLevelDown)
{
  const Grid g = Bowl();
  const SeedResult r = Fill(g,
    { Seed(g, 1, 1, 2.0),
      Seed(g, 3, 3, 5.0),
      Seed(g, 5, 3),
      Seed(g, 2, 2, 7.0),
      Seed(g, 5, 3, 0.0) });
  ExpectIds(g,
    r.id,
    {
      { 0, 0, 0, 0, 0, 0, 0 },
      { 0, 2, 2, 2, 0, 3, 0 },
      { 0, 2, 0, 2, 0, 0, 0 },
      { 0, 2, 2, 2, 0, 0, 0 },
      { 0, 0, 0, 0, 0, 0, 0 },
    });
  ASSERT_EQ(r.bodies.size(), 5u);
  const double levels[5] = { 2.0, 5.0, 0.0, 7.0, 0.0 };
  const std::int64_t cells[5] = { 0, 8, 1, 0, 0 };
  for (int s = 0; s < 5; ++s)
  {
    EXPECT_EQ(r.bodies[s].level, levels[s]) << s;
    EXPECT_EQ(r.bodies[s].cells, cells[s]) << s;
  }
  EXPECT_DOUBLE_EQ(r.bodies[1].volume, 162.0);
  EXPECT_DOUBLE_EQ(r.bodies[2].area, 6.0);
  EXPECT_EQ(r.bodies[2].volume, 0.0);
  EXPECT_EQ(r.bodies[0].area, 0.0);
  EXPECT_EQ(r.bodies[3].maxDepth, 0.0);
  EXPECT_EQ(r.depth[g.Cell(2, 2)], 0.0f);
}

// A corridor of low cells cut by a no-data cell (masked, with a low value under the mask):
// the water stops there; the cell gets id 0 and depth NaN. The same with a NaN elevation and
// no mask. A seed on a no-data cell fills nothing and has no level.
TEST(TerroirFloodFillSeeds, NoDataCellsBlockTheFill)
{
  Grid g(5,
    3,
    1.0,
    1.0,
    {
      { 9, 9, 9, 9, 9 },
      { 1, 1, 0, 1, 1 },
      { 9, 9, 9, 9, 9 },
    });
  g.MaskOut(2, 1);
  const SeedResult r = Fill(g, { Seed(g, 0, 1, 2.0) });
  ExpectIds(g,
    r.id,
    {
      { 0, 0, 0, 0, 0 },
      { 1, 1, 0, 0, 0 },
      { 0, 0, 0, 0, 0 },
    });
  EXPECT_TRUE(std::isnan(r.depth[g.Cell(2, 1)]));
  EXPECT_EQ(r.depth[g.Cell(1, 1)], 1.0f);
  EXPECT_EQ(r.depth[g.Cell(4, 1)], 0.0f);

  Grid h(5,
    3,
    1.0,
    1.0,
    {
      { 9, 9, 9, 9, 9 },
      { 1, 1, kNoData, 1, 1 },
      { 9, 9, 9, 9, 9 },
    });
  const SeedResult s = Fill(h, { Seed(h, 4, 1, 2.0), Seed(h, 2, 1) });
  EXPECT_EQ(s.bodies[0].cells, 2);
  EXPECT_EQ(s.id[h.Cell(3, 1)], 1);
  EXPECT_EQ(s.id[h.Cell(1, 1)], 0);
  EXPECT_TRUE(std::isnan(s.depth[h.Cell(2, 1)]));
  EXPECT_EQ(s.bodies[1].cells, 0);
  EXPECT_TRUE(std::isnan(s.bodies[1].level));
}

// Per-row spacing (geographic grids): a cell of row j covers rowDx[j] * dy.
// 3 x 3 cells at 0 under 1 m of water, rows 1, 2 and 4 m wide, 10 m tall:
// area 3 * (1 + 2 + 4) * 10 = 210 m^2, volume 210 m^3.
TEST(TerroirFloodFillSeeds, AreasUsePerRowSpacing)
{
  Grid g(3, 3, 99.0, 10.0, { { 0, 0, 0 }, { 0, 0, 0 }, { 0, 0, 0 } });
  const double rowDx[3] = { 1.0, 2.0, 4.0 };
  g.view.rowDx = rowDx;
  const SeedResult r = Fill(g, { Seed(g, 1, 1, 1.0) });
  EXPECT_DOUBLE_EQ(r.bodies[0].area, 210.0);
  EXPECT_DOUBLE_EQ(r.bodies[0].volume, 210.0);
}

TEST(TerroirFloodFillSeeds, NoSeedsLeaveEverythingDryAndBadCellsThrow)
{
  const Grid g = Bowl();
  const SeedResult r = Fill(g, {});
  EXPECT_TRUE(r.bodies.empty());
  for (std::size_t k = 0; k < g.z.size(); ++k)
  {
    EXPECT_EQ(r.id[k], 0);
    EXPECT_EQ(r.depth[k], 0.0f);
  }
  hy::FloodSeed outside;
  outside.cell = g.z.size();
  std::vector<std::int32_t> id(g.z.size());
  std::vector<float> depth(g.z.size());
  EXPECT_THROW(hy::FloodFillSeeds(g.view, { outside }, id.data(), depth.data()), std::out_of_range);
}

// ---------------------------------------------------------------------------------------------
// Priority-Flood

namespace
{
std::vector<float> PriorityFlood(const Grid& g, std::size_t* raised = nullptr)
{
  std::vector<float> filled(g.z.size(), -7.0f);
  const std::size_t n = hy::PriorityFloodBarnes2014(g.view, filled.data());
  if (raised)
  {
    *raised = n;
  }
  return filled;
}

bool HasData(const GridView<float>& v, int i, int j)
{
  return v.IsValid(i, j) && !std::isnan(v.At(i, j));
}

/// The filled surface by brute force: W = z on outlets (edge cells and cells next to no data),
/// +inf elsewhere, then W(c) = max(z(c), min of W over the 8 neighbours) until nothing changes.
std::vector<float> BruteForceFill(const GridView<float>& v)
{
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<float> w(v.Size());
  std::vector<bool> outlet(v.Size(), false);
  for (int j = 0; j < v.ny; ++j)
  {
    for (int i = 0; i < v.nx; ++i)
    {
      const std::size_t k = v.Index(i, j);
      if (!HasData(v, i, j))
      {
        w[k] = kNoData;
        continue;
      }
      bool edge = i == 0 || j == 0 || i == v.nx - 1 || j == v.ny - 1;
      for (int dj = -1; dj <= 1 && !edge; ++dj)
      {
        for (int di = -1; di <= 1; ++di)
        {
          edge = edge || !HasData(v, i + di, j + dj);
        }
      }
      outlet[k] = edge;
      w[k] = edge ? v.At(i, j) : inf;
    }
  }
  for (bool changed = true; changed;)
  {
    changed = false;
    for (int j = 1; j < v.ny - 1; ++j)
    {
      for (int i = 1; i < v.nx - 1; ++i)
      {
        const std::size_t k = v.Index(i, j);
        if (outlet[k] || !HasData(v, i, j))
        {
          continue;
        }
        float lowest = inf;
        for (int dj = -1; dj <= 1; ++dj)
        {
          for (int di = -1; di <= 1; ++di)
          {
            if (di != 0 || dj != 0)
            {
              lowest = std::min(lowest, w[v.Index(i + di, j + dj)]);
            }
          }
        }
        const float next = std::max(v.At(i, j), lowest);
        if (next != w[k])
        {
          w[k] = next;
          changed = true;
        }
      }
    }
  }
  return w;
}
} // namespace

// A 3 x 3 pit (3s around a 1) inside a rim of 5 with one edge cell at 4: everything inside
// drains over that cell, so the 9 inner cells are filled to 4.
TEST(TerroirPriorityFlood, PitIsFilledToItsSpillLevel)
{
  const Grid g(5,
    5,
    1.0,
    1.0,
    {
      { 5, 5, 5, 5, 5 },
      { 5, 3, 3, 3, 5 },
      { 5, 3, 1, 3, 4 },
      { 5, 3, 3, 3, 5 },
      { 5, 5, 5, 5, 5 },
    });
  std::size_t raised = 0;
  const std::vector<float> w = PriorityFlood(g, &raised);
  EXPECT_EQ(raised, 9u);
  for (int j = 0; j < 5; ++j)
  {
    for (int i = 0; i < 5; ++i)
    {
      const bool inner = i >= 1 && i <= 3 && j >= 1 && j <= 3;
      EXPECT_EQ(w[g.Cell(i, j)], inner ? 4.0f : g.z[g.Cell(i, j)]) << i << ", " << j;
    }
  }
}

// The cells around a no-data cell are outlets (water leaves the known terrain there), so a
// ring of 1s around a hole inside a rim of 5 is not filled; the hole stays NaN.
TEST(TerroirPriorityFlood, CellsNextToNoDataAreOutlets)
{
  Grid g(5,
    5,
    1.0,
    1.0,
    {
      { 5, 5, 5, 5, 5 },
      { 5, 1, 1, 1, 5 },
      { 5, 1, 0, 1, 5 },
      { 5, 1, 1, 1, 5 },
      { 5, 5, 5, 5, 5 },
    });
  g.MaskOut(2, 2);
  std::size_t raised = 0;
  const std::vector<float> w = PriorityFlood(g, &raised);
  EXPECT_EQ(raised, 0u);
  EXPECT_TRUE(std::isnan(w[g.Cell(2, 2)]));
  EXPECT_EQ(w[g.Cell(1, 1)], 1.0f);
  EXPECT_EQ(w[g.Cell(0, 0)], 5.0f);
}

// 50 random terrains (fixed seed, our own value mapping), half with heights in whole metres
// (many ties and flats), half continuous, some with no-data cells (masked or NaN): the filled
// surface equals the brute-force fixed point exactly.
TEST(TerroirPriorityFlood, EqualsBruteForceOnRandomTerrains)
{
  std::mt19937_64 rng(20140417);
  auto below = [&rng](std::uint64_t n) { return static_cast<int>((rng() >> 16) % n); };
  int withNoData = 0;
  for (int t = 0; t < 50; ++t)
  {
    const int nx = 1 + below(14);
    const int ny = 1 + below(14);
    const bool quantised = t % 2 == 0;
    const int noDataPerMille = t % 3 == 0 ? 80 : 0;
    std::vector<std::vector<float>> rows(ny, std::vector<float>(nx));
    std::vector<std::pair<int, int>> masked;
    for (int r = 0; r < ny; ++r)
    {
      for (int i = 0; i < nx; ++i)
      {
        const double u = static_cast<double>(rng() >> 11) / 9007199254740992.0; // [0, 1)
        float z = quantised ? static_cast<float>(std::floor(u * 12.0))
                            : static_cast<float>(100.0 + 25.0 * u);
        if (below(1000) < noDataPerMille)
        {
          if (below(2) == 0)
          {
            z = kNoData;
          }
          else
          {
            masked.emplace_back(i, ny - 1 - r);
          }
        }
        rows[r][i] = z;
      }
    }
    Grid g(nx, ny, 1.0, 1.0, rows);
    for (const auto& [i, j] : masked)
    {
      g.MaskOut(i, j);
    }
    bool anyNoData = !masked.empty();
    for (const float z : g.z)
    {
      anyNoData = anyNoData || std::isnan(z);
    }
    withNoData += anyNoData ? 1 : 0;
    const std::vector<float> expected = BruteForceFill(g.view);
    const std::vector<float> got = PriorityFlood(g);
    for (std::size_t k = 0; k < expected.size(); ++k)
    {
      if (std::isnan(expected[k]))
      {
        EXPECT_TRUE(std::isnan(got[k])) << "terrain " << t << " cell " << k;
      }
      else
      {
        EXPECT_EQ(got[k], expected[k]) << "terrain " << t << " cell " << k;
      }
    }
  }
  EXPECT_GT(withNoData, 5);
}

// ---------------------------------------------------------------------------------------------
// Water bodies of the filled surface

namespace
{
SeedResult Bodies(const Grid& g, double minimumArea, bool includeFlatSurfaces)
{
  const std::vector<float> filled = PriorityFlood(g);
  hy::DepressionWaterBodyOptions options;
  options.minimumArea = minimumArea;
  options.includeFlatSurfaces = includeFlatSurfaces;
  SeedResult r;
  r.id.assign(g.z.size(), -7);
  r.depth.assign(g.z.size(), -7.0f);
  r.bodies = hy::DepressionWaterBodies(g.view, filled.data(), options, r.id.data(), r.depth.data());
  return r;
}

/// Walls of distinct heights (no two neighbours equal, so no flat) from 10 m up.
float Wall(int i, int j)
{
  return 10.0f + 0.125f * static_cast<float>(i + 7 * j);
}
} // namespace

// A closed pit: walls all around except a channel (3, 2), (4, 2) at 5 m leaving over the east
// edge, through which a 2 x 2 floor (1, 2 / 3, 4) drains. Filled to 5: the floor and the two
// channel cells form a flat at 5 of 6 cells (10 m x 20 m = 200 m^2 each: 1200 m^2); depths
// 4, 3, 2, 1, 0, 0 (sum 10), volume 10 * 200 = 2000 m^3, max depth 4. Kept at MinimumArea 1200
// (inclusive) with or without includeFlatSurfaces, dropped at 1200.5.
TEST(TerroirDepressionWaterBodies, ClosedPitIsFilledToItsOutlet)
{
  std::vector<std::vector<float>> rows(4, std::vector<float>(5));
  for (int r = 0; r < 4; ++r)
  {
    for (int i = 0; i < 5; ++i)
    {
      rows[r][i] = Wall(i, 3 - r);
    }
  }
  rows[1][1] = 1; // (1, 2)
  rows[1][2] = 2; // (2, 2)
  rows[2][1] = 3; // (1, 1)
  rows[2][2] = 4; // (2, 1)
  rows[1][3] = 5; // (3, 2)
  rows[1][4] = 5; // (4, 2): the outlet on the east edge
  const Grid g(5, 4, 10.0, 20.0, rows);
  for (bool flats : { true, false })
  {
    const SeedResult r = Bodies(g, 1200.0, flats);
    ASSERT_EQ(r.bodies.size(), 1u) << flats;
    EXPECT_EQ(r.bodies[0].level, 5.0);
    EXPECT_EQ(r.bodies[0].cells, 6);
    EXPECT_DOUBLE_EQ(r.bodies[0].area, 1200.0);
    EXPECT_DOUBLE_EQ(r.bodies[0].volume, 2000.0);
    EXPECT_DOUBLE_EQ(r.bodies[0].maxDepth, 4.0);
    EXPECT_EQ(r.depth[g.Cell(1, 2)], 4.0f);
    EXPECT_EQ(r.depth[g.Cell(2, 1)], 1.0f);
    EXPECT_EQ(r.depth[g.Cell(4, 2)], 0.0f);
    EXPECT_EQ(r.id[g.Cell(4, 2)], 1);
    EXPECT_EQ(r.id[g.Cell(0, 0)], 0);
    EXPECT_EQ(r.depth[g.Cell(0, 0)], 0.0f);
  }
  EXPECT_TRUE(Bodies(g, 1200.5, true).bodies.empty());
}

// A hydro-flattened lake: a 4 x 3 flat at exactly 5 m whose outlet channel cell (4 m) is on the
// east edge; nothing is filled (the channel is lower). One more cell, masked out, lies inside
// the lake. The flat (11 cells of 50 m^2 = 550 m^2) is a water body only with
// includeFlatSurfaces and a MinimumArea up to 550; depth 0 everywhere, volume 0.
TEST(TerroirDepressionWaterBodies, FlatAtTheOutletLevelIsALakeOnlyWithFlatSurfaces)
{
  std::vector<std::vector<float>> rows(5, std::vector<float>(7));
  for (int r = 0; r < 5; ++r)
  {
    for (int i = 0; i < 7; ++i)
    {
      const int j = 4 - r;
      rows[r][i] = (i >= 1 && i <= 4 && j >= 1 && j <= 3) ? 5.0f : Wall(i, j);
    }
  }
  rows[2][5] = 4.5f; // (5, 2)
  rows[2][6] = 4.0f; // (6, 2): channel leaving over the east edge
  Grid g(7, 5, 5.0, 10.0, rows);
  g.MaskOut(2, 2);

  const SeedResult lake = Bodies(g, 550.0, true);
  ASSERT_EQ(lake.bodies.size(), 1u);
  EXPECT_EQ(lake.bodies[0].level, 5.0);
  EXPECT_EQ(lake.bodies[0].cells, 11);
  EXPECT_DOUBLE_EQ(lake.bodies[0].area, 550.0);
  EXPECT_EQ(lake.bodies[0].volume, 0.0);
  EXPECT_EQ(lake.bodies[0].maxDepth, 0.0);
  EXPECT_EQ(lake.id[g.Cell(1, 1)], 1);
  EXPECT_EQ(lake.id[g.Cell(4, 3)], 1);
  EXPECT_EQ(lake.id[g.Cell(2, 2)], 0);
  EXPECT_TRUE(std::isnan(lake.depth[g.Cell(2, 2)]));
  EXPECT_EQ(lake.id[g.Cell(5, 2)], 0);
  EXPECT_EQ(lake.depth[g.Cell(1, 1)], 0.0f);

  EXPECT_TRUE(Bodies(g, 550.0, false).bodies.empty());
  EXPECT_TRUE(Bodies(g, 551.0, true).bodies.empty());
}

// Two filled pits, 4 x 5 m cells (20 m^2). South: (4, 1) at 3 spills over (5, 1) and (6, 1) at 4
// (east edge): a flat at 4 of 3 cells, 60 m^2, depth 1 at the pit, volume 20 m^3. North: a
// 3 x 3 pit (2 around a 1) spills over a channel (4, 4), (5, 4), (6, 4) at 6: a flat at 6 of
// 12 cells, 240 m^2, depths 4 x 8 and 5, volume 37 * 20 = 740 m^3. Ids follow the first cell in
// row-major order (south first): the south pit is 1. MinimumArea 100 drops it and renumbers the
// north pit as 1; lone cells never form a flat, even at MinimumArea 0.
TEST(TerroirDepressionWaterBodies, MinimumAreaDropsSmallBodiesAndIdsFollowRowMajorOrder)
{
  std::vector<std::vector<float>> rows(7, std::vector<float>(7));
  for (int r = 0; r < 7; ++r)
  {
    for (int i = 0; i < 7; ++i)
    {
      rows[r][i] = Wall(i, 6 - r);
    }
  }
  auto set = [&rows](int i, int j, float z) { rows[6 - j][i] = z; };
  for (int j = 3; j <= 5; ++j)
  {
    for (int i = 1; i <= 3; ++i)
    {
      set(i, j, 2.0f);
    }
  }
  set(2, 4, 1.0f);
  set(4, 4, 6.0f);
  set(5, 4, 6.0f);
  set(6, 4, 6.0f);
  set(4, 1, 3.0f);
  set(5, 1, 4.0f);
  set(6, 1, 4.0f);
  const Grid g(7, 7, 4.0, 5.0, rows);

  for (double minimumArea : { 0.0, 60.0 })
  {
    const SeedResult r = Bodies(g, minimumArea, true);
    ASSERT_EQ(r.bodies.size(), 2u) << minimumArea;
    EXPECT_EQ(r.bodies[0].level, 4.0);
    EXPECT_EQ(r.bodies[0].cells, 3);
    EXPECT_DOUBLE_EQ(r.bodies[0].area, 60.0);
    EXPECT_DOUBLE_EQ(r.bodies[0].volume, 20.0);
    EXPECT_DOUBLE_EQ(r.bodies[0].maxDepth, 1.0);
    EXPECT_EQ(r.bodies[1].level, 6.0);
    EXPECT_EQ(r.bodies[1].cells, 12);
    EXPECT_DOUBLE_EQ(r.bodies[1].area, 240.0);
    EXPECT_DOUBLE_EQ(r.bodies[1].volume, 740.0);
    EXPECT_DOUBLE_EQ(r.bodies[1].maxDepth, 5.0);
    EXPECT_EQ(r.id[g.Cell(4, 1)], 1);
    EXPECT_EQ(r.id[g.Cell(6, 1)], 1);
    EXPECT_EQ(r.id[g.Cell(2, 4)], 2);
    EXPECT_EQ(r.id[g.Cell(6, 4)], 2);
    EXPECT_EQ(r.depth[g.Cell(2, 4)], 5.0f);
    EXPECT_EQ(r.depth[g.Cell(1, 3)], 4.0f);
  }
  const SeedResult big = Bodies(g, 100.0, true);
  ASSERT_EQ(big.bodies.size(), 1u);
  EXPECT_EQ(big.bodies[0].cells, 12);
  EXPECT_EQ(big.id[g.Cell(2, 4)], 1);
  EXPECT_EQ(big.id[g.Cell(4, 1)], 0);
  EXPECT_EQ(big.depth[g.Cell(4, 1)], 0.0f);
  EXPECT_TRUE(Bodies(g, 240.5, true).bodies.empty());
}

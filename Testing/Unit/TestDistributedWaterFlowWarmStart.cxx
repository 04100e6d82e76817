// Unit tests of terroir::hydrology::WaterFlowWarmStartDistributed (the water flow's
// coarse-to-fine warm start on a grid split into tiles) and WaterFlowWarmStartFitsTiles.
// Threads stand in for MPI processes; each holds only a copy of its tile and the ring around
// it. The answer is the serial WaterFlowWarmStart on the whole grid (itself checked by hand in
// TestWaterFlowWarmStart.cxx): every held cell within a tile's reach must get the serial
// initial water bit for bit, and every tile the serial levels (sizes, iterations, reasons).
// Each level's run reads the same values in the same order on every tile as in the serial run
// (the ring refreshed from its owners after every iteration), so the bits agree; the sums of
// an iteration are added in another order, which could move a stop by one iteration only on
// an exact tie of the balance rule (none here: the levels' counts are compared).
#include "DistributedWaterFlowWarmStart.h"
#include "PriorityFlood.h"
#include "TerroirThreadTiles.h"
#include "WaterFlowWarmStart.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace
{
namespace hy = terroir::hydrology;
using terroir::GridView;
using terroir_test::RunOnThreads;
using terroir_test::ThreadExchange;

/// A whole grid: a valley running north with bumps (pits that the fill floods), no-data cells
/// (NaN heights and masked cells), per-row spacing (and optionally per-row north-south
/// spacing), and a rain field.
struct Grid
{
  int nx = 0;
  int ny = 0;
  std::vector<float> z;
  std::vector<std::uint8_t> valid;
  std::vector<double> rowDx, rowDy, rain;
  bool geographicDy = false;
  bool rows = true; ///< false: one spacing for every row (no rowDx)

  GridView<float> View() const
  {
    GridView<float> v;
    v.data = z.data();
    v.nx = nx;
    v.ny = ny;
    v.dx = 30.0;
    v.dy = 30.0;
    v.rowDx = rows ? rowDx.data() : nullptr;
    v.rowDy = geographicDy ? rowDy.data() : nullptr;
    v.valid = valid.data();
    return v;
  }
  std::size_t Index(int i, int j) const { return static_cast<std::size_t>(j) * nx + i; }
};

double Uniform(std::mt19937_64& rng)
{
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

Grid MakeGrid(std::mt19937_64& rng, int nx, int ny, bool geographicDy)
{
  Grid g;
  g.nx = nx;
  g.ny = ny;
  g.geographicDy = geographicDy;
  for (int j = 0; j < ny; ++j)
  {
    g.rowDx.push_back(30.0 - 0.05 * j); // a geographic grid's narrowing rows
    g.rowDy.push_back(30.0 + 0.01 * j);
    for (int i = 0; i < nx; ++i)
    {
      const double thalweg = 0.4 * nx + 0.15 * nx * std::sin(0.1 * j);
      float z = static_cast<float>(0.5 * std::abs(i - thalweg) + 0.2 * j + 2.0 * Uniform(rng));
      std::uint8_t ok = 1;
      const int roll = static_cast<int>(rng() % 1000);
      if (roll < 8)
      {
        z = std::numeric_limits<float>::quiet_NaN();
      }
      else if (roll < 16)
      {
        ok = 0;
      }
      g.z.push_back(z);
      g.valid.push_back(ok);
      g.rain.push_back(1e-3 * (0.5 + Uniform(rng)));
    }
  }
  return g;
}

/// The still water of the whole grid (the Priority-Flood fill's depth, 0 on no data), as the
/// serial warm start's StillWater.
std::vector<double> StillWater(const Grid& g)
{
  const GridView<float> v = g.View();
  std::vector<float> filled(v.Size());
  hy::PriorityFloodBarnes2014(v, filled.data());
  std::vector<double> still(v.Size(), 0.0);
  for (std::size_t c = 0; c < still.size(); ++c)
  {
    if (g.valid[c] && std::isfinite(g.z[c]))
    {
      still[c] = std::max(0.0, static_cast<double>(filled[c]) - static_cast<double>(g.z[c]));
    }
  }
  return still;
}

hy::WaterFlowWarmStartOptions Options(int coarsestSide)
{
  hy::WaterFlowWarmStartOptions o;
  o.coarsestSide = coarsestSide;
  o.settleIterations = 15;
  o.rule.autoStopRatio = 0.0; // as the filter's river mode
  o.rule.balanceTolerance = 0.05;
  o.rule.maximumIterations = 250;
  return o;
}

/// What a runner saw of one level: its size and rule.
struct Seen
{
  int nx; ///< the simulated grid's (the held box's on a tile)
  int ny;
  long long balanceAfter;
  long long maximumIterations;
};

/// The serial answer: the initial water and the levels.
struct Serial
{
  std::vector<double> water;
  std::vector<hy::WaterFlowWarmStartLevel> levels;
  std::vector<Seen> seen;
};

Serial RunSerial(const Grid& g, bool rainField, const hy::WaterFlowWarmStartOptions& o)
{
  Serial s;
  s.water = StillWater(g);
  const hy::WaterFlowLevelRun run = [&](
                                      hy::WaterFlowSimulation& sim, const hy::WaterFlowStopRule& r)
  {
    s.seen.push_back(Seen{ sim.Nx(), sim.Ny(), r.balanceAfter, r.maximumIterations });
    return sim.Run(r);
  };
  s.levels = hy::WaterFlowWarmStart(
    g.View(), s.water.data(), 2e-3, rainField ? g.rain.data() : nullptr, o, run);
  return s;
}

/// One tile's copy of the grid: its box grown by `halo`, with the still water on the cells
/// within `reach` of the owned box and NaN beyond (the caller gives no more).
struct Copy
{
  hy::TileBox box;
  Grid g;
  std::vector<double> water;
};

Copy CopyOf(const Grid& w, const hy::TileBox& owned, int reach, int halo)
{
  Copy c;
  c.box = terroir::hydrology::TileBox{ std::max(0, owned.i0 - halo),
    std::min(w.nx - 1, owned.i1 + halo),
    std::max(0, owned.j0 - halo),
    std::min(w.ny - 1, owned.j1 + halo) };
  const std::vector<double> still = StillWater(w);
  const hy::TileBox near{ owned.i0 - reach, owned.i1 + reach, owned.j0 - reach, owned.j1 + reach };
  c.g.nx = c.box.i1 - c.box.i0 + 1;
  c.g.ny = c.box.j1 - c.box.j0 + 1;
  c.g.geographicDy = w.geographicDy;
  c.g.rows = w.rows;
  for (int j = c.box.j0; j <= c.box.j1; ++j)
  {
    c.g.rowDx.push_back(w.rowDx[j]);
    c.g.rowDy.push_back(w.rowDy[j]);
    for (int i = c.box.i0; i <= c.box.i1; ++i)
    {
      const std::size_t k = w.Index(i, j);
      c.g.z.push_back(w.z[k]);
      c.g.valid.push_back(w.valid[k]);
      c.g.rain.push_back(w.rain[k]);
      c.water.push_back(near.Contains(i, j) ? still[k] : std::nan(""));
    }
  }
  return c;
}

/// How the grid is cut and what each tile holds.
struct Split
{
  std::vector<hy::TileBox> owned;
  std::vector<int> reach;
  int extraHalo = 0; ///< cells held beyond reach + 1
};

/// px x py uneven tiles (random cuts) that keep every level non-empty.
std::vector<hy::TileBox> UnevenTiles(std::mt19937_64& rng,
  int nx,
  int ny,
  int px,
  int py,
  const hy::WaterFlowWarmStartOptions& o)
{
  for (int attempt = 0; attempt < 1000; ++attempt)
  {
    const std::vector<int> ci = terroir_test::Cuts(rng, nx, px);
    const std::vector<int> cj = terroir_test::Cuts(rng, ny, py);
    const std::vector<hy::TileBox> boxes = terroir_test::Blocks(ci, cj);
    if (static_cast<int>(boxes.size()) == px * py &&
      hy::WaterFlowWarmStartFitsTiles(boxes, nx, ny, o))
    {
      return boxes;
    }
  }
  ADD_FAILURE() << "no uneven split of " << nx << " x " << ny << " into " << px << " x " << py;
  return {};
}

/// Each tile's result.
struct Outcome
{
  std::vector<Copy> copies;
  std::vector<std::vector<hy::WaterFlowWarmStartLevel>> levels;
  std::vector<std::vector<Seen>> seen;
  std::vector<std::string> errors;
};

Outcome RunTiles(const Grid& w,
  const Split& split,
  bool rainField,
  const hy::WaterFlowWarmStartOptions& o,
  bool refresh = true)
{
  const int ranks = static_cast<int>(split.owned.size());
  Outcome out;
  for (int r = 0; r < ranks; ++r)
  {
    out.copies.push_back(
      CopyOf(w, split.owned[r], split.reach[r], split.reach[r] + 1 + split.extraHalo));
  }
  out.levels.resize(ranks);
  out.seen.resize(ranks);
  out.errors = RunOnThreads(ranks,
    [&](int r, ThreadExchange& exchange)
    {
      Copy& c = out.copies[r];
      hy::WaterFlowWarmStartTile tile;
      tile.view = c.g.View();
      tile.gi0 = c.box.i0;
      tile.gj0 = c.box.j0;
      tile.owned = split.owned;
      tile.reach = split.reach;
      tile.wholeNx = w.nx;
      tile.wholeNy = w.ny;
      const hy::WaterFlowLevelRun run =
        [&, r](hy::WaterFlowSimulation& sim, const hy::WaterFlowStopRule& rule)
      {
        out.seen[r].push_back(
          Seen{ sim.Nx(), sim.Ny(), rule.balanceAfter, rule.maximumIterations });
        if (!refresh)
        {
          // The control: a hook that only adds the tiles' sums (rank order), no ring refresh.
          sim.SetIterationHook(
            [&exchange](hy::WaterFlowSimulation&, hy::WaterFlowIteration& it)
            {
              std::vector<char> mine(sizeof(double) * 3);
              std::memcpy(mine.data(), &it.moved, sizeof(double));
              std::memcpy(mine.data() + 8, &it.outflow, sizeof(double));
              std::memcpy(mine.data() + 16, &it.emptied, sizeof(double));
              const std::vector<std::vector<char>> all = exchange.Gather(mine);
              std::vector<std::vector<char>> parts;
              if (exchange.Rank() == 0)
              {
                double sums[3] = { 0.0, 0.0, 0.0 };
                for (const std::vector<char>& a : all)
                {
                  for (int e = 0; e < 3; ++e)
                  {
                    double v = 0.0;
                    std::memcpy(&v, a.data() + 8 * e, sizeof(double));
                    sums[e] += v;
                  }
                }
                std::vector<char> total(sizeof(sums));
                std::memcpy(total.data(), sums, sizeof(sums));
                parts.assign(all.size(), total);
              }
              const std::vector<char> total = exchange.Scatter(parts);
              std::memcpy(&it.moved, total.data(), sizeof(double));
              std::memcpy(&it.outflow, total.data() + 8, sizeof(double));
              std::memcpy(&it.emptied, total.data() + 16, sizeof(double));
            });
        }
        return sim.Run(rule);
      };
      out.levels[r] = hy::WaterFlowWarmStartDistributed(
        tile, c.water.data(), 2e-3, rainField ? c.g.rain.data() : nullptr, o, exchange, run);
    });
  return out;
}

/// Bits equal (NaN with NaN).
bool SameBits(double a, double b)
{
  return std::memcmp(&a, &b, sizeof(double)) == 0;
}

/// Cells within reach of their tile whose water differs from the serial run's.
int Differences(const Grid& w, const Split& split, const Outcome& out, const Serial& s)
{
  int wrong = 0;
  for (std::size_t r = 0; r < split.owned.size(); ++r)
  {
    const hy::TileBox& o = split.owned[r];
    const int reach = split.reach[r];
    const Copy& c = out.copies[r];
    for (int j = std::max(0, o.j0 - reach); j <= std::min(w.ny - 1, o.j1 + reach); ++j)
    {
      for (int i = std::max(0, o.i0 - reach); i <= std::min(w.nx - 1, o.i1 + reach); ++i)
      {
        const double got =
          c.water[static_cast<std::size_t>(j - c.box.j0) * c.g.nx + (i - c.box.i0)];
        wrong += SameBits(got, s.water[w.Index(i, j)]) ? 0 : 1;
      }
    }
  }
  return wrong;
}

/// The box a tile's run of the level `down` levels below the grid holds: the coarse cells
/// whose fine cell (2i, 2j) the tile owns (found by search), grown by the level's reach + 1.
hy::TileBox ExpectedHeld(hy::TileBox owned, int reach, int nx, int ny, int down)
{
  for (int l = 0; l < down; ++l)
  {
    nx = (nx + 1) / 2;
    ny = (ny + 1) / 2;
    hy::TileBox c{ nx, -1, ny, -1 };
    for (int i = 0; i < nx; ++i)
    {
      if (owned.i0 <= 2 * i && 2 * i <= owned.i1)
      {
        c.i0 = std::min(c.i0, i);
        c.i1 = std::max(c.i1, i);
      }
    }
    for (int j = 0; j < ny; ++j)
    {
      if (owned.j0 <= 2 * j && 2 * j <= owned.j1)
      {
        c.j0 = std::min(c.j0, j);
        c.j1 = std::max(c.j1, j);
      }
    }
    owned = c;
    reach = std::max(2, reach / 2 + 1);
  }
  return hy::TileBox{ std::max(0, owned.i0 - reach - 1),
    std::min(nx - 1, owned.i1 + reach + 1),
    std::max(0, owned.j0 - reach - 1),
    std::min(ny - 1, owned.j1 + reach + 1) };
}

void ExpectSerial(const Grid& w,
  const Split& split,
  bool rainField,
  const hy::WaterFlowWarmStartOptions& o,
  const std::string& what)
{
  const Serial s = RunSerial(w, rainField, o);
  ASSERT_FALSE(s.levels.empty()) << what;
  const Outcome out = RunTiles(w, split, rainField, o);
  for (std::size_t r = 0; r < split.owned.size(); ++r)
  {
    ASSERT_EQ(out.errors[r], "") << what << " rank " << r;
    ASSERT_EQ(out.levels[r].size(), s.levels.size()) << what << " rank " << r;
    for (std::size_t l = 0; l < s.levels.size(); ++l)
    {
      EXPECT_EQ(out.levels[r][l].nx, s.levels[l].nx) << what << " level " << l;
      EXPECT_EQ(out.levels[r][l].ny, s.levels[l].ny) << what << " level " << l;
      EXPECT_EQ(out.levels[r][l].iterations, s.levels[l].iterations) << what << " level " << l;
      EXPECT_EQ(out.levels[r][l].reason, s.levels[l].reason) << what << " level " << l;
      EXPECT_EQ(out.seen[r][l].balanceAfter, s.seen[l].balanceAfter) << what << " level " << l;
      EXPECT_EQ(out.seen[r][l].maximumIterations, s.seen[l].maximumIterations) << what;
      // Each tile holds its own part of the level, not the level.
      const hy::TileBox held = ExpectedHeld(
        split.owned[r], split.reach[r], w.nx, w.ny, static_cast<int>(s.levels.size() - l));
      EXPECT_EQ(out.seen[r][l].nx, held.i1 - held.i0 + 1) << what << " level " << l;
      EXPECT_EQ(out.seen[r][l].ny, held.j1 - held.j0 + 1) << what << " level " << l;
    }
  }
  EXPECT_EQ(Differences(w, split, out, s), 0) << what;
}

Split Even(const std::vector<hy::TileBox>& owned, int reach, int extraHalo = 0)
{
  return Split{ owned, std::vector<int>(owned.size(), reach), extraHalo };
}
} // namespace

TEST(TerroirDistributedWarmStart, UniformRainEqualsSerialOnOneToSixTiles)
{
  std::mt19937_64 rng(2519);
  const Grid w = MakeGrid(rng, 97, 83, false);
  const hy::WaterFlowWarmStartOptions o = Options(10); // levels 49 x 42, 25 x 21, 13 x 11
  const Serial s = RunSerial(w, false, o);
  ASSERT_EQ(s.levels.size(), 3u);
  EXPECT_EQ(s.levels[0].nx, 13);
  EXPECT_EQ(s.levels[0].ny, 11);
  bool balanced = false;
  for (const hy::WaterFlowWarmStartLevel& l : s.levels)
  {
    balanced = balanced || l.reason == hy::WaterFlowStopReason::Balanced;
  }
  EXPECT_TRUE(balanced) << "no level reached the balance: the test would not see the sums";
  for (const auto& p : { std::pair<int, int>{ 1, 1 }, { 2, 1 }, { 2, 2 }, { 3, 2 } })
  {
    const Split split = Even(UnevenTiles(rng, w.nx, w.ny, p.first, p.second, o), 2);
    ExpectSerial(w, split, false, o, std::to_string(p.first * p.second) + " tiles");
  }
}

TEST(TerroirDistributedWarmStart, RainFieldGeographicRowsAndWideReachesEqualSerial)
{
  std::mt19937_64 rng(77);
  const Grid w = MakeGrid(rng, 75, 64, true);
  const hy::WaterFlowWarmStartOptions o = Options(8); // levels 38 x 32, 19 x 16, 10 x 8
  for (const auto& p : { std::pair<int, int>{ 2, 2 }, { 2, 3 } })
  {
    Split split;
    split.owned = UnevenTiles(rng, w.nx, w.ny, p.first, p.second, o);
    for (std::size_t r = 0; r < split.owned.size(); ++r)
    {
      split.reach.push_back(3 + static_cast<int>(r % 4)); // 3, 4, 5, 6: each parity
    }
    split.extraHalo = 2; // the tiles hold more than they need
    ExpectSerial(w, split, true, o, std::to_string(split.owned.size()) + " tiles, rain field");
  }
  // A larger grid in six tiles, reaches 2 to 5.
  const Grid big = MakeGrid(rng, 151, 131, true);
  const hy::WaterFlowWarmStartOptions o16 = Options(16); // levels 76 x 66, 38 x 33, 19 x 17
  Split split;
  split.owned = UnevenTiles(rng, big.nx, big.ny, 3, 2, o16);
  for (std::size_t r = 0; r < split.owned.size(); ++r)
  {
    split.reach.push_back(2 + static_cast<int>(r % 4));
  }
  ExpectSerial(big, split, true, o16, "151 x 131 in six tiles, rain field");
}

TEST(TerroirDistributedWarmStart, OneSpacingForEveryRowEqualsSerial)
{
  // No spacing per row: the coarse levels have none either (dx and dy doubled).
  std::mt19937_64 rng(31);
  Grid w = MakeGrid(rng, 60, 61, false);
  w.rows = false;
  const hy::WaterFlowWarmStartOptions o = Options(8); // levels 30 x 31, 15 x 16, 8 x 8
  const Split split = Even(UnevenTiles(rng, w.nx, w.ny, 2, 2, o), 2);
  ExpectSerial(w, split, false, o, "one spacing");
}

TEST(TerroirDistributedWarmStart, OneLevelAndNoLevelEqualSerial)
{
  std::mt19937_64 rng(5);
  const Grid w = MakeGrid(rng, 33, 20, false);
  const hy::WaterFlowWarmStartOptions o = Options(8); // 17 x 10, then 9 x 5 is too small
  const Split split = Even(UnevenTiles(rng, w.nx, w.ny, 3, 1, o), 2);
  ExpectSerial(w, split, true, o, "one level");
  const Serial s = RunSerial(w, false, o);
  EXPECT_EQ(s.levels.size(), 1u);

  // No level (coarsest side 11 > 10): the water comes back as given, on every tile.
  const hy::WaterFlowWarmStartOptions none = Options(11);
  const Outcome out = RunTiles(w, split, false, none);
  const std::vector<double> still = StillWater(w);
  for (std::size_t r = 0; r < split.owned.size(); ++r)
  {
    EXPECT_EQ(out.errors[r], "");
    EXPECT_TRUE(out.levels[r].empty());
  }
  Serial unchanged;
  unchanged.water = still;
  EXPECT_EQ(Differences(w, split, out, unchanged), 0);
}

TEST(TerroirDistributedWarmStart, WithoutTheRingRefreshTheTilesDiffer)
{
  // The control: the same tiles whose runs only add the sums (their rings keep the water they
  // started with). Water crosses the tiles' edges, so some cell within reach must differ.
  std::mt19937_64 rng(2519);
  const Grid w = MakeGrid(rng, 97, 83, false);
  const hy::WaterFlowWarmStartOptions o = Options(10);
  const Split split = Even(UnevenTiles(rng, w.nx, w.ny, 2, 2, o), 2);
  const Serial s = RunSerial(w, false, o);
  const Outcome wrong = RunTiles(w, split, false, o, false);
  for (std::size_t r = 0; r < split.owned.size(); ++r)
  {
    ASSERT_EQ(wrong.errors[r], "");
  }
  EXPECT_GT(Differences(w, split, wrong, s), 100);
  const Outcome right = RunTiles(w, split, false, o, true);
  EXPECT_EQ(Differences(w, split, right, s), 0);
}

TEST(TerroirDistributedWarmStart, FitsTilesByHand)
{
  // 40 x 40 with coarsest side 10: levels of 20 and 10 cells a side (5 < 10 ends them).
  // Coarse cell i belongs to the owner of fine cell 2i: columns [a, b] become
  // [ceil(a / 2), floor(b / 2)].
  const hy::WaterFlowWarmStartOptions o = Options(10);
  const auto columns = [](std::vector<std::pair<int, int>> c)
  {
    std::vector<hy::TileBox> boxes;
    for (const auto& p : c)
    {
      boxes.push_back(hy::TileBox{ p.first, p.second, 0, 39 });
    }
    return boxes;
  };
  EXPECT_TRUE(hy::WaterFlowWarmStartFitsTiles(columns({ { 0, 19 }, { 20, 39 } }), 40, 40, o));
  // [0, 0] keeps coarse column 0 on both levels.
  EXPECT_TRUE(hy::WaterFlowWarmStartFitsTiles(columns({ { 0, 0 }, { 1, 39 } }), 40, 40, o));
  // [1, 1]: ceil(1/2) = 1 > floor(1/2) = 0, empty on the first level.
  EXPECT_FALSE(
    hy::WaterFlowWarmStartFitsTiles(columns({ { 0, 0 }, { 1, 1 }, { 2, 39 } }), 40, 40, o));
  // [2, 3] -> [1, 1] on level 1 -> empty on level 2; with one level only (side 20) it fits.
  const std::vector<hy::TileBox> late = columns({ { 0, 1 }, { 2, 3 }, { 4, 39 } });
  EXPECT_FALSE(hy::WaterFlowWarmStartFitsTiles(late, 40, 40, o));
  EXPECT_TRUE(hy::WaterFlowWarmStartFitsTiles(late, 40, 40, Options(20)));
  // [3, 5] -> [2, 2] -> [1, 1]: fits.
  EXPECT_TRUE(
    hy::WaterFlowWarmStartFitsTiles(columns({ { 0, 2 }, { 3, 5 }, { 6, 39 } }), 40, 40, o));
  // Rows too: a 40 x 40 grid cut at row 2 into [0, 1] and [2, 39]: [0, 0] then [0, 0].
  EXPECT_TRUE(hy::WaterFlowWarmStartFitsTiles(
    { hy::TileBox{ 0, 39, 0, 1 }, hy::TileBox{ 0, 39, 2, 39 } }, 40, 40, o));
  EXPECT_FALSE(hy::WaterFlowWarmStartFitsTiles(
    { hy::TileBox{ 0, 39, 0, 0 }, hy::TileBox{ 0, 39, 1, 1 }, hy::TileBox{ 0, 39, 2, 39 } },
    40,
    40,
    o));
  // No level at all (side 21 > 20): nothing to keep.
  EXPECT_TRUE(hy::WaterFlowWarmStartFitsTiles(
    columns({ { 0, 0 }, { 1, 1 }, { 2, 39 } }), 40, 40, Options(21)));
  EXPECT_THROW(hy::WaterFlowWarmStartFitsTiles(columns({ { 0, 39 } }), 40, 40, Options(1)),
    std::invalid_argument);
}

namespace
{
/// Runs the tiles and expects the same std::invalid_argument on every rank, naming `words`.
void ExpectFailsEverywhere(const Grid& w,
  const Split& split,
  const std::vector<bool>& rainField,
  const hy::WaterFlowWarmStartOptions& o,
  const std::string& words,
  const std::vector<int>& holdReach = {})
{
  const int ranks = static_cast<int>(split.owned.size());
  std::vector<Copy> copies;
  for (int r = 0; r < ranks; ++r)
  {
    const int hold = holdReach.empty() ? split.reach[r] + 1 : holdReach[r];
    copies.push_back(CopyOf(w, split.owned[r], split.reach[r], std::max(0, hold)));
  }
  std::vector<int> invalid(ranks, 0);
  const std::vector<std::string> errors = RunOnThreads(ranks,
    [&](int r, ThreadExchange& exchange)
    {
      hy::WaterFlowWarmStartTile tile;
      tile.view = copies[r].g.View();
      tile.gi0 = copies[r].box.i0;
      tile.gj0 = copies[r].box.j0;
      tile.owned = split.owned;
      tile.reach = split.reach;
      tile.wholeNx = w.nx;
      tile.wholeNy = w.ny;
      try
      {
        hy::WaterFlowWarmStartDistributed(tile,
          copies[r].water.data(),
          2e-3,
          rainField[r] ? copies[r].g.rain.data() : nullptr,
          o,
          exchange);
      }
      catch (const std::invalid_argument&)
      {
        invalid[r] = 1;
        throw;
      }
    });
  for (int r = 0; r < ranks; ++r)
  {
    EXPECT_EQ(invalid[r], 1) << words << ": rank " << r << " says '" << errors[r] << "'";
    EXPECT_EQ(errors[r], errors[0]) << words;
    EXPECT_NE(errors[r].find(words), std::string::npos) << errors[r];
  }
}
} // namespace

TEST(TerroirDistributedWarmStart, BadTilesFailOnEveryRank)
{
  std::mt19937_64 rng(11);
  const Grid w = MakeGrid(rng, 40, 40, false);
  const hy::WaterFlowWarmStartOptions o = Options(10);
  const std::vector<bool> none(3, false);
  const std::vector<hy::TileBox> good{ { 0, 13, 0, 39 }, { 14, 27, 0, 39 }, { 28, 39, 0, 39 } };
  // Overlapping and missing cells.
  ExpectFailsEverywhere(
    w, Even({ { 0, 14, 0, 39 }, { 14, 27, 0, 39 }, { 28, 39, 0, 39 } }, 2), none, o, "overlap");
  ExpectFailsEverywhere(
    w, Even({ { 0, 12, 0, 39 }, { 14, 27, 0, 39 }, { 28, 39, 0, 39 } }, 2), none, o, "cover");
  // A reach under 2; a tile holding only its reach (no outer ring).
  ExpectFailsEverywhere(w, Split{ good, { 2, 1, 2 }, 0 }, none, o, "reach of rank 1 is 1");
  ExpectFailsEverywhere(w, Even(good, 2), none, o, "lacks the ring of 3", { 3, 2, 3 });
  // A level that would leave a tile empty ([14, 15] -> [7, 7] -> empty).
  ExpectFailsEverywhere(w,
    Even({ { 0, 13, 0, 39 }, { 14, 15, 0, 39 }, { 16, 39, 0, 39 } }, 2),
    none,
    o,
    "leave a tile empty");
  // A rain field on one rank only; bad options.
  ExpectFailsEverywhere(w, Even(good, 2), { false, true, false }, o, "kind of rain");
  hy::WaterFlowWarmStartOptions bad = o;
  bad.rule.balanceTolerance = 0.0;
  ExpectFailsEverywhere(w, Even(good, 2), none, bad, "balance tolerance");
}

TEST(TerroirDistributedWarmStart, AFailureInsideALevelFailsEveryRank)
{
  // A negative rain on one cell of the last tile: its coarse cell's mean is negative, the
  // serial run refuses it (SetRainField), and so must every tile, not only those holding it.
  std::mt19937_64 rng(13);
  Grid w = MakeGrid(rng, 40, 40, false);
  w.z[w.Index(36, 30)] = 20.0f;
  w.valid[w.Index(36, 30)] = 1;
  w.rain[w.Index(36, 30)] = -1.0;
  const hy::WaterFlowWarmStartOptions o = Options(10);
  std::vector<double> water = StillWater(w);
  EXPECT_THROW(
    hy::WaterFlowWarmStart(w.View(), water.data(), 2e-3, w.rain.data(), o), std::invalid_argument);
  const std::vector<hy::TileBox> good{ { 0, 13, 0, 39 }, { 14, 27, 0, 39 }, { 28, 39, 0, 39 } };
  ExpectFailsEverywhere(w, Even(good, 2), { true, true, true }, o, "rain");
}

// Unit tests of terroir::hydrology::FillDepressionsDistributed (Barnes 2016's parallel
// Priority-Flood and the water bodies merged across tiles). Threads stand in for MPI
// processes; each thread sees only a copy of its own tile and the ring around it. The answer
// is the serial PriorityFloodBarnes2014 + DepressionWaterBodies on the whole grid (both tested
// against a brute force and by hand in TestFloodFill.cxx).
#include "DepressionWaterBodies.h"
#include "DistributedPriorityFlood.h"
#include "FloodFill.h"
#include "PriorityFlood.h"
#include "TerroirThreadTiles.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{
namespace hy = terroir::hydrology;
using terroir::GridView;
using namespace terroir_test;

struct Outcome
{
  std::vector<TileCopy> copies;
  std::vector<hy::DistributedFillResult> results;
  std::vector<std::string> errors;    ///< per rank: the exception's message, or empty
  std::vector<std::size_t> sentBytes; ///< per rank: what it sent to rank 0
};

/// Runs every tile on its own thread; tile r sees its box grown by `halo` (clipped). With
/// `seeds`, the seed flood fill, else the depressions.
Outcome RunTiles(const Terrain& w,
  const std::vector<hy::TileBox>& owned,
  int reach,
  int halo,
  const hy::DepressionWaterBodyOptions& options,
  const std::vector<hy::DistributedSeed>* seeds = nullptr)
{
  Outcome out;
  out.results.resize(owned.size());
  for (const hy::TileBox& b : owned)
  {
    out.copies.push_back(HaloCopy(w, b, halo));
  }
  out.errors = RunOnThreads(
    static_cast<int>(owned.size()),
    [&](int r, ThreadExchange& exchange)
    {
      const hy::DistributedFillInput in = TileInput(w, out.copies[r], owned[r], reach);
      out.results[r] = seeds ? hy::FloodFillSeedsDistributed(in, *seeds, exchange)
                             : hy::FillDepressionsDistributed(in, options, exchange);
    },
    &out.sentBytes);
  return out;
}

bool SameFloat(float a, float b)
{
  return (std::isnan(a) && std::isnan(b)) || a == b;
}

/// Every tile's owned cells and ring equal the serial answer; the body tables agree. Returns
/// the number of water bodies that lie in more than one tile.
int ExpectSerial(const Terrain& w,
  const std::vector<hy::TileBox>& owned,
  int reach,
  const hy::DepressionWaterBodyOptions& options,
  const std::string& what)
{
  const GridView<float> v = w.View();
  std::vector<float> filled(v.Size());
  hy::PriorityFloodBarnes2014(v, filled.data());
  std::vector<std::int32_t> id(v.Size());
  std::vector<float> depth(v.Size());
  const std::vector<hy::WaterBodyStats> bodies =
    hy::DepressionWaterBodies(v, filled.data(), options, id.data(), depth.data());

  const Outcome out = RunTiles(w, owned, reach, reach + 1, options);
  std::vector<std::vector<int>> tilesOf(bodies.size() + 1);
  for (std::size_t r = 0; r < owned.size(); ++r)
  {
    if (!out.errors[r].empty())
    {
      ADD_FAILURE() << what << " rank " << r << ": " << out.errors[r];
      return 0;
    }
    const hy::DistributedFillResult& got = out.results[r];
    const TileCopy& c = out.copies[r];
    if (got.bodies.size() != bodies.size())
    {
      ADD_FAILURE() << what << " rank " << r << ": " << got.bodies.size() << " bodies, serial "
                    << bodies.size();
      return 0;
    }
    for (std::size_t b = 0; b < bodies.size(); ++b)
    {
      EXPECT_EQ(got.bodies[b].level, bodies[b].level) << what << " body " << b + 1;
      EXPECT_EQ(got.bodies[b].cells, bodies[b].cells) << what << " body " << b + 1;
      EXPECT_EQ(got.bodies[b].maxDepth, bodies[b].maxDepth) << what << " body " << b + 1;
      // Added tile by tile rather than breadth first: the order of the additions differs.
      EXPECT_NEAR(got.bodies[b].area, bodies[b].area, 1e-12 * bodies[b].area);
      EXPECT_NEAR(got.bodies[b].volume, bodies[b].volume, 1e-12 * bodies[b].volume + 1e-300);
    }
    if (owned[r].Cells() == 0)
    {
      continue;
    }
    const int i0 = std::max(0, owned[r].i0 - reach);
    const int i1 = std::min(w.nx - 1, owned[r].i1 + reach);
    const int j0 = std::max(0, owned[r].j0 - reach);
    const int j1 = std::min(w.ny - 1, owned[r].j1 + reach);
    for (int j = j0; j <= j1; ++j)
    {
      for (int i = i0; i <= i1; ++i)
      {
        const std::size_t k = static_cast<std::size_t>(j) * w.nx + i;
        const std::size_t t = static_cast<std::size_t>(j - c.gj0) * c.t.nx + (i - c.gi0);
        EXPECT_TRUE(SameFloat(got.filled[t], filled[k]))
          << what << " rank " << r << " cell (" << i << ", " << j << "): " << got.filled[t]
          << " vs serial " << filled[k];
        EXPECT_EQ(got.bodyId[t], id[k])
          << what << " rank " << r << " cell (" << i << ", " << j << ")";
        EXPECT_TRUE(SameFloat(got.depth[t], depth[k]))
          << what << " rank " << r << " cell (" << i << ", " << j << ")";
        if (owned[r].Contains(i, j) && id[k] > 0 &&
          (tilesOf[id[k]].empty() || tilesOf[id[k]].back() != static_cast<int>(r)))
        {
          tilesOf[id[k]].push_back(static_cast<int>(r));
        }
      }
    }
  }
  int spread = 0;
  for (const std::vector<int>& t : tilesOf)
  {
    spread += t.size() > 1 ? 1 : 0;
  }
  return spread;
}

} // namespace

// 60 random terrains (whole metres: many flats and ties; continuous; some with no data), split
// 1 to 16 ways in uneven blocks, rings of 1 to 3 cells: the filled surface, the ids and depths
// equal the serial code's, on the owned cells and on the ring each tile asked for.
TEST(DistributedPriorityFlood, EqualsSerialOnRandomTerrains)
{
  std::mt19937_64 rng(20160701);
  int spread = 0;
  for (int t = 0; t < 60; ++t)
  {
    const int nx = 3 + static_cast<int>(rng() % 40);
    const int ny = 3 + static_cast<int>(rng() % 40);
    const Terrain w = RandomTerrain(rng, nx, ny, t % 2 == 0, t % 3 == 0 ? 60 : 0);
    const std::vector<hy::TileBox> boxes = Blocks(Cuts(rng, nx, 1 + static_cast<int>(rng() % 4)),
      Cuts(rng, ny, 1 + static_cast<int>(rng() % 4)));
    hy::DepressionWaterBodyOptions options;
    options.includeFlatSurfaces = t % 4 < 2;
    options.minimumArea = t % 5 == 0 ? 0.0 : 6.0; // 0: every flat with a filled cell counts
    spread += ExpectSerial(w, boxes, 1 + t % 3, options, "terrain " + std::to_string(t));
  }
  EXPECT_GT(spread, 20); // water bodies that more than one tile holds part of
}

// A ring-shaped ridge whose lowest gap is at one place: the lake inside is one body that lies in
// all four tiles (split through its centre) and in no other, at the gap's height; a valley
// leaving through the gap crosses a tile edge too.
TEST(DistributedPriorityFlood, LakeAcrossFourTiles)
{
  Terrain w;
  w.nx = 41;
  w.ny = 41;
  for (int j = 0; j < w.ny; ++j)
  {
    w.rowDx.push_back(10.0);
    for (int i = 0; i < w.nx; ++i)
    {
      const double r = std::hypot(i - 20.0, j - 20.0);
      double z = 50.0 - 3.0 * std::abs(r - 12.0); // ridge at radius 12, 50 m high
      if (j == 20 && i > 20)
      {
        z = std::min(z, 30.0); // the gap to the east: 30 m
      }
      w.z.push_back(static_cast<float>(z));
      w.valid.push_back(1);
    }
  }
  const std::vector<hy::TileBox> boxes = Blocks({ 0, 20, 41 }, { 0, 21, 41 });
  hy::DepressionWaterBodyOptions options;
  options.minimumArea = 0.0;
  options.includeFlatSurfaces = false; // the cone's equal heights would count as flats
  EXPECT_EQ(ExpectSerial(w, boxes, 1, options, "ring lake"), 1);

  const Outcome out = RunTiles(w, boxes, 1, 2, options);
  ASSERT_EQ(out.results[0].bodies.size(), 1u);
  EXPECT_EQ(out.results[0].bodies[0].level, 30.0); // the gap
  for (std::size_t r = 0; r < boxes.size(); ++r)
  {
    int wet = 0;
    for (int j = boxes[r].j0; j <= boxes[r].j1; ++j)
    {
      for (int i = boxes[r].i0; i <= boxes[r].i1; ++i)
      {
        const TileCopy& c = out.copies[r];
        const std::size_t t = static_cast<std::size_t>(j - c.gj0) * c.t.nx + (i - c.gi0);
        wet += out.results[r].bodyId[t] == 1 ? 1 : 0;
        if (std::hypot(i - 20.0, j - 20.0) < 5.0)
        {
          EXPECT_EQ(out.results[r].filled[t], 30.0f) << "cell (" << i << ", " << j << ")";
        }
      }
    }
    EXPECT_GT(wet, 15) << "tile " << r << " holds part of the lake";
  }
}

// The tiles must partition the grid, and each must come with its ring; otherwise every rank
// fails with the same reason (none waits for the others for ever).
TEST(DistributedPriorityFlood, RefusesBadTiles)
{
  std::mt19937_64 rng(7);
  const Terrain w = RandomTerrain(rng, 10, 8, false, 0);
  hy::DepressionWaterBodyOptions options;
  const Outcome overlap = RunTiles(w, { { 0, 5, 0, 7 }, { 5, 9, 0, 7 } }, 1, 2, options);
  for (const std::string& e : overlap.errors)
  {
    EXPECT_NE(e.find("overlap"), std::string::npos) << e;
  }
  const Outcome gap = RunTiles(w, { { 0, 3, 0, 7 }, { 5, 9, 0, 7 } }, 1, 2, options);
  for (const std::string& e : gap.errors)
  {
    EXPECT_NE(e.find("cover 72 cells of a grid of 80"), std::string::npos) << e;
  }
  const Outcome ring = RunTiles(w, { { 0, 4, 0, 7 }, { 5, 9, 0, 7 } }, 2, 1, options);
  for (const std::string& e : ring.errors)
  {
    EXPECT_NE(e.find("lacks the ring of 2"), std::string::npos) << e;
  }
}

// What travels grows with a tile's perimeter, not its area: on a 480 x 480 random terrain cut
// in 4 (every cell its own one-cell flat, thousands of small pits), each rank sends rank 0
// less than 200 bytes per perimeter cell (measured: about 100). Sending every flat (the first
// version did) costs 56 bytes per cell of the tile, 3.2 MB here, and fails this.
TEST(DistributedPriorityFlood, SendsPerimetersNotTiles)
{
  std::mt19937_64 rng(2016);
  const Terrain w = RandomTerrain(rng, 480, 480, false, 0);
  const std::vector<hy::TileBox> boxes = Blocks({ 0, 240, 480 }, { 0, 240, 480 });
  hy::DepressionWaterBodyOptions options;
  const Outcome out = RunTiles(w, boxes, 1, 2, options);
  for (std::size_t r = 0; r < boxes.size(); ++r)
  {
    ASSERT_EQ(out.errors[r], "");
    const double perimeter = 2.0 * 240; // two inner edges of a corner tile
    EXPECT_LT(static_cast<double>(out.sentBytes[r]), 200.0 * perimeter) << "rank " << r;
  }
}

// The seed flood fill in tiles: 40 random terrains (flats, no data), 1 to 5 seeds each (levels
// given or the terrain's, some below the terrain, some on no data, some inside another's body),
// 1 to 16 uneven tiles: ids, depths and the seeds' table equal FloodFillSeeds on the whole
// grid, on every owned and ring cell.
TEST(DistributedPriorityFlood, SeedsEqualSerialOnRandomTerrains)
{
  std::mt19937_64 rng(1990);
  int crossing = 0;
  for (int t = 0; t < 40; ++t)
  {
    const int nx = 4 + static_cast<int>(rng() % 36);
    const int ny = 4 + static_cast<int>(rng() % 36);
    const Terrain w = RandomTerrain(rng, nx, ny, t % 2 == 0, t % 3 == 0 ? 60 : 0);
    const std::vector<hy::TileBox> boxes = Blocks(Cuts(rng, nx, 1 + static_cast<int>(rng() % 4)),
      Cuts(rng, ny, 1 + static_cast<int>(rng() % 4)));
    std::vector<hy::DistributedSeed> seeds(1 + rng() % 5);
    std::vector<hy::FloodSeed> serialSeeds;
    for (hy::DistributedSeed& seed : seeds)
    {
      seed.cell = static_cast<std::int64_t>(rng() % static_cast<std::uint64_t>(nx * ny));
      const int kind = static_cast<int>(rng() % 3);
      const float z = w.z[static_cast<std::size_t>(seed.cell)];
      const float top = t % 2 == 0 ? 8.0f : 125.0f;
      seed.level = kind == 0 ? std::numeric_limits<double>::quiet_NaN()
        : kind == 1          ? top * (0.3 + 0.6 * static_cast<double>(rng() % 1000) / 1000.0)
                             : (std::isnan(z) ? 50.0 : static_cast<double>(z) - 0.5);
      hy::FloodSeed f;
      f.cell = static_cast<std::size_t>(seed.cell);
      f.level = seed.level;
      serialSeeds.push_back(f);
    }
    const GridView<float> v = w.View();
    std::vector<std::int32_t> id(v.Size());
    std::vector<float> depth(v.Size());
    const std::vector<hy::WaterBodyStats> bodies =
      hy::FloodFillSeeds(v, serialSeeds, id.data(), depth.data());
    const int reach = 1 + t % 2;
    const Outcome out = RunTiles(w, boxes, reach, reach + 1, {}, &seeds);
    const std::string what = "terrain " + std::to_string(t);
    std::vector<std::vector<int>> tilesOf(seeds.size() + 1);
    for (std::size_t r = 0; r < boxes.size(); ++r)
    {
      ASSERT_EQ(out.errors[r], "") << what;
      const hy::DistributedFillResult& got = out.results[r];
      ASSERT_EQ(got.bodies.size(), bodies.size()) << what;
      for (std::size_t b = 0; b < bodies.size(); ++b)
      {
        EXPECT_TRUE(
          SameFloat(static_cast<float>(got.bodies[b].level), static_cast<float>(bodies[b].level)))
          << what << " seed " << b + 1;
        EXPECT_EQ(got.bodies[b].cells, bodies[b].cells) << what << " seed " << b + 1;
        EXPECT_EQ(got.bodies[b].maxDepth, bodies[b].maxDepth) << what << " seed " << b + 1;
        EXPECT_NEAR(got.bodies[b].area, bodies[b].area, 1e-12 * bodies[b].area);
        EXPECT_NEAR(got.bodies[b].volume, bodies[b].volume, 1e-12 * bodies[b].volume + 1e-300);
      }
      if (boxes[r].Cells() == 0)
      {
        continue;
      }
      const TileCopy& c = out.copies[r];
      for (int j = std::max(0, boxes[r].j0 - reach); j <= std::min(ny - 1, boxes[r].j1 + reach);
           ++j)
      {
        for (int i = std::max(0, boxes[r].i0 - reach); i <= std::min(nx - 1, boxes[r].i1 + reach);
             ++i)
        {
          const std::size_t k = static_cast<std::size_t>(j) * nx + i;
          const std::size_t q = static_cast<std::size_t>(j - c.gj0) * c.t.nx + (i - c.gi0);
          EXPECT_EQ(got.bodyId[q], id[k]) << what << " rank " << r << " (" << i << ", " << j << ")";
          EXPECT_TRUE(SameFloat(got.depth[q], depth[k]))
            << what << " rank " << r << " (" << i << ", " << j << ")";
          if (boxes[r].Contains(i, j) && id[k] > 0 &&
            (tilesOf[id[k]].empty() || tilesOf[id[k]].back() != static_cast<int>(r)))
          {
            tilesOf[id[k]].push_back(static_cast<int>(r));
          }
        }
      }
    }
    for (const std::vector<int>& held : tilesOf)
    {
      crossing += held.size() > 1 ? 1 : 0;
    }
  }
  EXPECT_GT(crossing, 10); // bodies that more than one tile holds part of
}

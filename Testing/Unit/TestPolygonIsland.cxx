// Weiss (2015)'s polygon-map island (IO/Core/PolygonIsland.h): the discrete Voronoi diagram
// against a brute-force search, Lloyd's relaxation lowering the quantisation energy, the ocean,
// lakes and coast against an independent flood, the elevation walk (downhill towards the
// coast, flat across lakes), rivers reaching the coast, biomes by Patel's rules, the
// normalised heights, and bit-identical output per seed.
#include "PolygonIsland.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <deque>
#include <limits>

using namespace terroir::generation;

namespace
{
PolygonIslandParameters Small(std::uint64_t seed = 7)
{
  PolygonIslandParameters p;
  p.seed = seed;
  p.width = 160;
  p.height = 128;
  p.regions = 400;
  return p;
}

/// Sum over cells of the squared distance to their region's point (Lloyd's energy).
double Energy(const PolygonIsland& o, int width, int height)
{
  double e = 0.0;
  for (int j = 0; j < height; ++j)
  {
    for (int i = 0; i < width; ++i)
    {
      const double x = (i + 0.5) * 2.0 / width - 1.0;
      const double y = (j + 0.5 - 0.5 * height) * 2.0 / width;
      const int r = o.region[static_cast<std::size_t>(j) * width + i];
      e += (x - o.siteX[r]) * (x - o.siteX[r]) + (y - o.siteY[r]) * (y - o.siteY[r]);
    }
  }
  return e;
}
} // namespace

TEST(PolygonIsland, VoronoiLabelsAreTheNearestPoint)
{
  std::uint64_t state = 42;
  std::vector<double> x, y;
  for (int k = 0; k < 97; ++k)
  {
    x.push_back(-1.0 + 2.0 * UnitDouble(state));
    y.push_back(-0.75 + 1.5 * UnitDouble(state));
  }
  const int w = 64, h = 48;
  const std::vector<int> labels = VoronoiLabels(x, y, w, h);
  for (int j = 0; j < h; ++j)
  {
    for (int i = 0; i < w; ++i)
    {
      const double px = (i + 0.5) * 2.0 / w - 1.0, py = (j + 0.5 - 0.5 * h) * 2.0 / w;
      int best = 0;
      double bestD = std::numeric_limits<double>::infinity();
      for (int k = 0; k < 97; ++k)
      {
        const double d = (x[k] - px) * (x[k] - px) + (y[k] - py) * (y[k] - py);
        if (d < bestD)
        {
          bestD = d;
          best = k;
        }
      }
      ASSERT_EQ(labels[static_cast<std::size_t>(j) * w + i], best) << i << "," << j;
    }
  }
}

TEST(PolygonIsland, LloydRelaxationLowersTheEnergy)
{
  // Each Lloyd step can only lower sum |cell - its point|^2 (Lloyd 1982): moving a point to
  // its region's centroid lowers it, and relabelling to the nearest point lowers it again.
  double previous = std::numeric_limits<double>::infinity();
  for (int steps = 0; steps <= 3; ++steps)
  {
    PolygonIslandParameters p = Small();
    p.relaxations = steps;
    PolygonIsland o;
    std::string error;
    ASSERT_TRUE(GeneratePolygonIsland(p, o, error)) << error;
    const double e = Energy(o, p.width, p.height);
    EXPECT_LT(e, previous) << steps << " relaxations";
    previous = e;
  }
}

TEST(PolygonIsland, OceanLakesAndCoastFollowTheirDefinitions)
{
  const PolygonIslandParameters p = Small();
  PolygonIsland o;
  std::string error;
  ASSERT_TRUE(GeneratePolygonIsland(p, o, error)) << error;
  const int n = p.regions;
  // Independent flood: water regions reached from a border water region through water.
  std::vector<int> reached(n, 0);
  std::deque<int> queue;
  int landCount = 0;
  for (int k = 0; k < n; ++k)
  {
    if (o.border[k])
    {
      EXPECT_TRUE(o.water[k]) << "border region " << k << " (eq. 2 makes the map's edge water)";
      reached[k] = 1;
      queue.push_back(k);
    }
    landCount += o.water[k] ? 0 : 1;
  }
  while (!queue.empty())
  {
    const int k = queue.front();
    queue.pop_front();
    for (int s : o.neighbors[k])
    {
      if (o.water[s] && !reached[s])
      {
        reached[s] = 1;
        queue.push_back(s);
      }
    }
  }
  for (int k = 0; k < n; ++k)
  {
    EXPECT_EQ(o.ocean[k] != 0, o.water[k] && reached[k]) << k;
    bool nextToOcean = false;
    for (int s : o.neighbors[k])
    {
      nextToOcean = nextToOcean || o.ocean[s];
      // Adjacency is symmetric.
      EXPECT_TRUE(std::binary_search(o.neighbors[s].begin(), o.neighbors[s].end(), k));
    }
    EXPECT_EQ(o.coast[k] != 0, !o.water[k] && nextToOcean) << k;
  }
  // Weiss's parameters make an island: land in the middle, ocean around it.
  EXPECT_GT(landCount, n / 10);
  EXPECT_LT(landCount, n * 9 / 10);
  const std::size_t middle = static_cast<std::size_t>(p.height / 2) * p.width + p.width / 2;
  EXPECT_FALSE(o.ocean[o.region[middle]]);
}

TEST(PolygonIsland, ElevationRisesFromTheCoastAndIsFlatAcrossLakes)
{
  const PolygonIslandParameters p = Small(11);
  PolygonIsland o;
  std::string error;
  ASSERT_TRUE(GeneratePolygonIsland(p, o, error)) << error;
  double coastMax = -1.0, inlandMax = -1.0;
  for (int k = 0; k < p.regions; ++k)
  {
    if (o.ocean[k])
    {
      EXPECT_LT(o.elevation[k], 0.0);
      EXPECT_GE(o.elevation[k], -1.0);
      continue;
    }
    EXPECT_GE(o.elevation[k], 0.0);
    EXPECT_LE(o.elevation[k], 1.0);
    EXPECT_DOUBLE_EQ(o.temperature[k], 1.0 - o.elevation[k]);
    const int d = o.downslope[k];
    if (o.coast[k])
    {
      EXPECT_EQ(d, -1);
      coastMax = std::max(coastMax, o.elevation[k]);
      continue;
    }
    inlandMax = std::max(inlandMax, o.elevation[k]);
    if (d < 0)
    {
      continue; // land the walk never reached (none on an island with a coast)
    }
    EXPECT_TRUE(std::binary_search(o.neighbors[k].begin(), o.neighbors[k].end(), d));
    if (o.water[k])
    {
      EXPECT_EQ(o.elevation[k], o.elevation[d]) << "a lake is as high as where it drains";
    }
    else
    {
      EXPECT_GT(o.elevation[k], o.elevation[d]) << "land one step further from the coast";
    }
  }
  EXPECT_LT(coastMax, inlandMax);
}

TEST(PolygonIsland, RiversRunDownToTheCoastCarryingMoreWater)
{
  const PolygonIslandParameters p = Small(3);
  PolygonIsland o;
  std::string error;
  ASSERT_TRUE(GeneratePolygonIsland(p, o, error)) << error;
  int riverRegions = 0;
  for (int k = 0; k < p.regions; ++k)
  {
    if (o.riverFlow[k] <= 0.0)
    {
      continue;
    }
    ++riverRegions;
    EXPECT_FALSE(o.ocean[k]);
    int c = k, guard = 0;
    while (o.downslope[c] >= 0 && guard++ < p.regions)
    {
      EXPECT_GE(o.riverFlow[o.downslope[c]], o.riverFlow[c] + 1.0) << "more water downstream";
      c = o.downslope[c];
    }
    EXPECT_TRUE(o.coast[c]) << "the river from " << k << " ends on the coast";
  }
  EXPECT_GT(riverRegions, 0);
  // Moisture: land in [0, 1]; the wettest land lies next to a river or a lake.
  double wettest = -1.0;
  int wettestRegion = -1;
  for (int k = 0; k < p.regions; ++k)
  {
    if (!o.water[k])
    {
      EXPECT_GE(o.moisture[k], 0.0);
      EXPECT_LE(o.moisture[k], 1.0);
      if (o.moisture[k] > wettest)
      {
        wettest = o.moisture[k];
        wettestRegion = k;
      }
    }
  }
  ASSERT_GE(wettestRegion, 0);
  bool fresh = o.riverFlow[wettestRegion] > 0.0;
  for (int s : o.neighbors[wettestRegion])
  {
    fresh = fresh || (o.water[s] && !o.ocean[s]) || o.riverFlow[s] > 0.0;
  }
  EXPECT_TRUE(fresh);
}

TEST(PolygonIsland, BiomesFollowPatelsRulesAndWeissTableI)
{
  // Hand-picked points of the rule: temperature = 1 - elevation, moisture.
  EXPECT_EQ(LandBiome(0.1, 0.9), Biome::Snow);
  EXPECT_EQ(LandBiome(0.1, 0.4), Biome::Tundra);
  EXPECT_EQ(LandBiome(0.1, 0.2), Biome::Bare);
  EXPECT_EQ(LandBiome(0.1, 0.1), Biome::Scorched);
  EXPECT_EQ(LandBiome(0.3, 0.7), Biome::Taiga);
  EXPECT_EQ(LandBiome(0.3, 0.5), Biome::Shrubland);
  EXPECT_EQ(LandBiome(0.3, 0.1), Biome::TemperateDesert);
  EXPECT_EQ(LandBiome(0.5, 0.9), Biome::TemperateRainForest);
  EXPECT_EQ(LandBiome(0.5, 0.6), Biome::DeciduousForest);
  EXPECT_EQ(LandBiome(0.5, 0.3), Biome::Grassland);
  EXPECT_EQ(LandBiome(0.9, 0.9), Biome::TropicalRainForest);
  EXPECT_EQ(LandBiome(0.9, 0.5), Biome::TropicalSeasonalForest);
  EXPECT_EQ(LandBiome(0.9, 0.1), Biome::SubtropicalDesert);
  // Table I, a few rows.
  EXPECT_EQ(BiomeAmplitude(Biome::Scorched), 0.7);
  EXPECT_EQ(BiomeRoughness(Biome::Snow), 0.7);
  EXPECT_EQ(BiomeAmplitude(Biome::TemperateDesert), 0.1);
  EXPECT_EQ(BiomeRoughness(Biome::Ocean), 0.1);
  EXPECT_STREQ(BiomeName(Biome::TropicalSeasonalForest), "Tropical seasonal forest");
  const PolygonIslandParameters p = Small(5);
  PolygonIsland o;
  std::string error;
  ASSERT_TRUE(GeneratePolygonIsland(p, o, error)) << error;
  for (int k = 0; k < p.regions; ++k)
  {
    const Biome expected = o.ocean[k] ? Biome::Ocean
      : o.water[k]                    ? Biome::Lake
      : o.coast[k]                    ? Biome::Beach
                                      : LandBiome(o.temperature[k], o.moisture[k]);
    EXPECT_EQ(o.biome[k], expected) << k;
  }
}

TEST(PolygonIsland, HeightsAreNormalisedAndSeedsGiveTheSameBits)
{
  PolygonIslandParameters p = Small(9);
  PolygonIsland a, b, c;
  std::string error;
  ASSERT_TRUE(GeneratePolygonIsland(p, a, error)) << error;
  ASSERT_TRUE(GeneratePolygonIsland(p, b, error)) << error;
  const std::size_t cells = static_cast<std::size_t>(p.width) * p.height;
  ASSERT_EQ(a.heightMeters.size(), cells);
  EXPECT_EQ(std::memcmp(a.heightMeters.data(), b.heightMeters.data(), cells * sizeof(float)), 0);
  EXPECT_EQ(a.riverMap, b.riverMap);
  EXPECT_EQ(a.biomeMap, b.biomeMap);
  float top = -1e9f, bottom = 1e9f;
  for (float h : a.heightMeters)
  {
    top = std::max(top, h);
    bottom = std::min(bottom, h);
  }
  EXPECT_FLOAT_EQ(top, static_cast<float>(p.maximumHeight));
  EXPECT_FLOAT_EQ(bottom, static_cast<float>(-p.maximumDepth));
  // The map's edge is ocean below sea level, the land's highest region above it.
  EXPECT_LT(a.heightMeters[0], 0.0f);
  EXPECT_EQ(a.waterMap[0], 2);
  p.seed = 10;
  ASSERT_TRUE(GeneratePolygonIsland(p, c, error)) << error;
  EXPECT_NE(std::memcmp(a.heightMeters.data(), c.heightMeters.data(), cells * sizeof(float)), 0);
  // Bad parameters are refused with a reason.
  p.regions = 3;
  EXPECT_FALSE(GeneratePolygonIsland(p, c, error));
  EXPECT_FALSE(error.empty());
}

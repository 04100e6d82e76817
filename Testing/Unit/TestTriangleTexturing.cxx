// Unit tests of the triangle-tile texturing core (Jensen 2011; no VTK, no GL). Expected values
// are worked out by hand from the rules in TriangleTexturing.h.
#include "TriangleTexturing.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace
{
using namespace terroir::rendering;

/// Exact equality of two texels (the sides are equal by construction, not approximately).
bool SameTexel(const float* p, const float* q)
{
  return p[0] == q[0] && p[1] == q[1] && p[2] == q[2];
}

// Across every side of a grid, the two triangles' own tiles (each placed in its own frame, U
// turned by 180 degrees) give bitwise the same texels all along the side: the diagonal of each
// cell, the horizontal side between a cell and the one below, the vertical side between a cell
// and the one to its right.
TEST(TerroirTriangleTexturingCore, SharedSidesEqualOnBothTriangles)
{
  const int T = 16;
  const TileAssignment tiles = AssignTilesJensen2011(24, 20, 7);
  for (const Material& material : DefaultMaterials())
  {
    const TileSet set = SynthesizeTiles(material, T, 99);
    long compared = 0, varying = 0;
    for (int j = 0; j < tiles.CellsY; ++j)
    {
      for (int i = 0; i < tiles.CellsX; ++i)
      {
        const int lower = tiles.LowerTile(i, j), upper = tiles.UpperTile(i, j);
        for (int a = 0; a <= T; ++a)
        {
          // Diagonal: L at (a, a), U at (T - a, T - a).
          ASSERT_TRUE(SameTexel(set.At(lower, a, a), set.At(upper, T - a, T - a)))
            << material.Name << " diagonal of cell " << i << "," << j << " at " << a;
          // Bottom side of L (y = j) against the top of U in the cell below: (T - a, 0).
          if (j > 0)
          {
            ASSERT_TRUE(SameTexel(set.At(lower, a, 0), set.At(tiles.UpperTile(i, j - 1), T - a, 0)))
              << material.Name << " bottom of cell " << i << "," << j << " at " << a;
          }
          // Right side of L (x = i + 1) against the left of U in the next cell: (T, T - b).
          if (i + 1 < tiles.CellsX)
          {
            ASSERT_TRUE(SameTexel(set.At(lower, T, a), set.At(tiles.UpperTile(i + 1, j), T, T - a)))
              << material.Name << " right of cell " << i << "," << j << " at " << a;
          }
          compared += 3;
          varying += set.At(lower, a, 0)[0] != set.At(lower, T / 2, T / 4)[0];
        }
      }
    }
    EXPECT_GT(compared, 0);
    // The sides are not a constant colour (the check above would then be empty).
    if (material.Amplitude >= 0.1f)
    {
      EXPECT_GT(varying, compared / 6) << material.Name;
    }
  }
}

// The eight tiles differ from each other, and a tile's edge (A or A') changes its side: tiles
// 0 and 1 differ on the bottom side (A against A') and agree on the right side (both B).
TEST(TerroirTriangleTexturingCore, TileBitsChooseTheEdges)
{
  const int T = 16;
  const TileSet set = SynthesizeTiles(DefaultMaterials()[Rock], T, 3);
  int bottomDiffers = 0;
  for (int a = 0; a <= T; ++a)
  {
    bottomDiffers += !SameTexel(set.At(0, a, 0), set.At(1, a, 0));
    EXPECT_TRUE(SameTexel(set.At(0, T, a), set.At(1, T, a))) << a;
    // A' is A read backwards: tile 1's bottom at a is tile 0's at T - a.
    EXPECT_TRUE(SameTexel(set.At(1, a, 0), set.At(0, T - a, 0))) << a;
  }
  EXPECT_GT(bottomDiffers, T / 2);
  // Corners: every tile gives the material's base colour at its three corners.
  const Material rock = DefaultMaterials()[Rock];
  for (int tile = 0; tile < 8; ++tile)
  {
    for (const auto& corner : { std::array<int, 2>{ 0, 0 }, { T, 0 }, { T, T } })
    {
      const float* c = set.At(tile, corner[0], corner[1]);
      for (int q = 0; q < 3; ++q)
      {
        EXPECT_FLOAT_EQ(c[q], rock.Color[q]) << tile;
      }
    }
  }
}

// The walk's rule: across every side the two triangles read matching edges (L reads the label,
// U the other one), and every tile index is made of the three edges the triangle reads.
TEST(TerroirTriangleTexturingCore, NeighboursReadMatchingEdges)
{
  const TileAssignment t = AssignTilesJensen2011(40, 30, 11);
  const int nx = t.CellsX;
  for (int j = 0; j < t.CellsY; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      const int L = t.LowerTile(i, j), U = t.UpperTile(i, j);
      EXPECT_EQ(L & 1, t.Horizontal[j * nx + i]);
      EXPECT_EQ((L >> 1) & 1, t.Vertical[j * (nx + 1) + i + 1]);
      EXPECT_EQ((L >> 2) & 1, t.Diagonal[j * nx + i]);
      EXPECT_EQ(U & 1, 1 - t.Horizontal[(j + 1) * nx + i]);
      EXPECT_EQ((U >> 1) & 1, 1 - t.Vertical[j * (nx + 1) + i]);
      EXPECT_EQ((U >> 2) & 1, 1 - t.Diagonal[j * nx + i]);
      if (j > 0)
      {
        EXPECT_NE(L & 1, t.UpperTile(i, j - 1) & 1); // A meets A'
      }
      if (i + 1 < nx)
      {
        EXPECT_NE((L >> 1) & 1, (t.UpperTile(i + 1, j) >> 1) & 1); // B meets B'
      }
    }
  }
}

// On a 512 x 512 grid (524288 triangles) each of the 8 tiles should appear 65536 times; with
// independent fair edges the count's standard deviation is sqrt(N p (1 - p)) = 239, so 2 %
// (1311, 5.5 sigma) is a safe bound; a 60/40 edge would move the counts by 20 % or more.
TEST(TerroirTriangleTexturingCore, EveryTileEquallyFrequent)
{
  const TileAssignment t = AssignTilesJensen2011(512, 512, 2026);
  std::array<long, 8> count{};
  for (std::uint8_t tile : t.Tiles)
  {
    ASSERT_LT(tile, 8);
    ++count[tile];
  }
  for (int k = 0; k < 8; ++k)
  {
    EXPECT_NEAR(count[k], 65536, 1311) << "tile " << k;
  }
}

// No translation by (px, py) cells, 0 <= px, py < 64 (not both 0), maps the tile pattern of a
// 192 x 192 grid onto itself: at most about 1/8 + correlation of the triangles agree (we allow
// half), where a periodic pattern would agree everywhere.
TEST(TerroirTriangleTexturingCore, AssignmentIsNotPeriodic)
{
  const int n = 192, w = 128;
  const TileAssignment t = AssignTilesJensen2011(n, n, 5);
  double worst = 0.0;
  for (int py = 0; py < 64; ++py)
  {
    for (int px = 0; px < 64; ++px)
    {
      if (px == 0 && py == 0)
      {
        continue;
      }
      long same = 0;
      for (int j = 0; j < w; ++j)
      {
        for (int i = 0; i < w; ++i)
        {
          same += t.LowerTile(i, j) == t.LowerTile(i + px, j + py);
          same += t.UpperTile(i, j) == t.UpperTile(i + px, j + py);
        }
      }
      worst = std::max(worst, same / (2.0 * w * w));
    }
  }
  EXPECT_LT(worst, 0.5);
  EXPECT_GT(worst, 0.0);
}

TEST(TerroirTriangleTexturingCore, SameSeedSameBytes)
{
  const int px = 21, py = 17;
  std::vector<float> heights(px * py);
  for (int j = 0; j < py; ++j)
  {
    for (int i = 0; i < px; ++i)
    {
      heights[j * px + i] = static_cast<float>(40.0 * std::sin(0.3 * i) + 30.0 * j);
    }
  }
  MaterialRules rules;
  rules.SnowLine = 400.0;
  const std::vector<float> w = MaterialWeights(px, py, 10.0, 10.0, heights, {}, rules);
  const auto a = BuildTerrainTexture(px, py, w, DefaultMaterials(), 8, 42);
  const auto b = BuildTerrainTexture(px, py, w, DefaultMaterials(), 8, 42);
  const auto c = BuildTerrainTexture(px, py, w, DefaultMaterials(), 8, 43);
  ASSERT_EQ(a.Rgb.size(), std::size_t(161 * 129 * 3));
  EXPECT_EQ(a.Rgb, b.Rgb);
  EXPECT_EQ(a.Tiles.Tiles, b.Tiles.Tiles);
  EXPECT_NE(a.Rgb, c.Rgb);
  EXPECT_NE(a.Tiles.Tiles, c.Tiles.Tiles);
}

/// Checks every texel of a two-material texture (k = 1) against the tiles' texels: grass
/// weight `grassAt(x, y)` (x, y in cells), rock the rest; U's tile is read turned by 180 degrees
/// (T - a, T - b) where b > a. Returns the number of channels where the materials differ.
template<typename F>
long CheckTwoMaterialTexture(const TerrainTexture& tex,
  const TileSet& grass,
  const TileSet& rock,
  F grassAt)
{
  const int T = tex.Layout.TexelsPerTile;
  long differ = 0;
  for (int y = 0; y < tex.Layout.Height; ++y)
  {
    for (int x = 0; x < tex.Layout.Width; ++x)
    {
      const int ti = std::min(x / T, tex.Layout.TilesX - 1);
      const int tj = std::min(y / T, tex.Layout.TilesY - 1);
      const int a = x - ti * T, b = y - tj * T;
      const bool lower = b <= a;
      const int tile = lower ? tex.Tiles.LowerTile(ti, tj) : tex.Tiles.UpperTile(ti, tj);
      const float* g = lower ? grass.At(tile, a, b) : grass.At(tile, T - a, T - b);
      const float* r = lower ? rock.At(tile, a, b) : rock.At(tile, T - a, T - b);
      const double w = grassAt(double(x) / T, double(y) / T);
      for (int q = 0; q < 3; ++q)
      {
        const double want = 255.0 * (w * g[q] + (1.0 - w) * r[q]);
        const int got = tex.Rgb[(std::size_t(y) * tex.Layout.Width + x) * 3 + q];
        EXPECT_LE(std::abs(got - want), 0.5 + 1e-6) << x << "," << y << " channel " << q;
        differ += std::abs(255.0 * g[q] - 255.0 * r[q]) > 4.0;
      }
    }
  }
  return differ;
}

// The texture is the weighted sum of the materials' tiles (rounded to 8 bits): two materials
// at 1/2 each, then grass weight (x + y) / 3 on a 3 x 2 grid (affine, so the bilinear
// interpolation of the points' weights is exact at every texel).
TEST(TerroirTriangleTexturingCore, TextureIsTheWeightedTiles)
{
  const int T = 8;
  const std::uint64_t seed = 9;
  std::vector<Material> materials = { DefaultMaterials()[Grass], DefaultMaterials()[Rock] };
  const TileSet grass = SynthesizeTiles(materials[0], T, MaterialTileSeed(seed, 0));
  const TileSet rock = SynthesizeTiles(materials[1], T, MaterialTileSeed(seed, 1));
  {
    const int px = 5, py = 4;
    std::vector<float> w(px * py * 2, 0.5f);
    const TerrainTexture tex = BuildTerrainTexture(px, py, w, materials, T, seed);
    ASSERT_EQ(tex.Layout.Width, 4 * T + 1);
    ASSERT_EQ(tex.Layout.Height, 3 * T + 1);
    const long differ =
      CheckTwoMaterialTexture(tex, grass, rock, [](double, double) { return 0.5; });
    EXPECT_GT(differ, long(33 * 25 * 3) / 4); // the two materials do differ
  }
  {
    const int px = 3, py = 2;
    std::vector<float> w(px * py * 2);
    for (int j = 0; j < py; ++j)
    {
      for (int i = 0; i < px; ++i)
      {
        w[2 * (j * px + i)] = static_cast<float>((i + j) / 3.0);
        w[2 * (j * px + i) + 1] = 1.0f - w[2 * (j * px + i)];
      }
    }
    const TerrainTexture tex = BuildTerrainTexture(px, py, w, materials, T, seed);
    CheckTwoMaterialTexture(tex, grass, rock, [](double x, double y) { return (x + y) / 3.0; });
  }
}

// Weights at hand-made points (default rules: rock 30..45 deg, sand below 0..5 m, snow
// 1900..2100 m): flat at 100 m is the zone's ground; 45 deg or more is rock only; 37.5 deg is
// half rock (smoothstep 1/2); flat at 0 m is sand; flat at 2100 m is snow; at 2000 m half snow.
TEST(TerroirTriangleTexturingCore, WeightsFollowTheRules)
{
  const MaterialRules rules;
  float w[MaterialCount];
  auto expect = [&](std::array<float, MaterialCount> want, const char* what)
  {
    double sum = 0.0;
    for (int m = 0; m < MaterialCount; ++m)
    {
      EXPECT_NEAR(w[m], want[m], 1e-6) << what << " material " << m;
      sum += w[m];
    }
    EXPECT_NEAR(sum, 1.0, 1e-6) << what;
  };
  MaterialWeightsAt(0.0, 100.0, -1, rules, w);
  expect({ 1, 0, 0, 0, 0, 0 }, "flat, no zone: grass");
  MaterialWeightsAt(0.0, 100.0, 4, rules, w);
  expect({ 0, 1, 0, 0, 0, 0 }, "zone 4: forest");
  MaterialWeightsAt(0.0, 100.0, 2, rules, w);
  expect({ 0, 0, 1, 0, 0, 0 }, "zone 2: dry soil");
  MaterialWeightsAt(0.0, 100.0, 3, rules, w);
  expect({ 1, 0, 0, 0, 0, 0 }, "zone 3: grass");
  MaterialWeightsAt(50.0, 100.0, 1, rules, w);
  expect({ 0, 0, 0, 1, 0, 0 }, "steep: rock");
  MaterialWeightsAt(37.5, 100.0, 1, rules, w);
  expect({ 0, 0.5f, 0, 0.5f, 0, 0 }, "37.5 deg: half rock");
  MaterialWeightsAt(0.0, 0.0, 1, rules, w);
  expect({ 0, 0, 0, 0, 1, 0 }, "sea level: sand");
  // 2.5 m: q = 1 - smoothstep(0.5) = 1/2.
  MaterialWeightsAt(0.0, 2.5, -1, rules, w);
  expect({ 0.5f, 0, 0, 0, 0.5f, 0 }, "2.5 m: half sand");
  MaterialWeightsAt(0.0, 2100.0, 1, rules, w);
  expect({ 0, 0, 0, 0, 0, 1 }, "high: snow");
  MaterialWeightsAt(0.0, 2000.0, -1, rules, w);
  expect({ 0.5f, 0, 0, 0, 0, 0.5f }, "snow line: half snow");
  // Steep and high: rock first, snow only on what rock leaves: 37.5 deg at 2100 m.
  MaterialWeightsAt(37.5, 2100.0, -1, rules, w);
  expect({ 0, 0, 0, 0.5f, 0, 0.5f }, "steep and high");
  MaterialWeightsAt(NAN, NAN, 2, rules, w);
  expect({ 0, 0, 1, 0, 0, 0 }, "no data: ground");
}

// Slopes of planes: z = x tan 30 deg on a 10 m grid is 30 deg everywhere (central and one-
// sided differences agree on a plane); a NaN point leaves its neighbours one-sided.
TEST(TerroirTriangleTexturingCore, SlopeOfPlanes)
{
  const int nx = 6, ny = 5;
  std::vector<float> z(nx * ny);
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      z[j * nx + i] = static_cast<float>(10.0 * i * std::tan(M_PI / 6.0) + 0.0 * j);
    }
  }
  z[2 * nx + 2] = NAN;
  const std::vector<float> s = SlopeDegrees(nx, ny, 10.0, 20.0, z);
  for (int k = 0; k < nx * ny; ++k)
  {
    if (k == 2 * nx + 2)
    {
      EXPECT_EQ(s[k], 0.0f);
      continue;
    }
    EXPECT_NEAR(s[k], 30.0, 1e-4) << k;
  }
  const std::vector<float> w = MaterialWeights(nx, ny, 10.0, 20.0, z, {}, MaterialRules());
  ASSERT_EQ(w.size(), std::size_t(nx * ny * MaterialCount));
  EXPECT_NEAR(w[(3 * nx + 3) * MaterialCount + Rock], 0.0, 1e-6); // 30 deg: rock starts
}

// Layout: the bundled DEM's 785 x 719 cells at 16 texels per tile need 12561 texels across, so
// with the 4096 limit a tile covers k = 4 cells: ceil(785/4) = 197 tiles, 197 x 16 + 1 = 3153
// texels; ceil(719/4) = 180 tiles, 2881 texels. A grid point at x cells is at texel x T / k.
TEST(TerroirTriangleTexturingCore, LayoutFitsTheLimit)
{
  const TextureLayout l = PlanTexture(785, 719, 16);
  EXPECT_EQ(l.CellsPerTile, 4);
  EXPECT_EQ(l.TilesX, 197);
  EXPECT_EQ(l.TilesY, 180);
  EXPECT_EQ(l.Width, 3153);
  EXPECT_EQ(l.Height, 2881);
  EXPECT_DOUBLE_EQ(l.TextureU(0.0), 0.5 / 3153);
  EXPECT_DOUBLE_EQ(l.TextureU(785.0), (3140.0 + 0.5) / 3153);
  const TextureLayout small = PlanTexture(20, 10, 16);
  EXPECT_EQ(small.CellsPerTile, 1);
  EXPECT_EQ(small.Width, 321);
  EXPECT_EQ(small.Height, 161);
  // Exactly at the limit: 255 tiles of 16 texels + 1 = 4081 <= 4096; 256 tiles would not fit.
  EXPECT_EQ(PlanTexture(255, 1, 16).CellsPerTile, 1);
  EXPECT_EQ(PlanTexture(256, 1, 16).CellsPerTile, 2);
}

TEST(TerroirTriangleTexturingCore, BadInputErrors)
{
  EXPECT_THROW(AssignTilesJensen2011(0, 5, 1), std::invalid_argument);
  EXPECT_THROW(AssignTilesJensen2011(5, -1, 1), std::invalid_argument);
  Material m = DefaultMaterials()[Grass];
  EXPECT_THROW(SynthesizeTiles(m, 1, 1), std::invalid_argument);
  EXPECT_THROW(SynthesizeTiles(m, 257, 1), std::invalid_argument);
  m.Amplitude = 1.5f;
  EXPECT_THROW(SynthesizeTiles(m, 16, 1), std::invalid_argument);
  m = DefaultMaterials()[Grass];
  m.FeatureSize = 0.0f;
  EXPECT_THROW(SynthesizeTiles(m, 16, 1), std::invalid_argument);
  EXPECT_THROW(PlanTexture(10, 10, 16, 16), std::invalid_argument);
  EXPECT_THROW(PlanTexture(0, 10, 16), std::invalid_argument);
  float w[MaterialCount];
  MaterialRules bad;
  bad.RockSlopeFull = bad.RockSlopeStart;
  EXPECT_THROW(MaterialWeightsAt(0, 0, 0, bad, w), std::invalid_argument);
  bad = MaterialRules();
  bad.SnowBand = 0.0;
  EXPECT_THROW(MaterialWeightsAt(0, 0, 0, bad, w), std::invalid_argument);
  const std::vector<float> z(12, 1.0f);
  EXPECT_THROW(SlopeDegrees(4, 4, 1.0, 1.0, z), std::invalid_argument);
  EXPECT_THROW(SlopeDegrees(4, 3, 0.0, 1.0, z), std::invalid_argument);
  EXPECT_THROW(MaterialWeights(4, 3, 1.0, 1.0, z, std::vector<int>(5), MaterialRules()),
    std::invalid_argument);
  const auto mats = DefaultMaterials();
  std::vector<float> weights(12 * mats.size(), 0.0f);
  EXPECT_THROW(BuildTerrainTexture(4, 3, weights, mats, 8, 1), std::invalid_argument); // sums 0
  for (int k = 0; k < 12; ++k)
  {
    weights[k * mats.size()] = 1.0f;
  }
  EXPECT_NO_THROW(BuildTerrainTexture(4, 3, weights, mats, 8, 1));
  weights[0] = -1.0f;
  weights[1] = 2.0f;
  EXPECT_THROW(BuildTerrainTexture(4, 3, weights, mats, 8, 1), std::invalid_argument);
  EXPECT_THROW(BuildTerrainTexture(4, 3, std::vector<float>(5), mats, 8, 1), std::invalid_argument);
  EXPECT_THROW(BuildTerrainTexture(4, 3, weights, {}, 8, 1), std::invalid_argument);
  try
  {
    PlanTexture(10, 10, 300);
    FAIL() << "no error";
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_NE(std::string(e.what()).find("texelsPerTile = 300"), std::string::npos) << e.what();
  }
}
} // namespace

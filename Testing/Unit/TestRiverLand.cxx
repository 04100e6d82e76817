// Jensen (2011)'s RiverLand (IO/Core/RiverLand.h): the medial axis of simple shapes (a strip
// between two parallel rivers, a ring river), pruning on an L-shaped river worked by hand,
// the slope profiles' values at known points, Jensen's two blending examples, influence
// flooding stopped by the ridge, the generated rivers (mouths on the coast, 4-connected,
// heights rising inland), the JSON parameters, and identical bits per seed and per thread
// count.
#include "RiverLand.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

using namespace terroir::generation;

namespace
{
/// A map with the given classes and one river network per `rivers` list (cells from the
/// mouth upstream), river heights all `h` (flat rivers) unless `rise`.
struct Map
{
  int W, H;
  std::vector<std::uint8_t> cls;
  std::vector<double> height;
  std::vector<int> down, depth;
  Map(int w, int h)
    : W(w)
    , H(h)
    , cls(static_cast<std::size_t>(w) * h, RiverLandLand)
    , height(cls.size(), 0.0)
    , down(cls.size(), -1)
    , depth(cls.size(), 0)
  {
  }
  int At(int i, int j) const { return j * W + i; }
  void River(const std::vector<int>& cells)
  {
    for (std::size_t k = 0; k < cells.size(); ++k)
    {
      cls[cells[k]] = RiverLandRiver;
      down[cells[k]] = k == 0 ? -1 : cells[k - 1];
      depth[cells[k]] = static_cast<int>(k);
    }
  }
  RiverLandParameters Params(bool prune) const
  {
    RiverLandParameters p;
    p.width = W;
    p.height = H;
    p.spacing = 1.0;
    p.hillSlope = 1.0;
    p.prune = prune;
    return p;
  }
};

/// Rivers along rows 0 and H - 1 (two networks, mouths at i = 0).
Map ParallelRivers(int W, int H)
{
  Map m(W, H);
  std::vector<int> a, b;
  for (int i = 0; i < W; ++i)
  {
    a.push_back(m.At(i, 0));
    b.push_back(m.At(i, H - 1));
  }
  m.River(a);
  m.River(b);
  return m;
}

/// One river from (0, 0) east to (20, 0), then north to (20, 20); land west and north of it.
Map LRiver()
{
  Map m(21, 21);
  std::vector<int> cells;
  for (int i = 0; i <= 20; ++i)
    cells.push_back(m.At(i, 0));
  for (int j = 1; j <= 20; ++j)
    cells.push_back(m.At(20, j));
  m.River(cells);
  return m;
}

RiverLandParameters SmallIsland(std::uint64_t seed = 3)
{
  RiverLandParameters p;
  p.seed = seed;
  p.width = 200;
  p.height = 160;
  p.rivers = 8;
  p.noiseAmplitude = 15.0;
  RiverLandSlope s;
  s.x = 0.45;
  s.y = 0.55;
  s.profile = SlopeProfile::Gauss;
  s.influence = 25;
  p.slopes.push_back(s);
  s.x = 0.6;
  s.profile = SlopeProfile::Custom;
  s.curveX = { 0.0, 0.3, 1.0 };
  s.curveY = { 0.0, 0.8, 1.0 };
  p.slopes.push_back(s);
  return p;
}
} // namespace

// Between rivers on rows 0 and 20, d = min(j, 20 - j): the medial axis is row 10 exactly,
// pruning keeps it (its cells point back to two different rivers), and the linear heights
// are h = d x hillSlope on the way up to the ridge's 10.
TEST(RiverLand, MedialAxisBetweenParallelRiversIsTheMidLine)
{
  for (bool prune : { false, true })
  {
    Map m = ParallelRivers(30, 21);
    RiverLand out;
    std::string error;
    ASSERT_TRUE(ShapeRiverLand(m.Params(prune), m.cls, m.height, m.down, m.depth, out, error))
      << error;
    for (int j = 1; j < 20; ++j)
    {
      for (int i = 0; i < 30; ++i)
      {
        const int c = m.At(i, j);
        EXPECT_EQ(out.medial[c] == 1, j == 10) << i << "," << j;
        EXPECT_DOUBLE_EQ(out.distance[c], std::min(j, 20 - j));
        EXPECT_EQ(out.target[c], m.At(i, 10)) << i << "," << j;
        EXPECT_NEAR(out.heightMeters[c], std::min(j, 20 - j), 1e-5) << i << "," << j;
      }
    }
    EXPECT_EQ(out.medialBefore, 30);
    EXPECT_EQ(out.medialAfter, 30);
  }
}

// A ring river of radius 12 around cell (20, 20): the farthest cell from it is the centre, a
// medial cell, and pruning leaves only medial cells around it.
TEST(RiverLand, MedialAxisOfARingRiverIsItsCentre)
{
  const int N = 41, C = 20;
  const double R = 12.0;
  Map m(N, N);
  // The ring (cells whose centre is within half a cell of radius R), ordered by angle.
  std::vector<std::pair<double, int>> ring;
  for (int j = 0; j < N; ++j)
  {
    for (int i = 0; i < N; ++i)
    {
      const double r = std::hypot(i - C, j - C);
      if (r > R + 0.5)
        m.cls[m.At(i, j)] = RiverLandSea;
      else if (r >= R - 0.5)
        ring.push_back({ std::atan2(j - C, i - C), m.At(i, j) });
    }
  }
  std::sort(ring.begin(), ring.end());
  std::vector<int> cells;
  for (const auto& e : ring)
    cells.push_back(e.second);
  m.River(cells);
  RiverLand out;
  std::string error;
  ASSERT_TRUE(ShapeRiverLand(m.Params(true), m.cls, m.height, m.down, m.depth, out, error));
  const int centre = m.At(C, C);
  double maxD = 0.0;
  int argMax = -1;
  for (std::size_t c = 0; c < out.distance.size(); ++c)
  {
    if (m.cls[c] == RiverLandLand && out.distance[c] > maxD)
    {
      maxD = out.distance[c];
      argMax = static_cast<int>(c);
    }
  }
  EXPECT_EQ(argMax, centre);
  EXPECT_EQ(out.medial[centre], 1);
  // The chamfer distance leaves spurious ridges up to the ring; pruning removes every one
  // whose cells point back to ring cells under 20 apart. What stays is the centre's small
  // plateau: cells within 3.5 cells of it, whose neighbours point to opposite sides.
  EXPECT_GT(out.medialBefore, 40);
  EXPECT_LE(out.medialAfter, 9);
  for (int j = 0; j < N; ++j)
  {
    for (int i = 0; i < N; ++i)
    {
      if (out.medial[m.At(i, j)] == 1)
      {
        EXPECT_LE(std::hypot(i - C, j - C), 3.5) << i << "," << j;
      }
    }
  }
  // Every land cell's path ends near the centre, and no land is higher than the centre.
  for (std::size_t c = 0; c < out.target.size(); ++c)
  {
    if (m.cls[c] != RiverLandLand)
      continue;
    const int t = out.target[c];
    EXPECT_LE(std::hypot(t % N - C, t / N - C), 3.5);
    EXPECT_LE(out.heightMeters[c], out.heightMeters[centre]);
  }
  EXPECT_NEAR(out.heightMeters[centre], out.distance[centre], 1e-5);
}

// L-shaped river, mouth at (0, 0): d = min(j, 20 - i) and the medial cells are the diagonal
// (i, 20 - i), i = 0..19, at D = 20 - i. Their neighbours point back to both arms; the
// farthest pair along the river is 2 D + 1 cells apart, so Jensen's threshold 20 prunes D <=
// 9 (i = 11..19) and keeps D >= 10 (i = 0..10). Pruned cells point up the diagonal to (10, 10).
TEST(RiverLand, PruningRemovesSpuriousCellsNearTheBendAndKeepsTheRidge)
{
  Map m = LRiver();
  RiverLand before, after;
  std::string error;
  ASSERT_TRUE(ShapeRiverLand(m.Params(false), m.cls, m.height, m.down, m.depth, before, error));
  ASSERT_TRUE(ShapeRiverLand(m.Params(true), m.cls, m.height, m.down, m.depth, after, error));
  for (int j = 1; j <= 20; ++j)
  {
    for (int i = 0; i < 20; ++i)
    {
      const int c = m.At(i, j);
      const bool diagonal = j == 20 - i;
      EXPECT_EQ(before.medial[c] == 1, diagonal) << i << "," << j;
      EXPECT_EQ(after.medial[c], !diagonal ? 0 : (i >= 11 ? 2 : 1)) << i << "," << j;
    }
  }
  EXPECT_EQ(before.medialBefore, 20);
  EXPECT_EQ(after.medialAfter, 11);
  EXPECT_EQ(after.medial[m.At(15, 5)], 2); // spurious: D = 5
  EXPECT_EQ(after.medial[m.At(5, 15)], 1); // real: D = 15
  EXPECT_EQ(after.target[m.At(15, 5)], m.At(10, 10));
  EXPECT_EQ(after.target[m.At(17, 1)], m.At(10, 10)); // a land cell below the pruned ones
  // Jensen's rule is "less than the threshold": 2D + 1 = 21 at D = 10 is kept by 21 and
  // pruned by 22.
  for (double threshold : { 21.0, 22.0 })
  {
    RiverLandParameters q = m.Params(true);
    q.pruneThreshold = threshold;
    RiverLand r;
    ASSERT_TRUE(ShapeRiverLand(q, m.cls, m.height, m.down, m.depth, r, error));
    EXPECT_EQ(r.medial[m.At(10, 10)], threshold == 21.0 ? 1 : 2) << threshold;
    EXPECT_EQ(r.medialAfter, threshold == 21.0 ? 11 : 10) << threshold;
  }
  // Threshold 0 prunes nothing.
  RiverLandParameters p = m.Params(true);
  p.pruneThreshold = 0.0;
  RiverLand none;
  ASSERT_TRUE(ShapeRiverLand(p, m.cls, m.height, m.down, m.depth, none, error));
  EXPECT_EQ(none.medialAfter, 20);
}

// Profiles at points worked out by hand: cos 1 - cos(pi t / 2), cos2 1 - cos^2(pi t / 2), the
// Gauss profile from the normal density's table values phi(0) = 0.398942, phi(1.55) =
// 0.120009, phi(3.1) = 0.0032668, and a custom curve interpolated linearly.
TEST(RiverLand, SlopeProfilesHaveTheirShapes)
{
  for (SlopeProfile s :
    { SlopeProfile::Linear, SlopeProfile::Cos, SlopeProfile::Cos2, SlopeProfile::Gauss })
  {
    EXPECT_NEAR(SlopeProfileValue(s, 0.0), 0.0, 1e-12) << SlopeProfileName(s);
    EXPECT_NEAR(SlopeProfileValue(s, 1.0), 1.0, 1e-12) << SlopeProfileName(s);
    EXPECT_NEAR(SlopeProfileValue(s, 2.0), 1.0, 1e-12) << "clamped";
  }
  EXPECT_NEAR(SlopeProfileValue(SlopeProfile::Linear, 0.3), 0.3, 1e-12);
  EXPECT_NEAR(SlopeProfileValue(SlopeProfile::Cos, 0.5), 1.0 - std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(SlopeProfileValue(SlopeProfile::Cos, 2.0 / 3.0), 0.5, 1e-12);
  EXPECT_NEAR(SlopeProfileValue(SlopeProfile::Cos2, 0.5), 0.5, 1e-12);
  EXPECT_NEAR(SlopeProfileValue(SlopeProfile::Cos2, 1.0 / 3.0), 0.25, 1e-12);
  EXPECT_NEAR(SlopeProfileValue(SlopeProfile::Gauss, 0.5),
    (0.120009 - 0.0032668) / (0.398942 - 0.0032668),
    1e-5);
  const std::vector<double> x{ 0.0, 0.25, 1.0 }, y{ 0.0, 0.75, 1.0 };
  EXPECT_NEAR(SlopeProfileValue(SlopeProfile::Custom, 0.125, x, y), 0.375, 1e-12);
  EXPECT_NEAR(SlopeProfileValue(SlopeProfile::Custom, 0.625, x, y), 0.875, 1e-12);
  EXPECT_NEAR(SlopeProfileValue(SlopeProfile::Custom, 1.0, x, y), 1.0, 1e-12);
}

// Jensen 2.4.2's example: influence 24 of 120, linear 100, custom 50 -> 90. Jensen 2.4.3's:
// fractions 25/50, 35/70, 10/30 and the linear 1 sum to 2.33, weights 21.5 %, 21.5 %, 14.3 %,
// 42.9 % (his rounding); heights 10, 20, 30 and linear 40 give 65 / (7/3).
TEST(RiverLand, BlendingFollowsJensensExamples)
{
  EXPECT_NEAR(BlendSlopeHeights(100.0, { 50.0 }, { 24.0 / 120.0 }), 90.0, 1e-12);
  EXPECT_NEAR(BlendSlopeHeights(40.0, { 10.0, 20.0, 30.0 }, { 25.0 / 50, 35.0 / 70, 10.0 / 30 }),
    65.0 / (7.0 / 3.0),
    1e-12);
  // His rounded weights (summing to 1.002) give the same height to 0.2 %.
  EXPECT_NEAR(BlendSlopeHeights(40.0, { 10.0, 20.0, 30.0 }, { 25.0 / 50, 35.0 / 70, 10.0 / 30 }),
    0.215 * 10 + 0.215 * 20 + 0.143 * 30 + 0.429 * 40,
    0.002 * 27.9);
  EXPECT_DOUBLE_EQ(BlendSlopeHeights(7.0, {}, {}), 7.0);
}

// A Gauss slope at (15, 5) between the parallel rivers, influence 5: its path is column 15
// (rows 1 to 10, full weight); the flood loses 1 per 4-step ((13, 5): 3/5) and never crosses
// the ridge row 10 ((15, 12) keeps the linear height).
TEST(RiverLand, SlopeInfluenceFloodsOneSideOfTheRidge)
{
  Map m = ParallelRivers(30, 21);
  RiverLandParameters p = m.Params(true);
  RiverLandSlope s;
  s.x = 15.5 / 30.0;
  s.y = 5.5 / 21.0;
  s.profile = SlopeProfile::Gauss;
  s.influence = 5.0;
  p.slopes.push_back(s);
  RiverLand out;
  std::string error;
  ASSERT_TRUE(ShapeRiverLand(p, m.cls, m.height, m.down, m.depth, out, error));
  EXPECT_EQ(out.slopesApplied, 1);
  const double g = SlopeProfileValue(SlopeProfile::Gauss, 0.5);
  for (int j = 1; j < 10; ++j)
  {
    EXPECT_FLOAT_EQ(out.slopeWeight[m.At(15, j)], 1.0f) << j;
    EXPECT_NEAR(
      out.heightMeters[m.At(15, j)], 10.0 * SlopeProfileValue(SlopeProfile::Gauss, j / 10.0), 1e-5);
  }
  EXPECT_FLOAT_EQ(out.slopeWeight[m.At(13, 5)], 0.6f);
  EXPECT_NEAR(out.heightMeters[m.At(13, 5)], 0.6 * 10.0 * g + 0.4 * 5.0, 1e-5);
  EXPECT_FLOAT_EQ(out.slopeWeight[m.At(10, 5)], 0.0f);
  EXPECT_FLOAT_EQ(out.slopeWeight[m.At(15, 12)], 0.0f);
  EXPECT_FLOAT_EQ(out.slopeWeight[m.At(15, 11)], 0.0f);
  EXPECT_NEAR(out.heightMeters[m.At(15, 12)], 8.0, 1e-5);
}

// The generated rivers: every main river starts on the coast (next to the sea), every river
// is 4-connected and joins its parent, and river heights rise strictly inland.
TEST(RiverLand, RiversReachTheCoastAndRiseInland)
{
  RiverLandParameters p = SmallIsland();
  RiverLand out;
  std::string error;
  ASSERT_TRUE(GenerateRiverLand(p, out, error)) << error;
  const int W = p.width;
  ASSERT_GE(out.rivers.size(), 4u);
  int tributaries = 0;
  auto adjacent = [W](int a, int b)
  { return std::abs(a % W - b % W) + std::abs(a / W - b / W) == 1; };
  for (std::size_t r = 0; r < out.rivers.size(); ++r)
  {
    const RiverLandRiverPath& path = out.rivers[r];
    ASSERT_FALSE(path.cells.empty());
    if (path.parent < 0)
    {
      const int m = path.cells[0];
      bool sea = false;
      for (int q : { m - 1, m + 1, m - W, m + W })
        sea = sea || out.cls[q] == RiverLandSea;
      EXPECT_TRUE(sea) << "river " << r << " mouth";
      EXPECT_EQ(out.riverHeight[m], 0.0);
    }
    else
    {
      ++tributaries;
      ASSERT_LT(path.parent, static_cast<int>(r));
      const auto& up = out.rivers[path.parent].cells;
      const bool joins = std::find(up.begin(), up.end(), path.junction) != up.end();
      EXPECT_TRUE(adjacent(path.junction, path.cells[0]));
      EXPECT_GT(out.riverHeight[path.cells[0]], out.riverHeight[path.junction]);
      EXPECT_TRUE(joins) << "tributary " << r;
      EXPECT_EQ(path.level, out.rivers[path.parent].level + 1);
    }
    for (std::size_t k = 1; k < path.cells.size(); ++k)
    {
      EXPECT_TRUE(adjacent(path.cells[k - 1], path.cells[k]));
      EXPECT_GT(out.riverHeight[path.cells[k]], out.riverHeight[path.cells[k - 1]]);
    }
    for (int c : path.cells)
    {
      EXPECT_EQ(out.cls[c], RiverLandRiver);
      EXPECT_EQ(out.riverId[c], static_cast<int>(r));
      EXPECT_FLOAT_EQ(out.heightMeters[c], static_cast<float>(out.riverHeight[c]));
    }
  }
  EXPECT_GT(tributaries, 0);
  EXPECT_EQ(out.slopesApplied, 2);
  EXPECT_LE(out.medialAfter, out.medialBefore);
}

// Same seed: the same bits, on 1, 2 and 3 threads; another seed: another terrain.
TEST(RiverLand, SeedsAndThreadsGiveIdenticalBits)
{
  RiverLandParameters p = SmallIsland(11);
  RiverLand a, b;
  std::string error;
  ASSERT_TRUE(GenerateRiverLand(p, a, error));
  for (int threads : { 1, 2, 3 })
  {
    p.threads = threads;
    ASSERT_TRUE(GenerateRiverLand(p, b, error));
    ASSERT_EQ(a.heightMeters.size(), b.heightMeters.size());
    EXPECT_EQ(
      0, std::memcmp(a.heightMeters.data(), b.heightMeters.data(), a.heightMeters.size() * 4))
      << threads << " threads";
    EXPECT_EQ(a.medial, b.medial);
    EXPECT_EQ(a.target, b.target);
    EXPECT_EQ(a.riverId, b.riverId);
  }
  p.seed = 12;
  ASSERT_TRUE(GenerateRiverLand(p, b, error));
  EXPECT_NE(
    0, std::memcmp(a.heightMeters.data(), b.heightMeters.data(), a.heightMeters.size() * 4));
}

// Border mode: the whole map but its outer ring is land; mouths on that ring.
TEST(RiverLand, BorderModeUsesTheMapEdgeAsCoast)
{
  RiverLandParameters p;
  p.width = 120;
  p.height = 100;
  p.island = false;
  p.rivers = 6;
  RiverLand out;
  std::string error;
  ASSERT_TRUE(GenerateRiverLand(p, out, error)) << error;
  for (int j = 0; j < p.height; ++j)
  {
    for (int i = 0; i < p.width; ++i)
    {
      const bool ring = i == 0 || j == 0 || i == p.width - 1 || j == p.height - 1;
      EXPECT_EQ(out.cls[j * p.width + i] == RiverLandSea, ring);
    }
  }
  EXPECT_GE(out.rivers.size(), 6u);
}

// JSON: every key, slopes with profiles and custom curves; unknown keys, bad types and
// ranges refused with the key named.
TEST(RiverLand, ParametersFromJson)
{
  RiverLandParameters p;
  std::string error;
  ASSERT_TRUE(RiverLandParametersFromJson(
    R"({"seed": 5, "width": 64, "height": 48, "prune": false, "prune_threshold": 12,
        "hill_slope": 0.5, "island": false, "comment": "a test",
        "slopes": [{"x": 0.2, "y": 0.3, "profile": "cos2", "influence": 9},
                   {"profile": "custom", "curve": [[0, 0], [0.5, 0.9], [1, 1]]}]})",
    p,
    error))
    << error;
  EXPECT_EQ(p.seed, 5u);
  EXPECT_EQ(p.width, 64);
  EXPECT_EQ(p.height, 48);
  EXPECT_FALSE(p.prune);
  EXPECT_FALSE(p.island);
  EXPECT_EQ(p.pruneThreshold, 12.0);
  EXPECT_EQ(p.hillSlope, 0.5);
  ASSERT_EQ(p.slopes.size(), 2u);
  EXPECT_EQ(p.slopes[0].profile, SlopeProfile::Cos2);
  EXPECT_EQ(p.slopes[0].influence, 9.0);
  EXPECT_EQ(p.slopes[1].profile, SlopeProfile::Custom);
  EXPECT_EQ(p.slopes[1].curveY[1], 0.9);

  RiverLandParameters q;
  EXPECT_FALSE(RiverLandParametersFromJson(R"({"sead": 5})", q, error));
  EXPECT_NE(error.find("unknown parameter 'sead'"), std::string::npos) << error;
  EXPECT_FALSE(RiverLandParametersFromJson(R"({"width": 7})", q, error));
  EXPECT_NE(error.find("'width'"), std::string::npos) << error;
  EXPECT_FALSE(RiverLandParametersFromJson(R"({"prune": 1})", q, error));
  EXPECT_FALSE(RiverLandParametersFromJson(R"({"slopes": [{"profile": "sine"}]})", q, error));
  EXPECT_FALSE(RiverLandParametersFromJson(R"({"slopes": [{"colour": 1}]})", q, error));
  std::string curve = "[";
  for (int k = 0; k < 65; ++k)
    curve += (k ? "," : "") + std::string("[") + std::to_string(k / 64.0) + ",0.5]";
  curve += "]";
  EXPECT_FALSE(RiverLandParametersFromJson(
    R"({"slopes": [{"profile": "custom", "curve": )" + curve + "}]}", q, error));
  EXPECT_NE(error.find("2 to 64"), std::string::npos) << error;
  EXPECT_FALSE(RiverLandParametersFromJson("[1, 2]", q, error));
  EXPECT_FALSE(RiverLandParametersFromJson("{", q, error));
  EXPECT_FALSE(RiverLandParametersFromJson(R"({"roughness": 1.0})", q, error));
}

// Unit tests of the river scoring core (no VTK, no GL): terroir::hydrology::ScoreRivers,
// LengthMatchingThreshold and RiverComparisonCategories. Rasters are drawn north row first in
// the source (as on a map) and stored with j = 0 in the south: '.' no river, 'r' reference
// only, 's' simulated only, 'b' both. Every expected number is worked out by hand in the
// comments, or comes from an independent brute force over all pairs of cells.
#include "RiverValidation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{
using terroir::GridView;
namespace hy = terroir::hydrology;

const double kInf = std::numeric_limits<double>::infinity();
const double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Reference and simulated rasters with their storage, drawn north row first.
struct Rivers
{
  std::vector<std::uint8_t> reference;
  std::vector<std::uint8_t> simulated;
  std::vector<double> rowDx;
  std::vector<double> rowDy;
  GridView<std::uint8_t> view;

  Rivers(double dx, double dy, const std::vector<std::string>& rows)
  {
    const int ny = static_cast<int>(rows.size());
    const int nx = static_cast<int>(rows[0].size());
    reference.assign(static_cast<std::size_t>(nx) * ny, 0);
    simulated.assign(reference.size(), 0);
    view.nx = nx;
    view.ny = ny;
    view.dx = dx;
    view.dy = dy;
    for (int j = 0; j < ny; ++j)
    {
      const std::string& row = rows[ny - 1 - j];
      for (int i = 0; i < nx; ++i)
      {
        const char c = row[i];
        reference[view.Index(i, j)] = (c == 'r' || c == 'b') ? 1 : 0;
        simulated[view.Index(i, j)] = (c == 's' || c == 'b') ? 1 : 0;
      }
    }
    view.data = reference.data();
  }
  void SetRowSpacing(const std::vector<double>& dxs, const std::vector<double>& dys)
  {
    rowDx = dxs;
    rowDy = dys;
    view.rowDx = rowDx.data();
    view.rowDy = rowDy.data();
  }
  hy::RiverScores Score(double tolerance, const std::uint8_t* area = nullptr) const
  {
    return hy::ScoreRivers(view, simulated.data(), area, tolerance);
  }
  std::vector<std::uint8_t> Categories(double tolerance, const std::uint8_t* area = nullptr) const
  {
    std::vector<std::uint8_t> c(reference.size(), 99);
    hy::RiverComparisonCategories(view, simulated.data(), area, tolerance, c.data());
    return c;
  }
};

/// A byte mask drawn north row first: '1' inside, anything else outside.
std::vector<std::uint8_t> Mask(const std::vector<std::string>& rows)
{
  const int ny = static_cast<int>(rows.size());
  const int nx = static_cast<int>(rows[0].size());
  std::vector<std::uint8_t> m(static_cast<std::size_t>(nx) * ny, 0);
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      m[static_cast<std::size_t>(j) * nx + i] = rows[ny - 1 - j][i] == '1' ? 1 : 0;
    }
  }
  return m;
}

void ExpectScores(const hy::RiverScores& s,
  std::size_t simulatedCells,
  std::size_t simulatedHits,
  std::size_t referenceCells,
  std::size_t referenceHits)
{
  EXPECT_EQ(s.simulatedCells, simulatedCells);
  EXPECT_EQ(s.simulatedHits, simulatedHits);
  EXPECT_EQ(s.referenceCells, referenceCells);
  EXPECT_EQ(s.referenceHits, referenceHits);
}

/// Expects the categories drawn north row first ('0'..'3') cell for cell.
void ExpectCategories(const Rivers& r,
  const std::vector<std::uint8_t>& category,
  const std::vector<std::string>& expected)
{
  for (int j = 0; j < r.view.ny; ++j)
  {
    for (int i = 0; i < r.view.nx; ++i)
    {
      EXPECT_EQ(
        static_cast<int>(category[r.view.Index(i, j)]), expected[r.view.ny - 1 - j][i] - '0')
        << "cell (" << i << ", " << j << ")";
    }
  }
}

} // namespace

// A reference line in column 1 and a simulated line in column 3, 10 m cells: every simulated
// cell is 2 x 10 = 20 m from the nearest reference cell (same row) and vice versa. Within 30 m
// (and exactly 20 m: inclusive) all match: precision = recall = F1 = 1; within 10 m or 19.9 m
// nothing does: all 0.
TEST(RiverValidation, ParallelLinesTwoCellsApart)
{
  const Rivers r(10.0,
    10.0,
    {
      ".r.s.",
      ".r.s.",
      ".r.s.",
      ".r.s.",
    });
  hy::RiverScores s = r.Score(30.0);
  ExpectScores(s, 4, 4, 4, 4);
  EXPECT_EQ(s.toleranceMetres, 30.0);
  EXPECT_EQ(s.precision, 1.0);
  EXPECT_EQ(s.recall, 1.0);
  EXPECT_EQ(s.f1, 1.0);

  ExpectScores(r.Score(20.0), 4, 4, 4, 4);

  for (double tolerance : { 10.0, 19.9, 0.0 })
  {
    s = r.Score(tolerance);
    ExpectScores(s, 4, 0, 4, 0);
    EXPECT_EQ(s.precision, 0.0);
    EXPECT_EQ(s.recall, 0.0);
    EXPECT_EQ(s.f1, 0.0);
  }
}

// Within 10 m on 10 m cells. Reference (0..2, 1); simulated (2, 1), (3, 1), and (7, 0), (8, 0)
// far away. Simulated hits: (2, 1) (same cell), (3, 1) (10 m from (2, 1)); (7, 0) is
// sqrt(50^2 + 10^2) from (2, 1): no; (8, 0) no. Precision 2/4 = 1/2. Reference hits: (1, 1)
// (10 m from (2, 1)), (2, 1); (0, 1) is 20 m from (2, 1): no. Recall 2/3.
// F1 = 2 (1/2)(2/3) / (1/2 + 2/3) = (2/3) / (7/6) = 4/7.
TEST(RiverValidation, PartialOverlapGivesPrecisionHalfAndRecallTwoThirds)
{
  const Rivers r(10.0,
    10.0,
    {
      "rrbs.....",
      ".......ss",
    });
  const hy::RiverScores s = r.Score(10.0);
  ExpectScores(s, 4, 2, 3, 2);
  EXPECT_DOUBLE_EQ(s.precision, 0.5);
  EXPECT_DOUBLE_EQ(s.recall, 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(s.f1, 4.0 / 7.0);

  // Within 0 m only the shared cell (2, 1) matches: precision 1/4, recall 1/3,
  // F1 = 2 (1/4)(1/3) / (7/12) = (1/6) / (7/12) = 2/7.
  const hy::RiverScores same = r.Score(0.0);
  ExpectScores(same, 4, 1, 3, 1);
  EXPECT_DOUBLE_EQ(same.precision, 0.25);
  EXPECT_DOUBLE_EQ(same.recall, 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(same.f1, 2.0 / 7.0);
}

// Diagonal neighbours on 10 m cells are sqrt(2) x 10 = 14.142 m apart: inside 15 m, outside
// 14 m. Two diagonal steps, 28.284 m: outside 28 m, inside 28.3 m.
TEST(RiverValidation, DiagonalDistanceIsEuclidean)
{
  const Rivers one(10.0,
    10.0,
    {
      "...",
      "..s",
      ".r.",
    });
  ExpectScores(one.Score(15.0), 1, 1, 1, 1);
  ExpectScores(one.Score(14.0), 1, 0, 1, 0);

  const Rivers two(10.0,
    10.0,
    {
      "..s",
      "...",
      "r..",
    });
  ExpectScores(two.Score(28.0), 1, 0, 1, 0);
  ExpectScores(two.Score(28.3), 1, 1, 1, 1);
}

// dx = 10 m east-west, dy = 30 m north-south. Reference (0, 0); simulated (2, 0): 20 m,
// (3, 0): 30 m, (0, 1): 30 m, (1, 1): sqrt(10^2 + 30^2) = 31.62 m. Within 25 m only (2, 0)
// matches (had dx and dy been swapped it would be 60 m away and (0, 1) 10 m): precision 1/4;
// the reference cell is matched: recall 1. Within 30 m: (2, 0), (3, 0), (0, 1): 3/4.
// Within 31.6 m still 3/4, within 31.7 m all 4.
TEST(RiverValidation, AnisotropicSpacing)
{
  const Rivers r(10.0,
    30.0,
    {
      "ss..",
      "r.ss",
    });
  hy::RiverScores s = r.Score(25.0);
  ExpectScores(s, 4, 1, 1, 1);
  EXPECT_DOUBLE_EQ(s.precision, 0.25);
  EXPECT_DOUBLE_EQ(s.recall, 1.0);
  EXPECT_DOUBLE_EQ(s.f1, 2.0 * 0.25 / 1.25);
  ExpectScores(r.Score(30.0), 4, 3, 1, 1);
  ExpectScores(r.Score(31.6), 4, 3, 1, 1);
  ExpectScores(r.Score(31.7), 4, 4, 1, 1);
  ExpectScores(r.Score(9.9), 4, 0, 1, 0);
}

// Per-row spacing (a geographic grid): rowDx = 10, 20, 30 m and rowDy = 10, 10, 20 m for rows
// j = 0, 1, 2. Centre-to-centre steps north: row 0 -> 1 (10 + 10)/2 = 10 m, row 1 -> 2
// (10 + 20)/2 = 15 m, so rows 0 and 2 are 25 m apart. One column step between rows j and k is
// (dx_j + dx_k)/2. Each case has one reference and one simulated cell:
//   (0, 0) and (1, 1): sqrt(15^2 + 10^2) = sqrt(325) = 18.03 m (with dx = 10 everywhere it
//                      would be 14.14 m);
//   (0, 2) and (2, 2): 2 x 30 = 60 m;
//   (0, 0) and (0, 2): 25 m;
//   (0, 0) and (3, 2): 3 x (10 + 30)/2 = 60 m east, 25 m north: sqrt(3600 + 625) = 65 m,
//                      the same whichever of the two is the reference (symmetric).
TEST(RiverValidation, PerRowSpacing)
{
  struct Case
  {
    std::vector<std::string> rows;
    double distance;
  };
  const std::vector<Case> cases = {
    { { "....", ".s..", "r..." }, std::sqrt(325.0) },
    { { "r.s.", "....", "...." }, 60.0 },
    { { "s...", "....", "r..." }, 25.0 },
    { { "...s", "....", "r..." }, 65.0 },
    { { "...r", "....", "s..." }, 65.0 },
  };
  for (const Case& c : cases)
  {
    Rivers r(1.0, 1.0, c.rows); // dx, dy replaced by the per-row spacings
    r.SetRowSpacing({ 10.0, 20.0, 30.0 }, { 10.0, 10.0, 20.0 });
    ExpectScores(r.Score(c.distance + 0.01), 1, 1, 1, 1);
    ExpectScores(r.Score(c.distance - 0.01), 1, 0, 1, 0);
  }
  // Exact distances are inclusive: 25 m and 60 m and 65 m sums and products are exact here.
  Rivers exact(1.0, 1.0, { "...s", "....", "r..." });
  exact.SetRowSpacing({ 10.0, 20.0, 30.0 }, { 10.0, 10.0, 20.0 });
  ExpectScores(exact.Score(65.0), 1, 1, 1, 1);
}

// Only cells inside the area count, as candidates and as partners. One row of 10 m cells:
// reference at 0 and 1, simulated at 2 and 5; the area leaves out cells 1 and 5.
// With the area: simulated cells inside: {2}; its nearest reference inside is 0, 20 m away:
// no hit within 10 m (cell 1, 10 m away, is outside). Reference inside: {0}, nearest simulated
// inside is 2, 20 m: no hit. P = R = F1 = 0. Within 20 m both hit: 1, 1, 1.
// Without the area: simulated {2, 5}: 2 hits (cell 1), 5 does not: P = 1/2; reference {0, 1}:
// 1 hits (cell 2), 0 does not (20 m): R = 1/2.
TEST(RiverValidation, AreaExcludesCandidatesAndPartners)
{
  const Rivers r(10.0, 10.0, { "rrs..s" });
  const std::vector<std::uint8_t> area = Mask({ "101110" });
  hy::RiverScores s = r.Score(10.0, area.data());
  ExpectScores(s, 1, 0, 1, 0);
  EXPECT_EQ(s.precision, 0.0);
  EXPECT_EQ(s.recall, 0.0);
  EXPECT_EQ(s.f1, 0.0);
  ExpectScores(r.Score(20.0, area.data()), 1, 1, 1, 1);

  s = r.Score(10.0);
  ExpectScores(s, 2, 1, 2, 1);
  EXPECT_DOUBLE_EQ(s.precision, 0.5);
  EXPECT_DOUBLE_EQ(s.recall, 0.5);
  EXPECT_DOUBLE_EQ(s.f1, 0.5);

  // The reference view's validity mask (no data) acts like the area.
  Rivers masked(10.0, 10.0, { "rrs..s" });
  masked.view.valid = area.data();
  ExpectScores(masked.Score(10.0), 1, 0, 1, 0);
}

// Empty cases give 0, never NaN: no simulated cell -> precision 0 (recall 0: nothing found);
// no reference cell -> recall 0 and precision 0 (nothing to hit); neither -> all 0; an empty
// grid -> all 0.
TEST(RiverValidation, EmptyCasesScoreZero)
{
  const Rivers noSimulated(10.0, 10.0, { "rr..", "...." });
  hy::RiverScores s = noSimulated.Score(60.0);
  ExpectScores(s, 0, 0, 2, 0);
  EXPECT_EQ(s.precision, 0.0);
  EXPECT_EQ(s.recall, 0.0);
  EXPECT_EQ(s.f1, 0.0);

  const Rivers noReference(10.0, 10.0, { "ss..", "...." });
  s = noReference.Score(60.0);
  ExpectScores(s, 2, 0, 0, 0);
  EXPECT_EQ(s.precision, 0.0);
  EXPECT_EQ(s.recall, 0.0);
  EXPECT_EQ(s.f1, 0.0);

  const Rivers nothing(10.0, 10.0, { "....", "...." });
  s = nothing.Score(60.0);
  ExpectScores(s, 0, 0, 0, 0);
  EXPECT_EQ(s.f1, 0.0);

  GridView<std::uint8_t> empty;
  s = hy::ScoreRivers(empty, nullptr, nullptr, 30.0);
  ExpectScores(s, 0, 0, 0, 0);
  EXPECT_EQ(s.f1, 0.0);
  hy::RiverComparisonCategories(empty, nullptr, nullptr, 30.0, nullptr);
}

TEST(RiverValidation, BadArgumentsThrow)
{
  const Rivers r(10.0, 10.0, { "rs" });
  EXPECT_THROW(r.Score(-1.0), std::invalid_argument);
  EXPECT_THROW(r.Score(kNaN), std::invalid_argument);
  EXPECT_THROW(r.Score(kInf), std::invalid_argument);
  EXPECT_THROW(hy::ScoreRivers(r.view, nullptr, nullptr, 10.0), std::invalid_argument);
  Rivers flat(0.0, 10.0, { "rs" });
  EXPECT_THROW(flat.Score(10.0), std::invalid_argument);
  EXPECT_THROW(hy::RiverComparisonCategories(r.view, r.simulated.data(), nullptr, 10.0, nullptr),
    std::invalid_argument);
  Rivers rows(1.0, 1.0, { "rs" });
  rows.SetRowSpacing({ -10.0 }, { 10.0 });
  EXPECT_THROW(rows.Score(10.0), std::invalid_argument);
}

// Categories within 10 m on 10 m cells, cell by cell:
//   (0, 3) r: nearest simulated (2, 1) is sqrt(20^2 + 20^2) = 28.3 m away -> 1 mapped only
//   (0, 2) r: (2, 1) is sqrt(20^2 + 10^2) = 22.4 m away                    -> 1
//   (1, 1) r: (2, 1) is 10 m away                                          -> 3 both
//   (2, 0) b: reference and simulated in the same cell                     -> 3
//   (2, 1) s: reference (1, 1) 10 m away                                   -> 3
//   (5, 3) s: nearest reference (0, 3) 50 m away                           -> 2 simulated only
// Every other cell is 0.
TEST(RiverValidation, CategoriesCellByCell)
{
  const Rivers r(10.0,
    10.0,
    {
      "r....s",
      "r.....",
      ".rs...",
      "..b...",
    });
  ExpectCategories(r,
    r.Categories(10.0),
    {
      "100002",
      "100000",
      "033000",
      "003000",
    });

  // The area leaves out (1, 1) and (2, 0): both become 0, and they are no partners any more:
  // (2, 1) keeps no reference within 10 m (the nearest inside, (0, 2), is 22.4 m away) -> 2.
  const std::vector<std::uint8_t> area = Mask({
    "111111",
    "111111",
    "101111",
    "110111",
  });
  ExpectCategories(r,
    r.Categories(10.0, area.data()),
    {
      "100002",
      "100000",
      "002000",
      "000000",
    });

  // Within 30 m, (0, 3) reaches (2, 1) (28.3 m) and (0, 2) too (22.4 m); (5, 3) reaches no
  // reference (the nearest is (2, 0), sqrt(30^2 + 30^2) = 42.4 m away).
  ExpectCategories(r,
    r.Categories(30.0),
    {
      "300002",
      "300000",
      "033000",
      "003000",
    });
}

namespace
{
/// Independent brute force over all pairs: the distance of RiverValidation.h written out
/// directly (northing of a row = sum of the half steps from row 0; column step = the mean of
/// the two rows' east-west spacings).
struct BruteForce
{
  std::size_t simulatedCells = 0, simulatedHits = 0, referenceCells = 0, referenceHits = 0;
  std::vector<std::uint8_t> category;
};

BruteForce BruteForceScores(const GridView<std::uint8_t>& g,
  const std::uint8_t* sim,
  const std::uint8_t* area,
  double tolerance)
{
  const int nx = g.nx;
  const int ny = g.ny;
  auto dxOf = [&](int j) { return g.rowDx ? g.rowDx[j] : g.dx; };
  auto dyOf = [&](int j) { return g.rowDy ? g.rowDy[j] : g.dy; };
  std::vector<double> y(ny, 0.0);
  for (int j = 1; j < ny; ++j)
  {
    y[j] = g.rowDy ? y[j - 1] + 0.5 * (dyOf(j - 1) + dyOf(j)) : j * g.dy;
  }
  auto within = [&](int i0, int j0, int i1, int j1)
  {
    const double ex = std::abs(i0 - i1) * 0.5 * (dxOf(j0) + dxOf(j1));
    const double ns = std::abs(y[j0] - y[j1]);
    return ex * ex + ns * ns <= tolerance * tolerance * (1.0 + 2e-9);
  };
  const std::size_t n = g.Size();
  std::vector<std::uint8_t> inside(n);
  for (std::size_t c = 0; c < n; ++c)
  {
    inside[c] = (!area || area[c]) && (!g.valid || g.valid[c]);
  }
  BruteForce b;
  b.category.assign(n, 0);
  for (int j0 = 0; j0 < ny; ++j0)
  {
    for (int i0 = 0; i0 < nx; ++i0)
    {
      const std::size_t c0 = g.Index(i0, j0);
      if (!inside[c0] || (!g.data[c0] && !sim[c0]))
      {
        continue;
      }
      bool refHit = false;
      bool simHit = false;
      for (int j1 = 0; j1 < ny; ++j1)
      {
        for (int i1 = 0; i1 < nx; ++i1)
        {
          const std::size_t c1 = g.Index(i1, j1);
          if (!inside[c1] || !within(i0, j0, i1, j1))
          {
            continue;
          }
          refHit = refHit || (g.data[c0] && sim[c1]);
          simHit = simHit || (sim[c0] && g.data[c1]);
        }
      }
      b.referenceCells += g.data[c0] ? 1 : 0;
      b.simulatedCells += sim[c0] ? 1 : 0;
      b.referenceHits += refHit ? 1 : 0;
      b.simulatedHits += simHit ? 1 : 0;
      b.category[c0] = (refHit || simHit) ? 3 : (g.data[c0] ? 1 : 2);
    }
  }
  return b;
}
} // namespace

// ScoreRivers and RiverComparisonCategories against the brute force on 60 random rasters
// (fixed mt19937_64 seed, own value mapping): sizes 1..24 x 1..18, river densities 2-30 %,
// random areas, constant spacing (dx != dy) or per-row spacing, tolerances from 0 to 70 m.
TEST(RiverValidation, MatchesBruteForceOnRandomRasters)
{
  std::mt19937_64 rng(20240601);
  auto below = [&rng](std::uint64_t n) { return static_cast<int>((rng() >> 16) % n); };
  const double tolerances[] = { 0.0, 7.5, 10.0, 14.0, 15.0, 22.0, 30.0, 45.5, 60.0, 70.0 };
  for (int trial = 0; trial < 60; ++trial)
  {
    const int nx = 1 + below(24);
    const int ny = 1 + below(18);
    const std::size_t n = static_cast<std::size_t>(nx) * ny;
    const int refPercent = 2 + below(29);
    const int simPercent = 2 + below(29);
    std::vector<std::uint8_t> ref(n), sim(n), area(n);
    for (std::size_t c = 0; c < n; ++c)
    {
      ref[c] = below(100) < refPercent ? static_cast<std::uint8_t>(1 + below(255)) : 0;
      sim[c] = below(100) < simPercent ? 1 : 0;
      area[c] = below(100) < 85 ? 1 : 0;
    }
    std::vector<double> rowDx(ny), rowDy(ny);
    for (int j = 0; j < ny; ++j)
    {
      rowDx[j] = 8.0 + 0.25 * below(16); // 8 .. 11.75 m
      rowDy[j] = 9.0 + 0.5 * below(6);   // 9 .. 11.5 m
    }
    GridView<std::uint8_t> g;
    g.data = ref.data();
    g.nx = nx;
    g.ny = ny;
    g.dx = 10.0;
    g.dy = 7.5;
    if (trial % 3 == 2)
    {
      g.rowDx = rowDx.data();
      g.rowDy = rowDy.data();
    }
    const std::uint8_t* areaPtr = trial % 2 ? area.data() : nullptr;
    for (double tolerance : tolerances)
    {
      SCOPED_TRACE("trial " + std::to_string(trial) + ", tolerance " + std::to_string(tolerance));
      const BruteForce b = BruteForceScores(g, sim.data(), areaPtr, tolerance);
      const hy::RiverScores s = hy::ScoreRivers(g, sim.data(), areaPtr, tolerance);
      ExpectScores(s, b.simulatedCells, b.simulatedHits, b.referenceCells, b.referenceHits);
      const double p = b.simulatedCells ? double(b.simulatedHits) / b.simulatedCells : 0.0;
      const double r = b.referenceCells ? double(b.referenceHits) / b.referenceCells : 0.0;
      EXPECT_DOUBLE_EQ(s.precision, p);
      EXPECT_DOUBLE_EQ(s.recall, r);
      EXPECT_DOUBLE_EQ(s.f1, p + r > 0.0 ? 2.0 * p * r / (p + r) : 0.0);
      std::vector<std::uint8_t> category(n, 99);
      hy::RiverComparisonCategories(g, sim.data(), areaPtr, tolerance, category.data());
      EXPECT_EQ(category, b.category);
    }
  }
}

// ---- LengthMatchingThreshold -------------------------------------------------------------

namespace
{
struct Values
{
  std::vector<double> value;
  std::vector<std::uint8_t> reference;
  GridView<double> view;

  Values(const std::vector<double>& v, std::size_t referenceCells)
    : value(v)
    , reference(v.size(), 0)
  {
    // The reference cells are simply the first ones: where they lie does not matter.
    std::fill(reference.begin(), reference.begin() + referenceCells, 1);
    view.data = value.data();
    view.nx = static_cast<int>(v.size());
    view.ny = 1;
  }
  double Threshold(std::size_t* count, const std::uint8_t* area = nullptr) const
  {
    return hy::LengthMatchingThreshold(view, reference.data(), area, count);
  }
};
} // namespace

// Values 5 3 9 1 7 8 2 6 (no ties). With k reference cells the threshold is the k-th largest:
// k = 3 -> 9, 8, 7 -> t = 7 (3 cells); k = 1 -> 9; k = 8 -> 1 (all cells).
TEST(LengthMatchingThreshold, KthLargestWithoutTies)
{
  const std::vector<double> v = { 5, 3, 9, 1, 7, 8, 2, 6 };
  std::size_t count = 99;
  EXPECT_EQ(Values(v, 3).Threshold(&count), 7.0);
  EXPECT_EQ(count, 3u);
  EXPECT_EQ(Values(v, 1).Threshold(&count), 9.0);
  EXPECT_EQ(count, 1u);
  EXPECT_EQ(Values(v, 8).Threshold(&count), 1.0);
  EXPECT_EQ(count, 8u);
  EXPECT_EQ(Values(v, 5).Threshold(nullptr), 5.0);
}

// Values 9 4 4 4 1 (descending). k = 2: t = 4 counts 4 (2 too many), t = 9 counts 1 (1 too
// few): 9 is closer -> t = 9, 1 cell. k = 3: t = 4 counts 4 (1 too many), t = 9 counts 1 (2
// too few) -> t = 4, 4 cells. k = 4: exact, t = 4.
TEST(LengthMatchingThreshold, TiesPickTheClosestCount)
{
  const std::vector<double> v = { 4, 1, 9, 4, 4 };
  std::size_t count = 99;
  EXPECT_EQ(Values(v, 2).Threshold(&count), 9.0);
  EXPECT_EQ(count, 1u);
  EXPECT_EQ(Values(v, 3).Threshold(&count), 4.0);
  EXPECT_EQ(count, 4u);
  EXPECT_EQ(Values(v, 4).Threshold(&count), 4.0);
  EXPECT_EQ(count, 4u);
  EXPECT_EQ(Values(v, 5).Threshold(&count), 1.0);
  EXPECT_EQ(count, 5u);
}

// Values 9 4 4 1, k = 2: t = 4 counts 3 (1 too many), t = 9 counts 1 (1 too few): equally
// close, the larger threshold wins -> 9, 1 cell. All values equal (2 2 2 2 2): k = 1 -> t = 2
// counts 5 (4 too many), nothing above counts 0 (1 too few) -> +inf, 0 cells; k = 3 -> 5 is 2
// too many, 0 is 3 too few -> t = 2, 5 cells.
TEST(LengthMatchingThreshold, EqualDistanceTiesPickTheLargerThreshold)
{
  std::size_t count = 99;
  EXPECT_EQ(Values({ 4, 9, 1, 4 }, 2).Threshold(&count), 9.0);
  EXPECT_EQ(count, 1u);
  const std::vector<double> flat = { 2, 2, 2, 2, 2 };
  EXPECT_EQ(Values(flat, 1).Threshold(&count), kInf);
  EXPECT_EQ(count, 0u);
  EXPECT_EQ(Values(flat, 3).Threshold(&count), 2.0);
  EXPECT_EQ(count, 5u);
}

// Non-finite values never count, and fewer finite values than reference cells give the
// smallest finite value (every finite cell). Values NaN 5 +inf 3 -inf 8: finite 5 3 8.
// k = 2 -> 8, 5 -> t = 5; k = 4 (more than the 3 finite values) -> t = 3, 3 cells.
// No reference cell, or no finite value -> +inf, 0 cells.
TEST(LengthMatchingThreshold, NonFiniteValuesAndEmptyCases)
{
  const std::vector<double> v = { kNaN, 5, kInf, 3, -kInf, 8 };
  std::size_t count = 99;
  EXPECT_EQ(Values(v, 2).Threshold(&count), 5.0);
  EXPECT_EQ(count, 2u);
  EXPECT_EQ(Values(v, 4).Threshold(&count), 3.0);
  EXPECT_EQ(count, 3u);
  count = 99;
  EXPECT_EQ(Values(v, 0).Threshold(&count), kInf);
  EXPECT_EQ(count, 0u);
  count = 99;
  EXPECT_EQ(Values({ kNaN, kNaN }, 1).Threshold(&count), kInf);
  EXPECT_EQ(count, 0u);
  GridView<double> empty;
  EXPECT_EQ(hy::LengthMatchingThreshold(empty, nullptr, nullptr, &count), kInf);
  EXPECT_EQ(count, 0u);
  GridView<double> noData;
  noData.nx = 2;
  noData.ny = 1;
  const std::uint8_t ref[2] = { 1, 1 };
  EXPECT_THROW(hy::LengthMatchingThreshold(noData, ref, nullptr), std::invalid_argument);
}

// The area limits both counts. Values 10 20 30 40 50 60, reference cells 0, 1, 2 (values 10,
// 20, 30); the area leaves out cells 1 and 5 (20 and 60). Reference cells inside: 0 and 2,
// k = 2; values inside: 10 30 40 50 -> the two largest are 50, 40 -> t = 40, 2 cells. The
// value view's validity mask acts the same way.
TEST(LengthMatchingThreshold, AreaLimitsReferenceAndValues)
{
  Values v({ 10, 20, 30, 40, 50, 60 }, 3);
  const std::uint8_t area[6] = { 1, 0, 1, 1, 1, 0 };
  std::size_t count = 99;
  EXPECT_EQ(v.Threshold(&count, area), 40.0);
  EXPECT_EQ(count, 2u);
  EXPECT_EQ(v.Threshold(&count), 40.0); // without the area: k = 3 -> 60 50 40
  EXPECT_EQ(count, 3u);
  v.view.valid = area;
  EXPECT_EQ(v.Threshold(&count), 40.0);
  EXPECT_EQ(count, 2u);
}

// The float overload returns one of the float values (0.1f is not 0.1). Values 0.3 0.1 0.2
// 0.1 (float), k = 2: 0.3, 0.2 -> t = 0.2f; k = 3: t = 0.1f counts 4 (1 too many), t = 0.2f
// counts 2 (1 too few): equal, the larger wins -> 0.2f, 2 cells.
TEST(LengthMatchingThreshold, FloatValues)
{
  const std::vector<float> v = { 0.3f, 0.1f, 0.2f, 0.1f };
  std::vector<std::uint8_t> ref = { 1, 1, 0, 0 };
  GridView<float> g;
  g.data = v.data();
  g.nx = 2;
  g.ny = 2;
  std::size_t count = 99;
  EXPECT_EQ(hy::LengthMatchingThreshold(g, ref.data(), nullptr, &count), double(0.2f));
  EXPECT_EQ(count, 2u);
  ref[2] = 1;
  EXPECT_EQ(hy::LengthMatchingThreshold(g, ref.data(), nullptr, &count), double(0.2f));
  EXPECT_EQ(count, 2u);
}

// Against a brute force over every candidate threshold (each distinct value and +inf): the
// count closest to k, ties to the larger threshold. Values are small integers, so ties are
// frequent; some are NaN; random areas. Fixed mt19937_64 seed.
TEST(LengthMatchingThreshold, MatchesBruteForceOnRandomValues)
{
  std::mt19937_64 rng(19700101);
  auto below = [&rng](std::uint64_t n) { return static_cast<int>((rng() >> 16) % n); };
  for (int trial = 0; trial < 300; ++trial)
  {
    const int n = 1 + below(40);
    std::vector<double> value(n);
    std::vector<std::uint8_t> ref(n), area(n);
    for (int c = 0; c < n; ++c)
    {
      value[c] = below(10) == 0 ? kNaN : static_cast<double>(below(8));
      ref[c] = below(100) < 30 ? 1 : 0;
      area[c] = below(100) < 80 ? 1 : 0;
    }
    const std::uint8_t* areaPtr = trial % 2 ? area.data() : nullptr;
    std::size_t k = 0;
    std::vector<double> candidates = { kInf };
    for (int c = 0; c < n; ++c)
    {
      if (areaPtr && !areaPtr[c])
      {
        continue;
      }
      k += ref[c];
      if (std::isfinite(value[c]))
      {
        candidates.push_back(value[c]);
      }
    }
    double best = kInf;
    std::size_t bestCount = 0;
    if (k > 0)
    {
      std::size_t bestGap = std::numeric_limits<std::size_t>::max();
      for (double t : candidates)
      {
        std::size_t cnt = 0;
        for (int c = 0; c < n; ++c)
        {
          cnt += (!areaPtr || areaPtr[c]) && std::isfinite(value[c]) && value[c] >= t;
        }
        const std::size_t gap = cnt > k ? cnt - k : k - cnt;
        if (gap < bestGap || (gap == bestGap && t > best))
        {
          best = t;
          bestGap = gap;
          bestCount = cnt;
        }
      }
    }
    GridView<double> g;
    g.data = value.data();
    g.nx = n;
    g.ny = 1;
    std::size_t count = 99;
    SCOPED_TRACE("trial " + std::to_string(trial));
    EXPECT_EQ(hy::LengthMatchingThreshold(g, ref.data(), areaPtr, &count), best);
    EXPECT_EQ(count, bestCount);
  }
}

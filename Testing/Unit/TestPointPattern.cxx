// Unit tests of the point-pattern core (terroir::clustering, Filters/Clustering/Core/
// PointPattern.h): set covariance and pair measure against closed forms, the pair-correlation
// estimate on patterns whose g is known (Poisson: 1; hard core: 0 below d0; a square lattice:
// worked out by hand), and the Metropolis-Hastings synthesis reproducing exemplars.
//
// Statistical tolerances. For n independent uniform points the estimate is unbiased
// (E[g(k)] = 1) and bin k holds U_k unordered pairs, close to Poisson distributed when a point
// has few neighbours per bin, so sd(g(k)) ~ 1 / sqrt(U_k) = sqrt(2 / N_k), N_k the ordered pair
// count that the estimate reports. A test allows 4 such standard deviations per bin (a false
// alarm once in ~16,000 bins for a random seed; the seeds here are fixed) and checks the
// chi-square of all bins against its mean K and standard deviation sqrt(2K).
//
// Random patterns come from std::mt19937_64 with our own mapping to doubles (the standard
// distributions differ between libraries).
#include "PointPattern.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace
{
namespace pp = terroir::clustering;
using Points = std::vector<pp::PatternPoint>;

constexpr double Pi = 3.14159265358979323846;

double Uniform(std::mt19937_64& rng)
{
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

/// Poisson-distributed count (Knuth's product of uniforms; means below ~700).
int PoissonCount(std::mt19937_64& rng, double mean)
{
  const double limit = std::exp(-mean);
  double product = Uniform(rng);
  int k = 0;
  while (product > limit)
  {
    product *= Uniform(rng);
    ++k;
  }
  return k;
}

/// Standard normal (Box-Muller).
double Normal(std::mt19937_64& rng)
{
  const double u = 1.0 - Uniform(rng);
  const double v = Uniform(rng);
  return std::sqrt(-2.0 * std::log(u)) * std::cos(2.0 * Pi * v);
}

/// n independent uniform points in [0, w) x [0, h) (a binomial process).
Points Binomial(std::mt19937_64& rng, int n, double w, double h, int category = 0)
{
  Points points;
  for (int i = 0; i < n; ++i)
  {
    points.push_back({ Uniform(rng) * w, Uniform(rng) * h, category });
  }
  return points;
}

/// Smallest distance between points of categories a and b (a brute-force O(n^2) scan).
double SmallestDistance(const Points& points, int a, int b)
{
  double best = INFINITY;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    for (std::size_t j = 0; j < points.size(); ++j)
    {
      if (i != j && points[i].category == a && points[j].category == b)
      {
        best = std::min(best, std::hypot(points[i].x - points[j].x, points[i].y - points[j].y));
      }
    }
  }
  return best;
}

/**
 * Dart throwing (random sequential adsorption) in [0, w) x [0, h): candidates uniform, each
 * kept when no kept point of a category c with minimum[c * 2 + category] > 0 lies closer than
 * that; stops at `target` kept points or after `attempts` candidates. Categories alternate 0, 1
 * when `twoCategories`. Uses its own grid of cells (side = the largest minimum distance).
 */
Points DartThrowing(std::mt19937_64& rng,
  int target,
  double w,
  double h,
  const double minimum[4],
  bool twoCategories,
  int attempts = 2000000)
{
  const double side = std::max(std::max(minimum[0], minimum[1]), std::max(minimum[2], minimum[3]));
  const int nx = static_cast<int>(std::ceil(w / side));
  const int ny = static_cast<int>(std::ceil(h / side));
  std::vector<std::vector<int>> grid(static_cast<std::size_t>(nx) * ny);
  Points points;
  for (int t = 0; t < attempts && static_cast<int>(points.size()) < target; ++t)
  {
    const pp::PatternPoint p{
      Uniform(rng) * w, Uniform(rng) * h, twoCategories ? static_cast<int>(points.size() % 2) : 0
    };
    const int i = static_cast<int>(p.x / side);
    const int j = static_cast<int>(p.y / side);
    bool free = true;
    for (int jj = std::max(0, j - 1); jj <= std::min(ny - 1, j + 1) && free; ++jj)
    {
      for (int ii = std::max(0, i - 1); ii <= std::min(nx - 1, i + 1) && free; ++ii)
      {
        for (int id : grid[static_cast<std::size_t>(jj) * nx + ii])
        {
          const double d = minimum[points[id].category * 2 + p.category];
          if (std::hypot(points[id].x - p.x, points[id].y - p.y) < d)
          {
            free = false;
            break;
          }
        }
      }
    }
    if (free)
    {
      grid[static_cast<std::size_t>(j) * nx + i].push_back(static_cast<int>(points.size()));
      points.push_back(p);
    }
  }
  return points;
}

/// Thomas cluster process in [0, w) x [0, h): parents Poisson(parentDensity) in the window grown
/// by 4 sigma, Poisson(children) children each, displaced by N(0, sigma^2) per axis; children
/// outside the window dropped. g(r) = 1 + exp(-r^2 / (4 sigma^2)) / (4 pi sigma^2 parentDensity)
/// (Illian et al. 2008, section 6.3.2).
Points Thomas(std::mt19937_64& rng,
  double parentDensity,
  double children,
  double sigma,
  double w,
  double h)
{
  const double m = 4.0 * sigma;
  const int parents = PoissonCount(rng, parentDensity * (w + 2 * m) * (h + 2 * m));
  Points points;
  for (int p = 0; p < parents; ++p)
  {
    const double px = -m + Uniform(rng) * (w + 2 * m);
    const double py = -m + Uniform(rng) * (h + 2 * m);
    const int n = PoissonCount(rng, children);
    for (int c = 0; c < n; ++c)
    {
      const double x = px + sigma * Normal(rng);
      const double y = py + sigma * Normal(rng);
      if (x >= 0 && x < w && y >= 0 && y < h)
      {
        points.push_back({ x, y, 0 });
      }
    }
  }
  return points;
}

int CountCategory(const Points& points, int c)
{
  return static_cast<int>(std::count_if(
    points.begin(), points.end(), [c](const pp::PatternPoint& p) { return p.category == c; }));
}

/// Statistical standard deviation of g(k) from its ordered pair count (see the file comment).
double CountSigma(const pp::PairCorrelation& pcf, int a, int b, int k)
{
  return std::sqrt(2.0 / std::max<double>(1.0, static_cast<double>(pcf.Pairs(a, b, k))));
}

/// Checks that g_ab is 1 within 4 sigma per bin and that its chi-square is below K + 4 sqrt(2K).
void ExpectPoisson(const pp::PairCorrelation& pcf, int a, int b)
{
  double chi2 = 0.0;
  for (int k = 0; k < pcf.bins; ++k)
  {
    const double sigma = CountSigma(pcf, a, b, k);
    EXPECT_NEAR(pcf.G(a, b, k), 1.0, 4.0 * sigma) << "bin " << k << " pair " << a << "-" << b;
    chi2 += std::pow((pcf.G(a, b, k) - 1.0) / sigma, 2);
  }
  EXPECT_LT(chi2, pcf.bins + 4.0 * std::sqrt(2.0 * pcf.bins)) << "pair " << a << "-" << b;
}

// =============================================================================================
// Domain, set covariance, pair measure

TEST(TerroirPointPattern, CellsDomainAreaAndContains)
{
  // 3 x 2 cells of 2 m x 1 m from (10, 20); allowed: (0,0), (2,0), (1,1).
  const auto d = pp::PatternDomain::Cells(3, 2, 2.0, 1.0, 10.0, 20.0, { 1, 0, 1, 0, 1, 0 });
  EXPECT_DOUBLE_EQ(d.Area(), 3 * 2.0);
  EXPECT_TRUE(d.Contains(10.0, 20.0));
  EXPECT_TRUE(d.Contains(11.99, 20.5));
  EXPECT_FALSE(d.Contains(12.0, 20.5)); // cell (1, 0)
  EXPECT_TRUE(d.Contains(14.5, 20.999));
  EXPECT_TRUE(d.Contains(13.0, 21.5));  // cell (1, 1)
  EXPECT_FALSE(d.Contains(15.0, 21.5)); // cell (2, 1)
  EXPECT_FALSE(d.Contains(16.0, 20.5)); // right of the grid
  EXPECT_FALSE(d.Contains(9.99, 20.5));
  const int labels[6] = { 7, 3, 7, 3, 3, 7 };
  const auto z = pp::PatternDomain::CellsWithLabel(3, 2, 2.0, 1.0, 10.0, 20.0, labels, 3);
  EXPECT_EQ(z.AllowedCellList(), (std::vector<std::uint32_t>{ 1, 3, 4 }));
}

TEST(TerroirPointPattern, RectangleSetCovarianceAndPairMeasureMatchClosedForms)
{
  // a x b rectangle: gamma(h) = (a - |hx|)(b - |hy|); for r <= min(a, b) the angular integral is
  // 2 pi a b - 4 r (a + b) + 2 r^2, so Gamma(r1, r2) = pi a b (r2^2 - r1^2)
  // - 4/3 (a + b)(r2^3 - r1^3) + 1/2 (r2^4 - r1^4).
  const double a = 30.0;
  const double b = 20.0;
  const auto d = pp::PatternDomain::Rectangle(5.0, -3.0, 5.0 + a, -3.0 + b);
  const pp::PatternSetCovariance cov(d, 15.0);
  EXPECT_DOUBLE_EQ(cov(0.0, 0.0), a * b);
  EXPECT_DOUBLE_EQ(cov(3.0, -4.0), (a - 3.0) * (b - 4.0));
  EXPECT_DOUBLE_EQ(cov(-31.0, 0.0), 0.0);
  const double edges[4][2] = { { 0.0, 1.0 }, { 2.5, 3.0 }, { 9.0, 15.0 }, { 0.0, 15.0 } };
  for (const auto& e : edges)
  {
    const double r1 = e[0];
    const double r2 = e[1];
    const double exact = Pi * a * b * (r2 * r2 - r1 * r1) -
      4.0 / 3.0 * (a + b) * (r2 * r2 * r2 - r1 * r1 * r1) +
      0.5 * (std::pow(r2, 4) - std::pow(r1, 4));
    EXPECT_NEAR(cov.PairMeasure(r1, r2), exact, 1e-7 * exact) << r1 << ".." << r2;
  }
}

TEST(TerroirPointPattern, FullMaskHasTheRectanglesCovariance)
{
  // A cells domain with every cell allowed is the rectangle of the grid: c(p, q) =
  // (nx - |p|)(ny - |q|), whose bilinear interpolation is exactly (a - |hx|)(b - |hy|).
  const int nx = 12;
  const int ny = 7;
  const auto cells =
    pp::PatternDomain::Cells(nx, ny, 2.5, 3.0, 1.0, 2.0, std::vector<std::uint8_t>(nx * ny, 1));
  const auto rect = pp::PatternDomain::Rectangle(1.0, 2.0, 1.0 + nx * 2.5, 2.0 + ny * 3.0);
  const pp::PatternSetCovariance cc(cells, 8.0);
  const pp::PatternSetCovariance rc(rect, 8.0);
  const double lags[5][2] = { { 0, 0 }, { 1.3, -2.2 }, { -7.9, 0.4 }, { 5.0, 6.0 }, { 0.1, 7.99 } };
  for (const auto& h : lags)
  {
    EXPECT_NEAR(cc(h[0], h[1]), rc(h[0], h[1]), 1e-9) << h[0] << ", " << h[1];
  }
  EXPECT_NEAR(cc.PairMeasure(2.0, 8.0), rc.PairMeasure(2.0, 8.0), 1e-6 * rc.PairMeasure(2.0, 8.0));
}

TEST(TerroirPointPattern, SeparateCellsCovariance)
{
  // Two allowed 1 m cells two cells apart, (0, 0) and (2, 0): gamma(h) is each cell's overlap
  // with itself, 2 (1 - |hx|)+(1 - |hy|)+, plus the overlaps of one with the other shifted by
  // (+-2, 0): (1 - |hx -+ 2|)+(1 - |hy|)+. So gamma(0.5, 0.25) = 2 * 0.5 * 0.75 = 0.75,
  // gamma(2.25, 0.5) = 0.75 * 0.5 = 0.375, gamma(1.5, 0) = 0.5 (from the shift 2), gamma(1, 0) = 0.
  const auto d = pp::PatternDomain::Cells(3, 1, 1.0, 1.0, 0.0, 0.0, { 1, 0, 1 });
  const pp::PatternSetCovariance cov(d, 3.0);
  EXPECT_DOUBLE_EQ(cov(0.5, 0.25), 0.75);
  EXPECT_DOUBLE_EQ(cov(-2.25, 0.5), 0.375);
  EXPECT_DOUBLE_EQ(cov(1.5, 0.0), 0.5);
  EXPECT_DOUBLE_EQ(cov(1.0, 0.0), 0.0);
  EXPECT_DOUBLE_EQ(cov(0.0, 0.0), 2.0);
}

// =============================================================================================
// Pair-correlation estimate

TEST(TerroirPointPattern, PairCorrelationOfPoissonIsOne)
{
  // 2000 uniform points in 100 m x 100 m, g in 20 bins to 10 m. The last bins hold ~12,000
  // ordered pairs (sd 1.3 %); without the edge correction they would read ~0.92 (a rectangle
  // loses a fraction 4 r (a + b) / (3 pi a b) ~ 8 % of its pairs at r = 10 m): 6 sd away.
  std::mt19937_64 rng(20260101);
  const Points points = Binomial(rng, 2000, 100.0, 100.0);
  const auto d = pp::PatternDomain::Rectangle(0, 0, 100, 100);
  const auto pcf = pp::EstimatePairCorrelation(points, d, { 0.0, 10.0, 20, 0 });
  ASSERT_EQ(pcf.categories, 1);
  EXPECT_EQ(pcf.counts[0], 2000);
  ExpectPoisson(pcf, 0, 0);
}

/// An L-shaped zone: 50 x 50 cells of 2 m, allowed where i < 20 or j < 20 (2400 m^2).
pp::PatternDomain LShapedZone()
{
  const int nx = 50;
  const int ny = 50;
  std::vector<std::uint8_t> allowed(nx * ny, 0);
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      allowed[j * nx + i] = (i < 20 || j < 20) ? 1 : 0;
    }
  }
  return pp::PatternDomain::Cells(nx, ny, 2.0, 2.0, 0.0, 0.0, allowed);
}

/// n uniform points in a domain (rejection from its bounding box).
Points UniformIn(std::mt19937_64& rng, const pp::PatternDomain& d, int n)
{
  const double* b = d.Bounds();
  Points points;
  while (static_cast<int>(points.size()) < n)
  {
    const double x = b[0] + Uniform(rng) * (b[2] - b[0]);
    const double y = b[1] + Uniform(rng) * (b[3] - b[1]);
    if (d.Contains(x, y))
    {
      points.push_back({ x, y, 0 });
    }
  }
  return points;
}

TEST(TerroirPointPattern, PairCorrelationOfPoissonOnMaskIsOne)
{
  // Uniform points on an L-shaped zone (the edge correction comes from the cells' set
  // covariance; without it the arms, 40 m wide, would lose up to ~25 % of the pairs at 12 m).
  // In such a domain the bins share a large common fluctuation (how many points sit near the
  // edges), so the count-based sd understates the error: the test averages R = 40 independent
  // patterns of 800 points and asks each bin's mean to be 1 within 4 standard errors measured
  // from the replicates themselves (sd / sqrt(R)).
  const auto d = LShapedZone();
  std::mt19937_64 rng(77);
  const int R = 40;
  const int bins = 11;
  std::vector<double> sum(bins, 0.0);
  std::vector<double> sum2(bins, 0.0);
  for (int rep = 0; rep < R; ++rep)
  {
    const auto pcf = pp::EstimatePairCorrelation(UniformIn(rng, d, 800), d, { 1.0, 12.0, bins, 0 });
    for (int k = 0; k < bins; ++k)
    {
      sum[k] += pcf.G(0, 0, k);
      sum2[k] += pcf.G(0, 0, k) * pcf.G(0, 0, k);
    }
  }
  for (int k = 0; k < bins; ++k)
  {
    const double mean = sum[k] / R;
    const double sd = std::sqrt((sum2[k] - R * mean * mean) / (R - 1));
    EXPECT_NEAR(mean, 1.0, 4.0 * sd / std::sqrt(double(R))) << "bin " << k << " sd " << sd;
  }
}

TEST(TerroirPointPattern, PairCorrelationOfHardCoreIsZeroBelowD0)
{
  // Dart throwing with d0 = 1 m: no pair is closer than d0, so every bin below d0 is exactly 0;
  // random sequential adsorption piles pairs up just beyond d0 (g > 1 there) and forgets d0
  // beyond a few d0 (g ~ 1).
  std::mt19937_64 rng(5);
  const double d0[4] = { 1.0, 1.0, 1.0, 1.0 };
  const Points points = DartThrowing(rng, 1500, 60.0, 60.0, d0, false);
  ASSERT_EQ(points.size(), 1500u); // density 0.42 per m^2, coverage 0.33 of the jamming limit
  const auto d = pp::PatternDomain::Rectangle(0, 0, 60, 60);
  const auto pcf = pp::EstimatePairCorrelation(points, d, { 0.0, 5.0, 25, 0 });
  for (int k = 0; k < 5; ++k) // bins [0, 0.2) ... [0.8, 1.0)
  {
    EXPECT_EQ(pcf.G(0, 0, k), 0.0) << "bin " << k;
    EXPECT_EQ(pcf.Pairs(0, 0, k), 0) << "bin " << k;
  }
  EXPECT_GT(pcf.G(0, 0, 5), 1.2); // [1.0, 1.2): the contact peak
  for (int k = 15; k < 25; ++k)   // beyond 3 d0
  {
    EXPECT_NEAR(pcf.G(0, 0, k), 1.0, 4.0 * CountSigma(pcf, 0, 0, k)) << "bin " << k;
  }
}

TEST(TerroirPointPattern, PairCorrelationOfLatticePeaksAtLatticeDistances)
{
  // n x n square lattice of spacing 1 m, points at (i + 0.5, j + 0.5), window [0, n)^2.
  // Lattice offset (p, q) is shared by (n - |p|)(n - |q|) ordered pairs, each weighted by
  // 1 / gamma = 1 / ((n - |p|)(n - |q|)): each offset adds exactly 1 (m^-2) to the weighted sum.
  // So g(k) = |W|^2 / (N (N - 1)) * m_k / A_k = n^2 m_k / ((n^2 - 1) A_k), N = n^2, m_k the
  // number of offsets whose length lies in bin k, A_k the bin's annulus area. Bins of 0.1 m from
  // 0.55 m: 1 (m = 4) in [0.95, 1.05), sqrt 2 (4) in [1.35, 1.45), 2 (4) in [1.95, 2.05),
  // sqrt 5 (8) in [2.15, 2.25); every other bin is 0.
  const int n = 10;
  Points points;
  for (int j = 0; j < n; ++j)
  {
    for (int i = 0; i < n; ++i)
    {
      points.push_back({ i + 0.5, j + 0.5, 0 });
    }
  }
  const auto d = pp::PatternDomain::Rectangle(0, 0, n, n);
  const auto pcf = pp::EstimatePairCorrelation(points, d, { 0.55, 2.55, 20, 0 });
  auto expected = [&](int k, int m)
  {
    const double r0 = 0.55 + 0.1 * k;
    const double r1 = r0 + 0.1;
    return n * n * m / ((n * n - 1.0) * Pi * (r1 * r1 - r0 * r0));
  };
  const int peakBins[4] = { 4, 8, 14, 16 };
  const int multiplicity[4] = { 4, 4, 4, 8 };
  for (int k = 0; k < 20; ++k)
  {
    const int* peak = std::find(peakBins, peakBins + 4, k);
    const double want = peak == peakBins + 4 ? 0.0 : expected(k, multiplicity[peak - peakBins]);
    EXPECT_NEAR(pcf.G(0, 0, k), want, 1e-12 * std::max(1.0, want)) << "bin " << k;
  }
  // By hand: bin 4 is [0.95, 1.05), A = pi (1.05^2 - 0.95^2) = 0.2 pi; g = 100 * 4 / (99 * 0.2 pi).
  EXPECT_NEAR(pcf.G(0, 0, 4), 6.43050, 1e-5);
  EXPECT_EQ(pcf.Pairs(0, 0, 4), 2 * 2 * n * (n - 1)); // 180 unordered pairs at distance 1
}

TEST(TerroirPointPattern, PairCorrelationOfTwoIndependentCategoriesIsOne)
{
  // Two independent uniform patterns: g_00, g_11, g_01 ~ 1; g_01 and g_10 are the same pairs.
  std::mt19937_64 rng(11);
  Points points = Binomial(rng, 1200, 80.0, 80.0, 0);
  const Points more = Binomial(rng, 800, 80.0, 80.0, 1);
  points.insert(points.end(), more.begin(), more.end());
  const auto d = pp::PatternDomain::Rectangle(0, 0, 80, 80);
  const auto pcf = pp::EstimatePairCorrelation(points, d, { 0.0, 8.0, 16, 0 });
  ASSERT_EQ(pcf.categories, 2);
  EXPECT_EQ(pcf.counts[0], 1200);
  EXPECT_EQ(pcf.counts[1], 800);
  for (int k = 0; k < 16; ++k)
  {
    EXPECT_EQ(pcf.Pairs(0, 1, k), pcf.Pairs(1, 0, k));
    EXPECT_EQ(pcf.G(0, 1, k), pcf.G(1, 0, k));
    EXPECT_EQ(pcf.Pairs(0, 0, k) % 2, 0);
  }
  ExpectPoisson(pcf, 0, 0);
  ExpectPoisson(pcf, 1, 1);
  // Cross pairs: N_01 ordered pairs are N_01 unordered ones (sd sqrt(1 / N_01), not 2 / N).
  for (int k = 0; k < 16; ++k)
  {
    EXPECT_NEAR(pcf.G(0, 1, k), 1.0, 4.0 / std::sqrt(double(pcf.Pairs(0, 1, k)))) << "bin " << k;
  }
}

TEST(TerroirPointPattern, LearnedModelHasDensitiesAndSmallestDistances)
{
  std::mt19937_64 rng(3);
  const double minimum[4] = { 0.5, 2.0, 2.0, 0.5 };
  const Points points = DartThrowing(rng, 400, 40.0, 30.0, minimum, true);
  const auto d = pp::PatternDomain::Rectangle(0, 0, 40, 30);
  const auto model = pp::LearnRadialDistribution(points, d, { 0.0, 4.0, 8, 0 });
  ASSERT_EQ(model.categories, 2);
  EXPECT_DOUBLE_EQ(model.density[0], CountCategory(points, 0) / 1200.0);
  EXPECT_DOUBLE_EQ(model.density[1], CountCategory(points, 1) / 1200.0);
  // Cross pairs: ~200 x 200 points, smallest distance >= 2 m: independent points would have
  // had ~200 * 200 * pi * 4 / 1200 ~ 400 pairs closer: a hard core. Same species (0.5 m
  // minimum, ~200 points): the smallest distance is >= 0.5 and independent points would have
  // had >= 200 * 199 / 2 * pi * 0.25 / 1200 ~ 13 closer pairs: kept too.
  for (int a = 0; a < 2; ++a)
  {
    for (int b = 0; b < 2; ++b)
    {
      EXPECT_DOUBLE_EQ(model.HardCore(a, b), std::min(4.0, SmallestDistance(points, a, b)));
    }
  }
  EXPECT_GE(model.HardCore(0, 1), 2.0);
  EXPECT_GE(model.HardCore(0, 0), 0.5);
  EXPECT_LT(model.HardCore(0, 0), 1.0);
  const auto soft = pp::LearnRadialDistribution(points, d, { 0.0, 4.0, 8, 0 }, false);
  EXPECT_EQ(soft.hardCore, std::vector<double>(4, 0.0));
}

TEST(TerroirPointPattern, HardCoreNeedsEvidence)
{
  // A rare species: 3 points 10 m apart (and > 4 m from the 400 common ones) in 40 m x 30 m. No
  // pair of them is closer than rMax = 4 m, but 3 pairs of independent points would fall that
  // close with probability ~ 3 * pi * 16 / 1200 = 0.13, not 3: no hard core for 1-1 (the
  // smallest distance, capped, would have been 4 m). Uniform common points: the smallest 0-0
  // distance among 400 is tiny (expected pairs closer ~1), so no hard core for 0-0 either.
  std::mt19937_64 rng(6);
  Points points;
  while (points.size() < 400)
  {
    const double x = Uniform(rng) * 40.0;
    const double y = Uniform(rng) * 30.0;
    if (y < 20.0 || x < 4.0 || x > 36.0)
    {
      points.push_back({ x, y, 0 });
    }
  }
  for (int i = 0; i < 3; ++i)
  {
    points.push_back({ 10.0 + 10.0 * i, 26.0, 1 });
  }
  const auto d = pp::PatternDomain::Rectangle(0, 0, 40, 30);
  const auto model = pp::LearnRadialDistribution(points, d, { 0.0, 4.0, 8, 0 });
  EXPECT_EQ(model.HardCore(1, 1), 0.0);
  EXPECT_EQ(model.HardCore(0, 0), 0.0);
  EXPECT_EQ(
    model.HardCore(0, 1), 4.0); // 400 x 3 cross pairs: ~ 1200 * pi * 16 / 1200 ~ 50 expected
}

// =============================================================================================
// Synthesis

/**
 * Largest |g_result - g_model| / sigma over bins k0..bins-1. The model's g is itself an
 * estimate from the exemplar's N_k pairs, and the result's from its own; two independent
 * patterns of the same process would differ by sigma = sqrt(2 / N_exemplar + 2 / N_result)
 * (relative, so times g where g > 1). The synthesis tests allow 3 sigma in every bin; over 6
 * seeds each the worst bin measured 0.4-1.1 sigma (Documentation/Plants.md), and a result
 * that ignored the model (a Poisson pattern for the clustered exemplar) is > 20 sigma off.
 */
double WorstDeviation(const pp::PairCorrelation& model,
  const pp::PairCorrelation& result,
  int a,
  int b,
  int k0)
{
  double worst = 0.0;
  for (int k = k0; k < model.bins; ++k)
  {
    const double sigma = std::hypot(CountSigma(model, a, b, k), CountSigma(result, a, b, k)) *
      std::max(1.0, model.G(a, b, k));
    worst = std::max(worst, std::abs(result.G(a, b, k) - model.G(a, b, k)) / sigma);
  }
  return worst;
}

TEST(TerroirPointPattern, SynthesisReproducesHardCore)
{
  // Exemplar: 500 darts with d0 = 1 m in 40 m x 40 m. Result on 50 m x 32 m: no pair closer
  // than the learned hard core (>= d0), the density within 3 % (the hard core lowers a Gibbs
  // process's density; kappa_n = 100 keeps it ~1 % low), g within 3 sigma beyond d0.
  std::mt19937_64 rng(8);
  const double d0[4] = { 1.0, 1.0, 1.0, 1.0 };
  const Points exemplar = DartThrowing(rng, 500, 40.0, 40.0, d0, false);
  const auto ed = pp::PatternDomain::Rectangle(0, 0, 40, 40);
  const pp::PairCorrelationParameters pcfp{ 0.0, 3.0, 15, 1 };
  const auto model = pp::LearnRadialDistribution(exemplar, ed, pcfp);
  const auto target = pp::EstimatePairCorrelation(exemplar, ed, pcfp);
  ASSERT_GE(model.HardCore(0, 0), 1.0);
  // A differently shaped window of about the same area.
  const auto d = pp::PatternDomain::Rectangle(0, 0, 50, 32);
  pp::SynthesisParameters sp;
  sp.seed = 42;
  const auto out = pp::SynthesizePattern(model, d, sp);
  const double density = out.points.size() / d.Area();
  std::printf("hard core: %zu points, density %.4f (model %.4f), energy %.1f\n",
    out.points.size(),
    density,
    model.density[0],
    out.statistics.energy);
  EXPECT_NEAR(density, model.density[0], 0.03 * model.density[0]);
  EXPECT_GE(SmallestDistance(out.points, 0, 0), model.HardCore(0, 0));
  const auto got = pp::EstimatePairCorrelation(out.points, d, pcfp);
  for (int k = 0; k < 15; ++k)
  {
    std::printf("  bin %2d  g model %.3f  result %.3f\n", k, target.G(0, 0, k), got.G(0, 0, k));
  }
  std::printf("  worst bin beyond d0: %.2f sigma\n", WorstDeviation(target, got, 0, 0, 5));
  EXPECT_LT(WorstDeviation(target, got, 0, 0, 5), 3.0);
  // Beyond 2 d0 the exemplar forgets the hard core (g = 1 up to its own noise, which the result
  // copies): 4 sigma of the two counts.
  for (int k = 10; k < 15; ++k)
  {
    const double sigma = std::hypot(CountSigma(target, 0, 0, k), CountSigma(got, 0, 0, k));
    EXPECT_NEAR(got.G(0, 0, k), 1.0, 4.0 * sigma) << "bin " << k;
  }
}

TEST(TerroirPointPattern, SynthesisReproducesClusters)
{
  // A clustered exemplar reproduced: g > 3 at short range (the Poisson value is 1), g within
  // 3 sigma in every bin, the density within 3 %. Thomas process: 0.01 parents per m^2, 10 children
  // each, sigma 1 m: g(0) = 1 + 1 / (4 pi 0.01) = 8.96, g(2 m) = 1 + 7.96 / e = 3.9.
  std::mt19937_64 rng(21);
  const Points exemplar = Thomas(rng, 0.01, 10.0, 1.0, 80.0, 80.0);
  const auto ed = pp::PatternDomain::Rectangle(0, 0, 80, 80);
  const pp::PairCorrelationParameters pcfp{ 0.0, 6.0, 12, 1 };
  const auto model = pp::LearnRadialDistribution(exemplar, ed, pcfp);
  const auto target = pp::EstimatePairCorrelation(exemplar, ed, pcfp);
  const auto d = pp::PatternDomain::Rectangle(0, 0, 80, 80);
  pp::SynthesisParameters sp;
  sp.seed = 7;
  const auto out = pp::SynthesizePattern(model, d, sp);
  const auto got = pp::EstimatePairCorrelation(out.points, d, pcfp);
  std::printf("clusters: exemplar %zu points, result %zu, energy %.1f\n",
    exemplar.size(),
    out.points.size(),
    out.statistics.energy);
  for (int k = 0; k < 12; ++k)
  {
    std::printf("  bin %2d  g model %.3f  result %.3f  thomas %.3f\n",
      k,
      target.G(0, 0, k),
      got.G(0, 0, k),
      1.0 + std::exp(-std::pow(0.25 + 0.5 * k, 2) / 4.0) / (4 * Pi * 0.01));
  }
  EXPECT_NEAR(out.points.size() / d.Area(), model.density[0], 0.03 * model.density[0]);
  EXPECT_GT(got.G(0, 0, 0), 3.0);
  std::printf("  worst bin: %.2f sigma\n", WorstDeviation(target, got, 0, 0, 0));
  EXPECT_LT(WorstDeviation(target, got, 0, 0, 0), 3.0);
}

TEST(TerroirPointPattern, SynthesisReproducesCrossInhibition)
{
  // Two species: no 0-1 pair closer than 2 m, same-species pairs free (0.3 m minimum).
  std::mt19937_64 rng(13);
  const double minimum[4] = { 0.3, 2.0, 2.0, 0.3 };
  const Points exemplar = DartThrowing(rng, 600, 50.0, 50.0, minimum, true);
  const auto ed = pp::PatternDomain::Rectangle(0, 0, 50, 50);
  const pp::PairCorrelationParameters pcfp{ 0.0, 5.0, 10, 2 };
  const auto model = pp::LearnRadialDistribution(exemplar, ed, pcfp);
  const auto target = pp::EstimatePairCorrelation(exemplar, ed, pcfp);
  const auto d = pp::PatternDomain::Rectangle(0, 0, 50, 50);
  pp::SynthesisParameters sp;
  sp.seed = 99;
  const auto out = pp::SynthesizePattern(model, d, sp);
  const auto got = pp::EstimatePairCorrelation(out.points, d, pcfp);
  std::printf("cross: %d + %d points (model %.0f + %.0f)\n",
    CountCategory(out.points, 0),
    CountCategory(out.points, 1),
    model.density[0] * 2500,
    model.density[1] * 2500);
  for (int k = 0; k < 10; ++k)
  {
    std::printf("  bin %2d  g00 %.3f/%.3f  g01 %.3f/%.3f  g11 %.3f/%.3f\n",
      k,
      target.G(0, 0, k),
      got.G(0, 0, k),
      target.G(0, 1, k),
      got.G(0, 1, k),
      target.G(1, 1, k),
      got.G(1, 1, k));
  }
  for (int c = 0; c < 2; ++c)
  {
    EXPECT_NEAR(CountCategory(out.points, c) / d.Area(), model.density[c], 0.05 * model.density[c]);
  }
  EXPECT_GE(SmallestDistance(out.points, 0, 1), 2.0);
  // Without the hard core the pair energy alone keeps the species apart: independent species
  // would have lambda_0 lambda_1 pi (2 m)^2 |W| = 0.12 * 0.12 * 4 pi * 2500 ~ 450 cross pairs
  // closer than 2 m (bins 0-3); allow 2 % of that.
  sp.useHardCore = false;
  const auto soft = pp::SynthesizePattern(model, d, sp);
  const auto gs = pp::EstimatePairCorrelation(soft.points, d, pcfp);
  const double independent = model.density[0] * model.density[1] * 4.0 * Pi * 2500.0;
  std::int64_t close = 0;
  for (int k = 0; k < 4; ++k)
  {
    close += gs.Pairs(0, 1, k);
  }
  std::printf("cross, no hard core: %lld cross pairs closer than 2 m (independent: %.0f)\n",
    static_cast<long long>(close),
    independent);
  EXPECT_LT(static_cast<double>(close), 0.02 * independent);
  EXPECT_LT(WorstDeviation(target, gs, 0, 0, 0), 3.0);
  EXPECT_LT(WorstDeviation(target, gs, 0, 1, 4), 3.0);
  EXPECT_LT(SmallestDistance(out.points, 0, 0), 1.0);
  EXPECT_LT(SmallestDistance(out.points, 1, 1), 1.0);
}

TEST(TerroirPointPattern, SynthesisRespectsMask)
{
  // A hard-core model learned on a rectangle, synthesised on a checkerboard zone of 5 m cells
  // (every other cell allowed, 1250 m^2 of 2500): no point in a forbidden cell (checked here
  // from the mask itself), the density that of the model per allowed area within 3 %, no pair
  // closer than the hard core, g within 3 sigma.
  std::mt19937_64 rng(31);
  const double d0[4] = { 1.0, 1.0, 1.0, 1.0 };
  const Points exemplar = DartThrowing(rng, 600, 40.0, 40.0, d0, false);
  const auto ed = pp::PatternDomain::Rectangle(0, 0, 40, 40);
  const pp::PairCorrelationParameters pcfp{ 0.0, 3.0, 15, 1 };
  const auto model = pp::LearnRadialDistribution(exemplar, ed, pcfp);
  const auto target = pp::EstimatePairCorrelation(exemplar, ed, pcfp);
  const int n = 10;
  std::vector<std::uint8_t> allowed(n * n);
  for (int j = 0; j < n; ++j)
  {
    for (int i = 0; i < n; ++i)
    {
      allowed[j * n + i] = (i + j) % 2 == 0 ? 1 : 0;
    }
  }
  const auto d = pp::PatternDomain::Cells(n, n, 5.0, 5.0, 100.0, 200.0, allowed);
  ASSERT_DOUBLE_EQ(d.Area(), 1250.0);
  pp::SynthesisParameters sp;
  sp.seed = 5;
  const auto out = pp::SynthesizePattern(model, d, sp);
  for (const auto& p : out.points)
  {
    const int i = static_cast<int>(std::floor((p.x - 100.0) / 5.0));
    const int j = static_cast<int>(std::floor((p.y - 200.0) / 5.0));
    ASSERT_TRUE(i >= 0 && i < n && j >= 0 && j < n) << p.x << ", " << p.y;
    ASSERT_EQ(allowed[j * n + i], 1) << p.x << ", " << p.y;
  }
  const double density = out.points.size() / 1250.0;
  std::printf(
    "mask: %zu points, density %.4f (model %.4f)\n", out.points.size(), density, model.density[0]);
  EXPECT_NEAR(density, model.density[0], 0.03 * model.density[0]);
  EXPECT_GE(SmallestDistance(out.points, 0, 0), model.HardCore(0, 0));
  // Pairs of this zone are mostly cut by its edges (at 3 m, 3/4 of a point's annulus lies in
  // forbidden cells): g, with the zone's own edge correction, still matches the exemplar's.
  const auto got = pp::EstimatePairCorrelation(out.points, d, pcfp);
  std::printf("  worst bin beyond d0: %.2f sigma\n", WorstDeviation(target, got, 0, 0, 5));
  EXPECT_LT(WorstDeviation(target, got, 0, 0, 5), 3.0);
}

TEST(TerroirPointPattern, SynthesisWithoutInteractionIsPoisson)
{
  // kappa = kappa_n = 0 and no hard core: f(X) = lambda^n, a Poisson process of the model's
  // density whatever the model's g (here a clustered one). The count is Poisson(mu), mu =
  // 0.2 * 80 * 80 = 1280: within 4 sqrt(mu) = 143; g ~ 1 within the count tolerance.
  pp::RadialDistributionModel model;
  model.categories = 1;
  model.bins = 8;
  model.rMin = 0.0;
  model.rMax = 4.0;
  model.density = { 0.2 };
  model.g = { 9, 7, 5, 3, 2, 1.5, 1.2, 1 };
  model.hardCore = { 0.5 };
  const auto d = pp::PatternDomain::Rectangle(0, 0, 80, 80);
  pp::SynthesisParameters sp;
  sp.seed = 17;
  sp.pairWeight = 0.0;
  sp.densityWeight = 0.0;
  sp.useHardCore = false;
  const auto out = pp::SynthesizePattern(model, d, sp);
  EXPECT_NEAR(static_cast<double>(out.points.size()), 1280.0, 4.0 * std::sqrt(1280.0));
  ExpectPoisson(pp::EstimatePairCorrelation(out.points, d, { 0.0, 4.0, 8, 1 }), 0, 0);
  EXPECT_LT(SmallestDistance(out.points, 0, 0), 0.5); // the hard core was not applied
}

TEST(TerroirPointPattern, SynthesisIsDeterministic)
{
  std::mt19937_64 rng(2);
  const double minimum[4] = { 0.5, 1.5, 1.5, 0.5 };
  const Points exemplar = DartThrowing(rng, 200, 20.0, 20.0, minimum, true);
  const auto model = pp::LearnRadialDistribution(
    exemplar, pp::PatternDomain::Rectangle(0, 0, 20, 20), { 0.0, 3.0, 6, 0 });
  const auto d = pp::PatternDomain::Rectangle(0, 0, 25, 20);
  pp::SynthesisParameters sp;
  sp.seed = 123;
  const auto a = pp::SynthesizePattern(model, d, sp);
  const auto b = pp::SynthesizePattern(model, d, sp);
  sp.seed = 124;
  const auto c = pp::SynthesizePattern(model, d, sp);
  ASSERT_GT(a.points.size(), 100u);
  ASSERT_EQ(a.points.size(), b.points.size());
  for (std::size_t i = 0; i < a.points.size(); ++i)
  {
    ASSERT_EQ(std::memcmp(&a.points[i].x, &b.points[i].x, sizeof(double)), 0) << i;
    ASSERT_EQ(std::memcmp(&a.points[i].y, &b.points[i].y, sizeof(double)), 0) << i;
    ASSERT_EQ(a.points[i].category, b.points[i].category) << i;
  }
  EXPECT_EQ(a.statistics.birthsAccepted, b.statistics.birthsAccepted);
  EXPECT_EQ(std::memcmp(&a.statistics.energy, &b.statistics.energy, sizeof(double)), 0);
  // Another seed: another pattern (not one point in common).
  int common = 0;
  for (const auto& p : c.points)
  {
    for (const auto& q : a.points)
    {
      common += (p.x == q.x && p.y == q.y) ? 1 : 0;
    }
  }
  EXPECT_EQ(common, 0);
}

TEST(TerroirPointPattern, PerturbationCostDoesNotGrowWithPoints)
{
  // The same model on windows of 20 m and 80 m (16 times the points): the points looked at per
  // perturbation stay the same (buckets), where a scan of all points would grow 16-fold. With
  // buckets of side s = rMax = 2 m and density lambda, one neighbour search looks at the 3 x 3
  // buckets, ~9 s^2 lambda points; a move searches twice.
  std::mt19937_64 rng(4);
  const double d0[4] = { 0.8, 0.8, 0.8, 0.8 };
  const Points exemplar = DartThrowing(rng, 400, 30.0, 30.0, d0, false);
  const auto model = pp::LearnRadialDistribution(
    exemplar, pp::PatternDomain::Rectangle(0, 0, 30, 30), { 0.0, 2.0, 10, 0 });
  double perPerturbation[2] = { 0.0, 0.0 };
  const double sides[2] = { 20.0, 80.0 };
  for (int w = 0; w < 2; ++w)
  {
    pp::SynthesisParameters sp;
    sp.seed = 9;
    const auto out =
      pp::SynthesizePattern(model, pp::PatternDomain::Rectangle(0, 0, sides[w], sides[w]), sp);
    perPerturbation[w] = double(out.statistics.neighboursVisited) / out.statistics.iterations;
  }
  const double bound = 2.0 * 9.0 * 2.0 * 2.0 * model.density[0];
  std::printf("points visited per perturbation: %.2f (20 m), %.2f (80 m), bound %.1f\n",
    perPerturbation[0],
    perPerturbation[1],
    bound);
  EXPECT_NEAR(perPerturbation[1] / perPerturbation[0], 1.0, 0.25);
  EXPECT_LT(perPerturbation[1], bound);
}

TEST(TerroirPointPattern, CategoryWithoutPointsIsNeverPlaced)
{
  pp::RadialDistributionModel model;
  model.categories = 3;
  model.bins = 2;
  model.rMax = 2.0;
  model.density = { 0.1, 0.0, 0.05 };
  model.g.assign(18, 1.0);
  model.hardCore.assign(9, 0.0);
  const auto out = pp::SynthesizePattern(model, pp::PatternDomain::Rectangle(0, 0, 40, 40), {});
  EXPECT_EQ(CountCategory(out.points, 1), 0);
  EXPECT_NEAR(CountCategory(out.points, 0), 160, 16);
  EXPECT_NEAR(CountCategory(out.points, 2), 80, 8);
}

TEST(TerroirPointPattern, ZoneSeedIsSplitMix64)
{
  // SplitMix64 from state 0 (Steele, Lea & Flood 2014; the reference code of Vigna's
  // splitmix64.c) outputs e220a8397b1dcdaf, 6e789e6aa1b965f4, 06c45d188009454f: zones 0, 1, 2
  // of seed 0 are those draws.
  EXPECT_EQ(pp::PatternZoneSeed(0, 0), 0xE220A8397B1DCDAFull);
  EXPECT_EQ(pp::PatternZoneSeed(0, 1), 0x6E789E6AA1B965F4ull);
  EXPECT_EQ(pp::PatternZoneSeed(0, 2), 0x06C45D188009454Full);
  EXPECT_NE(pp::PatternZoneSeed(1, 0), pp::PatternZoneSeed(0, 0));
}

TEST(TerroirPointPattern, ZonesGetTheirOwnPlants)
{
  // A 40 x 20 grid of 2 m cells: zone 3 is the left half, zone 5 the right half but a 10 x 10
  // cell hole of zone 9 (no model). Zone 3 takes a hard-core model, zone 5 a clustered one;
  // zone 8 has a model but no cell. Every point lies in a cell of its own zone; each zone's
  // points are those of SynthesizePattern on its cells with PatternZoneSeed; running the zones
  // on two threads gives the same bits.
  const int nx = 40;
  const int ny = 20;
  std::vector<int> labels(nx * ny);
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      const bool hole = i >= 25 && i < 35 && j >= 5 && j < 15;
      labels[j * nx + i] = i < 20 ? 3 : (hole ? 9 : 5);
    }
  }
  std::mt19937_64 rng(12);
  const double d0[4] = { 1.0, 1.0, 1.0, 1.0 };
  const auto hard = pp::LearnRadialDistribution(DartThrowing(rng, 300, 30.0, 30.0, d0, false),
    pp::PatternDomain::Rectangle(0, 0, 30, 30),
    { 0.0, 3.0, 10, 1 });
  const auto clustered = pp::LearnRadialDistribution(Thomas(rng, 0.02, 8.0, 1.0, 50.0, 50.0),
    pp::PatternDomain::Rectangle(0, 0, 50, 50),
    { 0.0, 4.0, 8, 1 });
  const std::vector<pp::ZoneModel> models = { { 3, hard }, { 5, clustered }, { 8, hard } };
  pp::SynthesisParameters sp;
  sp.seed = 2026;
  const double x0 = 500.0;
  const double y0 = 1000.0;
  const auto out = pp::SynthesizeZones(nx, ny, 2.0, 2.0, x0, y0, labels.data(), models, sp);
  ASSERT_EQ(out.points.size(), out.zones.size());
  ASSERT_EQ(out.statistics.size(), 3u);
  EXPECT_EQ(out.statistics[2].iterations, 0);
  int counts[2] = { 0, 0 };
  for (std::size_t p = 0; p < out.points.size(); ++p)
  {
    const int i = static_cast<int>(std::floor((out.points[p].x - x0) / 2.0));
    const int j = static_cast<int>(std::floor((out.points[p].y - y0) / 2.0));
    ASSERT_TRUE(i >= 0 && i < nx && j >= 0 && j < ny);
    ASSERT_EQ(labels[j * nx + i], out.zones[p]) << p;
    ++counts[out.zones[p] == 3 ? 0 : 1];
  }
  // Zone 3: 40 m x 40 m; zone 5: 1600 - 400 m^2.
  EXPECT_NEAR(counts[0] / 1600.0, hard.density[0], 0.05 * hard.density[0]);
  EXPECT_NEAR(counts[1] / 1200.0, clustered.density[0], 0.05 * clustered.density[0]);
  for (int z = 0; z < 2; ++z)
  {
    const int zone = z == 0 ? 3 : 5;
    pp::SynthesisParameters one = sp;
    one.seed = pp::PatternZoneSeed(sp.seed, zone);
    const auto alone = pp::SynthesizePattern(models[z].model,
      pp::PatternDomain::CellsWithLabel(nx, ny, 2.0, 2.0, x0, y0, labels.data(), zone),
      one);
    const std::size_t first = z == 0 ? 0 : static_cast<std::size_t>(counts[0]);
    ASSERT_EQ(alone.points.size(), static_cast<std::size_t>(counts[z]));
    for (std::size_t p = 0; p < alone.points.size(); ++p)
    {
      ASSERT_EQ(alone.points[p].x, out.points[first + p].x);
      ASSERT_EQ(alone.points[p].y, out.points[first + p].y);
    }
  }
  const pp::PatternParallelFor twoThreads =
    [](
      std::size_t begin, std::size_t end, const std::function<void(std::size_t, std::size_t)>& body)
  {
    const std::size_t middle = begin + (end - begin) / 2;
    std::thread other(body, begin, middle);
    body(middle, end);
    other.join();
  };
  const auto parallel =
    pp::SynthesizeZones(nx, ny, 2.0, 2.0, x0, y0, labels.data(), models, sp, twoThreads);
  ASSERT_EQ(parallel.points.size(), out.points.size());
  for (std::size_t p = 0; p < out.points.size(); ++p)
  {
    ASSERT_EQ(std::memcmp(&parallel.points[p], &out.points[p], sizeof(double) * 2), 0) << p;
    ASSERT_EQ(parallel.zones[p], out.zones[p]);
  }
  const std::vector<pp::ZoneModel> twice = { { 3, hard }, { 3, clustered } };
  EXPECT_THROW(
    pp::SynthesizeZones(nx, ny, 2.0, 2.0, x0, y0, labels.data(), twice, sp), std::invalid_argument);
}

TEST(TerroirPointPattern, BadParametersAreRejected)
{
  using pp::PatternDomain;
  EXPECT_THROW(PatternDomain::Rectangle(0, 0, 0, 1), std::invalid_argument);
  EXPECT_THROW(PatternDomain::Rectangle(0, 2, 1, 1), std::invalid_argument);
  EXPECT_THROW(PatternDomain::Rectangle(0, 0, NAN, 1), std::invalid_argument);
  EXPECT_THROW(PatternDomain::Cells(2, 2, 1, 1, 0, 0, { 1, 1, 1 }), std::invalid_argument);
  EXPECT_THROW(PatternDomain::Cells(2, 2, 0, 1, 0, 0, { 1, 1, 1, 1 }), std::invalid_argument);
  EXPECT_THROW(PatternDomain::Cells(2, 2, 1, 1, 0, 0, { 0, 0, 0, 0 }), std::invalid_argument);
  const auto d = PatternDomain::Rectangle(0, 0, 10, 10);
  const Points points = { { 1, 1, 0 }, { 2, 2, 1 } };
  auto estimate = [&](pp::PairCorrelationParameters p, const Points& pts)
  { return pp::EstimatePairCorrelation(pts, d, p); };
  EXPECT_THROW(estimate({ 2.0, 2.0, 10, 0 }, points), std::invalid_argument); // rMax <= rMin
  EXPECT_THROW(estimate({ -1.0, 2.0, 10, 0 }, points), std::invalid_argument);
  EXPECT_THROW(estimate({ 0.0, 2.0, 0, 0 }, points), std::invalid_argument);  // bins < 1
  EXPECT_THROW(estimate({ 0.0, 2.0, 10, 1 }, points), std::invalid_argument); // category 1
  EXPECT_THROW(estimate({ 0.0, 2.0, 10, 0 }, { { 1, 1, -1 } }), std::invalid_argument);
  EXPECT_THROW(estimate({ 0.0, 2.0, 10, 0 }, { { 11, 1, 0 } }), std::invalid_argument);
  EXPECT_NO_THROW(estimate({ 0.0, 2.0, 10, 0 }, points));
  try
  {
    estimate({ 3.0, 2.0, 10, 0 }, points);
    FAIL();
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_NE(std::string(e.what()).find("rMax = 2"), std::string::npos) << e.what();
  }

  pp::RadialDistributionModel model;
  model.categories = 1;
  model.bins = 2;
  model.rMax = 1.0;
  model.density = { 0.5 };
  model.g = { 0.5, 1.0 };
  model.hardCore = { 0.0 };
  EXPECT_NO_THROW(pp::SynthesizePattern(model, d, {}));
  auto bad = model;
  bad.density = { -0.1 };
  EXPECT_THROW(pp::SynthesizePattern(bad, d, {}), std::invalid_argument);
  bad = model;
  bad.g = { 0.5 };
  EXPECT_THROW(pp::SynthesizePattern(bad, d, {}), std::invalid_argument);
  bad = model;
  bad.g = { -0.5, 1.0 };
  EXPECT_THROW(pp::SynthesizePattern(bad, d, {}), std::invalid_argument);
  bad = model;
  bad.rMin = 1.0;
  EXPECT_THROW(pp::SynthesizePattern(bad, d, {}), std::invalid_argument);
  bad = model;
  bad.categories = 2;
  EXPECT_THROW(pp::SynthesizePattern(bad, d, {}), std::invalid_argument);
  auto sym = model;
  sym.categories = 2;
  sym.density = { 0.1, 0.1 };
  sym.g = { 1, 1, 1, 1, 0.5, 0.5, 1, 1 }; // g_01 != g_10
  sym.hardCore = { 0, 0, 0, 0 };
  EXPECT_THROW(pp::SynthesizePattern(sym, d, {}), std::invalid_argument);
  pp::SynthesisParameters sp;
  sp.iterations = -1;
  EXPECT_THROW(pp::SynthesizePattern(model, d, sp), std::invalid_argument);
  sp = {};
  sp.moveProbability = 1.0;
  EXPECT_THROW(pp::SynthesizePattern(model, d, sp), std::invalid_argument);
  sp = {};
  sp.pairWeight = -1.0;
  EXPECT_THROW(pp::SynthesizePattern(model, d, sp), std::invalid_argument);
  sp = {};
  sp.moveRadius = -1.0;
  EXPECT_THROW(pp::SynthesizePattern(model, d, sp), std::invalid_argument);
}

// Speed (not asserted): run with --gtest_also_run_disabled_tests. Synthesises the hard-core
// and the clustered model on 100 m x 100 m and prints perturbations and points per second.
TEST(TerroirPointPattern, DISABLED_SynthesisThroughput)
{
  std::mt19937_64 rng(8);
  const double d0[4] = { 1.0, 1.0, 1.0, 1.0 };
  const Points hard = DartThrowing(rng, 500, 40.0, 40.0, d0, false);
  const Points clustered = Thomas(rng, 0.01, 10.0, 1.0, 80.0, 80.0);
  const Points* exemplars[2] = { &hard, &clustered };
  const double sides[2] = { 40.0, 80.0 };
  const double rMax[2] = { 3.0, 6.0 };
  const char* names[2] = { "hard core", "Thomas" };
  for (int e = 0; e < 2; ++e)
  {
    const auto model = pp::LearnRadialDistribution(*exemplars[e],
      pp::PatternDomain::Rectangle(0, 0, sides[e], sides[e]),
      { 0.0, rMax[e], 15, 0 });
    const auto d = pp::PatternDomain::Rectangle(0, 0, 100, 100);
    const auto start = std::chrono::steady_clock::now();
    const auto out = pp::SynthesizePattern(model, d, {});
    const double s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("%s: %zu points, %lld perturbations in %.3f s: %.0f perturbations/s, %.0f "
                "points/s, %.1f points visited per perturbation\n",
      names[e],
      out.points.size(),
      static_cast<long long>(out.statistics.iterations),
      s,
      out.statistics.iterations / s,
      out.points.size() / s,
      double(out.statistics.neighboursVisited) / out.statistics.iterations);
  }
}

} // namespace

// Unit tests of the Morphometry core (no VTK, no GL); expected values worked out by hand
// (derivations in the comments), not by running the code.
#include "FlowAccumulation.h"
#include "Morphometry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace
{
using terroir::GridView;
using terroir::hydrology::ChannelNetworkStrahler1957;
using terroir::hydrology::FitLine;
using terroir::hydrology::Morphometry;
using terroir::hydrology::MorphometryCells;
using terroir::hydrology::MorphometryParams;
using terroir::hydrology::MorphometryReport;

const double kSqrt2 = std::sqrt(2.0);
const double kRadToDeg = 57.29577951308232;

GridView<float> View(const std::vector<float>& z, int nx, int ny, double dx, double dy)
{
  GridView<float> v;
  v.data = z.data();
  v.nx = nx;
  v.ny = ny;
  v.dx = dx;
  v.dy = dy;
  return v;
}

/// Least-squares slope written out independently of FitLine: sum((x-mx)(y-my)) / sum((x-mx)^2).
double Slope(const std::vector<double>& x, const std::vector<double>& y)
{
  double mx = 0, my = 0;
  for (std::size_t k = 0; k < x.size(); ++k)
  {
    mx += x[k] / x.size();
    my += y[k] / y.size();
  }
  double sxy = 0, sxx = 0;
  for (std::size_t k = 0; k < x.size(); ++k)
  {
    sxy += (x[k] - mx) * (y[k] - my);
    sxx += (x[k] - mx) * (x[k] - mx);
  }
  return sxy / sxx;
}

// A plane rising 0.5 m per metre to the north, 5 x 6 cells of 10 m: z = 5 j.
// - HI: heights 0, 5, ..., 25 in equal numbers: mean 12.5, HI = 12.5 / 25 = 0.5.
// - Slope: atan(0.5) = 26.5651 deg at every cell (Horn is exact on a plane, edges extrapolated
//   linearly), so mean = median = p10 = p90, all 30 cells in the bin [25, 30).
// - No depression: W = z.
// - Every cell drains south (drop 5 m over 10 m, against 5 m over 14.14 m diagonally); row 0
//   drains off the map. A at row j = (6 - j) cells x 100 m^2. With a 300 m^2 threshold rows
//   j = 0..3 are channels: 5 order-1 streams, each 3 steps of 10 m (row 0 adds nothing):
//   150 m of channel on 3000 m^2, 0.15 km / 0.003 km^2 = 50 km/km^2.
// - Hack: L at row j = (5 - j) x 10 m, A = (6 - j) x 100 m^2, channel rows j = 0..3.
TEST(TerroirMorphometryCore, TiltedPlaneKnownAnswers)
{
  const int nx = 5, ny = 6;
  std::vector<float> z(nx * ny);
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      z[j * nx + i] = 5.0f * j;
    }
  }
  MorphometryParams p;
  p.channelArea = 300.0;
  std::vector<std::uint8_t> order(z.size(), 99);
  std::vector<float> length(z.size()), depth(z.size());
  MorphometryCells cells;
  cells.strahlerOrder = order.data();
  cells.flowLength = length.data();
  cells.depressionDepth = depth.data();
  const MorphometryReport r = Morphometry(View(z, nx, ny, 10, 10), p, cells);

  EXPECT_EQ(r.validCells, 30u);
  EXPECT_DOUBLE_EQ(r.validArea, 3000.0);
  EXPECT_DOUBLE_EQ(r.hypsometricIntegral, 0.5);
  const double slope = std::atan(0.5) * kRadToDeg;
  EXPECT_NEAR(r.slopeMean, slope, 1e-4);
  EXPECT_NEAR(r.slopeMedian, slope, 1e-4);
  EXPECT_NEAR(r.slopeP10, slope, 1e-4);
  EXPECT_NEAR(r.slopeP90, slope, 1e-4);
  ASSERT_EQ(r.slopeHistogram.size(), 18u);
  EXPECT_EQ(r.slopeHistogram[5], 30);
  EXPECT_EQ(r.depressionCells, 0u);
  EXPECT_EQ(r.depressionVolume, 0.0);
  EXPECT_EQ(r.channelCells, 20u);
  EXPECT_NEAR(r.channelLength, 150.0, 1e-9);
  EXPECT_NEAR(r.drainageDensity, 50.0, 1e-9);
  ASSERT_EQ(r.orders.size(), 1u);
  EXPECT_EQ(r.orders[0].streams, 5);
  EXPECT_NEAR(r.orders[0].meanLength, 30.0, 1e-9);
  EXPECT_TRUE(std::isnan(r.bifurcationRatio)); // one order: nothing to fit
  EXPECT_EQ(r.hortonLastOrder, 0);
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      EXPECT_EQ(order[j * nx + i], j <= 3 ? 1 : 0) << i << "," << j;
      EXPECT_FLOAT_EQ(length[j * nx + i], 10.0f * (5 - j));
      EXPECT_EQ(depth[j * nx + i], 0.0f);
    }
  }
  std::vector<double> logA, logL;
  for (int j = 0; j <= 3; ++j)
  {
    logA.push_back(std::log10((6 - j) * 100.0 * 1e-6));
    logL.push_back(std::log10((5 - j) * 10.0 * 1e-3));
  }
  const double h = Slope(logA, logL);
  EXPECT_NEAR(r.hackExponent, h, 1e-9);
  EXPECT_NEAR(h, 1.3231, 1e-4); // numpy.polyfit of the same four pairs; L = A/dx - dx
  EXPECT_EQ(r.hackPoints, 20u);
}

// A square pyramid of 9 x 9 cells, z = 4 - max(|i - 4|, |j - 4|): the ring at Chebyshev
// distance d has 8d cells of height 4 - d, the top 1 cell of height 4. Sum of heights =
// 4 + 8 (3*1 + 2*2 + 1*3) = 84, mean 84/81, HI = (84/81) / 4 = 7/27 (a continuous pyramid
// would give 1/3; the base ring is a third of the cells). Every cell drains down a face: no
// depression.
TEST(TerroirMorphometryCore, PyramidHypsometricIntegral)
{
  const int n = 9;
  std::vector<float> z(n * n);
  for (int j = 0; j < n; ++j)
  {
    for (int i = 0; i < n; ++i)
    {
      z[j * n + i] = static_cast<float>(4 - std::max(std::abs(i - 4), std::abs(j - 4)));
    }
  }
  const MorphometryReport r = Morphometry(View(z, n, n, 1, 1), MorphometryParams{});
  EXPECT_NEAR(r.hypsometricIntegral, 7.0 / 27.0, 1e-12);
  EXPECT_EQ(r.minElevation, 0.0);
  EXPECT_EQ(r.maxElevation, 4.0);
  EXPECT_EQ(r.depressionCells, 0u);
  EXPECT_EQ(r.channelCells, 0u); // 81 m^2 is far below 0.1 km^2
  EXPECT_EQ(r.drainageDensity, 0.0);
}

// A flat 5 x 5 plateau at 10 m with a pit of two cells, 7 m at (2,2) and 8 m at (2,3), and a
// dimple of 0.5 mm at (1,1); cells 2 m x 3 m (6 m^2). Filling raises the three to 10 m:
// depths 3 m, 2 m and 0.0005 m. Two cells are deeper than 1 mm: share 2/25. Volume
// (3 + 2 + 0.0005) x 6 = 30.003 m^3.
TEST(TerroirMorphometryCore, PitOfKnownDepthAndVolume)
{
  const int n = 5;
  std::vector<float> z(n * n, 10.0f);
  z[2 * n + 2] = 7.0f;
  z[3 * n + 2] = 8.0f;
  z[1 * n + 1] = 9.9995f;
  std::vector<float> depth(z.size());
  MorphometryCells cells;
  cells.depressionDepth = depth.data();
  const MorphometryReport r = Morphometry(View(z, n, n, 2, 3), MorphometryParams{}, cells);
  EXPECT_EQ(r.depressionCells, 2u);
  EXPECT_DOUBLE_EQ(r.depressionShare, 2.0 / 25.0);
  EXPECT_NEAR(r.depressionVolume, 30.003, 1e-5);
  EXPECT_FLOAT_EQ(depth[2 * n + 2], 3.0f);
  EXPECT_FLOAT_EQ(depth[3 * n + 2], 2.0f);
  EXPECT_NEAR(depth[1 * n + 1], 0.0005, 1e-6);
  EXPECT_EQ(depth[0], 0.0f);
  // The depression threshold is a parameter: at 0.1 mm the dimple counts too.
  MorphometryParams p;
  p.depressionDepth = 1e-4;
  EXPECT_EQ(Morphometry(View(z, n, n, 2, 3), p).depressionCells, 3u);
}

// A hand-drawn D8 tree on 5 x 5 cells of 10 m (j = 0 south; '.' no data):
//
//   j=4   a  b  c  d  e        a (0,4) S,  b (1,4) SW, c (2,4) S, d (3,4) SE, e (4,4) S
//   j=3   f  g  h  .  k        f (0,3) SE, g (1,3) S,  h (2,3) S, k (4,3) SW
//   j=2   .  m  n  p  .        m (1,2) E,  n (2,2) S,  p (3,2) SW
//   j=1   .  .  q  .  .        q (2,1) S
//   j=0   .  .  r  .  .        r (2,0) drains off the map
//
// Every cell is a channel (threshold 1 cell). Orders: heads a b c d e g are 1; f (a + b) and
// k (d + e) are 2, new streams; h (c) 1; m (f:2, g:1) 2; n (h:1, m:2) 2; p (k) 2; q (n:2, p:2)
// 3, a new stream; r 3. N1 = 6, N2 = 2, N3 = 1.
// Lengths (each cell's step to its receiver; 10 or 10 sqrt 2):
//   order 1: a 10, b 10r2, c 10, h 10, d 10r2, e 10, g 10  -> 50 + 20 r2
//   order 2: f 10r2, m 10, n 10, k 10r2, p 10r2             -> 20 + 30 r2
//   order 3: q 10, r 0                                      -> 10
// Horton, orders 1..2 (the highest, 3, left out): R_b = 6 / 2 = 3,
// R_l = ((20 + 30 r2) / 2) / ((50 + 20 r2) / 6) = 3 (20 + 30 r2) / (50 + 20 r2) = 2.3922969...
// Longest flow path to r: from b: b-f 10r2, f-m 10r2, m-n 10, n-q 10, q-r 10 = 30 + 20 r2.
TEST(TerroirMorphometryCore, HandDrawnTreeStrahlerAndHorton)
{
  const int n = 5;
  const std::int8_t X = terroir::hydrology::kD8NoData;
  const std::int8_t E = 0, S = 6, SW = 5, SE = 7, O = terroir::hydrology::kD8Outlet;
  // Rows from south (j = 0) to north (j = 4).
  const std::vector<std::int8_t> dir = {
    X,
    X,
    O,
    X,
    X, //
    X,
    X,
    S,
    X,
    X, //
    X,
    E,
    S,
    SW,
    X, //
    SE,
    S,
    S,
    X,
    SW, //
    S,
    SW,
    S,
    SE,
    S, //
  };
  std::vector<float> z(n * n, 0.0f);
  std::vector<std::uint8_t> valid(n * n);
  for (int k = 0; k < n * n; ++k)
  {
    valid[k] = dir[k] == X ? 0 : 1;
  }
  GridView<float> v = View(z, n, n, 10, 10);
  v.valid = valid.data();
  std::vector<double> area(n * n);
  terroir::hydrology::AccumulationOptions acc;
  acc.timesCellArea = true;
  terroir::hydrology::D8FlowAccumulation(v, dir.data(), nullptr, area.data(), acc);

  MorphometryReport r;
  std::vector<std::uint8_t> order(n * n);
  std::vector<float> length(n * n);
  ChannelNetworkStrahler1957(v, dir.data(), area.data(), 100.0, r, order.data(), length.data());
  const std::vector<int> expected = {
    0,
    0,
    3,
    0,
    0, //
    0,
    0,
    3,
    0,
    0, //
    0,
    2,
    2,
    2,
    0, //
    2,
    1,
    1,
    0,
    2, //
    1,
    1,
    1,
    1,
    1, //
  };
  for (int k = 0; k < n * n; ++k)
  {
    EXPECT_EQ(order[k], expected[k]) << "cell " << k % n << "," << k / n;
  }
  EXPECT_EQ(r.channelCells, 14u);
  ASSERT_EQ(r.orders.size(), 3u);
  EXPECT_EQ(r.orders[0].streams, 6);
  EXPECT_EQ(r.orders[1].streams, 2);
  EXPECT_EQ(r.orders[2].streams, 1);
  EXPECT_NEAR(r.orders[0].totalLength, 50 + 20 * kSqrt2, 1e-9);
  EXPECT_NEAR(r.orders[1].totalLength, 20 + 30 * kSqrt2, 1e-9);
  EXPECT_NEAR(r.orders[2].totalLength, 10, 1e-9);
  EXPECT_NEAR(r.channelLength, 80 + 50 * kSqrt2, 1e-9);
  EXPECT_EQ(r.hortonFirstOrder, 1);
  EXPECT_EQ(r.hortonLastOrder, 2);
  EXPECT_NEAR(r.bifurcationRatio, 3.0, 1e-12);
  EXPECT_NEAR(r.lengthRatio, 3 * (20 + 30 * kSqrt2) / (50 + 20 * kSqrt2), 1e-12);
  EXPECT_NEAR(length[0 * n + 2], 30 + 20 * kSqrt2, 1e-4);
  EXPECT_TRUE(std::isnan(length[0]));
  EXPECT_EQ(area[0 * n + 2], 1400.0); // the 14 cells
}

// A network built so that Hack's law holds exactly: one chain of 8 cells 1 km apart draining
// east, and contributing areas given as A_k = (L_k / C)^(1/h) with C = 2, h = 0.6, L_k = k km
// the flow length of the k-th cell from the head (the head, L = 0, is left out of the fit).
TEST(TerroirMorphometryCore, HackExponentOfAConstructedNetwork)
{
  const int nx = 8, ny = 1;
  std::vector<float> z(nx, 0.0f);
  std::vector<std::int8_t> dir(nx, 0);
  dir[nx - 1] = terroir::hydrology::kD8Outlet;
  std::vector<double> area(nx);
  for (int k = 0; k < nx; ++k)
  {
    area[k] = k == 0 ? 1.0e6 : std::pow(k / 2.0, 1.0 / 0.6) * 1e6; // km^2 -> m^2
  }
  MorphometryReport r;
  std::vector<float> length(nx);
  ChannelNetworkStrahler1957(
    View(z, nx, ny, 1000, 1000), dir.data(), area.data(), 1.0, r, nullptr, length.data());
  EXPECT_NEAR(r.hackExponent, 0.6, 1e-9);
  EXPECT_NEAR(r.hackCoefficient, 2.0, 1e-9);
  EXPECT_EQ(r.hackPoints, 7u);
  EXPECT_FLOAT_EQ(length[7], 7000.0f);
  EXPECT_NEAR(r.channelLength, 7000.0, 1e-9);
}

// No-data cells are left out: the plane of TiltedPlaneKnownAnswers with its middle column
// masked (and a huge height under the mask). Cells next to the hole still drain south (they
// have a lower neighbour inside); every statistic counts the 24 cells left: 4 columns of 4
// channel cells, 4 x 30 m of channel on 2400 m^2.
TEST(TerroirMorphometryCore, NoDataCellsAreLeftOut)
{
  const int nx = 5, ny = 6;
  std::vector<float> z(nx * ny);
  std::vector<std::uint8_t> valid(nx * ny, 1);
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      z[j * nx + i] = 5.0f * j;
    }
    valid[j * nx + 2] = 0;
    z[j * nx + 2] = 1e6f; // would wreck every statistic if it were read
  }
  GridView<float> v = View(z, nx, ny, 10, 10);
  v.valid = valid.data();
  MorphometryParams p;
  p.channelArea = 300.0;
  std::vector<float> depth(z.size());
  std::vector<std::uint8_t> order(z.size());
  MorphometryCells cells;
  cells.depressionDepth = depth.data();
  cells.strahlerOrder = order.data();
  const MorphometryReport r = Morphometry(v, p, cells);
  EXPECT_EQ(r.validCells, 24u);
  EXPECT_DOUBLE_EQ(r.validArea, 2400.0);
  EXPECT_DOUBLE_EQ(r.hypsometricIntegral, 0.5);
  EXPECT_EQ(r.maxElevation, 25.0);
  EXPECT_EQ(r.channelCells, 16u);
  EXPECT_NEAR(r.drainageDensity, 0.120 / 0.0024, 1e-9);
  EXPECT_EQ(r.depressionCells, 0u);
  EXPECT_TRUE(std::isnan(depth[2]));
  EXPECT_EQ(order[2], 0);
}

TEST(TerroirMorphometryCore, FitLineNeedsTwoDistinctX)
{
  EXPECT_TRUE(std::isnan(FitLine({ 1.0 }, { 2.0 }).slope));
  EXPECT_TRUE(std::isnan(FitLine({ 1.0, 1.0 }, { 2.0, 3.0 }).slope));
  const auto fit = FitLine({ 0.0, 1.0, 2.0 }, { 1.0, 3.0, 5.0 });
  EXPECT_DOUBLE_EQ(fit.slope, 2.0);
  EXPECT_DOUBLE_EQ(fit.intercept, 1.0);
}

TEST(TerroirMorphometryCore, TooSmallOrEmptyGridsAreRefused)
{
  std::vector<float> z(4, std::numeric_limits<float>::quiet_NaN());
  EXPECT_THROW(Morphometry(View(z, 4, 1, 1, 1), MorphometryParams{}), std::invalid_argument);
  EXPECT_THROW(Morphometry(View(z, 2, 2, 1, 1), MorphometryParams{}), std::invalid_argument);
}

} // namespace

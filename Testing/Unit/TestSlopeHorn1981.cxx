// Unit tests of terroir::terrain::SlopeHorn1981Rows (no VTK, no GL).
// Expected values are analytic (atan of a known gradient) or come from gdaldem 3.6.
#include "SlopeHorn1981.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

namespace
{
using terroir::GridView;
using terroir::terrain::SlopeHorn1981;
using terroir::terrain::SlopeHorn1981Rows;
using terroir::terrain::SlopeParams;
using terroir::terrain::SlopeUnits;

constexpr double kDeg = 57.29577951308232;

struct Plane
{
  std::vector<double> z;
  GridView<double> view;
};

// z = a * x + b * y with x = i dx (east), y = j dy (north).
Plane MakePlane(int nx, int ny, double dx, double dy, double a, double b)
{
  Plane p;
  p.z.resize(static_cast<size_t>(nx) * ny);
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      p.z[static_cast<size_t>(j) * nx + i] = a * i * dx + b * j * dy + 100.0;
    }
  }
  p.view.data = p.z.data();
  p.view.nx = nx;
  p.view.ny = ny;
  p.view.dx = dx;
  p.view.dy = dy;
  return p;
}

bool IsCorner(int i, int j, int nx, int ny)
{
  return (i == 0 || i == nx - 1) && (j == 0 || j == ny - 1);
}

struct PlaneCase
{
  double a, b;   // gradient east, north
  double aspect; // expected downhill direction, degrees clockwise from north
};

class TerroirSlopeCore : public ::testing::TestWithParam<PlaneCase>
{
};

TEST_P(TerroirSlopeCore, TiltedPlaneHasExactSlopeAndAspectEverywhereButCorners)
{
  const PlaneCase pc = GetParam();
  const int nx = 7, ny = 6;
  Plane p = MakePlane(nx, ny, 10.0, 20.0, pc.a, pc.b);
  std::vector<double> slope(p.z.size()), aspect(p.z.size()), normals(3 * p.z.size());
  SlopeHorn1981(p.view, SlopeParams(), slope.data(), aspect.data(), normals.data());
  const double expSlope = std::atan(std::hypot(pc.a, pc.b)) * kDeg;
  const double norm = std::sqrt(pc.a * pc.a + pc.b * pc.b + 1.0);
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      if (IsCorner(i, j, nx, ny))
      {
        continue;
      }
      const size_t k = static_cast<size_t>(j) * nx + i;
      EXPECT_NEAR(slope[k], expSlope, 1e-9) << i << "," << j;
      double da = std::fmod(aspect[k] - pc.aspect + 540.0, 360.0) - 180.0;
      EXPECT_NEAR(da, 0.0, 1e-9) << i << "," << j;
      EXPECT_GE(aspect[k], 0.0);
      EXPECT_LT(aspect[k], 360.0);
      EXPECT_NEAR(normals[3 * k + 0], -pc.a / norm, 1e-12);
      EXPECT_NEAR(normals[3 * k + 1], -pc.b / norm, 1e-12);
      EXPECT_NEAR(normals[3 * k + 2], 1.0 / norm, 1e-12);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Directions,
  TerroirSlopeCore,
  ::testing::Values(PlaneCase{ 0.1, 0.0, 270.0 },            // rises to the east: faces west
    PlaneCase{ 0.0, 0.1, 180.0 },                            // rises to the north: faces south
    PlaneCase{ -0.1, 0.0, 90.0 },                            // faces east
    PlaneCase{ 0.0, -0.3, 0.0 },                             // faces north
    PlaneCase{ 0.2, 0.2, 225.0 },                            // faces south-west
    PlaneCase{ -0.5, 0.5, 135.0 },                           // faces south-east
    PlaneCase{ -1.0, -1.0, 45.0 },                           // faces north-east
    PlaneCase{ 1.0, -1.0 * std::tan(30.0 / kDeg), 300.0 })); // faces west-north-west

TEST(TerroirSlopeCoreTest, PlaneCornersFollowGdaldem)
{
  // gdaldem -compute_edges clamps the columns on the first and last rows, so at a corner the
  // east-west difference spans one cell but is divided by two: half the east-west gradient.
  const int nx = 5, ny = 4;
  Plane p = MakePlane(nx, ny, 10.0, 10.0, 0.4, 0.3);
  std::vector<double> slope(p.z.size());
  SlopeHorn1981(p.view,
    SlopeParams(),
    slope.data(),
    static_cast<double*>(nullptr),
    static_cast<double*>(nullptr));
  const double expCorner = std::atan(std::hypot(0.2, 0.3)) * kDeg;
  EXPECT_NEAR(slope[0], expCorner, 1e-9);
  EXPECT_NEAR(slope[nx - 1], expCorner, 1e-9);
  EXPECT_NEAR(slope[(ny - 1) * nx], expCorner, 1e-9);
  EXPECT_NEAR(slope[ny * nx - 1], expCorner, 1e-9);
  EXPECT_NEAR(slope[1], std::atan(0.5) * kDeg, 1e-9); // edge, not corner: exact
}

TEST(TerroirSlopeCoreTest, ConeHasAnalyticSlopeAwayFromApex)
{
  const int n = 81;
  const double dx = 5.0, s = 0.6; // z = 1000 - s r
  std::vector<float> z(n * n);
  const double c = (n - 1) / 2.0;
  for (int j = 0; j < n; ++j)
  {
    for (int i = 0; i < n; ++i)
    {
      z[j * n + i] = static_cast<float>(1000.0 - s * dx * std::hypot(i - c, j - c));
    }
  }
  GridView<float> v;
  v.data = z.data();
  v.nx = v.ny = n;
  v.dx = v.dy = dx;
  std::vector<float> slope(z.size()), aspect(z.size());
  SlopeHorn1981(v, SlopeParams(), slope.data(), aspect.data(), static_cast<float*>(nullptr));
  int checked = 0;
  for (int j = 1; j < n - 1; ++j)
  {
    for (int i = 1; i < n - 1; ++i)
    {
      const double r = std::hypot(i - c, j - c);
      if (r < 10.0)
      {
        continue;
      }
      const size_t k = static_cast<size_t>(j) * n + i;
      EXPECT_NEAR(slope[k], std::atan(s) * kDeg, 0.1) << i << "," << j;
      // Downhill points away from the apex: azimuth of (i - c, j - c).
      const double expAspect = std::atan2(i - c, j - c) * kDeg;
      const double da = std::fmod(aspect[k] - expAspect + 720.0 + 180.0, 360.0) - 180.0;
      EXPECT_NEAR(da, 0.0, 0.5) << i << "," << j;
      ++checked;
    }
  }
  EXPECT_GT(checked, 4000);
}

TEST(TerroirSlopeCoreTest, PerRowSpacingIsUsed)
{
  // A degree grid: every row has its own east-west cell size. Along column i0 the surface
  // z = g (i - i0) dx_j rises by g per metre eastwards in every row and is level north-south,
  // so the slope there is atan(g) exactly when each row's own dx is used.
  const int nx = 9, ny = 8, i0 = 4;
  const double g = 0.25;
  std::vector<double> rowDx(ny), rowDy(ny, 30.0), z(nx * ny);
  for (int j = 0; j < ny; ++j)
  {
    rowDx[j] = 10.0 + 5.0 * j; // 10 m .. 45 m
    for (int i = 0; i < nx; ++i)
    {
      z[j * nx + i] = g * (i - i0) * rowDx[j];
    }
  }
  GridView<double> v;
  v.data = z.data();
  v.nx = nx;
  v.ny = ny;
  v.dx = 27.5; // a wrong global value: must not be used
  v.dy = 30.0;
  v.rowDx = rowDx.data();
  v.rowDy = rowDy.data();
  std::vector<double> slope(z.size()), aspect(z.size());
  SlopeHorn1981(v, SlopeParams(), slope.data(), aspect.data(), static_cast<double*>(nullptr));
  for (int j = 1; j < ny - 1; ++j)
  {
    EXPECT_NEAR(slope[j * nx + i0], std::atan(g) * kDeg, 1e-9) << "row " << j;
    EXPECT_NEAR(aspect[j * nx + i0], 270.0, 1e-9) << "row " << j;
  }
  // And the north-south spacing of the row: z = b * y with rowDy = 30 m (dy unused).
  std::vector<double> z2(nx * ny);
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      z2[j * nx + i] = 0.1 * j * 30.0;
    }
  }
  v.data = z2.data();
  v.dy = 1.0;
  SlopeHorn1981(v, SlopeParams(), slope.data(), aspect.data(), static_cast<double*>(nullptr));
  EXPECT_NEAR(slope[3 * nx + 3], std::atan(0.1) * kDeg, 1e-9);
}

TEST(TerroirSlopeCoreTest, NoDataNeighbourIsReplacedByCentre)
{
  // z = x on a 1 m grid. With the east neighbour of the centre missing, gdaldem puts the centre
  // value there: dz/dx = (2 + 2*1 + 2) / 8 = 3/4, so the slope is atan(3/4) = 36.8699 deg.
  const int n = 5;
  std::vector<double> z(n * n);
  std::vector<std::uint8_t> mask(n * n, 1);
  for (int j = 0; j < n; ++j)
  {
    for (int i = 0; i < n; ++i)
    {
      z[j * n + i] = i;
    }
  }
  mask[2 * n + 3] = 0;
  GridView<double> v;
  v.data = z.data();
  v.nx = v.ny = n;
  v.valid = mask.data();
  std::vector<double> slope(z.size()), aspect(z.size()), normals(3 * z.size());
  SlopeHorn1981(v, SlopeParams(), slope.data(), aspect.data(), normals.data());
  EXPECT_NEAR(slope[2 * n + 2], 36.86989764584402, 1e-9);
  EXPECT_TRUE(std::isnan(slope[2 * n + 3]));
  EXPECT_TRUE(std::isnan(aspect[2 * n + 3]));
  EXPECT_TRUE(std::isnan(normals[3 * (2 * n + 3) + 2]));
  EXPECT_NEAR(slope[1 * n + 1], 45.0, 1e-9); // window untouched
}

TEST(TerroirSlopeCoreTest, MatchesGdaldemOnSmallGridWithNoData)
{
  // Known answer from GDAL 3.6.2: a 6x5 GeoTIFF (10 m, nodata -9999) holding
  // z = c^2 + 3 r (c column, r row from the north) with (r=2, c=3) no data, run through
  // `gdaldem slope -compute_edges`. Rows listed north first, as gdaldem writes them.
  const int nx = 6, ny = 5;
  const double expected[5][6] = { { 16.9165, 19.827, 26.5651, 33.8545, 40.5106, 28.406 },
    { 17.5484, 19.827, 19.827, 32.6518, 39.6128, 43.4915 },
    { 17.5484, 19.827, 22.1449, NAN, 34.7325, 43.4915 },
    { 17.5484, 19.827, 26.3923, 32.6518, 34.8887, 43.4915 },
    { 16.9165, 19.827, 26.5651, 33.8545, 40.5106, 28.406 } };
  std::vector<float> z(nx * ny);
  std::vector<std::uint8_t> mask(nx * ny, 1);
  for (int r = 0; r < ny; ++r)
  {
    const int j = ny - 1 - r;
    for (int c = 0; c < nx; ++c)
    {
      z[j * nx + c] = static_cast<float>(c * c + 3 * r);
    }
  }
  mask[(ny - 1 - 2) * nx + 3] = 0;
  z[(ny - 1 - 2) * nx + 3] = -9999.0f;
  GridView<float> v;
  v.data = z.data();
  v.nx = nx;
  v.ny = ny;
  v.dx = v.dy = 10.0;
  v.valid = mask.data();
  std::vector<float> slope(z.size());
  SlopeHorn1981Rows(v,
    SlopeParams(),
    slope.data(),
    static_cast<float*>(nullptr),
    static_cast<float*>(nullptr),
    0,
    ny);
  for (int r = 0; r < ny; ++r)
  {
    for (int c = 0; c < nx; ++c)
    {
      const float s = slope[(ny - 1 - r) * nx + c];
      if (std::isnan(expected[r][c]))
      {
        EXPECT_TRUE(std::isnan(s));
      }
      else
      {
        EXPECT_NEAR(s, expected[r][c], 1e-3) << "row " << r << " col " << c;
      }
    }
  }
}

TEST(TerroirSlopeCoreTest, PercentZFactorAndConvergence)
{
  const int nx = 4, ny = 4;
  Plane p = MakePlane(nx, ny, 2.0, 2.0, 0.0, -0.1); // faces north
  SlopeParams params;
  params.units = SlopeUnits::Percent;
  params.zFactor = 2.0;
  params.convergenceDeg = -1.5; // true = grid + gamma
  std::vector<double> slope(p.z.size()), aspect(p.z.size());
  SlopeHorn1981(p.view, params, slope.data(), aspect.data(), static_cast<double*>(nullptr));
  EXPECT_NEAR(slope[5], 20.0, 1e-9);
  EXPECT_NEAR(aspect[5], 358.5, 1e-9);
}

TEST(TerroirSlopeCoreTest, FlatCellsHaveZeroSlopeAndNaNAspect)
{
  Plane p = MakePlane(4, 3, 1.0, 1.0, 0.0, 0.0);
  std::vector<double> slope(p.z.size()), aspect(p.z.size()), normals(3 * p.z.size());
  SlopeHorn1981(p.view, SlopeParams(), slope.data(), aspect.data(), normals.data());
  for (size_t k = 0; k < p.z.size(); ++k)
  {
    EXPECT_EQ(slope[k], 0.0);
    EXPECT_TRUE(std::isnan(aspect[k]));
    EXPECT_EQ(normals[3 * k + 2], 1.0);
  }
}

TEST(TerroirSlopeCoreTest, RowBlocksGiveTheSameResultAsOnePass)
{
  const int nx = 37, ny = 23;
  std::vector<float> z(nx * ny);
  std::uint64_t state = 12345;
  for (auto& v : z)
  {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    v = static_cast<float>((state >> 40) % 1000) * 0.37f;
  }
  GridView<float> v;
  v.data = z.data();
  v.nx = nx;
  v.ny = ny;
  v.dx = 3.0;
  v.dy = 4.0;
  std::vector<float> a(z.size()), b(z.size());
  SlopeHorn1981(
    v, SlopeParams(), a.data(), static_cast<float*>(nullptr), static_cast<float*>(nullptr));
  for (int r0 = 0; r0 < ny; r0 += 5)
  {
    SlopeHorn1981Rows(v,
      SlopeParams(),
      b.data(),
      static_cast<float*>(nullptr),
      static_cast<float*>(nullptr),
      r0,
      r0 + 5);
  }
  for (size_t k = 0; k < z.size(); ++k)
  {
    EXPECT_EQ(a[k], b[k]);
  }
}

} // namespace

// Known answers of the horizon and cast-shadow core (Filters/Terrain/Core/ShadowHorizon.h):
// a wall's shadow, tangents on planes (the directional derivative), the Earth-curvature
// drop, and the sweep against ray marching on seeded random terrains.
#include "ShadowHorizon.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace
{
using terroir::GridView;
namespace tt = terroir::terrain;

constexpr double kPi = 3.14159265358979323846;
const double kInf = std::numeric_limits<double>::infinity();

GridView<double> View(const std::vector<double>& z, int nx, int ny, double dx, double dy)
{
  GridView<double> v;
  v.data = z.data();
  v.nx = nx;
  v.ny = ny;
  v.dx = dx;
  v.dy = dy;
  return v;
}

double MaxOf(const std::vector<double>& z)
{
  double m = -kInf;
  for (double x : z)
  {
    if (!std::isnan(x))
    {
      m = std::max(m, x);
    }
  }
  return m;
}

/// Horizon tangents of every cell toward grid azimuth `az` by ray marching.
std::vector<double> RayMarchAll(const GridView<double>& v, double az, float curvature)
{
  const tt::MarchDirection d = tt::MakeMarchDirection(az, v.dx, v.dy);
  std::vector<double> z(v.data, v.data + v.Size());
  const double zMax = MaxOf(z);
  std::vector<double> out(v.Size());
  for (int j = 0; j < v.ny; ++j)
  {
    for (int i = 0; i < v.nx; ++i)
    {
      out[v.Index(i, j)] = tt::HorizonTangentRayMarch(v, d, curvature, i, j, zMax, kInf);
    }
  }
  return out;
}

/// Horizon tangents of every cell toward grid azimuth `az` by the sweep.
std::vector<double> SweepAll(const GridView<double>& v, double az, float curvature)
{
  const tt::SweepPlan plan = tt::MakeSweepPlan(tt::MakeMarchDirection(az, v.dx, v.dy), v.nx, v.ny);
  std::vector<double> lines(static_cast<std::size_t>(plan.lineCount) * plan.nMajor);
  std::vector<double> scratch;
  for (int m = 0; m < plan.lineCount; ++m)
  {
    tt::SweepLine(
      v, plan, curvature, m, lines.data() + static_cast<std::size_t>(m) * plan.nMajor, scratch);
  }
  std::vector<double> out(v.Size());
  tt::GatherSweep(v, plan, lines.data(), out.data(), 0, plan.nMajor);
  return out;
}

/// Seeded rough terrain with our own value mapping (std distributions differ by library).
std::vector<double> RandomTerrain(int nx, int ny, std::uint64_t seed)
{
  std::mt19937_64 rng(seed);
  std::vector<double> z(static_cast<std::size_t>(nx) * ny);
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      const double noise = static_cast<double>(rng() >> 11) / 9007199254740992.0; // [0, 1)
      z[static_cast<std::size_t>(j) * nx + i] =
        40.0 * std::sin(0.21 * i) * std::cos(0.17 * j) + 1.5 * noise + 0.5 * i;
    }
  }
  return z;
}

} // namespace

// A wall 10 m high at x = 30 m on flat ground, sun in the east at 45 degrees: the shadow is
// 10 m long (cells 20..29; cell 20 sees the wall's top exactly at 45 degrees: not lit).
TEST(TerroirShadowHorizon, WallCastsShadowOfItsHeightAtFortyFiveDegrees)
{
  const int nx = 40;
  const int ny = 5;
  std::vector<double> z(static_cast<std::size_t>(nx) * ny, 0.0);
  for (int j = 0; j < ny; ++j)
  {
    z[static_cast<std::size_t>(j) * nx + 30] = 10.0;
  }
  const GridView<double> v = View(z, nx, ny, 1.0, 1.0);
  const std::vector<double> ray = RayMarchAll(v, 90.0, 0.0f);
  const std::vector<double> sweep = SweepAll(v, 90.0, 0.0f);
  const double tanSun = std::tan(45.0 * kPi / 180.0);
  for (int i = 0; i < 30; ++i)
  {
    const bool expectLit = i < 20;
    EXPECT_EQ(tanSun > ray[v.Index(i, 2)] + 1e-12, expectLit) << "ray, i = " << i;
    EXPECT_EQ(tanSun > sweep[v.Index(i, 2)] + 1e-12, expectLit) << "sweep, i = " << i;
    EXPECT_NEAR(ray[v.Index(i, 2)], 10.0 / (30 - i), 1e-12) << i;
  }
  // The sun in the west sees no obstacle behind the wall's west side: the horizon is flat.
  const std::vector<double> west = RayMarchAll(v, 270.0, 0.0f);
  EXPECT_DOUBLE_EQ(west[v.Index(10, 2)], 0.0);
  // An edge cell looking out of the grid has the horizontal plane as horizon.
  EXPECT_DOUBLE_EQ(ray[v.Index(nx - 1, 2)], tt::kNoHorizon);
  // Early exit keeps the comparison: the cell at 15 m sees the top at atan(2/3).
  const tt::MarchDirection east = tt::MakeMarchDirection(90.0, 1.0, 1.0);
  EXPECT_GE(tt::HorizonTangentRayMarch(v, east, 0.0f, 15, 2, 10.0, 0.5), 0.5);
  EXPECT_LT(tt::HorizonTangentRayMarch(v, east, 0.0f, 15, 2, 10.0, 0.8), 0.8);
}

// On a plane z = a x + b y every sample ahead rises at the directional derivative, so the
// horizon tangent toward azimuth phi is a sin(phi) + b cos(phi) for both methods, on any
// spacing (the interpolation across the minor axis is exact on a plane). The march slope and
// step length are float32 (as on the GPU): 1e-6 covers their rounding.
TEST(TerroirShadowHorizon, PlaneHorizonIsDirectionalDerivative)
{
  const int nx = 31;
  const int ny = 23;
  const double dx = 2.0;
  const double dy = 3.0;
  const double a = 0.3;
  const double b = -0.2;
  std::vector<double> z(static_cast<std::size_t>(nx) * ny);
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      z[static_cast<std::size_t>(j) * nx + i] = a * i * dx + b * j * dy + 100.0;
    }
  }
  const GridView<double> v = View(z, nx, ny, dx, dy);
  for (double az : { 0.0, 30.0, 56.3, 90.0, 123.0, 200.0, 250.0, 315.0, 347.5 })
  {
    const double expected = a * std::sin(az * kPi / 180.0) + b * std::cos(az * kPi / 180.0);
    const std::vector<double> ray = RayMarchAll(v, az, 0.0f);
    const std::vector<double> sweep = SweepAll(v, az, 0.0f);
    // Interior cells: at least one sample ahead in every direction.
    for (int j = 2; j < ny - 2; ++j)
    {
      for (int i = 2; i < nx - 2; ++i)
      {
        EXPECT_NEAR(ray[v.Index(i, j)], expected, 1e-6)
          << "ray az " << az << " at " << i << "," << j;
        EXPECT_NEAR(sweep[v.Index(i, j)], expected, 1e-6)
          << "sweep az " << az << " at " << i << "," << j;
      }
    }
  }
}

// A 300 m pillar 20 km east of a cell on flat ground: with the Earth's curvature its top
// drops by d^2 / (2R) = 31.39 m, so tan h = (300 - 31.39) / 20000.
TEST(TerroirShadowHorizon, EarthCurvatureLowersDistantTerrain)
{
  const int nx = 21;
  const int ny = 3;
  std::vector<double> z(static_cast<std::size_t>(nx) * ny, 0.0);
  z[static_cast<std::size_t>(1) * nx + 20] = 300.0;
  const GridView<double> v = View(z, nx, ny, 1000.0, 1000.0);
  const double drop = 20000.0 * 20000.0 / (2.0 * tt::kEarthRadiusM);
  EXPECT_NEAR(drop, 31.392, 1e-3);
  const float curv = tt::CurvatureCoefficient(true);
  const std::vector<double> ray = RayMarchAll(v, 90.0, curv);
  const std::vector<double> sweep = SweepAll(v, 90.0, curv);
  // The flat ground itself also drops: its best sample is the pillar.
  EXPECT_NEAR(ray[v.Index(0, 1)], (300.0 - drop) / 20000.0, 1e-9);
  EXPECT_NEAR(sweep[v.Index(0, 1)], (300.0 - drop) / 20000.0, 1e-9);
  EXPECT_NEAR(RayMarchAll(v, 90.0, 0.0f)[v.Index(0, 1)], 300.0 / 20000.0, 1e-12);
  // Without the pillar in view (looking west) the dropping ground gives a negative horizon:
  // the nearest sample, 1 km away, drops 1000^2 / (2R).
  const double drop15 = 15000.0 * 15000.0 / (2.0 * tt::kEarthRadiusM);
  EXPECT_NEAR(ray[v.Index(5, 1)], (300.0 - drop15) / 15000.0, 1e-9);
  const std::vector<double> west = RayMarchAll(v, 270.0, curv);
  EXPECT_NEAR(
    west[v.Index(5, 1)], -1000.0 / (2.0 * tt::kEarthRadiusM), 1e-10); // float32 coefficient
}

// Along axes and diagonals (dx = dy) the sweep lines pass through cell centres, so the sweep
// samples exactly what ray marching samples and their horizons agree to rounding.
TEST(TerroirShadowHorizon, SweepEqualsRayMarchingOnAxesAndDiagonals)
{
  const int nx = 48;
  const int ny = 37;
  const std::vector<double> z = RandomTerrain(nx, ny, 20261123);
  const GridView<double> v = View(z, nx, ny, 10.0, 10.0);
  for (int k = 0; k < 8; ++k)
  {
    const double az = 45.0 * k;
    for (float curv : { 0.0f, tt::CurvatureCoefficient(true) })
    {
      const std::vector<double> ray = RayMarchAll(v, az, curv);
      const std::vector<double> sweep = SweepAll(v, az, curv);
      for (std::size_t c = 0; c < ray.size(); ++c)
      {
        ASSERT_NEAR(sweep[c], ray[c], 1e-9 + 1e-9 * std::fabs(ray[c]))
          << "az " << az << " cell " << c;
      }
    }
  }
}

// Elsewhere the sweep interpolates between two lines one cell apart: on hilly random terrain
// (slopes up to 30 degrees, 1.5 m of noise per 10 m cell) the lit/shadow answer for suns 1..40
// degrees high agrees on >= 99 % of the cells. (Single cells can differ by many degrees: the
// horizon jumps where a nearer ridge hides a farther one.)
TEST(TerroirShadowHorizon, SweepCloseToRayMarchingOffAxis)
{
  const int nx = 64;
  const int ny = 64;
  const std::vector<double> z = RandomTerrain(nx, ny, 7);
  const GridView<double> v = View(z, nx, ny, 10.0, 10.0);
  std::size_t total = 0;
  std::size_t agree = 0;
  for (double az : { 17.0, 71.0, 133.0, 208.0, 289.0 })
  {
    const std::vector<double> ray = RayMarchAll(v, az, 0.0f);
    const std::vector<double> sweep = SweepAll(v, az, 0.0f);
    for (double el : { 1.0, 5.0, 10.0, 20.0, 40.0 })
    {
      const double t = std::tan(el * kPi / 180.0);
      for (std::size_t c = 0; c < ray.size(); ++c)
      {
        ++total;
        agree += (t > ray[c]) == (t > sweep[c]) ? 1 : 0;
      }
    }
  }
  EXPECT_GE(static_cast<double>(agree) / total, 0.99) << agree << " of " << total;
}

// No-data cells on the way neither block nor stop the ray; no-data cells get NaN.
TEST(TerroirShadowHorizon, NoDataNeitherBlocksNorStops)
{
  const int nx = 12;
  const int ny = 3;
  std::vector<double> z(static_cast<std::size_t>(nx) * ny, 0.0);
  std::vector<std::uint8_t> valid(z.size(), 1);
  for (int j = 0; j < ny; ++j)
  {
    z[static_cast<std::size_t>(j) * nx + 5] = 50.0; // a wall of no data
    valid[static_cast<std::size_t>(j) * nx + 5] = 0;
    z[static_cast<std::size_t>(j) * nx + 10] = 4.0; // a real bump behind it
  }
  GridView<double> v = View(z, nx, ny, 1.0, 1.0);
  v.valid = valid.data();
  const std::vector<double> ray = RayMarchAll(v, 90.0, 0.0f);
  const std::vector<double> sweep = SweepAll(v, 90.0, 0.0f);
  EXPECT_NEAR(ray[v.Index(2, 1)], 4.0 / 8.0, 1e-12);
  EXPECT_NEAR(sweep[v.Index(2, 1)], 4.0 / 8.0, 1e-12);
  EXPECT_TRUE(std::isnan(sweep[v.Index(5, 1)]));
}

TEST(TerroirShadowHorizon, SectorLookupInterpolatesBetweenNeighbours)
{
  tt::SectorLookup l = tt::LookupSectors(0.0, 64);
  EXPECT_EQ(l.sector0, 0);
  EXPECT_EQ(l.sector1, 1);
  EXPECT_FLOAT_EQ(l.weight1, 0.0f);
  l = tt::LookupSectors(1.5 * 360.0 / 64.0, 64);
  EXPECT_EQ(l.sector0, 1);
  EXPECT_EQ(l.sector1, 2);
  EXPECT_FLOAT_EQ(l.weight1, 0.5f);
  l = tt::LookupSectors(359.0, 8); // between sector 7 (315) and sector 0 (360)
  EXPECT_EQ(l.sector0, 7);
  EXPECT_EQ(l.sector1, 0);
  EXPECT_NEAR(l.weight1, 44.0 / 45.0, 1e-6);
  l = tt::LookupSectors(-90.0, 4);
  EXPECT_EQ(l.sector0, 3);
  EXPECT_DOUBLE_EQ(tt::SectorAzimuth(3, 4), 270.0);
}

TEST(TerroirShadowHorizon, MarchDirectionsFollowTheMajorAxis)
{
  tt::MarchDirection d = tt::MakeMarchDirection(90.0, 10.0, 10.0);
  EXPECT_TRUE(d.alongX);
  EXPECT_EQ(d.step, 1);
  EXPECT_EQ(d.slope, 0.0f);
  EXPECT_FLOAT_EQ(d.length, 10.0f);
  d = tt::MakeMarchDirection(225.0, 10.0, 10.0); // south-west diagonal
  EXPECT_EQ(d.step, -1);
  EXPECT_EQ(std::fabs(d.slope), 1.0f);
  EXPECT_NEAR(d.length, 10.0 * std::sqrt(2.0), 1e-5);
  // North-north-east on a grid with 30 m rows and 10 m columns: per row (30 m north) the ray
  // moves 30 tan(20 deg) m east = 1.0919 columns, so columns are the major axis.
  d = tt::MakeMarchDirection(20.0, 10.0, 30.0);
  EXPECT_TRUE(d.alongX);
  EXPECT_NEAR(d.slope, 1.0 / (3.0 * std::tan(20.0 * kPi / 180.0)), 1e-6);
  EXPECT_NEAR(d.length, 10.0 / std::sin(20.0 * kPi / 180.0), 1e-4);
}

// terroir::terrain feature curves and diffusion solver (Filters/Terrain/Core/FeatureCurves.h):
// Hermite interpolation, rasterised constraints and the multigrid solver against closed-form
// answers worked out by hand (see each test) and against plain Jacobi iterations.
#include "FeatureCurves.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <thread>
#include <vector>

using namespace terroir::terrain;

namespace
{
FeatureControlPoint Point(double x, double y, double z)
{
  FeatureControlPoint p;
  p.x = x;
  p.y = y;
  p.elevation = z;
  return p;
}

/// A straight ridge along x = 64 (from y = -1000 to 1000, so no end inside the grid) on a
/// 129 x 9 grid of 1 m: plateau 10 m across at 100 m, slopes 20 m wide at 45 degrees.
FeatureCurve StraightRidge()
{
  FeatureCurve c{ Point(64, -1000, 100), Point(64, 1000, 100) };
  for (auto& p : c)
  {
    p.plateauWidth = 10.0;
    p.slopeLeftWidth = p.slopeRightWidth = 20.0;
    p.slopeLeftAngle = p.slopeRightAngle = 45.0;
  }
  return c;
}

FeatureGrid Grid(int nx, int ny, double d = 1.0)
{
  FeatureGrid g;
  g.nx = nx;
  g.ny = ny;
  g.dx = g.dy = d;
  return g;
}

/// Two threads, each given half of the rows.
void TwoThreads(int rows, const std::function<void(int, int)>& body)
{
  std::thread t([&] { body(0, rows / 2); });
  body(rows / 2, rows);
  t.join();
}

/// A curved three-point ridge with a bounded envelope, a valley crossing it, over a tilted base.
std::vector<FeatureCurve> Scene(std::vector<float>& base, int n)
{
  FeatureCurve ridge{ Point(10, 12, 60), Point(30, 40, 80), Point(55, 30, 50) };
  for (auto& p : ridge)
  {
    p.plateauWidth = 4.0;
    p.slopeLeftWidth = 8.0;
    p.slopeRightWidth = 6.0;
    p.slopeLeftAngle = 30.0;
    p.slopeRightAngle = 40.0;
    p.envelopeLeft = 10.0;
    p.envelopeRight = 12.0;
  }
  FeatureCurve valley{ Point(5, 55, 10), Point(58, 50, 5) };
  for (auto& p : valley)
  {
    p.plateauWidth = 2.0;
    p.slopeLeftWidth = p.slopeRightWidth = 5.0;
    p.slopeLeftAngle = p.slopeRightAngle = -20.0;
    p.envelopeLeft = p.envelopeRight = 8.0;
  }
  base.resize(static_cast<std::size_t>(n) * n);
  for (int j = 0; j < n; ++j)
  {
    for (int i = 0; i < n; ++i)
    {
      base[static_cast<std::size_t>(j) * n + i] = static_cast<float>(20.0 + 0.3 * i - 0.1 * j);
    }
  }
  return { ridge, valley };
}
} // namespace

// The spline goes through the control points with the tangents it advertises: Catmull-Rom
// (P[k+1] - P[k-1]) / 2 inside, and at the ends 2 (P1 - P0) - m1 (a parabola), worked out here
// by hand for P = (0,0,0), (10,0,5), (20,10,5), (20,20,0).
TEST(FeatureCurves, HermiteHitsControlValuesAndTangents)
{
  FeatureCurve c{ Point(0, 0, 0), Point(10, 0, 5), Point(20, 10, 5), Point(20, 20, 0) };
  const double m1[3] = { 10, 5, 2.5 }, m2[3] = { 5, 10, -2.5 };
  const double m0[3] = { 2 * 10 - 10, 2 * 0 - 5, 2 * 5 - 2.5 };
  const double m3[3] = { 2 * 0 - 5, 2 * 10 - 10, 2 * -5 + 2.5 };
  const double* expected[4] = { m0, m1, m2, m3 };
  for (int k = 0; k < 4; ++k)
  {
    double m[3];
    FeatureCurveTangent(c, k, m);
    for (int q = 0; q < 3; ++q)
    {
      EXPECT_NEAR(m[q], expected[k][q], 1e-12) << "point " << k << " component " << q;
    }
  }
  for (int s = 0; s < 3; ++s)
  {
    double p[3], dp[3];
    FeatureCurveHermite(c, s, 0.0, p, dp);
    EXPECT_NEAR(p[0], c[s].x, 1e-12);
    EXPECT_NEAR(p[1], c[s].y, 1e-12);
    EXPECT_NEAR(p[2], c[s].elevation, 1e-12);
    for (int q = 0; q < 3; ++q)
    {
      EXPECT_NEAR(dp[q], expected[s][q], 1e-12);
    }
    FeatureCurveHermite(c, s, 1.0, p, dp);
    EXPECT_NEAR(p[0], c[s + 1].x, 1e-12);
    EXPECT_NEAR(p[1], c[s + 1].y, 1e-12);
    EXPECT_NEAR(p[2], c[s + 1].elevation, 1e-12);
    for (int q = 0; q < 3; ++q)
    {
      EXPECT_NEAR(dp[q], expected[s + 1][q], 1e-12);
    }
  }
  // The first segment is the parabola P0 + b t + a t^2 with b = m0, a = P1 - P0 - m0:
  // at t = 0.5, x = 0 + 10 * 0.5 + 0 = 5, y = -5 * 0.5 + 5 * 0.25 = -1.25.
  double p[3], dp[3];
  FeatureCurveHermite(c, 0, 0.5, p, dp);
  EXPECT_NEAR(p[0], 5.0, 1e-12);
  EXPECT_NEAR(p[1], -1.25, 1e-12);
  // A two-point curve is a straight line, run at constant speed.
  FeatureCurve line{ Point(0, 0, 0), Point(8, 4, 2) };
  FeatureCurveHermite(line, 0, 0.25, p, dp);
  EXPECT_NEAR(p[0], 2.0, 1e-12);
  EXPECT_NEAR(p[1], 1.0, 1e-12);
  EXPECT_NEAR(p[2], 0.5, 1e-12);
}

// Samples are at most `step` apart, start and end on the control points, and interpolate the
// other values linearly (plateau 2 -> 6 m: 4 m at the middle of a straight two-point curve).
TEST(FeatureCurves, SamplesAreDenseAndLinearInTheOtherValues)
{
  FeatureCurve c{ Point(0, 0, 0), Point(10, 0, 10) };
  c[0].plateauWidth = 2.0;
  c[1].plateauWidth = 6.0;
  const auto s = SampleFeatureCurve(c, 0.5);
  ASSERT_GE(s.size(), 21u);
  EXPECT_DOUBLE_EQ(s.front().x, 0.0);
  EXPECT_DOUBLE_EQ(s.back().x, 10.0);
  for (std::size_t k = 0; k + 1 < s.size(); ++k)
  {
    EXPECT_LE(std::hypot(s[k + 1].x - s[k].x, s[k + 1].y - s[k].y), 0.5 + 1e-12);
    EXPECT_NEAR(s[k].plateauWidth, 2.0 + 4.0 * s[k].x / 10.0, 1e-9);
    EXPECT_NEAR(s[k].elevation, s[k].x, 1e-9);
  }
}

// 1-D Laplace (eq. 8 only) between two held values: the discrete harmonic function is the
// straight line between them, 10 at i = 0 and 42 at i = 32 (H = 10 + i).
TEST(FeatureCurves, LaplaceBetweenTwoValuesIsAStraightLine)
{
  const int n = 33;
  FeatureConstraints c;
  c.alpha.assign(n, 0.0f);
  c.beta.assign(n, 0.0f);
  c.gamma.assign(n, 1.0f);
  c.elevation.assign(n, 0.0f);
  c.gradient.assign(n, 0.0f);
  c.dirX.assign(n, 0.0f);
  c.dirY.assign(n, 0.0f);
  c.kind.assign(n, 0);
  for (int k : { 0, 32 })
  {
    c.alpha[k] = 1.0f;
    c.kind[k] = 1;
    c.elevation[k] = k == 0 ? 10.0f : 42.0f;
  }
  FeatureSolverParameters p;
  p.tolerance = 1e-7;
  auto levels = BuildDiffusionLevels(c, n, 1, nullptr, p);
  EXPECT_GT(levels.size(), 2u);
  const DiffusionReport r = SolveDiffusionMultigrid(levels, p);
  EXPECT_TRUE(r.converged);
  for (int i = 0; i < n; ++i)
  {
    EXPECT_NEAR(levels[0].h[i], 10.0 + i, 1e-6) << "i = " << i;
  }
}

// A straight ridge with hard plateau constraints (alpha = 1) has a closed-form discrete
// answer. With d = |x - 64| in cells: the plateau (d <= 5) is 100; on the slope (5 < d <= 25)
// eq. 9 with beta = 0.5, n = (+-1, 0), G = -tan 45 = -1 and the y neighbours equal reads
// 6 H_d = 5 H_{d-1} + H_{d+1} - 4, whose solution is the 45-degree line 100 - (d - 5) plus
// delta_d = 0.05 (5^(d-24) - 5^-19) (delta_5 = 0; the foot's equation, with a flat
// neighbour, fixes delta_25 - delta_24 = 0.2); beyond the slope, pure Laplace with a mirrored
// edge is flat at H_25 = 80.25. So: the elevation exact on the plateau, the prescribed
// gradient on the slope except the last cells before the foot, harmonic (flat) beyond.
TEST(FeatureCurves, StraightRidgeGivesTheClosedFormProfile)
{
  FeatureSolverParameters p;
  p.plateauWeight = 1.0;
  p.tolerance = 1e-7;
  std::vector<float> h;
  DiffusionReport r;
  std::string error;
  ASSERT_TRUE(FeatureCurveTerrain({ StraightRidge() }, Grid(129, 9), nullptr, p, h, r, error))
    << error;
  EXPECT_TRUE(r.converged);
  for (int j = 0; j < 9; ++j)
  {
    for (int i = 0; i < 129; ++i)
    {
      const int d = std::abs(i - 64);
      double expected = 100.0;
      if (d > 5)
      {
        const int k = std::min(d, 25);
        expected = 100.0 - (k - 5) + 0.05 * (std::pow(5.0, k - 24) - std::pow(5.0, -19));
      }
      EXPECT_NEAR(h[static_cast<std::size_t>(j) * 129 + i], expected, 1e-5)
        << "i = " << i << ", j = " << j;
    }
  }
  // The slope's gradient is the prescribed tan 45 = 1 m per cell over its first 13 cells
  // (delta_18 - delta_17 = 2.6e-6; heights are float32, 7.6e-6 apart near 100 m).
  for (int d = 6; d <= 18; ++d)
  {
    EXPECT_NEAR(h[64 + d - 1] - h[64 + d], 1.0, 3e-5) << "d = " << d;
  }
}

// With Weiss's alpha = 0.9 the plateau is pulled a little by its neighbours; the multigrid
// answer is the same as the one of plain Jacobi iterations of eq. 9, and close to the ideal.
TEST(FeatureCurves, MultigridAgreesWithJacobiOnTheRidge)
{
  FeatureSolverParameters p;
  p.tolerance = 1e-7;
  FeatureConstraints c;
  std::string error;
  ASSERT_TRUE(RasterizeFeatureCurves({ StraightRidge() }, Grid(129, 9), p, c, error));
  auto mg = BuildDiffusionLevels(c, 129, 9, nullptr, p);
  auto jacobi = mg;
  const DiffusionReport r = SolveDiffusionMultigrid(mg, p);
  EXPECT_TRUE(r.converged);
  SolveDiffusionJacobi(jacobi[0], 1e-12, 100000);
  double largest = 0.0;
  for (std::size_t k = 0; k < mg[0].h.size(); ++k)
  {
    largest = std::max(largest, static_cast<double>(std::abs(mg[0].h[k] - jacobi[0].h[k])));
  }
  EXPECT_LT(largest, 1e-5);
  EXPECT_NEAR(mg[0].h[64], 100.0, 0.05); // the curve itself
}

// The curved scene: multigrid and Jacobi agree, the residual is below the tolerance after a
// few cycles, cells outside every envelope keep the base exactly, and 1 or 2 threads give the
// same bits.
TEST(FeatureCurves, SceneMultigridJacobiEnvelopeAndThreads)
{
  const int n = 65;
  std::vector<float> base;
  const auto curves = Scene(base, n);
  FeatureSolverParameters p;
  p.tolerance = 1e-6;
  FeatureConstraints c;
  std::string error;
  ASSERT_TRUE(RasterizeFeatureCurves(curves, Grid(n, n), p, c, error)) << error;
  int plateau = 0, slope = 0, outside = 0;
  for (std::size_t k = 0; k < c.kind.size(); ++k)
  {
    plateau += c.kind[k] == 1;
    slope += c.kind[k] == 2;
    outside += c.gamma[k] == 0.0f;
  }
  EXPECT_GT(plateau, 100);
  EXPECT_GT(slope, 400);
  EXPECT_GT(outside, 400);
  auto mg = BuildDiffusionLevels(c, n, n, base.data(), p);
  auto jacobi = mg;
  auto two = mg;
  const DiffusionReport r = SolveDiffusionMultigrid(mg, p);
  EXPECT_TRUE(r.converged);
  EXPECT_LT(r.cycles, 25);
  EXPECT_LT(r.residual, 1e-5);
  SolveDiffusionJacobi(jacobi[0], 1e-12, 100000);
  double largest = 0.0;
  for (std::size_t k = 0; k < mg[0].h.size(); ++k)
  {
    largest = std::max(largest, static_cast<double>(std::abs(mg[0].h[k] - jacobi[0].h[k])));
    if (c.gamma[k] == 0.0f && c.kind[k] == 0)
    {
      EXPECT_EQ(mg[0].h[k], base[k]) << "cell " << k << " outside the envelope moved";
    }
  }
  EXPECT_LT(largest, 1e-5);
  const DiffusionReport r2 = SolveDiffusionMultigrid(two, p, TwoThreads);
  EXPECT_EQ(r2.cycles, r.cycles);
  EXPECT_EQ(0, std::memcmp(two[0].h.data(), mg[0].h.data(), mg[0].h.size() * sizeof(double)));
}

// A slope across the grid's diagonal comes out at its angle: G makes eq. 6-7 exact for a plane,
// so between plateau and foot the height falls by tan(30) per metre of distance from the curve.
TEST(FeatureCurves, DiagonalSlopeHasThePrescribedAngle)
{
  FeatureCurve c{ Point(-500, 500, 50), Point(500, -500, 50) }; // the line x + y = 0
  for (auto& q : c)
  {
    q.plateauWidth = 4.0;
    q.slopeLeftWidth = q.slopeRightWidth = 30.0;
    q.slopeLeftAngle = q.slopeRightAngle = 30.0;
  }
  FeatureSolverParameters p;
  p.plateauWeight = 1.0;
  p.tolerance = 1e-5;
  FeatureGrid g = Grid(41, 41);
  g.x0 = g.y0 = -20.0;
  std::vector<float> h;
  DiffusionReport r;
  std::string error;
  ASSERT_TRUE(FeatureCurveTerrain({ c }, g, nullptr, p, h, r, error)) << error;
  const double t = std::tan(30.0 * 3.14159265358979323846 / 180.0);
  // Points (i, i) lie at distance sqrt(2) |x| from the line: one diagonal step is sqrt(2) m
  // farther, so the height falls by sqrt(2) tan 30 per step, from the plateau to the foot.
  for (int i = 23; i <= 32; ++i)
  {
    const std::size_t a = static_cast<std::size_t>(i) * 41 + i, b = a + 42;
    EXPECT_NEAR(h[a] - h[b], std::sqrt(2.0) * t, 0.02) << "i = " << i;
  }
  // The other side is the mirror image.
  EXPECT_NEAR(
    h[static_cast<std::size_t>(25) * 41 + 25], h[static_cast<std::size_t>(15) * 41 + 15], 1e-3);
}

TEST(FeatureCurves, BadCurvesAreRefused)
{
  FeatureSolverParameters p;
  FeatureConstraints c;
  std::string error;
  EXPECT_FALSE(RasterizeFeatureCurves({ FeatureCurve{ Point(0, 0, 0) } }, Grid(8, 8), p, c, error));
  EXPECT_NE(error.find("fewer than two"), std::string::npos);
  FeatureCurve steep{ Point(0, 0, 0), Point(5, 5, 0) };
  steep[1].slopeLeftAngle = 90.0;
  EXPECT_FALSE(RasterizeFeatureCurves({ steep }, Grid(8, 8), p, c, error));
  EXPECT_NE(error.find("angles"), std::string::npos);
  FeatureCurve nan{ Point(0, 0, 0), Point(5, std::nan(""), 0) };
  EXPECT_FALSE(RasterizeFeatureCurves({ nan }, Grid(8, 8), p, c, error));
  EXPECT_NE(error.find("finite"), std::string::npos);
}

// The rasteriser visits only the cells near each piece of the sampled curve (strips, wedges at
// the bends, caps at the ends): it must find what a search of every piece for every cell finds.
TEST(FeatureCurves, RasterisingMatchesABruteForceSearch)
{
  const int n = 65;
  std::vector<float> base;
  auto curves = Scene(base, n);
  // A sharp bend too (90 degrees), so that the wedge on its outer side matters.
  FeatureCurve bend{ Point(20, 5, 30), Point(40, 5, 30), Point(40, 25, 30) };
  for (auto& p : bend)
  {
    p.plateauWidth = 2.0;
    p.slopeLeftWidth = p.slopeRightWidth = 9.0;
    p.slopeLeftAngle = p.slopeRightAngle = 20.0;
    p.envelopeLeft = p.envelopeRight = 3.0;
  }
  curves.push_back(bend);
  FeatureSolverParameters p;
  FeatureConstraints c;
  std::string error;
  ASSERT_TRUE(RasterizeFeatureCurves(curves, Grid(n, n), p, c, error)) << error;
  std::vector<double> best(static_cast<std::size_t>(n) * n, 1e300);
  std::vector<int> kind(best.size(), 0);
  std::vector<int> inside(best.size(), 0);
  for (const auto& curve : curves)
  {
    const auto s = SampleFeatureCurveFlat(curve, 0.05, 64.0);
    for (std::size_t q = 0; q + 1 < s.size(); ++q)
    {
      const auto &A = s[q], &B = s[q + 1];
      const double ex = B.x - A.x, ey = B.y - A.y, len2 = ex * ex + ey * ey;
      for (int j = 0; j < n; ++j)
      {
        for (int i = 0; i < n; ++i)
        {
          double u = len2 > 0 ? ((i - A.x) * ex + (j - A.y) * ey) / len2 : 0.0;
          u = std::min(1.0, std::max(0.0, u));
          const double d = std::max(0.0, std::hypot(i - A.x - u * ex, j - A.y - u * ey) - 1e-6);
          const bool left = ex * (j - A.y) - ey * (i - A.x) > 0.0;
          const double half = 0.5 * (A.plateauWidth + u * (B.plateauWidth - A.plateauWidth));
          const double w = left ? A.slopeLeftWidth + u * (B.slopeLeftWidth - A.slopeLeftWidth)
                                : A.slopeRightWidth + u * (B.slopeRightWidth - A.slopeRightWidth);
          const double env = left ? A.envelopeLeft + u * (B.envelopeLeft - A.envelopeLeft)
                                  : A.envelopeRight + u * (B.envelopeRight - A.envelopeRight);
          const std::size_t k = static_cast<std::size_t>(j) * n + i;
          inside[k] |= d <= half + w + env;
          if (d <= half + w && d < best[k])
          {
            best[k] = d;
            kind[k] = d <= half ? 1 : 2;
          }
        }
      }
    }
  }
  int mismatches = 0, constrained = 0;
  for (std::size_t k = 0; k < best.size(); ++k)
  {
    mismatches += kind[k] != c.kind[k] || inside[k] != (c.gamma[k] == 1.0f);
    constrained += kind[k] != 0;
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(constrained, 1000);
}

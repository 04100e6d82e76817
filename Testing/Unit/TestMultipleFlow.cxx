// Unit tests of the dispersive baselines (no VTK, no GL): terroir::hydrology::
// MultipleFlowAccumulation (Freeman 1991, Quinn et al. 1991, Qin et al. 2007),
// DInfinityAccumulation (Tarboton 1997) and ChannelInitiationScore, after
// PriorityFloodBarnes2014 and D8FlowDirections. Expected shares are worked out by hand in the
// comments; plane tests use the recursion each method's fractions imply.
#include "FlowAccumulation.h"
#include "MultipleFlow.h"
#include "PriorityFlood.h"

#include "TerroirDrawnGrid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

namespace
{
namespace hy = terroir::hydrology;
using Grid = terroir_test::DrawnGrid;
constexpr double kPi = 3.14159265358979323846;

struct Filled
{
  std::vector<float> filled;
  std::vector<std::int8_t> dir;
};

Filled Fill(const Grid& g)
{
  Filled f;
  f.filled.assign(g.z.size(), 0.0f);
  f.dir.assign(g.z.size(), 0);
  hy::PriorityFloodBarnes2014(g.view, f.filled.data());
  hy::D8FlowDirections(g.view, f.filled.data(), f.dir.data());
  return f;
}

/// A cone's apex: the centre (10) above its 8 neighbours (9); the neighbours are edge cells
/// with no lower neighbour, so they are outlets and keep what they get.
Grid Apex()
{
  return Grid(3, 3, 1.0, 1.0, { { 9, 9, 9 }, { 9, 10, 9 }, { 9, 9, 9 } });
}

TEST(MultipleFlow, FreemanSharesOnAConeApex)
{
  // Slopes: 1 to the cardinal neighbours, 1/sqrt(2) to the diagonals. With p = 1.1 the shares
  // are 1 and 2^-0.55, normalised: a cardinal gets 1 / (4 + 4 * 2^-0.55).
  const Grid g = Apex();
  const Filled f = Fill(g);
  std::vector<double> acc(9, -1.0);
  hy::MFDOptions o;
  o.exponent = 1.1;
  hy::MultipleFlowAccumulation(g.view, f.filled.data(), f.dir.data(), o, nullptr, acc.data());
  const double d = std::pow(2.0, -0.55);
  const double total = 4.0 + 4.0 * d;
  EXPECT_DOUBLE_EQ(acc[g.Cell(1, 1)], 1.0);
  EXPECT_NEAR(acc[g.Cell(2, 1)], 1.0 + 1.0 / total, 1e-12); // E
  EXPECT_NEAR(acc[g.Cell(1, 2)], 1.0 + 1.0 / total, 1e-12); // N
  EXPECT_NEAR(acc[g.Cell(2, 2)], 1.0 + d / total, 1e-12);   // NE
  EXPECT_NEAR(acc[g.Cell(0, 0)], 1.0 + d / total, 1e-12);   // SW
}

TEST(MultipleFlow, QuinnContourLengthShares)
{
  // p = 1 times the contour length: cardinal 1 * 0.5, diagonal (1/sqrt 2) * (sqrt 2 / 4) =
  // 0.25; total 4 * 0.5 + 4 * 0.25 = 3: a cardinal gets 1/6, a diagonal 1/12.
  const Grid g = Apex();
  const Filled f = Fill(g);
  std::vector<double> acc(9, -1.0);
  hy::MFDOptions o;
  o.exponent = 1.0;
  o.contourLength = true;
  hy::MultipleFlowAccumulation(g.view, f.filled.data(), f.dir.data(), o, nullptr, acc.data());
  EXPECT_NEAR(acc[g.Cell(0, 1)], 1.0 + 1.0 / 6.0, 1e-12);  // W
  EXPECT_NEAR(acc[g.Cell(0, 2)], 1.0 + 1.0 / 12.0, 1e-12); // NW
}

TEST(MultipleFlow, AdaptiveExponentGrowsWithSlope)
{
  // Qin et al. (2007): p = 1.1 + 8.9 min(tan b, 1). The apex scaled to a drop of 0.5 has
  // tan b = 0.5, p = 5.55: a cardinal gets 1 / (4 + 4 * 2^(-p/2)).
  Grid g(3, 3, 1.0, 1.0, { { 9, 9, 9 }, { 9, 9.5f, 9 }, { 9, 9, 9 } });
  const Filled f = Fill(g);
  std::vector<double> acc(9, -1.0);
  hy::MFDOptions o;
  o.adaptive = true;
  hy::MultipleFlowAccumulation(g.view, f.filled.data(), f.dir.data(), o, nullptr, acc.data());
  const double p = 1.1 + 8.9 * 0.5;
  EXPECT_NEAR(acc[g.Cell(2, 1)], 1.0 + 1.0 / (4.0 + 4.0 * std::pow(2.0, -p / 2.0)), 1e-6);
}

/// A plane z = -(x cos(phi) + y sin(phi)) on nx x ny unit cells.
Grid Plane(int nx, int ny, double phiDegrees)
{
  const double phi = phiDegrees * kPi / 180.0;
  std::vector<std::vector<float>> rows(ny, std::vector<float>(nx));
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      rows[ny - 1 - j][i] = static_cast<float>(-(i * std::cos(phi) + j * std::sin(phi)));
    }
  }
  return Grid(nx, ny, 1.0, 1.0, rows);
}

TEST(DInfinity, PlaneDueEastFlowsInColumns)
{
  // phi = 0: facet E-NE has r = 0 (s1 = 1, s2 = 0) and ties with E-SE; the first wins, so all
  // the flow goes east: accumulation i + 1; the eastern column (no lower neighbour) drains off.
  const Grid g = Plane(6, 4, 0.0);
  const Filled f = Fill(g);
  std::vector<double> acc(g.z.size(), -1.0);
  std::vector<float> angle(g.z.size(), -1.0f);
  hy::DInfinityAccumulation(
    g.view, f.filled.data(), f.dir.data(), nullptr, acc.data(), angle.data());
  for (int j = 0; j < 4; ++j)
  {
    for (int i = 0; i < 6; ++i)
    {
      EXPECT_NEAR(acc[g.Cell(i, j)], i + 1.0, 1e-12) << i << ", " << j;
      if (i < 5)
      {
        EXPECT_NEAR(angle[g.Cell(i, j)], 0.0, 1e-6);
      }
    }
  }
}

TEST(DInfinity, PlaneOnAFacetBisectorSplitsHalfAndHalf)
{
  // phi = 22.5 degrees: inside the E-NE facet, s1 = cos(phi), s2 = sin(phi), r = phi = a / 2:
  // half east, half north-east. The northern row has no NE neighbour: its best facet is E-SE
  // with r < 0 -> r = 0, all east. The eastern column has no E neighbour: its best facet is
  // N-NW with r < 0, all north. So A(i, j) = 1 + share from the west + share from the south-west
  // (+ all of the southern cell in the eastern column), worked out in that order.
  const int nx = 7, ny = 5;
  const Grid g = Plane(nx, ny, 22.5);
  const Filled f = Fill(g);
  std::vector<double> acc(g.z.size(), -1.0);
  std::vector<float> angle(g.z.size(), -1.0f);
  hy::DInfinityAccumulation(
    g.view, f.filled.data(), f.dir.data(), nullptr, acc.data(), angle.data());
  std::vector<double> want(g.z.size(), 0.0);
  auto toEast = [&](int i, int j) { return i == nx - 1 ? 0.0 : (j == ny - 1 ? 1.0 : 0.5); };
  auto toNorthEast = [&](int i, int j) { return i == nx - 1 || j == ny - 1 ? 0.0 : 0.5; };
  for (int i = 0; i < nx; ++i)
  {
    for (int j = 0; j < ny; ++j)
    {
      double a = 1.0;
      if (i > 0)
      {
        a += toEast(i - 1, j) * want[g.Cell(i - 1, j)];
      }
      if (i > 0 && j > 0)
      {
        a += toNorthEast(i - 1, j - 1) * want[g.Cell(i - 1, j - 1)];
      }
      if (i == nx - 1 && j > 0)
      {
        a += want[g.Cell(i, j - 1)]; // the eastern column flows north
      }
      want[g.Cell(i, j)] = a;
    }
  }
  for (std::size_t k = 0; k < want.size(); ++k)
  {
    // Heights are floats: r is a / 2 within about 1e-7, and so are the shares.
    EXPECT_NEAR(acc[k], want[k], 1e-5 * want[k]) << "cell " << k;
  }
  EXPECT_NEAR(acc[g.Cell(nx - 1, ny - 1)], nx * ny, 1e-9); // the one outlet
  EXPECT_NEAR(angle[g.Cell(2, 2)], 22.5 * kPi / 180.0, 1e-5);
  EXPECT_TRUE(std::isnan(angle[g.Cell(nx - 1, ny - 1)]));
}

TEST(DInfinity, FacetAngleIsTheGradientDirection)
{
  // Any direction inside a facet is reproduced: phi = 110 degrees lies in facet N-NW
  // (r = 20 degrees from north towards north-west).
  const Grid g = Plane(5, 5, 110.0);
  const Filled f = Fill(g);
  std::vector<double> acc(g.z.size());
  std::vector<float> angle(g.z.size());
  hy::DInfinityAccumulation(
    g.view, f.filled.data(), f.dir.data(), nullptr, acc.data(), angle.data());
  EXPECT_NEAR(angle[g.Cell(2, 2)], 110.0 * kPi / 180.0, 1e-5);
}

TEST(MultipleFlow, RandomTerrainsConserveCellsAndRouteFlats)
{
  // Quantised random heights (flats and pits abound) and a no-data hole: every cell's unit
  // reaches an outlet, so the outlets' accumulations sum to the cells with data.
  std::mt19937_64 rng(20261126);
  std::uniform_int_distribution<int> level(0, 6);
  for (int t = 0; t < 20; ++t)
  {
    const int nx = 9 + t % 5, ny = 7 + t % 3;
    std::vector<std::vector<float>> rows(ny, std::vector<float>(nx));
    for (auto& r : rows)
    {
      for (float& z : r)
      {
        z = static_cast<float>(level(rng));
      }
    }
    Grid g(nx, ny, 10.0, 12.0, rows);
    g.MaskOut(nx / 2, ny / 2);
    const Filled f = Fill(g);
    std::vector<double> mfd(g.z.size()), dinf(g.z.size()), md(g.z.size());
    hy::MFDOptions o;
    hy::MultipleFlowAccumulation(g.view, f.filled.data(), f.dir.data(), o, nullptr, mfd.data());
    o.adaptive = true;
    hy::MultipleFlowAccumulation(g.view, f.filled.data(), f.dir.data(), o, nullptr, md.data());
    hy::DInfinityAccumulation(g.view, f.filled.data(), f.dir.data(), nullptr, dinf.data());
    for (const auto* acc : { &mfd, &md, &dinf })
    {
      double outlets = 0.0;
      for (std::size_t k = 0; k < g.z.size(); ++k)
      {
        if (f.dir[k] == hy::kD8NoData)
        {
          EXPECT_TRUE(std::isnan((*acc)[k]));
          continue;
        }
        EXPECT_GE((*acc)[k], 1.0 - 1e-12);
        outlets += f.dir[k] == hy::kD8Outlet ? (*acc)[k] : 0.0;
      }
      EXPECT_NEAR(outlets, static_cast<double>(nx * ny - 1), 1e-9 * nx * ny) << "terrain " << t;
    }
  }
}

TEST(MultipleFlow, WeightsAndCellAreas)
{
  // Weights replace the 1 per cell; timesCellArea multiplies by dx dy (2 x 3 m here).
  Grid g(3, 3, 2.0, 3.0, { { 9, 9, 9 }, { 9, 10, 9 }, { 9, 9, 9 } });
  const Filled f = Fill(g);
  std::vector<float> w(9, 0.0f);
  w[g.Cell(1, 1)] = 4.0f;
  std::vector<double> acc(9);
  hy::AccumulationOptions opt;
  opt.timesCellArea = true;
  hy::DInfinityAccumulation(
    g.view, f.filled.data(), f.dir.data(), w.data(), acc.data(), nullptr, opt);
  double outlets = 0.0;
  for (std::size_t k = 0; k < 9; ++k)
  {
    outlets += k == g.Cell(1, 1) ? 0.0 : acc[k];
  }
  EXPECT_DOUBLE_EQ(acc[g.Cell(1, 1)], 24.0);
  EXPECT_NEAR(outlets, 24.0, 1e-12);
}

TEST(MultipleFlow, ChannelInitiationScoreByHand)
{
  // A S^theta with S the steepest descent of the unfilled terrain: the centre drops 1 m over
  // 2 m to the east (S = 0.5); the eastern cells are edge cells with no lower neighbour (S = 0,
  // floored at 0.01).
  Grid g(3, 1, 2.0, 2.0, { { 3, 2, 1 } });
  std::vector<double> a = { 1.0, 2.0, 3.0 };
  std::vector<double> score(3);
  hy::ChannelInitiationScore(g.view, a.data(), 2.0, 0.01, score.data());
  EXPECT_NEAR(score[0], 1.0 * 0.25, 1e-12);
  EXPECT_NEAR(score[1], 2.0 * 0.25, 1e-12);
  EXPECT_NEAR(score[2], 3.0 * 1e-4, 1e-15);
  hy::ChannelInitiationScore(g.view, a.data(), 0.0, 0.0, score.data());
  EXPECT_DOUBLE_EQ(score[2], 3.0); // theta 0: the accumulation itself
}

TEST(MultipleFlow, BadParametersThrow)
{
  const Grid g = Apex();
  const Filled f = Fill(g);
  std::vector<double> acc(9);
  hy::MFDOptions o;
  o.exponent = 0.0;
  EXPECT_THROW(
    hy::MultipleFlowAccumulation(g.view, f.filled.data(), f.dir.data(), o, nullptr, acc.data()),
    std::invalid_argument);
  EXPECT_THROW(
    hy::ChannelInitiationScore(g.view, acc.data(), -1.0, 0.0, acc.data()), std::invalid_argument);
}

} // namespace

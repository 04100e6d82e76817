// Unit tests of Dunn's (2015) atmosphere core (terroir::terrain::AtmosphereStep and helpers):
// wind on the pipe model as a pressure field, vapour transport, rain. Expected values are worked
// out by hand in the comments from the equations of Atmosphere.h (Weiss eq. 11-16 on the air
// height, Dunn sections 2.3 and 3.5), from the Magnus formula restated here, or are properties
// any correct implementation has: still air stays still, air and vapour are conserved, a mirror
// or transposed world gives the mirrored or transposed wind, any row split gives the same bits.
#include "Atmosphere.h"
#include "Vegetation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{
using terroir::GridView;
namespace tr = terroir::terrain;

using Field = std::function<float(int, int)>;

std::vector<float> Fill(int nx, int ny, const Field& f)
{
  std::vector<float> v(static_cast<std::size_t>(nx) * ny);
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      v[static_cast<std::size_t>(j) * nx + i] = f(i, j);
    }
  }
  return v;
}

/// A still atmosphere of air height h0 on nx x ny square cells of `spacing` metres.
tr::AtmosphereState MakeAir(int nx,
  int ny,
  double h0,
  double spacing = 1.0,
  const std::vector<float>* vapour = nullptr,
  const std::uint8_t* valid = nullptr)
{
  GridView<float> grid;
  grid.nx = nx;
  grid.ny = ny;
  grid.dx = spacing;
  grid.dy = spacing;
  grid.valid = valid;
  return tr::MakeAtmosphereState(grid, h0, vapour ? vapour->data() : nullptr);
}

/// Random bumps in [0, amplitude] metres (seeded).
std::vector<float> Bumps(int nx, int ny, float amplitude, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, amplitude);
  return Fill(nx, ny, [&](int, int) { return u(rng); });
}

/// Magnus, restated from Vegetation.h's comment (Alduchov & Eskridge 1996): x_s, kg/kg.
double Magnus(double t, double p)
{
  const double es = 610.94 * std::exp(17.625 * t / (t + 243.04));
  return 0.622 * es / (p - es);
}

double Max(const std::vector<float>& v)
{
  double m = 0.0;
  for (float x : v)
  {
    m = std::max(m, static_cast<double>(std::fabs(x)));
  }
  return m;
}

TEST(TerroirAtmosphereCore, StillAirOverAnyTerrainStaysStill)
{
  // Uniform air height: every pipe sees h - h_k = 0, so no flux, u = v = 0 exactly, and the
  // vapour is sampled at its own cells (k = 1): nothing changes, whatever the terrain (the
  // terrain only shapes the pipes). Vapour 2 mm is below the capacity (x = 0.002 < x_s(15 C)
  // = 0.0107 at sea level; the bumps are at most 50 m high): no rain.
  const int nx = 9, ny = 7;
  const std::vector<float> b = Bumps(nx, ny, 50.0f, 3);
  const std::vector<float> q(static_cast<std::size_t>(nx) * ny, 0.002f);
  tr::AtmosphereState st = MakeAir(nx, ny, 10.0, 1.0, &q);
  std::vector<float> rain(q.size(), 0.0f);
  for (int n = 0; n < 100; ++n)
  {
    const tr::AtmosphereStepStats s =
      tr::AtmosphereStep(st, tr::AtmosphereParams(), b.data(), nullptr, rain.data());
    ASSERT_EQ(s.rain, 0.0);
  }
  EXPECT_EQ(Max(st.velocityU), 0.0);
  EXPECT_EQ(Max(st.velocityV), 0.0);
  EXPECT_EQ(st.air, std::vector<float>(q.size(), 10.0f));
  EXPECT_EQ(st.vapour, q);
  EXPECT_EQ(Max(rain), 0.0);
}

TEST(TerroirAtmosphereCore, HandWorkedFluxStep)
{
  // 3x3 cells of 1 m, h = 10 m, the centre 11 m; dt = 0.01, g = 10, A0 = l^2 = 1, c = 0.5.
  // Terrain 0 but the east neighbour at 1 m (uphill tangent 1: A = 1 - 0.5 = 0.5) and the north
  // one at -1 m (downhill: A = 1). Centre pipes: f = dt g A (11 - 10) / l = 0.1 A:
  // W 0.1, E 0.05, S 0.1, N 0.1; sum 0.35, K = min(1, 11 / (0.01 0.35)) = 1. Neighbours see a
  // higher centre: no flux. Centre h2 = 11 - 0.01 * 0.35 = 10.9965; west 10.001, east 10.0005.
  // Centre: dWx = ((0 - 0.1) + (0.05 - 0)) / 2 = -0.025, u = -0.025 / ((11 + 10.9965) / 2);
  // dWy = ((0 - 0.1) + (0.1 - 0)) / 2 = 0. East cell: dWx = 0.05 / 2, u = 0.025 / 10.00025.
  tr::AtmosphereState st = MakeAir(3, 3, 10.0);
  st.air[4] = 11.0f;
  std::vector<float> b(9, 0.0f);
  b[5] = 1.0f;
  b[7] = -1.0f;
  tr::AtmosphereParams p;
  p.uphillDamping = 0.5;
  EXPECT_FLOAT_EQ(tr::AtmospherePipeArea(p, 1.0f, 1.0f), 0.5f);
  EXPECT_FLOAT_EQ(tr::AtmospherePipeArea(p, 1.0f, -1.0f), 1.0f);
  EXPECT_FLOAT_EQ(tr::AtmospherePipeArea(p, 2.0f, 1.0f), 4.0f * 0.75f); // A0 = 4, tan 0.5
  EXPECT_FLOAT_EQ(tr::AtmospherePipeArea(p, 1.0f, 5.0f), 0.1f);         // clamped at A_min
  tr::AtmosphereStep(st, p, b.data());
  EXPECT_FLOAT_EQ(st.fluxW[4], 0.1f);
  EXPECT_FLOAT_EQ(st.fluxE[4], 0.05f);
  EXPECT_FLOAT_EQ(st.fluxS[4], 0.1f);
  EXPECT_FLOAT_EQ(st.fluxN[4], 0.1f);
  EXPECT_EQ(st.fluxW[5], 0.0f);
  EXPECT_EQ(st.fluxE[3], 0.0f);
  EXPECT_FLOAT_EQ(st.air[4], 10.9965f);
  EXPECT_FLOAT_EQ(st.air[3], 10.001f);
  EXPECT_FLOAT_EQ(st.air[5], 10.0005f);
  EXPECT_FLOAT_EQ(st.air[0], 10.0f);
  EXPECT_FLOAT_EQ(st.velocityU[4], -0.025f / 10.99825f);
  EXPECT_NEAR(st.velocityV[4], 0.0f, 1e-9f);
  EXPECT_FLOAT_EQ(st.velocityU[5], 0.025f / 10.00025f);
  EXPECT_FLOAT_EQ(st.velocityU[3], -0.05f / 10.0005f);
  EXPECT_FLOAT_EQ(st.velocityV[7], 0.05f / 10.0005f);

  // K: the centre 1 m, the rest 0, dt = 1: each pipe wants 1 * 10 * 1 * 1 = 10, sum 40, so
  // K = 1 / 40 and each pipe carries 0.25: the centre empties, each neighbour gets 0.25 m.
  tr::AtmosphereState dry = MakeAir(3, 3, 10.0);
  std::fill(dry.air.begin(), dry.air.end(), 0.0f);
  dry.air[4] = 1.0f;
  tr::AtmosphereParams big;
  big.timeStep = 1.0;
  tr::AtmosphereStep(dry, big, std::vector<float>(9, 0.0f).data());
  EXPECT_FLOAT_EQ(dry.fluxE[4], 0.25f);
  EXPECT_EQ(dry.air[4], 0.0f);
  for (int c : { 1, 3, 5, 7 })
  {
    EXPECT_FLOAT_EQ(dry.air[c], 0.25f) << c;
  }
}

TEST(TerroirAtmosphereCore, VapourTransportByHand)
{
  // A row of 4 cells of 1 m, air [11, 10, 10, 10] m, vapour [1, 2, 0, 0] mm, dt = 0.1 s.
  // Flux: cell 0 gives east f = dt g l (11 - 10) = 1 m^3/s (K = 1); h2 = [10.9, 10.1, 10, 10].
  // Velocities (eq. 16): u0 = ((0 - 0) + (1 - 0)) / 2 / ((11 + 10.9) / 2) = 0.5 / 10.95,
  // u1 = ((1 - 0) + (0 - 0)) / 2 / ((10 + 10.1) / 2) = 0.5 / 10.05, u2 = u3 = 0.
  // Back-trace: cell 1 samples at x = 1 - 0.1 u1 between cells 0 and 1: 1 + (1 - 0.1 u1)(2 - 1)
  // mm; cell 0 samples at -0.1 u0, clamped to the grid: 1 mm. Dunn's k = 3 / (1 + that), and
  // both are multiplied by it.
  const std::vector<float> q = { 0.001f, 0.002f, 0.0f, 0.0f };
  tr::AtmosphereState st = MakeAir(4, 1, 10.0, 1.0, &q);
  st.air[0] = 11.0f;
  tr::AtmosphereParams p;
  p.timeStep = 0.1;
  const tr::AtmosphereStepStats s = tr::AtmosphereStep(st, p, std::vector<float>(4, 0.0f).data());
  const double u0 = 0.5 / 10.95, u1 = 0.5 / 10.05;
  EXPECT_NEAR(st.velocityU[0], u0, 1e-7);
  EXPECT_NEAR(st.velocityU[1], u1, 1e-7);
  const double moved1 = 1.0 + (1.0 - 0.1 * u1);
  const double k = 3.0 / (1.0 + moved1);
  EXPECT_NEAR(s.vapourScale, k, 1e-6);
  EXPECT_NEAR(st.vapour[0], 0.001 * k, 1e-9);
  EXPECT_NEAR(st.vapour[1], 0.001 * moved1 * k, 1e-9);
  EXPECT_EQ(st.vapour[2], 0.0f);
  EXPECT_EQ(st.vapour[3], 0.0f);
}

TEST(TerroirAtmosphereCore, AirDamBreakConservesAir)
{
  // 20 x 16 cells of 50 m with a no-data hole (a wall), bumpy terrain, west half 12 m of air,
  // east half 8 m; dt = 1 s (wave speed sqrt(g h) ~ 11 m/s, a fifth of a cell per step).
  // Closed boundary: sum h a stays what it was, to float rounding (1e-6 relative over
  // 500 steps), h >= 0, the hole holds no air, and air did move east.
  const int nx = 20, ny = 16;
  std::vector<std::uint8_t> valid(static_cast<std::size_t>(nx) * ny, 1);
  valid[5 * nx + 9] = valid[5 * nx + 10] = valid[6 * nx + 10] = 0;
  tr::AtmosphereState st = MakeAir(nx, ny, 10.0, 50.0, nullptr, valid.data());
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      const std::size_t c = static_cast<std::size_t>(j) * nx + i;
      st.air[c] = valid[c] ? (i < nx / 2 ? 12.0f : 8.0f) : 0.0f;
    }
  }
  const std::vector<float> b = Bumps(nx, ny, 20.0f, 5);
  tr::AtmosphereParams p;
  p.timeStep = 1.0;
  const double air0 = tr::AtmosphereMeasure(st).air;
  for (int n = 0; n < 500; ++n)
  {
    tr::AtmosphereStep(st, p, b.data());
    ASSERT_GE(*std::min_element(st.air.begin(), st.air.end()), 0.0f) << n;
  }
  EXPECT_NEAR(tr::AtmosphereMeasure(st).air / air0, 1.0, 1e-6);
  EXPECT_EQ(st.air[5 * nx + 9], 0.0f);
  EXPECT_EQ(st.fluxE[5 * nx + 8], 0.0f); // nothing flows into the wall
  double east = 0.0;
  for (int j = 0; j < ny; ++j)
  {
    east += st.air[static_cast<std::size_t>(j) * nx + nx - 1];
  }
  EXPECT_GT(east / ny, 8.5); // started at 8 m
}

/// Runs `steps` steps of a prevailing wind from `fromDeg` on terrain b (air 10 m, cells 1 m).
tr::AtmosphereState Blow(int nx, int ny, const std::vector<float>& b, double fromDeg, int steps)
{
  tr::AtmosphereState st = MakeAir(nx, ny, 10.0);
  tr::AtmosphereParams p;
  p.windDirectionDeg = fromDeg;
  p.windStrength = 1.0;
  for (int n = 0; n < steps; ++n)
  {
    tr::AtmosphereStep(st, p, b.data());
  }
  return st;
}

double Mean(const std::vector<float>& v)
{
  double s = 0.0;
  for (float x : v)
  {
    s += x;
  }
  return s / static_cast<double>(v.size());
}

TEST(TerroirAtmosphereCore, PrevailingWindBlowsFromItsDirection)
{
  // From the west (270) on flat ground: air is added on the west column, removed on the east
  // one; every column stays uniform, so v = 0 exactly and u > 0 (eastwards). Total air is
  // unchanged (the source is balanced by the sink).
  const int nx = 24, ny = 16;
  const std::vector<float> flat(static_cast<std::size_t>(nx) * ny, 0.0f);
  tr::AtmosphereState west = Blow(nx, ny, flat, 270.0, 300);
  EXPECT_GT(Mean(west.velocityU), 1e-4);
  EXPECT_LE(Max(west.velocityV), 1e-6 * Max(west.velocityU));
  EXPECT_NEAR(tr::AtmosphereMeasure(west).air / (10.0 * nx * ny), 1.0, 1e-6);
  EXPECT_GT(west.air[0], west.air[nx - 1]); // higher pressure upwind
  // From the east (90): the mirror image, u < 0.
  tr::AtmosphereState east = Blow(nx, ny, flat, 90.0, 300);
  EXPECT_NEAR(Mean(east.velocityU), -Mean(west.velocityU), 1e-6 * Max(west.velocityU));
  // From the north-west (315): u > 0 and v < 0 (blowing south-east), by symmetry |u| = |v| on a
  // square grid.
  const std::vector<float> flatSq(static_cast<std::size_t>(ny) * ny, 0.0f);
  tr::AtmosphereState nw = Blow(ny, ny, flatSq, 315.0, 300);
  EXPECT_GT(Mean(nw.velocityU), 1e-5);
  EXPECT_NEAR(Mean(nw.velocityV), -Mean(nw.velocityU), 1e-4 * Mean(nw.velocityU));

  // Rotating the direction by 90 degrees (from the south, 180) on the transposed grid with the
  // transposed (bumpy) terrain gives the transposed wind: u(i, j) there is v(j, i) here.
  const std::vector<float> b = Bumps(nx, ny, 0.5f, 9);
  std::vector<float> bt(b.size());
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      bt[static_cast<std::size_t>(i) * ny + j] = b[static_cast<std::size_t>(j) * nx + i];
    }
  }
  tr::AtmosphereState a = Blow(nx, ny, b, 270.0, 200);
  tr::AtmosphereState t = Blow(ny, nx, bt, 180.0, 200);
  const double scale = Max(a.velocityU);
  ASSERT_GT(Max(a.velocityV), 1e-3 * scale); // the bumps do turn the wind
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      const std::size_t c = static_cast<std::size_t>(j) * nx + i;
      const std::size_t ct = static_cast<std::size_t>(i) * ny + j;
      ASSERT_NEAR(a.velocityU[c], t.velocityV[ct], 1e-6 * scale) << i << "," << j;
      ASSERT_NEAR(a.velocityV[c], t.velocityU[ct], 1e-6 * scale) << i << "," << j;
      ASSERT_NEAR(a.air[c], t.air[ct], 1e-5f) << i << "," << j;
    }
  }
}

TEST(TerroirAtmosphereCore, PrevailingWindByHandNeverTakesMoreAirThanThereIs)
{
  // A row of 3 cells of 1 m, air [1, 1, 0.05] m, wind from the west, S = 10 m/s, dt = 0.01 s:
  // the west cell's weight is +1 (its west edge faces the wind), the east cell's -1, the middle
  // one's 0 (its north and south edges cancel). Wanted: +0.1 m west, -0.1 m east; the east cell
  // has only 0.05 m, so 0.05 m is removed and the addition is scaled down to the same 0.05 m.
  tr::AtmosphereState st = MakeAir(3, 1, 1.0);
  st.air[2] = 0.05f;
  tr::AtmosphereParams p;
  p.windStrength = 10.0;
  EXPECT_NEAR(tr::AtmospherePrevailingWind(st, p), 0.05, 1e-7);
  EXPECT_FLOAT_EQ(st.air[0], 1.05f);
  EXPECT_EQ(st.air[1], 1.0f);
  EXPECT_EQ(st.air[2], 0.0f);
  // From the east (90 degrees) the roles swap: 0.1 m moves from the west cell to the east one.
  p.windDirectionDeg = 90.0;
  EXPECT_NEAR(tr::AtmospherePrevailingWind(st, p), 0.1, 1e-7);
  EXPECT_FLOAT_EQ(st.air[0], 0.95f);
  EXPECT_FLOAT_EQ(st.air[2], 0.1f);
}

TEST(TerroirAtmosphereCore, WindIsSlowerUpARidge)
{
  // A north-south ridge across the middle (rising 0.25 m per 1 m cell: uphill tangent 0.25,
  // A = 1 - 2 * 0.25 = 0.5 of A0 on the windward pipes). The same wind from the west: on the
  // windward flank the eastward wind is slower than over flat ground (where the terrain plays no
  // part), averaged over the run.
  const int nx = 32, ny = 8;
  const std::vector<float> ridge =
    Fill(nx, ny, [](int i, int) { return std::max(0.0f, 4.0f - 0.25f * std::abs(i - 16)); });
  const std::vector<float> flat(ridge.size(), 0.0f);
  tr::AtmosphereParams p;
  p.windStrength = 1.0;
  tr::AtmosphereState r = MakeAir(nx, ny, 10.0), f = MakeAir(nx, ny, 10.0);
  double ur = 0.0, uf = 0.0;
  for (int n = 0; n < 400; ++n)
  {
    tr::AtmosphereStep(r, p, ridge.data());
    tr::AtmosphereStep(f, p, flat.data());
    for (int j = 0; j < ny; ++j)
    {
      for (int i = 2; i < 15; ++i) // the windward flank, i = 1 .. 15 rising
      {
        ur += r.velocityU[static_cast<std::size_t>(j) * nx + i];
        uf += f.velocityU[static_cast<std::size_t>(j) * nx + i];
      }
    }
  }
  EXPECT_GT(uf, 0.0);
  EXPECT_LT(ur, 0.8 * uf);
}

TEST(TerroirAtmosphereCore, VapourIsConservedAndNeverNegative)
{
  // Random vapour (0 to 5 mm, below capacity: no rain) on bumpy terrain with a no-data cell,
  // blown from the south-west for 1000 steps: Dunn's rescaling keeps the total (1e-6
  // relative), bilinear back-tracing keeps it >= 0, and it did move (the field changed).
  const int nx = 20, ny = 14;
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> u(0.0f, 0.005f);
  std::vector<float> q = Fill(nx, ny, [&](int, int) { return u(rng); });
  std::vector<std::uint8_t> valid(q.size(), 1);
  valid[7 * nx + 4] = 0;
  tr::AtmosphereState st = MakeAir(nx, ny, 10.0, 1.0, &q, valid.data());
  const std::vector<float> b = Bumps(nx, ny, 1.0f, 2);
  tr::AtmosphereParams p;
  p.windDirectionDeg = 225.0;
  p.windStrength = 2.0;
  const double v0 = tr::AtmosphereMeasure(st).vapour;
  const std::vector<float> start = st.vapour;
  for (int n = 0; n < 1000; ++n)
  {
    const tr::AtmosphereStepStats s = tr::AtmosphereStep(st, p, b.data());
    ASSERT_EQ(s.rain, 0.0);
    ASSERT_GE(*std::min_element(st.vapour.begin(), st.vapour.end()), 0.0f) << n;
  }
  EXPECT_NEAR(tr::AtmosphereMeasure(st).vapour / v0, 1.0, 1e-6);
  EXPECT_EQ(st.vapour[7 * nx + 4], 0.0f);
  double changed = 0.0;
  for (std::size_t c = 0; c < q.size(); ++c)
  {
    changed += std::fabs(st.vapour[c] - start[c]);
  }
  EXPECT_GT(changed, 0.1 * v0); // v0 is per m^2 of 1 m cells
}

TEST(TerroirAtmosphereCore, RainsTheExcessOverCapacityByHand)
{
  // Still air at h_ref over flat sea-level ground, temperature 20 C given per cell:
  // x_s = Magnus(20 C, 101325 Pa) = 0.014662. With M = 1000 kg/m^2 and rho_w = 1000 kg/m^3,
  // x = q. The centre holds 20 mm (x = 0.020 > x_s): it rains r_c dt (x - x_s) M / rho_w =
  // 1 * 0.01 * (0.020 - 0.014662) = 5.34e-5 m, and the vapour loses the same. The other
  // cells hold 10 mm (x < x_s): no rain.
  std::vector<float> q(9, 0.010f);
  q[4] = 0.020f;
  tr::AtmosphereState st = MakeAir(3, 3, 10.0, 1.0, &q);
  const std::vector<float> b(9, 0.0f), t(9, 20.0f);
  std::vector<float> rain(9, 0.0f);
  tr::AtmosphereParams p;
  const double xs = Magnus(20.0, 101325.0);
  EXPECT_NEAR(xs, 0.014662, 2e-6);
  const tr::AtmosphereStepStats s = tr::AtmosphereStep(st, p, b.data(), t.data(), rain.data());
  const double expected = 0.01 * (0.020 - xs);
  EXPECT_NEAR(rain[4], expected, 1e-9);
  EXPECT_NEAR(st.vapour[4], 0.020 - expected, 1e-9);
  EXPECT_NEAR(s.rain, expected, 1e-10);
  for (int c : { 0, 1, 2, 3, 5, 6, 7, 8 })
  {
    EXPECT_EQ(rain[c], 0.0f) << c;
    EXPECT_EQ(st.vapour[c], 0.010f) << c;
  }

  // The capacity fields that eq. 2.6 sees: pressure from the air height (p = p0 h / h_ref) and
  // temperature from the height (T0 - Gamma b = 15 - 6.5 = 8.5 C at b = 1000 m).
  tr::AtmosphereState fields = MakeAir(3, 1, 10.0, 1.0);
  fields.air[1] = 12.0f;
  fields.vapour[2] = 0.004f;
  fields.velocityU[2] = 3.0f;
  fields.velocityV[2] = 4.0f;
  const std::vector<float> hill = { 0.0f, 0.0f, 1000.0f };
  std::vector<float> xsOut(3), xOut(3), wind(3);
  tr::AtmosphereEvaporationFields(
    fields, p, hill.data(), nullptr, xsOut.data(), xOut.data(), wind.data());
  EXPECT_NEAR(xsOut[0], Magnus(15.0, 101325.0), 1e-7);
  EXPECT_NEAR(xsOut[1], Magnus(15.0, 1.2 * 101325.0), 1e-7);
  EXPECT_NEAR(xsOut[2], Magnus(8.5, 101325.0), 1e-7);
  EXPECT_NEAR(xsOut[2], 0.0068791, 1e-6); // by hand: e_s = 1108.36 Pa
  EXPECT_FLOAT_EQ(xOut[2], 0.004f);
  EXPECT_FLOAT_EQ(wind[2], 5.0f);
  EXPECT_EQ(wind[0], 0.0f);

  // Colder (higher) cells rain first: 6 mm over cells at 0, 1000 and 2000 m (15, 8.5 and 2 C
  // from the lapse rate; x_s = 0.0107, 0.00688, 0.00436): only the top one rains,
  // 0.01 (0.006 - 0.004361) = 1.64e-5 m (by hand: e_s(2 C) = 705.46 Pa).
  const std::vector<float> six(3, 0.006f);
  tr::AtmosphereState hillAir = MakeAir(3, 1, 10.0, 1.0, &six);
  const std::vector<float> hills = { 0.0f, 1000.0f, 2000.0f };
  std::vector<float> hillRain(3, 0.0f);
  tr::AtmosphereStep(hillAir, p, hills.data(), nullptr, hillRain.data());
  EXPECT_EQ(hillRain[0], 0.0f);
  EXPECT_EQ(hillRain[1], 0.0f);
  EXPECT_NEAR(hillRain[2], 0.01 * (0.006 - 0.0043610), 2e-9);
  EXPECT_NEAR(hillRain[2], 0.01 * (0.006 - Magnus(2.0, 101325.0)), 1e-10);
}

/// Rain on the plain (i < 16) and on the slope of the plume test after `steps` steps.
void PlumeRain(double windStrength, int steps, double& plain, double& slope)
{
  const int nx = 32, ny = 6;
  const std::vector<float> b =
    Fill(nx, ny, [](int i, int) { return i < 16 ? 0.0f : 200.0f * (i - 15); });
  std::vector<float> q = Fill(nx, ny, [](int i, int) { return i < 16 ? 0.009f : 0.0f; });
  tr::AtmosphereState st = MakeAir(nx, ny, 10.0, 1000.0, &q);
  tr::AtmosphereParams p;
  p.timeStep = 20.0;
  p.pipeArea = 1000.0 * 10.0; // a face 1 km wide and 10 m high: dt^2 g A / (l a) = 0.04
  p.windStrength = windStrength;
  p.condensationRate = 0.01;
  p.uphillDamping = 0.0; // the slope here is about temperature, not about the pipes
  std::vector<float> rain(q.size(), 0.0f);
  for (int n = 0; n < steps; ++n)
  {
    tr::AtmosphereStep(st, p, b.data(), nullptr, rain.data());
  }
  plain = slope = 0.0;
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      (i < 16 ? plain : slope) += rain[static_cast<std::size_t>(j) * nx + i];
    }
  }
}

TEST(TerroirAtmosphereCore, PlumeCarriedUpASlopeRainsOnTheSlope)
{
  // Dunn's Figure 5.3: vapour over the low western plain is blown east up a slope; the air
  // cools with height (6.5 C/km), its capacity drops, and it rains on the slope, not on the
  // plain it came from. Cells of 1 km; the plain (i < 16) at 0 m, then rising 200 m per cell to
  // 3.2 km. 9 mm of vapour over the plain, none over the slope: x = 0.009 < x_s(15 C) = 0.0107,
  // no rain on the plain; x_s is 0.0069 at 1 km, 0.0044 at 2 km and 0.0025 at 3.2 km, so once the
  // wind has carried (and mixed) the vapour up the slope, it rains there. Without wind nothing
  // moves and nothing rains.
  double plain = 0.0, slope = 0.0;
  PlumeRain(0.01, 2000, plain, slope);
  EXPECT_GT(slope, 1e-3); // m summed over cells: over a millimetre per slope cell on average
  EXPECT_GT(slope, 100.0 * plain);
  double calmPlain = 0.0, calmSlope = 0.0;
  PlumeRain(0.0, 2000, calmPlain, calmSlope);
  EXPECT_EQ(calmPlain, 0.0);
  EXPECT_EQ(calmSlope, 0.0);
}

TEST(TerroirAtmosphereCore, CoupledWaterCycleConservesWater)
{
  // One time step of a filter, 500 times on a closed 16 x 12 bowl: ErosionHydraulicStep (its own
  // evaporation off; last step's rain as its rain rate), Dunn's eq. 2.6 evaporation fed by the
  // atmosphere's fields (vapour += evaporated), then AtmosphereStep (rain out). Surface water +
  // vapour + rain in flight is conserved (1e-5 relative; measured 9e-9), water did evaporate and
  // rain fell. A cold eastern third (-30 C given) makes the vapour rain there.
  const int nx = 16, ny = 12;
  const std::vector<float> bed = Fill(nx,
    ny,
    [](int i, int j)
    {
      const float x = i - 7.5f, y = j - 5.5f;
      return 0.02f * (x * x + y * y);
    });
  GridView<float> view;
  view.data = bed.data();
  view.nx = nx;
  view.ny = ny;
  tr::ErosionState ero = tr::MakeErosionState(view);
  std::fill(ero.water.begin(), ero.water.end(), 0.1f);
  tr::ErosionParams ep;
  ep.evaporation = 0.0;
  const std::vector<float> bare(bed.size(), 0.0f); // no vegetation: open water only
  GridView<float> none = view;
  none.data = bare.data();
  tr::VegetationState veg = tr::MakeVegetationState(none);
  tr::VegetationParams vp;
  tr::EvaporationParams evp;
  evp.scale = 5e4; // Dunn 5.2.1 raised his for effect
  tr::AtmosphereState air = MakeAir(nx, ny, 10.0);
  tr::AtmosphereParams ap;
  ap.windStrength = 1.0;
  const std::vector<float> temp = Fill(nx, ny, [](int i, int) { return i > 10 ? -30.0f : 20.0f; });
  const std::size_t n = bed.size();
  std::vector<float> rain(n, 0.0f), rate(n), xs(n), x(n), wind(n);
  auto total = [&]()
  {
    double r = 0.0;
    for (float v : rain)
    {
      r += v;
    }
    return tr::ErosionMeasure(ero).water + tr::AtmosphereMeasure(air).vapour + r;
  };
  const double w0 = total();
  double evaporated = 0.0, fell = 0.0;
  for (int step = 0; step < 500; ++step)
  {
    for (std::size_t c = 0; c < n; ++c)
    {
      rate[c] = static_cast<float>(rain[c] / ep.timeStep);
    }
    const tr::ErosionStepStats es = tr::ErosionHydraulicStep(ero, ep, rate.data());
    // What erosion added as rain is what was in flight (up to the rate's rounding).
    double flight = 0.0;
    for (float v : rain)
    {
      flight += v;
    }
    ASSERT_NEAR(es.rain, flight, 1e-6 * w0 + 1e-7 * flight);
    std::fill(rain.begin(), rain.end(), 0.0f);
    tr::AtmosphereEvaporationFields(
      air, ap, bed.data(), temp.data(), xs.data(), x.data(), wind.data());
    tr::EvaporationFields fields;
    fields.saturationRatio = xs.data();
    fields.humidityRatio = x.data();
    fields.windSpeed = wind.data();
    fields.vapour = air.vapour.data();
    tr::VegetationWater water;
    water.surface = ero.water.data();
    water.surfaceResidue = ero.waterResidue.data();
    evaporated += tr::EvaporationDunn2015Step(veg, water, ep.timeStep, vp, evp, fields).fromWater;
    fell += tr::AtmosphereStep(air, ap, bed.data(), temp.data(), rain.data()).rain;
  }
  EXPECT_GT(evaporated, 1e-3 * w0);
  EXPECT_GT(fell, 0.01 * evaporated); // measured: 1.25 m^3 evaporated, 0.028 m^3 rained
  EXPECT_NEAR(total() / w0, 1.0, 1e-5);
}

TEST(TerroirAtmosphereCore, AnyRowSplitGivesTheSameBits)
{
  // Blocks of 5 rows run last block first give the same bits as one call in order, with
  // geographic-style row spacings, a no-data cell, wind from 200 degrees (mostly from the
  // south), transport and rain. Air, and vapour plus rain, are conserved there too.
  const int nx = 23, ny = 19;
  std::vector<double> rowDx(ny);
  for (int j = 0; j < ny; ++j)
  {
    rowDx[j] = 900.0 + 7.0 * j;
  }
  std::vector<std::uint8_t> valid(static_cast<std::size_t>(nx) * ny, 1);
  valid[9 * nx + 11] = 0;
  std::mt19937 rng(23);
  std::uniform_real_distribution<float> u(0.0f, 0.012f);
  const std::vector<float> q = Fill(nx, ny, [&](int, int) { return u(rng); });
  GridView<float> grid;
  grid.nx = nx;
  grid.ny = ny;
  grid.rowDx = rowDx.data();
  grid.dy = 1000.0;
  grid.valid = valid.data();
  tr::AtmosphereState a = tr::MakeAtmosphereState(grid, 10.0, q.data());
  tr::AtmosphereState s = a;
  const std::vector<float> b = Bumps(nx, ny, 2000.0f, 4);
  tr::AtmosphereParams p;
  p.timeStep = 20.0;
  p.pipeArea = 1e4;
  p.condensationRate = 0.01;
  p.windStrength = 0.01;
  p.windDirectionDeg = 200.0;
  const tr::ErosionParallelFor split =
    [](int begin, int end, const std::function<void(int, int)>& body)
  {
    std::vector<std::pair<int, int>> blocks;
    for (int r = begin; r < end; r += 5)
    {
      blocks.emplace_back(r, std::min(r + 5, end));
    }
    for (auto it = blocks.rbegin(); it != blocks.rend(); ++it)
    {
      body(it->first, it->second);
    }
  };
  std::vector<float> ra(q.size(), 0.0f), rs(q.size(), 0.0f);
  double rainA = 0.0;
  const tr::AtmosphereTotals t0 = tr::AtmosphereMeasure(a);
  for (int n = 0; n < 100; ++n)
  {
    const tr::AtmosphereStepStats sa = tr::AtmosphereStep(a, p, b.data(), nullptr, ra.data());
    const tr::AtmosphereStepStats ss =
      tr::AtmosphereStep(s, p, b.data(), nullptr, rs.data(), split);
    ASSERT_EQ(sa.rain, ss.rain);
    ASSERT_EQ(sa.vapourScale, ss.vapourScale);
    rainA += sa.rain;
  }
  EXPECT_GT(rainA, 0.0);
  // The wind's source (south edge, narrower cells) and sink (north edge, wider cells) balance,
  // and the air's rounding residue keeps their same-every-step rounding from drifting: total air
  // unchanged; vapour + rain unchanged.
  const tr::AtmosphereTotals t1 = tr::AtmosphereMeasure(a);
  EXPECT_NEAR(t1.air / t0.air, 1.0, 1e-7); // measured 2.6e-9 (3.6e-7 without the residue)
  EXPECT_NEAR((t1.vapour + rainA) / t0.vapour, 1.0, 1e-6);
  EXPECT_EQ(a.air, s.air);
  EXPECT_EQ(a.vapour, s.vapour);
  EXPECT_EQ(a.velocityU, s.velocityU);
  EXPECT_EQ(a.velocityV, s.velocityV);
  EXPECT_EQ(ra, rs);
}

/// Expects `f` to throw std::invalid_argument whose message names `name`.
void ExpectNamed(const std::function<void()>& f, const std::string& name)
{
  try
  {
    f();
    ADD_FAILURE() << "no error for " << name;
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
  }
}

TEST(TerroirAtmosphereCore, ParameterErrorsNameTheParameter)
{
  tr::AtmosphereState st = MakeAir(4, 3, 10.0);
  std::vector<float> b(12, 0.0f);
  auto step = [&](const std::function<void(tr::AtmosphereParams&)>& change)
  {
    return [&st, &b, change]()
    {
      tr::AtmosphereParams p;
      change(p);
      tr::AtmosphereStep(st, p, b.data());
    };
  };
  ExpectNamed(step([](tr::AtmosphereParams& p) { p.timeStep = 0.0; }), "timeStep");
  ExpectNamed(step([](tr::AtmosphereParams& p) { p.gravity = -1.0; }), "gravity");
  ExpectNamed(step([](tr::AtmosphereParams& p) { p.minAreaFraction = 0.0; }), "minAreaFraction");
  ExpectNamed(step([](tr::AtmosphereParams& p) { p.uphillDamping = -1.0; }), "uphillDamping");
  ExpectNamed(step([](tr::AtmosphereParams& p) { p.windStrength = NAN; }), "windStrength");
  ExpectNamed(
    step([](tr::AtmosphereParams& p) { p.windDirectionDeg = INFINITY; }), "windDirectionDeg");
  ExpectNamed(step([](tr::AtmosphereParams& p) { p.airColumnMass = 0.0; }), "airColumnMass");
  ExpectNamed(
    step([](tr::AtmosphereParams& p) { p.condensationRate = 200.0; }), "condensationRate");
  ExpectNamed(step([](tr::AtmosphereParams& p) { p.surfacePressure = 0.0; }), "surfacePressure");
  ExpectNamed(step([](tr::AtmosphereParams& p) { p.lapseRate = NAN; }), "lapseRate");
  b[5] = NAN;
  ExpectNamed(step([](tr::AtmosphereParams&) {}), "terrain height");
  b[5] = 0.0f;
  ExpectNamed([&]() { tr::AtmosphereStep(st, tr::AtmosphereParams(), nullptr); }, "terrain");
  std::vector<float> t(12, 10.0f);
  t[3] = NAN;
  ExpectNamed(
    [&]() { tr::AtmosphereStep(st, tr::AtmosphereParams(), b.data(), t.data()); }, "temperature");
  ExpectNamed([&]() { MakeAir(3, 3, 0.0); }, "airHeight");
  std::vector<float> wet(9, -1.0f);
  ExpectNamed([&]() { MakeAir(3, 3, 10.0, 1.0, &wet); }, "vapour");
  tr::AtmosphereState broken = st;
  broken.vapour.pop_back();
  ExpectNamed([&]() { tr::AtmosphereStep(broken, tr::AtmosphereParams(), b.data()); }, "vapour");
}

} // namespace

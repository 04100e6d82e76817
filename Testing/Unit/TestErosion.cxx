// Unit tests of the erosion core (terroir::terrain::ErosionHydraulicStep, ErosionThermalStep).
// Expected values are worked out by hand in the comments (a 3x3 flux step, a uniform flow on a
// tilted plane), or are properties that any correct implementation has: a dam break keeps its
// volume on a closed domain, a still lake stays still, a tilted plane drains into the sea with a
// closed mass balance, sediment and water are conserved over 1000 steps, water and sediment never
// go negative, thermal erosion relaxes every slope to the talus angle and conserves material,
// and any split of the rows gives the same bits.
#include "Erosion.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{
using terroir::GridView;
namespace tr = terroir::terrain;

/// A state over heights z(i, j) on an nx x ny grid of square cells of `spacing` metres.
tr::ErosionState MakeState(int nx,
  int ny,
  const std::function<float(int, int)>& z,
  double spacing = 1.0,
  const std::vector<float>* soil = nullptr)
{
  std::vector<float> heights(static_cast<std::size_t>(nx) * ny);
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      heights[static_cast<std::size_t>(j) * nx + i] = z(i, j);
    }
  }
  GridView<float> view;
  view.data = heights.data();
  view.nx = nx;
  view.ny = ny;
  view.dx = spacing;
  view.dy = spacing;
  return tr::MakeErosionState(view, soil ? soil->data() : nullptr);
}

std::size_t Idx(const tr::ErosionState& st, int i, int j)
{
  return static_cast<std::size_t>(j) * st.nx + i;
}

/// Uniform double in [0, 1) from the generator's top 53 bits (std distributions differ by
/// standard library).
double Uniform(std::mt19937_64& rng)
{
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

float MinOf(const std::vector<float>& a)
{
  return a.empty() ? 0.0f : *std::min_element(a.begin(), a.end());
}

bool AllFinite(const std::vector<float>& a)
{
  return std::all_of(a.begin(), a.end(), [](float v) { return std::isfinite(v); });
}

/// Expect |actual - expected| <= 1e-6 |expected| + atol.
void ExpectClose(double actual, double expected, double atol, const char* what)
{
  EXPECT_NEAR(actual, expected, 1e-6 * std::fabs(expected) + atol) << what;
}

TEST(TerroirErosionCore, HandWorkedThreeByThreeFluxStep)
{
  // 3x3 cells of 1 m, flat bed at 0, 1 m of water in the centre, closed edges, Weiss's
  // defaults (g = 10, dt = 0.01, A = l^2 = 1, l = 1: coefficient dt g A / l = 0.1).
  tr::ErosionParams p;
  tr::ErosionState st = MakeState(3, 3, [](int, int) { return 0.0f; });
  st.water[Idx(st, 1, 1)] = 1.0f;
  const tr::ErosionStepStats stats = tr::ErosionHydraulicStep(st, p);
  // Centre: dh = 1 to each neighbour, f = max(0, 0 + 0.1 * 1) = 0.1 in each of the 4 pipes;
  // K = min(1, 1 * 1 / (0.4 * 0.01)) = 1. Neighbours look uphill at the centre (f = 0) and
  // across flat water-free cells (dh = 0): no flux; the edge pipes are closed.
  const std::size_t c = Idx(st, 1, 1);
  ExpectClose(st.fluxW[c], 0.1, 0.0, "centre west flux");
  ExpectClose(st.fluxE[c], 0.1, 0.0, "centre east flux");
  ExpectClose(st.fluxS[c], 0.1, 0.0, "centre south flux");
  ExpectClose(st.fluxN[c], 0.1, 0.0, "centre north flux");
  for (std::size_t k = 0; k < st.Size(); ++k)
  {
    if (k != c)
    {
      EXPECT_EQ(st.fluxW[k] + st.fluxE[k] + st.fluxS[k] + st.fluxN[k], 0.0f) << k;
    }
  }
  // Water: centre 1 - 0.01 * 0.4 = 0.996, each side neighbour 0.01 * 0.1 = 0.001, corners 0;
  // then evaporation (1 - 0.005 * 0.01) = 0.99995: 0.9959502 and 0.00099995.
  ExpectClose(st.water[c], 0.9959502, 0.0, "centre water");
  for (auto ij : { std::pair<int, int>{ 0, 1 }, { 2, 1 }, { 1, 0 }, { 1, 2 } })
  {
    ExpectClose(st.water[Idx(st, ij.first, ij.second)], 0.00099995, 0.0, "side water");
  }
  EXPECT_EQ(st.water[Idx(st, 0, 0)], 0.0f);
  // Velocity (eq. 16): centre dWx = (0 - 0.1 + 0.1 - 0) / 2 = 0; east neighbour
  // dWx = (0.1 - 0 + 0 - 0) / 2 = 0.05 over l d_mean = 1 * (0 + 0.001) / 2: u = 100 m/s.
  EXPECT_EQ(st.velocityU[c], 0.0f);
  ExpectClose(st.velocityU[Idx(st, 2, 1)], 100.0, 0.0, "east u");
  ExpectClose(st.velocityU[Idx(st, 0, 1)], -100.0, 0.0, "west u");
  ExpectClose(st.velocityV[Idx(st, 1, 2)], 100.0, 0.0, "north v");
  EXPECT_EQ(st.velocityV[Idx(st, 2, 1)], 0.0f);
  // Erosion at the side cells: flat bed, tilt clamped up to 0.005; C = 0.5 * 0.005 * 100 =
  // 0.25 > s = 0: the bed gives K_s C = 0.025. Transport: the side cells trace back to the
  // centre (x = 2 - 100 * 0.01), which holds no sediment, and nothing else holds any, so the
  // transported field is empty (m2 = 0) and the sediment stays where it is (k = 1).
  ExpectClose(st.terrain[Idx(st, 2, 1)], -0.025, 0.0, "east bed");
  ExpectClose(st.sediment[Idx(st, 2, 1)], 0.025, 0.0, "east sediment");
  EXPECT_EQ(st.terrain[c], 0.0f);
  EXPECT_DOUBLE_EQ(stats.sedimentScale, 1.0);
  ExpectClose(stats.eroded, 0.1, 0.0, "eroded volume");

  // The same with the capacity ramped by depth (capacityDepth = 0.002 m): the side cells hold
  // d2 = 0.001 m, so C = 0.25 * 0.001 / 0.002 = 0.125 and the bed gives 0.0125.
  tr::ErosionParams ramp;
  ramp.capacityDepth = 0.002;
  tr::ErosionState ramped = MakeState(3, 3, [](int, int) { return 0.0f; });
  ramped.water[c] = 1.0f;
  tr::ErosionHydraulicStep(ramped, ramp);
  ExpectClose(ramped.terrain[Idx(ramped, 2, 1)], -0.0125, 0.0, "east bed, ramped capacity");

  // Second case: the K scaling. Centre bed 10 m with 0.01 m of water, the rest dry at 0:
  // dh = 10.01, raw f = 0.1 * 10.01 = 1.001 each, sum 4.004; K = 0.01 * 1 / (4.004 * 0.01)
  // = 0.24975025 so each pipe carries 0.25 and the centre empties: each side cell gets
  // 0.01 * 0.25 = 0.0025 (0.002499875 after evaporation).
  tr::ErosionState tall =
    MakeState(3, 3, [](int i, int j) { return i == 1 && j == 1 ? 10.0f : 0.0f; });
  tall.water[c] = 0.01f;
  tr::ErosionParams noErosion;
  noErosion.capacity = 0.0;
  tr::ErosionHydraulicStep(tall, noErosion);
  ExpectClose(tall.fluxN[c], 0.25, 0.0, "scaled flux");
  ExpectClose(tall.fluxW[c], 0.25, 0.0, "scaled flux");
  EXPECT_NEAR(tall.water[c], 0.0, 1e-9);
  ExpectClose(tall.water[Idx(tall, 1, 0)], 0.002499875, 0.0, "side water after scaling");

  // Third case: Dunn's soft threshold (eq. 3.1) with O_min = 0.02, s_O = 0.05 caps the first
  // case's pipes at 0.02 + 0.05 * 1 = 0.07: centre 1 - 0.01 * 0.28 = 0.9972 (0.99715014 after
  // evaporation).
  tr::ErosionParams soft;
  soft.softOutflow = true;
  soft.softOutflowMin = 0.02;
  soft.softOutflowScale = 0.05;
  tr::ErosionState capped = MakeState(3, 3, [](int, int) { return 0.0f; });
  capped.water[c] = 1.0f;
  tr::ErosionHydraulicStep(capped, soft);
  ExpectClose(capped.fluxE[c], 0.07, 0.0, "soft threshold cap");
  ExpectClose(capped.water[c], 0.9972 * 0.99995, 0.0, "centre water with the cap");
}

TEST(TerroirErosionCore, DamBreakKeepsItsVolumeOnAClosedDomain)
{
  // The water model alone (K_c = 0: the bed stays flat), no evaporation.
  tr::ErosionParams p;
  p.evaporation = 0.0;
  p.capacity = 0.0;
  // A column 1 m deep over the western half of a 64 x 16 flat channel.
  for (bool perRow : { false, true })
  {
    tr::ErosionState st = MakeState(64, 16, [](int, int) { return 0.0f; });
    if (perRow)
    {
      // Geographic-like rows: each row its own east-west spacing (cell areas differ).
      for (int j = 0; j < st.ny; ++j)
      {
        st.rowDx[j] = 1.0 - 0.02 * j;
        st.rowDy[j] = 1.1;
      }
    }
    for (int j = 0; j < st.ny; ++j)
    {
      for (int i = 0; i < 32; ++i)
      {
        st.water[Idx(st, i, j)] = 1.0f;
      }
    }
    const double v0 = tr::ErosionMeasure(st).water;
    double clamped = 0.0;
    for (int n = 0; n < 1000; ++n)
    {
      clamped += tr::ErosionHydraulicStep(st, p).waterClamped;
    }
    const double v1 = tr::ErosionMeasure(st).water;
    EXPECT_NEAR(v1, v0, 1e-6 * v0) << "per-row spacing " << perRow;
    EXPECT_LE(clamped, 1e-7 * v0); // rounding residue only (the K scaling)
    // In 10 s of simulated time the front has crossed the channel and the column has dropped
    // at the wall (the rarefaction wave, sqrt(g h) = 3.2 cells/s, has come back from it).
    EXPECT_GT(st.water[Idx(st, 62, 8)], 0.1f);
    EXPECT_LT(st.water[Idx(st, 0, 8)], 0.99f);
    EXPECT_GE(MinOf(st.water), 0.0f);
  }
}

TEST(TerroirErosionCore, StillLakeStaysStill)
{
  // An uneven bed (multiples of 1/64 m in [0, 2)) under water up to 3 m: b + d = 3 exactly in
  // float, so every pipe sees dh = 0: no flux, no velocity, no capacity, no erosion, ever.
  std::mt19937_64 rng(27);
  tr::ErosionState st = MakeState(
    24, 20, [&](int, int) { return static_cast<float>(std::floor(Uniform(rng) * 128.0) / 64.0); });
  for (std::size_t c = 0; c < st.Size(); ++c)
  {
    st.water[c] = 3.0f - st.terrain[c];
  }
  const std::vector<float> bed = st.terrain;
  const std::vector<float> water = st.water;
  tr::ErosionParams p;
  p.evaporation = 0.0;
  for (int n = 0; n < 200; ++n)
  {
    const tr::ErosionStepStats stats = tr::ErosionHydraulicStep(st, p);
    ASSERT_EQ(stats.eroded, 0.0) << "step " << n;
  }
  EXPECT_EQ(st.terrain, bed);
  EXPECT_EQ(st.water, water);
  for (std::size_t c = 0; c < st.Size(); ++c)
  {
    ASSERT_EQ(st.fluxW[c] + st.fluxE[c] + st.fluxS[c] + st.fluxN[c], 0.0f) << c;
    ASSERT_EQ(st.velocityU[c], 0.0f);
    ASSERT_EQ(st.velocityV[c], 0.0f);
    ASSERT_EQ(st.sediment[c], 0.0f);
  }
  // The same lake with its surface raised by 1 cm in one cell does move (the test can fail).
  st.water[Idx(st, 10, 10)] += 0.01f;
  tr::ErosionHydraulicStep(st, p);
  EXPECT_GT(st.fluxE[Idx(st, 10, 10)], 0.0f);
}

TEST(TerroirErosionCore, TiltedPlaneDrainsIntoTheSea)
{
  // A plane rising 5 cm per cell eastwards from 1 m, 5 cm of water everywhere, sea at 0 all
  // round. Erosion off (K_c = 0) and no evaporation: only the pipes and the sea move water.
  tr::ErosionParams p;
  p.boundary = tr::ErosionBoundary::Sea;
  p.seaLevel = 0.0;
  p.capacity = 0.0;
  p.evaporation = 0.0;
  tr::ErosionState st = MakeState(32, 16, [](int i, int) { return 1.0f + 0.05f * i; });
  std::fill(st.water.begin(), st.water.end(), 0.05f);
  const double v0 = tr::ErosionMeasure(st).water;
  double toSea = 0.0;
  double clamped = 0.0;
  double previous = v0;
  for (int n = 0; n < 4000; ++n)
  {
    const tr::ErosionStepStats stats = tr::ErosionHydraulicStep(st, p);
    toSea += stats.waterToSea;
    clamped += stats.waterClamped;
    const double v = tr::ErosionMeasure(st).water;
    ASSERT_LE(v, previous + 1e-9 * v0) << "volume grew at step " << n;
    previous = v;
  }
  const double v1 = tr::ErosionMeasure(st).water;
  EXPECT_LT(v1, 1e-3 * v0) << "the plane has not drained";
  // Mass balance: what is left plus what reached the sea is what there was.
  EXPECT_NEAR(v1 + toSea - clamped, v0, 1e-6 * v0);
  EXPECT_GT(toSea, 0.99 * v0);
}

/// A uniform flow down a plane falling sigma = 0.05 m per 1 m cell eastwards, 0.5 m deep,
/// with an eastward flux F0 = 0.195 m^3/s in every pipe (the west and east edge cells aside).
/// One step: dh_E = 0.05, f_E = 0.195 + 0.1 * 0.05 = 0.2 (f_W = f_N = f_S = 0); the interior
/// depth is unchanged (in = out = 0.2); dW_X = (0.2 + 0.2) / 2 = 0.2; u = 0.2 / (1 * 0.5) =
/// 0.4 m/s. Tilt: tan(alpha) = 0.05, sin(alpha) = 0.05 / sqrt(1.0025) = 0.049937617;
/// C = 0.5 * 0.049937617 * 0.4 = 0.0099875234.
tr::ErosionState UniformFlow(float sediment)
{
  tr::ErosionState st = MakeState(32, 6, [](int i, int) { return 10.0f - 0.05f * i; });
  std::fill(st.water.begin(), st.water.end(), 0.5f);
  std::fill(st.sediment.begin(), st.sediment.end(), sediment);
  for (int j = 0; j < st.ny; ++j)
  {
    for (int i = 0; i + 1 < st.nx; ++i)
    {
      st.fluxE[Idx(st, i, j)] = 0.195f;
    }
  }
  return st;
}

TEST(TerroirErosionCore, UniformFlowBalancesErosionAndDeposition)
{
  const double capacity = 0.0099875234;
  tr::ErosionParams p;
  struct Case
  {
    double s0;       // suspended sediment before the step
    double bedDelta; // by hand: -K_s (C - s0) or +K_d (s0 - C)
  };
  // s0 = C: nothing; s0 = C / 2: the bed gives 0.1 * 0.0049937617; s0 = 2 C: K_d C settles.
  for (const Case& k : { Case{ capacity, 0.0 },
         Case{ capacity / 2, -0.00049937617 },
         Case{ 2 * capacity, 0.00099875234 } })
  {
    tr::ErosionState st = UniformFlow(static_cast<float>(k.s0));
    const std::vector<float> bed = st.terrain;
    const tr::ErosionStepStats stats = tr::ErosionHydraulicStep(st, p);
    for (int j = 0; j < st.ny; ++j)
    {
      for (int i = 3; i < st.nx - 3; ++i)
      {
        const std::size_t c = Idx(st, i, j);
        ASSERT_NEAR(st.fluxE[c], 0.2, 1e-6);
        ASSERT_NEAR(st.velocityU[c], 0.4, 1e-6);
        ASSERT_NEAR(st.terrain[c] - bed[c], k.bedDelta, 2e-6) << "s0 " << k.s0 << " cell " << i;
        // The interior's sediment is uniform, so transport leaves it as it is, up to Dunn's
        // global k (which the edges' different flow sets).
        const double suspended = (k.s0 - k.bedDelta) * stats.sedimentScale;
        ASSERT_NEAR(st.sediment[c], suspended, 1e-6 * suspended) << "s0 " << k.s0;
      }
    }
  }
}

TEST(TerroirErosionCore, SoilGoesFirstThenRockAtItsOwnRate)
{
  // The uniform flow above with s0 = C / 2 over 0.1 mm of soil, K_s = 0.1, K_s,rock = 0.02:
  // deficit C - s0 = 0.0049937617; the soil could give 0.1 * deficit = 0.00049937617 but has
  // only 0.0001, which covers 0.0001 / 0.1 = 0.001 of the deficit; the rock gives
  // 0.02 * (0.0049937617 - 0.001) = 0.000079875234. Bed change -0.000179875234, soil 0.
  const double capacity = 0.0099875234;
  tr::ErosionState st = UniformFlow(static_cast<float>(capacity / 2));
  st.soil.assign(st.Size(), 0.0001f);
  const std::vector<float> bed = st.terrain;
  tr::ErosionParams p;
  p.dissolvingRock = 0.02;
  tr::ErosionHydraulicStep(st, p);
  for (int i = 3; i < st.nx - 3; ++i)
  {
    const std::size_t c = Idx(st, i, 2);
    EXPECT_NEAR(st.terrain[c] - bed[c], -0.000179875234, 2e-6) << i;
    EXPECT_EQ(st.soil[c], 0.0f) << i;
  }
}

TEST(TerroirErosionCore, ErosionConstantsFollowTheErodedDepth)
{
  // Weiss's eq. 24 and his bound on the change, on the uniform flow above (deficit or excess
  // C / 2 = 0.0049937617 or C = 0.0099875234).
  const double capacity = 0.0099875234;
  struct Case
  {
    double s0, alreadyEroded, fs, fd, maxChange, bedDelta;
  };
  const Case cases[] = {
    // 0.2 m eroded, f_s = 0.2 m: K_s = 0.1 * 2^-1 = 0.05, bed -0.05 * 0.0049937617.
    { capacity / 2, 0.2, 0.2, 0.0, 0.0, -0.00024968809 },
    // 0.2 m eroded, f_d = 0.1 m: K_d = 0.1 * 2^2 = 0.4, bed +0.4 * 0.0099875234.
    { 2 * capacity, 0.2, 0.0, 0.1, 0.0, 0.0039950094 },
    // 0.1 mm eroded, bound 0.3 mm: only 0.2 mm more may go (K_s alone would take 0.5 mm).
    { capacity / 2, 0.0001, 0.0, 0.0, 0.0003, -0.0002 },
    // 0.1 mm deposited (eroded -0.0001), bound 0.3 mm: the deposit K_d C = 1 mm is cut to 0.2 mm.
    { 2 * capacity, -0.0001, 0.0, 0.0, 0.0003, 0.0002 },
  };
  for (const Case& k : cases)
  {
    tr::ErosionState st = UniformFlow(static_cast<float>(k.s0));
    for (std::size_t c = 0; c < st.Size(); ++c)
    {
      st.original[c] = st.terrain[c] + static_cast<float>(k.alreadyEroded);
    }
    const std::vector<float> bed = st.terrain;
    tr::ErosionParams p;
    p.halvingDepthErosion = k.fs;
    p.halvingDepthDeposition = k.fd;
    p.maxBedChange = k.maxChange;
    tr::ErosionHydraulicStep(st, p);
    for (int i = 3; i < st.nx - 3; ++i)
    {
      const std::size_t c = Idx(st, i, 3);
      EXPECT_NEAR(st.terrain[c] - bed[c], k.bedDelta, 2e-6) << "case s0 " << k.s0 << " cell " << i;
    }
  }
}

TEST(TerroirErosionCore, NoDataCellsAreWallsOrSea)
{
  // A 10 x 5 flat grid whose column i = 5 has no data; 1 m of water west of it, none east.
  const int nx = 10, ny = 5;
  std::vector<float> heights(static_cast<std::size_t>(nx) * ny, 0.0f);
  std::vector<std::uint8_t> valid(heights.size(), 1);
  for (int j = 0; j < ny; ++j)
  {
    valid[static_cast<std::size_t>(j) * nx + 5] = 0;
  }
  GridView<float> view;
  view.data = heights.data();
  view.nx = nx;
  view.ny = ny;
  view.valid = valid.data();
  for (tr::ErosionBoundary boundary : { tr::ErosionBoundary::Closed, tr::ErosionBoundary::Sea })
  {
    tr::ErosionState st = tr::MakeErosionState(view);
    for (int j = 0; j < ny; ++j)
    {
      for (int i = 0; i < 5; ++i)
      {
        st.water[Idx(st, i, j)] = 1.0f;
      }
    }
    tr::ErosionParams p;
    p.boundary = boundary;
    p.seaLevel = -10.0; // only the edge and the no-data column are sea
    p.evaporation = 0.0;
    const double v0 = tr::ErosionMeasure(st).water;
    double toSea = 0.0;
    for (int n = 0; n < 300; ++n)
    {
      toSea += tr::ErosionHydraulicStep(st, p).waterToSea;
    }
    for (int j = 0; j < ny; ++j)
    {
      for (int i = 5; i < nx; ++i)
      {
        // Neither a wall nor the sea passes water on: the east side stays dry.
        ASSERT_EQ(st.water[Idx(st, i, j)], 0.0f) << i << "," << j;
        ASSERT_EQ(st.sediment[Idx(st, i, j)], 0.0f) << i << "," << j;
      }
    }
    const double v1 = tr::ErosionMeasure(st).water;
    if (boundary == tr::ErosionBoundary::Closed)
    {
      EXPECT_NEAR(v1, v0, 1e-6 * v0);
      EXPECT_EQ(toSea, 0.0);
    }
    else
    {
      EXPECT_LT(v1, 0.5 * v0); // drained into the edge and the no-data column
      EXPECT_NEAR(v1 + toSea, v0, 1e-6 * v0);
    }
  }
}

TEST(TerroirErosionCore, SoftOutflowThresholdDampsSloshing)
{
  // A 10 cm bump on a 1 m lake (20 x 20, flat closed bed, water only). The pipe model has no
  // friction: the bump's waves slosh on; Dunn's soft threshold (eq. 3.1, O_min = 0,
  // s_O = 1 m^2/s) caps each pipe by its head difference and lets the surface settle.
  auto sloshing = [](bool soft)
  {
    tr::ErosionState st = MakeState(20, 20, [](int, int) { return 0.0f; });
    std::fill(st.water.begin(), st.water.end(), 1.0f);
    st.water[Idx(st, 10, 10)] += 0.1f;
    tr::ErosionParams p;
    p.capacity = 0.0;
    p.evaporation = 0.0;
    p.softOutflow = soft;
    p.softOutflowMin = 0.0;
    p.softOutflowScale = 1.0;
    const double v0 = tr::ErosionMeasure(st).water;
    for (int n = 0; n < 4000; ++n)
    {
      tr::ErosionHydraulicStep(st, p);
    }
    EXPECT_NEAR(tr::ErosionMeasure(st).water, v0, 1e-6 * v0);
    const double mean = tr::ErosionMeasure(st).water / st.Size();
    double worst = 0.0;
    for (float d : st.water)
    {
      worst = std::max(worst, std::fabs(d - mean));
    }
    return worst;
  };
  const double free = sloshing(false);
  const double damped = sloshing(true);
  EXPECT_GT(free, 1e-3);         // still sloshing after 40 s
  EXPECT_LT(damped, 0.2 * free); // measured: 3.4e-3 free, 1.1e-4 damped
}

TEST(TerroirErosionCore, DryAndSeaCellsSettleTheirSediment)
{
  // A dry flat cell holding 0.01 m of suspended sediment: no velocity, C = 0, K_d settles
  // 0.001; the cell has no water, so the remaining 0.009 settles too (Dunn section 3.3):
  // bed 0.01, nothing suspended.
  tr::ErosionState dry = MakeState(3, 3, [](int, int) { return 0.0f; });
  dry.sediment[Idx(dry, 1, 1)] = 0.01f;
  tr::ErosionParams p;
  const tr::ErosionStepStats stats = tr::ErosionHydraulicStep(dry, p);
  EXPECT_FLOAT_EQ(dry.terrain[Idx(dry, 1, 1)], 0.01f);
  EXPECT_EQ(dry.sediment[Idx(dry, 1, 1)], 0.0f);
  EXPECT_NEAR(stats.deposited, 0.01, 1e-9);
  // A sea cell (bed -1 m, sea level 0) holding 0.02 m: it does not erode; the sediment
  // settles on its bed (Weiss section VI-B3): -0.98 m.
  tr::ErosionState sea = MakeState(3, 3, [](int i, int) { return i == 0 ? -1.0f : 1.0f; });
  sea.sediment[Idx(sea, 0, 1)] = 0.02f;
  p.boundary = tr::ErosionBoundary::Sea;
  tr::ErosionHydraulicStep(sea, p);
  EXPECT_FLOAT_EQ(sea.terrain[Idx(sea, 0, 1)], -0.98f);
  EXPECT_EQ(sea.sediment[Idx(sea, 0, 1)], 0.0f);
}

TEST(TerroirErosionCore, EvaporationFollowsThePerCellFactor)
{
  // Uniform 1 m of water on a flat closed grid (nothing flows in the first step), K_e = 0.5,
  // dt = 0.01: d = 1 - 0.005 T for Weiss's temperature factor T (eq. 23): T = 0, 0.5, 1 give
  // 1, 0.9975, 0.995.
  tr::ErosionState st = MakeState(3, 1, [](int, int) { return 0.0f; });
  std::fill(st.water.begin(), st.water.end(), 1.0f);
  const std::vector<float> heat = { 0.0f, 0.5f, 1.0f };
  tr::ErosionParams p;
  p.evaporation = 0.5;
  const tr::ErosionStepStats stats = tr::ErosionHydraulicStep(st, p, nullptr, heat.data());
  EXPECT_EQ(st.water[0], 1.0f);
  EXPECT_FLOAT_EQ(st.water[1], 0.9975f);
  EXPECT_FLOAT_EQ(st.water[2], 0.995f);
  EXPECT_NEAR(stats.evaporated, 0.0075, 1e-7);
  // Rain (eq. 10): 2 m/s for 0.01 s adds 0.02 m before the flow.
  tr::ErosionState wet = MakeState(3, 1, [](int, int) { return 0.0f; });
  const std::vector<float> rain(3, 2.0f);
  p.evaporation = 0.0;
  const tr::ErosionStepStats rained = tr::ErosionHydraulicStep(wet, p, rain.data());
  EXPECT_FLOAT_EQ(wet.water[1], 0.02f);
  EXPECT_NEAR(rained.rain, 0.06, 1e-8);
}

/// Smooth hills with water on them: sines plus a little noise, heights in [0, 6] m.
tr::ErosionState Hills(int n,
  std::uint64_t seed,
  const std::vector<float>* soil = nullptr,
  double base = 0.0)
{
  std::mt19937_64 rng(seed);
  return MakeState(
    n,
    n,
    [&](int i, int j)
    {
      return static_cast<float>(
        base + 3.0 + 1.5 * std::sin(0.3 * i) * std::cos(0.23 * j) + 0.02 * j + 0.3 * Uniform(rng));
    },
    1.0,
    soil);
}

TEST(TerroirErosionCore, SedimentAndWaterAreConservedOverAThousandSteps)
{
  tr::ErosionParams p;
  p.evaporation = 0.0;
  const int n = 40;
  // One material and soil over rock; the hills at sea level and 1000 m up (where a float's
  // spacing, 61 micrometres, is larger than much of a step's erosion).
  for (int variant = 0; variant < 4; ++variant)
  {
    const bool layered = variant % 2 == 1;
    const double base = variant < 2 ? 0.0 : 1000.0;
    const std::vector<float> soil(static_cast<std::size_t>(n) * n, 0.05f);
    tr::ErosionState st = Hills(n, 11, layered ? &soil : nullptr, base);
    p.dissolvingRock = 0.02;
    std::fill(st.water.begin(), st.water.end(), 0.2f);
    const std::vector<float> rock0 = [&]
    {
      std::vector<float> r = st.terrain;
      for (std::size_t c = 0; c < r.size() && layered; ++c)
      {
        r[c] -= soil[c];
      }
      return r;
    }();
    const tr::ErosionTotals t0 = tr::ErosionMeasure(st);
    double eroded = 0.0;
    for (int step = 0; step < 1000; ++step)
    {
      eroded += tr::ErosionHydraulicStep(st, p).eroded;
    }
    const tr::ErosionTotals t1 = tr::ErosionMeasure(st);
    // The targets: water and bed + suspended sediment to 1e-6 relative per 1000 steps.
    EXPECT_NEAR(t1.water, t0.water, 1e-6 * t0.water) << "variant " << variant;
    const double material0 = t0.terrain + t0.sediment;
    const double material1 = t1.terrain + t1.sediment;
    EXPECT_NEAR(material1, material0, 1e-6 * material0) << "variant " << variant;
    // Stricter: the bed's change and the suspended load balance to 1e-7 of what was eroded
    // (measured 1.5e-8 at both heights; without the bed's compensation, 1e-6 at 1000 m).
    EXPECT_GT(eroded, 1.0) << "little erosion: the test would prove little";
    EXPECT_NEAR((t1.terrain - t0.terrain) + t1.sediment, 0.0, 1e-7 * eroded)
      << "variant " << variant;
    if (layered)
    {
      // Rock only wears down; the soil layer is bed minus rock and never negative.
      EXPECT_GE(MinOf(st.soil), 0.0f);
      for (std::size_t c = 0; c < st.Size(); ++c)
      {
        // rock = b - soil carries the float rounding of both (ulp(1000 m) = 6.1e-5)
        ASSERT_LE(st.terrain[c] - st.soil[c], rock0[c] + (base > 0.0 ? 2e-4f : 1e-5f)) << c;
      }
    }
  }
}

TEST(TerroirErosionCore, WaterAndSedimentNeverGoNegative)
{
  // Rough random terrains (white noise up to 5 m), random rain, several boundary settings.
  for (std::uint64_t seed : { 1u, 2u, 3u, 4u })
  {
    std::mt19937_64 rng(seed);
    const int n = 36;
    const std::vector<float> soil(static_cast<std::size_t>(n) * n, 0.02f);
    tr::ErosionState st = MakeState(
      n,
      n,
      [&](int, int) { return static_cast<float>(5.0 * Uniform(rng)); },
      1.0,
      seed == 3 ? &soil : nullptr);
    std::vector<float> rain(st.Size());
    for (float& r : rain)
    {
      r = static_cast<float>(0.5 * Uniform(rng)); // up to 5 mm per step
    }
    std::vector<float> heat(st.Size());
    for (float& t : heat)
    {
      t = static_cast<float>(Uniform(rng));
    }
    tr::ErosionParams p;
    p.boundary = seed % 2 == 0 ? tr::ErosionBoundary::Sea : tr::ErosionBoundary::Closed;
    p.seaLevel = 1.0;
    p.softOutflow = seed == 4;
    p.evaporation = 0.5;
    double rained = 0.0, evaporated = 0.0, toSea = 0.0, clamped = 0.0;
    const double v0 = tr::ErosionMeasure(st).water;
    for (int step = 0; step < 600; ++step)
    {
      const tr::ErosionStepStats s = tr::ErosionHydraulicStep(st, p, rain.data(), heat.data());
      rained += s.rain;
      evaporated += s.evaporated;
      toSea += s.waterToSea;
      clamped += s.waterClamped;
      ASSERT_GE(MinOf(st.water), 0.0f) << "seed " << seed << " step " << step;
      ASSERT_GE(MinOf(st.sediment), 0.0f) << "seed " << seed << " step " << step;
      ASSERT_GE(MinOf(st.soil), 0.0f) << "seed " << seed << " step " << step;
      ASSERT_TRUE(AllFinite(st.terrain) && AllFinite(st.water) && AllFinite(st.sediment));
    }
    // Water balance closes: rain in, evaporation and the sea out.
    const double v1 = tr::ErosionMeasure(st).water;
    EXPECT_NEAR(v1, v0 + rained - evaporated - toSea + clamped, 1e-6 * rained) << "seed " << seed;
    // The K scaling keeps the clamped residue at rounding level.
    EXPECT_LE(clamped, 1e-7 * rained) << "seed " << seed;
    EXPECT_GT(tr::ErosionMeasure(st).sediment, 0.0);
  }
}

TEST(TerroirErosionCore, AnyRowSplitGivesTheSameBits)
{
  tr::ErosionState a = Hills(30, 5);
  std::fill(a.water.begin(), a.water.end(), 0.1f);
  tr::ErosionState b = a;
  tr::ErosionParams p;
  p.boundary = tr::ErosionBoundary::Sea;
  p.seaLevel = 2.5;
  // Blocks of 7 rows, run last block first.
  const tr::ErosionParallelFor split =
    [](int begin, int end, const std::function<void(int, int)>& body)
  {
    std::vector<std::pair<int, int>> blocks;
    for (int r = begin; r < end; r += 7)
    {
      blocks.emplace_back(r, std::min(r + 7, end));
    }
    for (auto it = blocks.rbegin(); it != blocks.rend(); ++it)
    {
      body(it->first, it->second);
    }
  };
  tr::ThermalParams t;
  for (int n = 0; n < 50; ++n)
  {
    const tr::ErosionStepStats sa = tr::ErosionHydraulicStep(a, p);
    const tr::ErosionStepStats sb = tr::ErosionHydraulicStep(b, p, nullptr, nullptr, split);
    ASSERT_EQ(sa.sedimentScale, sb.sedimentScale);
    tr::ErosionThermalStep(a, t);
    tr::ErosionThermalStep(b, t, split);
  }
  EXPECT_EQ(a.terrain, b.terrain);
  EXPECT_EQ(a.water, b.water);
  EXPECT_EQ(a.sediment, b.sediment);
  EXPECT_EQ(a.fluxE, b.fluxE);
}

/// Largest excess of any 8-neighbour slope over tan(talus), in metres of height, over the
/// pipes whose upper cell satisfies `counts` (computed here, independently of the core).
double MaxExcess(const tr::ErosionState& st,
  double talusDeg,
  const std::function<bool(std::size_t)>& counts = {})
{
  const double t = std::tan(talusDeg * 3.14159265358979323846 / 180.0);
  double worst = -1e30;
  for (int j = 0; j < st.ny; ++j)
  {
    for (int i = 0; i < st.nx; ++i)
    {
      for (int dj = -1; dj <= 1; ++dj)
      {
        for (int di = -1; di <= 1; ++di)
        {
          const int ii = i + di, jj = j + dj;
          if ((di == 0 && dj == 0) || ii < 0 || jj < 0 || ii >= st.nx || jj >= st.ny)
          {
            continue;
          }
          const std::size_t c = Idx(st, i, j);
          if (counts && !counts(c))
          {
            continue;
          }
          const double dist = std::hypot(di * st.rowDx[j], dj * st.rowDy[j]);
          worst = std::max(worst, (st.terrain[c] - st.terrain[Idx(st, ii, jj)]) - t * dist);
        }
      }
    }
  }
  return worst;
}

double Sum(const std::vector<float>& a)
{
  double s = 0.0;
  for (float v : a)
  {
    s += v;
  }
  return s;
}

/// Thermal steps until the largest excess is below tol (at most maxSteps); returns the count.
int Relax(tr::ErosionState& st, const tr::ThermalParams& t, double tol, int maxSteps)
{
  for (int n = 0; n < maxSteps; ++n)
  {
    if (tr::ErosionThermalStep(st, t).maxExcess <= tol)
    {
      return n;
    }
  }
  return maxSteps;
}

TEST(TerroirErosionCore, ThermalErosionRelaxesASpikeAndACliffToTheTalusAngle)
{
  tr::ThermalParams t;
  t.talusSoilDeg = 30.0;
  // A 10 m spike on a flat 15 x 15 grid.
  tr::ErosionState spike =
    MakeState(15, 15, [](int i, int j) { return i == 7 && j == 7 ? 10.0f : 0.0f; });
  const double v0 = Sum(spike.terrain);
  EXPECT_GT(MaxExcess(spike, 30.0), 9.0);
  const int steps = Relax(spike, t, 1e-4, 20000);
  EXPECT_LT(steps, 20000);
  EXPECT_LE(MaxExcess(spike, 30.0), 1e-4 + 1e-6);
  EXPECT_NEAR(Sum(spike.terrain), v0, 1e-6 * v0);
  // A pile of 10 m^3 at 30 degrees: a cone would be (3 V / (pi tan 30))^(1/3) = 2.55 m wide
  // and 1.47 m high; the 8-neighbour pile is close to it.
  EXPECT_GT(spike.terrain[Idx(spike, 7, 7)], 1.0f);
  EXPECT_LT(spike.terrain[Idx(spike, 7, 7)], 2.5f);
  EXPECT_EQ(spike.terrain[Idx(spike, 0, 0)], 0.0f); // never reached the corner
  // Symmetric in x and y.
  EXPECT_NEAR(spike.terrain[Idx(spike, 6, 7)], spike.terrain[Idx(spike, 7, 6)], 1e-5);

  // A 5 m cliff on 2 m cells, talus 40 degrees.
  t.talusSoilDeg = 40.0;
  tr::ErosionState cliff = MakeState(
    20, 6, [](int i, int) { return i < 10 ? 0.0f : 5.0f; }, 2.0);
  const double c0 = Sum(cliff.terrain);
  Relax(cliff, t, 1e-4, 20000);
  EXPECT_LE(MaxExcess(cliff, 40.0), 1e-4 + 1e-6);
  EXPECT_NEAR(Sum(cliff.terrain), c0, 1e-6 * c0);
  // Rough ground 1000 m up (white noise of 3 m on 1 m cells; a float's spacing there is 61
  // micrometres), half rate, 500 steps: the volume is kept to 1e-8 of the volume moved
  // (measured 8e-11; 1e-6 with a plain float bed).
  std::mt19937_64 rng(5);
  tr::ErosionState rough =
    MakeState(40, 40, [&](int, int) { return static_cast<float>(1000.0 + 3.0 * Uniform(rng)); });
  t.talusSoilDeg = 30.0;
  t.rate = 0.5;
  const double h0 = tr::ErosionMeasure(rough).terrain;
  double moved = 0.0;
  for (int n = 0; n < 500; ++n)
  {
    moved += tr::ErosionThermalStep(rough, t).moved;
  }
  EXPECT_GT(moved, 100.0);
  EXPECT_NEAR(tr::ErosionMeasure(rough).terrain, h0, 1e-8 * moved);
  // Every row alike (the cliff is uniform along y).
  for (int i = 0; i < cliff.nx; ++i)
  {
    EXPECT_NEAR(cliff.terrain[Idx(cliff, i, 0)], cliff.terrain[Idx(cliff, i, 3)], 1e-4);
  }
}

TEST(TerroirErosionCore, ThermalErosionMovesSoilBeforeRock)
{
  // Rock ramp at 45 degrees (1 m per 1 m cell) under 0.3 m of soil; soil talus 30 degrees,
  // rock 60: the soil slides down, the rock stays.
  const int nx = 12, ny = 4;
  std::vector<float> soil(static_cast<std::size_t>(nx) * ny, 0.3f);
  tr::ErosionState st = MakeState(
    nx, ny, [](int i, int) { return 1.0f * i + 0.3f; }, 1.0, &soil);
  std::vector<float> rock0(st.Size());
  for (std::size_t c = 0; c < st.Size(); ++c)
  {
    rock0[c] = st.terrain[c] - st.soil[c];
  }
  const double v0 = Sum(st.terrain);
  const double soil0 = Sum(st.soil);
  tr::ThermalParams t;
  t.talusSoilDeg = 30.0;
  t.talusRockDeg = 60.0;
  Relax(st, t, 1e-5, 20000);
  for (std::size_t c = 0; c < st.Size(); ++c)
  {
    ASSERT_NEAR(st.terrain[c] - st.soil[c], rock0[c], 1e-5) << "rock moved at " << c;
  }
  EXPECT_GE(MinOf(st.soil), 0.0f);
  EXPECT_NEAR(Sum(st.terrain), v0, 1e-6 * v0);
  EXPECT_NEAR(Sum(st.soil), soil0, 1e-5 * soil0);
  // The soil gathered at the foot of the ramp and left the upper cells bare.
  EXPECT_GT(st.soil[Idx(st, 0, 1)], 1.0f);
  EXPECT_LT(st.soil[Idx(st, nx - 2, 1)], 1e-4f);
  // Where soil is left, its slopes are at most the soil talus.
  EXPECT_LE(MaxExcess(st, 30.0, [&](std::size_t c) { return st.soil[c] > 1e-4f; }), 2e-4);

  // A rock spike steeper than 60 degrees, no soil: rock falls and becomes soil below it.
  std::vector<float> bare(25, 0.0f);
  tr::ErosionState rock = MakeState(
    5, 5, [](int i, int j) { return i == 2 && j == 2 ? 8.0f : 0.0f; }, 1.0, &bare);
  Relax(rock, t, 1e-5, 20000);
  EXPECT_LE(MaxExcess(rock, 60.0, [&](std::size_t c) { return rock.soil[c] == 0.0f; }), 2e-5);
  EXPECT_GT(rock.soil[Idx(rock, 2, 1)], 0.1f);
  EXPECT_EQ(rock.soil[Idx(rock, 2, 2)], 0.0f);
  EXPECT_NEAR(Sum(rock.terrain), 8.0, 1e-5);
}

TEST(TerroirErosionCore, ParametersAreChecked)
{
  tr::ErosionState st = MakeState(4, 4, [](int, int) { return 0.0f; });
  auto expectThrow = [&](tr::ErosionParams p, const std::string& name)
  {
    try
    {
      tr::ErosionHydraulicStep(st, p);
      ADD_FAILURE() << name << " accepted";
    }
    catch (const std::invalid_argument& e)
    {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  };
  tr::ErosionParams p;
  p.timeStep = 0.0;
  expectThrow(p, "timeStep");
  p = {};
  p.dissolving = 1.5;
  expectThrow(p, "dissolving");
  p = {};
  p.maxTilt = 0.001;
  expectThrow(p, "maxTilt");
  p = {};
  p.evaporation = -1.0;
  expectThrow(p, "evaporation");
  tr::ThermalParams t;
  t.talusSoilDeg = 90.0;
  EXPECT_THROW(tr::ErosionThermalStep(st, t), std::invalid_argument);
  tr::ErosionState broken = st;
  broken.water.resize(3);
  EXPECT_THROW(tr::ErosionHydraulicStep(broken, tr::ErosionParams{}), std::invalid_argument);
  EXPECT_THROW(tr::ErosionThermalStep(broken, tr::ThermalParams{}), std::invalid_argument);
  std::vector<float> negative(16, -1.0f);
  EXPECT_THROW(MakeState(
                 4, 4, [](int, int) { return 0.0f; }, 1.0, &negative),
    std::invalid_argument);
}

// Throughput of the CPU core at 1024^2 (one thread, plain loops). Not a test: run with
// --gtest_also_run_disabled_tests --gtest_filter=*Throughput*; nothing is asserted on time.
TEST(TerroirErosionCore, DISABLED_Throughput1024)
{
  const int n = 1024;
  tr::ErosionState st = Hills(n, 3);
  std::fill(st.water.begin(), st.water.end(), 0.05f);
  std::vector<float> rain(st.Size(), 0.01f);
  tr::ErosionParams p;
  using Clock = std::chrono::steady_clock;
  tr::ErosionHydraulicStep(st, p, rain.data());
  const int steps = 20;
  auto t0 = Clock::now();
  for (int k = 0; k < steps; ++k)
  {
    tr::ErosionHydraulicStep(st, p, rain.data());
  }
  auto t1 = Clock::now();
  tr::ThermalParams t;
  for (int k = 0; k < steps; ++k)
  {
    tr::ErosionThermalStep(st, t);
  }
  auto t2 = Clock::now();
  const double cells = static_cast<double>(n) * n * steps;
  const double hs = std::chrono::duration<double>(t1 - t0).count();
  const double ts = std::chrono::duration<double>(t2 - t1).count();
  std::printf("hydraulic: %.1f steps/s, %.3g cells*steps/s\n", steps / hs, cells / hs);
  std::printf("thermal:   %.1f steps/s, %.3g cells*steps/s\n", steps / ts, cells / ts);
}

} // namespace

// Per-cell factors (vegetation's resistance, Vegetation.h): on the uniform flow of
// UniformFlowBalancesErosionAndDeposition with s0 = C / 2, a factor f on K_s makes the bed give
// f x 0.1 x 0.0049937617 (f = 0.5: half; f = 0: nothing); a factor 2 on the talus tangent
// leaves a spike at atan(2 tan 30 deg) = 49.1 degrees instead of 30.
TEST(TerroirErosionCore, PerCellFactorsScaleErosionAndTalus)
{
  const double capacity = 0.0099875234;
  tr::ErosionParams p;
  for (float f : { 0.5f, 0.0f })
  {
    tr::ErosionState st = UniformFlow(static_cast<float>(capacity / 2));
    st.erosionFactor.assign(st.Size(), f);
    const std::vector<float> bed = st.terrain;
    tr::ErosionHydraulicStep(st, p);
    for (int i = 3; i < st.nx - 3; ++i)
    {
      const std::size_t c = Idx(st, i, 1);
      ASSERT_NEAR(st.terrain[c] - bed[c], -f * 0.00049937617, 2e-6) << "factor " << f;
    }
  }
  tr::ThermalParams t;
  t.talusSoilDeg = 30.0;
  tr::ErosionState spike =
    MakeState(15, 15, [](int i, int j) { return i == 7 && j == 7 ? 10.0f : 0.0f; });
  spike.talusFactor.assign(spike.Size(), 2.0f);
  Relax(spike, t, 1e-4, 20000);
  const double steep = std::atan(2.0 * std::tan(30.0 * M_PI / 180.0)) * 180.0 / M_PI;
  EXPECT_LE(MaxExcess(spike, steep), 1e-4 + 1e-5);
  EXPECT_GT(MaxExcess(spike, 30.0), 0.1);
  // A negative factor is refused.
  spike.talusFactor[3] = -1.0f;
  EXPECT_THROW(tr::ErosionThermalStep(spike, t), std::invalid_argument);
}

// Unit tests of Dunn's (2015) vegetation automaton and evaporation core
// (terroir::terrain::VegetationStep, EvaporationDunn2015Step and the coupling helpers).
// Expected values are worked out by hand in the comments from the rules of Vegetation.h
// (Dunn section 3.4) and from Dunn's eq. 2.6 and Table 2.1, or are properties any correct
// implementation has: water is conserved, the spread probability matches 1 - exp(-r dt) per
// parent, the resistance factors are linear in the density, and any row split gives the same bits.
#include "Vegetation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
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

/// A state on an nx x ny grid of square cells with densities v(i, j) and stores w(i, j).
tr::VegetationState MakeVeg(int nx,
  int ny,
  const std::function<float(int, int)>& v,
  const std::function<float(int, int)>& w,
  double spacing = 1.0)
{
  std::vector<float> density(static_cast<std::size_t>(nx) * ny), stored(density.size());
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      density[static_cast<std::size_t>(j) * nx + i] = v(i, j);
      stored[static_cast<std::size_t>(j) * nx + i] = w(i, j);
    }
  }
  GridView<float> view;
  view.data = density.data();
  view.nx = nx;
  view.ny = ny;
  view.dx = spacing;
  view.dy = spacing;
  return tr::MakeVegetationState(view, stored.data());
}

/// Density v0 and store w0 at (ci, cj), nothing elsewhere.
tr::VegetationState OneCell(int n, int ci, int cj, float v0, float w0)
{
  return MakeVeg(
    n,
    n,
    [=](int i, int j) { return (i == ci && j == cj) ? v0 : 0.0f; },
    [=](int i, int j) { return (i == ci && j == cj) ? w0 : 0.0f; });
}

std::size_t Idx(const tr::VegetationState& st, int i, int j)
{
  return static_cast<std::size_t>(j) * st.nx + i;
}

tr::VegetationWater Surface(std::vector<float>& d)
{
  tr::VegetationWater water;
  water.surface = d.data();
  return water;
}

/// Parameters with no spreading (the tests that want it turn it on).
tr::VegetationParams NoSpread()
{
  tr::VegetationParams p;
  p.spreadRate = 0.0;
  return p;
}

TEST(TerroirVegetationCore, GrowsOnlyWithEnoughAbsorbedWater)
{
  // Centre of 3x3: v = 0.5, w = 0.004 m, with 0.002 m of surface water, dt = 1 s.
  // Absorption: want = min(r_a dt v, S - w) = min(0.01 * 0.5, 0.046) = 0.005; it takes all
  // 0.002 m, so d = 0 and w = 0.006 >= w_grow = 0.005: v = 0.5 + g dt = 0.55.
  tr::VegetationState st = OneCell(3, 1, 1, 0.5f, 0.004f);
  std::vector<float> d(9, 0.0f);
  d[4] = 0.002f;
  const tr::VegetationStepStats s = tr::VegetationStep(st, Surface(d), 1.0, NoSpread());
  EXPECT_FLOAT_EQ(st.density[4], 0.55f);
  EXPECT_FLOAT_EQ(st.stored[4], 0.006f);
  EXPECT_EQ(d[4], 0.0f);
  EXPECT_NEAR(s.absorbedSurface, 0.002, 1e-9);
  EXPECT_EQ(s.grown, 1);
  EXPECT_NEAR(s.cover, 0.55, 1e-7);
  for (std::size_t c = 0; c < 9; ++c)
  {
    if (c != 4)
    {
      EXPECT_EQ(st.density[c], 0.0f) << c;
    }
  }
  // Without the surface water w stays 0.004: above the drought level (0), below w_grow, so the
  // density does not change.
  tr::VegetationState dry = OneCell(3, 1, 1, 0.5f, 0.004f);
  std::vector<float> none(9, 0.0f);
  const tr::VegetationStepStats s2 = tr::VegetationStep(dry, Surface(none), 1.0, NoSpread());
  EXPECT_EQ(dry.density[4], 0.5f);
  EXPECT_EQ(dry.stored[4], 0.004f);
  EXPECT_EQ(s2.grown, 0);
  // Uptake is capped by the store: w = 0.049, S = 0.05 leaves room for 0.001 m only.
  tr::VegetationState full = OneCell(3, 1, 1, 1.0f, 0.049f);
  std::vector<float> pond(9, 0.0f);
  pond[4] = 0.05f;
  tr::VegetationStep(full, Surface(pond), 1.0, NoSpread());
  EXPECT_FLOAT_EQ(full.stored[4], 0.05f);
  EXPECT_FLOAT_EQ(pond[4], 0.049f);
}

TEST(TerroirVegetationCore, SpreadsToEmptyNeighbours)
{
  // Centre of 3x3: v = 1, w = 0.04 >= w_seed; spreading certain (p = 1 - exp(-1e9) = 1).
  // Each edge cell (empty, dry) has the centre as its only parent: v = g dt = 0.05 and
  // w = phi 0.04 = 0.004. The centre keeps 0.04 - 4 * 0.004 = 0.024 and stays at v = 1 (it
  // grows, capped). Corners touch no parent (4-neighbours only) and stay empty.
  tr::VegetationState st = OneCell(3, 1, 1, 1.0f, 0.04f);
  std::vector<float> d(9, 0.0f);
  tr::VegetationParams p;
  p.spreadRate = 1e9;
  const tr::VegetationStepStats s = tr::VegetationStep(st, Surface(d), 1.0, p);
  const int edges[4][2] = { { 1, 0 }, { 0, 1 }, { 2, 1 }, { 1, 2 } };
  for (const auto& e : edges)
  {
    EXPECT_FLOAT_EQ(st.density[Idx(st, e[0], e[1])], 0.05f);
    EXPECT_FLOAT_EQ(st.stored[Idx(st, e[0], e[1])], 0.004f);
  }
  for (int c : { 0, 2, 6, 8 })
  {
    EXPECT_EQ(st.density[c], 0.0f);
    EXPECT_EQ(st.stored[c], 0.0f);
  }
  EXPECT_FLOAT_EQ(st.stored[4], 0.024f);
  EXPECT_EQ(st.density[4], 1.0f);
  EXPECT_EQ(s.seeded, 4);
  EXPECT_NEAR(s.seedWater, 0.016, 1e-8);
  EXPECT_EQ(st.step, 1u);
}

TEST(TerroirVegetationCore, ChildWithTwoParentsTakesTheFirstInOrderENWS)
{
  // 3x1: parents at i = 0 (w = 0.02) and i = 2 (w = 0.04), the empty child between them;
  // spreading certain. The east parent comes first: the child gets 0.1 * 0.04 = 0.004 from it,
  // the east parent keeps 0.036 and the west one all its 0.02 (both grow, capped at 1).
  tr::VegetationState st = MakeVeg(
    3,
    1,
    [](int i, int) { return i == 1 ? 0.0f : 1.0f; },
    [](int i, int) { return i == 0 ? 0.02f : (i == 2 ? 0.04f : 0.0f); });
  std::vector<float> d(3, 0.0f);
  tr::VegetationParams p;
  p.spreadRate = 1e9;
  EXPECT_EQ(tr::VegetationStep(st, Surface(d), 1.0, p).seeded, 1);
  EXPECT_FLOAT_EQ(st.stored[1], 0.004f);
  EXPECT_FLOAT_EQ(st.stored[2], 0.036f);
  EXPECT_FLOAT_EQ(st.stored[0], 0.02f);
  EXPECT_FLOAT_EQ(st.density[1], 0.05f);
}

TEST(TerroirVegetationCore, SpreadNeedsWaterDensityAndDryGround)
{
  tr::VegetationParams p;
  p.spreadRate = 1e9;
  std::vector<float> d(9, 0.0f);
  // Too little water (0.009 < w_seed = 0.01): no seeding.
  tr::VegetationState thirsty = OneCell(3, 1, 1, 1.0f, 0.009f);
  EXPECT_EQ(tr::VegetationStep(thirsty, Surface(d), 1.0, p).seeded, 0);
  // Too sparse (0.4 < v_seed = 0.5): no seeding.
  tr::VegetationState sparse = OneCell(3, 1, 1, 0.4f, 0.04f);
  EXPECT_EQ(tr::VegetationStep(sparse, Surface(d), 1.0, p).seeded, 0);
  // A flooded neighbour (0.2 m > d_drown = 0.1 m) is not seeded; the other three are.
  tr::VegetationState wet = OneCell(3, 1, 1, 1.0f, 0.04f);
  d[Idx(wet, 2, 1)] = 0.2f;
  EXPECT_EQ(tr::VegetationStep(wet, Surface(d), 1.0, p).seeded, 3);
  EXPECT_EQ(wet.density[Idx(wet, 2, 1)], 0.0f);
  EXPECT_FLOAT_EQ(wet.stored[4], 0.04f - 3 * 0.004f);
}

TEST(TerroirVegetationCore, SharesWaterWithVegetatedNeighbours)
{
  // 5x5: centre v = 1, w = 0.04; its four neighbours v = 1, w = 0; no surface water, no
  // spreading, dt = 1. Each pair: q = (k_s dt / 4) max(0, min(w - T, w - w_n))
  // = 0.125 min(0.02, 0.04) = 0.0025. Centre 0.04 - 0.01 = 0.03 (grows, stays 1); the
  // neighbours get 0.0025 but decided on their store before sharing (0 <= w_drought = 0):
  // drought, v = 1 - r_drought dt = 0.98.
  tr::VegetationState st = MakeVeg(
    5,
    5,
    [](int i, int j) { return std::abs(i - 2) + std::abs(j - 2) <= 1 ? 1.0f : 0.0f; },
    [](int i, int j) { return (i == 2 && j == 2) ? 0.04f : 0.0f; });
  std::vector<float> d(25, 0.0f);
  const tr::VegetationStepStats s = tr::VegetationStep(st, Surface(d), 1.0, NoSpread());
  const int nb[4][2] = { { 3, 2 }, { 2, 3 }, { 1, 2 }, { 2, 1 } };
  EXPECT_FLOAT_EQ(st.stored[Idx(st, 2, 2)], 0.03f);
  EXPECT_EQ(st.density[Idx(st, 2, 2)], 1.0f);
  for (const auto& n : nb)
  {
    EXPECT_FLOAT_EQ(st.stored[Idx(st, n[0], n[1])], 0.0025f);
    EXPECT_FLOAT_EQ(st.density[Idx(st, n[0], n[1])], 0.98f);
  }
  EXPECT_NEAR(s.shared, 0.01, 1e-8);
  EXPECT_EQ(s.drought, 4);
  EXPECT_EQ(s.grown, 1);
  // Step 2: centre 0.03 gives 0.125 min(0.01, 0.0275) = 0.00125 to each: 0.025 left, the
  // neighbours 0.00375 (no longer dry, below w_grow: v stays 0.98).
  tr::VegetationStep(st, Surface(d), 1.0, NoSpread());
  EXPECT_FLOAT_EQ(st.stored[Idx(st, 2, 2)], 0.025f);
  for (const auto& n : nb)
  {
    EXPECT_FLOAT_EQ(st.stored[Idx(st, n[0], n[1])], 0.00375f);
    EXPECT_FLOAT_EQ(st.density[Idx(st, n[0], n[1])], 0.98f);
  }
  // Nothing reached the empty cells.
  EXPECT_EQ(st.stored[Idx(st, 0, 0)], 0.0f);
  EXPECT_EQ(st.stored[Idx(st, 3, 3)], 0.0f);
}

TEST(TerroirVegetationCore, DiesOfDrought)
{
  // v = 0.3, w = 0, no water: v = 0.3 - 0.02 per second of dt = 1.
  tr::VegetationState st = OneCell(3, 1, 1, 0.3f, 0.0f);
  std::vector<float> d(9, 0.0f);
  EXPECT_EQ(tr::VegetationStep(st, Surface(d), 1.0, NoSpread()).drought, 1);
  EXPECT_FLOAT_EQ(st.density[4], 0.28f);
  tr::VegetationStep(st, Surface(d), 1.0, NoSpread());
  EXPECT_FLOAT_EQ(st.density[4], 0.26f);
  // v = 0.01 drops to exactly 0 (clamped), and an empty cell is no longer counted.
  tr::VegetationState last = OneCell(3, 1, 1, 0.01f, 0.0f);
  tr::VegetationStep(last, Surface(d), 1.0, NoSpread());
  EXPECT_EQ(last.density[4], 0.0f);
  EXPECT_EQ(tr::VegetationStep(last, Surface(d), 1.0, NoSpread()).drought, 0);
  // The canopy empties its store (Table 2.1 floor E_min keeps it going), then drought starts:
  // w = 0.0001 m, v = 1 over 10 h: e = 0.019 + 0.171 * 0.0001 / 0.05 = 0.019342 mm/h, i.e.
  // 0.19342 mm > 0.1 mm: the store is emptied, to exactly 0.
  tr::VegetationState canopy = OneCell(3, 1, 1, 1.0f, 0.0001f);
  const tr::EvaporationStats e = tr::EvaporationDunn2015Step(
    canopy, Surface(d), 36000.0, tr::VegetationParams(), tr::EvaporationParams());
  EXPECT_EQ(canopy.stored[4], 0.0f);
  EXPECT_NEAR(e.fromCanopy, 0.0001, 1e-10);
  tr::VegetationStep(canopy, Surface(d), 1.0, NoSpread());
  EXPECT_FLOAT_EQ(canopy.density[4], 0.98f);
}

TEST(TerroirVegetationCore, DrownsUnderDeepWaterOnly)
{
  // dt = 0.5. Centre: v = 0.3 under 0.2 m of water. Absorption takes r_a dt v = 0.0015 m,
  // leaving 0.1985 > d_drown = 0.1: v = 0.3 - r_drown dt = 0.3 - 0.25 = 0.05.
  // Corner (0, 0): v = 0.3 under 0.05 m (rain): absorbs 0.0015, not drowned, w = 0.0015 is
  // neither dry nor enough to grow: v stays 0.3.
  tr::VegetationState st = MakeVeg(
    3,
    3,
    [](int i, int j) { return ((i == 1 && j == 1) || (i == 0 && j == 0)) ? 0.3f : 0.0f; },
    [](int, int) { return 0.0f; });
  std::vector<float> d(9, 0.0f);
  d[4] = 0.2f;
  d[0] = 0.05f;
  const tr::VegetationStepStats s = tr::VegetationStep(st, Surface(d), 0.5, NoSpread());
  EXPECT_FLOAT_EQ(st.density[4], 0.05f);
  EXPECT_FLOAT_EQ(st.stored[4], 0.0015f);
  EXPECT_FLOAT_EQ(d[4], 0.1985f);
  EXPECT_EQ(st.density[0], 0.3f);
  EXPECT_FLOAT_EQ(d[0], 0.0485f);
  EXPECT_EQ(s.drowned, 1);
  // Next step kills it: 0.05 - 0.25 < 0, clamped to 0.
  tr::VegetationStep(st, Surface(d), 0.5, NoSpread());
  EXPECT_EQ(st.density[4], 0.0f);
}

/// Random surface water, soil water, densities (a third empty) and stores on a grid whose rows
/// have different east-west spacings, with a few no-data cells.
struct RandomWorld
{
  std::vector<double> rowDx;
  std::vector<std::uint8_t> valid;
  tr::VegetationState st;
  std::vector<float> d, residue, soil;

  RandomWorld(int nx, int ny, unsigned seed)
  {
    std::mt19937_64 rng(seed);
    auto u = [&]() { return static_cast<float>((rng() >> 11) * (1.0 / 9007199254740992.0)); };
    const std::size_t n = static_cast<std::size_t>(nx) * ny;
    rowDx.resize(ny);
    for (int j = 0; j < ny; ++j)
    {
      rowDx[j] = 20.0 + 0.37 * j;
    }
    valid.assign(n, 1);
    std::vector<float> v(n), w(n);
    d.resize(n);
    soil.resize(n);
    residue.assign(n, 0.0f);
    for (std::size_t c = 0; c < n; ++c)
    {
      valid[c] = (c % 53 == 7) ? 0 : 1;
      const float r = u();
      v[c] = r < 0.33f ? 0.0f : u();
      w[c] = 0.05f * u();
      d[c] = u() < 0.2f ? 0.2f * u() : 0.01f * u();
      soil[c] = 0.02f * u();
    }
    GridView<float> view;
    view.data = v.data();
    view.nx = nx;
    view.ny = ny;
    view.rowDx = rowDx.data();
    view.dy = 25.0;
    view.valid = valid.data();
    st = tr::MakeVegetationState(view, w.data());
    for (std::size_t c = 0; c < n; ++c)
    {
      if (!valid[c])
      {
        d[c] = soil[c] = 0.0f;
      }
    }
  }
  tr::VegetationWater Water()
  {
    tr::VegetationWater water;
    water.surface = d.data();
    water.surfaceResidue = residue.data();
    water.soil = soil.data();
    return water;
  }
  /// sum of a over valid cells of one per-cell array (double, row by row).
  double Volume(const std::vector<float>& a, const std::vector<float>* lo = nullptr) const
  {
    double total = 0.0;
    for (int j = 0; j < st.ny; ++j)
    {
      for (int i = 0; i < st.nx; ++i)
      {
        const std::size_t c = Idx(st, i, j);
        if (valid[c])
        {
          total += (static_cast<double>(a[c]) + (lo ? (*lo)[c] : 0.0f)) * st.CellArea(j);
        }
      }
    }
    return total;
  }
};

TEST(TerroirVegetationCore, ConservesWater)
{
  RandomWorld world(40, 30, 11);
  tr::VegetationParams p;
  p.spreadRate = 2.0;
  const double total0 = world.Volume(world.d, &world.residue) + world.Volume(world.soil) +
    world.Volume(world.st.stored);
  long long seeded = 0;
  double shared = 0.0;
  for (int step = 0; step < 300; ++step)
  {
    const double d0 = world.Volume(world.d, &world.residue);
    const double g0 = world.Volume(world.soil);
    const tr::VegetationStepStats s = tr::VegetationStep(world.st, world.Water(), 0.1, p);
    // What vegetation absorbed is what left the surface and the soil (the surface exactly,
    // thanks to its residue; the soil up to float rounding of each cell).
    ASSERT_NEAR(d0 - world.Volume(world.d, &world.residue), s.absorbedSurface, 1e-9 * d0);
    ASSERT_NEAR(g0 - world.Volume(world.soil), s.absorbedSoil, 1e-6 * g0);
    seeded += s.seeded;
    shared += s.shared;
    for (std::size_t c = 0; c < world.st.Size(); ++c)
    {
      ASSERT_GE(world.st.density[c], 0.0f);
      ASSERT_LE(world.st.density[c], 1.0f);
      ASSERT_GE(world.st.stored[c], 0.0f);
      ASSERT_GE(world.d[c], 0.0f);
      ASSERT_GE(world.soil[c], 0.0f);
    }
  }
  const double total1 = world.Volume(world.d, &world.residue) + world.Volume(world.soil) +
    world.Volume(world.st.stored);
  EXPECT_NEAR(total1, total0, 1e-6 * total0);
  // The run exercised every path: spreading, sharing, absorption.
  EXPECT_GT(seeded, 10);
  EXPECT_GT(shared, 0.0);
  // No-data cells never change.
  for (std::size_t c = 0; c < world.st.Size(); ++c)
  {
    if (!world.valid[c])
    {
      ASSERT_EQ(world.st.density[c], 0.0f);
      ASSERT_EQ(world.st.stored[c], 0.0f);
    }
  }
}

TEST(TerroirVegetationCore, SpreadProbabilityIsOneMinusExpPerParent)
{
  // Even columns are parents (v = 1, w = 0.04), odd columns empty; dt = 1, r_s = 0.3. An empty
  // cell between two parents is seeded with probability 1 - (1 - p)^2 = 1 - exp(-0.6) = 0.4512;
  // the last column (one parent) with p = 1 - exp(-0.3) = 0.2592. Binomial spreads: 1984
  // cells, sigma = 0.0112; 64 cells, sigma = 0.055; we allow 4 sigma.
  const int n = 64;
  tr::VegetationParams p;
  p.spreadRate = 0.3;
  p.seed = 2024;
  tr::VegetationState st = MakeVeg(
    n,
    n,
    [](int i, int) { return i % 2 == 0 ? 1.0f : 0.0f; },
    [](int i, int) { return i % 2 == 0 ? 0.04f : 0.0f; });
  tr::VegetationState again = st;
  std::vector<float> d(st.Size(), 0.0f);
  tr::VegetationStep(st, Surface(d), 1.0, p);
  tr::VegetationStep(again, Surface(d), 1.0, p);
  EXPECT_EQ(st.density, again.density);
  int inner = 0, innerSeeded = 0, edgeSeeded = 0;
  for (int j = 0; j < n; ++j)
  {
    for (int i = 1; i < n; i += 2)
    {
      const bool seeded = st.density[Idx(st, i, j)] > 0.0f;
      if (i == n - 1)
      {
        edgeSeeded += seeded;
      }
      else
      {
        ++inner;
        innerSeeded += seeded;
      }
    }
  }
  EXPECT_NEAR(static_cast<double>(innerSeeded) / inner, 1.0 - std::exp(-0.6), 4 * 0.0112);
  EXPECT_NEAR(edgeSeeded / 64.0, 1.0 - std::exp(-0.3), 4 * 0.055);
  // Another seed draws another pattern.
  tr::VegetationState other = MakeVeg(
    n,
    n,
    [](int i, int) { return i % 2 == 0 ? 1.0f : 0.0f; },
    [](int i, int) { return i % 2 == 0 ? 0.04f : 0.0f; });
  p.seed = 7;
  tr::VegetationStep(other, Surface(d), 1.0, p);
  EXPECT_NE(st.density, other.density);
}

TEST(TerroirVegetationCore, OpenWaterEvaporationFollowsEq26)
{
  // Eq. 2.6 by hand: wind 2 m/s, Theta = 25 + 19 * 2 = 63 kg/(m^2 h); A = 10 m x 10 m;
  // x_s - x = 0.02 - 0.01: g_s = 63 * 100 * 0.01 / 3600 = 0.0175 kg/s. As depth:
  // 0.0175 / (1000 * 100) = 1.75e-7 m/s; over dt = 10 s, 1.75e-6 m.
  EXPECT_DOUBLE_EQ(tr::EvaporationCoefficientDunn2015(0.0), 25.0);
  EXPECT_DOUBLE_EQ(tr::EvaporationCoefficientDunn2015(2.0), 63.0);
  EXPECT_NEAR(tr::OpenWaterEvaporationDunn2015(100.0, 2.0, 0.02, 0.01), 0.0175, 1e-12);
  tr::VegetationState st = MakeVeg(
    2, 1, [](int, int) { return 0.0f; }, [](int, int) { return 0.0f; }, 10.0);
  std::vector<float> d = { 0.01f, 0.01f };
  std::vector<float> wind = { 2.0f, 0.0f }, vapour = { 0.5f, 0.0f };
  tr::EvaporationParams e;
  e.saturationRatio = 0.02;
  e.humidityRatio = 0.01;
  tr::EvaporationFields f;
  f.windSpeed = wind.data();
  f.vapour = vapour.data();
  const tr::EvaporationStats s =
    tr::EvaporationDunn2015Step(st, Surface(d), 10.0, tr::VegetationParams(), e, f);
  EXPECT_NEAR(d[0], 0.01 - 1.75e-6, 1e-9);
  // Cell 1, still air: Theta = 25, 25 * 0.01 / 3.6e6 * 10 = 6.944e-7 m.
  EXPECT_NEAR(d[1], 0.01 - 25.0 * 0.01 / 3.6e6 * 10.0, 1e-9);
  EXPECT_NEAR(vapour[0], 0.5 + 1.75e-6, 1e-7);
  EXPECT_NEAR(s.fromWater, 100.0 * (1.75e-6 + 6.9444e-7), 1e-9);
  EXPECT_EQ(s.fromCanopy, 0.0);
  // Humid air (x >= x_s): no evaporation (no condensation either).
  std::vector<float> humid = { 0.03f, 0.03f };
  f.humidityRatio = humid.data();
  const std::vector<float> before = d;
  tr::EvaporationDunn2015Step(st, Surface(d), 10.0, tr::VegetationParams(), e, f);
  EXPECT_EQ(d, before);
  // A NaN or negative wind counts as still air (Theta = 25): both cells lose 6.944e-7 m.
  std::vector<float> badWind = { NAN, -3.0f }, pools = { 0.01f, 0.01f };
  f.windSpeed = badWind.data();
  f.humidityRatio = nullptr;
  tr::EvaporationDunn2015Step(st, Surface(pools), 10.0, tr::VegetationParams(), e, f);
  EXPECT_NEAR(pools[0], 0.01 - 25.0 * 0.01 / 3.6e6 * 10.0, 1e-9);
  EXPECT_NEAR(pools[1], 0.01 - 25.0 * 0.01 / 3.6e6 * 10.0, 1e-9);
  f.windSpeed = wind.data();
  // Limited by the water there: a 1 micrometre film over a long step is all gone, no more.
  std::vector<float> film = { 1e-6f, 0.0f };
  f.humidityRatio = nullptr;
  std::fill(vapour.begin(), vapour.end(), 0.0f);
  tr::EvaporationDunn2015Step(st, Surface(film), 1e6, tr::VegetationParams(), e, f);
  EXPECT_EQ(film[0], 0.0f);
  EXPECT_EQ(film[1], 0.0f);
  EXPECT_EQ(vapour[0], 1e-6f);
  // The saturation ratio from a temperature (psychrometric tables: 0.01475 at 20 C, 0.02016
  // at 25 C, 0.02732 at 30 C, sea-level pressure), within 1.5 %.
  EXPECT_NEAR(tr::SaturationHumidityRatio(20.0), 0.01475, 0.015 * 0.01475);
  EXPECT_NEAR(tr::SaturationHumidityRatio(25.0), 0.02016, 0.015 * 0.02016);
  EXPECT_NEAR(tr::SaturationHumidityRatio(30.0), 0.02732, 0.015 * 0.02732);
}

TEST(TerroirVegetationCore, CanopyEvaporationUsesTable21)
{
  EXPECT_EQ(tr::CanopyEvaporationDunn2015(tr::CanopyType::ScotsPine), 0.19);
  EXPECT_EQ(tr::CanopyEvaporationDunn2015(tr::CanopyType::MontereyPine), 0.21);
  EXPECT_EQ(tr::CanopyEvaporationDunn2015(tr::CanopyType::SitkaSpruce), 0.18);
  EXPECT_EQ(tr::CanopyEvaporationDunn2015(tr::CanopyType::DouglasFir), 0.15);
  EXPECT_EQ(tr::CanopyEvaporationDunn2015(tr::CanopyType::CommonBeech), 0.45);
  EXPECT_EQ(tr::CanopyEvaporationDunn2015(tr::CanopyType::SouthernBeeches), 0.37);
  // Full store (w = S = 0.05), v = 1, Scots pine: 0.19 mm in one hour: w = 0.04981.
  // Half store, v = 0.5: 0.5 (0.019 + 0.171 * 0.5) = 0.05225 mm/h.
  // Full store, v = 1, common beech (0.45 mm/h, E_min 0.045): 0.45 mm.
  tr::VegetationState st = MakeVeg(
    3,
    1,
    [](int i, int) { return i == 1 ? 0.5f : 1.0f; },
    [](int i, int) { return i == 1 ? 0.025f : 0.05f; },
    10.0);
  std::vector<float> d(3, 0.0f);
  tr::EvaporationParams e;
  tr::EvaporationDunn2015Step(st, Surface(d), 3600.0, tr::VegetationParams(), e);
  EXPECT_NEAR(st.stored[0], 0.05 - 0.19e-3, 1e-8);
  EXPECT_NEAR(st.stored[1], 0.025 - 0.05225e-3, 1e-8);
  tr::VegetationState beech = OneCell(1, 0, 0, 1.0f, 0.05f);
  std::vector<float> d1(1, 0.0f);
  e.canopyRate = tr::CanopyEvaporationDunn2015(tr::CanopyType::CommonBeech);
  e.canopyMinRate = 0.045;
  const tr::EvaporationStats s =
    tr::EvaporationDunn2015Step(beech, Surface(d1), 3600.0, tr::VegetationParams(), e);
  EXPECT_NEAR(beech.stored[0], 0.05 - 0.45e-3, 1e-8);
  EXPECT_NEAR(s.fromCanopy, 0.45e-3, 1e-9);
  // Bare ground (v = 0) keeps its water.
  tr::VegetationState bare = OneCell(1, 0, 0, 0.0f, 0.05f);
  tr::EvaporationDunn2015Step(bare, Surface(d1), 3600.0, tr::VegetationParams(), e);
  EXPECT_EQ(bare.stored[0], 0.05f);
}

TEST(TerroirVegetationCore, ResistanceFactorsAreLinearAndBounded)
{
  tr::VegetationParams p; // f_e1 = 0.25, f_t1 = 1.5
  EXPECT_FLOAT_EQ(tr::VegetationErosionFactor(0.0f, p), 1.0f);
  EXPECT_FLOAT_EQ(tr::VegetationErosionFactor(0.5f, p), 0.625f);
  EXPECT_FLOAT_EQ(tr::VegetationErosionFactor(1.0f, p), 0.25f);
  EXPECT_FLOAT_EQ(tr::VegetationTalusFactor(0.0f, p), 1.0f);
  EXPECT_FLOAT_EQ(tr::VegetationTalusFactor(0.5f, p), 1.25f);
  EXPECT_FLOAT_EQ(tr::VegetationTalusFactor(1.0f, p), 1.5f);
  // Out-of-range densities are clamped.
  EXPECT_FLOAT_EQ(tr::VegetationErosionFactor(2.0f, p), 0.25f);
  EXPECT_FLOAT_EQ(tr::VegetationTalusFactor(-1.0f, p), 1.0f);
  float lastE = 2.0f, lastT = 0.0f;
  for (int k = 0; k <= 100; ++k)
  {
    const float v = 0.01f * k;
    const float e = tr::VegetationErosionFactor(v, p);
    const float t = tr::VegetationTalusFactor(v, p);
    ASSERT_LE(e, lastE);
    ASSERT_GE(t, lastT);
    ASSERT_GE(e, 0.25f - 1e-6f);
    ASSERT_LE(e, 1.0f);
    ASSERT_GE(t, 1.0f);
    ASSERT_LE(t, 1.5f + 1e-6f);
    lastE = e;
    lastT = t;
  }
  // Per cell; a no-data cell gets 1 and 1.
  std::vector<std::uint8_t> valid = { 1, 1, 0 };
  std::vector<float> v = { 0.0f, 0.8f, 1.0f };
  GridView<float> view;
  view.data = v.data();
  view.nx = 3;
  view.ny = 1;
  view.valid = valid.data();
  const tr::VegetationState st = tr::MakeVegetationState(view);
  std::vector<float> fe(3), ft(3);
  tr::VegetationResistance(st, p, fe.data(), ft.data());
  EXPECT_FLOAT_EQ(fe[0], 1.0f);
  EXPECT_FLOAT_EQ(fe[1], 1.0f - 0.75f * 0.8f);
  EXPECT_FLOAT_EQ(ft[1], 1.0f + 0.5f * 0.8f);
  EXPECT_EQ(fe[2], 1.0f);
  EXPECT_EQ(ft[2], 1.0f);
}

TEST(TerroirVegetationCore, SoilSlipDestroysVegetation)
{
  // d_slip = 0.1 m: a bed change of 0.05 m halves full vegetation, 0.2 m kills it, and a
  // cell whose bed does not move keeps its cover. Cells of 2 m x 2 m: lost 4 (0.5 + 1) m^2.
  tr::VegetationState st = MakeVeg(
    3, 1, [](int, int) { return 1.0f; }, [](int, int) { return 0.0f; }, 2.0);
  const std::vector<float> before = { 10.0f, 10.0f, 10.0f };
  const std::vector<float> after = { 9.95f, 10.2f, 10.0f };
  const double lost =
    tr::VegetationSlipDamage(st, before.data(), after.data(), tr::VegetationParams());
  EXPECT_NEAR(st.density[0], 0.5f, 1e-5f);
  EXPECT_EQ(st.density[1], 0.0f);
  EXPECT_EQ(st.density[2], 1.0f);
  EXPECT_NEAR(lost, 4.0 * 1.5, 1e-4);
}

TEST(TerroirVegetationCore, AnyRowSplitGivesTheSameBits)
{
  RandomWorld a(37, 29, 5);
  RandomWorld b(37, 29, 5);
  tr::VegetationParams p;
  p.spreadRate = 1.0;
  p.seed = 99;
  tr::EvaporationParams e;
  e.scale = 1000.0;
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
  std::vector<float> va(a.st.Size(), 0.0f), vb(b.st.Size(), 0.0f);
  tr::EvaporationFields fa, fb;
  fa.vapour = va.data();
  fb.vapour = vb.data();
  for (int n = 0; n < 60; ++n)
  {
    const tr::VegetationStepStats sa = tr::VegetationStep(a.st, a.Water(), 0.2, p);
    const tr::VegetationStepStats sb = tr::VegetationStep(b.st, b.Water(), 0.2, p, split);
    ASSERT_EQ(sa.seeded, sb.seeded);
    ASSERT_EQ(sa.cover, sb.cover);
    tr::EvaporationDunn2015Step(a.st, a.Water(), 0.2, p, e, fa);
    tr::EvaporationDunn2015Step(b.st, b.Water(), 0.2, p, e, fb, split);
  }
  EXPECT_EQ(a.st.density, b.st.density);
  EXPECT_EQ(a.st.stored, b.st.stored);
  EXPECT_EQ(a.d, b.d);
  EXPECT_EQ(a.residue, b.residue);
  EXPECT_EQ(a.soil, b.soil);
  EXPECT_EQ(va, vb);
}

TEST(TerroirVegetationCore, CouplesWithErosionOnOneTimeStep)
{
  // The coupling a filter does on each time step: ErosionHydraulicStep (its evaporation off),
  // VegetationStep on the state's water and residue, the per-cell talus factors (which the
  // thermal step does not take yet: it has one talus per material), soil slip, slip damage. On a
  // closed bowl the water in the flow plus the water held by vegetation is conserved (1e-6 relative
  // over 300 steps), and vegetation took some of it.
  const int n = 24;
  std::vector<float> z(static_cast<std::size_t>(n) * n);
  for (int j = 0; j < n; ++j)
  {
    for (int i = 0; i < n; ++i)
    {
      const float x = i - 11.5f, y = j - 11.5f;
      z[static_cast<std::size_t>(j) * n + i] = 0.01f * (x * x + y * y) + 0.3f * std::sin(0.7f * i);
    }
  }
  GridView<float> view;
  view.data = z.data();
  view.nx = n;
  view.ny = n;
  view.dx = view.dy = 2.0;
  tr::ErosionState flow = tr::MakeErosionState(view);
  std::fill(flow.water.begin(), flow.water.end(), 0.05f);
  GridView<float> none = view;
  none.data = nullptr;
  tr::VegetationState veg = tr::MakeVegetationState(none);
  for (std::size_t c = 0; c < veg.Size(); ++c)
  {
    veg.density[c] = (c % 3 == 0) ? 0.8f : 0.0f;
  }
  tr::ErosionParams ep;
  ep.evaporation = 0.0;
  tr::VegetationParams vp;
  tr::VegetationWater water;
  water.surface = flow.water.data();
  water.surfaceResidue = flow.waterResidue.data();
  const double total0 = tr::ErosionMeasure(flow).water + tr::VegetationMeasure(veg).stored;
  std::vector<float> talus(veg.Size()), before;
  double absorbed = 0.0;
  for (int step = 0; step < 300; ++step)
  {
    tr::ErosionHydraulicStep(flow, ep);
    absorbed += tr::VegetationStep(veg, water, ep.timeStep, vp).absorbedSurface;
    tr::VegetationResistance(veg, vp, nullptr, talus.data());
    before = flow.terrain;
    tr::ErosionThermalStep(flow, tr::ThermalParams());
    tr::VegetationSlipDamage(veg, before.data(), flow.terrain.data(), vp);
  }
  const double total1 = tr::ErosionMeasure(flow).water + tr::VegetationMeasure(veg).stored;
  EXPECT_NEAR(total1, total0, 1e-6 * total0);
  EXPECT_NEAR(tr::VegetationMeasure(veg).stored, absorbed, 1e-6 * absorbed);
  EXPECT_GT(absorbed, 0.01 * total0);
  EXPECT_GE(*std::min_element(talus.begin(), talus.end()), 1.0f);
}

/// Expects fn to throw std::invalid_argument whose message names `name`.
void ExpectThrowNaming(const std::function<void()>& fn, const std::string& name)
{
  try
  {
    fn();
    ADD_FAILURE() << "no exception for " << name;
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
  }
}

TEST(TerroirVegetationCore, RejectsBadParameters)
{
  std::vector<float> d(9, 0.0f);
  const auto step = [&](const tr::VegetationParams& p, double dt = 1.0)
  {
    tr::VegetationState st = OneCell(3, 1, 1, 1.0f, 0.0f);
    tr::VegetationStep(st, Surface(d), dt, p);
  };
  const std::vector<std::pair<std::string, std::function<void(tr::VegetationParams&)>>> bad = {
    { "absorptionRate", [](tr::VegetationParams& p) { p.absorptionRate = -1.0; } },
    { "storage", [](tr::VegetationParams& p) { p.storage = 0.0; } },
    { "shareRate", [](tr::VegetationParams& p) { p.shareRate = NAN; } },
    { "seedDensity", [](tr::VegetationParams& p) { p.seedDensity = 0.0; } },
    { "seedWaterFraction", [](tr::VegetationParams& p) { p.seedWaterFraction = 0.3; } },
    { "spreadRate", [](tr::VegetationParams& p) { p.spreadRate = -0.1; } },
    { "growthRate", [](tr::VegetationParams& p) { p.growthRate = INFINITY; } },
    { "drownDepth", [](tr::VegetationParams& p) { p.drownDepth = -1.0; } },
    { "slipKillDepth", [](tr::VegetationParams& p) { p.slipKillDepth = 0.0; } },
    { "erosionFactorFull", [](tr::VegetationParams& p) { p.erosionFactorFull = 1.1; } },
    { "talusFactorFull", [](tr::VegetationParams& p) { p.talusFactorFull = 0.9; } },
  };
  for (const auto& b : bad)
  {
    tr::VegetationParams p;
    b.second(p);
    ExpectThrowNaming([&]() { step(p); }, b.first);
  }
  ExpectThrowNaming([&]() { step(tr::VegetationParams(), 0.0); }, "dt");
  // k_s dt + 4 phi = 0.5 * 2 + 0.4 > 1: a store could go negative.
  ExpectThrowNaming([&]() { step(tr::VegetationParams(), 2.0); }, "shareRate * dt");
  ExpectThrowNaming(
    [&]()
    {
      tr::VegetationState st = OneCell(3, 1, 1, 1.0f, 0.0f);
      tr::VegetationStep(st, tr::VegetationWater(), 1.0, tr::VegetationParams());
    },
    "surface water");
  ExpectThrowNaming(
    [&]()
    {
      tr::VegetationState st = OneCell(3, 1, 1, 1.0f, 0.0f);
      st.stored.resize(4);
      tr::VegetationStep(st, Surface(d), 1.0, tr::VegetationParams());
    },
    "stored size");
  ExpectThrowNaming([&]() { OneCell(3, 1, 1, 1.5f, 0.0f); }, "density");
  ExpectThrowNaming([&]() { OneCell(3, 1, 1, 1.0f, -0.1f); }, "stored water");
  tr::EvaporationParams e;
  e.canopyMinRate = 0.5;
  ExpectThrowNaming(
    [&]()
    {
      tr::VegetationState st = OneCell(3, 1, 1, 1.0f, 0.0f);
      tr::EvaporationDunn2015Step(st, Surface(d), 1.0, tr::VegetationParams(), e);
    },
    "canopyMinRate");
  e = tr::EvaporationParams();
  e.waterDensity = 0.0;
  ExpectThrowNaming(
    [&]()
    {
      tr::VegetationState st = OneCell(3, 1, 1, 1.0f, 0.0f);
      tr::EvaporationDunn2015Step(st, Surface(d), 1.0, tr::VegetationParams(), e);
    },
    "waterDensity");
  ExpectThrowNaming(
    []() { tr::CanopyEvaporationDunn2015(static_cast<tr::CanopyType>(9)); }, "canopy type");
  ExpectThrowNaming([]() { tr::SaturationHumidityRatio(100.0); }, "temperatureC");
  ExpectThrowNaming([]() { tr::EvaporationCoefficientDunn2015(-1.0); }, "windSpeed");
}

// Throughput of the CPU core at 1024^2 (one thread, plain loops). Not a test: run with
// --gtest_also_run_disabled_tests --gtest_filter=*Vegetation*Throughput*; nothing is asserted
// on time.
/// Steps per second of VegetationStep and EvaporationDunn2015Step on `world` (20 steps each).
void Time(const char* name, RandomWorld& world)
{
  tr::VegetationParams p;
  tr::EvaporationParams e;
  using Clock = std::chrono::steady_clock;
  tr::VegetationStep(world.st, world.Water(), 0.02, p);
  const int steps = 20;
  auto t0 = Clock::now();
  for (int k = 0; k < steps; ++k)
  {
    tr::VegetationStep(world.st, world.Water(), 0.02, p);
  }
  auto t1 = Clock::now();
  for (int k = 0; k < steps; ++k)
  {
    tr::EvaporationDunn2015Step(world.st, world.Water(), 0.02, p, e);
  }
  auto t2 = Clock::now();
  const double cells = static_cast<double>(world.st.Size()) * steps;
  const double vs = std::chrono::duration<double>(t1 - t0).count();
  const double es = std::chrono::duration<double>(t2 - t1).count();
  std::printf("%s vegetation:  %.1f steps/s, %.3g cells*steps/s\n", name, steps / vs, cells / vs);
  std::printf("%s evaporation: %.1f steps/s, %.3g cells*steps/s\n", name, steps / es, cells / es);
}

// Throughput of the CPU core at 1024^2 (one thread, plain loops) on white noise (a third of the
// cells empty at random: worst case for branch prediction) and on smooth patches of vegetation.
// Not a test: run with --gtest_also_run_disabled_tests --gtest_filter=*Vegetation*Throughput*;
// nothing is asserted on time.
TEST(TerroirVegetationCore, DISABLED_Throughput1024)
{
  RandomWorld noise(1024, 1024, 3);
  Time("noise  ", noise);
  RandomWorld patches(1024, 1024, 3);
  for (int j = 0; j < 1024; ++j)
  {
    for (int i = 0; i < 1024; ++i)
    {
      const std::size_t c = Idx(patches.st, i, j);
      const float v = std::sin(i / 37.0f) * std::sin(j / 23.0f);
      patches.st.density[c] = patches.valid[c] ? std::max(0.0f, v) : 0.0f;
      patches.st.stored[c] = patches.valid[c] ? 0.02f : 0.0f;
      patches.d[c] = patches.valid[c] ? 0.005f : 0.0f;
    }
  }
  Time("patches", patches);
}

} // namespace

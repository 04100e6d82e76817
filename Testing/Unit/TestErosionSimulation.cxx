// Unit tests of the coupled erosion simulation and its brushes
// (terroir::terrain::ErosionSimulation). A step is checked against the core functions called by
// hand in the order ErosionSimulation.h documents; the dabs' weights w(r) = (1 + cos(pi r / R)) / 2
// are worked out by hand in the comments; the balances follow from conservation (closed domain:
// bed + suspended sediment changes only by the soil dabs, water only by the water dabs, rain and
// evaporation).
#include "ErosionSimulation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <stdexcept>
#include <vector>

namespace
{
using terroir::GridView;
namespace tr = terroir::terrain;

constexpr double kPi = 3.14159265358979323846;

/// A random bumpy terrain of nx x ny cells, spacing `d` metres, with `holes` no-data cells.
struct Terrain
{
  std::vector<float> z;
  std::vector<std::uint8_t> valid;
  GridView<float> view;
  Terrain(int nx, int ny, double d, unsigned seed, int holes = 0)
    : z(static_cast<std::size_t>(nx) * ny)
    , valid(z.size(), 1)
  {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 3.0f);
    for (int j = 0; j < ny; ++j)
    {
      for (int i = 0; i < nx; ++i)
      {
        z[static_cast<std::size_t>(j) * nx + i] = 100.0f + 0.8f * i + 0.3f * j + u(rng);
      }
    }
    for (int h = 0; h < holes; ++h)
    {
      valid[rng() % valid.size()] = 0;
    }
    view.data = z.data();
    view.nx = nx;
    view.ny = ny;
    view.dx = d;
    view.dy = d;
    view.valid = valid.data();
  }
};

bool SameBits(const std::vector<float>& a, const std::vector<float>& b)
{
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

/// Bed plus suspended sediment (m^3): what only the soil brush changes on a closed domain.
double Material(const tr::ErosionState& s)
{
  const tr::ErosionTotals t = tr::ErosionMeasure(s);
  return t.terrain + t.sediment;
}

TEST(TerroirErosionSimulationCore, StepIsTheCoreFunctionsInTheDocumentedOrder)
{
  const Terrain t(24, 20, 5.0, 7, 6);
  const std::size_t n = t.z.size();
  std::vector<float> factor(n);
  std::vector<float> density(n);
  for (std::size_t k = 0; k < n; ++k)
  {
    factor[k] = static_cast<float>(k % 5) / 4.0f;
    density[k] = static_cast<float>(k % 7) / 6.0f;
  }
  tr::ErosionSimulationParams p;
  p.thermalInterval = 2;
  p.rainRate = 2e-3;
  p.thermal.talusSoilDeg = 20.0;
  tr::ErosionSimulation sim(t.view, 0.03, factor, density.data());

  // By hand: the same state, the same calls.
  GridView<float> masked = t.view;
  tr::ErosionState s = tr::MakeErosionState(masked);
  for (std::size_t k = 0; k < n; ++k)
  {
    s.water[k] = t.valid[k] ? 0.03f : 0.0f;
  }
  GridView<float> dv = masked;
  std::vector<float> v0(n);
  for (std::size_t k = 0; k < n; ++k)
  {
    v0[k] = t.valid[k] ? density[k] : 0.0f;
  }
  dv.data = v0.data();
  tr::VegetationState veg = tr::MakeVegetationState(dv);
  s.erosionFactor.assign(n, 1.0f);
  s.talusFactor.assign(n, 1.0f);
  const std::vector<float> rain(n, static_cast<float>(p.rainRate));
  double eroded = 0.0;
  for (int step = 1; step <= 7; ++step)
  {
    sim.Step(p);
    tr::VegetationResistance(veg, p.vegetation, s.erosionFactor.data(), s.talusFactor.data());
    eroded += tr::ErosionHydraulicStep(s, p.hydraulic, rain.data(), factor.data()).eroded;
    tr::VegetationWater w;
    w.surface = s.water.data();
    w.surfaceResidue = s.waterResidue.data();
    tr::VegetationStep(veg, w, p.hydraulic.timeStep, p.vegetation);
    if (step % 2 == 0)
    {
      const std::vector<float> before = s.terrain;
      tr::ErosionThermalStep(s, p.thermal);
      tr::VegetationSlipDamage(veg, before.data(), s.terrain.data(), p.vegetation);
    }
  }
  EXPECT_EQ(sim.Steps(), 7);
  EXPECT_TRUE(SameBits(sim.State().terrain, s.terrain));
  EXPECT_TRUE(SameBits(sim.State().water, s.water));
  EXPECT_TRUE(SameBits(sim.State().sediment, s.sediment));
  EXPECT_TRUE(SameBits(sim.Vegetation().density, veg.density));
  EXPECT_TRUE(SameBits(sim.Vegetation().stored, veg.stored));
  EXPECT_EQ(sim.Volumes().eroded, eroded);
  EXPECT_GT(sim.Volumes().rain, 0.0);
}

TEST(TerroirErosionSimulationCore, WaterDabWeightsAndVolumeByHand)
{
  const Terrain t(11, 11, 2.0, 3);
  tr::ErosionSimulation sim(t.view, 0.0);
  // Radius 2 around cell (5, 5): the centre (w = 1), four cells at r = 1 (w = 1/2), four at
  // r = sqrt 2 (w = (1 + cos(pi sqrt2 / 2)) / 2); r = 2 and beyond get nothing.
  EXPECT_EQ(sim.Paint(tr::ErosionBrush::Water, 5.0, 5.0, 2.0, 0.2), 9);
  const double wDiag = 0.5 * (1.0 + std::cos(kPi * std::sqrt(2.0) / 2.0));
  const tr::ErosionState& s = sim.State();
  auto depth = [&](int i, int j)
  {
    const std::size_t k = static_cast<std::size_t>(j) * 11 + i;
    return static_cast<double>(s.water[k]) + s.waterResidue[k];
  };
  EXPECT_NEAR(depth(5, 5), 0.2, 1e-12);
  EXPECT_NEAR(depth(4, 5), 0.1, 1e-12);
  EXPECT_NEAR(depth(5, 6), 0.1, 1e-12);
  EXPECT_NEAR(depth(6, 6), 0.2 * wDiag, 1e-9);
  EXPECT_EQ(depth(7, 5), 0.0);
  EXPECT_EQ(depth(3, 3), 0.0);
  const double volume = 4.0 * 0.2 * (1.0 + 4.0 * 0.5 + 4.0 * wDiag); // area 4 m^2 a cell
  EXPECT_NEAR(sim.Volumes().brushWater, volume, 1e-12);
  EXPECT_NEAR(tr::ErosionMeasure(s).water, volume, 1e-9);
}

TEST(TerroirErosionSimulationCore, DabsAtTheEdgeAndOnNoDataCells)
{
  Terrain t(8, 6, 1.0, 5);
  t.valid[0] = 0; // cell (0, 0)
  tr::ErosionSimulation sim(t.view, 0.0);
  const float noData = sim.State().terrain[0];
  // Centre (0.5, 0) radius 1.2: cells (0,0) no data, (1,0) r = 0.5, (0,1) r = 1.118, (1,1)
  // r = 1.118, (2, 0) r = 1.5 out: three cells.
  EXPECT_EQ(sim.Paint(tr::ErosionBrush::Soil, 0.5, 0.0, 1.2, -0.4), 3);
  EXPECT_EQ(sim.State().terrain[0], noData);
  EXPECT_EQ(sim.State().terrainResidue[0], 0.0f);
  const double w05 = 0.5 * (1.0 + std::cos(kPi * 0.5 / 1.2));
  const double bed = static_cast<double>(sim.State().terrain[1]) + sim.State().terrainResidue[1];
  EXPECT_NEAR(bed, static_cast<double>(t.z[1]) - 0.4 * w05, 1e-9);
  EXPECT_LT(sim.Volumes().brushBed, 0.0);
}

TEST(TerroirErosionSimulationCore, RemovingWaterStopsAtDry)
{
  const Terrain t(9, 9, 3.0, 11);
  tr::ErosionSimulation sim(t.view, 0.05);
  const long long reached = sim.Paint(tr::ErosionBrush::Water, 4.0, 4.0, 1.5, -1.0);
  // r < 1.5: the centre, 4 at r = 1 and 4 at r = sqrt 2. The centre (w = 1) and the r = 1 cells
  // (w = 1/4) would lose more than their 0.05 m: they lose just that; the r = sqrt 2 cells lose
  // w = (1 + cos(pi sqrt2 / 1.5)) / 2 = 0.0083 m.
  EXPECT_EQ(reached, 9);
  const double w0 = static_cast<double>(0.05f); // the initial depth as stored
  const double wDiag = 0.5 * (1.0 + std::cos(kPi * std::sqrt(2.0) / 1.5));
  const double w1 = 0.5 * (1.0 + std::cos(kPi * 1.0 / 1.5));
  const tr::ErosionState& s = sim.State();
  EXPECT_EQ(s.water[4 * 9 + 4], 0.0f); // w = 1: all 0.05 m removed, no further
  EXPECT_EQ(s.water[4 * 9 + 5], 0.0f); // w1 = 0.25: 0.25 m > 0.05 m
  EXPECT_NEAR(s.water[5 * 9 + 5] + s.waterResidue[5 * 9 + 5], w0 - wDiag, 1e-9);
  const double removed = 9.0 * (w0 + 4.0 * w0 + 4.0 * wDiag);
  EXPECT_GT(w1, 0.05);
  EXPECT_NEAR(sim.Volumes().brushWater, -removed, 1e-9);
  EXPECT_NEAR(tr::ErosionMeasure(s).water, 81 * 9.0 * w0 - removed, 1e-9);
}

TEST(TerroirErosionSimulationCore, BalancesWithBrushesOnAClosedDomain)
{
  const Terrain t(32, 28, 4.0, 13, 10);
  tr::ErosionSimulation sim(t.view, 0.02);
  tr::ErosionSimulationParams p;
  p.rainRate = 1e-3;
  p.thermal.talusSoilDeg = 15.0;
  const double material0 = Material(sim.State());
  const double water0 = tr::ErosionMeasure(sim.State()).water;
  for (int step = 0; step < 120; ++step)
  {
    if (step % 30 == 5)
    {
      sim.Paint(tr::ErosionBrush::Soil, 10.3, 9.7, 4.0, 2.5);
      sim.Paint(tr::ErosionBrush::Water, 20.0, 14.0, 3.0, 0.5);
      sim.Paint(tr::ErosionBrush::Soil, 25.0, 20.0, 3.0, -1.5);
    }
    sim.Step(p);
  }
  const tr::ErosionVolumes& v = sim.Volumes();
  EXPECT_GT(v.eroded, 0.0);
  EXPECT_GT(v.brushBed, 0.0);
  EXPECT_NEAR(Material(sim.State()), material0 + v.brushBed, 1e-9 * material0);
  const double water = tr::ErosionMeasure(sim.State()).water;
  EXPECT_NEAR(water, water0 + v.brushWater + v.rain - v.evaporated, 1e-7 * (water0 + v.rain));
}

TEST(TerroirErosionSimulationCore, AVegetationDabStartsTheAutomaton)
{
  const Terrain t(10, 10, 2.0, 17);
  tr::ErosionSimulation sim(t.view, 0.05);
  EXPECT_FALSE(sim.HasVegetation());
  EXPECT_EQ(sim.Paint(tr::ErosionBrush::Vegetation, 4.0, 4.0, 2.0, 1.0), 9);
  ASSERT_TRUE(sim.HasVegetation());
  const std::vector<float>& v = sim.Vegetation().density;
  EXPECT_EQ(v[4 * 10 + 4], 1.0f);
  EXPECT_EQ(v[4 * 10 + 5], 0.5f);
  EXPECT_EQ(v[0], 0.0f);
  // A second dab toward 0.2 moves the centre to 0.2 and the r = 1 cells halfway: 0.35.
  sim.Paint(tr::ErosionBrush::Vegetation, 4.0, 4.0, 2.0, 0.2);
  EXPECT_FLOAT_EQ(v[4 * 10 + 4], 0.2f);
  EXPECT_FLOAT_EQ(v[5 * 10 + 4], 0.35f);
  // The automaton now runs on each step: the vegetated cells drink the surface water.
  const double water0 = tr::ErosionMeasure(sim.State()).water;
  sim.Step(tr::ErosionSimulationParams());
  EXPECT_LT(tr::ErosionMeasure(sim.State()).water, water0 - 1e-9);
  EXPECT_GT(tr::VegetationMeasure(sim.Vegetation()).stored, 0.0);
}

TEST(TerroirErosionSimulationCore, WeatherClosesTheWaterCycle)
{
  // Dunn's water cycle on a closed grid: what evaporates (eq. 2.6, raised 5e4 times for effect
  // as Dunn raised his) becomes vapour, the wind carries it, and it rains on the cold east
  // (-30 degC) where it exceeds the capacity; surface water + vapour + rain in flight stays
  // the same (float rounding), water did evaporate and rain did fall, and the rain fell where
  // it was cold.
  const Terrain t(20, 14, 10.0, 23);
  tr::ErosionSimulation sim(t.view, 0.05);
  std::vector<float> temperature(t.z.size());
  for (std::size_t k = 0; k < temperature.size(); ++k)
  {
    temperature[k] = (k % 20) > 13 ? -30.0f : 20.0f;
  }
  sim.SetTemperature(temperature);
  tr::ErosionSimulationParams p;
  p.weather = true;
  p.hydraulic.timeStep = 0.1; // 10 m cells: the vapour must cross 6 columns in 60 s
  p.evaporation.scale = 5e4;
  p.atmosphere.windStrength = 5.0;
  auto total = [&]()
  {
    double falling = 0.0;
    const std::vector<float>& f = sim.RainInFlight();
    for (float v : f)
    {
      falling += 100.0 * v; // 10 m cells
    }
    const double vapour =
      sim.HasWeather() ? tr::AtmosphereMeasure(sim.Atmosphere()).vapour : 0.0; // none yet
    return tr::ErosionMeasure(sim.State()).water + vapour + falling;
  };
  const double w0 = total();
  for (int step = 0; step < 600; ++step)
  {
    sim.Step(p);
  }
  ASSERT_TRUE(sim.HasWeather());
  const tr::ErosionVolumes& v = sim.Volumes();
  EXPECT_GT(v.evaporated, 1e-3 * w0);
  EXPECT_GT(v.weatherRain, 0.0);
  EXPECT_NEAR(total(), w0, 1e-6 * w0);
  // The rain fell on the cold columns: the vapour there is below the warm columns' (by area).
  double coldVapour = 0.0, warmVapour = 0.0;
  const std::vector<float>& q = sim.Atmosphere().vapour;
  for (std::size_t k = 0; k < q.size(); ++k)
  {
    ((k % 20) > 13 ? coldVapour : warmVapour) += q[k];
  }
  EXPECT_LT(coldVapour / 6.0, 0.5 * warmVapour / 14.0);
}

TEST(TerroirErosionSimulationCore, WeatherReplacesWeissEvaporation)
{
  // With weather on and its evaporation scaled to 0, no water leaves (Weiss's K_e is off);
  // without weather K_e takes (1 - K_e dt) of the water every step.
  const Terrain t(12, 10, 5.0, 29);
  tr::ErosionSimulation with(t.view, 0.05), without(t.view, 0.05);
  tr::ErosionSimulationParams p;
  const double w0 = tr::ErosionMeasure(with.State()).water;
  for (int step = 0; step < 50; ++step)
  {
    without.Step(p);
  }
  p.weather = true;
  p.evaporation.scale = 0.0;
  for (int step = 0; step < 50; ++step)
  {
    with.Step(p);
  }
  EXPECT_NEAR(tr::ErosionMeasure(with.State()).water, w0, 1e-7 * w0);
  EXPECT_NEAR(tr::ErosionMeasure(without.State()).water, w0 * std::pow(1.0 - 5e-5, 50), 1e-6 * w0);
  EXPECT_EQ(with.Volumes().evaporated, 0.0);
}

TEST(TerroirErosionSimulationCore, RainRatesPerCellAddToTheUniformRain)
{
  // Rain on the western half only (2e-3 m/s) plus 1e-3 m/s everywhere, no evaporation, a closed
  // grid: after n steps of dt the water is n dt (1e-3 x all cells + 2e-3 x western cells) x area,
  // and the rain volume says the same.
  const Terrain t(10, 8, 2.0, 31);
  tr::ErosionSimulation sim(t.view, 0.0);
  std::vector<float> rates(t.z.size(), 0.0f);
  for (std::size_t k = 0; k < rates.size(); ++k)
  {
    rates[k] = (k % 10) < 5 ? 2e-3f : 0.0f;
  }
  sim.SetRainRates(rates);
  tr::ErosionSimulationParams p;
  p.hydraulic.evaporation = 0.0;
  p.rainRate = 1e-3;
  for (int step = 0; step < 20; ++step)
  {
    sim.Step(p);
  }
  const double perStep = 0.01 * 4.0 * (80 * 1e-3 + 40 * static_cast<double>(2e-3f));
  EXPECT_NEAR(sim.Volumes().rain, 20 * perStep, 1e-6 * 20 * perStep);
  EXPECT_NEAR(tr::ErosionMeasure(sim.State()).water, 20 * perStep, 1e-6 * 20 * perStep);
  std::vector<float> bad(rates);
  bad[3] = -1.0f;
  EXPECT_THROW(sim.SetRainRates(bad), std::invalid_argument);
  EXPECT_THROW(sim.SetRainRates(std::vector<float>(7, 0.0f)), std::invalid_argument);
}

TEST(TerroirErosionSimulationCore, BadArgumentsAreRefused)
{
  const Terrain t(6, 6, 1.0, 19);
  EXPECT_THROW(tr::ErosionSimulation(t.view, -0.1), std::invalid_argument);
  EXPECT_THROW(
    tr::ErosionSimulation(t.view, 0.0, std::vector<float>(5, 1.0f)), std::invalid_argument);
  tr::ErosionSimulation sim(t.view, 0.0);
  EXPECT_THROW(sim.Paint(tr::ErosionBrush::Water, 2.0, 2.0, 0.0, 1.0), std::invalid_argument);
  EXPECT_THROW(sim.Paint(tr::ErosionBrush::Water, NAN, 2.0, 1.0, 1.0), std::invalid_argument);
  EXPECT_THROW(sim.Paint(tr::ErosionBrush::Soil, 2.0, 2.0, 1.0, INFINITY), std::invalid_argument);
  tr::ErosionSimulationParams p;
  p.rainRate = -1.0;
  EXPECT_THROW(sim.Step(p), std::invalid_argument);
  p.rainRate = 0.0;
  p.thermalInterval = -2;
  EXPECT_THROW(sim.Step(p), std::invalid_argument);
  EXPECT_EQ(sim.Steps(), 0);
}

} // namespace

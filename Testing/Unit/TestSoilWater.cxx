// Unit tests of the soil-water core (no VTK, no GL); expected values worked out by hand.
#include "SoilWater.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

namespace
{
using terroir::terrain::AbsorbedRainLong2016;
using terroir::terrain::ApplySlopeRule;
using terroir::terrain::FAOInfiltrationRate;
using terroir::terrain::MonthlyRain;
using terroir::terrain::SoilHumidityLong2016;

MonthlyRain UniformRain(float quantity, float intensity)
{
  MonthlyRain rain{};
  for (int m = 0; m < 12; ++m)
  {
    rain.quantityMm[m] = quantity;
    rain.intensityMmPerHour[m] = intensity;
  }
  return rain;
}

TEST(TerroirSoilWaterCore, CappedEquationAtChosenValues)
{
  // Soil absorbs 2 mm/h, rain falls at 8 mm/h: a quarter of the 80 mm soaks in.
  EXPECT_FLOAT_EQ(AbsorbedRainLong2016(2.0f, 80.0f, 8.0f), 20.0f);
  // Soil faster than the rain: everything soaks in, never more than falls (10/5 = 2 capped to 1).
  EXPECT_FLOAT_EQ(AbsorbedRainLong2016(10.0f, 60.0f, 5.0f), 60.0f);
  // Exactly as fast: all of it.
  EXPECT_FLOAT_EQ(AbsorbedRainLong2016(4.0f, 33.0f, 4.0f), 33.0f);
  // Impermeable soil (the slope rule's 0) absorbs nothing.
  EXPECT_FLOAT_EQ(AbsorbedRainLong2016(0.0f, 50.0f, 3.0f), 0.0f);
  // A dry month absorbs nothing, even with no intensity given.
  EXPECT_FLOAT_EQ(AbsorbedRainLong2016(7.0f, 0.0f, 0.0f), 0.0f);
  // 1.5 / 6 = 0.25 of 12 mm.
  EXPECT_FLOAT_EQ(AbsorbedRainLong2016(1.5f, 12.0f, 6.0f), 3.0f);
}

TEST(TerroirSoilWaterCore, SoilHumidityRowsMatchTheEquation)
{
  MonthlyRain rain = UniformRain(0.0f, 1.0f);
  const float q[12] = { 80, 40, 60, 0, 20, 10, 5, 0, 30, 90, 120, 100 };
  const float i[12] = { 8, 4, 2, 1, 10, 20, 5, 3, 6, 9, 12, 2 };
  for (int m = 0; m < 12; ++m)
  {
    rain.quantityMm[m] = q[m];
    rain.intensityMmPerHour[m] = i[m];
  }
  const std::vector<float> rate = { 4.0f, 0.0f, 100.0f };
  std::vector<float> sh(36), swh(36), sw(36);
  SoilHumidityLong2016(rate.data(), nullptr, rain, sh.data(), swh.data(), sw.data(), 0, 3);
  // Cell 0 (4 mm/h): Jan 4/8 -> 40, Feb 4/4 -> 40, Mar capped -> 60, Apr dry -> 0,
  // May 4/10 -> 8, Jun 4/20 -> 2, Jul 4/5 -> 4, Aug 0, Sep 4/6 -> 20, Oct 4/9 -> 40,
  // Nov 4/12 -> 40, Dec capped -> 100.
  const float expected0[12] = { 40, 40, 60, 0, 8, 2, 4, 0, 20, 40, 40, 100 };
  for (int m = 0; m < 12; ++m)
  {
    EXPECT_NEAR(sh[m], expected0[m], 1e-4) << "month " << m + 1;
    EXPECT_NEAR(sw[m], q[m] - expected0[m], 1e-4) << "month " << m + 1;
    EXPECT_EQ(sh[12 + m], 0.0f) << "impermeable cell absorbs nothing";
    EXPECT_EQ(sw[12 + m], q[m]) << "impermeable cell: all rain stands";
    EXPECT_EQ(sh[24 + m], q[m]) << "fast soil absorbs all the rain, never more";
    EXPECT_EQ(sw[24 + m], 0.0f);
  }
}

TEST(TerroirSoilWaterCore, WeightedAverageAcrossTheYearBoundary)
{
  // A soil that absorbs everything: S_h = R_q. S_wh(Jan) = Jan/2 + Dec/3 + Nov/6.
  MonthlyRain rain = UniformRain(0.0f, 1.0f);
  const float q[12] = { 12, 24, 0, 6, 0, 0, 0, 0, 0, 0, 6, 18 };
  for (int m = 0; m < 12; ++m)
  {
    rain.quantityMm[m] = q[m];
  }
  const float rate = 1000.0f;
  float swh[12];
  SoilHumidityLong2016(&rate, nullptr, rain, nullptr, swh, nullptr, 0, 1);
  EXPECT_NEAR(swh[0], 6.0f + 6.0f + 1.0f, 1e-5);  // Jan: 12/2 + 18/3 + 6/6
  EXPECT_NEAR(swh[1], 12.0f + 4.0f + 3.0f, 1e-5); // Feb: 24/2 + 12/3 + 18/6
  EXPECT_NEAR(swh[2], 0.0f + 8.0f + 2.0f, 1e-5);  // Mar: 0 + 24/3 + 12/6
  EXPECT_NEAR(swh[3], 3.0f + 0.0f + 4.0f, 1e-5);  // Apr: 6/2 + 0 + 24/6
  EXPECT_NEAR(swh[10], 3.0f, 1e-5);               // Nov: 6/2 + 0 + 0
  EXPECT_NEAR(swh[11], 9.0f + 2.0f, 1e-5);        // Dec: 18/2 + 6/3 + 0
  // The weights sum to one: a constant year stays constant.
  SoilHumidityLong2016(&rate, nullptr, UniformRain(30.0f, 1.0f), nullptr, swh, nullptr, 0, 1);
  for (int m = 0; m < 12; ++m)
  {
    EXPECT_NEAR(swh[m], 30.0f, 1e-4) << "month " << m + 1;
  }
}

TEST(TerroirSoilWaterCore, NoDataCellsGetNaN)
{
  const MonthlyRain rain = UniformRain(50.0f, 5.0f);
  const std::vector<float> rate = { 3.0f, std::nanf(""), 3.0f };
  const std::vector<std::uint8_t> valid = { 1, 1, 0 };
  std::vector<float> sh(36), swh(36), sw(36);
  SoilHumidityLong2016(rate.data(), valid.data(), rain, sh.data(), swh.data(), sw.data(), 0, 3);
  for (int m = 0; m < 12; ++m)
  {
    EXPECT_NEAR(sh[m], 30.0f, 1e-5);
    EXPECT_NEAR(swh[m], 30.0f, 1e-4);
    EXPECT_NEAR(sw[m], 20.0f, 1e-5);
    for (int cell = 1; cell < 3; ++cell)
    {
      EXPECT_TRUE(std::isnan(sh[12 * cell + m]));
      EXPECT_TRUE(std::isnan(swh[12 * cell + m]));
      EXPECT_TRUE(std::isnan(sw[12 * cell + m]));
    }
  }
}

TEST(TerroirSoilWaterCore, FAOTableMidPoints)
{
  // FAO Training Manual 5, Annex 2: sandy loam 20-30, loam 10-20, clay loam 5-10, clay 1-5,
  // sand > 30 (its bound).
  EXPECT_EQ(FAOInfiltrationRate(1), 30.0);
  EXPECT_EQ(FAOInfiltrationRate(2), 25.0);
  EXPECT_EQ(FAOInfiltrationRate(3), 15.0);
  EXPECT_EQ(FAOInfiltrationRate(4), 7.5);
  EXPECT_EQ(FAOInfiltrationRate(5), 3.0);
  EXPECT_TRUE(std::isnan(FAOInfiltrationRate(0)));
  EXPECT_TRUE(std::isnan(FAOInfiltrationRate(6)));
}

TEST(TerroirSoilWaterCore, SlopeRuleZeroesSteepCellsOnly)
{
  const std::vector<float> slope = { 10.0f, 30.0f, 30.5f, 60.0f, std::nanf("") };
  std::vector<float> rate = { 5.0f, 5.0f, 5.0f, 5.0f, 5.0f };
  ApplySlopeRule(slope.data(), 30.0, rate.data(), 0, rate.size());
  EXPECT_EQ(rate[0], 5.0f);
  EXPECT_EQ(rate[1], 5.0f) << "exactly at the threshold is not steeper";
  EXPECT_EQ(rate[2], 0.0f);
  EXPECT_EQ(rate[3], 0.0f);
  EXPECT_EQ(rate[4], 5.0f) << "no-data slope leaves the cell alone";
}

} // namespace

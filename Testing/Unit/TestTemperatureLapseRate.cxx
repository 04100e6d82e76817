// Unit tests of the temperature core (no VTK, no GL); expected values worked out by hand.
#include "TemperatureLapseRate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

namespace
{
using terroir::GridView;
using terroir::terrain::SeaLevelTemperaturesFromExtremes;
using terroir::terrain::TemperatureLapseRateRows;

TEST(TerroirTemperatureCore, NorthernDefaultsInterpolateAroundTheYear)
{
  double t[12];
  ASSERT_TRUE(SeaLevelTemperaturesFromExtremes(2.0, 20.0, 1, 7, t));
  // 18 degrees over 6 months: +3 per month up to July, -3 per month back to January.
  const double expected[12] = { 2, 5, 8, 11, 14, 17, 20, 17, 14, 11, 8, 5 };
  for (int m = 0; m < 12; ++m)
  {
    EXPECT_NEAR(t[m], expected[m], 1e-12) << "month " << m + 1;
  }
}

TEST(TerroirTemperatureCore, SouthernHemisphereSwapsTheSeasons)
{
  double t[12];
  ASSERT_TRUE(SeaLevelTemperaturesFromExtremes(2.0, 20.0, 7, 1, t));
  const double expected[12] = { 20, 17, 14, 11, 8, 5, 2, 5, 8, 11, 14, 17 };
  for (int m = 0; m < 12; ++m)
  {
    EXPECT_NEAR(t[m], expected[m], 1e-12) << "month " << m + 1;
  }
}

TEST(TerroirTemperatureCore, UnevenSeasons)
{
  double t[12];
  // Coldest January (0), warmest April (9): 3 months up (+3), 9 months down (-1).
  ASSERT_TRUE(SeaLevelTemperaturesFromExtremes(0.0, 9.0, 1, 4, t));
  const double expected[12] = { 0, 3, 6, 9, 8, 7, 6, 5, 4, 3, 2, 1 };
  for (int m = 0; m < 12; ++m)
  {
    EXPECT_NEAR(t[m], expected[m], 1e-12) << "month " << m + 1;
  }
  // Coldest December, warmest June (wraps the year end).
  ASSERT_TRUE(SeaLevelTemperaturesFromExtremes(-6.0, 18.0, 12, 6, t));
  EXPECT_NEAR(t[11], -6.0, 1e-12);
  EXPECT_NEAR(t[0], -2.0, 1e-12);
  EXPECT_NEAR(t[5], 18.0, 1e-12);
  EXPECT_NEAR(t[8], 6.0, 1e-12);
}

TEST(TerroirTemperatureCore, BadMonthsAreRejected)
{
  double t[12] = {};
  EXPECT_FALSE(SeaLevelTemperaturesFromExtremes(2.0, 20.0, 3, 3, t));
  EXPECT_FALSE(SeaLevelTemperaturesFromExtremes(2.0, 20.0, 0, 7, t));
  EXPECT_FALSE(SeaLevelTemperaturesFromExtremes(2.0, 20.0, 1, 13, t));
}

TEST(TerroirTemperatureCore, LapseRateAtChosenAltitudes)
{
  // Elevations 0, 1000, 2500 m, -100 m, and a no-data cell (masked) and a NaN cell.
  std::vector<float> z = { 0.0f, 1000.0f, 2500.0f, -100.0f, 500.0f, NAN };
  std::vector<std::uint8_t> mask = { 1, 1, 1, 1, 0, 1 };
  GridView<float> v;
  v.data = z.data();
  v.nx = 3;
  v.ny = 2;
  v.valid = mask.data();
  const double sea[12] = { 2, 5, 8, 11, 14, 17, 20, 17, 14, 11, 8, 5 };
  std::vector<float> out(12 * z.size());
  TemperatureLapseRateRows(v, sea, 6.4, out.data(), 0, 2);
  EXPECT_NEAR(out[12 * 0 + 0], 2.0, 1e-5);   // Jan at sea level
  EXPECT_NEAR(out[12 * 1 + 0], -4.4, 1e-5);  // Jan at 1000 m: 2 - 6.4
  EXPECT_NEAR(out[12 * 2 + 6], 4.0, 1e-5);   // Jul at 2500 m: 20 - 16
  EXPECT_NEAR(out[12 * 3 + 11], 5.64, 1e-5); // Dec at -100 m: 5 + 0.64
  for (int m = 0; m < 12; ++m)
  {
    EXPECT_TRUE(std::isnan(out[12 * 4 + m]));
    EXPECT_TRUE(std::isnan(out[12 * 5 + m]));
  }
}

TEST(TerroirTemperatureCore, TwelveGivenValuesAndOtherLapseRate)
{
  std::vector<double> z = { 2000.0 };
  GridView<double> v;
  v.data = z.data();
  v.nx = v.ny = 1;
  const double sea[12] = { -1, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10 };
  std::vector<double> out(12);
  TemperatureLapseRateRows(v, sea, 5.0, out.data(), 0, 1);
  for (int m = 0; m < 12; ++m)
  {
    EXPECT_NEAR(out[m], sea[m] - 10.0, 1e-12);
  }
}

} // namespace

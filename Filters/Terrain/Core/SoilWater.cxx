#include "SoilWater.h"

#include <algorithm>

#include <cmath>
#include <limits>

namespace terroir
{
namespace terrain
{

double FAOInfiltrationRate(int soilType)
{
  switch (soilType)
  {
    case static_cast<int>(SoilType::Sand):
      return 30.0;
    case static_cast<int>(SoilType::SandyLoam):
      return 25.0;
    case static_cast<int>(SoilType::Loam):
      return 15.0;
    case static_cast<int>(SoilType::ClayLoam):
      return 7.5;
    case static_cast<int>(SoilType::Clay):
      return 3.0;
    default:
      return std::numeric_limits<double>::quiet_NaN();
  }
}

SoilHumidityMonthConstants SoilHumidityLong2016Constants(const MonthlyRain& rain)
{
  SoilHumidityMonthConstants c;
  for (int m = 0; m < 12; ++m)
  {
    const bool rains = rain.quantityMm[m] > 0.0f;
    c.quantity[m] = rains ? rain.quantityMm[m] : 0.0f;
    c.inverseIntensity[m] = rains ? 1.0f / rain.intensityMmPerHour[m] : 0.0f;
  }
  return c;
}

void SoilHumidityLong2016(const float* infiltration,
  const std::uint8_t* valid,
  const MonthlyRain& rain,
  float* humidity,
  float* weighted,
  float* standing,
  std::size_t begin,
  std::size_t end)
{
  const float nan = std::numeric_limits<float>::quiet_NaN();
  // Branch-free form of AbsorbedRainLong2016, so that the month loops vectorise: a dry month
  // gets q = 0 and a zero reciprocal intensity (0 whatever the rate); a no-data cell a NaN rate,
  // which every output carries ((NaN > 1) is false). Shaders/SoilHumidity.comp does the same.
  // Local copies: the month loops vectorise over arrays the compiler sees are not aliased.
  const SoilHumidityMonthConstants constants = SoilHumidityLong2016Constants(rain);
  float q[12];
  float inverse[12];
  std::copy(constants.quantity, constants.quantity + 12, q);
  std::copy(constants.inverseIntensity, constants.inverseIntensity + 12, inverse);
  for (std::size_t k = begin; k < end; ++k)
  {
    const float rate = (!valid || valid[k] != 0) ? infiltration[k] : nan;
    float sh[12];
    for (int m = 0; m < 12; ++m)
    {
      const float ratio = rate * inverse[m];
      sh[m] = (ratio > 1.0f ? 1.0f : ratio) * q[m];
    }
    if (humidity)
    {
      for (int m = 0; m < 12; ++m)
      {
        humidity[12 * k + m] = sh[m];
      }
    }
    if (weighted)
    {
      // Same operation order as Shaders/SoilHumidity.comp.
      for (int m = 0; m < 12; ++m)
      {
        const float a = sh[m];
        const float b = sh[(m + 11) % 12];
        const float c = sh[(m + 10) % 12];
        weighted[12 * k + m] = a * 0.5f + b * (1.0f / 3.0f) + c * (1.0f / 6.0f);
      }
    }
    if (standing)
    {
      for (int m = 0; m < 12; ++m)
      {
        standing[12 * k + m] = q[m] - sh[m];
      }
    }
  }
}

void ApplySlopeRule(const float* slopeDegrees,
  double thresholdDegrees,
  float* rate,
  std::size_t begin,
  std::size_t end)
{
  const float threshold = static_cast<float>(thresholdDegrees);
  for (std::size_t k = begin; k < end; ++k)
  {
    if (slopeDegrees[k] > threshold)
    {
      rate[k] = 0.0f;
    }
  }
}

} // namespace terrain
} // namespace terroir

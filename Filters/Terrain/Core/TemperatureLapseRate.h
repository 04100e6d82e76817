/**
 * @file TemperatureLapseRate.h
 * @brief Monthly air temperature from sea-level temperatures and a constant lapse rate.
 *
 * Plain C++ (no VTK, no GL): the reference for vtkTerroirTemperature's CPU kernel and
 * Shaders/Temperature.comp.
 *
 * Model (Long (2016), eq. 3.4): the sea-level
 * temperature of each month is either given (12 values) or built from the temperatures of
 * the coldest and warmest months, interpolated linearly around the year (coldest -> warmest
 * -> coldest). At elevation h (metres) the temperature of month m is
 * \f[ T(m, h) = T_{sea}(m) - \Gamma\, h / 1000 \f]
 * with the lapse rate \f$\Gamma\f$ in °C per km (6.4 by default in vtkTerroirTemperature,
 * close to the ICAO standard atmosphere's 6.5 K/km).
 *
 * @par Correctness
 * Testing/Unit/TestTemperatureLapseRate.cxx (temperatures worked out by hand).
 */
#ifndef terroir_terrain_TemperatureLapseRate_h
#define terroir_terrain_TemperatureLapseRate_h

#include "GridView.h"

namespace terroir
{
namespace terrain
{

/**
 * @brief Sea-level temperature of the 12 months (index 0 = January) from the coldest and
 * warmest months, linear in the month number around the year.
 * @param[in] coldest, warmest   sea-level temperatures, °C
 * @param[in] coldestMonth, warmestMonth  1..12, different
 * @param[out] monthly  12 values, °C
 * @return false (monthly untouched) when a month is out of range or both are equal
 *
 * With d = (warmest - coldest + 12) mod 12 months from the coldest to the warmest month and
 * k = (m - coldestMonth + 12) mod 12: T = Tc + (Tw - Tc) k / d for k <= d, else
 * T = Tw + (Tc - Tw) (k - d) / (12 - d).
 */
bool SeaLevelTemperaturesFromExtremes(double coldest,
  double warmest,
  int coldestMonth,
  int warmestMonth,
  double monthly[12]);

/**
 * @brief T(m, h) = seaLevel[m] - lapseRate * h / 1000 for rows [row0, row1) of `view`.
 * @param[in] view      elevation (metres), optional validity mask
 * @param[in] seaLevel  12 sea-level temperatures, °C, January first
 * @param[in] lapseRate °C per km
 * @param[out] temperature  12 * nx * ny values (12 consecutive months per cell); NaN for
 *                          no-data cells (mask 0 or NaN elevation)
 * Instantiated for float and double.
 */
template<typename T>
void TemperatureLapseRateRows(const GridView<T>& view,
  const double seaLevel[12],
  double lapseRate,
  T* temperature,
  int row0,
  int row1);

} // namespace terrain
} // namespace terroir

#endif

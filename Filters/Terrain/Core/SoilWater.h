/**
 * @file SoilWater.h
 * @brief Long (2016)'s soil-water model: infiltration rates, absorbed rain (soil humidity),
 * its moving weighted average, standing water.
 *
 * Plain C++ (no VTK, no GL): the reference for vtkTerroirInfiltration, vtkTerroirSoilHumidity's
 * CPU kernel and Shaders/SoilHumidity.comp.
 *
 * Model (Long (2016), §3.2, as the Terroir issue states it). Month m brings R_q(m) mm of rain at a
 * mean intensity R_i(m) mm/h; a soil that absorbs S_ir mm/h takes in
 * \f[ S_h(m) = \min\left(\frac{S_{ir}}{R_i(m)}, 1\right) R_q(m) \f]
 * (Long (2016)'s equation 3.5, capped so that the soil never absorbs more rain than falls); the
 * rest, \f$R_q(m) - S_h(m)\f$, stands on the surface and feeds the water-flow simulation. Plants
 * feel the recent months too:
 * \f[ S_{wh}(m) = \tfrac12 S_h(m) + \tfrac13 S_h(m-1) + \tfrac16 S_h(m-2) \f]
 * with December and November before January (the year is taken as periodic).
 *
 * Infiltration rates of soil types: FAO, Irrigation Water Management Training Manual 5
 * (Brouwer, Prins, Kay, Heibloem 1988), Annex 2 "basic infiltration rate": sand > 30,
 * sandy loam 20-30, loam 10-20, clay loam 5-10, clay 1-5 mm/h.
 *
 * @par Correctness
 * Testing/Unit/TestSoilWater.cxx (the capped equation at hand-chosen values, the weighted
 * average across the year boundary, the FAO table, the slope rule).
 */
#ifndef terroir_terrain_SoilWater_h
#define terroir_terrain_SoilWater_h

#include <cstddef>
#include <cstdint>

namespace terroir
{
namespace terrain
{

/// Soil types of a soil-type raster (codes 1..5); any other code leaves a cell unpainted.
enum class SoilType : int
{
  Sand = 1,
  SandyLoam = 2,
  Loam = 3,
  ClayLoam = 4,
  Clay = 5
};

/**
 * @brief Default infiltration rate of a FAO soil type, mm/h: the mid-point of its range
 * (sandy loam 25, loam 15, clay loam 7.5, clay 3); sand, whose range has no upper bound
 * ("> 30"), gets its bound, 30.
 * @return the rate, or NaN for a code outside 1..5
 */
double FAOInfiltrationRate(int soilType);

/**
 * @brief Rain a soil absorbs in a month, mm (Long (2016)'s equation 3.5, capped):
 * min(infiltration / intensity, 1) * quantity. A month without rain (quantity 0) absorbs 0
 * whatever its intensity.
 * @pre infiltration >= 0, quantity >= 0, intensity > 0 when quantity > 0
 */
inline float AbsorbedRainLong2016(float infiltration, float quantity, float intensity)
{
  if (!(quantity > 0.0f))
  {
    return 0.0f;
  }
  const float ratio = infiltration / intensity;
  return (ratio < 1.0f ? ratio : 1.0f) * quantity;
}

/// Monthly climate the soil-water model reads, January first.
struct MonthlyRain
{
  float quantityMm[12];         ///< R_q, mm per month, >= 0
  float intensityMmPerHour[12]; ///< R_i, mm/h, > 0 where R_q > 0
};

/// The per-month constants of SoilHumidityLong2016: a dry month gets quantity 0 and a zero
/// reciprocal intensity (0 whatever the rate), so that the month loops need no branch. The CPU
/// kernel and Shaders/SoilHumidity.comp (through vtkTerroirSoilHumidity) both use these.
struct SoilHumidityMonthConstants
{
  float quantity[12];
  float inverseIntensity[12];
};
SoilHumidityMonthConstants SoilHumidityLong2016Constants(const MonthlyRain& rain);

/**
 * @brief Soil humidity, its weighted average and standing water of cells [begin, end).
 * @param[in] infiltration  S_ir per cell, mm/h; NaN marks a no-data cell
 * @param[in] valid         optional mask (1 valid), may be null
 * @param[in] rain          the 12 months of rain
 * @param[out] humidity, weighted, standing  12 values per cell (months consecutive, January
 *   first), mm: S_h, S_wh, R_q - S_h; NaN on no-data cells. Any of them may be null.
 * @post standing + humidity == quantity (to rounding), 0 <= humidity <= quantity.
 * @correctness TestSoilWater.SoilHumidityRowsMatchTheEquation, TestSoilWater.WeightedAverage*
 */
void SoilHumidityLong2016(const float* infiltration,
  const std::uint8_t* valid,
  const MonthlyRain& rain,
  float* humidity,
  float* weighted,
  float* standing,
  std::size_t begin,
  std::size_t end);

/**
 * @brief The slope rule: cells steeper than `thresholdDegrees` absorb nothing (rate 0).
 * Cells whose slope is NaN (no data) are left as they are.
 */
void ApplySlopeRule(const float* slopeDegrees,
  double thresholdDegrees,
  float* rate,
  std::size_t begin,
  std::size_t end);

} // namespace terrain
} // namespace terroir

#endif

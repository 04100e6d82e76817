/**
 * @file SolarIllumination.h
 * @brief Sun steps over a day (positions, weights, clear-sky beam) and their accumulation into
 *        hours of direct sun and direct-beam energy per cell.
 *
 * Plain C++ (no VTK, no GL): the reference for vtkTerroirSolarIllumination's CPU kernel and
 * for Shaders/SolarIllumination.comp.
 *
 * A day is integrated over the 24 hours centred on mean solar noon at the terrain's longitude
 * (12:00 - longitude / 15 h UTC), in steps of `stepMinutes` (the last one shorter when the
 * step does not divide the day), each evaluated at its midpoint. For every step the sun's
 * position comes from SolarPositionNREL2004 (true azimuth, refracted elevation); its grid
 * azimuth is the true azimuth minus the bearing of grid north (the meridian convergence, or
 * the user's terrain orientation). A cell is lit at a step when the sun is above the
 * horizontal plane and tan(sun elevation) exceeds its horizon tangent in the sun's direction
 * (ShadowHorizon.h): the horizon never counts below level, because the terrain beyond the
 * DEM (where a falling slope leads) is unknown; the few minutes a summit would see a sun just
 * below level are given up. Then the cell gains the step's hours, and
 * beam * hours * max(0, n . s) watt-hours per m^2, with n the surface normal and s the unit
 * vector to the sun (both in the grid frame).
 *
 * Clear-sky direct beam (normal incidence), after Campbell & Norman (1998), eq. 11.11:
 * \f[ S_b = \frac{S_0}{R^2}\, \tau^{m}, \qquad m = \frac{p}{p_0}\, m_r(Z) \f]
 * with S0 = 1361 W/m^2 (Kopp & Lean 2011), R the Earth-sun distance (AU), tau the atmospheric
 * transmittance (0.7 by default: a clear day), p/p0 = exp(-z/8200) for the terrain's mean
 * elevation z in metres (Campbell & Norman eq. 3.7) and m_r the relative optical air mass of
 * Kasten & Young (1989): 1 / (cos Z + 0.50572 (96.07995 - Z)^-1.6364), Z in degrees. The beam
 * is zero when the sun's centre is below the astronomical horizon (elevation <= 0).
 *
 * @par References
 * Campbell, G. S. and Norman, J. M. (1998). An Introduction to Environmental Biophysics, 2nd
 * ed., Springer, ch. 11. doi:10.1007/978-1-4612-1626-1.
 * Kasten, F. and Young, A. T. (1989). Revised optical air mass tables and approximation
 * formula. Applied Optics 28(22), 4735-4738. doi:10.1364/AO.28.004735.
 * Kopp, G. and Lean, J. L. (2011). A new, lower value of total solar irradiance. Geophysical
 * Research Letters 38, L01706. doi:10.1029/2010GL045777.
 *
 * @par Correctness
 * Testing/Unit/TestSolarIllumination.cxx: on a flat plane the lit hours equal the day length
 * (24/pi) arccos(-tan(lat) tan(decl)) and, with tau = 1, the energy equals the daily
 * extraterrestrial radiation on a horizontal surface (FAO-56 eq. 21); the air mass against
 * Kasten & Young's table; a wall's shadow; the sector lookup.
 */
#ifndef terroir_terrain_SolarIllumination_h
#define terroir_terrain_SolarIllumination_h

#include "GridView.h"
#include "ShadowHorizon.h"
#include "SolarPosition.h"

#include <string>
#include <vector>

namespace terroir
{
namespace terrain
{

/// Solar constant, W/m^2 (Kopp & Lean 2011).
constexpr double kSolarConstant = 1361.0;

/// One sun position and what a lit cell gains from it.
struct SunStep
{
  double utcHours = 0.0;               ///< hours after 00:00 UTC of the date (may be < 0 or >= 24)
  double azimuthDeg = 0.0;             ///< true azimuth, clockwise from true north
  double elevationDeg = 0.0;           ///< topocentric elevation (refracted when asked)
  double gridAzimuthDeg = 0.0;         ///< azimuth clockwise from grid north
  float tanElevation = 0.0f;           ///< tan(elevation); 1e30 at the zenith
  float sun[3] = { 0.0f, 0.0f, 1.0f }; ///< unit vector to the sun, grid frame (x east, z up)
  SectorLookup sectors;                ///< horizon-map planes for gridAzimuthDeg
  MarchDirection march;                ///< ray-march direction for gridAzimuthDeg
  float hours = 0.0f;                  ///< hours a lit cell gains
  float energy = 0.0f;                 ///< Wh/m^2 a lit cell gains per unit cos(incidence)
  int slot = 0;                        ///< output component (month index in Monthly mode)
  int month = 1;                       ///< date of the step (for the field data)
  int day = 1;
};

/// Where the sun is seen from, in which frame, and the beam model.
struct SunFrame
{
  Observer observer;             ///< latitude, longitude, elevation, refraction settings
  double gridNorthBearing = 0.0; ///< bearing of grid north clockwise from true north, degrees
  double dx = 1.0;               ///< grid spacings, metres (for the march directions)
  double dy = 1.0;
  int sectors = 64;            ///< horizon-map sectors
  double transmittance = 0.7;  ///< clear-sky atmospheric transmittance tau, (0, 1]
  double meanElevationM = 0.0; ///< for the pressure ratio of the air mass
};

/// Kasten & Young (1989) relative optical air mass at zenith angle `zenithDeg` (< 96.07995).
double RelativeAirMassKastenYoung1989(double zenithDeg);

/// Clear-sky direct-beam irradiance at normal incidence, W/m^2 (see the file comment); 0 when
/// elevationDeg <= 0.
double ClearSkyBeamCampbellNorman1998(double elevationDeg,
  double earthSunDistanceAU,
  double transmittance,
  double meanElevationM);

/// A step for the sun at (true) azimuth/elevation: frame conversions and lookups filled in;
/// hours, energy and slot left to the caller.
SunStep MakeSunStep(double azimuthDeg, double elevationDeg, const SunFrame& frame);

/**
 * @brief The steps of one day: the 24 h centred on mean solar noon of year-month-day.
 * @param stepMinutes  > 0 and <= 1440
 * @param slot  written into every step
 * @return ceil(1440 / stepMinutes) steps with hours = step width in hours and energy = beam
 *         (W/m^2) times that width
 * @pre IsValidDate(year, month, day)
 */
std::vector<SunStep> DaySunSteps(int year,
  int month,
  int day,
  double stepMinutes,
  int slot,
  const SunFrame& frame);

/// Where the lit/shadow answer of each step comes from.
template<typename T>
struct ShadowSource
{
  const T* map = nullptr; ///< horizon map (HorizonMapSectors), or nullptr: ray marching
  bool refine = false;    ///< with a map: ray-march where the sun lies between the horizons
                          ///< of the two sectors around it (their interpolation is a guess)
  float curvature = 0.0f; ///< CurvatureCoefficient(...)
  T zMax = T(0);          ///< largest valid elevation (the ray march's early exit)
};

/**
 * @brief Adds the steps' hours and energy to cells [cell0, cell1) (row-major indices).
 *
 * Per cell and step: lit when tan(elevation) > 0 and tan(elevation) > h, with h the horizon
 * tangent in the sun's
 * direction: from the map, (1 - w) H[sector0] + w H[sector1]; or by HorizonTangentRayMarch
 * when there is no map, or when `refine` and tan(elevation) lies strictly between H[sector0]
 * and H[sector1]. A lit cell gains `hours` and `energy * max(0, n . s)` in component `slot`.
 * @param[in] normals  3 per cell (grid frame, unit), or nullptr (n = z)
 * @param[in,out] hours, energy  `slots` values per cell, added to (no-data cells untouched)
 */
template<typename T>
void AccumulateIllumination(const GridView<T>& view,
  const ShadowSource<T>& source,
  const T* normals,
  const SunStep* steps,
  int stepCount,
  int slots,
  T* hours,
  T* energy,
  std::size_t cell0,
  std::size_t cell1);

} // namespace terrain
} // namespace terroir

#endif

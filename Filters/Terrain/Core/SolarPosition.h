/**
 * @file SolarPosition.h
 * @brief The sun's topocentric azimuth and elevation for a UTC instant and a place, by NREL's
 *        Solar Position Algorithm (Reda & Andreas 2004), plus the calendar helpers it needs.
 *
 * Plain C++ (no VTK, no GL). The filters call it once per time step on the host; nothing here
 * runs per cell.
 *
 * @par References
 * Reda, I. and Andreas, A. (2004). Solar position algorithm for solar radiation applications.
 * Solar Energy 76(5), 577-589. doi:10.1016/j.solener.2003.12.003 (NREL/TP-560-34302, revised
 * 2008). Periodic terms of the Earth's heliocentric position from VSOP87 and of nutation from
 * the 1980 IAU theory, as tabulated in that paper (after Meeus, Astronomical Algorithms, 1998).
 *
 * @par Correctness
 * Testing/Unit/TestSolarPosition.cxx: the worked example of the paper (2003-10-17 12:30:30
 * local, UTC-7, Golden CO) and published reference values at other places and dates, to
 * 0.01 degrees (sources in Testing/Data/KnownAnswers/SolarPosition/README.md).
 */
#ifndef terroir_terrain_SolarPosition_h
#define terroir_terrain_SolarPosition_h

namespace terroir
{
namespace terrain
{

/// A UTC instant on the proleptic Gregorian calendar (years 1..9999 accepted by IsValidDate).
struct UTCInstant
{
  int year = 2000;
  int month = 1;       ///< 1..12
  int day = 1;         ///< 1..days in month
  double hours = 12.0; ///< hours since 00:00 UTC of that day, [0, 24) (other values roll over)
};

/// Where, and in what air, the sun is seen from.
struct Observer
{
  double latitudeDeg = 0.0;      ///< geodetic latitude, degrees north, [-90, 90]
  double longitudeDeg = 0.0;     ///< degrees east, [-180, 180]
  double elevationM = 0.0;       ///< metres above sea level (topocentric parallax)
  double pressureMbar = 1013.25; ///< annual mean local pressure, millibars (refraction)
  double temperatureC = 15.0;    ///< annual mean local temperature, °C (refraction)
  bool refraction = true;        ///< apply the atmospheric refraction correction of SPA eq. 42
  double deltaTSeconds = 69.2;   ///< TT - UT1, seconds (69.2 s is the 2024 value)
};

/// Result of SolarPositionNREL2004.
struct SolarPosition
{
  double azimuthDeg = 0.0;         ///< topocentric azimuth, clockwise from true north, [0, 360)
  double elevationDeg = 0.0;       ///< topocentric elevation angle (refracted when asked), degrees
  double zenithDeg = 90.0;         ///< 90 - elevationDeg
  double declinationDeg = 0.0;     ///< geocentric declination, degrees
  double earthSunDistanceAU = 1.0; ///< Earth radius vector R, astronomical units
  double equationOfTimeMin = 0.0;  ///< equation of time, minutes (SPA appendix A.1)
};

/// True when year/month/day is a real date (Gregorian; 1 <= year <= 9999).
bool IsValidDate(int year, int month, int day);

/// Days in `month` (1..12) of `year` (Gregorian leap rule); 0 for a month out of range.
int DaysInMonth(int year, int month);

/// Julian day (UT) of a UTC instant, SPA eq. 4 (Meeus 7.1), Gregorian calendar.
double JulianDay(const UTCInstant& t);

/**
 * @brief Sun position by Reda & Andreas (2004).
 * @param[in] t     the instant, UTC
 * @param[in] where latitude, longitude, elevation, pressure, temperature, delta T
 * @return topocentric azimuth (true north, clockwise), elevation (refracted when
 *         `where.refraction` and the sun is above -(0.26667 + 0.5667) degrees, as SPA eq. 42),
 *         and the intermediate values listed in SolarPosition
 * @pre IsValidDate(t.year, t.month, t.day); |latitude| <= 90; |longitude| <= 180
 * Accuracy: +-0.0003 degrees for years -2000..6000 (the paper's claim).
 */
SolarPosition SolarPositionNREL2004(const UTCInstant& t, const Observer& where);

namespace detail
{
// The algorithm's stages (angles in degrees, distances in AU), exposed so that the
// intermediate values printed with the paper's worked example can be checked stage by stage
// (Testing/Unit/TestSolarPosition.cxx). Not meant for other callers.
void SpaEarthHeliocentric(double jme, double& lDeg, double& bDeg, double& rAU);
void SpaNutation(double jce, double& dPsiDeg, double& dEpsDeg);
double SpaMeanObliquityArcsec(double jme);
double SpaApparentSiderealTimeDeg(double jd, double jc, double dPsiDeg, double epsDeg);
void SpaGeocentricEquatorial(double lambdaDeg,
  double epsDeg,
  double betaDeg,
  double& alphaDeg,
  double& deltaDeg);
void SpaTopocentricParallax(double latDeg,
  double elevationM,
  double rAU,
  double hDeg,
  double deltaDeg,
  double& dAlphaDeg,
  double& deltaPrimeDeg);
double SpaRefractionDeg(double pressureMbar, double temperatureC, double e0Deg);
double SpaEquationOfTimeMin(double jme, double alphaDeg, double dPsiDeg, double epsDeg);
} // namespace detail

} // namespace terrain
} // namespace terroir

#endif

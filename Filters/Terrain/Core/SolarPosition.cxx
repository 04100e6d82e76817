/**
 * @file SolarPosition.cxx
 * @brief NREL's Solar Position Algorithm (Reda & Andreas 2004, NREL/TP-560-34302 rev. 2008).
 *
 * Equation numbers below are those of the report (section 3, "Procedure", and appendix A.1
 * for the equation of time). Angles are carried in degrees, as in the report, and converted
 * to radians only at the trigonometric calls.
 *
 * The stages that the report's worked example (appendix A.5) prints intermediate values for
 * are separate functions in namespace terroir::terrain::detail with external linkage, so that
 * Testing/Unit/TestSolarPosition.cxx can check each of them against the published numbers.
 * They are not part of the public interface (SolarPosition.h).
 */
#include "SolarPosition.h"

#include <cmath>
#include <cstddef>

namespace terroir
{
namespace terrain
{
namespace detail
{
// Declarations of the per-stage entry points (defined below; tests declare them too).
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

namespace
{

constexpr double kPi = 3.14159265358979323846;
constexpr double kRad = kPi / 180.0; ///< radians per degree
constexpr double kDeg = 180.0 / kPi; ///< degrees per radian

/// Julian day of the J2000.0 epoch (2000-01-01 12:00 TT).
constexpr double kJ2000 = 2451545.0;
/// Apparent radius of the sun's disc, degrees (SPA "SUN_RADIUS").
constexpr double kSunRadiusDeg = 0.26667;
/// Atmospheric refraction at sunrise and sunset, degrees (the report's default 0.5667).
constexpr double kHorizonRefractionDeg = 0.5667;

/// One term A cos(B + C JME) of a VSOP87 series (report Table A4.2): A in 1e-8 rad (L, B)
/// or 1e-8 AU (R), B in radians, C in radians per Julian millennium.
struct PeriodicTerm
{
  double a;
  double b;
  double c;
};

// Report Table A4.2, Earth periodic terms (the abridged VSOP87 of Meeus, appendix III).
// Heliocentric longitude L0..L5.
constexpr PeriodicTerm kL0[] = {
  { 175347046.0, 0.0, 0.0 },
  { 3341656.0, 4.6692568, 6283.07585 },
  { 34894.0, 4.6261, 12566.1517 },
  { 3497.0, 2.7441, 5753.3849 },
  { 3418.0, 2.8289, 3.5231 },
  { 3136.0, 3.6277, 77713.7715 },
  { 2676.0, 4.4181, 7860.4194 },
  { 2343.0, 6.1352, 3930.2097 },
  { 1324.0, 0.7425, 11506.7698 },
  { 1273.0, 2.0371, 529.691 },
  { 1199.0, 1.1096, 1577.3435 },
  { 990.0, 5.233, 5884.927 },
  { 902.0, 2.045, 26.298 },
  { 857.0, 3.508, 398.149 },
  { 780.0, 1.179, 5223.694 },
  { 753.0, 2.533, 5507.553 },
  { 505.0, 4.583, 18849.228 },
  { 492.0, 4.205, 775.523 },
  { 357.0, 2.92, 0.067 },
  { 317.0, 5.849, 11790.629 },
  { 284.0, 1.899, 796.298 },
  { 271.0, 0.315, 10977.079 },
  { 243.0, 0.345, 5486.778 },
  { 206.0, 4.806, 2544.314 },
  { 205.0, 1.869, 5573.143 },
  { 202.0, 2.458, 6069.777 },
  { 156.0, 0.833, 213.299 },
  { 132.0, 3.411, 2942.463 },
  { 126.0, 1.083, 20.775 },
  { 115.0, 0.645, 0.98 },
  { 103.0, 0.636, 4694.003 },
  { 102.0, 0.976, 15720.839 },
  { 102.0, 4.267, 7.114 },
  { 99.0, 6.21, 2146.17 },
  { 98.0, 0.68, 155.42 },
  { 86.0, 5.98, 161000.69 },
  { 85.0, 1.3, 6275.96 },
  { 85.0, 3.67, 71430.7 },
  { 80.0, 1.81, 17260.15 },
  { 79.0, 3.04, 12036.46 },
  { 75.0, 1.76, 5088.63 },
  { 74.0, 3.5, 3154.69 },
  { 74.0, 4.68, 801.82 },
  { 70.0, 0.83, 9437.76 },
  { 62.0, 3.98, 8827.39 },
  { 61.0, 1.82, 7084.9 },
  { 57.0, 2.78, 6286.6 },
  { 56.0, 4.39, 14143.5 },
  { 56.0, 3.47, 6279.55 },
  { 52.0, 0.19, 12139.55 },
  { 52.0, 1.33, 1748.02 },
  { 51.0, 0.28, 5856.48 },
  { 49.0, 0.49, 1194.45 },
  { 41.0, 5.37, 8429.24 },
  { 41.0, 2.4, 19651.05 },
  { 39.0, 6.17, 10447.39 },
  { 37.0, 6.04, 10213.29 },
  { 37.0, 2.57, 1059.38 },
  { 36.0, 1.71, 2352.87 },
  { 36.0, 1.78, 6812.77 },
  { 33.0, 0.59, 17789.85 },
  { 30.0, 0.44, 83996.85 },
  { 30.0, 2.74, 1349.87 },
  { 25.0, 3.16, 4690.48 },
};

constexpr PeriodicTerm kL1[] = {
  { 628331966747.0, 0.0, 0.0 },
  { 206059.0, 2.678235, 6283.07585 },
  { 4303.0, 2.6351, 12566.1517 },
  { 425.0, 1.59, 3.523 },
  { 119.0, 5.796, 26.298 },
  { 109.0, 2.966, 1577.344 },
  { 93.0, 2.59, 18849.23 },
  { 72.0, 1.14, 529.69 },
  { 68.0, 1.87, 398.15 },
  { 67.0, 4.41, 5507.55 },
  { 59.0, 2.89, 5223.69 },
  { 56.0, 2.17, 155.42 },
  { 45.0, 0.4, 796.3 },
  { 36.0, 0.47, 775.52 },
  { 29.0, 2.65, 7.11 },
  { 21.0, 5.34, 0.98 },
  { 19.0, 1.85, 5486.78 },
  { 19.0, 4.97, 213.3 },
  { 17.0, 2.99, 6275.96 },
  { 16.0, 0.03, 2544.31 },
  { 16.0, 1.43, 2146.17 },
  { 15.0, 1.21, 10977.08 },
  { 12.0, 2.83, 1748.02 },
  { 12.0, 3.26, 5088.63 },
  { 12.0, 5.27, 1194.45 },
  { 12.0, 2.08, 4694.0 },
  { 11.0, 0.77, 553.57 },
  { 10.0, 1.3, 6286.6 },
  { 10.0, 4.24, 1349.87 },
  { 9.0, 2.7, 242.73 },
  { 9.0, 5.64, 951.72 },
  { 8.0, 5.3, 2352.87 },
  { 6.0, 2.65, 9437.76 },
  { 6.0, 4.67, 4690.48 },
};

constexpr PeriodicTerm kL2[] = {
  { 52919.0, 0.0, 0.0 },
  { 8720.0, 1.0721, 6283.0758 },
  { 309.0, 0.867, 12566.152 },
  { 27.0, 0.05, 3.52 },
  { 16.0, 5.19, 26.3 },
  { 16.0, 3.68, 155.42 },
  { 10.0, 0.76, 18849.23 },
  { 9.0, 2.06, 77713.77 },
  { 7.0, 0.83, 775.52 },
  { 5.0, 4.66, 1577.34 },
  { 4.0, 1.03, 7.11 },
  { 4.0, 3.44, 5573.14 },
  { 3.0, 5.14, 796.3 },
  { 3.0, 6.05, 5507.55 },
  { 3.0, 1.19, 242.73 },
  { 3.0, 6.12, 529.69 },
  { 3.0, 0.31, 398.15 },
  { 3.0, 2.28, 553.57 },
  { 2.0, 4.38, 5223.69 },
  { 2.0, 3.75, 0.98 },
};

constexpr PeriodicTerm kL3[] = {
  { 289.0, 5.844, 6283.076 },
  { 35.0, 0.0, 0.0 },
  { 17.0, 5.49, 12566.15 },
  { 3.0, 5.2, 155.42 },
  { 1.0, 4.72, 3.52 },
  { 1.0, 5.3, 18849.23 },
  { 1.0, 5.97, 242.73 },
};

constexpr PeriodicTerm kL4[] = {
  { 114.0, 3.142, 0.0 },
  { 8.0, 4.13, 6283.08 },
  { 1.0, 3.84, 12566.15 },
};

constexpr PeriodicTerm kL5[] = {
  { 1.0, 3.14, 0.0 },
};

// Heliocentric latitude B0..B1.
constexpr PeriodicTerm kB0[] = {
  { 280.0, 3.199, 84334.662 },
  { 102.0, 5.422, 5507.553 },
  { 80.0, 3.88, 5223.69 },
  { 44.0, 3.7, 2352.87 },
  { 32.0, 4.0, 1577.34 },
};

constexpr PeriodicTerm kB1[] = {
  { 9.0, 3.9, 5507.55 },
  { 6.0, 1.73, 5223.69 },
};

// Radius vector R0..R4.
constexpr PeriodicTerm kR0[] = {
  { 100013989.0, 0.0, 0.0 },
  { 1670700.0, 3.0984635, 6283.07585 },
  { 13956.0, 3.05525, 12566.1517 },
  { 3084.0, 5.1985, 77713.7715 },
  { 1628.0, 1.1739, 5753.3849 },
  { 1576.0, 2.8469, 7860.4194 },
  { 925.0, 5.453, 11506.77 },
  { 542.0, 4.564, 3930.21 },
  { 472.0, 3.661, 5884.927 },
  { 346.0, 0.964, 5507.553 },
  { 329.0, 5.9, 5223.694 },
  { 307.0, 0.299, 5573.143 },
  { 243.0, 4.273, 11790.629 },
  { 212.0, 5.847, 1577.344 },
  { 186.0, 5.022, 10977.079 },
  { 175.0, 3.012, 18849.228 },
  { 110.0, 5.055, 5486.778 },
  { 98.0, 0.89, 6069.78 },
  { 86.0, 5.69, 15720.84 },
  { 86.0, 1.27, 161000.69 },
  { 65.0, 0.27, 17260.15 },
  { 63.0, 0.92, 529.69 },
  { 57.0, 2.01, 83996.85 },
  { 56.0, 5.24, 71430.7 },
  { 49.0, 3.25, 2544.31 },
  { 47.0, 2.58, 775.52 },
  { 45.0, 5.54, 9437.76 },
  { 43.0, 6.01, 6275.96 },
  { 39.0, 5.36, 4694.0 },
  { 38.0, 2.39, 8827.39 },
  { 37.0, 0.83, 19651.05 },
  { 37.0, 4.9, 12139.55 },
  { 36.0, 1.67, 12036.46 },
  { 35.0, 1.84, 2942.46 },
  { 33.0, 0.24, 7084.9 },
  { 32.0, 0.18, 5088.63 },
  { 32.0, 1.78, 398.15 },
  { 28.0, 1.21, 6286.6 },
  { 28.0, 1.9, 6279.55 },
  { 26.0, 4.59, 10447.39 },
};

constexpr PeriodicTerm kR1[] = {
  { 103019.0, 1.10749, 6283.07585 },
  { 1721.0, 1.0644, 12566.1517 },
  { 702.0, 3.142, 0.0 },
  { 32.0, 1.02, 18849.23 },
  { 31.0, 2.84, 5507.55 },
  { 25.0, 1.32, 5223.69 },
  { 18.0, 1.42, 1577.34 },
  { 10.0, 5.91, 10977.08 },
  { 9.0, 1.42, 6275.96 },
  { 9.0, 0.27, 5486.78 },
};

constexpr PeriodicTerm kR2[] = {
  { 4359.0, 5.7846, 6283.0758 },
  { 124.0, 5.579, 12566.152 },
  { 12.0, 3.14, 0.0 },
  { 9.0, 3.63, 77713.77 },
  { 6.0, 1.87, 5573.14 },
  { 3.0, 5.47, 18849.23 },
};

constexpr PeriodicTerm kR3[] = {
  { 145.0, 4.273, 6283.076 },
  { 7.0, 3.92, 12566.15 },
};

constexpr PeriodicTerm kR4[] = {
  { 4.0, 2.56, 6283.08 },
};

/// One row of the report's Table A4.3 (nutation in longitude and obliquity, 1980 IAU theory):
/// the multipliers Y0..Y4 of the arguments X0..X4 (eq. 15-19), then a, b (longitude) and
/// c, d (obliquity), in units of 0.0001 arc second (and per Julian century for b, d).
struct NutationTerm
{
  signed char y[5];
  double a;
  double b;
  double c;
  double d;
};

constexpr NutationTerm kNutation[] = {
  { { 0, 0, 0, 0, 1 }, -171996.0, -174.2, 92025.0, 8.9 },
  { { -2, 0, 0, 2, 2 }, -13187.0, -1.6, 5736.0, -3.1 },
  { { 0, 0, 0, 2, 2 }, -2274.0, -0.2, 977.0, -0.5 },
  { { 0, 0, 0, 0, 2 }, 2062.0, 0.2, -895.0, 0.5 },
  { { 0, 1, 0, 0, 0 }, 1426.0, -3.4, 54.0, -0.1 },
  { { 0, 0, 1, 0, 0 }, 712.0, 0.1, -7.0, 0.0 },
  { { -2, 1, 0, 2, 2 }, -517.0, 1.2, 224.0, -0.6 },
  { { 0, 0, 0, 2, 1 }, -386.0, -0.4, 200.0, 0.0 },
  { { 0, 0, 1, 2, 2 }, -301.0, 0.0, 129.0, -0.1 },
  { { -2, -1, 0, 2, 2 }, 217.0, -0.5, -95.0, 0.3 },
  { { -2, 0, 1, 0, 0 }, -158.0, 0.0, 0.0, 0.0 },
  { { -2, 0, 0, 2, 1 }, 129.0, 0.1, -70.0, 0.0 },
  { { 0, 0, -1, 2, 2 }, 123.0, 0.0, -53.0, 0.0 },
  { { 2, 0, 0, 0, 0 }, 63.0, 0.0, 0.0, 0.0 },
  { { 0, 0, 1, 0, 1 }, 63.0, 0.1, -33.0, 0.0 },
  { { 2, 0, -1, 2, 2 }, -59.0, 0.0, 26.0, 0.0 },
  { { 0, 0, -1, 0, 1 }, -58.0, -0.1, 32.0, 0.0 },
  { { 0, 0, 1, 2, 1 }, -51.0, 0.0, 27.0, 0.0 },
  { { -2, 0, 2, 0, 0 }, 48.0, 0.0, 0.0, 0.0 },
  { { 0, 0, -2, 2, 1 }, 46.0, 0.0, -24.0, 0.0 },
  { { 2, 0, 0, 2, 2 }, -38.0, 0.0, 16.0, 0.0 },
  { { 0, 0, 2, 2, 2 }, -31.0, 0.0, 13.0, 0.0 },
  { { 0, 0, 2, 0, 0 }, 29.0, 0.0, 0.0, 0.0 },
  { { -2, 0, 1, 2, 2 }, 29.0, 0.0, -12.0, 0.0 },
  { { 0, 0, 0, 2, 0 }, 26.0, 0.0, 0.0, 0.0 },
  { { -2, 0, 0, 2, 0 }, -22.0, 0.0, 0.0, 0.0 },
  { { 0, 0, -1, 2, 1 }, 21.0, 0.0, -10.0, 0.0 },
  { { 0, 2, 0, 0, 0 }, 17.0, -0.1, 0.0, 0.0 },
  { { 2, 0, -1, 0, 1 }, 16.0, 0.0, -8.0, 0.0 },
  { { -2, 2, 0, 2, 2 }, -16.0, 0.1, 7.0, 0.0 },
  { { 0, 1, 0, 0, 1 }, -15.0, 0.0, 9.0, 0.0 },
  { { -2, 0, 1, 0, 1 }, -13.0, 0.0, 7.0, 0.0 },
  { { 0, -1, 0, 0, 1 }, -12.0, 0.0, 6.0, 0.0 },
  { { 0, 0, 2, -2, 0 }, 11.0, 0.0, 0.0, 0.0 },
  { { 2, 0, -1, 2, 1 }, -10.0, 0.0, 5.0, 0.0 },
  { { 2, 0, 1, 2, 2 }, -8.0, 0.0, 3.0, 0.0 },
  { { 0, 1, 0, 2, 2 }, 7.0, 0.0, -3.0, 0.0 },
  { { -2, 1, 1, 0, 0 }, -7.0, 0.0, 0.0, 0.0 },
  { { 0, -1, 0, 2, 2 }, -7.0, 0.0, 3.0, 0.0 },
  { { 2, 0, 0, 2, 1 }, -7.0, 0.0, 3.0, 0.0 },
  { { 2, 0, 1, 0, 0 }, 6.0, 0.0, 0.0, 0.0 },
  { { -2, 0, 2, 2, 2 }, 6.0, 0.0, -3.0, 0.0 },
  { { -2, 0, 1, 2, 1 }, 6.0, 0.0, -3.0, 0.0 },
  { { 2, 0, -2, 0, 1 }, -6.0, 0.0, 3.0, 0.0 },
  { { 2, 0, 0, 0, 1 }, -6.0, 0.0, 3.0, 0.0 },
  { { 0, -1, 1, 0, 0 }, 5.0, 0.0, 0.0, 0.0 },
  { { -2, -1, 0, 2, 1 }, -5.0, 0.0, 3.0, 0.0 },
  { { -2, 0, 0, 0, 1 }, -5.0, 0.0, 3.0, 0.0 },
  { { 0, 0, 2, 2, 1 }, -5.0, 0.0, 3.0, 0.0 },
  { { -2, 0, 2, 0, 1 }, 4.0, 0.0, 0.0, 0.0 },
  { { -2, 1, 0, 2, 1 }, 4.0, 0.0, 0.0, 0.0 },
  { { 0, 0, 1, -2, 0 }, 4.0, 0.0, 0.0, 0.0 },
  { { -1, 0, 1, 0, 0 }, -4.0, 0.0, 0.0, 0.0 },
  { { -2, 1, 0, 0, 0 }, -4.0, 0.0, 0.0, 0.0 },
  { { 1, 0, 0, 0, 0 }, -4.0, 0.0, 0.0, 0.0 },
  { { 0, 0, 1, 2, 0 }, 3.0, 0.0, 0.0, 0.0 },
  { { 0, 0, -2, 2, 2 }, -3.0, 0.0, 0.0, 0.0 },
  { { -1, -1, 1, 0, 0 }, -3.0, 0.0, 0.0, 0.0 },
  { { 0, 1, 1, 0, 0 }, -3.0, 0.0, 0.0, 0.0 },
  { { 0, -1, 1, 2, 2 }, -3.0, 0.0, 0.0, 0.0 },
  { { 2, -1, -1, 2, 2 }, -3.0, 0.0, 0.0, 0.0 },
  { { 0, 0, 3, 2, 2 }, -3.0, 0.0, 0.0, 0.0 },
  { { 2, -1, 0, 2, 2 }, -3.0, 0.0, 0.0, 0.0 },
};

static_assert(sizeof(kL0) / sizeof(kL0[0]) == 64, "Table A4.2 has 64 L0 terms");
static_assert(sizeof(kL1) / sizeof(kL1[0]) == 34, "Table A4.2 has 34 L1 terms");
static_assert(sizeof(kL2) / sizeof(kL2[0]) == 20, "Table A4.2 has 20 L2 terms");
static_assert(sizeof(kL3) / sizeof(kL3[0]) == 7, "Table A4.2 has 7 L3 terms");
static_assert(sizeof(kL4) / sizeof(kL4[0]) == 3, "Table A4.2 has 3 L4 terms");
static_assert(sizeof(kB0) / sizeof(kB0[0]) == 5, "Table A4.2 has 5 B0 terms");
static_assert(sizeof(kB1) / sizeof(kB1[0]) == 2, "Table A4.2 has 2 B1 terms");
static_assert(sizeof(kR0) / sizeof(kR0[0]) == 40, "Table A4.2 has 40 R0 terms");
static_assert(sizeof(kR1) / sizeof(kR1[0]) == 10, "Table A4.2 has 10 R1 terms");
static_assert(sizeof(kR2) / sizeof(kR2[0]) == 6, "Table A4.2 has 6 R2 terms");
static_assert(sizeof(kR3) / sizeof(kR3[0]) == 2, "Table A4.2 has 2 R3 terms");
static_assert(sizeof(kNutation) / sizeof(kNutation[0]) == 63, "Table A4.3 has 63 rows");

/// A series of VSOP87 periodic terms: a pointer to its first term and its length.
struct Series
{
  const PeriodicTerm* terms;
  std::size_t count;
};

template<std::size_t N>
constexpr Series MakeSeries(const PeriodicTerm (&terms)[N])
{
  return Series{ terms, N };
}

/// Reduces an angle in degrees to [0, 360) (the report's "limit to 0-360" steps).
double LimitDegrees(double deg)
{
  double r = std::fmod(deg, 360.0);
  if (r < 0.0)
  {
    r += 360.0;
  }
  // fmod of a tiny negative value plus 360 can round to exactly 360.
  return r >= 360.0 ? 0.0 : r;
}

/// Eq. 9-10: the sum over i of A_i cos(B_i + C_i JME) for one series.
double SumSeries(const Series& s, double jme)
{
  double sum = 0.0;
  for (std::size_t i = 0; i < s.count; ++i)
  {
    sum += s.terms[i].a * std::cos(s.terms[i].b + s.terms[i].c * jme);
  }
  return sum;
}

/// Eq. 11 (and its analogues for B and R): (X0 + X1 JME + X2 JME^2 + ...) / 1e8, evaluated by
/// Horner's rule from the highest power down.
template<std::size_t N>
double EvaluatePolynomialSeries(const Series (&series)[N], double jme)
{
  double value = 0.0;
  for (std::size_t k = N; k-- > 0;)
  {
    value = value * jme + SumSeries(series[k], jme);
  }
  return value / 1.0e8;
}

/// Third-order polynomial a + b x + c x^2 + x^3 / d, the form of eq. 15-19.
double NutationArgument(double a, double b, double c, double d, double x)
{
  return a + x * (b + x * c) + x * x * x / d;
}

} // namespace

namespace detail
{

/// Earth heliocentric longitude L and latitude B (degrees, eq. 9-12 and section 3.2.7) and
/// radius vector R (AU, section 3.2.8) at Julian ephemeris millennium `jme` (eq. 8).
void SpaEarthHeliocentric(double jme, double& lDeg, double& bDeg, double& rAU)
{
  static constexpr Series kL[] = { MakeSeries(kL0),
    MakeSeries(kL1),
    MakeSeries(kL2),
    MakeSeries(kL3),
    MakeSeries(kL4),
    MakeSeries(kL5) };
  static constexpr Series kB[] = { MakeSeries(kB0), MakeSeries(kB1) };
  static constexpr Series kR[] = {
    MakeSeries(kR0), MakeSeries(kR1), MakeSeries(kR2), MakeSeries(kR3), MakeSeries(kR4)
  };
  lDeg = LimitDegrees(EvaluatePolynomialSeries(kL, jme) * kDeg); // eq. 11-12, limited
  bDeg = EvaluatePolynomialSeries(kB, jme) * kDeg;
  rAU = EvaluatePolynomialSeries(kR, jme);
}

/// Nutation in longitude (delta psi) and obliquity (delta epsilon), degrees, at Julian
/// ephemeris century `jce` (eq. 15-23, Table A4.3).
void SpaNutation(double jce, double& dPsiDeg, double& dEpsDeg)
{
  double x[5];
  // Eq. 15: mean elongation of the moon from the sun.
  x[0] = NutationArgument(297.85036, 445267.111480, -0.0019142, 189474.0, jce);
  // Eq. 16: mean anomaly of the sun (Earth).
  x[1] = NutationArgument(357.52772, 35999.050340, -0.0001603, -300000.0, jce);
  // Eq. 17: mean anomaly of the moon.
  x[2] = NutationArgument(134.96298, 477198.867398, 0.0086972, 56250.0, jce);
  // Eq. 18: moon's argument of latitude.
  x[3] = NutationArgument(93.27191, 483202.017538, -0.0036825, 327270.0, jce);
  // Eq. 19: longitude of the ascending node of the moon's mean orbit on the ecliptic.
  x[4] = NutationArgument(125.04452, -1934.136261, 0.0020708, 450000.0, jce);

  double sumPsi = 0.0;
  double sumEps = 0.0;
  for (const NutationTerm& t : kNutation)
  {
    double arg = 0.0;
    for (int j = 0; j < 5; ++j)
    {
      arg += x[j] * t.y[j];
    }
    arg *= kRad;
    sumPsi += (t.a + t.b * jce) * std::sin(arg); // eq. 20
    sumEps += (t.c + t.d * jce) * std::cos(arg); // eq. 21
  }
  dPsiDeg = sumPsi / 36000000.0; // eq. 22
  dEpsDeg = sumEps / 36000000.0; // eq. 23
}

/// Mean obliquity of the ecliptic epsilon0, arc seconds (eq. 24, U = JME / 10).
double SpaMeanObliquityArcsec(double jme)
{
  static constexpr double kCoefficients[] = {
    84381.448, -4680.93, -1.55, 1999.25, -51.38, -249.67, -39.05, 7.12, 27.87, 5.79, 2.45
  };
  const double u = jme / 10.0;
  double value = 0.0;
  for (std::size_t k = sizeof(kCoefficients) / sizeof(kCoefficients[0]); k-- > 0;)
  {
    value = value * u + kCoefficients[k];
  }
  return value;
}

/// Apparent sidereal time at Greenwich nu, degrees in [0, 360) (eq. 28-29), from the Julian
/// day and century (UT), the nutation in longitude and the true obliquity.
double SpaApparentSiderealTimeDeg(double jd, double jc, double dPsiDeg, double epsDeg)
{
  const double nu0 = LimitDegrees(280.46061837 + 360.98564736629 * (jd - kJ2000) +
    jc * jc * (0.000387933 - jc / 38710000.0));                 // eq. 28
  return LimitDegrees(nu0 + dPsiDeg * std::cos(epsDeg * kRad)); // eq. 29
}

/// Geocentric sun right ascension alpha in [0, 360) and declination delta, degrees (eq. 30-31),
/// from the apparent sun longitude lambda, the true obliquity epsilon and the geocentric
/// latitude beta.
void SpaGeocentricEquatorial(double lambdaDeg,
  double epsDeg,
  double betaDeg,
  double& alphaDeg,
  double& deltaDeg)
{
  const double lambda = lambdaDeg * kRad;
  const double eps = epsDeg * kRad;
  const double beta = betaDeg * kRad;
  alphaDeg = LimitDegrees(kDeg *
    std::atan2(std::sin(lambda) * std::cos(eps) - std::tan(beta) * std::sin(eps),
      std::cos(lambda))); // eq. 30
  deltaDeg = kDeg *
    std::asin(
      std::sin(beta) * std::cos(eps) + std::cos(beta) * std::sin(eps) * std::sin(lambda)); // eq. 31
}

/// Parallax in right ascension (delta alpha) and topocentric declination delta', degrees
/// (eq. 33-39), for an observer at geodetic latitude `latDeg` and `elevationM` metres, with
/// the Earth radius vector R, the observer local hour angle H and the geocentric declination.
void SpaTopocentricParallax(double latDeg,
  double elevationM,
  double rAU,
  double hDeg,
  double deltaDeg,
  double& dAlphaDeg,
  double& deltaPrimeDeg)
{
  const double phi = latDeg * kRad;
  const double h = hDeg * kRad;
  const double delta = deltaDeg * kRad;
  const double xi = (8.794 / (3600.0 * rAU)) * kRad;      // eq. 33: equatorial horizontal parallax
  const double u = std::atan(0.99664719 * std::tan(phi)); // eq. 34
  const double x = std::cos(u) + elevationM / 6378140.0 * std::cos(phi);              // eq. 35
  const double y = 0.99664719 * std::sin(u) + elevationM / 6378140.0 * std::sin(phi); // eq. 36
  const double denominator = std::cos(delta) - x * std::sin(xi) * std::cos(h);
  const double dAlpha = std::atan2(-x * std::sin(xi) * std::sin(h), denominator); // eq. 37
  dAlphaDeg = dAlpha * kDeg;
  deltaPrimeDeg = kDeg *
    std::atan2((std::sin(delta) - y * std::sin(xi)) * std::cos(dAlpha), denominator); // eq. 39
}

/// Atmospheric refraction correction delta e, degrees (eq. 42), for the topocentric elevation
/// angle without refraction e0 (degrees), annual mean pressure (mbar) and temperature (°C).
/// Unconditional: the caller decides whether the sun is high enough for it to apply.
double SpaRefractionDeg(double pressureMbar, double temperatureC, double e0Deg)
{
  return (pressureMbar / 1010.0) * (283.0 / (273.0 + temperatureC)) * 1.02 /
    (60.0 * std::tan(kRad * (e0Deg + 10.3 / (e0Deg + 5.11))));
}

/// Equation of time E, minutes in [-20, 20] (appendix A.1, eq. A1-A2), from the Julian
/// ephemeris millennium, the geocentric right ascension, the nutation in longitude and the
/// true obliquity.
double SpaEquationOfTimeMin(double jme, double alphaDeg, double dPsiDeg, double epsDeg)
{
  // Eq. A1: the sun's mean longitude M, degrees.
  const double m = LimitDegrees(280.4664567 +
    jme *
      (360007.6982779 +
        jme * (0.03032028 + jme * (1.0 / 49931.0 + jme * (-1.0 / 15300.0 - jme / 2000000.0)))));
  // Eq. A2, in degrees; four minutes of time per degree.
  double e = 4.0 * (m - 0.0057183 - alphaDeg + dPsiDeg * std::cos(epsDeg * kRad));
  if (e > 20.0)
  {
    e -= 1440.0;
  }
  else if (e < -20.0)
  {
    e += 1440.0;
  }
  return e;
}

} // namespace detail

int DaysInMonth(int year, int month)
{
  static constexpr int kDays[] = { 31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31 };
  if (month < 1 || month > 12)
  {
    return 0;
  }
  const bool leap = (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
  return kDays[month - 1] + ((month == 2 && leap) ? 1 : 0);
}

bool IsValidDate(int year, int month, int day)
{
  return year >= 1 && year <= 9999 && month >= 1 && month <= 12 && day >= 1 &&
    day <= DaysInMonth(year, month);
}

double JulianDay(const UTCInstant& t)
{
  // Eq. 4: January and February count as months 13 and 14 of the previous year.
  int y = t.year;
  int m = t.month;
  if (m < 3)
  {
    y -= 1;
    m += 12;
  }
  const double d = t.day + t.hours / 24.0; // day of month with its decimal time
  // Gregorian correction B = 2 - A + INT(A / 4), A = INT(Y / 100). INT truncates toward zero.
  const int a = y / 100;
  const int b = 2 - a + a / 4;
  return std::trunc(365.25 * (y + 4716)) + std::trunc(30.6001 * (m + 1)) + d + b - 1524.5;
}

SolarPosition SolarPositionNREL2004(const UTCInstant& t, const Observer& where)
{
  using namespace detail;

  // 3.1: Julian day, ephemeris day, century, ephemeris century and millennium (eq. 4-8).
  const double jd = JulianDay(t);
  const double jde = jd + where.deltaTSeconds / 86400.0;
  const double jc = (jd - kJ2000) / 36525.0;
  const double jce = (jde - kJ2000) / 36525.0;
  const double jme = jce / 10.0;

  // 3.2: Earth heliocentric position.
  double lDeg = 0.0;
  double bDeg = 0.0;
  double rAU = 1.0;
  SpaEarthHeliocentric(jme, lDeg, bDeg, rAU);

  // 3.3: geocentric longitude and latitude (eq. 13-14).
  const double thetaDeg = LimitDegrees(lDeg + 180.0);
  const double betaDeg = -bDeg;

  // 3.4-3.5: nutation and the true obliquity of the ecliptic (eq. 15-25).
  double dPsiDeg = 0.0;
  double dEpsDeg = 0.0;
  SpaNutation(jce, dPsiDeg, dEpsDeg);
  const double epsDeg = SpaMeanObliquityArcsec(jme) / 3600.0 + dEpsDeg; // eq. 25

  // 3.6-3.7: aberration correction and apparent sun longitude (eq. 26-27).
  const double dTauDeg = -20.4898 / (3600.0 * rAU);
  const double lambdaDeg = thetaDeg + dPsiDeg + dTauDeg;

  // 3.8-3.10: apparent sidereal time at Greenwich, geocentric right ascension and declination.
  const double nuDeg = SpaApparentSiderealTimeDeg(jd, jc, dPsiDeg, epsDeg);
  double alphaDeg = 0.0;
  double deltaDeg = 0.0;
  SpaGeocentricEquatorial(lambdaDeg, epsDeg, betaDeg, alphaDeg, deltaDeg);

  // 3.11: observer local hour angle (eq. 32), longitude positive east.
  const double hDeg = LimitDegrees(nuDeg + where.longitudeDeg - alphaDeg);

  // 3.12-3.13: topocentric declination and local hour angle (eq. 33-40).
  double dAlphaDeg = 0.0;
  double deltaPrimeDeg = 0.0;
  SpaTopocentricParallax(
    where.latitudeDeg, where.elevationM, rAU, hDeg, deltaDeg, dAlphaDeg, deltaPrimeDeg);
  const double hPrime = (hDeg - dAlphaDeg) * kRad;

  // 3.14: topocentric elevation (eq. 41-43) and zenith angle (eq. 44).
  const double phi = where.latitudeDeg * kRad;
  const double deltaPrime = deltaPrimeDeg * kRad;
  double sinE0 =
    std::sin(phi) * std::sin(deltaPrime) + std::cos(phi) * std::cos(deltaPrime) * std::cos(hPrime);
  sinE0 = sinE0 > 1.0 ? 1.0 : (sinE0 < -1.0 ? -1.0 : sinE0);
  const double e0Deg = kDeg * std::asin(sinE0); // eq. 41
  double dEDeg = 0.0;
  if (where.refraction && e0Deg >= -(kSunRadiusDeg + kHorizonRefractionDeg))
  {
    dEDeg = SpaRefractionDeg(where.pressureMbar, where.temperatureC, e0Deg); // eq. 42
  }
  const double eDeg = e0Deg + dEDeg; // eq. 43

  // 3.15: topocentric azimuth, astronomers' (westward from south, eq. 45), then navigators'
  // (eastward from north, eq. 46).
  const double gammaDeg = kDeg *
    std::atan2(
      std::sin(hPrime), std::cos(hPrime) * std::sin(phi) - std::tan(deltaPrime) * std::cos(phi));

  SolarPosition result;
  result.elevationDeg = eDeg;
  result.zenithDeg = 90.0 - eDeg; // eq. 44
  result.azimuthDeg = LimitDegrees(gammaDeg + 180.0);
  result.declinationDeg = deltaDeg;
  result.earthSunDistanceAU = rAU;
  result.equationOfTimeMin = SpaEquationOfTimeMin(jme, alphaDeg, dPsiDeg, epsDeg);
  return result;
}

} // namespace terrain
} // namespace terroir

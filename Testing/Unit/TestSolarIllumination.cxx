// Known answers of the day integration and beam model (Filters/Terrain/Core/SolarIllumination.h):
// flat-ground energy against the daily extraterrestrial radiation formula (FAO-56 eq. 21),
// the air mass against the plane-parallel limit, and the incidence on a tilted plane.
#include "SlopeHorn1981.h"
#include "SolarIllumination.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace
{
namespace tt = terroir::terrain;
using terroir::GridView;
constexpr double kPi = 3.14159265358979323846;

tt::SunFrame Frame(double lat, double lon)
{
  tt::SunFrame f;
  f.observer.latitudeDeg = lat;
  f.observer.longitudeDeg = lon;
  f.observer.refraction = false;
  f.dx = 10.0;
  f.dy = 10.0;
  f.sectors = 16;
  f.transmittance = 1.0;
  return f;
}

/// Hours and energy of one cell of flat ground over the steps (ray marching).
void FlatDay(const std::vector<tt::SunStep>& steps, double& hours, double& energy)
{
  std::vector<double> z(9, 100.0);
  GridView<double> v;
  v.data = z.data();
  v.nx = 3;
  v.ny = 3;
  v.dx = 10.0;
  v.dy = 10.0;
  std::vector<double> h(9, 0.0);
  std::vector<double> e(9, 0.0);
  tt::ShadowSource<double> source;
  source.zMax = 100.0;
  tt::AccumulateIllumination(v,
    source,
    static_cast<const double*>(nullptr),
    steps.data(),
    static_cast<int>(steps.size()),
    1,
    h.data(),
    e.data(),
    0,
    9);
  hours = h[4];
  energy = e[4];
}
} // namespace

// With tau = 1 the beam is the extraterrestrial S0/R^2, so a day's energy on flat ground is
// the daily extraterrestrial radiation on a horizontal surface (Allen et al. 1998, FAO-56,
// eq. 21, with dr = 1/R^2):
//   Ra = (24/pi) S0/R^2 [ws sin(lat) sin(decl) + cos(lat) cos(decl) sin(ws)],
//   ws = arccos(-tan(lat) tan(decl)).
TEST(TerroirSolarIllumination, FlatDayEnergyIsExtraterrestrialRadiation)
{
  struct Case
  {
    double lat;
    int month, day;
  };
  for (const Case& c :
    { Case{ 45.0, 6, 21 }, Case{ 45.0, 12, 21 }, Case{ -20.0, 3, 15 }, Case{ 0.0, 9, 23 } })
  {
    const tt::SunFrame frame = Frame(c.lat, 10.0);
    const std::vector<tt::SunStep> steps = tt::DaySunSteps(2025, c.month, c.day, 1.0, 0, frame);
    ASSERT_EQ(steps.size(), 1440u);
    double hours = 0.0;
    double energy = 0.0;
    FlatDay(steps, hours, energy);
    tt::UTCInstant noon;
    noon.year = 2025;
    noon.month = c.month;
    noon.day = c.day;
    noon.hours = 12.0 - 10.0 / 15.0;
    const tt::SolarPosition p = tt::SolarPositionNREL2004(noon, frame.observer);
    const double phi = c.lat * kPi / 180.0;
    const double d = p.declinationDeg * kPi / 180.0;
    const double ws = std::acos(-std::tan(phi) * std::tan(d));
    const double ra = 24.0 / kPi * tt::kSolarConstant /
      (p.earthSunDistanceAU * p.earthSunDistanceAU) *
      (ws * std::sin(phi) * std::sin(d) + std::cos(phi) * std::cos(d) * std::sin(ws));
    EXPECT_NEAR(energy, ra, 0.003 * ra) << "lat " << c.lat << " " << c.month << "-" << c.day;
    EXPECT_NEAR(hours, 24.0 / kPi * ws, 1.0 / 60.0 + 1e-9);
  }
}

// Kasten & Young (1989): m = 1 at the zenith, close to the plane-parallel 1/cos(Z) at moderate
// zenith angles, about 38 at the horizon (their table: 38.09; the formula is within 0.5 %).
TEST(TerroirSolarIllumination, AirMassKastenYoung)
{
  EXPECT_NEAR(tt::RelativeAirMassKastenYoung1989(0.0), 1.0, 5e-4);
  for (double z : { 20.0, 40.0, 60.0 })
  {
    EXPECT_NEAR(tt::RelativeAirMassKastenYoung1989(z),
      1.0 / std::cos(z * kPi / 180.0),
      0.003 / std::cos(z * kPi / 180.0))
      << z;
  }
  EXPECT_NEAR(tt::RelativeAirMassKastenYoung1989(90.0), 38.09, 0.005 * 38.09);
  // The beam at the zenith with tau = 0.7 at sea level: S0 * 0.7^m(0); none below the horizon.
  EXPECT_NEAR(tt::ClearSkyBeamCampbellNorman1998(90.0, 1.0, 0.7, 0.0),
    tt::kSolarConstant * std::pow(0.7, tt::RelativeAirMassKastenYoung1989(0.0)),
    1e-9);
  EXPECT_EQ(tt::ClearSkyBeamCampbellNorman1998(-0.5, 1.0, 0.7, 0.0), 0.0);
  // Thinner air at 2000 m: m * exp(-2000/8200) (Campbell & Norman eq. 3.7).
  EXPECT_NEAR(tt::ClearSkyBeamCampbellNorman1998(30.0, 1.0, 0.7, 2000.0),
    tt::kSolarConstant *
      std::pow(0.7, std::exp(-2000.0 / 8200.0) * tt::RelativeAirMassKastenYoung1989(60.0)),
    1e-9);
}

// On a plane rising 20 degrees to the north (facing south), a sun due south at elevation e
// strikes with cos(incidence) = n . s = sin(e + 20 deg); a sun due north 15 degrees high is
// below the plane's own rise: the plane shades itself.
TEST(TerroirSolarIllumination, IncidenceOnATiltedPlane)
{
  const int nx = 12;
  const int ny = 12;
  const double tilt = 20.0 * kPi / 180.0;
  std::vector<float> z(static_cast<std::size_t>(nx) * ny);
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      z[static_cast<std::size_t>(j) * nx + i] =
        static_cast<float>(500.0 + std::tan(tilt) * 10.0 * j);
    }
  }
  GridView<float> v;
  v.data = z.data();
  v.nx = nx;
  v.ny = ny;
  v.dx = 10.0;
  v.dy = 10.0;
  std::vector<float> normals(3 * z.size());
  tt::SlopeHorn1981(v,
    tt::SlopeParams(),
    static_cast<float*>(nullptr),
    static_cast<float*>(nullptr),
    normals.data());
  tt::SunFrame frame = Frame(45.0, 0.0);
  for (double el : { 50.0, 75.0 })
  {
    // The ground rises to the north (faces south): normal (0, -sin t, cos t).
    tt::SunStep step = tt::MakeSunStep(180.0, el, frame);
    step.hours = 1.0f;
    step.energy = 1.0f;
    std::vector<float> lit(z.size(), 0.0f);
    std::vector<float> cosi(z.size(), 0.0f);
    tt::ShadowSource<float> source;
    source.zMax = z.back();
    tt::AccumulateIllumination(
      v, source, normals.data(), &step, 1, 1, lit.data(), cosi.data(), 0, z.size());
    const double e = el * kPi / 180.0;
    // s = (0, -cos e, sin e): n . s = sin t cos e + cos t sin e = sin(e + t).
    const double expected = std::sin(e + tilt);
    for (int j = 1; j < ny - 1; ++j)
    {
      for (int i = 1; i < nx - 1; ++i)
      {
        const std::size_t c = static_cast<std::size_t>(j) * nx + i;
        EXPECT_EQ(lit[c], 1.0f);
        EXPECT_NEAR(cosi[c], expected, 1e-5) << el;
      }
    }
  }
  // A sun due north lower than the slope (15 degrees < 20): the plane shades itself.
  tt::SunStep north = tt::MakeSunStep(0.0, 15.0, frame);
  north.hours = 1.0f;
  north.energy = 1.0f;
  std::vector<float> lit(z.size(), 0.0f);
  std::vector<float> cosi(z.size(), 0.0f);
  tt::ShadowSource<float> source;
  source.zMax = z.back();
  tt::AccumulateIllumination(
    v, source, normals.data(), &north, 1, 1, lit.data(), cosi.data(), 0, z.size());
  EXPECT_EQ(lit[5 * nx + 5], 0.0f);
  EXPECT_EQ(cosi[5 * nx + 5], 0.0f);
}

// Steps: ceil(1440 / step) of them, the last one shorter, all centred on mean solar noon;
// grid azimuth = true azimuth - bearing of grid north.
TEST(TerroirSolarIllumination, DayStepsAndFrame)
{
  tt::SunFrame frame = Frame(40.0, -120.0);
  frame.gridNorthBearing = -2.5;
  const std::vector<tt::SunStep> steps = tt::DaySunSteps(2025, 6, 21, 7.0, 3, frame);
  ASSERT_EQ(steps.size(), 206u); // 205 steps of 7 min + one of 5 min
  double total = 0.0;
  for (const tt::SunStep& s : steps)
  {
    total += s.hours;
    EXPECT_EQ(s.slot, 3);
    EXPECT_NEAR(std::fmod(s.azimuthDeg + 2.5 + 360.0, 360.0), s.gridAzimuthDeg, 1e-9);
  }
  EXPECT_NEAR(total, 24.0, 1e-5);
  EXPECT_NEAR(steps.back().hours, 5.0 / 60.0, 1e-6);
  // First step centred 3.5 min after 00:00 mean solar time = 08:00 UTC at 120 W.
  EXPECT_NEAR(steps.front().utcHours, 8.0 + 3.5 / 60.0, 1e-9);
}

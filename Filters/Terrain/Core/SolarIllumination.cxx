#include "SolarIllumination.h"

#include <algorithm>
#include <cmath>

namespace terroir
{
namespace terrain
{
namespace
{
constexpr double kDeg = 3.14159265358979323846 / 180.0;

/// What a lit cell with unit normal n gains from `step` (the same arithmetic as the shaders).
template<typename T>
inline void Gain(const SunStep& step, const T* n, T* hours, T* energy)
{
  hours[step.slot] += static_cast<T>(step.hours);
  const T cosi = n ? n[0] * static_cast<T>(step.sun[0]) + n[1] * static_cast<T>(step.sun[1]) +
      n[2] * static_cast<T>(step.sun[2])
                   : static_cast<T>(step.sun[2]);
  if (cosi > T(0))
  {
    energy[step.slot] += static_cast<T>(step.energy) * cosi;
  }
}
} // namespace

//------------------------------------------------------------------------------
double RelativeAirMassKastenYoung1989(double zenithDeg)
{
  return 1.0 / (std::cos(zenithDeg * kDeg) + 0.50572 * std::pow(96.07995 - zenithDeg, -1.6364));
}

//------------------------------------------------------------------------------
double ClearSkyBeamCampbellNorman1998(double elevationDeg,
  double earthSunDistanceAU,
  double transmittance,
  double meanElevationM)
{
  if (!(elevationDeg > 0.0))
  {
    return 0.0;
  }
  const double m =
    std::exp(-meanElevationM / 8200.0) * RelativeAirMassKastenYoung1989(90.0 - elevationDeg);
  return kSolarConstant / (earthSunDistanceAU * earthSunDistanceAU) * std::pow(transmittance, m);
}

//------------------------------------------------------------------------------
SunStep MakeSunStep(double azimuthDeg, double elevationDeg, const SunFrame& frame)
{
  SunStep s;
  s.azimuthDeg = azimuthDeg;
  s.elevationDeg = elevationDeg;
  double g = std::fmod(azimuthDeg - frame.gridNorthBearing, 360.0);
  if (g < 0.0)
  {
    g += 360.0;
  }
  s.gridAzimuthDeg = g;
  s.tanElevation = elevationDeg >= 90.0 ? 1e30f : static_cast<float>(std::tan(elevationDeg * kDeg));
  const double ce = std::cos(elevationDeg * kDeg);
  s.sun[0] = static_cast<float>(std::sin(g * kDeg) * ce);
  s.sun[1] = static_cast<float>(std::cos(g * kDeg) * ce);
  s.sun[2] = static_cast<float>(std::sin(elevationDeg * kDeg));
  s.sectors = LookupSectors(g, frame.sectors);
  s.march = MakeMarchDirection(g, frame.dx, frame.dy);
  return s;
}

//------------------------------------------------------------------------------
std::vector<SunStep> DaySunSteps(int year,
  int month,
  int day,
  double stepMinutes,
  int slot,
  const SunFrame& frame)
{
  std::vector<SunStep> steps;
  const int count = static_cast<int>(std::ceil(1440.0 / stepMinutes - 1e-9));
  const double start = 12.0 - frame.observer.longitudeDeg / 15.0 - 12.0; // UTC hours
  steps.reserve(static_cast<std::size_t>(count));
  for (int k = 0; k < count; ++k)
  {
    const double t0 = k * stepMinutes;
    const double width = std::min(stepMinutes, 1440.0 - t0);
    UTCInstant t;
    t.year = year;
    t.month = month;
    t.day = day;
    t.hours = start + (t0 + 0.5 * width) / 60.0;
    const SolarPosition p = SolarPositionNREL2004(t, frame.observer);
    SunStep s = MakeSunStep(p.azimuthDeg, p.elevationDeg, frame);
    s.utcHours = t.hours;
    s.hours = static_cast<float>(width / 60.0);
    s.energy = static_cast<float>(
      ClearSkyBeamCampbellNorman1998(
        p.elevationDeg, p.earthSunDistanceAU, frame.transmittance, frame.meanElevationM) *
      width / 60.0);
    s.slot = slot;
    s.month = month;
    s.day = day;
    steps.push_back(s);
  }
  return steps;
}

//------------------------------------------------------------------------------
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
  std::size_t cell1)
{
  const std::size_t n = view.Size();
  const std::size_t nx = static_cast<std::size_t>(view.nx);
  auto march = [&](const SunStep& step, std::size_t c, T tanE)
  {
    const int i = static_cast<int>(c % nx);
    const int j = static_cast<int>(c / nx);
    return HorizonTangentRayMarch(view, step.march, source.curvature, i, j, source.zMax, tanE) <
      tanE;
  };
  // Blocks of cells stay in cache while every step passes over them.
  constexpr std::size_t kBlock = 1024;
  for (std::size_t b0 = cell0; b0 < cell1; b0 += kBlock)
  {
    const std::size_t b1 = std::min(cell1, b0 + kBlock);
    for (int si = 0; si < stepCount; ++si)
    {
      const SunStep& step = steps[si];
      const T tanE = static_cast<T>(step.tanElevation);
      if (!(tanE > T(0)))
      {
        continue; // the sun is below the horizontal plane: nothing is lit
      }
      if (!source.map)
      {
        for (std::size_t c = b0; c < b1; ++c)
        {
          if (view.valid ? view.valid[c] != 0 && !std::isnan(view.data[c])
                         : !std::isnan(view.data[c]))
          {
            if (march(step, c, tanE))
            {
              Gain(
                step, normals ? normals + 3 * c : nullptr, hours + slots * c, energy + slots * c);
            }
          }
        }
        continue;
      }
      const T* h0 = source.map + static_cast<std::size_t>(step.sectors.sector0) * n;
      const T* h1 = source.map + static_cast<std::size_t>(step.sectors.sector1) * n;
      const T w1 = static_cast<T>(step.sectors.weight1);
      const T w0 = T(1) - w1;
      for (std::size_t c = b0; c < b1; ++c)
      {
        // No-data cells hold NaN in the map: every comparison is false, they gain nothing.
        const T a = h0[c];
        const T b = h1[c];
        const T h = w0 * a + w1 * b;
        bool lit = tanE > h;
        if (source.refine && tanE > std::min(a, b) && tanE < std::max(a, b))
        {
          lit = march(step, c, tanE);
        }
        if (lit)
        {
          Gain(step, normals ? normals + 3 * c : nullptr, hours + slots * c, energy + slots * c);
        }
      }
    }
  }
}

#define TERROIR_INSTANTIATE(T)                                                                     \
  template void AccumulateIllumination<T>(const GridView<T>&,                                      \
    const ShadowSource<T>&,                                                                        \
    const T*,                                                                                      \
    const SunStep*,                                                                                \
    int,                                                                                           \
    int,                                                                                           \
    T*,                                                                                            \
    T*,                                                                                            \
    std::size_t,                                                                                   \
    std::size_t);
TERROIR_INSTANTIATE(float)
TERROIR_INSTANTIATE(double)
#undef TERROIR_INSTANTIATE

} // namespace terrain
} // namespace terroir

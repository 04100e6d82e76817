#include "ShadowHorizon.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace terroir
{
namespace terrain
{
namespace
{

/// Elevation and validity of cell (u, w) in march coordinates (u major, w minor).
template<typename T>
struct MarchGrid
{
  const GridView<T>& view;
  bool alongX;
  std::size_t Index(int u, int w) const
  {
    return this->alongX ? this->view.Index(u, w) : this->view.Index(w, u);
  }
  bool Valid(std::size_t k) const { return !this->view.valid || this->view.valid[k] != 0; }

  /// Sample at major index u, minor position w0 + f (f in [0, 1)); false when it touches a
  /// no-data cell or leaves the grid (w0 + 1 > nMinor - 1 with f > 0).
  bool Sample(int u, int w0, T f, int nMinor, T& z) const
  {
    if (w0 < 0 || w0 > nMinor - 1 || (f > T(0) && w0 + 1 > nMinor - 1))
    {
      return false;
    }
    const std::size_t k0 = this->Index(u, w0);
    const T z0 = this->view.data[k0];
    if (!this->Valid(k0) || std::isnan(z0))
    {
      return false;
    }
    if (f == T(0))
    {
      z = z0;
      return true;
    }
    const std::size_t k1 = this->Index(u, w0 + 1);
    const T z1 = this->view.data[k1];
    if (!this->Valid(k1) || std::isnan(z1))
    {
      return false;
    }
    z = (T(1) - f) * z0 + f * z1;
    return true;
  }
};

} // namespace

//------------------------------------------------------------------------------
MarchDirection MakeMarchDirection(double gridAzimuthDeg, double dx, double dy)
{
  double az = std::fmod(gridAzimuthDeg, 360.0);
  if (az < 0.0)
  {
    az += 360.0;
  }
  double s = 0.0;
  double c = 0.0;
  if (az == 0.0 || az == 90.0 || az == 180.0 || az == 270.0)
  {
    s = az == 90.0 ? 1.0 : (az == 270.0 ? -1.0 : 0.0);
    c = az == 0.0 ? 1.0 : (az == 180.0 ? -1.0 : 0.0);
  }
  else
  {
    const double rad = az * 3.14159265358979323846 / 180.0;
    s = std::sin(rad);
    c = std::cos(rad);
  }
  const double di = s / std::fabs(dx);
  const double dj = c / std::fabs(dy);
  MarchDirection d;
  d.alongX = std::fabs(di) >= std::fabs(dj);
  const double major = d.alongX ? di : dj;
  const double minor = d.alongX ? dj : di;
  d.step = major > 0.0 ? 1 : -1;
  double slope = minor / std::fabs(major);
  // Directions within rounding of an axis or a diagonal are snapped to it, so that their
  // samples fall on cell centres exactly.
  if (std::fabs(std::fabs(slope) - 1.0) < 1e-9)
  {
    slope = slope > 0.0 ? 1.0 : -1.0;
  }
  if (std::fabs(slope) < 1e-12)
  {
    slope = 0.0;
  }
  d.slope = static_cast<float>(slope);
  d.length = static_cast<float>(1.0 / std::fabs(major));
  return d;
}

//------------------------------------------------------------------------------
float CurvatureCoefficient(bool earthCurvature)
{
  return earthCurvature ? static_cast<float>(1.0 / (2.0 * kEarthRadiusM)) : 0.0f;
}

//------------------------------------------------------------------------------
template<typename T>
T HorizonTangentRayMarch(const GridView<T>& view,
  const MarchDirection& dir,
  float curvature,
  int i,
  int j,
  T zMax,
  T stopTangent)
{
  const MarchGrid<T> grid{ view, dir.alongX };
  const int nMajor = dir.alongX ? view.nx : view.ny;
  const int nMinor = dir.alongX ? view.ny : view.nx;
  const int u = dir.alongX ? i : j;
  const int w = dir.alongX ? j : i;
  const T z0 = view.At(i, j);
  const T slope = static_cast<T>(dir.slope);
  const T length = static_cast<T>(dir.length);
  const T curv = static_cast<T>(curvature);
  const bool decide = std::isfinite(stopTangent);
  T best = -std::numeric_limits<T>::infinity();
  bool found = false;
  for (int k = 1;; ++k)
  {
    const int uk = u + k * dir.step;
    if (uk < 0 || uk > nMajor - 1)
    {
      break;
    }
    const T s = static_cast<T>(k) * length;
    // No later sample can rise above (zMax - z0) / s: stop once that cannot change the answer.
    const T bound = (zMax - z0) / s;
    if (bound <= best || (decide && bound < stopTangent))
    {
      break;
    }
    const T wk = static_cast<T>(w) + static_cast<T>(k) * slope;
    if (wk < T(0) || wk > static_cast<T>(nMinor - 1))
    {
      break;
    }
    const T fl = std::floor(wk);
    T z;
    if (!grid.Sample(uk, static_cast<int>(fl), wk - fl, nMinor, z))
    {
      continue;
    }
    const T t = (z - z0 - curv * s * s) / s;
    found = true;
    if (t > best)
    {
      best = t;
      if (decide && best >= stopTangent)
      {
        break;
      }
    }
  }
  return found ? best : static_cast<T>(kNoHorizon);
}

//------------------------------------------------------------------------------
SweepPlan MakeSweepPlan(const MarchDirection& dir, int nx, int ny)
{
  SweepPlan p;
  p.dir = dir;
  p.nMajor = dir.alongX ? nx : ny;
  p.nMinor = dir.alongX ? ny : nx;
  p.floorAt.resize(static_cast<std::size_t>(p.nMajor));
  p.fracAt.resize(static_cast<std::size_t>(p.nMajor));
  int fMin = 0;
  int fMax = 0;
  for (int u = 0; u < p.nMajor; ++u)
  {
    // Toward the sun the minor position moves by `slope` per step of `step` major cells.
    const double pos = static_cast<double>(dir.slope) * dir.step * u;
    int fl = static_cast<int>(std::floor(pos));
    float fr = static_cast<float>(pos - fl);
    if (fr >= 1.0f)
    {
      fl += 1;
      fr = 0.0f;
    }
    p.floorAt[u] = fl;
    p.fracAt[u] = fr;
    fMin = std::min(fMin, fl);
    fMax = std::max(fMax, fl);
  }
  // Cell (u, w) lies between lines c = w - F_u - 1 and c = w - F_u.
  p.firstLine = -fMax - 1;
  p.lineCount = p.nMinor + fMax - fMin + 1;
  return p;
}

//------------------------------------------------------------------------------
template<typename T>
void SweepLine(const GridView<T>& view,
  const SweepPlan& plan,
  float curvature,
  int m,
  T* lineTangents,
  std::vector<T>& scratch)
{
  const MarchGrid<T> grid{ view, plan.dir.alongX };
  const int n = plan.nMajor;
  if (scratch.size() < 2 * static_cast<std::size_t>(n))
  {
    scratch.resize(2 * static_cast<std::size_t>(n));
  }
  T* hs = scratch.data();     // hull: distances
  T* hw = scratch.data() + n; // hull: heights lowered by the curvature drop
  int top = 0;                // hull size
  const int c = plan.firstLine + m;
  const T length = static_cast<T>(plan.dir.length);
  const T curv = static_cast<T>(curvature);
  const T twoCurv = T(2) * curv;
  const int step = plan.dir.step;
  // Walk from the sun's side back, so the hull always holds the samples ahead.
  for (int q = 0; q < n; ++q)
  {
    const int u = step > 0 ? n - 1 - q : q;
    T z;
    if (!grid.Sample(u, c + plan.floorAt[u], static_cast<T>(plan.fracAt[u]), plan.nMinor, z))
    {
      lineTangents[u] = std::numeric_limits<T>::quiet_NaN();
      continue;
    }
    const T s = static_cast<T>(step * u) * length;
    const T wv = z - curv * s * s;
    while (
      top >= 2 && (hw[top - 2] - wv) / (hs[top - 2] - s) >= (hw[top - 1] - wv) / (hs[top - 1] - s))
    {
      --top;
    }
    lineTangents[u] =
      top > 0 ? (hw[top - 1] - wv) / (hs[top - 1] - s) + twoCurv * s : static_cast<T>(kNoHorizon);
    hs[top] = s;
    hw[top] = wv;
    ++top;
  }
}

//------------------------------------------------------------------------------
template<typename T>
void GatherSweep(const GridView<T>& view,
  const SweepPlan& plan,
  const T* lines,
  T* tangents,
  int u0,
  int u1)
{
  const bool alongX = plan.dir.alongX;
  const std::size_t nMajor = static_cast<std::size_t>(plan.nMajor);
  for (int u = u0; u < u1; ++u)
  {
    const T f = static_cast<T>(plan.fracAt[u]);
    for (int w = 0; w < plan.nMinor; ++w)
    {
      const std::size_t k = alongX ? view.Index(u, w) : view.Index(w, u);
      if ((view.valid && !view.valid[k]) || std::isnan(view.data[k]))
      {
        tangents[k] = std::numeric_limits<T>::quiet_NaN();
        continue;
      }
      const std::size_t mb = static_cast<std::size_t>(w - plan.floorAt[u] - plan.firstLine);
      const T tb = lines[mb * nMajor + u];
      if (f == T(0))
      {
        tangents[k] = std::isnan(tb) ? static_cast<T>(kNoHorizon) : tb;
        continue;
      }
      const T ta = lines[(mb - 1) * nMajor + u];
      if (std::isnan(ta))
      {
        tangents[k] = std::isnan(tb) ? static_cast<T>(kNoHorizon) : tb;
      }
      else
      {
        tangents[k] = std::isnan(tb) ? ta : f * ta + (T(1) - f) * tb;
      }
    }
  }
}

//------------------------------------------------------------------------------
double SectorAzimuth(int k, int sectors)
{
  return 360.0 * k / sectors;
}

//------------------------------------------------------------------------------
SectorLookup LookupSectors(double gridAzimuthDeg, int sectors)
{
  double az = std::fmod(gridAzimuthDeg, 360.0);
  if (az < 0.0)
  {
    az += 360.0;
  }
  const double pos = az * sectors / 360.0;
  int k0 = static_cast<int>(std::floor(pos));
  double w = pos - k0;
  if (k0 >= sectors)
  {
    k0 = 0;
    w = 0.0;
  }
  SectorLookup l;
  l.sector0 = k0;
  l.sector1 = (k0 + 1) % sectors;
  l.weight1 = static_cast<float>(w);
  if (l.weight1 >= 1.0f)
  {
    l.sector0 = l.sector1;
    l.sector1 = (l.sector0 + 1) % sectors;
    l.weight1 = 0.0f;
  }
  return l;
}

//------------------------------------------------------------------------------
template<typename T>
void HorizonMapSectors(const GridView<T>& view,
  int sectors,
  float curvature,
  T* map,
  int k0,
  int k1)
{
  std::vector<T> lines;
  std::vector<T> scratch;
  for (int k = k0; k < k1; ++k)
  {
    const MarchDirection dir = MakeMarchDirection(SectorAzimuth(k, sectors), view.dx, view.dy);
    const SweepPlan plan = MakeSweepPlan(dir, view.nx, view.ny);
    lines.resize(static_cast<std::size_t>(plan.lineCount) * plan.nMajor);
    for (int m = 0; m < plan.lineCount; ++m)
    {
      SweepLine(view,
        plan,
        curvature,
        m,
        lines.data() + static_cast<std::size_t>(m) * plan.nMajor,
        scratch);
    }
    GatherSweep(
      view, plan, lines.data(), map + static_cast<std::size_t>(k) * view.Size(), 0, plan.nMajor);
  }
}

#define TERROIR_INSTANTIATE(T)                                                                     \
  template T HorizonTangentRayMarch<T>(                                                            \
    const GridView<T>&, const MarchDirection&, float, int, int, T, T);                             \
  template void SweepLine<T>(                                                                      \
    const GridView<T>&, const SweepPlan&, float, int, T*, std::vector<T>&);                        \
  template void GatherSweep<T>(const GridView<T>&, const SweepPlan&, const T*, T*, int, int);      \
  template void HorizonMapSectors<T>(const GridView<T>&, int, float, T*, int, int);
TERROIR_INSTANTIATE(float)
TERROIR_INSTANTIATE(double)
#undef TERROIR_INSTANTIATE

} // namespace terrain
} // namespace terroir

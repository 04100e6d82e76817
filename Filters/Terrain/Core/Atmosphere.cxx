#include "Atmosphere.h"

#include "ParameterCheck.h"
#include "RowKernels.h"
#include "Vegetation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace terroir
{
namespace terrain
{

namespace
{

using detail::AddCompensated;
using detail::ForRows;
using detail::SumRows;

constexpr double kDegree = 3.14159265358979323846 / 180.0;
/// Magnus's range (SaturationHumidityRatio); temperatures are clamped into it (ours).
constexpr float kMinTemperature = -80.0f;
constexpr float kMaxTemperature = 60.0f;
/// p / p0 is clamped to [1/2, 2] (ours): e_s(60 C) = 19.9 kPa stays below p.
constexpr float kMinPressureRatio = 0.5f;
constexpr float kMaxPressureRatio = 2.0f;

void Require(bool ok, const char* name, double value, const char* range)
{
  if (!ok)
  {
    detail::BadParameter("atmosphere", name, value, range);
  }
}

/// Per-row float constants: spacings, areas, and the north-south pipes between rows j, j + 1.
struct RowGeometry
{
  std::vector<float> lx, ly, area, lNorth;
  explicit RowGeometry(const AtmosphereState& st)
    : lx(st.ny)
    , ly(st.ny)
    , area(st.ny)
    , lNorth(st.ny, 0.0f)
  {
    for (int j = 0; j < st.ny; ++j)
    {
      lx[j] = static_cast<float>(st.rowDx[j]);
      ly[j] = static_cast<float>(st.rowDy[j]);
      area[j] = static_cast<float>(st.CellArea(j));
      if (j + 1 < st.ny)
      {
        lNorth[j] = static_cast<float>(0.5 * (st.rowDy[j] + st.rowDy[j + 1]));
      }
    }
  }
};

/// Read-only view of one step's arrays and constants.
struct Context
{
  const AtmosphereState& st;
  const AtmosphereParams& p;
  RowGeometry geo;
  float dt;

  Context(const AtmosphereState& state, const AtmosphereParams& params)
    : st(state)
    , p(params)
    , geo(state)
    , dt(static_cast<float>(params.timeStep))
  {
  }
  std::size_t Index(int i, int j) const
  {
    return static_cast<std::size_t>(j) * static_cast<std::size_t>(st.nx) +
      static_cast<std::size_t>(i);
  }
};

/// Air temperature of a valid cell, C: the given one or T0 - Gamma b / 1000, clamped to Magnus's
/// range.
inline float CellTemperature(const AtmosphereParams& p,
  const float* terrain,
  const float* t,
  std::size_t c)
{
  const float value = t ? t[c]
                        : static_cast<float>(p.seaLevelTemperature) -
      static_cast<float>(p.lapseRate * 0.001) * terrain[c];
  return std::min(std::max(value, kMinTemperature), kMaxTemperature);
}

/// Capacity x_s (kg/kg) of a valid cell at air height h: Magnus at T and p = p0 h / h_ref.
inline float CellCapacity(const Context& x,
  const float* terrain,
  const float* t,
  std::size_t c,
  float h)
{
  const double ratio = std::min(
    std::max(static_cast<double>(h) / x.st.referenceHeight, static_cast<double>(kMinPressureRatio)),
    static_cast<double>(kMaxPressureRatio));
  const double temperature = CellTemperature(x.p, terrain, t, c);
  return static_cast<float>(SaturationHumidityRatio(temperature, x.p.surfacePressure * ratio));
}

/// Pass 2 (ComputeOutflow) for rows [j0, j1): new fluxes W, E, S, N of every valid cell.
void OutflowRows(const Context& x, const float* b, float* const f[4], int j0, int j1)
{
  const AtmosphereState& st = x.st;
  const std::size_t nx = static_cast<std::size_t>(st.nx);
  const float g = static_cast<float>(x.p.gravity);
  for (int j = j0; j < j1; ++j)
  {
    const float len[4] = { x.geo.lx[j],
      x.geo.lx[j],
      j > 0 ? x.geo.lNorth[j - 1] : 1.0f,
      j + 1 < st.ny ? x.geo.lNorth[j] : 1.0f };
    for (int i = 0; i < st.nx; ++i)
    {
      const std::size_t c = x.Index(i, j);
      float out[4] = { 0.0f, 0.0f, 0.0f, 0.0f };
      if (st.IsValid(c))
      {
        const bool inside[4] = { i > 0, i + 1 < st.nx, j > 0, j + 1 < st.ny };
        const std::size_t n[4] = { c - 1, c + 1, c - nx, c + nx };
        const float old[4] = { st.fluxW[c], st.fluxE[c], st.fluxS[c], st.fluxN[c] };
        const float h = st.air[c];
        for (int k = 0; k < 4; ++k)
        {
          if (inside[k] && st.IsValid(n[k]))
          {
            const float area = AtmospherePipeArea(x.p, len[k], b[n[k]] - b[c]);
            const float coef = x.dt * g * area / len[k];
            out[k] = std::max(0.0f, old[k] + coef * (h - st.air[n[k]]));
          }
        }
        const float sum = (out[0] + out[1]) + (out[2] + out[3]);
        if (sum > 0.0f)
        {
          const float scale = std::min(1.0f, h * x.geo.area[j] / (sum * x.dt));
          for (float& v : out)
          {
            v *= scale;
          }
        }
      }
      for (int k = 0; k < 4; ++k)
      {
        f[k][c] = out[k];
      }
    }
  }
}

/// Air that flows into cell (i, j) from its four neighbours, m^3/s (walls give nothing).
inline float Inflow(const Context& x, const float* const f[4], int i, int j)
{
  const std::size_t c = x.Index(i, j);
  const std::size_t nx = static_cast<std::size_t>(x.st.nx);
  const float w = i > 0 ? f[1][c - 1] : 0.0f;
  const float e = i + 1 < x.st.nx ? f[0][c + 1] : 0.0f;
  const float s = j > 0 ? f[3][c - nx] : 0.0f;
  const float n = j + 1 < x.st.ny ? f[2][c + nx] : 0.0f;
  return (w + e) + (s + n);
}

/// dW_X and dW_Y of Mei et al.: the mean flux through the cell along x and y, m^3/s.
inline void NetFlux(const Context& x, const float* const f[4], int i, int j, float& fx, float& fy)
{
  const std::size_t c = x.Index(i, j);
  const std::size_t nx = static_cast<std::size_t>(x.st.nx);
  const float inW = i > 0 ? f[1][c - 1] : 0.0f;
  const float outE = i + 1 < x.st.nx ? f[0][c + 1] : 0.0f;
  const float inS = j > 0 ? f[3][c - nx] : 0.0f;
  const float outN = j + 1 < x.st.ny ? f[2][c + nx] : 0.0f;
  fx = 0.5f * ((inW - f[0][c]) + (f[1][c] - outE));
  fy = 0.5f * ((inS - f[2][c]) + (f[3][c] - outN));
}

/// Pass 3 (ComputeAirPressure, ComputeVelocities) for rows [j0, j1): h2 and (u, v).
void AirRows(const Context& x,
  AtmosphereState& st,
  const float* const f[4],
  float* h2,
  int j0,
  int j1)
{
  const float minHeight = static_cast<float>(x.p.minAirHeight);
  for (int j = j0; j < j1; ++j)
  {
    for (int i = 0; i < st.nx; ++i)
    {
      const std::size_t c = x.Index(i, j);
      st.velocityU[c] = 0.0f;
      st.velocityV[c] = 0.0f;
      if (!st.IsValid(c))
      {
        h2[c] = 0.0f;
        continue;
      }
      const float out = (f[0][c] + f[1][c]) + (f[2][c] + f[3][c]);
      float h = st.air[c];
      float& lo = st.airResidue[c]; // only this cell reads or writes it
      AddCompensated(h, lo, x.dt * (Inflow(x, f, i, j) - out) / x.geo.area[j]);
      if (h < 0.0f || static_cast<double>(h) + lo < 0.0)
      {
        h = 0.0f; // K keeps h2 >= 0 up to rounding
        lo = 0.0f;
      }
      h2[c] = h;
      const float mean = 0.5f * (st.air[c] + h);
      if (mean >= minHeight && mean > 0.0f)
      {
        float fx = 0.0f, fy = 0.0f;
        NetFlux(x, f, i, j, fx, fy);
        st.velocityU[c] = fx / (x.geo.ly[j] * mean);
        st.velocityV[c] = fy / (x.geo.lx[j] * mean);
      }
    }
  }
}

/// Bilinear sample of q at (px, py) in cell units, clamped to the grid.
inline float Sample(const Context& x, const float* q, float px, float py)
{
  const int nx = x.st.nx;
  const int ny = x.st.ny;
  // Written so that a NaN position samples cell 0 instead of indexing out of range.
  px = px > 0.0f ? std::min(px, static_cast<float>(nx - 1)) : 0.0f;
  py = py > 0.0f ? std::min(py, static_cast<float>(ny - 1)) : 0.0f;
  const int i0 = std::min(static_cast<int>(px), nx - 1);
  const int j0 = std::min(static_cast<int>(py), ny - 1);
  const int i1 = std::min(i0 + 1, nx - 1);
  const int j1 = std::min(j0 + 1, ny - 1);
  const float fx = px - static_cast<float>(i0);
  const float fy = py - static_cast<float>(j0);
  const float south = q[x.Index(i0, j0)] + fx * (q[x.Index(i1, j0)] - q[x.Index(i0, j0)]);
  const float north = q[x.Index(i0, j1)] + fx * (q[x.Index(i1, j1)] - q[x.Index(i0, j1)]);
  return south + fy * (north - south);
}

/// Pass 4 (ComputeVapourTransport) for rows [j0, j1): back-traced vapour and the row totals.
void AdvectRows(const Context& x,
  const float* q,
  float* moved,
  std::vector<double>& before,
  std::vector<double>& after,
  int j0,
  int j1)
{
  const AtmosphereState& st = x.st;
  for (int j = j0; j < j1; ++j)
  {
    double b = 0.0, a = 0.0;
    for (int i = 0; i < st.nx; ++i)
    {
      const std::size_t c = x.Index(i, j);
      moved[c] = 0.0f;
      if (!st.IsValid(c))
      {
        continue;
      }
      const float di = st.velocityU[c] * x.dt / x.geo.lx[j];
      const float dj = st.velocityV[c] * x.dt / x.geo.ly[j];
      moved[c] = Sample(x, q, static_cast<float>(i) - di, static_cast<float>(j) - dj);
      b += q[c];
      a += moved[c];
    }
    before[j] = b * x.geo.area[j];
    after[j] = a * x.geo.area[j];
  }
}

/// Pass 5 (rescaling by k; rain) for rows [j0, j1): the new vapour, rain out, rain per row.
void RainRows(const Context& x,
  AtmosphereState& st,
  const float* moved,
  double k,
  const float* terrain,
  const float* temperature,
  float* rain,
  std::vector<double>& rowRain,
  int j0,
  int j1)
{
  const float perKg = static_cast<float>(x.p.airColumnMass / x.p.waterDensity); // m per kg/kg
  const float fraction = static_cast<float>(x.p.condensationRate * x.p.timeStep);
  for (int j = j0; j < j1; ++j)
  {
    double fell = 0.0;
    for (int i = 0; i < st.nx; ++i)
    {
      const std::size_t c = x.Index(i, j);
      if (!st.IsValid(c))
      {
        st.vapour[c] = 0.0f;
        continue;
      }
      const float q = static_cast<float>(static_cast<double>(moved[c]) * k);
      const float capacity = CellCapacity(x, terrain, temperature, c, st.air[c]) * perKg;
      const float drop = q > capacity ? fraction * (q - capacity) : 0.0f;
      st.vapour[c] = q - drop;
      if (rain)
      {
        rain[c] += drop;
      }
      fell += drop;
    }
    rowRain[j] = fell * x.geo.area[j];
  }
}

/// Throws when an array of the state does not have nx*ny entries (a state built by hand).
void CheckState(const AtmosphereState& st)
{
  Require(st.nx > 0 && st.ny > 0, "grid size nx*ny", static_cast<double>(st.nx) * st.ny, "> 0");
  Require(st.rowDx.size() == static_cast<std::size_t>(st.ny), "rowDx size", st.rowDx.size(), "ny");
  Require(st.rowDy.size() == static_cast<std::size_t>(st.ny), "rowDy size", st.rowDy.size(), "ny");
  Require(std::isfinite(st.referenceHeight) && st.referenceHeight > 0.0,
    "referenceHeight",
    st.referenceHeight,
    "> 0");
  const std::size_t n = st.Size();
  const std::pair<const char*, std::size_t> sizes[] = { { "air", st.air.size() },
    { "vapour", st.vapour.size() },
    { "fluxW", st.fluxW.size() },
    { "fluxE", st.fluxE.size() },
    { "fluxS", st.fluxS.size() },
    { "fluxN", st.fluxN.size() },
    { "velocityU", st.velocityU.size() },
    { "velocityV", st.velocityV.size() },
    { "airResidue", st.airResidue.size() } };
  for (const auto& s : sizes)
  {
    Require(s.second == n, s.first, static_cast<double>(s.second), "of size nx*ny");
  }
  for (const std::vector<float>& a : st.scratch)
  {
    Require(a.size() == n, "scratch", static_cast<double>(a.size()), "of size nx*ny");
  }
  Require(st.valid.empty() || st.valid.size() == n, "valid", st.valid.size(), "empty or nx*ny");
}

/// Throws unless terrain (and temperature, if given) are finite on every valid cell.
void CheckInputs(const AtmosphereState& st, const float* terrain, const float* temperature)
{
  Require(terrain != nullptr, "terrain", 0.0, "given");
  for (std::size_t c = 0; c < st.Size(); ++c)
  {
    if (st.IsValid(c))
    {
      Require(std::isfinite(terrain[c]), "terrain height", terrain[c], "finite");
      Require(!temperature || std::isfinite(temperature[c]),
        "temperature",
        temperature ? temperature[c] : 0.0,
        "finite");
    }
  }
}

/// Pass 1's weight of cell (i, j): the sum of -(n . d) over its grid edges.
inline float EdgeWeight(const AtmosphereState& st, int i, int j, float dx, float dy)
{
  float w = 0.0f;
  w += i == 0 ? dx : 0.0f;
  w -= i + 1 == st.nx ? dx : 0.0f;
  w += j == 0 ? dy : 0.0f;
  w -= j + 1 == st.ny ? dy : 0.0f;
  return w;
}

/// Runs fn(c, j, weight) over the valid edge cells in a fixed order (rows, then columns).
template<typename Fn>
void ForEdgeCells(const AtmosphereState& st, float dx, float dy, Fn fn)
{
  for (int j = 0; j < st.ny; ++j)
  {
    const bool edgeRow = j == 0 || j + 1 == st.ny;
    for (int i = 0; i < st.nx; i += (edgeRow || i + 1 == st.nx) ? 1 : st.nx - 1)
    {
      const std::size_t c = static_cast<std::size_t>(j) * st.nx + i;
      if (st.IsValid(c))
      {
        fn(c, j, EdgeWeight(st, i, j, dx, dy));
      }
    }
  }
}

/// Direction the prevailing wind blows to, (east, north); components below 1e-12 are zero, so
/// the four cardinal directions are exact.
void BlowDirection(double fromDeg, float& dx, float& dy)
{
  auto snap = [](double v) { return std::fabs(v) < 1e-12 ? 0.0 : v; };
  dx = static_cast<float>(snap(-std::sin(fromDeg * kDegree)));
  dy = static_cast<float>(snap(-std::cos(fromDeg * kDegree)));
}

} // namespace

void CheckAtmosphereParams(const AtmosphereParams& p)
{
  auto finite = [](double v) { return std::isfinite(v); };
  Require(finite(p.timeStep) && p.timeStep > 0.0, "timeStep", p.timeStep, "> 0");
  Require(finite(p.gravity) && p.gravity > 0.0, "gravity", p.gravity, "> 0");
  Require(finite(p.pipeArea) && p.pipeArea >= 0.0, "pipeArea", p.pipeArea, ">= 0");
  Require(
    finite(p.uphillDamping) && p.uphillDamping >= 0.0, "uphillDamping", p.uphillDamping, ">= 0");
  Require(p.minAreaFraction > 0.0 && p.minAreaFraction <= 1.0,
    "minAreaFraction",
    p.minAreaFraction,
    "in (0, 1]");
  Require(finite(p.windDirectionDeg), "windDirectionDeg", p.windDirectionDeg, "finite");
  Require(finite(p.windStrength) && p.windStrength >= 0.0, "windStrength", p.windStrength, ">= 0");
  Require(finite(p.minAirHeight) && p.minAirHeight >= 0.0, "minAirHeight", p.minAirHeight, ">= 0");
  Require(finite(p.seaLevelTemperature), "seaLevelTemperature", p.seaLevelTemperature, "finite");
  Require(finite(p.lapseRate), "lapseRate", p.lapseRate, "finite");
  Require(finite(p.surfacePressure) && p.surfacePressure > 0.0,
    "surfacePressure",
    p.surfacePressure,
    "> 0");
  Require(
    finite(p.airColumnMass) && p.airColumnMass > 0.0, "airColumnMass", p.airColumnMass, "> 0");
  Require(finite(p.condensationRate) && p.condensationRate >= 0.0 &&
      p.condensationRate * p.timeStep <= 1.0,
    "condensationRate",
    p.condensationRate,
    ">= 0 with condensationRate * timeStep <= 1");
  Require(finite(p.waterDensity) && p.waterDensity > 0.0, "waterDensity", p.waterDensity, "> 0");
}

AtmosphereState MakeAtmosphereState(const GridView<float>& grid,
  double airHeight,
  const float* vapour)
{
  Require(grid.nx > 0, "nx", grid.nx, "> 0");
  Require(grid.ny > 0, "ny", grid.ny, "> 0");
  Require(std::isfinite(airHeight) && airHeight > 0.0, "airHeight", airHeight, "> 0");
  AtmosphereState st;
  st.nx = grid.nx;
  st.ny = grid.ny;
  st.rowDx.resize(st.ny);
  st.rowDy.resize(st.ny);
  for (int j = 0; j < st.ny; ++j)
  {
    st.rowDx[j] = grid.DxAt(j);
    st.rowDy[j] = grid.DyAt(j);
    Require(std::isfinite(st.rowDx[j]) && st.rowDx[j] > 0.0, "dx", st.rowDx[j], "> 0");
    Require(std::isfinite(st.rowDy[j]) && st.rowDy[j] > 0.0, "dy", st.rowDy[j], "> 0");
  }
  const std::size_t n = st.Size();
  if (grid.valid)
  {
    st.valid.assign(grid.valid, grid.valid + n);
  }
  st.referenceHeight = airHeight;
  st.air.assign(n, static_cast<float>(airHeight));
  st.vapour.assign(n, 0.0f);
  for (std::size_t c = 0; c < n; ++c)
  {
    if (!st.IsValid(c))
    {
      st.air[c] = 0.0f;
    }
    else if (vapour)
    {
      Require(vapour[c] >= 0.0f && std::isfinite(vapour[c]), "vapour", vapour[c], ">= 0");
      st.vapour[c] = vapour[c];
    }
  }
  for (std::vector<float>* a :
    { &st.airResidue, &st.fluxW, &st.fluxE, &st.fluxS, &st.fluxN, &st.velocityU, &st.velocityV })
  {
    a->assign(n, 0.0f);
  }
  for (std::vector<float>& a : st.scratch)
  {
    a.assign(n, 0.0f);
  }
  return st;
}

float AtmospherePipeArea(const AtmosphereParams& p, float length, float rise)
{
  const float a0 = p.pipeArea > 0.0 ? static_cast<float>(p.pipeArea) : length * length;
  const float uphill = std::max(0.0f, rise / length);
  const float factor = std::min(std::max(1.0f - static_cast<float>(p.uphillDamping) * uphill,
                                  static_cast<float>(p.minAreaFraction)),
    1.0f);
  return a0 * factor;
}

double AtmospherePrevailingWind(AtmosphereState& st, const AtmosphereParams& p)
{
  CheckAtmosphereParams(p);
  CheckState(st);
  float dx = 0.0f, dy = 0.0f;
  BlowDirection(p.windDirectionDeg, dx, dy);
  const float rate = static_cast<float>(p.windStrength * p.timeStep);
  // Totals of the wanted changes: added upwind, removed downwind (at most the air there).
  double added = 0.0, removed = 0.0;
  ForEdgeCells(st,
    dx,
    dy,
    [&](std::size_t c, int j, float w)
    {
      const float delta = rate * w;
      if (delta > 0.0f)
        added += static_cast<double>(delta) * st.CellArea(j);
      else if (delta < 0.0f)
        removed += static_cast<double>(std::min(-delta, st.air[c])) * st.CellArea(j);
    });
  if (added <= 0.0 || removed <= 0.0)
  {
    return 0.0; // nothing to balance against: no net source without a sink
  }
  const float scaleUp = static_cast<float>(std::min(1.0, removed / added));
  const float scaleDown = static_cast<float>(std::min(1.0, added / removed));
  ForEdgeCells(st,
    dx,
    dy,
    [&](std::size_t c, int, float w)
    {
      const float delta = rate * w;
      if (delta > 0.0f)
        AddCompensated(st.air[c], st.airResidue[c], delta * scaleUp);
      else if (delta < 0.0f)
      {
        AddCompensated(st.air[c], st.airResidue[c], -std::min(-delta, st.air[c]) * scaleDown);
        if (st.air[c] <= 0.0f)
        {
          st.air[c] = 0.0f;
          st.airResidue[c] = 0.0f;
        }
      }
    });
  return std::min(added, removed);
}

AtmosphereStepStats AtmosphereStep(AtmosphereState& st,
  const AtmosphereParams& params,
  const float* terrain,
  const float* temperature,
  float* rain,
  const ErosionParallelFor& parallelFor)
{
  CheckAtmosphereParams(params);
  CheckState(st);
  CheckInputs(st, terrain, temperature);
  AtmosphereStepStats stats;
  stats.windAir = AtmospherePrevailingWind(st, params);
  const Context x(st, params);
  const int ny = st.ny;
  std::vector<float>* sc = st.scratch;

  // 2. Outflow into scratch 0-3, swapped into the state.
  float* const fresh[4] = { sc[0].data(), sc[1].data(), sc[2].data(), sc[3].data() };
  ForRows(parallelFor, ny, [&](int j0, int j1) { OutflowRows(x, terrain, fresh, j0, j1); });
  std::swap(st.fluxW, sc[0]);
  std::swap(st.fluxE, sc[1]);
  std::swap(st.fluxS, sc[2]);
  std::swap(st.fluxN, sc[3]);

  // 3. Air height into scratch 4 (swapped in) and velocities.
  const float* const f[4] = { st.fluxW.data(), st.fluxE.data(), st.fluxS.data(), st.fluxN.data() };
  float* h2 = sc[4].data();
  ForRows(parallelFor, ny, [&](int j0, int j1) { AirRows(x, st, f, h2, j0, j1); });
  std::swap(st.air, sc[4]);

  // 4. Vapour transport into scratch 5; Dunn's k from the two totals.
  std::vector<double> before(ny, 0.0), after(ny, 0.0);
  float* moved = sc[5].data();
  ForRows(parallelFor,
    ny,
    [&](int j0, int j1) { AdvectRows(x, st.vapour.data(), moved, before, after, j0, j1); });
  const double m1 = SumRows(before);
  const double m2 = SumRows(after);
  double k = 1.0;
  if (m2 > 0.0)
  {
    k = m1 / m2;
  }
  else
  {
    moved = st.vapour.data(); // nothing moved anywhere: keep the vapour where it is
  }
  stats.vapourScale = k;

  // 5. Rescale and rain.
  std::vector<double> rowRain(ny, 0.0);
  ForRows(parallelFor,
    ny,
    [&](int j0, int j1)
    { RainRows(x, st, moved, k, terrain, temperature, rain, rowRain, j0, j1); });
  stats.rain = SumRows(rowRain);
  return stats;
}

void AtmosphereEvaporationFields(const AtmosphereState& st,
  const AtmosphereParams& params,
  const float* terrain,
  const float* temperature,
  float* saturationRatio,
  float* humidityRatio,
  float* windSpeed,
  const ErosionParallelFor& parallelFor)
{
  CheckAtmosphereParams(params);
  CheckState(st);
  CheckInputs(st, terrain, temperature);
  const Context x(st, params);
  const float perVapour = static_cast<float>(params.waterDensity / params.airColumnMass);
  ForRows(parallelFor,
    st.ny,
    [&](int j0, int j1)
    {
      for (int j = j0; j < j1; ++j)
      {
        for (int i = 0; i < st.nx; ++i)
        {
          const std::size_t c = x.Index(i, j);
          const bool ok = st.IsValid(c);
          if (saturationRatio)
            saturationRatio[c] = ok ? CellCapacity(x, terrain, temperature, c, st.air[c]) : 0.0f;
          if (humidityRatio)
            humidityRatio[c] = ok ? st.vapour[c] * perVapour : 0.0f;
          if (windSpeed)
          {
            const float u = st.velocityU[c], v = st.velocityV[c];
            windSpeed[c] = ok ? std::sqrt(u * u + v * v) : 0.0f;
          }
        }
      }
    });
}

AtmosphereTotals AtmosphereMeasure(const AtmosphereState& st)
{
  CheckState(st);
  AtmosphereTotals t;
  for (int j = 0; j < st.ny; ++j)
  {
    double air = 0.0, vapour = 0.0;
    for (int i = 0; i < st.nx; ++i)
    {
      const std::size_t c = static_cast<std::size_t>(j) * st.nx + i;
      if (st.IsValid(c))
      {
        air += static_cast<double>(st.air[c]) + st.airResidue[c];
        vapour += st.vapour[c];
      }
    }
    t.air += air * st.CellArea(j);
    t.vapour += vapour * st.CellArea(j);
  }
  return t;
}

} // namespace terrain
} // namespace terroir

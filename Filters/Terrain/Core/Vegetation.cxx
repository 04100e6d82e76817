#include "Vegetation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "ParameterCheck.h"
#include "RowKernels.h"

namespace terroir
{
namespace terrain
{

namespace
{

[[noreturn]] void Bad(const char* name, double value, const char* range)
{
  detail::BadParameter("vegetation", name, value, range);
}

void Require(bool ok, const char* name, double value, const char* range)
{
  if (!ok)
  {
    Bad(name, value, range);
  }
}

/// A finite value in [lo, hi].
void RequireIn(double value, double lo, double hi, const char* name, const char* range)
{
  Require(std::isfinite(value) && value >= lo && value <= hi, name, value, range);
}

constexpr double kHuge = 1e300;
constexpr double kMmPerHourToMetresPerSecond = 1e-3 / 3600.0;

/// hi + lo += delta with the rounding error kept in lo (TwoSum), as Erosion.cxx carries the
/// surface water; a result below zero (at most the residue, about 1e-7 of the depth) is zeroed.
inline void SubtractWater(float& hi, float* lo, float amount)
{
  if (!lo)
  {
    hi = std::max(0.0f, hi - amount);
    return;
  }
  const float t = -amount + *lo;
  const float sum = hi + t;
  const float back = sum - hi;
  *lo = (hi - (sum - back)) + (t - back);
  hi = sum;
  if (hi < 0.0f || (hi == 0.0f && *lo < 0.0f))
  {
    hi = 0.0f;
    *lo = 0.0f;
  }
}

using detail::ForRows; // RowKernels.h

/// Sum of per-row partial sums in row order (the same total for any row split).
template<typename T>
T SumRows(const std::vector<T>& rows)
{
  T total = 0;
  for (T r : rows)
  {
    total += r;
  }
  return total;
}

/// Counter-based hash (Wellons' "lowbias32" mixer): the same number for the same counter on
/// any thread, any row split, and in a shader (32-bit integer operations only).
inline std::uint32_t Mix32(std::uint32_t x)
{
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

/// The hash of (seed, step), once per step: the start of every draw of that step.
inline std::uint32_t DrawBase(std::uint32_t seed, std::uint64_t step)
{
  std::uint32_t h = Mix32(seed + 0x9e3779b9U);
  h = Mix32(h ^ static_cast<std::uint32_t>(step));
  return Mix32(h ^ static_cast<std::uint32_t>(step >> 32));
}

/// Uniform float in [0, 1) (24 bits) for the spreading draw of child `cell` from its
/// neighbour `k`, from the step's base.
inline float Draw(std::uint32_t base, std::size_t cell, int k)
{
  std::uint32_t h = Mix32(base ^ static_cast<std::uint32_t>(cell));
  h = Mix32(h ^ static_cast<std::uint32_t>(static_cast<std::uint64_t>(cell) >> 32));
  h = Mix32(h ^ static_cast<std::uint32_t>(k));
  return static_cast<float>(h >> 8) * (1.0f / 16777216.0f);
}

/// The four neighbours, in the order of the spreading rule: E, N, W, S.
constexpr int kDi[4] = { 1, 0, -1, 0 };
constexpr int kDj[4] = { 0, 1, 0, -1 };

/// Geometry shared by the passes.
struct Grid
{
  const VegetationState& st;
  std::vector<float> area; ///< cell area of row j, m^2

  explicit Grid(const VegetationState& state)
    : st(state)
    , area(state.ny)
  {
    for (int j = 0; j < state.ny; ++j)
    {
      area[j] = static_cast<float>(state.CellArea(j));
    }
  }
  std::size_t Index(int i, int j) const
  {
    return static_cast<std::size_t>(j) * static_cast<std::size_t>(st.nx) +
      static_cast<std::size_t>(i);
  }
  /// The valid neighbour k of (i, j), if any.
  bool Neighbour(int i, int j, int k, std::size_t& n) const
  {
    const int ii = i + kDi[k];
    const int jj = j + kDj[k];
    if (ii < 0 || jj < 0 || ii >= st.nx || jj >= st.ny)
    {
      return false;
    }
    n = this->Index(ii, jj);
    return st.IsValid(n);
  }
};

/// Float constants and the arrays of pass 2 (after absorption).
struct LifeContext : Grid
{
  float shareK, shareT, seedV, seedW, phi, prob, growth, growW, droughtW, droughtD, drownDepth,
    drownD;
  std::uint32_t base;        ///< DrawBase(seed, step)
  const float* d;            ///< surface water after absorption
  const float* w;            ///< stored water after absorption
  const float* v;            ///< density at the step's start
  const std::int8_t* chosen; ///< ChosenParent of every cell (pass 2a)

  LifeContext(const VegetationState& state, const VegetationParams& p, double dt)
    : Grid(state)
    , shareK(static_cast<float>(p.shareRate * dt / 4.0))
    , shareT(static_cast<float>(p.shareThreshold))
    , seedV(static_cast<float>(p.seedDensity))
    , seedW(static_cast<float>(p.seedWater))
    , phi(static_cast<float>(p.seedWaterFraction))
    , prob(static_cast<float>(-std::expm1(-p.spreadRate * dt)))
    , growth(static_cast<float>(p.growthRate * dt))
    , growW(static_cast<float>(p.growthWater))
    , droughtW(static_cast<float>(p.droughtWater))
    , droughtD(static_cast<float>(p.droughtRate * dt))
    , drownDepth(static_cast<float>(p.drownDepth))
    , drownD(static_cast<float>(p.drownRate * dt))
    , base(DrawBase(p.seed, state.step))
    , d(nullptr)
    , w(nullptr)
    , v(nullptr)
    , chosen(nullptr)
  {
  }

  bool Drowned(std::size_t c) const { return this->d[c] > this->drownDepth; }
  /// A cell able to seed its empty neighbours.
  bool Parent(std::size_t c) const
  {
    return this->v[c] >= this->seedV && this->w[c] >= this->seedW && !this->Drowned(c);
  }
  /// An empty cell that can be seeded.
  bool Child(std::size_t c) const { return this->v[c] == 0.0f && !this->Drowned(c); }
  /// The neighbour (0-3) that seeds the valid cell (i, j) this step, or -1 (pass 2a; the
  /// child and its parents then read the same answer).
  int ChosenParent(int i, int j) const
  {
    const std::size_t c = this->Index(i, j);
    if (!this->Child(c) || this->prob <= 0.0f)
    {
      return -1;
    }
    for (int k = 0; k < 4; ++k)
    {
      std::size_t n = 0;
      if (this->Neighbour(i, j, k, n) && this->Parent(n) && Draw(this->base, c, k) < this->prob)
      {
        return k;
      }
    }
    return -1;
  }
  /// Depth that a vegetated cell with store wg passes a vegetated neighbour with store wr.
  float Share(float wg, float wr) const
  {
    return this->shareK * std::max(0.0f, std::min(wg - this->shareT, wg - wr));
  }
};

/// Per-row sums of a step (indexed by row; summed in row order).
struct RowSums
{
  std::vector<double> absorbedSurface, absorbedSoil, shared, seedWater, cover;
  std::vector<long long> seeded, grown, drought, drowned;

  explicit RowSums(int ny)
    : absorbedSurface(ny, 0.0)
    , absorbedSoil(ny, 0.0)
    , shared(ny, 0.0)
    , seedWater(ny, 0.0)
    , cover(ny, 0.0)
    , seeded(ny, 0)
    , grown(ny, 0)
    , drought(ny, 0)
    , drowned(ny, 0)
  {
  }
};

/// Pass 1 for rows [j0, j1): uptake from the surface water, then the soil water, into wOut.
void AbsorbRows(const Grid& g,
  const VegetationParams& p,
  double dt,
  const VegetationWater& water,
  float* wOut,
  RowSums& sums,
  int j0,
  int j1)
{
  const VegetationState& st = g.st;
  const float uptake = static_cast<float>(p.absorptionRate * dt);
  const float storage = static_cast<float>(p.storage);
  for (int j = j0; j < j1; ++j)
  {
    double fromSurface = 0.0, fromSoil = 0.0;
    for (int i = 0; i < st.nx; ++i)
    {
      const std::size_t c = g.Index(i, j);
      float w = st.stored[c];
      if (st.IsValid(c))
      {
        const float want = std::min(uptake * st.density[c], std::max(0.0f, storage - w));
        const float a = std::min(water.surface[c], want);
        SubtractWater(
          water.surface[c], water.surfaceResidue ? water.surfaceResidue + c : nullptr, a);
        float b = 0.0f;
        if (water.soil)
        {
          b = std::min(water.soil[c], want - a);
          water.soil[c] = std::max(0.0f, water.soil[c] - b);
        }
        w = (w + a) + b;
        fromSurface += static_cast<double>(a) * g.area[j];
        fromSoil += static_cast<double>(b) * g.area[j];
      }
      wOut[c] = w;
    }
    sums.absorbedSurface[j] = fromSurface;
    sums.absorbedSoil[j] = fromSoil;
  }
}

/// The new density of a cell that was not seeded, and which rule applied (0 none, 1 drowned,
/// 2 drought, 3 grown).
inline float NewDensity(const LifeContext& x, std::size_t c, int& rule)
{
  const float v = x.v[c];
  const float w = x.w[c];
  rule = 0;
  if (v <= 0.0f)
  {
    return v;
  }
  if (x.Drowned(c))
  {
    rule = 1;
    return std::max(0.0f, v - x.drownD);
  }
  if (w <= x.droughtW)
  {
    rule = 2;
    return std::max(0.0f, v - x.droughtD);
  }
  if (w >= x.growW)
  {
    rule = 3;
    return std::min(1.0f, v + x.growth);
  }
  return v;
}

/// Pass 2a for rows [j0, j1): which neighbour seeds each cell (-1: none).
void ChooseRows(const LifeContext& x, std::int8_t* chosen, int j0, int j1)
{
  for (int j = j0; j < j1; ++j)
  {
    for (int i = 0; i < x.st.nx; ++i)
    {
      const std::size_t c = x.Index(i, j);
      chosen[c] = static_cast<std::int8_t>(x.st.IsValid(c) ? x.ChosenParent(i, j) : -1);
    }
  }
}

/// Pass 2b for rows [j0, j1): sharing, spreading, growth and death into wOut, vOut.
void LifeRows(const LifeContext& x, float* wOut, float* vOut, RowSums& sums, int j0, int j1)
{
  const VegetationState& st = x.st;
  for (int j = j0; j < j1; ++j)
  {
    double shared = 0.0, seedWater = 0.0, cover = 0.0;
    long long seeded = 0, counts[4] = { 0, 0, 0, 0 };
    float ratio[4]; // a_n / a_c of the neighbours in row j + kDj[k]
    for (int k = 0; k < 4; ++k)
    {
      const int jn = std::min(std::max(j + kDj[k], 0), st.ny - 1);
      ratio[k] = x.area[jn] / x.area[j];
    }
    for (int i = 0; i < st.nx; ++i)
    {
      const std::size_t c = x.Index(i, j);
      wOut[c] = x.w[c];
      vOut[c] = x.v[c];
      // Invalid, or empty and not seeded: no sharing, no giving, no receiving.
      if (!st.IsValid(c) || (x.v[c] <= 0.0f && x.chosen[c] < 0))
      {
        continue;
      }
      const float w = x.w[c];
      float out = 0.0f, in = 0.0f, given = 0.0f;
      const bool vegetated = x.v[c] > 0.0f;
      const bool parent = x.Parent(c);
      const float gift = x.phi * w;
      const int chosen = x.chosen[c];
      for (int k = 0; k < 4; ++k)
      {
        std::size_t n = 0;
        if (!x.Neighbour(i, j, k, n))
        {
          continue;
        }
        // Selects rather than branches (random patterns mispredict); adding 0 changes nothing.
        const float wn = x.w[n];
        const bool both = vegetated && x.v[n] > 0.0f;
        const float o = x.Share(w, wn);
        const float r = x.Share(wn, w) * ratio[k];
        out += both ? o : 0.0f;
        in += both ? r : 0.0f;
        given += (parent && x.chosen[n] == (k + 2) % 4) ? gift : 0.0f;
        if (k == chosen)
        {
          in += (x.phi * wn) * ratio[k];
          seedWater += static_cast<double>(x.phi * wn) * x.area[j + kDj[k]];
        }
      }
      shared += static_cast<double>(out) * x.area[j];
      wOut[c] = std::max(0.0f, ((w - out) - given) + in);
      int rule = 0;
      if (chosen >= 0)
      {
        vOut[c] = std::min(1.0f, x.growth);
        ++seeded;
      }
      else
      {
        vOut[c] = NewDensity(x, c, rule);
        ++counts[rule];
      }
      cover += static_cast<double>(vOut[c]) * x.area[j];
    }
    sums.shared[j] = shared;
    sums.seedWater[j] = seedWater;
    sums.cover[j] = cover;
    sums.seeded[j] = seeded;
    sums.drowned[j] = counts[1];
    sums.drought[j] = counts[2];
    sums.grown[j] = counts[3];
  }
}

/// Throws std::invalid_argument when an array of the state does not have its size.
void CheckState(const VegetationState& st)
{
  Require(st.nx > 0 && st.ny > 0, "grid size nx*ny", static_cast<double>(st.nx) * st.ny, "> 0");
  const std::size_t n = st.Size();
  Require(st.rowDx.size() == static_cast<std::size_t>(st.ny),
    "rowDx size",
    static_cast<double>(st.rowDx.size()),
    "ny");
  Require(st.rowDy.size() == static_cast<std::size_t>(st.ny),
    "rowDy size",
    static_cast<double>(st.rowDy.size()),
    "ny");
  const std::pair<const char*, std::size_t> sizes[] = { { "density size", st.density.size() },
    { "stored size", st.stored.size() },
    { "scratch size", st.scratch[0].size() },
    { "scratch size", st.scratch[1].size() } };
  for (const auto& s : sizes)
  {
    Require(s.second == n, s.first, static_cast<double>(s.second), "nx*ny (MakeVegetationState)");
  }
  Require(st.valid.empty() || st.valid.size() == n,
    "valid size",
    static_cast<double>(st.valid.size()),
    "empty or nx*ny");
}

void CheckStep(const VegetationState& st, const VegetationWater& water, double dt)
{
  CheckState(st);
  Require(water.surface != nullptr, "surface water", 0.0, "given");
  Require(std::isfinite(dt) && dt > 0.0, "dt", dt, "> 0");
}

} // namespace

double CanopyEvaporationDunn2015(CanopyType type)
{
  switch (type)
  {
    case CanopyType::ScotsPine:
      return 0.19;
    case CanopyType::MontereyPine:
      return 0.21;
    case CanopyType::SitkaSpruce:
      return 0.18;
    case CanopyType::DouglasFir:
      return 0.15;
    case CanopyType::CommonBeech:
      return 0.45;
    case CanopyType::SouthernBeeches:
      return 0.37;
  }
  Bad("canopy type", static_cast<double>(type), "one of Table 2.1's six (0 to 5)");
}

void CheckVegetationParams(const VegetationParams& p)
{
  RequireIn(p.absorptionRate, 0.0, kHuge, "absorptionRate", ">= 0");
  Require(std::isfinite(p.storage) && p.storage > 0.0, "storage", p.storage, "> 0");
  RequireIn(p.shareThreshold, 0.0, kHuge, "shareThreshold", ">= 0");
  RequireIn(p.shareRate, 0.0, kHuge, "shareRate", ">= 0");
  Require(p.seedDensity > 0.0 && p.seedDensity <= 1.0, "seedDensity", p.seedDensity, "in (0, 1]");
  RequireIn(p.seedWater, 0.0, kHuge, "seedWater", ">= 0");
  RequireIn(p.seedWaterFraction, 0.0, 0.25, "seedWaterFraction", "in [0, 0.25]");
  RequireIn(p.spreadRate, 0.0, kHuge, "spreadRate", ">= 0");
  RequireIn(p.growthRate, 0.0, kHuge, "growthRate", ">= 0");
  RequireIn(p.growthWater, 0.0, kHuge, "growthWater", ">= 0");
  RequireIn(p.droughtWater, 0.0, kHuge, "droughtWater", ">= 0");
  RequireIn(p.droughtRate, 0.0, kHuge, "droughtRate", ">= 0");
  RequireIn(p.drownDepth, 0.0, kHuge, "drownDepth", ">= 0");
  RequireIn(p.drownRate, 0.0, kHuge, "drownRate", ">= 0");
  Require(std::isfinite(p.slipKillDepth) && p.slipKillDepth > 0.0,
    "slipKillDepth",
    p.slipKillDepth,
    "> 0");
  RequireIn(p.erosionFactorFull, 0.0, 1.0, "erosionFactorFull", "in [0, 1]");
  RequireIn(p.talusFactorFull, 1.0, kHuge, "talusFactorFull", ">= 1");
}

void CheckEvaporationParams(const EvaporationParams& p)
{
  RequireIn(p.canopyRate, 0.0, kHuge, "canopyRate", ">= 0");
  RequireIn(p.canopyMinRate, 0.0, p.canopyRate, "canopyMinRate", "in [0, canopyRate]");
  RequireIn(p.saturationRatio, 0.0, kHuge, "saturationRatio", ">= 0");
  RequireIn(p.humidityRatio, 0.0, kHuge, "humidityRatio", ">= 0");
  RequireIn(p.windSpeed, 0.0, kHuge, "windSpeed", ">= 0");
  Require(
    std::isfinite(p.waterDensity) && p.waterDensity > 0.0, "waterDensity", p.waterDensity, "> 0");
  RequireIn(p.scale, 0.0, kHuge, "scale", ">= 0");
}

VegetationState MakeVegetationState(const GridView<float>& density, const float* stored)
{
  Require(density.nx > 0, "nx", density.nx, "> 0");
  Require(density.ny > 0, "ny", density.ny, "> 0");
  VegetationState st;
  st.nx = density.nx;
  st.ny = density.ny;
  st.rowDx.resize(st.ny);
  st.rowDy.resize(st.ny);
  for (int j = 0; j < st.ny; ++j)
  {
    st.rowDx[j] = density.DxAt(j);
    st.rowDy[j] = density.DyAt(j);
    Require(std::isfinite(st.rowDx[j]) && st.rowDx[j] > 0.0, "dx", st.rowDx[j], "> 0");
    Require(std::isfinite(st.rowDy[j]) && st.rowDy[j] > 0.0, "dy", st.rowDy[j], "> 0");
  }
  const std::size_t n = st.Size();
  if (density.valid)
  {
    st.valid.assign(density.valid, density.valid + n);
  }
  st.density.assign(n, 0.0f);
  st.stored.assign(n, 0.0f);
  for (std::size_t c = 0; c < n; ++c)
  {
    if (!st.IsValid(c))
    {
      continue;
    }
    if (density.data)
    {
      st.density[c] = density.data[c];
      Require(
        st.density[c] >= 0.0f && st.density[c] <= 1.0f, "density", st.density[c], "in [0, 1]");
    }
    if (stored)
    {
      st.stored[c] = stored[c];
      Require(
        std::isfinite(st.stored[c]) && st.stored[c] >= 0.0f, "stored water", st.stored[c], ">= 0");
    }
  }
  for (std::vector<float>& a : st.scratch)
  {
    a.assign(n, 0.0f);
  }
  st.scratchChosen.assign(n, -1);
  return st;
}

VegetationStepStats VegetationStep(VegetationState& st,
  const VegetationWater& water,
  double dt,
  const VegetationParams& p,
  const ErosionParallelFor& parallelFor)
{
  CheckStep(st, water, dt);
  CheckVegetationParams(p);
  const double out = p.shareRate * dt + 4.0 * p.seedWaterFraction;
  Require(out <= 1.0, "shareRate * dt + 4 * seedWaterFraction", out, "<= 1");
  RowSums sums(st.ny);
  LifeContext x(st, p, dt);
  float* absorbed = st.scratch[0].data();
  ForRows(parallelFor,
    st.ny,
    [&](int j0, int j1) { AbsorbRows(x, p, dt, water, absorbed, sums, j0, j1); });
  x.d = water.surface;
  x.w = absorbed;
  x.v = st.density.data();
  st.scratchChosen.resize(st.Size());
  std::int8_t* chosen = st.scratchChosen.data();
  ForRows(parallelFor, st.ny, [&](int j0, int j1) { ChooseRows(x, chosen, j0, j1); });
  x.chosen = chosen;
  float* vNew = st.scratch[1].data();
  float* wNew = st.stored.data();
  ForRows(parallelFor, st.ny, [&](int j0, int j1) { LifeRows(x, wNew, vNew, sums, j0, j1); });
  st.density.swap(st.scratch[1]);
  ++st.step;
  VegetationStepStats s;
  s.absorbedSurface = SumRows(sums.absorbedSurface);
  s.absorbedSoil = SumRows(sums.absorbedSoil);
  s.shared = SumRows(sums.shared);
  s.seedWater = SumRows(sums.seedWater);
  s.cover = SumRows(sums.cover);
  s.seeded = SumRows(sums.seeded);
  s.grown = SumRows(sums.grown);
  s.drought = SumRows(sums.drought);
  s.drowned = SumRows(sums.drowned);
  return s;
}

EvaporationStats EvaporationDunn2015Step(VegetationState& st,
  const VegetationWater& water,
  double dt,
  const VegetationParams& vegetation,
  const EvaporationParams& p,
  const EvaporationFields& fields,
  const ErosionParallelFor& parallelFor)
{
  CheckStep(st, water, dt);
  CheckVegetationParams(vegetation);
  CheckEvaporationParams(p);
  const Grid g(st);
  // Eq. 2.6 as a depth rate: Theta (x_s - x) / (3600 rho_w), m/s; Table 2.1 mm/h to m/s.
  const float waterK = static_cast<float>(p.scale / (3600.0 * p.waterDensity));
  const float canopyFull = static_cast<float>(p.scale * p.canopyRate * kMmPerHourToMetresPerSecond);
  const float canopyMin =
    static_cast<float>(p.scale * p.canopyMinRate * kMmPerHourToMetresPerSecond);
  const float storage = static_cast<float>(vegetation.storage);
  const float fdt = static_cast<float>(dt);
  std::vector<double> rowWater(st.ny, 0.0), rowCanopy(st.ny, 0.0);
  auto rows = [&](int j0, int j1)
  {
    for (int j = j0; j < j1; ++j)
    {
      double fromWater = 0.0, fromCanopy = 0.0;
      for (int i = 0; i < st.nx; ++i)
      {
        const std::size_t c = g.Index(i, j);
        if (!st.IsValid(c))
        {
          continue;
        }
        const float xs = fields.saturationRatio ? fields.saturationRatio[c]
                                                : static_cast<float>(p.saturationRatio);
        const float xa =
          fields.humidityRatio ? fields.humidityRatio[c] : static_cast<float>(p.humidityRatio);
        const float wind = fields.windSpeed ? fields.windSpeed[c] : static_cast<float>(p.windSpeed);
        const float theta = 25.0f + 19.0f * std::max(0.0f, wind); // NaN or < 0: still air
        const float ew = std::min(water.surface[c], waterK * theta * std::max(0.0f, xs - xa) * fdt);
        SubtractWater(
          water.surface[c], water.surfaceResidue ? water.surfaceResidue + c : nullptr, ew);
        const float w = st.stored[c];
        const float wet = std::min(1.0f, w / storage);
        const float ec =
          std::min(w, st.density[c] * (canopyMin + (canopyFull - canopyMin) * wet) * fdt);
        st.stored[c] = w - ec;
        if (fields.vapour)
        {
          fields.vapour[c] += ew + ec;
        }
        fromWater += static_cast<double>(ew) * g.area[j];
        fromCanopy += static_cast<double>(ec) * g.area[j];
      }
      rowWater[j] = fromWater;
      rowCanopy[j] = fromCanopy;
    }
  };
  ForRows(parallelFor, st.ny, rows);
  EvaporationStats s;
  s.fromWater = SumRows(rowWater);
  s.fromCanopy = SumRows(rowCanopy);
  return s;
}

double EvaporationCoefficientDunn2015(double windSpeed)
{
  RequireIn(windSpeed, 0.0, kHuge, "windSpeed", ">= 0");
  return 25.0 + 19.0 * windSpeed;
}

double OpenWaterEvaporationDunn2015(double area,
  double windSpeed,
  double saturationRatio,
  double humidityRatio)
{
  RequireIn(area, 0.0, kHuge, "area", ">= 0");
  RequireIn(saturationRatio, 0.0, kHuge, "saturationRatio", ">= 0");
  RequireIn(humidityRatio, 0.0, kHuge, "humidityRatio", ">= 0");
  return EvaporationCoefficientDunn2015(windSpeed) * area * (saturationRatio - humidityRatio) /
    3600.0;
}

double SaturationHumidityRatio(double temperatureC, double pressure)
{
  RequireIn(temperatureC, -80.0, 60.0, "temperatureC", "in [-80, 60]");
  const double es = 610.94 * std::exp(17.625 * temperatureC / (temperatureC + 243.04));
  Require(std::isfinite(pressure) && pressure > es, "pressure", pressure, "> the vapour pressure");
  return 0.622 * es / (pressure - es);
}

float VegetationErosionFactor(float density, const VegetationParams& p)
{
  const float v = std::min(1.0f, std::max(0.0f, density));
  return 1.0f - (1.0f - static_cast<float>(p.erosionFactorFull)) * v;
}

float VegetationTalusFactor(float density, const VegetationParams& p)
{
  const float v = std::min(1.0f, std::max(0.0f, density));
  return 1.0f + (static_cast<float>(p.talusFactorFull) - 1.0f) * v;
}

void VegetationResistance(const VegetationState& st,
  const VegetationParams& p,
  float* erosionFactor,
  float* talusFactor)
{
  CheckState(st);
  CheckVegetationParams(p);
  for (std::size_t c = 0; c < st.Size(); ++c)
  {
    const float v = st.IsValid(c) ? st.density[c] : 0.0f;
    if (erosionFactor)
    {
      erosionFactor[c] = VegetationErosionFactor(v, p);
    }
    if (talusFactor)
    {
      talusFactor[c] = VegetationTalusFactor(v, p);
    }
  }
}

double VegetationSlipDamage(VegetationState& st,
  const float* bedBefore,
  const float* bedAfter,
  const VegetationParams& p,
  const ErosionParallelFor& parallelFor)
{
  CheckState(st);
  CheckVegetationParams(p);
  Require(bedBefore && bedAfter, "bed before/after", 0.0, "given");
  const Grid g(st);
  const float inverse = static_cast<float>(1.0 / p.slipKillDepth);
  std::vector<double> rowLost(st.ny, 0.0);
  ForRows(parallelFor,
    st.ny,
    [&](int j0, int j1)
    {
      for (int j = j0; j < j1; ++j)
      {
        double lost = 0.0;
        for (int i = 0; i < st.nx; ++i)
        {
          const std::size_t c = g.Index(i, j);
          if (!st.IsValid(c))
          {
            continue;
          }
          const float v = st.density[c];
          st.density[c] = std::max(0.0f, v - std::fabs(bedAfter[c] - bedBefore[c]) * inverse);
          lost += static_cast<double>(v - st.density[c]) * g.area[j];
        }
        rowLost[j] = lost;
      }
    });
  return SumRows(rowLost);
}

VegetationTotals VegetationMeasure(const VegetationState& st)
{
  CheckState(st);
  VegetationTotals t;
  for (int j = 0; j < st.ny; ++j)
  {
    double cover = 0.0, stored = 0.0;
    for (int i = 0; i < st.nx; ++i)
    {
      const std::size_t c = static_cast<std::size_t>(j) * st.nx + i;
      if (st.IsValid(c))
      {
        cover += st.density[c];
        stored += st.stored[c];
      }
    }
    t.cover += cover * st.CellArea(j);
    t.stored += stored * st.CellArea(j);
  }
  return t;
}

} // namespace terrain
} // namespace terroir

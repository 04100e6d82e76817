#include "Erosion.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
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
  detail::BadParameter("erosion", name, value, range);
}

void Require(bool ok, const char* name, double value, const char* range)
{
  if (!ok)
  {
    Bad(name, value, range);
  }
}

// AddCompensated, ForRows and SumRows: RowKernels.h (shared with the other terrain cores).
using detail::AddCompensated;
using detail::ForRows;
using detail::SumRows;

/// The vectorised loops are also built for AVX2 and picked at run time where the CPU has it
/// (GCC's target_clones): the same IEEE operations on wider vectors, so the same bits (the
/// library is built with -ffp-contract=off, and "avx2" does not enable FMA).
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define TERROIR_EROSION_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define TERROIR_EROSION_CLONES
#endif

/// m ? a : b by bit masks: no branch, so that loops with it vectorise (the same bits).
inline float Select(bool m, float a, float b)
{
  std::uint32_t ua, ub;
  std::memcpy(&ua, &a, sizeof ua);
  std::memcpy(&ub, &b, sizeof ub);
  const std::uint32_t mask = 0u - static_cast<std::uint32_t>(m);
  const std::uint32_t r = (ua & mask) | (ub & ~mask);
  float out;
  std::memcpy(&out, &r, sizeof out);
  return out;
}

/// Per-row float constants shared by the passes. Pipe k of row j: its length and its
/// coefficient dt g A / l. A north-south pipe between rows j and j + 1 uses the mean spacing
/// of the two rows, so both of its directions have the same length.
struct RowGeometry
{
  std::vector<float> lx, ly, area;      ///< spacing and cell area of row j
  std::vector<float> lNorth;            ///< length of the pipe from row j to j + 1 (ny - 1 used)
  std::vector<float> lxNorth;           ///< mean east-west spacing of rows j and j + 1
  std::vector<float> coefEW, coefNorth; ///< dt g A / l of the pipes
};

RowGeometry MakeGeometry(const ErosionState& st, double dt, double g, double pipeArea)
{
  RowGeometry geo;
  const int ny = st.ny;
  geo.lx.resize(ny);
  geo.ly.resize(ny);
  geo.area.resize(ny);
  geo.lNorth.assign(ny, 0.0f);
  geo.lxNorth.assign(ny, 0.0f);
  geo.coefEW.resize(ny);
  geo.coefNorth.assign(ny, 0.0f);
  auto coef = [&](double l) { return dt * g * (pipeArea > 0.0 ? pipeArea / l : l); };
  for (int j = 0; j < ny; ++j)
  {
    geo.lx[j] = static_cast<float>(st.rowDx[j]);
    geo.ly[j] = static_cast<float>(st.rowDy[j]);
    geo.area[j] = static_cast<float>(st.CellArea(j));
    geo.coefEW[j] = static_cast<float>(coef(st.rowDx[j]));
    if (j + 1 < ny)
    {
      const double l = 0.5 * (st.rowDy[j] + st.rowDy[j + 1]);
      geo.lNorth[j] = static_cast<float>(l);
      geo.lxNorth[j] = static_cast<float>(0.5 * (st.rowDx[j] + st.rowDx[j + 1]));
      geo.coefNorth[j] = static_cast<float>(coef(l));
    }
  }
  return geo;
}

/// Which rows have no no-data cell: the rows that the vectorised loops run (the others, and
/// the first and last cell of a row, run cell by cell).
class RowValidity
{
public:
  explicit RowValidity(const ErosionState& st)
    : nx(st.nx)
    , valid(static_cast<std::size_t>(st.ny), 1)
  {
    if (st.valid.empty())
    {
      return;
    }
    for (int j = 0; j < st.ny; ++j)
    {
      const std::uint8_t* row = st.valid.data() + static_cast<std::size_t>(j) * st.nx;
      valid[j] = std::all_of(row, row + st.nx, [](std::uint8_t v) { return v != 0; });
    }
  }
  /// Row j has only valid cells.
  bool Valid(int j) const { return this->valid[j] != 0; }
  /// Cells 1..nx-2 of row j have all eight neighbours, all valid.
  bool Interior(int j) const
  {
    const int ny = static_cast<int>(this->valid.size());
    return j > 0 && j + 1 < ny && this->nx >= 3 && this->Valid(j - 1) && this->Valid(j) &&
      this->Valid(j + 1);
  }

private:
  int nx;
  std::vector<std::uint8_t> valid;
};

/// What a cell is during one hydraulic step (fixed at the step's start).
enum CellKind : std::uint8_t
{
  kWall = 0, ///< no data, Closed boundary: its pipes are closed
  kSea = 1,  ///< Sea boundary: no data, or b <= seaLevel
  kLand = 2  ///< holds water, gives it, erodes
};

/// Read-only view of the arrays and constants of one hydraulic step.
struct HydraulicContext
{
  const ErosionState& st;
  const ErosionParams& p;
  RowGeometry geo;
  bool sea;
  float seaLevel, dt, dryDepth;
  const std::uint8_t* kind; ///< CellKind of every cell, written by pass 1a (SurfaceRows)
  RowValidity rows;

  HydraulicContext(const ErosionState& state, const ErosionParams& params)
    : st(state)
    , p(params)
    , geo(MakeGeometry(state, params.timeStep, params.gravity, params.pipeArea))
    , sea(params.boundary == ErosionBoundary::Sea)
    , seaLevel(static_cast<float>(params.seaLevel))
    , dt(static_cast<float>(params.timeStep))
    , dryDepth(static_cast<float>(params.dryDepth))
    , kind(state.scratchKind.data())
    , rows(state)
  {
  }

  std::size_t Index(int i, int j) const
  {
    return static_cast<std::size_t>(j) * static_cast<std::size_t>(st.nx) +
      static_cast<std::size_t>(i);
  }
  /// A sea cell (Sea boundary only): no data, or bed at or below sea level at the step's start.
  bool IsSea(std::size_t c) const { return this->kind[c] == kSea; }
  /// A valid cell that is not sea: it holds water, gives it and erodes.
  bool IsLand(std::size_t c) const { return this->kind[c] == kLand; }
};

/// Dunn's soft outflow threshold (eq. 3.1): O_min and s_O, or off.
struct SoftThreshold
{
  bool on;
  float min, scale;
};

/// One pipe's new flux: max(0, f + coef dh), capped at O_min + s_O |dh| when enabled.
inline float PipeFlux(const SoftThreshold& soft, float old, float coef, float dh)
{
  float f = std::max(0.0f, old + coef * dh);
  if (soft.on)
  {
    f = std::min(f, soft.min + soft.scale * std::fabs(dh));
  }
  return f;
}

/// Pass 1a (rain, eq. 10) for row j, cell by cell (any grid): each cell's kind, d1 (its
/// residue in place) and water surface (b + d1 on land, seaLevel on sea).
void SurfaceCells(const HydraulicContext& h,
  const float* rain,
  float* waterLo,
  std::uint8_t* kind,
  float* d1,
  float* surface,
  std::vector<double>& rowRain,
  int j)
{
  const ErosionState& st = h.st;
  const float area = h.geo.area[j];
  double rained = 0.0;
  for (int i = 0; i < st.nx; ++i)
  {
    const std::size_t c = h.Index(i, j);
    if (!st.IsValid(c))
    {
      kind[c] = h.sea ? kSea : kWall;
      d1[c] = 0.0f;
      waterLo[c] = 0.0f;
      surface[c] = h.seaLevel;
      continue;
    }
    float depth = st.water[c];
    if (rain)
    {
      const float added = h.dt * rain[c];
      AddCompensated(depth, waterLo[c], added);
      rained += static_cast<double>(added) * area;
    }
    const bool sea = h.sea && st.terrain[c] <= h.seaLevel;
    kind[c] = sea ? kSea : kLand;
    d1[c] = depth;
    surface[c] = sea ? h.seaLevel : st.terrain[c] + depth;
  }
  rowRain[j] = rained;
}

/// Calls f(std::true_type) or f(std::false_type): a run-time flag made a compile-time one.
template<typename F>
void WithFlag(bool flag, F&& f)
{
  if (flag)
  {
    f(std::true_type{});
  }
  else
  {
    f(std::false_type{});
  }
}

/// Pass 1a over a whole row of a grid without no-data cells: SurfaceRows' arithmetic without
/// branches (the same bits); rained[i] the depth of rain added. Pointers from the row's start.
template<bool Rain>
TERROIR_EROSION_CLONES void SurfaceRow(const HydraulicContext& h,
  const float* __restrict terrain,
  const float* __restrict water,
  const float* __restrict rain,
  float* __restrict waterLo,
  std::uint8_t* __restrict kind,
  float* __restrict d1,
  float* __restrict surface,
  float* __restrict rained)
{
  const float dt = h.dt;
  const float seaLevel = h.seaLevel;
  const bool seaBoundary = h.sea;
  for (int i = 0; i < h.st.nx; ++i)
  {
    float depth = water[i];
    if constexpr (Rain)
    {
      const float added = dt * rain[i];
      float lo = waterLo[i];
      AddCompensated(depth, lo, added);
      waterLo[i] = lo;
      rained[i] = added;
    }
    const bool sea = seaBoundary && terrain[i] <= seaLevel;
    kind[i] = sea ? kSea : kLand;
    d1[i] = depth;
    surface[i] = Select(sea, seaLevel, terrain[i] + depth);
  }
}

/// Pass 1a (rain, eq. 10) for rows [j0, j1): each cell's kind, d1 (its residue in place) and
/// water surface (b + d1 on land, seaLevel on sea).
void SurfaceRows(const HydraulicContext& h,
  const float* rain,
  float* waterLo,
  std::uint8_t* kind,
  float* d1,
  float* surface,
  std::vector<double>& rowRain,
  int j0,
  int j1)
{
  const ErosionState& st = h.st;
  std::vector<float> rained(static_cast<std::size_t>(st.nx));
  for (int j = j0; j < j1; ++j)
  {
    if (!h.rows.Valid(j))
    {
      SurfaceCells(h, rain, waterLo, kind, d1, surface, rowRain, j);
      continue;
    }
    const std::size_t r = h.Index(0, j);
    const auto run = [&](auto withRain)
    {
      SurfaceRow<decltype(withRain)::value>(h,
        st.terrain.data() + r,
        st.water.data() + r,
        rain ? rain + r : nullptr,
        waterLo + r,
        kind + r,
        d1 + r,
        surface + r,
        rained.data());
    };
    WithFlag(rain != nullptr, run);
    double sum = 0.0;
    if (rain)
    {
      const float area = h.geo.area[j];
      for (float a : rained)
      {
        sum += static_cast<double>(a) * area;
      }
    }
    rowRain[j] = sum;
  }
}

/// Pass 1b's per-row constants: the pipe coefficients (W, E, S, N), the row's cell area, dt
/// and the soft threshold.
struct FluxRowConstants
{
  float coef[4];
  float area, dt;
  SoftThreshold soft;
};

FluxRowConstants MakeFluxRow(const HydraulicContext& h, int j)
{
  const ErosionState& st = h.st;
  // North-south pipes: between rows, the mean spacing; through the grid's edge (Sea
  // boundary), the row's own.
  const float coefEdge = static_cast<float>(
    h.p.timeStep * h.p.gravity * (h.p.pipeArea > 0.0 ? h.p.pipeArea / st.rowDy[j] : st.rowDy[j]));
  return { { h.geo.coefEW[j],
             h.geo.coefEW[j],
             j > 0 ? h.geo.coefNorth[j - 1] : coefEdge,
             j + 1 < st.ny ? h.geo.coefNorth[j] : coefEdge },
    h.geo.area[j],
    h.dt,
    { h.p.softOutflow,
      static_cast<float>(h.p.softOutflowMin),
      static_cast<float>(h.p.softOutflowScale) } };
}

/// Pass 1b of cell (i, j), any cell.
void FluxCell(const HydraulicContext& h,
  const FluxRowConstants& k,
  const float* d1,
  const float* surface,
  float* const out[4],
  int i,
  int j)
{
  const ErosionState& st = h.st;
  const std::size_t nx = static_cast<std::size_t>(st.nx);
  const std::size_t c = h.Index(i, j);
  float f[4] = { 0.0f, 0.0f, 0.0f, 0.0f }; // W, E, S, N
  if (h.kind[c] == kLand)
  {
    const bool inside[4] = { i > 0, i + 1 < st.nx, j > 0, j + 1 < st.ny };
    const std::size_t n[4] = { c - 1, c + 1, c - nx, c + nx };
    const float old[4] = { st.fluxW[c], st.fluxE[c], st.fluxS[c], st.fluxN[c] };
    for (int p = 0; p < 4; ++p)
    {
      const bool open = inside[p] ? h.kind[n[p]] != kWall : h.sea;
      if (open)
      {
        const float level = inside[p] ? surface[n[p]] : h.seaLevel;
        f[p] = PipeFlux(k.soft, old[p], k.coef[p], surface[c] - level);
      }
    }
    const float sum = (f[0] + f[1]) + (f[2] + f[3]);
    if (sum > 0.0f)
    {
      const float scale = std::min(1.0f, d1[c] * k.area / (sum * k.dt));
      for (float& v : f)
      {
        v *= scale;
      }
    }
  }
  for (int p = 0; p < 4; ++p)
  {
    out[p][c] = f[p];
  }
}

/// Pass 1b over cells 1..nx-2 of a row whose cells are all valid, as are the rows on either
/// side (so every pipe is open): FluxCell's arithmetic without branches (the same bits).
/// Pointers from the row's start (surface also rows j - 1 and j + 1).
template<bool Soft>
TERROIR_EROSION_CLONES void FluxInterior(const FluxRowConstants& k,
  int nx,
  const std::uint8_t* __restrict kind,
  const float* __restrict d1,
  const float* __restrict surfS,
  const float* __restrict surfC,
  const float* __restrict surfN,
  const float* __restrict oldW,
  const float* __restrict oldE,
  const float* __restrict oldS,
  const float* __restrict oldN,
  float* __restrict fw,
  float* __restrict fe,
  float* __restrict fs,
  float* __restrict fn)
{
  const float cW = k.coef[0], cE = k.coef[1], cS = k.coef[2], cN = k.coef[3];
  const float area = k.area, dt = k.dt;
  const SoftThreshold soft{ Soft, k.soft.min, k.soft.scale };
  for (int i = 1; i < nx - 1; ++i)
  {
    const float level = surfC[i];
    float w = PipeFlux(soft, oldW[i], cW, level - surfC[i - 1]);
    float e = PipeFlux(soft, oldE[i], cE, level - surfC[i + 1]);
    float s = PipeFlux(soft, oldS[i], cS, level - surfS[i]);
    float n = PipeFlux(soft, oldN[i], cN, level - surfN[i]);
    const float sum = (w + e) + (s + n);
    const float scale = std::min(1.0f, d1[i] * area / (sum * dt));
    const bool scaled = sum > 0.0f;
    const bool land = kind[i] == kLand;
    fw[i] = Select(land, Select(scaled, w * scale, w), 0.0f);
    fe[i] = Select(land, Select(scaled, e * scale, e), 0.0f);
    fs[i] = Select(land, Select(scaled, s * scale, s), 0.0f);
    fn[i] = Select(land, Select(scaled, n * scale, n), 0.0f);
  }
}

/// Pass 1b (flux, eq. 11-13) for rows [j0, j1): the new fluxes of land cells (0 elsewhere).
/// A pipe is open towards any cell but a wall; through the grid's edge only with the Sea
/// boundary, where it sees seaLevel.
void FluxRows(const HydraulicContext& h,
  const float* d1,
  const float* surface,
  float* fw,
  float* fe,
  float* fs,
  float* fn,
  int j0,
  int j1)
{
  const ErosionState& st = h.st;
  const int nx = st.nx;
  float* const out[4] = { fw, fe, fs, fn };
  for (int j = j0; j < j1; ++j)
  {
    const FluxRowConstants k = MakeFluxRow(h, j);
    if (!h.rows.Interior(j))
    {
      for (int i = 0; i < nx; ++i)
      {
        FluxCell(h, k, d1, surface, out, i, j);
      }
      continue;
    }
    FluxCell(h, k, d1, surface, out, 0, j);
    FluxCell(h, k, d1, surface, out, nx - 1, j);
    const std::size_t r = h.Index(0, j);
    const auto run = [&](auto soft)
    {
      FluxInterior<decltype(soft)::value>(k,
        nx,
        h.kind + r,
        d1 + r,
        surface + r - nx,
        surface + r,
        surface + r + nx,
        st.fluxW.data() + r,
        st.fluxE.data() + r,
        st.fluxS.data() + r,
        st.fluxN.data() + r,
        fw + r,
        fe + r,
        fs + r,
        fn + r);
    };
    WithFlag(k.soft.on, run);
  }
}

/// Net flux through cell (i, j) along x (dW_X of Mei et al.): the mean of what crosses its
/// west and east faces eastwards. Cells outside the grid contribute nothing.
inline float NetFluxX(const HydraulicContext& h, const float* fw, const float* fe, int i, int j)
{
  const std::size_t c = h.Index(i, j);
  const float inW = i > 0 ? fe[c - 1] : 0.0f;
  const float outE = i + 1 < h.st.nx ? fw[c + 1] : 0.0f;
  return 0.5f * ((inW - fw[c]) + (fe[c] - outE));
}

inline float NetFluxY(const HydraulicContext& h, const float* fs, const float* fn, int i, int j)
{
  const std::size_t c = h.Index(i, j);
  const std::size_t nx = static_cast<std::size_t>(h.st.nx);
  const float inS = j > 0 ? fn[c - nx] : 0.0f;
  const float outN = j + 1 < h.st.ny ? fs[c + nx] : 0.0f;
  return 0.5f * ((inS - fs[c]) + (fn[c] - outN));
}

/// Water that flows into cell (i, j) from its four neighbours, m^3/s.
inline float Inflow(const HydraulicContext& h,
  const float* fw,
  const float* fe,
  const float* fs,
  const float* fn,
  int i,
  int j)
{
  const std::size_t c = h.Index(i, j);
  const std::size_t nx = static_cast<std::size_t>(h.st.nx);
  const float w = i > 0 ? fe[c - 1] : 0.0f;
  const float e = i + 1 < h.st.nx ? fw[c + 1] : 0.0f;
  const float s = j > 0 ? fn[c - nx] : 0.0f;
  const float n = j + 1 < h.st.ny ? fs[c + nx] : 0.0f;
  return (w + e) + (s + n);
}

/// Outflow of a land cell through pipes that end outside the grid or in a no-data cell.
inline float OutflowToOutside(const HydraulicContext& h,
  const float* fw,
  const float* fe,
  const float* fs,
  const float* fn,
  int i,
  int j)
{
  const std::size_t c = h.Index(i, j);
  const std::size_t nx = static_cast<std::size_t>(h.st.nx);
  float out = 0.0f;
  out += (i == 0 || !h.st.IsValid(c - 1)) ? fw[c] : 0.0f;
  out += (i + 1 == h.st.nx || !h.st.IsValid(c + 1)) ? fe[c] : 0.0f;
  out += (j == 0 || !h.st.IsValid(c - nx)) ? fs[c] : 0.0f;
  out += (j + 1 == h.st.ny || !h.st.IsValid(c + nx)) ? fn[c] : 0.0f;
  return out;
}

struct WaterRowSums
{
  std::vector<double> toSea, clamped;
};

/// m ? a : b for doubles, by bit masks (see Select).
inline double SelectD(bool m, double a, double b)
{
  std::uint64_t ua, ub;
  std::memcpy(&ua, &a, sizeof ua);
  std::memcpy(&ub, &b, sizeof ub);
  const std::uint64_t mask = 0u - static_cast<std::uint64_t>(m);
  const std::uint64_t r = (ua & mask) | (ub & ~mask);
  double out;
  std::memcpy(&out, &r, sizeof out);
  return out;
}

/// Pass 2 of cell (i, j), any cell: d2 (into state.water), velocity; toSea[i] the water it
/// sends to the sea and clamped[i] the negative water it had clamped (area-weighted, 0 if
/// none; the row sums add them in order).
void WaterCell(const HydraulicContext& h,
  ErosionState& st,
  const float* d1,
  const float* const f[4],
  int i,
  int j,
  double* toSea,
  double* clamped)
{
  const float *fw = f[0], *fe = f[1], *fs = f[2], *fn = f[3];
  const float area = h.geo.area[j];
  const std::size_t c = h.Index(i, j);
  toSea[i] = 0.0;
  clamped[i] = 0.0;
  float d2 = 0.0f;
  float depth = 0.0f; // the depth the velocity divides by
  if (!st.IsValid(c))
  {
    st.water[c] = 0.0f;
    st.waterResidue[c] = 0.0f;
    st.velocityU[c] = 0.0f;
    st.velocityV[c] = 0.0f;
    return;
  }
  const float in = Inflow(h, fw, fe, fs, fn, i, j);
  if (h.IsSea(c))
  {
    toSea[i] =
      (static_cast<double>(d1[c]) + st.waterResidue[c]) * area + static_cast<double>(h.dt * in);
    st.waterResidue[c] = 0.0f;
    depth = std::max(h.seaLevel - st.terrain[c], h.dryDepth);
  }
  else
  {
    const float out = (fw[c] + fe[c]) + (fs[c] + fn[c]);
    d2 = d1[c];
    AddCompensated(d2, st.waterResidue[c], h.dt * (in - out) / area);
    const double total = static_cast<double>(d2) + st.waterResidue[c];
    if (total < 0.0 || d2 < 0.0f)
    {
      clamped[i] = total * area;
      d2 = 0.0f;
      st.waterResidue[c] = 0.0f;
    }
    if (h.sea)
    {
      toSea[i] = static_cast<double>(h.dt * OutflowToOutside(h, fw, fe, fs, fn, i, j));
    }
    depth = 0.5f * (d1[c] + d2);
  }
  st.water[c] = d2;
  float u = 0.0f;
  float v = 0.0f;
  if (depth >= h.dryDepth && depth > 0.0f)
  {
    u = NetFluxX(h, fw, fe, i, j) / (h.geo.ly[j] * depth);
    v = NetFluxY(h, fs, fn, i, j) / (h.geo.lx[j] * depth);
  }
  st.velocityU[c] = u;
  st.velocityV[c] = v;
}

/// Pass 2's constants for one row.
struct WaterRowConstants
{
  float area, dt, seaLevel, dryDepth, lx, ly;
};

/// Pass 2 over cells 1..nx-2 of a row with all cells valid, and the rows on either side:
/// WaterCell's arithmetic, both kinds computed and selected (the same bits). Pointers from the
/// row's start; fnS: fn of row j - 1, fsN: fs of row j + 1.
TERROIR_EROSION_CLONES
void WaterInterior(const WaterRowConstants& k,
  int nx,
  const std::uint8_t* __restrict kind,
  const float* __restrict terrain,
  const float* __restrict d1,
  const float* __restrict fw,
  const float* __restrict fe,
  const float* __restrict fs,
  const float* __restrict fn,
  const float* __restrict fnS,
  const float* __restrict fsN,
  float* __restrict water,
  float* __restrict residue,
  float* __restrict velocityU,
  float* __restrict velocityV,
  double* __restrict toSea,
  double* __restrict clamped)
{
  for (int i = 1; i < nx - 1; ++i)
  {
    const float in = (fe[i - 1] + fw[i + 1]) + (fnS[i] + fsN[i]);
    const float out = (fw[i] + fe[i]) + (fs[i] + fn[i]);
    const float lo0 = residue[i];
    float hi = d1[i];
    float lo = lo0;
    AddCompensated(hi, lo, k.dt * (in - out) / k.area);
    const double total = static_cast<double>(hi) + lo;
    const bool clamp = total < 0.0 || hi < 0.0f;
    const bool sea = kind[i] == kSea;
    const float landD2 = Select(clamp, 0.0f, hi);
    const float d2 = Select(sea, 0.0f, landD2);
    const float depth =
      Select(sea, std::max(k.seaLevel - terrain[i], k.dryDepth), 0.5f * (d1[i] + landD2));
    toSea[i] = SelectD(
      sea, (static_cast<double>(d1[i]) + lo0) * k.area + static_cast<double>(k.dt * in), 0.0);
    clamped[i] = SelectD(!sea && clamp, total * k.area, 0.0);
    residue[i] = Select(sea || clamp, 0.0f, lo);
    water[i] = d2;
    const bool wet = depth >= k.dryDepth && depth > 0.0f;
    const float netX = 0.5f * ((fe[i - 1] - fw[i]) + (fe[i] - fw[i + 1]));
    const float netY = 0.5f * ((fnS[i] - fs[i]) + (fn[i] - fsN[i]));
    velocityU[i] = Select(wet, netX / (k.ly * depth), 0.0f);
    velocityV[i] = Select(wet, netY / (k.lx * depth), 0.0f);
  }
}

/// Pass 2 (eq. 14-16) for rows [j0, j1): d2 (into state.water), velocity, water to the sea.
void WaterRows(const HydraulicContext& h,
  ErosionState& st,
  const float* d1,
  const float* fw,
  const float* fe,
  const float* fs,
  const float* fn,
  WaterRowSums& sums,
  int j0,
  int j1)
{
  const int nx = st.nx;
  const float* const f[4] = { fw, fe, fs, fn };
  std::vector<double> toSea(static_cast<std::size_t>(nx)), clamped(toSea.size());
  for (int j = j0; j < j1; ++j)
  {
    if (h.rows.Interior(j))
    {
      WaterCell(h, st, d1, f, 0, j, toSea.data(), clamped.data());
      WaterCell(h, st, d1, f, nx - 1, j, toSea.data(), clamped.data());
      const std::size_t r = h.Index(0, j);
      const WaterRowConstants k{
        h.geo.area[j], h.dt, h.seaLevel, h.dryDepth, h.geo.lx[j], h.geo.ly[j]
      };
      WaterInterior(k,
        nx,
        h.kind + r,
        st.terrain.data() + r,
        d1 + r,
        fw + r,
        fe + r,
        fs + r,
        fn + r,
        fn + r - nx,
        fs + r + nx,
        st.water.data() + r,
        st.waterResidue.data() + r,
        st.velocityU.data() + r,
        st.velocityV.data() + r,
        toSea.data(),
        clamped.data());
    }
    else
    {
      for (int i = 0; i < nx; ++i)
      {
        WaterCell(h, st, d1, f, i, j, toSea.data(), clamped.data());
      }
    }
    double sea = 0.0;
    double clamp = 0.0;
    for (int i = 0; i < nx; ++i)
    {
      sea += toSea[i];
      clamp -= clamped[i];
    }
    sums.toSea[j] = sea;
    sums.clamped[j] = clamp;
  }
}

/// sin(alpha) of Weiss eq. 17 over the pipe lengths, clamped to [minTilt, maxTilt].
inline float Tilt(const HydraulicContext& h, int i, int j)
{
  const ErosionState& st = h.st;
  const std::size_t c = h.Index(i, j);
  const std::size_t nx = static_cast<std::size_t>(st.nx);
  const float b = st.terrain[c];
  float t = 0.0f;
  if (i > 0 && st.IsValid(c - 1))
    t = std::max(t, std::fabs(b - st.terrain[c - 1]) / h.geo.lx[j]);
  if (i + 1 < st.nx && st.IsValid(c + 1))
    t = std::max(t, std::fabs(b - st.terrain[c + 1]) / h.geo.lx[j]);
  if (j > 0 && st.IsValid(c - nx))
    t = std::max(t, std::fabs(b - st.terrain[c - nx]) / h.geo.lNorth[j - 1]);
  if (j + 1 < st.ny && st.IsValid(c + nx))
    t = std::max(t, std::fabs(b - st.terrain[c + nx]) / h.geo.lNorth[j]);
  const float sine = t / std::sqrt(1.0f + t * t);
  return std::min(std::max(sine, static_cast<float>(h.p.minTilt)), static_cast<float>(h.p.maxTilt));
}

struct ErodeRowSums
{
  std::vector<double> eroded, deposited;
};

/// K_s, K_s,rock and K_d of one cell: the constants, or Weiss's eq. 24 when the halving depths
/// are set: K_s 2^(-db / f_s), K_d 2^(db / f_d) with db = b_original - b (clamped to 1).
struct CellRates
{
  float ks, ksRock, kd;
};

inline CellRates RatesAt(const HydraulicContext& h, float eroded)
{
  CellRates r{ static_cast<float>(h.p.dissolving),
    static_cast<float>(h.p.dissolvingRock),
    static_cast<float>(h.p.deposition) };
  if (h.p.halvingDepthErosion > 0.0)
  {
    const float f = std::exp2(-eroded / static_cast<float>(h.p.halvingDepthErosion));
    r.ks = std::min(1.0f, r.ks * f);
    r.ksRock = std::min(1.0f, r.ksRock * f);
  }
  if (h.p.halvingDepthDeposition > 0.0)
  {
    r.kd =
      std::min(1.0f, r.kd * std::exp2(eroded / static_cast<float>(h.p.halvingDepthDeposition)));
  }
  return r;
}

/// Bed taken into suspension for a capacity deficit (eq. 19): soil first at K_s, then rock at
/// K_s,rock for the part of the deficit the soil could not cover; at most `limit`. Updates soil.
inline float Dissolve(const CellRates& r, float deficit, float* soil, float limit)
{
  float take = r.ks * deficit;
  if (!soil)
  {
    return std::min(take, limit);
  }
  float fromSoil = std::min(*soil, take);
  float fromRock = 0.0f;
  if (fromSoil < take)
  {
    // The soil is used up: the rest of the deficit is dissolved from rock.
    const float rest = r.ks > 0.0f ? deficit - fromSoil / r.ks : deficit;
    fromRock = r.ksRock * std::max(rest, 0.0f);
  }
  fromSoil = std::min(fromSoil, limit);
  fromRock = std::min(fromRock, limit - fromSoil);
  *soil -= fromSoil;
  return fromSoil + fromRock;
}

/// The constants of pass 3, in float.
struct ErodeConstants
{
  float kc, rampDepth, maxChange, minTilt, maxTilt;
  bool layered;

  explicit ErodeConstants(const HydraulicContext& h)
    : kc(static_cast<float>(h.p.capacity))
    , rampDepth(static_cast<float>(h.p.capacityDepth))
    , maxChange(h.p.maxBedChange > 0.0 ? static_cast<float>(h.p.maxBedChange)
                                       : std::numeric_limits<float>::infinity())
    , minTilt(static_cast<float>(h.p.minTilt))
    , maxTilt(static_cast<float>(h.p.maxTilt))
    , layered(!h.st.soil.empty())
  {
  }
};

/// Pass 3 of cell (i, j), any cell: new bed into `bed`, s' into state.sediment, soil in place;
/// eroded[i] and deposited[i] the volumes it took and dropped (0 if none), per cell area.
void ErodeCell(const HydraulicContext& h,
  const ErodeConstants& k,
  ErosionState& st,
  float* bed,
  int i,
  int j,
  float* eroded,
  float* deposited)
{
  const std::size_t c = h.Index(i, j);
  const float b = st.terrain[c];
  bed[c] = b;
  eroded[i] = 0.0f;
  deposited[i] = 0.0f;
  if (!h.IsLand(c))
  {
    return;
  }
  const float u = st.velocityU[c];
  const float v = st.velocityV[c];
  float capacity = k.kc * Tilt(h, i, j) * std::sqrt(u * u + v * v);
  if (k.rampDepth > 0.0f)
  {
    capacity *= std::min(1.0f, st.water[c] / k.rampDepth);
  }
  const float original = st.original[c];
  CellRates r = RatesAt(h, original - b);
  if (!st.erosionFactor.empty())
  {
    r.ks *= st.erosionFactor[c]; // vegetation holds the soil (a multiplier <= 1)
    r.ksRock *= st.erosionFactor[c];
  }
  const float s = st.sediment[c];
  if (capacity > s)
  {
    // Weiss's cap on the total change: the bed stays above original - maxBedChange.
    const float limit = std::max(0.0f, b - (original - k.maxChange));
    const float take = Dissolve(r, capacity - s, k.layered ? &st.soil[c] : nullptr, limit);
    bed[c] = b;
    AddCompensated(bed[c], st.terrainResidue[c], -take);
    st.sediment[c] = s + take;
    eroded[i] = take;
  }
  else
  {
    const float limit = std::max(0.0f, (original + k.maxChange) - b);
    const float drop = std::min(r.kd * (s - capacity), limit);
    bed[c] = b;
    AddCompensated(bed[c], st.terrainResidue[c], drop);
    st.sediment[c] = s - drop;
    if (k.layered)
    {
      st.soil[c] += drop;
    }
    deposited[i] = drop;
  }
}

/// Row pointers of pass 3's vectorised loop (row j; terrain also rows j - 1 and j + 1).
struct ErodeRowArrays
{
  const float *bedS, *bedC, *bedN;
  const std::uint8_t* kind;
  const float *u, *v, *water, *original, *factor;
  float *sediment, *residue, *soil, *bed, *eroded, *deposited;
};

/// Pass 3 over cells 1..nx-2 of a row with all four neighbours valid: ErodeCell's arithmetic,
/// both branches computed and the result selected (so that the loop vectorises; the same
/// bits). Options fixed at compile time; with Weiss's eq. 24 (exp2) it stays scalar.
template<bool Layered, bool Factor, bool Ramp, bool Halving>
TERROIR_EROSION_CLONES void ErodeInterior(const HydraulicContext& h,
  const ErodeConstants& k,
  int nx,
  int j,
  const float* __restrict bedS,
  const float* __restrict bedC,
  const float* __restrict bedN,
  const std::uint8_t* __restrict kind,
  const float* __restrict uu,
  const float* __restrict vv,
  const float* __restrict water,
  const float* __restrict originalBed,
  const float* __restrict factor,
  float* __restrict sediment,
  float* __restrict residue,
  float* __restrict soil,
  float* __restrict bed,
  float* __restrict eroded,
  float* __restrict deposited)
{
  const float lx = h.geo.lx[j];
  const float lS = h.geo.lNorth[j - 1];
  const float lN = h.geo.lNorth[j];
  const CellRates base = RatesAt(h, 0.0f);
  for (int i = 1; i < nx - 1; ++i)
  {
    const float b = bedC[i];
    float t = 0.0f;
    t = std::max(t, std::fabs(b - bedC[i - 1]) / lx);
    t = std::max(t, std::fabs(b - bedC[i + 1]) / lx);
    t = std::max(t, std::fabs(b - bedS[i]) / lS);
    t = std::max(t, std::fabs(b - bedN[i]) / lN);
    const float sine = t / std::sqrt(1.0f + t * t);
    const float tilt = std::min(std::max(sine, k.minTilt), k.maxTilt);
    const float u = uu[i];
    const float v = vv[i];
    float capacity = k.kc * tilt * std::sqrt(u * u + v * v);
    if constexpr (Ramp)
    {
      capacity *= std::min(1.0f, water[i] / k.rampDepth);
    }
    const float original = originalBed[i];
    CellRates r = base;
    if constexpr (Halving)
    {
      r = RatesAt(h, original - b);
    }
    if constexpr (Factor)
    {
      r.ks *= factor[i];
      r.ksRock *= factor[i];
    }
    const float s = sediment[i];
    const float soil0 = Layered ? soil[i] : 0.0f;
    // Erosion (Dissolve, inlined without branches).
    const float limitE = std::max(0.0f, b - (original - k.maxChange));
    const float deficit = capacity - s;
    const float want = r.ks * deficit;
    float take = std::min(want, limitE);
    float soilE = soil0;
    if constexpr (Layered)
    {
      float fromSoil = std::min(soil0, want);
      const float rest = r.ks > 0.0f ? deficit - fromSoil / r.ks : deficit;
      float fromRock = fromSoil < want ? r.ksRock * std::max(rest, 0.0f) : 0.0f;
      fromSoil = std::min(fromSoil, limitE);
      fromRock = std::min(fromRock, limitE - fromSoil);
      soilE = soil0 - fromSoil;
      take = fromSoil + fromRock;
    }
    // Deposition.
    const float limitD = std::max(0.0f, (original + k.maxChange) - b);
    const float drop = std::min(r.kd * (s - capacity), limitD);
    const bool land = kind[i] == kLand;
    const bool erodes = capacity > s;
    const float lo0 = residue[i];
    float hi = b;
    float lo = lo0;
    AddCompensated(hi, lo, Select(erodes, -take, drop));
    bed[i] = Select(land, hi, b);
    residue[i] = Select(land, lo, lo0);
    sediment[i] = Select(land, Select(erodes, s + take, s - drop), s);
    if constexpr (Layered)
    {
      soil[i] = Select(land, Select(erodes, soilE, soil0 + drop), soil0);
    }
    eroded[i] = Select(land && erodes, take, 0.0f);
    deposited[i] = Select(land && !erodes, drop, 0.0f);
  }
}

/// Pass 3 (eq. 17-20, 24) for rows [j0, j1): new bed into `bed`, s' into state.sediment, soil
/// in place (both pointwise).
void ErodeRows(const HydraulicContext& h,
  ErosionState& st,
  float* bed,
  ErodeRowSums& sums,
  int j0,
  int j1)
{
  const ErodeConstants k(h);
  const int nx = st.nx;
  std::vector<float> eroded(static_cast<std::size_t>(nx)), deposited(eroded.size());
  const bool halving = h.p.halvingDepthErosion > 0.0 || h.p.halvingDepthDeposition > 0.0;
  for (int j = j0; j < j1; ++j)
  {
    if (h.rows.Interior(j))
    {
      ErodeCell(h, k, st, bed, 0, j, eroded.data(), deposited.data());
      ErodeCell(h, k, st, bed, nx - 1, j, eroded.data(), deposited.data());
      const std::size_t row = h.Index(0, j);
      const ErodeRowArrays a{ st.terrain.data() + row - nx,
        st.terrain.data() + row,
        st.terrain.data() + row + nx,
        h.kind + row,
        st.velocityU.data() + row,
        st.velocityV.data() + row,
        st.water.data() + row,
        st.original.data() + row,
        st.erosionFactor.empty() ? nullptr : st.erosionFactor.data() + row,
        st.sediment.data() + row,
        st.terrainResidue.data() + row,
        k.layered ? st.soil.data() + row : nullptr,
        bed + row,
        eroded.data(),
        deposited.data() };
      WithFlag(k.layered,
        [&](auto layered)
        {
          WithFlag(!st.erosionFactor.empty(),
            [&](auto factor)
            {
              WithFlag(k.rampDepth > 0.0f,
                [&](auto ramp)
                {
                  WithFlag(halving,
                    [&](auto halv)
                    {
                      ErodeInterior<decltype(layered)::value,
                        decltype(factor)::value,
                        decltype(ramp)::value,
                        decltype(halv)::value>(h,
                        k,
                        nx,
                        j,
                        a.bedS,
                        a.bedC,
                        a.bedN,
                        a.kind,
                        a.u,
                        a.v,
                        a.water,
                        a.original,
                        a.factor,
                        a.sediment,
                        a.residue,
                        a.soil,
                        a.bed,
                        a.eroded,
                        a.deposited);
                    });
                });
            });
        });
    }
    else
    {
      for (int i = 0; i < nx; ++i)
      {
        ErodeCell(h, k, st, bed, i, j, eroded.data(), deposited.data());
      }
    }
    const float area = h.geo.area[j];
    double er = 0.0;
    double dep = 0.0;
    for (int i = 0; i < nx; ++i)
    {
      er += static_cast<double>(eroded[i]) * area;
      dep += static_cast<double>(deposited[i]) * area;
    }
    sums.eroded[j] = er;
    sums.deposited[j] = dep;
  }
}

/// Bilinear sample of s' at (x, y) in cell units, clamped to the grid.
inline float Sample(const HydraulicContext& h, const float* s, float x, float y)
{
  const int nx = h.st.nx;
  const int ny = h.st.ny;
  x = std::min(std::max(x, 0.0f), static_cast<float>(nx - 1));
  y = std::min(std::max(y, 0.0f), static_cast<float>(ny - 1));
  const int i0 = std::min(static_cast<int>(x), nx - 1);
  const int j0 = std::min(static_cast<int>(y), ny - 1);
  const int i1 = std::min(i0 + 1, nx - 1);
  const int j1 = std::min(j0 + 1, ny - 1);
  const float fx = x - static_cast<float>(i0);
  const float fy = y - static_cast<float>(j0);
  const float south = s[h.Index(i0, j0)] + fx * (s[h.Index(i1, j0)] - s[h.Index(i0, j0)]);
  const float north = s[h.Index(i0, j1)] + fx * (s[h.Index(i1, j1)] - s[h.Index(i0, j1)]);
  return south + fy * (north - south);
}

struct AdvectRowSums
{
  std::vector<double> before, after;
};

/// Pass 4's back-traced value at cell (i, j) of a grid without no-data cells (AdvectRows'
/// arithmetic; u, v, kind from the row's start).
inline float AdvectCell(const HydraulicContext& h,
  int i,
  int j,
  const float* s,
  const float* velocityU,
  const float* velocityV,
  const std::uint8_t* kind)
{
  float di = velocityU[i] * h.dt / h.geo.lx[j];
  float dj = velocityV[i] * h.dt / h.geo.ly[j];
  if (kind[i] == kSea)
  {
    di = std::min(std::max(di, -1.0f), 1.0f);
    dj = std::min(std::max(dj, -1.0f), 1.0f);
  }
  return Sample(h, s, static_cast<float>(i) - di, static_cast<float>(j) - dj);
}

/// Pass 4 over cells 1..nx-2 of row j (0 < j < ny - 1) of a grid without no-data cells: where
/// the back-traced point lies within one cell (i0 in {i - 1, i}, j0 in {j - 1, j}: almost every
/// cell), Sample's four values are picked from rows j - 1, j, j + 1 by masks instead of
/// gathered, so the loop vectorises; far[i] = 1 marks the other cells, which the caller redoes
/// with AdvectCell. The same arithmetic, the same bits.
TERROIR_EROSION_CLONES
void AdvectInterior(const HydraulicContext& h,
  int j,
  const float* __restrict sS,
  const float* __restrict sC,
  const float* __restrict sN,
  const float* __restrict velocityU,
  const float* __restrict velocityV,
  const std::uint8_t* __restrict kind,
  float* __restrict moved,
  std::uint8_t* __restrict far)
{
  const int nx = h.st.nx;
  const int ny = h.st.ny;
  const float dt = h.dt;
  const float lx = h.geo.lx[j];
  const float ly = h.geo.ly[j];
  for (int i = 1; i < nx - 1; ++i)
  {
    float di = velocityU[i] * dt / lx;
    float dj = velocityV[i] * dt / ly;
    const bool sea = kind[i] == kSea;
    di = Select(sea, std::min(std::max(di, -1.0f), 1.0f), di);
    dj = Select(sea, std::min(std::max(dj, -1.0f), 1.0f), dj);
    const float x =
      std::min(std::max(static_cast<float>(i) - di, 0.0f), static_cast<float>(nx - 1));
    const float y =
      std::min(std::max(static_cast<float>(j) - dj, 0.0f), static_cast<float>(ny - 1));
    const int i0 = std::min(static_cast<int>(x), nx - 1);
    const int j0 = std::min(static_cast<int>(y), ny - 1);
    const float fx = x - static_cast<float>(i0);
    const float fy = y - static_cast<float>(j0);
    const bool east = i0 == i;  // else i0 == i - 1
    const bool north = j0 == j; // else j0 == j - 1
    far[i] = !((east || i0 == i - 1) && (north || j0 == j - 1));
    // Rows j0 and j0 + 1, columns i0 and i0 + 1.
    const float a00 = Select(north, Select(east, sC[i], sC[i - 1]), Select(east, sS[i], sS[i - 1]));
    const float a01 = Select(north, Select(east, sC[i + 1], sC[i]), Select(east, sS[i + 1], sS[i]));
    const float a10 = Select(north, Select(east, sN[i], sN[i - 1]), Select(east, sC[i], sC[i - 1]));
    const float a11 = Select(north, Select(east, sN[i + 1], sN[i]), Select(east, sC[i + 1], sC[i]));
    const float south = a00 + fx * (a01 - a00);
    const float northValue = a10 + fx * (a11 - a10);
    moved[i] = south + fy * (northValue - south);
  }
}

/// Pass 4 over a whole row of a grid without no-data cells: AdvectRows' arithmetic without
/// branches (the same bits); before[i], after[i] the cell's area-weighted terms.
void AdvectRow(const HydraulicContext& h,
  int j,
  const float* __restrict s,
  const float* __restrict velocityU,
  const float* __restrict velocityV,
  const std::uint8_t* __restrict kind,
  float* __restrict moved,
  double* __restrict before,
  double* __restrict after)
{
  const int nx = h.st.nx;
  const int ny = h.st.ny;
  const float dt = h.dt;
  const float lx = h.geo.lx[j];
  const float ly = h.geo.ly[j];
  const float area = h.geo.area[j];
  const float* __restrict row = s + static_cast<std::size_t>(j) * nx;
  for (int i = 0; i < nx; ++i)
  {
    float di = velocityU[i] * dt / lx;
    float dj = velocityV[i] * dt / ly;
    const bool sea = kind[i] == kSea;
    di = Select(sea, std::min(std::max(di, -1.0f), 1.0f), di);
    dj = Select(sea, std::min(std::max(dj, -1.0f), 1.0f), dj);
    // Sample(h, s, i - di, j - dj), inlined.
    const float x =
      std::min(std::max(static_cast<float>(i) - di, 0.0f), static_cast<float>(nx - 1));
    const float y =
      std::min(std::max(static_cast<float>(j) - dj, 0.0f), static_cast<float>(ny - 1));
    const int i0 = std::min(static_cast<int>(x), nx - 1);
    const int j0 = std::min(static_cast<int>(y), ny - 1);
    const int i1 = std::min(i0 + 1, nx - 1);
    const int j1 = std::min(j0 + 1, ny - 1);
    const float fx = x - static_cast<float>(i0);
    const float fy = y - static_cast<float>(j0);
    const std::ptrdiff_t r0 = static_cast<std::ptrdiff_t>(j0) * nx;
    const std::ptrdiff_t r1 = static_cast<std::ptrdiff_t>(j1) * nx;
    const float south = s[r0 + i0] + fx * (s[r0 + i1] - s[r0 + i0]);
    const float north = s[r1 + i0] + fx * (s[r1 + i1] - s[r1 + i0]);
    const float m = south + fy * (north - south);
    moved[i] = m;
    before[i] = static_cast<double>(row[i]) * area;
    after[i] = static_cast<double>(m) * area;
  }
}

/// Pass 4 (eq. 21) for rows [j0, j1): back-traced sediment into `moved`, area-weighted sums.
void AdvectRows(const HydraulicContext& h,
  const float* s,
  float* moved,
  AdvectRowSums& sums,
  int j0,
  int j1)
{
  const ErosionState& st = h.st;
  std::vector<double> rowBefore(static_cast<std::size_t>(st.nx)), rowAfter(rowBefore.size());
  std::vector<std::uint8_t> far(rowBefore.size());
  for (int j = j0; j < j1; ++j)
  {
    const float area = h.geo.area[j];
    double before = 0.0;
    double after = 0.0;
    if (h.rows.Interior(j))
    {
      const std::size_t r = h.Index(0, j);
      const float* u = st.velocityU.data() + r;
      const float* v = st.velocityV.data() + r;
      AdvectInterior(
        h, j, s + r - st.nx, s + r, s + r + st.nx, u, v, h.kind + r, moved + r, far.data());
      far[0] = 1;
      far[st.nx - 1] = 1;
      for (int i = 0; i < st.nx; ++i)
      {
        if (far[i])
        {
          moved[r + i] = AdvectCell(h, i, j, s, u, v, h.kind + r);
        }
        before += static_cast<double>(s[r + i]) * area;
        after += static_cast<double>(moved[r + i]) * area;
      }
      sums.before[j] = before;
      sums.after[j] = after;
      continue;
    }
    if (h.rows.Valid(j))
    {
      const std::size_t r = h.Index(0, j);
      AdvectRow(h,
        j,
        s,
        st.velocityU.data() + r,
        st.velocityV.data() + r,
        h.kind + r,
        moved + r,
        rowBefore.data(),
        rowAfter.data());
      for (int i = 0; i < st.nx; ++i)
      {
        before += rowBefore[i];
        after += rowAfter[i];
      }
      sums.before[j] = before;
      sums.after[j] = after;
      continue;
    }
    for (int i = 0; i < st.nx; ++i)
    {
      const std::size_t c = h.Index(i, j);
      if (!st.IsValid(c))
      {
        moved[c] = 0.0f;
        continue;
      }
      float di = st.velocityU[c] * h.dt / h.geo.lx[j];
      float dj = st.velocityV[c] * h.dt / h.geo.ly[j];
      if (h.IsSea(c))
      {
        di = std::min(std::max(di, -1.0f), 1.0f);
        dj = std::min(std::max(dj, -1.0f), 1.0f);
      }
      moved[c] = Sample(h, s, static_cast<float>(i) - di, static_cast<float>(j) - dj);
      before += static_cast<double>(s[c]) * area;
      after += static_cast<double>(moved[c]) * area;
    }
    sums.before[j] = before;
    sums.after[j] = after;
  }
}

struct FinishRowSums
{
  std::vector<double> evaporated, deposited;
};

/// Pass 5 of cell c of row j, any cell: evaporation, then dry and sea cells settle; the bed is
/// already state.terrain. evaporated[i], deposited[i]: the cell's terms of the row sums.
void FinishCell(const HydraulicContext& h,
  ErosionState& st,
  const float* moved,
  double k,
  const float* evaporationFactor,
  int i,
  int j,
  double* evaporated,
  float* deposited)
{
  const float ke = static_cast<float>(h.p.evaporation) * h.dt;
  const float area = h.geo.area[j];
  const std::size_t c = h.Index(i, j);
  const bool seaCell = h.IsSea(c); // before the bed changes, as in the other passes
  evaporated[i] = 0.0;
  deposited[i] = 0.0f;
  if (!st.IsValid(c))
  {
    st.sediment[c] = 0.0f;
    return;
  }
  const float s = static_cast<float>(static_cast<double>(moved[c]) * k);
  const float d2 = st.water[c];
  const float lo2 = st.waterResidue[c];
  const float factor = evaporationFactor ? std::max(evaporationFactor[c], 0.0f) : 1.0f;
  const float keep = std::max(0.0f, 1.0f - ke * factor);
  const float d3 = d2 * keep;
  const float lo3 = lo2 * keep;
  evaporated[i] = ((static_cast<double>(d2) + lo2) - (static_cast<double>(d3) + lo3)) * area;
  st.water[c] = d3;
  st.waterResidue[c] = lo3;
  if (seaCell || d3 < h.dryDepth)
  {
    AddCompensated(st.terrain[c], st.terrainResidue[c], s);
    if (!st.soil.empty())
    {
      st.soil[c] += s;
    }
    st.sediment[c] = 0.0f;
    deposited[i] = s;
  }
  else
  {
    st.sediment[c] = s;
  }
}

/// Pass 5 over a whole row of a grid without no-data cells: FinishCell's arithmetic without
/// branches (the same bits). Pointers from the row's start; `moved` may be `sediment`.
template<bool Layered, bool Evaporation>
TERROIR_EROSION_CLONES void FinishRow(const HydraulicContext& h,
  int j,
  double k,
  const std::uint8_t* __restrict kind,
  const float* moved,
  const float* __restrict evaporationFactor,
  float* __restrict water,
  float* __restrict waterLo,
  float* __restrict bed,
  float* __restrict bedLo,
  float* __restrict soil,
  float* sediment,
  double* __restrict evaporated,
  float* __restrict deposited)
{
  const float ke = static_cast<float>(h.p.evaporation) * h.dt;
  const float area = h.geo.area[j];
  const float dryDepth = h.dryDepth;
  for (int i = 0; i < h.st.nx; ++i)
  {
    const float s = static_cast<float>(static_cast<double>(moved[i]) * k);
    const float d2 = water[i];
    const float lo2 = waterLo[i];
    const float factor = Evaporation ? std::max(evaporationFactor[i], 0.0f) : 1.0f;
    const float keep = std::max(0.0f, 1.0f - ke * factor);
    const float d3 = d2 * keep;
    const float lo3 = lo2 * keep;
    evaporated[i] = ((static_cast<double>(d2) + lo2) - (static_cast<double>(d3) + lo3)) * area;
    water[i] = d3;
    waterLo[i] = lo3;
    const bool settle = kind[i] == kSea || d3 < dryDepth;
    const float b = bed[i];
    const float blo = bedLo[i];
    float hi = b;
    float lo = blo;
    AddCompensated(hi, lo, s);
    bed[i] = Select(settle, hi, b);
    bedLo[i] = Select(settle, lo, blo);
    if constexpr (Layered)
    {
      soil[i] = Select(settle, soil[i] + s, soil[i]);
    }
    sediment[i] = Select(settle, 0.0f, s);
    deposited[i] = Select(settle, s, 0.0f);
  }
}

/// Pass 5 (Dunn's rescaling; eq. 22-23; dry and sea cells settle) for rows [j0, j1); the new
/// bed is already state.terrain.
void FinishRows(const HydraulicContext& h,
  ErosionState& st,
  const float* moved,
  double k,
  const float* evaporationFactor,
  FinishRowSums& sums,
  int j0,
  int j1)
{
  const int nx = st.nx;
  const bool layered = !st.soil.empty();
  std::vector<double> evaporated(static_cast<std::size_t>(nx));
  std::vector<float> deposited(evaporated.size());
  for (int j = j0; j < j1; ++j)
  {
    if (h.rows.Valid(j))
    {
      const std::size_t r = h.Index(0, j);
      WithFlag(layered,
        [&](auto soil)
        {
          WithFlag(evaporationFactor != nullptr,
            [&](auto evap)
            {
              FinishRow<decltype(soil)::value, decltype(evap)::value>(h,
                j,
                k,
                h.kind + r,
                moved + r,
                evaporationFactor ? evaporationFactor + r : nullptr,
                st.water.data() + r,
                st.waterResidue.data() + r,
                st.terrain.data() + r,
                st.terrainResidue.data() + r,
                layered ? st.soil.data() + r : nullptr,
                st.sediment.data() + r,
                evaporated.data(),
                deposited.data());
            });
        });
    }
    else
    {
      for (int i = 0; i < nx; ++i)
      {
        FinishCell(h, st, moved, k, evaporationFactor, i, j, evaporated.data(), deposited.data());
      }
    }
    const float area = h.geo.area[j];
    double evap = 0.0;
    double dep = 0.0;
    for (int i = 0; i < nx; ++i)
    {
      evap += evaporated[i];
      dep += static_cast<double>(deposited[i]) * area;
    }
    sums.evaporated[j] = evap;
    sums.deposited[j] = dep;
  }
}

/// Thermal erosion: the height a giver sends one neighbour, rate/16 times its excess over the
/// talus. Called with the same arguments by the giver and the receiver (same bits).
inline float SlipHeight(float giver, float receiver, float tanTalus, float distance, float rate16)
{
  const float excess = (giver - receiver) - tanTalus * distance;
  return excess > 0.0f ? excess * rate16 : 0.0f;
}

constexpr double kDegree = 3.14159265358979323846 / 180.0;

/// The eight neighbours: offsets (E, NE, N, NW, W, SW, S, SE).
constexpr int kDi[8] = { 1, 1, 0, -1, -1, -1, 0, 1 };
constexpr int kDj[8] = { 0, 1, 1, 1, 0, -1, -1, -1 };

struct ThermalContext
{
  const ErosionState& st;
  std::vector<float> lx, area, lNorth, diagNorth; ///< per row; *North: rows j and j + 1
  float tanSoil, tanRock, rate16;
  bool layered;
  RowValidity rows;

  ThermalContext(const ErosionState& state, const ThermalParams& p)
    : st(state)
    , tanSoil(static_cast<float>(std::tan(p.talusSoilDeg * kDegree)))
    , tanRock(static_cast<float>(std::tan(p.talusRockDeg * kDegree)))
    , rate16(static_cast<float>(p.rate / 16.0))
    , layered(!state.soil.empty())
    , rows(state)
  {
    const int ny = st.ny;
    lx.resize(ny);
    area.resize(ny);
    lNorth.assign(ny, 0.0f);
    diagNorth.assign(ny, 0.0f);
    for (int j = 0; j < ny; ++j)
    {
      lx[j] = static_cast<float>(st.rowDx[j]);
      area[j] = static_cast<float>(st.CellArea(j));
      if (j + 1 < ny)
      {
        const double ly = 0.5 * (st.rowDy[j] + st.rowDy[j + 1]);
        const double mx = 0.5 * (st.rowDx[j] + st.rowDx[j + 1]);
        lNorth[j] = static_cast<float>(ly);
        diagNorth[j] = static_cast<float>(std::sqrt(ly * ly + mx * mx));
      }
    }
  }

  /// Distance from a cell of row j to its neighbour k.
  float Distance(int j, int k) const
  {
    const int dj = kDj[k];
    if (dj == 0)
    {
      return lx[j];
    }
    const int lower = dj > 0 ? j : j - 1;
    return kDi[k] == 0 ? lNorth[lower] : diagNorth[lower];
  }
  bool Neighbour(int i, int j, int k, std::size_t& n) const
  {
    const int ii = i + kDi[k];
    const int jj = j + kDj[k];
    if (ii < 0 || jj < 0 || ii >= st.nx || jj >= st.ny)
    {
      return false;
    }
    n =
      static_cast<std::size_t>(jj) * static_cast<std::size_t>(st.nx) + static_cast<std::size_t>(ii);
    return st.IsValid(n);
  }
  float TanTalus(std::size_t c) const
  {
    const float tan = (!layered || st.soil[c] > 0.0f) ? tanSoil : tanRock;
    return st.talusFactor.empty() ? tan : tan * st.talusFactor[c];
  }
};

/// Thermal: the talus tangent of cell c, as ThermalContext::TanTalus, with the soil layer and the
/// per-cell factor fixed at compile time (no per-cell tests of the options).
template<bool Layered, bool Factor>
struct TalusOf
{
  static constexpr bool kLayered = Layered;
  const float* soil;
  const float* factor;
  float tanSoil, tanRock;

  float operator()(std::size_t c) const
  {
    const float tan = (!Layered || soil[c] > 0.0f) ? tanSoil : tanRock;
    return Factor ? tan * factor[c] : tan;
  }
  /// The same, indexed from the start of a row.
  TalusOf Row(std::size_t row) const
  {
    return { Layered ? soil + row : soil, Factor ? factor + row : factor, tanSoil, tanRock };
  }
};

/// Calls f(talus) with the TalusOf that matches the state's options.
template<typename F>
void WithTalus(const ThermalContext& t, F&& f)
{
  const float* soil = t.st.soil.data();
  const float* factor = t.st.talusFactor.data();
  if (t.layered && !t.st.talusFactor.empty())
  {
    f(TalusOf<true, true>{ soil, factor, t.tanSoil, t.tanRock });
  }
  else if (t.layered)
  {
    f(TalusOf<true, false>{ soil, factor, t.tanSoil, t.tanRock });
  }
  else if (!t.st.talusFactor.empty())
  {
    f(TalusOf<false, true>{ soil, factor, t.tanSoil, t.tanRock });
  }
  else
  {
    f(TalusOf<false, false>{ soil, factor, t.tanSoil, t.tanRock });
  }
}

/// The eight neighbours of a cell of row j that has all of them (not on the grid's edge, no
/// no-data cells): index offsets, distances and area ratios (neighbour's row / row j).
struct SlipStencil
{
  std::ptrdiff_t offset[8];
  float distance[8];
  float areaRatio[8];
};

SlipStencil MakeStencil(const ThermalContext& t, int j)
{
  SlipStencil s;
  for (int k = 0; k < 8; ++k)
  {
    s.offset[k] = static_cast<std::ptrdiff_t>(kDj[k]) * t.st.nx + kDi[k];
    s.distance[k] = t.Distance(j, k);
    s.areaRatio[k] = t.area[j + kDj[k]] / t.area[j];
  }
  return s;
}

/// A soil giver never gives more than its soil: the factor on its pipes.
inline float SoilScale(bool layered, const float* soil, std::size_t c, float total)
{
  return (layered && soil[c] > 0.0f && total > soil[c]) ? soil[c] / total : 1.0f;
}

/// Thermal pass 1 of cell (i, j), any cell: its scale and its largest excess (-inf if none).
template<typename Talus>
void SlipScaleCell(const ThermalContext& t,
  const Talus& talus,
  int i,
  int j,
  float* scale,
  float& maxExcess)
{
  const ErosionState& st = t.st;
  const std::size_t c = static_cast<std::size_t>(j) * st.nx + i;
  scale[c] = 0.0f;
  maxExcess = -std::numeric_limits<float>::infinity();
  if (!st.IsValid(c))
  {
    return;
  }
  const float tanTalus = talus(c);
  float total = 0.0f;
  for (int k = 0; k < 8; ++k)
  {
    std::size_t n = 0;
    if (t.Neighbour(i, j, k, n))
    {
      const float d = t.Distance(j, k);
      total += SlipHeight(st.terrain[c], st.terrain[n], tanTalus, d, t.rate16);
      maxExcess = std::max(maxExcess, (st.terrain[c] - st.terrain[n]) - tanTalus * d);
    }
  }
  scale[c] = SoilScale(t.layered, st.soil.data(), c, total);
}

/// Thermal pass 1 over cells 1..nx-2 of a row that has all eight neighbours (see
/// SlipScaleCell; separate pointers, so that the loop vectorises). bed: rows j-1, j, j+1;
/// the other pointers: row j.
template<typename Talus>
TERROIR_EROSION_CLONES void SlipScaleInterior(int nx,
  const float* __restrict bedS,
  const float* __restrict bedC,
  const float* __restrict bedN,
  const Talus& talus,
  const SlipStencil& s,
  float rate16,
  const float* __restrict soil,
  float* __restrict scale,
  float* __restrict rowMax)
{
  const float* const bed[3] = { bedS, bedC, bedN };
  float distance[8];
  std::copy(s.distance, s.distance + 8, distance);
  for (int i = 1; i < nx - 1; ++i)
  {
    const float b = bed[1][i];
    const float tanTalus = talus(i);
    float total = 0.0f;
    float m = -std::numeric_limits<float>::infinity();
#pragma GCC unroll 8
    for (int k = 0; k < 8; ++k)
    {
      const float excess = (b - bed[1 + kDj[k]][i + kDi[k]]) - tanTalus * distance[k];
      total += excess > 0.0f ? excess * rate16 : 0.0f; // SlipHeight
      m = std::max(m, excess);
    }
    scale[i] = SoilScale(Talus::kLayered, soil, i, total);
    rowMax[i] = m;
  }
}

/// Thermal pass 1 for row j: each giver's scale (soil limit); rowMax[i] its largest excess.
template<typename Talus>
void SlipScaleRow(const ThermalContext& t, const Talus& talus, int j, float* scale, float* rowMax)
{
  const ErosionState& st = t.st;
  const int nx = st.nx;
  if (!t.rows.Interior(j))
  {
    for (int i = 0; i < nx; ++i)
    {
      SlipScaleCell(t, talus, i, j, scale, rowMax[i]);
    }
    return;
  }
  SlipScaleCell(t, talus, 0, j, scale, rowMax[0]);
  SlipScaleCell(t, talus, nx - 1, j, scale, rowMax[nx - 1]);
  const std::size_t row = static_cast<std::size_t>(j) * nx;
  const float* bed = st.terrain.data() + row;
  SlipScaleInterior(nx,
    bed - nx,
    bed,
    bed + nx,
    talus.Row(row),
    MakeStencil(t, j),
    t.rate16,
    t.layered ? st.soil.data() + row : nullptr,
    scale + row,
    rowMax);
}

/// Thermal pass 1 for rows [j0, j1): scales, and each row's largest excess (>= 0).
void SlipScaleRows(const ThermalContext& t,
  float* scale,
  std::vector<double>& rowExcess,
  int j0,
  int j1)
{
  std::vector<float> rowMax(static_cast<std::size_t>(t.st.nx));
  WithTalus(t,
    [&](const auto& talus)
    {
      for (int j = j0; j < j1; ++j)
      {
        SlipScaleRow(t, talus, j, scale, rowMax.data());
        double excess = 0.0;
        for (float m : rowMax)
        {
          excess = std::max(excess, static_cast<double>(m));
        }
        rowExcess[j] = excess;
      }
    });
}

/// Where thermal pass 2 writes: the new bed (its residue in place) and soil.
struct SlipOutput
{
  float* bed;
  float* bedLo;
  float* soil; ///< null without a soil layer
};

/// New bed and soil of a cell that gives `out` and gets `in` (the end of thermal pass 2).
inline void SlipUpdate(const ErosionState& st,
  const SlipOutput& o,
  std::size_t c,
  float out,
  float in)
{
  o.bed[c] = st.terrain[c];
  AddCompensated(o.bed[c], o.bedLo[c], in - out);
  if (o.soil)
  {
    const float fromSoil = st.soil[c] > 0.0f ? std::min(out, st.soil[c]) : 0.0f;
    o.soil[c] = (st.soil[c] - fromSoil) + in;
  }
}

/// Thermal pass 2 of cell (i, j), any cell: returns what it gives (0 for no-data cells).
template<typename Talus>
float SlipCell(const ThermalContext& t,
  const Talus& talus,
  const float* scale,
  const SlipOutput& o,
  int i,
  int j)
{
  const ErosionState& st = t.st;
  const std::size_t c = static_cast<std::size_t>(j) * st.nx + i;
  o.bed[c] = st.terrain[c];
  if (o.soil)
  {
    o.soil[c] = st.soil[c];
  }
  if (!st.IsValid(c))
  {
    return 0.0f;
  }
  const float tanTalus = talus(c);
  float out = 0.0f;
  float in = 0.0f;
  for (int k = 0; k < 8; ++k)
  {
    std::size_t n = 0;
    if (!t.Neighbour(i, j, k, n))
    {
      continue;
    }
    const float d = t.Distance(j, k);
    out += SlipHeight(st.terrain[c], st.terrain[n], tanTalus, d, t.rate16);
    const int jn = j + kDj[k];
    const float got = scale[n] * SlipHeight(st.terrain[n], st.terrain[c], talus(n), d, t.rate16);
    in += got * (t.area[jn] / t.area[j]);
  }
  out *= scale[c];
  SlipUpdate(st, o, c, out, in);
  return out;
}

/// Thermal pass 2 over cells 1..nx-2 of a row that has all eight neighbours (see
/// SlipCell; separate pointers, so that the loop vectorises). bed, scale, talus: rows j-1, j,
/// j+1; the other pointers: row j; given[i]: what cell i gives.
template<typename Talus>
TERROIR_EROSION_CLONES void SlipInterior(int nx,
  const float* __restrict bedS,
  const float* __restrict bedC,
  const float* __restrict bedN,
  const float* __restrict scaleS,
  const float* __restrict scaleC,
  const float* __restrict scaleN,
  const Talus* talus,
  const SlipStencil& s,
  float rate16,
  const float* __restrict soil,
  float* __restrict newBed,
  float* __restrict bedLo,
  float* __restrict newSoil,
  float* __restrict given)
{
  const float* const bed[3] = { bedS, bedC, bedN };
  const float* const sc[3] = { scaleS, scaleC, scaleN };
  float distance[8], areaRatio[8];
  std::copy(s.distance, s.distance + 8, distance);
  std::copy(s.areaRatio, s.areaRatio + 8, areaRatio);
  for (int i = 1; i < nx - 1; ++i)
  {
    const float b = bed[1][i];
    const float tanTalus = talus[1](i);
    float out = 0.0f;
    float in = 0.0f;
#pragma GCC unroll 8
    for (int k = 0; k < 8; ++k)
    {
      const int r = 1 + kDj[k];
      const int n = i + kDi[k];
      const float bn = bed[r][n];
      out += SlipHeight(b, bn, tanTalus, distance[k], rate16);
      in += (sc[r][n] * SlipHeight(bn, b, talus[r](n), distance[k], rate16)) * areaRatio[k];
    }
    out *= sc[1][i];
    float hi = b;
    float lo = bedLo[i];
    AddCompensated(hi, lo, in - out);
    newBed[i] = hi;
    bedLo[i] = lo;
    if constexpr (Talus::kLayered)
    {
      const float fromSoil = soil[i] > 0.0f ? std::min(out, soil[i]) : 0.0f;
      newSoil[i] = (soil[i] - fromSoil) + in;
    }
    given[i] = out;
  }
}

/// Thermal pass 2 for row j: the new bed (and soil); rowOut[i] what cell i gives.
template<typename Talus>
void SlipRow(const ThermalContext& t,
  const Talus& talus,
  const float* scale,
  const SlipOutput& o,
  int j,
  float* rowOut)
{
  const ErosionState& st = t.st;
  const int nx = st.nx;
  if (!t.rows.Interior(j))
  {
    for (int i = 0; i < nx; ++i)
    {
      rowOut[i] = SlipCell(t, talus, scale, o, i, j);
    }
    return;
  }
  rowOut[0] = SlipCell(t, talus, scale, o, 0, j);
  rowOut[nx - 1] = SlipCell(t, talus, scale, o, nx - 1, j);
  const std::size_t row = static_cast<std::size_t>(j) * nx;
  const float* bed = st.terrain.data() + row;
  const float* sc = scale + row;
  const Talus rowTalus[3] = { talus.Row(row - nx), talus.Row(row), talus.Row(row + nx) };
  SlipInterior(nx,
    bed - nx,
    bed,
    bed + nx,
    sc - nx,
    sc,
    sc + nx,
    rowTalus,
    MakeStencil(t, j),
    t.rate16,
    t.layered ? st.soil.data() + row : nullptr,
    o.bed + row,
    o.bedLo + row,
    t.layered ? o.soil + row : nullptr,
    rowOut);
}

/// Thermal pass 2 for rows [j0, j1): the new bed (and soil) from what each cell gives and gets.
void SlipRows(const ThermalContext& t,
  const float* scale,
  const SlipOutput& o,
  std::vector<double>& rowMoved,
  int j0,
  int j1)
{
  const ErosionState& st = t.st;
  std::vector<float> rowOut(static_cast<std::size_t>(st.nx));
  WithTalus(t,
    [&](const auto& talus)
    {
      for (int j = j0; j < j1; ++j)
      {
        SlipRow(t, talus, scale, o, j, rowOut.data());
        double moved = 0.0;
        for (int i = 0; i < st.nx; ++i)
        {
          if (st.IsValid(static_cast<std::size_t>(j) * st.nx + i))
          {
            moved += static_cast<double>(rowOut[i]) * t.area[j];
          }
        }
        rowMoved[j] = moved;
      }
    });
}

/// Throws std::invalid_argument when an array of the state does not have nx*ny entries (or
/// rowDx/rowDy ny), e.g. a state built by hand.
void CheckState(const ErosionState& st)
{
  Require(st.nx > 0 && st.ny > 0, "grid size nx*ny", static_cast<double>(st.nx) * st.ny, "> 0");
  Require(st.rowDx.size() == static_cast<std::size_t>(st.ny),
    "rowDx size",
    static_cast<double>(st.rowDx.size()),
    "ny");
  Require(st.rowDy.size() == static_cast<std::size_t>(st.ny),
    "rowDy size",
    static_cast<double>(st.rowDy.size()),
    "ny");
  const std::size_t n = st.Size();
  const std::pair<const char*, std::size_t> sizes[] = { { "terrain", st.terrain.size() },
    { "original", st.original.size() },
    { "terrainResidue", st.terrainResidue.size() },
    { "waterResidue", st.waterResidue.size() },
    { "water", st.water.size() },
    { "sediment", st.sediment.size() },
    { "fluxW", st.fluxW.size() },
    { "fluxE", st.fluxE.size() },
    { "fluxS", st.fluxS.size() },
    { "fluxN", st.fluxN.size() },
    { "velocityU", st.velocityU.size() },
    { "velocityV", st.velocityV.size() },
    { "scratchKind", st.scratchKind.size() } };
  for (const auto& s : sizes)
  {
    Require(
      s.second == n, s.first, static_cast<double>(s.second), "of size nx*ny (MakeErosionState)");
  }
  for (const std::vector<float>& a : st.scratch)
  {
    Require(a.size() == n, "scratch", static_cast<double>(a.size()), "of size nx*ny");
  }
  Require(st.soil.empty() || st.soil.size() == n,
    "soil",
    static_cast<double>(st.soil.size()),
    "empty or of size nx*ny");
  Require(st.valid.empty() || st.valid.size() == n,
    "valid",
    static_cast<double>(st.valid.size()),
    "empty or of size nx*ny");
  for (const auto& f : { std::make_pair("erosionFactor", &st.erosionFactor),
         std::make_pair("talusFactor", &st.talusFactor) })
  {
    Require(f.second->empty() || f.second->size() == n,
      f.first,
      static_cast<double>(f.second->size()),
      "empty or of size nx*ny");
    for (float x : *f.second)
    {
      Require(x >= 0.0f && std::isfinite(x), f.first, static_cast<double>(x), ">= 0 and finite");
    }
  }
}

} // namespace

void CheckErosionParams(const ErosionParams& p)
{
  Require(std::isfinite(p.timeStep) && p.timeStep > 0.0, "timeStep", p.timeStep, "> 0");
  Require(std::isfinite(p.gravity) && p.gravity > 0.0, "gravity", p.gravity, "> 0");
  Require(std::isfinite(p.pipeArea) && p.pipeArea >= 0.0, "pipeArea", p.pipeArea, ">= 0");
  Require(std::isfinite(p.capacity) && p.capacity >= 0.0, "capacity", p.capacity, ">= 0");
  Require(p.dissolving >= 0.0 && p.dissolving <= 1.0, "dissolving", p.dissolving, "in [0, 1]");
  Require(p.dissolvingRock >= 0.0 && p.dissolvingRock <= 1.0,
    "dissolvingRock",
    p.dissolvingRock,
    "in [0, 1]");
  Require(p.deposition >= 0.0 && p.deposition <= 1.0, "deposition", p.deposition, "in [0, 1]");
  Require(std::isfinite(p.evaporation) && p.evaporation >= 0.0 && p.evaporation * p.timeStep <= 1.0,
    "evaporation",
    p.evaporation,
    ">= 0 with evaporation * timeStep <= 1");
  Require(p.minTilt >= 0.0 && p.minTilt <= 1.0, "minTilt", p.minTilt, "in [0, 1]");
  Require(p.maxTilt >= p.minTilt && p.maxTilt <= 1.0, "maxTilt", p.maxTilt, "in [minTilt, 1]");
  Require(std::isfinite(p.capacityDepth) && p.capacityDepth >= 0.0,
    "capacityDepth",
    p.capacityDepth,
    ">= 0");
  Require(std::isfinite(p.halvingDepthErosion) && p.halvingDepthErosion >= 0.0,
    "halvingDepthErosion",
    p.halvingDepthErosion,
    ">= 0");
  Require(std::isfinite(p.halvingDepthDeposition) && p.halvingDepthDeposition >= 0.0,
    "halvingDepthDeposition",
    p.halvingDepthDeposition,
    ">= 0");
  Require(
    std::isfinite(p.maxBedChange) && p.maxBedChange >= 0.0, "maxBedChange", p.maxBedChange, ">= 0");
  Require(std::isfinite(p.dryDepth) && p.dryDepth >= 0.0, "dryDepth", p.dryDepth, ">= 0");
  Require(std::isfinite(p.softOutflowMin) && p.softOutflowMin >= 0.0,
    "softOutflowMin",
    p.softOutflowMin,
    ">= 0");
  Require(std::isfinite(p.softOutflowScale) && p.softOutflowScale >= 0.0,
    "softOutflowScale",
    p.softOutflowScale,
    ">= 0");
  Require(p.boundary == ErosionBoundary::Closed || p.boundary == ErosionBoundary::Sea,
    "boundary",
    static_cast<double>(p.boundary),
    "Closed (0) or Sea (1)");
  Require(std::isfinite(p.seaLevel), "seaLevel", p.seaLevel, "finite");
}

void CheckThermalParams(const ThermalParams& p)
{
  Require(p.talusSoilDeg > 0.0 && p.talusSoilDeg < 90.0,
    "talusSoilDeg",
    p.talusSoilDeg,
    "in (0, 90) degrees");
  Require(p.talusRockDeg > 0.0 && p.talusRockDeg < 90.0,
    "talusRockDeg",
    p.talusRockDeg,
    "in (0, 90) degrees");
  Require(p.rate > 0.0 && p.rate <= 1.0, "rate", p.rate, "in (0, 1]");
}

ErosionState MakeErosionState(const GridView<float>& terrain, const float* soil)
{
  Require(terrain.nx > 0, "nx", terrain.nx, "> 0");
  Require(terrain.ny > 0, "ny", terrain.ny, "> 0");
  Require(terrain.data != nullptr, "terrain data", 0.0, "given");
  ErosionState st;
  st.nx = terrain.nx;
  st.ny = terrain.ny;
  st.rowDx.resize(st.ny);
  st.rowDy.resize(st.ny);
  for (int j = 0; j < st.ny; ++j)
  {
    st.rowDx[j] = terrain.DxAt(j);
    st.rowDy[j] = terrain.DyAt(j);
    Require(std::isfinite(st.rowDx[j]) && st.rowDx[j] > 0.0, "dx", st.rowDx[j], "> 0");
    Require(std::isfinite(st.rowDy[j]) && st.rowDy[j] > 0.0, "dy", st.rowDy[j], "> 0");
  }
  const std::size_t n = st.Size();
  if (terrain.valid)
  {
    st.valid.assign(terrain.valid, terrain.valid + n);
  }
  st.terrain.assign(terrain.data, terrain.data + n);
  for (std::size_t c = 0; c < n; ++c)
  {
    if (!st.IsValid(c))
    {
      st.terrain[c] = 0.0f;
      continue;
    }
    Require(std::isfinite(st.terrain[c]), "terrain height", st.terrain[c], "finite");
  }
  st.original = st.terrain;
  if (soil)
  {
    st.soil.assign(soil, soil + n);
    for (std::size_t c = 0; c < n; ++c)
    {
      if (!st.IsValid(c))
      {
        st.soil[c] = 0.0f;
      }
      Require(st.soil[c] >= 0.0f, "soil thickness", st.soil[c], ">= 0");
    }
  }
  for (std::vector<float>* a : { &st.terrainResidue,
         &st.waterResidue,
         &st.water,
         &st.sediment,
         &st.fluxW,
         &st.fluxE,
         &st.fluxS,
         &st.fluxN,
         &st.velocityU,
         &st.velocityV })
  {
    a->assign(n, 0.0f);
  }
  for (std::vector<float>& a : st.scratch)
  {
    a.assign(n, 0.0f);
  }
  st.scratchKind.assign(n, 0);
  return st;
}

ErosionStepStats ErosionHydraulicStep(ErosionState& st,
  const ErosionParams& params,
  const float* rain,
  const float* evaporationFactor,
  const ErosionParallelFor& parallelFor)
{
  CheckErosionParams(params);
  CheckState(st);
  const HydraulicContext h(st, params);
  const int ny = st.ny;
  ErosionStepStats stats;
  std::vector<float>* sc = st.scratch;

  // 1. Rain, cell kinds and surfaces (scratch 4, 5); the new fluxes into scratch 0-3, then
  // swapped into the state.
  std::vector<double> rowRain(ny, 0.0);
  float* d1 = sc[4].data();
  float* surface = sc[5].data();
  ForRows(parallelFor,
    ny,
    [&](int j0, int j1)
    {
      SurfaceRows(
        h, rain, st.waterResidue.data(), st.scratchKind.data(), d1, surface, rowRain, j0, j1);
    });
  ForRows(parallelFor,
    ny,
    [&](int j0, int j1)
    { FluxRows(h, d1, surface, sc[0].data(), sc[1].data(), sc[2].data(), sc[3].data(), j0, j1); });
  std::swap(st.fluxW, sc[0]);
  std::swap(st.fluxE, sc[1]);
  std::swap(st.fluxS, sc[2]);
  std::swap(st.fluxN, sc[3]);
  stats.rain = SumRows(rowRain);

  // 2. Water height and velocity.
  WaterRowSums water{ std::vector<double>(ny, 0.0), std::vector<double>(ny, 0.0) };
  ForRows(parallelFor,
    ny,
    [&](int j0, int j1)
    {
      WaterRows(h,
        st,
        d1,
        st.fluxW.data(),
        st.fluxE.data(),
        st.fluxS.data(),
        st.fluxN.data(),
        water,
        j0,
        j1);
    });
  stats.waterToSea = SumRows(water.toSea);
  stats.waterClamped = SumRows(water.clamped);

  // 3. Erosion and deposition: the new bed into scratch 0, s' in place.
  float* bed = sc[0].data();
  ErodeRowSums erode{ std::vector<double>(ny, 0.0), std::vector<double>(ny, 0.0) };
  ForRows(parallelFor, ny, [&](int j0, int j1) { ErodeRows(h, st, bed, erode, j0, j1); });
  stats.eroded = SumRows(erode.eroded);
  std::swap(st.terrain, sc[0]); // the new bed is the state's (no pass below reads the old one)

  // 4. Transport: the back-traced field into scratch 1; Dunn's k from the two totals.
  float* moved = sc[1].data();
  AdvectRowSums advect{ std::vector<double>(ny, 0.0), std::vector<double>(ny, 0.0) };
  ForRows(parallelFor,
    ny,
    [&](int j0, int j1) { AdvectRows(h, st.sediment.data(), moved, advect, j0, j1); });
  const double before = SumRows(advect.before);
  const double after = SumRows(advect.after);
  double k = 1.0;
  if (after > 0.0)
  {
    k = before / after;
  }
  else
  {
    moved = st.sediment.data(); // nothing to rescale: keep s' where it is
  }
  stats.sedimentScale = k;

  // 5. Rescale, evaporate, settle on dry and sea cells.
  FinishRowSums finish{ std::vector<double>(ny, 0.0), std::vector<double>(ny, 0.0) };
  ForRows(parallelFor,
    ny,
    [&](int j0, int j1) { FinishRows(h, st, moved, k, evaporationFactor, finish, j0, j1); });
  stats.evaporated = SumRows(finish.evaporated);
  stats.deposited = SumRows(erode.deposited) + SumRows(finish.deposited);
  return stats;
}

ThermalStepStats ErosionThermalStep(ErosionState& st,
  const ThermalParams& params,
  const ErosionParallelFor& parallelFor)
{
  CheckThermalParams(params);
  CheckState(st);
  const ThermalContext t(st, params);
  const int ny = st.ny;
  std::vector<double> rowExcess(ny, 0.0);
  std::vector<double> rowMoved(ny, 0.0);
  float* scale = st.scratch[0].data();
  ForRows(parallelFor, ny, [&](int j0, int j1) { SlipScaleRows(t, scale, rowExcess, j0, j1); });
  float* bed = st.scratch[1].data();
  float* soil = t.layered ? st.scratch[2].data() : nullptr;
  ForRows(parallelFor,
    ny,
    [&](int j0, int j1) {
      SlipRows(t, scale, SlipOutput{ bed, st.terrainResidue.data(), soil }, rowMoved, j0, j1);
    });
  std::swap(st.terrain, st.scratch[1]);
  if (t.layered)
  {
    std::swap(st.soil, st.scratch[2]);
  }
  ThermalStepStats stats;
  stats.moved = SumRows(rowMoved);
  for (double e : rowExcess)
  {
    stats.maxExcess = std::max(stats.maxExcess, e);
  }
  return stats;
}

ErosionTotals ErosionMeasure(const ErosionState& st)
{
  ErosionTotals t;
  for (int j = 0; j < st.ny; ++j)
  {
    const double area = st.CellArea(j);
    double b = 0.0, soil = 0.0, d = 0.0, s = 0.0;
    for (int i = 0; i < st.nx; ++i)
    {
      const std::size_t c = static_cast<std::size_t>(j) * st.nx + i;
      if (!st.IsValid(c))
      {
        continue;
      }
      b += static_cast<double>(st.terrain[c]) + st.terrainResidue[c];
      soil += st.soil.empty() ? 0.0 : st.soil[c];
      d += static_cast<double>(st.water[c]) + st.waterResidue[c];
      s += st.sediment[c];
    }
    t.terrain += b * area;
    t.soil += soil * area;
    t.water += d * area;
    t.sediment += s * area;
  }
  return t;
}

} // namespace terrain
} // namespace terroir

#include "SlopeHorn1981.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define TERROIR_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#define TERROIR_ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define TERROIR_CLONES
#define TERROIR_ALWAYS_INLINE inline
#endif

namespace terroir
{
namespace terrain
{
namespace
{

/// Everything a cell needs once its window is known.
template<typename T>
struct CellOutput
{
  T* slope;
  T* aspect;
  T* normals;
  bool percent;
  T convergence;
};

template<typename T>
inline void ComputeCell(T w0,
  T w1,
  T w2,
  T w3,
  T w5,
  T w6,
  T w7,
  T w8,
  const SlopeRowCoefficients<T>& c,
  const CellOutput<T>& out,
  std::size_t idx)
{
  const T gx = (w2 - w0) * c.cN + (w5 - w3) * (T(2) * c.cC) + (w8 - w6) * c.cS;
  // Differences first: exact for nearby floats, so no rounding of the large sums.
  const T gy = ((w0 - w6) + T(2) * (w1 - w7) + (w2 - w8)) * c.cY;
  const T g2 = gx * gx + gy * gy;
  if (out.slope)
  {
    const T g = std::sqrt(g2);
    out.slope[idx] = out.percent ? T(100) * g : std::atan(g) * T(57.29577951308232);
  }
  if (out.aspect)
  {
    if (g2 == T(0))
    {
      out.aspect[idx] = std::numeric_limits<T>::quiet_NaN();
    }
    else
    {
      // Downhill direction (-gx, -gy), clockwise from north: atan2(east, north).
      T a = std::atan2(-gx, -gy) * T(57.29577951308232) + out.convergence;
      if (a < T(0))
      {
        a += T(360);
      }
      if (a >= T(360))
      {
        a -= T(360);
      }
      if (a < T(0) || a >= T(360)) // rounding at the wrap
      {
        a = T(0);
      }
      out.aspect[idx] = a;
    }
  }
  if (out.normals)
  {
    const T inv = T(1) / std::sqrt(g2 + T(1));
    out.normals[3 * idx + 0] = -gx * inv;
    out.normals[3 * idx + 1] = -gy * inv;
    out.normals[3 * idx + 2] = inv;
  }
}

template<typename T>
inline void SetNaN(const CellOutput<T>& out, std::size_t idx)
{
  const T nan = std::numeric_limits<T>::quiet_NaN();
  if (out.slope)
  {
    out.slope[idx] = nan;
  }
  if (out.aspect)
  {
    out.aspect[idx] = nan;
  }
  if (out.normals)
  {
    out.normals[3 * idx + 0] = nan;
    out.normals[3 * idx + 1] = nan;
    out.normals[3 * idx + 2] = nan;
  }
}

/// Value and validity of a grid cell.
template<typename T>
struct Sample
{
  T z;
  bool ok;
};

template<typename T>
inline Sample<T> Get(const GridView<T>& v, int i, int j)
{
  return { v.At(i, j), v.IsValid(i, j) };
}

/// gdaldem's INTERPOL(a, b) = 2a - b, no data if either is.
template<typename T>
inline Sample<T> Extrapolate(const Sample<T>& a, const Sample<T>& b)
{
  return { T(2) * a.z - b.z, a.ok && b.ok };
}

/// atan(t) for t in [0, 1]: odd polynomial of degree 15 (coefficients fitted here for minimum
/// max error), max error 1.4e-7 rad (8e-6 deg) in float. Branch-free so the loop vectorizes.
inline float AtanUnit(float t)
{
  const float u = t * t;
  float p = -0.004054558929055929f;
  p = p * u + 0.021862929686903954f;
  p = p * u - 0.05591228976845741f;
  p = p * u + 0.09642194956541061f;
  p = p * u - 0.1390862911939621f;
  p = p * u + 0.19946566224098206f;
  p = p * u - 0.33329859375953674f;
  p = p * u + 0.9999993443489075f;
  return p * t;
}

constexpr float kHalfPi = 1.5707963267948966f;
constexpr float kPi = 3.141592653589793f;
constexpr float kDegF = 57.29577951308232f;

/// atan(g) for g >= 0.
inline float AtanPositive(float g)
{
  const float inv = 1.0f / g; // unconditional (inf at 0, unused): keeps the loop branch-free
  const bool big = g > 1.0f;
  const float r = AtanUnit(big ? inv : g);
  return big ? kHalfPi - r : r;
}

/// atan2(y, x) in (-pi, pi]; NaN when x = y = 0 (the caller masks flat cells).
inline float Atan2Fast(float y, float x)
{
  const float ax = std::fabs(x);
  const float ay = std::fabs(y);
  const float r0 = AtanUnit(std::min(ax, ay) / std::max(ax, ay));
  const float r1 = ay > ax ? kHalfPi - r0 : r0;
  const float r2 = x < 0.0f ? kPi - r1 : r1;
  return y < 0.0f ? -r2 : r2;
}

/// The interior cells of one row (no mask, no border), float: branch-free and vectorizable;
/// same formulas as ComputeCell with the polynomial arctangents above.
template<bool S, bool A, bool N>
TERROIR_ALWAYS_INLINE void InteriorRowFloat(const float* __restrict rn,
  const float* __restrict rc,
  const float* __restrict rs,
  int nx,
  const SlopeRowCoefficients<float>& c,
  bool percent,
  float convergence,
  float* __restrict slope,
  float* __restrict aspect,
  float* __restrict normals)
{
  const float cN = c.cN, cC2 = 2.0f * c.cC, cS = c.cS, cY = c.cY;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  // One of the two is zero: a select on `percent` inside the loop stops GCC's vectorizer.
  const float percentScale = percent ? 100.0f : 0.0f;
  const float degreeScale = percent ? 0.0f : kDegF;
  for (int i = 1; i < nx - 1; ++i)
  {
    const float gx =
      (rn[i + 1] - rn[i - 1]) * cN + (rc[i + 1] - rc[i - 1]) * cC2 + (rs[i + 1] - rs[i - 1]) * cS;
    const float gy =
      ((rn[i - 1] - rs[i - 1]) + 2.0f * (rn[i] - rs[i]) + (rn[i + 1] - rs[i + 1])) * cY;
    const float g2 = gx * gx + gy * gy;
    if (S)
    {
      const float g = std::sqrt(g2);
      slope[i] = percentScale * g + degreeScale * AtanPositive(g);
    }
    if (A)
    {
      float a = Atan2Fast(-gx, -gy) * kDegF + convergence;
      a = a < 0.0f ? a + 360.0f : a;
      a = a >= 360.0f ? a - 360.0f : a;
      a = ((a < 0.0f) | (a >= 360.0f)) ? 0.0f : a;
      aspect[i] = g2 == 0.0f ? nan : a;
    }
    if (N)
    {
      const float inv = 1.0f / std::sqrt(g2 + 1.0f);
      normals[3 * i + 0] = -gx * inv;
      normals[3 * i + 1] = -gy * inv;
      normals[3 * i + 2] = inv;
    }
  }
}

/// One clone per instruction set (AVX-512F, AVX2, baseline x86-64 with GCC; -ffp-contract=off, so
/// all give bit-identical results); the loader picks the best for the machine.
TERROIR_CLONES void InteriorRowDispatch(int flags,
  const float* rn,
  const float* rc,
  const float* rs,
  int nx,
  const SlopeRowCoefficients<float>& c,
  bool percent,
  float convergence,
  float* slope,
  float* aspect,
  float* normals)
{
#define TERROIR_ROW(S, A, N)                                                                       \
  InteriorRowFloat<S, A, N>(rn, rc, rs, nx, c, percent, convergence, slope, aspect, normals)
  switch (flags)
  {
    case 0:
      TERROIR_ROW(false, false, false);
      break;
    case 1:
      TERROIR_ROW(false, false, true);
      break;
    case 2:
      TERROIR_ROW(false, true, false);
      break;
    case 3:
      TERROIR_ROW(false, true, true);
      break;
    case 4:
      TERROIR_ROW(true, false, false);
      break;
    case 5:
      TERROIR_ROW(true, false, true);
      break;
    case 6:
      TERROIR_ROW(true, true, false);
      break;
    default:
      TERROIR_ROW(true, true, true);
      break;
  }
#undef TERROIR_ROW
}

/// Float uses the vectorized row; double (the reference) the plain per-cell code.
template<typename T>
bool InteriorRowVectorized(const GridView<T>&,
  int,
  const SlopeRowCoefficients<T>&,
  const CellOutput<T>&)
{
  return false;
}

template<>
bool InteriorRowVectorized<float>(const GridView<float>& v,
  int j,
  const SlopeRowCoefficients<float>& c,
  const CellOutput<float>& out)
{
  const std::size_t row = v.Index(0, j);
  const int flags = (out.slope ? 4 : 0) + (out.aspect ? 2 : 0) + (out.normals ? 1 : 0);
  InteriorRowDispatch(flags,
    v.data + v.Index(0, j + 1),
    v.data + row,
    v.data + v.Index(0, j - 1),
    v.nx,
    c,
    out.percent,
    out.convergence,
    out.slope ? out.slope + row : nullptr,
    out.aspect ? out.aspect + row : nullptr,
    out.normals ? out.normals + 3 * row : nullptr);
  return true;
}

} // namespace

template<typename T>
bool HornWindow(const GridView<T>& v, int i, int j, T w[9])
{
  if (!v.IsValid(i, j))
  {
    return false;
  }
  Sample<T> s[9];
  const int nx = v.nx;
  const int ny = v.ny;
  if (j == 0 || j == ny - 1)
  {
    // First or last row: clamp the columns, extrapolate the missing row.
    const int cols[3] = { std::max(i - 1, 0), i, std::min(i + 1, nx - 1) };
    const int inner = (j == 0) ? 1 : ny - 2;
    for (int k = 0; k < 3; ++k)
    {
      const int c = cols[k];
      const Sample<T> north =
        (j == ny - 1) ? Extrapolate(Get(v, c, j), Get(v, c, inner)) : Get(v, c, j + 1);
      const Sample<T> south =
        (j == 0) ? Extrapolate(Get(v, c, j), Get(v, c, inner)) : Get(v, c, j - 1);
      s[k] = north;
      s[3 + k] = Get(v, c, j);
      s[6 + k] = south;
    }
  }
  else
  {
    const int rows[3] = { j + 1, j, j - 1 };
    for (int r = 0; r < 3; ++r)
    {
      const int jj = rows[r];
      s[3 * r + 1] = Get(v, i, jj);
      s[3 * r + 0] = (i == 0) ? Extrapolate(Get(v, 0, jj), Get(v, 1, jj)) : Get(v, i - 1, jj);
      s[3 * r + 2] =
        (i == nx - 1) ? Extrapolate(Get(v, nx - 1, jj), Get(v, nx - 2, jj)) : Get(v, i + 1, jj);
    }
  }
  const T centre = v.At(i, j);
  for (int k = 0; k < 9; ++k)
  {
    w[k] = s[k].ok ? s[k].z : centre;
  }
  return true;
}

template<typename T>
void SlopeHorn1981Rows(const GridView<T>& view,
  const SlopeParams& params,
  T* slope,
  T* aspect,
  T* normals,
  int row0,
  int row1)
{
  const int nx = view.nx;
  const int ny = view.ny;
  if (nx < 2 || ny < 2 || !view.data)
  {
    return;
  }
  row0 = std::max(row0, 0);
  row1 = std::min(row1, ny);
  const CellOutput<T> out = { slope,
    aspect,
    normals,
    params.units == SlopeUnits::Percent,
    static_cast<T>(params.convergenceDeg) };
  T w[9];
  for (int j = row0; j < row1; ++j)
  {
    const SlopeRowCoefficients<T> c = SlopeHorn1981RowCoefficients(view, j, params.zFactor);
    const std::size_t rowStart = view.Index(0, j);
    // Border cells (and every cell of the first and last rows) take the general path.
    const bool borderRow = (j == 0 || j == ny - 1);
    const int iEnd = borderRow ? 0 : nx - 1;
    for (int i : { 0, nx - 1 })
    {
      if (borderRow)
      {
        break;
      }
      const std::size_t idx = rowStart + static_cast<std::size_t>(i);
      if (HornWindow(view, i, j, w))
      {
        ComputeCell(w[0], w[1], w[2], w[3], w[5], w[6], w[7], w[8], c, out, idx);
      }
      else
      {
        SetNaN(out, idx);
      }
    }
    if (borderRow)
    {
      for (int i = 0; i < nx; ++i)
      {
        const std::size_t idx = rowStart + static_cast<std::size_t>(i);
        if (HornWindow(view, i, j, w))
        {
          ComputeCell(w[0], w[1], w[2], w[3], w[5], w[6], w[7], w[8], c, out, idx);
        }
        else
        {
          SetNaN(out, idx);
        }
      }
      continue;
    }
    // Interior cells: row pointers, no branches except the mask test.
    const T* rn = view.data + view.Index(0, j + 1);
    const T* rc = view.data + rowStart;
    const T* rs = view.data + view.Index(0, j - 1);
    if (!view.valid)
    {
      if (InteriorRowVectorized(view, j, c, out))
      {
        continue;
      }
      for (int i = 1; i < iEnd; ++i)
      {
        ComputeCell(rn[i - 1],
          rn[i],
          rn[i + 1],
          rc[i - 1],
          rc[i + 1],
          rs[i - 1],
          rs[i],
          rs[i + 1],
          c,
          out,
          rowStart + static_cast<std::size_t>(i));
      }
    }
    else
    {
      const std::uint8_t* mn = view.valid + view.Index(0, j + 1);
      const std::uint8_t* mc = view.valid + rowStart;
      const std::uint8_t* ms = view.valid + view.Index(0, j - 1);
      for (int i = 1; i < iEnd; ++i)
      {
        const std::size_t idx = rowStart + static_cast<std::size_t>(i);
        const bool all = mn[i - 1] && mn[i] && mn[i + 1] && mc[i - 1] && mc[i] && mc[i + 1] &&
          ms[i - 1] && ms[i] && ms[i + 1];
        if (all)
        {
          ComputeCell(rn[i - 1],
            rn[i],
            rn[i + 1],
            rc[i - 1],
            rc[i + 1],
            rs[i - 1],
            rs[i],
            rs[i + 1],
            c,
            out,
            idx);
        }
        else if (HornWindow(view, i, j, w))
        {
          ComputeCell(w[0], w[1], w[2], w[3], w[5], w[6], w[7], w[8], c, out, idx);
        }
        else
        {
          SetNaN(out, idx);
        }
      }
    }
  }
}

template<typename T>
void SlopeHorn1981(const GridView<T>& view,
  const SlopeParams& params,
  T* slope,
  T* aspect,
  T* normals)
{
  SlopeHorn1981Rows(view, params, slope, aspect, normals, 0, view.ny);
}

template bool HornWindow<float>(const GridView<float>&, int, int, float[9]);
template bool HornWindow<double>(const GridView<double>&, int, int, double[9]);
template void SlopeHorn1981Rows<float>(const GridView<float>&,
  const SlopeParams&,
  float*,
  float*,
  float*,
  int,
  int);
template void SlopeHorn1981Rows<double>(const GridView<double>&,
  const SlopeParams&,
  double*,
  double*,
  double*,
  int,
  int);
template void SlopeHorn1981<float>(const GridView<float>&,
  const SlopeParams&,
  float*,
  float*,
  float*);
template void SlopeHorn1981<double>(const GridView<double>&,
  const SlopeParams&,
  double*,
  double*,
  double*);

} // namespace terrain
} // namespace terroir

#include "WaterFlow.h"
#include "WaterFlowRun.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#endif

namespace terroir
{
namespace hydrology
{

namespace
{
/// Height given to an outlet cell that has no valid neighbour: nothing can flow onto it.
constexpr float kUnreachable = 1.0e30f;

/// Row buffers of what the givers of one row send: per slot (column + 1; one slot of zeros on
/// each side, so that column -1 and nx + 2, the neighbours of the border columns, read as "gives
/// nothing") the water the giver loses (`out`, a depth in metres) and, per neighbour k in
/// neighbour order, f_k = s c_k max(0, L - H_k) (`flow[k * width + slot]`). The gather then
/// only adds what its eight neighbours computed for it: each difference L - H_k is formed once.
struct GiverRow
{
  std::size_t width = 0;
  std::vector<double> out;
  std::vector<double> flow;
  void Resize(std::size_t n)
  {
    width = n;
    out.assign(n, 0.0);
    flow.assign(kWaterFlowNeighbours * n, 0.0);
  }
  double* Flow(int k) { return flow.data() + static_cast<std::size_t>(k) * width; }
  const double* Flow(int k) const { return flow.data() + static_cast<std::size_t>(k) * width; }
};

// The row kernels take their arrays as restrict parameters (not in a struct): the compiler
// then knows that no store aliases another array and vectorises the loops without run-time
// overlap checks (with the arrays in a struct it gave up: too many pairs to check).

/// The giver row of padded row r (nx cells from column 1): terrain T and water W of the row,
/// absolute heights H = T + W of the rows south, mid and north, the 8 closenesses in neighbour
/// order; writes out and the 8 flows f0 .. f7 at slot = column + 1, and a negative out (never a
/// real value) on the cells of the other cases: -1 for the "part" case (PartCellsBody), -2 for
/// all = W exactly (left to WaterFlowEvacuation); their flows are written as 0 here.
// clang-format off
#define TERROIR_GIVER_ROW_PARAMETERS                                                               \
  int nx, const float* __restrict T, const double* __restrict W, const double* __restrict hs,      \
    const double* __restrict hm, const double* __restrict hn, const double* __restrict close,      \
    double* __restrict out, double* __restrict f0, double* __restrict f1, double* __restrict f2,   \
    double* __restrict f3, double* __restrict f4, double* __restrict f5, double* __restrict f6,    \
    double* __restrict f7
#define TERROIR_GIVER_ROW_ARGUMENTS nx, T, W, hs, hm, hn, close, out, f0, f1, f2, f3, f4, f5, f6, f7
// clang-format on

/// The fast "none" and "all" cases of WaterFlowEvacuation for every cell of a row, as straight
/// code (the same operations in the same order, so the same bits) that the compiler vectorises
/// across cells, and the flows s c_k max(0, L - H_k) with L = T and s = W / A (0 for none): the
/// expression the gather used to evaluate per receiver, so the same bits as the GPU kernel.
/// Cells in the "part" case (for PartCellsBody) and at all = W exactly (for the scalar
/// function) are flagged in `out`. (A flag array of bytes next to the float and double arrays
/// kept GCC 12 from vectorising the loop.)
template<bool Literal>
inline __attribute__((always_inline)) void GiverRowBody(TERROIR_GIVER_ROW_PARAMETERS)
{
  const double c0 = close[0], c1 = close[1], c2 = close[2], c3 = close[3];
  const double c4 = close[4], c5 = close[5], c6 = close[6], c7 = close[7];
  for (int pi = 1; pi <= nx; ++pi)
  {
    const double t = T[pi];
    const double w = W[pi];
    // Neighbour order E, NE, N, NW, W, SW, S, SE.
    const double d0 = std::max(0.0, t - hm[pi + 1]);
    const double d1 = std::max(0.0, t - hn[pi + 1]);
    const double d2 = std::max(0.0, t - hn[pi]);
    const double d3 = std::max(0.0, t - hn[pi - 1]);
    const double d4 = std::max(0.0, t - hm[pi - 1]);
    const double d5 = std::max(0.0, t - hs[pi - 1]);
    const double d6 = std::max(0.0, t - hs[pi]);
    const double d7 = std::max(0.0, t - hs[pi + 1]);
    double all = c0 * d0;
    all += c1 * d1;
    all += c2 * d2;
    all += c3 * d3;
    all += c4 * d4;
    all += c5 * d5;
    all += c6 * d6;
    all += c7 * d7;
    const double share = w / all;
    // Long (2016)'s literal rule (WaterFlowLongCapacity): no flow when the signed capacity, higher
    // neighbours included, is negative.
    bool wet = w > 0.0;
    if (Literal)
    {
      double wec = c0 * (t - hm[pi + 1]);
      wec += c1 * (t - hn[pi + 1]);
      wec += c2 * (t - hn[pi]);
      wec += c3 * (t - hn[pi - 1]);
      wec += c4 * (t - hm[pi - 1]);
      wec += c5 * (t - hs[pi - 1]);
      wec += c6 * (t - hs[pi]);
      wec += c7 * (t - hs[pi + 1]);
      wet = wet & !(wec < 0.0);
    }
    const bool fast = wet & (all >= w) & (share < 1.0); // no branches: selects only
    const double scale = fast ? share : 0.0;
    // Flags for the other cases: -1 part (all < W), -2 all with share exactly 1.
    out[pi + 1] = fast ? w : (wet ? (all < w ? -1.0 : -2.0) : 0.0);
    f0[pi + 1] = scale * c0 * d0;
    f1[pi + 1] = scale * c1 * d1;
    f2[pi + 1] = scale * c2 * d2;
    f3[pi + 1] = scale * c3 * d3;
    f4[pi + 1] = scale * c4 * d4;
    f5[pi + 1] = scale * c5 * d5;
    f6[pi + 1] = scale * c6 * d6;
    f7[pi + 1] = scale * c7 * d7;
  }
}

/// The "part" case of WaterFlowEvacuation for the m cells of a row at padded columns column[i]
/// (hs, hm, hn: absolute heights of the rows south, mid and north). Copies each cell's own
/// height and its 8 neighbours' into a structure of arrays (hc[i], H[k * m + i], k in neighbour
/// order), applies the same receiver set, the same additions and subtractions in the same order
/// and the same divisions as the scalar function, written as selects so that the compiler
/// vectorises across cells, and writes out and the 8 flows back into the giver row at slot
/// column + 1 (rowFlow[k * width + slot]). Each pass drops, in every cell at once, the receivers at
/// or above the cell's current level; passes stop when no cell changed (at most 8 can change, one
/// receiver at least each time). Scratch: hc, H, level, num, den, lowest, changed, scale.
// clang-format off
#define TERROIR_PART_CELLS_PARAMETERS                                                              \
  int m, const int* __restrict column, const double* __restrict hs, const double* __restrict hm,   \
    const double* __restrict hn, double* __restrict hc, double* __restrict H,                      \
    const double* __restrict close, double* __restrict level, double* __restrict num,              \
    double* __restrict den, double* __restrict lowest, double* __restrict changed,                 \
    double* __restrict scale, std::size_t width, double* __restrict rowOut,                        \
    double* __restrict rowFlow
#define TERROIR_PART_CELLS_ARGUMENTS                                                               \
  m, column, hs, hm, hn, hc, H, close, level, num, den, lowest, changed, scale, width, rowOut,     \
    rowFlow
// clang-format on

inline __attribute__((always_inline)) void PartCellsBody(TERROIR_PART_CELLS_PARAMETERS)
{
  // The cells' own heights and their neighbours', as a structure of arrays.
  for (int i = 0; i < m; ++i)
  {
    const int pi = column[i];
    hc[i] = hm[pi];
    H[0 * m + i] = hm[pi + 1];
    H[1 * m + i] = hn[pi + 1];
    H[2 * m + i] = hn[pi];
    H[3 * m + i] = hn[pi - 1];
    H[4 * m + i] = hm[pi - 1];
    H[5 * m + i] = hs[pi - 1];
    H[6 * m + i] = hs[pi];
    H[7 * m + i] = hs[pi + 1];
  }
  const double c0 = close[0], c1 = close[1], c2 = close[2], c3 = close[3];
  const double c4 = close[4], c5 = close[5], c6 = close[6], c7 = close[7];
  const double* __restrict H0 = H;
  const double* __restrict H1 = H + m;
  const double* __restrict H2 = H + 2 * m;
  const double* __restrict H3 = H + 3 * m;
  const double* __restrict H4 = H + 4 * m;
  const double* __restrict H5 = H + 5 * m;
  const double* __restrict H6 = H + 6 * m;
  const double* __restrict H7 = H + 7 * m;
  // The receivers are never stored: neighbour k still receives at a pass when H_k is below the
  // cell's own height and below every level of the earlier passes, i.e. below lowest[i], the
  // smallest of them (so a drop never depends on the levels decreasing in floating point).
  // changed[i] is 1 when the last pass dropped a receiver of cell i. Flags are doubles: bytes
  // among the doubles kept GCC 12 from vectorising.
  for (int i = 0; i < m; ++i)
  {
    const double h = hc[i];
    double nu = h;
    double de = 1.0;
    double any = 0.0;
// clang-format off
#define TERROIR_PART_ADD(K)                                                                        \
  {                                                                                                \
    const bool below = H##K[i] < h;                                                                \
    nu = below ? nu + c##K * H##K[i] : nu;                                                         \
    de = below ? de + c##K : de;                                                                   \
    any = below ? 1.0 : any;                                                                       \
  }
    // clang-format on
    TERROIR_PART_ADD(0)
    TERROIR_PART_ADD(1)
    TERROIR_PART_ADD(2)
    TERROIR_PART_ADD(3)
    TERROIR_PART_ADD(4)
    TERROIR_PART_ADD(5)
    TERROIR_PART_ADD(6)
    TERROIR_PART_ADD(7)
#undef TERROIR_PART_ADD
    num[i] = nu;
    den[i] = de;
    lowest[i] = h;
    changed[i] = any;
    scale[i] = any; // 1 with a receiver; without one the scalar function leaves scale 0
    level[i] = any != 0.0 ? nu / de : h;
  }
  for (int pass = 0; pass < 9; ++pass)
  {
    for (int i = 0; i < m; ++i)
    {
      const double lv = level[i];
      const double low = lowest[i];
      double nu = num[i];
      double de = den[i];
      double dropped = 0.0;
// clang-format off
#define TERROIR_PART_DROP(K)                                                                       \
  {                                                                                                \
    const double hk = H##K[i];                                                                     \
    const bool d = (hk < low) & (hk >= lv);                                                        \
    nu = d ? nu - c##K * hk : nu;                                                                  \
    de = d ? de - c##K : de;                                                                       \
    dropped = d ? 1.0 : dropped;                                                                   \
  }
      // clang-format on
      TERROIR_PART_DROP(0)
      TERROIR_PART_DROP(1)
      TERROIR_PART_DROP(2)
      TERROIR_PART_DROP(3)
      TERROIR_PART_DROP(4)
      TERROIR_PART_DROP(5)
      TERROIR_PART_DROP(6)
      TERROIR_PART_DROP(7)
#undef TERROIR_PART_DROP
      lowest[i] = std::min(low, lv);
      level[i] = dropped != 0.0 ? nu / de : lv;
      num[i] = nu;
      den[i] = de;
      changed[i] = dropped;
    }
    bool any = false;
    for (int i = 0; i < m; ++i)
    {
      any = any || changed[i] != 0.0;
    }
    if (!any)
    {
      break;
    }
  }
  // What the cell gives: sum over all neighbours of c_k max(0, L - H_k) (nothing without a
  // receiver: the level stays H_i and no neighbour is lower), and what each neighbour gets,
  // s c_k max(0, L - H_k), both into the giver row.
  double* __restrict F0 = rowFlow;
  double* __restrict F1 = rowFlow + width;
  double* __restrict F2 = rowFlow + 2 * width;
  double* __restrict F3 = rowFlow + 3 * width;
  double* __restrict F4 = rowFlow + 4 * width;
  double* __restrict F5 = rowFlow + 5 * width;
  double* __restrict F6 = rowFlow + 6 * width;
  double* __restrict F7 = rowFlow + 7 * width;
  for (int i = 0; i < m; ++i)
  {
    const double lv = level[i];
    const double sc = scale[i];
    const int slot = column[i] + 1;
    const double d0 = std::max(0.0, lv - H0[i]);
    const double d1 = std::max(0.0, lv - H1[i]);
    const double d2 = std::max(0.0, lv - H2[i]);
    const double d3 = std::max(0.0, lv - H3[i]);
    const double d4 = std::max(0.0, lv - H4[i]);
    const double d5 = std::max(0.0, lv - H5[i]);
    const double d6 = std::max(0.0, lv - H6[i]);
    const double d7 = std::max(0.0, lv - H7[i]);
    double o = c0 * d0;
    o += c1 * d1;
    o += c2 * d2;
    o += c3 * d3;
    o += c4 * d4;
    o += c5 * d5;
    o += c6 * d6;
    o += c7 * d7;
    rowOut[slot] = o;
    F0[slot] = sc * c0 * d0;
    F1[slot] = sc * c1 * d1;
    F2[slot] = sc * c2 * d2;
    F3[slot] = sc * c3 * d3;
    F4[slot] = sc * c4 * d4;
    F5[slot] = sc * c5 * d5;
    F6[slot] = sc * c6 * d6;
    F7[slot] = sc * c7 * d7;
  }
}

/// Absolute heights h = T + W of the n cells of a padded row.
// clang-format off
#define TERROIR_HEIGHTS_ROW_PARAMETERS                                                             \
  int n, const float* __restrict T, const double* __restrict W, double* __restrict h
#define TERROIR_HEIGHTS_ROW_ARGUMENTS n, T, W, h
// clang-format on
inline __attribute__((always_inline)) void HeightsRowBody(TERROIR_HEIGHTS_ROW_PARAMETERS)
{
  for (int i = 0; i < n; ++i)
  {
    h[i] = T[i] + W[i];
  }
}

/// The gather of padded row r (columns = nx + 2 cells): water W of the row, its isCell flags
/// (`interior` false on the border rows), the area ratios of the neighbouring rows, what the
/// row's own givers lose (mo) and the flows towards this row of the givers in it (mE, mW: the
/// givers west and east of a cell sending east and west) and in the rows north (nSE, nS, nSW)
/// and south (sNE, sN, sNW), at slot = column + 1 of the giver; writes the new water and the
/// discharge of the row, and per column what a cell gave (0 on outlets) and what an outlet
/// received (0 on cells), for the row's sums.
struct GatherRowConstants
{
  double fromNorth, fromSouth;
};
// clang-format off
#define TERROIR_GATHER_ROW_PARAMETERS                                                              \
  int columns, bool interior, const GatherRowConstants& k, const double* __restrict W,             \
    const std::uint8_t* __restrict isCell, const double* __restrict mo,                            \
    const double* __restrict mE, const double* __restrict mW, const double* __restrict nSE,        \
    const double* __restrict nS, const double* __restrict nSW, const double* __restrict sNE,       \
    const double* __restrict sN, const double* __restrict sNW, double* __restrict next,            \
    double* __restrict discharge, double* __restrict cellOut, double* __restrict outletIn,         \
    const double* __restrict rainRow,                                                              \
    const double* __restrict m1, const double* __restrict m2, const double* __restrict m3,         \
    double* __restrict edgeE, double* __restrict edgeNE, double* __restrict edgeN,                 \
    double* __restrict edgeNW
#define TERROIR_GATHER_ROW_ARGUMENTS                                                               \
  columns, interior, k, W, isCell, mo, mE, mW, nSE, nS, nSW, sNE, sN, sNW, next, discharge,        \
    cellOut, outletIn, rainRow, m1, m2, m3, edgeE, edgeNE, edgeN, edgeNW
// clang-format on

template<bool Edges>
inline __attribute__((always_inline)) void GatherRowBody(TERROIR_GATHER_ROW_PARAMETERS)
{
  const double fromNorth = k.fromNorth, fromSouth = k.fromSouth;
  for (int pi = 0; pi < columns; ++pi)
  {
    const int s = pi + 1; // slot of this column
    const double inRow = mE[s - 1] + mW[s + 1];
    const double inNorth = nSE[s - 1] + nS[s] + nSW[s + 1];
    const double inSouth = sNE[s - 1] + sN[s] + sNW[s + 1];
    const double in = inRow + fromNorth * inNorth + fromSouth * inSouth;
    const bool cell = interior & (isCell[pi] != 0);
    const double o = mo[s];
    const double kept = std::max(0.0, W[pi] - o + in) + rainRow[pi];
    next[pi] = cell ? kept : 0.0;
    discharge[pi] += cell ? o : 0.0;
    cellOut[pi] = cell ? o : 0.0;
    outletIn[pi] = cell ? 0.0 : in;
    if (Edges)
    {
      // Net flux through the cell's E, NE, N and NW edges (depth of this cell, positive out):
      // what it sent less what that neighbour sent back.
      edgeE[pi] += mE[s] - mW[s + 1];
      edgeNE[pi] += m1[s] - fromNorth * nSW[s + 1];
      edgeN[pi] += m2[s] - fromNorth * nS[s];
      edgeNW[pi] += m3[s] - fromNorth * nSE[s - 1];
    }
  }
}

// The row kernels for the baseline x86-64 target and, chosen at run time, for AVX2 and
// AVX-512: one body, so the same operations (no FMA contraction: -ffp-contract=off) and the
// same bits on every path.
void GiverRowBase(TERROIR_GIVER_ROW_PARAMETERS)
{
  GiverRowBody<false>(TERROIR_GIVER_ROW_ARGUMENTS);
}
void GiverLiteralRowBase(TERROIR_GIVER_ROW_PARAMETERS)
{
  GiverRowBody<true>(TERROIR_GIVER_ROW_ARGUMENTS);
}
void GatherRowBase(TERROIR_GATHER_ROW_PARAMETERS)
{
  GatherRowBody<false>(TERROIR_GATHER_ROW_ARGUMENTS);
}
void GatherEdgesRowBase(TERROIR_GATHER_ROW_PARAMETERS)
{
  GatherRowBody<true>(TERROIR_GATHER_ROW_ARGUMENTS);
}
void PartCellsBase(TERROIR_PART_CELLS_PARAMETERS)
{
  PartCellsBody(TERROIR_PART_CELLS_ARGUMENTS);
}
void HeightsRowBase(TERROIR_HEIGHTS_ROW_PARAMETERS)
{
  HeightsRowBody(TERROIR_HEIGHTS_ROW_ARGUMENTS);
}
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
__attribute__((target("avx2"))) void GiverRowAVX2(TERROIR_GIVER_ROW_PARAMETERS)
{
  GiverRowBody<false>(TERROIR_GIVER_ROW_ARGUMENTS);
}
__attribute__((target("avx2"))) void GiverLiteralRowAVX2(TERROIR_GIVER_ROW_PARAMETERS)
{
  GiverRowBody<true>(TERROIR_GIVER_ROW_ARGUMENTS);
}
__attribute__((target("avx2"))) void GatherRowAVX2(TERROIR_GATHER_ROW_PARAMETERS)
{
  GatherRowBody<false>(TERROIR_GATHER_ROW_ARGUMENTS);
}
__attribute__((target("avx2"))) void GatherEdgesRowAVX2(TERROIR_GATHER_ROW_PARAMETERS)
{
  GatherRowBody<true>(TERROIR_GATHER_ROW_ARGUMENTS);
}
__attribute__((target("avx2"))) void PartCellsAVX2(TERROIR_PART_CELLS_PARAMETERS)
{
  PartCellsBody(TERROIR_PART_CELLS_ARGUMENTS);
}
__attribute__((target("avx2"))) void HeightsRowAVX2(TERROIR_HEIGHTS_ROW_PARAMETERS)
{
  HeightsRowBody(TERROIR_HEIGHTS_ROW_ARGUMENTS);
}
__attribute__((target("avx512f,avx512vl,avx512bw"))) void GiverRowAVX512(
  TERROIR_GIVER_ROW_PARAMETERS)
{
  GiverRowBody<false>(TERROIR_GIVER_ROW_ARGUMENTS);
}
__attribute__((target("avx512f,avx512vl,avx512bw"))) void GiverLiteralRowAVX512(
  TERROIR_GIVER_ROW_PARAMETERS)
{
  GiverRowBody<true>(TERROIR_GIVER_ROW_ARGUMENTS);
}
__attribute__((target("avx512f,avx512vl,avx512bw"))) void GatherRowAVX512(
  TERROIR_GATHER_ROW_PARAMETERS)
{
  GatherRowBody<false>(TERROIR_GATHER_ROW_ARGUMENTS);
}
__attribute__((target("avx512f,avx512vl,avx512bw"))) void GatherEdgesRowAVX512(
  TERROIR_GATHER_ROW_PARAMETERS)
{
  GatherRowBody<true>(TERROIR_GATHER_ROW_ARGUMENTS);
}
__attribute__((target("avx512f,avx512vl,avx512bw"))) void PartCellsAVX512(
  TERROIR_PART_CELLS_PARAMETERS)
{
  PartCellsBody(TERROIR_PART_CELLS_ARGUMENTS);
}
__attribute__((target("avx512f,avx512vl,avx512bw"))) void HeightsRowAVX512(
  TERROIR_HEIGHTS_ROW_PARAMETERS)
{
  HeightsRowBody(TERROIR_HEIGHTS_ROW_ARGUMENTS);
}
#endif

/// Columns pi (1 .. nx) of the cells flagged -1 ("part") in out[pi + 1], in column order, into
/// column[] (which has room for nx + 16); returns their count and sets `rare` when a cell is
/// flagged -2. Which cells go to the part kernel never changes a result, so the AVX-512 variant
/// may do it its own way.
// clang-format off
#define TERROIR_COMPACT_PARAMETERS                                                                 \
  int nx, const double* __restrict out, int* __restrict column, bool& rare
// clang-format on
int CompactPartsBase(TERROIR_COMPACT_PARAMETERS)
{
  int m = 0;
  bool anyRare = false;
  for (int pi = 1; pi <= nx; ++pi)
  {
    // Branch-free: the column is always written, kept only for a part cell.
    const double o = out[pi + 1];
    column[m] = pi;
    m += o == -1.0 ? 1 : 0;
    anyRare = anyRare || o == -2.0;
  }
  rare = anyRare;
  return m;
}
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
/// 16 cells at a time: two compares give a 16-bit mask, a compress in registers packs the
/// columns (a compress straight to memory is slow on AMD Zen 4), a full 16-int store writes
/// them and the count advances by the mask's population.
__attribute__((target("avx512f,avx512vl,avx512bw,popcnt"))) int CompactPartsAVX512(
  TERROIR_COMPACT_PARAMETERS)
{
  const __m512d part = _mm512_set1_pd(-1.0);
  const __m512d allW = _mm512_set1_pd(-2.0);
  __m512i columns = _mm512_setr_epi32(1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16);
  const __m512i sixteen = _mm512_set1_epi32(16);
  int m = 0;
  unsigned rareBits = 0;
  int pi = 1;
  for (; pi + 15 <= nx; pi += 16)
  {
    const __m512d a = _mm512_loadu_pd(out + pi + 1);
    const __m512d b = _mm512_loadu_pd(out + pi + 9);
    const unsigned mask = static_cast<unsigned>(_mm512_cmp_pd_mask(a, part, _CMP_EQ_OQ)) |
      (static_cast<unsigned>(_mm512_cmp_pd_mask(b, part, _CMP_EQ_OQ)) << 8);
    rareBits |= static_cast<unsigned>(_mm512_cmp_pd_mask(a, allW, _CMP_EQ_OQ)) |
      static_cast<unsigned>(_mm512_cmp_pd_mask(b, allW, _CMP_EQ_OQ));
    _mm512_storeu_si512(
      column + m, _mm512_maskz_compress_epi32(static_cast<__mmask16>(mask), columns));
    m += __builtin_popcount(mask);
    columns = _mm512_add_epi32(columns, sixteen);
  }
  bool tailRare = false;
  for (; pi <= nx; ++pi)
  {
    const double o = out[pi + 1];
    column[m] = pi;
    m += o == -1.0 ? 1 : 0;
    tailRare = tailRare || o == -2.0;
  }
  rare = rareBits != 0 || tailRare;
  return m;
}
#endif

/// Sum of x[0 .. n) in a fixed order that does not depend on the instruction set: eight
/// running sums (x[i] goes to sum i mod 8, in column order), then added pairwise. The compiler
/// vectorises the eight lanes; one running sum would be a chain of n dependent additions.
double RowSum(const double* x, int n)
{
  double lane[8] = { 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0 };
  int i = 0;
  for (; i + 8 <= n; i += 8)
  {
    for (int l = 0; l < 8; ++l)
    {
      lane[l] += x[i + l];
    }
  }
  for (int l = 0; i + l < n; ++l)
  {
    lane[l] += x[i + l];
  }
  return ((lane[0] + lane[1]) + (lane[2] + lane[3])) + ((lane[4] + lane[5]) + (lane[6] + lane[7]));
}

struct RowKernels
{
  void (*giver)(TERROIR_GIVER_ROW_PARAMETERS) = GiverRowBase;
  void (*giverLiteral)(TERROIR_GIVER_ROW_PARAMETERS) = GiverLiteralRowBase;
  void (*gather)(TERROIR_GATHER_ROW_PARAMETERS) = GatherRowBase;
  void (*gatherEdges)(TERROIR_GATHER_ROW_PARAMETERS) = GatherEdgesRowBase;
  void (*part)(TERROIR_PART_CELLS_PARAMETERS) = PartCellsBase;
  void (*heights)(TERROIR_HEIGHTS_ROW_PARAMETERS) = HeightsRowBase;
  int (*compact)(TERROIR_COMPACT_PARAMETERS) = CompactPartsBase;
};

/// The widest kernels this CPU runs (TERROIR_WATERFLOW_ISA=base|avx2|avx512 narrows the
/// choice, for benchmarks and tests).
RowKernels ChooseRowKernels()
{
  RowKernels k;
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  const char* env = std::getenv("TERROIR_WATERFLOW_ISA");
  const std::string want = env ? env : "";
  if (want == "base")
  {
    return k;
  }
  if (want != "avx2" && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
    __builtin_cpu_supports("avx512bw"))
  {
    k.giver = GiverRowAVX512;
    k.giverLiteral = GiverLiteralRowAVX512;
    k.gather = GatherRowAVX512;
    k.gatherEdges = GatherEdgesRowAVX512;
    k.part = PartCellsAVX512;
    k.heights = HeightsRowAVX512;
    k.compact = CompactPartsAVX512;
  }
  else if (__builtin_cpu_supports("avx2"))
  {
    k.giver = GiverRowAVX2;
    k.giverLiteral = GiverLiteralRowAVX2;
    k.gather = GatherRowAVX2;
    k.gatherEdges = GatherEdgesRowAVX2;
    k.part = PartCellsAVX2;
    k.heights = HeightsRowAVX2;
  }
#endif
  return k;
}
} // namespace

//------------------------------------------------------------------------------
const char* WaterFlowStopReasonName(WaterFlowStopReason reason)
{
  switch (reason)
  {
    case WaterFlowStopReason::AutoStop:
      return "AutoStop";
    case WaterFlowStopReason::NoMovement:
      return "NoMovement";
    case WaterFlowStopReason::MaximumIterations:
      return "MaximumIterations";
    case WaterFlowStopReason::Balanced:
      return "Balanced";
  }
  return "Unknown";
}

namespace
{
/// The row buffers of one block of rows: kept between iterations (in the simulation's pool)
/// instead of allocating and zeroing them, about 0.3 MB at 1024 columns, for each block of each
/// iteration. The giver rows' edge slots and the `zero` row are never written with anything but
/// zero, so they stay zero.
struct RowScratch
{
  explicit RowScratch(int stride)
  {
    const std::size_t n = static_cast<std::size_t>(stride);
    for (auto& r : this->rows)
    {
      r.Resize(n + 2);
    }
    this->zero.Resize(n + 2);
    for (auto& h : this->heights)
    {
      h.assign(n, 0.0);
    }
    this->cellOut.assign(n, 0.0);
    this->cellEmptied.assign(n, 0.0);
    this->outletIn.assign(n, 0.0);
    this->partColumn.assign(n + 16, 0);
    this->partHeights.assign(8 * n, 0.0);
    for (auto* v : { &this->partSelf,
           &this->partLevel,
           &this->partNum,
           &this->partDen,
           &this->partLowest,
           &this->partChanged,
           &this->partScale })
    {
      v->assign(n, 0.0);
    }
  }
  GiverRow rows[3];
  GiverRow zero; // beyond the southern and northern border rows
  std::vector<double> heights[4];
  std::vector<double> cellOut, outletIn, cellEmptied;
  // The part cells of one row.
  std::vector<int> partColumn;
  std::vector<double> partSelf, partHeights, partLevel, partNum, partDen, partLowest, partChanged,
    partScale;
};
} // namespace

/// A pool of row buffers (see RowScratch) shared by the blocks of rows.
struct WaterFlowSimulation::ScratchPool
{
  std::mutex mutex;
  std::vector<std::unique_ptr<RowScratch>> free;

  /// A scratch from the pool, or a new one for rows of `stride` padded cells.
  std::unique_ptr<RowScratch> Take(int stride)
  {
    std::unique_ptr<RowScratch> scratch;
    {
      std::lock_guard<std::mutex> lock(this->mutex);
      if (!this->free.empty())
      {
        scratch = std::move(this->free.back());
        this->free.pop_back();
      }
    }
    if (!scratch)
    {
      scratch.reset(new RowScratch(stride));
    }
    return scratch;
  }
};

/**
 * One block of rows of an iteration (RowBlock), on one scratch: what the givers of each padded
 * row send (Givers), then the gather of each row from its three giver rows (Gather), in a ring
 * of three giver rows (Rows). Each stage is one call of a row kernel (RowKernels) over a whole
 * row; the per-row set-up lives here.
 */
struct WaterFlowSimulation::RowPass
{
  RowPass(WaterFlowSimulation& sim, RowScratch& scratch);
  /// The rows [begin, end) of the block: RowMoved, RowOutflow and RowEmptied of each.
  void Rows(int begin, int end);

private:
  /// What an interior row and the border rows it gathers add up to (m^3, and a cell count).
  struct Volumes
  {
    double moved = 0.0;
    double outflow = 0.0;
    double emptied = 0.0;
  };
  /// Absolute heights H = T + W of padded row r, from the ring of four rows (computed once).
  const double* HeightsOf(int r);
  /// Fills `g` with the givers of padded row r (all zero on the border rows and columns).
  void Givers(int r, GiverRow& g);
  /// The cells of `g` flagged -2 (all = W exactly) through the scalar WaterFlowEvacuation.
  void RareGivers(std::size_t row0,
    const double* hs,
    const double* hm,
    const double* hn,
    const double close[8],
    GiverRow& g);
  /// Gathers padded row r (interior rows update water; outlets add to the outflow).
  void Gather(int r, const GiverRow& south, const GiverRow& mid, const GiverRow& north, Volumes& v);
  /// The cells of interior row r that gave all their water (Long (2016)'s stop measure).
  double EmptiedCells(int r, std::size_t row0);

  static std::size_t RowStart(int r, int stride)
  {
    return static_cast<std::size_t>(r) * static_cast<std::size_t>(stride);
  }

  WaterFlowSimulation& Sim;
  const RowKernels Kernels;
  const int NX;
  const int NY;
  const int Stride;
  RowScratch& Buffers;
  const float* T;
  const double* W;
  const std::uint8_t* IsCell;
  double* Next;
  double* Discharge;
  int HeightRow[4] = { -1, -1, -1, -1 };
};

//------------------------------------------------------------------------------
WaterFlowSimulation::RowPass::RowPass(WaterFlowSimulation& sim, RowScratch& scratch)
  : Sim(sim)
  , Kernels(ChooseRowKernels())
  , NX(sim.NX)
  , NY(sim.NY)
  , Stride(sim.NX + 2)
  , Buffers(scratch)
  , T(sim.Terrain.data())
  , W(sim.Water.data())
  , IsCell(sim.IsCell.data())
  , Next(sim.NextWater.data())
  , Discharge(sim.DischargeDepth.data())
{
}

//------------------------------------------------------------------------------
inline const double* WaterFlowSimulation::RowPass::HeightsOf(int r)
{
  // A ring of four rows: the givers of row r + 1 read rows r .. r + 2 while row r gathers.
  const int k = r & 3;
  std::vector<double>* heights = this->Buffers.heights;
  if (this->HeightRow[k] != r)
  {
    const std::size_t row0 = RowStart(r, this->Stride);
    this->Kernels.heights(this->Stride, this->T + row0, this->W + row0, heights[k].data());
    this->HeightRow[k] = r;
  }
  return heights[k].data();
}

//------------------------------------------------------------------------------
void WaterFlowSimulation::RowPass::Givers(int r, GiverRow& g)
{
  if (r <= 0 || r >= NY + 1)
  {
    std::fill(g.out.begin(), g.out.end(), 0.0);
    std::fill(g.flow.begin(), g.flow.end(), 0.0);
    return;
  }
  const WaterFlowSimulation& sim = this->Sim;
  const double close[8] = { sim.CloseEW[r],
    sim.CloseDiag[r],
    sim.CloseNS[r],
    sim.CloseDiag[r],
    sim.CloseEW[r],
    sim.CloseDiag[r - 1],
    sim.CloseNS[r - 1],
    sim.CloseDiag[r - 1] };
  const std::size_t row0 = RowStart(r, this->Stride);
  const double* hs = this->HeightsOf(r - 1);
  const double* hm = this->HeightsOf(r);
  const double* hn = this->HeightsOf(r + 1);
  (sim.LongCapacity ? this->Kernels.giverLiteral : this->Kernels.giver)(NX,
    this->T + row0,
    this->W + row0,
    hs,
    hm,
    hn,
    close,
    g.out.data(),
    g.Flow(0),
    g.Flow(1),
    g.Flow(2),
    g.Flow(3),
    g.Flow(4),
    g.Flow(5),
    g.Flow(6),
    g.Flow(7));
  // The part cells, gathered into a structure of arrays for the vectorised kernel; the rare
  // all = W cells through the scalar function.
  RowScratch& sc = this->Buffers;
  bool rare = false;
  const int m = this->Kernels.compact(NX, g.out.data(), sc.partColumn.data(), rare);
  if (rare)
  {
    this->RareGivers(row0, hs, hm, hn, close, g);
  }
  if (m == 0)
  {
    return;
  }
  this->Kernels.part(m,
    sc.partColumn.data(),
    hs,
    hm,
    hn,
    sc.partSelf.data(),
    sc.partHeights.data(),
    close,
    sc.partLevel.data(),
    sc.partNum.data(),
    sc.partDen.data(),
    sc.partLowest.data(),
    sc.partChanged.data(),
    sc.partScale.data(),
    g.width,
    g.out.data(),
    g.flow.data());
}

//------------------------------------------------------------------------------
void WaterFlowSimulation::RowPass::RareGivers(std::size_t row0,
  const double* hs,
  const double* hm,
  const double* hn,
  const double close[8],
  GiverRow& g)
{
  for (int pi = 1; pi <= NX; ++pi)
  {
    if (g.out[pi + 1] == -2.0)
    {
      const double h[8] = {
        hm[pi + 1], hn[pi + 1], hn[pi], hn[pi - 1], hm[pi - 1], hs[pi - 1], hs[pi], hs[pi + 1]
      };
      const WaterFlowGiver v = WaterFlowEvacuation(
        this->T[row0 + pi], this->W[row0 + pi], h, close, this->Sim.LongCapacity);
      g.out[pi + 1] = v.out;
      for (int k = 0; k < kWaterFlowNeighbours; ++k)
      {
        g.Flow(k)[pi + 1] = v.scale * close[k] * std::max(0.0, v.level - h[k]);
      }
    }
  }
}

//------------------------------------------------------------------------------
void WaterFlowSimulation::RowPass::Gather(int r,
  const GiverRow& south,
  const GiverRow& mid,
  const GiverRow& north,
  Volumes& v)
{
  const WaterFlowSimulation& sim = this->Sim;
  const std::vector<double>& area = sim.Area;
  RowScratch& sc = this->Buffers;
  const std::size_t row0 = RowStart(r, this->Stride);
  GatherRowConstants k;
  // Volume sent from a neighbouring row becomes depth here through the area ratio.
  k.fromNorth = r + 1 < NY + 2 ? area[r + 1] / area[r] : 0.0;
  k.fromSouth = r > 0 ? area[r - 1] / area[r] : 0.0;
  // Neighbour order E, NE, N, NW, W, SW, S, SE: a cell receives what its row's givers send
  // east (0) and west (4), what the northern row sends south-east (7), south (6) and
  // south-west (5), and what the southern row sends north-east (1), north (2), north-west (3).
  const bool edges = !sim.Edges.empty();
  double* edge = this->Sim.Edges.data();
  const std::size_t plane = edges ? sim.Edges.size() / 4 : 0;
  (edges ? this->Kernels.gatherEdges : this->Kernels.gather)(this->Stride,
    r >= 1 && r <= NY,
    k,
    this->W + row0,
    this->IsCell + row0,
    mid.out.data(),
    mid.Flow(0),
    mid.Flow(4),
    north.Flow(7),
    north.Flow(6),
    north.Flow(5),
    south.Flow(1),
    south.Flow(2),
    south.Flow(3),
    this->Next + row0,
    this->Discharge + row0,
    sc.cellOut.data(),
    sc.outletIn.data(),
    sim.RainField.empty() ? sim.RainRowData.data() : sim.RainField.data() + row0,
    mid.Flow(1),
    mid.Flow(2),
    mid.Flow(3),
    edges ? edge + row0 : nullptr,
    edges ? edge + plane + row0 : nullptr,
    edges ? edge + 2 * plane + row0 : nullptr,
    edges ? edge + 3 * plane + row0 : nullptr);
  if (sim.Window[0] >= 0)
  {
    // A count window (distributed runs): only its cells count (zeros add nothing).
    if (r < sim.Window[2] || r >= sim.Window[3])
    {
      return;
    }
    for (int pi = 0; pi < this->Stride; ++pi)
    {
      if (pi < sim.Window[0] || pi >= sim.Window[1])
      {
        sc.cellOut[pi] = 0.0;
        sc.outletIn[pi] = 0.0;
      }
    }
  }
  v.moved += RowSum(sc.cellOut.data(), this->Stride) * area[r];
  v.outflow += RowSum(sc.outletIn.data(), this->Stride) * area[r];
  if (sim.CountEmptied)
  {
    v.emptied += this->EmptiedCells(r, row0);
  }
}

//------------------------------------------------------------------------------
double WaterFlowSimulation::RowPass::EmptiedCells(int r, std::size_t row0)
{
  // Cells that gave all their water (the "all" case gives exactly W): cellOut holds what each
  // cell gave.
  RowScratch& sc = this->Buffers;
  const double* cellOut = sc.cellOut.data();
  double* cellEmptied = sc.cellEmptied.data();
  const double* w = this->W + row0;
  const std::uint8_t* cells = this->IsCell + row0;
  const bool interior = r >= 1 && r <= NY;
  const int stride = this->Stride;
  for (int pi = 0; pi < stride; ++pi)
  {
    cellEmptied[pi] = interior && cells[pi] && w[pi] > 0.0 && cellOut[pi] == w[pi] ? 1.0 : 0.0;
  }
  return RowSum(cellEmptied, stride);
}

//------------------------------------------------------------------------------
void WaterFlowSimulation::RowPass::Rows(int begin, int end)
{
  // Ring of three giver rows: padded rows r - 1, r, r + 1 for interior row r = j + 1. Each
  // stage runs over a whole row: strips of a few hundred columns, the stages interleaved (to
  // spread the memory traffic over the arithmetic), and software prefetches a row ahead were
  // both slower (1024^2: 1.5 ms per iteration whole, 1.65 in strips of 512, 2.2 of 256; 1.6-1.9
  // with the prefetches).
  GiverRow* rows = this->Buffers.rows;
  const GiverRow& zero = this->Buffers.zero;
  int slot[3] = { 0, 1, 2 };
  this->Givers(begin, rows[slot[0]]);
  this->Givers(begin + 1, rows[slot[1]]);
  for (int j = begin; j < end; ++j)
  {
    const int r = j + 1;
    this->Givers(r + 1, rows[slot[2]]);
    Volumes v;
    if (r == 1)
    {
      // The southern border row gathers from row 1 only.
      this->Gather(0, zero, rows[slot[0]], rows[slot[1]], v);
    }
    this->Gather(r, rows[slot[0]], rows[slot[1]], rows[slot[2]], v);
    if (r == NY)
    {
      this->Gather(NY + 1, rows[slot[1]], rows[slot[2]], zero, v);
    }
    this->Sim.RowMoved[j] = v.moved;
    this->Sim.RowOutflow[j] = v.outflow;
    this->Sim.RowEmptied[j] = v.emptied;
    std::rotate(slot, slot + 1, slot + 3);
  }
}

//------------------------------------------------------------------------------
WaterFlowSimulation::~WaterFlowSimulation() = default;
namespace
{
std::uint64_t NextSimulationId()
{
  static std::atomic<std::uint64_t> next{ 0 };
  return ++next;
}
} // namespace

WaterFlowSimulation::WaterFlowSimulation(WaterFlowSimulation&&) noexcept = default;
WaterFlowSimulation& WaterFlowSimulation::operator=(WaterFlowSimulation&&) noexcept = default;

//------------------------------------------------------------------------------
double WaterFlowSimulation::SmallestSpacing(const GridView<float>& terrain)
{
  double dmin = std::numeric_limits<double>::infinity();
  for (int j = 0; j < terrain.ny; ++j)
  {
    dmin = std::min(dmin, std::min(terrain.DxAt(j), terrain.DyAt(j)));
  }
  return dmin;
}

//------------------------------------------------------------------------------
WaterFlowSimulation::WaterFlowSimulation(const GridView<float>& terrain,
  const double* waterMetres,
  double smallestSpacing)
  : NX(terrain.nx)
  , NY(terrain.ny)
  , Identity(NextSimulationId())
  , Scratch(new ScratchPool)
{
  if (NX <= 0 || NY <= 0 || !terrain.data || !waterMetres)
  {
    throw std::invalid_argument("water flow: empty terrain");
  }
  const int stride = NX + 2;
  const std::size_t padded = static_cast<std::size_t>(stride) * static_cast<std::size_t>(NY + 2);
  this->Terrain.assign(padded, kUnreachable);
  this->IsCell.assign(padded, 0);
  this->Water.assign(padded, 0.0);
  this->DischargeDepth.assign(padded, 0.0);
  auto at = [stride](int i, int j) -> std::size_t
  {
    return static_cast<std::size_t>(j + 1) * static_cast<std::size_t>(stride) +
      static_cast<std::size_t>(i + 1);
  };
  auto valid = [&terrain](int i, int j) -> bool
  {
    return i >= 0 && j >= 0 && i < terrain.nx && j < terrain.ny && terrain.IsValid(i, j) &&
      std::isfinite(terrain.At(i, j));
  };

  // Spacing per padded row (the border rows copy their neighbour row) and areas.
  this->Area.assign(static_cast<std::size_t>(NY + 2), 0.0);
  std::vector<double> dx(NY + 2);
  std::vector<double> dy(NY + 2);
  double dmin = std::numeric_limits<double>::infinity();
  for (int r = 0; r < NY + 2; ++r)
  {
    const int j = std::min(std::max(r - 1, 0), NY - 1);
    dx[r] = terrain.DxAt(j);
    dy[r] = terrain.DyAt(j);
    if (!(std::isfinite(dx[r]) && dx[r] > 0.0 && std::isfinite(dy[r]) && dy[r] > 0.0))
    {
      throw std::invalid_argument(
        "water flow: spacing of row " + std::to_string(j) + " is not a positive number");
    }
    this->Area[r] = dx[r] * dy[r];
    dmin = std::min(dmin, std::min(dx[r], dy[r]));
  }
  if (smallestSpacing != 0.0)
  {
    if (!(std::isfinite(smallestSpacing) && smallestSpacing > 0.0 && smallestSpacing <= dmin))
    {
      throw std::invalid_argument("water flow: the smallest spacing must be positive and at most "
                                  "the grid's own");
    }
    dmin = smallestSpacing;
  }
  this->CloseEW.assign(NY + 2, 0.0);
  this->CloseNS.assign(NY + 2, 0.0);
  this->CloseDiag.assign(NY + 2, 0.0);
  for (int r = 0; r < NY + 2; ++r)
  {
    const int r1 = std::min(r + 1, NY + 1);
    const double mx = 0.5 * (dx[r] + dx[r1]);
    const double my = 0.5 * (dy[r] + dy[r1]);
    this->CloseEW[r] = dmin / dx[r];
    this->CloseNS[r] = dmin / my;
    this->CloseDiag[r] = dmin / std::sqrt(mx * mx + my * my);
  }

  // Terrain, water, initial volume.
  for (int j = 0; j < NY; ++j)
  {
    for (int i = 0; i < NX; ++i)
    {
      const std::size_t c = at(i, j);
      if (!valid(i, j))
      {
        continue;
      }
      const double w = waterMetres[terrain.Index(i, j)];
      if (!(std::isfinite(w) && w >= 0.0))
      {
        throw std::invalid_argument("water flow: water depth " + std::to_string(w) +
          " m at cell (" + std::to_string(i) + ", " + std::to_string(j) +
          ") is negative or not a number");
      }
      this->Terrain[c] = terrain.At(i, j);
      this->IsCell[c] = 1;
      this->Water[c] = w;
      this->Initial += w * this->Area[j + 1];
      this->CellAreaTotal += this->Area[j + 1];
    }
  }
  // Outlets: no-data cells take the lowest valid neighbour; border cells continue the slope.
  static const int di[8] = { 1, 1, 0, -1, -1, -1, 0, 1 };
  static const int dj[8] = { 0, 1, 1, 1, 0, -1, -1, -1 };
  auto lowestValidNeighbour = [&](int i, int j) -> float
  {
    float m = kUnreachable;
    for (int k = 0; k < 8; ++k)
    {
      if (valid(i + di[k], j + dj[k]))
      {
        m = std::min(m, terrain.At(i + di[k], j + dj[k]));
      }
    }
    return m;
  };
  for (int j = -1; j <= NY; ++j)
  {
    for (int i = -1; i <= NX; ++i)
    {
      const bool border = i < 0 || j < 0 || i >= NX || j >= NY;
      if (!border && valid(i, j))
      {
        continue;
      }
      float h = lowestValidNeighbour(i, j);
      if (border)
      {
        // The inward direction (towards the grid), one step for the edge cell, two for the
        // cell after it.
        const int si = i < 0 ? 1 : (i >= NX ? -1 : 0);
        const int sj = j < 0 ? 1 : (j >= NY ? -1 : 0);
        const int ei = i + si;
        const int ej = j + sj;
        if (valid(ei, ej))
        {
          const float te = terrain.At(ei, ej);
          h = valid(ei + si, ej + sj) ? 2.0f * te - terrain.At(ei + si, ej + sj) : te;
        }
      }
      this->Terrain[at(i, j)] = h;
    }
  }
  this->NextWater = this->Water;
  this->RowMoved.assign(NY, 0.0);
  this->RowOutflow.assign(NY, 0.0);
  this->RowEmptied.assign(NY, 0.0);
  this->RainRowData.assign(static_cast<std::size_t>(stride), 0.0);
}

//------------------------------------------------------------------------------
void WaterFlowSimulation::RowBlock(int begin, int end)
{
  // A scratch from the pool (or a new one), given back when the block is done.
  ScratchPool& pool = *this->Scratch;
  std::unique_ptr<RowScratch> scratch = pool.Take(NX + 2);
  struct GiveBack
  {
    ScratchPool& pool;
    std::unique_ptr<RowScratch>& s;
    ~GiveBack()
    {
      std::lock_guard<std::mutex> lock(pool.mutex);
      pool.free.push_back(std::move(s));
    }
  } giveBack{ pool, scratch };
  RowPass(*this, *scratch).Rows(begin, end);
}

//------------------------------------------------------------------------------
WaterFlowIteration WaterFlowSimulation::Step()
{
  auto body = [this](int b, int e) { this->RowBlock(b, e); };
  if (this->Parallel)
  {
    this->Parallel(0, NY, body);
  }
  else
  {
    body(0, NY);
  }
  WaterFlowIteration it;
  for (int j = 0; j < NY; ++j)
  {
    it.moved += this->RowMoved[j];
    it.outflow += this->RowOutflow[j];
    it.emptied += this->RowEmptied[j];
  }
  this->Water.swap(this->NextWater);
  if (this->Hook)
  {
    this->Hook(*this, it);
  }
  this->RecordIteration(it);
  return it;
}

//------------------------------------------------------------------------------
void WaterFlowSimulation::SetCountWindow(int column0, int column1, int row0, int row1)
{
  if (column0 < 0 || column1 > NX + 2 || column0 >= column1 || row0 < 0 || row1 > NY + 2 ||
    row0 >= row1)
  {
    throw std::invalid_argument("water flow: the count window is not inside the padded grid");
  }
  this->Window[0] = column0;
  this->Window[1] = column1;
  this->Window[2] = row0;
  this->Window[3] = row1;
}

//------------------------------------------------------------------------------
void WaterFlowSimulation::RecordIteration(const WaterFlowIteration& it)
{
  ++this->IterationCount;
  this->Moved.push_back(it.moved);
  this->Outflow.push_back(it.outflow);
  this->Emptied.push_back(it.emptied);
  this->MovedTotal += it.moved;
  this->OutflowTotal += it.outflow;
  this->EmptiedTotal += it.emptied;
}

//------------------------------------------------------------------------------
void WaterFlowSimulation::SetRain(double metres)
{
  if (!(std::isfinite(metres) && metres >= 0.0))
  {
    throw std::invalid_argument("water flow: rain per iteration must be a finite depth >= 0");
  }
  this->Rain = metres;
  std::vector<double>().swap(this->RainField);
  this->RainRowData.assign(static_cast<std::size_t>(NX + 2), metres);
  this->RainVolumeTotal = metres * this->CellAreaTotal;
}

//------------------------------------------------------------------------------
void WaterFlowSimulation::SetRainField(const double* metres)
{
  const int stride = NX + 2;
  std::vector<double> field(this->Water.size(), 0.0);
  double volume = 0.0;
  double most = 0.0;
  for (int j = 0; j < NY; ++j)
  {
    double row = 0.0;
    for (int i = 0; i < NX; ++i)
    {
      const std::size_t c = static_cast<std::size_t>(j + 1) * stride + (i + 1);
      if (!this->IsCell[c])
      {
        continue;
      }
      const double r = metres[static_cast<std::size_t>(j) * NX + i];
      if (!(std::isfinite(r) && r >= 0.0))
      {
        throw std::invalid_argument("water flow: rain " + std::to_string(r) + " m at cell (" +
          std::to_string(i) + ", " + std::to_string(j) + ") is negative or not a number");
      }
      field[c] = r;
      row += r;
      most = std::max(most, r);
    }
    volume += row * this->Area[j + 1];
  }
  this->RainField.swap(field);
  this->Rain = most;
  this->RainVolumeTotal = volume;
}

//------------------------------------------------------------------------------
void WaterFlowSimulation::SetNetFlux(bool on)
{
  if (on)
  {
    this->Edges.assign(4 * this->Water.size(), 0.0);
  }
  else
  {
    std::vector<double>().swap(this->Edges);
  }
}

//------------------------------------------------------------------------------
void WaterFlowSimulation::GetNetDischarge(double* discharge, std::int8_t* dominant) const
{
  if (this->Edges.empty())
  {
    throw std::logic_error("water flow: net flux is off");
  }
  const std::size_t stride = static_cast<std::size_t>(NX + 2);
  const std::size_t plane = this->Water.size();
  const double* e = this->Edges.data();
  const double* ne = e + plane;
  const double* n = e + 2 * plane;
  const double* nw = e + 3 * plane;
  for (int j = 0; j < NY; ++j)
  {
    const std::size_t r = static_cast<std::size_t>(j + 1);
    const double a = this->Area[r];
    const double below = this->Area[r - 1];
    for (int i = 0; i < NX; ++i)
    {
      const std::size_t c = r * stride + static_cast<std::size_t>(i + 1);
      const std::size_t out = static_cast<std::size_t>(j) * NX + i;
      if (!this->IsCell[c])
      {
        discharge[out] = std::numeric_limits<double>::quiet_NaN();
        if (dominant)
        {
          dominant[out] = -1;
        }
        continue;
      }
      // Volume out through each edge, neighbour order E, NE, N, NW, W, SW, S, SE.
      const double v[8] = { e[c] * a,
        ne[c] * a,
        n[c] * a,
        nw[c] * a,
        -e[c - 1] * a,
        -ne[c - stride - 1] * below,
        -n[c - stride] * below,
        -nw[c - stride + 1] * below };
      double q = 0.0;
      double most = 0.0;
      int d = -1;
      for (int k = 0; k < 8; ++k)
      {
        q += std::max(0.0, v[k]);
        if (v[k] > most)
        {
          most = v[k];
          d = k;
        }
      }
      discharge[out] = q;
      if (dominant)
      {
        dominant[out] = static_cast<std::int8_t>(d);
      }
    }
  }
}

//------------------------------------------------------------------------------
void ThinAcrossFlow(const GridView<double>& discharge,
  const std::int8_t* dominant,
  double factor,
  double* thinned)
{
  if (!(factor >= 0.0 && factor <= 1.0))
  {
    throw std::invalid_argument("ThinAcrossFlow: the factor must be in [0, 1]");
  }
  static const int di[8] = { 1, 1, 0, -1, -1, -1, 0, 1 };
  static const int dj[8] = { 0, 1, 1, 1, 0, -1, -1, -1 };
  for (int j = 0; j < discharge.ny; ++j)
  {
    for (int i = 0; i < discharge.nx; ++i)
    {
      const std::size_t k = discharge.Index(i, j);
      const double q = discharge.data[k];
      const int d = dominant[k];
      thinned[k] = q;
      if (d < 0 || d > 7 || std::isnan(q))
      {
        continue;
      }
      for (const int across : { (d + 2) % 8, (d + 6) % 8 })
      {
        const int ii = i + di[across];
        const int jj = j + dj[across];
        if (ii >= 0 && jj >= 0 && ii < discharge.nx && jj < discharge.ny &&
          discharge.At(ii, jj) > q)
        {
          thinned[k] = factor * q;
        }
      }
    }
  }
}

//------------------------------------------------------------------------------
bool WaterFlowSimulation::StopsAfter(const WaterFlowIteration& it,
  long long iteration,
  double movedBefore,
  const WaterFlowStopRule& rule,
  WaterFlowStopReason& reason,
  double emptiedBefore) const
{
  if (it.moved <= 0.0 && this->Rain <= 0.0)
  {
    reason = WaterFlowStopReason::NoMovement;
    return true;
  }
  if (rule.countEmptiedCells ? WaterFlowAutoStop(it.emptied, emptiedBefore, rule.autoStopRatio)
                             : WaterFlowAutoStop(it.moved, movedBefore, rule.autoStopRatio))
  {
    reason = WaterFlowStopReason::AutoStop;
    return true;
  }
  if (iteration >= rule.balanceAfter &&
    WaterFlowBalanced(it.outflow, this->RainVolume(), rule.balanceTolerance))
  {
    reason = WaterFlowStopReason::Balanced;
    return true;
  }
  return false;
}

//------------------------------------------------------------------------------
WaterFlowStopReason WaterFlowSimulation::Run(const WaterFlowStopRule& rule)
{
  CheckWaterFlowStopRule(rule);
  this->CountEmptied = this->CountEmptied || rule.countEmptiedCells;
  WaterFlowStopReason reason = WaterFlowStopReason::MaximumIterations;
  WaterFlowAdvanceCPU(*this, rule.maximumIterations, true, rule, reason);
  return reason;
}

//------------------------------------------------------------------------------
double WaterFlowSimulation::StoredVolume() const
{
  const int stride = NX + 2;
  const bool window = this->Window[0] >= 0;
  const int r0 = window ? std::max(1, this->Window[2]) : 1;
  const int r1 = window ? std::min(NY + 1, this->Window[3]) : NY + 1;
  const int c0 = window ? std::max(1, this->Window[0]) : 1;
  const int c1 = window ? std::min(NX + 1, this->Window[1]) : NX + 1;
  double total = 0.0;
  for (int r = r0; r < r1; ++r)
  {
    double row = 0.0;
    for (int pi = c0; pi < c1; ++pi)
    {
      row += this->Water[static_cast<std::size_t>(r) * stride + pi];
    }
    total += row * this->Area[r];
  }
  return total;
}

//------------------------------------------------------------------------------
void WaterFlowSimulation::WindowRainTotals(double& volume, double& area) const
{
  const int stride = NX + 2;
  const bool window = this->Window[0] >= 0;
  const int r0 = window ? std::max(1, this->Window[2]) : 1;
  const int r1 = window ? std::min(NY + 1, this->Window[3]) : NY + 1;
  const int c0 = window ? std::max(1, this->Window[0]) : 1;
  const int c1 = window ? std::min(NX + 1, this->Window[1]) : NX + 1;
  volume = 0.0;
  area = 0.0;
  for (int r = r0; r < r1; ++r)
  {
    double rain = 0.0;
    double cells = 0.0;
    for (int pi = c0; pi < c1; ++pi)
    {
      const std::size_t c = static_cast<std::size_t>(r) * stride + pi;
      if (this->IsCell[c])
      {
        rain += this->RainField.empty() ? this->Rain : this->RainField[c];
        cells += 1.0;
      }
    }
    volume += rain * this->Area[r];
    area += cells * this->Area[r];
  }
}

//------------------------------------------------------------------------------
void WaterFlowSimulation::SetRainTotals(double volume, double area)
{
  this->RainVolumeTotal = volume;
  this->CellAreaTotal = area;
}

//------------------------------------------------------------------------------
void WaterFlowSimulation::GetWaterHeight(float* depth) const
{
  const int stride = NX + 2;
  for (int j = 0; j < NY; ++j)
  {
    for (int i = 0; i < NX; ++i)
    {
      const std::size_t c = static_cast<std::size_t>(j + 1) * stride + (i + 1);
      depth[static_cast<std::size_t>(j) * NX + i] = this->IsCell[c]
        ? static_cast<float>(this->Water[c])
        : std::numeric_limits<float>::quiet_NaN();
    }
  }
}

//------------------------------------------------------------------------------
void WaterFlowSimulation::GetDischarge(double* discharge) const
{
  const int stride = NX + 2;
  for (int j = 0; j < NY; ++j)
  {
    for (int i = 0; i < NX; ++i)
    {
      const std::size_t c = static_cast<std::size_t>(j + 1) * stride + (i + 1);
      discharge[static_cast<std::size_t>(j) * NX + i] = this->IsCell[c]
        ? this->DischargeDepth[c] * this->Area[j + 1]
        : std::numeric_limits<double>::quiet_NaN();
    }
  }
}

//------------------------------------------------------------------------------
void WaterFlowSimulation::TruncateHistory(long long iterations)
{
  if (iterations < 0 || iterations > this->IterationCount)
  {
    throw std::invalid_argument("water flow: cannot go back to iteration " +
      std::to_string(iterations) + " of " + std::to_string(this->IterationCount));
  }
  this->Moved.resize(static_cast<std::size_t>(iterations));
  this->Outflow.resize(static_cast<std::size_t>(iterations));
  this->Emptied.resize(static_cast<std::size_t>(iterations));
  this->IterationCount = iterations;
  this->MovedTotal = 0.0;
  this->OutflowTotal = 0.0;
  this->EmptiedTotal = 0.0;
  for (std::size_t k = 0; k < this->Moved.size(); ++k)
  {
    this->MovedTotal += this->Moved[k];
    this->OutflowTotal += this->Outflow[k];
    this->EmptiedTotal += this->Emptied[k];
  }
}

//------------------------------------------------------------------------------
bool WaterFlowSimulation::FindStop(const WaterFlowStopRule& rule,
  long long& iteration,
  WaterFlowStopReason& reason) const
{
  double before = 0.0;
  double emptiedBefore = 0.0;
  for (std::size_t k = 0; k < this->Moved.size(); ++k)
  {
    if (static_cast<long long>(k) >= rule.maximumIterations)
    {
      break;
    }
    WaterFlowIteration it;
    it.moved = this->Moved[k];
    it.outflow = this->Outflow[k];
    it.emptied = this->Emptied[k];
    if (this->StopsAfter(it, static_cast<long long>(k) + 1, before, rule, reason, emptiedBefore))
    {
      iteration = static_cast<long long>(k) + 1;
      return true;
    }
    before += it.moved;
    emptiedBefore += it.emptied;
  }
  if (static_cast<long long>(this->Moved.size()) >= rule.maximumIterations)
  {
    iteration = rule.maximumIterations;
    reason = WaterFlowStopReason::MaximumIterations;
    return true;
  }
  return false;
}

} // namespace hydrology
} // namespace terroir

#include "KMeans.h"

#include "ClusterPalette.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>
#include <type_traits>
#include <utility>

namespace terroir
{
namespace clustering
{

namespace
{
/// Cells per vectorised assignment chunk: the float accumulators of one chunk stay in L1.
constexpr std::size_t kChunk = 64;

/// Features summed together by the block sums: as many independent double chains per cell.
constexpr int kSumGroup = 8;

/// Runs body over [begin, end) through parallelFor (or at once when it is empty).
void RunParallel(const KMeansParallelFor& parallelFor,
  std::size_t begin,
  std::size_t end,
  const std::function<void(std::size_t, std::size_t)>& body)
{
  if (begin >= end)
  {
    return;
  }
  if (parallelFor)
  {
    parallelFor(begin, end, body);
  }
  else
  {
    body(begin, end);
  }
}

std::size_t BlockBegin(std::size_t block)
{
  return block * KMeansBlockCells;
}

std::size_t BlockEnd(std::size_t block, std::size_t cells)
{
  return std::min(cells, (block + 1) * KMeansBlockCells);
}

std::size_t BlockCount(std::size_t cells)
{
  return (cells + KMeansBlockCells - 1) / KMeansBlockCells;
}

/**
 * acc[c] = d2 of cells c0 + c (c < n) to centre m: acc = acc + d * d, d = x - m, f = 0..F-1 in
 * order, in float. The f loop is outside, the cell loop inside and vectorised: each lane is one
 * cell's own sum in f order, so the bits are those of the scalar loop (no FMA: the library is
 * built with -ffp-contract=off).
 */
template<std::size_t N>
inline void ChunkDistances(const float* x,
  std::size_t stride,
  int features,
  const float* m,
  float* acc)
{
  for (std::size_t c = 0; c < N; ++c)
  {
    acc[c] = 0.0f;
  }
  for (int f = 0; f < features; ++f)
  {
    const float* xf = x + static_cast<std::size_t>(f) * stride;
    const float mf = m[f];
    for (std::size_t c = 0; c < N; ++c)
    {
      const float d = xf[c] - mf;
      acc[c] = acc[c] + d * d;
    }
  }
}

/// The same for a partial chunk of n < kChunk cells (same operations per cell).
inline void TailDistances(const float* x,
  std::size_t stride,
  int features,
  const float* m,
  std::size_t n,
  float* acc)
{
  for (std::size_t c = 0; c < n; ++c)
  {
    acc[c] = 0.0f;
  }
  for (int f = 0; f < features; ++f)
  {
    const float* xf = x + static_cast<std::size_t>(f) * stride;
    const float mf = m[f];
    for (std::size_t c = 0; c < n; ++c)
    {
      const float d = xf[c] - mf;
      acc[c] = acc[c] + d * d;
    }
  }
}

/// Nearest of k centres for a chunk of n cells starting at c0 (ties to the lowest k).
template<std::size_t N>
inline std::size_t AssignChunk(const KMeansFeatures& features,
  const float* centres,
  int k,
  std::size_t c0,
  std::size_t n,
  std::int32_t* labels,
  float* distance)
{
  alignas(64) float acc[N];
  alignas(64) float best[N];
  alignas(64) std::int32_t label[N];
  const float* x = features.data + c0;
  const int nf = features.features;
  if (n < N)
  {
    // A partial chunk: the lanes past n are never read back, but are kept defined.
    for (std::size_t c = n; c < N; ++c)
    {
      acc[c] = 0.0f;
      best[c] = 0.0f;
    }
  }
  if (n == N)
  {
    ChunkDistances<N>(x, features.cells, nf, centres, best);
  }
  else
  {
    TailDistances(x, features.cells, nf, centres, n, best);
  }
  for (std::size_t c = 0; c < N; ++c)
  {
    label[c] = 0;
  }
  for (int kk = 1; kk < k; ++kk)
  {
    const float* m = centres + static_cast<std::size_t>(kk) * nf;
    if (n == N)
    {
      ChunkDistances<N>(x, features.cells, nf, m, acc);
    }
    else
    {
      TailDistances(x, features.cells, nf, m, n, acc);
    }
    for (std::size_t c = 0; c < N; ++c)
    {
      const bool closer = acc[c] < best[c];
      best[c] = closer ? acc[c] : best[c];
      label[c] = closer ? kk : label[c];
    }
  }
  std::size_t changed = 0;
  for (std::size_t c = 0; c < n; ++c)
  {
    changed += labels[c0 + c] != label[c] ? 1 : 0;
    labels[c0 + c] = label[c];
    distance[c0 + c] = best[c];
  }
  return changed;
}

#if defined(__GNUC__) && !defined(TERROIR_KMEANS_SCALAR)
#define TERROIR_KMEANS_VECTOR 1
// The 32-byte vectors never cross a call boundary (everything below is inlined), so the ABI
// note GCC gives for them on the baseline target does not apply.
#pragma GCC diagnostic ignored "-Wpsabi"
/// Eight floats (GCC/Clang vector extension): one AVX register, two SSE registers. Each lane
/// does the scalar operations of its own cell, so the bits do not depend on the width.
typedef float Vec8 __attribute__((vector_size(32)));
typedef std::int32_t Int8 __attribute__((vector_size(32)));
/// The vector helpers are inlined into AssignKernelAVX2, so they get its instructions.
#define TERROIR_KMEANS_INLINE inline __attribute__((always_inline))

TERROIR_KMEANS_INLINE Vec8 Load8(const float* p)
{
  Vec8 v;
  std::memcpy(&v, p, sizeof(v));
  return v;
}

/// Cells per tile of the vector kernel: kTileVectors vectors of 8 cells.
constexpr std::size_t kTileVectors = 4;
constexpr std::size_t kTile = 8 * kTileVectors;
/// How far ahead (cells) the assignment prefetches the feature streams.
constexpr std::size_t kPrefetchCells = 4 * kTile;

/**
 * Nearest centre for the kTile cells from c: two clusters per pass over the features, so each
 * loaded feature vector serves two distance sums; 8 float accumulators stay in registers.
 */
TERROIR_KMEANS_INLINE std::size_t AssignTile(const KMeansFeatures& features,
  const float* centres,
  int k,
  std::size_t c,
  std::int32_t* labels,
  float* distance)
{
  const int nf = features.features;
  const std::size_t stride = features.cells;
  const float* x = features.data + c;
  Vec8 best[kTileVectors];
  Int8 label[kTileVectors];
  const Vec8 zero = {};
  for (std::size_t v = 0; v < kTileVectors; ++v)
  {
    best[v] = zero;
    label[v] = Int8{};
  }
  for (int kk = 0; kk < k; kk += 2)
  {
    const bool pair = kk + 1 < k;
    const float* m0 = centres + static_cast<std::size_t>(kk) * nf;
    const float* m1 = pair ? m0 + nf : m0;
    Vec8 a0[kTileVectors];
    Vec8 a1[kTileVectors];
    for (std::size_t v = 0; v < kTileVectors; ++v)
    {
      a0[v] = zero;
      a1[v] = zero;
    }
    for (int f = 0; f < nf; ++f)
    {
      const float* xf = x + static_cast<std::size_t>(f) * stride;
      const Vec8 b0 = zero + m0[f];
      const Vec8 b1 = zero + m1[f];
      for (std::size_t v = 0; v < kTileVectors; ++v)
      {
        const Vec8 xv = Load8(xf + 8 * v);
        const Vec8 d0 = xv - b0;
        const Vec8 d1 = xv - b1;
        a0[v] = a0[v] + d0 * d0;
        a1[v] = a1[v] + d1 * d1;
      }
    }
    for (std::size_t v = 0; v < kTileVectors; ++v)
    {
      if (kk == 0)
      {
        best[v] = a0[v];
      }
      else
      {
        const Int8 closer = a0[v] < best[v];
        best[v] = closer ? a0[v] : best[v];
        label[v] = closer ? Int8{} + kk : label[v];
      }
      if (pair)
      {
        const Int8 closer = a1[v] < best[v];
        best[v] = closer ? a1[v] : best[v];
        label[v] = closer ? Int8{} + (kk + 1) : label[v];
      }
    }
  }
  alignas(32) std::int32_t l[kTile];
  alignas(32) float d[kTile];
  std::memcpy(l, label, sizeof(l));
  std::memcpy(d, best, sizeof(d));
  std::size_t changed = 0;
  for (std::size_t i = 0; i < kTile; ++i)
  {
    changed += labels[c + i] != l[i] ? 1 : 0;
    labels[c + i] = l[i];
    distance[c + i] = d[i];
  }
  return changed;
}
#endif

/// KMeansAssignRange's loop in chunks of kChunk cells (auto-vectorised: one lane per cell).
std::size_t AssignChunks(const KMeansFeatures& features,
  const float* centres,
  int k,
  std::size_t c,
  std::size_t end,
  std::int32_t* labels,
  float* distance)
{
  std::size_t changed = 0;
  for (; c + kChunk <= end; c += kChunk)
  {
    changed += AssignChunk<kChunk>(features, centres, k, c, kChunk, labels, distance);
  }
  if (c < end)
  {
    changed += AssignChunk<kChunk>(features, centres, k, c, end - c, labels, distance);
  }
  return changed;
}

#if defined(TERROIR_KMEANS_VECTOR) && defined(__x86_64__)
#define TERROIR_KMEANS_AVX2 1
/**
 * KMeansAssignRange's loop with AVX2 (chosen at run time): kTile-cell tiles (AssignTile), the
 * rest in chunks. Without contraction (-ffp-contract=off) every lane does the scalar
 * operations, so the bits are those of AssignChunks. On SSE2 alone the tiles' 16 accumulators
 * would not fit in the registers: the baseline uses AssignChunks.
 */
__attribute__((target("avx2"))) std::size_t AssignKernelAVX2(const KMeansFeatures& features,
  const float* centres,
  int k,
  std::size_t begin,
  std::size_t end,
  std::int32_t* labels,
  float* distance)
{
  std::size_t changed = 0;
  std::size_t c = begin;
  for (; c + kTile <= end; c += kTile)
  {
    // 37 feature streams are more than the hardware prefetchers follow well: ask for the lines
    // four tiles ahead (measured: about 20 % off the assignment of 1024^2 x 37 cells).
    if (c + kPrefetchCells + kTile <= end)
    {
      for (int f = 0; f < features.features; ++f)
      {
        const float* p =
          features.data + static_cast<std::size_t>(f) * features.cells + c + kPrefetchCells;
        __builtin_prefetch(p);
        __builtin_prefetch(p + 16);
      }
    }
    changed += AssignTile(features, centres, k, c, labels, distance);
  }
  return changed + AssignChunks(features, centres, k, c, end, labels, distance);
}
#endif

std::size_t AssignKernel(const KMeansFeatures& features,
  const float* centres,
  int k,
  std::size_t begin,
  std::size_t end,
  std::int32_t* labels,
  float* distance)
{
#ifdef TERROIR_KMEANS_AVX2
  static const bool avx2 = __builtin_cpu_supports("avx2");
  if (avx2)
  {
    return AssignKernelAVX2(features, centres, k, begin, end, labels, distance);
  }
#endif
  return AssignChunks(features, centres, k, begin, end, labels, distance);
}

/// d2 of cells [begin, end) to one centre, as in the assignment.
void DistancesToCentre(const KMeansFeatures& features,
  const float* centre,
  std::size_t begin,
  std::size_t end,
  float* out)
{
  std::size_t c = begin;
  for (; c + kChunk <= end; c += kChunk)
  {
    ChunkDistances<kChunk>(features.data + c, features.cells, features.features, centre, out + c);
  }
  if (c < end)
  {
    TailDistances(features.data + c, features.cells, features.features, centre, end - c, out + c);
  }
}

/**
 * sums[labels[c] * F + f0 + j] += x_{f0 + j}(c), j < G, over cells c in [begin, end) in cell
 * order. G features at once give G independent double chains per cell; a run of equal labels
 * keeps its G sums in registers (loaded before, stored after: the same additions in the same
 * order as adding into memory cell by cell).
 */
template<int G>
void GroupSums(const KMeansFeatures& features,
  const std::int32_t* labels,
  int f0,
  std::size_t begin,
  std::size_t end,
  double* sums)
{
  const std::size_t stride = features.cells;
  const float* x = features.data + static_cast<std::size_t>(f0) * stride;
  const std::size_t nf = static_cast<std::size_t>(features.features);
  std::size_t c = begin;
  while (c < end)
  {
    const std::int32_t l = labels[c];
    double* s = sums + static_cast<std::size_t>(l) * nf + f0;
    double a[G];
    for (int j = 0; j < G; ++j)
    {
      a[j] = s[j];
    }
    do
    {
      for (int j = 0; j < G; ++j)
      {
        a[j] += static_cast<double>(x[j * stride + c]);
      }
      ++c;
    } while (c < end && labels[c] == l);
    for (int j = 0; j < G; ++j)
    {
      s[j] = a[j];
    }
  }
}

/// The general (slow) path of GroupSums for labels outside [0, k): those cells are skipped.
void CheckedSums(const KMeansFeatures& features,
  const std::int32_t* labels,
  int k,
  std::size_t begin,
  std::size_t end,
  double* sums)
{
  const std::size_t nf = static_cast<std::size_t>(features.features);
  for (std::size_t c = begin; c < end; ++c)
  {
    const std::int32_t l = labels[c];
    if (l < 0 || l >= k)
    {
      continue;
    }
    double* s = sums + static_cast<std::size_t>(l) * nf;
    for (std::size_t f = 0; f < nf; ++f)
    {
      s[f] += static_cast<double>(features.data[f * features.cells + c]);
    }
  }
}

/// Calls group(std::integral_constant<int, G>{}, f0) for the features in groups of kSumGroup,
/// the last group smaller: G is a constant in each call, so the G chains unroll.
template<typename Group>
void ForFeatureGroups(int features, Group&& group)
{
  int f0 = 0;
  for (; f0 + kSumGroup <= features; f0 += kSumGroup)
  {
    group(std::integral_constant<int, kSumGroup>{}, f0);
  }
  switch (features - f0)
  {
    case 7:
      group(std::integral_constant<int, 7>{}, f0);
      break;
    case 6:
      group(std::integral_constant<int, 6>{}, f0);
      break;
    case 5:
      group(std::integral_constant<int, 5>{}, f0);
      break;
    case 4:
      group(std::integral_constant<int, 4>{}, f0);
      break;
    case 3:
      group(std::integral_constant<int, 3>{}, f0);
      break;
    case 2:
      group(std::integral_constant<int, 2>{}, f0);
      break;
    case 1:
      group(std::integral_constant<int, 1>{}, f0);
      break;
    default:
      break;
  }
}

/**
 * Per-feature sums over the cells of one block, in cell order, in double: out[f] = sum of x_f,
 * or, with `mean`, of (x_f - mean[f])^2 (cells outer, G features inner: G chains side by side).
 */
template<int G, bool Squares>
void GroupFeatureSums(const KMeansFeatures& features,
  int f0,
  std::size_t begin,
  std::size_t end,
  const double* mean,
  double* out)
{
  const std::size_t stride = features.cells;
  const float* x = features.data + static_cast<std::size_t>(f0) * stride;
  double m[G];
  double a[G];
  for (int j = 0; j < G; ++j)
  {
    m[j] = Squares ? mean[f0 + j] : 0.0;
    a[j] = 0.0;
  }
  for (std::size_t c = begin; c < end; ++c)
  {
    for (int j = 0; j < G; ++j)
    {
      const double v = static_cast<double>(x[j * stride + c]);
      if (Squares)
      {
        const double d = v - m[j];
        a[j] += d * d;
      }
      else
      {
        a[j] += v;
      }
    }
  }
  for (int j = 0; j < G; ++j)
  {
    out[f0 + j] = a[j];
  }
}

/// GroupFeatureSums of every feature over block `block`.
template<bool Squares>
void BlockFeatureSums(const KMeansFeatures& features,
  std::size_t block,
  const double* mean,
  double* out)
{
  const std::size_t b0 = BlockBegin(block);
  const std::size_t b1 = BlockEnd(block, features.cells);
  ForFeatureGroups(features.features,
    [&](auto g, int f0)
    { GroupFeatureSums<decltype(g)::value, Squares>(features, f0, b0, b1, mean, out); });
}

/// Float ulp of |v| (the spacing of floats at |v|; the smallest subnormal at 0).
double FloatUlp(float v)
{
  const float a = std::fabs(v);
  const int e = a > 0.0f ? std::max(std::ilogb(a), -126) : -126;
  return std::ldexp(1.0, e - 23);
}

/// One draw in [0, 1): the top 53 bits of the generator's output.
double Uniform(std::mt19937_64& rng)
{
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

std::string ArrayLabel(const KMeansInputArray& array, std::size_t index)
{
  return array.name.empty() ? "input array " + std::to_string(index)
                            : "input array '" + array.name + "'";
}

/// KMeansPrepareFeatures' checks: every array has values, at least one component and a finite
/// weight >= 0, and one weight is > 0 (std::invalid_argument otherwise).
void CheckInputArrays(const std::vector<KMeansInputArray>& arrays)
{
  bool anyWeight = false;
  for (std::size_t a = 0; a < arrays.size(); ++a)
  {
    const KMeansInputArray& array = arrays[a];
    if (!array.values)
    {
      throw std::invalid_argument("k-means: " + ArrayLabel(array, a) + " has no values (null)");
    }
    if (array.components < 1)
    {
      throw std::invalid_argument("k-means: " + ArrayLabel(array, a) + " has " +
        std::to_string(array.components) + " components (at least 1 needed)");
    }
    if (!std::isfinite(array.weight) || array.weight < 0.0)
    {
      throw std::invalid_argument("k-means: " + ArrayLabel(array, a) + " has weight " +
        std::to_string(array.weight) + " (a finite number >= 0 is needed)");
    }
    anyWeight = anyWeight || array.weight > 0.0;
  }
  if (!anyWeight)
  {
    throw std::invalid_argument(arrays.empty()
        ? "k-means: no input array"
        : "k-means: every input array has weight 0 (nothing to cluster)");
  }
}

/// p.mean of input array `a` (its index, for messages): per block, per component, in cell
/// order; the blocks added in block order. Throws on a non-finite value.
void ArrayMeans(const KMeansInputArray& array,
  std::size_t a,
  std::size_t cells,
  double totalCells,
  const KMeansParallelFor& parallelFor,
  KMeansReduction* reduction,
  KMeansPreparedArray& p)
{
  const std::size_t blocks = BlockCount(cells);
  const std::size_t nc = static_cast<std::size_t>(array.components);
  const float* values = array.values;
  std::vector<double> partial(blocks * nc, 0.0);
  RunParallel(parallelFor,
    0,
    blocks,
    [&](std::size_t first, std::size_t last)
    {
      std::vector<double> acc(nc);
      for (std::size_t b = first; b < last; ++b)
      {
        std::fill(acc.begin(), acc.end(), 0.0);
        for (std::size_t c = BlockBegin(b); c < BlockEnd(b, cells); ++c)
        {
          for (std::size_t j = 0; j < nc; ++j)
          {
            acc[j] += static_cast<double>(values[c * nc + j]);
          }
        }
        std::copy(acc.begin(), acc.end(), partial.begin() + b * nc);
      }
    });
  for (std::size_t b = 0; b < blocks; ++b)
  {
    for (std::size_t j = 0; j < nc; ++j)
    {
      p.mean[j] += partial[b * nc + j];
    }
  }
  if (reduction)
  {
    reduction->Sum(p.mean.data(), nc);
  }
  for (std::size_t j = 0; j < nc; ++j)
  {
    // Finite floats cannot overflow a double sum: a non-finite sum means a non-finite value.
    if (!std::isfinite(p.mean[j]))
    {
      throw std::invalid_argument("k-means: " + ArrayLabel(array, a) + " component " +
        std::to_string(j) + " has a non-finite value (NaN or infinity)");
    }
    p.mean[j] = totalCells > 0 ? p.mean[j] / totalCells : 0.0;
  }
}

/// p.stddev (population standard deviations: a second pass, in ArrayMeans' order) and
/// p.collapsed, the collapse test: for every component j > 0 the interval of constants c_j
/// allowed by every cell, [max(d - tol), min(d + tol)], is not empty.
void ArrayDeviations(const KMeansInputArray& array,
  std::size_t cells,
  double totalCells,
  bool allowCollapse,
  const KMeansParallelFor& parallelFor,
  KMeansReduction* reduction,
  KMeansPreparedArray& p)
{
  const std::size_t blocks = BlockCount(cells);
  const std::size_t nc = static_cast<std::size_t>(array.components);
  const float* values = array.values;
  std::vector<double> partial(blocks * nc, 0.0);
  const bool tryCollapse = allowCollapse && nc > 1;
  std::vector<double> lo(tryCollapse ? blocks * nc : 0, -std::numeric_limits<double>::infinity());
  std::vector<double> hi(tryCollapse ? blocks * nc : 0, std::numeric_limits<double>::infinity());
  RunParallel(parallelFor,
    0,
    blocks,
    [&](std::size_t first, std::size_t last)
    {
      std::vector<double> acc(nc);
      for (std::size_t b = first; b < last; ++b)
      {
        std::fill(acc.begin(), acc.end(), 0.0);
        for (std::size_t c = BlockBegin(b); c < BlockEnd(b, cells); ++c)
        {
          for (std::size_t j = 0; j < nc; ++j)
          {
            const double d = static_cast<double>(values[c * nc + j]) - p.mean[j];
            acc[j] += d * d;
          }
        }
        std::copy(acc.begin(), acc.end(), partial.begin() + b * nc);
        if (tryCollapse)
        {
          double* l = lo.data() + b * nc;
          double* h = hi.data() + b * nc;
          for (std::size_t c = BlockBegin(b); c < BlockEnd(b, cells); ++c)
          {
            const float x0 = values[c * nc];
            for (std::size_t j = 1; j < nc; ++j)
            {
              const float xj = values[c * nc + j];
              const double d = static_cast<double>(xj) - static_cast<double>(x0);
              const double tol = 4.0 * FloatUlp(std::max(std::fabs(xj), std::fabs(x0)));
              l[j] = std::max(l[j], d - tol);
              h[j] = std::min(h[j], d + tol);
            }
          }
        }
      }
    });
  std::vector<double> squares(nc, 0.0);
  for (std::size_t b = 0; b < blocks; ++b)
  {
    for (std::size_t j = 0; j < nc; ++j)
    {
      squares[j] += partial[b * nc + j];
    }
  }
  if (reduction)
  {
    reduction->Sum(squares.data(), nc);
  }
  for (std::size_t j = 0; j < nc; ++j)
  {
    p.stddev[j] = totalCells > 0 ? std::sqrt(squares[j] / totalCells) : 0.0;
  }
  p.collapsed = false;
  if (tryCollapse)
  {
    // Each component's interval over this process's blocks, then over every process.
    std::vector<double> l(nc, -std::numeric_limits<double>::infinity());
    std::vector<double> h(nc, std::numeric_limits<double>::infinity());
    for (std::size_t j = 1; j < nc; ++j)
    {
      for (std::size_t b = 0; b < blocks; ++b)
      {
        l[j] = std::max(l[j], lo[b * nc + j]);
        h[j] = std::min(h[j], hi[b * nc + j]);
      }
    }
    if (reduction)
    {
      reduction->Max(l.data(), nc);
      reduction->Min(h.data(), nc);
    }
    p.collapsed = true;
    for (std::size_t j = 1; j < nc && p.collapsed; ++j)
    {
      p.collapsed = l[j] <= h[j];
    }
  }
}

/// The p.features rows of `array` in the feature-major matrix, from `dst` on: (x - mean) *
/// factor, with the mean and 1 / standard deviation when standardising and the square root of
/// the weight always; one pass over the array for all its features.
void WriteArrayFeatures(const KMeansInputArray& array,
  const KMeansPreparedArray& p,
  std::size_t cells,
  bool standardize,
  const KMeansParallelFor& parallelFor,
  float* dst)
{
  const std::size_t nc = static_cast<std::size_t>(array.components);
  // A collapsed array is component 0 counted `components` times.
  const double root =
    std::sqrt(p.collapsed ? array.weight * static_cast<double>(nc) : array.weight);
  std::vector<double> mean(static_cast<std::size_t>(p.features), 0.0);
  std::vector<double> factor(static_cast<std::size_t>(p.features), root);
  for (std::size_t j = 0; j < mean.size(); ++j)
  {
    if (standardize)
    {
      mean[j] = p.mean[j];
      factor[j] = p.stddev[j] > 0.0 ? root / p.stddev[j] : 0.0;
    }
  }
  const float* values = array.values;
  RunParallel(parallelFor,
    0,
    BlockCount(cells),
    [&](std::size_t first, std::size_t last)
    {
      const std::size_t c1 = BlockEnd(last - 1, cells);
      for (std::size_t c = BlockBegin(first); c < c1; ++c)
      {
        for (std::size_t j = 0; j < mean.size(); ++j)
        {
          const double x = static_cast<double>(values[c * nc + j]);
          dst[j * cells + c] = static_cast<float>((x - mean[j]) * factor[j]);
        }
      }
    });
}
} // namespace

//------------------------------------------------------------------------------
std::vector<KMeansPreparedArray> KMeansPrepareFeatures(const std::vector<KMeansInputArray>& arrays,
  std::size_t cells,
  bool standardize,
  bool allowCollapse,
  std::vector<float>& out,
  const KMeansParallelFor& parallelFor,
  KMeansReduction* reduction)
{
  CheckInputArrays(arrays);
  double totalCells = static_cast<double>(cells);
  if (reduction)
  {
    std::int64_t n = static_cast<std::int64_t>(cells);
    reduction->Sum(&n, 1);
    totalCells = static_cast<double>(n);
  }
  std::vector<KMeansPreparedArray> prepared(arrays.size());
  int features = 0;
  for (std::size_t a = 0; a < arrays.size(); ++a)
  {
    const KMeansInputArray& array = arrays[a];
    KMeansPreparedArray& p = prepared[a];
    const std::size_t nc = static_cast<std::size_t>(array.components);
    p.name = array.name;
    p.components = array.components;
    p.firstFeature = features;
    p.mean.assign(nc, 0.0);
    p.stddev.assign(nc, 0.0);
    if (!(array.weight > 0.0))
    {
      // Dropped: its values are not read.
      p.features = 0;
      continue;
    }
    // Means (per block, per component, in cell order; the blocks added in block order), then
    // the standard deviations and the collapse test.
    ArrayMeans(array, a, cells, totalCells, parallelFor, reduction, p);
    ArrayDeviations(array, cells, totalCells, allowCollapse, parallelFor, reduction, p);
    p.features = p.collapsed ? 1 : array.components;
    features += p.features;
  }

  // The feature-major matrix: one pass per array, all its features at once.
  out.assign(static_cast<std::size_t>(features) * cells, 0.0f);
  for (std::size_t a = 0; a < arrays.size(); ++a)
  {
    const KMeansPreparedArray& p = prepared[a];
    if (p.features == 0)
    {
      continue;
    }
    WriteArrayFeatures(arrays[a],
      p,
      cells,
      standardize,
      parallelFor,
      out.data() + static_cast<std::size_t>(p.firstFeature) * cells);
  }
  return prepared;
}

//------------------------------------------------------------------------------
void KMeansApplyPreparation(const std::vector<KMeansInputArray>& arrays,
  const std::vector<KMeansPreparedArray>& prepared,
  std::size_t cells,
  bool standardize,
  std::vector<float>& out)
{
  if (arrays.size() != prepared.size())
  {
    throw std::invalid_argument("k-means: " + std::to_string(arrays.size()) +
      " arrays for the preparation of " + std::to_string(prepared.size()));
  }
  int features = 0;
  for (const KMeansPreparedArray& p : prepared)
  {
    features += p.features;
  }
  out.assign(static_cast<std::size_t>(features) * cells, 0.0f);
  for (std::size_t a = 0; a < arrays.size(); ++a)
  {
    const KMeansPreparedArray& p = prepared[a];
    if (p.features == 0 || cells == 0)
    {
      continue;
    }
    if (arrays[a].components != p.components || !arrays[a].values)
    {
      throw std::invalid_argument(
        "k-means: array '" + arrays[a].name + "' does not match its preparation");
    }
    WriteArrayFeatures(arrays[a],
      p,
      cells,
      standardize,
      KMeansParallelFor(),
      out.data() + static_cast<std::size_t>(p.firstFeature) * cells);
  }
}

//------------------------------------------------------------------------------
std::vector<std::size_t> KMeansDiagonalSeedCells(int nx, int ny, const std::uint8_t* valid, int k)
{
  if (k < 1)
  {
    throw std::invalid_argument(
      "k-means: the number of clusters must be at least 1 (got " + std::to_string(k) + ")");
  }
  if (nx < 1 || ny < 1)
  {
    throw std::invalid_argument("k-means: the grid is empty (" + std::to_string(nx) + " x " +
      std::to_string(ny) + "), no cell to seed " + std::to_string(k) + " clusters");
  }
  std::vector<std::size_t> candidates;
  for (std::size_t cell : KMeansDiagonalCells(nx, ny))
  {
    if (!valid || valid[cell])
    {
      candidates.push_back(cell);
    }
  }
  const std::uint64_t NX = static_cast<std::uint64_t>(nx);
  const std::uint64_t NY = static_cast<std::uint64_t>(ny);
  const std::size_t K = static_cast<std::size_t>(k);
  if (candidates.size() < K)
  {
    // Too few valid diagonal cells: the same rule over every valid cell in row order.
    candidates.clear();
    const std::size_t n = static_cast<std::size_t>(NX * NY);
    for (std::size_t cell = 0; cell < n; ++cell)
    {
      if (!valid || valid[cell])
      {
        candidates.push_back(cell);
      }
    }
    if (candidates.size() < K)
    {
      throw std::invalid_argument("k-means: " + std::to_string(k) + " clusters but only " +
        std::to_string(candidates.size()) + " valid cells");
    }
  }
  std::vector<std::size_t> seeds;
  for (std::size_t position : KMeansDiagonalSeedPositions(candidates.size(), k))
  {
    seeds.push_back(candidates[position]);
  }
  return seeds;
}

//------------------------------------------------------------------------------
std::vector<std::size_t> KMeansDiagonalCells(int nx, int ny)
{
  const std::uint64_t NX = static_cast<std::uint64_t>(std::max(nx, 1));
  const std::uint64_t NY = static_cast<std::uint64_t>(std::max(ny, 1));
  const std::uint64_t L = std::max(NX, NY);
  // round(t a / b) with halves up, in integers: floor((2 t a + b) / (2 b)).
  auto along = [L](std::uint64_t t, std::uint64_t n) -> std::uint64_t
  {
    if (L == 1)
    {
      return 0;
    }
    const std::uint64_t b = L - 1;
    return (2 * t * (n - 1) + b) / (2 * b);
  };
  std::vector<std::size_t> cells;
  cells.reserve(static_cast<std::size_t>(L));
  for (std::uint64_t t = 0; t < L; ++t)
  {
    cells.push_back(static_cast<std::size_t>(along(t, NY) * NX + along(t, NX)));
  }
  return cells;
}

//------------------------------------------------------------------------------
std::vector<std::size_t> KMeansDiagonalSeedPositions(std::size_t m, int k)
{
  const std::size_t K = static_cast<std::size_t>(std::max(k, 1));
  std::vector<std::size_t> positions(K);
  for (std::size_t i = 0; i < K; ++i)
  {
    positions[i] = (2 * i + 1) * m / (2 * K);
  }
  return positions;
}

//------------------------------------------------------------------------------
std::vector<std::size_t> KMeansPlusPlusSeeds(const KMeansFeatures& features,
  int k,
  std::uint64_t seed,
  const KMeansParallelFor& parallelFor)
{
  if (k < 1 || static_cast<std::size_t>(k) > features.cells)
  {
    throw std::invalid_argument("k-means++: " + std::to_string(k) +
      " clusters need between 1 and the number of cells (" + std::to_string(features.cells) + ")");
  }
  const std::size_t n = features.cells;
  std::mt19937_64 rng(seed);
  std::vector<std::size_t> chosen;
  chosen.reserve(static_cast<std::size_t>(k));
  std::vector<std::uint8_t> taken(n, 0);
  std::size_t first = static_cast<std::size_t>(Uniform(rng) * static_cast<double>(n));
  first = std::min(first, n - 1);
  chosen.push_back(first);
  taken[first] = 1;

  std::vector<float> d2(n);
  std::vector<float> centre(static_cast<std::size_t>(features.features));
  auto setCentre = [&](std::size_t cell)
  {
    for (int f = 0; f < features.features; ++f)
    {
      centre[f] = features.At(f, cell);
    }
  };
  setCentre(first);
  const std::size_t blocks = features.Blocks();
  RunParallel(parallelFor,
    0,
    blocks,
    [&](std::size_t b0, std::size_t b1) {
      DistancesToCentre(features, centre.data(), BlockBegin(b0), BlockEnd(b1 - 1, n), d2.data());
    });

  std::vector<float> scratch(n);
  for (int i = 1; i < k; ++i)
  {
    const double u = Uniform(rng);
    double total = 0.0;
    for (std::size_t c = 0; c < n; ++c)
    {
      total += static_cast<double>(d2[c]);
    }
    std::size_t next = n;
    if (total > 0.0)
    {
      const double threshold = u * total;
      double running = 0.0;
      std::size_t lastPositive = n;
      for (std::size_t c = 0; c < n; ++c)
      {
        running += static_cast<double>(d2[c]);
        if (d2[c] > 0.0f)
        {
          lastPositive = c;
        }
        if (running > threshold)
        {
          next = c;
          break;
        }
      }
      if (next == n)
      {
        // u * total rounded up to total: the last cell that carries weight.
        next = lastPositive;
      }
    }
    else
    {
      for (std::size_t c = 0; c < n; ++c)
      {
        if (!taken[c])
        {
          next = c;
          break;
        }
      }
    }
    chosen.push_back(next);
    taken[next] = 1;
    if (i + 1 < k)
    {
      setCentre(next);
      RunParallel(parallelFor,
        0,
        blocks,
        [&](std::size_t b0, std::size_t b1)
        {
          const std::size_t c0 = BlockBegin(b0);
          const std::size_t c1 = BlockEnd(b1 - 1, n);
          DistancesToCentre(features, centre.data(), c0, c1, scratch.data());
          for (std::size_t c = c0; c < c1; ++c)
          {
            d2[c] = std::min(d2[c], scratch[c]);
          }
        });
    }
  }
  return chosen;
}

//------------------------------------------------------------------------------
std::vector<float> KMeansCentresFromCells(const KMeansFeatures& features,
  const std::vector<std::size_t>& cells)
{
  const std::size_t nf = static_cast<std::size_t>(features.features);
  std::vector<float> centres(cells.size() * nf);
  for (std::size_t i = 0; i < cells.size(); ++i)
  {
    if (cells[i] >= features.cells)
    {
      throw std::invalid_argument("k-means: seed cell " + std::to_string(cells[i]) +
        " is outside the " + std::to_string(features.cells) + " cells");
    }
    for (std::size_t f = 0; f < nf; ++f)
    {
      centres[i * nf + f] = features.At(static_cast<int>(f), cells[i]);
    }
  }
  return centres;
}

//------------------------------------------------------------------------------
std::size_t KMeansAssignRange(const KMeansFeatures& features,
  const float* centres,
  int k,
  std::size_t begin,
  std::size_t end,
  std::int32_t* labels,
  float* distance)
{
  if (begin >= end || k < 1)
  {
    return 0;
  }
  return AssignKernel(features, centres, k, begin, end, labels, distance);
}

//------------------------------------------------------------------------------
void KMeansBlockSums(const KMeansFeatures& features,
  const std::int32_t* labels,
  const float* distance,
  int k,
  std::size_t block,
  double* sums,
  std::int64_t* counts,
  double* inertia)
{
  const std::size_t nf = static_cast<std::size_t>(features.features);
  const std::size_t K = static_cast<std::size_t>(std::max(k, 0));
  std::fill(sums, sums + K * nf, 0.0);
  std::fill(counts, counts + K, std::int64_t(0));
  *inertia = 0.0;
  const std::size_t b0 = BlockBegin(block);
  const std::size_t b1 = BlockEnd(block, features.cells);
  double in = 0.0;
  bool inRange = true;
  for (std::size_t c = b0; c < b1; ++c)
  {
    const std::int32_t l = labels[c];
    if (l < 0 || l >= k)
    {
      inRange = false;
      continue;
    }
    ++counts[l];
    in += static_cast<double>(distance[c]);
  }
  *inertia = in;
  if (!inRange)
  {
    CheckedSums(features, labels, k, b0, b1, sums);
    return;
  }
  ForFeatureGroups(features.features,
    [&](auto g, int f0) { GroupSums<decltype(g)::value>(features, labels, f0, b0, b1, sums); });
}

//------------------------------------------------------------------------------
KMeansCPUEngine::KMeansCPUEngine(const KMeansFeatures& features, KMeansParallelFor parallelFor)
  : Features(features)
  , Parallel(std::move(parallelFor))
  , LabelData(features.cells, -1)
  , DistanceData(features.cells, 0.0f)
{
}

//------------------------------------------------------------------------------
std::size_t KMeansCPUEngine::Assign(const std::vector<float>& centres, int k)
{
  if (k < 1 || centres.size() != static_cast<std::size_t>(k) * this->Features.features)
  {
    throw std::invalid_argument("k-means: Assign needs k >= 1 and k * features centre values");
  }
  // Each block is assigned and then summed (KMeansBlockSums) while its features are still in
  // the cache: one pass over the features per iteration instead of two. Sums() then only adds
  // the blocks, as long as the block buffers fit k (they always hold the last Assign's sums).
  const std::size_t n = this->Features.cells;
  const std::size_t K = static_cast<std::size_t>(k);
  const std::size_t blocks = this->Features.Blocks();
  const std::size_t per = K * static_cast<std::size_t>(this->Features.features);
  this->BlockSumData.resize(blocks * per);
  this->BlockCountData.resize(blocks * K);
  this->BlockInertiaData.resize(blocks);
  std::atomic<std::size_t> changed{ 0 };
  RunParallel(this->Parallel,
    0,
    blocks,
    [&](std::size_t b0, std::size_t b1)
    {
      std::size_t local = 0;
      for (std::size_t b = b0; b < b1; ++b)
      {
        local += KMeansAssignRange(this->Features,
          centres.data(),
          k,
          BlockBegin(b),
          BlockEnd(b, n),
          this->LabelData.data(),
          this->DistanceData.data());
        KMeansBlockSums(this->Features,
          this->LabelData.data(),
          this->DistanceData.data(),
          k,
          b,
          this->BlockSumData.data() + b * per,
          this->BlockCountData.data() + b * K,
          this->BlockInertiaData.data() + b);
      }
      changed += local;
    });
  return changed.load();
}

//------------------------------------------------------------------------------
void KMeansCPUEngine::Sums(int k,
  std::vector<double>& sums,
  std::vector<std::int64_t>& counts,
  double& inertia)
{
  const std::size_t K = static_cast<std::size_t>(std::max(k, 0));
  const std::size_t nf = static_cast<std::size_t>(this->Features.features);
  const std::size_t blocks = this->Features.Blocks();
  const std::size_t per = K * nf;
  if (this->BlockSumData.size() != blocks * per || this->BlockCountData.size() != blocks * K)
  {
    // No Assign with this k yet (labels of an earlier k, or none): sum the blocks now.
    this->BlockSumData.resize(blocks * per);
    this->BlockCountData.resize(blocks * K);
    this->BlockInertiaData.resize(blocks);
    RunParallel(this->Parallel,
      0,
      blocks,
      [&](std::size_t b0, std::size_t b1)
      {
        for (std::size_t b = b0; b < b1; ++b)
        {
          KMeansBlockSums(this->Features,
            this->LabelData.data(),
            this->DistanceData.data(),
            k,
            b,
            this->BlockSumData.data() + b * per,
            this->BlockCountData.data() + b * K,
            this->BlockInertiaData.data() + b);
        }
      });
  }
  sums.assign(per, 0.0);
  counts.assign(K, 0);
  inertia = 0.0;
  for (std::size_t b = 0; b < blocks; ++b)
  {
    const double* s = this->BlockSumData.data() + b * per;
    for (std::size_t i = 0; i < per; ++i)
    {
      sums[i] += s[i];
    }
    const std::int64_t* c = this->BlockCountData.data() + b * K;
    for (std::size_t i = 0; i < K; ++i)
    {
      counts[i] += c[i];
    }
    inertia += this->BlockInertiaData[b];
  }
}

//------------------------------------------------------------------------------
const char* KMeansStopReasonName(KMeansStopReason reason)
{
  switch (reason)
  {
    case KMeansStopReason::Converged:
      return "Converged";
    case KMeansStopReason::Tolerance:
      return "Tolerance";
    case KMeansStopReason::MaximumIterations:
      return "MaximumIterations";
  }
  return "Unknown";
}

//------------------------------------------------------------------------------
double KMeansMeanVariance(const KMeansFeatures& features,
  const KMeansParallelFor& parallelFor,
  KMeansReduction* reduction)
{
  const std::size_t nf = static_cast<std::size_t>(std::max(features.features, 0));
  const std::size_t blocks = features.Blocks();
  std::int64_t cells = static_cast<std::int64_t>(features.cells);
  if (reduction)
  {
    reduction->Sum(&cells, 1);
  }
  if (nf == 0 || cells == 0)
  {
    return 0.0;
  }
  const double n = static_cast<double>(cells);
  // Per-feature sums of x (mean == nullptr) or of (x - mean)^2: each block in cell order, in
  // parallel, then the blocks added in block order.
  std::vector<double> partial(blocks * nf);
  auto blockOrderSums = [&](const double* mean)
  {
    RunParallel(parallelFor,
      0,
      blocks,
      [&](std::size_t b0, std::size_t b1)
      {
        for (std::size_t b = b0; b < b1; ++b)
        {
          if (mean)
          {
            BlockFeatureSums<true>(features, b, mean, &partial[b * nf]);
          }
          else
          {
            BlockFeatureSums<false>(features, b, nullptr, &partial[b * nf]);
          }
        }
      });
    std::vector<double> total(nf, 0.0);
    for (std::size_t b = 0; b < blocks; ++b)
    {
      for (std::size_t f = 0; f < nf; ++f)
      {
        total[f] += partial[b * nf + f];
      }
    }
    if (reduction)
    {
      reduction->Sum(total.data(), nf);
    }
    return total;
  };
  std::vector<double> mean = blockOrderSums(nullptr);
  for (double& m : mean)
  {
    m /= n;
  }
  const std::vector<double> squares = blockOrderSums(mean.data());
  double total = 0.0;
  for (std::size_t f = 0; f < nf; ++f)
  {
    total += squares[f] / n;
  }
  return total / static_cast<double>(nf);
}

namespace
{
/// KMeansLloyd's argument checks, in its documented order (std::invalid_argument).
void CheckLloydArguments(const KMeansFeatures& features,
  std::size_t totalCells,
  const std::vector<float>& initialCentres,
  int k,
  const KMeansOptions& options)
{
  if (k < 1 || k > KMeansMaxClusters)
  {
    throw std::invalid_argument("k-means: the number of clusters must be in [1, " +
      std::to_string(KMeansMaxClusters) + "] (got " + std::to_string(k) + ")");
  }
  if (static_cast<std::size_t>(k) > totalCells)
  {
    throw std::invalid_argument("k-means: " + std::to_string(k) + " clusters but only " +
      std::to_string(totalCells) + " cells");
  }
  const std::size_t K = static_cast<std::size_t>(k);
  const std::size_t nf = static_cast<std::size_t>(std::max(features.features, 0));
  if (features.features < 1 || initialCentres.size() != K * nf)
  {
    throw std::invalid_argument("k-means: " + std::to_string(initialCentres.size()) +
      " initial centre values, expected k * features = " + std::to_string(k) + " * " +
      std::to_string(features.features));
  }
  if (options.maximumIterations < 1)
  {
    throw std::invalid_argument("k-means: the maximum number of iterations must be at least 1 "
                                "(got " +
      std::to_string(options.maximumIterations) + ")");
  }
  if (!(options.tolerance >= 0.0))
  {
    throw std::invalid_argument("k-means: the tolerance must be a number >= 0");
  }
}

/// The clusters without a member, in increasing order.
std::vector<std::size_t> EmptyClusters(const std::vector<std::int64_t>& counts, std::size_t K)
{
  std::vector<std::size_t> empty;
  for (std::size_t kk = 0; kk < K; ++kk)
  {
    if (counts[kk] == 0)
    {
      empty.push_back(kk);
    }
  }
  return empty;
}

/**
 * Step 3 of KMeansLloyd, empty clusters (scikit-learn's _relocate_empty_clusters_dense): the
 * cells farthest from their centre, largest kept d2 first (ties to the lowest cell), move to
 * the empty clusters in increasing order (in `sums` and `counts`); nothing when every cell sits
 * on its centre. Reads the engine's labels and distances only when a cluster is empty. Returns
 * the number of clusters relocated.
 */
int RelocateEmptyClusters(KMeansEngine& engine,
  const KMeansFeatures& features,
  std::size_t K,
  std::vector<double>& sums,
  std::vector<std::int64_t>& counts)
{
  const std::size_t nf = static_cast<std::size_t>(std::max(features.features, 0));
  const std::vector<std::size_t> empty = EmptyClusters(counts, K);
  if (empty.empty())
  {
    return 0;
  }
  const float* d = engine.Distances();
  const std::int32_t* labels = engine.Labels();
  // The |empty| largest d2, in decreasing order (ties: lower index first). Scanning in cell
  // order, only a strictly larger d2 passes an entry already kept.
  std::vector<std::size_t> far;
  for (std::size_t c = 0; c < features.cells; ++c)
  {
    if (far.size() == empty.size() && !(d[c] > d[far.back()]))
    {
      continue;
    }
    std::size_t pos = far.size();
    while (pos > 0 && d[c] > d[far[pos - 1]])
    {
      --pos;
    }
    far.insert(far.begin() + static_cast<std::ptrdiff_t>(pos), c);
    if (far.size() > empty.size())
    {
      far.pop_back();
    }
  }
  int relocated = 0;
  if (!far.empty() && d[far[0]] > 0.0f)
  {
    for (std::size_t e = 0; e < empty.size(); ++e)
    {
      const std::size_t kk = empty[e];
      const std::size_t cell = far[e];
      const std::size_t old = static_cast<std::size_t>(labels[cell]);
      for (std::size_t f = 0; f < nf; ++f)
      {
        const double x = static_cast<double>(features.At(static_cast<int>(f), cell));
        sums[old * nf + f] -= x;
        sums[kk * nf + f] = x;
      }
      counts[kk] = 1;
      counts[old] -= 1;
      ++relocated;
    }
  }
  return relocated;
}

/**
 * Step 3 in a distributed run: the same cells as RelocateEmptyClusters would pick from all the
 * processes' cells together. For each empty cluster in increasing order, the largest kept d2
 * over every process (all-reduced maximum) among the cells not yet taken, ties to the lowest
 * cell of the whole grid (all-reduced minimum of `globalCells`); its owner contributes its
 * features and old label (all-reduced sum: the others add zeros), and every process moves it
 * in `sums` and `counts`, which are already the totals. Nothing when the farthest cell sits on
 * its centre.
 */
int RelocateEmptyClustersDistributed(KMeansEngine& engine,
  const KMeansFeatures& features,
  std::size_t K,
  KMeansReduction& reduction,
  const std::int64_t* globalCells,
  std::vector<double>& sums,
  std::vector<std::int64_t>& counts)
{
  const std::size_t nf = static_cast<std::size_t>(std::max(features.features, 0));
  const std::vector<std::size_t> empty = EmptyClusters(counts, K);
  if (empty.empty())
  {
    return 0;
  }
  const float* d = engine.Distances();
  const std::int32_t* labels = engine.Labels();
  std::vector<std::size_t> taken;
  int relocated = 0;
  for (std::size_t e = 0; e < empty.size(); ++e)
  {
    // This process's farthest cell not taken yet (ties: lowest cell, as the scan is in order).
    std::size_t best = features.cells;
    for (std::size_t c = 0; c < features.cells; ++c)
    {
      if ((best == features.cells || d[c] > d[best]) &&
        std::find(taken.begin(), taken.end(), c) == taken.end())
      {
        best = c;
      }
    }
    double farthest = best < features.cells ? static_cast<double>(d[best])
                                            : -std::numeric_limits<double>::infinity();
    reduction.Max(&farthest, 1);
    if (e == 0 && !(farthest > 0.0))
    {
      return 0; // every cell sits on its centre
    }
    const bool candidate = best < features.cells && static_cast<double>(d[best]) == farthest;
    std::int64_t cell = candidate ? globalCells[best] : std::numeric_limits<std::int64_t>::max();
    reduction.Min(&cell, 1);
    const bool mine = candidate && globalCells[best] == cell;
    // The owner's features and old label + 1 (the others contribute zeros).
    std::vector<double> payload(nf + 1, 0.0);
    if (mine)
    {
      for (std::size_t f = 0; f < nf; ++f)
      {
        payload[f] = static_cast<double>(features.At(static_cast<int>(f), best));
      }
      payload[nf] = static_cast<double>(labels[best]) + 1.0;
      taken.push_back(best);
    }
    reduction.Sum(payload.data(), nf + 1);
    const std::size_t kk = empty[e];
    const std::size_t old = static_cast<std::size_t>(payload[nf]) - 1;
    for (std::size_t f = 0; f < nf; ++f)
    {
      sums[old * nf + f] -= payload[f];
      sums[kk * nf + f] = payload[f];
    }
    counts[kk] = 1;
    counts[old] -= 1;
    ++relocated;
  }
  return relocated;
}

/// Adds every process's sums, counts and inertia (a distributed run), in place.
void ReduceSums(KMeansReduction* reduction,
  std::vector<double>& sums,
  std::vector<std::int64_t>& counts,
  double& inertia)
{
  if (!reduction)
  {
    return;
  }
  reduction->Sum(sums.data(), sums.size());
  reduction->Sum(counts.data(), counts.size());
  reduction->Sum(&inertia, 1);
}

/**
 * Step 4 of KMeansLloyd, the new centres (K * nf) into `next`: sums / counts. A cluster left
 * empty keeps sums of 0 as its centre (scikit-learn's _average_centers only divides clusters
 * with members). Returns the squared shift from `centres` (per cluster, then summed).
 */
double NewCentres(const std::vector<double>& sums,
  const std::vector<std::int64_t>& counts,
  std::size_t K,
  std::size_t nf,
  const std::vector<float>& centres,
  std::vector<float>& next)
{
  for (std::size_t kk = 0; kk < K; ++kk)
  {
    for (std::size_t f = 0; f < nf; ++f)
    {
      const double s = sums[kk * nf + f];
      next[kk * nf + f] =
        static_cast<float>(counts[kk] > 0 ? s / static_cast<double>(counts[kk]) : s);
    }
  }
  double shift = 0.0;
  for (std::size_t kk = 0; kk < K; ++kk)
  {
    double s = 0.0;
    for (std::size_t f = 0; f < nf; ++f)
    {
      const double d =
        static_cast<double>(next[kk * nf + f]) - static_cast<double>(centres[kk * nf + f]);
      s += d * d;
    }
    shift += s;
  }
  return shift;
}
} // namespace

//------------------------------------------------------------------------------
KMeansResult KMeansLloyd(KMeansEngine& engine,
  const KMeansFeatures& features,
  const std::vector<float>& initialCentres,
  int k,
  const KMeansOptions& options,
  const std::function<void(int, std::size_t)>& progress)
{
  KMeansReduction* reduction = options.reduction;
  if (reduction && !options.globalCells)
  {
    throw std::invalid_argument("k-means: a distributed run needs the cells' global indices");
  }
  std::int64_t totalCells = static_cast<std::int64_t>(features.cells);
  if (reduction)
  {
    reduction->Sum(&totalCells, 1);
  }
  CheckLloydArguments(features, static_cast<std::size_t>(totalCells), initialCentres, k, options);
  const std::size_t K = static_cast<std::size_t>(k);
  const std::size_t nf = static_cast<std::size_t>(std::max(features.features, 0));
  // scikit-learn's _tolerance: tol * mean of the features' variances (0 needs no pass).
  const double threshold = options.tolerance > 0.0
    ? options.tolerance * KMeansMeanVariance(features, KMeansParallelFor(), reduction)
    : 0.0;

  KMeansResult result;
  std::vector<float> centres = initialCentres; // used by the next assignment
  std::vector<float> next(K * nf);
  std::vector<double> sums;
  std::vector<std::int64_t> counts;
  double inertia = 0.0;
  std::vector<std::int64_t> rawCounts; // counts of the last assignment's labels
  bool strict = false;
  int i = 0;
  for (;; ++i)
  {
    // 1-2. Assignment to `centres`, sums of the new labels.
    std::size_t changed = engine.Assign(centres, k);
    engine.Sums(k, sums, counts, inertia);
    ReduceSums(reduction, sums, counts, inertia);
    if (reduction)
    {
      std::int64_t all = static_cast<std::int64_t>(changed);
      reduction->Sum(&all, 1);
      changed = static_cast<std::size_t>(all);
    }
    rawCounts = counts;

    // 3. Empty clusters take the cells farthest from their centres; 4. new centres.
    result.relocated += reduction
      ? RelocateEmptyClustersDistributed(
          engine, features, K, *reduction, options.globalCells, sums, counts)
      : RelocateEmptyClusters(engine, features, K, sums, counts);
    const double shift = NewCentres(sums, counts, K, nf, centres, next);
    std::swap(centres, next); // centres: new; next: those the labels were assigned to

    if (progress)
    {
      progress(i + 1, changed);
    }
    // 5. Stop tests, in scikit-learn's order.
    if (i > 0 && changed == 0)
    {
      strict = true;
      result.reason = KMeansStopReason::Converged;
      break;
    }
    if (shift <= threshold)
    {
      result.reason = KMeansStopReason::Tolerance;
      break;
    }
    if (i + 1 >= options.maximumIterations)
    {
      result.reason = KMeansStopReason::MaximumIterations;
      break;
    }
  }

  // Final assignment to the final centres (scikit-learn's "rerun E-step"); after a strict
  // convergence only when the centres moved nonetheless (a relocation), so that labels, centres
  // and inertia agree.
  if (!strict || std::memcmp(centres.data(), next.data(), centres.size() * sizeof(float)) != 0)
  {
    engine.Assign(centres, k);
    engine.Sums(k, sums, rawCounts, inertia);
    ReduceSums(reduction, sums, rawCounts, inertia);
  }
  result.centres = std::move(centres);
  result.counts = std::move(rawCounts);
  result.inertia = inertia;
  result.iterations = i + 1;
  return result;
}

//------------------------------------------------------------------------------

void KMeansClusterColorRGB(int id, unsigned char rgb[3])
{
  const unsigned char* c = terroir::ClusterColorRGB(id);
  rgb[0] = c[0];
  rgb[1] = c[1];
  rgb[2] = c[2];
}

std::string KMeansClusterColor(int id)
{
  unsigned char rgb[3];
  KMeansClusterColorRGB(id, rgb);
  static const char* hex = "0123456789abcdef";
  std::string s = "#";
  for (unsigned char v : rgb)
  {
    s += hex[v >> 4];
    s += hex[v & 15];
  }
  return s;
}

} // namespace clustering
} // namespace terroir

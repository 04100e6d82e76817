/**
 * @file RowKernels.h
 * @brief Row scheduling and fixed-order sums shared by the terrain cores (internal).
 *
 * A core pass is a function of a row range [j0, j1); it writes one partial sum per row, and the
 * rows' sums are added in row order afterwards, so a total has the same bits for any split of
 * the rows between threads. AddCompensated is the TwoSum update of a float carried with its
 * rounding residue. Used by Erosion.cxx, Vegetation.cxx and Atmosphere.cxx.
 */
#ifndef terroir_terrain_RowKernels_h
#define terroir_terrain_RowKernels_h

#include "Erosion.h"

#include <vector>

namespace terroir
{
namespace terrain
{
namespace detail
{

/// Runs body over rows [0, ny), through parallelFor when given, else in one call.
inline void ForRows(const ErosionParallelFor& parallelFor,
  int ny,
  const std::function<void(int, int)>& body)
{
  if (parallelFor)
  {
    parallelFor(0, ny, body);
  }
  else
  {
    body(0, ny);
  }
}

/// Sum of per-row partial sums in row order (the same total for any row split).
inline double SumRows(const std::vector<double>& rows)
{
  double total = 0.0;
  for (double r : rows)
  {
    total += r;
  }
  return total;
}

/// hi + lo += delta with the rounding error kept in lo (Knuth's TwoSum on hi and delta + lo):
/// a float carried with about twice float's precision, so that many small changes to a large
/// value add up instead of rounding away. Plain float operations (a shader can do the same).
inline void AddCompensated(float& hi, float& lo, float delta)
{
  const float t = delta + lo;
  const float sum = hi + t;
  const float back = sum - hi;
  lo = (hi - (sum - back)) + (t - back);
  hi = sum;
}

} // namespace detail
} // namespace terrain
} // namespace terroir

#endif

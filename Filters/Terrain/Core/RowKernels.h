/**
 * @file RowKernels.h
 * @brief Row scheduling and fixed-order sums shared by the terrain cores (internal).
 *
 * A core pass is a function of a row range [j0, j1); it writes one partial sum per row, and the
 * rows' sums are added in row order afterwards, so a total has the same bits for any split of
 * the rows between threads. (Erosion.cxx and Vegetation.cxx still carry their own copies of
 * these two helpers; they can move here.)
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

} // namespace detail
} // namespace terrain
} // namespace terroir

#endif

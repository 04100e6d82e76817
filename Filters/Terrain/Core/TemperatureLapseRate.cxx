#include "TemperatureLapseRate.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace terroir
{
namespace terrain
{

bool SeaLevelTemperaturesFromExtremes(double coldest,
  double warmest,
  int coldestMonth,
  int warmestMonth,
  double monthly[12])
{
  if (coldestMonth < 1 || coldestMonth > 12 || warmestMonth < 1 || warmestMonth > 12 ||
    coldestMonth == warmestMonth)
  {
    return false;
  }
  const int d = (warmestMonth - coldestMonth + 12) % 12;
  for (int m = 1; m <= 12; ++m)
  {
    const int k = (m - coldestMonth + 12) % 12;
    monthly[m - 1] = (k <= d) ? coldest + (warmest - coldest) * k / d
                              : warmest + (coldest - warmest) * (k - d) / (12 - d);
  }
  return true;
}

template<typename T>
void TemperatureLapseRateRows(const GridView<T>& view,
  const double seaLevel[12],
  double lapseRate,
  T* temperature,
  int row0,
  int row1)
{
  T sea[12];
  for (int m = 0; m < 12; ++m)
  {
    sea[m] = static_cast<T>(seaLevel[m]);
  }
  const T rate = static_cast<T>(lapseRate / 1000.0);
  const T nan = std::numeric_limits<T>::quiet_NaN();
  row0 = std::max(row0, 0);
  row1 = std::min(row1, view.ny);
  for (int j = row0; j < row1; ++j)
  {
    const std::size_t start = view.Index(0, j);
    for (int i = 0; i < view.nx; ++i)
    {
      const std::size_t idx = start + static_cast<std::size_t>(i);
      const T h = view.data[idx];
      T* out = temperature + 12 * idx;
      const bool ok = (!view.valid || view.valid[idx]) && !std::isnan(h);
      const T drop = rate * h;
      for (int m = 0; m < 12; ++m)
      {
        out[m] = ok ? sea[m] - drop : nan;
      }
    }
  }
}

template void TemperatureLapseRateRows<float>(const GridView<float>&,
  const double[12],
  double,
  float*,
  int,
  int);
template void TemperatureLapseRateRows<double>(const GridView<double>&,
  const double[12],
  double,
  double*,
  int,
  int);

} // namespace terrain
} // namespace terroir

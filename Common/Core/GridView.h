/**
 * @file GridView.h
 * @brief Non-owning view of a 2-D terrain grid, shared by every algorithm core.
 *
 * Layout: `nx` columns (west to east) by `ny` rows, row-major, index `j * nx + i`; row
 * `j = 0` is the southern row (VTK's image order, y grows northwards). Spacings are metres.
 * For geographic (degree) grids the east-west cell size changes from row to row: `rowDx`
 * (and `rowDy`) then hold one metric spacing per row, computed by the DEM reader with
 * GeographicLib geodesics; when null, `dx`/`dy` hold for every row.
 * `valid` is an optional mask (1 = valid, 0 = no data); when null every cell is valid.
 * No VTK and no GL types appear here, so the cores stay plain C++.
 */
#ifndef terroir_GridView_h
#define terroir_GridView_h

#include <cstddef>
#include <cstdint>

namespace terroir
{

template<typename T>
struct GridView
{
  const T* data = nullptr;       ///< nx*ny values, row j = 0 in the south
  int nx = 0;                    ///< columns
  int ny = 0;                    ///< rows
  double dx = 1.0;               ///< east-west spacing, metres (all rows unless rowDx)
  double dy = 1.0;               ///< north-south spacing, metres (all rows unless rowDy)
  const double* rowDx = nullptr; ///< optional, ny entries: east-west spacing of row j, metres
  const double* rowDy = nullptr; ///< optional, ny entries: north-south spacing at row j, metres
  const std::uint8_t* valid = nullptr; ///< optional, nx*ny entries: 1 valid, 0 no data

  std::size_t Size() const { return static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny); }
  std::size_t Index(int i, int j) const
  {
    return static_cast<std::size_t>(j) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(i);
  }
  T At(int i, int j) const { return data[Index(i, j)]; }
  bool IsValid(int i, int j) const { return !valid || valid[Index(i, j)] != 0; }
  double DxAt(int j) const { return rowDx ? rowDx[j] : dx; }
  double DyAt(int j) const { return rowDy ? rowDy[j] : dy; }
};

} // namespace terroir

#endif

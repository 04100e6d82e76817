// A small terrain drawn row by row in a test (north row first, as it reads on screen), with the
// storage behind its terroir::GridView. Header only and without VTK, so the unit tests (which
// link only the cores) can use it.
#ifndef TerroirDrawnGrid_h
#define TerroirDrawnGrid_h

#include "GridView.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace terroir_test
{

struct DrawnGrid
{
  std::vector<float> z;
  std::vector<std::uint8_t> valid;
  std::vector<double> rowDx, rowDy; ///< optional per-row spacings (point view.rowDx/rowDy here)
  terroir::GridView<float> view;

  /// `rows` lists the ny rows north first; each has nx heights, west to east.
  DrawnGrid(int nx, int ny, double dx, double dy, const std::vector<std::vector<float>>& rows)
  {
    z.resize(static_cast<std::size_t>(nx) * ny);
    for (int j = 0; j < ny; ++j)
    {
      for (int i = 0; i < nx; ++i)
      {
        z[static_cast<std::size_t>(j) * nx + i] = rows[ny - 1 - j][i];
      }
    }
    view.data = z.data();
    view.nx = nx;
    view.ny = ny;
    view.dx = dx;
    view.dy = dy;
  }
  /// Marks cell (i, j) as no data through the mask (its elevation stays as it is).
  void MaskOut(int i, int j)
  {
    if (valid.empty())
    {
      valid.assign(z.size(), 1);
    }
    valid[view.Index(i, j)] = 0;
    view.valid = valid.data();
  }
  std::size_t Cell(int i, int j) const { return view.Index(i, j); }
};

} // namespace terroir_test

#endif

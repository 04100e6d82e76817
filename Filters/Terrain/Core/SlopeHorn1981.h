/**
 * @file SlopeHorn1981.h
 * @brief Slope, aspect and surface normals by Horn's (1981) 3x3 method, as `gdaldem slope`.
 *
 * Plain C++ (no VTK, no GL): the reference implementation that the CPU kernel of
 * vtkTerroirSlope runs and that Shaders/Slope.comp mirrors step for step.
 *
 * Method. For each cell the 3x3 window w0..w8 is read with w0..w2 the northern row
 * (j + 1), w3..w5 the cell's row and w6..w8 the southern row (j - 1), west to east:
 * \f[
 *   \frac{\partial z}{\partial x} = \frac{(w_2-w_0)}{8\,dx_{j+1}} + \frac{2(w_5-w_3)}{8\,dx_j}
 *     + \frac{(w_8-w_6)}{8\,dx_{j-1}},\qquad
 *   \frac{\partial z}{\partial y} = \frac{(w_0-w_6)+2(w_1-w_7)+(w_2-w_8)}{8\,dy_j}
 * \f]
 * (times the z factor). With one spacing for every row this is exactly Horn's weighted
 * difference and gdaldem's; on geographic grids each row's difference is divided by that
 * row's own east-west cell size. Differences are taken before sums (exact for nearby floats),
 * so the float version stays within 3e-5 deg of the double one in aspect. For float, interior
 * rows without no data run a branch-free, vectorized loop whose arctangents are a degree-15
 * polynomial (max error 1.4e-7 rad); double uses std::atan/std::atan2. Slope = atan(|grad z|) in
 * degrees, or 100 |grad z| percent. Aspect is the direction the slope faces (downhill), degrees
 * clockwise from grid north, plus `convergenceDeg` (true = grid + gamma), wrapped to [0, 360); flat
 * cells (zero gradient) get NaN. Normal = (-dz/dx, -dz/dy, 1) / norm (x east, y north, z up, grid
 * axes).
 *
 * Edges and no data, as `gdaldem -compute_edges` (GDAL 3.6 apps/gdaldem_lib.cpp, verified
 * against the binary): on an interior row, the missing column beyond the first/last column is
 * extrapolated linearly (2 z_edge - z_inner); on the first/last row, the missing row is
 * extrapolated linearly in the same way while the window's columns are clamped to the grid
 * (so at the four corner cells the east-west difference spans one cell but is divided by two:
 * gdaldem's corner value, reproduced on purpose). A no-data cell gives NaN everywhere; a
 * no-data neighbour (or an extrapolation that uses one) is replaced by the centre value.
 *
 * @par Correctness
 * Testing/Unit/TestSlopeHorn1981.cxx (tilted planes, cone, edges, per-row spacing, no data),
 * Testing/Pipeline/TestTerroirSlopeGdaldem.cxx (every cell of the bundled DEM vs gdaldem).
 *
 * @par Reference
 * Horn, B.K.P. (1981). Hill shading and the reflectance map. Proceedings of the IEEE
 * 69(1):14-47. doi:10.1109/PROC.1981.11918
 */
#ifndef terroir_terrain_SlopeHorn1981_h
#define terroir_terrain_SlopeHorn1981_h

#include "GridView.h"

namespace terroir
{
namespace terrain
{

/// Units of the slope output.
enum class SlopeUnits
{
  Degrees = 0, ///< atan(|grad z|), degrees in [0, 90)
  Percent = 1  ///< 100 |grad z|
};

/// Parameters of SlopeHorn1981Rows.
struct SlopeParams
{
  double zFactor = 1.0;                   ///< elevation multiplier (vertical units to metres)
  SlopeUnits units = SlopeUnits::Degrees; ///< slope units
  double convergenceDeg = 0.0;            ///< added to the grid aspect (meridian convergence)
};

/// Per-row constants of Horn's kernel: 1/(8 dx) of the north, centre and south rows and
/// 1/(8 dy), times the z factor (computed in double, stored as T).
template<typename T>
struct SlopeRowCoefficients
{
  T cN, cC, cS, cY;
};

/// The constants of row j (its neighbours clamped at the edges); the CPU kernel and
/// Shaders/Slope.comp (through vtkTerroirSlope) both use these.
template<typename T>
SlopeRowCoefficients<T> SlopeHorn1981RowCoefficients(const GridView<T>& view, int j, double zFactor)
{
  const int jn = j + 1 < view.ny ? j + 1 : view.ny - 1;
  const int js = j > 0 ? j - 1 : 0;
  SlopeRowCoefficients<T> c;
  c.cN = static_cast<T>(zFactor / (8.0 * view.DxAt(jn)));
  c.cC = static_cast<T>(zFactor / (8.0 * view.DxAt(j)));
  c.cS = static_cast<T>(zFactor / (8.0 * view.DxAt(js)));
  c.cY = static_cast<T>(zFactor / (8.0 * view.DyAt(j)));
  return c;
}

/**
 * @brief Horn (1981) slope, aspect and normals for rows [row0, row1) of `view`.
 * @param[in] view    the grid (nx, ny >= 2), optional per-row spacing and validity mask
 * @param[in] params  z factor, slope units, meridian convergence
 * @param[out] slope   nx*ny values (only rows row0..row1-1 written), or nullptr
 * @param[out] aspect  nx*ny values, degrees clockwise from true north in [0,360), NaN when
 *                     flat or no data, or nullptr
 * @param[out] normals 3*nx*ny values (x, y, z per cell), or nullptr
 * @pre 0 <= row0 <= row1 <= ny, nx >= 2, ny >= 2; with no mask every value is finite
 * @post cells whose centre is no data get NaN in every output
 * Instantiated for float and double.
 */
template<typename T>
void SlopeHorn1981Rows(const GridView<T>& view,
  const SlopeParams& params,
  T* slope,
  T* aspect,
  T* normals,
  int row0,
  int row1);

/// All rows: SlopeHorn1981Rows(view, params, slope, aspect, normals, 0, view.ny).
template<typename T>
void SlopeHorn1981(const GridView<T>& view,
  const SlopeParams& params,
  T* slope,
  T* aspect,
  T* normals);

/**
 * @brief The 3x3 window of cell (i, j) with gdaldem's edge and no-data rules.
 * @param[out] w  w[0..2] northern row, w[3..5] centre row, w[6..8] southern row, west to east
 * @return false when the centre cell is no data (w is then undefined)
 */
template<typename T>
bool HornWindow(const GridView<T>& view, int i, int j, T w[9]);

} // namespace terrain
} // namespace terroir

#endif

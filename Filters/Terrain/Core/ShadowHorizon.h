/**
 * @file ShadowHorizon.h
 * @brief Terrain horizons and cast shadows: exact ray marching toward the sun, and a horizon
 *        map of K azimuth sectors by convex-hull sweeps (after Dozier & Frew 1990).
 *
 * Plain C++ (no VTK, no GL): the reference for vtkTerroirSolarIllumination's CPU kernel and
 * for Shaders/ShadowSweep.comp, ShadowGather.comp and SolarIllumination.comp (ray marching).
 *
 * Geometry. Cells are points at their centres; `dx`, `dy` are the spacings in metres (one per
 * axis: for geographic grids the filter passes the centre row's). A direction is a grid
 * azimuth phi (degrees clockwise from grid north; x = east = column i, y = north = row j).
 * Along phi the terrain is sampled where the ray crosses the grid lines of its major axis:
 * with (di, dj) = (sin phi / dx, cos phi / dy) cells per metre, the major axis is i when
 * |di| >= |dj| (else j); each step moves one cell along it and `slope` = minor/major cells,
 * |slope| <= 1, `length` = metres per step. A sample between two cells of the minor axis is
 * their linear interpolation (the terrain is piecewise linear along grid lines); a sample that
 * touches a no-data cell is skipped (it neither blocks nor stops the ray); the ray ends at the
 * grid's edge. The horizon of a cell in direction phi is the largest elevation-angle tangent
 * \f[ \tan h = \max_k \frac{z_k - z_0 - c\, s_k^2 / (2R)}{s_k} \f]
 * over its samples k at distances s_k, with c = 1 when the Earth's curvature is on
 * (R = 6371008.8 m, the IUGG mean radius) and 0 otherwise. With no sample (an edge cell
 * looking out of the grid) the horizon is the horizontal plane, kNoHorizon = 0, as if the
 * terrain went on flat. A cell is lit when tan(sun elevation) > tan h.
 *
 * Ray marching (HorizonTangentRayMarch) evaluates that maximum cell by cell: it is the
 * reference. The sweep (SweepLine / GatherSweep) runs, for each direction, parallel lines
 * one minor-axis cell apart, sampled at every major-axis index; along each line the upper
 * convex hull of the samples ahead (toward the sun) gives every sample's horizon in amortized
 * O(1) (the curvature term is handled exactly by hulling w = z - s^2/(2R) and adding s_p/R).
 * A cell centre lies between two lines; its horizon is their linear interpolation across the
 * minor axis. A horizon map stores, for K sectors phi_k = k * 360 / K, the tangents of every
 * cell (sector-major: plane k holds nx*ny values); a sun at grid azimuth phi reads the two
 * sectors around phi and interpolates the tangents linearly in azimuth.
 *
 * @par Correctness
 * Testing/Unit/TestShadowHorizon.cxx: a wall of height h with the sun at 45 degrees casts a
 * shadow of length h; tangents on planes and a cone worked out by hand; the Earth-curvature
 * drop; the sweep equals ray marching exactly on axis and diagonal directions (lines through
 * cell centres) and within interpolation error elsewhere, on seeded random terrains.
 * Testing/Pipeline/TestTerroirSolarIllumination.cxx: horizon map vs ray marching on the
 * bundled DEM (>= 99.5 % of cells agree for 20 sun positions over a year).
 * Testing/Python/TestGrassPeer.py: GRASS r.sunmask and r.horizon on the bundled DEM.
 *
 * @par References
 * Dozier, J. and Frew, J. (1990). Rapid calculation of terrain parameters for radiation
 * modeling from digital elevation data. IEEE Transactions on Geoscience and Remote Sensing
 * 28(5), 963-969. doi:10.1109/36.58986
 */
#ifndef terroir_terrain_ShadowHorizon_h
#define terroir_terrain_ShadowHorizon_h

#include "GridView.h"

#include <cstddef>
#include <vector>

namespace terroir
{
namespace terrain
{

/// Tangent used when a direction has no terrain sample (edge cells looking out): flat.
constexpr float kNoHorizon = 0.0f;
/// Earth's mean radius (IUGG), metres, for the curvature drop.
constexpr double kEarthRadiusM = 6371008.8;

/// How a direction is marched through the grid (see the file comment).
struct MarchDirection
{
  bool alongX = true;  ///< major axis: true = i (columns), false = j (rows)
  int step = 1;        ///< +1 or -1 along the major axis, toward the sun
  float slope = 0.0f;  ///< minor-axis cells per major step, |slope| <= 1
  float length = 1.0f; ///< metres per major step
};

/// The march of grid azimuth `gridAzimuthDeg` on a grid of spacings dx, dy (metres, > 0).
/// Multiples of 90 degrees give exact axis directions.
MarchDirection MakeMarchDirection(double gridAzimuthDeg, double dx, double dy);

/// 1 / (2R) per metre when `earthCurvature`, else 0: the curvature coefficient of the drop.
float CurvatureCoefficient(bool earthCurvature);

/**
 * @brief Horizon tangent of cell (i, j) toward `dir` by ray marching (the reference).
 * @param[in] view  elevations and optional mask (the cell itself must be valid)
 * @param[in] dir   from MakeMarchDirection
 * @param[in] curvature  CurvatureCoefficient(...)
 * @param[in] zMax  the largest valid elevation of the grid (for early exit)
 * @param[in] stopTangent  the march may stop as soon as the answer's comparison with this
 *                         value is known (pass +inf for the exact horizon)
 * @return the horizon tangent, or kNoHorizon when no sample exists; when stopped early the
 *         result r satisfies (r >= stopTangent) == (exact horizon >= stopTangent)
 */
template<typename T>
T HorizonTangentRayMarch(const GridView<T>& view,
  const MarchDirection& dir,
  float curvature,
  int i,
  int j,
  T zMax,
  T stopTangent);

/// Sweep lines of one direction: their count, and where each major-axis index sits.
struct SweepPlan
{
  MarchDirection dir;
  int nMajor = 0;            ///< cells along the major axis (nx or ny)
  int nMinor = 0;            ///< cells along the minor axis
  int lineCount = 0;         ///< number of lines
  int firstLine = 0;         ///< line offset c of line 0
  std::vector<int> floorAt;  ///< per major index u: F_u = floor(step * slope * u)
  std::vector<float> fracAt; ///< per major index u: f_u = step * slope * u - F_u, in [0, 1)
};

/// Lines of direction `dir` on an nx x ny grid. Line m passes minor position
/// c + step * slope * u at major index u, with c = firstLine + m.
SweepPlan MakeSweepPlan(const MarchDirection& dir, int nx, int ny);

/**
 * @brief Horizon tangents of the samples of line `m`, by the upper-convex-hull sweep.
 * @param[out] lineTangents  plan.nMajor values indexed by major index u: the tangent, or
 *                           NaN where the line has no valid sample at u
 * @param[in,out] scratch    working storage (resized as needed; reuse it between calls)
 */
template<typename T>
void SweepLine(const GridView<T>& view,
  const SweepPlan& plan,
  float curvature,
  int m,
  T* lineTangents,
  std::vector<T>& scratch);

/**
 * @brief Cells' horizon tangents from the line tangents of one direction.
 * @param[in] lines  plan.lineCount * plan.nMajor values (line m at m * nMajor)
 * @param[out] tangents  nx*ny values (row-major, j = 0 south); NaN for no-data cells
 * Cells in major-index range [u0, u1).
 */
template<typename T>
void GatherSweep(const GridView<T>& view,
  const SweepPlan& plan,
  const T* lines,
  T* tangents,
  int u0,
  int u1);

/// Grid azimuth of sector k of K: k * 360 / K degrees.
double SectorAzimuth(int k, int sectors);

/// Horizon-map lookup of a sun at grid azimuth `gridAzimuthDeg`: planes `sector0` and
/// `sector1` (= sector0 + 1 mod K) and the weight of `sector1` in [0, 1).
struct SectorLookup
{
  int sector0 = 0;
  int sector1 = 0;
  float weight1 = 0.0f;
};
SectorLookup LookupSectors(double gridAzimuthDeg, int sectors);

/**
 * @brief Horizon map of K sectors on the CPU, one direction after another (no threads here:
 * the caller splits sectors across threads).
 * @param[out] map  K * nx*ny tangents, sector-major (plane k = sector k), NaN for no data
 * Sectors in [k0, k1).
 */
template<typename T>
void HorizonMapSectors(const GridView<T>& view,
  int sectors,
  float curvature,
  T* map,
  int k0,
  int k1);

} // namespace terrain
} // namespace terroir

#endif

/**
 * @file RiverValidation.h
 * @brief Scores simulated river cells against reference (mapped) river cells on one grid.
 *
 * Plain C++ (no VTK, no GL): the scoring core of `terroir validate`. The reference is a river
 * network mapped by USGS (NHD flowlines) rasterised onto the DEM grid; the simulated rivers are
 * the cells a flow simulation calls river (for instance the top cells by `Discharge`, with the
 * threshold of LengthMatchingThreshold). Both are masks: a non-zero byte is a river cell.
 *
 * Distance. Cells are points at their centres. With constant spacing, cells (i, j) and
 * (i', j') lie sqrt((|i - i'| dx)^2 + (|j - j'| dy)^2) metres apart. With per-row spacing
 * (GridView::rowDx / rowDy, geographic grids), the north-south distance is the sum of the
 * centre-to-centre steps between the two rows, the step from row j to row j + 1 being
 * (dy_j + dy_{j+1}) / 2, and the east-west distance is |i - i'| times the mean of the two rows'
 * east-west spacings, (dx_j + dx_j') / 2. That mean makes the distance symmetric, so "a has b
 * within the tolerance" and "b has a within the tolerance" always agree. A cell is within the
 * tolerance of another when their distance is at most the tolerance (inclusive; a relative
 * 1e-9 allowance absorbs rounding, so a distance of exactly 3 x 10 m is within 30 m); distance
 * 0 means the same cell.
 *
 * Area. Only cells inside the area count: a cell is inside when `area` is null or `area[c]` is
 * non-zero, and the reference view's `valid` mask (when given) is non-zero there. A reference
 * or simulated cell outside the area is ignored completely: it is neither scored nor a match
 * partner for a cell inside. So a simulated river that leaves the watershed is not rewarded for
 * reaching a mapped river outside it, and the scores depend on the area only, never on what
 * lies beyond it.
 *
 * Method (exact, no approximation of the Euclidean disk). For the partner mask, one pass per
 * row stores for every cell the column distance |i - i'| to the nearest partner cell in the
 * same row (left-to-right, then right-to-left: the first, one-dimensional phase of the exact
 * Euclidean distance transforms of Saito & Toriwaki 1994 and Felzenszwalb & Huttenlocher
 * 2012). In a fixed pair of rows the distance grows with |i - i'|, so a query cell (i, j) has a
 * partner within the tolerance exactly when, for some row j' whose north-south distance to j
 * is within the tolerance, the nearest partner in row j' is close enough. Cost: O(nx ny) for
 * the row passes plus O(q r) for q query cells and r = the number of rows within the tolerance
 * (13 for 60 m on 10 m cells). Measured on the 2-core development machine (-O2), 4096^2 cells
 * of 10 m, 60 m: 0.17 s with 3 % river cells of each kind, 0.5 s when every cell is a
 * simulated river. Memory: 2 bytes per cell (4 when nx > 65535) for the column distances,
 * plus 3 bytes per cell of flags. Sequential and deterministic.
 *
 * @par Correctness
 * Testing/Unit/TestRiverValidation.cxx, suites RiverValidation and LengthMatchingThreshold:
 * precision, recall and categories worked out by hand (parallel lines 20 m apart, partial
 * overlaps, diagonal distances, dx != dy, per-row spacing, area masks, empty inputs), and
 * ScoreRivers equal to an O(n^2) brute force over all cell pairs on random rasters (fixed
 * mt19937_64 seed).
 *
 * @par References
 * Saito, T., Toriwaki, J.-I. (1994). New algorithms for Euclidean distance transformation of an
 * n-dimensional digitized picture with applications. Pattern Recognition 27(11):1551-1565.
 * doi:10.1016/0031-3203(94)90133-3
 * Felzenszwalb, P. F., Huttenlocher, D. P. (2012). Distance transforms of sampled functions.
 * Theory of Computing 8:415-428. doi:10.4086/toc.2012.v008a019
 */
#ifndef terroir_hydrology_RiverValidation_h
#define terroir_hydrology_RiverValidation_h

#include "GridView.h"

#include <cstddef>
#include <cstdint>

namespace terroir
{
namespace hydrology
{

/// Scores of simulated river cells against reference river cells (ScoreRivers).
struct RiverScores
{
  double toleranceMetres = 0.0;   ///< the tolerance the scores were computed with, metres
  std::size_t simulatedCells = 0; ///< simulated river cells inside the area
  std::size_t referenceCells = 0; ///< reference river cells inside the area
  std::size_t simulatedHits = 0;  ///< simulated cells with a reference cell within tolerance
  std::size_t referenceHits = 0;  ///< reference cells with a simulated cell within tolerance
  double precision = 0.0;         ///< simulatedHits / simulatedCells; 0 when no simulated cell
  double recall = 0.0;            ///< referenceHits / referenceCells; 0 when no reference cell
  double f1 = 0.0;                ///< 2 P R / (P + R); 0 when P + R = 0
};

/// Per-cell classes of RiverComparisonCategories (the values of the `RiverComparison` array).
enum RiverComparisonCategory : std::uint8_t
{
  RiverComparisonNone = 0,          ///< no river, or outside the area
  RiverComparisonMappedOnly = 1,    ///< reference cell with no simulated cell within tolerance
  RiverComparisonSimulatedOnly = 2, ///< simulated cell with no reference cell within tolerance
  RiverComparisonBoth = 3           ///< river cell with a partner of the other kind in tolerance
};

/**
 * @brief Precision, recall and F1 of simulated river cells against reference river cells,
 *        within a distance tolerance.
 *
 * precision = (simulated cells with a reference cell within the tolerance) / (simulated cells);
 * recall = (reference cells with a simulated cell within the tolerance) / (reference cells);
 * F1 = 2 precision recall / (precision + recall). All counts are over cells inside the area
 * (see the file comment for the distance and the area). Empty cases give 0, never NaN (the
 * scores go to JSON): no simulated cell gives precision 0, no reference cell gives recall 0,
 * and precision + recall = 0 gives F1 0. So with neither kind of cell every score is 0.
 *
 * @param[in] reference  reference rivers: nx*ny bytes, non-zero = river; the grid (nx, ny, dx,
 *                       dy, optional rowDx/rowDy) and the optional `valid` mask (0 = no data,
 *                       treated as outside the area) describe both rasters
 * @param[in] simulated  simulated rivers: nx*ny bytes on the same grid, non-zero = river
 * @param[in] area       optional nx*ny bytes, non-zero = scored; null = the whole grid
 * @param[in] toleranceMetres  match distance in metres (inclusive); 0 = the same cell only
 * @return the counts and scores, with toleranceMetres echoed
 * @pre reference.data and simulated non-null unless the grid is empty (else
 *      std::invalid_argument); toleranceMetres finite and >= 0 (else std::invalid_argument);
 *      dx, dy (or every rowDx/rowDy entry) finite and > 0 (else std::invalid_argument)
 * @post 0 <= precision, recall, f1 <= 1; simulatedHits <= simulatedCells; referenceHits <=
 *       referenceCells; the scores never decrease when the tolerance grows
 * @correctness Testing/Unit/TestRiverValidation.cxx, suite RiverValidation
 */
RiverScores ScoreRivers(const GridView<std::uint8_t>& reference,
  const std::uint8_t* simulated,
  const std::uint8_t* area,
  double toleranceMetres);

/**
 * @brief The river-value threshold at which the simulated river is as long as the reference:
 *        the number of cells with value >= t equals the number of reference cells.
 *
 * Counts are over cells inside the area (area null or non-zero, and `value.valid` null or
 * non-zero); non-finite values never count. Let k be the number of reference cells inside the
 * area. The result t is a value of the raster such that count(value >= t) = k. When ties make
 * the count jump past k (the k-th largest value v is shared by several cells), the two
 * candidates are v (count >= k) and the smallest value above v (count < k); the one whose
 * count is closer to k wins, and on a tie the larger threshold (the shorter river) wins. When
 * there are fewer than k finite values, t is the smallest of them (every cell counts). When
 * the closer candidate counts no cell (all values are tied at v and v overshoots by more than
 * k), t is +infinity.
 * Selection with std::nth_element, O(n) on average, no full sort.
 *
 * This is the "simulated river length equals reference length" rule of DESIGN.md, measured in
 * cells, so nothing is tuned to the answer: the threshold depends on how long the mapped
 * network is, not on where it lies.
 *
 * @param[in] value  the river strength per cell (e.g. Discharge), nx*ny values on the grid,
 *                   with its optional `valid` mask; spacing is not used
 * @param[in] reference  nx*ny bytes, non-zero = reference river cell; may be null only when
 *                       the grid is empty
 * @param[in] area   optional nx*ny bytes, non-zero = counted; null = the whole grid
 * @param[out] simulatedCellsOut  optional: the number of cells inside the area with value >= t
 * @return t; +infinity when there is no reference cell or no finite value in the area, or
 *         when the chosen count is 0 (then no cell is a simulated river and
 *         *simulatedCellsOut = 0)
 * @pre value.data and reference non-null unless the grid is empty (else std::invalid_argument)
 * @correctness Testing/Unit/TestRiverValidation.cxx, suite LengthMatchingThreshold
 */
double LengthMatchingThreshold(const GridView<double>& value,
  const std::uint8_t* reference,
  const std::uint8_t* area,
  std::size_t* simulatedCellsOut = nullptr);

/// @copydoc LengthMatchingThreshold(const GridView<double>&, const std::uint8_t*,
/// const std::uint8_t*, std::size_t*)
/// The float overload: t is one of the float values, returned as double.
double LengthMatchingThreshold(const GridView<float>& value,
  const std::uint8_t* reference,
  const std::uint8_t* area,
  std::size_t* simulatedCellsOut = nullptr);

/**
 * @brief Per-cell comparison classes, for the `RiverComparison` overlay.
 *
 * For each cell: 0 (RiverComparisonNone) when it is outside the area or neither kind of river;
 * 3 (RiverComparisonBoth) when it is a reference cell with a simulated cell within the
 * tolerance, or a simulated cell with a reference cell within the tolerance (a cell that is
 * both is always 3); otherwise 1 (RiverComparisonMappedOnly) for a reference cell and 2
 * (RiverComparisonSimulatedOnly) for a simulated cell. Distances, area and partners are those
 * of ScoreRivers, so the counts agree with its scores (a cell that is both kinds of river is
 * its own partner at distance 0).
 *
 * @param[in] reference  reference rivers and the grid (see ScoreRivers)
 * @param[in] simulated  simulated rivers, nx*ny bytes, non-zero = river
 * @param[in] area       optional nx*ny bytes, non-zero = inside; null = the whole grid
 * @param[in] toleranceMetres  match distance in metres (inclusive)
 * @param[out] category  nx*ny bytes: 0, 1, 2 or 3 as above; may not alias the inputs
 * @pre as ScoreRivers; category non-null unless the grid is empty (else std::invalid_argument)
 * @post the number of cells that are reference and in class 3 equals ScoreRivers'
 *       referenceHits, and the number of simulated cells in class 3 equals its simulatedHits
 * @correctness Testing/Unit/TestRiverValidation.cxx, suite RiverValidation (Categories*)
 */
void RiverComparisonCategories(const GridView<std::uint8_t>& reference,
  const std::uint8_t* simulated,
  const std::uint8_t* area,
  double toleranceMetres,
  std::uint8_t* category);

/**
 * @brief Channel cells of a flow measure (discharge, accumulation): the cells where the
 *        measure is a local maximum across at least one of the four axes through the cell.
 *
 * Rivers are lines, but a simulation that spreads water over a valley floor gives bands several
 * cells wide; a river is the crest of such a band. Cell c is a channel cell when, for one of
 * the axes E-W, N-S, NE-SW or NW-SE, value(c) >= value of both neighbours on that axis; an
 * axis with a neighbour outside the grid or without a value (NaN) does not count, so the grid's
 * edge does not make crests. On a D8 accumulation a channel
 * cell carries far more than its side neighbours, so D8 channels are kept whole. Non-finite
 * values are never channel cells.
 *
 * @param[in] value  nx*ny values (spacing is not used)
 * @param[out] channel nx*ny bytes, 1 = channel cell
 * @correctness Testing/Unit/TestWaterFlow.cxx, ChannelCells
 */
void ChannelCells(const GridView<double>& value, std::uint8_t* channel);

} // namespace hydrology
} // namespace terroir

#endif

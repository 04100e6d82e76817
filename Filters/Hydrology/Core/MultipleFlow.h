/**
 * @file MultipleFlow.h
 * @brief Dispersive flow accumulation baselines over a depression-filled surface: multiple
 *        flow directions (Freeman 1991, Quinn et al. 1991), D-infinity (Tarboton 1997), and
 *        the drainage-area x slope^theta channel-initiation score (Montgomery & Dietrich 1988).
 *
 * Plain C++ (no VTK, no GL): cores of vtkTerroirFlowAccumulation's methods besides D8. They
 * take the filled surface W of PriorityFloodBarnes2014 and the D8 codes of D8FlowDirections
 * (FlowAccumulation.h) for the same view.
 *
 * Partition. A cell with data and a code 0..7 sends its total (own weight plus everything it
 * received) to its receivers in fractions that sum to 1:
 * - when it has strictly lower neighbours (8-neighbours inside the grid with data, W lower),
 *   by the method's rule below;
 * - otherwise (a cell on a flat: a hydro-flattened lake, a filled depression) all of it to its
 *   D8 code's neighbour, the flat routing of D8FlowDirections (Barnes, Lehman & Mulla 2014);
 * cells coded -1 (outlets) keep their total; no-data cells (-2) get NaN.
 *
 * MFD (MultipleFlowAccumulation): neighbour k of drop tan b_k = (W_c - W_k) / L_k > 0 (L_k the
 * step length: dx, dy or the diagonal of the cell's row) gets a share proportional to
 * (tan b_k)^p, times the contour length C_k when `contourLength` is set (C = dy/2 for the
 * east-west steps, dx/2 for the north-south steps, sqrt(dx^2 + dy^2)/4 for the diagonals,
 * Quinn et al. 1991's 0.5 and 0.354 cell widths). p = 1.1 without contour lengths is Freeman
 * (1991) (SAGA's "Multiple Flow Direction"); p = 1 with them is Quinn et al. (1991); large p
 * tends to D8 (Holmgren 1994). With `adaptive`, each cell's p grows with its steepest descent
 * tan b_max on W: p = 1.1 + 8.9 min(tan b_max, 1) (MFD-md, Qin et al. 2007): dispersive on
 * gentle slopes, nearly D8 on steep ones.
 *
 * D-infinity (DInfinityAccumulation, Tarboton 1997): the eight triangular facets around the
 * cell, each between a cardinal neighbour e1 (at distance d1 along its axis) and the diagonal
 * neighbour e2 next to it (d2 along the other axis): s1 = (W_c - W_e1) / d1, s2 = (W_e1 -
 * W_e2) / d2, r = atan2(s2, s1), s = sqrt(s1^2 + s2^2); r < 0 gives r = 0, s = s1; r > a =
 * atan2(d2, d1) gives r = a, s = (W_c - W_e2) / sqrt(d1^2 + d2^2). The facet with the largest
 * s > 0 wins (ties to the first in the order E-NE, N-NE, N-NW, W-NW, W-SW, S-SW, S-SE, E-SE,
 * Tarboton's table 1); e1 gets (a - r) / a of the flow and e2 gets r / a. Facets with a
 * neighbour outside the grid or without data do not count; a cell with a lower neighbour but
 * no such facet follows its D8 code. The flow angle (radians counter-clockwise from east) is
 * returned for the `FlowAngle` array.
 *
 * Channel-initiation score (ChannelInitiationScore): A S^theta with A the accumulation given and
 * S the tangent of the steepest descent of the unfilled terrain to a lower 8-neighbour (the D8
 * rule's drop over step length, view.data), floored at `minimumSlope` so that flats and pits
 * (where filling made the surface level) keep a rank by area. Channels start where A S^theta
 * exceeds a threshold (Montgomery & Dietrich 1988, 1992; theta = 1 for their slope-area rule,
 * 2 for the stream-power form of Tarboton et al. 1991's constant drop).
 *
 * Accumulation: a topological sweep (Kahn 1962): in-degrees counted over the partition graph
 * (at most 8 per cell, one byte), then cells whose upstream cells are all done push their
 * totals, in a fixed order (a stack started in index order): deterministic, O(n) plus the
 * partition (computed twice per cell, no 32 bytes per cell of stored fractions). The graph has
 * no cycle: every edge goes to strictly lower W or, on flats, one D8 step nearer the flat's
 * outlet. Sums in double. Sequential.
 *
 * @par Correctness
 * Testing/Unit/TestMultipleFlow.cxx: fractions worked out by hand on planes (a plane along a
 * facet's bisector splits half and half; a plane at angle r sends (a - r)/a and r/a; MFD
 * shares on a cone apex and a saddle by hand), conservation (the outlets' totals sum to the
 * number of cells with data), a V-valley's thalweg, flats routed through their outlet,
 * Tarboton's example. Testing/Python/TestFlowAccumulationSaga.py compares the bundled DEM with
 * SAGA GIS when it is installed.
 *
 * @par References
 * Freeman, T.G. (1991). Calculating catchment area with divergent flow based on a regular
 * grid. Computers & Geosciences 17(3):413-422. doi:10.1016/0098-3004(91)90048-I
 * Quinn, P., Beven, K., Chevallier, P., Planchon, O. (1991). The prediction of hillslope flow
 * paths for distributed hydrological modelling using digital terrain models. Hydrological
 * Processes 5(1):59-79. doi:10.1002/hyp.3360050106
 * Holmgren, P. (1994). Multiple flow direction algorithms for runoff modelling in grid based
 * elevation models. Hydrological Processes 8(4):327-334. doi:10.1002/hyp.3360080405
 * Qin, C., Zhu, A.-X., Pei, T., Li, B., Zhou, C., Yang, L. (2007). An adaptive approach to
 * selecting a flow-partition exponent for a multiple-flow-direction algorithm. International
 * Journal of Geographical Information Science 21(4):443-458. doi:10.1080/13658810601073240
 * Tarboton, D.G. (1997). A new method for the determination of flow directions and upslope
 * areas in grid digital elevation models. Water Resources Research 33(2):309-319.
 * doi:10.1029/96WR03137
 * Montgomery, D.R., Dietrich, W.E. (1988). Where do channels begin? Nature 336:232-234.
 * doi:10.1038/336232a0
 * Kahn, A.B. (1962). Topological sorting of large networks. Communications of the ACM
 * 5(11):558-562. doi:10.1145/368996.369025
 */
#ifndef terroir_hydrology_MultipleFlow_h
#define terroir_hydrology_MultipleFlow_h

#include "FlowAccumulation.h"
#include "GridView.h"

#include <cstdint>

namespace terroir
{
namespace hydrology
{

/// Full citations, for logs.
extern const char* const kMFDFreeman1991Citation;
extern const char* const kDInfinityTarboton1997Citation;
extern const char* const kSlopeAreaMontgomery1988Citation;

/// Parameters of MultipleFlowAccumulation.
struct MFDOptions
{
  double exponent = 1.1;      ///< p, > 0: Freeman's 1.1 by default
  bool contourLength = false; ///< weigh shares by contour length (Quinn et al. 1991)
  /// Qin et al. (2007)'s MFD-md: the exponent of each cell is adaptiveMinimum +
  /// (adaptiveMaximum - adaptiveMinimum) min(tan b_max, 1), tan b_max its steepest descent
  /// (exponent unused).
  bool adaptive = false;
  double adaptiveMinimum = 1.1;  ///< p at flat cells (Qin et al. 2007)
  double adaptiveMaximum = 10.0; ///< p at slopes of 45 degrees and more (Qin et al. 2007)
};

/**
 * @brief MFD flow accumulation (see the file comment).
 * @param view      grid, spacing and validity; view.data unused
 * @param filled    nx*ny filled surface W (PriorityFloodBarnes2014)
 * @param direction nx*ny D8 codes of D8FlowDirections for the same W (flats, outlets, no data)
 * @param weight    nx*ny weights or null (1 per cell); NaN counts as 0
 * @param accumulation nx*ny output sums, NaN on no data
 * @throw std::invalid_argument on exponent <= 0 or not finite, an empty grid, a code 0..7
 *        pointing off the grid or to no data, or a cycle
 * @post with weight null, the outlets' (code -1) accumulations sum to the cells with data
 */
void MultipleFlowAccumulation(const GridView<float>& view,
  const float* filled,
  const std::int8_t* direction,
  const MFDOptions& mfd,
  const float* weight,
  double* accumulation,
  const AccumulationOptions& options = {});

/**
 * @brief D-infinity flow accumulation (see the file comment).
 * @param angle  optional nx*ny output: flow angle, radians counter-clockwise from east, in
 *               [0, 2 pi); NaN on no data and on outlets (-1); a flat cell's D8 direction
 * Other parameters, errors and post-condition as MultipleFlowAccumulation.
 */
void DInfinityAccumulation(const GridView<float>& view,
  const float* filled,
  const std::int8_t* direction,
  const float* weight,
  double* accumulation,
  float* angle = nullptr,
  const AccumulationOptions& options = {});

/**
 * @brief Slope-area channel-initiation score A S^theta (see the file comment).
 * @param view  the unfilled terrain (heights in view.data, validity, spacing)
 * @param accumulation nx*ny values A (any accumulation; NaN stays NaN)
 * @param theta exponent >= 0 (0 gives A); @param minimumSlope floor of S, >= 0
 * @param score nx*ny output (may alias accumulation)
 * @throw std::invalid_argument on theta or minimumSlope negative or not finite
 */
void ChannelInitiationScore(const GridView<float>& view,
  const double* accumulation,
  double theta,
  double minimumSlope,
  double* score);

} // namespace hydrology
} // namespace terroir

#endif

/**
 * @file Morphometry.h
 * @brief Landscape statistics of a DEM that a terrain generator can be judged by: hypsometric
 *        integral (Strahler 1952), slope distribution, drainage density, Strahler order and
 *        Horton's bifurcation and length ratios (Horton 1945, Strahler 1957), Hack's law
 *        (Hack 1957) and the share of cells in closed depressions.
 *
 * Plain C++ (no VTK, no GL): the whole of vtkTerroirMorphometry. CPU only and sequential: the
 * report is a handful of global sums and topological sweeps along the D8 flow paths, built on
 * the Priority-Flood fill and the D8 directions and accumulation of FlowAccumulation.h; it
 * costs a few times a flow accumulation and has no kernel worth a GPU.
 *
 * Definitions (chosen once, the same for every DEM; nothing is tuned per site). "Valid" cells
 * have data (mask 1 and a finite elevation). The cell area is DxAt(j) * DyAt(j).
 *
 * - Hypsometric integral (Strahler 1952, elevation-relief ratio form of Pike & Wilson 1971):
 *   HI = (mean z - min z) / (max z - min z) over valid cells; NaN when max = min.
 * - Slope: Horn (1981) degrees (SlopeHorn1981.h, the `terroir slope` core, gdaldem's edge
 *   rules) over valid cells: mean, median, 10th and 90th percentiles (linear interpolation
 *   between the two nearest ranks, as numpy.percentile's default: position p (n - 1) in the
 *   sorted values) and a histogram of slopeBinWidth-degree bins [0, w), [w, 2w), ... up to 90.
 * - Depressions: the filled surface W = PriorityFloodBarnes2014 (outlets: edge cells and cells
 *   next to no data, so the map edge and no-data holes drain out). Depression depth W - z; a
 *   cell is in a closed depression when W - z > depressionDepth (default 1 mm, above float
 *   rounding of real heights). Reported: that share of valid cells, and the volume sum((W - z)
 *   area) over all valid cells.
 * - Streams: D8 directions on W (D8FlowDirections: steepest descent, flats routed to their
 *   outlets) and D8 contributing area A in m^2 (the cell's own area included). A valid cell is
 *   a channel cell when A >= channelArea (default 1e5 m^2 = 0.1 km^2). Channel length: every
 *   channel cell adds its D8 step to the cell it drains to (DxAt(j) east-west, DyAt(j)
 *   north-south, sqrt(DxAt(j)^2 + DyAt(j)^2) diagonally, row j of the draining cell, as in
 *   D8FlowDirections); a channel cell that drains off the terrain adds nothing. Downstream of
 *   a channel cell is always a channel cell (A only grows downstream). Drainage density =
 *   channel length (km) / valid area (km^2).
 * - Strahler (1957) order of channel cells, in upstream-first order: a cell with no channel
 *   cell draining into it is order 1; else, with m the largest order among its channel
 *   inflows, m + 1 when two or more inflows have order m, else m. A stream of order w is a
 *   maximal chain of order-w cells; it starts at a head (no channel inflow) or at a junction
 *   of two or more order-(w - 1) inflows. N_w counts the starts of order w, L_w (total) sums
 *   the steps of the order-w cells (so a stream's length runs to the junction where it ends,
 *   and the L_w add up to the channel length), mean L_w = L_w / N_w. Every outlet's network
 *   is counted together (a DEM has many basins cut by its edge).
 * - Horton ratios (Horton 1945, in Strahler's ordering): least-squares slopes b_N of log10 N_w
 *   and b_L of log10 (mean L_w) against w; R_b = 10^(-b_N), R_l = 10^(b_L). Orders used:
 *   1 .. Omega - 1, Omega being the highest order on the DEM; the highest order is left out
 *   because the map edge cuts it (its streams are few, often one, and truncated). NaN when
 *   fewer than two orders remain (Omega < 3). The per-order table is reported for refits.
 * - Hack's law (Hack 1957) L = C A^h, fitted over every channel cell taken as the outlet of
 *   its sub-basin: A = its contributing area (km^2), L = its main-stream length (km) = the
 *   longest D8 flow path from the drainage divide to the cell (the longest chain of D8 steps
 *   ending at the cell; a cell with no inflow has L = 0; TauDEM's "plen"). Least squares of
 *   log10 L against log10 A over channel cells with L > 0: h = slope, C = 10^intercept
 *   (L in km, A in km^2). NaN with fewer than two distinct A.
 *
 * @par Correctness
 * Testing/Unit/TestMorphometry.cxx: a tilted plane (HI 0.5, constant analytic slope, no
 * depression, parallel order-1 streams of known length, Hack's fit against the (A, L) pairs
 * worked out by hand), a stepped square pyramid (HI 7/27 from its ring counts), one pit of
 * known depth and volume, a hand-drawn D8 tree with its orders, N_w, L_w, R_b and R_l worked
 * out on paper, a network built so that L = A^h exactly; no-data cells. The peer check
 * Testing/Python/TestMorphometryGrass.py compares slope, hypsometry, stream cells and
 * drainage density with GRASS (r.slope.aspect, r.univar, r.watershed -s) on the bundled DEM;
 * Testing/Python/TestMorphometry.py re-implements the network statistics in Python.
 *
 * @par References
 * Strahler, A.N. (1952). Hypsometric (area-altitude) analysis of erosional topography.
 * Geological Society of America Bulletin 63(11):1117-1142.
 * doi:10.1130/0016-7606(1952)63[1117:HAAOET]2.0.CO;2
 * Horton, R.E. (1945). Erosional development of streams and their drainage basins;
 * hydrophysical approach to quantitative morphology. GSA Bulletin 56(3):275-370.
 * doi:10.1130/0016-7606(1945)56[275:EDOSAT]2.0.CO;2
 * Strahler, A.N. (1957). Quantitative analysis of watershed geomorphology. Transactions,
 * American Geophysical Union 38(6):913-920. doi:10.1029/TR038i006p00913
 * Hack, J.T. (1957). Studies of longitudinal stream profiles in Virginia and Maryland. USGS
 * Professional Paper 294-B. doi:10.3133/pp294B
 * Pike, R.J., Wilson, S.E. (1971). Elevation-relief ratio, hypsometric integral, and
 * geomorphic area-altitude analysis. GSA Bulletin 82(4):1079-1084.
 * doi:10.1130/0016-7606(1971)82[1079:ERHIAG]2.0.CO;2
 */
#ifndef terroir_hydrology_Morphometry_h
#define terroir_hydrology_Morphometry_h

#include "GridView.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace terroir
{
namespace hydrology
{

/// Full citations of the statistics, for logs.
extern const char* const kMorphometryCitations;

/// The parameters of Morphometry (one default for every DEM).
struct MorphometryParams
{
  double channelArea = 1.0e5;    ///< contributing area of a channel cell, m^2 (> 0)
  double depressionDepth = 1e-3; ///< depth of a closed-depression cell, m (>= 0)
  double slopeBinWidth = 5.0;    ///< width of the slope histogram's bins, degrees (> 0)
};

/// One Strahler order of the channel network.
struct HortonOrderRow
{
  int order = 0;            ///< w (1 = headwater streams)
  long long streams = 0;    ///< N_w
  double totalLength = 0.0; ///< sum of the order-w cells' D8 steps, m
  double meanLength = 0.0;  ///< totalLength / N_w, m
};

/// A least-squares line y = intercept + slope x.
struct LineFit
{
  double slope = 0.0;
  double intercept = 0.0;
  std::size_t points = 0;
};

/// Every statistic of Morphometry (see the file comment for the definitions).
struct MorphometryReport
{
  std::size_t validCells = 0;
  double validArea = 0.0;                                             ///< m^2
  double minElevation = 0.0, maxElevation = 0.0, meanElevation = 0.0; ///< m
  double hypsometricIntegral = 0.0;

  double slopeMean = 0.0, slopeMedian = 0.0, slopeP10 = 0.0, slopeP90 = 0.0; ///< degrees
  double slopeBinWidth = 5.0;                                                ///< degrees
  std::vector<long long> slopeHistogram; ///< cells per bin, ceil(90 / width) bins

  std::size_t depressionCells = 0;
  double depressionShare = 0.0;  ///< depressionCells / validCells
  double depressionVolume = 0.0; ///< m^3

  double channelArea = 0.0; ///< the threshold used, m^2
  std::size_t channelCells = 0;
  double channelLength = 0.0;                    ///< m
  double drainageDensity = 0.0;                  ///< km / km^2
  std::vector<HortonOrderRow> orders;            ///< orders 1 .. Omega
  int hortonFirstOrder = 0, hortonLastOrder = 0; ///< orders of the two fits (0 when none)
  double bifurcationRatio = 0.0;                 ///< R_b (NaN when fewer than two orders fit)
  double lengthRatio = 0.0;                      ///< R_l
  double hackExponent = 0.0;                     ///< h
  double hackCoefficient = 0.0;                  ///< C, L in km and A in km^2
  std::size_t hackPoints = 0;
};

/// Per-cell outputs of Morphometry, each nx*ny values or null.
struct MorphometryCells
{
  const float* slope = nullptr;          ///< in: Horn slope in degrees, or null to compute it
  float* depressionDepth = nullptr;      ///< out: W - z, m (NaN no data)
  std::uint8_t* strahlerOrder = nullptr; ///< out: order of channel cells, 0 elsewhere
  float* flowLength = nullptr;           ///< out: longest flow path to the cell, m (NaN no data)
  double* contributingArea = nullptr;    ///< out: D8 contributing area, m^2 (NaN no data)
};

/**
 * @brief The channel network of D8 directions: Strahler orders, the Horton table, channel
 *        length, longest flow paths and Hack's fit (see the file comment).
 * @param[in] view       grid size, spacing and validity (data unused beyond validity)
 * @param[in] direction  nx*ny D8 codes (FlowAccumulation.h)
 * @param[in] area       nx*ny contributing areas in m^2 (NaN on no data)
 * @param[in] channelArea threshold A of a channel cell, m^2
 * @param[out] report    channelCells, channelLength, orders, Horton and Hack fields
 * @param[out] order     nx*ny Strahler orders (0 off the channels), or null
 * @param[out] flowLength nx*ny longest flow paths in m (NaN on no data), or null
 * @throw std::invalid_argument when the directions hold a cycle or leave the grid
 * @correctness Testing/Unit/TestMorphometry.cxx (hand-drawn tree, plane, Hack by construction)
 */
void ChannelNetworkStrahler1957(const GridView<float>& view,
  const std::int8_t* direction,
  const double* area,
  double channelArea,
  MorphometryReport& report,
  std::uint8_t* order,
  float* flowLength);

/// Least-squares line through (x, y); slope and intercept NaN with fewer than two distinct x.
LineFit FitLine(const std::vector<double>& x, const std::vector<double>& y);

/// R_b, R_l and the orders used, from report.orders (see the file comment).
void HortonRatios(MorphometryReport& report);

/**
 * @brief Every statistic of the file comment for one DEM.
 * @param[in] view   elevations (m), optional mask and per-row spacing
 * @param[in] params thresholds (validated by the caller: channelArea > 0, depressionDepth >= 0,
 *                   slopeBinWidth > 0)
 * @param[in,out] cells optional slope in, per-cell outputs
 * @param[in] progress optional, fraction done (0..1)
 * @pre nx, ny >= 2 (Horn's window)
 * @correctness Testing/Unit/TestMorphometry.cxx, Testing/Python/TestMorphometryGrass.py
 */
MorphometryReport Morphometry(const GridView<float>& view,
  const MorphometryParams& params,
  const MorphometryCells& cells = {},
  const std::function<void(double)>& progress = {});

} // namespace hydrology
} // namespace terroir

#endif

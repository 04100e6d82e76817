/**
 * @class   vtkTerroirMorphometry
 * @brief   Measures a terrain's landscape statistics: hypsometric integral, slope
 *          distribution, drainage density, Strahler orders with Horton's ratios, Hack's law
 *          and the share of cells in closed depressions.
 *
 * Input: a Terroir terrain (2-D vtkImageData, point array `Elevation` in metres, optional
 * `vtkValidPointMask`, spacing or per-row spacing `TerroirRowSpacing` in metres). Output: the
 * input's arrays plus, as point data,
 * - `StrahlerOrder` (vtkUnsignedCharArray): Strahler (1957) order of channel cells (D8
 *   contributing area >= ChannelArea), 0 elsewhere and on no data;
 * - `DepressionDepth` (float32, m): depression-filled surface minus elevation (0 outside
 *   closed depressions; NaN on no data);
 * - `FlowLength` (float32, m): length of the longest D8 flow path ending at the cell, from the
 *   drainage divide (Hack's main-stream length; NaN on no data);
 * and, as field data (one tuple each, double unless said): `HypsometricIntegral`,
 * `ElevationMin`/`ElevationMax`/`ElevationMean` (m), `SlopeMean`/`SlopeMedian`/`SlopeP10`/
 * `SlopeP90` (deg), `SlopeHistogram` (cells per SlopeBinWidth-degree bin, one tuple per bin,
 * vtkIdTypeArray), `SlopeBinWidth` (deg), `DrainageDensity` (km/km^2), `ChannelLength` (m),
 * `ChannelCells`, `ChannelArea` (m^2, the threshold), `ValidCells`, `ValidArea` (m^2),
 * `HortonStreamCount` (N_w, one tuple per order w = 1 .. Omega), `HortonMeanLength` and
 * `HortonTotalLength` (m, per order), `HortonOrdersFitted` (2 values: first and last order
 * of the fits, 0 0 when none), `BifurcationRatio`, `LengthRatio`, `HackExponent`,
 * `HackCoefficient` (L km = C (A km^2)^h), `HackPoints`, `DepressionShare`, `DepressionCells`,
 * `DepressionVolume` (m^3). Statistics that cannot be computed are NaN.
 *
 * Definitions (terroir::hydrology::Morphometry, Filters/Hydrology/Core/Morphometry.h, where
 * they are spelt out): HI = (mean - min)/(max - min); Horn (1981) slope; Priority-Flood
 * filling, D8 directions and contributing area (as vtkTerroirFlowAccumulation) with the map
 * edge and no-data holes draining out; drainage density = D8 channel length / valid area;
 * Horton ratios from the regression of log N_w and log mean L_w on w over orders 1 .. Omega-1
 * (the highest order, cut by the map edge, left out); Hack's h and C from the regression of
 * log L on log A over every channel cell; closed depression = filled - z > DepressionDepth.
 *
 * Whole extent (global filter). CPU only, sequential: a report of global sums and topological
 * sweeps along the flow paths (a few times the cost of a D8 flow accumulation, which has no
 * GPU path either); no kernel in it would repay a GPU. Backend Auto and CPU run the CPU path;
 * an explicit GPU request is an error, as for vtkTerroirFlowAccumulation. Errors (one line,
 * empty output): ChannelArea <= 0, DepressionDepth < 0 or SlopeBinWidth outside (0, 90], or
 * any of them not finite; a terrain smaller than 2 x 2 or without a cell with data.
 *
 * @par Correctness
 * Testing/Unit/TestMorphometry.cxx (tilted plane, pyramid, pit, hand-drawn D8 tree, Hack by
 * construction, no data), Testing/Pipeline/TestTerroirMorphometry.cxx (arrays, field data,
 * errors, the bundled DEM against independently computed statistics),
 * Testing/Python/TestMorphometry.py (the network re-implemented in Python),
 * Testing/Python/TestMorphometryGrass.py (GRASS r.univar, r.slope.aspect, r.watershed -s).
 *
 * @par References
 * Strahler, A.N. (1952). GSA Bulletin 63(11):1117-1142.
 * doi:10.1130/0016-7606(1952)63[1117:HAAOET]2.0.CO;2 Horton, R.E. (1945). GSA Bulletin
 * 56(3):275-370. doi:10.1130/0016-7606(1945)56[275:EDOSAT]2.0.CO;2 Strahler, A.N. (1957). Trans.
 * AGU 38(6):913-920. doi:10.1029/TR038i006p00913 Hack, J.T. (1957). USGS Professional Paper 294-B.
 * doi:10.3133/pp294B (full citations in Filters/Hydrology/Core/Morphometry.h)
 *
 * @sa vtkTerroirFlowAccumulation vtkTerroirSlope vtkTerroirImageAlgorithm
 */
#ifndef vtkTerroirMorphometry_h
#define vtkTerroirMorphometry_h

#include "vtkTerroirFiltersHydrologyModule.h" // For export macro
#include "vtkTerroirImageAlgorithm.h"

class VTKTERROIRFILTERSHYDROLOGY_EXPORT vtkTerroirMorphometry : public vtkTerroirImageAlgorithm
{
public:
  static vtkTerroirMorphometry* New();
  vtkTypeMacro(vtkTerroirMorphometry, vtkTerroirImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Output point-array names.
  static const char* StrahlerOrderName() { return "StrahlerOrder"; }
  static const char* DepressionDepthName() { return "DepressionDepth"; }
  static const char* FlowLengthName() { return "FlowLength"; }

  ///@{
  /// D8 contributing area from which a cell is a channel, m^2. Default 1e5 (0.1 km^2), the
  /// same for every DEM; must be > 0 and finite.
  vtkSetMacro(ChannelArea, double);
  vtkGetMacro(ChannelArea, double);
  ///@}

  ///@{
  /// Depth (filled minus original elevation) above which a cell lies in a closed depression,
  /// m. Default 0.001; must be >= 0 and finite.
  vtkSetMacro(DepressionDepth, double);
  vtkGetMacro(DepressionDepth, double);
  ///@}

  ///@{
  /// Width of the slope histogram's bins, degrees. Default 5; must be in (0, 90].
  vtkSetMacro(SlopeBinWidth, double);
  vtkGetMacro(SlopeBinWidth, double);
  ///@}

protected:
  vtkTerroirMorphometry();
  ~vtkTerroirMorphometry() override;

  int GetHaloWidth() override { return -1; }
  int GetMinimumGridSize() override { return 2; }
  bool HasGPUPath() override { return false; }
  double EstimateMemory(double nx, double ny) override;
  std::string CheckParameters() override;
#ifndef __VTK_WRAP__
  int RequestTerrainData(vtkImageData* input,
    const terroir::TerrainInput& terrain,
    vtkImageData* output) override;
#endif

  double ChannelArea = 1.0e5;
  double DepressionDepth = 1.0e-3;
  double SlopeBinWidth = 5.0;

private:
  vtkTerroirMorphometry(const vtkTerroirMorphometry&) = delete;
  void operator=(const vtkTerroirMorphometry&) = delete;
};

#endif

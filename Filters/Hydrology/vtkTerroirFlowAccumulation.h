/**
 * @class   vtkTerroirFlowAccumulation
 * @brief   Extracts streams the classic ways: fills depressions, routes flow downhill by D8,
 *          MFD or D-infinity and accumulates the contributing area (the baselines).
 *
 * Input: a Terroir terrain (2-D vtkImageData, point array `Elevation` in metres, optional
 * `vtkValidPointMask`, spacing or per-row spacing `TerroirRowSpacing` in metres). Output: the
 * input's arrays plus, as point data,
 * - `FilledElevation` (float32, m): the depression-filled surface W (no-data: NaN);
 * - `FlowDirection` (vtkSignedCharArray): D8 code 0..7 = E, NE, N, NW, W, SW, S, SE
 *   (counter-clockwise from east, north = +j), -1 = drains off the terrain (an edge cell, or a
 *   cell next to no data, with no lower neighbour inside), -2 = no data;
 * - `FlowAccumulation` (double, UNITS_LABEL "cells"): number of cells whose flow passes
 *   through the cell, the cell included (>= 1; NaN on no data); with MFD and D-infinity the
 *   fractions of cells that reach it;
 * - `ContributingArea` (double, m^2): the same sum over the cells' areas DxAt(j) * DyAt(j)
 *   (per-row spacing honoured; NaN on no data);
 * - `River` (vtkUnsignedCharArray): 1 where ContributingArea >= RiverThreshold, else 0
 *   (0 on no data);
 * - `ChannelInitiation` (double, m^2): the slope-area score A S^theta of Montgomery & Dietrich
 *   (1988), A = ContributingArea, S = tangent of the steepest descent of the unfilled terrain,
 *   floored at MinimumSlope (ChannelInitiationScore, MultipleFlow.h);
 * - `FlowAngle` (float, rad, counter-clockwise from east), with Method DInfinity only.
 * - `WeightedAccumulation` (double, m^3), only when WeightArrayName is set: the sum over the
 *   cell and its upstream cells of weight / 1000 * cell area, the weight being a water depth
 *   in mm (e.g. one month of `StandingWater`); a NaN weight counts as 0.
 *
 * Algorithm (terroir::hydrology, Filters/Hydrology/Core): the improved Priority-Flood of
 * Barnes et al. (2014) fills every depression to its spill level (PriorityFloodBarnes2014;
 * outlets are the edge cells and the cells next to no data); each cell then drains to the
 * neighbour of steepest descent on the filled surface, drop over distance (dx, dy or the
 * diagonal of its row), ties to the lowest code (D8FlowDirections, O'Callaghan & Mark 1984);
 * cells on flats (no lower neighbour: hydro-flattened lakes, filled depressions) drain to the
 * nearest neighbour one step closer, by breadth-first distance through the flat, to the
 * flat's draining cells (the "towards lower terrain" gradient of Garbrecht & Martz 1997 in
 * the form of Barnes, Lehman & Mulla 2014; flow crosses flats in parallel lines). Accumulation
 * is one topological sweep (D8FlowAccumulation): O(n), no recursion. Method MFD splits a cell's
 * flow among all its lower neighbours in proportion to slope^MFDExponent (Freeman 1991; with
 * MFDContourLength, times the contour length: Quinn et al. 1991; with MFDAdaptiveExponent, an
 * exponent per cell that grows with its slope: Qin et al. 2007), method DInfinity between the
 * two neighbours of the steepest triangular facet (Tarboton 1997); cells on flats follow their
 * D8 code in both (MultipleFlowAccumulation, DInfinityAccumulation in MultipleFlow.h).
 *
 * Whole extent (global filter). CPU only, sequential: flow accumulation is a topological
 * sweep along the flow paths; results cannot depend on the thread count. Distributed runs
 * (pvbatch or pvserver under mpirun, one piece per process): each process holds its piece and
 * 2 ghost layers; only piece perimeters travel. D8 (terroir::hydrology::
 * D8FlowAccumulationDistributed: Barnes 2016's parallel fill, the flats' distances relaxed
 * across pieces, Barnes 2017's perimeter graph for the sums): the filled surface, directions,
 * cell counts and River are the serial ones bit for bit; areas and weighted sums agree to
 * about 1e-15 relative (the order of the additions). MFD and DInfinity
 * (DispersiveFlowAccumulationDistributed: the same fill and directions, the sums in rounds of
 * inflow exchanged between the pieces until none changes): the filled surface, directions and
 * FlowAngle bit for bit, the sums to about 1e-15 relative. Backend Auto and CPU
 * run the CPU path; an explicit GPU request is an error (as for vtkTerroirFloodFill). Errors
 * (one line, empty output): RiverThreshold < 0 or not finite; MFDExponent <= 0, SlopeExponent
 * or MinimumSlope < 0, or one of them not finite; WeightArrayName naming no point
 * array of the input, or a non-numeric array, or WeightComponent out of its range.
 *
 * @par Correctness
 * Testing/Unit/TestFlowAccumulation.cxx (hand-computed grids: tilted planes, a V valley, a pit
 * filled and drained, a flat with one outlet, a no-data hole, per-row spacing; 40 random
 * terrains with every direction re-derived by brute force, no cycles, accumulations equal to
 * walking every path), Testing/Pipeline/TestTerroirFlowAccumulation.cxx (the Sagehen Creek
 * outlet drains the mapped 27.7 km^2 watershed; arrays, units, errors),
 * Testing/Pipeline/TestDeterminism.cxx, Testing/Python/TestFlowAccumulationGrass.py (flow
 * directions against GRASS r.watershed -s cell by cell, accumulation along the main stem).
 *
 * @par References
 * O'Callaghan, J.F., Mark, D.M. (1984). The extraction of drainage networks from digital
 * elevation data. Computer Vision, Graphics, and Image Processing 28(3):323-344.
 * doi:10.1016/S0734-189X(84)80011-0
 * Barnes, R., Lehman, C., Mulla, D. (2014). Priority-Flood: An optimal depression-filling and
 * watershed-labeling algorithm for digital elevation models. Computers & Geosciences
 * 62:117-127. doi:10.1016/j.cageo.2013.04.024
 * Barnes, R., Lehman, C., Mulla, D. (2014). An efficient assignment of drainage direction over
 * flat surfaces in raster digital elevation models. Computers & Geosciences 62:128-135.
 * doi:10.1016/j.cageo.2013.01.009
 * Garbrecht, J., Martz, L.W. (1997). The assignment of drainage direction over flat surfaces
 * in raster digital elevation models. Journal of Hydrology 193:204-213.
 * doi:10.1016/S0022-1694(96)03138-1
 * Freeman, T.G. (1991). Computers & Geosciences 17(3):413-422; Quinn, P. et al. (1991).
 * Hydrological Processes 5(1):59-79; Tarboton, D.G. (1997). Water Resources Research
 * 33(2):309-319; Montgomery, D.R., Dietrich, W.E. (1988). Nature 336:232-234 (full citations
 * in MultipleFlow.h).
 *
 * @sa vtkTerroirFloodFill vtkTerroirImageAlgorithm
 */
#ifndef vtkTerroirFlowAccumulation_h
#define vtkTerroirFlowAccumulation_h

#include "vtkTerroirFiltersHydrologyModule.h" // For export macro
#include "vtkTerroirImageAlgorithm.h"

class vtkDoubleArray;
class vtkFloatArray;
class vtkSignedCharArray;
namespace terroir
{
template<typename T>
struct GridView;
}

class VTKTERROIRFILTERSHYDROLOGY_EXPORT vtkTerroirFlowAccumulation : public vtkTerroirImageAlgorithm
{
public:
  static vtkTerroirFlowAccumulation* New();
  vtkTypeMacro(vtkTerroirFlowAccumulation, vtkTerroirImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Output point array names.
  static const char* FilledElevationName() { return "FilledElevation"; }
  static const char* FlowDirectionName() { return "FlowDirection"; }
  static const char* FlowAccumulationName() { return "FlowAccumulation"; }
  static const char* ContributingAreaName() { return "ContributingArea"; }
  static const char* RiverName() { return "River"; }
  static const char* WeightedAccumulationName() { return "WeightedAccumulation"; }
  static const char* ChannelInitiationName() { return "ChannelInitiation"; }
  static const char* FlowAngleName() { return "FlowAngle"; }
  ///@}

  /// Accumulation methods.
  enum MethodType
  {
    D8 = 0,       ///< steepest neighbour (O'Callaghan & Mark 1984)
    MFD = 1,      ///< all lower neighbours by slope^p (Freeman 1991, Quinn et al. 1991)
    DInfinity = 2 ///< steepest triangular facet, split by angle (Tarboton 1997)
  };
  /// "D8", "MFD", "DInfinity" ("unknown" otherwise).
  static const char* MethodName(int method);

  ///@{
  /// Accumulation method; default D8. FilledElevation and FlowDirection are D8's in every case.
  vtkSetClampMacro(Method, int, D8, DInfinity);
  vtkGetMacro(Method, int);
  void SetMethodToD8() { this->SetMethod(D8); }
  void SetMethodToMFD() { this->SetMethod(MFD); }
  void SetMethodToDInfinity() { this->SetMethod(DInfinity); }
  ///@}

  ///@{
  /// MFD's slope exponent p (default 1.1, Freeman 1991); must be finite and > 0.
  vtkSetMacro(MFDExponent, double);
  vtkGetMacro(MFDExponent, double);
  ///@}

  ///@{
  /// MFD shares times the contour length (Quinn et al. 1991); default off (Freeman 1991).
  vtkSetMacro(MFDContourLength, vtkTypeBool);
  vtkGetMacro(MFDContourLength, vtkTypeBool);
  vtkBooleanMacro(MFDContourLength, vtkTypeBool);
  ///@}

  ///@{
  /// MFD's exponent per cell from its steepest descent tan b: 1.1 + 8.9 min(tan b, 1) (MFD-md,
  /// Qin et al. 2007; MFDExponent unused); default off.
  vtkSetMacro(MFDAdaptiveExponent, vtkTypeBool);
  vtkGetMacro(MFDAdaptiveExponent, vtkTypeBool);
  vtkBooleanMacro(MFDAdaptiveExponent, vtkTypeBool);
  ///@}

  ///@{
  /// theta of the ChannelInitiation score A S^theta (default 1); finite, >= 0.
  vtkSetMacro(SlopeExponent, double);
  vtkGetMacro(SlopeExponent, double);
  ///@}

  ///@{
  /// Floor of S in the ChannelInitiation score (default 0.001); finite, >= 0.
  vtkSetMacro(MinimumSlope, double);
  vtkGetMacro(MinimumSlope, double);
  ///@}

  ///@{
  /**
   * Smallest contributing area of a river cell, m^2. Default 1e5 (0.1 km^2, 1000 cells of
   * 10 m); must be finite and >= 0 (0 marks every cell with data).
   */
  vtkSetMacro(RiverThreshold, double);
  vtkGetMacro(RiverThreshold, double);
  ///@}

  ///@{
  /**
   * Optional point array of water depth per cell, mm (for instance `StandingWater`): when set
   * (default none), the output gets `WeightedAccumulation`, m^3. Any numeric array type.
   */
  vtkSetStringMacro(WeightArrayName);
  vtkGetStringMacro(WeightArrayName);
  ///@}

  ///@{
  /// Component of the weight array used (default 0: January of a monthly array); >= 0.
  vtkSetClampMacro(WeightComponent, int, 0, VTK_INT_MAX);
  vtkGetMacro(WeightComponent, int);
  ///@}

protected:
  vtkTerroirFlowAccumulation();
  ~vtkTerroirFlowAccumulation() override;

  /// The whole extent, except in a distributed run: two ghost layers (one for the ring's
  /// directions, one for the slope of ChannelInitiation).
  int GetHaloWidth() override { return this->DistributedRequest ? 2 : -1; }
  bool HasGPUPath() override { return false; }
  double EstimateMemory(double nx, double ny) override;
  std::string CheckParameters() override;
#ifndef __VTK_WRAP__
  int RequestTerrainData(vtkImageData* input,
    const terroir::TerrainInput& terrain,
    vtkImageData* output) override;
#endif

  double RiverThreshold = 1e5;
  char* WeightArrayName = nullptr;
  int WeightComponent = 0;
  int Method = D8;
  double MFDExponent = 1.1;
  vtkTypeBool MFDContourLength = 0;
  vtkTypeBool MFDAdaptiveExponent = 0;
  double SlopeExponent = 1.0;
  double MinimumSlope = 1e-3;

private:
  /// A distributed run: fills the FilledElevation, FlowDirection, FlowAccumulation,
  /// ContributingArea, (with weights) WeightedAccumulation and (DInfinity) FlowAngle arrays of
  /// this piece.
  bool AccumulateInPieces(vtkImageData* input,
    const terroir::GridView<float>& view,
    const float* weight,
    vtkFloatArray* filled,
    vtkSignedCharArray* direction,
    vtkDoubleArray* cells,
    vtkDoubleArray* area,
    vtkDoubleArray* volume,
    vtkFloatArray* angle);

  vtkTerroirFlowAccumulation(const vtkTerroirFlowAccumulation&) = delete;
  void operator=(const vtkTerroirFlowAccumulation&) = delete;
};

#endif

/**
 * @class   vtkTerroirFeatureCurveTerrain
 * @brief   Terrain shaped by feature curves (Weiss 2015, section V): ridges, valleys and
 *          plateaus drawn as curves, the terrain between them found by a diffusion solver.
 *
 * Input port 0 (required): vtkPolyData whose lines or polylines are the curves, one control
 * point per line point (x, y in the output's world coordinates, metres), with point arrays
 * (all optional, 1 component; defaults in brackets):
 *   `Elevation` (m) [the point's z], `PlateauWidth` (m, across the curve, half on each side)
 *   [0], `SlopeLeft`, `SlopeRight` (degrees, > 0: the ground falls away from the curve, a
 *   ridge; < 0: it rises, a valley) [0], `SlopeLeftWidth`, `SlopeRightWidth` (m) [0],
 *   `EnvelopeLeft`, `EnvelopeRight` (m of smoothing beyond the slope, Weiss's l_l and l_r;
 *   < 0 unbounded) [-1], `ConstrainElevation` (0 leaves the plateau free) [1].
 * Left is the left of the direction of travel along the line.
 * Input port 1 (optional): a base terrain (2-D vtkImageData with `Elevation`, m): the output
 * takes its grid and arrays, and cells outside every curve's envelope keep its heights (the
 * bounded smoothing of Weiss's eq. 9). Without it the grid is Dimensions x Spacing from Origin
 * and the base is BaseElevation.
 *
 * Output: vtkImageData, point arrays `Elevation` (float32, m) and `FeatureKind` (uint8: 0
 * free, 1 plateau held at its elevation, 2 slope), plus the base's other arrays and field data.
 *
 * Parameters (defaults): Dimensions 512 x 512, Spacing 10 m, Origin (0, 0), BaseElevation 0 m,
 * PlateauWeight 0.9 and SlopeWeight 0.5 (Weiss's alpha and beta), Tolerance 1e-3 m (a V-cycle
 * that changes no height by more ends the solve), MaximumCycles 100, Backend Auto/CPU/GPU.
 *
 * Algorithm: Filters/Terrain/Core/FeatureCurves.h (Hermite curves, the constraints of eq. 5-9,
 * multigrid V(2,2) cycles with red-black Gauss-Seidel). CPU: vtkSMPTools over rows; GPU:
 * Shaders/FeatureCurveMultigrid.comp, the same operations in the same order (float64
 * heights): the GPU answer has the CPU's bits (Testing/GPU/TestFeatureCurveTerrainGPU.cxx).
 * Same input, same bits, on any number of threads. A run that does not reach the tolerance
 * within MaximumCycles warns and keeps its answer.
 *
 * @par Correctness
 * Testing/Unit/TestFeatureCurves.cxx (closed-form profiles, Jacobi reference),
 * Testing/Pipeline/TestTerroirFeatureCurveTerrain.cxx, Testing/GPU/TestFeatureCurveTerrainGPU.cxx.
 *
 * @par References
 * S. Weiss, "Procedural Terrain", CS6491 final project, Georgia Tech, 2015; H. Hnaidi et al.,
 * "Feature based terrain generation using diffusion equation", Computer Graphics Forum 29(7),
 * 2010.
 *
 * @sa vtkTerroirPolygonIslandSource
 */
#ifndef vtkTerroirFeatureCurveTerrain_h
#define vtkTerroirFeatureCurveTerrain_h

#include "vtkImageAlgorithm.h"
#include "vtkTerroirFiltersTerrainModule.h" // For export macro

#include <string> // For std::string

class vtkPolyData;

class VTKTERROIRFILTERSTERRAIN_EXPORT vtkTerroirFeatureCurveTerrain : public vtkImageAlgorithm
{
public:
  static vtkTerroirFeatureCurveTerrain* New();
  vtkTypeMacro(vtkTerroirFeatureCurveTerrain, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Output array names.
  static const char* ElevationName() { return "Elevation"; }
  static const char* FeatureKindName() { return "FeatureKind"; }

  /// The curves (port 0) and the optional base terrain (port 1).
  void SetCurvesData(vtkPolyData* curves);
  void SetBaseConnection(vtkAlgorithmOutput* base) { this->SetInputConnection(1, base); }
  void SetBaseData(vtkDataObject* base) { this->SetInputDataObject(1, base); }

  ///@{
  /// Grid points (nx, ny) without a base, each in [2, 65536]. Default 512 x 512.
  vtkSetVector2Macro(Dimensions, int);
  vtkGetVector2Macro(Dimensions, int);
  ///@}
  ///@{
  /// Cell size without a base, metres (> 0). Default 10.
  vtkSetMacro(Spacing, double);
  vtkGetMacro(Spacing, double);
  ///@}
  ///@{
  /// World coordinates of point (0, 0) without a base, metres. Default (0, 0).
  vtkSetVector2Macro(Origin, double);
  vtkGetVector2Macro(Origin, double);
  ///@}
  ///@{
  /// Height of the base without a base terrain, metres. Default 0.
  vtkSetMacro(BaseElevation, double);
  vtkGetMacro(BaseElevation, double);
  ///@}
  ///@{
  /// Weiss's alpha on plateaus, (0, 1]. Default 0.9.
  vtkSetClampMacro(PlateauWeight, double, 1e-6, 1.0);
  vtkGetMacro(PlateauWeight, double);
  ///@}
  ///@{
  /// Weiss's beta on slopes, [0, 1]. Default 0.5.
  vtkSetClampMacro(SlopeWeight, double, 0.0, 1.0);
  vtkGetMacro(SlopeWeight, double);
  ///@}
  ///@{
  /// The solve ends after a V-cycle that changes no height by more, metres (> 0). Default 1e-3.
  vtkSetMacro(Tolerance, double);
  vtkGetMacro(Tolerance, double);
  ///@}
  ///@{
  /// V-cycles at most, [1, 100000]. Default 100.
  vtkSetClampMacro(MaximumCycles, int, 1, 100000);
  vtkGetMacro(MaximumCycles, int);
  ///@}
  ///@{
  /// 0 Auto (default: TERROIR_BACKEND, else the GPU where it is verified faster), 1 CPU, 2 GPU.
  vtkSetClampMacro(Backend, int, 0, 2);
  vtkGetMacro(Backend, int);
  ///@}

  ///@{
  /// What the last run did: backend (1 CPU, 2 GPU, -1 none), V-cycles, multigrid levels, the
  /// last cycle's largest change and the final largest residual (m), and whether it converged.
  vtkGetMacro(LastBackend, int);
  vtkGetMacro(LastCycles, int);
  vtkGetMacro(LastLevels, int);
  vtkGetMacro(LastChange, double);
  vtkGetMacro(LastResidual, double);
  vtkGetMacro(LastConverged, bool);
  ///@}

  /// "" when the curves of `curves` (lines with the point arrays above) are usable, else one
  /// line naming the first bad curve and point ("curve 2, point 0: widths must not be
  /// negative"). RequestData refuses the same curves with the same words.
  static std::string CheckCurves(vtkPolyData* curves);

  /// The curves as the solver sees them, for drawing: each line of `curves` as its Hermite
  /// spline sampled within `flatness` metres (a polyline in `out`, z = the spline's elevation).
  static void SampleCurves(vtkPolyData* curves, double flatness, vtkPolyData* out);

  /// The last error as one line, or "" after a successful run.
  const char* GetErrorMessage() const { return this->ErrorMessage.c_str(); }

protected:
  vtkTerroirFeatureCurveTerrain();
  ~vtkTerroirFeatureCurveTerrain() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Dimensions[2] = { 512, 512 };
  double Spacing = 10.0;
  double Origin[2] = { 0.0, 0.0 };
  double BaseElevation = 0.0;
  double PlateauWeight = 0.9;
  double SlopeWeight = 0.5;
  double Tolerance = 1e-3;
  int MaximumCycles = 100;
  int Backend = 0;
  int LastBackend = -1;
  int LastCycles = 0;
  int LastLevels = 0;
  double LastChange = 0.0;
  double LastResidual = 0.0;
  bool LastConverged = false;
  std::string ErrorMessage;

private:
  vtkTerroirFeatureCurveTerrain(const vtkTerroirFeatureCurveTerrain&) = delete;
  void operator=(const vtkTerroirFeatureCurveTerrain&) = delete;
};

#endif

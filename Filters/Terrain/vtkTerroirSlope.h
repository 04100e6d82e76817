/**
 * @class   vtkTerroirSlope
 * @brief   Computes slope, aspect and surface normals of a terrain with Horn's (1981) method.
 *
 * Input: a Terroir terrain (2-D vtkImageData, point array `Elevation`, float32 or any other
 * numeric type, metres; optional `vtkValidPointMask`; georeference in field data, see
 * vtkTerroirGeoreference). Output: the input's arrays plus three float32 point arrays:
 * - `Slope`: degrees (UNITS_LABEL "deg", default) or percent ("%"), see SlopeUnits;
 * - `Aspect`: degrees clockwise from TRUE north (UNITS_LABEL "deg"), the direction the slope
 *   faces (downhill), in [0, 360): the grid aspect plus the meridian convergence gamma of
 *   `TerroirMeridianConvergence` (0 when absent). Flat cells (zero gradient) get NaN.
 * - `Normals`: 3 components (x, y, z), the unit surface normal of the surface
 *   z = ZFactor * elevation in the image's axes (x east / grid east, y north, z up), no units.
 *   It is NOT made the active point normals, because it describes the surface at vertical
 *   exaggeration 1 only; set it with `GetPointData()->SetActiveNormals("Normals")` if wanted.
 *
 * Method: Horn's 3x3 weighted differences, exactly as `gdaldem slope -compute_edges` (GDAL
 * 3.6): same edges (linear extrapolation beyond the border; clamped columns on the first and
 * last rows, hence gdaldem's corner values) and same no-data rule (a no-data neighbour is
 * replaced by the centre value; a no-data cell gives NaN). On geographic grids each row uses
 * its own metric cell size (`TerroirRowSpacing`). See terroir::terrain::SlopeHorn1981Rows.
 *
 * Streaming: halo of 1 cell. Backends: CPU (vtkSMPTools over row blocks, float32; results do
 * not depend on the thread count) and GPU (Shaders/Slope.comp, same arithmetic in float).
 *
 * @par Correctness
 * Testing/Unit/TestSlopeHorn1981.cxx, Testing/Pipeline/TestTerroirSlope.cxx,
 * Testing/Pipeline/TestTerroirSlopeGdaldem.cxx (every cell of the bundled DEM within 0.01 deg
 * of gdaldem; geographic vs UTM), Testing/GPU/TestSlopeGPU.cxx.
 *
 * @par References
 * Horn, B.K.P. (1981). Hill shading and the reflectance map. Proceedings of the IEEE
 * 69(1):14-47. doi:10.1109/PROC.1981.11918
 *
 * @sa vtkTerroirImageAlgorithm vtkImageGradient
 */
#ifndef vtkTerroirSlope_h
#define vtkTerroirSlope_h

#include "vtkTerroirFiltersTerrainModule.h" // For export macro
#include "vtkTerroirImageAlgorithm.h"

class VTKTERROIRFILTERSTERRAIN_EXPORT vtkTerroirSlope : public vtkTerroirImageAlgorithm
{
public:
  static vtkTerroirSlope* New();
  vtkTypeMacro(vtkTerroirSlope, vtkTerroirImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Output array names.
  static const char* SlopeName() { return "Slope"; }
  static const char* AspectName() { return "Aspect"; }
  static const char* NormalsName() { return "Normals"; }

  enum SlopeUnitsType
  {
    Degrees = 0,
    Percent = 1
  };

  ///@{
  /// Elevation multiplier (e.g. 0.3048 for feet to metres). Default 1; must be finite and > 0.
  vtkSetMacro(ZFactor, double);
  vtkGetMacro(ZFactor, double);
  ///@}

  ///@{
  /// Units of `Slope`: Degrees (0, default) or Percent (1, 100 * rise / run).
  vtkSetClampMacro(SlopeUnits, int, Degrees, Percent);
  vtkGetMacro(SlopeUnits, int);
  void SetSlopeUnitsToDegrees() { this->SetSlopeUnits(Degrees); }
  void SetSlopeUnitsToPercent() { this->SetSlopeUnits(Percent); }
  ///@}

  ///@{
  /// Which outputs to compute. All on by default.
  vtkSetMacro(ComputeAspect, bool);
  vtkGetMacro(ComputeAspect, bool);
  vtkBooleanMacro(ComputeAspect, bool);
  vtkSetMacro(ComputeNormals, bool);
  vtkGetMacro(ComputeNormals, bool);
  vtkBooleanMacro(ComputeNormals, bool);
  ///@}

protected:
  vtkTerroirSlope();
  ~vtkTerroirSlope() override;

  int GetHaloWidth() override { return 1; }
  int GetMinimumGridSize() override { return 2; }
  bool HasGPUPath() override { return true; }
  double EstimateMemory(double nx, double ny) override;
  std::string CheckParameters() override;
#ifndef __VTK_WRAP__
  int RequestTerrainData(vtkImageData* input,
    const terroir::TerrainInput& terrain,
    vtkImageData* output) override;
#endif

  double ZFactor = 1.0;
  int SlopeUnits = Degrees;
  bool ComputeAspect = true;
  bool ComputeNormals = true;

private:
  vtkTerroirSlope(const vtkTerroirSlope&) = delete;
  void operator=(const vtkTerroirSlope&) = delete;
};

#endif

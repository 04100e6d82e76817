/**
 * @class   vtkTerroirInfiltration
 * @brief   Builds the map of how fast the soil absorbs rain, from fill, slope-rule and paint
 *          operations applied in order.
 *
 * Input: a Terroir terrain (2-D vtkImageData, `Elevation` in metres, optional
 * `vtkValidPointMask`; optional point array `Slope` in degrees or %, as vtkTerroirSlope
 * writes it). Output: the input's arrays plus `InfiltrationRate`, float32, 1 component, mm/h
 * (UNITS_LABEL "mm/h"); NaN on no-data cells.
 *
 * Long (2016)'s three infiltration tools (Long (2016), §3.2), as an ordered list of
 * operations; every cell starts at 0 mm/h and each operation overwrites the cells it covers:
 * - `AddFill(rate)`: every cell;
 * - `AddSlopeRule(threshold)`: 0 where the slope exceeds `threshold` degrees (cliffs shed the
 *   rain). The slope is the input's `Slope` array when present (converted when its units are
 *   %), else it is computed here with Horn's method (as vtkTerroirSlope, z factor 1);
 * - paint: `AddPaintMask(image, rate)` (cells where the mask image's first point array is
 *   non-zero), `AddPaintMaskArray(name, rate)` (a mask array of the input itself, e.g. from
 *   vtkTerroirVectorRasterizer, which burns polygons of any OGR format onto the grid),
 *   `AddPaintStencil(stencil, rate)` (cells inside a vtkImageStencilData, in the terrain's
 *   index space), and the soil-type tools `AddSoilTypes(image)` / `AddSoilTypeArray(name)`
 *   (codes 1 sand, 2 sandy loam, 3 loam, 4 clay loam, 5 clay; any other code, NaN included,
 *   leaves a cell as it is) mapped through the FAO table of basic infiltration rates
 *   (SetSoilTypeRate overrides an entry).
 * With no operation the filter runs the default recipe: AddFill(15) (FAO loam, the mid-point
 * of 10-20 mm/h) then AddSlopeRule(30).
 * Mask and soil images must have the terrain's dimensions (resample them onto the DEM grid
 * first, e.g. with gdalwarp).
 *
 * Pointwise apart from the computed slope (halo 1); CPU only (every operation is a single
 * pass over memory).
 *
 * @par Correctness
 * Testing/Unit/TestSoilWater.cxx (slope rule, FAO table), Testing/Pipeline/
 * TestTerroirInfiltration.cxx (a plane of known slope, operation order, masks, stencils, soil
 * types, no data, errors), Testing/Python/TestTerrainPipeline.py.
 *
 * @par References
 * FAO Irrigation Water Management Training Manual 5 (Brouwer, Prins, Kay, Heibloem 1988),
 * Annex 2: basic infiltration rates sand > 30, sandy loam 20-30, loam 10-20, clay loam 5-10,
 * clay 1-5 mm/h (defaults: the mid-points; sand 30, its bound). Long (2016) (seed tools).
 *
 * @sa vtkTerroirSoilHumidity vtkTerroirSlope vtkTerroirVectorRasterizer
 */
#ifndef vtkTerroirInfiltration_h
#define vtkTerroirInfiltration_h

#include "vtkTerroirFiltersTerrainModule.h" // For export macro
#include "vtkTerroirImageAlgorithm.h"

class vtkImageData;
class vtkImageStencilData;

class VTKTERROIRFILTERSTERRAIN_EXPORT vtkTerroirInfiltration : public vtkTerroirImageAlgorithm
{
public:
  static vtkTerroirInfiltration* New();
  vtkTypeMacro(vtkTerroirInfiltration, vtkTerroirImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Output array name.
  static const char* InfiltrationRateName() { return "InfiltrationRate"; }

  /// Largest rate accepted by any operation, mm/h (1000; the fastest soils absorb ~250).
  static double GetMaximumRate() { return 1000.0; }

  ///@{
  /// Operations, applied in the order added (see the class comment). Rates in mm/h, in
  /// [0, 1000]; the slope threshold in degrees, in [0, 90]. Each call calls Modified().
  void AddFill(double rate);
  void AddSlopeRule(double thresholdDegrees);
  void AddPaintMask(vtkImageData* mask, double rate);
  void AddPaintMaskArray(const char* arrayName, double rate);
  void AddPaintStencil(vtkImageStencilData* stencil, double rate);
  void AddSoilTypes(vtkImageData* soilTypes);
  void AddSoilTypeArray(const char* arrayName);
  void RemoveAllOperations();
  int GetNumberOfOperations();
  ///@}

  /**
   * The default recipe with other numbers: RemoveAllOperations(), AddFill(rate),
   * AddSlopeRule(thresholdDegrees); one setter for ParaView's `FillAndSlopeRule` property.
   */
  void SetFillAndSlopeRule(double rate, double thresholdDegrees);

  ///@{
  /// Rate of soil type `code` (1..5), mm/h. Defaults: FAO mid-points 30, 25, 15, 7.5, 3.
  void SetSoilTypeRate(int code, double rate);
  double GetSoilTypeRate(int code);
  ///@}

  /// Includes the MTime of the mask images and stencils.
  vtkMTimeType GetMTime() override;

protected:
  vtkTerroirInfiltration();
  ~vtkTerroirInfiltration() override;

  int GetHaloWidth() override { return 1; }
  double EstimateMemory(double nx, double ny) override;
  std::string CheckParameters() override;
#ifndef __VTK_WRAP__
  int RequestTerrainData(vtkImageData* input,
    const terroir::TerrainInput& terrain,
    vtkImageData* output) override;
#endif

  double SoilTypeRates[5] = { 30.0, 25.0, 15.0, 7.5, 3.0 };

private:
  vtkTerroirInfiltration(const vtkTerroirInfiltration&) = delete;
  void operator=(const vtkTerroirInfiltration&) = delete;

  struct Internals;
  Internals* Impl;
};

#endif

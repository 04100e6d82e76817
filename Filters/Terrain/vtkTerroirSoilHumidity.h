/**
 * @class   vtkTerroirSoilHumidity
 * @brief   Computes the rain the soil absorbs each month, its moving weighted average, and the
 *          water left standing on the surface.
 *
 * Input: a Terroir terrain with the point array `InfiltrationRate` (mm/h, 1 component, as
 * vtkTerroirInfiltration writes it; chosen with SetInputArrayToProcess(1, ...)). Output: the
 * input's arrays plus three float32 arrays of 12 components named Jan ... Dec, mm
 * (UNITS_LABEL "mm"), NaN on no-data cells (invalid elevation or NaN rate):
 * - `SoilHumidity`: S_h(m) = min(S_ir / R_i(m), 1) R_q(m), Long (2016)'s equation 3.5, capped
 *   so that the soil never absorbs more rain than falls;
 * - `WeightedSoilHumidity`: S_wh(m) = S_h(m)/2 + S_h(m-1)/3 + S_h(m-2)/6, December and
 *   November before January;
 * - `StandingWater`: R_q(m) - S_h(m), the input of the water-flow simulation.
 * Field data `Precipitation` (mm) and `PrecipitationIntensity` (mm/h), 12 tuples each, record
 * the climate used.
 *
 * Climate: `Precipitation` R_q (12 values, mm per month, January first, >= 0) and
 * `PrecipitationIntensity` R_i (12 values, mm/h, > 0 where R_q > 0); a climate file is read
 * by vtkTerroirClimateReader (Terroir::IO), whose values are set here. Defaults: an illustrative
 * temperate (Köppen Cfb) year of 715 mm, 50-65 mm a month, falling at 2 mm/h in winter
 * (frontal rain) to 6 mm/h in July (showers).
 *
 * Pointwise (halo 0). Backends: CPU (vtkSMPTools, float32) and GPU
 * (Shaders/SoilHumidity.comp), the same float operations in the same order.
 *
 * @par Correctness
 * Testing/Unit/TestSoilWater.cxx, Testing/Pipeline/TestTerroirSoilHumidity.cxx,
 * Testing/GPU/TestSoilHumidityGPU.cxx, Testing/Python/TestTerrainPipeline.py.
 *
 * @par References
 * Long (2016), §3.2 (seed soil-water model, equation 3.5 and the weighted average).
 *
 * @sa vtkTerroirInfiltration terroir::terrain::SoilHumidityLong2016
 */
#ifndef vtkTerroirSoilHumidity_h
#define vtkTerroirSoilHumidity_h

#include "vtkTerroirFiltersTerrainModule.h" // For export macro
#include "vtkTerroirImageAlgorithm.h"

class VTKTERROIRFILTERSTERRAIN_EXPORT vtkTerroirSoilHumidity : public vtkTerroirImageAlgorithm
{
public:
  static vtkTerroirSoilHumidity* New();
  vtkTypeMacro(vtkTerroirSoilHumidity, vtkTerroirImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Output array names.
  static const char* SoilHumidityName() { return "SoilHumidity"; }
  static const char* WeightedSoilHumidityName() { return "WeightedSoilHumidity"; }
  static const char* StandingWaterName() { return "StandingWater"; }
  ///@}

  ///@{
  /// Monthly precipitation quantity R_q, mm, January first, each in [0, 10000].
  /// Default 60 50 55 55 65 60 60 60 55 65 65 65.
  vtkSetVectorMacro(Precipitation, double, 12);
  vtkGetVectorMacro(Precipitation, double, 12);
  /// One month (0 = January), for ParaView's Precipitation property.
  void SetMonthlyPrecipitation(int month, double value)
  {
    this->SetMonthValue(this->Precipitation, month, value);
  }
  ///@}

  ///@{
  /// Monthly mean precipitation intensity R_i, mm/h, January first, each in [0, 500] and > 0
  /// where R_q > 0. Default 2 2 2.5 3 4 5 6 5 4 3 2.5 2.
  vtkSetVectorMacro(PrecipitationIntensity, double, 12);
  vtkGetVectorMacro(PrecipitationIntensity, double, 12);
  /// One month (0 = January), for ParaView's PrecipitationIntensity property.
  void SetMonthlyPrecipitationIntensity(int month, double value)
  {
    this->SetMonthValue(this->PrecipitationIntensity, month, value);
  }
  ///@}

  ///@{
  ///@}

  ///@{
  /// Which outputs to make; all on by default (SoilHumidity is always made).
  vtkSetMacro(ComputeWeightedSoilHumidity, bool);
  vtkGetMacro(ComputeWeightedSoilHumidity, bool);
  vtkBooleanMacro(ComputeWeightedSoilHumidity, bool);
  vtkSetMacro(ComputeStandingWater, bool);
  vtkGetMacro(ComputeStandingWater, bool);
  vtkBooleanMacro(ComputeStandingWater, bool);
  ///@}

protected:
  vtkTerroirSoilHumidity();
  ~vtkTerroirSoilHumidity() override;

  int GetHaloWidth() override { return 0; }
  bool HasGPUPath() override { return true; }
  double EstimateMemory(double nx, double ny) override;
  std::string CheckParameters() override;
#ifndef __VTK_WRAP__
  int RequestTerrainData(vtkImageData* input,
    const terroir::TerrainInput& terrain,
    vtkImageData* output) override;
#endif

  double Precipitation[12] = { 60, 50, 55, 55, 65, 60, 60, 60, 55, 65, 65, 65 };
  double PrecipitationIntensity[12] = { 2, 2, 2.5, 3, 4, 5, 6, 5, 4, 3, 2.5, 2 };
  bool ComputeWeightedSoilHumidity = true;
  bool ComputeStandingWater = true;

private:
  vtkTerroirSoilHumidity(const vtkTerroirSoilHumidity&) = delete;
  void operator=(const vtkTerroirSoilHumidity&) = delete;
};

#endif

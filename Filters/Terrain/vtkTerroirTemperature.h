/**
 * @class   vtkTerroirTemperature
 * @brief   Computes the monthly air temperature of every cell from its elevation.
 *
 * Input: a Terroir terrain (2-D vtkImageData, point array `Elevation` in metres, optional
 * `vtkValidPointMask`, georeference in field data). Output: the input's arrays plus
 * `Temperature`, float32, 12 components named Jan ... Dec, °C (UNITS_LABEL "degC");
 * no-data cells get NaN.
 *
 * Model (Long (2016), section 3.2.2, eq. 3.4): a sea-level temperature per
 * month, lowered by a constant lapse rate,
 *   T(month, h) = T_sea(month) - LapseRate * h / 1000.
 * T_sea comes either from the 12 values of SetMonthlySeaLevelTemperatures (when
 * UseMonthlyTemperatures is on, calendar months, January first) or from the sea-level
 * temperatures of the coldest and warmest months, interpolated linearly around the year
 * (coldest -> warmest -> coldest; see terroir::terrain::SeaLevelTemperaturesFromExtremes).
 * ColdestMonth / WarmestMonth 0 (the default) mean "by hemisphere": January / July in the
 * north, July / January in the south. Hemisphere Auto takes the sign of the centre latitude
 * (`TerroirCenterLatLon`), north when the terrain has none.
 *
 * Pointwise (halo 0). Backends: CPU (vtkSMPTools, float32) and GPU (Shaders/Temperature.comp).
 *
 * @par Correctness
 * Testing/Unit/TestTemperatureLapseRate.cxx, Testing/Pipeline/TestTerroirTemperature.cxx,
 * Testing/GPU/TestTemperatureGPU.cxx.
 *
 * @par References
 * Long (2016) (seed temperature model, as cited by the Terroir issue). Lapse rate: 6.4 °C/km
 * by default, close to the 6.5 K/km of the ICAO standard atmosphere (ISO 2533:1975).
 *
 * @sa vtkTerroirImageAlgorithm vtkTerroirSlope
 */
#ifndef vtkTerroirTemperature_h
#define vtkTerroirTemperature_h

#include "vtkTerroirFiltersTerrainModule.h" // For export macro
#include "vtkTerroirImageAlgorithm.h"

class VTKTERROIRFILTERSTERRAIN_EXPORT vtkTerroirTemperature : public vtkTerroirImageAlgorithm
{
public:
  static vtkTerroirTemperature* New();
  vtkTypeMacro(vtkTerroirTemperature, vtkTerroirImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Output array name.
  static const char* TemperatureName() { return "Temperature"; }
  /// Component names of monthly arrays: "Jan" ... "Dec" for month 0..11 (nullptr otherwise).
  static const char* GetMonthName(int month);

  enum HemisphereType
  {
    AutoHemisphere = 0,
    North = 1,
    South = 2
  };

  ///@{
  /// Sea-level temperature of the coldest month, °C. Default 2. Every sea-level temperature must
  /// lie in [-90, 60] °C (the records are -89.2 and 56.7), the coldest not above the warmest.
  vtkSetMacro(SeaLevelTemperatureColdest, double);
  vtkGetMacro(SeaLevelTemperatureColdest, double);
  ///@}

  ///@{
  /// Sea-level temperature of the warmest month, °C. Default 20.
  vtkSetMacro(SeaLevelTemperatureWarmest, double);
  vtkGetMacro(SeaLevelTemperatureWarmest, double);
  ///@}

  ///@{
  /// Coldest / warmest month, 1 (January) .. 12, or 0 (default) for the hemisphere's
  /// (January / July in the north, July / January in the south). They must differ.
  vtkSetClampMacro(ColdestMonth, int, 0, 12);
  vtkGetMacro(ColdestMonth, int);
  vtkSetClampMacro(WarmestMonth, int, 0, 12);
  vtkGetMacro(WarmestMonth, int);
  ///@}

  ///@{
  /// AutoHemisphere (0, default: sign of the centre latitude, north when unknown), North (1), South
  /// (2).
  vtkSetClampMacro(Hemisphere, int, AutoHemisphere, South);
  vtkGetMacro(Hemisphere, int);
  void SetHemisphereToAuto() { this->SetHemisphere(AutoHemisphere); }
  void SetHemisphereToNorth() { this->SetHemisphere(North); }
  void SetHemisphereToSouth() { this->SetHemisphere(South); }
  ///@}

  ///@{
  /// Temperature decrease with height, °C per km. Default 6.4; must lie in [0, 20].
  vtkSetMacro(LapseRate, double);
  vtkGetMacro(LapseRate, double);
  ///@}

  ///@{
  /// Twelve sea-level temperatures, °C, January first, used when UseMonthlyTemperatures is on.
  /// Default: the values the coldest/warmest defaults give in the north (2, 5, ..., 20, ..., 5).
  vtkSetVectorMacro(MonthlySeaLevelTemperatures, double, 12);
  vtkGetVectorMacro(MonthlySeaLevelTemperatures, double, 12);
  /// One of them (month 0 = January), for ParaView's MonthlySeaLevelTemperatures property.
  void SetMonthlySeaLevelTemperature(int month, double value)
  {
    this->SetMonthValue(this->MonthlySeaLevelTemperatures, month, value);
  }
  ///@}

  ///@{
  /// Use the 12 given sea-level temperatures instead of coldest/warmest. Default off.
  vtkSetMacro(UseMonthlyTemperatures, bool);
  vtkGetMacro(UseMonthlyTemperatures, bool);
  vtkBooleanMacro(UseMonthlyTemperatures, bool);
  ///@}

  /// Hemisphere used by the last run (North or South; AutoHemisphere before the first run).
  vtkGetMacro(LastHemisphere, int);

  /**
   * The 12 sea-level temperatures the filter would use for a terrain in the given hemisphere
   * (North or South); returns false when ColdestMonth equals WarmestMonth.
   */
  bool ComputeSeaLevelTemperatures(int hemisphere, double monthly[12]);

protected:
  vtkTerroirTemperature();
  ~vtkTerroirTemperature() override;

  int GetHaloWidth() override { return 0; }
  bool HasGPUPath() override { return true; }
  double EstimateMemory(double nx, double ny) override;
  std::string CheckParameters() override;
#ifndef __VTK_WRAP__
  int RequestTerrainData(vtkImageData* input,
    const terroir::TerrainInput& terrain,
    vtkImageData* output) override;
#endif

  double SeaLevelTemperatureColdest = 2.0;
  double SeaLevelTemperatureWarmest = 20.0;
  int ColdestMonth = 0;
  int WarmestMonth = 0;
  int Hemisphere = AutoHemisphere;
  double LapseRate = 6.4;
  double MonthlySeaLevelTemperatures[12] = { 2, 5, 8, 11, 14, 17, 20, 17, 14, 11, 8, 5 };
  bool UseMonthlyTemperatures = false;
  int LastHemisphere = AutoHemisphere;

private:
  vtkTerroirTemperature(const vtkTerroirTemperature&) = delete;
  void operator=(const vtkTerroirTemperature&) = delete;
};

#endif

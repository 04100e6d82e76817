/**
 * @class   vtkTerroirClimateReader
 * @brief   Reads a climate table (CSV or JSON, Documentation/IO/ClimateFile.md) into twelve
 *          monthly values per quantity, for the filters that take a climate.
 *
 * The filters take parsed values (vtkTerroirSoilHumidity::SetPrecipitation and
 * SetPrecipitationIntensity, vtkTerroirTemperature::SetMonthlySeaLevelTemperatures); reading
 * the file is this class's job (parsing: terroir::io::ReadClimateTableFile, IO/Core).
 *
 * Output (after a successful Read(), January first): `Precipitation` (mm per month),
 * `PrecipitationIntensity` (mm/h) and `Temperature` (sea-level °C), each with Has...() telling
 * whether the file had the column; absent columns read as 0.
 *
 * Read() returns false with one error line "<file>: <problem>" (GetErrorMessage(), and
 * vtkErrorMacro): no such file, not a regular file, over 1 MiB, a missing month, an unknown
 * column, a value that is not finite or out of range.
 *
 * @par Correctness
 * TerroirClimateTable.* unit tests (the parser), TerroirClimateReader.* (this class), the
 * ClimateTable fuzz harness.
 *
 * @sa vtkTerroirSoilHumidity vtkTerroirTemperature
 */
#ifndef vtkTerroirClimateReader_h
#define vtkTerroirClimateReader_h

#include "vtkObject.h"
#include "vtkTerroirIOModule.h" // For export macro

#include <string> // For std::string

class VTKTERROIRIO_EXPORT vtkTerroirClimateReader : public vtkObject
{
public:
  static vtkTerroirClimateReader* New();
  vtkTypeMacro(vtkTerroirClimateReader, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The climate table to read (CSV or JSON). Default: none.
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  ///@}

  /// Reads the file; false (GetErrorMessage(), one line naming the file) on failure, and every
  /// value is then 0 and every Has...() false.
  bool Read();

  /// The last error as one line "<file>: <problem>", or "" after a successful read.
  const char* GetErrorMessage() const { return this->ErrorMessage.c_str(); }

  ///@{
  /// Whether the file had the column, and its twelve values (January first).
  bool HasPrecipitation() const { return this->HavePrecipitation; }
  bool HasPrecipitationIntensity() const { return this->HaveIntensity; }
  bool HasTemperature() const { return this->HaveTemperature; }
  vtkGetVectorMacro(Precipitation, double, 12);
  vtkGetVectorMacro(PrecipitationIntensity, double, 12);
  vtkGetVectorMacro(Temperature, double, 12);
  ///@}

protected:
  vtkTerroirClimateReader();
  ~vtkTerroirClimateReader() override;

  char* FileName = nullptr;
  std::string ErrorMessage;
  bool HavePrecipitation = false;
  bool HaveIntensity = false;
  bool HaveTemperature = false;
  double Precipitation[12] = {};
  double PrecipitationIntensity[12] = {};
  double Temperature[12] = {};

private:
  vtkTerroirClimateReader(const vtkTerroirClimateReader&) = delete;
  void operator=(const vtkTerroirClimateReader&) = delete;
};

#endif

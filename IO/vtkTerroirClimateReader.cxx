#include "vtkTerroirClimateReader.h"

#include "vtkObjectFactory.h"

#include "ClimateTable.h"

#include <algorithm>

vtkStandardNewMacro(vtkTerroirClimateReader);

//------------------------------------------------------------------------------
vtkTerroirClimateReader::vtkTerroirClimateReader() = default;

//------------------------------------------------------------------------------
vtkTerroirClimateReader::~vtkTerroirClimateReader()
{
  this->SetFileName(nullptr);
}

//------------------------------------------------------------------------------
void vtkTerroirClimateReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "Precipitation: " << (this->HavePrecipitation ? "yes" : "no")
     << ", PrecipitationIntensity: " << (this->HaveIntensity ? "yes" : "no")
     << ", Temperature: " << (this->HaveTemperature ? "yes" : "no") << "\n";
}

//------------------------------------------------------------------------------
bool vtkTerroirClimateReader::Read()
{
  terroir::io::ClimateTable table;
  std::string error;
  const bool ok = this->FileName && *this->FileName
    ? terroir::io::ReadClimateTableFile(this->FileName, table, error)
    : (error = "vtkTerroirClimateReader: no file name set", false);
  if (!ok)
  {
    table = terroir::io::ClimateTable();
  }
  this->ErrorMessage = error;
  this->HavePrecipitation = table.hasPrecipitation;
  this->HaveIntensity = table.hasIntensity;
  this->HaveTemperature = table.hasTemperature;
  std::copy(table.precipitationMm.begin(), table.precipitationMm.end(), this->Precipitation);
  std::copy(
    table.intensityMmPerHour.begin(), table.intensityMmPerHour.end(), this->PrecipitationIntensity);
  std::copy(table.temperatureC.begin(), table.temperatureC.end(), this->Temperature);
  this->Modified();
  if (!ok)
  {
    vtkErrorMacro(<< this->ErrorMessage);
  }
  return ok;
}

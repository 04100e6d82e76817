// `terroir temperature`: monthly temperature from elevation (12 bands)
#include "TerroirCommands.h"

#include "TerroirApp.h"
#include "TerroirCommandSupport.h"

#include "vtkImageData.h"
#include "vtkNew.h"

#include "vtkTerroirTemperature.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

using json = nlohmann::json;

namespace terroir
{
namespace app
{
namespace
{
int Temperature(const std::string& in,
  const std::string& outPath,
  bool overwrite,
  const std::string& backendName,
  bool allowNetwork,
  const std::string& zUnit,
  const terroir::app::TemperatureSettings& opts)
{
  const int backend = ParseBackend(backendName);
  terroir::app::CheckWritable({ outPath }, overwrite);
  vtkSmartPointer<vtkImageData> terrain = terroir::app::ReadTerrain(in, allowNetwork, zUnit);
  vtkNew<vtkTerroirTemperature> temperature;
  temperature->SetBackend(backend);
  ApplyTemperature(opts, temperature);
  json stages;
  vtkSmartPointer<vtkImageData> result =
    RunStage(temperature.Get(), terrain, "temperature", stages);
  WriteStageResult(result, "Temperature", outPath, overwrite);
  return 0;
}
} // namespace

int CommandTemperature(const CommandLine& c)
{
  return Temperature(
    c.Input, c.Output, c.Overwrite, c.Backend, c.AllowNetwork, c.ZUnit, c.Temperature);
}

} // namespace app
} // namespace terroir

// `terroir illumination`: cast shadows, hours of sun and insolation (instant, daily, monthly)
#include "TerroirCommands.h"

#include "TerroirApp.h"
#include "TerroirCommandSupport.h"

#include "vtkImageData.h"
#include "vtkNew.h"

#include "vtkTerroirSolarIllumination.h"

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
int Illumination(const std::string& in,
  const std::string& outPath,
  bool overwrite,
  const std::string& backendName,
  bool allowNetwork,
  const std::string& zUnit,
  const terroir::app::IlluminationSettings& opts)
{
  const int backend = ParseBackend(backendName);
  std::vector<std::string> outs = { outPath };
  for (const std::string* extra : { &opts.InsolationOutput, &opts.IncidenceOutput })
  {
    if (!extra->empty())
    {
      outs.push_back(*extra);
    }
  }
  terroir::app::CheckWritable(outs, overwrite);
  vtkSmartPointer<vtkImageData> terrain = terroir::app::ReadTerrain(in, allowNetwork, zUnit);
  vtkNew<vtkTerroirSolarIllumination> illumination;
  illumination->SetBackend(backend);
  ApplyIllumination(opts, illumination);
  json stages;
  vtkSmartPointer<vtkImageData> result =
    RunStage(illumination.Get(), terrain, "illumination", stages);
  // A .tif gets the lit/shadow mask (instant) or the hours of sun (1 or 12 bands); .vti all.
  const bool instant = opts.Mode == "instant";
  WriteStageResult(result,
    instant ? vtkTerroirSolarIllumination::IlluminatedName()
            : vtkTerroirSolarIllumination::IlluminationHoursName(),
    outPath,
    overwrite);
  if (!opts.InsolationOutput.empty())
  {
    WriteStageResult(
      result, vtkTerroirSolarIllumination::InsolationName(), opts.InsolationOutput, overwrite);
  }
  if (!opts.IncidenceOutput.empty())
  {
    WriteStageResult(
      result, vtkTerroirSolarIllumination::SunIncidenceName(), opts.IncidenceOutput, overwrite);
  }
  return 0;
}
} // namespace

int CommandIllumination(const CommandLine& c)
{
  return Illumination(
    c.Input, c.Output, c.Overwrite, c.Backend, c.AllowNetwork, c.ZUnit, c.Illumination);
}

} // namespace app
} // namespace terroir

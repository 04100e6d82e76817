// `terroir slope`: Horn slope (and aspect), like gdaldem slope
#include "TerroirCommands.h"

#include "TerroirApp.h"
#include "TerroirCommandSupport.h"

#include "vtkImageData.h"
#include "vtkNew.h"

#include "vtkTerroirSlope.h"

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
/// Writes a single-stage result: GeoTIFF of `array` for .tif/.tiff, every array for .vti.
int Slope(const std::string& in,
  const std::string& outPath,
  bool overwrite,
  const std::string& backendName,
  double zFactor,
  bool percent,
  const std::string& aspectPath,
  bool allowNetwork,
  const std::string& zUnit)
{
  const int backend = ParseBackend(backendName);
  std::vector<std::string> outs = { outPath };
  if (!aspectPath.empty())
  {
    outs.push_back(aspectPath);
  }
  terroir::app::CheckWritable(outs, overwrite);
  vtkSmartPointer<vtkImageData> terrain = terroir::app::ReadTerrain(in, allowNetwork, zUnit);
  vtkNew<vtkTerroirSlope> slope;
  slope->SetBackend(backend);
  slope->SetZFactor(zFactor);
  // Only what is written: a .tif gets Slope (and Aspect when asked); a .vti gets everything.
  const bool everything = terroir::app::HasExtension(outPath, ".vti");
  slope->SetComputeAspect(everything || !aspectPath.empty());
  slope->SetComputeNormals(everything);
  if (percent)
  {
    slope->SetSlopeUnitsToPercent();
  }
  json stages;
  vtkSmartPointer<vtkImageData> result = RunStage(slope.Get(), terrain, "slope", stages);
  WriteStageResult(result, "Slope", outPath, overwrite);
  if (!aspectPath.empty())
  {
    WriteStageResult(result, "Aspect", aspectPath, overwrite);
  }
  return 0;
}
} // namespace

int CommandSlope(const CommandLine& c)
{
  return Slope(c.Input,
    c.Output,
    c.Overwrite,
    c.Backend,
    c.ZFactor,
    c.Percent,
    c.AspectOutput,
    c.AllowNetwork,
    c.ZUnit);
}

} // namespace app
} // namespace terroir

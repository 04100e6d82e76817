// `terroir fractal`: a seeded synthetic DEM (GeoTIFF or .vti)
#include "TerroirCommands.h"

#include "TerroirApp.h"
#include "TerroirCommandSupport.h"

#include "vtkImageData.h"
#include "vtkNew.h"

#include "vtkTerroirFractalTerrainSource.h"

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
int Fractal(const std::string& outPath, int size, int seed, double spacing, bool overwrite)
{
  terroir::app::CheckWritable({ outPath }, overwrite);
  vtkNew<vtkTerroirFractalTerrainSource> source;
  source->SetDimensions(size, size);
  source->SetSeed(seed);
  source->SetSpacing(spacing);
  terroir::app::WatchProgress(source, "fractal");
  terroir::app::UpdateOrThrow(source, "fractal terrain");
  WriteStageResult(source->GetOutput(), "Elevation", outPath, overwrite);
  return 0;
}
} // namespace

int CommandFractal(const CommandLine& c)
{
  return Fractal(c.Output, c.FractalSize, c.FractalSeed, c.FractalSpacing, c.Overwrite);
}

} // namespace app
} // namespace terroir

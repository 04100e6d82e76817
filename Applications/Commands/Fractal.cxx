// `terroir fractal`: a seeded synthetic DEM (GeoTIFF or .vti)
#include "TerroirCommands.h"

#include "TerroirApp.h"
#include "TerroirCommandSupport.h"

#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationStringKey.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkUnsignedCharArray.h"

#include "vtkTerroirComputeContext.h"
#include "vtkTerroirFloodFill.h"
#include "vtkTerroirFractalTerrainSource.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirInfiltration.h"
#include "vtkTerroirKMeans.h"
#include "vtkTerroirSlope.h"
#include "vtkTerroirSoilHumidity.h"
#include "vtkTerroirSolarIllumination.h"
#include "vtkTerroirTemperature.h"
#include "vtkTerroirWaterFlow.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
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

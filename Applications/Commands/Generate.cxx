// `terroir generate island`: Weiss (2015)'s polygon-map island (vtkTerroirPolygonIslandSource).
#include "TerroirCommands.h"

#include "TerroirApp.h"
#include "TerroirCommandSupport.h"

#include "vtkCell.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"

#include "TerroirSafeOutput.h"
#include "vtkTerroirPolygonIslandSource.h"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <string>
#include <vector>

namespace terroir
{
namespace app
{

int CommandGenerateRiverLand(const CommandLine& c); // GenerateRiverLand.cxx
int CommandGenerateFeatures(const CommandLine& c);  // GenerateFeatures.cxx

void WriteRiverLines(vtkPolyData* rivers,
  const std::vector<LineProperty>& properties,
  const std::string& crs,
  const std::string& path,
  bool overwrite)
{
  nlohmann::json features = nlohmann::json::array();
  for (vtkIdType k = 0; k < rivers->GetNumberOfCells(); ++k)
  {
    vtkCell* line = rivers->GetCell(k);
    nlohmann::json coordinates = nlohmann::json::array();
    for (vtkIdType v = 0; v < line->GetNumberOfPoints(); ++v)
    {
      double xyz[3];
      rivers->GetPoint(line->GetPointId(v), xyz);
      coordinates.push_back({ xyz[0], xyz[1] });
    }
    nlohmann::json values = nlohmann::json::object();
    for (const LineProperty& p : properties)
    {
      const double value = rivers->GetCellData()->GetArray(p.array)->GetComponent(k, 0);
      if (p.integer)
      {
        values[p.key] = static_cast<int>(value);
      }
      else
      {
        values[p.key] = value;
      }
    }
    features.push_back({ { "type", "Feature" },
      { "properties", values },
      { "geometry", { { "type", "LineString" }, { "coordinates", coordinates } } } });
  }
  nlohmann::json collection = { { "type", "FeatureCollection" }, { "features", features } };
  if (!crs.empty())
  {
    // GeoJSON 2008's named CRS (GDAL reads it): the lines are in the generator's CRS.
    collection["crs"] = { { "type", "name" }, { "properties", { { "name", crs } } } };
  }
  WriteTextFile(path, collection.dump() + "\n", overwrite);
}

int CommandGenerate(const CommandLine& c)
{
  if (c.Generate.Kind == "riverland")
  {
    return CommandGenerateRiverLand(c);
  }
  const auto& g = c.Generate;
  if (g.Kind == "features")
  {
    return CommandGenerateFeatures(c);
  }
  std::vector<std::string> outputs{ c.Output };
  for (const std::string* extra : { &g.BiomeOutput, &g.RiverOutput, &g.RiverLines })
  {
    if (!extra->empty())
    {
      outputs.push_back(*extra);
    }
  }
  CheckWritable(outputs, c.Overwrite);
  vtkNew<vtkTerroirPolygonIslandSource> source;
  source->SetDimensions(g.Width, g.Height);
  source->SetSpacing(g.Spacing);
  source->SetSeed(static_cast<unsigned long long>(g.Seed));
  source->SetRegions(g.Regions);
  source->SetRelaxations(g.Relaxations);
  source->SetRivers(g.Rivers);
  source->SetMaximumHeight(g.MaximumHeight);
  source->SetMaximumDepth(g.MaximumDepth);
  source->SetNoiseScale(g.NoiseScale);
  source->SetPerturbation(g.Perturbation);
  if (!g.CRS.empty())
  {
    source->SetCRS(g.CRS.c_str());
    source->SetOrigin(g.Origin[0], g.Origin[1]);
  }
  UpdateOrThrow(source, "island");
  vtkImageData* island = source->GetOutput();
  // Every file goes into place at the end, or none.
  HoldCommits();
  try
  {
    WriteStageResult(island, "Elevation", c.Output, c.Overwrite);
    if (!g.BiomeOutput.empty())
    {
      WriteStageResult(island, "Biome", g.BiomeOutput, c.Overwrite);
    }
    if (!g.RiverOutput.empty())
    {
      WriteStageResult(island, "River", g.RiverOutput, c.Overwrite);
    }
    if (!g.RiverLines.empty())
    {
      // GeoJSON LineStrings in the image's coordinates (no CRS: metres from the first cell),
      // each with the water it carries.
      WriteRiverLines(vtkPolyData::SafeDownCast(source->GetOutputDataObject(1)),
        { { "river_flow", "RiverFlow", false } },
        g.CRS,
        g.RiverLines,
        c.Overwrite);
    }
  }
  catch (...)
  {
    DiscardHeldCommits();
    throw;
  }
  std::string error;
  if (!ReleaseHeldCommits(error))
  {
    throw Failure(error);
  }
  // One summary line: how much is land, lake and sea, and how many cells the rivers cover.
  vtkDataArray* water = island->GetPointData()->GetArray("WaterClass");
  vtkDataArray* river = island->GetPointData()->GetArray("River");
  long long counts[3] = { 0, 0, 0 }, rivers = 0;
  for (vtkIdType k = 0; k < water->GetNumberOfTuples(); ++k)
  {
    ++counts[static_cast<int>(water->GetComponent(k, 0)) % 3];
    rivers += river->GetComponent(k, 0) != 0.0 ? 1 : 0;
  }
  const double n = static_cast<double>(water->GetNumberOfTuples());
  std::printf("island %d x %d, seed %lld: land %.1f %%, lakes %.1f %%, sea %.1f %%, river cells "
              "%lld\n",
    g.Width,
    g.Height,
    g.Seed,
    100.0 * counts[0] / n,
    100.0 * counts[1] / n,
    100.0 * counts[2] / n,
    rivers);
  return 0;
}

} // namespace app
} // namespace terroir

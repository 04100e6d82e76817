// `terroir generate riverland`: Jensen (2011)'s river-first terrain (vtkTerroirRiverLandSource):
// the command (called from Generate.cxx; its options are checked in GenerateRiverLandOptions.cxx).
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
#include "vtkTerroirRiverLandSource.h"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <string>
#include <vector>

namespace terroir
{
namespace app
{

int CommandGenerateRiverLand(const CommandLine& c)
{
  const auto& g = c.Generate;
  std::vector<std::string> outputs{ c.Output };
  for (const std::string* extra : { &g.RiverOutput, &g.RiverLines })
  {
    if (!extra->empty())
    {
      outputs.push_back(*extra);
    }
  }
  CheckWritable(outputs, c.Overwrite);
  vtkNew<vtkTerroirRiverLandSource> source;
  source->SetDimensions(g.Width, g.Height);
  source->SetSpacing(g.Spacing);
  source->SetSeed(static_cast<unsigned long long>(g.Seed));
  source->SetRivers(g.Rivers);
  source->SetThreads(g.RiverLand.Threads);
  source->SetParametersJSON(g.RiverLand.Params.c_str());
  if (!g.CRS.empty())
  {
    source->SetCRS(g.CRS.c_str());
    source->SetOrigin(g.Origin[0], g.Origin[1]);
  }
  UpdateOrThrow(source, "riverland");
  vtkImageData* land = source->GetOutput();
  // Every file goes into place at the end, or none.
  HoldCommits();
  try
  {
    WriteStageResult(land, "Elevation", c.Output, c.Overwrite);
    if (!g.RiverOutput.empty())
    {
      WriteStageResult(land, "River", g.RiverOutput, c.Overwrite);
    }
    if (!g.RiverLines.empty())
    {
      // GeoJSON LineStrings through the river cells' centres, in the image's coordinates (or
      // its CRS), with each river's id, parent and level.
      WriteRiverLines(vtkPolyData::SafeDownCast(source->GetOutputDataObject(1)),
        { { "river_id", "RiverId", true },
          { "parent", "Parent", true },
          { "level", "Level", true } },
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
  // One summary line: land share, river cells and rivers, the medial cells before and after
  // pruning.
  vtkDataArray* cls = land->GetPointData()->GetArray("CellClass");
  long long landCells = 0, riverCells = 0;
  for (vtkIdType k = 0; k < cls->GetNumberOfTuples(); ++k)
  {
    const int v = static_cast<int>(cls->GetComponent(k, 0));
    landCells += v != 0 ? 1 : 0;
    riverCells += v == 3 ? 1 : 0;
  }
  const vtkIdType rivers =
    vtkPolyData::SafeDownCast(source->GetOutputDataObject(1))->GetNumberOfCells();
  std::printf("riverland %d x %d, seed %lld: land %.1f %%, %lld rivers and tributaries, river "
              "cells %lld, medial-axis cells %d (%d before pruning), user slopes %d\n",
    g.Width,
    g.Height,
    g.Seed,
    100.0 * landCells / static_cast<double>(cls->GetNumberOfTuples()),
    static_cast<long long>(rivers),
    riverCells,
    source->GetMedialCellsAfter(),
    source->GetMedialCellsBefore(),
    source->GetSlopesApplied());
  return 0;
}

} // namespace app
} // namespace terroir

// `terroir floodfill`: lakes from seeds, or every closed depression
#include "TerroirCommands.h"

#include "TerroirApp.h"
#include "TerroirCommandSupport.h"
#include "TerroirWaterSupport.h"

#include "TerroirApp.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkSmartPointer.h"
#include "vtkTerroirFloodFill.h"
#include <iomanip>
#include <iostream>
#include <vector>

namespace terroir
{
namespace app
{

int CommandFloodFill(const CommandLine& c)
{
  const FloodFillSettings& s = c.FloodFill;
  std::vector<std::string> outs = { c.Output };
  if (!s.IdsOutput.empty())
  {
    outs.push_back(s.IdsOutput);
  }
  CheckWritable(outs, c.Overwrite);
  vtkSmartPointer<vtkImageData> terrain = ReadTerrain(c.Input, c.AllowNetwork, c.ZUnit);
  vtkNew<vtkTerroirFloodFill> flood;
  flood->SetBackend(ParseBackend(c.Backend));
  ApplyFloodFill(s, flood);
  flood->SetInputData(terrain);
  WatchProgress(flood, "floodfill");
  const double t0 = Now();
  UpdateOrThrow(flood, "flood fill");
  const double seconds = Now() - t0;
  vtkImageData* result = flood->GetOutput();
  WriteStageResult(result, vtkTerroirFloodFill::WaterDepthName(), c.Output, c.Overwrite);
  if (!s.IdsOutput.empty())
  {
    WriteStageResult(result, vtkTerroirFloodFill::WaterBodyName(), s.IdsOutput, c.Overwrite);
  }
  std::cout << "terroir floodfill (" << flood->GetModeAsString() << ", " << std::fixed
            << std::setprecision(3) << seconds << " s): ";
  PrintWaterBodies(result, 20);
  return 0;
}

} // namespace app
} // namespace terroir

// `terroir infiltration`: infiltration rates from fill, slope-rule, paint and soil operations
#include "TerroirCommands.h"

#include "TerroirApp.h"
#include "TerroirCommandSupport.h"
#include "TerroirWaterSupport.h"

#include "TerroirApp.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkSmartPointer.h"
#include "vtkTerroirInfiltration.h"
#include <vector>

namespace terroir
{
namespace app
{

int CommandInfiltration(const CommandLine& c)
{
  CheckWritable({ c.Output }, c.Overwrite);
  vtkSmartPointer<vtkImageData> terrain = ReadTerrain(c.Input, c.AllowNetwork, c.ZUnit);
  vtkNew<vtkTerroirInfiltration> infiltration;
  infiltration->SetBackend(ParseBackend(c.Backend));
  ApplyInfiltration(c.SoilWater, infiltration, terrain, c.AllowNetwork);
  infiltration->SetInputData(terrain);
  WatchProgress(infiltration, "infiltration");
  UpdateOrThrow(infiltration, "infiltration");
  WriteStageResult(infiltration->GetOutput(),
    vtkTerroirInfiltration::InfiltrationRateName(),
    c.Output,
    c.Overwrite);
  return 0;
}

} // namespace app
} // namespace terroir

// `terroir waterflow`: the hydrostatic water-flow simulation of Long (2016): rivers and lakes
#include "TerroirCommands.h"

#include "TerroirApp.h"
#include "TerroirCommandSupport.h"
#include "TerroirFlowSupport.h"

#include "RiverValidation.h"
#include "TerroirApp.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkTerroirWaterFlow.h"
#include <vector>

namespace terroir
{
namespace app
{

//------------------------------------------------------------------------------
int CommandWaterFlow(const CommandLine& c)
{
  const WaterFlowSettings& s = c.WaterFlow;
  std::vector<std::string> outs = { c.Output };
  for (const std::string* extra : { &s.DischargeOutput, &s.RiverOutput })
  {
    if (!extra->empty())
    {
      outs.push_back(*extra);
    }
  }
  CheckWritable(outs, c.Overwrite);
  vtkSmartPointer<vtkImageData> terrain = ReadTerrain(c.Input, c.AllowNetwork, c.ZUnit);
  double seconds = 0.0;
  vtkSmartPointer<vtkImageData> out = SimulateWaterFlow(s, terrain, c.Backend, seconds);
  WriteStageResult(out, vtkTerroirWaterFlow::WaterHeightName(), c.Output, c.Overwrite);
  if (!s.DischargeOutput.empty())
  {
    // Rivers mode: the steady discharge rate (m3/s); pulse mode: the water that left (m3).
    const bool rivers = out->GetPointData()->GetArray(vtkTerroirWaterFlow::DischargeRateName());
    WriteStageResult(out,
      rivers ? vtkTerroirWaterFlow::DischargeRateName() : vtkTerroirWaterFlow::DischargeName(),
      s.DischargeOutput,
      c.Overwrite);
  }
  if (!s.RiverOutput.empty())
  {
    WriteStageResult(out, vtkTerroirWaterFlow::RiverName(), s.RiverOutput, c.Overwrite);
  }
  PrintWaterFlow(out, seconds);
  return 0;
}

} // namespace app
} // namespace terroir

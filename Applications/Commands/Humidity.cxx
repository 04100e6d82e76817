// `terroir humidity`: monthly soil humidity, its weighted average and standing water
#include "TerroirCommands.h"

#include "TerroirApp.h"
#include "TerroirCommandSupport.h"
#include "TerroirWaterSupport.h"

#include "TerroirApp.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkTerroirInfiltration.h"
#include "vtkTerroirSoilHumidity.h"
#include <vector>

namespace terroir
{
namespace app
{

int CommandHumidity(const CommandLine& c)
{
  const SoilWaterSettings& s = c.SoilWater;
  std::vector<std::string> outs = { c.Output };
  for (const std::string* extra : { &s.WeightedOutput, &s.StandingOutput })
  {
    if (!extra->empty())
    {
      outs.push_back(*extra);
    }
  }
  CheckWritable(outs, c.Overwrite);
  vtkSmartPointer<vtkImageData> terrain = ReadTerrain(c.Input, c.AllowNetwork, c.ZUnit);
  vtkSmartPointer<vtkImageData> withRates;
  if (!s.InfiltrationInput.empty())
  {
    vtkSmartPointer<vtkImageData> rates =
      ReadGridOperand(s.InfiltrationInput, terrain, c.AllowNetwork, "InfiltrationRate");
    withRates = vtkSmartPointer<vtkImageData>::New();
    withRates->ShallowCopy(terrain);
    withRates->GetPointData()->AddArray(rates->GetPointData()->GetScalars());
  }
  else
  {
    vtkNew<vtkTerroirInfiltration> infiltration;
    ApplyInfiltration(s, infiltration, terrain, c.AllowNetwork);
    infiltration->SetInputData(terrain);
    WatchProgress(infiltration, "infiltration");
    UpdateOrThrow(infiltration, "infiltration");
    withRates = vtkSmartPointer<vtkImageData>::New();
    withRates->ShallowCopy(infiltration->GetOutput());
  }
  vtkNew<vtkTerroirSoilHumidity> humidity;
  humidity->SetBackend(ParseBackend(c.Backend));
  ApplyClimate(s, humidity);
  humidity->SetInputData(withRates);
  WatchProgress(humidity, "humidity");
  UpdateOrThrow(humidity, "soil humidity");
  vtkImageData* result = humidity->GetOutput();
  WriteStageResult(result, vtkTerroirSoilHumidity::SoilHumidityName(), c.Output, c.Overwrite);
  if (!s.WeightedOutput.empty())
  {
    WriteStageResult(
      result, vtkTerroirSoilHumidity::WeightedSoilHumidityName(), s.WeightedOutput, c.Overwrite);
  }
  if (!s.StandingOutput.empty())
  {
    WriteStageResult(
      result, vtkTerroirSoilHumidity::StandingWaterName(), s.StandingOutput, c.Overwrite);
  }
  return 0;
}

} // namespace app
} // namespace terroir

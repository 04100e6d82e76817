// `terroir erosion`: hydraulic and thermal erosion (vtkTerroirErosion)
#include "TerroirCommands.h"

#include "TerroirApp.h"
#include "TerroirCommandSupport.h"

#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkNew.h"

#include "vtkTerroirErosion.h"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <iostream>
#include <string>

namespace terroir
{
namespace app
{

int CommandErosion(const CommandLine& c)
{
  const int backend = ParseBackend(c.Backend);
  CheckWritable({ c.Output }, c.Overwrite);
  vtkSmartPointer<vtkImageData> terrain = ReadTerrain(c.Input, c.AllowNetwork, c.ZUnit);
  vtkNew<vtkTerroirErosion> erosion;
  erosion->SetBackend(backend);
  const auto& e = c.Erosion;
  erosion->SetSteps(e.Steps);
  erosion->SetTimeStep(e.TimeStep);
  erosion->SetInitialWater(e.InitialWater);
  erosion->SetRainRate(e.RainRate);
  erosion->SetTalusAngle(e.TalusAngle);
  erosion->SetThermalInterval(e.ThermalInterval);
  erosion->SetCapacityDepth(e.CapacityDepth);
  if (e.Vegetation >= 0.0)
  {
    erosion->VegetationOn();
    erosion->SetInitialVegetation(e.Vegetation);
  }
  if (!e.SeaLevel.empty())
  {
    erosion->SetBoundary(vtkTerroirErosion::Sea);
    erosion->SetSeaLevel(std::stod(e.SeaLevel));
  }
  erosion->SetWeather(e.Weather);
  erosion->SetWindDirection(e.WindDirection);
  erosion->SetWindStrength(e.WindStrength);
  erosion->SetEvaporationScale(e.EvaporationScale);
  nlohmann::json stages;
  vtkSmartPointer<vtkImageData> result = RunStage(erosion.Get(), terrain, "erosion", stages);
  WriteStageResult(result, vtkTerroirErosion::ErodedElevationName(), c.Output, c.Overwrite);
  vtkDataArray* v = result->GetFieldData()->GetArray("ErosionVolumes");
  char line[256];
  std::snprintf(line,
    sizeof(line),
    "erosion: %d steps; eroded %.6g m3, deposited %.6g m3, rain %.6g m3, evaporated %.6g m3, "
    "to the sea %.6g m3\n",
    e.Steps,
    v ? v->GetComponent(0, 0) : 0.0,
    v ? v->GetComponent(0, 1) : 0.0,
    v ? v->GetComponent(0, 2) : 0.0,
    v ? v->GetComponent(0, 3) : 0.0,
    v ? v->GetComponent(0, 4) : 0.0);
  std::cout << line;
  if (vtkDataArray* w = result->GetFieldData()->GetArray("WeatherVolumes"))
  {
    std::snprintf(line,
      sizeof(line),
      "weather: evaporated %.6g m3 from the water and %.6g m3 from the canopy, rained %.6g m3\n",
      w->GetComponent(0, 0),
      w->GetComponent(0, 1),
      w->GetComponent(0, 2));
    std::cout << line;
  }
  return 0;
}

} // namespace app
} // namespace terroir

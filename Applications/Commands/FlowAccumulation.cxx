// `terroir flowacc`: flow accumulation after priority-flood filling (D8, MFD, D-infinity)
#include "TerroirCommands.h"

#include "TerroirApp.h"
#include "TerroirCommandSupport.h"
#include "TerroirFlowSupport.h"

#include "RiverValidation.h"
#include "TerroirApp.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkTerroirFlowAccumulation.h"
#include <iostream>
#include <vector>

namespace terroir
{
namespace app
{

//------------------------------------------------------------------------------
int CommandFlowAccumulation(const CommandLine& c)
{
  CheckWritable({ c.Output }, c.Overwrite);
  vtkSmartPointer<vtkImageData> terrain = ReadTerrain(c.Input, c.AllowNetwork, c.ZUnit);
  vtkNew<vtkTerroirFlowAccumulation> d8;
  d8->SetRiverThreshold(c.FlowRiverThreshold);
  d8->SetMethod(c.FlowMethod == "mfd"
      ? vtkTerroirFlowAccumulation::MFD
      : (c.FlowMethod == "dinf" ? vtkTerroirFlowAccumulation::DInfinity
                                : vtkTerroirFlowAccumulation::D8));
  d8->SetMFDExponent(c.FlowMFDExponent);
  d8->SetInputData(terrain);
  WatchProgress(d8, "flowacc");
  const double t0 = Now();
  UpdateOrThrow(d8, "flow accumulation");
  const double seconds = Now() - t0;
  vtkImageData* out = d8->GetOutput();
  WriteStageResult(out, "ContributingArea", c.Output, c.Overwrite);
  vtkDataArray* river = out->GetPointData()->GetArray("River");
  long long rivers = 0;
  for (vtkIdType k = 0; river && k < river->GetNumberOfTuples(); ++k)
  {
    rivers += river->GetComponent(k, 0) > 0.0 ? 1 : 0;
  }
  std::cout << "terroir flowacc " << vtkTerroirFlowAccumulation::MethodName(d8->GetMethod()) << " ("
            << Fixed(seconds, 3) << " s): " << rivers
            << " river cells (contributing area >= " << c.FlowRiverThreshold << " m2)\n";
  return 0;
}

} // namespace app
} // namespace terroir

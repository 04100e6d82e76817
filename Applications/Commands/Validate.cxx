// `terroir validate`: simulated rivers and the classic baselines scored against mapped rivers
#include "TerroirCommands.h"

#include "TerroirApp.h"
#include "TerroirCommandSupport.h"
#include "TerroirFlowSupport.h"
#include "TerroirWaterSupport.h"

#include "RiverValidation.h"
#include "TerroirApp.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkStringArray.h"
#include "vtkTerroirFlowAccumulation.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirInfiltration.h"
#include "vtkTerroirSoilHumidity.h"
#include "vtkTerroirVectorRasterizer.h"
#include "vtkTerroirWaterFlow.h"
#include "vtkUnsignedCharArray.h"
#include <cmath>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

namespace terroir
{
namespace app
{
namespace hy = terroir::hydrology;

namespace
{
/// The classic baselines scored into `methods` (their river cells into `simulated`).
void ScoreBaselines(vtkImageData* terrain,
  const GridView<std::uint8_t>& refView,
  const std::vector<std::uint8_t>& area,
  std::vector<MethodScores>& methods,
  std::vector<std::uint8_t>& simulated)
{
  // The classic baselines: D8, MFD (Freeman 1991 and the adaptive MFD-md of Qin et al. 2007)
  // and D-infinity by accumulation, and the slope-area score of each.
  const struct
  {
    int method;
    bool adaptive;
    const char* name;
  } baselines[] = { { vtkTerroirFlowAccumulation::D8, false, "D8" },
    { vtkTerroirFlowAccumulation::MFD, false, "MFD" },
    { vtkTerroirFlowAccumulation::MFD, true, "MFD-md" },
    { vtkTerroirFlowAccumulation::DInfinity, false, "D-infinity" } };
  for (const auto& b : baselines)
  {
    vtkNew<vtkTerroirFlowAccumulation> acc;
    acc->SetMethod(b.method);
    acc->SetMFDAdaptiveExponent(b.adaptive);
    acc->SetInputData(terrain);
    UpdateOrThrow(acc, "flow accumulation");
    vtkPointData* pd = acc->GetOutput()->GetPointData();
    methods.push_back(Score(b.name,
      "FlowAccumulation (cells)",
      AsDoubles(pd->GetArray(vtkTerroirFlowAccumulation::FlowAccumulationName()), false),
      std::nan(""),
      refView,
      area,
      simulated));
    if (b.adaptive)
    {
      continue;
    }
    methods.push_back(Score(std::string(b.name) + " A*S",
      "ChannelInitiation (m2)",
      AsDoubles(pd->GetArray(vtkTerroirFlowAccumulation::ChannelInitiationName()), false),
      std::nan(""),
      refView,
      area,
      simulated));
  }
}

/// The peers' accumulation grids (--peer NAME=FILE) scored into `methods`.
void ScorePeers(const CommandLine& c,
  vtkImageData* terrain,
  const GridView<std::uint8_t>& refView,
  const std::vector<std::uint8_t>& area,
  std::vector<MethodScores>& methods,
  std::vector<std::uint8_t>& simulated)
{
  const ValidateSettings& v = c.Validate;
  for (const std::string& peer : v.Peers)
  {
    const std::size_t eq = peer.find('=');
    const std::string name = peer.substr(0, eq);
    const std::string path = peer.substr(eq + 1);
    vtkSmartPointer<vtkImageData> acc = ReadGridOperand(path, terrain, c.AllowNetwork, "Peer");
    // r.watershed marks cells with off-map contributions by a negative accumulation.
    methods.push_back(Score(name,
      "accumulation |value| of " + path,
      AsDoubles(acc->GetPointData()->GetScalars(), true),
      std::nan(""),
      refView,
      area,
      simulated));
  }
}

/// The table of scores on the standard output.
void PrintScores(const std::string& dem,
  const std::string& reference,
  const std::string& maskPath,
  std::size_t refCells,
  const std::vector<MethodScores>& methods,
  std::size_t simulationRows)
{
  std::cout << "terroir validate: " << dem << "\n  reference " << reference << ": " << refCells
            << " river cells inside the area" << (maskPath.empty() ? "" : " (" + maskPath + ")")
            << "\n";
  std::cout
    << "  method                     threshold      P@30   R@30  F1@30   P@60   R@60  F1@60\n";
  for (const MethodScores& m : methods)
  {
    std::ostringstream th;
    th << std::setprecision(4) << m.threshold << (m.lengthMatched ? "*" : "");
    std::cout << "  " << std::left << std::setw(26) << m.name.substr(0, 26) << std::right
              << std::setw(10) << th.str() << "  " << std::setw(6) << Fixed(m.at30.precision, 3)
              << " " << std::setw(6) << Fixed(m.at30.recall, 3) << " " << std::setw(6)
              << Fixed(m.at30.f1, 3) << " " << std::setw(6) << Fixed(m.at60.precision, 3) << " "
              << std::setw(6) << Fixed(m.at60.recall, 3) << " " << std::setw(6)
              << Fixed(m.at60.f1, 3) << "\n";
  }
  std::cout << "  (* threshold chosen so that the river cells equal the reference's in number;\n"
               "   A*S: contributing area times slope, Montgomery & Dietrich 1988; the first "
            << simulationRows << " row(s): the water-flow simulation)\n";
}

/// --png: the first simulation's rivers against the reference within 60 m, over the terrain.
void WriteRiverComparison(const OverlayWriterFunction& writeOverlay,
  const std::string& png,
  vtkImageData* terrain,
  const GridView<std::uint8_t>& refView,
  const std::vector<std::uint8_t>& flowRivers,
  const std::vector<std::uint8_t>& area)
{
  const std::size_t n = static_cast<std::size_t>(terrain->GetNumberOfPoints());
  std::vector<std::uint8_t> category(n, 0);
  hy::RiverComparisonCategories(refView, flowRivers.data(), area.data(), 60.0, category.data());
  auto picture = vtkSmartPointer<vtkImageData>::New();
  picture->ShallowCopy(terrain);
  vtkNew<vtkUnsignedCharArray> cat;
  cat->SetName("RiverComparison");
  cat->SetNumberOfTuples(static_cast<vtkIdType>(n));
  std::copy(category.begin(), category.end(), cat->GetPointer(0));
  picture->GetPointData()->AddArray(cat);
  writeOverlay(picture, "RiverComparison", "RiverComparison", "Rivers within 60 m", png, true);
}
} // namespace

//------------------------------------------------------------------------------
int CommandValidate(const CommandLine& c)
{
  const OverlayWriterFunction writeOverlay = CommandOverlayWriter(c);
  const ValidateSettings& v = c.Validate;
  const bool bundled = c.Input.empty();
  const std::string dem = bundled ? DefaultDEM() : c.Input;
  const std::string dataDir = dem.substr(0, dem.find_last_of('/') + 1);
  const std::string reference = !v.Reference.empty()
    ? v.Reference
    : (bundled ? dataDir + "sagehen_nhd_flowlines_utm11n.geojson" : "");
  const std::string maskPath =
    !v.Mask.empty() ? v.Mask : (bundled ? dataDir + "sagehen_watershed_utm11n.geojson" : "");
  if (reference.empty())
  {
    throw Failure("validate: --reference LINES is needed for a DEM other than the bundled one");
  }
  std::vector<std::string> outs;
  for (const std::string* p : { &v.Json, &v.Png })
  {
    if (!p->empty())
    {
      outs.push_back(*p);
    }
  }
  CheckWritable(outs, c.Overwrite);
  vtkSmartPointer<vtkImageData> terrain = ReadTerrain(dem, c.AllowNetwork, c.ZUnit);
  RiverReference rr(terrain, dem, reference, maskPath, c.AllowNetwork);
  const std::vector<std::uint8_t>& area = rr.Area;
  const GridView<std::uint8_t>& refView = rr.View;

  // The simulation (one row per swept value), the classic baselines, the peers.
  std::string sweepName;
  std::vector<std::string> sweepValues;
  if (!v.Sweep.empty())
  {
    ParseSweep(v.Sweep, sweepName, sweepValues);
  }
  else
  {
    sweepValues.push_back("");
  }
  std::vector<MethodScores> methods;
  std::vector<std::uint8_t> simulated;
  std::vector<std::uint8_t> flowRivers;
  nlohmann::json runs = nlohmann::json::array();
  for (const std::string& value : sweepValues)
  {
    WaterFlowSettings settings = c.WaterFlow;
    if (!sweepName.empty())
    {
      ApplySweepValue(settings, sweepName, value);
    }
    double seconds = 0.0;
    vtkSmartPointer<vtkImageData> flow =
      SimulateWaterFlow(settings, terrain, c.Backend, seconds, "rivers");
    PrintWaterFlow(flow, seconds);
    const bool rivers =
      flow->GetPointData()->GetArray(vtkTerroirWaterFlow::DischargeRateName()) != nullptr;
    std::string name = rivers ? "terroir waterflow rivers" : "terroir waterflow pulse";
    if (!sweepName.empty())
    {
      name = sweepName + "=" + value;
    }
    // The overlay shows the first simulation row.
    std::vector<std::uint8_t>& cells = flowRivers.empty() ? flowRivers : simulated;
    methods.push_back(Score(name,
      rivers ? "RiverStrength (m3/s)" : "Discharge (m3)",
      AsDoubles(flow->GetPointData()->GetArray(rivers ? vtkTerroirWaterFlow::RiverStrengthName()
                                                      : vtkTerroirWaterFlow::DischargeName()),
        false),
      settings.RiverThreshold,
      refView,
      area,
      cells));
    runs.push_back({ { "method", name },
      { "mode", rivers ? "rivers" : "pulse" },
      { "iterations", FieldNumber(flow, vtkTerroirWaterFlow::IterationsName()) },
      { "stop_reason", FieldText(flow, vtkTerroirWaterFlow::StopReasonName()) },
      { "seconds", seconds } });
  }
  const std::size_t simulationRows = methods.size();

  ScoreBaselines(terrain, refView, area, methods, simulated);
  ScorePeers(c, terrain, refView, area, methods, simulated);

  // Text.
  const std::size_t refCells = rr.Cells;
  PrintScores(dem, reference, maskPath, refCells, methods, simulationRows);

  if (!v.Json.empty())
  {
    nlohmann::json j;
    j["dem"] = dem;
    j["reference"] = reference;
    j["mask"] = maskPath;
    j["reference_cells"] = refCells;
    j["water_flow"] = runs[0];
    j["water_flow_runs"] = runs;
    if (!sweepName.empty())
    {
      j["sweep"] = { { "option", sweepName }, { "values", sweepValues } };
    }
    for (const MethodScores& m : methods)
    {
      j["methods"].push_back(MethodScoresJson(m));
    }
    WriteTextFile(v.Json, j.dump(2) + "\n", c.Overwrite);
  }
  if (!v.Png.empty())
  {
    WriteRiverComparison(writeOverlay, v.Png, terrain, refView, flowRivers, area);
  }
  return 0;
}

} // namespace app
} // namespace terroir

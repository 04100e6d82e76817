#include "TerroirFlowSupport.h"

#include "TerroirApp.h"
#include "TerroirWaterSupport.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkStringArray.h"
#include "vtkUnsignedCharArray.h"

#include "vtkTerroirFlowAccumulation.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirInfiltration.h"
#include "vtkTerroirSoilHumidity.h"
#include "vtkTerroirVectorRasterizer.h"
#include "vtkTerroirWaterFlow.h"

#include "RiverValidation.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <vector>

namespace terroir
{
namespace app
{
namespace hy = terroir::hydrology;

/// Runs the simulation on `terrain` with the options of `s` (the soil-water chain first for
/// --month and --annual); returns the filter's output.
vtkSmartPointer<vtkImageData> SimulateWaterFlow(const WaterFlowSettings& s,
  vtkImageData* terrain,
  const std::string& backend,
  double& seconds,
  const char* defaultMode)
{
  const bool rivers = (s.Mode.empty() ? std::string(defaultMode) : s.Mode) == "rivers";
  vtkSmartPointer<vtkImageData> input = terrain;
  if (s.Month > 0 || s.Annual)
  {
    // StandingWater of the default soil recipe and climate (vtkTerroirInfiltration and
    // vtkTerroirSoilHumidity defaults), as `terroir humidity` computes it.
    vtkNew<vtkTerroirInfiltration> infiltration;
    infiltration->SetInputData(terrain);
    UpdateOrThrow(infiltration, "infiltration");
    vtkNew<vtkTerroirSoilHumidity> humidity;
    humidity->SetBackend(ParseBackend(backend));
    humidity->SetInputConnection(infiltration->GetOutputPort());
    UpdateOrThrow(humidity, "soil humidity");
    input = vtkSmartPointer<vtkImageData>::New();
    input->ShallowCopy(humidity->GetOutput());
  }
  vtkNew<vtkTerroirWaterFlow> flow;
  flow->SetBackend(ParseBackend(backend));
  flow->SetInitialWater(s.InitialWater);
  if (s.Month > 0)
  {
    flow->SetWaterSourceToStandingWaterMonth();
    flow->SetMonth(s.Month);
  }
  else if (s.Annual)
  {
    flow->SetWaterSourceToStandingWaterAnnual();
  }
  flow->SetMaximumIterations(static_cast<vtkIdType>(s.MaximumIterations));
  flow->SetAutoStopRatio(s.AutoStop);
  flow->SetMaximumSimulatedTime(s.Time);
  flow->SetIterationDuration(s.IterationDuration);
  flow->SetMode(rivers ? vtkTerroirWaterFlow::Rivers : vtkTerroirWaterFlow::Pulse);
  flow->SetRainRate(s.RainRate);
  flow->SetBalanceTolerance(s.BalanceTolerance);
  flow->SetThinningFactor(s.Thinning);
  flow->SetWarmStart(s.WarmStart);
  flow->SetSettleIterations(static_cast<vtkIdType>(s.Settle));
  flow->SetLongCapacityRule(s.LongCapacity);
  flow->SetCountEmptiedCells(s.CountEmptied);
  if (std::isfinite(s.RiverThreshold))
  {
    flow->SetRiverThreshold(s.RiverThreshold);
  }
  flow->SetInputData(input);
  WatchProgress(flow, "waterflow");
  const double t0 = Now();
  UpdateOrThrow(flow, "water flow");
  seconds = Now() - t0;
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->ShallowCopy(flow->GetOutput());
  return out;
}

std::string Fixed(double v, int digits)
{
  std::ostringstream os;
  os << std::fixed << std::setprecision(digits) << v;
  return os.str();
}

/// One line on what the simulation did.
void PrintWaterFlow(vtkImageData* out, double seconds)
{
  const double still = FieldNumber(out, "WaterFlowInitialVolume");
  const double rain = FieldNumber(out, "WaterFlowRainVolume");
  const bool rivers = std::isfinite(rain);
  const double water = still + (rivers ? rain : 0.0);
  const double outflow = FieldNumber(out, "WaterFlowOutflowVolume");
  std::cout << "terroir waterflow (" << Fixed(seconds, 3) << " s): "
            << static_cast<long long>(FieldNumber(out, vtkTerroirWaterFlow::IterationsName()))
            << " iterations (" << FieldText(out, vtkTerroirWaterFlow::StopReasonName()) << "), ";
  if (rivers)
  {
    // The initial water: the still water, plus the warm start's flowing water.
    std::cout << "initial water " << Fixed(still, 0) << " m3, rain " << Fixed(rain, 0) << " m3";
  }
  else
  {
    std::cout << "water " << Fixed(water, 0) << " m3";
  }
  std::cout << ", left the terrain " << Fixed(outflow, 0) << " m3 ("
            << Fixed(water > 0.0 ? 100.0 * outflow / water : 0.0, 1) << " %)";
  vtkDataArray* levels = vtkDataArray::SafeDownCast(
    out->GetFieldData()->GetAbstractArray("WaterFlowWarmStartIterations"));
  if (levels && levels->GetNumberOfTuples() > 0 && levels->GetNumberOfComponents() == 3)
  {
    std::cout << "; warm start:";
    for (vtkIdType l = 0; l < levels->GetNumberOfTuples(); ++l)
    {
      std::cout << (l ? "," : "") << " " << static_cast<long long>(levels->GetComponent(l, 0))
                << " iterations on " << static_cast<long long>(levels->GetComponent(l, 1)) << "x"
                << static_cast<long long>(levels->GetComponent(l, 2));
    }
  }
  std::cout << "\n";
}

/// A point array as doubles (NaN stays NaN), absolute values when `absolute`.
std::vector<double> AsDoubles(vtkDataArray* a, bool absolute)
{
  std::vector<double> v(static_cast<std::size_t>(a->GetNumberOfTuples()));
  for (std::size_t k = 0; k < v.size(); ++k)
  {
    const double x = a->GetComponent(static_cast<vtkIdType>(k), 0);
    v[k] = absolute ? std::fabs(x) : x;
  }
  return v;
}

MethodScores Score(const std::string& name,
  const std::string& measure,
  const std::vector<double>& values,
  double userThreshold,
  const GridView<std::uint8_t>& reference,
  const std::vector<std::uint8_t>& area,
  std::vector<std::uint8_t>& simulated)
{
  MethodScores m;
  m.name = name;
  m.measure = measure;
  GridView<double> view;
  view.data = values.data();
  view.nx = reference.nx;
  view.ny = reference.ny;
  view.dx = reference.dx;
  view.dy = reference.dy;
  view.rowDx = reference.rowDx;
  view.rowDy = reference.rowDy;
  // Only channel cells (crests of the measure) can be rivers.
  std::vector<double> crest(values);
  {
    std::vector<std::uint8_t> channel(values.size());
    GridView<double> all = view;
    hy::ChannelCells(all, channel.data());
    for (std::size_t k = 0; k < values.size(); ++k)
    {
      crest[k] = channel[k] ? values[k] : std::nan("");
    }
    view.data = crest.data();
  }
  if (std::isfinite(userThreshold))
  {
    m.threshold = userThreshold;
    m.lengthMatched = false;
  }
  else
  {
    m.threshold = hy::LengthMatchingThreshold(view, reference.data, area.data());
  }
  simulated.assign(values.size(), 0);
  for (std::size_t k = 0; k < values.size(); ++k)
  {
    simulated[k] = area[k] && crest[k] >= m.threshold ? 1 : 0;
  }
  m.at30 = hy::ScoreRivers(reference, simulated.data(), area.data(), 30.0);
  m.at60 = hy::ScoreRivers(reference, simulated.data(), area.data(), 60.0);
  return m;
}

nlohmann::json ScoresJson(const hy::RiverScores& s)
{
  return { { "tolerance_m", s.toleranceMetres },
    { "precision", s.precision },
    { "recall", s.recall },
    { "f1", s.f1 },
    { "simulated_cells", s.simulatedCells },
    { "reference_cells", s.referenceCells },
    { "simulated_hits", s.simulatedHits },
    { "reference_hits", s.referenceHits } };
}

//------------------------------------------------------------------------------
RiverReference::RiverReference(vtkImageData* terrain,
  const std::string& dem,
  const std::string& reference,
  const std::string& maskPath,
  bool allowNetwork)
{
  const std::size_t n = static_cast<std::size_t>(terrain->GetNumberOfPoints());

  // Reference lines on the DEM grid (GDAL's rasterisation: the cells of each segment's path).
  vtkSmartPointer<vtkImageData> refImage = RasterizePolygons(reference, "", terrain, allowNetwork);
  std::vector<std::uint8_t>& ref = this->Reference;
  ref.assign(n, 0);
  {
    vtkDataArray* a = refImage->GetPointData()->GetScalars();
    for (std::size_t k = 0; k < n; ++k)
    {
      ref[k] = a->GetComponent(static_cast<vtkIdType>(k), 0) > 0.0 ? 1 : 0;
    }
  }

  // The area: everything, a raster on the grid, or polygons.
  std::vector<std::uint8_t>& area = this->Area;
  area.assign(n, 1);
  if (!maskPath.empty())
  {
    const bool raster = HasExtension(maskPath, ".tif") || HasExtension(maskPath, ".tiff") ||
      HasExtension(maskPath, ".img") || HasExtension(maskPath, ".vti");
    vtkSmartPointer<vtkImageData> m = raster
      ? ReadGridOperand(maskPath, terrain, allowNetwork, "Area")
      : RasterizePolygons(maskPath, "", terrain, allowNetwork, true);
    vtkDataArray* a = m->GetPointData()->GetScalars();
    std::size_t inside = 0;
    for (std::size_t k = 0; k < n; ++k)
    {
      const double x = a->GetComponent(static_cast<vtkIdType>(k), 0);
      area[k] = std::isfinite(x) && x != 0.0 ? 1 : 0;
      inside += area[k];
    }
    if (inside == 0)
    {
      throw Failure(maskPath + ": the area mask does not overlap the DEM " + dem);
    }
  }
  // Heights must exist inside a given area; without one, the area is where the DEM has data.
  vtkDataArray* z = terrain->GetPointData()->GetArray(vtkTerroirGeoreference::ElevationName());
  vtkDataArray* validMask = terrain->GetPointData()->GetArray("vtkValidPointMask");
  std::size_t holes = 0;
  for (std::size_t k = 0; k < n; ++k)
  {
    const bool valid = std::isfinite(z->GetComponent(static_cast<vtkIdType>(k), 0)) &&
      (!validMask || validMask->GetComponent(static_cast<vtkIdType>(k), 0) != 0.0);
    if (maskPath.empty())
    {
      area[k] = valid ? 1 : 0;
    }
    holes += area[k] && !valid ? 1 : 0;
  }
  if (holes > 0)
  {
    throw Failure(dem + ": no height (NaN or no data) on " + std::to_string(holes) +
      " cell(s) inside the area; fill them or pass a --mask that leaves them out");
  }

  // The grid as the scores see it.
  GridView<std::uint8_t>& refView = this->View;
  refView.data = ref.data();
  int dims[3];
  terrain->GetDimensions(dims);
  double spacing[3];
  terrain->GetSpacing(spacing);
  refView.nx = dims[0];
  refView.ny = dims[1];
  refView.dx = std::fabs(spacing[0]);
  refView.dy = std::fabs(spacing[1]);
  if (vtkDoubleArray* rows = vtkTerroirGeoreference::GetRowSpacing(terrain))
  {
    if (rows->GetNumberOfTuples() == dims[1] && rows->GetNumberOfComponents() == 2)
    {
      for (int j = 0; j < dims[1]; ++j)
      {
        this->RowDx.push_back(std::fabs(rows->GetComponent(j, 0)));
        this->RowDy.push_back(std::fabs(rows->GetComponent(j, 1)));
      }
      refView.rowDx = this->RowDx.data();
      refView.rowDy = this->RowDy.data();
    }
  }

  for (std::size_t k = 0; k < n; ++k)
  {
    this->Cells += ref[k] && area[k] ? 1 : 0;
  }
}

//------------------------------------------------------------------------------
MethodScores ScoreRiverMeasure(const std::string& name,
  const std::string& measure,
  const std::vector<double>& values,
  double userThreshold,
  const RiverReference& reference,
  std::vector<std::uint8_t>& simulated)
{
  return Score(name, measure, values, userThreshold, reference.View, reference.Area, simulated);
}

//------------------------------------------------------------------------------
std::vector<double> PointArrayValues(vtkImageData* image, const char* name)
{
  vtkDataArray* a = image->GetPointData()->GetArray(name);
  if (!a)
  {
    throw Failure(std::string("no point array ") + name);
  }
  return AsDoubles(a, false);
}

//------------------------------------------------------------------------------
nlohmann::json MethodScoresJson(const MethodScores& m)
{
  return { { "name", m.name },
    { "measure", m.measure },
    { "threshold", m.threshold },
    { "length_matched", m.lengthMatched },
    { "scores", { ScoresJson(m.at30), ScoresJson(m.at60) } } };
}

} // namespace app
} // namespace terroir

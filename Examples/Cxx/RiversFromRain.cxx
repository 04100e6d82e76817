// Rivers from rain, scored against the mapped USGS rivers (NHD flowlines) (the C++ twin of
// Examples/Python/RiversFromRain.py; both print the same report).
//
// Pipeline: vtkTerroirDEMReader -> vtkTerroirVectorRasterizer (the NHD flowlines onto the DEM
// grid, array `Reference`) -> vtkTerroirVectorRasterizer (the watershed polygon, array `Area`)
// -> vtkTerroirWaterFlow (100 mm of rain on every cell runs downhill: `Discharge`, m3) and
// vtkTerroirFlowAccumulation (the classic D8 baseline: `FlowAccumulation`, cells).
//
// The scores come from the core library of `terroir validate` (RiverValidation.h, in
// TerroirHydrologyCore): river cells are the crests of the flow measure (ChannelCells) at or above
// the threshold that makes them as many as the reference cells inside the watershed
// (LengthMatchingThreshold); precision, recall and F1 within 30 m and 60 m (ScoreRivers). The
// result is the same as `terroir validate --mode pulse --max-iterations 150` (Long (2016)'s pulse;
// validate and run use the river-forming mode). A map of the comparison at 60 m is saved
// (RiverComparisonCategories).
//
// Run under an X display (or xvfb-run -a):
//   build/bin/RiversFromRain --data Data --out example-output [--iterations N]
// The simulation stops after 150 iterations here (a few seconds); --iterations 10000 lets the
// Long (2016)'s stop rule end it (371 iterations, F1@60 0.657 as in Documentation/validation.md).

#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkStringArray.h"
#include "vtkUnsignedCharArray.h"

#include "vtkTerroirDEMReader.h"
#include "vtkTerroirFlowAccumulation.h"
#include "vtkTerroirOverlayView.h"
#include "vtkTerroirVectorRasterizer.h"
#include "vtkTerroirWaterFlow.h"

#include "RiverValidation.h" // terroir::hydrology, plain C++

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace hy = terroir::hydrology;

int main(int argc, char* argv[])
{
  const char* env = std::getenv("TERROIR_DATA_DIR");
  std::string data = env && *env ? env : TERROIR_EXAMPLES_DATA_DIR;
  std::string out = "example-output";
  vtkIdType iterations = 150;
  for (int i = 1; i < argc; ++i)
  {
    const std::string option = argv[i];
    if (i + 1 < argc && (option == "--data" || option == "--out"))
    {
      (option == "--data" ? data : out) = argv[++i];
    }
    else if (i + 1 < argc && option == "--iterations")
    {
      iterations = std::atoll(argv[++i]);
    }
    else
    {
      std::fprintf(stderr, "usage: %s [--data DIR] [--out DIR] [--iterations N]\n", argv[0]);
      return EXIT_FAILURE;
    }
  }
  std::filesystem::create_directories(out);
  const std::string sagehen = data + "/sagehen_creek_ca/";

  vtkNew<vtkTerroirDEMReader> reader;
  reader->SetFileName((sagehen + "sagehen_dem_utm11n_10m.tif").c_str());
  vtkNew<vtkTerroirVectorRasterizer> reference; // lines: the cells of their path
  reference->SetInputConnection(reader->GetOutputPort());
  reference->SetFileName((sagehen + "sagehen_nhd_flowlines_utm11n.geojson").c_str());
  reference->SetOutputArrayName("Reference");
  vtkNew<vtkTerroirVectorRasterizer> area; // polygons: the cells whose centre is inside
  area->SetInputConnection(reference->GetOutputPort());
  area->SetFileName((sagehen + "sagehen_watershed_utm11n.geojson").c_str());
  area->SetOutputArrayName("Area");

  vtkNew<vtkTerroirWaterFlow> flow;
  flow->SetInputConnection(area->GetOutputPort());
  flow->SetWaterSourceToConstant();
  flow->SetInitialWater(100.0); // mm of rain on every cell
  flow->SetMaximumIterations(iterations);
  vtkNew<vtkTerroirFlowAccumulation> d8;
  d8->SetInputConnection(flow->GetOutputPort());
  d8->Update();
  vtkImageData* terrain = d8->GetOutput();
  if (terrain->GetNumberOfPoints() == 0)
  {
    std::fprintf(stderr, "RiversFromRain: the pipeline failed (see the error above)\n");
    return EXIT_FAILURE;
  }
  vtkFieldData* fields = terrain->GetFieldData();
  std::printf("water flow: %lld iterations (%s)\n",
    static_cast<long long>(fields->GetArray("WaterFlowIterations")->GetComponent(0, 0)),
    vtkStringArray::SafeDownCast(fields->GetAbstractArray("WaterFlowStopReason"))
      ->GetValue(0)
      .c_str());

  // The rasters as the scores see them: nx * ny values, row 0 the south edge.
  int dims[3];
  terrain->GetDimensions(dims);
  double spacing[3];
  terrain->GetSpacing(spacing);
  const std::size_t n = static_cast<std::size_t>(terrain->GetNumberOfPoints());
  vtkPointData* points = terrain->GetPointData();
  std::vector<std::uint8_t> ref(n), inside(n);
  std::size_t referenceCells = 0;
  for (std::size_t c = 0; c < n; ++c)
  {
    ref[c] = points->GetArray("Reference")->GetComponent(static_cast<vtkIdType>(c), 0) > 0;
    inside[c] = points->GetArray("Area")->GetComponent(static_cast<vtkIdType>(c), 0) > 0;
    referenceCells += ref[c] && inside[c];
  }
  terroir::GridView<std::uint8_t> grid;
  grid.data = ref.data();
  grid.nx = dims[0];
  grid.ny = dims[1];
  grid.dx = spacing[0];
  grid.dy = spacing[1];
  std::printf("reference: %zu river cells inside the watershed\n", referenceCells);
  std::printf("method       threshold    P@30   R@30  F1@30    P@60   R@60  F1@60\n");

  std::vector<std::uint8_t> comparison(n, 0);
  for (const char* method : { "waterflow", "D8" })
  {
    vtkDataArray* measure =
      points->GetArray(std::string(method) == "D8" ? "FlowAccumulation" : "Discharge");
    std::vector<double> value(n);
    for (std::size_t c = 0; c < n; ++c)
    {
      value[c] = measure->GetComponent(static_cast<vtkIdType>(c), 0);
    }
    // Only crests of the measure (channel cells) can be rivers.
    terroir::GridView<double> view;
    view.data = value.data();
    view.nx = grid.nx;
    view.ny = grid.ny;
    view.dx = grid.dx;
    view.dy = grid.dy;
    std::vector<std::uint8_t> channel(n);
    hy::ChannelCells(view, channel.data());
    for (std::size_t c = 0; c < n; ++c)
    {
      value[c] = channel[c] ? value[c] : std::nan("");
    }
    const double threshold = hy::LengthMatchingThreshold(view, ref.data(), inside.data());
    std::vector<std::uint8_t> simulated(n);
    for (std::size_t c = 0; c < n; ++c)
    {
      simulated[c] = inside[c] && value[c] >= threshold;
    }
    const hy::RiverScores at30 = hy::ScoreRivers(grid, simulated.data(), inside.data(), 30.0);
    const hy::RiverScores at60 = hy::ScoreRivers(grid, simulated.data(), inside.data(), 60.0);
    std::printf("%-10s %11.3f  %6.4f %6.4f %6.4f  %6.4f %6.4f %6.4f\n",
      method,
      threshold,
      at30.precision,
      at30.recall,
      at30.f1,
      at60.precision,
      at60.recall,
      at60.f1);
    if (std::string(method) == "waterflow")
    {
      // Classes of the RiverComparison overlay: 1 mapped only, 2 model only, 3 both.
      hy::RiverComparisonCategories(grid, simulated.data(), inside.data(), 60.0, comparison.data());
    }
  }

  vtkNew<vtkUnsignedCharArray> classes;
  classes->SetName("RiverComparison");
  classes->SetNumberOfTuples(static_cast<vtkIdType>(n));
  for (std::size_t c = 0; c < n; ++c)
  {
    classes->SetValue(static_cast<vtkIdType>(c), comparison[c]);
  }
  points->AddArray(classes);
  vtkNew<vtkTerroirOverlayView> picture;
  picture->SetInputData(terrain);
  picture->SetArrayName("RiverComparison");
  picture->SetPreset("RiverComparison");
  picture->SetTitle("Rivers within 60 m");
  picture->SetWidth(400);
  picture->SetHeight(400);
  if (!picture->WritePNG((out + "/rivers_comparison.png").c_str()))
  {
    std::fprintf(stderr, "RiversFromRain: %s\n", picture->GetLastError());
    return EXIT_FAILURE;
  }
  std::printf("wrote rivers_comparison.png\n");
  return EXIT_SUCCESS;
}

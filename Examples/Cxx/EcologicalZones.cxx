// The whole pipeline, from a DEM to ecological zones, with the zone table printed (the C++ twin
// of Examples/Python/EcologicalZones.py; both print the same report).
//
// Pipeline: vtkTerroirDEMReader -> vtkTerroirSlope -> vtkTerroirTemperature ->
// vtkTerroirSolarIllumination (monthly hours of sun) -> vtkTerroirInfiltration ->
// vtkTerroirSoilHumidity -> vtkTerroirKMeans (K = 5 zones on slope, temperature, sun hours and
// weighted soil humidity, Long (2016)'s features and weights).
// Prints the zone table (port 1 of vtkTerroirKMeans) and maps the zones.
//
// Run under an X display (or xvfb-run -a):
//   build/bin/EcologicalZones --data Data --out example-output [--zones K]
// It runs on the whole bundled DEM (786 x 720 cells) in about 2 s on two cores. On a large DEM
// try a window first (vtkExtractVOI after the reader, as in SunHoursAndSunPath.cxx). `terroir
// run` runs the same stages and also writes the table as CSV and JSON.

#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkVariant.h"

#include "vtkTerroirDEMReader.h"
#include "vtkTerroirInfiltration.h"
#include "vtkTerroirKMeans.h"
#include "vtkTerroirOverlayView.h"
#include "vtkTerroirSlope.h"
#include "vtkTerroirSoilHumidity.h"
#include "vtkTerroirSolarIllumination.h"
#include "vtkTerroirTemperature.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

int main(int argc, char* argv[])
{
  const char* env = std::getenv("TERROIR_DATA_DIR");
  std::string data = env && *env ? env : TERROIR_EXAMPLES_DATA_DIR;
  std::string out = "example-output";
  int k = 5;
  for (int i = 1; i < argc; ++i)
  {
    const std::string option = argv[i];
    if (i + 1 < argc && (option == "--data" || option == "--out"))
    {
      (option == "--data" ? data : out) = argv[++i];
    }
    else if (i + 1 < argc && option == "--zones")
    {
      k = std::atoi(argv[++i]);
    }
    else
    {
      std::fprintf(stderr, "usage: %s [--data DIR] [--out DIR] [--zones K]\n", argv[0]);
      return EXIT_FAILURE;
    }
  }
  std::filesystem::create_directories(out);

  vtkNew<vtkTerroirDEMReader> reader;
  reader->SetFileName((data + "/sagehen_creek_ca/sagehen_dem_utm11n_10m.tif").c_str());

  // Each stage passes its input's arrays through and adds its own.
  vtkNew<vtkTerroirSlope> slope; // Slope, Aspect, Normals
  slope->SetInputConnection(reader->GetOutputPort());
  vtkNew<vtkTerroirTemperature> temperature; // Temperature (12 months)
  temperature->SetInputConnection(slope->GetOutputPort());
  vtkNew<vtkTerroirSolarIllumination> sun; // IlluminationHours, Insolation (12 months)
  sun->SetInputConnection(temperature->GetOutputPort());
  sun->SetModeToMonthly();
  vtkNew<vtkTerroirInfiltration> infiltration; // InfiltrationRate (mm/h)
  infiltration->SetInputConnection(sun->GetOutputPort());
  infiltration->AddFill(15.0);             // loam everywhere ...
  infiltration->AddSlopeRule(30.0);        // ... but slopes over 30 degrees shed the rain
  vtkNew<vtkTerroirSoilHumidity> humidity; // SoilHumidity, WeightedSoilHumidity, ...
  humidity->SetInputConnection(infiltration->GetOutputPort());

  vtkNew<vtkTerroirKMeans> zones; // ClusterId, and the zone table on port 1
  zones->SetInputConnection(humidity->GetOutputPort());
  zones->SetNumberOfClusters(k);
  zones->AddFeature("Slope", 1.0);
  zones->AddFeature("Temperature", 1.0);
  zones->AddFeature("IlluminationHours", 1.0);
  zones->AddFeature("WeightedSoilHumidity", 0.1);
  zones->Update();
  vtkImageData* terrain = zones->GetOutput();
  vtkTable* table = zones->GetClusterTable();
  if (terrain->GetNumberOfPoints() == 0 || table->GetNumberOfRows() == 0)
  {
    std::fprintf(stderr, "EcologicalZones: the pipeline failed (see the error above)\n");
    return EXIT_FAILURE;
  }

  vtkFieldData* fields = terrain->GetFieldData();
  std::printf("k-means: %lld zones, %d iterations (%s)\n",
    static_cast<long long>(table->GetNumberOfRows()),
    static_cast<int>(fields->GetArray("KMeansIterations")->GetComponent(0, 0)),
    vtkStringArray::SafeDownCast(fields->GetAbstractArray("KMeansStopReason"))
      ->GetValue(0)
      .c_str());

  // The zone table: one row per zone, the mean of every feature in its own units.
  const char* columns[][2] = { { "Slope", "slope_deg" },
    { "Temperature_Jan", "T_jan_C" },
    { "Temperature_Jul", "T_jul_C" },
    { "IlluminationHours_Dec", "sun_dec_h" },
    { "IlluminationHours_Jun", "sun_jun_h" },
    { "WeightedSoilHumidity_Jul", "soil_jul_mm" } };
  std::printf("zone  colour     cells  share_%%");
  for (const auto& column : columns)
  {
    std::printf("  %11s", column[1]);
  }
  std::printf("\n");
  long long totalCells = 0;
  double totalShare = 0.0;
  for (vtkIdType row = 0; row < table->GetNumberOfRows(); ++row)
  {
    const long long cells = table->GetValueByName(row, "Cells").ToLongLong();
    const double share = table->GetValueByName(row, "Share").ToDouble() * 100.0;
    totalCells += cells;
    totalShare += share;
    std::printf("%4d  %s  %8lld  %7.3f",
      table->GetValueByName(row, "ClusterId").ToInt(),
      table->GetValueByName(row, "Color").ToString().c_str(),
      cells,
      share);
    for (const auto& column : columns)
    {
      std::printf("  %11.3f", table->GetValueByName(row, column[0]).ToDouble());
    }
    std::printf("\n");
  }
  std::printf("total %lld cells, %.3f %%\n", totalCells, totalShare);

  vtkNew<vtkTerroirOverlayView> view;
  view->SetInputData(terrain);
  view->SetArrayName("ClusterId"); // the Clusters preset; the legend shows each zone's share
  view->SetModeToMap();
  view->SetTitle("Ecological zones");
  view->SetWidth(400);
  view->SetHeight(400);
  if (!view->WritePNG((out + "/zones_map.png").c_str()))
  {
    std::fprintf(stderr, "EcologicalZones: %s\n", view->GetLastError());
    return EXIT_FAILURE;
  }
  std::printf("wrote zones_map.png\n");
  return EXIT_SUCCESS;
}

// A parameter sweep: the same valley moved from the equator to 60 degrees north (the C++ twin of
// Examples/Python/LatitudeSweep.py; both print the same report).
//
// Pipeline: vtkTerroirDEMReader -> vtkExtractVOI (200 x 200 cells) ->
// vtkTerroirSolarIllumination (daily mode, 21 December), run once per latitude from 0 to 60
// degrees in steps of 10 (the longitude stays the terrain's). Each step prints the mean hours of
// direct sun and the mean clear-sky insolation and writes one map; the horizon map of the
// terrain is computed once and reused by every step, since only the sun moves.
//
// Run under an X display (or xvfb-run -a):
//   build/bin/LatitudeSweep --data Data --out example-output [--step DEG]
// For a finer sweep pass --step 5 (or 1); for the whole DEM drop the vtkExtractVOI stage.

#include "vtkDataArray.h"
#include "vtkExtractVOI.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"

#include "vtkTerroirDEMReader.h"
#include "vtkTerroirOverlayView.h"
#include "vtkTerroirSolarIllumination.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace
{
/// Mean of the first component over the finite values.
double Mean(vtkDataArray* a)
{
  double sum = 0.0;
  long long n = 0;
  for (vtkIdType t = 0; t < a->GetNumberOfTuples(); ++t)
  {
    const double v = a->GetComponent(t, 0);
    if (std::isfinite(v))
    {
      sum += v;
      ++n;
    }
  }
  return n ? sum / n : std::nan("");
}
}

int main(int argc, char* argv[])
{
  const char* env = std::getenv("TERROIR_DATA_DIR");
  std::string data = env && *env ? env : TERROIR_EXAMPLES_DATA_DIR;
  std::string out = "example-output";
  int step = 10;
  for (int i = 1; i < argc; ++i)
  {
    const std::string option = argv[i];
    if (i + 1 < argc && (option == "--data" || option == "--out"))
    {
      (option == "--data" ? data : out) = argv[++i];
    }
    else if (i + 1 < argc && option == "--step" && std::atoi(argv[i + 1]) > 0)
    {
      step = std::atoi(argv[++i]);
    }
    else
    {
      std::fprintf(stderr, "usage: %s [--data DIR] [--out DIR] [--step DEG]\n", argv[0]);
      return EXIT_FAILURE;
    }
  }
  std::filesystem::create_directories(out);

  vtkNew<vtkTerroirDEMReader> reader;
  reader->SetFileName((data + "/sagehen_creek_ca/sagehen_dem_utm11n_10m.tif").c_str());
  vtkNew<vtkExtractVOI> crop;
  crop->SetInputConnection(reader->GetOutputPort());
  crop->SetVOI(380, 579, 250, 449, 0, 0);

  vtkNew<vtkTerroirSolarIllumination> sun;
  sun->SetInputConnection(crop->GetOutputPort());
  sun->SetModeToDaily();
  sun->SetYear(2025);
  sun->SetMonth(12);
  sun->SetDay(21);

  vtkNew<vtkTerroirOverlayView> view;
  view->SetArrayName("IlluminationHours");
  view->SetUseCustomRange(true);
  view->SetRange(0.0, 12.0); // one scale for every step, so the pictures compare
  view->SetWidth(300);
  view->SetHeight(300);

  std::printf("latitude  mean_sun_h  mean_insolation_kWh/m2\n");
  for (int latitude = 0; latitude <= 60; latitude += step)
  {
    sun->SetLatitude(latitude);
    sun->Update();
    vtkImageData* terrain = sun->GetOutput();
    if (terrain->GetNumberOfPoints() == 0)
    {
      std::fprintf(stderr, "LatitudeSweep: the illumination stage failed (see above)\n");
      return EXIT_FAILURE;
    }
    vtkPointData* points = terrain->GetPointData();
    std::printf("%8d  %10.4f  %10.4f\n",
      latitude,
      Mean(points->GetArray("IlluminationHours")),
      Mean(points->GetArray("Insolation")) / 1000.0);
    view->SetInputData(terrain);
    const std::string title = "21 December, " + std::to_string(latitude) + " N";
    view->SetTitle(title.c_str());
    char name[32];
    std::snprintf(name, sizeof(name), "sweep_lat%02d.png", latitude);
    if (!view->WritePNG((out + "/" + name).c_str()))
    {
      std::fprintf(stderr, "LatitudeSweep: %s\n", view->GetLastError());
      return EXIT_FAILURE;
    }
    std::printf("wrote %s\n", name);
  }
  return EXIT_SUCCESS;
}

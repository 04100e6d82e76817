// Slope and July temperature maps of a DEM, saved as PNG (the C++ twin of
// Examples/Python/SlopeTemperatureMaps.py; both print the same report).
//
// Pipeline: vtkTerroirDEMReader -> vtkTerroirSlope -> vtkTerroirTemperature, then two
// vtkTerroirOverlayView pictures: a top-down slope map and a 3-D relief coloured by the July
// temperature.
//
// Run under an X display (or xvfb-run -a):
//   build/bin/SlopeTemperatureMaps --data Data --out example-output
// Uses the whole bundled Sagehen Creek DEM (786 x 720 cells of 10 m); any DEM that GDAL reads
// works: change the file name below.

#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"

#include "vtkTerroirDEMReader.h"
#include "vtkTerroirOverlayView.h"
#include "vtkTerroirSlope.h"
#include "vtkTerroirTemperature.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace
{
/// Mean of one component over the finite values.
double Mean(vtkDataArray* a, int component)
{
  double sum = 0.0;
  long long n = 0;
  for (vtkIdType t = 0; t < a->GetNumberOfTuples(); ++t)
  {
    const double v = a->GetComponent(t, component);
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
  for (int i = 1; i < argc; ++i)
  {
    const std::string option = argv[i];
    if (i + 1 < argc && (option == "--data" || option == "--out"))
    {
      (option == "--data" ? data : out) = argv[++i];
    }
    else
    {
      std::fprintf(stderr, "usage: %s [--data DIR] [--out DIR]\n", argv[0]);
      return EXIT_FAILURE;
    }
  }
  std::filesystem::create_directories(out);

  // Read the DEM: elevation in metres, georeference in field data.
  vtkNew<vtkTerroirDEMReader> reader;
  reader->SetFileName((data + "/sagehen_creek_ca/sagehen_dem_utm11n_10m.tif").c_str());

  // Slope (degrees), aspect and normals, as `gdaldem slope` computes them.
  vtkNew<vtkTerroirSlope> slope;
  slope->SetInputConnection(reader->GetOutputPort());

  // Monthly temperature: 2 degC in January and 20 degC in July at sea level, 6.4 degC/km cooler
  // with height (the filter's defaults, spelled out here to show the knobs).
  vtkNew<vtkTerroirTemperature> temperature;
  temperature->SetInputConnection(slope->GetOutputPort());
  temperature->SetSeaLevelTemperatureColdest(2.0);
  temperature->SetSeaLevelTemperatureWarmest(20.0);
  temperature->SetLapseRate(6.4);
  temperature->Update();
  vtkImageData* terrain = temperature->GetOutput();
  if (terrain->GetNumberOfPoints() == 0)
  {
    std::fprintf(stderr, "SlopeTemperatureMaps: the pipeline failed (see the error above)\n");
    return EXIT_FAILURE;
  }

  int dims[3];
  terrain->GetDimensions(dims);
  vtkPointData* points = terrain->GetPointData();
  vtkDataArray* elevation = points->GetArray("Elevation");
  vtkDataArray* slopes = points->GetArray("Slope");
  vtkDataArray* temperatures = points->GetArray("Temperature"); // Jan..Dec
  std::printf("grid: %d x %d cells of %.1f m\n", dims[0], dims[1], terrain->GetSpacing()[0]);
  std::printf(
    "elevation: min %.2f max %.2f m\n", elevation->GetRange()[0], elevation->GetRange()[1]);
  std::printf("slope: mean %.3f max %.3f deg\n", Mean(slopes, 0), slopes->GetRange()[1]);
  std::printf("july temperature: min %.3f mean %.3f max %.3f degC\n",
    temperatures->GetRange(6)[0],
    Mean(temperatures, 6),
    temperatures->GetRange(6)[1]);

  // One overlay picture, 400 x 400 pixels, legend on the right.
  auto save = [&](const char* array, int component, int mode, const char* title, const char* name)
  {
    vtkNew<vtkTerroirOverlayView> view;
    view->SetInputData(terrain);
    view->SetArrayName(array);
    view->SetArrayComponent(component);
    view->SetMode(mode);
    view->SetTitle(title);
    view->SetWidth(400);
    view->SetHeight(400);
    if (!view->WritePNG((out + "/" + name).c_str()))
    {
      std::fprintf(stderr, "SlopeTemperatureMaps: %s\n", view->GetLastError());
      std::exit(EXIT_FAILURE);
    }
    std::printf("wrote %s\n", name);
  };
  save("Slope", 0, vtkTerroirOverlayView::Map, "Slope", "slope_map.png");
  save("Temperature",
    6,
    vtkTerroirOverlayView::Relief,
    "July temperature",
    "temperature_july_relief.png");
  return EXIT_SUCCESS;
}

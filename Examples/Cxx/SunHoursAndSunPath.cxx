// Monthly hours of direct sun in a valley, and a plot of the sun's path (the C++ twin of
// Examples/Python/SunHoursAndSunPath.py; both print the same report).
//
// Pipeline: vtkTerroirDEMReader -> vtkExtractVOI (the Sagehen Creek valley, 256 x 256 cells) ->
// vtkTerroirSolarIllumination (monthly mode: the 15th of every month, 10-minute steps, cast
// shadows from the terrain). Prints each month's mean, minimum and maximum hours of sun and mean
// clear-sky insolation, writes a map of the December sun hours and plots the sun's elevation
// against its azimuth for three days with VTK's charts (vtkChartXY).
//
// Run under an X display (or xvfb-run -a):
//   build/bin/SunHoursAndSunPath --data Data --out example-output
// The crop keeps the run short. For the whole DEM drop the vtkExtractVOI stage (about 1.5 s
// more on two cores); shadows cast from outside a crop are not seen.

#include "vtkAxis.h"
#include "vtkChartXY.h"
#include "vtkContextScene.h"
#include "vtkContextView.h"
#include "vtkDataArray.h"
#include "vtkExtractVOI.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPNGWriter.h"
#include "vtkPlot.h"
#include "vtkPointData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTable.h"
#include "vtkWindowToImageFilter.h"

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
  const char* display = std::getenv("DISPLAY");
  if (!display || !*display)
  {
    // VTK 9.1 aborts the process when a window cannot reach an X display: check first.
    std::fprintf(
      stderr, "SunHoursAndSunPath: no X display (DISPLAY unset); run under xvfb-run -a\n");
    return EXIT_FAILURE;
  }

  vtkNew<vtkTerroirDEMReader> reader;
  reader->SetFileName((data + "/sagehen_creek_ca/sagehen_dem_utm11n_10m.tif").c_str());

  // The valley of Sagehen Creek: columns 330..585, rows 230..485 (row 0 is the south edge).
  vtkNew<vtkExtractVOI> valley;
  valley->SetInputConnection(reader->GetOutputPort());
  valley->SetVOI(330, 585, 230, 485, 0, 0);

  vtkNew<vtkTerroirSolarIllumination> sun;
  sun->SetInputConnection(valley->GetOutputPort());
  sun->SetModeToMonthly(); // IlluminationHours and Insolation, 12 components (Jan..Dec)
  sun->SetYear(2025);
  sun->SetMonthlyDay(15);
  sun->SetTimeStep(10.0); // minutes
  sun->Update();
  vtkImageData* terrain = sun->GetOutput();
  if (terrain->GetNumberOfPoints() == 0)
  {
    std::fprintf(stderr, "SunHoursAndSunPath: the illumination stage failed (see above)\n");
    return EXIT_FAILURE;
  }

  vtkDataArray* hours = terrain->GetPointData()->GetArray("IlluminationHours");
  vtkDataArray* insolation = terrain->GetPointData()->GetArray("Insolation"); // Wh/m2 per day
  vtkDataArray* frame = terrain->GetFieldData()->GetArray("SolarFrame"); // lat, lon, grid north
  int dims[3];
  terrain->GetDimensions(dims);
  std::printf("valley: %d x %d cells, latitude %.4f, longitude %.4f\n",
    dims[0],
    dims[1],
    frame->GetComponent(0, 0),
    frame->GetComponent(0, 1));
  std::printf("month  mean_h  min_h  max_h  insolation_kWh/m2\n");
  const char* months[] = {
    "Jan", "Feb", "Mar", "Apr", "May", "Jun", "Jul", "Aug", "Sep", "Oct", "Nov", "Dec"
  };
  for (int m = 0; m < 12; ++m)
  {
    std::printf("%s    %6.3f %6.3f %6.3f  %6.3f\n",
      months[m],
      Mean(hours, m),
      hours->GetRange(m)[0],
      hours->GetRange(m)[1],
      Mean(insolation, m) / 1000.0);
  }

  // Map of the December hours of sun on a fixed 0-10 h scale.
  vtkNew<vtkTerroirOverlayView> view;
  view->SetInputData(terrain);
  view->SetArrayName("IlluminationHours");
  view->SetArrayComponent(11);
  view->SetUseCustomRange(true);
  view->SetRange(0.0, 10.0);
  view->SetTitle("Hours of sun, 15 December");
  view->SetWidth(400);
  view->SetHeight(400);
  if (!view->WritePNG((out + "/sun_hours_december.png").c_str()))
  {
    std::fprintf(stderr, "SunHoursAndSunPath: %s\n", view->GetLastError());
    return EXIT_FAILURE;
  }
  std::printf("wrote sun_hours_december.png\n");

  // The sun's path: field data SunPositions holds one tuple per time step (Month, Day, UTCHours,
  // Azimuth, Elevation, GridAzimuth), azimuth clockwise from true north, degrees.
  vtkDataArray* positions = terrain->GetFieldData()->GetArray("SunPositions");
  vtkNew<vtkChartXY> chart;
  chart->SetShowLegend(true);
  const struct
  {
    int axis;
    const char* title;
    double low, high;
  } axes[] = { { vtkAxis::LEFT, "Sun elevation (degrees)", 0.0, 80.0 },
    { vtkAxis::BOTTOM, "Azimuth from north (degrees)", 45.0, 315.0 } };
  for (const auto& a : axes)
  {
    chart->GetAxis(a.axis)->SetTitle(a.title);
    chart->GetAxis(a.axis)->SetRange(a.low, a.high);
    chart->GetAxis(a.axis)->SetBehavior(vtkAxis::FIXED); // keep these ranges
  }
  const struct
  {
    int month;
    const char* label;
    unsigned char rgb[3];
  } days[] = { { 6, "15 June", { 220, 50, 32 } },
    { 3, "15 March", { 0, 114, 178 } },
    { 12, "15 December", { 90, 90, 90 } } };
  for (const auto& day : days)
  {
    vtkNew<vtkTable> table;
    vtkNew<vtkFloatArray> azimuth;
    azimuth->SetName("Azimuth");
    vtkNew<vtkFloatArray> elevation;
    elevation->SetName(day.label);
    for (vtkIdType t = 0; t < positions->GetNumberOfTuples(); ++t)
    {
      if (positions->GetComponent(t, 0) == day.month && positions->GetComponent(t, 4) > 0.0)
      {
        azimuth->InsertNextValue(positions->GetComponent(t, 3));
        elevation->InsertNextValue(positions->GetComponent(t, 4));
      }
    }
    table->AddColumn(azimuth);
    table->AddColumn(elevation);
    std::printf("sun path %s: %lld steps above the horizon, highest %.3f deg\n",
      day.label,
      static_cast<long long>(azimuth->GetNumberOfTuples()),
      elevation->GetRange()[1]);
    vtkPlot* line = chart->AddPlot(vtkChart::LINE);
    line->SetInputData(table, 0, 1);
    line->SetColor(day.rgb[0], day.rgb[1], day.rgb[2], 255);
    line->SetWidth(2.0);
  }

  vtkNew<vtkContextView> chartView;
  chartView->GetScene()->AddItem(chart);
  chartView->GetRenderer()->SetBackground(1.0, 1.0, 1.0);
  vtkRenderWindow* window = chartView->GetRenderWindow();
  window->SetSize(480, 360);
  window->SetMultiSamples(0);
  window->OffScreenRenderingOn();
  window->Render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  vtkNew<vtkPNGWriter> png;
  png->SetInputConnection(grab->GetOutputPort());
  png->SetFileName((out + "/sun_path.png").c_str());
  png->Write();
  if (png->GetErrorCode() != 0)
  {
    std::fprintf(stderr, "SunHoursAndSunPath: cannot write %s/sun_path.png\n", out.c_str());
    return EXIT_FAILURE;
  }
  std::printf("wrote sun_path.png\n");
  return EXIT_SUCCESS;
}

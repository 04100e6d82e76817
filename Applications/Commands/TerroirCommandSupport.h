/**
 * @file TerroirCommandSupport.h
 * @brief What several `terroir` commands share beyond TerroirApp.h: the command line's
 * temperature, climate and illumination settings applied to their filters, array statistics
 * for the reports, a filter run as a timed stage, and the PNG overlay module (loaded with
 * dlopen only when a command draws).
 */
#ifndef TerroirCommandSupport_h
#define TerroirCommandSupport_h

#include "TerroirApp.h"
#include "TerroirCommandLine.h"
#include "TerroirOverlayPlugin.h"

#include "vtkImageData.h"
#include "vtkSmartPointer.h"
#include "vtkTerroirComputeContext.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <string>

class vtkDataArray;
class vtkPolyData;
class vtkTerroirSolarIllumination;
class vtkTerroirTemperature;

namespace terroir
{
namespace app
{

/// Reads the climate table of --climate (before any other work) into the 12 monthly sea-level
/// temperatures; for `run` (soil given) also its rain, when it has both series and neither
/// --precip nor --intensity was given. Throws Failure naming the file.
void LoadClimate(TemperatureSettings& t, SoilWaterSettings* soil);

/// Sets the temperature filter from the command line's temperature settings.
void ApplyTemperature(const TemperatureSettings& t, vtkTerroirTemperature* filter);

/// Sets the illumination filter from the command line's illumination settings.
void ApplyIllumination(const IlluminationSettings& s, vtkTerroirSolarIllumination* filter);

/// Minimum, maximum and mean of the non-NaN values of one component, and how many there are.
struct Statistics
{
  double Min = 0, Max = 0, Mean = 0;
  long long Valid = 0;
};
Statistics ArrayStatistics(vtkDataArray* array, int component);
/// {min, max, mean, valid_cells}, non-finite values as null.
nlohmann::json StatisticsJSON(const Statistics& s);

/// Runs a filter on `input` with progress and timing, records {seconds, backend, reason} as
/// stages[label], and returns the output (shallow copy).
template<typename Filter>
vtkSmartPointer<vtkImageData> RunStage(Filter* filter,
  vtkImageData* input,
  const std::string& label,
  nlohmann::json& stages)
{
  filter->SetInputData(input);
  WatchProgress(filter, label);
  const double t0 = Now();
  UpdateOrThrow(filter, label);
  const double seconds = Now() - t0;
  stages[label] = nlohmann::json{ { "seconds", seconds },
    { "backend", vtkTerroirComputeContext::GetBackendName(filter->GetLastBackend()) },
    { "reason", filter->GetLastBackendReason() ? filter->GetLastBackendReason() : "" } };
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->ShallowCopy(filter->GetOutput());
  return out;
}

/// The first value of a one-value field-data array (NaN when missing), or of a string array.
double FieldNumber(vtkImageData* image, const char* name);
/// Writes `data` as VTK XML polydata (.vtp, appended), temporary file then rename; throws
/// Failure naming `path`.
void WriteVTP(vtkPolyData* data, const std::string& path);
std::string FieldText(vtkImageData* image, const char* name);

/// True when DISPLAY is set (PNG overlays and the window need an X server).
bool HaveDisplay();

/// Loads `symbol` of the module `name` (beside the program's libraries, or the file named by
/// the environment variable `envName`); throws Failure naming `what` when it cannot.
void* LoadPluginSymbol(const char* name, const char* symbol, const char* envName, const char* what);

/// The overlay module's writer (TerroirOverlayPlugin.cxx), loaded once; throws when missing.
TerroirWriteOverlayFunction OverlayWriter();

/// While one is alive on a thread, the overlays that thread writes share one view (one window,
/// GL context and surface; TerroirOverlayPlugin.h), released when the outermost batch ends.
/// Without a batch each overlay gets its own view.
class OverlayBatch
{
public:
  OverlayBatch();
  ~OverlayBatch();
  OverlayBatch(const OverlayBatch&) = delete;
  OverlayBatch& operator=(const OverlayBatch&) = delete;
};

/// Writes one component of `array` as a PNG overlay (relief, or top-down when `map`).
void WriteOverlay(vtkImageData* image,
  const std::string& array,
  int component,
  const std::string& preset,
  const std::string& title,
  const std::string& path,
  bool overwrite,
  bool map = false);

/// Writes an overlay of component 0 (arguments: image, array, preset, title, path, map view).
using OverlayWriterFunction = std::function<void(vtkImageData*,
  const std::string&,
  const std::string&,
  const std::string&,
  const std::string&,
  bool)>;

/// The overlay writer of a command: refuses without an X display, honours --overwrite.
OverlayWriterFunction CommandOverlayWriter(const CommandLine& c);

} // namespace app
} // namespace terroir

#endif

/**
 * @file RunState.h
 * @brief What the stages of `terroir run` share (Run.cxx): the state carried from stage to
 * stage, the stage objects, and the reports written at the end (RunReport.cxx).
 */
#ifndef TerroirRunState_h
#define TerroirRunState_h

#include "TerroirApp.h"
#include "TerroirCommandLine.h"

#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"

#include "vtkTerroirComputeContext.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

namespace terroir
{
namespace app
{

/// What `terroir run` carries from stage to stage: its settings, the terrain with every array
/// computed so far, the report and the files it writes.
struct RunState
{
  explicit RunState(const CommandLine& line)
    : Line(line)
  {
  }
  const CommandLine& Line;
  std::string Dem;
  bool Bundled = false; ///< the bundled DEM: its rivers are scored against its NHD flowlines
  int Backend = vtkTerroirComputeContext::Auto;
  bool Png = true;
  std::filesystem::path Out;
  vtkSmartPointer<vtkImageData> Result;
  int Dims[3] = { 0, 0, 0 };
  double Spacing[3] = { 0, 0, 0 };
  double LatLon[2] = { NAN, NAN };
  bool Located = false;
  bool Illuminate = false;
  double HorizonMapSeconds = 0.0;
  /// On the bundled DEM with PNGs: each cell's category of the comparison with NHD's rivers.
  vtkSmartPointer<vtkUnsignedCharArray> RiverComparison;
  std::string ClusterCSV; ///< clusters.csv
  nlohmann::ordered_json ClusterSummary;
  nlohmann::json Report;
  nlohmann::json Stages;
  std::vector<std::string> Outputs;
  std::set<std::string> Selected; ///< the files this run writes (--outputs), reports aside
  GeoTIFFLayout Tiff;             ///< --tiff-compression, --tiff-layout, ...

  std::string File(const char* name) const { return (this->Out / name).string(); }
  bool Overwrite() const { return this->Line.Overwrite; }
  int Clusters() const { return this->Line.KMeans.Clusters; }
  bool Wants(const std::string& file) const { return this->Selected.count(file) > 0; }
};

/// The files of a stage, by kind: rasters come first in the report's list, then the reports,
/// the tables and the pictures.
struct RunFiles
{
  std::vector<std::string> Rasters, Tables, Pictures;
};

/// One stage of `terroir run`: the files it writes (known before any work, so that a run that
/// would overwrite is refused before it starts), what it computes, and how it writes them.
/// Write runs on the writer thread (RunWriter.h) while the stages after it compute: it reads
/// `image` (copies of the stage's arrays) and what its own Compute left in the state, which
/// later stages do not change.
struct RunStep
{
  const char* Name;
  void (*Files)(const RunState&, RunFiles&);
  void (*Compute)(RunState&);
  void (*Write)(const RunState&, vtkImageData* image);
};

/// The stages' names in the report's tables, in order.
const std::vector<const char*>& ReportedStages();
/// Statistics of every point array (per month for the 12-component ones).
nlohmann::json ArraysReport(vtkImageData* result);
/// report.json (scripts) and report.md (people), both written through a temporary file.
void WriteReports(RunState& r, nlohmann::json& arrays);
/// One line per stage on the terminal.
void PrintSummary(RunState& r);

} // namespace app
} // namespace terroir

#endif

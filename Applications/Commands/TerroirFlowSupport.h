/**
 * @file TerroirFlowSupport.h
 * @brief The water-flow commands of `terroir`: waterflow (the hydrostatic simulation), flowacc
 * (the D8 baseline) and validate (both scored against mapped rivers).
 */
#ifndef TerroirFlowSupport_h
#define TerroirFlowSupport_h

#include "TerroirCommandLine.h"
#include "TerroirCommandSupport.h" // For OverlayWriterFunction

#include "GridView.h"
#include "RiverValidation.h"

#include "vtkSmartPointer.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

class vtkDataArray;
class vtkImageData;
class vtkImageAlgorithm;

namespace terroir
{
namespace app
{

/// Mapped rivers rasterised on a DEM's grid, and the area they are scored in.
struct RiverReference
{
  /**
   * Rasterises `reference` (river lines, any OGR format) on the grid of `terrain` and reads the
   * area (`maskPath`: a raster on the grid or polygons; empty: the cells with heights). Throws
   * Failure on an area that misses the DEM or holds cells without height.
   */
  RiverReference(vtkImageData* terrain,
    const std::string& dem,
    const std::string& reference,
    const std::string& maskPath,
    bool allowNetwork);
  RiverReference(const RiverReference&) = delete; // View points into the vectors
  RiverReference& operator=(const RiverReference&) = delete;
  std::vector<std::uint8_t> Reference; ///< 1 on mapped river cells
  std::vector<std::uint8_t> Area;      ///< 1 inside the scored area
  std::vector<double> RowDx, RowDy;    ///< per-row spacing (geographic grids)
  GridView<std::uint8_t> View;         ///< the grid, over Reference
  std::size_t Cells = 0;               ///< reference cells inside the area
};

/// The scores of one method.
struct MethodScores
{
  std::string name;
  std::string measure; ///< what the threshold applies to
  double threshold = 0.0;
  bool lengthMatched = true;
  hydrology::RiverScores at30;
  hydrology::RiverScores at60;
};

/**
 * Scores a river measure (discharge, accumulation): its channel cells at or above the
 * threshold (the length-matching one unless `userThreshold` is finite) against the reference,
 * within 30 and 60 m; `simulated` gets the river cells (for overlays).
 */
MethodScores ScoreRiverMeasure(const std::string& name,
  const std::string& measure,
  const std::vector<double>& values,
  double userThreshold,
  const RiverReference& reference,
  std::vector<std::uint8_t>& simulated);

/// A method's scores as the JSON of `terroir validate --json`.
nlohmann::json MethodScoresJson(const MethodScores& m);

/// A point array as doubles; throws Failure when it is missing.
std::vector<double> PointArrayValues(vtkImageData* image, const char* name);

/// Runs the simulation on `terrain` with the options of `s` (the soil-water chain first for
/// --month and --annual; `defaultMode` when --mode is not given); `seconds` gets its time.
vtkSmartPointer<vtkImageData> SimulateWaterFlow(const WaterFlowSettings& s,
  vtkImageData* terrain,
  const std::string& backend,
  double& seconds,
  const char* defaultMode = "pulse");

/// One line on what the simulation did (iterations, stop reason, volumes).
void PrintWaterFlow(vtkImageData* out, double seconds);

/// `v` with `digits` decimals.
std::string Fixed(double v, int digits);

/// A point array as doubles (NaN stays NaN), absolute values when `absolute`.
std::vector<double> AsDoubles(vtkDataArray* a, bool absolute);

/// Scores the channel cells of `values` at or above the threshold (length-matched unless
/// `userThreshold` is finite) against `reference` within `area`; `simulated` gets them.
MethodScores Score(const std::string& name,
  const std::string& measure,
  const std::vector<double>& values,
  double userThreshold,
  const GridView<std::uint8_t>& reference,
  const std::vector<std::uint8_t>& area,
  std::vector<std::uint8_t>& simulated);

/// One tolerance's scores as JSON.
nlohmann::json ScoresJson(const hydrology::RiverScores& s);

} // namespace app
} // namespace terroir

#endif

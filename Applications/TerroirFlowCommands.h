/**
 * @file TerroirFlowCommands.h
 * @brief The water-flow commands of `terroir`: waterflow (the hydrostatic simulation), flowacc
 * (the D8 baseline) and validate (both scored against mapped rivers).
 */
#ifndef TerroirFlowCommands_h
#define TerroirFlowCommands_h

#include "TerroirCommandLine.h"
#include "TerroirCommandSupport.h" // For OverlayWriterFunction

#include "GridView.h"
#include "RiverValidation.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

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

int CommandWaterFlow(const CommandLine& c);
int CommandFlowAccumulation(const CommandLine& c);
int CommandValidate(const CommandLine& c);

} // namespace app
} // namespace terroir

#endif

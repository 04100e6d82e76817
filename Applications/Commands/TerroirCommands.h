/**
 * @file TerroirCommands.h
 * @brief The commands of the `terroir` program: one function per command, each in its own
 * file of Applications/Commands/ (or, for the soil-water, flow and cluster commands, beside the
 * helpers `terroir run` shares with them), and the registry that dispatches to them.
 *
 * Every command takes the parsed command line (TerroirCommandLine.h: its options, defaults and
 * checks) and returns the exit code; it throws Failure (TerroirApp.h) for a one-line error.
 * The names and summaries are TerroirCommandLine's CommandDescriptions(); Commands() binds each to
 * its function, and TestCommandLine checks that the two lists agree.
 */
#ifndef TerroirCommands_h
#define TerroirCommands_h

#include "TerroirCommandLine.h"

#include <string>
#include <vector>

class vtkPolyData;

namespace terroir
{
namespace app
{

using CommandFunction = int (*)(const CommandLine&);

/// A command's name (as CommandDescriptions() spells it) and its code.
struct Command
{
  const char* Name;
  CommandFunction Run;
};

/// Every command of the program.
const std::vector<Command>& Commands();

/// Runs `line.Command`: reads --climate first (its temperatures, and for `run` its rain, join
/// the settings), then calls the command. Throws Failure on an unknown name.
int RunCommand(CommandLine& line);

int CommandRun(const CommandLine& c);              // Run.cxx
int CommandSlope(const CommandLine& c);            // Slope.cxx
int CommandTemperature(const CommandLine& c);      // Temperature.cxx
int CommandIllumination(const CommandLine& c);     // Illumination.cxx
int CommandInfo(const CommandLine& c);             // Info.cxx
int CommandFractal(const CommandLine& c);          // Fractal.cxx
int CommandGenerate(const CommandLine& c);         // Generate.cxx
int CommandView(const CommandLine& c);             // View.cxx
int CommandInfiltration(const CommandLine& c);     // Infiltration.cxx
int CommandHumidity(const CommandLine& c);         // Humidity.cxx
int CommandFloodFill(const CommandLine& c);        // FloodFill.cxx
int CommandWaterFlow(const CommandLine& c);        // WaterFlow.cxx
int CommandFlowAccumulation(const CommandLine& c); // FlowAccumulation.cxx
int CommandValidate(const CommandLine& c);         // Validate.cxx
int CommandKMeans(const CommandLine& c);           // KMeans.cxx
int CommandMorphometry(const CommandLine& c);      // Morphometry.cxx
int CommandErosion(const CommandLine& c);          // Erosion.cxx
int CommandPlants(const CommandLine& c);           // Plants.cxx
// new-filter.sh: commands

/// One GeoJSON property of WriteRiverLines: `key`, from the lines' cell array `array`.
struct LineProperty
{
  const char* key;
  const char* array;
  bool integer; ///< written as an integer, else as a number
};

/**
 * Writes a generator's rivers (polylines, port 1 of the island and RiverLand sources) as a
 * GeoJSON FeatureCollection of LineStrings in the lines' coordinates, each with `properties`;
 * with a CRS (EPSG:NNNN or WKT) the collection names it (GeoJSON 2008's named CRS, which GDAL
 * reads). Generate.cxx.
 */
void WriteRiverLines(vtkPolyData* rivers,
  const std::vector<LineProperty>& properties,
  const std::string& crs,
  const std::string& path,
  bool overwrite);

} // namespace app
} // namespace terroir

#endif

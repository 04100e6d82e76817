/**
 * @file TerroirCommandOptions.h
 * @brief The options of each `terroir` command, declared in the command's own file
 * (Commands/<Name>Options.cxx, beside its Run in Commands/<Name>.cxx) for the parser
 * (TerroirCommandLine.h: plain CLI11, no VTK, so that it can be unit-tested and fuzzed alone),
 * and the option helpers they share (Commands/TerroirCommandOptions.cxx).
 *
 * A command's CommandOptions declares its options on its CLI11 subcommand, bound into the
 * CommandLine (Add), and checks them once the command line is parsed (Check: throws
 * std::invalid_argument with one line naming the option). CommandDescriptions() (in
 * TerroirCommandLine.cxx) lists each command with its summary and its options' factory.
 */
#ifndef TerroirCommandOptions_h
#define TerroirCommandOptions_h

#include "TerroirCommandLine.h"

#include <CLI/CLI.hpp>

#include <memory>
#include <string>
#include <vector>

namespace terroir
{
namespace app
{

/// The options of one command (see the file comment).
class CommandOptions
{
public:
  virtual ~CommandOptions() = default;
  /// Declares the options on `sub`, bound into `line`.
  virtual void Add(CLI::App* sub, CommandLine& line) = 0;
  /// After parsing, when this command was given: checks and completes `line`.
  virtual void Check(CommandLine& line, const CLI::App& sub) = 0;
};

using CommandOptionsFactory = std::unique_ptr<CommandOptions> (*)();

std::unique_ptr<CommandOptions> MakeRunOptions();              // RunOptions.cxx
std::unique_ptr<CommandOptions> MakeSlopeOptions();            // SlopeOptions.cxx
std::unique_ptr<CommandOptions> MakeTemperatureOptions();      // TemperatureOptions.cxx
std::unique_ptr<CommandOptions> MakeIlluminationOptions();     // IlluminationOptions.cxx
std::unique_ptr<CommandOptions> MakeInfiltrationOptions();     // InfiltrationOptions.cxx
std::unique_ptr<CommandOptions> MakeHumidityOptions();         // HumidityOptions.cxx
std::unique_ptr<CommandOptions> MakeFloodFillOptions();        // FloodFillOptions.cxx
std::unique_ptr<CommandOptions> MakeWaterFlowOptions();        // WaterFlowOptions.cxx
std::unique_ptr<CommandOptions> MakeFlowAccumulationOptions(); // FlowAccumulationOptions.cxx
std::unique_ptr<CommandOptions> MakeValidateOptions();         // ValidateOptions.cxx
std::unique_ptr<CommandOptions> MakeKMeansOptions();           // KMeansOptions.cxx
std::unique_ptr<CommandOptions> MakeViewOptions();             // ViewOptions.cxx
std::unique_ptr<CommandOptions> MakeBenchOptions();            // BenchOptions.cxx
std::unique_ptr<CommandOptions> MakeInfoOptions();             // InfoOptions.cxx
std::unique_ptr<CommandOptions> MakeFractalOptions();          // FractalOptions.cxx
std::unique_ptr<CommandOptions> MakeGenerateOptions();         // GenerateOptions.cxx
std::unique_ptr<CommandOptions> MakeMorphometryOptions();      // MorphometryOptions.cxx
std::unique_ptr<CommandOptions> MakeErosionOptions();          // ErosionOptions.cxx
std::unique_ptr<CommandOptions> MakePlantsOptions();           // PlantsOptions.cxx
// new-filter.sh: options factories

// ---- helpers the commands' options share (TerroirCommandOptions.cxx) ------------------------

/// A finite number within [lo, hi] (CLI11's own Range lets NaN through).
CLI::Validator FiniteIn(double lo, double hi);
/// A file name ending in one of `extensions` (case-insensitive).
CLI::Validator EndsWith(const std::vector<std::string>& extensions);
/// The raster outputs a command writes: .tif, .tiff, .vti.
const std::vector<std::string>& RasterOutputs();
/// --backend, --overwrite, --allow-network-paths and --z-unit.
void AddCommonOptions(CLI::App* sub, CommandLine& line);
/// --z-unit alone (info, view).
void AddZUnitOption(CLI::App* sub, CommandLine& line);
/// Throws when one of `extras` (non-empty) names the same file as OUT.
void CheckNotOutput(const std::vector<const std::string*>& extras, const std::string& output);
/// Throws "the input file name is empty" when it is.
void CheckInputGiven(const CommandLine& line);

void AddTemperatureOptions(CLI::App* app, TemperatureSettings& t, std::string& monthly);
void CheckTemperature(TemperatureSettings& t, const std::string& monthly);

/// Adds --lat and --lon (run, illumination, view).
void AddLocationOptions(CLI::App* app, IlluminationSettings& s);

/// The string options of the soil-water commands, checked after parsing (CheckSoilWater).
struct SoilWaterText
{
  std::string Precipitation;
  std::string Intensity;
  std::vector<std::string> Fill, SlopeRule, PaintRaster, PaintPolygons, SoilRaster, SoilPolygons;
  std::vector<CLI::Option*> OperationOptions; ///< in the order of the vectors above
};
void AddClimateOptions(CLI::App* app, SoilWaterText& text);
/// The infiltration operations, applied in the order given (infiltration, humidity).
void AddInfiltrationOptions(CLI::App* app,
  SoilWaterSettings& s,
  SoilWaterText& text,
  bool withRateInput);
void CheckSoilWater(SoilWaterSettings& s, const SoilWaterText& text, const CLI::App& app);

void AddFloodFillOptions(CLI::App* app,
  FloodFillSettings& s,
  std::vector<std::string>& seeds,
  std::vector<std::string>& cells);
void CheckFloodFill(FloodFillSettings& s,
  const std::vector<std::string>& seeds,
  const std::vector<std::string>& cells,
  const CLI::App& app);

void AddWaterFlowOptions(CLI::App* app, WaterFlowSettings& s);
void CheckWaterFlow(const WaterFlowSettings& s, const CLI::App& app);

/// --features NAME[:WEIGHT],... into the k-means settings.
void ParseFeatures(const std::string& text, KMeansSettings& s);

} // namespace app
} // namespace terroir

#endif

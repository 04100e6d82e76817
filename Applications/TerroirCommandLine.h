/**
 * @file TerroirCommandLine.h
 * @brief The `terroir` command line parsed into plain settings (CLI11, no VTK), so that parsing
 * can be unit-tested and fuzzed on its own (Testing/Fuzz/FuzzCommandLine.cxx).
 *
 * ParseCommandLine never prints and never exits: it fills a CommandLine, or says what to print
 * and which exit status to return (help: the text and 0; a bad option: one line and 2).
 * Every number is checked here (finite, within its documented range) and every output file
 * name must end in a format the command writes, so that a bad command line is refused before
 * any file is read or any work is done.
 */
#ifndef TerroirCommandLine_h
#define TerroirCommandLine_h

#include <string>
#include <vector>

namespace terroir
{
namespace app
{

/// Options of the temperature model (`run`, `temperature`).
struct TemperatureSettings
{
  double Coldest = 2.0;            ///< sea-level temperature of the coldest month, C
  double Warmest = 20.0;           ///< sea-level temperature of the warmest month, C
  int ColdestMonth = 0;            ///< 1..12, 0 = the hemisphere's default
  int WarmestMonth = 0;            ///< 1..12, 0 = the hemisphere's default
  std::vector<double> Monthly;     ///< 12 sea-level temperatures (--monthly), or empty
  std::string ClimateFile;         ///< --climate: a climate table with a temperature_c column
  double LapseRate = 6.4;          ///< C per km
  std::string Hemisphere = "auto"; ///< auto, north or south
};

/// Everything the command line says.
struct CommandLine
{
  std::string Command; ///< run, slope, temperature, bench, info or fractal
  bool Verbose = false;
  std::string Backend = "auto"; ///< auto, cpu or gpu
  bool Overwrite = false;
  bool AllowNetwork = false;

  std::string Input;  ///< DEM / IN (run: empty = the bundled DEM)
  std::string Output; ///< OUT (run: --out folder)
  bool NoPng = false; ///< run

  double ZFactor = 1.0;     ///< slope
  bool Percent = false;     ///< slope
  std::string AspectOutput; ///< slope --aspect

  TemperatureSettings Temperature; ///< run, temperature

  int BenchSize = 2048;
  int BenchRepeat = 3;
  std::vector<std::string> BenchBackends{ "cpu", "gpu" };
  bool BenchBandwidth = false;
  std::string BenchJson;

  int FractalSize = 1024;
  int FractalSeed = 1;
  double FractalSpacing = 10.0;
};

/// What ParseCommandLine decided.
struct ParseOutcome
{
  bool Run = false;   ///< true: carry out `CommandLine::Command`
  int ExitCode = 0;   ///< when !Run: 0 after help, 2 after an error
  std::string Stdout; ///< help text to print when !Run
  std::string Error;  ///< one line (no newline) when ExitCode != 0
};

/// Parses `argv` (argv[0] is the program name). See the file comment.
ParseOutcome ParseCommandLine(int argc, const char* const* argv, CommandLine& line);

/// Parses "a,b,c" into numbers; throws std::invalid_argument with a one-line message naming
/// `option` and the first item that is not a finite number.
std::vector<double> ParseNumberList(const std::string& text, const std::string& option);

} // namespace app
} // namespace terroir

#endif

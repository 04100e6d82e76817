#include "TerroirCommandLine.h"
#include "TerroirCommandOptions.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace terroir
{
namespace app
{
namespace
{
std::string OneLine(std::string text)
{
  std::replace(text.begin(), text.end(), '\n', ' ');
  while (!text.empty() && text.back() == ' ')
  {
    text.pop_back();
  }
  return text;
}

//------------------------------------------------------------------------------
/// Every command: name, summary (--help) and the factory of its options (Commands/*Options.cxx).
struct CommandEntry
{
  const char* Name;
  const char* Summary;
  CommandOptionsFactory Options;
};

const std::vector<CommandEntry>& CommandEntries()
{
  static const std::vector<CommandEntry> commands = {
    { "run", "Run every filter on a DEM (default: bundled Sagehen DEM)", MakeRunOptions },
    { "slope", "Slope in degrees (Horn 1981, as gdaldem slope)", MakeSlopeOptions },
    { "temperature", "Monthly temperature from a lapse rate", MakeTemperatureOptions },
    { "illumination",
      "Cast shadows, hours of direct sun and clear-sky insolation",
      MakeIlluminationOptions },
    { "infiltration",
      "Infiltration rate map (mm/h) from fill, slope-rule and paint operations",
      MakeInfiltrationOptions },
    { "humidity",
      "Monthly soil humidity, its weighted average and standing water (mm)",
      MakeHumidityOptions },
    { "floodfill",
      "Lakes: flood fill from seeds, or every closed depression (priority-flood)",
      MakeFloodFillOptions },
    { "waterflow",
      "Rivers and lakes: the hydrostatic water-flow simulation of Long (2016)",
      MakeWaterFlowOptions },
    { "flowacc",
      "Flow accumulation after priority-flood filling: D8, MFD or D-infinity (the classic "
      "baselines)",
      MakeFlowAccumulationOptions },
    { "validate",
      "Score simulated rivers against mapped ones (precision, recall, F1 at 30 and 60 m)",
      MakeValidateOptions },
    { "kmeans",
      "Ecological zones: k-means clustering of terrain resources, after Long (2016), ch. 4",
      MakeKMeansOptions },
    { "morphometry",
      "Landscape statistics: hypsometry, slope, drainage density, Horton ratios, Hack's law, "
      "closed depressions",
      MakeMorphometryOptions },
    { "erosion",
      "Hydraulic and thermal erosion on the virtual-pipe model (Weiss 2015, Dunn 2015)",
      MakeErosionOptions },
    { "plants",
      "Plants for each ecological zone: point patterns learned from an exemplar, or hard-core "
      "(Long 2016, section 2.2)",
      MakePlantsOptions },
    // new-filter.sh: commands
    { "view",
      "Interactive window: relief, overlays, sliders, lakes (default: bundled Sagehen DEM)",
      MakeViewOptions },
    { "bench", "Time each stage per backend on a synthetic DEM", MakeBenchOptions },
    { "info", "Grid and georeference of a DEM", MakeInfoOptions },
    { "fractal", "Write a seeded synthetic DEM (benchmarks, tests)", MakeFractalOptions },
    { "generate",
      "Terrain from nothing: a polygon-map island with biomes and rivers (Weiss 2015) or "
      "river-first terrain (RiverLand, Jensen 2011)",
      MakeGenerateOptions },
  };
  return commands;
}
} // namespace

//------------------------------------------------------------------------------
const std::vector<CommandDescription>& CommandDescriptions()
{
  static const std::vector<CommandDescription> commands = []
  {
    std::vector<CommandDescription> d;
    for (const CommandEntry& e : CommandEntries())
    {
      d.push_back({ e.Name, e.Summary });
    }
    return d;
  }();
  return commands;
}

//------------------------------------------------------------------------------
const char* CommandSummary(const std::string& name)
{
  for (const CommandDescription& c : CommandDescriptions())
  {
    if (name == c.Name)
    {
      return c.Summary;
    }
  }
  throw std::logic_error("no command named " + name);
}

const std::vector<std::string>& BenchStageNames()
{
  static const std::vector<std::string> names{
    "slope",
    "temperature",
    "horizon",
    "instant",
    "monthly",
    "infiltration",
    "humidity",
    "floodfill",
    "depressions",
    "flowacc",
    "waterflow",
    "kmeans",
    "morphometry",
    // new-filter.sh: stages
  };
  return names;
}

std::vector<double> ParseNumberList(const std::string& text, const std::string& option)
{
  std::vector<double> values;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ','))
  {
    std::size_t used = 0;
    double v = 0.0;
    try
    {
      v = std::stod(item, &used);
    }
    catch (const std::exception&)
    {
      used = 0;
    }
    if (used == 0 || used != item.size() || !std::isfinite(v))
    {
      throw std::invalid_argument(option + ": '" + item + "' is not a number");
    }
    values.push_back(v);
  }
  return values;
}

//------------------------------------------------------------------------------
void ApplySweepValue(WaterFlowSettings& s, const std::string& name, const std::string& value)
{
  if (name == "mode")
  {
    if (value != "pulse" && value != "rivers")
    {
      throw std::invalid_argument("--sweep: mode must be pulse or rivers, not '" + value + "'");
    }
    s.Mode = value;
    return;
  }
  const std::vector<double> v = ParseNumberList(value, "--sweep " + name);
  if (v.size() != 1)
  {
    throw std::invalid_argument("--sweep: '" + value + "' is not one number");
  }
  const double x = v[0];
  auto need = [&](bool ok, const char* range)
  {
    if (!ok)
    {
      throw std::invalid_argument(
        "--sweep: " + name + " = " + value + " is out of range (" + range + ")");
    }
  };
  if (name == "water")
  {
    need(x >= 0.0 && x <= 1e6, "0 to 1e6 mm");
    s.InitialWater = x;
  }
  else if (name == "rain")
  {
    need(x >= 1e-9 && x <= 1e6, "1e-9 to 1e6 mm/h");
    s.RainRate = x;
  }
  else if (name == "balance")
  {
    need(x >= 1e-9 && x <= 0.999, "1e-9 to 0.999");
    s.BalanceTolerance = x;
  }
  else if (name == "thinning")
  {
    need(x >= 0.0 && x <= 1.0, "0 to 1");
    s.Thinning = x;
  }
  else if (name == "settle")
  {
    need(x >= 0.0 && x <= 1e8 && x == std::floor(x), "a whole number, 0 to 1e8");
    s.Settle = static_cast<long long>(x);
  }
  else if (name == "max-iterations")
  {
    need(x >= 0.0 && x <= 1e8 && x == std::floor(x), "a whole number, 0 to 1e8");
    s.MaximumIterations = static_cast<long long>(x);
  }
  else if (name == "auto-stop")
  {
    need(x >= 0.0 && x <= 0.999, "0 to 0.999");
    s.AutoStop = x;
  }
  else if (name == "time")
  {
    need(x >= 0.0 && x <= 1e12, "0 to 1e12 s");
    s.Time = x;
  }
  else if (name == "iteration-duration")
  {
    need(x >= 1e-6 && x <= 1e9, "1e-6 to 1e9 s");
    s.IterationDuration = x;
  }
  else if (name == "river-threshold")
  {
    need(x >= 0.0 && x <= 1e18, "0 to 1e18");
    s.RiverThreshold = x;
  }
  else
  {
    throw std::invalid_argument("--sweep: unknown option '" + name +
      "' (water, rain, balance, thinning, settle, max-iterations, auto-stop, time, "
      "iteration-duration, river-threshold, mode)");
  }
}

void ParseSweep(const std::string& text, std::string& name, std::vector<std::string>& values)
{
  const std::size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 >= text.size())
  {
    throw std::invalid_argument(
      "--sweep needs NAME=V1,V2,... (e.g. rain=0.1,0.3,1), not '" + text + "'");
  }
  name = text.substr(0, eq);
  values.clear();
  std::stringstream ss(text.substr(eq + 1));
  std::string item;
  WaterFlowSettings probe;
  while (std::getline(ss, item, ','))
  {
    ApplySweepValue(probe, name, item);
    values.push_back(item);
  }
  if (values.empty())
  {
    throw std::invalid_argument("--sweep " + name + ": no value");
  }
}

ParseOutcome ParseCommandLine(int argc, const char* const* argv, CommandLine& line)
{
  line = CommandLine();
  ParseOutcome outcome;
  CLI::App app{ "terroir: terrain resources (slope, temperature, ...) from a DEM, as VTK filters",
    "terroir" };
  app.require_subcommand(1);
  app.fallthrough(); // -v is accepted after the command too
  app.add_flag("-v,--verbose", line.Verbose, "Show VTK's log (backend choice, timings)");
  // Each command declares its options (Commands/<Name>Options.cxx), in --help's order.
  std::vector<std::pair<CLI::App*, std::unique_ptr<CommandOptions>>> commands;
  for (const CommandEntry& e : CommandEntries())
  {
    CLI::App* sub = app.add_subcommand(e.Name, e.Summary);
    commands.emplace_back(sub, e.Options());
    commands.back().second->Add(sub, line);
  }
  try
  {
    // CLI11 wants a mutable argv; it does not modify the strings.
    app.parse(argc, const_cast<char**>(argv));
    for (auto& command : commands)
    {
      if (*command.first)
      {
        line.Command = command.first->get_name();
        command.second->Check(line, *command.first);
      }
    }
    outcome.Run = true;
  }
  catch (const CLI::CallForHelp&)
  {
    // CLI11 hands this to the command given, whose usage line then names the program too.
    outcome.Stdout = app.help();
  }
  catch (const CLI::CallForAllHelp&)
  {
    outcome.Stdout = app.help("", CLI::AppFormatMode::All);
  }
  catch (const CLI::ParseError& e)
  {
    outcome.ExitCode = 2;
    outcome.Error = OneLine(e.what()) + " (see terroir --help)";
  }
  catch (const std::invalid_argument& e)
  {
    outcome.ExitCode = 2;
    outcome.Error = OneLine(e.what());
  }
  return outcome;
}

} // namespace app
} // namespace terroir

#include "TerroirCommandLine.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace terroir
{
namespace app
{
namespace
{
/// A finite number within [lo, hi] (CLI11's own Range lets NaN through).
CLI::Validator FiniteIn(double lo, double hi)
{
  std::ostringstream name;
  name << "FINITE in [" << lo << ", " << hi << "]";
  return CLI::Validator(
    [lo, hi](std::string& text) -> std::string
    {
      double v = 0.0;
      std::size_t used = 0;
      try
      {
        v = std::stod(text, &used);
      }
      catch (const std::exception&)
      {
        return "'" + text + "' is not a number";
      }
      if (used != text.size() || !std::isfinite(v))
      {
        return "'" + text + "' is not a finite number";
      }
      if (v < lo || v > hi)
      {
        std::ostringstream os;
        os << text << " is outside [" << lo << ", " << hi << "]";
        return os.str();
      }
      return std::string();
    },
    name.str());
}

/// A file name ending in one of `extensions` (case-insensitive).
CLI::Validator EndsWith(const std::vector<std::string>& extensions)
{
  std::string list;
  for (const auto& e : extensions)
  {
    list += (list.empty() ? "" : ", ") + e;
  }
  return CLI::Validator(
    [extensions, list](std::string& text) -> std::string
    {
      for (const auto& e : extensions)
      {
        if (text.size() > e.size() &&
          std::equal(e.rbegin(),
            e.rend(),
            text.rbegin(),
            [](char a, char b) { return std::tolower(a) == std::tolower(b); }))
        {
          return std::string();
        }
      }
      return "'" + text + "': unknown output format (use " + list + ")";
    },
    "FILE (" + list + ")");
}

void AddTemperatureOptions(CLI::App* app, TemperatureSettings& t, std::string& monthly)
{
  app->add_option("--coldest", t.Coldest, "Sea-level temperature of the coldest month, C")
    ->check(FiniteIn(-90.0, 60.0))
    ->capture_default_str();
  app->add_option("--warmest", t.Warmest, "Sea-level temperature of the warmest month, C")
    ->check(FiniteIn(-90.0, 60.0))
    ->capture_default_str();
  app
    ->add_option(
      "--coldest-month", t.ColdestMonth, "Coldest month 1-12 (default: Jan north, Jul south)")
    ->check(CLI::Range(1, 12));
  app
    ->add_option(
      "--warmest-month", t.WarmestMonth, "Warmest month 1-12 (default: Jul north, Jan south)")
    ->check(CLI::Range(1, 12));
  auto* m =
    app->add_option("--monthly", monthly, "12 sea-level temperatures, C, January first (a,b,...)");
  app
    ->add_option("--climate",
      t.ClimateFile,
      "Climate table (CSV or JSON) whose temperature_c gives the 12 sea-level temperatures")
    ->excludes(m);
  app->add_option("--lapse-rate", t.LapseRate, "Temperature lapse rate, C per km")
    ->capture_default_str()
    ->check(FiniteIn(0.0, 20.0));
  app->add_option("--hemisphere", t.Hemisphere, "auto (from the georeference), north or south")
    ->check(CLI::IsMember({ "auto", "north", "south" }))
    ->capture_default_str();
}

/// Checks that involve several options of the temperature model.
void CheckTemperature(TemperatureSettings& t, const std::string& monthly)
{
  if (!monthly.empty())
  {
    t.Monthly = ParseNumberList(monthly, "--monthly");
    if (t.Monthly.size() != 12)
    {
      throw std::invalid_argument(
        "--monthly: expected 12 values, got " + std::to_string(t.Monthly.size()));
    }
    for (std::size_t k = 0; k < 12; ++k)
    {
      if (t.Monthly[k] < -90.0 || t.Monthly[k] > 60.0)
      {
        std::ostringstream os;
        os << "--monthly: value " << k + 1 << " (" << t.Monthly[k] << ") is outside [-90, 60]";
        throw std::invalid_argument(os.str());
      }
    }
  }
  if (t.Coldest > t.Warmest)
  {
    std::ostringstream os;
    os << "--coldest (" << t.Coldest << ") is above --warmest (" << t.Warmest << ")";
    throw std::invalid_argument(os.str());
  }
  if (t.ColdestMonth != 0 && t.ColdestMonth == t.WarmestMonth)
  {
    throw std::invalid_argument("--coldest-month and --warmest-month must differ");
  }
}

std::string OneLine(std::string text)
{
  std::replace(text.begin(), text.end(), '\n', ' ');
  while (!text.empty() && text.back() == ' ')
  {
    text.pop_back();
  }
  return text;
}
} // namespace

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

ParseOutcome ParseCommandLine(int argc, const char* const* argv, CommandLine& line)
{
  line = CommandLine();
  ParseOutcome outcome;
  CLI::App app{ "terroir: terrain resources (slope, temperature, ...) from a DEM, as VTK filters",
    "terroir" };
  app.require_subcommand(1);
  app.fallthrough(); // -v is accepted after the command too
  app.add_flag("-v,--verbose", line.Verbose, "Show VTK's log (backend choice, timings)");

  auto addCommon = [&](CLI::App* sub)
  {
    sub->add_option("--backend", line.Backend, "auto, cpu or gpu (TERROIR_BACKEND overrides auto)")
      ->check(CLI::IsMember({ "auto", "cpu", "gpu" }))
      ->capture_default_str();
    sub->add_flag("--overwrite", line.Overwrite, "Replace existing output files");
    sub->add_flag("--allow-network-paths",
      line.AllowNetwork,
      "Allow GDAL network and archive paths (/vsicurl/, /vsizip/, ...)");
  };
  const std::vector<std::string> rasterOut{ ".tif", ".tiff", ".vti" };

  // run
  CLI::App* run =
    app.add_subcommand("run", "Run every filter on a DEM (default: bundled Sagehen DEM)");
  std::string runMonthly;
  line.Output = "terroir-out";
  run->add_option("DEM", line.Input, "DEM file (GeoTIFF, .img, USGS .dem, Terragen .ter, ...)");
  run->add_option("-o,--out", line.Output, "Output folder")->capture_default_str();
  run->add_flag("--no-png", line.NoPng, "Skip the PNG overlays (they need an X display)");
  addCommon(run);
  AddTemperatureOptions(run, line.Temperature, runMonthly);

  // slope
  CLI::App* slope = app.add_subcommand("slope", "Slope in degrees (Horn 1981, as gdaldem slope)");
  slope->add_option("IN", line.Input, "Input DEM")->required();
  slope->add_option("OUT", line.Output, "Output .tif (Slope band) or .vti (all arrays)")
    ->required()
    ->check(EndsWith(rasterOut));
  slope->add_option("-z,--zfactor", line.ZFactor, "Vertical exaggeration of the elevations")
    ->check(FiniteIn(1e-9, 1e9))
    ->capture_default_str();
  slope->add_flag("-p,--percent", line.Percent, "Slope in percent instead of degrees");
  slope
    ->add_option("--aspect", line.AspectOutput, "Also write Aspect (degrees from true north) here")
    ->check(EndsWith(rasterOut));
  addCommon(slope);

  // temperature
  CLI::App* temp = app.add_subcommand("temperature", "Monthly temperature from a lapse rate");
  std::string tempMonthly;
  temp->add_option("IN", line.Input, "Input DEM")->required();
  temp->add_option("OUT", line.Output, "Output .tif (12 bands, Jan..Dec) or .vti")
    ->required()
    ->check(EndsWith(rasterOut));
  AddTemperatureOptions(temp, line.Temperature, tempMonthly);
  addCommon(temp);

  // bench
  CLI::App* bench = app.add_subcommand("bench", "Time each stage per backend on a synthetic DEM");
  std::string backends = "cpu,gpu";
  bench->add_option("-s,--size", line.BenchSize, "DEM is SIZE x SIZE cells")
    ->check(CLI::Range(16, 32768))
    ->capture_default_str();
  bench->add_option("-r,--repeat", line.BenchRepeat, "Timed runs per stage (best is reported)")
    ->check(CLI::Range(1, 100))
    ->capture_default_str();
  bench->add_option("--backends", backends, "Comma-separated backends")->capture_default_str();
  bench->add_flag("--bandwidth",
    line.BenchBandwidth,
    "Also measure memory bandwidth and the slope kernel's share");
  bench->add_option("--json", line.BenchJson, "Also write the results as JSON here");

  // info
  CLI::App* info = app.add_subcommand("info", "Grid and georeference of a DEM");
  info->add_option("IN", line.Input, "Input DEM")->required();
  info->add_flag(
    "--allow-network-paths", line.AllowNetwork, "Allow GDAL network and archive paths");

  // fractal
  CLI::App* fractal =
    app.add_subcommand("fractal", "Write a seeded synthetic DEM (benchmarks, tests)");
  fractal->add_option("OUT", line.Output, "Output .tif or .vti")
    ->required()
    ->check(EndsWith(rasterOut));
  fractal->add_option("-s,--size", line.FractalSize, "SIZE x SIZE cells")
    ->check(CLI::Range(2, 65536))
    ->capture_default_str();
  fractal->add_option("--seed", line.FractalSeed, "Random seed")->capture_default_str();
  fractal->add_option("--spacing", line.FractalSpacing, "Cell size, metres")
    ->check(FiniteIn(1e-3, 1e5))
    ->capture_default_str();
  fractal->add_flag("--overwrite", line.Overwrite, "Replace an existing output file");

  try
  {
    // CLI11 wants a mutable argv; it does not modify the strings.
    app.parse(argc, const_cast<char**>(argv));
    for (CLI::App* sub : { run, slope, temp, bench, info, fractal })
    {
      if (*sub)
      {
        line.Command = sub->get_name();
      }
    }
    if (*run)
    {
      CheckTemperature(line.Temperature, runMonthly);
    }
    if (*temp)
    {
      CheckTemperature(line.Temperature, tempMonthly);
    }
    if (*bench)
    {
      line.BenchBackends.clear();
      std::stringstream ss(backends);
      std::string item;
      while (std::getline(ss, item, ','))
      {
        if (item != "auto" && item != "cpu" && item != "gpu")
        {
          throw std::invalid_argument("--backends: '" + item + "' is not auto, cpu or gpu");
        }
        line.BenchBackends.push_back(item);
      }
      if (line.BenchBackends.empty())
      {
        throw std::invalid_argument("--backends: no backend given");
      }
    }
    if ((*slope || *temp || *info) && line.Input.empty())
    {
      throw std::invalid_argument("the input file name is empty");
    }
    if (*run && line.Output.empty())
    {
      throw std::invalid_argument("--out: the output folder name is empty");
    }
    outcome.Run = true;
  }
  catch (const CLI::CallForHelp&)
  {
    const CLI::App* sub = nullptr;
    for (CLI::App* s : { run, slope, temp, bench, info, fractal })
    {
      if (*s)
      {
        sub = s;
      }
    }
    outcome.Stdout = sub ? sub->help() : app.help();
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

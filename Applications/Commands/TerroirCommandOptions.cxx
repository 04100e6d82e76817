// The option helpers the commands' options share (TerroirCommandOptions.h); plain CLI11, no VTK.
#include "TerroirCommandOptions.h"

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

/// Adds --lat and --lon (run and illumination).
void AddLocationOptions(CLI::App* app, IlluminationSettings& s)
{
  app
    ->add_option("--lat",
      s.Latitude,
      "Latitude of the sun's observer, degrees north (default: the DEM's centre)")
    ->check(FiniteIn(-90.0, 90.0));
  app
    ->add_option("--lon",
      s.Longitude,
      "Longitude of the sun's observer, degrees east (default: the DEM's centre)")
    ->check(FiniteIn(-180.0, 180.0));
}

void AddClimateOptions(CLI::App* app, SoilWaterText& text)
{
  app->add_option(
    "--precip", text.Precipitation, "12 monthly precipitation quantities, mm, January first");
  app->add_option("--intensity",
    text.Intensity,
    "12 monthly mean precipitation intensities, mm/h, January first");
}

/// The infiltration operations, applied in the order given (infiltration, humidity).
void AddInfiltrationOptions(CLI::App* app,
  SoilWaterSettings& s,
  SoilWaterText& text,
  bool withRateInput)
{
  auto multi = [&](const char* name, std::vector<std::string>& into, const char* help)
  {
    CLI::Option* o =
      app->add_option(name, into, help)->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
    o->expected(1);
    o->allow_extra_args(false);
    text.OperationOptions.push_back(o);
  };
  multi("--fill", text.Fill, "Fill every cell with RATE mm/h");
  multi("--slope-rule", text.SlopeRule, "0 mm/h where the slope exceeds DEG degrees");
  multi("--paint-raster",
    text.PaintRaster,
    "FILE=RATE: RATE mm/h where the raster (on the DEM's grid) is non-zero");
  multi("--paint-polygons",
    text.PaintPolygons,
    "FILE=RATE: RATE mm/h inside the polygons (any OGR vector format)");
  multi("--soil-raster",
    text.SoilRaster,
    "FILE: FAO rates of the soil codes 1..5 (sand .. clay) of a raster on the DEM's grid");
  multi("--soil-polygons",
    text.SoilPolygons,
    "FILE=FIELD: FAO rates of the soil codes 1..5 in FIELD of the polygons");
  if (!withRateInput)
  {
    return;
  }
  app
    ->add_option("--infiltration",
      s.InfiltrationInput,
      "Read InfiltrationRate (mm/h) from this raster (on the DEM's grid) instead")
    ->excludes(text.OperationOptions[0])
    ->excludes(text.OperationOptions[1])
    ->excludes(text.OperationOptions[2])
    ->excludes(text.OperationOptions[3])
    ->excludes(text.OperationOptions[4])
    ->excludes(text.OperationOptions[5]);
}

/// "FILE=VALUE" split at the last '='.
std::pair<std::string, std::string> SplitAssignment(const std::string& text,
  const std::string& option,
  const char* what)
{
  const std::size_t eq = text.rfind('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
  {
    throw std::invalid_argument(option + ": '" + text + "' is not FILE=" + what);
  }
  return { text.substr(0, eq), text.substr(eq + 1) };
}

double RateValue(const std::string& text, const std::string& option)
{
  const std::vector<double> v = ParseNumberList(text, option);
  if (v.size() != 1 || v[0] < 0.0 || v[0] > 1000.0)
  {
    throw std::invalid_argument(option + ": '" + text + "' is not a rate in [0, 1000] mm/h");
  }
  return v[0];
}

/// 12 comma-separated values in [lo, hi] (precipitation, intensity).
std::vector<double> TwelveValues(const std::string& text,
  const std::string& option,
  double lo,
  double hi)
{
  std::vector<double> v = ParseNumberList(text, option);
  if (v.size() != 12)
  {
    throw std::invalid_argument(
      option + ": expected 12 values (January first), got " + std::to_string(v.size()));
  }
  for (std::size_t k = 0; k < 12; ++k)
  {
    if (v[k] < lo || v[k] > hi)
    {
      std::ostringstream os;
      os << option << ": value " << k + 1 << " (" << v[k] << ") is outside [" << lo << ", " << hi
         << "]";
      throw std::invalid_argument(os.str());
    }
  }
  return v;
}

/// Turns the soil-water text options into settings; operations keep the command line's order.
void CheckSoilWater(SoilWaterSettings& s, const SoilWaterText& text, const CLI::App& app)
{
  if (!text.Precipitation.empty())
  {
    s.Precipitation = TwelveValues(text.Precipitation, "--precip", 0.0, 10000.0);
  }
  if (!text.Intensity.empty())
  {
    s.Intensity = TwelveValues(text.Intensity, "--intensity", 0.0, 500.0);
  }
  if (!s.Precipitation.empty() || !s.Intensity.empty())
  {
    if (!s.ClimateFile.empty())
    {
      throw std::invalid_argument("--precip and --intensity exclude --climate");
    }
    // Each defaults to the filter's; a rainy month must then have a positive intensity,
    // which the filter checks against the values actually used.
    for (std::size_t k = 0; k < s.Precipitation.size() && k < s.Intensity.size(); ++k)
    {
      if (s.Precipitation[k] > 0.0 && !(s.Intensity[k] > 0.0))
      {
        throw std::invalid_argument("--intensity: month " + std::to_string(k + 1) +
          " has rain (--precip) but intensity 0: rain needs a positive intensity");
      }
    }
  }
  const std::vector<std::string>* values[6] = { &text.Fill,
    &text.SlopeRule,
    &text.PaintRaster,
    &text.PaintPolygons,
    &text.SoilRaster,
    &text.SoilPolygons };
  const char* kinds[6] = {
    "fill", "slope-rule", "paint-raster", "paint-polygons", "soil-raster", "soil-polygons"
  };
  std::size_t next[6] = { 0, 0, 0, 0, 0, 0 };
  for (const CLI::Option* o : app.parse_order())
  {
    for (int k = 0; k < 6 && k < static_cast<int>(text.OperationOptions.size()); ++k)
    {
      if (o != text.OperationOptions[k] || next[k] >= values[k]->size())
      {
        continue;
      }
      const std::string& v = (*values[k])[next[k]++];
      const std::string option = std::string("--") + kinds[k];
      InfiltrationOperation op;
      op.Kind = kinds[k];
      if (k == 0)
      {
        op.Value = RateValue(v, option);
      }
      else if (k == 1)
      {
        const std::vector<double> d = ParseNumberList(v, option);
        if (d.size() != 1 || d[0] < 0.0 || d[0] > 90.0)
        {
          throw std::invalid_argument(option + ": '" + v + "' is not an angle in [0, 90] degrees");
        }
        op.Value = d[0];
      }
      else if (k == 2 || k == 3)
      {
        auto [file, rate] = SplitAssignment(v, option, "RATE");
        op.File = file;
        op.Value = RateValue(rate, option);
      }
      else if (k == 4)
      {
        if (v.empty())
        {
          throw std::invalid_argument(option + ": the file name is empty");
        }
        op.File = v;
      }
      else
      {
        auto [file, field] = SplitAssignment(v, option, "FIELD");
        op.File = file;
        op.Attribute = field;
      }
      s.Operations.push_back(op);
    }
  }
}

void AddFloodFillOptions(CLI::App* app,
  FloodFillSettings& s,
  std::vector<std::string>& seeds,
  std::vector<std::string>& cells)
{
  app->add_option("--seed", seeds, "X,Y[,LEVEL]: a seed in the DEM's coordinates (metres)")
    ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  app->add_option("--seed-cell", cells, "I,J[,LEVEL]: a seed cell (column, row; row 0 south)")
    ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  app
    ->add_option("--level",
      s.Level,
      "Water level, metres, of seeds without their own (default: the terrain at the seed)")
    ->check(FiniteIn(-20000.0, 20000.0));
  app->add_flag("--fill-depressions",
    s.FillDepressions,
    "Find every closed depression and hydro-flattened lake instead of filling from seeds");
  app->add_option("--min-area", s.MinimumArea, "Smallest water body kept, m2 (--fill-depressions)")
    ->check(FiniteIn(0.0, 1e15))
    ->capture_default_str();
  app->add_flag("!--no-flat-surfaces",
    s.FlatSurfaces,
    "Do not count flat surfaces at their outlet's level as lakes (--fill-depressions)");
}

void CheckFloodFill(FloodFillSettings& s,
  const std::vector<std::string>& seeds,
  const std::vector<std::string>& cells,
  const CLI::App& app)
{
  for (int kind = 0; kind < 2; ++kind)
  {
    const std::vector<std::string>& list = kind == 0 ? seeds : cells;
    const std::string option = kind == 0 ? "--seed" : "--seed-cell";
    for (const std::string& text : list)
    {
      const std::vector<double> v = ParseNumberList(text, option);
      if (v.size() != 2 && v.size() != 3)
      {
        throw std::invalid_argument(
          option + ": '" + text + "' is not " + (kind == 0 ? "X,Y[,LEVEL]" : "I,J[,LEVEL]"));
      }
      FloodFillSettings::Seed seed;
      seed.X = v[0];
      seed.Y = v[1];
      seed.Cell = kind == 1;
      if (seed.Cell &&
        (v[0] != std::floor(v[0]) || v[1] != std::floor(v[1]) || v[0] < 0.0 || v[1] < 0.0 ||
          v[0] > 2147483647.0 || v[1] > 2147483647.0))
      {
        throw std::invalid_argument(
          option + ": '" + text + "': I and J must be cell indices (>= 0)");
      }
      if (v.size() == 3)
      {
        seed.Level = v[2];
      }
      s.Seeds.push_back(seed);
    }
  }
  const bool seeded = !s.Seeds.empty();
  if (s.FillDepressions && seeded)
  {
    throw std::invalid_argument("--fill-depressions excludes --seed and --seed-cell");
  }
  if (!s.FillDepressions && !seeded)
  {
    throw std::invalid_argument(
      "floodfill needs --seed X,Y (or --seed-cell I,J) or --fill-depressions");
  }
  if (s.FillDepressions && app.get_option("--level")->count() > 0)
  {
    throw std::invalid_argument("--level applies to seeds, not to --fill-depressions");
  }
  if (!s.FillDepressions &&
    (app.get_option("--min-area")->count() > 0 ||
      app.get_option("--no-flat-surfaces")->count() > 0))
  {
    throw std::invalid_argument("--min-area and --no-flat-surfaces apply to --fill-depressions");
  }
}

void AddWaterFlowOptions(CLI::App* app, WaterFlowSettings& s)
{
  app->add_option("--water", s.InitialWater, "Water on every cell, mm")
    ->check(FiniteIn(0.0, 1e6))
    ->capture_default_str();
  app->add_option("--month", s.Month, "Use the StandingWater of month M (1-12) instead")
    ->check(CLI::Range(1, 12));
  app->add_flag("--annual", s.Annual, "Use the year's StandingWater instead");
  app->add_option("--max-iterations", s.MaximumIterations, "Iteration limit")
    ->check(CLI::Range(0LL, 100000000LL))
    ->capture_default_str();
  app->add_option("--auto-stop", s.AutoStop, "Long (2016)'s stop ratio (0: off)")
    ->check(FiniteIn(0.0, 0.999))
    ->capture_default_str();
  app->add_option("--time", s.Time, "Simulated time limit, s (0: none)")
    ->check(FiniteIn(0.0, 1e12));
  app->add_option("--iteration-duration", s.IterationDuration, "Simulated seconds per iteration")
    ->check(FiniteIn(1e-6, 1e9))
    ->capture_default_str();
  app->add_option("--river-threshold", s.RiverThreshold, "Discharge of a river cell, m3")
    ->check(FiniteIn(0.0, 1e18));
  app
    ->add_option("--mode",
      s.Mode,
      "pulse: Long (2016)'s single pulse; rivers: steady rain until the outflow balances it "
      "(default: pulse for waterflow, rivers for validate and run)")
    ->check(CLI::IsMember({ "pulse", "rivers" }));
  app->add_option("--rain", s.RainRate, "Rivers mode: rain on every cell, mm/h")
    ->check(FiniteIn(1e-9, 1e6))
    ->capture_default_str();
  app
    ->add_option("--balance",
      s.BalanceTolerance,
      "Rivers mode: stop when the outflow reaches 1 - TOLERANCE of the rain")
    ->check(FiniteIn(1e-9, 0.999))
    ->capture_default_str();
  app
    ->add_option("--thinning",
      s.Thinning,
      "Rivers mode: RiverStrength factor beside the crest of a band of flow (0 removes, 1 keeps)")
    ->check(FiniteIn(0.0, 1.0))
    ->capture_default_str();
  app
    ->add_option("--settle",
      s.Settle,
      "Rivers mode: iterations a warm-started grid runs before the balance may stop it")
    ->check(CLI::Range(0LL, 100000000LL))
    ->capture_default_str();
  app->add_flag("!--no-warm-start",
    s.WarmStart,
    "Rivers mode: start from still water only, not from the steady state of coarser grids");
  app->add_flag("--long-capacity",
    s.LongCapacity,
    "Long (2016)'s literal rule: no flow from a cell whose capacity 2T - H(n-1) - H(n+1) "
    "(8 neighbours, higher ones included) is negative");
  app->add_flag("--count-emptied",
    s.CountEmptied,
    "Long (2016)'s stop measure: cells emptied per iteration instead of the volume moved (CPU)");
}

void CheckWaterFlow(const WaterFlowSettings& s, const CLI::App& app)
{
  const int sources =
    (app.get_option("--water")->count() > 0 ? 1 : 0) + (s.Month > 0 ? 1 : 0) + (s.Annual ? 1 : 0);
  if (sources > 1)
  {
    throw std::invalid_argument("--water, --month and --annual exclude each other");
  }
}

/// Fills s.FeatureNames/FeatureWeights from "NAME[:WEIGHT],..." (empty text: none, the
/// defaults); throws std::invalid_argument naming --features and the bad item.
void ParseFeatures(const std::string& text, KMeansSettings& s)
{
  if (text.empty())
  {
    return;
  }
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ','))
  {
    const std::size_t colon = item.rfind(':');
    const std::string name = item.substr(0, colon);
    double weight = 1.0;
    if (colon != std::string::npos)
    {
      const std::vector<double> w = ParseNumberList(item.substr(colon + 1), "--features");
      if (w.size() != 1 || w[0] < 0.0)
      {
        throw std::invalid_argument(
          "--features: '" + item + "' needs one weight >= 0 after the colon");
      }
      weight = w[0];
    }
    if (name.empty())
    {
      throw std::invalid_argument("--features: '" + item + "' has no array name");
    }
    for (const std::string& seen : s.FeatureNames)
    {
      if (seen == name)
      {
        throw std::invalid_argument("--features: '" + name + "' is given twice");
      }
    }
    s.FeatureNames.push_back(name);
    s.FeatureWeights.push_back(weight);
  }
  if (s.FeatureNames.empty())
  {
    throw std::invalid_argument("--features: no array named");
  }
}

//------------------------------------------------------------------------------
const std::vector<std::string>& RasterOutputs()
{
  static const std::vector<std::string> outputs{ ".tif", ".tiff", ".vti" };
  return outputs;
}

void AddZUnitOption(CLI::App* sub, CommandLine& line)
{
  sub
    ->add_option("--z-unit",
      line.ZUnit,
      "Unit of the DEM's heights: auto (the file's metadata, else metres), m, ft or us-ft")
    ->check(CLI::IsMember({ "auto", "m", "ft", "us-ft" }))
    ->capture_default_str();
}

void AddCommonOptions(CLI::App* sub, CommandLine& line)
{
  sub
    ->add_option("--backend",
      line.Backend,
      "auto, cpu or gpu (TERROIR_BACKEND overrides auto). auto runs a stage on the GPU only "
      "where its GPU path is recorded as verified, correct and faster than the CPU, on this "
      "kind of GPU (Documentation/Compute.md; no GPU has such a record yet, so auto means "
      "the CPU); gpu forces the GPU path")
    ->check(CLI::IsMember({ "auto", "cpu", "gpu" }))
    ->capture_default_str();
  sub->add_flag("--overwrite", line.Overwrite, "Replace existing output files");
  sub->add_flag("--allow-network-paths",
    line.AllowNetwork,
    "Allow GDAL network and archive paths (/vsicurl/, /vsizip/, ...)");
  AddZUnitOption(sub, line);
}

void CheckNotOutput(const std::vector<const std::string*>& extras, const std::string& output)
{
  for (const std::string* extra : extras)
  {
    if (!extra->empty() && *extra == output)
    {
      throw std::invalid_argument("'" + *extra + "' is both OUT and an extra output");
    }
  }
}

void CheckInputGiven(const CommandLine& line)
{
  if (line.Input.empty())
  {
    throw std::invalid_argument("the input file name is empty");
  }
}

} // namespace app
} // namespace terroir

#include "TerroirCommandLine.h"

#include "SolarPosition.h" // terroir::terrain::IsValidDate (TerroirTerrainCore, no VTK)

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

/// The string options of `illumination` that are checked after parsing (see CheckIllumination).
struct IlluminationText
{
  std::string Date;
  std::string Time;
  std::string Sun;
  CLI::Option* DateOption = nullptr;
  CLI::Option* TimeOption = nullptr;
  CLI::Option* UTCOffsetOption = nullptr;
  CLI::Option* YearOption = nullptr;
  CLI::Option* DayOption = nullptr;
  CLI::Option* StepOption = nullptr;
  CLI::Option* SunOption = nullptr;
};

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

void AddIlluminationOptions(CLI::App* app, IlluminationSettings& s, IlluminationText& text)
{
  const std::vector<std::string> rasterOut{ ".tif", ".tiff", ".vti" };
  app
    ->add_option("--mode",
      s.Mode,
      "instant (shadows at one moment), daily (one day) or monthly (one day of each month)")
    ->check(CLI::IsMember({ "instant", "daily", "monthly" }))
    ->capture_default_str();
  text.DateOption =
    app->add_option("--date", text.Date, "Date YYYY-MM-DD (instant, daily; default 2025-06-21)");
  text.TimeOption = app->add_option(
    "--time", text.Time, "Local clock time HH:MM[:SS] (instant; required unless --sun)");
  text.UTCOffsetOption =
    app
      ->add_option("--utc-offset",
        s.UTCOffset,
        "Hours the clock of --time is ahead of UTC (instant; -8 = PST; default 0: UTC)")
      ->check(FiniteIn(-14.0, 14.0));
  text.YearOption = app->add_option("--year", s.Year, "Year (monthly)")
                      ->check(CLI::Range(1, 9999))
                      ->capture_default_str();
  text.DayOption = app
                     ->add_option("--day",
                       s.MonthlyDay,
                       "Day of every month used (monthly; 29-31: the last day of shorter months)")
                     ->check(CLI::Range(1, 31))
                     ->capture_default_str();
  text.StepOption = app->add_option("--step", s.TimeStep, "Time step, minutes (daily, monthly)")
                      ->check(FiniteIn(1.0, 1440.0))
                      ->capture_default_str();
  AddLocationOptions(app, s);
  app
    ->add_option("--orientation",
      s.Orientation,
      "Bearing of grid north clockwise from true north, degrees (default: the CRS's meridian "
      "convergence, else 0)")
    ->check(FiniteIn(-360.0, 360.0));
  app
    ->add_option("--method",
      s.Method,
      "Shadows from a horizon map (horizon) or by marching every cell toward the sun (raymarch)")
    ->check(CLI::IsMember({ "horizon", "raymarch" }))
    ->capture_default_str();
  app->add_option("--sectors", s.Sectors, "Azimuth sectors of the horizon map")
    ->check(CLI::Range(4, 1024))
    ->capture_default_str();
  app->add_flag("--curvature", s.Curvature, "Lower distant terrain by the Earth's curvature");
  app
    ->add_option(
      "--transmittance", s.Transmittance, "Clear-sky atmospheric transmittance (insolation)")
    ->check(FiniteIn(0.01, 1.0))
    ->capture_default_str();
  text.SunOption = app->add_option(
    "--sun", text.Sun, "Fixed sun AZ,EL in degrees (azimuth from true north; instant)");
  app
    ->add_option("--insolation",
      s.InsolationOutput,
      "Also write Insolation (Wh/m2 per day; daily, monthly) here")
    ->check(EndsWith(rasterOut));
  app
    ->add_option("--incidence",
      s.IncidenceOutput,
      "Also write SunIncidence (cosine of the sun's incidence angle; instant) here")
    ->check(EndsWith(rasterOut));
}

/// "YYYY-MM-DD" (a real Gregorian date) into year, month, day.
void ParseDate(const std::string& text, IlluminationSettings& s)
{
  int y = 0, m = 0, d = 0;
  char tail = 0;
  const bool shaped = text.size() == 10 && text[4] == '-' && text[7] == '-' &&
    std::all_of(text.begin(),
      text.end(),
      [](char c) { return c == '-' || std::isdigit(static_cast<unsigned char>(c)); }) &&
    std::sscanf(text.c_str(), "%4d-%2d-%2d%c", &y, &m, &d, &tail) == 3;
  if (!shaped)
  {
    throw std::invalid_argument("--date: '" + text + "' is not a date (YYYY-MM-DD)");
  }
  if (!terroir::terrain::IsValidDate(y, m, d))
  {
    throw std::invalid_argument("--date: " + text + " does not exist");
  }
  s.Year = y;
  s.Month = m;
  s.Day = d;
}

/// "HH:MM" or "HH:MM:SS" (00:00 to 24:00) into hours.
double ParseTimeOfDay(const std::string& text)
{
  int field[3] = { 0, 0, 0 };
  int count = 0;
  std::size_t k = 0;
  bool ok = !text.empty();
  while (ok && k < text.size() && count < 3)
  {
    std::size_t digits = 0;
    int v = 0;
    while (k < text.size() && std::isdigit(static_cast<unsigned char>(text[k])) && digits < 2)
    {
      v = 10 * v + (text[k] - '0');
      ++k;
      ++digits;
    }
    // Hours take 1 or 2 digits, minutes and seconds exactly 2.
    ok = digits == 2 || (count == 0 && digits == 1);
    field[count++] = v;
    if (ok && k < text.size())
    {
      ok = text[k] == ':' && k + 1 < text.size();
      ++k;
    }
  }
  ok = ok && k == text.size() && count >= 2 && field[0] <= 24 && field[1] <= 59 && field[2] <= 59 &&
    (field[0] < 24 || (field[1] == 0 && field[2] == 0));
  if (!ok)
  {
    throw std::invalid_argument(
      "--time: '" + text + "' is not a time of day (HH:MM or HH:MM:SS, 00:00 to 24:00)");
  }
  return field[0] + field[1] / 60.0 + field[2] / 3600.0;
}

/// Checks that involve several options of `illumination`, and the options that apply to one
/// mode only.
void CheckIllumination(IlluminationSettings& s, const IlluminationText& text)
{
  const bool instant = s.Mode == "instant";
  const bool monthly = s.Mode == "monthly";
  auto given = [](const CLI::Option* o) { return o && o->count() > 0; };
  if (!instant)
  {
    for (const auto& [option, name] : { std::make_pair(text.TimeOption, "--time"),
           std::make_pair(text.UTCOffsetOption, "--utc-offset"),
           std::make_pair(text.SunOption, "--sun") })
    {
      if (given(option))
      {
        throw std::invalid_argument(std::string(name) + " applies to --mode instant only");
      }
    }
    if (!s.IncidenceOutput.empty())
    {
      throw std::invalid_argument(
        "--incidence applies to --mode instant only (daily and monthly give --insolation)");
    }
  }
  else
  {
    if (given(text.StepOption))
    {
      throw std::invalid_argument("--step applies to --mode daily or monthly");
    }
    if (!s.InsolationOutput.empty())
    {
      throw std::invalid_argument(
        "--insolation applies to --mode daily or monthly (instant gives --incidence)");
    }
  }
  if (monthly && given(text.DateOption))
  {
    throw std::invalid_argument(
      "--date applies to --mode instant or daily (monthly takes --year and --day)");
  }
  if (!monthly && (given(text.YearOption) || given(text.DayOption)))
  {
    throw std::invalid_argument(std::string(given(text.YearOption) ? "--year" : "--day") +
      " applies to --mode monthly (instant and daily take --date)");
  }
  if (given(text.DateOption))
  {
    ParseDate(text.Date, s);
  }
  if (given(text.TimeOption))
  {
    s.Time = ParseTimeOfDay(text.Time);
    s.HasTime = true;
  }
  if (given(text.SunOption))
  {
    if (given(text.DateOption) || given(text.TimeOption) || given(text.UTCOffsetOption))
    {
      throw std::invalid_argument("--sun excludes --date, --time and --utc-offset");
    }
    const std::vector<double> sun = ParseNumberList(text.Sun, "--sun");
    if (sun.size() != 2)
    {
      throw std::invalid_argument(
        "--sun: expected AZ,EL (2 values), got " + std::to_string(sun.size()));
    }
    if (sun[0] < 0.0 || sun[0] > 360.0)
    {
      std::ostringstream os;
      os << "--sun: azimuth " << sun[0] << " is outside [0, 360]";
      throw std::invalid_argument(os.str());
    }
    if (sun[1] < -90.0 || sun[1] > 90.0)
    {
      std::ostringstream os;
      os << "--sun: elevation " << sun[1] << " is outside [-90, 90]";
      throw std::invalid_argument(os.str());
    }
    s.UseSun = true;
    s.SunAzimuth = sun[0];
    s.SunElevation = sun[1];
  }
  if (instant && !s.UseSun && !s.HasTime)
  {
    throw std::invalid_argument("--mode instant needs --time HH:MM (or --sun AZ,EL)");
  }
}

/// The string options of the soil-water commands, checked after parsing (CheckSoilWater).
struct SoilWaterText
{
  std::string Precipitation;
  std::string Intensity;
  std::vector<std::string> Fill, SlopeRule, PaintRaster, PaintPolygons, SoilRaster, SoilPolygons;
  std::vector<CLI::Option*> OperationOptions; ///< in the order of the vectors above
};

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
  app->add_option("--water", s.WaterMm, "Water on every cell, mm")
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

//------------------------------------------------------------------------------
const std::vector<CommandDescription>& CommandDescriptions()
{
  static const std::vector<CommandDescription> commands = {
    { "run", "Run every filter on a DEM (default: bundled Sagehen DEM)" },
    { "slope", "Slope in degrees (Horn 1981, as gdaldem slope)" },
    { "temperature", "Monthly temperature from a lapse rate" },
    { "illumination", "Cast shadows, hours of direct sun and clear-sky insolation" },
    { "infiltration", "Infiltration rate map (mm/h) from fill, slope-rule and paint operations" },
    { "humidity", "Monthly soil humidity, its weighted average and standing water (mm)" },
    { "floodfill", "Lakes: flood fill from seeds, or every closed depression (priority-flood)" },
    { "waterflow", "Rivers and lakes: the hydrostatic water-flow simulation of Long (2016)" },
    { "flowacc",
      "Flow accumulation after priority-flood filling: D8, MFD or D-infinity (the classic "
      "baselines)" },
    { "validate",
      "Score simulated rivers against mapped ones (precision, recall, F1 at 30 and 60 m)" },
    { "kmeans",
      "Ecological zones: k-means clustering of terrain resources, after Long (2016), ch. 4" },
    { "view",
      "Interactive window: relief, overlays, sliders, lakes (default: bundled Sagehen DEM)" },
    { "bench", "Time each stage per backend on a synthetic DEM" },
    { "info", "Grid and georeference of a DEM" },
    { "fractal", "Write a seeded synthetic DEM (benchmarks, tests)" },
  };
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
  static const std::vector<std::string> names{ "slope",
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
    "kmeans" };
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
    s.WaterMm = x;
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

  auto addZUnit = [&](CLI::App* sub)
  {
    sub
      ->add_option("--z-unit",
        line.ZUnit,
        "Unit of the DEM's heights: auto (the file's metadata, else metres), m, ft or us-ft")
      ->check(CLI::IsMember({ "auto", "m", "ft", "us-ft" }))
      ->capture_default_str();
  };
  auto addCommon = [&](CLI::App* sub)
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
    addZUnit(sub);
  };
  const std::vector<std::string> rasterOut{ ".tif", ".tiff", ".vti" };

  // run
  CLI::App* run = app.add_subcommand("run", CommandSummary("run"));
  std::string runMonthly;
  line.Output = "terroir-out";
  run->add_option("DEM", line.Input, "DEM file (GeoTIFF, .img, USGS .dem, Terragen .ter, ...)");
  run->add_option("-o,--out", line.Output, "Output folder")->capture_default_str();
  run->add_flag("--no-png", line.NoPng, "Skip the PNG overlays (they need an X display)");
  addCommon(run);
  AddTemperatureOptions(run, line.Temperature, runMonthly);
  SoilWaterText runSoilText;
  AddClimateOptions(run, runSoilText);
  AddLocationOptions(run, line.Illumination);
  run->add_option("--clusters", line.KMeans.Clusters, "Ecological zones K (k-means; 0 skips)")
    ->check(CLI::Range(0, 64))
    ->capture_default_str();

  // slope
  CLI::App* slope = app.add_subcommand("slope", CommandSummary("slope"));
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
  CLI::App* temp = app.add_subcommand("temperature", CommandSummary("temperature"));
  std::string tempMonthly;
  temp->add_option("IN", line.Input, "Input DEM")->required();
  temp->add_option("OUT", line.Output, "Output .tif (12 bands, Jan..Dec) or .vti")
    ->required()
    ->check(EndsWith(rasterOut));
  AddTemperatureOptions(temp, line.Temperature, tempMonthly);
  addCommon(temp);

  // illumination
  CLI::App* illum = app.add_subcommand("illumination", CommandSummary("illumination"));
  IlluminationText illumText;
  illum->add_option("IN", line.Input, "Input DEM")->required();
  illum
    ->add_option("OUT",
      line.Output,
      "Output .tif (instant: Illuminated 0/1; daily, monthly: IlluminationHours, 1 or 12 bands) "
      "or .vti (all arrays)")
    ->required()
    ->check(EndsWith(rasterOut));
  AddIlluminationOptions(illum, line.Illumination, illumText);
  addCommon(illum);

  // infiltration
  CLI::App* infil = app.add_subcommand("infiltration", CommandSummary("infiltration"));
  SoilWaterText infilText;
  infil->add_option("IN", line.Input, "Input DEM")->required();
  infil->add_option("OUT", line.Output, "Output .tif (InfiltrationRate) or .vti (all arrays)")
    ->required()
    ->check(EndsWith(rasterOut));
  AddInfiltrationOptions(infil, line.SoilWater, infilText, false);
  addCommon(infil);

  // humidity
  CLI::App* humid = app.add_subcommand("humidity", CommandSummary("humidity"));
  SoilWaterText humidText;
  humid->add_option("IN", line.Input, "Input DEM")->required();
  humid
    ->add_option(
      "OUT", line.Output, "Output .tif (SoilHumidity, 12 bands Jan..Dec) or .vti (all arrays)")
    ->required()
    ->check(EndsWith(rasterOut));
  AddClimateOptions(humid, humidText);
  humid->add_option("--climate",
    line.SoilWater.ClimateFile,
    "Climate table (CSV or JSON) with precipitation_mm and intensity_mm_per_h");
  AddInfiltrationOptions(humid, line.SoilWater, humidText, true);
  humid
    ->add_option(
      "--weighted", line.SoilWater.WeightedOutput, "Also write WeightedSoilHumidity here")
    ->check(EndsWith(rasterOut));
  humid->add_option("--standing", line.SoilWater.StandingOutput, "Also write StandingWater here")
    ->check(EndsWith(rasterOut));
  addCommon(humid);

  // floodfill
  CLI::App* flood = app.add_subcommand("floodfill", CommandSummary("floodfill"));
  std::vector<std::string> floodSeeds, floodCells;
  flood->add_option("IN", line.Input, "Input DEM")->required();
  flood->add_option("OUT", line.Output, "Output .tif (WaterDepth, m; 0 dry) or .vti (all arrays)")
    ->required()
    ->check(EndsWith(rasterOut));
  AddFloodFillOptions(flood, line.FloodFill, floodSeeds, floodCells);
  flood->add_option("--ids", line.FloodFill.IdsOutput, "Also write WaterBody ids (0 dry) here")
    ->check(EndsWith(rasterOut));
  addCommon(flood);

  // waterflow
  CLI::App* flow = app.add_subcommand("waterflow", CommandSummary("waterflow"));
  flow->add_option("IN", line.Input, "Input DEM")->required();
  flow->add_option("OUT", line.Output, "Output .tif (WaterHeight, m) or .vti (all arrays)")
    ->required()
    ->check(EndsWith(rasterOut));
  AddWaterFlowOptions(flow, line.WaterFlow);
  flow->add_option("--discharge", line.WaterFlow.DischargeOutput, "Also write Discharge (m3)")
    ->check(EndsWith(rasterOut));
  flow->add_option("--river", line.WaterFlow.RiverOutput, "Also write the River mask")
    ->check(EndsWith(rasterOut));
  addCommon(flow);

  // flowacc
  CLI::App* flowacc = app.add_subcommand("flowacc", CommandSummary("flowacc"));
  flowacc->add_option("IN", line.Input, "Input DEM")->required();
  flowacc->add_option("OUT", line.Output, "Output .tif (ContributingArea, m2) or .vti (all arrays)")
    ->required()
    ->check(EndsWith(rasterOut));
  flowacc
    ->add_option("--river-threshold", line.FlowRiverThreshold, "Contributing area of a river, m2")
    ->check(FiniteIn(0.0, 1e18))
    ->capture_default_str();
  flowacc
    ->add_option("--method",
      line.FlowMethod,
      "d8 (O'Callaghan & Mark 1984), mfd (Freeman 1991) or dinf (Tarboton 1997)")
    ->check(CLI::IsMember({ "d8", "mfd", "dinf" }))
    ->capture_default_str();
  flowacc->add_option("--mfd-exponent", line.FlowMFDExponent, "MFD's slope exponent p")
    ->check(FiniteIn(1e-3, 100.0))
    ->capture_default_str();
  addCommon(flowacc);

  // validate
  CLI::App* validate = app.add_subcommand("validate", CommandSummary("validate"));
  validate->add_option("DEM", line.Input, "Input DEM (default: the bundled Sagehen DEM)");
  validate->add_option("--reference",
    line.Validate.Reference,
    "Reference river lines, any OGR format (default with the bundled DEM: its NHD flowlines)");
  validate->add_option("--mask",
    line.Validate.Mask,
    "Area to score: a raster on the DEM grid (non-zero inside) or polygons (default with the "
    "bundled DEM: its watershed)");
  validate
    ->add_option("--peer", line.Validate.Peers, "NAME=RASTER: also score a peer's accumulation")
    ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  validate->add_option("--json", line.Validate.Json, "Also write the scores as JSON here");
  validate->add_option("--png", line.Validate.Png, "Also write the overlay picture here");
  validate->add_option("--sweep",
    line.Validate.Sweep,
    "NAME=V1,V2,...: one simulation row per value of a water-flow option (e.g. rain=0.1,1,10)");
  AddWaterFlowOptions(validate, line.WaterFlow);
  addCommon(validate);

  // kmeans
  CLI::App* kmeans = app.add_subcommand("kmeans", CommandSummary("kmeans"));
  std::string kmeansFeatures;
  kmeans
    ->add_option("IN", line.Input, "Terrain with resource arrays (.vti of terroir run), or a DEM")
    ->required();
  kmeans->add_option("OUT", line.Output, "Output .tif (ClusterId) or .vti (all arrays)")
    ->required()
    ->check(EndsWith(rasterOut));
  kmeans->add_option("-k,--clusters", line.KMeans.Clusters, "Number of clusters K")
    ->check(CLI::Range(1, 64))
    ->capture_default_str();
  kmeans->add_option("--features",
    kmeansFeatures,
    "NAME[:WEIGHT],... point arrays to cluster on (default: Slope, Temperature, "
    "IlluminationHours, WeightedSoilHumidity:0.1, those present)");
  kmeans->add_flag("--standardize", line.KMeans.Standardize, "Cluster z-scores of the features");
  kmeans->add_option("--seeding", line.KMeans.Seeding, "diagonal (Long (2016)'s) or kmeans++")
    ->check(CLI::IsMember({ "diagonal", "kmeans++" }))
    ->capture_default_str();
  kmeans->add_option("--seed", line.KMeans.Seed, "Random seed of kmeans++")
    ->check(CLI::Range(0, std::numeric_limits<int>::max()))
    ->capture_default_str();
  kmeans->add_option("--max-iterations", line.KMeans.MaximumIterations, "Most Lloyd iterations")
    ->check(CLI::Range(1, std::numeric_limits<int>::max()))
    ->capture_default_str();
  kmeans
    ->add_option(
      "--tolerance", line.KMeans.Tolerance, "Centre shift, relative to the feature variance")
    ->check(FiniteIn(0.0, 1e9))
    ->capture_default_str();
  kmeans->add_option("--csv", line.KMeans.Csv, "Also write the cluster table as CSV here")
    ->check(EndsWith({ ".csv" }));
  kmeans->add_option("--json", line.KMeans.Json, "Also write the cluster table as JSON here")
    ->check(EndsWith({ ".json" }));
  kmeans->add_option("--png", line.KMeans.Png, "Also write the cluster overlay here")
    ->check(EndsWith({ ".png" }));
  addCommon(kmeans);

  // view
  CLI::App* view = app.add_subcommand("view", CommandSummary("view"));
  std::string viewSize;
  view->add_option("DEM", line.Input, "DEM file (default: the bundled Sagehen Creek DEM)");
  view->add_option("--script", line.View.Script, "Replay the actions of FILE (one per line)");
  view->add_option("--size", viewSize, "Window size WxH (default 1024x768)");
  view
    ->add_option("--overlay",
      line.View.Overlay,
      "First overlay: none, slope, illumination, sun-hours, temperature, humidity, water, "
      "clusters")
    ->check(CLI::IsMember({ "none",
      "slope",
      "illumination",
      "sun-hours",
      "temperature",
      "humidity",
      "water",
      "clusters" }))
    ->capture_default_str();
  view->add_option("--style", line.View.Style, "Navigation: terrain (drag) or first-person (WASD)")
    ->check(CLI::IsMember({ "terrain", "first-person" }))
    ->capture_default_str();
  view->add_option("--screenshot-dir",
    line.View.ScreenshotDir,
    "Folder of the screenshot key's PNGs (default: .)");
  view->add_option("--sensitivity", line.View.Sensitivity, "Mouse sensitivity (pan, rotate, zoom)")
    ->check(FiniteIn(0.01, 100.0))
    ->capture_default_str();
  view->add_option("--move-speed", line.View.MoveSpeed, "First-person step multiplier")
    ->check(FiniteIn(0.01, 100.0))
    ->capture_default_str();
  AddLocationOptions(view, line.Illumination);
  view->add_option("--month", line.View.Month, "Month of the sun, temperature, humidity")
    ->check(CLI::Range(1, 12))
    ->capture_default_str();
  view->add_option("--hour", line.View.Hour, "Local solar time, hours")
    ->check(FiniteIn(0.0, 24.0))
    ->capture_default_str();
  view
    ->add_option("--orientation",
      line.View.Orientation,
      "Bearing of grid north from true north, degrees (default: the CRS's, else 0)")
    ->check(FiniteIn(-360.0, 360.0));
  view->add_option("--clusters", line.View.Clusters, "K of the clusters overlay")
    ->check(CLI::Range(1, 64))
    ->capture_default_str();
  view->add_option("--lake-depth", line.View.LakeDepth, "Lake level above a clicked cell, m")
    ->check(FiniteIn(0.0, 10000.0))
    ->capture_default_str();
  view->add_flag(
    "--allow-network-paths", line.AllowNetwork, "Allow GDAL network and archive paths");
  addZUnit(view);

  // bench
  CLI::App* bench = app.add_subcommand("bench", CommandSummary("bench"));
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
    "Also measure memory bandwidth and the slope, soil-humidity and water-flow kernels' share");
  bench->add_flag("--gpu-breakdown",
    line.BenchGPUBreakdown,
    "Also run each GPU stage once more with GPU profiling and print where its time goes "
    "(allocation, upload, kernels by GL timer queries, download, the rest) and the kernels' "
    "share of the GPU's copy bandwidth");
  bench->add_option("--json", line.BenchJson, "Also write the results as JSON here");
  std::string stages;
  {
    std::string all;
    for (const auto& n : BenchStageNames())
    {
      all += (all.empty() ? "" : ",") + n;
    }
    stages = all;
    bench->add_option("--stages", stages, "Comma-separated stages to time")->capture_default_str();
  }

  // info
  CLI::App* info = app.add_subcommand("info", CommandSummary("info"));
  info->add_option("IN", line.Input, "Input DEM")->required();
  info->add_flag(
    "--allow-network-paths", line.AllowNetwork, "Allow GDAL network and archive paths");
  addZUnit(info);

  // fractal
  CLI::App* fractal = app.add_subcommand("fractal", CommandSummary("fractal"));
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
    for (CLI::App* sub : { run,
           slope,
           temp,
           illum,
           infil,
           humid,
           flood,
           flow,
           flowacc,
           validate,
           kmeans,
           bench,
           info,
           fractal,
           view })
    {
      if (*sub)
      {
        line.Command = sub->get_name();
      }
    }
    if (*infil)
    {
      CheckSoilWater(line.SoilWater, infilText, *infil);
    }
    if (*humid)
    {
      CheckSoilWater(line.SoilWater, humidText, *humid);
      for (const std::string* extra :
        { &line.SoilWater.WeightedOutput, &line.SoilWater.StandingOutput })
      {
        if (!extra->empty() && *extra == line.Output)
        {
          throw std::invalid_argument("'" + *extra + "' is both OUT and an extra output");
        }
      }
      if (!line.SoilWater.WeightedOutput.empty() &&
        line.SoilWater.WeightedOutput == line.SoilWater.StandingOutput)
      {
        throw std::invalid_argument("--weighted and --standing name the same file");
      }
    }
    if (*flood)
    {
      CheckFloodFill(line.FloodFill, floodSeeds, floodCells, *flood);
      if (line.FloodFill.IdsOutput == line.Output)
      {
        throw std::invalid_argument("--ids: '" + line.Output + "' is also OUT");
      }
    }
    if (*flow)
    {
      CheckWaterFlow(line.WaterFlow, *flow);
      for (const std::string* extra :
        { &line.WaterFlow.DischargeOutput, &line.WaterFlow.RiverOutput })
      {
        if (!extra->empty() && *extra == line.Output)
        {
          throw std::invalid_argument("'" + *extra + "' is both OUT and an extra output");
        }
      }
    }
    if (*validate)
    {
      CheckWaterFlow(line.WaterFlow, *validate);
      if (!line.Validate.Sweep.empty())
      {
        std::string name;
        std::vector<std::string> values;
        ParseSweep(line.Validate.Sweep, name, values);
      }
      for (const std::string& peer : line.Validate.Peers)
      {
        const std::size_t eq = peer.find('=');
        if (eq == std::string::npos || eq == 0 || eq + 1 == peer.size())
        {
          throw std::invalid_argument("--peer: '" + peer + "' is not NAME=RASTER");
        }
      }
    }
    if (*kmeans)
    {
      ParseFeatures(kmeansFeatures, line.KMeans);
      for (const std::string* extra : { &line.KMeans.Csv, &line.KMeans.Json, &line.KMeans.Png })
      {
        if (!extra->empty() && *extra == line.Output)
        {
          throw std::invalid_argument("'" + *extra + "' is both OUT and an extra output");
        }
      }
    }
    if (*run)
    {
      CheckTemperature(line.Temperature, runMonthly);
      CheckSoilWater(line.SoilWater, runSoilText, *run);
    }
    if (*temp)
    {
      CheckTemperature(line.Temperature, tempMonthly);
    }
    if (*illum)
    {
      CheckIllumination(line.Illumination, illumText);
      const std::string& extra = line.Illumination.InsolationOutput.empty()
        ? line.Illumination.IncidenceOutput
        : line.Illumination.InsolationOutput;
      if (!extra.empty() && extra == line.Output)
      {
        throw std::invalid_argument(
          std::string(line.Illumination.InsolationOutput.empty() ? "--incidence" : "--insolation") +
          ": '" + extra + "' is also OUT");
      }
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
      std::vector<std::string> asked;
      std::stringstream st(stages);
      while (std::getline(st, item, ','))
      {
        const auto& known = BenchStageNames();
        if (std::find(known.begin(), known.end(), item) == known.end())
        {
          std::string list;
          for (const auto& n : known)
          {
            list += (list.empty() ? "" : ", ") + n;
          }
          throw std::invalid_argument("--stages: '" + item + "' is not one of " + list);
        }
        asked.push_back(item);
      }
      if (asked.empty())
      {
        throw std::invalid_argument("--stages: no stage given");
      }
      // In the order the stages run, each once.
      for (const auto& n : BenchStageNames())
      {
        if (std::find(asked.begin(), asked.end(), n) != asked.end())
        {
          line.BenchStages.push_back(n);
        }
      }
    }
    if (*view && !viewSize.empty())
    {
      int w = 0, h = 0;
      char x = 0, tail = 0;
      const bool digits = std::all_of(viewSize.begin(),
        viewSize.end(),
        [](char c) { return c == 'x' || std::isdigit(static_cast<unsigned char>(c)); });
      if (!digits || viewSize.size() > 11 ||
        std::sscanf(viewSize.c_str(), "%d%c%d%c", &w, &x, &h, &tail) != 3 || x != 'x')
      {
        throw std::invalid_argument(
          "--size: '" + viewSize + "' is not WIDTHxHEIGHT (e.g. 1024x768)");
      }
      if (w < 320 || w > 7680 || h < 240 || h > 4320)
      {
        throw std::invalid_argument("--size: " + viewSize + " is outside 320x240 to 7680x4320");
      }
      line.View.Width = w;
      line.View.Height = h;
    }
    if ((*slope || *temp || *illum || *infil || *humid || *flood || *info) && line.Input.empty())
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

// The options of `terroir illumination` (TerroirCommandOptions.h); its code is Illumination.cxx.
#include "TerroirCommandOptions.h"

#include "SolarPosition.h" // terroir::terrain::IsValidDate (TerroirTerrainCore, no VTK)

#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace terroir
{
namespace app
{
namespace
{
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

class IlluminationOptions : public CommandOptions
{
public:
  void Add(CLI::App* sub, CommandLine& line) override
  {
    sub->add_option("IN", line.Input, "Input DEM")->required();
    sub
      ->add_option("OUT",
        line.Output,
        "Output .tif (instant: Illuminated 0/1; daily, monthly: IlluminationHours, 1 or 12 "
        "bands) or .vti (all arrays)")
      ->required()
      ->check(EndsWith(RasterOutputs()));
    AddIlluminationOptions(sub, line.Illumination, this->Text);
    AddCommonOptions(sub, line);
  }
  void Check(CommandLine& line, const CLI::App&) override
  {
    CheckIllumination(line.Illumination, this->Text);
    const std::string& extra = line.Illumination.InsolationOutput.empty()
      ? line.Illumination.IncidenceOutput
      : line.Illumination.InsolationOutput;
    if (!extra.empty() && extra == line.Output)
    {
      throw std::invalid_argument(
        std::string(line.Illumination.InsolationOutput.empty() ? "--incidence" : "--insolation") +
        ": '" + extra + "' is also OUT");
    }
    CheckInputGiven(line);
  }

private:
  IlluminationText Text;
};
} // namespace

std::unique_ptr<CommandOptions> MakeIlluminationOptions()
{
  return std::unique_ptr<CommandOptions>(new IlluminationOptions);
}

} // namespace app
} // namespace terroir

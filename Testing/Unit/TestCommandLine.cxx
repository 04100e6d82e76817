// The `terroir` command-line parser (Applications/TerroirCommandLine.h): defaults, every option
// landing in its field, and bad command lines refused with exit status 2 and the exact line a
// user reads, before any file is touched.
#include "TerroirCommandLine.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace
{
terroir::app::ParseOutcome Parse(std::vector<std::string> args, terroir::app::CommandLine& line)
{
  args.insert(args.begin(), "terroir");
  std::vector<const char*> argv;
  for (const auto& a : args)
  {
    argv.push_back(a.c_str());
  }
  argv.push_back(nullptr);
  return terroir::app::ParseCommandLine(static_cast<int>(args.size()), argv.data(), line);
}

std::string ErrorOf(const std::vector<std::string>& args)
{
  terroir::app::CommandLine line;
  const auto outcome = Parse(args, line);
  EXPECT_FALSE(outcome.Run);
  EXPECT_EQ(outcome.ExitCode, 2);
  return outcome.Error;
}
} // namespace

TEST(TerroirCommandLineParse, RunDefaults)
{
  terroir::app::CommandLine line;
  const auto outcome = Parse({ "run" }, line);
  ASSERT_TRUE(outcome.Run) << outcome.Error;
  EXPECT_EQ(line.Command, "run");
  EXPECT_EQ(line.Input, "");
  EXPECT_EQ(line.Output, "terroir-out");
  EXPECT_EQ(line.Backend, "auto");
  EXPECT_FALSE(line.Overwrite);
  EXPECT_FALSE(line.AllowNetwork);
  EXPECT_EQ(line.ZUnit, "auto");
  EXPECT_EQ(line.Temperature.Coldest, 2.0);
  EXPECT_EQ(line.Temperature.Warmest, 20.0);
  EXPECT_EQ(line.Temperature.LapseRate, 6.4);
  EXPECT_TRUE(line.Temperature.Monthly.empty());
}

TEST(TerroirCommandLineParse, ZUnitIsOneOfTheKnownUnits)
{
  terroir::app::CommandLine line;
  for (const char* unit : { "auto", "m", "ft", "us-ft" })
  {
    ASSERT_TRUE(Parse({ "info", "dem.tif", "--z-unit", unit }, line).Run) << unit;
    EXPECT_EQ(line.ZUnit, unit);
  }
  EXPECT_NE(
    ErrorOf({ "validate", "dem.tif", "--z-unit", "feet" }).find("--z-unit"), std::string::npos);
  EXPECT_NE(ErrorOf({ "info", "dem.tif", "--z-unit" }).find("--z-unit"), std::string::npos);
}

TEST(TerroirCommandLineParse, EveryOptionLandsInItsField)
{
  terroir::app::CommandLine line;
  auto outcome = Parse({ "slope",
                         "in.tif",
                         "out.TIF",
                         "-z",
                         "0.3048",
                         "-p",
                         "--aspect",
                         "a.vti",
                         "--backend",
                         "cpu",
                         "--overwrite",
                         "--allow-network-paths",
                         "--z-unit",
                         "us-ft",
                         "-v" },
    line);
  ASSERT_TRUE(outcome.Run) << outcome.Error;
  EXPECT_EQ(line.Command, "slope");
  EXPECT_EQ(line.Input, "in.tif");
  EXPECT_EQ(line.Output, "out.TIF");
  EXPECT_EQ(line.ZFactor, 0.3048);
  EXPECT_TRUE(line.Percent);
  EXPECT_EQ(line.AspectOutput, "a.vti");
  EXPECT_EQ(line.Backend, "cpu");
  EXPECT_TRUE(line.Overwrite && line.AllowNetwork && line.Verbose);
  EXPECT_EQ(line.ZUnit, "us-ft");

  outcome = Parse({ "temperature",
                    "in.ter",
                    "t.tif",
                    "--monthly",
                    "1,2,3,4,5,6,7,8,9,10,11,-12.5",
                    "--lapse-rate",
                    "5",
                    "--hemisphere",
                    "south" },
    line);
  ASSERT_TRUE(outcome.Run) << outcome.Error;
  ASSERT_EQ(line.Temperature.Monthly.size(), 12u);
  EXPECT_EQ(line.Temperature.Monthly[11], -12.5);
  EXPECT_EQ(line.Temperature.LapseRate, 5.0);
  EXPECT_EQ(line.Temperature.Hemisphere, "south");

  outcome = Parse({ "bench", "--size", "64", "--backends", "cpu,auto" }, line);
  ASSERT_TRUE(outcome.Run) << outcome.Error;
  EXPECT_EQ(line.BenchSize, 64);
  EXPECT_EQ(line.BenchBackends, (std::vector<std::string>{ "cpu", "auto" }));

  outcome = Parse({ "fractal", "f.vti", "--size", "96", "--seed", "-3", "--spacing", "2.5" }, line);
  ASSERT_TRUE(outcome.Run) << outcome.Error;
  EXPECT_EQ(line.FractalSize, 96);
  EXPECT_EQ(line.FractalSeed, -3);
  EXPECT_EQ(line.FractalSpacing, 2.5);
}

TEST(TerroirCommandLineParse, HelpIsTextAndExitStatusZero)
{
  terroir::app::CommandLine line;
  const auto outcome = Parse({ "slope", "--help" }, line);
  EXPECT_FALSE(outcome.Run);
  EXPECT_EQ(outcome.ExitCode, 0);
  EXPECT_NE(outcome.Stdout.find("--zfactor"), std::string::npos) << outcome.Stdout;
  EXPECT_EQ(outcome.Error, "");
  // Every command's --help is its own help, not the program's.
  for (const char* command : { "run",
         "slope",
         "temperature",
         "illumination",
         "infiltration",
         "humidity",
         "floodfill",
         "waterflow",
         "flowacc",
         "validate",
         "kmeans",
         "bench",
         "info",
         "fractal",
         "view" })
  {
    const auto help = Parse({ command, "--help" }, line);
    EXPECT_EQ(help.ExitCode, 0) << command;
    EXPECT_NE(help.Stdout.find(std::string("Usage: terroir ") + command + " "), std::string::npos)
      << command << ":\n"
      << help.Stdout;
  }
}

TEST(TerroirCommandLineParse, NegativeOrAbsurdParametersAreRefused)
{
  EXPECT_EQ(ErrorOf({ "temperature", "a.tif", "b.tif", "--lapse-rate", "-1" }),
    "--lapse-rate: -1 is outside [0, 20] (see terroir --help)");
  EXPECT_EQ(ErrorOf({ "temperature", "a.tif", "b.tif", "--lapse-rate", "nan" }),
    "--lapse-rate: 'nan' is not a finite number (see terroir --help)");
  EXPECT_EQ(ErrorOf({ "temperature", "a.tif", "b.tif", "--warmest", "1e6" }),
    "--warmest: 1e6 is outside [-90, 60] (see terroir --help)");
  EXPECT_EQ(ErrorOf({ "temperature", "a.tif", "b.tif", "--coldest", "25" }),
    "--coldest (25) is above --warmest (20)");
  EXPECT_EQ(ErrorOf({ "temperature", "a.tif", "b.tif", "--monthly", "1,2,x" }),
    "--monthly: 'x' is not a number");
  EXPECT_EQ(ErrorOf({ "temperature", "a.tif", "b.tif", "--monthly", "1,2,3" }),
    "--monthly: expected 12 values, got 3");
  EXPECT_EQ(ErrorOf({ "temperature", "a.tif", "b.tif", "--monthly", "1,2,3,4,5,6,7,8,9,10,11,99" }),
    "--monthly: value 12 (99) is outside [-90, 60]");
  EXPECT_EQ(ErrorOf({ "slope", "a.tif", "b.tif", "-z", "0" }),
    "--zfactor: 0 is outside [1e-09, 1e+09] (see terroir --help)");
  EXPECT_EQ(ErrorOf({ "slope", "a.tif", "b.png" }),
    "OUT: 'b.png': unknown output format (use .tif, .tiff, .vti) (see terroir --help)");
  EXPECT_EQ(ErrorOf({ "fractal", "f.tif", "--size", "0" }),
    "--size: Value 0 not in range 2 to 65536 (see terroir --help)");
  EXPECT_EQ(ErrorOf({ "fractal", "f.tif", "--spacing", "-5" }),
    "--spacing: -5 is outside [0.001, 100000] (see terroir --help)");
  EXPECT_EQ(
    ErrorOf({ "bench", "--backends", "cpu,cuda" }), "--backends: 'cuda' is not auto, cpu or gpu");
  EXPECT_EQ(ErrorOf({ "slope", "", "b.tif" }), "the input file name is empty");
  EXPECT_EQ(ErrorOf({ "slope", "a.tif" }), "OUT is required (see terroir --help)");
}

TEST(TerroirCommandLineParse, IlluminationDefaultsAreMonthly)
{
  terroir::app::CommandLine line;
  const auto outcome = Parse({ "illumination", "in.tif", "hours.tif" }, line);
  ASSERT_TRUE(outcome.Run) << outcome.Error;
  EXPECT_EQ(line.Command, "illumination");
  EXPECT_EQ(line.Input, "in.tif");
  EXPECT_EQ(line.Output, "hours.tif");
  const auto& s = line.Illumination;
  EXPECT_EQ(s.Mode, "monthly");
  EXPECT_EQ(s.Year, 2025);
  EXPECT_EQ(s.MonthlyDay, 15);
  EXPECT_EQ(s.TimeStep, 10.0);
  EXPECT_TRUE(std::isnan(s.Latitude) && std::isnan(s.Longitude) && std::isnan(s.Orientation));
  EXPECT_EQ(s.Method, "horizon");
  EXPECT_EQ(s.Sectors, 64);
  EXPECT_FALSE(s.Curvature);
  EXPECT_EQ(s.Transmittance, 0.7);
  EXPECT_FALSE(s.UseSun);
  EXPECT_EQ(s.InsolationOutput, "");
  EXPECT_EQ(s.IncidenceOutput, "");
}

TEST(TerroirCommandLineParse, IlluminationOptionsLandInTheirFields)
{
  terroir::app::CommandLine line;
  auto outcome = Parse({ "illumination",
                         "in.ter",
                         "shadow.vti",
                         "--mode",
                         "instant",
                         "--date",
                         "2024-02-29",
                         "--time",
                         "16:30:36",
                         "--utc-offset",
                         "-8",
                         "--lat",
                         "39.43",
                         "--lon",
                         "-120.24",
                         "--orientation",
                         "-0.9",
                         "--method",
                         "raymarch",
                         "--sectors",
                         "128",
                         "--curvature",
                         "--transmittance",
                         "0.6",
                         "--incidence",
                         "cos.tif",
                         "--backend",
                         "gpu" },
    line);
  ASSERT_TRUE(outcome.Run) << outcome.Error;
  const auto& s = line.Illumination;
  EXPECT_EQ(s.Mode, "instant");
  EXPECT_EQ(s.Year, 2024);
  EXPECT_EQ(s.Month, 2);
  EXPECT_EQ(s.Day, 29);
  EXPECT_TRUE(s.HasTime);
  EXPECT_DOUBLE_EQ(s.Time, 16.51);
  EXPECT_EQ(s.UTCOffset, -8.0);
  EXPECT_EQ(s.Latitude, 39.43);
  EXPECT_EQ(s.Longitude, -120.24);
  EXPECT_EQ(s.Orientation, -0.9);
  EXPECT_EQ(s.Method, "raymarch");
  EXPECT_EQ(s.Sectors, 128);
  EXPECT_TRUE(s.Curvature);
  EXPECT_EQ(s.Transmittance, 0.6);
  EXPECT_EQ(s.IncidenceOutput, "cos.tif");
  EXPECT_EQ(line.Backend, "gpu");

  outcome =
    Parse({ "illumination", "in.tif", "o.tif", "--mode", "instant", "--sun", "225,10.5" }, line);
  ASSERT_TRUE(outcome.Run) << outcome.Error;
  EXPECT_TRUE(line.Illumination.UseSun);
  EXPECT_EQ(line.Illumination.SunAzimuth, 225.0);
  EXPECT_EQ(line.Illumination.SunElevation, 10.5);
  EXPECT_FALSE(line.Illumination.HasTime);

  outcome = Parse({ "illumination",
                    "in.tif",
                    "o.tif",
                    "--mode",
                    "daily",
                    "--date",
                    "2025-12-21",
                    "--step",
                    "2.5",
                    "--insolation",
                    "w.tiff" },
    line);
  ASSERT_TRUE(outcome.Run) << outcome.Error;
  EXPECT_EQ(line.Illumination.Month, 12);
  EXPECT_EQ(line.Illumination.Day, 21);
  EXPECT_EQ(line.Illumination.TimeStep, 2.5);
  EXPECT_EQ(line.Illumination.InsolationOutput, "w.tiff");

  outcome = Parse({ "illumination", "in.tif", "o.tif", "--year", "2000", "--day", "31" }, line);
  ASSERT_TRUE(outcome.Run) << outcome.Error;
  EXPECT_EQ(line.Illumination.Year, 2000);
  EXPECT_EQ(line.Illumination.MonthlyDay, 31);

  // Times at the ends of the day.
  for (const auto& [text, hours] : { std::make_pair("0:00", 0.0),
         std::make_pair("09:05", 9.0 + 5.0 / 60.0),
         std::make_pair("24:00", 24.0),
         std::make_pair("23:59:59", 24.0 - 1.0 / 3600.0) })
  {
    outcome =
      Parse({ "illumination", "a.tif", "b.tif", "--mode", "instant", "--time", text }, line);
    ASSERT_TRUE(outcome.Run) << text << ": " << outcome.Error;
    EXPECT_DOUBLE_EQ(line.Illumination.Time, hours) << text;
  }

  // run takes the observer's place for DEMs without georeference.
  outcome = Parse({ "run", "--lat", "-33.9", "--lon", "18.4" }, line);
  ASSERT_TRUE(outcome.Run) << outcome.Error;
  EXPECT_EQ(line.Illumination.Latitude, -33.9);
  EXPECT_EQ(line.Illumination.Longitude, 18.4);
}

TEST(TerroirCommandLineParse, BadIlluminationParametersAreRefused)
{
  const std::vector<std::string> io{ "illumination", "a.tif", "b.tif" };
  auto with = [&io](std::vector<std::string> extra)
  {
    std::vector<std::string> args = io;
    args.insert(args.end(), extra.begin(), extra.end());
    return ErrorOf(args);
  };
  EXPECT_EQ(with({ "--lat", "91" }), "--lat: 91 is outside [-90, 90] (see terroir --help)");
  EXPECT_EQ(with({ "--lat", "-90.5" }), "--lat: -90.5 is outside [-90, 90] (see terroir --help)");
  EXPECT_EQ(with({ "--lon", "181" }), "--lon: 181 is outside [-180, 180] (see terroir --help)");
  EXPECT_EQ(with({ "--lon", "inf" }), "--lon: 'inf' is not a finite number (see terroir --help)");
  EXPECT_EQ(with({ "--step", "0" }), "--step: 0 is outside [1, 1440] (see terroir --help)");
  EXPECT_EQ(with({ "--step", "-10" }), "--step: -10 is outside [1, 1440] (see terroir --help)");
  EXPECT_EQ(with({ "--step", "1441" }), "--step: 1441 is outside [1, 1440] (see terroir --help)");
  EXPECT_EQ(
    with({ "--mode", "daily", "--date", "2025-02-29" }), "--date: 2025-02-29 does not exist");
  EXPECT_EQ(
    with({ "--mode", "daily", "--date", "2025-04-31" }), "--date: 2025-04-31 does not exist");
  EXPECT_EQ(
    with({ "--mode", "daily", "--date", "2025-13-01" }), "--date: 2025-13-01 does not exist");
  EXPECT_EQ(
    with({ "--mode", "daily", "--date", "0000-01-01" }), "--date: 0000-01-01 does not exist");
  for (const std::string bad : { "2025/06/21", "25-06-21", "2025-6-21", "2025-06-21x", "" })
  {
    EXPECT_EQ(with({ "--mode", "daily", "--date", bad }),
      "--date: '" + bad + "' is not a date (YYYY-MM-DD)");
  }
  for (const std::string bad : { "24:01", "12:60", "12", "7:5", "12:00:60", "-1:00", "12:00:", "" })
  {
    EXPECT_EQ(with({ "--mode", "instant", "--time", bad }),
      "--time: '" + bad + "' is not a time of day (HH:MM or HH:MM:SS, 00:00 to 24:00)");
  }
  EXPECT_EQ(with({ "--mode", "instant", "--time", "12:00", "--utc-offset", "15" }),
    "--utc-offset: 15 is outside [-14, 14] (see terroir --help)");
  EXPECT_EQ(with({ "--year", "0" }), "--year: Value 0 not in range 1 to 9999 (see terroir --help)");
  EXPECT_EQ(with({ "--day", "32" }), "--day: Value 32 not in range 1 to 31 (see terroir --help)");
  EXPECT_EQ(
    with({ "--sectors", "2" }), "--sectors: Value 2 not in range 4 to 1024 (see terroir --help)");
  EXPECT_EQ(with({ "--transmittance", "0" }),
    "--transmittance: 0 is outside [0.01, 1] (see terroir --help)");
  EXPECT_EQ(with({ "--transmittance", "1.5" }),
    "--transmittance: 1.5 is outside [0.01, 1] (see terroir --help)");
  EXPECT_EQ(with({ "--orientation", "nan" }),
    "--orientation: 'nan' is not a finite number (see terroir --help)");
  EXPECT_EQ(with({ "--mode", "hourly" }),
    "--mode: hourly not in {instant,daily,monthly} (see terroir --help)");
  EXPECT_EQ(with({ "--method", "exact" }),
    "--method: exact not in {horizon,raymarch} (see terroir --help)");
  EXPECT_EQ(
    with({ "--mode", "instant", "--sun", "180" }), "--sun: expected AZ,EL (2 values), got 1");
  EXPECT_EQ(
    with({ "--mode", "instant", "--sun", "400,10" }), "--sun: azimuth 400 is outside [0, 360]");
  EXPECT_EQ(
    with({ "--mode", "instant", "--sun", "180,95" }), "--sun: elevation 95 is outside [-90, 90]");
  EXPECT_EQ(with({ "--mode", "instant", "--sun", "180,nan" }), "--sun: 'nan' is not a number");
  EXPECT_EQ(with({ "--insolation", "w.png" }),
    "--insolation: 'w.png': unknown output format (use .tif, .tiff, .vti) (see terroir --help)");
  EXPECT_EQ(with({ "--insolation", "b.tif" }), "--insolation: 'b.tif' is also OUT");
  EXPECT_EQ(ErrorOf({ "illumination", "", "b.tif" }), "the input file name is empty");
  EXPECT_EQ(
    ErrorOf({ "run", "--lat", "100" }), "--lat: 100 is outside [-90, 90] (see terroir --help)");
}

TEST(TerroirCommandLineParse, IlluminationOptionsMustFitTheMode)
{
  auto with = [](std::vector<std::string> extra)
  {
    std::vector<std::string> args{ "illumination", "a.tif", "b.tif" };
    args.insert(args.end(), extra.begin(), extra.end());
    return ErrorOf(args);
  };
  EXPECT_EQ(with({ "--mode", "instant" }), "--mode instant needs --time HH:MM (or --sun AZ,EL)");
  EXPECT_EQ(with({ "--time", "12:00" }), "--time applies to --mode instant only");
  EXPECT_EQ(with({ "--mode", "daily", "--utc-offset", "-8" }),
    "--utc-offset applies to --mode instant only");
  EXPECT_EQ(with({ "--sun", "180,30" }), "--sun applies to --mode instant only");
  EXPECT_EQ(with({ "--incidence", "c.tif" }),
    "--incidence applies to --mode instant only (daily and monthly give --insolation)");
  EXPECT_EQ(with({ "--mode", "instant", "--time", "12:00", "--step", "5" }),
    "--step applies to --mode daily or monthly");
  EXPECT_EQ(with({ "--mode", "instant", "--time", "12:00", "--insolation", "w.tif" }),
    "--insolation applies to --mode daily or monthly (instant gives --incidence)");
  EXPECT_EQ(with({ "--date", "2025-06-21" }),
    "--date applies to --mode instant or daily (monthly takes --year and --day)");
  EXPECT_EQ(with({ "--mode", "daily", "--year", "2024" }),
    "--year applies to --mode monthly (instant and daily take --date)");
  EXPECT_EQ(with({ "--mode", "instant", "--time", "9:00", "--day", "3" }),
    "--day applies to --mode monthly (instant and daily take --date)");
  EXPECT_EQ(with({ "--mode", "instant", "--sun", "180,30", "--time", "12:00" }),
    "--sun excludes --date, --time and --utc-offset");
}

TEST(TerroirCommandLineParse, BenchStages)
{
  terroir::app::CommandLine line;
  auto outcome = Parse({ "bench" }, line);
  ASSERT_TRUE(outcome.Run) << outcome.Error;
  EXPECT_EQ(line.BenchStages, terroir::app::BenchStageNames());
  EXPECT_EQ(line.BenchStages,
    (std::vector<std::string>{ "slope",
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
      "morphometry" }));
  // Run in the fixed order, each once, whatever the order asked.
  outcome = Parse({ "bench", "--stages", "monthly,horizon,instant,horizon" }, line);
  ASSERT_TRUE(outcome.Run) << outcome.Error;
  EXPECT_EQ(line.BenchStages, (std::vector<std::string>{ "horizon", "instant", "monthly" }));
  EXPECT_EQ(ErrorOf({ "bench", "--stages", "slope,shadows" }),
    "--stages: 'shadows' is not one of slope, temperature, horizon, instant, monthly, "
    "infiltration, humidity, floodfill, depressions, flowacc, waterflow, kmeans, morphometry");
  EXPECT_EQ(ErrorOf({ "bench", "--stages", "" }), "--stages: no stage given");
}

TEST(TerroirCommandLineParse, InfiltrationOperationsKeepTheirOrder)
{
  terroir::app::CommandLine line;
  auto outcome = Parse({ "infiltration",
                         "dem.tif",
                         "rates.tif",
                         "--fill",
                         "15",
                         "--paint-polygons",
                         "rock=s.geojson=2.5",
                         "--slope-rule",
                         "30",
                         "--soil-polygons",
                         "soils.shp=TEXTURE",
                         "--fill",
                         "7",
                         "--soil-raster",
                         "soil.tif",
                         "--paint-raster",
                         "mask.tif=0" },
    line);
  ASSERT_TRUE(outcome.Run) << outcome.Error;
  EXPECT_EQ(line.Command, "infiltration");
  const auto& ops = line.SoilWater.Operations;
  ASSERT_EQ(ops.size(), 7u);
  const char* kinds[7] = {
    "fill", "paint-polygons", "slope-rule", "soil-polygons", "fill", "soil-raster", "paint-raster"
  };
  for (int k = 0; k < 7; ++k)
  {
    EXPECT_EQ(ops[k].Kind, kinds[k]) << k;
  }
  EXPECT_EQ(ops[0].Value, 15.0);
  EXPECT_EQ(ops[1].File, "rock=s.geojson"); // split at the last '='
  EXPECT_EQ(ops[1].Value, 2.5);
  EXPECT_EQ(ops[2].Value, 30.0);
  EXPECT_EQ(ops[3].File, "soils.shp");
  EXPECT_EQ(ops[3].Attribute, "TEXTURE");
  EXPECT_EQ(ops[4].Value, 7.0);
  EXPECT_EQ(ops[5].File, "soil.tif");
  EXPECT_EQ(ops[6].Value, 0.0);
  // No operation: the filter's default recipe.
  outcome = Parse({ "infiltration", "dem.tif", "rates.tif" }, line);
  ASSERT_TRUE(outcome.Run) << outcome.Error;
  EXPECT_TRUE(line.SoilWater.Operations.empty());
  EXPECT_EQ(ErrorOf({ "infiltration", "d.tif", "r.tif", "--fill", "-1" }),
    "--fill: '-1' is not a rate in [0, 1000] mm/h");
  EXPECT_EQ(ErrorOf({ "infiltration", "d.tif", "r.tif", "--slope-rule", "95" }),
    "--slope-rule: '95' is not an angle in [0, 90] degrees");
  EXPECT_EQ(ErrorOf({ "infiltration", "d.tif", "r.tif", "--paint-raster", "mask.tif" }),
    "--paint-raster: 'mask.tif' is not FILE=RATE");
  EXPECT_EQ(ErrorOf({ "infiltration", "d.tif", "r.tif", "--soil-polygons", "soils.shp=" }),
    "--soil-polygons: 'soils.shp=' is not FILE=FIELD");
}

TEST(TerroirCommandLineParse, HumidityClimate)
{
  terroir::app::CommandLine line;
  auto outcome = Parse({ "humidity",
                         "dem.tif",
                         "h.tif",
                         "--precip",
                         "1,2,3,4,5,6,7,8,9,10,11,12",
                         "--intensity",
                         "2,2,2,2,2,2,2,2,2,2,2,2",
                         "--weighted",
                         "w.tif",
                         "--standing",
                         "s.vti",
                         "--infiltration",
                         "rates.tif" },
    line);
  ASSERT_TRUE(outcome.Run) << outcome.Error;
  ASSERT_EQ(line.SoilWater.Precipitation.size(), 12u);
  EXPECT_EQ(line.SoilWater.Precipitation[11], 12.0);
  EXPECT_EQ(line.SoilWater.Intensity[0], 2.0);
  EXPECT_EQ(line.SoilWater.WeightedOutput, "w.tif");
  EXPECT_EQ(line.SoilWater.StandingOutput, "s.vti");
  EXPECT_EQ(line.SoilWater.InfiltrationInput, "rates.tif");
  EXPECT_EQ(ErrorOf({ "humidity", "d.tif", "h.tif", "--precip", "80,70" }),
    "--precip: expected 12 values (January first), got 2");
  EXPECT_EQ(ErrorOf({ "humidity", "d.tif", "h.tif", "--precip", "1,2,3,4,5,6,7,8,9,10,11,-12" }),
    "--precip: value 12 (-12) is outside [0, 10000]");
  EXPECT_EQ(ErrorOf({ "humidity",
              "d.tif",
              "h.tif",
              "--precip",
              "1,2,3,4,5,6,7,8,9,10,11,12",
              "--intensity",
              "2,2,0,2,2,2,2,2,2,2,2,2" }),
    "--intensity: month 3 has rain (--precip) but intensity 0: rain needs a positive intensity");
  EXPECT_EQ(ErrorOf({ "humidity",
              "d.tif",
              "h.tif",
              "--climate",
              "c.csv",
              "--precip",
              "1,2,3,4,5,6,7,8,9,10,11,12" }),
    "--precip and --intensity exclude --climate");
  EXPECT_EQ(ErrorOf({ "humidity", "d.tif", "h.tif", "--weighted", "h.tif" }),
    "'h.tif' is both OUT and an extra output");
  EXPECT_NE(
    ErrorOf({ "humidity", "d.tif", "h.tif", "--infiltration", "r.tif", "--fill", "3" }), "");
}

TEST(TerroirCommandLineParse, FloodFillSeeds)
{
  terroir::app::CommandLine line;
  auto outcome = Parse({ "floodfill",
                         "dem.tif",
                         "lake.tif",
                         "--seed",
                         "215375,4371215",
                         "--seed",
                         "1,2,2100.5",
                         "--seed-cell",
                         "10,20",
                         "--level",
                         "2118" },
    line);
  ASSERT_TRUE(outcome.Run) << outcome.Error;
  const auto& f = line.FloodFill;
  ASSERT_EQ(f.Seeds.size(), 3u);
  EXPECT_EQ(f.Seeds[0].X, 215375.0);
  EXPECT_TRUE(std::isnan(f.Seeds[0].Level));
  EXPECT_EQ(f.Seeds[1].Level, 2100.5);
  EXPECT_TRUE(f.Seeds[2].Cell);
  EXPECT_EQ(f.Seeds[2].Y, 20.0);
  EXPECT_EQ(f.Level, 2118.0);
  EXPECT_FALSE(f.FillDepressions);
  outcome = Parse({ "floodfill",
                    "dem.tif",
                    "lakes.tif",
                    "--fill-depressions",
                    "--min-area",
                    "500",
                    "--no-flat-surfaces",
                    "--ids",
                    "ids.tif" },
    line);
  ASSERT_TRUE(outcome.Run) << outcome.Error;
  EXPECT_TRUE(line.FloodFill.FillDepressions);
  EXPECT_EQ(line.FloodFill.MinimumArea, 500.0);
  EXPECT_FALSE(line.FloodFill.FlatSurfaces);
  EXPECT_EQ(line.FloodFill.IdsOutput, "ids.tif");
  EXPECT_EQ(ErrorOf({ "floodfill", "d.tif", "l.tif" }),
    "floodfill needs --seed X,Y (or --seed-cell I,J) or --fill-depressions");
  EXPECT_EQ(
    ErrorOf({ "floodfill", "d.tif", "l.tif", "--seed", "1" }), "--seed: '1' is not X,Y[,LEVEL]");
  EXPECT_EQ(ErrorOf({ "floodfill", "d.tif", "l.tif", "--seed-cell", "1.5,2" }),
    "--seed-cell: '1.5,2': I and J must be cell indices (>= 0)");
  EXPECT_EQ(ErrorOf({ "floodfill", "d.tif", "l.tif", "--seed", "1,2", "--fill-depressions" }),
    "--fill-depressions excludes --seed and --seed-cell");
  EXPECT_EQ(ErrorOf({ "floodfill", "d.tif", "l.tif", "--seed", "1,2", "--min-area", "5" }),
    "--min-area and --no-flat-surfaces apply to --fill-depressions");
  EXPECT_EQ(ErrorOf({ "floodfill", "d.tif", "l.tif", "--fill-depressions", "--level", "5" }),
    "--level applies to seeds, not to --fill-depressions");
  EXPECT_EQ(
    ErrorOf({ "floodfill", "d.tif", "l.tif", "--seed", "1,nan" }), "--seed: 'nan' is not a number");
}

TEST(TerroirCommandLineParse, WaterFlowFlowAccAndValidate)
{
  terroir::app::CommandLine line;
  auto outcome = Parse({ "waterflow",
                         "dem.tif",
                         "w.tif",
                         "--water",
                         "50",
                         "--max-iterations",
                         "200",
                         "--auto-stop",
                         "0.01",
                         "--time",
                         "3600",
                         "--iteration-duration",
                         "5",
                         "--river-threshold",
                         "1e4",
                         "--discharge",
                         "q.tif",
                         "--river",
                         "r.vti" },
    line);
  ASSERT_TRUE(outcome.Run) << outcome.Error;
  EXPECT_EQ(line.Command, "waterflow");
  const auto& w = line.WaterFlow;
  EXPECT_EQ(w.InitialWater, 50.0);
  EXPECT_EQ(w.MaximumIterations, 200);
  EXPECT_EQ(w.AutoStop, 0.01);
  EXPECT_EQ(w.Time, 3600.0);
  EXPECT_EQ(w.IterationDuration, 5.0);
  EXPECT_EQ(w.RiverThreshold, 1e4);
  EXPECT_EQ(w.DischargeOutput, "q.tif");
  EXPECT_EQ(w.RiverOutput, "r.vti");
  EXPECT_EQ(ErrorOf({ "waterflow", "d.tif", "w.tif", "--water", "5", "--month", "3" }),
    "--water, --month and --annual exclude each other");
  EXPECT_EQ(ErrorOf({ "waterflow", "d.tif", "w.tif", "--discharge", "w.tif" }),
    "'w.tif' is both OUT and an extra output");
  EXPECT_EQ(ErrorOf({ "waterflow", "d.tif", "w.tif", "--auto-stop", "1" }),
    "--auto-stop: 1 is outside [0, 0.999] (see terroir --help)");

  outcome = Parse({ "flowacc", "dem.tif", "acc.vti", "--river-threshold", "2e5" }, line);
  ASSERT_TRUE(outcome.Run) << outcome.Error;
  EXPECT_EQ(line.Command, "flowacc");
  EXPECT_EQ(line.FlowRiverThreshold, 2e5);
  EXPECT_EQ(ErrorOf({ "flowacc", "d.tif", "a.tif", "--river-threshold", "-1" }),
    "--river-threshold: -1 is outside [0, 1e+18] (see terroir --help)");

  // validate: the DEM may be left out (the bundled one); peers are NAME=RASTER.
  outcome = Parse({ "validate", "--peer", "grass=g.tif", "--peer", "wbt=w.tif", "--annual" }, line);
  ASSERT_TRUE(outcome.Run) << outcome.Error;
  EXPECT_EQ(line.Command, "validate");
  EXPECT_EQ(line.Input, "");
  EXPECT_EQ(line.Validate.Peers, (std::vector<std::string>{ "grass=g.tif", "wbt=w.tif" }));
  EXPECT_TRUE(line.WaterFlow.Annual);
  EXPECT_EQ(
    ErrorOf({ "validate", "d.tif", "--peer", "grass" }), "--peer: 'grass' is not NAME=RASTER");
  EXPECT_EQ(
    ErrorOf({ "validate", "d.tif", "--peer", "=g.tif" }), "--peer: '=g.tif' is not NAME=RASTER");

  // flowacc methods; the water flow's mode, rain and balance; validate's sweep.
  outcome = Parse({ "flowacc", "d.tif", "a.tif", "--method", "dinf", "--mfd-exponent", "4" }, line);
  ASSERT_TRUE(outcome.Run) << outcome.Error;
  EXPECT_EQ(line.FlowMethod, "dinf");
  EXPECT_EQ(line.FlowMFDExponent, 4.0);
  EXPECT_NE(ErrorOf({ "flowacc", "d.tif", "a.tif", "--method", "d16" }).find("--method"),
    std::string::npos);
  outcome = Parse(
    { "validate", "--mode", "pulse", "--rain", "2", "--balance", "0.05", "--sweep", "water=1,10" },
    line);
  ASSERT_TRUE(outcome.Run) << outcome.Error;
  EXPECT_EQ(line.WaterFlow.Mode, "pulse");
  EXPECT_EQ(line.WaterFlow.RainRate, 2.0);
  EXPECT_EQ(line.WaterFlow.BalanceTolerance, 0.05);
  EXPECT_EQ(line.Validate.Sweep, "water=1,10");
  EXPECT_EQ(ErrorOf({ "validate", "--sweep", "colour=1,2" }),
    "--sweep: unknown option 'colour' (water, rain, balance, thinning, settle, "
    "max-iterations, auto-stop, time, iteration-duration, river-threshold, mode)");
  EXPECT_EQ(ErrorOf({ "validate", "--sweep", "rain" }),
    "--sweep needs NAME=V1,V2,... (e.g. rain=0.1,0.3,1), not 'rain'");
  EXPECT_EQ(ErrorOf({ "validate", "--sweep", "rain=1,-2" }),
    "--sweep: rain = -2 is out of range (1e-9 to 1e6 mm/h)");
  EXPECT_EQ(ErrorOf({ "validate", "--sweep", "mode=pulse,fast" }),
    "--sweep: mode must be pulse or rivers, not 'fast'");
  // The coarse-to-fine start: on unless --no-warm-start; its settling count.
  EXPECT_TRUE(line.WaterFlow.WarmStart);
  EXPECT_EQ(line.WaterFlow.Settle, 100);
  outcome = Parse({ "validate", "--no-warm-start", "--settle", "30" }, line);
  ASSERT_TRUE(outcome.Run) << outcome.Error;
  EXPECT_FALSE(line.WaterFlow.WarmStart);
  EXPECT_EQ(line.WaterFlow.Settle, 30);
  EXPECT_EQ(ErrorOf({ "validate", "--settle", "-1" }),
    "--settle: Value -1 not in range 0 to 100000000 (see terroir --help)");
  terroir::app::WaterFlowSettings swept;
  terroir::app::ApplySweepValue(swept, "settle", "40");
  EXPECT_EQ(swept.Settle, 40);
  EXPECT_THROW(terroir::app::ApplySweepValue(swept, "settle", "4.5"), std::invalid_argument);
  terroir::app::ApplySweepValue(swept, "max-iterations", "250");
  EXPECT_EQ(swept.MaximumIterations, 250);
  EXPECT_THROW(
    terroir::app::ApplySweepValue(swept, "max-iterations", "2.5"), std::invalid_argument);
}

TEST(TerroirCommandLineParse, KMeansFeaturesAndOutputs)
{
  terroir::app::CommandLine line;
  auto outcome = Parse({ "kmeans",
                         "terrain.vti",
                         "zones.tif",
                         "-k",
                         "8",
                         "--features",
                         "Slope:2,Temperature",
                         "--standardize",
                         "--seeding",
                         "kmeans++",
                         "--seed",
                         "7",
                         "--csv",
                         "t.CSV",
                         "--png",
                         "t.png" },
    line);
  ASSERT_TRUE(outcome.Run) << outcome.Error;
  const auto& k = line.KMeans;
  EXPECT_EQ(k.Clusters, 8);
  EXPECT_EQ(k.FeatureNames, (std::vector<std::string>{ "Slope", "Temperature" }));
  EXPECT_EQ(k.FeatureWeights, (std::vector<double>{ 2.0, 1.0 }));
  EXPECT_TRUE(k.Standardize);
  EXPECT_EQ(k.Seeding, "kmeans++");
  EXPECT_EQ(k.Seed, 7);
  EXPECT_EQ(k.Csv, "t.CSV");
  EXPECT_EQ(k.Png, "t.png");
  EXPECT_EQ(ErrorOf({ "kmeans", "t.vti", "z.tif", "-k", "65" }),
    "--clusters: Value 65 not in range 1 to 64 (see terroir --help)");
  EXPECT_EQ(ErrorOf({ "kmeans", "t.vti", "z.tif", "--features", "Slope,Slope:2" }),
    "--features: 'Slope' is given twice");
  EXPECT_EQ(ErrorOf({ "kmeans", "t.vti", "z.tif", "--features", "Slope:-1" }),
    "--features: 'Slope:-1' needs one weight >= 0 after the colon");
  EXPECT_EQ(ErrorOf({ "kmeans", "t.vti", "z.tif", "--png", "z.jpg" }),
    "--png: 'z.jpg': unknown output format (use .png) (see terroir --help)");
}

TEST(TerroirCommandLineParse, ViewOptions)
{
  terroir::app::CommandLine line;
  auto outcome = Parse({ "view" }, line);
  ASSERT_TRUE(outcome.Run) << outcome.Error;
  EXPECT_EQ(line.Command, "view");
  EXPECT_EQ(line.Input, ""); // the bundled DEM
  EXPECT_EQ(line.View.Width, 1024);
  EXPECT_EQ(line.View.Height, 768);
  // A GDAL network path is the viewer's to refuse or open (--allow-network-paths), not the
  // parser's (Testing/Fuzz/regressions/CommandLine/view-with-network-path).
  outcome = Parse({ "view", "/vsicurl/http://x/y.tif", "--allow-network-paths" }, line);
  ASSERT_TRUE(outcome.Run) << outcome.Error;
  EXPECT_TRUE(line.AllowNetwork);
  outcome = Parse({ "view",
                    "dem.tif",
                    "--size",
                    "800x600",
                    "--overlay",
                    "water",
                    "--style",
                    "first-person",
                    "--month",
                    "3",
                    "--hour",
                    "14.5",
                    "--clusters",
                    "6",
                    "--lake-depth",
                    "3" },
    line);
  ASSERT_TRUE(outcome.Run) << outcome.Error;
  const auto& v = line.View;
  EXPECT_EQ(v.Width, 800);
  EXPECT_EQ(v.Height, 600);
  EXPECT_EQ(v.Overlay, "water");
  EXPECT_EQ(v.Style, "first-person");
  EXPECT_EQ(v.Month, 3);
  EXPECT_EQ(v.Hour, 14.5);
  EXPECT_EQ(v.Clusters, 6);
  EXPECT_EQ(v.LakeDepth, 3.0);
  EXPECT_EQ(
    ErrorOf({ "view", "--size", "100x100" }), "--size: 100x100 is outside 320x240 to 7680x4320");
  EXPECT_EQ(ErrorOf({ "view", "--size", "1024x768x" }),
    "--size: '1024x768x' is not WIDTHxHEIGHT (e.g. 1024x768)");
  EXPECT_EQ(
    ErrorOf({ "view", "--hour", "25" }), "--hour: 25 is outside [0, 24] (see terroir --help)");
}

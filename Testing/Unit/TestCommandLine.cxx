// The `terroir` command-line parser (Applications/TerroirCommandLine.h): defaults, every option
// landing in its field, and bad command lines refused with exit status 2 and the exact line a
// user reads, before any file is touched.
#include "TerroirCommandLine.h"

#include <gtest/gtest.h>

#include <string>
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
  EXPECT_EQ(line.Temperature.Coldest, 2.0);
  EXPECT_EQ(line.Temperature.Warmest, 20.0);
  EXPECT_EQ(line.Temperature.LapseRate, 6.4);
  EXPECT_TRUE(line.Temperature.Monthly.empty());
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

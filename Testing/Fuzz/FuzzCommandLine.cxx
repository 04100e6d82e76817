// libFuzzer harness: the `terroir` command-line parser (terroir::app::ParseCommandLine) on
// arbitrary argument lists. The input is split at NUL bytes into at most 32 arguments after
// argv[0]. Aborts (__builtin_trap) when an invariant breaks:
// - the parser either accepts (a known command, every number finite and inside its documented
//   range, 12 or no monthly temperatures, a date that exists, options that fit the illumination
//   mode, output names with a known extension), or prints
//   help (exit status 0, text, no error), or refuses with exit status 2 and one line of error;
// - it never exits, throws or prints by itself (a throw or exit would end the fuzzer).
#include "FuzzCheck.h"
#include "TerroirCommandLine.h"

#include "SolarPosition.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace
{
using terroir_fuzz::Check;

bool EndsWithRasterExtension(const std::string& name)
{
  std::string lower = name;
  for (char& c : lower)
  {
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  for (const std::string ext : { ".tif", ".tiff", ".vti" })
  {
    if (lower.size() > ext.size() && lower.compare(lower.size() - ext.size(), ext.size(), ext) == 0)
    {
      return true;
    }
  }
  return false;
}

bool Within(double v, double lo, double hi)
{
  return std::isfinite(v) && v >= lo && v <= hi;
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  std::vector<std::string> args{ "terroir" };
  std::string current;
  for (std::size_t k = 0; k < size && args.size() < 33; ++k)
  {
    if (data[k] == 0)
    {
      args.push_back(current);
      current.clear();
    }
    else
    {
      current.push_back(static_cast<char>(data[k]));
    }
  }
  if (!current.empty() && args.size() < 33)
  {
    args.push_back(current);
  }
  std::vector<const char*> argv;
  for (const auto& a : args)
  {
    argv.push_back(a.c_str());
  }
  argv.push_back(nullptr);

  terroir::app::CommandLine line;
  const terroir::app::ParseOutcome outcome =
    terroir::app::ParseCommandLine(static_cast<int>(args.size()), argv.data(), line);
  if (!outcome.Run)
  {
    if (outcome.ExitCode == 0)
    {
      Check(!outcome.Stdout.empty() && outcome.Error.empty());
    }
    else
    {
      Check(outcome.ExitCode == 2);
      Check(!outcome.Error.empty() && outcome.Error.find('\n') == std::string::npos);
    }
    return 0;
  }
  const std::string& c = line.Command;
  Check(c == "run" || c == "slope" || c == "temperature" || c == "illumination" || c == "bench" ||
    c == "info" || c == "fractal");
  Check(line.Backend == "auto" || line.Backend == "cpu" || line.Backend == "gpu");
  const auto& t = line.Temperature;
  Check(Within(t.Coldest, -90, 60) && Within(t.Warmest, -90, 60) && t.Coldest <= t.Warmest);
  Check(Within(t.LapseRate, 0, 20));
  Check(t.ColdestMonth >= 0 && t.ColdestMonth <= 12 && t.WarmestMonth >= 0 && t.WarmestMonth <= 12);
  Check(t.Monthly.empty() || t.Monthly.size() == 12);
  for (double m : t.Monthly)
  {
    Check(Within(m, -90, 60));
  }
  Check(t.Monthly.empty() || t.ClimateFile.empty());
  if (c == "slope" || c == "temperature" || c == "illumination" || c == "info")
  {
    Check(!line.Input.empty());
  }
  if (c == "slope" || c == "temperature" || c == "illumination" || c == "fractal")
  {
    Check(EndsWithRasterExtension(line.Output));
  }
  const auto& s = line.Illumination;
  // Latitude and longitude: NaN (from the georeference) or in range (run and illumination).
  Check(std::isnan(s.Latitude) || Within(s.Latitude, -90, 90));
  Check(std::isnan(s.Longitude) || Within(s.Longitude, -180, 180));
  if (c == "illumination")
  {
    Check(s.Mode == "instant" || s.Mode == "daily" || s.Mode == "monthly");
    Check(terroir::terrain::IsValidDate(s.Year, s.Month, s.Day));
    Check(Within(s.Time, 0, 24) && Within(s.UTCOffset, -14, 14));
    Check(s.MonthlyDay >= 1 && s.MonthlyDay <= 31);
    Check(Within(s.TimeStep, 1, 1440));
    Check(std::isnan(s.Orientation) || Within(s.Orientation, -360, 360));
    Check(s.Method == "horizon" || s.Method == "raymarch");
    Check(s.Sectors >= 4 && s.Sectors <= 1024);
    Check(Within(s.Transmittance, 0.01, 1));
    Check(Within(s.SunAzimuth, 0, 360) && Within(s.SunElevation, -90, 90));
    const bool instant = s.Mode == "instant";
    Check(!instant || s.UseSun || s.HasTime);
    Check(instant || (!s.UseSun && !s.HasTime && s.IncidenceOutput.empty()));
    Check(!instant || s.InsolationOutput.empty());
    for (const std::string* extra : { &s.InsolationOutput, &s.IncidenceOutput })
    {
      Check(extra->empty() || (EndsWithRasterExtension(*extra) && *extra != line.Output));
    }
  }
  if (c == "slope")
  {
    Check(Within(line.ZFactor, 1e-9, 1e9));
    Check(line.AspectOutput.empty() || EndsWithRasterExtension(line.AspectOutput));
  }
  if (c == "bench")
  {
    Check(line.BenchSize >= 16 && line.BenchSize <= 32768);
    Check(line.BenchRepeat >= 1 && line.BenchRepeat <= 100);
    Check(!line.BenchBackends.empty());
    const auto& known = terroir::app::BenchStageNames();
    Check(!line.BenchStages.empty() && line.BenchStages.size() <= known.size());
    for (const auto& stage : line.BenchStages)
    {
      Check(std::find(known.begin(), known.end(), stage) != known.end());
    }
  }
  if (c == "fractal")
  {
    Check(line.FractalSize >= 2 && line.FractalSize <= 65536);
    Check(Within(line.FractalSpacing, 1e-3, 1e5));
  }
  return 0;
}

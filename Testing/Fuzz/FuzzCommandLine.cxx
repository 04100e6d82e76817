// libFuzzer harness: the `terroir` command-line parser (terroir::app::ParseCommandLine) on
// arbitrary argument lists. The input is split at NUL bytes into at most 32 arguments after
// argv[0]. Aborts (__builtin_trap) when an invariant breaks:
// - the parser either accepts (one of the 15 commands, every number finite and inside its
//   documented range, 12 or no monthly values, a date that exists, options that fit the
//   illumination mode, output names with a known extension and no extra output named like OUT,
//   seeds or --fill-depressions but not both, at most one source of water), or prints
//   help (exit status 0, text, no error), or refuses with exit status 2 and one line of error;
// - it never exits, throws or prints by itself (a throw or exit would end the fuzzer).
#include "FuzzCheck.h"
#include "TerroirCommandLine.h"
#include "TerroirViewerScript.h"

#include "SolarPosition.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

namespace
{
using terroir_fuzz::Check;

/// `name` is longer than `ext` and ends in it, case-insensitively.
bool EndsWith(const std::string& name, const std::string& ext)
{
  if (name.size() <= ext.size())
  {
    return false;
  }
  for (std::size_t k = 0; k < ext.size(); ++k)
  {
    const auto a = static_cast<unsigned char>(name[name.size() - ext.size() + k]);
    if (std::tolower(a) != std::tolower(static_cast<unsigned char>(ext[k])))
    {
      return false;
    }
  }
  return true;
}

bool EndsWithRasterExtension(const std::string& name)
{
  return EndsWith(name, ".tif") || EndsWith(name, ".tiff") || EndsWith(name, ".vti");
}

bool Within(double v, double lo, double hi)
{
  return std::isfinite(v) && v >= lo && v <= hi;
}

/// An extra output: none, or a name other than OUT (and a raster's extension when `raster`).
bool ExtraOutput(const std::string& name, const std::string& out, bool raster = true)
{
  return name.empty() || ((!raster || EndsWithRasterExtension(name)) && name != out);
}

bool AllWithin(const std::vector<double>& values, double lo, double hi)
{
  return std::all_of(values.begin(), values.end(), [&](double v) { return Within(v, lo, hi); });
}

void CheckSoilWater(const terroir::app::CommandLine& line)
{
  const auto& s = line.SoilWater;
  Check(s.Precipitation.empty() ||
    (s.Precipitation.size() == 12 && AllWithin(s.Precipitation, 0, 1e4)));
  Check(s.Intensity.empty() || (s.Intensity.size() == 12 && AllWithin(s.Intensity, 0, 500)));
  Check((s.Precipitation.empty() && s.Intensity.empty()) || s.ClimateFile.empty());
  for (std::size_t k = 0; k < s.Precipitation.size() && k < s.Intensity.size(); ++k)
  {
    Check(s.Precipitation[k] == 0.0 || s.Intensity[k] > 0.0);
  }
  Check(s.InfiltrationInput.empty() || s.Operations.empty());
  for (const auto& op : s.Operations)
  {
    if (op.Kind == "fill" || op.Kind == "paint-raster" || op.Kind == "paint-polygons")
    {
      Check(Within(op.Value, 0, 1000));
    }
    else if (op.Kind == "slope-rule")
    {
      Check(Within(op.Value, 0, 90));
    }
    else
    {
      Check(op.Kind == "soil-raster" || op.Kind == "soil-polygons");
    }
    Check((op.Kind == "fill" || op.Kind == "slope-rule") == op.File.empty());
    Check((op.Kind == "soil-polygons") == !op.Attribute.empty());
  }
  if (line.Command == "humidity")
  {
    Check(ExtraOutput(s.WeightedOutput, line.Output) && ExtraOutput(s.StandingOutput, line.Output));
    Check(s.WeightedOutput.empty() || s.WeightedOutput != s.StandingOutput);
  }
}

void CheckFloodFill(const terroir::app::CommandLine& line)
{
  const auto& f = line.FloodFill;
  Check(f.FillDepressions == f.Seeds.empty());
  for (const auto& seed : f.Seeds)
  {
    Check(std::isfinite(seed.X) && std::isfinite(seed.Y));
    Check(std::isnan(seed.Level) || std::isfinite(seed.Level));
    Check(!seed.Cell ||
      (Within(seed.X, 0, 2147483647.0) && Within(seed.Y, 0, 2147483647.0) &&
        seed.X == std::floor(seed.X) && seed.Y == std::floor(seed.Y)));
  }
  Check(std::isnan(f.Level) || Within(f.Level, -20000, 20000));
  Check(!f.FillDepressions || std::isnan(f.Level));
  Check(Within(f.MinimumArea, 0, 1e15));
  Check(ExtraOutput(f.IdsOutput, line.Output));
}

void CheckWaterFlow(const terroir::app::CommandLine& line)
{
  const auto& w = line.WaterFlow;
  Check(Within(w.InitialWater, 0, 1e6));
  Check(w.Month >= 0 && w.Month <= 12);
  Check(!(w.Month > 0 && w.Annual));
  Check(w.MaximumIterations >= 0 && w.MaximumIterations <= 100000000LL);
  Check(Within(w.AutoStop, 0, 0.999) && Within(w.Time, 0, 1e12));
  Check(Within(w.IterationDuration, 1e-6, 1e9));
  Check(std::isnan(w.RiverThreshold) || Within(w.RiverThreshold, 0, 1e18));
  if (line.Command == "waterflow")
  {
    Check(ExtraOutput(w.DischargeOutput, line.Output) && ExtraOutput(w.RiverOutput, line.Output));
  }
  for (const std::string& peer : line.Validate.Peers)
  {
    const std::size_t eq = peer.find('=');
    Check(eq != std::string::npos && eq > 0 && eq + 1 < peer.size());
  }
}

void CheckKMeans(const terroir::app::CommandLine& line)
{
  const auto& k = line.KMeans;
  Check(k.Clusters >= 1 && k.Clusters <= 64);
  Check(k.FeatureNames.size() == k.FeatureWeights.size());
  for (std::size_t i = 0; i < k.FeatureNames.size(); ++i)
  {
    Check(!k.FeatureNames[i].empty() &&
      Within(k.FeatureWeights[i], 0, std::numeric_limits<double>::max()));
    Check(std::count(k.FeatureNames.begin(), k.FeatureNames.end(), k.FeatureNames[i]) == 1);
  }
  Check(k.Seeding == "diagonal" || k.Seeding == "kmeans++");
  Check(k.Seed >= 0 && k.MaximumIterations >= 1 && Within(k.Tolerance, 0, 1e9));
  for (const std::string* extra : { &k.Csv, &k.Json, &k.Png })
  {
    Check(ExtraOutput(*extra, line.Output, false));
  }
  Check(k.Csv.empty() || EndsWith(k.Csv, ".csv"));
  Check(k.Json.empty() || EndsWith(k.Json, ".json"));
  Check(k.Png.empty() || EndsWith(k.Png, ".png"));
}

void CheckView(const terroir::app::ViewSettings& v)
{
  Check(v.Width >= 320 && v.Width <= 7680 && v.Height >= 240 && v.Height <= 4320);
  // One of the overlays' names (the registry, TerroirViewerScript.h).
  Check(std::any_of(std::begin(terroir::viewer::kViewerOverlays),
    std::end(terroir::viewer::kViewerOverlays),
    [&](const terroir::viewer::ViewerOverlayInfo& o) { return v.Overlay == o.Name; }));
  Check(v.Style == "terrain" || v.Style == "first-person");
  Check(Within(v.Sensitivity, 0.01, 100) && Within(v.MoveSpeed, 0.01, 100));
  Check(v.Month >= 1 && v.Month <= 12 && Within(v.Hour, 0, 24));
  Check(std::isnan(v.Orientation) || Within(v.Orientation, -360, 360));
  Check(v.Clusters >= 1 && v.Clusters <= 64 && Within(v.LakeDepth, 0, 10000));
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
  // The commands the program knows (the registry's names: TerroirCommandLine's table).
  const auto& commands = terroir::app::CommandDescriptions();
  Check(std::any_of(commands.begin(),
    commands.end(),
    [&](const terroir::app::CommandDescription& d) { return c == d.Name; }));
  Check(line.Backend == "auto" || line.Backend == "cpu" || line.Backend == "gpu");
  Check(line.ZUnit == "auto" || line.ZUnit == "m" || line.ZUnit == "ft" || line.ZUnit == "us-ft");
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
  const bool rasterIn =
    c != "run" && c != "bench" && c != "fractal" && c != "view" && c != "generate";
  if (rasterIn && c != "validate")
  {
    Check(!line.Input.empty());
  }
  if (rasterIn && c != "info" && c != "validate" && c != "morphometry" && c != "plants")
  {
    Check(EndsWithRasterExtension(line.Output));
  }
  if (c == "morphometry")
  {
    Check(line.Output.empty() || EndsWithRasterExtension(line.Output));
  }
  if (c == "erosion")
  {
    const auto& e = line.Erosion;
    Check(e.Steps >= 0 && e.ThermalInterval >= 0);
    Check(Within(e.TimeStep, 1e-6, 100.0) && Within(e.InitialWater, 0.0, 1000.0));
    Check(Within(e.RainRate, 0.0, 1e7) && Within(e.TalusAngle, 0.01, 89.99));
    Check(Within(e.CapacityDepth, 0.0, 1000.0));
    Check(e.Vegetation == -1.0 || Within(e.Vegetation, 0.0, 1.0));
    Check(e.SeaLevel.empty() || Within(std::stod(e.SeaLevel), -1e5, 1e5));
    Check(Within(e.WindDirection, -360.0, 360.0) && Within(e.WindStrength, 0.0, 1000.0));
    Check(Within(e.EvaporationScale, 0.0, 1e9));
  }
  if (c == "plants")
  {
    const auto& p = line.Plants;
    Check(EndsWith(line.Output, ".vtp") || EndsWith(line.Output, ".csv"));
    Check(p.Exemplar.empty() || EndsWith(p.Exemplar, ".csv") || EndsWith(p.Exemplar, ".vtp"));
    Check(p.Exemplar != line.Output);
    Check(p.Window.empty() ||
      (p.Window.size() == 4 && !p.Exemplar.empty() && p.Window[0] < p.Window[1] &&
        p.Window[2] < p.Window[3]));
    Check(Within(p.Density, 0.0, 100.0) && Within(p.MinimumDistance, 0.0, 1e6));
    Check(Within(p.MaximumDistance, 0.0, 1e6) && p.Bins >= 1 && p.Bins <= 4096);
    Check(p.Iterations >= 0);
  }
  if (c == "fractal" || c == "generate")
  {
    Check(EndsWithRasterExtension(line.Output));
  }
  if (c == "generate")
  {
    const auto& g = line.Generate;
    Check(g.Kind == "island" || g.Kind == "riverland" || g.Kind == "features");
    Check(g.RiverLand.Threads >= 1 && g.RiverLand.Threads <= 1024);
    const auto& f = g.Features;
    Check((g.Kind == "features") == !f.Curves.empty());
    Check(f.Curves.empty() || EndsWith(f.Curves, ".geojson") || EndsWith(f.Curves, ".json") ||
      EndsWith(f.Curves, ".vtp"));
    Check(f.SaveCurves.empty() || (EndsWith(f.SaveCurves, ".vtp") && f.SaveCurves != line.Output));
    Check(g.Kind == "features" || (f.SaveCurves.empty() && f.Base.empty()));
    Check(Within(f.Tolerance, 1e-9, 1e3) && f.MaximumCycles >= 1 && f.MaximumCycles <= 100000);
    Check(Within(f.BaseElevation, -1e5, 1e5));
    Check(g.Width >= 8 && g.Width <= 65536 && g.Height >= 8 && g.Height <= 65536);
    Check(g.Regions >= 16 && g.Relaxations >= 0 && g.Relaxations <= 100 && g.Rivers >= 0);
    Check(Within(g.Spacing, 1e-3, 1e5) && Within(g.MaximumHeight, 1e-3, 1e5));
    Check(Within(g.MaximumDepth, 0, 1e5) && Within(g.NoiseScale, 0, 100));
    Check(Within(g.Perturbation, 0, 1) && g.Origin.size() == 2);
    Check(ExtraOutput(g.BiomeOutput, line.Output) && ExtraOutput(g.RiverOutput, line.Output));
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
  if (c == "infiltration" || c == "humidity" || c == "run")
  {
    CheckSoilWater(line);
  }
  if (c == "floodfill")
  {
    CheckFloodFill(line);
  }
  if (c == "waterflow" || c == "validate")
  {
    CheckWaterFlow(line);
  }
  if (c == "flowacc")
  {
    Check(Within(line.FlowRiverThreshold, 0, 1e18));
  }
  if (c == "kmeans")
  {
    CheckKMeans(line);
  }
  if (c == "view")
  {
    CheckView(line.View);
    Check(line.View.Curves.empty() || EndsWith(line.View.Curves, ".geojson") ||
      EndsWith(line.View.Curves, ".json") || EndsWith(line.View.Curves, ".vtp"));
  }
  if (c == "fractal")
  {
    Check(line.FractalSize >= 2 && line.FractalSize <= 65536);
    Check(Within(line.FractalSpacing, 1e-3, 1e5));
  }
  return 0;
}

// The options of `terroir generate` (TerroirCommandOptions.h); its code is Generate.cxx.
#include "TerroirCommandOptions.h"

#include <nlohmann/json.hpp>

#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>

namespace terroir
{
namespace app
{
void CheckRiverLandOptions(CommandLine& line, const CLI::App& sub); // GenerateRiverLandOptions.cxx
// GenerateFeaturesOptions.cxx
void AddGenerateFeaturesOptions(CLI::App* sub, CommandLine& line);
void CheckGenerateFeaturesOptions(CommandLine& line);

namespace
{
class GenerateOptions : public CommandOptions
{
public:
  void Add(CLI::App* sub, CommandLine& line) override
  {
    auto& g = line.Generate;
    sub
      ->add_option("KIND",
        g.Kind,
        "What to generate: island (Weiss 2015), riverland (Jensen 2011), features (Weiss's curves)")
      ->required()
      ->check(CLI::IsMember({ "island", "riverland", "features" }));
    sub->add_option("OUT", line.Output, "Output .tif (Elevation) or .vti (every array)")
      ->required()
      ->check(EndsWith(RasterOutputs()));
    sub->add_option("--params", g.ParamsFile, "JSON file of parameters (the options override it)");
    sub->add_option("--seed", g.Seed, "Random seed")->capture_default_str();
    sub->add_option("--width", g.Width, "Columns")
      ->check(CLI::Range(8, 65536))
      ->capture_default_str();
    sub->add_option("--height", g.Height, "Rows")
      ->check(CLI::Range(8, 65536))
      ->capture_default_str();
    sub->add_option("--spacing", g.Spacing, "Cell size, metres")
      ->check(FiniteIn(1e-3, 1e5))
      ->capture_default_str();
    sub->add_option("--regions", g.Regions, "Voronoi points")
      ->check(CLI::Range(16, 100000000))
      ->capture_default_str();
    sub->add_option("--relaxations", g.Relaxations, "Lloyd relaxation steps")
      ->check(CLI::Range(0, 100))
      ->capture_default_str();
    sub
      ->add_option("--rivers",
        g.Rivers,
        "River springs (0: regions / 20); riverland: river mouths (0: 12 or --params)")
      ->check(CLI::Range(0, 100000000))
      ->capture_default_str();
    sub->add_option("--max-height", g.MaximumHeight, "Height of the highest cell, m")
      ->check(FiniteIn(1e-3, 1e5))
      ->capture_default_str();
    sub->add_option("--max-depth", g.MaximumDepth, "Depth of the deepest sea cell, m")
      ->check(FiniteIn(0.0, 1e5))
      ->capture_default_str();
    sub->add_option("--noise-scale", g.NoiseScale, "Weight of the multifractal noise (eq. 4)")
      ->check(FiniteIn(0.0, 100.0))
      ->capture_default_str();
    sub->add_option("--perturbation", g.Perturbation, "Noise displacement, map-width units")
      ->check(FiniteIn(0.0, 1.0))
      ->capture_default_str();
    sub->add_option("--biome", g.BiomeOutput, "Also write the Biome codes (.tif or .vti)")
      ->check(EndsWith(RasterOutputs()));
    sub->add_option("--river-map", g.RiverOutput, "Also write the generated rivers (.tif or .vti)")
      ->check(EndsWith(RasterOutputs()));
    sub
      ->add_option("--river-lines",
        g.RiverLines,
        "Also write the generated rivers as GeoJSON lines (for terroir validate --reference)")
      ->check(EndsWith({ ".geojson", ".json" }));
    sub->add_option("--crs",
      g.CRS,
      "Place the island in this projected CRS (EPSG:NNNN or WKT), so it is georeferenced");
    sub
      ->add_option("--origin", g.Origin, "With --crs: world X,Y of the first cell (500000,4000000)")
      ->delimiter(',')
      ->expected(2);
    sub->add_option("--threads", g.RiverLand.Threads, "riverland: threads (same output on any)")
      ->check(CLI::Range(1, 1024))
      ->capture_default_str();
    sub->add_flag("--overwrite", line.Overwrite, "Replace existing output files");
    AddGenerateFeaturesOptions(sub, line);
  }

  /// The --params file's values for the options not given on the command line. Keys: seed,
  /// width, height, spacing, regions, relaxations, rivers, max_height, max_depth, noise_scale,
  /// perturbation (unknown keys are an error, so that a typo is not silently ignored).
  void Check(CommandLine& line, const CLI::App& sub) override
  {
    auto& g = line.Generate;
    CheckNotOutput({ &g.BiomeOutput, &g.RiverOutput, &g.RiverLines }, line.Output);
    CheckGenerateFeaturesOptions(line);
    if (!g.BiomeOutput.empty() && g.BiomeOutput == g.RiverOutput)
    {
      throw std::invalid_argument("'" + g.BiomeOutput + "' is both --biome and --river-map");
    }
    if (g.Kind == "riverland")
    {
      CheckRiverLandOptions(line, sub); // its own keys (GenerateRiverLandOptions.cxx)
      return;
    }
    if (g.ParamsFile.empty())
    {
      return;
    }
    std::ifstream in(g.ParamsFile);
    if (!in)
    {
      throw std::invalid_argument(g.ParamsFile + ": cannot be read");
    }
    nlohmann::json j;
    try
    {
      in >> j;
    }
    catch (const std::exception& e)
    {
      throw std::invalid_argument(g.ParamsFile + ": not JSON (" + std::string(e.what()) + ")");
    }
    if (!j.is_object())
    {
      throw std::invalid_argument(g.ParamsFile + ": expected a JSON object of parameters");
    }
    auto given = [&sub](const char* option) { return sub.get_option(option)->count() > 0; };
    for (auto it = j.begin(); it != j.end(); ++it)
    {
      const std::string& key = it.key();
      const char* option = key == "seed" ? "--seed"
        : key == "width"                 ? "--width"
        : key == "height"                ? "--height"
        : key == "spacing"               ? "--spacing"
        : key == "regions"               ? "--regions"
        : key == "relaxations"           ? "--relaxations"
        : key == "rivers"                ? "--rivers"
        : key == "max_height"            ? "--max-height"
        : key == "max_depth"             ? "--max-depth"
        : key == "noise_scale"           ? "--noise-scale"
        : key == "perturbation"          ? "--perturbation"
                                         : nullptr;
      if (!option)
      {
        throw std::invalid_argument(g.ParamsFile + ": unknown parameter '" + key + "'");
      }
      if (!it->is_number())
      {
        throw std::invalid_argument(g.ParamsFile + ": '" + key + "' is not a number");
      }
      if (given(option))
      {
        continue; // the command line wins
      }
      const double v = it->get<double>();
      auto whole = [&](double lo, double hi)
      {
        if (v != static_cast<double>(static_cast<long long>(v)) || v < lo || v > hi)
        {
          throw std::invalid_argument(g.ParamsFile + ": '" + key + "' must be a whole number in [" +
            std::to_string(static_cast<long long>(lo)) + ", " +
            std::to_string(static_cast<long long>(hi)) + "]");
        }
        return static_cast<long long>(v);
      };
      auto real = [&](double lo, double hi)
      {
        if (!(v >= lo && v <= hi))
        {
          throw std::invalid_argument(g.ParamsFile + ": '" + key + "' is outside [" +
            std::to_string(lo) + ", " + std::to_string(hi) + "]");
        }
        return v;
      };
      if (key == "seed")
        g.Seed = whole(-9.0e15, 9.0e15);
      else if (key == "width")
        g.Width = static_cast<int>(whole(8, 65536));
      else if (key == "height")
        g.Height = static_cast<int>(whole(8, 65536));
      else if (key == "spacing")
        g.Spacing = real(1e-3, 1e5);
      else if (key == "regions")
        g.Regions = static_cast<int>(whole(16, 1e8));
      else if (key == "relaxations")
        g.Relaxations = static_cast<int>(whole(0, 100));
      else if (key == "rivers")
        g.Rivers = static_cast<int>(whole(0, 1e8));
      else if (key == "max_height")
        g.MaximumHeight = real(1e-3, 1e5);
      else if (key == "max_depth")
        g.MaximumDepth = real(0.0, 1e5);
      else if (key == "noise_scale")
        g.NoiseScale = real(0.0, 100.0);
      else
        g.Perturbation = real(0.0, 1.0);
    }
  }
};
} // namespace

std::unique_ptr<CommandOptions> MakeGenerateOptions()
{
  return std::unique_ptr<CommandOptions>(new GenerateOptions);
}

} // namespace app
} // namespace terroir

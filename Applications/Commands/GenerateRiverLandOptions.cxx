// `terroir generate riverland`'s --params check, called from GenerateOptions.cxx's Check (the
// command is GenerateRiverLand.cxx). Plain C++: the parser library links RiverLand's core.
#include "TerroirCommandOptions.h"

#include "RiverLand.h"

#include <nlohmann/json.hpp>

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace terroir
{
namespace app
{

/// `generate riverland`'s checks: the island-only options are refused; the --params file
/// (RiverLand's JSON keys, RiverLand.h / vtkTerroirRiverLandSource.md) is read and validated
/// now, before any output; seed, width, height, spacing and rivers given on the command line
/// win over the file's (their keys are dropped from the text kept for the source), and the
/// file's values of those five fill the settings otherwise.
void CheckRiverLandOptions(CommandLine& line, const CLI::App& sub)
{
  auto& g = line.Generate;
  auto given = [&sub](const char* option) { return sub.get_option(option)->count() > 0; };
  for (const char* option : { "--regions",
         "--relaxations",
         "--max-height",
         "--max-depth",
         "--noise-scale",
         "--perturbation",
         "--biome" })
  {
    if (given(option))
    {
      throw std::invalid_argument(std::string(option) +
        " is an island option; riverland takes "
        "its other parameters from --params");
    }
  }
  nlohmann::json j = nlohmann::json::object();
  if (!g.ParamsFile.empty())
  {
    std::ifstream in(g.ParamsFile);
    if (!in)
    {
      throw std::invalid_argument(g.ParamsFile + ": cannot be read");
    }
    std::stringstream text;
    text << in.rdbuf();
    try
    {
      j = nlohmann::json::parse(text.str());
    }
    catch (const std::exception& e)
    {
      throw std::invalid_argument(g.ParamsFile + ": not JSON (" + std::string(e.what()) + ")");
    }
    if (!j.is_object())
    {
      throw std::invalid_argument(g.ParamsFile + ": expected a JSON object of parameters");
    }
  }
  const struct
  {
    const char* Key;
    const char* Option;
  } shared[] = { { "seed", "--seed" },
    { "width", "--width" },
    { "height", "--height" },
    { "spacing", "--spacing" },
    { "rivers", "--rivers" } };
  for (const auto& s : shared)
  {
    if (given(s.Option))
    {
      j.erase(s.Key);
    }
  }
  // The whole parameter set as the source will see it: the options, then the file's keys.
  terroir::generation::RiverLandParameters p;
  p.seed = static_cast<std::uint64_t>(g.Seed);
  p.width = g.Width;
  p.height = g.Height;
  p.spacing = g.Spacing;
  if (g.Rivers > 0)
  {
    p.rivers = g.Rivers;
  }
  p.threads = g.RiverLand.Threads;
  std::string error;
  if (!terroir::generation::RiverLandParametersFromJson(j.dump(), p, error))
  {
    throw std::invalid_argument(
      (g.ParamsFile.empty() ? std::string("riverland") : g.ParamsFile) + ": " + error);
  }
  g.Seed = static_cast<long long>(p.seed);
  g.Width = p.width;
  g.Height = p.height;
  g.Spacing = p.spacing;
  g.Rivers = p.rivers;
  g.RiverLand.Params = j.dump();
}

} // namespace app
} // namespace terroir

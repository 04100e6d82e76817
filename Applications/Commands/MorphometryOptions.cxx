// The options of `terroir morphometry` (TerroirCommandOptions.h); its code is Morphometry.cxx.
#include "TerroirCommandOptions.h"

#include <memory>
#include <stdexcept>
#include <string>

namespace terroir
{
namespace app
{
namespace
{
class MorphometryOptions : public CommandOptions
{
public:
  void Add(CLI::App* sub, CommandLine& line) override
  {
    sub->add_option("IN", line.Input, "Input DEM")->required();
    sub
      ->add_option("OUT",
        line.MorphometryOutput,
        "Optional output .tif (StrahlerOrder band) or .vti (StrahlerOrder, DepressionDepth, "
        "FlowLength and the statistics as field data)")
      ->check(EndsWith(RasterOutputs()));
    sub
      ->add_option("--channel-area",
        line.MorphometryChannelArea,
        "D8 contributing area of a channel cell, m2 (one default for every DEM: 0.1 km2)")
      ->check(FiniteIn(1e-6, 1e15))
      ->capture_default_str();
    sub
      ->add_option("--depression-depth",
        line.MorphometryDepressionDepth,
        "Filled minus original elevation above which a cell is in a closed depression, m")
      ->check(FiniteIn(0.0, 1e6))
      ->capture_default_str();
    sub->add_option("--json", line.MorphometryJson, "Also write every statistic as JSON here")
      ->check(EndsWith({ ".json" }));
    sub
      ->add_option(
        "--csv", line.MorphometryCsv, "Also write the Horton table (one row per order) as CSV here")
      ->check(EndsWith({ ".csv" }));
    AddCommonOptions(sub, line);
  }
  void Check(CommandLine& line, const CLI::App&) override
  {
    CheckInputGiven(line);
    CheckNotOutput({ &line.MorphometryJson, &line.MorphometryCsv }, line.MorphometryOutput);
    if (!line.MorphometryJson.empty() && line.MorphometryJson == line.MorphometryCsv)
    {
      throw std::invalid_argument("'" + line.MorphometryJson + "' is both --json and --csv");
    }
  }
};
} // namespace

std::unique_ptr<CommandOptions> MakeMorphometryOptions()
{
  return std::unique_ptr<CommandOptions>(new MorphometryOptions);
}

} // namespace app
} // namespace terroir

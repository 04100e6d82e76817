// The options of `terroir validate` (TerroirCommandOptions.h); its code is Validate.cxx.
#include "TerroirCommandOptions.h"

#include <algorithm>
#include <cctype>
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
class ValidateOptions : public CommandOptions
{
public:
  void Add(CLI::App* sub, CommandLine& line) override
  {
    sub->add_option("DEM", line.Input, "Input DEM (default: the bundled Sagehen DEM)");
    sub->add_option("--reference",
      line.Validate.Reference,
      "Reference river lines, any OGR format (default with the bundled DEM: its NHD flowlines)");
    sub->add_option("--mask",
      line.Validate.Mask,
      "Area to score: a raster on the DEM grid (non-zero inside) or polygons (default with the "
      "bundled DEM: its watershed)");
    sub->add_option("--peer", line.Validate.Peers, "NAME=RASTER: also score a peer's accumulation")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
    sub->add_option("--json", line.Validate.Json, "Also write the scores as JSON here");
    sub->add_option("--png", line.Validate.Png, "Also write the overlay picture here");
    sub->add_option("--sweep",
      line.Validate.Sweep,
      "NAME=V1,V2,...: one simulation row per value of a water-flow option (e.g. rain=0.1,1,10)");
    AddWaterFlowOptions(sub, line.WaterFlow);
    AddCommonOptions(sub, line);
  }
  void Check(CommandLine& line, const CLI::App& sub) override
  {
    CheckWaterFlow(line.WaterFlow, sub);
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
};
} // namespace

std::unique_ptr<CommandOptions> MakeValidateOptions()
{
  return std::unique_ptr<CommandOptions>(new ValidateOptions);
}

} // namespace app
} // namespace terroir

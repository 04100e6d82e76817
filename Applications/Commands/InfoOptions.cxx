// The options of `terroir info` (TerroirCommandOptions.h); its code is Info.cxx.
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
class InfoOptions : public CommandOptions
{
public:
  void Add(CLI::App* sub, CommandLine& line) override
  {
    sub->add_option("IN", line.Input, "Input DEM")->required();
    sub->add_flag(
      "--allow-network-paths", line.AllowNetwork, "Allow GDAL network and archive paths");
    AddZUnitOption(sub, line);
  }
  void Check(CommandLine& line, const CLI::App&) override { CheckInputGiven(line); }
};
} // namespace

std::unique_ptr<CommandOptions> MakeInfoOptions()
{
  return std::unique_ptr<CommandOptions>(new InfoOptions);
}

} // namespace app
} // namespace terroir

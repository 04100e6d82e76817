// The options of `terroir floodfill` (TerroirCommandOptions.h); its code is FloodFill.cxx.
#include "TerroirCommandOptions.h"

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
class FloodFillOptions : public CommandOptions
{
public:
  void Add(CLI::App* sub, CommandLine& line) override
  {
    sub->add_option("IN", line.Input, "Input DEM")->required();
    sub->add_option("OUT", line.Output, "Output .tif (WaterDepth, m; 0 dry) or .vti (all arrays)")
      ->required()
      ->check(EndsWith(RasterOutputs()));
    AddFloodFillOptions(sub, line.FloodFill, this->Seeds, this->Cells);
    sub->add_option("--ids", line.FloodFill.IdsOutput, "Also write WaterBody ids (0 dry) here")
      ->check(EndsWith(RasterOutputs()));
    AddCommonOptions(sub, line);
  }
  void Check(CommandLine& line, const CLI::App& sub) override
  {
    CheckFloodFill(line.FloodFill, this->Seeds, this->Cells, sub);
    if (line.FloodFill.IdsOutput == line.Output)
    {
      throw std::invalid_argument("--ids: '" + line.Output + "' is also OUT");
    }
    CheckInputGiven(line);
  }

private:
  std::vector<std::string> Seeds, Cells;
};
} // namespace

std::unique_ptr<CommandOptions> MakeFloodFillOptions()
{
  return std::unique_ptr<CommandOptions>(new FloodFillOptions);
}

} // namespace app
} // namespace terroir

// The options of `terroir waterflow` (TerroirCommandOptions.h); its code is WaterFlow.cxx.
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
class WaterFlowOptions : public CommandOptions
{
public:
  void Add(CLI::App* sub, CommandLine& line) override
  {
    sub->add_option("IN", line.Input, "Input DEM")->required();
    sub->add_option("OUT", line.Output, "Output .tif (WaterHeight, m) or .vti (all arrays)")
      ->required()
      ->check(EndsWith(RasterOutputs()));
    AddWaterFlowOptions(sub, line.WaterFlow);
    sub->add_option("--discharge", line.WaterFlow.DischargeOutput, "Also write Discharge (m3)")
      ->check(EndsWith(RasterOutputs()));
    sub->add_option("--river", line.WaterFlow.RiverOutput, "Also write the River mask")
      ->check(EndsWith(RasterOutputs()));
    AddCommonOptions(sub, line);
  }
  void Check(CommandLine& line, const CLI::App& sub) override
  {
    CheckWaterFlow(line.WaterFlow, sub);
    CheckNotOutput({ &line.WaterFlow.DischargeOutput, &line.WaterFlow.RiverOutput }, line.Output);
  }
};
} // namespace

std::unique_ptr<CommandOptions> MakeWaterFlowOptions()
{
  return std::unique_ptr<CommandOptions>(new WaterFlowOptions);
}

} // namespace app
} // namespace terroir

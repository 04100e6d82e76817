// The options of `terroir slope` (TerroirCommandOptions.h); its code is Slope.cxx.
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
class SlopeOptions : public CommandOptions
{
public:
  void Add(CLI::App* sub, CommandLine& line) override
  {
    sub->add_option("IN", line.Input, "Input DEM")->required();
    sub->add_option("OUT", line.Output, "Output .tif (Slope band) or .vti (all arrays)")
      ->required()
      ->check(EndsWith(RasterOutputs()));
    sub->add_option("-z,--zfactor", line.ZFactor, "Vertical exaggeration of the elevations")
      ->check(FiniteIn(1e-9, 1e9))
      ->capture_default_str();
    sub->add_flag("-p,--percent", line.Percent, "Slope in percent instead of degrees");
    sub
      ->add_option(
        "--aspect", line.AspectOutput, "Also write Aspect (degrees from true north) here")
      ->check(EndsWith(RasterOutputs()));
    AddCommonOptions(sub, line);
  }
  void Check(CommandLine& line, const CLI::App&) override { CheckInputGiven(line); }
};
} // namespace

std::unique_ptr<CommandOptions> MakeSlopeOptions()
{
  return std::unique_ptr<CommandOptions>(new SlopeOptions);
}

} // namespace app
} // namespace terroir

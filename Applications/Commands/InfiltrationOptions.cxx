// The options of `terroir infiltration` (TerroirCommandOptions.h); its code is Infiltration.cxx.
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
class InfiltrationOptions : public CommandOptions
{
public:
  void Add(CLI::App* sub, CommandLine& line) override
  {
    sub->add_option("IN", line.Input, "Input DEM")->required();
    sub->add_option("OUT", line.Output, "Output .tif (InfiltrationRate) or .vti (all arrays)")
      ->required()
      ->check(EndsWith(RasterOutputs()));
    AddInfiltrationOptions(sub, line.SoilWater, this->Text, false);
    AddCommonOptions(sub, line);
  }
  void Check(CommandLine& line, const CLI::App& sub) override
  {
    CheckSoilWater(line.SoilWater, this->Text, sub);
    CheckInputGiven(line);
  }

private:
  SoilWaterText Text;
};
} // namespace

std::unique_ptr<CommandOptions> MakeInfiltrationOptions()
{
  return std::unique_ptr<CommandOptions>(new InfiltrationOptions);
}

} // namespace app
} // namespace terroir

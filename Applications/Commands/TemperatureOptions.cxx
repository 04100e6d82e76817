// The options of `terroir temperature` (TerroirCommandOptions.h); its code is Temperature.cxx.
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
class TemperatureOptions : public CommandOptions
{
public:
  void Add(CLI::App* sub, CommandLine& line) override
  {
    sub->add_option("IN", line.Input, "Input DEM")->required();
    sub->add_option("OUT", line.Output, "Output .tif (12 bands, Jan..Dec) or .vti")
      ->required()
      ->check(EndsWith(RasterOutputs()));
    AddTemperatureOptions(sub, line.Temperature, this->Monthly);
    AddCommonOptions(sub, line);
  }
  void Check(CommandLine& line, const CLI::App&) override
  {
    CheckTemperature(line.Temperature, this->Monthly);
    CheckInputGiven(line);
  }

private:
  std::string Monthly;
};
} // namespace

std::unique_ptr<CommandOptions> MakeTemperatureOptions()
{
  return std::unique_ptr<CommandOptions>(new TemperatureOptions);
}

} // namespace app
} // namespace terroir

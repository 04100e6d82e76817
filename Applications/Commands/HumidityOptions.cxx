// The options of `terroir humidity` (TerroirCommandOptions.h); its code is Humidity.cxx.
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
class HumidityOptions : public CommandOptions
{
public:
  void Add(CLI::App* sub, CommandLine& line) override
  {
    sub->add_option("IN", line.Input, "Input DEM")->required();
    sub
      ->add_option(
        "OUT", line.Output, "Output .tif (SoilHumidity, 12 bands Jan..Dec) or .vti (all arrays)")
      ->required()
      ->check(EndsWith(RasterOutputs()));
    AddClimateOptions(sub, this->Text);
    sub->add_option("--climate",
      line.SoilWater.ClimateFile,
      "Climate table (CSV or JSON) with precipitation_mm and intensity_mm_per_h");
    AddInfiltrationOptions(sub, line.SoilWater, this->Text, true);
    sub
      ->add_option(
        "--weighted", line.SoilWater.WeightedOutput, "Also write WeightedSoilHumidity here")
      ->check(EndsWith(RasterOutputs()));
    sub->add_option("--standing", line.SoilWater.StandingOutput, "Also write StandingWater here")
      ->check(EndsWith(RasterOutputs()));
    AddCommonOptions(sub, line);
  }
  void Check(CommandLine& line, const CLI::App& sub) override
  {
    CheckSoilWater(line.SoilWater, this->Text, sub);
    CheckNotOutput({ &line.SoilWater.WeightedOutput, &line.SoilWater.StandingOutput }, line.Output);
    if (!line.SoilWater.WeightedOutput.empty() &&
      line.SoilWater.WeightedOutput == line.SoilWater.StandingOutput)
    {
      throw std::invalid_argument("--weighted and --standing name the same file");
    }
    CheckInputGiven(line);
  }

private:
  SoilWaterText Text;
};
} // namespace

std::unique_ptr<CommandOptions> MakeHumidityOptions()
{
  return std::unique_ptr<CommandOptions>(new HumidityOptions);
}

} // namespace app
} // namespace terroir

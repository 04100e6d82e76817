// The options of `terroir run` (TerroirCommandOptions.h); its code is Run.cxx.
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
class RunOptions : public CommandOptions
{
public:
  void Add(CLI::App* sub, CommandLine& line) override
  {
    line.Output = "terroir-out";
    sub->add_option("DEM", line.Input, "DEM file (GeoTIFF, .img, USGS .dem, Terragen .ter, ...)");
    sub->add_option("-o,--out", line.Output, "Output folder")->capture_default_str();
    sub->add_flag("--no-png", line.NoPng, "Skip the PNG overlays (they need an X display)");
    AddCommonOptions(sub, line);
    AddTemperatureOptions(sub, line.Temperature, this->Monthly);
    AddClimateOptions(sub, this->SoilText);
    AddLocationOptions(sub, line.Illumination);
    sub->add_option("--clusters", line.KMeans.Clusters, "Ecological zones K (k-means; 0 skips)")
      ->check(CLI::Range(0, 64))
      ->capture_default_str();
  }
  void Check(CommandLine& line, const CLI::App& sub) override
  {
    CheckTemperature(line.Temperature, this->Monthly);
    CheckSoilWater(line.SoilWater, this->SoilText, sub);
    if (line.Output.empty())
    {
      throw std::invalid_argument("--out: the output folder name is empty");
    }
  }

private:
  std::string Monthly;
  SoilWaterText SoilText;
};
} // namespace

std::unique_ptr<CommandOptions> MakeRunOptions()
{
  return std::unique_ptr<CommandOptions>(new RunOptions);
}

} // namespace app
} // namespace terroir

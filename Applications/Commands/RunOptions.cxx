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
    RunOutputSettings& o = line.RunOutputs;
    sub->add_flag("--no-vti", o.NoVti, "Skip terrain.vti (every array in one VTK file)");
    sub
      ->add_option("--outputs,--only",
        o.Only,
        "Write only these files (comma list of file names such as slope.tif, stages such as "
        "rivers, or kinds: vti, tif, png, tables); the reports are always written")
      ->delimiter(',');
    sub->add_option("--vti-compression", o.VtiCompression, "terrain.vti's compressor")
      ->check(CLI::IsMember({ "lz4", "zlib", "none" }))
      ->capture_default_str();
    sub->add_option("--tiff-compression", o.TiffCompression, "GeoTIFF compression (lossless)")
      ->check(CLI::IsMember({ "none", "deflate", "zstd", "lzw" }))
      ->capture_default_str();
    sub->add_option("--tiff-layout", o.TiffLayout, "GeoTIFF blocks: 256 x 256 tiles or strips")
      ->check(CLI::IsMember({ "tiles", "strips" }))
      ->capture_default_str();
    sub->add_option("--tiff-threads", o.TiffThreads, "GDAL compression threads (0: GDAL's default)")
      ->check(CLI::Range(0, 256))
      ->capture_default_str();
    sub->add_flag("--tiff-overviews", o.TiffOverviews, "GeoTIFF internal overviews (2, 4, 8, ...)");
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

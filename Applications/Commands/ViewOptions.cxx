// The options of `terroir view` (TerroirCommandOptions.h); its code is View.cxx.
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
class ViewOptions : public CommandOptions
{
public:
  void Add(CLI::App* sub, CommandLine& line) override
  {
    sub->add_option("DEM", line.Input, "DEM file (default: the bundled Sagehen Creek DEM)");
    sub->add_option("--script", line.View.Script, "Replay the actions of FILE (one per line)");
    sub
      ->add_option("--curves",
        line.View.Curves,
        "Draw the feature curves of FILE (GeoJSON or .vtp, as generate features reads them)")
      ->check(EndsWith({ ".geojson", ".json", ".vtp" }));
    sub->add_option("--size", this->Size, "Window size WxH (default 1024x768)");
    sub
      ->add_option("--overlay",
        line.View.Overlay,
        "First overlay: none, slope, illumination, sun-hours, temperature, humidity, water, "
        "clusters")
      ->check(CLI::IsMember({ "none",
        "slope",
        "illumination",
        "sun-hours",
        "temperature",
        "humidity",
        "water",
        "clusters" }))
      ->capture_default_str();
    sub->add_option("--style", line.View.Style, "Navigation: terrain (drag) or first-person (WASD)")
      ->check(CLI::IsMember({ "terrain", "first-person" }))
      ->capture_default_str();
    sub->add_option("--screenshot-dir",
      line.View.ScreenshotDir,
      "Folder of the screenshot key's PNGs (default: .)");
    sub->add_option("--sensitivity", line.View.Sensitivity, "Mouse sensitivity (pan, rotate, zoom)")
      ->check(FiniteIn(0.01, 100.0))
      ->capture_default_str();
    sub->add_option("--move-speed", line.View.MoveSpeed, "First-person step multiplier")
      ->check(FiniteIn(0.01, 100.0))
      ->capture_default_str();
    AddLocationOptions(sub, line.Illumination);
    sub->add_option("--month", line.View.Month, "Month of the sun, temperature, humidity")
      ->check(CLI::Range(1, 12))
      ->capture_default_str();
    sub->add_option("--hour", line.View.Hour, "Local solar time, hours")
      ->check(FiniteIn(0.0, 24.0))
      ->capture_default_str();
    sub
      ->add_option("--orientation",
        line.View.Orientation,
        "Bearing of grid north from true north, degrees (default: the CRS's, else 0)")
      ->check(FiniteIn(-360.0, 360.0));
    sub->add_option("--clusters", line.View.Clusters, "K of the clusters overlay")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
    sub->add_option("--lake-depth", line.View.LakeDepth, "Lake level above a clicked cell, m")
      ->check(FiniteIn(0.0, 10000.0))
      ->capture_default_str();
    sub->add_option("--climate",
      line.View.ClimateFile,
      "Climate file (CSV or JSON): monthly precipitation, intensity, temperatures");
    sub
      ->add_option("--lod-points",
        line.View.LodPoints,
        "Above this many grid points, draw a coarse surface while interacting (0: never)")
      ->check(CLI::Range(0LL, 1000000000000LL))
      ->capture_default_str();
    sub->add_flag(
      "--allow-network-paths", line.AllowNetwork, "Allow GDAL network and archive paths");
    AddZUnitOption(sub, line);
  }
  void Check(CommandLine& line, const CLI::App&) override
  {
    if (this->Size.empty())
    {
      return;
    }
    const std::string& size = this->Size;
    int w = 0, h = 0;
    char x = 0, tail = 0;
    const bool digits = std::all_of(size.begin(),
      size.end(),
      [](char c) { return c == 'x' || std::isdigit(static_cast<unsigned char>(c)); });
    if (!digits || size.size() > 11 ||
      std::sscanf(size.c_str(), "%d%c%d%c", &w, &x, &h, &tail) != 3 || x != 'x')
    {
      throw std::invalid_argument("--size: '" + size + "' is not WIDTHxHEIGHT (e.g. 1024x768)");
    }
    if (w < 320 || w > 7680 || h < 240 || h > 4320)
    {
      throw std::invalid_argument("--size: " + size + " is outside 320x240 to 7680x4320");
    }
    line.View.Width = w;
    line.View.Height = h;
  }

private:
  std::string Size;
};
} // namespace

std::unique_ptr<CommandOptions> MakeViewOptions()
{
  return std::unique_ptr<CommandOptions>(new ViewOptions);
}

} // namespace app
} // namespace terroir

// The options of `terroir fractal` (TerroirCommandOptions.h); its code is Fractal.cxx.
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
class FractalOptions : public CommandOptions
{
public:
  void Add(CLI::App* sub, CommandLine& line) override
  {
    sub->add_option("OUT", line.Output, "Output .tif or .vti")
      ->required()
      ->check(EndsWith(RasterOutputs()));
    sub->add_option("-s,--size", line.FractalSize, "SIZE x SIZE cells")
      ->check(CLI::Range(2, 65536))
      ->capture_default_str();
    sub->add_option("--seed", line.FractalSeed, "Random seed")->capture_default_str();
    sub->add_option("--spacing", line.FractalSpacing, "Cell size, metres")
      ->check(FiniteIn(1e-3, 1e5))
      ->capture_default_str();
    sub->add_flag("--overwrite", line.Overwrite, "Replace an existing output file");
  }
  void Check(CommandLine&, const CLI::App&) override {}
};
} // namespace

std::unique_ptr<CommandOptions> MakeFractalOptions()
{
  return std::unique_ptr<CommandOptions>(new FractalOptions);
}

} // namespace app
} // namespace terroir

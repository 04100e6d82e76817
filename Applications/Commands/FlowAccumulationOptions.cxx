// The options of `terroir flowacc` (TerroirCommandOptions.h); its code is FlowAccumulation.cxx.
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
class FlowAccumulationOptions : public CommandOptions
{
public:
  void Add(CLI::App* sub, CommandLine& line) override
  {
    sub->add_option("IN", line.Input, "Input DEM")->required();
    sub->add_option("OUT", line.Output, "Output .tif (ContributingArea, m2) or .vti (all arrays)")
      ->required()
      ->check(EndsWith(RasterOutputs()));
    sub
      ->add_option("--river-threshold", line.FlowRiverThreshold, "Contributing area of a river, m2")
      ->check(FiniteIn(0.0, 1e18))
      ->capture_default_str();
    sub
      ->add_option("--method",
        line.FlowMethod,
        "d8 (O'Callaghan & Mark 1984), mfd (Freeman 1991) or dinf (Tarboton 1997)")
      ->check(CLI::IsMember({ "d8", "mfd", "dinf" }))
      ->capture_default_str();
    sub->add_option("--mfd-exponent", line.FlowMFDExponent, "MFD's slope exponent p")
      ->check(FiniteIn(1e-3, 100.0))
      ->capture_default_str();
    AddCommonOptions(sub, line);
  }
  void Check(CommandLine&, const CLI::App&) override {}
};
} // namespace

std::unique_ptr<CommandOptions> MakeFlowAccumulationOptions()
{
  return std::unique_ptr<CommandOptions>(new FlowAccumulationOptions);
}

} // namespace app
} // namespace terroir

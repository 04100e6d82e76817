// The options of `terroir generate features` (Weiss 2015's feature curves), added to those of
// `terroir generate` (GenerateOptions.cxx); its code is GenerateFeatures.cxx.
#include "TerroirCommandOptions.h"

#include <stdexcept>
#include <string>

namespace terroir
{
namespace app
{

void AddGenerateFeaturesOptions(CLI::App* sub, CommandLine& line)
{
  auto& f = line.Generate.Features;
  sub
    ->add_option("--curves",
      f.Curves,
      "features: the feature curves, GeoJSON LineStrings (.geojson, .json) or VTK lines (.vtp)")
    ->check(EndsWith({ ".geojson", ".json", ".vtp" }));
  sub->add_option("--save-curves", f.SaveCurves, "features: also write the curves as .vtp")
    ->check(EndsWith({ ".vtp" }));
  sub->add_option("--base",
    f.Base,
    "features: a base DEM whose grid and heights are kept outside the curves' envelopes");
  sub
    ->add_option("--tolerance",
      f.Tolerance,
      "features: end the solve when a V-cycle changes no height by more, m")
    ->check(FiniteIn(1e-9, 1e3))
    ->capture_default_str();
  sub->add_option("--max-cycles", f.MaximumCycles, "features: multigrid V-cycles at most")
    ->check(CLI::Range(1, 100000))
    ->capture_default_str();
  sub
    ->add_option("--backend",
      line.Backend,
      "features: auto, cpu or gpu (the solver's GPU path gives the CPU's bits; auto means the "
      "CPU until a GPU is recorded as faster, Documentation/Compute.md)")
    ->check(CLI::IsMember({ "auto", "cpu", "gpu" }))
    ->capture_default_str();
  AddZUnitOption(sub, line); // for --base
  sub->add_option("--base-elevation", f.BaseElevation, "features: ground height without --base, m")
    ->check(FiniteIn(-1e5, 1e5))
    ->capture_default_str();
}

void CheckGenerateFeaturesOptions(CommandLine& line)
{
  const auto& g = line.Generate;
  const auto& f = g.Features;
  const bool features = g.Kind == "features";
  if (features && f.Curves.empty())
  {
    throw std::invalid_argument("generate features needs --curves FILE");
  }
  if (!features && (!f.Curves.empty() || !f.SaveCurves.empty() || !f.Base.empty()))
  {
    throw std::invalid_argument("--curves, --save-curves and --base are for generate features");
  }
  CheckNotOutput({ &f.SaveCurves }, line.Output);
}

} // namespace app
} // namespace terroir

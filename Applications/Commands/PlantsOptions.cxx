// The options of `terroir plants` (TerroirCommandOptions.h); its code is Plants.cxx.
#include "TerroirCommandOptions.h"

#include <memory>
#include <stdexcept>
#include <string>

namespace terroir
{
namespace app
{
namespace
{
class PlantsOptions : public CommandOptions
{
public:
  void Add(CLI::App* sub, CommandLine& line) override
  {
    auto& p = line.Plants;
    sub
      ->add_option("IN",
        line.Input,
        "Zones: a .vti with the ClusterId point array (terroir kmeans, terroir run; its "
        "Elevation gives the plants' z), or a raster whose first band is the zone id")
      ->required();
    sub
      ->add_option("OUT",
        line.Output,
        "Output .vtp (one vertex per plant: Species, ClusterId) or .csv (x,y,z,species,"
        "cluster_id)")
      ->required()
      ->check(EndsWith({ ".vtp", ".csv" }));
    sub
      ->add_option("--exemplar",
        p.Exemplar,
        "Exemplar plants to learn from: .csv (x,y[,species][,cluster_id]) or .vtp; without one, "
        "a hard-core pattern at --density and --min-distance")
      ->check(EndsWith({ ".csv", ".vtp" }));
    sub
      ->add_option("--exemplar-window",
        p.Window,
        "The exemplar's window XMIN XMAX YMIN YMAX, m (default: its points' bounds)")
      ->expected(4)
      ->check(FiniteIn(-1e12, 1e12));
    sub->add_option("--density", p.Density, "Without an exemplar: plants per m2")
      ->check(FiniteIn(0.0, 100.0))
      ->capture_default_str();
    sub
      ->add_option(
        "--min-distance", p.MinimumDistance, "Without an exemplar: no two plants closer, m")
      ->check(FiniteIn(0.0, 1e6))
      ->capture_default_str();
    sub
      ->add_option("--max-distance",
        p.MaximumDistance,
        "Largest distance of the pair correlations, m (0: 2 x --min-distance, 10 m with an "
        "exemplar)")
      ->check(FiniteIn(0.0, 1e6))
      ->capture_default_str();
    sub->add_option("--bins", p.Bins, "Distance bins of the pair correlations")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
    sub->add_option("--seed", p.Seed, "Seed of the random numbers")->capture_default_str();
    sub
      ->add_option("--iterations",
        p.Iterations,
        "Perturbations per zone (0: 200 per expected plant, at least 1000)")
      ->check(CLI::Range(0LL, 1000000000000LL))
      ->capture_default_str();
    sub->add_flag("--overwrite", line.Overwrite, "Replace existing output files");
    sub->add_flag("--allow-network-paths",
      line.AllowNetwork,
      "Allow GDAL network and archive paths (/vsicurl/, /vsizip/, ...)");
  }
  void Check(CommandLine& line, const CLI::App&) override
  {
    CheckInputGiven(line);
    const auto& w = line.Plants.Window;
    if (!w.empty() && line.Plants.Exemplar.empty())
    {
      throw std::invalid_argument("--exemplar-window needs --exemplar");
    }
    if (!w.empty() && !(w[0] < w[1] && w[2] < w[3]))
    {
      throw std::invalid_argument("--exemplar-window: XMIN < XMAX and YMIN < YMAX are needed");
    }
    CheckNotOutput({ &line.Plants.Exemplar }, line.Output);
  }
};
} // namespace

std::unique_ptr<CommandOptions> MakePlantsOptions()
{
  return std::unique_ptr<CommandOptions>(new PlantsOptions);
}

} // namespace app
} // namespace terroir

// The options of `terroir kmeans` (TerroirCommandOptions.h); its code is KMeans.cxx.
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
class KMeansOptions : public CommandOptions
{
public:
  void Add(CLI::App* sub, CommandLine& line) override
  {
    sub
      ->add_option("IN", line.Input, "Terrain with resource arrays (.vti of terroir run), or a DEM")
      ->required();
    sub->add_option("OUT", line.Output, "Output .tif (ClusterId) or .vti (all arrays)")
      ->required()
      ->check(EndsWith(RasterOutputs()));
    sub->add_option("-k,--clusters", line.KMeans.Clusters, "Number of clusters K")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
    sub->add_option("--features",
      this->Features,
      "NAME[:WEIGHT],... point arrays to cluster on (default: Slope, Temperature, "
      "IlluminationHours, WeightedSoilHumidity:0.1, those present)");
    sub->add_flag("--standardize", line.KMeans.Standardize, "Cluster z-scores of the features");
    sub->add_option("--seeding", line.KMeans.Seeding, "diagonal (Long (2016)'s) or kmeans++")
      ->check(CLI::IsMember({ "diagonal", "kmeans++" }))
      ->capture_default_str();
    sub->add_option("--seed", line.KMeans.Seed, "Random seed of kmeans++")
      ->check(CLI::Range(0, std::numeric_limits<int>::max()))
      ->capture_default_str();
    sub->add_option("--max-iterations", line.KMeans.MaximumIterations, "Most Lloyd iterations")
      ->check(CLI::Range(1, std::numeric_limits<int>::max()))
      ->capture_default_str();
    sub
      ->add_option(
        "--tolerance", line.KMeans.Tolerance, "Centre shift, relative to the feature variance")
      ->check(FiniteIn(0.0, 1e9))
      ->capture_default_str();
    sub->add_option("--csv", line.KMeans.Csv, "Also write the cluster table as CSV here")
      ->check(EndsWith({ ".csv" }));
    sub->add_option("--json", line.KMeans.Json, "Also write the cluster table as JSON here")
      ->check(EndsWith({ ".json" }));
    sub->add_option("--png", line.KMeans.Png, "Also write the cluster overlay here")
      ->check(EndsWith({ ".png" }));
    AddCommonOptions(sub, line);
  }
  void Check(CommandLine& line, const CLI::App&) override
  {
    ParseFeatures(this->Features, line.KMeans);
    CheckNotOutput({ &line.KMeans.Csv, &line.KMeans.Json, &line.KMeans.Png }, line.Output);
  }

private:
  std::string Features;
};
} // namespace

std::unique_ptr<CommandOptions> MakeKMeansOptions()
{
  return std::unique_ptr<CommandOptions>(new KMeansOptions);
}

} // namespace app
} // namespace terroir

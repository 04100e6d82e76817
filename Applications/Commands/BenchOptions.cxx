// The options of `terroir bench` (TerroirCommandOptions.h); its code is Bench.cxx.
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
class BenchOptions : public CommandOptions
{
public:
  void Add(CLI::App* sub, CommandLine& line) override
  {
    sub->add_option("-s,--size", line.BenchSize, "DEM is SIZE x SIZE cells")
      ->check(CLI::Range(16, 32768))
      ->capture_default_str();
    sub->add_option("-r,--repeat", line.BenchRepeat, "Timed runs per stage (best is reported)")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
    sub->add_option("--backends", this->Backends, "Comma-separated backends")
      ->capture_default_str();
    sub->add_flag("--bandwidth",
      line.BenchBandwidth,
      "Also measure memory bandwidth and the slope, soil-humidity and water-flow kernels' share");
    sub->add_flag("--gpu-breakdown",
      line.BenchGPUBreakdown,
      "Also run each GPU stage once more with GPU profiling and print where its time goes "
      "(allocation, upload, kernels by GL timer queries, download, the rest) and the kernels' "
      "share of the GPU's copy bandwidth");
    sub->add_option("--json", line.BenchJson, "Also write the results as JSON here");
    for (const auto& n : BenchStageNames())
    {
      this->Stages += (this->Stages.empty() ? "" : ",") + n;
    }
    sub->add_option("--stages", this->Stages, "Comma-separated stages to time")
      ->capture_default_str();
  }
  void Check(CommandLine& line, const CLI::App&) override
  {
    line.BenchBackends.clear();
    std::stringstream ss(this->Backends);
    std::string item;
    while (std::getline(ss, item, ','))
    {
      if (item != "auto" && item != "cpu" && item != "gpu")
      {
        throw std::invalid_argument("--backends: '" + item + "' is not auto, cpu or gpu");
      }
      line.BenchBackends.push_back(item);
    }
    if (line.BenchBackends.empty())
    {
      throw std::invalid_argument("--backends: no backend given");
    }
    std::vector<std::string> asked;
    std::stringstream st(this->Stages);
    const auto& known = BenchStageNames();
    while (std::getline(st, item, ','))
    {
      if (std::find(known.begin(), known.end(), item) == known.end())
      {
        std::string list;
        for (const auto& n : known)
        {
          list += (list.empty() ? "" : ", ") + n;
        }
        throw std::invalid_argument("--stages: '" + item + "' is not one of " + list);
      }
      asked.push_back(item);
    }
    if (asked.empty())
    {
      throw std::invalid_argument("--stages: no stage given");
    }
    // In the order the stages run, each once.
    for (const auto& n : known)
    {
      if (std::find(asked.begin(), asked.end(), n) != asked.end())
      {
        line.BenchStages.push_back(n);
      }
    }
  }

private:
  std::string Backends = "cpu,gpu";
  std::string Stages;
};
} // namespace

std::unique_ptr<CommandOptions> MakeBenchOptions()
{
  return std::unique_ptr<CommandOptions>(new BenchOptions);
}

} // namespace app
} // namespace terroir

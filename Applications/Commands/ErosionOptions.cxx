// The options of `terroir erosion` (TerroirCommandOptions.h); its code is Erosion.cxx.
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
class ErosionOptions : public CommandOptions
{
public:
  void Add(CLI::App* sub, CommandLine& line) override
  {
    auto& e = line.Erosion;
    sub->add_option("IN", line.Input, "Input DEM")->required();
    sub
      ->add_option("OUT",
        line.Output,
        "Output .tif (ErodedElevation band) or .vti (ErodedElevation, ErosionDepth, "
        "ErosionWaterDepth, SuspendedSediment and the volumes as field data)")
      ->required()
      ->check(EndsWith(RasterOutputs()));
    sub->add_option("--steps", e.Steps, "Hydraulic steps")
      ->check(CLI::Range(0, 10000000))
      ->capture_default_str();
    sub->add_option("--time-step", e.TimeStep, "Time step dt, seconds (Weiss 0.01)")
      ->check(FiniteIn(1e-6, 100.0))
      ->capture_default_str();
    sub->add_option("--water", e.InitialWater, "Water on every cell at the start, m")
      ->check(FiniteIn(0.0, 1000.0))
      ->capture_default_str();
    sub->add_option("--rain", e.RainRate, "Rain on every cell, mm per hour of simulated time")
      ->check(FiniteIn(0.0, 1e7))
      ->capture_default_str();
    sub->add_option("--talus", e.TalusAngle, "Talus angle of soil slip, degrees")
      ->check(FiniteIn(0.01, 89.99))
      ->capture_default_str();
    sub
      ->add_option("--thermal-interval",
        e.ThermalInterval,
        "A soil-slip step after every N hydraulic steps (0: none)")
      ->check(CLI::Range(0, 10000000))
      ->capture_default_str();
    sub
      ->add_option("--capacity-depth",
        e.CapacityDepth,
        "Water depth below which the sediment capacity is scaled down, m (0: off, as Weiss; on "
        "real DEMs try 0.1-1)")
      ->check(FiniteIn(0.0, 1000.0))
      ->capture_default_str();
    sub
      ->add_option("--vegetation",
        e.Vegetation,
        "Couple Dunn's vegetation, starting at this density (0-1) on every cell: it drinks, "
        "spreads, grows, dies and holds the soil")
      ->check(FiniteIn(0.0, 1.0));
    sub->add_option("--sea",
      e.SeaLevel,
      "Sea level, m: the grid's edge, no-data cells and cells at or below it take the water "
      "(default: a closed domain)");
    sub->add_flag("--weather",
      e.Weather,
      "Couple Dunn's weather: evaporation into vapour (his eq. 2.6 instead of Weiss's K_e), a "
      "prevailing wind on the pipe model, rain where the vapour exceeds the air's capacity");
    sub
      ->add_option("--wind-direction",
        e.WindDirection,
        "Weather: where the wind blows from, degrees clockwise from north")
      ->check(FiniteIn(-360.0, 360.0))
      ->capture_default_str();
    sub->add_option("--wind-strength", e.WindStrength, "Weather: the prevailing wind's push, m/s")
      ->check(FiniteIn(0.0, 1000.0))
      ->capture_default_str();
    sub
      ->add_option("--evaporation-scale",
        e.EvaporationScale,
        "Weather: factor on Dunn's evaporation (physical: 1; he raised his for effect)")
      ->check(FiniteIn(0.0, 1e9))
      ->capture_default_str();
    AddCommonOptions(sub, line);
  }
  void Check(CommandLine& line, const CLI::App&) override
  {
    CheckInputGiven(line);
    const std::string& sea = line.Erosion.SeaLevel;
    if (!sea.empty())
    {
      std::size_t used = 0;
      double level = 0.0;
      try
      {
        level = std::stod(sea, &used);
      }
      catch (const std::exception&)
      {
        used = 0;
      }
      if (used != sea.size() || !(level > -1e5 && level < 1e5))
      {
        throw std::invalid_argument("--sea '" + sea + "' must be a level in metres in (-1e5, 1e5)");
      }
    }
  }
};
} // namespace

std::unique_ptr<CommandOptions> MakeErosionOptions()
{
  return std::unique_ptr<CommandOptions>(new ErosionOptions);
}

} // namespace app
} // namespace terroir

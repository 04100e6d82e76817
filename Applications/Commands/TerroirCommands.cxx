#include "TerroirCommands.h"

#include "TerroirApp.h"
#include "TerroirBench.h"
#include "TerroirClusterSupport.h"
#include "TerroirCommandSupport.h"
#include "TerroirFlowSupport.h"
#include "TerroirWaterSupport.h"

#include <string>

namespace terroir
{
namespace app
{

//------------------------------------------------------------------------------
const std::vector<Command>& Commands()
{
  static const std::vector<Command> commands = {
    { "run", CommandRun },
    { "slope", CommandSlope },
    { "temperature", CommandTemperature },
    { "illumination", CommandIllumination },
    { "infiltration", CommandInfiltration },
    { "humidity", CommandHumidity },
    { "floodfill", CommandFloodFill },
    { "waterflow", CommandWaterFlow },
    { "flowacc", CommandFlowAccumulation },
    { "validate", CommandValidate },
    { "kmeans", CommandKMeans },
    { "morphometry", CommandMorphometry },
    { "erosion", CommandErosion },
    { "plants", CommandPlants },
    // new-filter.sh: commands
    { "view", CommandView },
    { "bench", [](const CommandLine& c) { return CommandBench(c); } },
    { "info", CommandInfo },
    { "fractal", CommandFractal },
    { "generate", CommandGenerate },
  };
  return commands;
}

//------------------------------------------------------------------------------
int RunCommand(CommandLine& line)
{
  LoadClimate(line.Temperature, line.Command == "run" ? &line.SoilWater : nullptr);
  for (const Command& command : Commands())
  {
    if (line.Command == command.Name)
    {
      const int status = command.Run(line);
      if (status == 0)
      {
        FlushNotes(); // the notes of a command that worked (placeholder climate, ...)
      }
      return status;
    }
  }
  throw Failure("no command named '" + line.Command + "' (see terroir --help)");
}

} // namespace app
} // namespace terroir

// terroir: the Terroir command-line program.
//
//   terroir run [DEM] [--out DIR]       every filter with defaults; .vti, GeoTIFFs, PNGs, report
//   terroir slope IN OUT                Horn slope (gdaldem style), GeoTIFF or .vti
//   terroir temperature IN OUT          monthly temperature (12 bands)
//   terroir illumination IN OUT         shadows, hours of sun, insolation (instant/daily/monthly)
//   terroir infiltration IN OUT         infiltration rates (fill, slope rule, paint, soil types)
//   terroir humidity IN OUT             monthly soil humidity, weighted, standing water
//   terroir floodfill IN OUT            lakes from seeds, or every closed depression
//   terroir waterflow IN OUT            the hydrostatic water-flow simulation (rivers, lakes)
//   terroir flowacc IN OUT              D8 flow accumulation after priority-flood filling
//   terroir validate [DEM]              simulated rivers scored against mapped ones
//   terroir kmeans IN OUT -k K          ecological zones: k-means of the resources, zone table
//   terroir bench [--size N]            time per stage and backend, per million cells
//   terroir info IN                     grid and georeference of a DEM
//   terroir fractal OUT --size N        a seeded synthetic DEM (GeoTIFF or .vti)
//   terroir view [DEM] [--script F]     the interactive window (Documentation/Viewer.md)
//
// Errors are one line on stderr ("terroir: error: ...") and exit code 1 (2 for a bad command
// line, found before any work: TerroirCommandLine.h); outputs are written under a temporary
// name and renamed, and existing files are kept unless --overwrite. The commands live in
// Commands/ (TerroirCommands.h: the registry).
#include "TerroirApp.h"
#include "TerroirCommandLine.h"
#include "TerroirCommands.h"

#include <exception>
#include <iostream>

int main(int argc, char** argv)
{
  terroir::app::CommandLine c;
  const int exitCode = terroir::app::StartCommandLine(argc, argv, c, "terroir");
  if (exitCode >= 0)
  {
    return exitCode;
  }
  try
  {
    return terroir::app::RunCommand(c);
  }
  catch (const std::exception& e)
  {
    std::cerr << "terroir: error: " << e.what() << "\n";
    return 1;
  }
}

/**
 * @file TerroirWaterSupport.h
 * @brief The soil-water and water-body commands of `terroir` (infiltration, humidity,
 * floodfill) and the pieces `terroir run` shares with them.
 */
#ifndef TerroirWaterSupport_h
#define TerroirWaterSupport_h

#include "TerroirCommandLine.h"

#include <string>

#include "vtkSmartPointer.h" // For vtkSmartPointer

class vtkImageData;
class vtkTerroirFloodFill;
class vtkTerroirInfiltration;
class vtkTerroirSoilHumidity;

namespace terroir
{
namespace app
{

/// Adds the infiltration operations of `s` to `filter`, in order: reads the rasters (which must
/// lie on the terrain's grid) and burns the polygons onto it. Throws Failure naming the file.
void ApplyInfiltration(const SoilWaterSettings& s,
  vtkTerroirInfiltration* filter,
  vtkImageData* terrain,
  bool allowNetwork);

/// Sets the soil-humidity filter's climate: --precip / --intensity (each replacing the
/// filter's default), or --climate (read with vtkTerroirClimateReader).
void ApplyClimate(const SoilWaterSettings& s, vtkTerroirSoilHumidity* filter);

/// Adds the seeds of `s` to `filter` (or sets FillDepressions mode) and its parameters.
void ApplyFloodFill(const FloodFillSettings& s, vtkTerroirFloodFill* filter);

/// Prints one line per water body of a vtkTerroirFloodFill output (id, level, cells, area,
/// volume, deepest point), at most `limit` of them, largest first.
void PrintWaterBodies(vtkImageData* result, int limit);

/// A raster read onto the terrain's grid: a new image with the terrain's structure whose only
/// (scalar) point array, named `arrayName`, holds the raster's values. Throws Failure naming
/// the file when its size or geotransform differ from the DEM's.
vtkSmartPointer<vtkImageData> ReadGridOperand(const std::string& path,
  vtkImageData* terrain,
  bool allowNetwork,
  const char* arrayName);

/// Polygons (or lines) burnt onto the terrain's grid: a new image whose scalars are the burnt
/// values (1 on covered cells and 0 elsewhere, or the attribute `field` and NaN elsewhere).
/// `quiet` drops the rasterizer's warnings (the caller reports an empty result itself).
vtkSmartPointer<vtkImageData> RasterizePolygons(const std::string& path,
  const std::string& field,
  vtkImageData* terrain,
  bool allowNetwork,
  bool quiet = false);

} // namespace app
} // namespace terroir

#endif

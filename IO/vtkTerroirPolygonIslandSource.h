/**
 * @class   vtkTerroirPolygonIslandSource
 * @brief   Generates a seeded island from Weiss (2015)'s polygon map: Voronoi regions, island
 *          shape, ocean and lakes, elevation from the coast, rivers, moisture and biomes, then
 *          the height map with biome-dependent multifractal noise.
 *
 * Output: vtkImageData (Dimensions[0], Dimensions[1], 1), spacing (Spacing, Spacing, 1) metres,
 * origin (0, 0, 0), no georeference. Point arrays: `Elevation` (float32, m; 0 = sea level,
 * MaximumHeight the highest cell, -MaximumDepth the deepest), `Biome` (uint8, the
 * terroir::generation::Biome code of the cell's region, Weiss's Table I order: 0 Snow ...
 * 13 Beach, 14 Lake, 15 Ocean), `Moisture` (float32, [0, 1]), `River` (uint8, 1 on the rivers
 * the generator drew), `WaterClass` (uint8, 0 land, 1 lake, 2 ocean) and `RegionId` (int32, the
 * cell's Voronoi region). Output port 1: the generated rivers as vtkPolyData, one line per
 * river step from a region's point to the next region's point down the river (world
 * coordinates of the image: cell (i, j) at (i, j) x Spacing), cell array `RiverFlow` (the water
 * the river carries there, in river steps, Weiss's "amount of water").
 *
 * Parameters (defaults): Dimensions 512 x 512, Spacing 30 m, Seed 1, Regions 1000 Voronoi
 * points, Relaxations 2 Lloyd steps, Rivers 0 (= Regions / 20 springs), MaximumHeight 1000 m,
 * MaximumDepth 200 m, NoiseScale 0.25 (the multifractal noise's weight), Perturbation 0.02
 * (the base map's noise displacement, in map-width units); the island-shape constants are
 * Weiss's (n = 4, o_b = 6, o_s = 2, a_b = 0.5, a_s = 2.5, scale = 2.2, offset = -0.2).
 *
 * Algorithm and its departures from the paper (a raster instead of a vector graph):
 * IO/Core/PolygonIsland.h (terroir::generation::GeneratePolygonIsland). Single-threaded and
 * bit-identical for a seed on every platform.
 *
 * @par Correctness
 * PolygonIsland.* unit tests (Voronoi labels against brute force, Lloyd's energy, ocean/lake/
 * coast against an independent flood, elevation walk, rivers, biomes, seeds) and
 * TerroirPolygonIslandSource.* pipeline tests.
 *
 * @par References
 * S. Weiss, "Procedural Terrain", CS6491 final project, Georgia Tech, 2015; A. Patel,
 * "Polygonal Map Generation for Games", 2010.
 */
#ifndef vtkTerroirPolygonIslandSource_h
#define vtkTerroirPolygonIslandSource_h

#include "vtkImageAlgorithm.h"
#include "vtkTerroirIOModule.h" // For export macro

#include <string> // For std::string

class VTKTERROIRIO_EXPORT vtkTerroirPolygonIslandSource : public vtkImageAlgorithm
{
public:
  static vtkTerroirPolygonIslandSource* New();
  vtkTypeMacro(vtkTerroirPolygonIslandSource, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Number of points (nx, ny), each in [8, 65536]. Default: 512 x 512.
  vtkSetVector2Macro(Dimensions, int);
  vtkGetVector2Macro(Dimensions, int);
  ///@}
  ///@{
  /// Cell size, metres. Default: 30.
  vtkSetMacro(Spacing, double);
  vtkGetMacro(Spacing, double);
  ///@}
  ///@{
  /// Seed (64-bit). Default: 1.
  vtkSetMacro(Seed, unsigned long long);
  vtkGetMacro(Seed, unsigned long long);
  ///@}
  ///@{
  /// Voronoi points, [16, cells / 4]. Default: 1000.
  vtkSetMacro(Regions, int);
  vtkGetMacro(Regions, int);
  ///@}
  ///@{
  /// Lloyd relaxation steps, [0, 100]. Default: 2.
  vtkSetMacro(Relaxations, int);
  vtkGetMacro(Relaxations, int);
  ///@}
  ///@{
  /// River springs; 0: Regions / 20. Default: 0.
  vtkSetMacro(Rivers, int);
  vtkGetMacro(Rivers, int);
  ///@}
  ///@{
  /// Heights of the highest cell and depth of the deepest, metres. Defaults: 1000, 200.
  vtkSetMacro(MaximumHeight, double);
  vtkGetMacro(MaximumHeight, double);
  vtkSetMacro(MaximumDepth, double);
  vtkGetMacro(MaximumDepth, double);
  ///@}
  ///@{
  /// Weight of eq. 4's multifractal noise, >= 0. Default: 0.25.
  vtkSetMacro(NoiseScale, double);
  vtkGetMacro(NoiseScale, double);
  ///@}
  ///@{
  /// Noise displacement of the base map, map-width units, >= 0. Default: 0.02.
  vtkSetMacro(Perturbation, double);
  vtkGetMacro(Perturbation, double);
  ///@}

  ///@{
  /// A place for the island: a coordinate reference system in metres (any definition GDAL
  /// takes: "EPSG:32631", WKT; empty, the default: no georeference) and the world coordinates
  /// of the first cell's centre (default 0, 0). With a CRS the image carries TerroirCRS and
  /// TerroirGeoTransform, so GeoTIFFs are georeferenced and `terroir validate` can score it.
  vtkSetStdStringFromCharMacro(CRS);
  vtkGetCharFromStdStringMacro(CRS);
  vtkSetVector2Macro(Origin, double);
  vtkGetVector2Macro(Origin, double);
  ///@}

  /// Port 0: the image; port 1: the rivers (vtkPolyData).
  int FillOutputPortInformation(int port, vtkInformation* info) override;

  /// The last error as one line, or "" after a successful run.
  const char* GetErrorMessage() const { return this->ErrorMessage.c_str(); }

protected:
  vtkTerroirPolygonIslandSource();
  ~vtkTerroirPolygonIslandSource() override = default;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Dimensions[2] = { 512, 512 };
  double Spacing = 30.0;
  unsigned long long Seed = 1;
  int Regions = 1000;
  int Relaxations = 2;
  int Rivers = 0;
  double MaximumHeight = 1000.0;
  double MaximumDepth = 200.0;
  double NoiseScale = 0.25;
  double Perturbation = 0.02;
  std::string CRS;
  double Origin[2] = { 0.0, 0.0 };
  std::string ErrorMessage;

private:
  vtkTerroirPolygonIslandSource(const vtkTerroirPolygonIslandSource&) = delete;
  void operator=(const vtkTerroirPolygonIslandSource&) = delete;
};

#endif

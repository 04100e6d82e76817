/**
 * @file PolygonIsland.h
 * @brief Weiss (2015)'s polygon-map island on a raster, no VTK: Voronoi regions of seeded random
 * points with Lloyd relaxation, the island shape of his eq. 1-2, ocean and lakes by a flood
 * from the border, elevation by breadth-first distance from the coast (redistributed so that
 * low land is common and peaks rare), rivers down the steepest descent from random springs,
 * moisture spreading from rivers and lakes with a factor 0.8 per step, biomes from temperature
 * (1 - elevation) and moisture, then the height map: the regions' elevations interpolated,
 * perturbed by noise, h <- sign(h) |h|^1.5 (his eq. 3) and the biome-dependent multifractal
 * noise of his eq. 4 with the amplitudes and roughness of his Table I.
 *
 * Departures from the paper, because it works on a vector graph and we on a raster (each
 * documented where it happens):
 * - The Voronoi diagram is discrete: a cell belongs to its nearest point (exact, by buckets).
 *   Lloyd's step moves a point to the centroid of its region's cells (Weiss averages the
 *   polygon's corners, an approximation of the same centroid).
 * - Eq. 1 sums each octave's noise mapped to [0, 1] ((Perlin + 1) / 2); read as [-1, 1], his
 *   parameters leave an islet of about 4 % of the map instead of the island of his figures.
 * - Weiss's corners are the region's boundary cells: a region is water when at least 30 % of
 *   its boundary cells are water by eq. 2 (he: 30 % of its corners).
 * - Elevation, rivers and moisture walk the regions' adjacency graph (his walk the corners).
 *   The coast is the land regions next to the ocean; land steps add 1 (0 into a lake), ocean
 *   steps subtract 1. Land elevations are redistributed by rank q in [0, 1] to 1 - sqrt(1 - q)
 *   (Patel 2010's redistribution, the paper's source [9]); ocean depths are -steps / deepest.
 * - The base height map interpolates the regions' elevations by inverse squared distance over
 *   the region and its neighbours (he draws the triangle mesh of centres and corners).
 * Biomes (the paper's section VII-A is empty; its 16 biomes are Patel's): ocean, lake, beach
 * (coast), then by temperature zone and moisture as in Patel (2010).
 *
 * Determinism: the random points and springs come from a 64-bit SplitMix generator mapped to
 * doubles by integer arithmetic, noise from terroir::io::GradientNoisePerlin2002, no std::
 * distributions: the same parameters give the same bits on every platform.
 *
 * References: S. Weiss, "Procedural Terrain", CS6491 final project, Georgia Tech, 2015;
 * A. Patel, "Polygonal Map Generation for Games", 2010,
 * http://www-cs-students.stanford.edu/~amitp/game-programming/polygon-map-generation/;
 * S. Lloyd, "Least squares quantization in PCM", IEEE Trans. Inf. Theory 28(2), 1982.
 */
#ifndef terroir_io_PolygonIsland_h
#define terroir_io_PolygonIsland_h

#include <cstdint>
#include <string>
#include <vector>

namespace terroir
{
namespace generation
{

/// Weiss (2015)'s biomes (his Table I), in its order.
enum class Biome : std::uint8_t
{
  Snow = 0,
  Tundra,
  Bare,
  Scorched,
  Taiga,
  Shrubland,
  TemperateDesert,
  TemperateRainForest,
  DeciduousForest,
  Grassland,
  TropicalRainForest,
  TropicalSeasonalForest,
  SubtropicalDesert,
  Beach,
  Lake,
  Ocean,
  Count
};

/// A biome's name ("Temperate rain forest") and its noise amplitude A and roughness R (Table I).
const char* BiomeName(Biome b);
double BiomeAmplitude(Biome b);
double BiomeRoughness(Biome b);

/// Patel (2010)'s Whittaker-style rule: the biome of a land region from its temperature
/// (1 - elevation, [0, 1]) and moisture ([0, 1]); water and coast are decided before.
Biome LandBiome(double temperature, double moisture);

/// Parameters; defaults are Weiss (2015)'s where he gives them.
struct PolygonIslandParameters
{
  std::uint64_t seed = 1;
  int width = 512;               ///< raster columns
  int height = 512;              ///< raster rows
  int regions = 1000;            ///< Voronoi points
  int relaxations = 2;           ///< Lloyd steps ("two or three iterations")
  int shapeOctaves = 4;          ///< eq. 1: n
  double baseOctave = 6.0;       ///< eq. 1: o_b
  double octaveScale = 2.0;      ///< eq. 1: o_s
  double baseAmplitude = 0.5;    ///< eq. 1: a_b
  double amplitudeScale = 2.5;   ///< eq. 1: a_s
  double shapeScale = 2.2;       ///< eq. 2: scale
  double shapeOffset = -0.2;     ///< eq. 2: offset
  double waterShare = 0.3;       ///< share of a region's boundary that makes it water
  int rivers = 0;                ///< springs; 0: regions / 20
  double moistureDecay = 0.8;    ///< moisture factor per step from rivers and lakes
  double perturbation = 0.02;    ///< noise displacement of the base map, map-width units
  double heightExponent = 1.5;   ///< eq. 3
  int noiseOctaves = 5;          ///< eq. 4: n
  double noiseRatio = 2.0;       ///< eq. 4: r
  double noiseFrequency = 4.0;   ///< eq. 4: the first octave's periods across the map
  double noiseScale = 0.25;      ///< eq. 4's N is multiplied by this (the paper gives no scale)
  double maximumHeight = 1000.0; ///< metres of the highest cell (1 after normalising)
  double maximumDepth = 200.0;   ///< metres below sea level of the deepest cell (-1)
};

/// The polygon map (one entry per region) and the rasters (row j = 0 south, i east; x in
/// [-1, 1] west to east, y = (j + 0.5 - height / 2) * 2 / width).
struct PolygonIsland
{
  // Regions.
  std::vector<double> siteX, siteY;        ///< relaxed points
  std::vector<std::vector<int>> neighbors; ///< sorted region adjacency (Delaunay dual)
  std::vector<std::uint8_t> water, ocean, coast, border;
  std::vector<double> elevation;   ///< land [0, 1], ocean [-1, 0)
  std::vector<double> moisture;    ///< land [0, 1] (rank-normalised), water 1
  std::vector<double> temperature; ///< 1 - max(elevation, 0)
  std::vector<double> riverFlow;   ///< water a river carries through the region, 0 if none
  std::vector<int> downslope;      ///< the next region down (BFS parent), -1 at the coast/ocean
  std::vector<Biome> biome;
  // Rasters (width * height, row-major from the south).
  std::vector<int> region;            ///< Voronoi label of each cell
  std::vector<float> heightMeters;    ///< Elevation, m (0 = sea level)
  std::vector<std::uint8_t> biomeMap; ///< Biome of each cell's region
  std::vector<float> moistureMap;     ///< the region's moisture
  std::vector<std::uint8_t> riverMap; ///< 1 on the rivers (segments between region points)
  std::vector<std::uint8_t> waterMap; ///< 0 land, 1 lake, 2 ocean (the region's class)
};

/// Nearest point of each raster cell (exact; ties to the lower index), coordinates as above.
std::vector<int> VoronoiLabels(const std::vector<double>& x,
  const std::vector<double>& y,
  int width,
  int height);

/// Generates the island. False with `error` for bad parameters (sizes, counts, ranges).
bool GeneratePolygonIsland(const PolygonIslandParameters& p,
  PolygonIsland& out,
  std::string& error);

/// The 64-bit SplitMix step (Steele et al. 2014) used for every random number here.
std::uint64_t SplitMix64(std::uint64_t& state);
/// A double in [0, 1) from the generator: the top 53 bits over 2^53.
double UnitDouble(std::uint64_t& state);

} // namespace generation
} // namespace terroir

#endif

/**
 * @file TriangleTexturing.h
 * @brief Non-periodic terrain texturing from eight edge-matched right-triangle tiles per
 *        material (Jensen 2011, after Neyret & Cani 1999), blended by slope, height and biome.
 *
 * Plain C++ (no VTK, no GL): the core of vtkTerroirOverlayView's `Texturing` option.
 *
 * Grid. A terrain of (cellsX + 1) x (cellsY + 1) points has cellsX x cellsY cells; cell (i, j)
 * spans [i, i + 1] x [j, j + 1] (cell units, x east, y north) and is split along its diagonal
 * from (i, j) to (i + 1, j + 1) into a lower triangle L (below the diagonal) and an upper
 * triangle U. U is L turned by 180 degrees, so one set of tiles serves both.
 *
 * Sides and edges (Jensen 2011, section 4.3, figures 20-21). A triangle's three sides are its
 * horizontal leg (edge pair (A, A')), its vertical leg (B, B') and its diagonal (C, C'); in L's
 * own frame they are its bottom, right and diagonal sides, in U's (turned) frame its top, left
 * and diagonal. Each side of a triangle carries one edge of its pair, so 2 x 2 x 2 = 8 tiles fit
 * every boundary condition: tile index = bit 0 (A'), bit 1 (B'), bit 2 (C') of the triangle's
 * own edges. Assignment walks the cells row by row (j, then i), L before U, and each triangle's
 * sides A, B, C in turn: a side already set by its neighbour gets the matching edge (A' for A),
 * otherwise an edge is drawn with probability 1/2 from a seeded splitmix64 stream; then the
 * tile that fits the three edges is placed.
 *
 * Tiles (our synthesis: the paper's textures are not available). A tile is T x T texels on a side
 * with texels at integer corner positions (a, b), 0 <= b <= a <= T, in L's frame. Each edge pair s
 * owns one band of 2-D value noise F_s(t, d) along its side (t along the side, d the distance
 * into the triangle; both in texel units, the diagonal's scaled by 1/sqrt 2). A side with edge
 * s reads F_s(t, d); with edge s' it reads F_s(L_s - t, -d), L_s the side's length: the band
 * turned by 180 degrees, which is what the neighbour's (turned) frame reads for the matching
 * edge, so both triangles see one and the same noise across their shared side. Texels on a
 * side are the band's texels on it (bitwise equal on both triangles); inside, the bands are
 * blended (weight of side s = product of the distances to the other two sides) and faded into
 * the tile's own interior noise N_k over a distance R = T / 8 (smoothstep of the distance to
 * the nearest side); each blend of independent noises is divided by the root of its summed
 * squared weights, which keeps the noise's contrast. Bands fade to 0 within max(1.5, T / 16)
 * texels of their ends, so every grid vertex gets the material's base colour from all six
 * triangles around it. Every side of a kind shows the same band (or its turn) all over the
 * terrain, so each band's noise stream is the one of 32 candidates whose mean over the band is
 * nearest 0 and whose spread is nearest the interiors' (a darker or flatter band would draw the
 * grid). Noise: three octaves of value noise, each octave's lattice turned by its own angle (no
 * axis shows, so diagonal bands look like the others). A noise value n (about -1..1) becomes the
 * colour base x (1 + Amplitude x n), clamped to [0, 1].
 *
 * Materials and rules (ours; see MaterialRules): rock on steep slopes, snow high up, sand near
 * sea level, elsewhere the ground of the point's biome zone (`ClusterId`): grass, forest floor
 * or dry soil by zone modulo 3, grass without a zone. The per-point weights are interpolated
 * bilinearly to each texel, so the blend is continuous across every side too.
 *
 * Texture. T texels per tile side; a tile covers k x k cells (k = CellsPerTile, 1 unless the
 * image would exceed the maximum size, default 4096 texels on a side, 48 MiB of RGB). Image
 * size (ceil(cellsX / k) T + 1) x (ceil(cellsY / k) T + 1), RGB, 8 bits, row 0 at y = 0.
 * A grid point at x cells has texture coordinate (x T / k + 0.5) / Width (a texel centre).
 *
 * @par Correctness
 * Testing/Unit/TestTriangleTexturing.cxx: shared sides equal on both triangles, the eight tiles
 * equally frequent, no translation symmetry, determinism, weights and rules, layout, errors.
 *
 * @par References
 * S. Jensen, "RiverLand 2.0", 2011, section 4 (non-periodic texturization).
 * F. Neyret and M.-P. Cani, "Pattern-based texturing revisited", SIGGRAPH 1999,
 * doi:10.1145/311535.311561.
 */
#ifndef terroir_rendering_TriangleTexturing_h
#define terroir_rendering_TriangleTexturing_h

#include <cstdint>
#include <string>
#include <vector>

namespace terroir
{
namespace rendering
{

/// Tile assignment of a cellsX x cellsY grid (AssignTilesJensen2011).
struct TileAssignment
{
  int CellsX = 0;
  int CellsY = 0;
  /// Edge label of each side as L reads it (0: A, 1: A'); U reads the other one.
  /// Horizontal sides y = j, x in [i, i + 1]: index j * CellsX + i, j in [0, CellsY].
  std::vector<std::uint8_t> Horizontal;
  /// Vertical sides x = i, y in [j, j + 1]: index j * (CellsX + 1) + i, i in [0, CellsX].
  std::vector<std::uint8_t> Vertical;
  /// Diagonal of cell (i, j): index j * CellsX + i.
  std::vector<std::uint8_t> Diagonal;
  /// Tile (0..7) of each triangle: index 2 (j * CellsX + i) for L, + 1 for U.
  std::vector<std::uint8_t> Tiles;

  std::uint8_t LowerTile(int i, int j) const
  {
    return this->Tiles[2 * (std::size_t(j) * this->CellsX + i)];
  }
  std::uint8_t UpperTile(int i, int j) const
  {
    return this->Tiles[2 * (std::size_t(j) * this->CellsX + i) + 1];
  }
};

/// Jensen's (2011) walk: the tiles of a cellsX x cellsY grid (both >= 1), seeded. Throws
/// std::invalid_argument on a bad size.
TileAssignment AssignTilesJensen2011(int cellsX, int cellsY, std::uint64_t seed);

/// The materials of the default set, in this order (MaterialRules refers to them).
enum MaterialIndex
{
  Grass = 0,
  Forest = 1,  ///< forest floor, dark soil
  DrySoil = 2, ///< dry, bare soil
  Rock = 3,
  Sand = 4,
  Snow = 5,
  MaterialCount = 6
};

/// A material: base colour (sRGB, 0..1), noise amplitude (relative change of the colour) and
/// feature size (the noise's lattice period as a fraction of a tile side; finer for smaller).
struct Material
{
  std::string Name;
  float Color[3] = { 0.5f, 0.5f, 0.5f };
  float Amplitude = 0.2f;
  float FeatureSize = 0.25f;
};

/// Grass, forest floor, dry soil, rock, sand and snow (MaterialIndex order); our choice of
/// colours (e.g. grass 0.36 0.52 0.22, rock 0.50 0.48 0.45, snow 0.95 0.96 0.98).
std::vector<Material> DefaultMaterials();

/// The eight tiles of one material: T texels per side, (T + 1)^2 RGB floats per tile at the
/// corner positions (a, b), of which those with b <= a (L's frame) are used.
struct TileSet
{
  int TexelsPerSide = 0;
  std::vector<float> Texels; ///< [tile][b][a][rgb]
  const float* At(int tile, int a, int b) const
  {
    const std::size_t n = std::size_t(this->TexelsPerSide) + 1;
    return &this->Texels[((std::size_t(tile) * n + b) * n + a) * 3];
  }
};

/// Synthesises a material's eight tiles (file comment), seeded. texelsPerSide in [2, 256];
/// Amplitude in [0, 1]; FeatureSize in (0, 4]. Throws std::invalid_argument otherwise.
TileSet SynthesizeTiles(const Material& material, int texelsPerSide, std::uint64_t seed);

/// The seed of material m's tiles in BuildTerrainTexture (a splitmix64 step of seed and m).
std::uint64_t MaterialTileSeed(std::uint64_t seed, std::size_t m);

/// Rules of the material weights (all heights in metres, slopes in degrees).
struct MaterialRules
{
  double RockSlopeStart = 30.0; ///< rock starts (weight 0) at this slope
  double RockSlopeFull = 45.0;  ///< rock only from this slope on
  double SeaLevel = 0.0;        ///< sand only up to this height...
  double SandHeight = 5.0;      ///< ...fading to none this far above it
  double SnowLine = 2000.0;     ///< half snow at this height...
  double SnowBand = 200.0;      ///< ...from none to full over this band around it
};

/// The weights (MaterialCount, summing to 1) of a point with slope `slopeDeg`, height
/// `height` and biome zone `zone` (< 0: none). With r = smoothstep(RockSlopeStart,
/// RockSlopeFull, slope), s = smoothstep(SnowLine - SnowBand/2, SnowLine + SnowBand/2, height),
/// q = 1 - smoothstep(SeaLevel, SeaLevel + SandHeight, height) and g the zone's ground (Grass,
/// Forest, DrySoil by zone mod 3; Grass without a zone): Rock r, Snow (1-r) s, Sand
/// (1-r)(1-s) q, g (1-r)(1-s)(1-q). A non-finite height or slope counts as flat ground.
/// Throws std::invalid_argument on rules with RockSlopeFull <= RockSlopeStart, SandHeight <= 0
/// or SnowBand <= 0.
void MaterialWeightsAt(double slopeDeg,
  double height,
  int zone,
  const MaterialRules& rules,
  float weights[MaterialCount]);

/// Slope (degrees) at each point of a pointsX x pointsY grid of heights (metres; row-major,
/// row 0 at y = 0) with spacing dx, dy (metres): atan |grad z| with central differences, one-
/// sided next to edges and non-finite heights, 0 where neither neighbour is usable.
std::vector<float> SlopeDegrees(int pointsX,
  int pointsY,
  double dx,
  double dy,
  const std::vector<float>& heights);

/// Per-point weights (MaterialCount per point) of a grid of heights (see SlopeDegrees) and
/// optional zones (empty or one per point). Throws std::invalid_argument on bad sizes.
std::vector<float> MaterialWeights(int pointsX,
  int pointsY,
  double dx,
  double dy,
  const std::vector<float>& heights,
  const std::vector<int>& zones,
  const MaterialRules& rules);

/// Size of the texture image of a grid (PlanTexture).
struct TextureLayout
{
  int CellsX = 0, CellsY = 0;
  int TexelsPerTile = 0; ///< T
  int CellsPerTile = 1;  ///< k
  int TilesX = 0, TilesY = 0;
  int Width = 0, Height = 0;
  /// Texture coordinate (0..1) of a point at `cells` cells along x (TextureU) or y.
  double TextureU(double cells) const
  {
    return (cells * this->TexelsPerTile / this->CellsPerTile + 0.5) / this->Width;
  }
  double TextureV(double cells) const
  {
    return (cells * this->TexelsPerTile / this->CellsPerTile + 0.5) / this->Height;
  }
};

/// The smallest k (cells per tile) for which the image of a cellsX x cellsY grid with T texels
/// per tile fits maxSize texels on a side. cells >= 1, T in [2, 256], maxSize >= T + 1.
TextureLayout PlanTexture(int cellsX, int cellsY, int texelsPerTile, int maxSize = 4096);

/// The texture of a grid and its tile assignment.
struct TerrainTexture
{
  TextureLayout Layout;
  TileAssignment Tiles;          ///< of the TilesX x TilesY tile grid
  std::vector<std::uint8_t> Rgb; ///< Width x Height x 3, row 0 at y = 0
};

/// The RGB texture of a pointsX x pointsY grid (>= 2 each) from per-point material weights
/// (materials.size() per point, each >= 0, summing to 1 within 1e-3), T texels per tile side,
/// `seed` (tiles of material m use a seed derived from seed and m) and the size limit
/// (PlanTexture). Each texel = sum over materials of (bilinear weight at its position) x (its
/// triangle's tile texel), rounded to 8 bits. Throws std::invalid_argument on bad input.
TerrainTexture BuildTerrainTexture(int pointsX,
  int pointsY,
  const std::vector<float>& weights,
  const std::vector<Material>& materials,
  int texelsPerTile,
  std::uint64_t seed,
  int maxSize = 4096);

/// The colour (0..1) that a triangle's tile gives the texel at (a, b) of a tile cell (both in
/// [0, T]): L's tile at (a, b) when b <= a, else U's turned tile at (T - a, T - b).
const float* TileTexel(const TileSet& tiles, int lowerTile, int upperTile, int a, int b);

} // namespace rendering
} // namespace terroir

#endif

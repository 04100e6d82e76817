/**
 * @file RiverLand.h
 * @brief Jensen (2011)'s RiverLand 2.0 on a raster, no VTK: river-first terrain. The rivers
 * come first and the land is shaped around them.
 *
 * Steps (each from the paper's section named; departures marked "ours"):
 * 1. Coast (ours: the paper's user paints the island). Island mode: land where fBm noise plus
 *    a radial fall-off is above a level, the largest 4-connected land mass kept and its lakes
 *    filled; border mode: everything but the map's outer ring is land. Coast cells are land
 *    cells 4-adjacent to the sea.
 * 2. Rivers (1.2.2): river mouths at random coast cells (at least `mouthSpacing` apart). From
 *    each, a river grows inland, first perpendicular to the coast (ours: the direction away
 *    from the sea cells within 4 cells), for `segmentLength` cells; then the direction turns
 *    by a random angle in [-maxTurn, maxTurn] (Jensen: +-90 degrees) at each SegmentPoint, for
 *    up to `segments` segments. A meandering curve is fitted between SegmentPoints: a half
 *    sine across each segment whose amplitude is random (up to `meander` x the segment
 *    length) and whose side alternates from one segment to the next. Tributaries start on
 *    the concave (outer) bank at the apex of a bend, with probability `tributaryChance` per
 *    bend, up to `tributaryLevels` deep, each level's segments, length and turn shrunk by
 *    `tributaryShrink`. Ours: a step is refused if it leaves the land, touches the coast or
 *    comes within `riverSpacing` cells of another river; up to 8 random turns are tried,
 *    then the river ends.
 * 3. River heights (1.2.2): 0 at the mouth, rising by `averageSlope` x step length, the
 *    slope scaled by (1 + steepening x s / L) (s the length along the network from the
 *    mouth, L the map's larger side: steeper near the sources) and by a random factor in
 *    [1 - roughness, 1 + roughness] per cell (roughness < 1: heights strictly rise inland).
 * 4. Distance propagation (1.2.3): river and coast cells start at d = 0; a list (ours: a
 *    Dijkstra heap ordered by (d, cell)) gives each neighbour d + step (1 or sqrt 2 cells)
 *    and a pointer back to the cell that sent it; each cell so knows its river (or coast)
 *    cell. Medial-axis cells are the cells that pointed to nobody. Ours, tie independent: a
 *    cell is medial when no 8-neighbour is reached through it on a shortest path, i.e. no
 *    neighbour n has d(n) = d(c) + step(c, n).
 * 5. Pruning (3.2-3.3): medial cells in ascending d; one is pruned when the river cells
 *    that all its 8 neighbours point back to lie within `pruneThreshold` (20) cells along the
 *    river network of its own river cell (Jensen's sparse table of traversal distances; ours:
 *    the tree distance through the lowest common river cell, found by climbing at most the
 *    threshold). A pruned cell points to a neighbouring medial cell not pruned yet (ours: or,
 *    if none, to its neighbour of largest d above its own; if neither, it is kept), and all
 *    pointers are then followed to a medial cell that remains. Ours: two coast cells count
 *    as near when their chessboard distance is under the threshold (`pruneCoast`).
 * 6. Heights (1.2.3, 2.4): each land cell walks up (ours: to the neighbour reached through
 *    it whose step best continues the step it came by) to a medial cell m. m's height is
 *    its river's height + `hillSlope` x d(m) (ours: the higher of the rivers that meet there,
 *    so that no river lies above its ridge). A cell at t = d / d(m) gets
 *    h = h_river + f(t) (h_m - h_river), f the linear profile t or a user slope's.
 * 7. User slopes (2.2-2.4): a profile (linear, cos: 1 - cos(pi t / 2), cos2: 1 - cos^2(pi t
 *    / 2), gauss: the normal density from x = 3.1 at the river to 0 at the ridge rescaled
 *    to [0, 1], or a custom curve of 2 to 64 points (x, y) in [0, 1], piecewise linear) at a
 *    chosen cell (ours: or the nearest plain land cell within 8 cells) with an influence
 *    distance I. Its path (the cell's pointers down to the
 *    river and up to its medial cell) gets influence I; a 4-neighbour flood gives each
 *    neighbour one less, never entering medial, river or coast cells. Blending (2.4.2): one
 *    slope, h = w h_s + (1 - w) h_linear with w = influence / I; (2.4.3) two or more,
 *    weights w_s and 1 for the linear slope, each divided by their sum. Both as Jensen
 *    writes them (the two rules differ where a second slope's influence begins).
 * 8. Optional fractal overlay (1.2.4): fBm noise of `noiseAmplitude` metres scaled by f(t),
 *    so rivers stay at their heights. Sea cells get -seaDepth.
 *
 * Determinism: one 64-bit SplitMix stream draws every random number in a fixed order; the
 * per-cell passes (medial test, heights) split rows between `threads` threads, each cell's
 * value depending only on its inputs: 1 and N threads give identical bits.
 *
 * Reference: J. Jensen, "RiverLand 2.0: Blending of Multiple User-defined Slopes in a
 * Procedurally Modeled Terrain", MS project, San Jose State University, 2011,
 * doi:10.31979/etd.65dg-txf7; S. T. Teoh, "RiverLand", ISVC 2009.
 */
#ifndef terroir_io_RiverLand_h
#define terroir_io_RiverLand_h

#include <cstdint>
#include <string>
#include <vector>

namespace terroir
{
namespace generation
{

/// A slope profile's shape f: [0, 1] -> [0, 1] from the river (0) to the ridge (1).
enum class SlopeProfile : std::uint8_t
{
  Linear = 0,
  Cos,
  Cos2,
  Gauss,
  Custom
};

/// A user-defined slope (Jensen 2.2): where, which shape, how far it reaches.
struct RiverLandSlope
{
  double x = 0.5; ///< position, fraction of the map's width (0 west .. 1 east)
  double y = 0.5; ///< position, fraction of the map's height (0 south .. 1 north)
  SlopeProfile profile = SlopeProfile::Cos;
  double influence = 40.0;            ///< influence distance, cells (> 0)
  std::vector<double> curveX, curveY; ///< Custom: 2 to 64 points, x increasing in [0, 1]
};

/// Parameters; defaults give a 512 x 512 island (Jensen's where he gives a value).
struct RiverLandParameters
{
  std::uint64_t seed = 1;
  int width = 512, height = 512;
  double spacing = 30.0;        ///< cell size, metres (heights and slopes are in metres)
  bool island = true;           ///< true: noise island; false: the map border is the coast
  double landLevel = 0.0;       ///< island: land where noise + fall-off > this
  double islandNoise = 0.35;    ///< island: noise weight against the radial fall-off
  int rivers = 12;              ///< river mouths
  int mouthSpacing = 16;        ///< cells between mouths, at least
  int segments = 12;            ///< SegmentPoints per main river
  double segmentLength = 14;    ///< cells between SegmentPoints
  double maxTurn = 90.0;        ///< degrees, Jensen's +-90
  double meander = 0.25;        ///< half-sine amplitude, fraction of the segment length
  double tributaryChance = 0.5; ///< per bend
  int tributaryLevels = 2;      ///< tributaries of tributaries ...
  double tributaryShrink = 0.6; ///< segments, length and turn of each level
  int riverSpacing = 4;         ///< cells between different rivers, at least
  double averageSlope = 0.004;  ///< river bed rise, m per m
  double steepening = 3.0;      ///< slope x (1 + steepening s / L)
  double roughness = 0.5;       ///< random factor of each river step's rise, in [0, 1)
  double hillSlope = 0.25;      ///< ridge rise above its river, m per m of d (Jensen's slope)
  bool prune = true;
  double pruneThreshold = 20.0; ///< cells along the rivers (Jensen: 20)
  bool pruneCoast = true;       ///< ours: prune between near coast cells too
  std::vector<RiverLandSlope> slopes;
  double noiseAmplitude = 0.0; ///< fractal overlay, metres
  double noiseFeature = 64.0;  ///< its largest wavelength, cells
  double seaDepth = 10.0;      ///< metres below sea level of sea cells
  int threads = 1;             ///< for the per-cell passes (results do not depend on it)
};

/// Cell classes.
enum RiverLandClass : std::uint8_t
{
  RiverLandSea = 0,
  RiverLandLand = 1,
  RiverLandCoast = 2,
  RiverLandRiver = 3
};

/// One river or tributary: its cells from its mouth (or junction) upstream.
struct RiverLandRiverPath
{
  int parent = -1;        ///< river it joins, -1 for a main river
  int junction = -1;      ///< the parent's cell it joins at (downstream of cells[0])
  int level = 0;          ///< 0 main river, 1 tributary, ...
  std::vector<int> cells; ///< cell indices, 4-connected, downstream first
};

/// The result (rasters width x height, row-major, row j = 0 south).
struct RiverLand
{
  std::vector<std::uint8_t> cls;    ///< RiverLandClass
  std::vector<int> riverId;         ///< river of a river cell, -1 elsewhere
  std::vector<float> heightMeters;  ///< Elevation, m
  std::vector<double> distance;     ///< Jensen's d, cells (0 on rivers and coast, -1 sea)
  std::vector<int> source;          ///< river or coast cell each cell points back to (-1 sea)
  std::vector<int> parent;          ///< the neighbour that sent it (-1 for sources and sea)
  std::vector<std::uint8_t> medial; ///< 1 medial, 2 pruned (was medial), 0 otherwise
  std::vector<int> target;          ///< the medial cell a land cell's path ends at (-1)
  std::vector<float> slopeWeight;   ///< total user-slope weight sum w_s (0 without slopes)
  std::vector<RiverLandRiverPath> rivers;
  std::vector<double> riverHeight;       ///< per cell: river bed height, m (rivers only, else 0)
  int medialBefore = 0, medialAfter = 0; ///< medial cells before and after pruning
  int slopesApplied = 0;                 ///< user slopes whose cell was plain land
  double pruneSeconds = 0.0;             ///< time of the pruning step
};

/// f(t) of a profile, t clamped to [0, 1]. Custom uses curveX/curveY (linear between).
double SlopeProfileValue(SlopeProfile profile,
  double t,
  const std::vector<double>& curveX = {},
  const std::vector<double>& curveY = {});

/// Jensen's blending (2.4.2 for one slope, 2.4.3 for more): heights and influence fractions
/// (influence / maximum) of the user slopes at a cell, and the linear height.
double BlendSlopeHeights(double linearHeight,
  const std::vector<double>& slopeHeights,
  const std::vector<double>& influenceFractions);

/// Profile name <-> enum: "linear", "cos", "cos2", "gauss", "custom".
bool ParseSlopeProfile(const std::string& name, SlopeProfile& out);
const char* SlopeProfileName(SlopeProfile profile);

/// Fills `p` from a JSON object's keys (see the documentation; unknown keys are an error).
/// False with a one-line `error` naming the key.
bool RiverLandParametersFromJson(const std::string& text,
  RiverLandParameters& p,
  std::string& error);

/// Checks ranges; false with `error`.
bool ValidateRiverLandParameters(const RiverLandParameters& p, std::string& error);

/// The whole generator. False with `error` for bad parameters.
bool GenerateRiverLand(const RiverLandParameters& p, RiverLand& out, std::string& error);

/**
 * @brief Steps 4 to 7 alone, on a given map (for tests and other river sources).
 * @param cls per cell RiverLandClass (rivers and coast are the sources)
 * @param riverHeight per cell, the river bed height (m) of river cells
 * @param riverDown per cell, the next river cell downstream (-1 at a mouth and elsewhere)
 * @param riverDepth per cell, cells along the network from its mouth (river cells)
 */
bool ShapeRiverLand(const RiverLandParameters& p,
  const std::vector<std::uint8_t>& cls,
  const std::vector<double>& riverHeight,
  const std::vector<int>& riverDown,
  const std::vector<int>& riverDepth,
  RiverLand& out,
  std::string& error);

} // namespace generation
} // namespace terroir

#endif

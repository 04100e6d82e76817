/**
 * @file FeatureCurves.h
 * @brief Weiss (2015)'s feature curves and diffusion solver (his section V, eq. 5-9, after
 * Hnaidi et al. 2010), no VTK: curves of control points with an elevation, a plateau and a
 * slope on each side, interpolated with cubic Hermite splines; their constraints rasterised on
 * a grid; the terrain that satisfies them solved by multigrid V-cycles.
 *
 * The curves. A control point has a position (x, y, metres, in the grid's world frame), an
 * elevation (m; with `constrainElevation` false its plateau is left free), a plateau of
 * `plateauWidth` metres across (half on each side of the curve), and on each side a slope of
 * `slope{Left,Right}Width` metres at `slope{Left,Right}Angle` degrees (positive: the ground
 * falls away from the curve, a ridge; negative: it rises, a valley), then a smoothing
 * envelope of `envelope{Left,Right}` metres beyond the slope (Weiss's l_l, l_r; negative:
 * unbounded). Left is the side to the left of the direction of travel. Between control points
 * the position and elevation (Weiss's (x, y, z)) follow a cubic Hermite spline with
 * Catmull-Rom tangents, quadratic on the first and last segments (the tangent at an end point
 * is the one that makes the end segment a parabola); a two-point curve is a straight line.
 * The other values are interpolated linearly (his section V-A).
 *
 * The constraints (eq. 5-9). Every grid point takes the constraints of the nearest point of
 * the nearest curve whose plateau or slope contains it (distance to the sampled spline, so the
 * ends are rounded): on the plateau alpha = plateauWeight (0.9), E = elevation; on a slope
 * beta = slopeWeight (0.5) with the unit direction n pointing away from the curve and the
 * per-step height change G; elsewhere alpha = beta = 0. gamma = 1 inside the union of the
 * curves' envelopes (everywhere when an envelope is unbounded), 0 outside. The iteration of
 * eq. 9 is
 *   H = alpha E + beta (N + G) + gamma (1 - alpha - beta) L + (1 - gamma)(1 - alpha - beta) B,
 * where N = nx^2 H[i - sign nx, j] + ny^2 H[i, j - sign ny] (eq. 7), L the mean of the four
 * neighbours (eq. 8) and B the base terrain (0 without one). The last term is ours: eq. 9 read
 * literally sets H to 0 outside the envelope, while Weiss's intent is that the terrain there
 * is kept; with it, cells outside the envelope keep the base. G: Weiss says only that it comes
 * from sin(phi); we take G = -tan(phi) (|nx|^3 dx + |ny|^3 dy), the value that makes eq. 6-7
 * hold exactly for a plane of slope angle phi falling along n, so the slopes come out at the
 * prescribed angle. Grid edges mirror (zero normal derivative).
 *
 * The solver. The fixed point of eq. 9 is the linear system
 *   H - sum_k c_k H_k = b  (a 5-point stencil, diagonal 1, c_k >= 0, sum c_k <= 1),
 * solved by geometric multigrid: V(2,2) cycles with red-black Gauss-Seidel smoothing,
 * full-weighting restriction and bilinear prolongation, on levels made by halving the grid
 * (coarse point I is fine point 2I) down to at most 8 points a side, where 200 red-black sweeps
 * solve the coarsest system. The coarse operators re-discretise the fine one's terms: the
 * identity weight a = alpha + (1 - gamma)(1 - alpha - beta), the four directional gradient
 * weights (summing to beta) and the Laplace weight w = gamma (1 - alpha - beta) are averaged
 * by full weighting, and on level l (cells 2^l wider) the stencil is d = a + beta / 2^l +
 * w / 4^l, c_k = g_k / 2^l + w / (4 * 4^l), so that every level approximates the same
 * continuous operator in the fine rows' units. Cycles stop when one changes no height by more
 * than `tolerance` metres (measured: each cycle cuts the error about fivefold).
 *
 * Arithmetic: stencils in float32, heights, right-hand sides and residuals in float64 (in
 * float32 the rounding of the fine residual, amplified by the coarse corrections, left
 * heights wandering by millimetres per cycle at 129 points and more on larger grids); every
 * operation in a fixed order with no fused multiply-add and no division (the stencils keep
 * 1 / d), so the GPU kernels (Shaders/FeatureCurve*.comp) can do the same operations; the row
 * kernels touch rows independently within a colour, so any number of threads gives the same
 * bits.
 *
 * References: S. Weiss, "Procedural Terrain", CS6491 final project, Georgia Tech, 2015,
 * section V; H. Hnaidi, E. Guerin, S. Akkouche, A. Peytavie, E. Galin, "Feature based terrain
 * generation using diffusion equation", Computer Graphics Forum 29(7), 2010;
 * W. L. Briggs, V. E. Henson, S. F. McCormick, "A Multigrid Tutorial", 2nd ed., SIAM, 2000.
 *
 * @correctness Testing/Unit/TestFeatureCurves.cxx: Hermite values and tangents; the 1-D
 * Laplace problem (a straight line); a straight ridge with hard plateau constraints against
 * its closed-form profile; multigrid against plain Jacobi; residual below tolerance; the
 * envelope keeping the base; the same bits on 1 and 2 threads.
 */
#ifndef terroir_terrain_FeatureCurves_h
#define terroir_terrain_FeatureCurves_h

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace terroir
{
namespace terrain
{

/// A control point of a feature curve (see the file comment for meanings and units).
struct FeatureControlPoint
{
  double x = 0.0;                 ///< m, world
  double y = 0.0;                 ///< m, world
  double elevation = 0.0;         ///< m
  bool constrainElevation = true; ///< plateau held at `elevation`
  double plateauWidth = 0.0;      ///< m, across the curve (half on each side)
  double slopeLeftWidth = 0.0;    ///< m
  double slopeRightWidth = 0.0;   ///< m
  double slopeLeftAngle = 0.0;    ///< degrees, > 0 falls away from the curve
  double slopeRightAngle = 0.0;   ///< degrees
  double envelopeLeft = -1.0;     ///< m beyond the slope; < 0 unbounded
  double envelopeRight = -1.0;    ///< m beyond the slope; < 0 unbounded
};

/// A feature curve: two or more control points.
using FeatureCurve = std::vector<FeatureControlPoint>;

/// The grid: nx x ny points, point (i, j) at (x0 + i dx, y0 + j dy), row j = 0 first.
struct FeatureGrid
{
  int nx = 0;
  int ny = 0;
  double dx = 1.0;
  double dy = 1.0;
  double x0 = 0.0;
  double y0 = 0.0;
};

/// Weights and solver settings; defaults are Weiss's where he gives them.
struct FeatureSolverParameters
{
  double plateauWeight = 0.9; ///< alpha on plateaus (Weiss: 0.9), (0, 1]
  double slopeWeight = 0.5;   ///< beta on slopes (Weiss: 0.5), [0, 1]
  double tolerance = 1e-3;    ///< stop when a V-cycle changes no height by more, m
  int maxCycles = 100;        ///< V-cycles at most
  int preSmooth = 2;          ///< red-black sweeps before the coarse correction
  int postSmooth = 2;         ///< and after
  int coarsestSize = 8;       ///< stop halving at this many points a side
  int coarsestSweeps = 200;   ///< red-black sweeps on the coarsest level
};

/// The cubic Hermite position (x, y, elevation) of segment `s` (between control points s and
/// s + 1) at t in [0, 1], and its derivative with respect to t.
void FeatureCurveHermite(const FeatureCurve& curve, int s, double t, double p[3], double dp[3]);

/// The tangent (d/dt of (x, y, elevation)) the spline uses at control point k.
void FeatureCurveTangent(const FeatureCurve& curve, int k, double m[3]);

/// Points along the spline, at most `step` metres apart (chord), from the first control point
/// to the last; x, y and elevation from the Hermite spline, the other values linear in t.
std::vector<FeatureControlPoint> SampleFeatureCurve(const FeatureCurve& curve, double step);

/// Points along the spline from the first control point to the last, the pieces halved (at
/// least three times per control segment) until the spline's midpoint is within `flatness`
/// metres of the chord's and the chord is at most `maxStep` metres; values as above. The
/// rasteriser uses it with a twentieth of a cell.
std::vector<FeatureControlPoint> SampleFeatureCurveFlat(const FeatureCurve& curve,
  double flatness,
  double maxStep);

/// The constraints of eq. 5-9 on a grid (row-major, n = nx ny).
struct FeatureConstraints
{
  std::vector<float> alpha;       ///< elevation weight
  std::vector<float> beta;        ///< gradient weight
  std::vector<float> gamma;       ///< 1 inside the smoothing envelope
  std::vector<float> elevation;   ///< E, m
  std::vector<float> gradient;    ///< G, m per step along n
  std::vector<float> dirX;        ///< n_x (0 off the slopes)
  std::vector<float> dirY;        ///< n_y
  std::vector<std::uint8_t> kind; ///< 0 free, 1 plateau, 2 slope
};

/// Rasterises the curves' constraints (serial, deterministic). False with `error` for a curve
/// with fewer than two points, a non-finite value, negative widths or |angle| >= 90 degrees.
bool RasterizeFeatureCurves(const std::vector<FeatureCurve>& curves,
  const FeatureGrid& grid,
  const FeatureSolverParameters& params,
  FeatureConstraints& out,
  std::string& error);

/// One level of the multigrid hierarchy: the stencil H - sum c_k H_k = b as six float arrays
/// of n = nx ny values, `coef` = [d | 1/d | cW | cE | cS | cN] (W: i - 1, E: i + 1, S: j - 1,
/// N: j + 1), and the level's solution, right-hand side and residual.
struct DiffusionLevel
{
  int nx = 0;
  int ny = 0;
  std::vector<float> coef; ///< 6 n
  std::vector<double> h;   ///< n
  std::vector<double> b;   ///< n
  std::vector<double> r;   ///< n
  std::size_t Size() const { return static_cast<std::size_t>(this->nx) * this->ny; }
};

/// The levels of the solver, finest first, with `b` of level 0 and the first guess `h` of
/// level 0 set: h = E on elevation constraints, the base elsewhere. `base` (n values, m) may be
/// null (0 everywhere).
std::vector<DiffusionLevel> BuildDiffusionLevels(const FeatureConstraints& c,
  int nx,
  int ny,
  const float* base,
  const FeatureSolverParameters& params);

/// Runs `body(row0, row1)` over [0, rows) (the wrapper passes vtkSMPTools; the default runs
/// serially). The kernels below give the same bits whatever the split.
using RowParallel = std::function<void(int rows, const std::function<void(int, int)>& body)>;

/// Coarse size of a fine size: the fine points 0, 2, 4, ...
inline int CoarseSize(int n)
{
  return (n - 1) / 2 + 1;
}

///@{
/// The row kernels (the GPU kernels mirror them operation for operation):
/// one colour of a red-black Gauss-Seidel sweep (cells with (i + j) % 2 == colour):
/// h = (b + cW hW + cE hE + cS hS + cN hN) / d, neighbours mirrored at the edges;
void DiffusionSmoothRows(DiffusionLevel& l, int colour, int row0, int row1);
/// the residual r = b - (d h - sum c_k h_k); returns the largest |r| of the rows;
double DiffusionResidualRows(DiffusionLevel& l, int row0, int row1);
/// the coarse right-hand side by full weighting of the fine residual (weights 1/4, 1/8, 1/16,
/// mirrored at the edges), and h = 0 on the coarse rows;
void DiffusionRestrictRows(const DiffusionLevel& fine, DiffusionLevel& coarse, int row0, int row1);
/// the fine h plus the bilinear interpolation of the coarse h;
void DiffusionProlongRows(const DiffusionLevel& coarse, DiffusionLevel& fine, int row0, int row1);
/// the largest |h - previous| of the rows, then previous = h (the stop test).
double DiffusionChangeRows(const DiffusionLevel& l, double* previous, int row0, int row1);
///@}

/// What a solve did.
struct DiffusionReport
{
  int levels = 0;
  int cycles = 0;
  double initialResidual = 0.0;
  double residual = 0.0; ///< largest fine residual |b - A H| at the end, m
  bool converged = false;
  std::vector<double> history; ///< largest change of a height in each cycle, m
};

/// V-cycles on `levels` (from BuildDiffusionLevels) until a cycle changes no height by more
/// than the tolerance (the cycles reduce the error about fivefold each, so the error left is
/// then about a quarter of the tolerance) or maxCycles have run. levels[0].h is the answer.
DiffusionReport SolveDiffusionMultigrid(std::vector<DiffusionLevel>& levels,
  const FeatureSolverParameters& params,
  const RowParallel& parallel = RowParallel());

/// The reference: plain Jacobi iterations of eq. 9 (h' = (b + sum c_k h_k) / d, all cells
/// from the previous h), in double, on level 0 until the largest change of an iteration is at most
/// `change` or `maxIterations` have run; returns the iterations.
int SolveDiffusionJacobi(DiffusionLevel& fine, double change, int maxIterations);

/// Everything at once: constraints, levels, V-cycles. `heights` gets nx ny values (m).
bool FeatureCurveTerrain(const std::vector<FeatureCurve>& curves,
  const FeatureGrid& grid,
  const float* base,
  const FeatureSolverParameters& params,
  std::vector<float>& heights,
  DiffusionReport& report,
  std::string& error,
  const RowParallel& parallel = RowParallel());

} // namespace terrain
} // namespace terroir

#endif

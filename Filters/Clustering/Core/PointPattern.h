/**
 * @file PointPattern.h
 * @brief Multi-type point patterns (plant positions by species): their pair-correlation
 *        functions, a radial-distribution model learned from an exemplar, and the synthesis of
 *        new patterns with the same statistics by Metropolis-Hastings birth, death and move.
 *        The core of "plants from zones" (issue 27). Plain C++: no VTK, no GL.
 *
 * Long (2016, section 2.2.2.1, "Radial distribution analysis") describes the method after
 * Emilien et al. (2015), Lane & Prusinkiewicz (2002) and Hurtut et al. (2009):
 *   - analysis: for every pair of categories (A, B) a histogram of the A-B point distances between
 *     R_min and R_max in bins, each bin divided by the area of its annulus and by the densities,
 *     so that it measures how much denser B is at distance r from an A point than on average:
 *     the pair-correlation function g_AB(r) of point-process statistics (Illian et al. 2008,
 *     section 4.3); EstimatePairCorrelation, LearnRadialDistribution;
 *   - reproduction: birth-and-death perturbations of a pattern accepted with probability
 *     min(1, R), R = f(X') / f(X) (times the proposal ratio), f the probability density of a
 *     pairwise-interaction (Gibbs) process built from the histograms; SynthesizePattern.
 *
 * Units: coordinates and distances in metres, densities in points per square metre, g
 * dimensionless (1 for complete spatial randomness, 0 where pairs never occur, > 1 where they
 * cluster).
 *
 * References:
 * - H. Long, "Using procedural methods to generate realistic virtual rural worlds", MSc minor
 *   dissertation (Computer Science), supervised by J. Gain and M.-P. Cani, February 2016,
 *   section 2.2.2.1.
 * - A. Emilien, U. Vimont, M.-P. Cani, P. Poulin, B. Benes, "WorldBrush: interactive
 *   example-based synthesis of procedural virtual worlds", ACM TOG 34(4), 2015,
 *   doi:10.1145/2766975.
 * - T. Hurtut, P.-E. Landes, J. Thollot, Y. Gousseau, R. Drouilhet, J.-F. Coeurjolly,
 *   "Appearance-guided synthesis of element arrangements by example", NPAR 2009, pp. 51-60,
 *   doi:10.1145/1572614.1572623.
 * - B. Lane, P. Prusinkiewicz, "Generating spatial distributions for multilevel models of plant
 *   communities", Graphics Interface 2002.
 * - J. Ohser, D. Stoyan, "On the second-order and orientation analysis of planar stationary
 *   point processes", Biometrical Journal 23(6), 1981 (the translation edge correction).
 * - C. J. Geyer, J. Moller, "Simulation procedures and likelihood inference for spatial point
 *   processes", Scandinavian Journal of Statistics 21(4), 1994 (birth-death Metropolis-Hastings).
 * - J. Illian, A. Penttinen, H. Stoyan, D. Stoyan, "Statistical analysis and modelling of
 *   spatial point patterns", Wiley 2008.
 */
#ifndef terroir_clustering_PointPattern_h
#define terroir_clustering_PointPattern_h

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace terroir
{
namespace clustering
{

/// Largest number of categories (species) in one pattern.
constexpr int PatternMaxCategories = 64;

/// Largest number of distance bins.
constexpr int PatternMaxBins = 4096;

/// One point of a pattern: position (metres) and category (species, 0..categories-1).
struct PatternPoint
{
  double x = 0.0;
  double y = 0.0;
  int category = 0;
};

/**
 * @brief Where points may lie: a rectangle, or the allowed cells of a grid (one ecological
 *        zone's cells).
 *
 * Cells domain: cell (i, j), i = 0..nx-1, j = 0..ny-1, covers
 * [x0 + i dx, x0 + (i+1) dx) x [y0 + j dy, y0 + (j+1) dy) and is allowed when
 * allowed[j * nx + i] != 0. For a VTK point-data array (ClusterId) on an image with origin o and
 * spacing s, each grid point stands for the cell around it: x0 = o_x - s_x / 2,
 * y0 = o_y - s_y / 2.
 */
class PatternDomain
{
public:
  /// The rectangle [xMin, xMax) x [yMin, yMax). @throws std::invalid_argument unless
  /// xMin < xMax, yMin < yMax, all finite.
  static PatternDomain Rectangle(double xMin, double yMin, double xMax, double yMax);

  /// The allowed cells of a grid (see the class comment); the mask is copied.
  /// @throws std::invalid_argument on nx or ny < 1, dx or dy <= 0, a non-finite origin,
  ///         allowed.size() != nx * ny, or no allowed cell.
  static PatternDomain Cells(int nx,
    int ny,
    double dx,
    double dy,
    double x0,
    double y0,
    std::vector<std::uint8_t> allowed);

  /// Cells domain of the cells of `labels` (nx * ny, row-major) equal to `label`: one zone of a
  /// ClusterId grid. @throws std::invalid_argument as Cells (no cell with that label included).
  static PatternDomain CellsWithLabel(int nx,
    int ny,
    double dx,
    double dy,
    double x0,
    double y0,
    const int* labels,
    int label);

  bool IsRectangle() const { return this->Allowed.empty(); }
  /// Area of the domain, m^2 (allowed cells times dx dy for a cells domain).
  double Area() const { return this->AreaValue; }
  /// True when (x, y) lies in the domain.
  bool Contains(double x, double y) const;
  /// Bounding rectangle: xMin, yMin, xMax, yMax.
  const double* Bounds() const { return this->Box; }

  int GridNx() const { return this->Nx; }
  int GridNy() const { return this->Ny; }
  double GridDx() const { return this->Dx; }
  double GridDy() const { return this->Dy; }
  /// Allowed flags of a cells domain (empty for a rectangle).
  const std::vector<std::uint8_t>& AllowedCells() const { return this->Allowed; }
  /// Indices j * nx + i of the allowed cells, in increasing order (empty for a rectangle).
  const std::vector<std::uint32_t>& AllowedCellList() const { return this->CellList; }

private:
  double Box[4] = { 0.0, 0.0, 0.0, 0.0 };
  double AreaValue = 0.0;
  int Nx = 0;
  int Ny = 0;
  double Dx = 0.0;
  double Dy = 0.0;
  std::vector<std::uint8_t> Allowed;
  std::vector<std::uint32_t> CellList;
};

/**
 * @brief The set covariance gamma_D(h) = |D intersect (D + h)| (m^2) of a domain for lags
 *        |h_x|, |h_y| <= maxLag, and its integral over annuli: the edge-correction terms.
 *
 * Rectangle a x b: gamma(h) = (a - |h_x|)+ (b - |h_y|)+. Cells domain: gamma(h) is the sum, over
 * pairs of allowed cells, of the overlap of one cell with the other shifted by h, i.e.
 * dx dy times the bilinear interpolation of c(p, q) = #{allowed cells (i, j) with (i+p, j+q)
 * allowed} at (h_x / dx, h_y / dy) (exact: two cells' overlap is a product of hat functions).
 * Building the table costs O(allowed cells * (2 maxLag/dx + 1) (2 maxLag/dy + 1)).
 * @correctness TestPointPattern.cxx: RectangleSetCovarianceAndPairMeasureMatchClosedForms,
 *   FullMaskHasTheRectanglesCovariance, SeparateCellsCovariance.
 */
class PatternSetCovariance
{
public:
  /// @throws std::invalid_argument when maxLag is negative or not finite.
  PatternSetCovariance(const PatternDomain& domain, double maxLag);

  /// gamma_D(hx, hy), m^2. For a cells domain, lags more than one cell beyond maxLag are outside
  /// the table and give 0.
  double operator()(double hx, double hy) const;

  /**
   * The pair measure Gamma(r1, r2) = integral over r1 <= |h| < r2 of gamma_D(h) dh (m^4): the
   * measure of the pairs (x, y) in D x D with r1 <= |x - y| < r2. A process with intensities
   * lambda_A, lambda_B and pair correlation g (constant on [r1, r2)) has on average
   * lambda_A lambda_B g Gamma ordered A-B pairs at those distances in D. Computed by quadrature:
   * 4-point Gauss-Legendre in r on sub-intervals no longer than a quarter cell, and the midpoint
   * rule on M >= 1024 angles (exact to ~1e-7 relative for a rectangle: the angular integrand
   * is piecewise smooth with its kinks on the grid of the rule). Needs 0 <= r1 <= r2 <= maxLag.
   */
  double PairMeasure(double r1, double r2) const;

private:
  PatternDomain Domain;
  double MaxLag = 0.0;
  int Px = 0;
  int Py = 0;
  std::vector<double> Table; ///< c(p, q), (2 Py + 1) rows of (2 Px + 1)
};

/// Parameters of the pair-correlation estimate and of the model learned from an exemplar.
struct PairCorrelationParameters
{
  /// Smallest distance analysed, m (Long's R_min). Default 0.
  double rMin = 0.0;
  /// Largest distance analysed, m (Long's R_max; also the interaction range of the synthesis).
  /// Must be > rMin.
  double rMax = 1.0;
  /// Number of bins of width (rMax - rMin) / bins (Long's bin size). Default 20, 1..4096.
  int bins = 20;
  /// Number of categories; 0 (default) = largest category in the points + 1.
  int categories = 0;
};

/**
 * @brief Pair-correlation functions g_AB(r) of a multi-type pattern, per ordered category pair,
 *        binned.
 *
 * Bin k covers [r_k, r_k+1), r_k = rMin + k w, w = (rMax - rMin) / bins, of area
 * A_k = pi (r_k+1^2 - r_k^2). The estimate is Long's h_rdf (section 2.2.2.1) with the
 * translation edge correction of Ohser & Stoyan (1981):
 *
 *   g_AB(k) = 1 / (lambda2_AB A_k) * sum_{a in A} sum_{b in B, b != a, r_k <= |b - a| < r_k+1}
 *             1 / gamma_D(b - a),
 *
 *   lambda2_AB = n_A n_B / |D|^2 (A != B),  n_A (n_A - 1) / |D|^2 (A = B),
 *
 * gamma_D the set covariance of the domain (PatternSetCovariance): a pair at lag h is seen in D
 * with probability gamma_D(h) / |D| under translation, so weighting it by |D| / gamma_D(h)
 * undoes the pairs lost across the edge. Without the correction (gamma_D = |D|) this is
 * exactly Long's formula. For n uniform independent points (binomial process) the estimate is
 * unbiased: E[g(k)] = 1 in every bin. g_AB = g_BA. A pair with no information (n_A = 0, or
 * n_A < 2 for A = B) gets g = 1 and zero counts.
 */
struct PairCorrelation
{
  int categories = 0;
  int bins = 0;
  double rMin = 0.0;
  double rMax = 0.0;
  /// Domain area, m^2.
  double area = 0.0;
  /// Points per category.
  std::vector<std::int64_t> counts;
  /// g, index (a * categories + b) * bins + k.
  std::vector<double> g;
  /// Ordered a-b point pairs per bin (each unordered same-category pair counted twice), same
  /// index: the counts behind g (their square roots give g's statistical error).
  std::vector<std::int64_t> pairs;

  double G(int a, int b, int k) const { return g[Index(a, b, k)]; }
  std::int64_t Pairs(int a, int b, int k) const { return pairs[Index(a, b, k)]; }
  double BinWidth() const { return (rMax - rMin) / bins; }
  /// Lower edge r_k of bin k, m.
  double BinLower(int k) const { return rMin + k * BinWidth(); }
  std::size_t Index(int a, int b, int k) const
  {
    return (static_cast<std::size_t>(a) * categories + b) * bins + k;
  }
};

/**
 * @brief Estimates the pair-correlation functions of a pattern (see PairCorrelation).
 *
 * Cost O(n + pairs closer than rMax) with a uniform grid of buckets of side >= rMax.
 * @correctness TestPointPattern.cxx: PairCorrelationOfPoissonIsOne (and OnMask),
 *   PairCorrelationOfHardCoreIsZeroBelowD0, PairCorrelationOfLatticePeaksAtLatticeDistances
 *   (exact values by hand), PairCorrelationOfTwoIndependentCategoriesIsOne.
 * @param points the pattern; every point must lie in `domain`
 * @throws std::invalid_argument on rMin < 0, rMax <= rMin, bins outside 1..4096, categories
 *         outside 0..64, a point with a negative or too large category, a non-finite point or
 *         one outside the domain
 */
PairCorrelation EstimatePairCorrelation(const std::vector<PatternPoint>& points,
  const PatternDomain& domain,
  const PairCorrelationParameters& parameters);

/**
 * @brief What is learned from an exemplar pattern: the input of SynthesizePattern.
 *
 * A model can also be written by hand (densities, g, hard cores); SynthesizePattern checks it.
 */
struct RadialDistributionModel
{
  int categories = 0;
  int bins = 0;
  double rMin = 0.0;
  double rMax = 0.0;
  /// Points per m^2, per category.
  std::vector<double> density;
  /// g_AB per bin, index (a * categories + b) * bins + k (as PairCorrelation::g); symmetric.
  std::vector<double> g;
  /// Hard-core distances, m, index a * categories + b, symmetric: no a-b pair closer than this.
  /// 0 = none. See LearnRadialDistribution.
  std::vector<double> hardCore;

  double G(int a, int b, int k) const
  {
    return g[(static_cast<std::size_t>(a) * categories + b) * bins + k];
  }
  double HardCore(int a, int b) const
  {
    return hardCore[static_cast<std::size_t>(a) * categories + b];
  }
};

/**
 * @brief Learns a RadialDistributionModel from an exemplar: densities n_c / |D|, g_AB from
 *        EstimatePairCorrelation, and, when `learnHardCore`, the hard cores.
 *
 * The hard core h_AB is the smallest A-B distance in the exemplar (capped at rMax: rMax when no
 * pair is closer), the maximum-likelihood estimate of a hard-core distance, kept only when it
 * is evidence of one: when independent uniform points with the exemplar's counts would have
 * had at least 3 A-B pairs closer than h in its domain (n_A n_B Gamma(0, h) / |D|^2, or
 * n_A (n_A - 1) Gamma(0, h) / (2 |D|^2) for A = B; none of them happening by chance has
 * probability e^-3 = 5 %). Otherwise, as for a rare species with a handful of points, h_AB = 0
 * and only the pair-count energy keeps such pairs as rare as in the exemplar. Without
 * `learnHardCore` every h_AB is 0.
 * @throws std::invalid_argument as EstimatePairCorrelation
 */
RadialDistributionModel LearnRadialDistribution(const std::vector<PatternPoint>& exemplar,
  const PatternDomain& domain,
  const PairCorrelationParameters& parameters,
  bool learnHardCore = true);

/// Parameters of SynthesizePattern.
struct SynthesisParameters
{
  /// Seed of the std::mt19937_64 generator; the same seed gives the same points, bit for bit.
  std::uint64_t seed = 1;
  /// Perturbations (birth, death or move proposals). 0 (default) = 200 per expected point:
  /// 200 * sum_c density_c * |D| (at least 1000).
  std::int64_t iterations = 0;
  /// Probability that a perturbation is a move (the rest are births and deaths, half each).
  /// Default 0.25, in [0, 1).
  double moveProbability = 0.25;
  /// Half-side of the square in which a move displaces a point, m; 0 (default) = rMax / 2.
  double moveRadius = 0.0;
  /// kappa: weight of the pair-count energy (1 = the Gaussian approximation of the Poisson
  /// log-likelihood of the pair counts). Default 4, >= 0.
  double pairWeight = 4.0;
  /// kappa_n: weight of the point-count energy. Default 100: the point count of category c then
  /// has a standard deviation of about sqrt(mu_c / 101), and a hard core (which lowers the
  /// density a Gibbs process reaches at a given activity) leaves it ~1 % below mu_c instead of
  /// ~5 % with kappa_n = 1 (measured: Documentation/Plants.md). >= 0.
  double densityWeight = 100.0;
  /// Whether the model's hard cores are enforced (proposals that break one are rejected).
  bool useHardCore = true;
};

/// Counts of a synthesis run.
struct SynthesisStatistics
{
  std::int64_t iterations = 0;
  std::int64_t birthsProposed = 0, birthsAccepted = 0;
  std::int64_t deathsProposed = 0, deathsAccepted = 0;
  std::int64_t movesProposed = 0, movesAccepted = 0;
  /// Points looked at in the buckets around the proposals (the cost of the run): per
  /// perturbation, about 9 rMax^2 times the local density, whatever the number of points.
  std::int64_t neighboursVisited = 0;
  /// Energy E of the final pattern (see SynthesizePattern).
  double energy = 0.0;
};

/// Points and counts of a synthesis run.
struct PatternSynthesis
{
  std::vector<PatternPoint> points;
  SynthesisStatistics statistics;
};

/**
 * @brief Synthesises a pattern in `domain` that reproduces a model's densities and pair
 *        correlations: Metropolis-Hastings birth, death and move of a multi-type Gibbs process
 *        (Long 2016 section 2.2.2.1, after Hurtut et al. 2009 and Emilien et al. 2015; the
 *        birth-death ratios of Geyer & Moller 1994).
 *
 * Target density, with respect to unit-rate Poisson processes of each category on D:
 *
 *   f(X) = prod_c lambda_c^{n_c} exp(-E(X))   (0 when a hard core is broken),
 *   E(X) = kappa sum_{A <= B} sum_k (N_AB(k) - T_AB(k))^2 / (2 max(T_AB(k), 1))
 *        + kappa_n sum_c (n_c - mu_c)^2 / (2 mu_c),
 *
 * N_AB(k) the unordered A-B point pairs of X in bin k, T_AB(k) their expected number under
 * the model, lambda_A lambda_B g_AB(k) Gamma_k (A != B) or lambda_A^2 g_AA(k) Gamma_k / 2,
 * Gamma_k = PatternSetCovariance::PairMeasure over bin k of this domain (so edges are accounted
 * for), mu_c = lambda_c |D|. With kappa = kappa_n = 0 and no hard core, f is a Poisson process
 * of the model's densities.
 *
 * Each perturbation, with probabilities (1 - p_m)/2, (1 - p_m)/2, p_m:
 *   - birth of a point u of category c (c drawn with probability q_c = lambda_c / sum lambda,
 *     u uniform in D): R = lambda_c |D| exp(-dE) / (q_c (n + 1));
 *   - death of a point drawn uniformly among the n: R = q_c n exp(-dE) / (lambda_c |D|);
 *   - move of a point drawn uniformly by a displacement uniform in [-s, s]^2 (rejected when it
 *     leaves D): R = exp(-dE);
 * accepted when a uniform number in (0, 1] is <= R. dE only involves the counts of the pairs
 * that contain the perturbed point, found in a uniform grid of buckets of side >= rMax: the
 * cost of a perturbation is O(neighbours within rMax + bins), not O(n). Counts are integers,
 * so E never drifts. The run starts from the empty pattern.
 *
 * Random numbers: std::mt19937_64(seed), mapped to doubles by our own rule (the 53 high bits),
 * so results do not depend on the standard library's distributions.
 *
 * @correctness TestPointPattern.cxx: SynthesisReproducesHardCore, SynthesisReproducesClusters,
 *   SynthesisReproducesCrossInhibition, SynthesisRespectsMask,
 *   SynthesisWithoutInteractionIsPoisson, SynthesisIsDeterministic,
 *   PerturbationCostDoesNotGrowWithPoints, CategoryWithoutPointsIsNeverPlaced.
 * @throws std::invalid_argument on an inconsistent model (categories outside 1..64, bins
 *         outside 1..4096, rMin < 0, rMax <= rMin, array sizes, a negative or non-finite
 *         density, g or hard core, an asymmetric g or hard core) or parameters (iterations < 0,
 *         moveProbability outside [0, 1), moveRadius < 0, negative weights)
 */
PatternSynthesis SynthesizePattern(const RadialDistributionModel& model,
  const PatternDomain& domain,
  const SynthesisParameters& parameters = {});

/**
 * The seed of one zone's run: SplitMix64 (Steele, Lea & Flood 2014) of seed + the zone's
 * number times the golden-ratio increment, so that neighbouring zones and seeds get unrelated
 * streams and a zone's points do not depend on which other zones are synthesised.
 */
std::uint64_t PatternZoneSeed(std::uint64_t seed, int zone);

/// A model for the cells of one zone (one ClusterId value).
struct ZoneModel
{
  int zone = 0;
  RadialDistributionModel model;
};

/// The points of every zone: points[i] belongs to zones[i]; statistics per ZoneModel, in order.
struct ZonePatterns
{
  std::vector<PatternPoint> points;
  std::vector<int> zones;
  std::vector<SynthesisStatistics> statistics;
};

/// Runs body(begin, end) over disjoint ranges covering [begin, end), possibly in parallel.
/// The default (empty function) runs body(begin, end) once.
using PatternParallelFor = std::function<void(std::size_t begin,
  std::size_t end,
  const std::function<void(std::size_t, std::size_t)>& body)>;

/**
 * @brief Plants for every zone of a label grid (a ClusterId image): for each ZoneModel, the
 *        cells with its label form the domain (PatternDomain::CellsWithLabel, so points never
 *        leave their zone) and SynthesizePattern runs with `parameters` and the seed
 *        PatternZoneSeed(parameters.seed, zone).
 *
 * Zones are independent (plants of neighbouring zones do not interact across the border), so
 * they may run in parallel through `parallelFor`; the result is gathered in ZoneModel order and
 * is the same, bit for bit, for any split of the work. A zone with no cell gets no points.
 * @param labels nx * ny labels, row-major (j * nx + i); the grid as in PatternDomain::Cells
 * @throws std::invalid_argument as PatternDomain::Cells (except for a zone with no cell) and
 *         SynthesizePattern, or when a zone appears twice
 */
ZonePatterns SynthesizeZones(int nx,
  int ny,
  double dx,
  double dy,
  double x0,
  double y0,
  const int* labels,
  const std::vector<ZoneModel>& models,
  const SynthesisParameters& parameters = {},
  const PatternParallelFor& parallelFor = {});

} // namespace clustering
} // namespace terroir

#endif

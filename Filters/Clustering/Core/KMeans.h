/**
 * @file KMeans.h
 * @brief K-means clustering of per-cell feature vectors (Lloyd 1982), the core of
 *        vtkTerroirKMeans. Plain C++: no VTK, no GL.
 *
 * Data: `KMeansFeatures` is a non-owning, feature-major (structure of arrays) float matrix:
 * feature f of cell c is data[f * cells + c]. Only valid cells are in it (the wrapper packs
 * them); weights and standardisation are applied before (KMeansPrepareFeatures), so the
 * distance is the plain squared Euclidean distance over the prepared features.
 *
 * Lloyd iterations (the same steps, in the same order, as scikit-learn 1.2's
 * `_kmeans_single_lloyd`, so both give the same answer from the same initial centres):
 *   1. assignment: label(c) = argmin_k d2(c, k), d2 = sum over f = 0..F-1, in that order, of
 *      (x_fc - m_kf)^2 in float (no fused multiply-add; the core is built with
 *      -ffp-contract=off), ties to the lowest k; the minimum d2 is kept per cell;
 *   2. update: per-cluster sums of the features in double, taken block by block
 *      (KMeansBlockCells cells, in cell order inside a block), the blocks then added in block
 *      order; so the sums do not depend on the thread count, and the GPU path, which uses the
 *      same blocks, gets the same bits;
 *   3. empty clusters: relocated to the cells farthest from their centre (largest kept d2,
 *      ties to the lowest cell index), one per empty cluster in increasing cluster order; the
 *      cell is taken out of its old cluster's sums (scikit-learn's rule);
 *   4. new centres = sums / counts, rounded to float;
 *   5. stop when no label changed in step 1 (except on the first iteration), or when
 *      sum_k |m_k(new) - m_k(old)|^2 <= tolerance * mean variance of the features (the
 *      scikit-learn definition of `tol`), or after maximumIterations.
 * After a stop by tolerance or iteration count, the cells are assigned once more to the final
 * centres (scikit-learn does the same), so labels, centres and inertia always agree. The
 * inertia (within-cluster sum of squares) is the double sum of the final d2 in block order.
 *
 * The assignment and the block sums are the two heavy steps. They sit behind `KMeansEngine`,
 * implemented for the CPU here (KMeansCPUEngine, cells in parallel through a ParallelFor
 * callback) and for the GPU in Filters/Clustering (Shaders/KMeansAssign.comp,
 * KMeansPartialSums.comp); KMeansLloyd drives either.
 *
 * Seeding: KMeansDiagonalSeedCells (Long (2016)'s deterministic choice, Long (2016) ch. 4)
 * and KMeansPlusPlusSeeds (Arthur & Vassilvitskii 2007) with a fixed random seed.
 *
 * References:
 * - S. P. Lloyd, "Least squares quantization in PCM", IEEE Trans. Inf. Theory 28(2), 1982,
 *   doi:10.1109/TIT.1982.1056489.
 * - D. Arthur, S. Vassilvitskii, "k-means++: the advantages of careful seeding", SODA 2007.
 * - H. Long, "Using procedural methods to generate realistic virtual rural worlds", MSc
 *   minor dissertation (Computer Science), supervised by J. Gain and M.-P. Cani, February
 *   2016, chapter 4.
 */
#ifndef terroir_clustering_KMeans_h
#define terroir_clustering_KMeans_h

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace terroir
{
namespace clustering
{

/// Largest number of clusters (the GPU kernels keep one accumulator per cluster).
constexpr int KMeansMaxClusters = 64;

/// Cells per reduction block (CPU and GPU alike; fixes the order of every sum).
constexpr std::size_t KMeansBlockCells = 4096;

/// Non-owning feature-major matrix: feature f of cell c is data[f * cells + c].
struct KMeansFeatures
{
  const float* data = nullptr;
  std::size_t cells = 0;
  int features = 0;

  float At(int f, std::size_t c) const { return data[static_cast<std::size_t>(f) * cells + c]; }
  std::size_t Blocks() const { return (cells + KMeansBlockCells - 1) / KMeansBlockCells; }
};

/// Runs body(begin, end) over disjoint ranges covering [begin, end), possibly in parallel.
/// The default (empty function) runs body(begin, end) once.
using KMeansParallelFor = std::function<void(std::size_t begin,
  std::size_t end,
  const std::function<void(std::size_t, std::size_t)>& body)>;

/**
 * All-reduce over the processes of a distributed run: each call replaces `values` (n of them)
 * on every process by their sum, maximum or minimum over all processes, the same on all. The
 * VTK layer implements it with vtkMultiProcessController (vtkTerroirKMeans); the core never
 * sees MPI. Every process must make the same calls in the same order. A null reduction (the
 * default everywhere) is a serial run.
 */
class KMeansReduction
{
public:
  virtual ~KMeansReduction() = default;
  virtual void Sum(double* values, std::size_t n) = 0;
  virtual void Sum(std::int64_t* values, std::size_t n) = 0;
  virtual void Max(double* values, std::size_t n) = 0;
  virtual void Min(double* values, std::size_t n) = 0;
  virtual void Min(std::int64_t* values, std::size_t n) = 0;
};

/// One input column before preparation: `components` interleaved values per cell (VTK's
/// layout), a weight, and its name (for reports).
struct KMeansInputArray
{
  std::string name;
  const float* values = nullptr; ///< cells * components values, cell-major
  int components = 1;
  double weight = 1.0;
};

/// What KMeansPrepareFeatures did with one input array.
struct KMeansPreparedArray
{
  std::string name;
  int components = 1;
  /// First prepared feature of this array.
  int firstFeature = 0;
  /// Prepared features of this array: `components`, or 1 when collapsed, 0 when weight is 0.
  int features = 0;
  /// True when every component differed from component 0 by one constant per component over all
  /// cells (Long (2016)'s storage trick), so the array became a single feature.
  bool collapsed = false;
  std::vector<double> mean;   ///< per component, over the packed cells (double, block order)
  std::vector<double> stddev; ///< per component (population), 0 when constant
};

/**
 * @brief Builds the prepared feature matrix from packed input arrays.
 *
 * For each array with weight w > 0 and each component j: x' = sqrt(w) * x, or, when
 * `standardize`, sqrt(w) * (x - mean_j) / stddev_j (a constant component, stddev 0, becomes 0).
 * So the squared distance is sum_f w_f (x_f - m_f)^2 on the raw or z-scored values. A weight of
 * 0 drops the array.
 *
 * Storage trick (Long (2016)'s, for Temperature): when for every component j there is a constant
 * c_j with x_j(c) - x_0(c) == c_j for all cells, up to float rounding of the stored values
 * (|x_j - x_0 - c_j| <= 4 ulp of max(|x_j|, |x_0|)), the array's components carry the same
 * distances as component 0 counted `components` times: it is stored as one feature scaled by
 * sqrt(w * components) (after standardisation: z_j == z_0 for every j). Arrays with one
 * component are never collapsed. `allowCollapse` = false turns the trick off.
 *
 * With a `reduction` (a distributed run, each process holding some of the cells) the means,
 * standard deviations and collapse test are those of all the processes' cells: block sums are
 * added over the processes (so the last bits of the means may differ from a serial run's, whose
 * blocks span the whole grid), the collapse intervals are intersected over them (the same
 * verdict as a serial run).
 *
 * @param cells number of packed (valid) cells
 * @param out filled with the feature-major matrix (features * cells floats)
 * @return one entry per input array, in order
 * @throws std::invalid_argument on a null array, components < 1, a negative or non-finite
 *         weight, a non-finite value, or when every weight is 0
 */
std::vector<KMeansPreparedArray> KMeansPrepareFeatures(const std::vector<KMeansInputArray>& arrays,
  std::size_t cells,
  bool standardize,
  bool allowCollapse,
  std::vector<float>& out,
  const KMeansParallelFor& parallelFor = {},
  KMeansReduction* reduction = nullptr);

/**
 * @brief The prepared features of more cells with the statistics and collapse verdicts of an
 *        earlier KMeansPrepareFeatures (`prepared`, for arrays with the same names, components
 *        and weights), with the same arithmetic: a cell gets the bits it would have got had it
 *        been one of the cells prepared then. For cells that take no part in the statistics,
 *        such as the boundary points a piece of a distributed run shares with its neighbour.
 * @param out filled with the feature-major matrix (features * cells floats)
 */
void KMeansApplyPreparation(const std::vector<KMeansInputArray>& arrays,
  const std::vector<KMeansPreparedArray>& prepared,
  std::size_t cells,
  bool standardize,
  std::vector<float>& out);

/**
 * @brief Long (2016)'s deterministic seeds: K valid cells equally spaced along the diagonal from
 *        cell (0, 0) to (nx - 1, ny - 1).
 *
 * The diagonal is the L = max(nx, ny) cells (round(t (nx-1)/(L-1)), round(t (ny-1)/(L-1))),
 * t = 0..L-1 (one cell when L = 1), rounding halves up. Of its M valid cells (valid == null: all),
 * seed i (i = 0..K-1) is the one at position floor((2i + 1) M / (2K)). When M < K the same rule
 * runs over all valid cells in row order instead.
 * @return K grid indices j * nx + i
 * @throws std::invalid_argument when k < 1 or there are fewer than k valid cells
 */
std::vector<std::size_t> KMeansDiagonalSeedCells(int nx, int ny, const std::uint8_t* valid, int k);

/// The L = max(nx, ny) cells of KMeansDiagonalSeedCells' diagonal, t = 0..L-1, as grid indices
/// j * nx + i (one cell when L = 1).
std::vector<std::size_t> KMeansDiagonalCells(int nx, int ny);

/**
 * Positions, among `m` valid diagonal cells, of KMeansDiagonalSeedCells' K seeds:
 * floor((2i + 1) m / (2K)), i = 0..K-1 (the rule a distributed run applies to the diagonal's
 * validity gathered from every process). Needs m >= k >= 1.
 */
std::vector<std::size_t> KMeansDiagonalSeedPositions(std::size_t m, int k);

/**
 * @brief k-means++ seeds (Arthur & Vassilvitskii 2007), reproducible.
 *
 * Random numbers: std::mt19937_64 seeded with `seed`; u = (draw >> 11) * 2^-53 in [0, 1) (our
 * own mapping: std:: distributions differ between standard libraries). First centre: cell
 * floor(u * cells). Each next centre: the first cell whose running sum of D2 (squared distance
 * to the nearest centre chosen so far, float as in the assignment, summed in double in cell
 * order) exceeds u * total; when total is 0 (all remaining cells sit on centres), the first
 * cell not yet chosen.
 * @return K packed cell indices (into `features`)
 * @throws std::invalid_argument when k < 1 or k > features.cells
 */
std::vector<std::size_t> KMeansPlusPlusSeeds(const KMeansFeatures& features,
  int k,
  std::uint64_t seed,
  const KMeansParallelFor& parallelFor = {});

/// Centres (k * F floats, row k) at the given packed cells.
std::vector<float> KMeansCentresFromCells(const KMeansFeatures& features,
  const std::vector<std::size_t>& cells);

/**
 * @brief Assigns cells [begin, end) to their nearest centre (step 1 above).
 * @param centres k * F floats, row-major
 * @param labels in: previous labels (any value, e.g. -1); out: new labels
 * @param distance out: the minimum d2 per cell
 * @return the number of cells whose label changed
 */
std::size_t KMeansAssignRange(const KMeansFeatures& features,
  const float* centres,
  int k,
  std::size_t begin,
  std::size_t end,
  std::int32_t* labels,
  float* distance);

/**
 * @brief Sums of block `block` (step 2): sums[kk * F + f] += x_f over its cells labelled kk,
 *        counts[kk] += 1, inertia += d2; in cell order, in double. The outputs are zeroed first.
 */
void KMeansBlockSums(const KMeansFeatures& features,
  const std::int32_t* labels,
  const float* distance,
  int k,
  std::size_t block,
  double* sums,
  std::int64_t* counts,
  double* inertia);

/// The heavy steps of an iteration, on some device. Labels and distances live in the engine.
class KMeansEngine
{
public:
  virtual ~KMeansEngine() = default;
  /// Step 1 for every cell with `centres` (k * F floats); returns how many labels changed.
  virtual std::size_t Assign(const std::vector<float>& centres, int k) = 0;
  /**
   * Step 2 for every cell with the current labels: sums (k * F), counts (k) and the inertia,
   * each the block-order total of KMeansBlockSums.
   */
  virtual void Sums(int k,
    std::vector<double>& sums,
    std::vector<std::int64_t>& counts,
    double& inertia) = 0;
  /// The current labels and kept d2 on the host (cells entries each); may copy from a device.
  virtual const std::int32_t* Labels() = 0;
  virtual const float* Distances() = 0;
};

/// KMeansEngine on the CPU: blocks of cells through `parallelFor`.
class KMeansCPUEngine : public KMeansEngine
{
public:
  explicit KMeansCPUEngine(const KMeansFeatures& features, KMeansParallelFor parallelFor = {});
  std::size_t Assign(const std::vector<float>& centres, int k) override;
  void Sums(int k,
    std::vector<double>& sums,
    std::vector<std::int64_t>& counts,
    double& inertia) override;
  const std::int32_t* Labels() override { return this->LabelData.data(); }
  const float* Distances() override { return this->DistanceData.data(); }

private:
  KMeansFeatures Features;
  KMeansParallelFor Parallel;
  std::vector<std::int32_t> LabelData;
  std::vector<float> DistanceData;
  std::vector<double> BlockSumData;
  std::vector<std::int64_t> BlockCountData;
  std::vector<double> BlockInertiaData;
};

/// Stop settings of KMeansLloyd.
struct KMeansOptions
{
  int maximumIterations = 300; ///< >= 1 (scikit-learn's default)
  /// Relative to the mean feature variance. 0: stop when no label changes, or when no centre
  /// moves at all (scikit-learn's `<=`).
  double tolerance = 1e-4;
  /**
   * A distributed run: the sums, counts, inertia and changed labels of every iteration are
   * all-reduced, and so are the mean variance (tolerance) and the choice of the cells that
   * re-seed empty clusters. Null: serial.
   */
  KMeansReduction* reduction = nullptr;
  /**
   * With `reduction`: each packed cell's index in the whole grid (j * nx + i), which breaks
   * ties between equally far cells of different processes as a serial run breaks them (lowest
   * cell first). Needed only then.
   */
  const std::int64_t* globalCells = nullptr;
};

/// Why KMeansLloyd stopped.
enum class KMeansStopReason
{
  Converged,         ///< no label changed
  Tolerance,         ///< the centres moved less than the tolerance
  MaximumIterations, ///< the iteration limit was reached
};

/// "Converged", "Tolerance", "MaximumIterations".
const char* KMeansStopReasonName(KMeansStopReason reason);

/// Result of KMeansLloyd. Labels and distances stay in the engine.
struct KMeansResult
{
  std::vector<float> centres;       ///< k * F, final
  std::vector<std::int64_t> counts; ///< members per cluster, final labels
  double inertia = 0.0;             ///< within-cluster sum of squares, final labels and centres
  int iterations = 0;               ///< Lloyd iterations run (scikit-learn's n_iter_)
  int relocated = 0;                ///< empty clusters relocated, over all iterations
  KMeansStopReason reason = KMeansStopReason::MaximumIterations;
};

/**
 * @brief Lloyd iterations from `initialCentres` (k * F floats) on `engine` (steps 1-5).
 * @param progress optional, called after each iteration with (iteration, changed labels)
 * @throws std::invalid_argument when k < 1, k > KMeansMaxClusters, k > cells, the centres'
 *         size is not k * F, maximumIterations < 1, or tolerance is negative or NaN
 */
KMeansResult KMeansLloyd(KMeansEngine& engine,
  const KMeansFeatures& features,
  const std::vector<float>& initialCentres,
  int k,
  const KMeansOptions& options,
  const std::function<void(int, std::size_t)>& progress = {});

/// Mean of each prepared feature's variance (population), the scale of `tolerance`.
double KMeansMeanVariance(const KMeansFeatures& features,
  const KMeansParallelFor& parallelFor = {},
  KMeansReduction* reduction = nullptr);

/// Colour of cluster `id` as "#rrggbb": Tableau 10 then two more, cycled (the `Clusters` overlay
/// preset's palette).
std::string KMeansClusterColor(int id);

/// The same colour as three bytes.
void KMeansClusterColorRGB(int id, unsigned char rgb[3]);

} // namespace clustering
} // namespace terroir

#endif

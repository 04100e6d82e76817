/**
 * @class   vtkTerroirKMeans
 * @brief   Groups the cells of a terrain into K ecological zones by k-means clustering of
 *          their resources, and describes each zone in a table.
 *
 * Input: a Terroir terrain (2-D vtkImageData, point array `Elevation`, optional
 * `vtkValidPointMask`) carrying the resource arrays to cluster on. Features are point arrays,
 * each with a weight (AddFeature); every component of a multi-component array is a feature.
 * With no feature added, Long (2016)'s defaults are used, those of them that exist: `Slope` (1),
 * `Temperature` (12 months, 1), `IlluminationHours` (12, 1), `WeightedSoilHumidity` (12, 0.1).
 * The squared distance between two cells is sum_f w_f (x_f - y_f)^2 over the features' values,
 * or over their z-scores (mean 0, standard deviation 1 over the valid cells) when Standardize
 * is on. A cell takes part when the terrain is valid there and every feature value is finite.
 *
 * Output port 0: the input's arrays plus `ClusterId` (vtkIntArray, 0..K-1; -1 on cells that
 * take no part), and in field data `KMeansWithinClusterSumOfSquares` (double, the inertia in
 * the weighted feature space), `KMeansIterations` (int), `KMeansStopReason` (string:
 * Converged, Tolerance, MaximumIterations), `KMeansRelocatedClusters` (int, empty clusters
 * re-seeded), `KMeansClusterShare` (double, K tuples: each cluster's fraction of the cells,
 * which the `Clusters` overlay legend shows) and `KMeansCollapsedArrays` (strings: the arrays
 * stored as one feature, below).
 * Output port 1: a vtkTable, one row per cluster: `ClusterId` (int), `Color` (string
 * "#rrggbb", the `Clusters` overlay colour), `Cells` (vtkIdType), `Share` (fraction of the
 * cells that take part), then the mean of every feature array component in its own units
 * (column `<Array>` for one component, `<Array>_<ComponentName>` such as `Temperature_Jan`, or
 * `<Array>_<index>` when the component has no name), Long (2016)'s cluster description table.
 *
 * Algorithm (terroir::clustering, Filters/Clustering/Core/KMeans.h): Lloyd iterations from K
 * seeds until no cell changes cluster, or the centres move less than Tolerance (relative to
 * the mean feature variance, scikit-learn's definition), or MaximumIterations; empty clusters
 * are re-seeded from the cells farthest from their centre. Seeds: Long (2016)'s
 * deterministic choice (K valid cells equally spaced along the diagonal from the south-west
 * to the north-east corner) or k-means++ with RandomSeed. Storage trick (Long (2016)'s, for
 * Temperature): an array whose components differ by one constant each over every cell (up to
 * float rounding) is stored as one feature with its weight times its component count, which
 * gives the same distances (and Tolerance keeps its meaning: the mean variance is taken over
 * the uncollapsed features), so the same result; it is applied when it holds and listed in
 * KMeansCollapsedArrays. The table's means are those of the final clusters' members; after a
 * stop by Tolerance or MaximumIterations the cells were assigned to centres one update older
 * (scikit-learn's `cluster_centers_` are the same), so the two differ by less than the
 * tolerance allows.
 *
 * Whole extent (global filter) in a serial run. In a distributed run (pvbatch + MPI: a global
 * vtkMultiProcessController of N > 1 processes and N pieces asked for; needs VTK::ParallelCore,
 * which both Debian's VTK 9.1 and ParaView 5.11 have) each process asks for its piece only and
 * every step is all-reduced over the processes (terroir::clustering::KMeansReduction): the
 * means and standard deviations, the collapse test, the per-cluster sums and counts of each
 * iteration (as vtkPKMeansStatistics does), the changed labels, the inertia, the mean variance
 * of the tolerance and the table's means. Seeds are the serial ones: the validity of the
 * diagonal's cells is summed over the processes and each seed's owner contributes its features.
 * Empty clusters take the serial run's farthest cells (all-reduced maximum, ties to the lowest
 * cell of the whole grid). Sums are taken per process and then added, so their last bits may
 * differ from a serial run's (whose blocks span the whole grid); labels are the serial ones
 * unless a cell is within that rounding of two centres. Collective: every process runs the filter
 * for the same request, as ParaView does. The distributed path runs on the CPU;
 * k-means++ seeding and fewer valid diagonal cells than clusters are serial only (an error).
 *
 * CPU (vtkSMPTools over blocks of 4096 cells) and GPU
 * (Shaders/KMeansAssign.comp, KMeansPartialSums.comp) paths give the same labels, centres and
 * inertia bit for bit: distances in float in feature order without fused multiply-add, sums in
 * double per block in cell order, blocks added in order. Same input, same result on any thread
 * count and backend. Errors (one line, empty outputs): a feature naming no point array, a
 * non-numeric array, negative or non-finite weights, all weights zero, no default feature
 * present, fewer cells with data than clusters.
 *
 * @par Correctness
 * Testing/Unit/TestKMeans.cxx (hand-worked iterations, separated blobs, seeding, weights,
 * empty clusters, thread independence), Testing/Pipeline/TestTerroirKMeans.cxx (arrays, table,
 * no data, the diagonal seeds, vtkKMeansStatistics on blobs), Testing/GPU/TestKMeansGPU.cxx,
 * Testing/Python/TestKMeansSklearn.py (scikit-learn's Lloyd from the same centres: same
 * assignments and inertia on the bundled DEM's resources and on blobs).
 *
 * @par References
 * Lloyd, S. P. (1982). Least squares quantization in PCM. IEEE Transactions on Information
 * Theory 28(2):129-137. doi:10.1109/TIT.1982.1056489
 * Arthur, D., Vassilvitskii, S. (2007). k-means++: the advantages of careful seeding. Proc.
 * 18th ACM-SIAM Symposium on Discrete Algorithms, 1027-1035.
 * Long, H. (2016). Using procedural methods to generate realistic virtual rural worlds. MSc
 * minor dissertation, chapter 4.
 *
 * @sa vtkTerroirImageAlgorithm vtkTerroirTemperature vtkTerroirSolarIllumination
 */
#ifndef vtkTerroirKMeans_h
#define vtkTerroirKMeans_h

#include "vtkTerroirFiltersClusteringModule.h" // For export macro
#include "vtkTerroirImageAlgorithm.h"

#include <string> // For std::string
#include <vector> // For std::vector

namespace terroir
{
template<typename T>
struct GridView;
}

class vtkTable;

class VTKTERROIRFILTERSCLUSTERING_EXPORT vtkTerroirKMeans : public vtkTerroirImageAlgorithm
{
public:
  static vtkTerroirKMeans* New();
  vtkTypeMacro(vtkTerroirKMeans, vtkTerroirImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Output point array name.
  static const char* ClusterIdName() { return "ClusterId"; }

  /// Seeding methods.
  enum SeedingType
  {
    Diagonal = 0,       ///< Long (2016)'s cells along the diagonal (default)
    KMeansPlusPlus = 1, ///< k-means++ with RandomSeed
  };

  ///@{
  /// Number of clusters K. Default 5; 1..64.
  vtkSetClampMacro(NumberOfClusters, int, 1, 64);
  vtkGetMacro(NumberOfClusters, int);
  ///@}

  ///@{
  /**
   * Features: point arrays and their weights (>= 0, finite; 0 drops the array). Adding an
   * array twice replaces its weight. With none added the defaults above are used.
   */
  void AddFeature(const char* arrayName, double weight);
  void RemoveAllFeatures();
  int GetNumberOfFeatures() { return static_cast<int>(this->Features.size()); }
  const char* GetFeatureName(int i);
  double GetFeatureWeight(int i);
  ///@}

  ///@{
  /// Cluster on z-scores of the features instead of their values. Default off.
  vtkSetMacro(Standardize, bool);
  vtkGetMacro(Standardize, bool);
  vtkBooleanMacro(Standardize, bool);
  ///@}

  ///@{
  /// Seeding: 0 Diagonal (default), 1 KMeansPlusPlus.
  vtkSetClampMacro(Seeding, int, 0, 1);
  vtkGetMacro(Seeding, int);
  void SetSeedingToDiagonal() { this->SetSeeding(Diagonal); }
  void SetSeedingToKMeansPlusPlus() { this->SetSeeding(KMeansPlusPlus); }
  ///@}

  ///@{
  /// Random seed of k-means++ (std::mt19937_64). Default 0; >= 0.
  vtkSetClampMacro(RandomSeed, int, 0, VTK_INT_MAX);
  vtkGetMacro(RandomSeed, int);
  ///@}

  ///@{
  /// Most Lloyd iterations. Default 300 (scikit-learn's); >= 1.
  vtkSetClampMacro(MaximumIterations, int, 1, VTK_INT_MAX);
  vtkGetMacro(MaximumIterations, int);
  ///@}

  ///@{
  /**
   * Stop when the squared centre shift summed over the clusters is at most Tolerance times the
   * mean variance of the (weighted) features, as scikit-learn's `tol`. Default 1e-4; 0 stops
   * only when no cell changes cluster.
   */
  vtkSetMacro(Tolerance, double);
  vtkGetMacro(Tolerance, double);
  ///@}

  ///@{
  /// Apply the storage trick when it holds. Default on (it never changes the distances).
  vtkSetMacro(CollapseConstantOffsets, bool);
  vtkGetMacro(CollapseConstantOffsets, bool);
  vtkBooleanMacro(CollapseConstantOffsets, bool);
  ///@}

  /// The cluster table (output port 1).
  vtkTable* GetClusterTable();

protected:
  vtkTerroirKMeans();
  ~vtkTerroirKMeans() override;

  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  /// Decides whether this request is a piece of a distributed run, then asks for the input.
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  /// The whole extent in a serial run, the piece alone in a distributed one.
  int GetHaloWidth() override { return this->DistributedRun ? 0 : -1; }
  bool HasGPUPath() override { return true; }
  double EstimateMemory(double nx, double ny) override;
  std::string CheckParameters() override;
#ifndef __VTK_WRAP__
  int RequestTerrainData(vtkImageData* input,
    const terroir::TerrainInput& terrain,
    vtkImageData* output) override;
#endif

  int NumberOfClusters = 5;
  bool Standardize = false;
  int Seeding = Diagonal;
  int RandomSeed = 0;
  int MaximumIterations = 300;
  double Tolerance = 1e-4;
  bool CollapseConstantOffsets = true;

private:
  vtkTerroirKMeans(const vtkTerroirKMeans&) = delete;
  void operator=(const vtkTerroirKMeans&) = delete;

  struct Feature
  {
    std::string name;
    double weight;
  };
  std::vector<Feature> Features;
  /// Feature components of the current input (set by RequestData, for EstimateMemory).
  int InputComponents = 0;
  /// Whether the current request is one piece of a distributed run (see the class comment).
  bool DistributedRun = false;
  /// The input's whole extent (global cell indices of a piece's cells).
  int WholeExtent[6] = { 0, -1, 0, -1, 0, -1 };
  /// Distributed: this piece's extent without ghost levels (the points it may own).
  int OwnedExtent[6] = { 0, -1, 0, -1, 0, -1 };

#ifndef __VTK_WRAP__
  // RequestTerrainData in steps, over the state of one request (Clustering).
  struct Clustering;
  /// Step 1: the feature arrays (the defaults when none was added), checked against the terrain.
  bool ResolveFeatures(vtkImageData* input, Clustering& c);
  /// Step 2: the cells with valid terrain and finite values of every weighted feature (>= k).
  bool SelectCells(const terroir::GridView<float>& v, Clustering& c);
  /// Step 3a: the core's view of each feature, packed into floats where needed.
  void PackFeatures(Clustering& c);
  /// Step 3b: the prepared, weighted feature matrix (KMeansPrepareFeatures); frees the copies.
  void PrepareMatrix(Clustering& c);
  /// Step 4: the initial centres (Long (2016)'s diagonal cells or k-means++).
  void SeedCentres(const terroir::GridView<float>& v, Clustering& c);
  /// Step 4 in a distributed run: the serial Diagonal seeds from every process's cells.
  void SeedCentresDistributed(Clustering& c);
  /// Step 5: the Lloyd iterations on the GPU or the CPU; false when the GPU path failed.
  bool RunLloyd(int backend, Clustering& c);
  /// Step 6: the ClusterId point array (-1 on the cells left out).
  void AddClusterIds(vtkImageData* output, const Clustering& c);
  /// Step 7: the cluster table (output port 1): members, share and feature means per cluster.
  void FillClusterTable(Clustering& c);
  /// Step 8: the run's field data (inertia, iterations, relocations, shares, stop reason, ...).
  void AddFieldData(vtkImageData* output, const Clustering& c);
#endif
};

#endif

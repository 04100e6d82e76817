/**
 * @class   vtkTerroirPlantPlacement
 * @brief   Plants for every ecological zone: point patterns with an exemplar's densities and
 *          pair correlations, synthesised by Metropolis-Hastings birth, death and move.
 *
 * Input port 0: the zones, a 2-D vtkImageData (spacing in metres) with the point array
 * `ClusterId` (vtkTerroirKMeans; -1 = no zone) and, optionally, `Elevation` (metres; the plants'
 * z, interpolated bilinearly; 0 without it). Each grid point stands for the cell around it.
 * Input port 1 (optional): an exemplar pattern, a vtkPolyData whose points (x, y, metres) are
 * plants, with the optional point arrays `Species` (integer 0..63; all 0 without it) and
 * `ClusterId` (the zone the plant exemplifies; without it every zone learns from every
 * exemplar point); its window is the field data `ExemplarWindow` (xmin, xmax, ymin, ymax) or
 * else the points' bounds.
 *
 * Output: vtkPolyData, one vertex per plant: points (x, y, z), point arrays `Species` and
 * `ClusterId` (vtkIntArray); field data `PlantZones` and `PlantCounts` (one tuple per zone).
 *
 * Algorithm (terroir::clustering, Filters/Clustering/Core/PointPattern.h): per zone, the
 * exemplar's radial-distribution model (LearnRadialDistribution: per-species densities, pair
 * correlations g_AB(r) in `Bins` bins up to `MaximumDistance`, translation edge correction,
 * hard cores where the exemplar shows them) is reproduced in the zone's cells by a Gibbs
 * process sampled with birth, death and move perturbations (SynthesizeZones; Long 2016
 * section 2.2.2.1 after Hurtut et al. 2009 and Emilien et al. 2015). Without an exemplar the
 * model is one species with no pair closer than `MinimumDistance` (default 5 m) at `Density`
 * plants per m^2 (default 0.01): a hard-core (Poisson-disk) pattern. Zones run in parallel
 * (vtkSMPTools); each zone's seed is derived from `Seed` (default 1) and its id, so the result
 * is the same bits on any thread count and a zone's plants do not depend on the others.
 * `Iterations` (default 0: 200 per expected plant) sets the perturbations per zone.
 * Plants of neighbouring zones do not interact across the border. Projected grids (uniform
 * spacing) only.
 *
 * Errors (one line, empty output): no `ClusterId` point array (or not one component), a
 * Species outside 0..63, an empty exemplar window, Density < 0, MinimumDistance < 0,
 * MaximumDistance <= 0 or Bins outside 1..4096.
 *
 * @par Correctness
 * Testing/Unit/TestPointPattern.cxx (the core: estimator, synthesis against exemplars, masks,
 * determinism), Testing/Pipeline/TestTerroirPlantPlacement.cxx (plants inside their zones, no
 * pair closer than the hard core, densities, z on a plane, exemplar species, seeds, errors),
 * Testing/Pipeline/TestDeterminism.cxx.
 *
 * @sa vtkTerroirKMeans Documentation/Plants.md
 */
#ifndef vtkTerroirPlantPlacement_h
#define vtkTerroirPlantPlacement_h

#include "vtkPolyDataAlgorithm.h"
#include "vtkTerroirFiltersClusteringModule.h" // For export macro

class VTKTERROIRFILTERSCLUSTERING_EXPORT vtkTerroirPlantPlacement : public vtkPolyDataAlgorithm
{
public:
  static vtkTerroirPlantPlacement* New();
  vtkTypeMacro(vtkTerroirPlantPlacement, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The exemplar pattern (input port 1, optional).
  void SetExemplarConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(1, output); }
  void SetExemplarData(vtkDataObject* data) { this->SetInputData(1, data); }

  ///@{
  /// Seed of every zone's random numbers (default 1).
  vtkSetMacro(Seed, vtkTypeUInt64);
  vtkGetMacro(Seed, vtkTypeUInt64);
  ///@}

  ///@{
  /// Without an exemplar: plants per m^2 (default 0.01, >= 0).
  vtkSetMacro(Density, double);
  vtkGetMacro(Density, double);
  ///@}

  ///@{
  /// Without an exemplar: no two plants closer than this, metres (default 5, >= 0).
  vtkSetMacro(MinimumDistance, double);
  vtkGetMacro(MinimumDistance, double);
  ///@}

  ///@{
  /// Largest distance of the pair correlations, metres (default 0: 2 x MinimumDistance
  /// without an exemplar, 10 m with one).
  vtkSetMacro(MaximumDistance, double);
  vtkGetMacro(MaximumDistance, double);
  ///@}

  ///@{
  /// Distance bins of the pair correlations (default 20, 1..4096).
  vtkSetClampMacro(Bins, int, 1, 4096);
  vtkGetMacro(Bins, int);
  ///@}

  ///@{
  /// Perturbations per zone (default 0: 200 per expected plant, at least 1000).
  vtkSetClampMacro(Iterations, vtkTypeInt64, 0, VTK_TYPE_INT64_MAX);
  vtkGetMacro(Iterations, vtkTypeInt64);
  ///@}

  /// Output array names.
  static const char* SpeciesName() { return "Species"; }
  static const char* ClusterIdName() { return "ClusterId"; }

protected:
  vtkTerroirPlantPlacement();
  ~vtkTerroirPlantPlacement() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  vtkTypeUInt64 Seed = 1;
  double Density = 0.01;
  double MinimumDistance = 5.0;
  double MaximumDistance = 0.0;
  int Bins = 20;
  vtkTypeInt64 Iterations = 0;

private:
  vtkTerroirPlantPlacement(const vtkTerroirPlantPlacement&) = delete;
  void operator=(const vtkTerroirPlantPlacement&) = delete;
};

#endif

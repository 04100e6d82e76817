/**
 * @file TerroirBenchPrivate.h
 * @brief The inside of `terroir bench` (TerroirBench.h): one run's state (BenchRun), the stage
 * table (BenchStages(): one function per stage, in TerroirBenchStages.cxx) and the probes that
 * time kernels without the pipeline (TerroirBenchProbes.cxx).
 *
 * A stage builds our filters on the synthetic terrain, times their Update() with
 * BenchRun::BestOf and reports one row per backend with BenchRun::Report. Adding a stage: a
 * function in TerroirBenchStages.cxx, its row in BenchStages(), and its name in
 * BenchStageNames() (TerroirCommandLine.cxx, the option parser's list; TestCommandRegistry
 * checks that the two lists agree).
 */
#ifndef TerroirBenchPrivate_h
#define TerroirBenchPrivate_h

#include "vtkSmartPointer.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <vector>

class vtkAlgorithm;
class vtkImageData;
class vtkTerroirSolarIllumination;

namespace terroir
{
namespace gpu
{
struct Stats;
}
namespace app
{

/// One benchmark run: the terrain, the backend being timed, and the rows reported so far.
class BenchRun
{
public:
  vtkSmartPointer<vtkImageData> Terrain; ///< SIZE x SIZE synthetic DEM (SyntheticTerrain)
  int Size = 0;
  double MCells = 0.0; ///< Size^2 / 1e6
  int Repeat = 1;      ///< timed calls per stage (best of)
  bool GPUBreakdown = false;
  double GPUCopyBandwidth = 0.0; ///< bytes/s, measured when GPUBreakdown is on
  int Backend = 0;               ///< vtkTerroirComputeContext::CPU or GPU
  const char* BackendName = "";
  nlohmann::json Results = nlohmann::json::array(); ///< one object per row

  // What a stage leaves for the --bandwidth probes and for later stages.
  double SlopeCPUSeconds = 0.0;
  vtkSmartPointer<vtkImageData> HumidityInput; ///< terrain + InfiltrationRate (CPU run)
  vtkSmartPointer<vtkImageData> KMeansInput;   ///< terrain + 37 feature components

  /// Best of Repeat timed calls of `once` (which returns its own seconds), after one untimed
  /// warm-up call (shader compile, first touch of memory); with --gpu-breakdown, a GPU stage
  /// then runs once more with profiling (its times perturbed by the waits: not the best).
  double BestOf(const std::function<double()>& once);
  /// Prints and records one row (with the GPU breakdown of the last BestOf, if any).
  void Report(const std::string& stage, double best, nlohmann::json extra);
  /// Seconds of one Update() of `f` after Modified(); throws Failure naming `stage`.
  static double TimedUpdate(vtkAlgorithm* f, const std::string& stage);
  /// A sun filter on the terrain for the current backend: the synthetic DEM has no
  /// georeference, so the sun is placed at Sagehen Creek (39.43 N, 120.24 W) with grid north =
  /// true north; the instants are 2025-06-21 15:00 local time (UTC-8), the sun at azimuth
  /// 260 deg, elevation 49 deg. `mode`: vtkTerroirSolarIllumination::Instant, Monthly, ...
  vtkSmartPointer<vtkTerroirSolarIllumination> Illumination(int mode) const;

private:
  nlohmann::json Breakdown; ///< of the last BestOf on the GPU, consumed by Report
};

/// A stage: its name (as BenchStageNames() spells it), whether it runs on the CPU only (GPU
/// runs are skipped without a row), and its code.
struct BenchStage
{
  const char* Name;
  bool CPUOnly;
  void (*Run)(BenchRun& run);
};

/// Every stage, in the order of BenchStageNames().
const std::vector<BenchStage>& BenchStages();

// Probes and inputs (TerroirBenchProbes.cxx).

/// vtkTerroirFractalTerrainSource's terrain with seed 1 and its defaults (10 m cells), made
/// from the same core so that the benchmark needs no IO module (GDAL).
vtkSmartPointer<vtkImageData> SyntheticTerrain(int size);
/// The terrain with 37 feature components for the k-means stage.
vtkSmartPointer<vtkImageData> BenchKMeansFeatures(vtkImageData* terrain);
/// Sustained memory bandwidth, bytes/s (a parallel copy of 256 MiB), best of `repeat`.
double MeasureCopyBandwidth(int repeat);
/// Best time of the slope kernel alone (core rows over vtkSMPTools), seconds.
double TimeSlopeKernel(vtkImageData* terrain, bool allOutputs, int repeat);
/// Seconds per iteration of the water-flow CPU kernel alone, best of `repeat`.
double TimeWaterFlowKernel(vtkImageData* terrain, int repeat);
/// Best time of the soil-humidity kernel alone on `withRates`' InfiltrationRate, seconds.
double TimeHumidityKernel(vtkImageData* withRates, bool allOutputs, int repeat);
/// How the GPU context moves data ("a staging ring", "mapped buffers", "glBufferSubData").
const char* GPUTransferName();
/// Bytes a stage's GPU kernels read and write per cell (0: compute-bound, no byte model).
double BenchKernelBytesPerCell(const std::string& stage);
/// The profiled run's counters as JSON (seconds).
nlohmann::json GPUBreakdownJson(const terroir::gpu::Stats& s, double total);
/// Prints the breakdown and adds the kernels' rate to it.
void PrintGPUBreakdown(nlohmann::json& b, double kernelBytes, double copyBandwidth);

} // namespace app
} // namespace terroir

#endif

/**
 * @class   vtkTerroirImageAlgorithm
 * @brief   Base class of the Terroir terrain filters: input checks, halo, backend choice.
 *
 * Every Terroir filter reads a terrain: a 2-D vtkImageData (dimensions nx, ny, 1; spacing in
 * metres) whose point data hold the elevation (by default the array `Elevation`, chosen with
 * `SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "Elevation")`),
 * optionally `vtkValidPointMask` (1 = valid) and the georeference field arrays of
 * vtkTerroirGeoreference. The output is a shallow copy of the input (every input array and the
 * field data pass through) plus the arrays the filter adds; no-data cells (mask 0 or NaN
 * elevation) get NaN in every added array.
 *
 * This class provides:
 * - `Backend` (Auto = 0, CPU = 1, GPU = 2; default Auto), resolved by
 *   vtkTerroirComputeContext::ResolveBackend (`TERROIR_BACKEND=cpu|gpu` overrides Auto); the
 *   choice is logged once per filter class and backend with `vtkLog(INFO, ...)` and kept in
 *   `GetLastBackend()` / `GetLastBackendReason()`. A GPU failure at run time falls back to the
 *   CPU with a warning under Auto and is an error under GPU.
 * - streaming: `RequestUpdateExtent` asks for the requested extent grown by `GetHaloWidth()`
 *   cells (clamped to the whole extent, as vtkImageGradient), or the whole extent when the
 *   halo is -1. A piece request (pvbatch + MPI: piece, number of pieces, ghost levels, which
 *   the pipeline turns into an extent with vtkExtentTranslator whatever UPDATE_EXTENT says)
 *   gets the halo as ghost levels, and a whole-extent filter asks for the one piece of one.
 *   The filter computes on the input's extent and the output is then cropped to the extent
 *   asked of it (vtkImageData::Crop; nothing is copied when they are the same, as in a serial
 *   run), so that the pieces of a parallel run do not overlap and a cell's value is the serial
 *   one: pointwise filters run per piece, stencil filters on their piece and halo, and
 *   whole-extent filters compute everything on each rank and keep their piece.
 * - `RequestData`: validates the parameters (`CheckParameters`) and the input, checks that the
 *   memory the filter will allocate (`EstimateMemory`, plus any conversion of the input) is
 *   available (terroir::CheckMemory, Common/Core/MemoryBudget.h), then shallow-copies the input,
 *   reports progress and calls `RequestTerrainData` with a terroir::TerrainInput
 *   (vtkTerroirTerrainInput.h). Any failure gives one clear error naming the source file and
 *   the problem, and an empty output; an allocation that fails anyway is reported the same way.
 *
 * @sa vtkTerroirSlope vtkTerroirTemperature vtkTerroirComputeContext
 */
#ifndef vtkTerroirImageAlgorithm_h
#define vtkTerroirImageAlgorithm_h

#include "vtkImageAlgorithm.h"
#include "vtkTerroirComputeContext.h"    // For the backend values
#include "vtkTerroirFiltersBaseModule.h" // For export macro

#include <functional> // For std::function
#include <string>     // For std::string

namespace terroir
{
struct TerrainInput;
}
class vtkMultiProcessController;

class VTKTERROIRFILTERSBASE_EXPORT vtkTerroirImageAlgorithm : public vtkImageAlgorithm
{
public:
  vtkAbstractTypeMacro(vtkTerroirImageAlgorithm, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Which backend runs the filter: 0 Auto (default; TERROIR_BACKEND, else the GPU when a
   * compute context can be made and the filter has a GPU path, else the CPU), 1 CPU, 2 GPU
   * (an error when no compute context can be made). Values of
   * vtkTerroirComputeContext::BackendType.
   */
  vtkSetClampMacro(Backend, int, 0, 2);
  vtkGetMacro(Backend, int);
  void SetBackendToAuto() { this->SetBackend(vtkTerroirComputeContext::Auto); }
  void SetBackendToCPU() { this->SetBackend(vtkTerroirComputeContext::CPU); }
  void SetBackendToGPU() { this->SetBackend(vtkTerroirComputeContext::GPU); }
  ///@}

  /// Backend of the last run: 1 CPU, 2 GPU, -1 before the first run or after a failed one.
  vtkGetMacro(LastBackend, int);
  /// One line saying why the last backend was chosen (empty before the first run).
  const char* GetLastBackendReason() { return this->LastBackendReason.c_str(); }

  /**
   * The global controller when `outInfo` asks for one piece of N and the global controller has
   * N > 1 processes (a distributed run: pvbatch or pvserver under mpirun); null otherwise, and
   * always null in a build without VTK::ParallelCore.
   */
  static vtkMultiProcessController* GetDistributedController(vtkInformation* outInfo);

  /**
   * The points piece `piece` of `pieces` owns in a distributed run: its extent
   * (vtkExtentTranslator, block mode, no ghost levels) less the upper boundary points that the
   * next piece along each axis also holds, so that the pieces' owned extents partition
   * `whole`.
   */
  static void GetOwnedExtent(int piece, int pieces, const int whole[6], int owned[6]);

protected:
  /**
   * Sets `months[month]` (month 0 = January, 12 months) to `value` and calls Modified() when
   * it changed; a month outside 0..11 is an error and changes nothing. The per-month setters
   * behind ParaView's indexed 12-value properties (its client-server layer cannot call the
   * array setters of vtkSetVectorMacro) are one line each with it.
   */
  void SetMonthValue(double* months, int month, double value);

  vtkTerroirImageAlgorithm();
  ~vtkTerroirImageAlgorithm() override;

  /// Stencil half-width in cells: 0 pointwise, r for a (2r+1)^2 stencil, -1 whole extent.
  /// Called by RequestUpdateExtent after DistributedRequest is set for the request.
  virtual int GetHaloWidth() { return 0; }
  /// Smallest nx and ny the filter accepts (1 by default).
  virtual int GetMinimumGridSize() { return 1; }
  /// Whether the subclass has a GPU path (false by default).
  virtual bool HasGPUPath() { return false; }
  /**
   * Bytes the filter allocates for an nx x ny terrain besides its input: output arrays and
   * working buffers, on whichever backend needs more host memory. RequestData refuses to run
   * when less memory is available.
   */
  virtual double EstimateMemory(double nx, double ny) = 0;
  /// One line naming the first parameter out of range, or "" when every parameter is usable.
  virtual std::string CheckParameters() { return std::string(); }

  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

#ifndef __VTK_WRAP__
  /**
   * Called by RequestData with a validated terrain; `output` already holds a shallow copy of
   * the input. Add arrays to `output` and return 1, or return 0 after a vtkErrorMacro.
   */
  virtual int RequestTerrainData(vtkImageData* input,
    const terroir::TerrainInput& terrain,
    vtkImageData* output) = 0;

  /**
   * Resolves the backend (see the class comment), logs the choice once per class and backend,
   * stores LastBackend and LastBackendReason and returns 1 (CPU) or 2 (GPU); returns -1 after a
   * vtkErrorMacro when the request cannot be met.
   */
  int SelectBackend(bool hasGPUPath);

  /**
   * Runs `gpuJob` (which calls terroir::gpu::Context::Global().Run). Returns 2 when it ran;
   * 1 when it threw under Auto (a warning was issued, LastBackend is now CPU: run the CPU
   * path); -1 when it threw under an explicit GPU request (a vtkErrorMacro was issued).
   */
  int RunGPUPath(const std::function<void()>& gpuJob);
#endif

  /// "<source file>: " when the input names its source file, else "".
  std::string SourcePrefix(vtkDataObject* input);

  int Backend = 0;
  int LastBackend = -1;
  /// Set by RequestUpdateExtent: this request is one of N pieces with a global controller of
  /// N > 1 processes (GetDistributedController is not null).
  bool DistributedRequest = false;
  std::string LastBackendReason;

private:
  vtkTerroirImageAlgorithm(const vtkTerroirImageAlgorithm&) = delete;
  void operator=(const vtkTerroirImageAlgorithm&) = delete;
};

#endif

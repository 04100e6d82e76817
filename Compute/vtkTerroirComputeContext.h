/**
 * @class   vtkTerroirComputeContext
 * @brief   Reports on Terroir's headless GPU compute context and resolves backend choices.
 *
 * A thin, wrapped (Python-visible) front for `terroir::gpu::Context` (see vtkTerroirGPU.h):
 * whether a compute context can be made, why not, and what GL it reports. It also holds the
 * single rule by which every filter picks its backend:
 *
 * - `CPU` and `GPU` requests are honoured; a `GPU` request without a context is an error.
 * - `Auto` becomes whatever the environment variable `TERROIR_BACKEND` says (`cpu` or `gpu`),
 *   else the GPU only where the stage's GPU path is recorded as verified -- correct and faster
 *   than its CPU path -- on the context's kind of hardware (the table of IsVerifiedFaster and
 *   Documentation/Compute.md, "Verified GPU paths"), else the CPU. Software rasterizers
 *   (llvmpipe) have rows there, all slower than the CPU, so `Auto` never picks them; tests and
 *   users reach any GPU path with `GPU` or `TERROIR_BACKEND=gpu`.
 */
#ifndef vtkTerroirComputeContext_h
#define vtkTerroirComputeContext_h

#include "vtkObject.h"
#include "vtkTerroirComputeModule.h" // For export macro

#include <string> // For std::string

class VTKTERROIRCOMPUTE_EXPORT vtkTerroirComputeContext : public vtkObject
{
public:
  static vtkTerroirComputeContext* New();
  vtkTypeMacro(vtkTerroirComputeContext, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum BackendType
  {
    Auto = 0,
    CPU = 1,
    GPU = 2
  };

  /// Makes the context if needed; true when GL >= 4.3 compute works.
  static bool IsAvailable();
  /// Empty when available.
  static std::string GetUnavailableReason();
  /// GL_RENDERER, GL_VERSION and the EGL platform, or empty when unavailable.
  static std::string GetRenderer();
  static std::string GetVersion();
  static std::string GetPlatform();
  /// True when the context is a software rasterizer (llvmpipe, softpipe, SwiftShader, ...).
  static bool IsSoftwareRenderer();

  /// Name of a backend value ("Auto", "CPU", "GPU").
  static const char* GetBackendName(int backend);

  /**
   * Resolves a requested backend (Auto/CPU/GPU) for a filter that has (or lacks) a GPU path.
   * Returns CPU or GPU and fills `reason` with one human line; returns -1 and fills `reason`
   * with the error when the request cannot be met (GPU asked for, no context or no GPU path;
   * or TERROIR_BACKEND holds something other than cpu/gpu/auto).
   */
  static int ResolveBackend(int requested, bool hasGPUPath, std::string& reason);
  /// The same for the stage `stage` (a filter's class name, e.g. "vtkTerroirSlope"): `Auto`
  /// picks the GPU only where IsVerifiedFaster(stage, renderer).
  static int ResolveBackend(int requested,
    const std::string& stage,
    bool hasGPUPath,
    std::string& reason);

  /**
   * True when the table of verified GPU paths has a row for `stage` whose hardware pattern
   * occurs in `renderer` (case-insensitive), with the GPU path correct and faster than the CPU
   * path there. `row` (may be null) gets that row, or the best row found for the stage, in
   * words.
   */
  static bool IsVerifiedFaster(const std::string& stage,
    const std::string& renderer,
    std::string* row = nullptr);
  /// The table of verified GPU paths, one line per row (stage, hardware, correct, speed ratio
  /// CPU time / GPU time, date, what ran).
  static std::string GetVerifiedTable();

protected:
  vtkTerroirComputeContext() = default;
  ~vtkTerroirComputeContext() override = default;

private:
  vtkTerroirComputeContext(const vtkTerroirComputeContext&) = delete;
  void operator=(const vtkTerroirComputeContext&) = delete;
};

#endif

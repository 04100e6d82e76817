/**
 * @file vtkTerroirKMeansGPU.h
 * @brief GPU path of the k-means (Shaders/KMeansAssign.comp, KMeansPartialSums.comp); private,
 *        not wrapped (exported only for Testing/GPU/TestKMeansGPU.cxx, as RunWaterFlowGPU).
 *
 * A terroir::clustering::KMeansEngine on the compute context: the feature matrix is uploaded
 * once; Assign is one dispatch (a cell per invocation, the core's float arithmetic in the same
 * order, `precise` so no fused multiply-add; the changed-label count reduced per work group);
 * Sums is one dispatch per KMeansBlockCells block (each block summed in cell order, in double,
 * exactly as KMeansBlockSums) followed by a final reduction over the blocks in block order. So
 * labels, sums and centres are the CPU path's bits, and KMeansLloyd takes the same steps.
 */
#ifndef vtkTerroirKMeansGPU_h
#define vtkTerroirKMeansGPU_h

#include "vtkTerroirFiltersClusteringModule.h" // For export macro

#include "KMeans.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace terroir
{
namespace clustering
{

/**
 * @brief KMeansLloyd (Core/KMeans.h) with the GPU engine, from `initialCentres`.
 *
 * Runs inside terroir::gpu::Context::Global().Run (the caller waits); `progress`, when set, is
 * called on the context's thread. The feature matrix is uploaded in chunks of whole
 * KMeansBlockCells blocks so that each fits GL_MAX_SHADER_STORAGE_BLOCK_SIZE, at most
 * `chunkBlocks` blocks per chunk (0, the default: as many as the driver's limits allow; tests
 * pass small values to run many chunks on small inputs); the result never depends on it.
 * @param labels out: features.cells final labels
 * @param distances out: features.cells final squared distances to the own centre
 * @throws terroir::gpu::Error on GL failures, when there is no compute context, or when a buffer
 *         exceeds GL_MAX_SHADER_STORAGE_BLOCK_SIZE or a dispatch GL_MAX_COMPUTE_WORK_GROUP_COUNT
 * @throws std::invalid_argument as KMeansLloyd
 */
VTKTERROIRFILTERSCLUSTERING_EXPORT KMeansResult RunKMeansGPU(const KMeansFeatures& features,
  const std::vector<float>& initialCentres,
  int k,
  const KMeansOptions& options,
  std::vector<std::int32_t>& labels,
  std::vector<float>& distances,
  const std::function<void(int, std::size_t)>& progress = {},
  std::size_t chunkBlocks = 0);

} // namespace clustering
} // namespace terroir

#endif

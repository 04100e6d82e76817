/**
 * @file vtkTerroirErosionGPU.h
 * @brief GPU path of the hydraulic and thermal erosion steps (Shaders/Erosion.comp); private,
 *        not wrapped.
 *
 * Runs steps of terroir::terrain::ErosionHydraulicStep and ErosionThermalStep
 * (Filters/Terrain/Core/Erosion.h) on the compute context. The state is uploaded once, every
 * step runs on the device (one dispatch per pass of the core, the fluxes ping-ponged; no
 * read-back and no wait between steps), and the state is read back once at the end into the
 * same ErosionState arrays. Each kernel does the core's float operations per cell in the same
 * order (with its TwoSum residues; divisions and square roots correctly rounded), and the sums
 * are taken as the core takes them, row by row in cell order and then over the rows in order,
 * in double (a row-sum kernel, then a one-invocation kernel): Dunn's k = m1 / m2 is computed on
 * the device between the transport and the rescaling, and the volumes are the core's. On a
 * driver with IEEE + - * (llvmpipe) the result is the CPU's to the bit; only exp2 (Weiss's
 * eq. 24, used when the halving depths are set) is the driver's.
 */
#ifndef vtkTerroirErosionGPU_h
#define vtkTerroirErosionGPU_h

#include "vtkTerroirFiltersTerrainModule.h" // For export macro

#include "Erosion.h"

namespace terroir
{
namespace terrain
{

/// Volumes of a GPU run, summed over its steps.
struct ErosionGPUTotals
{
  /// The hydraulic steps' ErosionStepStats summed in step order (m^3); sedimentScale is the
  /// last step's k (1 when no step ran).
  ErosionStepStats hydraulic;
  /// The thermal steps' moved volume summed in step order (m^3), and the last thermal step's
  /// maxExcess (m; 0 when none ran).
  ThermalStepStats thermal;
};

/**
 * @brief Runs `steps` hydraulic steps of `state` on the GPU, each followed by a thermal step
 *        when thermalInterval > 0 and its number (1, 2, ...) is a multiple of thermalInterval.
 *
 * The same as calling, on the CPU,
 * `for s in 1..steps: ErosionHydraulicStep(state, params, rain, evaporationFactor);
 *  if (thermalInterval > 0 && s % thermalInterval == 0) ErosionThermalStep(state, thermal);`
 * Every per-cell array of the state is honoured (valid mask, soil layer, erosionFactor,
 * talusFactor, the residues) and written back: terrain, terrainResidue, soil, water,
 * waterResidue, sediment, the four fluxes and the velocities (original, valid and the factors
 * are only read; the scratch arrays are left as they were). Runs inside
 * terroir::gpu::Context::Global().Run (the caller waits).
 *
 * @param[in,out] state       the simulation state (MakeErosionState)
 * @param[in] params          hydraulic constants (CheckErosionParams)
 * @param[in] thermal         thermal constants (CheckThermalParams; unused when
 *                            thermalInterval is 0)
 * @param[in] thermalInterval hydraulic steps per thermal step (>= 0; 0: none)
 * @param[in] rain            nx*ny rain rates (m/s), or nullptr
 * @param[in] evaporationFactor nx*ny factors on K_e, or nullptr for 1
 * @param[in] steps           hydraulic steps (>= 0; 0 does nothing)
 * @param[out] totals         the volumes moved, or nullptr
 * @throws std::invalid_argument for parameters out of range, negative steps or interval, or a
 *         state whose arrays do not have nx*ny entries
 * @throws terroir::gpu::Error without a compute context, on GL failures, or when the grid's
 *         state buffer (9 floats a cell) exceeds GL_MAX_SHADER_STORAGE_BLOCK_SIZE
 */
VTKTERROIRFILTERSTERRAIN_EXPORT void RunErosionGPU(ErosionState& state,
  const ErosionParams& params,
  const ThermalParams& thermal,
  int thermalInterval,
  const float* rain,
  const float* evaporationFactor,
  int steps,
  ErosionGPUTotals* totals = nullptr);

} // namespace terrain
} // namespace terroir

#endif

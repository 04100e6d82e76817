/**
 * @file vtkTerroirWaterFlowGPU.h
 * @brief GPU path of the hydrostatic water flow (Shaders/WaterFlow.comp), and the CPU path's
 *        threading with vtkSMPTools; private, not wrapped.
 *
 * Runs iterations of a terroir::hydrology::WaterFlowSimulation (Filters/Hydrology/Core/
 * WaterFlow.h) on the compute context: the padded terrain, water and discharge are uploaded,
 * each iteration is two dispatches (givers, then a gather that ping-pongs the water and reduces
 * the moved and outflow volumes per work group), and the state is written back into the
 * simulation at the end. The per-cell arithmetic is the core's, in double and in the same
 * order; only the sums of the volumes are taken in another order (per work group, then over the
 * groups in order), so totals agree with the CPU up to summation order.
 *
 * The partial sums are read back every `checkEvery` iterations. When a stop rule fires inside
 * such a block, the block's snapshot of water and discharge (taken on the GPU) is restored and
 * exactly the iterations up to the stopping one are run again, so the GPU stops after the same
 * iteration as WaterFlowSimulation::Run.
 */
#ifndef vtkTerroirWaterFlowGPU_h
#define vtkTerroirWaterFlowGPU_h

#include "vtkTerroirFiltersHydrologyModule.h" // For export macro

#include "WaterFlow.h"

namespace terroir
{
namespace hydrology
{

/// Runs the CPU iterations of `sim` on vtkSMPTools' threads, in blocks of
/// WaterFlowSimulation::BlockRows rows: how the filter runs them, and what `terroir bench` times.
VTKTERROIRFILTERSHYDROLOGY_EXPORT void UseSMPTools(WaterFlowSimulation& sim);

/// What a GPU run did.
struct WaterFlowGPUResult
{
  bool stopped = false; ///< a stop rule fired (else targetIterations was reached)
  WaterFlowStopReason reason = WaterFlowStopReason::MaximumIterations;
};

/**
 * @brief Runs iterations of `sim` on the GPU until sim.Iterations() == targetIterations or,
 *        when applyStopRules, a stop rule fires.
 *
 * Stop rules, tested after each iteration as WaterFlowSimulation::Run does (StopsAfter): moved
 * <= 0 without rain -> NoMovement; WaterFlowAutoStop(moved, movedBefore, autoStopRatio) ->
 * AutoStop. Every iteration
 * is recorded with sim.RecordIteration, and the final state is written into
 * sim.PaddedWater() and sim.PaddedDischarge(). Nothing runs when sim.Iterations() >=
 * targetIterations.
 *
 * Runs inside terroir::gpu::Context::Global().Run (the caller waits).
 * @param checkEvery iterations between two read-backs of the volumes (>= 1); it changes only
 *        the speed, never the result
 * @throws terroir::gpu::Error on GL failures, when there is no compute context, or when a
 *         buffer of the padded grid exceeds GL_MAX_SHADER_STORAGE_BLOCK_SIZE or the dispatch
 *         exceeds GL_MAX_COMPUTE_WORK_GROUP_COUNT
 * @throws std::invalid_argument when checkEvery < 1 or autoStopRatio is negative or NaN
 */
VTKTERROIRFILTERSHYDROLOGY_EXPORT WaterFlowGPUResult RunWaterFlowGPU(WaterFlowSimulation& sim,
  long long targetIterations,
  bool applyStopRules,
  double autoStopRatio,
  int checkEvery = 16);

/**
 * @brief The same with a whole stop rule (WaterFlowSimulation::StopsAfter: the auto-stop and the
 *        balance of outflow and rain; maximumIterations is not used, targetIterations is).
 *        The simulation's rain and net-flux sums (SetRain, SetNetFlux) run on the GPU too.
 */
VTKTERROIRFILTERSHYDROLOGY_EXPORT WaterFlowGPUResult RunWaterFlowGPU(WaterFlowSimulation& sim,
  long long targetIterations,
  bool applyStopRules,
  const WaterFlowStopRule& rule,
  int checkEvery = 16);

} // namespace hydrology
} // namespace terroir

#endif

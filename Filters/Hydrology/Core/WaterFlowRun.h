/**
 * @file WaterFlowRun.h
 * @brief The iteration loop of the water-flow simulation, written once: advancing to a target
 * iteration on any backend under the stop rules, checkpoints to go back in time, and the
 * river-forming mode's discharge rate. WaterFlowSimulation::Run, vtkTerroirWaterFlow (its
 * time steps, progress and IterationEvent) and the warm start's levels all go through it; a
 * backend only says how to advance (WaterFlowAdvanceCPU here, the GPU path in
 * vtkTerroirWaterFlowGPU.h).
 *
 * Plain C++ (no VTK, no GL).
 *
 * The stop rules themselves are WaterFlowSimulation::StopsAfter (no movement, Long (2016)'s
 * auto-stop, the balance of outflow and rain).
 */
#ifndef terroir_hydrology_WaterFlowRun_h
#define terroir_hydrology_WaterFlowRun_h

#include "WaterFlow.h"

#include <cstddef>
#include <functional>
#include <map>
#include <vector>

namespace terroir
{
namespace hydrology
{

/**
 * A backend's way to advance `sim` up to iteration `until` (at most): true, with `reason`, when
 * it stopped earlier because nothing moved or (with `applyRules`) a stop rule of `rule` fired
 * after the last iteration it ran. It may throw; the state is then undefined.
 */
using WaterFlowAdvance = std::function<bool(WaterFlowSimulation& sim,
  long long until,
  bool applyRules,
  const WaterFlowStopRule& rule,
  WaterFlowStopReason& reason)>;

/// The CPU backend: WaterFlowSimulation::Step until `until`; an iteration that moved nothing
/// without rain stops it (NoMovement) whether or not the rules apply.
bool WaterFlowAdvanceCPU(WaterFlowSimulation& sim,
  long long until,
  bool applyRules,
  const WaterFlowStopRule& rule,
  WaterFlowStopReason& reason);

/// Throws std::invalid_argument when `rule` has a negative iteration limit, stop ratio or
/// settling count, or a balance tolerance outside [0, 1).
void CheckWaterFlowStopRule(const WaterFlowStopRule& rule);

/// Saved states (water, discharge, edge sums) of one simulation at some iterations, as many as
/// a memory budget allows, to go back to an earlier iteration without starting over.
class WaterFlowCheckpoints
{
public:
  /// Forgets every checkpoint.
  void Clear() { this->States.clear(); }
  std::size_t Size() const { return this->States.size(); }
  /// Keeps at most as many checkpoints of `sim` as fit in `megabytes` MiB (>= 0).
  void SetBudget(double megabytes, WaterFlowSimulation& sim);
  /// Saves the state of `sim` at its current iteration, unless one is saved there already or
  /// the budget is full.
  void Save(WaterFlowSimulation& sim);
  /**
   * Puts `sim` back to the latest checkpoint at or before `iteration` (histories truncated);
   * false when there is none, and the caller starts again from iteration 0.
   */
  bool Restore(WaterFlowSimulation& sim, long long iteration) const;

private:
  struct State
  {
    std::vector<double> Water, Discharge, Edges;
  };
  std::map<long long, State> States;
  std::size_t Capacity = 0;
};

/// What WaterFlowAdvanceTo should do.
struct WaterFlowAdvancePlan
{
  long long target = 0;               ///< the iteration to reach unless a rule stops earlier
  bool applyRules = true;             ///< false: only NoMovement (CPU) stops before the target
  WaterFlowStopRule rule;             ///< the rules when applyRules
  long long checkpointInterval = 100; ///< pause (and save a checkpoint) at its multiples, >= 1
  long long eventInterval = 0;        ///< also pause at its multiples (0: no such pauses)
};

/// How WaterFlowAdvanceTo ended.
struct WaterFlowAdvanceOutcome
{
  bool stopped = false; ///< a rule (or NoMovement) stopped it before the target
  WaterFlowStopReason reason = WaterFlowStopReason::MaximumIterations;
};

/**
 * The loop: advances `sim` from its current iteration to `plan.target` with `advance`, in
 * pieces that end at multiples of the checkpoint and event intervals. After each piece it saves
 * a checkpoint at multiples of checkpointInterval (when `checkpoints` is given) and calls
 * `onPause(iterations, event)`, event being true at multiples of eventInterval past the first
 * iteration of this call (progress bars, VTK's IterationEvent).
 */
WaterFlowAdvanceOutcome WaterFlowAdvanceTo(WaterFlowSimulation& sim,
  const WaterFlowAdvancePlan& plan,
  const WaterFlowAdvance& advance,
  WaterFlowCheckpoints* checkpoints = nullptr,
  const std::function<void(long long iterations, bool event)>& onPause = nullptr);

/**
 * The river-forming mode's discharge rate: `iterations` more CPU iterations from the current
 * state with the edge sums at zero, their net discharge divided by `seconds` (m^3/s, nx*ny,
 * NaN on no data) and the dominant outflow direction of each cell; then the state and the
 * histories go back to where they were. @pre sim.GetNetFlux(), iterations >= 1, seconds > 0.
 */
void WaterFlowDischargeRate(WaterFlowSimulation& sim,
  long long iterations,
  double seconds,
  double* rate,
  std::int8_t* dominant);

} // namespace hydrology
} // namespace terroir

#endif

#include "WaterFlowRun.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace terroir
{
namespace hydrology
{

//------------------------------------------------------------------------------
bool WaterFlowAdvanceCPU(WaterFlowSimulation& sim,
  long long until,
  bool applyRules,
  const WaterFlowStopRule& rule,
  WaterFlowStopReason& reason)
{
  while (sim.Iterations() < until)
  {
    const double before = sim.TotalMoved();
    const double emptiedBefore = sim.TotalEmptied();
    const WaterFlowIteration it = sim.Step();
    if (it.moved <= 0.0 && sim.GetRain() <= 0.0)
    {
      reason = WaterFlowStopReason::NoMovement;
      return true;
    }
    if (applyRules && sim.StopsAfter(it, sim.Iterations(), before, rule, reason, emptiedBefore))
    {
      return true;
    }
  }
  return false;
}

//------------------------------------------------------------------------------
void CheckWaterFlowStopRule(const WaterFlowStopRule& rule)
{
  if (rule.maximumIterations < 0 || !(rule.autoStopRatio >= 0.0) ||
    !(rule.balanceTolerance >= 0.0 && rule.balanceTolerance < 1.0) || rule.balanceAfter < 0)
  {
    throw std::invalid_argument("water flow: negative iteration limit, stop ratio or settling "
                                "count, or balance tolerance not in [0, 1)");
  }
}

//------------------------------------------------------------------------------
void WaterFlowCheckpoints::SetBudget(double megabytes, WaterFlowSimulation& sim)
{
  const double bytes =
    16.0 * static_cast<double>(sim.PaddedWater().size()) + 8.0 * sim.PaddedEdges().size();
  this->Capacity =
    static_cast<std::size_t>(std::floor(megabytes * 1048576.0 / std::max(bytes, 1.0)));
}

//------------------------------------------------------------------------------
void WaterFlowCheckpoints::Save(WaterFlowSimulation& sim)
{
  if (this->States.size() < this->Capacity && !this->States.count(sim.Iterations()))
  {
    this->States[sim.Iterations()] = {
      sim.PaddedWater(), sim.PaddedDischarge(), sim.PaddedEdges()
    };
  }
}

//------------------------------------------------------------------------------
bool WaterFlowCheckpoints::Restore(WaterFlowSimulation& sim, long long iteration) const
{
  auto it = this->States.upper_bound(iteration);
  if (it == this->States.begin())
  {
    return false;
  }
  --it;
  sim.PaddedWater() = it->second.Water;
  sim.PaddedDischarge() = it->second.Discharge;
  sim.PaddedEdges() = it->second.Edges;
  sim.TruncateHistory(it->first);
  return true;
}

//------------------------------------------------------------------------------
WaterFlowAdvanceOutcome WaterFlowAdvanceTo(WaterFlowSimulation& sim,
  const WaterFlowAdvancePlan& plan,
  const WaterFlowAdvance& advance,
  WaterFlowCheckpoints* checkpoints,
  const std::function<void(long long iterations, bool event)>& onPause)
{
  if (plan.checkpointInterval < 1 || plan.eventInterval < 0)
  {
    throw std::invalid_argument("water flow: the checkpoint interval must be >= 1 and the "
                                "event interval >= 0");
  }
  WaterFlowAdvanceOutcome outcome;
  const long long first = sim.Iterations();
  const long long interval = plan.checkpointInterval;
  const long long watch = plan.eventInterval;
  while (!outcome.stopped && sim.Iterations() < plan.target)
  {
    long long next = std::min(plan.target, (sim.Iterations() / interval + 1) * interval);
    if (watch > 0)
    {
      next = std::min(next, (sim.Iterations() / watch + 1) * watch);
    }
    outcome.stopped = advance(sim, next, plan.applyRules, plan.rule, outcome.reason);
    if (checkpoints && sim.Iterations() % interval == 0)
    {
      checkpoints->Save(sim);
    }
    if (onPause)
    {
      onPause(
        sim.Iterations(), watch > 0 && sim.Iterations() % watch == 0 && sim.Iterations() > first);
    }
  }
  if (!outcome.stopped)
  {
    outcome.reason = WaterFlowStopReason::MaximumIterations;
  }
  return outcome;
}

//------------------------------------------------------------------------------
void WaterFlowDischargeRate(WaterFlowSimulation& sim,
  long long iterations,
  double seconds,
  double* rate,
  std::int8_t* dominant)
{
  if (!sim.GetNetFlux() || iterations < 1 || !(seconds > 0.0))
  {
    throw std::invalid_argument("water flow: the discharge rate needs the net flux, at least "
                                "one iteration and a positive duration");
  }
  const std::vector<double> water = sim.PaddedWater();
  const std::vector<double> discharge = sim.PaddedDischarge();
  const std::vector<double> edges = sim.PaddedEdges();
  const long long stop = sim.Iterations();
  std::fill(sim.PaddedEdges().begin(), sim.PaddedEdges().end(), 0.0);
  for (long long k = 0; k < iterations; ++k)
  {
    sim.Step();
  }
  sim.GetNetDischarge(rate, dominant);
  const std::size_t n = static_cast<std::size_t>(sim.Nx()) * static_cast<std::size_t>(sim.Ny());
  for (std::size_t c = 0; c < n; ++c)
  {
    rate[c] /= seconds; // NaN on no data stays NaN
  }
  sim.PaddedWater() = water;
  sim.PaddedDischarge() = discharge;
  sim.PaddedEdges() = edges;
  sim.TruncateHistory(stop);
}

} // namespace hydrology
} // namespace terroir

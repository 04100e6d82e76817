// The water-flow loop written once (WaterFlowRun.h): where WaterFlowAdvanceTo pauses (worked out
// by hand), checkpoints that take a run back bit for bit, the CPU backend's stops, and the
// discharge rate that leaves the state as it found it.
#include "WaterFlowRun.h"

#include "TerroirWaterFlowScenes.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <utility>
#include <vector>

namespace
{
namespace hy = terroir::hydrology;
using Grid = terroir_test::WaterFlowGrid;

/// A 9 x 12 V valley (thalweg in column 4) with 1 cm of water on every cell.
struct Valley
{
  Grid grid{ 9, 12 };
  std::vector<double> water;
  Valley()
    : water(9 * 12, 0.01)
  {
    terroir_test::DrawVValley(grid.z.data(), grid.nx, grid.ny, 4);
  }
  hy::WaterFlowSimulation Make() const { return hy::WaterFlowSimulation(grid.view, water.data()); }
};

std::vector<float> Depth(const hy::WaterFlowSimulation& sim)
{
  std::vector<float> d(static_cast<std::size_t>(sim.Nx()) * sim.Ny());
  sim.GetWaterHeight(d.data());
  return d;
}
} // namespace

TEST(WaterFlowRun, AdvancePausesAtCheckpointAndEventMultiples)
{
  Valley v;
  hy::WaterFlowSimulation sim = v.Make();
  hy::WaterFlowAdvancePlan plan;
  plan.target = 25;
  plan.applyRules = false;
  plan.checkpointInterval = 10;
  plan.eventInterval = 4;
  hy::WaterFlowCheckpoints checkpoints;
  checkpoints.SetBudget(64.0, sim);
  std::vector<std::pair<long long, bool>> pauses;
  const hy::WaterFlowAdvanceOutcome outcome = hy::WaterFlowAdvanceTo(sim,
    plan,
    hy::WaterFlowAdvanceCPU,
    &checkpoints,
    [&](long long iterations, bool event) { pauses.emplace_back(iterations, event); });
  // From 0: the next multiple of 10 or 4, whichever comes first, then the target.
  const std::vector<std::pair<long long, bool>> expected = { { 4, true },
    { 8, true },
    { 10, false },
    { 12, true },
    { 16, true },
    { 20, true },
    { 24, true },
    { 25, false } };
  EXPECT_EQ(pauses, expected);
  EXPECT_FALSE(outcome.stopped);
  EXPECT_EQ(outcome.reason, hy::WaterFlowStopReason::MaximumIterations);
  EXPECT_EQ(checkpoints.Size(), 2u); // 10 and 20
  // The pieces change nothing: 25 plain iterations give the same bits.
  hy::WaterFlowSimulation plain = v.Make();
  for (int k = 0; k < 25; ++k)
  {
    plain.Step();
  }
  EXPECT_EQ(sim.Iterations(), 25);
  EXPECT_EQ(Depth(sim), Depth(plain));
  EXPECT_EQ(sim.TotalMoved(), plain.TotalMoved());
}

TEST(WaterFlowRun, CheckpointsTakeARunBackBitForBit)
{
  Valley v;
  hy::WaterFlowSimulation sim = v.Make();
  hy::WaterFlowAdvancePlan plan;
  plan.target = 30;
  plan.applyRules = false;
  plan.checkpointInterval = 10;
  hy::WaterFlowCheckpoints checkpoints;
  checkpoints.SetBudget(64.0, sim);
  hy::WaterFlowAdvanceTo(sim, plan, hy::WaterFlowAdvanceCPU, &checkpoints);
  const std::vector<float> at30 = Depth(sim);
  const double moved30 = sim.TotalMoved();

  hy::WaterFlowSimulation fresh = v.Make();
  for (int k = 0; k < 20; ++k)
  {
    fresh.Step();
  }
  // Iteration 25 is not saved: the latest checkpoint before it (20) is restored.
  ASSERT_TRUE(checkpoints.Restore(sim, 25));
  EXPECT_EQ(sim.Iterations(), 20);
  EXPECT_EQ(Depth(sim), Depth(fresh));
  EXPECT_EQ(sim.TotalMoved(), fresh.TotalMoved());
  EXPECT_EQ(sim.MovedHistory().size(), 20u);
  // Forward again: the same 30th iteration.
  hy::WaterFlowAdvanceTo(sim, plan, hy::WaterFlowAdvanceCPU, &checkpoints);
  EXPECT_EQ(Depth(sim), at30);
  EXPECT_EQ(sim.TotalMoved(), moved30);
  // Before the first checkpoint there is nothing to go back to.
  EXPECT_FALSE(checkpoints.Restore(sim, 9));
  EXPECT_EQ(sim.Iterations(), 30);
}

TEST(WaterFlowRun, CheckpointBudgetIsHonoured)
{
  Valley v;
  hy::WaterFlowSimulation sim = v.Make();
  hy::WaterFlowAdvancePlan plan;
  plan.target = 50;
  plan.applyRules = false;
  plan.checkpointInterval = 10;
  hy::WaterFlowCheckpoints none;
  none.SetBudget(0.0, sim);
  hy::WaterFlowAdvanceTo(sim, plan, hy::WaterFlowAdvanceCPU, &none);
  EXPECT_EQ(none.Size(), 0u);
  // Room for exactly two states: 16 bytes per padded cell (water, discharge), no edge sums.
  hy::WaterFlowSimulation again = v.Make();
  hy::WaterFlowCheckpoints two;
  two.SetBudget(2.0 * 16.0 * 11 * 14 / 1048576.0, again);
  hy::WaterFlowAdvanceTo(again, plan, hy::WaterFlowAdvanceCPU, &two);
  EXPECT_EQ(two.Size(), 2u);
}

TEST(WaterFlowRun, RulesStopTheLoopAndNoMovementAlways)
{
  // Dry flat ground: the first iteration moves nothing, rules or not.
  Grid flat(6, 6);
  const std::vector<double> dry(36, 0.0);
  for (bool apply : { false, true })
  {
    hy::WaterFlowSimulation sim(flat.view, dry.data());
    hy::WaterFlowAdvancePlan plan;
    plan.target = 100;
    plan.applyRules = apply;
    const hy::WaterFlowAdvanceOutcome o =
      hy::WaterFlowAdvanceTo(sim, plan, hy::WaterFlowAdvanceCPU);
    EXPECT_TRUE(o.stopped);
    EXPECT_EQ(o.reason, hy::WaterFlowStopReason::NoMovement);
    EXPECT_EQ(sim.Iterations(), 1);
  }
  // The auto-stop fires at the same iteration as WaterFlowSimulation::Run's, and not without
  // the rules.
  Valley v;
  hy::WaterFlowStopRule rule;
  rule.autoStopRatio = 0.05;
  rule.maximumIterations = 1000;
  hy::WaterFlowSimulation run = v.Make();
  ASSERT_EQ(run.Run(rule), hy::WaterFlowStopReason::AutoStop);
  hy::WaterFlowSimulation looped = v.Make();
  hy::WaterFlowAdvancePlan plan;
  plan.target = 1000;
  plan.rule = rule;
  plan.checkpointInterval = 7;
  const hy::WaterFlowAdvanceOutcome o =
    hy::WaterFlowAdvanceTo(looped, plan, hy::WaterFlowAdvanceCPU);
  EXPECT_TRUE(o.stopped);
  EXPECT_EQ(o.reason, hy::WaterFlowStopReason::AutoStop);
  EXPECT_EQ(looped.Iterations(), run.Iterations());
  hy::WaterFlowSimulation unruled = v.Make();
  plan.applyRules = false;
  plan.target = run.Iterations() + 5;
  EXPECT_FALSE(hy::WaterFlowAdvanceTo(unruled, plan, hy::WaterFlowAdvanceCPU).stopped);
  EXPECT_EQ(unruled.Iterations(), run.Iterations() + 5);
}

TEST(WaterFlowRun, DischargeRateLeavesTheStateAsItFoundIt)
{
  Valley v;
  hy::WaterFlowSimulation a = v.Make();
  hy::WaterFlowSimulation b = v.Make();
  for (hy::WaterFlowSimulation* s : { &a, &b })
  {
    s->SetRain(1e-4);
    s->SetNetFlux(true);
    for (int k = 0; k < 40; ++k)
    {
      s->Step();
    }
  }
  const std::vector<float> before = Depth(a);
  const std::size_t n = 9 * 12;
  std::vector<double> rate(n);
  std::vector<std::int8_t> dominant(n);
  hy::WaterFlowDischargeRate(a, 6, 60.0, rate.data(), dominant.data());
  EXPECT_EQ(a.Iterations(), 40);
  EXPECT_EQ(Depth(a), before);
  EXPECT_EQ(a.MovedHistory().size(), 40u);
  // The rate is the net discharge of 6 further iterations from zeroed edge sums, per second.
  std::fill(b.PaddedEdges().begin(), b.PaddedEdges().end(), 0.0);
  for (int k = 0; k < 6; ++k)
  {
    b.Step();
  }
  std::vector<double> net(n);
  std::vector<std::int8_t> dominantB(n);
  b.GetNetDischarge(net.data(), dominantB.data());
  for (std::size_t c = 0; c < n; ++c)
  {
    EXPECT_EQ(rate[c], net[c] / 60.0) << c;
  }
  EXPECT_EQ(dominant, dominantB);
  // The thalweg carries water south: its outlet cell (column 4, row 0) has the largest rate.
  EXPECT_EQ(std::max_element(rate.begin(), rate.end()) - rate.begin(), 4);
}

TEST(WaterFlowRun, BadArguments)
{
  Valley v;
  hy::WaterFlowSimulation sim = v.Make();
  hy::WaterFlowAdvancePlan plan;
  plan.target = 5;
  plan.checkpointInterval = 0;
  EXPECT_THROW(hy::WaterFlowAdvanceTo(sim, plan, hy::WaterFlowAdvanceCPU), std::invalid_argument);
  std::vector<double> rate(9 * 12);
  EXPECT_THROW(hy::WaterFlowDischargeRate(sim, 3, 10.0, rate.data(), nullptr),
    std::invalid_argument); // no net flux
  sim.SetNetFlux(true);
  EXPECT_THROW(
    hy::WaterFlowDischargeRate(sim, 0, 10.0, rate.data(), nullptr), std::invalid_argument);
  hy::WaterFlowStopRule rule;
  rule.balanceTolerance = 1.0;
  EXPECT_THROW(hy::CheckWaterFlowStopRule(rule), std::invalid_argument);
  rule.balanceTolerance = 0.5;
  EXPECT_NO_THROW(hy::CheckWaterFlowStopRule(rule));
}

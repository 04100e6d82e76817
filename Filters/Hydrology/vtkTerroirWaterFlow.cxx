#include "vtkTerroirWaterFlow.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"
#include "vtkTerroirComputeContext.h"
#include "vtkTerroirTerrainInput.h"
#include "vtkUnsignedCharArray.h"

#include "DepressionWaterBodies.h"
#include "PriorityFlood.h"
#include "RiverValidation.h"
#include "WaterFlow.h"
#include "WaterFlowRun.h"
#include "WaterFlowWarmStart.h"
#include "vtkTerroirWaterFlowGPU.h"

#include "NumberText.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <new>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkTerroirWaterFlow);

namespace hy = terroir::hydrology;

/// The cached simulation and its checkpoints.
struct vtkTerroirWaterFlow::Cache
{
  std::unique_ptr<hy::WaterFlowSimulation> Sim;
  vtkMTimeType InputTime = 0;
  vtkMTimeType FilterTime = 0;
  vtkImageData* Input = nullptr;
  hy::WaterFlowCheckpoints Checkpoints;
  std::vector<std::uint8_t> Lake;                ///< Rivers mode: 1 on the lakes (LakeMask)
  std::vector<hy::WaterFlowWarmStartLevel> Warm; ///< Rivers mode: the warm start's levels
};

namespace
{
/// Advances on the GPU (`runGPU`: the filter's RunGPUPath) while `gpu`; a fallback to the CPU
/// clears it and goes on from where the state stood; a failed GPU request (reported) sets
/// `failed` and stops.
hy::WaterFlowAdvance BackendAdvance(const std::function<int(const std::function<void()>&)>& runGPU,
  bool& gpu,
  bool& failed)
{
  return [runGPU, &gpu, &failed](hy::WaterFlowSimulation& sim,
           long long until,
           bool applyRules,
           const hy::WaterFlowStopRule& rule,
           hy::WaterFlowStopReason& reason)
  {
    if (gpu && !failed)
    {
      hy::WaterFlowGPUResult result;
      const int ran = runGPU([&] { result = hy::RunWaterFlowGPU(sim, until, applyRules, rule); });
      failed = ran < 0;
      if (ran == vtkTerroirComputeContext::GPU)
      {
        reason = result.reason;
        return result.stopped;
      }
      gpu = false;
    }
    return failed || hy::WaterFlowAdvanceCPU(sim, until, applyRules, rule, reason);
  };
}

vtkSmartPointer<vtkDoubleArray> Scalar(const char* name, double value, const char* units)
{
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  a->InsertNextValue(value);
  if (units)
  {
    a->GetInformation()->Set(vtkDataArray::UNITS_LABEL(), units);
  }
  return a;
}
} // namespace

//------------------------------------------------------------------------------
vtkTerroirWaterFlow::vtkTerroirWaterFlow()
  : State(new Cache)
{
  this->SetInputArrayToProcess(1, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "StandingWater");
}

//------------------------------------------------------------------------------
vtkTerroirWaterFlow::~vtkTerroirWaterFlow() = default;

//------------------------------------------------------------------------------
void vtkTerroirWaterFlow::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "WaterSource: " << this->WaterSource << "\n";
  os << indent << "InitialWater: " << this->InitialWater << " mm\n";
  os << indent << "Month: " << this->Month << "\n";
  os << indent << "AutoStopRatio: " << this->AutoStopRatio << "\n";
  os << indent << "MaximumIterations: " << this->MaximumIterations << "\n";
  os << indent << "MaximumSimulatedTime: " << this->MaximumSimulatedTime << " s\n";
  os << indent << "IterationDuration: " << this->IterationDuration << " s\n";
  os << indent << "RiverThreshold: " << this->RiverThreshold << " m3\n";
  os << indent << "TimeStepStride: " << this->TimeStepStride << "\n";
  os << indent << "CheckpointInterval: " << this->CheckpointInterval << "\n";
  os << indent << "CheckpointMemory: " << this->CheckpointMemory << " MiB\n";
  os << indent << "IterationEventInterval: " << this->IterationEventInterval << "\n";
  os << indent << "Mode: " << (this->Mode == Rivers ? "Rivers" : "Pulse") << "\n";
  os << indent << "LongCapacityRule: " << this->LongCapacityRule << "\n";
  os << indent << "CountEmptiedCells: " << this->CountEmptiedCells << "\n";
  os << indent << "RainRate: " << this->RainRate << " mm/h\n";
  os << indent << "BalanceTolerance: " << this->BalanceTolerance << "\n";
  os << indent << "RateIterations: " << this->RateIterations << "\n";
  os << indent << "LakeArea: " << this->LakeArea << " m2\n";
  os << indent << "RiverArea: " << this->RiverArea << " m2\n";
  os << indent << "ThinningFactor: " << this->ThinningFactor << "\n";
  os << indent << "WarmStart: " << this->WarmStart << "\n";
  os << indent << "WarmStartSide: " << this->WarmStartSide << "\n";
  os << indent << "SettleIterations: " << this->SettleIterations << "\n";
}

//------------------------------------------------------------------------------
bool vtkTerroirWaterFlow::GetCurrentWaterHeight(vtkFloatArray* out)
{
  const hy::WaterFlowSimulation* sim = this->State->Sim.get();
  if (!sim || !out)
  {
    return false;
  }
  out->SetNumberOfComponents(1);
  out->SetNumberOfTuples(static_cast<vtkIdType>(sim->Nx()) * sim->Ny());
  sim->GetWaterHeight(out->GetPointer(0));
  out->Modified();
  return true;
}

//------------------------------------------------------------------------------
double vtkTerroirWaterFlow::EstimateMemory(double nx, double ny)
{
  // Padded state: terrain 4, cell flag 1, water 8 + 8 (ping-pong), discharge 8; input water 4;
  // outputs: WaterHeight 4, Discharge 8, River 1. Checkpoints are bounded separately.
  const double padded = (nx + 2.0) * (ny + 2.0);
  if (this->Mode == Rivers)
  {
    // Also: net-flux edge sums 32 (and their copy for the rate window 32), water and discharge
    // copies 16, rain per cell 8 (StandingWater sources); Priority-Flood and the lakes while
    // the state is set up (about 20); outputs DischargeRate 8, RiverStrength 8, LakeMask 1,
    // the dominant directions 1.
    // The warm start's levels (at most a third of the cells in all, one level's state and
    // fill at a time plus the refinement's arrays of each): about 20 bytes per cell.
    return padded * (29.0 + 32.0 + 32.0 + 16.0 + 8.0) +
      nx * ny * (17.0 + 20.0 + 18.0 + (this->WarmStart ? 20.0 : 0.0));
  }
  return padded * 29.0 + nx * ny * 17.0;
}

//------------------------------------------------------------------------------
std::string vtkTerroirWaterFlow::CheckParameters()
{
  if (!(std::isfinite(this->InitialWater) && this->InitialWater >= 0.0))
  {
    return "InitialWater " + terroir::NumberText(this->InitialWater) +
      " mm must be a finite number >= 0";
  }
  if (this->Month < 1 || this->Month > 12)
  {
    return "Month " + std::to_string(this->Month) + " must be 1 (January) to 12 (December)";
  }
  if (!(this->AutoStopRatio >= 0.0 && this->AutoStopRatio < 1.0))
  {
    return "AutoStopRatio " + terroir::NumberText(this->AutoStopRatio) + " must be in [0, 1)";
  }
  if (this->MaximumIterations < 0)
  {
    return "MaximumIterations " + std::to_string(this->MaximumIterations) + " must be >= 0";
  }
  if (!(std::isfinite(this->MaximumSimulatedTime) && this->MaximumSimulatedTime >= 0.0))
  {
    return "MaximumSimulatedTime " + terroir::NumberText(this->MaximumSimulatedTime) +
      " s must be a finite number >= 0";
  }
  if (!(std::isfinite(this->IterationDuration) && this->IterationDuration > 0.0))
  {
    return "IterationDuration " + terroir::NumberText(this->IterationDuration) +
      " s must be a finite number > 0";
  }
  if (!(this->RiverThreshold >= 0.0) || std::isnan(this->RiverThreshold))
  {
    return "RiverThreshold " + terroir::NumberText(this->RiverThreshold) + " m3 must be >= 0";
  }
  if (!(std::isfinite(this->RainRate) && this->RainRate > 0.0))
  {
    return "RainRate " + terroir::NumberText(this->RainRate) + " mm/h must be a finite number > 0";
  }
  if (!(this->BalanceTolerance > 0.0 && this->BalanceTolerance < 1.0))
  {
    return "BalanceTolerance " + terroir::NumberText(this->BalanceTolerance) + " must be in (0, 1)";
  }
  if (this->RateIterations < 1)
  {
    return "RateIterations " + std::to_string(this->RateIterations) + " must be >= 1";
  }
  if (!(std::isfinite(this->LakeArea) && this->LakeArea >= 0.0))
  {
    return "LakeArea " + terroir::NumberText(this->LakeArea) + " m2 must be a finite number >= 0";
  }
  if (!(this->ThinningFactor >= 0.0 && this->ThinningFactor <= 1.0))
  {
    return "ThinningFactor " + terroir::NumberText(this->ThinningFactor) + " must be in [0, 1]";
  }
  if (this->WarmStartSide < 2 || this->SettleIterations < 0)
  {
    return "WarmStartSide " + std::to_string(this->WarmStartSide) + " must be >= 2 and " +
      "SettleIterations " + std::to_string(this->SettleIterations) + " >= 0";
  }
  if (!(std::isfinite(this->RiverArea) && this->RiverArea >= 0.0))
  {
    return "RiverArea " + terroir::NumberText(this->RiverArea) + " m2 must be a finite number >= 0";
  }
  if (this->TimeStepStride < 1 || this->CheckpointInterval < 1)
  {
    return "TimeStepStride and CheckpointInterval must be >= 1";
  }
  if (!(std::isfinite(this->CheckpointMemory) && this->CheckpointMemory >= 0.0))
  {
    return "CheckpointMemory " + terroir::NumberText(this->CheckpointMemory) + " MiB must be >= 0";
  }
  return std::string();
}

//------------------------------------------------------------------------------
int vtkTerroirWaterFlow::RequestInformation(vtkInformation* request,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  if (!this->Superclass::RequestInformation(request, inputVector, outputVector))
  {
    return 0;
  }
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  const vtkIdType last = std::max<vtkIdType>(this->MaximumIterations, 0);
  const vtkIdType stride = std::max<vtkIdType>(this->TimeStepStride, 1);
  std::vector<double> steps;
  for (vtkIdType t = 0; t < last; t += stride)
  {
    steps.push_back(static_cast<double>(t));
  }
  steps.push_back(static_cast<double>(last));
  outInfo->Set(
    vtkStreamingDemandDrivenPipeline::TIME_STEPS(), steps.data(), static_cast<int>(steps.size()));
  const double range[2] = { 0.0, static_cast<double>(last) };
  outInfo->Set(vtkStreamingDemandDrivenPipeline::TIME_RANGE(), range, 2);
  return 1;
}

//------------------------------------------------------------------------------
//------------------------------------------------------------------------------
bool vtkTerroirWaterFlow::PrepareWater(vtkImageData* input,
  const terroir::GridView<float>& v,
  std::vector<double>& water,
  std::vector<double>& rain)
{
  const std::size_t n = v.Size();
  Cache& cache = *this->State;
  // Initial water, metres, every check before the simulation exists.
  water.assign(n, 0.0);
  vtkDataArray* standing = nullptr;
  if (this->WaterSource != Constant)
  {
    standing = this->GetInputArrayToProcess(1, input);
    if (!standing || standing->GetNumberOfComponents() != 12 ||
      standing->GetNumberOfTuples() != static_cast<vtkIdType>(n))
    {
      vtkErrorMacro(<< this->SourcePrefix(input)
                    << "the StandingWater sources need a point array `StandingWater` with 12 "
                       "components (mm, from vtkTerroirSoilHumidity)");
      return false;
    }
  }
  std::vector<float> spill;
  rain.assign(this->Mode == Rivers && this->WaterSource != Constant ? n : 0, 0.0);
  if (this->Mode == Rivers)
  {
    // Still water first: every depression full to its spill level (Priority-Flood), the
    // state rain alone reaches at steady state; the run then only has to form the flow.
    spill.resize(n);
    hy::PriorityFloodBarnes2014(v, spill.data());
    // Lakes: the filled depressions and the flat water surfaces (hydro-flattened lakes) of
    // at least LakeArea, as vtkTerroirFloodFill's FillDepressions finds them.
    hy::DepressionWaterBodyOptions lakeOptions;
    lakeOptions.minimumArea = this->LakeArea;
    std::vector<std::int32_t> ids(n, 0);
    std::vector<float> depth(n, 0.0f);
    hy::DepressionWaterBodies(v, spill.data(), lakeOptions, ids.data(), depth.data());
    cache.Lake.assign(n, 0);
    for (std::size_t c = 0; c < n; ++c)
    {
      cache.Lake[c] = ids[c] > 0 ? 1 : 0;
    }
  }
  for (std::size_t c = 0; c < n; ++c)
  {
    const bool valid = (!v.valid || v.valid[c]) && std::isfinite(v.data[c]);
    if (!valid)
    {
      continue;
    }
    if (this->Mode == Rivers)
    {
      water[c] = std::max(0.0, static_cast<double>(spill[c]) - static_cast<double>(v.data[c]));
      if (this->WaterSource == Constant)
      {
        continue; // uniform rain, RainRate
      }
    }
    double mm = this->InitialWater;
    if (this->WaterSource == StandingWaterMonth)
    {
      mm = standing->GetComponent(static_cast<vtkIdType>(c), this->Month - 1);
    }
    else if (this->WaterSource == StandingWaterAnnual)
    {
      mm = 0.0;
      for (int m = 0; m < 12; ++m)
      {
        mm += standing->GetComponent(static_cast<vtkIdType>(c), m);
      }
    }
    if (!(std::isfinite(mm) && mm >= 0.0))
    {
      vtkErrorMacro(<< this->SourcePrefix(input) << "water " << terroir::NumberText(mm)
                    << " mm at cell (" << c % v.nx << ", " << c / v.nx
                    << ") is negative or not a number: water depths must be >= 0");
      return false;
    }
    if (this->Mode == Rivers)
    {
      // The month's (or the year's) standing water spread evenly over its hours, as rain per
      // iteration, metres.
      static const double kDays[12] = { 31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31 };
      const double hours =
        24.0 * (this->WaterSource == StandingWaterMonth ? kDays[this->Month - 1] : 365.0);
      rain[c] = mm / hours / 1000.0 / 3600.0 * this->IterationDuration;
      continue;
    }
    water[c] = mm / 1000.0;
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkTerroirWaterFlow::NewSimulation(vtkImageData* input,
  const terroir::TerrainInput& terrain,
  int backend)
{
  const auto runGPU = [this](const std::function<void()>& job) { return this->RunGPUPath(job); };
  const terroir::GridView<float>& v = terrain.view;
  Cache& cache = *this->State;
  // Initial water, metres, every check before the simulation exists.
  std::vector<double> water, rain;
  if (!this->PrepareWater(input, v, water, rain))
  {
    return false;
  }
  const double uniformRain = this->RainRate / 1000.0 / 3600.0 * this->IterationDuration;
  cache.Warm.clear();
  try
  {
    if (this->Mode == Rivers && this->WarmStart)
    {
      // Coarse-to-fine: each coarser level run to the balance on the chosen path.
      hy::WaterFlowWarmStartOptions warm;
      warm.coarsestSide = this->WarmStartSide;
      warm.settleIterations = this->SettleIterations;
      warm.rule.autoStopRatio = 0.0;
      warm.rule.balanceTolerance = this->BalanceTolerance;
      warm.rule.maximumIterations = this->MaximumIterations;
      bool gpuLevels = backend == vtkTerroirComputeContext::GPU;
      bool failed = false;
      const hy::WaterFlowAdvance advanceLevel = BackendAdvance(runGPU, gpuLevels, failed);
      const hy::WaterFlowLevelRun runLevel =
        [&](hy::WaterFlowSimulation& level, const hy::WaterFlowStopRule& levelRule)
      {
        level.SetLongCapacityRule(this->LongCapacityRule != 0);
        hy::UseSMPTools(level);
        hy::WaterFlowStopReason why = hy::WaterFlowStopReason::MaximumIterations;
        advanceLevel(level, levelRule.maximumIterations, true, levelRule, why);
        return why;
      };
      cache.Warm = hy::WaterFlowWarmStart(
        v, water.data(), uniformRain, rain.empty() ? nullptr : rain.data(), warm, runLevel);
      if (failed)
      {
        return false; // the GPU request failed (reported)
      }
    }
    cache.Sim.reset(new hy::WaterFlowSimulation(v, water.data()));
    cache.Sim->SetLongCapacityRule(this->LongCapacityRule != 0);
    cache.Sim->SetCountEmptiedCells(this->CountEmptiedCells != 0);
    if (this->Mode == Rivers)
    {
      if (rain.empty())
      {
        cache.Sim->SetRain(uniformRain);
      }
      else
      {
        cache.Sim->SetRainField(rain.data());
      }
      cache.Sim->SetNetFlux(true);
    }
  }
  catch (const std::invalid_argument& e)
  {
    vtkErrorMacro(<< this->SourcePrefix(input) << e.what());
    return false;
  }
  cache.Checkpoints.Clear();
  cache.Input = input;
  cache.InputTime = input->GetMTime();
  cache.FilterTime = this->GetMTime();
  return true;
}

//------------------------------------------------------------------------------
bool vtkTerroirWaterFlow::Simulate(vtkImageData* input,
  const terroir::TerrainInput& terrain,
  int backend,
  RunInfo& run)
{
  const auto runGPU = [this](const std::function<void()>& job) { return this->RunGPUPath(job); };
  Cache& cache = *this->State;
  hy::WaterFlowSimulation& sim = *cache.Sim;
  hy::UseSMPTools(sim);

  // What to compute: a requested time step, or a run under the stop rules.
  vtkInformation* outInfo = this->GetOutputInformation(0);
  const bool timed = outInfo && outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP());
  hy::WaterFlowStopRule rule;
  rule.autoStopRatio = this->AutoStopRatio;
  rule.maximumIterations = this->MaximumIterations;
  rule.countEmptiedCells = this->CountEmptiedCells != 0;
  if (this->Mode == Rivers)
  {
    rule.autoStopRatio = 0.0; // steady rain moves the same every iteration
    rule.balanceTolerance = this->BalanceTolerance;
    rule.balanceAfter = cache.Warm.empty() ? 0 : this->SettleIterations;
  }
  bool bySimulatedTime = false;
  if (this->MaximumSimulatedTime > 0.0)
  {
    const double byTime = std::floor(this->MaximumSimulatedTime / this->IterationDuration);
    if (byTime < static_cast<double>(rule.maximumIterations))
    {
      rule.maximumIterations = static_cast<long long>(byTime);
      bySimulatedTime = true;
    }
  }
  long long target = rule.maximumIterations;
  bool applyRules = true;
  std::string reasonName;
  double requested = 0.0;
  if (timed)
  {
    requested = outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP());
    const double r = std::round(std::isfinite(requested) ? requested : 0.0);
    target = static_cast<long long>(
      std::min(std::max(r, 0.0), static_cast<double>(this->MaximumIterations)));
    applyRules = false;
    reasonName = "RequestedTime";
  }
  else
  {
    long long stop = 0;
    hy::WaterFlowStopReason reason;
    if (sim.FindStop(rule, stop, reason))
    {
      target = stop; // known from the cached history
      applyRules = false;
      reasonName = hy::WaterFlowStopReasonName(reason);
    }
  }

  // Go back to the nearest checkpoint when the cache is past the target.
  if (sim.Iterations() > target && !cache.Checkpoints.Restore(sim, target))
  {
    // Iteration 0: the initial state, rebuilt from the input.
    cache.Sim.reset();
    return this->NewSimulation(input, terrain, backend) &&
      this->Simulate(input, terrain, backend, run);
  }

  // The emptied-cell stop count runs on the CPU only: Auto uses the CPU, a GPU request fails.
  if (backend == vtkTerroirComputeContext::GPU && this->CountEmptiedCells && applyRules &&
    this->GetBackend() == vtkTerroirComputeContext::GPU)
  {
    vtkErrorMacro(<< this->SourcePrefix(input)
                  << "CountEmptiedCells (Long (2016)'s stop count) runs on the CPU path only");
    return false;
  }
  // Advance (WaterFlowRun.h), pausing at checkpoint and event iterations; the GPU path falls
  // back to the CPU from where it stood when the GPU is lost.
  bool gpu = backend == vtkTerroirComputeContext::GPU && !(this->CountEmptiedCells && applyRules);
  bool gpuFailed = false;
  const hy::WaterFlowAdvance advance = BackendAdvance(runGPU, gpu, gpuFailed);
  hy::WaterFlowAdvancePlan plan;
  plan.target = target;
  plan.applyRules = applyRules;
  plan.rule = rule;
  plan.checkpointInterval = this->CheckpointInterval;
  plan.eventInterval = this->IterationEventInterval;
  cache.Checkpoints.SetBudget(this->CheckpointMemory, sim);
  const long long first = sim.Iterations();
  const hy::WaterFlowAdvanceOutcome outcome = hy::WaterFlowAdvanceTo(sim,
    plan,
    advance,
    &cache.Checkpoints,
    [&](long long iterations, bool event)
    {
      this->UpdateProgress(
        0.05 + 0.9 * static_cast<double>(iterations) / static_cast<double>(std::max(target, 1LL)));
      if (event)
      {
        vtkIdType done = static_cast<vtkIdType>(iterations);
        this->InvokeEvent(IterationEvent, &done);
      }
    });
  if (gpuFailed)
  {
    return false;
  }
  const bool stopped = outcome.stopped;
  const hy::WaterFlowStopReason stopReason = outcome.reason;
  this->LastComputedIterations = static_cast<vtkIdType>(sim.Iterations() - first);
  if (reasonName.empty() || stopped)
  {
    if (stopped)
    {
      reasonName = hy::WaterFlowStopReasonName(stopReason);
    }
    else if (timed)
    {
      reasonName = "RequestedTime";
    }
    else
    {
      reasonName = bySimulatedTime ? "SimulatedTime" : "MaximumIterations";
    }
  }
  else if (reasonName == "MaximumIterations" && bySimulatedTime)
  {
    reasonName = "SimulatedTime";
  }
  run.ReasonName = reasonName;
  run.Timed = timed;
  run.Requested = requested;
  return true;
}

//------------------------------------------------------------------------------
void vtkTerroirWaterFlow::AddOutputs(vtkImageData* output,
  const terroir::GridView<float>& v,
  const RunInfo& run)
{
  const std::size_t n = v.Size();
  Cache& cache = *this->State;
  hy::WaterFlowSimulation& sim = *cache.Sim;
  // Rivers mode: the discharge rate, averaged over RateIterations more iterations of the
  // steady state (then the state goes back to where the run stopped).
  vtkSmartPointer<vtkDoubleArray> rate;
  vtkSmartPointer<vtkDoubleArray> strength;
  vtkSmartPointer<vtkUnsignedCharArray> body;
  if (this->Mode == Rivers)
  {
    rate = vtkSmartPointer<vtkDoubleArray>::New();
    rate->SetName(DischargeRateName());
    rate->SetNumberOfTuples(static_cast<vtkIdType>(n));
    rate->GetInformation()->Set(vtkDataArray::UNITS_LABEL(), "m3/s");
    double* qr = rate->GetPointer(0);
    std::vector<std::int8_t> dominant(n);
    hy::WaterFlowDischargeRate(sim,
      this->RateIterations,
      static_cast<double>(this->RateIterations) * this->IterationDuration,
      qr,
      dominant.data());
    strength = vtkSmartPointer<vtkDoubleArray>::New();
    strength->SetName(RiverStrengthName());
    strength->SetNumberOfTuples(static_cast<vtkIdType>(n));
    strength->GetInformation()->Set(vtkDataArray::UNITS_LABEL(), "m3/s");
    terroir::GridView<double> qv;
    qv.data = qr;
    qv.nx = v.nx;
    qv.ny = v.ny;
    hy::ThinAcrossFlow(qv, dominant.data(), this->ThinningFactor, strength->GetPointer(0));
    body = vtkSmartPointer<vtkUnsignedCharArray>::New();
    body->SetName(LakeMaskName());
    body->SetNumberOfTuples(static_cast<vtkIdType>(n));
    unsigned char* b = body->GetPointer(0);
    for (std::size_t c = 0; c < n; ++c)
    {
      b[c] = cache.Lake.size() == n ? cache.Lake[c] : 0;
    }
  }

  // Outputs.
  vtkSmartPointer<vtkFloatArray> height = vtkSmartPointer<vtkFloatArray>::Take(
    terroir::NewOutputArray(WaterHeightName(), 1, static_cast<long long>(n), "m"));
  sim.GetWaterHeight(height->GetPointer(0));
  auto discharge = vtkSmartPointer<vtkDoubleArray>::New();
  discharge->SetName(DischargeName());
  discharge->SetNumberOfTuples(static_cast<vtkIdType>(n));
  discharge->GetInformation()->Set(vtkDataArray::UNITS_LABEL(), "m3");
  if (sim.GetNetFlux())
  {
    sim.GetNetDischarge(discharge->GetPointer(0)); // Rivers mode: net flux only
  }
  else
  {
    sim.GetDischarge(discharge->GetPointer(0));
  }
  auto river = vtkSmartPointer<vtkUnsignedCharArray>::New();
  river->SetName(RiverName());
  river->SetNumberOfTuples(static_cast<vtkIdType>(n));
  const double* q = discharge->GetPointer(0);
  unsigned char* rv = river->GetPointer(0);
  if (rate)
  {
    // Rivers: crest cells of RiverStrength that carry the rain of RiverArea or more.
    std::vector<std::uint8_t> channel(n);
    terroir::GridView<double> qv;
    qv.data = strength->GetPointer(0);
    qv.nx = v.nx;
    qv.ny = v.ny;
    hy::ChannelCells(qv, channel.data());
    // m3/s: the mean rain rate (m/s) on RiverArea.
    const double least = this->RiverArea * sim.RainVolume() /
      std::max(sim.TotalCellArea(), 1e-300) / this->IterationDuration;
    const double* qr = rate->GetPointer(0);
    for (std::size_t c = 0; c < n; ++c)
    {
      rv[c] = channel[c] && qr[c] >= least && qr[c] > 0.0 ? 1 : 0;
    }
  }
  else
  {
    for (std::size_t c = 0; c < n; ++c)
    {
      rv[c] = q[c] >= this->RiverThreshold ? 1 : 0; // NaN (no data) is never a river
    }
  }
  output->GetPointData()->AddArray(height);
  output->GetPointData()->AddArray(discharge);
  output->GetPointData()->AddArray(river);
  if (rate)
  {
    output->GetPointData()->AddArray(rate);
    output->GetPointData()->AddArray(strength);
    output->GetPointData()->AddArray(body);
  }
  vtkFieldData* fd = output->GetFieldData();
  auto iterations = vtkSmartPointer<vtkIdTypeArray>::New();
  iterations->SetName(IterationsName());
  iterations->InsertNextValue(static_cast<vtkIdType>(sim.Iterations()));
  fd->AddArray(iterations);
  auto reason = vtkSmartPointer<vtkStringArray>::New();
  reason->SetName(StopReasonName());
  reason->InsertNextValue(run.ReasonName);
  fd->AddArray(reason);
  fd->AddArray(Scalar("WaterFlowSimulatedTime",
    static_cast<double>(sim.Iterations()) * this->IterationDuration,
    "s"));
  fd->AddArray(Scalar("WaterFlowInitialVolume", sim.InitialVolume(), "m3"));
  if (this->Mode == Rivers)
  {
    // The warm start's coarse levels, coarsest first: iterations and cells of each.
    auto levels = vtkSmartPointer<vtkIdTypeArray>::New();
    levels->SetName("WaterFlowWarmStartIterations");
    levels->SetNumberOfComponents(3);
    levels->GetInformation()->Set(vtkDataArray::UNITS_LABEL(), "iterations, nx, ny");
    for (const hy::WaterFlowWarmStartLevel& level : cache.Warm)
    {
      levels->InsertNextTuple3(static_cast<double>(level.iterations), level.nx, level.ny);
    }
    fd->AddArray(levels);
    fd->AddArray(Scalar(
      "WaterFlowRainVolume", sim.RainVolume() * static_cast<double>(sim.Iterations()), "m3"));
  }
  fd->AddArray(Scalar("WaterFlowStoredVolume", sim.StoredVolume(), "m3"));
  fd->AddArray(Scalar("WaterFlowOutflowVolume", sim.TotalOutflow(), "m3"));
  fd->AddArray(Scalar("WaterFlowMovedVolume", sim.TotalMoved(), "m3"));
  if (run.Timed)
  {
    output->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), run.Requested);
  }
}

//------------------------------------------------------------------------------
int vtkTerroirWaterFlow::RequestTerrainData(vtkImageData* input,
  const terroir::TerrainInput& terrain,
  vtkImageData* output)
{
  const int backend = this->SelectBackend(this->HasGPUPath());
  if (backend < 0)
  {
    return 0;
  }
  this->LastComputedIterations = 0;
  Cache& cache = *this->State;
  // A new input or new parameters start from scratch.
  if ((!cache.Sim || cache.Input != input || cache.InputTime != input->GetMTime() ||
        cache.FilterTime != this->GetMTime()) &&
    !this->NewSimulation(input, terrain, backend))
  {
    return 0;
  }
  RunInfo run;
  if (!this->Simulate(input, terrain, backend, run))
  {
    return 0;
  }
  this->AddOutputs(output, terrain.view, run);
  return 1;
}

#include "vtkTerroirWaterFlowGPU.h"

#include "vtkTerroirGPU.h"
#include "vtkTerroirWaterFlowCS.h"

#include "vtkSMPTools.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace terroir
{
namespace hydrology
{

namespace
{
/// Work-group size of Shaders/WaterFlow.comp (LOCAL_X, a power of two).
constexpr unsigned kLocalX = 256;
/// Doubles per padded row in the row buffer (binding 2, see the shader's header).
constexpr std::size_t kRowDoubles = 8;

/// Throws when one buffer of `bytes` exceeds the driver's SSBO size limit.
void CheckBufferSize(const char* what, std::size_t bytes, const gpu::Limits& limits)
{
  if (limits.MaxShaderStorageBlockSize > 0 &&
    bytes > static_cast<std::size_t>(limits.MaxShaderStorageBlockSize))
  {
    throw gpu::Error(std::string("WaterFlow.comp: the ") + what + " buffer needs " +
      std::to_string(bytes) + " bytes, more than GL_MAX_SHADER_STORAGE_BLOCK_SIZE (" +
      std::to_string(limits.MaxShaderStorageBlockSize) +
      " bytes); the grid is too large for the GPU path, use the CPU backend");
  }
}
/// Per padded row the closenesses, area ratios and area that RowBlock uses (the ratios divided
/// here, in double, exactly as the core divides them).
std::vector<double> RowData(const WaterFlowSimulation& sim)
{
  const std::size_t rows = static_cast<std::size_t>(sim.Ny()) + 2;
  const std::vector<double>& closeEW = sim.ClosenessEW();
  const std::vector<double>& closeNS = sim.ClosenessNS();
  const std::vector<double>& closeDiag = sim.ClosenessDiagonal();
  const std::vector<double>& area = sim.CellArea();
  std::vector<double> rowData(kRowDoubles * rows, 0.0);
  for (std::size_t r = 0; r < rows; ++r)
  {
    double* d = rowData.data() + kRowDoubles * r;
    d[0] = closeEW[r];
    d[1] = closeNS[r];
    d[2] = closeDiag[r];
    d[3] = r > 0 ? closeNS[r - 1] : 0.0;
    d[4] = r > 0 ? closeDiag[r - 1] : 0.0;
    d[5] = r + 1 < rows ? area[r + 1] / area[r] : 0.0;
    d[6] = r > 0 ? area[r - 1] / area[r] : 0.0;
    d[7] = area[r];
  }
  return rowData;
}

/**
 * Iterations of the next block: about half of those the automatic stop is still expected to
 * need, so that few iterations run past it (and are undone), and no more than `maxBlock`. The
 * expectation extrapolates the block's geometric decay of the moved volume (first to last
 * moved over `count` iterations) down to autoStopRatio times the total moved; without a decay
 * to go by the block doubles.
 */
std::size_t NextBlock(std::size_t length,
  std::size_t maxBlock,
  std::size_t count,
  double firstMoved,
  double lastMoved,
  double movedTotal,
  double autoStopRatio)
{
  if (count >= 2 && firstMoved > 0.0 && lastMoved > 0.0 && lastMoved < firstMoved &&
    autoStopRatio > 0.0)
  {
    const double decay = std::pow(lastMoved / firstMoved, 1.0 / static_cast<double>(count - 1));
    const double target = autoStopRatio * movedTotal;
    if (decay < 1.0 && target < lastMoved)
    {
      const double left = std::log(target / lastMoved) / std::log(decay);
      return std::max<std::size_t>(
        1, std::min(maxBlock, static_cast<std::size_t>(std::max(1.0, 0.5 * left))));
    }
    if (target >= lastMoved)
    {
      return 1; // the stop is due now
    }
  }
  return std::min(maxBlock, 2 * length);
}

/// RunWaterFlowGPU's argument checks (std::invalid_argument).
void CheckRunArguments(bool applyStopRules, const WaterFlowStopRule& rule, int checkEvery)
{
  if (checkEvery < 1)
  {
    throw std::invalid_argument(
      "water flow GPU: checkEvery must be at least 1, not " + std::to_string(checkEvery));
  }
  if (rule.countEmptiedCells && applyStopRules)
  {
    throw std::invalid_argument(
      "water flow GPU: the emptied-cell stop count runs on the CPU path only");
  }
  if (!(rule.autoStopRatio >= 0.0) ||
    !(rule.balanceTolerance >= 0.0 && rule.balanceTolerance < 1.0))
  {
    throw std::invalid_argument(
      "water flow GPU: negative or NaN auto-stop ratio, or balance tolerance not in [0, 1)");
  }
}

/// How the iterations over n padded cells are dispatched and read back.
struct DispatchPlan
{
  std::size_t gx = 0;         ///< work groups along x
  std::size_t gy = 0;         ///< and y
  std::size_t dispatched = 0; ///< gx * gy: partial volumes per iteration
  std::size_t maxBlock = 0;   ///< most iterations per read-back
};

/// The work groups (1-D, or gx x gy when the count exceeds the first dimension's limit) and the
/// iterations per read-back (at most checkEvery, fewer when the partials would not fit one
/// buffer), checked against the context's limits (gpu::Error).
DispatchPlan PlanDispatch(std::size_t n, const gpu::Limits& limits, int checkEvery)
{
  CheckBufferSize("water", n * sizeof(double), limits);
  if (n > 0xffffffffu - kLocalX)
  {
    throw gpu::Error("WaterFlow.comp: " + std::to_string(n) +
      " padded cells exceed the 32-bit cell index of the kernel");
  }
  DispatchPlan plan;
  const std::size_t groups = (n + kLocalX - 1) / kLocalX;
  const std::size_t maxX =
    limits.MaxWorkGroupCount[0] > 0 ? static_cast<std::size_t>(limits.MaxWorkGroupCount[0]) : 65535;
  const std::size_t maxY =
    limits.MaxWorkGroupCount[1] > 0 ? static_cast<std::size_t>(limits.MaxWorkGroupCount[1]) : 65535;
  plan.gx = std::min(groups, maxX);
  plan.gy = (groups + plan.gx - 1) / plan.gx;
  if (plan.gy > maxY)
  {
    throw gpu::Error("WaterFlow.comp: " + std::to_string(groups) +
      " work groups exceed GL_MAX_COMPUTE_WORK_GROUP_COUNT (" + std::to_string(maxX) + " x " +
      std::to_string(maxY) + ")");
  }
  plan.dispatched = plan.gx * plan.gy;
  // The length of each block adapts (NextBlock) up to maxBlock.
  std::size_t maxBlock = static_cast<std::size_t>(checkEvery);
  const std::size_t slotBytes = plan.dispatched * 2 * sizeof(double);
  if (limits.MaxShaderStorageBlockSize > 0)
  {
    maxBlock =
      std::min(maxBlock, static_cast<std::size_t>(limits.MaxShaderStorageBlockSize) / slotBytes);
  }
  plan.maxBlock = std::max<std::size_t>(maxBlock, 1);
  CheckBufferSize("partial volumes", plan.maxBlock * slotBytes, limits);
  return plan;
}

/// What a run changes, on the host: the simulation changes only when the whole run succeeded,
/// so the iterations are kept here (with the running total the stop rule needs, summed as
/// RecordIteration sums it) and the state is downloaded into copies.
struct HostState
{
  explicit HostState(WaterFlowSimulation& sim)
    : iterations(sim.Iterations())
    , movedTotal(sim.TotalMoved())
    , water(sim.PaddedWater())
    , discharge(sim.PaddedDischarge())
    , edges(sim.PaddedEdges())
    , withEdges(!edges.empty())
    , rain(sim.PaddedRain())
    , rainField(!rain.empty())
  {
    if (!this->rainField)
    {
      this->rain.assign(1, sim.GetRain());
    }
  }
  /// Swaps the state into `sim` and records the iterations there.
  void Commit(WaterFlowSimulation& sim)
  {
    sim.PaddedWater().swap(this->water);
    sim.PaddedDischarge().swap(this->discharge);
    if (this->withEdges)
    {
      sim.PaddedEdges().swap(this->edges);
    }
    for (const WaterFlowIteration& it : this->recorded)
    {
      sim.RecordIteration(it);
    }
  }

  std::vector<WaterFlowIteration> recorded;
  long long iterations;
  double movedTotal;
  std::vector<double> water;
  std::vector<double> discharge;
  std::vector<double> edges; ///< empty unless the net flux is on
  bool withEdges;
  /// Rain per padded cell (the simulation's field), or its uniform rain as one value.
  std::vector<double> rain;
  bool rainField;
};

/// The terrain, cell flags and row tables of a simulation on the device: they never change for
/// a simulation, so they stay resident under its id (one simulation at a time per key).
struct ResidentTables
{
  std::shared_ptr<gpu::StorageBuffer> terrain;
  std::shared_ptr<gpu::StorageBuffer> cell;
  std::shared_ptr<gpu::StorageBuffer> row;
};

/// The resident tables of `sim` (n padded cells in `rows` rows), uploaded when missing.
ResidentTables FindOrUploadTables(gpu::Context& ctx,
  const WaterFlowSimulation& sim,
  std::size_t n,
  std::size_t rows)
{
  static const char terrainTag = 0, cellTag = 0, rowTag = 0;
  const std::uint64_t id = sim.Id();
  ResidentTables t;
  t.terrain = ctx.FindResident(&terrainTag, id, n * sizeof(float));
  if (!t.terrain)
  {
    t.terrain = ctx.Resident(&terrainTag, id, n * sizeof(float), sim.PaddedTerrain().data());
  }
  t.cell = ctx.FindResident(&cellTag, id, ((n + 3) / 4) * sizeof(std::uint32_t));
  if (!t.cell)
  {
    const std::vector<std::uint32_t> cellWords =
      gpu::PackFlags(sim.PaddedIsCell().data(), sim.PaddedIsCell().size());
    t.cell = ctx.Resident(&cellTag, id, cellWords.size() * sizeof(std::uint32_t), cellWords.data());
  }
  t.row = ctx.FindResident(&rowTag, id, kRowDoubles * rows * sizeof(double));
  if (!t.row)
  {
    const std::vector<double> rowData = RowData(sim);
    t.row = ctx.Resident(&rowTag, id, rowData.size() * sizeof(double), rowData.data());
  }
  return t;
}

/**
 * One RunWaterFlowGPU inside the context's job: the device buffers, the two programs, and the
 * blocks of iterations in flight. Two blocks are in flight: each has its partial volumes and,
 * when a stop rule may undo its end, a snapshot of the water and discharge at its start.
 */
class GPURun
{
public:
  GPURun(gpu::Context& ctx,
    WaterFlowSimulation& sim,
    const DispatchPlan& plan,
    HostState& host,
    bool applyStopRules);
  /// Iterations up to targetIterations or, with stop rules, until one fires; the state is then
  /// downloaded into the host copies.
  void Run(long long targetIterations, const WaterFlowStopRule& rule, WaterFlowGPUResult& result);

private:
  /// A buffer of `bytes` for a kernel's output (undefined contents).
  static gpu::StorageBuffer Undefined(std::size_t bytes)
  {
    return gpu::StorageBuffer(bytes, gpu::Contents::Undefined);
  }
  /// A block of iterations issued together and read back together.
  struct Block
  {
    std::size_t count = 0; ///< iterations
    int start = 0;         ///< Water index holding the water at its start
    int ring = 0;          ///< its partials and snapshot buffers
    gpu::Fence done;       ///< after its last iteration
  };
  /// The uniforms of both programs and the bindings that never change.
  void SetUp(const WaterFlowSimulation& sim);
  /// One iteration (givers, then the gather into the other water buffer), its partial volumes
  /// into `slot` of `out`.
  void Iterate(std::size_t slot, gpu::StorageBuffer& out);
  /// Issues the next block (its snapshot first, when stop rules apply).
  void Issue(long long targetIterations);
  /// Puts the water, discharge and edge sums back as they were at the start of `b`.
  void Restore(const Block& b);
  /// Reads `block`'s volumes, records its iterations and applies the stop rules.
  void ReadBlock(const Block& block, const WaterFlowStopRule& rule, WaterFlowGPUResult& result);

  const WaterFlowSimulation& Sim;
  const DispatchPlan Plan;
  HostState& Host;
  const bool ApplyStopRules;
  const std::size_t N;             ///< padded cells
  const std::size_t CellBytes;     ///< one double per padded cell
  const std::size_t EdgeBytes;     ///< the edge sums (4 planes), or one double without them
  const std::size_t SnapBytes;     ///< a snapshot of water or discharge (stop rules only)
  const std::size_t SnapEdgeBytes; ///< a snapshot of the edge sums (stop rules and net flux)
  std::vector<double> PartialData;
  const ResidentTables Tables;
  gpu::StorageBuffer Water[2];
  gpu::StorageBuffer Level;
  gpu::StorageBuffer Scale;
  gpu::StorageBuffer Out;
  gpu::StorageBuffer Discharge;
  gpu::StorageBuffer Rain;
  gpu::StorageBuffer Edges;
  gpu::StorageBuffer PartialSums[2];
  gpu::StorageBuffer SnapWater[2];
  gpu::StorageBuffer SnapDischarge[2];
  gpu::StorageBuffer SnapEdges[2];
  gpu::Program& Givers;
  gpu::Program& Gather;
  int Current = 0; ///< Water[Current] holds the water after the iterations issued so far
  std::deque<Block> Flight;
  long long Issued;
  int Ring = 0;
  std::size_t Length;
};

//------------------------------------------------------------------------------
GPURun::GPURun(gpu::Context& ctx,
  WaterFlowSimulation& sim,
  const DispatchPlan& plan,
  HostState& host,
  bool applyStopRules)
  : Sim(sim)
  , Plan(plan)
  , Host(host)
  , ApplyStopRules(applyStopRules)
  , N(static_cast<std::size_t>(sim.Stride()) * (static_cast<std::size_t>(sim.Ny()) + 2))
  , CellBytes(this->N * sizeof(double))
  , EdgeBytes(host.withEdges ? 4 * this->CellBytes : sizeof(double))
  , SnapBytes(applyStopRules ? this->CellBytes : sizeof(double))
  , SnapEdgeBytes(applyStopRules && host.withEdges ? this->EdgeBytes : sizeof(double))
  , PartialData(plan.maxBlock * plan.dispatched * 2)
  , Tables(FindOrUploadTables(ctx, sim, this->N, static_cast<std::size_t>(sim.Ny()) + 2))
  , Water{ gpu::StorageBuffer(this->CellBytes, host.water.data()), Undefined(this->CellBytes) }
  , Level(Undefined(this->CellBytes))
  , Scale(Undefined(this->CellBytes))
  , Out(Undefined(this->CellBytes))
  , Discharge(this->CellBytes, host.discharge.data())
  , Rain(host.rain.size() * sizeof(double), host.rain.data())
  , Edges(this->EdgeBytes, host.withEdges ? host.edges.data() : host.rain.data())
  , PartialSums{ Undefined(this->PartialData.size() * sizeof(double)),
    Undefined(this->PartialData.size() * sizeof(double)) }
  , SnapWater{ Undefined(this->SnapBytes), Undefined(this->SnapBytes) }
  , SnapDischarge{ Undefined(this->SnapBytes), Undefined(this->SnapBytes) }
  , SnapEdges{ Undefined(this->SnapEdgeBytes), Undefined(this->SnapEdgeBytes) }
  , Givers(ctx.GetProgram("WaterFlow.comp",
      vtkTerroirWaterFlowCS,
      { "LOCAL_X 256", "WATERFLOW_GIVERS" }))
  , Gather(ctx.GetProgram("WaterFlow.comp", vtkTerroirWaterFlowCS, { "LOCAL_X 256" }))
  , Issued(host.iterations)
  , Length(std::min<std::size_t>(plan.maxBlock, applyStopRules ? 4 : plan.maxBlock))
{
  this->SetUp(sim);
}

//------------------------------------------------------------------------------
void GPURun::SetUp(const WaterFlowSimulation& sim)
{
  const std::size_t stride = static_cast<std::size_t>(sim.Stride());
  const std::size_t rows = static_cast<std::size_t>(sim.Ny()) + 2;
  for (auto* prog : { &this->Givers, &this->Gather })
  {
    prog->SetUInt("uStride", static_cast<unsigned>(stride));
    prog->SetUInt("uRows", static_cast<unsigned>(rows));
    prog->SetUInt("uCount", static_cast<unsigned>(this->N));
    prog->SetUInt("uGroups", static_cast<unsigned>(this->Plan.dispatched));
    prog->SetUInt("uEdges", this->Host.withEdges ? 1u : 0u);
    prog->SetUInt("uLongCapacity", sim.GetLongCapacityRule() ? 1u : 0u);
    prog->SetUInt("uRainField", this->Host.rainField ? 1u : 0u);
  }
  this->Tables.terrain->Bind(0);
  this->Tables.cell->Bind(1);
  this->Tables.row->Bind(2);
  this->Level.Bind(5);
  this->Scale.Bind(6);
  this->Out.Bind(7);
  this->Discharge.Bind(8);
  this->Rain.Bind(10);
  this->Edges.Bind(11);
}

//------------------------------------------------------------------------------
void GPURun::Iterate(std::size_t slot, gpu::StorageBuffer& out)
{
  const unsigned dx = static_cast<unsigned>(this->Plan.gx);
  const unsigned dy = static_cast<unsigned>(this->Plan.gy);
  this->Water[this->Current].Bind(3);
  this->Water[1 - this->Current].Bind(4);
  out.Bind(9);
  this->Givers.Dispatch(dx, dy);
  this->Gather.SetUInt("uSlot", static_cast<unsigned>(slot));
  this->Gather.Dispatch(dx, dy);
  this->Current = 1 - this->Current;
}

//------------------------------------------------------------------------------
void GPURun::Issue(long long targetIterations)
{
  Block b;
  b.count = static_cast<std::size_t>(
    std::min<long long>(static_cast<long long>(this->Length), targetIterations - this->Issued));
  b.start = this->Current;
  b.ring = this->Ring;
  this->Ring = 1 - this->Ring;
  if (this->ApplyStopRules)
  {
    this->SnapWater[b.ring].CopyFrom(this->Water[this->Current], this->CellBytes);
    this->SnapDischarge[b.ring].CopyFrom(this->Discharge, this->CellBytes);
    if (this->Host.withEdges)
    {
      this->SnapEdges[b.ring].CopyFrom(this->Edges, this->EdgeBytes);
    }
  }
  for (std::size_t k = 0; k < b.count; ++k)
  {
    this->Iterate(k, this->PartialSums[b.ring]);
  }
  b.done = gpu::Fence();
  this->Issued += static_cast<long long>(b.count);
  this->Flight.push_back(std::move(b));
}

//------------------------------------------------------------------------------
void GPURun::Restore(const Block& b)
{
  this->Water[b.start].CopyFrom(this->SnapWater[b.ring], this->CellBytes);
  this->Discharge.CopyFrom(this->SnapDischarge[b.ring], this->CellBytes);
  if (this->Host.withEdges)
  {
    this->Edges.CopyFrom(this->SnapEdges[b.ring], this->EdgeBytes);
  }
  this->Current = b.start;
}

//------------------------------------------------------------------------------
void GPURun::ReadBlock(const Block& block,
  const WaterFlowStopRule& rule,
  WaterFlowGPUResult& result)
{
  const std::size_t dispatched = this->Plan.dispatched;
  HostState& host = this->Host;
  this->PartialSums[block.ring].Download(
    this->PartialData.data(), block.count * dispatched * 2 * sizeof(double));
  double firstMoved = 0.0, lastMoved = 0.0;
  for (std::size_t b = 0; b < block.count; ++b)
  {
    WaterFlowIteration it;
    const double* p = this->PartialData.data() + b * dispatched * 2;
    for (std::size_t g = 0; g < dispatched; ++g)
    {
      it.moved += p[2 * g];
      it.outflow += p[2 * g + 1];
    }
    firstMoved = b == 0 ? it.moved : firstMoved;
    lastMoved = it.moved;
    const double before = host.movedTotal;
    host.movedTotal += it.moved;
    ++host.iterations;
    host.recorded.push_back(it);
    if (!this->ApplyStopRules)
    {
      continue;
    }
    result.stopped = this->Sim.StopsAfter(it, host.iterations, before, rule, result.reason);
    if (result.stopped)
    {
      if (b + 1 < block.count)
      {
        // Undo the block and run it again up to the stopping iteration (the kernels are
        // deterministic, so these are the iterations just recorded).
        this->Restore(block);
        for (std::size_t again = 0; again <= b; ++again)
        {
          this->Iterate(again, this->PartialSums[block.ring]);
        }
      }
      else if (!this->Flight.empty())
      {
        this->Restore(this->Flight.front()); // the next block's start is this block's end
      }
      this->Flight.clear();
      break;
    }
  }
  if (this->ApplyStopRules && !result.stopped)
  {
    this->Length = NextBlock(this->Length,
      this->Plan.maxBlock,
      block.count,
      firstMoved,
      lastMoved,
      host.movedTotal,
      rule.autoStopRatio);
  }
}

//------------------------------------------------------------------------------
void GPURun::Run(long long targetIterations,
  const WaterFlowStopRule& rule,
  WaterFlowGPUResult& result)
{
  while (!result.stopped)
  {
    // Keep the GPU one block ahead of the stop test: the next block runs while this one's
    // volumes are read (no wait for the GPU between blocks).
    while (this->Flight.size() < 2 && this->Issued < targetIterations)
    {
      this->Issue(targetIterations);
    }
    if (this->Flight.empty())
    {
      break;
    }
    Block block = std::move(this->Flight.front());
    this->Flight.pop_front();
    block.done.Wait();
    this->ReadBlock(block, rule, result);
  }
  this->Water[this->Current].Download(this->Host.water.data(), this->CellBytes);
  this->Discharge.Download(this->Host.discharge.data(), this->CellBytes);
  if (this->Host.withEdges)
  {
    this->Edges.Download(this->Host.edges.data(), this->EdgeBytes);
  }
}
} // namespace

//------------------------------------------------------------------------------
void UseSMPTools(WaterFlowSimulation& sim)
{
  sim.SetParallelFor(
    [](int begin, int end, const std::function<void(int, int)>& body)
    {
      const int grain =
        WaterFlowSimulation::BlockRows(end - begin, vtkSMPTools::GetEstimatedNumberOfThreads());
      vtkSMPTools::For(begin,
        end,
        grain,
        [&body](vtkIdType b, vtkIdType e) { body(static_cast<int>(b), static_cast<int>(e)); });
    });
}

//------------------------------------------------------------------------------
WaterFlowGPUResult RunWaterFlowGPU(WaterFlowSimulation& sim,
  long long targetIterations,
  bool applyStopRules,
  double autoStopRatio,
  int checkEvery)
{
  WaterFlowStopRule rule;
  rule.autoStopRatio = autoStopRatio;
  return RunWaterFlowGPU(sim, targetIterations, applyStopRules, rule, checkEvery);
}

//------------------------------------------------------------------------------
WaterFlowGPUResult RunWaterFlowGPU(WaterFlowSimulation& sim,
  long long targetIterations,
  bool applyStopRules,
  const WaterFlowStopRule& rule,
  int checkEvery)
{
  CheckRunArguments(applyStopRules, rule, checkEvery);
  WaterFlowGPUResult result;
  if (sim.Iterations() >= targetIterations)
  {
    return result;
  }
  const std::size_t n =
    static_cast<std::size_t>(sim.Stride()) * (static_cast<std::size_t>(sim.Ny()) + 2);
  auto& ctx = gpu::Context::Global();
  const DispatchPlan plan = PlanDispatch(n, ctx.GetLimits(), checkEvery);
  HostState host(sim);
  const double work =
    static_cast<double>(targetIterations - host.iterations) * static_cast<double>(n);
  ctx.Run("water flow",
    gpu::Context::Budget(work),
    [&]
    {
      GPURun run(ctx, sim, plan, host, applyStopRules);
      run.Run(targetIterations, rule, result);
    });
  host.Commit(sim);
  return result;
}

} // namespace hydrology
} // namespace terroir

#include "vtkTerroirWaterFlowGPU.h"

#include "vtkTerroirGPU.h"
#include "vtkTerroirWaterFlowCS.h"

#include "vtkSMPTools.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <deque>
#include <functional>
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
  const double autoStopRatio = rule.autoStopRatio;
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
  if (!(autoStopRatio >= 0.0) || !(rule.balanceTolerance >= 0.0 && rule.balanceTolerance < 1.0))
  {
    throw std::invalid_argument(
      "water flow GPU: negative or NaN auto-stop ratio, or balance tolerance not in [0, 1)");
  }
  WaterFlowGPUResult result;
  if (sim.Iterations() >= targetIterations)
  {
    return result;
  }

  const std::size_t stride = static_cast<std::size_t>(sim.Stride());
  const std::size_t rows = static_cast<std::size_t>(sim.Ny()) + 2;
  const std::size_t n = stride * rows;

  auto& ctx = gpu::Context::Global();
  const gpu::Limits limits = ctx.GetLimits();
  CheckBufferSize("water", n * sizeof(double), limits);
  if (n > 0xffffffffu - kLocalX)
  {
    throw gpu::Error("WaterFlow.comp: " + std::to_string(n) +
      " padded cells exceed the 32-bit cell index of the kernel");
  }

  // Work groups: 1-D, or gx x gy when the count exceeds the first dimension's limit.
  const std::size_t groups = (n + kLocalX - 1) / kLocalX;
  const std::size_t maxX =
    limits.MaxWorkGroupCount[0] > 0 ? static_cast<std::size_t>(limits.MaxWorkGroupCount[0]) : 65535;
  const std::size_t maxY =
    limits.MaxWorkGroupCount[1] > 0 ? static_cast<std::size_t>(limits.MaxWorkGroupCount[1]) : 65535;
  const std::size_t gx = std::min(groups, maxX);
  const std::size_t gy = (groups + gx - 1) / gx;
  if (gy > maxY)
  {
    throw gpu::Error("WaterFlow.comp: " + std::to_string(groups) +
      " work groups exceed GL_MAX_COMPUTE_WORK_GROUP_COUNT (" + std::to_string(maxX) + " x " +
      std::to_string(maxY) + ")");
  }
  const std::size_t dispatched = gx * gy;

  // Iterations per read-back: at most checkEvery, and fewer when the partials would not fit one
  // buffer; the length of each block adapts (NextBlock).
  std::size_t maxBlock = static_cast<std::size_t>(checkEvery);
  const std::size_t slotBytes = dispatched * 2 * sizeof(double);
  if (limits.MaxShaderStorageBlockSize > 0)
  {
    maxBlock =
      std::min(maxBlock, static_cast<std::size_t>(limits.MaxShaderStorageBlockSize) / slotBytes);
  }
  maxBlock = std::max<std::size_t>(maxBlock, 1);
  CheckBufferSize("partial volumes", maxBlock * slotBytes, limits);

  // The simulation changes only when the whole run succeeded: the iterations are kept here
  // (with the running total the stop rule needs, summed as RecordIteration sums it) and the
  // state is downloaded into copies.
  std::vector<WaterFlowIteration> recorded;
  long long iterations = sim.Iterations();
  double movedTotal = sim.TotalMoved();
  std::vector<double> water = sim.PaddedWater();
  std::vector<double> discharge = sim.PaddedDischarge();
  std::vector<double> edges = sim.PaddedEdges(); // empty unless the net flux is on
  const bool withEdges = !edges.empty();
  // Rain per padded cell (the simulation's field), or its uniform rain as one value.
  std::vector<double> rain = sim.PaddedRain();
  const bool rainField = !rain.empty();
  if (!rainField)
  {
    rain.assign(1, sim.GetRain());
  }
  std::vector<double> partials(maxBlock * dispatched * 2);
  const std::size_t cellBytes = n * sizeof(double);
  const double work = static_cast<double>(targetIterations - iterations) * static_cast<double>(n);

  ctx.Run("water flow",
    gpu::Context::Budget(work),
    [&]
    {
      // The terrain and the kernel's tables never change for a simulation: resident under its
      // id (one simulation at a time per key).
      static const char terrainTag = 0, cellTag = 0, rowTag = 0;
      const std::uint64_t id = sim.Id();
      auto bTerrain = ctx.FindResident(&terrainTag, id, n * sizeof(float));
      if (!bTerrain)
      {
        bTerrain = ctx.Resident(&terrainTag, id, n * sizeof(float), sim.PaddedTerrain().data());
      }
      auto bCell = ctx.FindResident(&cellTag, id, ((n + 3) / 4) * sizeof(std::uint32_t));
      if (!bCell)
      {
        const std::vector<std::uint32_t> cellWords =
          gpu::PackFlags(sim.PaddedIsCell().data(), sim.PaddedIsCell().size());
        bCell =
          ctx.Resident(&cellTag, id, cellWords.size() * sizeof(std::uint32_t), cellWords.data());
      }
      auto bRow = ctx.FindResident(&rowTag, id, kRowDoubles * rows * sizeof(double));
      if (!bRow)
      {
        const std::vector<double> rowData = RowData(sim);
        bRow = ctx.Resident(&rowTag, id, rowData.size() * sizeof(double), rowData.data());
      }
      const auto undefined = gpu::Contents::Undefined;
      gpu::StorageBuffer bWater[2] = { gpu::StorageBuffer(cellBytes, water.data()),
        gpu::StorageBuffer(cellBytes, undefined) };
      gpu::StorageBuffer bLevel(cellBytes, undefined);
      gpu::StorageBuffer bScale(cellBytes, undefined);
      gpu::StorageBuffer bOut(cellBytes, undefined);
      gpu::StorageBuffer bDischarge(cellBytes, discharge.data());
      gpu::StorageBuffer bRain(rain.size() * sizeof(double), rain.data());
      const std::size_t edgeBytes = withEdges ? 4 * cellBytes : sizeof(double);
      gpu::StorageBuffer bEdges(edgeBytes, withEdges ? edges.data() : rain.data());
      // Two blocks are in flight: each has its partial volumes and, when a stop rule may undo
      // its end, a snapshot of the water and discharge at its start.
      const std::size_t partialBytes = partials.size() * sizeof(double);
      gpu::StorageBuffer bPartials[2] = { gpu::StorageBuffer(partialBytes, undefined),
        gpu::StorageBuffer(partialBytes, undefined) };
      const std::size_t snapBytes = applyStopRules ? cellBytes : sizeof(double);
      gpu::StorageBuffer bSnapWater[2] = { gpu::StorageBuffer(snapBytes, undefined),
        gpu::StorageBuffer(snapBytes, undefined) };
      gpu::StorageBuffer bSnapDischarge[2] = { gpu::StorageBuffer(snapBytes, undefined),
        gpu::StorageBuffer(snapBytes, undefined) };
      const std::size_t snapEdgeBytes = applyStopRules && withEdges ? edgeBytes : sizeof(double);
      gpu::StorageBuffer bSnapEdges[2] = { gpu::StorageBuffer(snapEdgeBytes, undefined),
        gpu::StorageBuffer(snapEdgeBytes, undefined) };

      auto& givers = ctx.GetProgram(
        "WaterFlow.comp", vtkTerroirWaterFlowCS, { "LOCAL_X 256", "WATERFLOW_GIVERS" });
      auto& gather = ctx.GetProgram("WaterFlow.comp", vtkTerroirWaterFlowCS, { "LOCAL_X 256" });
      for (auto* prog : { &givers, &gather })
      {
        prog->SetUInt("uStride", static_cast<unsigned>(stride));
        prog->SetUInt("uRows", static_cast<unsigned>(rows));
        prog->SetUInt("uCount", static_cast<unsigned>(n));
        prog->SetUInt("uGroups", static_cast<unsigned>(dispatched));
        prog->SetUInt("uEdges", withEdges ? 1u : 0u);
        prog->SetUInt("uLongCapacity", sim.GetLongCapacityRule() ? 1u : 0u);
        prog->SetUInt("uRainField", rainField ? 1u : 0u);
      }
      bTerrain->Bind(0);
      bCell->Bind(1);
      bRow->Bind(2);
      bLevel.Bind(5);
      bScale.Bind(6);
      bOut.Bind(7);
      bDischarge.Bind(8);
      bRain.Bind(10);
      bEdges.Bind(11);
      const unsigned dx = static_cast<unsigned>(gx);
      const unsigned dy = static_cast<unsigned>(gy);

      int current = 0; // bWater[current] holds the water after the iterations issued so far
      auto iterate = [&](std::size_t slot, gpu::StorageBuffer& out)
      {
        bWater[current].Bind(3);
        bWater[1 - current].Bind(4);
        out.Bind(9);
        givers.Dispatch(dx, dy);
        gather.SetUInt("uSlot", static_cast<unsigned>(slot));
        gather.Dispatch(dx, dy);
        current = 1 - current;
      };

      struct Block
      {
        std::size_t count = 0; ///< iterations
        int start = 0;         ///< bWater index holding the water at its start
        int ring = 0;          ///< its partials and snapshot buffers
        gpu::Fence done;       ///< after its last iteration
      };
      std::deque<Block> flight;
      long long issued = iterations;
      int ring = 0;
      std::size_t length = std::min<std::size_t>(maxBlock, applyStopRules ? 4 : maxBlock);
      auto issue = [&]()
      {
        Block b;
        b.count = static_cast<std::size_t>(
          std::min<long long>(static_cast<long long>(length), targetIterations - issued));
        b.start = current;
        b.ring = ring;
        ring = 1 - ring;
        if (applyStopRules)
        {
          bSnapWater[b.ring].CopyFrom(bWater[current], cellBytes);
          bSnapDischarge[b.ring].CopyFrom(bDischarge, cellBytes);
          if (withEdges)
          {
            bSnapEdges[b.ring].CopyFrom(bEdges, edgeBytes);
          }
        }
        for (std::size_t k = 0; k < b.count; ++k)
        {
          iterate(k, bPartials[b.ring]);
        }
        b.done = gpu::Fence();
        issued += static_cast<long long>(b.count);
        flight.push_back(std::move(b));
      };
      auto restore = [&](const Block& b)
      {
        bWater[b.start].CopyFrom(bSnapWater[b.ring], cellBytes);
        bDischarge.CopyFrom(bSnapDischarge[b.ring], cellBytes);
        if (withEdges)
        {
          bEdges.CopyFrom(bSnapEdges[b.ring], edgeBytes);
        }
        current = b.start;
      };

      while (!result.stopped)
      {
        // Keep the GPU one block ahead of the stop test: the next block runs while this one's
        // volumes are read (no wait for the GPU between blocks).
        while (flight.size() < 2 && issued < targetIterations)
        {
          issue();
        }
        if (flight.empty())
        {
          break;
        }
        Block block = std::move(flight.front());
        flight.pop_front();
        block.done.Wait();
        bPartials[block.ring].Download(
          partials.data(), block.count * dispatched * 2 * sizeof(double));
        double firstMoved = 0.0, lastMoved = 0.0;
        for (std::size_t b = 0; b < block.count; ++b)
        {
          WaterFlowIteration it;
          const double* p = partials.data() + b * dispatched * 2;
          for (std::size_t g = 0; g < dispatched; ++g)
          {
            it.moved += p[2 * g];
            it.outflow += p[2 * g + 1];
          }
          firstMoved = b == 0 ? it.moved : firstMoved;
          lastMoved = it.moved;
          const double before = movedTotal;
          movedTotal += it.moved;
          ++iterations;
          recorded.push_back(it);
          if (!applyStopRules)
          {
            continue;
          }
          result.stopped = sim.StopsAfter(it, iterations, before, rule, result.reason);
          if (result.stopped)
          {
            if (b + 1 < block.count)
            {
              // Undo the block and run it again up to the stopping iteration (the kernels are
              // deterministic, so these are the iterations just recorded).
              restore(block);
              for (std::size_t again = 0; again <= b; ++again)
              {
                iterate(again, bPartials[block.ring]);
              }
            }
            else if (!flight.empty())
            {
              restore(flight.front()); // the next block's start is this block's end
            }
            flight.clear();
            break;
          }
        }
        if (applyStopRules && !result.stopped)
        {
          length = NextBlock(
            length, maxBlock, block.count, firstMoved, lastMoved, movedTotal, autoStopRatio);
        }
      }
      bWater[current].Download(water.data(), cellBytes);
      bDischarge.Download(discharge.data(), cellBytes);
      if (withEdges)
      {
        bEdges.Download(edges.data(), edgeBytes);
      }
    });
  sim.PaddedWater().swap(water);
  sim.PaddedDischarge().swap(discharge);
  if (withEdges)
  {
    sim.PaddedEdges().swap(edges);
  }
  for (const WaterFlowIteration& it : recorded)
  {
    sim.RecordIteration(it);
  }
  return result;
}

} // namespace hydrology
} // namespace terroir

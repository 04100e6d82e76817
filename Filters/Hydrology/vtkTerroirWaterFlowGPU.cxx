#include "vtkTerroirWaterFlowGPU.h"

#include "vtkTerroirGPU.h"
#include "vtkTerroirWaterFlowCS.h"

#include "vtkSMPTools.h"

#include <algorithm>
#include <cstdint>
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
  if (checkEvery < 1)
  {
    throw std::invalid_argument(
      "water flow GPU: checkEvery must be at least 1, not " + std::to_string(checkEvery));
  }
  if (!(autoStopRatio >= 0.0))
  {
    throw std::invalid_argument("water flow GPU: negative or NaN auto-stop ratio");
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

  // Iterations per read-back: checkEvery, or fewer when the partials would not fit one buffer.
  std::size_t block = static_cast<std::size_t>(checkEvery);
  const std::size_t slotBytes = dispatched * 2 * sizeof(double);
  if (limits.MaxShaderStorageBlockSize > 0)
  {
    block = std::min(block, static_cast<std::size_t>(limits.MaxShaderStorageBlockSize) / slotBytes);
  }
  block = std::max<std::size_t>(block, 1);
  CheckBufferSize("partial volumes", block * slotBytes, limits);

  // Inputs in the kernel's layouts: valid-cell bytes packed four to a word, and per padded row
  // the closenesses, area ratios and area that RowBlock uses (the ratios divided here, in
  // double, exactly as the core divides them).
  const std::vector<std::uint8_t>& isCell = sim.PaddedIsCell();
  std::vector<std::uint32_t> cellWords((n + 3) / 4, 0u);
  for (std::size_t c = 0; c < n; ++c)
  {
    cellWords[c / 4] |= static_cast<std::uint32_t>(isCell[c] ? 1u : 0u) << (8 * (c % 4));
  }
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

  // The simulation changes only when the whole run succeeded: the iterations are kept here
  // (with the running total the stop rule needs, summed as RecordIteration sums it) and the
  // state is downloaded into copies.
  std::vector<WaterFlowIteration> recorded;
  long long iterations = sim.Iterations();
  double movedTotal = sim.TotalMoved();
  std::vector<double> water = sim.PaddedWater();
  std::vector<double> discharge = sim.PaddedDischarge();
  std::vector<double> partials(block * dispatched * 2);
  const std::size_t cellBytes = n * sizeof(double);

  ctx.Run(
    [&]
    {
      gpu::StorageBuffer bTerrain(n * sizeof(float), sim.PaddedTerrain().data());
      gpu::StorageBuffer bCell(cellWords.size() * sizeof(std::uint32_t), cellWords.data());
      gpu::StorageBuffer bRow(rowData.size() * sizeof(double), rowData.data());
      gpu::StorageBuffer bWater[2] = { gpu::StorageBuffer(cellBytes, water.data()),
        gpu::StorageBuffer(cellBytes) };
      gpu::StorageBuffer bLevel(cellBytes);
      gpu::StorageBuffer bScale(cellBytes);
      gpu::StorageBuffer bOut(cellBytes);
      gpu::StorageBuffer bDischarge(cellBytes, discharge.data());
      gpu::StorageBuffer bPartials(partials.size() * sizeof(double));
      // The snapshot is only needed to undo the end of a block after a stop rule fired.
      gpu::StorageBuffer bSnapWater(applyStopRules ? cellBytes : sizeof(double));
      gpu::StorageBuffer bSnapDischarge(applyStopRules ? cellBytes : sizeof(double));

      auto& prog = ctx.GetProgram("WaterFlow.comp", vtkTerroirWaterFlowCS, { "LOCAL_X 256" });
      prog.Use();
      prog.SetUInt("uStride", static_cast<unsigned>(stride));
      prog.SetUInt("uRows", static_cast<unsigned>(rows));
      prog.SetUInt("uCount", static_cast<unsigned>(n));
      prog.SetUInt("uGroups", static_cast<unsigned>(dispatched));
      bTerrain.Bind(0);
      bCell.Bind(1);
      bRow.Bind(2);
      bLevel.Bind(5);
      bScale.Bind(6);
      bOut.Bind(7);
      bDischarge.Bind(8);
      bPartials.Bind(9);
      bSnapWater.Bind(10);
      bSnapDischarge.Bind(11);
      const unsigned dx = static_cast<unsigned>(gx);
      const unsigned dy = static_cast<unsigned>(gy);

      int current = 0; // bWater[current] holds the water now
      auto pass = [&](int which)
      {
        prog.SetInt("uPass", which);
        prog.Dispatch(dx, dy);
      };
      auto iterate = [&](std::size_t slot)
      {
        bWater[current].Bind(3);
        bWater[1 - current].Bind(4);
        pass(0);
        prog.SetUInt("uSlot", static_cast<unsigned>(slot));
        pass(1);
        current = 1 - current;
      };

      while (iterations < targetIterations && !result.stopped)
      {
        const std::size_t count = static_cast<std::size_t>(
          std::min<long long>(static_cast<long long>(block), targetIterations - iterations));
        const int snapshot = current;
        if (applyStopRules)
        {
          bWater[current].Bind(3);
          pass(2);
        }
        for (std::size_t b = 0; b < count; ++b)
        {
          iterate(b);
        }
        bPartials.Download(partials.data(), count * dispatched * 2 * sizeof(double));
        for (std::size_t b = 0; b < count; ++b)
        {
          WaterFlowIteration it;
          const double* p = partials.data() + b * dispatched * 2;
          for (std::size_t g = 0; g < dispatched; ++g)
          {
            it.moved += p[2 * g];
            it.outflow += p[2 * g + 1];
          }
          const double before = movedTotal;
          movedTotal += it.moved;
          ++iterations;
          recorded.push_back(it);
          if (!applyStopRules)
          {
            continue;
          }
          if (it.moved <= 0.0)
          {
            result.stopped = true;
            result.reason = WaterFlowStopReason::NoMovement;
          }
          else if (WaterFlowAutoStop(it.moved, before, autoStopRatio))
          {
            result.stopped = true;
            result.reason = WaterFlowStopReason::AutoStop;
          }
          if (result.stopped)
          {
            if (b + 1 < count)
            {
              // Undo the block and run it again up to the stopping iteration (the kernel is
              // deterministic, so these are the iterations just recorded).
              current = snapshot;
              bWater[current].Bind(4);
              pass(3);
              for (std::size_t again = 0; again <= b; ++again)
              {
                iterate(again);
              }
            }
            break;
          }
        }
      }
      bWater[current].Download(water.data(), cellBytes);
      bDischarge.Download(discharge.data(), cellBytes);
    });
  sim.PaddedWater().swap(water);
  sim.PaddedDischarge().swap(discharge);
  for (const WaterFlowIteration& it : recorded)
  {
    sim.RecordIteration(it);
  }
  return result;
}

} // namespace hydrology
} // namespace terroir

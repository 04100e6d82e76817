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

#include "vtkExtentTranslator.h"
#include "vtkNew.h"
#if VTK_MODULE_ENABLE_VTK_ParallelCore
#include "vtkMultiProcessController.h"
#include "vtkTerroirControllerTileExchange.h"
#endif
#if VTK_MODULE_ENABLE_VTK_ParallelMPI
#include "vtkMPICommunicator.h"
#include "vtkMPIController.h"
#endif

#include "DepressionWaterBodies.h"
#include "DistributedPriorityFlood.h"
#include "DistributedWaterFlowWarmStart.h"
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
#include <stdexcept>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkTerroirWaterFlow);

namespace hy = terroir::hydrology;

namespace
{
/// A point extent of the 2-D grid: i0..i1 x j0..j1, inclusive (empty when i0 > i1 or j0 > j1).
struct Box
{
  int i0 = 0, i1 = -1, j0 = 0, j1 = -1;
  bool Empty() const { return i0 > i1 || j0 > j1; }
  long long Cells() const
  {
    return this->Empty() ? 0 : static_cast<long long>(i1 - i0 + 1) * (j1 - j0 + 1);
  }
  Box Intersect(const Box& o) const
  {
    return { std::max(i0, o.i0), std::min(i1, o.i1), std::max(j0, o.j0), std::min(j1, o.j1) };
  }
  Box Grow(int r) const { return { i0 - r, i1 + r, j0 - r, j1 + r }; }
  bool Contains(const Box& o) const
  {
    return o.Empty() || (o.i0 >= i0 && o.i1 <= i1 && o.j0 >= j0 && o.j1 <= j1);
  }
};
} // namespace

/**
 * A distributed run's exchange for one piece: which cells of the padded arrays it sends to and
 * receives from each other process after every iteration, and the all-gather of the
 * iteration's sums. Every process builds the same lists from the pieces' extents. Over MPI the
 * messages are non-blocking, all posted before any is waited for; through another controller
 * the pairs are visited in one global order (the lower rank sends first), so blocking messages
 * cannot deadlock.
 */
struct vtkTerroirWaterFlowHalo
{
#if VTK_MODULE_ENABLE_VTK_ParallelCore
  vtkMultiProcessController* Controller = nullptr;
#endif
  int Rank = 0;
  int Processes = 1;
  Box Grid;                     ///< this process's grid (the input extent)
  Box Whole;                    ///< the whole grid's extent
  std::vector<Box> OwnedByRank; ///< every process's owned points, by rank
  std::vector<int> ReachByRank; ///< every process's refreshed rings (2 + its ghost levels)
  struct Link
  {
    int rank = 0;
    std::vector<std::size_t> send, receive; ///< padded indices
  };
  std::vector<Link> Links; ///< by rank
  std::vector<double> Buffer;
  std::vector<std::vector<double>> Outgoing, Incoming; ///< per link, MPI's non-blocking path
  long long CellsPerIteration = 0; ///< cells received per iteration (water), all links
  int Window[4] = { 0, 0, 0, 0 };  ///< WaterFlowSimulation::SetCountWindow's

  /// Refreshes the halo cells of `padded` (water, or discharge before the outputs): with an MPI
  /// controller, every receive and send posted at once (MPI's non-blocking calls) and then
  /// waited for; with another controller, blocking pairs in one global order.
  void Exchange(std::vector<double>& padded)
  {
#if VTK_MODULE_ENABLE_VTK_ParallelCore
    const int tag = 2517;
#if VTK_MODULE_ENABLE_VTK_ParallelMPI
    if (vtkMPIController* mpi = vtkMPIController::SafeDownCast(this->Controller))
    {
      const std::size_t n = this->Links.size();
      this->Outgoing.resize(n);
      this->Incoming.resize(n);
      std::vector<vtkMPICommunicator::Request> requests(2 * n);
      bool ok = true;
      for (std::size_t k = 0; k < n; ++k)
      {
        const Link& l = this->Links[k];
        this->Incoming[k].resize(l.receive.size());
        ok = mpi->NoBlockReceive(this->Incoming[k].data(),
               static_cast<int>(l.receive.size()),
               l.rank,
               tag,
               requests[2 * k]) != 0 &&
          ok;
      }
      for (std::size_t k = 0; k < n; ++k)
      {
        const Link& l = this->Links[k];
        std::vector<double>& out = this->Outgoing[k];
        out.resize(l.send.size());
        for (std::size_t c = 0; c < l.send.size(); ++c)
        {
          out[c] = padded[l.send[c]];
        }
        ok = mpi->NoBlockSend(
               out.data(), static_cast<int>(out.size()), l.rank, tag, requests[2 * k + 1]) != 0 &&
          ok;
      }
      if (n > 0 && !mpi->WaitAll(static_cast<int>(2 * n), requests.data()))
      {
        ok = false;
      }
      if (!ok)
      {
        throw std::runtime_error("water flow: the halo exchange over MPI failed");
      }
      for (std::size_t k = 0; k < n; ++k)
      {
        const Link& l = this->Links[k];
        for (std::size_t c = 0; c < l.receive.size(); ++c)
        {
          padded[l.receive[c]] = this->Incoming[k][c];
        }
      }
      return;
    }
#endif
    for (const Link& l : this->Links)
    {
      const bool sendFirst = this->Rank < l.rank;
      for (int step = 0; step < 2; ++step)
      {
        if ((step == 0) == sendFirst)
        {
          this->Buffer.resize(l.send.size());
          for (std::size_t k = 0; k < l.send.size(); ++k)
          {
            this->Buffer[k] = padded[l.send[k]];
          }
          if (!this->Controller->Send(
                this->Buffer.data(), static_cast<vtkIdType>(this->Buffer.size()), l.rank, tag))
          {
            throw std::runtime_error(
              "water flow: a halo send to process " + std::to_string(l.rank) + " failed");
          }
        }
        else
        {
          this->Buffer.resize(l.receive.size());
          if (!this->Controller->Receive(
                this->Buffer.data(), static_cast<vtkIdType>(this->Buffer.size()), l.rank, tag))
          {
            throw std::runtime_error(
              "water flow: a halo receive from process " + std::to_string(l.rank) + " failed");
          }
          for (std::size_t k = 0; k < l.receive.size(); ++k)
          {
            padded[l.receive[k]] = this->Buffer[k];
          }
        }
      }
    }
#else
    (void)padded;
#endif
  }

  /// Refreshes the halo cells of an unpadded nx * ny field (the grid's cells) as Exchange does.
  void ExchangeField(double* field, int nx, int ny)
  {
    const std::size_t stride = static_cast<std::size_t>(nx) + 2;
    std::vector<double> padded(stride * (static_cast<std::size_t>(ny) + 2), 0.0);
    for (int j = 0; j < ny; ++j)
    {
      std::copy(field + static_cast<std::size_t>(j) * nx,
        field + static_cast<std::size_t>(j + 1) * nx,
        padded.begin() + static_cast<std::ptrdiff_t>((j + 1) * stride + 1));
    }
    this->Exchange(padded);
    for (int j = 0; j < ny; ++j)
    {
      std::copy(padded.begin() + static_cast<std::ptrdiff_t>((j + 1) * stride + 1),
        padded.begin() + static_cast<std::ptrdiff_t>((j + 1) * stride + 1 + nx),
        field + static_cast<std::size_t>(j) * nx);
    }
  }

  /// True when `ok` is true on every process (every process must call it: a process that
  /// failed alone would leave the others waiting in the next exchange).
  bool AllOk(bool ok)
  {
#if VTK_MODULE_ENABLE_VTK_ParallelCore
    const int local = ok ? 1 : 0;
    int all = 0;
    if (!this->Controller->AllReduce(&local, &all, 1, vtkCommunicator::MIN_OP))
    {
      throw std::runtime_error("water flow: the all-reduce over the MPI processes failed");
    }
    return all == 1;
#else
    return ok;
#endif
  }

  /// The smallest of `value` over the processes.
  void Min(double* value)
  {
#if VTK_MODULE_ENABLE_VTK_ParallelCore
    const double local = *value;
    if (!this->Controller->AllReduce(&local, value, 1, vtkCommunicator::MIN_OP))
    {
      throw std::runtime_error("water flow: the all-reduce over the MPI processes failed");
    }
#else
    (void)value;
#endif
  }

  /// The sum over the processes of n values, added in rank order (the same bits everywhere).
  void Sum(double* values, int n)
  {
#if VTK_MODULE_ENABLE_VTK_ParallelCore
    std::vector<double> all(static_cast<std::size_t>(n) * this->Processes);
    if (!this->Controller->AllGather(values, all.data(), n))
    {
      throw std::runtime_error("water flow: the all-gather over the MPI processes failed");
    }
    for (int k = 0; k < n; ++k)
    {
      double total = 0.0;
      for (int p = 0; p < this->Processes; ++p)
      {
        total += all[static_cast<std::size_t>(p) * n + k];
      }
      values[k] = total;
    }
#else
    (void)values;
    (void)n;
#endif
  }
};

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
  std::shared_ptr<vtkTerroirWaterFlowHalo> Halo; ///< distributed run: this piece's exchange
  double InitialVolume = 0.0;                    ///< distributed run: over every piece
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

namespace
{
/// Piece `piece` of `pieces`: the points it owns (vtkTerroirImageAlgorithm::GetOwnedExtent).
Box OwnedBox(int piece, int pieces, const int whole[6])
{
  int e[6];
  vtkTerroirImageAlgorithm::GetOwnedExtent(piece, pieces, whole, e);
  return Box{ e[0], e[1], e[2], e[3] };
}
} // namespace

//------------------------------------------------------------------------------
int vtkTerroirWaterFlow::RequestUpdateExtent(vtkInformation* request,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
#if VTK_MODULE_ENABLE_VTK_ParallelCore
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  this->DistributedRun = this->RunsInPieces(outInfo) && GetDistributedController(outInfo);
#else
  this->DistributedRun = false;
#endif
  return this->Superclass::RequestUpdateExtent(request, inputVector, outputVector);
}

//------------------------------------------------------------------------------
bool vtkTerroirWaterFlow::RunsInPieces(vtkInformation* outInfo) const
{
  using SDDP = vtkStreamingDemandDrivenPipeline;
  if (this->Mode == Pulse || !this->WarmStart || this->WarmStartSide < 2)
  {
    return true; // (a side under 2: CheckParameters reports it on every process)
  }
  if (!outInfo || !outInfo->Has(SDDP::WHOLE_EXTENT()) ||
    !outInfo->Has(SDDP::UPDATE_NUMBER_OF_PIECES()))
  {
    return true; // not a distributed request: the caller's controller test decides
  }
  // Rivers with the warm start: in pieces when every coarse level keeps a cell in every piece.
  int whole[6];
  outInfo->Get(SDDP::WHOLE_EXTENT(), whole);
  const int pieces = outInfo->Get(SDDP::UPDATE_NUMBER_OF_PIECES());
  std::vector<hy::TileBox> owned;
  for (int p = 0; p < pieces; ++p)
  {
    const Box b = OwnedBox(p, pieces, whole);
    owned.push_back({ b.i0 - whole[0], b.i1 - whole[0], b.j0 - whole[2], b.j1 - whole[2] });
  }
  hy::WaterFlowWarmStartOptions warm;
  warm.coarsestSide = this->WarmStartSide;
  return hy::WaterFlowWarmStartFitsTiles(
    owned, whole[1] - whole[0] + 1, whole[3] - whole[2] + 1, warm);
}

//------------------------------------------------------------------------------
bool vtkTerroirWaterFlow::SetUpDistributed(vtkImageData* input)
{
  Cache& cache = *this->State;
  std::shared_ptr<vtkTerroirWaterFlowHalo> old = cache.Halo;
  cache.Halo.reset();
#if VTK_MODULE_ENABLE_VTK_ParallelCore
  using SDDP = vtkStreamingDemandDrivenPipeline;
  vtkInformation* outInfo = this->GetOutputInformation(0);
  vtkMultiProcessController* controller =
    this->RunsInPieces(outInfo) ? GetDistributedController(outInfo) : nullptr;
  if (!controller || !outInfo->Has(SDDP::WHOLE_EXTENT()))
  {
    if (old)
    {
      cache.Sim.reset(); // was distributed (its count window and hook), now serial
    }
    return true; // a serial run
  }
  auto halo = std::make_shared<vtkTerroirWaterFlowHalo>();
  halo->Controller = controller;
  halo->Rank = controller->GetLocalProcessId();
  halo->Processes = controller->GetNumberOfProcesses();
  int whole[6];
  outInfo->Get(SDDP::WHOLE_EXTENT(), whole);
  const int pieces = outInfo->Get(SDDP::UPDATE_NUMBER_OF_PIECES());
  const int piece = outInfo->Get(SDDP::UPDATE_PIECE_NUMBER());
  const int ghost = outInfo->Has(SDDP::UPDATE_NUMBER_OF_GHOST_LEVELS())
    ? outInfo->Get(SDDP::UPDATE_NUMBER_OF_GHOST_LEVELS())
    : 0;
  int e[6];
  input->GetExtent(e);
  halo->Grid = { e[0], e[1], e[2], e[3] };
  const Box wholeBox{ whole[0], whole[1], whole[2], whole[3] };
  // Cells within `reach` of the owned ones are refreshed every iteration: those the output
  // gives (the ghost levels asked) and the 2 rings that a cell's new depth reads (its
  // neighbours' flows, which read their neighbours' heights); one more ring is computed for the
  // heights of no-data cells there.
  const int reach = ghost + 2;
  const Box mine = OwnedBox(piece, pieces, whole);
  int local[6] = { piece, e[0], e[1], e[2], e[3], reach };
  std::vector<int> all(6 * static_cast<std::size_t>(halo->Processes));
  if (!controller->AllGather(local, all.data(), 6))
  {
    vtkErrorMacro(<< "the all-gather of the pieces' extents over the MPI processes failed");
    return false;
  }
  bool ok = halo->Grid.Contains(mine.Grow(reach + 1).Intersect(wholeBox));
  ok = halo->AllOk(ok); // every process fails together
  for (int p = 0; p < halo->Processes && ok; ++p)
  {
    const int* a = all.data() + 6 * p;
    ok = a[0] >= 0 && a[0] < pieces;
    for (int q = 0; q < p && ok; ++q)
    {
      ok = all[6 * q] != a[0]; // one piece per process
    }
  }
  if (!ok)
  {
    vtkErrorMacro(<< this->SourcePrefix(input) << "distributed water flow: piece " << piece
                  << " of " << pieces << " came without its halo of " << reach + 1
                  << " cells, or the processes do not hold one piece each");
    return false;
  }
  const int stride = halo->Grid.i1 - halo->Grid.i0 + 3;
  const auto padded = [&](int i, int j)
  {
    return static_cast<std::size_t>(j - halo->Grid.j0 + 1) * static_cast<std::size_t>(stride) +
      static_cast<std::size_t>(i - halo->Grid.i0 + 1);
  };
  const auto indices = [&](const Box& b, std::vector<std::size_t>& out)
  {
    for (int j = b.j0; !b.Empty() && j <= b.j1; ++j)
    {
      for (int i = b.i0; i <= b.i1; ++i)
      {
        out.push_back(padded(i, j));
      }
    }
  };
  halo->Whole = wholeBox;
  for (int p = 0; p < halo->Processes; ++p)
  {
    const int* a = all.data() + 6 * p;
    halo->OwnedByRank.push_back(OwnedBox(a[0], pieces, whole));
    halo->ReachByRank.push_back(a[5]);
  }
  for (int p = 0; p < halo->Processes; ++p)
  {
    if (p == halo->Rank)
    {
      continue;
    }
    const int* a = all.data() + 6 * p;
    const Box theirs = OwnedBox(a[0], pieces, whole);
    const Box theirGrid{ a[1], a[2], a[3], a[4] };
    vtkTerroirWaterFlowHalo::Link link;
    link.rank = p;
    indices(theirs.Intersect(mine.Grow(reach)).Intersect(halo->Grid), link.receive);
    indices(mine.Intersect(theirs.Grow(a[5])).Intersect(theirGrid), link.send);
    if (!link.receive.empty() || !link.send.empty())
    {
      halo->CellsPerIteration += static_cast<long long>(link.receive.size());
      halo->Links.push_back(std::move(link));
    }
  }
  // The window of the padded grid whose volumes this piece counts: its own cells, and the
  // grid's border on the sides its piece touches.
  const int nx = halo->Grid.i1 - halo->Grid.i0 + 1;
  const int ny = halo->Grid.j1 - halo->Grid.j0 + 1;
  halo->Window[0] = mine.i0 == whole[0] ? 0 : mine.i0 - halo->Grid.i0 + 1;
  halo->Window[1] = mine.i1 == whole[1] ? nx + 2 : mine.i1 - halo->Grid.i0 + 2;
  halo->Window[2] = mine.j0 == whole[2] ? 0 : mine.j0 - halo->Grid.j0 + 1;
  halo->Window[3] = mine.j1 == whole[3] ? ny + 2 : mine.j1 - halo->Grid.j0 + 2;
  if (old && old->Grid.i0 == halo->Grid.i0 && old->Grid.i1 == halo->Grid.i1 &&
    old->Grid.j0 == halo->Grid.j0 && old->Grid.j1 == halo->Grid.j1)
  {
    *old = std::move(*halo); // the cached simulation's hook keeps its object
    cache.Halo = old;
  }
  else
  {
    cache.Halo = halo;
    cache.Sim.reset(); // another piece: start again
  }
  vtkDebugMacro(<< "distributed water flow: process " << cache.Halo->Rank << ", grid " << nx
                << " x " << ny << ", " << cache.Halo->CellsPerIteration
                << " halo cells per iteration");
#else
  (void)input;
  (void)old;
#endif
  return true;
}

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
      if (cache.Halo && this->Mode == Rivers)
      {
        cache.Halo->AllOk(false); // the others wait for it before the still water
      }
      return false;
    }
  }
  std::vector<float> spill;
  rain.assign(this->Mode == Rivers && this->WaterSource != Constant ? n : 0, 0.0);
  if (this->Mode == Rivers)
  {
    // Still water first: every depression full to its spill level (Priority-Flood), the
    // state rain alone reaches at steady state; the run then only has to form the flow.
    // Lakes: the filled depressions and the flat water surfaces (hydro-flattened lakes) of
    // at least LakeArea, as vtkTerroirFloodFill's FillDepressions finds them.
    hy::DepressionWaterBodyOptions lakeOptions;
    lakeOptions.minimumArea = this->LakeArea;
    std::vector<std::int32_t> ids(n, 0);
    if (cache.Halo)
    {
      // In pieces: Barnes (2016)'s parallel fill and its water bodies on the piece and the
      // halo the iterations read (every process calls it: none may have failed before).
      if (!cache.Halo->AllOk(true))
      {
        vtkErrorMacro(<< this->SourcePrefix(input)
                      << "distributed water flow: another process failed to prepare its piece");
        return false;
      }
      if (!this->StillWaterInPieces(input, v, lakeOptions, spill, ids))
      {
        return false;
      }
    }
    else
    {
      spill.resize(n);
      hy::PriorityFloodBarnes2014(v, spill.data());
      std::vector<float> depth(n, 0.0f);
      hy::DepressionWaterBodies(v, spill.data(), lakeOptions, ids.data(), depth.data());
    }
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
bool vtkTerroirWaterFlow::StillWaterInPieces(vtkImageData* input,
  const terroir::GridView<float>& v,
  const terroir::hydrology::DepressionWaterBodyOptions& options,
  std::vector<float>& spill,
  std::vector<std::int32_t>& ids)
{
#if VTK_MODULE_ENABLE_VTK_ParallelCore
  vtkInformation* outInfo = this->GetOutputInformation(0);
  vtkTerroirControllerTileExchange exchange(GetDistributedController(outInfo));
  hy::DistributedFillInput in = vtkTerroirControllerTileExchange::TileInput(outInfo, input, v);
  in.reach += 1; // the 2 + g rings whose water every iteration reads (TileInput gives 1 + g)
  vtkDebugMacro(<< "still water in pieces: " << hy::kPriorityFloodBarnes2016Citation);
  std::string error;
  const bool ok = vtkTerroirControllerTileExchange::Run(
    [&]
    {
      hy::DistributedFillResult r = hy::FillDepressionsDistributed(in, options, exchange);
      spill = std::move(r.filled);
      ids = std::move(r.bodyId);
    },
    error);
  if (!ok)
  {
    vtkErrorMacro(<< this->SourcePrefix(input) << error);
  }
  return ok;
#else
  (void)v;
  (void)options;
  (void)spill;
  (void)ids;
  vtkErrorMacro(<< this->SourcePrefix(input) << "built without VTK::ParallelCore");
  return false;
#endif
}

//------------------------------------------------------------------------------
namespace
{
/// Rivers mode, WarmStart, in pieces: WaterFlowWarmStartDistributed on this piece (`v` is the
/// halo's grid), every process through the controller; false with `error` on any process's
/// failure (every process fails alike).
bool WarmStartInPieces(const vtkTerroirWaterFlowHalo& halo,
  const terroir::GridView<float>& v,
  std::vector<double>& water,
  double uniformRain,
  const std::vector<double>& rain,
  const hy::WaterFlowWarmStartOptions& options,
  const hy::WaterFlowLevelRun& runLevel,
  std::vector<hy::WaterFlowWarmStartLevel>& levels,
  std::string& error)
{
#if VTK_MODULE_ENABLE_VTK_ParallelCore
  const Box& w = halo.Whole;
  hy::WaterFlowWarmStartTile tile;
  tile.view = v;
  tile.gi0 = halo.Grid.i0 - w.i0;
  tile.gj0 = halo.Grid.j0 - w.j0;
  for (const Box& b : halo.OwnedByRank)
  {
    tile.owned.push_back({ b.i0 - w.i0, b.i1 - w.i0, b.j0 - w.j0, b.j1 - w.j0 });
  }
  tile.reach = halo.ReachByRank;
  tile.wholeNx = w.i1 - w.i0 + 1;
  tile.wholeNy = w.j1 - w.j0 + 1;
  vtkTerroirControllerTileExchange exchange(halo.Controller);
  return vtkTerroirControllerTileExchange::Run(
    [&]
    {
      levels = hy::WaterFlowWarmStartDistributed(tile,
        water.data(),
        uniformRain,
        rain.empty() ? nullptr : rain.data(),
        options,
        exchange,
        runLevel);
    },
    error);
#else
  (void)halo;
  (void)v;
  (void)water;
  (void)uniformRain;
  (void)rain;
  (void)options;
  (void)runLevel;
  (void)levels;
  error = "built without VTK::ParallelCore";
  return false;
#endif
}
} // namespace

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
  const bool prepared = this->PrepareWater(input, v, water, rain);
  if (cache.Halo && !cache.Halo->AllOk(prepared))
  {
    if (prepared)
    {
      vtkErrorMacro(<< this->SourcePrefix(input)
                    << "distributed water flow: another process failed to prepare its piece");
    }
    return false;
  }
  if (!prepared)
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
      if (cache.Halo)
      {
        std::string error;
        if (!WarmStartInPieces(
              *cache.Halo, v, water, uniformRain, rain, warm, runLevel, cache.Warm, error))
        {
          vtkErrorMacro(<< this->SourcePrefix(input) << error);
          return false;
        }
      }
      else
      {
        cache.Warm = hy::WaterFlowWarmStart(
          v, water.data(), uniformRain, rain.empty() ? nullptr : rain.data(), warm, runLevel);
      }
      if (failed)
      {
        return false; // the GPU request failed (reported)
      }
    }
    // A piece's closenesses are the whole grid's: d_min over every piece (an exact minimum).
    double dmin = 0.0;
    if (cache.Halo)
    {
      dmin = hy::WaterFlowSimulation::SmallestSpacing(v);
      cache.Halo->Min(&dmin);
    }
    cache.Sim.reset(new hy::WaterFlowSimulation(v, water.data(), dmin));
    if (cache.Halo)
    {
      // Distributed: count the owned cells, refresh the halo and add the sums of every piece
      // after each iteration.
      const int* w = cache.Halo->Window;
      cache.Sim->SetCountWindow(w[0], w[1], w[2], w[3]);
      Cache* c = &cache;
      cache.Sim->SetIterationHook(
        [c](hy::WaterFlowSimulation& sim, hy::WaterFlowIteration& it)
        {
          c->Halo->Exchange(sim.PaddedWater());
          double sums[3] = { it.moved, it.outflow, it.emptied };
          c->Halo->Sum(sums, 3);
          it.moved = sums[0];
          it.outflow = sums[1];
          it.emptied = sums[2];
        });
      cache.InitialVolume = cache.Sim->StoredVolume();
      cache.Halo->Sum(&cache.InitialVolume, 1);
    }
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
      if (cache.Halo)
      {
        // The balance rule and the rivers' least rate rest on the whole grid's rain.
        double totals[2] = { 0.0, 0.0 };
        cache.Sim->WindowRainTotals(totals[0], totals[1]);
        cache.Halo->Sum(totals, 2);
        cache.Sim->SetRainTotals(totals[0], totals[1]);
      }
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
  // A distributed run keeps no checkpoints: the pieces' budgets would differ, and a piece that
  // went back to one while another started over would not meet it at the same iteration.
  cache.Checkpoints.SetBudget(cache.Halo ? 0.0 : this->CheckpointMemory, sim);
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
    if (cache.Halo)
    {
      cache.Halo->ExchangeField(qr, v.nx, v.ny); // the owners' rates (see the strength below)
    }
    strength = vtkSmartPointer<vtkDoubleArray>::New();
    strength->SetName(RiverStrengthName());
    strength->SetNumberOfTuples(static_cast<vtkIdType>(n));
    strength->GetInformation()->Set(vtkDataArray::UNITS_LABEL(), "m3/s");
    terroir::GridView<double> qv;
    qv.data = qr;
    qv.nx = v.nx;
    qv.ny = v.ny;
    hy::ThinAcrossFlow(qv, dominant.data(), this->ThinningFactor, strength->GetPointer(0));
    if (cache.Halo)
    {
      // The halo's strength from the processes that own those cells: a cell's net flux (its
      // rate and dominant direction) reads its neighbours' outflows, and the halo's outer
      // cells lack theirs.
      cache.Halo->ExchangeField(strength->GetPointer(0), v.nx, v.ny);
    }
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
  if (cache.Halo)
  {
    // The halo's discharge comes from the processes that own those cells.
    cache.Halo->Exchange(sim.PaddedDischarge());
  }
  auto discharge = vtkSmartPointer<vtkDoubleArray>::New();
  discharge->SetName(DischargeName());
  discharge->SetNumberOfTuples(static_cast<vtkIdType>(n));
  discharge->GetInformation()->Set(vtkDataArray::UNITS_LABEL(), "m3");
  if (sim.GetNetFlux())
  {
    sim.GetNetDischarge(discharge->GetPointer(0)); // Rivers mode: net flux only
    if (cache.Halo)
    {
      cache.Halo->ExchangeField(discharge->GetPointer(0), v.nx, v.ny);
    }
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
  fd->AddArray(
    Scalar("WaterFlowInitialVolume", cache.Halo ? cache.InitialVolume : sim.InitialVolume(), "m3"));
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
  double stored = sim.StoredVolume(); // the owned cells' in a distributed run
  if (cache.Halo)
  {
    cache.Halo->Sum(&stored, 1);
  }
  fd->AddArray(Scalar("WaterFlowStoredVolume", stored, "m3"));
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
  int backend = this->SelectBackend(this->HasGPUPath());
  if (backend < 0)
  {
    return 0;
  }
  this->LastComputedIterations = 0;
  Cache& cache = *this->State;
  try
  {
    if (!this->SetUpDistributed(input))
    {
      return 0;
    }
    if (cache.Halo)
    {
      backend = vtkTerroirComputeContext::CPU; // the distributed path runs on the CPU
    }
    return this->RunTerrainData(input, terrain, output, backend) ? 1 : 0;
  }
  catch (const std::runtime_error& e)
  {
    cache.Sim.reset();
    vtkErrorMacro(<< this->SourcePrefix(input) << e.what());
    return 0;
  }
}

//------------------------------------------------------------------------------
bool vtkTerroirWaterFlow::RunTerrainData(vtkImageData* input,
  const terroir::TerrainInput& terrain,
  vtkImageData* output,
  int backend)
{
  Cache& cache = *this->State;
  // A new input or new parameters start from scratch.
  if ((!cache.Sim || cache.Input != input || cache.InputTime != input->GetMTime() ||
        cache.FilterTime != this->GetMTime()) &&
    !this->NewSimulation(input, terrain, backend))
  {
    return false;
  }
  RunInfo run;
  if (!this->Simulate(input, terrain, backend, run))
  {
    return false;
  }
  this->AddOutputs(output, terrain.view, run);
  return true;
}

#include "vtkTerroirKMeansGPU.h"

#include "vtkTerroirGPU.h"
#include "vtkTerroirKMeansAssignCS.h"
#include "vtkTerroirKMeansPartialSumsCS.h"

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace terroir
{
namespace clustering
{

namespace
{
/// Cells per work group of Shaders/KMeansAssign.comp, and per invocation (LOCAL_X = 32).
constexpr std::size_t kAssignLocal = 256;
constexpr std::size_t kAssignCellsPerInvocation = 8;
/// Work groups of Shaders/KMeansPartialSums.comp (both passes).
constexpr std::size_t kSumsLocal = 64;
/// Largest index the kernels form in 32 bits.
constexpr std::size_t kIndexLimit = 0xffffffffu;

static_assert(KMeansBlockCells % kAssignLocal == 0, "a block is a whole number of work groups");

/// Invocations per block in the block pass of KMeansPartialSums.comp: 4 features each, and one
/// for the counts and the inertia.
std::size_t SumGroups(std::size_t features)
{
  return (features + 3) / 4 + 1;
}

std::string Bytes(std::size_t bytes)
{
  return std::to_string(bytes) + " bytes";
}

/// How the cells are split into chunks of whole blocks, each with its own buffers.
struct ChunkPlan
{
  std::size_t blocksPerChunk = 0;
  std::size_t chunks = 0;
  std::size_t slots = 0; ///< doubles per block record: (F + 1) * K + 1, for K = KMeansMaxClusters
};

/**
 * The largest chunk that the driver's limits allow (GL_MAX_SHADER_STORAGE_BLOCK_SIZE per
 * buffer, GL_MAX_COMPUTE_WORK_GROUP_COUNT[0] per dispatch, 32-bit indices in the kernels),
 * at most `requested` blocks when that is not 0. Throws gpu::Error when not even one block
 * fits.
 */
ChunkPlan PlanChunks(const KMeansFeatures& x, const gpu::Limits& limits, std::size_t requested)
{
  const std::size_t f = static_cast<std::size_t>(x.features);
  const std::size_t maxBytes = std::min<std::size_t>(limits.MaxShaderStorageBlockSize > 0
      ? static_cast<std::size_t>(limits.MaxShaderStorageBlockSize)
      : kIndexLimit,
    kIndexLimit);
  const std::size_t maxGroups =
    limits.MaxWorkGroupCount[0] > 0 ? static_cast<std::size_t>(limits.MaxWorkGroupCount[0]) : 65535;
  ChunkPlan plan;
  plan.slots = (f + 1) * static_cast<std::size_t>(KMeansMaxClusters) + 1;

  const std::size_t centreBytes = static_cast<std::size_t>(KMeansMaxClusters) * f * sizeof(float);
  if (centreBytes > maxBytes)
  {
    throw gpu::Error("KMeansAssign.comp: the centres of " + std::to_string(KMeansMaxClusters) +
      " clusters x " + std::to_string(f) + " features need " + Bytes(centreBytes) +
      ", more than GL_MAX_SHADER_STORAGE_BLOCK_SIZE (" + Bytes(maxBytes) +
      "); too many features for the GPU path, use the CPU backend");
  }
  const std::size_t finalGroups = (plan.slots + kSumsLocal - 1) / kSumsLocal;
  if (finalGroups > maxGroups)
  {
    throw gpu::Error("KMeansPartialSums.comp: " + std::to_string(f) + " features need " +
      std::to_string(finalGroups) +
      " work groups in the final pass, more than GL_MAX_COMPUTE_WORK_GROUP_COUNT (" +
      std::to_string(maxGroups) + "); use the CPU backend");
  }

  // Each limit caps the blocks of a chunk.
  const std::size_t featureBlock = f * KMeansBlockCells * sizeof(float);
  const std::size_t partialBlock = plan.slots * sizeof(double);
  std::size_t blocks = maxBytes / featureBlock;                             // features
  blocks = std::min(blocks, maxBytes / (KMeansBlockCells * sizeof(float))); // labels, distances
  blocks = std::min(blocks, maxBytes / partialBlock);                       // block records
  blocks = std::min(blocks, maxGroups / (KMeansBlockCells / kAssignLocal)); // assignment groups
  blocks = std::min(blocks, maxGroups * kSumsLocal / SumGroups(f)); // block-pass invocations
  if (blocks < 1)
  {
    throw gpu::Error("KMeansAssign.comp: one block of " + std::to_string(KMeansBlockCells) +
      " cells x " + std::to_string(f) + " features needs " + Bytes(featureBlock) + " (and " +
      Bytes(partialBlock) + " of partial sums), more than GL_MAX_SHADER_STORAGE_BLOCK_SIZE (" +
      Bytes(maxBytes) + "); too many features for the GPU path, use the CPU backend");
  }
  if (requested > 0)
  {
    blocks = std::min(blocks, requested);
  }
  const std::size_t total = x.Blocks();
  plan.blocksPerChunk = std::max<std::size_t>(1, std::min(blocks, total));
  plan.chunks = (total + plan.blocksPerChunk - 1) / plan.blocksPerChunk;
  return plan;
}

/// K rounded up to a power of two (the MAX_K of the block pass: fewer accumulators for small K).
int AccumulatorCount(int k)
{
  int m = 1;
  while (m < k)
  {
    m *= 2;
  }
  return std::min(m, KMeansMaxClusters);
}

/// KMeansEngine on the compute context; construct and use inside gpu::Context::Run only.
class GPUEngine : public KMeansEngine
{
public:
  GPUEngine(const KMeansFeatures& x, const ChunkPlan& plan)
    : Features(x)
    , Plan(plan)
    , Ctx(gpu::Context::Global())
  {
    const std::size_t f = static_cast<std::size_t>(x.features);
    const std::size_t chunkCells = plan.blocksPerChunk * KMeansBlockCells;
    std::vector<float> staging;
    const std::vector<std::int32_t> unassigned(std::min(chunkCells, x.cells), -1);
    std::size_t groups = 0;
    for (std::size_t ci = 0; ci < plan.chunks; ++ci)
    {
      Chunk chunk;
      chunk.first = ci * chunkCells;
      chunk.cells = std::min(chunkCells, x.cells - chunk.first);
      chunk.blocks = (chunk.cells + KMeansBlockCells - 1) / KMeansBlockCells;
      chunk.groupOffset = groups;
      chunk.groups = (chunk.cells + kAssignLocal - 1) / kAssignLocal;
      groups += chunk.groups;
      // The chunk's feature-major matrix: feature j of its cell c at j * cells + c.
      const float* src = x.data + chunk.first;
      if (plan.chunks == 1)
      {
        chunk.features = gpu::StorageBuffer(f * chunk.cells * sizeof(float), x.data);
      }
      else
      {
        staging.resize(f * chunk.cells);
        for (std::size_t j = 0; j < f; ++j)
        {
          std::copy(src + j * x.cells,
            src + j * x.cells + chunk.cells,
            staging.begin() + static_cast<std::ptrdiff_t>(j * chunk.cells));
        }
        chunk.features = gpu::StorageBuffer(staging.size() * sizeof(float), staging.data());
      }
      // Labels start at -1, as the CPU engine's: the first assignment changes every label.
      chunk.labels = gpu::StorageBuffer(chunk.cells * sizeof(std::int32_t), unassigned.data());
      chunk.distances = gpu::StorageBuffer(chunk.cells * sizeof(float), gpu::Contents::Undefined);
      this->Chunks.push_back(std::move(chunk));
    }
    staging.clear();
    staging.shrink_to_fit();
    this->Centres = gpu::StorageBuffer(
      static_cast<std::size_t>(KMeansMaxClusters) * f * sizeof(float), gpu::Contents::Undefined);
    this->Changed = gpu::StorageBuffer(groups * sizeof(std::uint32_t), gpu::Contents::Undefined);
    this->ChangedHost.resize(groups);
    this->Partials = gpu::StorageBuffer(
      plan.blocksPerChunk * plan.slots * sizeof(double), gpu::Contents::Undefined);
    this->Totals = gpu::StorageBuffer(plan.slots * sizeof(double), gpu::Contents::Undefined);
  }

  std::size_t Assign(const std::vector<float>& centres, int k) override
  {
    const std::size_t f = static_cast<std::size_t>(this->Features.features);
    if (k < 1 || k > KMeansMaxClusters || centres.size() != static_cast<std::size_t>(k) * f)
    {
      throw std::invalid_argument("k-means GPU: " + std::to_string(centres.size()) +
        " centre values for k = " + std::to_string(k) + " and " + std::to_string(f) + " features");
    }
    // Centres per pass of the kernel (see its header): 4, or 8 for K > 8 (fewer passes over the
    // features; more accumulators than that spill registers on llvmpipe).
    const int perPass = k <= 8 ? 4 : 8;
    gpu::Program& prog = this->Ctx.GetProgram("KMeansAssign.comp",
      vtkTerroirKMeansAssignCS,
      { "LOCAL_X " + std::to_string(kAssignLocal / kAssignCellsPerInvocation),
        "CENTRES_PER_PASS " + std::to_string(perPass) });
    this->Centres.Upload(centres.data(), centres.size() * sizeof(float));
    prog.SetInt("uFeatures", this->Features.features);
    prog.SetInt("uK", k);
    this->Centres.Bind(1);
    this->Changed.Bind(4);
    for (const Chunk& chunk : this->Chunks)
    {
      prog.SetUInt("uCells", static_cast<unsigned>(chunk.cells));
      prog.SetUInt("uGroupOffset", static_cast<unsigned>(chunk.groupOffset));
      chunk.features.Bind(0);
      chunk.labels.Bind(2);
      chunk.distances.Bind(3);
      prog.Dispatch(static_cast<unsigned>(chunk.groups));
    }
    this->Changed.Download(
      this->ChangedHost.data(), this->ChangedHost.size() * sizeof(std::uint32_t));
    this->LabelsOnHost = false;
    this->DistancesOnHost = false;
    std::size_t changed = 0;
    for (std::uint32_t c : this->ChangedHost)
    {
      changed += c;
    }
    return changed;
  }

  void Sums(int k,
    std::vector<double>& sums,
    std::vector<std::int64_t>& counts,
    double& inertia) override
  {
    if (k < 1 || k > KMeansMaxClusters)
    {
      throw std::invalid_argument("k-means GPU: k = " + std::to_string(k) + " is not in 1.." +
        std::to_string(KMeansMaxClusters));
    }
    const std::size_t f = static_cast<std::size_t>(this->Features.features);
    const std::size_t kk = static_cast<std::size_t>(k);
    const std::size_t slots = (f + 1) * kk + 1;
    const std::vector<std::string> defines = { "LOCAL_X 64",
      "MAX_K " + std::to_string(AccumulatorCount(k)) };
    gpu::Program& blockPass =
      this->Ctx.GetProgram("KMeansPartialSums.comp", vtkTerroirKMeansPartialSumsCS, defines);
    gpu::Program& finalPass = this->Ctx.GetProgram("KMeansPartialSums.comp",
      vtkTerroirKMeansPartialSumsCS,
      { "LOCAL_X 64", "KMEANS_FINAL_PASS" });
    for (gpu::Program* p : { &blockPass, &finalPass })
    {
      p->SetInt("uFeatures", this->Features.features);
      p->SetInt("uK", k);
      p->SetUInt("uBlockCells", static_cast<unsigned>(KMeansBlockCells));
    }
    this->Totals.Clear();
    this->Partials.Bind(3);
    this->Totals.Bind(4);
    // The block pass's accumulators (MAX_K per invocation), from the pool.
    const std::size_t invocations = this->Plan.blocksPerChunk * SumGroups(f);
    gpu::StorageBuffer scratch(
      invocations * static_cast<std::size_t>(AccumulatorCount(k)) * 32, gpu::Contents::Undefined);
    scratch.Bind(5);
    for (const Chunk& chunk : this->Chunks)
    {
      chunk.features.Bind(0);
      chunk.labels.Bind(1);
      chunk.distances.Bind(2);
      blockPass.SetUInt("uCells", static_cast<unsigned>(chunk.cells));
      blockPass.SetUInt("uBlocks", static_cast<unsigned>(chunk.blocks));
      blockPass.Dispatch(
        static_cast<unsigned>((chunk.blocks * SumGroups(f) + kSumsLocal - 1) / kSumsLocal));
      finalPass.SetUInt("uCells", static_cast<unsigned>(chunk.cells));
      finalPass.SetUInt("uBlocks", static_cast<unsigned>(chunk.blocks));
      finalPass.Dispatch(static_cast<unsigned>((slots + kSumsLocal - 1) / kSumsLocal));
    }
    std::vector<double> totals(slots);
    this->Totals.Download(totals.data(), slots * sizeof(double));
    sums.assign(kk * f, 0.0);
    counts.assign(kk, 0);
    for (std::size_t c = 0; c < kk; ++c)
    {
      for (std::size_t j = 0; j < f; ++j)
      {
        sums[c * f + j] = totals[j * kk + c];
      }
      counts[c] = static_cast<std::int64_t>(totals[f * kk + c]);
    }
    inertia = totals[slots - 1];
  }

  const std::int32_t* Labels() override
  {
    if (!this->LabelsOnHost)
    {
      this->LabelHost.resize(this->Features.cells);
      for (const Chunk& chunk : this->Chunks)
      {
        chunk.labels.Download(
          this->LabelHost.data() + chunk.first, chunk.cells * sizeof(std::int32_t));
      }
      this->LabelsOnHost = true;
    }
    return this->LabelHost.data();
  }

  const float* Distances() override
  {
    if (!this->DistancesOnHost)
    {
      this->DistanceHost.resize(this->Features.cells);
      for (const Chunk& chunk : this->Chunks)
      {
        chunk.distances.Download(
          this->DistanceHost.data() + chunk.first, chunk.cells * sizeof(float));
      }
      this->DistancesOnHost = true;
    }
    return this->DistanceHost.data();
  }

  /// Moves the host copies out (downloading them first when needed).
  void TakeResults(std::vector<std::int32_t>& labels, std::vector<float>& distances)
  {
    this->Labels();
    this->Distances();
    labels.swap(this->LabelHost);
    distances.swap(this->DistanceHost);
    this->LabelsOnHost = false;
    this->DistancesOnHost = false;
  }

private:
  struct Chunk
  {
    std::size_t first = 0;       ///< first cell
    std::size_t cells = 0;       ///< cells (whole blocks, except in the last chunk)
    std::size_t blocks = 0;      ///< KMeansBlockCells blocks
    std::size_t groups = 0;      ///< work groups of the assignment
    std::size_t groupOffset = 0; ///< first slot in the changed-label counts
    gpu::StorageBuffer features{ sizeof(float) };
    gpu::StorageBuffer labels{ sizeof(std::int32_t) };
    gpu::StorageBuffer distances{ sizeof(float) };
  };

  KMeansFeatures Features;
  ChunkPlan Plan;
  gpu::Context& Ctx;
  std::vector<Chunk> Chunks;
  gpu::StorageBuffer Centres{ sizeof(float) };
  gpu::StorageBuffer Changed{ sizeof(std::uint32_t) };
  gpu::StorageBuffer Partials{ sizeof(double) };
  gpu::StorageBuffer Totals{ sizeof(double) };
  std::vector<std::uint32_t> ChangedHost;
  std::vector<std::int32_t> LabelHost;
  std::vector<float> DistanceHost;
  bool LabelsOnHost = false;
  bool DistancesOnHost = false;
};
} // namespace

//------------------------------------------------------------------------------
KMeansResult RunKMeansGPU(const KMeansFeatures& features,
  const std::vector<float>& initialCentres,
  int k,
  const KMeansOptions& options,
  std::vector<std::int32_t>& labels,
  std::vector<float>& distances,
  const std::function<void(int, std::size_t)>& progress,
  std::size_t chunkBlocks)
{
  // What KMeansLloyd would reject is rejected before any GL work, with the same exception type.
  if (k < 1 || k > KMeansMaxClusters)
  {
    throw std::invalid_argument("k-means GPU: k = " + std::to_string(k) + " is not in 1.." +
      std::to_string(KMeansMaxClusters));
  }
  if (static_cast<std::size_t>(k) > features.cells)
  {
    throw std::invalid_argument("k-means GPU: k = " + std::to_string(k) + " clusters but only " +
      std::to_string(features.cells) + " cells");
  }
  if (features.features < 1 || !features.data)
  {
    throw std::invalid_argument("k-means GPU: no feature matrix");
  }
  if (initialCentres.size() !=
    static_cast<std::size_t>(k) * static_cast<std::size_t>(features.features))
  {
    throw std::invalid_argument("k-means GPU: " + std::to_string(initialCentres.size()) +
      " initial centre values, not k * features = " +
      std::to_string(static_cast<std::size_t>(k) * static_cast<std::size_t>(features.features)));
  }

  auto& ctx = gpu::Context::Global();
  const ChunkPlan plan = PlanChunks(features, ctx.GetLimits(), chunkBlocks);
  KMeansResult result;
  const double work = static_cast<double>(features.cells) * features.features * k *
    std::max(1, options.maximumIterations);
  ctx.Run("k-means",
    gpu::Context::Budget(work),
    [&]
    {
      GPUEngine engine(features, plan);
      result = KMeansLloyd(engine, features, initialCentres, k, options, progress);
      engine.TakeResults(labels, distances);
    });
  return result;
}

} // namespace clustering
} // namespace terroir

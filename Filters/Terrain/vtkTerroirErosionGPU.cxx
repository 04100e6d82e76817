#include "vtkTerroirErosionGPU.h"

#include "vtkTerroirErosionCS.h"
#include "vtkTerroirGPU.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace terroir
{
namespace terrain
{

namespace
{
/// Work-group size of Shaders/Erosion.comp's cell kernels (LOCAL_X), and of the row sums (one
/// invocation per row: small groups, so that a GPU spreads the rows over more of its cores).
constexpr unsigned kLocalX = 256;
constexpr unsigned kRowLocalX = 64;
/// Planes of the kernel's buffers (see the shader's header comment).
constexpr std::size_t kStatePlanes = 9;
constexpr std::size_t kFluxPlanes = 4;
constexpr std::size_t kInputPlanes = 4;
constexpr std::size_t kScratchPlanes = 4;
constexpr std::size_t kRowPlanes = 10;
constexpr std::size_t kRowSlots = 11;
constexpr std::size_t kControl = 11;
/// State planes, in the kernel's order.
enum StatePlane
{
  kTerrain = 0,
  kTerrainLo,
  kOriginal,
  kSoil,
  kWater,
  kWaterLo,
  kSediment,
  kU,
  kV
};
/// uFlags bits of the kernel.
enum Flag : unsigned
{
  kSeaBoundary = 1u,
  kLayered = 2u,
  kErosionFactor = 4u,
  kTalusFactor = 8u,
  kRain = 16u,
  kEvaporationFactor = 32u,
  kSoftOutflow = 64u,
  kRamp = 128u,
  kHalvingErosion = 256u,
  kHalvingDeposition = 512u
};

[[noreturn]] void BadSize(const char* what, std::size_t size, std::size_t expected)
{
  throw std::invalid_argument(std::string("erosion GPU: ") + what + " has " + std::to_string(size) +
    " entries, not " + std::to_string(expected));
}

/// The core's CheckState, for the arrays the GPU path reads (std::invalid_argument).
void CheckState(const ErosionState& st)
{
  if (st.nx <= 0 || st.ny <= 0)
  {
    throw std::invalid_argument("erosion GPU: grid size " + std::to_string(st.nx) + " x " +
      std::to_string(st.ny) + " is not > 0");
  }
  const std::size_t n = st.Size();
  const std::size_t ny = static_cast<std::size_t>(st.ny);
  if (st.rowDx.size() != ny || st.rowDy.size() != ny)
  {
    BadSize("rowDx or rowDy", std::min(st.rowDx.size(), st.rowDy.size()), ny);
  }
  const std::pair<const char*, const std::vector<float>*> required[] = { { "terrain", &st.terrain },
    { "original", &st.original },
    { "terrainResidue", &st.terrainResidue },
    { "waterResidue", &st.waterResidue },
    { "water", &st.water },
    { "sediment", &st.sediment },
    { "fluxW", &st.fluxW },
    { "fluxE", &st.fluxE },
    { "fluxS", &st.fluxS },
    { "fluxN", &st.fluxN },
    { "velocityU", &st.velocityU },
    { "velocityV", &st.velocityV } };
  for (const auto& r : required)
  {
    if (r.second->size() != n)
    {
      BadSize(r.first, r.second->size(), n);
    }
  }
  const std::pair<const char*, const std::vector<float>*> optional[] = {
    { "soil", &st.soil }, { "erosionFactor", &st.erosionFactor }, { "talusFactor", &st.talusFactor }
  };
  for (const auto& o : optional)
  {
    if (!o.second->empty() && o.second->size() != n)
    {
      BadSize(o.first, o.second->size(), n);
    }
  }
  if (!st.valid.empty() && st.valid.size() != n)
  {
    BadSize("valid", st.valid.size(), n);
  }
  for (const std::vector<float>* f : { &st.erosionFactor, &st.talusFactor })
  {
    for (float x : *f)
    {
      if (!(x >= 0.0f && std::isfinite(x)))
      {
        throw std::invalid_argument(
          "erosion GPU: a per-cell factor = " + std::to_string(x) + " is not >= 0 and finite");
      }
    }
  }
}

/// Per-row float tables, computed with the core's expressions (MakeGeometry, FluxRows'
/// edge coefficient, ThermalContext) so that they have the core's bits.
std::vector<float> RowTables(const ErosionState& st, const ErosionParams& p)
{
  const std::size_t ny = static_cast<std::size_t>(st.ny);
  std::vector<float> t(kRowPlanes * ny, 0.0f);
  auto coef = [&](double l)
  { return p.timeStep * p.gravity * (p.pipeArea > 0.0 ? p.pipeArea / l : l); };
  auto at = [&](std::size_t plane, std::size_t j) -> float& { return t[plane * ny + j]; };
  for (std::size_t j = 0; j < ny; ++j)
  {
    at(0, j) = static_cast<float>(st.rowDx[j]);
    at(1, j) = static_cast<float>(st.rowDy[j]);
    at(2, j) = static_cast<float>(st.CellArea(static_cast<int>(j)));
    at(4, j) = static_cast<float>(coef(st.rowDx[j]));
    at(6, j) = static_cast<float>(
      p.timeStep * p.gravity * (p.pipeArea > 0.0 ? p.pipeArea / st.rowDy[j] : st.rowDy[j]));
    if (j + 1 < ny)
    {
      const double ly = 0.5 * (st.rowDy[j] + st.rowDy[j + 1]);
      const double mx = 0.5 * (st.rowDx[j] + st.rowDx[j + 1]);
      at(3, j) = static_cast<float>(ly);
      at(5, j) = static_cast<float>(coef(ly));
      at(7, j) = static_cast<float>(std::sqrt(ly * ly + mx * mx));
    }
  }
  for (std::size_t j = 0; j < ny; ++j)
  {
    at(8, j) = j > 0 ? at(2, j - 1) / at(2, j) : 0.0f;
    at(9, j) = j + 1 < ny ? at(2, j + 1) / at(2, j) : 0.0f;
  }
  return t;
}

/// The kernel's uFlags for this run.
unsigned Flags(const ErosionState& st,
  const ErosionParams& p,
  const float* rain,
  const float* evaporationFactor)
{
  unsigned f = 0;
  f |= p.boundary == ErosionBoundary::Sea ? kSeaBoundary : 0u;
  f |= st.soil.empty() ? 0u : kLayered;
  f |= st.erosionFactor.empty() ? 0u : kErosionFactor;
  f |= st.talusFactor.empty() ? 0u : kTalusFactor;
  f |= rain ? kRain : 0u;
  f |= evaporationFactor ? kEvaporationFactor : 0u;
  f |= p.softOutflow ? kSoftOutflow : 0u;
  f |= p.capacityDepth > 0.0 ? kRamp : 0u;
  f |= p.halvingDepthErosion > 0.0 ? kHalvingErosion : 0u;
  f |= p.halvingDepthDeposition > 0.0 ? kHalvingDeposition : 0u;
  return f;
}

/// The float constants of the kernel: the core's casts of the parameters.
void SetConstants(gpu::Program& prog,
  const ErosionState& st,
  const ErosionParams& p,
  const ThermalParams& th,
  unsigned flags)
{
  constexpr double degree = 3.14159265358979323846 / 180.0;
  const float dt = static_cast<float>(p.timeStep);
  prog.SetUInt("uNx", static_cast<unsigned>(st.nx));
  prog.SetUInt("uNy", static_cast<unsigned>(st.ny));
  prog.SetUInt("uN", static_cast<unsigned>(st.Size()));
  prog.SetUInt("uFlags", flags);
  prog.SetFloat("uSeaLevel", static_cast<float>(p.seaLevel));
  prog.SetFloat("uDt", dt);
  prog.SetFloat("uDryDepth", static_cast<float>(p.dryDepth));
  prog.SetFloat("uSoftMin", static_cast<float>(p.softOutflowMin));
  prog.SetFloat("uSoftScale", static_cast<float>(p.softOutflowScale));
  prog.SetFloat("uKc", static_cast<float>(p.capacity));
  prog.SetFloat("uRampDepth", static_cast<float>(p.capacityDepth));
  prog.SetFloat("uMaxChange",
    p.maxBedChange > 0.0 ? static_cast<float>(p.maxBedChange)
                         : std::numeric_limits<float>::infinity());
  prog.SetFloat("uKs", static_cast<float>(p.dissolving));
  prog.SetFloat("uKsRock", static_cast<float>(p.dissolvingRock));
  prog.SetFloat("uKd", static_cast<float>(p.deposition));
  prog.SetFloat("uHalvingE", static_cast<float>(p.halvingDepthErosion));
  prog.SetFloat("uHalvingD", static_cast<float>(p.halvingDepthDeposition));
  prog.SetFloat("uMinTilt", static_cast<float>(p.minTilt));
  prog.SetFloat("uMaxTilt", static_cast<float>(p.maxTilt));
  prog.SetFloat("uKe", static_cast<float>(p.evaporation) * dt);
  prog.SetFloat("uTanSoil", static_cast<float>(std::tan(th.talusSoilDeg * degree)));
  prog.SetFloat("uTanRock", static_cast<float>(std::tan(th.talusRockDeg * degree)));
  prog.SetFloat("uRate16", static_cast<float>(th.rate / 16.0));
}

/// Work groups of `local` covering `items` invocations (gx x gy within the context's limits).
gpu::Groups GroupsFor(std::size_t items, const gpu::Limits& limits, unsigned local = kLocalX)
{
  const std::size_t groups = std::max<std::size_t>(1, (items + local - 1) / local);
  const std::size_t maxX =
    limits.MaxWorkGroupCount[0] > 0 ? static_cast<std::size_t>(limits.MaxWorkGroupCount[0]) : 65535;
  gpu::Groups g;
  g.x = static_cast<unsigned>(std::min(groups, maxX));
  g.y = static_cast<unsigned>((groups + g.x - 1) / g.x);
  return g;
}

/// Throws gpu::Error when the grid's largest buffer does not fit the driver's limits.
void CheckFits(const ErosionState& st, const gpu::Limits& limits)
{
  const std::size_t bytes = kStatePlanes * st.Size() * sizeof(float);
  if (kStatePlanes * st.Size() >= 0xffffffffu ||
    (limits.MaxShaderStorageBlockSize > 0 &&
      bytes > static_cast<std::size_t>(limits.MaxShaderStorageBlockSize)))
  {
    throw gpu::Error("Erosion.comp: the state buffer of " + std::to_string(st.nx) + " x " +
      std::to_string(st.ny) + " cells needs " + std::to_string(bytes) +
      " bytes, more than GL_MAX_SHADER_STORAGE_BLOCK_SIZE (" +
      std::to_string(limits.MaxShaderStorageBlockSize) + "); use the CPU backend");
  }
  const std::size_t maxY =
    limits.MaxWorkGroupCount[1] > 0 ? static_cast<std::size_t>(limits.MaxWorkGroupCount[1]) : 65535;
  if (GroupsFor(st.Size(), limits).y > maxY)
  {
    throw gpu::Error("Erosion.comp: too many work groups for GL_MAX_COMPUTE_WORK_GROUP_COUNT");
  }
}

/// Concatenates planes of n floats (an empty plane is filled with `fill`).
std::vector<float> Planes(std::size_t n,
  std::initializer_list<std::pair<const float*, float>> planes)
{
  std::vector<float> out;
  out.reserve(planes.size() * n);
  for (const auto& p : planes)
  {
    if (p.first)
    {
      out.insert(out.end(), p.first, p.first + n);
    }
    else
    {
      out.insert(out.end(), n, p.second);
    }
  }
  return out;
}

const float* Data(const std::vector<float>& v)
{
  return v.empty() ? nullptr : v.data();
}

/// One RunErosionGPU inside the context's job: the device buffers, the programs and the steps.
class GPURun
{
public:
  GPURun(gpu::Context& ctx,
    const ErosionState& st,
    const ErosionParams& p,
    const ThermalParams& th,
    const float* rain,
    const float* evaporationFactor);
  /// `steps` hydraulic steps, a thermal one after every `interval`-th (0: none).
  void Run(int steps, int interval);
  /// Downloads the state into `st` and the totals into `totals` (may be null).
  void Read(ErosionState& st, ErosionGPUTotals* totals);

private:
  gpu::Program& Kernel(const char* define, unsigned local = kLocalX);
  void Dispatch(gpu::Program& prog, std::size_t items, unsigned local = kLocalX);
  /// Sums `planes` planes of contrib row by row into slots [slot, slot + planes).
  void Rows(unsigned planes, unsigned slot, unsigned maxMask = 0u);
  void Totals(unsigned mode);
  void Hydraulic();
  void Thermal();

  gpu::Context& Ctx;
  const gpu::Limits Limits;
  const std::size_t N;
  const std::size_t Ny;
  const bool Layered;
  gpu::StorageBuffer State;
  gpu::StorageBuffer Flux[2];
  gpu::StorageBuffer Inputs;
  gpu::StorageBuffer Scratch;
  gpu::StorageBuffer Kind;
  gpu::StorageBuffer Valid;
  gpu::StorageBuffer RowTable;
  gpu::StorageBuffer Contrib;
  gpu::StorageBuffer RowSums;
  gpu::StorageBuffer Control;
  int Current = 0; ///< Flux[Current] holds the fluxes of the last step
  std::vector<gpu::Program*> Programs;
  gpu::Program *Surface, *FluxKernel, *Water, *Erode, *Advect, *Finish, *SlipScale, *Slip,
    *RowKernel, *TotalsKernel;
};

std::vector<std::uint32_t> ValidWords(const ErosionState& st)
{
  if (!st.valid.empty())
  {
    return gpu::PackFlags(st.valid.data(), st.valid.size());
  }
  const std::vector<std::uint8_t> all(st.Size(), 1);
  return gpu::PackFlags(all.data(), all.size());
}

//------------------------------------------------------------------------------
GPURun::GPURun(gpu::Context& ctx,
  const ErosionState& st,
  const ErosionParams& p,
  const ThermalParams& th,
  const float* rain,
  const float* evaporationFactor)
  : Ctx(ctx)
  , Limits(ctx.GetLimits())
  , N(st.Size())
  , Ny(static_cast<std::size_t>(st.ny))
  , Layered(!st.soil.empty())
  , State(gpu::StorageBuffer(kStatePlanes * N * sizeof(float),
      Planes(N,
        { { st.terrain.data(), 0.0f },
          { st.terrainResidue.data(), 0.0f },
          { st.original.data(), 0.0f },
          { Data(st.soil), 0.0f },
          { st.water.data(), 0.0f },
          { st.waterResidue.data(), 0.0f },
          { st.sediment.data(), 0.0f },
          { st.velocityU.data(), 0.0f },
          { st.velocityV.data(), 0.0f } })
        .data()))
  , Flux{ gpu::StorageBuffer(kFluxPlanes * N * sizeof(float),
            Planes(N,
              { { st.fluxW.data(), 0.0f },
                { st.fluxE.data(), 0.0f },
                { st.fluxS.data(), 0.0f },
                { st.fluxN.data(), 0.0f } })
              .data()),
    gpu::StorageBuffer(kFluxPlanes * N * sizeof(float), gpu::Contents::Undefined) }
  , Inputs(gpu::StorageBuffer(kInputPlanes * N * sizeof(float),
      Planes(N,
        { { Data(st.erosionFactor), 1.0f },
          { Data(st.talusFactor), 1.0f },
          { rain, 0.0f },
          { evaporationFactor, 1.0f } })
        .data()))
  , Scratch(kScratchPlanes * N * sizeof(float), gpu::Contents::Undefined)
  , Kind(N * sizeof(std::uint32_t), gpu::Contents::Undefined)
  , Valid(((N + 3) / 4) * sizeof(std::uint32_t), ValidWords(st).data())
  , RowTable(kRowPlanes * Ny * sizeof(float), RowTables(st, p).data())
  , Contrib(2 * N * sizeof(double), gpu::Contents::Undefined)
  , RowSums(kRowSlots * Ny * sizeof(double), gpu::Contents::Zero)
  , Control(kControl * sizeof(double), gpu::Contents::Zero)
{
  this->Surface = &this->Kernel("EROSION_SURFACE");
  this->FluxKernel = &this->Kernel("EROSION_FLUX");
  this->Water = &this->Kernel("EROSION_WATER");
  this->Erode = &this->Kernel("EROSION_ERODE");
  this->Advect = &this->Kernel("EROSION_ADVECT");
  this->Finish = &this->Kernel("EROSION_FINISH");
  this->SlipScale = &this->Kernel("EROSION_SLIP_SCALE");
  this->Slip = &this->Kernel("EROSION_SLIP");
  this->RowKernel = &this->Kernel("EROSION_ROWS", kRowLocalX);
  this->TotalsKernel = &this->Kernel("EROSION_TOTALS", kRowLocalX);
  const unsigned flags = Flags(st, p, rain, evaporationFactor);
  for (gpu::Program* prog : this->Programs)
  {
    SetConstants(*prog, st, p, th, flags);
  }
  this->State.Bind(0);
  this->Inputs.Bind(3);
  this->Scratch.Bind(4);
  this->Kind.Bind(5);
  this->Valid.Bind(6);
  this->RowTable.Bind(7);
  this->Contrib.Bind(8);
  this->RowSums.Bind(9);
  this->Control.Bind(10);
}

//------------------------------------------------------------------------------
gpu::Program& GPURun::Kernel(const char* define, unsigned local)
{
  gpu::Program& prog = this->Ctx.GetProgram(
    "Erosion.comp", vtkTerroirErosionCS, { "LOCAL_X " + std::to_string(local), define });
  this->Programs.push_back(&prog);
  return prog;
}

//------------------------------------------------------------------------------
void GPURun::Dispatch(gpu::Program& prog, std::size_t items, unsigned local)
{
  const gpu::Groups g = GroupsFor(items, this->Limits, local);
  prog.Dispatch(g.x, g.y);
}

//------------------------------------------------------------------------------
void GPURun::Rows(unsigned planes, unsigned slot, unsigned maxMask)
{
  this->RowKernel->SetUInt("uPlanes", planes);
  this->RowKernel->SetUInt("uSlot", slot);
  this->RowKernel->SetUInt("uMaxMask", maxMask);
  this->Dispatch(*this->RowKernel, planes * this->Ny, kRowLocalX);
}

//------------------------------------------------------------------------------
void GPURun::Totals(unsigned mode)
{
  this->TotalsKernel->SetUInt("uMode", mode);
  this->Dispatch(*this->TotalsKernel, 1, kRowLocalX);
}

//------------------------------------------------------------------------------
void GPURun::Hydraulic()
{
  // Slots of rowSums: 0 rain, 1 to sea, 2 clamped, 3 eroded, 4 deposited, 5 before, 6 after,
  // 7 evaporated, 8 deposited (finish).
  this->Dispatch(*this->Surface, this->N);
  this->Rows(1, 0);
  this->Flux[this->Current].Bind(1);
  this->Flux[1 - this->Current].Bind(2);
  this->Dispatch(*this->FluxKernel, this->N);
  this->Current = 1 - this->Current;
  this->Flux[this->Current].Bind(1); // the new fluxes, read by the water pass
  this->Flux[1 - this->Current].Bind(2);
  this->Dispatch(*this->Water, this->N);
  this->Rows(2, 1);
  this->Dispatch(*this->Erode, this->N);
  this->Rows(2, 3);
  this->Dispatch(*this->Advect, this->N);
  this->Rows(2, 5);
  this->Totals(0);
  this->Dispatch(*this->Finish, this->N);
  this->Rows(2, 7);
  this->Totals(1);
}

//------------------------------------------------------------------------------
void GPURun::Thermal()
{
  this->Dispatch(*this->SlipScale, this->N);
  this->Rows(1, 9, 1u);
  this->Dispatch(*this->Slip, this->N);
  this->Rows(1, 10);
  this->Totals(2);
  const std::size_t plane = this->N * sizeof(float);
  this->State.CopyFrom(this->Scratch, plane, 1 * plane, kTerrain * plane);
  if (this->Layered)
  {
    this->State.CopyFrom(this->Scratch, plane, 2 * plane, kSoil * plane);
  }
}

//------------------------------------------------------------------------------
void GPURun::Run(int steps, int interval)
{
  // A bounded queue: every kBlock steps a fence; before issuing past one, wait for the fence
  // before it (never the one just issued, so the GPU keeps work), so at most two blocks of
  // dispatches wait in the driver however many steps are asked for, and every wait is within
  // the job's time budget.
  constexpr int kBlock = 64;
  gpu::Fence previous;
  for (int s = 1; s <= steps; ++s)
  {
    this->Hydraulic();
    if (interval > 0 && s % interval == 0)
    {
      this->Thermal();
    }
    if (s % kBlock == 0)
    {
      previous.Wait();
      previous = gpu::Fence();
    }
  }
}

//------------------------------------------------------------------------------
void GPURun::Read(ErosionState& st, ErosionGPUTotals* totals)
{
  std::vector<float> state(kStatePlanes * this->N);
  this->State.Download(state.data(), state.size() * sizeof(float));
  std::vector<float> flux(kFluxPlanes * this->N);
  this->Flux[this->Current].Download(flux.data(), flux.size() * sizeof(float));
  double control[kControl];
  this->Control.Download(control, sizeof(control));
  auto plane = [&](const std::vector<float>& from, std::size_t k, std::vector<float>& to)
  { std::copy(from.begin() + k * this->N, from.begin() + (k + 1) * this->N, to.begin()); };
  plane(state, kTerrain, st.terrain);
  plane(state, kTerrainLo, st.terrainResidue);
  if (this->Layered)
  {
    plane(state, kSoil, st.soil);
  }
  plane(state, kWater, st.water);
  plane(state, kWaterLo, st.waterResidue);
  plane(state, kSediment, st.sediment);
  plane(state, kU, st.velocityU);
  plane(state, kV, st.velocityV);
  plane(flux, 0, st.fluxW);
  plane(flux, 1, st.fluxE);
  plane(flux, 2, st.fluxS);
  plane(flux, 3, st.fluxN);
  if (totals)
  {
    ErosionStepStats& h = totals->hydraulic;
    h.rain = control[2];
    h.evaporated = control[3];
    h.waterToSea = control[4];
    h.waterClamped = control[5];
    h.eroded = control[6];
    h.deposited = control[7];
    h.sedimentScale = control[8];
    totals->thermal.moved = control[9];
    totals->thermal.maxExcess = control[10];
  }
}
} // namespace

//------------------------------------------------------------------------------
void RunErosionGPU(ErosionState& state,
  const ErosionParams& params,
  const ThermalParams& thermal,
  int thermalInterval,
  const float* rain,
  const float* evaporationFactor,
  int steps,
  ErosionGPUTotals* totals)
{
  CheckErosionParams(params);
  if (thermalInterval > 0)
  {
    CheckThermalParams(thermal);
  }
  if (steps < 0 || thermalInterval < 0)
  {
    throw std::invalid_argument("erosion GPU: steps = " + std::to_string(steps) +
      " and thermalInterval = " + std::to_string(thermalInterval) + " must be >= 0");
  }
  CheckState(state);
  if (totals)
  {
    *totals = ErosionGPUTotals();
  }
  if (steps == 0)
  {
    return;
  }
  auto& ctx = gpu::Context::Global();
  CheckFits(state, ctx.GetLimits());
  const double work = 20.0 * static_cast<double>(steps) * static_cast<double>(state.Size());
  ctx.Run("erosion",
    gpu::Context::Budget(work),
    [&]
    {
      GPURun run(ctx, state, params, thermal, rain, evaporationFactor);
      run.Run(steps, thermalInterval);
      run.Read(state, totals);
    });
}

} // namespace terrain
} // namespace terroir

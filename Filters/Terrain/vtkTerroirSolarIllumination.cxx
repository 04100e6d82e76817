#include "vtkTerroirSolarIllumination.h"
#include "vtkTerroirComputeContext.h"

#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkLogger.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTerroirGPU.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirShadowGatherCS.h"
#include "vtkTerroirShadowSweepCS.h"
#include "vtkTerroirSolarIlluminationCS.h"
#include "vtkTerroirTemperature.h"
#include "vtkTerroirTerrainInput.h"

#include "ShadowHorizon.h"
#include "SlopeHorn1981.h"
#include "SolarIllumination.h"
#include "SolarPosition.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <vector>

#include "vtkTerroirFiltersTerrainModule.h" // For VTK_MODULE_ENABLE_VTK_ParallelCore
#if VTK_MODULE_ENABLE_VTK_ParallelCore
#include "vtkCommunicator.h"
#include "vtkMultiProcessController.h"
#endif

vtkStandardNewMacro(vtkTerroirSolarIllumination);

namespace tt = terroir::terrain;

/// The cached horizon map and what it was computed from.
struct vtkTerroirSolarIllumination::Internals
{
  std::vector<float> Map; ///< HorizonSectors planes of nx*ny tangents
  vtkMTimeType InputTime = 0;
  const void* InputData = nullptr;
  int Sectors = 0;
  bool Curvature = false;
  int Backend = 0;
  std::size_t Cells = 0;
  unsigned long long Stamp = 0; ///< identifies the map computed last (its device copy's stamp)
};

namespace
{
const double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Throws when a buffer of `bytes` cannot be one storage buffer of the context.
void CheckBlock(terroir::gpu::Context& ctx, std::size_t bytes, const char* what)
{
  const long long maxBlock = ctx.GetLimits().MaxShaderStorageBlockSize;
  if (maxBlock > 0 && static_cast<long long>(bytes) > maxBlock)
  {
    throw terroir::gpu::Error(std::string("grid too large for one GPU storage buffer (") + what +
      " " + std::to_string(bytes) + " > " + std::to_string(maxBlock) + " bytes)");
  }
}

/// Key of the device copy of a horizon map held in `map` (the host cache's storage).
const void* MapKey(const float* map)
{
  return map;
}

/// Horizon map on the GPU: Shaders/ShadowSweep.comp per line, then ShadowGather.comp per
/// cell, one sector after another (bindings documented in the shaders), downloaded into `map`.
/// When the whole map fits one storage buffer it also stays on the device, under
/// MapKey(map) and `stamp`, for the accumulation (no upload there).
void HorizonMapGPU(const terroir::TerrainInput& terrain,
  int sectors,
  float curvature,
  float* map,
  unsigned long long stamp)
{
  const terroir::GridView<float>& v = terrain.view;
  const std::size_t n = v.Size();
  auto& ctx = terroir::gpu::Context::Global();
  std::size_t maxLines = 0;
  std::vector<tt::SweepPlan> plans;
  for (int k = 0; k < sectors; ++k)
  {
    plans.push_back(tt::MakeSweepPlan(
      tt::MakeMarchDirection(tt::SectorAzimuth(k, sectors), v.dx, v.dy), v.nx, v.ny));
    maxLines =
      std::max(maxLines, static_cast<std::size_t>(plans.back().lineCount) * plans.back().nMajor);
  }
  CheckBlock(ctx, maxLines * sizeof(float), "sweep lines");
  CheckBlock(ctx, n * sizeof(float), "elevation");
  const long long maxBlock = ctx.GetLimits().MaxShaderStorageBlockSize;
  const std::size_t mapBytes = static_cast<std::size_t>(sectors) * n * sizeof(float);
  const bool keep = maxBlock <= 0 || static_cast<long long>(mapBytes) <= maxBlock;
  ctx.Run("horizon map",
    terroir::gpu::Context::Budget(2.0 * sectors * static_cast<double>(n)),
    [&]
    {
      const auto undefined = terroir::gpu::Contents::Undefined;
      const terroir::GPUTerrain t = terroir::ResidentTerrain(terrain);
      const std::size_t maxMajor = static_cast<std::size_t>(std::max(v.nx, v.ny));
      terroir::gpu::StorageBuffer btable(2 * maxMajor * sizeof(float), undefined);
      terroir::gpu::StorageBuffer bhullS(maxLines * sizeof(float), undefined);
      terroir::gpu::StorageBuffer bhullW(maxLines * sizeof(float), undefined);
      terroir::gpu::StorageBuffer blines(maxLines * sizeof(float), undefined);
      terroir::gpu::StorageBuffer bplane(n * sizeof(float), undefined);
      std::shared_ptr<terroir::gpu::StorageBuffer> whole;
      if (keep)
      {
        whole = std::make_shared<terroir::gpu::StorageBuffer>(mapBytes, undefined);
      }
      auto& sweep = ctx.GetProgram("ShadowSweep.comp", vtkTerroirShadowSweepCS, { "LOCAL_X 64" });
      auto& gather = ctx.GetProgram(
        "ShadowGather.comp", vtkTerroirShadowGatherCS, { "LOCAL_X 16", "LOCAL_Y 16" });
      std::vector<std::int32_t> table(2 * maxMajor);
      for (int k = 0; k < sectors; ++k)
      {
        const tt::SweepPlan& p = plans[k];
        // Table: F_u as int bits, then f_u as float bits (one buffer, 2 * nMajor words).
        for (int u = 0; u < p.nMajor; ++u)
        {
          table[u] = p.floorAt[u];
          std::int32_t bits;
          static_assert(sizeof(bits) == sizeof(float), "32-bit float");
          std::memcpy(&bits, &p.fracAt[u], sizeof(bits));
          table[p.nMajor + u] = bits;
        }
        btable.Upload(table.data(), 2 * p.nMajor * sizeof(std::int32_t));
        for (auto* prog : { &sweep, &gather })
        {
          prog->SetInt("uNx", v.nx);
          prog->SetInt("uNy", v.ny);
          prog->SetInt("uAlongX", p.dir.alongX ? 1 : 0);
          prog->SetInt("uStep", p.dir.step);
          prog->SetInt("uFirstLine", p.firstLine);
          prog->SetInt("uLineCount", p.lineCount);
          prog->SetInt("uHasMask", v.valid ? 1 : 0);
          prog->SetFloat("uLength", p.dir.length);
          prog->SetFloat("uCurvature", curvature);
        }
        t.elevation->Bind(0);
        t.mask->Bind(1);
        btable.Bind(2);
        bhullS.Bind(3);
        bhullW.Bind(4);
        blines.Bind(5);
        bplane.Bind(6);
        sweep.Dispatch(static_cast<unsigned>((p.lineCount + 63) / 64));
        gather.Dispatch(
          static_cast<unsigned>((v.nx + 15) / 16), static_cast<unsigned>((v.ny + 15) / 16));
        if (whole)
        {
          whole->CopyFrom(bplane, n * sizeof(float), 0, static_cast<std::size_t>(k) * n * 4);
        }
        bplane.Download(map + static_cast<std::size_t>(k) * n, n * sizeof(float));
      }
      if (whole)
      {
        ctx.KeepResident(MapKey(map), stamp, whole);
      }
    });
}

/// One SunStep as the shaders read it (std430: 3 x 16 bytes).
struct GPUStep
{
  float tanE, sunX, sunY, sunZ;
  float hours, energy, weight1, slope;
  std::int32_t sector0, sector1, slot, march; // march: alongX | (step > 0) << 1
  float length, pad0, pad1, pad2;
};

std::vector<GPUStep> PackSteps(const std::vector<tt::SunStep>& steps)
{
  std::vector<GPUStep> out(steps.size());
  for (std::size_t s = 0; s < steps.size(); ++s)
  {
    const tt::SunStep& x = steps[s];
    GPUStep& g = out[s];
    g.tanE = x.tanElevation;
    g.sunX = x.sun[0];
    g.sunY = x.sun[1];
    g.sunZ = x.sun[2];
    g.hours = x.hours;
    g.energy = x.energy;
    g.weight1 = x.sectors.weight1;
    g.slope = x.march.slope;
    g.sector0 = x.sectors.sector0;
    g.sector1 = x.sectors.sector1;
    g.slot = x.slot;
    g.march = (x.march.alongX ? 1 : 0) | (x.march.step > 0 ? 2 : 0);
    g.length = x.march.length;
    g.pad0 = g.pad1 = g.pad2 = 0.0f;
  }
  return out;
}

/// Accumulation on the GPU (Shaders/SolarIllumination.comp), in slices of cells whose map
/// planes fit one storage buffer; a map that HorizonMapGPU left on the device (one slice) is
/// used there, without an upload.
void AccumulateGPU(const terroir::TerrainInput& terrain,
  const tt::ShadowSource<float>& source,
  int sectors,
  unsigned long long mapStamp,
  const float* normals,
  const std::vector<tt::SunStep>& steps,
  int slots,
  float* hours,
  float* energy)
{
  const terroir::GridView<float>& v = terrain.view;
  const std::size_t n = v.Size();
  const std::vector<GPUStep> packed = PackSteps(steps);
  auto& ctx = terroir::gpu::Context::Global();
  const long long maxBlock = ctx.GetLimits().MaxShaderStorageBlockSize;
  const bool rayMarch = source.map == nullptr;
  const float* map = source.map;
  const std::size_t perCell = rayMarch ? 3 : static_cast<std::size_t>(sectors);
  std::size_t slice = n;
  if (maxBlock > 0)
  {
    slice = std::min<std::size_t>(slice,
      static_cast<std::size_t>(maxBlock) /
        (sizeof(float) * std::max<std::size_t>({ perCell, 3, static_cast<std::size_t>(slots) })));
  }
  // One 1-D dispatch of 64-wide groups per slice (4 Mi cells would need 65536 groups, one more
  // than GL's minimum GL_MAX_COMPUTE_WORK_GROUP_COUNT).
  const int maxGroups = ctx.GetLimits().MaxWorkGroupCount[0];
  slice =
    std::min<std::size_t>(slice, static_cast<std::size_t>(maxGroups > 0 ? maxGroups : 65535) * 64);
  slice = std::max<std::size_t>(1, std::min<std::size_t>(slice, 1u << 22));
  CheckBlock(ctx, n * sizeof(float), "elevation");
  const double work = static_cast<double>(n) * static_cast<double>(steps.size()) *
    (rayMarch || source.refine ? 64.0 : 4.0);
  ctx.Run("solar illumination",
    terroir::gpu::Context::Budget(work),
    [&]
    {
      const auto undefined = terroir::gpu::Contents::Undefined;
      const terroir::GPUTerrain t = terroir::ResidentTerrain(terrain);
      terroir::gpu::StorageBuffer bsteps(packed.size() * sizeof(GPUStep), packed.data());
      std::shared_ptr<terroir::gpu::StorageBuffer> planesOnDevice;
      if (!rayMarch && slice == n)
      {
        planesOnDevice =
          ctx.FindResident(MapKey(map), mapStamp, static_cast<std::size_t>(sectors) * n * 4);
      }
      terroir::gpu::StorageBuffer bin(
        rayMarch || planesOnDevice ? sizeof(float) : perCell * slice * sizeof(float), undefined);
      terroir::gpu::StorageBuffer bnormals(3 * slice * sizeof(float), undefined);
      terroir::gpu::StorageBuffer bhours(
        static_cast<std::size_t>(slots) * slice * sizeof(float), undefined);
      terroir::gpu::StorageBuffer benergy(
        static_cast<std::size_t>(slots) * slice * sizeof(float), undefined);
      const int method = rayMarch ? 0 : (source.refine ? 2 : 1);
      auto& prog = ctx.GetProgram("SolarIllumination.comp",
        vtkTerroirSolarIlluminationCS,
        { "LOCAL_X 64", "ILLUMINATION_METHOD " + std::to_string(method) });
      prog.SetInt("uStepCount", static_cast<int>(packed.size()));
      prog.SetInt("uSlots", slots);
      prog.SetInt("uNx", v.nx);
      prog.SetInt("uNy", v.ny);
      prog.SetInt("uHasMask", v.valid ? 1 : 0);
      prog.SetFloat("uCurvature", source.curvature);
      prog.SetFloat("uZMax", source.zMax);
      std::vector<float> planes;
      for (std::size_t first = 0; first < n; first += slice)
      {
        const std::size_t count = std::min(slice, n - first);
        t.elevation->Bind(0);
        t.mask->Bind(1);
        if (!rayMarch && !planesOnDevice)
        {
          planes.resize(static_cast<std::size_t>(sectors) * count);
          for (int k = 0; k < sectors; ++k)
          {
            std::copy(map + static_cast<std::size_t>(k) * n + first,
              map + static_cast<std::size_t>(k) * n + first + count,
              planes.begin() + static_cast<std::ptrdiff_t>(k * count));
          }
          bin.Upload(planes.data(), planes.size() * sizeof(float));
        }
        (planesOnDevice ? *planesOnDevice : bin).Bind(6);
        bnormals.Upload(normals + 3 * first, 3 * count * sizeof(float));
        bhours.Upload(hours + slots * first, slots * count * sizeof(float));
        benergy.Upload(energy + slots * first, slots * count * sizeof(float));
        bsteps.Bind(2);
        bnormals.Bind(3);
        bhours.Bind(4);
        benergy.Bind(5);
        prog.SetUInt("uCount", static_cast<unsigned>(count));
        prog.SetUInt("uFirst", static_cast<unsigned>(first));
        prog.Dispatch(static_cast<unsigned>((count + 63) / 64));
        bhours.Download(hours + slots * first, slots * count * sizeof(float));
        benergy.Download(energy + slots * first, slots * count * sizeof(float));
      }
    });
}

const char* const kSunComponents[6] = { "Month",
  "Day",
  "UTCHours",
  "Azimuth",
  "Elevation",
  "GridAzimuth" };

/// Surface normals (Horn 1981, grid frame; 3 per cell), on the CPU for both backends.
std::vector<float> SurfaceNormals(const terroir::GridView<float>& v)
{
  std::vector<float> normals(3 * v.Size());
  tt::SlopeParams sp;
  vtkSMPTools::For(0,
    v.ny,
    64,
    [&](vtkIdType r0, vtkIdType r1)
    {
      tt::SlopeHorn1981Rows(v,
        sp,
        static_cast<float*>(nullptr),
        static_cast<float*>(nullptr),
        normals.data(),
        static_cast<int>(r0),
        static_cast<int>(r1));
    });
  return normals;
}

/// An output array of `slots` components, named after the months when there are 12.
vtkSmartPointer<vtkFloatArray> NewSlotArray(const char* name,
  int slots,
  std::size_t n,
  const char* units)
{
  vtkSmartPointer<vtkFloatArray> array = vtkSmartPointer<vtkFloatArray>::Take(
    terroir::NewOutputArray(name, slots, static_cast<long long>(n), units));
  if (slots == 12)
  {
    for (int m = 0; m < 12; ++m)
    {
      array->SetComponentName(m, vtkTerroirTemperature::GetMonthName(m));
    }
  }
  return array;
}

/// NaN in every slot of the no-data cells.
void MaskNoData(const terroir::GridView<float>& v, int slots, float* hours, float* energy)
{
  const std::size_t n = v.Size();
  for (std::size_t c = 0; c < n; ++c)
  {
    if ((v.valid && !v.valid[c]) || std::isnan(v.data[c]))
    {
      std::fill(hours + slots * c, hours + slots * (c + 1), std::nanf(""));
      std::fill(energy + slots * c, energy + slots * (c + 1), std::nanf(""));
    }
  }
}

/// The HorizonAngle array: the horizon map's k sectors per cell as elevation angles, degrees.
vtkSmartPointer<vtkFloatArray> HorizonAngles(const float* map, int k, std::size_t n)
{
  vtkSmartPointer<vtkFloatArray> angles =
    vtkSmartPointer<vtkFloatArray>::Take(terroir::NewOutputArray(
      vtkTerroirSolarIllumination::HorizonAngleName(), k, static_cast<long long>(n), "deg"));
  float* a = angles->GetPointer(0);
  vtkSMPTools::For(0,
    static_cast<vtkIdType>(n),
    4096,
    [&](vtkIdType c0, vtkIdType c1)
    {
      for (vtkIdType c = c0; c < c1; ++c)
      {
        for (int s = 0; s < k; ++s)
        {
          a[c * k + s] = static_cast<float>(
            std::atan(static_cast<double>(map[static_cast<std::size_t>(s) * n + c])) * 180.0 /
            3.14159265358979323846);
        }
      }
    });
  return angles;
}

/// Field data: the sun positions used (SunPositions) and the frame (SolarFrame; no latitude
/// and longitude when no place was needed).
void AddSunFieldData(vtkFieldData* fd,
  const std::vector<tt::SunStep>& steps,
  const tt::SunFrame& frame,
  bool needPlace)
{
  vtkNew<vtkDoubleArray> sun;
  sun->SetName(vtkTerroirSolarIllumination::SunPositionsName());
  sun->SetNumberOfComponents(6);
  for (int c = 0; c < 6; ++c)
  {
    sun->SetComponentName(c, kSunComponents[c]);
  }
  sun->SetNumberOfTuples(static_cast<vtkIdType>(steps.size()));
  for (std::size_t s = 0; s < steps.size(); ++s)
  {
    const double row[6] = { static_cast<double>(steps[s].month),
      static_cast<double>(steps[s].day),
      steps[s].utcHours,
      steps[s].azimuthDeg,
      steps[s].elevationDeg,
      steps[s].gridAzimuthDeg };
    sun->SetTypedTuple(static_cast<vtkIdType>(s), row);
  }
  fd->AddArray(sun);
  vtkNew<vtkDoubleArray> frameArray;
  frameArray->SetName(vtkTerroirSolarIllumination::SolarFrameName());
  frameArray->SetNumberOfComponents(3);
  frameArray->SetComponentName(0, "Latitude");
  frameArray->SetComponentName(1, "Longitude");
  frameArray->SetComponentName(2, "GridNorthBearing");
  // With a place needed, the observer's latitude and longitude are the finite ones used.
  const double f[3] = { needPlace ? frame.observer.latitudeDeg : kNaN,
    needPlace ? frame.observer.longitudeDeg : kNaN,
    frame.gridNorthBearing };
  frameArray->InsertNextTypedTuple(f);
  fd->AddArray(frameArray);
}
} // namespace

//------------------------------------------------------------------------------
vtkTerroirSolarIllumination::vtkTerroirSolarIllumination()
  : Latitude(kNaN)
  , Longitude(kNaN)
  , Orientation(kNaN)
  , Pressure(kNaN)
  , Impl(new Internals)
{
}

//------------------------------------------------------------------------------
vtkTerroirSolarIllumination::~vtkTerroirSolarIllumination() = default;

//------------------------------------------------------------------------------
void vtkTerroirSolarIllumination::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  static const char* modes[3] = { "Instant", "Daily", "Monthly" };
  os << indent << "Mode: " << modes[this->Mode] << "\n";
  os << indent << "Date: " << this->Year << "-" << this->Month << "-" << this->Day << "\n";
  os << indent << "Time: " << this->Time << " (UTCOffset " << this->UTCOffset << ")\n";
  os << indent << "UseSunDirection: " << (this->UseSunDirection ? "On" : "Off") << " ("
     << this->SunDirection[0] << ", " << this->SunDirection[1] << ")\n";
  os << indent << "MonthlyDay: " << this->MonthlyDay << "\n";
  os << indent << "TimeStep: " << this->TimeStep << " min\n";
  os << indent << "Latitude: " << this->Latitude << "\n";
  os << indent << "Longitude: " << this->Longitude << "\n";
  os << indent << "Orientation: " << this->Orientation << "\n";
  os << indent
     << "ShadowMethod: " << (this->ShadowMethod == RayMarching ? "RayMarching" : "HorizonMap")
     << "\n";
  os << indent << "HorizonSectors: " << this->HorizonSectors << "\n";
  os << indent << "EarthCurvature: " << (this->EarthCurvature ? "On" : "Off") << "\n";
  os << indent << "OutputHorizonMap: " << (this->OutputHorizonMap ? "On" : "Off") << "\n";
  os << indent << "CacheHorizonMap: " << (this->CacheHorizonMap ? "On" : "Off") << "\n";
  os << indent << "Refraction: " << (this->Refraction ? "On" : "Off") << "\n";
  os << indent << "Pressure: " << this->Pressure << " mbar\n";
  os << indent << "AirTemperature: " << this->AirTemperature << " C\n";
  os << indent << "Transmittance: " << this->Transmittance << "\n";
  os << indent << "DeltaT: " << this->DeltaT << " s\n";
  os << indent << "DistributedHalo: " << this->DistributedHalo << " cells\n";
  os << indent << "LastHorizonMapSeconds: " << this->LastHorizonMapSeconds << "\n";
}

//------------------------------------------------------------------------------
double vtkTerroirSolarIllumination::EstimateMemory(double nx, double ny)
{
  const double cells = nx * ny;
  const double slots = this->Mode == Monthly ? 12.0 : 1.0;
  // Outputs (2 arrays), normals (12 B), the mask copy of the GPU path (1 B).
  double bytes = cells * (2.0 * 4.0 * slots + 12.0 + 1.0);
  if (this->ShadowMethod == HorizonMap || this->OutputHorizonMap)
  {
    // The map (4 B per sector), the optional HorizonAngle copy, and per thread the sweep's
    // line buffer (up to 2 cells per cell: 8 B).
    bytes += cells * (4.0 * this->HorizonSectors * (this->OutputHorizonMap ? 2.0 : 1.0) + 16.0);
  }
  return bytes;
}

//------------------------------------------------------------------------------
std::string vtkTerroirSolarIllumination::CheckParameters()
{
  auto num = [](double x) { return std::to_string(x); };
  if (!std::isnan(this->Latitude) && !(this->Latitude >= -90.0 && this->Latitude <= 90.0))
  {
    return "Latitude " + num(this->Latitude) + " is outside [-90, 90] degrees";
  }
  if (!std::isnan(this->Longitude) && !(this->Longitude >= -180.0 && this->Longitude <= 180.0))
  {
    return "Longitude " + num(this->Longitude) + " is outside [-180, 180] degrees";
  }
  if (!std::isnan(this->Orientation) && !std::isfinite(this->Orientation))
  {
    return "Orientation must be finite";
  }
  const bool dated = !(this->Mode == Instant && this->UseSunDirection);
  if (dated && this->Mode != Monthly && !tt::IsValidDate(this->Year, this->Month, this->Day))
  {
    return "date " + std::to_string(this->Year) + "-" + std::to_string(this->Month) + "-" +
      std::to_string(this->Day) + " does not exist";
  }
  if (this->Mode == Monthly && !tt::IsValidDate(this->Year, 1, 1))
  {
    return "Year " + std::to_string(this->Year) + " is outside 1..9999";
  }
  if (this->Mode == Monthly && !(this->MonthlyDay >= 1 && this->MonthlyDay <= 31))
  {
    return "MonthlyDay " + std::to_string(this->MonthlyDay) + " is outside 1..31";
  }
  if (this->Mode == Instant && !this->UseSunDirection && !(this->Time >= 0.0 && this->Time <= 24.0))
  {
    return "Time " + num(this->Time) + " h is outside [0, 24]";
  }
  if (!(this->UTCOffset >= -14.0 && this->UTCOffset <= 14.0))
  {
    return "UTCOffset " + num(this->UTCOffset) + " h is outside [-14, 14]";
  }
  if (this->Mode != Instant && !(this->TimeStep > 0.0 && this->TimeStep <= 1440.0))
  {
    return "TimeStep " + num(this->TimeStep) + " min must be > 0 and <= 1440";
  }
  if (this->Mode == Instant && this->UseSunDirection &&
    !(std::isfinite(this->SunDirection[0]) && this->SunDirection[1] >= -90.0 &&
      this->SunDirection[1] <= 90.0))
  {
    return "SunDirection elevation " + num(this->SunDirection[1]) +
      " is outside [-90, 90] degrees (or the azimuth is not finite)";
  }
  if (!(this->HorizonSectors >= 4 && this->HorizonSectors <= 1024))
  {
    return "HorizonSectors " + std::to_string(this->HorizonSectors) + " is outside [4, 1024]";
  }
  if (!(this->Transmittance > 0.0 && this->Transmittance <= 1.0))
  {
    return "Transmittance " + num(this->Transmittance) + " is outside (0, 1]";
  }
  if (!std::isnan(this->Pressure) && !(this->Pressure > 0.0 && this->Pressure <= 1200.0))
  {
    return "Pressure " + num(this->Pressure) + " mbar is outside (0, 1200]";
  }
  if (!(this->AirTemperature >= -90.0 && this->AirTemperature <= 60.0))
  {
    return "AirTemperature " + num(this->AirTemperature) + " C is outside [-90, 60]";
  }
  if (!(std::fabs(this->DeltaT) <= 10000.0))
  {
    return "DeltaT " + num(this->DeltaT) + " s is outside [-10000, 10000]";
  }
  return std::string();
}

//------------------------------------------------------------------------------
bool vtkTerroirSolarIllumination::MakeFrame(vtkImageData* input,
  const terroir::GridView<float>& v,
  tt::SunFrame& frame,
  float& zMax)
{
  const std::size_t n = v.Size();
  double latLon[2] = { kNaN, kNaN };
  const bool hasCentre = vtkTerroirGeoreference::GetCenterLatLon(input, latLon);
  const double lat = std::isnan(this->Latitude) ? latLon[0] : this->Latitude;
  const double lon = std::isnan(this->Longitude) ? latLon[1] : this->Longitude;
  if (this->NeedsPlace() && (!std::isfinite(lat) || !std::isfinite(lon)))
  {
    vtkErrorMacro(<< this->SourcePrefix(input)
                  << (hasCentre ? "the georeference has no usable centre latitude/longitude"
                                : "the terrain has no georeference")
                  << ": set Latitude and Longitude (and Orientation, the bearing of grid north)");
    return false;
  }
  frame.gridNorthBearing = !std::isnan(this->Orientation)
    ? this->Orientation
    : vtkTerroirGeoreference::GetMeridianConvergence(input);
  frame.dx = v.DxAt(v.ny / 2);
  frame.dy = v.DyAt(v.ny / 2);
  frame.sectors = this->HorizonSectors;
  frame.transmittance = this->Transmittance;
  double zSum = 0.0;
  std::size_t zCount = 0;
  zMax = -std::numeric_limits<float>::infinity();
  for (std::size_t c = 0; c < n; ++c)
  {
    if ((!v.valid || v.valid[c]) && !std::isnan(v.data[c]))
    {
      zSum += v.data[c];
      ++zCount;
      zMax = std::max(zMax, v.data[c]);
    }
  }
#if VTK_MODULE_ENABLE_VTK_ParallelCore
  if (vtkMultiProcessController* controller = this->DistributedRequest
      ? GetDistributedController(this->GetOutputInformation(0))
      : nullptr)
  {
    // The whole grid's mean and highest elevation: every piece sees the same sun. The pieces'
    // halos overlap, so each adds only the cells it owns.
    using SDDP = vtkStreamingDemandDrivenPipeline;
    vtkInformation* outInfo = this->GetOutputInformation(0);
    int whole[6], owned[6], e[6];
    outInfo->Get(SDDP::WHOLE_EXTENT(), whole);
    GetOwnedExtent(outInfo->Get(SDDP::UPDATE_PIECE_NUMBER()),
      outInfo->Get(SDDP::UPDATE_NUMBER_OF_PIECES()),
      whole,
      owned);
    input->GetExtent(e);
    double local[2] = { 0.0, 0.0 }, all[2] = { 0.0, 0.0 };
    for (int j = owned[2]; j <= owned[3]; ++j)
    {
      for (int i = owned[0]; i <= owned[1]; ++i)
      {
        const std::size_t c = v.Index(i - e[0], j - e[2]);
        if ((!v.valid || v.valid[c]) && !std::isnan(v.data[c]))
        {
          local[0] += v.data[c];
          local[1] += 1.0;
        }
      }
    }
    float highest = zMax;
    if (!controller->AllReduce(local, all, 2, vtkCommunicator::SUM_OP) ||
      !controller->AllReduce(&highest, &zMax, 1, vtkCommunicator::MAX_OP))
    {
      vtkErrorMacro(<< this->SourcePrefix(input) << "the all-reduce of the elevations failed");
      return false;
    }
    zSum = all[0];
    zCount = static_cast<std::size_t>(all[1]);
  }
#endif
  frame.meanElevationM = zCount ? zSum / zCount : 0.0;
  frame.observer.latitudeDeg = std::isfinite(lat) ? lat : 0.0;
  frame.observer.longitudeDeg = std::isfinite(lon) ? lon : 0.0;
  frame.observer.elevationM = frame.meanElevationM;
  frame.observer.pressureMbar = std::isnan(this->Pressure)
    ? 1013.25 * std::exp(-frame.meanElevationM / 8200.0)
    : this->Pressure;
  frame.observer.temperatureC = this->AirTemperature;
  frame.observer.refraction = this->Refraction;
  frame.observer.deltaTSeconds = this->DeltaT;
  return true;
}

//------------------------------------------------------------------------------
std::vector<tt::SunStep> vtkTerroirSolarIllumination::SunSteps(const tt::SunFrame& frame,
  int& slots)
{
  std::vector<tt::SunStep> steps;
  slots = 1;
  if (this->Mode == Instant)
  {
    tt::SunStep s;
    if (this->UseSunDirection)
    {
      s = tt::MakeSunStep(this->SunDirection[0], this->SunDirection[1], frame);
      s.utcHours = kNaN;
      s.month = 0;
      s.day = 0;
    }
    else
    {
      tt::UTCInstant t;
      t.year = this->Year;
      t.month = this->Month;
      t.day = this->Day;
      t.hours = this->Time - this->UTCOffset;
      const tt::SolarPosition p = tt::SolarPositionNREL2004(t, frame.observer);
      s = tt::MakeSunStep(p.azimuthDeg, p.elevationDeg, frame);
      s.utcHours = t.hours;
      s.month = this->Month;
      s.day = this->Day;
    }
    s.hours = 1.0f;
    s.energy = 1.0f;
    steps.push_back(s);
  }
  else if (this->Mode == Daily)
  {
    steps = tt::DaySunSteps(this->Year, this->Month, this->Day, this->TimeStep, 0, frame);
  }
  else
  {
    slots = 12;
    for (int m = 1; m <= 12; ++m)
    {
      const int day = std::min(this->MonthlyDay, tt::DaysInMonth(this->Year, m));
      const std::vector<tt::SunStep> d =
        tt::DaySunSteps(this->Year, m, day, this->TimeStep, m - 1, frame);
      steps.insert(steps.end(), d.begin(), d.end());
    }
  }
  return steps;
}

//------------------------------------------------------------------------------
bool vtkTerroirSolarIllumination::UpdateHorizonMap(vtkImageData* input,
  const terroir::TerrainInput& terrain,
  float curvature,
  int& backend)
{
  const terroir::GridView<float>& v = terrain.view;
  const std::size_t n = v.Size();
  Internals& cache = *this->Impl;
  const bool fresh = cache.InputData == static_cast<const void*>(v.data) &&
    cache.InputTime == input->GetMTime() && cache.Sectors == this->HorizonSectors &&
    cache.Curvature == this->EarthCurvature && cache.Cells == n && cache.Backend == backend &&
    cache.Map.size() == static_cast<std::size_t>(this->HorizonSectors) * n;
  if (fresh)
  {
    return true;
  }
  cache.Map.clear();
  cache.InputData = nullptr;
  cache.Map.resize(static_cast<std::size_t>(this->HorizonSectors) * n);
  const auto t0 = std::chrono::steady_clock::now();
  float* map = cache.Map.data();
  const int sectors = this->HorizonSectors;
  // Every map computed gets a new stamp: its device copy (HorizonMapGPU) is keyed on it.
  static std::atomic<unsigned long long> mapStamps{ 0 };
  const unsigned long long mapStamp = ++mapStamps;
  cache.Stamp = mapStamp;
  if (backend == vtkTerroirComputeContext::GPU)
  {
    backend = this->RunGPUPath([&] { HorizonMapGPU(terrain, sectors, curvature, map, mapStamp); });
    if (backend < 0)
    {
      return false;
    }
  }
  if (backend == vtkTerroirComputeContext::CPU)
  {
    vtkSMPTools::For(0,
      sectors,
      1,
      [&](vtkIdType k0, vtkIdType k1) {
        tt::HorizonMapSectors(
          v, sectors, curvature, map, static_cast<int>(k0), static_cast<int>(k1));
      });
  }
  this->LastHorizonMapSeconds =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  cache.InputData = v.data;
  cache.InputTime = input->GetMTime();
  cache.Sectors = sectors;
  cache.Curvature = this->EarthCurvature;
  cache.Cells = n;
  cache.Backend = backend;
  vtkLog(
    TRACE, << "horizon map of " << sectors << " sectors: " << this->LastHorizonMapSeconds << " s");
  return true;
}

//------------------------------------------------------------------------------
bool vtkTerroirSolarIllumination::Accumulate(const terroir::TerrainInput& terrain,
  const tt::ShadowSource<float>& source,
  const std::vector<float>& normals,
  const std::vector<tt::SunStep>& steps,
  int slots,
  int& backend,
  float* hours,
  float* energy)
{
  const terroir::GridView<float>& v = terrain.view;
  const std::size_t n = v.Size();
  const bool useMap = this->ShadowMethod == HorizonMap;
  if (backend == vtkTerroirComputeContext::GPU)
  {
    backend = this->RunGPUPath(
      [&]
      {
        AccumulateGPU(terrain,
          source,
          this->HorizonSectors,
          this->Impl->Stamp,
          normals.data(),
          steps,
          slots,
          hours,
          energy);
      });
    if (backend < 0)
    {
      return false;
    }
    if (backend == vtkTerroirComputeContext::CPU)
    {
      std::fill(hours, hours + slots * n, 0.0f);
      std::fill(energy, energy + slots * n, 0.0f);
    }
  }
  if (backend == vtkTerroirComputeContext::CPU)
  {
    const int stepCount = static_cast<int>(steps.size());
    // Ten slices on this thread (for progress), each split over the SMP threads.
    const double p0 = (useMap || this->OutputHorizonMap) ? 0.5 : 0.0;
    for (int slice = 0; slice < 10; ++slice)
    {
      const vtkIdType c0 = static_cast<vtkIdType>(n) * slice / 10;
      const vtkIdType c1 = static_cast<vtkIdType>(n) * (slice + 1) / 10;
      vtkSMPTools::For(c0,
        c1,
        useMap && !source.refine ? 4096 : 256,
        [&](vtkIdType b0, vtkIdType b1)
        {
          tt::AccumulateIllumination(v,
            source,
            normals.data(),
            steps.data(),
            stepCount,
            slots,
            hours,
            energy,
            static_cast<std::size_t>(b0),
            static_cast<std::size_t>(b1));
        });
      this->UpdateProgress(p0 + (0.95 - p0) * (slice + 1) / 10.0);
    }
  }
  return true;
}

//------------------------------------------------------------------------------
int vtkTerroirSolarIllumination::RequestTerrainData(vtkImageData* input,
  const terroir::TerrainInput& terrain,
  vtkImageData* output)
{
  const terroir::GridView<float>& v = terrain.view;
  const std::size_t n = v.Size();

  // Frame: where the sun is seen from and how grid north is turned.
  tt::SunFrame frame;
  float zMax = 0.0f;
  if (!this->MakeFrame(input, v, frame, zMax))
  {
    return 0;
  }
  // Sun steps.
  int slots = 1;
  const std::vector<tt::SunStep> steps = this->SunSteps(frame, slots);

  int backend = this->SelectBackend(this->HasGPUPath());
  if (backend < 0)
  {
    return 0;
  }

  // Horizon map (cached while the input and its settings stay the same, unless the cache is
  // off: then freed when this update ends, whichever way).
  struct DropMap
  {
    vtkTerroirSolarIllumination* self;
    ~DropMap()
    {
      if (!self->CacheHorizonMap)
      {
        *self->Impl = Internals();
      }
    }
  } dropMap{ this };
  const bool useMap = this->ShadowMethod == HorizonMap;
  const float curvature = tt::CurvatureCoefficient(this->EarthCurvature);
  this->LastHorizonMapSeconds = 0.0;
  if (useMap || this->OutputHorizonMap)
  {
    if (!this->UpdateHorizonMap(input, terrain, curvature, backend))
    {
      return 0;
    }
    this->UpdateProgress(0.5);
  }

  // Surface normals (Horn 1981, grid frame), on the CPU for both backends.
  const std::vector<float> normals = SurfaceNormals(v);

  // Accumulation.
  const bool instant = this->Mode == Instant;
  vtkSmartPointer<vtkFloatArray> hoursArray = NewSlotArray(
    instant ? IlluminatedName() : IlluminationHoursName(), slots, n, instant ? nullptr : "h");
  vtkSmartPointer<vtkFloatArray> energyArray = NewSlotArray(
    instant ? SunIncidenceName() : InsolationName(), slots, n, instant ? nullptr : "Wh/m2");
  float* hours = hoursArray->GetPointer(0);
  float* energy = energyArray->GetPointer(0);
  std::fill(hours, hours + slots * n, 0.0f);
  std::fill(energy, energy + slots * n, 0.0f);
  const float* map = this->Impl->Map.empty() ? nullptr : this->Impl->Map.data();
  tt::ShadowSource<float> source;
  source.map = useMap ? map : nullptr;
  // An instant costs one lookup: where the interpolation between sectors cannot decide, march.
  source.refine = useMap && this->Mode == Instant;
  source.curvature = curvature;
  source.zMax = zMax;
  if (!this->Accumulate(terrain, source, normals, steps, slots, backend, hours, energy))
  {
    return 0;
  }
  // No-data cells: NaN.
  MaskNoData(v, slots, hours, energy);
  output->GetPointData()->AddArray(hoursArray);
  output->GetPointData()->AddArray(energyArray);

  if (this->OutputHorizonMap)
  {
    output->GetPointData()->AddArray(HorizonAngles(map, this->HorizonSectors, n));
  }

  // Field data: the sun positions used and the frame.
  AddSunFieldData(output->GetFieldData(), steps, frame, this->NeedsPlace());
  this->LastHaloUncertainShare = -1.0;
  if (this->DistributedRequest && !this->MeasureHaloUncertainty(input, v, steps, zMax, output))
  {
    return 0;
  }
  return 1;
}

//------------------------------------------------------------------------------
bool vtkTerroirSolarIllumination::MeasureHaloUncertainty(vtkImageData* input,
  const terroir::GridView<float>& v,
  const std::vector<terroir::terrain::SunStep>& steps,
  float zMax,
  vtkImageData* output)
{
#if VTK_MODULE_ENABLE_VTK_ParallelCore
  using SDDP = vtkStreamingDemandDrivenPipeline;
  vtkInformation* outInfo = this->GetOutputInformation(0);
  vtkMultiProcessController* controller = GetDistributedController(outInfo);
  if (!controller)
  {
    vtkErrorMacro(<< this->SourcePrefix(input) << "a distributed run without its controller");
    return false;
  }
  int whole[6], owned[6], e[6];
  outInfo->Get(SDDP::WHOLE_EXTENT(), whole);
  GetOwnedExtent(outInfo->Get(SDDP::UPDATE_PIECE_NUMBER()),
    outInfo->Get(SDDP::UPDATE_NUMBER_OF_PIECES()),
    whole,
    owned);
  input->GetExtent(e);
  // tan(elevation) of the steps with the sun above the horizontal, sorted.
  std::vector<float> tans;
  for (const tt::SunStep& step : steps)
  {
    if (step.elevationDeg > 0.0)
    {
      tans.push_back(step.tanElevation);
    }
  }
  std::sort(tans.begin(), tans.end());
  const double inf = std::numeric_limits<double>::infinity();
  // Terrain beyond a cut edge of the halo (one the whole grid does not share) lies at least
  // this far from a cell, and rises at most to the grid's highest cell: a step whose sun is
  // above that tangent is decided by the terrain this piece holds.
  double counts[2] = { 0.0, 0.0 }, all[2] = { 0.0, 0.0 };
  for (int j = owned[2]; j <= owned[3]; ++j)
  {
    const int vj = j - e[2];
    const double dx = v.DxAt(vj);
    const double dy = v.DyAt(vj);
    const double dj = std::min(
      e[2] > whole[2] ? (j - e[2] + 1) * dy : inf, e[3] < whole[3] ? (e[3] - j + 1) * dy : inf);
    for (int i = owned[0]; i <= owned[1]; ++i)
    {
      const std::size_t c = v.Index(i - e[0], vj);
      if ((v.valid && !v.valid[c]) || std::isnan(v.data[c]))
      {
        continue;
      }
      const double d = std::min({ dj,
        e[0] > whole[0] ? (i - e[0] + 1) * dx : inf,
        e[1] < whole[1] ? (e[1] - i + 1) * dx : inf });
      const double bound = (static_cast<double>(zMax) - v.data[c]) / d;
      counts[0] +=
        static_cast<double>(std::upper_bound(tans.begin(),
                              tans.end(),
                              bound,
                              [](double b, float t) { return b < static_cast<double>(t); }) -
          tans.begin());
      counts[1] += static_cast<double>(tans.size());
    }
  }
  if (!controller->AllReduce(counts, all, 2, vtkCommunicator::SUM_OP))
  {
    vtkErrorMacro(<< this->SourcePrefix(input) << "the all-reduce of the halo's decisions failed");
    return false;
  }
  this->LastHaloUncertainShare = all[1] > 0.0 ? all[0] / all[1] : 0.0;
  auto share = vtkSmartPointer<vtkDoubleArray>::New();
  share->SetName("SunHaloUncertainShare");
  share->InsertNextValue(this->LastHaloUncertainShare);
  output->GetFieldData()->AddArray(share);
  if (this->LastHaloUncertainShare > 0.0 && controller->GetLocalProcessId() == 0)
  {
    vtkWarningMacro(<< this->SourcePrefix(input) << "in pieces with a halo of "
                    << this->DistributedHalo << " cells, " << 100.0 * this->LastHaloUncertainShare
                    << " % of the sunlit decisions could change with terrain beyond the halo "
                       "(raise DistributedHalo for the serial shadows)");
  }
  return true;
#else
  (void)v;
  (void)steps;
  (void)zMax;
  (void)output;
  vtkErrorMacro(<< this->SourcePrefix(input) << "built without VTK::ParallelCore");
  return false;
#endif
}

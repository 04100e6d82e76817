#include "vtkTerroirTemperature.h"
#include "vtkTerroirComputeContext.h"

#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkTerroirGPU.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirTemperatureCS.h"
#include "vtkTerroirTerrainInput.h"

#include "TemperatureLapseRate.h"

#include <algorithm>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkTerroirTemperature);

namespace
{
const char* const kMonthNames[12] = { "Jan",
  "Feb",
  "Mar",
  "Apr",
  "May",
  "Jun",
  "Jul",
  "Aug",
  "Sep",
  "Oct",
  "Nov",
  "Dec" };

} // namespace

const char* vtkTerroirTemperature::GetMonthName(int month)
{
  return month >= 0 && month < 12 ? kMonthNames[month] : nullptr;
}

namespace
{
struct TemperatureFunctor
{
  const terroir::GridView<float>* View;
  const double* SeaLevel;
  double LapseRate;
  float* Out;
  void operator()(vtkIdType begin, vtkIdType end) const
  {
    terroir::terrain::TemperatureLapseRateRows(*this->View,
      this->SeaLevel,
      this->LapseRate,
      this->Out,
      static_cast<int>(begin),
      static_cast<int>(end));
  }
};

/// Runs Shaders/Temperature.comp (bindings documented there) in slices of cells whose output
/// fits one storage buffer; the elevation stays resident when the whole grid fits one.
void RunTemperatureGPU(const terroir::TerrainInput& terrain,
  const double seaLevel[12],
  double lapseRate,
  float* out)
{
  const terroir::GridView<float>& v = terrain.view;
  const std::size_t n = v.Size();
  float sea[12];
  for (int m = 0; m < 12; ++m)
  {
    sea[m] = static_cast<float>(seaLevel[m]);
  }
  auto& ctx = terroir::gpu::Context::Global();
  const terroir::gpu::Limits limits = ctx.GetLimits();
  const std::size_t maxBlock = limits.StorageBlockBytes();
  const terroir::gpu::GridPlan plan = terroir::gpu::PlanGrid(limits, 1, 256);
  std::size_t slice = std::min<std::size_t>(n, std::size_t(1) << 22); // 4 Mi cells, 192 MiB out
  slice = std::max<std::size_t>(1, std::min({ slice, plan.MaxItems, maxBlock / 48 }));
  const bool whole = n * sizeof(float) <= maxBlock;
  ctx.Run("temperature",
    terroir::gpu::Context::Budget(12.0 * static_cast<double>(n)),
    [&]
    {
      terroir::GPUTerrain t;
      std::unique_ptr<terroir::gpu::StorageBuffer> sliceZ;
      if (whole)
      {
        t = terroir::ResidentTerrain(terrain);
      }
      else
      {
        const std::vector<std::uint32_t> mask = terroir::PackValidMask(v);
        t.mask = std::make_shared<terroir::gpu::StorageBuffer>(
          mask.size() * sizeof(std::uint32_t), mask.data());
        sliceZ.reset(new terroir::gpu::StorageBuffer(
          slice * sizeof(float), terroir::gpu::Contents::Undefined));
      }
      terroir::gpu::StorageBuffer bt(12 * slice * sizeof(float), terroir::gpu::Contents::Undefined);
      std::vector<std::string> defines = { "LOCAL_X 256" };
      if (v.valid)
      {
        defines.push_back("TEMPERATURE_MASK");
      }
      auto& prog = ctx.GetProgram("Temperature.comp", vtkTerroirTemperatureCS, defines);
      prog.SetFloatArray("uSeaLevel", sea, 12);
      prog.SetFloat("uRate", static_cast<float>(lapseRate / 1000.0));
      (whole ? *t.elevation : *sliceZ).Bind(0);
      t.mask->Bind(1);
      bt.Bind(2);
      for (std::size_t first = 0; first < n; first += slice)
      {
        const std::size_t count = std::min(slice, n - first);
        if (!whole)
        {
          sliceZ->Upload(v.data + first, count * sizeof(float));
        }
        prog.SetUInt("uCount", static_cast<unsigned>(count));
        prog.SetUInt("uFirst", static_cast<unsigned>(first));
        prog.SetUInt("uElevationFirst", whole ? static_cast<unsigned>(first) : 0u);
        const terroir::gpu::Groups g = plan.For(count);
        prog.Dispatch(g.x, g.y);
        bt.Download(out + 12 * first, 12 * count * sizeof(float));
      }
    });
}
} // namespace

//------------------------------------------------------------------------------
vtkTerroirTemperature::vtkTerroirTemperature() = default;

//------------------------------------------------------------------------------
vtkTerroirTemperature::~vtkTerroirTemperature() = default;

//------------------------------------------------------------------------------
void vtkTerroirTemperature::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  static const char* hemis[3] = { "Auto", "North", "South" };
  os << indent << "SeaLevelTemperatureColdest: " << this->SeaLevelTemperatureColdest << "\n";
  os << indent << "SeaLevelTemperatureWarmest: " << this->SeaLevelTemperatureWarmest << "\n";
  os << indent << "ColdestMonth: " << this->ColdestMonth << "\n";
  os << indent << "WarmestMonth: " << this->WarmestMonth << "\n";
  os << indent << "Hemisphere: " << hemis[this->Hemisphere] << "\n";
  os << indent << "LapseRate: " << this->LapseRate << "\n";
  os << indent << "UseMonthlyTemperatures: " << (this->UseMonthlyTemperatures ? "On" : "Off")
     << "\n";
  os << indent << "MonthlySeaLevelTemperatures:";
  for (int m = 0; m < 12; ++m)
  {
    os << " " << this->MonthlySeaLevelTemperatures[m];
  }
  os << "\n";
  os << indent << "LastHemisphere: " << hemis[this->LastHemisphere] << "\n";
}

//------------------------------------------------------------------------------
bool vtkTerroirTemperature::ComputeSeaLevelTemperatures(int hemisphere, double monthly[12])
{
  if (this->UseMonthlyTemperatures)
  {
    std::copy(this->MonthlySeaLevelTemperatures, this->MonthlySeaLevelTemperatures + 12, monthly);
    return true;
  }
  const bool south = hemisphere == South;
  const int coldest = this->ColdestMonth > 0 ? this->ColdestMonth : (south ? 7 : 1);
  const int warmest = this->WarmestMonth > 0 ? this->WarmestMonth : (south ? 1 : 7);
  return terroir::terrain::SeaLevelTemperaturesFromExtremes(
    this->SeaLevelTemperatureColdest, this->SeaLevelTemperatureWarmest, coldest, warmest, monthly);
}

//------------------------------------------------------------------------------
double vtkTerroirTemperature::EstimateMemory(double nx, double ny)
{
  // Temperature (12 x 4 B per cell); the GPU path adds a packed mask (1 B) and, on a software
  // rasterizer, its mask storage buffer in host memory.
  return nx * ny * (48.0 + (this->Backend == vtkTerroirComputeContext::CPU ? 0.0 : 2.0));
}

//------------------------------------------------------------------------------
std::string vtkTerroirTemperature::CheckParameters()
{
  auto outside = [](double t) { return !(t >= -90.0 && t <= 60.0); };
  if (!(this->LapseRate >= 0.0 && this->LapseRate <= 20.0))
  {
    return "LapseRate " + std::to_string(this->LapseRate) + " C/km is outside [0, 20]";
  }
  if (this->UseMonthlyTemperatures)
  {
    for (int m = 0; m < 12; ++m)
    {
      if (outside(this->MonthlySeaLevelTemperatures[m]))
      {
        return std::string("sea-level temperature of ") + kMonthNames[m] + " " +
          std::to_string(this->MonthlySeaLevelTemperatures[m]) + " C is outside [-90, 60]";
      }
    }
    return std::string();
  }
  if (outside(this->SeaLevelTemperatureColdest) || outside(this->SeaLevelTemperatureWarmest))
  {
    return "sea-level temperatures " + std::to_string(this->SeaLevelTemperatureColdest) +
      " (coldest) and " + std::to_string(this->SeaLevelTemperatureWarmest) +
      " C (warmest) must lie in [-90, 60]";
  }
  if (this->SeaLevelTemperatureColdest > this->SeaLevelTemperatureWarmest)
  {
    return "the coldest month's sea-level temperature " +
      std::to_string(this->SeaLevelTemperatureColdest) + " C is above the warmest month's " +
      std::to_string(this->SeaLevelTemperatureWarmest) + " C";
  }
  return std::string();
}

//------------------------------------------------------------------------------
int vtkTerroirTemperature::RequestTerrainData(vtkImageData* input,
  const terroir::TerrainInput& terrain,
  vtkImageData* output)
{
  int hemisphere = this->Hemisphere;
  if (hemisphere == AutoHemisphere)
  {
    double latLon[2];
    hemisphere =
      (vtkTerroirGeoreference::GetCenterLatLon(input, latLon) && latLon[0] < 0.0) ? South : North;
  }
  double sea[12];
  if (!this->ComputeSeaLevelTemperatures(hemisphere, sea))
  {
    vtkErrorMacro(<< this->SourcePrefix(input) << "ColdestMonth and WarmestMonth must differ");
    return 0;
  }
  this->LastHemisphere = hemisphere;

  const terroir::GridView<float>& v = terrain.view;
  vtkSmartPointer<vtkFloatArray> temperature =
    vtkSmartPointer<vtkFloatArray>::Take(terroir::NewOutputArray(
      TemperatureName(), 12, static_cast<long long>(v.Size()), "degC", kMonthNames));
  float* out = temperature->GetPointer(0);

  int backend = this->SelectBackend(this->HasGPUPath());
  if (backend < 0)
  {
    return 0;
  }
  if (backend == vtkTerroirComputeContext::GPU)
  {
    backend = this->RunGPUPath([&] { RunTemperatureGPU(terrain, sea, this->LapseRate, out); });
    if (backend < 0)
    {
      return 0;
    }
  }
  if (backend == vtkTerroirComputeContext::CPU)
  {
    TemperatureFunctor functor{ &v, sea, this->LapseRate, out };
    const int slices = std::min(10, v.ny);
    for (int s = 0; s < slices; ++s)
    {
      const vtkIdType r0 = static_cast<vtkIdType>(v.ny) * s / slices;
      const vtkIdType r1 = static_cast<vtkIdType>(v.ny) * (s + 1) / slices;
      vtkSMPTools::For(r0, r1, 16, functor);
      this->UpdateProgress(0.9 * (s + 1) / slices);
    }
  }
  output->GetPointData()->AddArray(temperature);
  return 1;
}

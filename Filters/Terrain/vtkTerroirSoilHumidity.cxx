#include "vtkTerroirSoilHumidity.h"
#include "vtkTerroirComputeContext.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkTerroirGPU.h"
#include "vtkTerroirSoilHumidityCS.h"
#include "vtkTerroirTemperature.h"
#include "vtkTerroirTerrainInput.h"

#include "SoilWater.h"

#include <algorithm>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkTerroirSoilHumidity);

namespace
{
/// Cells per GPU dispatch: three 12-month float outputs of 48 MiB each.
constexpr std::size_t kGPUSliceCells = std::size_t(1) << 20;

struct SoilHumidityFunctor
{
  const float* Rate;
  const std::uint8_t* Valid;
  const terroir::terrain::MonthlyRain* Rain;
  float* Humidity;
  float* Weighted;
  float* Standing;
  void operator()(vtkIdType begin, vtkIdType end) const
  {
    terroir::terrain::SoilHumidityLong2016(this->Rate,
      this->Valid,
      *this->Rain,
      this->Humidity,
      this->Weighted,
      this->Standing,
      static_cast<std::size_t>(begin),
      static_cast<std::size_t>(end));
  }
};

/// Runs Shaders/SoilHumidity.comp (bindings documented there) in slices of cells whose outputs
/// fit one storage buffer; the rates (under `rateKey`, `rateStamp`) and the terrain's mask stay
/// resident when the whole grid fits one.
void RunSoilHumidityGPU(const terroir::TerrainInput& terrain,
  const float* rate,
  const void* rateKey,
  unsigned long long rateStamp,
  const terroir::terrain::MonthlyRain& rain,
  float* humidity,
  float* weighted,
  float* standing)
{
  const terroir::GridView<float>& v = terrain.view;
  const std::size_t n = v.Size();
  auto& ctx = terroir::gpu::Context::Global();
  const terroir::gpu::Limits limits = ctx.GetLimits();
  const std::size_t maxBlock = limits.StorageBlockBytes();
  const terroir::gpu::GridPlan plan = terroir::gpu::PlanGrid(limits, 1, 256);
  const std::size_t slice =
    std::max<std::size_t>(1, std::min({ n, kGPUSliceCells, plan.MaxItems, maxBlock / 48 }));
  const bool whole = n * sizeof(float) <= maxBlock;
  std::vector<std::string> defines = { "LOCAL_X 256" };
  if (v.valid)
  {
    defines.push_back("HUMIDITY_MASK");
  }
  if (weighted)
  {
    defines.push_back("HUMIDITY_WEIGHTED");
  }
  if (standing)
  {
    defines.push_back("HUMIDITY_STANDING");
  }
  const double outputs = 1.0 + (weighted ? 1 : 0) + (standing ? 1 : 0);
  ctx.Run("soil humidity",
    terroir::gpu::Context::Budget(12.0 * outputs * static_cast<double>(n)),
    [&]
    {
      const auto undefined = terroir::gpu::Contents::Undefined;
      std::shared_ptr<terroir::gpu::StorageBuffer> brate, bmask;
      if (whole)
      {
        brate = ctx.Resident(rateKey, rateStamp, n * sizeof(float), rate);
        bmask = terroir::ResidentTerrain(terrain).mask;
      }
      else
      {
        const std::vector<std::uint32_t> mask = terroir::PackValidMask(v);
        bmask = std::make_shared<terroir::gpu::StorageBuffer>(
          mask.size() * sizeof(std::uint32_t), mask.data());
        brate = std::make_shared<terroir::gpu::StorageBuffer>(slice * sizeof(float), undefined);
      }
      const std::size_t outBytes = 12 * slice * sizeof(float);
      terroir::gpu::StorageBuffer bh(outBytes, undefined);
      terroir::gpu::StorageBuffer bw(weighted ? outBytes : 16, undefined);
      terroir::gpu::StorageBuffer bs(standing ? outBytes : 16, undefined);
      auto& prog = ctx.GetProgram("SoilHumidity.comp", vtkTerroirSoilHumidityCS, defines);
      // The per-month constants of the core's kernel.
      const terroir::terrain::SoilHumidityMonthConstants constants =
        terroir::terrain::SoilHumidityLong2016Constants(rain);
      prog.SetFloatArray("uQuantity", constants.quantity, 12);
      prog.SetFloatArray("uInverseIntensity", constants.inverseIntensity, 12);
      brate->Bind(0);
      bmask->Bind(1);
      bh.Bind(2);
      bw.Bind(3);
      bs.Bind(4);
      for (std::size_t first = 0; first < n; first += slice)
      {
        const std::size_t count = std::min(slice, n - first);
        if (!whole)
        {
          brate->Upload(rate + first, count * sizeof(float));
        }
        prog.SetUInt("uCount", static_cast<unsigned>(count));
        prog.SetUInt("uFirst", static_cast<unsigned>(first));
        prog.SetUInt("uRateFirst", whole ? static_cast<unsigned>(first) : 0u);
        const terroir::gpu::Groups g = plan.For(count);
        prog.Dispatch(g.x, g.y);
        bh.Download(humidity + 12 * first, 12 * count * sizeof(float));
        if (weighted)
        {
          bw.Download(weighted + 12 * first, 12 * count * sizeof(float));
        }
        if (standing)
        {
          bs.Download(standing + 12 * first, 12 * count * sizeof(float));
        }
      }
    });
}

vtkSmartPointer<vtkDoubleArray> MonthlyFieldArray(const char* name,
  const double values[12],
  const char* units)
{
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  a->SetNumberOfValues(12);
  for (int m = 0; m < 12; ++m)
  {
    a->SetValue(m, values[m]);
  }
  a->GetInformation()->Set(vtkDataArray::UNITS_LABEL(), units);
  return a;
}

/// "" when the 24 climate values are usable, else one line naming the first bad one.
std::string CheckClimate(const double q[12], const double i[12])
{
  for (int m = 0; m < 12; ++m)
  {
    const std::string month = vtkTerroirTemperature::GetMonthName(m);
    if (!(q[m] >= 0.0 && q[m] <= 10000.0))
    {
      return "precipitation of " + month + " " + std::to_string(q[m]) + " mm is outside [0, 10000]";
    }
    if (!(i[m] >= 0.0 && i[m] <= 500.0))
    {
      return "precipitation intensity of " + month + " " + std::to_string(i[m]) +
        " mm/h is outside [0, 500]";
    }
    if (q[m] > 0.0 && !(i[m] > 0.0))
    {
      return "precipitation of " + month + " is " + std::to_string(q[m]) +
        " mm but its intensity is 0: rain needs a positive intensity";
    }
  }
  return std::string();
}
} // namespace

//------------------------------------------------------------------------------
vtkTerroirSoilHumidity::vtkTerroirSoilHumidity()
{
  this->SetInputArrayToProcess(
    1, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "InfiltrationRate");
}

//------------------------------------------------------------------------------
vtkTerroirSoilHumidity::~vtkTerroirSoilHumidity() {}

//------------------------------------------------------------------------------
void vtkTerroirSoilHumidity::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Precipitation:";
  for (double q : this->Precipitation)
  {
    os << " " << q;
  }
  os << "\n" << indent << "PrecipitationIntensity:";
  for (double i : this->PrecipitationIntensity)
  {
    os << " " << i;
  }
  os << "\n";
  os << indent
     << "ComputeWeightedSoilHumidity: " << (this->ComputeWeightedSoilHumidity ? "On" : "Off")
     << "\n";
  os << indent << "ComputeStandingWater: " << (this->ComputeStandingWater ? "On" : "Off") << "\n";
}

//------------------------------------------------------------------------------
double vtkTerroirSoilHumidity::EstimateMemory(double nx, double ny)
{
  const double outputs = 1.0 + (this->ComputeWeightedSoilHumidity ? 1.0 : 0.0) +
    (this->ComputeStandingWater ? 1.0 : 0.0);
  // 48 B per output per cell, a float copy of a non-float rate (4 B); the GPU path adds its
  // packed mask and, on a software rasterizer, one slice of buffers in host memory.
  double bytes = nx * ny * (48.0 * outputs + 4.0);
  if (this->Backend != vtkTerroirComputeContext::CPU)
  {
    bytes += nx * ny * 1.0 + static_cast<double>(kGPUSliceCells) * (4.0 + 48.0 * outputs);
  }
  return bytes;
}

//------------------------------------------------------------------------------
std::string vtkTerroirSoilHumidity::CheckParameters()
{
  return CheckClimate(this->Precipitation, this->PrecipitationIntensity);
}

//------------------------------------------------------------------------------
int vtkTerroirSoilHumidity::RequestTerrainData(vtkImageData* input,
  const terroir::TerrainInput& terrain,
  vtkImageData* output)
{
  const std::string prefix = this->SourcePrefix(input);
  double q[12];
  double intensity[12];
  std::copy(this->Precipitation, this->Precipitation + 12, q);
  std::copy(this->PrecipitationIntensity, this->PrecipitationIntensity + 12, intensity);

  const terroir::GridView<float>& v = terrain.view;
  const std::size_t n = v.Size();
  vtkDataArray* rateArray = this->GetInputArrayToProcess(1, input);
  if (!rateArray)
  {
    vtkErrorMacro(<< prefix << "the terrain has no InfiltrationRate array (mm/h): run "
                  << "vtkTerroirInfiltration first");
    return 0;
  }
  if (rateArray->GetNumberOfComponents() != 1 ||
    rateArray->GetNumberOfTuples() != static_cast<vtkIdType>(n))
  {
    vtkErrorMacro(<< prefix << "InfiltrationRate must have 1 component and " << n << " tuples, not "
                  << rateArray->GetNumberOfComponents() << " and "
                  << rateArray->GetNumberOfTuples());
    return 0;
  }
  const float* rate = nullptr;
  std::vector<float> rateCopy;
  if (auto* f = vtkFloatArray::FastDownCast(rateArray))
  {
    rate = f->GetPointer(0);
  }
  else
  {
    rateCopy.resize(n);
    for (std::size_t k = 0; k < n; ++k)
    {
      rateCopy[k] = static_cast<float>(rateArray->GetComponent(static_cast<vtkIdType>(k), 0));
    }
    rate = rateCopy.data();
  }
  const double minRate = rateArray->GetRange(0)[0];
  if (minRate < 0.0)
  {
    vtkErrorMacro(<< prefix << "InfiltrationRate has negative values (down to " << minRate
                  << " mm/h)");
    return 0;
  }

  terroir::terrain::MonthlyRain rain{};
  for (int m = 0; m < 12; ++m)
  {
    rain.quantityMm[m] = static_cast<float>(q[m]);
    rain.intensityMmPerHour[m] = static_cast<float>(intensity[m]);
  }
  const char* months[12];
  for (int m = 0; m < 12; ++m)
  {
    months[m] = vtkTerroirTemperature::GetMonthName(m);
  }
  auto make = [&](const char* name)
  {
    return vtkSmartPointer<vtkFloatArray>::Take(
      terroir::NewOutputArray(name, 12, static_cast<long long>(n), "mm", months));
  };
  vtkSmartPointer<vtkFloatArray> humidity = make(SoilHumidityName());
  vtkSmartPointer<vtkFloatArray> weighted =
    this->ComputeWeightedSoilHumidity ? make(WeightedSoilHumidityName()) : nullptr;
  vtkSmartPointer<vtkFloatArray> standing =
    this->ComputeStandingWater ? make(StandingWaterName()) : nullptr;
  float* h = humidity->GetPointer(0);
  float* w = weighted ? weighted->GetPointer(0) : nullptr;
  float* s = standing ? standing->GetPointer(0) : nullptr;

  int backend = this->SelectBackend(this->HasGPUPath());
  if (backend < 0)
  {
    return 0;
  }
  if (backend == vtkTerroirComputeContext::GPU)
  {
    backend = this->RunGPUPath(
      [&] { RunSoilHumidityGPU(terrain, rate, rateArray, rateArray->GetMTime(), rain, h, w, s); });
    if (backend < 0)
    {
      return 0;
    }
  }
  if (backend == vtkTerroirComputeContext::CPU)
  {
    SoilHumidityFunctor functor{ rate, v.valid, &rain, h, w, s };
    const int slices = static_cast<int>(std::min<std::size_t>(10, n));
    for (int k = 0; k < slices; ++k)
    {
      const vtkIdType c0 = static_cast<vtkIdType>(n * k / slices);
      const vtkIdType c1 = static_cast<vtkIdType>(n * (k + 1) / slices);
      vtkSMPTools::For(c0, c1, 4096, functor);
      this->UpdateProgress(0.9 * (k + 1) / slices);
    }
  }
  output->GetPointData()->AddArray(humidity);
  if (weighted)
  {
    output->GetPointData()->AddArray(weighted);
  }
  if (standing)
  {
    output->GetPointData()->AddArray(standing);
  }
  output->GetFieldData()->AddArray(MonthlyFieldArray("Precipitation", q, "mm"));
  output->GetFieldData()->AddArray(MonthlyFieldArray("PrecipitationIntensity", intensity, "mm/h"));
  return 1;
}

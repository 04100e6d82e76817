#include "vtkTerroirErosion.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTerroirTerrainInput.h"

#include "Erosion.h"
#include "NumberText.h"
#include "Vegetation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

vtkStandardNewMacro(vtkTerroirErosion);

namespace
{
namespace te = terroir::terrain;

/// Temperatures (degC) at which Weiss's evaporation factor T reaches 0 and 1.
constexpr double kColdDegC = 0.0;
constexpr double kHotDegC = 30.0;

/// Volumes summed over the steps, m^3, in the order of the ErosionVolumes field array.
enum Volume
{
  Eroded,
  Deposited,
  Rain,
  Evaporated,
  ToSea,
  VolumeCount
};

vtkSmartPointer<vtkDoubleArray> FieldArray(const char* name, const double* values, int n)
{
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  a->SetNumberOfComponents(n);
  a->InsertNextTuple(values);
  a->GetInformation()->Set(vtkDataArray::UNITS_LABEL(), "m3");
  return a;
}
} // namespace

/// The last state and what it was computed from.
struct vtkTerroirErosion::Cache
{
  bool Valid = false;
  te::ErosionState State;
  bool HasVegetation = false;
  te::VegetationState Vegetation;
  std::vector<float> Factor; ///< evaporation factor per cell (empty: 1)
  int Steps = 0;
  double Volumes[VolumeCount] = { 0, 0, 0, 0, 0 };
  vtkImageData* Input = nullptr;
  vtkMTimeType InputTime = 0;
  vtkMTimeType FilterTime = 0;
};

//------------------------------------------------------------------------------
vtkTerroirErosion::vtkTerroirErosion()
  : State(new Cache)
{
}

//------------------------------------------------------------------------------
vtkTerroirErosion::~vtkTerroirErosion()
{
  delete this->State;
}

//------------------------------------------------------------------------------
void vtkTerroirErosion::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Steps: " << this->Steps << "\n";
  os << indent << "InitialWater: " << this->InitialWater << " m\n";
  os << indent << "RainRate: " << this->RainRate << " mm/h\n";
  os << indent << "TimeStep: " << this->TimeStep << " s\n";
  os << indent << "Capacity: " << this->Capacity << "\n";
  os << indent << "Dissolving: " << this->Dissolving << "\n";
  os << indent << "Deposition: " << this->Deposition << "\n";
  os << indent << "Evaporation: " << this->Evaporation << " 1/s\n";
  os << indent << "CapacityDepth: " << this->CapacityDepth << " m\n";
  os << indent << "TalusAngle: " << this->TalusAngle << " deg\n";
  os << indent << "ThermalInterval: " << this->ThermalInterval << "\n";
  os << indent << "Boundary: " << (this->Boundary == Sea ? "Sea" : "Closed") << "\n";
  os << indent << "SeaLevel: " << this->SeaLevel << " m\n";
  os << indent << "TimeStepStride: " << this->TimeStepStride << "\n";
  os << indent << "Vegetation: " << this->Vegetation << "\n";
  os << indent << "InitialVegetation: " << this->InitialVegetation << "\n";
}

//------------------------------------------------------------------------------
double vtkTerroirErosion::EstimateMemory(double nx, double ny)
{
  // The state: bed, its start, two residues, water, sediment, four fluxes, two velocities and
  // six scratch arrays (float) and the cell kinds (1 B); the evaporation factors (4 B), the
  // rain (4 B) and the four float outputs.
  // With vegetation: its density, store, two scratch arrays and the two factors (float), the
  // chosen parents (1 B) and the bed's copy before soil slip (4 B).
  return nx * ny * (18.0 * 4.0 + 1.0 + 8.0 + 16.0 + (this->Vegetation ? 29.0 : 0.0));
}

//------------------------------------------------------------------------------
void vtkTerroirErosion::MakeParams(te::ErosionParams& p, te::ThermalParams& t) const
{
  p.timeStep = this->TimeStep;
  p.capacity = this->Capacity;
  p.dissolving = this->Dissolving;
  p.dissolvingRock = this->Dissolving;
  p.deposition = this->Deposition;
  p.evaporation = this->Evaporation;
  p.capacityDepth = this->CapacityDepth;
  p.boundary = this->Boundary == Sea ? te::ErosionBoundary::Sea : te::ErosionBoundary::Closed;
  p.seaLevel = this->SeaLevel;
  t.talusSoilDeg = this->TalusAngle;
}

//------------------------------------------------------------------------------
std::string vtkTerroirErosion::CheckParameters()
{
  if (!(this->InitialWater >= 0.0 && std::isfinite(this->InitialWater)))
  {
    return "InitialWater " + terroir::NumberText(this->InitialWater) +
      " m must be a finite number >= 0";
  }
  if (!(this->RainRate >= 0.0 && std::isfinite(this->RainRate)))
  {
    return "RainRate " + terroir::NumberText(this->RainRate) + " mm/h must be a finite number >= 0";
  }
  te::ErosionParams p;
  te::ThermalParams t;
  this->MakeParams(p, t);
  try
  {
    te::CheckErosionParams(p);
    te::CheckThermalParams(t);
  }
  catch (const std::invalid_argument& x)
  {
    return x.what();
  }
  return std::string();
}

//------------------------------------------------------------------------------
int vtkTerroirErosion::RequestInformation(vtkInformation* request,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  if (!this->Superclass::RequestInformation(request, inputVector, outputVector))
  {
    return 0;
  }
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  std::vector<double> steps;
  for (int t = 0; t < this->Steps; t += this->TimeStepStride)
  {
    steps.push_back(static_cast<double>(t));
  }
  steps.push_back(static_cast<double>(this->Steps));
  outInfo->Set(
    vtkStreamingDemandDrivenPipeline::TIME_STEPS(), steps.data(), static_cast<int>(steps.size()));
  const double range[2] = { 0.0, static_cast<double>(this->Steps) };
  outInfo->Set(vtkStreamingDemandDrivenPipeline::TIME_RANGE(), range, 2);
  return 1;
}

//------------------------------------------------------------------------------
int vtkTerroirErosion::RequestTerrainData(vtkImageData* input,
  const terroir::TerrainInput& terrain,
  vtkImageData* output)
{
  const terroir::GridView<float>& v = terrain.view;
  const std::size_t n = v.Size();
  if (this->SelectBackend(this->HasGPUPath()) < 0)
  {
    return 0; // a GPU request: this filter has no GPU path yet
  }
  vtkInformation* outInfo = this->GetOutputInformation(0);
  int steps = this->Steps;
  if (outInfo && outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()))
  {
    const double t = outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP());
    steps = static_cast<int>(std::min<double>(std::max(std::round(t), 0.0), this->Steps));
  }

  te::ErosionParams p;
  te::ThermalParams thermal;
  this->MakeParams(p, thermal);
  const te::ErosionParallelFor rows =
    [](int begin, int end, const std::function<void(int, int)>& body)
  {
    vtkSMPTools::For(begin,
      end,
      8,
      [&](vtkIdType b, vtkIdType e) { body(static_cast<int>(b), static_cast<int>(e)); });
  };

  Cache& c = *this->State;
  try
  {
    if (!c.Valid || c.Input != input || c.InputTime != input->GetMTime() ||
      c.FilterTime != this->GetMTime() || steps < c.Steps)
    {
      // A new start: the terrain's cells with data, InitialWater on each, the temperature's
      // evaporation factors.
      std::vector<std::uint8_t> mask(n);
      for (std::size_t k = 0; k < n; ++k)
      {
        mask[k] = (!v.valid || v.valid[k]) && std::isfinite(v.data[k]) ? 1 : 0;
      }
      terroir::GridView<float> masked = v;
      masked.valid = mask.data();
      c.Valid = false;
      c.State = te::MakeErosionState(masked);
      for (std::size_t k = 0; k < n; ++k)
      {
        c.State.water[k] = mask[k] ? static_cast<float>(this->InitialWater) : 0.0f;
      }
      c.Factor.clear();
      vtkDataArray* temperature = input->GetPointData()->GetArray("Temperature");
      if (temperature && temperature->GetNumberOfTuples() == static_cast<vtkIdType>(n))
      {
        c.Factor.resize(n);
        const int months = temperature->GetNumberOfComponents();
        for (std::size_t k = 0; k < n; ++k)
        {
          double mean = 0.0;
          for (int m = 0; m < months; ++m)
          {
            mean += temperature->GetComponent(static_cast<vtkIdType>(k), m);
          }
          mean /= months;
          const double f = (mean - kColdDegC) / (kHotDegC - kColdDegC);
          c.Factor[k] =
            std::isfinite(f) ? static_cast<float>(std::min(1.0, std::max(0.0, f))) : 0.0f;
        }
      }
      c.HasVegetation = this->Vegetation != 0;
      if (c.HasVegetation)
      {
        std::vector<float> density(n, 0.0f);
        vtkDataArray* given = input->GetPointData()->GetArray(VegetationName());
        for (std::size_t k = 0; k < n; ++k)
        {
          const double d = given && given->GetNumberOfTuples() == static_cast<vtkIdType>(n)
            ? given->GetComponent(static_cast<vtkIdType>(k), 0)
            : this->InitialVegetation;
          density[k] = mask[k] && std::isfinite(d)
            ? static_cast<float>(std::min(1.0, std::max(0.0, d)))
            : 0.0f;
        }
        terroir::GridView<float> dv = masked;
        dv.data = density.data();
        c.Vegetation = te::MakeVegetationState(dv);
        c.State.erosionFactor.assign(n, 1.0f);
        c.State.talusFactor.assign(n, 1.0f);
      }
      c.Steps = 0;
      std::fill(c.Volumes, c.Volumes + VolumeCount, 0.0);
      c.Input = input;
      c.InputTime = input->GetMTime();
      c.FilterTime = this->GetMTime();
      c.Valid = true;
    }
    const std::vector<float> rain(
      this->RainRate > 0.0 ? n : 0, static_cast<float>(this->RainRate / 1000.0 / 3600.0));
    const int first = c.Steps;
    const te::VegetationParams plants;
    std::vector<float> bedBefore;
    while (c.Steps < steps)
    {
      if (c.HasVegetation)
      {
        te::VegetationResistance(
          c.Vegetation, plants, c.State.erosionFactor.data(), c.State.talusFactor.data());
      }
      const te::ErosionStepStats s = te::ErosionHydraulicStep(c.State,
        p,
        rain.empty() ? nullptr : rain.data(),
        c.Factor.empty() ? nullptr : c.Factor.data(),
        rows);
      c.Volumes[Eroded] += s.eroded;
      c.Volumes[Deposited] += s.deposited;
      c.Volumes[Rain] += s.rain;
      c.Volumes[Evaporated] += s.evaporated;
      c.Volumes[ToSea] += s.waterToSea;
      ++c.Steps;
      if (c.HasVegetation)
      {
        te::VegetationWater w;
        w.surface = c.State.water.data();
        w.surfaceResidue = c.State.waterResidue.data();
        te::VegetationStep(c.Vegetation, w, this->TimeStep, plants, rows);
      }
      if (this->ThermalInterval > 0 && c.Steps % this->ThermalInterval == 0)
      {
        if (c.HasVegetation)
        {
          bedBefore = c.State.terrain;
        }
        te::ErosionThermalStep(c.State, thermal, rows);
        if (c.HasVegetation)
        {
          te::VegetationSlipDamage(
            c.Vegetation, bedBefore.data(), c.State.terrain.data(), plants, rows);
        }
      }
      if ((c.Steps - first) % 16 == 0)
      {
        this->UpdateProgress(0.05 + 0.9 * (c.Steps - first) / std::max(1, steps - first));
      }
    }
  }
  catch (const std::invalid_argument& x)
  {
    c.Valid = false;
    vtkErrorMacro(<< this->SourcePrefix(input) << x.what());
    return 0;
  }

  // Outputs: the bed and the water with their rounding residues, NaN on no data.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const te::ErosionState& s = c.State;
  auto make = [&](const char* name)
  {
    return vtkSmartPointer<vtkFloatArray>::Take(
      terroir::NewOutputArray(name, 1, static_cast<long long>(n), "m"));
  };
  vtkSmartPointer<vtkFloatArray> bed = make(ErodedElevationName());
  vtkSmartPointer<vtkFloatArray> change = make(ErosionDepthName());
  vtkSmartPointer<vtkFloatArray> water = make(WaterDepthName());
  vtkSmartPointer<vtkFloatArray> sediment = make(SedimentName());
  for (std::size_t k = 0; k < n; ++k)
  {
    if (!s.IsValid(k))
    {
      bed->SetValue(k, nan);
      change->SetValue(k, nan);
      water->SetValue(k, nan);
      sediment->SetValue(k, nan);
      continue;
    }
    const double b = static_cast<double>(s.terrain[k]) + static_cast<double>(s.terrainResidue[k]);
    bed->SetValue(k, static_cast<float>(b));
    change->SetValue(k, static_cast<float>(b - static_cast<double>(v.data[k])));
    water->SetValue(k,
      static_cast<float>(static_cast<double>(s.water[k]) + static_cast<double>(s.waterResidue[k])));
    sediment->SetValue(k, s.sediment[k]);
  }
  vtkPointData* pd = output->GetPointData();
  if (c.HasVegetation)
  {
    vtkSmartPointer<vtkFloatArray> plants = vtkSmartPointer<vtkFloatArray>::Take(
      terroir::NewOutputArray(VegetationName(), 1, static_cast<long long>(n), ""));
    for (std::size_t k = 0; k < n; ++k)
    {
      plants->SetValue(static_cast<vtkIdType>(k), s.IsValid(k) ? c.Vegetation.density[k] : nan);
    }
    pd->AddArray(plants);
  }
  pd->AddArray(bed);
  pd->AddArray(change);
  pd->AddArray(water);
  pd->AddArray(sediment);
  vtkFieldData* fd = output->GetFieldData();
  auto count = vtkSmartPointer<vtkIntArray>::New();
  count->SetName("ErosionSteps");
  count->InsertNextValue(c.Steps);
  fd->AddArray(count);
  fd->AddArray(FieldArray("ErosionVolumes", c.Volumes, VolumeCount));
  const te::ErosionTotals totals = te::ErosionMeasure(s);
  const double now[3] = { totals.terrain, totals.water, totals.sediment };
  fd->AddArray(FieldArray("ErosionTotals", now, 3));
  return 1;
}

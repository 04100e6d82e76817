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
#include "ErosionSimulation.h"
#include "NumberText.h"
#include "Vegetation.h"
#include "vtkTerroirComputeContext.h"
#include "vtkTerroirErosionGPU.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <vector>

vtkStandardNewMacro(vtkTerroirErosion);

namespace
{
namespace te = terroir::terrain;

/// Temperatures (degC) at which Weiss's evaporation factor T reaches 0 and 1.
constexpr double kColdDegC = 0.0;
constexpr double kHotDegC = 30.0;

vtkSmartPointer<vtkDoubleArray> FieldArray(const char* name, const double* values, int n)
{
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  a->SetNumberOfComponents(n);
  a->InsertNextTuple(values);
  a->GetInformation()->Set(vtkDataArray::UNITS_LABEL(), "m3");
  return a;
}
/**
 * A new start: the terrain's cells with data, InitialWater on each, the temperature's
 * evaporation factors, and with vegetation (initialVegetation >= 0) the input's
 * VegetationDensity or initialVegetation on every cell.
 */
std::unique_ptr<te::ErosionSimulation> StartSimulation(vtkImageData* input,
  const terroir::GridView<float>& v,
  double initialWater,
  double initialVegetation,
  bool weather)
{
  const std::size_t n = v.Size();
  std::vector<std::uint8_t> mask(n);
  for (std::size_t k = 0; k < n; ++k)
  {
    mask[k] = (!v.valid || v.valid[k]) && std::isfinite(v.data[k]) ? 1 : 0;
  }
  terroir::GridView<float> masked = v;
  masked.valid = mask.data();
  std::vector<float> factor, meanC;
  vtkDataArray* temperature = input->GetPointData()->GetArray("Temperature");
  if (temperature && temperature->GetNumberOfTuples() == static_cast<vtkIdType>(n))
  {
    factor.resize(n);
    meanC.resize(weather ? n : 0);
    const int months = temperature->GetNumberOfComponents();
    for (std::size_t k = 0; k < n; ++k)
    {
      double mean = 0.0;
      for (int m = 0; m < months; ++m)
      {
        mean += temperature->GetComponent(static_cast<vtkIdType>(k), m);
      }
      mean /= months;
      if (weather)
      {
        meanC[k] = std::isfinite(mean) ? static_cast<float>(mean) : 15.0f;
      }
      const double f = (mean - kColdDegC) / (kHotDegC - kColdDegC);
      factor[k] = std::isfinite(f) ? static_cast<float>(std::min(1.0, std::max(0.0, f))) : 0.0f;
    }
  }
  std::vector<float> density;
  if (initialVegetation >= 0.0)
  {
    density.assign(n, static_cast<float>(initialVegetation));
    vtkDataArray* given = input->GetPointData()->GetArray(vtkTerroirErosion::VegetationName());
    if (given && given->GetNumberOfTuples() == static_cast<vtkIdType>(n))
    {
      for (std::size_t k = 0; k < n; ++k)
      {
        density[k] = static_cast<float>(given->GetComponent(static_cast<vtkIdType>(k), 0));
      }
    }
  }
  // A soil layer: the input's SoilThickness (m over rock; no data and NaN: none).
  std::vector<float> soil;
  vtkDataArray* layer = input->GetPointData()->GetArray(vtkTerroirErosion::SoilThicknessName());
  if (layer && layer->GetNumberOfTuples() == static_cast<vtkIdType>(n))
  {
    soil.resize(n);
    for (std::size_t k = 0; k < n; ++k)
    {
      const double d = layer->GetComponent(static_cast<vtkIdType>(k), 0);
      soil[k] = mask[k] && std::isfinite(d) ? static_cast<float>(d) : 0.0f;
    }
  }
  auto sim = std::unique_ptr<te::ErosionSimulation>(new te::ErosionSimulation(masked,
    initialWater,
    std::move(factor),
    density.empty() ? nullptr : density.data(),
    soil.empty() ? nullptr : soil.data()));
  sim->SetTemperature(std::move(meanC));
  // A rain map: the input's RainRate point array (mm/h), added to the RainRate property.
  vtkDataArray* rain = input->GetPointData()->GetArray(vtkTerroirErosion::RainRateName());
  if (rain && rain->GetNumberOfTuples() == static_cast<vtkIdType>(n))
  {
    std::vector<float> rates(n, 0.0f);
    for (std::size_t k = 0; k < n; ++k)
    {
      rates[k] = mask[k]
        ? static_cast<float>(rain->GetComponent(static_cast<vtkIdType>(k), 0) / 1000.0 / 3600.0)
        : 0.0f;
    }
    sim->SetRainRates(std::move(rates));
  }
  return sim;
}
/**
 * Runs sim's steps up to `steps` on the GPU (RunErosionGPU) and counts them in `sim`: first the
 * steps up to the next thermal step when the cache stopped between two, so that the soil slip
 * falls on the same step numbers as on the CPU, then the rest. The state is read back at the end.
 */
void RunStepsGPU(te::ErosionSimulation& sim, const te::ErosionSimulationParams& sp, long long steps)
{
  const int interval = sp.thermalInterval;
  const float* rain = sim.RainField(sp.rainRate);
  auto run = [&](int count, int thermalEvery)
  {
    te::ErosionGPUTotals totals;
    te::RunErosionGPU(sim.State(),
      sp.hydraulic,
      sp.thermal,
      thermalEvery,
      rain,
      sim.EvaporationFactor(),
      count,
      &totals);
    sim.AddSteps(count, totals.hydraulic);
  };
  long long left = steps - sim.Steps();
  if (interval > 0 && sim.Steps() % interval != 0 && left > 0)
  {
    const long long toThermal = interval - sim.Steps() % interval;
    const int count = static_cast<int>(std::min(left, toThermal));
    run(count, count == toThermal ? count : 0);
    left -= count;
  }
  while (left > 0)
  {
    const int count = static_cast<int>(std::min<long long>(left, 1 << 30));
    run(count, interval);
    left -= count;
  }
}
} // namespace

/// The last state and what it was computed from.
struct vtkTerroirErosion::Cache
{
  std::unique_ptr<te::ErosionSimulation> Simulation; ///< null: none valid
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
  os << indent << "SoftOutflow: " << this->SoftOutflow << " (" << this->SoftOutflowMinimum
     << " m3/s + " << this->SoftOutflowScale << " m2/s x |dh|)\n";
  os << indent << "RockDissolving: " << this->RockDissolving << "\n";
  os << indent << "RockTalusAngle: " << this->RockTalusAngle << " deg\n";
  os << indent << "ThermalInterval: " << this->ThermalInterval << "\n";
  os << indent << "Boundary: " << (this->Boundary == Sea ? "Sea" : "Closed") << "\n";
  os << indent << "SeaLevel: " << this->SeaLevel << " m\n";
  os << indent << "TimeStepStride: " << this->TimeStepStride << "\n";
  os << indent << "Vegetation: " << this->Vegetation << "\n";
  os << indent << "InitialVegetation: " << this->InitialVegetation << "\n";
  os << indent << "Weather: " << this->Weather << "\n";
  os << indent << "WindDirection: " << this->WindDirection << " deg\n";
  os << indent << "WindStrength: " << this->WindStrength << " m/s\n";
  os << indent << "EvaporationScale: " << this->EvaporationScale << "\n";
}

//------------------------------------------------------------------------------
double vtkTerroirErosion::EstimateMemory(double nx, double ny)
{
  // The state: bed, its start, two residues, water, sediment, four fluxes, two velocities and
  // six scratch arrays (float) and the cell kinds (1 B); the evaporation factors (4 B), the
  // rain (4 B) and the four float outputs.
  // With vegetation: its density, store, two scratch arrays and the two factors (float), the
  // chosen parents (1 B) and the bed's copy before soil slip (4 B).
  // With weather: the atmosphere's 15 float arrays (air, residue, vapour, fluxes, velocities,
  // scratch), the fields x_s, x and wind, the falling rain, the rain rates, a bare canopy (4
  // floats) and the Vapour output.
  return nx * ny *
    (18.0 * 4.0 + 1.0 + 8.0 + 16.0 + (this->Vegetation ? 29.0 : 0.0) +
      (this->Weather ? 25.0 * 4.0 : 0.0));
}

//------------------------------------------------------------------------------
void vtkTerroirErosion::MakeParams(te::ErosionSimulationParams& sp) const
{
  te::ErosionParams& p = sp.hydraulic;
  p.timeStep = this->TimeStep;
  p.capacity = this->Capacity;
  p.dissolving = this->Dissolving;
  p.dissolvingRock = this->RockDissolving;
  p.softOutflow = this->SoftOutflow != 0;
  p.softOutflowMin = this->SoftOutflowMinimum;
  p.softOutflowScale = this->SoftOutflowScale;
  p.deposition = this->Deposition;
  p.evaporation = this->Evaporation;
  p.capacityDepth = this->CapacityDepth;
  p.boundary = this->Boundary == Sea ? te::ErosionBoundary::Sea : te::ErosionBoundary::Closed;
  p.seaLevel = this->SeaLevel;
  sp.thermal.talusSoilDeg = this->TalusAngle;
  sp.thermal.talusRockDeg = this->RockTalusAngle;
  sp.thermalInterval = this->ThermalInterval;
  sp.rainRate = this->RainRate / 1000.0 / 3600.0;
  sp.weather = this->Weather != 0;
  sp.atmosphere.timeStep = this->TimeStep;
  sp.atmosphere.windDirectionDeg = this->WindDirection;
  sp.atmosphere.windStrength = this->WindStrength;
  sp.evaporation.scale = this->EvaporationScale;
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
  te::ErosionSimulationParams sp;
  this->MakeParams(sp);
  try
  {
    te::CheckErosionParams(sp.hydraulic);
    te::CheckThermalParams(sp.thermal);
    if (sp.weather)
    {
      te::CheckAtmosphereParams(sp.atmosphere);
      te::CheckEvaporationParams(sp.evaporation);
    }
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
  if (this->Backend == vtkTerroirComputeContext::GPU && !this->HasGPUPath())
  {
    vtkErrorMacro(<< "the GPU path runs the erosion and soil slip only: turn Vegetation and "
                     "Weather off, or use the CPU backend");
    return 0;
  }
  const int backend = this->SelectBackend(this->HasGPUPath());
  if (backend < 0)
  {
    return 0;
  }
  vtkInformation* outInfo = this->GetOutputInformation(0);
  int steps = this->Steps;
  if (outInfo && outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()))
  {
    const double t = outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP());
    steps = static_cast<int>(std::min<double>(std::max(std::round(t), 0.0), this->Steps));
  }

  te::ErosionSimulationParams sp;
  this->MakeParams(sp);
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
    if (!c.Simulation || c.Input != input || c.InputTime != input->GetMTime() ||
      c.FilterTime != this->GetMTime() || steps < c.Simulation->Steps())
    {
      c.Simulation.reset();
      c.Simulation = StartSimulation(input,
        v,
        this->InitialWater,
        this->Vegetation != 0 ? this->InitialVegetation : -1.0,
        this->Weather != 0);
      c.Input = input;
      c.InputTime = input->GetMTime();
      c.FilterTime = this->GetMTime();
    }
    te::ErosionSimulation& sim = *c.Simulation;
    const long long first = sim.Steps();
    if (backend == vtkTerroirComputeContext::GPU && sim.Steps() < steps)
    {
      const int ran = this->RunGPUPath([&] { RunStepsGPU(sim, sp, steps); });
      if (ran < 0)
      {
        return 0; // an explicit GPU request failed (reported)
      }
      // ran == CPU: Auto fell back (reported); the CPU goes on from where the state stands.
    }
    while (sim.Steps() < steps)
    {
      sim.Step(sp, rows);
      if ((sim.Steps() - first) % 16 == 0)
      {
        this->UpdateProgress(0.05 +
          0.9 * static_cast<double>(sim.Steps() - first) /
            static_cast<double>(std::max<long long>(1, steps - first)));
      }
    }
  }
  catch (const std::invalid_argument& x)
  {
    c.Simulation.reset();
    vtkErrorMacro(<< this->SourcePrefix(input) << x.what());
    return 0;
  }
  if (!c.Simulation)
  {
    return 0;
  }

  // Outputs: the bed and the water with their rounding residues, NaN on no data.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const te::ErosionSimulation& sim = *c.Simulation;
  const te::ErosionState& s = sim.State();
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
  if (sim.HasVegetation())
  {
    vtkSmartPointer<vtkFloatArray> plants = vtkSmartPointer<vtkFloatArray>::Take(
      terroir::NewOutputArray(VegetationName(), 1, static_cast<long long>(n), ""));
    for (std::size_t k = 0; k < n; ++k)
    {
      plants->SetValue(static_cast<vtkIdType>(k), s.IsValid(k) ? sim.Vegetation().density[k] : nan);
    }
    pd->AddArray(plants);
  }
  if (sim.HasWeather())
  {
    vtkSmartPointer<vtkFloatArray> vapour = vtkSmartPointer<vtkFloatArray>::Take(
      terroir::NewOutputArray(VapourName(), 1, static_cast<long long>(n), "m"));
    for (std::size_t k = 0; k < n; ++k)
    {
      vapour->SetValue(static_cast<vtkIdType>(k), s.IsValid(k) ? sim.Atmosphere().vapour[k] : nan);
    }
    pd->AddArray(vapour);
    const te::ErosionVolumes& w = sim.Volumes();
    const double weather[] = { w.evaporated, w.canopyEvaporated, w.weatherRain };
    output->GetFieldData()->AddArray(FieldArray("WeatherVolumes", weather, 3));
  }
  if (!s.soil.empty())
  {
    vtkSmartPointer<vtkFloatArray> soil = vtkSmartPointer<vtkFloatArray>::Take(
      terroir::NewOutputArray(SoilThicknessName(), 1, static_cast<long long>(n), "m"));
    for (std::size_t k = 0; k < n; ++k)
    {
      soil->SetValue(static_cast<vtkIdType>(k), s.IsValid(k) ? s.soil[k] : nan);
    }
    pd->AddArray(soil);
  }
  pd->AddArray(bed);
  pd->AddArray(change);
  pd->AddArray(water);
  pd->AddArray(sediment);
  vtkFieldData* fd = output->GetFieldData();
  auto count = vtkSmartPointer<vtkIntArray>::New();
  count->SetName("ErosionSteps");
  count->InsertNextValue(static_cast<int>(sim.Steps()));
  fd->AddArray(count);
  const te::ErosionVolumes& sums = sim.Volumes();
  const double volumes[] = { sums.eroded, sums.deposited, sums.rain, sums.evaporated, sums.toSea };
  fd->AddArray(FieldArray("ErosionVolumes", volumes, 5));
  const te::ErosionTotals totals = te::ErosionMeasure(s);
  const double now[3] = { totals.terrain, totals.water, totals.sediment };
  fd->AddArray(FieldArray("ErosionTotals", now, 3));
  return 1;
}

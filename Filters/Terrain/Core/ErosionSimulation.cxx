#include "ErosionSimulation.h"

#include "ParameterCheck.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace terroir
{
namespace terrain
{

namespace
{
constexpr double kPi = 3.14159265358979323846;
constexpr const char* kModel = "erosion simulation";

/// value + residue += delta, kept exactly as a float and its rounding residue.
void AddCompensated(float& value, float& residue, double delta)
{
  const double sum = static_cast<double>(value) + static_cast<double>(residue) + delta;
  value = static_cast<float>(sum);
  residue = static_cast<float>(sum - static_cast<double>(value));
}
} // namespace

//------------------------------------------------------------------------------
ErosionSimulation::ErosionSimulation(const GridView<float>& terrain,
  double initialWater,
  std::vector<float> evaporationFactor,
  const float* vegetation,
  const float* soil)
  : Erosion(MakeErosionState(terrain, soil))
  , Factor(std::move(evaporationFactor))
{
  if (!(initialWater >= 0.0 && std::isfinite(initialWater)))
  {
    detail::BadParameter(kModel, "initialWater", initialWater, "a finite number >= 0 (m)");
  }
  const std::size_t n = this->Erosion.Size();
  if (!this->Factor.empty() && this->Factor.size() != n)
  {
    throw std::invalid_argument("evaporation factors: " + std::to_string(this->Factor.size()) +
      " values for " + std::to_string(n) + " cells");
  }
  for (std::size_t k = 0; k < n; ++k)
  {
    this->Erosion.water[k] = this->Erosion.IsValid(k) ? static_cast<float>(initialWater) : 0.0f;
  }
  if (vegetation)
  {
    this->StartVegetation(vegetation);
  }
}

//------------------------------------------------------------------------------
void ErosionSimulation::StartVegetation(const float* density)
{
  const ErosionState& s = this->Erosion;
  const std::size_t n = s.Size();
  std::vector<float> v(n, 0.0f);
  for (std::size_t k = 0; k < n; ++k)
  {
    const float d = density ? density[k] : 0.0f;
    v[k] = s.IsValid(k) && std::isfinite(d) ? std::min(1.0f, std::max(0.0f, d)) : 0.0f;
  }
  this->PlantState = MakeVegetationState(this->View(v.data()));
  this->Erosion.erosionFactor.assign(n, 1.0f);
  this->Erosion.talusFactor.assign(n, 1.0f);
  this->Plants = true;
}

//------------------------------------------------------------------------------
void ErosionSimulation::Step(const ErosionSimulationParams& p, const ErosionParallelFor& rows)
{
  if (!(p.rainRate >= 0.0 && std::isfinite(p.rainRate)))
  {
    detail::BadParameter(kModel, "rainRate", p.rainRate, "a finite number >= 0 (m/s)");
  }
  if (p.thermalInterval < 0)
  {
    detail::BadParameter(kModel, "thermalInterval", p.thermalInterval, ">= 0");
  }
  ErosionState& s = this->Erosion;
  const float* rain = this->RainField(p.rainRate);
  ErosionParams hydraulic = p.hydraulic;
  if (p.weather)
  {
    // Dunn's evaporation replaces Weiss's K_e; the atmosphere's rain of the last step falls now.
    hydraulic.evaporation = 0.0;
    this->StartWeather(p);
    const std::size_t n = s.Size();
    this->RainRates.resize(n);
    for (std::size_t k = 0; k < n; ++k)
    {
      this->RainRates[k] = static_cast<float>(
        (rain ? rain[k] : 0.0f) + static_cast<double>(this->Falling[k]) / p.hydraulic.timeStep);
    }
    rain = this->RainRates.data();
  }
  if (this->Plants)
  {
    VegetationResistance(
      this->PlantState, p.vegetation, s.erosionFactor.data(), s.talusFactor.data());
  }
  const ErosionStepStats stats = ErosionHydraulicStep(
    s, hydraulic, rain, this->Factor.empty() ? nullptr : this->Factor.data(), rows);
  this->Sums.eroded += stats.eroded;
  this->Sums.deposited += stats.deposited;
  this->Sums.rain += stats.rain;
  this->Sums.evaporated += stats.evaporated;
  this->Sums.toSea += stats.waterToSea;
  ++this->StepCount;
  if (this->Plants)
  {
    VegetationWater w;
    w.surface = s.water.data();
    w.surfaceResidue = s.waterResidue.data();
    VegetationStep(this->PlantState, w, p.hydraulic.timeStep, p.vegetation, rows);
  }
  if (p.thermalInterval > 0 && this->StepCount % p.thermalInterval == 0)
  {
    if (this->Plants)
    {
      this->BedBefore = s.terrain;
    }
    ErosionThermalStep(s, p.thermal, rows);
    if (this->Plants)
    {
      VegetationSlipDamage(
        this->PlantState, this->BedBefore.data(), s.terrain.data(), p.vegetation, rows);
    }
  }
  if (p.weather)
  {
    this->WeatherStep(p, rows);
  }
}

//------------------------------------------------------------------------------
void ErosionSimulation::StartWeather(const ErosionSimulationParams& p)
{
  if (this->Weather)
  {
    return;
  }
  const ErosionState& s = this->Erosion;
  GridView<float> view = this->View(s.terrain.data());
  this->Air = MakeAtmosphereState(view, p.airHeight);
  const std::vector<float> none(s.Size(), 0.0f);
  view.data = none.data();
  this->Bare = MakeVegetationState(view);
  this->Falling.assign(s.Size(), 0.0f);
  this->Weather = true;
}

//------------------------------------------------------------------------------
void ErosionSimulation::WeatherStep(const ErosionSimulationParams& p,
  const ErosionParallelFor& rows)
{
  ErosionState& s = this->Erosion;
  const std::size_t n = s.Size();
  AtmosphereParams air = p.atmosphere;
  air.timeStep = p.hydraulic.timeStep;
  const float* temperature = this->Temperature.empty() ? nullptr : this->Temperature.data();
  this->Xs.resize(n);
  this->X.resize(n);
  this->Wind.resize(n);
  AtmosphereEvaporationFields(this->Air,
    air,
    s.terrain.data(),
    temperature,
    this->Xs.data(),
    this->X.data(),
    this->Wind.data(),
    rows);
  EvaporationFields fields;
  fields.saturationRatio = this->Xs.data();
  fields.humidityRatio = this->X.data();
  fields.windSpeed = this->Wind.data();
  fields.vapour = this->Air.vapour.data();
  VegetationWater water;
  water.surface = s.water.data();
  water.surfaceResidue = s.waterResidue.data();
  const EvaporationStats e = EvaporationDunn2015Step(this->Plants ? this->PlantState : this->Bare,
    water,
    p.hydraulic.timeStep,
    p.vegetation,
    p.evaporation,
    fields,
    rows);
  this->Sums.evaporated += e.fromWater;
  this->Sums.canopyEvaporated += e.fromCanopy;
  std::fill(this->Falling.begin(), this->Falling.end(), 0.0f);
  this->Sums.weatherRain +=
    AtmosphereStep(this->Air, air, s.terrain.data(), temperature, this->Falling.data(), rows).rain;
}

//------------------------------------------------------------------------------
GridView<float> ErosionSimulation::View(const float* data) const
{
  const ErosionState& s = this->Erosion;
  GridView<float> view;
  view.nx = s.nx;
  view.ny = s.ny;
  view.dx = s.rowDx[0];
  view.dy = s.rowDy[0];
  view.rowDx = s.rowDx.data();
  view.rowDy = s.rowDy.data();
  view.data = data;
  view.valid = s.valid.empty() ? nullptr : s.valid.data();
  return view;
}

//------------------------------------------------------------------------------
void ErosionSimulation::SetTemperature(std::vector<float> temperature)
{
  if (!temperature.empty() && temperature.size() != this->Erosion.Size())
  {
    detail::BadParameter(kModel,
      "temperature values",
      static_cast<double>(temperature.size()),
      "one per cell (or none)");
  }
  this->Temperature = std::move(temperature);
}

//------------------------------------------------------------------------------
void ErosionSimulation::SetRainRates(std::vector<float> rates)
{
  const std::size_t n = this->Erosion.Size();
  if (!rates.empty() && rates.size() != n)
  {
    detail::BadParameter(
      kModel, "rain rates", static_cast<double>(rates.size()), "one per cell (or none)");
  }
  for (std::size_t k = 0; k < rates.size(); ++k)
  {
    if (!(rates[k] >= 0.0f && std::isfinite(rates[k])))
    {
      detail::BadParameter(kModel, "rain rate (m/s) of a cell", rates[k], "a finite number >= 0");
    }
  }
  this->RainMap = std::move(rates);
  this->RainRate = -1.0; // the next RainField builds the field again
}

//------------------------------------------------------------------------------
const float* ErosionSimulation::RainField(double rate)
{
  if (rate != this->RainRate)
  {
    const std::size_t n = this->Erosion.Size();
    if (this->RainMap.empty())
    {
      this->Rain.assign(rate > 0.0 ? n : 0, static_cast<float>(rate));
    }
    else
    {
      this->Rain.resize(n);
      for (std::size_t k = 0; k < n; ++k)
      {
        this->Rain[k] = static_cast<float>(static_cast<double>(this->RainMap[k]) + rate);
      }
    }
    this->RainRate = rate;
  }
  return this->Rain.empty() ? nullptr : this->Rain.data();
}

//------------------------------------------------------------------------------
void ErosionSimulation::AddSteps(long long steps, const ErosionStepStats& sums)
{
  if (this->Plants || this->Weather)
  {
    throw std::logic_error("erosion simulation: steps run outside cannot couple vegetation or "
                           "weather");
  }
  this->Sums.eroded += sums.eroded;
  this->Sums.deposited += sums.deposited;
  this->Sums.rain += sums.rain;
  this->Sums.evaporated += sums.evaporated;
  this->Sums.toSea += sums.waterToSea;
  this->StepCount += steps;
}

//------------------------------------------------------------------------------
long long ErosionSimulation::Paint(ErosionBrush brush,
  double ci,
  double cj,
  double radius,
  double amount)
{
  if (!std::isfinite(ci))
  {
    detail::BadParameter(kModel, "brush i", ci, "finite");
  }
  if (!std::isfinite(cj))
  {
    detail::BadParameter(kModel, "brush j", cj, "finite");
  }
  if (!(radius > 0.0 && std::isfinite(radius)))
  {
    detail::BadParameter(kModel, "brush radius", radius, "a finite number > 0 (cells)");
  }
  if (!std::isfinite(amount))
  {
    detail::BadParameter(kModel, "brush amount", amount, "finite");
  }
  if (brush == ErosionBrush::Vegetation && !this->Plants)
  {
    this->StartVegetation(nullptr);
  }
  ErosionState& s = this->Erosion;
  const int i0 = std::max(0, static_cast<int>(std::ceil(ci - radius)));
  const int i1 = std::min(s.nx - 1, static_cast<int>(std::floor(ci + radius)));
  const int j0 = std::max(0, static_cast<int>(std::ceil(cj - radius)));
  const int j1 = std::min(s.ny - 1, static_cast<int>(std::floor(cj + radius)));
  long long reached = 0;
  for (int j = j0; j <= j1; ++j)
  {
    const double area = s.CellArea(j);
    for (int i = i0; i <= i1; ++i)
    {
      const std::size_t k =
        static_cast<std::size_t>(j) * static_cast<std::size_t>(s.nx) + static_cast<std::size_t>(i);
      const double r = std::hypot(i - ci, j - cj);
      if (r >= radius || !s.IsValid(k))
      {
        continue;
      }
      ++reached;
      const double w = 0.5 * (1.0 + std::cos(kPi * r / radius));
      switch (brush)
      {
        case ErosionBrush::Soil:
        {
          const double delta = amount * w;
          AddCompensated(s.terrain[k], s.terrainResidue[k], delta);
          if (!s.soil.empty())
          {
            s.soil[k] = std::max(0.0f, static_cast<float>(s.soil[k] + delta));
          }
          this->Sums.brushBed += delta * area;
          break;
        }
        case ErosionBrush::Water:
        {
          const double before = static_cast<double>(s.water[k]) + s.waterResidue[k];
          const double delta = std::max(amount * w, -before);
          AddCompensated(s.water[k], s.waterResidue[k], delta); // delta >= -before: >= 0
          this->Sums.brushWater += delta * area;
          break;
        }
        case ErosionBrush::Vegetation:
        {
          float& v = this->PlantState.density[k];
          const double target = std::min(1.0, std::max(0.0, amount));
          v = static_cast<float>(std::min(1.0, std::max(0.0, v + (target - v) * w)));
          break;
        }
      }
    }
  }
  return reached;
}

} // namespace terrain
} // namespace terroir

#include "vtkTerroirFlowAccumulation.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSignedCharArray.h"
#include "vtkSmartPointer.h"
#include "vtkTerroirTerrainInput.h"
#include "vtkUnsignedCharArray.h"

#include "vtkTerroirFiltersHydrologyModule.h" // For VTK_MODULE_ENABLE_VTK_ParallelCore
#if VTK_MODULE_ENABLE_VTK_ParallelCore
#include "vtkMultiProcessController.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTerroirControllerTileExchange.h"
#endif

#include "DistributedFlowAccumulation.h"
#include "FlowAccumulation.h"
#include "MultipleFlow.h"
#include "PriorityFlood.h"

#include "NumberText.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <new>
#include <sstream>
#include <vector>

vtkStandardNewMacro(vtkTerroirFlowAccumulation);

namespace
{
/// A new array of `n` tuples named `name` with UNITS_LABEL `units` (none when null).
template<typename ArrayT>
vtkSmartPointer<ArrayT> NewArray(const char* name, std::size_t n, const char* units)
{
  auto a = vtkSmartPointer<ArrayT>::New();
  a->SetName(name);
  if (!a->Allocate(static_cast<vtkIdType>(n)))
  {
    throw std::bad_alloc();
  }
  a->SetNumberOfTuples(static_cast<vtkIdType>(n));
  if (units)
  {
    a->GetInformation()->Set(vtkDataArray::UNITS_LABEL(), units);
  }
  return a;
}
} // namespace

//------------------------------------------------------------------------------
vtkTerroirFlowAccumulation::vtkTerroirFlowAccumulation() = default;

//------------------------------------------------------------------------------
vtkTerroirFlowAccumulation::~vtkTerroirFlowAccumulation()
{
  this->SetWeightArrayName(nullptr);
}

//------------------------------------------------------------------------------
void vtkTerroirFlowAccumulation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "RiverThreshold: " << this->RiverThreshold << " m2\n";
  os << indent << "WeightArrayName: " << (this->WeightArrayName ? this->WeightArrayName : "(none)")
     << "\n";
  os << indent << "WeightComponent: " << this->WeightComponent << "\n";
  os << indent << "Method: " << MethodName(this->Method) << "\n";
  os << indent << "MFDExponent: " << this->MFDExponent << "\n";
  os << indent << "MFDContourLength: " << this->MFDContourLength << "\n";
  os << indent << "MFDAdaptiveExponent: " << this->MFDAdaptiveExponent << "\n";
  os << indent << "SlopeExponent: " << this->SlopeExponent << "\n";
  os << indent << "MinimumSlope: " << this->MinimumSlope << "\n";
}

//------------------------------------------------------------------------------
const char* vtkTerroirFlowAccumulation::MethodName(int method)
{
  switch (method)
  {
    case D8:
      return "D8";
    case MFD:
      return "MFD";
    case DInfinity:
      return "DInfinity";
    default:
      return "unknown";
  }
}

//------------------------------------------------------------------------------
double vtkTerroirFlowAccumulation::EstimateMemory(double nx, double ny)
{
  // Outputs: FilledElevation 4 B, FlowDirection 1 B, FlowAccumulation 8 B, ContributingArea
  // 8 B, River 1 B per cell; with a weight, WeightedAccumulation 8 B and the weights as float
  // (4 B). Working memory at its peak, during Priority-Flood (which writes FilledElevation in
  // place): visited flags 1 B, the priority queue 8 B per queued cell (up to twice that while
  // growing) and the pit FIFO 4 B. The flats' breadth-first search (4 B distances + 4 B queue)
  // and the accumulation's in-degrees (1 B) need less.
  const bool weighted = this->WeightArrayName && *this->WeightArrayName;
  const double perCell = 4.0 + 1.0 + 8.0 + 8.0 + 1.0 + 8.0 +
    (this->Method == DInfinity ? 4.0 : 0.0) + (weighted ? 12.0 : 0.0) + 1.0 + 16.0 + 4.0;
  return nx * ny * perCell;
}

//------------------------------------------------------------------------------
std::string vtkTerroirFlowAccumulation::CheckParameters()
{
  if (!(this->RiverThreshold >= 0.0) || !std::isfinite(this->RiverThreshold))
  {
    return "RiverThreshold " + terroir::NumberText(this->RiverThreshold) +
      " m2 must be a finite number >= 0";
  }
  if (!(this->MFDExponent > 0.0) || !std::isfinite(this->MFDExponent))
  {
    return "MFDExponent " + terroir::NumberText(this->MFDExponent) + " must be a finite number > 0";
  }
  if (!(this->SlopeExponent >= 0.0) || !std::isfinite(this->SlopeExponent))
  {
    return "SlopeExponent " + terroir::NumberText(this->SlopeExponent) +
      " must be a finite number >= 0";
  }
  if (!(this->MinimumSlope >= 0.0) || !std::isfinite(this->MinimumSlope))
  {
    return "MinimumSlope " + terroir::NumberText(this->MinimumSlope) +
      " must be a finite number >= 0";
  }
  return std::string();
}

//------------------------------------------------------------------------------
int vtkTerroirFlowAccumulation::RequestTerrainData(vtkImageData* input,
  const terroir::TerrainInput& terrain,
  vtkImageData* output)
{
  namespace hy = terroir::hydrology;
  const terroir::GridView<float>& v = terrain.view;
  const std::size_t n = v.Size();
  if (this->SelectBackend(this->HasGPUPath()) < 0)
  {
    return 0; // a GPU request: this filter has no GPU path
  }

  // The weight array, checked before anything is allocated.
  vtkDataArray* weightArray = nullptr;
  const bool weighted = this->WeightArrayName && *this->WeightArrayName;
  if (weighted)
  {
    vtkAbstractArray* a = input->GetPointData()->GetAbstractArray(this->WeightArrayName);
    if (!a)
    {
      vtkErrorMacro(<< this->SourcePrefix(input) << "WeightArrayName '" << this->WeightArrayName
                    << "' names no point array of the input");
      return 0;
    }
    weightArray = vtkDataArray::SafeDownCast(a);
    if (!weightArray)
    {
      vtkErrorMacro(<< this->SourcePrefix(input) << "weight array '" << this->WeightArrayName
                    << "' is not numeric (" << a->GetClassName() << ")");
      return 0;
    }
    if (this->WeightComponent >= weightArray->GetNumberOfComponents())
    {
      vtkErrorMacro(<< this->SourcePrefix(input) << "WeightComponent " << this->WeightComponent
                    << " is out of range: weight array '" << this->WeightArrayName << "' has "
                    << weightArray->GetNumberOfComponents() << " component(s)");
      return 0;
    }
    if (weightArray->GetNumberOfTuples() != static_cast<vtkIdType>(n))
    {
      vtkErrorMacro(<< this->SourcePrefix(input) << "weight array '" << this->WeightArrayName
                    << "' has " << weightArray->GetNumberOfTuples() << " tuples, the terrain " << n
                    << " cells");
      return 0;
    }
  }

  std::vector<float> weight;
  if (weighted)
  {
    weight.resize(n);
    for (std::size_t k = 0; k < n; ++k)
    {
      weight[k] = static_cast<float>(
        weightArray->GetComponent(static_cast<vtkIdType>(k), this->WeightComponent));
    }
  }
  auto filled = NewArray<vtkFloatArray>(FilledElevationName(), n, "m");
  auto direction = NewArray<vtkSignedCharArray>(FlowDirectionName(), n, nullptr);
  auto cells = NewArray<vtkDoubleArray>(FlowAccumulationName(), n, "cells");
  auto area = NewArray<vtkDoubleArray>(ContributingAreaName(), n, "m2");
  auto volume = weighted ? NewArray<vtkDoubleArray>(WeightedAccumulationName(), n, "m3")
                         : vtkSmartPointer<vtkDoubleArray>();
  auto angle = this->Method == DInfinity ? NewArray<vtkFloatArray>(FlowAngleName(), n, "rad")
                                         : vtkSmartPointer<vtkFloatArray>();
  if (this->DistributedRequest)
  {
    if (!this->AccumulateInPieces(input,
          v,
          weighted ? weight.data() : nullptr,
          filled,
          direction,
          cells,
          area,
          volume,
          angle))
    {
      return 0;
    }
  }
  else
  {
    // 1. Depression filling, straight into the output array.
    vtkDebugMacro(<< "Priority-Flood: " << hy::kPriorityFloodBarnes2014Citation);
    hy::PriorityFloodBarnes2014(
      v, filled->GetPointer(0), [this](double f) { this->UpdateProgress(0.05 + 0.45 * f); });

    // 2. D8 directions, flats routed breadth-first.
    vtkDebugMacro(<< "D8: " << hy::kD8OCallaghanMark1984Citation
                  << "; flats: " << hy::kFlatsBarnes2014Citation);
    const hy::D8Summary summary = hy::D8FlowDirections(v,
      filled->GetPointer(0),
      direction->GetPointer(0),
      [this](double f) { this->UpdateProgress(0.5 + 0.2 * f); });
    vtkDebugMacro(<< summary.outlets << " outlets, " << summary.flatCells << " flat cells, "
                  << summary.sinks << " sinks");
    const std::int8_t* dir = direction->GetPointer(0);

    // 3. Accumulations by the chosen method: cells, area, and the weighted volume.
    hy::MFDOptions mfd;
    mfd.exponent = this->MFDExponent;
    mfd.contourLength = this->MFDContourLength != 0;
    mfd.adaptive = this->MFDAdaptiveExponent != 0;
    auto accumulate = [&](const float* w, double* out, const hy::AccumulationOptions& o)
    {
      switch (this->Method)
      {
        case MFD:
          hy::MultipleFlowAccumulation(v, filled->GetPointer(0), dir, mfd, w, out, o);
          break;
        case DInfinity:
          hy::DInfinityAccumulation(v,
            filled->GetPointer(0),
            dir,
            w,
            out,
            angle && w == nullptr && !o.timesCellArea ? angle->GetPointer(0) : nullptr,
            o);
          break;
        default:
          hy::D8FlowAccumulation(v, dir, w, out, o);
      }
    };
    vtkDebugMacro(<< "accumulation: " << MethodName(this->Method));
    hy::AccumulationOptions options;
    options.progress = [this](double f) { this->UpdateProgress(0.7 + 0.08 * f); };
    accumulate(nullptr, cells->GetPointer(0), options);
    options.timesCellArea = true;
    options.progress = [this](double f) { this->UpdateProgress(0.78 + 0.08 * f); };
    accumulate(nullptr, area->GetPointer(0), options);
    if (weighted)
    {
      options.scale = 1e-3; // mm -> m
      options.progress = [this](double f) { this->UpdateProgress(0.86 + 0.08 * f); };
      accumulate(weight.data(), volume->GetPointer(0), options);
    }
  }

  // 4. The slope-area channel-initiation score of the contributing area.
  auto score = NewArray<vtkDoubleArray>(ChannelInitiationName(), n, nullptr);
  hy::ChannelInitiationScore(
    v, area->GetPointer(0), this->SlopeExponent, this->MinimumSlope, score->GetPointer(0));

  auto river = NewArray<vtkUnsignedCharArray>(RiverName(), n, nullptr);
  const double* a = area->GetPointer(0);
  unsigned char* r = river->GetPointer(0);
  for (std::size_t k = 0; k < n; ++k)
  {
    r[k] = a[k] >= this->RiverThreshold ? 1 : 0; // NaN (no data) compares false
  }

  vtkPointData* pd = output->GetPointData();
  pd->AddArray(filled);
  pd->AddArray(direction);
  pd->AddArray(cells);
  pd->AddArray(area);
  pd->AddArray(river);
  pd->AddArray(score);
  if (angle)
  {
    pd->AddArray(angle);
  }
  if (volume)
  {
    pd->AddArray(volume);
  }
  return 1;
}

//------------------------------------------------------------------------------
bool vtkTerroirFlowAccumulation::AccumulateInPieces(vtkImageData* input,
  const terroir::GridView<float>& view,
  const float* weight,
  vtkFloatArray* filled,
  vtkSignedCharArray* direction,
  vtkDoubleArray* cells,
  vtkDoubleArray* area,
  vtkDoubleArray* volume,
  vtkFloatArray* angle)
{
  namespace hy = terroir::hydrology;
#if VTK_MODULE_ENABLE_VTK_ParallelCore
  vtkInformation* outInfo = this->GetOutputInformation(0);
  vtkMultiProcessController* controller = GetDistributedController(outInfo);
  if (!controller || !outInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
  {
    vtkErrorMacro(<< this->SourcePrefix(input) << "a distributed run without its controller");
    return false;
  }
  vtkDebugMacro(<< MethodName(this->Method)
                << " in pieces: " << hy::kPriorityFloodBarnes2016Citation << "; "
                << hy::kFlowAccumulationBarnes2017Citation);
  hy::DispersiveFlowMethod dispersive;
  dispersive.dInfinity = this->Method == DInfinity;
  dispersive.mfd.exponent = this->MFDExponent;
  dispersive.mfd.contourLength = this->MFDContourLength != 0;
  dispersive.mfd.adaptive = this->MFDAdaptiveExponent != 0;
  vtkTerroirControllerTileExchange exchange(controller);
  hy::DistributedFlowOptions options;
  options.weight = weight;
  options.weightScale = 1e-3; // mm -> m
  std::string error;
  const bool ok = vtkTerroirControllerTileExchange::Run(
    [&]
    {
      const hy::DistributedFillInput tile =
        vtkTerroirControllerTileExchange::TileInput(outInfo, input, view);
      const hy::DistributedFlowResult r = this->Method == D8
        ? hy::D8FlowAccumulationDistributed(tile, options, exchange)
        : hy::DispersiveFlowAccumulationDistributed(tile, dispersive, options, exchange);
      vtkDebugMacro(<< r.summary.outlets << " outlets, " << r.summary.flatCells << " flat cells, "
                    << r.summary.sinks << " sinks; the flats took " << r.flatExchanges
                    << " exchanges, the sums " << r.accumulationRounds << " rounds");
      std::copy(r.filled.begin(), r.filled.end(), filled->GetPointer(0));
      std::copy(r.direction.begin(), r.direction.end(), direction->GetPointer(0));
      std::copy(r.cells.begin(), r.cells.end(), cells->GetPointer(0));
      std::copy(r.area.begin(), r.area.end(), area->GetPointer(0));
      if (volume)
      {
        std::copy(r.weighted.begin(), r.weighted.end(), volume->GetPointer(0));
      }
      if (angle)
      {
        std::copy(r.angle.begin(), r.angle.end(), angle->GetPointer(0));
      }
    },
    error);
  if (!ok)
  {
    vtkErrorMacro(<< this->SourcePrefix(input) << error);
  }
  return ok;
#else
  (void)view;
  (void)weight;
  (void)filled;
  (void)direction;
  (void)cells;
  (void)area;
  (void)volume;
  (void)angle;
  vtkErrorMacro(<< this->SourcePrefix(input) << "built without VTK::ParallelCore");
  return false;
#endif
}

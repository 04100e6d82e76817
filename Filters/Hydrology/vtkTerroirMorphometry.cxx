#include "vtkTerroirMorphometry.h"

#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkTerroirTerrainInput.h"
#include "vtkUnsignedCharArray.h"

#include "Morphometry.h"
#include "NumberText.h"
#include "SlopeHorn1981.h"

#include <cmath>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkTerroirMorphometry);

namespace
{
/// A field array `name` holding `values` (one component, one tuple per value).
void AddField(vtkFieldData* fd, const char* name, const std::vector<double>& values)
{
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  a->SetNumberOfValues(static_cast<vtkIdType>(values.size()));
  for (std::size_t k = 0; k < values.size(); ++k)
  {
    a->SetValue(static_cast<vtkIdType>(k), values[k]);
  }
  fd->AddArray(a);
}

void AddField(vtkFieldData* fd, const char* name, double value)
{
  AddField(fd, name, std::vector<double>{ value });
}
} // namespace

//------------------------------------------------------------------------------
vtkTerroirMorphometry::vtkTerroirMorphometry() = default;

//------------------------------------------------------------------------------
vtkTerroirMorphometry::~vtkTerroirMorphometry() = default;

//------------------------------------------------------------------------------
void vtkTerroirMorphometry::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ChannelArea: " << this->ChannelArea << " m2\n";
  os << indent << "DepressionDepth: " << this->DepressionDepth << " m\n";
  os << indent << "SlopeBinWidth: " << this->SlopeBinWidth << " deg\n";
}

//------------------------------------------------------------------------------
double vtkTerroirMorphometry::EstimateMemory(double nx, double ny)
{
  // Outputs: StrahlerOrder 1, DepressionDepth 4, FlowLength 4 B per cell. Working buffers of
  // the core at their peak (the channel sweep): directions 1, contributing area 8, longest
  // paths 8, in-degree and two order counters 3 B per cell; earlier, the slope 4 (plus a copy
  // of the valid slopes, 4) and the filled surface 4.
  return nx * ny * (9.0 + 20.0 + 8.0);
}

//------------------------------------------------------------------------------
std::string vtkTerroirMorphometry::CheckParameters()
{
  if (!std::isfinite(this->ChannelArea) || this->ChannelArea <= 0.0)
  {
    return "ChannelArea " + terroir::NumberText(this->ChannelArea) + " m2 must be > 0 and finite";
  }
  if (!std::isfinite(this->DepressionDepth) || this->DepressionDepth < 0.0)
  {
    return "DepressionDepth " + terroir::NumberText(this->DepressionDepth) +
      " m must be >= 0 and finite";
  }
  if (!std::isfinite(this->SlopeBinWidth) || this->SlopeBinWidth <= 0.0 ||
    this->SlopeBinWidth > 90.0)
  {
    return "SlopeBinWidth " + terroir::NumberText(this->SlopeBinWidth) + " deg must be in (0, 90]";
  }
  return std::string();
}

//------------------------------------------------------------------------------
int vtkTerroirMorphometry::RequestTerrainData(vtkImageData* input,
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
  vtkDebugMacro(<< "Morphometry: " << hy::kMorphometryCitations);

  // Slope first, over row blocks (the only data-parallel part; Horn's rows are independent).
  std::vector<float> slope(n);
  terroir::terrain::SlopeParams sp;
  vtkSMPTools::For(0,
    v.ny,
    64,
    [&](vtkIdType j0, vtkIdType j1)
    {
      terroir::terrain::SlopeHorn1981Rows<float>(
        v, sp, slope.data(), nullptr, nullptr, static_cast<int>(j0), static_cast<int>(j1));
    });
  this->UpdateProgress(0.1);

  vtkSmartPointer<vtkFloatArray> depth = vtkSmartPointer<vtkFloatArray>::Take(
    terroir::NewOutputArray(DepressionDepthName(), 1, static_cast<long long>(n), "m"));
  vtkSmartPointer<vtkFloatArray> length = vtkSmartPointer<vtkFloatArray>::Take(
    terroir::NewOutputArray(FlowLengthName(), 1, static_cast<long long>(n), "m"));
  auto order = vtkSmartPointer<vtkUnsignedCharArray>::New();
  order->SetName(StrahlerOrderName());
  if (!order->Allocate(static_cast<vtkIdType>(n)))
  {
    throw std::bad_alloc();
  }
  order->SetNumberOfTuples(static_cast<vtkIdType>(n));

  hy::MorphometryParams params;
  params.channelArea = this->ChannelArea;
  params.depressionDepth = this->DepressionDepth;
  params.slopeBinWidth = this->SlopeBinWidth;
  hy::MorphometryCells cells;
  cells.slope = slope.data();
  cells.depressionDepth = depth->GetPointer(0);
  cells.strahlerOrder = order->GetPointer(0);
  cells.flowLength = length->GetPointer(0);
  hy::MorphometryReport r;
  try
  {
    r =
      hy::Morphometry(v, params, cells, [this](double f) { this->UpdateProgress(0.1 + 0.85 * f); });
  }
  catch (const std::logic_error& e) // no cell with data, a grid too small, a cycle
  {
    vtkErrorMacro(<< this->SourcePrefix(input) << e.what());
    return 0;
  }
  slope.clear();
  slope.shrink_to_fit();

  output->GetPointData()->AddArray(order);
  output->GetPointData()->AddArray(depth);
  output->GetPointData()->AddArray(length);

  vtkFieldData* fd = output->GetFieldData();
  AddField(fd, "ValidCells", static_cast<double>(r.validCells));
  AddField(fd, "ValidArea", r.validArea);
  AddField(fd, "ElevationMin", r.minElevation);
  AddField(fd, "ElevationMax", r.maxElevation);
  AddField(fd, "ElevationMean", r.meanElevation);
  AddField(fd, "HypsometricIntegral", r.hypsometricIntegral);
  AddField(fd, "SlopeMean", r.slopeMean);
  AddField(fd, "SlopeMedian", r.slopeMedian);
  AddField(fd, "SlopeP10", r.slopeP10);
  AddField(fd, "SlopeP90", r.slopeP90);
  AddField(fd, "SlopeBinWidth", r.slopeBinWidth);
  auto histogram = vtkSmartPointer<vtkIdTypeArray>::New();
  histogram->SetName("SlopeHistogram");
  histogram->SetNumberOfValues(static_cast<vtkIdType>(r.slopeHistogram.size()));
  for (std::size_t k = 0; k < r.slopeHistogram.size(); ++k)
  {
    histogram->SetValue(static_cast<vtkIdType>(k), static_cast<vtkIdType>(r.slopeHistogram[k]));
  }
  fd->AddArray(histogram);
  AddField(fd, "DepressionCells", static_cast<double>(r.depressionCells));
  AddField(fd, "DepressionShare", r.depressionShare);
  AddField(fd, "DepressionVolume", r.depressionVolume);
  AddField(fd, "ChannelArea", r.channelArea);
  AddField(fd, "ChannelCells", static_cast<double>(r.channelCells));
  AddField(fd, "ChannelLength", r.channelLength);
  AddField(fd, "DrainageDensity", r.drainageDensity);
  std::vector<double> count, mean, total;
  for (const hy::HortonOrderRow& row : r.orders)
  {
    count.push_back(static_cast<double>(row.streams));
    mean.push_back(row.meanLength);
    total.push_back(row.totalLength);
  }
  AddField(fd, "HortonStreamCount", count);
  AddField(fd, "HortonMeanLength", mean);
  AddField(fd, "HortonTotalLength", total);
  AddField(fd,
    "HortonOrdersFitted",
    std::vector<double>{
      static_cast<double>(r.hortonFirstOrder), static_cast<double>(r.hortonLastOrder) });
  AddField(fd, "BifurcationRatio", r.bifurcationRatio);
  AddField(fd, "LengthRatio", r.lengthRatio);
  AddField(fd, "HackExponent", r.hackExponent);
  AddField(fd, "HackCoefficient", r.hackCoefficient);
  AddField(fd, "HackPoints", static_cast<double>(r.hackPoints));
  this->UpdateProgress(1.0);
  return 1;
}

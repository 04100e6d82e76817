#include "vtkTerroirPolygonIslandSource.h"

#include "PolygonIsland.h"

#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirIOPrivate.h"
#include "vtkUnsignedCharArray.h"

#include "MemoryBudget.h"

#include <algorithm>

vtkStandardNewMacro(vtkTerroirPolygonIslandSource);

//------------------------------------------------------------------------------
vtkTerroirPolygonIslandSource::vtkTerroirPolygonIslandSource()
{
  this->SetNumberOfInputPorts(0);
  this->SetNumberOfOutputPorts(1);
}

//------------------------------------------------------------------------------
void vtkTerroirPolygonIslandSource::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Dimensions: " << this->Dimensions[0] << " x " << this->Dimensions[1] << "\n";
  os << indent << "Spacing: " << this->Spacing << " m\n";
  os << indent << "Seed: " << this->Seed << "\n";
  os << indent << "Regions: " << this->Regions << "\n";
  os << indent << "Relaxations: " << this->Relaxations << "\n";
  os << indent << "Rivers: " << this->Rivers << "\n";
  os << indent << "MaximumHeight: " << this->MaximumHeight << " m\n";
  os << indent << "MaximumDepth: " << this->MaximumDepth << " m\n";
  os << indent << "NoiseScale: " << this->NoiseScale << "\n";
  os << indent << "Perturbation: " << this->Perturbation << "\n";
}

//------------------------------------------------------------------------------
int vtkTerroirPolygonIslandSource::RequestInformation(vtkInformation*,
  vtkInformationVector**,
  vtkInformationVector* outputVector)
{
  const int nx = this->Dimensions[0], ny = this->Dimensions[1];
  if (nx < 8 || ny < 8 || nx > 65536 || ny > 65536 || !(this->Spacing > 0.0))
  {
    this->ErrorMessage = "vtkTerroirPolygonIslandSource: Dimensions must be 8 to 65536 and "
                         "Spacing positive";
    vtkErrorMacro(<< this->ErrorMessage);
    return 0;
  }
  terroir::io::detail::SetTerrainInformation(
    outputVector->GetInformationObject(0), nx, ny, this->Spacing, this->Spacing, 0.0, 0.0);
  return 1;
}

//------------------------------------------------------------------------------
int vtkTerroirPolygonIslandSource::RequestData(vtkInformation*,
  vtkInformationVector**,
  vtkInformationVector* outputVector)
{
  vtkImageData* output = vtkImageData::GetData(outputVector, 0);
  output->Initialize();
  this->ErrorMessage.clear();
  const int nx = this->Dimensions[0], ny = this->Dimensions[1];
  // The rasters of the generator (about 30 bytes a cell) and the output arrays (15).
  const std::string memory = terroir::CheckMemory(45.0 * nx * ny, "the polygon-map island");
  if (!memory.empty())
  {
    this->ErrorMessage = "vtkTerroirPolygonIslandSource: " + memory;
    vtkErrorMacro(<< this->ErrorMessage);
    return 0;
  }
  terroir::generation::PolygonIslandParameters p;
  p.seed = this->Seed;
  p.width = nx;
  p.height = ny;
  p.regions = this->Regions;
  p.relaxations = this->Relaxations;
  p.rivers = this->Rivers;
  p.maximumHeight = this->MaximumHeight;
  p.maximumDepth = this->MaximumDepth;
  p.noiseScale = this->NoiseScale;
  p.perturbation = this->Perturbation;
  terroir::generation::PolygonIsland island;
  std::string error;
  if (!terroir::generation::GeneratePolygonIsland(p, island, error))
  {
    this->ErrorMessage = "vtkTerroirPolygonIslandSource: " + error;
    vtkErrorMacro(<< this->ErrorMessage);
    return 0;
  }
  output->SetExtent(0, nx - 1, 0, ny - 1, 0, 0);
  output->SetSpacing(this->Spacing, this->Spacing, 1.0);
  output->SetOrigin(0.0, 0.0, 0.0);
  const vtkIdType n = static_cast<vtkIdType>(nx) * ny;
  vtkNew<vtkFloatArray> elevation;
  elevation->SetName(vtkTerroirGeoreference::ElevationName());
  elevation->SetNumberOfTuples(n);
  elevation->GetInformation()->Set(vtkDataArray::UNITS_LABEL(), "m");
  std::copy(island.heightMeters.begin(), island.heightMeters.end(), elevation->GetPointer(0));
  auto bytes = [n](const char* name, const std::vector<std::uint8_t>& values)
  {
    vtkNew<vtkUnsignedCharArray> a;
    a->SetName(name);
    a->SetNumberOfTuples(n);
    std::copy(values.begin(), values.end(), a->GetPointer(0));
    return vtkSmartPointer<vtkUnsignedCharArray>(a.Get());
  };
  vtkNew<vtkFloatArray> moisture;
  moisture->SetName("Moisture");
  moisture->SetNumberOfTuples(n);
  std::copy(island.moistureMap.begin(), island.moistureMap.end(), moisture->GetPointer(0));
  vtkNew<vtkIntArray> region;
  region->SetName("RegionId");
  region->SetNumberOfTuples(n);
  std::copy(island.region.begin(), island.region.end(), region->GetPointer(0));
  vtkPointData* pd = output->GetPointData();
  pd->SetScalars(elevation);
  pd->AddArray(bytes("Biome", island.biomeMap));
  pd->AddArray(moisture);
  pd->AddArray(bytes("River", island.riverMap));
  pd->AddArray(bytes("WaterClass", island.waterMap));
  pd->AddArray(region);
  return 1;
}

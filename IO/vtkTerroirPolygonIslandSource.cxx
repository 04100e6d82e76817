#include "vtkTerroirPolygonIslandSource.h"

#include "PolygonIsland.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirIOPrivate.h"
#include "vtkUnsignedCharArray.h"

#include "MemoryBudget.h"

#include <cpl_conv.h>
#include <ogr_srs_api.h>

#include <algorithm>

vtkStandardNewMacro(vtkTerroirPolygonIslandSource);

//------------------------------------------------------------------------------
vtkTerroirPolygonIslandSource::vtkTerroirPolygonIslandSource()
{
  this->SetNumberOfInputPorts(0);
  this->SetNumberOfOutputPorts(2);
}

//------------------------------------------------------------------------------
int vtkTerroirPolygonIslandSource::FillOutputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), port == 0 ? "vtkImageData" : "vtkPolyData");
  return 1;
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
  os << indent << "CRS: " << (this->CRS.empty() ? "(none)" : this->CRS) << "\n";
  os << indent << "Origin: " << this->Origin[0] << ", " << this->Origin[1] << "\n";
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
  // The CRS, resolved before any work.
  std::string wkt;
  if (!this->CRS.empty())
  {
    OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
    char* text = nullptr;
    const bool ok = OSRSetFromUserInput(srs, this->CRS.c_str()) == OGRERR_NONE &&
      OSRIsProjected(srs) && OSRExportToWkt(srs, &text) == OGRERR_NONE;
    if (ok)
    {
      wkt = text;
    }
    CPLFree(text);
    OSRDestroySpatialReference(srs);
    if (!ok)
    {
      this->ErrorMessage = "vtkTerroirPolygonIslandSource: CRS '" + this->CRS +
        "' is not a projected coordinate reference system GDAL knows";
      vtkErrorMacro(<< this->ErrorMessage);
      return 0;
    }
  }
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
  output->SetOrigin(this->Origin[0], this->Origin[1], 0.0);
  if (!wkt.empty())
  {
    // North-up GeoTransform of the cells' corners; row 0 of the image is the southern one.
    const double s = this->Spacing;
    const double gt[6] = {
      this->Origin[0] - 0.5 * s, s, 0.0, this->Origin[1] + (ny - 0.5) * s, 0.0, -s
    };
    vtkTerroirGeoreference::SetGeoTransform(output, gt);
    vtkTerroirGeoreference::SetCRS(output, wkt);
  }
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

  // Port 1: the rivers, a line per step from a region's point to the next one down.
  vtkPolyData* rivers = vtkPolyData::GetData(outputVector, 1);
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkCellArray> lines;
  vtkNew<vtkFloatArray> flow;
  flow->SetName("RiverFlow");
  auto world = [&](int k, double xyz[3])
  {
    // Map coordinates to the image's: cell i's centre is at x = (i + 0.5) 2 / nx - 1.
    xyz[0] = this->Origin[0] + ((island.siteX[k] + 1.0) * nx / 2.0 - 0.5) * this->Spacing;
    xyz[1] = this->Origin[1] + (island.siteY[k] * nx / 2.0 + 0.5 * ny - 0.5) * this->Spacing;
    xyz[2] = 0.0;
  };
  for (int k = 0; k < p.regions; ++k)
  {
    const int next = island.downslope[k];
    if (island.riverFlow[k] <= 0.0 || next < 0)
    {
      continue;
    }
    double a[3], b[3];
    world(k, a);
    world(next, b);
    const vtkIdType ids[2] = { points->InsertNextPoint(a), points->InsertNextPoint(b) };
    lines->InsertNextCell(2, ids);
    flow->InsertNextValue(static_cast<float>(island.riverFlow[k]));
  }
  rivers->SetPoints(points);
  rivers->SetLines(lines);
  rivers->GetCellData()->AddArray(flow);
  return 1;
}

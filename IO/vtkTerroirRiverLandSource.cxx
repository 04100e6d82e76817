#include "vtkTerroirRiverLandSource.h"

#include "RiverLand.h"

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
#include "vtkSMPTools.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirIOPrivate.h"
#include "vtkUnsignedCharArray.h"

#include "MemoryBudget.h"

#include <cpl_conv.h>
#include <ogr_srs_api.h>

#include <algorithm>

vtkStandardNewMacro(vtkTerroirRiverLandSource);

namespace
{
/// The properties, then the JSON's keys over them.
bool Gather(vtkTerroirRiverLandSource* s,
  terroir::generation::RiverLandParameters& p,
  std::string& error)
{
  p.width = s->GetDimensions()[0];
  p.height = s->GetDimensions()[1];
  p.spacing = s->GetSpacing();
  p.seed = s->GetSeed();
  p.rivers = s->GetRivers();
  p.island = s->GetIsland();
  p.prune = s->GetPrune();
  p.pruneThreshold = s->GetPruneThreshold();
  p.hillSlope = s->GetHillSlope();
  p.noiseAmplitude = s->GetNoiseAmplitude();
  p.threads = s->GetThreads() > 0 ? s->GetThreads() : vtkSMPTools::GetEstimatedNumberOfThreads();
  const std::string json = s->GetParametersJSON();
  if (!json.empty())
  {
    return terroir::generation::RiverLandParametersFromJson(json, p, error);
  }
  return terroir::generation::ValidateRiverLandParameters(p, error);
}
} // namespace

//------------------------------------------------------------------------------
vtkTerroirRiverLandSource::vtkTerroirRiverLandSource()
{
  this->SetNumberOfInputPorts(0);
  this->SetNumberOfOutputPorts(2);
}

//------------------------------------------------------------------------------
int vtkTerroirRiverLandSource::FillOutputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), port == 0 ? "vtkImageData" : "vtkPolyData");
  return 1;
}

//------------------------------------------------------------------------------
void vtkTerroirRiverLandSource::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Dimensions: " << this->Dimensions[0] << " x " << this->Dimensions[1] << "\n";
  os << indent << "Spacing: " << this->Spacing << " m\n";
  os << indent << "Seed: " << this->Seed << "\n";
  os << indent << "Rivers: " << this->Rivers << "\n";
  os << indent << "Island: " << this->Island << "\n";
  os << indent << "Prune: " << this->Prune << " (threshold " << this->PruneThreshold << ")\n";
  os << indent << "HillSlope: " << this->HillSlope << "\n";
  os << indent << "NoiseAmplitude: " << this->NoiseAmplitude << " m\n";
  os << indent << "Threads: " << this->Threads << "\n";
  os << indent << "ParametersJSON: " << (this->ParametersJSON.empty() ? "(none)" : "set") << "\n";
  os << indent << "CRS: " << (this->CRS.empty() ? "(none)" : this->CRS) << "\n";
  os << indent << "Origin: " << this->Origin[0] << ", " << this->Origin[1] << "\n";
}

//------------------------------------------------------------------------------
int vtkTerroirRiverLandSource::RequestInformation(vtkInformation*,
  vtkInformationVector**,
  vtkInformationVector* outputVector)
{
  terroir::generation::RiverLandParameters p;
  std::string error;
  if (!Gather(this, p, error))
  {
    this->ErrorMessage = "vtkTerroirRiverLandSource: " + error;
    vtkErrorMacro(<< this->ErrorMessage);
    return 0;
  }
  terroir::io::detail::SetTerrainInformation(
    outputVector->GetInformationObject(0), p.width, p.height, p.spacing, p.spacing, 0.0, 0.0);
  return 1;
}

//------------------------------------------------------------------------------
int vtkTerroirRiverLandSource::RequestData(vtkInformation*,
  vtkInformationVector**,
  vtkInformationVector* outputVector)
{
  vtkImageData* output = vtkImageData::GetData(outputVector, 0);
  output->Initialize();
  this->ErrorMessage.clear();
  terroir::generation::RiverLandParameters p;
  std::string error;
  if (!Gather(this, p, error))
  {
    this->ErrorMessage = "vtkTerroirRiverLandSource: " + error;
    vtkErrorMacro(<< this->ErrorMessage);
    return 0;
  }
  const int nx = p.width, ny = p.height;
  // The generator's rasters (about 90 bytes a cell) and the output arrays (19).
  const std::string memory = terroir::CheckMemory(110.0 * nx * ny, "the RiverLand terrain");
  if (!memory.empty())
  {
    this->ErrorMessage = "vtkTerroirRiverLandSource: " + memory;
    vtkErrorMacro(<< this->ErrorMessage);
    return 0;
  }
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
      this->ErrorMessage = "vtkTerroirRiverLandSource: CRS '" + this->CRS +
        "' is not a projected coordinate reference system GDAL knows";
      vtkErrorMacro(<< this->ErrorMessage);
      return 0;
    }
  }
  terroir::generation::RiverLand land;
  if (!terroir::generation::GenerateRiverLand(p, land, error))
  {
    this->ErrorMessage = "vtkTerroirRiverLandSource: " + error;
    vtkErrorMacro(<< this->ErrorMessage);
    return 0;
  }
  this->MedialBefore = land.medialBefore;
  this->MedialAfter = land.medialAfter;
  this->PruneSeconds = land.pruneSeconds;
  this->SlopesApplied = land.slopesApplied;
  const double s = p.spacing;
  output->SetExtent(0, nx - 1, 0, ny - 1, 0, 0);
  output->SetSpacing(s, s, 1.0);
  output->SetOrigin(this->Origin[0], this->Origin[1], 0.0);
  if (!wkt.empty())
  {
    // North-up GeoTransform of the cells' corners; row 0 of the image is the southern one.
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
  std::copy(land.heightMeters.begin(), land.heightMeters.end(), elevation->GetPointer(0));
  vtkNew<vtkUnsignedCharArray> river, medial, cls;
  river->SetName("River");
  medial->SetName("MedialAxis");
  cls->SetName("CellClass");
  vtkNew<vtkIntArray> riverId;
  riverId->SetName("RiverId");
  vtkNew<vtkFloatArray> distance, weight;
  distance->SetName("DistanceToRiver");
  distance->GetInformation()->Set(vtkDataArray::UNITS_LABEL(), "m");
  weight->SetName("SlopeWeight");
  for (vtkDataArray* a : { static_cast<vtkDataArray*>(river.Get()),
         static_cast<vtkDataArray*>(medial.Get()),
         static_cast<vtkDataArray*>(cls.Get()),
         static_cast<vtkDataArray*>(riverId.Get()),
         static_cast<vtkDataArray*>(distance.Get()),
         static_cast<vtkDataArray*>(weight.Get()) })
  {
    a->SetNumberOfTuples(n);
  }
  for (vtkIdType c = 0; c < n; ++c)
  {
    const bool isRiver = land.cls[c] == terroir::generation::RiverLandRiver;
    river->SetValue(c, isRiver ? 1 : 0);
    riverId->SetValue(c, land.riverId[c]);
    medial->SetValue(c, land.medial[c]);
    cls->SetValue(c, land.cls[c]);
    distance->SetValue(c,
      land.cls[c] == terroir::generation::RiverLandSea ? -1.0f
                                                       : static_cast<float>(land.distance[c] * s));
    weight->SetValue(c, land.slopeWeight[c]);
  }
  vtkPointData* pd = output->GetPointData();
  pd->SetScalars(elevation);
  pd->AddArray(river);
  pd->AddArray(riverId);
  pd->AddArray(medial);
  pd->AddArray(distance);
  pd->AddArray(cls);
  pd->AddArray(weight);

  // Port 1: a polyline per river through its cells' centres, from its mouth or junction.
  vtkPolyData* rivers = vtkPolyData::GetData(outputVector, 1);
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkCellArray> lines;
  vtkNew<vtkIntArray> ids, parents, levels;
  ids->SetName("RiverId");
  parents->SetName("Parent");
  levels->SetName("Level");
  for (std::size_t r = 0; r < land.rivers.size(); ++r)
  {
    const terroir::generation::RiverLandRiverPath& path = land.rivers[r];
    std::vector<int> cells;
    if (path.junction >= 0)
    {
      cells.push_back(path.junction);
    }
    cells.insert(cells.end(), path.cells.begin(), path.cells.end());
    if (cells.size() < 2)
    {
      continue;
    }
    lines->InsertNextCell(static_cast<vtkIdType>(cells.size()));
    for (int c : cells)
    {
      lines->InsertCellPoint(points->InsertNextPoint(
        this->Origin[0] + (c % nx) * s, this->Origin[1] + (c / nx) * s, 0.0));
    }
    ids->InsertNextValue(static_cast<int>(r));
    parents->InsertNextValue(path.parent);
    levels->InsertNextValue(path.level);
  }
  rivers->SetPoints(points);
  rivers->SetLines(lines);
  rivers->GetCellData()->AddArray(ids);
  rivers->GetCellData()->AddArray(parents);
  rivers->GetCellData()->AddArray(levels);
  return 1;
}

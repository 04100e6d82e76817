// `terroir plants`: plants for every ecological zone (vtkTerroirPlantPlacement), from the zones
// of `terroir kmeans` or `terroir run`, optionally learned from an exemplar file.
#include "TerroirCommands.h"

#include "TerroirApp.h"
#include "TerroirCommandSupport.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkXMLPolyDataReader.h"

#include "PointPatternFile.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirPlantPlacement.h"

#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <sys/stat.h>

namespace terroir
{
namespace app
{
namespace
{
const char* const kClusterId = vtkTerroirPlantPlacement::ClusterIdName();

/// The zones: a ClusterId point array, or the first band taken as whole zone ids (NaN: -1).
vtkSmartPointer<vtkImageData> ReadZones(const std::string& path, bool allowNetwork)
{
  vtkSmartPointer<vtkImageData> image = ReadTerrain(path, allowNetwork, "auto");
  vtkPointData* pd = image->GetPointData();
  vtkDataArray* ids = pd->GetArray(kClusterId);
  if (ids)
  {
    if (ids->GetNumberOfComponents() != 1)
    {
      throw Failure(path + ": its ClusterId array has " +
        std::to_string(ids->GetNumberOfComponents()) + " components, 1 is needed");
    }
    return image;
  }
  vtkDataArray* band = pd->GetArray(vtkTerroirGeoreference::ElevationName());
  if (!band)
  {
    throw Failure(path + ": no ClusterId point array and no band to read zone ids from");
  }
  int dims[3];
  image->GetDimensions(dims);
  vtkNew<vtkIntArray> zone;
  zone->SetName(kClusterId);
  zone->SetNumberOfValues(band->GetNumberOfTuples());
  for (vtkIdType k = 0; k < band->GetNumberOfTuples(); ++k)
  {
    const double v = band->GetComponent(k, 0);
    if (std::isfinite(v) && (v != std::floor(v) || v < -1.0 || v > 1e9))
    {
      throw Failure(path + ": value " + std::to_string(v) + " at cell (" +
        std::to_string(k % dims[0]) + ", " + std::to_string(k / dims[0]) +
        ") is not a zone id (a whole number from -1); give the ClusterId raster of terroir "
        "kmeans");
    }
    zone->SetValue(k, std::isfinite(v) ? static_cast<int>(v) : -1);
  }
  // The band was the zones, not heights: the plants stand at z = 0.
  pd->RemoveArray(vtkTerroirGeoreference::ElevationName());
  pd->AddArray(zone);
  return image;
}

/// The exemplar plants of a .csv (PointPatternFile.h) or .vtp file, with `window` (4 values:
/// xmin, xmax, ymin, ymax) as their ExemplarWindow when given.
vtkSmartPointer<vtkPolyData> ReadExemplar(const std::string& path,
  const std::vector<double>& window)
{
  struct stat st;
  if (stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode))
  {
    throw Failure(path + ": cannot be read (no such file)");
  }
  auto plants = vtkSmartPointer<vtkPolyData>::New();
  if (HasExtension(path, ".vtp"))
  {
    vtkNew<vtkXMLPolyDataReader> reader;
    reader->SetFileName(path.c_str());
    reader->Update();
    TakeLastVTKError();
    if (reader->GetErrorCode() != 0 || !reader->GetOutput() ||
      reader->GetOutput()->GetNumberOfPoints() == 0)
    {
      throw Failure(path + ": not a VTK polydata file with points");
    }
    plants->ShallowCopy(reader->GetOutput());
  }
  else
  {
    if (static_cast<std::size_t>(st.st_size) > io::kMaxPointPatternFileBytes)
    {
      throw Failure(
        path + ": larger than " + std::to_string(io::kMaxPointPatternFileBytes >> 20) + " MiB");
    }
    std::ifstream in(path, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    if (!in)
    {
      throw Failure(path + ": cannot be read");
    }
    const std::string bytes = text.str();
    io::PointPatternTable t;
    std::string error;
    if (!io::ParsePointPatternCsv(bytes.data(), bytes.size(), t, error))
    {
      throw Failure(path + ": " + error);
    }
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    for (std::size_t k = 0; k < t.x.size(); ++k)
    {
      points->InsertNextPoint(t.x[k], t.y[k], t.hasZ ? t.z[k] : 0.0);
    }
    plants->SetPoints(points);
    auto add = [&](const std::vector<int>& values, const char* name)
    {
      if (values.empty())
      {
        return;
      }
      vtkNew<vtkIntArray> a;
      a->SetName(name);
      for (int v : values)
      {
        a->InsertNextValue(v);
      }
      plants->GetPointData()->AddArray(a);
    };
    add(t.species, vtkTerroirPlantPlacement::SpeciesName());
    add(t.zone, kClusterId);
  }
  if (window.size() == 4)
  {
    vtkNew<vtkDoubleArray> w;
    w->SetName("ExemplarWindow");
    w->SetNumberOfComponents(4);
    w->InsertNextTuple(window.data());
    plants->GetFieldData()->AddArray(w);
  }
  return plants;
}

/// The plants as CSV: x, y, z, species, cluster_id.
std::string PlantsCsv(vtkPolyData* plants)
{
  io::PointPatternTable t;
  t.hasZ = true;
  vtkDataArray* species = plants->GetPointData()->GetArray(vtkTerroirPlantPlacement::SpeciesName());
  vtkDataArray* zone = plants->GetPointData()->GetArray(kClusterId);
  for (vtkIdType k = 0; k < plants->GetNumberOfPoints(); ++k)
  {
    double p[3];
    plants->GetPoint(k, p);
    t.x.push_back(p[0]);
    t.y.push_back(p[1]);
    t.z.push_back(p[2]);
    t.species.push_back(species ? static_cast<int>(species->GetComponent(k, 0)) : 0);
    t.zone.push_back(zone ? static_cast<int>(zone->GetComponent(k, 0)) : -1);
  }
  if (t.x.empty())
  {
    return "x,y,z,species,cluster_id\n";
  }
  return io::FormatPointPatternCsv(t);
}
} // namespace

int CommandPlants(const CommandLine& c)
{
  const auto& s = c.Plants;
  CheckWritable({ c.Output }, c.Overwrite);
  vtkSmartPointer<vtkImageData> zones = ReadZones(c.Input, c.AllowNetwork);
  vtkNew<vtkTerroirPlantPlacement> placement;
  placement->SetInputData(zones);
  if (!s.Exemplar.empty())
  {
    placement->SetExemplarData(ReadExemplar(s.Exemplar, s.Window));
  }
  placement->SetDensity(s.Density);
  placement->SetMinimumDistance(s.MinimumDistance);
  placement->SetMaximumDistance(s.MaximumDistance);
  placement->SetBins(s.Bins);
  placement->SetSeed(s.Seed);
  placement->SetIterations(s.Iterations);
  WatchProgress(placement, "plants");
  UpdateOrThrow(placement, "plants");
  vtkPolyData* plants = placement->GetOutput();
  if (HasExtension(c.Output, ".csv"))
  {
    WriteTextFile(c.Output, PlantsCsv(plants), c.Overwrite);
  }
  else
  {
    WriteVTP(plants, c.Output);
  }
  vtkDataArray* zoneIds = plants->GetFieldData()->GetArray("PlantZones");
  std::cout << "plants: " << plants->GetNumberOfPoints() << " plants in "
            << (zoneIds ? zoneIds->GetNumberOfTuples() : 0) << " zones"
            << (s.Exemplar.empty() ? " (hard core)" : " (learned from " + s.Exemplar + ")") << "\n";
  return 0;
}

} // namespace app
} // namespace terroir

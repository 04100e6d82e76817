#include "vtkTerroirPlantPlacement.h"

#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"

#include "PointPattern.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkTerroirPlantPlacement);

namespace
{
namespace cl = terroir::clustering;

/// One species, no pair closer than d0, `density` plants per m^2: g is 0 below d0 and 1
/// beyond (the share of a bin's annulus beyond d0 where d0 falls inside it).
cl::RadialDistributionModel HardCoreModel(double density, double d0, double rMax, int bins)
{
  cl::RadialDistributionModel m;
  m.categories = 1;
  m.bins = bins;
  m.rMin = 0.0;
  m.rMax = rMax;
  m.density = { density };
  m.hardCore = { d0 };
  const double width = rMax / bins;
  for (int k = 0; k < bins; ++k)
  {
    const double r0 = k * width;
    const double r1 = (k + 1) * width;
    const double beyond =
      std::max(0.0, r1 * r1 - std::max(r0, std::min(d0, r1)) * std::max(r0, std::min(d0, r1)));
    m.g.push_back(beyond / (r1 * r1 - r0 * r0));
  }
  return m;
}

/// Elevation at (x, y): bilinear between the 4 grid points around it (clamped to the grid),
/// over those with a finite value; 0 without an elevation array or finite neighbours.
double ElevationAt(vtkImageData* image, vtkDataArray* z, double x, double y)
{
  if (!z)
  {
    return 0.0;
  }
  int dims[3];
  double origin[3], spacing[3];
  image->GetDimensions(dims);
  image->GetOrigin(origin);
  image->GetSpacing(spacing);
  const double fi = std::min(std::max((x - origin[0]) / spacing[0], 0.0), dims[0] - 1.0);
  const double fj = std::min(std::max((y - origin[1]) / spacing[1], 0.0), dims[1] - 1.0);
  const int i0 = static_cast<int>(fi);
  const int j0 = static_cast<int>(fj);
  const int i1 = std::min(i0 + 1, dims[0] - 1);
  const int j1 = std::min(j0 + 1, dims[1] - 1);
  const double u = fi - i0;
  const double v = fj - j0;
  const int ci[4] = { i0, i1, i0, i1 };
  const int cj[4] = { j0, j0, j1, j1 };
  const double w[4] = { (1 - u) * (1 - v), u * (1 - v), (1 - u) * v, u * v };
  double sum = 0.0;
  double weight = 0.0;
  for (int c = 0; c < 4; ++c)
  {
    const double h = z->GetComponent(static_cast<vtkIdType>(cj[c]) * dims[0] + ci[c], 0);
    if (std::isfinite(h) && w[c] > 0.0)
    {
      sum += w[c] * h;
      weight += w[c];
    }
  }
  return weight > 0.0 ? sum / weight : 0.0;
}

/// The exemplar's plants: position, species and (when given) zone (-1: every zone).
struct Exemplar
{
  std::vector<cl::PatternPoint> points;
  std::vector<int> zone;
  double window[4] = { 0, 0, 0, 0 }; ///< xmin, xmax, ymin, ymax
  int categories = 1;
  bool zoned = false;
};

/// Reads the exemplar; throws std::invalid_argument on bad species or an empty window.
Exemplar ReadExemplar(vtkPolyData* data)
{
  Exemplar e;
  vtkDataArray* species = data->GetPointData()->GetArray(vtkTerroirPlantPlacement::SpeciesName());
  vtkDataArray* zones = data->GetPointData()->GetArray(vtkTerroirPlantPlacement::ClusterIdName());
  e.zoned = zones != nullptr;
  const vtkIdType n = data->GetNumberOfPoints();
  for (vtkIdType p = 0; p < n; ++p)
  {
    double x[3];
    data->GetPoint(p, x);
    const double s = species ? species->GetComponent(p, 0) : 0.0;
    if (!(s >= 0.0 && s < cl::PatternMaxCategories) || s != std::floor(s))
    {
      throw std::invalid_argument("exemplar plant " + std::to_string(p) + " has Species " +
        std::to_string(s) + ": species must be integers 0.." +
        std::to_string(cl::PatternMaxCategories - 1));
    }
    e.points.push_back(cl::PatternPoint{ x[0], x[1], static_cast<int>(s) });
    e.zone.push_back(zones ? static_cast<int>(zones->GetComponent(p, 0)) : -1);
    e.categories = std::max(e.categories, static_cast<int>(s) + 1);
  }
  vtkDataArray* window = data->GetFieldData()->GetArray("ExemplarWindow");
  if (window && window->GetNumberOfValues() >= 4)
  {
    for (int k = 0; k < 4; ++k)
    {
      e.window[k] = window->GetComponent(
        k / window->GetNumberOfComponents(), k % window->GetNumberOfComponents());
    }
  }
  else
  {
    // The points' bounds, the upper edges moved up by one ulp: the window is half-open, and
    // the points that make the bounds belong in it.
    double b[6];
    data->GetBounds(b);
    const double inf = std::numeric_limits<double>::infinity();
    const bool area = b[1] > b[0] && b[3] > b[2]; // a line of points has none
    const double w[4] = {
      b[0], area ? std::nextafter(b[1], inf) : b[1], b[2], area ? std::nextafter(b[3], inf) : b[3]
    };
    std::copy(w, w + 4, e.window);
  }
  if (!(e.window[1] > e.window[0] && e.window[3] > e.window[2]))
  {
    throw std::invalid_argument("the exemplar's window (ExemplarWindow or its points' bounds) "
                                "is empty");
  }
  return e;
}
} // namespace

//------------------------------------------------------------------------------
vtkTerroirPlantPlacement::vtkTerroirPlantPlacement()
{
  this->SetNumberOfInputPorts(2);
}

//------------------------------------------------------------------------------
vtkTerroirPlantPlacement::~vtkTerroirPlantPlacement() = default;

//------------------------------------------------------------------------------
void vtkTerroirPlantPlacement::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Seed: " << this->Seed << "\n";
  os << indent << "Density: " << this->Density << " per m2\n";
  os << indent << "MinimumDistance: " << this->MinimumDistance << " m\n";
  os << indent << "MaximumDistance: " << this->MaximumDistance << " m\n";
  os << indent << "Bins: " << this->Bins << "\n";
  os << indent << "Iterations: " << this->Iterations << "\n";
}

//------------------------------------------------------------------------------
int vtkTerroirPlantPlacement::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 0)
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkImageData");
    return 1;
  }
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

//------------------------------------------------------------------------------
int vtkTerroirPlantPlacement::RequestData(vtkInformation*,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  vtkImageData* image = vtkImageData::GetData(inputVector[0]);
  vtkPolyData* exemplarData = inputVector[1]->GetNumberOfInformationObjects() > 0
    ? vtkPolyData::GetData(inputVector[1])
    : nullptr;
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  if (!image || !output)
  {
    vtkErrorMacro(<< "vtkTerroirPlantPlacement needs an image of zones");
    return 0;
  }
  vtkDataArray* labelArray = image->GetPointData()->GetArray(ClusterIdName());
  if (!labelArray || labelArray->GetNumberOfComponents() != 1)
  {
    vtkErrorMacro(<< "the zones image has no one-component point array `ClusterId` "
                     "(vtkTerroirKMeans makes it)");
    return 0;
  }
  if (!(this->Density >= 0.0 && std::isfinite(this->Density)) ||
    !(this->MinimumDistance >= 0.0 && std::isfinite(this->MinimumDistance)) ||
    !(this->MaximumDistance >= 0.0 && std::isfinite(this->MaximumDistance)))
  {
    vtkErrorMacro(<< "Density, MinimumDistance and MaximumDistance must be finite numbers >= 0");
    return 0;
  }
  int dims[3];
  double origin[3], spacing[3];
  image->GetDimensions(dims);
  image->GetOrigin(origin);
  image->GetSpacing(spacing);
  const std::size_t n = static_cast<std::size_t>(dims[0]) * static_cast<std::size_t>(dims[1]);
  if (dims[2] != 1 || n == 0 || static_cast<std::size_t>(labelArray->GetNumberOfTuples()) != n)
  {
    vtkErrorMacro(<< "the zones image must be 2-D (nx, ny, 1) with one ClusterId per point");
    return 0;
  }
  std::vector<int> labels(n);
  std::set<int> zones;
  for (std::size_t k = 0; k < n; ++k)
  {
    const double l = labelArray->GetComponent(static_cast<vtkIdType>(k), 0);
    labels[k] = std::isfinite(l) && l >= 0.0 ? static_cast<int>(l) : -1;
    if (labels[k] >= 0)
    {
      zones.insert(labels[k]);
    }
  }

  cl::ZonePatterns plants;
  try
  {
    std::vector<cl::ZoneModel> models;
    if (!exemplarData || exemplarData->GetNumberOfPoints() == 0)
    {
      const double rMax = this->MaximumDistance > 0.0 ? this->MaximumDistance
                                                      : std::max(2.0 * this->MinimumDistance, 1.0);
      const cl::RadialDistributionModel m =
        HardCoreModel(this->Density, this->MinimumDistance, rMax, this->Bins);
      for (int z : zones)
      {
        models.push_back(cl::ZoneModel{ z, m });
      }
    }
    else
    {
      const Exemplar e = ReadExemplar(exemplarData);
      const cl::PatternDomain window =
        cl::PatternDomain::Rectangle(e.window[0], e.window[2], e.window[1], e.window[3]);
      cl::PairCorrelationParameters p;
      p.rMax = this->MaximumDistance > 0.0 ? this->MaximumDistance : 10.0;
      p.bins = this->Bins;
      p.categories = e.categories;
      const auto learn = [&](int zone)
      {
        std::vector<cl::PatternPoint> mine;
        for (std::size_t k = 0; k < e.points.size(); ++k)
        {
          if (!e.zoned || e.zone[k] == zone)
          {
            mine.push_back(e.points[k]);
          }
        }
        return cl::LearnRadialDistribution(mine, window, p);
      };
      const cl::RadialDistributionModel shared =
        e.zoned ? cl::RadialDistributionModel() : learn(-1);
      for (int z : zones)
      {
        if (!e.zoned)
        {
          models.push_back(cl::ZoneModel{ z, shared });
        }
        else if (std::find(e.zone.begin(), e.zone.end(), z) != e.zone.end())
        {
          models.push_back(cl::ZoneModel{ z, learn(z) }); // zones without exemplar: no plants
        }
      }
    }
    cl::SynthesisParameters s;
    s.seed = this->Seed;
    s.iterations = this->Iterations;
    const cl::PatternParallelFor parallel =
      [](std::size_t begin,
        std::size_t end,
        const std::function<void(std::size_t, std::size_t)>& body)
    {
      vtkSMPTools::For(static_cast<vtkIdType>(begin),
        static_cast<vtkIdType>(end),
        1,
        [&](vtkIdType b, vtkIdType e)
        { body(static_cast<std::size_t>(b), static_cast<std::size_t>(e)); });
    };
    plants = cl::SynthesizeZones(dims[0],
      dims[1],
      spacing[0],
      spacing[1],
      origin[0] - 0.5 * spacing[0],
      origin[1] - 0.5 * spacing[1],
      labels.data(),
      models,
      s,
      parallel);
    this->UpdateProgress(0.9);
  }
  catch (const std::invalid_argument& x)
  {
    vtkErrorMacro(<< "plant placement: " << x.what());
    return 0;
  }

  vtkDataArray* elevation = image->GetPointData()->GetArray("Elevation");
  const vtkIdType count = static_cast<vtkIdType>(plants.points.size());
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(count);
  auto species = vtkSmartPointer<vtkIntArray>::New();
  species->SetName(SpeciesName());
  species->SetNumberOfTuples(count);
  auto zone = vtkSmartPointer<vtkIntArray>::New();
  zone->SetName(ClusterIdName());
  zone->SetNumberOfTuples(count);
  auto verts = vtkSmartPointer<vtkCellArray>::New();
  std::map<int, vtkIdType> perZone;
  for (vtkIdType p = 0; p < count; ++p)
  {
    const cl::PatternPoint& q = plants.points[static_cast<std::size_t>(p)];
    points->SetPoint(p, q.x, q.y, ElevationAt(image, elevation, q.x, q.y));
    species->SetValue(p, q.category);
    zone->SetValue(p, plants.zones[static_cast<std::size_t>(p)]);
    verts->InsertNextCell(1, &p);
    ++perZone[plants.zones[static_cast<std::size_t>(p)]];
  }
  output->SetPoints(points);
  output->SetVerts(verts);
  output->GetPointData()->AddArray(species);
  output->GetPointData()->AddArray(zone);
  auto zoneIds = vtkSmartPointer<vtkIntArray>::New();
  zoneIds->SetName("PlantZones");
  auto zoneCounts = vtkSmartPointer<vtkIntArray>::New();
  zoneCounts->SetName("PlantCounts");
  for (int z : zones)
  {
    zoneIds->InsertNextValue(z);
    zoneCounts->InsertNextValue(static_cast<int>(perZone[z]));
  }
  output->GetFieldData()->AddArray(zoneIds);
  output->GetFieldData()->AddArray(zoneCounts);
  return 1;
}

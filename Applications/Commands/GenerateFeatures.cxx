// `terroir generate features OUT --curves FILE`: Weiss (2015)'s feature curves and diffusion
// solver (vtkTerroirFeatureCurveTerrain). The curves come from GeoJSON or a .vtp; the format is
// in Documentation/TerrainGeneration.md ("Feature curves"):
//   a FeatureCollection of LineString features (coordinates in metres, in the output grid's
//   world frame: without --base the first grid point is at 0, 0); per feature, `properties`
//   give each value either as one number (every vertex) or as an array of one number per
//   vertex: elevation (m; else the coordinates' third value), plateau_width (m), slope_left,
//   slope_right (degrees, > 0 falls away from the curve), slope_left_width, slope_right_width
//   (m), envelope_left, envelope_right (m beyond the slope, < 0 unbounded), constrain_elevation
//   (true/false or 1/0); slope, slope_width and envelope set both sides (the one-sided keys
//   win). Other properties are ignored.
#include "TerroirCommands.h"

#include "TerroirApp.h"
#include "TerroirCommandSupport.h"

#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkXMLPolyDataReader.h"

#include "TerroirSafeOutput.h"
#include "vtkTerroirFeatureCurveTerrain.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <string>
#include <sys/stat.h>
#include <vector>

namespace terroir
{
namespace app
{
namespace
{

/// The point arrays of vtkTerroirFeatureCurveTerrain and their GeoJSON keys; `both` is the
/// two-sided shorthand key, `fallback` the value when nothing is given.
struct CurveKey
{
  const char* array;
  const char* key;
  const char* both;
  double fallback;
};
const CurveKey kKeys[] = {
  { "PlateauWidth", "plateau_width", nullptr, 0.0 },
  { "SlopeLeft", "slope_left", "slope", 0.0 },
  { "SlopeRight", "slope_right", "slope", 0.0 },
  { "SlopeLeftWidth", "slope_left_width", "slope_width", 0.0 },
  { "SlopeRightWidth", "slope_right_width", "slope_width", 0.0 },
  { "EnvelopeLeft", "envelope_left", "envelope", -1.0 },
  { "EnvelopeRight", "envelope_right", "envelope", -1.0 },
  { "ConstrainElevation", "constrain_elevation", nullptr, 1.0 },
};

/// One number of a property (a number or a boolean).
bool Number(const nlohmann::json& v, double& out)
{
  if (v.is_boolean())
  {
    out = v.get<bool>() ? 1.0 : 0.0;
    return true;
  }
  if (v.is_number())
  {
    out = v.get<double>();
    return std::isfinite(out);
  }
  return false;
}

/// The curves of a GeoJSON file as polydata with the filter's point arrays; throws Failure
/// naming the file and the feature for anything it cannot use.
vtkSmartPointer<vtkPolyData> ReadGeoJSONCurves(const std::string& path)
{
  std::ifstream in(path);
  if (!in)
  {
    throw Failure(path + ": cannot be read");
  }
  nlohmann::json j;
  try
  {
    in >> j;
  }
  catch (const std::exception& e)
  {
    throw Failure(path + ": not JSON (" + std::string(e.what()) + ")");
  }
  if (!j.is_object() || j.value("type", "") != "FeatureCollection" || !j.contains("features") ||
    !j["features"].is_array())
  {
    throw Failure(path + ": expected a GeoJSON FeatureCollection of LineString features");
  }
  auto curves = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkCellArray> lines;
  vtkNew<vtkDoubleArray> elevation;
  elevation->SetName("Elevation");
  std::vector<vtkSmartPointer<vtkDoubleArray>> arrays;
  for (const CurveKey& k : kKeys)
  {
    auto a = vtkSmartPointer<vtkDoubleArray>::New();
    a->SetName(k.array);
    arrays.push_back(a);
  }
  int index = 0;
  for (const nlohmann::json& feature : j["features"])
  {
    const std::string where = path + ": feature " + std::to_string(index++);
    if (!feature.is_object() || !feature.contains("geometry") || !feature["geometry"].is_object() ||
      feature["geometry"].value("type", "") != "LineString" ||
      !feature["geometry"].contains("coordinates") ||
      !feature["geometry"]["coordinates"].is_array())
    {
      throw Failure(where + ": not a LineString feature");
    }
    const nlohmann::json& coordinates = feature["geometry"]["coordinates"];
    const std::size_t n = coordinates.size();
    if (n < 2)
    {
      throw Failure(where + ": a curve needs at least two points");
    }
    const nlohmann::json properties =
      feature.contains("properties") && feature["properties"].is_object()
      ? feature["properties"]
      : nlohmann::json::object();
    // The value of `key` at vertex v: a number for every vertex, or an array of n numbers.
    auto value = [&](const char* key, std::size_t v, double& out) -> bool
    {
      if (!key || !properties.contains(key))
      {
        return false;
      }
      const nlohmann::json& p = properties[key];
      if (p.is_array())
      {
        if (p.size() != n)
        {
          throw Failure(where + ": '" + key + "' has " + std::to_string(p.size()) + " values for " +
            std::to_string(n) + " points");
        }
        if (!Number(p[v], out))
        {
          throw Failure(
            where + ": '" + key + "' value " + std::to_string(v) + " is not a finite number");
        }
        return true;
      }
      if (!Number(p, out))
      {
        throw Failure(where + ": '" + key + "' is not a finite number or an array of them");
      }
      return true;
    };
    lines->InsertNextCell(static_cast<int>(n));
    for (std::size_t v = 0; v < n; ++v)
    {
      const nlohmann::json& c = coordinates[v];
      double xyz[3] = { 0.0, 0.0, 0.0 };
      if (!c.is_array() || c.size() < 2 || !Number(c[0], xyz[0]) || !Number(c[1], xyz[1]) ||
        (c.size() > 2 && !Number(c[2], xyz[2])))
      {
        throw Failure(where + ": coordinate " + std::to_string(v) + " is not [x, y] or [x, y, z]");
      }
      double z = 0.0;
      if (!value("elevation", v, z))
      {
        if (c.size() < 3)
        {
          throw Failure(where + ": no 'elevation' property and no third coordinate");
        }
        z = xyz[2];
      }
      lines->InsertCellPoint(points->InsertNextPoint(xyz[0], xyz[1], 0.0));
      elevation->InsertNextValue(z);
      for (std::size_t a = 0; a < arrays.size(); ++a)
      {
        double x = kKeys[a].fallback;
        if (!value(kKeys[a].key, v, x))
        {
          value(kKeys[a].both, v, x);
        }
        arrays[a]->InsertNextValue(x);
      }
    }
  }
  if (index == 0)
  {
    throw Failure(path + ": no LineString features");
  }
  curves->SetPoints(points);
  curves->SetLines(lines);
  curves->GetPointData()->AddArray(elevation);
  for (auto& a : arrays)
  {
    curves->GetPointData()->AddArray(a);
  }
  return curves;
}

/// The curves of a .vtp file (lines with the filter's point arrays).
vtkSmartPointer<vtkPolyData> ReadVTPCurves(const std::string& path)
{
  struct stat st;
  if (stat(path.c_str(), &st) != 0)
  {
    throw Failure(path + ": cannot be read");
  }
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkPolyData* pd = reader->GetOutput();
  TakeLastVTKError();
  if (reader->GetErrorCode() != 0 || !pd || pd->GetNumberOfLines() == 0)
  {
    throw Failure(path + ": not a VTK polydata file with lines");
  }
  auto copy = vtkSmartPointer<vtkPolyData>::New();
  copy->ShallowCopy(pd);
  return copy;
}

} // namespace

vtkSmartPointer<vtkPolyData> ReadFeatureCurves(const std::string& path)
{
  vtkSmartPointer<vtkPolyData> curves =
    HasExtension(path, ".vtp") ? ReadVTPCurves(path) : ReadGeoJSONCurves(path);
  const std::string bad = vtkTerroirFeatureCurveTerrain::CheckCurves(curves);
  if (!bad.empty())
  {
    throw Failure(path + ": " + bad);
  }
  return curves;
}

int CommandGenerateFeatures(const CommandLine& c)
{
  const auto& g = c.Generate;
  const auto& f = g.Features;
  std::vector<std::string> outputs{ c.Output };
  if (!f.SaveCurves.empty())
  {
    outputs.push_back(f.SaveCurves);
  }
  CheckWritable(outputs, c.Overwrite);
  vtkSmartPointer<vtkPolyData> curves = ReadFeatureCurves(f.Curves);
  vtkNew<vtkTerroirFeatureCurveTerrain> filter;
  filter->SetCurvesData(curves);
  filter->SetBackend(ParseBackend(c.Backend));
  filter->SetTolerance(f.Tolerance);
  filter->SetMaximumCycles(f.MaximumCycles);
  vtkSmartPointer<vtkImageData> base;
  if (!f.Base.empty())
  {
    base = ReadTerrain(f.Base, c.AllowNetwork, c.ZUnit);
    filter->SetBaseData(base);
  }
  else
  {
    filter->SetDimensions(g.Width, g.Height);
    filter->SetSpacing(g.Spacing);
    filter->SetBaseElevation(f.BaseElevation);
  }
  const double start = Now();
  UpdateOrThrow(filter, "feature curves");
  const double seconds = Now() - start;
  vtkImageData* terrain = filter->GetOutput();
  HoldCommits();
  try
  {
    WriteStageResult(terrain, "Elevation", c.Output, c.Overwrite);
    if (!f.SaveCurves.empty())
    {
      WriteVTP(curves, f.SaveCurves);
    }
  }
  catch (...)
  {
    DiscardHeldCommits();
    throw;
  }
  std::string error;
  if (!ReleaseHeldCommits(error))
  {
    throw Failure(error);
  }
  int dims[3];
  terrain->GetDimensions(dims);
  double range[2];
  terrain->GetPointData()->GetArray("Elevation")->GetRange(range, 0);
  std::printf("features %d x %d: %lld curves, %d V-cycles on %d levels (%s, %.2f s), last "
              "change %.2g m, heights %.1f to %.1f m\n",
    dims[0],
    dims[1],
    static_cast<long long>(curves->GetNumberOfLines()),
    filter->GetLastCycles(),
    filter->GetLastLevels(),
    filter->GetLastBackend() == 2 ? "GPU" : "CPU",
    seconds,
    filter->GetLastChange(),
    range[0],
    range[1]);
  return 0;
}

} // namespace app
} // namespace terroir

// Feature-curve scenes shared by the pipeline, determinism and GPU tests of
// vtkTerroirFeatureCurveTerrain: polydata curves with the point arrays the filter reads.
#ifndef TerroirFeatureCurveScenes_h
#define TerroirFeatureCurveScenes_h

#include "vtkCellArray.h"
#include "vtkDoubleArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <initializer_list>
#include <string>
#include <vector>

namespace terroir_test
{

/// One control point: x, y (m), elevation (m), plateau width (m), slope angle (degrees, both
/// sides), slope width (m, both sides), envelope (m, both sides; < 0 unbounded).
struct CurvePoint
{
  double x, y, z, plateau, angle, width, envelope;
};

/// Polydata with one polyline per curve and the arrays Elevation, PlateauWidth, SlopeLeft,
/// SlopeRight, SlopeLeftWidth, SlopeRightWidth, EnvelopeLeft, EnvelopeRight.
inline vtkSmartPointer<vtkPolyData> FeatureCurvesPolyData(
  const std::vector<std::vector<CurvePoint>>& curves)
{
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> lines;
  const char* names[] = { "Elevation",
    "PlateauWidth",
    "SlopeLeft",
    "SlopeRight",
    "SlopeLeftWidth",
    "SlopeRightWidth",
    "EnvelopeLeft",
    "EnvelopeRight" };
  std::vector<vtkSmartPointer<vtkDoubleArray>> arrays;
  for (const char* n : names)
  {
    auto a = vtkSmartPointer<vtkDoubleArray>::New();
    a->SetName(n);
    arrays.push_back(a);
  }
  for (const auto& c : curves)
  {
    lines->InsertNextCell(static_cast<int>(c.size()));
    for (const CurvePoint& p : c)
    {
      lines->InsertCellPoint(points->InsertNextPoint(p.x, p.y, 0.0));
      const double v[] = {
        p.z, p.plateau, p.angle, p.angle, p.width, p.width, p.envelope, p.envelope
      };
      for (std::size_t k = 0; k < arrays.size(); ++k)
      {
        arrays[k]->InsertNextValue(v[k]);
      }
    }
  }
  pd->SetPoints(points);
  pd->SetLines(lines);
  for (auto& a : arrays)
  {
    pd->GetPointData()->AddArray(a);
  }
  return pd;
}

/// A curved ridge and a valley on a grid of about 1300 x 1000 m: the scene of the tests.
inline vtkSmartPointer<vtkPolyData> RidgeAndValley()
{
  return FeatureCurvesPolyData({
    { { 100, 200, 300, 40, 25, 150, -1 },
      { 500, 700, 450, 60, 30, 200, -1 },
      { 1100, 600, 350, 30, 20, 150, -1 } },
    { { 150, 900, 80, 20, -15, 100, -1 }, { 1200, 850, 60, 20, -15, 100, -1 } },
  });
}

} // namespace terroir_test

#endif

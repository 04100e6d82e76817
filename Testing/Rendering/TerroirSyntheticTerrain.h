// Small synthetic terrains for the rendering tests (Testing/Rendering only).
#ifndef TerroirSyntheticTerrain_h
#define TerroirSyntheticTerrain_h

#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"

#include <functional>
#include <string>

namespace terroir
{
namespace testing
{
/// nx x ny grid, spacing d metres, origin (0, 0); `Elevation` = elevation(x, y) in metres.
inline vtkSmartPointer<vtkImageData> MakeTerrain(int nx,
  int ny,
  double d,
  const std::function<double(double, double)>& elevation)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(nx, ny, 1);
  image->SetSpacing(d, d, 1.0);
  image->SetOrigin(0.0, 0.0, 0.0);
  vtkNew<vtkFloatArray> z;
  z->SetName("Elevation");
  z->SetNumberOfTuples(static_cast<vtkIdType>(nx) * ny);
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      z->SetValue(static_cast<vtkIdType>(j) * nx + i, static_cast<float>(elevation(i * d, j * d)));
    }
  }
  image->GetPointData()->AddArray(z);
  return image;
}

/// Adds a one-component float point array `name` = value(x, y).
inline void AddField(vtkImageData* image,
  const std::string& name,
  const std::function<double(double, double)>& value)
{
  int dims[3];
  image->GetDimensions(dims);
  double d[3];
  image->GetSpacing(d);
  vtkNew<vtkFloatArray> a;
  a->SetName(name.c_str());
  a->SetNumberOfTuples(static_cast<vtkIdType>(dims[0]) * dims[1]);
  for (int j = 0; j < dims[1]; ++j)
  {
    for (int i = 0; i < dims[0]; ++i)
    {
      a->SetValue(
        static_cast<vtkIdType>(j) * dims[0] + i, static_cast<float>(value(i * d[0], j * d[1])));
    }
  }
  image->GetPointData()->AddArray(a);
}
} // namespace testing
} // namespace terroir

#endif

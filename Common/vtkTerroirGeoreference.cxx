#include "vtkTerroirGeoreference.h"

#include "vtkDataObject.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkStringArray.h"

vtkStandardNewMacro(vtkTerroirGeoreference);

namespace
{
vtkFieldData* Fields(vtkDataObject* data, bool create)
{
  if (!data)
  {
    return nullptr;
  }
  vtkFieldData* fd = data->GetFieldData();
  if (!fd && create)
  {
    vtkNew<vtkFieldData> newFd;
    data->SetFieldData(newFd);
    fd = data->GetFieldData();
  }
  return fd;
}

std::string GetString(vtkDataObject* data, const char* name)
{
  vtkFieldData* fd = Fields(data, false);
  if (!fd)
  {
    return std::string();
  }
  auto* arr = vtkStringArray::SafeDownCast(fd->GetAbstractArray(name));
  if (!arr || arr->GetNumberOfValues() < 1)
  {
    return std::string();
  }
  return arr->GetValue(0);
}

void SetString(vtkDataObject* data, const char* name, const std::string& value)
{
  vtkFieldData* fd = Fields(data, true);
  if (!fd)
  {
    return;
  }
  vtkNew<vtkStringArray> arr;
  arr->SetName(name);
  arr->InsertNextValue(value);
  fd->RemoveArray(name);
  fd->AddArray(arr);
}

vtkDoubleArray* GetDoubles(vtkDataObject* data, const char* name, vtkIdType count)
{
  vtkFieldData* fd = Fields(data, false);
  if (!fd)
  {
    return nullptr;
  }
  auto* arr = vtkDoubleArray::SafeDownCast(fd->GetAbstractArray(name));
  if (!arr || (count >= 0 && arr->GetNumberOfValues() != count))
  {
    return nullptr;
  }
  return arr;
}

void SetDoubles(vtkDataObject* data, const char* name, const double* v, int n)
{
  vtkFieldData* fd = Fields(data, true);
  if (!fd)
  {
    return;
  }
  vtkNew<vtkDoubleArray> arr;
  arr->SetName(name);
  arr->SetNumberOfValues(n);
  for (int i = 0; i < n; ++i)
  {
    arr->SetValue(i, v[i]);
  }
  fd->RemoveArray(name);
  fd->AddArray(arr);
}
} // namespace

void vtkTerroirGeoreference::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}

std::string vtkTerroirGeoreference::GetCRS(vtkDataObject* data)
{
  return GetString(data, CRSName());
}

void vtkTerroirGeoreference::SetCRS(vtkDataObject* data, const std::string& wkt)
{
  SetString(data, CRSName(), wkt);
}

bool vtkTerroirGeoreference::GetGeoTransform(vtkDataObject* data, double gt[6])
{
  vtkDoubleArray* arr = GetDoubles(data, GeoTransformName(), 6);
  if (!arr)
  {
    return false;
  }
  for (int i = 0; i < 6; ++i)
  {
    gt[i] = arr->GetValue(i);
  }
  return true;
}

void vtkTerroirGeoreference::SetGeoTransform(vtkDataObject* data, const double gt[6])
{
  SetDoubles(data, GeoTransformName(), gt, 6);
}

bool vtkTerroirGeoreference::GetCenterLatLon(vtkDataObject* data, double latLon[2])
{
  vtkDoubleArray* arr = GetDoubles(data, CenterLatLonName(), 2);
  if (!arr)
  {
    return false;
  }
  latLon[0] = arr->GetValue(0);
  latLon[1] = arr->GetValue(1);
  return true;
}

void vtkTerroirGeoreference::SetCenterLatLon(vtkDataObject* data, double lat, double lon)
{
  const double v[2] = { lat, lon };
  SetDoubles(data, CenterLatLonName(), v, 2);
}

double vtkTerroirGeoreference::GetMeridianConvergence(vtkDataObject* data)
{
  vtkDoubleArray* arr = GetDoubles(data, MeridianConvergenceName(), 1);
  return arr ? arr->GetValue(0) : 0.0;
}

bool vtkTerroirGeoreference::HasMeridianConvergence(vtkDataObject* data)
{
  return GetDoubles(data, MeridianConvergenceName(), 1) != nullptr;
}

void vtkTerroirGeoreference::SetMeridianConvergence(vtkDataObject* data, double gammaDegrees)
{
  SetDoubles(data, MeridianConvergenceName(), &gammaDegrees, 1);
}

vtkDoubleArray* vtkTerroirGeoreference::GetRowSpacing(vtkDataObject* data)
{
  vtkDoubleArray* arr = GetDoubles(data, RowSpacingName(), -1);
  if (!arr || arr->GetNumberOfComponents() != 2)
  {
    return nullptr;
  }
  return arr;
}

void vtkTerroirGeoreference::SetRowSpacing(vtkDataObject* data, vtkDoubleArray* rowSpacing)
{
  vtkFieldData* fd = Fields(data, true);
  if (!fd)
  {
    return;
  }
  fd->RemoveArray(RowSpacingName());
  if (rowSpacing)
  {
    rowSpacing->SetName(RowSpacingName());
    fd->AddArray(rowSpacing);
  }
}

std::string vtkTerroirGeoreference::GetSourceFile(vtkDataObject* data)
{
  return GetString(data, SourceFileName());
}

void vtkTerroirGeoreference::SetSourceFile(vtkDataObject* data, const std::string& path)
{
  SetString(data, SourceFileName(), path);
}

void vtkTerroirGeoreference::Copy(vtkDataObject* from, vtkDataObject* to)
{
  vtkFieldData* src = Fields(from, false);
  if (!src || !to)
  {
    return;
  }
  const char* names[] = { CRSName(),
    GeoTransformName(),
    CenterLatLonName(),
    MeridianConvergenceName(),
    RowSpacingName(),
    SourceFileName() };
  vtkFieldData* dst = Fields(to, true);
  for (const char* name : names)
  {
    if (vtkAbstractArray* arr = src->GetAbstractArray(name))
    {
      dst->RemoveArray(name);
      dst->AddArray(arr);
    }
  }
}

bool vtkTerroirGeoreference::HasGeoreference(vtkDataObject* data)
{
  double ll[2];
  return !GetCRS(data).empty() || GetCenterLatLon(data, ll);
}

// TerroirGPUCheckDEMToVTI IN OUT.vti: writes the DEM that the tests' terroir_test::ReadDEM makes
// of IN (vtkTerroirDEMReader, GDAL) as VTK XML image data, reads OUT back with
// vtkXMLImageDataReader and fails unless the two are identical: grid, every point, cell and
// field data array bit for bit (the georeference travels in field data), names, units.
// Scripts/gpu-check.sh runs it to give terroir-gpu-check (no GDAL) the GPU tests' DEMs.
#include "TerroirFilterTestUtilities.h"

#include "vtkAbstractArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkMatrix3x3.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkStringArray.h"
#include "vtkXMLImageDataReader.h"
#include "vtkXMLImageDataWriter.h"

#include <cstring>
#include <iostream>
#include <sstream>
#include <string>

namespace
{

std::string Units(vtkAbstractArray* a)
{
  vtkInformation* info = a->GetInformation();
  return (info && info->Has(vtkDataArray::UNITS_LABEL())) ? info->Get(vtkDataArray::UNITS_LABEL())
                                                          : "";
}

/// Empty when `a` and `b` hold the same array; else what differs.
std::string CompareArrays(vtkAbstractArray* a, vtkAbstractArray* b)
{
  const std::string name = a->GetName() ? a->GetName() : "(unnamed)";
  if (!b)
  {
    return name + ": missing after the round trip";
  }
  if (std::string(b->GetName() ? b->GetName() : "(unnamed)") != name)
  {
    return name + ": read back as " + (b->GetName() ? b->GetName() : "(unnamed)");
  }
  if (a->GetDataType() != b->GetDataType() ||
    a->GetNumberOfComponents() != b->GetNumberOfComponents() ||
    a->GetNumberOfTuples() != b->GetNumberOfTuples())
  {
    return name + ": type, components or tuples differ";
  }
  if (Units(a) != Units(b))
  {
    return name + ": units '" + Units(a) + "' read back as '" + Units(b) + "'";
  }
  for (int c = 0; c < a->GetNumberOfComponents(); ++c)
  {
    const char* ca = a->GetComponentName(c);
    const char* cb = b->GetComponentName(c);
    if (std::string(ca ? ca : "") != std::string(cb ? cb : ""))
    {
      return name + ": component names differ";
    }
  }
  if (auto* sa = vtkStringArray::SafeDownCast(a))
  {
    auto* sb = vtkStringArray::SafeDownCast(b);
    for (vtkIdType k = 0; k < sa->GetNumberOfValues(); ++k)
    {
      if (sa->GetValue(k) != sb->GetValue(k))
      {
        return name + ": string " + std::to_string(k) + " differs";
      }
    }
    return "";
  }
  auto* da = vtkDataArray::SafeDownCast(a);
  auto* db = vtkDataArray::SafeDownCast(b);
  if (!da || !db)
  {
    return name + ": neither a data array nor a string array";
  }
  const std::size_t bytes = static_cast<std::size_t>(da->GetNumberOfValues()) *
    static_cast<std::size_t>(da->GetDataTypeSize());
  if (bytes && std::memcmp(da->GetVoidPointer(0), db->GetVoidPointer(0), bytes) != 0)
  {
    return name + ": values differ";
  }
  return "";
}

/// Compares every array of `a` with the array of the same index in `b`.
std::string CompareFields(const char* what, vtkFieldData* a, vtkFieldData* b)
{
  if (a->GetNumberOfArrays() != b->GetNumberOfArrays())
  {
    return std::string(what) + ": " + std::to_string(a->GetNumberOfArrays()) +
      " arrays, read back " + std::to_string(b->GetNumberOfArrays());
  }
  for (int i = 0; i < a->GetNumberOfArrays(); ++i)
  {
    const std::string d = CompareArrays(a->GetAbstractArray(i), b->GetAbstractArray(i));
    if (!d.empty())
    {
      return std::string(what) + " array " + d;
    }
  }
  return "";
}

std::string CompareImages(vtkImageData* a, vtkImageData* b)
{
  int ea[6], eb[6];
  a->GetExtent(ea);
  b->GetExtent(eb);
  double oa[3], ob[3], sa[3], sb[3];
  a->GetOrigin(oa);
  b->GetOrigin(ob);
  a->GetSpacing(sa);
  b->GetSpacing(sb);
  for (int i = 0; i < 6; ++i)
  {
    if (ea[i] != eb[i])
    {
      return "extents differ";
    }
  }
  for (int i = 0; i < 3; ++i)
  {
    if (oa[i] != ob[i] || sa[i] != sb[i])
    {
      return "origin or spacing differ";
    }
  }
  for (int i = 0; i < 9; ++i)
  {
    if (a->GetDirectionMatrix()->GetData()[i] != b->GetDirectionMatrix()->GetData()[i])
    {
      return "direction matrices differ";
    }
  }
  vtkDataArray* scalarsA = a->GetPointData()->GetScalars();
  vtkDataArray* scalarsB = b->GetPointData()->GetScalars();
  const std::string nameA = scalarsA && scalarsA->GetName() ? scalarsA->GetName() : "";
  const std::string nameB = scalarsB && scalarsB->GetName() ? scalarsB->GetName() : "";
  if (nameA != nameB)
  {
    return "active point scalars '" + nameA + "' read back as '" + nameB + "'";
  }
  std::string d = CompareFields("point data", a->GetPointData(), b->GetPointData());
  if (d.empty())
  {
    d = CompareFields("cell data", a->GetCellData(), b->GetCellData());
  }
  if (d.empty())
  {
    d = CompareFields("field data", a->GetFieldData(), b->GetFieldData());
  }
  return d;
}

std::string ArrayList(vtkFieldData* fd)
{
  std::ostringstream os;
  for (int i = 0; i < fd->GetNumberOfArrays(); ++i)
  {
    vtkAbstractArray* a = fd->GetAbstractArray(i);
    os << (i ? ", " : "") << (a->GetName() ? a->GetName() : "(unnamed)") << " ("
       << a->GetDataTypeAsString() << " x" << a->GetNumberOfComponents();
    const std::string units = Units(a);
    os << (units.empty() ? "" : ", " + units) << ")";
  }
  return os.str();
}

} // namespace

int main(int argc, char* argv[])
{
  if (argc != 3)
  {
    std::cerr << "usage: TerroirGPUCheckDEMToVTI IN OUT.vti\n";
    return 2;
  }
  const std::string in = argv[1];
  const std::string out = argv[2];
  vtkSmartPointer<vtkImageData> dem = terroir_test::ReadDEM(in);
  if (!dem)
  {
    std::cerr << "TerroirGPUCheckDEMToVTI: error: " << in << ": ReadDEM failed\n";
    return 1;
  }
  // Raw appended binary: the bundle's xz compresses it better than zlib would.
  vtkNew<vtkXMLImageDataWriter> writer;
  writer->SetInputData(dem);
  writer->SetFileName(out.c_str());
  writer->SetDataModeToAppended();
  writer->EncodeAppendedDataOff();
  writer->SetCompressorTypeToNone();
  if (writer->Write() != 1)
  {
    std::cerr << "TerroirGPUCheckDEMToVTI: error: " << out << ": cannot write\n";
    return 1;
  }
  vtkNew<vtkXMLImageDataReader> reader;
  reader->SetFileName(out.c_str());
  reader->Update();
  vtkImageData* back = reader->GetOutput();
  const std::string difference = back ? CompareImages(dem, back) : "cannot read it back";
  if (!difference.empty())
  {
    std::cerr << "TerroirGPUCheckDEMToVTI: error: " << out << " is not " << in
              << " as ReadDEM reads it: " << difference << "\n";
    return 1;
  }
  int dims[3];
  dem->GetDimensions(dims);
  std::cout << out << ": " << dims[0] << " x " << dims[1] << ", identical to ReadDEM(" << in
            << ") after the round trip; point data: " << ArrayList(dem->GetPointData())
            << "; field data: " << ArrayList(dem->GetFieldData()) << "\n";
  return 0;
}

// libFuzzer harness: vtkTerroirVectorRasterizer on any vector file OGR may be handed. The input
// is a few option bytes, then the bytes of the vector file itself, which the harness writes into
// GDAL's memory file system (/vsimem/, which the rasterizer accepts as a local path) and burns
// onto a small synthetic terrain.
// Layout (bytes past the end read as zero; MakeVectorRasterizerSeeds.py writes seeds):
//   u8 flags   bit0 AllTouched, bit1 burn the numeric attribute "v", bit2 geographic terrain
//              (WGS 84 lon/lat grid at origin (0, 0)) instead of UTM zone 11N, bit3 attribute
//              filter "v > 0", bit4 LayerName "rivers"
//   u8 burn    % 4: BurnValue 1, 7, 0.5, -3 (the first two give an unsigned char mask)
//   u8 nx, ny  % 32 + 1
//   rest       the vector file (GeoJSON, TopoJSON, ESRI JSON, GML, KML, ... as
//              OGR recognises it from its content and the .json name)
// Aborts (__builtin_trap) when an invariant breaks: a refusal is one line "<file>: <problem>"
// with an empty output; a success keeps the terrain's size and Elevation, adds `Mask` with one
// value per cell, unsigned char exactly when documented, holding only the burn value and 0 (or
// NaN) without an attribute, finite values on covered cells, and NumberOfCoveredCells equal to
// the cells it marks.
#include "FuzzCheck.h"
#include "FuzzQuietGDAL.h"
#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkLogger.h"
#include "vtkNew.h"
#include "vtkObject.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirVectorRasterizer.h"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <cpl_vsi.h>
#include <gdal.h>

#include <cmath>
#include <cstdint>
#include <string>

namespace
{
using terroir_fuzz::Check;

const char* const kUTM11N =
  "PROJCS[\"WGS 84 / UTM zone 11N\",GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\","
  "6378137,298.257223563]],PRIMEM[\"Greenwich\",0],UNIT[\"degree\",0.0174532925199433]],"
  "PROJECTION[\"Transverse_Mercator\"],PARAMETER[\"latitude_of_origin\",0],"
  "PARAMETER[\"central_meridian\",-117],PARAMETER[\"scale_factor\",0.9996],"
  "PARAMETER[\"false_easting\",500000],PARAMETER[\"false_northing\",0],UNIT[\"metre\",1],"
  "AXIS[\"Easting\",EAST],AXIS[\"Northing\",NORTH],AUTHORITY[\"EPSG\",\"32611\"]]";
const char* const kWGS84 =
  "GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\",6378137,298.257223563]],"
  "PRIMEM[\"Greenwich\",0],UNIT[\"degree\",0.0174532925199433],AUTHORITY[\"EPSG\",\"4326\"]]";
const float kElevation = 1900.0f;

/// nx x ny cells: 10 m cells of UTM 11N with the north-west corner at (500000, 4360000), or
/// 0.001° cells of WGS 84 with the north-west corner at (-117, 36), as vtkTerroirDEMReader
/// would give them.
vtkSmartPointer<vtkImageData> Terrain(int nx, int ny, bool geographic)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(nx, ny, 1);
  vtkNew<vtkFloatArray> z;
  z->SetName("Elevation");
  z->SetNumberOfTuples(static_cast<vtkIdType>(nx) * ny);
  z->FillValue(kElevation);
  image->GetPointData()->AddArray(z);
  if (geographic)
  {
    const double gt[6] = { -117.0, 0.001, 0.0, 36.0, 0.0, -0.001 };
    image->SetSpacing(90.0, 111.0, 1.0);
    image->SetOrigin(0.0, 0.0, 0.0);
    vtkTerroirGeoreference::SetCRS(image, kWGS84);
    vtkTerroirGeoreference::SetGeoTransform(image, gt);
  }
  else
  {
    const double gt[6] = { 500000.0, 10.0, 0.0, 4360000.0, 0.0, -10.0 };
    image->SetSpacing(10.0, 10.0, 1.0);
    image->SetOrigin(500005.0, 4360000.0 - 10.0 * ny + 5.0, 0.0);
    vtkTerroirGeoreference::SetCRS(image, kUTM11N);
    vtkTerroirGeoreference::SetGeoTransform(image, gt);
  }
  return image;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  static const bool quiet = terroir_fuzz::QuietGDALAndVTK();
  (void)quiet;
  static const char* const kFile = "/vsimem/terroir_fuzz.json";
  static const double kBurn[4] = { 1.0, 7.0, 0.5, -3.0 };
  auto byte = [&](std::size_t k) -> int { return k < size ? data[k] : 0; };
  const int flags = byte(0);
  const double burn = kBurn[byte(1) % 4];
  const int nx = byte(2) % 32 + 1;
  const int ny = byte(3) % 32 + 1;
  const std::size_t header = 4;
  const bool useAttribute = (flags & 2) != 0;

  VSILFILE* f = VSIFOpenL(kFile, "wb");
  Check(f != nullptr);
  if (size > header)
  {
    Check(VSIFWriteL(data + header, 1, size - header, f) == size - header);
  }
  VSIFCloseL(f);

  {
    vtkNew<vtkTerroirVectorRasterizer> rasterizer;
    rasterizer->SetInputData(Terrain(nx, ny, (flags & 4) != 0));
    rasterizer->SetFileName(kFile);
    rasterizer->SetAllTouched((flags & 1) != 0);
    rasterizer->SetBurnValue(burn);
    rasterizer->SetAttributeName(useAttribute ? "v" : "");
    rasterizer->SetAttributeFilter((flags & 8) ? "v > 0" : "");
    rasterizer->SetLayerName((flags & 16) ? "rivers" : "");
    rasterizer->Update();
    const std::string message = rasterizer->GetErrorMessage();
    vtkImageData* image = rasterizer->GetOutput();
    if (!message.empty())
    {
      Check(message.rfind(std::string(kFile) + ": ", 0) == 0);
      Check(message.find('\n') == std::string::npos);
      Check(image->GetNumberOfPoints() == 0);
    }
    else
    {
      const vtkIdType cells = static_cast<vtkIdType>(nx) * ny;
      int dims[3];
      image->GetDimensions(dims);
      Check(dims[0] == nx && dims[1] == ny && dims[2] == 1);
      vtkDataArray* z = image->GetPointData()->GetArray("Elevation");
      Check(z && z->GetNumberOfTuples() == cells);
      vtkDataArray* mask = image->GetPointData()->GetArray("Mask");
      Check(mask && mask->GetNumberOfTuples() == cells && mask->GetNumberOfComponents() == 1);
      const bool asByte = !useAttribute && burn >= 1.0;
      Check(mask->GetDataType() == (asByte ? VTK_UNSIGNED_CHAR : VTK_FLOAT));
      vtkIdType covered = 0;
      for (vtkIdType k = 0; k < cells; ++k)
      {
        Check(z->GetComponent(k, 0) == kElevation);
        const double v = mask->GetComponent(k, 0);
        const bool isCovered = asByte ? v != 0.0 : !std::isnan(v);
        covered += isCovered ? 1 : 0;
        if (!useAttribute)
        {
          Check(!isCovered || v == burn);
        }
        else if (isCovered)
        {
          // A double attribute past float's range becomes +-inf: still a value, never NaN.
          Check(!std::isnan(v));
        }
      }
      Check(covered == rasterizer->GetNumberOfCoveredCells());
      Check(rasterizer->GetNumberOfFeatures() >= 0);
    }
  }
  // The input and whatever GDAL wrote beside it (a GML reader's .gfs schema file), so that
  // every input starts from the same empty folder and a run can be repeated.
  char** files = VSIReadDir("/vsimem/");
  for (char** name = files; name && *name; ++name)
  {
    if (std::string(*name).rfind("terroir_fuzz.", 0) == 0)
    {
      VSIUnlink((std::string("/vsimem/") + *name).c_str());
    }
  }
  CSLDestroy(files);
  return 0;
}

// libFuzzer harness: vtkTerroirDEMReader's handling of what GDAL returns. The input describes
// a small raster -- size, data type, geotransform, nodata, scale and offset, unit, CRS, pixel
// values -- that the harness writes as a GeoTIFF in GDAL's memory file system through GDAL's
// own API (so every property is one GDAL can really hand back), then reads with the reader.
// Layout (little-endian; bytes past the end read as zero; MakeDEMReaderSeeds.py writes seeds):
//   u8 flags   bit0 geotransform, bit1 nodata, bit2 scale+offset, bit3 unit, bit4 CRS
//   u8 type    % 7: Byte, UInt16, Int16, UInt32, Int32, Float32, Float64
//   u8 nx, ny  % 64 + 1
//   f64 x 6    geotransform;  f64 nodata;  f64 scale;  f64 offset
//   u8 n + n bytes   unit type (n % 17)
//   u8 crs     % 3: 0 EPSG code (u16), 1 built CRS (f64 semi-major, f64 inverse flattening,
//              f64 linear unit in metres, u8 projection % 4: geographic, transverse Mercator,
//              polar stereographic, Lambert conformal conic; f64 latitude, f64 longitude of
//              origin), 2 WKT text (u16 length % 1024, then the text)
//   rest       pixel values, repeated to fill the raster
// Aborts (__builtin_trap) when an invariant breaks: a refusal is one line "<file>: <problem>"
// with an empty output; a success has the raster's size, positive finite spacings (per row
// too), a finite origin, valid cells exactly where elevations are finite and at most 1e30 m,
// at least one of them, and a centre and convergence that are finite numbers.
#include "FuzzCheck.h"
#include "FuzzQuietGDAL.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkImageData.h"
#include "vtkLogger.h"
#include "vtkNew.h"
#include "vtkObject.h"
#include "vtkPointData.h"
#include "vtkTerroirDEMReader.h"
#include "vtkTerroirGeoreference.h"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_vsi.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace
{
using terroir_fuzz::Check;

/// Reads the fuzz input front to back; zeros past its end.
class Bytes
{
public:
  Bytes(const std::uint8_t* data, std::size_t size)
    : Data(data)
    , Size(size)
  {
  }
  std::uint8_t U8() { return this->Pos < this->Size ? this->Data[this->Pos++] : 0; }
  std::uint16_t U16() { return static_cast<std::uint16_t>(this->U8() | (this->U8() << 8)); }
  double F64()
  {
    std::uint64_t u = 0;
    for (int k = 0; k < 8; ++k)
    {
      u |= static_cast<std::uint64_t>(this->U8()) << (8 * k);
    }
    double d;
    std::memcpy(&d, &u, sizeof(d));
    return d;
  }
  std::string Text(std::size_t n)
  {
    std::string s;
    for (std::size_t k = 0; k < n && this->Pos < this->Size; ++k)
    {
      const char c = static_cast<char>(this->U8());
      if (c != '\0')
      {
        s.push_back(c);
      }
    }
    return s;
  }
  std::vector<std::uint8_t> Rest() const
  {
    return std::vector<std::uint8_t>(this->Data + this->Pos, this->Data + this->Size);
  }

private:
  const std::uint8_t* Data;
  std::size_t Size;
  std::size_t Pos = 0;
};

/// The WKT of the CRS the input asks for ("" when GDAL cannot make one).
std::string MakeCRS(Bytes& in)
{
  OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
  std::string wkt;
  const int mode = in.U8() % 3;
  OGRErr err = OGRERR_FAILURE;
  if (mode == 0)
  {
    err = OSRImportFromEPSG(srs, in.U16());
  }
  else if (mode == 1)
  {
    const double a = in.F64();
    const double invf = in.F64();
    const double unit = in.F64();
    const int projection = in.U8() % 4;
    const double lat = in.F64();
    const double lon = in.F64();
    err = OSRSetGeogCS(srs,
      "fuzz",
      "fuzz datum",
      "fuzz ellipsoid",
      a,
      invf,
      "Greenwich",
      0.0,
      "degree",
      0.0174532925199433);
    if (err == OGRERR_NONE && projection > 0)
    {
      OSRSetProjCS(srs, "fuzz projection");
      err = projection == 1 ? OSRSetTM(srs, lat, lon, 0.9996, 500000.0, 0.0)
        : projection == 2   ? OSRSetPS(srs, lat, lon, 1.0, 0.0, 0.0)
                            : OSRSetLCC(srs, lat, lat + 1.0, lat, lon, 0.0, 0.0);
      if (err == OGRERR_NONE)
      {
        err = OSRSetLinearUnits(srs, "fuzz unit", unit);
      }
    }
  }
  else
  {
    const std::string text = in.Text(in.U16() % 1024);
    char* p = const_cast<char*>(text.c_str());
    err = OSRImportFromWkt(srs, &p);
  }
  char* out = nullptr;
  if (err == OGRERR_NONE && OSRExportToWkt(srs, &out) == OGRERR_NONE && out)
  {
    wkt = out;
  }
  CPLFree(out);
  OSRDestroySpatialReference(srs);
  return wkt;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  static const bool quiet = terroir_fuzz::QuietGDALAndVTK();
  (void)quiet;
  static const char* const kFile = "/vsimem/terroir_fuzz.tif";
  static const GDALDataType kTypes[7] = {
    GDT_Byte, GDT_UInt16, GDT_Int16, GDT_UInt32, GDT_Int32, GDT_Float32, GDT_Float64
  };
  Bytes in(data, size);
  const int flags = in.U8();
  const GDALDataType type = kTypes[in.U8() % 7];
  const int nx = in.U8() % 64 + 1;
  const int ny = in.U8() % 64 + 1;
  double gt[6];
  for (double& g : gt)
  {
    g = in.F64();
  }
  const double nodata = in.F64();
  const double scale = in.F64();
  const double offset = in.F64();
  const std::string unit = in.Text(in.U8() % 17);
  const std::string wkt = (flags & 16) ? MakeCRS(in) : std::string();
  std::vector<std::uint8_t> pixels = in.Rest();

  GDALDatasetH ds = GDALCreate(GDALGetDriverByName("GTiff"), kFile, nx, ny, 1, type, nullptr);
  Check(ds != nullptr);
  if (flags & 1)
  {
    GDALSetGeoTransform(ds, gt);
  }
  if (!wkt.empty())
  {
    GDALSetProjection(ds, wkt.c_str());
  }
  GDALRasterBandH band = GDALGetRasterBand(ds, 1);
  if (flags & 2)
  {
    GDALSetRasterNoDataValue(band, nodata);
  }
  if (flags & 4)
  {
    GDALSetRasterScale(band, scale);
    GDALSetRasterOffset(band, offset);
  }
  if (flags & 8)
  {
    GDALSetRasterUnitType(band, unit.c_str());
  }
  const std::size_t bytes =
    static_cast<std::size_t>(nx) * ny * static_cast<std::size_t>(GDALGetDataTypeSizeBytes(type));
  std::vector<std::uint8_t> raster(bytes, 0);
  for (std::size_t k = 0; k < bytes && !pixels.empty(); ++k)
  {
    raster[k] = pixels[k % pixels.size()];
  }
  Check(GDALRasterIO(band, GF_Write, 0, 0, nx, ny, raster.data(), nx, ny, type, 0, 0) == CE_None);
  GDALClose(ds);

  {
    vtkNew<vtkTerroirDEMReader> reader;
    reader->SetFileName(kFile);
    reader->Update();
    const std::string message = reader->GetErrorMessage();
    vtkImageData* image = reader->GetOutput();
    if (!message.empty())
    {
      Check(message.rfind(std::string(kFile) + ": ", 0) == 0);
      Check(message.find('\n') == std::string::npos);
      Check(image->GetNumberOfPoints() == 0);
    }
    else
    {
      int dims[3];
      image->GetDimensions(dims);
      Check(dims[0] == nx && dims[1] == ny && dims[2] == 1);
      double spacing[3], origin[3];
      image->GetSpacing(spacing);
      image->GetOrigin(origin);
      Check(
        std::isfinite(spacing[0]) && spacing[0] > 0 && std::isfinite(spacing[1]) && spacing[1] > 0);
      Check(std::isfinite(origin[0]) && std::isfinite(origin[1]));
      vtkDataArray* z = image->GetPointData()->GetArray("Elevation");
      Check(z && z->GetDataType() == VTK_FLOAT && z->GetNumberOfTuples() == nx * ny);
      vtkDataArray* mask = image->GetPointData()->GetArray("vtkValidPointMask");
      Check(!mask || mask->GetNumberOfTuples() == nx * ny);
      vtkIdType valid = 0;
      for (vtkIdType k = 0; k < nx * ny; ++k)
      {
        const double h = z->GetComponent(k, 0);
        const bool isValid = !mask || mask->GetComponent(k, 0) != 0.0;
        Check(isValid == (std::isfinite(h) && std::fabs(h) <= 1e30));
        valid += isValid ? 1 : 0;
      }
      Check(valid > 0);
      if (vtkDoubleArray* rows = vtkTerroirGeoreference::GetRowSpacing(image))
      {
        Check(rows->GetNumberOfTuples() == ny && rows->GetNumberOfComponents() == 2);
        for (vtkIdType j = 0; j < ny; ++j)
        {
          for (int c = 0; c < 2; ++c)
          {
            const double s = rows->GetComponent(j, c);
            Check(std::isfinite(s) && s > 0);
          }
        }
      }
      double latLon[2];
      if (vtkTerroirGeoreference::GetCenterLatLon(image, latLon))
      {
        Check(std::fabs(latLon[0]) <= 90.0 && std::isfinite(latLon[1]));
      }
      Check(std::isfinite(vtkTerroirGeoreference::GetMeridianConvergence(image)));
    }
  }
  VSIUnlink(kFile);
  return 0;
}

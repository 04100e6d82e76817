#include "vtkTerroirGeoTIFFWriter.h"

#include "TerroirSafeOutput.h"
#include "vtkDataArray.h"
#include "vtkErrorCode.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkTerroirGDALPrivate.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirIOPrivate.h"
#include "vtkUnsignedCharArray.h"

#include <gdal.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

vtkStandardNewMacro(vtkTerroirGeoTIFFWriter);

vtkTerroirGeoTIFFWriter::vtkTerroirGeoTIFFWriter()
{
  GDALAllRegister();
}

vtkTerroirGeoTIFFWriter::~vtkTerroirGeoTIFFWriter() {}

void vtkTerroirGeoTIFFWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Compress: " << this->Compress << "\n";
}

void vtkTerroirGeoTIFFWriter::WriteData()
{
  vtkDataArray* array = nullptr;
  vtkImageData* input = this->ValidatedInput(array);
  if (!input)
  {
    return;
  }
  int dims[3];
  input->GetDimensions(dims);
  const int nx = dims[0];
  const int ny = dims[1];
  const int nc = array->GetNumberOfComponents();
  GDALDataType type = GDT_Int32;
  double nodata = -9999.0;
  switch (array->GetDataType())
  {
    case VTK_FLOAT:
      type = GDT_Float32;
      nodata = std::numeric_limits<double>::quiet_NaN();
      break;
    case VTK_DOUBLE:
      type = GDT_Float64;
      nodata = std::numeric_limits<double>::quiet_NaN();
      break;
    case VTK_CHAR:
    case VTK_SIGNED_CHAR:
    case VTK_UNSIGNED_CHAR:
      type = GDT_Byte;
      nodata = 255.0;
      break;
    default:
      break;
  }
  vtkDataArray* mask = input->GetPointData()->GetArray(vtkTerroirGeoreference::ValidMaskName());
  const bool floating = type == GDT_Float32 || type == GDT_Float64;

  double gt[6];
  if (!vtkTerroirGeoreference::GetGeoTransform(input, gt))
  {
    double origin[3], spacing[3];
    input->GetOrigin(origin);
    input->GetSpacing(spacing);
    int extent[6];
    input->GetExtent(extent);
    const double west = origin[0] + (extent[0] - 0.5) * spacing[0];
    const double north = origin[1] + (extent[3] + 0.5) * spacing[1];
    gt[0] = west;
    gt[1] = spacing[0];
    gt[2] = 0.0;
    gt[3] = north;
    gt[4] = 0.0;
    gt[5] = -spacing[1];
  }
  const std::string wkt = vtkTerroirGeoreference::GetCRS(input);

  GDALDriverH driver = GDALGetDriverByName("GTiff");
  if (!driver)
  {
    this->Fail("GDAL has no GTiff driver");
    return;
  }
  const std::string target = this->FileName;
  const std::string temp = terroir::TemporaryNameFor(target);
  errno = 0;
  terroir::io::detail::GDALErrorCapture capture;
  auto discard = [&](GDALDatasetH ds, const std::string& problem)
  {
    // A full disk or a file-size limit: the system's reason says more than GDAL's follow-up
    // ("Cannot initialize empty blocks"); otherwise GDAL's message, naming the target rather
    // than the temporary file.
    const int cause = errno;
    std::string reason = capture.Last();
    if (cause == ENOSPC || cause == EFBIG || cause == EDQUOT)
    {
      reason = std::strerror(cause);
    }
    for (std::size_t at = reason.find(temp); at != std::string::npos; at = reason.find(temp))
    {
      reason.replace(at, temp.size(), target);
    }
    if (ds)
    {
      GDALClose(ds);
    }
    terroir::DiscardTemporary(temp);
    this->Fail(problem + (reason.empty() ? "" : " (" + reason + ")"));
  };
  // Uncompressed by default, like gdaldem; DEFLATE (floating-point predictor for float bands)
  // on request. Multi-band rasters are band-interleaved so each band is written in one pass.
  std::vector<const char*> options = { "INTERLEAVE=BAND" };
  if (this->Compress)
  {
    options.push_back("COMPRESS=DEFLATE");
    options.push_back(floating ? "PREDICTOR=3" : "PREDICTOR=2");
  }
  if (static_cast<double>(nx) * ny * nc * 8.0 > 3.9e9)
  {
    options.push_back("BIGTIFF=YES");
  }
  options.push_back(nullptr);
  GDALDatasetH ds =
    GDALCreate(driver, temp.c_str(), nx, ny, nc, type, const_cast<char**>(options.data()));
  if (!ds)
  {
    discard(nullptr,
      "cannot create a GeoTIFF in folder '" + terroir::io::detail::DirectoryOf(target) + "'");
    return;
  }
  if (GDALSetGeoTransform(ds, gt) != CE_None)
  {
    discard(ds, "cannot set the geotransform");
    return;
  }
  if (!wkt.empty() && GDALSetProjection(ds, wkt.c_str()) != CE_None)
  {
    discard(ds, "cannot set the coordinate reference system");
    return;
  }
  // Rows go out north first (GDAL row r = image row ny-1-r) in blocks of rows; float32 arrays
  // are copied as floats, everything else through double.
  auto* floats = vtkFloatArray::SafeDownCast(array);
  auto* maskBytes = vtkUnsignedCharArray::SafeDownCast(mask);
  // Each band gets its no-data value before its pixels. GDAL's GTiff driver does not write a
  // block that holds nothing but the band's no-data value (0 while none is set) and fills it
  // with the no-data value when the file is closed: a block of zeros written before the value
  // was set came back as no-data (a flat DEM's slope, rows in shadow). Float and Int32 bands
  // always have one; byte bands only when some cell is masked (a byte value is never NaN).
  bool masked = false;
  for (vtkIdType k = 0; mask && !masked && k < static_cast<vtkIdType>(nx) * ny; ++k)
  {
    masked = mask->GetComponent(k, 0) == 0.0;
  }
  const bool hasNoData = floating || type == GDT_Int32 || masked;
  const int blockRows = std::max(1, std::min(ny, static_cast<int>((std::size_t(4) << 20) / nx)));
  std::vector<float> blockF(floats ? static_cast<std::size_t>(nx) * blockRows : 0);
  std::vector<double> blockD(floats ? 0 : static_cast<std::size_t>(nx) * blockRows);
  for (int c = 0; c < nc; ++c)
  {
    GDALRasterBandH band = GDALGetRasterBand(ds, c + 1);
    const char* componentName = array->GetComponentName(c);
    GDALSetDescription(band, componentName ? componentName : (nc == 1 ? array->GetName() : ""));
    if (hasNoData && GDALSetRasterNoDataValue(band, nodata) != CE_None)
    {
      discard(ds, "cannot set the no-data value");
      return;
    }
    for (int r0 = 0; r0 < ny; r0 += blockRows)
    {
      const int rows = std::min(blockRows, ny - r0);
      for (int r = 0; r < rows; ++r)
      {
        const vtkIdType j = ny - 1 - (r0 + r);
        const std::size_t out = static_cast<std::size_t>(r) * nx;
        if (floats)
        {
          const float* src = floats->GetPointer(0) + (j * nx) * nc + c;
          const unsigned char* m = maskBytes ? maskBytes->GetPointer(0) + j * nx : nullptr;
          const float nodataF = static_cast<float>(nodata);
          for (int i = 0; i < nx; ++i)
          {
            const float v = src[static_cast<std::size_t>(i) * nc];
            const bool valid = (!m || m[i] != 0) && !std::isnan(v);
            blockF[out + i] = valid ? v : nodataF;
          }
        }
        else
        {
          for (int i = 0; i < nx; ++i)
          {
            const vtkIdType k = j * nx + i;
            const double v = array->GetComponent(k, c);
            const bool valid = (!mask || mask->GetComponent(k, 0) != 0.0) && !std::isnan(v);
            blockD[out + i] = valid ? v : nodata;
          }
        }
      }
      CPLErr err = floats
        ? GDALRasterIO(band, GF_Write, 0, r0, nx, rows, blockF.data(), nx, rows, GDT_Float32, 0, 0)
        : GDALRasterIO(band, GF_Write, 0, r0, nx, rows, blockD.data(), nx, rows, GDT_Float64, 0, 0);
      // Write the rows out now: left in GDAL's block cache (5 % of RAM by default) they would
      // hold up to one more copy of the band in memory until the file is closed.
      if (err == CE_None)
      {
        err = GDALFlushRasterCache(band);
      }
      if (err != CE_None)
      {
        discard(ds, "write failed at row " + std::to_string(r0));
        return;
      }
    }
    this->UpdateProgress(static_cast<double>(c + 1) / nc);
  }
  GDALClose(ds);
  if (capture.Failed())
  {
    discard(nullptr, "write failed");
    return;
  }
  std::string error;
  if (!terroir::CommitTemporary(temp, target, error))
  {
    this->Fail(error);
  }
}

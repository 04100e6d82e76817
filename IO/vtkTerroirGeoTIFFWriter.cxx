#include "vtkTerroirGeoTIFFWriter.h"

#include "TerroirSafeOutput.h"
#include "vtkDataArray.h"
#include "vtkErrorCode.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
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
#include <string>
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
  const char* name = GetCompressionName(this->Compression);
  os << indent << "Compression: " << (name ? name : "?") << "\n";
  os << indent << "Tiled: " << this->Tiled << "\n";
  os << indent << "Threads: " << this->Threads << "\n";
  os << indent << "Overviews: " << this->Overviews << "\n";
}

namespace
{
const char* const CompressionNames[] = { "none", "deflate", "zstd", "lzw" };
const char* const CompressionCreationOptions[] = { nullptr,
  "COMPRESS=DEFLATE",
  "COMPRESS=ZSTD",
  "COMPRESS=LZW" };
} // namespace

const char* vtkTerroirGeoTIFFWriter::GetCompressionName(int compression)
{
  return compression >= COMPRESSION_NONE && compression <= COMPRESSION_LZW
    ? CompressionNames[compression]
    : nullptr;
}

int vtkTerroirGeoTIFFWriter::GetCompressionFromName(const char* name)
{
  for (int c = COMPRESSION_NONE; name && c <= COMPRESSION_LZW; ++c)
  {
    if (std::strcmp(name, CompressionNames[c]) == 0)
    {
      return c;
    }
  }
  return -1;
}

namespace
{
/// The GDAL band type and no-data value for an array's VTK type (Int32 and -9999 by default).
void BandTypeOf(vtkDataArray* array, GDALDataType& type, double& nodata)
{
  type = GDT_Int32;
  nodata = -9999.0;
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
}

/**
 * The image's TerroirGeoTransform, or one made from its origin, spacing and extent. The field
 * data's geotransform is the whole raster's (readers give every piece the same): for a piece
 * (an extent smaller than `whole`) its corner moves to the piece's north-west cell, so that the
 * piece's GeoTIFF lies where its cells are and the pieces mosaic (a VRT) into the whole.
 */
void GeoTransformOf(vtkImageData* input, const int whole[6], double gt[6])
{
  if (vtkTerroirGeoreference::GetGeoTransform(input, gt))
  {
    int extent[6];
    input->GetExtent(extent);
    if (whole && whole[0] <= whole[1] && whole[2] <= whole[3])
    {
      gt[0] += (extent[0] - whole[0]) * gt[1];
      // Rows go out north first: the piece's GDAL row 0 is image row extent[3], which is row
      // whole[3] - extent[3] of the whole raster's file.
      gt[3] += (whole[3] - extent[3]) * gt[5];
    }
    return;
  }
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

/// GTiff creation options, null-terminated.
/// GDAL's creation options for the writer's layout; the strings live in `storage`.
std::vector<const char*> CreationOptions(int compression,
  bool tiled,
  int threads,
  bool floating,
  int nx,
  int ny,
  int nc,
  std::vector<std::string>& storage)
{
  // Multi-band rasters are band-interleaved so each band is written in one pass.
  storage = { "INTERLEAVE=BAND" };
  if (compression != vtkTerroirGeoTIFFWriter::COMPRESSION_NONE)
  {
    storage.emplace_back(CompressionCreationOptions[compression]);
    storage.emplace_back(floating ? "PREDICTOR=3" : "PREDICTOR=2");
    if (threads != 0)
    {
      storage.push_back(
        threads < 0 ? "NUM_THREADS=ALL_CPUS" : "NUM_THREADS=" + std::to_string(threads));
    }
  }
  if (tiled)
  {
    storage.insert(storage.end(), { "TILED=YES", "BLOCKXSIZE=256", "BLOCKYSIZE=256" });
  }
  if (static_cast<double>(nx) * ny * nc * 8.0 > 3.9e9)
  {
    storage.emplace_back("BIGTIFF=YES");
  }
  std::vector<const char*> options;
  for (const std::string& o : storage)
  {
    options.push_back(o.c_str());
  }
  options.push_back(nullptr);
  return options;
}

/// Internal overviews at 2, 4, 8, ... until the smaller side is under 256 cells (none for a
/// smaller raster): AVERAGE for float bands, NEAREST for integer ones (classes). Returns the
/// problem, empty on success.
std::string BuildOverviews(GDALDatasetH ds, bool floating, int nx, int ny)
{
  std::vector<int> levels;
  for (int f = 2; std::min(nx, ny) / (f / 2) >= 256; f *= 2)
  {
    levels.push_back(f);
  }
  if (levels.empty())
  {
    return std::string();
  }
  if (GDALBuildOverviews(ds,
        floating ? "AVERAGE" : "NEAREST",
        static_cast<int>(levels.size()),
        levels.data(),
        0,
        nullptr,
        nullptr,
        nullptr) != CE_None)
  {
    return "cannot build the overviews";
  }
  return std::string();
}

/// True when the mask (may be null) marks some of the n cells invalid.
bool AnyMasked(vtkDataArray* mask, vtkIdType n)
{
  bool masked = false;
  for (vtkIdType k = 0; mask && !masked && k < n; ++k)
  {
    masked = mask->GetComponent(k, 0) == 0.0;
  }
  return masked;
}

/// The array, its mask and the grid being written, and the row blocks that carry them.
struct BandSource
{
  vtkDataArray* Array = nullptr;
  vtkFloatArray* Floats = nullptr; // Array when it holds float32, else null
  vtkDataArray* Mask = nullptr;
  vtkUnsignedCharArray* MaskBytes = nullptr; // Mask when it holds bytes, else null
  int NX = 0;
  int NY = 0;
  int NC = 0;
  double NoData = 0.0;
  bool HasNoData = false;
  int BlockRows = 1;
  std::vector<float> BlockF;
  std::vector<double> BlockD;
};

/// Fills the block with component c of image rows ny-1-r0 ... (north first), `rows` of them;
/// masked and NaN cells get the no-data value.
void FillBlock(BandSource& s, int c, int r0, int rows)
{
  const int nx = s.NX;
  const int nc = s.NC;
  for (int r = 0; r < rows; ++r)
  {
    const vtkIdType j = s.NY - 1 - (r0 + r);
    const std::size_t out = static_cast<std::size_t>(r) * nx;
    if (s.Floats)
    {
      const float* src = s.Floats->GetPointer(0) + (j * nx) * nc + c;
      const unsigned char* m = s.MaskBytes ? s.MaskBytes->GetPointer(0) + j * nx : nullptr;
      const float nodataF = static_cast<float>(s.NoData);
      for (int i = 0; i < nx; ++i)
      {
        const float v = src[static_cast<std::size_t>(i) * nc];
        const bool valid = (!m || m[i] != 0) && !std::isnan(v);
        s.BlockF[out + i] = valid ? v : nodataF;
      }
    }
    else
    {
      for (int i = 0; i < nx; ++i)
      {
        const vtkIdType k = j * nx + i;
        const double v = s.Array->GetComponent(k, c);
        const bool valid = (!s.Mask || s.Mask->GetComponent(k, 0) != 0.0) && !std::isnan(v);
        s.BlockD[out + i] = valid ? v : s.NoData;
      }
    }
  }
}

/// Fills a BandSource for component-by-component writing in blocks of rows (about 4 MiB).
void PrepareSource(vtkDataArray* array,
  vtkDataArray* mask,
  int nx,
  int ny,
  double nodata,
  bool hasNoData,
  BandSource& s)
{
  s.Array = array;
  s.Floats = vtkFloatArray::SafeDownCast(array);
  s.Mask = mask;
  s.MaskBytes = vtkUnsignedCharArray::SafeDownCast(mask);
  s.NX = nx;
  s.NY = ny;
  s.NC = array->GetNumberOfComponents();
  s.NoData = nodata;
  s.HasNoData = hasNoData;
  s.BlockRows = std::max(1, std::min(ny, static_cast<int>((std::size_t(4) << 20) / nx)));
  s.BlockF.resize(s.Floats ? static_cast<std::size_t>(nx) * s.BlockRows : 0);
  s.BlockD.resize(s.Floats ? 0 : static_cast<std::size_t>(nx) * s.BlockRows);
}

/// Writes component c into band c + 1 (name, no-data value, then the rows north first);
/// "" on success, else the problem.
std::string WriteBand(GDALDatasetH ds, BandSource& s, int c)
{
  const int nx = s.NX;
  const int ny = s.NY;
  GDALRasterBandH band = GDALGetRasterBand(ds, c + 1);
  const char* componentName = s.Array->GetComponentName(c);
  GDALSetDescription(band, componentName ? componentName : (s.NC == 1 ? s.Array->GetName() : ""));
  if (s.HasNoData && GDALSetRasterNoDataValue(band, s.NoData) != CE_None)
  {
    return "cannot set the no-data value";
  }
  for (int r0 = 0; r0 < ny; r0 += s.BlockRows)
  {
    const int rows = std::min(s.BlockRows, ny - r0);
    FillBlock(s, c, r0, rows);
    CPLErr err = s.Floats
      ? GDALRasterIO(band, GF_Write, 0, r0, nx, rows, s.BlockF.data(), nx, rows, GDT_Float32, 0, 0)
      : GDALRasterIO(band, GF_Write, 0, r0, nx, rows, s.BlockD.data(), nx, rows, GDT_Float64, 0, 0);
    // Write the rows out now: left in GDAL's block cache (5 % of RAM by default) they would
    // hold up to one more copy of the band in memory until the file is closed.
    if (err == CE_None)
    {
      err = GDALFlushRasterCache(band);
    }
    if (err != CE_None)
    {
      return "write failed at row " + std::to_string(r0);
    }
  }
  return std::string();
}

/// The temporary file a GeoTIFF is written to before it replaces its target.
struct TemporaryTarget
{
  std::string Target;
  std::string Temp;

  /// Closes `ds` (may be null), removes the temporary file and returns `problem` with its
  /// reason; call it right after the failure, as it reads errno.
  std::string Discard(GDALDatasetH ds,
    const std::string& problem,
    const terroir::io::detail::GDALErrorCapture& capture) const
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
    for (std::size_t at = reason.find(this->Temp); at != std::string::npos;
         at = reason.find(this->Temp))
    {
      reason.replace(at, this->Temp.size(), this->Target);
    }
    if (ds)
    {
      GDALClose(ds);
    }
    terroir::DiscardTemporary(this->Temp);
    return problem + (reason.empty() ? "" : " (" + reason + ")");
  }
};
} // namespace

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
  BandTypeOf(array, type, nodata);
  vtkDataArray* mask = input->GetPointData()->GetArray(vtkTerroirGeoreference::ValidMaskName());
  const bool floating = type == GDT_Float32 || type == GDT_Float64;

  double gt[6];
  int whole[6] = { 0, -1, 0, -1, 0, -1 };
  vtkInformation* inInfo = this->GetInputInformation(0, 0);
  if (inInfo && inInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
  {
    inInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), whole);
  }
  GeoTransformOf(input, whole, gt);
  const std::string wkt = vtkTerroirGeoreference::GetCRS(input);

  GDALDriverH driver = GDALGetDriverByName("GTiff");
  if (!driver)
  {
    this->Fail("GDAL has no GTiff driver");
    return;
  }
  TemporaryTarget file;
  file.Target = this->FileName;
  file.Temp = terroir::TemporaryNameFor(file.Target);
  errno = 0;
  terroir::io::detail::GDALErrorCapture capture;
  std::vector<std::string> optionText;
  std::vector<const char*> options = CreationOptions(
    this->Compression, this->Tiled, this->Threads, floating, nx, ny, nc, optionText);
  GDALDatasetH ds =
    GDALCreate(driver, file.Temp.c_str(), nx, ny, nc, type, const_cast<char**>(options.data()));
  if (!ds)
  {
    this->Fail(file.Discard(nullptr,
      "cannot create a GeoTIFF in folder '" + terroir::io::detail::DirectoryOf(file.Target) + "'",
      capture));
    return;
  }
  if (GDALSetGeoTransform(ds, gt) != CE_None)
  {
    this->Fail(file.Discard(ds, "cannot set the geotransform", capture));
    return;
  }
  if (!wkt.empty() && GDALSetProjection(ds, wkt.c_str()) != CE_None)
  {
    this->Fail(file.Discard(ds, "cannot set the coordinate reference system", capture));
    return;
  }
  // Each band gets its no-data value before its pixels. GDAL's GTiff driver does not write a
  // block that holds nothing but the band's no-data value (0 while none is set) and fills it
  // with the no-data value when the file is closed: a block of zeros written before the value
  // was set came back as no-data (a flat DEM's slope, rows in shadow). Float and Int32 bands
  // always have one; byte bands only when some cell is masked (a byte value is never NaN).
  const bool masked = AnyMasked(mask, static_cast<vtkIdType>(nx) * ny);
  // Rows go out north first (GDAL row r = image row ny-1-r) in blocks of rows; float32 arrays
  // are copied as floats, everything else through double.
  BandSource source;
  PrepareSource(array, mask, nx, ny, nodata, floating || type == GDT_Int32 || masked, source);
  for (int c = 0; c < nc; ++c)
  {
    const std::string problem = WriteBand(ds, source, c);
    if (!problem.empty())
    {
      this->Fail(file.Discard(ds, problem, capture));
      return;
    }
    this->UpdateProgress(static_cast<double>(c + 1) / nc);
  }
  if (this->Overviews)
  {
    const std::string problem = BuildOverviews(ds, floating, nx, ny);
    if (!problem.empty())
    {
      this->Fail(file.Discard(ds, problem, capture));
      return;
    }
  }
  GDALClose(ds);
  if (capture.Failed())
  {
    this->Fail(file.Discard(nullptr, "write failed", capture));
    return;
  }
  std::string error;
  if (!terroir::CommitTemporary(file.Temp, file.Target, error))
  {
    this->Fail(error);
  }
}

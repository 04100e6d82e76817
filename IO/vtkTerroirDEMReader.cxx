#include "vtkTerroirDEMReader.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTerroirGDALPrivate.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirIOPrivate.h"
#include "vtkUnsignedCharArray.h"

#if VTK_MODULE_ENABLE_VTK_ParallelCore
#include "vtkCommunicator.h"
#include "vtkMultiProcessController.h"
#endif

#include "MemoryBudget.h"

#include <cpl_string.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/TransverseMercator.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <vector>

vtkStandardNewMacro(vtkTerroirDEMReader);

namespace
{
using terroir::io::detail::CTPtr;
using terroir::io::detail::DatasetPtr;
using terroir::io::detail::GDALErrorCapture;
using terroir::io::detail::SRSPtr;
constexpr double kFoot = 0.3048;
constexpr double kUSSurveyFoot = 1200.0 / 3937.0;
/// Larger magnitudes (and NaN, infinities) are no-data: no terrain is 1e30 m high.
constexpr float kLargestHeight = 1.0e30f;

/// Metres per unit for a unit name; 0 when the name is not a length unit we know.
double LengthUnitFromName(const std::string& name)
{
  const std::string l = terroir::io::detail::ToLower(name);
  if (l == "ft" || l == "foot" || l == "feet" || l == "international foot" || l == "ft_intl")
  {
    return kFoot;
  }
  if (l == "us-ft" || l == "ftus" || l == "us survey foot" || l == "foot_us" ||
    l == "us_survey_foot" || l == "survey foot")
  {
    return kUSSurveyFoot;
  }
  if (l == "m" || l == "metre" || l == "meter" || l == "metres" || l == "meters")
  {
    return 1.0;
  }
  return 0.0;
}

/// Everything RequestInformation and RequestData need, read without touching pixels.
struct Description
{
  int nx = 0;
  int ny = 0;
  double gt[6] = { 0, 1, 0, 0, 0, 1 };
  bool hasGeoTransform = false;
  std::string wkt;
  bool geographic = false;
  double spacing[2] = { 1, 1 };
  double origin[2] = { 0, 0 };
  double zScale = 1.0;     // band value -> metres (unit only)
  double bandScale = 1.0;  // GDAL scale
  double bandOffset = 0.0; // GDAL offset
  bool hasNodata = false;
  double nodata = 0.0;
  bool floatBand = false;
  bool hasCenter = false;
  double centerLat = 0.0;
  double centerLon = 0.0;
  bool hasConvergence = false;
  double convergence = 0.0;
  std::vector<double> rowDx, rowDy; // j = 0 south
  std::vector<std::string> warnings;

  /// The grid's centre in CRS coordinates (from the geotransform).
  double CentreX() const { return this->gt[0] + 0.5 * this->nx * this->gt[1]; }
  double CentreY() const { return this->gt[3] + 0.5 * this->ny * this->gt[5]; }
  /// True when the file's first row is the northern one (GDAL's usual order).
  bool NorthUp() const { return this->gt[5] < 0.0; }
};

/// Reads the raster size and the band's no-data value, scale, offset and unit.
bool DescribeBand(GDALDatasetH ds,
  int bandIndex,
  vtkIdType maxCells,
  Description& d,
  std::string& error)
{
  d.nx = GDALGetRasterXSize(ds);
  d.ny = GDALGetRasterYSize(ds);
  const int bands = GDALGetRasterCount(ds);
  if (bands < 1)
  {
    error = "the file holds no raster band";
    return false;
  }
  if (bandIndex > bands)
  {
    error =
      "band " + std::to_string(bandIndex) + " requested, the file has " + std::to_string(bands);
    return false;
  }
  if (d.nx < 1 || d.ny < 1)
  {
    error = "invalid raster size " + std::to_string(d.nx) + " x " + std::to_string(d.ny);
    return false;
  }
  const double cells = static_cast<double>(d.nx) * static_cast<double>(d.ny);
  if (cells > static_cast<double>(maxCells))
  {
    error = "raster of " + std::to_string(d.nx) + " x " + std::to_string(d.ny) +
      " cells exceeds MaxCells = " + std::to_string(static_cast<long long>(maxCells));
    return false;
  }
  GDALRasterBandH band = GDALGetRasterBand(ds, bandIndex);
  int has = 0;
  d.nodata = GDALGetRasterNoDataValue(band, &has);
  d.hasNodata = has != 0;
  d.floatBand = GDALGetRasterDataType(band) == GDT_Float32;
  d.bandScale = GDALGetRasterScale(band, &has);
  if (!has || d.bandScale == 0.0)
  {
    d.bandScale = 1.0;
  }
  d.bandOffset = GDALGetRasterOffset(band, &has);
  if (!has)
  {
    d.bandOffset = 0.0;
  }
  const char* unitType = GDALGetRasterUnitType(band);
  if (unitType && *unitType)
  {
    const double f = LengthUnitFromName(unitType);
    if (f > 0.0)
    {
      d.zScale = f;
    }
    else
    {
      d.warnings.push_back(
        std::string("unknown band unit '") + unitType + "', values taken as metres");
    }
  }
  return true;
}

/// Reads the geotransform (north-up, finite) or, when the file has none, sets a unit one.
bool DescribeGeoTransform(GDALDatasetH ds, Description& d, std::string& error)
{
  d.hasGeoTransform = GDALGetGeoTransform(ds, d.gt) == CE_None;
  if (d.hasGeoTransform && (d.gt[2] != 0.0 || d.gt[4] != 0.0))
  {
    error = "rotated or sheared geotransform (" + std::to_string(d.gt[2]) + ", " +
      std::to_string(d.gt[4]) + ") is not supported; warp it north-up first (gdalwarp)";
    return false;
  }
  if (d.hasGeoTransform &&
    (d.gt[1] == 0.0 || d.gt[5] == 0.0 || !std::isfinite(d.gt[1]) || !std::isfinite(d.gt[5])))
  {
    error = "invalid pixel size in the geotransform";
    return false;
  }
  if (d.hasGeoTransform &&
    !(std::isfinite(d.gt[0]) && std::isfinite(d.gt[3]) && std::isfinite(d.gt[0] + d.nx * d.gt[1]) &&
      std::isfinite(d.gt[3] + d.ny * d.gt[5])))
  {
    error = "invalid origin in the geotransform (not finite)";
    return false;
  }
  if (!d.hasGeoTransform)
  {
    for (int k = 0; k < 6; ++k)
    {
      d.gt[k] = (k == 1) ? 1.0 : ((k == 5) ? -1.0 : 0.0);
    }
  }
  return true;
}

/// A file without CRS or geotransform: refused when `requireGeo`, else pixel units taken as
/// metres and no georeference.
bool DescribeUngeoreferenced(bool requireGeo, Description& d, std::string& error)
{
  if (requireGeo)
  {
    error = d.wkt.empty() ? "no coordinate reference system (RequireGeoreference is on)"
                          : "no geotransform (RequireGeoreference is on)";
    return false;
  }
  d.warnings.push_back(d.wkt.empty()
      ? "no coordinate reference system: pixel size taken as metres, no georeference"
      : "no geotransform: spacing 1 m, no georeference");
  d.wkt.clear();
  d.spacing[0] = std::fabs(d.gt[1]);
  d.spacing[1] = std::fabs(d.gt[5]);
  d.origin[0] = d.gt[0] + 0.5 * d.gt[1];
  d.origin[1] = d.gt[5] < 0 ? d.gt[3] + (d.ny - 0.5) * d.gt[5] : d.gt[3] + 0.5 * d.gt[5];
  return true;
}

/// Reads the vertical unit and the ellipsoid (semi-major axis a, flattening f) of the CRS.
bool DescribeEllipsoid(OGRSpatialReferenceH srs,
  Description& d,
  double& a,
  double& f,
  std::string& error)
{
  if (OSRIsCompound(srs) || OSRIsVertical(srs))
  {
    const double vf = OSRGetTargetLinearUnits(srs, "VERT_CS", nullptr);
    if (vf > 0.0 && std::fabs(vf - 1.0) > 1e-12)
    {
      d.zScale = vf;
    }
  }
  OGRErr err = OGRERR_NONE;
  a = OSRGetSemiMajor(srs, &err);
  const double invf = OSRGetInvFlattening(srs, &err);
  // GeographicLib throws on a degenerate ellipsoid; no body a file may describe needs more
  // than a flattening of 1/2.
  if (!(a > 0.0 && a <= 1e10) || !(invf == 0.0 || (invf > 2.0 && std::isfinite(invf))))
  {
    error = "the CRS ellipsoid (semi-major axis " + std::to_string(a) + " m, inverse flattening " +
      std::to_string(invf) + ") is not usable";
    return false;
  }
  f = invf > 0.0 ? 1.0 / invf : 0.0;
  return true;
}

/// A geographic grid: metric spacing of every row on the ellipsoid, centre, no convergence.
bool DescribeGeographic(OGRSpatialReferenceH srs,
  const GeographicLib::Geodesic& geod,
  Description& d,
  std::string& error)
{
  const double cx = d.CentreX();
  const double cy = d.CentreY();
  const bool northUp = d.NorthUp();
  auto gdalRow = [&](int j) { return northUp ? d.ny - 1 - j : j; };
  d.geographic = true;
  const double toDeg = OSRGetAngularUnits(srs, nullptr) * 180.0 / M_PI;
  const double dLon = std::fabs(d.gt[1]) * toDeg;
  const double dLat = std::fabs(d.gt[5]) * toDeg;
  d.centerLon = cx * toDeg;
  d.centerLat = cy * toDeg;
  d.hasCenter = true;
  d.hasConvergence = true;
  d.convergence = 0.0;
  d.rowDx.resize(d.ny);
  d.rowDy.resize(d.ny);
  for (int j = 0; j < d.ny; ++j)
  {
    const double lat = (d.gt[3] + (gdalRow(j) + 0.5) * d.gt[5]) * toDeg;
    if (std::fabs(lat) + 0.5 * dLat > 90.0)
    {
      std::ostringstream os;
      os << "row latitude " << lat
         << " is outside [-90, 90]: the geotransform is not in the degrees of the file's "
            "geographic CRS (mismatched CRS?)";
      error = os.str();
      return false;
    }
    double s12 = 0.0;
    geod.Inverse(lat, d.centerLon, lat, d.centerLon + dLon, s12);
    d.rowDx[j] = s12;
    geod.Inverse(lat - 0.5 * dLat, d.centerLon, lat + 0.5 * dLat, d.centerLon, s12);
    d.rowDy[j] = s12;
  }
  d.spacing[0] = d.rowDx[d.ny / 2];
  d.spacing[1] = d.rowDy[d.ny / 2];
  d.origin[0] = 0.0;
  d.origin[1] = 0.0;
  return true;
}

/// A projected (or local) grid: spacing and origin in metres, then, for a projection, the
/// geographic centre and the meridian convergence there.
bool DescribeProjected(OGRSpatialReferenceH srs,
  double a,
  double f,
  const GeographicLib::Geodesic& geod,
  Description& d,
  std::string& error)
{
  const double cx = d.CentreX();
  const double cy = d.CentreY();
  const bool northUp = d.NorthUp();
  const double lin = OSRIsProjected(srs) ? OSRGetLinearUnits(srs, nullptr) : 1.0;
  d.spacing[0] = std::fabs(d.gt[1]) * lin;
  d.spacing[1] = std::fabs(d.gt[5]) * lin;
  d.origin[0] = (d.gt[0] + 0.5 * d.gt[1]) * lin;
  d.origin[1] = (northUp ? d.gt[3] + (d.ny - 0.5) * d.gt[5] : d.gt[3] + 0.5 * d.gt[5]) * lin;
  if (!OSRIsProjected(srs))
  {
    d.warnings.push_back("CRS is neither geographic nor projected: no centre or convergence");
    return true;
  }
  SRSPtr geogOwner(OSRCloneGeogCS(srs));
  auto geog = static_cast<OGRSpatialReferenceH>(geogOwner.get());
  if (!geog)
  {
    error = "cannot derive the geographic CRS of the projection";
    return false;
  }
  OSRSetAxisMappingStrategy(geog, OAMS_TRADITIONAL_GIS_ORDER);
  CTPtr ctOwner(OCTNewCoordinateTransformation(srs, geog));
  auto ct = static_cast<OGRCoordinateTransformationH>(ctOwner.get());
  if (!ct)
  {
    error = "cannot transform the projection to its geographic CRS";
    return false;
  }
  double px[3] = { cx, cx, cx };
  double py[3] = { cy, cy - 0.5, cy + 0.5 };
  int ok[3] = { 0, 0, 0 };
  if (!OCTTransformEx(ct, 3, px, py, nullptr, ok) || !ok[0] || !ok[1] || !ok[2])
  {
    error = "cannot transform the grid centre to geographic coordinates";
    return false;
  }
  d.centerLon = px[0];
  d.centerLat = py[0];
  d.hasCenter = true;
  int north = 0;
  const int zone = OSRGetUTMZone(srs, &north);
  if (zone > 0)
  {
    const GeographicLib::TransverseMercator tm(a, f, 0.9996);
    double x, y, gamma, k;
    tm.Forward(6.0 * zone - 183.0, d.centerLat, d.centerLon, x, y, gamma, k);
    d.convergence = gamma;
  }
  else
  {
    double s12, azi1, azi2;
    geod.Inverse(py[1], px[1], py[2], px[2], s12, azi1, azi2);
    const double r = M_PI / 180.0;
    d.convergence =
      std::atan2(std::sin(azi1 * r) + std::sin(azi2 * r), std::cos(azi1 * r) + std::cos(azi2 * r)) /
      r;
  }
  d.hasConvergence = true;
  return true;
}

/// Reads everything Description holds from the file, without the final sanity checks.
bool DescribeRaw(GDALDatasetH ds,
  int bandIndex,
  bool requireGeo,
  vtkIdType maxCells,
  Description& d,
  std::string& error)
{
  if (!DescribeBand(ds, bandIndex, maxCells, d, error) || !DescribeGeoTransform(ds, d, error))
  {
    return false;
  }
  const char* wkt = GDALGetProjectionRef(ds);
  d.wkt = wkt ? wkt : "";
  if (d.wkt.empty() || !d.hasGeoTransform)
  {
    return DescribeUngeoreferenced(requireGeo, d, error);
  }

  SRSPtr srsOwner(OSRNewSpatialReference(nullptr));
  auto srs = static_cast<OGRSpatialReferenceH>(srsOwner.get());
  if (OSRImportFromWkt(srs, const_cast<char**>(&wkt)) != OGRERR_NONE)
  {
    error = "cannot parse the coordinate reference system";
    return false;
  }
  OSRSetAxisMappingStrategy(srs, OAMS_TRADITIONAL_GIS_ORDER);
  double a = 0.0;
  double f = 0.0;
  if (!DescribeEllipsoid(srs, d, a, f, error))
  {
    return false;
  }
  const GeographicLib::Geodesic geod(a, f);
  if (OSRIsGeographic(srs))
  {
    return DescribeGeographic(srs, geod, d, error);
  }
  return DescribeProjected(srs, a, f, geod, d, error);
}

/// DescribeRaw, then checks that everything derived from what GDAL returned is usable: a CRS
/// with odd units or a degenerate ellipsoid must not turn into NaN or zero spacings.
bool Describe(GDALDatasetH ds,
  int bandIndex,
  bool requireGeo,
  vtkIdType maxCells,
  Description& d,
  std::string& error)
{
  try
  {
    if (!DescribeRaw(ds, bandIndex, requireGeo, maxCells, d, error))
    {
      return false;
    }
  }
  catch (const std::exception& e)
  {
    // GeographicLib reports what it cannot compute (e.g. latitudes beyond the poles) by throwing.
    error = std::string("the georeference cannot be evaluated (") + e.what() + ")";
    return false;
  }
  auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!positive(d.spacing[0]) || !positive(d.spacing[1]))
  {
    error = "cell size " + std::to_string(d.spacing[0]) + " x " + std::to_string(d.spacing[1]) +
      " m derived from the geotransform and CRS units is not positive and finite";
    return false;
  }
  if (!std::isfinite(d.origin[0]) || !std::isfinite(d.origin[1]))
  {
    error = "grid origin derived from the geotransform and CRS units is not finite";
    return false;
  }
  for (std::size_t j = 0; j < d.rowDx.size(); ++j)
  {
    if (!positive(d.rowDx[j]) || !positive(d.rowDy[j]))
    {
      error = "cell size of row " + std::to_string(j) + " on the CRS ellipsoid is " +
        std::to_string(d.rowDx[j]) + " x " + std::to_string(d.rowDy[j]) +
        " m (degenerate ellipsoid?)";
      return false;
    }
  }
  if (d.hasCenter &&
    !(std::fabs(d.centerLat) <= 90.0 && std::isfinite(d.centerLon) && std::fabs(d.centerLon) < 1e6))
  {
    error = "grid centre " + std::to_string(d.centerLat) + ", " + std::to_string(d.centerLon) +
      " is not a valid latitude, longitude";
    return false;
  }
  if (d.hasConvergence && !std::isfinite(d.convergence))
  {
    error = "meridian convergence at the grid centre is not finite";
    return false;
  }
  if (!std::isfinite(d.zScale) || d.zScale <= 0.0 || !std::isfinite(d.bandScale) ||
    !std::isfinite(d.bandOffset))
  {
    error = "band scale, offset or vertical unit is not finite";
    return false;
  }
  return true;
}
} // namespace

vtkTerroirDEMReader::vtkTerroirDEMReader()
{
  this->SetNumberOfInputPorts(0);
  this->SetNumberOfOutputPorts(1);
  GDALAllRegister();
}

vtkTerroirDEMReader::~vtkTerroirDEMReader()
{
  this->SetFileName(nullptr);
}

void vtkTerroirDEMReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "Band: " << this->Band << "\n";
  os << indent << "VerticalUnit: " << this->VerticalUnit << "\n";
  os << indent << "RequireGeoreference: " << this->RequireGeoreference << "\n";
  os << indent << "MaxCells: " << this->MaxCells << "\n";
  os << indent << "AllowNetworkPaths: " << this->AllowNetworkPaths << "\n";
  os << indent << "VerticalUnitToMetres: " << this->VerticalUnitToMetres << "\n";
  os << indent << "ErrorMessage: " << this->ErrorMessage << "\n";
}

void vtkTerroirDEMReader::Fail(const std::string& problem)
{
  this->ErrorMessage = terroir::io::detail::FileError(this->FileName, problem);
  vtkErrorMacro(<< this->ErrorMessage);
}

namespace
{
/// Opens the file after the path checks; on failure returns null and sets `error`. Without
/// `allowNetwork` the caller holds a ScopedNetworkRefusal, and a dataset that still needs the
/// network (a server driver, or a file naming remote or archived data) is refused here.
DatasetPtr OpenRaster(const char* fileName, bool allowNetwork, std::string& error)
{
  bool remote = false;
  error = terroir::io::detail::CheckPathToOpen(fileName, allowNetwork, remote);
  if (!error.empty())
  {
    return DatasetPtr();
  }
  const std::string path = fileName;
  if (!remote && path.rfind("/vsimem/", 0) != 0 &&
    !terroir::io::detail::CheckInputFile(path, error))
  {
    return DatasetPtr();
  }
  GDALErrorCapture capture;
  DatasetPtr ds(GDALOpenEx(fileName,
    GDAL_OF_RASTER | GDAL_OF_READONLY | GDAL_OF_VERBOSE_ERROR,
    nullptr,
    nullptr,
    nullptr));
  if (!ds)
  {
    error = "not a raster GDAL can read" + capture.Suffix();
    return ds;
  }
  if (allowNetwork)
  {
    return ds;
  }
  const terroir::io::detail::DatasetSources s =
    terroir::io::detail::ListDatasetSources(ds.get(), terroir::io::detail::IsServerDriver);
  error = terroir::io::detail::RefuseNetworkDataset(s.Driver, s.Server, s.Files);
  return error.empty() ? std::move(ds) : DatasetPtr();
}

/// Replaces the file's vertical unit with the one chosen (VerticalUnit other than AUTO),
/// with a warning when the file declared another one.
void ApplyVerticalUnit(int verticalUnit, Description& d)
{
  if (verticalUnit == vtkTerroirDEMReader::VERTICAL_UNIT_AUTO)
  {
    return;
  }
  const double chosen = verticalUnit == vtkTerroirDEMReader::VERTICAL_UNIT_FOOT ? kFoot
    : verticalUnit == vtkTerroirDEMReader::VERTICAL_UNIT_US_FOOT                ? kUSSurveyFoot
                                                                                : 1.0;
  if (d.zScale != 1.0 && d.zScale != chosen)
  {
    d.warnings.push_back("the file's vertical unit (" + std::to_string(d.zScale) +
      " m) is replaced by VerticalUnit (" + std::to_string(chosen) + " m)");
  }
  d.zScale = chosen;
}

/// Where ReadElevations puts the heights (metres, row 0 = south) and the validity of the cells
/// of the window it reads, and how many cells it found invalid.
struct ElevationTarget
{
  float* Elevation = nullptr;
  unsigned char* Valid = nullptr;
  vtkIdType InvalidCount = 0;
};

/// The part of the raster a read covers, in VTK's indices (i east, j north, j = 0 the southern
/// row): columns i0..i1, rows j0..j1. The whole raster unless a piece is asked for.
struct ReadWindow
{
  int i0 = 0, i1 = -1, j0 = 0, j1 = -1;
  int Width() const { return this->i1 - this->i0 + 1; }
  int Height() const { return this->j1 - this->j0 + 1; }
};

/// Reads `w` of the band in blocks of chunkRows rows as Sample (float or double, GDAL type
/// ioType), converts to metres, masks no-data and flips rows (row 0 = south) into `target`
/// (Width() x Height() cells); reports progress to `algorithm`. On a failed read sets `error`
/// and returns false. A cell's value does not depend on the window: the same conversion runs
/// on the same sample.
template<typename Sample>
bool ReadElevations(GDALRasterBandH band,
  GDALDataType ioType,
  const Description& d,
  const ReadWindow& w,
  int chunkRows,
  ElevationTarget& target,
  vtkAlgorithm* algorithm,
  const GDALErrorCapture& capture,
  std::string& error)
{
  const vtkIdType nx = w.Width();
  const int ny = w.Height();
  const bool northUp = d.NorthUp();
  // GDAL rows of the window: row 0 is the first row of the file (the northern one when
  // north-up), so VTK rows j0..j1 are GDAL rows ny - 1 - j1 .. ny - 1 - j0 there.
  const int gdalRow0 = northUp ? d.ny - 1 - w.j1 : w.j0;
  const float nodataF = static_cast<float>(d.nodata);
  const double factor = d.bandScale * d.zScale;
  const double offset = d.bandOffset * d.zScale;
  std::vector<Sample> buffer(static_cast<std::size_t>(nx) * chunkRows);
  const Sample nodataS = static_cast<Sample>(d.nodata);
  const bool scaled = factor != 1.0 || offset != 0.0;
  for (int r0 = 0; r0 < ny; r0 += chunkRows)
  {
    const int rows = std::min(chunkRows, ny - r0);
    if (GDALRasterIO(band,
          GF_Read,
          w.i0,
          gdalRow0 + r0,
          w.Width(),
          rows,
          buffer.data(),
          w.Width(),
          rows,
          ioType,
          0,
          0) != CE_None)
    {
      error = "read failed at row " + std::to_string(gdalRow0 + r0) + capture.Suffix();
      return false;
    }
    // Drop the blocks GDAL cached for these rows: the elevation array is the one copy kept.
    GDALFlushRasterCache(band);
    for (int r = 0; r < rows; ++r)
    {
      const int gr = r0 + r;
      const vtkIdType j = northUp ? ny - 1 - gr : gr;
      const Sample* src = buffer.data() + static_cast<std::size_t>(r) * nx;
      float* dst = target.Elevation + j * nx;
      unsigned char* vdst = target.Valid + j * nx;
      for (vtkIdType i = 0; i < nx; ++i)
      {
        const Sample v = src[i];
        bool isValid = !std::isnan(v);
        if (isValid && d.hasNodata)
        {
          isValid = d.floatBand ? static_cast<float>(v) != nodataF : v != nodataS;
        }
        // A value that is, or scales to, infinity is no height either, nor a float sentinel
        // such as -3.4e38 (ESRI's default no-data) left undeclared.
        const float h = !isValid ? std::numeric_limits<float>::quiet_NaN()
          : scaled               ? static_cast<float>(v * factor + offset)
                                 : static_cast<float>(v);
        isValid = isValid && std::fabs(h) <= kLargestHeight;
        vdst[i] = isValid ? 1 : 0;
        dst[i] = isValid ? h : std::numeric_limits<float>::quiet_NaN();
        target.InvalidCount += isValid ? 0 : 1;
      }
    }
    algorithm->UpdateProgress(static_cast<double>(r0 + rows) / ny);
  }
  return true;
}

/// Gives the output its extent (the window `w`; spacing and origin those of the whole grid),
/// the elevation (and the mask when `masked`) and the georeference of `d` (whole-grid values,
/// the same for every piece), and names the source file.
void AssembleTerrain(vtkImageData* output,
  const Description& d,
  const ReadWindow& w,
  vtkFloatArray* elevation,
  vtkUnsignedCharArray* mask,
  bool masked,
  const char* fileName)
{
  output->SetExtent(w.i0, w.i1, w.j0, w.j1, 0, 0);
  output->SetSpacing(d.spacing[0], d.spacing[1], 1.0);
  output->SetOrigin(d.origin[0], d.origin[1], 0.0);
  output->GetPointData()->SetScalars(elevation);
  if (masked)
  {
    output->GetPointData()->AddArray(mask);
  }
  if (d.hasGeoTransform)
  {
    vtkTerroirGeoreference::SetGeoTransform(output, d.gt);
  }
  if (!d.wkt.empty())
  {
    vtkTerroirGeoreference::SetCRS(output, d.wkt);
  }
  if (d.hasCenter)
  {
    vtkTerroirGeoreference::SetCenterLatLon(output, d.centerLat, d.centerLon);
  }
  if (d.hasConvergence)
  {
    vtkTerroirGeoreference::SetMeridianConvergence(output, d.convergence);
  }
  if (d.geographic)
  {
    const vtkIdType ny = d.ny;
    vtkNew<vtkDoubleArray> rows;
    rows->SetNumberOfComponents(2);
    rows->SetComponentName(0, "dx");
    rows->SetComponentName(1, "dy");
    rows->SetNumberOfTuples(ny);
    for (vtkIdType j = 0; j < ny; ++j)
    {
      rows->SetTypedComponent(j, 0, d.rowDx[j]);
      rows->SetTypedComponent(j, 1, d.rowDy[j]);
    }
    rows->GetInformation()->Set(vtkDataArray::UNITS_LABEL(), "m");
    vtkTerroirGeoreference::SetRowSpacing(output, rows);
  }
  vtkTerroirGeoreference::SetSourceFile(output, fileName);
}
} // namespace

int vtkTerroirDEMReader::RequestInformation(vtkInformation*,
  vtkInformationVector**,
  vtkInformationVector* outputVector)
{
  this->ErrorMessage.clear();
  std::string error;
  std::unique_ptr<terroir::io::detail::ScopedNetworkRefusal> offline;
  if (!this->AllowNetworkPaths)
  {
    offline.reset(new terroir::io::detail::ScopedNetworkRefusal);
  }
  DatasetPtr ds = OpenRaster(this->FileName, this->AllowNetworkPaths, error);
  Description d;
  if (ds)
  {
    GDALErrorCapture capture;
    if (!Describe(static_cast<GDALDatasetH>(ds.get()),
          this->Band,
          this->RequireGeoreference,
          this->MaxCells,
          d,
          error))
    {
      error += capture.Suffix();
    }
  }
  if (!error.empty())
  {
    this->Fail(error);
    if (vtkImageData* output = vtkImageData::GetData(outputVector, 0))
    {
      output->Initialize();
    }
    return 0;
  }
  terroir::io::detail::SetTerrainInformation(outputVector->GetInformationObject(0),
    d.nx,
    d.ny,
    d.spacing[0],
    d.spacing[1],
    d.origin[0],
    d.origin[1]);
  // Pieces: RequestData reads only the update extent (a GDAL window).
  outputVector->GetInformationObject(0)->Set(vtkAlgorithm::CAN_PRODUCE_SUB_EXTENT(), 1);
  return 1;
}

int vtkTerroirDEMReader::RequestData(vtkInformation*,
  vtkInformationVector**,
  vtkInformationVector* outputVector)
{
  vtkImageData* output = vtkImageData::GetData(outputVector, 0);
  output->Initialize();
  this->ErrorMessage.clear();
  std::string error;
  std::unique_ptr<terroir::io::detail::ScopedNetworkRefusal> offline;
  if (!this->AllowNetworkPaths)
  {
    offline.reset(new terroir::io::detail::ScopedNetworkRefusal);
  }
  DatasetPtr ds = OpenRaster(this->FileName, this->AllowNetworkPaths, error);
  if (!ds)
  {
    this->Fail(error);
    return 0;
  }
  auto dataset = static_cast<GDALDatasetH>(ds.get());
  GDALErrorCapture capture;
  Description d;
  if (!Describe(dataset, this->Band, this->RequireGeoreference, this->MaxCells, d, error))
  {
    this->Fail(error + capture.Suffix());
    return 0;
  }
  ApplyVerticalUnit(this->VerticalUnit, d);
  this->VerticalUnitToMetres = d.zScale;

  ReadWindow w;
  w.i1 = d.nx - 1;
  w.j1 = d.ny - 1;
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT()))
  {
    int ext[6];
    outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), ext);
    if (ext[0] > ext[1] || ext[2] > ext[3] || ext[4] > ext[5])
    {
      // An empty piece (more pieces than rows): nothing to read, nothing to report.
      this->ReadExtent[0] = this->ReadExtent[2] = this->ReadExtent[4] = 0;
      this->ReadExtent[1] = this->ReadExtent[3] = this->ReadExtent[5] = -1;
      vtkIdType none[2];
      this->ReducePieces(outInfo, 0, 0, none);
      return 1;
    }
    if (ext[0] < 0 || ext[1] > d.nx - 1 || ext[2] < 0 || ext[3] > d.ny - 1 || ext[4] != 0 ||
      ext[5] != 0)
    {
      std::ostringstream os;
      os << "requested extent " << ext[0] << ".." << ext[1] << " x " << ext[2] << ".." << ext[3]
         << " x " << ext[4] << ".." << ext[5] << " is outside the raster's 0.." << d.nx - 1
         << " x 0.." << d.ny - 1 << " x 0..0";
      this->Fail(os.str());
      return 0;
    }
    w.i0 = ext[0];
    w.i1 = ext[1];
    w.j0 = ext[2];
    w.j1 = ext[3];
  }
  const bool whole = w.i0 == 0 && w.j0 == 0 && w.i1 == d.nx - 1 && w.j1 == d.ny - 1;
  const vtkIdType nx = w.Width();
  const vtkIdType ny = w.Height();
  // Elevation (4 B) and mask (1 B) per cell, plus one block of rows read as doubles.
  const int chunkRows =
    std::max(1, std::min(w.Height(), static_cast<int>((std::size_t(4) << 20) / w.Width())));
  error = terroir::CheckMemory(static_cast<double>(nx) * static_cast<double>(ny) * 5.0 +
      8.0 * static_cast<double>(nx) * chunkRows,
    "reading the raster");
  vtkNew<vtkFloatArray> elevation;
  elevation->SetName(vtkTerroirGeoreference::ElevationName());
  vtkNew<vtkUnsignedCharArray> mask;
  mask->SetName(vtkTerroirGeoreference::ValidMaskName());
  ElevationTarget target;
  if (error.empty())
  {
    elevation->SetNumberOfTuples(nx * ny);
    elevation->GetInformation()->Set(vtkDataArray::UNITS_LABEL(), "m");
    mask->SetNumberOfTuples(nx * ny);
    target.Elevation = elevation->GetPointer(0);
    target.Valid = mask->GetPointer(0);
  }

  GDALRasterBandH band = GDALGetRasterBand(dataset, this->Band);
  // Bands whose values float32 holds exactly (Float32, Byte, Int16, UInt16) are read as float,
  // the rest as double; either way one pass converts, masks and flips rows (row 0 = south).
  const GDALDataType bandType = GDALGetRasterDataType(band);
  const bool asFloat = bandType == GDT_Float32 || bandType == GDT_Byte || bandType == GDT_Int16 ||
    bandType == GDT_UInt16;
  const bool ok = error.empty() &&
    (asFloat
        ? ReadElevations<float>(band, GDT_Float32, d, w, chunkRows, target, this, capture, error)
        : ReadElevations<double>(band, GDT_Float64, d, w, chunkRows, target, this, capture, error));
  // Every piece takes part in the reduction, even one whose read failed, so that no rank waits.
  const vtkIdType cells = ok ? nx * ny : 0;
  const vtkIdType invalid = ok ? target.InvalidCount : 0;
  vtkIdType totals[2] = { invalid, cells - invalid };
  const bool reduced = this->ReducePieces(outInfo, invalid, cells - invalid, totals);
  const vtkIdType anyInvalid = totals[0];
  const vtkIdType anyValid = totals[1];
  if (!ok)
  {
    this->Fail(error);
    output->Initialize();
    return 0;
  }
  this->ReadExtent[0] = w.i0;
  this->ReadExtent[1] = w.i1;
  this->ReadExtent[2] = w.j0;
  this->ReadExtent[3] = w.j1;
  this->ReadExtent[4] = this->ReadExtent[5] = 0;
  // The whole raster, or the pieces of one parallel run (whose union is the whole raster): the
  // serial rule, from every piece's counts. A piece read alone cannot see the other cells: it
  // keeps the mask whenever the file can hold no-data, so that all its pieces have the same
  // arrays, and an all no-data piece is no error.
  bool masked = anyInvalid > 0;
  if (!whole && !reduced)
  {
    masked = target.InvalidCount > 0 || d.hasNodata || GDALDataTypeIsFloating(bandType);
  }
  if ((whole || reduced) && anyValid == 0)
  {
    this->Fail("every cell is no-data (nothing to read)");
    output->Initialize();
    return 0;
  }
  for (const std::string& msg : d.warnings)
  {
    vtkWarningMacro(<< terroir::io::detail::FileError(this->FileName, msg));
  }
  AssembleTerrain(output, d, w, elevation, mask, masked, this->FileName);
  return 1;
}

bool vtkTerroirDEMReader::ReducePieces(vtkInformation* outInfo,
  vtkIdType invalid,
  vtkIdType valid,
  vtkIdType totals[2])
{
  totals[0] = invalid;
  totals[1] = valid;
#if VTK_MODULE_ENABLE_VTK_ParallelCore
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  const int pieces = outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES())
    ? outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES())
    : 1;
  if (!controller || controller->GetNumberOfProcesses() < 2 ||
    pieces != controller->GetNumberOfProcesses())
  {
    return false;
  }
  const vtkIdType local[2] = { invalid, valid };
  controller->AllReduce(local, totals, 2, vtkCommunicator::SUM_OP);
  return true;
#else
  (void)outInfo;
  return false;
#endif
}

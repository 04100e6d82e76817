#include "vtkTerroirVectorRasterizer.h"

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

#include "MemoryBudget.h"

#include <cpl_minixml.h>
#include <cpl_string.h>
#include <gdal.h>
#include <gdal_alg.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <sstream>
#include <vector>

#include <sys/stat.h>
#include <unistd.h>

vtkStandardNewMacro(vtkTerroirVectorRasterizer);

namespace
{
using terroir::io::detail::CTPtr;
using terroir::io::detail::DatasetPtr;
using terroir::io::detail::GDALErrorCapture;
using terroir::io::detail::SRSPtr;

struct FeatureDeleter
{
  void operator()(void* f) const
  {
    if (f)
    {
      OGR_F_Destroy(static_cast<OGRFeatureH>(f));
    }
  }
};
using FeaturePtr = std::unique_ptr<void, FeatureDeleter>;

struct GeometryDeleter
{
  void operator()(void* g) const
  {
    if (g)
    {
      OGR_G_DestroyGeometry(static_cast<OGRGeometryH>(g));
    }
  }
};
using GeometryPtr = std::unique_ptr<void, GeometryDeleter>;

/// Line vertices farther than this many cells outside the raster are moved onto that margin
/// before GDAL burns the line. GDAL's Bresenham walk (AllTouched off) visits every cell from one
/// vertex to the next, inside the raster or not, and casts the cell numbers to int: a segment
/// reaching 1e9 cells away takes seconds and one reaching 2^31 overflows. With the margin no
/// walk is longer than the raster plus twice the margin.
const double kLineMarginCells = 1024.0;

/// The raster's footprint, grown by kLineMarginCells, in the terrain's CRS.
struct ClipBox
{
  double X0, X1, Y0, Y1;
};

/// Liang-Barsky: the parameters t0 <= t1 of the part of a + t (b - a), t in [0, 1], inside the
/// box; false when no part is (or a coordinate is not finite).
bool ClipSegment(const ClipBox& box, const double a[2], const double b[2], double& t0, double& t1)
{
  if (!std::isfinite(a[0]) || !std::isfinite(a[1]) || !std::isfinite(b[0]) || !std::isfinite(b[1]))
  {
    return false;
  }
  t0 = 0.0;
  t1 = 1.0;
  const double d[2] = { b[0] - a[0], b[1] - a[1] };
  const double lo[2] = { box.X0, box.Y0 };
  const double hi[2] = { box.X1, box.Y1 };
  for (int axis = 0; axis < 2; ++axis)
  {
    if (d[axis] == 0.0)
    {
      if (a[axis] < lo[axis] || a[axis] > hi[axis])
      {
        return false;
      }
      continue;
    }
    double ta = (lo[axis] - a[axis]) / d[axis];
    double tb = (hi[axis] - a[axis]) / d[axis];
    if (ta > tb)
    {
      std::swap(ta, tb);
    }
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 <= t1;
}

bool Inside(const ClipBox& box, const double p[2])
{
  return p[0] >= box.X0 && p[0] <= box.X1 && p[1] >= box.Y0 && p[1] <= box.Y1;
}

/// A LineString cut to the box: a MultiLineString of the parts inside, vertices inside the box
/// kept bit for bit. Null when every vertex is inside already (nothing to change).
GeometryPtr ClipLineString(OGRGeometryH line, const ClipBox& box)
{
  const int n = OGR_G_GetPointCount(line);
  std::vector<double> xy(2 * static_cast<std::size_t>(std::max(n, 0)));
  bool allInside = true;
  for (int k = 0; k < n; ++k)
  {
    OGR_G_GetPointZM(line, k, &xy[2 * k], &xy[2 * k + 1], nullptr, nullptr);
    allInside = allInside && Inside(box, &xy[2 * k]);
  }
  if (allInside)
  {
    return nullptr;
  }
  GeometryPtr parts(OGR_G_CreateGeometry(wkbMultiLineString));
  OGRGeometryH part = nullptr;
  auto flush = [&]()
  {
    if (part)
    {
      OGR_G_AddGeometryDirectly(static_cast<OGRGeometryH>(parts.get()), part);
      part = nullptr;
    }
  };
  for (int k = 1; k < n; ++k)
  {
    const double* a = &xy[2 * (k - 1)];
    const double* b = &xy[2 * k];
    double t0 = 0.0;
    double t1 = 1.0;
    if (!ClipSegment(box, a, b, t0, t1))
    {
      flush();
      continue;
    }
    if (!part || t0 > 0.0)
    {
      flush();
      part = OGR_G_CreateGeometry(wkbLineString);
      OGR_G_AddPoint_2D(part,
        t0 > 0.0 ? a[0] + t0 * (b[0] - a[0]) : a[0],
        t0 > 0.0 ? a[1] + t0 * (b[1] - a[1]) : a[1]);
    }
    OGR_G_AddPoint_2D(part,
      t1 < 1.0 ? a[0] + t1 * (b[0] - a[0]) : b[0],
      t1 < 1.0 ? a[1] + t1 * (b[1] - a[1]) : b[1]);
    if (t1 < 1.0)
    {
      flush();
    }
  }
  flush();
  return parts;
}

/// `geometry` with every line in it cut to the box (ClipLineString), as a new geometry of the
/// same kind; null when nothing changes. Points and polygons are left to GDAL, whose polygon
/// fill and ALL_TOUCHED outline only visit the raster's own rows and columns.
GeometryPtr ClipLines(OGRGeometryH geometry, const ClipBox& box)
{
  const OGRwkbGeometryType type = wkbFlatten(OGR_G_GetGeometryType(geometry));
  if (type == wkbLineString)
  {
    return ClipLineString(geometry, box);
  }
  if (type != wkbMultiLineString && type != wkbGeometryCollection)
  {
    return nullptr;
  }
  const int n = OGR_G_GetGeometryCount(geometry);
  std::vector<GeometryPtr> clipped(static_cast<std::size_t>(std::max(n, 0)));
  bool changed = false;
  for (int k = 0; k < n; ++k)
  {
    clipped[k] = ClipLines(OGR_G_GetGeometryRef(geometry, k), box);
    changed = changed || clipped[k] != nullptr;
  }
  if (!changed)
  {
    return nullptr;
  }
  GeometryPtr out(OGR_G_CreateGeometry(type));
  auto collection = static_cast<OGRGeometryH>(out.get());
  for (int k = 0; k < n; ++k)
  {
    auto piece = static_cast<OGRGeometryH>(clipped[k].get());
    if (!piece)
    {
      OGR_G_AddGeometry(collection, OGR_G_GetGeometryRef(geometry, k));
    }
    else if (type == wkbMultiLineString)
    {
      for (int p = 0; p < OGR_G_GetGeometryCount(piece); ++p)
      {
        OGR_G_AddGeometry(collection, OGR_G_GetGeometryRef(piece, p));
      }
    }
    else
    {
      OGR_G_AddGeometryDirectly(collection, static_cast<OGRGeometryH>(clipped[k].release()));
    }
  }
  return out;
}

/// Text of every <SrcDataSource> element under `node` (OGR VRT files, unions included).
void CollectVRTSources(const CPLXMLNode* node, std::vector<std::string>& out)
{
  for (; node; node = node->psNext)
  {
    if (node->eType == CXT_Element && EQUAL(node->pszValue, "SrcDataSource"))
    {
      const char* text = CPLGetXMLValue(node, nullptr, nullptr);
      if (text)
      {
        out.emplace_back(text);
      }
    }
    CollectVRTSources(node->psChild, out);
  }
}

/// "refers to '<url>' ..." when the network refusal stopped a request, else "".
std::string RefusedRequest(const terroir::io::detail::ScopedNetworkRefusal* offline)
{
  if (!offline || offline->RefusedURL().empty())
  {
    return std::string();
  }
  return "refers to '" + offline->RefusedURL() +
    "', a network path: refused; turn AllowNetworkPaths on to read it";
}

/// Opens a vector file after the path checks; on failure returns null and sets `error`.
/// `offline` is the caller's ScopedNetworkRefusal, or null when network access is allowed;
/// with one, a dataset that still needs the network (a server driver, a file naming remote or
/// archived data, a request GDAL tried to send) is refused.
DatasetPtr OpenVector(const char* fileName,
  const terroir::io::detail::ScopedNetworkRefusal* offline,
  std::string& error)
{
  const bool allowNetwork = offline == nullptr;
  bool remote = false;
  error = terroir::io::detail::CheckPathToOpen(fileName, allowNetwork, remote);
  if (!error.empty())
  {
    return DatasetPtr();
  }
  const std::string path = fileName;
  // A folder is a vector dataset too (shapefiles, FileGDB); anything else must be a regular,
  // readable file (a FIFO or a device could block the read forever).
  struct stat st;
  const bool folder = ::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
  if (folder && ::access(path.c_str(), R_OK | X_OK) != 0)
  {
    error = std::string("cannot be read (") + std::strerror(errno) + ")";
    return DatasetPtr();
  }
  if (!remote && !folder && path.rfind("/vsimem/", 0) != 0 &&
    !terroir::io::detail::CheckInputFile(path, error))
  {
    return DatasetPtr();
  }
  GDALErrorCapture capture;
  DatasetPtr ds(GDALOpenEx(fileName,
    GDAL_OF_VECTOR | GDAL_OF_READONLY | GDAL_OF_VERBOSE_ERROR,
    nullptr,
    nullptr,
    nullptr));
  if (!ds)
  {
    error = RefusedRequest(offline);
    if (error.empty())
    {
      error = "not a vector file OGR can read" + capture.Suffix();
    }
    return ds;
  }
  if (allowNetwork)
  {
    return ds;
  }
  terroir::io::detail::DatasetSources s =
    terroir::io::detail::ListDatasetSources(ds.get(), terroir::io::detail::IsVectorServerDriver);
  // An OGR VRT opens its sources lazily and lists only itself: read them from the XML.
  if (!s.Server && s.Driver && EQUAL(s.Driver, "OGR_VRT") && !folder)
  {
    CPLXMLNode* xml = CPLParseXMLFile(fileName);
    CollectVRTSources(xml, s.Files);
    CPLDestroyXMLNode(xml);
  }
  error = terroir::io::detail::RefuseNetworkDataset(s.Driver, s.Server, s.Files);
  return error.empty() ? std::move(ds) : DatasetPtr();
}

std::string LayerList(GDALDatasetH ds)
{
  std::string names;
  const int n = GDALDatasetGetLayerCount(ds);
  for (int k = 0; k < n; ++k)
  {
    OGRLayerH layer = GDALDatasetGetLayer(ds, k);
    names += (k ? ", '" : "'") + std::string(layer ? OGR_L_GetName(layer) : "?") + "'";
  }
  return names;
}

std::string NumericFieldList(OGRFeatureDefnH defn)
{
  std::string names;
  for (int k = 0; k < OGR_FD_GetFieldCount(defn); ++k)
  {
    OGRFieldDefnH field = OGR_FD_GetFieldDefn(defn, k);
    const OGRFieldType type = OGR_Fld_GetType(field);
    if (type == OFTInteger || type == OFTInteger64 || type == OFTReal)
    {
      names += (names.empty() ? "'" : ", '") + std::string(OGR_Fld_GetNameRef(field)) + "'";
    }
  }
  return names.empty() ? std::string("none") : names;
}

std::string CRSName(OGRSpatialReferenceH srs)
{
  const char* name = srs ? OSRGetName(srs) : nullptr;
  return name && *name ? name : "unnamed CRS";
}

std::string Number(double v)
{
  std::ostringstream os;
  os.precision(12);
  os << v;
  return os.str();
}

/// Where the terrain's points are on the grid of its geotransform: point (i, j) is GDAL pixel
/// (Col0 + i, Row0 + RowStep * j).
struct Placement
{
  long long Col0 = 0;
  long long Row0 = 0;
  int RowStep = -1;
};

/// Nearest integer to v when v is within 1e-6 of it.
bool NearInteger(double v, long long& n)
{
  if (!std::isfinite(v) || std::fabs(v) > 1e15)
  {
    return false;
  }
  const double r = std::round(v);
  n = static_cast<long long>(r);
  return std::fabs(v - r) <= 1e-6;
}

/// Places the terrain on the grid of its geotransform (see the class comment).
bool Place(vtkImageData* image,
  const int wholeExtent[6],
  const double gt[6],
  OGRSpatialReferenceH srs,
  Placement& p,
  std::string& error)
{
  std::ostringstream gtText;
  gtText.precision(12);
  gtText << "(" << gt[0] << ", " << gt[1] << ", " << gt[2] << ", " << gt[3] << ", " << gt[4] << ", "
         << gt[5] << ")";
  if (gt[2] != 0.0 || gt[4] != 0.0)
  {
    error = "the terrain's TerroirGeoTransform " + gtText.str() +
      " is rotated or sheared; only north-up grids are supported";
    return false;
  }
  if (!(gt[1] > 0.0) || gt[5] == 0.0 || !std::isfinite(gt[1]) || !std::isfinite(gt[5]) ||
    !std::isfinite(gt[0]) || !std::isfinite(gt[3]))
  {
    error = "the terrain's TerroirGeoTransform " + gtText.str() +
      " has no positive finite pixel width, no finite pixel height or no finite origin";
    return false;
  }
  p.RowStep = gt[5] < 0.0 ? -1 : 1;
  if (OSRIsGeographic(srs))
  {
    // Geographic terrains have origin (0, 0) and metric spacings: cells are placed by index.
    if (wholeExtent[0] != 0 || wholeExtent[2] != 0)
    {
      error = "the terrain's whole extent starts at (" + std::to_string(wholeExtent[0]) + ", " +
        std::to_string(wholeExtent[2]) +
        "), not (0, 0): it was cropped after reading, and its geographic TerroirGeoTransform "
        "no longer places it; rasterise onto the terrain as read, then crop";
      return false;
    }
    const long long rows = static_cast<long long>(wholeExtent[3]) + 1;
    vtkDoubleArray* rowSpacing = vtkTerroirGeoreference::GetRowSpacing(image);
    if (rowSpacing && rowSpacing->GetNumberOfTuples() != rows)
    {
      error = "the terrain has " + std::to_string(rows) + " rows but its TerroirRowSpacing " +
        std::to_string(rowSpacing->GetNumberOfTuples()) +
        ": it was cropped after reading, and its geographic TerroirGeoTransform no longer "
        "places it; rasterise onto the terrain as read, then crop";
      return false;
    }
    p.Col0 = 0;
    p.Row0 = p.RowStep < 0 ? rows - 1 : 0;
    return true;
  }
  // Projected (or local) CRS: the image origin and spacing are CRS coordinates in metres.
  const double unit = OSRIsProjected(srs) ? OSRGetLinearUnits(srs, nullptr) : 1.0;
  double spacing[3], origin[3];
  image->GetSpacing(spacing);
  image->GetOrigin(origin);
  const double expectedDx = gt[1] * unit;
  const double expectedDy = std::fabs(gt[5]) * unit;
  if (!(unit > 0.0) || std::fabs(spacing[0] - expectedDx) > 1e-9 * expectedDx ||
    std::fabs(spacing[1] - expectedDy) > 1e-9 * expectedDy)
  {
    error = "the terrain's spacing (" + Number(spacing[0]) + ", " + Number(spacing[1]) +
      ") m is not the (" + Number(expectedDx) + ", " + Number(expectedDy) +
      ") m of its TerroirGeoTransform " + gtText.str() + ": it was resampled after reading";
    return false;
  }
  const double col0 = (origin[0] / unit - gt[0]) / gt[1] - 0.5;
  const double row0 = (origin[1] / unit - gt[3]) / gt[5] - 0.5;
  if (!NearInteger(col0, p.Col0) || !NearInteger(row0, p.Row0))
  {
    error = "the terrain's origin (" + Number(origin[0]) + ", " + Number(origin[1]) +
      ") m is not a cell centre of its TerroirGeoTransform " + gtText.str() +
      "; as vtkTerroirDEMReader does, set it to the south-west cell centre in CRS metres";
    return false;
  }
  return true;
}

int CPL_STDCALL RasterizeProgress(double fraction, const char*, void* data)
{
  auto* self = static_cast<vtkTerroirVectorRasterizer*>(data);
  self->UpdateProgress(0.2 + 0.7 * fraction);
  return self->GetAbortExecute() ? FALSE : TRUE;
}

/// "" when the burn value and the output array name are usable, else the problem.
std::string ParameterProblem(bool useAttribute, double burnValue, const char* outputArrayName)
{
  if (!useAttribute && !std::isfinite(burnValue))
  {
    return "BurnValue " + Number(burnValue) + " is not a finite number";
  }
  if (!outputArrayName || !*outputArrayName)
  {
    return "OutputArrayName is empty";
  }
  return std::string();
}

/// The terrain's grid: its extent, geotransform, CRS and place on the geotransform's grid.
struct TerrainGrid
{
  int Extent[6] = { 0, -1, 0, -1, 0, -1 };
  double GT[6] = { 0.0, 1.0, 0.0, 0.0, 0.0, 1.0 };
  SRSPtr SRSOwner;
  OGRSpatialReferenceH SRS = nullptr;
  Placement Place;
  int NX = 0;
  int NY = 0;
  vtkIdType Cells = 0;
};

/// Parses the terrain's TerroirCRS (WKT only) into grid.SRS, in GIS axis order.
bool ParseTerrainCRS(const std::string& wkt, TerrainGrid& grid, std::string& error)
{
  grid.SRSOwner.reset(OSRNewSpatialReference(nullptr));
  grid.SRS = static_cast<OGRSpatialReferenceH>(grid.SRSOwner.get());
  {
    GDALErrorCapture capture;
    // WKT only: OSRSetFromUserInput would also take file names and URLs.
    char* text = const_cast<char*>(wkt.c_str());
    if (OSRImportFromWkt(grid.SRS, &text) != OGRERR_NONE)
    {
      error = "the terrain's TerroirCRS cannot be parsed" + capture.Suffix();
      return false;
    }
  }
  OSRSetAxisMappingStrategy(grid.SRS, OAMS_TRADITIONAL_GIS_ORDER);
  return true;
}

/// Checks that the input is a georeferenced 2-D terrain and places it (see Place).
bool ReadTerrainGrid(vtkImageData* input,
  vtkInformation* inInfo,
  TerrainGrid& grid,
  std::string& error)
{
  int* extent = grid.Extent;
  input->GetExtent(extent);
  if (input->GetNumberOfPoints() < 1)
  {
    error = "the input terrain is empty";
    return false;
  }
  if (extent[4] != extent[5])
  {
    error = "the input is not a 2-D terrain (an image of nx x ny x 1 points)";
    return false;
  }
  const std::string wkt = vtkTerroirGeoreference::GetCRS(input);
  const bool hasGT = vtkTerroirGeoreference::GetGeoTransform(input, grid.GT);
  if (wkt.empty() || !hasGT)
  {
    error = std::string("the terrain has no georeference (") +
      (wkt.empty() && !hasGT ? "TerroirCRS and TerroirGeoTransform are"
          : wkt.empty()      ? "TerroirCRS is"
                             : "TerroirGeoTransform is") +
      " missing): it must come from a georeferenced DEM (vtkTerroirDEMReader with a CRS)";
    return false;
  }
  if (!ParseTerrainCRS(wkt, grid, error))
  {
    return false;
  }
  int wholeExtent[6];
  std::copy(extent, extent + 6, wholeExtent);
  if (inInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
  {
    inInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), wholeExtent);
  }
  if (!Place(input, wholeExtent, grid.GT, grid.SRS, grid.Place, error))
  {
    return false;
  }
  grid.NX = extent[1] - extent[0] + 1;
  grid.NY = extent[3] - extent[2] + 1;
  grid.Cells = static_cast<vtkIdType>(grid.NX) * grid.NY;
  return true;
}

/// The layer to burn, the attribute field of the burn values (-1: every feature burns
/// BurnValue) and the attribute filter set on the layer (null when none).
struct VectorLayer
{
  OGRLayerH Layer = nullptr;
  std::string Name;
  int Field = -1;
  const char* Filter = nullptr;
};

/// The index of the numeric field `attributeName` of the layer; -1 with `error` set when the
/// layer has no such field or it is not a number.
int NumericField(OGRFeatureDefnH defn,
  const char* attributeName,
  const std::string& layerName,
  std::string& error)
{
  const int field = OGR_FD_GetFieldIndex(defn, attributeName);
  if (field < 0)
  {
    error = std::string("no attribute '") + attributeName + "' in layer '" + layerName +
      "' (numeric attributes: " + NumericFieldList(defn) + ")";
    return -1;
  }
  const OGRFieldType type = OGR_Fld_GetType(OGR_FD_GetFieldDefn(defn, field));
  if (type != OFTInteger && type != OFTInteger64 && type != OFTReal)
  {
    error = std::string("attribute '") + attributeName + "' of layer '" + layerName + "' is a " +
      OGR_GetFieldTypeName(type) +
      " field, not a number (numeric attributes: " + NumericFieldList(defn) + ")";
    return -1;
  }
  return field;
}

/// Picks the layer (by name, else the first), its attribute field (when `attributeName` is not
/// null) and sets the attribute filter (when not empty); `capture` holds GDAL's messages.
bool ChooseLayer(GDALDatasetH dataset,
  const char* layerName,
  const char* attributeName,
  const char* attributeFilter,
  const GDALErrorCapture& capture,
  VectorLayer& out,
  std::string& error)
{
  if (GDALDatasetGetLayerCount(dataset) < 1)
  {
    error = "holds no vector layer";
    return false;
  }
  OGRLayerH layer = nullptr;
  if (layerName && *layerName)
  {
    layer = GDALDatasetGetLayerByName(dataset, layerName);
    if (!layer)
    {
      error = std::string("no layer '") + layerName + "' (layers: " + LayerList(dataset) + ")";
      return false;
    }
  }
  else
  {
    layer = GDALDatasetGetLayer(dataset, 0);
  }
  out.Layer = layer;
  out.Name = OGR_L_GetName(layer);
  OGRFeatureDefnH defn = OGR_L_GetLayerDefn(layer);
  if (attributeName)
  {
    out.Field = NumericField(defn, attributeName, out.Name, error);
    if (out.Field < 0)
    {
      return false;
    }
  }
  const bool filtered = attributeFilter && *attributeFilter;
  if (filtered && OGR_L_SetAttributeFilter(layer, attributeFilter) != OGRERR_NONE)
  {
    error = std::string("invalid attribute filter '") + attributeFilter + "'" + capture.Suffix();
    return false;
  }
  out.Filter = filtered ? attributeFilter : nullptr;
  return true;
}

/// The layer's CRS (null when it has none) and the transformation from it to the terrain's
/// (null when none is needed).
struct LayerTransform
{
  CTPtr CT;
  SRSPtr LayerSRS;
};

/// Finds how the layer's coordinates reach the terrain's CRS; `warning` is set when the layer
/// has no CRS (its coordinates are then taken as they are).
bool TransformToTerrain(const VectorLayer& layer,
  OGRSpatialReferenceH terrainSRS,
  LayerTransform& t,
  std::string& warning,
  std::string& error)
{
  OGRSpatialReferenceH layerSRS = OGR_L_GetSpatialRef(layer.Layer);
  t.LayerSRS.reset(layerSRS ? OSRClone(layerSRS) : nullptr);
  layerSRS = static_cast<OGRSpatialReferenceH>(t.LayerSRS.get());
  if (!layerSRS)
  {
    warning = "layer '" + layer.Name +
      "' has no CRS: its coordinates are taken as already in the terrain's CRS (" +
      CRSName(terrainSRS) + ")";
    return true;
  }
  OSRSetAxisMappingStrategy(layerSRS, OAMS_TRADITIONAL_GIS_ORDER);
  if (!OSRIsSame(layerSRS, terrainSRS))
  {
    t.CT.reset(OCTNewCoordinateTransformation(layerSRS, terrainSRS));
    if (!t.CT)
    {
      // GDAL's message only repeats both CRSs as WKT: their names say it in one line.
      error = "cannot transform coordinates from the layer's CRS (" + CRSName(layerSRS) +
        ") to the terrain's (" + CRSName(terrainSRS) + ")";
      return false;
    }
  }
  return true;
}

/// The vector file while it is read: the network refusal (null when network paths are
/// allowed), the dataset, GDAL's messages since it was opened, the layer and how its
/// coordinates reach the terrain's CRS. Members go in reverse order, the refusal last.
struct VectorSource
{
  std::unique_ptr<terroir::io::detail::ScopedNetworkRefusal> Offline;
  DatasetPtr Dataset;
  std::unique_ptr<GDALErrorCapture> Capture;
  VectorLayer Layer;
  LayerTransform Transform;
};

/// Opens the vector file (OpenVector), picks its layer (ChooseLayer) and finds how its
/// coordinates reach the terrain's CRS (TransformToTerrain, which may set `warning`).
bool OpenSource(const char* fileName,
  bool allowNetwork,
  const char* layerName,
  const char* attributeName,
  const char* attributeFilter,
  OGRSpatialReferenceH terrainSRS,
  VectorSource& source,
  std::string& warning,
  std::string& error)
{
  if (!allowNetwork)
  {
    source.Offline.reset(new terroir::io::detail::ScopedNetworkRefusal);
  }
  source.Dataset = OpenVector(fileName, source.Offline.get(), error);
  if (!source.Dataset)
  {
    return false;
  }
  source.Capture.reset(new GDALErrorCapture);
  return ChooseLayer(static_cast<GDALDatasetH>(source.Dataset.get()),
           layerName,
           attributeName,
           attributeFilter,
           *source.Capture,
           source.Layer,
           error) &&
    TransformToTerrain(source.Layer, terrainSRS, source.Transform, warning, error);
}

/// What is burnt: the geometries in the terrain's CRS, their burn values, and how many
/// features were left out for having no value.
struct BurnList
{
  std::vector<GeometryPtr> Geometries;
  std::vector<double> Values;
  vtkIdType NullValues = 0;
};

/// A copy of the feature's geometry (curves made linear) in the terrain's CRS; null with
/// `error` set when it cannot be copied or transformed.
GeometryPtr TerrainGeometry(OGRFeatureH f,
  OGRGeometryH geometry,
  const std::string& layerName,
  const LayerTransform& t,
  OGRSpatialReferenceH terrainSRS,
  const GDALErrorCapture& reading,
  std::string& error)
{
  GeometryPtr copy(OGR_G_HasCurveGeometry(geometry, TRUE)
      ? OGR_G_GetLinearGeometry(geometry, 0.0, nullptr)
      : OGR_G_Clone(geometry));
  if (!copy)
  {
    error = "feature " + std::to_string(static_cast<long long>(OGR_F_GetFID(f))) + " of layer '" +
      layerName + "' has a geometry that cannot be copied" + reading.Suffix();
    return nullptr;
  }
  auto ct = static_cast<OGRCoordinateTransformationH>(t.CT.get());
  if (ct && OGR_G_Transform(static_cast<OGRGeometryH>(copy.get()), ct) != OGRERR_NONE)
  {
    error = "feature " + std::to_string(static_cast<long long>(OGR_F_GetFID(f))) + " of layer '" +
      layerName + "' cannot be transformed from " +
      CRSName(static_cast<OGRSpatialReferenceH>(t.LayerSRS.get())) + " to the terrain's CRS (" +
      CRSName(terrainSRS) + ")" + reading.Suffix();
    return nullptr;
  }
  return copy;
}

/// Reads the layer's features with a geometry (and a value, when burning an attribute) into
/// `burn`, in the terrain's CRS.
bool ReadFeatures(const VectorLayer& layer,
  double burnValue,
  const LayerTransform& t,
  OGRSpatialReferenceH terrainSRS,
  BurnList& burn,
  std::string& error)
{
  GDALErrorCapture reading;
  OGR_L_ResetReading(layer.Layer);
  for (FeaturePtr feature(OGR_L_GetNextFeature(layer.Layer)); feature;
       feature.reset(OGR_L_GetNextFeature(layer.Layer)))
  {
    auto f = static_cast<OGRFeatureH>(feature.get());
    OGRGeometryH geometry = OGR_F_GetGeometryRef(f);
    if (!geometry || OGR_G_IsEmpty(geometry))
    {
      continue;
    }
    double value = burnValue;
    if (layer.Field >= 0)
    {
      if (!OGR_F_IsFieldSetAndNotNull(f, layer.Field))
      {
        ++burn.NullValues;
        continue;
      }
      value = OGR_F_GetFieldAsDouble(f, layer.Field);
    }
    GeometryPtr copy = TerrainGeometry(f, geometry, layer.Name, t, terrainSRS, reading, error);
    if (!copy)
    {
      return false;
    }
    burn.Geometries.push_back(std::move(copy));
    burn.Values.push_back(value);
  }
  if (reading.Failed())
  {
    // A driver that fails half-way through a file reports it here, not by a null feature.
    // SQL drivers (GeoPackage, SQLite) accept any filter and compile it at the first read.
    if (layer.Filter && burn.Geometries.empty() && burn.NullValues == 0)
    {
      error = std::string("invalid attribute filter '") + layer.Filter + "'" + reading.Suffix();
    }
    else
    {
      error = "reading the features of layer '" + layer.Name + "' failed" + reading.Suffix();
    }
    return false;
  }
  return true;
}

/// The in-memory raster GDAL burns into: the terrain's cells, its row 0 the upper one.
struct MemRaster
{
  DatasetPtr Owner;
  GDALRasterBandH Band = nullptr;
  double GT[6] = { 0.0, 1.0, 0.0, 0.0, 0.0, 1.0 };
  long long RowTop = 0; // the GDAL row of the MEM raster's row 0
};

/// Creates the MEM raster (byte or float32) over the terrain's cells, filled with the
/// background (0 or NaN).
bool CreateMemRaster(const TerrainGrid& grid,
  bool asByte,
  const GDALErrorCapture& capture,
  MemRaster& mem,
  std::string& error)
{
  const Placement& place = grid.Place;
  const double* gt = grid.GT;
  // GDAL rows of the terrain's first and last rows; the MEM raster's row 0 is the upper one.
  const long long rowA = place.Row0 + static_cast<long long>(place.RowStep) * grid.Extent[2];
  const long long rowB = place.Row0 + static_cast<long long>(place.RowStep) * grid.Extent[3];
  mem.RowTop = std::min(rowA, rowB);
  const long long colLeft = place.Col0 + grid.Extent[0];
  GDALDriverH memDriver = GDALGetDriverByName("MEM");
  mem.Owner.reset(memDriver
      ? GDALCreate(memDriver, "", grid.NX, grid.NY, 1, asByte ? GDT_Byte : GDT_Float32, nullptr)
      : nullptr);
  if (!mem.Owner)
  {
    error = "cannot create the in-memory raster" + capture.Suffix();
    return false;
  }
  auto dataset = static_cast<GDALDatasetH>(mem.Owner.get());
  const double memGT[6] = { gt[0] + static_cast<double>(colLeft) * gt[1],
    gt[1],
    0.0,
    gt[3] + static_cast<double>(mem.RowTop) * gt[5],
    0.0,
    gt[5] };
  std::copy(memGT, memGT + 6, mem.GT);
  GDALSetGeoTransform(dataset, mem.GT);
  mem.Band = GDALGetRasterBand(dataset, 1);
  const double background = asByte ? 0.0 : std::numeric_limits<double>::quiet_NaN();
  GDALFillRaster(mem.Band, background, 0.0);
  return true;
}

/// Cuts the lines among the geometries to the MEM raster grown by kLineMarginCells.
void ClipToMargin(const MemRaster& mem, int nx, int ny, std::vector<GeometryPtr>& geometries)
{
  const double* memGT = mem.GT;
  const double m = kLineMarginCells;
  const double xa = memGT[0] - m * memGT[1];
  const double xb = memGT[0] + (nx + m) * memGT[1];
  const double ya = memGT[3] - m * memGT[5];
  const double yb = memGT[3] + (ny + m) * memGT[5];
  const ClipBox box{ std::min(xa, xb), std::max(xa, xb), std::min(ya, yb), std::max(ya, yb) };
  for (GeometryPtr& g : geometries)
  {
    if (GeometryPtr clipped = ClipLines(static_cast<OGRGeometryH>(g.get()), box))
    {
      g = std::move(clipped);
    }
  }
}

/// Burns every geometry with its value into the MEM raster (lines cut first, see
/// ClipToMargin); progress and abort go through `self`.
bool BurnGeometries(vtkTerroirVectorRasterizer* self,
  bool allTouched,
  const TerrainGrid& grid,
  const MemRaster& mem,
  BurnList& burn,
  const GDALErrorCapture& capture,
  std::string& error)
{
  ClipToMargin(mem, grid.NX, grid.NY, burn.Geometries);
  std::vector<OGRGeometryH> handles(burn.Geometries.size());
  std::transform(burn.Geometries.begin(),
    burn.Geometries.end(),
    handles.begin(),
    [](const GeometryPtr& g) { return static_cast<OGRGeometryH>(g.get()); });
  int bandList[1] = { 1 };
  char** options = nullptr;
  if (allTouched)
  {
    options = CSLSetNameValue(options, "ALL_TOUCHED", "TRUE");
  }
  const CPLErr err = GDALRasterizeGeometries(static_cast<GDALDatasetH>(mem.Owner.get()),
    1,
    bandList,
    static_cast<int>(handles.size()),
    handles.data(),
    nullptr,
    nullptr,
    burn.Values.data(),
    options,
    &RasterizeProgress,
    self);
  CSLDestroy(options);
  if (err != CE_None)
  {
    error = self->GetAbortExecute() ? std::string("rasterisation aborted")
                                    : "rasterisation failed" + capture.Suffix();
    return false;
  }
  return true;
}

/// A new output array, unsigned char or float, named `name`, with `cells` values and no unit.
vtkSmartPointer<vtkDataArray> NewBurnArray(bool asByte, const char* name, vtkIdType cells)
{
  vtkSmartPointer<vtkDataArray> array;
  if (asByte)
  {
    array = vtkSmartPointer<vtkUnsignedCharArray>::New();
  }
  else
  {
    array = vtkSmartPointer<vtkFloatArray>::New();
  }
  array->SetName(name);
  array->SetNumberOfTuples(cells);
  array->GetInformation()->Set(vtkDataArray::UNITS_LABEL(), "");
  return array;
}

/// Copies the MEM raster's rows into the array in VTK order (j = 0 south).
bool CopyRows(const MemRaster& mem,
  const TerrainGrid& grid,
  bool asByte,
  vtkDataArray* array,
  const GDALErrorCapture& capture,
  std::string& error)
{
  const int* extent = grid.Extent;
  const int nx = grid.NX;
  const int cellBytes = asByte ? 1 : 4;
  auto* base = static_cast<unsigned char*>(array->GetVoidPointer(0));
  for (int j = extent[2]; j <= extent[3]; ++j)
  {
    const long long memRow =
      grid.Place.Row0 + static_cast<long long>(grid.Place.RowStep) * j - mem.RowTop;
    void* dst = base + static_cast<std::size_t>(j - extent[2]) * nx * cellBytes;
    if (GDALRasterIO(mem.Band,
          GF_Read,
          0,
          static_cast<int>(memRow),
          nx,
          1,
          dst,
          nx,
          1,
          asByte ? GDT_Byte : GDT_Float32,
          0,
          0) != CE_None)
    {
      error = "reading the in-memory raster failed" + capture.Suffix();
      return false;
    }
  }
  return true;
}

/// The cells burnt: non-zero bytes, or floats that are not NaN.
vtkIdType CountCovered(vtkDataArray* array, bool asByte, vtkIdType cells)
{
  const auto* base = static_cast<const unsigned char*>(array->GetVoidPointer(0));
  if (asByte)
  {
    const unsigned char* v = base;
    return static_cast<vtkIdType>(std::count_if(v, v + cells, [](unsigned char c) { return c; }));
  }
  const auto* v = reinterpret_cast<const float*>(base);
  return static_cast<vtkIdType>(
    std::count_if(v, v + cells, [](float x) { return !std::isnan(x); }));
}

/// The warnings on what was burnt: features without a value, no feature, no cell covered.
std::vector<std::string> BurnWarnings(const VectorLayer& layer,
  const char* attributeName,
  const BurnList& burn,
  vtkIdType covered)
{
  std::vector<std::string> warnings;
  if (burn.NullValues > 0)
  {
    warnings.push_back(std::to_string(static_cast<long long>(burn.NullValues)) +
      " feature(s) of layer '" + layer.Name + "' have no value in '" + attributeName +
      "' and were left out");
  }
  if (burn.Geometries.empty())
  {
    warnings.push_back("layer '" + layer.Name + "' has no feature with a geometry" +
      (layer.Filter ? std::string(" matching the filter '") + layer.Filter + "'" : std::string()) +
      ": nothing burnt");
  }
  else if (covered == 0)
  {
    warnings.push_back("none of the " +
      std::to_string(static_cast<long long>(burn.Geometries.size())) + " features of layer '" +
      layer.Name + "' covers a cell of the terrain: nothing burnt");
  }
  return warnings;
}
} // namespace

vtkTerroirVectorRasterizer::vtkTerroirVectorRasterizer()
{
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(1);
  this->SetOutputArrayName("Mask");
  GDALAllRegister();
}

vtkTerroirVectorRasterizer::~vtkTerroirVectorRasterizer()
{
  this->SetFileName(nullptr);
  this->SetLayerName(nullptr);
  this->SetAttributeFilter(nullptr);
  this->SetAttributeName(nullptr);
  this->SetOutputArrayName(nullptr);
}

void vtkTerroirVectorRasterizer::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  auto text = [](const char* s) { return s ? s : "(none)"; };
  os << indent << "FileName: " << text(this->FileName) << "\n";
  os << indent << "LayerName: " << text(this->LayerName) << "\n";
  os << indent << "AttributeFilter: " << text(this->AttributeFilter) << "\n";
  os << indent << "BurnValue: " << this->BurnValue << "\n";
  os << indent << "AttributeName: " << text(this->AttributeName) << "\n";
  os << indent << "OutputArrayName: " << text(this->OutputArrayName) << "\n";
  os << indent << "AllTouched: " << this->AllTouched << "\n";
  os << indent << "AllowNetworkPaths: " << this->AllowNetworkPaths << "\n";
  os << indent << "ErrorMessage: " << this->ErrorMessage << "\n";
  os << indent << "NumberOfFeatures: " << this->NumberOfFeatures << "\n";
  os << indent << "NumberOfCoveredCells: " << this->NumberOfCoveredCells << "\n";
}

void vtkTerroirVectorRasterizer::Fail(const std::string& problem)
{
  this->ErrorMessage = terroir::io::detail::FileError(this->FileName, problem);
  vtkErrorMacro(<< this->ErrorMessage);
}

void vtkTerroirVectorRasterizer::Warn(const std::string& problem)
{
  vtkWarningMacro(<< terroir::io::detail::FileError(this->FileName, problem));
}

int vtkTerroirVectorRasterizer::RequestData(vtkInformation*,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  vtkImageData* input = vtkImageData::GetData(inputVector[0], 0);
  vtkImageData* output = vtkImageData::GetData(outputVector, 0);
  output->Initialize();
  this->ErrorMessage.clear();
  this->NumberOfFeatures = 0;
  this->NumberOfCoveredCells = 0;

  // --- Parameters and the terrain --------------------------------------------------------
  const bool useAttribute = this->AttributeName && *this->AttributeName;
  std::string error = ParameterProblem(useAttribute, this->BurnValue, this->OutputArrayName);
  TerrainGrid grid;
  if (!error.empty() ||
    !ReadTerrainGrid(input, inputVector[0]->GetInformationObject(0), grid, error))
  {
    this->Fail(error);
    return 0;
  }
  const bool asByte = !useAttribute && this->BurnValue >= 1.0 && this->BurnValue <= 255.0 &&
    this->BurnValue == std::floor(this->BurnValue);
  const int cellBytes = asByte ? 1 : 4;
  // The MEM raster and the output array.
  error = terroir::CheckMemory(
    2.0 * cellBytes * static_cast<double>(grid.Cells), "rasterising the layer");
  if (!error.empty())
  {
    this->Fail(error);
    return 0;
  }

  // --- The vector file, its layer, filter, attribute and CRS ------------------------------
  VectorSource source;
  std::string warning;
  if (!OpenSource(this->FileName,
        this->AllowNetworkPaths,
        this->LayerName,
        useAttribute ? this->AttributeName : nullptr,
        this->AttributeFilter,
        grid.SRS,
        source,
        warning,
        error))
  {
    this->Fail(error);
    return 0;
  }
  if (!warning.empty())
  {
    this->Warn(warning);
  }
  const VectorLayer& layer = source.Layer;
  const GDALErrorCapture& capture = *source.Capture;

  // --- Features: geometries in the terrain's CRS and their burn values ----------------------
  BurnList burn;
  if (!ReadFeatures(layer, this->BurnValue, source.Transform, grid.SRS, burn, error))
  {
    this->Fail(error);
    return 0;
  }
  error = RefusedRequest(source.Offline.get());
  if (!error.empty())
  {
    this->Fail(error);
    return 0;
  }
  this->NumberOfFeatures = static_cast<vtkIdType>(burn.Geometries.size());
  this->UpdateProgress(0.2);

  // --- Burn into a MEM raster with the terrain's cells --------------------------------------
  MemRaster mem;
  if (!CreateMemRaster(grid, asByte, capture, mem, error) ||
    (!burn.Geometries.empty() &&
      !BurnGeometries(this, this->AllTouched, grid, mem, burn, capture, error)))
  {
    this->Fail(error);
    return 0;
  }

  // --- Rows into VTK order (j = 0 south) -----------------------------------------------------
  vtkSmartPointer<vtkDataArray> array = NewBurnArray(asByte, this->OutputArrayName, grid.Cells);
  if (!CopyRows(mem, grid, asByte, array, capture, error))
  {
    this->Fail(error);
    return 0;
  }
  const vtkIdType covered = CountCovered(array, asByte, grid.Cells);
  this->NumberOfCoveredCells = covered;
  for (const std::string& w : BurnWarnings(layer, this->AttributeName, burn, covered))
  {
    this->Warn(w);
  }

  output->ShallowCopy(input);
  output->GetPointData()->AddArray(array);
  this->UpdateProgress(1.0);
  return 1;
}

/**
 * @class   vtkTerroirVectorRasterizer
 * @brief   Burns the features of an OGR vector file (polygons, lines, points) onto a
 *          terrain's grid, as one point-data array.
 *
 * Input (port 0): a Terroir terrain, a 2-D vtkImageData (nx, ny, 1) with the georeference
 * field arrays of vtkTerroirGeoreference: `TerroirCRS` (WKT) and `TerroirGeoTransform` (the
 * GDAL geotransform of the DEM file, north-up), as vtkTerroirDEMReader writes them.
 * Output: a shallow copy of the input (every array passes through) plus one point array named
 * OutputArrayName (default `Mask`; an input array of that name is replaced), UNITS_LABEL "":
 * - vtkUnsignedCharArray when AttributeName is empty and BurnValue is an integer in 1..255:
 *   BurnValue on covered cells, 0 elsewhere;
 * - vtkFloatArray otherwise (an attribute, or a BurnValue that is 0, negative, fractional or
 *   above 255): the burnt value on covered cells, NaN on cells no feature covers.
 * Row j = 0 is the south row, as everywhere in Terroir (GDAL's row 0 is the north one).
 *
 * Which cells a feature covers (GDAL's rasterisation, as `gdal_rasterize`):
 * - AllTouched off (default): polygons cover the cells whose centre is inside; lines the cells
 *   of their Bresenham path from the cell holding one vertex to the cell holding the next;
 *   points the cell that holds them.
 * - AllTouched on (GDAL's ALL_TOUCHED=TRUE): every cell a polygon or a line touches at all.
 * Lines are first cut 1024 cells outside the terrain (GDAL's Bresenham walk visits every cell
 * between two vertices; a vertex 1e9 cells away took seconds); vertices within that margin are
 * kept exactly, so real data burns as gdal_rasterize burns it.
 * Where features overlap, the later one in the layer wins (GDAL's MERGE_ALG=REPLACE).
 * Features whose attribute is null are left out (with a warning).
 *
 * Coordinates: each geometry is transformed from the layer's CRS into the terrain's with an
 * OGR coordinate transformation (both CRSs with OAMS_TRADITIONAL_GIS_ORDER, so x = easting or
 * longitude); a layer without CRS is taken as already in the terrain's CRS (with a warning).
 * The geometries are burnt with GDALRasterizeGeometries into an in-memory (MEM) raster that has
 * the terrain's cells and geotransform, then rows are copied south first. The cells are located
 * from the image itself: for a projected CRS the image origin and spacing (metres) must be
 * those the geotransform gives (origin = a cell centre, spacing = |pixel size| x CRS unit), and
 * any extent, a sub-extent or a crop included, is placed by position; for a geographic CRS
 * (origin (0, 0)) the whole extent must start at (0, 0) and, when `TerroirRowSpacing` is
 * present, have its rows, and a sub-extent is placed by its indices.
 *
 * Errors (one line "<FileName>: <problem>", GetErrorMessage() and vtkErrorMacro, empty output):
 * no file name, missing or unreadable file, not a vector file OGR reads, network or archive
 * paths and local files that name remote data (unless AllowNetworkPaths), no layer, layer not
 * found (the available ones are listed), attribute not found or not numeric, invalid attribute
 * filter, input not a 2-D image, terrain without georeference, a georeference that does not
 * match the image (rotated geotransform, spacing or origin off the geotransform's grid), a CRS
 * transformation that cannot be made or fails on a feature, not enough memory. A layer with no
 * feature (after the filter) or whose features all fall outside the terrain is a warning, and
 * the array is all 0 (or all NaN).
 *
 * @par Correctness
 * Testing/Pipeline/TestTerroirVectorRasterizer.cxx (TerroirVectorRasterizer.*): cells worked
 * out by hand on a synthetic UTM grid (centre rule, row order north = high j, Bresenham line,
 * ALL_TOUCHED widening, attributes, attribute filter, a lon/lat twin of a UTM polygon,
 * sub-extents); agreement with the shipped `gdal_rasterize` masks of the bundled Sagehen
 * watershed and NHD flowlines (also through a NAD83 GeoPackage, and onto the geographic DEM
 * against GeographicLib projections); every error case. Testing/Pipeline/TestDeterminism.cxx.
 * Testing/Fuzz/FuzzVectorRasterizer.cxx (any vector file, fuzzed options).
 *
 * @par References
 * GDAL/OGR, https://gdal.org (GDALRasterizeGeometries, gdal_rasterize).
 *
 * @sa vtkTerroirDEMReader vtkTerroirGeoreference vtkTerroirInfiltration
 */
#ifndef vtkTerroirVectorRasterizer_h
#define vtkTerroirVectorRasterizer_h

#include "vtkImageAlgorithm.h"
#include "vtkTerroirIOModule.h" // For export macro

#include <string> // For std::string

class VTKTERROIRIO_EXPORT vtkTerroirVectorRasterizer : public vtkImageAlgorithm
{
public:
  static vtkTerroirVectorRasterizer* New();
  vtkTypeMacro(vtkTerroirVectorRasterizer, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The vector file (any OGR vector format: GeoJSON, shapefile, GeoPackage, ...). Default: none.
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  ///@}

  ///@{
  /// The layer to burn; empty or null = the first layer. Default: empty.
  vtkSetStringMacro(LayerName);
  vtkGetStringMacro(LayerName);
  ///@}

  ///@{
  /// OGR SQL WHERE clause selecting the features (e.g. "FCODE = 46006"); empty or null = all.
  /// Default: empty.
  vtkSetStringMacro(AttributeFilter);
  vtkGetStringMacro(AttributeFilter);
  ///@}

  ///@{
  /// Value burnt on covered cells when AttributeName is empty. Default: 1 (unsigned char
  /// output; see the class comment for when the output is float).
  vtkSetMacro(BurnValue, double);
  vtkGetMacro(BurnValue, double);
  ///@}

  ///@{
  /// Numeric attribute (integer or real field) whose value each feature burns instead of
  /// BurnValue; empty or null = BurnValue. The output is then float, NaN where not covered.
  /// Default: empty.
  vtkSetStringMacro(AttributeName);
  vtkGetStringMacro(AttributeName);
  ///@}

  ///@{
  /// Name of the output point array. Default: "Mask".
  vtkSetStringMacro(OutputArrayName);
  vtkGetStringMacro(OutputArrayName);
  ///@}

  ///@{
  /// Off: cell centres inside polygons, Bresenham cells for lines. On: every cell a polygon or
  /// line touches (GDAL's ALL_TOUCHED). Default: off.
  vtkSetMacro(AllTouched, bool);
  vtkGetMacro(AllTouched, bool);
  vtkBooleanMacro(AllTouched, bool);
  ///@}

  ///@{
  /// Allow GDAL network and archive paths (/vsicurl/, /vsizip/, http://, ...), server drivers
  /// (WFS, OGC API, databases) and local files that name remote data. Default: off.
  vtkSetMacro(AllowNetworkPaths, bool);
  vtkGetMacro(AllowNetworkPaths, bool);
  vtkBooleanMacro(AllowNetworkPaths, bool);
  ///@}

  /// The last error as one line "<file>: <problem>", or "" after a successful run.
  const char* GetErrorMessage() const { return this->ErrorMessage.c_str(); }

  /// Features rasterised by the last run (those with a geometry that pass the attribute filter
  /// and have a value), whether or not they fall on the terrain.
  vtkGetMacro(NumberOfFeatures, vtkIdType);

  /// Cells the last run covered (non-zero, or not NaN).
  vtkGetMacro(NumberOfCoveredCells, vtkIdType);

protected:
  vtkTerroirVectorRasterizer();
  ~vtkTerroirVectorRasterizer() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* FileName = nullptr;
  char* LayerName = nullptr;
  char* AttributeFilter = nullptr;
  double BurnValue = 1.0;
  char* AttributeName = nullptr;
  char* OutputArrayName = nullptr;
  bool AllTouched = false;
  bool AllowNetworkPaths = false;
  std::string ErrorMessage;
  vtkIdType NumberOfFeatures = 0;
  vtkIdType NumberOfCoveredCells = 0;

private:
  vtkTerroirVectorRasterizer(const vtkTerroirVectorRasterizer&) = delete;
  void operator=(const vtkTerroirVectorRasterizer&) = delete;

  void Fail(const std::string& problem);
  void Warn(const std::string& problem);
};

#endif

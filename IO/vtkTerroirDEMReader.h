/**
 * @class   vtkTerroirDEMReader
 * @brief   Reads any raster DEM that GDAL reads (GeoTIFF, Erdas Imagine `.img`, USGS ASCII
 *          `.dem`, ...) into a georeferenced Terroir terrain.
 *
 * Output: vtkImageData (nx, ny, 1), point array `Elevation` (float32, metres; band values
 * times the band's GDAL scale plus offset, times 0.3048 (or 1200/3937) when the band unit is
 * feet or the CRS's vertical unit is feet, or when VerticalUnit says so for a file that does
 * not), and, when some cells are no-data (the band's
 * nodata value, or NaN), `vtkValidPointMask` (unsigned char, 1 = valid) with NaN in
 * `Elevation` at those cells; values that are infinite, or larger than 1e30 m in magnitude
 * (float sentinels such as ESRI's -3.4e38 left undeclared), are no-data too. Row j = 0 is
 * the SOUTH row (GDAL's row 0, the north one, becomes j = ny - 1 for north-up rasters). Field
 * data (see vtkTerroirGeoreference): `TerroirCRS` (WKT), `TerroirGeoTransform` (as in the file),
 * `TerroirCenterLatLon`, `TerroirMeridianConvergence` (degrees), `TerroirSourceFile`, and for
 * geographic grids `TerroirRowSpacing`.
 *
 * - Projected CRS: spacing = |pixel size| times the CRS linear unit (metres), origin = the
 *   south-west cell centre in CRS coordinates converted to metres. Meridian convergence at
 *   the grid centre: for UTM, GeographicLib::TransverseMercator on the CRS ellipsoid; for
 *   other projections the centre and points 0.5 CRS units south and north of it are
 *   transformed to geographic coordinates with OGR and the grid-north bearing is the mean of
 *   the end azimuths of the geodesic between them (GeographicLib::Geodesic::Inverse).
 * - Geographic CRS: origin (0, 0); for every row the east-west spacing is the geodesic
 *   distance between the centres of two neighbouring cells of the row, and the north-south
 *   spacing the geodesic distance across one cell height centred on the row, on the CRS
 *   ellipsoid; both are stored in `TerroirRowSpacing` (ny x 2, j = 0 south) and the image
 *   spacing is that of row ny/2; convergence 0.
 * - No CRS: error when RequireGeoreference is on; otherwise a warning, spacing = |pixel
 *   size| taken as metres, no georeference arrays but the geotransform.
 *
 * RequestInformation reports WHOLE_EXTENT, spacing and origin without reading pixels, and
 * CAN_PRODUCE_SUB_EXTENT: RequestData reads only the UPDATE_EXTENT asked for (one GDAL window;
 * GetReadExtent() says which), so under pvbatch + MPI each rank reads its piece and its ghost
 * cells. Spacing, origin and the georeference field data are those of the whole raster on every
 * piece, and a cell's value and validity do not depend on the piece. `vtkValidPointMask` is
 * present when some cell of the whole raster is no-data: in a parallel run (a global
 * vtkMultiProcessController with as many processes as pieces) the pieces all-reduce their
 * counts for it; a piece read without one has it whenever the file can hold no-data (a nodata
 * value or a floating-point band), so that all its pieces have the same arrays.
 * Errors (one line "<file>: <problem>", GetErrorMessage() and vtkErrorMacro, empty output):
 * missing file, not a raster GDAL reads (GDAL's own message included), band out of range,
 * a folder, FIFO or unreadable file, more cells than MaxCells or than the memory available
 * (terroir::CheckMemory), rotated or sheared geotransform, a non-finite origin or a CRS whose
 * units give non-finite spacings, every cell no-data, missing CRS with RequireGeoreference.
 *
 * Network: unless AllowNetworkPaths is on, network and archive paths (`/vsicurl/`,
 * `/vsizip/`, `http://`, ...) are refused, and so are local files that need the network: a
 * server driver's description (WMS, WCS, ...) or a file naming remote or archived data (a VRT
 * source); while the file is opened and read GDAL cannot reach the network from this thread
 * (see vtkTerroirGDALPrivate.h).
 *
 * @par Correctness
 * TerroirDEMReader.* pipeline tests: UTM GeoTIFF origin/spacing/CRS and convergence
 * against the Snyder (1987) series; geographic `.img` row spacings against the meridian
 * radius M(phi) and N(phi) cos(phi) formulas; the feet `.dem` against gdallocationinfo.
 *
 * @par References
 * C. F. F. Karney, "Algorithms for geodesics", J. Geodesy 87:43-55 (2013),
 * doi:10.1007/s00190-012-0578-z (GeographicLib). GDAL/OGR, https://gdal.org.
 *
 * @sa vtkTerroirGeoreference vtkTerroirGeoTIFFWriter
 */
#ifndef vtkTerroirDEMReader_h
#define vtkTerroirDEMReader_h

#include "vtkImageAlgorithm.h"
#include "vtkTerroirIOModule.h" // For export macro

#include <string> // For std::string

class VTKTERROIRIO_EXPORT vtkTerroirDEMReader : public vtkImageAlgorithm
{
public:
  static vtkTerroirDEMReader* New();
  vtkTypeMacro(vtkTerroirDEMReader, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The raster to read (any GDAL raster format). Default: none.
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  ///@}

  ///@{
  /// 1-based band to read. Default: 1.
  vtkSetClampMacro(Band, int, 1, VTK_INT_MAX);
  vtkGetMacro(Band, int);
  ///@}

  ///@{
  /// Fail when the raster has no CRS. Default: off (warn and use the pixel size as metres).
  vtkSetMacro(RequireGeoreference, bool);
  vtkGetMacro(RequireGeoreference, bool);
  vtkBooleanMacro(RequireGeoreference, bool);
  ///@}

  /// Units of the band values (after GDAL's scale and offset).
  enum VerticalUnits
  {
    VERTICAL_UNIT_AUTO = 0, ///< the band's unit type, else the CRS's vertical unit, else metres
    VERTICAL_UNIT_METRE,    ///< metres, whatever the file says
    VERTICAL_UNIT_FOOT,     ///< international feet (0.3048 m)
    VERTICAL_UNIT_US_FOOT   ///< US survey feet (1200/3937 m)
  };

  ///@{
  /// Units of the band values, for DEMs without (or with wrong) unit metadata, such as the
  /// bundled Shellmound DEM in feet. Anything but Auto replaces the file's unit, with a warning
  /// when the file declares a different one. Default: VERTICAL_UNIT_AUTO.
  vtkSetClampMacro(VerticalUnit, int, VERTICAL_UNIT_AUTO, VERTICAL_UNIT_US_FOOT);
  vtkGetMacro(VerticalUnit, int);
  void SetVerticalUnitToAuto() { this->SetVerticalUnit(VERTICAL_UNIT_AUTO); }
  void SetVerticalUnitToMetre() { this->SetVerticalUnit(VERTICAL_UNIT_METRE); }
  void SetVerticalUnitToFoot() { this->SetVerticalUnit(VERTICAL_UNIT_FOOT); }
  void SetVerticalUnitToUSFoot() { this->SetVerticalUnit(VERTICAL_UNIT_US_FOOT); }
  ///@}

  ///@{
  /// Largest number of cells (nx * ny) accepted. Default: 2^31 - 1.
  vtkSetClampMacro(MaxCells, vtkIdType, 1, VTK_ID_MAX);
  vtkGetMacro(MaxCells, vtkIdType);
  ///@}

  ///@{
  /// Allow GDAL network and archive paths (/vsicurl/, /vsizip/, http://, ...), and local files
  /// that name remote data. Default: off.
  vtkSetMacro(AllowNetworkPaths, bool);
  vtkGetMacro(AllowNetworkPaths, bool);
  vtkBooleanMacro(AllowNetworkPaths, bool);
  ///@}

  /// The last error as one line "<file>: <problem>", or "" after a successful read.
  const char* GetErrorMessage() const { return this->ErrorMessage.c_str(); }

  /// Factor applied to the band values to get metres in the last read (1, 0.3048, ...).
  vtkGetMacro(VerticalUnitToMetres, double);

  /// Extent (i0, i1, j0, j1, 0, 0; j = 0 south) of the GDAL window the last read covered: the
  /// update extent asked for (a piece and its ghost cells), the whole raster when no piece was
  /// asked for; (0, -1, 0, -1, 0, -1) before the first read and for an empty piece.
  vtkGetVector6Macro(ReadExtent, int);

protected:
  vtkTerroirDEMReader();
  ~vtkTerroirDEMReader() override;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* FileName = nullptr;
  int Band = 1;
  bool RequireGeoreference = false;
  vtkIdType MaxCells = 2147483647;
  bool AllowNetworkPaths = false;
  int VerticalUnit = VERTICAL_UNIT_AUTO;
  double VerticalUnitToMetres = 1.0;
  std::string ErrorMessage;
  int ReadExtent[6] = { 0, -1, 0, -1, 0, -1 };

private:
  vtkTerroirDEMReader(const vtkTerroirDEMReader&) = delete;
  void operator=(const vtkTerroirDEMReader&) = delete;

  void Fail(const std::string& problem);
  /**
   * In a parallel run (a global vtkMultiProcessController of N > 1 processes, N pieces asked
   * for) sums the invalid and valid cell counts of every piece into `totals` (collective: every
   * rank's RequestData calls it once) and returns true; otherwise copies them and returns false.
   */
  bool ReducePieces(vtkInformation* outInfo,
    vtkIdType invalid,
    vtkIdType valid,
    vtkIdType totals[2]);
};

#endif

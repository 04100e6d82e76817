/**
 * @class   vtkTerroirGeoreference
 * @brief   Reads and writes the georeference that travels with a terrain in field data.
 *
 * A Terroir terrain is a 2-D vtkImageData (dimensions nx, ny, 1) with point data
 * `Elevation` (float32, metres) and, where cells have no data, a `vtkValidPointMask`
 * (unsigned char, 1 = valid). Its georeference lives in field data under fixed names:
 *
 * | field array                | type          | content                                          |
 * |----------------------------|---------------|--------------------------------------------------|
 * | `TerroirCRS`               | string        | the CRS as WKT (empty when unknown)              |
 * | `TerroirGeoTransform`      | double[6]     | the GDAL geotransform of the source raster       |
 * | `TerroirCenterLatLon`      | double[2]     | centre latitude, longitude (degrees, WGS84-like) |
 * | `TerroirMeridianConvergence` | double[1]   | bearing of grid north clockwise from true north,
 * degrees (GeographicLib's gamma); true azimuth = grid azimuth + gamma | | `TerroirRowSpacing` |
 * double, ny×2  | per image row j (j = 0 south): east-west and north-south cell size, metres
 * (geographic grids only) | | `TerroirSourceFile`        | string        | the file the terrain was
 * read from               |
 *
 * Image spacing is always metres. For projected grids the image origin is the south-west
 * cell centre in the CRS (metres); for geographic grids it is (0, 0) and the spacing is the
 * metric cell size at the centre row, with the per-row sizes in `TerroirRowSpacing`.
 *
 * All methods are static; the class is never instantiated by users.
 */
#ifndef vtkTerroirGeoreference_h
#define vtkTerroirGeoreference_h

#include "vtkObject.h"
#include "vtkTerroirCommonModule.h" // For export macro

#include <string> // For std::string

class vtkDataObject;
class vtkDoubleArray;

class VTKTERROIRCOMMON_EXPORT vtkTerroirGeoreference : public vtkObject
{
public:
  static vtkTerroirGeoreference* New();
  vtkTypeMacro(vtkTerroirGeoreference, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Fixed array names (see the class comment).
  static const char* ElevationName() { return "Elevation"; }
  static const char* ValidMaskName() { return "vtkValidPointMask"; }
  static const char* CRSName() { return "TerroirCRS"; }
  static const char* GeoTransformName() { return "TerroirGeoTransform"; }
  static const char* CenterLatLonName() { return "TerroirCenterLatLon"; }
  static const char* MeridianConvergenceName() { return "TerroirMeridianConvergence"; }
  static const char* RowSpacingName() { return "TerroirRowSpacing"; }
  static const char* SourceFileName() { return "TerroirSourceFile"; }
  ///@}

  ///@{
  /// Accessors on a data object's field data. Getters return false (or an empty string,
  /// or nullptr) when the array is missing or has the wrong size.
  static std::string GetCRS(vtkDataObject* data);
  static void SetCRS(vtkDataObject* data, const std::string& wkt);
  static bool GetGeoTransform(vtkDataObject* data, double gt[6]);
  static void SetGeoTransform(vtkDataObject* data, const double gt[6]);
  static bool GetCenterLatLon(vtkDataObject* data, double latLon[2]);
  static void SetCenterLatLon(vtkDataObject* data, double lat, double lon);
  /// Degrees; returns 0 when absent (no georeference: grid north is taken as true north).
  static double GetMeridianConvergence(vtkDataObject* data);
  static bool HasMeridianConvergence(vtkDataObject* data);
  static void SetMeridianConvergence(vtkDataObject* data, double gammaDegrees);
  /// ny tuples of (dx, dy) metres, or nullptr for grids with one spacing.
  static vtkDoubleArray* GetRowSpacing(vtkDataObject* data);
  static void SetRowSpacing(vtkDataObject* data, vtkDoubleArray* rowSpacing);
  static std::string GetSourceFile(vtkDataObject* data);
  static void SetSourceFile(vtkDataObject* data, const std::string& path);
  ///@}

  /// Copies every Terroir georeference array from one data object's field data to another's.
  static void Copy(vtkDataObject* from, vtkDataObject* to);

  /// True when a CRS or a centre latitude/longitude is present.
  static bool HasGeoreference(vtkDataObject* data);

protected:
  vtkTerroirGeoreference() = default;
  ~vtkTerroirGeoreference() override = default;

private:
  vtkTerroirGeoreference(const vtkTerroirGeoreference&) = delete;
  void operator=(const vtkTerroirGeoreference&) = delete;
};

#endif

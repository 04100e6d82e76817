/**
 * @file TerroirIOTestUtilities.h
 * @brief Small helpers for the Terroir::IO pipeline tests: scratch folders and hand-written
 *        raster files (ESRI ASCII grids, VRTs) that GDAL reads.
 */
#ifndef TerroirIOTestUtilities_h
#define TerroirIOTestUtilities_h

#include <string>
#include <vector>

namespace terroir
{
namespace testing
{

/// A fresh, empty folder under TERROIR_TEMP_DIR named after `name` (removed first if present).
std::string IOScratchFolder(const std::string& name);

/// Writes `text` to `path` (binary, truncating). Returns false on failure.
bool WriteTextFile(const std::string& path, const std::string& text);

/// Reads a whole file; empty when missing.
std::vector<char> ReadWholeFile(const std::string& path);

/// Names of the entries of a folder (without "." and "..").
std::vector<std::string> ListFolder(const std::string& path);

bool PathExists(const std::string& path);

/**
 * ESRI ASCII grid text ("AAIGrid"): `rowsNorthFirst` holds nrows strings of ncols values,
 * the first string the NORTH row, as the format wants.
 */
std::string AsciiGrid(int ncols,
  int nrows,
  double xll,
  double yll,
  double cellsize,
  double nodata,
  const std::vector<std::string>& rowsNorthFirst);

/**
 * VRT text: an nx x ny Float32 raster whose band is `source` (a file name relative to the VRT,
 * or `sourceTag` given whole), with the given `geoTransform` ("x0, dx, rx, y0, ry, dy") and,
 * when not empty, an `<SRS>` element.
 */
std::string SimpleVRT(int nx,
  int ny,
  const std::string& geoTransform,
  const std::string& source,
  const std::string& srs = std::string());

} // namespace testing
} // namespace terroir

#endif

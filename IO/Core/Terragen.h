/**
 * @file Terragen.h
 * @brief Parses and writes Terragen terrain files (`.ter`), without VTK or GDAL.
 *
 * Format (Planetside Software, "Terragen Terrain File Specification", little-endian):
 * a 16-byte magic `TERRAGENTERRAIN `, then chunks, each starting with a 4-byte tag:
 * `SIZE` (int16 = min(xpts, ypts) - 1, 2 bytes padding), `XPTS` / `YPTS` (int16, 2 bytes
 * padding), `SCAL` (3 float32: metres per terrain unit in x, y, z; default 30),
 * `CRAD` (float32 planet radius in km, ignored), `CRVM` (uint32 curve mode, ignored),
 * `ALTW` (int16 HeightScale, int16 BaseHeight, then xpts*ypts int16 values, first row =
 * SOUTH edge, west to east), and an optional `EOF `. Height in metres =
 * SCAL.z * (BaseHeight + value * HeightScale / 65536).
 *
 * Row order matches terroir::GridView (row j = 0 south), so no flip is needed.
 */
#ifndef terroir_io_Terragen_h
#define terroir_io_Terragen_h

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace terroir
{
namespace io
{

/// Range of SCAL components (metres per terrain unit) the reader accepts and the writer writes.
constexpr float kTerragenMinScale = 1.0e-6f;
constexpr float kTerragenMaxScale = 1.0e7f;

/// No Terragen file is larger: 32767 x 32767 int16 heights (2 bytes each) plus its chunks.
constexpr double kTerragenMaxFileBytes = 2.0 * 32767.0 * 32767.0 + 1024.0;

/// A decoded Terragen terrain.
struct TerragenTerrain
{
  int nx = 0;                             ///< points west to east (XPTS, or SIZE+1)
  int ny = 0;                             ///< points south to north (YPTS, or SIZE+1)
  double scale[3] = { 30.0, 30.0, 30.0 }; ///< SCAL: metres per terrain unit x, y, z
  double planetRadiusKm = 6370.0;         ///< CRAD (informative only)
  std::uint32_t curveMode = 0;            ///< CRVM (informative only)
  int heightScale = 0;                    ///< ALTW HeightScale
  int baseHeight = 0;                     ///< ALTW BaseHeight (terrain units)
  std::vector<std::int16_t> raw;          ///< nx*ny raw ALTW values, row 0 = south
  std::vector<float> heights;             ///< nx*ny heights in metres, row 0 = south
};

/**
 * @brief Decodes a Terragen file held in memory.
 * @param[in] bytes,size the whole file
 * @param[out] terrain the decoded terrain (left empty on failure)
 * @param[out] error one-line description of the first problem ("" on success), e.g.
 *   "unknown chunk 'ABCD' at offset 40"
 * @return true on success
 */
bool ReadTerragen(const std::uint8_t* bytes,
  std::size_t size,
  TerragenTerrain& terrain,
  std::string& error);

/// Convenience overload for a byte vector.
bool ReadTerragen(const std::vector<std::uint8_t>& bytes,
  TerragenTerrain& terrain,
  std::string& error);

/**
 * @brief Encodes heights (metres, row 0 = south) as a Terragen file.
 *
 * Writes SIZE, XPTS, YPTS, SCAL = (dx, dy, dz), ALTW, EOF. dz = dx (as GDAL's Terragen
 * driver does) unless the heights do not fit int16 terrain units, then dz doubles until they
 * do, or, if that passes kTerragenMaxScale, the smallest dz that fits (heights up to 1.6e11 m
 * always fit). BaseHeight is the rounded mid-range and HeightScale the smallest integer covering
 * the half range with raw values in [-32767, 32767], so the quantisation error is at most
 * range / 131068 + dz / 65534 metres. NaN heights are written as the minimum (warning returned).
 *
 * @param[in] heights nx*ny metres, row 0 south
 * @param[out] bytes the encoded file
 * @param[out] warning set to a one-line note when NaNs were replaced ("" otherwise)
 * @param[out] error one-line error when the grid cannot be written (sizes, spacing outside
 *   [kTerragenMinScale, kTerragenMaxScale], all NaN, heights too large for int16 units)
 * @return true on success
 */
bool WriteTerragen(const float* heights,
  int nx,
  int ny,
  double dx,
  double dy,
  std::vector<std::uint8_t>& bytes,
  std::string& warning,
  std::string& error);

} // namespace io
} // namespace terroir

#endif

/**
 * @file PointPatternFile.h
 * @brief Parses and writes plant point patterns as CSV (`terroir plants --exemplar`, its CSV
 * output), without VTK or GDAL.
 *
 * Format: optional UTF-8 BOM, `\n` or `\r\n` line ends, blank lines and `#` comment lines
 * ignored, comma separated, no quoting. Header (names case-insensitive, any order): `x` and `y`
 * (metres, the same projected coordinates as the zones' grid), optionally `z` (metres, read and
 * ignored), `species` (integer 0..63) and `cluster_id` (integer, the zone the plant exemplifies,
 * -1 for none). Then one plant per row with exactly the header's fields. Numbers are C-locale
 * decimals (std::from_chars), finite.
 *
 * Limits: at most kMaxPointPatternFileBytes (64 MiB) and kMaxPointPatternPoints rows, no NUL
 * byte, at least one plant. Every error is one line naming the problem and its line, e.g.
 * "line 3: species 70 is outside 0..63". User page: Documentation/Plants.md.
 */
#ifndef terroir_io_PointPatternFile_h
#define terroir_io_PointPatternFile_h

#include <cstddef>
#include <string>
#include <vector>

namespace terroir
{
namespace io
{

/// Largest point-pattern file accepted, in bytes (64 MiB), and most plants in one.
constexpr std::size_t kMaxPointPatternFileBytes = std::size_t(64) << 20;
constexpr std::size_t kMaxPointPatternPoints = 1000000;

/// Plants: x, y (m) and, when the file has the columns, species and zone (ClusterId).
struct PointPatternTable
{
  std::vector<double> x, y, z;
  bool hasZ = false;
  std::vector<int> species; ///< empty without the column
  std::vector<int> zone;    ///< empty without the column
};

/**
 * @brief Parses a point pattern held in memory (see the file comment).
 * @param[out] table the plants; left empty on failure
 * @param[out] error "" on success, else ONE line naming the problem and its line
 * @return true on success
 */
bool ParsePointPatternCsv(const char* bytes,
  std::size_t size,
  PointPatternTable& table,
  std::string& error);

/// The table as CSV in the format above (`x,y,z,species,cluster_id` with the columns it has,
/// numbers with 17 significant digits so that a parse gives the same doubles back).
std::string FormatPointPatternCsv(const PointPatternTable& table);

} // namespace io
} // namespace terroir

#endif

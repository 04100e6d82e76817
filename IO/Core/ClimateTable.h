/**
 * @file ClimateTable.h
 * @brief Parses small monthly climate tables (CSV or JSON), without VTK or GDAL.
 *
 * A climate table gives up to three monthly series, January first:
 * `precipitation_mm` (monthly precipitation quantity, mm, 0 to 10000), `intensity_mm_per_h`
 * (mean precipitation intensity, mm/h, 0 to 500) and `temperature_c` (monthly mean sea-level
 * temperature, deg C, -90 to 60). A month with precipitation > 0 needs an intensity > 0 when
 * both series are given.
 *
 * Two formats, told apart by the first non-blank character ('{' means JSON):
 * - CSV: optional UTF-8 BOM, `\n` or `\r\n` line ends, blank lines and `#` comment lines
 *   ignored, comma separated, no quoting. Header (names case-insensitive): `month` plus at least
 *   one value column. Then exactly 12 rows in any order; the month is 1..12, `Jan`..`Dec` or
 *   `January`..`December` (case-insensitive). Numbers are C-locale decimals (std::from_chars).
 * - JSON: one object with the keys `precipitation_mm`, `intensity_mm_per_h`, `temperature_c`
 *   (arrays of exactly 12 numbers) and the ignored strings `description` and `source`.
 *
 * Limits: at most kMaxClimateFileBytes (1 MiB), no NUL byte, JSON nested at most 16 levels.
 * Every error is one line naming the problem (and the line for CSV), e.g.
 * "line 4: precipitation_mm for Mar is -4, must be >= 0". User page:
 * Documentation/IO/ClimateFile.md.
 */
#ifndef terroir_io_ClimateTable_h
#define terroir_io_ClimateTable_h

#include <array>
#include <cstddef>
#include <string>

namespace terroir
{
namespace io
{

/// Largest climate file accepted, in bytes (1 MiB).
constexpr std::size_t kMaxClimateFileBytes = 1 << 20;

/// Monthly climate values, January first. `has*` tells which columns/keys the file gave.
struct ClimateTable
{
  bool hasPrecipitation = false;
  std::array<double, 12> precipitationMm{}; ///< monthly precipitation quantity, mm, >= 0
  bool hasIntensity = false;
  std::array<double, 12> intensityMmPerHour{}; ///< mean precipitation intensity, mm/h, >= 0
  bool hasTemperature = false;
  std::array<double, 12> temperatureC{}; ///< monthly mean sea-level temperature, deg C
};

/**
 * @brief Parses a climate table held in memory (CSV or JSON, detected from the first non-blank
 * character: '{' means JSON).
 * @param[in] bytes,size the whole file
 * @param[out] table the parsed values; left default-constructed on failure
 * @param[out] error "" on success, else ONE line (no '\n') naming the problem and, for CSV,
 *   the line number, e.g. "line 1: unknown column 'precip'; expected month, precipitation_mm,
 *   intensity_mm_per_h, temperature_c"
 * @return true on success
 */
bool ParseClimateTable(const char* bytes,
  std::size_t size,
  ClimateTable& table,
  std::string& error);

/**
 * @brief Reads and parses a climate file.
 * @param[in] path the file
 * @param[out] table the parsed values; left default-constructed on failure
 * @param[out] error "" on success, else "<path>: <problem>": no such file, is a directory (not a
 * file), cannot be read (strerror text), larger than 1 MiB, or the ParseClimateTable error
 * @return true on success
 */
bool ReadClimateTableFile(const std::string& path, ClimateTable& table, std::string& error);

} // namespace io
} // namespace terroir

#endif

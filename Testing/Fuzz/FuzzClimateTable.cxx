// libFuzzer harness for terroir::io::ParseClimateTable (CSV and JSON climate tables).
// Any input must either parse to finite values inside the documented ranges, with at least one
// series present, or fail with a one-line message and a default table. A violated invariant
// traps; sanitizers report the rest. Seeds: Testing/Fuzz/corpus/ClimateTable/.
#include "ClimateTable.h"
#include "FuzzCheck.h"

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

namespace
{
using terroir_fuzz::Check;

/// The message is well-formed UTF-8 without any control character (one line, printable).
bool Printable(const std::string& text)
{
  for (std::size_t k = 0; k < text.size();)
  {
    const auto c = static_cast<unsigned char>(text[k]);
    const std::size_t n = c < 0x80 ? 1
      : (c >= 0xC2 && c <= 0xDF)   ? 2
      : (c >= 0xE0 && c <= 0xEF)   ? 3
      : (c >= 0xF0 && c <= 0xF4)   ? 4
                                   : 0;
    if (n == 0 || c < 32 || c == 127 || text.size() - k < n)
    {
      return false;
    }
    std::uint32_t code = n == 1 ? c : (c & (0x7F >> n));
    for (std::size_t i = 1; i < n; ++i)
    {
      const auto b = static_cast<unsigned char>(text[k + i]);
      if ((b & 0xC0) != 0x80)
      {
        return false;
      }
      code = (code << 6) | (b & 0x3F);
    }
    const std::uint32_t smallest[5] = { 0, 0, 0x80, 0x800, 0x10000 };
    if (code < smallest[n] || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF) ||
      (code >= 0x80 && code < 0xA0))
    {
      return false;
    }
    k += n;
  }
  return true;
}

/// The series is all zero (as in a default table).
bool AllZero(const std::array<double, 12>& values)
{
  for (double v : values)
  {
    if (v != 0.0)
    {
      return false;
    }
  }
  return true;
}

/// Every value is finite and inside [lo, hi] (ranges from Documentation/IO/ClimateFile.md).
bool AllInside(const std::array<double, 12>& values, double lo, double hi)
{
  for (double v : values)
  {
    if (!std::isfinite(v) || v < lo || v > hi)
    {
      return false;
    }
  }
  return true;
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  terroir::io::ClimateTable table;
  table.hasTemperature = true; // the parser must reset the table either way
  table.temperatureC[0] = 99.0;
  std::string error = "stale";
  const bool ok =
    terroir::io::ParseClimateTable(reinterpret_cast<const char*>(data), size, table, error);
  if (ok)
  {
    Check(error.empty());
    Check(table.hasPrecipitation || table.hasIntensity || table.hasTemperature);
    Check(table.hasPrecipitation ? AllInside(table.precipitationMm, 0.0, 10000.0)
                                 : AllZero(table.precipitationMm));
    Check(table.hasIntensity ? AllInside(table.intensityMmPerHour, 0.0, 500.0)
                             : AllZero(table.intensityMmPerHour));
    Check(table.hasTemperature ? AllInside(table.temperatureC, -90.0, 60.0)
                               : AllZero(table.temperatureC));
    if (table.hasPrecipitation && table.hasIntensity)
    {
      for (int m = 0; m < 12; ++m)
      {
        Check(!(table.precipitationMm[m] > 0.0) || table.intensityMmPerHour[m] > 0.0);
      }
    }
  }
  else
  {
    Check(!error.empty());
    Check(error.find('\n') == std::string::npos);
    Check(Printable(error));
    Check(!table.hasPrecipitation && !table.hasIntensity && !table.hasTemperature);
    Check(AllZero(table.precipitationMm) && AllZero(table.intensityMmPerHour) &&
      AllZero(table.temperatureC));
  }
  return 0;
}

#include "MemoryBudget.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <sys/resource.h>

namespace terroir
{
namespace
{
bool ReadSmallFile(const char* path, std::string& text)
{
  std::ifstream in(path);
  if (!in)
  {
    return false;
  }
  std::ostringstream ss;
  ss << in.rdbuf();
  text = ss.str();
  return true;
}

/// A number alone in a file (cgroup files); false for "max" or anything else.
bool ReadNumberFile(const char* path, double& value)
{
  std::string text;
  if (!ReadSmallFile(path, text))
  {
    return false;
  }
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || !std::isfinite(v) || v < 0.0)
  {
    return false;
  }
  value = v;
  return true;
}

/// A "<key>: <number> kB" line of a /proc status-like text, in bytes.
bool ParseKilobyteLine(const std::string& text, const std::string& key, double& bytes)
{
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line))
  {
    if (line.compare(0, key.size() + 1, key + ":") != 0)
    {
      continue;
    }
    char* end = nullptr;
    const char* start = line.c_str() + key.size() + 1;
    const double kb = std::strtod(start, &end);
    if (end == start || !std::isfinite(kb) || kb < 0.0)
    {
      return false;
    }
    bytes = kb * 1024.0;
    return true;
  }
  return false;
}

void TakeSmaller(MemoryAvailability& out, double bytes, const char* source)
{
  bytes = std::max(0.0, bytes);
  if (out.source.empty() || bytes < out.bytes)
  {
    out.bytes = bytes;
    out.source = source;
  }
}
} // namespace

bool ParseMemorySize(const std::string& text, double& bytes)
{
  std::size_t k = 0;
  while (k < text.size() && std::isspace(static_cast<unsigned char>(text[k])))
  {
    ++k;
  }
  const char* start = text.c_str() + k;
  char* end = nullptr;
  const double value = std::strtod(start, &end);
  if (end == start || !std::isfinite(value) || value < 0.0 || *start == '-' || *start == '+')
  {
    return false;
  }
  std::string unit(end);
  unit.erase(
    std::remove_if(unit.begin(), unit.end(), [](unsigned char c) { return std::isspace(c) != 0; }),
    unit.end());
  std::transform(unit.begin(),
    unit.end(),
    unit.begin(),
    [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  if (unit.size() > 1 && unit.back() == 'B')
  {
    unit.pop_back(); // "MB" -> "M", "MIB" -> "MI", "B" stays
  }
  if (unit.size() == 2 && unit[1] == 'I')
  {
    unit.pop_back();
  }
  static const std::string units = "KMGT";
  double factor = 1.0;
  if (!unit.empty() && unit != "B")
  {
    const std::size_t p = units.find(unit);
    if (unit.size() != 1 || p == std::string::npos)
    {
      return false;
    }
    factor = std::pow(1024.0, static_cast<double>(p + 1));
  }
  // Hexadecimal and exponent forms are accepted by strtod; "1e3" is fine, "0x10" is not.
  if (text.find_first_of("xX") != std::string::npos)
  {
    return false;
  }
  bytes = value * factor;
  return std::isfinite(bytes);
}

bool ParseMemAvailable(const std::string& meminfo, double& bytes)
{
  return ParseKilobyteLine(meminfo, "MemAvailable", bytes);
}

bool AvailableMemory(MemoryAvailability& out, std::string& error)
{
  out = MemoryAvailability();
  error.clear();
  if (const char* env = std::getenv("TERROIR_MEMORY_LIMIT"))
  {
    const std::string value = env;
    if (value == "off" || value == "OFF")
    {
      out.limited = false;
      out.bytes = std::numeric_limits<double>::infinity();
      out.source = "TERROIR_MEMORY_LIMIT=off";
      return true;
    }
    if (!ParseMemorySize(value, out.bytes))
    {
      error = "TERROIR_MEMORY_LIMIT: '" + value + "' is not a size (examples: 512M, 2G, off)";
      return false;
    }
    out.source = "TERROIR_MEMORY_LIMIT";
    return true;
  }
  std::string text;
  double v = 0.0;
  if (ReadSmallFile("/proc/meminfo", text) && ParseMemAvailable(text, v))
  {
    TakeSmaller(out, v, "MemAvailable in /proc/meminfo");
  }
  double limit = 0.0, usage = 0.0;
  if (ReadNumberFile("/sys/fs/cgroup/memory.max", limit) &&
    ReadNumberFile("/sys/fs/cgroup/memory.current", usage))
  {
    TakeSmaller(out, limit - usage, "cgroup memory.max");
  }
  else if (ReadNumberFile("/sys/fs/cgroup/memory/memory.limit_in_bytes", limit) &&
    ReadNumberFile("/sys/fs/cgroup/memory/memory.usage_in_bytes", usage) && limit < 1e18)
  {
    TakeSmaller(out, limit - usage, "cgroup memory.limit_in_bytes");
  }
  struct rlimit rl;
  if (getrlimit(RLIMIT_AS, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY &&
    ReadSmallFile("/proc/self/status", text) && ParseKilobyteLine(text, "VmSize", v))
  {
    TakeSmaller(out, static_cast<double>(rl.rlim_cur) - v, "address-space limit (ulimit -v)");
  }
  if (out.source.empty())
  {
    // Nothing to measure with (not Linux?): do not refuse.
    out.limited = false;
    out.bytes = std::numeric_limits<double>::infinity();
    out.source = "unknown";
  }
  return true;
}

std::string CheckMemory(double neededBytes, const std::string& what)
{
  MemoryAvailability available;
  std::string error;
  if (!AvailableMemory(available, error))
  {
    return error;
  }
  if (!available.limited || neededBytes <= available.bytes)
  {
    return std::string();
  }
  return "not enough memory for " + what + ": needs " + FormatBytes(neededBytes) + ", " +
    FormatBytes(available.bytes) + " available (" + available.source + ")";
}

std::string FormatBytes(double bytes)
{
  static const char* const units[] = { "B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB" };
  int u = 0;
  while (bytes >= 1024.0 && u < 6)
  {
    bytes /= 1024.0;
    ++u;
  }
  char text[32];
  if (u == 0)
  {
    std::snprintf(text, sizeof(text), "%.0f B", bytes);
  }
  else
  {
    std::snprintf(text, sizeof(text), bytes < 100.0 ? "%.1f %s" : "%.0f %s", bytes, units[u]);
  }
  return text;
}

} // namespace terroir

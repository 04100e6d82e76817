/**
 * @file MemoryBudget.h
 * @brief How much memory a stage may allocate, checked before it allocates (no VTK).
 *
 * Every reader, filter and writer estimates the bytes it is about to allocate and calls
 * CheckMemory() first, so a grid too large for the machine is refused with one clear line
 * ("needs 6.0 GiB, 3.2 GiB available (MemAvailable in /proc/meminfo)") instead of the process
 * being killed half-way.
 *
 * The memory available is the smallest of:
 * - `MemAvailable` in /proc/meminfo (Linux's estimate of what can be allocated without
 *   swapping);
 * - the cgroup limit minus current usage (v2 `memory.max` - `memory.current`, or v1
 *   `memory.limit_in_bytes` - `memory.usage_in_bytes`), for containers and CI runners;
 * - the address-space limit (`ulimit -v`, RLIMIT_AS) minus the process's current VmSize.
 * The environment variable `TERROIR_MEMORY_LIMIT` replaces that measurement: a size in bytes
 * with an optional suffix K, M, G, T (powers of 1024, "KiB"/"KB" alike, decimals allowed:
 * "1.5G"), or `off` to skip the check.
 */
#ifndef terroir_MemoryBudget_h
#define terroir_MemoryBudget_h

#include <cstdint>
#include <string>

namespace terroir
{

/// What AvailableMemory() found.
struct MemoryAvailability
{
  bool limited = true; ///< false when TERROIR_MEMORY_LIMIT=off (no check)
  double bytes = 0.0;  ///< bytes available now
  std::string source;  ///< where the figure comes from, e.g. "MemAvailable in /proc/meminfo"
};

/**
 * @brief Measures the memory available now (see the file comment).
 * @param[out] out the figure and its source
 * @param[out] error set when TERROIR_MEMORY_LIMIT is set but not a size
 * @return false (with `error`) only for a malformed TERROIR_MEMORY_LIMIT
 */
bool AvailableMemory(MemoryAvailability& out, std::string& error);

/**
 * @brief Checks that `neededBytes` can be allocated now.
 * @return "" when it can (or the check is off), else one line:
 *   "not enough memory for <what>: needs 6.0 GiB, 3.2 GiB available (<source>)"
 *   (or the TERROIR_MEMORY_LIMIT error).
 */
std::string CheckMemory(double neededBytes, const std::string& what);

/// "512 B", "12.0 KiB", "340 MiB", "3.2 GiB" (three significant figures at most).
std::string FormatBytes(double bytes);

/// Parses a size as TERROIR_MEMORY_LIMIT takes it ("1.5G", "512MiB", "1000"); false if not one.
bool ParseMemorySize(const std::string& text, double& bytes);

/// The `MemAvailable` line of a /proc/meminfo text, in bytes; false when absent.
bool ParseMemAvailable(const std::string& meminfo, double& bytes);

} // namespace terroir

#endif

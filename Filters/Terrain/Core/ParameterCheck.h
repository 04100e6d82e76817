/**
 * @file ParameterCheck.h
 * @brief The one-line parameter errors of the terrain cores (internal; Erosion.cxx,
 *        Vegetation.cxx): "<model>: <name> = <value> is not <range>" as std::invalid_argument.
 */
#ifndef terroir_terrain_ParameterCheck_h
#define terroir_terrain_ParameterCheck_h

#include <stdexcept>
#include <string>

namespace terroir
{
namespace terrain
{
namespace detail
{
/// Throws "<model>: <name> = <value> is not <range>".
[[noreturn]] inline void BadParameter(const char* model,
  const char* name,
  double value,
  const char* range)
{
  throw std::invalid_argument(
    std::string(model) + ": " + name + " = " + std::to_string(value) + " is not " + range);
}
} // namespace detail
} // namespace terrain
} // namespace terroir

#endif

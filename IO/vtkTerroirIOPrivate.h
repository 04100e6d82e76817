/**
 * @file vtkTerroirIOPrivate.h
 * @brief Helpers shared by the Terroir::IO writers (not installed): the input array as
 * float heights with no-data as NaN, and the write-to-temporary-then-rename step.
 */
#ifndef vtkTerroirIOPrivate_h
#define vtkTerroirIOPrivate_h

#include <string>

namespace terroir
{
namespace io
{
namespace detail
{

/// Folder part of a path ("." when there is none).
std::string DirectoryOf(const std::string& path);

/// A new, unused temporary file name in the folder of `target` (hidden, same extension).
std::string TemporaryNameFor(const std::string& target);

/// Renames `from` to `to` (replacing `to`); on failure removes `from` and sets `error`.
bool CommitTemporary(const std::string& from, const std::string& to, std::string& error);

bool FileExists(const std::string& path);

} // namespace detail
} // namespace io
} // namespace terroir

#endif

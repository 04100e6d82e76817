/**
 * @file vtkTerroirIOPrivate.h
 * @brief Helpers shared by the Terroir::IO readers and writers (not installed): the terrain
 * output information every source reports, and the write-to-temporary-then-rename step.
 */
#ifndef vtkTerroirIOPrivate_h
#define vtkTerroirIOPrivate_h

#include <string>

class vtkInformation;

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

/// Sets what a terrain source reports in RequestInformation: whole extent nx x ny x 1, spacing
/// (dx, dy, 1), origin (x0, y0, 0) and one float32 point scalar (Elevation).
void SetTerrainInformation(vtkInformation* outInfo,
  int nx,
  int ny,
  double dx,
  double dy,
  double x0,
  double y0);

} // namespace detail
} // namespace io
} // namespace terroir

#endif

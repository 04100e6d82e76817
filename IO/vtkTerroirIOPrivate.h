/**
 * @file vtkTerroirIOPrivate.h
 * @brief Helpers shared by the Terroir::IO readers and writers (not installed): the terrain
 * output information every source reports and the checks of files to read (outputs go through
 * TerroirSafeOutput.h).
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

/// `text` with every control character (a line break in a file's own layer or field name, in
/// GDAL's message or in the file name) as a space, so that an error stays on one line.
std::string OneLine(std::string text);

/// The error line of a reader or writer: "<fileName>: <problem>" ("(no file name)" when the
/// name is null or empty), through OneLine.
std::string FileError(const char* fileName, const std::string& problem);

/// Folder part of a path ("." when there is none).
std::string DirectoryOf(const std::string& path);

bool FileExists(const std::string& path);

/**
 * Checks a path a reader is about to open: it must exist, be a regular file (not a folder, a
 * FIFO or a device, which could block a read forever) and be readable by this process.
 * On failure returns false with `error` = "no such file", "is a directory, not a file",
 * "not a regular file", or "cannot be read (Permission denied)". `size` gets the file size.
 */
bool CheckInputFile(const std::string& path, std::string& error, double* size = nullptr);

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

#include "vtkTerroirIOPrivate.h"

#include "vtkDataObject.h"
#include "vtkInformation.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <sys/stat.h>
#include <unistd.h>

namespace terroir
{
namespace io
{
namespace detail
{

std::string OneLine(std::string text)
{
  for (char& c : text)
  {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f)
    {
      c = ' ';
    }
  }
  return text;
}

std::string FileError(const char* fileName, const std::string& problem)
{
  return OneLine(std::string(fileName && *fileName ? fileName : "(no file name)") + ": " + problem);
}

std::string DirectoryOf(const std::string& path)
{
  const std::size_t slash = path.find_last_of('/');
  if (slash == std::string::npos)
  {
    return ".";
  }
  return slash == 0 ? "/" : path.substr(0, slash);
}

bool FileExists(const std::string& path)
{
  struct stat st;
  return ::stat(path.c_str(), &st) == 0;
}

bool CheckInputFile(const std::string& path, std::string& error, double* size)
{
  struct stat st;
  if (::stat(path.c_str(), &st) != 0)
  {
    error = errno == ENOENT || errno == ENOTDIR
      ? "no such file"
      : std::string("cannot be read (") + std::strerror(errno) + ")";
    return false;
  }
  if (S_ISDIR(st.st_mode))
  {
    error = "is a directory, not a file";
    return false;
  }
  if (!S_ISREG(st.st_mode))
  {
    error = "not a regular file";
    return false;
  }
  if (::access(path.c_str(), R_OK) != 0)
  {
    error = std::string("cannot be read (") + std::strerror(errno) + ")";
    return false;
  }
  if (size)
  {
    *size = static_cast<double>(st.st_size);
  }
  return true;
}

void SetTerrainInformation(vtkInformation* outInfo,
  int nx,
  int ny,
  double dx,
  double dy,
  double x0,
  double y0)
{
  int extent[6] = { 0, nx - 1, 0, ny - 1, 0, 0 };
  double spacing[3] = { dx, dy, 1.0 };
  double origin[3] = { x0, y0, 0.0 };
  outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
  outInfo->Set(vtkDataObject::SPACING(), spacing, 3);
  outInfo->Set(vtkDataObject::ORIGIN(), origin, 3);
  vtkDataObject::SetPointDataActiveScalarInfo(outInfo, VTK_FLOAT, 1);
}

} // namespace detail
} // namespace io
} // namespace terroir

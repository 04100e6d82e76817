#include "vtkTerroirIOPrivate.h"

#include "vtkDataObject.h"
#include "vtkInformation.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <atomic>
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

std::string DirectoryOf(const std::string& path)
{
  const std::size_t slash = path.find_last_of('/');
  if (slash == std::string::npos)
  {
    return ".";
  }
  return slash == 0 ? "/" : path.substr(0, slash);
}

std::string TemporaryNameFor(const std::string& target)
{
  static std::atomic<unsigned> counter{ 0 };
  const std::size_t slash = target.find_last_of('/');
  const std::string dir = slash == std::string::npos ? "" : target.substr(0, slash + 1);
  const std::string base = slash == std::string::npos ? target : target.substr(slash + 1);
  const std::size_t dot = base.find_last_of('.');
  const std::string ext = dot == std::string::npos ? "" : base.substr(dot);
  std::string name;
  do
  {
    name = dir + "." + base + ".tmp" + std::to_string(static_cast<long>(getpid())) + "_" +
      std::to_string(counter++) + ext;
  } while (FileExists(name));
  return name;
}

bool CommitTemporary(const std::string& from, const std::string& to, std::string& error)
{
  if (std::rename(from.c_str(), to.c_str()) != 0)
  {
    error =
      std::string("cannot rename the temporary file into place (") + std::strerror(errno) + ")";
    std::remove(from.c_str());
    return false;
  }
  return true;
}

bool FileExists(const std::string& path)
{
  struct stat st;
  return ::stat(path.c_str(), &st) == 0;
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

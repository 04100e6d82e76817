#include "TerroirIOTestUtilities.h"

#include <dirent.h>
#include <fstream>
#include <iterator>
#include <sstream>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

namespace terroir
{
namespace testing
{
namespace
{
void RemoveTree(const std::string& path)
{
  struct stat st;
  if (::lstat(path.c_str(), &st) != 0)
  {
    return;
  }
  if (S_ISDIR(st.st_mode))
  {
    ::chmod(path.c_str(), 0755);
    for (const std::string& entry : ListFolder(path))
    {
      RemoveTree(path + "/" + entry);
    }
    ::rmdir(path.c_str());
  }
  else
  {
    ::unlink(path.c_str());
  }
}
} // namespace

std::string IOScratchFolder(const std::string& name)
{
  const std::string path = std::string(TERROIR_TEMP_DIR) + "/io_" + name;
  RemoveTree(path);
  ::mkdir(TERROIR_TEMP_DIR, 0755);
  ::mkdir(path.c_str(), 0755);
  return path;
}

bool WriteTextFile(const std::string& path, const std::string& text)
{
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  return static_cast<bool>(out);
}

std::vector<char> ReadWholeFile(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  return std::vector<char>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

std::vector<std::string> ListFolder(const std::string& path)
{
  std::vector<std::string> names;
  if (DIR* dir = ::opendir(path.c_str()))
  {
    while (dirent* e = ::readdir(dir))
    {
      const std::string n = e->d_name;
      if (n != "." && n != "..")
      {
        names.push_back(n);
      }
    }
    ::closedir(dir);
  }
  return names;
}

bool PathExists(const std::string& path)
{
  struct stat st;
  return ::stat(path.c_str(), &st) == 0;
}

std::string AsciiGrid(int ncols,
  int nrows,
  double xll,
  double yll,
  double cellsize,
  double nodata,
  const std::vector<std::string>& rowsNorthFirst)
{
  std::ostringstream s;
  s.precision(17);
  s << "ncols " << ncols << "\nnrows " << nrows << "\nxllcorner " << xll << "\nyllcorner " << yll
    << "\ncellsize " << cellsize << "\nNODATA_value " << nodata << "\n";
  for (const std::string& row : rowsNorthFirst)
  {
    s << row << "\n";
  }
  return s.str();
}

std::string SimpleVRT(int nx,
  int ny,
  const std::string& geoTransform,
  const std::string& source,
  const std::string& srs)
{
  const std::string sourceTag = source.rfind("<", 0) == 0
    ? source
    : "<SourceFilename relativeToVRT=\"1\">" + source + "</SourceFilename>";
  return "<VRTDataset rasterXSize=\"" + std::to_string(nx) + "\" rasterYSize=\"" +
    std::to_string(ny) + "\">\n" + (srs.empty() ? "" : "  <SRS>" + srs + "</SRS>\n") +
    "  <GeoTransform>" + geoTransform + "</GeoTransform>\n" +
    "  <VRTRasterBand dataType=\"Float32\" band=\"1\">\n    <SimpleSource>" + sourceTag +
    "<SourceBand>1</SourceBand></SimpleSource>\n  </VRTRasterBand>\n</VRTDataset>\n";
}

} // namespace testing
} // namespace terroir

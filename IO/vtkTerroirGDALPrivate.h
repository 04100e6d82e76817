/**
 * @file vtkTerroirGDALPrivate.h
 * @brief GDAL helpers shared by the Terroir::IO classes (not installed): GDAL's error messages
 * captured for one-line reports, and the refusal of network access while a file that is
 * supposed to be local is opened and read.
 */
#ifndef vtkTerroirGDALPrivate_h
#define vtkTerroirGDALPrivate_h

#include <memory>
#include <string>
#include <vector>

namespace terroir
{
namespace io
{
namespace detail
{

/// Owners of GDAL/OGR handles (opaque pointers here, so that this header needs no GDAL one):
/// GDALClose, OSRDestroySpatialReference, OCTDestroyCoordinateTransformation.
struct DatasetCloser
{
  void operator()(void* ds) const;
};
using DatasetPtr = std::unique_ptr<void, DatasetCloser>;
struct SRSDeleter
{
  void operator()(void* srs) const;
};
using SRSPtr = std::unique_ptr<void, SRSDeleter>;
struct CTDeleter
{
  void operator()(void* ct) const;
};
using CTPtr = std::unique_ptr<void, CTDeleter>;

/// Collects GDAL's failure messages on this thread while alive (a scoped error handler).
class GDALErrorCapture
{
public:
  GDALErrorCapture();
  ~GDALErrorCapture();
  GDALErrorCapture(const GDALErrorCapture&) = delete;
  GDALErrorCapture& operator=(const GDALErrorCapture&) = delete;
  /// The last failure message ("" when none).
  const std::string& Last() const { return this->LastMessage; }
  /// True when GDAL reported a failure since construction.
  bool Failed() const { return this->Failure; }
  /// " (<last message>)" or "" when none: the suffix of Terroir's one-line errors.
  std::string Suffix() const;

private:
  static void Handler(int level, int number, const char* message);
  std::string LastMessage;
  bool Failure = false;
};

/**
 * While alive, GDAL may not reach the network from this thread: /vsicurl/ and the file systems
 * built on it (/vsis3/, /vsigs/, /vsiaz/, /vsihttp...) refuse every file
 * (CPL_VSIL_CURL_ALLOWED_FILENAME set to a name no URL has), and CPLHTTPFetch, which the
 * server drivers (WMS, WCS, ...) use, answers every request with an error. A local file that
 * names remote data (a VRT source, a WMS description) therefore cannot make Terroir go online.
 */
class ScopedNetworkRefusal
{
public:
  ScopedNetworkRefusal();
  ~ScopedNetworkRefusal();
  ScopedNetworkRefusal(const ScopedNetworkRefusal&) = delete;
  ScopedNetworkRefusal& operator=(const ScopedNetworkRefusal&) = delete;
  /// The first URL a driver tried to fetch while refused ("" when none).
  const std::string& RefusedURL() const { return this->URL; }

private:
  std::string OldAllowedFilename;
  bool HadOldAllowedFilename = false;
  std::string URL;
};

/// `s` in lower case (ASCII).
std::string ToLower(std::string s);

/// True for GDAL paths that are not plain local files: /vsi* (but /vsimem/), or a "://" URL.
bool IsNetworkOrArchivePath(const std::string& path);

/// Short names of the GDAL raster drivers that read from servers by design (WMS, WCS, ...).
bool IsServerDriver(const std::string& shortName);

/// IsServerDriver, and the OGR drivers that read from servers or databases by design (WFS,
/// PostgreSQL, ...).
bool IsVectorServerDriver(const std::string& shortName);

/// The network rule before a file is opened (the one place it is written, for rasters and
/// vectors alike): a remote or archive path is refused unless `allowNetwork`. Returns the
/// one-line reason, or "" when the path may be opened.
std::string RefuseNetworkPath(const std::string& path, bool allowNetwork);

/// The checks before a reader opens `fileName`: "no file name set" for a null or empty name,
/// else RefuseNetworkPath. Sets `remote` (IsNetworkOrArchivePath) when the name is given.
std::string CheckPathToOpen(const char* fileName, bool allowNetwork, bool& remote);

/// The network rule after a dataset opened without network access: refused when its driver
/// reads from a server (`serverDriver`: IsServerDriver or the vector list) or when one of the
/// files it names is a network or archive path. Returns the one-line reason, or "".
std::string RefuseNetworkDataset(const char* driver,
  bool serverDriver,
  const std::vector<std::string>& files);

/// What RefuseNetworkDataset needs to know of an opened dataset (`dataset`: a GDALDatasetH):
/// its driver's short name, whether that driver reads from servers (`isServer`: IsServerDriver
/// or IsVectorServerDriver; a server driver is asked nothing more), and the files it names.
struct DatasetSources
{
  const char* Driver = nullptr;
  bool Server = false;
  std::vector<std::string> Files;
};
DatasetSources ListDatasetSources(void* dataset, bool (*isServer)(const std::string&));

} // namespace detail
} // namespace io
} // namespace terroir

#endif

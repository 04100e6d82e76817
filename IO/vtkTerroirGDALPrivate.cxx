#include "vtkTerroirGDALPrivate.h"
#include "vtkTerroirIOPrivate.h"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_http.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#include <algorithm>
#include <cctype>
#include <cstring>

namespace terroir
{
namespace io
{
namespace detail
{

void DatasetCloser::operator()(void* ds) const
{
  if (ds)
  {
    GDALClose(static_cast<GDALDatasetH>(ds));
  }
}

void SRSDeleter::operator()(void* srs) const
{
  if (srs)
  {
    OSRDestroySpatialReference(static_cast<OGRSpatialReferenceH>(srs));
  }
}

void CTDeleter::operator()(void* ct) const
{
  if (ct)
  {
    OCTDestroyCoordinateTransformation(static_cast<OGRCoordinateTransformationH>(ct));
  }
}
namespace
{
constexpr const char* kNoURL = "terroir:network-access-refused";

CPLHTTPResult* RefuseFetch(const char* url,
  CSLConstList,
  GDALProgressFunc,
  void*,
  CPLHTTPFetchWriteFunc,
  void*,
  void* userData)
{
  auto* refusedURL = static_cast<std::string*>(userData);
  if (refusedURL && refusedURL->empty() && url)
  {
    *refusedURL = url;
  }
  auto* result = static_cast<CPLHTTPResult*>(CPLCalloc(1, sizeof(CPLHTTPResult)));
  result->nStatus = 1;
  result->pszErrBuf = CPLStrdup("network access refused (turn AllowNetworkPaths on)");
  return result;
}
} // namespace

GDALErrorCapture::GDALErrorCapture()
{
  CPLPushErrorHandlerEx([](CPLErr level, CPLErrorNum number, const char* message)
    { GDALErrorCapture::Handler(static_cast<int>(level), number, message); },
    this);
}

GDALErrorCapture::~GDALErrorCapture()
{
  CPLPopErrorHandler();
}

void GDALErrorCapture::Handler(int level, int, const char* message)
{
  auto* self = static_cast<GDALErrorCapture*>(CPLGetErrorHandlerUserData());
  if (self && level >= CE_Failure)
  {
    self->Failure = true;
    self->LastMessage = OneLine(message ? message : "");
  }
}

std::string GDALErrorCapture::Suffix() const
{
  return this->LastMessage.empty() ? std::string() : " (" + this->LastMessage + ")";
}

ScopedNetworkRefusal::ScopedNetworkRefusal()
{
  if (const char* old = CPLGetThreadLocalConfigOption("CPL_VSIL_CURL_ALLOWED_FILENAME", nullptr))
  {
    this->OldAllowedFilename = old;
    this->HadOldAllowedFilename = true;
  }
  CPLSetThreadLocalConfigOption("CPL_VSIL_CURL_ALLOWED_FILENAME", kNoURL);
  CPLHTTPPushFetchCallback(&RefuseFetch, &this->URL);
}

ScopedNetworkRefusal::~ScopedNetworkRefusal()
{
  CPLHTTPPopFetchCallback();
  CPLSetThreadLocalConfigOption("CPL_VSIL_CURL_ALLOWED_FILENAME",
    this->HadOldAllowedFilename ? this->OldAllowedFilename.c_str() : nullptr);
}

std::string ToLower(std::string s)
{
  std::transform(s.begin(),
    s.end(),
    s.begin(),
    [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

bool IsNetworkOrArchivePath(const std::string& path)
{
  const std::string l = ToLower(path);
  if (l.rfind("/vsi", 0) == 0 && l.rfind("/vsimem/", 0) != 0)
  {
    return true;
  }
  return l.find("://") != std::string::npos;
}

bool IsServerDriver(const std::string& shortName)
{
  static const char* const servers[] = { "wms",
    "wmts",
    "wcs",
    "http",
    "daas",
    "eeda",
    "eedai",
    "ogcapi",
    "plmosaic",
    "plscenes",
    "ngw",
    "stacta",
    "stacit",
    "postgisraster" };
  const std::string lower = ToLower(shortName);
  return std::any_of(
    std::begin(servers), std::end(servers), [&](const char* s) { return lower == s; });
}

bool IsVectorServerDriver(const std::string& shortName)
{
  static const char* const servers[] = { "wfs",
    "oapif",
    "carto",
    "elasticsearch",
    "postgresql",
    "mysql",
    "mssqlspatial",
    "oci",
    "odbc",
    "pgeo",
    "mongodbv3",
    "hana",
    "ngw",
    "amigocloud",
    "csw",
    "plscenes",
    "eeda" };
  const std::string lower = ToLower(shortName);
  return IsServerDriver(shortName) ||
    std::any_of(std::begin(servers), std::end(servers), [&](const char* s) { return lower == s; });
}

std::string RefuseNetworkPath(const std::string& path, bool allowNetwork)
{
  if (!allowNetwork && IsNetworkOrArchivePath(path))
  {
    return "network and archive paths (/vsicurl/, /vsizip/, http://, ...) are refused; "
           "turn AllowNetworkPaths on to read them";
  }
  return std::string();
}

std::string RefuseNetworkDataset(const char* driver,
  bool serverDriver,
  const std::vector<std::string>& files)
{
  if (driver && serverDriver)
  {
    return std::string("the ") + driver +
      " driver reads from a server: network access is refused; turn AllowNetworkPaths on";
  }
  for (const std::string& f : files)
  {
    if (IsNetworkOrArchivePath(f))
    {
      return "refers to '" + f +
        "', a network or archive path: refused; turn AllowNetworkPaths on to read it";
    }
  }
  return std::string();
}

//------------------------------------------------------------------------------
DatasetSources ListDatasetSources(void* dataset, bool (*isServer)(const std::string&))
{
  DatasetSources s;
  auto ds = static_cast<GDALDatasetH>(dataset);
  s.Driver = GDALGetDriverShortName(GDALGetDatasetDriver(ds));
  // A server driver is refused before anything else is asked of it.
  s.Server = s.Driver && isServer(s.Driver);
  char** files = s.Server ? nullptr : GDALGetFileList(ds);
  for (char** f = files; f && *f; ++f)
  {
    s.Files.emplace_back(*f);
  }
  CSLDestroy(files);
  return s;
}

//------------------------------------------------------------------------------
std::string CheckPathToOpen(const char* fileName, bool allowNetwork, bool& remote)
{
  if (!fileName || !*fileName)
  {
    return "no file name set";
  }
  remote = IsNetworkOrArchivePath(fileName);
  return RefuseNetworkPath(fileName, allowNetwork);
}

} // namespace detail
} // namespace io
} // namespace terroir

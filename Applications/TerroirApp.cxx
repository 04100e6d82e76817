// The parts of TerroirApp.h that read and write DEMs (GDAL); TerroirAppCore.cxx has the rest.
#include "TerroirApp.h"

#include "vtkDataArray.h"
#include "vtkErrorCode.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkXMLImageDataReader.h"
#include "vtkXMLImageDataWriter.h"

#include "vtkTerroirDEMReader.h"
#include "vtkTerroirGeoTIFFWriter.h"
#include "vtkTerroirTerragenReader.h"

#include "TerroirSafeOutput.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>

namespace fs = std::filesystem;

namespace terroir
{
namespace app
{

std::string DefaultDEM()
{
  if (const char* dir = std::getenv("TERROIR_DATA_DIR"))
  {
    return std::string(dir) + "/sagehen_creek_ca/sagehen_dem_utm11n_10m.tif";
  }
  return std::string(TERROIR_DATA_DIR) + "/sagehen_creek_ca/sagehen_dem_utm11n_10m.tif";
}

vtkSmartPointer<vtkImageData> ReadTerrain(const std::string& path,
  bool allowNetwork,
  const std::string& zUnit)
{
  vtkSmartPointer<vtkAlgorithm> reader;
  std::string error;
  TakeLastVTKError();
  if (HasExtension(path, ".vti"))
  {
    // A terrain Terroir wrote (terroir run's terrain.vti, any command's .vti output): every
    // array, the georeference in field data, Elevation in metres.
    if (zUnit != "auto")
    {
      throw Failure(path + ": --z-unit applies to GDAL rasters; a .vti holds metres");
    }
    vtkNew<vtkXMLImageDataReader> vti;
    if (!vti->CanReadFile(path.c_str()))
    {
      throw Failure(path + ": not a VTK XML image data file (.vti) this program can read");
    }
    vti->SetFileName(path.c_str());
    WatchProgress(vti, "read");
    vti->Update();
    reader = vti;
    int dims[3] = { 0, 0, 0 };
    const std::string xmlError = TakeLastVTKError();
    if (!xmlError.empty() || vti->GetErrorCode() != 0)
    {
      error = path + ": " + (xmlError.empty() ? "could not be read" : xmlError);
    }
    else if (vtkImageData* image = vti->GetOutput())
    {
      image->GetDimensions(dims);
      vtkDataArray* z = image->GetPointData()->GetArray("Elevation");
      if (dims[2] != 1 || dims[0] < 1 || dims[1] < 1)
      {
        error = path + ": not a 2-D grid (" + std::to_string(dims[0]) + " x " +
          std::to_string(dims[1]) + " x " + std::to_string(dims[2]) + " points)";
      }
      else if (!z || z->GetNumberOfComponents() != 1)
      {
        error = path + ": no one-component point array named Elevation (a terrain of terroir)";
      }
    }
  }
  else if (HasExtension(path, ".ter"))
  {
    if (zUnit != "auto")
    {
      throw Failure(path + ": --z-unit applies to GDAL rasters; a Terragen file carries its own " +
        "height scale");
    }
    vtkNew<vtkTerroirTerragenReader> ter;
    ter->SetFileName(path.c_str());
    ter->Update();
    error = ter->GetErrorMessage();
    reader = ter;
  }
  else
  {
    vtkNew<vtkTerroirDEMReader> dem;
    dem->SetFileName(path.c_str());
    dem->SetAllowNetworkPaths(allowNetwork);
    dem->SetVerticalUnit(zUnit == "m" ? vtkTerroirDEMReader::VERTICAL_UNIT_METRE
        : zUnit == "ft"               ? vtkTerroirDEMReader::VERTICAL_UNIT_FOOT
        : zUnit == "us-ft"            ? vtkTerroirDEMReader::VERTICAL_UNIT_US_FOOT
                                      : vtkTerroirDEMReader::VERTICAL_UNIT_AUTO);
    WatchProgress(dem, "read");
    dem->Update();
    error = dem->GetErrorMessage();
    reader = dem;
  }
  const std::string vtkError = TakeLastVTKError();
  if (error.empty() && reader->GetErrorCode() != 0)
  {
    error = vtkError.empty() ? path + ": could not be read" : vtkError;
  }
  auto* image = vtkImageData::SafeDownCast(reader->GetOutputDataObject(0));
  if (error.empty() && (!image || image->GetNumberOfPoints() == 0))
  {
    error = vtkError.empty() ? path + ": no raster data" : vtkError;
  }
  if (!error.empty())
  {
    throw Failure(error);
  }
  vtkSmartPointer<vtkImageData> result = vtkSmartPointer<vtkImageData>::New();
  result->ShallowCopy(image);
  return result;
}

void WriteVTI(vtkImageData* image,
  const std::string& path,
  bool overwrite,
  const std::string& compressor)
{
  const double t0 = Now();
  CheckWritable({ path }, overwrite);
  const std::string tmp = terroir::TemporaryNameFor(path);
  vtkNew<vtkXMLImageDataWriter> writer;
  writer->SetInputData(image);
  writer->SetFileName(tmp.c_str());
  // Appended raw bytes (not base64: 25% smaller, several times faster to write and read), with
  // 64-bit block headers so that an array over 4 GiB can be written.
  writer->SetDataModeToAppended();
  writer->EncodeAppendedDataOff();
  writer->SetHeaderTypeToUInt64();
  if (compressor == "lz4")
  {
    writer->SetCompressorTypeToLZ4();
  }
  else if (compressor == "none")
  {
    writer->SetCompressorTypeToNone();
  }
  else
  {
    writer->SetCompressorTypeToZLib();
  }
  TakeLastVTKError();
  const int ok = writer->Write();
  const std::string err = TakeLastVTKError();
  if (!ok || writer->GetErrorCode() != 0 || !err.empty())
  {
    terroir::DiscardTemporary(tmp);
    // The writer's error code says why; the executive's "returned failure" text does not.
    const unsigned long code = writer->GetErrorCode();
    const std::string why = code == vtkErrorCode::OutOfDiskSpaceError
      ? "out of disk space, or over the file-size limit"
      : code == vtkErrorCode::CannotOpenFileError ? "cannot create the file"
      : code != 0                                 ? vtkErrorCode::GetStringFromErrorCode(code)
                                                  : err;
    throw Failure(path + ": could not be written (" + why + ")");
  }
  std::string error;
  if (!terroir::CommitTemporary(tmp, path, error))
  {
    throw Failure(path + ": " + error);
  }
  RecordWrittenFile(path, "vti", Now() - t0);
}

void WriteGeoTIFF(vtkImageData* image,
  const std::string& array,
  const std::string& path,
  bool overwrite,
  const GeoTIFFLayout& layout)
{
  const double t0 = Now();
  CheckWritable({ path }, overwrite);
  vtkNew<vtkTerroirGeoTIFFWriter> writer;
  writer->SetCompression(layout.Compression);
  writer->SetTiled(layout.Tiled);
  writer->SetThreads(layout.Threads);
  writer->SetOverviews(layout.Overviews);
  writer->SetInputData(image);
  writer->SetArrayName(array.c_str());
  writer->SetFileName(path.c_str());
  writer->SetOverwrite(overwrite);
  TakeLastVTKError();
  writer->Write();
  std::string err = writer->GetErrorMessage();
  if (err.empty() && writer->GetErrorCode() != 0)
  {
    err = TakeLastVTKError();
    if (err.empty())
    {
      err = path + ": could not be written";
    }
  }
  if (!err.empty())
  {
    throw Failure(err);
  }
  RecordWrittenFile(path, "geotiff", Now() - t0);
}

void WriteStageResult(vtkImageData* image,
  const std::string& array,
  const std::string& path,
  bool overwrite)
{
  if (terroir::app::HasExtension(path, ".vti"))
  {
    terroir::app::WriteVTI(image, path, overwrite);
  }
  else if (terroir::app::HasExtension(path, ".tif") || terroir::app::HasExtension(path, ".tiff"))
  {
    terroir::app::WriteGeoTIFF(image, array, path, overwrite);
  }
  else
  {
    throw Failure(path + ": unknown output format (use .tif, .tiff or .vti)");
  }
}

} // namespace app
} // namespace terroir

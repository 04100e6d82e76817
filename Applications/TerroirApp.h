/**
 * @file TerroirApp.h
 * @brief Plumbing shared by the `terroir` sub-commands: clean one-line errors, progress
 * display, reading a DEM, and outputs written under a temporary name then renamed.
 */
#ifndef TerroirApp_h
#define TerroirApp_h

#include "vtkSmartPointer.h"

#include <stdexcept>
#include <string>
#include <vector>

class vtkAlgorithm;
class vtkImageData;

namespace terroir
{
namespace app
{
struct CommandLine;
}
}

namespace terroir
{
namespace app
{

/// A failure reported to the user as one line ("terroir: error: <what>") and exit code 1.
class Failure : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/// A note for the user ("terroir: note: <text>" on stderr), kept until the command succeeds:
/// FlushNotes prints each distinct one once (RunCommand calls it after a command returns 0), so
/// a command that fails prints its one error line and nothing else.
void AddNote(const std::string& text);
void FlushNotes();

/// Routes VTK's error and warning text to one clean line each (no file/line/object
/// address), remembers the last error, and silences VTK's INFO log unless verbose.
void InstallQuietOutput(bool verbose);
/// What every `terroir`-style program does first: parses the command line into `line`, checks
/// TERROIR_MEMORY_LIMIT, installs quiet output and the signal cleanup. Returns -1 when the
/// command is to run, else the exit code (help and version printed, or a one-line error
/// "<program>: error: ..." on stderr).
int StartCommandLine(int argc, const char* const* argv, CommandLine& line, const char* program);
/// The last error VTK reported since the previous call (then cleared).
std::string TakeLastVTKError();

/// Shows the progress of `algorithm` as a bar on a terminal, as plain lines otherwise.
void WatchProgress(vtkAlgorithm* algorithm, const std::string& label);

/// Updates `algorithm`; throws Failure with the algorithm's (or VTK's) error on failure.
void UpdateOrThrow(vtkAlgorithm* algorithm, const std::string& what);

/// The bundled default DEM (Data/sagehen_creek_ca/sagehen_dem_utm11n_10m.tif).
std::string DefaultDEM();

/// Reads a terrain: Terragen `.ter` natively, anything else through GDAL. `zUnit` (--z-unit):
/// auto (the file's unit metadata), m, ft or us-ft for a GDAL DEM's heights; a `.ter` file
/// carries its own height scale, so anything but auto is refused for it.
vtkSmartPointer<vtkImageData> ReadTerrain(const std::string& path,
  bool allowNetwork,
  const std::string& zUnit = "auto");

/// Throws Failure if any of `paths` exists and overwriting was not asked for.
void CheckWritable(const std::vector<std::string>& paths, bool overwrite);

/// One file written by WriteVTI, WriteGeoTIFF, WriteTextFile or WriteOverlay: its path, its
/// kind ("vti", "geotiff", "text", "png") and the seconds it took, checks and renaming included.
struct WrittenFile
{
  std::string Path;
  std::string Kind;
  double Seconds = 0.0;
};
/// Records a written file (the writers call it after the rename, from any thread);
/// TakeWrittenFiles() hands the records out, oldest first, and starts a new list (`terroir run`'s
/// report: where writing goes).
void RecordWrittenFile(const std::string& path, const char* kind, double seconds);
std::vector<WrittenFile> TakeWrittenFiles();

/// Writes every array of `image` as VTK XML image data (.vti), appended binary, temp file then
/// rename. `compressor`: "zlib" (VTK's default, the smallest), "lz4" or "none" (raw).
void WriteVTI(vtkImageData* image,
  const std::string& path,
  bool overwrite,
  const std::string& compressor = "zlib");

/// Writes `text` to `path` through a temporary file in the same folder, renamed on success.
void WriteTextFile(const std::string& path, const std::string& text, bool overwrite);

/// How a GeoTIFF is laid out (vtkTerroirGeoTIFFWriter's options); the default is that class's:
/// uncompressed strips, like gdaldem.
struct GeoTIFFLayout
{
  int Compression = 0; ///< vtkTerroirGeoTIFFWriter::CompressionType
  bool Tiled = false;
  int Threads = 0; ///< GDAL's NUM_THREADS (0 its default, -1 all cores)
  bool Overviews = false;
};

/// Writes one point-data array (one band per component) as a georeferenced GeoTIFF.
void WriteGeoTIFF(vtkImageData* image,
  const std::string& array,
  const std::string& path,
  bool overwrite,
  const GeoTIFFLayout& layout = GeoTIFFLayout());

/// The backend named on the command line (auto, cpu, gpu) as vtkTerroirComputeContext's value.
int ParseBackend(const std::string& name);

/// Writes `array` of `image` as a GeoTIFF (.tif, .tiff: one band per component) or every array
/// as VTK XML image data (.vti), by the file name's extension.
void WriteStageResult(vtkImageData* image,
  const std::string& array,
  const std::string& path,
  bool overwrite);

/// True when the file name ends with `ext` (case-insensitive, ext with the dot).
bool HasExtension(const std::string& path, const std::string& ext);

/// Seconds since an arbitrary epoch (steady clock).
double Now();

} // namespace app
} // namespace terroir

#endif

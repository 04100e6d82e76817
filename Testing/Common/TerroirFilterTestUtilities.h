// Helpers shared by the terrain filter tests (Pipeline, GPU): synthetic terrains, ESRI ASCII
// grids to talk to the gdaldem binary, an error observer, and the bundled DEM.
#ifndef TerroirFilterTestUtilities_h
#define TerroirFilterTestUtilities_h

#include "vtkCommand.h"
#include "vtkImageData.h"
#include "vtkSmartPointer.h"

#include <array>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

class vtkAlgorithm;

namespace terroir_test
{

/// A terrain nx x ny, spacing dx, dy, point array `Elevation` (float32) = z(i, j), j = 0 south.
/// NaN values of z become no-data cells (NaN plus `vtkValidPointMask` = 0).
vtkSmartPointer<vtkImageData> MakeTerrain(int nx,
  int ny,
  double dx,
  double dy,
  const std::function<double(int, int)>& z);

/// A grid read from or written to an ESRI ASCII (AAIGrid) file, rows stored north first as in
/// the file; `At(i, j)` uses Terroir's order (j = 0 south). No-data values become NaN.
struct AsciiGrid
{
  int nx = 0;
  int ny = 0;
  double cellSize = 1.0;
  std::vector<double> values; ///< file order (north row first)
  double At(int i, int j) const { return values[static_cast<size_t>(ny - 1 - j) * nx + i]; }
};
bool ReadAsciiGrid(const std::string& path, AsciiGrid& grid);
/// Writes the `Elevation` of a terrain with square cells (NaN / masked cells as -9999).
bool WriteAsciiGrid(const std::string& path, vtkImageData* terrain);

/// Runs a command line through the shell; returns its exit status (0 = success).
int RunCommand(const std::string& command);
/// True when /usr/bin/gdaldem exists.
bool HaveGdaldem();

/// Path of a bundled data file (Data/...).
std::string DataFile(const std::string& relative);
/// A path in the test temporary folder.
std::string TempFile(const std::string& name);

/// Reads a DEM with vtkTerroirDEMReader (nullptr on failure).
vtkSmartPointer<vtkImageData> ReadDEM(const std::string& path);

/// A concrete vtkAlgorithm subclass of the project, found in the module headers.
struct AlgorithmClass
{
  std::string Name;        ///< e.g. "vtkTerroirSlope"
  std::string Header;      ///< path of its header
  bool HasGPUPath = false; ///< the header overrides HasGPUPath() to return true
};
/// Every class with a New() in Compute/, Common/, IO/, Filters/*/ and Rendering/ whose superclass
/// is an algorithm, reader, writer or source (read from the headers, so that a new filter cannot
/// escape the tests that must cover every filter).
std::vector<AlgorithmClass> ProjectAlgorithmClasses();

/// The input extent `filter` asks for when `request` is asked of its output: the filter's input
/// becomes `input` through a vtkTrivialProducer, then the filter is updated for `request`
/// (vtkAlgorithm::UpdateExtent).
std::array<int, 6> RequestedInputExtent(vtkAlgorithm* filter,
  vtkImageData* input,
  const std::array<int, 6>& request);

/// Runs filter->Update() and returns every progress value it reported, in order.
std::vector<double> UpdateWithProgress(vtkAlgorithm* filter);

/// Collects vtkErrorMacro / vtkWarningMacro messages of the objects it observes.
class ErrorObserver : public vtkCommand
{
public:
  static ErrorObserver* New() { return new ErrorObserver; }
  void Execute(vtkObject*, unsigned long event, void* data) override;
  std::string Errors;
  std::string Warnings;
  int ErrorCount = 0;
};

/// True when the GPU tests should run: a compute context exists. When it does not and
/// TERROIR_REQUIRE_GPU=1, `mustFail` is set (the test should FAIL instead of skipping).
bool GPUAvailable(bool& mustFail, std::string& reason);

} // namespace terroir_test

/// In a GoogleTest body: skip when no GPU compute context can be made, or FAIL when
/// TERROIR_REQUIRE_GPU=1 (as CI sets it), naming the reason either way.
#define TERROIR_REQUIRE_GPU_OR_SKIP()                                                              \
  do                                                                                               \
  {                                                                                                \
    bool terroirMustFail = false;                                                                  \
    std::string terroirWhy;                                                                        \
    if (!terroir_test::GPUAvailable(terroirMustFail, terroirWhy))                                  \
    {                                                                                              \
      if (terroirMustFail)                                                                         \
      {                                                                                            \
        FAIL() << "TERROIR_REQUIRE_GPU=1 but no GPU compute context: " << terroirWhy;              \
      }                                                                                            \
      GTEST_SKIP() << "no GPU compute context: " << terroirWhy;                                    \
    }                                                                                              \
  } while (false)

/// In a GoogleTest body: when `available` is false (a peer program such as gdaldem is missing),
/// skip the test, or FAIL it when TERROIR_REQUIRE_PEERS=1 (Scripts/setup.sh test sets it, so CI
/// never passes with a peer check left out), naming what is missing.
#define TERROIR_REQUIRE_PEER_OR_SKIP(available, what)                                              \
  do                                                                                               \
  {                                                                                                \
    if (!(available))                                                                              \
    {                                                                                              \
      const char* terroirPeers = std::getenv("TERROIR_REQUIRE_PEERS");                             \
      if (terroirPeers && std::string(terroirPeers) == "1")                                        \
      {                                                                                            \
        FAIL() << "TERROIR_REQUIRE_PEERS=1 but " << (what);                                        \
      }                                                                                            \
      GTEST_SKIP() << (what);                                                                      \
    }                                                                                              \
  } while (false)

#endif

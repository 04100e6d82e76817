// terroir-gpu-check: the GDAL-free program of the GPU check bundle (Scripts/gpu-check.sh,
// Documentation/GPUCheck.md), small enough to travel to a GPU machine with its libraries.
//
//   terroir-gpu-check context                 the compute context (renderer, EGL platform, limits)
//   terroir-gpu-check tests [gtest options]   the GPU test suite (Testing/GPU, compiled in)
//   terroir-gpu-check bench [options]         `terroir bench` (the same options and output)
//
// The tests read their DEMs from .vti copies (Testing/Common/GPUCheck): TERROIR_DATA_DIR names
// the folder that holds them. Standard output is line-buffered, so that a step stopped by
// `timeout` leaves every line it finished.
#include "TerroirApp.h"
#include "TerroirBench.h"
#include "TerroirCommandLine.h"

#include "vtkSMPTools.h"
#include "vtkTerroirComputeContext.h"
#include "vtkTerroirGPU.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <exception>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <set>
#include <string>
#include <vector>

namespace
{

const char* const kUsage = R"(usage: terroir-gpu-check COMMAND [options]

  context                  make the GPU compute context and print what it reports
  tests [gtest options]    run the GPU test suite (e.g. --gtest_filter=SlopeGPU.*)
  bench [options]          time each stage per backend: the options of `terroir bench`
                           (see `terroir-gpu-check bench --help`)

Environment: TERROIR_DATA_DIR (the tests' .vti DEMs), TERROIR_REQUIRE_GPU=1 (tests fail instead
of skipping without a context), TERROIR_SOURCE_DIR (source tree for the coverage test),
TERROIR_EGL_PLATFORM (device or surfaceless), TERROIR_BACKEND.
)";

/// `tests`: GoogleTest on the compiled-in suites. argv keeps "tests": GoogleTest re-executes the
/// program with the same arguments for the threadsafe death tests, and the child must come back
/// here.
int RunTests(int argc, char** argv)
{
  ::testing::InitGoogleTest(&argc, argv);
  if (argc > 2)
  {
    std::cerr << "terroir-gpu-check: error: tests: unknown argument '" << argv[2]
              << "' (only GoogleTest options, e.g. --gtest_filter=SlopeGPU.*)\n";
    return 2;
  }
  return RUN_ALL_TESTS();
}

/// `bench`: parsed as `terroir bench ...` and run by the same code.
int RunBench(int argc, char** argv)
{
  std::vector<const char*> args{ "terroir", "bench" };
  for (int i = 2; i < argc; ++i)
  {
    args.push_back(argv[i]);
  }
  terroir::app::CommandLine c;
  const int exitCode = terroir::app::StartCommandLine(
    static_cast<int>(args.size()), args.data(), c, "terroir-gpu-check");
  if (exitCode >= 0)
  {
    return exitCode;
  }
  try
  {
    return terroir::app::CommandBench(c);
  }
  catch (const std::exception& e)
  {
    std::cerr << "terroir-gpu-check: error: " << e.what() << "\n";
    return 1;
  }
}

/// The GL, EGL and driver libraries this process has loaded (from /proc/self/maps): which
/// loader (the bundle's or the system's) and which vendor library GLVND chose.
std::string LoadedGLLibraries()
{
  std::ifstream maps("/proc/self/maps");
  std::set<std::string> paths;
  std::string line;
  while (std::getline(maps, line))
  {
    const std::string::size_type slash = line.find('/');
    if (slash == std::string::npos)
    {
      continue;
    }
    const std::string path = line.substr(slash);
    const std::string name = path.substr(path.find_last_of('/') + 1);
    for (const char* key :
      { "libEGL", "libGL", "libOpenGL", "libepoxy", "nvidia", "dri", "gallium" })
    {
      if (name.find(key) != std::string::npos)
      {
        paths.insert(path);
      }
    }
  }
  std::string list;
  for (const std::string& p : paths)
  {
    list += "  " + p + "\n";
  }
  return list;
}

/// `context`: one line per property of the compute context; exit status 1 when there is none.
int RunContext()
{
  auto& ctx = terroir::gpu::Context::Global();
  std::cout << "threads: " << vtkSMPTools::GetEstimatedNumberOfThreads() << " ("
            << vtkSMPTools::GetBackend() << ")\n";
  if (!ctx.IsAvailable())
  {
    std::cout << "context: none: " << ctx.UnavailableReason() << "\n"
              << "GL libraries loaded:\n"
              << LoadedGLLibraries();
    return 1;
  }
  const terroir::gpu::Limits lim = ctx.GetLimits();
  std::cout << "context: " << lim.Renderer << " | " << lim.Version << " | EGL " << lim.Platform
            << " | created in " << std::fixed << std::setprecision(3) << lim.CreationSeconds
            << " s\n"
            << "vendor: " << lim.Vendor << "\n"
            << "software rasterizer: "
            << (vtkTerroirComputeContext::IsSoftwareRenderer() ? "yes" : "no") << "\n"
            << "device memory: "
            << (lim.DeviceMemoryBytes > 0 ? std::to_string(lim.DeviceMemoryBytes >> 20) + " MiB"
                                          : std::string("unknown"))
            << "\n"
            << "max shader storage block: " << (lim.MaxShaderStorageBlockSize >> 20) << " MiB, "
            << lim.MaxShaderStorageBufferBindings << " bindings\n"
            << "max work groups: " << lim.MaxWorkGroupCount[0] << " x " << lim.MaxWorkGroupCount[1]
            << " x " << lim.MaxWorkGroupCount[2] << ", " << lim.MaxWorkGroupInvocations
            << " invocations per group\n"
            << "immutable storage: " << (lim.ImmutableStorage ? "yes" : "no") << "\n"
            << "GL libraries loaded:\n"
            << LoadedGLLibraries();
  try
  {
    const double bandwidth = ctx.MeasureCopyBandwidth();
    std::cout << "copy kernel (64 MiB): " << std::setprecision(1) << bandwidth / 1e9
              << " GB/s read + write\n";
  }
  catch (const std::exception& e)
  {
    std::cout << "copy kernel: failed: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

} // namespace

int main(int argc, char** argv)
{
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  const std::string command = argc > 1 ? argv[1] : "";
  if (command == "tests")
  {
    return RunTests(argc, argv);
  }
  if (command == "bench")
  {
    return RunBench(argc, argv);
  }
  if (command == "context" && argc == 2)
  {
    return RunContext();
  }
  if (command == "help" || command == "-h" || command == "--help")
  {
    std::cout << kUsage;
    return 0;
  }
  std::cerr << kUsage;
  if (!command.empty())
  {
    std::cerr << "terroir-gpu-check: error: unknown command or argument '"
              << (command == "context" ? argv[2] : command) << "'\n";
  }
  return 2;
}

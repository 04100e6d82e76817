// The test folders of terroir-gpu-check (Applications/GPUCheck.cmake), read at run time: that
// build force-includes this header (-include) into the GPU tests and Testing/Common, instead of
// the compile-time paths (-DTERROIR_DATA_DIR="...") the other test executables get, so that the
// bundle of Scripts/gpu-check.sh runs from any folder on a machine without the source tree.
#ifndef TerroirGPUCheckPaths_h
#define TerroirGPUCheckPaths_h

namespace terroir_gpu_check
{

/// $TERROIR_DATA_DIR (the bundle's data/), else the source tree's Data/ at configure time.
const char* DataDir();
/// $TERROIR_TESTING_DATA_DIR, else the source tree's Testing/Data at configure time.
const char* TestingDataDir();
/// $TERROIR_SOURCE_DIR, else the source tree at configure time (which may not exist here).
const char* SourceDir();
/// $TERROIR_TEMP_DIR, else $TMPDIR, else /tmp.
const char* TempDir();

} // namespace terroir_gpu_check

#define TERROIR_DATA_DIR ::terroir_gpu_check::DataDir()
#define TERROIR_TESTING_DATA_DIR ::terroir_gpu_check::TestingDataDir()
#define TERROIR_SOURCE_DIR ::terroir_gpu_check::SourceDir()
#define TERROIR_TEMP_DIR ::terroir_gpu_check::TempDir()

#endif

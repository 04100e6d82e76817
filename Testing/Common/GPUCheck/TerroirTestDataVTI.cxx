// terroir-gpu-check's GDAL-free test data access: the run-time test folders of
// TerroirGPUCheckPaths.h and the .vti stand-in for vtkTerroirDEMReader (vtkTerroirDEMReader.h in
// this folder). TERROIR_GPU_CHECK_CONFIGURED_SOURCE_DIR is the source tree at configure time.
#include "TerroirGPUCheckPaths.h"
#include "vtkTerroirDEMReader.h"

#include "vtkObjectFactory.h"

#include <cstdlib>
#include <string>

namespace
{
/// The value of environment variable `name` when set and not empty, else `fallback`.
const char* EnvOr(const char* name, const char* fallback)
{
  const char* value = std::getenv(name);
  return (value && *value) ? value : fallback;
}
} // namespace

namespace terroir_gpu_check
{

const char* DataDir()
{
  return EnvOr("TERROIR_DATA_DIR", TERROIR_GPU_CHECK_CONFIGURED_SOURCE_DIR "/Data");
}

const char* TestingDataDir()
{
  return EnvOr("TERROIR_TESTING_DATA_DIR", TERROIR_GPU_CHECK_CONFIGURED_SOURCE_DIR "/Testing/Data");
}

const char* SourceDir()
{
  return EnvOr("TERROIR_SOURCE_DIR", TERROIR_GPU_CHECK_CONFIGURED_SOURCE_DIR);
}

const char* TempDir()
{
  return EnvOr("TERROIR_TEMP_DIR", EnvOr("TMPDIR", "/tmp"));
}

} // namespace terroir_gpu_check

vtkStandardNewMacro(vtkTerroirDEMReader);

//------------------------------------------------------------------------------
std::string vtkTerroirDEMReader::VTIPath(const std::string& name)
{
  const std::string::size_type slash = name.find_last_of('/');
  const std::string::size_type dot = name.find_last_of('.');
  const bool hasExtension = dot != std::string::npos && (slash == std::string::npos || dot > slash);
  if (hasExtension && name.compare(dot, std::string::npos, ".vti") == 0)
  {
    return name;
  }
  return (hasExtension ? name.substr(0, dot) : name) + ".vti";
}

//------------------------------------------------------------------------------
void vtkTerroirDEMReader::SetFileName(const char* name)
{
  if (!name)
  {
    this->Superclass::SetFileName(nullptr);
    return;
  }
  this->Superclass::SetFileName(VTIPath(name).c_str());
}

#include "vtkTerroirComputeContext.h"

#include "vtkObjectFactory.h"
#include "vtkTerroirGPU.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>

vtkStandardNewMacro(vtkTerroirComputeContext);

namespace
{
std::string LowerTrim(const char* value)
{
  std::string s = value ? value : "";
  const auto notSpace = [](unsigned char c) { return !std::isspace(c); };
  s.erase(s.begin(), std::find_if(s.begin(), s.end(), notSpace));
  s.erase(std::find_if(s.rbegin(), s.rend(), notSpace).base(), s.end());
  std::transform(s.begin(),
    s.end(),
    s.begin(),
    [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

/// "llvmpipe (LLVM 15.0.6, 256 bits), EGL surfaceless"
std::string Describe()
{
  const terroir::gpu::Limits lim = terroir::gpu::Context::Global().GetLimits();
  return lim.Renderer + ", EGL " + lim.Platform;
}
} // namespace

//------------------------------------------------------------------------------
void vtkTerroirComputeContext::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  const bool available = vtkTerroirComputeContext::IsAvailable();
  os << indent << "Available: " << (available ? "yes" : "no") << "\n";
  if (!available)
  {
    os << indent << "UnavailableReason: " << vtkTerroirComputeContext::GetUnavailableReason()
       << "\n";
    return;
  }
  const terroir::gpu::Limits lim = terroir::gpu::Context::Global().GetLimits();
  os << indent << "Renderer: " << lim.Renderer << "\n";
  os << indent << "Vendor: " << lim.Vendor << "\n";
  os << indent << "Version: " << lim.Version << "\n";
  os << indent << "Platform: " << lim.Platform << "\n";
  os << indent << "MaxWorkGroupCount: " << lim.MaxWorkGroupCount[0] << " "
     << lim.MaxWorkGroupCount[1] << " " << lim.MaxWorkGroupCount[2] << "\n";
  os << indent << "MaxWorkGroupSize: " << lim.MaxWorkGroupSize[0] << " " << lim.MaxWorkGroupSize[1]
     << " " << lim.MaxWorkGroupSize[2] << "\n";
  os << indent << "MaxWorkGroupInvocations: " << lim.MaxWorkGroupInvocations << "\n";
  os << indent << "MaxShaderStorageBlockSize: " << lim.MaxShaderStorageBlockSize << "\n";
}

//------------------------------------------------------------------------------
bool vtkTerroirComputeContext::IsAvailable()
{
  return terroir::gpu::Context::Global().IsAvailable();
}

std::string vtkTerroirComputeContext::GetUnavailableReason()
{
  return terroir::gpu::Context::Global().UnavailableReason();
}

std::string vtkTerroirComputeContext::GetRenderer()
{
  return terroir::gpu::Context::Global().GetLimits().Renderer;
}

std::string vtkTerroirComputeContext::GetVersion()
{
  return terroir::gpu::Context::Global().GetLimits().Version;
}

std::string vtkTerroirComputeContext::GetPlatform()
{
  return terroir::gpu::Context::Global().GetLimits().Platform;
}

const char* vtkTerroirComputeContext::GetBackendName(int backend)
{
  switch (backend)
  {
    case Auto:
      return "Auto";
    case CPU:
      return "CPU";
    case GPU:
      return "GPU";
    default:
      return "Unknown";
  }
}

//------------------------------------------------------------------------------
int vtkTerroirComputeContext::ResolveBackend(int requested, bool hasGPUPath, std::string& reason)
{
  switch (requested)
  {
    case CPU:
      reason = "CPU (requested CPU)";
      return CPU;
    case GPU:
      if (!hasGPUPath)
      {
        reason = "GPU requested but the filter has no GPU path";
        return -1;
      }
      if (!IsAvailable())
      {
        reason = "GPU requested but there is no GPU compute context: " + GetUnavailableReason();
        return -1;
      }
      reason = "GPU (requested GPU: " + Describe() + ")";
      return GPU;
    case Auto:
      break;
    default:
      reason = "unknown backend " + std::to_string(requested) + " (use Auto=0, CPU=1 or GPU=2)";
      return -1;
  }

  const char* env = std::getenv("TERROIR_BACKEND");
  const std::string value = LowerTrim(env);
  if (value == "cpu")
  {
    reason = "CPU (TERROIR_BACKEND=cpu)";
    return CPU;
  }
  if (value == "gpu")
  {
    if (!IsAvailable())
    {
      reason = "TERROIR_BACKEND=gpu but there is no GPU compute context: " + GetUnavailableReason();
      return -1;
    }
    if (!hasGPUPath)
    {
      // The variable sets the backend for whole runs; stages without a GPU path stay on the CPU.
      reason = "CPU (TERROIR_BACKEND=gpu, but the filter has no GPU path)";
      return CPU;
    }
    reason = "GPU (TERROIR_BACKEND=gpu: " + Describe() + ")";
    return GPU;
  }
  if (!value.empty() && value != "auto")
  {
    reason = "TERROIR_BACKEND='" + std::string(env) + "' is not cpu, gpu or auto";
    return -1;
  }
  if (!hasGPUPath)
  {
    reason = "CPU (auto: filter has no GPU path)";
    return CPU;
  }
  if (!terroir::gpu::Context::Global().HasHardwareDevice())
  {
    // Decided without making a context (that costs 20-40 ms): EGL lists no hardware device.
    reason = "CPU (auto: EGL lists no hardware GPU, only software rasterizers; set "
             "TERROIR_BACKEND=gpu or Backend=GPU to run the GPU path on one)";
    return CPU;
  }
  if (!IsAvailable())
  {
    reason = "CPU (auto: no GPU compute context: " + GetUnavailableReason() + ")";
    return CPU;
  }
  if (IsSoftwareRenderer())
  {
    // Measured here: llvmpipe runs the slope kernel 10-20x slower than the CPU path.
    reason = "CPU (auto: the only GPU context is a software rasterizer, " + Describe() +
      "; set TERROIR_BACKEND=gpu or Backend=GPU to use it)";
    return CPU;
  }
  reason = "GPU (auto: " + Describe() + ")";
  return GPU;
}

//------------------------------------------------------------------------------
bool vtkTerroirComputeContext::IsSoftwareRenderer()
{
  if (!IsAvailable())
  {
    return false;
  }
  std::string r = GetRenderer();
  for (auto& c : r)
  {
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  for (const char* name :
    { "llvmpipe", "softpipe", "swiftshader", "swrast", "software rasterizer", "lavapipe" })
  {
    if (r.find(name) != std::string::npos)
    {
      return true;
    }
  }
  return false;
}

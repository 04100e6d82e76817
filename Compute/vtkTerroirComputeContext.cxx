#include "vtkTerroirComputeContext.h"

#include "vtkObjectFactory.h"
#include "vtkTerroirGPU.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
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

/**
 * Verified GPU paths: stage x hardware -> correct on the GPU test suite, speed ratio (the CPU
 * path's time over the GPU path's, same machine and run, `terroir bench`, 2048^2 unless said),
 * date. `Auto` picks the GPU for a stage only where a row matches the context's GL_RENDERER
 * and says correct and faster (ratio > 1). Documentation/Compute.md holds the same table with
 * the runs behind it. Rows come only from measurements (the GPU suite and Scripts/gpu-check.sh).
 */
struct VerifiedRow
{
  const char* Stage;
  const char* Hardware; ///< lowercase substring of GL_RENDERER
  bool Correct;
  double SpeedRatio;
  const char* Date;
  const char* Run;
};
const VerifiedRow kVerified[] = {
  // 2 cores of an AMD EPYC, Mesa 22.3.6 llvmpipe: correct (GPU suite and its stress modes),
  // slower than the CPU path on the same two cores.
  { "vtkTerroirSlope", "llvmpipe", true, 0.33, "2026-11-26", "bench 2048^2, 2 cores" },
  { "vtkTerroirTemperature", "llvmpipe", true, 0.34, "2026-11-26", "bench 2048^2, 2 cores" },
  { "vtkTerroirSoilHumidity", "llvmpipe", true, 0.46, "2026-11-26", "bench 2048^2, 2 cores" },
  { "vtkTerroirSolarIllumination",
    "llvmpipe",
    true,
    0.13,
    "2026-11-26",
    "bench 1024^2 monthly, 2 cores" },
  { "vtkTerroirWaterFlow", "llvmpipe", true, 0.029, "2026-11-26", "bench 1024^2, 2 cores" },
  { "vtkTerroirKMeans", "llvmpipe", true, 0.17, "2026-11-26", "bench 1024^2, 2 cores" },
  // NVIDIA H200 (driver 580.159.04, 16 host cores), Scripts/gpu-check.sh runs of 2026-11-26:
  // slope, temperature and soil humidity pass the GPU suite but are slower than the CPU (the
  // downloads of their outputs dominate); the others are faster but their final kernels have
  // not run there yet (Documentation/Compute.md, "NVIDIA"), so they count as not verified.
  { "vtkTerroirSlope", "nvidia h200", true, 0.94, "2026-11-26", "gpu-check, bench 2048^2" },
  { "vtkTerroirTemperature", "nvidia h200", true, 0.83, "2026-11-26", "gpu-check, bench 2048^2" },
  { "vtkTerroirSoilHumidity", "nvidia h200", true, 0.88, "2026-11-26", "gpu-check, bench 2048^2" },
  { "vtkTerroirSolarIllumination",
    "nvidia h200",
    false,
    2.0,
    "2026-11-26",
    "gpu-check, bench 2048^2 monthly; final kernel not yet run there" },
  { "vtkTerroirWaterFlow",
    "nvidia h200",
    false,
    1.4,
    "2026-11-26",
    "gpu-check, bench 2048^2; bit-identity fix not yet run there" },
  { "vtkTerroirKMeans",
    "nvidia h200",
    false,
    1.3,
    "2026-11-26",
    "gpu-check, bench 2048^2; bit-identity fix not yet run there" },
};

std::string DescribeRow(const VerifiedRow& r)
{
  char ratio[32];
  std::snprintf(ratio, sizeof(ratio), "%.2f", r.SpeedRatio);
  return std::string(r.Stage) + " on '" + r.Hardware +
    "': " + (r.Correct ? "correct" : "not verified correct") + ", GPU " + ratio +
    "x the CPU path's speed (" + r.Run + ", " + r.Date + ")";
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
  return ResolveBackend(requested, std::string(), hasGPUPath, reason);
}

int vtkTerroirComputeContext::ResolveBackend(int requested,
  const std::string& stage,
  bool hasGPUPath,
  std::string& reason)
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
  const std::string name = stage.empty() ? std::string("this stage") : stage;
  bool anyFaster = false;
  for (const VerifiedRow& r : kVerified)
  {
    anyFaster = anyFaster || (stage == r.Stage && r.Correct && r.SpeedRatio > 1.0);
  }
  if (!anyFaster)
  {
    // Decided without making a context: no hardware has a verified, faster GPU path for it.
    reason = "CPU (auto: the GPU path of " + name +
      " is not yet verified correct and faster than the CPU on any GPU (Documentation/"
      "Compute.md, 'Verified GPU paths'); set TERROIR_BACKEND=gpu or Backend=GPU to run it)";
    return CPU;
  }
  if (!IsAvailable())
  {
    reason = "CPU (auto: no GPU compute context: " + GetUnavailableReason() + ")";
    return CPU;
  }
  std::string row;
  if (!IsVerifiedFaster(stage, GetRenderer(), &row))
  {
    reason = "CPU (auto: the GPU path of " + name + " is not verified correct and faster on " +
      Describe() + (row.empty() ? std::string() : "; best record: " + row) +
      "; set TERROIR_BACKEND=gpu or Backend=GPU to run it)";
    return CPU;
  }
  reason = "GPU (auto: " + Describe() + "; verified: " + row + ")";
  return GPU;
}

//------------------------------------------------------------------------------
bool vtkTerroirComputeContext::IsVerifiedFaster(const std::string& stage,
  const std::string& renderer,
  std::string* row)
{
  const std::string r = LowerTrim(renderer.c_str());
  const VerifiedRow* best = nullptr;
  for (const VerifiedRow& v : kVerified)
  {
    if (stage != v.Stage || r.find(v.Hardware) == std::string::npos)
    {
      continue;
    }
    if (!best || (v.Correct && v.SpeedRatio > best->SpeedRatio))
    {
      best = &v;
    }
  }
  if (row)
  {
    *row = best ? DescribeRow(*best) : std::string();
  }
  return best && best->Correct && best->SpeedRatio > 1.0;
}

std::string vtkTerroirComputeContext::GetVerifiedTable()
{
  std::string text;
  for (const VerifiedRow& v : kVerified)
  {
    text += DescribeRow(v) + "\n";
  }
  return text;
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

// terroir::gpu::Context: the headless EGL/OpenGL 4.3+ compute context on its own worker thread.
#include "vtkTerroirGPU.h"

#include "Private/vtkTerroirGPUPrivate.h"
#include "vtkLogger.h"
#include "vtkTerroirCommonGLSL.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <dlfcn.h>
#include <pthread.h>

#include <algorithm>
#include <cfenv>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <exception>
#include <map>
#include <mutex>
#include <sstream>
#include <system_error>
#include <thread>
#if defined(__x86_64__) || defined(__i386__)
#include <xmmintrin.h>
#endif

namespace terroir
{
namespace gpu
{

namespace
{
/// Set on the worker thread only.
thread_local bool tlsOnContextThread = false;
/// The limits of the one context (written once on the worker before any job runs).
Limits gContextLimits;
/// Marks the global context lost (set by its constructor).
std::function<void(const std::string&)> gMarkLost;

/// The unsigned number of megabytes in environment variable `name`, or `fallback` bytes.
std::size_t EnvMegabytes(const char* name, std::size_t fallback)
{
  const char* env = std::getenv(name);
  if (!env || !*env)
  {
    return fallback;
  }
  char* end = nullptr;
  const unsigned long long mb = std::strtoull(env, &end, 10);
  return (end && *end == '\0') ? static_cast<std::size_t>(mb) << 20 : fallback;
}

constexpr std::chrono::seconds kCreateTimeout{ 60 };
constexpr std::chrono::seconds kShutdownTimeout{ 10 };
/// Budget of a job run without one (Context::Run(job)).
constexpr double kDefaultBudgetSeconds = 600.0;

std::string Hex(unsigned value)
{
  char buf[16];
  std::snprintf(buf, sizeof(buf), "0x%04X", value);
  return buf;
}

std::string EGLErrorString()
{
  const EGLint err = eglGetError();
  switch (err)
  {
    case EGL_SUCCESS:
      return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED:
      return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
      return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
      return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
      return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
      return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
      return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY:
      return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
      return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER:
      return "EGL_BAD_PARAMETER";
    default:
      return "EGL error " + Hex(static_cast<unsigned>(err));
  }
}

bool HasExtension(const char* list, const char* name)
{
  if (!list)
  {
    return false;
  }
  const std::size_t n = std::strlen(name);
  for (const char* p = std::strstr(list, name); p; p = std::strstr(p + 1, name))
  {
    const bool startOk = (p == list || p[-1] == ' ');
    const bool endOk = (p[n] == '\0' || p[n] == ' ');
    if (startOk && endOk)
    {
      return true;
    }
  }
  return false;
}

std::string Lower(std::string s)
{
  std::transform(s.begin(),
    s.end(),
    s.begin(),
    [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

/// libepoxy aborts the process when it cannot dlopen libEGL / libOpenGL: check first.
bool LibrariesPresent(std::string& reason)
{
  void* egl = dlopen("libEGL.so.1", RTLD_LAZY | RTLD_GLOBAL);
  if (!egl)
  {
    const char* e = dlerror();
    reason = std::string("libEGL.so.1 cannot be loaded: ") + (e ? e : "unknown error");
    return false;
  }
  void* gl = dlopen("libOpenGL.so.0", RTLD_LAZY | RTLD_GLOBAL);
  if (!gl)
  {
    gl = dlopen("libGL.so.1", RTLD_LAZY | RTLD_GLOBAL);
  }
  if (!gl)
  {
    const char* e = dlerror();
    reason = std::string("neither libOpenGL.so.0 nor libGL.so.1 can be loaded: ") +
      (e ? e : "unknown error");
    return false;
  }
  // Handles stay open for the life of the process (epoxy holds its own too).
  return true;
}
} // namespace

//------------------------------------------------------------------------------
struct Context::Internals
{
  enum class State
  {
    NotStarted,
    Starting,
    Ready,
    Failed,
    Stopped
  };

  struct Task
  {
    std::function<void()> Job;
    std::string Stage;
    double BudgetSeconds = 0.0;
    std::exception_ptr Error;
    bool Done = false;
  };

  std::once_flag StartOnce;
  std::mutex Mutex;
  std::condition_variable WorkCv; // worker waits for tasks or stop
  std::condition_variable DoneCv; // callers wait for task completion, start and shutdown
  State Status = State::NotStarted;
  std::string Reason;
  std::deque<std::shared_ptr<Task>> Queue;
  bool Lost = false; ///< a stage ran past its budget: the context is given up
  bool StopRequested = false;
  bool WorkerFinished = false;
  std::thread Worker;

  // Context thread only.
  EGLDisplay Display = EGL_NO_DISPLAY;
  EGLContext GLContext = EGL_NO_CONTEXT;
  struct CachedProgram
  {
    std::string Source;
    std::unique_ptr<Program> Prog;
  };
  std::map<std::string, CachedProgram> Programs;

  void EnsureStarted();
  void Shutdown();
  void MarkLost(const std::string& why)
  {
    std::lock_guard<std::mutex> lock(this->Mutex);
    this->Lost = true;
    this->Status = State::Failed;
    this->Reason = why;
  }
  /// Reads TERROIR_GPU_STRESS, TERROIR_GPU_TRANSFER and the cache sizes (on the worker, once the
  /// context works).
  static void Configure();
  static void WorkerMain(Internals* self);
  /// SetStorageBlockLimit: a cap on the reported MaxShaderStorageBlockSize (0: none).
  long long BlockLimit = 0;

  bool CreateGL(std::string& reason);
  bool TryDisplay(EGLDisplay dpy, const char* platform, std::string& reason);
  bool ProbeGL(const char* platform, std::string& reason);
  void DestroyGL();
};

namespace
{
/// The internals to shut down at exit (a Context::Internals*, set once the context works).
void* gInternalsForExit = nullptr;
}

//------------------------------------------------------------------------------
bool Context::Internals::TryDisplay(EGLDisplay dpy, const char* platform, std::string& reason)
{
  if (dpy == EGL_NO_DISPLAY)
  {
    reason = std::string("no EGL display for the ") + platform + " platform: " + EGLErrorString();
    return false;
  }
  EGLint major = 0, minor = 0;
  if (!eglInitialize(dpy, &major, &minor))
  {
    reason =
      std::string("eglInitialize failed on the ") + platform + " platform: " + EGLErrorString();
    return false;
  }
  this->Display = dpy;
  const char* ext = eglQueryString(dpy, EGL_EXTENSIONS);
  if (!HasExtension(ext, "EGL_KHR_surfaceless_context"))
  {
    reason = std::string("EGL ") + platform + " display lacks EGL_KHR_surfaceless_context";
    this->DestroyGL();
    return false;
  }
  if (!HasExtension(ext, "EGL_KHR_create_context") && (major < 1 || (major == 1 && minor < 5)))
  {
    reason = std::string("EGL ") + platform + " display lacks EGL_KHR_create_context";
    this->DestroyGL();
    return false;
  }
  if (!eglBindAPI(EGL_OPENGL_API))
  {
    reason = std::string("eglBindAPI(EGL_OPENGL_API) failed on the ") + platform +
      " platform: " + EGLErrorString();
    this->DestroyGL();
    return false;
  }
  EGLConfig config = EGL_NO_CONFIG_KHR;
  if (!HasExtension(ext, "EGL_KHR_no_config_context") &&
    !HasExtension(ext, "EGL_MESA_configless_context"))
  {
    const EGLint attribs[] = { EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, 0, EGL_NONE };
    EGLint count = 0;
    if (!eglChooseConfig(dpy, attribs, &config, 1, &count) || count < 1)
    {
      reason = std::string("no EGL config with EGL_OPENGL_BIT on the ") + platform + " platform";
      this->DestroyGL();
      return false;
    }
  }
  std::string lastError;
  for (int minorGL = 6; minorGL >= 3; --minorGL)
  {
    const EGLint ctxAttribs[] = { EGL_CONTEXT_MAJOR_VERSION_KHR,
      4,
      EGL_CONTEXT_MINOR_VERSION_KHR,
      minorGL,
      EGL_CONTEXT_OPENGL_PROFILE_MASK_KHR,
      EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT_KHR,
      EGL_NONE };
    EGLContext ctx = eglCreateContext(dpy, config, EGL_NO_CONTEXT, ctxAttribs);
    if (ctx != EGL_NO_CONTEXT)
    {
      this->GLContext = ctx;
      break;
    }
    lastError = EGLErrorString();
  }
  if (this->GLContext == EGL_NO_CONTEXT)
  {
    reason =
      std::string("no OpenGL 4.3+ core context on the EGL ") + platform + " platform: " + lastError;
    this->DestroyGL();
    return false;
  }
  if (!eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, this->GLContext))
  {
    reason =
      std::string("eglMakeCurrent failed on the ") + platform + " platform: " + EGLErrorString();
    this->DestroyGL();
    return false;
  }
  if (!this->ProbeGL(platform, reason))
  {
    this->DestroyGL();
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
bool Context::Internals::ProbeGL(const char* platform, std::string& reason)
{
  Limits lim;
  auto str = [](GLenum name)
  {
    const GLubyte* s = glGetString(name);
    return s ? std::string(reinterpret_cast<const char*>(s)) : std::string();
  };
  lim.Vendor = str(GL_VENDOR);
  lim.Renderer = str(GL_RENDERER);
  lim.Version = str(GL_VERSION);
  lim.Platform = platform;
  GLint major = 0, minor = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  lim.MajorVersion = major;
  lim.MinorVersion = minor;
  if (major < 4 || (major == 4 && minor < 3))
  {
    reason = "OpenGL " + std::to_string(major) + "." + std::to_string(minor) + " < 4.3 on " +
      lim.Renderer + " (EGL " + platform + "): no compute shaders";
    return false;
  }
  for (GLuint i = 0; i < 3; ++i)
  {
    GLint v = 0;
    glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, i, &v);
    lim.MaxWorkGroupCount[i] = v;
    v = 0;
    glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_SIZE, i, &v);
    lim.MaxWorkGroupSize[i] = v;
  }
  GLint inv = 0;
  glGetIntegerv(GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS, &inv);
  lim.MaxWorkGroupInvocations = inv;
  GLint64 block = 0;
  glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &block);
  lim.MaxShaderStorageBlockSize = static_cast<long long>(block);
  GLint bindings = 0;
  glGetIntegerv(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, &bindings);
  lim.MaxShaderStorageBufferBindings = bindings;
  const GLenum err = glGetError();
  if (err != GL_NO_ERROR)
  {
    reason = "probing GL limits on " + lim.Renderer + " failed: " + detail::GLErrorName(err);
    return false;
  }
  if (lim.MaxWorkGroupCount[0] <= 0 || lim.MaxWorkGroupInvocations <= 0)
  {
    reason = "GL on " + lim.Renderer + " reports no compute work groups";
    return false;
  }
  // glBufferStorage (pooled buffers, persistently mapped staging): core in 4.4.
  GLint extensions = 0;
  glGetIntegerv(GL_NUM_EXTENSIONS, &extensions);
  bool bufferStorage = major > 4 || (major == 4 && minor >= 4);
  bool nvxMemory = false;
  for (GLint i = 0; i < extensions; ++i)
  {
    const GLubyte* e = glGetStringi(GL_EXTENSIONS, static_cast<GLuint>(i));
    const std::string name = e ? reinterpret_cast<const char*>(e) : "";
    bufferStorage = bufferStorage || name == "GL_ARB_buffer_storage";
    nvxMemory = nvxMemory || name == "GL_NVX_gpu_memory_info";
  }
  lim.ImmutableStorage = bufferStorage;
  if (nvxMemory)
  {
    GLint kb = 0;
    glGetIntegerv(0x9048 /* GL_GPU_MEMORY_INFO_TOTAL_AVAILABLE_MEMORY_NVX */, &kb);
    lim.DeviceMemoryBytes = static_cast<long long>(kb) * 1024;
  }
  detail::ClearGLErrors();
  gContextLimits = lim;
  return true;
}

//------------------------------------------------------------------------------
bool Context::Internals::CreateGL(std::string& reason)
{
  const char* forcedEnv = std::getenv("TERROIR_EGL_PLATFORM");
  const std::string forced = forcedEnv ? Lower(forcedEnv) : std::string();
  if (!forced.empty() && forced != "device" && forced != "surfaceless")
  {
    reason = "TERROIR_EGL_PLATFORM='" + std::string(forcedEnv) + "' is not device or surfaceless";
    return false;
  }
  if (!LibrariesPresent(reason))
  {
    return false;
  }
  const char* clientExt = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!clientExt)
  {
    reason = "no EGL display: EGL client extensions unavailable (" + EGLErrorString() + ")";
    return false;
  }
  if (!HasExtension(clientExt, "EGL_EXT_platform_base"))
  {
    reason = "no EGL display: EGL_EXT_platform_base is missing";
    return false;
  }
  std::vector<std::string> failures;

  // 1. The EGL device platform, on a hardware device (NVIDIA).
  if (forced != "surfaceless")
  {
    if (HasExtension(clientExt, "EGL_EXT_platform_device") &&
      (HasExtension(clientExt, "EGL_EXT_device_base") ||
        (HasExtension(clientExt, "EGL_EXT_device_enumeration") &&
          HasExtension(clientExt, "EGL_EXT_device_query"))))
    {
      EGLint count = 0;
      if (eglQueryDevicesEXT(0, nullptr, &count) && count > 0)
      {
        std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(count));
        eglQueryDevicesEXT(count, devices.data(), &count);
        std::vector<EGLDeviceEXT> hardware, software;
        for (EGLint i = 0; i < count; ++i)
        {
          const char* devExt = eglQueryDeviceStringEXT(devices[i], EGL_EXTENSIONS);
          (HasExtension(devExt, "EGL_MESA_device_software") ? software : hardware)
            .push_back(devices[i]);
        }
        std::vector<EGLDeviceEXT> candidates = hardware;
        if (forced == "device")
        {
          candidates.insert(candidates.end(), software.begin(), software.end());
        }
        if (candidates.empty())
        {
          failures.push_back("EGL device platform: no hardware device");
        }
        for (EGLDeviceEXT dev : candidates)
        {
          std::string why;
          EGLDisplay dpy = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, dev, nullptr);
          if (this->TryDisplay(dpy, "device", why))
          {
            return true;
          }
          failures.push_back(why);
        }
      }
      else
      {
        failures.push_back("EGL device platform: no devices (" + EGLErrorString() + ")");
      }
    }
    else
    {
      failures.push_back("EGL_EXT_platform_device unsupported");
    }
  }

  // 2. Mesa's surfaceless platform (llvmpipe on machines without a GPU).
  if (forced != "device")
  {
    if (HasExtension(clientExt, "EGL_MESA_platform_surfaceless"))
    {
      std::string why;
      EGLDisplay dpy =
        eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
      if (this->TryDisplay(dpy, "surfaceless", why))
      {
        return true;
      }
      failures.push_back(why);
    }
    else
    {
      failures.push_back("EGL_MESA_platform_surfaceless unsupported");
    }
  }

  std::string joined;
  for (const auto& f : failures)
  {
    joined += (joined.empty() ? "" : "; ") + f;
  }
  reason = "no EGL display: " + joined;
  return false;
}

//------------------------------------------------------------------------------
void Context::Internals::DestroyGL()
{
  if (this->Display == EGL_NO_DISPLAY)
  {
    return;
  }
  eglMakeCurrent(this->Display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  if (this->GLContext != EGL_NO_CONTEXT)
  {
    eglDestroyContext(this->Display, this->GLContext);
    this->GLContext = EGL_NO_CONTEXT;
  }
  eglTerminate(this->Display);
  this->Display = EGL_NO_DISPLAY;
  eglReleaseThread();
}

//------------------------------------------------------------------------------
/// Sets the stress modes from a comma-separated list (unknown names are logged and ignored).
static void ApplyStress(const std::string& text)
{
  detail::Runtime& rt = detail::State();
  rt.FillNaN = rt.FillPattern = rt.Split = rt.Shuffle = false;
  rt.StressText.clear();
  std::stringstream list(Lower(text));
  std::string mode;
  while (std::getline(list, mode, ','))
  {
    mode.erase(0, mode.find_first_not_of(" \t"));
    mode.erase(mode.find_last_not_of(" \t") + 1);
    bool* flag = mode == "fill-nan" ? &rt.FillNaN
      : mode == "fill-pattern"      ? &rt.FillPattern
      : mode == "split"             ? &rt.Split
      : mode == "shuffle"           ? &rt.Shuffle
                                    : nullptr;
    if (flag)
    {
      *flag = true;
      rt.StressText += (rt.StressText.empty() ? "" : ",") + mode;
    }
    else if (!mode.empty())
    {
      vtkLogF(WARNING,
        "TERROIR_GPU_STRESS: '%s' is not fill-nan, fill-pattern, split or shuffle: ignored",
        mode.c_str());
    }
  }
}

//------------------------------------------------------------------------------
void Context::Internals::Configure()
{
  detail::Runtime& rt = detail::State();
  std::string renderer = Lower(gContextLimits.Renderer);
  bool software = false;
  for (const char* name :
    { "llvmpipe", "softpipe", "swiftshader", "swrast", "software rasterizer", "lavapipe" })
  {
    software = software || renderer.find(name) != std::string::npos;
  }
  // Measured (Documentation/Compute.md): on llvmpipe a buffer is host memory, and a mapped copy
  // on all cores beats glBufferSubData's one-thread memcpy (the staging ring only adds a copy);
  // on a discrete GPU the driver's glBufferSubData runs at 2-4 GB/s, a copy from pinned
  // staging memory at bus speed.
  rt.Method = software ? Transfer::Mapped : Transfer::Staging;
  if (const char* env = std::getenv("TERROIR_GPU_TRANSFER"))
  {
    const std::string v = Lower(env);
    if (v == "subdata")
    {
      rt.Method = Transfer::SubData;
    }
    else if (v == "staging")
    {
      rt.Method = Transfer::Staging;
    }
    else if (v == "mapped")
    {
      rt.Method = Transfer::Mapped;
    }
    else if (!v.empty())
    {
      vtkLogF(WARNING, "TERROIR_GPU_TRANSFER='%s' is not subdata, staging or mapped: ignored", env);
    }
  }
  if (const char* env = std::getenv("TERROIR_GPU_LEGACY_BUFFERS"))
  {
    rt.Legacy = std::string(env) == "1";
  }
  if (!gContextLimits.ImmutableStorage || rt.Legacy)
  {
    rt.Method = Transfer::SubData;
  }
  if (const char* env = std::getenv("TERROIR_GPU_STRESS"))
  {
    ApplyStress(env);
  }
  // Tests: a smaller storage-block limit makes every GPU path cut its work into slices and
  // bands as it must on a driver with a small limit (llvmpipe's is 128 MiB).
  const std::size_t cap = EnvMegabytes("TERROIR_GPU_MAX_STORAGE_BLOCK_MB", 0);
  if (cap > 0 &&
    (gContextLimits.MaxShaderStorageBlockSize <= 0 ||
      static_cast<long long>(cap) < gContextLimits.MaxShaderStorageBlockSize))
  {
    gContextLimits.MaxShaderStorageBlockSize = static_cast<long long>(cap);
  }
  const long long device = gContextLimits.DeviceMemoryBytes;
  const std::size_t mib = std::size_t(1) << 20;
  rt.PoolCapBytes = EnvMegabytes("TERROIR_GPU_POOL_MB",
    device > 0 ? static_cast<std::size_t>(device / 8) : (software ? 512 : 2048) * mib);
  rt.ResidentCapBytes = EnvMegabytes(
    "TERROIR_GPU_CACHE_MB", device > 0 ? static_cast<std::size_t>(device / 4) : 1024 * mib);
}

//------------------------------------------------------------------------------
void Context::Internals::WorkerMain(Internals* self)
{
  tlsOnContextThread = true;
  {
    // The floating-point environment host code inside jobs must keep (the driver's libraries
    // may change it when they load or later).
    detail::Runtime& state = detail::State();
    std::fegetenv(&state.HostEnv);
    state.HostControl = detail::FloatingPointControl();
    state.HostEnvSet = true;
  }
  const auto t0 = std::chrono::steady_clock::now();
  std::string reason;
  bool ok = false;
  try
  {
    ok = self->CreateGL(reason);
    if (ok)
    {
      Configure();
    }
  }
  catch (const std::exception& e)
  {
    reason = std::string("creating the GL context threw: ") + e.what();
    ok = false;
  }
  gContextLimits.CreationSeconds =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  {
    std::lock_guard<std::mutex> lock(self->Mutex);
    if (self->Status != State::Starting) // the caller gave up waiting (timeout)
    {
      ok = false;
    }
    else
    {
      self->Status = ok ? State::Ready : State::Failed;
      self->Reason = reason;
    }
  }
  self->DoneCv.notify_all();
  if (!ok)
  {
    self->DestroyGL();
    std::lock_guard<std::mutex> lock(self->Mutex);
    self->WorkerFinished = true;
    self->DoneCv.notify_all();
    return;
  }

  detail::Runtime& rt = detail::State();
  for (;;)
  {
    std::shared_ptr<Task> task;
    {
      std::unique_lock<std::mutex> lock(self->Mutex);
      self->WorkCv.wait(lock, [self] { return self->StopRequested || !self->Queue.empty(); });
      if (self->Queue.empty())
      {
        break; // stop requested and nothing left to do
      }
      task = self->Queue.front();
      self->Queue.pop_front();
    }
    detail::RestoreHostFloatingPoint();
    const auto t0 = detail::Clock::now();
    rt.Stage = task->Stage;
    rt.BudgetSeconds = task->BudgetSeconds;
    rt.Deadline = t0 +
      std::chrono::duration_cast<detail::Clock::duration>(
        std::chrono::duration<double>(task->BudgetSeconds));
    try
    {
      task->Job();
      if (rt.Profiling)
      {
        detail::CollectQueries();
      }
    }
    catch (...)
    {
      task->Error = std::current_exception();
    }
    rt.Stage.clear();
    rt.Deadline = detail::Clock::time_point::max();
    const double seconds = detail::Since(t0);
    detail::Count([seconds](Stats& c) { c.JobSeconds += seconds; });
    {
      std::lock_guard<std::mutex> lock(self->Mutex);
      task->Done = true;
    }
    self->DoneCv.notify_all();
  }

  // Shut down on the GL thread: programs and buffers first, then the context and display. A
  // lost context may still run a kernel that never ends: then nothing waits for the GPU.
  bool lost = false;
  {
    std::lock_guard<std::mutex> lock(self->Mutex);
    lost = self->Lost;
  }
  if (!lost)
  {
    self->Programs.clear();
    detail::ReleaseAll();
    glFinish();
    self->DestroyGL();
  }
  {
    std::lock_guard<std::mutex> lock(self->Mutex);
    self->WorkerFinished = true;
  }
  self->DoneCv.notify_all();
}

//------------------------------------------------------------------------------
void Context::Internals::EnsureStarted()
{
  std::call_once(this->StartOnce,
    [this]
    {
      // Mesa's shader disk cache runs a queue of threads whose condition variable a child of
      // fork() inherits mid-use: the child's exit() then hangs in Mesa's atexit handler (seen
      // here after new shaders were compiled). Compiling a kernel takes milliseconds, so the
      // context goes without that cache unless the user configured it.
      if (!std::getenv("MESA_SHADER_CACHE_DISABLE") && !std::getenv("MESA_GLSL_CACHE_DISABLE"))
      {
        setenv("MESA_SHADER_CACHE_DISABLE", "true", 0);
      }
      std::unique_lock<std::mutex> lock(this->Mutex);
      this->Status = State::Starting;
      try
      {
        this->Worker = std::thread(&Internals::WorkerMain, this);
      }
      catch (const std::system_error& e)
      {
        this->Status = State::Failed;
        this->Reason = std::string("cannot start the compute thread: ") + e.what();
        return;
      }
      const bool answered = this->DoneCv.wait_for(
        lock, kCreateTimeout, [this] { return this->Status != State::Starting; });
      if (!answered)
      {
        this->Status = State::Failed;
        this->Reason = "creating the EGL context took longer than 60 s";
        this->StopRequested = true;
        lock.unlock();
        this->Worker.detach();
        return;
      }
      if (this->Status == State::Failed)
      {
        lock.unlock();
        this->Worker.join();
        vtkLogF(TRACE, "Terroir compute context unavailable: %s", this->Reason.c_str());
        return;
      }
      lock.unlock();
      vtkLogF(TRACE,
        "Terroir compute context: %s, %s, EGL %s, made in %.1f ms",
        gContextLimits.Renderer.c_str(),
        gContextLimits.Version.c_str(),
        gContextLimits.Platform.c_str(),
        gContextLimits.CreationSeconds * 1e3);
      // Registered now, after the GL driver (and e.g. LLVM) ran its static constructors, so
      // that this runs before their static destructors at exit.
      gInternalsForExit = this;
      std::atexit(
        []
        {
          if (gInternalsForExit)
          {
            static_cast<Internals*>(gInternalsForExit)->Shutdown();
          }
        });
    });
}

//------------------------------------------------------------------------------
void Context::Internals::Shutdown()
{
  if (tlsOnContextThread)
  {
    return; // exit() called from inside a job: the worker cannot join itself
  }
  std::unique_lock<std::mutex> lock(this->Mutex);
  if (this->Status != State::Ready || this->StopRequested)
  {
    if (this->Lost && !this->StopRequested)
    {
      // A lost context's worker may be stuck in the driver: leave it, never wait at exit.
      this->StopRequested = true;
      this->WorkCv.notify_all();
      lock.unlock();
      if (this->Worker.joinable())
      {
        this->Worker.detach();
      }
    }
    return;
  }
  this->StopRequested = true;
  this->WorkCv.notify_all();
  const bool finished =
    this->DoneCv.wait_for(lock, kShutdownTimeout, [this] { return this->WorkerFinished; });
  this->Status = State::Stopped;
  this->Reason = "the compute context has been shut down";
  lock.unlock();
  if (finished)
  {
    this->Worker.join();
  }
  else
  {
    std::fprintf(stderr, "Terroir: the GPU compute thread did not stop within 10 s\n");
    this->Worker.detach();
  }
}

//------------------------------------------------------------------------------
namespace
{
/// The process-wide context, for the fork handler.
Context* gContextForFork = nullptr;
}

Context::Context()
  : Impl(new Internals)
{
  gContextForFork = this;
  gMarkLost = [this](const std::string& why) { this->Impl->MarkLost(why); };
  static std::once_flag forkOnce;
  std::call_once(forkOnce,
    []
    {
      // A child of fork() has a copy of the context's memory but not its worker thread (nor
      // llvmpipe's): a context made in the parent is unusable there. The child gets fresh,
      // unavailable internals (so Auto falls back to the CPU and Run throws instead of waiting
      // forever) and no exit-time shutdown of the parent's copy.
      pthread_atfork(nullptr,
        nullptr,
        []
        {
          Context* ctx = gContextForFork;
          if (!ctx || !ctx->Impl || ctx->Impl->Status == Internals::State::NotStarted)
          {
            return;
          }
          gInternalsForExit = nullptr;
          (void)ctx->Impl.release(); // the parent's copy is left alone (its mutex may be held)
          ctx->Impl.reset(new Internals);
          std::call_once(ctx->Impl->StartOnce, [] {});
          ctx->Impl->Status = Internals::State::Failed;
          ctx->Impl->Reason =
            "the GPU compute context was created before fork() and cannot be used in the child";
        });
    });
}

Context::~Context()
{
  this->Impl->Shutdown();
  if (gInternalsForExit == this->Impl.get())
  {
    gInternalsForExit = nullptr;
  }
  if (this->Impl->Worker.joinable()) // timed out: leave the state to the detached thread
  {
    this->Impl->Worker.detach();
    (void)this->Impl.release();
  }
}

Context& Context::Global()
{
  // Never destroyed: shutdown happens in an atexit handler registered once the driver is
  // loaded (see EnsureStarted), which keeps the order of static destructors safe.
  static Context* instance = new Context;
  return *instance;
}

bool Context::IsAvailable()
{
  this->Impl->EnsureStarted();
  std::lock_guard<std::mutex> lock(this->Impl->Mutex);
  return this->Impl->Status == Internals::State::Ready;
}

std::string Context::UnavailableReason()
{
  this->Impl->EnsureStarted();
  std::lock_guard<std::mutex> lock(this->Impl->Mutex);
  return this->Impl->Status == Internals::State::Ready ? std::string() : this->Impl->Reason;
}

bool Context::HasHardwareDevice()
{
  static std::once_flag once;
  static bool hardware = false;
  std::call_once(once,
    []
    {
      std::string why;
      if (!LibrariesPresent(why))
      {
        return;
      }
      const char* clientExt = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
      if (!clientExt || !HasExtension(clientExt, "EGL_EXT_platform_device") ||
        !(HasExtension(clientExt, "EGL_EXT_device_base") ||
          HasExtension(clientExt, "EGL_EXT_device_enumeration")))
      {
        return;
      }
      EGLint count = 0;
      if (!eglQueryDevicesEXT(0, nullptr, &count) || count <= 0)
      {
        return;
      }
      std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(count));
      eglQueryDevicesEXT(count, devices.data(), &count);
      for (EGLint i = 0; i < count; ++i)
      {
        const char* devExt = eglQueryDeviceStringEXT(devices[i], EGL_EXTENSIONS);
        if (!HasExtension(devExt, "EGL_MESA_device_software"))
        {
          hardware = true;
        }
      }
    });
  return hardware;
}

Limits Context::GetLimits()
{
  this->Impl->EnsureStarted();
  std::lock_guard<std::mutex> lock(this->Impl->Mutex);
  if (this->Impl->Status != Internals::State::Ready)
  {
    return Limits();
  }
  Limits limits = gContextLimits;
  if (this->Impl->BlockLimit > 0 && limits.MaxShaderStorageBlockSize > 0)
  {
    limits.MaxShaderStorageBlockSize =
      std::min(limits.MaxShaderStorageBlockSize, this->Impl->BlockLimit);
  }
  return limits;
}

void Context::SetStorageBlockLimit(long long bytes)
{
  std::lock_guard<std::mutex> lock(this->Impl->Mutex);
  this->Impl->BlockLimit = bytes > 0 ? bytes : 0;
}

void Context::Run(const std::function<void()>& job)
{
  this->Run(std::string(), kDefaultBudgetSeconds, job);
}

void Context::Run(const std::string& stage, double budgetSeconds, const std::function<void()>& job)
{
  if (!job)
  {
    throw Error("terroir::gpu::Context::Run: empty job");
  }
  if (tlsOnContextThread)
  {
    job(); // re-entrant call from inside a job: the outer job's stage and budget apply
    return;
  }
  if (!(budgetSeconds > 0.0))
  {
    budgetSeconds = kDefaultBudgetSeconds;
  }
  this->Impl->EnsureStarted();
  auto task = std::make_shared<Internals::Task>();
  task->Job = job;
  task->Stage = stage;
  task->BudgetSeconds = budgetSeconds;
  {
    std::unique_lock<std::mutex> lock(this->Impl->Mutex);
    if (this->Impl->Status != Internals::State::Ready || this->Impl->StopRequested)
    {
      throw Error("GPU compute context unavailable: " + this->Impl->Reason);
    }
    this->Impl->Queue.push_back(task);
    this->Impl->WorkCv.notify_one();
    // Jobs queued before this one have budgets of their own: wait for them too, then for the
    // budget of this one and a grace period (the job normally throws at its deadline first).
    for (;;)
    {
      const double grace = std::min(60.0, 5.0 + 0.5 * budgetSeconds);
      const auto limit = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(budgetSeconds + grace));
      if (this->Impl->DoneCv.wait_for(lock, limit, [&task] { return task->Done; }))
      {
        break;
      }
      auto queued = std::find(this->Impl->Queue.begin(), this->Impl->Queue.end(), task);
      if (queued != this->Impl->Queue.end())
      {
        continue; // not started yet: an earlier job holds the worker (it has its own limit)
      }
      // The job started and never returned: the driver or the GPU hangs.
      std::ostringstream msg;
      msg << (stage.empty() ? std::string("GPU job") : stage)
          << ": the GPU did not finish within the stage's budget of " << budgetSeconds
          << " s (the driver does not return); the compute context is given up, so GPU stages "
             "now run on the CPU under Auto (TERROIR_GPU_BUDGET_SCALE raises the budget of a "
             "slow GPU)";
      this->Impl->Lost = true;
      this->Impl->Status = Internals::State::Failed;
      this->Impl->Reason = msg.str();
      throw Error(msg.str());
    }
  }
  if (task->Error)
  {
    std::rethrow_exception(task->Error);
  }
}

double Context::Budget(double workUnits)
{
  double scale = 1.0;
  if (const char* env = std::getenv("TERROIR_GPU_BUDGET_SCALE"))
  {
    char* end = nullptr;
    const double v = std::strtod(env, &end);
    if (end != env && v > 0.0 && std::isfinite(v))
    {
      scale = v;
    }
  }
  return scale * (60.0 + 1e-6 * std::max(0.0, workUnits));
}

Program& Context::GetProgram(const std::string& name,
  const std::string& source,
  const std::vector<std::string>& defines)
{
  detail::RequireContextThread("terroir::gpu::Context::GetProgram");
  std::string key = name;
  for (const auto& d : defines)
  {
    key += '\n';
    key += d;
  }
  auto it = this->Impl->Programs.find(key);
  if (it != this->Impl->Programs.end())
  {
    if (it->second.Source != source)
    {
      throw Error(name + ": GetProgram called again with a different source for the same name");
    }
    return *it->second.Prog;
  }
  Internals::CachedProgram entry;
  entry.Source = source;
  entry.Prog.reset(new Program(name, source, defines)); // throws on compile/link failure
  detail::RestoreHostFloatingPoint();
  Program& result = *entry.Prog;
  this->Impl->Programs.emplace(key, std::move(entry));
  return result;
}

void Context::WaitIdle()
{
  detail::RequireContextThread("terroir::gpu::Context::WaitIdle");
  detail::WaitAll("WaitIdle");
}

void Context::Finish()
{
  this->WaitIdle();
}

void Context::ClearResident()
{
  if (!this->IsAvailable())
  {
    return;
  }
  this->Run(
    []
    {
      detail::Runtime& rt = detail::State();
      rt.ResidentList.clear();
      rt.ResidentBytes = 0;
    });
}

void Context::TrimPool()
{
  {
    std::lock_guard<std::mutex> lock(this->Impl->Mutex);
    if (this->Impl->Status != Internals::State::Ready)
    {
      return;
    }
  }
  this->Run([] { detail::TrimFree(0); });
}

std::size_t Context::PooledBytes()
{
  std::size_t bytes = 0;
  if (this->IsAvailable())
  {
    this->Run([&bytes] { bytes = detail::State().FreeBytes; });
  }
  return bytes;
}

std::size_t Context::ResidentBytes()
{
  std::size_t bytes = 0;
  if (this->IsAvailable())
  {
    this->Run([&bytes] { bytes = detail::State().ResidentBytes; });
  }
  return bytes;
}

Stats Context::GetStats()
{
  detail::Runtime& rt = detail::State();
  std::lock_guard<std::mutex> lock(rt.CountersMutex);
  return rt.Counters;
}

void Context::ResetStats()
{
  detail::Runtime& rt = detail::State();
  std::lock_guard<std::mutex> lock(rt.CountersMutex);
  rt.Counters = Stats();
}

void Context::SetProfiling(bool on)
{
  this->Impl->EnsureStarted();
  if (this->IsAvailable())
  {
    this->Run([on] { detail::State().Profiling = on; });
  }
}

bool Context::GetProfiling()
{
  return detail::State().Profiling;
}

void Context::SetTransfer(Transfer method)
{
  if (this->IsAvailable())
  {
    this->Run(
      [method]
      {
        detail::Runtime& rt = detail::State();
        if (rt.Method == method)
        {
          return;
        }
        // Buffers are made with the flags of their method: start afresh.
        rt.ResidentList.clear();
        rt.ResidentBytes = 0;
        detail::TrimFree(0);
        rt.Method = gContextLimits.ImmutableStorage ? method : Transfer::SubData;
      });
  }
}

Transfer Context::GetTransfer()
{
  this->Impl->EnsureStarted();
  return detail::State().Method;
}

void Context::SetStressModes(const std::string& modes)
{
  if (this->IsAvailable())
  {
    this->Run([modes] { ApplyStress(modes); });
  }
}

std::string Context::StressModes()
{
  this->Impl->EnsureStarted();
  return detail::State().StressText;
}

bool Context::IsLost()
{
  std::lock_guard<std::mutex> lock(this->Impl->Mutex);
  return this->Impl->Lost;
}

//------------------------------------------------------------------------------
namespace detail
{
bool OnContextThread()
{
  return tlsOnContextThread;
}

void RequireContextThread(const char* what)
{
  if (!tlsOnContextThread)
  {
    throw Error(std::string(what) + " must be used inside terroir::gpu::Context::Run");
  }
}

void ClearGLErrors()
{
  for (int i = 0; i < 32 && glGetError() != GL_NO_ERROR; ++i)
  {
  }
}

std::string GLErrorName(unsigned error)
{
  const char* name = nullptr;
  switch (error)
  {
    case GL_INVALID_ENUM:
      name = "GL_INVALID_ENUM";
      break;
    case GL_INVALID_VALUE:
      name = "GL_INVALID_VALUE";
      break;
    case GL_INVALID_OPERATION:
      name = "GL_INVALID_OPERATION";
      break;
    case GL_INVALID_FRAMEBUFFER_OPERATION:
      name = "GL_INVALID_FRAMEBUFFER_OPERATION";
      break;
    case GL_OUT_OF_MEMORY:
      name = "GL_OUT_OF_MEMORY";
      break;
    default:
      name = "GL error";
  }
  return std::string(name) + " (" + Hex(error) + ")";
}

void CheckGLError(const std::string& what)
{
  const GLenum err = glGetError();
  if (err != GL_NO_ERROR)
  {
    ClearGLErrors();
    throw Error(what + ": " + GLErrorName(err));
  }
}

const Limits& ContextLimits()
{
  return gContextLimits;
}

const char* CommonSource()
{
  return vtkTerroirCommonGLSL;
}

Runtime& State()
{
  static Runtime* runtime = new Runtime; // never destroyed (used until the worker stops)
  return *runtime;
}

void CheckDeadline(const char* what)
{
  const Runtime& rt = State();
  if (Clock::now() >= rt.Deadline)
  {
    std::ostringstream msg;
    msg << (rt.Stage.empty() ? std::string("GPU job") : rt.Stage)
        << ": past the stage's time budget of " << rt.BudgetSeconds << " s (before " << what
        << "); stopped (TERROIR_GPU_BUDGET_SCALE raises the budget of a slow GPU)";
    throw Error(msg.str());
  }
}

unsigned FloatingPointControl()
{
#if defined(__x86_64__) || defined(__i386__)
  // MXCSR without its exception flags, and the x87 control word (precision and rounding of
  // the x87 unit, which parts of libm use).
  unsigned short x87 = 0;
  __asm__ __volatile__("fnstcw %0" : "=m"(x87));
  return (_mm_getcsr() & 0xffc0u) | (static_cast<unsigned>(x87) << 16);
#else
  return static_cast<unsigned>(std::fegetround());
#endif
}

void RestoreHostFloatingPoint()
{
  Runtime& rt = State();
  if (rt.HostEnvSet && FloatingPointControl() != rt.HostControl)
  {
    std::fesetenv(&rt.HostEnv);
    Count([](Stats& c) { ++c.HostFloatingPointResets; });
  }
}

void MarkLost(const std::string& reason)
{
  if (gMarkLost)
  {
    gMarkLost(reason);
  }
}
} // namespace detail

} // namespace gpu
} // namespace terroir

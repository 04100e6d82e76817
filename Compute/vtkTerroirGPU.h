/**
 * @file vtkTerroirGPU.h
 * @brief GL-free C++ interface to Terroir's headless compute context (not wrapped).
 *
 * One OpenGL 4.3+ core context, made through EGL (the device platform on NVIDIA, Mesa's
 * surfaceless platform elsewhere, e.g. llvmpipe), lives on its own worker thread. Filters
 * never include GL headers: they post a job with `Context::Run`, and inside the job they
 * create `StorageBuffer`s, get cached `Program`s and dispatch them. Every GL object must be
 * created, used and destroyed inside a job (on the context thread).
 *
 * Typical use in a filter's GPU path:
 * @code
 * auto& ctx = terroir::gpu::Context::Global();
 * ctx.Run([&] {
 *   terroir::gpu::StorageBuffer in(n * sizeof(float), elevation);
 *   terroir::gpu::StorageBuffer out(n * sizeof(float));
 *   auto& prog = ctx.GetProgram("Slope.comp", vtkTerroirSlopeCS, { "LOCAL_X 16", "LOCAL_Y 16" });
 *   prog.Use();
 *   prog.SetInt("uNx", nx);
 *   in.Bind(0);
 *   out.Bind(1);
 *   prog.Dispatch((nx + 15) / 16, (ny + 15) / 16);
 *   out.Download(result, n * sizeof(float));
 * });
 * @endcode
 */
#ifndef vtkTerroirGPU_h
#define vtkTerroirGPU_h

#include "vtkTerroirComputeModule.h" // For export macro

#include <cstddef>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

namespace terroir
{
namespace gpu
{

/// Thrown for GL failures (shader compile/link errors carry the file name and driver log).
class VTKTERROIRCOMPUTE_EXPORT Error : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/// What the context reported when it was probed.
struct Limits
{
  int MajorVersion = 0;
  int MinorVersion = 0;
  int MaxWorkGroupCount[3] = { 0, 0, 0 };
  int MaxWorkGroupSize[3] = { 0, 0, 0 };
  int MaxWorkGroupInvocations = 0;
  long long MaxShaderStorageBlockSize = 0; ///< bytes
  std::string Vendor;
  std::string Renderer;
  std::string Version;
  std::string Platform;                   ///< EGL platform used ("device", "surfaceless")
  int MaxShaderStorageBufferBindings = 0; ///< number of SSBO binding points
  double CreationSeconds = 0.0;           ///< wall time to create and probe the context
};

/// RAII shader storage buffer (GL_SHADER_STORAGE_BUFFER). Context thread only: construction
/// and every method throw `Error` elsewhere; out-of-range Upload/Download and allocation
/// failure (GL_OUT_OF_MEMORY, with the byte count) throw `Error` too.
class VTKTERROIRCOMPUTE_EXPORT StorageBuffer
{
public:
  /// Allocates `bytes` (> 0) and uploads `data` if not null (otherwise zero-filled).
  explicit StorageBuffer(std::size_t bytes, const void* data = nullptr);
  ~StorageBuffer();
  StorageBuffer(StorageBuffer&& other) noexcept;
  StorageBuffer& operator=(StorageBuffer&& other) noexcept;
  StorageBuffer(const StorageBuffer&) = delete;
  StorageBuffer& operator=(const StorageBuffer&) = delete;

  std::size_t Size() const { return this->Bytes; }
  void Upload(const void* src, std::size_t bytes, std::size_t offset = 0);
  void Download(void* dst, std::size_t bytes, std::size_t offset = 0) const;
  /// Fills the whole buffer with zero bytes.
  void Clear();
  /// Binds to `binding` of GL_SHADER_STORAGE_BUFFER (the shader's `layout(std430, binding = N)`).
  void Bind(unsigned binding) const;
  unsigned Id() const { return this->Handle; }

private:
  unsigned Handle = 0;
  std::size_t Bytes = 0;
};

/// RAII compute program. The source has no `#version`: the program prepends
/// `#version 430 core`, one `#define` per entry of `defines` (e.g. "LOCAL_X 16"),
/// Shaders/Common.glsl, then `#line 1`. Compile or link failure throws `Error` with the
/// shader's name, the numbered source and the driver log. Context thread only.
class VTKTERROIRCOMPUTE_EXPORT Program
{
public:
  Program(const std::string& name,
    const std::string& source,
    const std::vector<std::string>& defines = {});
  ~Program();
  Program(const Program&) = delete;
  Program& operator=(const Program&) = delete;

  const std::string& Name() const { return this->ShaderName; }
  void Use() const;
  ///@{
  /// Set a uniform of the program (calls Use() first). Unknown names are ignored, as GL does.
  void SetInt(const char* name, int value);
  void SetUInt(const char* name, unsigned value);
  void SetFloat(const char* name, float value);
  void SetVec2(const char* name, float x, float y);
  void SetVec3(const char* name, float x, float y, float z);
  void SetFloatArray(const char* name, const float* values, int count);
  void SetVec4(const char* name, float x, float y, float z, float w);
  void SetIVec2(const char* name, int x, int y);
  void SetUVec2(const char* name, unsigned x, unsigned y);
  void SetIntArray(const char* name, const int* values, int count);
  ///@}
  /// glDispatchCompute followed by a shader-storage + buffer-update memory barrier.
  /// Throws `Error` when a group count exceeds GL_MAX_COMPUTE_WORK_GROUP_COUNT; a zero
  /// count dispatches nothing.
  void Dispatch(unsigned groupsX, unsigned groupsY = 1, unsigned groupsZ = 1);
  /// GL program object name (for debugging).
  unsigned Id() const { return this->Handle; }

private:
  int Location(const char* name);

  std::string ShaderName;
  unsigned Handle = 0;
  std::unordered_map<std::string, int> Locations; ///< uniform locations, looked up once
};

/// The process-wide compute context on its own worker thread. `Global()` is never destroyed:
/// an atexit handler stops and joins the worker (deleting the GL objects on it) at process
/// exit. In a child of fork() made after the context existed, the context is unavailable.
/// See Documentation/Compute.md.
class VTKTERROIRCOMPUTE_EXPORT Context
{
public:
  static Context& Global();

  /// Creates the context on first call (thread-safe) and says whether it works
  /// (GL >= 4.3 core with compute shaders). Never aborts the process.
  bool IsAvailable();
  /// Why the context is unavailable (empty when available).
  std::string UnavailableReason();

  /// Cheap probe, done once and without making a context: does EGL enumerate a hardware
  /// device (one without EGL_MESA_device_software)? False when EGL is missing or lists only
  /// software rasterizers (llvmpipe). Used by `Auto` to avoid starting a context that it would
  /// not use.
  bool HasHardwareDevice();
  /// Limits probed when the context was made (zeros when unavailable).
  Limits GetLimits();

  /// Runs `job` on the context thread and waits for it. Exceptions thrown by the job are
  /// re-thrown in the caller. Throws `Error` when the context is unavailable. Jobs from
  /// several threads are serialised.
  void Run(const std::function<void()>& job);

  /// A program compiled once and cached by (name, defines). Only inside `Run`.
  Program& GetProgram(const std::string& name,
    const std::string& source,
    const std::vector<std::string>& defines = {});

  /// glFinish; only inside `Run`.
  void Finish();

  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

private:
  Context();
  struct Internals;
  std::unique_ptr<Internals> Impl;
};

} // namespace gpu
} // namespace terroir

#endif

/**
 * @file vtkTerroirGPU.h
 * @brief GL-free C++ interface to Terroir's headless compute context (not wrapped).
 *
 * One OpenGL 4.3+ core context, made through EGL (the device platform on NVIDIA, Mesa's
 * surfaceless platform elsewhere, e.g. llvmpipe), lives on its own worker thread. Filters
 * never include GL headers: they post a job with `Context::Run`, and inside the job they
 * create `StorageBuffer`s (taken from a pool, returned to it when destroyed), get cached
 * `Program`s and dispatch them. Every GL object must be created, used and destroyed inside a
 * job (on the context thread).
 *
 * Typical use in a filter's GPU path:
 * @code
 * auto& ctx = terroir::gpu::Context::Global();
 * ctx.Run("slope", terroir::gpu::Context::Budget(n), [&] {
 *   auto in = ctx.Resident(elevationArray, elevationArray->GetMTime(), n * 4, elevation);
 *   terroir::gpu::StorageBuffer out(n * sizeof(float), terroir::gpu::Contents::Undefined);
 *   auto& prog = ctx.GetProgram("Slope.comp", vtkTerroirSlopeCS, { "LOCAL_X 16", "LOCAL_Y 16" });
 *   prog.SetInt("uNx", nx);
 *   in->Bind(0);
 *   out.Bind(1);
 *   prog.Dispatch((nx + 15) / 16, (ny + 15) / 16);
 *   out.Download(result, n * sizeof(float));
 * });
 * @endcode
 * See Documentation/Compute.md.
 */
#ifndef vtkTerroirGPU_h
#define vtkTerroirGPU_h

#include "vtkTerroirComputeModule.h" // For export macro

#include <cstddef>
#include <cstdint>
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

/// Thrown for GL failures (shader compile/link errors carry the file name and driver log), for
/// a stage that runs past its time budget, and for work on a lost or unavailable context.
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
  long long DeviceMemoryBytes = 0; ///< total device memory (GL_NVX_gpu_memory_info), 0: unknown
  bool ImmutableStorage = false;   ///< glBufferStorage (GL 4.4 or ARB_buffer_storage)

  /// The largest storage block a kernel may bind, bytes; `unknown` when the driver did not say.
  std::size_t StorageBlockBytes(std::size_t unknown = std::size_t(128) << 20) const
  {
    return this->MaxShaderStorageBlockSize > 0
      ? static_cast<std::size_t>(this->MaxShaderStorageBlockSize)
      : unknown;
  }
};

/// What a new StorageBuffer that is given no data holds.
enum class Contents
{
  Zero,     ///< every byte 0
  Undefined ///< anything (the bytes of an earlier user of the pooled buffer; with
            ///< TERROIR_GPU_STRESS=fill-nan or fill-pattern a pattern no kernel may rely on)
};

/// How uploads and downloads move bytes between host memory and storage buffers.
enum class Transfer
{
  SubData, ///< glBufferSubData / glGetBufferSubData
  Staging, ///< a persistently mapped staging ring and glCopyBufferSubData (GL 4.4)
  Mapped   ///< glMapBufferRange of the buffer itself and a copy on all cores (GL 4.4; for
           ///< software rasterizers, whose buffers are host memory)
};

/// Counters and times of the compute layer since the last Context::ResetStats (all threads).
/// The times of allocations, transfers and dispatches are measured only while profiling is on
/// (Context::SetProfiling), which waits for the GPU around each operation to attribute it.
struct Stats
{
  unsigned long long BuffersCreated = 0;      ///< GL buffer objects made (pool misses)
  unsigned long long BytesCreated = 0;        ///< their bytes
  unsigned long long BuffersReused = 0;       ///< StorageBuffers served by the pool
  unsigned long long Uploads = 0;             ///< Upload calls and buffers made with data
  unsigned long long BytesUploaded = 0;       ///<
  unsigned long long Downloads = 0;           ///< Download calls
  unsigned long long BytesDownloaded = 0;     ///<
  unsigned long long ResidentHits = 0;        ///< Context::Resident served without an upload
  unsigned long long ResidentBytesReused = 0; ///< bytes those uploads would have moved
  unsigned long long Dispatches = 0;          ///< Program::Dispatch calls
  unsigned long long Waits = 0;               ///< host waits for the GPU (fences)
  /// Times a GL call had changed the context thread's floating-point control (rounding, flush
  /// to zero) and it was put back (host arithmetic inside jobs must be the CPU's).
  unsigned long long HostFloatingPointResets = 0;
  double AllocSeconds = 0.0;    ///< buffer creation and fills (profiling)
  double UploadSeconds = 0.0;   ///< uploads (profiling)
  double DownloadSeconds = 0.0; ///< downloads, excluding the kernels before them
  double DispatchSeconds = 0.0; ///< wall time of dispatches to completion (profiling)
  double KernelSeconds = 0.0;   ///< GL timer queries of the dispatches (profiling; about 0 where
                                ///< the driver's timer misses compute work, as llvmpipe's)
  double JobSeconds = 0.0;      ///< wall time inside Context::Run jobs
};

/// Work groups of one dispatch.
struct Groups
{
  unsigned x = 0;
  unsigned y = 1;
};

/// A 1-D range of invocations laid out as gx x gy groups of `Local` (a kernel finds its
/// invocation as t = id.y * gx * Local + id.x, gx = TERROIR_NUM_WORKGROUPS.x), within
/// GL_MAX_COMPUTE_WORK_GROUP_COUNT and 32-bit indices.
struct GridPlan
{
  std::size_t Local = 256;
  std::size_t MaxX = 65535;
  std::size_t MaxY = 65535;
  std::size_t MaxItems = 0; ///< items (of `perItem` invocations) one dispatch can cover
  /// The groups covering `invocations` (at most MaxItems * perItem).
  Groups For(std::size_t invocations) const;
};

/// The plan for items of `perItem` invocations in groups of `local` on a context with `limits`.
VTKTERROIRCOMPUTE_EXPORT GridPlan PlanGrid(const Limits& limits,
  std::size_t perItem,
  std::size_t local);

/// Flags (one byte per cell, nonzero = set) packed four to a uint as the kernels read them:
/// byte k of word w is 1 or 0 for cell 4w + k. At least one word (zero) when `n` is 0.
VTKTERROIRCOMPUTE_EXPORT std::vector<std::uint32_t> PackFlags(const std::uint8_t* flags,
  std::size_t n);

/// RAII shader storage buffer (GL_SHADER_STORAGE_BUFFER) from the context's pool. Context
/// thread only: construction and every method throw `Error` elsewhere; out-of-range transfers
/// and allocation failure (GL_OUT_OF_MEMORY, with the byte count) throw `Error` too.
class VTKTERROIRCOMPUTE_EXPORT StorageBuffer
{
public:
  /// `bytes` (> 0) holding `data` when not null, otherwise zero-filled.
  explicit StorageBuffer(std::size_t bytes, const void* data = nullptr);
  /// `bytes` (> 0) holding zeros or undefined bytes (for outputs a kernel writes in full).
  StorageBuffer(std::size_t bytes, Contents contents);
  /// Returns the GL buffer to the pool.
  ~StorageBuffer();
  StorageBuffer(StorageBuffer&& other) noexcept;
  StorageBuffer& operator=(StorageBuffer&& other) noexcept;
  StorageBuffer(const StorageBuffer&) = delete;
  StorageBuffer& operator=(const StorageBuffer&) = delete;

  /// Bytes asked for (what Bind exposes and transfers may touch).
  std::size_t Size() const { return this->Bytes; }
  /// Bytes of the pooled GL buffer behind it (>= Size()).
  std::size_t Capacity() const { return this->CapacityBytes; }
  void Upload(const void* src, std::size_t bytes, std::size_t offset = 0);
  /// Waits (within the job's budget) for the GPU work that writes the buffer, then copies.
  void Download(void* dst, std::size_t bytes, std::size_t offset = 0) const;
  /// Copies `bytes` of `src` (from `srcOffset`) to `dstOffset` of this buffer, on the GPU.
  void CopyFrom(const StorageBuffer& src,
    std::size_t bytes,
    std::size_t srcOffset = 0,
    std::size_t dstOffset = 0);
  /// Fills the whole buffer with zero bytes.
  void Clear();
  /// Binds [0, Size()) to `binding` of GL_SHADER_STORAGE_BUFFER (the shader's
  /// `layout(std430, binding = N)`).
  void Bind(unsigned binding) const;
  unsigned Id() const { return this->Handle; }

private:
  void Acquire(std::size_t bytes, const void* data, Contents contents);
  void Release() noexcept;

  unsigned Handle = 0;
  std::size_t Bytes = 0;
  std::size_t CapacityBytes = 0;
};

/// A point in the GL command stream (glFenceSync). Context thread only.
class VTKTERROIRCOMPUTE_EXPORT Fence
{
public:
  /// Inserts the fence after the commands issued so far.
  Fence();
  ~Fence();
  Fence(Fence&& other) noexcept;
  Fence& operator=(Fence&& other) noexcept;
  Fence(const Fence&) = delete;
  Fence& operator=(const Fence&) = delete;

  /// True when the GPU has passed the fence (does not wait).
  bool IsSignaled();
  /// Waits for the fence within the job's time budget (Error past it).
  void Wait();

private:
  void* Sync = nullptr;
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
  /**
   * glDispatchCompute followed by a shader-storage + buffer-update memory barrier. Throws
   * `Error` when a group count exceeds GL_MAX_COMPUTE_WORK_GROUP_COUNT or when the job is past
   * its time budget; a zero count dispatches nothing. Kernels read their group and invocation
   * ids through Common.glsl's TERROIR_WORKGROUP_ID / TERROIR_GLOBAL_ID /
   * TERROIR_NUM_WORKGROUPS, so that the stress modes `split` and `shuffle`
   * (TERROIR_GPU_STRESS) can issue the groups as several dispatches, in any order.
   */
  void Dispatch(unsigned groupsX, unsigned groupsY = 1, unsigned groupsZ = 1);
  /// GL program object name (for debugging).
  unsigned Id() const { return this->Handle; }

private:
  int Location(const char* name);

  std::string ShaderName;
  unsigned Handle = 0;
  int GroupOffsetLocation = -1;                   ///< Common.glsl's terroirGroupOffset
  int GroupCountLocation = -1;                    ///< Common.glsl's terroirGroupCount
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
  /// (GL >= 4.3 core with compute shaders, not lost). Never aborts the process.
  bool IsAvailable();
  /// Why the context is unavailable (empty when available).
  std::string UnavailableReason();

  /// Cheap probe, done once and without making a context: does EGL enumerate a hardware
  /// device (one without EGL_MESA_device_software)? False when EGL is missing or lists only
  /// software rasterizers (llvmpipe). Used by `Auto` to avoid starting a context that it would
  /// not use.
  bool HasHardwareDevice();
  /// Limits probed when the context was made (zeros when unavailable), with
  /// MaxShaderStorageBlockSize capped by SetStorageBlockLimit.
  Limits GetLimits();
  /// Caps the MaxShaderStorageBlockSize that GetLimits reports (bytes; 0, the default: the
  /// device's own). Filters then split their work into bands as on a device with that limit:
  /// the tests of the banded paths run on any GPU, small.
  void SetStorageBlockLimit(long long bytes);

  /// Runs `job` on the context thread and waits for it, with the default budget (10 min).
  /// Exceptions thrown by the job are re-thrown in the caller. Throws `Error` when the context
  /// is unavailable. Jobs from several threads are serialised.
  void Run(const std::function<void()>& job);
  /**
   * Runs `job` as the stage `stage` with a time budget of `budgetSeconds` (see Budget()).
   * GPU waits inside the job (downloads, fences, WaitIdle, dispatches) throw `Error` naming
   * the stage once the budget is spent; if the job itself does not return within the budget
   * plus a grace period (the GPU or driver hangs), the caller gets that `Error`, and the
   * context is marked lost: later jobs throw and `Auto` runs on the CPU. Never hangs.
   */
  void Run(const std::string& stage, double budgetSeconds, const std::function<void()>& job);
  /// A generous budget for a job of `workUnits` (cells times passes or steps): 60 s plus
  /// 1 microsecond per unit (llvmpipe needs 10-100 ns), times TERROIR_GPU_BUDGET_SCALE (>0).
  static double Budget(double workUnits);

  /// A program compiled once and cached by (name, defines). Only inside `Run`.
  Program& GetProgram(const std::string& name,
    const std::string& source,
    const std::vector<std::string>& defines = {});

  /// Waits until the GPU has finished the commands issued so far, within the job's budget.
  /// Only inside `Run`.
  void WaitIdle();
  /// Same as WaitIdle (kept for timings).
  void Finish();

  ///@{
  /**
   * Device copies of host arrays that outlive jobs, so that a filter chain uploads an array
   * once. `key` identifies the host array (e.g. its vtkDataArray*), `stamp` its version (its
   * MTime): `Resident` returns the cached buffer when (key, stamp, bytes) match, else uploads
   * `data` (bytes) and caches it. `KeepResident` caches a buffer that a kernel wrote and whose
   * host copy is `key` at `stamp`; `FindResident` only looks. Keys are identities, never
   * dereferenced. The least recently used entries are dropped beyond
   * TERROIR_GPU_CACHE_MB (default 1024, or a quarter of the device memory when known). Only
   * inside `Run`. `ClearResident` drops every entry (any thread).
   */
  std::shared_ptr<StorageBuffer> Resident(const void* key,
    unsigned long long stamp,
    std::size_t bytes,
    const void* data);
  /// The cached buffer of (key, stamp, bytes), or null (no upload).
  std::shared_ptr<StorageBuffer> FindResident(const void* key,
    unsigned long long stamp,
    std::size_t bytes);
  void KeepResident(const void* key,
    unsigned long long stamp,
    std::shared_ptr<StorageBuffer> buffer);
  void ClearResident();
  ///@}

  /// Deletes the pool's free buffers (any thread; a no-op when the context was never made).
  void TrimPool();
  /// Bytes held by the pool's free buffers and by the resident cache.
  std::size_t PooledBytes();
  std::size_t ResidentBytes();

  ///@{
  /// Counters and times (see Stats); profiling adds GL timer queries and waits around each
  /// operation, to attribute time (use for breakdowns, not for the fastest run).
  Stats GetStats();
  void ResetStats();
  void SetProfiling(bool on);
  bool GetProfiling();
  ///@}

  ///@{
  /// The transfer method (default: TERROIR_GPU_TRANSFER=subdata|staging|mapped, else Staging
  /// on hardware devices and Mapped on software rasterizers; Documentation/Compute.md has the
  /// measurements). Buffers made under one method are kept for it: set it before any work.
  void SetTransfer(Transfer method);
  Transfer GetTransfer();
  ///@}

  /// Stress modes from TERROIR_GPU_STRESS (comma-separated: fill-nan, fill-pattern, split,
  /// shuffle), for tests that must catch kernels relying on llvmpipe's zeroed memory or order.
  std::string StressModes();
  /// Replaces the stress modes (the same list as TERROIR_GPU_STRESS; "" turns them off).
  void SetStressModes(const std::string& modes);

  /// Read + write bytes per second of a copy kernel (one uint per invocation) over two buffers
  /// of `bytes`, best of `repeats` dispatches after a warm-up, timed with GL timer queries (or
  /// the wall time to completion where the timer misses compute work, as llvmpipe's does): the
  /// reference for kernels' share of the GPU's bandwidth. Throws when unavailable.
  double MeasureCopyBandwidth(std::size_t bytes = std::size_t(64) << 20, int repeats = 5);

  /// The copy kernel MeasureCopyBandwidth times (dst[i] = src[i], one uint per invocation, a
  /// 2-D grid of 256-wide groups, uniform uN; bindings 0 src, 1 dst), for tests that need one.
  static const char* CopyKernelSource();

  /// True once a stage ran past its budget (the context is then unavailable).
  bool IsLost();

  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

private:
  Context();
  struct Internals;
  std::unique_ptr<Internals> Impl;
  friend class StorageBuffer;
  friend class Program;
  friend class Fence;
};

} // namespace gpu
} // namespace terroir

#endif

/**
 * @file vtkTerroirGPUPrivate.h
 * @brief Internal helpers shared by the Terroir::Compute sources (not installed, no GL types).
 */
#ifndef vtkTerroirGPUPrivate_h
#define vtkTerroirGPUPrivate_h

#include "vtkTerroirGPU.h"

#include <cfenv>
#include <chrono>
#include <cstddef>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace terroir
{
namespace gpu
{
namespace detail
{

/// True on the compute context's worker thread (that is, inside `Context::Run`).
bool OnContextThread();

/// Throws `Error` ("<what> must be used inside terroir::gpu::Context::Run") off the context thread.
void RequireContextThread(const char* what);

/// Drains pending GL errors (bounded), so that the next check only sees new ones.
void ClearGLErrors();

/// Throws `Error` "<what>: GL error GL_INVALID_OPERATION (0x0502)" when glGetError reports one.
void CheckGLError(const std::string& what);

/// Symbolic name of a GL error code ("GL_OUT_OF_MEMORY (0x0505)").
std::string GLErrorName(unsigned error);

/// The limits probed when the context was made; only valid on the context thread.
const Limits& ContextLimits();

/// Shaders/Common.glsl, embedded at build time.
const char* CommonSource();

using Clock = std::chrono::steady_clock;

/// State of the compute layer shared by its sources. Everything but `Counters` (guarded by
/// `CountersMutex`) and the settings (written before use or under their own rules) belongs to
/// the context thread.
struct Runtime
{
  // Settings (read once when the context starts; the setters of Context change them).
  bool Profiling = false;
  Transfer Method = Transfer::SubData;
  bool FillNaN = false;     ///< TERROIR_GPU_STRESS fill-nan: undefined buffers are 0xff bytes
  bool FillPattern = false; ///< fill-pattern: 0xcd bytes (a small negative float)
  bool Split = false;       ///< split: dispatches cut into several
  bool Shuffle = false;     ///< shuffle: ... and issued in a random order
  /// TERROIR_GPU_LEGACY_BUFFERS=1 (diagnosis): buffers made as before the pool (glBufferData,
  /// zero-filled on the GPU, then uploaded with glBufferSubData; deleted, not pooled).
  bool Legacy = false;
  std::string StressText;
  std::size_t PoolCapBytes = std::size_t(512) << 20;
  std::size_t ResidentCapBytes = std::size_t(1024) << 20;

  // Counters (any thread reads them).
  std::mutex CountersMutex;
  Stats Counters;

  // The context thread's floating-point environment before the driver was loaded (context
  // thread): GL drivers may change it (rounding, flush to zero), and host arithmetic inside jobs
  // (k-means' centres, the water flow's tables and volumes) must be the CPU path's.
  std::fenv_t HostEnv;
  bool HostEnvSet = false;
  unsigned HostControl = 0; ///< FloatingPointControl() at that time

  // The job now running (context thread).
  std::string Stage;
  double BudgetSeconds = 0.0;
  Clock::time_point Deadline = Clock::time_point::max();

  // Pool of free GL buffers by capacity (context thread).
  std::multimap<std::size_t, unsigned> Free;
  std::list<std::pair<std::size_t, unsigned>> FreeOrder; ///< oldest release first
  std::size_t FreeBytes = 0;

  // Resident cache (context thread), most recently used last.
  struct ResidentEntry
  {
    const void* Key = nullptr;
    unsigned long long Stamp = 0;
    std::shared_ptr<StorageBuffer> Buffer;
  };
  std::list<ResidentEntry> ResidentList;
  std::size_t ResidentBytes = 0;

  // Staging ring (context thread): one persistently mapped buffer cut into slots.
  unsigned StagingHandle = 0;
  unsigned char* StagingPtr = nullptr;
  std::size_t SlotBytes = 0;
  std::vector<void*> SlotFences;
  std::size_t NextSlot = 0;

  // Timer queries of the dispatches not yet read (profiling).
  std::vector<unsigned> PendingQueries;
};

/// The one runtime of the process.
Runtime& State();

/// Adds to the counters (thread-safe).
template<typename F>
void Count(F&& update)
{
  Runtime& rt = State();
  std::lock_guard<std::mutex> lock(rt.CountersMutex);
  update(rt.Counters);
}

/// Puts the context thread's floating-point environment back when a GL call changed its control
/// settings (counted in Stats::HostFloatingPointResets). Called after the GL calls of the
/// Compute classes and before each job.
void RestoreHostFloatingPoint();

/// The control part of the current floating-point environment (on x86 MXCSR without its flags
/// and the x87 control word, else the rounding mode).
unsigned FloatingPointControl();

/// Throws `Error` naming the stage when the running job is past its deadline.
void CheckDeadline(const char* what);

/// Waits for a GL sync object within the job's deadline (throws past it; marks the context
/// lost, since the GPU is still busy with work that will not finish in time).
void WaitSync(void* sync, const char* what);

/// Inserts a fence and waits for it (WaitIdle).
void WaitAll(const char* what);

/// Marks the context lost with `reason` (later jobs throw, Auto runs on the CPU).
void MarkLost(const std::string& reason);

/// Seconds since `t0`.
inline double Since(Clock::time_point t0)
{
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// Deletes every pooled free buffer, the staging ring and the resident cache (context thread,
/// at shutdown or on request).
void ReleaseAll();

/// Drops free buffers until the pool holds at most `cap` bytes (context thread).
void TrimFree(std::size_t cap);

/// Collects the results of pending timer queries into the counters (context thread).
void CollectQueries();

} // namespace detail
} // namespace gpu
} // namespace terroir

#endif

// terroir::gpu::StorageBuffer, Fence and the device-side caches: the buffer pool (size
// classes, reused across jobs), the staging ring for transfers, and the resident cache.
#include "vtkTerroirGPU.h"

#include "Private/vtkTerroirGPUPrivate.h"

#include "vtkSMPTools.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>

namespace terroir
{
namespace gpu
{

namespace
{
/// Transfers smaller than this always use glBufferSubData / glGetBufferSubData.
constexpr std::size_t kStagingMinBytes = std::size_t(256) << 10;
/// The staging ring: 4 slots of 32 MiB (pinned host memory, made on first use).
constexpr std::size_t kStagingSlots = 4;
constexpr std::size_t kStagingSlotBytes = std::size_t(32) << 20;

/// Throws unless [offset, offset + bytes) lies inside a buffer of `size` bytes.
void CheckRange(const char* what, std::size_t bytes, std::size_t offset, std::size_t size)
{
  if (offset > size || bytes > size - offset)
  {
    std::ostringstream msg;
    msg << "terroir::gpu::StorageBuffer::" << what << ": range [" << offset << ", " << offset
        << " + " << bytes << ") lies outside the buffer of " << size << " bytes";
    throw Error(msg.str());
  }
}

/// Pool size class of `bytes`: 4 KiB, then 1, 1.25, 1.5 or 1.75 times a power of two (at most
/// a quarter wasted).
std::size_t SizeClass(std::size_t bytes)
{
  constexpr std::size_t kMin = 4096;
  if (bytes <= kMin)
  {
    return kMin;
  }
  std::size_t p = kMin;
  while (p * 2 <= bytes && p * 2 > p)
  {
    p *= 2;
  }
  for (std::size_t quarter = 0; quarter <= 4; ++quarter)
  {
    const std::size_t c = p + quarter * (p / 4);
    if (c >= bytes)
    {
      return c;
    }
  }
  return bytes; // beyond the classes (never reached for sizes GL accepts)
}

/// Byte filled into undefined buffers by the stress modes (0 = none).
int StressByte()
{
  const detail::Runtime& rt = detail::State();
  return rt.FillNaN ? 0xff : (rt.FillPattern ? 0xcd : 0);
}

/// Fills [offset, offset + bytes) of buffer `handle` with `value`.
void FillRange(unsigned handle, std::size_t offset, std::size_t bytes, unsigned char value)
{
  glBindBuffer(GL_COPY_WRITE_BUFFER, handle);
  glClearBufferSubData(GL_COPY_WRITE_BUFFER,
    GL_R8UI,
    static_cast<GLintptr>(offset),
    static_cast<GLsizeiptr>(bytes),
    GL_RED_INTEGER,
    GL_UNSIGNED_BYTE,
    &value);
  glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
}

/// Makes a GL buffer of `capacity` bytes (immutable storage when the context has it).
unsigned CreateBuffer(std::size_t capacity, GLenum& err)
{
  GLuint handle = 0;
  glGenBuffers(1, &handle);
  glBindBuffer(GL_COPY_WRITE_BUFFER, handle);
  if (detail::ContextLimits().ImmutableStorage)
  {
    // Mappable only for the Mapped method: elsewhere the flags could put a buffer in host
    // memory that kernels read slowly.
    const GLbitfield flags = GL_DYNAMIC_STORAGE_BIT |
      (detail::State().Method == Transfer::Mapped ? GL_MAP_READ_BIT | GL_MAP_WRITE_BIT : 0);
    glBufferStorage(GL_COPY_WRITE_BUFFER, static_cast<GLsizeiptr>(capacity), nullptr, flags);
  }
  else
  {
    glBufferData(GL_COPY_WRITE_BUFFER, static_cast<GLsizeiptr>(capacity), nullptr, GL_DYNAMIC_COPY);
  }
  err = glGetError();
  glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
  if (err != GL_NO_ERROR)
  {
    glDeleteBuffers(1, &handle);
    detail::ClearGLErrors();
    return 0;
  }
  return handle;
}

/// The staging ring, made on first use; false when the context cannot map persistently.
bool EnsureStaging()
{
  detail::Runtime& rt = detail::State();
  if (rt.StagingHandle)
  {
    return true;
  }
  if (!detail::ContextLimits().ImmutableStorage)
  {
    return false;
  }
  const std::size_t bytes = kStagingSlots * kStagingSlotBytes;
  const GLbitfield flags = GL_MAP_READ_BIT | GL_MAP_WRITE_BIT | GL_MAP_PERSISTENT_BIT |
    GL_MAP_COHERENT_BIT | GL_CLIENT_STORAGE_BIT;
  detail::ClearGLErrors();
  GLuint handle = 0;
  glGenBuffers(1, &handle);
  glBindBuffer(GL_COPY_WRITE_BUFFER, handle);
  glBufferStorage(GL_COPY_WRITE_BUFFER, static_cast<GLsizeiptr>(bytes), nullptr, flags);
  void* ptr = glGetError() == GL_NO_ERROR
    ? glMapBufferRange(GL_COPY_WRITE_BUFFER,
        0,
        static_cast<GLsizeiptr>(bytes),
        GL_MAP_READ_BIT | GL_MAP_WRITE_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT)
    : nullptr;
  glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
  if (!ptr)
  {
    glDeleteBuffers(1, &handle);
    detail::ClearGLErrors();
    return false;
  }
  rt.StagingHandle = handle;
  rt.StagingPtr = static_cast<unsigned char*>(ptr);
  rt.SlotBytes = kStagingSlotBytes;
  rt.SlotFences.assign(kStagingSlots, nullptr);
  rt.NextSlot = 0;
  return true;
}

/// Waits for and deletes the fence of staging slot `slot` (the GPU is done with its bytes).
void FreeSlot(std::size_t slot, const char* what)
{
  detail::Runtime& rt = detail::State();
  if (rt.SlotFences[slot])
  {
    detail::WaitSync(rt.SlotFences[slot], what);
    glDeleteSync(static_cast<GLsync>(rt.SlotFences[slot]));
    rt.SlotFences[slot] = nullptr;
  }
}

/// memcpy on all cores (vtkSMPTools), in 1 MiB pieces.
void ParallelCopy(unsigned char* to, const unsigned char* from, std::size_t bytes)
{
  constexpr std::size_t kPiece = std::size_t(1) << 20;
  const vtkIdType pieces = static_cast<vtkIdType>((bytes + kPiece - 1) / kPiece);
  vtkSMPTools::For(0,
    pieces,
    1,
    [&](vtkIdType p0, vtkIdType p1)
    {
      for (vtkIdType p = p0; p < p1; ++p)
      {
        const std::size_t at = static_cast<std::size_t>(p) * kPiece;
        std::memcpy(to + at, from + at, std::min(kPiece, bytes - at));
      }
    });
}

/// Maps [offset, offset + bytes) of `handle` for `access` after the GPU is done with it.
unsigned char* MapRange(unsigned handle, std::size_t offset, std::size_t bytes, GLbitfield access)
{
  detail::WaitAll(access & GL_MAP_READ_BIT ? "download" : "upload");
  glBindBuffer(GL_COPY_WRITE_BUFFER, handle);
  void* p = glMapBufferRange(
    GL_COPY_WRITE_BUFFER, static_cast<GLintptr>(offset), static_cast<GLsizeiptr>(bytes), access);
  if (!p)
  {
    const GLenum err = glGetError();
    glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
    throw Error(std::string("terroir::gpu::StorageBuffer: glMapBufferRange failed: ") +
      detail::GLErrorName(err));
  }
  return static_cast<unsigned char*>(p);
}

void Unmap()
{
  glUnmapBuffer(GL_COPY_WRITE_BUFFER);
  glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
}

bool UseMapped(std::size_t bytes)
{
  return detail::State().Method == Transfer::Mapped && bytes >= kStagingMinBytes &&
    detail::ContextLimits().ImmutableStorage;
}

bool UseStaging(std::size_t bytes)
{
  return detail::State().Method == Transfer::Staging && bytes >= kStagingMinBytes &&
    EnsureStaging();
}

/// Host to buffer, through the staging ring or glBufferSubData.
void UploadBytes(unsigned handle, const void* src, std::size_t bytes, std::size_t offset)
{
  detail::Runtime& rt = detail::State();
  const auto* from = static_cast<const unsigned char*>(src);
  if (UseMapped(bytes))
  {
    unsigned char* to = MapRange(handle, offset, bytes, GL_MAP_WRITE_BIT);
    ParallelCopy(to, from, bytes);
    Unmap();
    return;
  }
  if (!UseStaging(bytes))
  {
    glBindBuffer(GL_COPY_WRITE_BUFFER, handle);
    glBufferSubData(
      GL_COPY_WRITE_BUFFER, static_cast<GLintptr>(offset), static_cast<GLsizeiptr>(bytes), src);
    glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
    return;
  }
  glBindBuffer(GL_COPY_READ_BUFFER, rt.StagingHandle);
  glBindBuffer(GL_COPY_WRITE_BUFFER, handle);
  for (std::size_t done = 0; done < bytes;)
  {
    const std::size_t chunk = std::min(rt.SlotBytes, bytes - done);
    const std::size_t slot = rt.NextSlot;
    rt.NextSlot = (rt.NextSlot + 1) % rt.SlotFences.size();
    FreeSlot(slot, "upload");
    ParallelCopy(rt.StagingPtr + slot * rt.SlotBytes, from + done, chunk);
    glCopyBufferSubData(GL_COPY_READ_BUFFER,
      GL_COPY_WRITE_BUFFER,
      static_cast<GLintptr>(slot * rt.SlotBytes),
      static_cast<GLintptr>(offset + done),
      static_cast<GLsizeiptr>(chunk));
    rt.SlotFences[slot] = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    done += chunk;
  }
  glBindBuffer(GL_COPY_READ_BUFFER, 0);
  glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
}

/// Buffer to host, after the GPU work writing it is done (waited for within the budget).
void DownloadBytes(unsigned handle, void* dst, std::size_t bytes, std::size_t offset)
{
  detail::Runtime& rt = detail::State();
  auto* to = static_cast<unsigned char*>(dst);
  if (UseMapped(bytes))
  {
    const unsigned char* from = MapRange(handle, offset, bytes, GL_MAP_READ_BIT);
    const auto t0 = detail::Clock::now();
    ParallelCopy(to, from, bytes);
    const double s = detail::Since(t0);
    Unmap();
    detail::Count([s](Stats& c) { c.DownloadSeconds += s; });
    return;
  }
  if (!UseStaging(bytes))
  {
    detail::WaitAll("download");
    const auto t0 = detail::Clock::now();
    glBindBuffer(GL_COPY_READ_BUFFER, handle);
    glGetBufferSubData(
      GL_COPY_READ_BUFFER, static_cast<GLintptr>(offset), static_cast<GLsizeiptr>(bytes), dst);
    glBindBuffer(GL_COPY_READ_BUFFER, 0);
    const double s = detail::Since(t0);
    detail::Count([s](Stats& c) { c.DownloadSeconds += s; });
    return;
  }
  const std::size_t slots = rt.SlotFences.size();
  const std::size_t pieces = (bytes + rt.SlotBytes - 1) / rt.SlotBytes;
  double seconds = 0.0;
  std::size_t issued = 0;
  for (std::size_t consumed = 0; consumed < pieces; ++consumed)
  {
    // Keep every slot busy: copies of the next pieces run while this one is copied out.
    while (issued < pieces && issued - consumed < slots)
    {
      const std::size_t slot = issued % slots;
      FreeSlot(slot, "download");
      const std::size_t chunk = std::min(rt.SlotBytes, bytes - issued * rt.SlotBytes);
      glBindBuffer(GL_COPY_READ_BUFFER, handle);
      glBindBuffer(GL_COPY_WRITE_BUFFER, rt.StagingHandle);
      glCopyBufferSubData(GL_COPY_READ_BUFFER,
        GL_COPY_WRITE_BUFFER,
        static_cast<GLintptr>(offset + issued * rt.SlotBytes),
        static_cast<GLintptr>(slot * rt.SlotBytes),
        static_cast<GLsizeiptr>(chunk));
      rt.SlotFences[slot] = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
      ++issued;
    }
    const std::size_t slot = consumed % slots;
    FreeSlot(slot, "download");
    const auto t0 = detail::Clock::now();
    const std::size_t chunk = std::min(rt.SlotBytes, bytes - consumed * rt.SlotBytes);
    ParallelCopy(to + consumed * rt.SlotBytes, rt.StagingPtr + slot * rt.SlotBytes, chunk);
    seconds += detail::Since(t0);
  }
  glBindBuffer(GL_COPY_READ_BUFFER, 0);
  glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
  rt.NextSlot = 0;
  detail::Count([seconds](Stats& c) { c.DownloadSeconds += seconds; });
}
} // namespace

//------------------------------------------------------------------------------
StorageBuffer::StorageBuffer(std::size_t bytes, const void* data)
{
  this->Acquire(bytes, data, Contents::Zero);
}

StorageBuffer::StorageBuffer(std::size_t bytes, Contents contents)
{
  this->Acquire(bytes, nullptr, contents);
}

void StorageBuffer::Acquire(std::size_t bytes, const void* data, Contents contents)
{
  detail::RequireContextThread("terroir::gpu::StorageBuffer");
  if (bytes == 0)
  {
    throw Error("terroir::gpu::StorageBuffer: size must be > 0 bytes");
  }
  if (bytes > static_cast<std::size_t>(std::numeric_limits<GLsizeiptr>::max() / 2))
  {
    throw Error("terroir::gpu::StorageBuffer: " + std::to_string(bytes) + " bytes is too large");
  }
  detail::Runtime& rt = detail::State();
  const bool profiling = rt.Profiling;
  if (profiling)
  {
    detail::WaitAll("allocation");
  }
  const auto t0 = detail::Clock::now();
  const std::size_t capacity = SizeClass(bytes);
  detail::ClearGLErrors();
  unsigned handle = 0;
  auto it = rt.Legacy ? rt.Free.end() : rt.Free.find(capacity);
  if (rt.Legacy)
  {
    GLenum err = GL_NO_ERROR;
    GLuint h = 0;
    glGenBuffers(1, &h);
    glBindBuffer(GL_COPY_WRITE_BUFFER, h);
    glBufferData(GL_COPY_WRITE_BUFFER, static_cast<GLsizeiptr>(capacity), nullptr, GL_DYNAMIC_COPY);
    err = glGetError();
    glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
    if (err != GL_NO_ERROR)
    {
      glDeleteBuffers(1, &h);
      throw Error("terroir::gpu::StorageBuffer: cannot allocate " + std::to_string(bytes) +
        " bytes: " + detail::GLErrorName(err));
    }
    handle = h;
    FillRange(handle, 0, capacity, 0); // then the data, as commit 60aa2d9 did
    detail::Count(
      [capacity](Stats& c)
      {
        ++c.BuffersCreated;
        c.BytesCreated += capacity;
      });
  }
  else if (it != rt.Free.end())
  {
    handle = it->second;
    rt.Free.erase(it);
    rt.FreeBytes -= capacity;
    detail::Count([](Stats& c) { ++c.BuffersReused; });
  }
  else
  {
    GLenum err = GL_NO_ERROR;
    handle = CreateBuffer(capacity, err);
    if (!handle && err == GL_OUT_OF_MEMORY && (rt.FreeBytes > 0 || rt.ResidentBytes > 0))
    {
      // Give the pool's and the cache's memory back, then try once more.
      detail::TrimFree(0);
      rt.ResidentList.clear();
      rt.ResidentBytes = 0;
      detail::TrimFree(0);
      handle = CreateBuffer(capacity, err);
    }
    if (!handle)
    {
      throw Error("terroir::gpu::StorageBuffer: cannot allocate " + std::to_string(bytes) +
        " bytes: " + detail::GLErrorName(err));
    }
    detail::Count(
      [capacity](Stats& c)
      {
        ++c.BuffersCreated;
        c.BytesCreated += capacity;
      });
  }
  this->Handle = handle;
  this->Bytes = bytes;
  this->CapacityBytes = capacity;
  if (data)
  {
    UploadBytes(handle, data, bytes, 0);
    detail::Count(
      [bytes](Stats& c)
      {
        ++c.Uploads;
        c.BytesUploaded += bytes;
      });
  }
  else if (contents == Contents::Zero)
  {
    FillRange(handle, 0, bytes, 0);
  }
  else if (const int b = StressByte())
  {
    FillRange(handle, 0, capacity, static_cast<unsigned char>(b));
  }
  const GLenum err = glGetError();
  if (err != GL_NO_ERROR)
  {
    detail::ClearGLErrors();
    this->Release();
    throw Error("terroir::gpu::StorageBuffer: filling " + std::to_string(bytes) +
      " bytes failed: " + detail::GLErrorName(err));
  }
  detail::RestoreHostFloatingPoint();
  if (profiling)
  {
    detail::WaitAll("allocation");
    const double s = detail::Since(t0);
    if (data)
    {
      detail::Count([s](Stats& c) { c.UploadSeconds += s; });
    }
    else
    {
      detail::Count([s](Stats& c) { c.AllocSeconds += s; });
    }
  }
}

void StorageBuffer::Release() noexcept
{
  // Only the context thread can touch GL objects; elsewhere (misuse, or objects outliving the
  // context at exit) the name is leaked.
  if (!this->Handle || !detail::OnContextThread())
  {
    this->Handle = 0;
    return;
  }
  detail::Runtime& rt = detail::State();
  if (rt.Legacy)
  {
    glDeleteBuffers(1, &this->Handle);
    this->Handle = 0;
    return;
  }
  rt.Free.emplace(this->CapacityBytes, this->Handle);
  rt.FreeBytes += this->CapacityBytes;
  this->Handle = 0;
  if (rt.FreeBytes > rt.PoolCapBytes)
  {
    detail::TrimFree(rt.PoolCapBytes);
  }
}

StorageBuffer::~StorageBuffer()
{
  this->Release();
}

StorageBuffer::StorageBuffer(StorageBuffer&& other) noexcept
  : Handle(other.Handle)
  , Bytes(other.Bytes)
  , CapacityBytes(other.CapacityBytes)
{
  other.Handle = 0;
  other.Bytes = 0;
  other.CapacityBytes = 0;
}

StorageBuffer& StorageBuffer::operator=(StorageBuffer&& other) noexcept
{
  if (this != &other)
  {
    this->Release();
    this->Handle = other.Handle;
    this->Bytes = other.Bytes;
    this->CapacityBytes = other.CapacityBytes;
    other.Handle = 0;
    other.Bytes = 0;
    other.CapacityBytes = 0;
  }
  return *this;
}

void StorageBuffer::Upload(const void* src, std::size_t bytes, std::size_t offset)
{
  detail::RequireContextThread("terroir::gpu::StorageBuffer::Upload");
  if (!this->Handle)
  {
    throw Error("terroir::gpu::StorageBuffer::Upload: empty (moved-from) buffer");
  }
  CheckRange("Upload", bytes, offset, this->Bytes);
  if (bytes == 0)
  {
    return;
  }
  if (!src)
  {
    throw Error("terroir::gpu::StorageBuffer::Upload: null source");
  }
  const bool profiling = detail::State().Profiling;
  if (profiling)
  {
    detail::WaitAll("upload");
  }
  const auto t0 = detail::Clock::now();
  detail::ClearGLErrors();
  UploadBytes(this->Handle, src, bytes, offset);
  detail::CheckGLError("terroir::gpu::StorageBuffer::Upload");
  detail::RestoreHostFloatingPoint();
  if (profiling)
  {
    detail::WaitAll("upload");
  }
  const double s = profiling ? detail::Since(t0) : 0.0;
  detail::Count(
    [bytes, s](Stats& c)
    {
      ++c.Uploads;
      c.BytesUploaded += bytes;
      c.UploadSeconds += s;
    });
}

void StorageBuffer::Download(void* dst, std::size_t bytes, std::size_t offset) const
{
  detail::RequireContextThread("terroir::gpu::StorageBuffer::Download");
  if (!this->Handle)
  {
    throw Error("terroir::gpu::StorageBuffer::Download: empty (moved-from) buffer");
  }
  CheckRange("Download", bytes, offset, this->Bytes);
  if (bytes == 0)
  {
    return;
  }
  if (!dst)
  {
    throw Error("terroir::gpu::StorageBuffer::Download: null destination");
  }
  detail::ClearGLErrors();
  DownloadBytes(this->Handle, dst, bytes, offset);
  detail::CheckGLError("terroir::gpu::StorageBuffer::Download");
  detail::RestoreHostFloatingPoint();
  detail::Count(
    [bytes](Stats& c)
    {
      ++c.Downloads;
      c.BytesDownloaded += bytes;
    });
}

void StorageBuffer::CopyFrom(const StorageBuffer& src,
  std::size_t bytes,
  std::size_t srcOffset,
  std::size_t dstOffset)
{
  detail::RequireContextThread("terroir::gpu::StorageBuffer::CopyFrom");
  if (!this->Handle || !src.Handle)
  {
    throw Error("terroir::gpu::StorageBuffer::CopyFrom: empty (moved-from) buffer");
  }
  CheckRange("CopyFrom", bytes, srcOffset, src.Bytes);
  CheckRange("CopyFrom", bytes, dstOffset, this->Bytes);
  if (bytes == 0)
  {
    return;
  }
  detail::ClearGLErrors();
  glBindBuffer(GL_COPY_READ_BUFFER, src.Handle);
  glBindBuffer(GL_COPY_WRITE_BUFFER, this->Handle);
  glCopyBufferSubData(GL_COPY_READ_BUFFER,
    GL_COPY_WRITE_BUFFER,
    static_cast<GLintptr>(srcOffset),
    static_cast<GLintptr>(dstOffset),
    static_cast<GLsizeiptr>(bytes));
  glBindBuffer(GL_COPY_READ_BUFFER, 0);
  glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
  detail::CheckGLError("terroir::gpu::StorageBuffer::CopyFrom");
}

void StorageBuffer::Clear()
{
  detail::RequireContextThread("terroir::gpu::StorageBuffer::Clear");
  if (!this->Handle)
  {
    throw Error("terroir::gpu::StorageBuffer::Clear: empty (moved-from) buffer");
  }
  detail::ClearGLErrors();
  FillRange(this->Handle, 0, this->Bytes, 0);
  detail::CheckGLError("terroir::gpu::StorageBuffer::Clear");
}

void StorageBuffer::Bind(unsigned binding) const
{
  detail::RequireContextThread("terroir::gpu::StorageBuffer::Bind");
  if (!this->Handle)
  {
    throw Error("terroir::gpu::StorageBuffer::Bind: empty (moved-from) buffer");
  }
  const int maxBindings = detail::ContextLimits().MaxShaderStorageBufferBindings;
  if (maxBindings > 0 && binding >= static_cast<unsigned>(maxBindings))
  {
    throw Error("terroir::gpu::StorageBuffer::Bind: binding " + std::to_string(binding) +
      " >= GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS (" + std::to_string(maxBindings) + ")");
  }
  glBindBufferRange(
    GL_SHADER_STORAGE_BUFFER, binding, this->Handle, 0, static_cast<GLsizeiptr>(this->Bytes));
}

//------------------------------------------------------------------------------
Fence::Fence()
{
  detail::RequireContextThread("terroir::gpu::Fence");
  this->Sync = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
  if (!this->Sync)
  {
    throw Error("terroir::gpu::Fence: glFenceSync failed");
  }
}

Fence::~Fence()
{
  if (this->Sync && detail::OnContextThread())
  {
    glDeleteSync(static_cast<GLsync>(this->Sync));
  }
}

Fence::Fence(Fence&& other) noexcept
  : Sync(other.Sync)
{
  other.Sync = nullptr;
}

Fence& Fence::operator=(Fence&& other) noexcept
{
  if (this != &other)
  {
    if (this->Sync && detail::OnContextThread())
    {
      glDeleteSync(static_cast<GLsync>(this->Sync));
    }
    this->Sync = other.Sync;
    other.Sync = nullptr;
  }
  return *this;
}

bool Fence::IsSignaled()
{
  detail::RequireContextThread("terroir::gpu::Fence::IsSignaled");
  if (!this->Sync)
  {
    return true;
  }
  const GLenum r = glClientWaitSync(static_cast<GLsync>(this->Sync), GL_SYNC_FLUSH_COMMANDS_BIT, 0);
  return r == GL_ALREADY_SIGNALED || r == GL_CONDITION_SATISFIED;
}

void Fence::Wait()
{
  detail::RequireContextThread("terroir::gpu::Fence::Wait");
  if (this->Sync)
  {
    detail::WaitSync(this->Sync, "fence");
  }
}

//------------------------------------------------------------------------------
namespace detail
{
void WaitSync(void* sync, const char* what)
{
  Runtime& rt = State();
  Count([](Stats& c) { ++c.Waits; });
  GLbitfield flags = GL_SYNC_FLUSH_COMMANDS_BIT;
  for (;;)
  {
    const auto now = Clock::now();
    if (now >= rt.Deadline)
    {
      std::ostringstream msg;
      msg << (rt.Stage.empty() ? std::string("GPU job") : rt.Stage)
          << ": the GPU did not finish within the stage's budget of " << rt.BudgetSeconds
          << " s (waiting for " << what
          << "); the compute context is given up, so GPU stages now run on the CPU under Auto "
             "(TERROIR_GPU_BUDGET_SCALE raises the budget of a slow GPU)";
      MarkLost(msg.str());
      throw Error(msg.str());
    }
    const auto left = std::chrono::duration_cast<std::chrono::nanoseconds>(rt.Deadline - now);
    const GLuint64 slice = static_cast<GLuint64>(
      std::min<long long>(left.count(), 100000000LL)); // at most 0.1 s per wait
    const GLenum r = glClientWaitSync(static_cast<GLsync>(sync), flags, slice);
    if (r == GL_ALREADY_SIGNALED || r == GL_CONDITION_SATISFIED)
    {
      RestoreHostFloatingPoint();
      return;
    }
    if (r == GL_WAIT_FAILED)
    {
      throw Error(std::string("glClientWaitSync failed while waiting for ") + what + ": " +
        GLErrorName(glGetError()));
    }
    flags = 0;
  }
}

void WaitAll(const char* what)
{
  GLsync sync = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
  if (!sync)
  {
    throw Error(std::string("glFenceSync failed before ") + what);
  }
  try
  {
    WaitSync(sync, what);
  }
  catch (...)
  {
    glDeleteSync(sync);
    throw;
  }
  glDeleteSync(sync);
}

void TrimFree(std::size_t cap)
{
  Runtime& rt = State();
  // The largest free buffers go first: they hold the most memory, and a pool is most useful
  // for the many small and medium buffers of repeated calls.
  while (rt.FreeBytes > cap && !rt.Free.empty())
  {
    auto last = std::prev(rt.Free.end());
    GLuint handle = last->second;
    glDeleteBuffers(1, &handle);
    rt.FreeBytes -= last->first;
    rt.Free.erase(last);
  }
}

void ReleaseAll()
{
  Runtime& rt = State();
  rt.ResidentList.clear(); // returns the buffers to the pool
  rt.ResidentBytes = 0;
  TrimFree(0);
  for (void*& f : rt.SlotFences)
  {
    if (f)
    {
      glDeleteSync(static_cast<GLsync>(f));
      f = nullptr;
    }
  }
  if (rt.StagingHandle)
  {
    glBindBuffer(GL_COPY_WRITE_BUFFER, rt.StagingHandle);
    glUnmapBuffer(GL_COPY_WRITE_BUFFER);
    glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
    GLuint h = rt.StagingHandle;
    glDeleteBuffers(1, &h);
    rt.StagingHandle = 0;
    rt.StagingPtr = nullptr;
  }
  if (!rt.PendingQueries.empty())
  {
    glDeleteQueries(static_cast<GLsizei>(rt.PendingQueries.size()), rt.PendingQueries.data());
    rt.PendingQueries.clear();
  }
}

void CollectQueries()
{
  Runtime& rt = State();
  if (rt.PendingQueries.empty())
  {
    return;
  }
  double seconds = 0.0;
  for (GLuint q : rt.PendingQueries)
  {
    GLuint64 ns = 0;
    glGetQueryObjectui64v(q, GL_QUERY_RESULT, &ns);
    seconds += static_cast<double>(ns) * 1e-9;
  }
  glDeleteQueries(static_cast<GLsizei>(rt.PendingQueries.size()), rt.PendingQueries.data());
  rt.PendingQueries.clear();
  Count([seconds](Stats& c) { c.KernelSeconds += seconds; });
}
} // namespace detail

namespace
{
// Forgets the resident array of `key` (any version), so that the pool can reuse its buffer.
void DropResident(detail::Runtime& rt, const void* key)
{
  for (auto it = rt.ResidentList.begin(); it != rt.ResidentList.end(); ++it)
  {
    if (it->Key == key)
    {
      rt.ResidentBytes -= it->Buffer->Capacity();
      rt.ResidentList.erase(it);
      break;
    }
  }
}
} // namespace

//------------------------------------------------------------------------------
std::shared_ptr<StorageBuffer> Context::FindResident(const void* key,
  unsigned long long stamp,
  std::size_t bytes)
{
  detail::RequireContextThread("terroir::gpu::Context::FindResident");
  detail::Runtime& rt = detail::State();
  for (auto it = rt.ResidentList.begin(); it != rt.ResidentList.end(); ++it)
  {
    if (it->Key == key && it->Stamp == stamp && it->Buffer->Size() == bytes)
    {
      rt.ResidentList.splice(rt.ResidentList.end(), rt.ResidentList, it); // most recent
      detail::Count(
        [bytes](Stats& c)
        {
          ++c.ResidentHits;
          c.ResidentBytesReused += bytes;
        });
      return rt.ResidentList.back().Buffer;
    }
  }
  return nullptr;
}

std::shared_ptr<StorageBuffer> Context::Resident(const void* key,
  unsigned long long stamp,
  std::size_t bytes,
  const void* data)
{
  if (auto hit = this->FindResident(key, stamp, bytes))
  {
    return hit;
  }
  if (!data)
  {
    throw Error("terroir::gpu::Context::Resident: no data to upload");
  }
  // An older version of the same array goes first, so that the pool can reuse its buffer.
  DropResident(detail::State(), key);
  auto buffer = std::make_shared<StorageBuffer>(bytes, data);
  this->KeepResident(key, stamp, buffer);
  return buffer;
}

void Context::KeepResident(const void* key,
  unsigned long long stamp,
  std::shared_ptr<StorageBuffer> buffer)
{
  detail::RequireContextThread("terroir::gpu::Context::KeepResident");
  if (!buffer || !buffer->Id())
  {
    throw Error("terroir::gpu::Context::KeepResident: empty buffer");
  }
  detail::Runtime& rt = detail::State();
  DropResident(rt, key);
  rt.ResidentBytes += buffer->Capacity();
  rt.ResidentList.push_back({ key, stamp, std::move(buffer) });
  // Least recently used first out (the newest entry always stays).
  while (rt.ResidentBytes > rt.ResidentCapBytes && rt.ResidentList.size() > 1)
  {
    rt.ResidentBytes -= rt.ResidentList.front().Buffer->Capacity();
    rt.ResidentList.pop_front();
  }
}

} // namespace gpu
} // namespace terroir

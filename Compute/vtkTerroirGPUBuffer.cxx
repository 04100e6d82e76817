// terroir::gpu::StorageBuffer: RAII shader storage buffers.
#include "vtkTerroirGPU.h"

#include "Private/vtkTerroirGPUPrivate.h"

#include <epoxy/gl.h>

#include <cstdint>
#include <limits>
#include <sstream>

namespace terroir
{
namespace gpu
{

namespace
{
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
} // namespace

StorageBuffer::StorageBuffer(std::size_t bytes, const void* data)
{
  detail::RequireContextThread("terroir::gpu::StorageBuffer");
  if (bytes == 0)
  {
    throw Error("terroir::gpu::StorageBuffer: size must be > 0 bytes");
  }
  if (bytes > static_cast<std::size_t>(std::numeric_limits<GLsizeiptr>::max()))
  {
    throw Error("terroir::gpu::StorageBuffer: " + std::to_string(bytes) + " bytes is too large");
  }
  detail::ClearGLErrors();
  GLuint handle = 0;
  glGenBuffers(1, &handle);
  glBindBuffer(GL_COPY_WRITE_BUFFER, handle);
  glBufferData(GL_COPY_WRITE_BUFFER, static_cast<GLsizeiptr>(bytes), data, GL_DYNAMIC_COPY);
  const GLenum err = glGetError();
  glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
  if (err != GL_NO_ERROR)
  {
    glDeleteBuffers(1, &handle);
    detail::ClearGLErrors();
    throw Error("terroir::gpu::StorageBuffer: cannot allocate " + std::to_string(bytes) +
      " bytes: " + detail::GLErrorName(err));
  }
  this->Handle = handle;
  this->Bytes = bytes;
  if (!data)
  {
    this->Clear();
  }
}

StorageBuffer::~StorageBuffer()
{
  // Only the context thread can delete GL objects; elsewhere (misuse) the name is leaked.
  if (this->Handle && detail::OnContextThread())
  {
    glDeleteBuffers(1, &this->Handle);
  }
}

StorageBuffer::StorageBuffer(StorageBuffer&& other) noexcept
  : Handle(other.Handle)
  , Bytes(other.Bytes)
{
  other.Handle = 0;
  other.Bytes = 0;
}

StorageBuffer& StorageBuffer::operator=(StorageBuffer&& other) noexcept
{
  if (this != &other)
  {
    if (this->Handle && detail::OnContextThread())
    {
      glDeleteBuffers(1, &this->Handle);
    }
    this->Handle = other.Handle;
    this->Bytes = other.Bytes;
    other.Handle = 0;
    other.Bytes = 0;
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
  detail::ClearGLErrors();
  glBindBuffer(GL_COPY_WRITE_BUFFER, this->Handle);
  glBufferSubData(
    GL_COPY_WRITE_BUFFER, static_cast<GLintptr>(offset), static_cast<GLsizeiptr>(bytes), src);
  glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
  detail::CheckGLError("terroir::gpu::StorageBuffer::Upload");
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
  glBindBuffer(GL_COPY_READ_BUFFER, this->Handle);
  glGetBufferSubData(
    GL_COPY_READ_BUFFER, static_cast<GLintptr>(offset), static_cast<GLsizeiptr>(bytes), dst);
  glBindBuffer(GL_COPY_READ_BUFFER, 0);
  detail::CheckGLError("terroir::gpu::StorageBuffer::Download");
}

void StorageBuffer::Clear()
{
  detail::RequireContextThread("terroir::gpu::StorageBuffer::Clear");
  if (!this->Handle)
  {
    throw Error("terroir::gpu::StorageBuffer::Clear: empty (moved-from) buffer");
  }
  detail::ClearGLErrors();
  glBindBuffer(GL_COPY_WRITE_BUFFER, this->Handle);
  glClearBufferData(GL_COPY_WRITE_BUFFER, GL_R8UI, GL_RED_INTEGER, GL_UNSIGNED_BYTE, nullptr);
  glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
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
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, this->Handle);
}

} // namespace gpu
} // namespace terroir

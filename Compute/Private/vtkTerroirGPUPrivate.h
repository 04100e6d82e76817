/**
 * @file vtkTerroirGPUPrivate.h
 * @brief Internal helpers shared by the Terroir::Compute sources (not installed, no GL types).
 */
#ifndef vtkTerroirGPUPrivate_h
#define vtkTerroirGPUPrivate_h

#include "vtkTerroirGPU.h"

#include <string>

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

} // namespace detail
} // namespace gpu
} // namespace terroir

#endif

// Shaders/Common.glsl -- helpers shared by every Terroir compute kernel.
//
// terroir::gpu::Program prepends, in this order: `#version 430 core`, one `#define` per
// requested define (work-group sizes, feature flags), this file, then `#line 1` and the
// kernel. Testing/CheckShaders.sh does the same offline with glslangValidator.
// Keep this file small, declaration-only and free of buffers, uniforms or layouts: every
// kernel sees it.

#ifndef TERROIR_COMMON_GLSL
#define TERROIR_COMMON_GLSL

// pi in float32.
const float TERROIR_PI = 3.14159265358979323846;

// A quiet NaN (bit pattern 0x7fc00000): the value written for no-data cells.
#define TERROIR_NAN uintBitsToFloat(0x7fc00000u)

// Linear index of grid cell (i, j) in a row-major grid of `nx` columns; row j = 0 is the
// southern row, as in terroir::GridView.
uint terroirIndex(uvec2 ij, uint nx)
{
  return ij.y * nx + ij.x;
}

// True when (i, j) lies inside an nx x ny grid (use it to skip the invocations of the last,
// partial work group).
bool terroirInside(uvec2 ij, uvec2 n)
{
  return ij.x < n.x && ij.y < n.y;
}

// NaN test on the bit pattern: unlike isnan(), drivers cannot optimise it away.
bool terroirIsNaN(float x)
{
  uint b = floatBitsToUint(x);
  return (b & 0x7f800000u) == 0x7f800000u && (b & 0x007fffffu) != 0u;
}

// True for a finite value (neither NaN nor +-Inf).
bool terroirIsFinite(float x)
{
  return (floatBitsToUint(x) & 0x7f800000u) != 0x7f800000u;
}

#endif

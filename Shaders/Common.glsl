// Shaders/Common.glsl -- helpers shared by every Terroir compute kernel.
//
// terroir::gpu::Program prepends, in this order: `#version 430 core`, one `#define` per
// requested define (work-group sizes, feature flags), this file, then `#line 1` and the
// kernel. Testing/CheckShaders.sh does the same offline with glslangValidator.
// Keep this file small, declaration-only and free of buffers or layouts: every kernel sees it.
// Its only uniforms are the two that terroir::gpu::Program::Dispatch sets.

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

// Work-group and invocation ids. Program::Dispatch may issue a grid as several dispatches
// (TERROIR_GPU_STRESS=split or shuffle): kernels read their ids through these macros, never
// gl_WorkGroupID, gl_GlobalInvocationID or gl_NumWorkGroups.
uniform uvec3 terroirGroupOffset; // first group of this dispatch in the whole grid
uniform uvec3 terroirGroupCount;  // groups of the whole grid
#define TERROIR_WORKGROUP_ID (gl_WorkGroupID + terroirGroupOffset)
#define TERROIR_GLOBAL_ID (TERROIR_WORKGROUP_ID * gl_WorkGroupSize + gl_LocalInvocationID)
#define TERROIR_NUM_WORKGROUPS terroirGroupCount

// Exact products (Dekker 1971, with Veltkamp's splitting): hi + lo == x * y exactly, using
// only correctly rounded + - * (which GLSL guarantees) and `precise` (no fusion, no
// reassociation). GLSL's fma() is no substitute: it may round twice (Mesa 22's llvmpipe does).
dvec2 terroirTwoProduct(double x, double y)
{
  precise double cx = 134217729.0LF * x; // 2^27 + 1
  precise double xh = cx - (cx - x);
  precise double xl = x - xh;
  precise double cy = 134217729.0LF * y;
  precise double yh = cy - (cy - y);
  precise double yl = y - yh;
  precise double p = x * y;
  precise double e = ((xh * yh - p) + xh * yl + xl * yh) + xl * yl;
  return dvec2(p, e);
}

// a - q * b, exact when q is within a few units in the last place of a / b (Sterbenz).
double terroirResidual(double a, double b, double q)
{
  dvec2 p = terroirTwoProduct(q, b);
  precise double d = a - p.x;
  precise double r = d - p.y;
  return r;
}

// Correctly rounded division (IEEE round to nearest, as the CPU's a / b). GLSL lets `a / b` be
// off by 2.5 ULP in float (NVIDIA computes a * rcp(b)) and leaves double division's accuracy to
// the driver, so a kernel whose decisions or bits must match the CPU divides with these. They
// refine an approximate quotient `q` (2^-20 relative) with
// Newton steps on exact residuals (terroirResidual), then take the nearer of the two
// representable values around a / b (a quotient never lies exactly halfway between two).
// For moderate magnitudes (|a|, |b| and |a / b| in [1e-290, 1e290], where the exact products
// neither overflow nor go subnormal: every float quotient); elsewhere, and for zero, infinite
// or NaN operands, the result is a / b.
double terroirDivRefine(double a, double b, double q)
{
  double m = min(min(abs(a), abs(b)), abs(q));
  double x = max(max(abs(a), abs(b)), abs(q));
  if (!(m >= 1.0e-290LF) || !(x <= 1.0e290LF))
  {
    return a / b;
  }
  precise double y = 1.0LF / b;
  precise double q1 = q + terroirResidual(a, b, q) * y;
  precise double q2 = q1 + terroirResidual(a, b, q1) * y;
  double r2 = terroirResidual(a, b, q2);
  bool up = (r2 > 0.0LF) == (b > 0.0LF);
  uvec2 w = unpackDouble2x32(q2);
  // Next representable value away from zero (+1) or toward zero (-1) on the 64-bit pattern.
  bool away = (q2 > 0.0LF) == up;
  uint lo = away ? w.x + 1u : w.x - 1u;
  uint hi = away ? (lo == 0u ? w.y + 1u : w.y) : (w.x == 0u ? w.y - 1u : w.y);
  double n = packDouble2x32(uvec2(lo, hi));
  double rn = terroirResidual(a, b, n);
  return abs(rn) < abs(r2) ? n : q2;
}

double terroirDiv(double a, double b)
{
  return terroirDivRefine(a, b, a / b);
}

// Float quotients through the double one: a correctly rounded double quotient of two floats,
// rounded to float, is the correctly rounded float quotient (53 >= 2 * 24 + 2: double
// rounding is innocuous for division; Figueroa 1995). Measured on an H200: a float version of
// the refinement gave other bits in 1 % of the cases, the double one none.
float terroirDiv(float a, float b)
{
  return float(terroirDiv(double(a), double(b)));
}

float terroirDivRefine(float a, float b, float q)
{
  return float(terroirDivRefine(double(a), double(b), double(q)));
}

#endif

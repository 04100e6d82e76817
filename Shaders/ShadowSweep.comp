// ShadowSweep.comp: horizon tangents of the samples of one sweep line per invocation, by the
// upper-convex-hull sweep; mirrors terroir::terrain::SweepLine
// (Filters/Terrain/Core/ShadowHorizon.cxx) step for step in float. Its divisions are the
// driver's (GLSL allows 2.5 ULP): the tangents agree with the CPU's within rounding (1e-4
// degrees in the tests); correctly rounded ones (terroirDiv) made this kernel 4x slower on an
// H200 for no visible gain.
//
// Bindings (std430):
//   0  readonly  float elevation[nx*ny]     row j = 0 is the southern row
//   1  readonly  uint  validMask[(n+3)/4]   byte k of word w = validity of cell 4w+k (uHasMask)
//   2  readonly  int   table[2*nMajor]      F_u = floor(step*slope*u), then the bits of the
//                                           float f_u = step*slope*u - F_u (SweepPlan)
//   3  coherent  float hullS[lines*nMajor]  scratch: hull distances, nMajor per line
//   4  coherent  float hullW[lines*nMajor]  scratch: hull heights minus the curvature drop
//   5  writeonly float lines[lines*nMajor]  tangent of line m's sample at major index u
//                                           (m*nMajor + u); NaN where there is no sample
// Uniforms: int uNx, uNy, uAlongX (major axis: 1 = columns), uStep (+1/-1 toward the sun),
// uFirstLine, uLineCount, uHasMask; float uLength (metres per step), uCurvature (1/(2R) or 0).
// Work group LOCAL_X (define, 64); dispatch ceil(lines/64).

#ifndef LOCAL_X
#define LOCAL_X 64
#endif

layout(local_size_x = LOCAL_X, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer ElevationBuffer { float elevation[]; };
layout(std430, binding = 1) readonly buffer MaskBuffer { uint validMask[]; };
layout(std430, binding = 2) readonly buffer TableBuffer { int table[]; };
layout(std430, binding = 3) buffer HullSBuffer { float hullS[]; };
layout(std430, binding = 4) buffer HullWBuffer { float hullW[]; };
layout(std430, binding = 5) writeonly buffer LinesBuffer { float linesOut[]; };

uniform int uNx;
uniform int uNy;
uniform int uAlongX;
uniform int uStep;
uniform int uFirstLine;
uniform int uLineCount;
uniform int uHasMask;
uniform float uLength;
uniform float uCurvature;

bool cellValid(uint k)
{
  return uHasMask == 0 || ((validMask[k >> 2u] >> (8u * (k & 3u))) & 0xffu) != 0u;
}

uint cellIndex(int u, int w)
{
  return uAlongX != 0 ? uint(w * uNx + u) : uint(u * uNx + w);
}

// MarchGrid::Sample: the terrain at major index u, minor position w0 + f.
bool sampleAt(int u, int w0, float f, int nMinor, out float z)
{
  z = 0.0;
  if (w0 < 0 || w0 > nMinor - 1 || (f > 0.0 && w0 + 1 > nMinor - 1))
  {
    return false;
  }
  uint k0 = cellIndex(u, w0);
  float z0 = elevation[k0];
  if (!cellValid(k0) || terroirIsNaN(z0))
  {
    return false;
  }
  if (f == 0.0)
  {
    z = z0;
    return true;
  }
  uint k1 = cellIndex(u, w0 + 1);
  float z1 = elevation[k1];
  if (!cellValid(k1) || terroirIsNaN(z1))
  {
    return false;
  }
  precise float sum = (1.0 - f) * z0 + f * z1;
  z = sum;
  return true;
}

void main()
{
  int m = int(TERROIR_GLOBAL_ID.x);
  if (m >= uLineCount)
  {
    return;
  }
  int nMajor = uAlongX != 0 ? uNx : uNy;
  int nMinor = uAlongX != 0 ? uNy : uNx;
  int c = uFirstLine + m;
  uint base = uint(m) * uint(nMajor);
  float twoCurv = 2.0 * uCurvature;
  int top = 0;
  for (int q = 0; q < nMajor; ++q)
  {
    int u = uStep > 0 ? nMajor - 1 - q : q;
    float z;
    if (!sampleAt(u, c + table[u], intBitsToFloat(table[nMajor + u]), nMinor, z))
    {
      linesOut[base + uint(u)] = TERROIR_NAN;
      continue;
    }
    precise float s = float(uStep * u) * uLength;
    precise float wv = z - uCurvature * s * s;
    while (top >= 2)
    {
      precise float far = (hullW[base + uint(top - 2)] - wv) / (hullS[base + uint(top - 2)] - s);
      precise float near = (hullW[base + uint(top - 1)] - wv) / (hullS[base + uint(top - 1)] - s);
      if (far >= near)
      {
        --top;
      }
      else
      {
        break;
      }
    }
    if (top > 0)
    {
      precise float t =
        (hullW[base + uint(top - 1)] - wv) / (hullS[base + uint(top - 1)] - s) + twoCurv * s;
      linesOut[base + uint(u)] = t;
    }
    else
    {
      linesOut[base + uint(u)] = 0.0; // kNoHorizon: the horizontal plane
    }
    hullS[base + uint(top)] = s;
    hullW[base + uint(top)] = wv;
    ++top;
  }
}

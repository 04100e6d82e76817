// SolarIllumination.comp: hours of direct sun and direct-beam energy of a slice of cells, all
// sun steps in one invocation per cell; mirrors terroir::terrain::AccumulateIllumination and
// HorizonTangentRayMarch (Filters/Terrain/Core/SolarIllumination.cxx, ShadowHorizon.cxx). Its
// divisions are the driver's (GLSL allows 2.5 ULP): a lit/shadow answer may then differ where
// the sun sits on a cell's horizon within rounding (the tests allow 0.1 % of cells; none on
// llvmpipe or the H200).
// Nothing is lit while the sun is below the horizontal plane. Otherwise the lit/shadow answer
// of a step comes from ray marching (ILLUMINATION_METHOD 0), from the horizon map
// (1), or from the map with ray marching where the sun lies between the horizons of the two
// sectors around it (2).
//
// Bindings (std430):
//   0  readonly  float elevation[nx*ny]     row j = 0 is the southern row
//   1  readonly  uint  validMask[(n+3)/4]   byte k of word w = validity of cell 4w+k (uHasMask)
//   2  readonly  Step  steps[uStepCount]    see below
//   3  readonly  float normals[3*count]     unit surface normals of the slice (grid frame)
//   4            float hours[slots*count]   added to (k*slots + slot)
//   5            float energy[slots*count]  added to, Wh/m^2 (cos(incidence) for instants)
//   6  readonly  float planes[sectors*count] horizon tangents of the slice, sector-major
//                                           (sector s of cell k at s*count + k), methods 1, 2
// Step (64 bytes): vec4 (tan(elevation), sun x, y, z), vec4 (hours, energy, weight of sector1,
// march slope), ivec4 (sector0, sector1, slot, march flags: bit 0 = major axis is columns,
// bit 1 = step +1), vec4 (march length, 0, 0, 0).
// Uniforms: uint uCount, uFirst (grid index of the slice's first cell); int uNx, uNy,
// uHasMask, uStepCount, uSlots; float uCurvature (1/(2R) or 0), uZMax. Define
// ILLUMINATION_METHOD (0, 1 or 2, as above).
// Work group LOCAL_X (define, 64); dispatch ceil(count/64) per slice.

#ifndef LOCAL_X
#define LOCAL_X 64
#endif
// 0: ray marching, 1: the horizon map, 2: the map, and ray marching where the two sectors around
// the sun disagree. A define, not a uniform: llvmpipe would run every method for every cell.
#ifndef ILLUMINATION_METHOD
#define ILLUMINATION_METHOD 1
#endif

layout(local_size_x = LOCAL_X, local_size_y = 1, local_size_z = 1) in;

struct Step
{
  vec4 sun;
  vec4 gain;
  ivec4 lookup;
  vec4 march;
};

layout(std430, binding = 0) readonly buffer ElevationBuffer { float elevation[]; };
layout(std430, binding = 1) readonly buffer MaskBuffer { uint validMask[]; };
layout(std430, binding = 2) readonly buffer StepsBuffer { Step steps[]; };
layout(std430, binding = 3) readonly buffer NormalsBuffer { float normals[]; };
layout(std430, binding = 4) buffer HoursBuffer { float hours[]; };
layout(std430, binding = 5) buffer EnergyBuffer { float energy[]; };
layout(std430, binding = 6) readonly buffer PlanesBuffer { float planes[]; };

uniform uint uCount;
uniform uint uFirst;
uniform int uNx;
uniform int uNy;
uniform int uHasMask;
uniform int uStepCount;
uniform int uSlots;
uniform float uCurvature;
uniform float uZMax;

bool cellValid(uint k)
{
  return uHasMask == 0 || ((validMask[k >> 2u] >> (8u * (k & 3u))) & 0xffu) != 0u;
}

uint cellIndex(bool alongX, int u, int w)
{
  return alongX ? uint(w * uNx + u) : uint(u * uNx + w);
}

// MarchGrid::Sample (ShadowSweep.comp has the same function).
bool sampleAt(bool alongX, int u, int w0, float f, int nMinor, out float z)
{
  z = 0.0;
  if (w0 < 0 || w0 > nMinor - 1 || (f > 0.0 && w0 + 1 > nMinor - 1))
  {
    return false;
  }
  uint k0 = cellIndex(alongX, u, w0);
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
  uint k1 = cellIndex(alongX, u, w0 + 1);
  float z1 = elevation[k1];
  if (!cellValid(k1) || terroirIsNaN(z1))
  {
    return false;
  }
  precise float sum = (1.0 - f) * z0 + f * z1;
  z = sum;
  return true;
}

// HorizonTangentRayMarch with a finite stop tangent.
float horizonTangent(int i, int j, float z0, Step st)
{
  bool alongX = (st.lookup.w & 1) != 0;
  int stepDir = (st.lookup.w & 2) != 0 ? 1 : -1;
  int nMajor = alongX ? uNx : uNy;
  int nMinor = alongX ? uNy : uNx;
  int u = alongX ? i : j;
  int w = alongX ? j : i;
  float slope = st.gain.w;
  float len = st.march.x;
  float stopT = st.sun.x;
  float best = uintBitsToFloat(0xff800000u); // -inf
  bool found = false;
  for (int k = 1;; ++k)
  {
    int uk = u + k * stepDir;
    if (uk < 0 || uk > nMajor - 1)
    {
      break;
    }
    precise float s = float(k) * len;
    precise float bound = (uZMax - z0) / s;
    if (bound <= best || bound < stopT)
    {
      break;
    }
    precise float wk = float(w) + float(k) * slope;
    if (wk < 0.0 || wk > float(nMinor - 1))
    {
      break;
    }
    float fl = floor(wk);
    float z;
    if (!sampleAt(alongX, uk, int(fl), wk - fl, nMinor, z))
    {
      continue;
    }
    precise float t = (z - z0 - uCurvature * s * s) / s;
    found = true;
    if (t > best)
    {
      best = t;
      if (best >= stopT)
      {
        break;
      }
    }
  }
  return found ? best : 0.0;
}

void main()
{
  uint k = TERROIR_GLOBAL_ID.x;
  if (k >= uCount)
  {
    return;
  }
  uint g = uFirst + k;
  float z0 = elevation[g];
  if (!cellValid(g) || terroirIsNaN(z0))
  {
    return;
  }
  int i = int(g % uint(uNx));
  int j = int(g / uint(uNx));
  float nx = normals[3u * k];
  float ny = normals[3u * k + 1u];
  float nz = normals[3u * k + 2u];
  uint out0 = k * uint(uSlots);
  for (int si = 0; si < uStepCount; ++si)
  {
    Step st = steps[si];
    if (!(st.sun.x > 0.0))
    {
      continue; // the sun is below the horizontal plane: nothing is lit
    }
    bool lit;
    if (ILLUMINATION_METHOD == 0)
    {
      lit = horizonTangent(i, j, z0, st) < st.sun.x;
    }
    else
    {
      float a = planes[uint(st.lookup.x) * uCount + k];
      float b = planes[uint(st.lookup.y) * uCount + k];
      float w1 = st.gain.z;
      precise float w0 = 1.0 - w1;
      precise float h = w0 * a + w1 * b;
      lit = st.sun.x > h;
      if (ILLUMINATION_METHOD == 2 && st.sun.x > min(a, b) && st.sun.x < max(a, b))
      {
        lit = horizonTangent(i, j, z0, st) < st.sun.x;
      }
    }
    if (lit)
    {
      uint o = out0 + uint(st.lookup.z);
      precise float hv = hours[o] + st.gain.x;
      hours[o] = hv;
      precise float cosi = nx * st.sun.y + ny * st.sun.z + nz * st.sun.w;
      if (cosi > 0.0)
      {
        precise float ev = energy[o] + st.gain.y * cosi;
        energy[o] = ev;
      }
    }
  }
}

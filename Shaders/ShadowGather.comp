// ShadowGather.comp: a cell's horizon tangent in one direction from the two sweep lines around
// it (ShadowSweep.comp's output); mirrors terroir::terrain::GatherSweep
// (Filters/Terrain/Core/ShadowHorizon.cxx).
//
// Bindings (std430):
//   0  readonly  float elevation[nx*ny]     row j = 0 is the southern row
//   1  readonly  uint  validMask[(n+3)/4]   byte k of word w = validity of cell 4w+k (uHasMask)
//   2  readonly  int   table[2*nMajor]      F_u, then the bits of f_u (as ShadowSweep.comp)
//   5  readonly  float lines[lines*nMajor]  ShadowSweep.comp's output
//   6  writeonly float tangents[nx*ny]      the sector's plane; NaN for no-data cells
// (bindings 3 and 4 are ShadowSweep's scratch and unused here.)
// Uniforms: int uNx, uNy, uAlongX, uFirstLine, uHasMask.
// Work group LOCAL_X x LOCAL_Y (defines, 16 x 16); dispatch ceil(nx/16) x ceil(ny/16).

#ifndef LOCAL_X
#define LOCAL_X 16
#endif
#ifndef LOCAL_Y
#define LOCAL_Y 16
#endif

layout(local_size_x = LOCAL_X, local_size_y = LOCAL_Y, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer ElevationBuffer { float elevation[]; };
layout(std430, binding = 1) readonly buffer MaskBuffer { uint validMask[]; };
layout(std430, binding = 2) readonly buffer TableBuffer { int table[]; };
layout(std430, binding = 5) readonly buffer LinesBuffer { float linesIn[]; };
layout(std430, binding = 6) writeonly buffer PlaneBuffer { float tangents[]; };

uniform int uNx;
uniform int uNy;
uniform int uAlongX;
uniform int uFirstLine;
uniform int uHasMask;

void main()
{
  uvec2 ij = TERROIR_GLOBAL_ID.xy;
  if (!terroirInside(ij, uvec2(uNx, uNy)))
  {
    return;
  }
  uint k = terroirIndex(ij, uint(uNx));
  bool ok = !terroirIsNaN(elevation[k]);
  if (uHasMask != 0)
  {
    ok = ok && ((validMask[k >> 2u] >> (8u * (k & 3u))) & 0xffu) != 0u;
  }
  if (!ok)
  {
    tangents[k] = TERROIR_NAN;
    return;
  }
  int nMajor = uAlongX != 0 ? uNx : uNy;
  int u = uAlongX != 0 ? int(ij.x) : int(ij.y);
  int w = uAlongX != 0 ? int(ij.y) : int(ij.x);
  float f = intBitsToFloat(table[nMajor + u]);
  int mb = w - table[u] - uFirstLine;
  float tb = linesIn[uint(mb) * uint(nMajor) + uint(u)];
  if (f == 0.0)
  {
    tangents[k] = terroirIsNaN(tb) ? 0.0 : tb;
    return;
  }
  float ta = linesIn[uint(mb - 1) * uint(nMajor) + uint(u)];
  if (terroirIsNaN(ta))
  {
    tangents[k] = terroirIsNaN(tb) ? 0.0 : tb;
  }
  else if (terroirIsNaN(tb))
  {
    tangents[k] = ta;
  }
  else
  {
    precise float sum = f * ta + (1.0 - f) * tb;
    tangents[k] = sum;
  }
}

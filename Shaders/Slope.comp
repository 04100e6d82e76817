// Slope.comp: Horn (1981) slope, aspect and normals, one thread per cell; mirrors
// terroir::terrain::SlopeHorn1981Rows (Filters/Terrain/Core/SlopeHorn1981.cxx) in float,
// including gdaldem's -compute_edges border rules and no-data rule.
//
// Bindings (std430):
//   0  readonly  float elevation[nx*ny]      row j = 0 is the southern row
//   1  readonly  uint  validMask[(n+3)/4]    byte k of word w = validity of cell 4w+k (uHasMask)
//   2  readonly  vec4  rowCoef[ny]           (1/(8dx) north row, centre row, south row, 1/(8dy)),
//                                            times the z factor
//   3  writeonly float slope[nx*rows]        degrees, or percent when uPercent
//   4  writeonly float aspect[nx*rows]       degrees clockwise from true north (if uAspect)
//   5  writeonly float normals[3*nx*rows]    unit normal x, y, z (if uNormals)
// Outputs cover the band of rows [uRowStart, uRowEnd) (rows = uRowEnd - uRowStart), so that
// grids whose outputs exceed one storage buffer run band by band; inputs cover the whole grid.
// Uniforms: int uNx, uNy, uRowStart, uRowEnd, uHasMask, uPercent, uAspect, uNormals;
// float uConvergence (degrees).
// Work group LOCAL_X x LOCAL_Y (defines, 16 x 16 by default); dispatch ceil(nx/16) x
// ceil(rows/16).

#ifndef LOCAL_X
#define LOCAL_X 16
#endif
#ifndef LOCAL_Y
#define LOCAL_Y 16
#endif

layout(local_size_x = LOCAL_X, local_size_y = LOCAL_Y, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer ElevationBuffer { float elevation[]; };
layout(std430, binding = 1) readonly buffer MaskBuffer { uint validMask[]; };
layout(std430, binding = 2) readonly buffer RowCoefBuffer { vec4 rowCoef[]; };
layout(std430, binding = 3) writeonly buffer SlopeBuffer { float slopeOut[]; };
layout(std430, binding = 4) writeonly buffer AspectBuffer { float aspectOut[]; };
layout(std430, binding = 5) writeonly buffer NormalsBuffer { float normalsOut[]; };

uniform int uNx;
uniform int uNy;
uniform int uRowStart;
uniform int uRowEnd;
uniform int uHasMask;
uniform int uPercent;
uniform int uAspect;
uniform int uNormals;
uniform float uConvergence;

const float kDegrees = 57.29577951308232;

bool cellValid(int i, int j)
{
  if (uHasMask == 0)
  {
    return true;
  }
  uint k = uint(j * uNx + i);
  return ((validMask[k >> 2u] >> (8u * (k & 3u))) & 0xffu) != 0u;
}

float z(int i, int j)
{
  return elevation[j * uNx + i];
}

// A window sample: value in x, validity (1 or 0) in y.
vec2 sampleAt(int i, int j)
{
  return vec2(z(i, j), cellValid(i, j) ? 1.0 : 0.0);
}

// gdaldem's INTERPOL(a, b) = 2a - b, no data if either is.
vec2 extrapolate(vec2 a, vec2 b)
{
  return vec2(2.0 * a.x - b.x, min(a.y, b.y));
}

void main()
{
  int i = int(gl_GlobalInvocationID.x);
  int j = uRowStart + int(gl_GlobalInvocationID.y);
  if (i >= uNx || j >= uRowEnd || j >= uNy)
  {
    return;
  }
  int idx = (j - uRowStart) * uNx + i; // index into this band's outputs
  if (!cellValid(i, j))
  {
    float nan = uintBitsToFloat(0x7fc00000u);
    slopeOut[idx] = nan;
    if (uAspect != 0)
    {
      aspectOut[idx] = nan;
    }
    if (uNormals != 0)
    {
      normalsOut[3 * idx + 0] = nan;
      normalsOut[3 * idx + 1] = nan;
      normalsOut[3 * idx + 2] = nan;
    }
    return;
  }
  // w[0..2] north row (j + 1), w[3..5] centre row, w[6..8] south row (j - 1), west to east.
  vec2 s[9];
  if (j == 0 || j == uNy - 1)
  {
    int cols[3] = int[3](max(i - 1, 0), i, min(i + 1, uNx - 1));
    int inner = (j == 0) ? 1 : uNy - 2;
    for (int k = 0; k < 3; ++k)
    {
      int c = cols[k];
      vec2 centreRow = sampleAt(c, j);
      vec2 outside = extrapolate(centreRow, sampleAt(c, inner));
      s[k] = (j == uNy - 1) ? outside : sampleAt(c, j + 1);
      s[3 + k] = centreRow;
      s[6 + k] = (j == 0) ? outside : sampleAt(c, j - 1);
    }
  }
  else
  {
    for (int r = 0; r < 3; ++r)
    {
      int jj = j + 1 - r;
      s[3 * r + 1] = sampleAt(i, jj);
      s[3 * r + 0] = (i == 0) ? extrapolate(sampleAt(0, jj), sampleAt(1, jj)) : sampleAt(i - 1, jj);
      s[3 * r + 2] = (i == uNx - 1) ? extrapolate(sampleAt(uNx - 1, jj), sampleAt(uNx - 2, jj))
                                   : sampleAt(i + 1, jj);
    }
  }
  float centre = z(i, j);
  float w[9];
  for (int k = 0; k < 9; ++k)
  {
    w[k] = (s[k].y != 0.0) ? s[k].x : centre;
  }
  vec4 c = rowCoef[j];
  float gx = (w[2] - w[0]) * c.x + (w[5] - w[3]) * (2.0 * c.y) + (w[8] - w[6]) * c.z;
  float gy = ((w[0] - w[6]) + 2.0 * (w[1] - w[7]) + (w[2] - w[8])) * c.w;
  float g2 = gx * gx + gy * gy;
  float g = sqrt(g2);
  slopeOut[idx] = (uPercent != 0) ? 100.0 * g : atan(g) * kDegrees;
  if (uAspect != 0)
  {
    float a;
    if (g2 == 0.0)
    {
      a = uintBitsToFloat(0x7fc00000u);
    }
    else
    {
      a = atan(-gx, -gy) * kDegrees + uConvergence;
      if (a < 0.0)
      {
        a += 360.0;
      }
      if (a >= 360.0)
      {
        a -= 360.0;
      }
      if (a < 0.0 || a >= 360.0)
      {
        a = 0.0;
      }
    }
    aspectOut[idx] = a;
  }
  if (uNormals != 0)
  {
    float inv = 1.0 / sqrt(g2 + 1.0);
    normalsOut[3 * idx + 0] = -gx * inv;
    normalsOut[3 * idx + 1] = -gy * inv;
    normalsOut[3 * idx + 2] = inv;
  }
}

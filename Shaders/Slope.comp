// Slope.comp: Horn (1981) slope, aspect and normals, one invocation per cell; mirrors
// terroir::terrain::SlopeHorn1981Rows (Filters/Terrain/Core/SlopeHorn1981.cxx) in float,
// including gdaldem's -compute_edges border rules and no-data rule.
//
// Two kernels (one file): the default one does the interior cells (1 <= i < nx - 1,
// 1 <= j < ny - 1) of the band, whose window lies inside the grid; SLOPE_BORDER does the band's
// border cells (its first and last columns, and the grid's first and last rows when they are in
// the band), with the extrapolation rules. They are apart because llvmpipe runs every branch of
// a kernel, taken or not, for each group of 8 invocations: the border code inside the interior
// kernel made every cell 4x slower there.
//
// Bindings (std430):
//   0  readonly  float elevation[nx*ny]      row j = 0 is the southern row
//   1  readonly  uint  validMask[(n+3)/4]    byte k of word w = validity of cell 4w+k
//                                            (SLOPE_MASK; SLOPE_BORDER: uHasMask)
//   2  readonly  vec4  rowCoef[ny]           (1/(8dx) north row, centre row, south row, 1/(8dy)),
//                                            times the z factor
//   3  writeonly float slope[nx*rows]        degrees, or percent with SLOPE_PERCENT
//   4  writeonly float aspect[nx*rows]       degrees clockwise from true north (SLOPE_ASPECT)
//   5  writeonly float normals[3*nx*rows]    unit normal x, y, z (SLOPE_NORMALS)
// Outputs cover the band of rows [uRowStart, uRowEnd) (rows = uRowEnd - uRowStart), so that
// grids whose outputs exceed one storage buffer run band by band; inputs cover the whole grid.
// Uniforms: int uNx, uNy, uRowStart, uRowEnd, uHasMask (SLOPE_BORDER); float uConvergence
// (degrees).
// Defines: SLOPE_PERCENT, SLOPE_ASPECT, SLOPE_NORMALS (outputs), SLOPE_MASK (the interior kernel
// reads the mask), SLOPE_BORDER (the border kernel); LOCAL_X x LOCAL_Y (16 x 16 by default).
// Dispatch: interior ceil((nx-2)/16) x ceil(interior rows/16); border (LOCAL_X 64, LOCAL_Y 1)
// ceil(border cells/64), border cells = nx for each of rows 0 and ny-1 in the band, plus 2 for
// each other row of the band.

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
uniform float uConvergence;

const float kDegrees = 57.29577951308232;

bool validAt(int k)
{
  return ((validMask[uint(k) >> 2u] >> (8u * (uint(k) & 3u))) & 0xffu) != 0u;
}

// Slope, aspect and normal of the cell written at band index `idx` from Horn's gradient.
void emit(int idx, float gx, float gy)
{
  float g2 = gx * gx + gy * gy;
  float g = sqrt(g2);
#ifdef SLOPE_PERCENT
  slopeOut[idx] = 100.0 * g;
#else
  slopeOut[idx] = atan(g) * kDegrees;
#endif
#ifdef SLOPE_ASPECT
  float a;
  if (g2 == 0.0)
  {
    a = TERROIR_NAN;
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
#endif
#ifdef SLOPE_NORMALS
  float inv = 1.0 / sqrt(g2 + 1.0);
  normalsOut[3 * idx + 0] = -gx * inv;
  normalsOut[3 * idx + 1] = -gy * inv;
  normalsOut[3 * idx + 2] = inv;
#endif
}

// A no-data cell: NaN in every output.
void emitNoData(int idx)
{
  slopeOut[idx] = TERROIR_NAN;
#ifdef SLOPE_ASPECT
  aspectOut[idx] = TERROIR_NAN;
#endif
#ifdef SLOPE_NORMALS
  normalsOut[3 * idx + 0] = TERROIR_NAN;
  normalsOut[3 * idx + 1] = TERROIR_NAN;
  normalsOut[3 * idx + 2] = TERROIR_NAN;
#endif
}

// Horn's gradient of the window (north row w0..w2, centre w3, w5, south w6..w8, west to east).
vec2 horn(float w0, float w1, float w2, float w3, float w5, float w6, float w7, float w8, vec4 c)
{
  float gx = (w2 - w0) * c.x + (w5 - w3) * (2.0 * c.y) + (w8 - w6) * c.z;
  float gy = ((w0 - w6) + 2.0 * (w1 - w7) + (w2 - w8)) * c.w;
  return vec2(gx, gy);
}

#ifndef SLOPE_BORDER

void main()
{
  int i = 1 + int(TERROIR_GLOBAL_ID.x);
  int j = max(uRowStart, 1) + int(TERROIR_GLOBAL_ID.y);
  if (i >= uNx - 1 || j >= min(uRowEnd, uNy - 1))
  {
    return;
  }
  int idx = (j - uRowStart) * uNx + i; // index into this band's outputs
  int b = j * uNx + i;
  float w0 = elevation[b + uNx - 1];
  float w1 = elevation[b + uNx];
  float w2 = elevation[b + uNx + 1];
  float w3 = elevation[b - 1];
  float w5 = elevation[b + 1];
  float w6 = elevation[b - uNx - 1];
  float w7 = elevation[b - uNx];
  float w8 = elevation[b - uNx + 1];
#ifdef SLOPE_MASK
  if (!validAt(b))
  {
    emitNoData(idx);
    return;
  }
  // A no-data neighbour counts as the centre's height (gdaldem).
  float c = elevation[b];
  w0 = validAt(b + uNx - 1) ? w0 : c;
  w1 = validAt(b + uNx) ? w1 : c;
  w2 = validAt(b + uNx + 1) ? w2 : c;
  w3 = validAt(b - 1) ? w3 : c;
  w5 = validAt(b + 1) ? w5 : c;
  w6 = validAt(b - uNx - 1) ? w6 : c;
  w7 = validAt(b - uNx) ? w7 : c;
  w8 = validAt(b - uNx + 1) ? w8 : c;
#endif
  vec2 g = horn(w0, w1, w2, w3, w5, w6, w7, w8, rowCoef[j]);
  emit(idx, g.x, g.y);
}

#else

bool cellValid(int i, int j)
{
  return uHasMask == 0 || validAt(j * uNx + i);
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
  // Border cell number t of the band: row 0 (when in the band), row ny - 1 (when in the band),
  // then columns 0 and nx - 1 of the other rows, two by two.
  int t = int(TERROIR_GLOBAL_ID.x);
  int bottom = uRowStart == 0 ? uNx : 0;
  int top = (uRowEnd == uNy && uNy > 1) ? uNx : 0;
  int midStart = max(uRowStart, 1);
  int mid = max(0, min(uRowEnd, uNy - 1) - midStart);
  int i;
  int j;
  if (t < bottom)
  {
    i = t;
    j = 0;
  }
  else if (t < bottom + top)
  {
    i = t - bottom;
    j = uNy - 1;
  }
  else if (t < bottom + top + 2 * mid)
  {
    int m = t - bottom - top;
    i = (m & 1) == 0 ? 0 : uNx - 1;
    j = midStart + m / 2;
  }
  else
  {
    return;
  }
  int idx = (j - uRowStart) * uNx + i;
  if (!cellValid(i, j))
  {
    emitNoData(idx);
    return;
  }
  // s[0..2] north row (j + 1), s[3..5] centre row, s[6..8] south row (j - 1), west to east.
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
  vec2 g = horn(w[0], w[1], w[2], w[3], w[5], w[6], w[7], w[8], rowCoef[j]);
  emit(idx, g.x, g.y);
}

#endif

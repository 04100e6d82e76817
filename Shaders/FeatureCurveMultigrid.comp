// FeatureCurveMultigrid.comp: the multigrid V-cycle of Weiss (2015)'s diffusion solver (eq. 9),
// one invocation per grid point; mirrors the row kernels of terroir::terrain
// (Filters/Terrain/Core/FeatureCurves.cxx) operation for operation, in the same order, with
// `precise` (no fused multiply-add): DiffusionSmoothRows (FC_SMOOTH), DiffusionResidualRows
// (FC_RESIDUAL), DiffusionRestrictRows (FC_RESTRICT), DiffusionProlongRows (FC_PROLONG) and
// DiffusionChangeRows (FC_CHANGE). Stencils are float32, heights and residuals float64, as in
// the core. Edges mirror (index -1 is 1, index n is n - 2; 0 when n is 1).
//
// Bindings (std430):
//   0  readonly  float  coef[6*n]     [d | 1/d | cW | cE | cS | cN] of the level (smooth, residual)
//   1            double h[n]          the level's heights (smooth, residual, change: this level;
//                                     restrict: the coarse level's, set to 0; prolong: the fine)
//   2            double b[n]          right-hand side (smooth, residual; restrict: the coarse one)
//   3            double r[n]          residual (residual writes; restrict reads the fine one)
//   4  writeonly double groupMax[]    per work group, the largest |r| (residual) or |h - prev|
//                                     (change); group g = y * groupsX + x
//   5  readonly  double e[nc]         the coarse heights (prolong)
//   6            double prev[n]       the heights before the cycle (change: compared, replaced)
// Uniforms: int uNx, uNy (the level's size; restrict and prolong: the fine level's), uCx, uCy
// (the coarse level's size: restrict and prolong), uColour (smooth: 0 or 1, the cells with
// (i + j) % 2 == uColour).
// Dispatch: ceil(nx / 16) x ceil(ny / 16) groups of the level written (restrict: the coarse one).

#ifndef LOCAL_X
#define LOCAL_X 16
#endif
#ifndef LOCAL_Y
#define LOCAL_Y 16
#endif

layout(local_size_x = LOCAL_X, local_size_y = LOCAL_Y, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer CoefBuffer { float coef[]; };
layout(std430, binding = 1) buffer HeightBuffer { double h[]; };
layout(std430, binding = 2) buffer RhsBuffer { double b[]; };
layout(std430, binding = 3) buffer ResidualBuffer { double r[]; };
layout(std430, binding = 4) writeonly buffer GroupMaxBuffer { double groupMax[]; };
layout(std430, binding = 5) readonly buffer CoarseBuffer { double e[]; };
layout(std430, binding = 6) buffer PreviousBuffer { double prev[]; };

uniform int uNx;
uniform int uNy;
uniform int uCx;
uniform int uCy;
uniform int uColour;

int mirror(int i, int n)
{
  if (i < 0)
  {
    return n > 1 ? -i : 0;
  }
  if (i >= n)
  {
    return n > 1 ? 2 * n - 2 - i : 0;
  }
  return i;
}

#if defined(FC_RESIDUAL) || defined(FC_CHANGE)
shared double sMax[LOCAL_X * LOCAL_Y];

void storeGroupMax(double v)
{
  uint l = gl_LocalInvocationIndex;
  sMax[l] = v;
  barrier();
  for (uint s = uint(LOCAL_X * LOCAL_Y) / 2u; s > 0u; s >>= 1u)
  {
    if (l < s)
    {
      sMax[l] = max(sMax[l], sMax[l + s]);
    }
    barrier();
  }
  if (l == 0u)
  {
    uvec3 g = TERROIR_WORKGROUP_ID;
    groupMax[g.y * TERROIR_NUM_WORKGROUPS.x + g.x] = sMax[0];
  }
}
#endif

void main()
{
  ivec2 ij = ivec2(TERROIR_GLOBAL_ID.xy);
  int i = ij.x;
  int j = ij.y;
#if defined(FC_SMOOTH)
  if (i >= uNx || j >= uNy || ((i + j) & 1) != uColour)
  {
    return;
  }
  int n = uNx * uNy;
  int rc = j * uNx;
  int k = rc + i;
  precise double s = b[k];
  s = s + double(coef[2 * n + k]) * h[rc + mirror(i - 1, uNx)];
  s = s + double(coef[3 * n + k]) * h[rc + mirror(i + 1, uNx)];
  s = s + double(coef[4 * n + k]) * h[mirror(j - 1, uNy) * uNx + i];
  s = s + double(coef[5 * n + k]) * h[mirror(j + 1, uNy) * uNx + i];
  precise double v = s * double(coef[n + k]);
  h[k] = v;
#elif defined(FC_RESIDUAL)
  double a = 0.0LF;
  if (i < uNx && j < uNy)
  {
    int n = uNx * uNy;
    int rc = j * uNx;
    int k = rc + i;
    precise double t = double(coef[k]) * h[k];
    t = t - double(coef[2 * n + k]) * h[rc + mirror(i - 1, uNx)];
    t = t - double(coef[3 * n + k]) * h[rc + mirror(i + 1, uNx)];
    t = t - double(coef[4 * n + k]) * h[mirror(j - 1, uNy) * uNx + i];
    t = t - double(coef[5 * n + k]) * h[mirror(j + 1, uNy) * uNx + i];
    precise double v = b[k] - t;
    r[k] = v;
    a = abs(v);
  }
  storeGroupMax(a);
#elif defined(FC_RESTRICT)
  if (i >= uCx || j >= uCy)
  {
    return;
  }
  int js = mirror(2 * j - 1, uNy) * uNx;
  int jc = mirror(2 * j, uNy) * uNx;
  int jn = mirror(2 * j + 1, uNy) * uNx;
  int iw = mirror(2 * i - 1, uNx);
  int ic = mirror(2 * i, uNx);
  int ie = mirror(2 * i + 1, uNx);
  precise double s1 = r[jc + iw] + r[jc + ie];
  s1 = s1 + r[js + ic];
  s1 = s1 + r[jn + ic];
  precise double s2 = r[js + iw] + r[js + ie];
  s2 = s2 + r[jn + iw];
  s2 = s2 + r[jn + ie];
  precise double v = r[jc + ic] * 0.25LF;
  v = v + s1 * 0.125LF;
  v = v + s2 * 0.0625LF;
  int K = j * uCx + i;
  b[K] = v;
  h[K] = 0.0LF;
#elif defined(FC_PROLONG)
  if (i >= uNx || j >= uNy)
  {
    return;
  }
  int J0 = j / 2;
  int J1 = (j & 1) != 0 ? min(J0 + 1, uCy - 1) : J0;
  int I0 = i / 2;
  int I1 = (i & 1) != 0 ? min(I0 + 1, uCx - 1) : I0;
  int r0 = J0 * uCx;
  int r1 = J1 * uCx;
  precise double v;
  if ((i & 1) == 0 && (j & 1) == 0)
  {
    v = e[r0 + I0];
  }
  else if ((j & 1) == 0)
  {
    v = (e[r0 + I0] + e[r0 + I1]) * 0.5LF;
  }
  else if ((i & 1) == 0)
  {
    v = (e[r0 + I0] + e[r1 + I0]) * 0.5LF;
  }
  else
  {
    precise double a = e[r0 + I0] + e[r0 + I1];
    precise double c = e[r1 + I0] + e[r1 + I1];
    v = (a + c) * 0.25LF;
  }
  int k = j * uNx + i;
  precise double sum = h[k] + v;
  h[k] = sum;
#elif defined(FC_CHANGE)
  double a = 0.0LF;
  if (i < uNx && j < uNy)
  {
    int k = j * uNx + i;
    precise double d = h[k] - prev[k];
    a = abs(d);
    prev[k] = h[k];
  }
  storeGroupMax(a);
#endif
}

// SoilHumidity.comp: absorbed rain, its weighted average and standing water, one invocation
// per cell (vec4 stores of its 12 months); mirrors terroir::terrain::SoilHumidityLong2016 (Filters/Terrain/Core/SoilWater.cxx),
// the same float operations in the same order.
//   S_h(m)  = min(S_ir * uInverseIntensity[m], 1) * uQuantity[m]   (both 0 for a dry month;
//             a NaN rate or a masked cell is no data: NaN in every output)
//   S_wh(m) = S_h(m) * 0.5 + S_h(m-1) * (1/3) + S_h(m-2) * (1/6)   (months mod 12)
//   W(m)    = R_q(m) - S_h(m)
//
// Bindings (std430):
//   0  readonly  float rate[]                   S_ir, mm/h; cell uFirst + k of the grid at
//                                               uRateFirst + k (the whole grid with uRateFirst =
//                                               uFirst, or this slice with 0); NaN marks no data
//   1  readonly  uint  validMask[(n+3)/4]        byte k of word w = validity of cell 4w+k of
//                                                the whole grid (HUMIDITY_MASK)
//   2  writeonly vec4  humidity[3*count]         S_h, mm, 12 months per cell, January first
//   3  writeonly vec4  weighted[3*count]         S_wh, mm (HUMIDITY_WEIGHTED)
//   4  writeonly vec4  standing[3*count]         W, mm (HUMIDITY_STANDING)
// NaN in every output for no-data cells.
// Uniforms: uint uCount, uFirst, uRateFirst; float uQuantity[12] (mm, 0 for a dry month),
// uInverseIntensity[12] (h/mm, 1/R_i; 0 for a dry month).
// Defines: HUMIDITY_MASK, HUMIDITY_WEIGHTED, HUMIDITY_STANDING (compile-time: llvmpipe runs
// untaken branches); LOCAL_X (256 by default). Dispatch: gx x gy groups of LOCAL_X covering
// count invocations (cell k = id.y * gx * LOCAL_X + id.x).

#ifndef LOCAL_X
#define LOCAL_X 256
#endif

layout(local_size_x = LOCAL_X, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer RateBuffer { float rate[]; };
layout(std430, binding = 1) readonly buffer MaskBuffer { uint validMask[]; };
layout(std430, binding = 2) writeonly buffer HumidityBuffer { vec4 humidity[]; };
layout(std430, binding = 3) writeonly buffer WeightedBuffer { vec4 weighted[]; };
layout(std430, binding = 4) writeonly buffer StandingBuffer { vec4 standing[]; };

uniform uint uCount;
uniform uint uFirst;
uniform uint uRateFirst;
uniform float uQuantity[12];
uniform float uInverseIntensity[12];

void main()
{
  uint k = TERROIR_GLOBAL_ID.y * (TERROIR_NUM_WORKGROUPS.x * uint(LOCAL_X)) + TERROIR_GLOBAL_ID.x;
  if (k >= uCount)
  {
    return;
  }
  // No data is tested explicitly: GLSL does not promise IEEE NaN propagation through the
  // select below (llvmpipe turns it into a min that drops the NaN).
  float s = rate[uRateFirst + k];
  bool ok = !terroirIsNaN(s);
#ifdef HUMIDITY_MASK
  uint g = uFirst + k;
  ok = ok && (((validMask[g >> 2u] >> (8u * (g & 3u))) & 0xffu) != 0u);
#endif
  float sh[12];
  for (int m = 0; m < 12; ++m)
  {
    float ratio = s * uInverseIntensity[m];
    sh[m] = ok ? (ratio > 1.0 ? 1.0 : ratio) * uQuantity[m] : TERROIR_NAN;
  }
  for (int q = 0; q < 3; ++q)
  {
    humidity[3u * k + uint(q)] = vec4(sh[4 * q], sh[4 * q + 1], sh[4 * q + 2], sh[4 * q + 3]);
  }
#ifdef HUMIDITY_WEIGHTED
  float sw[12];
  for (int m = 0; m < 12; ++m)
  {
    float a = sh[m];
    float b = sh[(m + 11) % 12];
    float c = sh[(m + 10) % 12];
    sw[m] = a * 0.5 + b * (1.0 / 3.0) + c * (1.0 / 6.0);
  }
  for (int q = 0; q < 3; ++q)
  {
    weighted[3u * k + uint(q)] = vec4(sw[4 * q], sw[4 * q + 1], sw[4 * q + 2], sw[4 * q + 3]);
  }
#endif
#ifdef HUMIDITY_STANDING
  float w[12];
  for (int m = 0; m < 12; ++m)
  {
    w[m] = ok ? uQuantity[m] - sh[m] : TERROIR_NAN;
  }
  for (int q = 0; q < 3; ++q)
  {
    standing[3u * k + uint(q)] = vec4(w[4 * q], w[4 * q + 1], w[4 * q + 2], w[4 * q + 3]);
  }
#endif
}

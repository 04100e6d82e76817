// SoilHumidity.comp: absorbed rain, its weighted average and standing water, one thread per
// cell; mirrors terroir::terrain::SoilHumidityLong2016 (Filters/Terrain/Core/SoilWater.cxx),
// the same float operations in the same order.
//   S_h(m)  = min(S_ir * uInverseIntensity[m], 1) * uQuantity[m]   (both 0 for a dry month;
//             a NaN rate or a masked cell is no data: NaN in every output)
//   S_wh(m) = S_h(m) * 0.5 + S_h(m-1) * (1/3) + S_h(m-2) * (1/6)   (months mod 12)
//   W(m)    = R_q(m) - S_h(m)
//
// Bindings (std430):
//   0  readonly  float rate[count]              S_ir, mm/h, cells uFirst .. uFirst + count - 1;
//                                               NaN marks no data
//   1  readonly  uint  validMask[(n+3)/4]        byte k of word w = validity of cell 4w+k of
//                                                the whole grid (read when uHasMask)
//   2  writeonly float humidity[12*count]        S_h, mm, 12 months per cell, January first
//   3  writeonly float weighted[12*count]        S_wh, mm (written when uWeighted)
//   4  writeonly float standing[12*count]        W, mm (written when uStanding)
// NaN in every output for no-data cells.
// Uniforms: uint uCount, uint uFirst, int uHasMask, int uWeighted, int uStanding,
// float uQuantity[12] (mm, 0 for a dry month), float uInverseIntensity[12] (h/mm, 1/R_i; 0 for a
// dry month).
// Work group LOCAL_X (define, 256 by default); dispatch ceil(count/LOCAL_X).

#ifndef LOCAL_X
#define LOCAL_X 256
#endif

layout(local_size_x = LOCAL_X, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer RateBuffer { float rate[]; };
layout(std430, binding = 1) readonly buffer MaskBuffer { uint validMask[]; };
layout(std430, binding = 2) writeonly buffer HumidityBuffer { float humidity[]; };
layout(std430, binding = 3) writeonly buffer WeightedBuffer { float weighted[]; };
layout(std430, binding = 4) writeonly buffer StandingBuffer { float standing[]; };

uniform uint uCount;
uniform uint uFirst;
uniform int uHasMask;
uniform int uWeighted;
uniform int uStanding;
uniform float uQuantity[12];
uniform float uInverseIntensity[12];

void main()
{
  uint k = gl_GlobalInvocationID.x;
  if (k >= uCount)
  {
    return;
  }
  // No data is tested explicitly: GLSL does not promise IEEE NaN propagation through the
  // select below (llvmpipe turns it into a min that drops the NaN).
  float nan = uintBitsToFloat(0x7fc00000u);
  float s = rate[k];
  bool ok = !isnan(s);
  if (uHasMask != 0)
  {
    uint g = uFirst + k;
    ok = ok && (((validMask[g >> 2u] >> (8u * (g & 3u))) & 0xffu) != 0u);
  }
  float sh[12];
  for (int m = 0; m < 12; ++m)
  {
    float ratio = s * uInverseIntensity[m];
    sh[m] = ok ? (ratio > 1.0 ? 1.0 : ratio) * uQuantity[m] : nan;
    humidity[12u * k + uint(m)] = sh[m];
  }
  if (uWeighted != 0)
  {
    for (int m = 0; m < 12; ++m)
    {
      float a = sh[m];
      float b = sh[(m + 11) % 12];
      float c = sh[(m + 10) % 12];
      weighted[12u * k + uint(m)] = a * 0.5 + b * (1.0 / 3.0) + c * (1.0 / 6.0);
    }
  }
  if (uStanding != 0)
  {
    for (int m = 0; m < 12; ++m)
    {
      standing[12u * k + uint(m)] = ok ? uQuantity[m] - sh[m] : nan;
    }
  }
}

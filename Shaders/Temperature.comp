// Temperature.comp: monthly temperature with a constant lapse rate, one thread per cell;
// mirrors terroir::terrain::TemperatureLapseRateRows (Filters/Terrain/Core/TemperatureLapseRate.cxx).
//   T(m, h) = uSeaLevel[m] - uRate * h      (uRate = lapse rate in °C per metre)
//
// Bindings (std430):
//   0  readonly  float elevation[count]         metres, cells uFirst .. uFirst + count - 1
//   1  readonly  uint  validMask[(n+3)/4]        byte k of word w = validity of cell 4w+k of
//                                                the whole grid (read when uHasMask)
//   2  writeonly float temperature[12*count]     °C, 12 months per cell, January first; NaN
//                                                for no-data cells
// Uniforms: uint uCount (cells in this dispatch), uint uFirst (index of the first cell in the
// grid, for the mask), int uHasMask, float uSeaLevel[12] (°C), float uRate (°C/m).
// Work group LOCAL_X (define, 256 by default); dispatch ceil(count/LOCAL_X).

#ifndef LOCAL_X
#define LOCAL_X 256
#endif

layout(local_size_x = LOCAL_X, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer ElevationBuffer { float elevation[]; };
layout(std430, binding = 1) readonly buffer MaskBuffer { uint validMask[]; };
layout(std430, binding = 2) writeonly buffer TemperatureBuffer { float temperature[]; };

uniform uint uCount;
uniform uint uFirst;
uniform int uHasMask;
uniform float uSeaLevel[12];
uniform float uRate;

void main()
{
  uint k = gl_GlobalInvocationID.x;
  if (k >= uCount)
  {
    return;
  }
  float h = elevation[k];
  bool ok = !isnan(h);
  if (uHasMask != 0)
  {
    uint g = uFirst + k;
    ok = ok && (((validMask[g >> 2u] >> (8u * (g & 3u))) & 0xffu) != 0u);
  }
  float drop = uRate * h;
  float nan = uintBitsToFloat(0x7fc00000u);
  for (int m = 0; m < 12; ++m)
  {
    temperature[12u * k + uint(m)] = ok ? uSeaLevel[m] - drop : nan;
  }
}

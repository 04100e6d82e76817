// Temperature.comp: monthly temperature with a constant lapse rate, one invocation per cell
// (three vec4 stores of its 12 months); mirrors terroir::terrain::TemperatureLapseRateRows
// (Filters/Terrain/Core/TemperatureLapseRate.cxx).
//   T(m, h) = uSeaLevel[m] - uRate * h      (uRate = lapse rate in °C per metre)
//
// Bindings (std430):
//   0  readonly  float elevation[]               metres; cell uFirst + k of the grid at
//                                                uElevationFirst + k (the whole grid with
//                                                uElevationFirst = uFirst, or this slice with 0)
//   1  readonly  uint  validMask[(n+3)/4]        byte k of word w = validity of cell 4w+k of
//                                                the whole grid (TEMPERATURE_MASK)
//   2  writeonly vec4  temperature[3*count]      °C, 12 months per cell, January first; NaN
//                                                for no-data cells
// Uniforms: uint uCount (cells of the slice), uFirst (its first cell in the grid),
// uElevationFirst; float uSeaLevel[12] (°C), uRate (°C/m).
// Defines: TEMPERATURE_MASK (the grid has no-data cells); LOCAL_X (256 by default).
// Dispatch: gx x gy groups of LOCAL_X covering count invocations (cell k = id.y * gx * LOCAL_X +
// id.x).

#ifndef LOCAL_X
#define LOCAL_X 256
#endif

layout(local_size_x = LOCAL_X, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer ElevationBuffer { float elevation[]; };
layout(std430, binding = 1) readonly buffer MaskBuffer { uint validMask[]; };
layout(std430, binding = 2) writeonly buffer TemperatureBuffer { vec4 temperature[]; };

uniform uint uCount;
uniform uint uFirst;
uniform uint uElevationFirst;
uniform float uSeaLevel[12];
uniform float uRate;

void main()
{
  uint k = TERROIR_GLOBAL_ID.y * (TERROIR_NUM_WORKGROUPS.x * uint(LOCAL_X)) + TERROIR_GLOBAL_ID.x;
  if (k >= uCount)
  {
    return;
  }
  float h = elevation[uElevationFirst + k];
  bool ok = !terroirIsNaN(h);
#ifdef TEMPERATURE_MASK
  uint g = uFirst + k;
  ok = ok && (((validMask[g >> 2u] >> (8u * (g & 3u))) & 0xffu) != 0u);
#endif
  float drop = uRate * h;
  for (int q = 0; q < 3; ++q)
  {
    vec4 v = vec4(uSeaLevel[4 * q] - drop,
      uSeaLevel[4 * q + 1] - drop,
      uSeaLevel[4 * q + 2] - drop,
      uSeaLevel[4 * q + 3] - drop);
    temperature[3u * k + uint(q)] = ok ? v : vec4(TERROIR_NAN);
  }
}

// WaterFlow.comp: one iteration of the hydrostatic water flow in two passes (a gather); mirrors
// terroir::hydrology::WaterFlowSimulation::RowBlock and WaterFlowEvacuation
// (Filters/Hydrology/Core/WaterFlow.{h,cxx}): the same double operations in the same order
// (`precise`: no fused multiply-add, no reassociation;
// divisions correctly rounded by terroirDiv, as the CPU's,
// where GLSL leaves double division's accuracy to the driver), on the same padded
// (nx + 2) x (ny + 2) arrays, row 0 = the southern border row.
// Double precision, the one exception to the float32 rule of Documentation/Shaders.md: water
// depths are kept in double by the core, and the GPU path must stop after the same iteration.
//
// Two kernels (one file), since llvmpipe runs every branch of a kernel, taken or not:
// WATERFLOW_GIVERS  for every padded cell, (level, scale, out) of WaterFlowEvacuation from its
//          terrain, water and its 8 neighbours' heights T + W (order E, NE, N, NW, W, SW, S, SE);
//          zeros on the border rows and columns and on dry cells (outlets are always dry).
// (default) gather: for every padded cell, in = sum over the 8 neighbours of
//          scale * c * max(0, level - H) (neighbours outside the padded array give nothing;
//          volume from rows r +- 1 becomes depth through the area ratio); on cells (interior row,
//          isCell) waterOut = max(0, W - out + in) + rain[c] and discharge += out; on outlets
//          waterOut = 0; with uEdges, the net flux through each cell's E, NE, N and NW edges is
//          added to edges[] (the river-forming mode's net discharge).
//          Each work group reduces out * area (moved) and in * area of its outlets (outflow), in
//          a fixed tree order, into partials[2 * (uSlot * uGroups + group) + {0, 1}] (m^3).
// (The host snapshots and restores water and discharge with buffer copies.)
//
// Bindings (std430; N = (nx + 2) * (ny + 2) padded cells, index r * uStride + column):
//   0  readonly  float  terrain[N]          T, metres (border and no-data heights included)
//   1  readonly  uint   isCell[(N+3)/4]     byte k of word w = 1 when padded cell 4w+k is a
//                                           valid cell, 0 on outlets (border, no data)
//   2  readonly  double rowData[8*(ny+2)]   per padded row r: closeness E/W (row r), N (r to
//                                           r+1), NE/NW (r to r+1), S (r to r-1, 0 on row 0),
//                                           SE/SW (r to r-1, 0 on row 0), area ratio from the
//                                           north A[r+1]/A[r] (0 on the last row), from the
//                                           south A[r-1]/A[r] (0 on row 0), cell area A[r] (m^2)
//   3  readonly  double waterIn[N]          W, metres
//   4  writeonly double waterOut[N]         W', metres (gather)
//   5            double giverLevel[N]       L, metres (written by the givers, read by the gather)
//   6            double giverScale[N]       s (givers -> gather)
//   7            double giverOut[N]         water the cell gives, metres (givers -> gather)
//   8            double discharge[N]        accumulated out, metres of depth (gather)
//   9  writeonly double partials[]          2 per work group and iteration slot (gather)
//  10  readonly  double rain[N or 1]        rain added to each cell per iteration, metres (one
//                                           value for every cell when uRainField is 0)
//  11            double edges[4*N]          net flux sums, planes E, NE, N, NW (uEdges != 0)
// Uniforms: uint uStride (nx + 2), uint uRows (ny + 2), uint uCount (N), uint uGroups (work
// groups per dispatch, gx * gy), uint uSlot (partials slot of this iteration), uint uEdges (1:
// accumulate edges[]), uint uLongCapacity (1: Long (2016)'s literal capacity rule, givers), uint
// uRainField (1: rain[] per cell).
// Work group LOCAL_X (define, a power of two, 256 by default); dispatch ceil(N / LOCAL_X)
// groups, as gx x gy when that exceeds GL_MAX_COMPUTE_WORK_GROUP_COUNT[0] (group index
// TERROIR_WORKGROUP_ID.y * TERROIR_NUM_WORKGROUPS.x + TERROIR_WORKGROUP_ID.x).

#ifndef LOCAL_X
#define LOCAL_X 256
#endif

layout(local_size_x = LOCAL_X, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer TerrainBuffer { float terrain[]; };
layout(std430, binding = 1) readonly buffer IsCellBuffer { uint isCell[]; };
layout(std430, binding = 2) readonly buffer RowBuffer { double rowData[]; };
layout(std430, binding = 3) readonly buffer WaterInBuffer { double waterIn[]; };
layout(std430, binding = 4) writeonly buffer WaterOutBuffer { double waterOut[]; };
layout(std430, binding = 5) buffer LevelBuffer { double giverLevel[]; };
layout(std430, binding = 6) buffer ScaleBuffer { double giverScale[]; };
layout(std430, binding = 7) buffer OutBuffer { double giverOut[]; };
layout(std430, binding = 8) buffer DischargeBuffer { double discharge[]; };
layout(std430, binding = 9) writeonly buffer PartialsBuffer { double partials[]; };
layout(std430, binding = 10) readonly buffer RainBuffer { double rain[]; };
layout(std430, binding = 11) buffer EdgesBuffer { double edges[]; };

uniform uint uStride;
uniform uint uRows;
uniform uint uCount;
uniform uint uGroups;
uniform uint uSlot;
uniform uint uEdges;
uniform uint uLongCapacity;
uniform uint uRainField;

#ifndef WATERFLOW_GIVERS
shared double sMoved[LOCAL_X];
shared double sOutflow[LOCAL_X];
#endif

// Row data slots.
const uint kEW = 0u;
const uint kN = 1u;
const uint kNE = 2u;
const uint kS = 3u;
const uint kSE = 4u;
const uint kFromNorth = 5u;
const uint kFromSouth = 6u;
const uint kArea = 7u;

double Row(uint r, uint slot)
{
  return rowData[8u * r + slot];
}

// Height T + W of padded cell c (in double, as the core).
double Height(uint c)
{
  precise double h = double(terrain[c]) + waterIn[c];
  return h;
}

// Neighbour k of padded cell c, in the order E, NE, N, NW, W, SW, S, SE.
uint Neighbour(uint c, int k)
{
  int dx = (k == 0 || k == 1 || k == 7) ? 1 : ((k >= 3 && k <= 5) ? -1 : 0);
  int dy = (k >= 1 && k <= 3) ? 1 : (k >= 5 ? -1 : 0);
  return uint(int(c) + dy * int(uStride) + dx);
}

// Closeness of a cell of padded row r to its neighbour k.
double Closeness(uint r, int k)
{
  return (k == 0 || k == 4) ? Row(r, kEW)
    : (k == 1 || k == 3)    ? Row(r, kNE)
    : k == 2                ? Row(r, kN)
    : k == 6                ? Row(r, kS)
                            : Row(r, kSE);
}

// Pass 0: WaterFlowEvacuation for padded cell c at column i, row r. No local arrays of doubles:
// NVIDIA's compiler (driver 580.159.04, H200) gave other values for them than the ones stored
// (TestGPUDataPath.DoubleIdiomsOfTheKernels); the neighbours' heights and closenesses are read
// from the buffers where they are used.
void Givers(uint c, uint i, uint r)
{
  double level = 0.0LF;
  double scale = 0.0LF;
  double out_ = 0.0LF;
  double water = waterIn[c];
  bool inner = r >= 1u && r + 1u < uRows && i >= 1u && i + 1u < uStride;
  bool gated = false;
  if (inner && water > 0.0LF && uLongCapacity != 0u)
  {
    // Long (2016)'s literal rule: no flow when WEC = sum c (T - H), higher neighbours included,
    // is negative (WaterFlowLongCapacity).
    double t = double(terrain[c]);
    precise double wec = 0.0LF;
    for (int k = 0; k < 8; ++k)
    {
      precise double d = t - Height(Neighbour(c, k));
      wec = wec + Closeness(r, k) * d;
    }
    gated = wec < 0.0LF;
  }
  if (inner && water > 0.0LF && !gated)
  {
    double t = double(terrain[c]);
    precise double h = t + water;
    level = h;
    precise double all = 0.0LF;
    for (int k = 0; k < 8; ++k)
    {
      precise double drop = max(0.0LF, t - Height(Neighbour(c, k)));
      all = all + Closeness(r, k) * drop;
    }
    bool moves = true;
    if (all >= water)
    {
      level = t;
      scale = terroirDiv(water, all);
    }
    else
    {
      // Part: L = (H_i + sum_R c_k H_k) / (1 + sum_R c_k) over the receivers R = {H_k < L}.
      precise double num = h;
      precise double den = 1.0LF;
      uint receivers = 0u;
      for (int k = 0; k < 8; ++k)
      {
        double hk = Height(Neighbour(c, k));
        if (hk < h)
        {
          num = num + Closeness(r, k) * hk;
          den = den + Closeness(r, k);
          receivers |= 1u << uint(k);
        }
      }
      if (receivers == 0u)
      {
        moves = false;
      }
      else
      {
        double lv = terroirDiv(num, den);
        for (bool changed = true; changed;)
        {
          changed = false;
          for (int k = 0; k < 8; ++k)
          {
            double hk = Height(Neighbour(c, k));
            if (((receivers >> uint(k)) & 1u) != 0u && hk >= lv)
            {
              num = num - Closeness(r, k) * hk;
              den = den - Closeness(r, k);
              receivers &= ~(1u << uint(k));
              changed = true;
            }
          }
          if (changed)
          {
            lv = terroirDiv(num, den);
          }
        }
        level = lv;
        scale = 1.0LF;
      }
    }
    if (moves)
    {
      if (scale < 1.0LF)
      {
        out_ = water;
      }
      else
      {
        precise double sum = 0.0LF;
        for (int k = 0; k < 8; ++k)
        {
          precise double drop = max(0.0LF, level - Height(Neighbour(c, k)));
          sum = sum + Closeness(r, k) * drop;
        }
        out_ = sum;
      }
    }
  }
  giverLevel[c] = level;
  giverScale[c] = scale;
  giverOut[c] = out_;
}

// What giver n sends to a receiver at height h through closeness cl: scale * c * max(0, L - h).
double Sent(uint n, double cl, double h)
{
  precise double drop = max(0.0LF, giverLevel[n] - h);
  precise double s = giverScale[n] * cl * drop;
  return s;
}

// Pass 1: gather of padded cell c at column i, row r; returns (moved, outflow) volumes.
dvec2 Gather(uint c, uint i, uint r)
{
  double h = Height(c);
  bool west = i >= 1u;
  bool east = i + 1u < uStride;
  precise double inRow = (west ? Sent(c - 1u, Row(r, kEW), h) : 0.0LF) +
    (east ? Sent(c + 1u, Row(r, kEW), h) : 0.0LF);
  precise double inNorth = 0.0LF;
  if (r + 1u < uRows)
  {
    uint n = c + uStride;
    double cN = Row(r, kN);
    double cNE = Row(r, kNE);
    inNorth = (west ? Sent(n - 1u, cNE, h) : 0.0LF) + Sent(n, cN, h);
    inNorth = inNorth + (east ? Sent(n + 1u, cNE, h) : 0.0LF);
  }
  precise double inSouth = 0.0LF;
  if (r >= 1u)
  {
    uint s = c - uStride;
    double cS = Row(r, kS);
    double cSE = Row(r, kSE);
    inSouth = (west ? Sent(s - 1u, cSE, h) : 0.0LF) + Sent(s, cS, h);
    inSouth = inSouth + (east ? Sent(s + 1u, cSE, h) : 0.0LF);
  }
  precise double inflow =
    inRow + Row(r, kFromNorth) * inNorth + Row(r, kFromSouth) * inSouth;
  bool interior = r >= 1u && r + 1u < uRows;
  bool cell = ((isCell[c >> 2u] >> (8u * (c & 3u))) & 0xffu) != 0u;
  double area = Row(r, kArea);
  if (uEdges != 0u)
  {
    // Net flux through the cell's E, NE, N and NW edges (as the core's gather): what it sent
    // less what that neighbour sent back, as depth of this cell.
    bool north = r + 1u < uRows;
    uint n = c + uStride;
    double fromNorth = Row(r, kFromNorth);
    double own = east ? Sent(c, Row(r, kEW), Height(c + 1u)) : 0.0LF;
    double back = east ? Sent(c + 1u, Row(r, kEW), h) : 0.0LF;
    precise double dE = own - back;
    own = north && east ? Sent(c, Row(r, kNE), Height(n + 1u)) : 0.0LF;
    back = north && east ? Sent(n + 1u, Row(r, kNE), h) : 0.0LF;
    precise double dNE = own - fromNorth * back;
    own = north ? Sent(c, Row(r, kN), Height(n)) : 0.0LF;
    back = north ? Sent(n, Row(r, kN), h) : 0.0LF;
    precise double dN = own - fromNorth * back;
    own = north && west ? Sent(c, Row(r, kNE), Height(n - 1u)) : 0.0LF;
    back = north && west ? Sent(n - 1u, Row(r, kNE), h) : 0.0LF;
    precise double dNW = own - fromNorth * back;
    precise double e0 = edges[c] + dE;
    precise double e1 = edges[uCount + c] + dNE;
    precise double e2 = edges[2u * uCount + c] + dN;
    precise double e3 = edges[3u * uCount + c] + dNW;
    edges[c] = e0;
    edges[uCount + c] = e1;
    edges[2u * uCount + c] = e2;
    edges[3u * uCount + c] = e3;
  }
  if (interior && cell)
  {
    double out_ = giverOut[c];
    precise double w = waterIn[c] - out_ + inflow;
    precise double kept = max(0.0LF, w) + rain[uRainField != 0u ? c : 0u];
    waterOut[c] = kept;
    precise double d = discharge[c] + out_;
    discharge[c] = d;
    precise double moved = out_ * area;
    return dvec2(moved, 0.0LF);
  }
  waterOut[c] = 0.0LF;
  precise double outflow = inflow * area;
  return dvec2(0.0LF, outflow);
}

#ifdef WATERFLOW_GIVERS

void main()
{
  uint group = TERROIR_WORKGROUP_ID.y * TERROIR_NUM_WORKGROUPS.x + TERROIR_WORKGROUP_ID.x;
  uint c = group * uint(LOCAL_X) + gl_LocalInvocationID.x;
  if (c < uCount)
  {
    uint r = c / uStride;
    Givers(c, c - r * uStride, r);
  }
}

#else

void main()
{
  uint group = TERROIR_WORKGROUP_ID.y * TERROIR_NUM_WORKGROUPS.x + TERROIR_WORKGROUP_ID.x;
  uint lid = gl_LocalInvocationID.x;
  uint c = group * uint(LOCAL_X) + lid;
  bool live = c < uCount;
  uint r = live ? c / uStride : 0u;
  uint i = live ? c - r * uStride : 0u;
  // Every invocation reaches the barriers, live (c < N) or not.
  dvec2 v = live ? Gather(c, i, r) : dvec2(0.0LF);
  sMoved[lid] = v.x;
  sOutflow[lid] = v.y;
  memoryBarrierShared();
  barrier();
  for (uint half_ = uint(LOCAL_X) / 2u; half_ > 0u; half_ >>= 1u)
  {
    if (lid < half_)
    {
      precise double m = sMoved[lid] + sMoved[lid + half_];
      precise double o = sOutflow[lid] + sOutflow[lid + half_];
      sMoved[lid] = m;
      sOutflow[lid] = o;
    }
    memoryBarrierShared();
    barrier();
  }
  if (lid == 0u && group < uGroups)
  {
    uint p = 2u * (uSlot * uGroups + group);
    partials[p] = sMoved[0];
    partials[p + 1u] = sOutflow[0];
  }
}

#endif

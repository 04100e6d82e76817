// Erosion.comp: the hydraulic step (passes 1-6) and the thermal step (soil slip) of
// terroir::terrain::ErosionHydraulicStep / ErosionThermalStep (Filters/Terrain/Core/Erosion.{h,cxx}),
// one kernel per pass, chosen by a #define. The per-cell arithmetic is the core's, in float,
// operation for operation and in the same order (`precise`: no fused multiply-add, no
// reassociation; std::min/std::max written as the C++ library defines them, so that zeros keep
// their sign), with the core's TwoSum residues. Divisions go through terroirDiv and square roots
// through SqrtFloat (both correctly rounded, as the CPU's), so on a driver whose + - * are IEEE
// the state is the CPU's to the bit. Only exp2 (Weiss's eq. 24, halving depths, off by default)
// is the driver's.
// Sums are taken in double as the core takes them: each pass writes each cell's contribution
// (exact double products of floats) into `contrib`, EROSION_ROWS sums every row in cell order
// (one invocation per row and plane), EROSION_TOTALS sums the rows in row order on one
// invocation: the same additions in the same order as the core's SumRows, so Dunn's k and the
// volumes are the CPU's bits too. Double is the second exception to the float32 rule of
// Documentation/Shaders.md (the core keeps its totals in double).
//
// Kernels (one invocation per cell c = j nx + i unless said; 1-D groups of LOCAL_X, gx x gy):
// EROSION_SURFACE   pass 1a (SurfaceRows): kind, d1 (waterLo in place), surface; contrib 0 rain
// EROSION_FLUX      pass 1b (FluxRows): new fluxes of land cells into fluxOut (0 elsewhere)
// EROSION_WATER     pass 2 (WaterRows): d2, residue, velocity; contrib 0 to sea, 1 clamped
// EROSION_ERODE     pass 3 (ErodeRows): bed into scratch, s', soil, terrainLo in place;
//                   contrib 0 eroded, 1 deposited
// EROSION_ADVECT    pass 4 (AdvectRows): back-traced s' into scratch; contrib 0 before, 1 after
// EROSION_FINISH    pass 5 (FinishRows): Dunn's k, evaporation, settling; contrib 0 evaporated,
//                   1 deposited
// EROSION_SLIP_SCALE thermal pass 1 (SlipScaleRows): giver scale; contrib 0 excess (max)
// EROSION_SLIP      thermal pass 2 (SlipRows): new bed and soil into scratch, terrainLo in
//                   place; contrib 0 moved
// EROSION_ROWS      one invocation per (plane p < uPlanes, row j): rowSums[(uSlot + p) ny + j] =
//                   the sum (or, for the planes in uMaxMask, the max from 0) of contrib plane p
//                   over the row in cell order
// EROSION_TOTALS    one invocation: uMode 0: Dunn's k from slots 5, 6 into control[0], and
//                   control[1] = 1 when the moved field is used (after > 0); uMode 1: adds the
//                   hydraulic step's volumes to control[2..7], k into control[8]; uMode 2: adds
//                   the thermal moved volume to control[9], its largest excess into control[10]
//
// Bindings (std430; N = nx ny cells; "plane p" = entries [p N, (p + 1) N)):
//   0  float  state[9 N]   planes 0 terrain b, 1 terrain residue, 2 original, 3 soil, 4 water d,
//                          5 water residue, 6 sediment s, 7 u, 8 v (m, m/s)
//   1  readonly float fluxIn[4 N]   planes W, E, S, N of the previous step (m^3/s)
//   2  writeonly float fluxOut[4 N] the new fluxes (EROSION_FLUX)
//   3  readonly float inputs[4 N]   planes 0 erosion factor, 1 talus factor, 2 rain (m/s),
//                          3 evaporation factor (each read only when its uFlags bit is set)
//   4  float  scratch[4 N] hydraulic: planes 0 d1, 1 surface, 2 new bed, 3 moved s;
//                          thermal: 0 giver scale, 1 new bed, 2 new soil
//   5  uint   kind[N]      0 wall, 1 sea, 2 land (written by EROSION_SURFACE)
//   6  readonly uint valid[(N + 3) / 4]  byte k of word w: 1 when cell 4w + k has data
//   7  readonly float rows[10 ny]  per row j, planes: 0 lx, 1 ly, 2 area, 3 lNorth (j to j+1),
//                          4 coefEW, 5 coefNorth (j to j+1), 6 coefEdge (through the edge),
//                          7 diagNorth, 8 area[j-1]/area[j], 9 area[j+1]/area[j]
//   8  double contrib[2 N] per-cell terms of the row sums (m^3; m for the excess)
//   9  double rowSums[11 ny] slots 0 rain, 1 to sea, 2 clamped, 3 eroded, 4 deposited (erode),
//                          5 before, 6 after, 7 evaporated, 8 deposited (finish), 9 thermal
//                          excess (max), 10 thermal moved
//  10  double control[11]  0 k, 1 moved used, 2 rain, 3 evaporated, 4 to sea, 5 clamped,
//                          6 eroded, 7 deposited (totals over the steps, m^3), 8 last k,
//                          9 thermal moved (m^3), 10 last thermal excess (m)
// Uniforms: uint uNx, uNy, uN, uFlags (bits below), uPlanes, uSlot, uMaxMask, uMode; float
// uSeaLevel, uDt, uDryDepth, uSoftMin, uSoftScale, uKc, uRampDepth, uMaxChange (+inf: none),
// uKs, uKsRock, uKd, uHalvingE, uHalvingD, uMinTilt, uMaxTilt, uKe (K_e dt), uTanSoil, uTanRock,
// uRate16 (rate / 16). All float constants are the core's float casts, made on the host.
// Work group LOCAL_X (define, 256 by default; the host uses 64 for EROSION_ROWS and
// EROSION_TOTALS); the host dispatches ceil(items / LOCAL_X) groups as gx x gy
// (group = TERROIR_WORKGROUP_ID.y * TERROIR_NUM_WORKGROUPS.x + .x).

#ifndef LOCAL_X
#define LOCAL_X 256
#endif

layout(local_size_x = LOCAL_X, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = 0) buffer StateBuffer { float state[]; };
layout(std430, binding = 1) readonly buffer FluxInBuffer { float fluxIn[]; };
layout(std430, binding = 2) writeonly buffer FluxOutBuffer { float fluxOut[]; };
layout(std430, binding = 3) readonly buffer InputsBuffer { float inputs[]; };
layout(std430, binding = 4) buffer ScratchBuffer { float scratch[]; };
layout(std430, binding = 5) buffer KindBuffer { uint kind[]; };
layout(std430, binding = 6) readonly buffer ValidBuffer { uint valid[]; };
layout(std430, binding = 7) readonly buffer RowsBuffer { float rows[]; };
layout(std430, binding = 8) buffer ContribBuffer { double contrib[]; };
layout(std430, binding = 9) buffer RowSumsBuffer { double rowSums[]; };
layout(std430, binding = 10) buffer ControlBuffer { double control[]; };

uniform uint uNx;
uniform uint uNy;
uniform uint uN;
uniform uint uFlags;
uniform uint uPlanes;
uniform uint uSlot;
uniform uint uMaxMask;
uniform uint uMode;
uniform float uSeaLevel;
uniform float uDt;
uniform float uDryDepth;
uniform float uSoftMin;
uniform float uSoftScale;
uniform float uKc;
uniform float uRampDepth;
uniform float uMaxChange;
uniform float uKs;
uniform float uKsRock;
uniform float uKd;
uniform float uHalvingE;
uniform float uHalvingD;
uniform float uMinTilt;
uniform float uMaxTilt;
uniform float uKe;
uniform float uTanSoil;
uniform float uTanRock;
uniform float uRate16;

// uFlags bits.
const uint kSeaBoundary = 1u;
const uint kLayered = 2u;
const uint kErosionFactor = 4u;
const uint kTalusFactor = 8u;
const uint kRain = 16u;
const uint kEvaporationFactor = 32u;
const uint kSoftOutflow = 64u;
const uint kRamp = 128u;
const uint kHalvingErosion = 256u;
const uint kHalvingDeposition = 512u;

// Planes of state, inputs, scratch and rows.
const uint kB = 0u;
const uint kBLo = 1u;
const uint kOriginal = 2u;
const uint kSoil = 3u;
const uint kD = 4u;
const uint kDLo = 5u;
const uint kS = 6u;
const uint kU = 7u;
const uint kV = 8u;
const uint kInErosion = 0u;
const uint kInTalus = 1u;
const uint kInRain = 2u;
const uint kInEvaporation = 3u;
const uint kD1 = 0u;
const uint kSurface = 1u;
const uint kBed = 2u;
const uint kMoved = 3u;
const uint kSlipScale = 0u;
const uint kSlipBed = 1u;
const uint kSlipSoil = 2u;
const uint kRowLx = 0u;
const uint kRowLy = 1u;
const uint kRowArea = 2u;
const uint kRowLNorth = 3u;
const uint kRowCoefEW = 4u;
const uint kRowCoefNorth = 5u;
const uint kRowCoefEdge = 6u;
const uint kRowDiagNorth = 7u;
const uint kRowFromSouth = 8u;
const uint kRowFromNorth = 9u;

// Cell kinds (the core's CellKind).
const uint kWall = 0u;
const uint kSea = 1u;
const uint kLand = 2u;

bool Flag(uint bit)
{
  return (uFlags & bit) != 0u;
}

float St(uint plane, uint c)
{
  return state[plane * uN + c];
}

void SetSt(uint plane, uint c, float v)
{
  state[plane * uN + c] = v;
}

float Sc(uint plane, uint c)
{
  return scratch[plane * uN + c];
}

void SetSc(uint plane, uint c, float v)
{
  scratch[plane * uN + c] = v;
}

float Row(uint plane, uint j)
{
  return rows[plane * uNy + j];
}

float Input(uint plane, uint c)
{
  return inputs[plane * uN + c];
}

bool IsValid(uint c)
{
  return ((valid[c >> 2u] >> (8u * (c & 3u))) & 0xffu) != 0u;
}

// std::max(a, b) and std::min(a, b) as the C++ library defines them (which operand a tie or a
// pair of zeros returns matters for the bits).
float MaxF(float a, float b)
{
  return (a < b) ? b : a;
}

float MinF(float a, float b)
{
  return (b < a) ? b : a;
}

double MaxD(double a, double b)
{
  return (a < b) ? b : a;
}

// Correctly rounded float square root (as std::sqrt): the driver's double root rounded to
// float, then moved one float up or down when x lies beyond the midpoint to that neighbour
// (midpoints have 25 significant bits, so their squares are exact in double).
float SqrtFloat(float x)
{
  if (!(x > 0.0) || !terroirIsFinite(x))
  {
    return sqrt(x);
  }
  float r = float(sqrt(double(x)));
  double dx = double(x);
  float up = uintBitsToFloat(floatBitsToUint(r) + 1u);
  float down = uintBitsToFloat(floatBitsToUint(r) - 1u);
  precise double midUp = (double(r) + double(up)) * 0.5LF;
  precise double midDown = (double(r) + double(down)) * 0.5LF;
  precise double up2 = midUp * midUp;
  precise double down2 = midDown * midDown;
  if (dx > up2)
  {
    return up;
  }
  if (dx < down2)
  {
    return down;
  }
  return r;
}

// The core's AddCompensated: hi + lo += delta, the rounding error kept in lo (TwoSum).
// Returns (hi, lo).
vec2 AddCompensated(float hi, float lo, float delta)
{
  precise float t = delta + lo;
  precise float sum = hi + t;
  precise float back = sum - hi;
  precise float newLo = (hi - (sum - back)) + (t - back);
  return vec2(sum, newLo);
}

// Cell index of the invocation (1-D groups), and whether it is below `count`.
uint Invocation()
{
  uint group = TERROIR_WORKGROUP_ID.y * TERROIR_NUM_WORKGROUPS.x + TERROIR_WORKGROUP_ID.x;
  return group * uint(LOCAL_X) + gl_LocalInvocationID.x;
}

// The four pipes: 0 W, 1 E, 2 S, 3 N. Neighbour index (meaningful when Inside).
bool Inside(uint i, uint j, uint k)
{
  return k == 0u ? i > 0u : (k == 1u ? i + 1u < uNx : (k == 2u ? j > 0u : j + 1u < uNy));
}

uint PipeNeighbour(uint c, uint k)
{
  return k == 0u ? c - 1u : (k == 1u ? c + 1u : (k == 2u ? c - uNx : c + uNx));
}

float FluxIn(uint k, uint c)
{
  return fluxIn[k * uN + c];
}

#ifdef EROSION_SURFACE

void main()
{
  uint c = Invocation();
  if (c >= uN)
  {
    return;
  }
  uint j = c / uNx;
  double rained = 0.0LF;
  if (!IsValid(c))
  {
    kind[c] = Flag(kSeaBoundary) ? kSea : kWall;
    SetSc(kD1, c, 0.0);
    SetSt(kDLo, c, 0.0);
    SetSc(kSurface, c, uSeaLevel);
    contrib[c] = rained;
    return;
  }
  float depth = St(kD, c);
  if (Flag(kRain))
  {
    precise float added = uDt * Input(kInRain, c);
    vec2 d = AddCompensated(depth, St(kDLo, c), added);
    depth = d.x;
    SetSt(kDLo, c, d.y);
    precise double r = double(added) * double(Row(kRowArea, j));
    rained = r;
  }
  float b = St(kB, c);
  bool sea = Flag(kSeaBoundary) && b <= uSeaLevel;
  kind[c] = sea ? kSea : kLand;
  SetSc(kD1, c, depth);
  precise float surface = b + depth;
  SetSc(kSurface, c, sea ? uSeaLevel : surface);
  contrib[c] = rained;
}

#endif

#ifdef EROSION_FLUX

// One pipe's new flux (the core's PipeFlux), or 0 when the pipe is closed.
float Pipe(uint c, uint i, uint j, uint k, float coef, float surface)
{
  bool inside = Inside(i, j, k);
  bool open = inside ? kind[PipeNeighbour(c, k)] != kWall : Flag(kSeaBoundary);
  if (!open)
  {
    return 0.0;
  }
  float level = inside ? Sc(kSurface, PipeNeighbour(c, k)) : uSeaLevel;
  precise float dh = surface - level;
  precise float raw = FluxIn(k, c) + coef * dh;
  precise float f = MaxF(0.0, raw);
  if (Flag(kSoftOutflow))
  {
    precise float cap = uSoftMin + uSoftScale * abs(dh);
    f = MinF(f, cap);
  }
  return f;
}

void main()
{
  uint c = Invocation();
  if (c >= uN)
  {
    return;
  }
  uint j = c / uNx;
  uint i = c - j * uNx;
  float fw = 0.0;
  float fe = 0.0;
  float fs = 0.0;
  float fn = 0.0;
  if (kind[c] == kLand)
  {
    float surface = Sc(kSurface, c);
    float coefEW = Row(kRowCoefEW, j);
    float coefS = j > 0u ? Row(kRowCoefNorth, j - 1u) : Row(kRowCoefEdge, j);
    float coefN = j + 1u < uNy ? Row(kRowCoefNorth, j) : Row(kRowCoefEdge, j);
    fw = Pipe(c, i, j, 0u, coefEW, surface);
    fe = Pipe(c, i, j, 1u, coefEW, surface);
    fs = Pipe(c, i, j, 2u, coefS, surface);
    fn = Pipe(c, i, j, 3u, coefN, surface);
    precise float sum = (fw + fe) + (fs + fn);
    if (sum > 0.0)
    {
      precise float have = Sc(kD1, c) * Row(kRowArea, j);
      precise float want = sum * uDt;
      float scale = MinF(1.0, terroirDiv(have, want));
      precise float w = fw * scale;
      precise float e = fe * scale;
      precise float s = fs * scale;
      precise float n = fn * scale;
      fw = w;
      fe = e;
      fs = s;
      fn = n;
    }
  }
  fluxOut[c] = fw;
  fluxOut[uN + c] = fe;
  fluxOut[2u * uN + c] = fs;
  fluxOut[3u * uN + c] = fn;
}

#endif

#ifdef EROSION_WATER

// The new fluxes are bound as fluxIn for this pass and the next ones.
float Fw(uint c)
{
  return FluxIn(0u, c);
}
float Fe(uint c)
{
  return FluxIn(1u, c);
}
float Fs(uint c)
{
  return FluxIn(2u, c);
}
float Fn(uint c)
{
  return FluxIn(3u, c);
}

void main()
{
  uint c = Invocation();
  if (c >= uN)
  {
    return;
  }
  uint j = c / uNx;
  uint i = c - j * uNx;
  double toSea = 0.0LF;
  double clamped = 0.0LF;
  if (!IsValid(c))
  {
    SetSt(kD, c, 0.0);
    SetSt(kDLo, c, 0.0);
    SetSt(kU, c, 0.0);
    SetSt(kV, c, 0.0);
    contrib[c] = toSea;
    contrib[uN + c] = clamped;
    return;
  }
  float area = Row(kRowArea, j);
  float d1 = Sc(kD1, c);
  // Inflow (the core's Inflow): what the four neighbours send this cell.
  float w = i > 0u ? Fe(c - 1u) : 0.0;
  float e = i + 1u < uNx ? Fw(c + 1u) : 0.0;
  float s = j > 0u ? Fn(c - uNx) : 0.0;
  float n = j + 1u < uNy ? Fs(c + uNx) : 0.0;
  precise float inflow = (w + e) + (s + n);
  float d2 = 0.0;
  float depth = 0.0;
  if (kind[c] == kSea)
  {
    precise double sea = (double(d1) + double(St(kDLo, c))) * double(area);
    precise float inDt = uDt * inflow;
    precise double sum = sea + double(inDt);
    toSea = sum;
    SetSt(kDLo, c, 0.0);
    depth = MaxF(uSeaLevel - St(kB, c), uDryDepth);
  }
  else
  {
    precise float out_ = (Fw(c) + Fe(c)) + (Fs(c) + Fn(c));
    precise float net = uDt * (inflow - out_);
    vec2 d = AddCompensated(d1, St(kDLo, c), terroirDiv(net, area));
    d2 = d.x;
    float lo = d.y;
    precise double total = double(d2) + double(lo);
    if (total < 0.0LF || d2 < 0.0)
    {
      precise double gone = total * double(area);
      clamped = -gone;
      d2 = 0.0;
      lo = 0.0;
    }
    SetSt(kDLo, c, lo);
    if (Flag(kSeaBoundary))
    {
      // The core's OutflowToOutside: pipes through the edge or into no-data cells.
      precise float o = 0.0;
      o += (i == 0u || !IsValid(c - 1u)) ? Fw(c) : 0.0;
      o += (i + 1u == uNx || !IsValid(c + 1u)) ? Fe(c) : 0.0;
      o += (j == 0u || !IsValid(c - uNx)) ? Fs(c) : 0.0;
      o += (j + 1u == uNy || !IsValid(c + uNx)) ? Fn(c) : 0.0;
      precise float oDt = uDt * o;
      toSea = double(oDt);
    }
    precise float mean = 0.5 * (d1 + d2);
    depth = mean;
  }
  SetSt(kD, c, d2);
  float u = 0.0;
  float v = 0.0;
  if (depth >= uDryDepth && depth > 0.0)
  {
    // Net fluxes (the core's NetFluxX, NetFluxY).
    float inW = i > 0u ? Fe(c - 1u) : 0.0;
    float outE = i + 1u < uNx ? Fw(c + 1u) : 0.0;
    precise float netX = 0.5 * ((inW - Fw(c)) + (Fe(c) - outE));
    float inS = j > 0u ? Fn(c - uNx) : 0.0;
    float outN = j + 1u < uNy ? Fs(c + uNx) : 0.0;
    precise float netY = 0.5 * ((inS - Fs(c)) + (Fn(c) - outN));
    precise float denX = Row(kRowLy, j) * depth;
    precise float denY = Row(kRowLx, j) * depth;
    u = terroirDiv(netX, denX);
    v = terroirDiv(netY, denY);
  }
  SetSt(kU, c, u);
  SetSt(kV, c, v);
  contrib[c] = toSea;
  contrib[uN + c] = clamped;
}

#endif

#ifdef EROSION_ERODE

// |b - b_n| / l for a valid neighbour n, else 0 (the core's Tilt takes the max from 0).
float Slope(float b, uint n, float l)
{
  precise float dz = abs(b - St(kB, n));
  return terroirDiv(dz, l);
}

// sin(alpha) of Weiss eq. 17 (the core's Tilt), clamped to [minTilt, maxTilt].
float Tilt(uint c, uint i, uint j)
{
  float b = St(kB, c);
  float t = 0.0;
  if (i > 0u && IsValid(c - 1u))
    t = MaxF(t, Slope(b, c - 1u, Row(kRowLx, j)));
  if (i + 1u < uNx && IsValid(c + 1u))
    t = MaxF(t, Slope(b, c + 1u, Row(kRowLx, j)));
  if (j > 0u && IsValid(c - uNx))
    t = MaxF(t, Slope(b, c - uNx, Row(kRowLNorth, j - 1u)));
  if (j + 1u < uNy && IsValid(c + uNx))
    t = MaxF(t, Slope(b, c + uNx, Row(kRowLNorth, j)));
  precise float t2 = 1.0 + t * t;
  float sine = terroirDiv(t, SqrtFloat(t2));
  return MinF(MaxF(sine, uMinTilt), uMaxTilt);
}

void main()
{
  uint c = Invocation();
  if (c >= uN)
  {
    return;
  }
  uint j = c / uNx;
  uint i = c - j * uNx;
  float b = St(kB, c);
  SetSc(kBed, c, b);
  double eroded = 0.0LF;
  double deposited = 0.0LF;
  if (kind[c] != kLand)
  {
    contrib[c] = eroded;
    contrib[uN + c] = deposited;
    return;
  }
  float area = Row(kRowArea, j);
  float u = St(kU, c);
  float v = St(kV, c);
  precise float speed2 = u * u + v * v;
  precise float capacity = uKc * Tilt(c, i, j) * SqrtFloat(speed2);
  if (Flag(kRamp))
  {
    precise float ramped = capacity * MinF(1.0, terroirDiv(St(kD, c), uRampDepth));
    capacity = ramped;
  }
  float original = St(kOriginal, c);
  precise float erodedDepth = original - b;
  // The core's RatesAt (Weiss eq. 24 when the halving depths are set).
  float ks = uKs;
  float ksRock = uKsRock;
  float kd = uKd;
  if (Flag(kHalvingErosion))
  {
    float f = exp2(terroirDiv(-erodedDepth, uHalvingE));
    precise float a = ks * f;
    precise float r = ksRock * f;
    ks = MinF(1.0, a);
    ksRock = MinF(1.0, r);
  }
  if (Flag(kHalvingDeposition))
  {
    precise float a = kd * exp2(terroirDiv(erodedDepth, uHalvingD));
    kd = MinF(1.0, a);
  }
  if (Flag(kErosionFactor))
  {
    precise float a = ks * Input(kInErosion, c);
    precise float r = ksRock * Input(kInErosion, c);
    ks = a;
    ksRock = r;
  }
  float s = St(kS, c);
  vec2 bed;
  if (capacity > s)
  {
    precise float floor_ = original - uMaxChange;
    precise float room = b - floor_;
    float limit = MaxF(0.0, room);
    precise float deficit = capacity - s;
    // The core's Dissolve: soil first at K_s, then rock at K_s,rock.
    precise float take = ks * deficit;
    float taken;
    if (!Flag(kLayered))
    {
      taken = MinF(take, limit);
    }
    else
    {
      float soil = St(kSoil, c);
      float fromSoil = MinF(soil, take);
      float fromRock = 0.0;
      if (fromSoil < take)
      {
        precise float rest = ks > 0.0 ? deficit - terroirDiv(fromSoil, ks) : deficit;
        precise float rock = ksRock * MaxF(rest, 0.0);
        fromRock = rock;
      }
      fromSoil = MinF(fromSoil, limit);
      precise float left = limit - fromSoil;
      fromRock = MinF(fromRock, left);
      precise float newSoil = soil - fromSoil;
      SetSt(kSoil, c, newSoil);
      precise float sum = fromSoil + fromRock;
      taken = sum;
    }
    bed = AddCompensated(b, St(kBLo, c), -taken);
    precise float s2 = s + taken;
    SetSt(kS, c, s2);
    precise double e = double(taken) * double(area);
    eroded = e;
  }
  else
  {
    precise float ceiling = original + uMaxChange;
    precise float room = ceiling - b;
    float limit = MaxF(0.0, room);
    precise float excess = s - capacity;
    precise float want = kd * excess;
    float drop = MinF(want, limit);
    bed = AddCompensated(b, St(kBLo, c), drop);
    precise float s2 = s - drop;
    SetSt(kS, c, s2);
    if (Flag(kLayered))
    {
      precise float soil = St(kSoil, c) + drop;
      SetSt(kSoil, c, soil);
    }
    precise double e = double(drop) * double(area);
    deposited = e;
  }
  SetSc(kBed, c, bed.x);
  SetSt(kBLo, c, bed.y);
  contrib[c] = eroded;
  contrib[uN + c] = deposited;
}

#endif

#ifdef EROSION_ADVECT

float Sed(uint i, uint j)
{
  return St(kS, j * uNx + i);
}

// Bilinear sample of s' at (x, y) in cell units, clamped to the grid (the core's Sample).
float Sample(float x, float y)
{
  x = MinF(MaxF(x, 0.0), float(uNx - 1u));
  y = MinF(MaxF(y, 0.0), float(uNy - 1u));
  uint i0 = min(uint(int(x)), uNx - 1u);
  uint j0 = min(uint(int(y)), uNy - 1u);
  uint i1 = min(i0 + 1u, uNx - 1u);
  uint j1 = min(j0 + 1u, uNy - 1u);
  precise float fx = x - float(i0);
  precise float fy = y - float(j0);
  precise float south = Sed(i0, j0) + fx * (Sed(i1, j0) - Sed(i0, j0));
  precise float north = Sed(i0, j1) + fx * (Sed(i1, j1) - Sed(i0, j1));
  precise float s = south + fy * (north - south);
  return s;
}

void main()
{
  uint c = Invocation();
  if (c >= uN)
  {
    return;
  }
  uint j = c / uNx;
  uint i = c - j * uNx;
  double before = 0.0LF;
  double after = 0.0LF;
  if (!IsValid(c))
  {
    SetSc(kMoved, c, 0.0);
    contrib[c] = before;
    contrib[uN + c] = after;
    return;
  }
  precise float uDtProduct = St(kU, c) * uDt;
  precise float vDtProduct = St(kV, c) * uDt;
  float di = terroirDiv(uDtProduct, Row(kRowLx, j));
  float dj = terroirDiv(vDtProduct, Row(kRowLy, j));
  if (kind[c] == kSea)
  {
    di = MinF(MaxF(di, -1.0), 1.0);
    dj = MinF(MaxF(dj, -1.0), 1.0);
  }
  precise float x = float(i) - di;
  precise float y = float(j) - dj;
  float moved = Sample(x, y);
  SetSc(kMoved, c, moved);
  float area = Row(kRowArea, j);
  precise double b = double(St(kS, c)) * double(area);
  precise double a = double(moved) * double(area);
  contrib[c] = b;
  contrib[uN + c] = a;
}

#endif

#ifdef EROSION_FINISH

void main()
{
  uint c = Invocation();
  if (c >= uN)
  {
    return;
  }
  uint j = c / uNx;
  double evaporated = 0.0LF;
  double deposited = 0.0LF;
  bool seaCell = kind[c] == kSea;
  SetSt(kB, c, Sc(kBed, c));
  if (!IsValid(c))
  {
    SetSt(kS, c, 0.0);
    contrib[c] = evaporated;
    contrib[uN + c] = deposited;
    return;
  }
  float area = Row(kRowArea, j);
  float moved = control[1] != 0.0LF ? Sc(kMoved, c) : St(kS, c);
  precise double scaled = double(moved) * control[0];
  float s = float(scaled);
  float d2 = St(kD, c);
  float lo2 = St(kDLo, c);
  float factor = Flag(kEvaporationFactor) ? MaxF(Input(kInEvaporation, c), 0.0) : 1.0;
  precise float lost = uKe * factor;
  precise float keepRaw = 1.0 - lost;
  float keep = MaxF(0.0, keepRaw);
  precise float d3 = d2 * keep;
  precise float lo3 = lo2 * keep;
  precise double was = double(d2) + double(lo2);
  precise double now = double(d3) + double(lo3);
  precise double gone = (was - now) * double(area);
  evaporated = gone;
  SetSt(kD, c, d3);
  SetSt(kDLo, c, lo3);
  if (seaCell || d3 < uDryDepth)
  {
    vec2 bed = AddCompensated(St(kB, c), St(kBLo, c), s);
    SetSt(kB, c, bed.x);
    SetSt(kBLo, c, bed.y);
    if (Flag(kLayered))
    {
      precise float soil = St(kSoil, c) + s;
      SetSt(kSoil, c, soil);
    }
    SetSt(kS, c, 0.0);
    precise double dep = double(s) * double(area);
    deposited = dep;
  }
  else
  {
    SetSt(kS, c, s);
  }
  contrib[c] = evaporated;
  contrib[uN + c] = deposited;
}

#endif

#if defined(EROSION_SLIP_SCALE) || defined(EROSION_SLIP)

// The eight neighbours, E, NE, N, NW, W, SW, S, SE (the core's kDi, kDj).
int Di(int k)
{
  return (k == 0 || k == 1 || k == 7) ? 1 : ((k >= 3 && k <= 5) ? -1 : 0);
}

int Dj(int k)
{
  return (k >= 1 && k <= 3) ? 1 : (k >= 5 ? -1 : 0);
}

// Neighbour k of (i, j) when it is inside the grid and has data; its index in n.
bool Neighbour(uint i, uint j, int k, out uint n)
{
  int ii = int(i) + Di(k);
  int jj = int(j) + Dj(k);
  n = 0u;
  if (ii < 0 || jj < 0 || ii >= int(uNx) || jj >= int(uNy))
  {
    return false;
  }
  n = uint(jj) * uNx + uint(ii);
  return IsValid(n);
}

// Distance from a cell of row j to its neighbour k (the core's ThermalContext::Distance).
float Distance(uint j, int k)
{
  int dj = Dj(k);
  if (dj == 0)
  {
    return Row(kRowLx, j);
  }
  uint lower = dj > 0 ? j : j - 1u;
  return Di(k) == 0 ? Row(kRowLNorth, lower) : Row(kRowDiagNorth, lower);
}

float TanTalus(uint c)
{
  float t = (!Flag(kLayered) || St(kSoil, c) > 0.0) ? uTanSoil : uTanRock;
  if (Flag(kTalusFactor))
  {
    precise float f = t * Input(kInTalus, c);
    t = f;
  }
  return t;
}

// The core's SlipHeight: rate/16 times the giver's excess over the talus, or 0.
float SlipHeight(float giver, float receiver, float tanTalus, float d)
{
  precise float excess = (giver - receiver) - tanTalus * d;
  precise float h = excess * uRate16;
  return excess > 0.0 ? h : 0.0;
}

#endif

#ifdef EROSION_SLIP_SCALE

void main()
{
  uint c = Invocation();
  if (c >= uN)
  {
    return;
  }
  uint j = c / uNx;
  uint i = c - j * uNx;
  double excess = 0.0LF;
  float sc = 0.0;
  if (IsValid(c))
  {
    float tanTalus = TanTalus(c);
    float b = St(kB, c);
    precise float total = 0.0;
    for (int k = 0; k < 8; ++k)
    {
      uint n;
      if (Neighbour(i, j, k, n))
      {
        float d = Distance(j, k);
        float bn = St(kB, n);
        total = total + SlipHeight(b, bn, tanTalus, d);
        precise float e = (b - bn) - tanTalus * d;
        excess = MaxD(excess, double(e));
      }
    }
    sc = 1.0;
    float soil = St(kSoil, c);
    if (Flag(kLayered) && soil > 0.0 && total > soil)
    {
      sc = terroirDiv(soil, total);
    }
  }
  SetSc(kSlipScale, c, sc);
  contrib[c] = excess;
}

#endif

#ifdef EROSION_SLIP

void main()
{
  uint c = Invocation();
  if (c >= uN)
  {
    return;
  }
  uint j = c / uNx;
  uint i = c - j * uNx;
  float b = St(kB, c);
  SetSc(kSlipBed, c, b);
  if (Flag(kLayered))
  {
    SetSc(kSlipSoil, c, St(kSoil, c));
  }
  double moved = 0.0LF;
  if (!IsValid(c))
  {
    contrib[c] = moved;
    return;
  }
  float tanTalus = TanTalus(c);
  precise float out_ = 0.0;
  precise float in_ = 0.0;
  for (int k = 0; k < 8; ++k)
  {
    uint n;
    if (!Neighbour(i, j, k, n))
    {
      continue;
    }
    float d = Distance(j, k);
    float bn = St(kB, n);
    out_ = out_ + SlipHeight(b, bn, tanTalus, d);
    precise float got = Sc(kSlipScale, n) * SlipHeight(bn, b, TanTalus(n), d);
    int dj = Dj(k);
    float ratio = dj == 0 ? 1.0 : (dj > 0 ? Row(kRowFromNorth, j) : Row(kRowFromSouth, j));
    in_ = in_ + got * ratio;
  }
  precise float given = out_ * Sc(kSlipScale, c);
  precise float net = in_ - given;
  vec2 bed = AddCompensated(b, St(kBLo, c), net);
  SetSc(kSlipBed, c, bed.x);
  SetSt(kBLo, c, bed.y);
  if (Flag(kLayered))
  {
    float soil = St(kSoil, c);
    float fromSoil = soil > 0.0 ? MinF(given, soil) : 0.0;
    precise float newSoil = (soil - fromSoil) + in_;
    SetSc(kSlipSoil, c, newSoil);
  }
  precise double m = double(given) * double(Row(kRowArea, j));
  contrib[c] = m;
}

#endif

#ifdef EROSION_ROWS

void main()
{
  uint t = Invocation();
  if (t >= uPlanes * uNy)
  {
    return;
  }
  uint plane = t / uNy;
  uint j = t - plane * uNy;
  bool isMax = ((uMaxMask >> plane) & 1u) != 0u;
  uint base = plane * uN + j * uNx;
  precise double acc = 0.0LF;
  for (uint i = 0u; i < uNx; ++i)
  {
    double x = contrib[base + i];
    acc = isMax ? MaxD(acc, x) : acc + x;
  }
  rowSums[(uSlot + plane) * uNy + j] = acc;
}

#endif

#ifdef EROSION_TOTALS

// Sum of the rows of slot `slot` in row order (the core's SumRows).
double SumRows(uint slot)
{
  precise double total = 0.0LF;
  for (uint j = 0u; j < uNy; ++j)
  {
    total = total + rowSums[slot * uNy + j];
  }
  return total;
}

void main()
{
  if (Invocation() != 0u)
  {
    return;
  }
  if (uMode == 0u)
  {
    double before = SumRows(5u);
    double after = SumRows(6u);
    bool used = after > 0.0LF;
    control[0] = used ? terroirDiv(before, after) : 1.0LF;
    control[1] = used ? 1.0LF : 0.0LF;
  }
  else if (uMode == 1u)
  {
    precise double rain = control[2] + SumRows(0u);
    precise double evaporated = control[3] + SumRows(7u);
    precise double toSea = control[4] + SumRows(1u);
    precise double clamped = control[5] + SumRows(2u);
    precise double eroded = control[6] + SumRows(3u);
    precise double deposited = SumRows(4u) + SumRows(8u);
    precise double allDeposited = control[7] + deposited;
    control[2] = rain;
    control[3] = evaporated;
    control[4] = toSea;
    control[5] = clamped;
    control[6] = eroded;
    control[7] = allDeposited;
    control[8] = control[0];
  }
  else
  {
    double excess = 0.0LF;
    for (uint j = 0u; j < uNy; ++j)
    {
      excess = MaxD(excess, rowSums[9u * uNy + j]);
    }
    precise double moved = control[9] + SumRows(10u);
    control[9] = moved;
    control[10] = excess;
  }
}

#endif

#include "WaterFlow.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace terroir
{
namespace hydrology
{

namespace
{
/// Height given to an outlet cell that has no valid neighbour: nothing can flow onto it.
constexpr float kUnreachable = 1.0e30f;

/// Row buffers of giver states, one cell of zeros on each side so that column -1 and nx + 2
/// (the neighbours of the border columns) read as "gives nothing".
struct GiverRow
{
  std::vector<double> level;
  std::vector<double> scale;
  std::vector<double> out;
  void Resize(std::size_t n)
  {
    level.assign(n, 0.0);
    scale.assign(n, 0.0);
    out.assign(n, 0.0);
  }
};

/// What the giver in `row` at column slot `s` sends to a receiver at absolute height `h`.
inline double Sent(const GiverRow& row, std::size_t s, double closeness, double h)
{
  // The giver's own expression (WaterFlowEvacuation), branch-free: scale * c * max(0, drop).
  return row.scale[s] * closeness * std::max(0.0, row.level[s] - h);
}
} // namespace

//------------------------------------------------------------------------------
const char* WaterFlowStopReasonName(WaterFlowStopReason reason)
{
  switch (reason)
  {
    case WaterFlowStopReason::AutoStop:
      return "AutoStop";
    case WaterFlowStopReason::NoMovement:
      return "NoMovement";
    case WaterFlowStopReason::MaximumIterations:
      return "MaximumIterations";
  }
  return "Unknown";
}

//------------------------------------------------------------------------------
WaterFlowSimulation::WaterFlowSimulation(const GridView<float>& terrain, const double* waterMetres)
  : NX(terrain.nx)
  , NY(terrain.ny)
{
  if (NX <= 0 || NY <= 0 || !terrain.data || !waterMetres)
  {
    throw std::invalid_argument("water flow: empty terrain");
  }
  const int stride = NX + 2;
  const std::size_t padded = static_cast<std::size_t>(stride) * static_cast<std::size_t>(NY + 2);
  this->Terrain.assign(padded, kUnreachable);
  this->IsCell.assign(padded, 0);
  this->Water.assign(padded, 0.0);
  this->DischargeDepth.assign(padded, 0.0);
  auto at = [stride](int i, int j) -> std::size_t
  {
    return static_cast<std::size_t>(j + 1) * static_cast<std::size_t>(stride) +
      static_cast<std::size_t>(i + 1);
  };
  auto valid = [&terrain](int i, int j) -> bool
  {
    return i >= 0 && j >= 0 && i < terrain.nx && j < terrain.ny && terrain.IsValid(i, j) &&
      std::isfinite(terrain.At(i, j));
  };

  // Spacing per padded row (the border rows copy their neighbour row) and areas.
  this->Area.assign(static_cast<std::size_t>(NY + 2), 0.0);
  std::vector<double> dx(NY + 2);
  std::vector<double> dy(NY + 2);
  double dmin = std::numeric_limits<double>::infinity();
  for (int r = 0; r < NY + 2; ++r)
  {
    const int j = std::min(std::max(r - 1, 0), NY - 1);
    dx[r] = terrain.DxAt(j);
    dy[r] = terrain.DyAt(j);
    if (!(std::isfinite(dx[r]) && dx[r] > 0.0 && std::isfinite(dy[r]) && dy[r] > 0.0))
    {
      throw std::invalid_argument(
        "water flow: spacing of row " + std::to_string(j) + " is not a positive number");
    }
    this->Area[r] = dx[r] * dy[r];
    dmin = std::min(dmin, std::min(dx[r], dy[r]));
  }
  this->CloseEW.assign(NY + 2, 0.0);
  this->CloseNS.assign(NY + 2, 0.0);
  this->CloseDiag.assign(NY + 2, 0.0);
  for (int r = 0; r < NY + 2; ++r)
  {
    const int r1 = std::min(r + 1, NY + 1);
    const double mx = 0.5 * (dx[r] + dx[r1]);
    const double my = 0.5 * (dy[r] + dy[r1]);
    this->CloseEW[r] = dmin / dx[r];
    this->CloseNS[r] = dmin / my;
    this->CloseDiag[r] = dmin / std::sqrt(mx * mx + my * my);
  }

  // Terrain, water, initial volume.
  for (int j = 0; j < NY; ++j)
  {
    for (int i = 0; i < NX; ++i)
    {
      const std::size_t c = at(i, j);
      if (!valid(i, j))
      {
        continue;
      }
      const double w = waterMetres[terrain.Index(i, j)];
      if (!(std::isfinite(w) && w >= 0.0))
      {
        throw std::invalid_argument("water flow: water depth " + std::to_string(w) +
          " m at cell (" + std::to_string(i) + ", " + std::to_string(j) +
          ") is negative or not a number");
      }
      this->Terrain[c] = terrain.At(i, j);
      this->IsCell[c] = 1;
      this->Water[c] = w;
      this->Initial += w * this->Area[j + 1];
    }
  }
  // Outlets: no-data cells take the lowest valid neighbour; border cells continue the slope.
  static const int di[8] = { 1, 1, 0, -1, -1, -1, 0, 1 };
  static const int dj[8] = { 0, 1, 1, 1, 0, -1, -1, -1 };
  auto lowestValidNeighbour = [&](int i, int j) -> float
  {
    float m = kUnreachable;
    for (int k = 0; k < 8; ++k)
    {
      if (valid(i + di[k], j + dj[k]))
      {
        m = std::min(m, terrain.At(i + di[k], j + dj[k]));
      }
    }
    return m;
  };
  for (int j = -1; j <= NY; ++j)
  {
    for (int i = -1; i <= NX; ++i)
    {
      const bool border = i < 0 || j < 0 || i >= NX || j >= NY;
      if (!border && valid(i, j))
      {
        continue;
      }
      float h = lowestValidNeighbour(i, j);
      if (border)
      {
        // The inward direction (towards the grid), one step for the edge cell, two for the
        // cell after it.
        const int si = i < 0 ? 1 : (i >= NX ? -1 : 0);
        const int sj = j < 0 ? 1 : (j >= NY ? -1 : 0);
        const int ei = i + si;
        const int ej = j + sj;
        if (valid(ei, ej))
        {
          const float te = terrain.At(ei, ej);
          h = valid(ei + si, ej + sj) ? 2.0f * te - terrain.At(ei + si, ej + sj) : te;
        }
      }
      this->Terrain[at(i, j)] = h;
    }
  }
  this->NextWater = this->Water;
  this->RowMoved.assign(NY, 0.0);
  this->RowOutflow.assign(NY, 0.0);
}

//------------------------------------------------------------------------------
void WaterFlowSimulation::RowBlock(int begin, int end)
{
  const int stride = NX + 2;
  const std::size_t width = static_cast<std::size_t>(stride) + 2;
  GiverRow rows[3];
  GiverRow zero; // beyond the southern and northern border rows
  for (auto& r : rows)
  {
    r.Resize(width);
  }
  zero.Resize(width);
  const float* T = this->Terrain.data();
  const double* W = this->Water.data();
  const std::uint8_t* isCell = this->IsCell.data();
  double* next = this->NextWater.data();
  double* discharge = this->DischargeDepth.data();

  // Fills `g` with the givers of padded row r (all zero on the border rows and columns).
  auto givers = [&](int r, GiverRow& g)
  {
    if (r <= 0 || r >= NY + 1)
    {
      std::fill(g.scale.begin(), g.scale.end(), 0.0);
      std::fill(g.out.begin(), g.out.end(), 0.0);
      std::fill(g.level.begin(), g.level.end(), 0.0);
      return;
    }
    const double close[8] = { CloseEW[r],
      CloseDiag[r],
      CloseNS[r],
      CloseDiag[r],
      CloseEW[r],
      CloseDiag[r - 1],
      CloseNS[r - 1],
      CloseDiag[r - 1] };
    const std::ptrdiff_t s = stride;
    const std::ptrdiff_t off[8] = { 1, s + 1, s, s - 1, -1, -s - 1, -s, -s + 1 };
    const std::size_t row0 = static_cast<std::size_t>(r) * static_cast<std::size_t>(stride);
    for (int pi = 1; pi <= NX; ++pi)
    {
      const std::size_t c = row0 + static_cast<std::size_t>(pi);
      WaterFlowGiver v;
      if (W[c] > 0.0)
      {
        double h[8];
        for (int k = 0; k < 8; ++k)
        {
          const std::size_t n = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(c) + off[k]);
          h[k] = T[n] + W[n];
        }
        v = WaterFlowEvacuation(T[c], W[c], h, close);
      }
      g.level[pi + 1] = v.level;
      g.scale[pi + 1] = v.scale;
      g.out[pi + 1] = v.out;
    }
  };

  // Gathers padded row r (interior rows update water; outlets add to the outflow).
  auto gather = [&](int r,
                  const GiverRow& south,
                  const GiverRow& mid,
                  const GiverRow& north,
                  double& moved,
                  double& outflow)
  {
    const double cEW = CloseEW[r];
    const double cN = CloseNS[r];
    const double cNE = CloseDiag[r];
    const double cS = r > 0 ? CloseNS[r - 1] : 0.0;
    const double cSE = r > 0 ? CloseDiag[r - 1] : 0.0;
    // Volume sent from a neighbouring row becomes depth here through the area ratio.
    const double fromNorth = r + 1 < NY + 2 ? Area[r + 1] / Area[r] : 0.0;
    const double fromSouth = r > 0 ? Area[r - 1] / Area[r] : 0.0;
    const std::size_t row0 = static_cast<std::size_t>(r) * static_cast<std::size_t>(stride);
    const bool interior = r >= 1 && r <= NY;
    double rowOut = 0.0;
    double rowIn = 0.0;
    for (int pi = 0; pi < stride; ++pi)
    {
      const std::size_t c = row0 + static_cast<std::size_t>(pi);
      const std::size_t s = static_cast<std::size_t>(pi) + 1; // slot of this column
      const double h = T[c] + W[c];
      const double inRow = Sent(mid, s - 1, cEW, h) + Sent(mid, s + 1, cEW, h);
      const double inNorth =
        Sent(north, s - 1, cNE, h) + Sent(north, s, cN, h) + Sent(north, s + 1, cNE, h);
      const double inSouth =
        Sent(south, s - 1, cSE, h) + Sent(south, s, cS, h) + Sent(south, s + 1, cSE, h);
      const double in = inRow + fromNorth * inNorth + fromSouth * inSouth;
      if (interior && isCell[c])
      {
        const double out = mid.out[s];
        next[c] = std::max(0.0, W[c] - out + in);
        discharge[c] += out;
        rowOut += out;
      }
      else
      {
        next[c] = 0.0;
        rowIn += in;
      }
    }
    moved += rowOut * Area[r];
    outflow += rowIn * Area[r];
  };

  // Ring of three giver rows: padded rows r - 1, r, r + 1 for interior row r = j + 1.
  int slot[3] = { 0, 1, 2 };
  givers(begin, rows[slot[0]]);
  givers(begin + 1, rows[slot[1]]);
  for (int j = begin; j < end; ++j)
  {
    const int r = j + 1;
    givers(r + 1, rows[slot[2]]);
    double moved = 0.0;
    double outflow = 0.0;
    if (r == 1)
    {
      // The southern border row gathers from row 1 only.
      gather(0, zero, rows[slot[0]], rows[slot[1]], moved, outflow);
    }
    gather(r, rows[slot[0]], rows[slot[1]], rows[slot[2]], moved, outflow);
    if (r == NY)
    {
      gather(NY + 1, rows[slot[1]], rows[slot[2]], zero, moved, outflow);
    }
    this->RowMoved[j] = moved;
    this->RowOutflow[j] = outflow;
    std::rotate(slot, slot + 1, slot + 3);
  }
}

//------------------------------------------------------------------------------
WaterFlowIteration WaterFlowSimulation::Step()
{
  auto body = [this](int b, int e) { this->RowBlock(b, e); };
  if (this->Parallel)
  {
    this->Parallel(0, NY, body);
  }
  else
  {
    body(0, NY);
  }
  WaterFlowIteration it;
  for (int j = 0; j < NY; ++j)
  {
    it.moved += this->RowMoved[j];
    it.outflow += this->RowOutflow[j];
  }
  this->Water.swap(this->NextWater);
  this->RecordIteration(it);
  return it;
}

//------------------------------------------------------------------------------
void WaterFlowSimulation::RecordIteration(const WaterFlowIteration& it)
{
  ++this->IterationCount;
  this->Moved.push_back(it.moved);
  this->Outflow.push_back(it.outflow);
  this->MovedTotal += it.moved;
  this->OutflowTotal += it.outflow;
}

//------------------------------------------------------------------------------
WaterFlowStopReason WaterFlowSimulation::Run(const WaterFlowStopRule& rule)
{
  if (rule.maximumIterations < 0 || !(rule.autoStopRatio >= 0.0))
  {
    throw std::invalid_argument("water flow: negative iteration limit or stop ratio");
  }
  while (this->IterationCount < rule.maximumIterations)
  {
    const double before = this->MovedTotal;
    const WaterFlowIteration it = this->Step();
    if (it.moved <= 0.0)
    {
      return WaterFlowStopReason::NoMovement;
    }
    if (WaterFlowAutoStop(it.moved, before, rule.autoStopRatio))
    {
      return WaterFlowStopReason::AutoStop;
    }
  }
  return WaterFlowStopReason::MaximumIterations;
}

//------------------------------------------------------------------------------
double WaterFlowSimulation::StoredVolume() const
{
  const int stride = NX + 2;
  double total = 0.0;
  for (int r = 1; r <= NY; ++r)
  {
    double row = 0.0;
    for (int pi = 1; pi <= NX; ++pi)
    {
      row += this->Water[static_cast<std::size_t>(r) * stride + pi];
    }
    total += row * this->Area[r];
  }
  return total;
}

//------------------------------------------------------------------------------
void WaterFlowSimulation::GetWaterDepth(float* depth) const
{
  const int stride = NX + 2;
  for (int j = 0; j < NY; ++j)
  {
    for (int i = 0; i < NX; ++i)
    {
      const std::size_t c = static_cast<std::size_t>(j + 1) * stride + (i + 1);
      depth[static_cast<std::size_t>(j) * NX + i] = this->IsCell[c]
        ? static_cast<float>(this->Water[c])
        : std::numeric_limits<float>::quiet_NaN();
    }
  }
}

//------------------------------------------------------------------------------
void WaterFlowSimulation::GetDischarge(double* discharge) const
{
  const int stride = NX + 2;
  for (int j = 0; j < NY; ++j)
  {
    for (int i = 0; i < NX; ++i)
    {
      const std::size_t c = static_cast<std::size_t>(j + 1) * stride + (i + 1);
      discharge[static_cast<std::size_t>(j) * NX + i] = this->IsCell[c]
        ? this->DischargeDepth[c] * this->Area[j + 1]
        : std::numeric_limits<double>::quiet_NaN();
    }
  }
}

//------------------------------------------------------------------------------
void WaterFlowSimulation::TruncateHistory(long long iterations)
{
  if (iterations < 0 || iterations > this->IterationCount)
  {
    throw std::invalid_argument("water flow: cannot go back to iteration " +
      std::to_string(iterations) + " of " + std::to_string(this->IterationCount));
  }
  this->Moved.resize(static_cast<std::size_t>(iterations));
  this->Outflow.resize(static_cast<std::size_t>(iterations));
  this->IterationCount = iterations;
  this->MovedTotal = 0.0;
  this->OutflowTotal = 0.0;
  for (std::size_t k = 0; k < this->Moved.size(); ++k)
  {
    this->MovedTotal += this->Moved[k];
    this->OutflowTotal += this->Outflow[k];
  }
}

//------------------------------------------------------------------------------
bool WaterFlowSimulation::FindStop(const WaterFlowStopRule& rule,
  long long& iteration,
  WaterFlowStopReason& reason) const
{
  double before = 0.0;
  for (std::size_t k = 0; k < this->Moved.size(); ++k)
  {
    if (static_cast<long long>(k) >= rule.maximumIterations)
    {
      break;
    }
    const double moved = this->Moved[k];
    if (moved <= 0.0 || WaterFlowAutoStop(moved, before, rule.autoStopRatio))
    {
      iteration = static_cast<long long>(k) + 1;
      reason = moved <= 0.0 ? WaterFlowStopReason::NoMovement : WaterFlowStopReason::AutoStop;
      return true;
    }
    before += moved;
  }
  if (static_cast<long long>(this->Moved.size()) >= rule.maximumIterations)
  {
    iteration = rule.maximumIterations;
    reason = WaterFlowStopReason::MaximumIterations;
    return true;
  }
  return false;
}

} // namespace hydrology
} // namespace terroir

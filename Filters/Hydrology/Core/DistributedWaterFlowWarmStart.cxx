#include "DistributedWaterFlowWarmStart.h"

#include "DistributedTiles.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace terroir
{
namespace hydrology
{

using namespace tiles;

namespace
{
constexpr const char* kName = "WaterFlowWarmStartDistributed";

/// The serial warm start's rule of a cell with data (WaterFlowWarmStart.cxx): mask and a
/// finite height.
bool CellHasData(const GridView<float>& g, std::size_t c)
{
  return (!g.valid || g.valid[c]) && std::isfinite(g.data[c]);
}

/// True when the warm start adds a coarser level to a level of nx x ny cells.
bool AddsLevel(int nx, int ny, int coarsestSide)
{
  return std::min((nx + 1) / 2, (ny + 1) / 2) >= coarsestSide;
}

/// The owned box of the coarser level: coarse cell (i, j) belongs to the owner of fine cell
/// (2i, 2j), so [a, b] becomes [ceil(a / 2), floor(b / 2)] per axis (empty stays empty).
TileBox Halve(const TileBox& b)
{
  if (b.Cells() == 0)
  {
    return TileBox();
  }
  return TileBox{ (b.i0 + 1) / 2, b.i1 / 2, (b.j0 + 1) / 2, b.j1 / 2 };
}

/// Reach of the coarser level. The fine cells within r of the owned box [a, b] read coarse
/// cells floor((a - r) / 2) .. floor((b + r) / 2); the coarse owned box is [ceil(a / 2),
/// floor(b / 2)], so they lie within floor(r / 2) + 1 of it (a odd: ceil(a / 2) -
/// floor((a - r) / 2) = floor(r / 2) + 1; the upper side needs ceil(r / 2) at most). The
/// simulation needs 2 (a cell's new depth reads its neighbours' flows).
int CoarseReach(int r)
{
  return std::max(2, r / 2 + 1);
}

/// One level as this process holds it.
struct Level
{
  GridView<float> view; ///< the held cells (owned box grown by at least reach + 1)
  int gi0 = 0;          ///< whole-level column of view cell (0, 0)
  int gj0 = 0;          ///< whole-level row of view cell (0, 0)
  int nx = 0;           ///< columns of the whole level
  int ny = 0;           ///< rows of the whole level
  std::vector<TileBox> owned;
  std::vector<int> reach;
  int rank = 0;
  const double* rain = nullptr; ///< view-sized rain field, or null (uniform rain)

  const TileBox& Mine() const { return this->owned[static_cast<std::size_t>(this->rank)]; }
  int Reach() const { return this->reach[static_cast<std::size_t>(this->rank)]; }
  int MaxReach() const { return *std::max_element(this->reach.begin(), this->reach.end()); }
  std::size_t At(int gi, int gj) const { return this->view.Index(gi - this->gi0, gj - this->gj0); }
  /// The cells within reach of the owned box (clipped to the level).
  TileBox Near() const { return Grow(this->Mine(), this->Reach(), this->nx, this->ny); }
  /// This tile as the distributed fill and ExchangeRing take it, with ring `ring`.
  DistributedFillInput Input(int ring) const
  {
    DistributedFillInput in;
    in.view = this->view;
    in.gi0 = this->gi0;
    in.gj0 = this->gj0;
    in.owned = this->Mine();
    in.wholeNx = this->nx;
    in.wholeNy = this->ny;
    in.reach = ring;
    return in;
  }
};

/// A coarse level and the arrays behind its view.
struct CoarseLevel
{
  Level level;
  std::vector<float> z;
  std::vector<std::uint8_t> valid;
  std::vector<double> rowDx, rowDy, rain;
};

/// What a coarse cell's owner sends to the tiles whose ring holds it (floats as doubles).
struct CoarseCell
{
  double z = 0.0;
  double rain = 0.0;
  double dx = 0.0; ///< its row's spacing
  double dy = 0.0;
  std::uint8_t valid = 0;
};

/// WaterFlowWarmStart.cxx's BlockMean on the whole-level indices of `fine`: the mean of
/// `values` over the cells with data of coarse cell (i, j)'s block, in the same order.
template<typename T>
bool BlockMean(const Level& fine, const T* values, int i, int j, double& mean)
{
  double sum = 0.0;
  int count = 0;
  for (int fj = 2 * j; fj < std::min(2 * j + 2, fine.ny); ++fj)
  {
    for (int fi = 2 * i; fi < std::min(2 * i + 2, fine.nx); ++fi)
    {
      const std::size_t c = fine.At(fi, fj);
      if (CellHasData(fine.view, c))
      {
        sum += values[c];
        ++count;
      }
    }
  }
  mean = count > 0 ? sum / count : 0.0;
  return count > 0;
}

enum class Reduction
{
  Sum, ///< added over the ranks in rank order, from 0.0
  Min
};

/**
 * Every rank's `values` reduced elementwise over the ranks, through rank 0 (a collective
 * call); `problem` non-empty on any rank: every rank throws std::invalid_argument with the
 * first failed rank's problem instead.
 */
std::vector<double> AllReduce(TileExchange& exchange,
  const std::string& problem,
  const std::vector<double>& values,
  Reduction op)
{
  Writer w;
  w.Put<std::uint8_t>(problem.empty() ? 0 : 1);
  w.PutString(problem);
  w.PutVector(values);
  const std::vector<std::vector<char>> all = exchange.Gather(w.Bytes);
  std::vector<std::vector<char>> replies;
  if (exchange.Rank() == 0)
  {
    try
    {
      std::vector<double> total(
        values.size(), op == Reduction::Sum ? 0.0 : std::numeric_limits<double>::infinity());
      std::string why;
      for (std::size_t t = 0; t < all.size(); ++t)
      {
        Reader r(all[t]);
        const bool failed = r.Get<std::uint8_t>() != 0;
        const std::string message = r.GetString();
        const std::vector<double> v = r.GetVector<double>();
        if (failed && why.empty())
        {
          why = "rank " + std::to_string(t) + ": " + message;
        }
        if (v.size() != total.size())
        {
          throw std::runtime_error("the ranks reduce vectors of different sizes");
        }
        for (std::size_t e = 0; e < v.size(); ++e)
        {
          total[e] = op == Reduction::Sum ? total[e] + v[e] : std::min(total[e], v[e]);
        }
      }
      if (!why.empty())
      {
        throw std::runtime_error(why);
      }
      Writer reply;
      reply.Put<std::uint8_t>(0);
      reply.PutVector(total);
      replies.assign(all.size(), reply.Bytes);
    }
    catch (const std::exception& x)
    {
      replies = FailAll(exchange.Size(), x.what());
    }
  }
  const std::vector<char> mine = exchange.Scatter(replies);
  Reader r(mine);
  CheckStatus(r, kName);
  return r.GetVector<double>();
}

/// Why this rank cannot start ("" when it can): options, sizes, reaches, its view's ring.
std::string CheckLocal(const WaterFlowWarmStartTile& tile,
  const double* water,
  const WaterFlowWarmStartOptions& options,
  int rank,
  int ranks)
{
  if (options.coarsestSide < 2 || options.settleIterations < 0 ||
    !(options.rule.balanceTolerance > 0.0 && options.rule.balanceTolerance < 1.0) ||
    options.rule.maximumIterations < 0)
  {
    return "water flow warm start: the coarsest side must be >= 2, the settling count >= 0, "
           "the balance tolerance in (0, 1)";
  }
  if (tile.owned.size() != static_cast<std::size_t>(ranks) ||
    tile.reach.size() != tile.owned.size())
  {
    return "the tile lists " + std::to_string(tile.owned.size()) + " owned boxes and " +
      std::to_string(tile.reach.size()) + " reaches for " + std::to_string(ranks) + " ranks";
  }
  for (std::size_t p = 0; p < tile.reach.size(); ++p)
  {
    if (tile.reach[p] < 2)
    {
      return "the reach of rank " + std::to_string(p) + " is " + std::to_string(tile.reach[p]) +
        ", it must be >= 2";
    }
  }
  if (!water)
  {
    return "no water array";
  }
  DistributedFillInput in;
  in.view = tile.view;
  in.gi0 = tile.gi0;
  in.gj0 = tile.gj0;
  in.owned = tile.owned[static_cast<std::size_t>(rank)];
  in.wholeNx = tile.wholeNx;
  in.wholeNy = tile.wholeNy;
  in.reach = tile.reach[static_cast<std::size_t>(rank)] + 1;
  return CheckTile(in);
}

/// Collective: every rank's tile checked, and (rank 0) that all see the same grid, boxes,
/// reaches, kind of rain and rows, that the boxes partition the grid and that every level
/// keeps every tile non-empty. Throws std::invalid_argument on every rank alike otherwise.
void CheckStart(const WaterFlowWarmStartTile& tile,
  const double* water,
  const double* rainField,
  const WaterFlowWarmStartOptions& options,
  TileExchange& exchange)
{
  const int ranks = exchange.Size();
  const std::string problem = CheckLocal(tile, water, options, exchange.Rank(), ranks);
  Writer w;
  w.Put<std::uint8_t>(problem.empty() ? 0 : 1);
  w.PutString(problem);
  w.Put<std::int32_t>(tile.wholeNx);
  w.Put<std::int32_t>(tile.wholeNy);
  w.PutVector(tile.owned);
  w.PutVector(std::vector<std::int32_t>(tile.reach.begin(), tile.reach.end()));
  w.Put<std::uint8_t>(rainField ? 1 : 0);
  w.Put<std::uint8_t>(tile.view.rowDx ? 1 : 0);
  w.Put<std::uint8_t>(tile.view.rowDy ? 1 : 0);
  const std::vector<std::vector<char>> all = exchange.Gather(w.Bytes);
  std::vector<std::vector<char>> replies;
  if (exchange.Rank() == 0)
  {
    try
    {
      std::vector<char> first; // rank 0's view of the whole, after its status
      for (int t = 0; t < ranks; ++t)
      {
        Reader r(all.at(static_cast<std::size_t>(t)));
        const bool failed = r.Get<std::uint8_t>() != 0;
        const std::string message = r.GetString();
        if (failed)
        {
          throw std::runtime_error("rank " + std::to_string(t) + ": " + message);
        }
        const std::size_t head = 1 + sizeof(std::uint64_t) + message.size();
        const std::vector<char> rest(
          all[t].begin() + static_cast<std::ptrdiff_t>(head), all[t].end());
        if (t == 0)
        {
          first = rest;
        }
        else if (rest != first)
        {
          throw std::runtime_error("rank " + std::to_string(t) +
            " sees another grid, other tiles or reaches, or another kind of rain or rows than "
            "rank 0");
        }
      }
      const std::string why = CheckPartition(tile.owned, tile.wholeNx, tile.wholeNy);
      if (!why.empty())
      {
        throw std::runtime_error(why);
      }
      if (!WaterFlowWarmStartFitsTiles(tile.owned, tile.wholeNx, tile.wholeNy, options))
      {
        throw std::runtime_error("a coarse level of at least " +
          std::to_string(options.coarsestSide) + " cells a side would leave a tile empty");
      }
      Writer ok;
      ok.Put<std::uint8_t>(0);
      replies.assign(static_cast<std::size_t>(ranks), ok.Bytes);
    }
    catch (const std::exception& x)
    {
      replies = FailAll(ranks, x.what());
    }
  }
  const std::vector<char> mine = exchange.Scatter(replies);
  Reader r(mine);
  CheckStatus(r, kName);
}

/// The coarser level's geometry: its size, owned boxes, reaches and this tile's held box
/// (owned grown by reach + 1) as the view's origin and size (no data yet).
Level CoarseGeometry(const Level& fine)
{
  Level L;
  L.nx = (fine.nx + 1) / 2;
  L.ny = (fine.ny + 1) / 2;
  L.rank = fine.rank;
  for (std::size_t p = 0; p < fine.owned.size(); ++p)
  {
    L.owned.push_back(Halve(fine.owned[p]));
    L.reach.push_back(CoarseReach(fine.reach[p]));
  }
  const TileBox held = Grow(L.Mine(), L.Reach() + 1, L.nx, L.ny);
  L.gi0 = held.i0;
  L.gj0 = held.j0;
  L.view.nx = held.i1 - held.i0 + 1;
  L.view.ny = held.j1 - held.j0 + 1;
  return L;
}

/// The owned cells of coarse level `L` from `fine` (WaterFlowCoarsen's arithmetic), in a
/// held-sized array.
std::vector<CoarseCell> OwnedCoarseCells(const Level& fine, const Level& L)
{
  std::vector<CoarseCell> cells(L.view.Size());
  const TileBox& o = L.Mine();
  for (int j = o.j0; j <= o.j1; ++j)
  {
    const int a = 2 * j - fine.gj0;
    const int b = std::min(2 * j + 1, fine.ny - 1) - fine.gj0;
    const double dx = fine.view.DxAt(a) + fine.view.DxAt(b); // two columns at the rows' mean
    const double dy = fine.view.DyAt(a) + fine.view.DyAt(b);
    for (int i = o.i0; i <= o.i1; ++i)
    {
      CoarseCell& cell = cells[L.At(i, j)];
      double mean = 0.0;
      cell.valid = BlockMean(fine, fine.view.data, i, j, mean) ? 1 : 0;
      cell.z = static_cast<float>(mean);
      if (fine.rain)
      {
        BlockMean(fine, fine.rain, i, j, cell.rain);
      }
      cell.dx = dx;
      cell.dy = dy;
    }
  }
  return cells;
}

/// Step 1: the coarser level of `fine` into `c`: the owned cells computed, the ring of
/// reach + 1 from its owners; spacing per row only when the fine level has it.
void Coarsen(const Level& fine, CoarseLevel& c, TileExchange& exchange)
{
  Level& L = c.level;
  L = CoarseGeometry(fine);
  std::vector<CoarseCell> cells = OwnedCoarseCells(fine, L);
  ExchangeRing<CoarseCell>(
    L.Input(L.Reach() + 1), L.MaxReach() + 1, cells.data(), CoarseCell(), exchange, nullptr, kName);
  for (const CoarseCell& cell : cells)
  {
    c.z.push_back(static_cast<float>(cell.z));
    c.valid.push_back(cell.valid);
    if (fine.rain)
    {
      c.rain.push_back(cell.rain);
    }
  }
  const std::size_t hnx = static_cast<std::size_t>(L.view.nx);
  for (std::size_t r = 0; (fine.view.rowDx || fine.view.rowDy) && r < cells.size() / hnx; ++r)
  {
    c.rowDx.push_back(cells[r * hnx].dx);
    c.rowDy.push_back(cells[r * hnx].dy);
  }
  L.rain = fine.rain ? c.rain.data() : nullptr;
  L.view.data = c.z.data();
  L.view.valid = c.valid.data();
  L.view.dx = 2.0 * fine.view.dx;
  L.view.dy = 2.0 * fine.view.dy;
  L.view.rowDx = fine.view.rowDx ? c.rowDx.data() : nullptr;
  L.view.rowDy = fine.view.rowDy ? c.rowDy.data() : nullptr;
}

/// Step 2: the still water of the level within reach of the owned cells (the distributed
/// Priority-Flood's depth; 0 on no data and on the outer ring).
std::vector<double> StillWater(const Level& L, TileExchange& exchange)
{
  const DistributedFillResult fill =
    FillDepressionsDistributed(L.Input(L.Reach()), DepressionWaterBodyOptions(), exchange);
  std::vector<double> still(L.view.Size(), 0.0);
  for (std::size_t c = 0; c < still.size(); ++c)
  {
    if (CellHasData(L.view, c) && !std::isnan(fill.filled[c]))
    {
      still[c] =
        std::max(0.0, static_cast<double>(fill.filled[c]) - static_cast<double>(L.view.data[c]));
    }
  }
  return still;
}

/// Why refining `fine` from `coarse` could read a coarse cell outside the coarse reach ("" if
/// it cannot): the coarse cells of the fine cells within reach must lie within the coarse one.
std::string CheckRefinementReach(const Level& fine, const Level& coarse)
{
  const TileBox f = fine.Near();
  const TileBox need{ f.i0 / 2, f.i1 / 2, f.j0 / 2, f.j1 / 2 };
  const TileBox have = coarse.Near();
  if (need.i0 < have.i0 || need.i1 > have.i1 || need.j0 < have.j0 || need.j1 > have.j1)
  {
    return "the coarse level's reach " + std::to_string(coarse.Reach()) +
      " does not cover the refinement of the fine level's reach " + std::to_string(fine.Reach());
  }
  return std::string();
}

/// Step 3's run: the level's simulation with the whole level's smallest spacing and rain
/// totals, its count window and the iteration hook; failures on any rank thrown on all.
WaterFlowSimulation LevelSimulation(const Level& fine,
  const Level& L,
  const std::vector<double>& initial,
  double rain,
  TileExchange& exchange)
{
  const double dmin = AllReduce(
    exchange, std::string(), { WaterFlowSimulation::SmallestSpacing(L.view) }, Reduction::Min)[0];
  std::string problem = CheckRefinementReach(fine, L);
  std::vector<double> totals{ 0.0, 0.0 };
  std::unique_ptr<WaterFlowSimulation> sim;
  try
  {
    sim.reset(new WaterFlowSimulation(L.view, initial.data(), dmin));
    const TileBox& o = L.Mine();
    sim->SetCountWindow(o.i0 == 0 ? 0 : o.i0 - L.gi0 + 1,
      o.i1 == L.nx - 1 ? L.view.nx + 2 : o.i1 - L.gi0 + 2,
      o.j0 == 0 ? 0 : o.j0 - L.gj0 + 1,
      o.j1 == L.ny - 1 ? L.view.ny + 2 : o.j1 - L.gj0 + 2);
    if (L.rain)
    {
      sim->SetRainField(L.rain);
    }
    else
    {
      sim->SetRain(rain);
    }
    sim->WindowRainTotals(totals[0], totals[1]);
  }
  catch (const std::invalid_argument& e)
  {
    problem = e.what();
  }
  totals = AllReduce(exchange, problem, totals, Reduction::Sum);
  sim->SetRainTotals(totals[0], totals[1]);

  // The padded water as ExchangeRing's view: padded cell (0, 0) is held cell (-1, -1).
  DistributedFillInput padded = L.Input(L.Reach());
  padded.view.nx = L.view.nx + 2;
  padded.view.ny = L.view.ny + 2;
  padded.gi0 = L.gi0 - 1;
  padded.gj0 = L.gj0 - 1;
  const int width = L.MaxReach();
  sim->SetIterationHook(
    [&exchange, padded, width](WaterFlowSimulation& s, WaterFlowIteration& it)
    {
      ExchangeRing<double>(padded, width, s.PaddedWater().data(), 0.0, exchange, nullptr, kName);
      const std::vector<double> sums =
        AllReduce(exchange, std::string(), { it.moved, it.outflow, it.emptied }, Reduction::Sum);
      it.moved = sums[0];
      it.outflow = sums[1];
      it.emptied = sums[2];
    });
  return std::move(*sim);
}

/// Step 4: the fine still water plus twice the coarse flowing water, on the fine view's cells
/// with data whose coarse cell is held (CheckRefinementReach: all within the fine reach).
void Refine(const Level& fine,
  const Level& coarse,
  const std::vector<double>& still,
  WaterFlowSimulation& sim,
  double* water)
{
  const std::vector<double>& w = sim.PaddedWater();
  const std::size_t stride = static_cast<std::size_t>(sim.Stride());
  const TileBox held{
    coarse.gi0, coarse.gi0 + coarse.view.nx - 1, coarse.gj0, coarse.gj0 + coarse.view.ny - 1
  };
  for (int vj = 0; vj < fine.view.ny; ++vj)
  {
    for (int vi = 0; vi < fine.view.nx; ++vi)
    {
      const std::size_t c = fine.view.Index(vi, vj);
      const int ci = (vi + fine.gi0) / 2;
      const int cj = (vj + fine.gj0) / 2;
      if (!CellHasData(fine.view, c) || !held.Contains(ci, cj))
      {
        continue;
      }
      const std::size_t cc = coarse.At(ci, cj);
      const double depth = w[static_cast<std::size_t>(cj - coarse.gj0 + 1) * stride +
        static_cast<std::size_t>(ci - coarse.gi0 + 1)];
      water[c] += 2.0 * std::max(0.0, depth - still[cc]);
    }
  }
}

/// The levels below `fine` (WaterFlowWarmStart's recursion), refined into `water`.
std::vector<WaterFlowWarmStartLevel> Descend(const Level& fine,
  double* water,
  double rain,
  const WaterFlowWarmStartOptions& options,
  TileExchange& exchange,
  const WaterFlowLevelRun& run)
{
  std::vector<WaterFlowWarmStartLevel> levels;
  if (!AddsLevel(fine.nx, fine.ny, options.coarsestSide))
  {
    return levels;
  }
  CoarseLevel coarse;
  Coarsen(fine, coarse, exchange);
  const Level& L = coarse.level;
  const std::vector<double> still = StillWater(L, exchange);
  std::vector<double> initial = still;
  levels = Descend(L, initial.data(), rain, options, exchange, run);

  WaterFlowSimulation sim = LevelSimulation(fine, L, initial, rain, exchange);
  WaterFlowStopRule rule = options.rule;
  rule.balanceAfter = levels.empty() ? 0 : options.settleIterations;
  WaterFlowWarmStartLevel level;
  level.nx = L.nx;
  level.ny = L.ny;
  level.reason = run ? run(sim, rule) : sim.Run(rule);
  level.iterations = sim.Iterations();
  levels.push_back(level);
  Refine(fine, L, still, sim, water);
  return levels;
}
} // namespace

//------------------------------------------------------------------------------
bool WaterFlowWarmStartFitsTiles(const std::vector<TileBox>& owned,
  int wholeNx,
  int wholeNy,
  const WaterFlowWarmStartOptions& options)
{
  if (options.coarsestSide < 2)
  {
    throw std::invalid_argument(
      "WaterFlowWarmStartFitsTiles: the coarsest side must be >= 2, not " +
      std::to_string(options.coarsestSide));
  }
  std::vector<TileBox> boxes = owned;
  int nx = wholeNx;
  int ny = wholeNy;
  while (AddsLevel(nx, ny, options.coarsestSide))
  {
    nx = (nx + 1) / 2;
    ny = (ny + 1) / 2;
    for (TileBox& b : boxes)
    {
      b = Halve(b);
      if (b.Cells() == 0)
      {
        return false;
      }
    }
  }
  return true;
}

//------------------------------------------------------------------------------
std::vector<WaterFlowWarmStartLevel> WaterFlowWarmStartDistributed(
  const WaterFlowWarmStartTile& tile,
  double* water,
  double rain,
  const double* rainField,
  const WaterFlowWarmStartOptions& options,
  TileExchange& exchange,
  const WaterFlowLevelRun& run)
{
  CheckStart(tile, water, rainField, options, exchange);
  Level fine;
  fine.view = tile.view;
  fine.gi0 = tile.gi0;
  fine.gj0 = tile.gj0;
  fine.nx = tile.wholeNx;
  fine.ny = tile.wholeNy;
  fine.owned = tile.owned;
  fine.reach = tile.reach;
  fine.rank = exchange.Rank();
  fine.rain = rainField;
  return Descend(fine, water, rain, options, exchange, run);
}

} // namespace hydrology
} // namespace terroir

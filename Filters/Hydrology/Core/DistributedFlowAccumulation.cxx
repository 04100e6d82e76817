#include "DistributedFlowAccumulation.h"

#include "DistributedTiles.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace terroir
{
namespace hydrology
{

const char* const kFlowAccumulationBarnes2017Citation =
  "Barnes, R. (2017). Parallel non-divergent flow accumulation for trillion cell digital "
  "elevation models on desktops or clusters. Environmental Modelling & Software 92:202-212. "
  "doi:10.1016/j.envsoft.2017.02.022";

using namespace tiles;

namespace
{
constexpr const char* kName = "D8FlowAccumulationDistributed";
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr std::int64_t kUnknown = -2;

/// A cell's whole-grid column and row from its view index.
struct Cell
{
  int gi;
  int gj;
};

Cell GlobalOf(const DistributedFillInput& in, std::size_t k)
{
  const auto nx = static_cast<std::size_t>(in.view.nx);
  return Cell{ in.gi0 + static_cast<int>(k % nx), in.gj0 + static_cast<int>(k / nx) };
}

/// Calls f(kk, gi, gj) for the 8-neighbours of view cell k that lie in the view.
template<typename F>
void ForNeighbours(const DistributedFillInput& in, std::size_t k, F f)
{
  const Cell c = GlobalOf(in, k);
  for (int e = 0; e < 8; ++e)
  {
    const int ii = c.gi - in.gi0 + kD8Di[e];
    const int jj = c.gj - in.gj0 + kD8Dj[e];
    if (ii >= 0 && jj >= 0 && ii < in.view.nx && jj < in.view.ny)
    {
      f(in.view.Index(ii, jj), c.gi + kD8Di[e], c.gj + kD8Dj[e]);
    }
  }
}

/// Calls f(k, gi, gj) for the owned cells, row by row (k the view index).
template<typename F>
void ForOwned(const DistributedFillInput& in, F f)
{
  const Tile tile(in);
  for (int gj = in.owned.j0; gj <= in.owned.j1 && in.owned.Cells() > 0; ++gj)
  {
    for (int gi = in.owned.i0; gi <= in.owned.i1; ++gi)
    {
      f(tile.ViewIndex(gi, gj), gi, gj);
    }
  }
}

/// The flats' breadth-first distances on the owned cells (D8FlowDirections' rule): 0 on the
/// draining cells next to a flat cell of equal W, and through flat cells of equal W from those
/// and from the distances `distance` holds on the ring. Owned entries are rewritten.
void OwnedFlatDistances(const DistributedFillInput& in,
  const float* w,
  const std::int8_t* dir,
  std::int32_t* distance)
{
  std::vector<std::pair<std::int32_t, std::size_t>> sources;
  ForOwned(in, [&](std::size_t k, int, int) { distance[k] = -1; });
  ForOwned(in,
    [&](std::size_t k, int, int)
    {
      if (dir[k] == kD8NoData)
      {
        return;
      }
      const bool flat = dir[k] == detail::kD8Unset;
      std::int32_t best = -1;
      ForNeighbours(in,
        k,
        [&](std::size_t kk, int ii, int jj)
        {
          if (w[kk] != w[k])
          {
            return;
          }
          if (!flat && dir[kk] == detail::kD8Unset)
          {
            best = 0; // a draining cell of a flat
          }
          else if (flat && !in.owned.Contains(ii, jj) && distance[kk] >= 0 &&
            (best < 0 || distance[kk] + 1 < best))
          {
            best = distance[kk] + 1; // reached from the ring
          }
        });
      if (best >= 0)
      {
        sources.emplace_back(best, k);
      }
    });
  std::sort(sources.begin(), sources.end());
  // Two queues in non-decreasing distance: the sorted sources and the search's FIFO.
  std::vector<std::pair<std::int32_t, std::size_t>> fifo;
  std::size_t s = 0;
  std::size_t head = 0;
  while (s < sources.size() || head < fifo.size())
  {
    const bool fromSources =
      head == fifo.size() || (s < sources.size() && sources[s].first <= fifo[head].first);
    const std::pair<std::int32_t, std::size_t> item = fromSources ? sources[s++] : fifo[head++];
    const std::size_t k = item.second;
    if (distance[k] >= 0)
    {
      continue;
    }
    distance[k] = item.first;
    ForNeighbours(in,
      k,
      [&](std::size_t kk, int ii, int jj)
      {
        if (in.owned.Contains(ii, jj) && dir[kk] == detail::kD8Unset && distance[kk] < 0 &&
          w[kk] == w[k])
        {
          fifo.emplace_back(item.first + 1, kk);
        }
      });
  }
}

/// The directions of the owned cells (D8FlowDirections' answer), the flats' distances agreed
/// with the other tiles; the owned counts in `summary`. Returns the number of exchanges.
int OwnedDirections(const DistributedFillInput& in,
  const float* w,
  std::int8_t* dir,
  TileExchange& exchange,
  D8Summary& summary)
{
  const std::size_t n = in.view.Size();
  for (std::size_t k = 0; k < n; ++k)
  {
    dir[k] = HasData(in.view, k) && !std::isnan(w[k]) ? detail::kD8Unset : kD8NoData;
  }
  std::size_t outlets = 0;
  detail::D8SteepestDescent(in.view, w, dir, {}, outlets);

  DistributedFillInput perimeter = in;
  perimeter.reach = 1;
  std::vector<std::int32_t> distance(n, -1);
  std::vector<std::int32_t> previous;
  int exchanges = 0;
  for (std::uint8_t changed = 1; changed;)
  {
    OwnedFlatDistances(in, w, dir, distance.data());
    std::vector<std::int32_t> band;
    ForOwned(in,
      [&](std::size_t k, int gi, int gj)
      {
        if (InBand(in.owned, gi, gj, 1, in.wholeNx, in.wholeNy))
        {
          band.push_back(distance[k]);
        }
      });
    changed = band != previous ? 1 : 0;
    previous = std::move(band);
    ExchangeRing<std::int32_t>(perimeter, 1, distance.data(), -1, exchange, &changed, kName);
    ++exchanges;
  }

  ForOwned(in,
    [&](std::size_t k, int gi, int gj)
    {
      if (dir[k] == detail::kD8Unset)
      {
        if (distance[k] < 0)
        {
          dir[k] = kD8Outlet; // a pit or closed flat: W was not depression-free
          ++summary.sinks;
        }
        else
        {
          dir[k] = static_cast<std::int8_t>(
            detail::D8FlatStep(in.view, w, distance.data(), gi - in.gi0, gj - in.gj0));
          ++summary.flatCells;
        }
      }
      summary.outlets += dir[k] == kD8Outlet ? 1 : 0;
    });
  return exchanges;
}

/// The tile alone: its owned cells as a grid of their own (spacing of their rows), directions
/// that leave it turned into outlets.
struct LocalTile
{
  GridView<float> view;
  std::vector<float> filled;
  std::vector<std::int8_t> dir;
  std::vector<float> weight;
};

LocalTile MakeLocalTile(const DistributedFillInput& in,
  const float* w,
  const std::int8_t* dir,
  const float* weight)
{
  const Tile tile(in);
  LocalTile t;
  const std::size_t cells = static_cast<std::size_t>(in.owned.Cells());
  t.filled.resize(cells);
  t.dir.resize(cells);
  if (weight)
  {
    t.weight.resize(cells);
  }
  ForOwned(in,
    [&](std::size_t k, int gi, int gj)
    {
      const std::size_t o = tile.Owned(gi, gj);
      t.filled[o] = w[k];
      int d = dir[k];
      if (d >= 0 && !in.owned.Contains(gi + kD8Di[d], gj + kD8Dj[d]))
      {
        d = kD8Outlet;
      }
      t.dir[o] = static_cast<std::int8_t>(d);
      if (weight)
      {
        t.weight[o] = weight[k];
      }
    });
  const int row0 = in.owned.j0 - in.gj0;
  t.view.data = t.filled.data();
  t.view.nx = tile.ox;
  t.view.ny = tile.oy;
  t.view.dx = in.view.dx;
  t.view.dy = in.view.dy;
  t.view.rowDx = in.view.rowDx ? in.view.rowDx + row0 : nullptr;
  t.view.rowDy = in.view.rowDy ? in.view.rowDy + row0 : nullptr;
  return t;
}

/// The tile's sums (cells, area, and weighted when weights are given), each owned-sized, with
/// `inflow` (one owned-sized array per sum, or none) added where flow enters the tile.
std::vector<std::vector<double>> LocalSums(const LocalTile& t,
  const DistributedFlowOptions& options,
  const std::vector<std::vector<double>>* inflow)
{
  const std::size_t m = t.weight.empty() ? 2 : 3;
  std::vector<std::vector<double>> sums(m, std::vector<double>(t.filled.size()));
  for (std::size_t s = 0; s < m && !t.filled.empty(); ++s)
  {
    AccumulationOptions o;
    o.timesCellArea = s == 1;
    o.scale = s == 2 ? options.weightScale : 1.0;
    o.inflow = inflow ? (*inflow)[s].data() : nullptr;
    D8FlowAccumulation(t.view, t.dir.data(), s == 2 ? t.weight.data() : nullptr, sums[s].data(), o);
  }
  return sums;
}

/// Along the directions from owned cell (gi, gj): the first cell after it that is on the
/// tile's perimeter or outside the tile (whole-grid index), or -1 when the way ends at an
/// outlet inside. `memo` (owned-sized, kUnknown at first) keeps the answers of inner cells.
std::int64_t NextPerimeterCell(const DistributedFillInput& in,
  const std::int8_t* dir,
  int gi,
  int gj,
  std::vector<std::int64_t>& memo)
{
  const Tile tile(in);
  std::vector<std::size_t> inner;
  std::int64_t result = -1;
  while (true)
  {
    const int d = dir[tile.ViewIndex(gi, gj)];
    if (d < 0)
    {
      break;
    }
    gi += kD8Di[d];
    gj += kD8Dj[d];
    if (!in.owned.Contains(gi, gj) || InBand(in.owned, gi, gj, 1, in.wholeNx, in.wholeNy))
    {
      result = tile.Global(gi, gj);
      break;
    }
    const std::size_t o = tile.Owned(gi, gj);
    if (memo[o] != kUnknown)
    {
      result = memo[o];
      break;
    }
    inner.push_back(o);
  }
  for (std::size_t o : inner)
  {
    memo[o] = result;
  }
  return result;
}

/// The head of a tile's sums message: WriteHead's, its D8 counts and the number of sums.
void WriteSumsHead(Writer& w,
  const std::string& problem,
  const DistributedFillInput& in,
  const D8Summary& counts,
  std::size_t m)
{
  WriteHead(w, problem, in);
  w.Put<std::uint64_t>(counts.outlets);
  w.Put<std::uint64_t>(counts.flatCells);
  w.Put<std::uint64_t>(counts.sinks);
  w.Put<std::uint64_t>(m);
}

/// Rank 0 reads tile t's WriteSumsHead (ReadHead's checks; its box and reach appended to
/// `boxes` and `reaches`) and adds its counts to `total`; throws on a failed tile or another
/// number of sums.
void ReadSumsHead(Reader& r,
  int t,
  const DistributedFillInput& in,
  std::vector<TileBox>& boxes,
  std::vector<std::int32_t>& reaches,
  D8Summary& total,
  std::size_t m)
{
  const std::string why = ReadHead(r, t, in.wholeNx, in.wholeNy, boxes, reaches);
  if (!why.empty())
  {
    throw std::runtime_error(why);
  }
  total.outlets += r.Get<std::uint64_t>();
  total.flatCells += r.Get<std::uint64_t>();
  total.sinks += r.Get<std::uint64_t>();
  if (r.Get<std::uint64_t>() != m)
  {
    throw std::runtime_error("the tiles disagree on the weights");
  }
}

/// The whole grid's D8 counts in rank 0's reply.
void PutCounts(Writer& w, const D8Summary& counts)
{
  w.Put<std::uint64_t>(counts.outlets);
  w.Put<std::uint64_t>(counts.flatCells);
  w.Put<std::uint64_t>(counts.sinks);
}

D8Summary GetCounts(Reader& r)
{
  D8Summary counts;
  counts.outlets = static_cast<std::size_t>(r.Get<std::uint64_t>());
  counts.flatCells = static_cast<std::size_t>(r.Get<std::uint64_t>());
  counts.sinks = static_cast<std::size_t>(r.Get<std::uint64_t>());
  return counts;
}

/// Rank 0's inflows (m sums per whole-grid cell of `cells`, in `flow`) into `inflow` (m
/// arrays, zeroed first) at index(gi, gj); throws naming `function` when a cell is not owned.
template<typename Index>
void SetInflows(const DistributedFillInput& in,
  const std::vector<std::int64_t>& cells,
  const std::vector<double>& flow,
  std::vector<std::vector<double>>& inflow,
  Index index,
  const char* function)
{
  const std::size_t m = inflow.size();
  for (std::vector<double>& f : inflow)
  {
    std::fill(f.begin(), f.end(), 0.0);
  }
  for (std::size_t e = 0; e < cells.size(); ++e)
  {
    const int gi = static_cast<int>(cells[e] % in.wholeNx);
    const int gj = static_cast<int>(cells[e] / in.wholeNx);
    if (!in.owned.Contains(gi, gj))
    {
      throw std::runtime_error(std::string(function) + ": an inflow to a cell of another tile");
    }
    for (std::size_t s = 0; s < m; ++s)
    {
      inflow[s][index(gi, gj)] = flow[e * m + s];
    }
  }
}

/// Steps 1-3 of both accumulations: the filled surface W into result.filled, on the tile and
/// one ring beyond the caller's (for the ring's directions); the owned cells' D8 codes into
/// `dir` (view-sized; the flats agreed across tiles) and their counts into `counts`.
void FilledAndDirections(const DistributedFillInput& in,
  TileExchange& exchange,
  DistributedFlowResult& result,
  std::vector<std::int8_t>& dir,
  D8Summary& counts)
{
  DistributedFillInput wide = in;
  wide.reach = in.reach + 1;
  result.filled = FillDepressionsDistributed(wide, DepressionWaterBodyOptions(), exchange).filled;
  dir.assign(in.view.Size(), kD8NoData);
  result.flatExchanges = OwnedDirections(in, result.filled.data(), dir.data(), exchange, counts);
}

/// View-sized values: f(k, gi, gj) on the owned cells, the ring of `reach` from their owners,
/// `missing` elsewhere (a collective call).
template<typename T, typename F>
std::vector<T> OwnedAndRing(const DistributedFillInput& in,
  int reach,
  T missing,
  F f,
  TileExchange& exchange,
  const char* function)
{
  std::vector<T> out(in.view.Size(), missing);
  ForOwned(in, [&](std::size_t k, int gi, int gj) { out[k] = f(k, gi, gj); });
  ExchangeRing<T>(in, reach, out.data(), missing, exchange, nullptr, function);
  return out;
}

/// Step 5 of both accumulations: the m sums (sum(s, k, gi, gj) on the owned cells) and the
/// owned cells' directions `dir` into `result`, view-sized, the ring's from their owners.
template<typename Sum>
void RingResults(const DistributedFillInput& in,
  int reach,
  std::size_t m,
  Sum sum,
  const std::int8_t* dir,
  DistributedFlowResult& result,
  TileExchange& exchange,
  const char* function)
{
  std::vector<double>* outputs[3] = { &result.cells, &result.area, &result.weighted };
  for (std::size_t s = 0; s < m; ++s)
  {
    *outputs[s] = OwnedAndRing<double>(
      in,
      reach,
      kNaN,
      [&](std::size_t k, int gi, int gj) { return sum(s, k, gi, gj); },
      exchange,
      function);
  }
  result.direction = OwnedAndRing<std::int8_t>(
    in, reach, kD8NoData, [&](std::size_t k, int, int) { return dir[k]; }, exchange, function);
}

/// One tile's part of the perimeter graph.
struct PerimeterPart
{
  TileBox box;
  std::vector<std::int64_t> cells;
  std::vector<std::int64_t> next;
  std::vector<double> sums; ///< m per cell
};

/// Rank 0: the flow entering each tile from the others, per cell (m sums per cell), by the
/// perimeter graph in topological order.
void SolvePerimeterGraph(const std::vector<PerimeterPart>& parts,
  std::size_t m,
  std::vector<std::vector<std::int64_t>>& entryCells,
  std::vector<std::vector<double>>& entryFlow)
{
  std::vector<std::size_t> base(parts.size() + 1, 0);
  std::unordered_map<std::int64_t, std::size_t> node;
  for (std::size_t t = 0; t < parts.size(); ++t)
  {
    const PerimeterPart& p = parts[t];
    if (p.next.size() != p.cells.size() || p.sums.size() != m * p.cells.size())
    {
      throw std::runtime_error("a tile's perimeter does not match its sums");
    }
    base[t + 1] = base[t] + p.cells.size();
    for (std::size_t c = 0; c < p.cells.size(); ++c)
    {
      node.emplace(p.cells[c], base[t] + c);
    }
  }
  const std::size_t nodes = base.back();
  std::vector<std::int64_t> down(nodes, -1);
  std::vector<std::uint8_t> across(nodes, 0);
  std::vector<std::uint32_t> upstream(nodes, 0);
  std::vector<int> tileOf(nodes, 0);
  for (std::size_t t = 0; t < parts.size(); ++t)
  {
    for (std::size_t c = 0; c < parts[t].cells.size(); ++c)
    {
      const std::size_t a = base[t] + c;
      tileOf[a] = static_cast<int>(t);
      const std::int64_t next = parts[t].next[c];
      if (next < 0)
      {
        continue;
      }
      const auto it = node.find(next);
      if (it == node.end())
      {
        throw std::runtime_error("a perimeter cell drains to a cell no tile has on its perimeter");
      }
      down[a] = static_cast<std::int64_t>(it->second);
      across[a] = it->second >= base[t] && it->second < base[t + 1] ? 0 : 1; // another tile
      ++upstream[it->second];
    }
  }
  // Flow received from outside the tile (carried within it) and what crosses into each cell.
  std::vector<double> outside(nodes * m, 0.0);
  std::vector<double> entering(nodes * m, 0.0);
  std::vector<std::uint8_t> entered(nodes, 0);
  std::vector<std::size_t> ready;
  for (std::size_t a = 0; a < nodes; ++a)
  {
    if (upstream[a] == 0)
    {
      ready.push_back(a);
    }
  }
  std::size_t done = 0;
  for (std::size_t r = 0; r < ready.size(); ++r)
  {
    const std::size_t a = ready[r];
    ++done;
    if (down[a] < 0)
    {
      continue;
    }
    const auto b = static_cast<std::size_t>(down[a]);
    const std::size_t c = a - base[tileOf[a]];
    for (std::size_t s = 0; s < m; ++s)
    {
      const double carried =
        outside[a * m + s] + (across[a] ? parts[tileOf[a]].sums[c * m + s] : 0.0);
      outside[b * m + s] += carried;
      if (across[a])
      {
        entering[b * m + s] += carried;
      }
    }
    entered[b] = static_cast<std::uint8_t>(entered[b] | across[a]);
    if (--upstream[b] == 0)
    {
      ready.push_back(b);
    }
  }
  if (done != nodes)
  {
    throw std::runtime_error("the tiles' directions hold a cycle across tile edges");
  }
  entryCells.assign(parts.size(), {});
  entryFlow.assign(parts.size(), {});
  for (std::size_t a = 0; a < nodes; ++a)
  {
    if (entered[a])
    {
      const int t = tileOf[a];
      entryCells[t].push_back(parts[t].cells[a - base[t]]);
      entryFlow[t].insert(entryFlow[t].end(),
        entering.begin() + static_cast<std::ptrdiff_t>(a * m),
        entering.begin() + static_cast<std::ptrdiff_t>((a + 1) * m));
    }
  }
}
} // namespace

DistributedFlowResult D8FlowAccumulationDistributed(const DistributedFillInput& in,
  const DistributedFlowOptions& options,
  TileExchange& exchange)
{
  const int ranks = exchange.Size();
  const Tile tile(in);
  DistributedFlowResult result;

  // ---- 1-3. The filled surface and the directions of the owned cells.
  std::vector<std::int8_t> directions;
  D8Summary mine;
  FilledAndDirections(in, exchange, result, directions, mine);
  const float* w = result.filled.data();
  const std::int8_t* dir = directions.data();

  // ---- 4. The tile's own sums and its part of the perimeter graph.
  const LocalTile local = MakeLocalTile(in, w, dir, options.weight);
  std::vector<std::vector<double>> sums = LocalSums(local, options, nullptr);
  const std::size_t m = sums.size();
  PerimeterPart part;
  part.box = in.owned;
  std::vector<std::int64_t> memo(local.filled.size(), kUnknown);
  ForOwned(in,
    [&](std::size_t, int gi, int gj)
    {
      if (InBand(in.owned, gi, gj, 1, in.wholeNx, in.wholeNy))
      {
        part.cells.push_back(tile.Global(gi, gj));
        part.next.push_back(NextPerimeterCell(in, dir, gi, gj, memo));
        for (std::size_t s = 0; s < m; ++s)
        {
          part.sums.push_back(sums[s][tile.Owned(gi, gj)]);
        }
      }
    });
  Writer w1;
  WriteSumsHead(w1, std::string(), in, mine, m);
  w1.PutVector(part.cells);
  w1.PutVector(part.next);
  w1.PutVector(part.sums);
  const std::vector<std::vector<char>> all = exchange.Gather(w1.Bytes);
  std::vector<std::vector<char>> replies;
  if (exchange.Rank() == 0)
  {
    try
    {
      std::vector<TileBox> boxes;
      std::vector<std::int32_t> reaches;
      std::vector<PerimeterPart> parts;
      D8Summary total;
      for (int t = 0; t < ranks; ++t)
      {
        Reader r(all.at(static_cast<std::size_t>(t)));
        ReadSumsHead(r, t, in, boxes, reaches, total, m);
        PerimeterPart p;
        p.box = boxes.back();
        p.cells = r.GetVector<std::int64_t>();
        p.next = r.GetVector<std::int64_t>();
        p.sums = r.GetVector<double>();
        parts.push_back(std::move(p));
      }
      std::vector<std::vector<std::int64_t>> entryCells;
      std::vector<std::vector<double>> entryFlow;
      SolvePerimeterGraph(parts, m, entryCells, entryFlow);
      for (int t = 0; t < ranks; ++t)
      {
        Writer reply;
        reply.Put<std::uint8_t>(0);
        reply.Put<std::int32_t>(*std::max_element(reaches.begin(), reaches.end()));
        PutCounts(reply, total);
        reply.PutVector(entryCells[t]);
        reply.PutVector(entryFlow[t]);
        replies.push_back(std::move(reply.Bytes));
      }
    }
    catch (const std::exception& x)
    {
      replies = FailAll(ranks, x.what());
    }
  }
  const std::vector<char> reply = exchange.Scatter(replies);
  Reader r(reply);
  CheckStatus(r, kName);
  const auto reachAll = r.Get<std::int32_t>();
  result.summary = GetCounts(r);
  const std::vector<std::int64_t> entryCells = r.GetVector<std::int64_t>();
  const std::vector<double> entryFlow = r.GetVector<double>();
  if (entryFlow.size() != m * entryCells.size() || reachAll < in.reach)
  {
    throw std::runtime_error(std::string(kName) + ": rank 0's inflows do not match this tile");
  }

  // ---- The sums again with the flow entering the tile.
  std::vector<std::vector<double>> inflow(m, std::vector<double>(local.filled.size(), 0.0));
  SetInflows(
    in, entryCells, entryFlow, inflow, [&](int gi, int gj) { return tile.Owned(gi, gj); }, kName);
  sums = LocalSums(local, options, &inflow);

  // ---- 5. The view-sized results; the ring's from its owners.
  RingResults(
    in,
    reachAll,
    m,
    [&](std::size_t s, std::size_t, int gi, int gj) { return sums[s][tile.Owned(gi, gj)]; },
    dir,
    result,
    exchange,
    kName);
  return result;
}

namespace
{
constexpr const char* kDispersiveName = "DispersiveFlowAccumulationDistributed";

/// What rank 0 keeps between the rounds of the dispersive accumulation: per tile, the flow
/// entering its cells (whole-grid cell -> m sums), the last round's.
using Inflows = std::vector<std::map<std::int64_t, std::vector<double>>>;

/// One round: each tile sends the m sums its owned cells sent into the cells around it (its
/// ring of 1, cells with data); rank 0 adds them per receiving cell in rank order and returns
/// each tile the flow entering its owned cells, written into `inflow` (m view-sized arrays,
/// zero elsewhere). True when no tile's inflow changed since the last round (rank 0 keeps
/// them in `previous`; `round` counts from 1). Also the grid's D8 counts (`total`, of the tiles'
/// `summary`) and the widest reach (`reach`).
bool InflowRound(const DistributedFillInput& in,
  const std::int8_t* dir,
  const std::vector<std::vector<double>>& sums,
  std::vector<std::vector<double>>& inflow,
  TileExchange& exchange,
  Inflows& previous,
  int round,
  const std::string& problem,
  const D8Summary& summary,
  D8Summary& total,
  int& reach)
{
  const Tile tile(in);
  const std::size_t m = sums.size();
  std::vector<std::int64_t> cells;
  std::vector<double> values;
  ForRing(in.owned,
    1,
    in.wholeNx,
    in.wholeNy,
    [&](int gi, int gj)
    {
      const std::size_t k = tile.ViewIndex(gi, gj);
      if (dir[k] != kD8NoData)
      {
        cells.push_back(tile.Global(gi, gj));
        for (std::size_t s = 0; s < m; ++s)
        {
          values.push_back(sums[s][k]);
        }
      }
    });
  Writer w;
  WriteSumsHead(w, problem, in, summary, m);
  w.PutVector(cells);
  w.PutVector(values);
  const std::vector<std::vector<char>> all = exchange.Gather(w.Bytes);
  std::vector<std::vector<char>> replies;
  if (exchange.Rank() == 0)
  {
    try
    {
      const int ranks = exchange.Size();
      std::vector<TileBox> boxes;
      std::vector<std::int32_t> reaches;
      D8Summary total;
      std::vector<std::vector<std::int64_t>> sent(static_cast<std::size_t>(ranks));
      std::vector<std::vector<double>> sentValues(static_cast<std::size_t>(ranks));
      for (int t = 0; t < ranks; ++t)
      {
        Reader r(all.at(static_cast<std::size_t>(t)));
        ReadSumsHead(r, t, in, boxes, reaches, total, m);
        sent[t] = r.GetVector<std::int64_t>();
        sentValues[t] = r.GetVector<double>();
        if (sentValues[t].size() != m * sent[t].size())
        {
          throw std::runtime_error("a tile's sums do not match its cells");
        }
      }
      const std::string why = CheckPartition(boxes, in.wholeNx, in.wholeNy);
      if (!why.empty())
      {
        throw std::runtime_error(why);
      }
      // A path of the acyclic flow graph enters each cell once: it crosses into other tiles
      // at most once per ring cell, and one more round sees no change.
      std::size_t ringCells = 0;
      for (const std::vector<std::int64_t>& c : sent)
      {
        ringCells += c.size();
      }
      if (static_cast<std::size_t>(round) > ringCells + 2)
      {
        throw std::runtime_error("the flow between the tiles does not settle (a cycle)");
      }
      // Each receiving cell's sums over the senders, in rank order.
      Inflows now(static_cast<std::size_t>(ranks));
      for (int t = 0; t < ranks; ++t)
      {
        for (std::size_t c = 0; c < sent[t].size(); ++c)
        {
          const int gi = static_cast<int>(sent[t][c] % in.wholeNx);
          const int gj = static_cast<int>(sent[t][c] / in.wholeNx);
          std::size_t owner = 0;
          while (owner < boxes.size() && !boxes[owner].Contains(gi, gj))
          {
            ++owner;
          }
          if (owner == boxes.size() || owner == static_cast<std::size_t>(t))
          {
            throw std::runtime_error("a tile sent flow to a cell no other tile owns");
          }
          std::vector<double>& into = now[owner][sent[t][c]];
          into.resize(m, 0.0);
          for (std::size_t s = 0; s < m; ++s)
          {
            into[s] += sentValues[t][c * m + s];
          }
        }
      }
      const bool same = now == previous;
      previous = std::move(now);
      for (int t = 0; t < ranks; ++t)
      {
        Writer reply;
        reply.Put<std::uint8_t>(0);
        reply.Put<std::uint8_t>(same ? 1 : 0);
        reply.Put<std::int32_t>(*std::max_element(reaches.begin(), reaches.end()));
        PutCounts(reply, total);
        std::vector<std::int64_t> to;
        std::vector<double> flow;
        for (const auto& entry : previous[t])
        {
          to.push_back(entry.first);
          flow.insert(flow.end(), entry.second.begin(), entry.second.end());
        }
        reply.PutVector(to);
        reply.PutVector(flow);
        replies.push_back(std::move(reply.Bytes));
      }
    }
    catch (const std::exception& x)
    {
      replies = FailAll(exchange.Size(), x.what());
    }
  }
  const std::vector<char> bytes = exchange.Scatter(replies);
  Reader r(bytes);
  CheckStatus(r, kDispersiveName);
  const bool same = r.Get<std::uint8_t>() != 0;
  reach = r.Get<std::int32_t>();
  total = GetCounts(r);
  const std::vector<std::int64_t> to = r.GetVector<std::int64_t>();
  const std::vector<double> flow = r.GetVector<double>();
  if (flow.size() != m * to.size() || reach < in.reach)
  {
    throw std::runtime_error(std::string(kDispersiveName) + ": rank 0's inflows do not match");
  }
  SetInflows(
    in, to, flow, inflow, [&](int gi, int gj) { return tile.ViewIndex(gi, gj); }, kDispersiveName);
  return same;
}
} // namespace

//------------------------------------------------------------------------------
DistributedFlowResult DispersiveFlowAccumulationDistributed(const DistributedFillInput& in,
  const DispersiveFlowMethod& method,
  const DistributedFlowOptions& options,
  TileExchange& exchange)
{
  const std::size_t n = in.view.Size();
  DistributedFlowResult result;

  // ---- 1-3. The filled surface and the D8 codes, as for D8: the owned cells', then the
  // ring's from their owners (the partitions read them).
  std::vector<std::int8_t> dir;
  D8Summary mine;
  FilledAndDirections(in, exchange, result, dir, mine);
  const float* w = result.filled.data();
  result.direction.assign(n, kD8NoData);
  ForOwned(in, [&](std::size_t k, int, int) { result.direction[k] = dir[k]; });
  // Rounds need every tile's reach for the ring; the first round tells it, so the ring of 1
  // (what the partitions read) comes first and the caller's ring at the end.
  DistributedFillInput near = in;
  near.reach = 1;
  ExchangeRing<std::int8_t>(
    near, 1, result.direction.data(), kD8NoData, exchange, nullptr, kDispersiveName);

  // ---- 4. The sums in rounds: each tile accumulates its owned cells with the flow entering
  // them; the flow they send into other tiles' cells becomes those tiles' inflow; until no
  // inflow changes (a flow path crossing tile edges k times needs k + 1 rounds).
  const std::size_t m = options.weight ? 3 : 2;
  std::vector<std::vector<double>> sums(m, std::vector<double>(n, 0.0));
  std::vector<std::vector<double>> inflow(m, std::vector<double>(n, 0.0));
  const int box[4] = {
    in.owned.i0 - in.gi0, in.owned.i1 - in.gi0, in.owned.j0 - in.gj0, in.owned.j1 - in.gj0
  };
  // `incoming`: the flow entering the owned cells (a full run), or its change since the last
  // round (an incremental one: only the cells downstream of a change are updated).
  const auto accumulate =
    [&](std::size_t s, const std::vector<double>& incoming, bool incremental, float* angle)
  {
    AccumulationOptions o;
    o.active = box;
    o.inflow = incoming.data();
    o.incremental = incremental;
    o.timesCellArea = s == 1;
    o.scale = s == 2 ? options.weightScale : 1.0;
    const float* weight = s == 2 ? options.weight : nullptr;
    if (method.dInfinity)
    {
      DInfinityAccumulation(in.view, w, result.direction.data(), weight, sums[s].data(), angle, o);
    }
    else
    {
      MultipleFlowAccumulation(
        in.view, w, result.direction.data(), method.mfd, weight, sums[s].data(), o);
    }
  };
  Inflows previous;
  int reachAll = in.reach;
  std::vector<std::vector<double>> received = inflow;
  for (bool same = false; !same;)
  {
    // A tile's failure travels with its message, so that every rank fails alike.
    std::string problem;
    try
    {
      const bool incremental = result.accumulationRounds > 0;
      for (std::size_t s = 0; s < m; ++s)
      {
        if (incremental)
        {
          for (std::size_t k = 0; k < n; ++k)
          {
            const double now = received[s][k];
            received[s][k] = now - inflow[s][k]; // the change
            inflow[s][k] = now;
          }
        }
        accumulate(s, incremental ? received[s] : inflow[s], incremental, nullptr);
      }
    }
    catch (const std::exception& x)
    {
      problem = x.what();
    }
    ++result.accumulationRounds;
    same = InflowRound(in,
      result.direction.data(),
      sums,
      received,
      exchange,
      previous,
      result.accumulationRounds,
      problem,
      mine,
      result.summary,
      reachAll);
  }

  // ---- 5. The view-sized results, the ring's from its owners (the angles computed on the
  // owned cells after the sums were taken: the accumulation run for them rewrites sums[0]).
  RingResults(
    in,
    reachAll,
    m,
    [&](std::size_t s, std::size_t k, int, int) { return sums[s][k]; },
    dir.data(),
    result,
    exchange,
    kDispersiveName);
  if (method.dInfinity)
  {
    std::vector<float> angle(n);
    accumulate(0, std::vector<double>(n, 0.0), false, angle.data());
    result.angle = OwnedAndRing<float>(
      in,
      reachAll,
      std::numeric_limits<float>::quiet_NaN(),
      [&](std::size_t k, int, int) { return angle[k]; },
      exchange,
      kDispersiveName);
  }
  return result;
}

} // namespace hydrology
} // namespace terroir

#include "DistributedPriorityFlood.h"

#include "DistributedTiles.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <deque>
#include <limits>
#include <numeric>
#include <queue>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <utility>

namespace terroir
{
namespace hydrology
{

const char* const kPriorityFloodBarnes2016Citation =
  "Barnes, R. (2016). Parallel priority-flood depression filling for trillion cell digital "
  "elevation models on desktops or clusters. Computers & Geosciences 96:56-68. "
  "doi:10.1016/j.cageo.2016.07.001";

using namespace tiles;

namespace
{
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

struct PerimeterCell
{
  std::int64_t cell; ///< whole-grid row-major index
  std::int32_t label;
  float z;
};

struct SpillEdge
{
  std::int32_t a;
  std::int32_t b;
  float level;
};

struct BandCell
{
  std::int64_t cell; ///< whole-grid row-major index
  float filled;
  std::int32_t flat;
};

struct FlatSummary
{
  WaterBodyStats stats;
  std::int64_t first = 0; ///< whole-grid row-major index of its first cell
  std::uint8_t anyFilled = 0;
};

/// DepressionWaterBodies' rule: a filled cell, or a flat of two or more cells when flats count;
/// and at least the minimum area.
bool IsWater(const FlatSummary& f, const DepressionWaterBodyOptions& options)
{
  return (f.anyFilled || (options.includeFlatSurfaces && f.stats.cells >= 2)) &&
    f.stats.area >= options.minimumArea;
}

struct OpenCell
{
  float height;
  std::int32_t cell;
};

/// Lowest height first, then lowest index (the serial code's order).
struct HigherFirst
{
  bool operator()(const OpenCell& a, const OpenCell& b) const
  {
    return a.height > b.height || (a.height == b.height && a.cell > b.cell);
  }
};

} // namespace

DistributedFillResult FillDepressionsDistributed(const DistributedFillInput& in,
  const DepressionWaterBodyOptions& options,
  TileExchange& exchange)
{
  const int ranks = exchange.Size();
  const bool root = exchange.Rank() == 0;
  const Tile tile(in);
  const TileBox& owned = in.owned;
  const std::size_t ownedCells = static_cast<std::size_t>(owned.Cells());
  const int nx = in.wholeNx;
  const int ny = in.wholeNy;

  // ---- 1. Priority-Flood of the tile, seeded with its outlets and perimeter.
  const std::string problem = CheckTile(in);
  std::vector<float> water(ownedCells, kNaN);
  std::vector<std::int32_t> label(ownedCells, -1);
  std::vector<PerimeterCell> perimeter;
  std::vector<SpillEdge> edges;
  std::int32_t labels = 1; // label 0: the ocean (the grid's outlets)
  if (problem.empty() && ownedCells > 0)
  {
    std::priority_queue<OpenCell, std::vector<OpenCell>, HigherFirst> open;
    std::deque<std::int32_t> pit;
    std::vector<std::uint8_t> closed(ownedCells, 0);
    for (int gj = owned.j0; gj <= owned.j1; ++gj)
    {
      for (int gi = owned.i0; gi <= owned.i1; ++gi)
      {
        const std::size_t o = tile.Owned(gi, gj);
        if (!tile.Data(gi, gj))
        {
          closed[o] = 1;
          continue;
        }
        water[o] = in.view.data[tile.ViewIndex(gi, gj)];
        bool outlet = gi == 0 || gj == 0 || gi == nx - 1 || gj == ny - 1;
        bool edge = false;
        for (int e = 0; e < 8; ++e)
        {
          const int ii = gi + detail::kNeighbourDi[e];
          const int jj = gj + detail::kNeighbourDj[e];
          if (tile.InWhole(ii, jj))
          {
            outlet = outlet || !tile.Data(ii, jj);
            edge = edge || !owned.Contains(ii, jj);
          }
        }
        if (!outlet && !edge)
        {
          continue;
        }
        closed[o] = 1;
        label[o] = outlet ? 0 : labels++;
        open.push(OpenCell{ water[o], static_cast<std::int32_t>(o) });
        if (edge)
        {
          perimeter.push_back(PerimeterCell{ tile.Global(gi, gj), label[o], water[o] });
        }
      }
    }
    std::unordered_map<std::uint64_t, float> spill;
    while (!open.empty() || !pit.empty())
    {
      std::int32_t c;
      if (!pit.empty())
      {
        c = pit.front();
        pit.pop_front();
      }
      else
      {
        c = open.top().cell;
        open.pop();
      }
      const float h = water[c];
      const std::int32_t lc = label[c];
      const int gi = owned.i0 + c % tile.ox;
      const int gj = owned.j0 + c / tile.ox;
      for (int e = 0; e < 8; ++e)
      {
        const int ii = gi + detail::kNeighbourDi[e];
        const int jj = gj + detail::kNeighbourDj[e];
        if (!owned.Contains(ii, jj))
        {
          continue;
        }
        const std::size_t k = tile.Owned(ii, jj);
        if (closed[k])
        {
          const std::int32_t lk = label[k];
          if (lk >= 0 && lk != lc)
          {
            // Where two watersheds meet: the lowest level at which water passes.
            const std::uint64_t key = (static_cast<std::uint64_t>(std::min(lc, lk)) << 32) |
              static_cast<std::uint32_t>(std::max(lc, lk));
            const float level = std::max(h, water[k]);
            auto it = spill.emplace(key, level).first;
            it->second = std::min(it->second, level);
          }
          continue;
        }
        closed[k] = 1;
        label[k] = lc;
        if (water[k] <= h)
        {
          water[k] = h;
          pit.push_back(static_cast<std::int32_t>(k));
        }
        else
        {
          open.push(OpenCell{ water[k], static_cast<std::int32_t>(k) });
        }
      }
    }
    edges.reserve(spill.size());
    for (const auto& s : spill)
    {
      edges.push_back(SpillEdge{ static_cast<std::int32_t>(s.first >> 32),
        static_cast<std::int32_t>(s.first & 0xffffffffu),
        s.second });
    }
    std::sort(edges.begin(),
      edges.end(),
      [](const SpillEdge& a, const SpillEdge& b)
      { return a.a < b.a || (a.a == b.a && a.b < b.b); });
  }
  {
    Writer w;
    WriteHead(w, problem, in);
    w.Put<std::int32_t>(labels);
    w.PutVector(perimeter);
    w.PutVector(edges);
    std::vector<std::vector<char>> replies;
    std::vector<TileBox> boxes;
    std::vector<std::int32_t> reaches;
    const std::vector<std::vector<char>> all = exchange.Gather(w.Bytes);
    if (root)
    {
      // ---- 2. Rank 0: the spill graph of every tile, flooded from the ocean.
      std::string why;
      std::vector<std::int32_t> labelCount;
      std::vector<std::vector<PerimeterCell>> perimeters;
      std::vector<std::vector<SpillEdge>> spills;
      for (int t = 0; t < ranks && why.empty(); ++t)
      {
        Reader r(all.at(static_cast<std::size_t>(t)));
        why = ReadHead(r, t, nx, ny, boxes, reaches);
        if (!why.empty())
        {
          break;
        }
        labelCount.push_back(r.Get<std::int32_t>());
        perimeters.push_back(r.GetVector<PerimeterCell>());
        spills.push_back(r.GetVector<SpillEdge>());
      }
      if (why.empty())
      {
        why = CheckPartition(boxes, nx, ny);
      }
      if (!why.empty())
      {
        replies = FailAll(ranks, why);
      }
      else
      {
        // Nodes: 0 the ocean, then each tile's labels 1.. in rank order.
        std::vector<std::int64_t> base(static_cast<std::size_t>(ranks) + 1, 1);
        for (int t = 0; t < ranks; ++t)
        {
          base[t + 1] = base[t] + std::max(0, labelCount[t] - 1);
        }
        const auto node = [&](int t, std::int32_t l)
        { return l == 0 ? std::int64_t(0) : base[t] + l - 1; };
        std::vector<std::vector<std::pair<std::int64_t, float>>> links(
          static_cast<std::size_t>(base[ranks]));
        const auto link = [&](std::int64_t a, std::int64_t b, float level)
        {
          if (a != b)
          {
            links[a].emplace_back(b, level);
            links[b].emplace_back(a, level);
          }
        };
        struct Owner
        {
          int tile;
          std::int32_t label;
          float z;
        };
        std::unordered_map<std::int64_t, Owner> where;
        for (int t = 0; t < ranks; ++t)
        {
          for (const SpillEdge& s : spills[t])
          {
            if (s.a < 0 || s.b < 0 || s.a >= labelCount[t] || s.b >= labelCount[t])
            {
              throw std::runtime_error("FillDepressionsDistributed: a spill edge names an "
                                       "unknown label");
            }
            link(node(t, s.a), node(t, s.b), s.level);
          }
          for (const PerimeterCell& p : perimeters[t])
          {
            if (p.label < 0 || p.label >= labelCount[t])
            {
              throw std::runtime_error("FillDepressionsDistributed: a perimeter cell names an "
                                       "unknown label");
            }
            where.emplace(p.cell, Owner{ t, p.label, p.z });
          }
        }
        // Neighbouring perimeter cells of two tiles: water passes at the higher of the two.
        for (int t = 0; t < ranks; ++t)
        {
          for (const PerimeterCell& p : perimeters[t])
          {
            ForOtherTiles(p.cell,
              boxes[t],
              nx,
              ny,
              [&](std::int64_t q)
              {
                const auto it = where.find(q);
                if (it != where.end() && q > p.cell)
                {
                  link(node(t, p.label),
                    node(it->second.tile, it->second.label),
                    std::max(p.z, it->second.z));
                }
              });
          }
        }
        // Minimax Dijkstra from the ocean: the level each seed's water must reach to leave.
        std::vector<float> level(links.size(), kInf);
        level[0] = -kInf;
        using Item = std::pair<float, std::int64_t>;
        std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
        queue.emplace(level[0], 0);
        while (!queue.empty())
        {
          const Item top = queue.top();
          queue.pop();
          if (top.first > level[top.second])
          {
            continue;
          }
          for (const auto& next : links[top.second])
          {
            const float l = std::max(top.first, next.second);
            if (l < level[next.first])
            {
              level[next.first] = l;
              queue.emplace(l, next.first);
            }
          }
        }
        const std::int32_t reach = *std::max_element(reaches.begin(), reaches.end());
        for (int t = 0; t < ranks; ++t)
        {
          std::vector<float> spillLevel(static_cast<std::size_t>(labelCount[t]));
          for (std::int32_t l = 0; l < labelCount[t]; ++l)
          {
            // Every seed reaches the ocean (its region touches an outlet); -inf keeps W as is.
            const float s = level[node(t, l)];
            spillLevel[l] = s == kInf ? -kInf : s;
          }
          Writer reply;
          reply.Put<std::uint8_t>(0);
          reply.Put<std::int32_t>(reach);
          reply.PutVector(spillLevel);
          replies.push_back(std::move(reply.Bytes));
        }
      }
    }
    const std::vector<char> mine = exchange.Scatter(replies);
    Reader r(mine);
    CheckStatus(r, "FillDepressionsDistributed");
    const auto reachAll = r.Get<std::int32_t>();
    const std::vector<float> spillLevel = r.GetVector<float>();
    if (spillLevel.size() != static_cast<std::size_t>(labels) || reachAll < in.reach)
    {
      throw std::runtime_error("FillDepressionsDistributed: rank 0's spill levels do not match "
                               "this tile");
    }

    // ---- 3. The filled surface of the tile; its flats.
    for (std::size_t o = 0; o < ownedCells; ++o)
    {
      if (label[o] >= 0)
      {
        water[o] = std::max(water[o], spillLevel[label[o]]);
      }
    }
    std::vector<std::int32_t> flat(ownedCells, -1);
    std::vector<FlatSummary> flats;
    std::vector<std::int32_t> queue;
    for (int gj = owned.j0; gj <= owned.j1; ++gj)
    {
      for (int gi = owned.i0; gi <= owned.i1; ++gi)
      {
        const std::size_t first = tile.Owned(gi, gj);
        if (label[first] < 0 || flat[first] >= 0)
        {
          continue;
        }
        const auto id = static_cast<std::int32_t>(flats.size());
        FlatSummary f;
        f.stats.level = water[first];
        f.first = tile.Global(gi, gj);
        flat[first] = id;
        queue.assign(1, static_cast<std::int32_t>(first));
        for (std::size_t head = 0; head < queue.size(); ++head)
        {
          const std::int32_t c = queue[head];
          const int ci = owned.i0 + c % tile.ox;
          const int cj = owned.j0 + c / tile.ox;
          const int vj = cj - in.gj0;
          const double d = static_cast<double>(water[c]) -
            static_cast<double>(in.view.data[tile.ViewIndex(ci, cj)]);
          f.anyFilled = f.anyFilled || d > 0.0 ? 1 : 0;
          f.stats.AddCell(in.view.DxAt(vj) * in.view.DyAt(vj), d);
          for (int e = 0; e < 8; ++e)
          {
            const int ii = ci + detail::kNeighbourDi[e];
            const int jj = cj + detail::kNeighbourDj[e];
            if (!owned.Contains(ii, jj))
            {
              continue;
            }
            const std::size_t k = tile.Owned(ii, jj);
            if (label[k] >= 0 && flat[k] < 0 && water[k] == f.stats.level)
            {
              flat[k] = id;
              queue.push_back(static_cast<std::int32_t>(k));
            }
          }
        }
        flats.push_back(f);
      }
    }
    // The band along the tile's inner edges that other tiles' rings reach.
    std::vector<BandCell> band;
    for (int gj = owned.j0; gj <= owned.j1 && ownedCells > 0; ++gj)
    {
      for (int gi = owned.i0; gi <= owned.i1; ++gi)
      {
        const std::size_t o = tile.Owned(gi, gj);
        if (InBand(owned, gi, gj, reachAll, nx, ny) && label[o] >= 0)
        {
          band.push_back(BandCell{ tile.Global(gi, gj), water[o], flat[o] });
        }
      }
    }
    // Rank 0 needs the flats that may continue in another tile (those with a band cell) and the
    // water bodies lying wholly in this one (for their numbers and the table); the other flats
    // are dry whatever the other tiles hold. On a DEM without flats nearly every cell is a flat
    // of its own: sending them all would cost the whole tile.
    std::vector<std::int32_t> sent(flats.size(), -1);
    for (BandCell& b : band)
    {
      sent[b.flat] = 0;
    }
    std::vector<FlatSummary> flatsSent;
    for (std::size_t f = 0; f < flats.size(); ++f)
    {
      if (sent[f] == 0 || IsWater(flats[f], options))
      {
        sent[f] = static_cast<std::int32_t>(flatsSent.size());
        flatsSent.push_back(flats[f]);
      }
    }
    for (BandCell& b : band)
    {
      b.flat = sent[b.flat];
    }
    Writer w2;
    w2.PutVector(flatsSent);
    w2.PutVector(band);
    const std::vector<std::vector<char>> all2 = exchange.Gather(w2.Bytes);
    std::vector<std::vector<char>> replies2;
    if (root)
    {
      // ---- 4. Rank 0: flats joined across tiles, water bodies kept and numbered.
      std::vector<std::vector<FlatSummary>> tileFlats;
      std::vector<std::vector<BandCell>> bands;
      std::vector<std::int64_t> base(static_cast<std::size_t>(ranks) + 1, 0);
      for (int t = 0; t < ranks; ++t)
      {
        Reader r2(all2.at(static_cast<std::size_t>(t)));
        tileFlats.push_back(r2.GetVector<FlatSummary>());
        bands.push_back(r2.GetVector<BandCell>());
        base[t + 1] = base[t] + static_cast<std::int64_t>(tileFlats[t].size());
      }
      struct BandOwner
      {
        int tile;
        float filled;
        std::int32_t flat;
      };
      std::unordered_map<std::int64_t, BandOwner> where;
      for (int t = 0; t < ranks; ++t)
      {
        for (const BandCell& b : bands[t])
        {
          if (b.flat < 0 || static_cast<std::size_t>(b.flat) >= tileFlats[t].size())
          {
            throw std::runtime_error("FillDepressionsDistributed: a band cell names an unknown "
                                     "flat");
          }
          where.emplace(b.cell, BandOwner{ t, b.filled, b.flat });
        }
      }
      Groups groups(static_cast<std::size_t>(base[ranks]));
      for (int t = 0; t < ranks; ++t)
      {
        for (const BandCell& b : bands[t])
        {
          ForOtherTiles(b.cell,
            boxes[t],
            nx,
            ny,
            [&](std::int64_t q)
            {
              const auto it = where.find(q);
              if (it != where.end() && it->second.filled == b.filled)
              {
                groups.Join(base[t] + b.flat, base[it->second.tile] + it->second.flat);
              }
            });
        }
      }
      // Each group's statistics added in rank order, then flat order.
      std::vector<FlatSummary> merged(static_cast<std::size_t>(base[ranks]));
      for (int t = 0; t < ranks; ++t)
      {
        for (std::size_t f = 0; f < tileFlats[t].size(); ++f)
        {
          const FlatSummary& a = tileFlats[t][f];
          const std::int64_t g = groups.Find(base[t] + static_cast<std::int64_t>(f));
          FlatSummary& m = merged[g];
          if (m.stats.cells == 0)
          {
            m = a;
            continue;
          }
          m.stats.cells += a.stats.cells;
          m.stats.area += a.stats.area;
          m.stats.volume += a.stats.volume;
          m.stats.maxDepth = std::max(m.stats.maxDepth, a.stats.maxDepth);
          m.anyFilled = m.anyFilled | a.anyFilled;
          m.first = std::min(m.first, a.first);
        }
      }
      std::vector<std::int64_t> kept;
      for (std::int64_t g = 0; g < base[ranks]; ++g)
      {
        const FlatSummary& m = merged[g];
        if (m.stats.cells > 0 && groups.Find(g) == g && IsWater(m, options))
        {
          kept.push_back(g);
        }
      }
      std::sort(kept.begin(),
        kept.end(),
        [&](std::int64_t a, std::int64_t b) { return merged[a].first < merged[b].first; });
      std::vector<std::int32_t> bodyOf(static_cast<std::size_t>(base[ranks]), 0);
      std::vector<WaterBodyStats> bodies;
      for (std::size_t b = 0; b < kept.size(); ++b)
      {
        bodyOf[kept[b]] = static_cast<std::int32_t>(b + 1);
        bodies.push_back(merged[kept[b]].stats);
      }
      for (int t = 0; t < ranks; ++t)
      {
        std::vector<std::int32_t> flatBody(tileFlats[t].size());
        for (std::size_t f = 0; f < flatBody.size(); ++f)
        {
          flatBody[f] = bodyOf[groups.Find(base[t] + static_cast<std::int64_t>(f))];
        }
        // The ring this tile's caller wants, row by row (no data: NaN and 0).
        std::vector<float> ringFilled;
        std::vector<std::int32_t> ringBody;
        ForRing(boxes[t],
          reaches[t],
          nx,
          ny,
          [&](int ii, int jj)
          {
            const auto it = where.find(static_cast<std::int64_t>(jj) * nx + ii);
            ringFilled.push_back(it == where.end() ? kNaN : it->second.filled);
            ringBody.push_back(
              it == where.end() ? 0 : bodyOf[groups.Find(base[it->second.tile] + it->second.flat)]);
          });
        Writer reply;
        reply.PutVector(flatBody);
        reply.PutVector(ringFilled);
        reply.PutVector(ringBody);
        reply.PutVector(bodies);
        replies2.push_back(std::move(reply.Bytes));
      }
    }
    const std::vector<char> mine2 = exchange.Scatter(replies2);

    // ---- 5. This tile's results, and its ring's.
    Reader r2(mine2);
    const std::vector<std::int32_t> flatBody = r2.GetVector<std::int32_t>();
    const std::vector<float> ringFilled = r2.GetVector<float>();
    const std::vector<std::int32_t> ringBody = r2.GetVector<std::int32_t>();
    DistributedFillResult result;
    result.bodies = r2.GetVector<WaterBodyStats>();
    const std::size_t n = in.view.Size();
    result.filled.assign(n, kNaN);
    result.bodyId.assign(n, 0);
    result.depth.assign(n, kNaN);
    if (flatBody.size() != flatsSent.size())
    {
      throw std::runtime_error("FillDepressionsDistributed: rank 0's water bodies do not match "
                               "this tile");
    }
    const auto set = [&](int gi, int gj, float w, std::int32_t body)
    {
      const std::size_t k = tile.ViewIndex(gi, gj);
      if (std::isnan(w))
      {
        return;
      }
      result.filled[k] = w;
      result.bodyId[k] = body;
      result.depth[k] = body > 0
        ? static_cast<float>(static_cast<double>(w) - static_cast<double>(in.view.data[k]))
        : 0.0f;
    };
    std::size_t next = 0;
    const TileBox ring = Grow(owned, in.reach, nx, ny);
    for (int gj = ring.j0; gj <= ring.j1 && ownedCells > 0; ++gj)
    {
      for (int gi = ring.i0; gi <= ring.i1; ++gi)
      {
        if (owned.Contains(gi, gj))
        {
          const std::size_t o = tile.Owned(gi, gj);
          set(gi, gj, water[o], flat[o] >= 0 && sent[flat[o]] >= 0 ? flatBody[sent[flat[o]]] : 0);
        }
        else if (next < ringFilled.size() && next < ringBody.size())
        {
          set(gi, gj, ringFilled[next], ringBody[next]);
          ++next;
        }
        else
        {
          throw std::runtime_error("FillDepressionsDistributed: rank 0's ring does not match "
                                   "this tile");
        }
      }
    }
    return result;
  }
}

namespace
{
struct SeedCell
{
  std::int32_t seed;
  std::uint8_t data;
  float z;
};

struct SeedBand
{
  std::int64_t cell; ///< whole-grid row-major index
  std::int32_t seed;
  std::int32_t component; ///< this tile's component under the seed's level (sent index)
};

struct SeedComponent
{
  std::int32_t seedCell; ///< index into the tile's SeedCell list
  std::int32_t seed;
  std::int32_t component; ///< that seed cell's component under this seed's level, or -1
};
} // namespace

DistributedFillResult FloodFillSeedsDistributed(const DistributedFillInput& in,
  const std::vector<DistributedSeed>& seeds,
  TileExchange& exchange)
{
  const int ranks = exchange.Size();
  const bool root = exchange.Rank() == 0;
  const Tile tile(in);
  const TileBox& owned = in.owned;
  const std::size_t ownedCells = static_cast<std::size_t>(owned.Cells());
  const int nx = in.wholeNx;
  const int ny = in.wholeNy;
  const auto nSeeds = static_cast<std::int32_t>(seeds.size());

  // ---- 1. The seed cells this tile holds; rank 0 resolves the levels and the order.
  std::string problem = CheckTile(in);
  for (std::int32_t s = 0; s < nSeeds && problem.empty(); ++s)
  {
    if (seeds[s].cell < 0 || seeds[s].cell >= static_cast<std::int64_t>(nx) * ny)
    {
      problem = "seed " + std::to_string(s + 1) + " lies outside the grid";
    }
  }
  std::vector<SeedCell> mine;
  for (std::int32_t s = 0; s < nSeeds && problem.empty(); ++s)
  {
    const int gi = static_cast<int>(seeds[s].cell % nx);
    const int gj = static_cast<int>(seeds[s].cell / nx);
    if (owned.Contains(gi, gj))
    {
      const bool data = tile.Data(gi, gj);
      mine.push_back(SeedCell{ s,
        static_cast<std::uint8_t>(data ? 1 : 0),
        data ? in.view.data[tile.ViewIndex(gi, gj)] : kNaN });
    }
  }
  Writer w1;
  WriteHead(w1, problem, in);
  w1.PutVector(mine);
  const std::vector<std::vector<char>> all1 = exchange.Gather(w1.Bytes);
  std::vector<std::vector<char>> replies1;
  std::vector<TileBox> boxes;
  std::vector<std::int32_t> reaches;
  std::vector<std::vector<SeedCell>> seedCells;
  std::vector<double> level(seeds.size(), std::numeric_limits<double>::quiet_NaN());
  std::vector<std::uint8_t> starts(seeds.size(), 0);
  std::vector<std::int32_t> ownerOf(seeds.size(), -1), slotOf(seeds.size(), -1);
  if (root)
  {
    std::string why;
    for (int t = 0; t < ranks && why.empty(); ++t)
    {
      Reader r(all1.at(static_cast<std::size_t>(t)));
      why = ReadHead(r, t, nx, ny, boxes, reaches);
      if (!why.empty())
      {
        break;
      }
      seedCells.push_back(r.GetVector<SeedCell>());
    }
    if (why.empty())
    {
      why = CheckPartition(boxes, nx, ny);
    }
    for (int t = 0; t < ranks && why.empty(); ++t)
    {
      for (std::size_t k = 0; k < seedCells[t].size(); ++k)
      {
        const SeedCell& c = seedCells[t][k];
        if (c.seed < 0 || c.seed >= nSeeds)
        {
          throw std::runtime_error("FloodFillSeedsDistributed: a seed cell names an unknown seed");
        }
        ownerOf[c.seed] = t;
        slotOf[c.seed] = static_cast<std::int32_t>(k);
        level[c.seed] = !std::isnan(seeds[c.seed].level) ? seeds[c.seed].level
          : c.data                                       ? static_cast<double>(c.z)
                                                         : level[c.seed];
        starts[c.seed] = c.data && static_cast<double>(c.z) <= level[c.seed] ? 1 : 0;
      }
    }
    Writer reply;
    if (!why.empty())
    {
      replies1 = FailAll(ranks, why);
    }
    else
    {
      reply.Put<std::uint8_t>(0);
      reply.Put<std::int32_t>(*std::max_element(reaches.begin(), reaches.end()));
      reply.PutVector(level);
      replies1.assign(static_cast<std::size_t>(ranks), reply.Bytes);
    }
  }
  {
    const std::vector<char> got = exchange.Scatter(replies1);
    Reader r(got);
    CheckStatus(r, "FloodFillSeedsDistributed");
    const auto reachAll = r.Get<std::int32_t>();
    level = r.GetVector<double>();
    if (level.size() != seeds.size() || reachAll < in.reach)
    {
      throw std::runtime_error("FloodFillSeedsDistributed: rank 0's levels do not match");
    }
    // The serial order: highest level first, ties in seed order, seeds without a level last.
    std::vector<std::int32_t> order(seeds.size());
    std::iota(order.begin(), order.end(), 0);
    const auto key = [&](std::int32_t s)
    { return std::isnan(level[s]) ? -std::numeric_limits<double>::infinity() : level[s]; };
    std::stable_sort(
      order.begin(), order.end(), [&](std::int32_t a, std::int32_t b) { return key(a) > key(b); });

    // ---- 2. Per seed, the tile's components of {data, z <= level}; those rank 0 needs.
    const auto inMask = [&](std::size_t o, double l)
    {
      const int gi = owned.i0 + static_cast<int>(o % static_cast<std::size_t>(tile.ox));
      const int gj = owned.j0 + static_cast<int>(o / static_cast<std::size_t>(tile.ox));
      const std::size_t k = tile.ViewIndex(gi, gj);
      return HasData(in.view, k) && static_cast<double>(in.view.data[k]) <= l;
    };
    const auto near = [&](int gi, int gj) { return InBand(owned, gi, gj, reachAll, nx, ny); };
    std::vector<std::vector<std::int32_t>> component(seeds.size()); // sent index per owned cell
    std::vector<std::vector<WaterBodyStats>> sentStats(seeds.size());
    std::vector<SeedBand> band;
    std::vector<SeedComponent> seedComponents;
    std::vector<std::int32_t> queue;
    for (std::int32_t s = 0; s < nSeeds && ownedCells > 0; ++s)
    {
      const double l = level[s];
      if (std::isnan(l))
      {
        continue;
      }
      std::vector<std::int32_t>& comp = component[s];
      comp.assign(ownedCells, -1);
      std::vector<WaterBodyStats> stats;
      for (std::size_t first = 0; first < ownedCells; ++first)
      {
        if (comp[first] >= 0 || !inMask(first, l))
        {
          continue;
        }
        const auto id = static_cast<std::int32_t>(stats.size());
        WaterBodyStats body;
        body.level = l;
        comp[first] = id;
        queue.assign(1, static_cast<std::int32_t>(first));
        for (std::size_t head = 0; head < queue.size(); ++head)
        {
          const std::int32_t c = queue[head];
          const int ci = owned.i0 + c % tile.ox;
          const int cj = owned.j0 + c / tile.ox;
          const int vj = cj - in.gj0;
          body.AddCell(in.view.DxAt(vj) * in.view.DyAt(vj),
            l - static_cast<double>(in.view.data[tile.ViewIndex(ci, cj)]));
          for (int e = 0; e < 8; ++e)
          {
            const int ii = ci + detail::kNeighbourDi[e];
            const int jj = cj + detail::kNeighbourDj[e];
            if (!owned.Contains(ii, jj))
            {
              continue;
            }
            const std::size_t k = tile.Owned(ii, jj);
            if (comp[k] < 0 && inMask(k, l))
            {
              comp[k] = id;
              queue.push_back(static_cast<std::int32_t>(k));
            }
          }
        }
        stats.push_back(body);
      }
      // Sent: the components with a band cell or a seed cell; the others wet nothing.
      std::vector<std::int32_t> sent(stats.size(), -1);
      const auto send = [&](std::int32_t c)
      {
        if (sent[c] < 0)
        {
          sent[c] = static_cast<std::int32_t>(sentStats[s].size());
          sentStats[s].push_back(stats[c]);
        }
        return sent[c];
      };
      for (int gj = owned.j0; gj <= owned.j1; ++gj)
      {
        for (int gi = owned.i0; gi <= owned.i1; ++gi)
        {
          const std::size_t o = tile.Owned(gi, gj);
          if (comp[o] >= 0 && near(gi, gj))
          {
            band.push_back(SeedBand{ tile.Global(gi, gj), s, send(comp[o]) });
          }
        }
      }
      for (std::size_t k = 0; k < mine.size(); ++k)
      {
        const int gi = static_cast<int>(seeds[mine[k].seed].cell % nx);
        const int gj = static_cast<int>(seeds[mine[k].seed].cell / nx);
        const std::int32_t c = comp[tile.Owned(gi, gj)];
        seedComponents.push_back(
          SeedComponent{ static_cast<std::int32_t>(k), s, c >= 0 ? send(c) : -1 });
      }
      for (std::int32_t& c : comp)
      {
        c = c >= 0 ? sent[c] : -1;
      }
    }
    Writer w2;
    for (std::int32_t s = 0; s < nSeeds; ++s)
    {
      w2.PutVector(sentStats[s]);
    }
    w2.PutVector(band);
    w2.PutVector(seedComponents);
    const std::vector<std::vector<char>> all2 = exchange.Gather(w2.Bytes);

    // ---- 3. Rank 0: components joined across tiles per seed; the seeds' bodies in order.
    std::vector<std::vector<char>> replies2;
    if (root)
    {
      std::vector<std::vector<std::vector<WaterBodyStats>>> tileStats(
        static_cast<std::size_t>(ranks));
      std::vector<std::vector<SeedBand>> bands(static_cast<std::size_t>(ranks));
      std::vector<std::vector<SeedComponent>> seedComps(static_cast<std::size_t>(ranks));
      // Node of (seed, tile, component): base[s][t] + component.
      std::vector<std::vector<std::int64_t>> base(
        seeds.size(), std::vector<std::int64_t>(static_cast<std::size_t>(ranks) + 1, 0));
      for (int t = 0; t < ranks; ++t)
      {
        Reader r2(all2.at(static_cast<std::size_t>(t)));
        for (std::int32_t s = 0; s < nSeeds; ++s)
        {
          tileStats[t].push_back(r2.GetVector<WaterBodyStats>());
        }
        bands[t] = r2.GetVector<SeedBand>();
        seedComps[t] = r2.GetVector<SeedComponent>();
      }
      std::int64_t nodes = 0;
      for (std::int32_t s = 0; s < nSeeds; ++s)
      {
        for (int t = 0; t <= ranks; ++t)
        {
          base[s][t] = nodes;
          nodes += t < ranks ? static_cast<std::int64_t>(tileStats[t][s].size()) : 0;
        }
      }
      const auto check = [&](int t, std::int32_t s, std::int32_t c)
      {
        if (s < 0 || s >= nSeeds || c < 0 || static_cast<std::size_t>(c) >= tileStats[t][s].size())
        {
          throw std::runtime_error("FloodFillSeedsDistributed: a message names an unknown "
                                   "component");
        }
        return base[s][t] + c;
      };
      std::unordered_map<std::int64_t, std::pair<int, std::int32_t>> where; // cell*S+s
      for (int t = 0; t < ranks; ++t)
      {
        for (const SeedBand& b : bands[t])
        {
          check(t, b.seed, b.component);
          where.emplace(b.cell * nSeeds + b.seed, std::make_pair(t, b.component));
        }
      }
      Groups groups(static_cast<std::size_t>(nodes));
      for (int t = 0; t < ranks; ++t)
      {
        for (const SeedBand& b : bands[t])
        {
          ForOtherTiles(b.cell,
            boxes[t],
            nx,
            ny,
            [&](std::int64_t q)
            {
              const auto it = where.find(q * nSeeds + b.seed);
              if (it != where.end())
              {
                groups.Join(base[b.seed][t] + b.component,
                  base[b.seed][it->second.first] + it->second.second);
              }
            });
        }
      }
      // The component of seed u's cell under seed s's level, as a node (-1: not in the mask).
      const auto seedNode = [&](std::int32_t u, std::int32_t s) -> std::int64_t
      {
        const int t = ownerOf[u];
        for (const SeedComponent& c : seedComps[t])
        {
          if (c.seedCell == slotOf[u] && c.seed == s)
          {
            return c.component < 0 ? -1 : groups.Find(check(t, s, c.component));
          }
        }
        return -1;
      };
      std::vector<std::int64_t> wet(seeds.size(), -1); // each seed's group, -1 when empty
      std::vector<WaterBodyStats> bodies(seeds.size());
      for (std::size_t k = 0; k < order.size(); ++k)
      {
        const std::int32_t s = order[k];
        bodies[s].level = level[s];
        if (!starts[s])
        {
          continue; // no data, no level, or the terrain above the level
        }
        bool joins = false;
        for (std::size_t e = 0; e < k && !joins; ++e)
        {
          const std::int32_t t = order[e];
          joins = wet[t] >= 0 && seedNode(s, t) == wet[t];
        }
        if (!joins)
        {
          wet[s] = seedNode(s, s);
        }
      }
      for (std::int32_t s = 0; s < nSeeds; ++s)
      {
        for (int t = 0; t < ranks && wet[s] >= 0; ++t)
        {
          for (std::size_t c = 0; c < tileStats[t][s].size(); ++c)
          {
            if (groups.Find(base[s][t] + static_cast<std::int64_t>(c)) != wet[s])
            {
              continue;
            }
            const WaterBodyStats& a = tileStats[t][s][c];
            bodies[s].cells += a.cells;
            bodies[s].area += a.area;
            bodies[s].volume += a.volume;
            bodies[s].maxDepth = std::max(bodies[s].maxDepth, a.maxDepth);
          }
        }
      }
      for (int t = 0; t < ranks; ++t)
      {
        Writer reply;
        for (std::int32_t s = 0; s < nSeeds; ++s)
        {
          std::vector<std::uint8_t> wetComponent(tileStats[t][s].size(), 0);
          for (std::size_t c = 0; c < wetComponent.size() && wet[s] >= 0; ++c)
          {
            wetComponent[c] =
              groups.Find(base[s][t] + static_cast<std::int64_t>(c)) == wet[s] ? 1 : 0;
          }
          reply.PutVector(wetComponent);
        }
        std::vector<std::int32_t> ringBody;
        ForRing(boxes[t],
          reaches[t],
          nx,
          ny,
          [&](int ii, int jj)
          {
            std::int32_t body = 0;
            for (std::size_t k = 0; k < order.size() && body == 0; ++k)
            {
              const std::int32_t s = order[k];
              const auto it = where.find((static_cast<std::int64_t>(jj) * nx + ii) * nSeeds + s);
              if (wet[s] >= 0 && it != where.end() &&
                groups.Find(base[s][it->second.first] + it->second.second) == wet[s])
              {
                body = s + 1;
              }
            }
            ringBody.push_back(body);
          });
        reply.PutVector(ringBody);
        reply.PutVector(bodies);
        replies2.push_back(std::move(reply.Bytes));
      }
    }
    const std::vector<char> mine2 = exchange.Scatter(replies2);

    // ---- 4. This tile's cells and its ring: the first seed in order whose body holds them.
    Reader r2(mine2);
    std::vector<std::vector<std::uint8_t>> wetComponent;
    for (std::int32_t s = 0; s < nSeeds; ++s)
    {
      wetComponent.push_back(r2.GetVector<std::uint8_t>());
      if (wetComponent[s].size() != sentStats[s].size())
      {
        throw std::runtime_error("FloodFillSeedsDistributed: rank 0's bodies do not match "
                                 "this tile");
      }
    }
    const std::vector<std::int32_t> ringBody = r2.GetVector<std::int32_t>();
    DistributedFillResult result;
    result.bodies = r2.GetVector<WaterBodyStats>();
    const std::size_t n = in.view.Size();
    result.filled.assign(n, kNaN);
    result.bodyId.assign(n, 0);
    result.depth.assign(n, kNaN);
    const auto set = [&](int gi, int gj, std::int32_t body)
    {
      const std::size_t k = tile.ViewIndex(gi, gj);
      if (!HasData(in.view, k))
      {
        return;
      }
      result.bodyId[k] = body;
      result.depth[k] = body > 0
        ? static_cast<float>(level[body - 1] - static_cast<double>(in.view.data[k]))
        : 0.0f;
    };
    std::size_t next = 0;
    const TileBox ring = Grow(owned, in.reach, nx, ny);
    for (int gj = ring.j0; gj <= ring.j1 && ownedCells > 0; ++gj)
    {
      for (int gi = ring.i0; gi <= ring.i1; ++gi)
      {
        if (!owned.Contains(gi, gj))
        {
          if (next >= ringBody.size())
          {
            throw std::runtime_error("FloodFillSeedsDistributed: rank 0's ring does not match "
                                     "this tile");
          }
          set(gi, gj, ringBody[next++]);
          continue;
        }
        const std::size_t o = tile.Owned(gi, gj);
        std::int32_t body = 0;
        for (std::size_t k = 0; k < order.size() && body == 0; ++k)
        {
          const std::int32_t s = order[k];
          const std::int32_t c = component[s].empty() ? -1 : component[s][o];
          body = c >= 0 && wetComponent[s][c] ? s + 1 : 0;
        }
        set(gi, gj, body);
      }
    }
    return result;
  }
}

} // namespace hydrology
} // namespace terroir

/**
 * @file DistributedTiles.h
 * @brief What the distributed hydrology cores share (internal): plain-value messages, a tile's
 *        geometry, the checks of a partition, and the loops over a tile's ring and its
 *        neighbours in other tiles.
 *
 * Used by DistributedPriorityFlood.cxx and DistributedFlowAccumulation.cxx only; not installed.
 * A message is a byte vector of trivially copyable values (Writer); its reader checks every size
 * against what is left before it trusts it (Reader). Rank 0 fails every rank alike (FailAll,
 * CheckStatus) so that no process waits for ever.
 */
#ifndef terroir_hydrology_DistributedTiles_h
#define terroir_hydrology_DistributedTiles_h

#include "DistributedPriorityFlood.h"
#include "WaterBody.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <vector>

namespace terroir
{
namespace hydrology
{
namespace tiles
{

/// Appends plain values to a message.
class Writer
{
public:
  template<typename T>
  void Put(const T& value)
  {
    static_assert(std::is_trivially_copyable<T>::value, "plain values only");
    const char* p = reinterpret_cast<const char*>(&value);
    this->Bytes.insert(this->Bytes.end(), p, p + sizeof(T));
  }
  template<typename T>
  void PutVector(const std::vector<T>& values)
  {
    this->Put<std::uint64_t>(values.size());
    const char* p = reinterpret_cast<const char*>(values.data());
    this->Bytes.insert(this->Bytes.end(), p, p + values.size() * sizeof(T));
  }
  void PutString(const std::string& s) { this->PutVector(std::vector<char>(s.begin(), s.end())); }
  std::vector<char> Bytes;
};

/// Reads a message back, checking every size against what is left.
class Reader
{
public:
  explicit Reader(const std::vector<char>& bytes)
    : Bytes(bytes)
  {
  }
  template<typename T>
  T Get()
  {
    if (this->Bytes.size() - this->Position < sizeof(T))
    {
      throw std::runtime_error("a tile message ends too early");
    }
    T value;
    std::memcpy(&value, this->Bytes.data() + this->Position, sizeof(T));
    this->Position += sizeof(T);
    return value;
  }
  template<typename T>
  std::vector<T> GetVector()
  {
    const auto n = this->Get<std::uint64_t>();
    if (n > (this->Bytes.size() - this->Position) / sizeof(T))
    {
      throw std::runtime_error("a tile message announces more values than it holds");
    }
    std::vector<T> values(static_cast<std::size_t>(n));
    if (n > 0) // an empty vector's data() may be null, which memcpy does not take
    {
      std::memcpy(values.data(), this->Bytes.data() + this->Position, n * sizeof(T));
    }
    this->Position += static_cast<std::size_t>(n * sizeof(T));
    return values;
  }
  std::string GetString()
  {
    const std::vector<char> s = this->GetVector<char>();
    return std::string(s.begin(), s.end());
  }

private:
  const std::vector<char>& Bytes;
  std::size_t Position = 0;
};

/// The tile's geometry in one place: whole-grid and owned-box indices.
struct Tile
{
  const DistributedFillInput& in;
  int ox;
  int oy;

  explicit Tile(const DistributedFillInput& input)
    : in(input)
    , ox(std::max(0, input.owned.i1 - input.owned.i0 + 1))
    , oy(std::max(0, input.owned.j1 - input.owned.j0 + 1))
  {
  }
  std::size_t Owned(int gi, int gj) const
  {
    return static_cast<std::size_t>(gj - in.owned.j0) * static_cast<std::size_t>(ox) +
      static_cast<std::size_t>(gi - in.owned.i0);
  }
  std::size_t ViewIndex(int gi, int gj) const { return in.view.Index(gi - in.gi0, gj - in.gj0); }
  bool InWhole(int gi, int gj) const
  {
    return gi >= 0 && gj >= 0 && gi < in.wholeNx && gj < in.wholeNy;
  }
  bool Data(int gi, int gj) const { return HasData(in.view, this->ViewIndex(gi, gj)); }
  std::int64_t Global(int gi, int gj) const
  {
    return static_cast<std::int64_t>(gj) * in.wholeNx + gi;
  }
};

inline TileBox Grow(const TileBox& b, int r, int nx, int ny)
{
  return TileBox{ std::max(0, b.i0 - r),
    std::min(nx - 1, b.i1 + r),
    std::max(0, b.j0 - r),
    std::min(ny - 1, b.j1 + r) };
}

/// An empty string when the tile holds what it needs, else why not.
inline std::string CheckTile(const DistributedFillInput& in)
{
  const GridView<float>& v = in.view;
  if (in.wholeNx < 1 || in.wholeNy < 1 ||
    static_cast<double>(in.wholeNx) * in.wholeNy > std::numeric_limits<std::int32_t>::max())
  {
    return "the whole grid must have 1 to 2^31 - 1 cells";
  }
  if (in.reach < 0)
  {
    return "the reach must be >= 0";
  }
  if (in.owned.Cells() == 0)
  {
    return std::string();
  }
  if (in.owned.i0 < 0 || in.owned.j0 < 0 || in.owned.i1 >= in.wholeNx || in.owned.j1 >= in.wholeNy)
  {
    return "the owned cells reach outside the grid";
  }
  if (!v.data || v.nx < 1 || v.ny < 1 ||
    v.Size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
  {
    return "the tile's grid is empty or has more than 2^31 - 1 cells";
  }
  const TileBox need = Grow(in.owned, std::max(1, in.reach), in.wholeNx, in.wholeNy);
  if (need.i0 < in.gi0 || need.j0 < in.gj0 || need.i1 > in.gi0 + v.nx - 1 ||
    need.j1 > in.gj0 + v.ny - 1)
  {
    return "the tile's grid (columns " + std::to_string(in.gi0) + ".." +
      std::to_string(in.gi0 + v.nx - 1) + ", rows " + std::to_string(in.gj0) + ".." +
      std::to_string(in.gj0 + v.ny - 1) + ") lacks the ring of " +
      std::to_string(std::max(1, in.reach)) + " around its owned cells";
  }
  return std::string();
}

/// Rank 0: an empty string when the boxes partition the grid, else why not.
inline std::string CheckPartition(const std::vector<TileBox>& boxes, int nx, int ny)
{
  long long total = 0;
  for (std::size_t a = 0; a < boxes.size(); ++a)
  {
    total += boxes[a].Cells();
    for (std::size_t b = 0; b < a && boxes[a].Cells() > 0; ++b)
    {
      const TileBox& p = boxes[a];
      const TileBox& q = boxes[b];
      if (q.Cells() > 0 && p.i0 <= q.i1 && q.i0 <= p.i1 && p.j0 <= q.j1 && q.j0 <= p.j1)
      {
        return "the tiles of ranks " + std::to_string(b) + " and " + std::to_string(a) + " overlap";
      }
    }
  }
  if (total != static_cast<long long>(nx) * ny)
  {
    return "the tiles cover " + std::to_string(total) + " cells of a grid of " +
      std::to_string(static_cast<long long>(nx) * ny);
  }
  return std::string();
}

/// Union-find with path halving; the smaller index becomes the root.
struct Groups
{
  std::vector<std::int64_t> parent;
  explicit Groups(std::size_t n)
    : parent(n)
  {
    std::iota(parent.begin(), parent.end(), std::int64_t(0));
  }
  std::int64_t Find(std::int64_t x)
  {
    while (parent[x] != x)
    {
      parent[x] = parent[parent[x]];
      x = parent[x];
    }
    return x;
  }
  void Join(std::int64_t a, std::int64_t b)
  {
    a = this->Find(a);
    b = this->Find(b);
    if (a != b)
    {
      parent[std::max(a, b)] = std::min(a, b);
    }
  }
};

/// Rank 0 fails every rank alike: the reply to each is the status 1 and the reason.
inline std::vector<std::vector<char>> FailAll(int ranks, const std::string& why)
{
  Writer w;
  w.Put<std::uint8_t>(1);
  w.PutString(why);
  return std::vector<std::vector<char>>(static_cast<std::size_t>(ranks), w.Bytes);
}

/// Reads the status at the head of a reply; throws std::invalid_argument naming `function` on
/// failure.
inline void CheckStatus(Reader& r, const char* function)
{
  if (r.Get<std::uint8_t>() != 0)
  {
    throw std::invalid_argument(std::string(function) + ": " + r.GetString());
  }
}

/// The head of every tile's first message: its status, its tile and what it needs.
inline void WriteHead(Writer& w, const std::string& problem, const DistributedFillInput& in)
{
  w.Put<std::uint8_t>(problem.empty() ? 0 : 1);
  w.PutString(problem);
  w.Put(in.owned);
  w.Put<std::int32_t>(in.wholeNx);
  w.Put<std::int32_t>(in.wholeNy);
  w.Put<std::int32_t>(in.reach);
}

/// Rank 0 reads the head of tile t's first message into boxes and reaches; returns why it
/// cannot go on ("" when it can).
inline std::string ReadHead(Reader& r,
  int t,
  int nx,
  int ny,
  std::vector<TileBox>& boxes,
  std::vector<std::int32_t>& reaches)
{
  const bool failed = r.Get<std::uint8_t>() != 0;
  const std::string message = r.GetString();
  if (failed)
  {
    return "rank " + std::to_string(t) + ": " + message;
  }
  boxes.push_back(r.Get<TileBox>());
  const auto wnx = r.Get<std::int32_t>();
  const auto wny = r.Get<std::int32_t>();
  reaches.push_back(r.Get<std::int32_t>());
  if (wnx != nx || wny != ny)
  {
    return "rank " + std::to_string(t) + " sees a grid of " + std::to_string(wnx) + " x " +
      std::to_string(wny) + ", rank 0 one of " + std::to_string(nx) + " x " + std::to_string(ny);
  }
  return std::string();
}

/// Calls f(i, j) for the cells of `box` grown by `reach` (within the grid) outside `box`, row
/// by row: the ring whose results a tile's caller wants.
template<typename F>
void ForRing(const TileBox& box, int reach, int nx, int ny, F f)
{
  const TileBox ring = Grow(box, reach, nx, ny);
  for (int j = ring.j0; j <= ring.j1 && box.Cells() > 0; ++j)
  {
    for (int i = ring.i0; i <= ring.i1; ++i)
    {
      if (!box.Contains(i, j))
      {
        f(i, j);
      }
    }
  }
}

/// Calls f(q) for the 8-neighbours of whole-grid cell `cell` that lie in the grid outside
/// `box` (in other tiles), q their whole-grid index.
template<typename F>
void ForOtherTiles(std::int64_t cell, const TileBox& box, int nx, int ny, F f)
{
  const int gi = static_cast<int>(cell % nx);
  const int gj = static_cast<int>(cell / nx);
  for (int e = 0; e < 8; ++e)
  {
    const int ii = gi + detail::kNeighbourDi[e];
    const int jj = gj + detail::kNeighbourDj[e];
    if (ii >= 0 && jj >= 0 && ii < nx && jj < ny && !box.Contains(ii, jj))
    {
      f(static_cast<std::int64_t>(jj) * nx + ii);
    }
  }
}
/// True when owned cell (gi, gj) of `box` lies within `width` cells of another tile (of a
/// neighbouring cell of the grid outside `box`): the band whose values other tiles' rings hold.
inline bool InBand(const TileBox& box, int gi, int gj, int width, int nx, int ny)
{
  return (box.i0 > 0 && gi - box.i0 < width) || (box.i1 < nx - 1 && box.i1 - gi < width) ||
    (box.j0 > 0 && gj - box.j0 < width) || (box.j1 < ny - 1 && box.j1 - gj < width);
}

/**
 * Every tile's ring of `in.reach` cells gets the values its owners hold, through rank 0 (a
 * collective call). `values` is view-sized (in.view's indices): each tile reads its owned cells
 * within `width` of another tile and receives, in place, the values of its ring (cells outside
 * the grid are not asked; a ring cell no tile sent gets `missing`). `width` must be at least
 * every tile's reach, the same on every rank. `flag`, when given: in, this tile's; out, the OR
 * of every tile's. Throws std::runtime_error naming `function` (on every rank alike) on a
 * malformed message.
 */
template<typename T>
void ExchangeRing(const DistributedFillInput& in,
  int width,
  T* values,
  T missing,
  TileExchange& exchange,
  std::uint8_t* flag,
  const char* function)
{
  const Tile tile(in);
  const int nx = in.wholeNx;
  const int ny = in.wholeNy;
  std::vector<std::int64_t> cells;
  std::vector<T> band;
  for (int gj = in.owned.j0; gj <= in.owned.j1 && in.owned.Cells() > 0; ++gj)
  {
    for (int gi = in.owned.i0; gi <= in.owned.i1; ++gi)
    {
      if (InBand(in.owned, gi, gj, width, nx, ny))
      {
        cells.push_back(tile.Global(gi, gj));
        band.push_back(values[tile.ViewIndex(gi, gj)]);
      }
    }
  }
  Writer w;
  w.Put(in.owned);
  w.Put<std::int32_t>(in.reach);
  w.Put<std::uint8_t>(flag ? *flag : 0);
  w.PutVector(cells);
  w.PutVector(band);
  const std::vector<std::vector<char>> all = exchange.Gather(w.Bytes);
  std::vector<std::vector<char>> replies;
  if (exchange.Rank() == 0)
  {
    try
    {
      std::vector<TileBox> boxes;
      std::vector<std::int32_t> reaches;
      std::uint8_t any = 0;
      std::unordered_map<std::int64_t, T> where;
      for (const std::vector<char>& bytes : all)
      {
        Reader r(bytes);
        boxes.push_back(r.Get<TileBox>());
        reaches.push_back(r.Get<std::int32_t>());
        any = static_cast<std::uint8_t>(any | r.Get<std::uint8_t>());
        const std::vector<std::int64_t> c = r.GetVector<std::int64_t>();
        const std::vector<T> v = r.GetVector<T>();
        if (c.size() != v.size() || reaches.back() > width)
        {
          throw std::runtime_error("a tile's band does not match its values or is too narrow");
        }
        for (std::size_t b = 0; b < c.size(); ++b)
        {
          where.emplace(c[b], v[b]);
        }
      }
      for (std::size_t t = 0; t < boxes.size(); ++t)
      {
        std::vector<T> ring;
        ForRing(boxes[t],
          reaches[t],
          nx,
          ny,
          [&](int ii, int jj)
          {
            const auto it = where.find(static_cast<std::int64_t>(jj) * nx + ii);
            ring.push_back(it == where.end() ? missing : it->second);
          });
        Writer reply;
        reply.Put<std::uint8_t>(0);
        reply.Put<std::uint8_t>(any);
        reply.PutVector(ring);
        replies.push_back(std::move(reply.Bytes));
      }
    }
    catch (const std::exception& x)
    {
      replies = FailAll(exchange.Size(), x.what());
    }
  }
  const std::vector<char> mine = exchange.Scatter(replies);
  Reader r(mine);
  CheckStatus(r, function);
  const auto any = r.Get<std::uint8_t>();
  const std::vector<T> ring = r.GetVector<T>();
  std::size_t next = 0;
  ForRing(in.owned,
    in.reach,
    nx,
    ny,
    [&](int gi, int gj)
    {
      if (next >= ring.size())
      {
        throw std::runtime_error(
          std::string(function) + ": rank 0's ring does not match this tile");
      }
      values[tile.ViewIndex(gi, gj)] = ring[next++];
    });
  if (flag)
  {
    *flag = any;
  }
}
} // namespace tiles
} // namespace hydrology
} // namespace terroir

#endif

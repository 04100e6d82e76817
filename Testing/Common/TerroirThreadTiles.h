// Tiles on threads for the tests of the distributed cores (DistributedPriorityFlood.h,
// DistributedFlowAccumulation.h): threads stand in for MPI processes, each with a copy of its
// own tile; random terrains and uneven partitions.
#ifndef TerroirThreadTiles_h
#define TerroirThreadTiles_h

#include "DistributedPriorityFlood.h"
#include "GridView.h"

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <limits>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <vector>

namespace terroir_test
{
namespace hy = terroir::hydrology;
using terroir::GridView;

/// The collective calls of `ranks` threads: each call waits until every thread has come.
class ThreadMailbox
{
public:
  explicit ThreadMailbox(int ranks)
    : Ranks(ranks)
    , Slots(static_cast<std::size_t>(ranks))
    , SentBytes(static_cast<std::size_t>(ranks), 0)
  {
  }
  void Barrier()
  {
    std::unique_lock<std::mutex> lock(this->Mutex);
    const long long generation = this->Generation;
    if (++this->Waiting == this->Ranks)
    {
      this->Waiting = 0;
      ++this->Generation;
      this->Wake.notify_all();
      return;
    }
    this->Wake.wait(lock, [&] { return this->Generation != generation; });
  }
  int Ranks;
  std::vector<std::vector<char>> Slots;
  std::vector<std::size_t> SentBytes; ///< per rank: bytes each has given to Gather, in all
  std::vector<std::vector<char>> Parts;

private:
  std::mutex Mutex;
  std::condition_variable Wake;
  int Waiting = 0;
  long long Generation = 0;
};

/// One thread's TileExchange over a shared ThreadMailbox.
class ThreadExchange : public hy::TileExchange
{
public:
  ThreadExchange(ThreadMailbox& box, int rank)
    : Box(box)
    , MyRank(rank)
  {
  }
  int Rank() const override { return this->MyRank; }
  int Size() const override { return this->Box.Ranks; }
  std::vector<std::vector<char>> Gather(const std::vector<char>& mine) override
  {
    this->Box.Slots[this->MyRank] = mine;
    this->Box.SentBytes[this->MyRank] += mine.size();
    this->Box.Barrier();
    std::vector<std::vector<char>> all;
    if (this->MyRank == 0)
    {
      all = this->Box.Slots;
    }
    this->Box.Barrier();
    return all;
  }
  std::vector<char> Scatter(const std::vector<std::vector<char>>& parts) override
  {
    if (this->MyRank == 0)
    {
      this->Box.Parts = parts;
    }
    this->Box.Barrier();
    std::vector<char> mine = this->Box.Parts.at(static_cast<std::size_t>(this->MyRank));
    this->Box.Barrier();
    return mine;
  }

private:
  ThreadMailbox& Box;
  int MyRank;
};

/// A whole grid with a mask and a different east-west spacing on every row.
struct Terrain
{
  int nx = 0;
  int ny = 0;
  std::vector<float> z;
  std::vector<std::uint8_t> valid;
  std::vector<double> rowDx;
  GridView<float> View() const
  {
    GridView<float> v;
    v.data = z.data();
    v.nx = nx;
    v.ny = ny;
    v.dy = 2.0;
    v.rowDx = rowDx.data();
    v.valid = valid.data();
    return v;
  }
};

/// A copy of the cells of `box` (whole-grid indices), as a process would hold them.
struct TileCopy
{
  Terrain t;
  int gi0 = 0;
  int gj0 = 0;
};

inline TileCopy CopyOf(const Terrain& w, const hy::TileBox& box)
{
  TileCopy c;
  c.gi0 = box.i0;
  c.gj0 = box.j0;
  c.t.nx = box.i1 - box.i0 + 1;
  c.t.ny = box.j1 - box.j0 + 1;
  for (int j = box.j0; j <= box.j1; ++j)
  {
    c.t.rowDx.push_back(w.rowDx[j]);
    for (int i = box.i0; i <= box.i1; ++i)
    {
      c.t.z.push_back(w.z[static_cast<std::size_t>(j) * w.nx + i]);
      c.t.valid.push_back(w.valid[static_cast<std::size_t>(j) * w.nx + i]);
    }
  }
  return c;
}

/// `cuts` + 1 uneven pieces of [0, n): random cut points (some pieces may be one cell).
inline std::vector<int> Cuts(std::mt19937_64& rng, int n, int pieces)
{
  std::vector<int> at{ 0 };
  for (int p = 1; p < pieces; ++p)
  {
    at.push_back(1 + static_cast<int>(rng() % static_cast<std::uint64_t>(std::max(1, n - 1))));
  }
  at.push_back(n);
  std::sort(at.begin(), at.end());
  at.erase(std::unique(at.begin(), at.end()), at.end());
  return at;
}

inline std::vector<hy::TileBox> Blocks(const std::vector<int>& ci, const std::vector<int>& cj)
{
  std::vector<hy::TileBox> boxes;
  for (std::size_t b = 0; b + 1 < cj.size(); ++b)
  {
    for (std::size_t a = 0; a + 1 < ci.size(); ++a)
    {
      boxes.push_back(hy::TileBox{ ci[a], ci[a + 1] - 1, cj[b], cj[b + 1] - 1 });
    }
  }
  return boxes;
}

inline Terrain RandomTerrain(std::mt19937_64& rng,
  int nx,
  int ny,
  bool quantised,
  int noDataPerMille)
{
  Terrain t;
  t.nx = nx;
  t.ny = ny;
  for (int j = 0; j < ny; ++j)
  {
    t.rowDx.push_back(1.0 + 0.01 * j);
    for (int i = 0; i < nx; ++i)
    {
      const double u = static_cast<double>(rng() >> 11) / 9007199254740992.0;
      float z =
        quantised ? static_cast<float>(std::floor(u * 8.0)) : static_cast<float>(100.0 + 25.0 * u);
      std::uint8_t ok = 1;
      if (static_cast<int>(rng() % 1000) < noDataPerMille)
      {
        if (rng() % 2 == 0)
        {
          z = std::numeric_limits<float>::quiet_NaN();
        }
        else
        {
          ok = 0;
        }
      }
      t.z.push_back(z);
      t.valid.push_back(ok);
    }
  }
  return t;
}
/// The copy of the whole grid a process holds for tile `b`: the box grown by `halo` cells
/// (clipped to the grid), or one cell for an empty box.
inline TileCopy HaloCopy(const Terrain& w, const hy::TileBox& b, int halo)
{
  hy::TileBox g{ std::max(0, b.i0 - halo),
    std::min(w.nx - 1, b.i1 + halo),
    std::max(0, b.j0 - halo),
    std::min(w.ny - 1, b.j1 + halo) };
  if (b.Cells() == 0)
  {
    g = hy::TileBox{ 0, 0, 0, 0 };
  }
  return CopyOf(w, g);
}

/// The input of a distributed core for tile `owned` held as `copy`.
inline hy::DistributedFillInput TileInput(const Terrain& w,
  const TileCopy& copy,
  const hy::TileBox& owned,
  int reach)
{
  hy::DistributedFillInput in;
  in.view = copy.t.View();
  in.gi0 = copy.gi0;
  in.gj0 = copy.gj0;
  in.owned = owned;
  in.wholeNx = w.nx;
  in.wholeNy = w.ny;
  in.reach = reach;
  return in;
}

/// Runs f(rank, exchange) on `ranks` threads, each with its own exchange; returns each rank's
/// exception message ("" when none) and, when asked, the bytes each rank gave to Gather.
template<typename F>
std::vector<std::string> RunOnThreads(int ranks, F f, std::vector<std::size_t>* sentBytes = nullptr)
{
  ThreadMailbox box(ranks);
  std::vector<std::string> errors(static_cast<std::size_t>(ranks));
  std::vector<std::thread> threads;
  for (int r = 0; r < ranks; ++r)
  {
    threads.emplace_back(
      [&, r]
      {
        ThreadExchange exchange(box, r);
        try
        {
          f(r, exchange);
        }
        catch (const std::exception& e)
        {
          errors[r] = e.what();
        }
      });
  }
  for (std::thread& t : threads)
  {
    t.join();
  }
  if (sentBytes)
  {
    *sentBytes = box.SentBytes;
  }
  return errors;
}
} // namespace terroir_test

#endif

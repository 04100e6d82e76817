// Unit tests of the water flow's hooks for distributed runs (WaterFlowSimulation::SetCountWindow,
// SetIterationHook, the smallest-spacing argument): a grid cut into pieces, each run on its own
// thread on its piece grown by 3 cells, the hook refreshing the cells within 2 of the piece from
// the pieces that own them and adding the pieces' sums in piece order, as vtkTerroirWaterFlow does
// over MPI. Expected answers come from the whole grid run in one simulation: the same water and
// discharge on every cell, bit for bit (every cell's update reads the same values in the same
// order), the same stop iteration and reason, and the volumes within 1e-12 relative (the same
// terms added in another order). A run whose hook only adds the sums (no halo refresh) must
// differ: water crosses the pieces' boundaries.
#include "WaterFlow.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <random>
#include <stdexcept>
#include <thread>
#include <vector>

namespace
{
namespace hy = terroir::hydrology;

/// Cells [i0, i1) x [j0, j1).
struct Block
{
  int i0, i1, j0, j1;
  bool Has(int i, int j) const { return i >= i0 && i < i1 && j >= j0 && j < j1; }
};

/// A reusable barrier for the piece threads.
class Barrier
{
public:
  explicit Barrier(int n)
    : N(n)
  {
  }
  void Wait()
  {
    std::unique_lock<std::mutex> lock(this->M);
    const long generation = this->Generation;
    if (++this->Count == this->N)
    {
      this->Count = 0;
      ++this->Generation;
      this->C.notify_all();
    }
    else
    {
      this->C.wait(lock, [&] { return this->Generation != generation; });
    }
  }

private:
  std::mutex M;
  std::condition_variable C;
  int N;
  int Count = 0;
  long Generation = 0;
};

/// A terrain whose valley runs diagonally across the grid (so across the pieces' boundaries),
/// with bumps from a fixed seed (our own mapping to [0, 1)), uneven rows (per-row spacing) and
/// a few no-data cells beside the boundaries.
struct Terrain
{
  int nx = 40, ny = 32;
  std::vector<float> z;
  std::vector<std::uint8_t> valid;
  std::vector<double> rowDx, rowDy, water;

  Terrain()
  {
    std::mt19937_64 random(2517);
    z.resize(static_cast<std::size_t>(nx) * ny);
    valid.assign(z.size(), 1);
    water.assign(z.size(), 0.05);
    for (int j = 0; j < ny; ++j)
    {
      rowDx.push_back(10.0 - 0.01 * j); // a geographic grid's narrowing rows
      rowDy.push_back(10.0);
      for (int i = 0; i < nx; ++i)
      {
        const double u = static_cast<double>(random() >> 11) * 0x1.0p-53;
        const double thalweg = 0.3 * nx + 0.5 * j;
        z[static_cast<std::size_t>(j) * nx + i] =
          static_cast<float>(std::abs(i - thalweg) * 0.8 + 0.05 * j + 0.3 * u);
      }
    }
    for (const auto& c : { std::array<int, 2>{ 19, 10 }, { 21, 15 }, { 5, 16 }, { 30, 17 } })
    {
      valid[static_cast<std::size_t>(c[1]) * nx + c[0]] = 0;
    }
  }
  terroir::GridView<float> View() const
  {
    terroir::GridView<float> v;
    v.data = z.data();
    v.nx = nx;
    v.ny = ny;
    v.rowDx = rowDx.data();
    v.rowDy = rowDy.data();
    v.valid = valid.data();
    return v;
  }
};

/// What a run gave: water height and discharge per cell of the whole grid, and its totals.
struct Result
{
  std::vector<float> height;
  std::vector<double> discharge;
  long long iterations = 0;
  hy::WaterFlowStopReason reason = hy::WaterFlowStopReason::MaximumIterations;
  double moved = 0.0, outflow = 0.0, stored = 0.0;
};

Result Whole(const Terrain& t, const hy::WaterFlowStopRule& rule)
{
  hy::WaterFlowSimulation sim(t.View(), t.water.data());
  Result r;
  r.reason = sim.Run(rule);
  r.iterations = sim.Iterations();
  r.height.resize(t.z.size());
  r.discharge.resize(t.z.size());
  sim.GetWaterHeight(r.height.data());
  sim.GetDischarge(r.discharge.data());
  r.moved = sim.TotalMoved();
  r.outflow = sim.TotalOutflow();
  r.stored = sim.StoredVolume();
  return r;
}

/// The grid cut into px x py pieces, each on its own thread; `exchange` false: the hook only adds
/// the sums (a wrong distributed run, for the control).
Result Pieces(const Terrain& t, int px, int py, const hy::WaterFlowStopRule& rule, bool exchange)
{
  const int n = px * py;
  std::vector<Block> owned, grid;
  for (int b = 0; b < py; ++b)
  {
    for (int a = 0; a < px; ++a)
    {
      const Block o{ a * t.nx / px, (a + 1) * t.nx / px, b * t.ny / py, (b + 1) * t.ny / py };
      owned.push_back(o);
      grid.push_back({ std::max(o.i0 - 3, 0),
        std::min(o.i1 + 3, t.nx),
        std::max(o.j0 - 3, 0),
        std::min(o.j1 + 3, t.ny) });
    }
  }
  const double dmin = hy::WaterFlowSimulation::SmallestSpacing(t.View());
  std::vector<std::unique_ptr<hy::WaterFlowSimulation>> sims(n);
  // Each piece's copy of its grid (terrain, mask, spacing, water).
  std::vector<Terrain> local(n, t);
  for (int p = 0; p < n; ++p)
  {
    const Block& g = grid[p];
    Terrain& l = local[p];
    l.nx = g.i1 - g.i0;
    l.ny = g.j1 - g.j0;
    l.z.clear();
    l.valid.clear();
    l.water.clear();
    l.rowDx.assign(t.rowDx.begin() + g.j0, t.rowDx.begin() + g.j1);
    l.rowDy.assign(t.rowDy.begin() + g.j0, t.rowDy.begin() + g.j1);
    for (int j = g.j0; j < g.j1; ++j)
    {
      for (int i = g.i0; i < g.i1; ++i)
      {
        const std::size_t c = static_cast<std::size_t>(j) * t.nx + i;
        l.z.push_back(t.z[c]);
        l.valid.push_back(t.valid[c]);
        l.water.push_back(t.water[c]);
      }
    }
    sims[p].reset(new hy::WaterFlowSimulation(l.View(), l.water.data(), dmin));
    // Padded window: the owned cells, and the grid's border where the piece touches it.
    const Block& o = owned[p];
    sims[p]->SetCountWindow(o.i0 == 0 ? 0 : o.i0 - g.i0 + 1,
      o.i1 == t.nx ? l.nx + 2 : o.i1 - g.i0 + 1,
      o.j0 == 0 ? 0 : o.j0 - g.j0 + 1,
      o.j1 == t.ny ? l.ny + 2 : o.j1 - g.j0 + 1);
  }
  const auto padded = [&](int p, int i, int j)
  {
    return static_cast<std::size_t>(j - grid[p].j0 + 1) * (grid[p].i1 - grid[p].i0 + 2) +
      static_cast<std::size_t>(i - grid[p].i0 + 1);
  };
  Barrier barrier(n);
  std::vector<std::array<double, 3>> sums(n);
  for (int p = 0; p < n; ++p)
  {
    sims[p]->SetIterationHook(
      [&, p](hy::WaterFlowSimulation& sim, hy::WaterFlowIteration& it)
      {
        sums[p] = { it.moved, it.outflow, it.emptied };
        barrier.Wait(); // every piece has its new state
        if (exchange)
        {
          const Block near{ owned[p].i0 - 2, owned[p].i1 + 2, owned[p].j0 - 2, owned[p].j1 + 2 };
          for (int j = grid[p].j0; j < grid[p].j1; ++j)
          {
            for (int i = grid[p].i0; i < grid[p].i1; ++i)
            {
              for (int q = 0; q < n && near.Has(i, j) && !owned[p].Has(i, j); ++q)
              {
                if (owned[q].Has(i, j))
                {
                  sim.PaddedWater()[padded(p, i, j)] = sims[q]->PaddedWater()[padded(q, i, j)];
                }
              }
            }
          }
        }
        it = hy::WaterFlowIteration();
        for (int q = 0; q < n; ++q)
        {
          it.moved += sums[q][0];
          it.outflow += sums[q][1];
          it.emptied += sums[q][2];
        }
        barrier.Wait(); // every piece has read the others
      });
  }
  std::vector<hy::WaterFlowStopReason> reasons(n);
  std::vector<std::thread> threads;
  for (int p = 0; p < n; ++p)
  {
    threads.emplace_back([&, p] { reasons[p] = sims[p]->Run(rule); });
  }
  for (std::thread& th : threads)
  {
    th.join();
  }
  Result r;
  r.height.assign(t.z.size(), -1.0f);
  r.discharge.assign(t.z.size(), -1.0);
  r.iterations = sims[0]->Iterations();
  r.reason = reasons[0];
  r.moved = sims[0]->TotalMoved();
  r.outflow = sims[0]->TotalOutflow();
  for (int p = 0; p < n; ++p)
  {
    EXPECT_EQ(sims[p]->Iterations(), r.iterations) << "piece " << p;
    EXPECT_EQ(reasons[p], r.reason) << "piece " << p;
    EXPECT_EQ(sims[p]->TotalMoved(), r.moved) << "piece " << p; // the same sums everywhere
    const std::size_t cells = static_cast<std::size_t>(sims[p]->Nx()) * sims[p]->Ny();
    std::vector<float> h(cells);
    std::vector<double> q(cells);
    sims[p]->GetWaterHeight(h.data());
    sims[p]->GetDischarge(q.data());
    r.stored += sims[p]->StoredVolume(); // the owned cells' (the count window)
    for (int j = owned[p].j0; j < owned[p].j1; ++j)
    {
      for (int i = owned[p].i0; i < owned[p].i1; ++i)
      {
        const std::size_t c = static_cast<std::size_t>(j - grid[p].j0) * sims[p]->Nx() +
          static_cast<std::size_t>(i - grid[p].i0);
        r.height[static_cast<std::size_t>(j) * t.nx + i] = h[c];
        r.discharge[static_cast<std::size_t>(j) * t.nx + i] = q[c];
      }
    }
  }
  return r;
}

/// Cells whose bits differ (NaN equal to NaN).
template<typename T>
int Differences(const std::vector<T>& a, const std::vector<T>& b)
{
  int d = 0;
  for (std::size_t c = 0; c < a.size(); ++c)
  {
    d += (a[c] == b[c] || (std::isnan(a[c]) && std::isnan(b[c]))) ? 0 : 1;
  }
  return d;
}

void ExpectSameRun(const Result& whole, const Result& pieces)
{
  EXPECT_EQ(pieces.iterations, whole.iterations);
  EXPECT_EQ(pieces.reason, whole.reason);
  EXPECT_EQ(Differences(pieces.height, whole.height), 0);
  EXPECT_EQ(Differences(pieces.discharge, whole.discharge), 0);
  EXPECT_NEAR(pieces.moved, whole.moved, 1e-12 * whole.moved);
  EXPECT_NEAR(pieces.outflow, whole.outflow, 1e-12 * whole.outflow);
  EXPECT_NEAR(pieces.stored, whole.stored, 1e-12 * whole.stored);
}
} // namespace

TEST(TerroirWaterFlowPieces, TwoPiecesGiveTheWholeGridsRun)
{
  const Terrain t;
  hy::WaterFlowStopRule rule;
  const Result whole = Whole(t, rule);
  ASSERT_GT(whole.iterations, 20);
  ASSERT_GT(whole.outflow, 0.0);
  ExpectSameRun(whole, Pieces(t, 2, 1, rule, true));
}

TEST(TerroirWaterFlowPieces, FourAndSixPiecesGiveTheWholeGridsRun)
{
  const Terrain t;
  hy::WaterFlowStopRule rule;
  const Result whole = Whole(t, rule);
  ExpectSameRun(whole, Pieces(t, 2, 2, rule, true));
  ExpectSameRun(whole, Pieces(t, 3, 2, rule, true));
}

TEST(TerroirWaterFlowPieces, WithoutTheHaloExchangeThePiecesDiffer)
{
  // The control: the same pieces whose halo keeps its initial water. Water crosses the
  // boundaries, so some cell must differ.
  const Terrain t;
  hy::WaterFlowStopRule rule;
  rule.autoStopRatio = 0.0;
  rule.maximumIterations = 30;
  const Result whole = Whole(t, rule);
  const Result wrong = Pieces(t, 2, 2, rule, false);
  EXPECT_GT(Differences(wrong.height, whole.height), 0);
  ExpectSameRun(whole, Pieces(t, 2, 2, rule, true));
}

TEST(TerroirWaterFlowPieces, CountWindowMustLieInThePaddedGrid)
{
  const Terrain t;
  hy::WaterFlowSimulation sim(t.View(), t.water.data());
  EXPECT_THROW(sim.SetCountWindow(0, t.nx + 3, 0, 4), std::invalid_argument);
  EXPECT_THROW(sim.SetCountWindow(5, 5, 0, 4), std::invalid_argument);
  EXPECT_FALSE(sim.HasCountWindow());
  sim.SetCountWindow(0, t.nx + 2, 0, t.ny + 2); // the whole padded grid: the serial sums
  EXPECT_TRUE(sim.HasCountWindow());
  EXPECT_THROW(hy::WaterFlowSimulation(t.View(), t.water.data(), 1e9), std::invalid_argument);
}

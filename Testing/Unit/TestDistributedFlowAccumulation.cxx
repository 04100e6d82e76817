// Unit tests of terroir::hydrology::D8FlowAccumulationDistributed (D8 directions and
// accumulation of a grid split into tiles: the flats' distances relaxed across tiles, Barnes
// 2017's perimeter graph). Threads stand in for MPI processes; each sees only a copy of its own
// tile and the ring around it. The answer is the serial PriorityFloodBarnes2014 +
// D8FlowDirections + D8FlowAccumulation on the whole grid (checked by brute force and by hand
// in TestFlowAccumulation.cxx).
#include "DistributedFlowAccumulation.h"
#include "FlowAccumulation.h"
#include "MultipleFlow.h"
#include "PriorityFlood.h"
#include "TerroirThreadTiles.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace
{
namespace hy = terroir::hydrology;
using terroir::GridView;
using namespace terroir_test;

/// The accumulation under test: D8 (D8FlowAccumulationDistributed), or MFD or D-infinity
/// (DispersiveFlowAccumulationDistributed).
struct Method
{
  enum Kind
  {
    D8,
    MFD,
    DInfinity
  } kind = D8;
  hy::MFDOptions mfd;
};

/// The serial answer on the whole grid.
struct Serial
{
  std::vector<float> filled;
  std::vector<std::int8_t> direction;
  std::vector<double> cells;
  std::vector<double> area;
  std::vector<double> weighted;
  std::vector<float> angle; ///< D-infinity
  hy::D8Summary summary;
};

Serial RunSerial(const Terrain& w, const float* weight, const Method& method = Method())
{
  const GridView<float> v = w.View();
  Serial s;
  s.filled.resize(v.Size());
  s.direction.resize(v.Size());
  s.cells.resize(v.Size());
  s.area.resize(v.Size());
  hy::PriorityFloodBarnes2014(v, s.filled.data());
  s.summary = hy::D8FlowDirections(v, s.filled.data(), s.direction.data());
  const auto accumulate =
    [&](const float* wt, double* out, const hy::AccumulationOptions& o, float* angle)
  {
    if (method.kind == Method::MFD)
    {
      hy::MultipleFlowAccumulation(v, s.filled.data(), s.direction.data(), method.mfd, wt, out, o);
    }
    else if (method.kind == Method::DInfinity)
    {
      hy::DInfinityAccumulation(v, s.filled.data(), s.direction.data(), wt, out, angle, o);
    }
    else
    {
      hy::D8FlowAccumulation(v, s.direction.data(), wt, out, o);
    }
  };
  if (method.kind == Method::DInfinity)
  {
    s.angle.resize(v.Size());
  }
  accumulate(nullptr, s.cells.data(), {}, s.angle.empty() ? nullptr : s.angle.data());
  hy::AccumulationOptions area;
  area.timesCellArea = true;
  accumulate(nullptr, s.area.data(), area, nullptr);
  if (weight)
  {
    s.weighted.resize(v.Size());
    hy::AccumulationOptions o;
    o.scale = 1e-3;
    accumulate(weight, s.weighted.data(), o, nullptr);
  }
  return s;
}

struct Outcome
{
  std::vector<TileCopy> copies;
  std::vector<std::vector<float>> weights; ///< per rank, the copy's weights
  std::vector<hy::DistributedFlowResult> results;
  std::vector<std::string> errors;
  std::vector<std::size_t> sentBytes;
};

/// Every tile on its own thread, holding its box grown by `halo`.
Outcome RunTiles(const Terrain& w,
  const std::vector<hy::TileBox>& owned,
  int reach,
  int halo,
  const std::vector<float>* weight,
  const Method& method = Method())
{
  Outcome out;
  out.results.resize(owned.size());
  for (const hy::TileBox& b : owned)
  {
    out.copies.push_back(HaloCopy(w, b, halo));
    std::vector<float> local;
    const TileCopy& c = out.copies.back();
    for (int j = 0; weight && j < c.t.ny; ++j)
    {
      for (int i = 0; i < c.t.nx; ++i)
      {
        local.push_back((*weight)[static_cast<std::size_t>(j + c.gj0) * w.nx + (i + c.gi0)]);
      }
    }
    out.weights.push_back(local);
  }
  out.errors = RunOnThreads(
    static_cast<int>(owned.size()),
    [&](int r, ThreadExchange& exchange)
    {
      hy::DistributedFlowOptions options;
      options.weight = weight ? out.weights[r].data() : nullptr;
      options.weightScale = 1e-3;
      const hy::DistributedFillInput in = TileInput(w, out.copies[r], owned[r], reach);
      if (method.kind == Method::D8)
      {
        out.results[r] = hy::D8FlowAccumulationDistributed(in, options, exchange);
        return;
      }
      hy::DispersiveFlowMethod dispersive;
      dispersive.dInfinity = method.kind == Method::DInfinity;
      dispersive.mfd = method.mfd;
      out.results[r] = hy::DispersiveFlowAccumulationDistributed(in, dispersive, options, exchange);
    },
    &out.sentBytes);
  return out;
}

bool Same(double a, double b)
{
  return (std::isnan(a) && std::isnan(b)) || a == b;
}

bool Near(double a, double b)
{
  return (std::isnan(a) && std::isnan(b)) || std::abs(a - b) <= 1e-12 * std::abs(b);
}

/// Every tile's owned cells and ring equal the serial answer (the dispersive methods' cell
/// counts to 1e-12: their sums add a tile's inflow as one term). Returns the largest number of
/// exchanges the flats took (`rounds`, when given: the dispersive sums' rounds).
int ExpectSerial(const Terrain& w,
  const std::vector<hy::TileBox>& owned,
  int reach,
  const std::vector<float>* weight,
  const std::string& what,
  const Method& method = Method(),
  int* rounds = nullptr)
{
  const Serial s = RunSerial(w, weight ? weight->data() : nullptr, method);
  const Outcome out = RunTiles(w, owned, reach, reach + 1, weight, method);
  int exchanges = 0;
  for (std::size_t r = 0; r < owned.size(); ++r)
  {
    if (!out.errors[r].empty())
    {
      ADD_FAILURE() << what << " rank " << r << ": " << out.errors[r];
      return 0;
    }
    const hy::DistributedFlowResult& got = out.results[r];
    exchanges = std::max(exchanges, got.flatExchanges);
    if (rounds)
    {
      *rounds = std::max(*rounds, got.accumulationRounds);
    }
    EXPECT_EQ(got.angle.empty(), method.kind != Method::DInfinity) << what;
    EXPECT_EQ(got.summary.outlets, s.summary.outlets) << what;
    EXPECT_EQ(got.summary.flatCells, s.summary.flatCells) << what;
    EXPECT_EQ(got.summary.sinks, s.summary.sinks) << what;
    EXPECT_EQ(got.weighted.empty(), weight == nullptr) << what;
    if (owned[r].Cells() == 0)
    {
      continue;
    }
    const TileCopy& c = out.copies[r];
    const hy::TileBox ring{ std::max(0, owned[r].i0 - reach),
      std::min(w.nx - 1, owned[r].i1 + reach),
      std::max(0, owned[r].j0 - reach),
      std::min(w.ny - 1, owned[r].j1 + reach) };
    int wrong = 0;
    for (int j = ring.j0; j <= ring.j1; ++j)
    {
      for (int i = ring.i0; i <= ring.i1; ++i)
      {
        const std::size_t k = static_cast<std::size_t>(j) * w.nx + i;
        const std::size_t t = static_cast<std::size_t>(j - c.gj0) * c.t.nx + (i - c.gi0);
        const bool cellsOk = method.kind == Method::D8 ? Same(got.cells[t], s.cells[k])
                                                       : Near(got.cells[t], s.cells[k]);
        const bool ok = Same(got.filled[t], s.filled[k]) && got.direction[t] == s.direction[k] &&
          cellsOk && Near(got.area[t], s.area[k]) &&
          (!weight || Near(got.weighted[t], s.weighted[k])) &&
          (s.angle.empty() || Same(got.angle[t], s.angle[k]));
        if (!ok && ++wrong <= 3)
        {
          ADD_FAILURE() << what << " rank " << r << " cell (" << i << ", " << j << "): direction "
                        << int(got.direction[t]) << " vs serial " << int(s.direction[k])
                        << ", cells " << got.cells[t] << " vs " << s.cells[k] << ", area "
                        << got.area[t] << " vs " << s.area[k];
        }
      }
    }
  }
  return exchanges;
}

/// Random weights (mm), some NaN.
std::vector<float> RandomWeights(std::mt19937_64& rng, const Terrain& w)
{
  std::vector<float> weight;
  for (std::size_t k = 0; k < w.z.size(); ++k)
  {
    weight.push_back(rng() % 17 == 0 ? std::nanf("") : static_cast<float>(rng() % 1000) * 0.37f);
  }
  return weight;
}

/// Random case t: a terrain of 3 to 42 cells a side (whole metres every other case, no data
/// every third), 1 to 4 uneven cuts per axis, random weights.
struct RandomCase
{
  Terrain w;
  std::vector<hy::TileBox> boxes;
  std::vector<float> weight;
};

RandomCase MakeRandomCase(std::mt19937_64& rng, int t)
{
  RandomCase c;
  const int nx = 3 + static_cast<int>(rng() % 40);
  const int ny = 3 + static_cast<int>(rng() % 40);
  c.w = RandomTerrain(rng, nx, ny, t % 2 == 0, t % 3 == 0 ? 60 : 0);
  c.boxes = Blocks(
    Cuts(rng, nx, 1 + static_cast<int>(rng() % 4)), Cuts(rng, ny, 1 + static_cast<int>(rng() % 4)));
  c.weight = RandomWeights(rng, c.w);
  return c;
}

/// A terrain of `nx` x `ny` at `height` everywhere, walls (100 m) on the grid's edge.
Terrain Walled(int nx, int ny, float height)
{
  Terrain t;
  t.nx = nx;
  t.ny = ny;
  for (int j = 0; j < ny; ++j)
  {
    t.rowDx.push_back(10.0 + 0.1 * j);
    for (int i = 0; i < nx; ++i)
    {
      const bool edge = i == 0 || j == 0 || i == nx - 1 || j == ny - 1;
      t.z.push_back(edge ? 100.0f : height);
      t.valid.push_back(1);
    }
  }
  return t;
}

/// The cells of a serpentine corridor that crosses column `edge` back and forth: rows 2, 4,
/// ..., each from column edge - 6 to edge + 6, joined at alternate ends; returned from its
/// first row upwards.
std::vector<std::pair<int, int>> Serpentine(int edge, int rows)
{
  std::vector<std::pair<int, int>> path;
  for (int r = 0; r < rows; ++r)
  {
    const int j = 2 + 2 * r;
    for (int s = 0; s <= 12; ++s)
    {
      path.emplace_back(r % 2 == 0 ? edge - 6 + s : edge + 6 - s, j);
    }
    if (r + 1 < rows)
    {
      path.emplace_back(r % 2 == 0 ? edge + 6 : edge - 6, j + 1);
    }
  }
  return path;
}

/// A 41 x 25 walled terrain (30 m) with the corridor `path` cut in at 10 m (descending: rising
/// 1 cm per cell from its start) and its start drained west through the wall to an outlet.
Terrain SerpentineTerrain(const std::vector<std::pair<int, int>>& path, bool descending)
{
  Terrain w = Walled(41, 25, 30.0f);
  for (std::size_t p = 0; p < path.size(); ++p)
  {
    const float z = descending ? 10.0f + 0.01f * static_cast<float>(p) : 10.0f;
    w.z[static_cast<std::size_t>(path[p].second) * w.nx + path[p].first] = z;
  }
  w.z[static_cast<std::size_t>(path[0].second) * w.nx + 0] = 1.0f; // outlet through the wall
  for (int i = 1; i < path[0].first; ++i)
  {
    w.z[static_cast<std::size_t>(path[0].second) * w.nx + i] = 8.0f + 0.01f * i;
  }
  return w;
}
} // namespace

// 60 random terrains (whole metres: many flats and ties; continuous; some with no data; some
// with weights), split 1 to 16 ways in uneven blocks, rings of 1 to 3 cells: W, the directions
// and the cell counts equal the serial code's bit for bit, areas and weighted sums to 1e-12, on
// the owned cells and on the ring each tile asked for; the whole grid's counts too.
TEST(DistributedFlowAccumulation, EqualsSerialOnRandomTerrains)
{
  std::mt19937_64 rng(20170301);
  int several = 0;
  for (int t = 0; t < 60; ++t)
  {
    const RandomCase c = MakeRandomCase(rng, t);
    const Terrain& w = c.w;
    const std::vector<hy::TileBox>& boxes = c.boxes;
    const std::vector<float>& weight = c.weight;
    const int exchanges = ExpectSerial(
      w, boxes, 1 + t % 3, t % 4 == 1 ? &weight : nullptr, "terrain " + std::to_string(t));
    several += exchanges > 2 ? 1 : 0;
  }
  EXPECT_GT(several, 5); // terrains whose flats needed distances from several tiles away
}

// A walled lake flat at 10 m with its one outlet in the south-west corner: every flat cell
// drains along the shortest way to that corner, across every tile edge of a 4 x 4 split. The
// distances travel one tile per exchange, so the exchanges grow with the tiles crossed.
TEST(DistributedFlowAccumulation, FlatAcrossTiles)
{
  Terrain w = Walled(41, 37, 10.0f);
  w.z[1] = 5.0f; // cell (1, 0): the outlet through the wall
  const std::vector<hy::TileBox> boxes = Blocks({ 0, 9, 20, 31, 41 }, { 0, 8, 17, 27, 37 });
  const int exchanges = ExpectSerial(w, boxes, 1, nullptr, "walled flat");
  EXPECT_GE(exchanges, 4);
  // The outlet (cell (1, 0)) receives every cell: the walls drain into the lake.
  const Outcome out = RunTiles(w, boxes, 1, 2, nullptr);
  EXPECT_EQ(out.results[0].cells[1], 41.0 * 37.0);
}

// A flat corridor that crosses a tile edge 11 times (walls at 30 m, the corridor at 10 m, the
// outlet at its start): its far end is 11 tile crossings from the outlet, so the flats need
// more than 10 exchanges; and a descending channel along the same serpentine carries the whole
// corridor's flow across the edge and back 11 times (the perimeter graph).
TEST(DistributedFlowAccumulation, SerpentineAcrossAnEdge)
{
  const std::vector<std::pair<int, int>> path = Serpentine(20, 11);
  const std::vector<hy::TileBox> boxes = Blocks({ 0, 20, 41 }, { 0, 13, 25 });
  for (int descending = 0; descending < 2; ++descending)
  {
    const Terrain w = SerpentineTerrain(path, descending != 0);
    const std::string what = descending ? "channel" : "flat corridor";
    const int exchanges = ExpectSerial(w, boxes, 1, nullptr, what);
    if (!descending)
    {
      EXPECT_GT(exchanges, 10) << what;
    }
    // Every corridor cell drains to its predecessor: the first cell gathers the corridor.
    const Outcome out = RunTiles(w, boxes, 1, 2, nullptr);
    const std::size_t first = static_cast<std::size_t>(path[0].second) * w.nx + path[0].first;
    const TileCopy& c = out.copies[0];
    const std::size_t t = (first / w.nx - c.gj0) * c.t.nx + (first % w.nx - c.gi0);
    EXPECT_GE(out.results[0].cells[t], static_cast<double>(path.size())) << what;
  }
}

// MFD (Freeman's, Quinn's contour lengths, Qin's adaptive exponent) and D-infinity in tiles:
// 45 random terrains (flats, no data, weights), 1 to 16 uneven tiles, rings of 1 to 3: W, the
// directions and D-infinity's angles bit for bit, the sums within 1e-12 of the serial
// MultipleFlowAccumulation / DInfinityAccumulation on the owned cells and the ring. Flow
// spreads, so some terrain needs more than two rounds (flow coming back into a tile).
TEST(DistributedFlowAccumulation, DispersiveEqualsSerialOnRandomTerrains)
{
  std::mt19937_64 rng(19910301);
  int rounds = 0;
  for (int t = 0; t < 45; ++t)
  {
    const RandomCase c = MakeRandomCase(rng, t);
    const Terrain& w = c.w;
    const std::vector<hy::TileBox>& boxes = c.boxes;
    const std::vector<float>& weight = c.weight;
    Method method;
    method.kind = t % 3 == 2 ? Method::DInfinity : Method::MFD;
    method.mfd.contourLength = t % 5 == 1;
    method.mfd.adaptive = t % 5 == 3;
    method.mfd.exponent = t % 5 == 1 ? 1.0 : 1.1;
    ExpectSerial(w,
      boxes,
      1 + t % 3,
      t % 4 == 1 ? &weight : nullptr,
      "terrain " + std::to_string(t) + (method.kind == Method::MFD ? " MFD" : " D-infinity"),
      method,
      &rounds);
  }
  EXPECT_GT(rounds, 2);
}

// The descending serpentine channel across a tile edge (11 crossings), walls sloping into it:
// MFD and D-infinity carry the corridor's flow across the edge and back, one crossing per
// round, so the sums need more than 11 rounds, and still equal the serial ones.
TEST(DistributedFlowAccumulation, DispersiveSerpentineNeedsARoundPerCrossing)
{
  const std::vector<std::pair<int, int>> path = Serpentine(20, 11);
  const std::vector<hy::TileBox> boxes = Blocks({ 0, 20, 41 }, { 0, 13, 25 });
  const Terrain w = SerpentineTerrain(path, true);
  for (const Method::Kind kind : { Method::MFD, Method::DInfinity })
  {
    Method method;
    method.kind = kind;
    int rounds = 0;
    ExpectSerial(w, boxes, 1, nullptr, kind == Method::MFD ? "MFD" : "D-infinity", method, &rounds);
    EXPECT_GT(rounds, 11);
  }
}

// The tiles must partition the grid and each must hold the ring of reach + 1; otherwise every
// rank fails with the same reason (none waits for the others for ever).
TEST(DistributedFlowAccumulation, RefusesBadTiles)
{
  std::mt19937_64 rng(7);
  const Terrain w = RandomTerrain(rng, 10, 8, false, 0);
  const Outcome overlap = RunTiles(w, { { 0, 5, 0, 7 }, { 5, 9, 0, 7 } }, 1, 2, nullptr);
  for (const std::string& e : overlap.errors)
  {
    EXPECT_NE(e.find("overlap"), std::string::npos) << e;
  }
  const Outcome ring = RunTiles(w, { { 0, 4, 0, 7 }, { 5, 9, 0, 7 } }, 1, 1, nullptr);
  for (const std::string& e : ring.errors)
  {
    EXPECT_NE(e.find("lacks the ring of 2"), std::string::npos) << e;
  }
}

// What travels grows with a tile's perimeter, not its area: on a 480 x 480 random terrain cut
// in 4, each rank sends rank 0 less than 400 bytes per perimeter cell (the fill's ~100, the
// flats' and the accumulation's records, the ring's results); sending the tile's sums would
// cost 16 bytes per cell, 920 kB here.
TEST(DistributedFlowAccumulation, SendsPerimetersNotTiles)
{
  std::mt19937_64 rng(2017);
  const Terrain w = RandomTerrain(rng, 480, 480, false, 0);
  const std::vector<hy::TileBox> boxes = Blocks({ 0, 240, 480 }, { 0, 240, 480 });
  const Outcome out = RunTiles(w, boxes, 1, 2, nullptr);
  for (std::size_t r = 0; r < boxes.size(); ++r)
  {
    ASSERT_EQ(out.errors[r], "");
    const double perimeter = 2.0 * 240; // two inner edges of a corner tile
    EXPECT_LT(static_cast<double>(out.sentBytes[r]), 400.0 * perimeter) << "rank " << r;
  }
}

// Unit tests of the k-means core (terroir::clustering, Filters/Clustering/Core/KMeans.h).
// Expected values are worked out by hand in the comments (small 1-D and 2-D examples, seed
// positions on small grids, the palette), or are properties any correct implementation has
// (far-apart blobs are found exactly, the same bits for every split of the work, reference sums
// computed here in the plainest way).
#include "KMeans.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <cstring>
#include <functional>
#include <map>
#include <mutex>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace
{
namespace km = terroir::clustering;

/// A feature-major matrix built from cell-major points, with its view.
struct Matrix
{
  std::vector<float> data;
  km::KMeansFeatures view;

  explicit Matrix(const std::vector<std::vector<float>>& points)
  {
    const std::size_t n = points.size();
    const int nf = n > 0 ? static_cast<int>(points[0].size()) : 0;
    data.resize(n * static_cast<std::size_t>(nf));
    for (std::size_t c = 0; c < n; ++c)
    {
      for (int f = 0; f < nf; ++f)
      {
        data[static_cast<std::size_t>(f) * n + c] = points[c][f];
      }
    }
    view.data = data.data();
    view.cells = n;
    view.features = nf;
  }
  Matrix(std::vector<float> featureMajor, std::size_t cells, int features)
    : data(std::move(featureMajor))
  {
    view.data = data.data();
    view.cells = cells;
    view.features = features;
  }
};

/// Everything one Lloyd run gives, labels and distances copied out of the engine.
struct LloydRun
{
  km::KMeansResult result;
  std::vector<std::int32_t> labels;
  std::vector<float> distances;
  std::vector<std::pair<int, std::size_t>> progress;
};

LloydRun Lloyd(const km::KMeansFeatures& features,
  const std::vector<float>& centres,
  int k,
  const km::KMeansOptions& options,
  const km::KMeansParallelFor& parallelFor = {})
{
  km::KMeansCPUEngine engine(features, parallelFor);
  LloydRun run;
  run.result = km::KMeansLloyd(engine,
    features,
    centres,
    k,
    options,
    [&run](int iteration, std::size_t changed) { run.progress.emplace_back(iteration, changed); });
  run.labels.assign(engine.Labels(), engine.Labels() + features.cells);
  run.distances.assign(engine.Distances(), engine.Distances() + features.cells);
  return run;
}

km::KMeansOptions Options(int maximumIterations, double tolerance)
{
  km::KMeansOptions o;
  o.maximumIterations = maximumIterations;
  o.tolerance = tolerance;
  return o;
}

/// Our own uniform mapping and Box-Muller (no std:: distributions: reproducible everywhere).
double Uniform(std::mt19937_64& rng)
{
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

double Normal(std::mt19937_64& rng)
{
  const double u1 = 1.0 - Uniform(rng); // (0, 1]
  const double u2 = Uniform(rng);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

/// True when `labels` and `truth` are the same partition (a bijection between label values).
bool SamePartition(const std::vector<std::int32_t>& labels, const std::vector<int>& truth)
{
  if (labels.size() != truth.size())
  {
    return false;
  }
  std::map<int, int> forward;
  std::map<int, int> backward;
  for (std::size_t c = 0; c < labels.size(); ++c)
  {
    auto f = forward.emplace(labels[c], truth[c]).first;
    auto b = backward.emplace(truth[c], labels[c]).first;
    if (f->second != truth[c] || b->second != labels[c])
    {
      return false;
    }
  }
  return true;
}

/// Splits [begin, end) into pieces of 1, 2, 3, ... and runs them in reversed order.
void OddReversed(std::size_t begin,
  std::size_t end,
  const std::function<void(std::size_t, std::size_t)>& body)
{
  std::vector<std::pair<std::size_t, std::size_t>> pieces;
  std::size_t size = 1;
  for (std::size_t b = begin; b < end; b += size, ++size)
  {
    pieces.emplace_back(b, std::min(end, b + size));
  }
  for (auto it = pieces.rbegin(); it != pieces.rend(); ++it)
  {
    body(it->first, it->second);
  }
}

/// Two real threads, split at one third.
void TwoThreads(std::size_t begin,
  std::size_t end,
  const std::function<void(std::size_t, std::size_t)>& body)
{
  const std::size_t mid = begin + (end - begin) / 3;
  std::thread t([&] { body(begin, mid); });
  body(mid, end);
  t.join();
}

bool SameBits(const void* a, const void* b, std::size_t bytes)
{
  return std::memcmp(a, b, bytes) == 0;
}

/// The plainest squared distance (volatile: no contraction into a fused multiply-add here).
float NaiveD2(const km::KMeansFeatures& x, std::size_t c, const float* m)
{
  float acc = 0.0f;
  for (int f = 0; f < x.features; ++f)
  {
    const float d = x.At(f, c) - m[f];
    volatile float sq = d * d;
    acc = acc + sq;
  }
  return acc;
}

/// Random features in [-1, 1) (feature-major).
Matrix RandomMatrix(std::size_t cells, int features, std::uint64_t seed)
{
  std::mt19937_64 rng(seed);
  std::vector<float> data(cells * static_cast<std::size_t>(features));
  for (float& v : data)
  {
    v = static_cast<float>(2.0 * Uniform(rng) - 1.0);
  }
  return Matrix(std::move(data), cells, features);
}

/**
 * KMeansReduction among `ranks` threads standing in for MPI processes: each call waits until
 * every thread has brought its values, then each takes the sum (or max, min) over the threads
 * in rank order.
 */
class ThreadReduction
{
public:
  explicit ThreadReduction(int ranks)
    : Ranks(ranks)
    , Slots(static_cast<std::size_t>(ranks))
  {
  }

  template<typename T>
  void Reduce(int rank, T* values, std::size_t n, int op)
  {
    std::unique_lock<std::mutex> lock(this->Mutex);
    const long generation = this->Generation;
    this->Slots[static_cast<std::size_t>(rank)].assign(values, values + n);
    if (++this->Arrived == this->Ranks)
    {
      this->Arrived = 0;
      this->Result.assign(n, 0.0L);
      for (std::size_t i = 0; i < n; ++i)
      {
        long double r = this->Slots[0][i];
        for (int q = 1; q < this->Ranks; ++q)
        {
          const long double v = this->Slots[static_cast<std::size_t>(q)][i];
          r = op == 0 ? r + v : (op == 1 ? std::max(r, v) : std::min(r, v));
        }
        this->Result[i] = r;
      }
      if (op == 0 && std::is_floating_point<T>::value)
      {
        // Sums of doubles in rank order, in double (as an MPI sum of two or four would be).
        for (std::size_t i = 0; i < n; ++i)
        {
          double d = static_cast<double>(this->Slots[0][i]);
          for (int q = 1; q < this->Ranks; ++q)
          {
            d += static_cast<double>(this->Slots[static_cast<std::size_t>(q)][i]);
          }
          this->Result[i] = d;
        }
      }
      ++this->Generation;
      this->Done.notify_all();
    }
    else
    {
      this->Done.wait(lock, [&] { return this->Generation != generation; });
    }
    for (std::size_t i = 0; i < n; ++i)
    {
      values[i] = static_cast<T>(this->Result[i]);
    }
  }

private:
  int Ranks;
  int Arrived = 0;
  long Generation = 0;
  std::vector<std::vector<long double>> Slots;
  std::vector<long double> Result;
  std::mutex Mutex;
  std::condition_variable Done;
};

/// One thread's view of a ThreadReduction, as the core sees it.
class RankReduction : public km::KMeansReduction
{
public:
  RankReduction(ThreadReduction& all, int rank)
    : All(all)
    , Rank(rank)
  {
  }
  void Sum(double* v, std::size_t n) override { this->All.Reduce(this->Rank, v, n, 0); }
  void Sum(std::int64_t* v, std::size_t n) override { this->All.Reduce(this->Rank, v, n, 0); }
  void Max(double* v, std::size_t n) override { this->All.Reduce(this->Rank, v, n, 1); }
  void Min(double* v, std::size_t n) override { this->All.Reduce(this->Rank, v, n, 2); }
  void Min(std::int64_t* v, std::size_t n) override { this->All.Reduce(this->Rank, v, n, 2); }

private:
  ThreadReduction& All;
  int Rank;
};

/**
 * Lloyd on `x` split into `ranks` contiguous parts, one thread each with a RankReduction (the
 * distributed path of KMeansLloyd); the parts' labels put back in cell order.
 */
LloydRun DistributedLloyd(const Matrix& x,
  const std::vector<float>& centres,
  int k,
  const km::KMeansOptions& options,
  int ranks,
  const std::vector<std::size_t>& starts)
{
  ThreadReduction all(ranks);
  const std::size_t n = x.view.cells;
  const int nf = x.view.features;
  std::vector<LloydRun> runs(static_cast<std::size_t>(ranks));
  std::vector<std::thread> threads;
  for (int r = 0; r < ranks; ++r)
  {
    threads.emplace_back(
      [&, r]
      {
        const std::size_t b = starts[static_cast<std::size_t>(r)];
        const std::size_t e = r + 1 < ranks ? starts[static_cast<std::size_t>(r) + 1] : n;
        std::vector<float> part((e - b) * static_cast<std::size_t>(nf));
        std::vector<std::int64_t> ids;
        for (int f = 0; f < nf; ++f)
        {
          for (std::size_t c = b; c < e; ++c)
          {
            part[static_cast<std::size_t>(f) * (e - b) + (c - b)] = x.view.At(f, c);
          }
        }
        for (std::size_t c = b; c < e; ++c)
        {
          ids.push_back(static_cast<std::int64_t>(c));
        }
        Matrix local(std::move(part), e - b, nf);
        RankReduction reduction(all, r);
        km::KMeansOptions o = options;
        o.reduction = &reduction;
        o.globalCells = ids.data();
        runs[static_cast<std::size_t>(r)] = Lloyd(local.view, centres, k, o);
      });
  }
  for (std::thread& t : threads)
  {
    t.join();
  }
  LloydRun joined = runs[0];
  for (int r = 1; r < ranks; ++r)
  {
    const LloydRun& run = runs[static_cast<std::size_t>(r)];
    joined.labels.insert(joined.labels.end(), run.labels.begin(), run.labels.end());
    EXPECT_EQ(run.result.centres, joined.result.centres) << "rank " << r;
    EXPECT_EQ(run.result.iterations, joined.result.iterations) << "rank " << r;
  }
  return joined;
}

/// The 1-D example worked by hand in Lloyd1D below.
const std::vector<std::vector<float>> kLine = { { 1 }, { 2 }, { 3 }, { 8 }, { 9 }, { 10 }, { 25 } };
} // namespace

//------------------------------------------------------------------------------
// Lloyd, worked by hand. x = 1 2 3 8 9 10 25, K = 2, initial centres 1 and 2 (cells 0, 1).
//  it 1: d2 to (1, 2): 1 -> (0, 1) -> 0; 2 -> (1, 0) -> 1; 3 -> (4, 1) -> 1; 8, 9, 10, 25 -> 1.
//        labels 0 1 1 1 1 1 1 (7 changed from -1); m0 = 1, m1 = (2+3+8+9+10+25)/6 = 57/6 = 9.5;
//        m1 moved 2 -> 9.5: shift = 0 + 7.5^2 = 56.25.
//  it 2: 2: (1, 56.25) -> 0; 3: (4, 42.25) -> 0; 8: (49, 2.25) -> 1; 9, 10, 25 -> 1.
//        labels 0 0 0 1 1 1 1 (2 changed); m0 = 6/3 = 2, m1 = 52/4 = 13; shift = 1 + 12.25.
//  it 3: 3: (1, 100) -> 0; 8: (36, 25) -> 1; 9: (49, 16) -> 1: no label changed: Converged.
//  inertia = (1 + 0 + 1) + (25 + 16 + 9 + 144) = 196; counts 3, 4; iterations 3.
TEST(KMeans, Lloyd1D)
{
  Matrix x(kLine);
  const LloydRun run = Lloyd(x.view, { 1.0f, 2.0f }, 2, Options(300, 0.0));
  EXPECT_EQ(run.result.reason, km::KMeansStopReason::Converged);
  EXPECT_EQ(run.result.iterations, 3);
  EXPECT_EQ(run.labels, (std::vector<std::int32_t>{ 0, 0, 0, 1, 1, 1, 1 }));
  EXPECT_EQ(run.result.centres, (std::vector<float>{ 2.0f, 13.0f }));
  EXPECT_EQ(run.result.counts, (std::vector<std::int64_t>{ 3, 4 }));
  EXPECT_EQ(run.result.inertia, 196.0); // integers: exact
  EXPECT_EQ(run.result.relocated, 0);
  EXPECT_EQ(run.distances, (std::vector<float>{ 1, 0, 1, 25, 16, 9, 144 }));
  const std::vector<std::pair<int, std::size_t>> progress = { { 1, 7 }, { 2, 2 }, { 3, 0 } };
  EXPECT_EQ(run.progress, progress);
}

// 2-D: A(0,0) B(0,2) C(4,0) D(4,2) E(2,1), K = 2 from A and C.
//  it 1: E is at d2 4 + 1 = 5 from both centres: the tie goes to cluster 0. B: 4 vs 20 -> 0;
//        D: 20 vs 4 -> 1. labels 0 0 1 1 0; m0 = (A+B+E)/3 = (2/3, 1), m1 = (C+D)/2 = (4, 1).
//  it 2: A, B: 4/9 + 1 vs 17 -> 0; E: 16/9 vs 4 -> 0; C, D: 100/9 + 1 vs 1 -> 1. Converged.
//  inertia = A 13/9 + B 13/9 + E 16/9 + C 1 + D 1 = 42/9 + 2 = 20/3; iterations 2.
TEST(KMeans, Lloyd2D)
{
  Matrix x({ { 0, 0 }, { 0, 2 }, { 4, 0 }, { 4, 2 }, { 2, 1 } });
  const LloydRun run = Lloyd(x.view, { 0, 0, 4, 0 }, 2, Options(300, 1e-4));
  EXPECT_EQ(run.result.reason, km::KMeansStopReason::Converged);
  EXPECT_EQ(run.result.iterations, 2);
  EXPECT_EQ(run.labels, (std::vector<std::int32_t>{ 0, 0, 1, 1, 0 }));
  EXPECT_EQ(run.result.centres, (std::vector<float>{ 2.0f / 3.0f, 1.0f, 4.0f, 1.0f }));
  EXPECT_NEAR(run.result.inertia, 20.0 / 3.0, 1e-5);
  EXPECT_EQ(run.result.counts, (std::vector<std::int64_t>{ 3, 2 }));
  // First iteration: all five labels changed from -1; E's tie went to 0 and stayed there.
  ASSERT_EQ(run.progress.size(), 2u);
  EXPECT_EQ(run.progress[0].second, 5u);
  EXPECT_EQ(run.progress[1].second, 0u);
}

// Ties go to the lowest cluster: (2, 1) is at d2 5 from (0, 0), (4, 0), (4, 2) and (0, 2).
TEST(KMeans, AssignTiesAndDistances)
{
  Matrix x({ { 2, 1 }, { 1, 2 } });
  const std::vector<float> centres = { 9, 9, 4, 0, 0, 0, 4, 2, 0, 2 };
  std::vector<std::int32_t> labels = { 3, 1 };
  std::vector<float> d(2);
  const std::size_t changed =
    km::KMeansAssignRange(x.view, centres.data(), 5, 0, 2, labels.data(), d.data());
  // (2,1): (9,9) 49 + 64 = 113, then 5, 5, 5, 5 -> cluster 1 (the first of the tie).
  // (1,2): (9,9) 64 + 49 = 113; (4,0) 9 + 4 = 13; (0,0) 1 + 4 = 5; (4,2) 9 + 0 = 9;
  // (0,2) 1 + 0 = 1 -> cluster 4, d2 1. Both labels changed (from 3 and 1).
  EXPECT_EQ(labels, (std::vector<std::int32_t>{ 1, 4 }));
  EXPECT_EQ(d, (std::vector<float>{ 5, 1 }));
  EXPECT_EQ(changed, 2u);
  // Again with the same centres: nothing changes. Only cell 1 of [1, 2) is touched.
  EXPECT_EQ(km::KMeansAssignRange(x.view, centres.data(), 5, 1, 2, labels.data(), d.data()), 0u);

  // The same two points 50 times each (the vectorised tiles and the scalar tail alike), and with
  // the centres in another order: (4,2) (0,2) (9,9) (0,0) (4,0): (2,1) ties between 0, 1, 3, 4
  // -> 0; (1,2) is nearest (0,2) -> 1.
  std::vector<std::vector<float>> many;
  for (int i = 0; i < 50; ++i)
  {
    many.push_back({ 2, 1 });
    many.push_back({ 1, 2 });
  }
  Matrix y(many);
  for (const auto& order : { std::make_pair(centres, std::vector<std::int32_t>{ 1, 4 }),
         std::make_pair(
           std::vector<float>{ 4, 2, 0, 2, 9, 9, 0, 0, 4, 0 }, std::vector<std::int32_t>{ 0, 1 }) })
  {
    std::vector<std::int32_t> l(100, -1);
    std::vector<float> dd(100);
    EXPECT_EQ(
      km::KMeansAssignRange(y.view, order.first.data(), 5, 0, 100, l.data(), dd.data()), 100u);
    for (int c = 0; c < 100; ++c)
    {
      EXPECT_EQ(l[c], order.second[c % 2]) << "cell " << c;
      EXPECT_EQ(dd[c], c % 2 == 0 ? 5.0f : 1.0f);
    }
  }
}

// The vectorised assignment gives the bits of the plainest float loop, cell by cell, for chunk
// boundaries of every kind (ranges starting and ending anywhere).
TEST(KMeans, AssignMatchesNaiveLoop)
{
  const Matrix x = RandomMatrix(1000, 7, 11);
  std::mt19937_64 rng(12);
  for (int k : { 1, 2, 3, 6, 9 })
  {
    std::vector<float> centres(static_cast<std::size_t>(k) * 7);
    for (float& v : centres)
    {
      v = static_cast<float>(Uniform(rng) - 0.5);
    }
    for (auto range : { std::make_pair(0, 1000),
           std::make_pair(3, 70),
           std::make_pair(31, 32),
           std::make_pair(100, 997) })
    {
      std::vector<std::int32_t> labels(1000, -1);
      std::vector<float> d(1000, -1.0f);
      km::KMeansAssignRange(
        x.view, centres.data(), k, range.first, range.second, labels.data(), d.data());
      for (std::size_t c = 0; c < 1000; ++c)
      {
        const bool inside =
          static_cast<int>(c) >= range.first && static_cast<int>(c) < range.second;
        if (!inside)
        {
          ASSERT_EQ(labels[c], -1);
          ASSERT_EQ(d[c], -1.0f);
          continue;
        }
        float best = NaiveD2(x.view, c, centres.data());
        int label = 0;
        for (int kk = 1; kk < k; ++kk)
        {
          const float v = NaiveD2(x.view, c, centres.data() + kk * 7);
          if (v < best)
          {
            best = v;
            label = kk;
          }
        }
        ASSERT_EQ(labels[c], label) << "k " << k << " cell " << c;
        ASSERT_TRUE(SameBits(&d[c], &best, sizeof(float))) << "k " << k << " cell " << c;
      }
    }
  }
}

// Block sums against the plainest loop (in cell order, in double), including a partial last
// block, runs of equal labels and alternating labels; outputs are zeroed first; labels outside
// [0, k) (as before the first assignment) are left out.
TEST(KMeans, BlockSumsMatchNaiveLoop)
{
  const std::size_t n = 2 * km::KMeansBlockCells + 777;
  const Matrix x = RandomMatrix(n, 11, 21);
  std::vector<std::int32_t> labels(n);
  std::vector<float> d(n);
  std::mt19937_64 rng(22);
  const int k = 4;
  for (std::size_t c = 0; c < n; ++c)
  {
    // Runs of 1 to 40 equal labels, some cells alternating.
    labels[c] = c % 97 < 40 ? static_cast<int>((c / 40) % k) : static_cast<int>(rng() % k);
    d[c] = static_cast<float>(Uniform(rng));
  }
  labels[5] = -1;
  labels[6] = k;
  for (std::size_t b = 0; b < x.view.Blocks(); ++b)
  {
    std::vector<double> sums(k * 11, 123.0);
    std::vector<std::int64_t> counts(k, 77);
    double inertia = 5.0;
    km::KMeansBlockSums(
      x.view, labels.data(), d.data(), k, b, sums.data(), counts.data(), &inertia);
    std::vector<double> es(k * 11, 0.0);
    std::vector<std::int64_t> ec(k, 0);
    double ei = 0.0;
    const std::size_t c1 = std::min(n, (b + 1) * km::KMeansBlockCells);
    for (std::size_t c = b * km::KMeansBlockCells; c < c1; ++c)
    {
      if (labels[c] < 0 || labels[c] >= k)
      {
        continue;
      }
      for (int f = 0; f < 11; ++f)
      {
        es[labels[c] * 11 + f] += static_cast<double>(x.view.At(f, c));
      }
      ec[labels[c]] += 1;
      ei += static_cast<double>(d[c]);
    }
    EXPECT_TRUE(SameBits(sums.data(), es.data(), es.size() * sizeof(double))) << "block " << b;
    EXPECT_EQ(counts, ec);
    EXPECT_TRUE(SameBits(&inertia, &ei, sizeof(double)));
  }
}

//------------------------------------------------------------------------------
// Four Gaussian blobs (sigma 1) at (0,0,0), (100,0,0), (0,100,0), (0,0,100), in four horizontal
// bands of three rows of a 12 x 12 grid (band = row / 3). The diagonal cells (t, t) lie in rows
// 0..11; with M = 12, K = 4 the seeds sit at positions floor((2i+1) 12 / 8) = 1, 4, 7, 10: rows
// 1, 4, 7, 10, one per band. Lloyd then finds the bands exactly.
TEST(KMeans, SeparatedBlobs)
{
  const int nx = 12;
  const int ny = 12;
  const double at[4][3] = { { 0, 0, 0 }, { 100, 0, 0 }, { 0, 100, 0 }, { 0, 0, 100 } };
  std::mt19937_64 rng(2024);
  std::vector<std::vector<float>> points;
  std::vector<int> truth;
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      const int band = j / 3;
      std::vector<float> p(3);
      for (int f = 0; f < 3; ++f)
      {
        p[f] = static_cast<float>(at[band][f] + Normal(rng));
      }
      points.push_back(p);
      truth.push_back(band);
    }
  }
  Matrix x(points);

  // Independent expectations: each band's mean and the within-band sum of squares (double).
  std::vector<double> mean(12, 0.0);
  for (std::size_t c = 0; c < points.size(); ++c)
  {
    for (int f = 0; f < 3; ++f)
    {
      mean[truth[c] * 3 + f] += points[c][f] / 36.0;
    }
  }
  double wss = 0.0;
  for (std::size_t c = 0; c < points.size(); ++c)
  {
    for (int f = 0; f < 3; ++f)
    {
      const double d = points[c][f] - mean[truth[c] * 3 + f];
      wss += d * d;
    }
  }

  const std::vector<std::size_t> diagonal = km::KMeansDiagonalSeedCells(nx, ny, nullptr, 4);
  EXPECT_EQ(
    diagonal, (std::vector<std::size_t>{ 1 * 12 + 1, 4 * 12 + 4, 7 * 12 + 7, 10 * 12 + 10 }));
  for (std::uint64_t seed : { 0ull, 1ull, 99ull })
  {
    const std::vector<std::size_t> cells =
      seed == 0 ? diagonal : km::KMeansPlusPlusSeeds(x.view, 4, seed);
    const LloydRun run =
      Lloyd(x.view, km::KMeansCentresFromCells(x.view, cells), 4, Options(300, 1e-4));
    ASSERT_TRUE(SamePartition(run.labels, truth)) << "seed " << seed;
    EXPECT_NEAR(run.result.inertia, wss, 1e-5 * wss);
    for (std::size_t c = 0; c < points.size(); ++c)
    {
      for (int f = 0; f < 3; ++f)
      {
        EXPECT_NEAR(run.result.centres[run.labels[c] * 3 + f], mean[truth[c] * 3 + f], 1e-3);
      }
    }
    EXPECT_EQ(run.result.counts, (std::vector<std::int64_t>{ 36, 36, 36, 36 }));
    EXPECT_EQ(run.result.relocated, 0);
  }
}

//------------------------------------------------------------------------------
TEST(KMeans, DiagonalSeedCells)
{
  // 5 x 5: the diagonal is (t, t), cells 0, 6, 12, 18, 24; M = 5, K = 2: positions
  // floor(1 * 5 / 4) = 1 and floor(3 * 5 / 4) = 3 -> cells 6 and 18.
  EXPECT_EQ(km::KMeansDiagonalSeedCells(5, 5, nullptr, 2), (std::vector<std::size_t>{ 6, 18 }));
  // K = 5 takes the whole diagonal: positions floor((2i+1) 5 / 10) = 0, 1, 2, 3, 4.
  EXPECT_EQ(
    km::KMeansDiagonalSeedCells(5, 5, nullptr, 5), (std::vector<std::size_t>{ 0, 6, 12, 18, 24 }));
  // 4 x 2: L = 4, i = t, j = round(t / 3) = 0, 0, 1, 1 (0.33 -> 0, 0.67 -> 1): cells 0, 1, 6, 7;
  // K = 2: positions 1, 3 -> cells 1, 7.
  EXPECT_EQ(km::KMeansDiagonalSeedCells(4, 2, nullptr, 2), (std::vector<std::size_t>{ 1, 7 }));
  // 3 x 2: L = 3, j = round(t / 2): t = 1 gives 0.5, rounded up to 1: cells 0, (1,1) = 4,
  // (2,1) = 5. K = 3: positions floor(3/6), floor(9/6), floor(15/6) = 0, 1, 2 -> 0, 4, 5.
  EXPECT_EQ(km::KMeansDiagonalSeedCells(3, 2, nullptr, 3), (std::vector<std::size_t>{ 0, 4, 5 }));
  // A column, 1 x 4: i = 0, j = t: cells 0..3; K = 2 -> positions 1, 3.
  EXPECT_EQ(km::KMeansDiagonalSeedCells(1, 4, nullptr, 2), (std::vector<std::size_t>{ 1, 3 }));
  // One cell.
  EXPECT_EQ(km::KMeansDiagonalSeedCells(1, 1, nullptr, 1), (std::vector<std::size_t>{ 0 }));

  // No-data on the diagonal: 5 x 5 with cells 6 and 18 invalid. Valid diagonal cells 0, 12, 24
  // (M = 3); K = 2: positions floor(3/4) = 0, floor(9/4) = 2 -> cells 0 and 24.
  std::vector<std::uint8_t> valid(25, 1);
  valid[6] = 0;
  valid[18] = 0;
  EXPECT_EQ(
    km::KMeansDiagonalSeedCells(5, 5, valid.data(), 2), (std::vector<std::size_t>{ 0, 24 }));

  // M < K: 3 x 3, diagonal 0, 4, 8 with 4 invalid (M = 2 < K = 3): all valid cells in row order,
  // 0 1 2 3 5 6 7 8 (8 cells), positions floor(8/6) = 1, floor(24/6) = 4, floor(40/6) = 6
  // -> cells 1, 5, 7.
  std::vector<std::uint8_t> v3(9, 1);
  v3[4] = 0;
  EXPECT_EQ(km::KMeansDiagonalSeedCells(3, 3, v3.data(), 3), (std::vector<std::size_t>{ 1, 5, 7 }));

  EXPECT_THROW(km::KMeansDiagonalSeedCells(3, 3, nullptr, 0), std::invalid_argument);
  std::vector<std::uint8_t> one = { 0, 1, 0, 0 };
  EXPECT_EQ(km::KMeansDiagonalSeedCells(2, 2, one.data(), 1), (std::vector<std::size_t>{ 1 }));
  EXPECT_THROW(km::KMeansDiagonalSeedCells(2, 2, one.data(), 2), std::invalid_argument);
  EXPECT_THROW(km::KMeansDiagonalSeedCells(0, 3, nullptr, 1), std::invalid_argument);
}

//------------------------------------------------------------------------------
TEST(KMeans, PlusPlusReproducibleAndDistinct)
{
  const Matrix x = RandomMatrix(300, 4, 5);
  const std::vector<std::size_t> a = km::KMeansPlusPlusSeeds(x.view, 8, 42);
  const std::vector<std::size_t> b = km::KMeansPlusPlusSeeds(x.view, 8, 42);
  const std::vector<std::size_t> c = km::KMeansPlusPlusSeeds(x.view, 8, 43);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  EXPECT_EQ(a, km::KMeansPlusPlusSeeds(x.view, 8, 42, OddReversed));
  for (const auto& s : { a, c })
  {
    ASSERT_EQ(s.size(), 8u);
    EXPECT_EQ(std::set<std::size_t>(s.begin(), s.end()).size(), 8u);
    for (std::size_t cell : s)
    {
      EXPECT_LT(cell, 300u);
    }
  }
  // Every cell once when k = cells.
  const Matrix small = RandomMatrix(6, 2, 6);
  const auto all = km::KMeansPlusPlusSeeds(small.view, 6, 1);
  EXPECT_EQ(std::set<std::size_t>(all.begin(), all.end()).size(), 6u);
}

// The first two picks from the documented rule, worked out here on 1-D points 0 0 1 3 (D2 of
// the running sum in cell order).
TEST(KMeans, PlusPlusRule)
{
  Matrix x({ { 0 }, { 0 }, { 1 }, { 3 } });
  for (std::uint64_t seed : { 1ull, 2ull, 3ull, 4ull, 5ull, 6ull, 7ull, 8ull })
  {
    std::mt19937_64 rng(seed);
    const double u1 = static_cast<double>(rng() >> 11) / 9007199254740992.0;
    const double u2 = static_cast<double>(rng() >> 11) / 9007199254740992.0;
    const std::size_t first = static_cast<std::size_t>(u1 * 4.0);
    const double xs[4] = { 0, 0, 1, 3 };
    double d2[4];
    double total = 0.0;
    for (int c = 0; c < 4; ++c)
    {
      d2[c] = (xs[c] - xs[first]) * (xs[c] - xs[first]);
      total += d2[c];
    }
    std::size_t second = 0;
    double running = 0.0;
    for (int c = 0; c < 4; ++c)
    {
      running += d2[c];
      if (running > u2 * total)
      {
        second = c;
        break;
      }
    }
    EXPECT_EQ(km::KMeansPlusPlusSeeds(x.view, 2, seed), (std::vector<std::size_t>{ first, second }))
      << "seed " << seed;
  }
}

// Heavy duplicates: 100 cells holding only 4 distinct points. Any 4 seeds are 4 distinct points;
// with K = 6 the two extra seeds (total D2 = 0) are the first cells not chosen yet.
TEST(KMeans, PlusPlusPicksDistinctPoints)
{
  std::vector<std::vector<float>> pts;
  const float values[4][2] = { { 0, 0 }, { 5, 0 }, { 0, 7 }, { 1, 1 } };
  for (int c = 0; c < 100; ++c)
  {
    const int v = (c * 7 + c / 9) % 4;
    pts.push_back({ values[v][0], values[v][1] });
  }
  Matrix x(pts);
  for (std::uint64_t seed = 1; seed <= 40; ++seed)
  {
    const auto s = km::KMeansPlusPlusSeeds(x.view, 4, seed);
    std::set<std::pair<float, float>> seen;
    for (std::size_t cell : s)
    {
      seen.emplace(pts[cell][0], pts[cell][1]);
    }
    EXPECT_EQ(seen.size(), 4u) << "seed " << seed;

    const auto s6 = km::KMeansPlusPlusSeeds(x.view, 6, seed);
    ASSERT_EQ(s6.size(), 6u);
    EXPECT_TRUE(std::equal(s.begin(), s.end(), s6.begin())) << "same stream, same first picks";
    std::set<std::size_t> taken(s.begin(), s.end());
    std::size_t expect = 0;
    for (int extra = 4; extra < 6; ++extra)
    {
      while (taken.count(expect))
      {
        ++expect;
      }
      EXPECT_EQ(s6[extra], expect) << "seed " << seed;
      taken.insert(expect);
    }
  }
  EXPECT_THROW(km::KMeansPlusPlusSeeds(x.view, 0, 1), std::invalid_argument);
  EXPECT_THROW(km::KMeansPlusPlusSeeds(x.view, 101, 1), std::invalid_argument);
}

//------------------------------------------------------------------------------
// A weight of 0 drops the array: the prepared matrix (and so every result) is the one without it.
TEST(KMeans, ZeroWeightDropsFeature)
{
  const std::size_t n = 50;
  std::vector<float> a(n);
  std::vector<float> b(n * 2);
  std::mt19937_64 rng(3);
  for (std::size_t c = 0; c < n; ++c)
  {
    a[c] = static_cast<float>(Uniform(rng) * 10.0);
    b[2 * c] = static_cast<float>(Uniform(rng) * 1000.0);
    b[2 * c + 1] = static_cast<float>(Uniform(rng));
  }
  for (bool standardize : { false, true })
  {
    std::vector<float> with;
    std::vector<float> without;
    const auto pw = km::KMeansPrepareFeatures(
      { { "A", a.data(), 1, 1.0 }, { "B", b.data(), 2, 0.0 } }, n, standardize, true, with);
    const auto po =
      km::KMeansPrepareFeatures({ { "A", a.data(), 1, 1.0 } }, n, standardize, true, without);
    ASSERT_EQ(pw.size(), 2u);
    EXPECT_EQ(pw[0].features, 1);
    EXPECT_EQ(pw[1].features, 0);
    EXPECT_EQ(pw[1].firstFeature, 1);
    EXPECT_EQ(with, without);
    if (!standardize)
    {
      // Weight 1, raw values: x' = sqrt(1) x = x.
      EXPECT_EQ(with, a);
    }
    // A dropped array may even hold NaN: it is not read.
    std::vector<float> bad(n * 2, NAN);
    std::vector<float> again;
    km::KMeansPrepareFeatures(
      { { "A", a.data(), 1, 1.0 }, { "B", bad.data(), 2, 0.0 } }, n, standardize, true, again);
    EXPECT_EQ(again, without);
  }
}

// Four groups: (x, y) in {0, 1}^2, 5 cells each, with small jitter. With a large weight on x the
// two clusters are x = 0 and x = 1; with it on y, y = 0 and y = 1. Seeds (0,0) and (1,1): with
// w_x = 100, (0,1) is at 100 * 0 + 1 = 1 from (0,0) and 100 from (1,1): it goes with x = 0.
TEST(KMeans, LargeWeightLeadsPartition)
{
  std::vector<float> xs;
  std::vector<float> ys;
  std::vector<int> byX;
  std::vector<int> byY;
  for (int g = 0; g < 4; ++g)
  {
    for (int r = 0; r < 5; ++r)
    {
      xs.push_back(static_cast<float>(g & 1) + 0.01f * static_cast<float>(r));
      ys.push_back(static_cast<float>(g >> 1) - 0.01f * static_cast<float>(r));
      byX.push_back(g & 1);
      byY.push_back(g >> 1);
    }
  }
  const std::size_t n = xs.size();
  // Cell 0 is group (0, 0), cell 15 group (1, 1).
  for (int heavy = 0; heavy < 2; ++heavy)
  {
    std::vector<float> m;
    const auto p = km::KMeansPrepareFeatures({ { "x", xs.data(), 1, heavy == 0 ? 100.0 : 1.0 },
                                               { "y", ys.data(), 1, heavy == 1 ? 100.0 : 1.0 } },
      n,
      false,
      true,
      m);
    ASSERT_EQ(m.size(), 2 * n);
    // sqrt(100) = 10 exactly: x' = 10 x (rounded to float once).
    EXPECT_EQ(m[heavy * n + 15],
      static_cast<float>(10.0 * static_cast<double>(heavy == 0 ? xs[15] : ys[15])));
    Matrix x(std::move(m), n, 2);
    const LloydRun run =
      Lloyd(x.view, km::KMeansCentresFromCells(x.view, { 0, 15 }), 2, Options(300, 1e-4));
    EXPECT_TRUE(SamePartition(run.labels, heavy == 0 ? byX : byY)) << "heavy " << heavy;
  }
}

// Standardisation: 1 2 3 4 has mean 2.5 and population variance (2.25 + 0.25) * 2 / 4 = 1.25;
// with weight 4 the z-scores are doubled (variance 4). A constant component becomes 0.
TEST(KMeans, Standardize)
{
  const std::vector<float> v = { 1, 10, 7, 2, 20, 7, 3, 30, 7, 4, 40, 7 }; // 3 components
  std::vector<float> m;
  const auto p = km::KMeansPrepareFeatures({ { "v", v.data(), 3, 4.0 } }, 4, true, false, m);
  ASSERT_EQ(p.size(), 1u);
  EXPECT_EQ(p[0].features, 3);
  EXPECT_FALSE(p[0].collapsed);
  EXPECT_EQ(p[0].mean, (std::vector<double>{ 2.5, 25.0, 7.0 }));
  EXPECT_DOUBLE_EQ(p[0].stddev[0], std::sqrt(1.25));
  EXPECT_DOUBLE_EQ(p[0].stddev[1], std::sqrt(125.0)); // 10x the first
  EXPECT_EQ(p[0].stddev[2], 0.0);
  ASSERT_EQ(m.size(), 12u);
  // z of 1 is -1.5 / sqrt(1.25) = -1.3416..., doubled by sqrt(4).
  EXPECT_NEAR(m[0], -2.0 * 1.5 / std::sqrt(1.25), 1e-6);
  for (int f = 0; f < 2; ++f)
  {
    double mean = 0.0;
    double var = 0.0;
    for (int c = 0; c < 4; ++c)
    {
      mean += m[f * 4 + c] / 4.0;
    }
    for (int c = 0; c < 4; ++c)
    {
      var += (m[f * 4 + c] - mean) * (m[f * 4 + c] - mean) / 4.0;
    }
    EXPECT_NEAR(mean, 0.0, 1e-6);
    EXPECT_NEAR(var, 4.0, 1e-5); // weight 4: variance 4
  }
  for (int c = 0; c < 4; ++c)
  {
    EXPECT_EQ(m[8 + c], 0.0f);
  }

  // Weight 1 on 1000 random values: unit variance, zero mean, and the mean variance is 1.
  const Matrix r = RandomMatrix(1000, 1, 9);
  std::vector<float> z;
  const std::vector<float> raw(r.data.begin(), r.data.end());
  km::KMeansPrepareFeatures({ { "r", raw.data(), 1, 1.0 } }, 1000, true, false, z);
  Matrix zm(std::move(z), 1000, 1);
  EXPECT_NEAR(km::KMeansMeanVariance(zm.view), 1.0, 1e-5);
}

// KMeansMeanVariance by hand: 1 2 3 8 9 10 25 has mean 58/7 and population variance
// 884/7 - (58/7)^2 = 2824/49. A second feature 0 0 0 0 0 0 7 has variance 49/7 - 1 = 6.
TEST(KMeans, MeanVariance)
{
  Matrix one(kLine);
  EXPECT_NEAR(km::KMeansMeanVariance(one.view), 2824.0 / 49.0, 1e-12);
  Matrix two({ { 1, 0 }, { 2, 0 }, { 3, 0 }, { 8, 0 }, { 9, 0 }, { 10, 0 }, { 25, 7 } });
  EXPECT_NEAR(km::KMeansMeanVariance(two.view), (2824.0 / 49.0 + 6.0) / 2.0, 1e-12);
}

//------------------------------------------------------------------------------
// The storage trick: 12 monthly values that differ from January by a constant per month (up to
// float rounding: x_j = float(base + 0.1 j)). Collapsed to one feature sqrt(12) x_0, it gives
// the labels and (up to rounding) the inertia of the 12-feature run.
TEST(KMeans, CollapseConstantOffsets)
{
  const std::size_t n = 400;
  std::mt19937_64 rng(8);
  std::vector<float> t(n * 12);
  std::vector<float> notConstant(n * 12);
  for (std::size_t c = 0; c < n; ++c)
  {
    // Three well-separated groups of "temperature".
    const double base = 10.0 * static_cast<double>(c % 3) + Uniform(rng);
    for (int j = 0; j < 12; ++j)
    {
      t[c * 12 + j] = static_cast<float>(base + 0.1 * j - 3.0);
      notConstant[c * 12 + j] = static_cast<float>(base * (j == 7 ? 1.01 : 1.0) + 0.1 * j);
    }
  }
  // The rounding is real: some x_j - x_0 differ between cells (else the tolerance is untested).
  std::set<float> diffs;
  for (std::size_t c = 0; c < n; ++c)
  {
    diffs.insert(t[c * 12 + 5] - t[c * 12]);
  }
  EXPECT_GT(diffs.size(), 1u);

  for (bool standardize : { false, true })
  {
    std::vector<float> collapsed;
    std::vector<float> full;
    const auto pc =
      km::KMeansPrepareFeatures({ { "T", t.data(), 12, 2.0 } }, n, standardize, true, collapsed);
    const auto pf =
      km::KMeansPrepareFeatures({ { "T", t.data(), 12, 2.0 } }, n, standardize, false, full);
    ASSERT_TRUE(pc[0].collapsed);
    EXPECT_EQ(pc[0].features, 1);
    EXPECT_EQ(pc[0].components, 12);
    EXPECT_EQ(pc[0].mean.size(), 12u);
    EXPECT_FALSE(pf[0].collapsed);
    EXPECT_EQ(pf[0].features, 12);
    ASSERT_EQ(collapsed.size(), n);
    if (!standardize)
    {
      // sqrt(w * components) * x_0 = sqrt(24) x_0.
      EXPECT_NEAR(collapsed[17], std::sqrt(24.0) * t[17 * 12], 1e-4);
    }
    Matrix mc(std::move(collapsed), n, 1);
    Matrix mf(std::move(full), n, 12);
    const std::vector<std::size_t> seeds = { 0, 1, 2 };
    const LloydRun rc =
      Lloyd(mc.view, km::KMeansCentresFromCells(mc.view, seeds), 3, Options(300, 0));
    const LloydRun rf =
      Lloyd(mf.view, km::KMeansCentresFromCells(mf.view, seeds), 3, Options(300, 0));
    EXPECT_EQ(rc.labels, rf.labels);
    EXPECT_NEAR(rc.result.inertia, rf.result.inertia, 1e-4 * rf.result.inertia);
    EXPECT_EQ(rc.result.counts, rf.result.counts);
  }

  std::vector<float> m;
  const auto pn =
    km::KMeansPrepareFeatures({ { "N", notConstant.data(), 12, 1.0 } }, n, false, true, m);
  EXPECT_FALSE(pn[0].collapsed);
  EXPECT_EQ(pn[0].features, 12);
  EXPECT_EQ(m.size(), 12 * n);
  // One component is never collapsed.
  const auto p1 = km::KMeansPrepareFeatures({ { "one", t.data(), 1, 1.0 } }, n, false, true, m);
  EXPECT_FALSE(p1[0].collapsed);
  EXPECT_EQ(p1[0].features, 1);
}

// Several arrays: features in order, firstFeature counted over the kept ones.
TEST(KMeans, PrepareLayout)
{
  const std::vector<float> a = { 1, 2, 3 };
  const std::vector<float> b = { 1, 11, 2, 12, 3, 13 }; // b1 = b0 + 10 exactly: collapses
  const std::vector<float> c = { 5, 0, 6, 1, 7, 3 };    // c1 - c0 = -5, -5, -4: does not
  std::vector<float> m;
  const auto p = km::KMeansPrepareFeatures(
    { { "a", a.data(), 1, 1.0 }, { "b", b.data(), 2, 2.0 }, { "c", c.data(), 2, 1.0 } },
    3,
    false,
    true,
    m);
  ASSERT_EQ(p.size(), 3u);
  EXPECT_EQ(p[0].firstFeature, 0);
  EXPECT_EQ(p[1].firstFeature, 1);
  EXPECT_TRUE(p[1].collapsed);
  EXPECT_EQ(p[1].features, 1);
  EXPECT_EQ(p[2].firstFeature, 2);
  EXPECT_EQ(p[2].features, 2);
  EXPECT_EQ(p[1].name, "b");
  EXPECT_EQ(p[1].mean, (std::vector<double>{ 2.0, 12.0 }));
  // a: 1 2 3; b: sqrt(2 * 2) b0 = 2 4 6; c: 5 6 7 then 0 1 3.
  EXPECT_EQ(m, (std::vector<float>{ 1, 2, 3, 2, 4, 6, 5, 6, 7, 0, 1, 3 }));
}

//------------------------------------------------------------------------------
// Empty cluster, worked by hand: x = 0 1 2 10, K = 3 from centres 0 0 10 (two the same).
//  it 1: ties go to cluster 0: labels 0 0 0 2, cluster 1 empty, kept d2 0 1 4 0. The farthest
//        cell is 2 (d2 4): it leaves cluster 0 (sum 3 - 2 = 1, count 2, centre 0.5) and becomes
//        cluster 1 (centre 2). Centres 0.5 2 10, shift 0.25 + 4.
//  it 2: 0: (0.25, 4, 100) -> 0; 1: (0.25, 1, 81) -> 0; 2: (2.25, 0, 64) -> 1; 10 -> 2. One label
//        changed; centres 0.5 2 10 again: shift 0 <= tolerance: stop (Tolerance), 2 iterations.
//  inertia 0.25 + 0.25 + 0 + 0 = 0.5.
TEST(KMeans, EmptyClusterRelocation)
{
  Matrix x({ { 0 }, { 1 }, { 2 }, { 10 } });
  const LloydRun run = Lloyd(x.view, { 0, 0, 10 }, 3, Options(300, 1e-4));
  EXPECT_EQ(run.result.relocated, 1);
  EXPECT_EQ(run.result.reason, km::KMeansStopReason::Tolerance);
  EXPECT_EQ(run.result.iterations, 2);
  EXPECT_EQ(run.labels, (std::vector<std::int32_t>{ 0, 0, 1, 2 }));
  EXPECT_EQ(run.result.centres, (std::vector<float>{ 0.5f, 2.0f, 10.0f }));
  EXPECT_EQ(run.result.counts, (std::vector<std::int64_t>{ 2, 1, 1 }));
  EXPECT_EQ(run.result.inertia, 0.5);
  ASSERT_EQ(run.progress.size(), 2u);
  EXPECT_EQ(run.progress[1].second, 1u);
}

// Two empty clusters and a tie in distance: x = 0 4 -4 1, K = 3 from centres 0 0 0.
//  it 1: all to cluster 0, d2 0 16 16 1. Clusters 1 and 2 take the two farthest cells in cell
//        order of the tie: cluster 1 <- cell 1 (4), cluster 2 <- cell 2 (-4). Cluster 0 keeps
//        0 + 1 (sum 1 - 4 + 4 = 1, count 2): centre 0.5.
//  it 2: labels 0 1 2 0 (2 changed); centres 0.5 4 -4 again: Tolerance, 2 iterations, inertia
//        0.25 + 0.25 = 0.5.
TEST(KMeans, TwoEmptyClustersTieOrder)
{
  Matrix x({ { 0 }, { 4 }, { -4 }, { 1 } });
  const LloydRun run = Lloyd(x.view, { 0, 0, 0 }, 3, Options(300, 0.0));
  EXPECT_EQ(run.result.relocated, 2);
  EXPECT_EQ(run.result.centres, (std::vector<float>{ 0.5f, 4.0f, -4.0f }));
  EXPECT_EQ(run.labels, (std::vector<std::int32_t>{ 0, 1, 2, 0 }));
  EXPECT_EQ(run.result.reason, km::KMeansStopReason::Tolerance);
  EXPECT_EQ(run.result.iterations, 2);
  EXPECT_EQ(run.result.inertia, 0.5);
}

// More clusters than distinct points: every cell sits on its centre (largest d2 is 0), so nothing
// is relocated (scikit-learn's rule) and the empty cluster's centre becomes its sums, 0.
// x = 5 5 5, K = 2 from 5 5: it 1 all to 0; centres 5, 0. it 2: d2 (0, 25): nothing changed.
TEST(KMeans, NoRelocationWhenAllOnCentres)
{
  Matrix x(std::vector<std::vector<float>>{ { 5 }, { 5 }, { 5 } });
  const LloydRun run = Lloyd(x.view, { 5, 5 }, 2, Options(300, 1e-4));
  EXPECT_EQ(run.result.relocated, 0);
  EXPECT_EQ(run.result.reason, km::KMeansStopReason::Converged);
  EXPECT_EQ(run.result.iterations, 2);
  EXPECT_EQ(run.result.centres, (std::vector<float>{ 5.0f, 0.0f }));
  EXPECT_EQ(run.result.counts, (std::vector<std::int64_t>{ 3, 0 }));
  EXPECT_EQ(run.result.inertia, 0.0);
}

//------------------------------------------------------------------------------
// The distributed path (KMeansOptions::reduction, as vtkTerroirKMeans uses it under MPI) gives
// the serial answer when the cells are split among "processes" (threads here): on the
// hand-worked examples above, including the relocations and their tie (the farthest cells sit
// on different processes), with every split; and on random data with three and four parts,
// whose per-process sums are added in another order than the serial blocks: the same labels,
// centres within a few float ulps.
TEST(KMeans, DistributedMatchesSerial)
{
  struct Case
  {
    std::vector<std::vector<float>> points;
    std::vector<float> centres;
    int k;
    double tolerance;
  };
  const std::vector<Case> cases = {
    { kLine, { 1, 2 }, 2, 1e-4 },
    { { { 0 }, { 1 }, { 2 }, { 10 } }, { 0, 0, 10 }, 3, 1e-4 },
    { { { 0 }, { 4 }, { -4 }, { 1 } }, { 0, 0, 0 }, 3, 0.0 },
    { { { 5 }, { 5 }, { 5 } }, { 5, 5 }, 2, 1e-4 },
  };
  for (const Case& c : cases)
  {
    Matrix x(c.points);
    const LloydRun serial = Lloyd(x.view, c.centres, c.k, Options(300, c.tolerance));
    for (std::size_t split = 1; split < c.points.size(); ++split)
    {
      const LloydRun run =
        DistributedLloyd(x, c.centres, c.k, Options(300, c.tolerance), 2, { 0, split });
      EXPECT_EQ(run.labels, serial.labels) << "split " << split;
      EXPECT_EQ(run.result.centres, serial.result.centres) << "split " << split;
      EXPECT_EQ(run.result.counts, serial.result.counts) << "split " << split;
      EXPECT_EQ(run.result.relocated, serial.result.relocated) << "split " << split;
      EXPECT_EQ(run.result.iterations, serial.result.iterations) << "split " << split;
      EXPECT_EQ(run.result.reason, serial.result.reason) << "split " << split;
      EXPECT_EQ(run.result.inertia, serial.result.inertia) << "split " << split;
    }
  }
  const Matrix random = RandomMatrix(30000, 3, 7);
  const std::vector<float> centres = { -0.5f, 0, 0, 0.5f, 0, 0, 0, 0.5f, 0.5f, 0, -0.5f, -0.5f };
  const LloydRun serial = Lloyd(random.view, centres, 4, Options(300, 0.0));
  for (const std::vector<std::size_t>& starts :
    { std::vector<std::size_t>{ 0, 9000, 21000 }, std::vector<std::size_t>{ 0, 1, 4097, 29999 } })
  {
    const LloydRun run = DistributedLloyd(
      random, centres, 4, Options(300, 0.0), static_cast<int>(starts.size()), starts);
    EXPECT_EQ(run.labels, serial.labels);
    EXPECT_EQ(run.result.counts, serial.result.counts);
    EXPECT_EQ(run.result.iterations, serial.result.iterations);
    ASSERT_EQ(run.result.centres.size(), serial.result.centres.size());
    for (std::size_t i = 0; i < centres.size(); ++i)
    {
      EXPECT_NEAR(run.result.centres[i], serial.result.centres[i], 1e-6);
    }
    EXPECT_NEAR(run.result.inertia, serial.result.inertia, 1e-9 * serial.result.inertia);
  }
}

// The seeds' positions among the valid diagonal cells (the rule a distributed run applies to the
// gathered validity) and the diagonal itself are KMeansDiagonalSeedCells' own: on a 7 x 4 grid
// with no mask the diagonal is (0,0) (1,1) (2,1) (3,2) (4,2) (5,3) (6,3), and K = 3 picks
// positions 1, 3, 5.
TEST(KMeans, DiagonalSeedPositions)
{
  EXPECT_EQ(km::KMeansDiagonalCells(7, 4), (std::vector<std::size_t>{ 0, 8, 9, 17, 18, 26, 27 }));
  EXPECT_EQ(km::KMeansDiagonalSeedPositions(7, 3), (std::vector<std::size_t>{ 1, 3, 5 }));
  EXPECT_EQ(km::KMeansDiagonalSeedCells(7, 4, nullptr, 3), (std::vector<std::size_t>{ 8, 17, 26 }));
}

// KMeansApplyPreparation gives cells prepared later the bits KMeansPrepareFeatures gave them,
// standardised or not, with a collapsed array.
TEST(KMeans, ApplyPreparationSameBits)
{
  const std::size_t n = 50;
  std::vector<float> a(n), t(n * 3);
  for (std::size_t c = 0; c < n; ++c)
  {
    a[c] = static_cast<float>(c * c % 17) * 0.37f;
    for (int j = 0; j < 3; ++j)
    {
      t[c * 3 + j] = static_cast<float>(c) * 0.1f + static_cast<float>(j);
    }
  }
  for (bool standardize : { false, true })
  {
    std::vector<float> all;
    const auto prepared = km::KMeansPrepareFeatures(
      { { "a", a.data(), 1, 2.0 }, { "t", t.data(), 3, 0.5 } }, n, standardize, true, all);
    ASSERT_TRUE(prepared[1].collapsed);
    // Cells 10..19 prepared again from the same statistics.
    std::vector<float> later;
    km::KMeansApplyPreparation({ { "a", a.data() + 10, 1, 2.0 }, { "t", t.data() + 30, 3, 0.5 } },
      prepared,
      10,
      standardize,
      later);
    ASSERT_EQ(later.size(), 20u);
    for (int f = 0; f < 2; ++f)
    {
      for (std::size_t c = 0; c < 10; ++c)
      {
        EXPECT_TRUE(SameBits(&later[f * 10 + c], &all[f * n + 10 + c], sizeof(float)))
          << "feature " << f << " cell " << c;
      }
    }
  }
}

//------------------------------------------------------------------------------
// Stops on the 1-D example (Lloyd1D): shifts 56.25 (it 1) and 13.25 (it 2); mean variance
// 2824/49 = 57.63.
//  - tolerance 0.5 (threshold 28.8): it 1 goes on, it 2 stops (Tolerance, 2 iterations) with
//    centres 2, 13; the final assignment keeps labels 0 0 0 1 1 1 1, inertia 196.
//  - tolerance 1 (threshold 57.6 >= 56.25): stops after it 1 with centres 1, 9.5, whose own
//    labels were 0 1 1 1 1 1 1; the final assignment to 1, 9.5 gives 0 0 0 1 1 1 1 (counts 3, 4)
//    and inertia 0 + 1 + 4 + 2.25 + 0.25 + 0.25 + 240.25 = 248.
//  - maximumIterations 1: the same as tolerance 1, stopped by MaximumIterations.
//  - maximumIterations 2 (tolerance 0): centres 2, 13, inertia 196, MaximumIterations.
TEST(KMeans, ToleranceAndMaximumIterations)
{
  Matrix x(kLine);
  const LloydRun t05 = Lloyd(x.view, { 1, 2 }, 2, Options(300, 0.5));
  EXPECT_EQ(t05.result.reason, km::KMeansStopReason::Tolerance);
  EXPECT_EQ(t05.result.iterations, 2);
  EXPECT_EQ(t05.result.centres, (std::vector<float>{ 2, 13 }));
  EXPECT_EQ(t05.result.inertia, 196.0);

  const LloydRun t1 = Lloyd(x.view, { 1, 2 }, 2, Options(300, 1.0));
  EXPECT_EQ(t1.result.reason, km::KMeansStopReason::Tolerance);
  EXPECT_EQ(t1.result.iterations, 1);
  EXPECT_EQ(t1.result.centres, (std::vector<float>{ 1, 9.5 }));
  EXPECT_EQ(t1.labels, (std::vector<std::int32_t>{ 0, 0, 0, 1, 1, 1, 1 }));
  EXPECT_EQ(t1.result.counts, (std::vector<std::int64_t>{ 3, 4 }));
  EXPECT_EQ(t1.result.inertia, 248.0);
  EXPECT_EQ(t1.distances, (std::vector<float>{ 0, 1, 4, 2.25, 0.25, 0.25, 240.25 }));
  // The loop's own assignment (before the final one) changed all 7 labels.
  ASSERT_EQ(t1.progress.size(), 1u);
  EXPECT_EQ(t1.progress[0].second, 7u);

  const LloydRun m1 = Lloyd(x.view, { 1, 2 }, 2, Options(1, 0.0));
  EXPECT_EQ(m1.result.reason, km::KMeansStopReason::MaximumIterations);
  EXPECT_EQ(m1.result.iterations, 1);
  EXPECT_EQ(m1.result.centres, (std::vector<float>{ 1, 9.5 }));
  EXPECT_EQ(m1.labels, (std::vector<std::int32_t>{ 0, 0, 0, 1, 1, 1, 1 }));
  EXPECT_EQ(m1.result.inertia, 248.0);

  const LloydRun m2 = Lloyd(x.view, { 1, 2 }, 2, Options(2, 0.0));
  EXPECT_EQ(m2.result.reason, km::KMeansStopReason::MaximumIterations);
  EXPECT_EQ(m2.result.iterations, 2);
  EXPECT_EQ(m2.result.centres, (std::vector<float>{ 2, 13 }));
  EXPECT_EQ(m2.result.inertia, 196.0);

  EXPECT_STREQ(km::KMeansStopReasonName(km::KMeansStopReason::Converged), "Converged");
  EXPECT_STREQ(km::KMeansStopReasonName(km::KMeansStopReason::Tolerance), "Tolerance");
  EXPECT_STREQ(
    km::KMeansStopReasonName(km::KMeansStopReason::MaximumIterations), "MaximumIterations");
}

// The first iteration never counts as converged (scikit-learn compares with labels of -1), even
// on an engine whose labels already are the answer. From the solution of Lloyd1D (centres 2, 13):
// it 1 changes no label of the reused engine, yet goes on to the stop tests: the centres moved
// 0 <= tolerance, so it stops by Tolerance after 1 iteration, then assigns once more.
TEST(KMeans, FirstIterationNeverConverged)
{
  Matrix x(kLine);
  km::KMeansCPUEngine engine(x.view);
  const km::KMeansResult first = km::KMeansLloyd(engine, x.view, { 1, 2 }, 2, Options(300, 0.0));
  ASSERT_EQ(first.reason, km::KMeansStopReason::Converged);
  std::vector<std::size_t> changed;
  const km::KMeansResult again = km::KMeansLloyd(engine,
    x.view,
    first.centres,
    2,
    Options(300, 0.0),
    [&](int, std::size_t n) { changed.push_back(n); });
  EXPECT_EQ(changed, (std::vector<std::size_t>{ 0 }));
  EXPECT_EQ(again.reason, km::KMeansStopReason::Tolerance);
  EXPECT_EQ(again.iterations, 1);
  EXPECT_EQ(again.centres, first.centres);
  EXPECT_EQ(again.inertia, 196.0);
}

//------------------------------------------------------------------------------
// The same bits whatever the split of the work: serial, odd pieces in reversed order, and two
// real threads, on 3 full blocks and a partial one.
TEST(KMeans, ThreadCountIndependence)
{
  const std::size_t n = 3 * km::KMeansBlockCells + 1234;
  std::mt19937_64 rng(77);
  std::vector<float> raw(n * 6);
  for (float& v : raw)
  {
    v = static_cast<float>(100.0 * Uniform(rng));
  }
  const std::vector<km::KMeansInputArray> arrays = { { "a", raw.data(), 4, 1.5 },
    { "b", raw.data() + 4 * n, 2, 0.5 } };
  // Note: "b" reads the tail of raw as 2-component values of n cells (2n floats, inside raw).
  std::vector<float> m0;
  std::vector<float> m1;
  std::vector<float> m2;
  const auto p0 = km::KMeansPrepareFeatures(arrays, n, true, true, m0);
  const auto p1 = km::KMeansPrepareFeatures(arrays, n, true, true, m1, OddReversed);
  km::KMeansPrepareFeatures(arrays, n, true, true, m2, TwoThreads);
  EXPECT_EQ(m0, m1);
  EXPECT_EQ(m0, m2);
  EXPECT_EQ(p0[0].mean, p1[0].mean);
  EXPECT_EQ(p0[0].stddev, p1[0].stddev);
  Matrix x(std::move(m0), n, 6);
  EXPECT_EQ(km::KMeansMeanVariance(x.view), km::KMeansMeanVariance(x.view, OddReversed));

  const auto seeds = km::KMeansPlusPlusSeeds(x.view, 7, 5);
  EXPECT_EQ(seeds, km::KMeansPlusPlusSeeds(x.view, 7, 5, OddReversed));
  EXPECT_EQ(seeds, km::KMeansPlusPlusSeeds(x.view, 7, 5, TwoThreads));
  const std::vector<float> centres = km::KMeansCentresFromCells(x.view, seeds);
  const LloydRun serial = Lloyd(x.view, centres, 7, Options(300, 1e-4));
  EXPECT_GT(serial.result.iterations, 3);
  for (const km::KMeansParallelFor& pf :
    { km::KMeansParallelFor(OddReversed), km::KMeansParallelFor(TwoThreads) })
  {
    const LloydRun other = Lloyd(x.view, centres, 7, Options(300, 1e-4), pf);
    EXPECT_EQ(other.labels, serial.labels);
    EXPECT_TRUE(SameBits(other.distances.data(), serial.distances.data(), n * sizeof(float)));
    EXPECT_TRUE(SameBits(other.result.centres.data(),
      serial.result.centres.data(),
      serial.result.centres.size() * sizeof(float)));
    EXPECT_TRUE(SameBits(&other.result.inertia, &serial.result.inertia, sizeof(double)));
    EXPECT_EQ(other.result.counts, serial.result.counts);
    EXPECT_EQ(other.result.iterations, serial.result.iterations);
    EXPECT_EQ(other.progress, serial.progress);
  }

  // The engine's Sums is the block-order total of KMeansBlockSums.
  km::KMeansCPUEngine engine(x.view, OddReversed);
  engine.Assign(serial.result.centres, 7);
  std::vector<double> sums;
  std::vector<std::int64_t> counts;
  double inertia = 0.0;
  engine.Sums(7, sums, counts, inertia);
  std::vector<double> es(7 * 6, 0.0);
  std::vector<std::int64_t> ec(7, 0);
  double ei = 0.0;
  for (std::size_t b = 0; b < x.view.Blocks(); ++b)
  {
    std::vector<double> s(7 * 6);
    std::vector<std::int64_t> c(7);
    double in = 0.0;
    km::KMeansBlockSums(x.view, engine.Labels(), engine.Distances(), 7, b, s.data(), c.data(), &in);
    for (std::size_t i = 0; i < s.size(); ++i)
    {
      es[i] += s[i];
    }
    for (int i = 0; i < 7; ++i)
    {
      ec[i] += c[i];
    }
    ei += in;
  }
  EXPECT_TRUE(SameBits(sums.data(), es.data(), es.size() * sizeof(double)));
  EXPECT_EQ(counts, ec);
  EXPECT_TRUE(SameBits(&inertia, &ei, sizeof(double)));
  EXPECT_EQ(counts, serial.result.counts);
  EXPECT_TRUE(SameBits(&inertia, &serial.result.inertia, sizeof(double)));
}

//------------------------------------------------------------------------------
TEST(KMeans, BadInput)
{
  const std::vector<float> v = { 1, 2, 3, 4 };
  std::vector<float> out;
  auto prepare = [&](std::vector<km::KMeansInputArray> arrays)
  { km::KMeansPrepareFeatures(arrays, 4, false, true, out); };
  auto message = [&](std::vector<km::KMeansInputArray> arrays) -> std::string
  {
    try
    {
      prepare(arrays);
    }
    catch (const std::invalid_argument& e)
    {
      return e.what();
    }
    return "";
  };
  EXPECT_THROW(prepare({ { "Slope", nullptr, 1, 1.0 } }), std::invalid_argument);
  EXPECT_NE(message({ { "Slope", nullptr, 1, 1.0 } }).find("Slope"), std::string::npos);
  EXPECT_THROW(prepare({ { "Slope", v.data(), 0, 1.0 } }), std::invalid_argument);
  EXPECT_THROW(prepare({ { "Slope", v.data(), 1, -1.0 } }), std::invalid_argument);
  EXPECT_THROW(prepare({ { "Slope", v.data(), 1, NAN } }), std::invalid_argument);
  EXPECT_THROW(prepare({ { "Slope", v.data(), 1, INFINITY } }), std::invalid_argument);
  EXPECT_THROW(prepare({ { "Slope", v.data(), 1, 0.0 } }), std::invalid_argument);
  EXPECT_THROW(prepare({}), std::invalid_argument);
  const std::vector<float> withNaN = { 1, NAN, 3, 4 };
  const std::vector<float> withInf = { 1, 2, -INFINITY, 4 };
  EXPECT_THROW(prepare({ { "Aspect", withNaN.data(), 1, 1.0 } }), std::invalid_argument);
  EXPECT_THROW(prepare({ { "Aspect", withInf.data(), 1, 1.0 } }), std::invalid_argument);
  EXPECT_NE(
    message({ { "A", v.data(), 1, 1.0 }, { "Aspect", withInf.data(), 1, 1.0 } }).find("Aspect"),
    std::string::npos);
  EXPECT_NO_THROW(prepare({ { "A", v.data(), 1, 1.0 }, { "B", v.data(), 1, 0.0 } }));

  Matrix x(kLine);
  km::KMeansCPUEngine engine(x.view);
  const km::KMeansOptions ok;
  EXPECT_THROW(km::KMeansLloyd(engine, x.view, {}, 0, ok), std::invalid_argument);
  EXPECT_THROW(
    km::KMeansLloyd(engine, x.view, std::vector<float>(65), 65, ok), std::invalid_argument);
  EXPECT_THROW(km::KMeansLloyd(engine, x.view, std::vector<float>(8), 8, ok), // 8 > 7 cells
    std::invalid_argument);
  EXPECT_THROW(km::KMeansLloyd(engine, x.view, { 1, 2, 3 }, 2, ok), std::invalid_argument);
  EXPECT_THROW(
    km::KMeansLloyd(engine, x.view, { 1, 2 }, 2, Options(0, 1e-4)), std::invalid_argument);
  EXPECT_THROW(
    km::KMeansLloyd(engine, x.view, { 1, 2 }, 2, Options(10, -1.0)), std::invalid_argument);
  EXPECT_THROW(
    km::KMeansLloyd(engine, x.view, { 1, 2 }, 2, Options(10, NAN)), std::invalid_argument);
  EXPECT_NO_THROW(km::KMeansLloyd(engine, x.view, { 1, 2 }, 2, ok));
  EXPECT_THROW(km::KMeansCentresFromCells(x.view, { 7 }), std::invalid_argument);
}

//------------------------------------------------------------------------------
TEST(KMeans, Palette)
{
  // Tableau 10, then navy and black, cycled both ways.
  const char* expected[12] = { "#1f77b4",
    "#ff7f0e",
    "#2ca02c",
    "#d62728",
    "#9467bd",
    "#8c564b",
    "#e377c2",
    "#7f7f7f",
    "#bcbd22",
    "#17becf",
    "#000080",
    "#000000" };
  for (int i = 0; i < 12; ++i)
  {
    EXPECT_EQ(km::KMeansClusterColor(i), expected[i]);
    EXPECT_EQ(km::KMeansClusterColor(i + 12), expected[i]);
    EXPECT_EQ(km::KMeansClusterColor(i - 24), expected[i]);
  }
  EXPECT_EQ(km::KMeansClusterColor(-1), "#000000");
  unsigned char rgb[3];
  km::KMeansClusterColorRGB(3, rgb);
  EXPECT_EQ(rgb[0], 0xd6);
  EXPECT_EQ(rgb[1], 0x27);
  EXPECT_EQ(rgb[2], 0x28);
  km::KMeansClusterColorRGB(-2, rgb); // entry 10: navy
  EXPECT_EQ(rgb[0], 0x00);
  EXPECT_EQ(rgb[1], 0x00);
  EXPECT_EQ(rgb[2], 0x80);
}

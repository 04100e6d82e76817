// Timing of the k-means core's two heavy steps (Filters/Clustering/Core/KMeans.h) on 1024 x 1024
// cells x 37 features (the size of Long (2016)'s resources: 12 illumination + 12 temperature + 12
// humidity + slope), K = 5 and 10, 1 and 2 threads (std::thread in a ParallelFor lambda).
//   engine:   KMeansCPUEngine::Assign (which sums each block right after assigning it) and Sums
//             (which then only adds the blocks);
//   separate: KMeansAssignRange over all cells, then KMeansBlockSums over all blocks.
// Best of REPS runs, wall-clock milliseconds; also checks that both thread counts give the same
// bits. Built and run by kmeans_core.sh. Not a test: nothing here is asserted.
#include "KMeans.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <thread>
#include <vector>

namespace km = terroir::clustering;
using Clock = std::chrono::steady_clock;

namespace
{
double Ms(Clock::time_point a, Clock::time_point b)
{
  return std::chrono::duration<double, std::milli>(b - a).count();
}

/// FNV-1a over bytes: a fingerprint of labels, distances and sums.
std::uint64_t Hash(std::uint64_t h, const void* p, std::size_t bytes)
{
  const unsigned char* q = static_cast<const unsigned char*>(p);
  for (std::size_t i = 0; i < bytes; ++i)
  {
    h = (h ^ q[i]) * 1099511628211ull;
  }
  return h;
}
} // namespace

int main(int argc, char** argv)
{
  const int reps = argc > 1 ? std::max(1, std::atoi(argv[1])) : 20;
  const std::size_t n = 1024 * 1024;
  const int nf = 37;
  // Smooth fields with a little noise: spatially coherent labels, as on a terrain.
  std::vector<float> data(n * nf);
  std::mt19937_64 rng(1);
  for (int f = 0; f < nf; ++f)
  {
    for (std::size_t c = 0; c < n; ++c)
    {
      const float i = static_cast<float>(c % 1024);
      const float j = static_cast<float>(c / 1024);
      data[f * n + c] = std::sin(0.01f * i * static_cast<float>(f + 1) + 0.02f * j) +
        0.01f * static_cast<float>(rng() >> 40) / 16777216.0f;
    }
  }
  const km::KMeansFeatures features{ data.data(), n, nf };
  const km::KMeansParallelFor two =
    [](std::size_t b, std::size_t e, const std::function<void(std::size_t, std::size_t)>& body)
  {
    const std::size_t mid = b + (e - b) / 2;
    std::thread t([&] { body(b, mid); });
    body(mid, e);
    t.join();
  };
  const std::size_t blocks = features.Blocks();
  std::printf("k-means core, %zu cells x %d features, best of %d (ms)\n", n, nf, reps);
  std::printf("%3s %7s | %8s %8s %8s | %8s %8s %8s | %s\n",
    "K",
    "threads",
    "Assign",
    "Sums",
    "engine",
    "Assign",
    "Sums",
    "separate",
    "bits");
  for (int k : { 5, 10 })
  {
    const std::vector<float> centres =
      km::KMeansCentresFromCells(features, km::KMeansDiagonalSeedCells(1024, 1024, nullptr, k));
    std::uint64_t reference = 0;
    for (int threads : { 1, 2 })
    {
      const km::KMeansParallelFor pf = threads == 2 ? two : km::KMeansParallelFor{};
      km::KMeansCPUEngine engine(features, pf);
      std::vector<double> sums;
      std::vector<std::int64_t> counts;
      double inertia = 0.0;
      double ea = 1e30;
      double es = 1e30;
      for (int r = 0; r < reps; ++r)
      {
        const auto t0 = Clock::now();
        engine.Assign(centres, k);
        const auto t1 = Clock::now();
        engine.Sums(k, sums, counts, inertia);
        const auto t2 = Clock::now();
        ea = std::min(ea, Ms(t0, t1));
        es = std::min(es, Ms(t1, t2));
      }
      std::uint64_t h = 1469598103934665603ull;
      h = Hash(h, engine.Labels(), n * sizeof(std::int32_t));
      h = Hash(h, engine.Distances(), n * sizeof(float));
      h = Hash(h, sums.data(), sums.size() * sizeof(double));
      h = Hash(h, &inertia, sizeof(inertia));
      reference = threads == 1 ? h : reference;

      std::vector<std::int32_t> labels(n, -1);
      std::vector<float> d2(n);
      const std::size_t per = static_cast<std::size_t>(k) * nf;
      std::vector<double> bs(blocks * per);
      std::vector<std::int64_t> bc(blocks * k);
      std::vector<double> bi(blocks);
      double sa = 1e30;
      double ss = 1e30;
      auto assign = [&](std::size_t b0, std::size_t b1)
      {
        km::KMeansAssignRange(features,
          centres.data(),
          k,
          b0 * km::KMeansBlockCells,
          std::min(n, b1 * km::KMeansBlockCells),
          labels.data(),
          d2.data());
      };
      auto blockSums = [&](std::size_t b0, std::size_t b1)
      {
        for (std::size_t b = b0; b < b1; ++b)
        {
          km::KMeansBlockSums(
            features, labels.data(), d2.data(), k, b, &bs[b * per], &bc[b * k], &bi[b]);
        }
      };
      for (int r = 0; r < reps; ++r)
      {
        const auto t0 = Clock::now();
        pf ? pf(0, blocks, assign) : assign(0, blocks);
        const auto t1 = Clock::now();
        pf ? pf(0, blocks, blockSums) : blockSums(0, blocks);
        const auto t2 = Clock::now();
        sa = std::min(sa, Ms(t0, t1));
        ss = std::min(ss, Ms(t1, t2));
      }
      std::printf("%3d %7d | %8.2f %8.2f %8.2f | %8.2f %8.2f %8.2f | %s\n",
        k,
        threads,
        ea,
        es,
        ea + es,
        sa,
        ss,
        sa + ss,
        h == reference ? "same" : "DIFFERENT");
    }
  }
  return 0;
}

// Bit-identity hashes and timing of the erosion core (Filters/Terrain/Core/Erosion.h), for the
// speed work of issue 27. Not a test: nothing here is asserted.
//
//   ErosionCoreTiming hash [STEPS]
//     Runs STEPS (default 40) hydraulic + thermal steps on a few random terrains that between them
//     use every option of the core (Closed and Sea boundaries, scattered no-data cells and a
//     disc of them, a soil layer, per-cell erosion and talus factors, rain, an evaporation field,
//     the soft outflow, Weiss's eq. 24 and bed cap, the capacity ramp, pipe areas, per-row
//     spacings, 1-cell-wide grids) and
//     prints an FNV-1a hash of every state array and of the step statistics, once with the rows
//     in order and once with random row splits (the two lines must agree). An optimisation of the
//     core must leave every line unchanged: record them before, compare after.
//   ErosionCoreTiming bench [N] [STEPS] [ROUNDS]
//     Steps per second at N^2 (default 1024) of the hydraulic step alone and of hydraulic +
//     thermal, with 1 and 2 threads (std::thread over row blocks, as the filter's vtkSMPTools),
//     best of ROUNDS interleaved rounds of STEPS steps each, and the process's CPU time per step
//     (steadier than the wall clock on a shared machine). The terrain is a fractal-like sum of
//     octaves with 10 m cells, the filter's defaults (Sea at 0 m below the whole terrain, rain
//     50 mm/h, 0.05 m of initial water), as in Testing/Benchmarks/erosion_vs_grass.sh.
//
// Built by hand against the core library (after `cmake --build build --target TerroirTerrainCore`):
//   g++ -O2 -std=c++17 -pthread -IFilters/Terrain/Core -ICommon/Core \
//     Testing/Benchmarks/ErosionCoreTiming.cxx build/lib/libTerroirTerrainCore.a \
//     build/lib/libTerroirCommonCore.a -o /tmp/erosion_timing
#include "Erosion.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <functional>
#include <random>
#include <string>
#include <thread>
#include <vector>

namespace tr = terroir::terrain;
using Clock = std::chrono::steady_clock;

namespace
{

/// FNV-1a over bytes.
std::uint64_t Hash(std::uint64_t h, const void* p, std::size_t bytes)
{
  const unsigned char* q = static_cast<const unsigned char*>(p);
  for (std::size_t i = 0; i < bytes; ++i)
  {
    h = (h ^ q[i]) * 1099511628211ull;
  }
  return h;
}

template<typename T>
std::uint64_t HashVec(std::uint64_t h, const std::vector<T>& v)
{
  const std::uint64_t n = v.size();
  h = Hash(h, &n, sizeof(n));
  return v.empty() ? h : Hash(h, v.data(), v.size() * sizeof(T));
}

double Uniform(std::mt19937_64& rng)
{
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

/// Row scheduler that runs the body over random row chunks, in order, on this thread.
tr::ErosionParallelFor RandomSplits(std::mt19937_64& rng)
{
  return [&rng](int begin, int end, const std::function<void(int, int)>& body)
  {
    int j = begin;
    while (j < end)
    {
      const int len = 1 + static_cast<int>(rng() % 7);
      const int stop = std::min(end, j + len);
      body(j, stop);
      j = stop;
    }
  };
}

/// Row scheduler over `threads` std::threads, one contiguous block each.
tr::ErosionParallelFor Threads(int threads)
{
  if (threads <= 1)
  {
    return {};
  }
  return [threads](int begin, int end, const std::function<void(int, int)>& body)
  {
    std::vector<std::thread> pool;
    const int n = end - begin;
    for (int t = 0; t < threads; ++t)
    {
      const int a = begin + static_cast<int>(static_cast<long long>(n) * t / threads);
      const int b = begin + static_cast<int>(static_cast<long long>(n) * (t + 1) / threads);
      if (b > a)
      {
        pool.emplace_back(body, a, b);
      }
    }
    for (std::thread& th : pool)
    {
      th.join();
    }
  };
}

/// One random hash case: a terrain, its options and the per-cell fields.
struct Case
{
  const char* name;
  int nx, ny;
  bool sea, mask, soil, factors, rain, evapField, soft, halving, cap, ramp, pipeArea, rows;
  bool thermal;
  bool disc = false; ///< with mask: a disc of no-data cells instead of scattered ones
};

struct Setup
{
  tr::ErosionState st;
  tr::ErosionParams p;
  tr::ThermalParams tp;
  std::vector<float> rain, evap;
};

Setup MakeCase(const Case& k, std::uint64_t seed)
{
  std::mt19937_64 rng(seed);
  const std::size_t n = static_cast<std::size_t>(k.nx) * k.ny;
  std::vector<float> z(n), soil(n);
  std::vector<std::uint8_t> valid(n, 1);
  std::vector<double> rowDx(k.ny), rowDy(k.ny);
  for (int j = 0; j < k.ny; ++j)
  {
    rowDx[j] = k.rows ? 8.0 + 4.0 * std::cos(0.05 * j) : 10.0;
    rowDy[j] = k.rows ? 9.0 + 0.5 * Uniform(rng) : 10.0;
    for (int i = 0; i < k.nx; ++i)
    {
      const std::size_t c = static_cast<std::size_t>(j) * k.nx + i;
      z[c] = static_cast<float>(20.0 * std::sin(0.21 * i) * std::cos(0.17 * j) + 0.3 * i - 0.2 * j +
        6.0 * Uniform(rng) + (Uniform(rng) < 0.03 ? 30.0 : 0.0));
      soil[c] = static_cast<float>(Uniform(rng) < 0.2 ? 0.0 : 2.0 * Uniform(rng));
      const double di = i - k.nx / 3.0, dj = j - k.ny / 2.0;
      const bool hole = k.disc ? di * di + dj * dj < k.ny * k.ny / 16.0 : Uniform(rng) < 0.06;
      if (k.mask && hole)
      {
        valid[c] = 0;
        z[c] = std::nanf("");
      }
    }
  }
  terroir::GridView<float> view;
  view.data = z.data();
  view.nx = k.nx;
  view.ny = k.ny;
  view.rowDx = rowDx.data();
  view.rowDy = rowDy.data();
  view.valid = k.mask ? valid.data() : nullptr;
  Setup s{ tr::MakeErosionState(view, k.soil ? soil.data() : nullptr), {}, {}, {}, {} };
  for (std::size_t c = 0; c < n; ++c)
  {
    if (!s.st.IsValid(c))
    {
      continue;
    }
    s.st.water[c] = static_cast<float>(Uniform(rng) < 0.3 ? 0.0 : 0.5 * Uniform(rng));
    s.st.sediment[c] = static_cast<float>(Uniform(rng) < 0.5 ? 0.0 : 0.01 * Uniform(rng));
  }
  if (k.factors)
  {
    s.st.erosionFactor.resize(n);
    s.st.talusFactor.resize(n);
    for (std::size_t c = 0; c < n; ++c)
    {
      s.st.erosionFactor[c] = static_cast<float>(Uniform(rng));
      s.st.talusFactor[c] = static_cast<float>(0.5 + Uniform(rng));
    }
  }
  if (k.rain)
  {
    s.rain.resize(n);
    for (float& r : s.rain)
    {
      r = static_cast<float>(Uniform(rng) < 0.5 ? 0.0 : 0.05 * Uniform(rng));
    }
  }
  if (k.evapField)
  {
    s.evap.resize(n);
    for (float& e : s.evap)
    {
      e = static_cast<float>(2.0 * Uniform(rng) - 0.2);
    }
  }
  tr::ErosionParams& p = s.p;
  p.boundary = k.sea ? tr::ErosionBoundary::Sea : tr::ErosionBoundary::Closed;
  p.seaLevel = k.sea ? -5.0 : 0.0;
  p.evaporation = 0.5;
  p.capacity = 2.0;
  p.softOutflow = k.soft;
  p.softOutflowMin = 0.01;
  p.softOutflowScale = 3.0;
  p.halvingDepthErosion = k.halving ? 0.05 : 0.0;
  p.halvingDepthDeposition = k.halving ? 0.08 : 0.0;
  p.maxBedChange = k.cap ? 0.02 : 0.0;
  p.capacityDepth = k.ramp ? 0.1 : 0.0;
  p.pipeArea = k.pipeArea ? 3.0 : 0.0;
  p.dissolvingRock = 0.03;
  s.tp.rate = 0.7;
  return s;
}

std::uint64_t HashState(const tr::ErosionState& st, std::uint64_t h)
{
  for (const std::vector<float>* v : { &st.terrain,
         &st.original,
         &st.terrainResidue,
         &st.waterResidue,
         &st.soil,
         &st.erosionFactor,
         &st.talusFactor,
         &st.water,
         &st.sediment,
         &st.fluxW,
         &st.fluxE,
         &st.fluxS,
         &st.fluxN,
         &st.velocityU,
         &st.velocityV })
  {
    h = HashVec(h, *v);
  }
  return HashVec(h, st.valid);
}

std::uint64_t RunCase(const Case& k, int steps, bool split)
{
  Setup s = MakeCase(k, 12345 + static_cast<std::uint64_t>(k.nx) * 977 + k.ny);
  std::mt19937_64 splitRng(7);
  const tr::ErosionParallelFor pf = split ? RandomSplits(splitRng) : tr::ErosionParallelFor{};
  std::uint64_t h = 1469598103934665603ull;
  for (int step = 0; step < steps; ++step)
  {
    const tr::ErosionStepStats a = tr::ErosionHydraulicStep(s.st,
      s.p,
      s.rain.empty() ? nullptr : s.rain.data(),
      s.evap.empty() ? nullptr : s.evap.data(),
      pf);
    const double sa[7] = {
      a.rain, a.evaporated, a.waterToSea, a.waterClamped, a.eroded, a.deposited, a.sedimentScale
    };
    h = Hash(h, sa, sizeof(sa));
    if (k.thermal)
    {
      const tr::ThermalStepStats t = tr::ErosionThermalStep(s.st, s.tp, pf);
      const double st[2] = { t.moved, t.maxExcess };
      h = Hash(h, st, sizeof(st));
    }
    if (step % 10 == 9 || step + 1 == steps)
    {
      h = HashState(s.st, h);
    }
  }
  return h;
}

int HashMode(int steps)
{
  // name, nx, ny, sea, mask, soil, factors, rain, evapField, soft, halving, cap, ramp, pipeArea,
  // rows, thermal
  const Case cases[] = {
    { "closed-plain",
      97,
      61,
      false,
      false,
      false,
      false,
      true,
      false,
      false,
      false,
      false,
      false,
      false,
      false,
      true },
    { "sea-all",
      83,
      77,
      true,
      true,
      true,
      true,
      true,
      true,
      true,
      true,
      true,
      true,
      false,
      true,
      true },
    { "closed-mask-soil",
      64,
      64,
      false,
      true,
      true,
      false,
      false,
      true,
      false,
      false,
      false,
      false,
      true,
      false,
      true },
    { "sea-plain",
      70,
      45,
      true,
      false,
      false,
      false,
      true,
      false,
      false,
      false,
      false,
      false,
      false,
      false,
      true },
    { "closed-factors",
      50,
      90,
      false,
      false,
      true,
      true,
      true,
      false,
      true,
      true,
      true,
      true,
      true,
      true,
      true },
    { "sea-mask-hydro",
      66,
      33,
      true,
      true,
      false,
      true,
      false,
      true,
      false,
      false,
      false,
      false,
      false,
      true,
      false },
    { "closed-disc",
      71,
      63,
      false,
      true,
      true,
      false,
      true,
      false,
      false,
      false,
      false,
      false,
      false,
      false,
      true,
      true },
    { "sea-disc",
      64,
      80,
      true,
      true,
      false,
      true,
      true,
      true,
      true,
      true,
      true,
      false,
      false,
      true,
      true,
      true },
    { "sea-norain-soil",
      57,
      49,
      true,
      false,
      true,
      false,
      false,
      true,
      false,
      true,
      false,
      true,
      false,
      true,
      true },
    { "sea-1x9",
      1,
      9,
      true,
      false,
      true,
      false,
      true,
      false,
      false,
      false,
      false,
      false,
      false,
      false,
      true },
    { "closed-9x1",
      9,
      1,
      false,
      false,
      true,
      false,
      true,
      true,
      false,
      false,
      false,
      false,
      false,
      false,
      true },
    { "sea-2x2",
      2,
      2,
      true,
      false,
      false,
      false,
      true,
      false,
      false,
      false,
      false,
      false,
      false,
      false,
      true },
    { "sea-1x1",
      1,
      1,
      true,
      false,
      true,
      false,
      true,
      true,
      false,
      false,
      false,
      false,
      false,
      false,
      true },
    { "sea-3x2-mask",
      3,
      2,
      true,
      true,
      true,
      true,
      true,
      true,
      true,
      true,
      true,
      true,
      true,
      true,
      true },
  };
  bool same = true;
  for (const Case& k : cases)
  {
    const std::uint64_t a = RunCase(k, steps, false);
    const std::uint64_t b = RunCase(k, steps, true);
    same = same && a == b;
    std::printf("%-18s %016llx %016llx%s\n",
      k.name,
      static_cast<unsigned long long>(a),
      static_cast<unsigned long long>(b),
      a == b ? "" : "  SPLIT DIFFERS");
  }
  return same ? 0 : 1;
}

/// The benchmark's state: a fractal-like terrain, 10 m cells, Sea at 0 m below all of it.
Setup MakeBench(int n)
{
  std::mt19937_64 rng(1);
  std::vector<float> z(static_cast<std::size_t>(n) * n, 0.0f);
  double amp = 200.0;
  for (int o = 0; o < 7; ++o, amp *= 0.5)
  {
    const double f = (1 << o) * 6.283185307 / n;
    const double ph[4] = {
      6.3 * Uniform(rng), 6.3 * Uniform(rng), 6.3 * Uniform(rng), 6.3 * Uniform(rng)
    };
    for (int j = 0; j < n; ++j)
    {
      for (int i = 0; i < n; ++i)
      {
        z[static_cast<std::size_t>(j) * n + i] += static_cast<float>(amp *
          (std::sin(f * i + ph[0]) * std::cos(f * j + ph[1]) + 0.5 * std::sin(f * (i + j) + ph[2]) +
            0.3 * std::cos(f * (i - j) + ph[3])));
      }
    }
  }
  for (float& v : z)
  {
    v += 600.0f;
  }
  terroir::GridView<float> view;
  view.data = z.data();
  view.nx = n;
  view.ny = n;
  view.dx = 10.0;
  view.dy = 10.0;
  Setup s{ tr::MakeErosionState(view), {}, {}, {}, {} };
  std::fill(s.st.water.begin(), s.st.water.end(), 0.05f);
  s.rain.assign(z.size(), static_cast<float>(0.05 / 3600.0));
  s.p.boundary = tr::ErosionBoundary::Sea;
  s.p.seaLevel = 0.0;
  return s;
}

/// Wall-clock seconds of `steps` steps; cpu: the process's CPU seconds (all threads).
double TimeSteps(Setup& s, int steps, bool thermal, int threads, double& cpu)
{
  const tr::ErosionParallelFor pf = Threads(threads);
  const std::clock_t c0 = std::clock();
  const Clock::time_point t0 = Clock::now();
  for (int k = 0; k < steps; ++k)
  {
    tr::ErosionHydraulicStep(s.st, s.p, s.rain.data(), nullptr, pf);
    if (thermal)
    {
      tr::ErosionThermalStep(s.st, s.tp, pf);
    }
  }
  cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

int BenchMode(int n, int steps, int rounds)
{
  double load[3] = { 0, 0, 0 };
  if (FILE* f = std::fopen("/proc/loadavg", "r"))
  {
    if (std::fscanf(f, "%lf %lf %lf", &load[0], &load[1], &load[2]) != 3)
    {
      load[0] = -1;
    }
    std::fclose(f);
  }
  std::printf("%d^2, %d steps a run, best of %d rounds, load %.2f %.2f %.2f\n",
    n,
    steps,
    rounds,
    load[0],
    load[1],
    load[2]);
  Setup base = MakeBench(n);
  double cpu = 0.0;
  TimeSteps(base, 5, true, 1, cpu); // warm: fluxes and water under way
  double best[2][2] = { { 1e30, 1e30 }, { 1e30, 1e30 } };
  double bestCpu[2][2] = { { 1e30, 1e30 }, { 1e30, 1e30 } };
  for (int r = 0; r < rounds; ++r)
  {
    for (int thermal = 0; thermal < 2; ++thermal)
    {
      for (int threads = 1; threads <= 2; ++threads)
      {
        Setup s = base;
        const double t = TimeSteps(s, steps, thermal != 0, threads, cpu);
        best[thermal][threads - 1] = std::min(best[thermal][threads - 1], t);
        bestCpu[thermal][threads - 1] = std::min(bestCpu[thermal][threads - 1], cpu);
      }
    }
  }
  const double cells = static_cast<double>(n) * n;
  for (int thermal = 0; thermal < 2; ++thermal)
  {
    for (int threads = 1; threads <= 2; ++threads)
    {
      const double t = best[thermal][threads - 1];
      std::printf("%-20s %d thread%s: %7.2f steps/s  %.3g cells*steps/s  (CPU %.1f ms/step)\n",
        thermal ? "hydraulic + thermal" : "hydraulic",
        threads,
        threads > 1 ? "s" : " ",
        steps / t,
        cells * steps / t,
        1e3 * bestCpu[thermal][threads - 1] / steps);
    }
  }
  return 0;
}

} // namespace

int main(int argc, char** argv)
{
  const std::string mode = argc > 1 ? argv[1] : "hash";
  if (mode == "hash")
  {
    return HashMode(argc > 2 ? std::max(1, std::atoi(argv[2])) : 40);
  }
  if (mode == "bench")
  {
    return BenchMode(argc > 2 ? std::atoi(argv[2]) : 1024,
      argc > 3 ? std::atoi(argv[3]) : 20,
      argc > 4 ? std::atoi(argv[4]) : 3);
  }
  std::fprintf(stderr, "usage: %s hash [STEPS] | bench [N] [STEPS] [ROUNDS]\n", argv[0]);
  return 2;
}

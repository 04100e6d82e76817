// Timing of RiverLand (IO/Core/RiverLand.h): the medial-axis pruning alone (Jensen 2011's
// Figure 18 measures it: 1.205 s at 350^2, 3.844 s at 700^2) and the whole generator (coast,
// rivers, distance propagation, medial axis, pruning, heights), at the sizes given, on 1 and 2
// threads, best of REPS runs. Two river densities: "default" (RiverLandParameters' defaults,
// an island) and "dense" (the map border as coast, 4 mouths per 100 cells of border, tributary
// chance 0.8, 3 levels: tens of thousands of river cells at 700^2, as Jensen reports).
// Also checks that 1 and 2 threads give the same bits. Built and run by riverland_bench.sh.
// Not a test: nothing here is asserted.
//   RiverLandTiming REPS SIZE [SIZE ...]
#include "RiverLand.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace gen = terroir::generation;
using Clock = std::chrono::steady_clock;

int main(int argc, char** argv)
{
  if (argc < 3)
  {
    std::fprintf(stderr, "usage: RiverLandTiming REPS SIZE [SIZE ...]\n");
    return 2;
  }
  const int reps = std::atoi(argv[1]);
  std::printf("%-8s %-7s %7s %9s %9s %9s %11s %11s %11s %6s\n",
    "size",
    "rivers",
    "threads",
    "riverCells",
    "medial",
    "pruned",
    "prune_s",
    "total_s",
    "cells/s",
    "same");
  for (int a = 2; a < argc; ++a)
  {
    const int n = std::atoi(argv[a]);
    for (const char* density : { "default", "dense" })
    {
      std::vector<float> first;
      for (int threads : { 1, 2 })
      {
        gen::RiverLandParameters p;
        p.width = p.height = n;
        p.threads = threads;
        if (std::string(density) == "dense")
        {
          p.island = false;
          p.rivers = 4 * (4 * n) / 100;
          p.mouthSpacing = 8;
          p.tributaryChance = 0.8;
          p.tributaryLevels = 3;
        }
        double bestTotal = 1e300, bestPrune = 1e300;
        gen::RiverLand out;
        for (int r = 0; r < reps; ++r)
        {
          out = gen::RiverLand();
          std::string error;
          const auto t0 = Clock::now();
          if (!gen::GenerateRiverLand(p, out, error))
          {
            std::fprintf(stderr, "%s\n", error.c_str());
            return 1;
          }
          const double total = std::chrono::duration<double>(Clock::now() - t0).count();
          bestTotal = std::min(bestTotal, total);
          bestPrune = std::min(bestPrune, out.pruneSeconds);
        }
        long long riverCells = 0;
        for (std::uint8_t c : out.cls)
        {
          riverCells += c == gen::RiverLandRiver ? 1 : 0;
        }
        bool same = true;
        if (threads == 1)
        {
          first = out.heightMeters;
        }
        else
        {
          same = std::memcmp(first.data(), out.heightMeters.data(), first.size() * 4) == 0;
        }
        std::printf("%-8s %-7s %7d %9lld %9d %9d %11.4f %11.3f %11.3g %6s\n",
          (std::to_string(n) + "^2").c_str(),
          density,
          threads,
          riverCells,
          out.medialBefore,
          out.medialBefore - out.medialAfter,
          bestPrune,
          bestTotal,
          static_cast<double>(n) * n / bestTotal,
          same ? "yes" : "NO");
        std::fflush(stdout);
      }
    }
  }
  return 0;
}

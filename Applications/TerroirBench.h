/**
 * @file TerroirBench.h
 * @brief `terroir bench`: times each stage per backend on a synthetic DEM, per million cells,
 * with the GPU breakdown (Documentation/CLI.md). Needs no GDAL: the GPU check program
 * (terroir-gpu-check, Scripts/gpu-check.sh) runs it too.
 */
#ifndef TerroirBench_h
#define TerroirBench_h

#include <string>
#include <vector>

namespace terroir
{
namespace app
{
struct CommandLine;

/**
 * Runs the benchmark on a SIZE x SIZE synthetic terrain (vtkTerroirFractalTerrainSource's, seed
 * 1) and prints one line per stage and backend; `backends`: auto, cpu or gpu, in order; `bandwidth`
 * adds the memory bandwidth and the kernels' share of it; `gpuBreakdown` runs each GPU stage once
 * more with profiling and prints where its time goes; `jsonPath` (may be empty) receives everything
 * as JSON. Returns the exit code; throws Failure.
 */
int CommandBench(int size,
  int repeat,
  const std::vector<std::string>& backends,
  const std::vector<std::string>& stages,
  bool bandwidth,
  bool gpuBreakdown,
  const std::string& jsonPath);

/// The same from the parsed `bench` options (--size, --repeat, --backends, --stages,
/// --bandwidth, --gpu-breakdown, --json; all stages when --stages is not given).
int CommandBench(const CommandLine& line);

} // namespace app
} // namespace terroir

#endif

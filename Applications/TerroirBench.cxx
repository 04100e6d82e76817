// `terroir bench` (TerroirBench.h): runs the stages of BenchStages() (TerroirBenchStages.cxx) per
// backend, then the --bandwidth probes (TerroirBenchProbes.cxx).
#include "TerroirBench.h"
#include "TerroirBenchPrivate.h"

#include "TerroirApp.h"
#include "TerroirCommandLine.h"

#include "vtkAlgorithm.h"
#include "vtkImageData.h"
#include "vtkSMPTools.h"

#include "vtkTerroirComputeContext.h"
#include "vtkTerroirGPU.h"
#include "vtkTerroirSolarIllumination.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <iomanip>
#include <iostream>
#include <vector>

namespace terroir
{
namespace app
{
using json = nlohmann::json;

//------------------------------------------------------------------------------
double BenchRun::BestOf(const std::function<double()>& once)
{
  once();
  double best = 1e300;
  for (int r = 0; r < this->Repeat; ++r)
  {
    best = std::min(best, once());
  }
  if (this->GPUBreakdown && this->Backend == vtkTerroirComputeContext::GPU)
  {
    auto& ctx = terroir::gpu::Context::Global();
    ctx.SetProfiling(true);
    ctx.ResetStats();
    const double total = once();
    const terroir::gpu::Stats st = ctx.GetStats();
    ctx.SetProfiling(false);
    this->Breakdown = GPUBreakdownJson(st, total);
  }
  return best;
}

//------------------------------------------------------------------------------
void BenchRun::Report(const std::string& stage, double best, json extra)
{
  std::cout << std::left << std::setw(18) << stage << std::setw(8) << this->BackendName
            << std::right << std::setw(12) << best * 1e3 << std::setw(14)
            << best * 1e3 / this->MCells << std::setw(14) << this->MCells / best << "\n";
  json row{ { "stage", stage },
    { "backend", this->BackendName },
    { "seconds", best },
    { "mcells", this->MCells },
    { "ms_per_mcell", best * 1e3 / this->MCells } };
  row.update(extra);
  if (!this->Breakdown.is_null())
  {
    const double kernelBytes = BenchKernelBytesPerCell(stage) * this->MCells * 1e6;
    PrintGPUBreakdown(this->Breakdown, kernelBytes, this->GPUCopyBandwidth);
    row["gpu_breakdown"] = this->Breakdown;
    this->Breakdown = json();
  }
  this->Results.push_back(row);
}

//------------------------------------------------------------------------------
double BenchRun::TimedUpdate(vtkAlgorithm* f, const std::string& stage)
{
  f->Modified();
  const double t0 = Now();
  UpdateOrThrow(f, stage);
  return Now() - t0;
}

//------------------------------------------------------------------------------
vtkSmartPointer<vtkTerroirSolarIllumination> BenchRun::Illumination(int mode) const
{
  auto f = vtkSmartPointer<vtkTerroirSolarIllumination>::New();
  f->SetBackend(this->Backend);
  f->SetInputData(this->Terrain);
  f->SetLatitude(39.43);
  f->SetLongitude(-120.24);
  f->SetOrientation(0.0);
  f->SetMode(mode);
  f->SetYear(2025);
  f->SetMonth(6);
  f->SetDay(21);
  f->SetTime(15.0);
  f->SetUTCOffset(-8.0);
  return f;
}

namespace
{
/// The backends to time, in order; the GPU is skipped with a message when it is unavailable.
std::vector<int> BenchBackends(const std::vector<std::string>& backends)
{
  std::vector<int> list;
  for (const std::string& item : backends)
  {
    const int b = ParseBackend(item);
    if (b == vtkTerroirComputeContext::GPU && !vtkTerroirComputeContext::IsAvailable())
    {
      std::cerr << "terroir bench: GPU skipped: "
                << vtkTerroirComputeContext::GetUnavailableReason() << "\n";
      continue;
    }
    list.push_back(b);
  }
  return list;
}

/// The table's title lines and its first row (the synthetic terrain's generation).
void PrintBenchHeader(const BenchRun& run, double genSeconds)
{
  std::cout << "terroir bench: " << run.Size << " x " << run.Size << " synthetic DEM ("
            << std::fixed << std::setprecision(2) << run.MCells << " Mcells), best of "
            << run.Repeat << ", " << vtkSMPTools::GetEstimatedNumberOfThreads() << " threads ("
            << vtkSMPTools::GetBackend() << ")\n";
  if (vtkTerroirComputeContext::IsAvailable())
  {
    std::cout << "GPU: " << vtkTerroirComputeContext::GetRenderer() << "\n";
  }
  std::cout << std::left << std::setw(18) << "stage" << std::setw(8) << "backend" << std::right
            << std::setw(12) << "ms" << std::setw(14) << "ms/Mcell" << std::setw(14) << "Mcells/s"
            << "\n";
  std::cout << std::left << std::setw(18) << "fractal" << std::setw(8) << "CPU" << std::right
            << std::setw(12) << genSeconds * 1e3 << std::setw(14) << genSeconds * 1e3 / run.MCells
            << std::setw(14) << run.MCells / genSeconds << "\n";
}

/// Runs each named stage on each backend. One stage failing on one backend (e.g. a grid too
/// large for the GPU) gets a failure row and does not stop the others.
void RunBenchStages(BenchRun& run,
  const std::vector<std::string>& stages,
  std::vector<int> backends)
{
  for (const std::string& name : stages)
  {
    const auto& table = BenchStages();
    const auto stage =
      std::find_if(table.begin(), table.end(), [&](const BenchStage& s) { return name == s.Name; });
    if (stage == table.end())
    {
      throw Failure("bench: no stage named '" + name + "'");
    }
    for (int b : backends)
    {
      if (stage->CPUOnly && b != vtkTerroirComputeContext::CPU)
      {
        continue;
      }
      run.Backend = b;
      run.BackendName = vtkTerroirComputeContext::GetBackendName(b);
      try
      {
        stage->Run(run);
      }
      catch (const Failure& e)
      {
        std::cout << std::left << std::setw(18) << name << std::setw(8) << run.BackendName
                  << "failed: " << e.what() << "\n";
        run.Results.push_back(
          json{ { "stage", name }, { "backend", run.BackendName }, { "error", e.what() } });
      }
    }
  }
}

/// --bandwidth: the machine's copy bandwidth `bw` and the share of it the kernels reach alone
/// (without allocation or pipeline work) and the slope filter reaches in the pipeline.
void ReportBandwidth(BenchRun& run, const std::vector<std::string>& stages, double bw, json& doc)
{
  const double mcells = run.MCells;
  const int repeat = std::max(3, run.Repeat);
  // The slope filter reads one float and writes Slope, Aspect and 3 Normals components.
  const double bytesPerCell = 4.0 + 4.0 * (1 + 1 + 3);
  std::cout << "memory bandwidth (parallel copy, 256 MiB, "
            << vtkSMPTools::GetEstimatedNumberOfThreads() << " threads): " << bw / 1e9 << " GB/s\n";
  doc["copy_bandwidth_GBps"] = bw / 1e9;
  // The kernel alone: bytes = 4 read + 4 per output.
  for (bool all : { false, true })
  {
    const double sec = TimeSlopeKernel(run.Terrain, all, repeat);
    const double bytes = (all ? bytesPerCell : 8.0) * mcells * 1e6;
    const char* what = all ? "slope kernel (Slope+Aspect+Normals)" : "slope kernel (Slope only)";
    std::cout << what << ": " << std::setprecision(2) << sec * 1e3 / mcells << " ms/Mcell, "
              << bytes / sec / 1e9 << " GB/s = " << std::setprecision(0) << 100.0 * bytes / sec / bw
              << " % of copy bandwidth\n"
              << std::setprecision(2);
    doc[all ? "slope_kernel_all_GBps" : "slope_kernel_slope_only_GBps"] = bytes / sec / 1e9;
  }
  if (run.HumidityInput)
  {
    // Soil humidity: 4 B read (the rate) and 48 B written per output (12 months).
    for (bool all : { false, true })
    {
      const double sec = TimeHumidityKernel(run.HumidityInput, all, repeat);
      const double bytes = (all ? 4.0 + 3 * 48.0 : 4.0 + 48.0) * mcells * 1e6;
      const char* what =
        all ? "humidity kernel (all three outputs)" : "humidity kernel (SoilHumidity)";
      std::cout << what << ": " << std::setprecision(2) << sec * 1e3 << " ms, "
                << sec * 1e3 / mcells << " ms/Mcell, " << bytes / sec / 1e9
                << " GB/s = " << std::setprecision(0) << 100.0 * bytes / sec / bw
                << " % of copy bandwidth\n"
                << std::setprecision(2);
      doc[all ? "humidity_kernel_all_seconds" : "humidity_kernel_seconds"] = sec;
      doc[all ? "humidity_kernel_all_fraction_of_bandwidth"
              : "humidity_kernel_fraction_of_bandwidth"] = bytes / sec / bw;
    }
  }
  if (std::find(stages.begin(), stages.end(), "waterflow") != stages.end())
  {
    // Water flow, per iteration: terrain 4 B and water 8 B read, new water 8 B written,
    // discharge 8 B read and written (WaterFlow.h).
    const double sec = TimeWaterFlowKernel(run.Terrain, repeat);
    const double bytes = 36.0 * mcells * 1e6;
    std::cout << "water-flow kernel (per iteration, run to the automatic stop): "
              << std::setprecision(3) << sec * 1e3 << " ms, " << std::setprecision(0)
              << mcells / sec << " Mcells/s, " << std::setprecision(2) << bytes / sec / 1e9
              << " GB/s = " << std::setprecision(0) << 100.0 * bytes / sec / bw
              << " % of copy bandwidth\n"
              << std::setprecision(2);
    doc["waterflow_kernel_ms_per_iteration"] = sec * 1e3;
    doc["waterflow_kernel_fraction_of_bandwidth"] = bytes / sec / bw;
  }
  if (run.SlopeCPUSeconds > 0)
  {
    const double eff = bytesPerCell * mcells * 1e6 / run.SlopeCPUSeconds;
    std::cout << "slope CPU filter effective bandwidth: " << eff / 1e9
              << " GB/s = " << std::setprecision(0) << 100.0 * eff / bw << " % of copy bandwidth\n";
    doc["slope_cpu_effective_GBps"] = eff / 1e9;
    doc["slope_cpu_fraction_of_bandwidth"] = eff / bw;
  }
}
} // namespace

//------------------------------------------------------------------------------
int CommandBench(int size,
  int repeat,
  const std::vector<std::string>& backends,
  const std::vector<std::string>& stages,
  bool bandwidth,
  bool gpuBreakdown,
  const std::string& jsonPath)
{
  // Measured first, while the process holds no other large arrays.
  const double bw = bandwidth ? MeasureCopyBandwidth(std::max(5, repeat)) : 0.0;
  BenchRun run;
  const double tg = Now();
  run.Terrain = SyntheticTerrain(size);
  const double genSeconds = Now() - tg;
  run.Size = size;
  run.MCells = static_cast<double>(size) * size / 1e6;
  run.Repeat = repeat;
  run.GPUBreakdown = gpuBreakdown;
  const std::vector<int> backendList = BenchBackends(backends);
  PrintBenchHeader(run, genSeconds);
  // --gpu-breakdown: the GPU's copy bandwidth, and per GPU stage one more run with profiling.
  if (gpuBreakdown && vtkTerroirComputeContext::IsAvailable() &&
    std::find(backendList.begin(), backendList.end(), vtkTerroirComputeContext::GPU) !=
      backendList.end())
  {
    run.GPUCopyBandwidth = terroir::gpu::Context::Global().MeasureCopyBandwidth();
    std::cout << "GPU copy kernel (64 MiB): " << std::setprecision(2) << run.GPUCopyBandwidth / 1e9
              << " GB/s read + write; transfers by " << GPUTransferName() << "\n";
  }
  RunBenchStages(run, stages, backendList);
  json doc{ { "size", size },
    { "repeat", repeat },
    { "mcells", run.MCells },
    { "stages", stages },
    { "results", run.Results } };
  if (bandwidth)
  {
    ReportBandwidth(run, stages, bw, doc);
  }
  if (!jsonPath.empty())
  {
    WriteTextFile(jsonPath, doc.dump(2) + "\n", true);
  }
  return 0;
}

int CommandBench(const CommandLine& line)
{
  return CommandBench(line.BenchSize,
    line.BenchRepeat,
    line.BenchBackends,
    line.BenchStages.empty() ? BenchStageNames() : line.BenchStages,
    line.BenchBandwidth,
    line.BenchGPUBreakdown,
    line.BenchJson);
}

} // namespace app
} // namespace terroir

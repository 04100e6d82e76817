// `terroir bench` (TerroirBench.h).
#include "TerroirBench.h"

#include "TerroirApp.h"
#include "TerroirCommandLine.h"

#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkSMPTools.h"

#include "vtkTerroirComputeContext.h"
#include "vtkTerroirFloodFill.h"
#include "vtkTerroirFlowAccumulation.h"
#include "vtkTerroirGPU.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirInfiltration.h"
#include "vtkTerroirKMeans.h"
#include "vtkTerroirSlope.h"
#include "vtkTerroirSoilHumidity.h"
#include "vtkTerroirSolarIllumination.h"
#include "vtkTerroirTemperature.h"
#include "vtkTerroirWaterFlow.h"
#include "vtkTerroirWaterFlowGPU.h" // UseSMPTools

#include "FractalNoise.h"
#include "GridView.h"
#include "MemoryBudget.h"
#include "SlopeHorn1981.h"
#include "SoilWater.h"
#include "WaterFlow.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <vector>

namespace terroir
{
namespace app
{
namespace
{
using json = nlohmann::json;

// ---------------------------------------------------------------------------------------------
/// Sustained memory bandwidth of this machine, bytes/s: a parallel copy of two 256 MiB arrays
/// (STREAM "copy": 8 bytes moved per float), best of `repeat`.
double MeasureCopyBandwidth(int repeat)
{
  const std::size_t n = std::size_t(64) << 20; // 64 Mi floats = 256 MiB
  std::vector<float> a(n, 1.0f), b(n, 0.0f);
  double best = 0;
  for (int r = 0; r < repeat; ++r)
  {
    const double t0 = terroir::app::Now();
    vtkSMPTools::For(0,
      static_cast<vtkIdType>(n),
      1 << 20,
      [&](vtkIdType i0, vtkIdType i1) { std::copy(a.data() + i0, a.data() + i1, b.data() + i0); });
    const double dt = terroir::app::Now() - t0;
    best = std::max(best, 2.0 * sizeof(float) * static_cast<double>(n) / dt);
  }
  if (b[n / 2] != 1.0f)
  {
    throw Failure("bandwidth probe: copy failed");
  }
  return best;
}

/// The synthetic DEM's float Elevation as a core grid view (uniform spacing).
terroir::GridView<float> ElevationView(vtkImageData* terrain)
{
  int dims[3];
  terrain->GetDimensions(dims);
  auto* z = vtkFloatArray::SafeDownCast(terrain->GetPointData()->GetArray("Elevation"));
  if (!z)
  {
    throw Failure("bench: the synthetic DEM has no float Elevation array");
  }
  terroir::GridView<float> view;
  view.data = z->GetPointer(0);
  view.nx = dims[0];
  view.ny = dims[1];
  double spacing[3];
  terrain->GetSpacing(spacing);
  view.dx = spacing[0];
  view.dy = spacing[1];
  return view;
}

/// Best time of the slope kernel alone (core SlopeHorn1981Rows over row blocks with
/// vtkSMPTools, outputs allocated and touched beforehand), seconds.
double TimeSlopeKernel(vtkImageData* terrain, bool allOutputs, int repeat)
{
  const terroir::GridView<float> view = ElevationView(terrain);
  const std::size_t n = view.Size();
  std::vector<float> slope(n, 0.0f), aspect(allOutputs ? n : 0, 0.0f),
    normals(allOutputs ? 3 * n : 0, 0.0f);
  const terroir::terrain::SlopeParams params;
  double best = 1e300;
  for (int r = 0; r < repeat + 1; ++r) // the first run warms caches and page tables
  {
    const double t0 = terroir::app::Now();
    vtkSMPTools::For(0,
      view.ny,
      16,
      [&](vtkIdType j0, vtkIdType j1)
      {
        terroir::terrain::SlopeHorn1981Rows(view,
          params,
          slope.data(),
          allOutputs ? aspect.data() : nullptr,
          allOutputs ? normals.data() : nullptr,
          static_cast<int>(j0),
          static_cast<int>(j1));
      });
    const double dt = terroir::app::Now() - t0;
    if (r > 0)
    {
      best = std::min(best, dt);
    }
  }
  return best;
}

/// Seconds per iteration of the water-flow CPU kernel alone (core WaterFlowSimulation, rows in
/// parallel as the filter runs them): Long (2016)'s benchmark, 100 mm on every cell run to the
/// automatic stop, timed without setting up the state; the best of `repeat` runs.
double TimeWaterFlowKernel(vtkImageData* terrain, int repeat)
{
  const terroir::GridView<float> view = ElevationView(terrain);
  const std::vector<double> water(view.Size(), 0.1);
  double best = 1e300;
  for (int r = 0; r < repeat; ++r)
  {
    terroir::hydrology::WaterFlowSimulation sim(view, water.data());
    terroir::hydrology::UseSMPTools(sim);
    const double t0 = terroir::app::Now();
    sim.Run(terroir::hydrology::WaterFlowStopRule{});
    const double dt = terroir::app::Now() - t0;
    if (sim.Iterations() > 0)
    {
      best = std::min(best, dt / static_cast<double>(sim.Iterations()));
    }
  }
  return best;
}

/// Best time of the soil-humidity kernel alone (core SoilHumidityLong2016 over blocks of cells
/// with vtkSMPTools, outputs allocated and touched beforehand, the default climate), seconds.
double TimeHumidityKernel(vtkImageData* withRates, bool allOutputs, int repeat)
{
  auto* rate = vtkFloatArray::SafeDownCast(
    withRates->GetPointData()->GetArray(vtkTerroirInfiltration::InfiltrationRateName()));
  if (!rate)
  {
    throw Failure("bench: no float InfiltrationRate array");
  }
  const std::size_t n = static_cast<std::size_t>(rate->GetNumberOfTuples());
  vtkNew<vtkTerroirSoilHumidity> defaults;
  terroir::terrain::MonthlyRain rain{};
  for (int m = 0; m < 12; ++m)
  {
    rain.quantityMm[m] = static_cast<float>(defaults->GetPrecipitation()[m]);
    rain.intensityMmPerHour[m] = static_cast<float>(defaults->GetPrecipitationIntensity()[m]);
  }
  std::vector<float> h(12 * n, 0.0f), w(allOutputs ? 12 * n : 0, 0.0f),
    st(allOutputs ? 12 * n : 0, 0.0f);
  const float* r = rate->GetPointer(0);
  double best = 1e300;
  for (int k = 0; k < repeat + 1; ++k) // the first run warms caches and page tables
  {
    const double t0 = terroir::app::Now();
    vtkSMPTools::For(0,
      static_cast<vtkIdType>(n),
      4096,
      [&](vtkIdType c0, vtkIdType c1)
      {
        terroir::terrain::SoilHumidityLong2016(r,
          nullptr,
          rain,
          h.data(),
          allOutputs ? w.data() : nullptr,
          allOutputs ? st.data() : nullptr,
          static_cast<std::size_t>(c0),
          static_cast<std::size_t>(c1));
      });
    const double dt = terroir::app::Now() - t0;
    if (k > 0)
    {
      best = std::min(best, dt);
    }
  }
  return best;
}

/// The bench terrain with 37 feature components for the k-means stage: Slope, Temperature
/// (12), and two 12-month fields that vary across the terrain and between months (stand-ins
/// for IlluminationHours and WeightedSoilHumidity, which take long to compute).
vtkSmartPointer<vtkImageData> BenchKMeansFeatures(vtkImageData* terrain)
{
  vtkNew<vtkTerroirSlope> slope;
  slope->SetInputData(terrain);
  vtkNew<vtkTerroirTemperature> temperature;
  temperature->SetInputConnection(slope->GetOutputPort());
  terroir::app::UpdateOrThrow(temperature, "kmeans features");
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->ShallowCopy(temperature->GetOutput());
  int dims[3];
  out->GetDimensions(dims);
  const vtkIdType n = static_cast<vtkIdType>(dims[0]) * dims[1];
  vtkDataArray* z = out->GetPointData()->GetArray("Elevation");
  vtkDataArray* s = out->GetPointData()->GetArray("Slope");
  for (const char* name : { "IlluminationHours", "WeightedSoilHumidity" })
  {
    vtkNew<vtkFloatArray> a;
    a->SetName(name);
    a->SetNumberOfComponents(12);
    a->SetNumberOfTuples(n);
    const bool sun = name[0] == 'I';
    vtkSMPTools::For(0,
      n,
      [&](vtkIdType b, vtkIdType e)
      {
        for (vtkIdType c = b; c < e; ++c)
        {
          const double x = static_cast<double>(c % dims[0]) / dims[0];
          for (int m = 0; m < 12; ++m)
          {
            const double season = std::cos(2.0 * M_PI * (m - 5.5) / 12.0);
            const double v = sun ? 10.0 + 3.0 * season - 0.05 * s->GetComponent(c, 0) + x
                                 : 80.0 - 40.0 * season + 0.02 * z->GetComponent(c, 0) - 20.0 * x;
            a->SetComponent(c, m, v);
          }
        }
      });
    out->GetPointData()->AddArray(a);
  }
  return out;
}

const char* TransferName(terroir::gpu::Transfer t)
{
  switch (t)
  {
    case terroir::gpu::Transfer::Staging:
      return "a staging ring";
    case terroir::gpu::Transfer::Mapped:
      return "mapped buffers";
    default:
      return "glBufferSubData";
  }
}

/// Bytes a stage's GPU kernels read and write per cell (0: compute-bound, no byte model):
/// slope reads the elevation and writes Slope, Aspect and 3 Normals; temperature and soil
/// humidity read one float and write 12 per output.
double BenchKernelBytesPerCell(const std::string& stage)
{
  if (stage == "slope")
  {
    return 4.0 + 4.0 * 5;
  }
  if (stage == "temperature" || stage == "humidity")
  {
    return 4.0 + 48.0;
  }
  if (stage == "humidity-all")
  {
    return 4.0 + 3 * 48.0;
  }
  return 0.0;
}

/// The profiled run's counters as JSON (seconds; "rest" is what no category covers: host work
/// in and around the jobs).
json GPUBreakdownJson(const terroir::gpu::Stats& s, double total)
{
  const double gpu = s.AllocSeconds + s.UploadSeconds + s.DispatchSeconds + s.DownloadSeconds;
  return json{ { "total_seconds", total },
    { "alloc_seconds", s.AllocSeconds },
    { "upload_seconds", s.UploadSeconds },
    { "dispatch_seconds", s.DispatchSeconds },
    { "kernel_timer_seconds", s.KernelSeconds },
    { "download_seconds", s.DownloadSeconds },
    { "rest_seconds", std::max(0.0, total - gpu) },
    { "outside_jobs_seconds", std::max(0.0, total - s.JobSeconds) },
    { "buffers_created", s.BuffersCreated },
    { "buffers_reused", s.BuffersReused },
    { "bytes_uploaded", s.BytesUploaded },
    { "bytes_downloaded", s.BytesDownloaded },
    { "resident_hits", s.ResidentHits },
    { "resident_bytes_reused", s.ResidentBytesReused },
    { "dispatches", s.Dispatches },
    { "waits", s.Waits } };
}

void PrintGPUBreakdown(json& b, double kernelBytes, double copyBandwidth)
{
  auto ms = [&b](const char* key) { return 1e3 * b[key].get<double>(); };
  std::cout << std::setprecision(1) << "  GPU breakdown: " << ms("total_seconds") << " ms = alloc "
            << ms("alloc_seconds") << " + upload " << ms("upload_seconds") << " + kernels "
            << ms("dispatch_seconds") << " (GL timer "
            << (b["kernel_timer_seconds"].get<double>() > 0.1 * b["dispatch_seconds"].get<double>()
                   ? std::to_string(ms("kernel_timer_seconds")).substr(0, 8)
                   : std::string("n/a"))
            << ") + download " << ms("download_seconds") << " + rest " << ms("rest_seconds")
            << " (outside GPU jobs " << ms("outside_jobs_seconds") << "); buffers made "
            << b["buffers_created"].get<unsigned long long>() << ", reused "
            << b["buffers_reused"].get<unsigned long long>() << "; "
            << b["bytes_uploaded"].get<unsigned long long>() / 1e6 << " MB up, "
            << b["bytes_downloaded"].get<unsigned long long>() / 1e6 << " MB down";
  if (b["resident_hits"].get<unsigned long long>() > 0)
  {
    std::cout << ", " << b["resident_bytes_reused"].get<unsigned long long>() / 1e6
              << " MB resident (not uploaded)";
  }
  // The GL timer when the driver's sees compute work (llvmpipe's reads nanoseconds), else the
  // dispatches' wall time to completion.
  const double timer = b["kernel_timer_seconds"].get<double>();
  const double wall = b["dispatch_seconds"].get<double>();
  const bool timed = timer > 0.1 * wall;
  const double kernel = timed ? timer : wall;
  b["kernel_seconds"] = kernel;
  if (kernelBytes > 0 && kernel > 0)
  {
    const double rate = kernelBytes / kernel;
    b["kernel_GBps"] = rate / 1e9;
    std::cout << "; kernels " << std::setprecision(2) << rate / 1e9 << " GB/s";
    if (copyBandwidth > 0)
    {
      b["kernel_fraction_of_copy_bandwidth"] = rate / copyBandwidth;
      std::cout << " = " << std::setprecision(0) << 100.0 * rate / copyBandwidth
                << " % of the copy kernel's";
    }
  }
  std::cout << std::setprecision(2) << "\n";
}

/// vtkTerroirFractalTerrainSource's terrain with seed 1 and its defaults (10 m cells), made
/// from the same core (terroir::io::FractalNoisePerlin2002Rows, the same bits) so that the
/// benchmark needs no IO module (GDAL): the GPU check program links this file.
vtkSmartPointer<vtkImageData> SyntheticTerrain(int size)
{
  const std::string memory = terroir::CheckMemory(4.0 * size * size, "the synthetic terrain");
  if (!memory.empty())
  {
    throw Failure("bench: " + memory);
  }
  terroir::io::FractalNoiseParameters p;
  p.seed = 1;
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetExtent(0, size - 1, 0, size - 1, 0, 0);
  image->SetSpacing(10.0, 10.0, 1.0);
  vtkNew<vtkFloatArray> elevation;
  elevation->SetName(vtkTerroirGeoreference::ElevationName());
  elevation->SetNumberOfTuples(static_cast<vtkIdType>(size) * size);
  elevation->GetInformation()->Set(vtkDataArray::UNITS_LABEL(), "m");
  float* out = elevation->GetPointer(0);
  vtkSMPTools::For(0,
    size,
    16,
    [&](vtkIdType j0, vtkIdType j1)
    {
      terroir::io::FractalNoisePerlin2002Rows(
        p, size, static_cast<int>(j0), static_cast<int>(j1), out);
    });
  image->GetPointData()->SetScalars(elevation);
  return image;
}

} // namespace

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
  const double tg = terroir::app::Now();
  vtkSmartPointer<vtkImageData> terrain = SyntheticTerrain(size);
  const double genSeconds = terroir::app::Now() - tg;
  const double mcells = static_cast<double>(size) * size / 1e6;

  std::vector<int> backendList;
  for (const std::string& item : backends)
  {
    const int b = ParseBackend(item);
    if (b == vtkTerroirComputeContext::GPU && !vtkTerroirComputeContext::IsAvailable())
    {
      std::cerr << "terroir bench: GPU skipped: "
                << vtkTerroirComputeContext::GetUnavailableReason() << "\n";
      continue;
    }
    backendList.push_back(b);
  }

  json results = json::array();
  std::cout << "terroir bench: " << size << " x " << size << " synthetic DEM (" << std::fixed
            << std::setprecision(2) << mcells << " Mcells), best of " << repeat << ", "
            << vtkSMPTools::GetEstimatedNumberOfThreads() << " threads ("
            << vtkSMPTools::GetBackend() << ")\n";
  if (vtkTerroirComputeContext::IsAvailable())
  {
    std::cout << "GPU: " << vtkTerroirComputeContext::GetRenderer() << "\n";
  }
  std::cout << std::left << std::setw(18) << "stage" << std::setw(8) << "backend" << std::right
            << std::setw(12) << "ms" << std::setw(14) << "ms/Mcell" << std::setw(14) << "Mcells/s"
            << "\n";
  std::cout << std::left << std::setw(18) << "fractal" << std::setw(8) << "CPU" << std::right
            << std::setw(12) << genSeconds * 1e3 << std::setw(14) << genSeconds * 1e3 / mcells
            << std::setw(14) << mcells / genSeconds << "\n";

  double slopeCpuSeconds = 0;
  vtkSmartPointer<vtkImageData> humidityInput; // terrain + InfiltrationRate, for --bandwidth
  vtkSmartPointer<vtkImageData> kmeansInput;   // terrain + 37 feature components
  // --gpu-breakdown: the GPU's copy bandwidth, and per GPU stage one more run with profiling.
  int currentBackend = 0;
  json breakdown; // of the last bestOf on the GPU, consumed by report
  double gpuCopyBandwidth = 0.0;
  if (gpuBreakdown && vtkTerroirComputeContext::IsAvailable() &&
    std::find(backendList.begin(), backendList.end(), vtkTerroirComputeContext::GPU) !=
      backendList.end())
  {
    gpuCopyBandwidth = terroir::gpu::Context::Global().MeasureCopyBandwidth();
    std::cout << "GPU copy kernel (64 MiB): " << std::setprecision(2) << gpuCopyBandwidth / 1e9
              << " GB/s read + write; transfers by "
              << TransferName(terroir::gpu::Context::Global().GetTransfer()) << "\n";
  }
  auto report = [&](const std::string& stage, const char* bname, double best, json extra)
  {
    std::cout << std::left << std::setw(18) << stage << std::setw(8) << bname << std::right
              << std::setw(12) << best * 1e3 << std::setw(14) << best * 1e3 / mcells
              << std::setw(14) << mcells / best << "\n";
    json row{ { "stage", stage },
      { "backend", bname },
      { "seconds", best },
      { "mcells", mcells },
      { "ms_per_mcell", best * 1e3 / mcells } };
    row.update(extra);
    if (!breakdown.is_null())
    {
      const double kernelBytes = BenchKernelBytesPerCell(stage) * mcells * 1e6;
      PrintGPUBreakdown(breakdown, kernelBytes, gpuCopyBandwidth);
      row["gpu_breakdown"] = breakdown;
      breakdown = json();
    }
    results.push_back(row);
  };
  // Best of `repeat` timed calls of `once` (which returns its own seconds), after one untimed
  // warm-up call (shader compile, first touch of memory); with --gpu-breakdown, a GPU stage
  // then runs once more with profiling (its times perturbed by the waits: not the best).
  auto bestOf = [&](const std::function<double()>& once)
  {
    once();
    double best = 1e300;
    for (int r = 0; r < repeat; ++r)
    {
      best = std::min(best, once());
    }
    if (gpuBreakdown && currentBackend == vtkTerroirComputeContext::GPU)
    {
      auto& ctx = terroir::gpu::Context::Global();
      ctx.SetProfiling(true);
      ctx.ResetStats();
      const double total = once();
      const terroir::gpu::Stats st = ctx.GetStats();
      ctx.SetProfiling(false);
      breakdown = GPUBreakdownJson(st, total);
    }
    return best;
  };
  // The illumination stages: the synthetic DEM has no georeference, so the sun is placed at
  // Sagehen Creek (39.43 N, 120.24 W) with grid north = true north; the instants are
  // 2025-06-21 15:00 local time (UTC-8), the sun at azimuth 260 deg, elevation 49 deg.
  auto illumination = [&](int b, int mode)
  {
    auto f = vtkSmartPointer<vtkTerroirSolarIllumination>::New();
    f->SetBackend(b);
    f->SetInputData(terrain);
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
  };
  auto timedUpdate = [](vtkAlgorithm* f, const std::string& stage)
  {
    f->Modified();
    const double t0 = terroir::app::Now();
    terroir::app::UpdateOrThrow(f, stage);
    return terroir::app::Now() - t0;
  };
  for (const std::string& stage : stages)
  {
    for (int b : backendList)
    {
      const char* bname = vtkTerroirComputeContext::GetBackendName(b);
      currentBackend = b;
      breakdown = json();
      try
      {
        if (stage == "slope" || stage == "temperature")
        {
          vtkSmartPointer<vtkTerroirImageAlgorithm> filter;
          if (stage == "slope")
          {
            filter = vtkSmartPointer<vtkTerroirSlope>::New();
          }
          else
          {
            filter = vtkSmartPointer<vtkTerroirTemperature>::New();
          }
          filter->SetBackend(b);
          filter->SetInputData(terrain);
          const double best = bestOf([&] { return timedUpdate(filter, stage); });
          report(stage, bname, best, json::object());
          if (stage == "slope" && b == vtkTerroirComputeContext::CPU)
          {
            slopeCpuSeconds = best;
          }
        }
        else if (stage == "horizon")
        {
          // The horizon map alone, as the filter times it, built by a fresh filter each time.
          int sectors = 0;
          const double best = bestOf(
            [&]
            {
              auto f = illumination(b, vtkTerroirSolarIllumination::Instant);
              terroir::app::UpdateOrThrow(f, stage);
              sectors = f->GetHorizonSectors();
              return f->GetLastHorizonMapSeconds();
            });
          report(stage, bname, best, json{ { "sectors", sectors } });
        }
        else if (stage == "instant")
        {
          // One instant with the horizon map already built (the warm-up builds it, later runs
          // find it in the filter's cache), then the same instant by ray marching.
          auto f = illumination(b, vtkTerroirSolarIllumination::Instant);
          double mapSeconds = 0.0;
          const double best = bestOf(
            [&]
            {
              const double t = timedUpdate(f, stage);
              mapSeconds = f->GetLastHorizonMapSeconds();
              return t;
            });
          report(stage,
            bname,
            best,
            json{ { "method", "horizon" }, { "horizon_map_seconds", mapSeconds } });
          auto g = illumination(b, vtkTerroirSolarIllumination::Instant);
          g->SetShadowMethodToRayMarching();
          const double march = bestOf([&] { return timedUpdate(g, stage); });
          report("instant-raymarch", bname, march, json{ { "method", "raymarch" } });
        }
        else if (stage == "infiltration")
        {
          // The default recipe: fill, then the slope rule on a slope computed inside (CPU only).
          if (b != vtkTerroirComputeContext::CPU)
          {
            continue;
          }
          vtkNew<vtkTerroirInfiltration> f;
          f->SetInputData(terrain);
          report(stage, bname, bestOf([&] { return timedUpdate(f, stage); }), json::object());
        }
        else if (stage == "humidity")
        {
          // Soil humidity alone (Long (2016)'s first kernel) and with the weighted average and
          // standing water (its second), from rates of the default infiltration recipe.
          vtkNew<vtkTerroirInfiltration> rates;
          rates->SetInputData(terrain);
          terroir::app::UpdateOrThrow(rates, "infiltration");
          vtkNew<vtkTerroirSoilHumidity> f;
          f->SetBackend(b);
          f->SetInputConnection(rates->GetOutputPort());
          f->ComputeWeightedSoilHumidityOff();
          f->ComputeStandingWaterOff();
          report("humidity",
            bname,
            bestOf([&] { return timedUpdate(f, stage); }),
            json{ { "outputs", "SoilHumidity" } });
          f->ComputeWeightedSoilHumidityOn();
          f->ComputeStandingWaterOn();
          report("humidity-all",
            bname,
            bestOf([&] { return timedUpdate(f, stage); }),
            json{ { "outputs", "SoilHumidity, WeightedSoilHumidity, StandingWater" } });
          if (b == vtkTerroirComputeContext::CPU)
          {
            humidityInput = vtkSmartPointer<vtkImageData>::New();
            humidityInput->ShallowCopy(rates->GetOutput());
          }
        }
        else if (stage == "floodfill" || stage == "depressions")
        {
          // Seeds: one seed in the lowest cell, level at the median height (about half the
          // terrain connected to it floods); depressions: priority-flood and lakes.
          if (b != vtkTerroirComputeContext::CPU)
          {
            continue;
          }
          vtkNew<vtkTerroirFloodFill> f;
          f->SetInputData(terrain);
          json extra = json::object();
          if (stage == "floodfill")
          {
            vtkDataArray* z = terrain->GetPointData()->GetArray("Elevation");
            std::vector<float> sorted(static_cast<std::size_t>(z->GetNumberOfTuples()));
            vtkIdType lowest = 0;
            for (vtkIdType k = 0; k < z->GetNumberOfTuples(); ++k)
            {
              sorted[static_cast<std::size_t>(k)] = static_cast<float>(z->GetComponent(k, 0));
              if (z->GetComponent(k, 0) < z->GetComponent(lowest, 0))
              {
                lowest = k;
              }
            }
            std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
            const double median = sorted[sorted.size() / 2];
            f->AddSeedCell(
              static_cast<int>(lowest % size), static_cast<int>(lowest / size), median);
            extra["level_m"] = median;
          }
          else
          {
            f->SetModeToFillDepressions();
          }
          const double best = bestOf([&] { return timedUpdate(f, stage); });
          vtkDataArray* cells =
            f->GetOutput()->GetFieldData()->GetArray(vtkTerroirFloodFill::WaterBodyCellsName());
          double wet = 0.0;
          for (vtkIdType k = 0; cells && k < cells->GetNumberOfTuples(); ++k)
          {
            wet += cells->GetComponent(k, 0);
          }
          extra["water_bodies"] = cells ? cells->GetNumberOfTuples() : 0;
          extra["wet_cells"] = wet;
          report(stage, bname, best, extra);
        }
        else if (stage == "flowacc")
        {
          // D8 flow accumulation (Priority-Flood, flats, D8 directions, accumulation): CPU.
          if (b != vtkTerroirComputeContext::CPU)
          {
            continue;
          }
          vtkNew<vtkTerroirFlowAccumulation> f;
          f->SetInputData(terrain);
          const double best = bestOf([&] { return timedUpdate(f, stage); });
          vtkDataArray* dir = f->GetOutput()->GetPointData()->GetArray(
            vtkTerroirFlowAccumulation::FlowDirectionName());
          vtkIdType outlets = 0;
          for (vtkIdType k = 0; dir && k < dir->GetNumberOfTuples(); ++k)
          {
            outlets += dir->GetComponent(k, 0) == -1.0 ? 1 : 0;
          }
          report(stage, bname, best, json{ { "outlet_cells", outlets } });
        }
        else if (stage == "waterflow")
        {
          // Long (2016)'s benchmark: 100 mm on every cell, run to the automatic stop; a fresh
          // filter each time (the filter caches its state).
          long long iterations = 0;
          const double best = bestOf(
            [&]
            {
              vtkNew<vtkTerroirWaterFlow> f;
              f->SetBackend(b);
              f->SetInputData(terrain);
              const double t = timedUpdate(f, stage);
              vtkDataArray* it =
                f->GetOutput()->GetFieldData()->GetArray(vtkTerroirWaterFlow::IterationsName());
              iterations = it ? static_cast<long long>(it->GetComponent(0, 0)) : 0;
              return t;
            });
          const double cells = static_cast<double>(size) * size;
          report(stage,
            bname,
            best,
            json{ { "iterations", iterations },
              { "ms_per_iteration", iterations > 0 ? 1e3 * best / iterations : 0.0 },
              { "mcells_iterations_per_s",
                iterations > 0 ? cells * iterations / best / 1e6 : 0.0 } });
        }
        else if (stage == "kmeans")
        {
          // Lloyd iterations on 37 features (Slope, Temperature x 12 with the storage trick
          // off, and two synthetic 12-month fields), K = 5 and 10, Long (2016)'s diagonal seeds.
          // Time per iteration = (time of 11 iterations - time of 1) / 10: the set-up (packing,
          // seeding, the table) cancels out. The stage's seconds: 11 iterations at K = 5.
          if (!kmeansInput)
          {
            kmeansInput = BenchKMeansFeatures(terrain);
          }
          json perK;
          double best5 = 0.0;
          for (int k : { 5, 10 })
          {
            auto once = [&](int iterations)
            {
              return bestOf(
                [&]
                {
                  vtkNew<vtkTerroirKMeans> f;
                  f->SetBackend(b);
                  f->SetNumberOfClusters(k);
                  f->SetCollapseConstantOffsets(false);
                  f->SetTolerance(0.0);
                  f->SetMaximumIterations(iterations);
                  f->SetInputData(kmeansInput);
                  return timedUpdate(f, stage);
                });
            };
            const double t1 = once(1);
            const double t11 = once(11);
            const double perIteration = std::max(0.0, (t11 - t1) / 10.0);
            perK[std::to_string(k)] = json{ { "ms_per_iteration", 1e3 * perIteration },
              { "seconds_1_iteration", t1 },
              { "seconds_11_iterations", t11 } };
            if (k == 5)
            {
              best5 = t11;
            }
            std::cout << "  kmeans K=" << k << " " << bname << ": " << std::setprecision(2)
                      << 1e3 * perIteration << " ms per iteration (37 features)\n";
          }
          report(stage, bname, best5, json{ { "features", 37 }, { "per_k", perK } });
        }
        else if (stage == "monthly")
        {
          // Monthly mode with its defaults (the 15th of each month, 10-minute steps), a fresh
          // filter each time: the horizon map is included.
          double mapSeconds = 0.0, bestSeconds = 1e300;
          int steps = 0;
          const double best = bestOf(
            [&]
            {
              auto f = illumination(b, vtkTerroirSolarIllumination::Monthly);
              const double t = timedUpdate(f, stage);
              if (t < bestSeconds)
              {
                bestSeconds = t;
                mapSeconds = f->GetLastHorizonMapSeconds();
              }
              vtkDataArray* sun = f->GetOutput()->GetFieldData()->GetArray(
                vtkTerroirSolarIllumination::SunPositionsName());
              steps = sun ? static_cast<int>(sun->GetNumberOfTuples()) : 0;
              return t;
            });
          report(stage,
            bname,
            best,
            json{ { "horizon_map_seconds", mapSeconds }, { "sun_steps", steps } });
        }
      }
      catch (const Failure& e)
      {
        // One stage failing on one backend (e.g. a grid too large for the GPU) does not
        // stop the others.
        std::cout << std::left << std::setw(18) << stage << std::setw(8) << bname
                  << "failed: " << e.what() << "\n";
        results.push_back(json{ { "stage", stage }, { "backend", bname }, { "error", e.what() } });
      }
    }
  }
  json doc{ { "size", size },
    { "repeat", repeat },
    { "mcells", mcells },
    { "stages", stages },
    { "results", results } };
  if (bandwidth)
  {
    // The slope filter reads one float and writes Slope, Aspect and 3 Normals components.
    const double bytesPerCell = 4.0 + 4.0 * (1 + 1 + 3);
    std::cout << "memory bandwidth (parallel copy, 256 MiB, "
              << vtkSMPTools::GetEstimatedNumberOfThreads() << " threads): " << bw / 1e9
              << " GB/s\n";
    doc["copy_bandwidth_GBps"] = bw / 1e9;
    // The kernel alone, without allocation or pipeline work: bytes = 4 read + 4 per output.
    for (bool all : { false, true })
    {
      const double sec = TimeSlopeKernel(terrain, all, std::max(3, repeat));
      const double bytes = (all ? bytesPerCell : 8.0) * mcells * 1e6;
      const char* what = all ? "slope kernel (Slope+Aspect+Normals)" : "slope kernel (Slope only)";
      std::cout << what << ": " << std::setprecision(2) << sec * 1e3 / mcells << " ms/Mcell, "
                << bytes / sec / 1e9 << " GB/s = " << std::setprecision(0)
                << 100.0 * bytes / sec / bw << " % of copy bandwidth\n"
                << std::setprecision(2);
      doc[all ? "slope_kernel_all_GBps" : "slope_kernel_slope_only_GBps"] = bytes / sec / 1e9;
    }
    if (humidityInput)
    {
      // Soil humidity: 4 B read (the rate) and 48 B written per output (12 months).
      for (bool all : { false, true })
      {
        const double sec = TimeHumidityKernel(humidityInput, all, std::max(3, repeat));
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
      const double sec = TimeWaterFlowKernel(terrain, std::max(3, repeat));
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
    if (slopeCpuSeconds > 0)
    {
      const double eff = bytesPerCell * mcells * 1e6 / slopeCpuSeconds;
      std::cout << "slope CPU filter effective bandwidth: " << eff / 1e9
                << " GB/s = " << std::setprecision(0) << 100.0 * eff / bw
                << " % of copy bandwidth\n";
      doc["slope_cpu_effective_GBps"] = eff / 1e9;
      doc["slope_cpu_fraction_of_bandwidth"] = eff / bw;
    }
  }
  if (!jsonPath.empty())
  {
    terroir::app::WriteTextFile(jsonPath, doc.dump(2) + "\n", true);
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

// Probes and inputs of `terroir bench` (TerroirBenchPrivate.h): the synthetic terrain, the
// k-means features, kernels timed without the pipeline for --bandwidth, the GPU breakdown.
#include "TerroirBenchPrivate.h"

#include "TerroirApp.h"

#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkSMPTools.h"

#include "vtkTerroirGPU.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirInfiltration.h"
#include "vtkTerroirSlope.h"
#include "vtkTerroirSoilHumidity.h"
#include "vtkTerroirTemperature.h"
#include "vtkTerroirWaterFlowGPU.h" // UseSMPTools

#include "FractalNoise.h"
#include "GridView.h"
#include "MemoryBudget.h"
#include "SlopeHorn1981.h"
#include "SoilWater.h"
#include "WaterFlow.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <vector>

namespace terroir
{
namespace app
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

namespace
{
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

} // namespace

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

const char* GPUTransferName()
{
  switch (terroir::gpu::Context::Global().GetTransfer())
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

} // namespace app
} // namespace terroir

// The GPU path of the k-means (RunKMeansGPU, Shaders/KMeansAssign.comp and
// KMeansPartialSums.comp) against the CPU core (KMeansLloyd with KMeansCPUEngine) from the same
// initial centres: identical labels and distances, and centres, counts and inertia equal bit
// for bit, with the same iterations, relocations and stop reason. Tolerance: none. Both sides
// do the same float operations per cell in the same order (the kernel marks them `precise`,
// the core is built with -ffp-contract=off) and the same double sums in the same order (per
// KMeansBlockCells block in cell order, then the blocks in order), so any difference is a bug.
// Also: the result does not depend on how the GPU path chunks the cells; the filter
// (vtkTerroirKMeans) gives the same ClusterId with Backend GPU and CPU.
#include "TerroirFilterTestUtilities.h"

#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIntArray.h"
#include "vtkPointData.h"
#include "vtkSMPTools.h"
#include "vtkTerroirComputeContext.h"
#include "vtkTerroirKMeans.h"
#include "vtkTerroirKMeansGPU.h"

#include "KMeans.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <ctime>
#include <functional>
#include <iostream>
#include <random>
#include <string>
#include <vector>

namespace
{
namespace cl = terroir::clustering;

/// A feature-major matrix with its storage.
struct Data
{
  std::vector<float> values;
  std::size_t cells = 0;
  int features = 0;
  cl::KMeansFeatures View() const
  {
    cl::KMeansFeatures x;
    x.data = values.data();
    x.cells = cells;
    x.features = features;
    return x;
  }
  float& At(int f, std::size_t c) { return values[static_cast<std::size_t>(f) * cells + c]; }
};

/// Uniform [0, 1) from a 64-bit draw (our own mapping, as the core's).
double Uniform(std::mt19937_64& rng)
{
  return static_cast<double>(rng() >> 11) * (1.0 / 9007199254740992.0);
}

/// Standard normal (Box-Muller; the same bits on both sides, which see the same matrix).
double Normal(std::mt19937_64& rng)
{
  const double u = 1.0 - Uniform(rng);
  const double v = Uniform(rng);
  return std::sqrt(-2.0 * std::log(u)) * std::cos(6.283185307179586 * v);
}

/// (a) `blobs` well separated Gaussian blobs in `features` dimensions, cells in random order
/// (so labels change from cell to cell).
Data Blobs(std::size_t cells, int features, int blobs, std::uint64_t seed)
{
  Data d;
  d.cells = cells;
  d.features = features;
  d.values.resize(cells * static_cast<std::size_t>(features));
  std::mt19937_64 rng(seed);
  std::vector<double> centre(static_cast<std::size_t>(blobs) * features);
  for (double& m : centre)
  {
    m = 40.0 * Uniform(rng) - 20.0;
  }
  for (std::size_t c = 0; c < cells; ++c)
  {
    const int b = static_cast<int>(Uniform(rng) * blobs);
    for (int f = 0; f < features; ++f)
    {
      d.At(f, c) =
        static_cast<float>(centre[static_cast<std::size_t>(b) * features + f] + 0.5 * Normal(rng));
    }
  }
  return d;
}

/// (b) A terrain-like matrix: cells of an nx-wide grid in row order (labels come in runs),
/// 37 features as the filter prepares them (slope, 12 temperatures, 12 illumination hours, 12
/// weighted humidities), smooth fields with noise, roughly standardised.
Data TerrainLike(std::size_t cells, int nx, std::uint64_t seed)
{
  Data d;
  d.cells = cells;
  d.features = 37;
  d.values.resize(cells * 37);
  std::mt19937_64 rng(seed);
  for (std::size_t c = 0; c < cells; ++c)
  {
    const double i = static_cast<double>(c % static_cast<std::size_t>(nx));
    const double j = static_cast<double>(c / static_cast<std::size_t>(nx));
    const double z =
      std::sin(i * 0.031) * std::cos(j * 0.027) + 0.3 * std::sin(i * 0.11 + j * 0.07);
    const double slope = std::fabs(std::cos(i * 0.031) * std::sin(j * 0.027)) + 0.1 * Uniform(rng);
    d.At(0, c) = static_cast<float>(2.0 * slope - 0.8);
    for (int m = 0; m < 12; ++m)
    {
      const double season = std::cos(6.283185307179586 * (m - 6) / 12.0);
      d.At(1 + m, c) = static_cast<float>(-z + 0.5 * season + 0.02 * Normal(rng));
      d.At(13 + m, c) = static_cast<float>(
        0.8 * season - 0.6 * slope + 0.3 * std::sin(i * 0.05) + 0.05 * Normal(rng));
      d.At(25 + m, c) = static_cast<float>(0.3 * (z + 0.2 * Normal(rng)) * (1.0 + 0.1 * m));
    }
  }
  return d;
}

/// Terrain-like values scaled by random powers of two from 2^-30 to 2^20, so that the double
/// sums of a block (and of the blocks) are rounded and their order shows in the last bits (sums
/// of floats of similar size are exact in double, whatever the order).
Data WideRange(std::size_t cells, int nx, std::uint64_t seed)
{
  Data d = TerrainLike(cells, nx, seed);
  std::mt19937_64 rng(seed + 1);
  for (float& v : d.values)
  {
    v = std::ldexp(v, static_cast<int>(Uniform(rng) * 51.0) - 30);
  }
  return d;
}

/// What one run gave.
struct Outcome
{
  cl::KMeansResult result;
  std::vector<std::int32_t> labels;
  std::vector<float> distances;
};

Outcome RunCPU(const Data& d, const std::vector<float>& centres, int k, const cl::KMeansOptions& o)
{
  const cl::KMeansFeatures x = d.View();
  cl::KMeansCPUEngine engine(x);
  Outcome r;
  r.result = cl::KMeansLloyd(engine, x, centres, k, o);
  r.labels.assign(engine.Labels(), engine.Labels() + x.cells);
  r.distances.assign(engine.Distances(), engine.Distances() + x.cells);
  return r;
}

Outcome RunGPU(const Data& d,
  const std::vector<float>& centres,
  int k,
  const cl::KMeansOptions& o,
  std::size_t chunkBlocks = 0)
{
  Outcome r;
  r.result = cl::RunKMeansGPU(d.View(), centres, k, o, r.labels, r.distances, {}, chunkBlocks);
  return r;
}

/// Bits of a float / double (EXPECT_EQ on the values would let -0 == +0 through).
std::uint32_t Bits(float v)
{
  std::uint32_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}
std::uint64_t Bits(double v)
{
  std::uint64_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

void ExpectIdentical(const Outcome& cpu, const Outcome& gpu, const std::string& what)
{
  SCOPED_TRACE(what);
  EXPECT_EQ(gpu.result.iterations, cpu.result.iterations);
  EXPECT_EQ(gpu.result.reason, cpu.result.reason)
    << cl::KMeansStopReasonName(gpu.result.reason) << " vs "
    << cl::KMeansStopReasonName(cpu.result.reason);
  EXPECT_EQ(gpu.result.relocated, cpu.result.relocated);
  EXPECT_EQ(gpu.result.counts, cpu.result.counts);
  EXPECT_EQ(gpu.result.inertia, cpu.result.inertia);
  EXPECT_EQ(Bits(gpu.result.inertia), Bits(cpu.result.inertia));
  ASSERT_EQ(gpu.result.centres.size(), cpu.result.centres.size());
  std::size_t centreDiffs = 0;
  for (std::size_t i = 0; i < cpu.result.centres.size(); ++i)
  {
    centreDiffs += Bits(gpu.result.centres[i]) != Bits(cpu.result.centres[i]) ? 1 : 0;
    EXPECT_EQ(gpu.result.centres[i], cpu.result.centres[i]) << "centre value " << i;
    if (centreDiffs > 5)
    {
      break;
    }
  }
  EXPECT_EQ(centreDiffs, 0u);
  ASSERT_EQ(gpu.labels.size(), cpu.labels.size());
  ASSERT_EQ(gpu.distances.size(), cpu.distances.size());
  std::size_t labelDiffs = 0, distanceDiffs = 0, first = cpu.labels.size();
  for (std::size_t c = 0; c < cpu.labels.size(); ++c)
  {
    if (gpu.labels[c] != cpu.labels[c])
    {
      ++labelDiffs;
      first = std::min(first, c);
    }
    distanceDiffs += Bits(gpu.distances[c]) != Bits(cpu.distances[c]) ? 1 : 0;
  }
  EXPECT_EQ(labelDiffs, 0u) << "first different label at cell " << first;
  EXPECT_EQ(distanceDiffs, 0u);
}

std::vector<float> PlusPlus(const Data& d, int k, std::uint64_t seed)
{
  const cl::KMeansFeatures x = d.View();
  return cl::KMeansCentresFromCells(x, cl::KMeansPlusPlusSeeds(x, k, seed));
}

/// Centres at cells spread evenly over the matrix (the diagonal seeds' spirit).
std::vector<float> Spread(const Data& d, int k)
{
  std::vector<std::size_t> cells;
  for (int i = 0; i < k; ++i)
  {
    cells.push_back(
      (2 * static_cast<std::size_t>(i) + 1) * d.cells / (2 * static_cast<std::size_t>(k)));
  }
  return cl::KMeansCentresFromCells(d.View(), cells);
}

cl::KMeansOptions Options(int maximumIterations, double tolerance)
{
  cl::KMeansOptions o;
  o.maximumIterations = maximumIterations;
  o.tolerance = tolerance;
  return o;
}
} // namespace

TEST(KMeansGPU, SeparatedBlobsIdenticalToCPU)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  const Data d = Blobs(10000, 3, 5, 11);
  const std::vector<float> centres = PlusPlus(d, 5, 3);
  const cl::KMeansOptions o = Options(300, 0.0);
  const Outcome cpu = RunCPU(d, centres, 5, o);
  EXPECT_EQ(cpu.result.reason, cl::KMeansStopReason::Converged);
  ExpectIdentical(cpu, RunGPU(d, centres, 5, o), "blobs");
}

TEST(KMeansGPU, TerrainLikeSeveralBlocksIdenticalToCPU)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  // 3 whole blocks and a partial one; 37 features; labels in runs along rows.
  const std::size_t cells = 3 * cl::KMeansBlockCells + 123;
  const Data d = TerrainLike(cells, 97, 5);
  const std::vector<float> centres = Spread(d, 8);
  // To convergence (labels only), by tolerance, and by the iteration limit.
  for (const cl::KMeansOptions& o : { Options(300, 0.0), Options(300, 1e-4), Options(3, 0.0) })
  {
    const Outcome cpu = RunCPU(d, centres, 8, o);
    const std::string what = std::string("stop ") + cl::KMeansStopReasonName(cpu.result.reason) +
      " after " + std::to_string(cpu.result.iterations);
    ExpectIdentical(cpu, RunGPU(d, centres, 8, o), what);
  }
  const Outcome converged = RunCPU(d, centres, 8, Options(300, 0.0));
  EXPECT_EQ(converged.result.reason, cl::KMeansStopReason::Converged);
  EXPECT_GT(converged.result.iterations, 3);
  EXPECT_EQ(
    RunCPU(d, centres, 8, Options(3, 0.0)).result.reason, cl::KMeansStopReason::MaximumIterations);
}

TEST(KMeansGPU, ManyBlocksAreAddedInBlockOrder)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  // 48 whole blocks and a partial one, values over 50 binary orders of magnitude: the sums are
  // rounded, so adding the cells or the blocks in another order changes their last bits
  // (checked by reversing the kernel's block loop: this test then fails).
  const std::size_t cells = 48 * cl::KMeansBlockCells + 2049;
  const Data d = WideRange(cells, 457, 13);
  const std::vector<float> centres = PlusPlus(d, 10, 5);
  const cl::KMeansOptions o = Options(4, 0.0);
  const Outcome cpu = RunCPU(d, centres, 10, o);
  ExpectIdentical(cpu, RunGPU(d, centres, 10, o), "49 blocks");
  ExpectIdentical(cpu, RunGPU(d, centres, 10, o, 7), "49 blocks, 7 a chunk");
}

TEST(KMeansGPU, BlockOrderShowsInTheInertia)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  // One huge value in block 0 and random ones elsewhere: the total inertia rounds differently
  // when the blocks are added in another order (checked below on the CPU's own block values),
  // so this fails when the kernel does not add them in block order.
  const std::size_t blocks = 49;
  Data d;
  d.cells = blocks * cl::KMeansBlockCells - 1000;
  d.features = 2;
  d.values.assign(d.cells * 2, 0.0f);
  std::mt19937_64 rng(8);
  for (std::size_t c = 0; c < d.cells; ++c)
  {
    d.At(1, c) = static_cast<float>(std::ldexp(Uniform(rng), 43));
  }
  d.At(0, 0) = std::ldexp(1.0f, 60);
  const std::vector<float> centres = { 1.0f, 1.0f };
  const cl::KMeansOptions o = Options(10, 0.0);
  const Outcome cpu = RunCPU(d, centres, 1, o);
  ExpectIdentical(cpu, RunGPU(d, centres, 1, o), "huge block 0");
  ExpectIdentical(cpu, RunGPU(d, centres, 1, o, 5), "huge block 0, 5 blocks a chunk");

  // The test's power: the same block inertias added in reverse order give other bits.
  std::vector<double> sums(2);
  std::int64_t count = 0;
  double reversed = 0.0;
  for (std::size_t b = blocks; b-- > 0;)
  {
    double inertia = 0.0;
    cl::KMeansBlockSums(
      d.View(), cpu.labels.data(), cpu.distances.data(), 1, b, sums.data(), &count, &inertia);
    reversed += inertia;
  }
  EXPECT_NE(Bits(reversed), Bits(cpu.result.inertia));
}

TEST(KMeansGPU, ResultDoesNotDependOnTheChunks)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  // One, two and three blocks per chunk (the last chunk partial), as when a large matrix is
  // split to fit GL_MAX_SHADER_STORAGE_BLOCK_SIZE.
  const std::size_t cells = 5 * cl::KMeansBlockCells + 1000;
  const Data d = TerrainLike(cells, 131, 9);
  const std::vector<float> centres = PlusPlus(d, 6, 1);
  const cl::KMeansOptions o = Options(300, 0.0);
  const Outcome cpu = RunCPU(d, centres, 6, o);
  for (std::size_t chunk : { 1, 2, 3 })
  {
    ExpectIdentical(
      cpu, RunGPU(d, centres, 6, o, chunk), std::to_string(chunk) + " blocks a chunk");
  }
}

TEST(KMeansGPU, EmptyClusterIsRelocatedAsOnTheCPU)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  const Data d = TerrainLike(2 * cl::KMeansBlockCells + 77, 89, 21);
  // Centres 1 and 2 are the same: ties go to cluster 1, so cluster 2 is empty after the first
  // assignment and must be relocated to the farthest cell (which needs Labels() and
  // Distances() from the GPU).
  std::vector<float> centres = Spread(d, 5);
  const std::size_t f = static_cast<std::size_t>(d.features);
  std::copy(centres.begin() + f, centres.begin() + 2 * f, centres.begin() + 2 * f);
  const cl::KMeansOptions o = Options(300, 0.0);
  const Outcome cpu = RunCPU(d, centres, 5, o);
  EXPECT_GE(cpu.result.relocated, 1);
  ExpectIdentical(cpu, RunGPU(d, centres, 5, o), "duplicate centres");
  ExpectIdentical(cpu, RunGPU(d, centres, 5, o, 1), "duplicate centres, chunks of 1 block");
}

TEST(KMeansGPU, OneClusterAndSixtyFourClusters)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  const Data d = TerrainLike(3 * cl::KMeansBlockCells + 123, 97, 5);
  for (int k : { 1, 64 })
  {
    const std::vector<float> centres = PlusPlus(d, k, 17);
    const cl::KMeansOptions o = Options(k == 1 ? 300 : 25, 1e-4);
    const Outcome cpu = RunCPU(d, centres, k, o);
    ExpectIdentical(cpu, RunGPU(d, centres, k, o), "K = " + std::to_string(k));
    if (k == 1)
    {
      EXPECT_EQ(cpu.result.counts[0], static_cast<std::int64_t>(d.cells));
    }
  }
  // Random-order blobs with K = 64: labels change at every cell.
  const Data blobs = Blobs(3 * cl::KMeansBlockCells + 5, 4, 64, 3);
  const std::vector<float> centres = PlusPlus(blobs, 64, 2);
  const cl::KMeansOptions o = Options(20, 0.0);
  ExpectIdentical(RunCPU(blobs, centres, 64, o), RunGPU(blobs, centres, 64, o), "blobs, K = 64");
}

TEST(KMeansGPU, InvalidArgumentsThrowBeforeAnyGPUWork)
{
  const Data d = Blobs(100, 2, 2, 1);
  std::vector<std::int32_t> labels;
  std::vector<float> distances;
  const std::vector<float> two(4, 0.0f);
  EXPECT_THROW(cl::RunKMeansGPU(d.View(), {}, 0, {}, labels, distances), std::invalid_argument);
  EXPECT_THROW(cl::RunKMeansGPU(d.View(), std::vector<float>(130, 0.0f), 65, {}, labels, distances),
    std::invalid_argument);
  EXPECT_THROW(cl::RunKMeansGPU(d.View(), two, 3, {}, labels, distances), std::invalid_argument);
  Data small = Blobs(1, 2, 1, 1);
  EXPECT_THROW(
    cl::RunKMeansGPU(small.View(), two, 2, {}, labels, distances), std::invalid_argument);
}

namespace
{
/// A small terrain with Slope (1 component), Temperature (12, months differing by constants:
/// the storage trick applies) and IlluminationHours (12) arrays, and a few no-data cells.
vtkSmartPointer<vtkImageData> ClusterTerrain()
{
  const int nx = 150, ny = 130;
  auto t = terroir_test::MakeTerrain(nx,
    ny,
    30.0,
    30.0,
    [](int i, int j)
    {
      if (i > 60 && i < 66 && j > 40 && j < 50)
      {
        return std::nan("");
      }
      return 1000.0 + 200.0 * std::sin(i * 0.04) * std::cos(j * 0.05) +
        3.0 * ((i * 7 + j * 13) % 11);
    });
  vtkDataArray* z = t->GetPointData()->GetArray("Elevation");
  auto slope = vtkSmartPointer<vtkFloatArray>::New();
  slope->SetName("Slope");
  auto temperature = vtkSmartPointer<vtkFloatArray>::New();
  temperature->SetName("Temperature");
  temperature->SetNumberOfComponents(12);
  auto hours = vtkSmartPointer<vtkFloatArray>::New();
  hours->SetName("IlluminationHours");
  hours->SetNumberOfComponents(12);
  const vtkIdType n = z->GetNumberOfTuples();
  slope->SetNumberOfTuples(n);
  temperature->SetNumberOfTuples(n);
  hours->SetNumberOfTuples(n);
  for (vtkIdType c = 0; c < n; ++c)
  {
    const int i = static_cast<int>(c % nx), j = static_cast<int>(c / nx);
    const double h = z->GetComponent(c, 0);
    slope->SetValue(c,
      static_cast<float>(
        20.0 * std::fabs(std::cos(i * 0.04) * std::sin(j * 0.05)) + 0.1 * ((i * 3 + j * 5) % 7)));
    for (int m = 0; m < 12; ++m)
    {
      temperature->SetComponent(
        c, m, 15.0 - 0.0065 * (h - 1000.0) + 8.0 * std::cos((m - 6) * 0.5236));
      hours->SetComponent(c,
        m,
        6.0 + 4.0 * std::cos((m - 6) * 0.5236) +
          0.05 * slope->GetValue(c) * std::sin(i * 0.02 + m));
    }
  }
  t->GetPointData()->AddArray(slope);
  t->GetPointData()->AddArray(temperature);
  t->GetPointData()->AddArray(hours);
  return t;
}

vtkSmartPointer<vtkImageData> RunFilter(vtkImageData* in, int backend, bool standardize, int k)
{
  auto f = vtkSmartPointer<vtkTerroirKMeans>::New();
  f->SetBackend(backend);
  f->SetNumberOfClusters(k);
  f->SetStandardize(standardize);
  f->SetInputData(in);
  f->Update();
  EXPECT_EQ(f->GetLastBackend(), backend);
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->DeepCopy(f->GetOutput());
  return out;
}
} // namespace

TEST(KMeansGPU, FilterGivesTheSameClusterIdOnGPUAndCPU)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  auto in = ClusterTerrain();
  for (bool standardize : { false, true })
  {
    for (int k : { 3, 7 })
    {
      SCOPED_TRACE("standardize " + std::to_string(standardize) + ", K = " + std::to_string(k));
      auto gpu = RunFilter(in, vtkTerroirComputeContext::GPU, standardize, k);
      auto cpu = RunFilter(in, vtkTerroirComputeContext::CPU, standardize, k);
      auto* a = vtkIntArray::SafeDownCast(gpu->GetPointData()->GetArray("ClusterId"));
      auto* b = vtkIntArray::SafeDownCast(cpu->GetPointData()->GetArray("ClusterId"));
      ASSERT_TRUE(a && b);
      ASSERT_EQ(a->GetNumberOfValues(), b->GetNumberOfValues());
      vtkIdType diffs = 0, excluded = 0;
      for (vtkIdType c = 0; c < a->GetNumberOfValues(); ++c)
      {
        diffs += a->GetValue(c) != b->GetValue(c) ? 1 : 0;
        excluded += b->GetValue(c) < 0 ? 1 : 0;
      }
      EXPECT_EQ(diffs, 0);
      EXPECT_EQ(excluded, 5 * 9); // the no-data cells
      for (const char* name : { "KMeansWithinClusterSumOfSquares", "KMeansIterations" })
      {
        vtkDataArray* g = gpu->GetFieldData()->GetArray(name);
        vtkDataArray* c = cpu->GetFieldData()->GetArray(name);
        ASSERT_TRUE(g && c) << name;
        EXPECT_EQ(g->GetTuple1(0), c->GetTuple1(0)) << name;
      }
    }
  }
}

// Timings for Documentation/Shaders.md (not asserted, not run by default):
//   TerroirGPUTests --gtest_also_run_disabled_tests --gtest_filter='*KMeansGPU*Timings*'
// Per iteration = (time of 1 + n iterations - time of 1 iteration) / n, so the uploads, the
// final assignment and the downloads are left out; `setup` is the 1-iteration run. Wall time
// and process CPU time (all threads, llvmpipe's included: on a shared machine it is steadier).
TEST(KMeansGPU, DISABLED_Timings)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  using Clock = std::chrono::steady_clock;
  const int extra = 4;
  const Data d = TerrainLike(std::size_t(1024) * 1024, 1024, 3);
  const cl::KMeansFeatures x = d.View();
  const cl::KMeansParallelFor smp =
    [](std::size_t b, std::size_t e, const std::function<void(std::size_t, std::size_t)>& body)
  {
    vtkSMPTools::For(static_cast<vtkIdType>(b),
      static_cast<vtkIdType>(e),
      1,
      [&body](vtkIdType rb, vtkIdType re)
      { body(static_cast<std::size_t>(rb), static_cast<std::size_t>(re)); });
  };
  struct Times
  {
    double setup, wall, cpu; ///< s, ms per iteration, CPU ms per iteration
  };
  for (int k : { 5, 10 })
  {
    const std::vector<float> centres = Spread(d, k);
    auto time = [&](const std::function<void(int)>& run)
    {
      auto t0 = Clock::now();
      const std::clock_t c0 = std::clock();
      run(1);
      auto t1 = Clock::now();
      const std::clock_t c1 = std::clock();
      run(1 + extra);
      auto t2 = Clock::now();
      const std::clock_t c2 = std::clock();
      const double one = std::chrono::duration<double>(t1 - t0).count();
      const double more = std::chrono::duration<double>(t2 - t1).count();
      const double cpu =
        (static_cast<double>(c2 - c1) - static_cast<double>(c1 - c0)) / CLOCKS_PER_SEC / extra;
      return Times{ one, 1e3 * (more - one) / extra, 1e3 * cpu };
    };
    auto cpuRun = [&](const cl::KMeansParallelFor& pf)
    {
      return [&, pf](int it)
      {
        cl::KMeansCPUEngine engine(x, pf);
        const cl::KMeansResult r = cl::KMeansLloyd(engine, x, centres, k, Options(it, 0.0));
        EXPECT_EQ(r.iterations, it);
      };
    };
    const Times one = time(cpuRun({}));
    const Times two = time(cpuRun(smp));
    const Times gpu = time(
      [&](int it)
      {
        std::vector<std::int32_t> labels;
        std::vector<float> distances;
        const cl::KMeansResult r =
          cl::RunKMeansGPU(x, centres, k, Options(it, 0.0), labels, distances);
        EXPECT_EQ(r.iterations, it);
      });
    std::cout << "1024^2 cells x 37 features, K = " << k
              << ", ms per iteration (CPU ms): CPU 1 thread " << one.wall << " (" << one.cpu
              << "), CPU " << vtkSMPTools::GetEstimatedNumberOfThreads() << " threads " << two.wall
              << " (" << two.cpu << "), llvmpipe " << gpu.wall << " (" << gpu.cpu
              << "); 1-iteration runs " << one.setup << " s, " << two.setup << " s, " << gpu.setup
              << " s (GPU: with context, compile and uploads)" << std::endl;
  }
}

// Diagnosis on a new GPU (not run by default: --gtest_also_run_disabled_tests): the squared
// distances of one assignment, GPU against CPU, bit for bit, printing the first differing cells
// in full.
TEST(KMeansGPU, DISABLED_FirstDifferences)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  const Data d = Blobs(10000, 3, 5, 11);
  const std::vector<float> centres = PlusPlus(d, 5, 3);
  const Outcome cpu = RunCPU(d, centres, 5, Options(1, 0.0));
  const Outcome gpu = RunGPU(d, centres, 5, Options(1, 0.0));
  int differ = 0;
  for (std::size_t c = 0; c < cpu.distances.size(); ++c)
  {
    if (Bits(cpu.distances[c]) != Bits(gpu.distances[c]) && differ++ < 3)
    {
      const int k = cpu.labels[c];
      float acc = 0.0f;
      for (int f = 0; f < 3; ++f)
      {
        volatile float diff = d.values[static_cast<std::size_t>(f) * d.cells + c] -
          centres[static_cast<std::size_t>(k) * 3 + f];
        volatile float sq = diff * diff;
        acc = acc + sq;
      }
      std::printf("[ first    ] cell %zu label cpu %d gpu %d: d2 cpu %a gpu %a scalar %a; x = "
                  "(%a, %a, %a), m = (%a, %a, %a)\n",
        c,
        k,
        gpu.labels[c],
        cpu.distances[c],
        gpu.distances[c],
        acc,
        d.values[c],
        d.values[d.cells + c],
        d.values[2 * d.cells + c],
        centres[k * 3],
        centres[k * 3 + 1],
        centres[k * 3 + 2]);
    }
  }
  std::printf(
    "[ first    ] %d of %zu distances differ after one assignment\n", differ, cpu.distances.size());
  EXPECT_EQ(differ, 0); // the GPU engine's contract: the CPU engine's bits
}

// The GPU data path of Terroir::Compute: the buffer pool, the resident cache, the transfer
// methods, the stress modes (TERROIR_GPU_STRESS), the correctly rounded division of
// Common.glsl, and the stage budgets (a job that never ends stops with a message naming its
// stage). Runs on Mesa llvmpipe here and on NVIDIA through the EGL device platform.
#include "TerroirFilterTestUtilities.h"
#include "vtkTerroirComputeContext.h"
#include "vtkTerroirGPU.h"
#include "vtkTerroirGeoreference.h"

#include "vtkDataArray.h"
#include "vtkExtractVOI.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkTerroirInfiltration.h"
#include "vtkTerroirKMeans.h"
#include "vtkTerroirSlope.h"
#include "vtkTerroirSoilHumidity.h"
#include "vtkTerroirSolarIllumination.h"
#include "vtkTerroirTemperature.h"
#include "vtkTerroirWaterFlow.h"
#include "vtkUnsignedCharArray.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <iostream>
#include <random>
#include <string>
#include <thread>
#include <vector>

namespace
{
using terroir::gpu::Contents;
using terroir::gpu::Context;
using terroir::gpu::Error;
using terroir::gpu::StorageBuffer;
using terroir::gpu::Transfer;

// Copies src to dst, one uint per invocation (2-D grid of 256-wide groups): the bandwidth
// probe's kernel.
const char* const kCopySource = terroir::gpu::Context::CopyKernelSource();

// ids[i] = i (through the split-aware macros); the first invocation of each group records the
// order in which the groups ran.
const char* kOrderSource = R"(
layout(local_size_x = 64) in;
layout(std430, binding = 0) buffer Counter { uint counter[]; };
layout(std430, binding = 1) writeonly buffer Order { uint order[]; };
layout(std430, binding = 2) writeonly buffer Ids { uint ids[]; };
void main()
{
  uint i = TERROIR_GLOBAL_ID.x;
  ids[i] = i;
  if (gl_LocalInvocationID.x == 0u)
  {
    order[TERROIR_WORKGROUP_ID.x] = atomicAdd(counter[0], 1u);
  }
}
)";

// Division: exact[i] = terroirDiv(a, b); refined[i] = terroirDivRefine from a quotient moved off
// by `shift` (float: ULPs; double: a relative error of shift * 2^-22, a float-precision
// reciprocal).
const char* kDivisionSource = R"(
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Pairs { vec2 pairs[]; };
layout(std430, binding = 1) readonly buffer Shifts { int shifts[]; };
layout(std430, binding = 2) writeonly buffer Exact { float exact[]; };
layout(std430, binding = 3) writeonly buffer Refined { float refined[]; };
layout(std430, binding = 4) readonly buffer PairsD { dvec2 pairsD[]; };
layout(std430, binding = 5) writeonly buffer ExactD { double exactD[]; };
layout(std430, binding = 6) writeonly buffer RefinedD { double refinedD[]; };
uniform uint uN;
void main()
{
  uint i = TERROIR_GLOBAL_ID.x;
  if (i >= uN)
  {
    return;
  }
  vec2 p = pairs[i];
  exact[i] = terroirDiv(p.x, p.y);
  float q = intBitsToFloat(floatBitsToInt(p.x / p.y) + shifts[i]);
  refined[i] = terroirDivRefine(p.x, p.y, q);
  dvec2 d = pairsD[i];
  exactD[i] = terroirDiv(d.x, d.y);
  precise double qd = (d.x / d.y) * (1.0LF + double(shifts[i]) * 2.384185791015625e-7LF);
  refinedD[i] = terroirDivRefine(d.x, d.y, qd);
}
)";

// Spins for uIterations per invocation: a job that runs far past any budget.
const char* kEndlessSource = R"(
layout(local_size_x = 64) in;
layout(std430, binding = 0) buffer Out { float outValues[]; };
uniform uint uIterations;
void main()
{
  uint i = TERROIR_GLOBAL_ID.x;
  float acc = outValues[i];
  for (uint k = 0u; k < uIterations; ++k)
  {
    acc = acc * 1.0000001 + 1.0;
  }
  outValues[i] = acc;
}
)";

std::vector<std::uint8_t> Pattern(std::size_t bytes, std::uint32_t seed)
{
  std::vector<std::uint8_t> v(bytes);
  std::uint32_t x = seed;
  for (auto& b : v)
  {
    x = x * 1664525u + 1013904223u;
    b = static_cast<std::uint8_t>(x >> 24);
  }
  return v;
}

/// Restores the stress modes and the transfer method a test changed.
struct RestoreSettings
{
  std::string Stress = Context::Global().StressModes();
  Transfer Method = Context::Global().GetTransfer();
  ~RestoreSettings()
  {
    Context::Global().SetStressModes(this->Stress);
    Context::Global().SetTransfer(this->Method);
  }
};

/// A crop of the bundled DEM (nx x ny cells from column 400, row 300), georeference kept.
vtkSmartPointer<vtkImageData> Crop(int nx, int ny)
{
  auto dem =
    terroir_test::ReadDEM(terroir_test::DataFile("sagehen_creek_ca/sagehen_dem_utm11n_10m.tif"));
  vtkNew<vtkExtractVOI> voi;
  voi->SetInputData(dem);
  voi->SetVOI(400, 400 + nx - 1, 300, 300 + ny - 1, 0, 0);
  voi->Update();
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->DeepCopy(voi->GetOutput());
  out->SetExtent(0, nx - 1, 0, ny - 1, 0, 0);
  out->GetFieldData()->ShallowCopy(dem->GetFieldData());
  return out;
}

/// Largest |a - b| over two arrays (NaN where either is NaN must match), or infinity.
double MaxDifference(vtkDataArray* a, vtkDataArray* b)
{
  if (!a || !b || a->GetNumberOfValues() != b->GetNumberOfValues())
  {
    return INFINITY;
  }
  double worst = 0.0;
  for (vtkIdType k = 0; k < a->GetNumberOfValues(); ++k)
  {
    const double x = a->GetVariantValue(k).ToDouble();
    const double y = b->GetVariantValue(k).ToDouble();
    if (std::isnan(x) || std::isnan(y))
    {
      if (std::isnan(x) != std::isnan(y))
      {
        return INFINITY;
      }
      continue;
    }
    worst = std::max(worst, std::fabs(x - y));
  }
  return worst;
}
} // namespace

//------------------------------------------------------------------------------
TEST(GPUDataPath, PoolServesRepeatedJobsWithoutNewBuffers)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  auto& ctx = Context::Global();
  const std::vector<std::size_t> sizes = { 1000, 5000, std::size_t(1) << 20, (3u << 20) + 7 };
  const std::vector<std::uint8_t> junk = Pattern(sizes[2], 7);
  auto job = [&]
  {
    std::vector<StorageBuffer> held;
    for (std::size_t s : sizes)
    {
      held.emplace_back(s, Contents::Undefined);
      EXPECT_EQ(held.back().Size(), s);
      EXPECT_GE(held.back().Capacity(), s);
    }
    held[2].Upload(junk.data(), junk.size()); // dirty a buffer that goes back to the pool
  };
  ctx.Run(job);
  ctx.ResetStats();
  ctx.Run(job);
  terroir::gpu::Stats s = ctx.GetStats();
  EXPECT_EQ(s.BuffersCreated, 0u);
  EXPECT_EQ(s.BuffersReused, sizes.size());
  // A zero-filled buffer from the pool holds zeros, whatever its last user left in it.
  std::vector<std::uint8_t> back(sizes[2], 1);
  ctx.Run(
    [&]
    {
      StorageBuffer z(sizes[2], Contents::Zero);
      z.Download(back.data(), back.size());
    });
  EXPECT_EQ(std::count(back.begin(), back.end(), 0), static_cast<long>(back.size()));
  EXPECT_GT(ctx.PooledBytes(), 0u);
  ctx.TrimPool();
  EXPECT_EQ(ctx.PooledBytes(), 0u);
}

TEST(GPUDataPath, SizeClassesWasteAtMostAQuarter)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  Context::Global().Run(
    [&]
    {
      for (std::size_t s : { std::size_t(1),
             std::size_t(4096),
             std::size_t(4097),
             std::size_t(10000),
             std::size_t(65537),
             std::size_t(1) << 20,
             (std::size_t(5) << 20) + 1 })
      {
        StorageBuffer b(s, Contents::Undefined);
        EXPECT_GE(b.Capacity(), s);
        EXPECT_LE(static_cast<double>(b.Capacity()), std::max(4096.0, 1.25 * s)) << s;
      }
    });
}

TEST(GPUDataPath, TransfersRoundTripExactlyWithEveryMethod)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  RestoreSettings restore;
  auto& ctx = Context::Global();
  // Larger than one 32 MiB staging slot, and ranges that start and end mid-slot.
  const std::size_t bytes = (std::size_t(40) << 20) + 12;
  const std::vector<std::uint8_t> data = Pattern(bytes - 4, 11);
  for (Transfer method : { Transfer::SubData, Transfer::Staging, Transfer::Mapped })
  {
    ctx.SetTransfer(method);
    std::vector<std::uint8_t> whole(bytes - 4), part(17u << 20), small(300);
    ctx.Run(
      [&]
      {
        StorageBuffer b(bytes, Contents::Undefined);
        b.Upload(data.data(), data.size(), 4);
        b.Download(whole.data(), whole.size(), 4);
        b.Download(part.data(), part.size(), 1234 + 4);
        b.Download(small.data(), small.size(), (20u << 20) + 4);
      });
    const int m = static_cast<int>(method);
    EXPECT_TRUE(whole == data) << "method " << m;
    EXPECT_TRUE(std::equal(part.begin(), part.end(), data.begin() + 1234)) << "method " << m;
    EXPECT_TRUE(std::equal(small.begin(), small.end(), data.begin() + (20u << 20)))
      << "method " << m;
  }
}

TEST(GPUDataPath, ZeroFilledBufferThenUploadIsWhatKernelsRead)
{
  // A buffer cleared on the GPU (glClearBufferSubData) and then uploaded must hold the upload
  // for the next kernel: the pattern of the old GPU path's inputs (made zero-filled, then
  // uploaded), a suspect for the NVIDIA illumination failures of issue 19.
  TERROIR_REQUIRE_GPU_OR_SKIP();
  auto& ctx = Context::Global();
  for (std::size_t bytes : { std::size_t(1) << 10,
         std::size_t(64) << 10,
         std::size_t(1) << 20,
         (std::size_t(17) << 20) + 8 })
  {
    const std::vector<std::uint8_t> data = Pattern(bytes, static_cast<std::uint32_t>(bytes));
    std::vector<std::uint8_t> back(bytes);
    ctx.Run(
      [&]
      {
        StorageBuffer in(bytes, Contents::Zero);
        in.Upload(data.data(), bytes);
        StorageBuffer out(bytes, Contents::Undefined);
        auto& prog = ctx.GetProgram("TestCopy.comp", kCopySource);
        const std::size_t n = bytes / 4;
        prog.SetUInt("uN", static_cast<unsigned>(n));
        in.Bind(0);
        out.Bind(1);
        const unsigned groups = static_cast<unsigned>((n + 255) / 256);
        const unsigned gx = std::min(groups, 4096u);
        prog.Dispatch(gx, (groups + gx - 1) / gx);
        out.Download(back.data(), bytes);
      });
    EXPECT_TRUE(back == data) << bytes << " bytes";
  }
}

TEST(GPUDataPath, StressFillMakesUndefinedBuffersPatterns)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  RestoreSettings restore;
  auto& ctx = Context::Global();
  for (const std::pair<const char*, int>& mode :
    { std::make_pair("fill-nan", 0xff), std::make_pair("fill-pattern", 0xcd) })
  {
    ctx.SetStressModes(mode.first);
    EXPECT_EQ(ctx.StressModes(), mode.first);
    std::vector<std::uint8_t> u(8192), z(8192, 1), d(8192);
    const std::vector<std::uint8_t> data = Pattern(8192, 3);
    ctx.Run(
      [&]
      {
        StorageBuffer undefined(8192, Contents::Undefined);
        undefined.Download(u.data(), u.size());
        StorageBuffer zero(8192, Contents::Zero);
        zero.Download(z.data(), z.size());
        StorageBuffer given(8192, data.data());
        given.Download(d.data(), d.size());
      });
    EXPECT_EQ(std::count(u.begin(), u.end(), mode.second), 8192) << mode.first;
    EXPECT_EQ(std::count(z.begin(), z.end(), 0), 8192) << mode.first;
    EXPECT_TRUE(d == data) << mode.first;
  }
  // As float, fill-nan is a NaN and fill-pattern a small negative number; as int, -1 and
  // -842150451: no kernel may mistake them for the zeros llvmpipe's new memory holds.
  float f;
  const std::uint32_t nanBits = 0xffffffffu, patternBits = 0xcdcdcdcdu;
  std::memcpy(&f, &nanBits, 4);
  EXPECT_TRUE(std::isnan(f));
  std::memcpy(&f, &patternBits, 4);
  EXPECT_LT(f, 0.0f);
}

TEST(GPUDataPath, SplitKeepsIdsAndShuffleChangesTheOrder)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  RestoreSettings restore;
  auto& ctx = Context::Global();
  const unsigned groups = 64; // 4 pieces of 16 groups in the stress modes
  auto run = [&](std::vector<std::uint32_t>& order, std::vector<std::uint32_t>& ids)
  {
    order.assign(groups, 0);
    ids.assign(groups * 64, 0);
    ctx.Run(
      [&]
      {
        StorageBuffer counter(4, Contents::Zero);
        StorageBuffer o(groups * 4, Contents::Undefined);
        StorageBuffer i(groups * 64 * 4, Contents::Undefined);
        auto& prog = ctx.GetProgram("TestOrder.comp", kOrderSource);
        counter.Bind(0);
        o.Bind(1);
        i.Bind(2);
        prog.Dispatch(groups);
        o.Download(order.data(), groups * 4);
        i.Download(ids.data(), ids.size() * 4);
      });
  };
  auto identity = [](const std::vector<std::uint32_t>& ids)
  {
    for (std::size_t k = 0; k < ids.size(); ++k)
    {
      if (ids[k] != k)
      {
        return false;
      }
    }
    return true;
  };
  // The pieces' order: piece p ran entirely before piece q when its largest order < q's
  // smallest (llvmpipe runs one dispatch at a time).
  auto piecesInOrder = [&](const std::vector<std::uint32_t>& order)
  {
    for (unsigned p = 0; p + 1 < 4; ++p)
    {
      const auto a = std::minmax_element(order.begin() + p * 16, order.begin() + (p + 1) * 16);
      const auto b =
        std::minmax_element(order.begin() + (p + 1) * 16, order.begin() + (p + 2) * 16);
      if (!(*a.second < *b.first))
      {
        return false;
      }
    }
    return true;
  };
  std::vector<std::uint32_t> order, ids;
  ctx.SetStressModes("");
  run(order, ids);
  EXPECT_TRUE(identity(ids));
  ctx.SetStressModes("split");
  run(order, ids);
  EXPECT_TRUE(identity(ids));
  std::vector<std::uint32_t> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (unsigned g = 0; g < groups; ++g)
  {
    EXPECT_EQ(sorted[g], g); // every group ran once
  }
  const bool software = vtkTerroirComputeContext::IsSoftwareRenderer();
  if (software)
  {
    EXPECT_TRUE(piecesInOrder(order));
  }
  ctx.SetStressModes("shuffle");
  bool reordered = false;
  for (int attempt = 0; attempt < 10 && !reordered; ++attempt)
  {
    run(order, ids);
    EXPECT_TRUE(identity(ids));
    reordered = !piecesInOrder(order);
  }
  EXPECT_TRUE(reordered || !software) << "ten shuffled dispatches all ran their pieces in order";
}

TEST(GPUDataPath, DivisionIsCorrectlyRoundedEvenFromAnApproximateQuotient)
{
  // terroirDiv must give the CPU's a / b bit for bit, and terroirDivRefine must recover those
  // bits from a quotient a few ULP off (GLSL allows 2.5 ULP for float division; NVIDIA
  // computes a * rcp(b)) or 2^-22 relative off in double (a float-precision reciprocal).
  TERROIR_REQUIRE_GPU_OR_SKIP();
  const std::size_t n = 200000;
  std::mt19937_64 rng(19);
  auto uniform = [&rng] { return static_cast<double>(rng() >> 11) * (1.0 / 9007199254740992.0); };
  std::vector<float> pairs(2 * n);
  std::vector<double> pairsD(2 * n);
  std::vector<std::int32_t> shifts(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    double a, b;
    switch (i % 4)
    {
      case 0: // wide exponents, both signs
        a =
          std::ldexp(uniform() + 0.5, static_cast<int>(uniform() * 80) - 40) * (rng() & 1 ? -1 : 1);
        b =
          std::ldexp(uniform() + 0.5, static_cast<int>(uniform() * 80) - 40) * (rng() & 1 ? -1 : 1);
        break;
      case 1: // terrain-like: height differences over distances (the horizon tangents)
        a = 400.0 * (uniform() - 0.5);
        b = 10.0 * (1 + static_cast<int>(uniform() * 2000));
        break;
      case 2: // exact quotients
        b = 1 + static_cast<int>(uniform() * 1000);
        a = b * static_cast<int>(uniform() * 1000 - 500);
        break;
      default: // water depths over a sum of closenesses
        a = uniform() * 0.1;
        b = 1.0 + uniform() * 3.0;
    }
    if (a == 0.0)
    {
      a = 1.0;
    }
    pairs[2 * i] = static_cast<float>(a);
    pairs[2 * i + 1] = static_cast<float>(b);
    pairsD[2 * i] = a * (1.0 + 1e-9 * uniform());
    pairsD[2 * i + 1] = b;
    shifts[i] = static_cast<std::int32_t>(i % 7) - 3;
  }
  std::vector<float> exact(n), refined(n);
  std::vector<double> exactD(n), refinedD(n);
  auto& ctx = Context::Global();
  ctx.Run(
    [&]
    {
      StorageBuffer bp(pairs.size() * 4, pairs.data());
      StorageBuffer bs(shifts.size() * 4, shifts.data());
      StorageBuffer be(n * 4, Contents::Undefined), br(n * 4, Contents::Undefined);
      StorageBuffer bpd(pairsD.size() * 8, pairsD.data());
      StorageBuffer bed(n * 8, Contents::Undefined), brd(n * 8, Contents::Undefined);
      auto& prog = ctx.GetProgram("TestDivision.comp", kDivisionSource);
      prog.SetUInt("uN", static_cast<unsigned>(n));
      bp.Bind(0);
      bs.Bind(1);
      be.Bind(2);
      br.Bind(3);
      bpd.Bind(4);
      bed.Bind(5);
      brd.Bind(6);
      prog.Dispatch(static_cast<unsigned>((n + 63) / 64));
      be.Download(exact.data(), n * 4);
      br.Download(refined.data(), n * 4);
      bed.Download(exactD.data(), n * 8);
      brd.Download(refinedD.data(), n * 8);
    });
  std::size_t bad = 0, badRefined = 0, badD = 0, badRefinedD = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    const float cpu = pairs[2 * i] / pairs[2 * i + 1];
    const double cpuD = pairsD[2 * i] / pairsD[2 * i + 1];
    const std::size_t before = bad + badRefined + badD + badRefinedD;
    bad += std::memcmp(&cpu, &exact[i], 4) != 0 ? 1 : 0;
    badRefined += std::memcmp(&cpu, &refined[i], 4) != 0 ? 1 : 0;
    badD += std::memcmp(&cpuD, &exactD[i], 8) != 0 ? 1 : 0;
    badRefinedD += std::memcmp(&cpuD, &refinedD[i], 8) != 0 ? 1 : 0;
    if (before == 0 && bad + badRefined + badD + badRefinedD > 0)
    {
      ADD_FAILURE() << "first difference at " << i << ": " << pairs[2 * i] << " / "
                    << pairs[2 * i + 1] << " (double " << pairsD[2 * i] << " / "
                    << pairsD[2 * i + 1] << ") shift " << shifts[i];
    }
  }
  EXPECT_EQ(bad, 0u);
  EXPECT_EQ(badRefined, 0u);
  EXPECT_EQ(badD, 0u);
  EXPECT_EQ(badRefinedD, 0u);
}

namespace
{
// Runs `source` (uniform uN = n, 64 invocations a group) on a float and a double input at
// bindings 0 and 1, writing the float and double outputs at bindings 2 and 3.
void RunFloatAndDoubleKernel(const char* name,
  const char* source,
  std::size_t n,
  const std::vector<float>& in,
  const std::vector<double>& inD,
  std::vector<float>& out,
  std::vector<double>& outD)
{
  auto& ctx = Context::Global();
  ctx.Run(
    [&]
    {
      StorageBuffer bIn(in.size() * 4, in.data()), bInD(inD.size() * 8, inD.data());
      StorageBuffer bOut(out.size() * 4, Contents::Undefined),
        bOutD(outD.size() * 8, Contents::Undefined);
      auto& prog = ctx.GetProgram(name, source);
      prog.SetUInt("uN", static_cast<unsigned>(n));
      bIn.Bind(0);
      bInD.Bind(1);
      bOut.Bind(2);
      bOutD.Bind(3);
      prog.Dispatch(static_cast<unsigned>((n + 63) / 64));
      bOut.Download(out.data(), out.size() * 4);
      bOutD.Download(outD.data(), outD.size() * 8);
    });
}
} // namespace

TEST(GPUDataPath, PreciseProductsAreNotFused)
{
  // A `precise` a * b + c must be round(round(a * b) + c), as the CPU computes it without
  // contraction (GLSL forbids fusing it into one fma; the exact kernels rely on that). Also
  // without `precise`, measured and printed: a compiler may fuse there.
  TERROIR_REQUIRE_GPU_OR_SKIP();
  static const char* const source = R"(
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer In { vec4 abc[]; };
layout(std430, binding = 1) readonly buffer InD { dvec4 abcD[]; };
layout(std430, binding = 2) writeonly buffer Out { vec2 r[]; };
layout(std430, binding = 3) writeonly buffer OutD { dvec2 rD[]; };
uniform uint uN;
void main()
{
  uint i = TERROIR_GLOBAL_ID.x;
  if (i >= uN)
  {
    return;
  }
  vec4 v = abc[i];
  precise float plain = v.x * v.y + v.z;
  float guarded = v.x * v.y + v.z;
  r[i] = vec2(plain, guarded);
  dvec4 d = abcD[i];
  precise double plainD = d.x * d.y + d.z;
  double guardedD = d.x * d.y + d.z;
  rD[i] = dvec2(plainD, guardedD);
}
)";
  const std::size_t n = 100000;
  std::mt19937_64 rng(23);
  auto uniform = [&rng] { return static_cast<double>(rng() >> 11) * (1.0 / 9007199254740992.0); };
  std::vector<float> abc(4 * n);
  std::vector<double> abcD(4 * n);
  for (std::size_t i = 0; i < n; ++i)
  {
    // Products whose rounding error the addition does not swamp: c close to -a * b.
    const double a = 1.0 + uniform(), b = 1.0 + uniform();
    abc[4 * i] = static_cast<float>(a);
    abc[4 * i + 1] = static_cast<float>(b);
    abc[4 * i + 2] = -static_cast<float>(a * b) * static_cast<float>(1.0 + 1e-6 * uniform());
    abcD[4 * i] = a;
    abcD[4 * i + 1] = b;
    abcD[4 * i + 2] = -(a * b) * (1.0 + 1e-14 * uniform());
  }
  std::vector<float> r(2 * n);
  std::vector<double> rD(2 * n);
  RunFloatAndDoubleKernel("TestProducts.comp", source, n, abc, abcD, r, rD);
  std::size_t plain = 0, guarded = 0, plainD = 0, guardedD = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    volatile float p = abc[4 * i] * abc[4 * i + 1];
    const float cpu = p + abc[4 * i + 2];
    volatile double pd = abcD[4 * i] * abcD[4 * i + 1];
    const double cpuD = pd + abcD[4 * i + 2];
    plain += r[2 * i] != cpu ? 1 : 0;
    guarded += r[2 * i + 1] != cpu ? 1 : 0;
    plainD += rD[2 * i] != cpuD ? 1 : 0;
    guardedD += rD[2 * i + 1] != cpuD ? 1 : 0;
  }
  std::cout << "[ products ] " << vtkTerroirComputeContext::GetRenderer() << ": precise a*b+c "
            << "differs from the CPU in " << plain << " (float) and " << plainD << " (double) of "
            << n << "; without precise in " << guarded << " and " << guardedD << "\n";
  EXPECT_EQ(plain, 0u);
  EXPECT_EQ(plainD, 0u);
}

TEST(GPUDataPath, PreciseSumsKeepTheirOrder)
{
  // A `precise` chain of additions is the CPU's left-to-right sum, bit for bit (GLSL forbids
  // reassociating it; the exact kernels rely on that). Without `precise`, measured and printed.
  TERROIR_REQUIRE_GPU_OR_SKIP();
  static const char* const source = R"(
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer In { float v[]; };
layout(std430, binding = 1) readonly buffer InD { double vD[]; };
layout(std430, binding = 2) writeonly buffer Out { vec2 r[]; };
layout(std430, binding = 3) writeonly buffer OutD { dvec2 rD[]; };
uniform uint uN;
void main()
{
  uint i = TERROIR_GLOBAL_ID.x;
  if (i >= uN)
  {
    return;
  }
  precise float plain = 0.0;
  float guarded = 0.0;
  precise double plainD = 0.0LF;
  double guardedD = 0.0LF;
  for (uint k = 0u; k < 16u; ++k)
  {
    plain = plain + v[16u * i + k];
    guarded = guarded + v[16u * i + k];
    plainD = plainD + vD[16u * i + k];
    guardedD = guardedD + vD[16u * i + k];
  }
  r[i] = vec2(plain, guarded);
  rD[i] = dvec2(plainD, guardedD);
}
)";
  const std::size_t n = 50000;
  std::mt19937_64 rng(29);
  auto uniform = [&rng] { return static_cast<double>(rng() >> 11) * (1.0 / 9007199254740992.0); };
  std::vector<float> v(16 * n);
  std::vector<double> vD(16 * n);
  for (std::size_t k = 0; k < v.size(); ++k)
  {
    // Magnitudes over 20 binary orders: the order of the additions shows in the last bits.
    const double x = std::ldexp(uniform() - 0.3, static_cast<int>(uniform() * 20));
    v[k] = static_cast<float>(x);
    vD[k] = x;
  }
  std::vector<float> r(2 * n);
  std::vector<double> rD(2 * n);
  RunFloatAndDoubleKernel("TestSums.comp", source, n, v, vD, r, rD);
  std::size_t plain = 0, guarded = 0, plainD = 0, guardedD = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    volatile float s = 0.0f;
    volatile double sD = 0.0;
    for (std::size_t k = 0; k < 16; ++k)
    {
      s = s + v[16 * i + k];
      sD = sD + vD[16 * i + k];
    }
    plain += r[2 * i] != s ? 1 : 0;
    guarded += r[2 * i + 1] != s ? 1 : 0;
    plainD += rD[2 * i] != sD ? 1 : 0;
    guardedD += rD[2 * i + 1] != sD ? 1 : 0;
  }
  std::cout << "[ sums     ] " << vtkTerroirComputeContext::GetRenderer() << ": precise sums "
            << "differ from the CPU in " << plain << " (float) and " << plainD << " (double) of "
            << n << "; without precise in " << guarded << " and " << guardedD << "\n";
  EXPECT_EQ(plain, 0u);
  EXPECT_EQ(plainD, 0u);
}

TEST(GPUDataPath, HostArithmeticInsideJobsIsTheCPUs)
{
  // Jobs run host code between GL calls (k-means' centres, the water flow's tables and volume
  // sums): its arithmetic must be the caller's, whatever the driver does to the context
  // thread's floating-point control (NVIDIA's changed it: Documentation/Compute.md).
  TERROIR_REQUIRE_GPU_OR_SKIP();
  auto arithmetic = []
  {
    // Divisions, sums and square roots whose last bits depend on the rounding mode, and a
    // product in the subnormal range (flush-to-zero).
    double sum = 0.0;
    for (int k = 1; k <= 1000; ++k)
    {
      volatile double d = 1.0 / (3.0 * k + 0.1);
      sum += d;
    }
    volatile double tiny = 1e-300;
    volatile double sub = tiny * 1e-10;
    volatile float tinyF = 1e-30f;
    volatile float subF = tinyF * 1e-10f;
    return std::vector<double>{ sum, std::sqrt(sum), sub, static_cast<double>(subF) };
  };
  const std::vector<double> here = arithmetic();
  std::vector<double> there;
  auto& ctx = Context::Global();
  ctx.ResetStats();
  ctx.Run(
    [&]
    {
      StorageBuffer b(1 << 20, Contents::Zero);
      auto& prog = ctx.GetProgram("TestCopyHost.comp", kCopySource);
      prog.SetUInt("uN", 1u << 18);
      b.Bind(0);
      b.Bind(1);
      prog.Dispatch(1024);
      std::vector<char> back(1 << 20);
      b.Download(back.data(), back.size());
      there = arithmetic();
    });
  std::cout << "[ host fp  ] " << vtkTerroirComputeContext::GetRenderer()
            << ": floating-point control put back " << ctx.GetStats().HostFloatingPointResets
            << " times in the job\n";
  ASSERT_EQ(there.size(), here.size());
  for (std::size_t i = 0; i < here.size(); ++i)
  {
    EXPECT_EQ(std::memcmp(&here[i], &there[i], sizeof(double)), 0)
      << "value " << i << ": " << here[i] << " here, " << there[i] << " in the job";
  }
}

//------------------------------------------------------------------------------
TEST(GPUDataPath, ResidentTerrainIsUploadedOnceAndFollowsChanges)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  auto& ctx = Context::Global();
  auto dem = Crop(130, 110);
  ctx.ClearResident();
  vtkNew<vtkTerroirSlope> slope;
  slope->SetBackendToGPU();
  slope->SetInputData(dem);
  vtkNew<vtkTerroirTemperature> temperature;
  temperature->SetBackendToGPU();
  temperature->SetInputConnection(slope->GetOutputPort());
  slope->Update();
  ctx.ResetStats();
  temperature->Update();
  terroir::gpu::Stats s = ctx.GetStats();
  // The elevation and its mask came from the slope filter's job.
  EXPECT_GE(s.ResidentHits, 2u);
  EXPECT_EQ(s.BytesUploaded, 0u);

  // Changed heights (and Modified()) are uploaded again: the GPU slope follows them.
  vtkFloatArray* z = vtkFloatArray::SafeDownCast(dem->GetPointData()->GetArray("Elevation"));
  ASSERT_NE(z, nullptr);
  for (vtkIdType k = 0; k < z->GetNumberOfTuples(); ++k)
  {
    z->SetValue(k, z->GetValue(k) * 1.5f + 0.25f * static_cast<float>(k % 13));
  }
  z->Modified();
  dem->Modified();
  slope->Update();
  vtkNew<vtkTerroirSlope> cpu;
  cpu->SetBackendToCPU();
  cpu->SetInputData(dem);
  cpu->Update();
  EXPECT_LE(MaxDifference(slope->GetOutput()->GetPointData()->GetArray("Slope"),
              cpu->GetOutput()->GetPointData()->GetArray("Slope")),
    1e-3);
}

TEST(GPUDataPath, ReplacedValidityMaskIsNotTakenFromTheCache)
{
  // The validity mask is cached under its own array: a new mask array replacing the old one is
  // uploaded even when it is older than the elevation's last change (so no MTime grew).
  TERROIR_REQUIRE_GPU_OR_SKIP();
  auto& ctx = Context::Global();
  auto dem = Crop(120, 100);
  const vtkIdType n = dem->GetNumberOfPoints();
  auto makeMask = [n](int i0, int i1)
  {
    auto m = vtkSmartPointer<vtkUnsignedCharArray>::New();
    m->SetName(vtkTerroirGeoreference::ValidMaskName());
    m->SetNumberOfTuples(n);
    for (vtkIdType k = 0; k < n; ++k)
    {
      const int i = static_cast<int>(k % 120);
      m->SetValue(k, i >= i0 && i < i1 ? 0 : 1);
    }
    return m;
  };
  auto later = makeMask(70, 90); // replaces `first` below; made before the elevation changes
  auto first = makeMask(10, 30);
  dem->GetPointData()->AddArray(first);
  vtkFloatArray* z = vtkFloatArray::SafeDownCast(dem->GetPointData()->GetArray("Elevation"));
  ASSERT_NE(z, nullptr);
  z->SetValue(0, z->GetValue(0) + 1.0f);
  z->Modified();
  ctx.ClearResident();
  vtkNew<vtkTerroirSlope> gpu;
  gpu->SetBackendToGPU();
  gpu->SetInputData(dem);
  gpu->Update();
  dem->GetPointData()->AddArray(later); // same name: replaces `first`
  dem->Modified();
  gpu->Update();
  vtkNew<vtkTerroirSlope> cpu;
  cpu->SetBackendToCPU();
  cpu->SetInputData(dem);
  cpu->Update();
  vtkDataArray* g = gpu->GetOutput()->GetPointData()->GetArray("Slope");
  ASSERT_NE(g, nullptr);
  EXPECT_TRUE(std::isnan(g->GetTuple1(80)));  // column 80: invalid under the new mask
  EXPECT_FALSE(std::isnan(g->GetTuple1(20))); // column 20: valid again
  EXPECT_LE(MaxDifference(g, cpu->GetOutput()->GetPointData()->GetArray("Slope")), 1e-3);
}

TEST(GPUDataPath, GPUChainMatchesCPUChainWithACPUFilterInBetween)
{
  // Slope (GPU) -> infiltration (CPU, reads the host copies) -> soil humidity (GPU) ->
  // temperature (GPU), against the same chain on the CPU.
  TERROIR_REQUIRE_GPU_OR_SKIP();
  auto dem = Crop(150, 120);
  auto chain = [&](int backend)
  {
    vtkNew<vtkTerroirSlope> slope;
    slope->SetBackend(backend);
    slope->SetInputData(dem);
    vtkNew<vtkTerroirInfiltration> rates;
    rates->SetInputConnection(slope->GetOutputPort());
    vtkNew<vtkTerroirSoilHumidity> humidity;
    humidity->SetBackend(backend);
    humidity->SetInputConnection(rates->GetOutputPort());
    vtkNew<vtkTerroirTemperature> temperature;
    temperature->SetBackend(backend);
    temperature->SetInputConnection(humidity->GetOutputPort());
    temperature->Update();
    EXPECT_EQ(slope->GetLastBackend(), backend);
    EXPECT_EQ(humidity->GetLastBackend(), backend);
    EXPECT_EQ(temperature->GetLastBackend(), backend);
    auto out = vtkSmartPointer<vtkImageData>::New();
    out->ShallowCopy(temperature->GetOutput());
    return out;
  };
  auto gpu = chain(vtkTerroirComputeContext::GPU);
  auto cpu = chain(vtkTerroirComputeContext::CPU);
  // Tolerances of the GPU suite (slope 1e-3 deg; the others do the same float operations).
  const std::pair<const char*, double> arrays[] = { { "Slope", 1e-3 },
    { "Aspect", 1e-2 },
    { "InfiltrationRate", 0.0 },
    { "SoilHumidity", 1e-4 },
    { "WeightedSoilHumidity", 1e-4 },
    { "StandingWater", 1e-4 },
    { "Temperature", 1e-3 } };
  for (const auto& a : arrays)
  {
    vtkDataArray* g = gpu->GetPointData()->GetArray(a.first);
    vtkDataArray* c = cpu->GetPointData()->GetArray(a.first);
    ASSERT_TRUE(g && c) << a.first;
    EXPECT_LE(MaxDifference(g, c), a.second) << a.first;
  }
}

TEST(GPUDataPath, SecondIdenticalUpdateMakesNoBuffer)
{
  // After a warm-up, the same work on a fresh filter takes every GL buffer from the pool.
  TERROIR_REQUIRE_GPU_OR_SKIP();
  auto dem = Crop(96, 80);
  vtkNew<vtkTerroirInfiltration> rates;
  rates->SetInputData(dem);
  rates->Update();
  vtkNew<vtkTerroirSlope> slopes;
  slopes->SetInputConnection(rates->GetOutputPort());
  vtkNew<vtkTerroirTemperature> temperatures;
  temperatures->SetInputConnection(slopes->GetOutputPort());
  temperatures->Update();
  vtkImageData* withRates = temperatures->GetOutput();
  using Make = std::function<vtkSmartPointer<vtkAlgorithm>()>;
  const std::vector<std::pair<const char*, Make>> filters = {
    { "slope",
      []
      {
        auto f = vtkSmartPointer<vtkTerroirSlope>::New();
        f->SetBackendToGPU();
        return f;
      } },
    { "temperature",
      []
      {
        auto f = vtkSmartPointer<vtkTerroirTemperature>::New();
        f->SetBackendToGPU();
        return f;
      } },
    { "soil humidity",
      []
      {
        auto f = vtkSmartPointer<vtkTerroirSoilHumidity>::New();
        f->SetBackendToGPU();
        return f;
      } },
    { "illumination (daily, horizon map)",
      []
      {
        auto f = vtkSmartPointer<vtkTerroirSolarIllumination>::New();
        f->SetBackendToGPU();
        f->SetModeToDaily();
        f->SetTimeStep(60.0);
        f->SetHorizonSectors(16);
        return f;
      } },
    { "illumination (instant, ray march)",
      []
      {
        auto f = vtkSmartPointer<vtkTerroirSolarIllumination>::New();
        f->SetBackendToGPU();
        f->SetShadowMethodToRayMarching();
        return f;
      } },
    { "water flow",
      []
      {
        auto f = vtkSmartPointer<vtkTerroirWaterFlow>::New();
        f->SetBackendToGPU();
        return f;
      } },
    { "k-means",
      []
      {
        auto f = vtkSmartPointer<vtkTerroirKMeans>::New();
        f->SetBackendToGPU();
        f->AddFeature("Elevation", 1.0);
        f->AddFeature("Slope", 1.0);
        f->AddFeature("Temperature", 1.0);
        f->SetMaximumIterations(10);
        return f;
      } },
  };
  auto& ctx = Context::Global();
  for (const auto& entry : filters)
  {
    // The same filter again (Modified), except the water flow, whose filter would answer from
    // its cache: a new one with the same settings.
    const bool fresh = std::string(entry.first) == "water flow";
    vtkSmartPointer<vtkAlgorithm> f = entry.second();
    f->SetInputDataObject(withRates);
    f->Update();
    ctx.ResetStats();
    if (fresh)
    {
      f = entry.second();
      f->SetInputDataObject(withRates);
    }
    f->Modified();
    f->Update();
    const terroir::gpu::Stats s = ctx.GetStats();
    EXPECT_EQ(s.BuffersCreated, 0u) << entry.first;
    EXPECT_GT(s.Dispatches, 0u) << entry.first << " ran no GPU work";
  }
}

TEST(GPUDataPath, WaterFlowStopIsFoundWithinAFewIterations)
{
  // The stop test reads the volumes of one block while the next runs; blocks shrink as the
  // automatic stop nears, so few iterations run past it (they are undone, the result is the
  // CPU's: TestWaterFlowGPU.cxx).
  TERROIR_REQUIRE_GPU_OR_SKIP();
  auto dem = Crop(128, 128);
  auto& ctx = Context::Global();
  vtkNew<vtkTerroirWaterFlow> f;
  f->SetBackendToGPU();
  f->SetInputData(dem);
  ctx.ResetStats();
  f->Update();
  const terroir::gpu::Stats s = ctx.GetStats();
  vtkDataArray* it =
    f->GetOutput()->GetFieldData()->GetArray(vtkTerroirWaterFlow::IterationsName());
  ASSERT_NE(it, nullptr);
  const double iterations = it->GetComponent(0, 0);
  const double run = static_cast<double>(s.Dispatches) / 2.0; // givers + gather per iteration
  std::cout << "[ waterflow] " << iterations << " iterations, " << run
            << " run on the GPU (including those undone), " << s.Waits << " waits\n";
  EXPECT_GT(iterations, 10.0);
  EXPECT_GE(run, iterations);
  EXPECT_LE(run - iterations, 8.0 + 0.1 * iterations);
  // Far fewer host waits than iterations: no read-back per iteration.
  EXPECT_LT(static_cast<double>(s.Waits), 0.5 * iterations);
}

//------------------------------------------------------------------------------
TEST(GPUDataPathDeathTest, EndlessJobStopsWithTheStageMessage)
{
  // A kernel that would run for hours, in a stage with a budget of one second: the caller gets
  // an Error naming the stage within the budget and its grace period, and the context is given
  // up (Auto then picks the CPU). In a child process: the endless kernel keeps llvmpipe's
  // threads busy until the process ends.
  TERROIR_REQUIRE_GPU_OR_SKIP();
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
    {
      auto& ctx = Context::Global();
      const auto t0 = std::chrono::steady_clock::now();
      try
      {
        ctx.Run("endless test",
          1.0,
          [&]
          {
            StorageBuffer b(4096 * 64 * 4, Contents::Zero);
            auto& prog = ctx.GetProgram("TestEndless.comp", kEndlessSource);
            prog.SetUInt("uIterations", 0x7fffffffu);
            b.Bind(0);
            prog.Dispatch(4096);
            ctx.WaitIdle();
          });
        std::fprintf(stderr, "the endless job returned\n");
        _exit(1);
      }
      catch (const Error& e)
      {
        const double s =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::string why;
        const int backend =
          vtkTerroirComputeContext::ResolveBackend(vtkTerroirComputeContext::GPU, true, why);
        std::fprintf(stderr,
          "%s\nafter %.1f s; lost %d; GPU request then: %d (%s)\n",
          e.what(),
          s,
          ctx.IsLost() ? 1 : 0,
          backend,
          why.c_str());
        std::fflush(stderr);
        _exit(s < 30.0 && ctx.IsLost() && backend == -1 ? 0 : 2);
      }
    },
    ::testing::ExitedWithCode(0),
    "endless test: the GPU did not finish within the stage's budget of 1 s");
}

TEST(GPUDataPathDeathTest, WaitPastTheBudgetStops)
{
  // The job's own waits (a download, WaitIdle) check the budget.
  TERROIR_REQUIRE_GPU_OR_SKIP();
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
    {
      auto& ctx = Context::Global();
      try
      {
        ctx.Run("slow test",
          0.5,
          [&]
          {
            StorageBuffer b(4096, Contents::Zero);
            std::this_thread::sleep_for(std::chrono::milliseconds(700));
            std::vector<char> back(4096);
            b.Download(back.data(), back.size());
          });
        _exit(1);
      }
      catch (const Error& e)
      {
        std::fprintf(stderr, "%s\n", e.what());
        std::fflush(stderr);
        _exit(0);
      }
    },
    ::testing::ExitedWithCode(0),
    "slow test: the GPU did not finish within the stage's budget of 0.5 s \\(waiting for "
    "download\\)");
}

// Double arithmetic as the water flow and k-means kernels use it, against the CPU: sums of
// values read from buffers, float-to-double conversions in a dvec4, max, and k-means' float
// distance must be exact. Local arrays of doubles are measured and printed, not asserted: our
// kernels have none (Testing/CheckShaderRules.sh), since on an H200 (driver 580.159.04) every
// sum through one differed from the CPU's (20000 of 20000, and 12000 of 20000 for a dvec4
// array indexed by label) while the same sums read from the buffer were exact.
TEST(GPUDataPath, DoubleIdiomsOfTheKernels)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  static const char* const source = R"(
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer In { double v[]; };
layout(std430, binding = 1) readonly buffer InF { float f[]; };
layout(std430, binding = 2) readonly buffer Lab { int lab[]; };
layout(std430, binding = 3) writeonly buffer Out { double r[]; };
uniform uint uN;
void main()
{
  uint i = TERROIR_GLOBAL_ID.x;
  uint n = uN;
  if (i >= uN)
  {
    return;
  }
  // 0: a local double array, dynamic index (the water flow's heights, as they were)
  double arr[8];
  for (int k = 0; k < 8; ++k)
  {
    arr[k] = v[8u * i + uint(k)];
  }
  precise double s0 = 0.0LF;
  for (int k = 0; k < 8; ++k)
  {
    int j = (k * 3 + int(i)) & 7;
    s0 = s0 + arr[j];
  }
  // 1: the same from the buffer directly
  precise double s1 = 0.0LF;
  for (int k = 0; k < 8; ++k)
  {
    int j = (k * 3 + int(i)) & 7;
    s1 = s1 + v[8u * i + uint(j)];
  }
  // 2: float to double conversions summed in a dvec4 (k-means' partial sums)
  precise dvec4 run = dvec4(0.0LF);
  for (int k = 0; k < 8; k += 4)
  {
    run = run + dvec4(f[8u * i + uint(k)], f[8u * i + uint(k + 1)], f[8u * i + uint(k + 2)],
                  f[8u * i + uint(k + 3)]);
  }
  // 3: a local dvec4 array indexed by data (k-means' accumulators)
  dvec4 acc[4];
  for (int k = 0; k < 4; ++k)
  {
    acc[k] = dvec4(0.0LF);
  }
  for (int k = 0; k < 8; ++k)
  {
    int l = lab[8u * i + uint(k)];
    acc[l] = acc[l] + dvec4(double(f[8u * i + uint(k)]));
  }
  // 4: max and a difference (the water flow's drops)
  precise double d4 = max(0.0LF, v[8u * i] - v[8u * i + 1u]);
  // 5: k-means' float distance: vec4 differences squared and summed in order
  vec4 xa = vec4(f[8u * i], f[8u * i + 1u], f[8u * i + 2u], f[8u * i + 3u]);
  vec4 xb = vec4(f[8u * i + 4u], f[8u * i + 5u], f[8u * i + 6u], f[8u * i + 7u]);
  precise vec4 dd = xa - xb;
  precise vec4 sq = dd * dd;
  precise float d5 = ((sq.x + sq.y) + sq.z) + sq.w;
  r[8u * i] = s0;
  r[8u * i + 1u] = s1;
  r[8u * i + 2u] = run.x + run.y + run.z + run.w;
  r[8u * i + 3u] = acc[0].x;
  r[8u * i + 4u] = acc[1].y;
  r[8u * i + 5u] = acc[2].z;
  r[8u * i + 6u] = acc[3].w;
  r[8u * i + 7u] = d4;
  r[8u * n + i] = double(d5);
}
)";
  const std::size_t n = 20000;
  std::mt19937_64 rng(31);
  auto uniform = [&rng] { return static_cast<double>(rng() >> 11) * (1.0 / 9007199254740992.0); };
  std::vector<double> v(8 * n);
  std::vector<float> f(8 * n);
  std::vector<std::int32_t> lab(8 * n);
  for (std::size_t k = 0; k < v.size(); ++k)
  {
    v[k] = std::ldexp(uniform() + 0.1, static_cast<int>(uniform() * 30) - 15);
    f[k] = static_cast<float>(std::ldexp(uniform() + 0.1, static_cast<int>(uniform() * 30) - 15));
    lab[k] = static_cast<std::int32_t>(rng() % 4);
  }
  std::vector<double> r(9 * n);
  auto& ctx = Context::Global();
  ctx.Run(
    [&]
    {
      StorageBuffer bv(v.size() * 8, v.data()), bf(f.size() * 4, f.data()),
        bl(lab.size() * 4, lab.data()), br(r.size() * 8, Contents::Undefined);
      auto& prog = ctx.GetProgram("TestDoubleIdioms.comp", source);
      prog.SetUInt("uN", static_cast<unsigned>(n));
      bv.Bind(0);
      bf.Bind(1);
      bl.Bind(2);
      br.Bind(3);
      prog.Dispatch(static_cast<unsigned>((n + 63) / 64));
      br.Download(r.data(), r.size() * 8);
    });
  std::size_t bad[9] = { 0, 0, 0, 0, 0, 0, 0, 0, 0 };
  for (std::size_t i = 0; i < n; ++i)
  {
    double s0 = 0.0;
    for (int k = 0; k < 8; ++k)
    {
      s0 = s0 + v[8 * i + static_cast<std::size_t>((k * 3 + static_cast<int>(i)) & 7)];
    }
    double run[4] = { 0, 0, 0, 0 };
    for (int k = 0; k < 8; ++k)
    {
      run[k % 4] = run[k % 4] + static_cast<double>(f[8 * i + static_cast<std::size_t>(k)]);
    }
    double acc[4] = { 0, 0, 0, 0 };
    for (int k = 0; k < 8; ++k)
    {
      const int l = lab[8 * i + static_cast<std::size_t>(k)];
      acc[l] = acc[l] + static_cast<double>(f[8 * i + static_cast<std::size_t>(k)]);
    }
    const double expect[8] = { s0,
      s0,
      ((run[0] + run[1]) + run[2]) + run[3],
      acc[0],
      acc[1],
      acc[2],
      acc[3],
      std::max(0.0, v[8 * i] - v[8 * i + 1]) };
    for (int q = 0; q < 8; ++q)
    {
      bad[q] += std::memcmp(&expect[q], &r[8 * i + static_cast<std::size_t>(q)], 8) != 0 ? 1 : 0;
    }
    float d5 = 0.0f;
    for (int k = 0; k < 4; ++k)
    {
      volatile float dd =
        f[8 * i + static_cast<std::size_t>(k)] - f[8 * i + 4 + static_cast<std::size_t>(k)];
      volatile float sq = dd * dd;
      d5 = d5 + sq;
    }
    bad[8] += static_cast<double>(d5) != r[8 * n + i] ? 1 : 0;
  }
  std::cout << "[ doubles  ] " << vtkTerroirComputeContext::GetRenderer()
            << ": differ from the CPU (of " << n << "): local array " << bad[0] << ", buffer "
            << bad[1] << ", dvec4 of floats " << bad[2] << ", local dvec4 array by label " << bad[3]
            << " " << bad[4] << " " << bad[5] << " " << bad[6] << ", max " << bad[7]
            << ", float distance " << bad[8] << "\n";
  for (int q : { 1, 2, 7, 8 })
  {
    EXPECT_EQ(bad[q], 0u) << "idiom " << q;
  }
}

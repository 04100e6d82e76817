// Tests of Terroir::Compute: the headless EGL compute context, programs, storage buffers, the
// worker thread and the backend rule. Runs on Mesa llvmpipe here (EGL surfaceless) and on
// NVIDIA through the EGL device platform.
#include "TerroirFilterTestUtilities.h"
#include "TerroirScopedEnvironment.h"
#include "vtkTerroirComputeContext.h"
#include "vtkTerroirGPU.h"

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <limits>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace
{
using terroir::gpu::Context;
using terroir::gpu::Error;
using terroir::gpu::Program;
using terroir::gpu::StorageBuffer;

// y = a*x + b, one invocation per element; `precise` forbids contraction into an fma, so the
// result is the correctly rounded float32 a*x, then + b, as on the CPU.
const char* kSaxpySource = R"(
layout(local_size_x = LOCAL_X) in;
layout(std430, binding = 0) readonly buffer XBuf { float x[]; };
layout(std430, binding = 1) writeonly buffer YBuf { float y[]; };
uniform uint uN;
uniform float uA;
uniform float uB;
void main()
{
  uint i = gl_GlobalInvocationID.x;
  if (i >= uN)
  {
    return;
  }
  precise float ax = uA * x[i];
  precise float r = ax + uB;
  y[i] = r;
}
)";

// Copies src to dst, one uint per invocation.
const char* kCopySource = R"(
layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Src { uint src[]; };
layout(std430, binding = 1) writeonly buffer Dst { uint dst[]; };
uniform uint uN;
void main()
{
  uint i = gl_GlobalInvocationID.y * (gl_NumWorkGroups.x * 256u) + gl_GlobalInvocationID.x;
  if (i < uN)
  {
    dst[i] = src[i];
  }
}
)";

// Writes the work-group size the program was compiled with (set by a define).
const char* kGroupSizeSource = R"(
#ifndef LOCAL_X
#define LOCAL_X 8
#endif
layout(local_size_x = LOCAL_X) in;
layout(std430, binding = 0) writeonly buffer Out { uint result[]; };
void main()
{
  if (gl_GlobalInvocationID.x == 0u)
  {
    result[0] = gl_WorkGroupSize.x;
  }
}
)";

// Uses the helpers of Shaders/Common.glsl (prepended by Program).
const char* kCommonSource = R"(
layout(local_size_x = 4, local_size_y = 4) in;
layout(std430, binding = 0) readonly buffer In { float values[]; };
layout(std430, binding = 1) writeonly buffer Out { uint flags[]; };
uniform uvec2 uSize;
void main()
{
  uvec2 ij = gl_GlobalInvocationID.xy;
  if (!terroirInside(ij, uSize))
  {
    return;
  }
  uint k = terroirIndex(ij, uSize.x);
  float v = values[k];
  uint f = 0u;
  if (terroirIsNaN(v)) f |= 1u;
  if (terroirIsFinite(v)) f |= 2u;
  if (terroirIsNaN(TERROIR_NAN)) f |= 4u;
  if (abs(TERROIR_PI - 3.14159265) < 1e-6) f |= 8u;
  flags[k] = f;
}
)";

std::vector<float> SaxpyInput(std::size_t n)
{
  // Deterministic, non-trivial values with full mantissas (no std:: distributions).
  std::vector<float> x(n);
  std::uint64_t s = 0x9E3779B97F4A7C15ull;
  for (std::size_t i = 0; i < n; ++i)
  {
    s ^= s << 13;
    s ^= s >> 7;
    s ^= s << 17;
    x[i] = static_cast<float>(static_cast<double>(s >> 11) / 9007199254740992.0 * 2000.0 - 1000.0);
  }
  return x;
}

} // namespace

//------------------------------------------------------------------------------
TEST(TerroirComputeContext, ContextIsAvailableWithGL43)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  const auto lim = Context::Global().GetLimits();
  EXPECT_TRUE(lim.MajorVersion > 4 || (lim.MajorVersion == 4 && lim.MinorVersion >= 3))
    << lim.Version;
  EXPECT_TRUE(Context::Global().UnavailableReason().empty());
  EXPECT_FALSE(lim.Renderer.empty());
  EXPECT_NE(
    lim.Version.find(std::to_string(lim.MajorVersion) + "." + std::to_string(lim.MinorVersion)),
    std::string::npos)
    << lim.Version;
  EXPECT_TRUE(lim.Platform == "device" || lim.Platform == "surfaceless") << lim.Platform;
  // OpenGL 4.3 core minimums (spec table 23.63 ff.).
  for (int i = 0; i < 3; ++i)
  {
    EXPECT_GE(lim.MaxWorkGroupCount[i], 65535) << i;
  }
  EXPECT_GE(lim.MaxWorkGroupSize[0], 1024);
  EXPECT_GE(lim.MaxWorkGroupSize[1], 1024);
  EXPECT_GE(lim.MaxWorkGroupSize[2], 64);
  EXPECT_GE(lim.MaxWorkGroupInvocations, 1024);
  if (const char* cap = std::getenv("TERROIR_GPU_MAX_STORAGE_BLOCK_MB"))
  {
    // The stress run lowers the limit on purpose (Documentation/Compute.md).
    EXPECT_LE(lim.MaxShaderStorageBlockSize, std::atoll(cap) << 20);
  }
  else
  {
    EXPECT_GE(lim.MaxShaderStorageBlockSize, 1LL << 24);
  }
  EXPECT_GE(lim.MaxShaderStorageBufferBindings, 8);
  // The wrapped front reports the same thing.
  EXPECT_TRUE(vtkTerroirComputeContext::IsAvailable());
  EXPECT_EQ(vtkTerroirComputeContext::GetRenderer(), lim.Renderer);
  EXPECT_EQ(vtkTerroirComputeContext::GetVersion(), lim.Version);
  EXPECT_EQ(vtkTerroirComputeContext::GetPlatform(), lim.Platform);
  std::cout << "[ context  ] " << lim.Renderer << " | " << lim.Version << " | EGL " << lim.Platform
            << " | created in " << lim.CreationSeconds * 1e3 << " ms\n";
  RecordProperty("CreationMilliseconds", std::to_string(lim.CreationSeconds * 1e3));
}

TEST(TerroirComputeContext, SaxpyMatchesCPUExactly)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  const std::size_t n = 1000003; // not a multiple of the work-group size
  const unsigned local = 256;
  const float a = 2.7182817f;
  const float b = -1.4142135f;
  const std::vector<float> x = SaxpyInput(n);
  std::vector<float> y(n, -7.0f);
  auto& ctx = Context::Global();
  ctx.Run(
    [&]
    {
      StorageBuffer xb(n * sizeof(float), x.data());
      StorageBuffer yb(n * sizeof(float));
      auto& prog = ctx.GetProgram("Saxpy.comp", kSaxpySource, { "LOCAL_X 256" });
      prog.SetUInt("uN", static_cast<unsigned>(n));
      prog.SetFloat("uA", a);
      prog.SetFloat("uB", b);
      xb.Bind(0);
      yb.Bind(1);
      prog.Dispatch(static_cast<unsigned>((n + local - 1) / local));
      yb.Download(y.data(), n * sizeof(float));
    });
  std::size_t mismatches = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    volatile float ax = a * x[i]; // volatile: no fma contraction on the CPU either
    const float expected = ax + b;
    if (std::memcmp(&expected, &y[i], sizeof(float)) != 0)
    {
      if (++mismatches <= 5)
      {
        ADD_FAILURE() << "i=" << i << " x=" << x[i] << " gpu=" << y[i] << " cpu=" << expected;
      }
    }
  }
  EXPECT_EQ(mismatches, 0u);
}

TEST(TerroirComputeContext, UploadDownloadRoundTripWithOffsets)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  const std::size_t count = 1000;
  std::vector<std::int32_t> expected(count, 0);
  std::vector<std::int32_t> all(count, -1);
  std::vector<std::int32_t> window(12, -1);
  Context::Global().Run(
    [&]
    {
      StorageBuffer buf(count * sizeof(std::int32_t));
      EXPECT_EQ(buf.Size(), count * sizeof(std::int32_t));
      buf.Download(all.data(), count * sizeof(std::int32_t));
      EXPECT_EQ(all, expected) << "a new buffer without data must be zero-filled";

      std::vector<std::int32_t> part(100);
      for (int i = 0; i < 100; ++i)
      {
        part[i] = 1000 + 7 * i;
        expected[100 + i] = part[i];
      }
      buf.Upload(part.data(), part.size() * sizeof(std::int32_t), 100 * sizeof(std::int32_t));
      buf.Download(all.data(), count * sizeof(std::int32_t));
      EXPECT_EQ(all, expected);
      // A window straddling the start of the uploaded range (offset 98 elements).
      buf.Download(window.data(), window.size() * sizeof(std::int32_t), 98 * sizeof(std::int32_t));
      EXPECT_EQ(window[0], 0);
      EXPECT_EQ(window[1], 0);
      EXPECT_EQ(window[2], 1000);
      EXPECT_EQ(window[11], 1000 + 7 * 9);

      // Misuse is reported, not silently truncated.
      EXPECT_THROW(buf.Upload(part.data(), 8, count * sizeof(std::int32_t) - 4), Error);
      EXPECT_THROW(buf.Download(all.data(), count * sizeof(std::int32_t) + 1), Error);
      EXPECT_THROW(StorageBuffer(0), Error);

      // Clear zeroes everything again; a move leaves the source empty.
      buf.Clear();
      buf.Download(all.data(), count * sizeof(std::int32_t));
      EXPECT_EQ(all, std::vector<std::int32_t>(count, 0));
      StorageBuffer moved(std::move(buf));
      EXPECT_EQ(buf.Id(), 0u);
      EXPECT_NE(moved.Id(), 0u);
      EXPECT_THROW(buf.Bind(0), Error);
    });
}

TEST(TerroirComputeContext, GLObjectsOutsideRunThrow)
{
  EXPECT_THROW(StorageBuffer(16), Error);
  EXPECT_THROW(Program("Outside.comp", kGroupSizeSource), Error);
}

TEST(TerroirComputeContext, SyntaxErrorNamesShaderAndDriverLog)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  const char* broken = "layout(local_size_x = 1) in;\n"
                       "void main()\n"
                       "{\n"
                       "  float x = ;\n"
                       "}\n";
  std::string message;
  Context::Global().Run(
    [&]
    {
      try
      {
        Context::Global().GetProgram("Broken.comp", broken);
      }
      catch (const Error& e)
      {
        message = e.what();
      }
    });
  ASSERT_FALSE(message.empty()) << "compiling a syntax error did not throw";
  EXPECT_NE(message.find("Broken.comp"), std::string::npos) << message;
  const auto logAt = message.find("--- driver log ---\n");
  ASSERT_NE(logAt, std::string::npos) << message;
  EXPECT_NE(message.find("rror", logAt), std::string::npos) << message; // driver's error text
  // The numbered source points at kernel line 4 (not a line of the preamble).
  EXPECT_NE(message.find(">    4 |   float x = ;"), std::string::npos) << message;
  std::cout << message;
}

TEST(TerroirComputeContext, CommonHelpersArePrepended)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  const unsigned nx = 5, ny = 3;
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<float> values(nx * ny, 1.5f);
  values[3] = std::nanf("");
  values[7] = inf;
  values[8] = -inf;
  std::vector<std::uint32_t> flags(nx * ny, 0xFFFFFFFFu);
  Context::Global().Run(
    [&]
    {
      StorageBuffer in(values.size() * sizeof(float), values.data());
      StorageBuffer out(flags.size() * sizeof(std::uint32_t));
      auto& prog = Context::Global().GetProgram("CommonHelpers.comp", kCommonSource);
      prog.SetUVec2("uSize", nx, ny);
      in.Bind(0);
      out.Bind(1);
      prog.Dispatch((nx + 3) / 4, (ny + 3) / 4);
      out.Download(flags.data(), flags.size() * sizeof(std::uint32_t));
    });
  for (unsigned k = 0; k < nx * ny; ++k)
  {
    const std::uint32_t expected =
      (k == 3 ? 1u : 0u) | ((k == 3 || k == 7 || k == 8) ? 0u : 2u) | 4u | 8u;
    EXPECT_EQ(flags[k], expected) << "cell " << k;
  }
}

TEST(TerroirComputeContext, ExceptionInsideRunPropagates)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  auto& ctx = Context::Global();
  try
  {
    ctx.Run([] { throw std::runtime_error("boom from the compute thread"); });
    ADD_FAILURE() << "Run did not rethrow";
  }
  catch (const std::runtime_error& e)
  {
    EXPECT_STREQ(e.what(), "boom from the compute thread");
  }
  EXPECT_THROW(ctx.Run([] { throw Error("gl failure"); }), Error);
  // The context keeps working afterwards.
  bool ran = false;
  ctx.Run([&] { ran = true; });
  EXPECT_TRUE(ran);
}

TEST(TerroirComputeContext, RunFromTwoThreadsIsSerialised)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  auto& ctx = Context::Global();
  std::thread::id contextThread;
  ctx.Run([&] { contextThread = std::this_thread::get_id(); });
  ASSERT_NE(contextThread, std::this_thread::get_id());

  std::atomic<int> inside{ 0 };
  std::atomic<int> overlaps{ 0 };
  std::atomic<int> wrongThread{ 0 };
  std::atomic<int> wrongResults{ 0 };
  int counter = 0; // deliberately not atomic: jobs are serialised
  auto worker = [&](float scale)
  {
    for (int iter = 0; iter < 25; ++iter)
    {
      const std::size_t n = 1000;
      std::vector<float> x(n), y(n);
      for (std::size_t i = 0; i < n; ++i)
      {
        x[i] = static_cast<float>(i);
      }
      ctx.Run(
        [&]
        {
          if (inside.fetch_add(1) != 0)
          {
            ++overlaps;
          }
          if (std::this_thread::get_id() != contextThread)
          {
            ++wrongThread;
          }
          ++counter;
          StorageBuffer xb(n * sizeof(float), x.data());
          StorageBuffer yb(n * sizeof(float));
          auto& prog = ctx.GetProgram("Saxpy.comp", kSaxpySource, { "LOCAL_X 64" });
          prog.SetUInt("uN", static_cast<unsigned>(n));
          prog.SetFloat("uA", scale);
          prog.SetFloat("uB", 0.0f);
          xb.Bind(0);
          yb.Bind(1);
          prog.Dispatch(static_cast<unsigned>((n + 63) / 64));
          yb.Download(y.data(), n * sizeof(float));
          inside.fetch_sub(1);
        });
      for (std::size_t i = 0; i < n; ++i)
      {
        if (y[i] != scale * static_cast<float>(i))
        {
          ++wrongResults;
          break;
        }
      }
    }
  };
  std::thread t1(worker, 2.0f);
  std::thread t2(worker, 3.0f);
  t1.join();
  t2.join();
  EXPECT_EQ(counter, 50);
  EXPECT_EQ(overlaps.load(), 0);
  EXPECT_EQ(wrongThread.load(), 0);
  EXPECT_EQ(wrongResults.load(), 0);
}

TEST(TerroirComputeContext, ReentrantRunRunsInline)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  auto& ctx = Context::Global();
  std::thread::id outer, inner;
  int order = 0;
  int innerOrder = -1, afterOrder = -1;
  ctx.Run(
    [&]
    {
      outer = std::this_thread::get_id();
      ctx.Run(
        [&]
        {
          inner = std::this_thread::get_id();
          innerOrder = order++;
        });
      afterOrder = order++;
    });
  EXPECT_EQ(outer, inner);
  EXPECT_EQ(innerOrder, 0);
  EXPECT_EQ(afterOrder, 1);
  // Exceptions from a nested job reach the outer caller too.
  EXPECT_THROW(ctx.Run([&] { ctx.Run([] { throw Error("nested"); }); }), Error);
}

TEST(TerroirComputeContext, ProgramCacheIsKeyedByDefines)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  auto& ctx = Context::Global();
  std::uint32_t size64 = 0, size32 = 0, sizeDefault = 0;
  ctx.Run(
    [&]
    {
      Program& p64 = ctx.GetProgram("GroupSize.comp", kGroupSizeSource, { "LOCAL_X 64" });
      Program& again = ctx.GetProgram("GroupSize.comp", kGroupSizeSource, { "LOCAL_X 64" });
      Program& p32 = ctx.GetProgram("GroupSize.comp", kGroupSizeSource, { "LOCAL_X 32" });
      Program& pDefault = ctx.GetProgram("GroupSize.comp", kGroupSizeSource);
      EXPECT_EQ(&p64, &again);
      EXPECT_EQ(p64.Id(), again.Id());
      EXPECT_NE(&p64, &p32);
      EXPECT_NE(p64.Id(), p32.Id());
      EXPECT_NE(&p64, &pDefault);
      EXPECT_EQ(p64.Name(), "GroupSize.comp");
      StorageBuffer out(sizeof(std::uint32_t));
      out.Bind(0);
      p64.Dispatch(1);
      out.Download(&size64, sizeof(size64));
      p32.Dispatch(1);
      out.Download(&size32, sizeof(size32));
      pDefault.Dispatch(1);
      out.Download(&sizeDefault, sizeof(sizeDefault));
      // Same name, other source: refused instead of returning the wrong program.
      EXPECT_THROW(ctx.GetProgram("GroupSize.comp", kCopySource, { "LOCAL_X 64" }), Error);
    });
  EXPECT_EQ(size64, 64u);
  EXPECT_EQ(size32, 32u);
  EXPECT_EQ(sizeDefault, 8u);
}

TEST(TerroirComputeContext, DispatchWithTooManyGroupsThrows)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  auto& ctx = Context::Global();
  const auto lim = ctx.GetLimits();
  std::string message;
  ctx.Run(
    [&]
    {
      Program& p = ctx.GetProgram("GroupSize.comp", kGroupSizeSource, { "LOCAL_X 64" });
      StorageBuffer out(sizeof(std::uint32_t));
      out.Bind(0);
      try
      {
        p.Dispatch(static_cast<unsigned>(lim.MaxWorkGroupCount[0]) + 1u);
      }
      catch (const Error& e)
      {
        message = e.what();
      }
      EXPECT_THROW(p.Dispatch(1, static_cast<unsigned>(lim.MaxWorkGroupCount[1]) + 1u), Error);
      EXPECT_THROW(p.Dispatch(1, 1, static_cast<unsigned>(lim.MaxWorkGroupCount[2]) + 1u), Error);
      EXPECT_NO_THROW(p.Dispatch(static_cast<unsigned>(lim.MaxWorkGroupCount[0])));
    });
  EXPECT_NE(message.find("GroupSize.comp"), std::string::npos) << message;
  EXPECT_NE(message.find("GL_MAX_COMPUTE_WORK_GROUP_COUNT"), std::string::npos) << message;
}

//------------------------------------------------------------------------------
namespace
{
// Sets or unsets TERROIR_BACKEND for one scope and restores the previous value.
struct ScopedBackendEnv : terroir_test::ScopedEnvironment
{
  explicit ScopedBackendEnv(const char* value)
    : ScopedEnvironment("TERROIR_BACKEND", value)
  {
  }
};

bool Contains(const std::string& s, const std::string& part)
{
  return s.find(part) != std::string::npos;
}
} // namespace

TEST(TerroirComputeContext, PackFlagsPutsCellFourWPlusKInByteKOfWordW)
{
  // Worked by hand: cells 0 and 2 set in word 0 (bytes 0 and 2), cell 5 in word 1 (byte 1);
  // any nonzero byte counts as set and is stored as 1.
  const std::uint8_t flags[6] = { 1, 0, 7, 0, 0, 255 };
  const std::vector<std::uint32_t> words = terroir::gpu::PackFlags(flags, 6);
  ASSERT_EQ(words.size(), 2u);
  EXPECT_EQ(words[0], 0x00010001u);
  EXPECT_EQ(words[1], 0x00000100u);
  EXPECT_EQ(terroir::gpu::PackFlags(flags, 0), std::vector<std::uint32_t>(1, 0u));
}

TEST(TerroirComputeContext, VerifiedGPUPathsTable)
{
  using C = vtkTerroirComputeContext;
  std::string row;
  // llvmpipe's rows: verified correct, slower than the CPU: never chosen.
  EXPECT_FALSE(C::IsVerifiedFaster("vtkTerroirSlope", "llvmpipe (LLVM 15.0.6, 256 bits)", &row));
  EXPECT_TRUE(Contains(row, "vtkTerroirSlope on 'llvmpipe': correct")) << row;
  // The H200's rows: correct but slower (slope), or faster but not yet verified correct
  // (water flow): neither is chosen. No row for other GPUs, nor for unknown stages.
  EXPECT_FALSE(C::IsVerifiedFaster("vtkTerroirSlope", "NVIDIA H200/PCIe/SSE2", &row));
  EXPECT_TRUE(Contains(row, "correct, GPU 0.94x")) << row;
  EXPECT_FALSE(C::IsVerifiedFaster("vtkTerroirWaterFlow", "NVIDIA H200/PCIe/SSE2", &row));
  EXPECT_TRUE(Contains(row, "not verified correct")) << row;
  EXPECT_FALSE(C::IsVerifiedFaster("vtkTerroirSlope", "NVIDIA GeForce RTX 4090", &row));
  EXPECT_TRUE(row.empty()) << row;
  EXPECT_FALSE(C::IsVerifiedFaster("vtkTerroirNoSuchFilter", "llvmpipe", &row));
  // Every filter with a GPU path has a llvmpipe row.
  const std::string table = C::GetVerifiedTable();
  for (const char* stage : { "vtkTerroirSlope",
         "vtkTerroirTemperature",
         "vtkTerroirSoilHumidity",
         "vtkTerroirSolarIllumination",
         "vtkTerroirWaterFlow",
         "vtkTerroirKMeans" })
  {
    EXPECT_TRUE(Contains(table, std::string(stage) + " on 'llvmpipe'")) << table;
  }
}

TEST(TerroirComputeContext, ResolveBackendRules)
{
  using C = vtkTerroirComputeContext;
  const bool gpu = C::IsAvailable();
  const std::string renderer = C::GetRenderer();
  std::string why;

  EXPECT_STREQ(C::GetBackendName(C::Auto), "Auto");
  EXPECT_STREQ(C::GetBackendName(C::CPU), "CPU");
  EXPECT_STREQ(C::GetBackendName(C::GPU), "GPU");

  {
    ScopedBackendEnv env(nullptr);
    // Explicit CPU is always honoured.
    EXPECT_EQ(C::ResolveBackend(C::CPU, true, why), C::CPU);
    EXPECT_TRUE(Contains(why, "requested CPU")) << why;
    // Explicit GPU needs a GPU path and a context.
    EXPECT_EQ(C::ResolveBackend(C::GPU, false, why), -1);
    EXPECT_TRUE(Contains(why, "no GPU path")) << why;
    EXPECT_EQ(C::ResolveBackend(C::GPU, true, why), gpu ? C::GPU : -1);
    EXPECT_TRUE(Contains(why, gpu ? renderer : "no GPU compute context")) << why;
    // Auto: GPU when possible, else CPU with the reason.
    EXPECT_EQ(C::ResolveBackend(C::Auto, false, why), C::CPU);
    EXPECT_TRUE(Contains(why, "filter has no GPU path")) << why;
    // Auto picks the GPU only where the stage's GPU path is verified correct and faster on this
    // hardware: never a software rasterizer (llvmpipe's rows are slower than the CPU), and on
    // hardware no stage until its row exists.
    const bool hardware =
      gpu && terroir::gpu::Context::Global().HasHardwareDevice() && !C::IsSoftwareRenderer();
    const bool verified = hardware && C::IsVerifiedFaster("vtkTerroirSlope", renderer);
    EXPECT_EQ(C::ResolveBackend(C::Auto, "vtkTerroirSlope", true, why), verified ? C::GPU : C::CPU);
    if (verified)
    {
      EXPECT_TRUE(Contains(why, "GPU (auto: " + renderer)) << why;
    }
    else if (terroir::gpu::Context::Global().HasHardwareDevice())
    {
      EXPECT_TRUE(Contains(why, "not") && Contains(why, "verified")) << why;
    }
    else
    {
      EXPECT_TRUE(Contains(why, "EGL lists no hardware GPU")) << why;
    }
    // Without a stage name nothing is verified.
    EXPECT_EQ(C::ResolveBackend(C::Auto, true, why), C::CPU);
    // Unknown request values are errors.
    EXPECT_EQ(C::ResolveBackend(7, true, why), -1);
  }
  {
    ScopedBackendEnv env("CPU"); // case-insensitive
    EXPECT_EQ(C::ResolveBackend(C::Auto, true, why), C::CPU);
    EXPECT_TRUE(Contains(why, "TERROIR_BACKEND=cpu")) << why;
    // The variable only overrides Auto.
    EXPECT_EQ(C::ResolveBackend(C::GPU, true, why), gpu ? C::GPU : -1);
  }
  {
    ScopedBackendEnv env("Gpu");
    EXPECT_EQ(C::ResolveBackend(C::Auto, true, why), gpu ? C::GPU : -1);
    EXPECT_TRUE(Contains(why, "TERROIR_BACKEND=gpu")) << why;
    EXPECT_EQ(C::ResolveBackend(C::CPU, true, why), C::CPU);
    // A stage without a GPU path stays on the CPU (the variable applies to whole runs).
    EXPECT_EQ(C::ResolveBackend(C::Auto, false, why), gpu ? C::CPU : -1);
  }
  {
    ScopedBackendEnv env("auto");
    EXPECT_EQ(C::ResolveBackend(C::Auto, true, why), C::CPU);
    EXPECT_TRUE(Contains(why, "auto")) << why;
  }
  {
    ScopedBackendEnv env("fast");
    EXPECT_EQ(C::ResolveBackend(C::Auto, true, why), -1);
    EXPECT_EQ(why, "TERROIR_BACKEND='fast' is not cpu, gpu or auto");
    EXPECT_EQ(C::ResolveBackend(C::CPU, true, why), C::CPU);
  }
}

//------------------------------------------------------------------------------
// Shutdown at process exit: the worker thread is stopped and joined by an atexit handler,
// including while another thread keeps posting jobs. Death tests run in a fresh process.
TEST(TerroirComputeContextDeathTest, ExitAfterUseIsClean)
{
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
    {
      auto& ctx = Context::Global();
      if (ctx.IsAvailable())
      {
        ctx.Run(
          [&]
          {
            StorageBuffer b(1024);
            ctx.GetProgram("GroupSize.comp", kGroupSizeSource, { "LOCAL_X 16" });
          });
      }
      std::exit(0);
    },
    ::testing::ExitedWithCode(0),
    "");
}

TEST(TerroirComputeContextDeathTest, ExitWhileAnotherThreadRunsJobsIsClean)
{
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
    {
      auto& ctx = Context::Global();
      if (ctx.IsAvailable())
      {
        // Static: the thread outlives this block and keeps running during exit().
        static std::atomic<int> done{ 0 };
        std::thread(
          [&ctx]
          {
            for (;;)
            {
              try
              {
                ctx.Run(
                  [&]
                  {
                    StorageBuffer b(4096);
                    ++done;
                  });
              }
              catch (const Error&)
              {
                return; // the context has been shut down
              }
            }
          })
          .detach();
        while (done.load() < 10)
        {
          std::this_thread::yield();
        }
      }
      std::exit(0);
    },
    ::testing::ExitedWithCode(0),
    "");
}

// A child of fork() cannot use the parent's context (its worker thread is not copied): it must
// report the context unavailable, make Run throw instead of waiting forever, fall back to the
// CPU under Auto, and exit at once (no wait for a worker that does not exist).
TEST(TerroirComputeContext, ForkedChildFallsBackAndExits)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0)
  {
    int code = 0;
    auto& ctx = Context::Global();
    if (ctx.IsAvailable())
    {
      code |= 1;
    }
    if (ctx.UnavailableReason().find("fork()") == std::string::npos)
    {
      code |= 2;
    }
    try
    {
      ctx.Run([] {});
      code |= 4;
    }
    catch (const Error&)
    {
    }
    std::string why;
    if (vtkTerroirComputeContext::ResolveBackend(vtkTerroirComputeContext::Auto, true, why) !=
      vtkTerroirComputeContext::CPU)
    {
      code |= 8;
    }
    // A forked child leaves with _exit, as Python's multiprocessing does: exit() would run the
    // GL driver's exit handlers in the child, and NVIDIA's tore down the parent's context
    // through the file descriptors the child shares (the parent's next GPU job hung: H200,
    // 2026-11-26; Documentation/Compute.md, "Shutdown, exit and fork").
    _exit(code);
  }
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  const double seconds =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_TRUE(WIFEXITED(status)) << "child did not exit normally, status " << status;
  EXPECT_EQ(WEXITSTATUS(status), 0) << "bitmask of failed checks in the child";
  EXPECT_LT(seconds, 5.0);
  // The parent's context is unaffected.
  bool ran = false;
  Context::Global().Run([&] { ran = true; });
  EXPECT_TRUE(ran);
}

//------------------------------------------------------------------------------
// Measurement: bandwidth of a trivial copy kernel on 64 MB (read 64 MB + write 64 MB).
TEST(TerroirComputeContext, CopyKernelBandwidth64MB)
{
  TERROIR_REQUIRE_GPU_OR_SKIP();
  const std::size_t n = (64u << 20) / sizeof(std::uint32_t);
  std::vector<std::uint32_t> src(n), dst(n, 0);
  for (std::size_t i = 0; i < n; ++i)
  {
    src[i] = static_cast<std::uint32_t>(i * 2654435761u);
  }
  auto& ctx = Context::Global();
  double best = 1e30;
  double uploadSeconds = 0, downloadSeconds = 0, compileSeconds = 0;
  ctx.Run(
    [&]
    {
      auto t0 = std::chrono::steady_clock::now();
      StorageBuffer a(n * sizeof(std::uint32_t), src.data());
      StorageBuffer b(n * sizeof(std::uint32_t));
      ctx.Finish();
      uploadSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      t0 = std::chrono::steady_clock::now();
      auto& prog = ctx.GetProgram("Copy.comp", kCopySource);
      compileSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      prog.SetUInt("uN", static_cast<unsigned>(n));
      a.Bind(0);
      b.Bind(1);
      const unsigned groups = static_cast<unsigned>((n + 255) / 256);
      const unsigned gx = 4096, gy = (groups + gx - 1) / gx;
      prog.Dispatch(gx, gy); // warm-up (compiles llvmpipe's variant)
      ctx.Finish();
      for (int rep = 0; rep < 5; ++rep)
      {
        t0 = std::chrono::steady_clock::now();
        prog.Dispatch(gx, gy);
        ctx.Finish();
        best = std::min(
          best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      }
      t0 = std::chrono::steady_clock::now();
      b.Download(dst.data(), n * sizeof(std::uint32_t));
      downloadSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    });
  EXPECT_EQ(dst, src);
  const double gbps = 2.0 * 64.0 * 1048576.0 / best / 1e9;
  std::cout << "[ bandwidth] copy kernel 64 MB: " << best * 1e3 << " ms, " << gbps
            << " GB/s (read+write); upload " << uploadSeconds * 1e3 << " ms, download "
            << downloadSeconds * 1e3 << " ms; compile " << compileSeconds * 1e3 << " ms\n";
  RecordProperty("CopyGBps", std::to_string(gbps));
}

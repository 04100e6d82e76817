// terroir::gpu::Program: compute programs with the Terroir preamble and readable errors.
#include "vtkTerroirGPU.h"

#include "Private/vtkTerroirGPUPrivate.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <random>
#include <regex>
#include <set>
#include <sstream>
#include <utility>

namespace terroir
{
namespace gpu
{

namespace
{
std::vector<std::string> SplitLines(const std::string& text)
{
  std::vector<std::string> lines;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line))
  {
    lines.push_back(line);
  }
  return lines;
}

/// Lines `first..last` (1-based, clamped) of `lines`, numbered, with `>` on `mark`.
void AppendNumbered(std::ostringstream& out,
  const std::vector<std::string>& lines,
  int first,
  int last,
  int mark)
{
  first = std::max(first, 1);
  last = std::min(last, static_cast<int>(lines.size()));
  for (int i = first; i <= last; ++i)
  {
    char prefix[16];
    std::snprintf(prefix, sizeof(prefix), "%c%5d | ", i == mark ? '>' : ' ', i);
    out << prefix << lines[static_cast<std::size_t>(i - 1)] << "\n";
  }
}

/**
 * Builds "name: compile failed\n<driver log>\n<numbered source around each error>".
 * Source string 0 is the kernel (after `#line 1 0`), string 1 is Common.glsl (`#line 1 1`).
 * Understands Mesa ("0:12(5): error"), NVIDIA ("0(12) : error") and glslang ("ERROR: 0:12:").
 */
std::string CompileErrorMessage(const std::string& name,
  const std::string& log,
  const std::string& source,
  const std::string& common)
{
  std::ostringstream out;
  out << name << ": compute shader compilation failed\n--- driver log ---\n" << log;
  if (log.empty() || log.back() != '\n')
  {
    out << "\n";
  }
  const std::vector<std::string> srcLines = SplitLines(source);
  const std::vector<std::string> commonLines = SplitLines(common);
  static const std::regex locRe(R"(^\s*(?:ERROR:\s*|WARNING:\s*)?(\d+)(?::(\d+)|\((\d+)\)))");
  std::set<std::pair<int, int>> shown;
  for (const std::string& line : SplitLines(log))
  {
    std::smatch m;
    if (!std::regex_search(line, m, locRe) || line.find("rror") == std::string::npos)
    {
      continue;
    }
    const int string = std::stoi(m[1].str());
    const int lineNo = std::stoi(m[2].matched ? m[2].str() : m[3].str());
    if (!shown.insert({ string, lineNo }).second || shown.size() > 5)
    {
      continue;
    }
    const bool inCommon = (string == 1);
    const auto& lines = inCommon ? commonLines : srcLines;
    out << "--- " << (inCommon ? std::string("Common.glsl") : name) << " line " << lineNo
        << " ---\n";
    AppendNumbered(out, lines, lineNo - 3, lineNo + 3, lineNo);
  }
  if (shown.empty())
  {
    out << "--- " << name << " ---\n";
    AppendNumbered(out, srcLines, 1, 200, -1);
  }
  return out.str();
}
} // namespace

//------------------------------------------------------------------------------
Program::Program(const std::string& name,
  const std::string& source,
  const std::vector<std::string>& defines)
  : ShaderName(name)
{
  detail::RequireContextThread("terroir::gpu::Program");
  std::string full = "#version 430 core\n";
  for (const auto& d : defines)
  {
    full += "#define " + d + "\n";
  }
  const std::string common = detail::CommonSource();
  full += "#line 1 1\n";
  full += common;
  if (!common.empty() && common.back() != '\n')
  {
    full += "\n";
  }
  full += "#line 1 0\n";
  full += source;

  detail::ClearGLErrors();
  const GLuint shader = glCreateShader(GL_COMPUTE_SHADER);
  if (!shader)
  {
    throw Error(name + ": glCreateShader(GL_COMPUTE_SHADER) failed");
  }
  const char* text = full.c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  GLint logLength = 0;
  glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &logLength);
  std::string log(static_cast<std::size_t>(std::max(logLength, 0)), '\0');
  if (logLength > 0)
  {
    glGetShaderInfoLog(shader, logLength, nullptr, &log[0]);
    log.resize(std::strlen(log.c_str()));
  }
  if (!ok)
  {
    glDeleteShader(shader);
    throw Error(CompileErrorMessage(name, log, source, common));
  }

  const GLuint program = glCreateProgram();
  glAttachShader(program, shader);
  glLinkProgram(program);
  glDetachShader(program, shader);
  glDeleteShader(shader);
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok)
  {
    glGetProgramiv(program, GL_INFO_LOG_LENGTH, &logLength);
    std::string linkLog(static_cast<std::size_t>(std::max(logLength, 0)), '\0');
    if (logLength > 0)
    {
      glGetProgramInfoLog(program, logLength, nullptr, &linkLog[0]);
      linkLog.resize(std::strlen(linkLog.c_str()));
    }
    glDeleteProgram(program);
    throw Error(name + ": compute program link failed\n--- driver log ---\n" + linkLog);
  }
  this->Handle = program;
  this->GroupOffsetLocation = glGetUniformLocation(program, "terroirGroupOffset");
  this->GroupCountLocation = glGetUniformLocation(program, "terroirGroupCount");
  detail::CheckGLError(name + ": creating the program");
}

Program::~Program()
{
  // GL objects can only be deleted on the context thread; elsewhere the name is leaked
  // (the cache in Context keeps programs until shutdown, on the context thread).
  if (this->Handle && detail::OnContextThread())
  {
    glDeleteProgram(this->Handle);
  }
}

void Program::Use() const
{
  detail::RequireContextThread("terroir::gpu::Program::Use");
  glUseProgram(this->Handle);
}

int Program::Location(const char* name)
{
  auto it = this->Locations.find(name);
  if (it != this->Locations.end())
  {
    return it->second;
  }
  const int loc = glGetUniformLocation(this->Handle, name);
  this->Locations.emplace(name, loc);
  return loc;
}

void Program::SetInt(const char* name, int value)
{
  this->Use();
  glUniform1i(this->Location(name), value);
}

void Program::SetUInt(const char* name, unsigned value)
{
  this->Use();
  glUniform1ui(this->Location(name), value);
}

void Program::SetFloat(const char* name, float value)
{
  this->Use();
  glUniform1f(this->Location(name), value);
}

void Program::SetVec2(const char* name, float x, float y)
{
  this->Use();
  glUniform2f(this->Location(name), x, y);
}

void Program::SetVec3(const char* name, float x, float y, float z)
{
  this->Use();
  glUniform3f(this->Location(name), x, y, z);
}

void Program::SetVec4(const char* name, float x, float y, float z, float w)
{
  this->Use();
  glUniform4f(this->Location(name), x, y, z, w);
}

void Program::SetIVec2(const char* name, int x, int y)
{
  this->Use();
  glUniform2i(this->Location(name), x, y);
}

void Program::SetUVec2(const char* name, unsigned x, unsigned y)
{
  this->Use();
  glUniform2ui(this->Location(name), x, y);
}

void Program::SetFloatArray(const char* name, const float* values, int count)
{
  this->Use();
  if (count > 0 && values)
  {
    glUniform1fv(this->Location(name), count, values);
  }
}

void Program::SetIntArray(const char* name, const int* values, int count)
{
  this->Use();
  if (count > 0 && values)
  {
    glUniform1iv(this->Location(name), count, values);
  }
}

void Program::Dispatch(unsigned groupsX, unsigned groupsY, unsigned groupsZ)
{
  detail::RequireContextThread("terroir::gpu::Program::Dispatch");
  const Limits& lim = detail::ContextLimits();
  const unsigned groups[3] = { groupsX, groupsY, groupsZ };
  for (int i = 0; i < 3; ++i)
  {
    if (groups[i] > static_cast<unsigned>(lim.MaxWorkGroupCount[i]))
    {
      std::ostringstream msg;
      msg << this->ShaderName << ": Dispatch(" << groupsX << ", " << groupsY << ", " << groupsZ
          << ") exceeds GL_MAX_COMPUTE_WORK_GROUP_COUNT (" << lim.MaxWorkGroupCount[0] << ", "
          << lim.MaxWorkGroupCount[1] << ", " << lim.MaxWorkGroupCount[2] << ")";
      throw Error(msg.str());
    }
  }
  if (groupsX == 0 || groupsY == 0 || groupsZ == 0)
  {
    return;
  }
  detail::CheckDeadline(this->ShaderName.c_str());
  detail::Runtime& rt = detail::State();
  const bool profiling = rt.Profiling;
  if (profiling)
  {
    detail::WaitAll(this->ShaderName.c_str());
  }
  const auto t0 = detail::Clock::now();
  detail::ClearGLErrors();
  glUseProgram(this->Handle);
  // The whole grid, which TERROIR_NUM_WORKGROUPS reports, and the offset of each piece.
  if (this->GroupCountLocation >= 0)
  {
    glUniform3ui(this->GroupCountLocation, groupsX, groupsY, groupsZ);
  }
  GLuint query = 0;
  if (profiling)
  {
    glGenQueries(1, &query);
    glBeginQuery(GL_TIME_ELAPSED, query);
  }
  if ((rt.Split || rt.Shuffle) && this->GroupOffsetLocation >= 0)
  {
    // Stress modes: up to 4 x 4 x 4 pieces; shuffled, they run in a random order (llvmpipe
    // runs one dispatch at a time, so a kernel that needs one group to run before another, or
    // reads the groups' output within the dispatch, gives another answer).
    struct Piece
    {
      unsigned o[3];
      unsigned n[3];
    };
    std::vector<Piece> pieces;
    unsigned step[3];
    for (int d = 0; d < 3; ++d)
    {
      step[d] = std::max(1u, (groups[d] + 3) / 4);
    }
    for (unsigned z = 0; z < groupsZ; z += step[2])
    {
      for (unsigned y = 0; y < groupsY; y += step[1])
      {
        for (unsigned x = 0; x < groupsX; x += step[0])
        {
          Piece p{ { x, y, z },
            { std::min(step[0], groupsX - x),
              std::min(step[1], groupsY - y),
              std::min(step[2], groupsZ - z) } };
          pieces.push_back(p);
        }
      }
    }
    if (rt.Shuffle)
    {
      static std::mt19937_64 rng(20261126);
      for (std::size_t i = pieces.size(); i > 1; --i)
      {
        std::swap(pieces[i - 1], pieces[static_cast<std::size_t>(rng() % i)]);
      }
    }
    for (const Piece& p : pieces)
    {
      glUniform3ui(this->GroupOffsetLocation, p.o[0], p.o[1], p.o[2]);
      glDispatchCompute(p.n[0], p.n[1], p.n[2]);
    }
    glUniform3ui(this->GroupOffsetLocation, 0u, 0u, 0u);
  }
  else
  {
    if (this->GroupOffsetLocation >= 0)
    {
      glUniform3ui(this->GroupOffsetLocation, 0u, 0u, 0u);
    }
    glDispatchCompute(groupsX, groupsY, groupsZ);
  }
  if (profiling)
  {
    glEndQuery(GL_TIME_ELAPSED);
    rt.PendingQueries.push_back(query);
  }
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  detail::CheckGLError(this->ShaderName + ": glDispatchCompute");
  double seconds = 0.0;
  if (profiling)
  {
    detail::WaitAll(this->ShaderName.c_str());
    seconds = detail::Since(t0);
    detail::CollectQueries();
  }
  detail::Count(
    [seconds](Stats& c)
    {
      ++c.Dispatches;
      c.DispatchSeconds += seconds;
    });
  detail::RestoreHostFloatingPoint();
}

//------------------------------------------------------------------------------
GridPlan PlanGrid(const Limits& limits, std::size_t perItem, std::size_t local)
{
  GridPlan p;
  p.Local = std::max<std::size_t>(1, local);
  p.MaxX =
    limits.MaxWorkGroupCount[0] > 0 ? static_cast<std::size_t>(limits.MaxWorkGroupCount[0]) : 65535;
  p.MaxY =
    limits.MaxWorkGroupCount[1] > 0 ? static_cast<std::size_t>(limits.MaxWorkGroupCount[1]) : 65535;
  // Invocation indices are 32-bit in the kernels.
  const std::size_t invocations = std::min<std::size_t>(
    static_cast<std::size_t>(p.MaxX) * p.MaxY * p.Local, std::size_t(0xffffffffu) - p.Local);
  p.MaxItems = invocations / std::max<std::size_t>(1, perItem);
  return p;
}

std::vector<std::uint32_t> PackFlags(const std::uint8_t* flags, std::size_t n)
{
  std::vector<std::uint32_t> words(std::max<std::size_t>(1, (n + 3) / 4), 0u);
  for (std::size_t c = 0; c < n; ++c)
  {
    words[c / 4] |= static_cast<std::uint32_t>(flags[c] ? 1u : 0u) << (8 * (c % 4));
  }
  return words;
}

Groups GridPlan::For(std::size_t invocations) const
{
  const std::size_t groups = (invocations + this->Local - 1) / this->Local;
  Groups g;
  if (groups == 0)
  {
    g.x = 0;
    return g;
  }
  const std::size_t gx = std::min(groups, this->MaxX);
  const std::size_t gy = (groups + gx - 1) / gx;
  if (gy > this->MaxY)
  {
    throw Error("dispatch of " + std::to_string(invocations) + " invocations exceeds " +
      "GL_MAX_COMPUTE_WORK_GROUP_COUNT (" + std::to_string(this->MaxX) + " x " +
      std::to_string(this->MaxY) + " groups of " + std::to_string(this->Local) + ")");
  }
  g.x = static_cast<unsigned>(gx);
  g.y = static_cast<unsigned>(gy);
  return g;
}

//------------------------------------------------------------------------------
const char* Context::CopyKernelSource()
{
  static const char* const kCopy = R"(
layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Src { uint src[]; };
layout(std430, binding = 1) writeonly buffer Dst { uint dst[]; };
uniform uint uN;
void main()
{
  uint i = TERROIR_GLOBAL_ID.y * (TERROIR_NUM_WORKGROUPS.x * 256u) + TERROIR_GLOBAL_ID.x;
  if (i < uN)
  {
    dst[i] = src[i];
  }
}
)";
  return kCopy;
}

//------------------------------------------------------------------------------
double Context::MeasureCopyBandwidth(std::size_t bytes, int repeats)
{
  const char* const kCopy = CopyKernelSource();
  const std::size_t n = std::max<std::size_t>(1, bytes / 4);
  double best = 0.0;
  this->Run("copy bandwidth",
    Context::Budget(static_cast<double>(n) * (repeats + 1)),
    [&]
    {
      StorageBuffer a(n * 4, Contents::Zero);
      StorageBuffer b(n * 4, Contents::Undefined);
      auto& prog = this->GetProgram("TerroirCopy.comp", kCopy);
      prog.SetUInt("uN", static_cast<unsigned>(n));
      a.Bind(0);
      b.Bind(1);
      const unsigned groups = static_cast<unsigned>((n + 255) / 256);
      const unsigned gx = std::min(groups, 4096u);
      const unsigned gy = (groups + gx - 1) / gx;
      prog.Dispatch(gx, gy); // warm-up
      detail::WaitAll("copy bandwidth");
      GLuint query = 0;
      glGenQueries(1, &query);
      double seconds = 1e300;
      for (int r = 0; r < std::max(1, repeats); ++r)
      {
        // GL's timer when it measures compute work (llvmpipe's reads nanoseconds: then the
        // wall time of the dispatch to completion).
        const auto t0 = detail::Clock::now();
        glBeginQuery(GL_TIME_ELAPSED, query);
        prog.Dispatch(gx, gy);
        glEndQuery(GL_TIME_ELAPSED);
        detail::WaitAll("copy bandwidth");
        const double wall = detail::Since(t0);
        GLuint64 ns = 0;
        glGetQueryObjectui64v(query, GL_QUERY_RESULT, &ns);
        const double timer = static_cast<double>(ns) * 1e-9;
        seconds = std::min(seconds, timer > 0.1 * wall ? timer : wall);
      }
      glDeleteQueries(1, &query);
      best = 2.0 * static_cast<double>(n * 4) / seconds;
    });
  return best;
}

} // namespace gpu
} // namespace terroir

// terroir::gpu::Program: compute programs with the Terroir preamble and readable errors.
#include "vtkTerroirGPU.h"

#include "Private/vtkTerroirGPUPrivate.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
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
  detail::ClearGLErrors();
  glUseProgram(this->Handle);
  glDispatchCompute(groupsX, groupsY, groupsZ);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  detail::CheckGLError(this->ShaderName + ": glDispatchCompute");
}

} // namespace gpu
} // namespace terroir

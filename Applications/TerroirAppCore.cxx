// The GDAL-free part of TerroirApp.h: quiet VTK output, progress, updates, text files, the
// backend names (the GPU check program links this file alone; see TerroirApp.cxx for the rest).
#include "TerroirApp.h"

#include "vtkAlgorithm.h"
#include "vtkCallbackCommand.h"
#include "vtkCommand.h"
#include "vtkLogger.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkOutputWindow.h"

#include "vtkTerroirComputeContext.h"

#include "MemoryBudget.h"
#include "TerroirCommandLine.h"
#include "TerroirSafeOutput.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <unistd.h>
#include <vector>

namespace fs = std::filesystem;

namespace
{
// Each thread keeps its own last VTK error (terroir run writes on a second thread).
thread_local std::string LastError;
bool Verbose = false;

// Strips VTK's "ERROR: In <file>, line <n>\n<class> (0x...): " prefix down to the message.
std::string CleanVTKText(const char* text)
{
  std::string s = text ? text : "";
  const std::string marker = "): ";
  auto pos = s.find(marker);
  if (s.rfind("ERROR:", 0) == 0 || s.rfind("Warning:", 0) == 0 || s.rfind("WARNING:", 0) == 0)
  {
    if (pos != std::string::npos)
    {
      s = s.substr(pos + marker.size());
    }
  }
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back())))
  {
    s.pop_back();
  }
  std::replace(s.begin(), s.end(), '\n', ' ');
  return s;
}

class QuietOutputWindow : public vtkOutputWindow
{
public:
  static QuietOutputWindow* New();
  vtkTypeMacro(QuietOutputWindow, vtkOutputWindow);
  void DisplayText(const char* text) override
  {
    if (Verbose && text)
    {
      std::cerr << text;
    }
  }
  void DisplayErrorText(const char* text) override
  {
    // Keep the first error: the executive's "returned failure for request" follows the cause.
    const std::string clean = CleanVTKText(text);
    if (LastError.empty())
    {
      LastError = clean;
    }
    if (Verbose)
    {
      std::cerr << "terroir: vtk: " << clean << "\n";
    }
  }
  void DisplayWarningText(const char* text) override
  {
    std::cerr << "terroir: warning: " << CleanVTKText(text) << "\n";
  }
  void DisplayGenericWarningText(const char* text) override { this->DisplayWarningText(text); }
  void DisplayDebugText(const char* text) override { this->DisplayText(text); }
};
vtkStandardNewMacro(QuietOutputWindow);

struct ProgressState
{
  std::string Label;
  bool Terminal = false;
  int LastShown = -1;
};

void OnProgress(vtkObject* caller, unsigned long, void* clientData, void* callData)
{
  auto* state = static_cast<ProgressState*>(clientData);
  const double p = callData ? *static_cast<double*>(callData) : 0.0;
  const int percent = std::max(0, std::min(100, static_cast<int>(p * 100.0 + 0.5)));
  (void)caller;
  if (state->Terminal)
  {
    if (percent == state->LastShown)
    {
      return;
    }
    const int width = 30;
    const int filled = percent * width / 100;
    std::fprintf(stderr,
      "\r%-14s [%s%s] %3d%%",
      state->Label.c_str(),
      std::string(filled, '#').c_str(),
      std::string(width - filled, ' ').c_str(),
      percent);
    if (percent == 100)
    {
      std::fputc('\n', stderr);
    }
    std::fflush(stderr);
  }
  else
  {
    // Plain lines at 0, 25, 50, 75 and 100 %.
    const int step = percent / 25 * 25;
    if (step == state->LastShown)
    {
      return;
    }
    std::fprintf(stderr, "%s: %d%%\n", state->Label.c_str(), step);
    state->LastShown = step;
    return;
  }
  state->LastShown = percent;
}

void DeleteProgressState(void* clientData)
{
  delete static_cast<ProgressState*>(clientData);
}

} // namespace

namespace terroir
{
namespace app
{

namespace
{
std::mutex NotesMutex;
std::vector<std::string> Notes;
} // namespace

void AddNote(const std::string& text)
{
  std::lock_guard<std::mutex> lock(NotesMutex);
  if (std::find(Notes.begin(), Notes.end(), text) == Notes.end())
  {
    Notes.push_back(text);
  }
}

void FlushNotes()
{
  std::lock_guard<std::mutex> lock(NotesMutex);
  for (const std::string& note : Notes)
  {
    std::cerr << "terroir: note: " << note << "\n";
  }
  Notes.clear();
}

void InstallQuietOutput(bool verbose)
{
  Verbose = verbose;
  vtkNew<QuietOutputWindow> window;
  vtkOutputWindow::SetInstance(window);
  // VTK 9.1 also logs every error and warning through vtkLogger; the output window above
  // prints them as single clean lines, so the logger stays quiet unless asked.
  vtkLogger::SetStderrVerbosity(verbose ? vtkLogger::VERBOSITY_INFO : vtkLogger::VERBOSITY_OFF);
}

int StartCommandLine(int argc, const char* const* argv, CommandLine& line, const char* program)
{
  const ParseOutcome parsed = ParseCommandLine(argc, argv, line);
  if (!parsed.Run)
  {
    std::cout << parsed.Stdout;
    if (!parsed.Error.empty())
    {
      std::cerr << program << ": error: " << parsed.Error << "\n";
    }
    return parsed.ExitCode;
  }
  // A malformed TERROIR_MEMORY_LIMIT is the user's error, not the first reader's.
  MemoryAvailability memory;
  std::string memoryError;
  if (!AvailableMemory(memory, memoryError))
  {
    std::cerr << program << ": error: " << memoryError << "\n";
    return 2;
  }
  InstallQuietOutput(line.Verbose);
  // Interrupted or over `ulimit -f`: remove the temporaries, leave earlier results as they were.
  InstallSignalCleanup();
  return -1;
}

std::string TakeLastVTKError()
{
  std::string e;
  e.swap(LastError);
  return e;
}

void WatchProgress(vtkAlgorithm* algorithm, const std::string& label)
{
  vtkNew<vtkCallbackCommand> cb;
  auto* state = new ProgressState;
  state->Label = label;
  state->Terminal = ::isatty(STDERR_FILENO) != 0;
  cb->SetClientData(state);
  cb->SetClientDataDeleteCallback(DeleteProgressState);
  cb->SetCallback(OnProgress);
  algorithm->AddObserver(vtkCommand::ProgressEvent, cb);
}

void UpdateOrThrow(vtkAlgorithm* algorithm, const std::string& what)
{
  TakeLastVTKError();
  algorithm->Update();
  const std::string err = TakeLastVTKError();
  if (algorithm->GetErrorCode() != 0 || !err.empty())
  {
    throw Failure(err.empty() ? what + " failed" : err);
  }
}

bool HasExtension(const std::string& path, const std::string& ext)
{
  if (path.size() < ext.size())
  {
    return false;
  }
  return std::equal(ext.rbegin(),
    ext.rend(),
    path.rbegin(),
    [](char a, char b) { return std::tolower(a) == std::tolower(b); });
}

void CheckWritable(const std::vector<std::string>& paths, bool overwrite)
{
  for (const auto& p : paths)
  {
    std::error_code ec;
    if (!overwrite && fs::exists(p, ec))
    {
      throw Failure(p + ": exists; pass --overwrite to replace it");
    }
    const fs::path parent = fs::path(p).parent_path();
    if (!parent.empty() && !fs::is_directory(parent, ec))
    {
      throw Failure(parent.string() + ": output folder does not exist");
    }
  }
}

namespace
{
std::mutex WrittenFilesLock;
std::vector<WrittenFile>& WrittenFiles()
{
  static std::vector<WrittenFile> files;
  return files;
}
} // namespace

void RecordWrittenFile(const std::string& path, const char* kind, double seconds)
{
  std::lock_guard<std::mutex> lock(WrittenFilesLock);
  WrittenFiles().push_back(WrittenFile{ path, kind, seconds });
}

std::vector<WrittenFile> TakeWrittenFiles()
{
  std::lock_guard<std::mutex> lock(WrittenFilesLock);
  std::vector<WrittenFile> files;
  files.swap(WrittenFiles());
  return files;
}

void WriteTextFile(const std::string& path, const std::string& text, bool overwrite)
{
  const double t0 = Now();
  CheckWritable({ path }, overwrite);
  const std::string tmp = terroir::TemporaryNameFor(path);
  {
    std::ofstream f(tmp, std::ios::binary);
    f << text;
    f.flush();
    if (!f)
    {
      f.close();
      terroir::DiscardTemporary(tmp);
      throw Failure(path + ": could not be written (" + std::strerror(errno) + ")");
    }
  }
  std::string error;
  if (!terroir::CommitTemporary(tmp, path, error))
  {
    throw Failure(path + ": " + error);
  }
  RecordWrittenFile(path, "text", Now() - t0);
}

double Now()
{
  using clock = std::chrono::steady_clock;
  return std::chrono::duration<double>(clock::now().time_since_epoch()).count();
}

int ParseBackend(const std::string& name)
{
  if (name == "auto")
  {
    return vtkTerroirComputeContext::Auto;
  }
  if (name == "cpu")
  {
    return vtkTerroirComputeContext::CPU;
  }
  if (name == "gpu")
  {
    return vtkTerroirComputeContext::GPU;
  }
  throw Failure("--backend: '" + name + "' is not auto, cpu or gpu");
}

} // namespace app
} // namespace terroir

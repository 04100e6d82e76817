#include "TerroirSafeOutput.h"

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <sys/stat.h>
#include <unistd.h>
#include <utility>
#include <vector>

namespace terroir
{
namespace
{
// A fixed table, so that a signal handler can walk it without locks or allocation. A slot is
// free (0), being filled or emptied (1), or holds a name (2).
constexpr int kSlots = 256;
constexpr std::size_t kNameSize = 4096;
std::atomic<int> SlotState[kSlots];
char SlotName[kSlots][kNameSize];

void Register(const std::string& name)
{
  if (name.size() >= kNameSize)
  {
    return;
  }
  for (int s = 0; s < kSlots; ++s)
  {
    int expected = 0;
    if (SlotState[s].compare_exchange_strong(expected, 1))
    {
      std::memcpy(SlotName[s], name.c_str(), name.size() + 1);
      SlotState[s].store(2);
      return;
    }
  }
  // Table full: the file is still written safely, only not removed on a signal.
}

void Unregister(const std::string& name)
{
  for (int s = 0; s < kSlots; ++s)
  {
    int expected = 2;
    if (SlotState[s].load() == 2 && name == SlotName[s] &&
      SlotState[s].compare_exchange_strong(expected, 1))
    {
      SlotName[s][0] = '\0';
      SlotState[s].store(0);
      return;
    }
  }
}

/// The commits held by HoldCommits(): (temporary, target) in commit order.
struct HeldCommits
{
  std::mutex Lock;
  bool Holding = false;
  std::vector<std::pair<std::string, std::string>> Renames;
};
HeldCommits& Held()
{
  static HeldCommits held;
  return held;
}

bool Exists(const std::string& path)
{
  struct stat st;
  return ::lstat(path.c_str(), &st) == 0;
}

void OnTerminatingSignal(int signal)
{
  RemoveRegisteredTemporaries();
  // The default action (termination, with the usual exit status) runs once the handler returns.
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}
} // namespace

std::string TemporaryNameFor(const std::string& target)
{
  static std::atomic<unsigned> counter{ 0 };
  const std::size_t slash = target.find_last_of('/');
  const std::string dir = slash == std::string::npos ? "" : target.substr(0, slash + 1);
  const std::string base = slash == std::string::npos ? target : target.substr(slash + 1);
  const std::size_t dot = base.find_last_of('.');
  const std::string ext = dot == std::string::npos || dot == 0 ? "" : base.substr(dot);
  std::string name;
  do
  {
    name = dir + "." + base + ".tmp" + std::to_string(static_cast<long>(::getpid())) + "_" +
      std::to_string(counter++) + ext;
  } while (Exists(name));
  Register(name);
  return name;
}

bool CommitTemporary(const std::string& temporary, const std::string& target, std::string& error)
{
  {
    HeldCommits& held = Held();
    std::lock_guard<std::mutex> lock(held.Lock);
    if (held.Holding)
    {
      held.Renames.emplace_back(temporary, target);
      return true;
    }
  }
  if (std::rename(temporary.c_str(), target.c_str()) != 0)
  {
    error =
      std::string("cannot rename the temporary file into place (") + std::strerror(errno) + ")";
    DiscardTemporary(temporary);
    return false;
  }
  Unregister(temporary);
  return true;
}

void HoldCommits()
{
  HeldCommits& held = Held();
  std::lock_guard<std::mutex> lock(held.Lock);
  held.Holding = true;
}

bool ReleaseHeldCommits(std::string& error)
{
  std::vector<std::pair<std::string, std::string>> renames;
  {
    HeldCommits& held = Held();
    std::lock_guard<std::mutex> lock(held.Lock);
    renames.swap(held.Renames);
    held.Holding = false;
  }
  for (std::size_t k = 0; k < renames.size(); ++k)
  {
    std::string why;
    if (!CommitTemporary(renames[k].first, renames[k].second, why))
    {
      error = renames[k].second + ": " + why;
      for (std::size_t rest = k + 1; rest < renames.size(); ++rest)
      {
        DiscardTemporary(renames[rest].first);
      }
      return false;
    }
  }
  return true;
}

void DiscardHeldCommits()
{
  std::vector<std::pair<std::string, std::string>> renames;
  {
    HeldCommits& held = Held();
    std::lock_guard<std::mutex> lock(held.Lock);
    renames.swap(held.Renames);
    held.Holding = false;
  }
  for (const auto& r : renames)
  {
    DiscardTemporary(r.first);
  }
}

void DiscardTemporary(const std::string& temporary)
{
  ::unlink(temporary.c_str());
  Unregister(temporary);
}

void RemoveRegisteredTemporaries()
{
  for (int s = 0; s < kSlots; ++s)
  {
    if (SlotState[s].load() == 2)
    {
      ::unlink(SlotName[s]);
    }
  }
}

int RegisteredTemporaryCount()
{
  int n = 0;
  for (int s = 0; s < kSlots; ++s)
  {
    n += SlotState[s].load() == 2 ? 1 : 0;
  }
  return n;
}

void InstallSignalCleanup()
{
  for (int signal : { SIGINT, SIGTERM, SIGHUP, SIGQUIT })
  {
    struct sigaction action;
    std::memset(&action, 0, sizeof(action));
    action.sa_handler = &OnTerminatingSignal;
    sigemptyset(&action.sa_mask);
    sigaction(signal, &action, nullptr);
  }
  std::signal(SIGXFSZ, SIG_IGN);
}

} // namespace terroir

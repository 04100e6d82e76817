// A main() for the fuzz harnesses in builds without libFuzzer (gcc, or TERROIR_FUZZ off): runs
// LLVMFuzzerTestOneInput once on every file named on the command line, and on every file of
// every folder named there (the seed corpus and the saved crash inputs), then exits. Arguments
// starting with '-' (libFuzzer flags such as -runs=0) are ignored, so CTest can call both
// builds the same way. Exit status: 0 when every input ran, 1 when an input could not be read or
// there was none; a harness that finds a broken invariant aborts.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace
{
bool RunFile(const std::filesystem::path& path)
{
  std::ifstream in(path, std::ios::binary);
  if (!in)
  {
    std::fprintf(stderr, "%s: cannot be read\n", path.c_str());
    return false;
  }
  const std::vector<char> bytes(
    (std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // A copy of exactly the input's size, so AddressSanitizer sees reads past its end.
  std::vector<std::uint8_t> copy(bytes.begin(), bytes.end());
  LLVMFuzzerTestOneInput(copy.empty() ? nullptr : copy.data(), copy.size());
  return true;
}
} // namespace

int main(int argc, char** argv)
{
  int inputs = 0;
  bool ok = true;
  for (int a = 1; a < argc; ++a)
  {
    const std::string arg = argv[a];
    if (!arg.empty() && arg[0] == '-')
    {
      continue;
    }
    std::error_code ec;
    if (std::filesystem::is_directory(arg, ec))
    {
      std::vector<std::filesystem::path> files;
      for (const auto& entry : std::filesystem::directory_iterator(arg, ec))
      {
        if (entry.is_regular_file())
        {
          files.push_back(entry.path());
        }
      }
      std::sort(files.begin(), files.end());
      for (const auto& f : files)
      {
        ok = RunFile(f) && ok;
        ++inputs;
      }
    }
    else
    {
      ok = RunFile(arg) && ok;
      ++inputs;
    }
  }
  std::printf("%d inputs run\n", inputs);
  return ok && inputs > 0 ? 0 : 1;
}

// Safe outputs: every writer goes through a temporary file in the target folder renamed on
// success. A failure midway -- simulated with the file-size limit (RLIMIT_FSIZE, what
// `ulimit -f` sets: writes past it fail with EFBIG, as on a full disk) -- must leave neither a
// partial file nor a damaged earlier result; an existing file is kept unless Overwrite is on;
// and an interrupted program removes its temporaries.
#include "TerroirFilterTestUtilities.h"
#include "TerroirIOTestUtilities.h"
#include "TerroirSafeOutput.h"

#include "vtkPointData.h"
#include "vtkTerroirGeoTIFFWriter.h"
#include "vtkTerroirTerragenWriter.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <csignal>
#include <functional>
#include <string>
#include <sys/resource.h>
#include <vector>

namespace
{
using terroir::testing::ListFolder;
using terroir::testing::ReadWholeFile;

/// Lowers the file-size soft limit for one scope; SIGXFSZ is ignored meanwhile so that the
/// write fails with EFBIG instead of killing the test.
class ScopedFileSizeLimit
{
public:
  explicit ScopedFileSizeLimit(rlim_t bytes)
  {
    getrlimit(RLIMIT_FSIZE, &this->Old);
    this->OldHandler = std::signal(SIGXFSZ, SIG_IGN);
    struct rlimit lowered = this->Old;
    lowered.rlim_cur = bytes;
    this->Ok = setrlimit(RLIMIT_FSIZE, &lowered) == 0;
  }
  ~ScopedFileSizeLimit()
  {
    setrlimit(RLIMIT_FSIZE, &this->Old);
    std::signal(SIGXFSZ, this->OldHandler);
  }
  bool Ok = false;

private:
  struct rlimit Old;
  void (*OldHandler)(int) = nullptr;
};

vtkSmartPointer<vtkImageData> Terrain(int n)
{
  return terroir_test::MakeTerrain(
    n, n, 10.0, 10.0, [](int i, int j) { return 1000.0 + 0.37 * i - 0.11 * j; });
}

/// Writes `first` with a writer, then tries to replace it while the file-size limit is below
/// what the new file needs: the write must fail, the folder must hold the first file only,
/// byte for byte.
void ExpectFailedReplaceKeepsEarlierResult(const std::string& folder,
  const std::string& name,
  const std::function<int(vtkImageData*, const std::string&, std::string&)>& write)
{
  const std::string dir = terroir::testing::IOScratchFolder(folder);
  const std::string path = dir + "/" + name;
  std::string error;
  ASSERT_EQ(write(Terrain(16), path, error), 1) << error;
  const std::vector<char> before = ReadWholeFile(path);
  ASSERT_GT(before.size(), 0u);
  {
    ScopedFileSizeLimit limit(64 * 1024); // the 512 x 512 grid needs at least 512 KiB
    ASSERT_TRUE(limit.Ok);
    EXPECT_EQ(write(Terrain(512), path, error), 0);
  }
  EXPECT_EQ(error.rfind(path + ": ", 0), 0u) << error;
  EXPECT_EQ(error.find('\n'), std::string::npos) << error;
  EXPECT_EQ(ListFolder(dir), std::vector<std::string>{ name }) << "a temporary was left behind";
  EXPECT_EQ(ReadWholeFile(path), before) << "the earlier result was damaged";
  EXPECT_EQ(terroir::RegisteredTemporaryCount(), 0);
  // With room again the replacement succeeds.
  ASSERT_EQ(write(Terrain(512), path, error), 1) << error;
  EXPECT_GT(ReadWholeFile(path).size(), 512u * 1024u);
  EXPECT_EQ(ListFolder(dir), std::vector<std::string>{ name });
}
} // namespace

/// Writes `image` to `path` with a new `Writer` (Overwrite on); 1 on success, else 0 and `error`.
template<typename Writer>
int WriteWith(vtkImageData* image, const std::string& path, std::string& error)
{
  vtkNew<Writer> w;
  w->SetInputData(image);
  w->SetFileName(path.c_str());
  w->OverwriteOn();
  const int ok = w->Write();
  error = w->GetErrorMessage();
  return ok && error.empty() ? 1 : 0;
}

TEST(TerroirSafeOutputs, GeoTIFFWriterFailingMidwayKeepsEarlierResult)
{
  ExpectFailedReplaceKeepsEarlierResult("safe_tif", "dem.tif", &WriteWith<vtkTerroirGeoTIFFWriter>);
}

TEST(TerroirSafeOutputs, TerragenWriterFailingMidwayKeepsEarlierResult)
{
  ExpectFailedReplaceKeepsEarlierResult(
    "safe_ter", "dem.ter", &WriteWith<vtkTerroirTerragenWriter>);
}

TEST(TerroirSafeOutputs, WritersRefuseExistingFilesWithoutOverwrite)
{
  const std::string dir = terroir::testing::IOScratchFolder("safe_existing");
  for (const char* name : { "a.tif", "a.ter" })
  {
    const std::string path = dir + "/" + name;
    terroir::testing::WriteTextFile(path, "precious");
    vtkSmartPointer<vtkTerroirImageWriter> w;
    if (std::string(name) == "a.tif")
    {
      w = vtkSmartPointer<vtkTerroirGeoTIFFWriter>::New();
    }
    else
    {
      w = vtkSmartPointer<vtkTerroirTerragenWriter>::New();
    }
    w->SetInputData(Terrain(8));
    w->SetFileName(path.c_str());
    w->Write();
    EXPECT_EQ(
      std::string(w->GetErrorMessage()), path + ": file exists (turn Overwrite on to replace it)");
    const std::vector<char> bytes = ReadWholeFile(path);
    EXPECT_EQ(std::string(bytes.begin(), bytes.end()), "precious");
  }
  std::vector<std::string> names = ListFolder(dir);
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{ "a.ter", "a.tif" }));
}

TEST(TerroirSafeOutputs, WriterIntoMissingFolderFailsCleanly)
{
  const std::string dir = terroir::testing::IOScratchFolder("safe_missing");
  const std::string path = dir + "/no/such/folder/dem.tif";
  vtkNew<vtkTerroirGeoTIFFWriter> w;
  w->SetInputData(Terrain(8));
  w->SetFileName(path.c_str());
  w->Write();
  EXPECT_EQ(std::string(w->GetErrorMessage())
              .rfind(path + ": cannot create a GeoTIFF in folder '" + dir + "/no/such/folder'", 0),
    0u)
    << w->GetErrorMessage();
  EXPECT_TRUE(ListFolder(dir).empty());
}

TEST(TerroirSafeOutputs, TemporaryNamesAreHiddenBesideTheTargetAndRegistered)
{
  const std::string dir = terroir::testing::IOScratchFolder("safe_names");
  const int before = terroir::RegisteredTemporaryCount();
  const std::string a = terroir::TemporaryNameFor(dir + "/out.tif");
  const std::string b = terroir::TemporaryNameFor(dir + "/out.tif");
  EXPECT_NE(a, b);
  EXPECT_EQ(a.rfind(dir + "/.out.tif.tmp", 0), 0u) << a;
  EXPECT_EQ(a.substr(a.size() - 4), ".tif"); // GDAL picks drivers by extension
  EXPECT_EQ(terroir::RegisteredTemporaryCount(), before + 2);
  terroir::testing::WriteTextFile(a, "A");
  std::string error;
  ASSERT_TRUE(terroir::CommitTemporary(a, dir + "/out.tif", error)) << error;
  terroir::DiscardTemporary(b);
  EXPECT_EQ(terroir::RegisteredTemporaryCount(), before);
  EXPECT_EQ(ListFolder(dir), std::vector<std::string>{ "out.tif" });
}

TEST(TerroirSafeOutputsDeathTest, InterruptedProgramRemovesItsTemporaries)
{
  const std::string dir = terroir::testing::IOScratchFolder("safe_signal");
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
    {
      terroir::InstallSignalCleanup();
      const std::string t = terroir::TemporaryNameFor(dir + "/big.tif");
      terroir::testing::WriteTextFile(t, "half a file");
      std::raise(SIGTERM);
    },
    ::testing::KilledBySignal(SIGTERM),
    "");
  EXPECT_TRUE(ListFolder(dir).empty()) << "the temporary survived SIGTERM";
}

// A held job (terroir run): every commit waits for the end, then all files go into place in
// commit order; a failure discards them all, and an earlier result is kept as it was.
TEST(TerroirSafeOutputs, HeldCommitsGoIntoPlaceTogetherOrNotAtAll)
{
  const std::string dir = terroir::testing::IOScratchFolder("safe_held");
  const int before = terroir::RegisteredTemporaryCount();
  terroir::testing::WriteTextFile(dir + "/b.txt", "earlier");
  auto sortedFolder = [&dir]
  {
    std::vector<std::string> names = ListFolder(dir);
    std::sort(names.begin(), names.end());
    return names;
  };
  auto write = [&](const std::string& name, const std::string& text)
  {
    const std::string t = terroir::TemporaryNameFor(dir + "/" + name);
    terroir::testing::WriteTextFile(t, text);
    std::string error;
    EXPECT_TRUE(terroir::CommitTemporary(t, dir + "/" + name, error)) << error;
  };

  terroir::HoldCommits();
  write("a.txt", "A");
  write("b.txt", "B");
  // Nothing in place yet: the targets are as they were, the temporaries still registered.
  const std::vector<std::string> files = ListFolder(dir);
  EXPECT_EQ(std::count(files.begin(), files.end(), "a.txt"), 0);
  EXPECT_EQ(terroir::RegisteredTemporaryCount(), before + 2);
  const std::vector<char> earlier = ReadWholeFile(dir + "/b.txt");
  EXPECT_EQ(std::string(earlier.begin(), earlier.end()), "earlier");
  std::string error;
  ASSERT_TRUE(terroir::ReleaseHeldCommits(error)) << error;
  EXPECT_EQ(sortedFolder(), (std::vector<std::string>{ "a.txt", "b.txt" }));
  const std::vector<char> b = ReadWholeFile(dir + "/b.txt");
  EXPECT_EQ(std::string(b.begin(), b.end()), "B");
  EXPECT_EQ(terroir::RegisteredTemporaryCount(), before);

  // Discarded: no new file, no temporary, the earlier results untouched.
  terroir::HoldCommits();
  write("c.txt", "C");
  write("a.txt", "A2");
  terroir::DiscardHeldCommits();
  EXPECT_EQ(sortedFolder(), (std::vector<std::string>{ "a.txt", "b.txt" }));
  const std::vector<char> a = ReadWholeFile(dir + "/a.txt");
  EXPECT_EQ(std::string(a.begin(), a.end()), "A");
  EXPECT_EQ(terroir::RegisteredTemporaryCount(), before);

  // After the hold, commits rename at once again.
  write("d.txt", "D");
  EXPECT_EQ(sortedFolder(), (std::vector<std::string>{ "a.txt", "b.txt", "d.txt" }));
}

// terroir::CheckMemory and its parsers: sizes as TERROIR_MEMORY_LIMIT takes them, the
// MemAvailable line of /proc/meminfo, the exact refusal message, and the live measurement
// against MemTotal read independently.
#include "MemoryBudget.h"
#include "TerroirScopedEnvironment.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

namespace
{
/// TERROIR_MEMORY_LIMIT set (or unset, for null) for one scope.
struct ScopedLimit : terroir_test::ScopedEnvironment
{
  explicit ScopedLimit(const char* value)
    : ScopedEnvironment("TERROIR_MEMORY_LIMIT", value)
  {
  }
};
} // namespace

TEST(TerroirMemoryBudget, ParsesSizesInPowersOf1024)
{
  double b = 0;
  ASSERT_TRUE(terroir::ParseMemorySize("1000", b));
  EXPECT_EQ(b, 1000.0);
  ASSERT_TRUE(terroir::ParseMemorySize("512M", b));
  EXPECT_EQ(b, 512.0 * 1048576.0);
  ASSERT_TRUE(terroir::ParseMemorySize("512MiB", b));
  EXPECT_EQ(b, 536870912.0);
  ASSERT_TRUE(terroir::ParseMemorySize("1.5G", b));
  EXPECT_EQ(b, 1610612736.0);
  ASSERT_TRUE(terroir::ParseMemorySize(" 2 gb", b));
  EXPECT_EQ(b, 2147483648.0);
  ASSERT_TRUE(terroir::ParseMemorySize("64k", b));
  EXPECT_EQ(b, 65536.0);
  ASSERT_TRUE(terroir::ParseMemorySize("1T", b));
  EXPECT_EQ(b, 1099511627776.0);
  for (const char* bad : { "", "abc", "-1G", "12Q", "1.5 GiBs", "nan", "inf", "0x10", "G" })
  {
    EXPECT_FALSE(terroir::ParseMemorySize(bad, b)) << bad;
  }
}

TEST(TerroirMemoryBudget, ReadsMemAvailableInKilobytes)
{
  const std::string meminfo = "MemTotal:       24609184 kB\n"
                              "MemFree:        21000000 kB\n"
                              "MemAvailable:   23000000 kB\n"
                              "Buffers:           12345 kB\n";
  double b = 0;
  ASSERT_TRUE(terroir::ParseMemAvailable(meminfo, b));
  EXPECT_EQ(b, 23000000.0 * 1024.0);
  EXPECT_FALSE(terroir::ParseMemAvailable("MemTotal: 1 kB\n", b));
}

TEST(TerroirMemoryBudget, FormatsBytes)
{
  EXPECT_EQ(terroir::FormatBytes(512), "512 B");
  EXPECT_EQ(terroir::FormatBytes(1536), "1.5 KiB");
  EXPECT_EQ(terroir::FormatBytes(340.0 * 1048576.0), "340 MiB");
  EXPECT_EQ(terroir::FormatBytes(3.25 * 1073741824.0), "3.2 GiB");
}

TEST(TerroirMemoryBudget, RefusesWithNeededAndAvailable)
{
  ScopedLimit limit("1M");
  EXPECT_EQ(terroir::CheckMemory(2.0 * 1048576.0, "vtkTerroirSlope"),
    "not enough memory for vtkTerroirSlope: needs 2.0 MiB, 1.0 MiB available "
    "(TERROIR_MEMORY_LIMIT)");
  EXPECT_EQ(terroir::CheckMemory(1048576.0, "vtkTerroirSlope"), "");
}

TEST(TerroirMemoryBudget, LimitOffSkipsTheCheckAndGarbageIsAnError)
{
  {
    ScopedLimit limit("off");
    EXPECT_EQ(terroir::CheckMemory(1e30, "x"), "");
  }
  ScopedLimit limit("lots");
  EXPECT_EQ(terroir::CheckMemory(1.0, "x"),
    "TERROIR_MEMORY_LIMIT: 'lots' is not a size (examples: 512M, 2G, off)");
}

TEST(TerroirMemoryBudget, MeasuresNoMoreThanTheMachineHas)
{
  ScopedLimit limit(nullptr);
  terroir::MemoryAvailability a;
  std::string error;
  ASSERT_TRUE(terroir::AvailableMemory(a, error)) << error;
  std::ifstream in("/proc/meminfo");
  if (!in)
  {
    GTEST_SKIP() << "no /proc/meminfo";
  }
  std::string line;
  double totalKb = 0;
  while (std::getline(in, line))
  {
    if (line.rfind("MemTotal:", 0) == 0)
    {
      totalKb = std::strtod(line.c_str() + 9, nullptr);
    }
  }
  ASSERT_GT(totalKb, 0);
  EXPECT_TRUE(a.limited);
  EXPECT_GT(a.bytes, 0.0);
  EXPECT_LE(a.bytes, totalKb * 1024.0);
  EXPECT_FALSE(a.source.empty());
  // A request for twice the machine's memory is refused, naming what was measured.
  const std::string refusal = terroir::CheckMemory(2.0 * totalKb * 1024.0, "a test");
  EXPECT_EQ(refusal.rfind("not enough memory for a test: needs ", 0), 0u) << refusal;
  EXPECT_NE(refusal.find(a.source), std::string::npos) << refusal;
}

// The image comparison (TerroirImageCompare.h) rejects visibly wrong pictures: every baseline in
// Testing/Baselines passes against itself and fails when perturbed in memory the ways VTK 9.1's
// legacy metric let through (30 % darker, +100 red, green x 0.6, +90 on every channel) and the
// ways it caught (an inverted 10 x 10 block, the centre mirrored). Also the rule by hand: a
// one-pixel shift and 8 levels pass, 9 levels on 17 pixels fail, a thin line that disappears
// fails. No rendering: runs without a display.
#include "TerroirImageCompare.h"

#include "vtkNew.h"
#include "vtkPNGReader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace
{
using terroir::testing::CompareRGB;
using terroir::testing::ImageTolerance;

struct Image
{
  int w = 0;
  int h = 0;
  std::vector<unsigned char> rgb;
  unsigned char& At(int x, int y, int c)
  {
    return rgb[(static_cast<std::size_t>(y) * w + x) * 3 + c];
  }
};

unsigned char Clamp(double v)
{
  return static_cast<unsigned char>(std::min(255.0, std::max(0.0, std::round(v))));
}
} // namespace

TEST(TerroirImageComparison, RuleByHand)
{
  // A 40 x 30 grey image with a vertical black line at x = 20.
  Image a;
  a.w = 40;
  a.h = 30;
  a.rgb.assign(40 * 30 * 3, 128);
  for (int y = 0; y < 30; ++y)
  {
    for (int c = 0; c < 3; ++c)
    {
      a.At(20, y, c) = 0;
    }
  }
  const ImageTolerance t;
  EXPECT_TRUE(CompareRGB(a.rgb, a.rgb, a.w, a.h, t).Passed(t));
  Image shifted = a; // the line one pixel to the right: edges may move by one pixel
  for (int y = 0; y < 30; ++y)
  {
    for (int c = 0; c < 3; ++c)
    {
      shifted.At(20, y, c) = 128;
      shifted.At(21, y, c) = 0;
    }
  }
  EXPECT_TRUE(CompareRGB(shifted.rgb, a.rgb, a.w, a.h, t).Passed(t));
  Image within = a; // every channel 8 levels up: passes
  for (auto& v : within.rgb)
  {
    v = static_cast<unsigned char>(v + 8);
  }
  const auto c8 = CompareRGB(within.rgb, a.rgb, a.w, a.h, t);
  EXPECT_TRUE(c8.Passed(t)) << c8.Describe(t);
  EXPECT_EQ(c8.worst, 8);
  Image patch = a; // 17 pixels 9 levels off (a block far from the line): fails; 16 pass
  for (int k = 0; k < 17; ++k)
  {
    patch.At(2 + k % 5, 2 + k / 5, 1) = 128 + 9;
  }
  const auto c17 = CompareRGB(patch.rgb, a.rgb, a.w, a.h, t);
  EXPECT_FALSE(c17.Passed(t)) << c17.Describe(t);
  EXPECT_EQ(c17.differing, 17);
  patch.At(2 + 16 % 5, 2 + 16 / 5, 1) = 128;
  EXPECT_TRUE(CompareRGB(patch.rgb, a.rgb, a.w, a.h, t).Passed(t));
  Image gone = a; // the line disappears: every test pixel has a grey neighbour in the baseline,
  for (int y = 0; y < 30; ++y) // but the baseline's line pixels have none in the test image
  {
    for (int c = 0; c < 3; ++c)
    {
      gone.At(20, y, c) = 128;
    }
  }
  const auto cg = CompareRGB(gone.rgb, a.rgb, a.w, a.h, t);
  EXPECT_FALSE(cg.Passed(t));
  EXPECT_EQ(cg.differing, 30);
  EXPECT_FALSE(CompareRGB(a.rgb, std::vector<unsigned char>(10, 0), a.w, a.h, t).sameSize);
}

TEST(TerroirImageComparison, EveryBaselineRejectsItsPerturbations)
{
  const std::filesystem::path dir(TERROIR_BASELINE_DIR);
  const std::vector<std::pair<std::string, std::function<void(Image&)>>> perturbations = {
    { "30 % darker",
      [](Image& m)
      {
        for (auto& v : m.rgb)
        {
          v = Clamp(0.7 * v);
        }
      } },
    { "+100 red",
      [](Image& m)
      {
        for (std::size_t p = 0; p < m.rgb.size(); p += 3)
        {
          m.rgb[p] = Clamp(m.rgb[p] + 100.0);
        }
      } },
    { "green x 0.6",
      [](Image& m)
      {
        for (std::size_t p = 1; p < m.rgb.size(); p += 3)
        {
          m.rgb[p] = Clamp(0.6 * m.rgb[p]);
        }
      } },
    { "+90 on every channel",
      [](Image& m)
      {
        for (auto& v : m.rgb)
        {
          v = Clamp(v + 90.0);
        }
      } },
    { "inverted 10 x 10 block at the centre",
      [](Image& m)
      {
        for (int y = m.h / 2 - 5; y < m.h / 2 + 5; ++y)
        {
          for (int x = m.w / 2 - 5; x < m.w / 2 + 5; ++x)
          {
            for (int c = 0; c < 3; ++c)
            {
              m.At(x, y, c) = static_cast<unsigned char>(255 - m.At(x, y, c));
            }
          }
        }
      } },
    { "centre mirrored left-right",
      [](Image& m)
      {
        const Image copy = m;
        for (int y = m.h / 4; y < 3 * m.h / 4; ++y)
        {
          for (int x = m.w / 4; x < 3 * m.w / 4; ++x)
          {
            for (int c = 0; c < 3; ++c)
            {
              m.At(x, y, c) = copy.rgb[(static_cast<std::size_t>(y) * m.w + (m.w - 1 - x)) * 3 + c];
            }
          }
        }
      } },
  };
  const ImageTolerance t;
  int baselines = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
  {
    if (entry.path().extension() != ".png")
    {
      continue;
    }
    ++baselines;
    vtkNew<vtkPNGReader> reader;
    reader->SetFileName(entry.path().string().c_str());
    reader->Update();
    Image base;
    base.rgb = terroir::testing::RGBOf(reader->GetOutput(), base.w, base.h);
    ASSERT_GT(base.w, 20) << entry.path();
    const std::string name = entry.path().filename().string();
    EXPECT_TRUE(CompareRGB(base.rgb, base.rgb, base.w, base.h, t).Passed(t)) << name;
    for (const auto& perturbation : perturbations)
    {
      Image changed = base;
      perturbation.second(changed);
      const auto r = CompareRGB(changed.rgb, base.rgb, base.w, base.h, t);
      EXPECT_FALSE(r.Passed(t)) << name << ", " << perturbation.first << ": " << r.Describe(t);
    }
  }
  EXPECT_GE(baselines, 22); // Testing/Baselines holds 22 images today; none may go unchecked
}

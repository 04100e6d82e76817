// Image regression test of terrain texturing (issue 27; label rendering, run under xvfb-run -a):
// vtkTerroirOverlayView with Texturing on (Jensen's (2011) triangle tiles, Rendering/Core/
// TriangleTexturing.h) at 400 x 400 against Testing/Baselines/TerroirTexturingImages_<Test>.png
// (TerroirImageCompare.h), plus checks that do not depend on a baseline: the materials where
// the rules put them, the texture's size, determinism and the untextured picture unchanged.
#include "TerroirRenderingTestHelpers.h"

#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkTerroirOverlayView.h"
#include "vtkUnsignedCharArray.h"

#include <gtest/gtest.h>

#include <cmath>

using terroir::testing::CompareWithBaseline;
using terroir::testing::PixelAt;

namespace
{
/// An island of n x n points, `d` metres apart (1270 m across for n = 128, d = 10): a Gaussian peak
/// 650 m high (sigma 220 m) on a cone that falls 6 cm per metre from 25 m at the centre, so that
/// the corners lie below the sea (0 m). Zones (`ClusterId`) 0, 1, 2 in the west, middle and east
/// thirds.
vtkSmartPointer<vtkImageData> MakeIsland(int n, double d = 10.0)
{
  auto terrain = vtkSmartPointer<vtkImageData>::New();
  terrain->SetDimensions(n, n, 1);
  terrain->SetSpacing(d, d, 1.0);
  vtkNew<vtkFloatArray> z;
  z->SetName("Elevation");
  vtkNew<vtkIntArray> zone;
  zone->SetName("ClusterId");
  const double c = 0.5 * d * (n - 1);
  for (int j = 0; j < n; ++j)
  {
    for (int i = 0; i < n; ++i)
    {
      const double r = std::hypot(d * i - c, d * j - c);
      z->InsertNextValue(
        static_cast<float>(650.0 * std::exp(-r * r / (2.0 * 220.0 * 220.0)) + 25.0 - 0.06 * r));
      zone->InsertNextValue(3 * i / n);
    }
  }
  terrain->GetPointData()->AddArray(z);
  terrain->GetPointData()->AddArray(zone);
  return terrain;
}

/// Mean RGB over the 9 x 9 pixels around (x, y).
void MeanRGB(vtkImageData* image, int x, int y, double rgb[3])
{
  rgb[0] = rgb[1] = rgb[2] = 0.0;
  for (int dy = -4; dy <= 4; ++dy)
  {
    for (int dx = -4; dx <= 4; ++dx)
    {
      unsigned char p[3];
      PixelAt(image, x + dx, y + dy, p);
      for (int c = 0; c < 3; ++c)
      {
        rgb[c] += p[c] / 81.0;
      }
    }
  }
}

std::vector<unsigned char> Bytes(vtkImageData* image)
{
  auto* a = vtkUnsignedCharArray::SafeDownCast(image->GetPointData()->GetScalars());
  return a ? std::vector<unsigned char>(a->GetPointer(0), a->GetPointer(0) + a->GetDataSize())
           : std::vector<unsigned char>();
}
} // namespace

// The island (33 x 33 points, 39.7 m apart) in relief, lit from the south-east, textured (16
// texels per cell, seed 1): snow on the peak (above 85 % of
// the elevation range), grey rock on its steep flanks, a sand shore towards the corners, and
// the lowlands grass (west), forest floor (middle) and dry soil (east) by zone.
TEST(TerroirTexturingImages, TexturedIslandRelief)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  auto terrain = MakeIsland(33, 1270.0 / 32);
  vtkNew<vtkTerroirOverlayView> view;
  view->SetInputData(terrain);
  view->TexturingOn();
  view->SetModeToRelief();
  view->SetLightAzimuth(135.0); // from the south-east, the side the relief camera sees
  CompareWithBaseline(view);
  // 32 cells at 16 texels per tile: 32 x 16 + 1 = 513 texels, a tile per cell.
  EXPECT_EQ(view->GetLastTextureSize()[0], 513);
  EXPECT_EQ(view->GetLastTextureSize()[1], 513);
  EXPECT_EQ(view->GetLastCellsPerTile(), 1);
}

// The same island seen from above (map, no legend: the terrain fills the 400 x 400 frame,
// 400 / 127 pixels per cell). The materials show where the rules put them: the peak (centre)
// is snow, nearly white and grey-neutral; the corner (below the sea) is sand, yellow (red well
// above blue); the western lowland (zone 0, grass) is green; the eastern one (zone 2, dry soil)
// brown (red above green above blue). Then: the same seed gives the same picture, another
// seed another one, and turning texturing off again gives exactly the untextured picture.
TEST(TerroirTexturingImages, MaterialsWhereTheRulesPutThem)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  auto terrain = MakeIsland(128);
  vtkNew<vtkTerroirOverlayView> view;
  view->SetInputData(terrain);
  view->SetWidth(400);
  view->SetHeight(400);
  view->ShowLegendOff();
  vtkNew<vtkImageData> plain;
  ASSERT_TRUE(view->GetImage(plain)) << view->GetLastError();
  view->TexturingOn();
  vtkNew<vtkImageData> textured;
  ASSERT_TRUE(view->GetImage(textured)) << view->GetLastError();
  double rgb[3];
  MeanRGB(textured, 200, 200, rgb); // the peak
  EXPECT_GT(rgb[2], 150.0);
  EXPECT_LT(std::abs(rgb[0] - rgb[2]), 25.0);
  MeanRGB(textured, 12, 12, rgb); // south-west corner, below the sea
  EXPECT_GT(rgb[0], rgb[2] + 40.0);
  MeanRGB(textured, 20, 200, rgb); // west lowland, zone 0: grass
  EXPECT_GT(rgb[1], rgb[0] + 10.0);
  EXPECT_GT(rgb[1], rgb[2] + 30.0);
  MeanRGB(textured, 380, 200, rgb); // east lowland, zone 2: dry soil
  EXPECT_GT(rgb[0], rgb[1] + 10.0);
  EXPECT_GT(rgb[1], rgb[2] + 10.0);

  vtkNew<vtkImageData> again;
  ASSERT_TRUE(view->GetImage(again));
  EXPECT_TRUE(Bytes(again) == Bytes(textured)) << "same seed, another picture";
  view->SetTextureSeed(2);
  vtkNew<vtkImageData> otherSeed;
  ASSERT_TRUE(view->GetImage(otherSeed));
  EXPECT_TRUE(Bytes(otherSeed) != Bytes(textured)) << "another seed, the same picture";
  view->TexturingOff();
  vtkNew<vtkImageData> plainAgain;
  ASSERT_TRUE(view->GetImage(plainAgain));
  EXPECT_TRUE(Bytes(plainAgain) == Bytes(plain)) << "texturing off differs from never on";
  EXPECT_TRUE(Bytes(plain) != Bytes(textured)) << "texturing changed nothing";
}

// A grid too big for a tile per cell: 600 x 600 points with 16 texels per tile and textures of
// at most 1024 texels make 63 tiles fit across ((1024 - 1) / 16), so a tile covers
// k = ceil(599 / 63) = 10 cells: 60 tiles, 60 x 16 + 1 = 961 texels.
TEST(TerroirTexturingImages, BigGridSharesTiles)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  auto terrain = MakeIsland(600);
  vtkNew<vtkTerroirOverlayView> view;
  view->SetInputData(terrain);
  view->SetWidth(200);
  view->SetHeight(200);
  view->TexturingOn();
  view->SetMaxTextureSize(1024);
  vtkNew<vtkImageData> image;
  ASSERT_TRUE(view->GetImage(image)) << view->GetLastError();
  EXPECT_EQ(view->GetLastCellsPerTile(), 10);
  EXPECT_EQ(view->GetLastTextureSize()[0], 961);
  EXPECT_EQ(view->GetLastTextureSize()[1], 961);
}

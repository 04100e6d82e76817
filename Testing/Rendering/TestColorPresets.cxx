// Colour presets: end points, middles and special colours worked out from the preset definitions
// in Documentation/Rendering.md (no display needed).
#include "vtkLookupTable.h"
#include "vtkSmartPointer.h"
#include "vtkTerroirColorPresets.h"
#include "vtkVariant.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>
#include <string>

namespace
{
vtkSmartPointer<vtkLookupTable> Make(const char* preset, double lo, double hi)
{
  return vtkSmartPointer<vtkLookupTable>::Take(
    vtkTerroirColorPresets::CreateLookupTable(preset, lo, hi));
}

void ExpectRGBA(vtkLookupTable* lut, double value, int r, int g, int b, int a, int tol = 0)
{
  const unsigned char* c = lut->MapValue(value);
  EXPECT_NEAR(c[0], r, tol) << "value " << value;
  EXPECT_NEAR(c[1], g, tol) << "value " << value;
  EXPECT_NEAR(c[2], b, tol) << "value " << value;
  EXPECT_NEAR(c[3], a, tol) << "value " << value;
}
}

TEST(TerroirColorPresets, SlopeIsBlackAtZeroAndWhiteAtSixtyDegrees)
{
  auto lut =
    vtkSmartPointer<vtkLookupTable>::Take(vtkTerroirColorPresets::CreateLookupTable("Slope"));
  ASSERT_NE(lut.Get(), nullptr);
  double range[2];
  ASSERT_TRUE(vtkTerroirColorPresets::GetDefaultRange("Slope", range));
  EXPECT_EQ(range[0], 0.0);
  EXPECT_EQ(range[1], 60.0);
  ExpectRGBA(lut, 0.0, 0, 0, 0, 255);
  ExpectRGBA(lut, 60.0, 255, 255, 255, 255);
  ExpectRGBA(lut, 30.0, 128, 128, 128, 255, 1); // linear grey ramp: half way is mid grey
  ExpectRGBA(lut, 85.0, 255, 255, 255, 255);    // steeper than the range clamps to white
  ExpectRGBA(lut, -5.0, 0, 0, 0, 255);
}

TEST(TerroirColorPresets, IlluminationIsBlackToWhiteAndHumidityBlackToBlue)
{
  auto ill = Make("Illumination", 0.0, 12.0);
  ExpectRGBA(ill, 0.0, 0, 0, 0, 255);
  ExpectRGBA(ill, 12.0, 255, 255, 255, 255);
  auto hum = Make("Humidity", 0.0, 50.0);
  ExpectRGBA(hum, 0.0, 0, 0, 0, 255);
  const unsigned char* wet = hum->MapValue(50.0);
  EXPECT_EQ(wet[0], 0);
  EXPECT_GT(wet[2], 250);
  EXPECT_GT(wet[2], wet[1]);
}

TEST(TerroirColorPresets, TemperatureIsBlueColdWhiteAtZeroRedWarm)
{
  // Range -10..30 °C: 0 °C lies at a quarter of the range and must be the white point.
  auto lut = Make("Temperature", -10.0, 30.0);
  ExpectRGBA(lut, -10.0, 59, 76, 192, 255, 1); // cool-warm blue (0.230, 0.299, 0.754)
  ExpectRGBA(lut, 30.0, 180, 4, 38, 255, 1);   // cool-warm red (0.706, 0.016, 0.150)
  ExpectRGBA(lut, 0.0, 221, 221, 221, 255, 6); // white point (0.865) within one of 256 bins
  // A range that does not contain 0 °C puts the white point in its middle.
  auto july = Make("Temperature", 10.0, 20.0);
  ExpectRGBA(july, 15.0, 221, 221, 221, 255, 6);
  const unsigned char* warm = july->MapValue(19.0);
  EXPECT_GT(warm[0], warm[2]);
  const unsigned char* cold = july->MapValue(11.0);
  EXPECT_GT(cold[2], cold[0]);
}

// Erosion: brown (0.549, 0.318, 0.039) for the most material lost, blue-green (0.004, 0.400,
// 0.369) for the most gained, near-white (0.961) at 0 m wherever 0 lies in the range.
TEST(TerroirColorPresets, ErosionIsBrownWhereLostWhiteAtZeroGreenWhereGained)
{
  auto lut = Make("Erosion", -3.0, 1.0);
  ExpectRGBA(lut, -3.0, 140, 81, 10, 255, 1);
  ExpectRGBA(lut, 1.0, 1, 102, 94, 255, 1);
  ExpectRGBA(lut, 0.0, 245, 245, 245, 255, 6);
  EXPECT_STREQ(vtkTerroirColorPresets::GetPresetForArray("ErosionDepth"), "Erosion");
  EXPECT_FALSE(vtkTerroirColorPresets::IsCategorical("Erosion"));
}

// Vegetation: pale sand (0.929, 0.871, 0.702) for bare ground, olive (0.553, 0.702, 0.298) at
// half cover, dark green (0.051, 0.353, 0.102) at full cover, on 0..1 by default.
TEST(TerroirColorPresets, VegetationGoesFromSandToDarkGreen)
{
  auto lut = Make("Vegetation", 0.0, 1.0);
  ExpectRGBA(lut, 0.0, 237, 222, 179, 255, 1);
  ExpectRGBA(lut, 0.5, 141, 179, 76, 255, 2);
  ExpectRGBA(lut, 1.0, 13, 90, 26, 255, 1);
  double range[2] = { -1.0, -1.0 };
  EXPECT_TRUE(vtkTerroirColorPresets::GetDefaultRange("Vegetation", range));
  EXPECT_EQ(range[0], 0.0);
  EXPECT_EQ(range[1], 1.0);
  EXPECT_STREQ(vtkTerroirColorPresets::GetPresetForArray("VegetationDensity"), "Vegetation");
  EXPECT_FALSE(vtkTerroirColorPresets::IsCategorical("Vegetation"));
}

TEST(TerroirColorPresets, ElevationGoesFromGreenToWhite)
{
  auto lut = Make("Elevation", 1900.0, 2700.0);
  const unsigned char* low = lut->MapValue(1900.0);
  EXPECT_GT(low[1], low[0]); // green dominates at the bottom
  EXPECT_GT(low[1], low[2] - 1);
  ExpectRGBA(lut, 2700.0, 255, 255, 255, 255);
}

TEST(TerroirColorPresets, WaterIsTransparentWhenDryAndDarkerWhenDeeper)
{
  auto lut = Make("Water", 0.0, 2.0);
  EXPECT_EQ(lut->MapValue(0.0)[3], 0);   // dry: fully transparent
  EXPECT_EQ(lut->MapValue(0.005)[3], 0); // below range/256 = 7.8 mm: still dry
  EXPECT_EQ(lut->MapValue(0.1)[3], 255);
  ExpectRGBA(lut, 2.0, 0, 31, 128, 255, 1); // deepest: dark blue (0, 0.12, 0.5)
  const unsigned char* shallow = lut->MapValue(0.1);
  const unsigned char* deep = lut->MapValue(1.5);
  EXPECT_GT(shallow[0] + shallow[1] + shallow[2], deep[0] + deep[1] + deep[2]);
  EXPECT_GT(deep[2], deep[0]);
}

TEST(TerroirColorPresets, WaterBodiesAreOpaqueEvenAtDepthZero)
{
  // A hydro-flattened lake has depth 0 everywhere: it must still be blue, not transparent.
  auto lut = Make("WaterBodies", 0.0, 2.0);
  ExpectRGBA(lut, 0.0, 179, 217, 255, 255, 1); // light blue (0.7, 0.85, 1)
  ExpectRGBA(lut, 2.0, 0, 31, 128, 255, 1);    // deepest: dark blue (0, 0.12, 0.5)
}

TEST(TerroirColorPresets, ClustersAreCategoricalDistinctAndInFixedOrder)
{
  auto lut = Make("Clusters", 0.0, 11.0);
  ASSERT_NE(lut.Get(), nullptr);
  EXPECT_TRUE(vtkTerroirColorPresets::IsCategorical("Clusters"));
  EXPECT_EQ(lut->GetIndexedLookup(), 1);
  EXPECT_EQ(lut->GetNumberOfAnnotatedValues(), 12);
  EXPECT_EQ(std::string(lut->GetAnnotation(3)), "Cluster 3");
  ExpectRGBA(lut, 0.0, 31, 119, 180, 255, 1); // Tableau blue first
  ExpectRGBA(lut, 1.0, 255, 127, 14, 255, 1); // then orange
  std::set<long> colours;
  for (int id = 0; id < 12; ++id)
  {
    const unsigned char* c = lut->MapValue(id);
    colours.insert((long(c[0]) << 16) | (long(c[1]) << 8) | c[2]);
  }
  EXPECT_EQ(colours.size(), 12u);
  // Same input, same colours (deterministic), and the palette cycles after 12 ids.
  auto again = Make("Clusters", 0.0, 13.0);
  for (int id = 0; id < 12; ++id)
  {
    const unsigned char* a = lut->MapValue(id);
    const unsigned char* b = again->MapValue(id);
    EXPECT_TRUE(a[0] == b[0] && a[1] == b[1] && a[2] == b[2]) << "cluster " << id;
  }
  const unsigned char* c12 = again->MapValue(12);
  ExpectRGBA(again, 0.0, c12[0], c12[1], c12[2], 255);
}

TEST(TerroirColorPresets, SunlitIsBlackInShadowWhiteWhereLit)
{
  // Illuminated is 0 (shadow) or 1 (lit): two fixed classes, whatever the range asked for.
  EXPECT_STREQ(vtkTerroirColorPresets::GetPresetForArray("Illuminated"), "Sunlit");
  EXPECT_TRUE(vtkTerroirColorPresets::IsCategorical("Sunlit"));
  double range[2];
  ASSERT_TRUE(vtkTerroirColorPresets::GetDefaultRange("Sunlit", range));
  EXPECT_EQ(range[0], 0.0);
  EXPECT_EQ(range[1], 1.0);
  for (const auto& lut :
    { vtkSmartPointer<vtkLookupTable>::Take(vtkTerroirColorPresets::CreateLookupTable("Sunlit")),
      Make("Sunlit", 0.0, 0.0),
      Make("Sunlit", 3.0, 7.0) })
  {
    ASSERT_NE(lut.Get(), nullptr);
    EXPECT_EQ(lut->GetIndexedLookup(), 1);
    ASSERT_EQ(lut->GetNumberOfAnnotatedValues(), 2);
    EXPECT_EQ(std::string(lut->GetAnnotation(0)), "shadow");
    EXPECT_EQ(std::string(lut->GetAnnotation(1)), "lit");
    ExpectRGBA(lut, 0.0, 0, 0, 0, 255);
    ExpectRGBA(lut, 1.0, 255, 255, 255, 255);
    // The filter's float32 values map to the same classes; anything else is not a class.
    ExpectRGBA(lut, static_cast<double>(1.0f), 255, 255, 255, 255);
    ExpectRGBA(lut, 0.5, 128, 128, 128, 255, 1);
    ExpectRGBA(lut, std::numeric_limits<double>::quiet_NaN(), 128, 128, 128, 255, 1);
  }
  EXPECT_EQ(vtkTerroirColorPresets::GetLegendTitle("Sunlit"), "Direct sun");
}

TEST(TerroirColorPresets, RiverComparisonHasThreeColourBlindSafeClasses)
{
  // Classes 1 map only, 2 model only (simulated), 3 both (RiverComparisonCategories), whatever the
  // range asked for; 0 is no class and is left uncoloured through the mask array.
  EXPECT_STREQ(vtkTerroirColorPresets::GetPresetForArray("RiverComparison"), "RiverComparison");
  EXPECT_TRUE(vtkTerroirColorPresets::IsCategorical("RiverComparison"));
  EXPECT_STREQ(vtkTerroirColorPresets::GetMaskArrayName("RiverComparison"), "RiverComparison");
  EXPECT_STREQ(vtkTerroirColorPresets::GetUnits("RiverComparison"), "");
  EXPECT_EQ(vtkTerroirColorPresets::GetLegendTitle("RiverComparison"), "Rivers");
  double range[2];
  ASSERT_TRUE(vtkTerroirColorPresets::GetDefaultRange("RiverComparison", range));
  EXPECT_EQ(range[0], 0.0);
  EXPECT_EQ(range[1], 3.0);
  for (const auto& lut : { vtkSmartPointer<vtkLookupTable>::Take(
                             vtkTerroirColorPresets::CreateLookupTable("RiverComparison")),
         Make("RiverComparison", 0.0, 0.0),
         Make("RiverComparison", 2.0, 9.0) })
  {
    ASSERT_NE(lut.Get(), nullptr);
    EXPECT_EQ(lut->GetIndexedLookup(), 1);
    ASSERT_EQ(lut->GetNumberOfAnnotatedValues(), 3);
    EXPECT_EQ(lut->GetAnnotatedValue(0).ToInt(), 1);
    EXPECT_EQ(std::string(lut->GetAnnotation(0)), "map only");
    EXPECT_EQ(std::string(lut->GetAnnotation(1)), "model only");
    EXPECT_EQ(std::string(lut->GetAnnotation(2)), "both");
    // Okabe-Ito blue (0, 114, 178), vermillion (213, 94, 0), and black; all opaque.
    ExpectRGBA(lut, 1.0, 0, 114, 178, 255, 1);
    ExpectRGBA(lut, 2.0, 213, 94, 0, 255, 1);
    ExpectRGBA(lut, 3.0, 0, 0, 0, 255);
    // The unsigned-char array's values arrive as doubles; 0 and others are no class (NaN grey).
    ExpectRGBA(lut, static_cast<double>(static_cast<unsigned char>(2)), 213, 94, 0, 255, 1);
    ExpectRGBA(lut, 0.0, 128, 128, 128, 255, 1);
    ExpectRGBA(lut, 4.0, 128, 128, 128, 255, 1);
  }
  // Distinct in lightness too (Rec. 709 luma, 0..255): black 0 < blue 94 < vermillion 113,
  // so the three classes stay apart in grey scale, not only in hue.
  auto lut = Make("RiverComparison", 0.0, 3.0);
  auto luma = [&lut](double v)
  {
    const unsigned char* c = lut->MapValue(v);
    return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
  };
  EXPECT_LT(luma(3.0) + 50.0, luma(1.0));
  EXPECT_LT(luma(1.0) + 10.0, luma(2.0));
}

TEST(TerroirColorPresets, IncidenceIsBlackToWhiteOverZeroToOne)
{
  EXPECT_STREQ(vtkTerroirColorPresets::GetPresetForArray("SunIncidence"), "Incidence");
  auto lut =
    vtkSmartPointer<vtkLookupTable>::Take(vtkTerroirColorPresets::CreateLookupTable("Incidence"));
  ASSERT_NE(lut.Get(), nullptr);
  EXPECT_FALSE(vtkTerroirColorPresets::IsCategorical("Incidence"));
  ExpectRGBA(lut, 0.0, 0, 0, 0, 255);
  ExpectRGBA(lut, 1.0, 255, 255, 255, 255);
  ExpectRGBA(lut, 0.5, 128, 128, 128, 255, 1);
}

TEST(TerroirColorPresets, InsolationGoesFromBlackThroughWarmColoursToPaleYellow)
{
  EXPECT_STREQ(vtkTerroirColorPresets::GetPresetForArray("Insolation"), "Insolation");
  EXPECT_STREQ(vtkTerroirColorPresets::GetPresetForArray("IlluminationHours"), "Illumination");
  EXPECT_STREQ(vtkTerroirColorPresets::GetUnits("Insolation"), "Wh/m\xC2\xB2/day");
  EXPECT_EQ(vtkTerroirColorPresets::GetLegendTitle("Insolation"), "Insolation (Wh/m\xC2\xB2/day)");
  double range[2];
  EXPECT_FALSE(vtkTerroirColorPresets::GetDefaultRange("Insolation", range)); // data range
  auto lut = Make("Insolation", 0.0, 8000.0);
  ExpectRGBA(lut, 0.0, 0, 0, 0, 255);
  ExpectRGBA(lut, 8000.0, 255, 255, 191, 255, 1); // pale yellow (1, 1, 0.75)
  ExpectRGBA(lut, 2800.0, 140, 20, 13, 255, 1);   // dark red (0.55, 0.08, 0.05) at 35 %
  ExpectRGBA(lut, 5600.0, 242, 140, 26, 255, 1);  // orange (0.95, 0.55, 0.10) at 70 %
  // Dark to bright: the luminance rises over the whole range.
  double previous = -1.0;
  for (int k = 0; k <= 32; ++k)
  {
    const unsigned char* c = lut->MapValue(8000.0 * k / 32.0);
    const double luminance = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
    EXPECT_GT(luminance, previous) << "sample " << k;
    previous = luminance;
  }
}

TEST(TerroirColorPresets, NaNMapsToTheNanColor)
{
  double nan[4];
  vtkTerroirColorPresets::GetNanColor(nan);
  EXPECT_EQ(nan[0], 0.5);
  EXPECT_EQ(nan[3], 1.0);
  auto lut = Make("Slope", 0.0, 60.0);
  ExpectRGBA(lut, std::numeric_limits<double>::quiet_NaN(), 128, 128, 128, 255, 1);
}

TEST(TerroirColorPresets, MetadataAndBadInput)
{
  EXPECT_EQ(vtkTerroirColorPresets::GetNumberOfPresets(), 15);
  EXPECT_STREQ(vtkTerroirColorPresets::GetPresetName(0), "Elevation");
  EXPECT_STREQ(vtkTerroirColorPresets::GetPresetName(6), "Clusters");
  EXPECT_STREQ(vtkTerroirColorPresets::GetPresetName(7), "Sunlit");
  EXPECT_STREQ(vtkTerroirColorPresets::GetPresetName(9), "Insolation");
  EXPECT_STREQ(vtkTerroirColorPresets::GetPresetName(10), "WaterBodies");
  EXPECT_STREQ(vtkTerroirColorPresets::GetPresetName(11), "RiverComparison");
  EXPECT_STREQ(vtkTerroirColorPresets::GetPresetName(12), "Rivers");
  EXPECT_STREQ(vtkTerroirColorPresets::GetPresetName(13), "Erosion");
  EXPECT_STREQ(vtkTerroirColorPresets::GetPresetName(14), "Vegetation");
  EXPECT_EQ(vtkTerroirColorPresets::GetPresetName(15), nullptr);
  EXPECT_STREQ(vtkTerroirColorPresets::GetMaskArrayName("Rivers"), "RiverNetwork");
  EXPECT_TRUE(vtkTerroirColorPresets::IsCategorical("Rivers"));
  // Rivers: 1 Okabe-Ito blue (0, 114, 178), 2 sky blue (86, 180, 233), annotated.
  auto rivers = Make("Rivers", 0.0, 2.0);
  ExpectRGBA(rivers, 1.0, 0, 114, 178, 255, 1);
  ExpectRGBA(rivers, 2.0, 86, 180, 233, 255, 1);
  ASSERT_EQ(rivers->GetNumberOfAnnotatedValues(), 2);
  EXPECT_EQ(rivers->GetAnnotatedValue(0).ToInt(), 1);
  EXPECT_EQ(std::string(rivers->GetAnnotation(0)), "river");
  EXPECT_EQ(std::string(rivers->GetAnnotation(1)), "lake");
  ExpectRGBA(rivers, 0.0, 128, 128, 128, 255, 1); // dry land: no class (masked by the view)
  EXPECT_STREQ(vtkTerroirColorPresets::GetDefaultArrayName("WaterBodies"), "WaterDepth");
  EXPECT_STREQ(vtkTerroirColorPresets::GetMaskArrayName("WaterBodies"), "WaterBody");
  EXPECT_EQ(vtkTerroirColorPresets::GetMaskArrayName("Water"), nullptr);
  EXPECT_STREQ(vtkTerroirColorPresets::GetPresetForArray("WaterDepth"), "WaterBodies");
  EXPECT_STREQ(vtkTerroirColorPresets::GetDefaultArrayName("Illumination"), "IlluminationHours");
  EXPECT_STREQ(vtkTerroirColorPresets::GetDefaultArrayName("Water"), "WaterHeight");
  EXPECT_STREQ(vtkTerroirColorPresets::GetUnits("Temperature"),
    "\xC2\xB0"
    "C");
  EXPECT_EQ(vtkTerroirColorPresets::GetLegendTitle("Slope"), "Slope (\xC2\xB0)");
  EXPECT_EQ(vtkTerroirColorPresets::GetLegendTitle("Clusters"), "Cluster");
  EXPECT_STREQ(vtkTerroirColorPresets::GetPresetForArray("Temperature"), "Temperature");
  EXPECT_STREQ(vtkTerroirColorPresets::GetPresetForArray("StandingWater"), "Humidity");
  EXPECT_EQ(vtkTerroirColorPresets::GetPresetForArray("Nonsense"), nullptr);
  double range[2];
  EXPECT_FALSE(vtkTerroirColorPresets::GetDefaultRange("Temperature", range));
  EXPECT_EQ(vtkTerroirColorPresets::CreateLookupTable("Temperature"), nullptr);
  EXPECT_EQ(vtkTerroirColorPresets::CreateLookupTable("NoSuchPreset", 0.0, 1.0), nullptr);
  EXPECT_EQ(vtkTerroirColorPresets::CreateLookupTable("Slope", 5.0, 1.0), nullptr);
  EXPECT_EQ(vtkTerroirColorPresets::CreateLookupTable(
              "Slope", 0.0, std::numeric_limits<double>::infinity()),
    nullptr);
}

// vtkTerroirOverlayView: non-image assertions (shading worked out by hand from the Blinn-Phong
// formula, no-data colour, framing, orientation, errors, PNG export).
#include "TerroirRenderingTestHelpers.h"
#include "TerroirSyntheticTerrain.h"

#include "vtkActor.h"
#include "vtkImageData.h"
#include "vtkLookupTable.h"
#include "vtkMapper.h"
#include "vtkNew.h"
#include "vtkPNGReader.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkTerroirOverlayView.h"
#include "vtkTerroirReliefSurface.h"
#include "vtkUnsignedCharArray.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>

#include <sys/stat.h>
#include <unistd.h>

using terroir::testing::AddField;
using terroir::testing::FileExists;
using terroir::testing::MakeTerrain;
using terroir::testing::MeanIntensity;
using terroir::testing::PixelAt;

namespace
{
constexpr double Pi = 3.14159265358979323846;

// A north-south ridge 1000 m x 1000 m (101 x 101 points, 10 m): the west face rises eastwards
// and the east face falls, both at 30 degrees, so their normals are (-+sin 30, 0, cos 30).
vtkSmartPointer<vtkImageData> Ridge()
{
  auto t = MakeTerrain(101,
    101,
    10.0,
    [](double x, double) { return 1000.0 - std::abs(x - 500.0) * std::tan(Pi / 6); });
  AddField(t, "Paint", [](double, double) { return 60.0; }); // white with the Slope preset
  return t;
}

// Blinn-Phong for a white surface seen from straight above (V = (0, 0, 1)):
// ka + kd max(0, N.L) + ks max(0, N.H)^p with L from azimuth/elevation and H = norm(L + V).
double BlinnPhong(const double n[3],
  double azDeg,
  double elDeg,
  double ka = 0.25,
  double kd = 0.75,
  double ks = 0.15,
  double p = 20.0)
{
  const double az = azDeg * Pi / 180, el = elDeg * Pi / 180;
  const double l[3] = { std::sin(az) * std::cos(el), std::cos(az) * std::cos(el), std::sin(el) };
  double h[3] = { l[0], l[1], l[2] + 1.0 };
  const double hn = std::sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
  const double ndl = n[0] * l[0] + n[1] * l[1] + n[2] * l[2];
  const double ndh = (n[0] * h[0] + n[1] * h[1] + n[2] * h[2]) / hn;
  const double df = std::max(0.0, ndl);
  const double sf = df > 0 ? std::pow(std::max(0.0, ndh), p) : 0.0;
  return 255.0 * std::min(1.0, ka + kd * df + ks * sf);
}

void SetupMapView(vtkTerroirOverlayView* view, vtkImageData* terrain, const char* array)
{
  view->SetInputData(terrain);
  view->SetArrayName(array);
  view->SetPreset("Slope");
  view->SetModeToMap();
  view->ShowLegendOff();
  view->SetWidth(400);
  view->SetHeight(400);
}
}

TEST(TerroirOverlayView, RidgeFaceTowardsTheLightIsBrighterByBlinnPhong)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  auto ridge = Ridge();
  vtkNew<vtkTerroirOverlayView> view;
  SetupMapView(view, ridge, "Paint");
  vtkNew<vtkImageData> image;
  ASSERT_TRUE(view->GetImage(image)) << view->GetLastError();

  // The 1000 m square fills the 400 x 400 frame: x = 2.5 m per pixel. Sample away from the
  // crest (x = 500 m, column 200) and the edges.
  const double west = MeanIntensity(image, 40, 160, 40, 360);
  const double east = MeanIntensity(image, 240, 360, 40, 360);
  const double s = std::sin(Pi / 6), c = std::cos(Pi / 6);
  const double nWest[3] = { -s, 0.0, c }, nEast[3] = { s, 0.0, c };
  const double expectWest = BlinnPhong(nWest, 315, 45); // 238.7
  const double expectEast = BlinnPhong(nEast, 315, 45); // 133.1
  EXPECT_GT(west, east + 80.0) << "the face towards the north-west light must be brighter";
  // Within 3 grey levels of the formula; VTK's default Phong (reflection vector) would give
  // 229 on the west face, so this also checks that the half-vector model is in use.
  EXPECT_NEAR(west, expectWest, 3.0);
  EXPECT_NEAR(east, expectEast, 3.0);

  // Moving the light to the south-east swaps the bright and dark faces.
  view->SetLightAzimuth(135.0);
  ASSERT_TRUE(view->GetImage(image)) << view->GetLastError();
  EXPECT_NEAR(MeanIntensity(image, 40, 160, 40, 360), BlinnPhong(nWest, 135, 45), 3.0);
  EXPECT_NEAR(MeanIntensity(image, 240, 360, 40, 360), BlinnPhong(nEast, 135, 45), 3.0);
  EXPECT_LT(MeanIntensity(image, 40, 160, 40, 360), MeanIntensity(image, 240, 360, 40, 360));
}

TEST(TerroirOverlayView, FlatTerrainShadingMatchesTheFormula)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  auto flat = MakeTerrain(51, 51, 20.0, [](double, double) { return 250.0; });
  AddField(flat, "Paint", [](double, double) { return 60.0; });
  vtkNew<vtkTerroirOverlayView> view;
  SetupMapView(view, flat, "Paint");
  vtkNew<vtkImageData> image;
  ASSERT_TRUE(view->GetImage(image)) << view->GetLastError();
  const double up[3] = { 0.0, 0.0, 1.0 };
  EXPECT_NEAR(MeanIntensity(image, 20, 380, 20, 380), BlinnPhong(up, 315, 45), 2.0); // 206.8
  // Light at the zenith: 0.25 + 0.75 + 0.15 * 1 clamps to white.
  view->SetLightElevation(90.0);
  ASSERT_TRUE(view->GetImage(image)) << view->GetLastError();
  EXPECT_NEAR(MeanIntensity(image, 20, 380, 20, 380), 255.0, 1.0);
}

TEST(TerroirOverlayView, DryWaterShowsTheBareTerrainAndDeepWaterIsDarkBlue)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  // Flat terrain, dry west half (0 m), 1 m of water on the east half, range 0..1 m.
  auto flat = MakeTerrain(51, 51, 20.0, [](double, double) { return 100.0; });
  AddField(flat, "WaterHeight", [](double x, double) { return x > 500.0 ? 1.0 : 0.0; });
  vtkNew<vtkTerroirOverlayView> view;
  SetupMapView(view, flat, "WaterHeight");
  view->SetPreset(nullptr); // WaterHeight -> Water
  view->UseCustomRangeOn();
  view->SetRange(0.0, 1.0);
  EXPECT_STREQ(view->GetEffectivePreset(), "Water");
  vtkNew<vtkImageData> image;
  ASSERT_TRUE(view->GetImage(image)) << view->GetLastError();
  // Flat, light at 45 degrees: colour factor 0.25 + 0.75 sin 45 = 0.7803, specular
  // 0.15 * cos(22.5)^20 = 0.0308. Dry: base grey 0.85; deep: 8-bit (0, 31, 128) / 255.
  const double shade = 0.25 + 0.75 * std::sqrt(0.5);
  const double spec = 0.15 * std::pow(std::cos(Pi / 8), 20.0);
  unsigned char rgb[3];
  PixelAt(image, 100, 200, rgb);
  for (int c = 0; c < 3; ++c)
  {
    EXPECT_NEAR(rgb[c], 255.0 * (0.85 * shade + spec), 3.0);
  }
  PixelAt(image, 300, 200, rgb);
  EXPECT_NEAR(rgb[0], 255.0 * spec, 3.0);
  EXPECT_NEAR(rgb[1], 31.0 * shade + 255.0 * spec, 3.0);
  EXPECT_NEAR(rgb[2], 128.0 * shade + 255.0 * spec, 3.0);
}

TEST(TerroirOverlayView, NoDataHoleIsDrawnInTheNanColor)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  // 1000 m square; NaN elevation for points 40..60 (centre), mask = 0 for points 5..15 with
  // finite elevation (south-west corner).
  auto t = MakeTerrain(101,
    101,
    10.0,
    [](double x, double y)
    {
      const int i = static_cast<int>(std::lround(x / 10)),
                j = static_cast<int>(std::lround(y / 10));
      if (i >= 40 && i <= 60 && j >= 40 && j <= 60)
      {
        return std::numeric_limits<double>::quiet_NaN();
      }
      return 300.0 + 0.05 * x;
    });
  AddField(t, "Paint", [](double, double) { return 60.0; });
  vtkNew<vtkUnsignedCharArray> mask;
  mask->SetName("vtkValidPointMask");
  mask->SetNumberOfTuples(101 * 101);
  for (int j = 0; j < 101; ++j)
  {
    for (int i = 0; i < 101; ++i)
    {
      mask->SetValue(j * 101 + i, (i >= 5 && i <= 15 && j >= 5 && j <= 15) ? 0 : 1);
    }
  }
  t->GetPointData()->AddArray(mask);

  vtkNew<vtkTerroirOverlayView> view;
  SetupMapView(view, t, "Paint");
  view->SetNanColor(1.0, 0.0, 1.0, 1.0);
  vtkNew<vtkImageData> image;
  ASSERT_TRUE(view->GetImage(image)) << view->GetLastError();
  unsigned char rgb[3];
  for (int p : { 170, 200, 230 }) // NaN hole: x, y in 400..600 m = pixels 160..240
  {
    PixelAt(image, p, p, rgb);
    EXPECT_EQ(rgb[0], 255);
    EXPECT_EQ(rgb[1], 0);
    EXPECT_EQ(rgb[2], 255);
  }
  PixelAt(image, 40, 40, rgb); // masked: 50..150 m = pixels 20..60
  EXPECT_EQ(rgb[0], 255);
  EXPECT_EQ(rgb[1], 0);
  EXPECT_EQ(rgb[2], 255);
  for (int p : { 100, 300 }) // valid terrain is shaded white-grey, not the NaN colour
  {
    PixelAt(image, p, 300, rgb);
    EXPECT_GT(rgb[1], 150);
    EXPECT_NEAR(rgb[0], rgb[1], 1);
  }

  // The default NaN colour is opaque grey 0.5.
  vtkNew<vtkTerroirOverlayView> grey;
  SetupMapView(grey, t, "Paint");
  ASSERT_TRUE(grey->GetImage(image)) << grey->GetLastError();
  PixelAt(image, 200, 200, rgb);
  EXPECT_NEAR(rgb[0], 128, 1);
  EXPECT_NEAR(rgb[1], 128, 1);
  EXPECT_NEAR(rgb[2], 128, 1);
}

TEST(TerroirOverlayView, MapIsNorthUpAndFitsTheFrame)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  // 2000 m (east-west) x 1000 m (north-south); white (60) in the north-east quadrant only.
  auto t = MakeTerrain(201, 101, 10.0, [](double, double) { return 0.0; });
  AddField(t, "Paint", [](double x, double y) { return (x > 1000.0 && y > 500.0) ? 60.0 : 0.0; });
  vtkNew<vtkTerroirOverlayView> view;
  SetupMapView(view, t, "Paint");
  view->SetBackground(0.0, 1.0, 0.0); // green background to tell it from the terrain
  vtkNew<vtkImageData> image;
  ASSERT_TRUE(view->GetImage(image)) << view->GetLastError();
  // 5 m per pixel: the terrain spans all columns and rows 100..300 (image row 0 = bottom).
  unsigned char rgb[3];
  auto isBackground = [&](int x, int y)
  {
    PixelAt(image, x, y, rgb);
    return rgb[0] == 0 && rgb[1] == 255 && rgb[2] == 0;
  };
  EXPECT_TRUE(isBackground(200, 90));
  EXPECT_TRUE(isBackground(200, 310));
  EXPECT_FALSE(isBackground(200, 110));
  EXPECT_FALSE(isBackground(200, 290));
  EXPECT_FALSE(isBackground(1, 200));
  EXPECT_FALSE(isBackground(398, 200));
  // North-east quadrant (top right) is white-ish, the other three are black.
  EXPECT_GT(MeanIntensity(image, 220, 380, 210, 290), 180.0);
  EXPECT_LT(MeanIntensity(image, 20, 180, 210, 290), 20.0);
  EXPECT_LT(MeanIntensity(image, 220, 380, 110, 190), 20.0);
  EXPECT_LT(MeanIntensity(image, 20, 180, 110, 190), 20.0);
}

TEST(TerroirOverlayView, BadInputFailsWithOneClearMessage)
{
  // Validation happens before any window is made, so this needs no display.
  vtkNew<vtkTerroirOverlayView> view;
  view->GlobalWarningDisplayOff();
  EXPECT_FALSE(view->Render());
  EXPECT_NE(std::string(view->GetLastError()).find("no input terrain"), std::string::npos);

  auto t = MakeTerrain(10, 10, 10.0, [](double x, double) { return x; });
  view->SetInputData(t);
  view->SetArrayName("Temperature");
  EXPECT_FALSE(view->Render());
  EXPECT_NE(
    std::string(view->GetLastError()).find("no point array 'Temperature'"), std::string::npos);

  view->SetArrayName("Elevation");
  view->SetArrayComponent(6);
  EXPECT_FALSE(view->Render());
  EXPECT_NE(std::string(view->GetLastError()).find("component 6"), std::string::npos);

  view->SetArrayComponent(0);
  view->SetPreset("Rainbow");
  EXPECT_FALSE(view->Render());
  EXPECT_NE(
    std::string(view->GetLastError()).find("unknown colour preset 'Rainbow'"), std::string::npos);

  auto line = MakeTerrain(10, 1, 10.0, [](double, double) { return 0.0; });
  view->SetPreset(nullptr);
  view->SetInputData(line);
  EXPECT_FALSE(view->Render());
  EXPECT_NE(std::string(view->GetLastError()).find("2-D image"), std::string::npos);

  auto allNaN = MakeTerrain(
    4, 4, 10.0, [](double, double) { return std::numeric_limits<double>::quiet_NaN(); });
  view->SetInputData(allNaN);
  EXPECT_FALSE(view->Render());
  EXPECT_NE(std::string(view->GetLastError()).find("no valid elevation"), std::string::npos);
}

TEST(TerroirOverlayView, WithoutDisplayFailsInsteadOfAborting)
{
  const char* saved = std::getenv("DISPLAY");
  const std::string display = saved ? saved : "";
  unsetenv("DISPLAY");
  auto t = MakeTerrain(10, 10, 10.0, [](double x, double) { return x; });
  vtkNew<vtkTerroirOverlayView> view;
  view->GlobalWarningDisplayOff();
  view->SetInputData(t);
  EXPECT_FALSE(view->Render());
  EXPECT_STREQ(view->GetLastError(),
    "vtkTerroirOverlayView: no X display (DISPLAY unset); run under xvfb-run -a");
  const std::string out = std::string(TERROIR_TEMP_DIR) + "/TerroirOverlayView_NoDisplay.png";
  std::remove(out.c_str());
  EXPECT_FALSE(view->WritePNG(out.c_str()));
  EXPECT_FALSE(FileExists(out));
  // A display that is set but has no server (VTK would abort with "bad X server connection").
  setenv("DISPLAY", ":54321", 1);
  EXPECT_FALSE(view->Render());
  EXPECT_STREQ(view->GetLastError(),
    "vtkTerroirOverlayView: cannot connect to the X display ':54321' (is the X server "
    "running?); run under xvfb-run -a");
  unsetenv("DISPLAY");
  if (!display.empty())
  {
    setenv("DISPLAY", display.c_str(), 1);
  }
}

TEST(TerroirOverlayView, WritePNGWritesTheRenderedImage)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  auto ridge = Ridge();
  vtkNew<vtkTerroirOverlayView> view;
  SetupMapView(view, ridge, "Paint");
  view->SetWidth(160);
  view->SetHeight(120);
  const std::string out = std::string(TERROIR_TEMP_DIR) + "/TerroirOverlayView_WritePNG.png";
  std::remove(out.c_str());
  ASSERT_TRUE(view->WritePNG(out.c_str())) << view->GetLastError();
  EXPECT_STREQ(view->GetLastError(), "");
  const std::string temp = out + ".tmp" + std::to_string(static_cast<long>(getpid())) + ".png";
  EXPECT_FALSE(FileExists(temp)) << "the temporary file must be renamed";

  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(out.c_str());
  reader->Update();
  int dims[3];
  reader->GetOutput()->GetDimensions(dims);
  EXPECT_EQ(dims[0], 160);
  EXPECT_EQ(dims[1], 120);
  vtkNew<vtkImageData> image;
  ASSERT_TRUE(view->GetImage(image));
  long differing = 0;
  for (int y = 0; y < 120; ++y)
  {
    for (int x = 0; x < 160; ++x)
    {
      unsigned char a[3], b[3];
      PixelAt(image, x, y, a);
      PixelAt(reader->GetOutput(), x, y, b);
      differing += (a[0] != b[0] || a[1] != b[1] || a[2] != b[2]) ? 1 : 0;
    }
  }
  EXPECT_EQ(differing, 0);
}

TEST(TerroirOverlayView, WritePNGToReadOnlyFolderFailsAndLeavesNoFile)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  std::string folder = std::string(TERROIR_TEMP_DIR) + "/TerroirOverlayView_ReadOnly";
  ::mkdir(folder.c_str(), 0755);
  ASSERT_EQ(::chmod(folder.c_str(), 0555), 0);
  if (::access(folder.c_str(), W_OK) == 0)
  {
    // Running as root: permissions do not stop us, so use a folder no one can create files in.
    folder = "/proc";
  }
  const std::string out = folder + "/overlay.png";
  auto ridge = Ridge();
  vtkNew<vtkTerroirOverlayView> view;
  view->GlobalWarningDisplayOff();
  SetupMapView(view, ridge, "Paint");
  EXPECT_FALSE(view->WritePNG(out.c_str()));
  const std::string error = view->GetLastError();
  EXPECT_NE(error.find("cannot write"), std::string::npos) << error;
  EXPECT_NE(error.find(out), std::string::npos) << error;
  EXPECT_FALSE(FileExists(out));
  EXPECT_FALSE(FileExists(out + ".tmp" + std::to_string(static_cast<long>(getpid())) + ".png"));
}

// A grid with more points than the frame has pixels is drawn at every Stride-th point and the
// last ones: its picture is the picture of that subsample, pixel for pixel. A 1201 x 1201 grid
// (1 m) in a 400 x 400 frame is drawn at every 3rd point, i.e. as the 401 x 401 grid of 3 m
// holding the same heights (whose extremes, like the colour field's, lie on drawn points).
TEST(TerroirOverlayView, BigGridIsDrawnAsItsSubsample)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  auto height = [](double x, double y)
  { return 50.0 + 20.0 * std::sin(2 * Pi * x / 300.0) * std::cos(2 * Pi * y / 240.0); };
  auto paint = [](double x, double y) { return 0.02 * (x + y); };
  auto big = MakeTerrain(1201, 1201, 1.0, height);
  AddField(big, "Paint", paint);
  auto small = MakeTerrain(401, 401, 3.0, height);
  AddField(small, "Paint", paint);
  vtkNew<vtkImageData> bigImage, smallImage;
  vtkNew<vtkTerroirOverlayView> view;
  SetupMapView(view, big, "Paint");
  ASSERT_TRUE(view->GetImage(bigImage)) << view->GetLastError();
  SetupMapView(view, small, "Paint");
  ASSERT_TRUE(view->GetImage(smallImage)) << view->GetLastError();
  vtkDataArray* a = bigImage->GetPointData()->GetScalars();
  vtkDataArray* b = smallImage->GetPointData()->GetScalars();
  ASSERT_EQ(a->GetNumberOfValues(), b->GetNumberOfValues());
  vtkIdType differ = 0;
  for (vtkIdType k = 0; k < a->GetNumberOfValues(); ++k)
  {
    differ += a->GetVariantValue(k) == b->GetVariantValue(k) ? 0 : 1;
  }
  EXPECT_EQ(differ, 0) << "pixel values differ between the grid and its subsample";
  // Not a blank frame: the shading varies over the waves.
  EXPECT_GT(std::abs(MeanIntensity(bigImage, 40, 160, 40, 360) -
              MeanIntensity(bigImage, 240, 360, 40, 360)) +
      std::abs(
        MeanIntensity(bigImage, 40, 360, 40, 160) - MeanIntensity(bigImage, 40, 360, 240, 360)),
    1.0);
}

// The drawn points of a stride: 0, 3, 6, 9 and the last column 10 of 11; 0, 3, 6 of 7 rows.
TEST(TerroirReliefSurface, StrideDrawsEveryNthPointAndTheLast)
{
  auto t = MakeTerrain(11, 7, 10.0, [](double x, double y) { return 0.5 * x + 0.25 * y; });
  AddField(t, "Paint", [](double x, double) { return x; });
  vtkNew<vtkTerroirReliefSurface> relief;
  relief->SetInputData(t);
  relief->SetStride(3);
  std::string why;
  ASSERT_TRUE(relief->BuildGeometry(why)) << why;
  vtkPolyData* surface =
    vtkPolyData::SafeDownCast(relief->GetSurfaceActor()->GetMapper()->GetInput());
  ASSERT_NE(surface, nullptr);
  ASSERT_EQ(surface->GetNumberOfPoints(), 5 * 3);
  ASSERT_EQ(surface->GetNumberOfPolys(), 4 * 2);
  const double expectX[5] = { 0, 30, 60, 90, 100 };
  const double expectY[3] = { 0, 30, 60 };
  vtkDataArray* normals = surface->GetPointData()->GetNormals();
  // The plane z = 0.5 x + 0.25 y: normal (-0.5, -0.25, 1) normalised, at every drawn point
  // whatever the distance to its neighbours.
  const double len = std::sqrt(0.25 + 0.0625 + 1.0);
  for (int j = 0; j < 3; ++j)
  {
    for (int i = 0; i < 5; ++i)
    {
      double p[3];
      surface->GetPoint(j * 5 + i, p);
      EXPECT_DOUBLE_EQ(p[0], expectX[i]);
      EXPECT_DOUBLE_EQ(p[1], expectY[j]);
      EXPECT_NEAR(p[2], 0.5 * expectX[i] + 0.25 * expectY[j], 1e-4);
      EXPECT_NEAR(normals->GetComponent(j * 5 + i, 0), -0.5 / len, 1e-6);
      EXPECT_NEAR(normals->GetComponent(j * 5 + i, 1), -0.25 / len, 1e-6);
    }
  }
  // Colours come from the grid's values at the drawn points: a grey ramp on x.
  vtkNew<vtkLookupTable> lut;
  lut->SetRange(0.0, 100.0);
  lut->SetSaturationRange(0, 0);
  lut->SetValueRange(0, 1);
  lut->Build();
  relief->SetColors(t->GetPointData()->GetArray("Paint"), 0, lut, nullptr);
  vtkDataArray* colours = surface->GetPointData()->GetScalars();
  for (int i = 0; i < 5; ++i)
  {
    const unsigned char* rgba = lut->MapValue(expectX[i]);
    EXPECT_EQ(colours->GetComponent(i, 0), rgba[0]) << "drawn point " << i;
  }
  // The data range is the whole grid's.
  double range[2];
  ASSERT_TRUE(relief->ComputeDataRange(t->GetPointData()->GetArray("Paint"), 0, nullptr, range));
  EXPECT_EQ(range[0], 0.0);
  EXPECT_EQ(range[1], 100.0);
}

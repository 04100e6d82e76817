// Image regression tests of the overlays (label rendering, run under xvfb-run -a).
// Each test renders at 400 x 400 and compares with Testing/Baselines/<Suite>_<Test>.png
// (TerroirImageCompare.h: 8 levels, one pixel of slack, 16 pixels); see
// TerroirRenderingTestHelpers.h and Documentation/Rendering.md for the review-and-update
// workflow.
//
// The bundled DEM (Data/sagehen_creek_ca/sagehen_dem_utm11n_10m.tif, UTM 11N, 10 m) goes
// through vtkTerroirDEMReader -> vtkTerroirSlope -> vtkTerroirTemperature, and separately
// through vtkTerroirSolarIllumination (CPU backend, so the analysis numbers are the reference
// ones; GPU agreement is tested in Testing/GPU).
#include "RiverValidation.h"
#include "TerroirRenderingTestHelpers.h"
#include "TerroirSyntheticTerrain.h"

#include "vtkExtractVOI.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkTerroirDEMReader.h"
#include "vtkTerroirFloodFill.h"
#include "vtkTerroirInfiltration.h"
#include "vtkTerroirKMeans.h"
#include "vtkTerroirOverlayView.h"
#include "vtkTerroirSlope.h"
#include "vtkTerroirSoilHumidity.h"
#include "vtkTerroirSolarIllumination.h"
#include "vtkTerroirTemperature.h"
#include "vtkTerroirWaterFlow.h"
#include "vtkUnsignedCharArray.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <iostream>
#include <string>
#include <vector>

using terroir::testing::CompareWithBaseline;
using terroir::testing::MakeTerrain;

namespace
{
// The bundled DEM with Slope and Temperature, read and computed once for all tests.
vtkImageData* SagehenTerrain()
{
  static vtkSmartPointer<vtkImageData> terrain;
  if (!terrain)
  {
    vtkNew<vtkTerroirDEMReader> reader;
    const std::string file =
      std::string(TERROIR_DATA_DIR) + "/sagehen_creek_ca/sagehen_dem_utm11n_10m.tif";
    reader->SetFileName(file.c_str());
    vtkNew<vtkTerroirSlope> slope;
    slope->SetInputConnection(reader->GetOutputPort());
    slope->SetBackendToCPU();
    vtkNew<vtkTerroirTemperature> temperature;
    temperature->SetInputConnection(slope->GetOutputPort());
    temperature->SetBackendToCPU();
    temperature->Update();
    terrain = vtkSmartPointer<vtkImageData>::New();
    terrain->ShallowCopy(temperature->GetOutput());
  }
  return terrain;
}

// The bundled DEM through vtkTerroirSolarIllumination with the location of its georeference
// (39.43 N, 120.28 W): Instant mode on 2025-12-21 at 16:00 PST (UTC-8, the sun low in the
// south-west, azimuth 233 deg, elevation 5.9 deg), or Monthly mode with its defaults (the 15th
// of each month, 10-minute steps). Computed once each.
vtkImageData* SagehenIllumination(int mode)
{
  static vtkSmartPointer<vtkImageData> results[3];
  vtkSmartPointer<vtkImageData>& result = results[mode];
  if (!result)
  {
    vtkNew<vtkTerroirDEMReader> reader;
    const std::string file =
      std::string(TERROIR_DATA_DIR) + "/sagehen_creek_ca/sagehen_dem_utm11n_10m.tif";
    reader->SetFileName(file.c_str());
    vtkNew<vtkTerroirSolarIllumination> illumination;
    illumination->SetInputConnection(reader->GetOutputPort());
    illumination->SetBackendToCPU();
    illumination->SetMode(mode);
    illumination->SetYear(2025);
    illumination->SetMonth(12);
    illumination->SetDay(21);
    illumination->SetTime(16.0);
    illumination->SetUTCOffset(-8.0);
    illumination->Update();
    result = vtkSmartPointer<vtkImageData>::New();
    result->ShallowCopy(illumination->GetOutput());
  }
  return result;
}

// The bundled DEM through vtkTerroirInfiltration and vtkTerroirSoilHumidity: soils by height
// band (clay below 2100 m, loam to 2300 m, sandy loam above; a made-up soil map, as the DEM
// has none), dry cliffs above 30 degrees, and the monthly climate of the climate-file example
// (wet winters at 2-2.5 mm/h, dry summers in showers of 5-10 mm/h).
vtkImageData* SagehenSoilWater()
{
  static vtkSmartPointer<vtkImageData> result;
  if (!result)
  {
    vtkImageData* terrain = SagehenTerrain();
    auto soil = vtkSmartPointer<vtkImageData>::New();
    soil->CopyStructure(terrain);
    vtkNew<vtkIntArray> codes;
    codes->SetName("Soil");
    vtkDataArray* z = terrain->GetPointData()->GetArray("Elevation");
    codes->SetNumberOfTuples(z->GetNumberOfTuples());
    for (vtkIdType k = 0; k < z->GetNumberOfTuples(); ++k)
    {
      const double h = z->GetComponent(k, 0);
      codes->SetValue(k, h < 2100.0 ? 5 : (h < 2300.0 ? 3 : 2));
    }
    soil->GetPointData()->SetScalars(codes);
    vtkNew<vtkTerroirInfiltration> infiltration;
    infiltration->SetInputData(terrain);
    infiltration->AddSoilTypes(soil);
    infiltration->AddSlopeRule(30.0);
    vtkNew<vtkTerroirSoilHumidity> humidity;
    humidity->SetInputConnection(infiltration->GetOutputPort());
    humidity->SetBackendToCPU();
    const double q[12] = { 150, 140, 110, 60, 35, 15, 5, 5, 15, 50, 110, 145 };
    const double i[12] = { 2.5, 2.5, 2, 1.5, 3, 6, 10, 10, 5, 2, 2, 2.5 };
    humidity->SetPrecipitation(q);
    humidity->SetPrecipitationIntensity(i);
    humidity->Update();
    result = vtkSmartPointer<vtkImageData>::New();
    result->ShallowCopy(humidity->GetOutput());
  }
  return result;
}

void SetupIllumination(vtkTerroirOverlayView* view,
  int illuminationMode,
  const char* array,
  int component,
  int mode)
{
  vtkImageData* t = SagehenIllumination(illuminationMode);
  ASSERT_NE(t->GetPointData()->GetArray(array), nullptr) << array;
  view->SetInputData(t);
  view->SetArrayName(array);
  view->SetArrayComponent(component);
  view->SetMode(mode);
  view->ShowLegendOff();
}

void ExpectTerrainArrays(vtkImageData* t)
{
  int dims[3];
  t->GetDimensions(dims);
  ASSERT_EQ(dims[0], 786);
  ASSERT_EQ(dims[1], 720);
  ASSERT_NE(t->GetPointData()->GetArray("Slope"), nullptr);
  ASSERT_NE(t->GetPointData()->GetArray("Temperature"), nullptr);
  ASSERT_EQ(t->GetPointData()->GetArray("Temperature")->GetNumberOfComponents(), 12);
}

// Three-lobed hill labelled with 5 clusters by sector and height (a synthetic labelled image).
vtkSmartPointer<vtkImageData> LabelledHill()
{
  auto t = MakeTerrain(161,
    161,
    25.0,
    [](double x, double y)
    {
      const double dx = x - 2000.0, dy = y - 2000.0;
      return 1500.0 + 600.0 * std::exp(-(dx * dx + dy * dy) / (2 * 900.0 * 900.0)) +
        80.0 * std::sin(x / 400.0) * std::cos(y / 500.0);
    });
  vtkNew<vtkIntArray> ids;
  ids->SetName("ClusterId");
  ids->SetNumberOfTuples(161 * 161);
  for (int j = 0; j < 161; ++j)
  {
    for (int i = 0; i < 161; ++i)
    {
      const double dx = i * 25.0 - 2000.0, dy = j * 25.0 - 2000.0;
      const double r = std::sqrt(dx * dx + dy * dy);
      int id = 4; // summit
      if (r > 700.0)
      {
        const double a = std::atan2(dy, dx); // -pi..pi
        id = a < -1.0 ? 0 : (a < 1.0 ? 1 : (a < 2.5 ? 2 : 3));
      }
      ids->SetValue(j * 161 + i, id);
    }
  }
  t->GetPointData()->AddArray(ids);
  return t;
}

void SetupSagehen(vtkTerroirOverlayView* view, const char* array, int component, int mode)
{
  view->SetInputData(SagehenTerrain());
  view->SetArrayName(array);
  view->SetArrayComponent(component);
  view->SetMode(mode);
  view->ShowLegendOff();
}
}

TEST(TerroirOverlayImages, SlopeMap)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  ExpectTerrainArrays(SagehenTerrain());
  vtkNew<vtkTerroirOverlayView> view;
  SetupSagehen(view, "Slope", 0, vtkTerroirOverlayView::Map);
  CompareWithBaseline(view);
}

TEST(TerroirOverlayImages, SlopeRelief)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  vtkNew<vtkTerroirOverlayView> view;
  SetupSagehen(view, "Slope", 0, vtkTerroirOverlayView::Relief);
  CompareWithBaseline(view);
}

TEST(TerroirOverlayImages, TemperatureJulyMap)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  vtkNew<vtkTerroirOverlayView> view;
  SetupSagehen(view, "Temperature", 6, vtkTerroirOverlayView::Map);
  CompareWithBaseline(view);
}

TEST(TerroirOverlayImages, TemperatureJulyRelief)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  vtkNew<vtkTerroirOverlayView> view;
  SetupSagehen(view, "Temperature", 6, vtkTerroirOverlayView::Relief);
  CompareWithBaseline(view);
}

TEST(TerroirOverlayImages, ElevationReliefExaggerated)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  vtkNew<vtkTerroirOverlayView> view;
  SetupSagehen(view, "Elevation", 0, vtkTerroirOverlayView::Relief);
  view->SetVerticalExaggeration(2.0);
  CompareWithBaseline(view);
}

TEST(TerroirOverlayImages, ClustersMap)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  auto hill = LabelledHill();
  vtkNew<vtkTerroirOverlayView> view;
  view->SetInputData(hill);
  view->SetArrayName("ClusterId");
  view->ShowLegendOff();
  EXPECT_STREQ(view->GetEffectivePreset(), "Clusters");
  CompareWithBaseline(view);
}

// Legends and text only in the legend tests.
TEST(TerroirOverlayImages, LegendTemperatureMap)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  vtkNew<vtkTerroirOverlayView> view;
  SetupSagehen(view, "Temperature", 6, vtkTerroirOverlayView::Map);
  view->ShowLegendOn();
  view->SetTitle("Sagehen Creek, July");
  CompareWithBaseline(view);
}

TEST(TerroirOverlayImages, LegendClustersRelief)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  auto hill = LabelledHill();
  vtkNew<vtkTerroirOverlayView> view;
  view->SetInputData(hill);
  view->SetArrayName("ClusterId");
  view->SetModeToRelief();
  view->ShowLegendOn();
  CompareWithBaseline(view);
}

// The five ecological zones vtkTerroirKMeans finds on the bundled DEM's Slope and Temperature
// (CPU, Long (2016)'s diagonal seeds), with each zone's share in the legend (field data
// KMeansClusterShare). Steep slopes (zones 0, 1) lie on the canyon walls in the south-west.
TEST(TerroirOverlayImages, LegendKMeansZonesRelief)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  vtkNew<vtkTerroirKMeans> kmeans;
  kmeans->SetBackendToCPU();
  kmeans->SetInputData(SagehenTerrain());
  kmeans->Update();
  vtkImageData* zones = kmeans->GetOutput();
  vtkDataArray* shares = zones->GetFieldData()->GetArray("KMeansClusterShare");
  ASSERT_NE(shares, nullptr);
  ASSERT_EQ(shares->GetNumberOfTuples(), 5);
  vtkNew<vtkTerroirOverlayView> view;
  view->SetInputData(zones);
  view->SetArrayName("ClusterId");
  view->SetModeToRelief();
  view->ShowLegendOn();
  view->SetTitle("Ecological zones, K = 5");
  EXPECT_STREQ(view->GetEffectivePreset(), "Clusters");
  CompareWithBaseline(view);
}

// Instant shadows of a low winter afternoon sun from the south-west: black (shadow) on the
// north- and east-facing slopes, white (lit) on the slopes facing the sun.
TEST(TerroirOverlayImages, ShadowsDecemberAfternoonMap)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  vtkNew<vtkTerroirOverlayView> view;
  SetupIllumination(view,
    vtkTerroirSolarIllumination::Instant,
    vtkTerroirSolarIllumination::IlluminatedName(),
    0,
    vtkTerroirOverlayView::Map);
  EXPECT_STREQ(view->GetEffectivePreset(), "Sunlit");
  CompareWithBaseline(view);
}

// Hours of direct sun on December 15. Fixed range 0-10 h (the day is 9.3 h long at 39.4 N),
// so that the grey levels mean the same hours whatever the extremes of the data.
TEST(TerroirOverlayImages, IlluminationHoursDecemberMap)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  vtkNew<vtkTerroirOverlayView> view;
  SetupIllumination(view,
    vtkTerroirSolarIllumination::Monthly,
    vtkTerroirSolarIllumination::IlluminationHoursName(),
    11,
    vtkTerroirOverlayView::Map);
  EXPECT_STREQ(view->GetEffectivePreset(), "Illumination");
  view->UseCustomRangeOn();
  view->SetRange(0.0, 10.0);
  CompareWithBaseline(view);
}

// Clear-sky direct insolation on June 15 (data range), seen from the south-south-east.
TEST(TerroirOverlayImages, InsolationJuneRelief)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  vtkNew<vtkTerroirOverlayView> view;
  SetupIllumination(view,
    vtkTerroirSolarIllumination::Monthly,
    vtkTerroirSolarIllumination::InsolationName(),
    5,
    vtkTerroirOverlayView::Relief);
  EXPECT_STREQ(view->GetEffectivePreset(), "Insolation");
  CompareWithBaseline(view);
}

// The two-class legend of the shadow map: a black "shadow" swatch and a white "lit" swatch,
// outlined so that it shows on the white background.
TEST(TerroirOverlayImages, LegendShadowsMap)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  vtkNew<vtkTerroirOverlayView> view;
  SetupIllumination(view,
    vtkTerroirSolarIllumination::Instant,
    vtkTerroirSolarIllumination::IlluminatedName(),
    0,
    vtkTerroirOverlayView::Map);
  view->ShowLegendOn();
  view->SetTitle("Sagehen Creek, 2025-12-21 16:00 PST");
  CompareWithBaseline(view);
}

// Weighted soil humidity of July (July, June and May rain), black -> blue: clay valley floors
// (3 mm/h) absorb less of the summer showers than loam (by hand: 9.1 mm against 13.3 mm),
// cliffs nothing.
TEST(TerroirOverlayImages, WeightedSoilHumidityJulyMap)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  vtkNew<vtkTerroirOverlayView> view;
  view->SetInputData(SagehenSoilWater());
  view->SetArrayName(vtkTerroirSoilHumidity::WeightedSoilHumidityName());
  view->SetArrayComponent(6);
  view->SetModeToMap();
  view->ShowLegendOff();
  EXPECT_STREQ(view->GetEffectivePreset(), "Humidity");
  CompareWithBaseline(view);
}

// The humidity legend in millimetres over the relief.
TEST(TerroirOverlayImages, LegendSoilHumidityJanuaryRelief)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  vtkNew<vtkTerroirOverlayView> view;
  view->SetInputData(SagehenSoilWater());
  view->SetArrayName(vtkTerroirSoilHumidity::SoilHumidityName());
  view->SetArrayComponent(0);
  view->SetModeToRelief();
  view->ShowLegendOn();
  view->SetTitle("Soil humidity, January");
  CompareWithBaseline(view);
}

// Lakes of the bundled DEM (FillDepressions: Independence Lake, a hydro-flattened surface at
// 2117.8 m in the north-west, and a small closed depression), blue over the bare terrain, with
// the depth legend. Independence Lake has depth 0 (the DEM records its surface): light blue.
TEST(TerroirOverlayImages, LegendLakesMap)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  vtkNew<vtkTerroirFloodFill> lakes;
  lakes->SetInputData(SagehenTerrain());
  lakes->SetModeToFillDepressions();
  lakes->Update();
  vtkNew<vtkTerroirOverlayView> view;
  view->SetInputData(lakes->GetOutput());
  view->SetArrayName(vtkTerroirFloodFill::WaterDepthName());
  view->SetModeToMap();
  EXPECT_STREQ(view->GetEffectivePreset(), "WaterBodies");
  view->ShowLegendOn();
  view->SetTitle("Lakes (FillDepressions)");
  CompareWithBaseline(view);
}

// `terroir run`'s rivers overlay: the water flow's river-forming mode on the bundled DEM
// (defaults: 0.3 mm/h to the balance), rivers (River, Okabe-Ito blue) and lakes (LakeMask, sky
// blue: Independence Lake in the north-west and a small pond), top-down with the legend.
TEST(TerroirOverlayImages, LegendRiversMap)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  vtkNew<vtkTerroirWaterFlow> flow;
  flow->SetInputData(SagehenTerrain());
  flow->SetModeToRivers();
  flow->SetBackendToCPU();
  flow->Update();
  vtkImageData* out = flow->GetOutput();
  vtkDataArray* river = out->GetPointData()->GetArray(vtkTerroirWaterFlow::RiverName());
  vtkDataArray* lake = out->GetPointData()->GetArray(vtkTerroirWaterFlow::LakeMaskName());
  ASSERT_TRUE(river && lake);
  vtkNew<vtkUnsignedCharArray> network;
  network->SetName("RiverNetwork");
  network->SetNumberOfTuples(river->GetNumberOfTuples());
  long long rivers = 0, lakes = 0;
  for (vtkIdType k = 0; k < river->GetNumberOfTuples(); ++k)
  {
    const bool r = river->GetComponent(k, 0) != 0.0;
    const bool l = lake->GetComponent(k, 0) != 0.0;
    network->SetValue(k, r ? 1 : (l ? 2 : 0));
    rivers += r ? 1 : 0;
    lakes += l ? 1 : 0;
  }
  // Rivers are lines (a few thousand cells of 566,000), the lakes Independence Lake (about
  // 24,000 cells) and the small ponds.
  EXPECT_GT(rivers, 2000);
  EXPECT_LT(rivers, 20000);
  EXPECT_GT(lakes, 20000);
  auto picture = vtkSmartPointer<vtkImageData>::New();
  picture->ShallowCopy(out);
  picture->GetPointData()->AddArray(network);
  vtkNew<vtkTerroirOverlayView> view;
  view->SetInputData(picture);
  view->SetArrayName("RiverNetwork");
  view->SetPreset("Rivers");
  view->SetModeToMap();
  view->ShowLegendOn();
  view->SetTitle("Rivers and lakes (map)");
  CompareWithBaseline(view);
}

namespace
{
// A 0/1 mask of the bundled data (Byte GeoTIFF on the DEM grid) as bytes, row j = 0 south.
std::vector<std::uint8_t> ReadSagehenMask(const char* name, int nx, int ny)
{
  vtkNew<vtkTerroirDEMReader> reader;
  const std::string file = std::string(TERROIR_DATA_DIR) + "/sagehen_creek_ca/" + name;
  reader->SetFileName(file.c_str());
  reader->Update();
  vtkImageData* image = reader->GetOutput();
  int dims[3];
  image->GetDimensions(dims);
  std::vector<std::uint8_t> mask;
  vtkDataArray* values = image->GetPointData()->GetArray("Elevation");
  if (dims[0] != nx || dims[1] != ny || !values)
  {
    return mask;
  }
  mask.resize(static_cast<std::size_t>(nx) * ny);
  for (std::size_t k = 0; k < mask.size(); ++k)
  {
    mask[k] = values->GetComponent(static_cast<vtkIdType>(k), 0) != 0.0 ? 1 : 0;
  }
  return mask;
}
}

// terroir validate's overlay (terroir::hydrology::RiverComparisonCategories) on the bundled DEM,
// map view with its legend. Reference: the shipped NHD stream mask (6668 cells). Simulated: a
// stand-in that needs no water flow, the reference moved 4 cells (40 m) east and kept inside
// the watershed mask, which is also the scored area. Within 30 m, reaches running east-west
// overlap their shifted copy and 45-degree reaches lie 28 m from it (black, "both"); reaches
// running north-south lie 40 m from it: blue ("map only") beside vermillion ("model only").
// The picture shows the north-eastern tributaries (cells 470..710 x 330..570).
TEST(TerroirOverlayImages, LegendRiverComparisonMap)
{
  TERROIR_SKIP_WITHOUT_DISPLAY();
  vtkNew<vtkTerroirDEMReader> reader;
  const std::string file =
    std::string(TERROIR_DATA_DIR) + "/sagehen_creek_ca/sagehen_dem_utm11n_10m.tif";
  reader->SetFileName(file.c_str());
  reader->Update();
  vtkNew<vtkImageData> terrain;
  terrain->ShallowCopy(reader->GetOutput());
  int dims[3];
  terrain->GetDimensions(dims);
  double spacing[3];
  terrain->GetSpacing(spacing);
  const int nx = dims[0];
  const int ny = dims[1];
  const std::vector<std::uint8_t> reference =
    ReadSagehenMask("sagehen_nhd_streams_mask_utm11n_10m.tif", nx, ny);
  const std::vector<std::uint8_t> watershed =
    ReadSagehenMask("sagehen_watershed_mask_utm11n_10m.tif", nx, ny);
  ASSERT_FALSE(reference.empty());
  ASSERT_FALSE(watershed.empty());

  const int shift = 4; // cells east
  std::vector<std::uint8_t> simulated(reference.size(), 0);
  for (int j = 0; j < ny; ++j)
  {
    for (int i = shift; i < nx; ++i)
    {
      const std::size_t k = static_cast<std::size_t>(j) * nx + i;
      simulated[k] = (reference[k - shift] && watershed[k]) ? 1 : 0;
    }
  }
  terroir::GridView<std::uint8_t> grid;
  grid.data = reference.data();
  grid.nx = nx;
  grid.ny = ny;
  grid.dx = spacing[0];
  grid.dy = spacing[1];
  const double tolerance = 30.0;
  vtkNew<vtkUnsignedCharArray> comparison;
  comparison->SetName("RiverComparison");
  comparison->SetNumberOfTuples(static_cast<vtkIdType>(reference.size()));
  terroir::hydrology::RiverComparisonCategories(
    grid, simulated.data(), watershed.data(), tolerance, comparison->GetPointer(0));
  terrain->GetPointData()->AddArray(comparison);

  const terroir::hydrology::RiverScores scores =
    terroir::hydrology::ScoreRivers(grid, simulated.data(), watershed.data(), tolerance);
  std::cout << "[ measured ] reference shifted " << shift << " cells east, within " << tolerance
            << " m: precision " << scores.precision << ", recall " << scores.recall << ", F1 "
            << scores.f1 << " (" << scores.simulatedCells << " simulated, " << scores.referenceCells
            << " reference cells)\n";
  // The picture shows every class.
  std::size_t perClass[4] = { 0, 0, 0, 0 };
  for (std::size_t k = 0; k < reference.size(); ++k)
  {
    ++perClass[comparison->GetValue(static_cast<vtkIdType>(k)) & 3];
  }
  EXPECT_GT(perClass[1], 0u);
  EXPECT_GT(perClass[2], 0u);
  EXPECT_GT(perClass[3], 0u);

  // The north-east tributaries at about 1.3 pixels per cell: on the whole DEM (2.6 cells per
  // pixel) one-cell-wide rivers are too thin to tell the classes apart.
  vtkNew<vtkExtractVOI> crop;
  crop->SetInputData(terrain);
  crop->SetVOI(470, 710, 330, 570, 0, 0);
  crop->Update();
  vtkNew<vtkTerroirOverlayView> view;
  view->SetInputData(crop->GetOutput());
  view->SetArrayName("RiverComparison");
  view->SetModeToMap();
  EXPECT_STREQ(view->GetEffectivePreset(), "RiverComparison");
  view->ShowLegendOn();
  view->SetTitle("Rivers: NHD vs NHD 40 m east");
  CompareWithBaseline(view);
}

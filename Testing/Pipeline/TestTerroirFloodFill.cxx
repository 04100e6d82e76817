// Pipeline tests of vtkTerroirFloodFill: Independence Lake on the bundled Sagehen Creek DEM
// (a hydro-flattened lake) found from a world-coordinate seed and by FillDepressions; the VTK
// contract (arrays, units, field data, defaults, Modified, PrintSelf, whole extent, progress);
// bad inputs; and a timing print on a 2048 x 2048 fractal terrain (for the filter's page).
#include "TerroirFilterTestUtilities.h"

#include "vtkDataArray.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkIntArray.h"
#include "vtkPointData.h"
#include "vtkStringArray.h"
#include "vtkTerroirComputeContext.h"
#include "vtkTerroirFloodFill.h"
#include "vtkTerroirFractalTerrainSource.h"
#include "vtkTerroirGeoreference.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <iostream>
#include <map>
#include <sstream>
#include <vector>

namespace
{
using terroir_test::MakeTerrain;

// Independence Lake, Sagehen DEM (786 x 720 cells of 10 m, origin = centre of the south-west
// cell (213985, 4366475)): cell (138, 474), found by looking for the lake's flat height
// (float 2117.803955078125, the most common value of the DEM) near the middle of the flat.
constexpr double kLakeX = 215365.0;  // 213985 + 138 * 10
constexpr double kLakeY = 4371215.0; // 4366475 + 474 * 10
constexpr int kLakeI = 138;
constexpr int kLakeJ = 474;
constexpr float kLakeLevel = 2117.803955078125f;

vtkImageData* Sagehen()
{
  static vtkSmartPointer<vtkImageData> dem =
    terroir_test::ReadDEM(terroir_test::DataFile("sagehen_creek_ca/sagehen_dem_utm11n_10m.tif"));
  return dem;
}

vtkSmartPointer<vtkImageData> RunFloodFill(vtkTerroirFloodFill* f, vtkImageData* in)
{
  f->SetInputData(in);
  f->Update();
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->ShallowCopy(f->GetOutput());
  return out;
}

double FieldValue(vtkImageData* out, const char* name, vtkIdType body)
{
  vtkDataArray* a = vtkDataArray::SafeDownCast(out->GetFieldData()->GetAbstractArray(name));
  return a && body < a->GetNumberOfTuples() ? a->GetComponent(body, 0) : std::nan("");
}

vtkIntArray* Ids(vtkImageData* out)
{
  return vtkIntArray::SafeDownCast(out->GetPointData()->GetArray("WaterBody"));
}

// The bowl of the unit tests (Testing/Unit/TestFloodFill.cxx): floor 1 2 1 / 2 8 3 / 1 2 1
// around an island (8), rim 9, a separate pit (0) at (5, 3); cells 2 m x 3 m. Its extent
// starts at (10, 20) and its origin is (1000, 2000), so cell (1, 1) of the extent lies at
// x = 1000 + 11 * 2 = 1022, y = 2000 + 21 * 3 = 2063.
vtkSmartPointer<vtkImageData> Bowl()
{
  const float rows[5][7] = {
    { 9, 9, 9, 9, 9, 9, 9 },
    { 9, 1, 2, 1, 9, 0, 9 },
    { 9, 2, 8, 3, 9, 9, 9 },
    { 9, 1, 2, 1, 9, 9, 9 },
    { 9, 9, 9, 9, 9, 9, 9 },
  };
  auto in = MakeTerrain(7, 5, 2.0, 3.0, [&rows](int i, int j) { return rows[4 - j][i]; });
  in->SetExtent(10, 16, 20, 24, 0, 0);
  in->SetOrigin(1000.0, 2000.0, 0.0);
  return in;
}

} // namespace

// (a) A seed in the middle of Independence Lake at the terrain's height floods the lake's
// flat: >= 10,000 cells at 2117.8 m, nearly all in the north-west quarter of the DEM.
TEST(TerroirFloodFill, SeedFloodsIndependenceLake)
{
  std::cout.precision(10);
  vtkImageData* dem = Sagehen();
  ASSERT_NE(dem, nullptr);
  int dims[3];
  dem->GetDimensions(dims);
  ASSERT_EQ(dims[0], 786);
  ASSERT_EQ(dims[1], 720);
  double origin[3], spacing[3];
  dem->GetOrigin(origin);
  dem->GetSpacing(spacing);
  // The world coordinate is the centre of cell (138, 474), which lies on the lake's flat.
  EXPECT_EQ(origin[0] + kLakeI * spacing[0], kLakeX);
  EXPECT_EQ(origin[1] + kLakeJ * spacing[1], kLakeY);
  vtkDataArray* z = dem->GetPointData()->GetArray("Elevation");
  ASSERT_EQ(z->GetComponent(static_cast<vtkIdType>(kLakeJ) * 786 + kLakeI, 0), kLakeLevel);

  vtkNew<vtkTerroirFloodFill> f;
  f->AddSeedPoint(kLakeX, kLakeY);
  auto out = RunFloodFill(f, dem);
  vtkIntArray* ids = Ids(out);
  ASSERT_NE(ids, nullptr);
  const double level = FieldValue(out, "WaterBodyLevel", 0);
  const double cells = FieldValue(out, "WaterBodyCells", 0);
  const double area = FieldValue(out, "WaterBodyArea", 0);
  EXPECT_EQ(level, static_cast<double>(kLakeLevel));
  EXPECT_NEAR(level, 2117.8, 0.01);
  EXPECT_GE(cells, 10000.0);
  EXPECT_DOUBLE_EQ(area, cells * 100.0);

  vtkIdType wet = 0, northWest = 0;
  double sumI = 0.0, sumJ = 0.0;
  for (int j = 0; j < 720; ++j)
  {
    for (int i = 0; i < 786; ++i)
    {
      if (ids->GetValue(static_cast<vtkIdType>(j) * 786 + i) == 1)
      {
        ++wet;
        northWest += (i < 393 && j >= 360) ? 1 : 0;
        sumI += i;
        sumJ += j;
      }
    }
  }
  EXPECT_EQ(static_cast<double>(wet), cells);
  EXPECT_GE(northWest, 0.95 * wet);
  EXPECT_LT(sumI / wet, 393.0);
  EXPECT_GE(sumJ / wet, 360.0);
  std::cout << "Independence Lake from seed (" << kLakeX << ", " << kLakeY << "): " << wet
            << " cells, level " << level << " m, area " << area << " m2, volume "
            << FieldValue(out, "WaterBodyVolume", 0) << " m3, max depth "
            << FieldValue(out, "WaterBodyMaxDepth", 0) << " m, " << northWest
            << " cells in the north-west quarter\n";
}

// (b) FillDepressions with its defaults finds a water body that covers >= 95 % of the lake the
// seed found.
TEST(TerroirFloodFill, FillDepressionsFindsIndependenceLake)
{
  std::cout.precision(10);
  vtkImageData* dem = Sagehen();
  ASSERT_NE(dem, nullptr);
  vtkNew<vtkTerroirFloodFill> seed;
  seed->AddSeedPoint(kLakeX, kLakeY);
  auto lake = RunFloodFill(seed, dem);
  vtkNew<vtkTerroirFloodFill> fill;
  fill->SetModeToFillDepressions();
  auto out = RunFloodFill(fill, dem);
  vtkIntArray* lakeIds = Ids(lake);
  vtkIntArray* ids = Ids(out);
  ASSERT_TRUE(lakeIds && ids);

  std::map<int, vtkIdType> overlap; // body id of FillDepressions -> lake cells it covers
  vtkIdType lakeCells = 0;
  for (vtkIdType k = 0; k < ids->GetNumberOfTuples(); ++k)
  {
    if (lakeIds->GetValue(k) == 1)
    {
      ++lakeCells;
      ++overlap[ids->GetValue(k)];
    }
  }
  int best = 0;
  for (const auto& [id, n] : overlap)
  {
    if (id != 0 && (best == 0 || n > overlap[best]))
    {
      best = id;
    }
  }
  ASSERT_NE(best, 0) << "no water body overlaps the lake";
  EXPECT_GE(overlap[best], 0.95 * lakeCells);
  EXPECT_EQ(FieldValue(out, "WaterBodyLevel", best - 1), static_cast<double>(kLakeLevel));
  const vtkIdType bodies =
    out->GetFieldData()->GetAbstractArray("WaterBodyLevel")->GetNumberOfTuples();
  std::cout << "FillDepressions: " << bodies << " water bodies; Independence Lake is body " << best
            << " with " << FieldValue(out, "WaterBodyCells", best - 1) << " cells ("
            << overlap[best] << " of the seed's " << lakeCells << "), level "
            << FieldValue(out, "WaterBodyLevel", best - 1) << " m, area "
            << FieldValue(out, "WaterBodyArea", best - 1) << " m2, volume "
            << FieldValue(out, "WaterBodyVolume", best - 1) << " m3, max depth "
            << FieldValue(out, "WaterBodyMaxDepth", best - 1) << " m\n";
  for (vtkIdType b = 0; b < bodies; ++b)
  {
    std::cout << "  body " << b + 1 << ": level " << FieldValue(out, "WaterBodyLevel", b) << " m, "
              << FieldValue(out, "WaterBodyCells", b) << " cells, volume "
              << FieldValue(out, "WaterBodyVolume", b) << " m3, max depth "
              << FieldValue(out, "WaterBodyMaxDepth", b) << " m\n";
  }

  // Without flat surfaces, depression filling alone touches only the lake's shore.
  vtkNew<vtkTerroirFloodFill> pits;
  pits->SetModeToFillDepressions();
  pits->IncludeFlatSurfacesOff();
  pits->SetMinimumArea(0.0);
  auto pitOut = RunFloodFill(pits, dem);
  vtkIntArray* pitIds = Ids(pitOut);
  vtkDataArray* depth = pitOut->GetPointData()->GetArray("WaterDepth");
  vtkIdType filledInLake = 0;
  for (vtkIdType k = 0; k < pitIds->GetNumberOfTuples(); ++k)
  {
    filledInLake += (lakeIds->GetValue(k) == 1 && depth->GetComponent(k, 0) > 0.0) ? 1 : 0;
  }
  EXPECT_LT(filledInLake, 0.01 * lakeCells);
  std::cout << "Priority-Flood alone raises " << filledInLake << " of the lake's " << lakeCells
            << " cells\n";
}

// (c) Arrays, types, units, field data, on the bowl: seed cell (1, 1) of the extent at 5 m
// wets the 8 floor cells around the island (depths 4 3 4 / 3 _ 2 / 4 3 4: 162 m^3 on
// 6 m^2 cells), not the island, the rim or the separate pit.
TEST(TerroirFloodFill, ArraysUnitsAndFieldData)
{
  auto in = Bowl();
  vtkNew<vtkTerroirFloodFill> f;
  f->AddSeedCell(1, 1, 5.0);
  auto out = RunFloodFill(f, in);
  vtkIntArray* ids = Ids(out);
  vtkDataArray* depth = out->GetPointData()->GetArray("WaterDepth");
  ASSERT_NE(ids, nullptr);
  ASSERT_NE(depth, nullptr);
  EXPECT_NE(out->GetPointData()->GetArray("Elevation"), nullptr);
  EXPECT_EQ(ids->GetNumberOfComponents(), 1);
  EXPECT_EQ(depth->GetDataType(), VTK_FLOAT);
  EXPECT_EQ(depth->GetNumberOfComponents(), 1);
  EXPECT_STREQ(depth->GetInformation()->Get(vtkDataArray::UNITS_LABEL()), "m");
  EXPECT_STREQ(vtkTerroirFloodFill::WaterBodyName(), "WaterBody");
  EXPECT_STREQ(vtkTerroirFloodFill::WaterDepthName(), "WaterDepth");
  const int expected[5][7] = {
    { 0, 0, 0, 0, 0, 0, 0 },
    { 0, 4, 3, 4, 0, 0, 0 },
    { 0, 3, 0, 2, 0, 0, 0 },
    { 0, 4, 3, 4, 0, 0, 0 },
    { 0, 0, 0, 0, 0, 0, 0 },
  };
  for (int j = 0; j < 5; ++j)
  {
    for (int i = 0; i < 7; ++i)
    {
      const vtkIdType k = j * 7 + i;
      const int d = expected[4 - j][i];
      const bool floor = i >= 1 && i <= 3 && j >= 1 && j <= 3 && !(i == 2 && j == 2);
      EXPECT_EQ(ids->GetValue(k), floor ? 1 : 0) << i << ", " << j;
      EXPECT_EQ(depth->GetComponent(k, 0), d) << i << ", " << j;
    }
  }
  vtkFieldData* fd = out->GetFieldData();
  const std::map<std::string, std::pair<double, const char*>> field = {
    { "WaterBodyLevel", { 5.0, "m" } },
    { "WaterBodyArea", { 48.0, "m2" } },
    { "WaterBodyVolume", { 162.0, "m3" } },
    { "WaterBodyCells", { 8.0, nullptr } },
    { "WaterBodyMaxDepth", { 4.0, "m" } },
  };
  for (const auto& [name, value] : field)
  {
    vtkDataArray* a = vtkDataArray::SafeDownCast(fd->GetAbstractArray(name.c_str()));
    ASSERT_NE(a, nullptr) << name;
    EXPECT_EQ(a->GetNumberOfTuples(), 1) << name;
    EXPECT_DOUBLE_EQ(a->GetComponent(0, 0), value.first) << name;
    if (value.second)
    {
      EXPECT_STREQ(a->GetInformation()->Get(vtkDataArray::UNITS_LABEL()), value.second) << name;
    }
  }
  auto* mode = vtkStringArray::SafeDownCast(fd->GetAbstractArray("FloodFillMode"));
  ASSERT_NE(mode, nullptr);
  EXPECT_EQ(mode->GetValue(0), "Seeds");

  // The same seed given in world coordinates, off the cell centre by less than half a cell.
  vtkNew<vtkTerroirFloodFill> g;
  g->AddSeedPoint(1022.9, 2061.6, 5.0);
  auto out2 = RunFloodFill(g, in);
  EXPECT_EQ(FieldValue(out2, "WaterBodyCells", 0), 8.0);
  EXPECT_EQ(Ids(out2)->GetValue(1 * 7 + 1), 1);

  // FillDepressions on the bowl: its floor fills to the lowest rim (9) and joins the rim, which
  // is one flat at 9 with the pit (filled to 9 as well): a single body of all 35 cells.
  vtkNew<vtkTerroirFloodFill> h;
  h->SetModeToFillDepressions();
  h->SetMinimumArea(0.0);
  auto out3 = RunFloodFill(h, in);
  auto* mode3 =
    vtkStringArray::SafeDownCast(out3->GetFieldData()->GetAbstractArray("FloodFillMode"));
  EXPECT_EQ(mode3->GetValue(0), "FillDepressions");
  EXPECT_EQ(FieldValue(out3, "WaterBodyCells", 0), 35.0);
  EXPECT_EQ(FieldValue(out3, "WaterBodyLevel", 0), 9.0);
  EXPECT_EQ(Ids(out3)->GetValue(2 * 7 + 2), 1);
  EXPECT_EQ(out3->GetPointData()->GetArray("WaterDepth")->GetComponent(3 * 7 + 5, 0), 9.0);
}

// No-data cells get WaterBody 0 and WaterDepth NaN in both modes; a seed level below the
// terrain is a warning and an empty body.
TEST(TerroirFloodFill, NoDataAndLevelBelowTheTerrain)
{
  auto in = MakeTerrain(5,
    3,
    10.0,
    10.0,
    [](int i, int j) { return (i == 2 && j == 1) ? std::nan("") : (j == 1 ? 1.0 : 9.0); });
  for (int mode : { vtkTerroirFloodFill::Seeds, vtkTerroirFloodFill::FillDepressions })
  {
    vtkNew<vtkTerroirFloodFill> f;
    f->SetMode(mode);
    f->AddSeedCell(0, 1, 3.0);
    auto out = RunFloodFill(f, in);
    EXPECT_EQ(Ids(out)->GetValue(7), 0) << mode;
    EXPECT_TRUE(std::isnan(out->GetPointData()->GetArray("WaterDepth")->GetComponent(7, 0)));
  }
  vtkNew<vtkTerroirFloodFill> f;
  vtkNew<terroir_test::ErrorObserver> obs;
  f->AddObserver(vtkCommand::WarningEvent, obs);
  f->AddObserver(vtkCommand::ErrorEvent, obs);
  f->AddSeedCell(0, 0, 5.0);
  auto out = RunFloodFill(f, in);
  EXPECT_EQ(obs->ErrorCount, 0);
  EXPECT_NE(obs->Warnings.find("seed 1 at cell (0, 0): level 5 m is below the terrain there (9 m)"),
    std::string::npos)
    << obs->Warnings;
  EXPECT_EQ(FieldValue(out, "WaterBodyCells", 0), 0.0);
  EXPECT_EQ(FieldValue(out, "WaterBodyLevel", 0), 5.0);
}

TEST(TerroirFloodFill, DefaultsModifiedAndPrintSelf)
{
  vtkNew<vtkTerroirFloodFill> f;
  EXPECT_EQ(f->GetMode(), vtkTerroirFloodFill::Seeds);
  EXPECT_EQ(f->GetMinimumArea(), 10000.0);
  EXPECT_TRUE(f->GetIncludeFlatSurfaces());
  EXPECT_EQ(f->GetNumberOfSeeds(), 0);
  EXPECT_STREQ(f->GetInputArrayInformation(0)->Get(vtkDataObject::FIELD_NAME()), "Elevation");

  std::vector<std::function<void()>> changes = {
    [&] { f->SetModeToFillDepressions(); },
    [&] { f->SetModeToSeeds(); },
    [&] { f->SetMinimumArea(50.0); },
    [&] { f->IncludeFlatSurfacesOff(); },
    [&] { f->AddSeedPoint(1.0, 2.0); },
    [&] { f->AddSeedPoint(3.0, 4.0, 1234.5); },
    [&] { f->AddSeedCell(5, 6); },
    [&] { f->AddSeedCell(7, 8, 99.0); },
  };
  for (std::size_t c = 0; c < changes.size(); ++c)
  {
    const vtkMTimeType before = f->GetMTime();
    changes[c]();
    EXPECT_GT(f->GetMTime(), before) << "change " << c;
  }
  EXPECT_EQ(f->GetNumberOfSeeds(), 4);
  vtkMTimeType t = f->GetMTime();
  f->SetMinimumArea(50.0);
  EXPECT_EQ(f->GetMTime(), t);
  f->SetMode(7); // clamped
  EXPECT_EQ(f->GetMode(), vtkTerroirFloodFill::FillDepressions);
  f->SetModeToSeeds();

  std::ostringstream os;
  f->Print(os);
  for (const char* word : { "Mode: Seeds",
         "Seeds: 4",
         "seed 1 at (1, 2), level terrain",
         "seed 2 at (3, 4), level 1234.5 m",
         "seed 3 at cell (5, 6), level terrain",
         "seed 4 at cell (7, 8), level 99 m",
         "MinimumArea: 50",
         "IncludeFlatSurfaces: Off",
         "Backend" })
  {
    EXPECT_NE(os.str().find(word), std::string::npos) << word << "\n" << os.str();
  }

  t = f->GetMTime();
  f->RemoveAllSeeds();
  EXPECT_GT(f->GetMTime(), t);
  EXPECT_EQ(f->GetNumberOfSeeds(), 0);
}

// CPU only: Auto runs on the CPU; an explicit GPU request is an error with an empty output.
TEST(TerroirFloodFill, RunsOnTheCPUOnly)
{
  auto in = Bowl();
  vtkNew<vtkTerroirFloodFill> f;
  f->AddSeedCell(1, 1);
  auto out = RunFloodFill(f, in);
  EXPECT_EQ(f->GetLastBackend(), vtkTerroirComputeContext::CPU);
  EXPECT_NE(Ids(out), nullptr);

  vtkNew<vtkTerroirFloodFill> g;
  vtkNew<terroir_test::ErrorObserver> errors;
  g->AddObserver(vtkCommand::ErrorEvent, errors);
  g->SetBackendToGPU();
  g->AddSeedCell(1, 1);
  auto none = RunFloodFill(g, in);
  EXPECT_EQ(errors->ErrorCount, 1) << errors->Errors;
  EXPECT_NE(errors->Errors.find("requested backend"), std::string::npos) << errors->Errors;
  EXPECT_EQ(none->GetPointData()->GetNumberOfArrays(), 0);
}

// A global filter: whatever extent is requested downstream, it asks for the whole input.
TEST(TerroirFloodFill, AsksForTheWholeExtentAndReportsProgress)
{
  auto in = MakeTerrain(20, 20, 1.0, 1.0, [](int i, int j) { return i + j; });
  vtkNew<vtkTerroirFloodFill> f;
  f->SetModeToFillDepressions();
  const std::array<int, 6> whole = { 0, 19, 0, 19, 0, 0 };
  EXPECT_EQ(terroir_test::RequestedInputExtent(f, in, { 2, 5, 3, 6, 0, 0 }), whole);

  vtkNew<vtkTerroirFloodFill> g;
  g->AddSeedCell(3, 3, 10.0);
  g->SetInputData(in);
  const std::vector<double> progress = terroir_test::UpdateWithProgress(g);
  ASSERT_GE(progress.size(), 3u);
  EXPECT_EQ(progress.back(), 1.0);
}

// Bad inputs: one error line each (prefixed with the source file), and an empty output.
TEST(TerroirFloodFill, BadInputsAreOneErrorAndAnEmptyOutput)
{
  auto in = MakeTerrain(
    4, 3, 10.0, 10.0, [](int i, int j) { return (i == 3 && j == 2) ? std::nan("") : 100.0 + i; });
  vtkTerroirGeoreference::SetSourceFile(in, "dem.tif");
  struct Case
  {
    std::function<void(vtkTerroirFloodFill*)> set;
    std::string message;
  };
  const std::vector<Case> cases = {
    { [](vtkTerroirFloodFill*) {},
      "dem.tif: Seeds mode needs at least one seed (AddSeedPoint or AddSeedCell)" },
    { [](vtkTerroirFloodFill* f)
      {
        f->AddSeedCell(0, 0);
        f->AddSeedPoint(35.0, -25.0);
      },
      "dem.tif: seed 2 at (35, -25) lies outside the terrain, which covers x -5 .. 35, y -5 .. "
      "25" },
    { [](vtkTerroirFloodFill* f) { f->AddSeedCell(4, 0); },
      "dem.tif: seed 1 at cell (4, 0) lies outside the terrain of 4 x 3 cells (i 0..3, j 0..2)" },
    { [](vtkTerroirFloodFill* f) { f->AddSeedPoint(31.0, 21.0); },
      "dem.tif: seed 1 at (31, 21) falls on cell (3, 2), which holds no data" },
    { [](vtkTerroirFloodFill* f) { f->AddSeedPoint(10.0, 10.0, std::nan("")); },
      "dem.tif: seed 1 at (10, 10) has a non-finite level nan" },
    { [](vtkTerroirFloodFill* f) { f->AddSeedCell(1, 1, HUGE_VAL); },
      "dem.tif: seed 1 at cell (1, 1) has a non-finite level inf" },
    { [](vtkTerroirFloodFill* f) { f->AddSeedPoint(std::nan(""), 10.0); },
      "dem.tif: seed 1 at (nan, 10) has non-finite coordinates" },
    { [](vtkTerroirFloodFill* f)
      {
        f->SetModeToFillDepressions();
        f->SetMinimumArea(-1.0);
      },
      "dem.tif: MinimumArea -1 m2 must be a finite number >= 0" },
  };
  for (const Case& c : cases)
  {
    vtkNew<vtkTerroirFloodFill> f;
    vtkNew<terroir_test::ErrorObserver> errors;
    f->AddObserver(vtkCommand::ErrorEvent, errors);
    vtkNew<terroir_test::ErrorObserver> pipeline; // the executive's "returned failure" line
    f->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, pipeline);
    c.set(f);
    auto out = RunFloodFill(f, in);
    EXPECT_EQ(errors->ErrorCount, 1) << c.message << ": " << errors->Errors;
    EXPECT_NE(errors->Errors.find(c.message), std::string::npos) << errors->Errors;
    EXPECT_EQ(out->GetNumberOfPoints(), 0) << c.message;
    EXPECT_EQ(out->GetPointData()->GetNumberOfArrays(), 0) << c.message;
  }
  // Seeds are ignored in FillDepressions mode, even bad ones.
  vtkNew<vtkTerroirFloodFill> f;
  f->SetModeToFillDepressions();
  f->AddSeedCell(40, 40, std::nan(""));
  auto out = RunFloodFill(f, in);
  EXPECT_NE(Ids(out), nullptr);
}

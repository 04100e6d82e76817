// Pipeline tests of vtkTerroirFlowAccumulation: the Sagehen Creek outlet on the bundled DEM
// drains the mapped watershed; the VTK contract (arrays, types, units, no data, per-row
// spacing, weights, defaults, Modified, PrintSelf, whole extent, progress, CPU only); bad
// inputs; and timing prints on the bundled DEM and a 2048 x 2048 fractal terrain (for the
// filter's page; not assertions).
#include "TerroirFilterTestUtilities.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkIntArray.h"
#include "vtkPointData.h"
#include "vtkSignedCharArray.h"
#include "vtkStringArray.h"
#include "vtkTerroirComputeContext.h"
#include "vtkTerroirFlowAccumulation.h"
#include "vtkTerroirFractalTerrainSource.h"
#include "vtkTerroirGeoreference.h"
#include "vtkUnsignedCharArray.h"

#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cmath>
#include <fstream>
#include <functional>
#include <iostream>
#include <regex>
#include <sstream>
#include <vector>

namespace
{
using terroir_test::MakeTerrain;

constexpr int kDi[8] = { 1, 1, 0, -1, -1, -1, 0, 1 };
constexpr int kDj[8] = { 0, 1, 1, 1, 0, -1, -1, -1 };

vtkImageData* Sagehen()
{
  static vtkSmartPointer<vtkImageData> dem =
    terroir_test::ReadDEM(terroir_test::DataFile("sagehen_creek_ca/sagehen_dem_utm11n_10m.tif"));
  return dem;
}

vtkSmartPointer<vtkImageData> RunFilter(vtkTerroirFlowAccumulation* f, vtkImageData* in)
{
  f->SetInputData(in);
  f->Update();
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->ShallowCopy(f->GetOutput());
  return out;
}

vtkDataArray* Array(vtkImageData* out, const char* name)
{
  return out->GetPointData()->GetArray(name);
}

std::string Units(vtkDataArray* a)
{
  return a && a->GetInformation()->Has(vtkDataArray::UNITS_LABEL())
    ? a->GetInformation()->Get(vtkDataArray::UNITS_LABEL())
    : std::string();
}

/// The V valley of the unit tests, z = 10 |i - 2| + j, 5 x 6 cells of 2 m x 3 m (6 m^2), with
/// cell (4, 5) (north-east corner) set to NaN.
vtkSmartPointer<vtkImageData> Valley()
{
  return MakeTerrain(5,
    6,
    2.0,
    3.0,
    [](int i, int j) { return (i == 4 && j == 5) ? std::nan("") : 10.0 * std::abs(i - 2) + j; });
}

} // namespace

// (a) The outlet of Sagehen Creek (Data/sagehen_creek_ca/sagehen_outlet_utm11n.geojson, read
// here with a regular expression) drains the mapped watershed: its contributing area is within
// 2 % of the watershed mask's area (277,180 cells of 100 m^2 = 27.718 km^2; PROVENANCE.md: the
// 27.72 km^2 gsflow-arcpy model boundary), and the cells upstream of it overlap the mask with an
// intersection over union >= 0.95.
//
// Snapping: the outlet point lies 3.4 m from the centre of cell (731, 320), which is beside the
// D8 channel (0.0015 km^2 drain through it): as every GIS does with pour points, the outlet is
// the cell of largest accumulation among the 3 x 3 cells around the point (within 14 m). A
// wider window is wrong here: 40 m downstream a tributary joins (28.6 km^2).
//
// Tolerances: the mask is the model boundary rasterised onto this grid, drawn by gsflow-arcpy on
// the original geographic NED grid, while this DEM is that grid resampled bilinearly to UTM; the
// divides therefore differ by a cell or two along the watershed's 3,160 cell edges of perimeter
// (1 cell everywhere = 3,160 cells = 1.1 % of the area). Measured: 27.574 km^2 (-0.52 %), IoU
// 0.9775 (2,427 cells upstream outside the mask, 3,867 mask cells not upstream).
TEST(TerroirFlowAccumulation, SagehenOutletDrainsTheMappedWatershed)
{
  std::cout.precision(8);
  vtkImageData* dem = Sagehen();
  ASSERT_NE(dem, nullptr);
  int dims[3];
  dem->GetDimensions(dims);
  ASSERT_EQ(dims[0], 786);
  ASSERT_EQ(dims[1], 720);
  const int nx = dims[0], ny = dims[1];
  double origin[3], spacing[3];
  dem->GetOrigin(origin);
  dem->GetSpacing(spacing);

  // The outlet point, from the GeoJSON text.
  std::ifstream in(terroir_test::DataFile("sagehen_creek_ca/sagehen_outlet_utm11n.geojson"));
  std::stringstream text;
  text << in.rdbuf();
  std::smatch m;
  const std::string json = text.str();
  ASSERT_TRUE(std::regex_search(
    json, m, std::regex(R"rx("coordinates"\s*:\s*\[\s*([-0-9.eE+]+)\s*,\s*([-0-9.eE+]+))rx")))
    << json;
  const double ox = std::stod(m[1].str());
  const double oy = std::stod(m[2].str());
  EXPECT_NEAR(ox, 221298.4, 0.1);
  EXPECT_NEAR(oy, 4369675.0, 0.1);
  const int oi = static_cast<int>(std::lround((ox - origin[0]) / spacing[0]));
  const int oj = static_cast<int>(std::lround((oy - origin[1]) / spacing[1]));
  ASSERT_TRUE(oi > 0 && oi < nx - 1 && oj > 0 && oj < ny - 1);

  // The watershed mask (Byte, 1 inside), on the same grid.
  auto mask = terroir_test::ReadDEM(
    terroir_test::DataFile("sagehen_creek_ca/sagehen_watershed_mask_utm11n_10m.tif"));
  ASSERT_NE(mask, nullptr);
  vtkDataArray* inside = Array(mask, "Elevation");
  ASSERT_NE(inside, nullptr);
  ASSERT_EQ(inside->GetNumberOfTuples(), static_cast<vtkIdType>(nx) * ny);
  vtkIdType maskCells = 0;
  for (vtkIdType k = 0; k < inside->GetNumberOfTuples(); ++k)
  {
    maskCells += inside->GetComponent(k, 0) == 1.0 ? 1 : 0;
  }
  const double maskArea = maskCells * spacing[0] * spacing[1];
  EXPECT_EQ(maskCells, 277180); // PROVENANCE.md
  EXPECT_NEAR(maskArea / 1e6, 27.72, 0.01);

  vtkNew<vtkTerroirFlowAccumulation> f;
  const auto t0 = std::chrono::steady_clock::now();
  auto out = RunFilter(f, dem);
  const double seconds =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  vtkDataArray* area = Array(out, "ContributingArea");
  vtkDataArray* cells = Array(out, "FlowAccumulation");
  auto* dir = vtkSignedCharArray::SafeDownCast(Array(out, "FlowDirection"));
  ASSERT_TRUE(area && cells && dir);

  int bi = oi, bj = oj;
  for (int j = oj - 1; j <= oj + 1; ++j)
  {
    for (int i = oi - 1; i <= oi + 1; ++i)
    {
      if (area->GetComponent(j * nx + i, 0) > area->GetComponent(bj * nx + bi, 0))
      {
        bi = i;
        bj = j;
      }
    }
  }
  const vtkIdType outlet = static_cast<vtkIdType>(bj) * nx + bi;
  const double outletArea = area->GetComponent(outlet, 0);
  EXPECT_NEAR(outletArea, maskArea, 0.02 * maskArea);
  EXPECT_DOUBLE_EQ(outletArea, cells->GetComponent(outlet, 0) * 100.0);

  // Upstream cells of the outlet: every cell whose direction leads into the set.
  std::vector<char> up(static_cast<std::size_t>(nx) * ny, 0);
  std::vector<vtkIdType> stack = { outlet };
  up[outlet] = 1;
  while (!stack.empty())
  {
    const vtkIdType k = stack.back();
    stack.pop_back();
    const int i = static_cast<int>(k % nx), j = static_cast<int>(k / nx);
    for (int e = 0; e < 8; ++e)
    {
      const int ii = i - kDi[e], jj = j - kDj[e]; // the neighbour that points here with code e
      if (ii >= 0 && ii < nx && jj >= 0 && jj < ny)
      {
        const vtkIdType kk = static_cast<vtkIdType>(jj) * nx + ii;
        if (!up[kk] && dir->GetValue(kk) == e)
        {
          up[kk] = 1;
          stack.push_back(kk);
        }
      }
    }
  }
  vtkIdType upstream = 0, both = 0, either = 0;
  for (vtkIdType k = 0; k < static_cast<vtkIdType>(up.size()); ++k)
  {
    const bool w = inside->GetComponent(k, 0) == 1.0;
    upstream += up[k];
    both += (up[k] && w) ? 1 : 0;
    either += (up[k] || w) ? 1 : 0;
  }
  EXPECT_EQ(static_cast<double>(upstream), cells->GetComponent(outlet, 0));
  const double iou = static_cast<double>(both) / static_cast<double>(either);
  EXPECT_GE(iou, 0.95);

  vtkIdType outlets = 0, rivers = 0;
  vtkDataArray* river = Array(out, "River");
  for (vtkIdType k = 0; k < dir->GetNumberOfTuples(); ++k)
  {
    outlets += dir->GetValue(k) == -1 ? 1 : 0;
    rivers += river->GetComponent(k, 0) == 1.0 ? 1 : 0;
  }
  std::cout << "Sagehen outlet point (" << ox << ", " << oy << ") -> cell (" << bi << ", " << bj
            << "): contributing area " << outletArea / 1e6 << " km2 against the mask's "
            << maskArea / 1e6 << " km2 (" << 100.0 * (outletArea / maskArea - 1.0)
            << " %); upstream " << upstream << " cells, mask " << maskCells << ", both " << both
            << ", IoU " << iou << "; " << outlets << " outlet cells, " << rivers
            << " river cells (>= 0.1 km2); " << seconds << " s for 786 x 720\n";
}

// (b) Arrays, types, units and values on the V valley (2 m x 3 m cells, one NaN corner). By
// hand (Testing/Unit/TestFlowAccumulation.cxx, VValleyCollectsBothSides): the floor (i = 2)
// drains S, the sides into the floor, the outlet (2, 0) is -1 and collects every valid cell:
// 29 cells, 174 m^2. The NaN corner (4, 5): direction -2, accumulations NaN, River 0.
TEST(TerroirFlowAccumulation, ArraysUnitsAndValues)
{
  auto in = Valley();
  vtkNew<vtkTerroirFlowAccumulation> f;
  f->SetRiverThreshold(60.0); // 10 cells of 6 m^2
  auto out = RunFilter(f, in);
  auto* filled = vtkFloatArray::SafeDownCast(Array(out, "FilledElevation"));
  auto* dir = vtkSignedCharArray::SafeDownCast(Array(out, "FlowDirection"));
  auto* cells = vtkDoubleArray::SafeDownCast(Array(out, "FlowAccumulation"));
  auto* area = vtkDoubleArray::SafeDownCast(Array(out, "ContributingArea"));
  auto* river = vtkUnsignedCharArray::SafeDownCast(Array(out, "River"));
  ASSERT_TRUE(filled && dir && cells && area && river);
  EXPECT_EQ(Array(out, "WeightedAccumulation"), nullptr);
  EXPECT_NE(Array(out, "Elevation"), nullptr); // passed through
  EXPECT_EQ(Units(filled), "m");
  EXPECT_EQ(Units(cells), "cells");
  EXPECT_EQ(Units(area), "m2");
  const std::vector<vtkDataArray*> all = {
    Array(out, "FilledElevation"), Array(out, "FlowDirection"), cells, area, Array(out, "River")
  };
  for (vtkDataArray* a : all)
  {
    EXPECT_EQ(a->GetNumberOfTuples(), 30);
    EXPECT_EQ(a->GetNumberOfComponents(), 1);
  }
  const vtkIdType corner = 5 * 5 + 4, outlet = 2;
  EXPECT_EQ(dir->GetValue(corner), -2);
  EXPECT_TRUE(std::isnan(filled->GetValue(corner)));
  EXPECT_TRUE(std::isnan(cells->GetValue(corner)));
  EXPECT_TRUE(std::isnan(area->GetValue(corner)));
  EXPECT_EQ(river->GetValue(corner), 0);
  EXPECT_EQ(dir->GetValue(outlet), -1);
  EXPECT_EQ(cells->GetValue(outlet), 29.0);
  EXPECT_DOUBLE_EQ(area->GetValue(outlet), 174.0);
  for (int j = 0; j < 6; ++j)
  {
    EXPECT_EQ(dir->GetValue(j * 5 + 1), 0) << j; // E into the floor
    EXPECT_EQ(dir->GetValue(j * 5 + 3), 4) << j; // W into the floor
    if (j > 0)
    {
      EXPECT_EQ(dir->GetValue(j * 5 + 2), 6) << j; // S along the floor
    }
    // Floor cell j collects 5 cells per row at or north of it (4 in the top row).
    const double floor = 5.0 * (6 - j) - 1.0;
    EXPECT_EQ(cells->GetValue(j * 5 + 2), floor) << j;
    EXPECT_EQ(river->GetValue(j * 5 + 2), floor * 6.0 >= 60.0 ? 1 : 0) << j;
    EXPECT_EQ(river->GetValue(j * 5 + 1), 0) << j;
  }
  for (vtkIdType k = 0; k < 30; ++k)
  {
    if (k != corner)
    {
      EXPECT_EQ(
        filled->GetValue(k), static_cast<float>(Array(out, "Elevation")->GetComponent(k, 0)));
    }
  }
}

// (c) Per-row spacing (TerroirRowSpacing, geographic grids) sets the cell areas: rows 0..5 of
// the valley with dx = 1..6 m and dy = 2 m: the outlet collects 5 cells per row except the
// NaN corner in row 5: 2 * (5 * (1 + 2 + 3 + 4 + 5) + 4 * 6) = 198 m^2.
TEST(TerroirFlowAccumulation, PerRowSpacingSetsCellAreas)
{
  auto in = Valley();
  auto rows = vtkSmartPointer<vtkDoubleArray>::New();
  rows->SetNumberOfComponents(2);
  for (int j = 0; j < 6; ++j)
  {
    rows->InsertNextTuple2(1.0 + j, 2.0);
  }
  vtkTerroirGeoreference::SetRowSpacing(in, rows);
  vtkNew<vtkTerroirFlowAccumulation> f;
  auto out = RunFilter(f, in);
  ASSERT_NE(Array(out, "ContributingArea"), nullptr);
  EXPECT_DOUBLE_EQ(Array(out, "ContributingArea")->GetComponent(2, 0), 198.0);
  EXPECT_EQ(Array(out, "FlowAccumulation")->GetComponent(2, 0), 29.0);
}

// (d) WeightedAccumulation: a 12-component depth array in mm; component 3 holds 10 mm on every
// cell except 50 mm on (0, 5): the outlet collects (28 * 10 + 50) mm * 6 m^2 / 1000 = 1.98 m^3;
// the side cell (1, 5) collects (10 + 50) * 6 / 1000 = 0.36 m^3. Any numeric type works (int
// here).
TEST(TerroirFlowAccumulation, WeightedAccumulationInCubicMetres)
{
  auto in = Valley();
  auto depth = vtkSmartPointer<vtkIntArray>::New();
  depth->SetName("StandingWater");
  depth->SetNumberOfComponents(12);
  depth->SetNumberOfTuples(30);
  depth->Fill(999);
  for (vtkIdType k = 0; k < 30; ++k)
  {
    depth->SetComponent(k, 3, k == 25 ? 50 : 10);
  }
  in->GetPointData()->AddArray(depth);
  vtkNew<vtkTerroirFlowAccumulation> f;
  f->SetWeightArrayName("StandingWater");
  f->SetWeightComponent(3);
  auto out = RunFilter(f, in);
  vtkDataArray* v = Array(out, "WeightedAccumulation");
  ASSERT_NE(v, nullptr);
  EXPECT_EQ(Units(v), "m3");
  EXPECT_NEAR(v->GetComponent(2, 0), 1.98, 1e-12);
  EXPECT_NEAR(v->GetComponent(5 * 5 + 1, 0), 0.36, 1e-12);
  EXPECT_TRUE(std::isnan(v->GetComponent(5 * 5 + 4, 0)));
}

TEST(TerroirFlowAccumulation, DefaultsModifiedAndPrintSelf)
{
  vtkNew<vtkTerroirFlowAccumulation> f;
  EXPECT_EQ(f->GetRiverThreshold(), 1e5);
  EXPECT_EQ(f->GetWeightArrayName(), nullptr);
  EXPECT_EQ(f->GetWeightComponent(), 0);
  EXPECT_EQ(f->GetBackend(), vtkTerroirComputeContext::Auto);
  EXPECT_STREQ(f->GetInputArrayInformation(0)->Get(vtkDataObject::FIELD_NAME()), "Elevation");
  EXPECT_STREQ(vtkTerroirFlowAccumulation::FlowDirectionName(), "FlowDirection");
  EXPECT_STREQ(vtkTerroirFlowAccumulation::FlowAccumulationName(), "FlowAccumulation");
  EXPECT_STREQ(vtkTerroirFlowAccumulation::ContributingAreaName(), "ContributingArea");
  EXPECT_STREQ(vtkTerroirFlowAccumulation::FilledElevationName(), "FilledElevation");
  EXPECT_STREQ(vtkTerroirFlowAccumulation::RiverName(), "River");
  EXPECT_STREQ(vtkTerroirFlowAccumulation::WeightedAccumulationName(), "WeightedAccumulation");

  std::vector<std::function<void()>> changes = {
    [&] { f->SetRiverThreshold(5e4); },
    [&] { f->SetWeightArrayName("StandingWater"); },
    [&] { f->SetWeightComponent(6); },
    [&] { f->SetBackendToCPU(); },
  };
  for (std::size_t c = 0; c < changes.size(); ++c)
  {
    const vtkMTimeType before = f->GetMTime();
    changes[c]();
    EXPECT_GT(f->GetMTime(), before) << "change " << c;
  }
  const vtkMTimeType t = f->GetMTime();
  f->SetRiverThreshold(5e4);
  f->SetWeightComponent(6);
  EXPECT_EQ(f->GetMTime(), t);
  f->SetWeightComponent(-3); // clamped
  EXPECT_EQ(f->GetWeightComponent(), 0);

  std::ostringstream os;
  f->Print(os);
  for (const char* word : { "RiverThreshold: 50000 m2",
         "WeightArrayName: StandingWater",
         "WeightComponent: 0",
         "Backend" })
  {
    EXPECT_NE(os.str().find(word), std::string::npos) << word << "\n" << os.str();
  }
}

// CPU only: Auto runs on the CPU; an explicit GPU request is an error with an empty output.
TEST(TerroirFlowAccumulation, RunsOnTheCPUOnly)
{
  auto in = Valley();
  vtkNew<vtkTerroirFlowAccumulation> f;
  auto out = RunFilter(f, in);
  EXPECT_EQ(f->GetLastBackend(), vtkTerroirComputeContext::CPU);
  EXPECT_NE(Array(out, "FlowDirection"), nullptr);

  vtkNew<vtkTerroirFlowAccumulation> g;
  vtkNew<terroir_test::ErrorObserver> errors;
  g->AddObserver(vtkCommand::ErrorEvent, errors);
  g->SetBackendToGPU();
  auto none = RunFilter(g, in);
  EXPECT_EQ(errors->ErrorCount, 1) << errors->Errors;
  EXPECT_NE(errors->Errors.find("requested backend"), std::string::npos) << errors->Errors;
  EXPECT_EQ(none->GetPointData()->GetNumberOfArrays(), 0);
}

// A global filter: whatever extent is requested downstream, it asks for the whole input.
TEST(TerroirFlowAccumulation, AsksForTheWholeExtentAndReportsProgress)
{
  auto in = MakeTerrain(20, 20, 1.0, 1.0, [](int i, int j) { return i + j; });
  vtkNew<vtkTerroirFlowAccumulation> f;
  const std::array<int, 6> whole = { 0, 19, 0, 19, 0, 0 };
  EXPECT_EQ(terroir_test::RequestedInputExtent(f, in, { 2, 5, 3, 6, 0, 0 }), whole);

  vtkNew<vtkTerroirFlowAccumulation> g;
  g->SetInputData(in);
  const std::vector<double> progress = terroir_test::UpdateWithProgress(g);
  ASSERT_GE(progress.size(), 3u);
  for (std::size_t p = 1; p < progress.size(); ++p)
  {
    EXPECT_GE(progress[p], progress[p - 1]);
  }
  EXPECT_EQ(progress.back(), 1.0);
}

// Bad inputs: one error line each (prefixed with the source file), and an empty output.
TEST(TerroirFlowAccumulation, BadInputsAreOneErrorAndAnEmptyOutput)
{
  auto in = Valley();
  vtkTerroirGeoreference::SetSourceFile(in, "dem.tif");
  auto names = vtkSmartPointer<vtkStringArray>::New();
  names->SetName("Names");
  names->SetNumberOfValues(30);
  in->GetPointData()->AddArray(names);
  auto monthly = vtkSmartPointer<vtkFloatArray>::New();
  monthly->SetName("StandingWater");
  monthly->SetNumberOfComponents(12);
  monthly->SetNumberOfTuples(30);
  monthly->Fill(1.0f);
  in->GetPointData()->AddArray(monthly);
  struct Case
  {
    std::function<void(vtkTerroirFlowAccumulation*)> set;
    std::string message;
  };
  const std::vector<Case> cases = {
    { [](vtkTerroirFlowAccumulation* f) { f->SetRiverThreshold(-1.0); },
      "dem.tif: RiverThreshold -1 m2 must be a finite number >= 0" },
    { [](vtkTerroirFlowAccumulation* f) { f->SetRiverThreshold(std::nan("")); },
      "dem.tif: RiverThreshold nan m2 must be a finite number >= 0" },
    { [](vtkTerroirFlowAccumulation* f) { f->SetRiverThreshold(HUGE_VAL); },
      "dem.tif: RiverThreshold inf m2 must be a finite number >= 0" },
    { [](vtkTerroirFlowAccumulation* f) { f->SetWeightArrayName("Rain"); },
      "dem.tif: WeightArrayName 'Rain' names no point array of the input" },
    { [](vtkTerroirFlowAccumulation* f) { f->SetWeightArrayName("Names"); },
      "dem.tif: weight array 'Names' is not numeric (vtkStringArray)" },
    { [](vtkTerroirFlowAccumulation* f)
      {
        f->SetWeightArrayName("StandingWater");
        f->SetWeightComponent(12);
      },
      "dem.tif: WeightComponent 12 is out of range: weight array 'StandingWater' has 12 "
      "component(s)" },
  };
  for (const Case& c : cases)
  {
    vtkNew<vtkTerroirFlowAccumulation> f;
    vtkNew<terroir_test::ErrorObserver> errors;
    f->AddObserver(vtkCommand::ErrorEvent, errors);
    vtkNew<terroir_test::ErrorObserver> pipeline; // the executive's "returned failure" line
    f->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, pipeline);
    c.set(f);
    auto out = RunFilter(f, in);
    EXPECT_EQ(errors->ErrorCount, 1) << c.message << ": " << errors->Errors;
    EXPECT_NE(errors->Errors.find(c.message), std::string::npos) << errors->Errors;
    EXPECT_EQ(out->GetNumberOfPoints(), 0) << c.message;
    EXPECT_EQ(out->GetPointData()->GetNumberOfArrays(), 0) << c.message;
  }
  // RiverThreshold 0 is allowed: every cell with data is a river cell.
  vtkNew<vtkTerroirFlowAccumulation> f;
  f->SetRiverThreshold(0.0);
  auto out = RunFilter(f, in);
  vtkDataArray* river = Array(out, "River");
  ASSERT_NE(river, nullptr);
  EXPECT_EQ(river->GetRange()[0], 0.0); // the NaN corner
  double sum = 0.0;
  for (vtkIdType k = 0; k < 30; ++k)
  {
    sum += river->GetComponent(k, 0);
  }
  EXPECT_EQ(sum, 29.0);
}

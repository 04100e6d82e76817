// Pipeline tests of vtkTerroirVectorRasterizer: which cells a polygon, a line or a point
// covers on a small synthetic UTM grid (worked out by hand below), attributes, filters, CRS
// handling, sub-extents, the bundled Sagehen data against the masks shipped with it (made by
// gdal_rasterize, Data/sagehen_creek_ca/PROVENANCE.md), and every error case.
#include "TerroirFilterTestUtilities.h"
#include "TerroirIOTestUtilities.h"
#include "TerroirScopedEnvironment.h"

#include "vtkDataArray.h"
#include "vtkExecutive.h"
#include "vtkExtractVOI.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirVectorRasterizer.h"

#include <GeographicLib/TransverseMercator.hpp>

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace
{
// The synthetic terrain: 8 x 6 cells of 10 m in WGS 84 / UTM zone 11N (EPSG:32611), west edge
// x = 500000, north edge y = 4360060. Column i spans x in [500000 + 10 i, 500010 + 10 i]
// (centre 500005 + 10 i); row j spans y in [4360000 + 10 j, 4360010 + 10 j] (centre
// 4360005 + 10 j), j = 0 being the SOUTH row. GDAL's row r is j = 5 - r.
const char* const kUTM11N =
  "PROJCS[\"WGS 84 / UTM zone 11N\",GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\","
  "6378137,298.257223563,AUTHORITY[\"EPSG\",\"7030\"]],AUTHORITY[\"EPSG\",\"6326\"]],"
  "PRIMEM[\"Greenwich\",0,AUTHORITY[\"EPSG\",\"8901\"]],UNIT[\"degree\",0.0174532925199433,"
  "AUTHORITY[\"EPSG\",\"9122\"]],AUTHORITY[\"EPSG\",\"4326\"]],PROJECTION[\"Transverse_"
  "Mercator\"],PARAMETER[\"latitude_of_origin\",0],PARAMETER[\"central_meridian\",-117],"
  "PARAMETER[\"scale_factor\",0.9996],PARAMETER[\"false_easting\",500000],"
  "PARAMETER[\"false_northing\",0],UNIT[\"metre\",1,AUTHORITY[\"EPSG\",\"9001\"]],"
  "AXIS[\"Easting\",EAST],AXIS[\"Northing\",NORTH],AUTHORITY[\"EPSG\",\"32611\"]]";
const double kGeoTransform[6] = { 500000, 10, 0, 4360060, 0, -10 };
const char* const kEPSG32611 = "urn:ogc:def:crs:EPSG::32611";

const std::string kSagehen = std::string(TERROIR_DATA_DIR) + "/sagehen_creek_ca/";

vtkSmartPointer<vtkImageData> SmallTerrain()
{
  auto terrain = terroir_test::MakeTerrain(8, 6, 10.0, 10.0, [](int, int) { return 2000.0; });
  // As vtkTerroirDEMReader sets it: the south-west cell centre.
  terrain->SetOrigin(500005.0, 4360005.0, 0.0);
  vtkTerroirGeoreference::SetCRS(terrain, kUTM11N);
  vtkTerroirGeoreference::SetGeoTransform(terrain, kGeoTransform);
  return terrain;
}

/// A scratch folder of its own for each test (ctest runs tests in parallel).
std::string Scratch()
{
  return terroir::testing::IOScratchFolder(
    std::string("vector_") + ::testing::UnitTest::GetInstance()->current_test_info()->name());
}

/// A GeoJSON FeatureCollection named "soils"; `crs` empty = no "crs" member (RFC 7946: WGS 84
/// longitude, latitude).
std::string WriteGeoJSON(const std::string& path,
  const std::string& crs,
  const std::vector<std::string>& features)
{
  std::ostringstream os;
  os << "{\"type\":\"FeatureCollection\",\"name\":\"soils\",";
  if (!crs.empty())
  {
    os << "\"crs\":{\"type\":\"name\",\"properties\":{\"name\":\"" << crs << "\"}},";
  }
  os << "\"features\":[";
  for (std::size_t k = 0; k < features.size(); ++k)
  {
    os << (k ? ",\n" : "\n") << features[k];
  }
  os << "]}\n";
  EXPECT_TRUE(terroir::testing::WriteTextFile(path, os.str())) << path;
  return path;
}

std::string Feature(const std::string& properties, const std::string& geometry)
{
  return "{\"type\":\"Feature\",\"properties\":{" + properties + "},\"geometry\":" + geometry + "}";
}

std::string Coordinates(const std::vector<std::pair<double, double>>& points)
{
  std::ostringstream os;
  os.precision(15);
  os << "[";
  for (std::size_t k = 0; k < points.size(); ++k)
  {
    os << (k ? "," : "") << "[" << points[k].first << "," << points[k].second << "]";
  }
  os << "]";
  return os.str();
}

/// Axis-aligned rectangle [x0, x1] x [y0, y1] as a GeoJSON polygon.
std::string Rectangle(double x0, double y0, double x1, double y1)
{
  return "{\"type\":\"Polygon\",\"coordinates\":[" +
    Coordinates({ { x0, y0 }, { x1, y0 }, { x1, y1 }, { x0, y1 }, { x0, y0 } }) + "]}";
}

std::string Line(const std::vector<std::pair<double, double>>& points)
{
  return "{\"type\":\"LineString\",\"coordinates\":" + Coordinates(points) + "}";
}

struct Result
{
  vtkSmartPointer<vtkImageData> Image;
  std::string Errors;
  std::string Warnings;
  int ErrorCount = 0;
};

Result Rasterize(vtkTerroirVectorRasterizer* f, vtkImageData* terrain)
{
  vtkNew<terroir_test::ErrorObserver> observer;
  f->AddObserver(vtkCommand::ErrorEvent, observer);
  f->AddObserver(vtkCommand::WarningEvent, observer);
  vtkNew<terroir_test::ErrorObserver> executive; // the executive's "returned failure" line
  f->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, executive);
  f->SetInputData(terrain);
  f->Update();
  f->RemoveObservers(vtkCommand::ErrorEvent);
  f->RemoveObservers(vtkCommand::WarningEvent);
  f->GetExecutive()->RemoveObservers(vtkCommand::ErrorEvent);
  Result r;
  r.Image = vtkSmartPointer<vtkImageData>::New();
  r.Image->ShallowCopy(f->GetOutput());
  r.Errors = observer->Errors;
  r.Warnings = observer->Warnings;
  r.ErrorCount = observer->ErrorCount;
  return r;
}

/// The array as a picture, NORTH row first: a digit for a covered cell holding 1..9, '#' for
/// other covered values, '.' for 0 or NaN.
std::string Picture(vtkImageData* image, const char* name)
{
  vtkDataArray* a = image->GetPointData()->GetArray(name);
  if (!a)
  {
    return "(no array)";
  }
  int extent[6];
  image->GetExtent(extent);
  const int nx = extent[1] - extent[0] + 1;
  std::string out;
  for (int j = extent[3]; j >= extent[2]; --j)
  {
    for (int i = extent[0]; i <= extent[1]; ++i)
    {
      const double v =
        a->GetComponent(static_cast<vtkIdType>(j - extent[2]) * nx + (i - extent[0]), 0);
      const bool integer = v >= 1 && v <= 9 && v == std::floor(v);
      out += std::isnan(v) || v == 0 ? '.' : (integer ? static_cast<char>('0' + v) : '#');
    }
    out += '\n';
  }
  return out;
}

/// Rows given north first, as they are drawn.
std::string Rows(const std::vector<std::string>& northFirst)
{
  std::string out;
  for (const std::string& row : northFirst)
  {
    out += row + "\n";
  }
  return out;
}

/// The Mask picture of the lines or polygons in `path` rasterised onto SmallTerrain() with
/// AllTouched on or off ("(errors) ..." when the filter reported errors); `covered` receives
/// GetNumberOfCoveredCells().
std::string MaskOnSmallTerrain(const std::string& path,
  bool allTouched,
  vtkIdType* covered = nullptr)
{
  vtkNew<vtkTerroirVectorRasterizer> f;
  f->SetFileName(path.c_str());
  f->SetAllTouched(allTouched);
  Result r = Rasterize(f, SmallTerrain());
  if (covered)
  {
    *covered = f->GetNumberOfCoveredCells();
  }
  return r.ErrorCount != 0 ? "(errors) " + r.Errors : Picture(r.Image, "Mask");
}

/// Counts cells where two 0/1 arrays agree; `a` is compared as (value != 0 && !NaN).
struct Agreement
{
  vtkIdType Cells = 0;
  vtkIdType Agree = 0;
  vtkIdType OnlyA = 0;
  vtkIdType OnlyB = 0;
  vtkIdType Both = 0;
};

Agreement Compare(vtkDataArray* a, vtkDataArray* b)
{
  Agreement r;
  r.Cells = a->GetNumberOfTuples();
  for (vtkIdType k = 0; k < r.Cells; ++k)
  {
    const double va = a->GetComponent(k, 0);
    const double vb = b->GetComponent(k, 0);
    const bool inA = va != 0 && !std::isnan(va);
    const bool inB = vb != 0 && !std::isnan(vb);
    r.Agree += inA == inB ? 1 : 0;
    r.OnlyA += inA && !inB ? 1 : 0;
    r.OnlyB += inB && !inA ? 1 : 0;
    r.Both += inA && inB ? 1 : 0;
  }
  return r;
}
} // namespace

TEST(TerroirVectorRasterizer, DefaultsPrintSelfAndModified)
{
  vtkNew<vtkTerroirVectorRasterizer> f;
  EXPECT_EQ(f->GetFileName(), nullptr);
  EXPECT_EQ(f->GetLayerName(), nullptr);
  EXPECT_EQ(f->GetAttributeFilter(), nullptr);
  EXPECT_EQ(f->GetAttributeName(), nullptr);
  EXPECT_EQ(f->GetBurnValue(), 1.0);
  EXPECT_STREQ(f->GetOutputArrayName(), "Mask");
  EXPECT_FALSE(f->GetAllTouched());
  EXPECT_FALSE(f->GetAllowNetworkPaths());
  EXPECT_EQ(f->GetNumberOfInputPorts(), 1);
  EXPECT_EQ(f->GetNumberOfOutputPorts(), 1);
  const vtkMTimeType t0 = f->GetMTime();
  f->SetAllTouched(true);
  EXPECT_GT(f->GetMTime(), t0);
  std::ostringstream os;
  f->Print(os);
  for (const char* name : { "FileName",
         "LayerName",
         "AttributeFilter",
         "BurnValue",
         "AttributeName",
         "OutputArrayName",
         "AllTouched",
         "AllowNetworkPaths",
         "ErrorMessage",
         "NumberOfFeatures",
         "NumberOfCoveredCells" })
  {
    EXPECT_NE(os.str().find(std::string(name) + ":"), std::string::npos) << name;
  }
}

// A square in the north-east quarter: x in [500027, 500053], y in [4360043, 4360057].
// Centres inside: x = 500035, 500045 (i = 3, 4; 500025 and 500055 are outside) and
// y = 4360045, 4360055 (j = 4, 5): the two NORTHERN rows, j = 4 and 5 of 0..5.
// Touched: x overlaps columns 2..5 ([500020, 500030] ... [500050, 500060]), y rows 4..5.
TEST(TerroirVectorRasterizer, PolygonCoversCellCentresInsideAndNorthIsHighJ)
{
  const std::string dir = Scratch();
  const std::string path = WriteGeoJSON(dir + "/square.geojson",
    kEPSG32611,
    { Feature("\"soil\":2", Rectangle(500027, 4360043, 500053, 4360057)) });
  vtkNew<vtkTerroirVectorRasterizer> f;
  f->SetFileName(path.c_str());
  Result r = Rasterize(f, SmallTerrain());
  ASSERT_EQ(r.ErrorCount, 0) << r.Errors;
  EXPECT_EQ(r.Warnings, "");
  vtkDataArray* mask = r.Image->GetPointData()->GetArray("Mask");
  ASSERT_NE(mask, nullptr);
  EXPECT_EQ(mask->GetDataType(), VTK_UNSIGNED_CHAR);
  EXPECT_STREQ(mask->GetInformation()->Get(vtkDataArray::UNITS_LABEL()), "");
  EXPECT_EQ(Picture(r.Image, "Mask"),
    Rows({ "...11...", // j = 5 (north)
      "...11...",      // j = 4
      "........",      // j = 3
      "........",      //
      "........",      //
      "........" }));  // j = 0 (south)
  // Index check without the picture: cell (3, 5) is point 5 * 8 + 3.
  EXPECT_EQ(mask->GetComponent(5 * 8 + 3, 0), 1.0);
  EXPECT_EQ(mask->GetComponent(0 * 8 + 3, 0), 0.0);
  EXPECT_EQ(f->GetNumberOfFeatures(), 1);
  EXPECT_EQ(f->GetNumberOfCoveredCells(), 4);
  // The input passes through.
  EXPECT_NE(r.Image->GetPointData()->GetArray("Elevation"), nullptr);
  EXPECT_EQ(vtkTerroirGeoreference::GetCRS(r.Image), kUTM11N);

  f->AllTouchedOn();
  r = Rasterize(f, SmallTerrain());
  EXPECT_EQ(Picture(r.Image, "Mask"),
    Rows({ "..1111..", "..1111..", "........", "........", "........", "........" }));
}

// A line at y = 4360013 (row j = 1, [4360010, 4360020]) from x = 500012 (column 1) to
// x = 500067 (column 6): the Bresenham path runs from cell (1, 1) to cell (6, 1), and the line
// touches exactly those cells too.
TEST(TerroirVectorRasterizer, LineAlongARowCoversThatRow)
{
  const std::string dir = Scratch();
  const std::string path = WriteGeoJSON(dir + "/line.geojson",
    kEPSG32611,
    { Feature("\"id\":1", Line({ { 500012, 4360013 }, { 500067, 4360013 } })) });
  for (bool allTouched : { false, true })
  {
    EXPECT_EQ(MaskOnSmallTerrain(path, allTouched),
      Rows({ "........", "........", "........", "........", ".111111.", "........" }))
      << "AllTouched " << allTouched;
  }
}

// Lines whose vertices lie 1e12 m away: GDAL's Bresenham walk (AllTouched off) would step
// through every cell in between and overflow int; the filter cuts lines 1024 cells outside the
// terrain first. A horizontal line at y = 4360013 covers row j = 1; a vertical one at x = 500065
// (in a MultiLineString inside a GeometryCollection, beside a small square in the north-west
// cell) covers column 6, whichever way cells are chosen.
TEST(TerroirVectorRasterizer, LinesReachingFarBeyondTheTerrainCoverTheirCells)
{
  const std::string dir = Scratch();
  const std::string vertical = "{\"type\":\"MultiLineString\",\"coordinates\":[" +
    Coordinates({ { 500065, -1e12 }, { 500065, 4360030 }, { 500065, 1e12 } }) + "]}";
  const std::string path = WriteGeoJSON(dir + "/far_lines.geojson",
    kEPSG32611,
    { Feature("\"id\":1", Line({ { -1e12, 4360013 }, { 500040, 4360013 }, { 1e12, 4360013 } })),
      Feature("\"id\":2",
        "{\"type\":\"GeometryCollection\",\"geometries\":[" + vertical + "," +
          Rectangle(500001, 4360051, 500009, 4360059) + "]}") });
  for (bool allTouched : { false, true })
  {
    vtkIdType covered = 0;
    EXPECT_EQ(MaskOnSmallTerrain(path, allTouched, &covered),
      Rows({ "1.....1.", "......1.", "......1.", "......1.", "11111111", "......1." }))
      << "AllTouched " << allTouched;
    EXPECT_EQ(covered, 14);
  }
}

// A diagonal from (500004, 4360004) to (500036, 4360026): in cell units u = (x - 500000) / 10,
// v = (y - 4360000) / 10 it runs from (0.4, 0.4) to (3.6, 2.6), slope 2.2 / 3.2 = 0.6875.
// Bresenham between the end cells (0, 0) and (3, 2) steps once per column, v = 2u/3 rounded:
// (0, 0), (1, 1), (2, 1), (3, 2). The line itself crosses v = 1 at u = 0.4 + 0.6 / 0.6875 =
// 1.27 and v = 2 at u = 0.4 + 1.6 / 0.6875 = 2.73, so it also touches (1, 0) and (2, 2).
TEST(TerroirVectorRasterizer, AllTouchedWidensADiagonalLine)
{
  const std::string dir = Scratch();
  const std::string path = WriteGeoJSON(dir + "/diagonal.geojson",
    kEPSG32611,
    { Feature("\"id\":1", Line({ { 500004, 4360004 }, { 500036, 4360026 } })) });
  vtkNew<vtkTerroirVectorRasterizer> f;
  f->SetFileName(path.c_str());
  Result r = Rasterize(f, SmallTerrain());
  ASSERT_EQ(r.ErrorCount, 0) << r.Errors;
  EXPECT_EQ(Picture(r.Image, "Mask"),
    Rows({ "........", "........", "........", "...1....", ".11.....", "1......." }));
  f->AllTouchedOn();
  r = Rasterize(f, SmallTerrain());
  EXPECT_EQ(Picture(r.Image, "Mask"),
    Rows({ "........", "........", "........", "..11....", ".11.....", "11......" }));
  EXPECT_EQ(f->GetNumberOfCoveredCells(), 6);
}

// Two soil polygons:
// - soil 2: x in [500003, 500027] (centres of columns 0, 1, 2), y in [4360031, 4360058]
//   (centres of rows 3, 4, 5): 9 cells in the north-west;
// - soil 5: x in [500041, 500077] (columns 4..7), y in [4360002, 4360024] (rows 0, 1; the row 2
//   centre 4360025 is outside): 8 cells in the south-east.
// A third feature has a null soil and is left out with a warning.
TEST(TerroirVectorRasterizer, AttributeValuesAndFilter)
{
  const std::string dir = Scratch();
  const std::string path = WriteGeoJSON(dir + "/soils.geojson",
    kEPSG32611,
    { Feature("\"soil\":2,\"name\":\"sandy loam\"", Rectangle(500003, 4360031, 500027, 4360058)),
      Feature("\"soil\":5,\"name\":\"clay\"", Rectangle(500041, 4360002, 500077, 4360024)),
      Feature("\"soil\":null,\"name\":\"unknown\"", Rectangle(500000, 4360000, 500080, 4360060)) });
  vtkNew<vtkTerroirVectorRasterizer> f;
  f->SetFileName(path.c_str());
  f->SetAttributeName("soil");
  f->SetOutputArrayName("SoilType");
  Result r = Rasterize(f, SmallTerrain());
  ASSERT_EQ(r.ErrorCount, 0) << r.Errors;
  EXPECT_NE(
    r.Warnings.find("1 feature(s) of layer 'soils' have no value in 'soil'"), std::string::npos)
    << r.Warnings;
  vtkDataArray* soil = r.Image->GetPointData()->GetArray("SoilType");
  ASSERT_NE(soil, nullptr);
  EXPECT_EQ(soil->GetDataType(), VTK_FLOAT);
  EXPECT_EQ(r.Image->GetPointData()->GetArray("Mask"), nullptr);
  EXPECT_EQ(Picture(r.Image, "SoilType"),
    Rows({ "222.....", "222.....", "222.....", "........", "....5555", "....5555" }));
  EXPECT_TRUE(std::isnan(soil->GetComponent(2 * 8 + 3, 0))); // not covered: NaN, not 0
  EXPECT_EQ(soil->GetComponent(0 * 8 + 7, 0), 5.0);
  EXPECT_EQ(f->GetNumberOfFeatures(), 2);
  EXPECT_EQ(f->GetNumberOfCoveredCells(), 17);

  // The filter keeps the clay polygon only; burning the default 1 gives an unsigned char mask.
  vtkNew<vtkTerroirVectorRasterizer> clay;
  clay->SetFileName(path.c_str());
  clay->SetAttributeFilter("soil = 5");
  r = Rasterize(clay, SmallTerrain());
  ASSERT_EQ(r.ErrorCount, 0) << r.Errors;
  EXPECT_EQ(r.Image->GetPointData()->GetArray("Mask")->GetDataType(), VTK_UNSIGNED_CHAR);
  EXPECT_EQ(Picture(r.Image, "Mask"),
    Rows({ "........", "........", "........", "........", "....1111", "....1111" }));
  EXPECT_EQ(clay->GetNumberOfFeatures(), 1);

  // A string filter on another field.
  clay->SetAttributeFilter("name = 'sandy loam'");
  r = Rasterize(clay, SmallTerrain());
  EXPECT_EQ(Picture(r.Image, "Mask"),
    Rows({ "111.....", "111.....", "111.....", "........", "........", "........" }));
}

// Where features overlap, the later one wins (GDAL's MERGE_ALG=REPLACE): soil 3 over
// x in [500013, 500037] (columns 1..3), y in [4360041, 4360049] (row 4 only) after soil 2 of
// the test above.
TEST(TerroirVectorRasterizer, LaterFeatureWinsWhereFeaturesOverlap)
{
  const std::string dir = Scratch();
  const std::string path = WriteGeoJSON(dir + "/overlap.geojson",
    kEPSG32611,
    { Feature("\"soil\":2", Rectangle(500003, 4360031, 500027, 4360058)),
      Feature("\"soil\":3", Rectangle(500013, 4360041, 500037, 4360049)) });
  vtkNew<vtkTerroirVectorRasterizer> f;
  f->SetFileName(path.c_str());
  f->SetAttributeName("soil");
  Result r = Rasterize(f, SmallTerrain());
  ASSERT_EQ(r.ErrorCount, 0) << r.Errors;
  EXPECT_EQ(Picture(r.Image, "Mask"),
    Rows({ "222.....", "2333....", "222.....", "........", "........", "........" }));
}

// Unsigned char only for the default kind of mask: an integer BurnValue in 1..255 and no
// attribute. Otherwise float, NaN where nothing is burnt.
TEST(TerroirVectorRasterizer, OutputTypeFollowsTheBurnValue)
{
  const std::string dir = Scratch();
  const std::string path = WriteGeoJSON(dir + "/square.geojson",
    kEPSG32611,
    { Feature("\"soil\":2", Rectangle(500027, 4360043, 500053, 4360057)) });
  struct Case
  {
    double Value;
    int Type;
  };
  for (const Case& c : { Case{ 7, VTK_UNSIGNED_CHAR },
         Case{ 255, VTK_UNSIGNED_CHAR },
         Case{ 256, VTK_FLOAT },
         Case{ 0.5, VTK_FLOAT },
         Case{ 0, VTK_FLOAT },
         Case{ -3, VTK_FLOAT } })
  {
    vtkNew<vtkTerroirVectorRasterizer> f;
    f->SetFileName(path.c_str());
    f->SetBurnValue(c.Value);
    Result r = Rasterize(f, SmallTerrain());
    ASSERT_EQ(r.ErrorCount, 0) << r.Errors;
    vtkDataArray* a = r.Image->GetPointData()->GetArray("Mask");
    ASSERT_NE(a, nullptr);
    EXPECT_EQ(a->GetDataType(), c.Type) << c.Value;
    EXPECT_EQ(a->GetComponent(5 * 8 + 3, 0), c.Value) << c.Value;
    const double outside = a->GetComponent(0, 0);
    if (c.Type == VTK_FLOAT)
    {
      EXPECT_TRUE(std::isnan(outside)) << c.Value;
    }
    else
    {
      EXPECT_EQ(outside, 0.0) << c.Value;
    }
    EXPECT_EQ(f->GetNumberOfCoveredCells(), 4) << c.Value;
  }
}

// The square of the first test, corners converted from UTM 11N to WGS 84 longitude, latitude
// with GeographicLib (TransverseMercator::UTM().Reverse, central meridian -117); gdaltransform
// -s_srs EPSG:32611 -t_srs EPSG:4326 gives the same to 1e-11 degrees. Over 26 m the edges'
// curvature is far below a millimetre, and every edge is 2 m or more from a cell centre.
TEST(TerroirVectorRasterizer, LonLatTwinLandsOnTheSameCells)
{
  const std::vector<std::pair<double, double>> ring = { { -116.999686464077, 39.389876061688 },
    { -116.999384540597, 39.389876060482 },
    { -116.999384539488, 39.390002211016 },
    { -116.999686463513, 39.390002212221 },
    { -116.999686464077, 39.389876061688 } };
  const std::string polygon = "{\"type\":\"Polygon\",\"coordinates\":[" + Coordinates(ring) + "]}";
  const std::string dir = Scratch();
  // RFC 7946 GeoJSON (no "crs": WGS 84 longitude, latitude), and the older explicit EPSG:4326,
  // whose official axis order is latitude first: both must be read as longitude, latitude.
  for (const std::string& crs : { std::string(), std::string("urn:ogc:def:crs:EPSG::4326") })
  {
    const std::string path =
      WriteGeoJSON(dir + (crs.empty() ? "/rfc7946.geojson" : "/epsg4326.geojson"),
        crs,
        { Feature("", polygon) });
    vtkNew<vtkTerroirVectorRasterizer> f;
    f->SetFileName(path.c_str());
    Result r = Rasterize(f, SmallTerrain());
    ASSERT_EQ(r.ErrorCount, 0) << r.Errors;
    EXPECT_EQ(r.Warnings, "");
    EXPECT_EQ(Picture(r.Image, "Mask"),
      Rows({ "...11...", "...11...", "........", "........", "........", "........" }))
      << path;
    f->AllTouchedOn();
    r = Rasterize(f, SmallTerrain());
    EXPECT_EQ(Picture(r.Image, "Mask"),
      Rows({ "..1111..", "..1111..", "........", "........", "........", "........" }))
      << path;
  }
}

// A CSV with a WKT column has no CRS: its coordinates are taken as the terrain's, with a warning.
// Points burn the cell that holds them: (500015, 4360025) is cell (1, 2).
TEST(TerroirVectorRasterizer, LayerWithoutCRSIsTakenInTheTerrainCRS)
{
  const std::string dir = Scratch();
  const std::string path = dir + "/soils.csv";
  ASSERT_TRUE(terroir::testing::WriteTextFile(path,
    "WKT,soil\n"
    "\"POLYGON((500027 4360043,500053 4360043,500053 4360057,500027 4360057,500027 4360043))\","
    "2\n"
    "\"POINT(500015 4360025)\",3\n"));
  vtkNew<vtkTerroirVectorRasterizer> f;
  f->SetFileName(path.c_str());
  Result r = Rasterize(f, SmallTerrain());
  ASSERT_EQ(r.ErrorCount, 0) << r.Errors;
  EXPECT_NE(r.Warnings.find(path + ": layer 'soils' has no CRS"), std::string::npos) << r.Warnings;
  EXPECT_EQ(Picture(r.Image, "Mask"),
    Rows({ "...11...", "...11...", "........", ".1......", "........", "........" }));
}

// A cropped terrain (vtkExtractVOI keeps indices and origin) is placed by position: columns
// 2..6 and rows 3..5 of the grid above; the square covers (3..4, 4..5) of the full grid.
TEST(TerroirVectorRasterizer, SubExtentIsPlacedByPosition)
{
  const std::string dir = Scratch();
  const std::string path = WriteGeoJSON(dir + "/square.geojson",
    kEPSG32611,
    { Feature("\"soil\":2", Rectangle(500027, 4360043, 500053, 4360057)) });
  vtkNew<vtkExtractVOI> crop;
  crop->SetInputData(SmallTerrain());
  crop->SetVOI(2, 6, 3, 5, 0, 0);
  vtkNew<vtkTerroirVectorRasterizer> f;
  f->SetFileName(path.c_str());
  f->SetInputConnection(crop->GetOutputPort());
  f->Update();
  EXPECT_STREQ(f->GetErrorMessage(), "");
  vtkImageData* out = f->GetOutput();
  int extent[6];
  out->GetExtent(extent);
  EXPECT_EQ(extent[0], 2);
  EXPECT_EQ(extent[1], 6);
  EXPECT_EQ(extent[2], 3);
  EXPECT_EQ(extent[3], 5);
  EXPECT_EQ(Picture(out, "Mask"), Rows({ ".11..", ".11..", "....." }));

  // The same with a crop reaching the south edge and the square moved south by 30 m (rows 1, 2).
  const std::string south = WriteGeoJSON(dir + "/south.geojson",
    kEPSG32611,
    { Feature("\"soil\":2", Rectangle(500027, 4360013, 500053, 4360027)) });
  crop->SetVOI(1, 5, 0, 3, 0, 0);
  f->SetFileName(south.c_str());
  f->Update();
  EXPECT_STREQ(f->GetErrorMessage(), "");
  EXPECT_EQ(Picture(f->GetOutput(), "Mask"), Rows({ ".....", "..11.", "..11.", "....." }));
}

TEST(TerroirVectorRasterizer, FeaturesOutsideTheTerrainGiveAWarningAndAnEmptyMask)
{
  const std::string dir = Scratch();
  const std::string path = WriteGeoJSON(dir + "/far.geojson",
    kEPSG32611,
    { Feature("\"soil\":2", Rectangle(510000, 4370000, 510100, 4370100)),
      Feature("\"soil\":3", Line({ { 499000, 4360000 }, { 499000, 4361000 } })) });
  vtkNew<vtkTerroirVectorRasterizer> f;
  f->SetFileName(path.c_str());
  Result r = Rasterize(f, SmallTerrain());
  EXPECT_EQ(r.ErrorCount, 0) << r.Errors;
  EXPECT_NE(r.Warnings.find(path + ": none of the 2 features of layer 'soils' covers a cell"),
    std::string::npos)
    << r.Warnings;
  vtkDataArray* mask = r.Image->GetPointData()->GetArray("Mask");
  ASSERT_NE(mask, nullptr);
  EXPECT_EQ(mask->GetRange()[1], 0.0);
  EXPECT_EQ(f->GetNumberOfCoveredCells(), 0);

  // A filter that matches nothing: a warning too.
  f->SetAttributeFilter("soil > 100");
  r = Rasterize(f, SmallTerrain());
  EXPECT_EQ(r.ErrorCount, 0) << r.Errors;
  EXPECT_NE(r.Warnings.find("has no feature with a geometry matching the filter 'soil > 100'"),
    std::string::npos)
    << r.Warnings;
}

// Each bad input gives one error line "<file>: <problem>" and an empty output.
TEST(TerroirVectorRasterizer, ErrorsAreOneLineNamingTheFileWithAnEmptyOutput)
{
  const std::string dir = Scratch();
  const std::string soils = WriteGeoJSON(dir + "/soils.geojson",
    kEPSG32611,
    { Feature("\"soil\":2,\"name\":\"sandy loam\"", Rectangle(500003, 4360031, 500027, 4360058)) });
  const std::string mars = WriteGeoJSON(dir + "/mars.geojson",
    "urn:ogc:def:crs:IAU_2015::49900",
    { Feature("\"soil\":2", Rectangle(10, 10, 11, 11)) });
  const std::string notes = dir + "/notes.geojson";
  ASSERT_TRUE(terroir::testing::WriteTextFile(notes, "these are not features\n"));
  // A layer name with a line break and a tab (JSON escapes): the error stays on one line.
  const std::string brokenName = dir + "/broken_name.geojson";
  ASSERT_TRUE(terroir::testing::WriteTextFile(brokenName,
    "{\"type\":\"FeatureCollection\",\"name\":\"soils\\nof\\tthe valley\",\"features\":[]}\n"));
  const std::string dem = kSagehen + "sagehen_dem_utm11n_10m.tif";
  // Local files that name remote data: an OGR VRT source (read lazily, listed nowhere but in
  // its XML) and a WFS service description. Port 9 (discard) on the loopback: nothing answers.
  const std::string remoteVRT = dir + "/remote.vrt";
  ASSERT_TRUE(terroir::testing::WriteTextFile(remoteVRT,
    "<OGRVRTDataSource><OGRVRTLayer name=\"soils\"><SrcDataSource>"
    "/vsicurl/http://127.0.0.1:9/soils.geojson</SrcDataSource></OGRVRTLayer>"
    "</OGRVRTDataSource>\n"));
  const std::string wfs = dir + "/service.xml";
  ASSERT_TRUE(terroir::testing::WriteTextFile(
    wfs, "<OGRWFSDataSource><URL>http://127.0.0.1:9/wfs?</URL></OGRWFSDataSource>\n"));

  auto bare = terroir_test::MakeTerrain(8, 6, 10.0, 10.0, [](int, int) { return 0.0; });
  auto noCRS = SmallTerrain();
  noCRS->GetFieldData()->RemoveArray(vtkTerroirGeoreference::CRSName());
  auto offGrid = SmallTerrain();
  offGrid->SetOrigin(0.0, 0.0, 0.0);
  // A latitude beyond the pole: PROJ refuses the vertex.
  const std::string beyondPole = WriteGeoJSON(dir + "/beyond_pole.geojson",
    "",
    { Feature("\"soil\":2", Line({ { -117, 39 }, { -117, 95 } })) });
  const std::string fifo = dir + "/pipe.geojson";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  auto rotated = SmallTerrain();
  const double rotatedGT[6] = { 500000, 10, 1, 4360060, 0, -10 };
  vtkTerroirGeoreference::SetGeoTransform(rotated, rotatedGT);
  // A geographic terrain whose extent no longer starts at (0, 0): a crop of a bigger one.
  auto geographicCrop = terroir_test::MakeTerrain(8, 6, 8.0, 10.0, [](int, int) { return 0.0; });
  geographicCrop->SetExtent(2, 9, 0, 5, 0, 0);
  vtkTerroirGeoreference::SetCRS(geographicCrop,
    "GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\",6378137,298.257223563]],"
    "PRIMEM[\"Greenwich\",0],UNIT[\"degree\",0.0174532925199433]]");
  const double geographicGT[6] = { -117.0, 1e-4, 0, 39.0, 0, -1e-4 };
  vtkTerroirGeoreference::SetGeoTransform(geographicCrop, geographicGT);
  auto volume = vtkSmartPointer<vtkImageData>::New();
  volume->SetDimensions(8, 6, 2);
  volume->AllocateScalars(VTK_FLOAT, 1);
  auto resampled = SmallTerrain();
  resampled->SetSpacing(5.0, 5.0, 1.0);

  struct Case
  {
    std::string File;
    std::function<void(vtkTerroirVectorRasterizer*)> Set;
    vtkSmartPointer<vtkImageData> Terrain;
    std::string Expect;
  };
  const std::vector<Case> cases = {
    { dir + "/missing.geojson", nullptr, SmallTerrain(), ": no such file" },
    { notes, nullptr, SmallTerrain(), ": not a vector file OGR can read" },
    { dem, nullptr, SmallTerrain(), ": not a vector file OGR can read" },
    { dir, nullptr, SmallTerrain(), ": not a vector file OGR can read" }, // a folder of none
    { "/vsicurl/https://example.com/soils.geojson",
      nullptr,
      SmallTerrain(),
      ": network and archive paths (/vsicurl/, /vsizip/, http://, ...) are refused" },
    { remoteVRT,
      nullptr,
      SmallTerrain(),
      ": refers to '/vsicurl/http://127.0.0.1:9/soils.geojson', a network or archive path: "
      "refused; turn AllowNetworkPaths on to read it" },
    { wfs,
      nullptr,
      SmallTerrain(),
      ": refers to 'http://127.0.0.1:9/wfs?SERVICE=WFS&REQUEST=GetCapabilities', a network "
      "path: refused; turn AllowNetworkPaths on to read it" },
    { soils,
      [](vtkTerroirVectorRasterizer* f) { f->SetLayerName("rivers"); },
      SmallTerrain(),
      ": no layer 'rivers' (layers: 'soils')" },
    { brokenName,
      [](vtkTerroirVectorRasterizer* f) { f->SetLayerName("rivers"); },
      SmallTerrain(),
      ": no layer 'rivers' (layers: 'soils of the valley')" },
    { soils,
      [](vtkTerroirVectorRasterizer* f) { f->SetAttributeName("ph"); },
      SmallTerrain(),
      ": no attribute 'ph' in layer 'soils' (numeric attributes: 'soil')" },
    { soils,
      [](vtkTerroirVectorRasterizer* f) { f->SetAttributeName("name"); },
      SmallTerrain(),
      ": attribute 'name' of layer 'soils' is a String field, not a number" },
    { soils,
      [](vtkTerroirVectorRasterizer* f) { f->SetAttributeFilter("soil ==== 5"); },
      SmallTerrain(),
      ": invalid attribute filter 'soil ==== 5'" },
    { soils,
      nullptr,
      bare,
      ": the terrain has no georeference (TerroirCRS and TerroirGeoTransform are missing): it "
      "must come from a georeferenced DEM" },
    { soils, nullptr, noCRS, ": the terrain has no georeference (TerroirCRS is missing)" },
    { fifo, nullptr, SmallTerrain(), ": not a regular file" },
    { beyondPole,
      nullptr,
      SmallTerrain(),
      ": feature 0 of layer 'soils' cannot be transformed from WGS 84 to the terrain's CRS "
      "(WGS 84 / UTM zone 11N)" },
    { soils,
      nullptr,
      rotated,
      ": the terrain's TerroirGeoTransform (500000, 10, 1, 4360060, 0, -10) is rotated or "
      "sheared; only north-up grids are supported" },
    { soils,
      nullptr,
      geographicCrop,
      ": the terrain's whole extent starts at (2, 0), not (0, 0): it was cropped after reading" },
    { soils, nullptr, vtkSmartPointer<vtkImageData>::New(), ": the input terrain is empty" },
    { soils, nullptr, volume, ": the input is not a 2-D terrain (an image of nx x ny x 1 points)" },
    { soils, nullptr, offGrid, ": the terrain's origin (0, 0) m is not a cell centre" },
    { soils,
      nullptr,
      resampled,
      ": the terrain's spacing (5, 5) m is not the (10, 10) m of its TerroirGeoTransform" },
    { mars,
      nullptr,
      SmallTerrain(),
      ": cannot transform coordinates from the layer's CRS (Mars (2015) - Sphere / Ocentric) to "
      "the terrain's (WGS 84 / UTM zone 11N)" },
    { soils,
      [](vtkTerroirVectorRasterizer* f) { f->SetBurnValue(std::nan("")); },
      SmallTerrain(),
      ": BurnValue nan is not a finite number" },
  };
  for (const Case& c : cases)
  {
    vtkNew<vtkTerroirVectorRasterizer> f;
    f->SetFileName(c.File.c_str());
    if (c.Set)
    {
      c.Set(f);
    }
    Result r = Rasterize(f, c.Terrain);
    const std::string message = f->GetErrorMessage();
    EXPECT_EQ(r.ErrorCount, 1) << c.File << c.Expect << "\n" << r.Errors;
    EXPECT_EQ(message.rfind(c.File + c.Expect, 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_NE(r.Errors.find(message), std::string::npos) << r.Errors;
    EXPECT_EQ(r.Image->GetNumberOfPoints(), 0) << c.Expect;
  }
}

// The MEM raster and the output array, 1 byte per cell each for a mask: 96 B for 8 x 6 cells.
TEST(TerroirVectorRasterizer, RefusesBeforeAllocatingWhenMemoryIsShort)
{
  const std::string dir = Scratch();
  const std::string path = WriteGeoJSON(dir + "/square.geojson",
    kEPSG32611,
    { Feature("\"soil\":2", Rectangle(500027, 4360043, 500053, 4360057)) });
  terroir_test::ScopedEnvironment limit("TERROIR_MEMORY_LIMIT", "50");
  vtkNew<vtkTerroirVectorRasterizer> f;
  f->SetFileName(path.c_str());
  Result r = Rasterize(f, SmallTerrain());
  EXPECT_EQ(r.ErrorCount, 1) << r.Errors;
  EXPECT_EQ(std::string(f->GetErrorMessage()),
    path +
      ": not enough memory for rasterising the layer: needs 96 B, 50 B available "
      "(TERROIR_MEMORY_LIMIT)");
  EXPECT_EQ(r.Image->GetNumberOfPoints(), 0);
}

// The bundled watershed polygon and NHD flowlines against the masks shipped with the data, which
// PROVENANCE.md says were made by `gdal_rasterize -burn 1 -init 0 -ot Byte -te 213980 4366470
// 221840 4373670 -tr 10 10` (cell centres, not ALL_TOUCHED) on the UTM DEM's grid.
TEST(TerroirVectorRasterizer, SagehenMatchesTheShippedGdalRasterizeMasks)
{
  auto dem = terroir_test::ReadDEM(kSagehen + "sagehen_dem_utm11n_10m.tif");
  ASSERT_NE(dem, nullptr);
  struct Case
  {
    const char* Vector;
    const char* Mask;
    vtkIdType MaskCells; // PROVENANCE.md
  };
  for (const Case& c :
    { Case{ "sagehen_watershed_utm11n.geojson", "sagehen_watershed_mask_utm11n_10m.tif", 277180 },
      Case{
        "sagehen_nhd_flowlines_utm11n.geojson", "sagehen_nhd_streams_mask_utm11n_10m.tif", 6668 } })
  {
    auto shipped = terroir_test::ReadDEM(kSagehen + c.Mask);
    ASSERT_NE(shipped, nullptr) << c.Mask;
    vtkNew<vtkTerroirVectorRasterizer> f;
    f->SetFileName((kSagehen + c.Vector).c_str());
    const auto t0 = std::chrono::steady_clock::now();
    Result r = Rasterize(f, dem);
    const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::cout << "[ timing ] " << c.Vector << " onto 786 x 720 cells: " << seconds * 1e3 << " ms\n";
    ASSERT_EQ(r.ErrorCount, 0) << r.Errors;
    EXPECT_EQ(r.Warnings, "");
    vtkDataArray* ours = r.Image->GetPointData()->GetArray("Mask");
    vtkDataArray* theirs = shipped->GetPointData()->GetArray("Elevation");
    ASSERT_NE(ours, nullptr);
    ASSERT_EQ(ours->GetNumberOfTuples(), 786 * 720);
    ASSERT_EQ(theirs->GetNumberOfTuples(), 786 * 720);
    const Agreement a = Compare(ours, theirs);
    EXPECT_EQ(a.Both + a.OnlyB, c.MaskCells) << c.Mask;
    const double agreement = static_cast<double>(a.Agree) / a.Cells;
    const double ofMask = 1.0 - static_cast<double>(a.OnlyA + a.OnlyB) / c.MaskCells;
    std::cout << "[ measured ] " << c.Vector << ": " << a.Agree << " of " << a.Cells
              << " cells agree (" << 100.0 * agreement << " %); " << a.OnlyA << " cells only ours, "
              << a.OnlyB << " only the shipped mask (" << 100.0 * ofMask << " % of its "
              << c.MaskCells << " cells)\n";
    EXPECT_GE(agreement, 0.995) << c.Vector;
    // Stricter, since the mask is a small part of the grid (streams: 1.2 %): the cells that
    // differ are at most 0.5 % of the mask's.
    EXPECT_GE(ofMask, 0.995) << c.Vector;
  }
}

// The flowlines converted by ogr2ogr to a GeoPackage in NAD83 longitude, latitude (EPSG:4269)
// come back onto the UTM grid through the layer's CRS and still match the shipped mask. A
// GeoPackage accepts any filter and compiles it when the features are read: still reported as
// an invalid filter.
TEST(TerroirVectorRasterizer, GeoPackageInGeographicCoordinates)
{
  TERROIR_REQUIRE_PEER_OR_SKIP(
    terroir::testing::PathExists("/usr/bin/ogr2ogr"), "no /usr/bin/ogr2ogr (Debian gdal-bin)");
  const std::string dir = Scratch();
  const std::string gpkg = dir + "/flowlines_nad83.gpkg";
  ASSERT_EQ(terroir_test::RunCommand("/usr/bin/ogr2ogr -q -f GPKG -t_srs EPSG:4269 '" + gpkg +
              "' '" + kSagehen + "sagehen_nhd_flowlines_utm11n.geojson'"),
    0);
  auto dem = terroir_test::ReadDEM(kSagehen + "sagehen_dem_utm11n_10m.tif");
  auto shipped = terroir_test::ReadDEM(kSagehen + "sagehen_nhd_streams_mask_utm11n_10m.tif");
  ASSERT_NE(dem, nullptr);
  ASSERT_NE(shipped, nullptr);
  vtkNew<vtkTerroirVectorRasterizer> f;
  f->SetFileName(gpkg.c_str());
  Result r = Rasterize(f, dem);
  ASSERT_EQ(r.ErrorCount, 0) << r.Errors;
  EXPECT_EQ(f->GetNumberOfFeatures(), 182); // PROVENANCE.md
  const Agreement a = Compare(
    r.Image->GetPointData()->GetArray("Mask"), shipped->GetPointData()->GetArray("Elevation"));
  std::cout << "[ measured ] flowlines via NAD83 GeoPackage: " << a.OnlyA << " cells only ours, "
            << a.OnlyB << " only the shipped mask (of 6668)\n";
  EXPECT_LE(a.OnlyA + a.OnlyB, 6668 / 200);

  f->SetAttributeFilter("FCODE ===");
  r = Rasterize(f, dem);
  EXPECT_EQ(r.ErrorCount, 1);
  EXPECT_EQ(
    std::string(f->GetErrorMessage()).rfind(gpkg + ": invalid attribute filter 'FCODE ==='", 0), 0u)
    << f->GetErrorMessage();
}

// The geographic path: the UTM watershed onto the NAD83 geographic DEM (1026 x 734 cells of
// 1/3 arc-second, placed by index). Reference, independent of GDAL and PROJ: each geographic
// cell centre projected to UTM 11N with GeographicLib (GRS80, k0 = 0.9996, lon0 = -117) and
// looked up in the shipped UTM mask. Only cells near the outline can differ (a UTM cell centre
// is within 7.1 m of any point of its cell): with a ~30 km outline and a band of a few metres,
// some 0.3 % of the watershed's 337,000 cells. The bound is 0.5 %: a grid shifted by one row
// would add about as many cells as the outline is long in cells (the shipped UTM mask shifted
// by one row differs in 1,626 cells), a flipped one over 100,000 (UTM mask: 167,808).
TEST(TerroirVectorRasterizer, GeographicTerrainAgreesWithTheUTMMask)
{
  auto geographic = terroir_test::ReadDEM(kSagehen + "ned10m_nad83.img");
  auto utmMask = terroir_test::ReadDEM(kSagehen + "sagehen_watershed_mask_utm11n_10m.tif");
  ASSERT_NE(geographic, nullptr);
  ASSERT_NE(utmMask, nullptr);
  vtkNew<vtkTerroirVectorRasterizer> f;
  f->SetFileName((kSagehen + "sagehen_watershed_utm11n.geojson").c_str());
  Result r = Rasterize(f, geographic);
  ASSERT_EQ(r.ErrorCount, 0) << r.Errors;
  vtkDataArray* ours = r.Image->GetPointData()->GetArray("Mask");
  ASSERT_NE(ours, nullptr);

  double gt[6];
  ASSERT_TRUE(vtkTerroirGeoreference::GetGeoTransform(geographic, gt));
  vtkDataArray* reference = utmMask->GetPointData()->GetArray("Elevation");
  const GeographicLib::TransverseMercator tm(6378137.0, 1.0 / 298.257222101, 0.9996);
  vtkIdType differ = 0, inside = 0;
  for (int j = 0; j < 734; ++j)
  {
    const int gdalRow = 733 - j;
    const double lat = gt[3] + (gdalRow + 0.5) * gt[5];
    for (int i = 0; i < 1026; ++i)
    {
      const double lon = gt[0] + (i + 0.5) * gt[1];
      double x = 0, y = 0;
      tm.Forward(-117.0, lat, lon, x, y);
      x += 500000.0;
      const int col = static_cast<int>(std::floor((x - 213980.0) / 10.0));
      const int row = static_cast<int>(std::floor((4373670.0 - y) / 10.0));
      double expected = 0.0;
      if (col >= 0 && col < 786 && row >= 0 && row < 720)
      {
        expected = reference->GetComponent(static_cast<vtkIdType>(719 - row) * 786 + col, 0);
      }
      const bool got = ours->GetComponent(static_cast<vtkIdType>(j) * 1026 + i, 0) != 0;
      inside += expected != 0 ? 1 : 0;
      differ += got != (expected != 0) ? 1 : 0;
    }
  }
  std::cout << "[ measured ] watershed on the geographic grid: " << f->GetNumberOfCoveredCells()
            << " cells (PROVENANCE.md: 337,636); " << differ << " differ from the UTM mask ("
            << 100.0 * differ / inside << " % of " << inside << ")\n";
  EXPECT_LE(differ, inside / 200) << "more than 0.5 % of the watershed's cells differ";
  EXPECT_NEAR(static_cast<double>(f->GetNumberOfCoveredCells()), 337636.0, 0.005 * 337636.0);
}

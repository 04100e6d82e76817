// Pipeline tests of vtkTerroirDEMReader on the bundled rasters and on hand-written bad files.
#include "TerroirFilterTestUtilities.h"
#include "TerroirIOTestUtilities.h"
#include "vtkTerroirDEMReader.h"
#include "vtkTerroirGeoreference.h"

#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkExtentTranslator.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <string>
#include <sys/stat.h>

namespace
{
const std::string kUTM =
  std::string(TERROIR_DATA_DIR) + "/sagehen_creek_ca/sagehen_dem_utm11n_10m.tif";
const std::string kGeographic =
  std::string(TERROIR_DATA_DIR) + "/sagehen_creek_ca/ned10m_nad83.img";
const std::string kFeet =
  std::string(TERROIR_DATA_DIR) + "/san_francisco_usgs_dem/sanfranciscos.dem";
constexpr double kPi = 3.14159265358979323846;

float ElevationAt(vtkImageData* img, int i, int j)
{
  int dims[3];
  img->GetDimensions(dims);
  return static_cast<float>(img->GetPointData()
                              ->GetArray("Elevation")
                              ->GetComponent(static_cast<vtkIdType>(j) * dims[0] + i, 0));
}

// Reads `path`, expects failure; returns the error message and checks the output is empty.
std::string ExpectFailure(vtkTerroirDEMReader* reader, const std::string& path)
{
  reader->SetFileName(path.c_str());
  reader->Update();
  EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 0) << path;
  const std::string message = reader->GetErrorMessage();
  EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  return message;
}
} // namespace

TEST(TerroirDEMReader, UTMGeoTIFFGeoreference)
{
  vtkNew<vtkTerroirDEMReader> reader;
  reader->SetFileName(kUTM.c_str());
  const auto t0 = std::chrono::steady_clock::now();
  reader->Update();
  const double seconds =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::cout << "[ timing ] read " << kUTM << " (786 x 720): " << seconds * 1e3 << " ms\n";
  EXPECT_STREQ(reader->GetErrorMessage(), "");
  vtkImageData* img = reader->GetOutput();
  int dims[3];
  img->GetDimensions(dims);
  EXPECT_EQ(dims[0], 786);
  EXPECT_EQ(dims[1], 720);
  EXPECT_EQ(dims[2], 1);
  double spacing[3], origin[3];
  img->GetSpacing(spacing);
  img->GetOrigin(origin);
  EXPECT_DOUBLE_EQ(spacing[0], 10.0);
  EXPECT_DOUBLE_EQ(spacing[1], 10.0);
  // South-west cell centre: west edge 213980 + 5; south edge 4373670 - 720*10 = 4366470, + 5.
  EXPECT_DOUBLE_EQ(origin[0], 213985.0);
  EXPECT_DOUBLE_EQ(origin[1], 4366475.0);
  const std::string crs = vtkTerroirGeoreference::GetCRS(img);
  EXPECT_NE(crs.find("UTM zone 11N"), std::string::npos) << crs;
  double gt[6];
  ASSERT_TRUE(vtkTerroirGeoreference::GetGeoTransform(img, gt));
  const double gtExpected[6] = { 213980, 10, 0, 4373670, 0, -10 };
  for (int k = 0; k < 6; ++k)
  {
    EXPECT_DOUBLE_EQ(gt[k], gtExpected[k]);
  }
  EXPECT_EQ(vtkTerroirGeoreference::GetSourceFile(img), kUTM);
  EXPECT_EQ(img->GetPointData()->GetArray("vtkValidPointMask"), nullptr); // no nodata cells
  vtkDataArray* elev = img->GetPointData()->GetArray("Elevation");
  ASSERT_NE(elev, nullptr);
  EXPECT_EQ(elev->GetDataType(), VTK_FLOAT);
  EXPECT_STREQ(elev->GetInformation()->Get(vtkDataArray::UNITS_LABEL()), "m");
  // gdallocationinfo -valonly <tif> X Y (pixel X, line Y from the north) gives:
  //   (100, 200) 2178.1162109375, (0, 0) 2259.97094726562, (785, 719) 1965.23754882812.
  // Line Y is image row j = 719 - Y.
  EXPECT_FLOAT_EQ(ElevationAt(img, 100, 719 - 200), 2178.1162109375f);
  EXPECT_FLOAT_EQ(ElevationAt(img, 0, 719), 2259.97094726562f);
  EXPECT_FLOAT_EQ(ElevationAt(img, 785, 0), 1965.23754882812f);

  // Centre (217910 E, 4370070 N): `gdaltransform -s_srs EPSG:26911 -t_srs EPSG:4269` gives
  // -120.277471320998, 39.4340205438458.
  double ll[2];
  ASSERT_TRUE(vtkTerroirGeoreference::GetCenterLatLon(img, ll));
  EXPECT_NEAR(ll[0], 39.4340205438458, 1e-9);
  EXPECT_NEAR(ll[1], -120.277471320998, 1e-9);

  // Meridian convergence from the transverse Mercator series (Snyder 1987, "Map Projections:
  // A Working Manual", USGS PP 1395, p. 62, with the CRS ellipsoid GRS80):
  //   gamma = dl sin(phi) [1 + dl^2 cos^2(phi)/3 (1 + 3 eta^2 + 2 eta^4)
  //                          + dl^4 cos^4(phi)/15 (2 - tan^2(phi))],
  //   dl = lon - lon0 (zone 11: lon0 = -117 deg), eta^2 = e'^2 cos^2(phi).
  const double f = 1.0 / 298.257222101;
  const double e2 = f * (2 - f);
  const double ep2 = e2 / (1 - e2);
  const double phi = ll[0] * kPi / 180.0;
  const double dl = (ll[1] + 117.0) * kPi / 180.0;
  const double c = std::cos(phi), s = std::sin(phi), t = std::tan(phi);
  const double eta2 = ep2 * c * c;
  const double gamma = dl * s *
    (1.0 + dl * dl * c * c / 3.0 * (1.0 + 3.0 * eta2 + 2.0 * eta2 * eta2) +
      std::pow(dl, 4) * std::pow(c, 4) / 15.0 * (2.0 - t * t));
  ASSERT_TRUE(vtkTerroirGeoreference::HasMeridianConvergence(img));
  const double gammaDeg = gamma * 180.0 / kPi;
  EXPECT_NEAR(vtkTerroirGeoreference::GetMeridianConvergence(img), gammaDeg, 1e-6);
  // West of the central meridian in the northern hemisphere grid north points west of true
  // north: negative convergence, about -2.08 degrees here.
  EXPECT_LT(gammaDeg, -2.0);
}

TEST(TerroirDEMReader, RequestInformationReportsExtentWithoutPixels)
{
  vtkNew<vtkTerroirDEMReader> reader;
  reader->SetFileName(kUTM.c_str());
  reader->UpdateInformation();
  vtkInformation* info = reader->GetOutputInformation(0);
  int extent[6];
  info->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent);
  EXPECT_EQ(extent[1], 785);
  EXPECT_EQ(extent[3], 719);
  double spacing[3], origin[3];
  info->Get(vtkDataObject::SPACING(), spacing);
  info->Get(vtkDataObject::ORIGIN(), origin);
  EXPECT_DOUBLE_EQ(spacing[0], 10.0);
  EXPECT_DOUBLE_EQ(origin[0], 213985.0);
  EXPECT_DOUBLE_EQ(origin[1], 4366475.0);
  EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 0); // nothing read yet
}

TEST(TerroirDEMReader, GeographicImgRowSpacing)
{
  vtkNew<vtkTerroirDEMReader> reader;
  reader->SetFileName(kGeographic.c_str());
  reader->Update();
  EXPECT_STREQ(reader->GetErrorMessage(), "");
  vtkImageData* img = reader->GetOutput();
  int dims[3];
  img->GetDimensions(dims);
  ASSERT_EQ(dims[0], 1026);
  ASSERT_EQ(dims[1], 734);
  double origin[3];
  img->GetOrigin(origin);
  EXPECT_EQ(origin[0], 0.0);
  EXPECT_EQ(origin[1], 0.0);
  double ll[2];
  ASSERT_TRUE(vtkTerroirGeoreference::GetCenterLatLon(img, ll));
  EXPECT_NEAR(ll[0], 39.434, 1e-9); // gdalinfo "Center (-120.2775000, 39.4340000)"
  EXPECT_NEAR(ll[1], -120.2775, 1e-9);
  EXPECT_EQ(vtkTerroirGeoreference::GetMeridianConvergence(img), 0.0);
  // gdallocationinfo: (100, 200) 2346.2705078125, (0, 0) 2225.89013671875; 734 rows.
  EXPECT_FLOAT_EQ(ElevationAt(img, 100, 733 - 200), 2346.2705078125f);
  EXPECT_FLOAT_EQ(ElevationAt(img, 0, 733), 2225.89013671875f);

  double gt[6];
  ASSERT_TRUE(vtkTerroirGeoreference::GetGeoTransform(img, gt));
  vtkDoubleArray* rows = vtkTerroirGeoreference::GetRowSpacing(img);
  ASSERT_NE(rows, nullptr);
  ASSERT_EQ(rows->GetNumberOfTuples(), 734);
  // Independent formulas on GRS80: dx = N(phi) cos(phi) dlambda, dy = M(phi) dphi with
  // N = a / sqrt(1 - e^2 sin^2), M = a (1 - e^2) / (1 - e^2 sin^2)^(3/2).
  const double a = 6378137.0;
  const double f = 1.0 / 298.257222101;
  const double e2 = f * (2 - f);
  const double dLambda = gt[1] * kPi / 180.0;
  const double dPhi = -gt[5] * kPi / 180.0;
  for (int j : { 0, 367, 733 })
  {
    const int gdalRow = 733 - j;
    const double lat = gt[3] + (gdalRow + 0.5) * gt[5];
    const double phi = lat * kPi / 180.0;
    const double w = 1.0 - e2 * std::sin(phi) * std::sin(phi);
    const double n = a / std::sqrt(w);
    const double m = a * (1.0 - e2) / (w * std::sqrt(w));
    EXPECT_NEAR(rows->GetComponent(j, 0), n * std::cos(phi) * dLambda, 1e-3) << "row " << j;
    EXPECT_NEAR(rows->GetComponent(j, 1), m * dPhi, 1e-3) << "row " << j;
  }
  // Spacing is the centre row's: about 7.97 m x 10.29 m (PROVENANCE.md rounds to 7.96).
  double spacing[3];
  img->GetSpacing(spacing);
  EXPECT_DOUBLE_EQ(spacing[0], rows->GetComponent(367, 0));
  EXPECT_DOUBLE_EQ(spacing[1], rows->GetComponent(367, 1));
  EXPECT_NEAR(spacing[0], 7.97, 0.01);
  EXPECT_NEAR(spacing[1], 10.29, 0.01);
  // East-west spacing shrinks northwards.
  EXPECT_GT(rows->GetComponent(0, 0), rows->GetComponent(733, 0));
}

// The Shellmound DEM is in feet without saying so. `gdallocationinfo -valonly
// meras_100m_dem.tif 200 150` prints 131.643310546875 (feet); its 341 rows put GDAL's row 150
// at j = 190.
TEST(TerroirDEMReader, VerticalUnitOverridesMissingMetadata)
{
  const std::string path = std::string(TERROIR_DATA_DIR) + "/shellmound_ms/meras_100m_dem.tif";
  const double raw = 131.643310546875;
  const struct
  {
    int unit;
    double metresPerUnit;
  } cases[] = { { vtkTerroirDEMReader::VERTICAL_UNIT_AUTO, 1.0 },
    { vtkTerroirDEMReader::VERTICAL_UNIT_METRE, 1.0 },
    { vtkTerroirDEMReader::VERTICAL_UNIT_FOOT, 0.3048 },
    { vtkTerroirDEMReader::VERTICAL_UNIT_US_FOOT, 1200.0 / 3937.0 } };
  for (const auto& c : cases)
  {
    vtkNew<vtkTerroirDEMReader> reader;
    reader->SetFileName(path.c_str());
    reader->SetVerticalUnit(c.unit);
    reader->Update();
    EXPECT_STREQ(reader->GetErrorMessage(), "");
    EXPECT_DOUBLE_EQ(reader->GetVerticalUnitToMetres(), c.metresPerUnit) << c.unit;
    EXPECT_FLOAT_EQ(
      ElevationAt(reader->GetOutput(), 200, 340 - 150), static_cast<float>(raw * c.metresPerUnit))
      << c.unit;
  }
}

// A file that declares feet (the USGS .dem) read with VerticalUnit = metre keeps the raw values
// and says that it overrode the file.
TEST(TerroirDEMReader, VerticalUnitOverridesDeclaredFeetWithWarning)
{
  vtkNew<vtkTerroirDEMReader> reader;
  vtkNew<terroir_test::ErrorObserver> observer;
  reader->AddObserver(vtkCommand::WarningEvent, observer);
  reader->SetFileName(kFeet.c_str());
  reader->SetVerticalUnitToMetre();
  reader->Update();
  EXPECT_STREQ(reader->GetErrorMessage(), "");
  EXPECT_DOUBLE_EQ(reader->GetVerticalUnitToMetres(), 1.0);
  EXPECT_FLOAT_EQ(ElevationAt(reader->GetOutput(), 100, 465 - 200), 242.0f);
  EXPECT_NE(observer->Warnings.find("replaced by VerticalUnit"), std::string::npos)
    << observer->Warnings;
}

TEST(TerroirDEMReader, USGSDemInFeetConvertedToMetres)
{
  vtkNew<vtkTerroirDEMReader> reader;
  reader->SetFileName(kFeet.c_str());
  reader->Update();
  EXPECT_STREQ(reader->GetErrorMessage(), "");
  vtkImageData* img = reader->GetOutput();
  int dims[3];
  img->GetDimensions(dims);
  ASSERT_EQ(dims[0], 371);
  ASSERT_EQ(dims[1], 466);
  EXPECT_DOUBLE_EQ(reader->GetVerticalUnitToMetres(), 0.3048);
  // `gdallocationinfo -valonly sanfranciscos.dem 100 200` prints 242 (feet).
  EXPECT_FLOAT_EQ(ElevationAt(img, 100, 465 - 200), static_cast<float>(242 * 0.3048));
  // Horizontal units are metres (UTM 10N, NAD27): 30 m cells, origin = SW cell centre.
  double spacing[3], origin[3];
  img->GetSpacing(spacing);
  img->GetOrigin(origin);
  EXPECT_DOUBLE_EQ(spacing[0], 30.0);
  EXPECT_DOUBLE_EQ(origin[0], 544035.0 + 15.0);
  EXPECT_DOUBLE_EQ(origin[1], 4178085.0 - 465.5 * 30.0);
  // Corner cells hold the nodata value -32767 (gdallocationinfo 0 0 / 370 465).
  vtkDataArray* mask = img->GetPointData()->GetArray("vtkValidPointMask");
  ASSERT_NE(mask, nullptr);
  EXPECT_EQ(mask->GetDataType(), VTK_UNSIGNED_CHAR);
  EXPECT_EQ(mask->GetComponent(465 * 371 + 0, 0), 0.0);
  EXPECT_TRUE(std::isnan(ElevationAt(img, 0, 465)));
  EXPECT_EQ(mask->GetComponent(265 * 371 + 100, 0), 1.0);
}

TEST(TerroirDEMReader, AsciiGridOrientationNodataAndMissingCRS)
{
  const std::string dir = terroir::testing::IOScratchFolder("dem_ascii");
  const std::string path = dir + "/small.asc";
  ASSERT_TRUE(terroir::testing::WriteTextFile(
    path, terroir::testing::AsciiGrid(3, 2, 1000, 2000, 25, -9999, { "1 2 3", "4 -9999 6" })));
  vtkNew<vtkTerroirDEMReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  EXPECT_STREQ(reader->GetErrorMessage(), ""); // no CRS: a warning only
  vtkImageData* img = reader->GetOutput();
  ASSERT_EQ(img->GetNumberOfPoints(), 6);
  double spacing[3], origin[3];
  img->GetSpacing(spacing);
  img->GetOrigin(origin);
  EXPECT_EQ(spacing[0], 25.0);
  EXPECT_EQ(origin[0], 1012.5);
  EXPECT_EQ(origin[1], 2012.5);
  EXPECT_EQ(ElevationAt(img, 0, 0), 4.0f); // first text row is the north one
  EXPECT_EQ(ElevationAt(img, 2, 1), 3.0f);
  EXPECT_TRUE(std::isnan(ElevationAt(img, 1, 0)));
  vtkDataArray* mask = img->GetPointData()->GetArray("vtkValidPointMask");
  ASSERT_NE(mask, nullptr);
  const double expectedMask[6] = { 1, 0, 1, 1, 1, 1 };
  for (int k = 0; k < 6; ++k)
  {
    EXPECT_EQ(mask->GetComponent(k, 0), expectedMask[k]) << k;
  }
  EXPECT_TRUE(vtkTerroirGeoreference::GetCRS(img).empty());

  reader->RequireGeoreferenceOn();
  const std::string m = ExpectFailure(reader, path);
  EXPECT_NE(m.find("no coordinate reference system"), std::string::npos) << m;
}

TEST(TerroirDEMReader, RejectsBadFiles)
{
  const std::string dir = terroir::testing::IOScratchFolder("dem_bad");
  vtkNew<vtkTerroirDEMReader> reader;

  std::string m = ExpectFailure(reader, dir + "/missing.tif");
  EXPECT_NE(m.find("no such file"), std::string::npos) << m;

  const std::string text = dir + "/notraster.tif";
  terroir::testing::WriteTextFile(text, "this is not a raster\n");
  m = ExpectFailure(reader, text);
  EXPECT_NE(m.find("not a raster GDAL can read"), std::string::npos) << m;

  const std::string allNodata = dir + "/nodata.asc";
  terroir::testing::WriteTextFile(
    allNodata, terroir::testing::AsciiGrid(2, 2, 0, 0, 1, -9999, { "-9999 -9999", "-9999 -9999" }));
  m = ExpectFailure(reader, allNodata);
  EXPECT_NE(m.find("every cell is no-data"), std::string::npos) << m;

  const std::string ok = dir + "/ok.asc";
  terroir::testing::WriteTextFile(
    ok, terroir::testing::AsciiGrid(3, 2, 0, 0, 10, -9999, { "1 2 3", "4 5 6" }));
  reader->SetMaxCells(5);
  m = ExpectFailure(reader, ok);
  EXPECT_NE(m.find("exceeds MaxCells = 5"), std::string::npos) << m;
  reader->SetMaxCells(6);
  reader->SetBand(2);
  m = ExpectFailure(reader, ok);
  EXPECT_NE(m.find("band 2 requested, the file has 1"), std::string::npos) << m;
  reader->SetBand(1);

  // A VRT over the small grid with a rotated geotransform.
  const std::string rotated = dir + "/rotated.vrt";
  terroir::testing::WriteTextFile(
    rotated, terroir::testing::SimpleVRT(3, 2, "0, 10, 2, 20, 1, -10", "ok.asc"));
  m = ExpectFailure(reader, rotated);
  EXPECT_NE(m.find("rotated or sheared geotransform"), std::string::npos) << m;

  for (const std::string& remote : { std::string("/vsicurl/https://example.com/dem.tif"),
         std::string("https://example.com/dem.tif"),
         std::string("/vsizip/") + dir + "/a.zip/dem.tif" })
  {
    m = ExpectFailure(reader, remote);
    EXPECT_NE(m.find("AllowNetworkPaths"), std::string::npos) << m;
  }

  // After the failures a good file reads again, and the message is cleared.
  reader->SetFileName(ok.c_str());
  reader->Update();
  EXPECT_STREQ(reader->GetErrorMessage(), "");
  EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 6);
}

namespace
{
std::string CustomTransverseMercator(const char* unit)
{
  return std::string("PROJCS[\"custom TM\",GEOGCS[\"NAD83\",DATUM[\"North_American_Datum_1983\","
                     "SPHEROID[\"GRS 1980\",6378137,298.257222101]],PRIMEM[\"Greenwich\",0],"
                     "UNIT[\"degree\",0.0174532925199433]],PROJECTION[\"Transverse_Mercator\"],"
                     "PARAMETER[\"latitude_of_origin\",0],PARAMETER[\"central_meridian\",-117],"
                     "PARAMETER[\"scale_factor\",0.9995],PARAMETER[\"false_easting\",500000],"
                     "PARAMETER[\"false_northing\",0],") +
    unit + "]";
}
} // namespace

TEST(TerroirDEMReader, NonUTMProjectionConvergenceAndFeet)
{
  // A transverse Mercator that is not UTM (k0 = 0.9995) takes the general path (OGR +
  // geodesic azimuth); the convergence does not depend on k0, so the Snyder series applies.
  const std::string dir = terroir::testing::IOScratchFolder("dem_tm");
  const std::string path = dir + "/tm.asc";
  terroir::testing::WriteTextFile(path,
    terroir::testing::AsciiGrid(3, 3, 217895, 4370055, 10, -9999, { "1 2 3", "4 5 6", "7 8 9" }));
  terroir::testing::WriteTextFile(dir + "/tm.prj", CustomTransverseMercator("UNIT[\"metre\",1]"));
  vtkNew<vtkTerroirDEMReader> reader;
  reader->SetFileName(path.c_str());
  reader->RequireGeoreferenceOn();
  reader->Update();
  ASSERT_STREQ(reader->GetErrorMessage(), "");
  vtkImageData* img = reader->GetOutput();
  double ll[2];
  ASSERT_TRUE(vtkTerroirGeoreference::GetCenterLatLon(img, ll));
  EXPECT_NEAR(ll[0], 39.438, 0.01); // k0 = 0.9995 moves it ~440 m north of the UTM point
  const double f = 1.0 / 298.257222101;
  const double e2 = f * (2 - f);
  const double ep2 = e2 / (1 - e2);
  const double phi = ll[0] * kPi / 180.0;
  const double dl = (ll[1] + 117.0) * kPi / 180.0;
  const double c = std::cos(phi), s = std::sin(phi), t = std::tan(phi);
  const double eta2 = ep2 * c * c;
  const double gamma = dl * s *
    (1.0 + dl * dl * c * c / 3.0 * (1.0 + 3.0 * eta2 + 2.0 * eta2 * eta2) +
      std::pow(dl, 4) * std::pow(c, 4) / 15.0 * (2.0 - t * t));
  EXPECT_NEAR(vtkTerroirGeoreference::GetMeridianConvergence(img), gamma * 180.0 / kPi, 1e-6);
  double origin[3];
  img->GetOrigin(origin);
  EXPECT_EQ(origin[0], 217900.0);

  // The same grid with the CRS in US survey feet: spacing and origin converted to metres.
  terroir::testing::WriteTextFile(
    dir + "/tm.prj", CustomTransverseMercator("UNIT[\"US survey foot\",0.304800609601219]"));
  reader->Modified();
  reader->Update();
  ASSERT_STREQ(reader->GetErrorMessage(), "");
  double spacing[3];
  reader->GetOutput()->GetSpacing(spacing);
  reader->GetOutput()->GetOrigin(origin);
  EXPECT_NEAR(spacing[0], 10 * 0.304800609601219, 1e-12);
  EXPECT_NEAR(origin[0], 217900.0 * 0.304800609601219, 1e-6);
  EXPECT_NEAR(origin[1], 4370060.0 * 0.304800609601219, 1e-6);
}

// A local file can name remote data: a VRT whose source is a URL, or a description file for a
// server driver. Without AllowNetworkPaths the reader refuses both without going online (the
// sandbox has no network, so a request would fail anyway: the messages prove the refusal).
TEST(TerroirDEMReader, LocalFilesNamingRemoteDataAreRefused)
{
  const std::string dir = terroir::testing::IOScratchFolder("dem_remote");
  vtkNew<vtkTerroirDEMReader> reader;
  // SourceProperties let GDAL open the VRT without opening its source.
  const std::string vrt = dir + "/remote.vrt";
  terroir::testing::WriteTextFile(vrt,
    terroir::testing::SimpleVRT(3,
      2,
      "0, 10, 0, 20, 0, -10",
      "<SourceFilename relativeToVRT=\"0\">/vsicurl/http://127.0.0.1:9/dem.tif</SourceFilename>"
      "<SourceProperties RasterXSize=\"3\" RasterYSize=\"2\" DataType=\"Float32\" "
      "BlockXSize=\"3\" BlockYSize=\"1\"/>"));
  std::string m = ExpectFailure(reader, vrt);
  EXPECT_NE(m.find("refers to '/vsicurl/http://127.0.0.1:9/dem.tif', a network or archive path"),
    std::string::npos)
    << m;
  EXPECT_NE(m.find("AllowNetworkPaths"), std::string::npos) << m;

  const std::string wms = dir + "/tiles.xml";
  terroir::testing::WriteTextFile(wms,
    "<GDAL_WMS><Service name=\"TMS\"><ServerUrl>http://127.0.0.1:9/${z}/${x}/${y}.png"
    "</ServerUrl></Service><DataWindow><UpperLeftX>-20037508.34</UpperLeftX>"
    "<UpperLeftY>20037508.34</UpperLeftY><LowerRightX>20037508.34</LowerRightX>"
    "<LowerRightY>-20037508.34</LowerRightY><TileLevel>1</TileLevel><TileCountX>1</TileCountX>"
    "<TileCountY>1</TileCountY><YOrigin>top</YOrigin></DataWindow><Projection>EPSG:3857"
    "</Projection><BlockSizeX>256</BlockSizeX><BlockSizeY>256</BlockSizeY><BandsCount>1"
    "</BandsCount></GDAL_WMS>\n");
  m = ExpectFailure(reader, wms);
  EXPECT_NE(
    m.find("the WMS driver reads from a server: network access is refused"), std::string::npos)
    << m;
}

TEST(TerroirDEMReader, FoldersFifosAndEmptyFilesAreClearErrors)
{
  const std::string dir = terroir::testing::IOScratchFolder("dem_kinds");
  vtkNew<vtkTerroirDEMReader> reader;
  EXPECT_EQ(ExpectFailure(reader, dir), dir + ": is a directory, not a file");
  const std::string fifo = dir + "/pipe.tif";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  // Opening a FIFO would block until a writer comes: it must be refused, not read.
  EXPECT_EQ(ExpectFailure(reader, fifo), fifo + ": not a regular file");
  const std::string empty = dir + "/empty.tif";
  terroir::testing::WriteTextFile(empty, "");
  EXPECT_NE(ExpectFailure(reader, empty).find("not a raster GDAL can read"), std::string::npos);
}

TEST(TerroirDEMReader, InfiniteValuesAreNoDataAndNonFiniteOriginIsAnError)
{
  const std::string dir = terroir::testing::IOScratchFolder("dem_inf");
  // An ASCII grid whose values overflow float32 (1e39) or are written as inf: no heights.
  const std::string grid = dir + "/inf.asc";
  terroir::testing::WriteTextFile(
    grid, terroir::testing::AsciiGrid(3, 1, 0, 0, 10, -9999, { "1e39 inf 7.5" }));
  vtkNew<vtkTerroirDEMReader> reader;
  reader->SetFileName(grid.c_str());
  reader->Update();
  ASSERT_STREQ(reader->GetErrorMessage(), "");
  vtkImageData* img = reader->GetOutput();
  vtkDataArray* z = img->GetPointData()->GetArray("Elevation");
  vtkDataArray* mask = img->GetPointData()->GetArray("vtkValidPointMask");
  ASSERT_NE(mask, nullptr);
  EXPECT_EQ(mask->GetComponent(0, 0), 0.0);
  EXPECT_EQ(mask->GetComponent(1, 0), 0.0);
  EXPECT_EQ(mask->GetComponent(2, 0), 1.0);
  EXPECT_TRUE(std::isnan(z->GetComponent(0, 0)));
  EXPECT_TRUE(std::isnan(z->GetComponent(1, 0)));
  EXPECT_EQ(z->GetComponent(2, 0), 7.5);

  const std::string vrt = dir + "/nan_origin.vrt";
  terroir::testing::WriteTextFile(
    vrt, terroir::testing::SimpleVRT(3, 1, "nan, 10, 0, 20, 0, -10", "inf.asc"));
  EXPECT_NE(ExpectFailure(reader, vrt).find("invalid origin in the geotransform (not finite)"),
    std::string::npos);
}

// Found by Testing/Fuzz/FuzzDEMReader (corpus seed built_degenerate_ellipsoid): a CRS whose
// ellipsoid has a semi-major axis of 1 m and an inverse flattening of 0.5 made GeographicLib
// throw from inside the pipeline, which ended the program. Now it is a one-line error.
TEST(TerroirDEMReader, DegenerateEllipsoidIsAnErrorNotACrash)
{
  const std::string dir = terroir::testing::IOScratchFolder("dem_ellipsoid");
  terroir::testing::WriteTextFile(
    dir + "/ok.asc", terroir::testing::AsciiGrid(3, 2, 0, 0, 10, -9999, { "1 2 3", "4 5 6" }));
  const std::string vrt = dir + "/odd.vrt";
  terroir::testing::WriteTextFile(vrt,
    terroir::testing::SimpleVRT(3,
      2,
      "10, 0.001, 0, 40, 0, -0.001",
      "ok.asc",
      "GEOGCS[\"odd\",DATUM[\"odd\",SPHEROID[\"odd\",1,0.5]],PRIMEM[\"Greenwich\",0],"
      "UNIT[\"degree\",0.0174532925199433]]"));
  vtkNew<vtkTerroirDEMReader> reader;
  EXPECT_EQ(ExpectFailure(reader, vrt),
    vrt +
      ": the CRS ellipsoid (semi-major axis 1.000000 m, inverse flattening 0.500000) is not "
      "usable");
}

// Pieces (issue 25): an update extent is read as one GDAL window whose cells are the whole
// read's cells bit for bit, with the whole raster's origin, spacing and georeference (and the
// mask, all valid: see PieceOfAFileWithNoDataKeepsTheMask); the
// window is reported by GetReadExtent. The north-up flip is checked with a window touching
// neither the south nor the north row. A piece request (2 of 4 with 1 ghost level) reads the
// block vtkExtentTranslator gives, grown by the ghost level.
TEST(TerroirDEMReader, ReadsOnlyTheRequestedExtent)
{
  vtkNew<vtkTerroirDEMReader> whole;
  whole->SetFileName(kUTM.c_str());
  whole->Update();
  vtkImageData* all = whole->GetOutput();
  int wholeExtent[6];
  all->GetExtent(wholeExtent);
  EXPECT_EQ(whole->GetReadExtent()[1], wholeExtent[1]);
  EXPECT_EQ(whole->GetReadExtent()[3], wholeExtent[3]);

  auto check = [&](vtkTerroirDEMReader* piece, const int* expected)
  {
    vtkImageData* img = piece->GetOutput();
    int ext[6];
    img->GetExtent(ext);
    for (int a = 0; a < 6; ++a)
    {
      EXPECT_EQ(ext[a], expected[a]) << a;
      EXPECT_EQ(piece->GetReadExtent()[a], expected[a]) << a;
    }
    EXPECT_EQ(img->GetNumberOfPoints(),
      static_cast<vtkIdType>(expected[1] - expected[0] + 1) * (expected[3] - expected[2] + 1));
    double o1[3], o2[3], s1[3], s2[3];
    img->GetOrigin(o1);
    all->GetOrigin(o2);
    img->GetSpacing(s1);
    all->GetSpacing(s2);
    for (int a = 0; a < 3; ++a)
    {
      EXPECT_EQ(o1[a], o2[a]);
      EXPECT_EQ(s1[a], s2[a]);
    }
    EXPECT_EQ(vtkTerroirGeoreference::GetCRS(img), vtkTerroirGeoreference::GetCRS(all));
    // Sagehen has no no-data cell, so the whole read has no mask; a piece read alone cannot
    // know that of the other cells and, the file declaring a nodata value, has one: all valid.
    vtkDataArray* mask = img->GetPointData()->GetArray("vtkValidPointMask");
    ASSERT_NE(mask, nullptr);
    EXPECT_EQ(mask->GetRange()[0], 1.0);
    int mismatches = 0;
    for (int j = expected[2]; j <= expected[3]; ++j)
    {
      for (int i = expected[0]; i <= expected[1]; ++i)
      {
        const int index[3] = { i, j, 0 };
        const vtkIdType a = img->ComputePointId(const_cast<int*>(index));
        const vtkIdType b = all->ComputePointId(const_cast<int*>(index));
        const float x =
          static_cast<float>(img->GetPointData()->GetArray("Elevation")->GetComponent(a, 0));
        const float y =
          static_cast<float>(all->GetPointData()->GetArray("Elevation")->GetComponent(b, 0));
        mismatches += std::memcmp(&x, &y, sizeof(float)) != 0 ? 1 : 0;
      }
    }
    EXPECT_EQ(mismatches, 0);
  };

  vtkNew<vtkTerroirDEMReader> window;
  window->SetFileName(kUTM.c_str());
  window->UpdateInformation();
  const int sub[6] = { 100, 350, 40, 517, 0, 0 };
  window->UpdateExtent(sub);
  EXPECT_STREQ(window->GetErrorMessage(), "");
  check(window, sub);

  vtkNew<vtkTerroirDEMReader> piece;
  piece->SetFileName(kUTM.c_str());
  piece->UpdateInformation();
  piece->UpdatePiece(2, 4, 1);
  int expected[6];
  vtkNew<vtkExtentTranslator> translator;
  translator->PieceToExtentThreadSafe(
    2, 4, 1, wholeExtent, expected, vtkExtentTranslator::BLOCK_MODE, 0);
  EXPECT_LT(static_cast<double>(expected[1] - expected[0] + 1) * (expected[3] - expected[2] + 1),
    0.3 * all->GetNumberOfPoints());
  check(piece, expected);
}

// A piece read alone (no parallel run to all-reduce the no-data counts with) keeps the mask
// whenever the file can hold no-data, even if the piece has none, and an all-no-data piece is
// no error; the mask's values are the whole read's.
TEST(TerroirDEMReader, PieceOfAFileWithNoDataKeepsTheMask)
{
  const std::string dir = terroir::testing::IOScratchFolder("dem_pieces");
  const std::string path = dir + "/holes.asc";
  ASSERT_TRUE(terroir::testing::WriteTextFile(path,
    terroir::testing::AsciiGrid(
      4, 3, 0, 0, 10, -9999, { "-9999 -9999 3 4", "5 6 7 8", "9 10 11 -9999" })));
  vtkNew<vtkTerroirDEMReader> reader;
  reader->SetFileName(path.c_str());
  reader->UpdateInformation();
  // South row (the file's last line), the three western cells: 9 10 11, all valid.
  const int south[6] = { 0, 2, 0, 0, 0, 0 };
  reader->UpdateExtent(south);
  vtkDataArray* mask = reader->GetOutput()->GetPointData()->GetArray("vtkValidPointMask");
  ASSERT_NE(mask, nullptr);
  for (int k = 0; k < 3; ++k)
  {
    EXPECT_EQ(mask->GetComponent(k, 0), 1.0) << k;
    EXPECT_EQ(ElevationAt(reader->GetOutput(), k, 0), 9.0f + k);
  }
  // North-west corner: two no-data cells only.
  vtkNew<vtkTerroirDEMReader> corner;
  corner->SetFileName(path.c_str());
  corner->UpdateInformation();
  const int holes[6] = { 0, 1, 2, 2, 0, 0 };
  corner->UpdateExtent(holes);
  EXPECT_STREQ(corner->GetErrorMessage(), "");
  ASSERT_EQ(corner->GetOutput()->GetNumberOfPoints(), 2);
  EXPECT_TRUE(std::isnan(ElevationAt(corner->GetOutput(), 0, 0)));
}

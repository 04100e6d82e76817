// Pipeline tests of vtkTerroirTerragenReader: the bundled .ter against the bundled GeoTIFF.
#include "TerroirIOTestUtilities.h"
#include "vtkTerroirDEMReader.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirTerragenReader.h"

#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkNew.h"
#include "vtkPointData.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace
{
const std::string kDir = std::string(TERROIR_DATA_DIR) + "/sagehen_creek_ca";
}

TEST(TerroirTerragenReader, MatchesBundledGeoTIFF)
{
  vtkNew<vtkTerroirTerragenReader> ter;
  ter->SetFileName((kDir + "/sagehen_dem_utm11n_10m.ter").c_str());
  ter->Update();
  EXPECT_STREQ(ter->GetErrorMessage(), "");
  vtkNew<vtkTerroirDEMReader> tif;
  tif->SetFileName((kDir + "/sagehen_dem_utm11n_10m.tif").c_str());
  tif->Update();
  vtkImageData* a = ter->GetOutput();
  vtkImageData* b = tif->GetOutput();
  int da[3], db[3];
  a->GetDimensions(da);
  b->GetDimensions(db);
  ASSERT_EQ(da[0], 786); // XPTS
  ASSERT_EQ(da[1], 720); // YPTS
  ASSERT_EQ(da[0], db[0]);
  ASSERT_EQ(da[1], db[1]);
  double spacing[3], origin[3];
  a->GetSpacing(spacing);
  a->GetOrigin(origin);
  EXPECT_EQ(spacing[0], 10.0); // SCAL
  EXPECT_EQ(spacing[1], 10.0);
  EXPECT_EQ(origin[0], 0.0);
  EXPECT_FALSE(vtkTerroirGeoreference::HasGeoreference(a));
  vtkDataArray* ea = a->GetPointData()->GetArray("Elevation");
  vtkDataArray* eb = b->GetPointData()->GetArray("Elevation");
  ASSERT_NE(ea, nullptr);
  EXPECT_EQ(ea->GetDataType(), VTK_FLOAT);
  double worst = 0.0;
  vtkIdType worstIndex = -1;
  for (vtkIdType k = 0; k < ea->GetNumberOfTuples(); ++k)
  {
    const double d = std::fabs(ea->GetComponent(k, 0) - eb->GetComponent(k, 0));
    if (d > worst)
    {
      worst = d;
      worstIndex = k;
    }
  }
  std::cout << "[ value  ] max |ter - tif| = " << worst << " m at " << worstIndex << "\n";
  // PROVENANCE.md: max deviation 0.0123 m (GDAL's writer truncates, so up to one
  // quantisation step, 10 * 81 / 65536 = 0.01236 m), plus half a float32 ulp at 2048-4096 m
  // (2^-13 m) because the decoded heights are stored as float32. The row orders agree only
  // if the .ter's first row is read as the south one.
  EXPECT_LE(worst, 10.0 * 81.0 / 65536.0 + std::ldexp(1.0, -13));
  EXPECT_GT(worst, 0.005);
}

TEST(TerroirTerragenReader, ReportsBadFiles)
{
  const std::string dir = terroir::testing::IOScratchFolder("ter_bad");
  vtkNew<vtkTerroirTerragenReader> reader;
  auto fails = [&](const std::string& path, const std::string& expected)
  {
    reader->SetFileName(path.c_str());
    reader->Update();
    const std::string m = reader->GetErrorMessage();
    EXPECT_EQ(m.rfind(path + ": ", 0), 0u) << m;
    EXPECT_NE(m.find(expected), std::string::npos) << m;
    EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 0);
  };
  fails(dir + "/missing.ter", "no such file");
  fails(dir, "is a directory, not a file");
  terroir::testing::WriteTextFile(dir + "/empty.ter", "");
  fails(dir + "/empty.ter", "not a Terragen file");
  terroir::testing::WriteTextFile(dir + "/text.ter", "hello, not a terrain file");
  fails(dir + "/text.ter", "not a Terragen file");
  // The bundled file cut in the middle of its ALTW chunk.
  std::vector<char> bytes = terroir::testing::ReadWholeFile(kDir + "/sagehen_dem_utm11n_10m.ter");
  ASSERT_EQ(bytes.size(), 1131904u);
  terroir::testing::WriteTextFile(
    dir + "/cut.ter", std::string(bytes.begin(), bytes.begin() + 100000));
  fails(dir + "/cut.ter", "expected xpts*ypts = 786*720 = 565920");
  // A good read after the failures clears the message.
  reader->SetFileName((kDir + "/sagehen_dem_utm11n_10m.ter").c_str());
  reader->Update();
  EXPECT_STREQ(reader->GetErrorMessage(), "");
  EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 786 * 720);
}

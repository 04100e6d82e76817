// Pipeline tests of vtkTerroirTerragenWriter: round trip, masks, temporary file, Overwrite.
#include "TerroirIOTestUtilities.h"
#include "vtkTerroirDEMReader.h"
#include "vtkTerroirFractalTerrainSource.h"
#include "vtkTerroirTerragenReader.h"
#include "vtkTerroirTerragenWriter.h"

#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkUnsignedCharArray.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

TEST(TerroirTerragenWriter, RoundTripFractalTerrain)
{
  const std::string dir = terroir::testing::IOScratchFolder("ter_write");
  const std::string path = dir + "/fractal.ter";
  vtkNew<vtkTerroirFractalTerrainSource> source;
  source->SetDimensions(120, 90);
  source->SetSpacing(25.0);
  source->Update();
  vtkNew<vtkTerroirTerragenWriter> writer;
  writer->SetInputConnection(source->GetOutputPort());
  writer->SetFileName(path.c_str());
  ASSERT_EQ(writer->Write(), 1) << writer->GetErrorMessage();
  EXPECT_STREQ(writer->GetErrorMessage(), "");
  // Only the target remains in the folder (the temporary file was renamed).
  EXPECT_EQ(terroir::testing::ListFolder(dir), std::vector<std::string>{ "fractal.ter" });

  vtkNew<vtkTerroirTerragenReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkImageData* out = reader->GetOutput();
  int dims[3];
  out->GetDimensions(dims);
  ASSERT_EQ(dims[0], 120);
  ASSERT_EQ(dims[1], 90);
  double spacing[3];
  out->GetSpacing(spacing);
  EXPECT_EQ(spacing[0], 25.0);
  EXPECT_EQ(spacing[1], 25.0);
  vtkDataArray* a = source->GetOutput()->GetPointData()->GetArray("Elevation");
  vtkDataArray* b = out->GetPointData()->GetArray("Elevation");
  double range[2];
  a->GetRange(range, 0);
  ASSERT_GT(range[1] - range[0], 2 * 25.0);
  double worst = 0.0;
  for (vtkIdType k = 0; k < a->GetNumberOfTuples(); ++k)
  {
    worst = std::max(worst, std::fabs(a->GetComponent(k, 0) - b->GetComponent(k, 0)));
  }
  EXPECT_LE(worst, (range[1] - range[0]) / 65536.0);
}

TEST(TerroirTerragenWriter, OverwriteAndErrors)
{
  const std::string dir = terroir::testing::IOScratchFolder("ter_overwrite");
  const std::string path = dir + "/t.ter";
  vtkNew<vtkTerroirFractalTerrainSource> source;
  source->SetDimensions(16, 12);
  vtkNew<vtkTerroirTerragenWriter> writer;
  writer->SetInputConnection(source->GetOutputPort());
  writer->SetFileName(path.c_str());
  ASSERT_EQ(writer->Write(), 1);
  const std::vector<char> first = terroir::testing::ReadWholeFile(path);

  source->SetSeed(99);
  EXPECT_EQ(writer->Write(), 0); // Overwrite off
  EXPECT_NE(std::string(writer->GetErrorMessage()).find(path + ": file exists"), std::string::npos)
    << writer->GetErrorMessage();
  EXPECT_EQ(terroir::testing::ReadWholeFile(path), first);

  writer->SetArrayName("NoSuchArray");
  writer->OverwriteOn();
  EXPECT_EQ(writer->Write(), 0);
  EXPECT_NE(
    std::string(writer->GetErrorMessage()).find("no point array 'NoSuchArray'"), std::string::npos);
  EXPECT_EQ(terroir::testing::ReadWholeFile(path), first); // untouched

  writer->SetArrayName("Elevation");
  ASSERT_EQ(writer->Write(), 1);
  EXPECT_NE(terroir::testing::ReadWholeFile(path), first); // replaced by seed 99

  writer->SetFileName((dir + "/no/such/folder/t.ter").c_str());
  EXPECT_EQ(writer->Write(), 0);
  EXPECT_NE(std::string(writer->GetErrorMessage()).find("cannot create a file"), std::string::npos);
  EXPECT_EQ(terroir::testing::ListFolder(dir), std::vector<std::string>{ "t.ter" });
}

TEST(TerroirTerragenWriter, MaskedCellsWrittenAsMinimum)
{
  const std::string dir = terroir::testing::IOScratchFolder("ter_mask");
  vtkNew<vtkTerroirFractalTerrainSource> source;
  source->SetDimensions(8, 8);
  source->Update();
  vtkNew<vtkImageData> img;
  img->DeepCopy(source->GetOutput());
  vtkNew<vtkUnsignedCharArray> mask;
  mask->SetName("vtkValidPointMask");
  mask->SetNumberOfTuples(64);
  mask->FillValue(1);
  mask->SetValue(10, 0);
  img->GetPointData()->AddArray(mask);
  vtkDataArray* e = img->GetPointData()->GetArray("Elevation");
  e->SetComponent(10, 0, 1.0e6); // garbage under the mask must not count
  double lo = 1e30;
  for (vtkIdType k = 0; k < 64; ++k)
  {
    if (k != 10)
    {
      lo = std::min(lo, e->GetComponent(k, 0));
    }
  }
  vtkNew<vtkTerroirTerragenWriter> writer;
  writer->SetInputData(img);
  writer->SetFileName((dir + "/m.ter").c_str());
  ASSERT_EQ(writer->Write(), 1);
  vtkNew<vtkTerroirTerragenReader> reader;
  reader->SetFileName((dir + "/m.ter").c_str());
  reader->Update();
  EXPECT_NEAR(
    reader->GetOutput()->GetPointData()->GetArray("Elevation")->GetComponent(10, 0), lo, 0.05);
}

TEST(TerroirTerragenWriter, BundledDEMRoundTrip)
{
  // Sagehen UTM DEM (range 766 m, spacing 10 m) through our writer: error bound
  // range / 131068 + dz / 65534 = 0.0058 + 0.00015 m, plus 2^-13 m of float32 storage.
  const std::string dir = terroir::testing::IOScratchFolder("ter_bundled");
  vtkNew<vtkTerroirDEMReader> dem;
  dem->SetFileName(
    (std::string(TERROIR_DATA_DIR) + "/sagehen_creek_ca/sagehen_dem_utm11n_10m.tif").c_str());
  vtkNew<vtkTerroirTerragenWriter> writer;
  writer->SetInputConnection(dem->GetOutputPort());
  writer->SetFileName((dir + "/sagehen.ter").c_str());
  ASSERT_EQ(writer->Write(), 1) << writer->GetErrorMessage();
  vtkNew<vtkTerroirTerragenReader> reader;
  reader->SetFileName((dir + "/sagehen.ter").c_str());
  reader->Update();
  vtkDataArray* a = dem->GetOutput()->GetPointData()->GetArray("Elevation");
  vtkDataArray* b = reader->GetOutput()->GetPointData()->GetArray("Elevation");
  ASSERT_EQ(a->GetNumberOfTuples(), b->GetNumberOfTuples());
  double range[2];
  a->GetRange(range, 0);
  double worst = 0.0;
  for (vtkIdType k = 0; k < a->GetNumberOfTuples(); ++k)
  {
    worst = std::max(worst, std::fabs(a->GetComponent(k, 0) - b->GetComponent(k, 0)));
  }
  std::cout << "[ value  ] max |written .ter - tif| = " << worst << " m\n";
  EXPECT_LE(worst, (range[1] - range[0]) / 131068.0 + 10.0 / 65534.0 + std::ldexp(1.0, -13));
  EXPECT_LE(worst, (range[1] - range[0]) / 65536.0);
}

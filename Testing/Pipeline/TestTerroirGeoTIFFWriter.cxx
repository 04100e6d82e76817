// Pipeline tests of vtkTerroirGeoTIFFWriter: round trip through vtkTerroirDEMReader.
#include "TerroirIOTestUtilities.h"
#include "vtkTerroirDEMReader.h"
#include "vtkTerroirFractalTerrainSource.h"
#include "vtkTerroirGeoTIFFWriter.h"
#include "vtkTerroirGeoreference.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkTrivialProducer.h"
#include "vtkUnsignedCharArray.h"

#include <gdal.h>
#include <gdal_utils.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

namespace
{
const std::string kUTM =
  std::string(TERROIR_DATA_DIR) + "/sagehen_creek_ca/sagehen_dem_utm11n_10m.tif";

// Slope-like data: central-difference gradient magnitude in degrees, plus its components.
void AddSlopeLike(vtkImageData* img)
{
  int dims[3];
  img->GetDimensions(dims);
  double spacing[3];
  img->GetSpacing(spacing);
  vtkDataArray* e = img->GetPointData()->GetArray("Elevation");
  vtkNew<vtkFloatArray> slope;
  slope->SetName("SlopeLike");
  slope->SetNumberOfTuples(e->GetNumberOfTuples());
  vtkNew<vtkDoubleArray> grad;
  grad->SetName("GradientLike");
  grad->SetNumberOfComponents(2);
  grad->SetComponentName(0, "dzdx");
  grad->SetComponentName(1, "dzdy");
  grad->SetNumberOfTuples(e->GetNumberOfTuples());
  for (int j = 0; j < dims[1]; ++j)
  {
    for (int i = 0; i < dims[0]; ++i)
    {
      const vtkIdType k = static_cast<vtkIdType>(j) * dims[0] + i;
      const int i0 = std::max(i - 1, 0), i1 = std::min(i + 1, dims[0] - 1);
      const int j0 = std::max(j - 1, 0), j1 = std::min(j + 1, dims[1] - 1);
      const double gx = (e->GetComponent(static_cast<vtkIdType>(j) * dims[0] + i1, 0) -
                          e->GetComponent(static_cast<vtkIdType>(j) * dims[0] + i0, 0)) /
        ((i1 - i0) * spacing[0]);
      const double gy = (e->GetComponent(static_cast<vtkIdType>(j1) * dims[0] + i, 0) -
                          e->GetComponent(static_cast<vtkIdType>(j0) * dims[0] + i, 0)) /
        ((j1 - j0) * spacing[1]);
      slope->SetValue(k, static_cast<float>(std::atan(std::hypot(gx, gy)) * 180.0 / M_PI));
      grad->SetTypedComponent(k, 0, gx);
      grad->SetTypedComponent(k, 1, gy);
    }
  }
  img->GetPointData()->AddArray(slope);
  img->GetPointData()->AddArray(grad);
}
} // namespace

TEST(TerroirGeoTIFFWriter, RoundTripKeepsValuesGeotransformAndCRS)
{
  const std::string dir = terroir::testing::IOScratchFolder("tif_roundtrip");
  vtkNew<vtkTerroirDEMReader> reader;
  reader->SetFileName(kUTM.c_str());
  reader->Update();
  vtkNew<vtkImageData> img;
  img->DeepCopy(reader->GetOutput());
  AddSlopeLike(img);
  // Mask a few cells.
  vtkNew<vtkUnsignedCharArray> mask;
  mask->SetName("vtkValidPointMask");
  mask->SetNumberOfTuples(img->GetNumberOfPoints());
  mask->FillValue(1);
  mask->SetValue(0, 0);
  mask->SetValue(12345, 0);
  img->GetPointData()->AddArray(mask);

  vtkNew<vtkTerroirGeoTIFFWriter> writer;
  writer->SetInputData(img);
  writer->SetArrayName("SlopeLike");
  writer->SetFileName((dir + "/slope.tif").c_str());
  ASSERT_EQ(writer->Write(), 1) << writer->GetErrorMessage();
  EXPECT_EQ(terroir::testing::ListFolder(dir), std::vector<std::string>{ "slope.tif" });

  vtkNew<vtkTerroirDEMReader> back;
  back->SetFileName((dir + "/slope.tif").c_str());
  back->Update();
  ASSERT_STREQ(back->GetErrorMessage(), "");
  vtkImageData* out = back->GetOutput();
  ASSERT_EQ(out->GetNumberOfPoints(), img->GetNumberOfPoints());
  double gtIn[6], gtOut[6];
  ASSERT_TRUE(vtkTerroirGeoreference::GetGeoTransform(img, gtIn));
  ASSERT_TRUE(vtkTerroirGeoreference::GetGeoTransform(out, gtOut));
  for (int k = 0; k < 6; ++k)
  {
    EXPECT_EQ(gtIn[k], gtOut[k]) << k;
  }
  EXPECT_EQ(vtkTerroirGeoreference::GetCRS(out), vtkTerroirGeoreference::GetCRS(img));
  double oIn[3], oOut[3];
  img->GetOrigin(oIn);
  out->GetOrigin(oOut);
  EXPECT_EQ(oIn[0], oOut[0]);
  EXPECT_EQ(oIn[1], oOut[1]);
  EXPECT_NEAR(vtkTerroirGeoreference::GetMeridianConvergence(out),
    vtkTerroirGeoreference::GetMeridianConvergence(img),
    1e-12);
  // Values bit-identical (Float32 both ways), masked cells come back masked.
  vtkDataArray* a = img->GetPointData()->GetArray("SlopeLike");
  vtkDataArray* b = out->GetPointData()->GetArray("Elevation");
  vtkDataArray* m = out->GetPointData()->GetArray("vtkValidPointMask");
  ASSERT_NE(m, nullptr);
  vtkIdType masked = 0;
  for (vtkIdType k = 0; k < a->GetNumberOfTuples(); ++k)
  {
    if (k == 0 || k == 12345)
    {
      EXPECT_EQ(m->GetComponent(k, 0), 0.0);
      EXPECT_TRUE(std::isnan(b->GetComponent(k, 0)));
      ++masked;
      continue;
    }
    ASSERT_EQ(a->GetComponent(k, 0), b->GetComponent(k, 0)) << k;
  }
  EXPECT_EQ(masked, 2);

  // Two-component double array: band 2 holds the second component.
  writer->SetArrayName("GradientLike");
  writer->SetFileName((dir + "/grad.tif").c_str());
  ASSERT_EQ(writer->Write(), 1) << writer->GetErrorMessage();
  back->SetFileName((dir + "/grad.tif").c_str());
  back->SetBand(2);
  back->Update();
  ASSERT_STREQ(back->GetErrorMessage(), "");
  vtkDataArray* g = img->GetPointData()->GetArray("GradientLike");
  b = back->GetOutput()->GetPointData()->GetArray("Elevation");
  for (vtkIdType k : { 1, 777, 300000 })
  {
    EXPECT_FLOAT_EQ(b->GetComponent(k, 0), static_cast<float>(g->GetComponent(k, 1)));
  }
}

TEST(TerroirGeoTIFFWriter, NoGeoreferenceUsesOriginAndSpacing)
{
  const std::string dir = terroir::testing::IOScratchFolder("tif_nogeo");
  vtkNew<vtkImageData> img;
  img->SetDimensions(4, 3, 1);
  img->SetOrigin(100.0, 200.0, 0.0);
  img->SetSpacing(2.0, 5.0, 1.0);
  vtkNew<vtkIntArray> ids;
  ids->SetName("Elevation");
  ids->SetNumberOfTuples(12);
  for (int k = 0; k < 12; ++k)
  {
    ids->SetValue(k, k * 10);
  }
  img->GetPointData()->AddArray(ids);
  vtkNew<vtkTerroirGeoTIFFWriter> writer;
  writer->SetInputData(img);
  writer->SetFileName((dir + "/ids.tif").c_str());
  ASSERT_EQ(writer->Write(), 1) << writer->GetErrorMessage();
  vtkNew<vtkTerroirDEMReader> back;
  back->SetFileName((dir + "/ids.tif").c_str());
  back->Update();
  vtkImageData* out = back->GetOutput();
  double gt[6];
  ASSERT_TRUE(vtkTerroirGeoreference::GetGeoTransform(out, gt));
  // West edge 100 - 1, north edge 200 + 2 * 5 + 2.5; pixel 2 x -5.
  EXPECT_EQ(gt[0], 99.0);
  EXPECT_EQ(gt[1], 2.0);
  EXPECT_EQ(gt[3], 212.5);
  EXPECT_EQ(gt[5], -5.0);
  double o[3];
  out->GetOrigin(o);
  EXPECT_EQ(o[0], 100.0);
  EXPECT_EQ(o[1], 200.0);
  EXPECT_TRUE(vtkTerroirGeoreference::GetCRS(out).empty());
  vtkDataArray* e = out->GetPointData()->GetArray("Elevation");
  for (int k = 0; k < 12; ++k)
  {
    EXPECT_EQ(e->GetComponent(k, 0), k * 10.0);
  }
}

TEST(TerroirGeoTIFFWriter, TemporaryFileAndOverwrite)
{
  const std::string dir = terroir::testing::IOScratchFolder("tif_overwrite");
  const std::string path = dir + "/dem.tif";
  vtkNew<vtkTerroirFractalTerrainSource> source;
  source->SetDimensions(32, 24);
  vtkNew<vtkTerroirGeoTIFFWriter> writer;
  writer->SetInputConnection(source->GetOutputPort());
  writer->SetFileName(path.c_str());
  ASSERT_EQ(writer->Write(), 1) << writer->GetErrorMessage();
  const std::vector<char> first = terroir::testing::ReadWholeFile(path);
  ASSERT_FALSE(first.empty());

  source->SetSeed(5);
  EXPECT_EQ(writer->Write(), 0);
  EXPECT_EQ(std::string(writer->GetErrorMessage()),
    path + ": file exists (turn Overwrite on to replace it)");
  EXPECT_EQ(terroir::testing::ReadWholeFile(path), first);

  writer->OverwriteOn();
  writer->SetArrayName("Missing");
  EXPECT_EQ(writer->Write(), 0);
  EXPECT_EQ(terroir::testing::ReadWholeFile(path), first);
  writer->SetArrayName("Elevation");
  ASSERT_EQ(writer->Write(), 1);
  EXPECT_NE(terroir::testing::ReadWholeFile(path), first);
  EXPECT_EQ(terroir::testing::ListFolder(dir), std::vector<std::string>{ "dem.tif" });

  // A folder that does not exist: error, nothing created.
  const std::string missing = dir + "/nope/dem.tif";
  writer->SetFileName(missing.c_str());
  EXPECT_EQ(writer->Write(), 0);
  EXPECT_EQ(std::string(writer->GetErrorMessage()).rfind(missing + ": cannot create", 0), 0u)
    << writer->GetErrorMessage();
  EXPECT_FALSE(terroir::testing::PathExists(dir + "/nope"));

  // A read-only folder (permissions do not bind root, so only checked for other users).
  if (::geteuid() != 0)
  {
    const std::string ro = dir + "/readonly";
    ::mkdir(ro.c_str(), 0555);
    writer->SetFileName((ro + "/dem.tif").c_str());
    EXPECT_EQ(writer->Write(), 0);
    EXPECT_TRUE(terroir::testing::ListFolder(ro).empty());
    ::chmod(ro.c_str(), 0755);
  }
}

// Compress: DEFLATE with the floating-point predictor is lossless and smaller for a DEM;
// uncompressed (the default, like gdaldem) holds exactly nx * ny * 4 bytes of pixels.
TEST(TerroirGeoTIFFWriter, CompressionIsLosslessAndOptional)
{
  const std::string dir = terroir::testing::IOScratchFolder("tif_compress");
  vtkNew<vtkTerroirDEMReader> reader;
  reader->SetFileName(kUTM.c_str());
  reader->Update();
  vtkImageData* dem = reader->GetOutput();
  vtkNew<vtkTerroirGeoTIFFWriter> writer;
  writer->SetInputData(dem);
  EXPECT_FALSE(writer->GetCompress());
  writer->SetFileName((dir + "/plain.tif").c_str());
  ASSERT_EQ(writer->Write(), 1) << writer->GetErrorMessage();
  writer->CompressOn();
  writer->SetFileName((dir + "/deflate.tif").c_str());
  ASSERT_EQ(writer->Write(), 1) << writer->GetErrorMessage();

  const std::size_t pixels = static_cast<std::size_t>(dem->GetNumberOfPoints()) * 4;
  const std::size_t plain = terroir::testing::ReadWholeFile(dir + "/plain.tif").size();
  const std::size_t deflate = terroir::testing::ReadWholeFile(dir + "/deflate.tif").size();
  EXPECT_GE(plain, pixels);
  EXPECT_LT(plain, pixels + 64 * 1024); // header, tags and CRS only
  EXPECT_LT(deflate, plain * 3 / 4) << "DEFLATE with predictor 3 should shrink a smooth DEM";

  vtkNew<vtkTerroirDEMReader> back;
  back->SetFileName((dir + "/deflate.tif").c_str());
  back->Update();
  ASSERT_STREQ(back->GetErrorMessage(), "");
  vtkDataArray* a = dem->GetPointData()->GetArray("Elevation");
  vtkDataArray* b = back->GetOutput()->GetPointData()->GetArray("Elevation");
  ASSERT_EQ(a->GetNumberOfTuples(), b->GetNumberOfTuples());
  for (vtkIdType k = 0; k < a->GetNumberOfTuples(); ++k)
  {
    ASSERT_EQ(a->GetComponent(k, 0), b->GetComponent(k, 0)) << k;
  }
}

// Every compression and layout is lossless (float bands with predictor 3, integer bands with
// predictor 2), says what it is in the file's IMAGE_STRUCTURE, and tiles are 256 x 256.
// Overviews: a 600 x 520 raster gets levels 2 and 4 (520 / 2 = 260 >= 256, 520 / 4 < 256);
// AVERAGE for a float band (the 2 x 2 means of a plane are exact), NEAREST for an integer one
// (every overview value is one of the classes).
TEST(TerroirGeoTIFFWriter, CompressionsLayoutsAndOverviews)
{
  const std::string dir = terroir::testing::IOScratchFolder("tif_layouts");
  const int nx = 600, ny = 520;
  vtkNew<vtkImageData> image;
  image->SetDimensions(nx, ny, 1);
  image->SetSpacing(10, 10, 1);
  vtkNew<vtkFloatArray> plane;
  plane->SetName("Plane");
  plane->SetNumberOfComponents(2);
  plane->SetNumberOfTuples(static_cast<vtkIdType>(nx) * ny);
  vtkNew<vtkIntArray> classes;
  classes->SetName("Classes");
  classes->SetNumberOfTuples(static_cast<vtkIdType>(nx) * ny);
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      const vtkIdType k = static_cast<vtkIdType>(j) * nx + i;
      plane->SetTypedComponent(k, 0, 0.25f * i - 0.5f * j);
      plane->SetTypedComponent(k, 1, std::sin(0.01f * i * j));
      classes->SetValue(k, (i / 7 + j / 5) % 4);
    }
  }
  image->GetPointData()->AddArray(plane);
  image->GetPointData()->AddArray(classes);

  const char* names[] = { "NONE", "DEFLATE", "ZSTD", "LZW" };
  for (int c = vtkTerroirGeoTIFFWriter::COMPRESSION_NONE;
       c <= vtkTerroirGeoTIFFWriter::COMPRESSION_LZW;
       ++c)
  {
    EXPECT_EQ(vtkTerroirGeoTIFFWriter::GetCompressionFromName(
                vtkTerroirGeoTIFFWriter::GetCompressionName(c)),
      c);
    for (bool tiled : { false, true })
    {
      for (const char* array : { "Plane", "Classes" })
      {
        const std::string path =
          dir + "/" + array + std::to_string(c) + (tiled ? "t" : "s") + ".tif";
        vtkNew<vtkTerroirGeoTIFFWriter> writer;
        writer->SetInputData(image);
        writer->SetArrayName(array);
        writer->SetCompression(c);
        writer->SetTiled(tiled);
        writer->SetThreads(2);
        writer->SetOverviews(tiled);
        writer->SetFileName(path.c_str());
        ASSERT_EQ(writer->Write(), 1) << writer->GetErrorMessage();

        GDALDatasetH ds = GDALOpen(path.c_str(), GA_ReadOnly);
        ASSERT_NE(ds, nullptr) << path;
        const char* method = GDALGetMetadataItem(ds, "COMPRESSION", "IMAGE_STRUCTURE");
        EXPECT_STREQ(method ? method : "NONE", names[c]) << path;
        vtkDataArray* source = image->GetPointData()->GetArray(array);
        const int bands = source->GetNumberOfComponents();
        ASSERT_EQ(GDALGetRasterCount(ds), bands);
        for (int b = 0; b < bands; ++b)
        {
          GDALRasterBandH band = GDALGetRasterBand(ds, b + 1);
          int bx = 0, by = 0;
          GDALGetBlockSize(band, &bx, &by);
          if (tiled)
          {
            EXPECT_EQ(bx, 256);
            EXPECT_EQ(by, 256);
          }
          else
          {
            EXPECT_EQ(bx, nx); // strips: whole rows
          }
          std::vector<double> values(static_cast<std::size_t>(nx) * ny);
          ASSERT_EQ(
            GDALRasterIO(band, GF_Read, 0, 0, nx, ny, values.data(), nx, ny, GDT_Float64, 0, 0),
            CE_None);
          for (int j = 0; j < ny; ++j)
          {
            for (int i = 0; i < nx; ++i)
            {
              // GDAL row 0 is the north row: image row ny - 1.
              const vtkIdType k = static_cast<vtkIdType>(ny - 1 - j) * nx + i;
              ASSERT_EQ(values[static_cast<std::size_t>(j) * nx + i], source->GetComponent(k, b))
                << path << " band " << b << " at " << i << "," << j;
            }
          }
          ASSERT_EQ(GDALGetOverviewCount(band), tiled ? 2 : 0) << path;
          if (!tiled)
          {
            continue;
          }
          GDALRasterBandH half = GDALGetOverview(band, 0);
          ASSERT_EQ(GDALGetRasterBandXSize(half), nx / 2);
          std::vector<double> coarse(static_cast<std::size_t>(nx / 2) * (ny / 2));
          ASSERT_EQ(GDALRasterIO(half,
                      GF_Read,
                      0,
                      0,
                      nx / 2,
                      ny / 2,
                      coarse.data(),
                      nx / 2,
                      ny / 2,
                      GDT_Float64,
                      0,
                      0),
            CE_None);
          for (int j = 0; j < ny / 2; j += 37)
          {
            for (int i = 0; i < nx / 2; i += 29)
            {
              const std::size_t at = static_cast<std::size_t>(j) * (nx / 2) + i;
              double sum = 0.0;
              bool isClass = false;
              for (int dj = 0; dj < 2; ++dj)
              {
                for (int di = 0; di < 2; ++di)
                {
                  const double v = values[static_cast<std::size_t>(2 * j + dj) * nx + 2 * i + di];
                  sum += v;
                  isClass = isClass || v == coarse[at];
                }
              }
              if (b == 0 && std::string(array) == "Plane")
              {
                EXPECT_NEAR(coarse[at], 0.25 * sum, 1e-4)
                  << path << " overview at " << i << "," << j;
              }
              else if (std::string(array) == "Classes")
              {
                EXPECT_TRUE(isClass) << path << " overview value " << coarse[at] << " at " << i
                                     << "," << j << " is none of its 2 x 2 cells";
              }
            }
          }
        }
        GDALClose(ds);
      }
    }
  }
}

// Pieces (issue 25): each of 4 pieces of the bundled DEM (the pieces a 4-rank run reads) written
// as its own GeoTIFF lies where its cells are (the whole raster's geotransform moved to the
// piece's corner), and the pieces mosaicked by a VRT (GDALBuildVRT, as gdalbuildvrt does) give
// the GeoTIFF of the whole raster: the same size, geotransform and pixels, bit for bit.
TEST(TerroirGeoTIFFWriter, PiecesMosaicIntoTheWholeRaster)
{
  const std::string dir = terroir::testing::IOScratchFolder("geotiff_pieces");
  vtkNew<vtkTerroirDEMReader> reader;
  reader->SetFileName(kUTM.c_str());
  reader->Update();
  int whole[6];
  reader->GetOutput()->GetExtent(whole);
  const std::string serial = dir + "/whole.tif";
  vtkNew<vtkTerroirGeoTIFFWriter> writer;
  writer->SetInputConnection(reader->GetOutputPort());
  writer->SetFileName(serial.c_str());
  writer->OverwriteOn();
  writer->Write();
  ASSERT_STREQ(writer->GetErrorMessage(), "");

  std::vector<std::string> names;
  for (int piece = 0; piece < 4; ++piece)
  {
    vtkNew<vtkTerroirDEMReader> part;
    part->SetFileName(kUTM.c_str());
    part->UpdateInformation();
    part->UpdatePiece(piece, 4, 0);
    vtkNew<vtkImageData> copy;
    copy->ShallowCopy(part->GetOutput());
    vtkNew<vtkTrivialProducer> producer;
    producer->SetOutput(copy);
    producer->SetWholeExtent(whole);
    names.push_back(dir + "/piece" + std::to_string(piece) + ".tif");
    vtkNew<vtkTerroirGeoTIFFWriter> pieceWriter;
    pieceWriter->SetInputConnection(producer->GetOutputPort());
    pieceWriter->SetFileName(names.back().c_str());
    pieceWriter->OverwriteOn();
    pieceWriter->Write();
    ASSERT_STREQ(pieceWriter->GetErrorMessage(), "");
  }
  std::vector<const char*> sources;
  for (const std::string& n : names)
  {
    sources.push_back(n.c_str());
  }
  const std::string vrt = dir + "/mosaic.vrt";
  int usageError = 0;
  GDALDatasetH mosaic = GDALBuildVRT(
    vrt.c_str(), static_cast<int>(sources.size()), nullptr, sources.data(), nullptr, &usageError);
  ASSERT_NE(mosaic, nullptr);
  GDALDatasetH full = GDALOpen(serial.c_str(), GA_ReadOnly);
  ASSERT_NE(full, nullptr);
  const int nx = GDALGetRasterXSize(full);
  const int ny = GDALGetRasterYSize(full);
  EXPECT_EQ(GDALGetRasterXSize(mosaic), nx);
  EXPECT_EQ(GDALGetRasterYSize(mosaic), ny);
  double a[6], b[6];
  GDALGetGeoTransform(mosaic, a);
  GDALGetGeoTransform(full, b);
  for (int k = 0; k < 6; ++k)
  {
    EXPECT_EQ(a[k], b[k]) << k;
  }
  std::vector<float> x(static_cast<std::size_t>(nx) * ny), y(x.size());
  ASSERT_EQ(
    GDALRasterIO(
      GDALGetRasterBand(mosaic, 1), GF_Read, 0, 0, nx, ny, x.data(), nx, ny, GDT_Float32, 0, 0),
    CE_None);
  ASSERT_EQ(
    GDALRasterIO(
      GDALGetRasterBand(full, 1), GF_Read, 0, 0, nx, ny, y.data(), nx, ny, GDT_Float32, 0, 0),
    CE_None);
  EXPECT_EQ(std::memcmp(x.data(), y.data(), x.size() * sizeof(float)), 0);
  GDALClose(full);
  GDALClose(mosaic);
}

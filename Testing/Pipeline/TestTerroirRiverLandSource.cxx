// vtkTerroirRiverLandSource: its arrays and extent equal the core generator's, the JSON
// parameters override the properties, the river lines follow the river cells, the same bits
// for a seed and thread count, and a clear error for bad parameters.
#include "RiverLand.h"
#include "TerroirFilterTestUtilities.h"
#include "vtkTerroirRiverLandSource.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkIdList.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>

TEST(TerroirRiverLandSource, ArraysEqualTheCoreGenerator)
{
  vtkNew<vtkTerroirRiverLandSource> source;
  source->SetDimensions(96, 80);
  source->SetSpacing(25.0);
  source->SetSeed(12);
  source->SetRivers(5);
  source->Update();
  vtkImageData* out = source->GetOutput();
  int dims[3];
  out->GetDimensions(dims);
  EXPECT_EQ(dims[0], 96);
  EXPECT_EQ(dims[1], 80);
  EXPECT_EQ(out->GetSpacing()[0], 25.0);
  for (const char* name : { "Elevation",
         "River",
         "RiverId",
         "MedialAxis",
         "DistanceToRiver",
         "CellClass",
         "SlopeWeight" })
  {
    ASSERT_NE(out->GetPointData()->GetArray(name), nullptr) << name;
    EXPECT_EQ(out->GetPointData()->GetArray(name)->GetNumberOfTuples(), 96 * 80) << name;
  }
  terroir::generation::RiverLandParameters p;
  p.width = 96;
  p.height = 80;
  p.spacing = 25.0;
  p.seed = 12;
  p.rivers = 5;
  terroir::generation::RiverLand land;
  std::string error;
  ASSERT_TRUE(terroir::generation::GenerateRiverLand(p, land, error)) << error;
  auto* z = vtkFloatArray::SafeDownCast(out->GetPointData()->GetArray("Elevation"));
  ASSERT_NE(z, nullptr);
  EXPECT_EQ(std::memcmp(z->GetPointer(0), land.heightMeters.data(), 96 * 80 * sizeof(float)), 0);
  vtkDataArray* river = out->GetPointData()->GetArray("River");
  vtkDataArray* medial = out->GetPointData()->GetArray("MedialAxis");
  vtkDataArray* distance = out->GetPointData()->GetArray("DistanceToRiver");
  long long riverCells = 0;
  for (vtkIdType k = 0; k < 96 * 80; ++k)
  {
    const std::size_t c = static_cast<std::size_t>(k);
    ASSERT_EQ(river->GetComponent(k, 0), land.cls[c] == terroir::generation::RiverLandRiver);
    ASSERT_EQ(medial->GetComponent(k, 0), land.medial[c]);
    if (land.cls[c] != terroir::generation::RiverLandSea)
    {
      ASSERT_FLOAT_EQ(distance->GetComponent(k, 0), static_cast<float>(land.distance[c] * 25.0));
    }
    riverCells += river->GetComponent(k, 0) != 0.0 ? 1 : 0;
  }
  EXPECT_GT(riverCells, 0);
  EXPECT_EQ(source->GetMedialCellsAfter(), land.medialAfter);

  // Port 1: every polyline vertex is the centre of a river cell, one line per river.
  auto* lines = vtkPolyData::SafeDownCast(source->GetOutputDataObject(1));
  ASSERT_NE(lines, nullptr);
  EXPECT_EQ(lines->GetNumberOfCells(), static_cast<vtkIdType>(land.rivers.size()));
  ASSERT_NE(lines->GetCellData()->GetArray("Level"), nullptr);
  for (vtkIdType k = 0; k < lines->GetNumberOfPoints(); ++k)
  {
    double xyz[3];
    lines->GetPoint(k, xyz);
    const int i = static_cast<int>(std::lround(xyz[0] / 25.0));
    const int j = static_cast<int>(std::lround(xyz[1] / 25.0));
    ASSERT_EQ(river->GetComponent(static_cast<vtkIdType>(j) * 96 + i, 0), 1.0) << k;
  }
}

TEST(TerroirRiverLandSource, JsonOverridesPropertiesAndThreadsKeepTheBits)
{
  vtkNew<vtkTerroirRiverLandSource> a;
  a->SetDimensions(200, 200);
  a->SetSeed(4);
  a->SetParametersJSON(R"({"width": 120, "height": 100, "seed": 9, "noise_amplitude": 20,
    "slopes": [{"x": 0.5, "y": 0.5, "profile": "cos2", "influence": 20}]})");
  a->Update();
  int dims[3];
  a->GetOutput()->GetDimensions(dims);
  EXPECT_EQ(dims[0], 120);
  EXPECT_EQ(dims[1], 100);
  vtkNew<vtkTerroirRiverLandSource> b;
  b->SetParametersJSON(a->GetParametersJSON());
  b->SetThreads(2);
  b->Update();
  auto* za = vtkFloatArray::SafeDownCast(a->GetOutput()->GetPointData()->GetArray("Elevation"));
  auto* zb = vtkFloatArray::SafeDownCast(b->GetOutput()->GetPointData()->GetArray("Elevation"));
  ASSERT_NE(zb, nullptr);
  EXPECT_EQ(std::memcmp(za->GetPointer(0), zb->GetPointer(0), 120 * 100 * sizeof(float)), 0);
  // Seed 9 from the JSON, not the property's 4.
  terroir::generation::RiverLandParameters p;
  std::string error;
  ASSERT_TRUE(terroir::generation::RiverLandParametersFromJson(a->GetParametersJSON(), p, error));
  terroir::generation::RiverLand land;
  ASSERT_TRUE(terroir::generation::GenerateRiverLand(p, land, error));
  EXPECT_EQ(std::memcmp(za->GetPointer(0), land.heightMeters.data(), 120 * 100 * sizeof(float)), 0);
}

TEST(TerroirRiverLandSource, BadParametersAreAClearError)
{
  vtkNew<vtkTerroirRiverLandSource> source;
  source->SetParametersJSON(R"({"hill_slop": 1})");
  vtkNew<terroir_test::ErrorObserver> errors;
  source->AddObserver(vtkCommand::ErrorEvent, errors);
  source->Update();
  EXPECT_GE(errors->ErrorCount, 1);
  EXPECT_EQ(source->GetOutput()->GetNumberOfPoints(), 0);
  EXPECT_NE(
    std::string(source->GetErrorMessage()).find("unknown parameter 'hill_slop'"), std::string::npos)
    << source->GetErrorMessage();
}

// vtkTerroirPolygonIslandSource: its arrays and extent, the same cells as the core generator,
// the same bits for a seed, and a clear error for bad parameters.
#include "PolygonIsland.h"
#include "TerroirFilterTestUtilities.h"
#include "vtkTerroirPolygonIslandSource.h"

#include "vtkCommand.h"

#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"

#include <gtest/gtest.h>

#include <cstring>
#include <string>

TEST(TerroirPolygonIslandSource, ArraysEqualTheCoreGenerator)
{
  vtkNew<vtkTerroirPolygonIslandSource> source;
  source->SetDimensions(96, 80);
  source->SetSpacing(25.0);
  source->SetSeed(12);
  source->SetRegions(300);
  source->Update();
  vtkImageData* out = source->GetOutput();
  int dims[3];
  out->GetDimensions(dims);
  EXPECT_EQ(dims[0], 96);
  EXPECT_EQ(dims[1], 80);
  EXPECT_EQ(out->GetSpacing()[0], 25.0);
  for (const char* name : { "Elevation", "Biome", "Moisture", "River", "WaterClass", "RegionId" })
  {
    ASSERT_NE(out->GetPointData()->GetArray(name), nullptr) << name;
    EXPECT_EQ(out->GetPointData()->GetArray(name)->GetNumberOfTuples(), 96 * 80) << name;
  }
  terroir::generation::PolygonIslandParameters p;
  p.width = 96;
  p.height = 80;
  p.seed = 12;
  p.regions = 300;
  terroir::generation::PolygonIsland island;
  std::string error;
  ASSERT_TRUE(terroir::generation::GeneratePolygonIsland(p, island, error)) << error;
  auto* z = vtkFloatArray::SafeDownCast(out->GetPointData()->GetArray("Elevation"));
  ASSERT_NE(z, nullptr);
  EXPECT_EQ(std::memcmp(z->GetPointer(0), island.heightMeters.data(), 96 * 80 * sizeof(float)), 0);
  vtkDataArray* biome = out->GetPointData()->GetArray("Biome");
  vtkDataArray* water = out->GetPointData()->GetArray("WaterClass");
  for (vtkIdType k = 0; k < 96 * 80; ++k)
  {
    ASSERT_EQ(biome->GetComponent(k, 0), island.biomeMap[static_cast<std::size_t>(k)]);
    ASSERT_EQ(water->GetComponent(k, 0), island.waterMap[static_cast<std::size_t>(k)]);
  }
  // The same seed again: the same bits; another: another island.
  vtkNew<vtkTerroirPolygonIslandSource> again;
  again->SetDimensions(96, 80);
  again->SetSeed(12);
  again->SetRegions(300);
  again->Update();
  auto* z2 = vtkFloatArray::SafeDownCast(again->GetOutput()->GetPointData()->GetArray("Elevation"));
  EXPECT_EQ(std::memcmp(z->GetPointer(0), z2->GetPointer(0), 96 * 80 * sizeof(float)), 0);
  again->SetSeed(13);
  again->Update();
  z2 = vtkFloatArray::SafeDownCast(again->GetOutput()->GetPointData()->GetArray("Elevation"));
  EXPECT_NE(std::memcmp(z->GetPointer(0), z2->GetPointer(0), 96 * 80 * sizeof(float)), 0);
}

TEST(TerroirPolygonIslandSource, BadParametersAreAClearError)
{
  vtkNew<vtkTerroirPolygonIslandSource> source;
  source->SetDimensions(64, 64);
  source->SetRegions(5000); // more than a quarter of the cells
  vtkNew<terroir_test::ErrorObserver> errors;
  source->AddObserver(vtkCommand::ErrorEvent, errors);
  source->Update();
  EXPECT_EQ(errors->ErrorCount, 1);
  EXPECT_EQ(source->GetOutput()->GetNumberOfPoints(), 0);
  EXPECT_NE(std::string(source->GetErrorMessage()).find("regions"), std::string::npos)
    << source->GetErrorMessage();
}

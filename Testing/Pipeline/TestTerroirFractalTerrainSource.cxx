// Pipeline tests of vtkTerroirFractalTerrainSource.
#include "FractalNoise.h"
#include "vtkTerroirFractalTerrainSource.h"
#include "vtkTerroirGeoreference.h"

#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkSMPTools.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

namespace
{
std::vector<float> Generate(int nx, int ny, unsigned seed)
{
  vtkNew<vtkTerroirFractalTerrainSource> source;
  source->SetDimensions(nx, ny);
  source->SetSeed(seed);
  source->Update();
  auto* e = vtkFloatArray::SafeDownCast(source->GetOutput()->GetPointData()->GetArray("Elevation"));
  if (!e)
  {
    return {};
  }
  return std::vector<float>(e->GetPointer(0), e->GetPointer(0) + e->GetNumberOfValues());
}
} // namespace

TEST(TerroirFractalTerrainSource, DefaultsAndDimensions)
{
  vtkNew<vtkTerroirFractalTerrainSource> source;
  EXPECT_EQ(source->GetDimensions()[0], 512);
  EXPECT_EQ(source->GetDimensions()[1], 512);
  EXPECT_EQ(source->GetSpacing(), 10.0);
  EXPECT_EQ(source->GetSeed(), 1u);
  EXPECT_EQ(source->GetOctaves(), 8);
  EXPECT_EQ(source->GetFeatureSize(), 256.0);
  EXPECT_EQ(source->GetPersistence(), 0.5);
  EXPECT_EQ(source->GetAmplitude(), 500.0);
  EXPECT_EQ(source->GetBaseHeight(), 1500.0);

  source->SetDimensions(301, 207);
  source->SetSpacing(30.0);
  source->UpdateInformation();
  int extent[6];
  source->GetOutputInformation(0)->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent);
  EXPECT_EQ(extent[1], 300);
  EXPECT_EQ(extent[3], 206);
  EXPECT_EQ(source->GetOutput()->GetNumberOfPoints(), 0); // nothing generated yet
  source->Update();
  vtkImageData* img = source->GetOutput();
  int dims[3];
  img->GetDimensions(dims);
  EXPECT_EQ(dims[0], 301);
  EXPECT_EQ(dims[1], 207);
  EXPECT_EQ(dims[2], 1);
  double spacing[3];
  img->GetSpacing(spacing);
  EXPECT_EQ(spacing[0], 30.0);
  EXPECT_EQ(spacing[1], 30.0);
  vtkDataArray* e = img->GetPointData()->GetArray("Elevation");
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->GetDataType(), VTK_FLOAT);
  EXPECT_STREQ(e->GetInformation()->Get(vtkDataArray::UNITS_LABEL()), "m");
  // The VTK output is the core function at (i, j) with j = 0 the first (south) row.
  terroir::io::FractalNoiseParameters p;
  for (int k : { 0, 5000, 301 * 207 - 1 })
  {
    EXPECT_EQ(e->GetComponent(k, 0),
      static_cast<float>(terroir::io::FractalNoisePerlin2002(p, k % 301, k / 301)));
  }
  double range[2];
  e->GetRange(range, 0);
  EXPECT_GE(range[0], 1500.0 - terroir::io::FractalNoiseBound(p));
  EXPECT_LE(range[1], 1500.0 + terroir::io::FractalNoiseBound(p));
}

TEST(TerroirFractalTerrainSource, DeterministicAndSeedDependent)
{
  const auto a = Generate(200, 100, 3);
  const auto b = Generate(200, 100, 3);
  const auto c = Generate(200, 100, 4);
  ASSERT_EQ(a.size(), 20000u);
  EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(float)));
  EXPECT_NE(0, std::memcmp(a.data(), c.data(), a.size() * sizeof(float)));
}

TEST(TerroirFractalTerrainSource, ThreadCountDoesNotChangeOutput)
{
  const std::string backend = vtkSMPTools::GetBackend() ? vtkSMPTools::GetBackend() : "";
  vtkSMPTools::Initialize(1);
  const auto one = Generate(333, 257, 11);
  vtkSMPTools::Initialize(2);
  const auto two = Generate(333, 257, 11);
  vtkSMPTools::SetBackend("Sequential");
  const auto sequential = Generate(333, 257, 11);
  vtkSMPTools::SetBackend("STDThread");
  vtkSMPTools::Initialize(2);
  const auto stdthread = Generate(333, 257, 11);
  if (!backend.empty())
  {
    vtkSMPTools::SetBackend(backend.c_str());
  }
  vtkSMPTools::Initialize(0);
  ASSERT_EQ(one.size(), 333u * 257u);
  EXPECT_EQ(0, std::memcmp(one.data(), two.data(), one.size() * sizeof(float)));
  EXPECT_EQ(0, std::memcmp(one.data(), sequential.data(), one.size() * sizeof(float)));
  EXPECT_EQ(0, std::memcmp(one.data(), stdthread.data(), one.size() * sizeof(float)));
}

TEST(TerroirFractalTerrainSource, RejectsBadParameters)
{
  vtkNew<vtkTerroirFractalTerrainSource> source;
  source->SetDimensions(0, 10);
  source->Update();
  EXPECT_EQ(source->GetOutput()->GetNumberOfPoints(), 0);
  EXPECT_NE(
    std::string(source->GetErrorMessage()).find("invalid Dimensions 0 x 10"), std::string::npos);
  source->SetDimensions(10, 10);
  source->SetSpacing(-1.0);
  source->Update();
  EXPECT_EQ(source->GetOutput()->GetNumberOfPoints(), 0);
  EXPECT_NE(std::string(source->GetErrorMessage()).find("Spacing"), std::string::npos);
  source->SetSpacing(1.0);
  source->Update();
  EXPECT_EQ(source->GetOutput()->GetNumberOfPoints(), 100);
  EXPECT_STREQ(source->GetErrorMessage(), "");
}

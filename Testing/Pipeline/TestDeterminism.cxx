// Determinism: every algorithm of the project (filters, sources, readers, writers) gives
// bit-identical results with 1 and 2 threads, on each of VTK's SMP backends here (STDThread,
// TBB, Sequential), and across repeated runs. Results are compared as raw bytes: every point
// and field array of an output, or the whole file a writer wrote. The list of algorithms is
// checked against the classes declared in the module headers, so a new filter must be added
// here (its GPU path is covered by Testing/GPU/TestDeterminismGPU.cxx).
#include "TerroirFilterTestUtilities.h"
#include "TerroirIOTestUtilities.h"

#include "TerroirFeatureCurveScenes.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"
#include "vtkTable.h"
#include "vtkTerroirDEMReader.h"
#include "vtkTerroirErosion.h"
#include "vtkTerroirFeatureCurveTerrain.h"
#include "vtkTerroirFloodFill.h"
#include "vtkTerroirFlowAccumulation.h"
#include "vtkTerroirFractalTerrainSource.h"
#include "vtkTerroirGeoTIFFWriter.h"
#include "vtkTerroirInfiltration.h"
#include "vtkTerroirKMeans.h"
#include "vtkTerroirMorphometry.h"
#include "vtkTerroirPlantPlacement.h"
#include "vtkTerroirPolygonIslandSource.h"
#include "vtkTerroirRiverLandSource.h"
#include "vtkTerroirSlope.h"
#include "vtkTerroirSoilHumidity.h"
#include "vtkTerroirSolarIllumination.h"
#include "vtkTerroirTemperature.h"
#include "vtkTerroirTerragenReader.h"
#include "vtkTerroirTerragenWriter.h"
#include "vtkTerroirVectorRasterizer.h"
#include "vtkTerroirWaterFlow.h"
// new-filter.sh: includes

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace
{
using Bytes = std::map<std::string, std::string>; ///< array or file name -> raw bytes

void AddArrays(vtkFieldData* data, const std::string& prefix, Bytes& out)
{
  for (int a = 0; data && a < data->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* array = data->GetArray(a);
    if (!array || !array->GetName())
    {
      continue;
    }
    const auto* p = static_cast<const char*>(array->GetVoidPointer(0));
    const std::size_t size = static_cast<std::size_t>(array->GetNumberOfValues()) *
      static_cast<std::size_t>(array->GetDataTypeSize());
    out[prefix + array->GetName()] = std::string(p, p + size);
  }
}

Bytes OutputBytes(vtkImageData* image)
{
  Bytes out;
  EXPECT_NE(image, nullptr);
  if (image)
  {
    EXPECT_GT(image->GetNumberOfPoints(), 0);
    AddArrays(image->GetPointData(), "point:", out);
    AddArrays(image->GetFieldData(), "field:", out);
  }
  return out;
}

/// A point set's bytes: its points and point and field arrays.
Bytes PolyBytes(vtkPolyData* poly)
{
  Bytes out;
  EXPECT_NE(poly, nullptr);
  if (poly && poly->GetPoints())
  {
    EXPECT_GT(poly->GetNumberOfPoints(), 0);
    vtkDataArray* xyz = poly->GetPoints()->GetData();
    out["points"] = std::string(static_cast<const char*>(xyz->GetVoidPointer(0)),
      static_cast<std::size_t>(xyz->GetNumberOfValues()) * xyz->GetDataTypeSize());
    AddArrays(poly->GetPointData(), "point:", out);
    AddArrays(poly->GetFieldData(), "field:", out);
  }
  return out;
}

Bytes FileBytes(const std::string& path)
{
  const std::vector<char> bytes = terroir::testing::ReadWholeFile(path);
  EXPECT_FALSE(bytes.empty()) << path;
  return Bytes{ { path, std::string(bytes.begin(), bytes.end()) } };
}

/// The bundled DEM with a block of no-data cells, so that masks take part.
vtkSmartPointer<vtkImageData> TerrainWithHoles()
{
  static vtkSmartPointer<vtkImageData> terrain;
  if (!terrain)
  {
    terrain =
      terroir_test::ReadDEM(terroir_test::DataFile("sagehen_creek_ca/sagehen_dem_utm11n_10m.tif"));
    vtkDataArray* z = terrain->GetPointData()->GetArray("Elevation");
    for (vtkIdType j = 300; j < 340; ++j)
    {
      for (vtkIdType i = 100; i < 150; ++i)
      {
        z->SetComponent(j * 786 + i, 0, std::nan(""));
      }
    }
  }
  return terrain;
}

std::string Scratch(const std::string& name)
{
  static const std::string dir = terroir::testing::IOScratchFolder("determinism");
  return dir + "/" + name;
}

/// One run of each algorithm; the runner is called under every SMP configuration.
const std::map<std::string, std::function<Bytes()>>& Runners()
{
  static const std::map<std::string, std::function<Bytes()>> runners = {
    { "vtkTerroirSlope",
      []
      {
        vtkNew<vtkTerroirSlope> f;
        f->SetBackendToCPU();
        f->SetInputData(TerrainWithHoles());
        f->Update();
        return OutputBytes(f->GetOutput());
      } },
    { "vtkTerroirSolarIllumination",
      []
      {
        // Horizon map (sectors split over threads) and a day of half-hour steps (cells split).
        vtkNew<vtkTerroirSolarIllumination> f;
        f->SetBackendToCPU();
        f->SetModeToDaily();
        f->SetTimeStep(30.0);
        f->SetHorizonSectors(16);
        f->SetOutputHorizonMap(true);
        f->SetInputData(TerrainWithHoles());
        f->Update();
        return OutputBytes(f->GetOutput());
      } },
    { "vtkTerroirInfiltration",
      []
      {
        // The default recipe: fill, then the slope rule with a slope computed inside.
        vtkNew<vtkTerroirInfiltration> f;
        f->SetInputData(TerrainWithHoles());
        f->Update();
        return OutputBytes(f->GetOutput());
      } },
    { "vtkTerroirSoilHumidity",
      []
      {
        vtkNew<vtkTerroirInfiltration> rates;
        rates->SetInputData(TerrainWithHoles());
        vtkNew<vtkTerroirSoilHumidity> f;
        f->SetBackendToCPU();
        f->SetInputConnection(rates->GetOutputPort());
        f->Update();
        return OutputBytes(f->GetOutput());
      } },
    { "vtkTerroirFloodFill",
      []
      {
        // Both modes: a seed fill of Independence Lake and every depression and flat.
        Bytes all;
        for (int mode : { vtkTerroirFloodFill::Seeds, vtkTerroirFloodFill::FillDepressions })
        {
          vtkNew<vtkTerroirFloodFill> f;
          f->SetMode(mode);
          f->AddSeedPoint(215365.0, 4371215.0);
          f->AddSeedPoint(216000.0, 4368000.0, 2100.0);
          f->SetInputData(TerrainWithHoles());
          f->Update();
          for (const auto& [key, bytes] : OutputBytes(f->GetOutput()))
          {
            all[std::string(f->GetModeAsString()) + ":" + key] = bytes;
          }
        }
        return all;
      } },
    { "vtkTerroirFlowAccumulation",
      []
      {
        // With a weight (the elevation itself, as a stand-in for a depth in mm).
        vtkNew<vtkTerroirFlowAccumulation> f;
        f->SetWeightArrayName("Elevation");
        f->SetInputData(TerrainWithHoles());
        f->Update();
        return OutputBytes(f->GetOutput());
      } },
    { "vtkTerroirWaterFlow",
      []
      {
        // 60 iterations of 100 mm on the terrain with no-data holes.
        vtkNew<vtkTerroirWaterFlow> f;
        f->SetBackendToCPU();
        f->SetMaximumIterations(60);
        f->SetInputData(TerrainWithHoles());
        f->Update();
        return OutputBytes(f->GetOutput());
      } },
    { "vtkTerroirKMeans",
      []
      {
        // Slope and Temperature of the terrain with holes, K = 6, both seedings; the cluster
        // table (port 1) too.
        vtkNew<vtkTerroirSlope> slope;
        slope->SetBackendToCPU();
        slope->SetInputData(TerrainWithHoles());
        vtkNew<vtkTerroirTemperature> temperature;
        temperature->SetBackendToCPU();
        temperature->SetInputConnection(slope->GetOutputPort());
        Bytes all;
        for (int seeding : { vtkTerroirKMeans::Diagonal, vtkTerroirKMeans::KMeansPlusPlus })
        {
          vtkNew<vtkTerroirKMeans> f;
          f->SetBackendToCPU();
          f->SetNumberOfClusters(6);
          f->SetSeeding(seeding);
          f->SetInputConnection(temperature->GetOutputPort());
          f->Update();
          Bytes out = OutputBytes(f->GetOutput());
          AddArrays(f->GetClusterTable()->GetRowData(), "table:", out);
          for (const auto& [key, bytes] : out)
          {
            all[std::to_string(seeding) + ":" + key] = bytes;
          }
        }
        return all;
      } },
    { "vtkTerroirTemperature",
      []
      {
        vtkNew<vtkTerroirTemperature> f;
        f->SetBackendToCPU();
        f->SetInputData(TerrainWithHoles());
        f->Update();
        return OutputBytes(f->GetOutput());
      } },
    { "vtkTerroirFractalTerrainSource",
      []
      {
        vtkNew<vtkTerroirFractalTerrainSource> f;
        f->SetDimensions(640, 480);
        f->SetSeed(7);
        f->Update();
        return OutputBytes(f->GetOutput());
      } },
    { "vtkTerroirPolygonIslandSource",
      []
      {
        vtkNew<vtkTerroirPolygonIslandSource> f;
        f->SetDimensions(320, 240);
        f->SetSeed(7);
        f->SetRegions(500);
        f->Update();
        return OutputBytes(f->GetOutput());
      } },
    { "vtkTerroirRiverLandSource",
      []
      {
        vtkNew<vtkTerroirRiverLandSource> f;
        f->SetDimensions(320, 240);
        f->SetSeed(7);
        f->SetNoiseAmplitude(20.0); // Threads 0: vtkSMPTools' thread count
        f->Update();
        return OutputBytes(f->GetOutput());
      } },
    { "vtkTerroirDEMReader",
      []
      {
        vtkNew<vtkTerroirDEMReader> r;
        r->SetFileName(terroir_test::DataFile("sagehen_creek_ca/ned10m_nad83.img").c_str());
        r->Update();
        return OutputBytes(r->GetOutput());
      } },
    { "vtkTerroirTerragenReader",
      []
      {
        vtkNew<vtkTerroirTerragenReader> r;
        r->SetFileName(
          terroir_test::DataFile("sagehen_creek_ca/sagehen_dem_utm11n_10m.ter").c_str());
        r->Update();
        return OutputBytes(r->GetOutput());
      } },
    { "vtkTerroirGeoTIFFWriter",
      []
      {
        vtkNew<vtkTerroirGeoTIFFWriter> w;
        w->SetInputData(TerrainWithHoles());
        w->SetFileName(Scratch("dem.tif").c_str());
        w->OverwriteOn();
        w->SetCompress(true);
        w->Write();
        EXPECT_STREQ(w->GetErrorMessage(), "");
        return FileBytes(Scratch("dem.tif"));
      } },
    { "vtkTerroirVectorRasterizer",
      []
      {
        // GDAL's rasterisation is single-threaded; checked all the same, lines and polygons.
        vtkNew<vtkTerroirVectorRasterizer> f;
        f->SetInputData(TerrainWithHoles());
        f->SetFileName(
          terroir_test::DataFile("sagehen_creek_ca/sagehen_nhd_flowlines_utm11n.geojson").c_str());
        f->SetAttributeName("FCODE");
        f->AllTouchedOn();
        f->Update();
        return OutputBytes(f->GetOutput());
      } },
    { "vtkTerroirTerragenWriter",
      []
      {
        vtkNew<vtkTerroirTerragenWriter> w;
        w->SetInputData(TerrainWithHoles());
        w->SetFileName(Scratch("dem.ter").c_str());
        w->OverwriteOn();
        w->Write();
        return FileBytes(Scratch("dem.ter"));
      } },
    { "vtkTerroirMorphometry",
      []
      {
        vtkNew<vtkTerroirMorphometry> f;
        f->SetBackendToCPU();
        f->SetInputData(TerrainWithHoles());
        f->Update();
        return OutputBytes(f->GetOutput());
      } },
    { "vtkTerroirFeatureCurveTerrain",
      []
      {
        vtkNew<vtkTerroirFeatureCurveTerrain> f;
        f->SetBackend(1);
        f->SetCurvesData(terroir_test::RidgeAndValley());
        f->SetDimensions(131, 101);
        f->SetTolerance(1e-4);
        f->Update();
        return OutputBytes(f->GetOutput());
      } },
    { "vtkTerroirPlantPlacement",
      []
      {
        // Plants in the k-means zones of the terrain with holes (zones in parallel).
        vtkNew<vtkTerroirSlope> slope;
        slope->SetBackendToCPU();
        slope->SetInputData(TerrainWithHoles());
        vtkNew<vtkTerroirKMeans> zones;
        zones->SetBackendToCPU();
        zones->SetNumberOfClusters(4);
        zones->SetInputConnection(slope->GetOutputPort());
        vtkNew<vtkTerroirPlantPlacement> f;
        f->SetInputConnection(zones->GetOutputPort());
        f->SetDensity(0.0001); // about 5,700 plants on the 57 km2 DEM: quick under ASan too
        f->SetMinimumDistance(30.0);
        f->SetSeed(9);
        f->Update();
        return PolyBytes(f->GetOutput());
      } },
    { "vtkTerroirErosion",
      []
      {
        // 10 steps of water, erosion, soil slip, vegetation and weather (wind, vapour, rain) on
        // the terrain with holes (rows in parallel; the sanitizer build runs this case on every
        // SMP backend too).
        vtkNew<vtkTerroirErosion> f;
        f->SetInputData(TerrainWithHoles());
        f->SetSteps(10);
        f->VegetationOn();
        f->WeatherOn();
        f->SetEvaporationScale(1e4);
        f->SetInitialWater(0.5);
        f->SetRainRate(5000.0);
        f->Update();
        return OutputBytes(f->GetOutput());
      } },
    // new-filter.sh: cases
  };
  return runners;
}

struct SMPConfig
{
  const char* Backend;
  int Threads;
};

std::string Describe(const SMPConfig& c)
{
  return std::string(c.Backend) + " x " + std::to_string(c.Threads);
}
} // namespace

TEST(TerroirDeterminism, EveryAlgorithmOfTheProjectIsCovered)
{
  const auto classes = terroir_test::ProjectAlgorithmClasses();
  ASSERT_GE(classes.size(), Runners().size()) << "the header scan found too few classes";
  for (const auto& c : classes)
  {
    EXPECT_EQ(Runners().count(c.Name), 1u)
      << c.Name << " (" << c.Header << ") has no determinism run in TestDeterminism.cxx";
  }
}

TEST(TerroirDeterminism, BitIdenticalWithOneAndTwoThreadsOnEverySMPBackend)
{
  const std::string original = vtkSMPTools::GetBackend();
  const std::vector<SMPConfig> configs = { { "STDThread", 1 },
    { "STDThread", 2 },
    { "TBB", 1 },
    { "TBB", 2 },
    { "Sequential", 1 },
    { "STDThread", 2 } };
  for (const auto& entry : Runners())
  {
    // Not a structured binding: clang 14 cannot capture those in the lambda below.
    const std::string& name = entry.first;
    const std::function<Bytes()>& run = entry.second;
    Bytes reference;
    std::string referenceConfig;
    for (const SMPConfig& config : configs)
    {
      if (!vtkSMPTools::SetBackend(config.Backend))
      {
        continue; // not compiled into this VTK
      }
      Bytes result;
      vtkSMPTools::LocalScope(vtkSMPTools::Config{ config.Threads }, [&] { result = run(); });
      if (referenceConfig.empty())
      {
        reference = result;
        referenceConfig = Describe(config);
        EXPECT_FALSE(reference.empty()) << name;
        continue;
      }
      ASSERT_EQ(result.size(), reference.size()) << name << ": " << Describe(config);
      for (const auto& [key, bytes] : reference)
      {
        EXPECT_TRUE(result[key] == bytes) << name << ": '" << key << "' differs between "
                                          << referenceConfig << " and " << Describe(config);
      }
    }
    EXPECT_FALSE(referenceConfig.empty());
  }
  vtkSMPTools::SetBackend(original.c_str());
}

// vtkTerroirPlantPlacement: plants for every zone of a ClusterId image. The answers are
// checked independently: each plant's zone against the cell under it, distances between
// plants by brute force, counts against density x zone area, z against the plane the
// elevation samples, and an exemplar made here by dart throwing.
#include "TerroirFilterTestUtilities.h"

#include "vtkCommand.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkTerroirPlantPlacement.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace
{
constexpr double kOrigin[2] = { 1000.0, 2000.0 };

/// 200 x 100 points, 1 m apart: zone 0 west of column 100, zone 1 east of it, no zone (-1) in
/// the 5 southern rows; Elevation = 10 + 0.5 x + 0.25 y (x, y from the origin).
vtkSmartPointer<vtkImageData> Zones()
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(200, 100, 1);
  image->SetOrigin(kOrigin[0], kOrigin[1], 0.0);
  image->SetSpacing(1.0, 1.0, 1.0);
  auto labels = vtkSmartPointer<vtkIntArray>::New();
  labels->SetName("ClusterId");
  auto z = vtkSmartPointer<vtkFloatArray>::New();
  z->SetName("Elevation");
  for (int j = 0; j < 100; ++j)
  {
    for (int i = 0; i < 200; ++i)
    {
      labels->InsertNextValue(j < 5 ? -1 : (i < 100 ? 0 : 1));
      z->InsertNextValue(static_cast<float>(10.0 + 0.5 * i + 0.25 * j));
    }
  }
  image->GetPointData()->AddArray(labels);
  image->GetPointData()->AddArray(z);
  return image;
}

/// The zone of the cell under (x, y) in Zones(): each point stands for the 1 m cell around it.
int ZoneUnder(double x, double y)
{
  const int i = static_cast<int>(std::floor(x - kOrigin[0] + 0.5));
  const int j = static_cast<int>(std::floor(y - kOrigin[1] + 0.5));
  if (i < 0 || i >= 200 || j < 0 || j >= 100)
  {
    return -2;
  }
  return j < 5 ? -1 : (i < 100 ? 0 : 1);
}

/// The smallest distance between two plants of the same zone (brute force).
double SmallestDistanceWithinZones(vtkPolyData* plants)
{
  vtkDataArray* zone = plants->GetPointData()->GetArray("ClusterId");
  double best = 1e300;
  for (vtkIdType a = 0; a < plants->GetNumberOfPoints(); ++a)
  {
    double p[3];
    plants->GetPoint(a, p);
    for (vtkIdType b = a + 1; b < plants->GetNumberOfPoints(); ++b)
    {
      double q[3];
      plants->GetPoint(b, q);
      if (zone->GetComponent(a, 0) == zone->GetComponent(b, 0))
      {
        best = std::min(best, std::hypot(p[0] - q[0], p[1] - q[1]));
      }
    }
  }
  return best;
}

std::map<int, int> CountPerZone(vtkPolyData* plants)
{
  std::map<int, int> count;
  vtkDataArray* zone = plants->GetPointData()->GetArray("ClusterId");
  for (vtkIdType p = 0; p < plants->GetNumberOfPoints(); ++p)
  {
    ++count[static_cast<int>(zone->GetComponent(p, 0))];
  }
  return count;
}

/// A hard-core exemplar made by dart throwing: up to `tries` uniform candidates in a 60 x 60 m
/// window, each kept when no kept point is closer than d0; species alternate 0, 1.
vtkSmartPointer<vtkPolyData> DartThrowing(double d0, int tries, unsigned seed)
{
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 60.0);
  std::vector<std::array<double, 2>> kept;
  for (int t = 0; t < tries; ++t)
  {
    const std::array<double, 2> c{ u(rng), u(rng) };
    bool ok = true;
    for (const auto& k : kept)
    {
      ok = ok && std::hypot(c[0] - k[0], c[1] - k[1]) >= d0;
    }
    if (ok)
    {
      kept.push_back(c);
    }
  }
  auto data = vtkSmartPointer<vtkPolyData>::New();
  auto points = vtkSmartPointer<vtkPoints>::New();
  auto species = vtkSmartPointer<vtkIntArray>::New();
  species->SetName("Species");
  for (std::size_t k = 0; k < kept.size(); ++k)
  {
    points->InsertNextPoint(kept[k][0], kept[k][1], 0.0);
    species->InsertNextValue(static_cast<int>(k % 2));
  }
  data->SetPoints(points);
  data->GetPointData()->AddArray(species);
  auto window = vtkSmartPointer<vtkDoubleArray>::New();
  window->SetName("ExemplarWindow");
  for (double v : { 0.0, 60.0, 0.0, 60.0 })
  {
    window->InsertNextValue(v);
  }
  data->GetFieldData()->AddArray(window);
  return data;
}

vtkSmartPointer<vtkPolyData> Place(vtkImageData* zones,
  vtkPolyData* exemplar,
  unsigned long long seed,
  std::string* errors = nullptr)
{
  vtkNew<vtkTerroirPlantPlacement> f;
  vtkNew<terroir_test::ErrorObserver> observer;
  f->AddObserver(vtkCommand::ErrorEvent, observer);
  f->SetInputData(zones);
  if (exemplar)
  {
    f->SetExemplarData(exemplar);
    f->SetMaximumDistance(12.0);
    f->SetBins(12);
  }
  else
  {
    f->SetDensity(0.02);
    f->SetMinimumDistance(3.0);
  }
  f->SetSeed(seed);
  f->Update();
  if (errors)
  {
    *errors = observer->Errors;
  }
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->ShallowCopy(f->GetOutput());
  return out;
}
} // namespace

// Without an exemplar: a hard-core pattern of 0.02 plants per m^2, none closer than 3 m, in
// each zone's cells only; every plant's ClusterId is the zone under it; counts within 10 % of
// density x area (95 x 100 m^2 per zone: 190 plants); z on the elevation plane.
TEST(TerroirPlantPlacement, HardCorePlantsStayInTheirZones)
{
  vtkSmartPointer<vtkImageData> zones = Zones();
  vtkSmartPointer<vtkPolyData> plants = Place(zones, nullptr, 1);
  ASSERT_GT(plants->GetNumberOfPoints(), 0);
  EXPECT_EQ(plants->GetNumberOfVerts(), plants->GetNumberOfPoints());
  vtkDataArray* zone = plants->GetPointData()->GetArray("ClusterId");
  ASSERT_NE(zone, nullptr);
  for (vtkIdType p = 0; p < plants->GetNumberOfPoints(); ++p)
  {
    double x[3];
    plants->GetPoint(p, x);
    ASSERT_EQ(ZoneUnder(x[0], x[1]), static_cast<int>(zone->GetComponent(p, 0))) << "plant " << p;
    // The plane, with the position clamped to the grid's points (the outer half cells).
    const double u = std::min(std::max(x[0] - kOrigin[0], 0.0), 199.0);
    const double v = std::min(std::max(x[1] - kOrigin[1], 0.0), 99.0);
    EXPECT_NEAR(x[2], 10.0 + 0.5 * u + 0.25 * v, 1e-4) << "plant " << p;
  }
  EXPECT_GE(SmallestDistanceWithinZones(plants), 3.0);
  const std::map<int, int> count = CountPerZone(plants);
  EXPECT_EQ(count.count(-1), 0u);
  for (int z : { 0, 1 })
  {
    EXPECT_NEAR(count.at(z), 0.02 * 95.0 * 100.0, 19.0) << "zone " << z;
  }
  vtkDataArray* counts = plants->GetFieldData()->GetArray("PlantCounts");
  ASSERT_NE(counts, nullptr);
  EXPECT_EQ(counts->GetComponent(0, 0), count.at(0));
  EXPECT_EQ(counts->GetComponent(1, 0), count.at(1));
}

// With an exemplar (dart throwing, 4 m hard core, two species): the plants keep the
// exemplar's hard core (no pair of a zone closer than its smallest distance, >= 4 m), its
// density within 10 %, and both species.
TEST(TerroirPlantPlacement, ReproducesAnExemplar)
{
  vtkSmartPointer<vtkPolyData> exemplar = DartThrowing(4.0, 400, 11);
  const double density = exemplar->GetNumberOfPoints() / 3600.0;
  ASSERT_GT(exemplar->GetNumberOfPoints(), 100);
  vtkSmartPointer<vtkPolyData> plants = Place(Zones(), exemplar, 5);
  EXPECT_GE(SmallestDistanceWithinZones(plants), 4.0 - 1e-9);
  const std::map<int, int> count = CountPerZone(plants);
  for (int z : { 0, 1 })
  {
    EXPECT_NEAR(count.at(z), density * 9500.0, 0.1 * density * 9500.0) << "zone " << z;
  }
  vtkDataArray* species = plants->GetPointData()->GetArray("Species");
  ASSERT_NE(species, nullptr);
  int seen[2] = { 0, 0 };
  for (vtkIdType p = 0; p < plants->GetNumberOfPoints(); ++p)
  {
    const int s = static_cast<int>(species->GetComponent(p, 0));
    ASSERT_TRUE(s == 0 || s == 1);
    ++seen[s];
  }
  EXPECT_GT(seen[0], 50);
  EXPECT_GT(seen[1], 50);
}

// Without an ExemplarWindow the window is the points' bounds: the points that make the upper
// bounds are inside it (the window is half-open; they were refused before).
TEST(TerroirPlantPlacement, TheBoundsWindowHoldsThePointsOnItsUpperEdges)
{
  vtkNew<vtkPolyData> exemplar;
  vtkNew<vtkPoints> points;
  for (int k = 0; k < 30; ++k)
  {
    points->InsertNextPoint(3.0 * (k % 6), 5.0 * (k / 6), 0.0); // corner (15, 20) included
  }
  exemplar->SetPoints(points);
  vtkSmartPointer<vtkPolyData> plants = Place(Zones(), exemplar, 3);
  EXPECT_GT(plants->GetNumberOfPoints(), 0);
}

// The same seed gives the same plants, bit for bit; another seed others.
TEST(TerroirPlantPlacement, SeedsDecide)
{
  vtkSmartPointer<vtkImageData> zones = Zones();
  vtkSmartPointer<vtkPolyData> a = Place(zones, nullptr, 3);
  vtkSmartPointer<vtkPolyData> b = Place(zones, nullptr, 3);
  vtkSmartPointer<vtkPolyData> c = Place(zones, nullptr, 4);
  ASSERT_EQ(a->GetNumberOfPoints(), b->GetNumberOfPoints());
  bool differs = a->GetNumberOfPoints() != c->GetNumberOfPoints();
  for (vtkIdType p = 0; p < a->GetNumberOfPoints(); ++p)
  {
    double x[3], y[3];
    a->GetPoint(p, x);
    b->GetPoint(p, y);
    ASSERT_EQ(x[0], y[0]);
    ASSERT_EQ(x[1], y[1]);
    if (!differs)
    {
      double w[3];
      c->GetPoint(p, w);
      differs = w[0] != x[0] || w[1] != x[1];
    }
  }
  EXPECT_TRUE(differs);
}

// Errors: no ClusterId, a species outside 0..63, an empty exemplar window.
TEST(TerroirPlantPlacement, Errors)
{
  std::string errors;
  vtkSmartPointer<vtkImageData> plain = Zones();
  plain->GetPointData()->RemoveArray("ClusterId");
  EXPECT_EQ(Place(plain, nullptr, 1, &errors)->GetNumberOfPoints(), 0);
  EXPECT_NE(errors.find("no one-component point array `ClusterId`"), std::string::npos) << errors;

  vtkSmartPointer<vtkPolyData> exemplar = DartThrowing(4.0, 50, 2);
  vtkIntArray::SafeDownCast(exemplar->GetPointData()->GetArray("Species"))->SetValue(3, 70);
  EXPECT_EQ(Place(Zones(), exemplar, 1, &errors)->GetNumberOfPoints(), 0);
  EXPECT_NE(errors.find("exemplar plant 3 has Species 70"), std::string::npos) << errors;

  vtkSmartPointer<vtkPolyData> line = DartThrowing(4.0, 50, 2);
  line->GetFieldData()->RemoveArray("ExemplarWindow");
  for (vtkIdType p = 0; p < line->GetNumberOfPoints(); ++p)
  {
    double x[3];
    line->GetPoint(p, x);
    line->GetPoints()->SetPoint(p, x[0], 5.0, 0.0); // every plant on one line: no area
  }
  EXPECT_EQ(Place(Zones(), line, 1, &errors)->GetNumberOfPoints(), 0);
  EXPECT_NE(errors.find("window"), std::string::npos) << errors;
}

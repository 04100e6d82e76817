// Pipeline tests of vtkTerroirKMeans: regions with known resources give the exact partition
// and the table their known means; the diagonal seeds set the cluster numbering; weights,
// standardisation and the storage trick do what they say; no data; defaults and errors;
// vtkKMeansStatistics (VTK's own k-means) from the same initial centres gives the same centres.
#include "TerroirFilterTestUtilities.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkIntArray.h"
#include "vtkKMeansStatistics.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkPointData.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkTerroirKMeans.h"
#include "vtkTerroirSlope.h"
#include "vtkTerroirTemperature.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace
{
using terroir_test::MakeTerrain;

constexpr int NX = 45;
constexpr int NY = 30;

/// Adds a float point array `name` with `components` components: value(i, j, component).
void AddArray(vtkImageData* image,
  const char* name,
  int components,
  const std::function<double(int, int, int)>& value,
  const char* units = nullptr)
{
  int dims[3];
  image->GetDimensions(dims);
  vtkNew<vtkFloatArray> a;
  a->SetName(name);
  a->SetNumberOfComponents(components);
  a->SetNumberOfTuples(static_cast<vtkIdType>(dims[0]) * dims[1]);
  for (int j = 0; j < dims[1]; ++j)
  {
    for (int i = 0; i < dims[0]; ++i)
    {
      for (int c = 0; c < components; ++c)
      {
        a->SetComponent(static_cast<vtkIdType>(j) * dims[0] + i, c, value(i, j, c));
      }
    }
  }
  if (units)
  {
    a->GetInformation()->Set(vtkDataArray::UNITS_LABEL(), units);
  }
  image->GetPointData()->AddArray(a);
}

/// Region of a cell: column thirds 0, 1, 2 (west to east).
int Third(int i)
{
  return i / (NX / 3);
}

/// A flat terrain whose Slope and Temperature are constant over the three column thirds:
/// Slope 5, 20, 35 degrees; Temperature (12 months) 10 + m, 0 + m, -10 + m degrees C.
vtkSmartPointer<vtkImageData> ThreeRegions()
{
  auto t = MakeTerrain(NX, NY, 10.0, 10.0, [](int, int) { return 1000.0; });
  AddArray(
    t, "Slope", 1, [](int i, int, int) { return 5.0 + 15.0 * Third(i); }, "deg");
  AddArray(
    t, "Temperature", 12, [](int i, int, int m) { return 10.0 - 10.0 * Third(i) + m; }, "degC");
  return t;
}

vtkSmartPointer<vtkImageData> RunKMeans(vtkTerroirKMeans* f, vtkImageData* in)
{
  f->SetBackendToCPU();
  f->SetInputData(in);
  f->Update();
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->ShallowCopy(f->GetOutput());
  return out;
}

std::vector<int> Ids(vtkImageData* out)
{
  auto* a = vtkIntArray::SafeDownCast(out->GetPointData()->GetArray("ClusterId"));
  EXPECT_NE(a, nullptr);
  std::vector<int> ids;
  for (vtkIdType k = 0; a && k < a->GetNumberOfTuples(); ++k)
  {
    ids.push_back(a->GetValue(k));
  }
  return ids;
}

/// True when `ids` and `regions` are the same partition up to renumbering (-1 must match -1).
bool SamePartition(const std::vector<int>& ids, const std::vector<int>& regions)
{
  std::map<int, int> forward, backward;
  if (ids.size() != regions.size())
  {
    return false;
  }
  for (std::size_t k = 0; k < ids.size(); ++k)
  {
    if ((ids[k] < 0) != (regions[k] < 0))
    {
      return false;
    }
    if (ids[k] < 0)
    {
      continue;
    }
    auto f = forward.emplace(ids[k], regions[k]).first;
    auto b = backward.emplace(regions[k], ids[k]).first;
    if (f->second != regions[k] || b->second != ids[k])
    {
      return false;
    }
  }
  return true;
}

double FieldNumber(vtkImageData* out, const char* name)
{
  vtkDataArray* a = out->GetFieldData()->GetArray(name);
  EXPECT_NE(a, nullptr) << name;
  return a ? a->GetComponent(0, 0) : std::nan("");
}

std::string ErrorsOf(vtkTerroirKMeans* f, vtkImageData* in)
{
  vtkNew<terroir_test::ErrorObserver> errors;
  f->AddObserver(vtkCommand::ErrorEvent, errors);
  f->SetBackendToCPU();
  f->SetInputData(in);
  f->Update();
  return errors->Errors;
}
} // namespace

TEST(TerroirKMeans, RegionsGiveTheExactPartitionAndTheTableTheirMeans)
{
  auto in = ThreeRegions();
  vtkNew<vtkTerroirKMeans> f;
  f->SetNumberOfClusters(3);
  auto out = RunKMeans(f, in);
  const std::vector<int> ids = Ids(out);
  std::vector<int> regions;
  for (int j = 0; j < NY; ++j)
  {
    for (int i = 0; i < NX; ++i)
    {
      regions.push_back(Third(i));
    }
  }
  EXPECT_TRUE(SamePartition(ids, regions));

  // Diagonal seeds: the diagonal crosses the thirds west to east, so seed c (cluster c) lies in
  // third c; the cluster numbers follow.
  EXPECT_EQ(ids[0], 0);
  EXPECT_EQ(ids[NX - 1 + (NY - 1) * NX], 2);
  EXPECT_EQ(ids[NX / 2 + (NY / 2) * NX], 1);

  vtkTable* table = f->GetClusterTable();
  ASSERT_NE(table, nullptr);
  ASSERT_EQ(table->GetNumberOfRows(), 3);
  // 4 fixed columns + Slope + 12 months of Temperature.
  ASSERT_EQ(table->GetNumberOfColumns(), 4 + 1 + 12);
  EXPECT_STREQ(table->GetColumnName(0), "ClusterId");
  EXPECT_STREQ(table->GetColumnName(1), "Color");
  EXPECT_STREQ(table->GetColumnName(2), "Cells");
  EXPECT_STREQ(table->GetColumnName(3), "Share");
  EXPECT_STREQ(table->GetColumnName(4), "Slope");
  EXPECT_STREQ(table->GetColumnName(5), "Temperature_0"); // no component names on this array
  EXPECT_STREQ(table->GetColumn(4)->GetInformation()->Get(vtkDataArray::UNITS_LABEL()), "deg");
  long long cells = 0;
  double share = 0.0;
  for (int c = 0; c < 3; ++c)
  {
    EXPECT_EQ(table->GetValue(c, 0).ToInt(), c);
    EXPECT_EQ(table->GetValueByName(c, "Cells").ToLongLong(), NX / 3 * NY);
    EXPECT_DOUBLE_EQ(table->GetValueByName(c, "Share").ToDouble(), 1.0 / 3.0);
    cells += table->GetValueByName(c, "Cells").ToLongLong();
    share += table->GetValueByName(c, "Share").ToDouble();
    // Cluster c is third c: slope 5 + 15c, temperature of month m 10 - 10c + m.
    EXPECT_DOUBLE_EQ(table->GetValueByName(c, "Slope").ToDouble(), 5.0 + 15.0 * c);
    EXPECT_DOUBLE_EQ(table->GetValueByName(c, "Temperature_7").ToDouble(), 10.0 - 10.0 * c + 7);
  }
  EXPECT_EQ(cells, NX * NY);
  EXPECT_DOUBLE_EQ(share, 1.0);
  EXPECT_EQ(table->GetValue(0, 1).ToString(), "#1f77b4");
  EXPECT_EQ(table->GetValue(1, 1).ToString(), "#ff7f0e");

  // Every cell sits on its centre: no within-cluster spread. The seeds already are the
  // regions' values, so the first iteration moves no centre: a centre shift of 0 <= tolerance
  // stops the run after one iteration (scikit-learn's rule; the first iteration can never
  // count as "no label changed", every label being new).
  EXPECT_EQ(FieldNumber(out, "KMeansWithinClusterSumOfSquares"), 0.0);
  EXPECT_EQ(FieldNumber(out, "KMeansIterations"), 1.0);
  auto* reason =
    vtkStringArray::SafeDownCast(out->GetFieldData()->GetAbstractArray("KMeansStopReason"));
  ASSERT_NE(reason, nullptr);
  EXPECT_EQ(reason->GetValue(0), "Tolerance");
  vtkDataArray* shares = out->GetFieldData()->GetArray("KMeansClusterShare");
  ASSERT_NE(shares, nullptr);
  EXPECT_EQ(shares->GetNumberOfTuples(), 3);
  // Temperature's months differ by the constants 1, 2, ... 11: stored as one feature.
  auto* collapsed =
    vtkStringArray::SafeDownCast(out->GetFieldData()->GetAbstractArray("KMeansCollapsedArrays"));
  ASSERT_NE(collapsed, nullptr);
  ASSERT_EQ(collapsed->GetNumberOfValues(), 1);
  EXPECT_EQ(collapsed->GetValue(0), "Temperature");
}

TEST(TerroirKMeans, NoDataCellsGetMinusOneAndTakeNoPart)
{
  // A NaN elevation (terrain no data) and a NaN slope (feature no data) in the west third.
  auto in = MakeTerrain(
    NX, NY, 10.0, 10.0, [](int i, int j) { return i == 3 && j == 4 ? std::nan("") : 1000.0; });
  AddArray(in,
    "Slope",
    1,
    [](int i, int j, int) { return i == 5 && j == 6 ? std::nan("") : 5.0 + 15.0 * Third(i); });
  vtkNew<vtkTerroirKMeans> f;
  f->SetNumberOfClusters(3);
  auto out = RunKMeans(f, in);
  const std::vector<int> ids = Ids(out);
  ASSERT_EQ(ids.size(), static_cast<std::size_t>(NX * NY));
  EXPECT_EQ(ids[3 + 4 * NX], -1);
  EXPECT_EQ(ids[5 + 6 * NX], -1);
  vtkTable* table = f->GetClusterTable();
  long long cells = 0;
  for (vtkIdType c = 0; c < table->GetNumberOfRows(); ++c)
  {
    cells += table->GetValueByName(c, "Cells").ToLongLong();
  }
  EXPECT_EQ(cells, NX * NY - 2);
  EXPECT_DOUBLE_EQ(table->GetValueByName(0, "Cells").ToDouble() / (NX * NY - 2),
    table->GetValueByName(0, "Share").ToDouble());
  EXPECT_EQ(table->GetValueByName(0, "Cells").ToLongLong(), NX / 3 * NY - 2);
}

TEST(TerroirKMeans, AZeroWeightRemovesAFeature)
{
  // Slope splits west/middle/east; a second array, Rows, splits south/north with a far larger
  // spread, so with weight 1 it decides a K = 2 partition.
  auto in = ThreeRegions();
  AddArray(in, "Rows", 1, [](int, int j, int) { return j < NY / 2 ? 0.0 : 1000.0; });
  std::vector<int> rows, thirds;
  for (int j = 0; j < NY; ++j)
  {
    for (int i = 0; i < NX; ++i)
    {
      rows.push_back(j < NY / 2 ? 0 : 1);
      thirds.push_back(Third(i));
    }
  }
  {
    vtkNew<vtkTerroirKMeans> f;
    f->SetNumberOfClusters(2);
    f->AddFeature("Slope", 1.0);
    f->AddFeature("Rows", 1.0);
    EXPECT_TRUE(SamePartition(Ids(RunKMeans(f, in)), rows));
  }
  {
    vtkNew<vtkTerroirKMeans> f;
    f->SetNumberOfClusters(3);
    f->AddFeature("Slope", 1.0);
    f->AddFeature("Rows", 0.0);
    auto withZero = RunKMeans(f, in);
    EXPECT_TRUE(SamePartition(Ids(withZero), thirds));
    // The zero-weight array still gets its means in the table (0 and 1000 mixed: 500).
    EXPECT_DOUBLE_EQ(f->GetClusterTable()->GetValueByName(0, "Rows").ToDouble(), 500.0);
    vtkNew<vtkTerroirKMeans> g;
    g->SetNumberOfClusters(3);
    g->AddFeature("Slope", 1.0);
    auto without = RunKMeans(g, in);
    EXPECT_EQ(Ids(withZero), Ids(without));
    EXPECT_EQ(FieldNumber(withZero, "KMeansWithinClusterSumOfSquares"),
      FieldNumber(without, "KMeansWithinClusterSumOfSquares"));
  }
}

TEST(TerroirKMeans, WeightsScaleTheSquaredDistance)
{
  // Within-cluster sum of squares with weight w is w times the one with weight 1 (the distance
  // is sum w_f (x_f - y_f)^2), for the same partition. Slope varies inside each third here.
  auto in = MakeTerrain(NX, NY, 10.0, 10.0, [](int, int) { return 1000.0; });
  AddArray(in, "Slope", 1, [](int i, int j, int) { return 30.0 * Third(i) + (i + j) % 4; });
  vtkNew<vtkTerroirKMeans> one;
  one->SetNumberOfClusters(3);
  one->AddFeature("Slope", 1.0);
  auto a = RunKMeans(one, in);
  vtkNew<vtkTerroirKMeans> four;
  four->SetNumberOfClusters(3);
  four->AddFeature("Slope", 4.0);
  auto b = RunKMeans(four, in);
  EXPECT_EQ(Ids(a), Ids(b));
  const double ssOne = FieldNumber(a, "KMeansWithinClusterSumOfSquares");
  EXPECT_GT(ssOne, 0.0);
  EXPECT_NEAR(FieldNumber(b, "KMeansWithinClusterSumOfSquares"), 4.0 * ssOne, 1e-5 * ssOne);
}

TEST(TerroirKMeans, StandardizeEqualsClusteringZScoresComputedByHand)
{
  // Two arrays on very different scales, with structure in both.
  auto in = MakeTerrain(NX, NY, 10.0, 10.0, [](int, int) { return 1000.0; });
  auto a = [](int i, int j) { return 0.01 * ((i * 7 + j * 3) % 11) + 0.5 * (i > NX / 2); };
  auto b = [](int i, int j) { return 1000.0 * ((i * 5 + j * 13) % 17) + 9000.0 * (j > NY / 3); };
  AddArray(in, "A", 1, [&](int i, int j, int) { return a(i, j); });
  AddArray(in, "B", 1, [&](int i, int j, int) { return b(i, j); });
  // z-scores in double, population standard deviation.
  auto zscore = [](const std::function<double(int, int)>& v)
  {
    double sum = 0.0, sum2 = 0.0;
    for (int j = 0; j < NY; ++j)
    {
      for (int i = 0; i < NX; ++i)
      {
        sum += v(i, j);
      }
    }
    const double mean = sum / (NX * NY);
    for (int j = 0; j < NY; ++j)
    {
      for (int i = 0; i < NX; ++i)
      {
        sum2 += (v(i, j) - mean) * (v(i, j) - mean);
      }
    }
    const double sd = std::sqrt(sum2 / (NX * NY));
    return std::function<double(int, int)>(
      [v, mean, sd](int i, int j) { return (v(i, j) - mean) / sd; });
  };
  auto za = zscore(a);
  auto zb = zscore(b);
  AddArray(in, "ZA", 1, [&](int i, int j, int) { return za(i, j); });
  AddArray(in, "ZB", 1, [&](int i, int j, int) { return zb(i, j); });

  vtkNew<vtkTerroirKMeans> standardized;
  standardized->SetNumberOfClusters(4);
  standardized->AddFeature("A", 1.0);
  standardized->AddFeature("B", 1.0);
  standardized->StandardizeOn();
  auto s = RunKMeans(standardized, in);
  vtkNew<vtkTerroirKMeans> byHand;
  byHand->SetNumberOfClusters(4);
  byHand->AddFeature("ZA", 1.0);
  byHand->AddFeature("ZB", 1.0);
  auto h = RunKMeans(byHand, in);
  EXPECT_EQ(Ids(s), Ids(h));
  EXPECT_NEAR(FieldNumber(s, "KMeansWithinClusterSumOfSquares"),
    FieldNumber(h, "KMeansWithinClusterSumOfSquares"),
    1e-4 * FieldNumber(h, "KMeansWithinClusterSumOfSquares"));
  // And it matters: without standardisation B alone decides.
  vtkNew<vtkTerroirKMeans> raw;
  raw->SetNumberOfClusters(4);
  raw->AddFeature("A", 1.0);
  raw->AddFeature("B", 1.0);
  EXPECT_NE(Ids(RunKMeans(raw, in)), Ids(s));
}

TEST(TerroirKMeans, StorageTrickChangesNothingButTheStorage)
{
  // Temperature's months differ by whole-degree constants; the annual cycle is not constant
  // per cell in Other (amplitude grows eastward), so Other is not collapsed.
  auto in = MakeTerrain(NX, NY, 10.0, 10.0, [](int, int) { return 1000.0; });
  AddArray(in,
    "Temperature",
    12,
    [](int i, int j, int m) { return 0.25 * ((i * 3 + j * 7) % 29) + (m < 6 ? m : 12 - m); });
  AddArray(in, "Other", 12, [](int i, int j, int m) { return 0.1 * i * m + 0.2 * j; });
  vtkNew<vtkTerroirKMeans> on;
  on->SetNumberOfClusters(5);
  on->AddFeature("Temperature", 1.0);
  on->AddFeature("Other", 0.5);
  auto a = RunKMeans(on, in);
  auto* collapsed =
    vtkStringArray::SafeDownCast(a->GetFieldData()->GetAbstractArray("KMeansCollapsedArrays"));
  ASSERT_NE(collapsed, nullptr);
  ASSERT_EQ(collapsed->GetNumberOfValues(), 1);
  EXPECT_EQ(collapsed->GetValue(0), "Temperature");
  vtkNew<vtkTerroirKMeans> off;
  off->SetNumberOfClusters(5);
  off->AddFeature("Temperature", 1.0);
  off->AddFeature("Other", 0.5);
  off->CollapseConstantOffsetsOff();
  auto b = RunKMeans(off, in);
  auto* none =
    vtkStringArray::SafeDownCast(b->GetFieldData()->GetAbstractArray("KMeansCollapsedArrays"));
  ASSERT_NE(none, nullptr);
  EXPECT_EQ(none->GetNumberOfValues(), 0);
  EXPECT_EQ(Ids(a), Ids(b));
  const double ss = FieldNumber(b, "KMeansWithinClusterSumOfSquares");
  EXPECT_NEAR(FieldNumber(a, "KMeansWithinClusterSumOfSquares"), ss, 1e-5 * ss);

  // Tolerance means the same with the trick: the mean feature variance is taken over the 24
  // uncollapsed features, not the 13 stored ones (else the threshold would be 24/13 larger and
  // runs stopped by tolerance would end earlier). Stops by tolerance must happen at the same
  // iteration with and without the trick.
  int byTolerance = 0;
  for (double tolerance : { 1e-4, 1e-3, 1e-2, 3e-2, 1e-1 })
  {
    on->SetTolerance(tolerance);
    off->SetTolerance(tolerance);
    auto x = RunKMeans(on, in);
    auto y = RunKMeans(off, in);
    EXPECT_EQ(FieldNumber(x, "KMeansIterations"), FieldNumber(y, "KMeansIterations")) << tolerance;
    EXPECT_EQ(Ids(x), Ids(y)) << tolerance;
    auto* reason =
      vtkStringArray::SafeDownCast(y->GetFieldData()->GetAbstractArray("KMeansStopReason"));
    byTolerance += reason && reason->GetValue(0) == "Tolerance";
  }
  EXPECT_GT(byTolerance, 0) << "no run stopped by tolerance: the check above proves nothing";
}

TEST(TerroirKMeans, SameCentresAsVTKsKMeansStatistics)
{
  // Four blobs in 3-D on a 40 x 25 grid, one per column quarter (deterministic jitter),
  // K = 4, the same initial centres given to both: VTK's Lloyd iterations
  // (vtkKMeansStatistics, tolerance 0) and ours must end at the same centres.
  const int nx = 40, ny = 25;
  auto blob = [](int i, int) { return i / 10; };
  auto jitter = [](int i, int j, int c)
  { return 0.3 * std::sin(12.9898 * i + 78.233 * j + 37.719 * c); };
  const double centre[4][3] = { { 0, 0, 0 }, { 5, 0, 1 }, { 0, 6, 2 }, { 5, 6, -3 } };
  auto in = MakeTerrain(nx, ny, 10.0, 10.0, [](int, int) { return 1000.0; });
  const char* names[3] = { "X", "Y", "Z" };
  for (int c = 0; c < 3; ++c)
  {
    AddArray(
      in, names[c], 1, [&](int i, int j, int) { return centre[blob(i, j)][c] + jitter(i, j, c); });
  }
  vtkNew<vtkTerroirKMeans> ours;
  ours->SetNumberOfClusters(4);
  for (const char* n : names)
  {
    ours->AddFeature(n, 1.0);
  }
  ours->SetTolerance(0.0);
  auto out = RunKMeans(ours, in);
  vtkTable* table = ours->GetClusterTable();

  // The diagonal seeds of a 40 x 25 grid with 4 clusters (KMeansDiagonalSeedCells): cells
  // t = 5, 15, 25, 35 of the 40-cell diagonal (floor((2i+1) 40 / 8)), i.e. (5, 3), (15, 9),
  // (25, 15), (35, 22) (j = round(t * 24 / 39)): one in each blob.
  const int seeds[4][2] = { { 5, 3 }, { 15, 9 }, { 25, 15 }, { 35, 22 } };
  vtkNew<vtkTable> data;
  vtkNew<vtkTable> initial;
  vtkNew<vtkIdTypeArray> runK; // LEARN_PARAMETERS: first column K (vtkIdType), one run
  runK->SetName("K");
  for (int r = 0; r < 4; ++r)
  {
    runK->InsertNextValue(4);
  }
  initial->AddColumn(runK);
  for (int c = 0; c < 3; ++c)
  {
    vtkNew<vtkDoubleArray> column;
    column->SetName(names[c]);
    vtkNew<vtkDoubleArray> init;
    init->SetName(names[c]);
    vtkDataArray* a = in->GetPointData()->GetArray(names[c]);
    for (vtkIdType k = 0; k < a->GetNumberOfTuples(); ++k)
    {
      column->InsertNextValue(a->GetComponent(k, 0));
    }
    for (const auto& s : seeds)
    {
      init->InsertNextValue(a->GetComponent(s[0] + s[1] * nx, 0));
    }
    data->AddColumn(column);
    initial->AddColumn(init);
  }
  vtkNew<vtkKMeansStatistics> vtk;
  vtk->SetInputData(vtkStatisticsAlgorithm::INPUT_DATA, data);
  vtk->SetInputData(vtkStatisticsAlgorithm::LEARN_PARAMETERS, initial);
  for (const char* n : names)
  {
    vtk->SetColumnStatus(n, 1);
  }
  vtk->RequestSelectedColumns();
  vtk->SetLearnOption(true);
  vtk->SetDeriveOption(true);
  vtk->SetAssessOption(false);
  vtk->SetTolerance(0.0);
  vtk->SetMaxNumIterations(100);
  vtk->Update();
  auto* model = vtkMultiBlockDataSet::SafeDownCast(
    vtk->GetOutputDataObject(vtkStatisticsAlgorithm::OUTPUT_MODEL));
  ASSERT_NE(model, nullptr);
  auto* centres = vtkTable::SafeDownCast(model->GetBlock(0));
  ASSERT_NE(centres, nullptr);
  ASSERT_EQ(centres->GetNumberOfRows(), 4);
  for (vtkIdType r = 0; r < 4; ++r)
  {
    // Row r of VTK's table is the run from our initial centres, cluster r.
    for (const char* n : names)
    {
      const double vtkValue = centres->GetValueByName(r, n).ToDouble();
      const double ourValue = table->GetValueByName(r, n).ToDouble();
      EXPECT_NEAR(ourValue, vtkValue, 1e-6 * (1.0 + std::fabs(vtkValue)))
        << "cluster " << r << " " << n;
    }
  }
  // And the blobs are found.
  std::vector<int> truth;
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      truth.push_back(blob(i, j));
    }
  }
  EXPECT_TRUE(SamePartition(Ids(out), truth));
}

TEST(TerroirKMeans, DefaultFeaturesAreTheSeedsThatExist)
{
  auto in = ThreeRegions();
  AddArray(in, "IlluminationHours", 12, [](int i, int, int m) { return 8.0 + i % 3 + 0.1 * m; });
  vtkNew<vtkTerroirKMeans> f;
  f->SetNumberOfClusters(3);
  auto out = RunKMeans(f, in);
  vtkTable* table = f->GetClusterTable();
  // Slope, Temperature, IlluminationHours (no WeightedSoilHumidity): 4 + 1 + 12 + 12 columns.
  EXPECT_EQ(table->GetNumberOfColumns(), 29);
  EXPECT_EQ(f->GetNumberOfFeatures(), 0);

  auto bare = MakeTerrain(8, 8, 10.0, 10.0, [](int i, int) { return i; });
  vtkNew<vtkTerroirKMeans> g;
  const std::string errors = ErrorsOf(g, bare);
  EXPECT_NE(errors.find("none of the default features"), std::string::npos) << errors;
  EXPECT_EQ(g->GetClusterTable()->GetNumberOfRows(), 0);
}

TEST(TerroirKMeans, BadParametersAndInputsAreClearErrors)
{
  auto in = ThreeRegions();
  vtkNew<vtkStringArray> text;
  text->SetName("Names");
  text->SetNumberOfValues(NX * NY);
  in->GetPointData()->AddArray(text);
  struct Case
  {
    std::function<void(vtkTerroirKMeans*)> set;
    std::string message;
  };
  const std::vector<Case> cases = {
    { [](vtkTerroirKMeans* f) { f->AddFeature("Missing", 1.0); },
      "feature 'Missing' names no point array of the input" },
    { [](vtkTerroirKMeans* f) { f->AddFeature("Names", 1.0); },
      "feature 'Names' is not numeric (vtkStringArray)" },
    { [](vtkTerroirKMeans* f) { f->AddFeature("Slope", -1.0); },
      "feature 'Slope' has weight -1; weights must be finite and >= 0" },
    { [](vtkTerroirKMeans* f) { f->AddFeature("Slope", std::nan("")); },
      "feature 'Slope' has weight nan; weights must be finite and >= 0" },
    { [](vtkTerroirKMeans* f) { f->AddFeature("Slope", 0.0); },
      "every feature weight is 0: nothing to cluster on" },
    { [](vtkTerroirKMeans* f) { f->SetTolerance(-1.0); },
      "Tolerance -1 must be a finite number >= 0" },
  };
  for (const Case& c : cases)
  {
    vtkNew<vtkTerroirKMeans> f;
    c.set(f);
    const std::string errors = ErrorsOf(f, in);
    EXPECT_NE(errors.find(c.message), std::string::npos) << c.message << " | " << errors;
    EXPECT_EQ(f->GetOutput()->GetNumberOfPoints(), 0);
  }
  // Fewer cells with data than clusters.
  auto tiny = MakeTerrain(3, 2, 10.0, 10.0, [](int i, int) { return i == 0 ? std::nan("") : 1.0; });
  AddArray(tiny, "Slope", 1, [](int i, int j, int) { return i + j; });
  vtkNew<vtkTerroirKMeans> f;
  f->SetNumberOfClusters(5);
  const std::string errors = ErrorsOf(f, tiny);
  EXPECT_NE(errors.find("4 cell(s) have data for every feature, fewer than the 5 clusters"),
    std::string::npos)
    << errors;
}

TEST(TerroirKMeans, ContractDefaultsModifiedAndPrintSelf)
{
  vtkNew<vtkTerroirKMeans> f;
  EXPECT_EQ(f->GetNumberOfOutputPorts(), 2);
  EXPECT_EQ(f->GetNumberOfClusters(), 5);
  EXPECT_FALSE(f->GetStandardize());
  EXPECT_EQ(f->GetSeeding(), vtkTerroirKMeans::Diagonal);
  EXPECT_EQ(f->GetRandomSeed(), 0);
  EXPECT_EQ(f->GetMaximumIterations(), 300);
  EXPECT_DOUBLE_EQ(f->GetTolerance(), 1e-4);
  EXPECT_TRUE(f->GetCollapseConstantOffsets());
  EXPECT_STREQ(vtkTerroirKMeans::ClusterIdName(), "ClusterId");
  f->SetNumberOfClusters(100);
  EXPECT_EQ(f->GetNumberOfClusters(), 64);
  vtkMTimeType t = f->GetMTime();
  f->AddFeature("Slope", 2.0);
  EXPECT_GT(f->GetMTime(), t);
  t = f->GetMTime();
  f->AddFeature("Slope", 2.0); // same weight: no change
  EXPECT_EQ(f->GetMTime(), t);
  f->AddFeature("Slope", 3.0); // replaces the weight
  EXPECT_GT(f->GetMTime(), t);
  EXPECT_EQ(f->GetNumberOfFeatures(), 1);
  EXPECT_STREQ(f->GetFeatureName(0), "Slope");
  EXPECT_DOUBLE_EQ(f->GetFeatureWeight(0), 3.0);
  EXPECT_EQ(f->GetFeatureName(1), nullptr);
  std::ostringstream os;
  f->Print(os);
  EXPECT_NE(os.str().find("Features: Slope=3"), std::string::npos) << os.str();
  f->RemoveAllFeatures();
  EXPECT_EQ(f->GetNumberOfFeatures(), 0);
}

TEST(TerroirKMeans, SagehenSlopeAndTemperatureInFiveZones)
{
  auto dem =
    terroir_test::ReadDEM(terroir_test::DataFile("sagehen_creek_ca/sagehen_dem_utm11n_10m.tif"));
  ASSERT_NE(dem, nullptr);
  vtkNew<vtkTerroirSlope> slope;
  slope->SetBackendToCPU();
  slope->SetInputData(dem);
  vtkNew<vtkTerroirTemperature> temperature;
  temperature->SetBackendToCPU();
  temperature->SetInputConnection(slope->GetOutputPort());
  vtkNew<vtkTerroirKMeans> f;
  f->SetBackendToCPU();
  f->SetInputConnection(temperature->GetOutputPort());
  f->Update();
  vtkImageData* out = f->GetOutput();
  const std::vector<int> ids = Ids(out);
  std::vector<long long> count(5, 0);
  long long valid = 0;
  vtkDataArray* z = out->GetPointData()->GetArray("Elevation");
  for (std::size_t k = 0; k < ids.size(); ++k)
  {
    const bool hasData = std::isfinite(z->GetComponent(static_cast<vtkIdType>(k), 0));
    valid += hasData;
    ASSERT_EQ(ids[k] >= 0, hasData) << k;
    if (ids[k] >= 0)
    {
      ASSERT_LT(ids[k], 5);
      ++count[ids[k]];
    }
  }
  vtkTable* table = f->GetClusterTable();
  long long sum = 0;
  for (int c = 0; c < 5; ++c)
  {
    EXPECT_EQ(table->GetValueByName(c, "Cells").ToLongLong(), count[c]);
    EXPECT_GT(count[c], 0);
    sum += count[c];
  }
  EXPECT_EQ(sum, valid);
  // The Temperature filter's months differ by constants (sea-level cycle minus one lapse
  // term) up to float rounding: the storage trick applies.
  auto* collapsed =
    vtkStringArray::SafeDownCast(out->GetFieldData()->GetAbstractArray("KMeansCollapsedArrays"));
  ASSERT_NE(collapsed, nullptr);
  std::cout << "Sagehen, K = 5 on Slope + Temperature: " << FieldNumber(out, "KMeansIterations")
            << " iterations, collapsed arrays: " << collapsed->GetNumberOfValues() << "\n";
}

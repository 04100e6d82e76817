// Pipeline tests of vtkTerroirMorphometry: arrays, units and field data, defaults, errors, the
// CPU-only backend, the whole extent; and the bundled DEM's statistics recomputed here from
// other filters' outputs (vtkTerroirSlope, vtkTerroirFlowAccumulation) and the elevations.
#include "TerroirFilterTestUtilities.h"

#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkTerroirComputeContext.h"
#include "vtkTerroirFlowAccumulation.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirMorphometry.h"
#include "vtkTerroirSlope.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <sstream>
#include <vector>

namespace
{
using terroir_test::MakeTerrain;

vtkSmartPointer<vtkImageData> RunMorphometry(vtkTerroirMorphometry* f, vtkImageData* in)
{
  f->SetInputData(in);
  f->Update();
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->ShallowCopy(f->GetOutput());
  return out;
}

double Field(vtkImageData* out, const char* name, int k = 0)
{
  vtkDataArray* a = vtkDataArray::SafeDownCast(out->GetFieldData()->GetAbstractArray(name));
  EXPECT_NE(a, nullptr) << name;
  return a && k < a->GetNumberOfValues() ? a->GetComponent(k, 0) : NAN;
}

// A plane rising 0.5 m/m to the north (z = 5 j on 10 m cells, 5 x 6) with one no-data cell in
// the north-west corner (0, 5): every value below is worked out by hand as in the unit test
// TiltedPlaneKnownAnswers, with 29 valid cells and column 0 one cell shorter (rows 0..4, its
// head row 4): there A = (5 - j) cells, so only rows 0..2 are channels (2 steps, 20 m).
// Channels: 4 x 4 + 3 = 19 cells, 4 x 30 + 20 = 140 m, 5 order-1 streams of mean 28 m.
TEST(TerroirMorphometry, ArraysUnitsAndFieldData)
{
  auto in =
    MakeTerrain(5, 6, 10.0, 10.0, [](int i, int j) { return i == 0 && j == 5 ? NAN : 5.0 * j; });
  vtkNew<vtkTerroirMorphometry> f;
  f->SetChannelArea(300.0);
  auto out = RunMorphometry(f, in);
  EXPECT_EQ(f->GetLastBackend(), vtkTerroirComputeContext::CPU);
  EXPECT_NE(out->GetPointData()->GetArray("Elevation"), nullptr);
  vtkDataArray* order = out->GetPointData()->GetArray("StrahlerOrder");
  vtkDataArray* depth = out->GetPointData()->GetArray("DepressionDepth");
  vtkDataArray* length = out->GetPointData()->GetArray("FlowLength");
  ASSERT_TRUE(order && depth && length);
  EXPECT_EQ(order->GetDataType(), VTK_UNSIGNED_CHAR);
  EXPECT_EQ(depth->GetDataType(), VTK_FLOAT);
  EXPECT_STREQ(depth->GetInformation()->Get(vtkDataArray::UNITS_LABEL()), "m");
  EXPECT_STREQ(length->GetInformation()->Get(vtkDataArray::UNITS_LABEL()), "m");
  EXPECT_TRUE(std::isnan(depth->GetComponent(0 + 5 * 5, 0)));
  EXPECT_TRUE(std::isnan(length->GetComponent(0 + 5 * 5, 0)));
  EXPECT_EQ(order->GetComponent(0 + 5 * 5, 0), 0);
  for (int j = 0; j < 6; ++j)
  {
    // Column 1: a full column; rows 0..3 drain >= 3 cells.
    EXPECT_EQ(order->GetComponent(1 + 5 * j, 0), j <= 3 ? 1 : 0) << j;
    EXPECT_FLOAT_EQ(static_cast<float>(length->GetComponent(1 + 5 * j, 0)), 10.0f * (5 - j));
  }
  // Column 0 (next to the hole) drains south too: its longest path starts at row 4.
  EXPECT_FLOAT_EQ(static_cast<float>(length->GetComponent(0, 0)), 40.0f);
  EXPECT_EQ(order->GetComponent(0 + 5 * 2, 0), 1); // 3 cells drain through row 2
  EXPECT_EQ(order->GetComponent(0 + 5 * 3, 0), 0); // 2 cells through row 3
  EXPECT_EQ(Field(out, "ValidCells"), 29);
  EXPECT_EQ(Field(out, "ValidArea"), 2900);
  // Heights: 0..20 five times each, 25 four times: mean = (5 * 50 + 100) / 29.
  EXPECT_NEAR(Field(out, "HypsometricIntegral"), (350.0 / 29.0) / 25.0, 1e-12);
  EXPECT_EQ(Field(out, "ChannelCells"), 19);
  EXPECT_NEAR(Field(out, "ChannelLength"), 140.0, 1e-9);
  EXPECT_NEAR(Field(out, "DrainageDensity"), 0.140 / 0.0029, 1e-9);
  EXPECT_EQ(Field(out, "HortonStreamCount", 0), 5);
  EXPECT_NEAR(Field(out, "HortonMeanLength", 0), 28.0, 1e-9);
  EXPECT_TRUE(std::isnan(Field(out, "BifurcationRatio")));
  EXPECT_EQ(Field(out, "HortonOrdersFitted", 1), 0);
  EXPECT_EQ(Field(out, "DepressionShare"), 0.0);
  EXPECT_EQ(Field(out, "SlopeBinWidth"), 5.0);
  vtkDataArray* histogram =
    vtkDataArray::SafeDownCast(out->GetFieldData()->GetAbstractArray("SlopeHistogram"));
  ASSERT_NE(histogram, nullptr);
  EXPECT_EQ(histogram->GetNumberOfValues(), 18);
  double cells = 0;
  for (vtkIdType k = 0; k < 18; ++k)
  {
    cells += histogram->GetComponent(k, 0);
  }
  EXPECT_EQ(cells, 29);
  EXPECT_GT(Field(out, "HackExponent"), 1.0); // L = A/dx - dx on a plane (unit test)
}

TEST(TerroirMorphometry, DefaultsModifiedAndPrintSelf)
{
  vtkNew<vtkTerroirMorphometry> f;
  EXPECT_EQ(f->GetChannelArea(), 1e5);
  EXPECT_EQ(f->GetDepressionDepth(), 1e-3);
  EXPECT_EQ(f->GetSlopeBinWidth(), 5.0);
  EXPECT_STREQ(f->GetInputArrayInformation(0)->Get(vtkDataObject::FIELD_NAME()), "Elevation");
  std::vector<std::function<void()>> changes = {
    [&] { f->SetChannelArea(5e4); },
    [&] { f->SetDepressionDepth(0.01); },
    [&] { f->SetSlopeBinWidth(10); },
  };
  for (std::size_t c = 0; c < changes.size(); ++c)
  {
    const vtkMTimeType before = f->GetMTime();
    changes[c]();
    EXPECT_GT(f->GetMTime(), before) << "change " << c;
  }
  std::ostringstream os;
  f->Print(os);
  for (const char* word :
    { "ChannelArea: 50000 m2", "DepressionDepth: 0.01 m", "SlopeBinWidth: 10 deg" })
  {
    EXPECT_NE(os.str().find(word), std::string::npos) << word << "\n" << os.str();
  }
}

// CPU only: an explicit GPU request is an error with an empty output; whole extent asked.
TEST(TerroirMorphometry, RunsOnTheCPUOnlyOverTheWholeExtent)
{
  auto in = MakeTerrain(20, 20, 1.0, 1.0, [](int i, int j) { return i + j; });
  vtkNew<vtkTerroirMorphometry> g;
  vtkNew<terroir_test::ErrorObserver> errors;
  g->AddObserver(vtkCommand::ErrorEvent, errors);
  g->SetBackendToGPU();
  auto none = RunMorphometry(g, in);
  EXPECT_EQ(errors->ErrorCount, 1) << errors->Errors;
  EXPECT_EQ(none->GetPointData()->GetNumberOfArrays(), 0);

  vtkNew<vtkTerroirMorphometry> f;
  const std::array<int, 6> whole = { 0, 19, 0, 19, 0, 0 };
  EXPECT_EQ(terroir_test::RequestedInputExtent(f, in, { 2, 5, 3, 6, 0, 0 }), whole);
  vtkNew<vtkTerroirMorphometry> h;
  h->SetInputData(in);
  const std::vector<double> progress = terroir_test::UpdateWithProgress(h);
  ASSERT_GE(progress.size(), 3u);
  EXPECT_EQ(progress.back(), 1.0);
}

TEST(TerroirMorphometry, BadParametersAreOneErrorAndAnEmptyOutput)
{
  auto in = MakeTerrain(3, 3, 10.0, 10.0, [](int i, int) { return 5.0 * i; });
  vtkTerroirGeoreference::SetSourceFile(in, "dem.tif");
  struct Case
  {
    std::function<void(vtkTerroirMorphometry*)> set;
    std::string message;
  };
  const std::vector<Case> cases = {
    { [](vtkTerroirMorphometry* f) { f->SetChannelArea(0.0); },
      "dem.tif: ChannelArea 0 m2 must be > 0 and finite" },
    { [](vtkTerroirMorphometry* f) { f->SetChannelArea(std::nan("")); },
      "dem.tif: ChannelArea nan m2 must be > 0 and finite" },
    { [](vtkTerroirMorphometry* f) { f->SetDepressionDepth(-1.0); },
      "dem.tif: DepressionDepth -1 m must be >= 0 and finite" },
    { [](vtkTerroirMorphometry* f) { f->SetSlopeBinWidth(91.0); },
      "dem.tif: SlopeBinWidth 91 deg must be in (0, 90]" },
  };
  for (const Case& c : cases)
  {
    vtkNew<vtkTerroirMorphometry> f;
    vtkNew<terroir_test::ErrorObserver> errors;
    f->AddObserver(vtkCommand::ErrorEvent, errors);
    c.set(f);
    auto out = RunMorphometry(f, in);
    EXPECT_EQ(errors->ErrorCount, 1) << errors->Errors;
    EXPECT_NE(errors->Errors.find(c.message), std::string::npos) << errors->Errors;
    EXPECT_EQ(out->GetPointData()->GetNumberOfArrays(), 0);
  }
  // A terrain without a cell with data.
  vtkNew<vtkTerroirMorphometry> f;
  vtkNew<terroir_test::ErrorObserver> errors;
  f->AddObserver(vtkCommand::ErrorEvent, errors);
  auto out = RunMorphometry(f, MakeTerrain(3, 3, 10.0, 10.0, [](int, int) { return NAN; }));
  EXPECT_EQ(errors->ErrorCount, 1) << errors->Errors;
  EXPECT_NE(errors->Errors.find("the DEM has no cell with data"), std::string::npos)
    << errors->Errors;
  EXPECT_EQ(out->GetPointData()->GetNumberOfArrays(), 0);
}

// The bundled Sagehen Creek DEM (786 x 720, 10 m): each statistic recomputed here from the
// elevations and from the outputs of vtkTerroirSlope and vtkTerroirFlowAccumulation (same
// threshold, 0.1 km^2), with code of its own: hypsometric integral, slope mean and median,
// depression cells, channel cells and length, and N_w counted from the StrahlerOrder array and
// the flow directions.
TEST(TerroirMorphometry, BundledDEMAgreesWithOtherFiltersOutputs)
{
  auto in =
    terroir_test::ReadDEM(terroir_test::DataFile("sagehen_creek_ca/sagehen_dem_utm11n_10m.tif"));
  int dims[3];
  in->GetDimensions(dims);
  const int nx = dims[0], ny = dims[1];
  double spacing[3];
  in->GetSpacing(spacing);
  vtkNew<vtkTerroirMorphometry> m;
  auto out = RunMorphometry(m, in);
  vtkNew<vtkTerroirSlope> s;
  s->SetInputData(in);
  s->Update();
  vtkNew<vtkTerroirFlowAccumulation> fa;
  fa->SetInputData(in);
  fa->Update();
  vtkDataArray* z = in->GetPointData()->GetArray("Elevation");
  vtkDataArray* slope = s->GetOutput()->GetPointData()->GetArray("Slope");
  vtkDataArray* filled = fa->GetOutput()->GetPointData()->GetArray("FilledElevation");
  vtkDataArray* dir = fa->GetOutput()->GetPointData()->GetArray("FlowDirection");
  vtkDataArray* river = fa->GetOutput()->GetPointData()->GetArray("River");
  vtkDataArray* order = out->GetPointData()->GetArray("StrahlerOrder");
  ASSERT_TRUE(z && slope && filled && dir && river && order);

  const vtkIdType n = z->GetNumberOfTuples();
  double zmin = INFINITY, zmax = -INFINITY, zsum = 0;
  long long valid = 0, deep = 0, channels = 0;
  double channelLength = 0;
  std::vector<double> slopes;
  const int di[8] = { 1, 1, 0, -1, -1, -1, 0, 1 };
  const int dj[8] = { 0, 1, 1, 1, 0, -1, -1, -1 };
  for (vtkIdType k = 0; k < n; ++k)
  {
    const double h = z->GetComponent(k, 0);
    if (std::isnan(h))
    {
      continue;
    }
    ++valid;
    zmin = std::min(zmin, h);
    zmax = std::max(zmax, h);
    zsum += h;
    slopes.push_back(slope->GetComponent(k, 0));
    deep += filled->GetComponent(k, 0) - h > 1e-3 ? 1 : 0;
    if (river->GetComponent(k, 0) == 1)
    {
      ++channels;
      const int d = static_cast<int>(dir->GetComponent(k, 0));
      if (d >= 0)
      {
        channelLength += std::hypot(di[d] * spacing[0], dj[d] * spacing[1]);
      }
      EXPECT_GT(order->GetComponent(k, 0), 0) << k;
    }
    else
    {
      EXPECT_EQ(order->GetComponent(k, 0), 0) << k;
    }
  }
  EXPECT_EQ(Field(out, "ValidCells"), valid);
  EXPECT_NEAR(Field(out, "HypsometricIntegral"), (zsum / valid - zmin) / (zmax - zmin), 1e-9);
  double mean = 0;
  for (double v : slopes)
  {
    mean += v / slopes.size();
  }
  std::sort(slopes.begin(), slopes.end());
  const double pos = 0.5 * (slopes.size() - 1);
  const std::size_t lo = static_cast<std::size_t>(pos);
  const double median = slopes[lo] + (pos - lo) * (slopes[lo + 1] - slopes[lo]);
  EXPECT_NEAR(Field(out, "SlopeMean"), mean, 1e-6);
  EXPECT_NEAR(Field(out, "SlopeMedian"), median, 1e-6);
  EXPECT_EQ(Field(out, "DepressionCells"), deep);
  EXPECT_EQ(Field(out, "ChannelCells"), channels);
  EXPECT_NEAR(Field(out, "ChannelLength"), channelLength, 1e-6 * channelLength);
  EXPECT_NEAR(Field(out, "DrainageDensity"),
    (channelLength / 1e3) / (valid * spacing[0] * spacing[1] / 1e6),
    1e-9);

  // N_w: order-w cells into which no order-w cell drains.
  std::vector<char> sameOrderInflow(static_cast<std::size_t>(n), 0);
  int omega = 0;
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      const vtkIdType k = i + static_cast<vtkIdType>(nx) * j;
      const int w = static_cast<int>(order->GetComponent(k, 0));
      omega = std::max(omega, w);
      const int d = static_cast<int>(dir->GetComponent(k, 0));
      if (w > 0 && d >= 0)
      {
        const vtkIdType t = (i + di[d]) + static_cast<vtkIdType>(nx) * (j + dj[d]);
        if (static_cast<int>(order->GetComponent(t, 0)) == w)
        {
          sameOrderInflow[t] = 1;
        }
        EXPECT_GE(order->GetComponent(t, 0), w); // orders never fall downstream
      }
    }
  }
  std::vector<long long> streams(omega, 0);
  for (vtkIdType k = 0; k < n; ++k)
  {
    const int w = static_cast<int>(order->GetComponent(k, 0));
    if (w > 0 && !sameOrderInflow[k])
    {
      ++streams[w - 1];
    }
  }
  ASSERT_GE(omega, 4);
  for (int w = 1; w <= omega; ++w)
  {
    EXPECT_EQ(Field(out, "HortonStreamCount", w - 1), streams[w - 1]) << "order " << w;
  }
  // R_b from those counts, by a regression written here: orders 1 .. omega - 1.
  double mw = 0, mn = 0;
  for (int w = 1; w < omega; ++w)
  {
    mw += w / double(omega - 1);
    mn += std::log10(double(streams[w - 1])) / double(omega - 1);
  }
  double sxy = 0, sxx = 0;
  for (int w = 1; w < omega; ++w)
  {
    sxy += (w - mw) * (std::log10(double(streams[w - 1])) - mn);
    sxx += (w - mw) * (w - mw);
  }
  EXPECT_NEAR(Field(out, "BifurcationRatio"), std::pow(10.0, -sxy / sxx), 1e-9);
  EXPECT_EQ(Field(out, "HortonOrdersFitted", 1), omega - 1);

  // FlowLength is the longest path from the divide: along every D8 step it grows by at least
  // the step, and a cell with inflows equals its longest inflow plus that inflow's step.
  vtkDataArray* length = out->GetPointData()->GetArray("FlowLength");
  std::vector<double> best(static_cast<std::size_t>(n), -1.0);
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      const vtkIdType k = i + static_cast<vtkIdType>(nx) * j;
      const int d = static_cast<int>(dir->GetComponent(k, 0));
      if (d >= 0)
      {
        const vtkIdType t = (i + di[d]) + static_cast<vtkIdType>(nx) * (j + dj[d]);
        const double via =
          length->GetComponent(k, 0) + std::hypot(di[d] * spacing[0], dj[d] * spacing[1]);
        best[t] = std::max(best[t], via);
      }
    }
  }
  long long wrong = 0;
  for (vtkIdType k = 0; k < n; ++k)
  {
    const double l = length->GetComponent(k, 0);
    wrong += std::abs(l - std::max(0.0, best[k])) > 1e-3 * std::max(1.0, l) ? 1 : 0;
  }
  EXPECT_EQ(wrong, 0);
}

} // namespace

// vtkTerroirSlope on the bundled Sagehen Creek DEM against the gdaldem binary (GDAL's own
// code), and the slope of the geographic (degree) original against the UTM grid.
#include "TerroirFilterTestUtilities.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkPointData.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirSlope.h"

#include "SlopeHorn1981.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <vector>

namespace
{
const char* kUTM = "sagehen_creek_ca/sagehen_dem_utm11n_10m.tif";
const char* kGeographic = "sagehen_creek_ca/ned10m_nad83.img";

vtkSmartPointer<vtkImageData> Slope(vtkImageData* in)
{
  auto f = vtkSmartPointer<vtkTerroirSlope>::New();
  f->SetBackendToCPU();
  f->SetInputData(in);
  f->Update();
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->ShallowCopy(f->GetOutput());
  return out;
}

double Percentile(std::vector<double> v, double p)
{
  if (v.empty())
  {
    return NAN;
  }
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(p * (v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}

class TerroirSlopeGdaldem : public ::testing::Test
{
protected:
  void SetUp() override
  {
    TERROIR_REQUIRE_PEER_OR_SKIP(terroir_test::HaveGdaldem(), "/usr/bin/gdaldem not installed");
  }
};

TEST_F(TerroirSlopeGdaldem, SlopeOfBundledDEMMatchesGdaldemAtEveryCell)
{
  const std::string dem = terroir_test::DataFile(kUTM);
  auto in = terroir_test::ReadDEM(dem);
  ASSERT_NE(in, nullptr) << "cannot read " << dem;
  const std::string ref = terroir_test::TempFile("sagehen_slope_gdaldem.asc");
  ASSERT_EQ(terroir_test::RunCommand(
              "/usr/bin/gdaldem slope -q -compute_edges -of AAIGrid '" + dem + "' '" + ref + "'"),
    0);
  terroir_test::AsciiGrid expected;
  ASSERT_TRUE(terroir_test::ReadAsciiGrid(ref, expected));
  int dims[3];
  in->GetDimensions(dims);
  ASSERT_EQ(expected.nx, dims[0]);
  ASSERT_EQ(expected.ny, dims[1]);
  auto out = Slope(in);
  vtkDataArray* slope = out->GetPointData()->GetArray("Slope");
  ASSERT_NE(slope, nullptr);
  double maxDiff = 0.0;
  long long compared = 0;
  for (int j = 0; j < dims[1]; ++j)
  {
    for (int i = 0; i < dims[0]; ++i)
    {
      const double e = expected.At(i, j);
      const double s = slope->GetComponent(static_cast<vtkIdType>(j) * dims[0] + i, 0);
      ASSERT_EQ(std::isnan(e), std::isnan(s)) << "cell " << i << "," << j;
      if (!std::isnan(e))
      {
        maxDiff = std::max(maxDiff, std::fabs(s - e));
        ++compared;
      }
    }
  }
  std::cout << "slope vs gdaldem: " << compared << " cells, max |diff| = " << maxDiff << " deg"
            << std::endl;
  RecordProperty("MaxSlopeDifferenceDegrees", std::to_string(maxDiff));
  EXPECT_EQ(compared, static_cast<long long>(dims[0]) * dims[1]);
  EXPECT_LT(maxDiff, 0.01);
}

TEST_F(TerroirSlopeGdaldem, AspectMatchesGdaldemWithConvergenceRemoved)
{
  const std::string dem = terroir_test::DataFile(kUTM);
  auto in = terroir_test::ReadDEM(dem);
  ASSERT_NE(in, nullptr) << "cannot read " << dem;
  const double gamma = vtkTerroirGeoreference::GetMeridianConvergence(in);
  // Sagehen Creek lies about 2.4 degrees of longitude west of the UTM 11 central meridian:
  // grid north there is west of true north (gamma < 0).
  ASSERT_TRUE(vtkTerroirGeoreference::HasMeridianConvergence(in));
  EXPECT_LT(gamma, -1.0);
  const std::string ref = terroir_test::TempFile("sagehen_aspect_gdaldem.asc");
  ASSERT_EQ(terroir_test::RunCommand(
              "/usr/bin/gdaldem aspect -q -compute_edges -of AAIGrid '" + dem + "' '" + ref + "'"),
    0);
  terroir_test::AsciiGrid expected;
  ASSERT_TRUE(terroir_test::ReadAsciiGrid(ref, expected));
  auto out = Slope(in);
  vtkDataArray* aspect = out->GetPointData()->GetArray("Aspect");
  vtkDataArray* slope = out->GetPointData()->GetArray("Slope");
  int dims[3];
  in->GetDimensions(dims);
  double maxDiff = 0.0, maxSteep = 0.0;
  std::vector<double> allDiffs;
  long long compared = 0, flat = 0, nearFlat = 0;
  for (int j = 0; j < dims[1]; ++j)
  {
    for (int i = 0; i < dims[0]; ++i)
    {
      const vtkIdType k = static_cast<vtkIdType>(j) * dims[0] + i;
      const double e = expected.At(i, j);
      const double a = aspect->GetComponent(k, 0);
      // gdaldem sums the window in float before differencing (z ~ 2000 m: a rounding of
      // ~1e-5 in the gradient), we difference first. Below 0.05 deg of slope the direction
      // rests on that rounding (either side may even find an exact zero): such cells are
      // counted, not compared; above it the difference shrinks as 1/slope.
      if (slope->GetComponent(k, 0) < 0.05)
      {
        ++nearFlat;
        continue;
      }
      ASSERT_FALSE(std::isnan(e)) << "cell " << i << "," << j;
      ASSERT_FALSE(std::isnan(a)) << "cell " << i << "," << j;
      EXPECT_GE(a, 0.0);
      EXPECT_LT(a, 360.0);
      const double d = std::fabs(std::remainder(a - gamma - e, 360.0));
      maxDiff = std::max(maxDiff, d);
      ++compared;
      if (slope->GetComponent(k, 0) >= 10.0)
      {
        maxSteep = std::max(maxSteep, d);
      }
      allDiffs.push_back(d);
    }
  }
  for (vtkIdType k = 0; k < aspect->GetNumberOfTuples(); ++k)
  {
    flat += std::isnan(aspect->GetComponent(k, 0)) ? 1 : 0;
  }
  std::cout << "aspect vs gdaldem (gamma " << gamma << " removed): " << compared << " cells ("
            << nearFlat << " below 0.05 deg not compared, " << flat
            << " flat), max |diff| = " << maxDiff << " deg" << std::endl;
  const double p99 = Percentile(allDiffs, 0.99);
  const double p90 = Percentile(allDiffs, 0.9);
  std::cout << "aspect: slope >= 10 deg max |diff| " << maxSteep << ", all compared p90 " << p90
            << ", p99 " << p99 << std::endl;
  EXPECT_GT(compared, 0.95 * dims[0] * dims[1]);
  EXPECT_LT(maxSteep, 0.01);
  EXPECT_LT(p90, 0.01);
  EXPECT_LT(p99, 0.03);
  EXPECT_LT(maxDiff, 1.0);

  // Our float aspect against the same core in double on the same elevations: the float
  // kernel differences before summing, so it stays within 0.001 deg wherever slope >= 0.05.
  vtkDataArray* elev = in->GetPointData()->GetArray("Elevation");
  std::vector<double> z(elev->GetNumberOfTuples());
  for (vtkIdType k = 0; k < elev->GetNumberOfTuples(); ++k)
  {
    z[k] = elev->GetComponent(k, 0);
  }
  terroir::GridView<double> v;
  v.data = z.data();
  v.nx = dims[0];
  v.ny = dims[1];
  v.dx = in->GetSpacing()[0];
  v.dy = in->GetSpacing()[1];
  terroir::terrain::SlopeParams params;
  params.convergenceDeg = gamma;
  std::vector<double> refAspect(z.size());
  terroir::terrain::SlopeHorn1981(
    v, params, static_cast<double*>(nullptr), refAspect.data(), static_cast<double*>(nullptr));
  double maxVsDouble = 0.0;
  for (vtkIdType k = 0; k < elev->GetNumberOfTuples(); ++k)
  {
    if (slope->GetComponent(k, 0) >= 0.05)
    {
      maxVsDouble = std::max(
        maxVsDouble, std::fabs(std::remainder(aspect->GetComponent(k, 0) - refAspect[k], 360.0)));
    }
  }
  std::cout << "aspect: float kernel vs double core max |diff| " << maxVsDouble << std::endl;
  EXPECT_LT(maxVsDouble, 0.001);
}

TEST_F(TerroirSlopeGdaldem, GeographicAndUTMSlopesAgree)
{
  // The UTM grid was resampled (bilinear) from the geographic NED grid, so both slope maps
  // describe the same terrain. The geographic slope (per-row metric spacing) is sampled at
  // each UTM cell centre, mapped into the .img's pixel grid with gdaltransform (OGR).
  const std::string utmPath = terroir_test::DataFile(kUTM);
  const std::string geoPath = terroir_test::DataFile(kGeographic);
  auto utm = terroir_test::ReadDEM(utmPath);
  auto geo = terroir_test::ReadDEM(geoPath);
  ASSERT_NE(utm, nullptr);
  ASSERT_NE(geo, nullptr);
  ASSERT_NE(vtkTerroirGeoreference::GetRowSpacing(geo), nullptr)
    << "the geographic grid must carry TerroirRowSpacing";
  int ud[3], gd[3];
  utm->GetDimensions(ud);
  geo->GetDimensions(gd);

  const std::string pts = terroir_test::TempFile("sagehen_utm_pixels.txt");
  const std::string mapped = terroir_test::TempFile("sagehen_utm_in_img_pixels.txt");
  {
    std::ofstream o(pts);
    for (int r = 0; r < ud[1]; ++r)
    {
      for (int c = 0; c < ud[0]; ++c)
      {
        o << c + 0.5 << " " << r + 0.5 << "\n";
      }
    }
  }
  ASSERT_EQ(terroir_test::RunCommand("gdaltransform '" + utmPath + "' '" + geoPath + "' < '" + pts +
              "' > '" + mapped + "'"),
    0);

  auto utmOut = Slope(utm);
  auto geoOut = Slope(geo);
  vtkDataArray* su = utmOut->GetPointData()->GetArray("Slope");
  vtkDataArray* sg = geoOut->GetPointData()->GetArray("Slope");

  // The same geographic grid treated as if every row had the centre row's spacing (what a
  // filter that ignored the per-row spacing would do) must be visibly worse: a control.
  auto flat = vtkSmartPointer<vtkImageData>::New();
  flat->ShallowCopy(geo);
  flat->GetFieldData()->RemoveArray(vtkTerroirGeoreference::RowSpacingName());
  flat->SetSpacing(vtkTerroirGeoreference::GetRowSpacing(geo)->GetComponent(0, 0) /
      std::cos(39.45 / 57.29577951308232),
    geo->GetSpacing()[1],
    1.0); // no cos(latitude): a degree taken as at the equator
  auto flatOut = Slope(flat);
  vtkDataArray* sf = flatOut->GetPointData()->GetArray("Slope");

  auto sample = [&](vtkDataArray* a, double px, double py)
  {
    // GDAL pixel coordinates (x right, y down from the north edge) to a bilinear sample of
    // cell centres; Terroir row j = ny - 1 - gdal row.
    const double x = px - 0.5, y = py - 0.5;
    const int i0 = static_cast<int>(std::floor(x)), l0 = static_cast<int>(std::floor(y));
    if (i0 < 0 || l0 < 0 || i0 + 1 >= gd[0] || l0 + 1 >= gd[1])
    {
      return std::numeric_limits<double>::quiet_NaN();
    }
    const double fx = x - i0, fy = y - l0;
    auto v = [&](int i, int l)
    { return a->GetComponent(static_cast<vtkIdType>(gd[1] - 1 - l) * gd[0] + i, 0); };
    return (1 - fy) * ((1 - fx) * v(i0, l0) + fx * v(i0 + 1, l0)) +
      fy * ((1 - fx) * v(i0, l0 + 1) + fx * v(i0 + 1, l0 + 1));
  };

  std::ifstream in(mapped);
  std::vector<double> diffs, absDiffs, absFlat;
  double sumDiff = 0.0;
  for (int r = 0; r < ud[1]; ++r)
  {
    for (int c = 0; c < ud[0]; ++c)
    {
      double px, py, pz;
      ASSERT_TRUE(static_cast<bool>(in >> px >> py >> pz));
      // Skip the UTM border (gdaldem edge rules differ from interior cells).
      if (r == 0 || c == 0 || r == ud[1] - 1 || c == ud[0] - 1)
      {
        continue;
      }
      const double g = sample(sg, px, py);
      const double u = su->GetComponent(static_cast<vtkIdType>(ud[1] - 1 - r) * ud[0] + c, 0);
      if (std::isnan(g) || std::isnan(u))
      {
        continue;
      }
      diffs.push_back(u - g);
      absDiffs.push_back(std::fabs(u - g));
      absFlat.push_back(std::fabs(u - sample(sf, px, py)));
      sumDiff += u - g;
    }
  }
  ASSERT_GT(diffs.size(), 400000u);
  const double mean = sumDiff / diffs.size();
  const double p50 = Percentile(absDiffs, 0.5), p95 = Percentile(absDiffs, 0.95);
  const double mx = *std::max_element(absDiffs.begin(), absDiffs.end());
  const double f50 = Percentile(absFlat, 0.5), f95 = Percentile(absFlat, 0.95);
  std::cout << "UTM vs geographic slope over " << diffs.size() << " cells: mean diff " << mean
            << ", |diff| p50 " << p50 << ", p95 " << p95 << ", max " << mx
            << " deg; without per-row spacing: p50 " << f50 << ", p95 " << f95 << std::endl;
  EXPECT_LT(std::fabs(mean), 0.5);
  EXPECT_LT(p50, 0.5);
  EXPECT_GT(f50, 2.0 * p50); // the control really is worse
}

} // namespace

// Pipeline tests of vtkTerroirSoilHumidity: arrays, units, month names, the capped equation and
// the weighted average through the filter, climate files, the chain reader -> slope ->
// infiltration -> soil humidity on the bundled DEM, no data, errors.
#include "TerroirFilterTestUtilities.h"

#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkTerroirClimateReader.h"
#include "vtkTerroirDEMReader.h"
#include "vtkTerroirInfiltration.h"
#include "vtkTerroirSlope.h"
#include "vtkTerroirSoilHumidity.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

namespace
{
using terroir_test::MakeTerrain;

/// A 3 x 1 terrain whose InfiltrationRate is 0, 4 and 100 mm/h.
vtkSmartPointer<vtkImageData> ThreeSoils()
{
  auto in = MakeTerrain(3, 1, 10.0, 10.0, [](int, int) { return 500.0; });
  auto rate = vtkSmartPointer<vtkFloatArray>::New();
  rate->SetName("InfiltrationRate");
  rate->SetNumberOfValues(3);
  rate->SetValue(0, 0.0f);
  rate->SetValue(1, 4.0f);
  rate->SetValue(2, 100.0f);
  in->GetPointData()->AddArray(rate);
  return in;
}

vtkSmartPointer<vtkImageData> RunHumidity(vtkImageData* in, vtkTerroirSoilHumidity* f)
{
  f->SetBackendToCPU();
  f->SetInputData(in);
  f->Update();
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->ShallowCopy(f->GetOutput());
  return out;
}

TEST(TerroirSoilHumidity, ArraysFollowTheCappedEquationAndTheWeightedAverage)
{
  auto f = vtkSmartPointer<vtkTerroirSoilHumidity>::New();
  const double q[12] = { 80, 40, 60, 0, 20, 10, 5, 0, 30, 90, 120, 100 };
  const double i[12] = { 8, 4, 2, 1, 10, 20, 5, 3, 6, 9, 12, 2 };
  f->SetPrecipitation(q);
  f->SetPrecipitationIntensity(i);
  auto out = RunHumidity(ThreeSoils(), f);
  for (const char* name : { "SoilHumidity", "WeightedSoilHumidity", "StandingWater" })
  {
    vtkDataArray* a = out->GetPointData()->GetArray(name);
    ASSERT_NE(a, nullptr) << name;
    EXPECT_EQ(a->GetDataType(), VTK_FLOAT);
    EXPECT_EQ(a->GetNumberOfComponents(), 12);
    EXPECT_STREQ(a->GetComponentName(0), "Jan");
    EXPECT_STREQ(a->GetComponentName(11), "Dec");
    EXPECT_STREQ(a->GetInformation()->Get(vtkDataArray::UNITS_LABEL()), "mm");
  }
  vtkDataArray* sh = out->GetPointData()->GetArray("SoilHumidity");
  vtkDataArray* swh = out->GetPointData()->GetArray("WeightedSoilHumidity");
  vtkDataArray* sw = out->GetPointData()->GetArray("StandingWater");
  // The 4 mm/h soil, by hand: min(4 / R_i, 1) R_q.
  const double expected[12] = { 40, 40, 60, 0, 8, 2, 4, 0, 20, 40, 40, 100 };
  for (int m = 0; m < 12; ++m)
  {
    EXPECT_NEAR(sh->GetComponent(1, m), expected[m], 1e-4) << "month " << m + 1;
    EXPECT_NEAR(sw->GetComponent(1, m), q[m] - expected[m], 1e-4) << "month " << m + 1;
    EXPECT_EQ(sh->GetComponent(0, m), 0.0);
    EXPECT_EQ(sw->GetComponent(0, m), q[m]);
    EXPECT_EQ(sh->GetComponent(2, m), q[m]);
  }
  // January's weighted value reaches back to December and November: 40/2 + 100/3 + 40/6.
  EXPECT_NEAR(swh->GetComponent(1, 0), 20.0 + 100.0 / 3.0 + 40.0 / 6.0, 1e-4);
  // February: 40/2 + 40/3 + 100/6.
  EXPECT_NEAR(swh->GetComponent(1, 1), 20.0 + 40.0 / 3.0 + 100.0 / 6.0, 1e-4);
  // The climate used is recorded.
  vtkDataArray* p = out->GetFieldData()->GetArray("Precipitation");
  ASSERT_NE(p, nullptr);
  EXPECT_EQ(p->GetNumberOfTuples(), 12);
  EXPECT_EQ(p->GetComponent(10, 0), 120.0);
  ASSERT_NE(out->GetFieldData()->GetArray("PrecipitationIntensity"), nullptr);
}

TEST(TerroirSoilHumidity, DefaultsOptionalOutputsModifiedAndPrintSelf)
{
  auto f = vtkSmartPointer<vtkTerroirSoilHumidity>::New();
  double sum = 0.0;
  for (int m = 0; m < 12; ++m)
  {
    sum += f->GetPrecipitation()[m];
    EXPECT_GT(f->GetPrecipitationIntensity()[m], 0.0);
  }
  EXPECT_EQ(sum, 715.0);
  EXPECT_STREQ(
    f->GetInputArrayInformation(1)->Get(vtkDataObject::FIELD_NAME()), "InfiltrationRate");
  vtkMTimeType t = f->GetMTime();
  f->ComputeStandingWaterOff();
  EXPECT_GT(f->GetMTime(), t);
  f->SetComputeWeightedSoilHumidity(false);
  auto out = RunHumidity(ThreeSoils(), f);
  EXPECT_NE(out->GetPointData()->GetArray("SoilHumidity"), nullptr);
  EXPECT_EQ(out->GetPointData()->GetArray("WeightedSoilHumidity"), nullptr);
  EXPECT_EQ(out->GetPointData()->GetArray("StandingWater"), nullptr);
  std::ostringstream os;
  f->Print(os);
  EXPECT_NE(os.str().find("Precipitation: 60 50 55"), std::string::npos) << os.str();
  EXPECT_NE(os.str().find("ComputeStandingWater: Off"), std::string::npos);
}

TEST(TerroirSoilHumidity, OneMonthSettersChangeOnlyThatMonth)
{
  // ParaView's indexed Precipitation / PrecipitationIntensity properties: month 0 = January.
  auto f = vtkSmartPointer<vtkTerroirSoilHumidity>::New();
  double q[12], r[12];
  f->GetPrecipitation(q);
  f->GetPrecipitationIntensity(r);
  vtkMTimeType t = f->GetMTime();
  f->SetMonthlyPrecipitation(11, 120.0);
  EXPECT_GT(f->GetMTime(), t);
  t = f->GetMTime();
  f->SetMonthlyPrecipitationIntensity(0, 7.0);
  EXPECT_GT(f->GetMTime(), t);
  for (int m = 0; m < 12; ++m)
  {
    EXPECT_EQ(f->GetPrecipitation()[m], m == 11 ? 120.0 : q[m]) << m;
    EXPECT_EQ(f->GetPrecipitationIntensity()[m], m == 0 ? 7.0 : r[m]) << m;
  }
}

TEST(TerroirSoilHumidity, ClimateFileReplacesTheParameters)
{
  const std::string path = terroir_test::TempFile("soil_climate.csv");
  {
    std::ofstream out(path);
    out << "month,precipitation_mm,intensity_mm_per_h\n";
    for (int m = 1; m <= 12; ++m)
    {
      out << m << "," << 10 * m << ",8\n";
    }
  }
  vtkNew<vtkTerroirClimateReader> climate;
  climate->SetFileName(path.c_str());
  ASSERT_TRUE(climate->Read()) << climate->GetErrorMessage();
  ASSERT_TRUE(climate->HasPrecipitation() && climate->HasPrecipitationIntensity());
  EXPECT_FALSE(climate->HasTemperature());
  auto f = vtkSmartPointer<vtkTerroirSoilHumidity>::New();
  f->SetPrecipitation(climate->GetPrecipitation());
  f->SetPrecipitationIntensity(climate->GetPrecipitationIntensity());
  auto out = RunHumidity(ThreeSoils(), f);
  vtkDataArray* sh = out->GetPointData()->GetArray("SoilHumidity");
  ASSERT_NE(sh, nullptr);
  for (int m = 0; m < 12; ++m)
  {
    EXPECT_NEAR(sh->GetComponent(1, m), 10.0 * (m + 1) * 0.5, 1e-4); // 4 / 8 of the rain
  }
}

TEST(TerroirSoilHumidity, ChainOnTheBundledDEM)
{
  auto reader = vtkSmartPointer<vtkTerroirDEMReader>::New();
  reader->SetFileName(
    terroir_test::DataFile("sagehen_creek_ca/sagehen_dem_utm11n_10m.tif").c_str());
  auto slope = vtkSmartPointer<vtkTerroirSlope>::New();
  slope->SetInputConnection(reader->GetOutputPort());
  slope->SetBackendToCPU();
  auto infiltration = vtkSmartPointer<vtkTerroirInfiltration>::New();
  infiltration->SetInputConnection(slope->GetOutputPort());
  auto humidity = vtkSmartPointer<vtkTerroirSoilHumidity>::New();
  humidity->SetInputConnection(infiltration->GetOutputPort());
  humidity->SetBackendToCPU();
  humidity->Update();
  vtkImageData* out = humidity->GetOutput();
  vtkDataArray* s = out->GetPointData()->GetArray("Slope");
  vtkDataArray* r = out->GetPointData()->GetArray("InfiltrationRate");
  vtkDataArray* sh = out->GetPointData()->GetArray("SoilHumidity");
  vtkDataArray* sw = out->GetPointData()->GetArray("StandingWater");
  ASSERT_TRUE(s && r && sh && sw);
  const double* q = humidity->GetPrecipitation();
  const double* intensity = humidity->GetPrecipitationIntensity();
  vtkIdType cliffs = 0;
  for (vtkIdType k = 0; k < r->GetNumberOfTuples(); ++k)
  {
    const bool cliff = s->GetComponent(k, 0) > 30.0;
    cliffs += cliff ? 1 : 0;
    ASSERT_EQ(r->GetComponent(k, 0), cliff ? 0.0 : 15.0) << "cell " << k;
    for (int m : { 0, 6 })
    {
      const double expected = std::min(r->GetComponent(k, 0) / intensity[m], 1.0) * q[m];
      ASSERT_NEAR(sh->GetComponent(k, m), expected, 1e-4) << "cell " << k << " month " << m;
      ASSERT_NEAR(sh->GetComponent(k, m) + sw->GetComponent(k, m), q[m], 1e-4);
    }
  }
  // Sagehen is steep: some cells are cliffs, most are not.
  EXPECT_GT(cliffs, 0);
  EXPECT_LT(cliffs, r->GetNumberOfTuples() / 2);
}

TEST(TerroirSoilHumidity, NoDataAndNaNRatesGiveNaN)
{
  auto in = MakeTerrain(3, 1, 10.0, 10.0, [](int i, int) { return i == 0 ? std::nan("") : 1.0; });
  auto rate = vtkSmartPointer<vtkFloatArray>::New();
  rate->SetName("InfiltrationRate");
  rate->SetNumberOfValues(3);
  rate->SetValue(0, 5.0f);
  rate->SetValue(1, std::nanf(""));
  rate->SetValue(2, 5.0f);
  in->GetPointData()->AddArray(rate);
  auto f = vtkSmartPointer<vtkTerroirSoilHumidity>::New();
  auto out = RunHumidity(in, f);
  for (const char* name : { "SoilHumidity", "WeightedSoilHumidity", "StandingWater" })
  {
    vtkDataArray* a = out->GetPointData()->GetArray(name);
    EXPECT_TRUE(std::isnan(a->GetComponent(0, 3))) << name;
    EXPECT_TRUE(std::isnan(a->GetComponent(1, 3))) << name;
    EXPECT_FALSE(std::isnan(a->GetComponent(2, 3))) << name;
  }
}

TEST(TerroirSoilHumidity, BadClimateAndInputsGiveOneErrorAndNoOutput)
{
  struct Case
  {
    std::function<void(vtkTerroirSoilHumidity*, vtkImageData*)> Setup;
    std::string Expected;
  };
  const std::vector<Case> cases = {
    { [](vtkTerroirSoilHumidity* f, vtkImageData*)
      {
        double q[12] = { 10, 10, -4, 10, 10, 10, 10, 10, 10, 10, 10, 10 };
        f->SetPrecipitation(q);
      },
      "precipitation of Mar -4" },
    { [](vtkTerroirSoilHumidity* f, vtkImageData*)
      {
        double i[12] = { 2, 2, 2, 2, 0, 2, 2, 2, 2, 2, 2, 2 };
        f->SetPrecipitationIntensity(i);
      },
      "rain needs a positive intensity" },
    { [](vtkTerroirSoilHumidity* f, vtkImageData*)
      {
        double q[12] = { 10, 10, 10, 10, 10, 10, 10, 10, 10, 10, 10, std::nan("") };
        f->SetPrecipitation(q);
      },
      "precipitation of Dec" },
    { [](vtkTerroirSoilHumidity*, vtkImageData* in)
      { in->GetPointData()->RemoveArray("InfiltrationRate"); },
      "no InfiltrationRate array" },
    { [](vtkTerroirSoilHumidity*, vtkImageData* in)
      {
        vtkDataArray* r = in->GetPointData()->GetArray("InfiltrationRate");
        r->SetComponent(1, 0, -2.0);
      },
      "negative values" },
  };
  for (const Case& c : cases)
  {
    auto in = ThreeSoils();
    auto f = vtkSmartPointer<vtkTerroirSoilHumidity>::New();
    auto obs = vtkSmartPointer<terroir_test::ErrorObserver>::New();
    f->AddObserver(vtkCommand::ErrorEvent, obs);
    c.Setup(f, in);
    RunHumidity(in, f);
    EXPECT_EQ(obs->ErrorCount, 1) << obs->Errors;
    EXPECT_NE(obs->Errors.find(c.Expected), std::string::npos) << obs->Errors;
    EXPECT_EQ(f->GetOutput()->GetNumberOfPoints(), 0);
  }
}

} // namespace

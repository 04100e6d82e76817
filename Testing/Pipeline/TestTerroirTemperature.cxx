// Pipeline tests of vtkTerroirTemperature: arrays, units, component names, defaults,
// Modified, PrintSelf, hemispheres, 12-value mode, no data, input types, bad input, halo 0.
#include "TerroirFilterTestUtilities.h"

#include "vtkDataArray.h"
#include "vtkExecutive.h"
#include "vtkInformation.h"
#include "vtkPointData.h"
#include "vtkTerroirComputeContext.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirTemperature.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <sstream>
#include <vector>

namespace
{
using terroir_test::MakeTerrain;

vtkSmartPointer<vtkImageData> RunTemperature(vtkImageData* in, vtkTerroirTemperature* f)
{
  f->SetBackendToCPU();
  f->SetInputData(in);
  f->Update();
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->ShallowCopy(f->GetOutput());
  return out;
}

// Elevations 0, 1000, 2500 m along the first row.
vtkSmartPointer<vtkImageData> ThreeHeights()
{
  return MakeTerrain(
    3, 2, 30.0, 30.0, [](int i, int) { return i == 0 ? 0.0
                                         : i == 1    ? 1000.0
                                                     : 2500.0; });
}

TEST(TerroirTemperature, MonthlyArrayWithUnitsAndMonthNames)
{
  auto f = vtkSmartPointer<vtkTerroirTemperature>::New();
  auto out = RunTemperature(ThreeHeights(), f);
  vtkDataArray* t = out->GetPointData()->GetArray("Temperature");
  ASSERT_NE(t, nullptr);
  EXPECT_EQ(t->GetDataType(), VTK_FLOAT);
  EXPECT_EQ(t->GetNumberOfComponents(), 12);
  EXPECT_STREQ(t->GetComponentName(0), "Jan");
  EXPECT_STREQ(t->GetComponentName(6), "Jul");
  EXPECT_STREQ(t->GetComponentName(11), "Dec");
  EXPECT_STREQ(t->GetInformation()->Get(vtkDataArray::UNITS_LABEL()), "degC");
  EXPECT_NE(out->GetPointData()->GetArray("Elevation"), nullptr);
  // Defaults: coldest 2 degC in January, warmest 20 degC in July, 6.4 degC/km.
  EXPECT_NEAR(t->GetComponent(0, 0), 2.0, 1e-5);
  EXPECT_NEAR(t->GetComponent(0, 6), 20.0, 1e-5);
  EXPECT_NEAR(t->GetComponent(0, 3), 11.0, 1e-5);                  // April: halfway
  EXPECT_NEAR(t->GetComponent(1, 0), -4.4, 1e-5);                  // 2 - 6.4
  EXPECT_NEAR(t->GetComponent(2, 6), 4.0, 1e-5);                   // 20 - 16
  EXPECT_NEAR(t->GetComponent(2, 9), -5.0, 1e-5);                  // October 11 - 16
  EXPECT_EQ(f->GetLastHemisphere(), vtkTerroirTemperature::North); // no georeference
}

TEST(TerroirTemperature, DefaultsModifiedAndPrintSelf)
{
  auto f = vtkSmartPointer<vtkTerroirTemperature>::New();
  EXPECT_EQ(f->GetSeaLevelTemperatureColdest(), 2.0);
  EXPECT_EQ(f->GetSeaLevelTemperatureWarmest(), 20.0);
  EXPECT_EQ(f->GetColdestMonth(), 0);
  EXPECT_EQ(f->GetWarmestMonth(), 0);
  EXPECT_EQ(f->GetHemisphere(), vtkTerroirTemperature::AutoHemisphere);
  EXPECT_EQ(f->GetLapseRate(), 6.4);
  EXPECT_FALSE(f->GetUseMonthlyTemperatures());
  EXPECT_EQ(f->GetBackend(), vtkTerroirComputeContext::Auto);
  EXPECT_STREQ(f->GetInputArrayInformation(0)->Get(vtkDataObject::FIELD_NAME()), "Elevation");

  vtkMTimeType t = f->GetMTime();
  f->SetLapseRate(5.0);
  EXPECT_GT(f->GetMTime(), t);
  t = f->GetMTime();
  f->SetLapseRate(5.0);
  EXPECT_EQ(f->GetMTime(), t);
  f->SetHemisphereToSouth();
  EXPECT_GT(f->GetMTime(), t);
  t = f->GetMTime();
  const double months[12] = { 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12 };
  f->SetMonthlySeaLevelTemperatures(months);
  EXPECT_GT(f->GetMTime(), t);
  t = f->GetMTime();
  f->SetColdestMonth(3);
  EXPECT_GT(f->GetMTime(), t);
  f->SetWarmestMonth(14); // clamped
  EXPECT_EQ(f->GetWarmestMonth(), 12);

  std::ostringstream os;
  f->Print(os);
  for (const char* word : { "LapseRate: 5",
         "Hemisphere: South",
         "ColdestMonth: 3",
         "SeaLevelTemperatureColdest",
         "SeaLevelTemperatureWarmest",
         "UseMonthlyTemperatures",
         "MonthlySeaLevelTemperatures: 1 2 3",
         "Backend" })
  {
    EXPECT_NE(os.str().find(word), std::string::npos) << word;
  }
}

TEST(TerroirTemperature, SouthernHemisphereFromCentreLatitude)
{
  auto in = ThreeHeights();
  vtkTerroirGeoreference::SetCenterLatLon(in, -41.3, 174.8); // Wellington
  auto f = vtkSmartPointer<vtkTerroirTemperature>::New();
  auto out = RunTemperature(in, f);
  vtkDataArray* t = out->GetPointData()->GetArray("Temperature");
  EXPECT_EQ(f->GetLastHemisphere(), vtkTerroirTemperature::South);
  EXPECT_NEAR(t->GetComponent(0, 0), 20.0, 1e-5);       // January warmest
  EXPECT_NEAR(t->GetComponent(0, 6), 2.0, 1e-5);        // July coldest
  EXPECT_NEAR(t->GetComponent(1, 9), 11.0 - 6.4, 1e-5); // October: 2 + 3 * 3 at sea level
  // Forcing the north on the same terrain.
  auto g = vtkSmartPointer<vtkTerroirTemperature>::New();
  g->SetHemisphereToNorth();
  auto out2 = RunTemperature(in, g);
  EXPECT_NEAR(out2->GetPointData()->GetArray("Temperature")->GetComponent(0, 0), 2.0, 1e-5);
  // Explicit months win over the hemisphere.
  auto h = vtkSmartPointer<vtkTerroirTemperature>::New();
  h->SetColdestMonth(2);
  h->SetWarmestMonth(8);
  auto out3 = RunTemperature(in, h);
  EXPECT_NEAR(out3->GetPointData()->GetArray("Temperature")->GetComponent(0, 1), 2.0, 1e-5);
  EXPECT_NEAR(out3->GetPointData()->GetArray("Temperature")->GetComponent(0, 7), 20.0, 1e-5);
}

TEST(TerroirTemperature, TwelveGivenSeaLevelTemperatures)
{
  auto f = vtkSmartPointer<vtkTerroirTemperature>::New();
  const double sea[12] = { -3, -1, 2, 6, 10, 14, 17, 16, 12, 7, 2, -2 };
  f->SetMonthlySeaLevelTemperatures(sea);
  f->UseMonthlyTemperaturesOn();
  f->SetLapseRate(6.0);
  auto out = RunTemperature(ThreeHeights(), f);
  vtkDataArray* t = out->GetPointData()->GetArray("Temperature");
  for (int m = 0; m < 12; ++m)
  {
    EXPECT_NEAR(t->GetComponent(0, m), sea[m], 1e-5);
    EXPECT_NEAR(t->GetComponent(2, m), sea[m] - 15.0, 1e-5); // 2500 m at 6 degC/km
  }
}

TEST(TerroirTemperature, OneMonthSetterChangesOnlyThatMonth)
{
  // SetMonthlySeaLevelTemperature (ParaView's indexed property): month 0 is January; a new
  // value calls Modified(), the same value does not, a month outside 0..11 changes nothing.
  auto f = vtkSmartPointer<vtkTerroirTemperature>::New();
  double before[12];
  f->GetMonthlySeaLevelTemperatures(before);
  vtkMTimeType t = f->GetMTime();
  f->SetMonthlySeaLevelTemperature(2, 9.5);
  EXPECT_GT(f->GetMTime(), t);
  for (int m = 0; m < 12; ++m)
  {
    EXPECT_EQ(f->GetMonthlySeaLevelTemperatures()[m], m == 2 ? 9.5 : before[m]) << m;
  }
  t = f->GetMTime();
  f->SetMonthlySeaLevelTemperature(2, 9.5);
  EXPECT_EQ(f->GetMTime(), t);
  auto obs = vtkSmartPointer<terroir_test::ErrorObserver>::New();
  f->AddObserver(vtkCommand::ErrorEvent, obs);
  f->SetMonthlySeaLevelTemperature(12, 1.0);
  f->SetMonthlySeaLevelTemperature(-1, 1.0);
  EXPECT_EQ(obs->ErrorCount, 2);
  EXPECT_NE(obs->Errors.find("outside 0..11"), std::string::npos) << obs->Errors;
  EXPECT_EQ(f->GetMTime(), t);
}

TEST(TerroirTemperature, NoDataGivesNaNAndOtherTypesWork)
{
  auto in =
    MakeTerrain(3, 3, 1.0, 1.0, [](int i, int j) { return (i == 1 && j == 1) ? NAN : 500.0; });
  auto f = vtkSmartPointer<vtkTerroirTemperature>::New();
  auto out = RunTemperature(in, f);
  vtkDataArray* t = out->GetPointData()->GetArray("Temperature");
  for (int m = 0; m < 12; ++m)
  {
    EXPECT_TRUE(std::isnan(t->GetComponent(4, m)));
    EXPECT_FALSE(std::isnan(t->GetComponent(3, m)));
  }
  EXPECT_NEAR(t->GetComponent(0, 0), 2.0 - 3.2, 1e-5);

  for (int type : { VTK_DOUBLE, VTK_SHORT })
  {
    auto img = vtkSmartPointer<vtkImageData>::New();
    img->SetDimensions(2, 1, 1);
    vtkSmartPointer<vtkDataArray> a;
    a.TakeReference(vtkDataArray::CreateDataArray(type));
    a->SetName("Elevation");
    a->SetNumberOfTuples(2);
    a->SetComponent(0, 0, 250.0);
    a->SetComponent(1, 0, 1500.0);
    img->GetPointData()->AddArray(a);
    auto g = vtkSmartPointer<vtkTerroirTemperature>::New();
    auto o = RunTemperature(img, g);
    vtkDataArray* tt = o->GetPointData()->GetArray("Temperature");
    ASSERT_NE(tt, nullptr) << type;
    EXPECT_NEAR(tt->GetComponent(0, 6), 20.0 - 1.6, 1e-5);
    EXPECT_NEAR(tt->GetComponent(1, 0), 2.0 - 9.6, 1e-5);
  }
}

TEST(TerroirTemperature, BadInputAndBadMonthsAreErrors)
{
  auto in = MakeTerrain(3, 3, 1.0, 1.0, [](int, int) { return 1.0; });
  in->GetPointData()->GetArray("Elevation")->SetName("Altitude");
  auto f = vtkSmartPointer<vtkTerroirTemperature>::New();
  auto obs = vtkSmartPointer<terroir_test::ErrorObserver>::New();
  f->AddObserver(vtkCommand::ErrorEvent, obs);
  f->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, obs);
  RunTemperature(in, f);
  EXPECT_NE(obs->Errors.find("no elevation array"), std::string::npos) << obs->Errors;
  EXPECT_EQ(f->GetOutput()->GetPointData()->GetArray("Temperature"), nullptr);

  auto good = ThreeHeights();
  auto g = vtkSmartPointer<vtkTerroirTemperature>::New();
  auto obs2 = vtkSmartPointer<terroir_test::ErrorObserver>::New();
  g->AddObserver(vtkCommand::ErrorEvent, obs2);
  g->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, obs2);
  g->SetColdestMonth(5);
  g->SetWarmestMonth(5);
  RunTemperature(good, g);
  EXPECT_NE(obs2->Errors.find("must differ"), std::string::npos) << obs2->Errors;
  EXPECT_EQ(g->GetOutput()->GetPointData()->GetArray("Temperature"), nullptr);
}

TEST(TerroirTemperature, PointwiseUpdateExtentIsNotGrown)
{
  auto in = MakeTerrain(10, 10, 1.0, 1.0, [](int i, int j) { return i + j; });
  auto f = vtkSmartPointer<vtkTerroirTemperature>::New();
  f->SetBackendToCPU();
  const std::array<int, 6> request = { 2, 5, 3, 6, 0, 0 };
  EXPECT_EQ(terroir_test::RequestedInputExtent(f, in, request), request);
}

} // namespace

TEST(TerroirTemperature, AbsurdParametersAreErrorsNamingTheValue)
{
  struct Case
  {
    std::function<void(vtkTerroirTemperature*)> set;
    std::string message;
  };
  const std::vector<Case> cases = {
    { [](vtkTerroirTemperature* f) { f->SetLapseRate(-1.0); },
      "LapseRate -1.000000 C/km is outside [0, 20]" },
    { [](vtkTerroirTemperature* f) { f->SetLapseRate(std::nan("")); },
      "LapseRate nan C/km is outside [0, 20]" },
    { [](vtkTerroirTemperature* f) { f->SetSeaLevelTemperatureWarmest(100.0); },
      "sea-level temperatures 2.000000 (coldest) and 100.000000 C (warmest) must lie in [-90, "
      "60]" },
    { [](vtkTerroirTemperature* f) { f->SetSeaLevelTemperatureColdest(25.0); },
      "the coldest month's sea-level temperature 25.000000 C is above the warmest month's "
      "20.000000 C" },
    { [](vtkTerroirTemperature* f)
      {
        double m[12] = { 0, 1, 2, 3, 4, 5, INFINITY, 7, 8, 9, 10, 11 };
        f->SetMonthlySeaLevelTemperatures(m);
        f->UseMonthlyTemperaturesOn();
      },
      "sea-level temperature of Jul inf C is outside [-90, 60]" },
  };
  for (const Case& c : cases)
  {
    auto f = vtkSmartPointer<vtkTerroirTemperature>::New();
    f->SetBackendToCPU();
    c.set(f);
    auto obs = vtkSmartPointer<terroir_test::ErrorObserver>::New();
    f->AddObserver(vtkCommand::ErrorEvent, obs);
    RunTemperature(ThreeHeights(), f);
    EXPECT_NE(obs->Errors.find(c.message), std::string::npos) << obs->Errors;
    EXPECT_EQ(f->GetOutput()->GetPointData()->GetArray("Temperature"), nullptr);
  }
}

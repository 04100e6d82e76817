// vtkTerroirClimateReader: a climate table read into twelve values per quantity (the parser
// itself is tested in Testing/Unit/TestClimateTable.cxx), and its failures as one line naming
// the file.
#include "TerroirFilterTestUtilities.h"

#include "vtkCommand.h"
#include "vtkNew.h"
#include "vtkTerroirClimateReader.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

TEST(TerroirClimateReader, ReadsEveryColumnJanuaryFirst)
{
  const std::string path = terroir_test::TempFile("climate_reader.csv");
  {
    std::ofstream out(path);
    out << "month,precipitation_mm,intensity_mm_per_h,temperature_c\n";
    for (int m = 1; m <= 12; ++m)
    {
      out << m << "," << 10 * m << "," << 0.5 * m << "," << m - 3 << "\n";
    }
  }
  vtkNew<vtkTerroirClimateReader> r;
  r->SetFileName(path.c_str());
  ASSERT_TRUE(r->Read()) << r->GetErrorMessage();
  EXPECT_STREQ(r->GetErrorMessage(), "");
  EXPECT_TRUE(r->HasPrecipitation());
  EXPECT_TRUE(r->HasPrecipitationIntensity());
  EXPECT_TRUE(r->HasTemperature());
  for (int m = 0; m < 12; ++m)
  {
    EXPECT_EQ(r->GetPrecipitation()[m], 10.0 * (m + 1));
    EXPECT_EQ(r->GetPrecipitationIntensity()[m], 0.5 * (m + 1));
    EXPECT_EQ(r->GetTemperature()[m], m - 2.0);
  }
}

TEST(TerroirClimateReader, AMissingColumnIsAbsentNotZeroFilled)
{
  const std::string path = terroir_test::TempFile("climate_reader_rain_only.csv");
  {
    std::ofstream out(path);
    out << "month,precipitation_mm\n";
    for (int m = 1; m <= 12; ++m)
    {
      out << m << ",10\n";
    }
  }
  vtkNew<vtkTerroirClimateReader> r;
  r->SetFileName(path.c_str());
  ASSERT_TRUE(r->Read()) << r->GetErrorMessage();
  EXPECT_TRUE(r->HasPrecipitation());
  EXPECT_FALSE(r->HasPrecipitationIntensity());
  EXPECT_FALSE(r->HasTemperature());
}

TEST(TerroirClimateReader, FailuresAreOneLineNamingTheFile)
{
  const std::string bad = terroir_test::TempFile("climate_reader_bad.csv");
  {
    std::ofstream out(bad);
    out << "month,precipitation_mm\n1,10\n"; // eleven months missing
  }
  for (const std::string& path : { std::string("/nonexistent/climate.csv"), bad })
  {
    vtkNew<vtkTerroirClimateReader> r;
    auto obs = vtkSmartPointer<terroir_test::ErrorObserver>::New();
    r->AddObserver(vtkCommand::ErrorEvent, obs);
    r->SetFileName(path.c_str());
    EXPECT_FALSE(r->Read());
    const std::string error = r->GetErrorMessage();
    EXPECT_EQ(error.rfind(path + ": ", 0), 0u) << error;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
    EXPECT_EQ(obs->ErrorCount, 1);
    EXPECT_FALSE(r->HasPrecipitation());
    EXPECT_EQ(r->GetPrecipitation()[0], 0.0);
  }
  vtkNew<vtkTerroirClimateReader> none;
  auto obs = vtkSmartPointer<terroir_test::ErrorObserver>::New();
  none->AddObserver(vtkCommand::ErrorEvent, obs);
  EXPECT_FALSE(none->Read());
  EXPECT_NE(std::string(none->GetErrorMessage()).find("no file name"), std::string::npos);
}

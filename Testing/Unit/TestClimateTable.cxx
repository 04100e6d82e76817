// Unit tests of terroir::io::ParseClimateTable / ReadClimateTableFile on hand-written tables.
// The error messages are part of the user interface: they are compared exactly.
#include "ClimateTable.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

namespace
{
using terroir::io::ClimateTable;
using terroir::io::kMaxClimateFileBytes;

bool Parse(const std::string& text, ClimateTable& table, std::string& error)
{
  return terroir::io::ParseClimateTable(text.data(), text.size(), table, error);
}

bool IsDefault(const ClimateTable& t)
{
  const std::array<double, 12> zero{};
  return !t.hasPrecipitation && !t.hasIntensity && !t.hasTemperature && t.precipitationMm == zero &&
    t.intensityMmPerHour == zero && t.temperatureC == zero;
}

/// Parses `text`, expects a failure with a default table and a one-line error; returns it.
std::string ErrorOf(const std::string& text)
{
  ClimateTable t;
  t.hasTemperature = true; // must be reset by the parser
  t.temperatureC[3] = 7.0;
  std::string error;
  EXPECT_FALSE(Parse(text, t, error)) << text;
  EXPECT_TRUE(IsDefault(t));
  EXPECT_EQ(error.find('\n'), std::string::npos) << error;
  return error;
}

/// "month,temperature_c" then one row "m,m" per month number in `months` (row k on line k+2).
std::string TemperatureCsv(const std::vector<int>& months)
{
  std::string s = "month,temperature_c\n";
  for (int m : months)
  {
    s += std::to_string(m) + "," + std::to_string(m) + "\n";
  }
  return s;
}

/// A JSON array of 12 numbers, all `fill` except `index` which gets `value` (raw text).
std::string Array12(const std::string& fill, int index = -1, const std::string& value = "")
{
  std::string s = "[";
  for (int m = 0; m < 12; ++m)
  {
    s += (m ? ", " : "") + (m == index ? value : fill);
  }
  return s + "]";
}

std::string TempPath(const std::string& name)
{
  return std::string(TERROIR_TEMP_DIR) + "/ClimateTable_" + name;
}

void WriteFile(const std::string& path, const std::string& bytes)
{
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  ASSERT_TRUE(out.good()) << path;
}

const char* const kAllColumns = "month,precipitation_mm,intensity_mm_per_h,temperature_c\n"
                                "1,80.5,2.5,-3.25\n"
                                "2,60,2,-1.5\n"
                                "3,55,3,4\n"
                                "4,40,4,9.75\n"
                                "5,30,6,14\n"
                                "6,10,8,18.5\n"
                                "7,0,0,21\n"
                                "8,0,0,20.5\n"
                                "9,20,7,16\n"
                                "10,50,5,10\n"
                                "11,70,3,4.5\n"
                                "12,90.25,2.25,-1\n";
} // namespace

// ---------------------------------------------------------------------------------------------
// Valid tables

TEST(TerroirClimateTable, CsvWithAllThreeColumnsParsesExactValues)
{
  ClimateTable t;
  std::string error = "stale";
  ASSERT_TRUE(Parse(kAllColumns, t, error)) << error;
  EXPECT_TRUE(error.empty());
  EXPECT_TRUE(t.hasPrecipitation);
  EXPECT_TRUE(t.hasIntensity);
  EXPECT_TRUE(t.hasTemperature);
  const std::array<double, 12> p = { 80.5, 60, 55, 40, 30, 10, 0, 0, 20, 50, 70, 90.25 };
  const std::array<double, 12> i = { 2.5, 2, 3, 4, 6, 8, 0, 0, 7, 5, 3, 2.25 };
  const std::array<double, 12> c = { -3.25, -1.5, 4, 9.75, 14, 18.5, 21, 20.5, 16, 10, 4.5, -1 };
  // Every value is exactly representable: the parse must be exact.
  EXPECT_EQ(t.precipitationMm, p);
  EXPECT_EQ(t.intensityMmPerHour, i);
  EXPECT_EQ(t.temperatureC, c);
}

TEST(TerroirClimateTable, CsvMonthNamesInShuffledOrderLandInTheirSlots)
{
  const std::string text = "month,temperature_c\n"
                           "December,12\n"
                           "jan,1\n"
                           "MAR,3\n"
                           "february,2\n"
                           "7,7\n"
                           "Jun,6\n"
                           "may,5\n"
                           "April,4\n"
                           "aug,8\n"
                           "SEPTEMBER,9\n"
                           "oct,10\n"
                           "Nov,11\n";
  ClimateTable t;
  std::string error;
  ASSERT_TRUE(Parse(text, t, error)) << error;
  EXPECT_FALSE(t.hasPrecipitation);
  EXPECT_FALSE(t.hasIntensity);
  ASSERT_TRUE(t.hasTemperature);
  for (int m = 0; m < 12; ++m)
  {
    EXPECT_EQ(t.temperatureC[m], m + 1.0) << "month " << m + 1;
  }
}

TEST(TerroirClimateTable, CsvAcceptsCrlfBomCommentsBlankLinesAndPadding)
{
  // BOM, comments (one indented), blank lines with blanks, CRLF, tabs around fields, columns in
  // another order with mixed case, a leading '+', leading zeros, no newline at the end.
  const std::string text = "\xEF\xBB\xBF# monthly normals\r\n"
                           "\r\n"
                           "   # indented comment\r\n"
                           "Temperature_C ,\tMONTH\r\n"
                           "+1.5, 01\r\n"
                           "2.5,2\r\n"
                           " \t \r\n"
                           "3.5,3\r\n"
                           "4.5,4\r\n"
                           "# spring is over\r\n"
                           "5.5,5\r\n"
                           "6.5,6\r\n"
                           "7.5,7\r\n"
                           "8.5,8\r\n"
                           "9.5,9\r\n"
                           "10.5,10\r\n"
                           "11.5,11\r\n"
                           "\t1.25e1 ,\t12";
  ClimateTable t;
  std::string error;
  ASSERT_TRUE(Parse(text, t, error)) << error;
  ASSERT_TRUE(t.hasTemperature);
  EXPECT_FALSE(t.hasPrecipitation);
  for (int m = 0; m < 12; ++m)
  {
    EXPECT_EQ(t.temperatureC[m], m + 1.5) << "month " << m + 1;
  }
}

TEST(TerroirClimateTable, CsvAcceptsTheLimitsExactly)
{
  std::string text = "month,precipitation_mm,intensity_mm_per_h,temperature_c\n";
  for (int m = 1; m <= 12; ++m)
  {
    text += std::to_string(m) + (m % 2 ? ",10000,500,60\n" : ",0,0,-90\n");
  }
  ClimateTable t;
  std::string error;
  ASSERT_TRUE(Parse(text, t, error)) << error;
  EXPECT_EQ(t.precipitationMm[0], 10000.0);
  EXPECT_EQ(t.intensityMmPerHour[0], 500.0);
  EXPECT_EQ(t.temperatureC[0], 60.0);
  EXPECT_EQ(t.precipitationMm[1], 0.0);
  EXPECT_EQ(t.temperatureC[1], -90.0);
}

TEST(TerroirClimateTable, JsonWithTwoKeysSetsOnlyThoseFlags)
{
  const std::string text = "  \n{\n"
                           "  \"description\": \"Sagehen Creek normals\",\n"
                           "  \"source\": \"hand-made\",\n"
                           "  \"temperature_c\": [-2, -1.5, 1, 4, 8, 12, 16, 15.5, 12, 7, 2, -1],\n"
                           "  \"precipitation_mm\": [150, 140, 110, 60, 35, 15, 5, 5, 15, 50, "
                           "110, 145]\n"
                           "}\n";
  ClimateTable t;
  std::string error;
  ASSERT_TRUE(Parse(text, t, error)) << error;
  EXPECT_TRUE(t.hasTemperature);
  EXPECT_TRUE(t.hasPrecipitation);
  EXPECT_FALSE(t.hasIntensity);
  const std::array<double, 12> c = { -2, -1.5, 1, 4, 8, 12, 16, 15.5, 12, 7, 2, -1 };
  const std::array<double, 12> p = { 150, 140, 110, 60, 35, 15, 5, 5, 15, 50, 110, 145 };
  EXPECT_EQ(t.temperatureC, c);
  EXPECT_EQ(t.precipitationMm, p);
  EXPECT_EQ(t.intensityMmPerHour, (std::array<double, 12>{}));
}

TEST(TerroirClimateTable, JsonWithBomAndAllThreeKeys)
{
  const std::string text = "\xEF\xBB\xBF{\"intensity_mm_per_h\": " + Array12("2.5") +
    ", \"precipitation_mm\": " + Array12("10", 6, "0") +
    ", \"temperature_c\": " + Array12("-90", 11, "60") + "}";
  ClimateTable t;
  std::string error;
  ASSERT_TRUE(Parse(text, t, error)) << error;
  EXPECT_TRUE(t.hasPrecipitation && t.hasIntensity && t.hasTemperature);
  EXPECT_EQ(t.intensityMmPerHour[0], 2.5);
  EXPECT_EQ(t.precipitationMm[5], 10.0);
  EXPECT_EQ(t.precipitationMm[6], 0.0);
  EXPECT_EQ(t.temperatureC[0], -90.0);
  EXPECT_EQ(t.temperatureC[11], 60.0);
}

TEST(TerroirClimateTable, JsonBracketsInsideStringsDoNotCountAsNesting)
{
  const std::string text = "{\"description\": \"[[[[[[[[[[[[[[[[[[[[{{{{{{{{{{{{{{{{{{\\\"\", "
                           "\"temperature_c\": " +
    Array12("3") + "}";
  ClimateTable t;
  std::string error;
  ASSERT_TRUE(Parse(text, t, error)) << error;
  EXPECT_EQ(t.temperatureC[11], 3.0);
}

TEST(TerroirClimateTable, FailureResetsAPreviouslyFilledTable)
{
  ClimateTable t;
  std::string error;
  ASSERT_TRUE(Parse(kAllColumns, t, error)) << error;
  EXPECT_FALSE(Parse("month,temperature_c\n1,4\n", t, error));
  EXPECT_TRUE(IsDefault(t));
  EXPECT_EQ(error, "missing months: Feb, Mar, Apr, May, Jun, Jul, Aug, Sep, Oct, Nov, Dec");
  ASSERT_TRUE(Parse(kAllColumns, t, error)) << error;
  EXPECT_TRUE(error.empty());
}

// ---------------------------------------------------------------------------------------------
// Errors common to both formats

TEST(TerroirClimateTable, RejectsInputLargerThanOneMiB)
{
  EXPECT_EQ(
    ErrorOf(std::string(kMaxClimateFileBytes + 1, ' ')), "larger than 1 MiB: not a climate table");
  // Exactly the limit is read (and is blank here).
  EXPECT_EQ(ErrorOf(std::string(kMaxClimateFileBytes, ' ')), "empty file");
}

TEST(TerroirClimateTable, RejectsEmptyInput)
{
  EXPECT_EQ(ErrorOf(""), "empty file");
  EXPECT_EQ(ErrorOf(" \t\r\n\n"), "empty file");
  EXPECT_EQ(ErrorOf("\xEF\xBB\xBF"), "empty file");
  ClimateTable t;
  std::string error;
  EXPECT_FALSE(terroir::io::ParseClimateTable(nullptr, 10, t, error));
  EXPECT_EQ(error, "empty file");
}

TEST(TerroirClimateTable, RejectsNulByte)
{
  const std::string text("month,temperature_c\n1,\0\n", 24);
  EXPECT_EQ(ErrorOf(text), "binary data, not a climate table");
  EXPECT_EQ(
    ErrorOf(std::string("{\"temperature_c\": \0}", 20)), "binary data, not a climate table");
}

// ---------------------------------------------------------------------------------------------
// CSV errors

TEST(TerroirClimateTable, CsvRejectsUnknownColumn)
{
  EXPECT_EQ(ErrorOf("month,precip\n1,4\n"),
    "line 1: unknown column 'precip'; expected month, precipitation_mm, intensity_mm_per_h, "
    "temperature_c");
  // The line number counts comment and blank lines; control bytes are not echoed.
  EXPECT_EQ(ErrorOf("# climate\n\nMonth,te\x01mp\n"),
    "line 3: unknown column 'te?mp'; expected month, precipitation_mm, intensity_mm_per_h, "
    "temperature_c");
  // A first line of data is not a header.
  EXPECT_EQ(ErrorOf("1,4\n"),
    "line 1: unknown column '1'; expected month, precipitation_mm, intensity_mm_per_h, "
    "temperature_c");
}

TEST(TerroirClimateTable, MessagesEchoOnlyWellFormedPrintableText)
{
  const std::string expected =
    "; expected month, precipitation_mm, intensity_mm_per_h, temperature_c";
  // UTF-8 text is kept; a stray byte, a cut sequence, a C1 control (U+0085) and an encoded
  // surrogate become '?' (one per byte that does not start a well-formed character).
  const std::string eAcute = "\xC3\xA9", stray = "\xFF", cut = "\xC3", c1 = "\xC2\x85";
  const std::string surrogate = "\xED\xA0\x80";
  EXPECT_EQ(ErrorOf("month,pr" + eAcute + "cip\n"),
    "line 1: unknown column 'pr" + eAcute + "cip'" + expected);
  EXPECT_EQ(
    ErrorOf("month,a" + stray + "b" + cut + "\n"), "line 1: unknown column 'a?b?'" + expected);
  EXPECT_EQ(ErrorOf("month,a" + c1 + "b" + surrogate + "\n"),
    "line 1: unknown column 'a?b" + std::string(3, '?') + "'" + expected);
}

TEST(TerroirClimateTable, CsvRejectsDuplicateColumn)
{
  EXPECT_EQ(
    ErrorOf("month,temperature_c,Temperature_C\n"), "line 1: duplicate column 'temperature_c'");
  EXPECT_EQ(ErrorOf("month,temperature_c,MONTH\n"), "line 1: duplicate column 'month'");
}

TEST(TerroirClimateTable, CsvRejectsMissingOrEmptyColumns)
{
  EXPECT_EQ(ErrorOf("temperature_c,precipitation_mm\n"), "line 1: missing column 'month'");
  EXPECT_EQ(ErrorOf("month\n1\n"),
    "line 1: no value column; expected at least one of precipitation_mm, intensity_mm_per_h, "
    "temperature_c");
  EXPECT_EQ(ErrorOf("month,,temperature_c\n"),
    "line 1: empty column name (column 2); expected month, precipitation_mm, "
    "intensity_mm_per_h, temperature_c");
}

TEST(TerroirClimateTable, CsvRejectsMissingHeaderOrRows)
{
  EXPECT_EQ(ErrorOf("# only a comment\n"),
    "no header line; expected month and at least one of precipitation_mm, intensity_mm_per_h, "
    "temperature_c");
  EXPECT_EQ(ErrorOf("\n# notes\nmonth,temperature_c\n# nothing yet\n"),
    "no data rows after the header on line 3; expected one row per month");
}

TEST(TerroirClimateTable, CsvRejectsWrongFieldCount)
{
  EXPECT_EQ(ErrorOf("month,temperature_c\n1,4\n2,4,5\n"),
    "line 3: 3 fields, expected 2 (month, temperature_c); decimals take '.', not ','");
  EXPECT_EQ(ErrorOf("month,precipitation_mm,temperature_c\n1,2\n"),
    "line 2: 2 fields, expected 3 (month, precipitation_mm, temperature_c)");
  EXPECT_EQ(ErrorOf("month,temperature_c\n1,4,\n"),
    "line 2: 3 fields, expected 2 (month, temperature_c); decimals take '.', not ','");
}

TEST(TerroirClimateTable, CsvRejectsEmptyValue)
{
  EXPECT_EQ(ErrorOf("month,temperature_c\n1, \t\n"), "line 2: empty value in column temperature_c");
  EXPECT_EQ(ErrorOf("month,temperature_c\n , 4\n"), "line 2: empty value in column month");
}

TEST(TerroirClimateTable, CsvRejectsQuotedField)
{
  EXPECT_EQ(ErrorOf("month,temperature_c\n1,\"4\"\n"),
    "line 2: field 2 '\"4\"' contains a double quote; quoting is not supported");
  EXPECT_EQ(ErrorOf("\"month\",temperature_c\n"),
    "line 1: field 1 '\"month\"' contains a double quote; quoting is not supported");
}

TEST(TerroirClimateTable, CsvRejectsCarriageReturnInsideALine)
{
  EXPECT_EQ(ErrorOf("month,temperature_c\n1,4\r5\n"),
    "line 2: carriage return inside a line (lines must end with \\n or \\r\\n)");
  // Old Mac line ends: the whole file is one line.
  EXPECT_EQ(ErrorOf("month,temperature_c\r1,4\r2,5\r"),
    "line 1: carriage return inside a line (lines must end with \\n or \\r\\n)");
}

TEST(TerroirClimateTable, CsvRejectsUnknownMonth)
{
  const std::string expected = "; expected 1 to 12, Jan to Dec or January to December";
  EXPECT_EQ(ErrorOf("month,temperature_c\nJanu,4\n"), "line 2: unknown month 'Janu'" + expected);
  EXPECT_EQ(ErrorOf("month,temperature_c\n0,4\n"), "line 2: unknown month '0'" + expected);
  EXPECT_EQ(ErrorOf("month,temperature_c\n13,4\n"), "line 2: unknown month '13'" + expected);
  EXPECT_EQ(ErrorOf("month,temperature_c\n1.0,4\n"), "line 2: unknown month '1.0'" + expected);
}

TEST(TerroirClimateTable, CsvRejectsMonthGivenTwice)
{
  EXPECT_EQ(ErrorOf(TemperatureCsv({ 1, 2, 3, 3 })), "line 5: Mar given twice (first on line 4)");
  EXPECT_EQ(ErrorOf("month,temperature_c\n12,1\n# x\nDecember,2\n"),
    "line 4: Dec given twice (first on line 2)");
}

TEST(TerroirClimateTable, CsvRejectsMissingMonths)
{
  EXPECT_EQ(
    ErrorOf(TemperatureCsv({ 1, 2, 5, 6, 7, 8, 9, 10, 11, 12 })), "missing months: Mar, Apr");
  EXPECT_EQ(ErrorOf(TemperatureCsv({ 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11 })), "missing month: Dec");
}

TEST(TerroirClimateTable, CsvRejectsMoreThanTwelveRows)
{
  EXPECT_EQ(ErrorOf(TemperatureCsv({ 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 1 })),
    "line 14: more than 12 data rows (one per month)");
}

TEST(TerroirClimateTable, CsvRejectsMalformedAndNonFiniteNumbers)
{
  const std::string head = "month,temperature_c\n";
  EXPECT_EQ(
    ErrorOf(head + "1,nan\n"), "line 2: temperature_c for Jan is 'nan', not a finite number");
  EXPECT_EQ(
    ErrorOf(head + "2,inf\n"), "line 2: temperature_c for Feb is 'inf', not a finite number");
  EXPECT_EQ(ErrorOf(head + "2,-Infinity\n"),
    "line 2: temperature_c for Feb is '-Infinity', not a finite number");
  EXPECT_EQ(ErrorOf(head + "3,0x1p3\n"), "line 2: temperature_c for Mar is '0x1p3', not a number");
  EXPECT_EQ(ErrorOf(head + "3,12abc\n"), "line 2: temperature_c for Mar is '12abc', not a number");
  EXPECT_EQ(ErrorOf(head + "3,1 2\n"), "line 2: temperature_c for Mar is '1 2', not a number");
  EXPECT_EQ(ErrorOf(head + "3,++1\n"), "line 2: temperature_c for Mar is '++1', not a number");
  EXPECT_EQ(ErrorOf(head + "3,+-1\n"), "line 2: temperature_c for Mar is '+-1', not a number");
  EXPECT_EQ(ErrorOf(head + "4,1e400\n"),
    "line 2: temperature_c for Apr is '1e400', too large or too small for a double");
  // Long text is cut in the message.
  EXPECT_EQ(ErrorOf(head + "5," + std::string(100, 'x') + "\n"),
    "line 2: temperature_c for May is '" + std::string(40, 'x') + "...', not a number");
}

TEST(TerroirClimateTable, CsvRejectsValuesOutOfRange)
{
  EXPECT_EQ(ErrorOf("month,precipitation_mm\n1,10\n2,10\n3,-4\n"),
    "line 4: precipitation_mm for Mar is -4, must be >= 0");
  EXPECT_EQ(ErrorOf("month,precipitation_mm\nJul,10000.5\n"),
    "line 2: precipitation_mm for Jul is 10000.5, must be <= 10000");
  EXPECT_EQ(ErrorOf("month,intensity_mm_per_h\n1,500.01\n"),
    "line 2: intensity_mm_per_h for Jan is 500.01, must be <= 500");
  EXPECT_EQ(ErrorOf("month,intensity_mm_per_h\n1,-0.1\n"),
    "line 2: intensity_mm_per_h for Jan is -0.1, must be >= 0");
  EXPECT_EQ(ErrorOf("month,temperature_c\n8,-90.5\n"),
    "line 2: temperature_c for Aug is -90.5, must be >= -90");
  EXPECT_EQ(ErrorOf("month,temperature_c\n8,6e1\n9,60.1\n"),
    "line 3: temperature_c for Sep is 60.1, must be <= 60");
}

TEST(TerroirClimateTable, CsvRejectsRainWithoutIntensity)
{
  EXPECT_EQ(ErrorOf("month,precipitation_mm,intensity_mm_per_h\n1,0,0\n2,12,0.0\n"),
    "line 3: precipitation_mm for Feb is 12 but intensity_mm_per_h is 0.0: rain needs a "
    "positive intensity");
  // Column order does not matter.
  EXPECT_EQ(ErrorOf("intensity_mm_per_h,month,precipitation_mm\n0,Jun,0.5\n"),
    "line 2: precipitation_mm for Jun is 0.5 but intensity_mm_per_h is 0: rain needs a "
    "positive intensity");
}

// ---------------------------------------------------------------------------------------------
// JSON errors

TEST(TerroirClimateTable, JsonRejectsUnknownKey)
{
  EXPECT_EQ(ErrorOf("{\"temperature_c\": " + Array12("1") + ", \"precip\": []}"),
    "unknown key 'precip'; expected precipitation_mm, intensity_mm_per_h, temperature_c, "
    "description, source");
  // JSON keys are case-sensitive.
  EXPECT_EQ(ErrorOf("{\"Temperature_C\": " + Array12("1") + "}"),
    "unknown key 'Temperature_C'; expected precipitation_mm, intensity_mm_per_h, temperature_c, "
    "description, source");
}

TEST(TerroirClimateTable, JsonRejectsDuplicateKey)
{
  EXPECT_EQ(
    ErrorOf("{\"temperature_c\": " + Array12("1") + ", \"temperature_c\": " + Array12("2") + "}"),
    "duplicate key 'temperature_c'");
}

TEST(TerroirClimateTable, JsonRejectsWrongTypes)
{
  EXPECT_EQ(ErrorOf("{\"temperature_c\": \"warm\"}"),
    "temperature_c must be an array of 12 numbers, not a string");
  EXPECT_EQ(ErrorOf("{\"precipitation_mm\": {\"jan\": 1}}"),
    "precipitation_mm must be an array of 12 numbers, not an object");
  EXPECT_EQ(ErrorOf("{\"temperature_c\": [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11]}"),
    "temperature_c has 11 values, expected 12 (January first)");
  EXPECT_EQ(ErrorOf("{\"precipitation_mm\": " + Array12("1", 3, "\"4\"") + "}"),
    "precipitation_mm[3] (Apr) is a string, expected a number");
  EXPECT_EQ(ErrorOf("{\"temperature_c\": " + Array12("1", 0, "null") + "}"),
    "temperature_c[0] (Jan) is null, expected a number");
  EXPECT_EQ(ErrorOf("{\"temperature_c\": " + Array12("1", 11, "true") + "}"),
    "temperature_c[11] (Dec) is a boolean, expected a number");
  EXPECT_EQ(ErrorOf("{\"temperature_c\": " + Array12("1", 5, "[6]") + "}"),
    "temperature_c[5] (Jun) is an array, expected a number");
  EXPECT_EQ(ErrorOf("{\"description\": 3, \"temperature_c\": " + Array12("1") + "}"),
    "description must be a string, not a number");
  EXPECT_EQ(ErrorOf("{\"source\": null, \"temperature_c\": " + Array12("1") + "}"),
    "source must be a string, not null");
}

TEST(TerroirClimateTable, JsonRejectsMissingValueKeys)
{
  const std::string expected =
    "no climate values; expected at least one of precipitation_mm, intensity_mm_per_h, "
    "temperature_c";
  EXPECT_EQ(ErrorOf("{}"), expected);
  EXPECT_EQ(ErrorOf("{\"description\": \"empty\", \"source\": \"nobody\"}"), expected);
}

TEST(TerroirClimateTable, JsonRejectsValuesOutOfRange)
{
  EXPECT_EQ(ErrorOf("{\"precipitation_mm\": " + Array12("10", 2, "-4") + "}"),
    "precipitation_mm[2] (Mar) is -4, must be >= 0");
  EXPECT_EQ(ErrorOf("{\"precipitation_mm\": " + Array12("10", 6, "1.2e4") + "}"),
    "precipitation_mm[6] (Jul) is 12000, must be <= 10000");
  EXPECT_EQ(ErrorOf("{\"intensity_mm_per_h\": " + Array12("10", 0, "500.5") + "}"),
    "intensity_mm_per_h[0] (Jan) is 500.5, must be <= 500");
  EXPECT_EQ(ErrorOf("{\"temperature_c\": " + Array12("10", 6, "60.5") + "}"),
    "temperature_c[6] (Jul) is 60.5, must be <= 60");
  EXPECT_EQ(ErrorOf("{\"temperature_c\": " + Array12("10", 1, "-1e300") + "}"),
    "temperature_c[1] (Feb) is -1e+300, must be >= -90");
}

TEST(TerroirClimateTable, JsonRejectsNonFiniteNumber)
{
  // JSON has no NaN or Infinity literal; nlohmann/json refuses numbers that overflow a double.
  EXPECT_EQ(ErrorOf("{\"temperature_c\": " + Array12("1", 0, "1e400") + "}"),
    "invalid JSON: number overflow parsing '1e400'");
  const std::string nanText = ErrorOf("{\"temperature_c\": " + Array12("1", 0, "NaN") + "}");
  EXPECT_EQ(nanText.rfind("invalid JSON: ", 0), 0u) << nanText;
}

TEST(TerroirClimateTable, JsonRejectsRainWithoutIntensity)
{
  EXPECT_EQ(ErrorOf("{\"precipitation_mm\": " + Array12("0", 4, "12.5") +
              ", \"intensity_mm_per_h\": " + Array12("0", 4, "0") + "}"),
    "precipitation_mm[4] (May) is 12.5 but intensity_mm_per_h[4] is 0: rain needs a positive "
    "intensity");
}

TEST(TerroirClimateTable, JsonRejectsSyntaxErrors)
{
  // nlohmann/json's own description follows the prefix (its exception id is dropped).
  EXPECT_EQ(ErrorOf("{\"temperature_c\": [1, 2,]}"),
    "invalid JSON: parse error at line 1, column 25: syntax error while parsing value - "
    "unexpected ']'; expected '[', '{', or a literal");
  EXPECT_EQ(ErrorOf("{\n\"temperature_c\": [1]\n} {}"),
    "invalid JSON: parse error at line 3, column 3: syntax error while parsing value - "
    "unexpected '{'; expected end of input");
  // A control character inside a string is never echoed raw.
  const std::string control = ErrorOf("{\"description\": \"a\nb\"}");
  EXPECT_EQ(control.rfind("invalid JSON: parse error at line 2, column 0: syntax error while "
                          "parsing value - invalid string: control character U+000A (LF)",
              0),
    0u)
    << control;
}

TEST(TerroirClimateTable, JsonRejectsDeepNesting)
{
  const std::string expected = "JSON nested deeper than 16 levels: not a climate table";
  // '{' is level 1: 15 brackets reach level 16 (allowed), 16 reach level 17.
  EXPECT_EQ(ErrorOf("{\"description\": " + std::string(15, '[') + std::string(15, ']') + "}"),
    "description must be a string, not an array");
  EXPECT_EQ(
    ErrorOf("{\"description\": " + std::string(16, '[') + std::string(16, ']') + "}"), expected);
  // Far deeper than any stack could take, and unterminated.
  EXPECT_EQ(ErrorOf("{\"a\": " + std::string(500000, '[')), expected);
}

// ---------------------------------------------------------------------------------------------
// Files

TEST(TerroirClimateTable, ReadFileReportsMissingFile)
{
  const std::string path = TempPath("missing.csv");
  std::filesystem::remove(path);
  ClimateTable t;
  std::string error;
  EXPECT_FALSE(terroir::io::ReadClimateTableFile(path, t, error));
  EXPECT_EQ(error, path + ": no such file");
  EXPECT_TRUE(IsDefault(t));
}

TEST(TerroirClimateTable, ReadFileReportsDirectory)
{
  const std::string path = TempPath("folder.csv");
  std::filesystem::create_directories(path);
  ClimateTable t;
  std::string error;
  EXPECT_FALSE(terroir::io::ReadClimateTableFile(path, t, error));
  EXPECT_EQ(error, path + ": is a directory, not a file");
}

TEST(TerroirClimateTable, ReadFileRejectsFileJustOverTheLimit)
{
  // A valid table padded with a comment to exactly 1 MiB is read; one byte more is refused.
  std::string text = kAllColumns;
  text += "#";
  text += std::string(kMaxClimateFileBytes - text.size() - 1, 'x');
  text += "\n";
  ASSERT_EQ(text.size(), kMaxClimateFileBytes);
  const std::string path = TempPath("limit.csv");
  WriteFile(path, text);
  ClimateTable t;
  std::string error;
  EXPECT_TRUE(terroir::io::ReadClimateTableFile(path, t, error)) << error;
  EXPECT_EQ(t.temperatureC[11], -1.0);

  WriteFile(path, text + "\n");
  EXPECT_FALSE(terroir::io::ReadClimateTableFile(path, t, error));
  EXPECT_EQ(error, path + ": larger than 1 MiB: not a climate table");
  EXPECT_TRUE(IsDefault(t));
  std::filesystem::remove(path);
}

TEST(TerroirClimateTable, ReadFileParsesValidFileAndPrefixesParseErrors)
{
  const std::string path = TempPath("valid.json");
  WriteFile(path, "{\"temperature_c\": " + Array12("4.5", 6, "21") + "}\n");
  ClimateTable t;
  std::string error;
  ASSERT_TRUE(terroir::io::ReadClimateTableFile(path, t, error)) << error;
  EXPECT_TRUE(error.empty());
  EXPECT_TRUE(t.hasTemperature);
  EXPECT_FALSE(t.hasPrecipitation);
  EXPECT_EQ(t.temperatureC[0], 4.5);
  EXPECT_EQ(t.temperatureC[6], 21.0);

  const std::string bad = TempPath("bad.csv");
  WriteFile(bad, "month,precip\n");
  EXPECT_FALSE(terroir::io::ReadClimateTableFile(bad, t, error));
  EXPECT_EQ(error,
    bad +
      ": line 1: unknown column 'precip'; expected month, precipitation_mm, "
      "intensity_mm_per_h, temperature_c");
  EXPECT_TRUE(IsDefault(t));

  WriteFile(bad, "");
  EXPECT_FALSE(terroir::io::ReadClimateTableFile(bad, t, error));
  EXPECT_EQ(error, bad + ": empty file");
  std::filesystem::remove(path);
  std::filesystem::remove(bad);
}

TEST(TerroirClimateTable, ReadFileReportsUnreadablePath)
{
  // A regular file used as a folder counts as missing (ENOTDIR, like ENOENT).
  const std::string file = TempPath("plain.csv");
  WriteFile(file, kAllColumns);
  ClimateTable t;
  std::string error;
  EXPECT_FALSE(terroir::io::ReadClimateTableFile(file + "/x.csv", t, error));
  EXPECT_EQ(error, file + "/x.csv: no such file");
  std::filesystem::remove(file);
  // Any other failure carries the system's message: a symbolic link to itself.
  const std::string loop = TempPath("loop.csv");
  std::filesystem::remove(loop);
  std::filesystem::create_symlink("ClimateTable_loop.csv", loop);
  EXPECT_FALSE(terroir::io::ReadClimateTableFile(loop, t, error));
  EXPECT_EQ(error, loop + ": cannot be read (Too many levels of symbolic links)");
  EXPECT_TRUE(IsDefault(t));
  std::filesystem::remove(loop);
}

TEST(TerroirClimateTable, ReadFileReportsUnreadableFile)
{
  // In a folder anyone may enter, so that the check below is about the file's own permissions.
  char folder[] = "/tmp/terroir-climate-XXXXXX";
  ASSERT_NE(mkdtemp(folder), nullptr);
  ASSERT_EQ(chmod(folder, 0755), 0);
  const std::string path = std::string(folder) + "/unreadable.csv";
  WriteFile(path, kAllColumns);
  std::filesystem::permissions(path, std::filesystem::perms::none);
  auto check = [&path]
  {
    ClimateTable t;
    std::string error;
    const bool read = terroir::io::ReadClimateTableFile(path, t, error);
    return !read && error == path + ": cannot be read (Permission denied)";
  };
  if (geteuid() != 0)
  {
    EXPECT_TRUE(check());
  }
  else
  {
    // Root reads any file: check as the unprivileged user nobody, in a child process.
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    EXPECT_EXIT(
      {
        if (setgid(65534) != 0 || setuid(65534) != 0)
        {
          std::_Exit(2);
        }
        std::_Exit(check() ? 0 : 1);
      },
      ::testing::ExitedWithCode(0),
      "");
  }
  std::filesystem::remove_all(folder);
}

// Unit tests of the plant point-pattern CSV (terroir::io::ParsePointPatternCsv and
// FormatPointPatternCsv): values read as written, the optional columns, the one-line errors with
// their line numbers, and a round trip that gives the same doubles back.
#include "PointPatternFile.h"

#include <gtest/gtest.h>

#include <string>

namespace
{
using terroir::io::PointPatternTable;

bool Parse(const std::string& text, PointPatternTable& t, std::string& error)
{
  return terroir::io::ParsePointPatternCsv(text.data(), text.size(), t, error);
}

std::string ErrorOf(const std::string& text)
{
  PointPatternTable t;
  std::string error;
  EXPECT_FALSE(Parse(text, t, error));
  EXPECT_TRUE(t.x.empty());
  return error;
}

TEST(TerroirPointPatternFile, ReadsTheColumnsInAnyOrderWithCommentsAndCRLF)
{
  PointPatternTable t;
  std::string error;
  ASSERT_TRUE(Parse("\xEF\xBB\xBF# exemplar, 2 species\r\nSpecies, Y ,x,cluster_id\r\n"
                    "1,20.5,10,3\r\n\r\n# a comment\n0,-4e2,+7.25,-1\n",
    t,
    error))
    << error;
  ASSERT_EQ(t.x.size(), 2u);
  EXPECT_EQ(t.x[0], 10.0);
  EXPECT_EQ(t.y[0], 20.5);
  EXPECT_EQ(t.x[1], 7.25);
  EXPECT_EQ(t.y[1], -400.0);
  EXPECT_EQ(t.species, (std::vector<int>{ 1, 0 }));
  EXPECT_EQ(t.zone, (std::vector<int>{ 3, -1 }));
  EXPECT_FALSE(t.hasZ);
}

TEST(TerroirPointPatternFile, OnlyXAndYAreNeeded)
{
  PointPatternTable t;
  std::string error;
  ASSERT_TRUE(Parse("x,y,z\n1,2,3\n4,5,6", t, error)) << error;
  EXPECT_EQ(t.x.size(), 2u);
  EXPECT_TRUE(t.hasZ);
  EXPECT_EQ(t.z[1], 6.0);
  EXPECT_TRUE(t.species.empty());
  EXPECT_TRUE(t.zone.empty());
}

TEST(TerroirPointPatternFile, BadFilesAreOneLineNamingTheLine)
{
  EXPECT_EQ(ErrorOf(""), "no header (a line such as x,y,species)");
  EXPECT_EQ(ErrorOf("x,y\n"), "no plants after the header");
  EXPECT_EQ(ErrorOf("x,height\n1,2\n"),
    "line 1: unknown column 'height'; expected x, y, z, species, cluster_id");
  EXPECT_EQ(ErrorOf("x,species\n1,2\n"), "line 1: the header needs the columns x and y");
  EXPECT_EQ(ErrorOf("x,y,X\n1,2,3\n"), "line 1: column 'X' appears twice");
  EXPECT_EQ(ErrorOf("x,y\n1,2\n3\n"), "line 3: 1 fields, the header has 2");
  EXPECT_EQ(ErrorOf("x,y\n1,nan\n"), "line 2: y 'nan' is not a finite number");
  EXPECT_EQ(ErrorOf("x,y\n1,1e999\n"), "line 2: y '1e999' is not a finite number");
  EXPECT_EQ(ErrorOf("x,y\n1,2abc\n"), "line 2: y '2abc' is not a finite number");
  EXPECT_EQ(
    ErrorOf("x,y,species\n1,2,64\n"), "line 2: species '64' is not a whole number in 0..63");
  EXPECT_EQ(
    ErrorOf("x,y,species\n1,2,1.5\n"), "line 2: species '1.5' is not a whole number in 0..63");
  EXPECT_EQ(ErrorOf("x,y,cluster_id\n1,2,-2\n"),
    "line 2: cluster_id '-2' is not a whole number in -1..1000000000");
  EXPECT_EQ(ErrorOf(std::string("x,y\n1,2\0\n", 9)), "not a text file (it holds a NUL byte)");
  EXPECT_EQ(
    ErrorOf("x,\x01y\n"), "line 1: unknown column '?y'; expected x, y, z, species, cluster_id");
}

TEST(TerroirPointPatternFile, FormatThenParseGivesTheSameValues)
{
  PointPatternTable t;
  t.x = { 0.1, 1e6 / 3.0, -2.5 };
  t.y = { 1.0 / 7.0, 2.0, 3.0 };
  t.hasZ = true;
  t.z = { 1000.25, 0.0, -1.0 };
  t.species = { 0, 63, 5 };
  t.zone = { -1, 2, 7 };
  const std::string text = terroir::io::FormatPointPatternCsv(t);
  EXPECT_EQ(text.substr(0, text.find('\n')), "x,y,z,species,cluster_id");
  PointPatternTable back;
  std::string error;
  ASSERT_TRUE(Parse(text, back, error)) << error;
  EXPECT_EQ(back.x, t.x);
  EXPECT_EQ(back.y, t.y);
  EXPECT_EQ(back.z, t.z);
  EXPECT_EQ(back.species, t.species);
  EXPECT_EQ(back.zone, t.zone);
}

} // namespace

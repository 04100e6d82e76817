// Unit tests of terroir::io::ReadTerragen / WriteTerragen on hand-built byte strings.
#include "Terragen.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace
{
using Bytes = std::vector<std::uint8_t>;

void Tag(Bytes& b, const char* t)
{
  b.insert(b.end(), t, t + 4);
}
void I16(Bytes& b, int v)
{
  const auto u = static_cast<std::uint16_t>(static_cast<std::int16_t>(v));
  b.push_back(static_cast<std::uint8_t>(u & 0xff));
  b.push_back(static_cast<std::uint8_t>(u >> 8));
}
void F32(Bytes& b, float f)
{
  std::uint32_t u;
  std::memcpy(&u, &f, 4);
  for (int k = 0; k < 4; ++k)
  {
    b.push_back(static_cast<std::uint8_t>(u >> (8 * k)));
  }
}
Bytes Header()
{
  const char* magic = "TERRAGENTERRAIN ";
  return Bytes(magic, magic + 16);
}

// A 3 x 2 terrain written byte by byte following the specification.
Bytes SmallFile(bool withXY = true, bool withEOF = true)
{
  Bytes b = Header();
  Tag(b, "SIZE");
  I16(b, 1); // min(3, 2) - 1
  I16(b, 0);
  if (withXY)
  {
    Tag(b, "XPTS");
    I16(b, 3);
    I16(b, 0);
    Tag(b, "YPTS");
    I16(b, 2);
    I16(b, 0);
  }
  Tag(b, "SCAL");
  F32(b, 5.0f);
  F32(b, 7.0f);
  F32(b, 2.0f);
  Tag(b, "CRAD");
  F32(b, 6370.0f);
  Tag(b, "CRVM");
  b.insert(b.end(), { 0, 0, 0, 0 });
  Tag(b, "ALTW");
  I16(b, 16384); // HeightScale: raw * 16384 / 65536 = raw / 4 terrain units
  I16(b, 100);   // BaseHeight
  const int raw[6] = { 0, 4, -4, 400, -32768, 32767 };
  for (int r : raw)
  {
    I16(b, r);
  }
  if (withEOF)
  {
    Tag(b, "EOF ");
  }
  return b;
}
} // namespace

TEST(TerroirTerragen, ParsesHandBuiltFile)
{
  terroir::io::TerragenTerrain t;
  std::string error;
  ASSERT_TRUE(terroir::io::ReadTerragen(SmallFile(), t, error)) << error;
  EXPECT_TRUE(error.empty());
  EXPECT_EQ(t.nx, 3);
  EXPECT_EQ(t.ny, 2);
  EXPECT_DOUBLE_EQ(t.scale[0], 5.0);
  EXPECT_DOUBLE_EQ(t.scale[1], 7.0);
  EXPECT_DOUBLE_EQ(t.scale[2], 2.0);
  EXPECT_EQ(t.heightScale, 16384);
  EXPECT_EQ(t.baseHeight, 100);
  ASSERT_EQ(t.heights.size(), 6u);
  // metres = 2 * (100 + raw / 4), worked out by hand.
  const double expected[6] = {
    200.0, 202.0, 198.0, 400.0, 2.0 * (100 - 8192), 2.0 * (100 + 8191.75)
  };
  for (int k = 0; k < 6; ++k)
  {
    EXPECT_DOUBLE_EQ(t.heights[k], expected[k]) << "value " << k;
  }
}

TEST(TerroirTerragen, SizeOnlyMeansSquare)
{
  // Without XPTS/YPTS the grid is (SIZE+1)^2: SIZE 1 -> 2 x 2 = 4 values.
  Bytes b = Header();
  Tag(b, "SIZE");
  I16(b, 1);
  I16(b, 0);
  Tag(b, "ALTW");
  I16(b, 65536 / 4); // 16384
  I16(b, 0);
  for (int r : { 4, 8, 12, 16 })
  {
    I16(b, r);
  }
  terroir::io::TerragenTerrain t;
  std::string error;
  ASSERT_TRUE(terroir::io::ReadTerragen(b, t, error)) << error;
  EXPECT_EQ(t.nx, 2);
  EXPECT_EQ(t.ny, 2);
  // Default SCAL is 30 m: 30 * raw / 4.
  EXPECT_DOUBLE_EQ(t.heights[0], 30.0);
  EXPECT_DOUBLE_EQ(t.heights[3], 120.0);
}

TEST(TerroirTerragen, RejectsWrongMagic)
{
  Bytes b = SmallFile();
  b[0] = 'X';
  terroir::io::TerragenTerrain t;
  std::string error;
  EXPECT_FALSE(terroir::io::ReadTerragen(b, t, error));
  EXPECT_NE(error.find("not a Terragen file"), std::string::npos) << error;
  EXPECT_TRUE(t.heights.empty());
  EXPECT_FALSE(terroir::io::ReadTerragen(Bytes(5, 0), t, error));
}

TEST(TerroirTerragen, RejectsTruncatedChunk)
{
  Bytes b = Header();
  Tag(b, "SIZE");
  I16(b, 1); // padding missing
  terroir::io::TerragenTerrain t;
  std::string error;
  EXPECT_FALSE(terroir::io::ReadTerragen(b, t, error));
  EXPECT_NE(error.find("truncated 'SIZE' chunk at offset 16"), std::string::npos) << error;

  Bytes c = Header();
  c.push_back('S');
  c.push_back('I');
  c.push_back('Z');
  EXPECT_FALSE(terroir::io::ReadTerragen(c, t, error));
  EXPECT_NE(error.find("truncated chunk tag at offset 16"), std::string::npos) << error;
}

TEST(TerroirTerragen, RejectsShortALTW)
{
  Bytes b = SmallFile(true, false);
  b.resize(b.size() - 2); // one height missing
  terroir::io::TerragenTerrain t;
  std::string error;
  EXPECT_FALSE(terroir::io::ReadTerragen(b, t, error));
  EXPECT_NE(error.find("holds 5 heights, expected xpts*ypts = 3*2 = 6"), std::string::npos)
    << error;
}

TEST(TerroirTerragen, RejectsBadSizes)
{
  terroir::io::TerragenTerrain t;
  std::string error;
  // Negative XPTS.
  Bytes b = SmallFile();
  b[16 + 8 + 4] = 0xff;
  b[16 + 8 + 5] = 0xff; // XPTS = -1
  EXPECT_FALSE(terroir::io::ReadTerragen(b, t, error));
  EXPECT_NE(error.find("invalid XPTS -1"), std::string::npos) << error;
  // SIZE inconsistent with XPTS/YPTS.
  Bytes c = SmallFile();
  c[16 + 4] = 5; // SIZE 5, but min(3, 2) - 1 = 1
  EXPECT_FALSE(terroir::io::ReadTerragen(c, t, error));
  EXPECT_NE(error.find("SIZE 5 does not match"), std::string::npos) << error;
  // Zero SIZE.
  Bytes d = SmallFile();
  d[16 + 4] = 0;
  EXPECT_FALSE(terroir::io::ReadTerragen(d, t, error));
  EXPECT_NE(error.find("invalid SIZE 0"), std::string::npos) << error;
  // A huge YPTS (32767) with the 6-value ALTW: size does not match the file length.
  Bytes e = SmallFile();
  e[16 + 4] = 2; // SIZE = min(3, 32767) - 1
  e[16 + 16 + 4] = 0xff;
  e[16 + 16 + 5] = 0x7f;
  EXPECT_FALSE(terroir::io::ReadTerragen(e, t, error));
  EXPECT_NE(error.find("expected xpts*ypts"), std::string::npos) << error;
}

TEST(TerroirTerragen, RejectsUnknownChunk)
{
  Bytes b = Header();
  Tag(b, "SIZE");
  I16(b, 1);
  I16(b, 0);
  Tag(b, "ABCD");
  I16(b, 0);
  I16(b, 0);
  terroir::io::TerragenTerrain t;
  std::string error;
  EXPECT_FALSE(terroir::io::ReadTerragen(b, t, error));
  EXPECT_EQ(error, "unknown chunk 'ABCD' at offset 24");
}

TEST(TerroirTerragen, RejectsMissingALTW)
{
  Bytes b = Header();
  Tag(b, "SIZE");
  I16(b, 1);
  I16(b, 0);
  Tag(b, "EOF ");
  terroir::io::TerragenTerrain t;
  std::string error;
  EXPECT_FALSE(terroir::io::ReadTerragen(b, t, error));
  EXPECT_NE(error.find("missing ALTW"), std::string::npos) << error;
  EXPECT_FALSE(terroir::io::ReadTerragen(Header(), t, error));
  EXPECT_NE(error.find("missing SIZE and ALTW"), std::string::npos) << error;
}

TEST(TerroirTerragen, RejectsInvalidScale)
{
  Bytes b = Header();
  Tag(b, "SIZE");
  I16(b, 1);
  I16(b, 0);
  Tag(b, "SCAL");
  F32(b, 1.0f);
  F32(b, -1.0f);
  F32(b, 1.0f);
  terroir::io::TerragenTerrain t;
  std::string error;
  EXPECT_FALSE(terroir::io::ReadTerragen(b, t, error));
  EXPECT_NE(error.find("invalid SCAL component 1"), std::string::npos) << error;
}

TEST(TerroirTerragen, WriterLayoutMatchesSpecification)
{
  const float h[6] = { 10, 11, 12, 13, 14, 15 };
  Bytes bytes;
  std::string warning, error;
  ASSERT_TRUE(terroir::io::WriteTerragen(h, 3, 2, 2.0, 4.0, bytes, warning, error)) << error;
  EXPECT_TRUE(warning.empty());
  // 16 magic + SIZE 8 + XPTS 8 + YPTS 8 + SCAL 16 + ALTW 8 + 12 + EOF 4 = 80 bytes.
  ASSERT_EQ(bytes.size(), 80u);
  EXPECT_EQ(std::string(bytes.begin(), bytes.begin() + 16), "TERRAGENTERRAIN ");
  EXPECT_EQ(std::string(bytes.begin() + 16, bytes.begin() + 20), "SIZE");
  EXPECT_EQ(bytes[20], 1); // min(3, 2) - 1
  EXPECT_EQ(std::string(bytes.begin() + 24, bytes.begin() + 28), "XPTS");
  EXPECT_EQ(bytes[28], 3);
  EXPECT_EQ(std::string(bytes.begin() + 32, bytes.begin() + 36), "YPTS");
  EXPECT_EQ(bytes[36], 2);
  EXPECT_EQ(std::string(bytes.begin() + 40, bytes.begin() + 44), "SCAL");
  float sx, sy;
  std::memcpy(&sx, &bytes[44], 4);
  std::memcpy(&sy, &bytes[48], 4);
  EXPECT_EQ(sx, 2.0f);
  EXPECT_EQ(sy, 4.0f);
  EXPECT_EQ(std::string(bytes.begin() + 56, bytes.begin() + 60), "ALTW");
  EXPECT_EQ(std::string(bytes.end() - 4, bytes.end()), "EOF ");
}

TEST(TerroirTerragen, RoundTripWithinOnePartIn65536)
{
  // Synthetic grid: a tilted plane plus a bump, range about 900 m, spacing 10 m.
  const int nx = 37, ny = 23;
  std::vector<float> h(nx * ny);
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      h[j * nx + i] = static_cast<float>(1234.5 + 20.0 * i - 7.25 * j +
        300.0 * std::exp(-((i - 18) * (i - 18) + (j - 11) * (j - 11)) / 40.0));
    }
  }
  float lo = h[0], hi = h[0];
  for (float v : h)
  {
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  Bytes bytes;
  std::string warning, error;
  ASSERT_TRUE(terroir::io::WriteTerragen(h.data(), nx, ny, 10.0, 10.0, bytes, warning, error));
  terroir::io::TerragenTerrain t;
  ASSERT_TRUE(terroir::io::ReadTerragen(bytes, t, error)) << error;
  ASSERT_EQ(t.nx, nx);
  ASSERT_EQ(t.ny, ny);
  EXPECT_DOUBLE_EQ(t.scale[0], 10.0);
  const double tolerance = (hi - lo) / 65536.0;
  double worst = 0.0;
  for (int k = 0; k < nx * ny; ++k)
  {
    worst = std::max(worst, std::fabs(static_cast<double>(t.heights[k]) - h[k]));
  }
  EXPECT_LE(worst, tolerance) << "range " << hi - lo;
  EXPECT_GT(worst, 0.0); // 16-bit quantisation is not lossless on this grid
  // Rows are kept south first: the first value is the first value written.
  EXPECT_NEAR(t.heights[0], h[0], tolerance);
  EXPECT_NEAR(t.heights[nx * (ny - 1)], h[nx * (ny - 1)], tolerance);
}

TEST(TerroirTerragen, RoundTripLargeHeightsGrowsVerticalUnit)
{
  // With dz = spacing = 0.5 m, 20000 m does not fit int16 terrain units: dz must grow.
  const float h[4] = { -500.0f, 20000.0f, 8000.0f, 3.0f };
  Bytes bytes;
  std::string warning, error;
  ASSERT_TRUE(terroir::io::WriteTerragen(h, 2, 2, 0.5, 0.5, bytes, warning, error)) << error;
  terroir::io::TerragenTerrain t;
  ASSERT_TRUE(terroir::io::ReadTerragen(bytes, t, error)) << error;
  EXPECT_GT(t.scale[2], 0.5);
  for (int k = 0; k < 4; ++k)
  {
    EXPECT_NEAR(t.heights[k], h[k], 20500.0 / 65536.0 + t.scale[2] / 65534.0);
  }
}

TEST(TerroirTerragen, WriterReplacesNaNByMinimumAndWarns)
{
  const float nan = std::nanf("");
  const float h[4] = { 100.0f, nan, 300.0f, 200.0f };
  Bytes bytes;
  std::string warning, error;
  ASSERT_TRUE(terroir::io::WriteTerragen(h, 2, 2, 1.0, 1.0, bytes, warning, error));
  EXPECT_NE(warning.find("1 NaN"), std::string::npos) << warning;
  terroir::io::TerragenTerrain t;
  ASSERT_TRUE(terroir::io::ReadTerragen(bytes, t, error));
  EXPECT_NEAR(t.heights[1], 100.0, 200.0 / 65536.0);
}

TEST(TerroirTerragen, WriterRejectsBadInput)
{
  const float nan = std::nanf("");
  const float allNaN[4] = { nan, nan, nan, nan };
  Bytes bytes;
  std::string warning, error;
  EXPECT_FALSE(terroir::io::WriteTerragen(allNaN, 2, 2, 1.0, 1.0, bytes, warning, error));
  EXPECT_NE(error.find("NaN"), std::string::npos);
  const float h[4] = { 1, 2, 3, 4 };
  EXPECT_FALSE(terroir::io::WriteTerragen(h, 1, 4, 1.0, 1.0, bytes, warning, error));
  EXPECT_FALSE(terroir::io::WriteTerragen(h, 40000, 4, 1.0, 1.0, bytes, warning, error));
  EXPECT_FALSE(terroir::io::WriteTerragen(h, 2, 2, 0.0, 1.0, bytes, warning, error));
  EXPECT_TRUE(bytes.empty());
}

// Found by Testing/Fuzz/FuzzTerragen (regressions/Terragen/scal_beyond_reader_limit.ter): heights
// of ~5e11 m on a 1e7 m grid made the writer double the vertical unit past the largest SCAL the
// reader accepts, so it wrote a file it could not read back. Now the writer refuses.
TEST(TerroirTerragen, WriterNeverWritesAScaleItsReaderRefuses)
{
  const float huge[4] = { 4.915e11f, 1.63835e11f, 3.2767e11f, 3.27675e11f };
  Bytes bytes;
  std::string warning, error;
  EXPECT_FALSE(terroir::io::WriteTerragen(huge, 2, 2, 1.0e7, 1.0e7, bytes, warning, error));
  EXPECT_NE(error.find("out of the range Terragen can store"), std::string::npos) << error;
  EXPECT_TRUE(bytes.empty());
  // Spacings outside [1e-6, 1e7] m would be refused on reading as well.
  const float h[4] = { 1, 2, 3, 4 };
  EXPECT_FALSE(terroir::io::WriteTerragen(h, 2, 2, 2.0e7, 1.0, bytes, warning, error));
  EXPECT_FALSE(terroir::io::WriteTerragen(h, 2, 2, 1.0, 1.0e-9, bytes, warning, error));
  EXPECT_NE(error.find("1e-6 to 1e7"), std::string::npos) << error;
  // The largest heights a 1e7 m grid can hold still round-trip: dz stays 1e7 m.
  const float big[4] = { 1.5e11f, -1.5e11f, 0.0f, 1.0e11f };
  ASSERT_TRUE(terroir::io::WriteTerragen(big, 2, 2, 1.0e7, 1.0e7, bytes, warning, error)) << error;
  terroir::io::TerragenTerrain t;
  ASSERT_TRUE(terroir::io::ReadTerragen(bytes, t, error)) << error;
  EXPECT_FLOAT_EQ(t.scale[2], 1.0e7f);
  for (int k = 0; k < 4; ++k)
  {
    EXPECT_NEAR(t.heights[k], big[k], (3.0e11 + 1.0e7) / 131072.0 + 1e-6 * 1.5e11);
  }
}

TEST(TerroirTerragen, RejectsScaleOutsideStorableRange)
{
  Bytes prefix = Header();
  Tag(prefix, "SIZE");
  I16(prefix, 1);
  I16(prefix, 0);
  Tag(prefix, "SCAL");
  F32(prefix, 1.0f);
  F32(prefix, 1.0f);
  for (float bad : { 0.0f, -1.0f, 1.0e-9f, 2.0e7f, std::nanf("") })
  {
    Bytes b = prefix;
    F32(b, bad);
    terroir::io::TerragenTerrain t;
    std::string error;
    EXPECT_FALSE(terroir::io::ReadTerragen(b, t, error)) << bad;
    EXPECT_NE(error.find("invalid SCAL component 2"), std::string::npos) << error;
    EXPECT_NE(error.find("must be 1e-6 to 1e7 m"), std::string::npos) << error;
  }
}

// Found by Testing/Fuzz/FuzzTerragen: with a range small against dz, the error reaches
// range / 131068 + dz / 65534 (the bound on the writer's page), more than the
// (range + dz) / 131072 the header used to state. Worked example: dz = 30 m, heights in terrain
// units 0.125 .. 0.5 -> BaseHeight 0, HeightScale ceil(0.5 * 65536 / 32767) = 2, one raw step
// = 2 / 65536 * 30 m = 0.000916 m, so up to half a step (0.000458 m) is lost in rounding.
TEST(TerroirTerragen, QuantisationErrorWithinDocumentedBound)
{
  const float h[4] = { 3.75046f, 7.50092f, 11.2514f, 15.0018f };
  Bytes bytes;
  std::string warning, error;
  ASSERT_TRUE(terroir::io::WriteTerragen(h, 2, 2, 30.0, 30.0, bytes, warning, error)) << error;
  terroir::io::TerragenTerrain t;
  ASSERT_TRUE(terroir::io::ReadTerragen(bytes, t, error)) << error;
  EXPECT_EQ(t.heightScale, 2);
  EXPECT_EQ(t.baseHeight, 0);
  const double range = 15.0018 - 3.75046;
  double worst = 0.0;
  for (int k = 0; k < 4; ++k)
  {
    worst = std::max(worst, std::fabs(static_cast<double>(t.heights[k]) - h[k]));
  }
  EXPECT_LE(worst, range / 131068.0 + 30.0 / 65534.0);
  EXPECT_LE(worst, 0.5 * 2.0 / 65536.0 * 30.0 + 1e-6);
  EXPECT_GT(worst, (range + 30.0) / 131072.0); // the old statement was wrong
}

// Found by Testing/Fuzz/FuzzTerragen (regressions/Terragen/tiny_spacing_huge_heights.ter): a
// 3.8e-5 m grid with heights near -1.8e11 m; doubling dz from the spacing jumps from 5.2e6 m
// (too small) to 1.05e7 m (more than SCAL may hold). The writer now takes the smallest dz that
// fits instead of failing.
TEST(TerroirTerragen, WriterFindsAVerticalUnitWhenDoublingOvershoots)
{
  const float h[4] = { -1.82033e11f, -1.82029e11f, -1.82031e11f, -1.8203e11f };
  Bytes bytes;
  std::string warning, error;
  ASSERT_TRUE(terroir::io::WriteTerragen(h, 2, 2, 3.8147e-5, 10.0, bytes, warning, error)) << error;
  terroir::io::TerragenTerrain t;
  ASSERT_TRUE(terroir::io::ReadTerragen(bytes, t, error)) << error;
  EXPECT_LE(t.scale[2], terroir::io::kTerragenMaxScale);
  EXPECT_GT(t.scale[2], 1.82033e11 / 32767.0);
  for (int k = 0; k < 4; ++k)
  {
    EXPECT_NEAR(t.heights[k], h[k], 4.0e6 / 131068.0 + t.scale[2] / 65534.0 + 1e-6 * 1.83e11);
  }
}

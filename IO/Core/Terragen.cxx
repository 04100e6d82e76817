#include "Terragen.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace terroir
{
namespace io
{
namespace
{
const char kMagic[] = "TERRAGENTERRAIN ";
constexpr std::size_t kMagicSize = 16;

std::int16_t GetInt16(const std::uint8_t* p)
{
  return static_cast<std::int16_t>(static_cast<std::uint16_t>(p[0] | (p[1] << 8)));
}

std::uint32_t GetUInt32(const std::uint8_t* p)
{
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
    (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}

float GetFloat32(const std::uint8_t* p)
{
  const std::uint32_t u = GetUInt32(p);
  float f;
  std::memcpy(&f, &u, sizeof(f));
  return f;
}

void PutTag(std::vector<std::uint8_t>& out, const char* tag)
{
  out.insert(out.end(), tag, tag + 4);
}

void PutInt16(std::vector<std::uint8_t>& out, int v)
{
  const auto u = static_cast<std::uint16_t>(static_cast<std::int16_t>(v));
  out.push_back(static_cast<std::uint8_t>(u & 0xff));
  out.push_back(static_cast<std::uint8_t>(u >> 8));
}

void PutFloat32(std::vector<std::uint8_t>& out, float f)
{
  std::uint32_t u;
  std::memcpy(&u, &f, sizeof(u));
  for (int k = 0; k < 4; ++k)
  {
    out.push_back(static_cast<std::uint8_t>((u >> (8 * k)) & 0xff));
  }
}

std::string Printable(const std::uint8_t* p, std::size_t n)
{
  std::string s;
  for (std::size_t k = 0; k < n; ++k)
  {
    s += (p[k] >= 32 && p[k] < 127) ? static_cast<char>(p[k]) : '?';
  }
  return s;
}

bool Fail(std::string& error, TerragenTerrain& terrain, const std::string& message)
{
  error = message;
  terrain = TerragenTerrain();
  return false;
}

/// Where the reader is in the file, and what the chunks read so far said.
struct ChunkCursor
{
  const std::uint8_t* Bytes = nullptr;
  std::size_t Size = 0;
  std::size_t Offset = 0;
  int SizeChunk = -1;
  int XPoints = -1;
  int YPoints = -1;
  bool HaveAltw = false;
};

/// The chunk at the cursor: its tag, where it starts and how many bytes are left from there.
struct Chunk
{
  const std::uint8_t* Tag = nullptr;
  std::string TagName;
  std::size_t Offset = 0;
  std::size_t Remaining = 0;

  /// True when the file holds the tag plus `payload` bytes from here.
  bool Holds(std::size_t payload) const { return this->Remaining >= 4 + payload; }

  /// The message for a chunk too short for `payload` bytes.
  std::string Truncated(std::size_t payload) const
  {
    return "truncated '" + this->TagName + "' chunk at offset " + std::to_string(this->Offset) +
      " (needs " + std::to_string(4 + payload) + " bytes, " + std::to_string(this->Remaining) +
      " left)";
  }
};

/// True when bytes[offset, size) are all zero.
bool OnlyZerosFrom(const std::uint8_t* bytes, std::size_t offset, std::size_t size)
{
  bool zeros = true;
  for (std::size_t k = offset; k < size; ++k)
  {
    zeros = zeros && bytes[k] == 0;
  }
  return zeros;
}

/// Reads a SIZE, XPTS or YPTS chunk into the cursor; "" on success, else the problem.
std::string ReadSizeChunk(const Chunk& chunk, ChunkCursor& cursor)
{
  if (!chunk.Holds(4))
  {
    return chunk.Truncated(4);
  }
  const int v = GetInt16(chunk.Tag + 4);
  const int minimum = chunk.TagName == "SIZE" ? 1 : 2;
  if (v < minimum)
  {
    return "invalid " + chunk.TagName + " " + std::to_string(v) + " at offset " +
      std::to_string(chunk.Offset) + " (must be at least " + std::to_string(minimum) + ")";
  }
  (chunk.TagName == "SIZE" ? cursor.SizeChunk
                           : (chunk.TagName == "XPTS" ? cursor.XPoints : cursor.YPoints)) = v;
  cursor.Offset += 8;
  return std::string();
}

/// Reads a SCAL chunk into terrain.scale; "" on success, else the problem.
std::string ReadScaleChunk(const Chunk& chunk, ChunkCursor& cursor, TerragenTerrain& terrain)
{
  if (!chunk.Holds(12))
  {
    return chunk.Truncated(12);
  }
  for (int k = 0; k < 3; ++k)
  {
    const float s = GetFloat32(chunk.Tag + 4 + 4 * k);
    if (!(s >= kTerragenMinScale && s <= kTerragenMaxScale))
    {
      return "invalid SCAL component " + std::to_string(k) + " (" + std::to_string(s) +
        ") at offset " + std::to_string(chunk.Offset) + " (must be 1e-6 to 1e7 m)";
    }
    terrain.scale[k] = s;
  }
  cursor.Offset += 16;
  return std::string();
}

/// Reads an ALTW chunk (the heights) into the terrain; "" on success, else the problem.
std::string ReadHeightsChunk(const Chunk& chunk, ChunkCursor& cursor, TerragenTerrain& terrain)
{
  if (cursor.SizeChunk < 0)
  {
    return "ALTW chunk at offset " + std::to_string(chunk.Offset) + " comes before the SIZE chunk";
  }
  const int nx = cursor.XPoints > 0 ? cursor.XPoints : cursor.SizeChunk + 1;
  const int ny = cursor.YPoints > 0 ? cursor.YPoints : cursor.SizeChunk + 1;
  if (std::min(nx, ny) - 1 != cursor.SizeChunk)
  {
    return "SIZE " + std::to_string(cursor.SizeChunk) + " does not match XPTS " +
      std::to_string(nx) + " x YPTS " + std::to_string(ny) + " (expected min - 1)";
  }
  const std::size_t count = static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny);
  if (!chunk.Holds(4))
  {
    return chunk.Truncated(4);
  }
  if (chunk.Remaining - 8 < 2 * count)
  {
    return "ALTW chunk at offset " + std::to_string(chunk.Offset) + " holds " +
      std::to_string((chunk.Remaining - 8) / 2) +
      " heights, expected xpts*ypts = " + std::to_string(nx) + "*" + std::to_string(ny) + " = " +
      std::to_string(count) + " (file truncated or sizes wrong)";
  }
  terrain.nx = nx;
  terrain.ny = ny;
  terrain.heightScale = GetInt16(chunk.Tag + 4);
  terrain.baseHeight = GetInt16(chunk.Tag + 6);
  terrain.raw.resize(count);
  terrain.heights.resize(count);
  const std::uint8_t* p = chunk.Tag + 8;
  const double unitScale = terrain.heightScale / 65536.0;
  for (std::size_t k = 0; k < count; ++k)
  {
    const std::int16_t r = GetInt16(p + 2 * k);
    terrain.raw[k] = r;
    terrain.heights[k] =
      static_cast<float>(terrain.scale[2] * (terrain.baseHeight + r * unitScale));
  }
  cursor.HaveAltw = true;
  cursor.Offset += 8 + 2 * count;
  return std::string();
}

/// Reads the chunk at the cursor and moves past it; "" on success, else the problem. `end` is
/// set at the EOF chunk and at up to 3 bytes of zero padding after the last chunk.
std::string ReadChunk(ChunkCursor& cursor, TerragenTerrain& terrain, bool& end)
{
  const std::size_t remaining = cursor.Size - cursor.Offset;
  if (remaining < 4)
  {
    // Tolerate up to 3 bytes of zero padding after the last chunk.
    if (OnlyZerosFrom(cursor.Bytes, cursor.Offset, cursor.Size))
    {
      end = true;
      return std::string();
    }
    return "truncated chunk tag at offset " + std::to_string(cursor.Offset) + " (" +
      std::to_string(remaining) + " bytes left)";
  }
  Chunk chunk;
  chunk.Tag = cursor.Bytes + cursor.Offset;
  chunk.TagName = Printable(chunk.Tag, 4);
  chunk.Offset = cursor.Offset;
  chunk.Remaining = remaining;
  if (chunk.TagName == "EOF ")
  {
    end = true;
    return std::string();
  }
  if (chunk.TagName == "SIZE" || chunk.TagName == "XPTS" || chunk.TagName == "YPTS")
  {
    return ReadSizeChunk(chunk, cursor);
  }
  if (chunk.TagName == "SCAL")
  {
    return ReadScaleChunk(chunk, cursor, terrain);
  }
  if (chunk.TagName == "CRAD")
  {
    if (!chunk.Holds(4))
    {
      return chunk.Truncated(4);
    }
    terrain.planetRadiusKm = GetFloat32(chunk.Tag + 4);
    cursor.Offset += 8;
    return std::string();
  }
  if (chunk.TagName == "CRVM")
  {
    if (!chunk.Holds(4))
    {
      return chunk.Truncated(4);
    }
    terrain.curveMode = GetUInt32(chunk.Tag + 4);
    cursor.Offset += 8;
    return std::string();
  }
  if (chunk.TagName == "ALTW")
  {
    return ReadHeightsChunk(chunk, cursor, terrain);
  }
  return "unknown chunk '" + chunk.TagName + "' at offset " + std::to_string(chunk.Offset);
}
} // namespace

bool ReadTerragen(const std::uint8_t* bytes,
  std::size_t size,
  TerragenTerrain& terrain,
  std::string& error)
{
  terrain = TerragenTerrain();
  error.clear();
  if (!bytes || size < kMagicSize || std::memcmp(bytes, kMagic, kMagicSize) != 0)
  {
    return Fail(error, terrain, "not a Terragen file (missing 'TERRAGENTERRAIN ' header)");
  }
  ChunkCursor cursor;
  cursor.Bytes = bytes;
  cursor.Size = size;
  cursor.Offset = kMagicSize;
  bool end = false;
  while (!end && cursor.Offset < size)
  {
    const std::string problem = ReadChunk(cursor, terrain, end);
    if (!problem.empty())
    {
      return Fail(error, terrain, problem);
    }
  }
  if (!cursor.HaveAltw)
  {
    return Fail(error,
      terrain,
      cursor.SizeChunk < 0 ? "missing SIZE and ALTW chunks" : "missing ALTW chunk (no heights)");
  }
  return true;
}

bool ReadTerragen(const std::vector<std::uint8_t>& bytes,
  TerragenTerrain& terrain,
  std::string& error)
{
  return ReadTerragen(bytes.data(), bytes.size(), terrain, error);
}

bool WriteTerragen(const float* heights,
  int nx,
  int ny,
  double dx,
  double dy,
  std::vector<std::uint8_t>& bytes,
  std::string& warning,
  std::string& error)
{
  bytes.clear();
  warning.clear();
  error.clear();
  if (!heights || nx < 2 || ny < 2 || nx > 32767 || ny > 32767)
  {
    error = "cannot write a " + std::to_string(nx) + " x " + std::to_string(ny) +
      " grid as Terragen (2 to 32767 points per side)";
    return false;
  }
  // SCAL is stored as float32; the reader accepts what rounds into [min, max].
  auto storable = [](double v)
  {
    const float f = static_cast<float>(v);
    return f >= kTerragenMinScale && f <= kTerragenMaxScale;
  };
  if (!storable(dx) || !storable(dy))
  {
    error = "invalid spacing for Terragen (must be 1e-6 to 1e7 m)";
    return false;
  }
  const std::size_t count = static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny);
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  std::size_t nanCount = 0;
  for (std::size_t k = 0; k < count; ++k)
  {
    const double h = heights[k];
    if (!std::isfinite(h))
    {
      ++nanCount;
      continue;
    }
    lo = std::min(lo, h);
    hi = std::max(hi, h);
  }
  if (nanCount == count)
  {
    error = "every height is NaN: nothing to write";
    return false;
  }
  if (nanCount > 0)
  {
    warning = std::to_string(nanCount) + " NaN heights written as the minimum height " +
      std::to_string(lo) + " m";
  }
  // Vertical unit: dx (as GDAL writes), doubled until BaseHeight and HeightScale fit int16;
  // when doubling overshoots what SCAL may hold (the reader refuses more), the smallest unit
  // that fits, found from the centre and half range. Heights up to 1.6e11 m always fit.
  double dz = dx;
  int base = 0;
  int heightScale = 0;
  auto fits = [&](double unit)
  {
    const double mid = std::round(0.5 * (lo + hi) / unit);
    const double half = std::max(hi / unit - mid, mid - lo / unit);
    const double hs = std::max(1.0, std::ceil(half * 65536.0 / 32767.0));
    if (!storable(unit) || std::fabs(mid) > 32767.0 || hs > 32767.0)
    {
      return false;
    }
    dz = unit;
    base = static_cast<int>(mid);
    heightScale = static_cast<int>(hs);
    return true;
  };
  bool found = false;
  for (double unit = dx; !found && storable(unit); unit *= 2.0)
  {
    found = fits(unit);
  }
  double unit = std::max(
    dx, 1.0001 * std::max(std::fabs(0.5 * (lo + hi)) / 32766.0, 0.5 * (hi - lo) / 16382.0));
  for (int attempt = 0; !found && attempt < 64 && storable(unit); ++attempt, unit *= 1.01)
  {
    found = fits(unit);
  }
  if (!found)
  {
    error = "heights from " + std::to_string(lo) + " to " + std::to_string(hi) +
      " m are out of the range Terragen can store with this spacing";
    return false;
  }
  bytes.reserve(80 + 2 * count);
  bytes.insert(bytes.end(), kMagic, kMagic + kMagicSize);
  PutTag(bytes, "SIZE");
  PutInt16(bytes, std::min(nx, ny) - 1);
  PutInt16(bytes, 0);
  PutTag(bytes, "XPTS");
  PutInt16(bytes, nx);
  PutInt16(bytes, 0);
  PutTag(bytes, "YPTS");
  PutInt16(bytes, ny);
  PutInt16(bytes, 0);
  PutTag(bytes, "SCAL");
  PutFloat32(bytes, static_cast<float>(dx));
  PutFloat32(bytes, static_cast<float>(dy));
  PutFloat32(bytes, static_cast<float>(dz));
  // SCAL is stored as float32: quantise with the value a reader will see.
  const double dzStored = static_cast<float>(dz);
  PutTag(bytes, "ALTW");
  PutInt16(bytes, heightScale);
  PutInt16(bytes, base);
  const double toRaw = 65536.0 / heightScale;
  for (std::size_t k = 0; k < count; ++k)
  {
    const double h = std::isfinite(heights[k]) ? heights[k] : lo;
    const double r = std::round((h / dzStored - base) * toRaw);
    PutInt16(bytes, static_cast<int>(std::min(32767.0, std::max(-32768.0, r))));
  }
  PutTag(bytes, "EOF ");
  return true;
}

} // namespace io
} // namespace terroir

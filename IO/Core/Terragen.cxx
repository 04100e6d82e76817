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
  int sizeChunk = -1;
  int xpts = -1;
  int ypts = -1;
  bool haveAltw = false;
  std::size_t offset = kMagicSize;
  while (offset < size)
  {
    const std::size_t remaining = size - offset;
    if (remaining < 4)
    {
      // Tolerate up to 3 bytes of zero padding after the last chunk.
      bool zeros = true;
      for (std::size_t k = offset; k < size; ++k)
      {
        zeros = zeros && bytes[k] == 0;
      }
      if (zeros)
      {
        break;
      }
      return Fail(error,
        terrain,
        "truncated chunk tag at offset " + std::to_string(offset) + " (" +
          std::to_string(remaining) + " bytes left)");
    }
    const std::uint8_t* tag = bytes + offset;
    const std::string tagName = Printable(tag, 4);
    auto need = [&](std::size_t payload) { return remaining >= 4 + payload; };
    auto truncated = [&](std::size_t payload)
    {
      return Fail(error,
        terrain,
        "truncated '" + tagName + "' chunk at offset " + std::to_string(offset) + " (needs " +
          std::to_string(4 + payload) + " bytes, " + std::to_string(remaining) + " left)");
    };
    if (tagName == "EOF ")
    {
      break;
    }
    if (tagName == "SIZE" || tagName == "XPTS" || tagName == "YPTS")
    {
      if (!need(4))
      {
        return truncated(4);
      }
      const int v = GetInt16(tag + 4);
      const int minimum = tagName == "SIZE" ? 1 : 2;
      if (v < minimum)
      {
        return Fail(error,
          terrain,
          "invalid " + tagName + " " + std::to_string(v) + " at offset " + std::to_string(offset) +
            " (must be at least " + std::to_string(minimum) + ")");
      }
      (tagName == "SIZE" ? sizeChunk : (tagName == "XPTS" ? xpts : ypts)) = v;
      offset += 8;
    }
    else if (tagName == "SCAL")
    {
      if (!need(12))
      {
        return truncated(12);
      }
      for (int k = 0; k < 3; ++k)
      {
        const float s = GetFloat32(tag + 4 + 4 * k);
        if (!(s >= kTerragenMinScale && s <= kTerragenMaxScale))
        {
          return Fail(error,
            terrain,
            "invalid SCAL component " + std::to_string(k) + " (" + std::to_string(s) +
              ") at offset " + std::to_string(offset) + " (must be 1e-6 to 1e7 m)");
        }
        terrain.scale[k] = s;
      }
      offset += 16;
    }
    else if (tagName == "CRAD")
    {
      if (!need(4))
      {
        return truncated(4);
      }
      terrain.planetRadiusKm = GetFloat32(tag + 4);
      offset += 8;
    }
    else if (tagName == "CRVM")
    {
      if (!need(4))
      {
        return truncated(4);
      }
      terrain.curveMode = GetUInt32(tag + 4);
      offset += 8;
    }
    else if (tagName == "ALTW")
    {
      if (sizeChunk < 0)
      {
        return Fail(error,
          terrain,
          "ALTW chunk at offset " + std::to_string(offset) + " comes before the SIZE chunk");
      }
      const int nx = xpts > 0 ? xpts : sizeChunk + 1;
      const int ny = ypts > 0 ? ypts : sizeChunk + 1;
      if (std::min(nx, ny) - 1 != sizeChunk)
      {
        return Fail(error,
          terrain,
          "SIZE " + std::to_string(sizeChunk) + " does not match XPTS " + std::to_string(nx) +
            " x YPTS " + std::to_string(ny) + " (expected min - 1)");
      }
      const std::size_t count = static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny);
      if (!need(4))
      {
        return truncated(4);
      }
      if (remaining - 8 < 2 * count)
      {
        return Fail(error,
          terrain,
          "ALTW chunk at offset " + std::to_string(offset) + " holds " +
            std::to_string((remaining - 8) / 2) +
            " heights, expected xpts*ypts = " + std::to_string(nx) + "*" + std::to_string(ny) +
            " = " + std::to_string(count) + " (file truncated or sizes wrong)");
      }
      terrain.nx = nx;
      terrain.ny = ny;
      terrain.heightScale = GetInt16(tag + 4);
      terrain.baseHeight = GetInt16(tag + 6);
      terrain.raw.resize(count);
      terrain.heights.resize(count);
      const std::uint8_t* p = tag + 8;
      const double unitScale = terrain.heightScale / 65536.0;
      for (std::size_t k = 0; k < count; ++k)
      {
        const std::int16_t r = GetInt16(p + 2 * k);
        terrain.raw[k] = r;
        terrain.heights[k] =
          static_cast<float>(terrain.scale[2] * (terrain.baseHeight + r * unitScale));
      }
      haveAltw = true;
      offset += 8 + 2 * count;
    }
    else
    {
      return Fail(
        error, terrain, "unknown chunk '" + tagName + "' at offset " + std::to_string(offset));
    }
  }
  if (!haveAltw)
  {
    return Fail(error,
      terrain,
      sizeChunk < 0 ? "missing SIZE and ALTW chunks" : "missing ALTW chunk (no heights)");
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

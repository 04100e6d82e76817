#include "PointPatternFile.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <string_view>

namespace terroir
{
namespace io
{
namespace
{

enum Column
{
  ColumnX,
  ColumnY,
  ColumnZ,
  ColumnSpecies,
  ColumnZone,
  ColumnCount
};
const char* const ColumnNames[ColumnCount] = { "x", "y", "z", "species", "cluster_id" };

std::string_view Trim(std::string_view s)
{
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t'))
  {
    s.remove_prefix(1);
  }
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
  {
    s.remove_suffix(1);
  }
  return s;
}

/// At most 40 printable ASCII characters of `s`, others as '?', in quotes.
std::string Quote(std::string_view s)
{
  std::string out = "'";
  for (std::size_t k = 0; k < s.size() && k < 40; ++k)
  {
    const unsigned char c = static_cast<unsigned char>(s[k]);
    out += (c >= 0x20 && c < 0x7f) ? static_cast<char>(c) : '?';
  }
  return out + (s.size() > 40 ? "...'" : "'");
}

std::vector<std::string_view> Split(std::string_view line)
{
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  for (;;)
  {
    const std::size_t comma = line.find(',', start);
    fields.push_back(Trim(line.substr(start, comma - start)));
    if (comma == std::string_view::npos)
    {
      return fields;
    }
    start = comma + 1;
  }
}

bool Number(std::string_view field, double& value)
{
  if (!field.empty() && field.front() == '+')
  {
    field.remove_prefix(1);
  }
  const auto r = std::from_chars(field.data(), field.data() + field.size(), value);
  return r.ec == std::errc() && r.ptr == field.data() + field.size() && std::isfinite(value);
}

std::string At(std::size_t line)
{
  return "line " + std::to_string(line) + ": ";
}

/// Reads the header into `index` (column -> field position, -1 absent); "" or the problem.
std::string Header(const std::vector<std::string_view>& fields, int index[ColumnCount])
{
  for (int c = 0; c < ColumnCount; ++c)
  {
    index[c] = -1;
  }
  for (std::size_t f = 0; f < fields.size(); ++f)
  {
    std::string name(fields[f]);
    for (char& ch : name)
    {
      ch = (ch >= 'A' && ch <= 'Z') ? static_cast<char>(ch - 'A' + 'a') : ch;
    }
    int c = 0;
    while (c < ColumnCount && name != ColumnNames[c])
    {
      ++c;
    }
    if (c == ColumnCount)
    {
      return "unknown column " + Quote(fields[f]) + "; expected x, y, z, species, cluster_id";
    }
    if (index[c] >= 0)
    {
      return "column " + Quote(fields[f]) + " appears twice";
    }
    index[c] = static_cast<int>(f);
  }
  if (index[ColumnX] < 0 || index[ColumnY] < 0)
  {
    return "the header needs the columns x and y";
  }
  return std::string();
}

} // namespace

bool ParsePointPatternCsv(const char* bytes,
  std::size_t size,
  PointPatternTable& table,
  std::string& error)
{
  table = PointPatternTable();
  error.clear();
  if (size > kMaxPointPatternFileBytes)
  {
    error = "file larger than " + std::to_string(kMaxPointPatternFileBytes >> 20) + " MiB";
    return false;
  }
  std::string_view text(bytes, size);
  if (text.find('\0') != std::string_view::npos)
  {
    error = "not a text file (it holds a NUL byte)";
    return false;
  }
  if (text.substr(0, 3) == "\xEF\xBB\xBF")
  {
    text.remove_prefix(3);
  }
  PointPatternTable t;
  int index[ColumnCount];
  bool haveHeader = false;
  std::size_t fieldCount = 0;
  std::size_t lineNumber = 0;
  std::size_t start = 0;
  while (start <= text.size())
  {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    const std::string_view line = Trim(text.substr(start, end - start));
    ++lineNumber;
    start = end + 1;
    if (line.empty() || line.front() == '#')
    {
      continue;
    }
    const std::vector<std::string_view> fields = Split(line);
    if (!haveHeader)
    {
      const std::string problem = Header(fields, index);
      if (!problem.empty())
      {
        error = At(lineNumber) + problem;
        return false;
      }
      haveHeader = true;
      fieldCount = fields.size();
      t.hasZ = index[ColumnZ] >= 0;
      continue;
    }
    if (fields.size() != fieldCount)
    {
      error = At(lineNumber) + std::to_string(fields.size()) + " fields, the header has " +
        std::to_string(fieldCount);
      return false;
    }
    if (t.x.size() == kMaxPointPatternPoints)
    {
      error = At(lineNumber) + "more than " + std::to_string(kMaxPointPatternPoints) + " plants";
      return false;
    }
    double v[ColumnCount] = { 0.0, 0.0, 0.0, 0.0, -1.0 };
    for (int c = 0; c < ColumnCount; ++c)
    {
      if (index[c] < 0)
      {
        continue;
      }
      if (!Number(fields[static_cast<std::size_t>(index[c])], v[c]))
      {
        error = At(lineNumber) + ColumnNames[c] + " " +
          Quote(fields[static_cast<std::size_t>(index[c])]) + " is not a finite number";
        return false;
      }
    }
    if (index[ColumnSpecies] >= 0 &&
      !(v[ColumnSpecies] >= 0.0 && v[ColumnSpecies] <= 63.0 &&
        v[ColumnSpecies] == std::floor(v[ColumnSpecies])))
    {
      error = At(lineNumber) + "species " +
        Quote(fields[static_cast<std::size_t>(index[ColumnSpecies])]) +
        " is not a whole number in 0..63";
      return false;
    }
    if (index[ColumnZone] >= 0 &&
      !(v[ColumnZone] >= -1.0 && v[ColumnZone] <= 1e9 &&
        v[ColumnZone] == std::floor(v[ColumnZone])))
    {
      error = At(lineNumber) + "cluster_id " +
        Quote(fields[static_cast<std::size_t>(index[ColumnZone])]) +
        " is not a whole number in -1..1000000000";
      return false;
    }
    t.x.push_back(v[ColumnX]);
    t.y.push_back(v[ColumnY]);
    if (t.hasZ)
    {
      t.z.push_back(v[ColumnZ]);
    }
    if (index[ColumnSpecies] >= 0)
    {
      t.species.push_back(static_cast<int>(v[ColumnSpecies]));
    }
    if (index[ColumnZone] >= 0)
    {
      t.zone.push_back(static_cast<int>(v[ColumnZone]));
    }
  }
  if (!haveHeader)
  {
    error = "no header (a line such as x,y,species)";
    return false;
  }
  if (t.x.empty())
  {
    error = "no plants after the header";
    return false;
  }
  table = std::move(t);
  return true;
}

std::string FormatPointPatternCsv(const PointPatternTable& t)
{
  std::string out = "x,y";
  out += t.hasZ ? ",z" : "";
  out += t.species.empty() ? "" : ",species";
  out += t.zone.empty() ? "" : ",cluster_id";
  out += "\n";
  char number[64];
  for (std::size_t k = 0; k < t.x.size(); ++k)
  {
    std::snprintf(number, sizeof(number), "%.17g,%.17g", t.x[k], t.y[k]);
    out += number;
    if (t.hasZ)
    {
      std::snprintf(number, sizeof(number), ",%.17g", t.z[k]);
      out += number;
    }
    if (!t.species.empty())
    {
      out += "," + std::to_string(t.species[k]);
    }
    if (!t.zone.empty())
    {
      out += "," + std::to_string(t.zone[k]);
    }
    out += "\n";
  }
  return out;
}

} // namespace io
} // namespace terroir

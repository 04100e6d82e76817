#include "ClimateTable.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <set>
#include <string_view>
#include <system_error>
#include <vector>

namespace terroir
{
namespace io
{
namespace
{
using Json = nlohmann::json;

constexpr int kMaxJsonDepth = 16;
constexpr std::size_t kMaxQuoted = 40; // longest user text echoed in a message

/// Month names, January first; the abbreviations are their first three letters.
const char* const kMonthNames[12] = { "january",
  "february",
  "march",
  "april",
  "may",
  "june",
  "july",
  "august",
  "september",
  "october",
  "november",
  "december" };

/// "Jan" ... "Dec".
std::string MonthAbbreviation(int m)
{
  std::string s(kMonthNames[m], 3);
  s[0] = static_cast<char>(s[0] - 'a' + 'A');
  return s;
}

/// The three value series, in the order of the ClimateTable members.
struct Quantity
{
  const char* name;
  double minimum;
  double maximum;
};
constexpr int kQuantityCount = 3;
constexpr int kPrecipitation = 0;
constexpr int kIntensity = 1;
const Quantity kQuantities[kQuantityCount] = {
  { "precipitation_mm", 0.0, 10000.0 }, // wettest month on record: about 9300 mm
  { "intensity_mm_per_h", 0.0, 500.0 },
  { "temperature_c", -90.0, 60.0 }, // records: -89.2 (Vostok), 56.7 (Death Valley)
};
const char kValueNames[] = "precipitation_mm, intensity_mm_per_h, temperature_c";

bool& Has(ClimateTable& table, int q)
{
  return q == 0 ? table.hasPrecipitation : (q == 1 ? table.hasIntensity : table.hasTemperature);
}

std::array<double, 12>& Values(ClimateTable& table, int q)
{
  return q == 0 ? table.precipitationMm : (q == 1 ? table.intensityMmPerHour : table.temperatureC);
}

/// Shortest round-trip text of a finite double, in plain notation when that stays short.
std::string FormatNumber(double v)
{
  char buffer[64];
  const double magnitude = std::fabs(v);
  const bool plain = magnitude == 0.0 || (magnitude >= 1e-6 && magnitude < 1e15);
  const auto result = plain
    ? std::to_chars(buffer, buffer + sizeof(buffer), v, std::chars_format::fixed)
    : std::to_chars(buffer, buffer + sizeof(buffer), v);
  return result.ec == std::errc() ? std::string(buffer, result.ptr) : std::string("?");
}

/// Length of the well-formed UTF-8 sequence starting at text[k] (RFC 3629), 0 if there is none.
std::size_t Utf8Length(std::string_view text, std::size_t k)
{
  const auto c = static_cast<unsigned char>(text[k]);
  if (c < 0x80)
  {
    return 1;
  }
  std::size_t n = 0;
  unsigned char low = 0x80; // range of the second byte (no overlong forms, no surrogates)
  unsigned char high = 0xBF;
  if (c >= 0xC2 && c <= 0xDF)
  {
    n = 2;
  }
  else if (c >= 0xE0 && c <= 0xEF)
  {
    n = 3;
    low = c == 0xE0 ? 0xA0 : 0x80;
    high = c == 0xED ? 0x9F : 0xBF;
  }
  else if (c >= 0xF0 && c <= 0xF4)
  {
    n = 4;
    low = c == 0xF0 ? 0x90 : 0x80;
    high = c == 0xF4 ? 0x8F : 0xBF;
  }
  if (n == 0 || text.size() - k < n)
  {
    return 0;
  }
  for (std::size_t i = 1; i < n; ++i)
  {
    const auto b = static_cast<unsigned char>(text[k + i]);
    if (b < (i == 1 ? low : 0x80) || b > (i == 1 ? high : 0xBF))
    {
      return 0;
    }
  }
  return n;
}

/// User text made safe for a one-line message (and for a JSON report): control characters
/// and bytes that are not UTF-8 become '?', and text longer than `maximum` bytes is cut.
std::string Sanitize(std::string_view text, std::size_t maximum)
{
  std::string s;
  for (std::size_t k = 0; k < text.size();)
  {
    if (s.size() >= maximum)
    {
      s += "...";
      break;
    }
    const std::size_t n = Utf8Length(text, k);
    const auto c = static_cast<unsigned char>(text[k]);
    const bool control = c < 32 || c == 127 ||
      (n == 2 && c == 0xC2 && static_cast<unsigned char>(text[k + 1]) < 0xA0); // C1 controls
    if (n == 0 || control)
    {
      s += '?';
      k += n == 0 ? 1 : n;
    }
    else
    {
      s.append(text, k, n);
      k += n;
    }
  }
  return s;
}

std::string Quote(std::string_view text)
{
  return "'" + Sanitize(text, kMaxQuoted) + "'";
}

/// "" when v is inside the range of quantity q, else "must be >= min" / "must be <= max".
std::string RangeProblem(int q, double v)
{
  if (v < kQuantities[q].minimum)
  {
    return "must be >= " + FormatNumber(kQuantities[q].minimum);
  }
  if (v > kQuantities[q].maximum)
  {
    return "must be <= " + FormatNumber(kQuantities[q].maximum);
  }
  return std::string();
}

bool IsBlank(char c)
{
  return c == ' ' || c == '\t';
}

std::string_view Trim(std::string_view s)
{
  while (!s.empty() && IsBlank(s.front()))
  {
    s.remove_prefix(1);
  }
  while (!s.empty() && IsBlank(s.back()))
  {
    s.remove_suffix(1);
  }
  return s;
}

std::string Lower(std::string_view s)
{
  std::string out(s);
  for (char& c : out)
  {
    if (c >= 'A' && c <= 'Z')
    {
      c = static_cast<char>(c - 'A' + 'a');
    }
  }
  return out;
}

/// 0..11 for "1".."12", "jan", "January"... (case-insensitive), -1 otherwise.
int ParseMonth(std::string_view s)
{
  int number = 0;
  const auto result = std::from_chars(s.data(), s.data() + s.size(), number);
  if (result.ec == std::errc() && result.ptr == s.data() + s.size())
  {
    return number >= 1 && number <= 12 ? number - 1 : -1;
  }
  const std::string lower = Lower(s);
  for (int m = 0; m < 12; ++m)
  {
    if (lower == kMonthNames[m] || lower == std::string_view(kMonthNames[m], 3))
    {
      return m;
    }
  }
  return -1;
}

/// Parses a whole CSV field as a finite decimal number; "" on success, else the problem.
std::string ParseNumber(std::string_view s, double& v)
{
  std::string_view digits = s;
  if (digits.size() > 1 && digits.front() == '+' && digits[1] != '-' && digits[1] != '+')
  {
    digits.remove_prefix(1); // from_chars takes no '+', people write "+12.5"
  }
  const char* end = digits.data() + digits.size();
  const auto result = std::from_chars(digits.data(), end, v, std::chars_format::general);
  if (result.ec == std::errc::result_out_of_range && result.ptr == end)
  {
    return "too large or too small for a double";
  }
  if (result.ec != std::errc() || result.ptr != end)
  {
    return "not a number";
  }
  if (!std::isfinite(v))
  {
    return "not a finite number";
  }
  v += 0.0; // -0 -> +0
  return std::string();
}

// ------------------------------------------------------------------------------------------
// CSV

/// The column index of the month in CsvState::columns (value columns hold a quantity index).
constexpr int kMonthColumn = -1;

/// What ParseCsv has read so far.
struct CsvState
{
  std::vector<int> columns; // per field: kMonthColumn or a quantity index
  bool haveHeader = false;
  int headerLine = 0;
  int monthLine[12] = {}; // line of each month's row, 0 = not seen yet
  int rows = 0;
};

/// Splits a line (no end of line, not blank) into trimmed comma-separated fields, refusing
/// carriage returns and double quotes; `where` is the message prefix "line N: ".
bool SplitCsvLine(std::string_view line,
  const std::string& where,
  std::vector<std::string_view>& fields,
  std::string& error)
{
  if (line.find('\r') != std::string_view::npos)
  {
    error = where + "carriage return inside a line (lines must end with \\n or \\r\\n)";
    return false;
  }
  fields.clear();
  for (std::size_t start = 0;;)
  {
    const std::size_t comma = line.find(',', start);
    fields.push_back(Trim(line.substr(start, comma - start)));
    if (comma == std::string_view::npos)
    {
      break;
    }
    start = comma + 1;
  }
  for (std::size_t f = 0; f < fields.size(); ++f)
  {
    if (fields[f].find('"') != std::string_view::npos)
    {
      error = where + "field " + std::to_string(f + 1) + " " + Quote(fields[f]) +
        " contains a double quote; quoting is not supported";
      return false;
    }
  }
  return true;
}

/// Reads the header's column names into state.columns and marks the quantities present.
bool ParseCsvHeader(const std::vector<std::string_view>& fields,
  const std::string& where,
  CsvState& state,
  ClimateTable& table,
  std::string& error)
{
  const std::string expected =
    "; expected month, precipitation_mm, intensity_mm_per_h, temperature_c";
  for (std::size_t f = 0; f < fields.size(); ++f)
  {
    const std::string name = Lower(fields[f]);
    int column = -2;
    if (name == "month")
    {
      column = kMonthColumn;
    }
    for (int q = 0; q < kQuantityCount; ++q)
    {
      if (name == kQuantities[q].name)
      {
        column = q;
      }
    }
    if (fields[f].empty())
    {
      error = where + "empty column name (column " + std::to_string(f + 1) + ")" + expected;
      return false;
    }
    if (column == -2)
    {
      error = where + "unknown column " + Quote(fields[f]) + expected;
      return false;
    }
    for (int previous : state.columns)
    {
      if (previous == column)
      {
        error = where + "duplicate column '" + name + "'";
        return false;
      }
    }
    state.columns.push_back(column);
  }
  bool haveMonth = false;
  for (int column : state.columns)
  {
    haveMonth = haveMonth || column == kMonthColumn;
    if (column != kMonthColumn)
    {
      Has(table, column) = true;
    }
  }
  if (!haveMonth)
  {
    error = where + "missing column 'month'";
    return false;
  }
  if (state.columns.size() < 2)
  {
    error = where + "no value column; expected at least one of " + kValueNames;
    return false;
  }
  return true;
}

/// Checks that a data row may follow the rows read so far and has one non-empty value per
/// column.
bool CheckCsvRowShape(const std::vector<std::string_view>& fields,
  const std::string& where,
  const CsvState& state,
  std::string& error)
{
  const std::vector<int>& columns = state.columns;
  if (state.rows == 12)
  {
    error = where + "more than 12 data rows (one per month)";
    return false;
  }
  if (fields.size() != columns.size())
  {
    std::string names;
    for (int column : columns)
    {
      names += (names.empty() ? "" : ", ") +
        std::string(column == kMonthColumn ? "month" : kQuantities[column].name);
    }
    error = where + std::to_string(fields.size()) + " fields, expected " +
      std::to_string(columns.size()) + " (" + names + ")";
    if (fields.size() > columns.size())
    {
      error += "; decimals take '.', not ','";
    }
    return false;
  }
  for (std::size_t f = 0; f < fields.size(); ++f)
  {
    if (fields[f].empty())
    {
      error = where + "empty value in column " +
        (columns[f] == kMonthColumn ? "month" : kQuantities[columns[f]].name);
      return false;
    }
  }
  return true;
}

/// Reads the month of a data row (0..11) and records it as seen on `lineNumber`.
bool ParseCsvRowMonth(const std::vector<std::string_view>& fields,
  const std::string& where,
  int lineNumber,
  CsvState& state,
  int& month,
  std::string& error)
{
  month = -1;
  for (std::size_t f = 0; f < fields.size(); ++f)
  {
    if (state.columns[f] == kMonthColumn)
    {
      month = ParseMonth(fields[f]);
      if (month < 0)
      {
        error = where + "unknown month " + Quote(fields[f]) +
          "; expected 1 to 12, Jan to Dec or January to December";
        return false;
      }
    }
  }
  if (state.monthLine[month] != 0)
  {
    error = where + MonthAbbreviation(month) + " given twice (first on line " +
      std::to_string(state.monthLine[month]) + ")";
    return false;
  }
  state.monthLine[month] = lineNumber;
  ++state.rows;
  return true;
}

/// Reads the values of a data row for `month` into the table, each checked for its range.
bool ParseCsvRowValues(const std::vector<std::string_view>& fields,
  const std::string& where,
  const CsvState& state,
  int month,
  ClimateTable& table,
  std::string& error)
{
  const std::string monthName = MonthAbbreviation(month);
  std::string_view valueText[kQuantityCount]; // as written, for messages
  for (std::size_t f = 0; f < fields.size(); ++f)
  {
    const int q = state.columns[f];
    if (q == kMonthColumn)
    {
      continue;
    }
    const std::string subject =
      where + kQuantities[q].name + " for " + monthName + " is " + Quote(fields[f]) + ", ";
    double v = 0.0;
    const std::string numberProblem = ParseNumber(fields[f], v);
    if (!numberProblem.empty())
    {
      error = subject + numberProblem;
      return false;
    }
    const std::string rangeProblem = RangeProblem(q, v);
    if (!rangeProblem.empty())
    {
      error = where + kQuantities[q].name + " for " + monthName + " is " +
        Sanitize(fields[f], kMaxQuoted) + ", " + rangeProblem;
      return false;
    }
    Values(table, q)[month] = v;
    valueText[q] = fields[f];
  }
  if (table.hasPrecipitation && table.hasIntensity && table.precipitationMm[month] > 0.0 &&
    !(table.intensityMmPerHour[month] > 0.0))
  {
    error = where + "precipitation_mm for " + monthName + " is " +
      Sanitize(valueText[kPrecipitation], kMaxQuoted) + " but intensity_mm_per_h is " +
      Sanitize(valueText[kIntensity], kMaxQuoted) + ": rain needs a positive intensity";
    return false;
  }
  return true;
}

/// Checks, after the last line, that there was a header and a row for every month.
bool CheckCsvComplete(const CsvState& state, std::string& error)
{
  if (!state.haveHeader)
  {
    error = std::string("no header line; expected month and at least one of ") + kValueNames;
    return false;
  }
  if (state.rows == 0)
  {
    error = "no data rows after the header on line " + std::to_string(state.headerLine) +
      "; expected one row per month";
    return false;
  }
  std::string missing;
  int missingCount = 0;
  for (int m = 0; m < 12; ++m)
  {
    if (state.monthLine[m] == 0)
    {
      missing += (missing.empty() ? "" : ", ") + MonthAbbreviation(m);
      ++missingCount;
    }
  }
  if (missingCount > 0)
  {
    error = (missingCount == 1 ? "missing month: " : "missing months: ") + missing;
    return false;
  }
  return true;
}

bool ParseCsv(std::string_view text, ClimateTable& table, std::string& error)
{
  CsvState state;
  int lineNumber = 0;
  std::vector<std::string_view> fields;
  std::size_t position = 0;
  while (position < text.size())
  {
    const std::size_t eol = text.find('\n', position);
    const std::size_t lineEnd = eol == std::string_view::npos ? text.size() : eol;
    std::string_view line = text.substr(position, lineEnd - position);
    position = lineEnd + 1;
    ++lineNumber;
    if (!line.empty() && line.back() == '\r')
    {
      line.remove_suffix(1);
    }
    const std::string_view trimmed = Trim(line);
    if (trimmed.empty() || trimmed.front() == '#')
    {
      continue;
    }
    const std::string where = "line " + std::to_string(lineNumber) + ": ";
    if (!SplitCsvLine(line, where, fields, error))
    {
      return false;
    }
    if (!state.haveHeader)
    {
      if (!ParseCsvHeader(fields, where, state, table, error))
      {
        return false;
      }
      state.haveHeader = true;
      state.headerLine = lineNumber;
      continue;
    }
    int month = -1;
    if (!CheckCsvRowShape(fields, where, state, error) ||
      !ParseCsvRowMonth(fields, where, lineNumber, state, month, error) ||
      !ParseCsvRowValues(fields, where, state, month, table, error))
    {
      return false;
    }
  }
  return CheckCsvComplete(state, error);
}

// ------------------------------------------------------------------------------------------
// JSON

/// Deepest nesting of [ and { outside strings; stops counting past `limit`.
int JsonDepth(std::string_view text, int limit)
{
  int depth = 0;
  int deepest = 0;
  bool inString = false;
  for (std::size_t k = 0; k < text.size(); ++k)
  {
    const char c = text[k];
    if (inString)
    {
      if (c == '\\')
      {
        ++k;
      }
      else if (c == '"')
      {
        inString = false;
      }
    }
    else if (c == '"')
    {
      inString = true;
    }
    else if (c == '[' || c == '{')
    {
      deepest = std::max(deepest, ++depth);
      if (deepest > limit)
      {
        break;
      }
    }
    else if ((c == ']' || c == '}') && depth > 0)
    {
      --depth;
    }
  }
  return deepest;
}

/// "a string", "an object", "a number"... for messages.
std::string Described(const Json& value)
{
  const std::string type = value.type_name();
  if (value.is_null())
  {
    return "null";
  }
  return (type[0] == 'a' || type[0] == 'o' ? "an " : "a ") + type;
}

bool ParseJson(std::string_view text, ClimateTable& table, std::string& error)
{
  if (JsonDepth(text, kMaxJsonDepth) > kMaxJsonDepth)
  {
    error =
      "JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels: not a climate table";
    return false;
  }
  // nlohmann keeps the last of duplicate keys: catch them while parsing.
  std::set<std::string> seen;
  std::string duplicate;
  const Json::parser_callback_t callback = [&](int depth, Json::parse_event_t event, Json& parsed)
  {
    if (event == Json::parse_event_t::key && depth == 1 && parsed.is_string() &&
      !seen.insert(parsed.get_ref<const std::string&>()).second && duplicate.empty())
    {
      duplicate = parsed.get_ref<const std::string&>();
    }
    return true;
  };
  Json document;
  try
  {
    document = Json::parse(text.begin(), text.end(), callback);
  }
  catch (const Json::exception& e)
  {
    // "[json.exception.parse_error.101] parse error at line 1, column 2: ..."
    std::string_view what = e.what();
    const std::size_t bracket = what.find("] ");
    if (what.substr(0, 1) == "[" && bracket != std::string_view::npos)
    {
      what.remove_prefix(bracket + 2);
    }
    error = "invalid JSON: " + Sanitize(what, 200);
    return false;
  }
  if (!document.is_object())
  {
    error = "JSON top level must be an object, not " + Described(document);
    return false;
  }
  if (!duplicate.empty())
  {
    error = "duplicate key " + Quote(duplicate);
    return false;
  }
  for (const auto& item : document.items())
  {
    const std::string& key = item.key();
    bool known = key == "description" || key == "source";
    for (int q = 0; q < kQuantityCount; ++q)
    {
      known = known || key == kQuantities[q].name;
    }
    if (!known)
    {
      error = "unknown key " + Quote(key) + "; expected " + kValueNames + ", description, source";
      return false;
    }
    if ((key == "description" || key == "source") && !item.value().is_string())
    {
      error = key + " must be a string, not " + Described(item.value());
      return false;
    }
  }
  for (int q = 0; q < kQuantityCount; ++q)
  {
    const auto found = document.find(kQuantities[q].name);
    if (found == document.end())
    {
      continue;
    }
    const std::string name = kQuantities[q].name;
    if (!found->is_array())
    {
      error = name + " must be an array of 12 numbers, not " + Described(*found);
      return false;
    }
    if (found->size() != 12)
    {
      error =
        name + " has " + std::to_string(found->size()) + " values, expected 12 (January first)";
      return false;
    }
    for (int m = 0; m < 12; ++m)
    {
      const Json& value = (*found)[m];
      const std::string subject =
        name + "[" + std::to_string(m) + "] (" + MonthAbbreviation(m) + ") is ";
      if (!value.is_number())
      {
        error = subject + Described(value) + ", expected a number";
        return false;
      }
      const double v = value.get<double>() + 0.0; // -0 -> +0
      if (!std::isfinite(v))
      {
        error = subject + "not a finite number";
        return false;
      }
      const std::string rangeProblem = RangeProblem(q, v);
      if (!rangeProblem.empty())
      {
        error = subject + FormatNumber(v) + ", " + rangeProblem;
        return false;
      }
      Values(table, q)[m] = v;
    }
    Has(table, q) = true;
  }
  if (!table.hasPrecipitation && !table.hasIntensity && !table.hasTemperature)
  {
    error = std::string("no climate values; expected at least one of ") + kValueNames;
    return false;
  }
  if (table.hasPrecipitation && table.hasIntensity)
  {
    for (int m = 0; m < 12; ++m)
    {
      if (table.precipitationMm[m] > 0.0 && !(table.intensityMmPerHour[m] > 0.0))
      {
        const std::string index = "[" + std::to_string(m) + "]";
        error = "precipitation_mm" + index + " (" + MonthAbbreviation(m) + ") is " +
          FormatNumber(table.precipitationMm[m]) + " but intensity_mm_per_h" + index + " is " +
          FormatNumber(table.intensityMmPerHour[m]) + ": rain needs a positive intensity";
        return false;
      }
    }
  }
  return true;
}
} // namespace

bool ParseClimateTable(const char* bytes, std::size_t size, ClimateTable& table, std::string& error)
{
  table = ClimateTable();
  error.clear();
  if (!bytes)
  {
    size = 0;
  }
  if (size > kMaxClimateFileBytes)
  {
    error = "larger than 1 MiB: not a climate table";
    return false;
  }
  if (size == 0)
  {
    error = "empty file";
    return false;
  }
  if (std::memchr(bytes, 0, size) != nullptr)
  {
    error = "binary data, not a climate table";
    return false;
  }
  std::string_view text(bytes, size);
  if (text.substr(0, 3) == "\xEF\xBB\xBF")
  {
    text.remove_prefix(3);
  }
  const std::size_t first = text.find_first_not_of(" \t\r\n");
  if (first == std::string_view::npos)
  {
    error = "empty file";
    return false;
  }
  ClimateTable parsed;
  const bool ok =
    text[first] == '{' ? ParseJson(text, parsed, error) : ParseCsv(text, parsed, error);
  if (ok)
  {
    table = parsed;
  }
  return ok;
}

bool ReadClimateTableFile(const std::string& path, ClimateTable& table, std::string& error)
{
  table = ClimateTable();
  error.clear();
  const auto fail = [&](const std::string& problem)
  {
    error = path + ": " + problem;
    return false;
  };
  std::error_code code;
  const std::filesystem::file_status status = std::filesystem::status(path, code);
  if (status.type() == std::filesystem::file_type::not_found ||
    code == std::errc::no_such_file_or_directory)
  {
    return fail("no such file");
  }
  if (code)
  {
    return fail("cannot be read (" + code.message() + ")");
  }
  if (std::filesystem::is_directory(status))
  {
    return fail("is a directory, not a file");
  }
  if (std::filesystem::is_regular_file(status) &&
    std::filesystem::file_size(path, code) > kMaxClimateFileBytes && !code)
  {
    return fail("larger than 1 MiB: not a climate table");
  }
  errno = 0;
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (!file)
  {
    return fail("cannot be read (" + std::generic_category().message(errno) + ")");
  }
  // Read at most one byte more than the limit (the size of a pipe or device is not known).
  std::string bytes;
  char buffer[65536];
  while (bytes.size() <= kMaxClimateFileBytes)
  {
    const std::size_t count = std::fread(buffer, 1, sizeof(buffer), file);
    bytes.append(buffer, count);
    if (count < sizeof(buffer))
    {
      break;
    }
  }
  const int readErrno = errno;
  const bool readFailed = std::ferror(file) != 0;
  std::fclose(file);
  if (readFailed)
  {
    return fail("cannot be read (" + std::generic_category().message(readErrno) + ")");
  }
  std::string problem;
  if (!ParseClimateTable(bytes.data(), bytes.size(), table, problem))
  {
    return fail(problem);
  }
  return true;
}

} // namespace io
} // namespace terroir

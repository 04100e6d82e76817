#include "TerroirViewerScript.h"

#include "NumberText.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace terroir
{
namespace viewer
{
namespace
{
/// Key names accepted besides single printable characters (X key symbols).
const char* const NamedKeys[] = { "space",
  "Return",
  "Escape",
  "Tab",
  "BackSpace",
  "Delete",
  "Left",
  "Right",
  "Up",
  "Down",
  "Prior",
  "Next",
  "Home",
  "End",
  "plus",
  "minus",
  "bracketleft",
  "bracketright",
  "F1",
  "F2",
  "F3",
  "F4",
  "F5",
  "F6",
  "F7",
  "F8",
  "F9",
  "F10",
  "F11",
  "F12" };

/// A verb with a fixed number of numbers in [lo, hi] (integers when `integer`).
struct NumericVerb
{
  const char* Verb;
  double Lo;
  double Hi;
  bool Integer;
};

const NumericVerb NumericVerbs[] = {
  { "latitude", -90.0, 90.0, false },
  { "longitude", -180.0, 180.0, false },
  { "month", 1.0, 12.0, true },
  { "hour", 0.0, 24.0, false },
  { "orientation", -360.0, 360.0, false },
  { "clusters", 1.0, 64.0, true },
  { "lake-depth", 0.0, 10000.0, false },
  { "brush-size", 0.0, 1000.0, false },
  { "brush-rate", 0.0, 1000.0, false },
  { "slope-threshold", 0.0, 90.0, false },
  { "sensitivity", 0.01, 100.0, false },
  { "move-speed", 0.01, 100.0, false },
  { "flow-iterations", 1.0, 1000000.0, true },
  { "flow-water", 0.0, 100000.0, false },
  { "flow-rain-rate", 0.001, 1000.0, false },
  { "flow-stop", 0.0, 1.0, false },
  { "flow-balance", 0.0001, 0.999, false },
  { "sea", -12000.0, 10000.0, false },
  { "coldest", -90.0, 60.0, false },
  { "warmest", -90.0, 60.0, false },
  { "lapse-rate", 0.0, 20.0, false },
  { "erosion-amount", -100.0, 100.0, false },
  { "erosion-rain", 0.0, 10000.0, false },
  { "wait-erosion", 1.0, 1e9, true },
};

/// A whole token as a finite number; false otherwise.
bool ToNumber(const std::string& token, double& value)
{
  if (token.empty())
  {
    return false;
  }
  errno = 0;
  char* end = nullptr;
  value = std::strtod(token.c_str(), &end);
  return end == token.c_str() + token.size() && errno == 0 && std::isfinite(value);
}

/// One line of a script being parsed: its words, the action they make, and where a problem
/// is reported ("NAME:LINE: problem").
struct ScriptLine
{
  const std::string& Name;
  int Number; ///< 1-based line
  int Width;
  int Height;
  std::vector<ViewerAction>& Actions; ///< cleared on failure
  std::string& Error;
  std::vector<std::string> W; ///< the words, the verb first
  ViewerAction A;
  std::size_t Args = 0; ///< words after the verb

  /// Sets Error to the problem on this line, clears Actions; returns false.
  bool Fail(const std::string& problem)
  {
    this->Error = this->Name + ":" + std::to_string(this->Number) + ": " + problem;
    this->Actions.clear();
    return false;
  }

  /// Between lo and hi arguments, else fails with the verb's usage.
  bool WantArgs(std::size_t lo, std::size_t hi, const char* usage)
  {
    const std::size_t args = this->Args;
    if (args < lo || args > hi)
    {
      return this->Fail("'" + this->A.Verb + "' takes " + usage + ", got " + std::to_string(args) +
        " argument" + (args == 1 ? "" : "s"));
    }
    return true;
  }

  /// Numbers at W[first .. first+count), each in [lo, hi] (x and y: within the window).
  bool Numbers(std::size_t first,
    std::size_t count,
    double lo,
    double hi,
    bool integer,
    const char* what)
  {
    const std::vector<std::string>& w = this->W;
    ViewerAction& a = this->A;
    for (std::size_t k = first; k < first + count; ++k)
    {
      double v = 0.0;
      if (!ToNumber(w[k], v))
      {
        return this->Fail("'" + a.Verb + "': " + what + " '" + w[k] + "' is not a finite number");
      }
      if (integer && v != std::floor(v))
      {
        return this->Fail("'" + a.Verb + "': " + what + " " + w[k] + " is not a whole number");
      }
      const double top = std::strcmp(what, "x") == 0 ? this->Width - 1
        : std::strcmp(what, "y") == 0                ? this->Height - 1
                                                     : hi;
      if (v < lo || v > top)
      {
        return this->Fail("'" + a.Verb + "': " + what + " " + w[k] + " is outside [" +
          terroir::NumberText(lo, 6) + ", " + terroir::NumberText(top, 6) + "]");
      }
      a.Numbers.push_back(v);
    }
    return true;
  }

  /// Trailing modifiers of click and drag.
  bool Modifiers(std::size_t first)
  {
    const std::vector<std::string>& w = this->W;
    ViewerAction& a = this->A;
    for (std::size_t k = first; k < w.size(); ++k)
    {
      if (w[k] == "ctrl")
      {
        a.Control = true;
      }
      else if (w[k] == "shift")
      {
        a.Shift = true;
      }
      else
      {
        return this->Fail("'" + a.Verb + "': unknown modifier '" + w[k] + "' (ctrl or shift)");
      }
    }
    return true;
  }
};

/// overlay NAME.
bool ParseOverlay(ScriptLine& s)
{
  const std::vector<std::string>& w = s.W;
  ViewerAction& a = s.A;
  ViewerOverlay overlay;
  if (!s.WantArgs(1, 1, "one overlay name"))
  {
    return false;
  }
  if (!OverlayFromName(w[1], overlay))
  {
    return s.Fail("unknown overlay '" + w[1] + "' (" + OverlayNameList() + ")");
  }
  a.Text = w[1];
  return true;
}

/// style, tool, view, button, flow-mode, card, erosion and erosion-brush: one word of a fixed
/// list.
bool ParseChoice(ScriptLine& s)
{
  const std::vector<std::string>& w = s.W;
  ViewerAction& a = s.A;
  const std::vector<std::string> allowed = a.Verb == "style"
    ? std::vector<std::string>{ "terrain", "first-person" }
    : a.Verb == "tool"          ? std::vector<std::string>{ "navigate", "lake", "brush", "sea" }
    : a.Verb == "button"        ? ViewerButtonNames()
    : a.Verb == "flow-mode"     ? std::vector<std::string>{ "pulse", "rivers" }
    : a.Verb == "card"          ? std::vector<std::string>{ "none", "climate", "settings" }
    : a.Verb == "erosion"       ? std::vector<std::string>{ "start", "stop", "keep" }
    : a.Verb == "erosion-brush" ? std::vector<std::string>{ "soil", "water", "vegetation" }
    : a.Verb == "texture"       ? std::vector<std::string>{ "on", "off" }
                                : std::vector<std::string>{ "relief", "map" };
  std::string list;
  for (const std::string& name : allowed)
  {
    list += (list.empty() ? "" : ", ") + name;
  }
  if (!s.WantArgs(1, 1, ("one of " + list).c_str()))
  {
    return false;
  }
  if (std::find(allowed.begin(), allowed.end(), w[1]) == allowed.end())
  {
    return s.Fail("'" + a.Verb + "': unknown value '" + w[1] + "' (" + list + ")");
  }
  a.Text = w[1];
  return true;
}

/// click X Y [ctrl] [shift].
bool ParseClick(ScriptLine& s)
{
  if (s.Args < 2)
  {
    return s.Fail("'click' takes X Y [ctrl] [shift]");
  }
  if (!s.Numbers(1, 1, 0.0, 0.0, true, "x") || !s.Numbers(2, 1, 0.0, 0.0, true, "y") ||
    !s.Modifiers(3))
  {
    return false;
  }
  return true;
}

/// drag X0 Y0 X1 Y1 [ctrl] [shift].
bool ParseDrag(ScriptLine& s)
{
  if (s.Args < 4)
  {
    return s.Fail("'drag' takes X0 Y0 X1 Y1 [ctrl] [shift]");
  }
  if (!s.Numbers(1, 1, 0.0, 0.0, true, "x") || !s.Numbers(2, 1, 0.0, 0.0, true, "y") ||
    !s.Numbers(3, 1, 0.0, 0.0, true, "x") || !s.Numbers(4, 1, 0.0, 0.0, true, "y") ||
    !s.Modifiers(5))
  {
    return false;
  }
  return true;
}

/// wheel NOTCHES (negative: backward, not 0).
bool ParseWheel(ScriptLine& s)
{
  if (!s.WantArgs(1, 1, "one whole number of notches (negative: backward)") ||
    !s.Numbers(1, 1, -100.0, 100.0, true, "notches"))
  {
    return false;
  }
  if (s.A.Numbers[0] == 0.0)
  {
    return s.Fail("'wheel': 0 notches does nothing");
  }
  return true;
}

/// key [ctrl+][shift+]KEY.
bool ParseKey(ScriptLine& s)
{
  const std::vector<std::string>& w = s.W;
  ViewerAction& a = s.A;
  KeySpec key;
  std::string why;
  if (!s.WantArgs(1, 1, "one key (e.g. ctrl+z)"))
  {
    return false;
  }
  if (!ParseKeySpec(w[1], key, why))
  {
    return s.Fail(why);
  }
  a.Text = key.Symbol;
  a.Control = key.Control;
  a.Shift = key.Shift;
  return true;
}

/// screenshot FILE.png.
bool ParseScreenshot(ScriptLine& s)
{
  const std::vector<std::string>& w = s.W;
  ViewerAction& a = s.A;
  if (!s.WantArgs(1, 1, "one file name ending in .png"))
  {
    return false;
  }
  const std::string& f = w[1];
  std::string lower = f;
  std::transform(lower.begin(),
    lower.end(),
    lower.begin(),
    [](char c) { return static_cast<char>(std::tolower(static_cast<unsigned char>(c))); });
  if (lower.size() <= 4 || lower.compare(lower.size() - 4, 4, ".png") != 0)
  {
    return s.Fail("'screenshot': '" + f + "' does not end in .png");
  }
  a.Text = f;
  return true;
}

/// cluster-weight FEATURE W: one of kViewerClusterFeatures and a weight in [0, 1000].
bool ParseClusterWeight(ScriptLine& s)
{
  std::string list;
  for (const ViewerClusterFeature& f : kViewerClusterFeatures)
  {
    list += (list.empty() ? "" : ", ") + std::string(f.Name);
  }
  if (!s.WantArgs(2, 2, ("a feature (" + list + ") and a weight").c_str()))
  {
    return false;
  }
  if (ClusterFeatureIndex(s.W[1]) < 0)
  {
    return s.Fail("'cluster-weight': unknown feature '" + s.W[1] + "' (" + list + ")");
  }
  s.A.Text = s.W[1];
  return s.Numbers(2, 1, 0.0, 1000.0, false, "weight");
}

/// precipitation MONTH MM, intensity MONTH MM/H.
bool ParseMonthly(ScriptLine& s)
{
  const bool quantity = s.A.Verb == "precipitation";
  return s.WantArgs(2, 2, quantity ? "a month 1..12 and millimetres" : "a month 1..12 and mm/h") &&
    s.Numbers(1, 1, 1.0, 12.0, true, "month") &&
    s.Numbers(2, 1, 0.0, quantity ? 10000.0 : 500.0, false, "value");
}

/// climate-load FILE, climate-save FILE.
bool ParseFileVerb(ScriptLine& s)
{
  if (!s.WantArgs(1, 1, "one file name"))
  {
    return false;
  }
  s.A.Text = s.W[1];
  return true;
}

/// table-csv FILE.csv.
bool ParseTableCsv(ScriptLine& s)
{
  if (!s.WantArgs(1, 1, "one file name ending in .csv"))
  {
    return false;
  }
  const std::string& f = s.W[1];
  if (f.size() <= 4 || f.compare(f.size() - 4, 4, ".csv") != 0)
  {
    return s.Fail("'table-csv': '" + f + "' does not end in .csv");
  }
  s.A.Text = f;
  return true;
}

/// The arguments of the line's verb into its action; false with the error on a bad line.
bool ParseArguments(ScriptLine& s)
{
  const ViewerAction& a = s.A;
  const NumericVerb* numeric = nullptr;
  for (const NumericVerb& v : NumericVerbs)
  {
    if (a.Verb == v.Verb)
    {
      numeric = &v;
    }
  }
  if (numeric)
  {
    if (!s.WantArgs(1, 1, "one number") ||
      !s.Numbers(1, 1, numeric->Lo, numeric->Hi, numeric->Integer, "value"))
    {
      return false;
    }
  }
  else if (a.Verb == "overlay")
  {
    return ParseOverlay(s);
  }
  else if (a.Verb == "style" || a.Verb == "tool" || a.Verb == "view" || a.Verb == "button" ||
    a.Verb == "flow-mode" || a.Verb == "card" || a.Verb == "erosion" || a.Verb == "erosion-brush" ||
    a.Verb == "texture")
  {
    return ParseChoice(s);
  }
  else if (a.Verb == "click")
  {
    return ParseClick(s);
  }
  else if (a.Verb == "drag")
  {
    return ParseDrag(s);
  }
  else if (a.Verb == "wheel")
  {
    return ParseWheel(s);
  }
  else if (a.Verb == "key")
  {
    return ParseKey(s);
  }
  else if (a.Verb == "screenshot")
  {
    return ParseScreenshot(s);
  }
  else if (a.Verb == "cluster-weight")
  {
    return ParseClusterWeight(s);
  }
  else if (a.Verb == "table-csv")
  {
    return ParseTableCsv(s);
  }
  else if (a.Verb == "precipitation" || a.Verb == "intensity")
  {
    return ParseMonthly(s);
  }
  else if (a.Verb == "climate-load" || a.Verb == "climate-save")
  {
    return ParseFileVerb(s);
  }
  else if (a.Verb == "wait" || a.Verb == "quit" || a.Verb == "flow" || a.Verb == "undo" ||
    a.Verb == "camera" || a.Verb == "state")
  {
    if (!s.WantArgs(0, 0, "no argument"))
    {
      return false;
    }
  }
  else
  {
    return s.Fail("unknown action '" + a.Verb +
      "' (overlay, latitude, longitude, month, hour, orientation, clusters, lake-depth, "
      "brush-size, brush-rate, slope-threshold, sensitivity, move-speed, style, tool, view, "
      "button, card, click, "
      "drag, wheel, key, flow, undo, wait, camera, state, screenshot, cluster-weight, table-csv, "
      "flow-mode, flow-iterations, flow-water, flow-rain-rate, flow-stop, flow-balance, sea, "
      "coldest, warmest, lapse-rate, precipitation, intensity, climate-load, climate-save, "
      "erosion, erosion-brush, erosion-amount, erosion-rain, wait-erosion, texture, quit)");
  }
  return true;
}
} // namespace

int ClusterFeatureIndex(const std::string& name)
{
  for (std::size_t k = 0; k < kViewerClusterFeatureCount; ++k)
  {
    if (name == kViewerClusterFeatures[k].Name)
    {
      return static_cast<int>(k);
    }
  }
  return -1;
}

const char* OverlayName(ViewerOverlay overlay)
{
  const int k = static_cast<int>(overlay);
  return k >= 0 && k < static_cast<int>(ViewerOverlay::Count) ? kViewerOverlays[k].Name : "";
}

const char* OverlayTitle(ViewerOverlay overlay)
{
  const int k = static_cast<int>(overlay);
  return k >= 0 && k < static_cast<int>(ViewerOverlay::Count) ? kViewerOverlays[k].Title : "";
}

bool OverlayFromName(const std::string& name, ViewerOverlay& overlay)
{
  for (int k = 0; k < static_cast<int>(ViewerOverlay::Count); ++k)
  {
    if (name == kViewerOverlays[k].Name)
    {
      overlay = static_cast<ViewerOverlay>(k);
      return true;
    }
  }
  return false;
}

const std::vector<std::string>& ViewerButtonNames()
{
  static const std::vector<std::string> names = { "navigate",
    "lake",
    "brush",
    "fill",
    "slope-rule",
    "flow",
    "undo",
    "table",
    "climate",
    "settings" };
  return names;
}

std::string OverlayNameList()
{
  std::string list;
  for (const ViewerOverlayInfo& o : kViewerOverlays)
  {
    list += (list.empty() ? "" : ", ") + std::string(o.Name);
  }
  return list;
}

bool ParseKeySpec(const std::string& text, KeySpec& key, std::string& why)
{
  key = KeySpec();
  std::string rest = text;
  for (;;)
  {
    if (rest.rfind("ctrl+", 0) == 0 && rest.size() > 5)
    {
      key.Control = true;
      rest = rest.substr(5);
    }
    else if (rest.rfind("shift+", 0) == 0 && rest.size() > 6)
    {
      key.Shift = true;
      rest = rest.substr(6);
    }
    else
    {
      break;
    }
  }
  const bool printable =
    rest.size() == 1 && std::isgraph(static_cast<unsigned char>(rest[0])) && rest[0] != '#';
  const bool named = std::find_if(std::begin(NamedKeys),
                       std::end(NamedKeys),
                       [&rest](const char* k) { return rest == k; }) != std::end(NamedKeys);
  if (!printable && !named)
  {
    why = "unknown key '" + text +
      "' (a character, or space, Return, Escape, Tab, Left, Right, Up, Down, F1..F12, with "
      "optional ctrl+ and shift+)";
    return false;
  }
  key.Symbol = rest;
  return true;
}

//------------------------------------------------------------------------------
bool ParseViewerScript(const std::string& text,
  const std::string& name,
  int width,
  int height,
  std::vector<ViewerAction>& actions,
  std::string& error)
{
  actions.clear();
  std::istringstream lines(text);
  std::string line;
  int number = 0;
  while (std::getline(lines, line))
  {
    ++number;
    const std::size_t hash = line.find('#');
    if (hash != std::string::npos)
    {
      line.resize(hash);
    }
    std::istringstream words(line);
    ScriptLine s{ name, number, width, height, actions, error, {}, {}, 0 };
    for (std::string word; words >> word;)
    {
      s.W.push_back(word);
    }
    if (s.W.empty())
    {
      continue;
    }
    s.A.Verb = s.W[0];
    s.A.Line = number;
    s.Args = s.W.size() - 1;
    if (!ParseArguments(s))
    {
      return false;
    }
    actions.push_back(s.A);
  }
  return true;
}

bool ReadViewerScript(const std::string& path,
  int width,
  int height,
  std::vector<ViewerAction>& actions,
  std::string& error)
{
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
  {
    error = path + ": is a folder, not a script";
    return false;
  }
  std::ifstream file(path, std::ios::binary);
  if (!file)
  {
    error = path + ": cannot read (" + std::strerror(errno) + ")";
    return false;
  }
  std::ostringstream text;
  text << file.rdbuf();
  if (file.bad())
  {
    error = path + ": cannot read (" + std::strerror(errno) + ")";
    return false;
  }
  const std::string content = text.str();
  if (content.find('\0') != std::string::npos)
  {
    error = path + ": not a text file";
    return false;
  }
  return ParseViewerScript(content, path, width, height, actions, error);
}

} // namespace viewer
} // namespace terroir

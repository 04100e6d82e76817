/**
 * @file TerroirViewerScript.h
 * @brief The action scripts of `terroir view --script FILE` and the viewer's overlay names,
 * parsed without VTK (so that a bad script is refused before any window opens, and the parser
 * can be unit-tested: Testing/Unit/TestViewerScript.cxx).
 *
 * One action per line; `#` starts a comment; blank lines are skipped; words are separated by
 * blanks. Display positions are pixels from the top-left corner of the window (as in the
 * screenshots), checked against the window size. See Documentation/Viewer.md for the verbs.
 */
#ifndef TerroirViewerScript_h
#define TerroirViewerScript_h

#include <cstddef>
#include <string>
#include <vector>

namespace terroir
{
namespace viewer
{

/// The overlays of the viewer, in the order of the number keys 0..8.
enum class ViewerOverlay
{
  None = 0,
  Slope,
  Illumination,
  SunHours,
  Temperature,
  Humidity,
  Water,
  Clusters,
  WeightedHumidity,
  Count
};

/// Each overlay's script and command-line name and its title in the window's list, in the order
/// of ViewerOverlay. Adding an overlay: its value above, its row here, its recipe in
/// TerroirViewerSessionOverlays.cxx (TestViewerSession checks that every overlay has one).
struct ViewerOverlayInfo
{
  const char* Name;
  const char* Title;
};
inline constexpr ViewerOverlayInfo kViewerOverlays[] = {
  { "none", "No overlay" },
  { "slope", "Slope" },
  { "illumination", "Sun and shadow" },
  { "sun-hours", "Hours of sun" },
  { "temperature", "Temperature" },
  { "humidity", "Soil humidity" },
  { "water", "Water" },
  { "clusters", "Clusters" },
  { "weighted-humidity", "Weighted humidity" },
};
static_assert(sizeof(kViewerOverlays) / sizeof(kViewerOverlays[0]) ==
    static_cast<std::size_t>(ViewerOverlay::Count),
  "one row of kViewerOverlays per ViewerOverlay");

/// The features of the clusters overlay: the script's name (`cluster-weight NAME W`), the
/// point array vtkTerroirKMeans clusters on, and Long (2016)'s weight (vtkTerroirKMeans's
/// defaults). ViewerParameters::ClusterWeights holds one weight per row, in this order.
struct ViewerClusterFeature
{
  const char* Name;
  const char* ArrayName;
  double DefaultWeight;
};
inline constexpr ViewerClusterFeature kViewerClusterFeatures[] = {
  { "slope", "Slope", 1.0 },
  { "temperature", "Temperature", 1.0 },
  { "sun", "IlluminationHours", 1.0 },
  { "humidity", "WeightedSoilHumidity", 0.1 },
};
inline constexpr std::size_t kViewerClusterFeatureCount =
  sizeof(kViewerClusterFeatures) / sizeof(kViewerClusterFeatures[0]);

/// Index in kViewerClusterFeatures of a feature's script name; -1 when unknown.
int ClusterFeatureIndex(const std::string& name);

/// Script and command-line name of an overlay ("none", "slope", "illumination", "sun-hours",
/// "temperature", "humidity", "water", "clusters", "weighted-humidity").
const char* OverlayName(ViewerOverlay overlay);
/// Title shown in the window's list ("Slope", "Sun and shadow", ...).
const char* OverlayTitle(ViewerOverlay overlay);
/// Parses a name of OverlayName; false when unknown.
bool OverlayFromName(const std::string& name, ViewerOverlay& overlay);
/// "none, slope, ..." for messages.
std::string OverlayNameList();

/// The window's on-screen buttons, as the script's `button` names them: navigate, lake,
/// brush (tools), fill, slope-rule (infiltration), flow (run the water flow), undo, table
/// (show or hide the cluster table).
const std::vector<std::string>& ViewerButtonNames();

/// One parsed line of a script.
struct ViewerAction
{
  std::string Verb;            ///< overlay, latitude, click, key, ... (Documentation/Viewer.md)
  std::vector<double> Numbers; ///< numeric arguments, checked
  std::string Text;            ///< overlay name, key, file, style, tool, view
  bool Control = false;        ///< click, drag: `ctrl` given; key: `ctrl+`
  bool Shift = false;          ///< click, drag: `shift` given; key: `shift+`
  int Line = 0;                ///< 1-based line in the file
};

/// A key as the script names it: modifiers and the X key symbol ("z", "1", "space", "Escape").
struct KeySpec
{
  bool Control = false;
  bool Shift = false;
  std::string Symbol;
};

/// Parses "ctrl+shift+z", "w", "F1", "space"... False with a reason when the key is unknown.
bool ParseKeySpec(const std::string& text, KeySpec& key, std::string& why);

/// Parses a whole script. `name` prefixes the error ("FILE:LINE: problem"); positions must lie
/// in [0, width) x [0, height). Returns false with `error` at the first bad line.
bool ParseViewerScript(const std::string& text,
  const std::string& name,
  int width,
  int height,
  std::vector<ViewerAction>& actions,
  std::string& error);

/// Reads and parses FILE. A file that cannot be read gives "FILE: cannot read (reason)".
bool ReadViewerScript(const std::string& path,
  int width,
  int height,
  std::vector<ViewerAction>& actions,
  std::string& error);

} // namespace viewer
} // namespace terroir

#endif

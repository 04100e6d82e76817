/**
 * @file TerroirViewerPlugin.h
 * @brief Interface of the `terroir view` window module (terroir-viewer.so, loaded with dlopen
 * like the overlay module, so that the other commands do not load VTK's rendering libraries).
 */
#ifndef TerroirViewerPlugin_h
#define TerroirViewerPlugin_h

#include <string>
#include <vector>

class vtkImageData;
class vtkPolyData;

namespace terroir
{
namespace app
{
struct CommandLine;
}
namespace viewer
{
struct ViewerAction;
}
}

/// What `terroir view` hands to the window module.
struct TerroirViewerRequest
{
  vtkImageData* Terrain = nullptr;                                     ///< the DEM, read
  std::string TerrainName;                                             ///< for the window title
  const terroir::app::CommandLine* Line = nullptr;                     ///< the parsed command line
  const std::vector<terroir::viewer::ViewerAction>* Actions = nullptr; ///< --script, or null
  vtkPolyData* Curves = nullptr; ///< --curves, read (lines with the feature-curve arrays), or null
  std::string Error;             ///< set on failure (one line)
};

/// Opens the window, replays the actions, then (without `quit`) lets the user work. Returns the
/// exit status: 0, or 1 with `Error` set.
using TerroirRunViewerFunction = int (*)(TerroirViewerRequest* request);

#define TERROIR_VIEWER_PLUGIN_NAME "terroir-viewer.so"
#define TERROIR_VIEWER_PLUGIN_SYMBOL "terroir_run_viewer"
#define TERROIR_VIEWER_PLUGIN_EXPORT __attribute__((visibility("default")))

#endif

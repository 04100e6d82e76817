// `terroir view`: the interactive window (Documentation/Viewer.md)
#include "TerroirCommands.h"

#include "TerroirApp.h"
#include "TerroirCommandSupport.h"
#include "TerroirViewerPlugin.h"
#include "TerroirViewerScript.h"

#include "vtkImageData.h"
#include "vtkPolyData.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace terroir
{
namespace app
{
/// GenerateFeatures.cxx: the curves of a GeoJSON or .vtp file, checked (Failure naming the file).
vtkSmartPointer<vtkPolyData> ReadFeatureCurves(const std::string& path);

namespace
{
/// `terroir view`: checks the script (one line naming FILE:LINE and the problem) before any
/// other work, reads the DEM, and hands both to the window module (TerroirViewerWindow.cxx).
int View(const terroir::app::CommandLine& c)
{
  std::vector<terroir::viewer::ViewerAction> actions;
  if (!c.View.Script.empty())
  {
    std::string error;
    if (!terroir::viewer::ReadViewerScript(
          c.View.Script, c.View.Width, c.View.Height, actions, error))
    {
      throw Failure(error);
    }
  }
  std::error_code ec;
  if (!c.View.ScreenshotDir.empty() && !fs::is_directory(c.View.ScreenshotDir, ec))
  {
    throw Failure(c.View.ScreenshotDir + ": screenshot folder does not exist");
  }
  if (!HaveDisplay())
  {
    throw Failure("terroir view needs an X display (DISPLAY unset); run under 'xvfb-run -a'");
  }
  const std::string dem = c.Input.empty() ? terroir::app::DefaultDEM() : c.Input;
  if (c.Input.empty())
  {
    std::cerr << "terroir view: no DEM given; opening the bundled Sagehen Creek DEM (" << dem
              << ")\n";
  }
  // --curves: read and checked before the DEM, so a bad file is the one error.
  vtkSmartPointer<vtkPolyData> curves;
  if (!c.View.Curves.empty())
  {
    curves = ReadFeatureCurves(c.View.Curves);
  }
  vtkSmartPointer<vtkImageData> terrain = terroir::app::ReadTerrain(dem, c.AllowNetwork, c.ZUnit);
  auto run = reinterpret_cast<TerroirRunViewerFunction>(LoadPluginSymbol(TERROIR_VIEWER_PLUGIN_NAME,
    TERROIR_VIEWER_PLUGIN_SYMBOL,
    "TERROIR_VIEWER_PLUGIN",
    "terroir view"));
  TerroirViewerRequest request;
  request.Terrain = terrain;
  request.TerrainName = dem;
  request.Line = &c;
  request.Actions = c.View.Script.empty() ? nullptr : &actions;
  request.Curves = curves;
  if (run(&request) != 0)
  {
    throw Failure(request.Error.empty() ? "terroir view failed" : request.Error);
  }
  return 0;
}
} // namespace

int CommandView(const CommandLine& c)
{
  return View(c);
}

} // namespace app
} // namespace terroir

// The PNG overlay writer of the `terroir` program, built as a loadable module.
//
// Rendering pulls in VTK's OpenGL, X11 and FreeType libraries, whose symbol relocation costs
// every process 10-20 ms at start-up (measured: `terroir --help` 50 ms linked with them, 35 ms
// without). Only `terroir run` draws overlays, so the program loads this module with dlopen()
// when it needs it, and the other commands start as fast as gdaldem does.
#include "TerroirOverlayPlugin.h"

#include "vtkImageData.h"
#include "vtkSmartPointer.h"
#include "vtkTerroirOverlayView.h"

#include <string>

namespace
{
/// The calling thread's view, kept between overlays (see TerroirOverlayPlugin.h).
vtkSmartPointer<vtkTerroirOverlayView>& ThreadView()
{
  static thread_local vtkSmartPointer<vtkTerroirOverlayView> view;
  return view;
}
} // namespace

extern "C" TERROIR_OVERLAY_PLUGIN_EXPORT const char* terroir_write_overlay(vtkImageData* image,
  const char* array,
  int component,
  const char* preset,
  const char* title,
  const char* path,
  int map)
{
  static thread_local std::string error;
  vtkSmartPointer<vtkTerroirOverlayView>& view = ThreadView();
  if (!view)
  {
    view = vtkSmartPointer<vtkTerroirOverlayView>::New();
  }
  view->SetInputData(image);
  view->SetArrayName(array);
  view->SetArrayComponent(component);
  view->SetPreset(preset);
  view->SetTitle(title);
  if (map)
  {
    view->SetModeToMap();
  }
  else
  {
    view->SetModeToRelief();
  }
  view->SetShowLegend(true);
  const bool written = view->WritePNG(path);
  view->SetInputData(nullptr); // the view keeps its surface, not the caller's terrain
  if (written)
  {
    return nullptr;
  }
  error = view->GetLastError();
  if (error.empty())
  {
    error = "rendering failed";
  }
  return error.c_str();
}

extern "C" TERROIR_OVERLAY_PLUGIN_EXPORT void terroir_release_overlays()
{
  ThreadView() = nullptr;
}

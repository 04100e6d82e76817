/**
 * @file TerroirOverlayPlugin.h
 * @brief C interface of the `terroir` program's overlay module (loaded with dlopen).
 */
#ifndef TerroirOverlayPlugin_h
#define TerroirOverlayPlugin_h

#define TERROIR_OVERLAY_PLUGIN_EXPORT __attribute__((visibility("default")))

class vtkImageData;

/// Renders `array` (component `component`) of `image` with `preset` as an overlay with a legend,
/// in relief (`map` 0) or top-down (`map` 1: parallel projection from above, the terrain filling
/// the frame), and writes it to the PNG `path` (temporary file, then rename). Returns nullptr
/// on success, else a one-line error (valid until the next call on this thread).
/// Each thread keeps one view between calls (its window, GL context, shaders, and the surface
/// while the terrain's elevation stays the same): release it with the function below.
using TerroirWriteOverlayFunction = const char* (*)(vtkImageData* image,
  const char* array,
  int component,
  const char* preset,
  const char* title,
  const char* path,
  int map);

/// Releases the calling thread's view (its window and X connection). Safe without one.
using TerroirReleaseOverlaysFunction = void (*)();

/// The file name of the module, beside the program's libraries.
#define TERROIR_OVERLAY_PLUGIN_NAME "terroir-overlay.so"
/// The exported symbol.
#define TERROIR_OVERLAY_PLUGIN_SYMBOL "terroir_write_overlay"
/// The exported symbol of the release function.
#define TERROIR_OVERLAY_RELEASE_SYMBOL "terroir_release_overlays"

#endif

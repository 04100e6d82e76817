/**
 * @file TerroirOverlayPlugin.h
 * @brief C interface of the `terroir` program's overlay module (loaded with dlopen).
 */
#ifndef TerroirOverlayPlugin_h
#define TerroirOverlayPlugin_h

#define TERROIR_OVERLAY_PLUGIN_EXPORT __attribute__((visibility("default")))

class vtkImageData;

/// Renders `array` (component `component`) of `image` with `preset` as a relief overlay with a
/// legend and writes it to the PNG `path` (temporary file, then rename). Returns nullptr on
/// success, else a one-line error (valid until the next call on this thread).
using TerroirWriteOverlayFunction = const char* (*)(vtkImageData* image,
  const char* array,
  int component,
  const char* preset,
  const char* title,
  const char* path);

/// The file name of the module, beside the program's libraries.
#define TERROIR_OVERLAY_PLUGIN_NAME "terroir-overlay.so"
/// The exported symbol.
#define TERROIR_OVERLAY_PLUGIN_SYMBOL "terroir_write_overlay"

#endif
